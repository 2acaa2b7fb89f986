//! `cierva review`: what moved in the known discrepancies and on the scoreboard, and (with
//! `--accept`) recording it.
//!
//! The counterpart of `cargo insta review` for the checks that are expected to fail: each one's
//! values are recorded in `reports/discrepancies/<case-id>.yaml` (see
//! [`cierva_harness::discrepancy`]), and a check whose model leaves them fails as "discrepancy
//! moved" until they are reviewed and accepted here.

use super::*;
use cierva_harness::{discrepancy, scoreboard};

/// Runs the review. Exit 0 when nothing moved (or everything was accepted), 1 when something
/// moved and was not accepted or an expected failure could not be evaluated, 2 on bad input.
pub(crate) fn run(paths: Vec<PathBuf>, accept: bool, format: Format) -> ExitCode {
    let paths = if paths.is_empty() {
        vec![PathBuf::from("cases")]
    } else {
        paths
    };
    let loaded = match load_cases(&paths) {
        Ok(l) if !l.is_empty() => l,
        Ok(_) => {
            eprintln!("error: no case files (*.yaml) under {}", show(&paths));
            return ExitCode::from(2);
        }
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let mut cases = Vec::new();
    for c in loaded {
        match c {
            Ok(case) => cases.push(case),
            Err(e) => {
                eprintln!("{}", e.render());
                return ExitCode::from(2);
            }
        }
    }
    let board = match scoreboard::load() {
        Ok(b) => b,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let (reviews, scores) = review_cases(&cases);
    let judged = cierva_harness::review::judge(&board, scores.clone());
    let scores_moved: Vec<&cierva_harness::review::Judged> = judged
        .iter()
        .filter(|j| j.change != scoreboard::Change::Same)
        .collect();
    // Committed scores that a reviewed case no longer declares: `--accept` drops them.
    let reviewed: Vec<&str> = cases.iter().map(|c| c.id.as_str()).collect();
    let stale: Vec<String> = reviewed
        .iter()
        .filter_map(|case| board.scores.get(*case).map(|m| (case, m)))
        .flat_map(|(case, m)| {
            m.keys()
                .filter(|id| !scores.iter().any(|s| s.case == **case && s.id == **id))
                .map(move |id| format!("{case} {id}"))
        })
        .collect();
    let mut written = Vec::new();
    if accept && !(scores_moved.is_empty() && stale.is_empty()) {
        match scoreboard::write(&scoreboard::with(&board, &reviewed, &scores)) {
            Ok(true) => written.push(scoreboard::path()),
            Ok(false) => {}
            Err(e) => {
                eprintln!(
                    "error: could not write {}: {e}",
                    scoreboard::path().display()
                );
                return ExitCode::from(2);
            }
        }
    }
    if accept {
        for r in reviews.iter().filter(|r| !r.changes.is_empty()) {
            match discrepancy::write(&r.now) {
                Ok(true) => written.push(discrepancy::path_for(&r.case)),
                Ok(false) => {}
                Err(e) => {
                    eprintln!(
                        "error: could not write {}: {e}",
                        discrepancy::path_for(&r.case).display()
                    );
                    return ExitCode::from(2);
                }
            }
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
            });
            print_json(&out);
        }
        Format::Text => print_text(&reviews, &judged, &scores_moved, &stale, &written, accept),
    }
    if errors > 0 || (moved > 0 && !accept) {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// The text output: what moved, case by case and on the scoreboard, and what to do about it.
fn print_text(
    reviews: &[cierva_harness::review::CaseReview],
    judged: &[cierva_harness::review::Judged],
    scores_moved: &[&cierva_harness::review::Judged],
    stale: &[String],
    written: &[PathBuf],
    accept: bool,
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
        println!("scoreboard ({}):", scoreboard::path().display());
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
             the changes are intended, record them with `cierva review --accept` and say \
             why in the commit",
            reviews.len()
        );
    }
}

/// Every case's review and scores: every check when the case has scores, its expected failures
/// otherwise. Checks on every core, shared out one at a time.
fn review_cases(
    cases: &[cierva_harness::case::Case],
) -> (
    Vec<cierva_harness::review::CaseReview>,
    Vec<cierva_harness::scoreboard::Score>,
) {
    let select = |case: &cierva_harness::case::Case, check: &cierva_harness::checks::Check| {
        !case.scores.is_empty() || check.expected_failure.is_some()
    };
    let selected: usize = cases
        .iter()
        .map(|case| case.checks.iter().filter(|c| select(case, c)).count())
        .sum();
    let bar = progress(selected as u64, "review");
    let all: Vec<&cierva_harness::case::Case> = cases.iter().collect();
    let ran = eval::run_cases(&all, select, |case, _| {
        bar.set_message(case.id.clone());
        bar.inc(1);
    });
    bar.finish_and_clear();
    let mut reviews = Vec::new();
    let mut scores = Vec::new();
    for (case, (results, _)) in cases.iter().zip(ran) {
        reviews.push(cierva_harness::review::review(case, &results));
        scores.extend(cierva_harness::review::scores_of(case, &results));
    }
    (reviews, scores)
}
