//! What evaluating a check gives: each quantity compared with its expectation, what the
//! model found instead of an answer, and what the report plots.

use super::Expectation;
use crate::checks::tolerance::ToleranceKind;
use cierva_model::analysis::bcar::Verdict;
use cierva_model::analysis::modes::Complex;
use serde::Serialize;

/// Named computed values of a check, as the flight models give them (defined once, in
/// [`crate::external`]).
pub use crate::external::Quantities;

/// What the model found instead of a check's quantities, with the numbers that describe it.
pub type Found = (Finding, Vec<(String, f64)>);

/// What the model found instead of the quantities a check asks for: a physical answer, not an
/// evaluation error.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[serde(tag = "finding", rename_all = "snake_case")]
pub enum Finding {
    /// The model has no equilibrium where the reference has one (an isolated rotor whose
    /// driving torque never changes sign, or whose inflow has no solution). A validation
    /// failure; the check's `fingerprint` holds the numbers that describe it (the largest
    /// driving-torque coefficient over the bracket, the solver's last residual).
    NoEquilibrium { reason: String },
    /// The data cannot decide the check: no quantity is computed, and the check does not pass
    /// (a `frequency_response` check whose reference has no frequency of enough coherence,
    /// "inconclusive: coherence"). `reason` starts with what is lacking.
    Inconclusive { reason: String },
    /// The model found its quantities with an equation outside its stated validity (momentum
    /// theory in descent through the rotor's own wake): the quantities are shown, and the
    /// check does not pass on them. `reason` says which equation and where.
    OutsideValidity { reason: String },
}

impl Finding {
    /// The finding in words, for tables and logs ("no equilibrium: ...", "inconclusive: ...").
    pub fn describe(&self) -> String {
        match self {
            Self::NoEquilibrium { reason } => format!("no equilibrium: {reason}"),
            Self::Inconclusive { reason } => format!("inconclusive: {reason}"),
            Self::OutsideValidity { reason } => format!("outside validity: {reason}"),
        }
    }

    /// Why, without the label.
    pub fn reason(&self) -> &str {
        match self {
            Self::NoEquilibrium { reason }
            | Self::Inconclusive { reason }
            | Self::OutsideValidity { reason } => reason,
        }
    }
}

/// One quantity compared with its expectation.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct QuantityResult {
    pub quantity: String,
    pub value: f64,
    pub expected: Option<f64>,
    pub tolerance: String,
    /// The tolerance in words (`± 1.2e-3`, `[-0.133, -0.044]`).
    pub allowed: String,
    pub reason: String,
    /// The allowed range as numbers (for plots): `expected ± bound`, the interval, or
    /// `expected / factor .. expected * factor`.
    pub lower: f64,
    pub upper: f64,
    pub margin: f64,
    pub pass: bool,
}

/// A check's data for the report's plots.
#[derive(Debug, Clone, PartialEq)]
pub enum PlotData {
    /// Every eigenvalue of the system the check looked at, and the check's mode; for a check
    /// that sets a derivative, the root locus from its nominal value to the one set.
    Modes {
        eigenvalues: Vec<Complex>,
        selected: Option<Complex>,
        locus: Option<Locus>,
    },
    /// The reference record and the model's responses, signal by signal.
    TimeHistory { traces: Vec<Trace> },
    /// The trims of a sweep: airspeed, mph, and the quantities at it.
    Sweep { points: Vec<(f64, Quantities)> },
    /// A flight test's trim points and the model at each, by quantity.
    TrimPoints {
        quantities: Vec<(String, Vec<PointAgainstModel>)>,
    },
    /// A frequency response: the reference's (from records or a file) with its coherence, and
    /// the model's, at the reference's frequencies; `title` names the output and input.
    FrequencyResponse {
        title: String,
        frequencies_hz: Vec<f64>,
        reference: Vec<rustfft::num_complex::Complex64>,
        coherence: Vec<f64>,
        model: Vec<rustfft::num_complex::Complex64>,
    },
}

/// A flight trim point and the model trimmed at it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointAgainstModel {
    pub airspeed_mph: f64,
    /// The point's value and its scatter (one standard deviation).
    pub flight: f64,
    pub sd: f64,
    pub model: f64,
}

/// A root locus (seed 002 Figs. 2, 3, 6-8): the system's eigenvalues as one derivative moves
/// from its nominal value to the value a check sets, and a quarter of the way beyond both.
#[derive(Debug, Clone, PartialEq)]
pub struct Locus {
    pub derivative: String,
    pub nominal: f64,
    pub set: f64,
    /// `(value, eigenvalues)` along the sweep.
    pub points: Vec<(f64, Vec<Complex>)>,
}

/// One response of a time-history check: the reference, the model, and the allowed error.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub signal: String,
    pub time_s: Vec<f64>,
    pub reference: Vec<f64>,
    pub model: Vec<f64>,
    /// The tolerance on the largest error, where the check sets an absolute one.
    pub band: Option<f64>,
}

/// What evaluating a check gives.
#[derive(Default)]
pub struct Evaluated {
    pub quantities: Vec<QuantityResult>,
    pub verdict: Option<(Verdict, Verdict)>,
    pub plot: Option<PlotData>,
    pub finding: Option<Finding>,
    pub fingerprint: Vec<(String, f64)>,
    /// What the check says about how it computed its quantities (which linearisation gave the
    /// model's response), in words.
    pub note: Option<String>,
}

impl Evaluated {
    pub fn of(quantities: Vec<QuantityResult>) -> Self {
        Self {
            quantities,
            ..Self::default()
        }
    }
}

/// Compares one computed value with its expectation; `rounding` gives the bound of a
/// `rounding` tolerance (asked only for one).
pub fn compare(
    e: &Expectation,
    value: f64,
    rounding: impl FnOnce() -> Result<f64, String>,
) -> Result<QuantityResult, String> {
    let bound = match e.tolerance.kind {
        ToleranceKind::Rounding(_) => Some(rounding()?),
        _ => None,
    };
    let j = crate::checks::tolerance::judge(&e.tolerance.kind, e.value, value, bound)
        .ok_or("expectation and tolerance do not fit (checked at load)")?;
    Ok(QuantityResult {
        quantity: e.quantity.clone(),
        value,
        expected: e.value,
        tolerance: e.tolerance.name.clone(),
        allowed: j.allowed,
        reason: e.tolerance.reason.clone(),
        lower: j.lower,
        upper: j.upper,
        margin: j.margin,
        pass: j.pass,
    })
}

/// Compares every expectation with its value among `values` (quantities computed without a
/// rounding tolerance).
pub fn compare_all(
    expectations: &[Expectation],
    values: &[(&str, f64)],
) -> Result<Vec<QuantityResult>, String> {
    expectations
        .iter()
        .map(|e| {
            let v = values
                .iter()
                .find(|(n, _)| *n == e.quantity)
                .map(|(_, v)| *v)
                .ok_or_else(|| format!("`{}` is not computed", e.quantity))?;
            compare(e, v, || Ok(0.0))
        })
        .collect()
}
