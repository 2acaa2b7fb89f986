//! Reviewing a run against what is committed: the known discrepancies' records
//! ([`crate::discrepancy`]) and the scoreboard ([`crate::scoreboard`]). What `cierva review`
//! shows and, with `--accept`, writes; what `cierva validate` and the scoreboard trials judge.

use crate::discrepancy::{Band, CaseRecord, Recorded};
use crate::eval::{CheckResult, Finding, departures};
use crate::scoreboard::{Board, Change, Metric, Score, ScoreSpec, change};
use serde::Serialize;

/// What the model gives now for a failing check, as a record.
pub fn record_of(result: &CheckResult) -> Recorded {
    let quantities = result
        .quantities
        .iter()
        .map(|q| {
            (
                q.quantity.clone(),
                Band::around(q.value, 0.5 * (q.upper - q.lower)),
            )
        })
        .collect();
    Recorded {
        quantities,
        verdict: result.verdict.map(|(_, got)| got),
        no_equilibrium: matches!(result.finding, Some(Finding::NoEquilibrium { .. })),
        fingerprint: result
            .fingerprint
            .iter()
            .map(|(n, v)| (n.clone(), Band::around(*v, 0.0)))
            .collect(),
    }
}

/// What reviewing a case's known discrepancies found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseReview {
    pub case: String,
    /// The records as the model gives them now.
    #[serde(skip)]
    pub now: CaseRecord,
    /// Every difference from the committed records, in words (empty: nothing moved).
    pub changes: Vec<String>,
    /// Expected failures that could not be evaluated: they cannot be recorded.
    pub errors: Vec<String>,
}

/// Compares what the model gives for a case's expected failures (among `results`, the case's
/// results) with its records.
pub fn review(case: &crate::case::Case, results: &[CheckResult]) -> CaseReview {
    let results: Vec<&CheckResult> = results
        .iter()
        .filter(|r| r.expected_failure.is_some())
        .collect();
    let now = CaseRecord {
        case: case.id.clone(),
        checks: results
            .iter()
            .filter(|r| !r.passed && r.error.is_none())
            .map(|r| (r.check.clone(), record_of(r)))
            .collect(),
    };
    let empty = CaseRecord::default();
    let old = case.recorded.as_ref().unwrap_or(&empty);
    let mut changes = Vec::new();
    let mut errors = Vec::new();
    for r in &results {
        if let Some(e) = &r.error {
            errors.push(format!("{}: {e}", r.check));
        } else if r.passed {
            changes.push(format!(
                "{}: passes now; remove its `expected_failure` from the case",
                r.check
            ));
        } else {
            match old.checks.get(&r.check) {
                None => changes.push(format!("{}: not recorded yet", r.check)),
                Some(rec) => {
                    for d in departures(r, rec) {
                        changes.push(format!("{}: {d}", r.check));
                    }
                }
            }
        }
    }
    for id in old.checks.keys() {
        if !now.checks.contains_key(id) && !results.iter().any(|r| &r.check == id) {
            changes.push(format!(
                "{id}: recorded, but no longer an expected failure of the case"
            ));
        }
    }
    CaseReview {
        case: case.id.clone(),
        now,
        changes,
        errors,
    }
}

/// A scored value: the value, its reference, the tolerance's half-width, and whether it passed.
type Row = (f64, f64, f64, bool);

