//! Running checks: evaluate each (its kind's module in [`crate::checks`] computes and
//! compares), then decide the outcome against the case's known discrepancies.
//!
//! # Margins and outcomes
//! Each quantity is judged by [`crate::checks::tolerance::judge`] (margins are positive when it
//! passes; NaN never passes). A check passes when every expectation passes (and, for `bcar`,
//! the verdict matches). An expected failure stays one only while the model gives what was
//! recorded for it ([`crate::suite::discrepancy`]); a check that cannot be evaluated, or computes a
//! value that is not finite, is an `error`, whatever the case expects.

use crate::checks::{Check, CheckClass, CheckKind};
pub use crate::checks::{Finding, Locus, PlotData, QuantityResult, Trace};
use crate::suite::case::Case;
use cierva_model::analysis::bcar::Verdict;
use serde::{Deserialize, Serialize};

/// The outcome of a check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    Pass,
    Fail,
    /// Failed, as the case says it would, and the model gives what was recorded for it (see
    /// [`crate::suite::discrepancy`]).
    ExpectedFailure,
    /// Failed as the case says it would, but the model has left its recorded band (better or
    /// worse), or nothing was recorded: the discrepancy is to be reviewed
    /// (`cierva review`).
    DiscrepancyMoved,
    /// Passed although the case says it fails: the case (or the model) must be looked at.
    UnexpectedPass,
    /// The check could not be evaluated (an error, or a value that is not a number). Always
    /// fails, whatever the case expects.
    Error,
}

impl Outcome {
    /// Whether this outcome is acceptable (the run stays green).
    pub fn ok(self) -> bool {
        matches!(self, Self::Pass | Self::ExpectedFailure)
    }

    /// Short label for tables.
    pub fn label(self) -> &'static str {
        match self {
            Self::Pass => "pass",
            Self::Fail => "FAIL",
            Self::ExpectedFailure => "xfail",
            Self::DiscrepancyMoved => "MOVED",
            Self::UnexpectedPass => "XPASS",
            Self::Error => "ERROR",
        }
    }

    /// Every outcome, in the order tables list them.
    pub const ALL: [Outcome; 6] = [
        Self::Pass,
        Self::Fail,
        Self::ExpectedFailure,
        Self::DiscrepancyMoved,
        Self::UnexpectedPass,
        Self::Error,
    ];
}

/// The result of one check (read back from a plan's results, [`crate::plan`], without its
/// plot).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckResult {
    pub case: String,
    pub check: String,
    pub kind: CheckKind,
    /// What the check is evidence of (validation, cross-code, verification, regression).
    pub class: CheckClass,
    pub outcome: Outcome,
    /// Whether every expectation held (and the verdict matched), whatever the case expects.
    pub passed: bool,
    pub quantities: Vec<QuantityResult>,
    /// For `bcar`: (expected, computed) verdicts.
    pub verdict: Option<(Verdict, Verdict)>,
    /// Why the check could not be computed, if it could not.
    pub error: Option<String>,
    /// What the model found instead of the quantities (no equilibrium), or why the data cannot
    /// decide the check (inconclusive).
    pub finding: Option<Finding>,
    pub expected_failure: Option<String>,
    /// Numbers that describe the check's result beyond its expectations (a BCAR margin, what
    /// a search without a solution ended on), so that a recorded known discrepancy notices
    /// when they move.
    pub fingerprint: Vec<(String, f64)>,
    /// For an expected failure: how the model has left what was recorded for it.
    pub departures: Vec<String>,
    /// How the check computed its quantities, where it says (which linearisation gave a
    /// frequency response).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// Where it runs with corrections outside the domain they were fitted on: which file, its
    /// domain, and what of the check lies outside.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub extrapolation: Option<String>,
    /// The corrections files applied whose fit was fitted to this check: its agreement is what
    /// the fit made, no evidence for them (reported apart, never counted as validation).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub calibrated_on: Option<String>,
    /// What the report plots beyond the quantities (not in the JSON results).
    #[serde(skip)]
    pub plot: Option<PlotData>,
}

