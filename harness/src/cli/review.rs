//! `cierva review`: what moved in the known discrepancies and on the scoreboard, and (with
//! `--accept`) recording it.
//!
//! The counterpart of `cargo insta review` for the checks that are expected to fail: each one's
//! values are recorded in the suite's `reports/discrepancies/<case-id>.yaml` (see
//! [`cierva_harness::suite::discrepancy`]), and a check whose model leaves them fails as "discrepancy
//! moved" until they are reviewed and accepted here.
//!
//! Accepting needs a reason (`--accept --reason TEXT`): each acceptance is appended to
//! the suite's `reports/acceptances.yaml` with what changed and the fingerprint of what it wrote (see
//! [`cierva_harness::suite::review`]).

use super::*;
use cierva_harness::suite::review::{self as rv, Acceptance};
use cierva_harness::suite::{discrepancy, scoreboard};

/// Review the known discrepancies: run every check that is expected to fail and compare
/// what the model gives with what is recorded for it in `reports/discrepancies/`.
///
/// A check marked `expected_failure` stays one only while the model stays inside its
/// recorded bands; when the model moves (better or worse), `cargo test` and `cierva validate`
/// fail it as "discrepancy moved". This command lists what moved; `--accept` records the
/// model's values as they are now (as `cargo insta review` accepts snapshots), with a
/// reason (`--reason`) and one per changed item (`--because`), appending an entry to
/// `reports/acceptances.yaml`: the date, commit, reason, each change (old, new, better or
/// worse, its reason), the fingerprint of the files written and the entry's hash chain link. Exit code 0 when nothing moved or all was accepted, 1 otherwise, 2 on bad input
/// (`--accept` without `--reason`).
///
/// Example: `cierva review cases/naca-tr515-table-iii.yaml`, then `cierva review --accept
/// --reason "hub drag from the fitted corrections" --because
/// 'naca-tr515-table-iii/low-mu-*=the hub drag now comes from the fit'`
#[derive(clap::Args)]
pub(crate) struct ReviewArgs {
    /// Case files or folders searched for `*.yaml` (default: `cases`).
    paths: Vec<PathBuf>,
    /// Record the model's values as they are now (needs `--reason`).
    #[arg(long)]
    accept: bool,
    /// Why the scores and records may change (required with `--accept`): logged in
    /// `reports/acceptances.yaml` with what changed.
    #[arg(long, value_name = "TEXT")]
    reason: Option<String>,
    /// Why one changed score or record may change, `CASE/ITEM=TEXT` (`*` allowed in ITEM, the
    /// case named in full); every changed item needs one with `--accept`, and `cierva review`
    /// lists the ones to fill. Repeat for each item.
    #[arg(long, value_name = "CASE/ITEM=TEXT")]
    because: Vec<rv::ItemReason>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

/// The reason to log when accepting, or why the arguments are refused: `--accept` needs a
/// reason that says something, and `--reason` and `--because` go only with `--accept`.
fn reason_for(
    accept: bool,
    reason: Option<String>,
    because: &[rv::ItemReason],
) -> Result<Option<String>, &'static str> {
    if !accept && !because.is_empty() {
        return Err(
            "`--because` goes with `--accept` (it is an item's reason logged for accepting); \
             without `--accept` nothing is written",
        );
    }
    match (accept, reason) {
        (false, None) => Ok(None),
        (false, Some(_)) => Err(
            "`--reason` goes with `--accept` (it is the reason logged for accepting); without \
             `--accept` nothing is written",
        ),
        (true, None) => Err(
            "`--accept` needs `--reason TEXT`: say why the scores and records may change; the \
             reason is logged with what changed in the suite's acceptance log. Nothing was \
             written",
        ),
        (true, Some(r)) if r.trim().is_empty() => Err(
            "`--reason` is empty: say why the scores and records may change. Nothing was written",
        ),
        (true, Some(r)) => Ok(Some(r.trim().to_string())),
    }
}

