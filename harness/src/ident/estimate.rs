//! Frequency-domain equation-error identification (seed 000 Sec. IV, Eqs. 9-11).
//!
//! For each degree of freedom `x_i' = sum_j a_ij x_j + sum_k b_ik u_k`, the Fourier transform of
//! both sides at a set of frequencies gives one complex equation per frequency; its real and
//! imaginary parts, weighted equally, are the rows of a linear regression for the unknown
//! `a_ij, b_ik` (Eq. 11). Known (fixed) parameters move to the left-hand side.
//!
//! The transform of the derivative is taken exactly for a finite record with a taper `w(t)`:
//! `F[w x'] = i w F[w x] - F[w' x] + w(T) x(T) e^(-i w T) - w(0) x(0)`, so neither the
//! record's ends nor the taper leak into the equations (with no taper, `w = 1`, this is
//! `i w X` plus the end terms; seed 000 Eq. 9 is the case of a record at rest at both ends).
//! Records may be split into overlapping tapered segments (Tischler); their equations are
//! stacked.
//!
//! Statistics: ordinary least squares by singular value decomposition (or instrumental
//! variables, given a first model), on regressors scaled to unit column norms; the
//! heteroscedasticity-consistent (sandwich) covariance, each frequency point's variance its own
//! squared residual with the small-sample factor `n / (n - p)`; 95 % bounds `+-t(0.975, n - p)`
//! standard errors. The arithmetic is `cierva_fft::regression`'s. The estimator
//! never panics on data: it returns [`IdentError`] or fits with warnings.

use super::fourier::{ChirpZ, hann, transform};
use cierva_fft::regression::{self, Failure};
use nalgebra::DMatrix;
pub use rustfft::num_complex::Complex64 as C;
use serde::Serialize;
use thiserror::Error;

/// Time histories (perturbations), one vector per variable, sampled at `dt_s` from `t = 0`.
#[derive(Debug, Clone, Copy)]
pub struct Signals<'a> {
    pub states: &'a [String],
    pub controls: &'a [String],
    pub x: &'a [Vec<f64>],
    pub u: &'a [Vec<f64>],
    pub dt_s: f64,
}

/// Where the equations are formed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Frequencies {
    /// `points` evenly spaced from `from_hz` to `to_hz` (chirp-z).
    Band {
        from_hz: f64,
        to_hz: f64,
        points: usize,
    },
    /// A list, Hz.
    List(Vec<f64>),
}

impl Frequencies {
    /// The frequencies in rad/s.
    pub fn omegas(&self) -> Vec<f64> {
        let two_pi = 2.0 * std::f64::consts::PI;
        match self {
            Self::Band {
                from_hz,
                to_hz,
                points,
            } => match points {
                0 => vec![],
                1 => vec![two_pi * from_hz],
                n => (0..*n)
                    .map(|k| two_pi * (from_hz + (to_hz - from_hz) * k as f64 / (*n - 1) as f64))
                    .collect(),
            },
            Self::List(v) => v.iter().map(|f| two_pi * f).collect(),
        }
    }

    /// The lowest frequency, Hz.
    pub fn lowest_hz(&self) -> f64 {
        self.omegas().iter().copied().fold(f64::INFINITY, f64::min) / (2.0 * std::f64::consts::PI)
    }
}

/// Segmenting and tapering.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Windowing {
    /// Number of segments (1: the whole record).
    pub segments: usize,
    /// Overlap between neighbouring segments, as a fraction of a segment.
    pub overlap: f64,
    /// Hann taper on each segment (else rectangular).
    pub hann: bool,
}

impl Default for Windowing {
    fn default() -> Self {
        Self {
            segments: 1,
            overlap: 0.0,
            hann: false,
        }
    }
}

/// One equation to identify: the row of `state`, its free parameters and its fixed ones.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Equation {
    pub state: String,
    /// States and controls whose coefficients are estimated.
    pub estimate: Vec<String>,
    /// States and controls whose coefficients are known.
    pub fixed: Vec<(String, f64)>,
}

/// One estimated coefficient.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Coefficient {
    /// The variable (column) it multiplies.
    pub variable: String,
    pub value: f64,
    pub standard_error: f64,
    pub lower_95: f64,
    pub upper_95: f64,
}

