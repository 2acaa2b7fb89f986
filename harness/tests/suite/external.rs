//! External simulations as subjects (`docs/external-models.md`): the example suite
//! (`examples/vpm-m16-external`) validates through a command and through files, and a broken
//! command is an error (exit 2) that shows why.

use super::common::{cierva_in, repo_root};
use std::path::{Path, PathBuf};

/// The example's checks: the command's linear model (6: seed 002 Table 1's exact modes, the
/// short-period approximation, Eq. 21's elements, Eqs. 24-25), trim sweeps at two masses (2)
/// and time history (1); the files' linear model (6, the same), trim sweep (1) and time
/// history (1).
const EXAMPLE_CHECKS: usize = 17;

/// Fails with a message that says so when `python3` cannot be run (the example is a Python 3
/// script).
pub fn require_python3() {
    let ok = std::process::Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    assert!(
        ok,
        "python3 is not installed (or not on PATH): the example external model \
         (examples/vpm-m16-external/model/vpm_m16.py) needs it"
    );
}

#[test]
fn the_example_external_model_validates_through_a_command_and_files() {
    require_python3();
    let suite = repo_root().join("examples/vpm-m16-external");
    let (code, out, err) = cierva_in(
        &repo_root(),
        &[
            "--suite",
            suite.to_str().unwrap(),
            "validate",
            "--no-report",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let want = format!("{EXAMPLE_CHECKS} checks: {EXAMPLE_CHECKS} passed");
    assert!(out.contains(&want), "wanted `{want}` in:\n{out}");
    // The README shows this run's summary line: it must be what the run prints.
    let summary = out
        .lines()
        .find(|l| l.contains(&want))
        .expect("the summary line");
    let readme = std::fs::read_to_string(repo_root().join("README.md")).unwrap();
    assert!(
        readme.contains(summary),
        "README.md's tour shows the example's run; replace its line with:\n{summary}"
    );
    for case in [
        "vpm-m16-linear-command",
        "vpm-m16-trim-command-max-weight",
        "vpm-m16-trim-command-min-weight",
        "vpm-m16-linear-files",
        "vpm-m16-trim-files-max-weight",
        "vpm-m16-time-history-command",
        "vpm-m16-time-history-files",
    ] {
        assert!(out.contains(case), "{case} did not run:\n{out}");
    }
}

/// A suite in a fresh folder whose one case runs `command` for a trim (timeout `timeout_s`).
pub fn suite_with_command(dir: &Path, command: &str, timeout_s: f64) -> PathBuf {
    super::common::new_suite(dir);
    std::fs::write(
        dir.join("cases/broken.yaml"),
        format!(
            "id: broken\ntitle: a broken external command\nclass: regression\n\
             provenance: {{source: a test of harness/tests/suite/external.rs}}\n\
             model:\n  external:\n    command: {command}\n    timeout_s: {timeout_s}\n\
             tolerances:\n  forward:\n    sign: negative\n    reason: the test's own\n\
             checks:\n  - id: trends\n    kind: trim_sweep\n    sweep_mph: [30.0, 40.0]\n\
             \x20   description: the sign guards the model's side (a test's)\n\
             \x20   expect:\n      stick_longitudinal_percent_per_mph_max: {{tolerance: forward}}\n"
        ),
    )
    .unwrap();
    dir.to_path_buf()
}

#[test]
fn a_broken_external_command_is_an_error_that_shows_why() {
    require_python3();
    let base = crate::common::scratch("external");
    // Each: the command, and what the error must say.
    let cases: [(&str, &str, &[&str]); 6] = [
        (
            "not-found",
            "[cierva-no-such-program-here]",
            &["`cierva-no-such-program-here` was not found"],
        ),
        (
            "exits-3",
            "[python3, -c, \"import sys; sys.stderr.write('the model has no data here\\\\n'); sys.exit(3)\"]",
            &["exited 3", "the model has no data here"],
        ),
        (
            "garbage",
            "[python3, -c, \"import sys, json; open(json.load(open(sys.argv[1]))['response'], 'w').write('this is not JSON')\"]",
            &["is not JSON", "at line 1 column"],
        ),
        (
            "sleeps",
            "[python3, -c, \"import time; time.sleep(30)\"]",
            &["timed out after 1 s", "killed"],
        ),
        (
            "missing-quantity",
            "[python3, -c, \"import sys, json; r = json.load(open(sys.argv[1])); open(r['response'], 'w').write(json.dumps({'protocol': 'cierva-external/1', 'trim': {'pitch_deg': 3.0}}))\"]",
            &["gives no `stick_longitudinal_percent` in its trim at 30 mph"],
        ),
        (
            "start-in-v1",
            "[python3, -c, \"import sys, json; r = json.load(open(sys.argv[1])); open(r['response'], 'w').write(json.dumps({'protocol': 'cierva-external/1', 'trim': {'pitch_deg': 3.0}, 'start': [1.0]}))\"]",
            &[
                "has a `start`, which is `cierva-external/2`'s (the case asks in `cierva-external/1`)",
            ],
        ),
    ];
    let mut problems = Vec::new();
    for (name, command, want) in cases {
        let dir = suite_with_command(&base.join(name), command, 1.0);
        let started = std::time::Instant::now();
        let (code, out, err) = cierva_in(&dir, &["validate", "--no-report"]);
        let all = format!("{out}{err}");
        if code != 2 {
            problems.push(format!("{name}: exit {code}, not 2:\n{all}"));
        }
        if !all.contains("cases/broken.yaml") {
            problems.push(format!(
                "{name}: the error does not name the case file:\n{all}"
            ));
        }
        for w in want {
            if !all.contains(w) {
                problems.push(format!("{name}: no `{w}` in:\n{all}"));
            }
        }
        // The timeout is 1 s and the sleeper is killed at it (a sweep of two airspeeds asks
        // once, then stops): well under the 30 s it would sleep.
        if name == "sleeps" && started.elapsed().as_secs_f64() > 10.0 {
            problems.push(format!(
                "{name}: took {:.1} s: the command was not killed at its timeout",
                started.elapsed().as_secs_f64()
            ));
        }
    }
    let _ = std::fs::remove_dir_all(&base);
    assert!(problems.is_empty(), "{}", problems.join("\n\n"));
}

/// A files subject's tables are read when the case loads: a bad cell or column is an error
/// that names the table's line and column, inside the case's located error.
#[test]
fn a_bad_trim_table_is_a_located_error() {
    let dir = crate::common::scratch("external-files");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("cierva.toml"), "format_version = 1\n").unwrap();
    std::fs::copy(
        repo_root().join("cases/tolerances.yaml"),
        dir.join("tolerances.yaml"),
    )
    .unwrap();
    let case = dir.join("case.yaml");
    std::fs::write(
        &case,
        "id: case\ntitle: a bad trim table\nclass: regression\n\
         provenance: {source: a test of harness/tests/suite/external.rs}\n\
         model:\n  files:\n    trim_table: trim.csv\n\
         tolerances:\n  forward:\n    sign: negative\n    reason: the test's own\n\
         checks:\n  - id: trends\n    kind: trim_sweep\n    sweep_mph: [30.0, 40.0]\n\
         \x20   description: the sign guards the model's side (a test's)\n\
         \x20   expect:\n      stick_longitudinal_percent_per_mph_max: {tolerance: forward}\n",
    )
    .unwrap();
    // Each: the table, and what the error must say (the table's line and column first).
    let tables = [
        (
            "# a comment\nairspeed_mph,pitch_deg\n30,4.0\n40,abc\n",
            "trim.csv:4:4: `pitch_deg`: `abc` is not a number",
        ),
        (
            "airspeed_mph,pitch_degs\n30,4.0\n",
            "trim.csv:1:2: `pitch_degs` is not a trim quantity (did you mean `pitch_deg`?)",
        ),
        ("pitch_deg\n4.0\n", "trim.csv:1: no airspeed column"),
        (
            "airspeed_mph,pitch_deg\n30,4.0\n30,4.1\n",
            "trim.csv:3: a second row",
        ),
    ];
    let mut problems = Vec::new();
    for (table, want) in tables {
        std::fs::write(dir.join("trim.csv"), table).unwrap();
        match cierva_harness::suite::case::load(&case) {
            Ok(_) => problems.push(format!("loaded with the table:\n{table}")),
            Err(e) => {
                let msg = e.to_string();
                if !(msg.contains(want) && e.line == Some(7)) {
                    problems.push(format!("wanted `{want}` at the case's line 7, got: {msg}"));
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