/// Runs the review. Exit 0 when nothing moved (or everything was accepted), 1 when something
/// moved and was not accepted or an expected failure could not be evaluated, 2 on bad input
/// (`--accept` without `--reason` among it).
pub(crate) fn review(a: ReviewArgs) -> Result<ExitCode, Error> {
    let ReviewArgs {
        paths,
        accept,
        reason,
        because,
        format,
    } = a;
    let reason = reason_for(accept, reason, &because).map_err(Error::input)?;
    let suite = suite()?;
    let log = rv::load_log(&suite.acceptances())?;
    let cases = suite_cases(&suite, paths)?;
    let board = scoreboard::load(&suite)?;
    let ran = review_cases(&cases);
    let (scores, judged) = (ran.scores(), ran.judged(&board));
    let reviews: Vec<_> = ran
        .cases
        .iter()
        .map(|c| rv::review(&c.case, &c.results))
        .collect();
    let scores_moved: Vec<&cierva_harness::suite::review::Judged> = judged
        .iter()
        .filter(|j| j.change != scoreboard::Change::Same)
        .collect();
    // Committed scores that a reviewed case no longer declares: `--accept` drops them.
    let reviewed: Vec<&str> = cases.iter().map(|c| c.id.as_str()).collect();
    let dropped: Vec<(String, String)> = reviewed
        .iter()
        .filter_map(|case| board.scores.get(*case).map(|m| (case, m)))
        .flat_map(|(case, m)| {
            m.keys()
                .filter(|id| !scores.iter().any(|s| s.case == **case && s.id == **id))
                .map(move |id| (case.to_string(), id.clone()))
        })
        .collect();
    let stale: Vec<String> = dropped.iter().map(|(c, id)| format!("{c} {id}")).collect();
    let mut written = Vec::new();
    let mut logged = None;
    let mut changes = rv::changes(&board, &judged, &dropped, &reviews);
    if let Some(reason) = reason {
        // The commit is read before anything is written: the files written make the tree dirty.
        let commit = rv::head_commit(&suite.root);
        rv::assign_reasons(&mut changes, &because).map_err(Error::input)?;
        let board = (!(scores_moved.is_empty() && stale.is_empty()))
            .then(|| scoreboard::with(&board, &reviewed, &scores));
        if let Err(e) = write_accepted(&suite, board.as_ref(), &reviews, &mut written) {
            return Err(Error::input(e));
        }
        match log_acceptance(&suite, &log, reason, commit, changes.clone()) {
            Ok(entry) => logged = Some(entry),
            Err(e) => return Err(Error::input(e)),
        }
    }
    let moved =
        reviews.iter().filter(|r| !r.changes.is_empty()).count() + scores_moved.len() + stale.len();
    let errors = reviews.iter().map(|r| r.errors.len()).sum::<usize>();
    match format {
        Format::Json => {
            let out = serde_json::json!({
                "cases": reviews,
                "scores": judged,
                "scores_no_longer_declared": stale,
                "accepted": accept,
                "written": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
                "logged": logged.as_ref().and_then(|l| l.as_ref()),
            });
            print_json(&out);
        }
        Format::Text => {
            print_text(
                &reviews,
                (&judged, &scores_moved, &stale),
                &written,
                accept,
                &suite.scoreboard(),
            );
            if !accept && !changes.is_empty() {
                println!(
                    "each changed item needs its own reason when accepted:\n{}",
                    changes
                        .iter()
                        .map(rv::because_line)
                        .collect::<Vec<_>>()
                        .join("\n")
                );
            }
            print_logged(&suite, logged.as_ref(), &log);
        }
    }
    if errors > 0 || (moved > 0 && !accept) {
        Ok(ExitCode::from(1))
    } else {
        Ok(ExitCode::SUCCESS)
    }
}

/// The cases under `paths` (default: the suite's cases folder), every one loaded and the
/// suite's own; otherwise the error, printed, and exit code 2.
fn suite_cases(
    suite: &cierva_harness::suite::Suite,
    paths: Vec<PathBuf>,
) -> Result<Vec<cierva_harness::suite::case::Case>, Error> {
    let paths = if paths.is_empty() {
        vec![suite.cases().to_path_buf()]
    } else {
        paths
    };
    let loaded = match load_cases(&paths) {
        Ok(l) if !l.is_empty() => l,
        Ok(_) => {
            return Err(Error::input(format!(
                "no case files (*.yaml) under {}",
                show(&paths)
            )));
        }
        Err(e) => return Err(Error::input(e)),
    };
    let mut cases = Vec::new();
    for c in loaded {
        match c {
            // Its records are written to the suite's folder, where only the suite's own cases
            // find them.
            Ok(case) if case.records_dir.as_deref() != Some(suite.discrepancies().as_path()) => {
                return Err(Error::input(format!(
                    "{}: not a case of the suite at {}: review it in its own suite (--suite)",
                    case.path.display(),
                    suite.root.display()
                )));
            }
            Ok(case) => cases.push(case),
            Err(e) => return Err(e.into()),
        }
    }
    Ok(cases)
}

