//! Airframe coefficients estimated by published methods, from geometry, each with the range its
//! method's accuracy gives: what an aircraft file can use where nothing was measured, and what
//! `cierva estimate` prints step by step.
//!
//! One module per method family, each a set of pure functions from geometry (and, for the
//! propeller's effect, its operating point) to an [`Estimate`]:
//! * [`lifting_surface`]: lift-curve slopes from aspect ratio and sweep (Helmbold's equation in
//!   DATCOM's form), and a fin's effective aspect ratio with the end-plate effect of the body and
//!   the tailplane (DATCOM Sec. 5.3.1.1, its charts read by hand);
//! * [`body`]: a pod as the prolate spheroid of its length and cross-section, its apparent-mass
//!   factors (Lamb), its destabilising Munk couple in sideslip (Munk 1924) and the sidewash its
//!   cross-flow makes at a point behind it;
//! * [`slipstream`]: the propeller's slipstream by momentum theory: its velocity and dynamic
//!   pressure at a surface, the share of a surface inside it, and how much of the sideslip the
//!   propeller's normal force takes out of it;
//! * [`airframe`]: the steps for an aircraft's fin, tailplane and pod in order, composed from the
//!   others (what `cierva estimate` prints and an aircraft file's values are checked against).
//!
//! Each method is a [`Method`]: its name, source (with the equation or figure) and stated
//! accuracy. Where the source states no accuracy that the project could reach, the accuracy
//! says "estimated:" and why. A range is the method's accuracy (and, for a chart, its reading),
//! not the uncertainty of the geometry fed to it: that belongs to the geometry's own ranges.
//!
//! Bad geometry (a zero span, a negative chord, a pod shorter than it is wide, a surface outside
//! a chart's domain) is an [`EstimateError`] naming the input, never a panic. The module uses
//! nothing from the assembled aircraft or above.

pub mod airframe;
pub mod body;
pub mod lifting_surface;
pub mod slipstream;

use serde::Serialize;
use thiserror::Error;

/// An estimated value and the range its method's accuracy gives (`lower <= value <= upper`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    pub value: f64,
    pub lower: f64,
    pub upper: f64,
}

impl Estimate {
    /// A value with no range of its own (a geometric identity, or a definition).
    pub fn exact(value: f64) -> Self {
        Self {
            value,
            lower: value,
            upper: value,
        }
    }

    /// A value with a range `[lower, upper]` (put in order, and widened to hold the value).
    pub fn within(value: f64, lower: f64, upper: f64) -> Self {
        let (lo, hi) = if lower <= upper {
            (lower, upper)
        } else {
            (upper, lower)
        };
        Self {
            value,
            lower: lo.min(value),
            upper: hi.max(value),
        }
    }

    /// A value with a range from `below` under it to `above` over it, as fractions of it
    /// (`relative(2.0, 0.1, 0.2)` is 2.0 in [1.8, 2.4]).
    pub fn relative(value: f64, below: f64, above: f64) -> Self {
        Self::within(
            value,
            value - below * value.abs(),
            value + above * value.abs(),
        )
    }

    /// `f` of an estimate through a monotonic `f`: the value's image, with the range spanned by
    /// the images of its ends.
    pub fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Self::within(f(self.value), f(self.lower), f(self.upper))
    }

    /// The range widened by `below` and `above` as fractions of its ends (a second accuracy on
    /// top of the first, such as a method's on its inputs' reading).
    pub fn widened(self, below: f64, above: f64) -> Self {
        Self::within(
            self.value,
            self.lower - below * self.lower.abs(),
            self.upper + above * self.upper.abs(),
        )
    }
}

/// A published method: what it estimates, where it comes from and how accurate its source says
/// it is (or "estimated: ..." and why, where no stated accuracy could be reached).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Method {
    pub name: &'static str,
    /// The source with its section, equation or figure (labels as `REFERENCES.md` gives them).
    pub source: &'static str,
    pub accuracy: &'static str,
}

/// Geometry or an operating point that gives no finite estimate.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EstimateError {
    /// `name` is the input as the function's caller knows it (`span_m`, `length_m`, ...).
    #[error("{name} must be {requirement}, got {value}")]
    Input {
        name: &'static str,
        requirement: &'static str,
        value: f64,
    },
    /// The geometry is outside what the method's chart or theory covers.
    #[error("{name} = {value:.3} is outside {method}'s domain: {domain}")]
    Domain {
        name: &'static str,
        value: f64,
        method: &'static str,
        domain: &'static str,
    },
}

/// `value` if it is finite and positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, EstimateError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(EstimateError::Input {
            name,
            requirement: "positive and finite",
            value,
        })
    }
}

/// `value` if it is finite and not negative.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, EstimateError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(EstimateError::Input {
            name,
            requirement: "non-negative and finite",
            value,
        })
    }
}

/// `value` if it is finite.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, EstimateError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(EstimateError::Input {
            name,
            requirement: "finite",
            value,
        })
    }
}

/// Linear interpolation in a table of `(x, y)` rows with `x` rising; `None` outside it.
pub(crate) fn interpolate(table: &[(f64, f64)], x: f64) -> Option<f64> {
    let (first, last) = (table.first()?, table.last()?);
    if !(first.0..=last.0).contains(&x) {
        return None;
    }
    let i = table
        .partition_point(|r| r.0 <= x)
        .clamp(1, table.len() - 1);
    let (a, b) = (table[i - 1], table[i]);
    Some(a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_estimate_keeps_its_value_inside_its_range() {
        let e = Estimate::relative(2.0, 0.1, 0.2);
        assert_eq!((e.lower, e.value, e.upper), (1.8, 2.0, 2.4));
        let n = Estimate::relative(-2.0, 0.1, 0.2);
        assert_eq!((n.lower, n.upper), (-2.2, -1.6));
        let m = Estimate::within(1.0, 3.0, 2.0).map(|x| -x);
        assert_eq!((m.lower, m.value, m.upper), (-3.0, -1.0, -1.0));
        let w = Estimate::within(1.0, 0.5, 2.0).widened(0.1, 0.1);
        assert_eq!((w.lower, w.upper), (0.45, 2.2));
    }

    #[test]
    fn interpolation_refuses_to_extrapolate() {
        let t = [(0.0, 0.0), (1.0, 2.0), (3.0, 3.0)];
        assert_eq!(interpolate(&t, 0.5), Some(1.0));
        assert_eq!(interpolate(&t, 2.0), Some(2.5));
        assert_eq!(interpolate(&t, 3.0), Some(3.0));
        assert_eq!(interpolate(&t, 3.1), None);
        assert_eq!(interpolate(&t, f64::NAN), None);
    }
}