/// The fit of one equation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EquationFit {
    pub state: String,
    pub estimates: Vec<Coefficient>,
    pub fixed: Vec<(String, f64)>,
    /// Coefficient of determination of the regression.
    pub r_squared: f64,
    /// Degrees of freedom `n - p`.
    pub dof: usize,
    /// Correlation matrix of the estimates.
    pub correlation: Vec<Vec<f64>>,
    /// Ratio of the largest to the smallest singular value of the (column-scaled) regressors.
    pub condition_number: f64,
    pub warnings: Vec<String>,
}

/// Why identification could not be done.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum IdentError {
    #[error("no frequencies to form equations at")]
    NoFrequencies,
    #[error(
        "the record is too short for the band: a segment of {segment_s:.1} s resolves nothing below {resolvable_hz:.4} Hz, the band starts at {lowest_hz:.4} Hz (needs segments of at least {needed_s:.1} s)"
    )]
    TooShort {
        segment_s: f64,
        resolvable_hz: f64,
        lowest_hz: f64,
        needed_s: f64,
    },
    #[error("`{0}` is neither a state nor a control of the signals")]
    Unknown(String),
    #[error("signal `{0}` has a different length from the others, or is empty")]
    Length(String),
    #[error("signal `{name}` is not finite at sample {index}")]
    NotFinite { name: String, index: usize },
    #[error("equation `{state}`: {p} parameters but only {rows} equations")]
    Underdetermined {
        state: String,
        p: usize,
        rows: usize,
    },
    #[error(
        "equation `{state}`: the regressors are singular ({detail}): a parameter has no effect on the data, or two have the same"
    )]
    Singular { state: String, detail: String },
    #[error("a setting is out of range: {0}")]
    Setting(String),
}

/// Warning thresholds.
const HIGH_CORRELATION: f64 = 0.95;
const LARGE_RELATIVE_ERROR: f64 = 0.5;
const ILL_CONDITIONED: f64 = 1e6;

/// The transforms of a record's signals at the chosen frequencies: computed once, then used
/// by every fit (least squares and each instrumental-variable pass).
#[derive(Debug, Clone)]
pub struct Spectra {
    names: Vec<String>,
    states: usize,
    /// The frequency of each stacked (segment, frequency) point, rad/s.
    omegas: Vec<f64>,
    /// `F[w v]` of every state and control, stacked over segments.
    var_ft: Vec<Vec<C>>,
    /// `F[w x']` of every state.
    der_ft: Vec<Vec<C>>,
}

impl Spectra {
    /// The frequency of each stacked (segment, frequency) point, rad/s.
    pub fn omegas(&self) -> &[f64] {
        &self.omegas
    }

    /// The transforms of every state and control (states first) at each point.
    pub fn transforms(&self) -> &[Vec<C>] {
        &self.var_ft
    }

    /// The spectra of a known frequency response: `var_ft[variable][k]`, the transform of every
    /// state and control (states first, `states` of them) at `omegas[k]`, rad/s. The rates'
    /// transforms are `i w X`, exactly.
    pub fn from_response(
        names: Vec<String>,
        states: usize,
        omegas: &[f64],
        var_ft: Vec<Vec<C>>,
    ) -> Result<Spectra, IdentError> {
        if var_ft.len() != names.len()
            || states > names.len()
            || var_ft.iter().any(|v| v.len() != omegas.len())
        {
            return Err(IdentError::Setting(format!(
                "a frequency response needs every variable ({}) at every frequency ({})",
                names.len(),
                omegas.len()
            )));
        }
        if omegas.is_empty() {
            return Err(IdentError::NoFrequencies);
        }
        let der_ft = var_ft[..states]
            .iter()
            .map(|x| {
                x.iter()
                    .zip(omegas)
                    .map(|(v, w)| C::new(0.0, *w) * v)
                    .collect()
            })
            .collect();
        Ok(Spectra {
            names,
            states,
            omegas: omegas.to_vec(),
            var_ft,
            der_ft,
        })
    }

