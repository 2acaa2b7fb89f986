//! Modes of a linear model: eigenvalues, eigenvectors, mode characteristics and classification.
//!
//! Eigen-decomposition is done with faer (it gives right eigenvectors); left eigenvectors are
//! the rows of the inverse of the right-eigenvector matrix.
//!
//! # Classification
//! States have different units (m/s, rad/s, rad), so raw eigenvector magnitudes depend on the
//! choice of units. Modes are therefore classified by *participation factors*
//! `p_ki = |l_ik r_ki|` (normalised to sum to one over the states), which are dimensionless and
//! unchanged by rescaling a state. The share of each group of states decides the class:
//!
//! | class | eigenvalue | dominant states (share >= 0.5) |
//! |---|---|---|
//! | short period | complex | `w`, `q` |
//! | phugoid | complex | `u`, `theta` |
//! | rotorspeed | real | `Omega` |
//! | Dutch roll | complex | `v`, `p`, `r`, `phi`, `psi` |
//! | roll subsidence | real | lateral states, `p` the largest |
//! | spiral | real | lateral states, `phi` or `r` the largest |
//! | heading | real, zero | `psi` alone (the heading integrator) |
//!
//! Anything else, or a mode whose dominant group holds less than half the participation, is
//! [`ModeKind::Unclassified`]. When the eigenvector matrix is numerically singular (a defective
//! matrix), participation factors do not exist and every mode is unclassified.

use crate::analysis::linear::LinearModel;
use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use serde::Serialize;
use std::f64::consts::LN_2;
use thiserror::Error;

/// A complex number with named parts, for output.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Complex {
    pub re: f64,
    pub im: f64,
}

impl Complex {
    /// Modulus.
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
}

impl std::fmt::Display for Complex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let p = f.precision().unwrap_or(4);
        if self.im == 0.0 {
            write!(f, "{:.p$}", self.re)
        } else {
            write!(f, "{:.p$} ± {:.p$}i", self.re, self.im.abs())
        }
    }
}

/// Mode classes recognised from eigenvector content.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeKind {
    ShortPeriod,
    Phugoid,
    Rotorspeed,
    DutchRoll,
    RollSubsidence,
    Spiral,
    Heading,
    Unclassified,
}

impl ModeKind {
    /// The snake_case name used in case files and output.
    pub fn name(self) -> &'static str {
        match self {
            Self::ShortPeriod => "short_period",
            Self::Phugoid => "phugoid",
            Self::Rotorspeed => "rotorspeed",
            Self::DutchRoll => "dutch_roll",
            Self::RollSubsidence => "roll_subsidence",
            Self::Spiral => "spiral",
            Self::Heading => "heading",
            Self::Unclassified => "unclassified",
        }
    }
}

/// One mode: a real eigenvalue or a complex-conjugate pair (stored with `im > 0`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    pub kind: ModeKind,
    pub eigenvalue: Complex,
    /// Damped frequency in rad/s (0 for a real mode).
    pub damped_frequency_rad_s: f64,
    /// Undamped natural frequency `|lambda|` in rad/s.
    pub natural_frequency_rad_s: f64,
    /// Damping ratio `-re/|lambda|` of an oscillatory mode; `None` for a real mode.
    pub damping_ratio: Option<f64>,
    /// Period `2 pi / im` of an oscillatory mode.
    pub period_s: Option<f64>,
    /// Time to half amplitude `ln 2 / -re` of a stable mode.
    pub time_to_half_s: Option<f64>,
    /// Time to double amplitude `ln 2 / re` of an unstable mode.
    pub time_to_double_s: Option<f64>,
    /// Participation share of each state (same order as the model's states), summing to one;
    /// empty when the eigenvector matrix is singular.
    pub participation: Vec<f64>,
    /// Right eigenvector, normalised so that its largest component is 1 (real) for display.
    pub eigenvector: Vec<Complex>,
}

impl Mode {
    /// Whether the mode is a complex pair.
    pub fn is_oscillatory(&self) -> bool {
        self.eigenvalue.im > 0.0
    }
}

