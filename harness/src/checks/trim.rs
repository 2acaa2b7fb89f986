//! `trim`: one trimmed flight condition of an aircraft: controls, attitudes, rotor speed,
//! rotor thrust, flapping and inflow.

use super::result::{Evaluated, Quantities, compare_all};
use super::{
    At, CheckSpec, Cx, Evaluate, Expectation, Kind, Measured, Place, Placed, Refusal, Snapshotted,
    Trivial,
};
use crate::checks::subject::Subject;
use crate::inputs::quantity as q;
use crate::inputs::yaml::InputError;

/// A `trim` check: its flight condition.
#[derive(Debug, Clone, PartialEq)]
pub struct TrimCheck {
    pub condition: crate::inputs::condition::TrimRequest,
}

/// A `trim` check's own fields, as written.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrimSpec {
    /// The flight condition.
    pub condition: crate::inputs::condition::TrimRequest,
}

impl Kind for TrimCheck {
    type Spec = TrimSpec;
    const SUBJECTS: &'static str = super::FLIGHT_MODELS;

    fn runs_on(subject: &Subject) -> bool {
        super::is_flight_model(subject)
    }

    fn resolve(cx: &Cx, own: TrimSpec, _: &CheckSpec) -> Result<Self, InputError> {
        let condition = own.condition;
        super::check_condition(cx, &condition, false)?;
        Ok(Self { condition })
    }
}

impl Evaluate for TrimCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::TRIM)
    }

    fn condition(&self) -> Option<crate::inputs::condition::TrimRequest> {
        Some(self.condition)
    }

    fn series(&self) -> Option<String> {
        Some("trim".into())
    }

    fn measured(&self) -> Measured<'_> {
        Measured::At(Place::Flight(self.condition))
    }

    fn placed(&self) -> Option<Placed<'_>> {
        Some(Placed::Airspeed(self.condition.airspeed_mph))
    }

    fn snapshotted(&self) -> Vec<Snapshotted<'_>> {
        vec![Snapshotted::Trims(vec![self.condition])]
    }

    fn trivial(
        &self,
        _subject: &Subject,
        expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        refuse_enforced(expectations)?;
        Ok(vec![])
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let (model, loading) = super::flight_model(at.subject)
            .ok_or("a trim check needs an aircraft or an external model")?;
        let values = model.trim(&crate::external::Request::at(self.condition, loading))?;
        if let Some(e) = expectations
            .iter()
            .find(|e| !values.iter().any(|(n, _)| *n == e.quantity))
        {
            return Err(format!(
                "{} gives no `{}` in its trim",
                model.describe(),
                e.quantity
            ));
        }
        Ok(Evaluated::of(compare_all(expectations, &values)?))
    }
}

/// Refuses an expectation of what the trim solves for: a trim whose scaled residuals exceed
/// 1e-7, or whose rotor is not free, is an error, so such a check cannot fail.
pub fn refuse_enforced(expectations: &[Expectation]) -> Result<(), Refusal> {
    for q in q::ENFORCED_BY_TRIM {
        if expectations.iter().any(|e| e.quantity == q.name()) {
            return Err((
                format!(".expect.{q}"),
                format!(
                    "`{q}` is what the trim solves for (a trim whose scaled residuals exceed \
                     1e-7, or whose rotor is not free, is an error): a check of it cannot fail"
                ),
            ));
        }
    }
    Ok(())
}

/// The quantities of one trim (see [`crate::inputs::quantity::TRIM`]).
pub fn trim_quantities(
    file: &crate::inputs::aircraft::AircraftFile,
    loading: crate::inputs::condition::Loading,
    request: crate::inputs::condition::TrimRequest,
) -> Result<Quantities, String> {
    let t =
        crate::run::trim::run_trim(&file.aircraft, request, loading).map_err(|e| e.to_string())?;
    Ok(trim_quantities_of(&file.aircraft, loading, &t))
}

pub use crate::external::trim_quantities_of;