    /// Several records' spectra as one: their (segment, frequency) points stacked, as the
    /// segments of one record are. This is how flight testers identify one condition from
    /// several runs (a longitudinal and a lateral sweep): each run excites what the others do
    /// not, and the equations hold in all of them. The parts must have the same variables.
    pub fn concatenate(parts: Vec<Spectra>) -> Result<Spectra, IdentError> {
        let mut parts = parts.into_iter();
        let mut out = parts.next().ok_or(IdentError::NoFrequencies)?;
        for p in parts {
            if p.names != out.names || p.states != out.states {
                return Err(IdentError::Setting(format!(
                    "records with different variables cannot be identified together ({:?} and {:?})",
                    out.names, p.names
                )));
            }
            out.omegas.extend(p.omegas);
            for (a, b) in out.var_ft.iter_mut().zip(p.var_ft) {
                a.extend(b);
            }
            for (a, b) in out.der_ft.iter_mut().zip(p.der_ft) {
                a.extend(b);
            }
        }
        Ok(out)
    }
}

/// Identifies each equation by least squares.
pub fn identify(
    sig: Signals<'_>,
    freqs: &Frequencies,
    windowing: Windowing,
    equations: &[Equation],
) -> Result<Vec<EquationFit>, IdentError> {
    fit_equations(&spectra(sig, freqs, windowing)?, equations, None)
}

/// Identifies each equation with instrumental variables built from a first model `(a, b)`
/// (states and controls in the order of the signals): at each frequency the state instruments
/// are `Z(w) = (i w I - a)^-1 b U(w)`, the first model's response to the measured inputs
/// alone; the controls are their own instruments.
///
/// Turbulence forces the states, so the measured states are correlated with the equation error
/// at the same frequency and least squares is biased; the instruments are not (and, built in
/// the frequency domain, they exist even when the first model is unstable).
/// `theta = (Z'X)^-1 Z'y`.
pub fn identify_iv(
    spectra: &Spectra,
    equations: &[Equation],
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
) -> Result<Vec<EquationFit>, IdentError> {
    let (n, m) = (spectra.states, spectra.names.len() - spectra.states);
    if a.shape() != (n, n)
        || b.shape() != (n, m)
        || a.iter().chain(b.iter()).any(|v| !v.is_finite())
    {
        return Err(IdentError::Setting(
            "the instrument model must be finite, states x states and states x controls".into(),
        ));
    }
    fit_equations(spectra, equations, Some((a, b)))
}