/// The modes of a model and the states they refer to.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModalAnalysis {
    pub states: Vec<String>,
    /// Modes sorted by decreasing natural frequency, then by real part.
    pub modes: Vec<Mode>,
    /// True when participation factors could not be computed (defective matrix).
    pub defective: bool,
}

impl ModalAnalysis {
    /// Modes of one class.
    pub fn of_kind(&self, kind: ModeKind) -> impl Iterator<Item = &Mode> {
        self.modes.iter().filter(move |m| m.kind == kind)
    }

    /// All eigenvalues, each conjugate pair expanded to both members.
    pub fn eigenvalues(&self) -> Vec<Complex> {
        let mut v = Vec::new();
        for m in &self.modes {
            v.push(m.eigenvalue);
            if m.is_oscillatory() {
                v.push(Complex {
                    re: m.eigenvalue.re,
                    im: -m.eigenvalue.im,
                });
            }
        }
        v
    }
}

/// Failure of the eigen-decomposition.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModesError {
    #[error("the model has no states")]
    Empty,
    #[error("eigen-decomposition did not converge")]
    NoConvergence,
}

/// Imaginary parts below this fraction of the modulus (or absolute, near zero) are real.
const REAL_TOLERANCE: f64 = 1e-9;
/// A mode's dominant group must hold at least this share of its participation.
const DOMINANT_SHARE: f64 = 0.5;

/// Computes the modes of a linear model.
pub fn modes(model: &LinearModel) -> Result<ModalAnalysis, ModesError> {
    let a = model.a();
    let n = a.nrows();
    if n == 0 {
        return Err(ModesError::Empty);
    }
    let m = Mat::<f64>::from_fn(n, n, |i, j| a[(i, j)]);
    let evd = m.eigen().map_err(|_| ModesError::NoConvergence)?;
    let s = evd.S().column_vector();
    let u = evd.U();
    let lambdas: Vec<Complex> = (0..n)
        .map(|i| Complex {
            re: s[i].re,
            im: s[i].im,
        })
        .collect();
    if lambdas
        .iter()
        .any(|l| !l.re.is_finite() || !l.im.is_finite())
    {
        return Err(ModesError::NoConvergence);
    }
    let left = u.to_owned().partial_piv_lu().inverse();
    let defective = (0..n).any(|i| (0..n).any(|j| !left[(i, j)].re.is_finite()))
        || condition_too_large(&u.to_owned(), &left);

    let mut out = Vec::new();
    for i in 0..n {
        let lam = lambdas[i];
        let scale = lam.abs().max(1.0);
        let is_real = lam.im.abs() <= REAL_TOLERANCE * scale;
        if !is_real && lam.im < 0.0 {
            continue; // the conjugate with im > 0 represents the pair
        }
        let eigenvalue = Complex {
            re: lam.re,
            im: if is_real { 0.0 } else { lam.im },
        };
        let participation = if defective {
            Vec::new()
        } else {
            let raw: Vec<f64> = (0..n)
                .map(|k| {
                    let r = u[(k, i)];
                    let l = left[(i, k)];
                    (r * l).norm()
                })
                .collect();
            let total: f64 = raw.iter().sum();
            raw.iter().map(|p| p / total).collect()
        };
        let eigenvector = normalise(&(0..n).map(|k| u[(k, i)]).collect::<Vec<_>>());
        let kind = if defective {
            ModeKind::Unclassified
        } else {
            classify(model.states(), &participation, eigenvalue)
        };
        out.push(characterise(eigenvalue, kind, participation, eigenvector));
    }
    out.sort_by(|a, b| {
        b.natural_frequency_rad_s
            .total_cmp(&a.natural_frequency_rad_s)
            .then(a.eigenvalue.re.total_cmp(&b.eigenvalue.re))
    });
    Ok(ModalAnalysis {
        states: model.states().to_vec(),
        modes: out,
        defective,
    })
}

/// Eigenvalues only (each conjugate pair as two entries), for sweeps.
pub fn eigenvalues(model: &LinearModel) -> Result<Vec<Complex>, ModesError> {
    Ok(modes(model)?.eigenvalues())
}

