//! `trim_sweep`: trends of trim over a sweep of airspeeds: the least and greatest slope of
//! each trend quantity between neighbouring airspeeds, and the worst residual.

use super::result::{Evaluated, PlotData, Quantities, compare_all};
use super::trim::{refuse_enforced, trim_quantities};
use super::{At, CheckKind, CheckSpec, Cx, Evaluate, Expectation, Kind, Refusal, Trivial};
use crate::quantity::{self as q, Quantity as Q};
use crate::subject::Subject;
use crate::yaml::InputError;

/// A `trim_sweep` check: its airspeeds, mph, rising.
#[derive(Debug, Clone, PartialEq)]
pub struct TrimSweepCheck {
    pub sweep_mph: Vec<f64>,
}

impl Kind for TrimSweepCheck {
    const KIND: CheckKind = CheckKind::TrimSweep;
    const FIELDS: &'static [&'static str] = &["sweep_mph"];
    const SUBJECTS: &'static str = "an aircraft";

    fn runs_on(subject: &Subject) -> bool {
        super::is_aircraft(subject)
    }

    fn resolve(cx: &Cx, spec: &CheckSpec) -> Result<Self, InputError> {
        let s = cx.needs(&spec.sweep_mph, "sweep_mph")?;
        let rising = s
            .windows(2)
            .all(|w| w[1].partial_cmp(&w[0]) == Some(std::cmp::Ordering::Greater));
        if s.len() < 2 || !rising || s.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(cx.err(".sweep_mph", "give at least two positive airspeeds, rising"));
        }
        Ok(Self { sweep_mph: s })
    }
}

impl Evaluate for TrimSweepCheck {
    fn quantities(&self) -> Vec<String> {
        q::sweep_names()
    }

    fn trivial(
        &self,
        _subject: &Subject,
        expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        refuse_enforced(expectations)?;
        Ok(expectations
            .iter()
            .map(|e| Trivial {
                quantity: e.quantity.clone(),
                value: 0.0,
                predictor: "a trim that does not change with airspeed",
                verdict: false,
            })
            .collect())
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let Subject::Aircraft { file, loading } = at.subject else {
            return Err("a trim_sweep check needs an aircraft".into());
        };
        let points = trim_sweep(file, *loading, &self.sweep_mph)?;
        let trends = sweep_trends(&points);
        let values: Vec<(&str, f64)> = trends.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        Ok(Evaluated {
            plot: Some(PlotData::Sweep { points }),
            ..Evaluated::of(compare_all(expectations, &values)?)
        })
    }
}

/// Trims over a sweep of airspeeds: each point's quantities, or the first failure (named by
/// its airspeed).
pub fn trim_sweep(
    file: &crate::aircraft_file::AircraftFile,
    loading: crate::Loading,
    sweep_mph: &[f64],
) -> Result<Vec<(f64, Quantities)>, String> {
    sweep_mph
        .iter()
        .map(|&v| {
            let request = crate::TrimRequest {
                airspeed_mph: v,
                climb_m_s: 0.0,
                turn_rate_deg_s: 0.0,
            };
            trim_quantities(file, loading, request)
                .map(|q| (v, q))
                .map_err(|e| format!("at {v} mph: {e}"))
        })
        .collect()
}

/// The trend quantities of a sweep (see [`crate::quantity::sweep_names`]).
pub fn sweep_trends(points: &[(f64, Quantities)]) -> Vec<(String, f64)> {
    let get = |q: &Quantities, name: &str| {
        q.iter()
            .find(|(n, _)| *n == name)
            .map_or(f64::NAN, |(_, v)| *v)
    };
    let mut out = vec![(
        Q::MaxResidualNorm.name().to_string(),
        points
            .iter()
            .map(|(_, q)| get(q, Q::ResidualNorm.name()))
            .fold(0.0f64, |m, v| if v.is_nan() { f64::NAN } else { m.max(v) }),
    )];
    for name in crate::quantity::TREND.iter().map(|q| q.name()) {
        let slopes: Vec<f64> = points
            .windows(2)
            .map(|w| (get(&w[1].1, name) - get(&w[0].1, name)) / (w[1].0 - w[0].0))
            .collect();
        let lo = slopes.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = slopes.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let nan = slopes.iter().any(|v| v.is_nan());
        out.push((
            format!("{name}_per_mph_min"),
            if nan { f64::NAN } else { lo },
        ));
        out.push((
            format!("{name}_per_mph_max"),
            if nan { f64::NAN } else { hi },
        ));
    }
    out
}