/// The text output: what moved, case by case and on the scoreboard, and what to do about it.
fn print_text(
    reviews: &[cierva_harness::suite::review::CaseReview],
    (judged, scores_moved, stale): (
        &[cierva_harness::suite::review::Judged],
        &[&cierva_harness::suite::review::Judged],
        &[String],
    ),
    written: &[PathBuf],
    accept: bool,
    scoreboard_file: &Path,
) {
    let moved =
        reviews.iter().filter(|r| !r.changes.is_empty()).count() + scores_moved.len() + stale.len();
    for r in reviews {
        if r.changes.is_empty() && r.errors.is_empty() {
            continue;
        }
        println!("{}:", r.case);
        for c in &r.changes {
            println!("  {c}");
        }
        for e in &r.errors {
            println!("  error (cannot be recorded): {e}");
        }
    }
    if !(scores_moved.is_empty() && stale.is_empty()) {
        println!("scoreboard ({}):", scoreboard_file.display());
        for j in scores_moved {
            println!("  {}", j.describe());
        }
        for s in stale {
            let what = if accept {
                "dropped"
            } else {
                "would be dropped"
            };
            println!("  {s}: committed, no longer declared by its case ({what})");
        }
    }
    let recorded: usize = reviews.iter().map(|r| r.now.checks.len()).sum();
    if moved == 0 {
        println!(
            "{} cases, {recorded} known discrepancies, {} scores: nothing moved",
            reviews.len(),
            judged.len()
        );
    } else if accept {
        println!(
            "{} cases, {recorded} known discrepancies: {moved} cases or scores changed, recorded in {}",
            reviews.len(),
            if written.is_empty() {
                "no file".to_string()
            } else {
                show(written)
            }
        );
    } else {
        println!(
            "{} cases, {recorded} known discrepancies: {moved} cases or scores moved; if \
             the changes are intended, record them with `cierva review --accept --reason \
             TEXT --because CASE/ITEM=TEXT ...` (the reasons are logged in \
             reports/acceptances.yaml)",
            reviews.len()
        );
    }
}

/// Writes what is accepted: the scoreboard (when given) and the records of every review that
/// moved; each file that changed is added to `written`.
fn write_accepted(
    suite: &cierva_harness::suite::Suite,
    board: Option<&scoreboard::Board>,
    reviews: &[rv::CaseReview],
    written: &mut Vec<PathBuf>,
) -> Result<(), String> {
    if let Some(board) = board {
        match scoreboard::write(suite, board) {
            Ok(true) => written.push(suite.scoreboard()),
            Ok(false) => {}
            Err(e) => {
                return Err(format!(
                    "could not write {}: {e}",
                    suite.scoreboard().display()
                ));
            }
        }
    }
    let records = suite.discrepancies();
    for r in reviews.iter().filter(|r| !r.changes.is_empty()) {
        let path = discrepancy::path_for(&records, &r.case);
        match discrepancy::write(&records, &r.now) {
            Ok(true) => written.push(path),
            Ok(false) => {}
            Err(e) => return Err(format!("could not write {}: {e}", path.display())),
        }
    }
    Ok(())
}

/// Appends the acceptance to the log, with the fingerprint of the files as now written and its
/// chain link. Nothing is logged (`None`) when nothing changed and the log's last entry already
/// holds that fingerprint and a link; with no changes, an entry is logged only for a missing
/// log, files that differ from its last entry, or a last entry logged before the chain (the
/// new entry starts it).
fn log_acceptance(
    suite: &cierva_harness::suite::Suite,
    log: &rv::Log,
    reason: String,
    commit: String,
    changes: Vec<rv::Accepted>,
) -> Result<Option<Acceptance>, String> {
    let fingerprint = rv::fingerprint(suite.reports())?;
    let last = log.acceptances.last();
    if changes.is_empty() && last.is_some_and(|l| l.fingerprint == fingerprint && l.chain.is_some())
    {
        return Ok(None);
    }
    let entry = Acceptance {
        date: rv::now_utc(),
        commit,
        reason,
        changes,
        fingerprint,
        chain: None,
    };
    rv::append_log(&suite.acceptances(), &entry).map(Some)
}

/// The text output's last line for an acceptance: what was logged, or that nothing was.
fn print_logged(
    suite: &cierva_harness::suite::Suite,
    logged: Option<&Option<Acceptance>>,
    log: &rv::Log,
) {
    match logged {
        None => {}
        Some(Some(entry)) => println!(
            "logged in {}: {} at {}, {} changes: {}",
            suite.acceptances().display(),
            entry.date,
            entry.commit,
            entry.changes.len(),
            entry.reason
        ),
        Some(None) => println!(
            "nothing to accept: the scoreboard and the records are as last accepted{}; nothing \
             written",
            log.acceptances
                .last()
                .map_or(String::new(), |l| format!(" ({}, {})", l.date, l.commit))
        ),
    }
}

/// Every case run for its review and scores: every check when the case has scores, its
/// expected failures otherwise. Checks on every core, shared out one at a time.
fn review_cases(
    cases: &[cierva_harness::suite::case::Case],
) -> cierva_harness::suite::validation::Ran {
    let select = |case: &cierva_harness::suite::case::Case,
                  check: &cierva_harness::checks::Check| {
        !case.scores.is_empty() || check.expected_failure.is_some()
    };
    let selected: usize = cases
        .iter()
        .map(|case| case.checks.iter().filter(|c| select(case, c)).count())
        .sum();
    let bar = progress(selected as u64, "review");
    let ran = cierva_harness::suite::validation::validate(
        cases.iter().cloned().map(Ok).collect(),
        &cierva_harness::suite::validation::Options {
            select: &select,
            done: &|case, _| {
                bar.set_message(case.id.clone());
                bar.inc(1);
            },
            ..Default::default()
        },
    );
    bar.finish_and_clear();
    ran
}