/// Builds the mode characteristics from an eigenvalue.
pub fn characterise(
    eigenvalue: Complex,
    kind: ModeKind,
    participation: Vec<f64>,
    eigenvector: Vec<Complex>,
) -> Mode {
    let wn = eigenvalue.abs();
    let osc = eigenvalue.im > 0.0;
    let re = eigenvalue.re;
    Mode {
        kind,
        eigenvalue,
        damped_frequency_rad_s: eigenvalue.im,
        natural_frequency_rad_s: wn,
        damping_ratio: (osc && wn > 0.0).then(|| -re / wn),
        period_s: osc.then(|| 2.0 * std::f64::consts::PI / eigenvalue.im),
        time_to_half_s: (re < 0.0).then(|| LN_2 / -re),
        time_to_double_s: (re > 0.0).then(|| LN_2 / re),
        participation,
        eigenvector,
    }
}

fn condition_too_large(u: &Mat<faer::c64>, inv: &Mat<faer::c64>) -> bool {
    let norm = |m: &Mat<faer::c64>| {
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)].norm()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    norm(u) * norm(inv) > 1e12
}

fn normalise(v: &[faer::c64]) -> Vec<Complex> {
    let big = v
        .iter()
        .copied()
        .max_by(|a, b| a.norm().total_cmp(&b.norm()))
        .unwrap_or(faer::c64::new(1.0, 0.0));
    v.iter()
        .map(|x| {
            let y = if big.norm() > 0.0 { *x / big } else { *x };
            Complex { re: y.re, im: y.im }
        })
        .collect()
}

const LATERAL: [&str; 5] = ["v", "p", "r", "phi", "psi"];