impl CheckResult {
    /// A one-paragraph explanation, for test failures and logs.
    pub fn explain(&self) -> String {
        let mut s = format!(
            "{}::{} [{}, {}]",
            self.case,
            self.check,
            self.outcome.label(),
            self.class.name()
        );
        if let Some(e) = &self.error {
            s += &format!("\n  error: {e}");
        }
        match &self.finding {
            Some(Finding::NoEquilibrium { reason, .. }) => {
                s += &format!("\n  the model has no equilibrium here: {reason}")
            }
            Some(f @ (Finding::Inconclusive { .. } | Finding::OutsideValidity { .. })) => {
                s += &format!("\n  {}", f.describe())
            }
            None => {}
        }
        if let Some(x) = &self.extrapolation {
            s += &format!("\n  {x}");
        }
        if let Some(by) = &self.calibrated_on {
            s += &format!("\n  calibrated on: a target of the fit of {by}, so no evidence for it");
        }
        if let Some(n) = &self.note {
            s += &format!("\n  {n}");
        }
        if let Some((want, got)) = self.verdict {
            s += &format!("\n  verdict: expected {want:?}, computed {got:?}");
        }
        for q in &self.quantities {
            s += &format!(
                "\n  {}: value {:.6e}, expected {} {} ({}: {}), margin {:.3e} -> {}",
                q.quantity,
                q.value,
                q.expected.map_or("-".into(), |v| format!("{v:.6e}")),
                q.allowed,
                q.tolerance,
                q.reason,
                q.margin,
                if q.pass { "ok" } else { "out of tolerance" }
            );
        }
        match (self.outcome, &self.expected_failure) {
            (Outcome::UnexpectedPass, Some(r)) => {
                s += &format!(
                    "\n  this check is marked as an expected failure ({r}) but it passes: \
                     review the case and remove `expected_failure` if the discrepancy is gone, \
                     then run `cierva review --accept --reason TEXT`"
                )
            }
            (Outcome::DiscrepancyMoved, Some(r)) => {
                s += &format!("\n  known discrepancy ({r}) moved:");
                for d in &self.departures {
                    s += &format!("\n    {d}");
                }
                s += "\n  if the change is intended, record the model's new values with \
                      `cierva review --accept --reason TEXT` (the reason is logged)";
            }
            (Outcome::ExpectedFailure, Some(r)) => s += &format!("\n  expected failure: {r}"),
            (Outcome::Error, Some(_)) => {
                s += "\n  an error fails even a check that is expected to fail"
            }
            _ => {}
        }
        s
    }
}

/// Every way the model has left its record, in words ("rpm 97.52: recorded 96.91 in [96.90,
/// 96.92]"); empty when it has not.
pub fn departures(
    result: &CheckResult,
    recorded: &crate::suite::discrepancy::Recorded,
) -> Vec<String> {
    let mut out = Vec::new();
    let fmt = |b: &crate::suite::discrepancy::RecordedBand| {
        format!(
            "recorded {:.6e} in [{:.6e}, {:.6e}]",
            b.value, b.lower, b.upper
        )
    };
    for q in &result.quantities {
        match recorded.quantities.get(&q.quantity) {
            Some(b) if b.holds(q.value) => {}
            Some(b) => out.push(format!("{} {:.6e}: {}", q.quantity, q.value, fmt(b))),
            None => out.push(format!("{} {:.6e}: not recorded", q.quantity, q.value)),
        }
    }
    for q in recorded.quantities.keys() {
        if !result.quantities.iter().any(|r| &r.quantity == q) {
            out.push(format!("{q}: recorded, but not computed now"));
        }
    }
    let got = result.verdict.map(|(_, got)| got);
    if got != recorded.verdict {
        out.push(format!("verdict {got:?}: recorded {:?}", recorded.verdict));
    }
    let no_equilibrium = matches!(result.finding, Some(Finding::NoEquilibrium { .. }));
    match (no_equilibrium, recorded.no_equilibrium) {
        (true, false) => out.push("no equilibrium now: recorded with one".into()),
        (false, true) => out.push("an equilibrium now: recorded without one".into()),
        _ => {}
    }
    for (n, v) in &result.fingerprint {
        match recorded.fingerprint.get(n) {
            Some(b) if b.holds(*v) => {}
            Some(b) => out.push(format!("{n} {v:.6e}: {}", fmt(b))),
            None => out.push(format!("{n} {v:.6e}: not recorded")),
        }
    }
    out
}