/// Computes a case's score from its results. `tip_speed_ratio` gives a check's tip-speed
/// ratio where its condition states one (for `peak_tip_speed_ratio_offset`).
pub fn compute(
    case: &str,
    spec: &ScoreSpec,
    results: &[CheckResult],
    tip_speed_ratio: &dyn Fn(&str) -> Option<f64>,
) -> Score {
    let q = spec.quantity.as_deref();
    let chosen: Vec<CheckResult>;
    let results = match &spec.checks {
        None => results,
        Some(ids) => {
            chosen = results
                .iter()
                .filter(|r| ids.contains(&r.check))
                .cloned()
                .collect();
            &chosen[..]
        }
    };
    let named: Vec<(&str, Row)> = results
        .iter()
        .flat_map(|r| r.quantities.iter().map(move |x| (r.check.as_str(), x)))
        .filter(|(_, x)| q == Some(x.quantity.as_str()))
        .map(|(check, x)| {
            let reference = x.expected.unwrap_or(0.5 * (x.lower + x.upper));
            (
                check,
                (x.value, reference, 0.5 * (x.upper - x.lower), x.pass),
            )
        })
        .filter(|(_, (v, r, ..))| v.is_finite() && r.is_finite())
        .collect();
    let rows: Vec<Row> = named.iter().map(|(_, r)| *r).collect();
    let rms = |f: &dyn Fn(&Row) -> f64| {
        let s: Vec<f64> = rows.iter().map(f).filter(|e| e.is_finite()).collect();
        if s.is_empty() {
            f64::NAN
        } else {
            (s.iter().map(|e| e * e).sum::<f64>() / s.len() as f64).sqrt()
        }
    };
    // The check with the largest value, and the one with the largest reference.
    let peak = |of: fn(&Row) -> f64| {
        named
            .iter()
            .max_by(|a, b| of(&a.1).total_cmp(&of(&b.1)))
            .map(|(check, row)| (*check, of(row)))
    };
    let peaks = peak(|r| r.0).zip(peak(|r| r.1));
    let (value, count) = match spec.metric {
        Metric::RmsRelativeError => (rms(&|(v, r, ..)| (v - r) / r.abs()), rows.len()),
        Metric::RmsError => (rms(&|(v, r, ..)| v - r), rows.len()),
        Metric::RmsErrorInHalfWidths => (rms(&|(v, r, h, _)| (v - r) / h), rows.len()),
        Metric::MaxErrorInHalfWidths => (
            rows.iter()
                .map(|(v, r, h, _)| ((v - r) / h).abs())
                .fold(f64::NAN, f64::max),
            rows.len(),
        ),
        Metric::PeakRelativeError => (
            peaks.map_or(f64::NAN, |((_, v), (_, r))| ((v - r) / r).abs()),
            rows.len(),
        ),
        Metric::PeakTipSpeedRatioOffset => (
            peaks
                .and_then(|((model, _), (reference, _))| {
                    Some((tip_speed_ratio(model)? - tip_speed_ratio(reference)?).abs())
                })
                .unwrap_or(f64::NAN),
            rows.len(),
        ),
        Metric::Inside => match q {
            Some(_) => (rows.iter().filter(|x| x.3).count() as f64, rows.len()),
            None => (
                results.iter().filter(|r| r.passed).count() as f64,
                results.len(),
            ),
        },
        Metric::Unsolved => (
            results
                .iter()
                .filter(|r| r.finding.is_some() || r.error.is_some())
                .count() as f64,
            results.len(),
        ),
    };
    Score {
        case: case.to_string(),
        id: spec.id.clone(),
        metric: spec.metric,
        quantity: spec.quantity.clone(),
        value,
        count,
        noise_floor: spec.noise_floor,
        reason: spec.reason.clone(),
    }
}

/// Every score a case declares, computed from its results.
pub fn scores_of(case: &crate::case::Case, results: &[CheckResult]) -> Vec<Score> {
    let tip_speed_ratio = |id: &str| {
        case.checks
            .iter()
            .find(|c| c.id == id)?
            .tunnel_tip_speed_ratio()
    };
    case.scores
        .iter()
        .map(|s| compute(&case.id, s, results, &tip_speed_ratio))
        .collect()
}

/// A score with its committed value and how it compares.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Judged {
    pub score: Score,
    pub committed: Option<f64>,
    pub change: Change,
}

/// Judges scores against the board.
pub fn judge(board: &Board, scores: Vec<Score>) -> Vec<Judged> {
    scores
        .into_iter()
        .map(|score| {
            let c = board.scores.get(&score.case).and_then(|m| m.get(&score.id));
            Judged {
                change: change(&score, c),
                committed: c.map(|c| c.value),
                score,
            }
        })
        .collect()
}

impl Judged {
    /// "naca-tr515-table-iii rpm-rms: 0.1234 (committed 0.1200, WORSE)".
    pub fn describe(&self) -> String {
        format!(
            "{} {}: {:.6} ({}, {})",
            self.score.case,
            self.score.id,
            self.score.value,
            self.committed
                .map_or("nothing committed".to_string(), |c| format!(
                    "committed {c:.6}"
                )),
            self.change.label()
        )
    }
}
