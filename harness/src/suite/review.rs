//! Reviewing a run against what is committed: the known discrepancies' records
//! ([`crate::suite::discrepancy`]) and the scoreboard ([`crate::suite::scoreboard`]). What `cierva review`
//! shows and, with `--accept`, writes; what `cierva validate` and the scoreboard trials judge.
//!
//! # The acceptance log
//! Every `cierva review --accept --reason TEXT` appends one entry to `reports/acceptances.yaml`
//! ([`Acceptance`]): when (UTC), on which commit, why, what changed (each score and record, old
//! and new, which way, and each one's own reason), the fingerprint of what it left (the FNV-1a
//! 64 hash of the bytes of `reports/scoreboard.yaml` and of every `reports/discrepancies/*.yaml`),
//! and its link in a hash chain over the entries' content ([`link`]). The log is only ever
//! appended to ([`append_log`]); [`acceptance_state`] tells whether the committed files are
//! still what its last entry accepted and whether the chain holds, so that a score or a record
//! never changes without a logged reason, and an entry edited or appended by hand is found.

use crate::inputs::yaml::{self, InputError};
use crate::suite::discrepancy::{CaseRecord, Recorded, RecordedBand};
use crate::suite::outcome::{CheckResult, Finding, departures};
use crate::suite::scoreboard::{Board, Change, Metric, Score, ScoreSpec, change};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// What the model gives now for a failing check, as a record.
pub fn record_of(result: &CheckResult) -> Recorded {
    let quantities = result
        .quantities
        .iter()
        .map(|q| {
            (
                q.quantity.clone(),
                RecordedBand::around(q.value, 0.5 * (q.upper - q.lower)),
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
            .map(|(n, v)| (n.clone(), RecordedBand::around(*v, 0.0)))
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
    /// The records as committed.
    #[serde(skip)]
    pub old: CaseRecord,
    /// The recorded checks whose model left their record.
    #[serde(skip)]
    pub moved: BTreeSet<String>,
    /// Every difference from the committed records, in words (empty: nothing moved).
    pub changes: Vec<String>,
    /// Expected failures that could not be evaluated: they cannot be recorded.
    pub errors: Vec<String>,
}

/// Compares what the model gives for a case's expected failures (among `results`, the case's
/// results) with its records.
pub fn review(case: &crate::suite::case::Case, results: &[CheckResult]) -> CaseReview {
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
    let mut moved = BTreeSet::new();
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
                        moved.insert(r.check.clone());
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
        old: old.clone(),
        moved,
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
pub fn scores_of(case: &crate::suite::case::Case, results: &[CheckResult]) -> Vec<Score> {
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

/// The committed scores no case declares any more, as `case score-id` with why: for each of
/// `cases`, a committed score it does not declare; with `whole_suite` (the cases are all the
/// suite's), also every case on the board that is not among them. A score leaves the board only
/// through `cierva review --accept`, which drops it with its reason; removing it from its case
/// alone fails the run.
pub fn undeclared(
    board: &Board,
    cases: &[&crate::suite::case::Case],
    whole_suite: bool,
) -> Vec<String> {
    let mut out = Vec::new();
    for (case, scores) in &board.scores {
        match cases.iter().find(|c| &c.id == case) {
            Some(c) => out.extend(
                scores
                    .keys()
                    .filter(|id| !c.scores.iter().any(|s| &s.id == *id))
                    .map(|id| {
                        format!("{case} {id}: committed, but its case no longer declares it")
                    }),
            ),
            None if whole_suite => out.push(format!(
                "{case}: {} committed, but the suite has no case `{case}`",
                crate::units::count(scores.len(), "score", "scores")
            )),
            None => {}
        }
    }
    out
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

/// The acceptance log's file name, in the reports folder beside what it accepts.
pub use crate::suite::ACCEPTANCES_FILE as LOG_FILE;

/// The acceptance log as written: every acceptance, oldest first.
#[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Log {
    #[serde(default)]
    pub acceptances: Vec<Acceptance>,
}

/// One `cierva review --accept`: when, where, why, what changed and what it left.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Acceptance {
    /// UTC, ISO 8601, from the system clock.
    pub date: String,
    /// The short commit the run was made on, with `+dirty` when the tree had changes
    /// (`unknown` without git).
    pub commit: String,
    pub reason: String,
    #[serde(default)]
    pub changes: Vec<Accepted>,
    /// Each accepted file (relative to `reports/`) and the hash of its bytes after writing.
    pub fingerprint: BTreeMap<String, String>,
    /// The link of the hash chain ([`link`]): the FNV-1a 64 hash of the previous entry's link
    /// and this entry's content. Entries logged before the chain began have none; every entry
    /// after the first one with a link must have one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chain: Option<String>,
}

/// One score or record an acceptance changed.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Accepted {
    pub case: String,
    /// A score's id, or the id of a check with a discrepancy record.
    pub item: String,
    /// A score's value, a record in short; none for a new one.
    pub old: Option<Value>,
    /// None for a dropped one.
    pub new: Option<Value>,
    pub direction: Direction,
    /// Why this item may change (`--because CASE/ITEM=TEXT`): required of every change of a
    /// chained entry; entries logged before per-item reasons have none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// A logged value: a score's number, or a record in short.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub enum Value {
    Number(f64),
    Text(String),
}

/// Which way an accepted item went.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    Better,
    Worse,
    New,
    Dropped,
    /// A record whose model left it (records have no better or worse).
    Moved,
}

impl Direction {
    /// The direction as written in the log.
    pub fn name(self) -> &'static str {
        match self {
            Self::Better => "better",
            Self::Worse => "worse",
            Self::New => "new",
            Self::Dropped => "dropped",
            Self::Moved => "moved",
        }
    }
}

impl Value {
    /// The value as a person reads it.
    pub fn show(&self) -> String {
        match self {
            Self::Number(x) => crate::units::sig(*x, 6),
            Self::Text(t) => t.clone(),
        }
    }
}

/// What accepting changes: the scores that moved beyond their noise floor (`judged` against
/// `board`), the committed scores a reviewed case no longer declares (`dropped`, case and id),
/// and the records of the reviews that moved.
pub fn changes(
    board: &Board,
    judged: &[Judged],
    dropped: &[(String, String)],
    reviews: &[CaseReview],
) -> Vec<Accepted> {
    let scores = judged.iter().filter_map(|j| {
        let direction = match j.change {
            Change::Same => return None,
            Change::Better => Direction::Better,
            Change::Worse => Direction::Worse,
            Change::New => Direction::New,
        };
        Some(Accepted {
            case: j.score.case.clone(),
            item: j.score.id.clone(),
            old: j.committed.map(Value::Number),
            new: Some(Value::Number(j.score.value)),
            direction,
            reason: None,
        })
    });
    let gone = dropped.iter().map(|(case, id)| Accepted {
        case: case.clone(),
        item: id.clone(),
        old: board
            .scores
            .get(case)
            .and_then(|s| s.get(id))
            .map(|c| Value::Number(c.value)),
        new: None,
        direction: Direction::Dropped,
        reason: None,
    });
    scores
        .chain(gone)
        .chain(reviews.iter().flat_map(record_changes))
        .collect()
}

/// The records a case's review changes when accepted (none when nothing moved): new, dropped,
/// and moved ones.
pub fn record_changes(r: &CaseReview) -> Vec<Accepted> {
    if r.changes.is_empty() {
        return vec![];
    }
    let ids: BTreeSet<&String> = r.old.checks.keys().chain(r.now.checks.keys()).collect();
    ids.into_iter()
        .filter_map(|id| {
            let (old, new) = (r.old.checks.get(id), r.now.checks.get(id));
            let direction = match (old, new) {
                (None, Some(_)) => Direction::New,
                (Some(_), None) => Direction::Dropped,
                (Some(_), Some(_)) if r.moved.contains(id) => Direction::Moved,
                _ => return None,
            };
            Some(Accepted {
                case: r.case.clone(),
                item: id.clone(),
                old: old.map(summary),
                new: new.map(summary),
                direction,
                reason: None,
            })
        })
        .collect()
}

/// A record in short: its quantities' values, its verdict, no equilibrium.
fn summary(r: &Recorded) -> Value {
    let mut parts: Vec<String> = r
        .quantities
        .iter()
        .map(|(q, b)| format!("{q} {}", crate::units::sig(b.value, 6)))
        .collect();
    if let Some(v) = r.verdict {
        parts.push(match v {
            cierva_model::analysis::bcar::Verdict::Complies => "complies".into(),
            cierva_model::analysis::bcar::Verdict::DoesNotComply => "does not comply".into(),
        });
    }
    if r.no_equilibrium {
        parts.push("no equilibrium".into());
    }
    if !r.fingerprint.is_empty() {
        parts.push(format!("{} fingerprint numbers", r.fingerprint.len()));
    }
    Value::Text(parts.join("; "))
}

/// FNV-1a, 64 bits: the hash of an accepted file's bytes.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The accepted files under `reports` (the scoreboard and every discrepancy record, relative
/// to `reports`) and the hash of each one's bytes.
pub fn fingerprint(reports: &Path) -> Result<BTreeMap<String, String>, String> {
    let mut files = vec!["scoreboard.yaml".to_string()];
    let records = reports.join("discrepancies");
    match std::fs::read_dir(&records) {
        Ok(entries) => {
            for e in entries {
                let name = e
                    .map_err(|e| format!("cannot list {}: {e}", records.display()))?
                    .file_name()
                    .to_string_lossy()
                    .into_owned();
                if name.ends_with(".yaml") {
                    files.push(format!("discrepancies/{name}"));
                }
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(format!("cannot list {}: {e}", records.display())),
    }
    let mut out = BTreeMap::new();
    for f in files {
        let path = reports.join(&f);
        match std::fs::read(&path) {
            Ok(bytes) => {
                out.insert(f, format!("fnv1a64:{:016x}", fnv1a64(&bytes)));
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound && f == "scoreboard.yaml" => {}
            Err(e) => return Err(format!("cannot read {}: {e}", path.display())),
        }
    }
    Ok(out)
}

/// An entry's content as its chain link hashes it: every field but the link, in order, one per
/// line, each number by its bits (a NaN as `nan`), so that the link does not hang on how YAML
/// quotes a string or prints a number.
fn canonical(a: &Acceptance) -> String {
    use std::fmt::Write as _;
    let value = |v: &Option<Value>| match v {
        None => "none".to_string(),
        Some(Value::Number(x)) if x.is_nan() => "nan".to_string(),
        Some(Value::Number(x)) => format!("number {:016x}", x.to_bits()),
        Some(Value::Text(t)) => format!("text {t:?}"),
    };
    let mut o = format!(
        "date {:?}\ncommit {:?}\nreason {:?}\n",
        a.date, a.commit, a.reason
    );
    for c in &a.changes {
        let _ = writeln!(
            o,
            "change {:?} {:?} {} {} {} {:?}",
            c.case,
            c.item,
            value(&c.old),
            value(&c.new),
            c.direction.name(),
            c.reason
        );
    }
    for (f, h) in &a.fingerprint {
        let _ = writeln!(o, "file {f:?} {h:?}");
    }
    o
}

/// The chain link of `entry` after an entry whose link is `previous` (`""` before the first
/// entry): `fnv1a64:` and the FNV-1a 64 hash of `previous`, a newline and the entry's content
/// (`canonical`). Editing, removing or inserting an entry changes every later link; an entry
/// appended by hand has none. (FNV is not a cryptographic hash: the chain shows an edit made by
/// mistake or by hand, not one made by someone who recomputes it on purpose.)
pub fn link(previous: &str, entry: &Acceptance) -> String {
    let text = format!("{previous}\n{}", canonical(entry));
    format!("fnv1a64:{:016x}", fnv1a64(text.as_bytes()))
}

/// The links the log's entries should carry, in order (each computed, whether or not the
/// entry carries one).
fn links(log: &Log) -> Vec<String> {
    let mut previous = String::new();
    log.acceptances
        .iter()
        .map(|a| {
            previous = link(&previous, a);
            previous.clone()
        })
        .collect()
}

/// Whether the log's hash chain holds: it is not broken (`chain_breaks`) and its last entry
/// has a link.
pub fn chain_state(log: &Log) -> Result<(), String> {
    chain_breaks(log)?;
    match log.acceptances.last() {
        Some(last) if last.chain.is_none() => Err(format!(
            "the last acceptance ({}, {}) has no chain link: the log's entries are not \
             chained; `cierva review --accept --reason TEXT` logs a chained entry",
            last.date, last.commit
        )),
        _ => Ok(()),
    }
}

/// Whether the log's hash chain is broken: a link an entry carries that is not the one its
/// content and the entries before it give, or an entry without a link after one with a link.
/// An error names the first entry that breaks it (by index and date) and why.
fn chain_breaks(log: &Log) -> Result<(), String> {
    let mut chained = false;
    for (i, (a, want)) in log.acceptances.iter().zip(links(log)).enumerate() {
        match &a.chain {
            Some(got) if *got != want => {
                return Err(format!(
                    "acceptances[{i}] ({}, {}): its chain link is {got}, but the entries up to it \
                     give {want}: it, or an entry before it, was edited, inserted or removed by hand",
                    a.date, a.commit
                ));
            }
            Some(_) => chained = true,
            None if chained => {
                return Err(format!(
                    "acceptances[{i}] ({}, {}): no chain link after chained entries: it was not \
                     written by `cierva review --accept`",
                    a.date, a.commit
                ));
            }
            None => {}
        }
    }
    Ok(())
}

/// A reason given for some changed items: `CASE/ITEM=TEXT` (`--because`), where `ITEM` may
/// hold `*` (any run of characters) to name several items of one case; the case is named in full.
#[derive(Debug, Clone, PartialEq)]
pub struct ItemReason {
    pub case: String,
    pub item: String,
    pub text: String,
}

impl std::str::FromStr for ItemReason {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let form = "give it as CASE/ITEM=TEXT, e.g. `naca-tr515-table-iii/low-mu-rpm-rms=the \
                    hub drag's new estimate`";
        let (name, text) = s
            .split_once('=')
            .ok_or_else(|| format!("`{s}`: no `=`; {form}"))?;
        let (case, item) = name
            .trim()
            .split_once('/')
            .ok_or_else(|| format!("`{name}`: no `/` between the case and the item; {form}"))?;
        let (case, item, text) = (case.trim(), item.trim(), text.trim());
        if case.is_empty() || item.is_empty() || text.is_empty() {
            return Err(format!(
                "`{s}`: the case, the item and the reason each need a text; {form}"
            ));
        }
        if case.contains('*') {
            return Err(format!(
                "`{s}`: the case is named in full (a `*` may stand in the item only): one reason \
                 does not cover several data sets"
            ));
        }
        Ok(Self {
            case: case.into(),
            item: item.into(),
            text: text.into(),
        })
    }
}

/// Whether `pattern` (with `*` for any run of characters) matches all of `s`.
fn glob(pattern: &str, s: &str) -> bool {
    match pattern.split_once('*') {
        None => pattern == s,
        Some((head, rest)) => {
            let Some(tail) = s.strip_prefix(head) else {
                return false;
            };
            (0..=tail.len())
                .filter(|&i| tail.is_char_boundary(i))
                .any(|i| glob(rest, &tail[i..]))
        }
    }
}

/// The `--because` argument to fill for a change, with what changed:
/// `  --because 'case/item=TEXT'   # worse: 0.05 -> 0.06`.
pub fn because_line(c: &Accepted) -> String {
    format!(
        "  --because '{}/{}=TEXT'   # {}{}",
        c.case,
        c.item,
        c.direction.name(),
        match (&c.old, &c.new) {
            (Some(o), Some(n)) => format!(": {} -> {}", o.show(), n.show()),
            _ => String::new(),
        }
    )
}

/// Gives each change its reason from `given`: an item named exactly takes that reason, else
/// the first pattern of its case that matches it. Refused, with every item that has no reason
/// (and a `--because` line to fill for each) or every reason that names no changed item.
pub fn assign_reasons(changes: &mut [Accepted], given: &[ItemReason]) -> Result<(), String> {
    let matches = |r: &ItemReason, c: &Accepted| r.case == c.case && glob(&r.item, &c.item);
    let mut missing = Vec::new();
    for c in changes.iter_mut() {
        let exact = given.iter().find(|r| r.case == c.case && r.item == c.item);
        match exact.or_else(|| given.iter().find(|r| matches(r, c))) {
            Some(r) => c.reason = Some(r.text.clone()),
            None => missing.push(because_line(c)),
        }
    }
    let unused: Vec<String> = given
        .iter()
        .filter(|r| !changes.iter().any(|c| matches(r, c)))
        .map(|r| format!("`{}/{}`", r.case, r.item))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "every changed score and record needs its own reason (`--because CASE/ITEM=TEXT`, \
             `*` allowed in ITEM); {} without one:\n{}\nNothing was written",
            missing.len(),
            missing.join("\n")
        ));
    }
    if !unused.is_empty() {
        return Err(format!(
            "reasons for items that did not change: {}; nothing was written",
            unused.join(", ")
        ));
    }
    Ok(())
}