/// Checks the signals and settings and computes the transforms.
pub fn spectra(
    sig: Signals<'_>,
    freqs: &Frequencies,
    windowing: Windowing,
) -> Result<Spectra, IdentError> {
    let omegas = freqs.omegas();
    if omegas.is_empty() {
        return Err(IdentError::NoFrequencies);
    }
    if omegas.iter().any(|w| !w.is_finite() || *w <= 0.0) {
        return Err(IdentError::Setting(
            "frequencies must be positive and finite".into(),
        ));
    }
    if !(sig.dt_s.is_finite() && sig.dt_s > 0.0) {
        return Err(IdentError::Setting(format!("time step {} s", sig.dt_s)));
    }
    if windowing.segments == 0 || !(0.0..0.9).contains(&windowing.overlap) {
        return Err(IdentError::Setting(
            "segments >= 1 and overlap in [0, 0.9)".into(),
        ));
    }
    let n = sig.x.first().map_or(0, Vec::len);
    let names: Vec<&String> = sig.states.iter().chain(sig.controls).collect();
    let series: Vec<&Vec<f64>> = sig.x.iter().chain(sig.u).collect();
    if names.len() != series.len() {
        return Err(IdentError::Setting("as many signals as names".into()));
    }
    for (name, s) in names.iter().zip(&series) {
        if s.len() != n || n < 4 {
            return Err(IdentError::Length(name.to_string()));
        }
        if let Some(index) = s.iter().position(|v| !v.is_finite()) {
            return Err(IdentError::NotFinite {
                name: name.to_string(),
                index,
            });
        }
    }
    // Segments: length L with overlap; the lowest frequency needs two cycles in a segment.
    let k = windowing.segments as f64;
    let seg_len = ((n as f64) / (k - (k - 1.0) * windowing.overlap)).floor() as usize;
    let hop = ((1.0 - windowing.overlap) * seg_len as f64)
        .round()
        .max(1.0) as usize;
    let segment_s = (seg_len.max(1) - 1) as f64 * sig.dt_s;
    let lowest_hz = freqs.lowest_hz();
    if lowest_hz < 2.0 / segment_s {
        return Err(IdentError::TooShort {
            segment_s,
            resolvable_hz: 2.0 / segment_s,
            lowest_hz,
            needed_s: 2.0 / lowest_hz,
        });
    }
    // Transforms of every variable (F[w v]) and of every state's derivative, per segment.
    // Evenly spaced frequencies go by chirp-z, prepared once per segment length.
    let plans: std::cell::RefCell<Vec<ChirpZ>> = Default::default();
    let ft = |v: &[f64]| -> Vec<C> {
        match freqs {
            Frequencies::Band { points, .. } if *points > 1 => {
                let mut plans = plans.borrow_mut();
                if let Some(p) = plans.iter().find(|p| p.len() == v.len()) {
                    return p.apply(v);
                }
                let p = ChirpZ::new(v.len(), sig.dt_s, omegas[0], omegas[1] - omegas[0], *points);
                let out = p.apply(v);
                plans.push(p);
                out
            }
            _ => transform(v, sig.dt_s, &omegas),
        }
    };
    let mut var_ft: Vec<Vec<C>> = vec![Vec::new(); names.len()];
    let mut der_ft: Vec<Vec<C>> = vec![Vec::new(); sig.states.len()];

    for s in 0..windowing.segments {
        let start = s * hop;
        let end = (start + seg_len).min(n);
        let (w, dw) = if windowing.hann {
            hann(end - start, sig.dt_s)
        } else {
            (vec![1.0; end - start], vec![0.0; end - start])
        };
        let t_end = (end - start - 1) as f64 * sig.dt_s;
        for (i, s) in series.iter().enumerate() {
            let seg = &s[start..end];
            let wx: Vec<f64> = seg.iter().zip(&w).map(|(a, b)| a * b).collect();
            let fwx = ft(&wx);
            if i < sig.states.len() {
                // Without a taper w' = 0, and so is F[w' x]: no transform is needed for it.
                let fdw = if windowing.hann {
                    ft(&seg.iter().zip(&dw).map(|(a, b)| a * b).collect::<Vec<_>>())
                } else {
                    vec![C::new(0.0, 0.0); omegas.len()]
                };
                let (x0, xt) = (w[0] * seg[0], w[w.len() - 1] * seg[seg.len() - 1]);
                der_ft[i].extend(
                    omegas
                        .iter()
                        .zip(fwx.iter().zip(&fdw))
                        .map(|(&om, (a, d))| {
                            C::new(0.0, om) * a - d + C::from_polar(xt, -om * t_end) - x0
                        }),
                );
            }
            var_ft[i].extend(fwx);
        }
    }
    let stacked: Vec<f64> = (0..windowing.segments)
        .flat_map(|_| omegas.iter().copied())
        .collect();
    Ok(Spectra {
        names: names.iter().map(|n| n.to_string()).collect(),
        states: sig.states.len(),
        omegas: stacked,
        var_ft,
        der_ft,
    })
}

/// Fits each equation on precomputed spectra, by least squares or, given a first model, by
/// instrumental variables.
pub fn fit_equations(
    spectra: &Spectra,
    equations: &[Equation],
    instruments: Option<(&DMatrix<f64>, &DMatrix<f64>)>,
) -> Result<Vec<EquationFit>, IdentError> {
    let ins_ft = instruments.map(|(a, b)| {
        regression::state_instruments(a, b, &spectra.omegas, &spectra.var_ft, spectra.states)
    });
    let index = |name: &str| {
        spectra
            .names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| IdentError::Unknown(name.to_string()))
    };
    equations
        .iter()
        .map(|eq| {
            let row = spectra.names[..spectra.states]
                .iter()
                .position(|s| *s == eq.state)
                .ok_or_else(|| IdentError::Unknown(eq.state.clone()))?;
            let cols = eq
                .estimate
                .iter()
                .map(|v| index(v))
                .collect::<Result<Vec<_>, _>>()?;
            let fixed = eq
                .fixed
                .iter()
                .map(|(v, val)| Ok((index(v)?, *val)))
                .collect::<Result<Vec<_>, IdentError>>()?;
            fit(
                eq,
                &spectra.der_ft[row],
                &spectra.var_ft,
                ins_ft.as_deref(),
                &cols,
                &fixed,
            )
        })
        .collect()
}

