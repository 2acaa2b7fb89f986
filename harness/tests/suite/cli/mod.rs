//! The command line, one module per command: exit codes, output and files written, run as a
//! user runs them (the test build's `cierva` binary from the repository's root).

mod autorotate;
mod help;
mod identify;
mod inflow;
mod init;
mod linearize;
mod modes;
mod review;
mod sensitivity;
mod simulate;
mod synth_flight;
mod synth_history;
mod trim;
mod uncertainty;
mod validate;

use std::path::{Path, PathBuf};

pub(super) fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Runs `cierva` from the repository's root. `validate` writes no report unless the test asks
/// for one with `--report-dir` (tests run in parallel and must not share `reports/`).
pub(super) fn cierva(args: &[&str]) -> (i32, String, String) {
    let mut args: Vec<&str> = args.to_vec();
    if args.first() == Some(&"validate") && !args.contains(&"--report-dir") {
        args.push("--no-report");
    }
    crate::common::cierva(&args)
}

/// Two quick shipped cases, one with expected failures: exit 0 and the counts in the text.
/// (The whole suite runs as the `cases` trials and in CI's `cierva validate`; running it here
/// again would double the test time and test nothing more of the command line.)
pub(super) const QUICK_CASES: [&str; 2] = [
    "cases/seed002-vpm-m16-60kn.yaml",
    "cases/seed002-puma-autorotation-70kn.yaml",
];
