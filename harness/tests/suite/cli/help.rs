//! What every command shares: help examples, a closed pipe.

use super::*;
use std::process::Command;

/// A reader that stops early (`cierva ... | head`) ends the run quietly with the status of a
/// process SIGPIPE ended (141), not a panic.
#[test]
fn a_closed_pipe_ends_the_run_quietly() {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_cierva"))
        .args([
            "modes",
            "flight-refs/seed002-vpm-m16-60kn.yaml",
            "--sweep",
            "Q_u=0.06:0.26:2000",
            "--format",
            "json",
        ])
        .current_dir(root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let mut first = [0u8; 16];
    child
        .stdout
        .take()
        .expect("piped")
        .read_exact(&mut first)
        .expect("some output");
    // The reading end is dropped here, mid-output (the JSON is megabytes long).
    let out = child.wait_with_output().expect("ends");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(141), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// Every example in `--help` names files that exist: a path of the repository (a word with a
/// `/` that is not under `/tmp` and is not an output) must be there.
#[test]
fn help_examples_name_files_that_exist() {
    let (_, top, _) = cierva(&["--help"]);
    let commands: Vec<String> = top
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect();
    assert!(commands.len() >= 15, "{top}");
    let mut missing = Vec::new();
    for c in &commands {
        let (_, help, _) = cierva(&[c, "--help"]);
        for example in help.split("Example: `").skip(1) {
            let example = example.split('`').next().unwrap_or_default();
            let mut previous = "";
            for w in example.split_whitespace() {
                let output = matches!(previous, "--output" | "--report" | ">" | "new-case");
                if w.contains('/') && !w.starts_with("/tmp") && !output && !root().join(w).exists()
                {
                    missing.push(format!("`cierva {c} --help`: {w} in `{example}`"));
                }
                previous = w;
            }
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}