/// Classifies a mode from its participation shares (see the module docs).
pub fn classify(states: &[String], participation: &[f64], eigenvalue: Complex) -> ModeKind {
    let share = |names: &[&str]| -> f64 {
        states
            .iter()
            .zip(participation)
            .filter(|(s, _)| names.contains(&s.as_str()))
            .map(|(_, p)| *p)
            .sum()
    };
    let one = |name: &str| share(&[name]);
    let osc = eigenvalue.im > 0.0;
    if osc {
        let groups = [
            (ModeKind::ShortPeriod, share(&["w", "q"])),
            (ModeKind::Phugoid, share(&["u", "theta"])),
            (ModeKind::DutchRoll, share(&LATERAL)),
        ];
        let (kind, best) = groups
            .iter()
            .copied()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("three groups");
        return if best >= DOMINANT_SHARE {
            kind
        } else {
            ModeKind::Unclassified
        };
    }
    if one("Omega") >= DOMINANT_SHARE {
        return ModeKind::Rotorspeed;
    }
    let lateral = share(&LATERAL);
    if lateral >= DOMINANT_SHARE {
        if one("psi") >= 1.0 - 1e-6 && eigenvalue.abs() < 1e-9 {
            return ModeKind::Heading;
        }
        let largest = LATERAL
            .iter()
            .filter(|s| **s != "psi")
            .copied()
            .max_by(|a, b| one(a).total_cmp(&one(b)))
            .expect("non-empty");
        return match largest {
            "p" => ModeKind::RollSubsidence,
            "phi" | "r" => ModeKind::Spiral,
            _ => ModeKind::Unclassified,
        };
    }
    ModeKind::Unclassified
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testdata::{puma_eq26, vpm_eq20};

    #[test]
    fn vpm_modes_are_classified() {
        let a = modes(&vpm_eq20()).unwrap();
        let sp: Vec<_> = a.of_kind(ModeKind::ShortPeriod).collect();
        let ph: Vec<_> = a.of_kind(ModeKind::Phugoid).collect();
        let rs: Vec<_> = a.of_kind(ModeKind::Rotorspeed).collect();
        assert_eq!((sp.len(), ph.len(), rs.len()), (1, 1, 1), "{a:#?}");
        // Computed from the printed matrix with numpy's LAPACK eigvals (independent oracle).
        assert!((sp[0].eigenvalue.re - -1.064_475_117).abs() < 1e-8);
        assert!((sp[0].eigenvalue.im - 0.864_183_763).abs() < 1e-8);
        assert!((ph[0].eigenvalue.re - -0.073_698_737).abs() < 1e-8);
        assert!((ph[0].eigenvalue.im - 0.134_194_325).abs() < 1e-8);
        assert!((rs[0].eigenvalue.re - -0.289_652_292).abs() < 1e-8);
        for m in &a.modes {
            let s: f64 = m.participation.iter().sum();
            assert!((s - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn puma_modes_are_classified() {
        let a = modes(&puma_eq26()).unwrap();
        let kinds: Vec<_> = a.modes.iter().map(|m| m.kind).collect();
        assert_eq!(
            kinds,
            [
                ModeKind::ShortPeriod,
                ModeKind::Phugoid,
                ModeKind::Rotorspeed
            ]
        );
    }

    #[test]
    fn characteristics_follow_from_the_eigenvalue() {
        let m = characterise(
            Complex { re: -0.5, im: 2.0 },
            ModeKind::Unclassified,
            vec![],
            vec![],
        );
        let wn = (0.25f64 + 4.0).sqrt();
        assert!((m.natural_frequency_rad_s - wn).abs() < 1e-15);
        assert!((m.damping_ratio.unwrap() - 0.5 / wn).abs() < 1e-15);
        assert!((m.period_s.unwrap() - std::f64::consts::PI).abs() < 1e-15);
        assert!((m.time_to_half_s.unwrap() - LN_2 / 0.5).abs() < 1e-15);
        assert!(m.time_to_double_s.is_none());
        let r = characterise(
            Complex { re: 0.1, im: 0.0 },
            ModeKind::Unclassified,
            vec![],
            vec![],
        );
        assert!(r.damping_ratio.is_none() && r.period_s.is_none());
        assert!((r.time_to_double_s.unwrap() - LN_2 / 0.1).abs() < 1e-12);
    }

    #[test]
    fn participation_is_unchanged_by_state_scaling() {
        // Express w in ft/s instead of m/s: a diagonal similarity transform.
        let m = vpm_eq20();
        let k = 1.0 / 0.3048;
        let i = m.state_index("w").unwrap();
        let mut a = m.a().clone();
        let mut b = m.b().clone();
        for j in 0..a.ncols() {
            a[(i, j)] *= k;
        }
        for r in 0..a.nrows() {
            a[(r, i)] /= k;
        }
        for j in 0..b.ncols() {
            b[(i, j)] *= k;
        }
        let scaled = LinearModel::new(m.states().to_vec(), m.controls().to_vec(), a, b).unwrap();
        let (p1, p2) = (modes(&m).unwrap(), modes(&scaled).unwrap());
        for (x, y) in p1.modes.iter().zip(&p2.modes) {
            assert_eq!(x.kind, y.kind);
            for (a, b) in x.participation.iter().zip(&y.participation) {
                assert!((a - b).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn lateral_modes_are_classified() {
        // Test-only lateral/directional model with textbook-like structure (synthetic, not
        // from a source): states v p r phi psi.
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let m = LinearModel::from_rows(
            names(&["v", "p", "r", "phi", "psi"]),
            names(&["eta_c"]),
            &[
                vec![-0.15, 0.5, -30.0, 9.81, 0.0],
                vec![-0.05, -2.5, 0.8, 0.0, 0.0],
                vec![0.06, -0.1, -0.6, 0.0, 0.0],
                vec![0.0, 1.0, 0.0, 0.0, 0.0],
                vec![0.0, 0.0, 1.0, 0.0, 0.0],
            ],
            &[vec![0.0], vec![0.1], vec![0.0], vec![0.0], vec![0.0]],
        )
        .unwrap();
        let a = modes(&m).unwrap();
        let kinds: Vec<_> = a.modes.iter().map(|m| m.kind).collect();
        assert!(kinds.contains(&ModeKind::DutchRoll), "{a:#?}");
        assert!(kinds.contains(&ModeKind::RollSubsidence), "{a:#?}");
        assert!(kinds.contains(&ModeKind::Spiral), "{a:#?}");
        assert!(kinds.contains(&ModeKind::Heading), "{a:#?}");
    }
}
