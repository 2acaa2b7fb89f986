//! BCAR Section T dynamic-stability criteria for oscillatory modes (seed 000 Sec. V).
//!
//! The criteria relate the damping that is acceptable to the period `T` of the oscillation:
//!
//! 1. `T < 5 s`: damp to half amplitude in not more than one cycle;
//! 2. `5 <= T < 10 s`: damp to half amplitude in not more than two cycles;
//! 3. `10 <= T < 20 s`: the oscillation must be damped;
//! 4. `T >= 20 s`: if unstable, the time to double amplitude must be greater than 20 s.
//!
//! The paper writes the bands as `T < 5`, `5 < T < 10`, `10 < T < 20` and `T > 20`; a period
//! exactly on a band edge is assigned here to the band above it.
//!
//! # The compliance chart
//! Seed 000 Fig. 3 plots period against damping with the boundary; a mode to the right of the
//! boundary complies. Here the abscissa is the *damping index*
//! `x = T / t_half = -re T / ln 2`: the inverse of the number of cycles to half amplitude for a
//! stable mode, and minus the inverse of the number of cycles to double amplitude for an
//! unstable one, so the axis is continuous through neutral stability. The boundary is
//! `x_b(T) = 1` (band 1), `1/2` (band 2), `0` (band 3) and `-T/20 s` (band 4). A mode complies
//! when `x >= x_b(T)` (strictly `x > 0` in band 3 and strictly `t_double > 20 s` in band 4).
//!
//! The margin is reported two ways: on the chart, `x - x_b(T)`, and as a real part,
//! `re_b(T) - re` in 1/s, where `re_b = -x_b ln 2 / T` is the largest real part that complies at
//! this period. Both are positive when the mode complies.

use crate::analysis::modes::Mode;
use serde::Serialize;
use std::f64::consts::LN_2;

/// The period band of the criteria.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Band {
    /// T < 5 s.
    Under5s,
    /// 5 <= T < 10 s.
    From5To10s,
    /// 10 <= T < 20 s.
    From10To20s,
    /// T >= 20 s.
    Over20s,
}

impl Band {
    /// The band of a period.
    pub fn of(period_s: f64) -> Self {
        if period_s < 5.0 {
            Self::Under5s
        } else if period_s < 10.0 {
            Self::From5To10s
        } else if period_s < 20.0 {
            Self::From10To20s
        } else {
            Self::Over20s
        }
    }

    /// The requirement in words.
    pub fn requirement(self) -> &'static str {
        match self {
            Self::Under5s => "T < 5 s: damp to half amplitude in not more than one cycle",
            Self::From5To10s => "5 <= T < 10 s: damp to half amplitude in not more than two cycles",
            Self::From10To20s => "10 <= T < 20 s: the oscillation must be damped",
            Self::Over20s => "T >= 20 s: if unstable, time to double amplitude greater than 20 s",
        }
    }
}

/// Pass or fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Complies,
    DoesNotComply,
}

/// The assessment of one oscillatory mode.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Assessment {
    pub band: Band,
    pub verdict: Verdict,
    pub period_s: f64,
    /// Damping index `x = -re T / ln 2` (the chart's abscissa).
    pub damping_index: f64,
    /// The boundary's abscissa at this period.
    pub boundary_index: f64,
    /// `damping_index - boundary_index`: positive when the mode complies.
    pub margin_index: f64,
    /// Largest real part that complies at this period, 1/s.
    pub boundary_real_per_s: f64,
    /// `boundary_real_per_s - re`: positive when the mode complies, 1/s.
    pub margin_real_per_s: f64,
}

/// The boundary's abscissa at a period (see the module docs).
pub fn boundary_index(period_s: f64) -> f64 {
    match Band::of(period_s) {
        Band::Under5s => 1.0,
        Band::From5To10s => 0.5,
        Band::From10To20s => 0.0,
        Band::Over20s => -period_s / 20.0,
    }
}

/// Assesses an oscillatory mode; `None` for a real mode (the criteria do not apply).
pub fn assess(mode: &Mode) -> Option<Assessment> {
    let period_s = mode.period_s?;
    Some(assess_eigenvalue(mode.eigenvalue.re, period_s))
}