fn fit(
    eq: &Equation,
    y_c: &[C],
    var_ft: &[Vec<C>],
    ins_ft: Option<&[Vec<C>]>,
    cols: &[usize],
    fixed: &[(usize, f64)],
) -> Result<EquationFit, IdentError> {
    let m = y_c.len();
    let (rows, p) = (2 * m, cols.len());
    // The arithmetic (the regression, its column scaling, the solution and the sandwich
    // covariance; see the module's documentation) is `cierva_fft::regression`'s, and so is the
    // refusal of too few rows (no estimated variable, or no more rows than variables).
    let singular = |detail: String| IdentError::Singular {
        state: eq.state.clone(),
        detail,
    };
    let solved =
        regression::equation_error(y_c, var_ft, ins_ft, cols, fixed).map_err(|f| match f {
            Failure::ZeroColumn(c) => singular(format!(
                "the regressor of `{}` is zero or not finite",
                eq.estimate[c]
            )),
            Failure::Singular { largest, smallest } => singular(format!(
                "singular values from {largest:.3e} down to {smallest:.3e}"
            )),
            Failure::NotInvertible => singular("the normal equations cannot be inverted".into()),
            Failure::TooFewRows => IdentError::Underdetermined {
                state: eq.state.clone(),
                p,
                rows,
            },
        })?;
    let (theta_s, cov_s, scales) = (&solved.theta, &solved.covariance, &solved.scales);
    let t = student_t_975(solved.dof);
    let mut estimates = Vec::with_capacity(p);
    for c in 0..p {
        let value = theta_s[c] / scales[c];
        let se = cov_s[(c, c)].sqrt() / scales[c];
        estimates.push(Coefficient {
            variable: eq.estimate[c].clone(),
            value,
            standard_error: se,
            lower_95: value - t * se,
            upper_95: value + t * se,
        });
    }
    let correlation: Vec<Vec<f64>> = (0..p)
        .map(|a| {
            (0..p)
                .map(|b| cov_s[(a, b)] / (cov_s[(a, a)] * cov_s[(b, b)]).sqrt())
                .collect()
        })
        .collect();
    let warnings = warnings_of(eq, &estimates, &correlation, solved.condition_number);
    Ok(EquationFit {
        state: eq.state.clone(),
        estimates,
        fixed: eq.fixed.clone(),
        r_squared: if solved.tss > 0.0 {
            1.0 - solved.rss / solved.tss
        } else {
            1.0
        },
        dof: solved.dof,
        correlation,
        condition_number: solved.condition_number,
        warnings,
    })
}

/// The fit's warnings: pairs of highly correlated coefficients, poorly identified ones, and
/// ill-conditioned regressors.
fn warnings_of(
    eq: &Equation,
    estimates: &[Coefficient],
    correlation: &[Vec<f64>],
    condition_number: f64,
) -> Vec<String> {
    let mut warnings = Vec::new();
    for (a, row) in correlation.iter().enumerate() {
        for (b, r) in row.iter().enumerate().skip(a + 1) {
            if r.abs() > HIGH_CORRELATION {
                warnings.push(format!(
                    "the coefficients of {} and {} are highly correlated (r = {r:.3}): their estimates trade off against each other in this record",
                    eq.estimate[a], eq.estimate[b]
                ));
            }
        }
        let e = &estimates[a];
        if e.standard_error > LARGE_RELATIVE_ERROR * e.value.abs() {
            warnings.push(format!(
                "{} is poorly identified: standard error {:.3e} against an estimate of {:.3e}",
                e.variable, e.standard_error, e.value
            ));
        }
    }
    if condition_number > ILL_CONDITIONED {
        warnings.push(format!(
            "ill-conditioned regressors (condition number {condition_number:.2e})"
        ));
    }
    warnings
}

/// The 97.5 % quantile of Student's t with `dof` degrees of freedom (Cornish-Fisher expansion
/// about the normal quantile; better than 1e-3 relative for dof >= 3).
pub fn student_t_975(dof: usize) -> f64 {
    let z: f64 = 1.959_963_984_540_054;
    let v = dof.max(1) as f64;
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    z + (z3 + z) / (4.0 * v)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * v * v)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * v * v * v)
}
