//! An uncertain input: its nominal value, its distribution and the distribution's source, and
//! how a point of the unit interval maps onto it (the inverse of its cumulative distribution).

use crate::inputs::aircraft::{Range, Shape};
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal};

/// A distribution over a bounded range.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum InputDistribution {
    Uniform {
        lower: f64,
        upper: f64,
    },
    Triangular {
        lower: f64,
        mode: f64,
        upper: f64,
    },
    /// A normal of `mean` and `sigma`, truncated to `[lower, upper]` (either may be infinite).
    Normal {
        mean: f64,
        sigma: f64,
        lower: f64,
        upper: f64,
    },
}

/// The unit interval's ends are kept this far inside, so that a normal's quantile stays finite.
const UNIT_MARGIN: f64 = 1e-12;

impl InputDistribution {
    /// The distribution an aircraft file's range gives a parameter whose value is `nominal`.
    pub fn of_range(nominal: f64, r: &Range) -> Self {
        match (r.distribution, r.sigma) {
            (Shape::Triangular, _) => Self::Triangular {
                lower: r.lower,
                mode: nominal,
                upper: r.upper,
            },
            (Shape::Normal, Some(sigma)) => Self::Normal {
                mean: nominal,
                sigma,
                lower: r.lower,
                upper: r.upper,
            },
            _ => Self::Uniform {
                lower: r.lower,
                upper: r.upper,
            },
        }
    }

    /// The value whose cumulative probability is `u` (`u` in [0, 1]).
    pub fn quantile(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        match *self {
            Self::Uniform { lower, upper } => lower + u * (upper - lower),
            Self::Triangular { lower, mode, upper } => {
                let width = upper - lower;
                let at_mode = (mode - lower) / width;
                if u < at_mode {
                    lower + (u * width * (mode - lower)).sqrt()
                } else {
                    upper - ((1.0 - u) * width * (upper - mode)).sqrt()
                }
            }
            Self::Normal {
                mean,
                sigma,
                lower,
                upper,
            } => {
                let (a, b) = truncation(mean, sigma, lower, upper);
                let p = (a + u * (b - a)).clamp(UNIT_MARGIN, 1.0 - UNIT_MARGIN);
                (mean + sigma * Normal::standard().inverse_cdf(p)).clamp(lower, upper)
            }
        }
    }

    /// The probability of a value at most `x` (the inverse of [`Self::quantile`]).
    pub fn cdf(&self, x: f64) -> f64 {
        match *self {
            Self::Uniform { lower, upper } => ((x - lower) / (upper - lower)).clamp(0.0, 1.0),
            Self::Triangular { lower, mode, upper } => {
                let width = upper - lower;
                if x <= lower {
                    0.0
                } else if x >= upper {
                    1.0
                } else if x <= mode {
                    (x - lower).powi(2) / (width * (mode - lower))
                } else {
                    1.0 - (upper - x).powi(2) / (width * (upper - mode))
                }
            }
            Self::Normal {
                mean,
                sigma,
                lower,
                upper,
            } => {
                let (ca, cb) = truncation(mean, sigma, lower, upper);
                let cx = Normal::standard().cdf(
                    ((x - mean) / sigma).clamp((lower - mean) / sigma, (upper - mean) / sigma),
                );
                ((cx - ca) / (cb - ca)).clamp(0.0, 1.0)
            }
        }
    }

    /// Its standard deviation (a truncated normal's is taken as its `sigma`, an upper bound).
    pub fn std_dev(&self) -> f64 {
        match *self {
            Self::Uniform { lower, upper } => (upper - lower) / 12f64.sqrt(),
            Self::Triangular { lower, mode, upper } => {
                ((lower * lower + mode * mode + upper * upper
                    - lower * mode
                    - lower * upper
                    - mode * upper)
                    / 18.0)
                    .sqrt()
            }
            Self::Normal { sigma, .. } => sigma,
        }
    }

    /// Its mean (a truncated normal's, exactly).
    pub fn mean(&self) -> f64 {
        match *self {
            Self::Uniform { lower, upper } => 0.5 * (lower + upper),
            Self::Triangular { lower, mode, upper } => (lower + mode + upper) / 3.0,
            Self::Normal {
                mean,
                sigma,
                lower,
                upper,
            } => {
                let standard = Normal::standard();
                let (a, b) = standardised(mean, sigma, lower, upper);
                let mass = standard.cdf(b) - standard.cdf(a);
                let density = |x: f64| (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt();
                if mass > 0.0 {
                    mean + sigma * (density(a) - density(b)) / mass
                } else {
                    mean
                }
            }
        }
    }

    /// In words, for tables (`uniform [200, 320]`).
    pub fn describe(&self) -> String {
        match *self {
            Self::Uniform { lower, upper } => format!("uniform [{lower}, {upper}]"),
            Self::Triangular { lower, mode, upper } => {
                format!("triangular [{lower}, {upper}], mode {mode}")
            }
            Self::Normal {
                mean,
                sigma,
                lower,
                upper,
            } => format!("normal {mean} +- {sigma} in [{lower}, {upper}]"),
        }
    }
}

/// An uncertain input: a named parameter, the value the model uses, the distribution sampled
/// and where it comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Input {
    pub name: String,
    pub nominal: f64,
    pub distribution: InputDistribution,
    pub source: String,
    /// Where it is a factor of a joint distribution (a fit's posterior,
    /// [`crate::inputs::corrections::Posterior`]): the parameters it moves, each by
    /// `per_unit` times its value. Empty: it is the parameter of its name.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub moves: Vec<Moved>,
    /// The cases or checks whose data its range was taken from
    /// ([`crate::inputs::ranges::RangeSpec::taken_from`]): a check among them judged with it is
    /// circular.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub taken_from: Vec<String>,
}

