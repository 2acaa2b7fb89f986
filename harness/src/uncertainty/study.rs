//! The uncertainty study of a case: its inputs, and the propagation that suits it, sampled
//! ([`super::propagate`]) or to first order ([`super::first_order`]). The entry points live
//! here, above both, so that neither method's module uses the other's.

use super::propagate::{
    CaseUncertainty, Propagation, PropagationSettings, inputs, sampled, without_inputs,
};
use crate::checks::CheckClass;
use crate::suite::case::Case;
use crate::suite::outcome::CheckResult;

/// Runs the propagation of one case. `done` is called after each evaluation (a progress bar).
pub fn propagate(
    case: &Case,
    settings: PropagationSettings,
    done: impl Fn() + Sync,
) -> Result<CaseUncertainty, String> {
    propagate_from(case, &crate::suite::outcome::run_case(case), settings, done)
}

/// [`propagate`] about results already computed with the nominal inputs (`validate`'s). A case
/// without uncertain inputs is not re-run: its quantities get no verdict, and say why.
pub fn propagate_from(
    case: &Case,
    nominal: &[CheckResult],
    settings: PropagationSettings,
    done: impl Fn() + Sync,
) -> Result<CaseUncertainty, String> {
    if settings.validation_only {
        let keep: Vec<bool> = case
            .checks
            .iter()
            .map(|k| k.class == CheckClass::Validation)
            .collect();
        let mut only = case.clone();
        only.checks = case
            .checks
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(c, _)| c.clone())
            .collect();
        let results: Vec<CheckResult> = nominal
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(r, _)| r.clone())
            .collect();
        let settings = PropagationSettings {
            validation_only: false,
            ..settings
        };
        return if only.checks.is_empty() {
            let mut none = without_inputs(&only, &results);
            none.method = "none: the case has no validation checks".into();
            Ok(none)
        } else {
            propagate_from(&only, &results, settings, done)
        };
    }
    let inputs = inputs(case)?;
    if inputs.is_empty() {
        return Ok(without_inputs(case, nominal));
    }
    let first = match settings.method {
        Propagation::Auto => case.checks.iter().any(|c| c.behaviour().tunnel().is_some()),
        Propagation::Sampled => false,
        Propagation::FirstOrder => true,
    };
    if first {
        return Ok(super::first_order::propagate(
            case,
            nominal,
            inputs,
            super::numerics::grid_study(case),
            done,
        ));
    }
    sampled(case, nominal, inputs, settings, done)
}
