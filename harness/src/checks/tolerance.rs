//! Tolerances: their kinds, and the arithmetic that judges a value against an expectation.
//!
//! Case loading uses it to refuse checks that a trivial predictor would pass, and evaluation to
//! judge the model; neither depends on the other.
//!
//! # Margins
//! Every judgement gives a margin that is positive when the value is admitted:
//! `absolute`: `bound - |value - expected|`; `relative`: `bound |expected| - |value - expected|`;
//! `interval`: the distance to the nearer end, `min(value - lower, upper - value)`;
//! `rounding`: as `absolute`, with the bound computed by evaluation; `factor`: in log units,
//! `ln f - |ln(value / expected)|` (`-ln f - |ln|value / expected||` across a sign change); `sign`: the value itself, positive for the stated sign, and a
//! zero value is never admitted. A NaN value, bound or margin is never admitted.

use serde::{Deserialize, Serialize};

/// A resolved tolerance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tolerance {
    pub name: String,
    pub kind: ToleranceKind,
    pub reason: String,
    /// The level of an interval that is a confidence interval of the measured value (0.95):
    /// where the data's standard uncertainty comes from.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub confidence: Option<f64>,
    /// The measurement's standard deviation (an `absolute` or `relative` tolerance; a fraction of
    /// the value for `relative`), from repeat runs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub standard_deviation: Option<f64>,
    /// The degrees of freedom of `standard_deviation` (none: taken as known).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub degrees_of_freedom: Option<f64>,
}

/// Tolerance for published numbers that were rounded: the inputs (the model's matrices) to
/// `input_decimals`, the expected value to `output_decimals`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RoundingSpec {
    pub input_decimals: u32,
    pub output_decimals: u32,
}

/// The sign a `sign` tolerance asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sign {
    Positive,
    Negative,
}

/// The kinds of tolerance.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ToleranceKind {
    /// `|value - expected| <= bound`.
    Absolute(f64),
    /// `|value - expected| <= bound |expected|`.
    Relative(f64),
    /// `lower <= value <= upper` (no expected value).
    Interval(f64, f64),
    /// Published rounding propagated through the computation (see `eval`).
    Rounding(RoundingSpec),
    /// The same sign as the expected value and `1/f <= value/expected <= f`.
    Factor(f64),
    /// Strictly of the stated sign (no expected value): zero is not admitted.
    Sign(Sign),
}

impl ToleranceKind {
    /// Whether the tolerance takes no expected value.
    pub fn is_bound_only(&self) -> bool {
        matches!(self, Self::Interval(..) | Self::Sign(_))
    }
}

/// A value judged against an expectation.
#[derive(Debug, Clone, PartialEq)]
pub struct Judgement {
    pub margin: f64,
    /// The tolerance in words (`± 1.2e-3`, `in [-0.133, -0.044]`).
    pub allowed: String,
    /// The admitted range as numbers (for plots and records).
    pub lower: f64,
    pub upper: f64,
    pub pass: bool,
}

/// Judges `value` against `expected` under `kind`; `rounding` gives the bound of a `rounding`
/// tolerance (computed by evaluation). `None` when the kind needs an expected value and none is
/// given (refused at load).
pub fn judge(
    kind: &ToleranceKind,
    expected: Option<f64>,
    value: f64,
    rounding: Option<f64>,
) -> Option<Judgement> {
    let (margin, allowed, (lower, upper)) = match (kind, expected) {
        (ToleranceKind::Absolute(b), Some(x)) => {
            (b - (value - x).abs(), format!("± {b:.3e}"), (x - b, x + b))
        }
        (ToleranceKind::Relative(r), Some(x)) => {
            let b = r * x.abs();
            (
                b - (value - x).abs(),
                format!("± {:.3} % ({b:.3e})", 100.0 * r),
                (x - b, x + b),
            )
        }
        (ToleranceKind::Interval(lo, hi), None) => (
            (value - lo).min(hi - value),
            format!("in [{lo}, {hi}]"),
            (*lo, *hi),
        ),
        (ToleranceKind::Rounding(r), Some(x)) => {
            let b = rounding?;
            (
                b - (value - x).abs(),
                format!(
                    "± {b:.3e} (rounding to {} / {} decimals)",
                    r.input_decimals, r.output_decimals
                ),
                (x - b, x + b),
            )
        }
        (ToleranceKind::Factor(f), Some(x)) => {
            // In log units; across a sign change, as far again beyond the factor (a zero value
            // is infinitely far).
            let ratio = value / x;
            let margin = if ratio > 0.0 {
                f.ln() - ratio.ln().abs()
            } else {
                -f.ln() - ratio.abs().ln().abs()
            };
            let (a, b) = (x / f, x * f);
            (
                margin,
                format!("same sign, within x{f} (ratio {ratio:.3})"),
                (a.min(b), a.max(b)),
            )
        }
        (ToleranceKind::Sign(s), None) => match s {
            Sign::Positive => (value, "> 0".to_string(), (0.0, f64::INFINITY)),
            Sign::Negative => (-value, "< 0".to_string(), (f64::NEG_INFINITY, 0.0)),
        },
        _ => return None,
    };
    let strict = matches!(kind, ToleranceKind::Sign(_));
    let pass = value.is_finite()
        && margin.is_finite()
        && if strict { margin > 0.0 } else { margin >= 0.0 };
    Some(Judgement {
        margin,
        allowed,
        lower,
        upper,
        pass,
    })
}

/// Whether a trivial prediction `value` would pass (`None` when that cannot be told at load:
/// a rounding tolerance, whose bound needs the model).
pub fn admits(kind: &ToleranceKind, expected: Option<f64>, value: f64) -> Option<bool> {
    if matches!(kind, ToleranceKind::Rounding(_)) {
        return None;
    }
    judge(kind, expected, value, None).map(|j| j.pass)
}