impl Input {
    /// Whether its range was taken from the data of `case`'s check `check`.
    pub fn taken_from_check(&self, case: &str, check: &str) -> bool {
        self.taken_from
            .iter()
            .any(|t| t == case || *t == format!("{case}/{check}"))
    }
}

/// A parameter a factor input moves ([`Input::moves`]), and how.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Moved {
    pub parameter: String,
    pub by: Move,
}

/// How a factor input moves a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Move {
    /// Linearly, with the other factors that move it (a fit's posterior): `value` plus the
    /// sum of `per_unit` times each factor's value, reflected into `[lower, upper]`.
    Linear {
        value: f64,
        per_unit: f64,
        lower: f64,
        upper: f64,
    },
    /// To the factor's quantile of its own distribution (a method's shared error).
    AtQuantile(InputDistribution),
}

impl Input {
    /// The factors of a fit's joint distribution (`id`: its corrections file's): one standard
    /// normal input per principal direction of its covariance, largest first, each moving
    /// every fitted parameter by the direction's component times its standard deviation.
    /// Named `<id>: factor k (mostly <parameter>)`.
    pub fn factors_of(id: &str, posterior: &crate::inputs::corrections::Posterior) -> Vec<Input> {
        let n = posterior.parameters.len();
        let c = nalgebra::DMatrix::from_fn(n, n, |a, b| posterior.covariance[a][b]);
        let eigen = nalgebra::SymmetricEigen::new(c);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        order
            .iter()
            .enumerate()
            .filter(|(_, k)| eigen.eigenvalues[**k] > 0.0)
            .map(|(rank, &k)| {
                let sd = eigen.eigenvalues[k].sqrt();
                let v = eigen.eigenvectors.column(k);
                let main = (0..n)
                    .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
                    .map_or("", |a| posterior.parameters[a].name.as_str());
                Input {
                    name: format!("{id}: factor {} (mostly {main})", rank + 1),
                    nominal: 0.0,
                    distribution: InputDistribution::Normal {
                        mean: 0.0,
                        sigma: 1.0,
                        lower: f64::NEG_INFINITY,
                        upper: f64::INFINITY,
                    },
                    source: format!("the fit of {id}: {}", posterior.method),
                    taken_from: Vec::new(),
                    moves: posterior
                        .parameters
                        .iter()
                        .enumerate()
                        .map(|(a, p)| Moved {
                            parameter: p.name.clone(),
                            by: Move::Linear {
                                value: p.value,
                                per_unit: v[a] * sd,
                                lower: p.lower,
                                upper: p.upper,
                            },
                        })
                        .collect(),
                }
            })
            .collect()
    }
}

/// The inputs that share an estimating method's error (their ranges' `shares`) as one input
/// each: a uniform quantile, named `method <name>: <parameters>`, that draws every such
/// parameter at the same quantile of its own distribution (perfectly rank-correlated: the
/// method's error sampled once). A method only one input names leaves it as it is. The
/// shared input's nominal is the quantile of the first parameter's nominal value.
pub fn shared_by_method(inputs: Vec<Input>, shares: &dyn Fn(&str) -> Option<String>) -> Vec<Input> {
    let mut methods: Vec<(String, Vec<Input>)> = Vec::new();
    let mut out = Vec::new();
    for i in inputs {
        match shares(&i.name) {
            Some(m) if i.moves.is_empty() => match methods.iter_mut().find(|(n, _)| *n == m) {
                Some((_, v)) => v.push(i),
                None => methods.push((m, vec![i])),
            },
            _ => out.push(i),
        }
    }
    for (method, members) in methods {
        if members.len() < 2 {
            out.extend(members);
            continue;
        }
        let names: Vec<&str> = members.iter().map(|m| m.name.as_str()).collect();
        let nominal = members[0].distribution.cdf(members[0].nominal);
        out.push(Input {
            name: format!("method {method}: {}", names.join(", ")),
            nominal,
            distribution: InputDistribution::Uniform {
                lower: 0.0,
                upper: 1.0,
            },
            source: members
                .iter()
                .map(|m| format!("{}: {}", m.name, m.source))
                .collect::<Vec<_>>()
                .join("; "),
            taken_from: members
                .iter()
                .flat_map(|m| m.taken_from.iter().cloned())
                .collect(),
            moves: members
                .iter()
                .map(|m| Moved {
                    parameter: m.name.clone(),
                    by: Move::AtQuantile(m.distribution),
                })
                .collect(),
        });
    }
    out
}

/// `x` reflected into `[lower, upper]` at whichever bound it left by (then held there, if it
/// left by more than the width).
pub fn reflected(x: f64, lower: f64, upper: f64) -> f64 {
    let r = if x < lower {
        2.0 * lower - x
    } else if x > upper {
        2.0 * upper - x
    } else {
        x
    };
    r.clamp(lower, upper)
}

/// A truncated normal's bounds as cumulative probabilities of the untruncated one.
fn truncation(mean: f64, sigma: f64, lower: f64, upper: f64) -> (f64, f64) {
    let standard = Normal::standard();
    let (a, b) = standardised(mean, sigma, lower, upper);
    (standard.cdf(a), standard.cdf(b))
}

/// A truncated normal's bounds in standard deviations from its mean.
fn standardised(mean: f64, sigma: f64, lower: f64, upper: f64) -> (f64, f64) {
    ((lower - mean) / sigma, (upper - mean) / sigma)
}
