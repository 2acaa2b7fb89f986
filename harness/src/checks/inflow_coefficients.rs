//! `inflow_coefficients`: the inflow components found from a teeter record's blade flapping
//! (seed 003), with the coning and flapping they are found from.

use super::result::{Evaluated, compare_all};
use super::{At, CheckSpec, Cx, Evaluate, Expectation, Kind, Placed, Refusal, Trivial};
use crate::checks::subject::Subject;
use crate::inputs::quantity::{self as q, Quantity as Q};
use crate::inputs::yaml::InputError;

/// An `inflow_coefficients` check (everything it needs is its case's teeter record).
#[derive(Debug, Clone, PartialEq)]
pub struct InflowCoefficientsCheck;

/// An `inflow_coefficients` check's own fields, as written: none.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InflowCoefficientsSpec {}

impl Kind for InflowCoefficientsCheck {
    type Spec = InflowCoefficientsSpec;
    const SUBJECTS: &'static str = "a teeter record (`flap_record`)";

    fn runs_on(subject: &Subject) -> bool {
        matches!(subject, Subject::FlapRecord { .. })
    }

    fn resolve(_: &Cx, _: InflowCoefficientsSpec, _: &CheckSpec) -> Result<Self, InputError> {
        Ok(Self)
    }
}

impl Evaluate for InflowCoefficientsCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::INFLOW_COEFFICIENTS)
    }

    fn placed(&self) -> Option<Placed<'_>> {
        Some(Placed::FlapRecord)
    }

    /// Uniform inflow: no first harmonics.
    fn trivial(
        &self,
        _subject: &Subject,
        _expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        Ok([Q::InflowV1sMS, Q::InflowV1cMS]
            .iter()
            .map(|q| Trivial::value(q.name(), 0.0, "uniform inflow"))
            .collect())
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let Subject::FlapRecord {
            record,
            rotor,
            settings,
        } = at.subject
        else {
            return Err("an inflow check needs a teeter record".into());
        };
        let r = crate::ident::flap::inflow_from_record(record, &rotor.rotor, settings)?;
        let values = [
            (Q::InflowV0MS.name(), r.v0_m_s),
            (Q::InflowV1sMS.name(), r.v1s_m_s),
            (Q::InflowV1cMS.name(), r.v1c_m_s),
            (Q::ConingDeg.name(), r.coning_deg),
            (Q::Beta1cDeg.name(), r.beta_1c_deg),
            (Q::Beta1sDeg.name(), r.beta_1s_deg),
        ];
        Ok(Evaluated::of(compare_all(expectations, &values)?))
    }
}
