//! The uncertainty study of a case: its inputs, and the propagation that suits it, sampled
//! ([`super::propagate`]) or to first order ([`super::first_order`]), its evaluations run on
//! this machine's cores ([`super::jobs`]). The entry points live here, above both, so that
//! neither method's module uses the other's.

use super::jobs::CaseJobs;
use super::propagate::{CaseUncertainty, PropagationSettings};
use crate::suite::outcome::CheckResult;

/// Runs the propagation of one case. `done` is called after each evaluation (a progress bar).
pub fn propagate(
    case: &crate::suite::case::Case,
    settings: PropagationSettings,
    done: impl Fn() + Sync,
) -> Result<CaseUncertainty, String> {
    let jobs = CaseJobs::of(case, settings)?;
    let nominal = crate::suite::outcome::run_case(&jobs.case);
    Ok(jobs.finish(jobs.run_locally(nominal, done)))
}

/// [`propagate`] about results already computed with the nominal inputs (`validate`'s, of
/// every check of the case). A case without uncertain inputs is not re-run: its quantities get
/// no verdict, and say why.
pub fn propagate_from(
    case: &crate::suite::case::Case,
    nominal: &[CheckResult],
    settings: PropagationSettings,
    done: impl Fn() + Sync,
) -> Result<CaseUncertainty, String> {
    let jobs = CaseJobs::of(case, settings)?;
    let nominal = jobs.nominal_of(nominal);
    Ok(jobs.finish(jobs.run_locally(nominal, done)))
}