/// Assesses an oscillation with real part `re` (1/s) and period `period_s`.
pub fn assess_eigenvalue(re: f64, period_s: f64) -> Assessment {
    let band = Band::of(period_s);
    let x = -re * period_s / LN_2;
    let xb = boundary_index(period_s);
    // Band 3 needs strict damping and band 4 a strictly longer doubling time; with x and xb
    // both exact there, the strict comparison is `x > xb`. Bands 1 and 2 allow equality.
    let complies = match band {
        Band::Under5s | Band::From5To10s => x >= xb,
        Band::From10To20s | Band::Over20s => x > xb,
    } && x.is_finite();
    let re_b = -xb * LN_2 / period_s;
    Assessment {
        band,
        verdict: if complies {
            Verdict::Complies
        } else {
            Verdict::DoesNotComply
        },
        period_s,
        damping_index: x,
        boundary_index: xb,
        margin_index: x - xb,
        boundary_real_per_s: re_b,
        margin_real_per_s: re_b - re,
    }
}

/// The boundary as a polyline `(damping_index, period_s)` from `T = 0` to `t_max_s`, for plots.
///
/// The steps at 5, 10 and 20 s appear as horizontal segments (two points at the same period).
pub fn boundary_curve(t_max_s: f64) -> Vec<(f64, f64)> {
    let mut pts = vec![(1.0, 0.0), (1.0, 5.0), (0.5, 5.0), (0.5, 10.0)];
    pts.extend([(0.0, 10.0), (0.0, 20.0), (-1.0, 20.0)]);
    if t_max_s > 20.0 {
        pts.push((-t_max_s / 20.0, t_max_s));
    }
    pts.retain(|&(_, t)| t <= t_max_s.max(0.0));
    pts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(re: f64, period: f64) -> Assessment {
        assess_eigenvalue(re, period)
    }

    #[test]
    fn each_band_applies_its_own_rule() {
        // Band 1: one cycle to half amplitude at T = 4 s needs re <= -ln2/4.
        let edge = -LN_2 / 4.0;
        assert_eq!(check(edge * 1.01, 4.0).verdict, Verdict::Complies);
        assert_eq!(check(edge * 0.99, 4.0).verdict, Verdict::DoesNotComply);
        // Band 2: two cycles at T = 8 s needs re <= -ln2/16.
        let edge = -LN_2 / 16.0;
        assert_eq!(check(edge * 1.01, 8.0).verdict, Verdict::Complies);
        assert_eq!(check(edge * 0.99, 8.0).verdict, Verdict::DoesNotComply);
        // Band 3: any damping, none without.
        assert_eq!(check(-1e-6, 15.0).verdict, Verdict::Complies);
        assert_eq!(check(0.0, 15.0).verdict, Verdict::DoesNotComply);
        // Band 4: doubling slower than 20 s.
        let edge = LN_2 / 20.0;
        assert_eq!(check(edge * 0.99, 30.0).verdict, Verdict::Complies);
        assert_eq!(check(edge * 1.01, 30.0).verdict, Verdict::DoesNotComply);
    }

    #[test]
    fn margins_agree_in_sign_and_vanish_on_the_boundary() {
        for (re, t) in [(-0.3, 3.0), (0.01, 25.0), (-0.01, 12.0), (-0.05, 7.0)] {
            let a = check(re, t);
            assert_eq!(a.margin_index > 0.0, a.margin_real_per_s > 0.0);
            let on = check(a.boundary_real_per_s, t);
            assert!(on.margin_index.abs() < 1e-12 && on.margin_real_per_s.abs() < 1e-15);
        }
    }

    #[test]
    fn band_edges_go_to_the_band_above() {
        assert_eq!(Band::of(5.0), Band::From5To10s);
        assert_eq!(Band::of(10.0), Band::From10To20s);
        assert_eq!(Band::of(20.0), Band::Over20s);
    }

    #[test]
    fn curve_is_a_staircase_then_a_line() {
        let c = boundary_curve(40.0);
        assert_eq!(c.first(), Some(&(1.0, 0.0)));
        assert_eq!(c.last(), Some(&(-2.0, 40.0)));
        for &(x, t) in &c[1..] {
            assert!((x - boundary_index(t)).abs() < 1e-12 || [5.0, 10.0, 20.0].contains(&t));
        }
    }
}