/// Whether the scoreboard and the discrepancy records under `reports` are what the acceptance
/// log there (`reports/acceptances.yaml`) last accepted: an error names every file that
/// differs, is missing or was never accepted.
pub fn acceptance_state(reports: &Path) -> Result<(), String> {
    let path = reports.join(LOG_FILE);
    let log = load_log(&path).map_err(|e| e.to_string())?;
    chain_state(&log).map_err(|e| format!("{}: {e}", path.display()))?;
    let Some(last) = log.acceptances.last() else {
        return Err(format!(
            "{}: no acceptance logged; accept with `cierva review --accept --reason TEXT`",
            path.display()
        ));
    };
    let now = fingerprint(reports)?;
    let mut wrong = Vec::new();
    for (f, hash) in &last.fingerprint {
        match now.get(f) {
            None => wrong.push(format!("{f}: accepted, now missing")),
            Some(h) if h != hash => wrong.push(format!("{f}: differs from what was accepted")),
            Some(_) => {}
        }
    }
    for f in now.keys().filter(|f| !last.fingerprint.contains_key(*f)) {
        wrong.push(format!("{f}: never accepted"));
    }
    if wrong.is_empty() {
        return Ok(());
    }
    Err(format!(
        "under {}, {}; the last acceptance ({}, {}) left them otherwise. Scores and records \
         change only through `cierva review --accept --reason TEXT`, never by hand",
        reports.display(),
        wrong.join("; "),
        last.date,
        last.commit
    ))
}

