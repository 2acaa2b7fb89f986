//! `trim_sweep`: trends of trim over a sweep of airspeeds: the least and greatest slope of
//! each trend quantity between neighbouring airspeeds, and the worst residual.

use super::result::{Evaluated, PlotData, Quantities, compare_all};
use super::trim::refuse_enforced;
use super::{At, CheckSpec, Cx, Evaluate, Expectation, Kind, Refusal, Snapshotted, Trivial};
use crate::checks::subject::Subject;
use crate::inputs::quantity::{self as q, Quantity as Q};
use crate::inputs::yaml::InputError;

/// A `trim_sweep` check: its airspeeds, mph, rising.
#[derive(Debug, Clone, PartialEq)]
pub struct TrimSweepCheck {
    pub sweep_mph: Vec<f64>,
}

/// A `trim_sweep` check's own fields, as written.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrimSweepSpec {
    /// The airspeeds, mph, rising.
    pub sweep_mph: Vec<f64>,
}

impl Kind for TrimSweepCheck {
    type Spec = TrimSweepSpec;
    const SUBJECTS: &'static str = super::FLIGHT_MODELS;

    fn runs_on(subject: &Subject) -> bool {
        super::is_flight_model(subject)
    }

    fn resolve(cx: &Cx, own: TrimSweepSpec, _: &CheckSpec) -> Result<Self, InputError> {
        let s = own.sweep_mph;
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

    /// The sweep's airspeeds, each trimmed in straight and level flight.
    fn snapshotted(&self) -> Vec<Snapshotted<'_>> {
        vec![Snapshotted::Trims(
            self.sweep_mph
                .iter()
                .map(|v| crate::inputs::condition::TrimRequest::level(*v))
                .collect(),
        )]
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
        let (model, loading) = super::flight_model(at.subject)
            .ok_or("a trim_sweep check needs an aircraft or an external model")?;
        let points = trim_sweep_of(model.as_ref(), loading, &self.sweep_mph)?;
        let trends = sweep_trends(&points);
        // A trend of a quantity the model does not give at every airspeed is an error that
        // names it, not a number that fails.
        for e in expectations {
            let base = if e.quantity == Q::MaxResidualNorm.name() {
                Q::ResidualNorm.name()
            } else {
                e.quantity
                    .trim_end_matches("_per_mph_min")
                    .trim_end_matches("_per_mph_max")
            };
            if let Some((v, _)) = points
                .iter()
                .find(|(_, q)| !q.iter().any(|(n, _)| *n == base))
            {
                return Err(format!(
                    "{} gives no `{base}` in its trim at {v} mph (`{}` needs it)",
                    model.describe(),
                    e.quantity
                ));
            }
        }
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
    file: &crate::inputs::aircraft::AircraftFile,
    loading: crate::inputs::condition::Loading,
    sweep_mph: &[f64],
) -> Result<Vec<(f64, Quantities)>, String> {
    trim_sweep_of(
        &crate::external::CiervaAircraft::new(file),
        loading,
        sweep_mph,
    )
}

/// [`trim_sweep`] of any flight model.
pub fn trim_sweep_of(
    model: &dyn crate::external::FlightModel,
    loading: crate::inputs::condition::Loading,
    sweep_mph: &[f64],
) -> Result<Vec<(f64, Quantities)>, String> {
    sweep_mph
        .iter()
        .map(|&v| {
            let request = crate::inputs::condition::TrimRequest::level(v);
            model
                .trim(&crate::external::Request::at(request, loading))
                .map(|q| (v, q))
                .map_err(|e| format!("at {v} mph: {e}"))
        })
        .collect()
}

/// The trend quantities of a sweep (see [`crate::inputs::quantity::sweep_names`]).
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
    for name in crate::inputs::quantity::TREND.iter().map(|q| q.name()) {
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