/// Runs every check of a case.
pub fn run_case(case: &Case) -> Vec<CheckResult> {
    case.checks.iter().map(|c| run_check(case, c)).collect()
}

/// The checks `select` picks from every case, on every core. The items shared out are the
/// checks, not the cases, so that one case of many slow checks (TR 515's 33 angle searches)
/// does not leave the other cores idle. For each case: its results in check order, and the
/// seconds its checks took together (summed over threads, not wall time). `done` is called as
/// each check ends (a progress bar). The results do not depend on the schedule.
pub fn run_cases(
    cases: &[&Case],
    select: impl Fn(&Case, &Check) -> bool + Sync,
    done: impl Fn(&Case, &Check) + Sync,
) -> Vec<(Vec<CheckResult>, f64)> {
    let mut items = Vec::new();
    for (i, case) in cases.iter().enumerate() {
        for (j, check) in case.checks.iter().enumerate() {
            if select(case, check) {
                items.push((i, j));
            }
        }
    }
    let ran = crate::run::parallel::parallel_map(&items, |&(i, j)| {
        let (case, check) = (cases[i], &cases[i].checks[j]);
        let started = std::time::Instant::now();
        let result = run_check(case, check);
        done(case, check);
        (result, started.elapsed().as_secs_f64())
    });
    let mut out: Vec<(Vec<CheckResult>, f64)> = cases.iter().map(|_| (Vec::new(), 0.0)).collect();
    for (&(i, _), (result, seconds)) in items.iter().zip(ran) {
        out[i].0.push(result);
        out[i].1 += seconds;
    }
    out
}

/// Runs one check.
pub fn run_check(case: &Case, check: &Check) -> CheckResult {
    let mut result = CheckResult {
        case: case.id.clone(),
        check: check.id.clone(),
        kind: check.kind(),
        class: check.class,
        outcome: Outcome::Error,
        passed: false,
        quantities: vec![],
        verdict: None,
        error: None,
        finding: None,
        expected_failure: check.expected_failure.clone(),
        fingerprint: vec![],
        departures: vec![],
        note: None,
        extrapolation: {
            let e: Vec<&String> = case
                .calibrations
                .iter()
                .filter_map(|c| c.extrapolated.get(&check.id))
                .collect();
            (!e.is_empty()).then(|| e.iter().map(|s| s.as_str()).collect::<Vec<_>>().join("; "))
        },
        calibrated_on: {
            let by: Vec<&str> = case
                .calibrations
                .iter()
                .filter(|c| c.calibrated_on.contains(&check.id))
                .map(|c| c.id.as_str())
                .collect();
            (!by.is_empty()).then(|| by.join(", "))
        },
        plot: None,
    };
    match check.evaluate(case.subject_of(&check.id), &case.checks) {
        Ok(e) => {
            let verdict_ok = e.verdict.is_none_or(|(want, got)| want == got);
            result.passed =
                e.finding.is_none() && verdict_ok && e.quantities.iter().all(|q| q.pass);
            let finite = e.quantities.iter().all(|q| q.value.is_finite());
            result.quantities = e.quantities;
            result.verdict = e.verdict;
            result.plot = e.plot;
            result.finding = e.finding;
            result.fingerprint = e.fingerprint;
            result.note = e.note;
            if !finite {
                result.error = Some("a computed value is not a finite number".into());
                return result;
            }
        }
        Err(e) => {
            result.error = Some(e);
            return result;
        }
    }
    result.outcome = match (result.passed, check.expected_failure.is_some()) {
        (true, false) => Outcome::Pass,
        (false, false) => Outcome::Fail,
        (true, true) => Outcome::UnexpectedPass,
        (false, true) => {
            let recorded = case.recorded.as_ref().and_then(|r| r.checks.get(&check.id));
            result.departures = match recorded {
                Some(r) => departures(&result, r),
                None => vec![match &case.records_dir {
                    Some(dir) => format!(
                        "nothing is recorded for this check in {}",
                        crate::suite::discrepancy::path_for(dir, &case.id).display()
                    ),
                    None => format!(
                        "nothing is recorded for this check: the case is in no suite (no {} above it)",
                        crate::suite::MARKER
                    ),
                }],
            };
            if result.departures.is_empty() {
                Outcome::ExpectedFailure
            } else {
                Outcome::DiscrepancyMoved
            }
        }
    };
    result
}