/// Loads an acceptance log (empty when there is none). Every entry needs a reason.
pub fn load_log(path: &Path) -> Result<Log, InputError> {
    if !path.exists() {
        return Ok(Log::default());
    }
    let src = yaml::read(path)?;
    if src.trim().is_empty() {
        return Ok(Log::default());
    }
    let log: Log = yaml::parse(path, &src)?;
    if let Some(i) = log
        .acceptances
        .iter()
        .position(|a| a.reason.trim().is_empty())
    {
        return Err(InputError::field(
            path,
            &src,
            &format!("acceptances[{i}].reason"),
            "an acceptance needs a reason",
        ));
    }
    // A chained entry gives every change its own reason.
    for (i, a) in log.acceptances.iter().enumerate() {
        let unreasoned = a
            .changes
            .iter()
            .position(|c| c.reason.as_deref().is_none_or(|r| r.trim().is_empty()));
        if let (Some(_), Some(j)) = (&a.chain, unreasoned) {
            return Err(InputError::field(
                path,
                &src,
                &format!("acceptances[{i}].changes[{j}]"),
                "each change of a chained acceptance needs its own reason",
            ));
        }
    }
    Ok(log)
}

/// The log's header, written once when the log is created.
const LOG_HEADER: &str = "# Written by `cierva review --accept --reason TEXT`, one entry per acceptance, appended:\n\
     # never rewritten, never edited by hand. Each entry's fingerprint is the FNV-1a 64 hash of\n\
     # the bytes of reports/scoreboard.yaml and of each reports/discrepancies/*.yaml as it left\n\
     # them; `cargo test` fails when the committed files are not what the last entry accepted.\n\
     # Each entry's `chain` hashes the previous entry's and its own content: an entry edited,\n\
     # removed or appended by hand breaks it. Every change carries its own reason.\n\
     acceptances:\n";

