//! The validation comparison of ASME V&V 20-2009 (Sec. 2; REFERENCES.md): the comparison error
//! `E = S - D` of a simulation result `S` against measured data `D`, and the validation
//! uncertainty
//!
//! ```text
//! u_val = sqrt(u_num^2 + u_input^2 + u_D^2)
//! ```
//!
//! from the numerical solution (`u_num`), the model's inputs (`u_input`) and the data (`u_D`),
//! each a standard uncertainty. The model-form error lies in `E +- k u_val` (about 95 %), with
//! `k = 2`, or Student's t at the effective degrees of freedom where the data's standard
//! deviation comes from few repeats ([`coverage`]); `2` below stands for `k`.
//!
//! # Verdicts
//! - **model-form error**: `|E| > 2 u_val`. No plausible input, numerical error or data error
//!   explains the difference: the model's form is at fault. Where the inputs were sampled, also
//!   when `D` lies outside the sampled 95 % interval of `S` widened by `2 sqrt(u_num^2 +
//!   u_D^2)` either way: `E +- 2 u_val` assumes a symmetric spread, and a quantity that the
//!   inputs spread one way only (a fin's weathercock stability, bounded below by the rest of
//!   the airframe) can miss the data on every sample while `|E| <= 2 u_val`. V&V 20 (Sec. 2-4)
//!   asks for the distribution's own interval where it is not normal.
//! - **inconclusive**: otherwise, when the model's own uncertainty, `2 sqrt(u_num^2 +
//!   u_input^2)`, is wider than the check's tolerance (its half-width): the inputs must be
//!   known better before agreement means anything. The data's part is left out of this test on
//!   purpose: for a check against a 95 % flight bound the tolerance *is* `1.96 u_D`, so `2 u_val`
//!   would exceed it by construction and every such check would be inconclusive.
//! - **agrees**: `|E| <= 2 u_val` and the model's uncertainty is inside the tolerance.
//! - **no data uncertainty**: the data state no uncertainty, so `u_val` cannot be formed and
//!   `E` cannot be weighed (a single flight point without its scatter); `E` and the model's own
//!   uncertainty are given, not a verdict on them. Apart from inconclusive, which says the
//!   inputs must be known better.

use serde::Serialize;

/// The coverage factor: `2 u` is about a 95 % interval. It is the least one: where the data's
/// standard deviation comes from few repeats, [`coverage`] gives Student's t at the effective
/// degrees of freedom.
pub const COVERAGE: f64 = 2.0;

/// The coverage factor of `u_val` at 95 %: Student's t at the effective degrees of freedom of
/// Welch and Satterthwaite, `nu_eff = u_val^4 / (u_D^4 / nu_D)` (the model's terms, from many
/// samples or a grid study, taken as known), and never below [`COVERAGE`]; [`COVERAGE`] where the
/// data's degrees of freedom are not stated. (JCGM 100:2008, G.4 and G.6.4.)
pub fn coverage(u_val: f64, u_data: f64, data_dof: Option<f64>) -> (f64, Option<f64>) {
    let Some(nu) = data_dof else {
        return (COVERAGE, None);
    };
    if u_data <= 0.0 {
        return (COVERAGE, None);
    }
    let nu_eff = u_val.powi(4) / (u_data.powi(4) / nu);
    let t = statrs::distribution::StudentsT::new(0.0, 1.0, nu_eff)
        .map(|d| statrs::distribution::ContinuousCDF::inverse_cdf(&d, 0.975))
        .unwrap_or(COVERAGE);
    (t.max(COVERAGE), Some(nu_eff))
}

/// The verdict of a comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Vv20Verdict {
    Agrees,
    ModelFormError,
    Inconclusive,
    /// The data state no uncertainty: `E` is given, not weighed.
    NoDataUncertainty,
}

impl Vv20Verdict {
    /// For tables.
    pub fn label(self) -> &'static str {
        match self {
            Self::Agrees => "agrees",
            Self::ModelFormError => "model-form error",
            Self::Inconclusive => "inconclusive",
            Self::NoDataUncertainty => "no data uncertainty",
        }
    }

    pub const ALL: [Vv20Verdict; 4] = [
        Self::Agrees,
        Self::ModelFormError,
        Self::Inconclusive,
        Self::NoDataUncertainty,
    ];
}

/// One comparison, with its numbers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Comparison {
    /// `E = S - D`.
    pub estimate_error: f64,
    pub u_num: f64,
    pub u_input: f64,
    pub u_data: f64,
    pub u_val: f64,
    /// The coverage factor `k` of `u_val` ([`coverage`]): 2, or Student's t at the effective
    /// degrees of freedom where the data's are stated.
    pub coverage: f64,
    /// The effective degrees of freedom of `u_val`, where the data's are stated.
    pub effective_dof: Option<f64>,
    /// Where the model-form error lies: `E -+ k u_val`.
    pub model_form_interval: [f64; 2],
    /// The check's tolerance as a half-width about `D`.
    pub tolerance_half_width: f64,
    /// The sampled 95 % interval of `S` widened by `2 sqrt(u_num^2 + u_D^2)`, where sampled.
    pub sampled_interval: Option<[f64; 2]>,
    pub verdict: Vv20Verdict,
}

/// The standard uncertainties of a comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Uncertainties {
    pub u_num: f64,
    pub u_input: f64,
    pub u_data: f64,
    /// The degrees of freedom of `u_data` (none: known).
    pub data_dof: Option<f64>,
}

/// Compares `simulation` with `data`, given the uncertainties, the check's tolerance as a
/// half-width, and (where the inputs were sampled) the 2.5 and 97.5 percentiles of the
/// simulation over them. Returns `None` when a number is not finite (a verdict is never drawn
/// from NaN).
pub fn compare(
    simulation: f64,
    data: f64,
    u: Uncertainties,
    tolerance_half_width: f64,
    sampled: Option<[f64; 2]>,
) -> Option<Comparison> {
    let Uncertainties {
        u_num,
        u_input,
        u_data,
        data_dof,
    } = u;
    let e = simulation - data;
    let u_val = (u_num * u_num + u_input * u_input + u_data * u_data).sqrt();
    let model = (u_num * u_num + u_input * u_input).sqrt();
    if ![e, u_val, tolerance_half_width]
        .iter()
        .all(|x| x.is_finite())
    {
        return None;
    }
    let (k, effective_dof) = coverage(u_val, u_data, data_dof);
    let widen = COVERAGE * (u_num * u_num + u_data * u_data).sqrt();
    let sampled_interval = sampled
        .filter(|[lo, hi]| lo.is_finite() && hi.is_finite())
        .map(|[lo, hi]| [lo - widen, hi + widen]);
    let outside_samples = sampled_interval.is_some_and(|[lo, hi]| !(lo..=hi).contains(&data));
    let verdict = if e.abs() > k * u_val || outside_samples {
        Vv20Verdict::ModelFormError
    } else if COVERAGE * model > tolerance_half_width {
        Vv20Verdict::Inconclusive
    } else {
        Vv20Verdict::Agrees
    };
    Some(Comparison {
        estimate_error: e,
        u_num,
        u_input,
        u_data,
        u_val,
        coverage: k,
        effective_dof,
        model_form_interval: [e - k * u_val, e + k * u_val],
        tolerance_half_width,
        sampled_interval,
        verdict,
    })
}
