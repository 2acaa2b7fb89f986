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
                let standard = Normal::standard();
                let (a, b) = standardised(mean, sigma, lower, upper);
                let (a, b) = (standard.cdf(a), standard.cdf(b));
                let p = (a + u * (b - a)).clamp(UNIT_MARGIN, 1.0 - UNIT_MARGIN);
                (mean + sigma * standard.inverse_cdf(p)).clamp(lower, upper)
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
}

/// A truncated normal's bounds in standard deviations from its mean.
fn standardised(mean: f64, sigma: f64, lower: f64, upper: f64) -> (f64, f64) {
    ((lower - mean) / sigma, (upper - mean) / sigma)
}