/// Appends `entry` to the log at `path` (creating it), with its chain link ([`link`]), and
/// returns it as logged: the bytes already there are never rewritten (the file is opened for
/// appending). Refused untouched: a log that does not load, whose chain is broken, or that
/// would not read back as its earlier entries followed by this one, and an entry with a change
/// that has no reason of its own.
pub fn append_log(path: &Path, entry: &Acceptance) -> Result<Acceptance, String> {
    use std::io::Write as _;
    let before = load_log(path).map_err(|e| e.to_string())?;
    // A broken chain is refused: a new link would vouch for the entry that broke it.
    chain_breaks(&before).map_err(|e| format!("{}: {e}; refused", path.display()))?;
    let previous = links(&before).pop().unwrap_or_default();
    let entry = &Acceptance {
        chain: Some(link(&previous, entry)),
        ..entry.clone()
    };
    if let Some(j) = entry
        .changes
        .iter()
        .position(|c| c.reason.as_deref().is_none_or(|r| r.trim().is_empty()))
    {
        return Err(format!(
            "{}: change {j} ({}/{}) has no reason of its own; refused",
            path.display(),
            entry.changes[j].case,
            entry.changes[j].item
        ));
    }
    let old = std::fs::read_to_string(path).unwrap_or_default();
    let mut added = String::new();
    if old.trim().is_empty() {
        added += LOG_HEADER;
    } else if !old.ends_with('\n') {
        added.push('\n');
    }
    added += &serde_yaml::to_string(std::slice::from_ref(entry))
        .map_err(|e| format!("cannot write the entry: {e}"))?;
    let after: Log = serde_yaml::from_str(&format!("{old}{added}"))
        .map_err(|e| format!("{}: the entry would not read back: {e}", path.display()))?;
    let same = |a: &Acceptance, b: &Acceptance| {
        serde_yaml::to_string(a)
            .ok()
            .zip(serde_yaml::to_string(b).ok())
            .is_some_and(|(a, b)| a == b)
    };
    let n = before.acceptances.len();
    let kept = after.acceptances.len() == n + 1
        && before
            .acceptances
            .iter()
            .zip(&after.acceptances)
            .all(|(a, b)| same(a, b))
        && same(&after.acceptances[n], entry);
    if !kept {
        return Err(format!(
            "{}: appending would not keep the earlier entries and add this one; refused",
            path.display()
        ));
    }
    let mut file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| format!("cannot open {}: {e}", path.display()))?;
    file.write_all(added.as_bytes())
        .map_err(|e| format!("cannot append to {}: {e}", path.display()))?;
    Ok(entry.clone())
}

/// The civil date and time in UTC, ISO 8601, of a time in seconds since 1970 (Howard Hinnant's
/// `civil_from_days`).
pub fn utc_iso8601(unix_seconds: u64) -> String {
    let (days, secs) = ((unix_seconds / 86_400) as i64, unix_seconds % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs % 3600 / 60,
        secs % 60
    )
}

/// Now, in UTC (ISO 8601), from the system clock.
pub fn now_utc() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    utc_iso8601(secs)
}

/// The repository's short HEAD commit, with `+dirty` when its tree has changes; `unknown`
/// without git or outside a repository.
pub fn head_commit(root: &Path) -> String {
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("-C")
            .arg(root)
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(c) if !c.is_empty() => match git(&["status", "--porcelain"]) {
            Some(s) if s.is_empty() => c,
            _ => format!("{c}+dirty"),
        },
        _ => "unknown".to_string(),
    }
}
