//! `cierva review`: what moved in the known discrepancies, and (with `--accept`) recording it.
//!
//! The counterpart of `cargo insta review` for the checks that are expected to fail: each one's
//! values are recorded in `reports/discrepancies/<case-id>.yaml` (see
//! [`cierva_harness::discrepancy`]), and a check whose model leaves them fails as "discrepancy
//! moved" until they are reviewed and accepted here.

use crate::{Format, progress, show};
use cierva_harness::{discrepancy, load_cases};
use std::path::PathBuf;
use std::process::ExitCode;

/// Runs the review. Exit 0 when nothing moved (or everything was accepted), 1 when something
/// moved and was not accepted or an expected failure could not be evaluated, 2 on bad input.
pub fn run(paths: Vec<PathBuf>, accept: bool, format: Format) -> ExitCode {
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
    let bar = progress(cases.len() as u64, "review");
    let mut reviews = Vec::new();
    for case in &cases {
        bar.set_message(case.id.clone());
        reviews.push(discrepancy::review(case));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut written = Vec::new();
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
    let moved = reviews.iter().filter(|r| !r.changes.is_empty()).count();
    let errors = reviews.iter().map(|r| r.errors.len()).sum::<usize>();
    match format {
        Format::Json => {
            let out = serde_json::json!({
                "cases": reviews,
                "accepted": accept,
                "written": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            });
            println!(
                "{}",
                serde_json::to_string_pretty(&out).expect("serialisable")
            );
        }
        Format::Text => {
            for r in &reviews {
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
            let recorded: usize = reviews.iter().map(|r| r.now.checks.len()).sum();
            if moved == 0 {
                println!(
                    "{} cases, {recorded} known discrepancies: nothing moved",
                    reviews.len()
                );
            } else if accept {
                println!(
                    "{} cases, {recorded} known discrepancies: {moved} cases changed, recorded in {}",
                    reviews.len(),
                    if written.is_empty() {
                        "no file".to_string()
                    } else {
                        show(&written)
                    }
                );
            } else {
                println!(
                    "{} cases, {recorded} known discrepancies: {moved} cases moved; if the \
                     changes are intended, record them with `cierva review --accept` and say why \
                     in the commit",
                    reviews.len()
                );
            }
        }
    }
    if errors > 0 || (moved > 0 && !accept) {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
