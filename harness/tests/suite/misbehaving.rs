//! Models that misbehave behind the command protocol (issue 49, "A model that misbehaves"):
//! each costs bounded time and memory and ends in an error, never a pass.
//! - A model that starts a child and hangs: at its timeout its whole process group is killed.
//! - A flood of stderr (one 50 MB line): kept to its end, cut as input errors are.
//! - A response that grows without end: killed as it passes its size limit, never read.
//! - Six checks asking the same request at once: the command runs once.
//! - A number too small for a double (`1e-400`): refused, not read as 0.
//!
//! The memory a run of `cierva` takes is its peak resident set as the kernel counts it for the
//! process and the children it waited for (`getrusage`'s `ru_maxrss`), so the model's own is in
//! it too: the models below write in chunks and hold little.

use cierva_harness::external::command::ExternalCommand;
use cierva_harness::external::{FlightModel as _, Request};
use cierva_harness::inputs::condition::{Loading, TrimRequest};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The most memory a run of `cierva validate` on a misbehaving model may take, bytes (100 MB,
/// the bound): its own `validate` of one case takes about 10 MB, so anything near the
/// bound is what the model sent it.
const MAX_RUN_BYTES: u64 = 100_000_000;

/// The most a misbehaving model's error may print, bytes: twenty stderr lines of 100
/// characters and the case's context are under 4 kB; 64 kB is far from the megabytes an
/// uncut line would print.
const MAX_PRINTED_BYTES: usize = 64_000;

/// A suite in a fresh folder under the system's temporary folder, whose one case runs
/// `command` for two trims (a sweep at 30 and 40 mph), with `timeout_s`.
fn suite_with(name: &str, command: &str, timeout_s: f64) -> PathBuf {
    let dir = crate::common::scratch(&format!("misbehaving-{name}"));
    super::external::suite_with_command(&dir, command, timeout_s)
}

/// What a run of `cierva validate --no-report` in `dir` gave: exit code, stdout and stderr
/// together, and its peak memory (with the children it waited for), bytes.
struct Run {
    code: i32,
    printed: String,
    peak_bytes: u64,
}

/// The marker before the peak memory that [`WRAPPER`] prints last on stderr.
const PEAK_MARKER: &str = "\ncierva-test-peak-kib: ";

/// Runs its arguments as a command and prints the peak memory of what it ran (the children it
/// waited for), KiB, last on stderr; exits with its code. It runs `cierva` from a small
/// process: a process started straight from the test binary inherits the test binary's own
/// peak in its count, which with the suite's tests running beside it is hundreds of MB.
const WRAPPER: &str = "import resource, subprocess, sys\n\
                       code = subprocess.run(sys.argv[1:]).returncode\n\
                       peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss\n\
                       sys.stderr.write('\\ncierva-test-peak-kib: %d' % peak)\n\
                       sys.exit(code)";

fn validate_in(dir: &Path) -> Run {
    let out = std::process::Command::new("python3")
        .args([
            "-c",
            WRAPPER,
            env!("CARGO_BIN_EXE_cierva"),
            "validate",
            "--no-report",
        ])
        .current_dir(dir)
        .stdin(std::process::Stdio::null())
        .output()
        .expect("python3 runs cierva");
    let mut printed = String::from_utf8_lossy(&out.stdout).into_owned();
    let err = String::from_utf8_lossy(&out.stderr);
    let (err, peak) = err
        .rsplit_once(PEAK_MARKER)
        .expect("the wrapper's last line");
    printed.push_str(err);
    // Linux counts ru_maxrss in KiB, macOS in bytes.
    let unit = if cfg!(target_os = "macos") { 1 } else { 1024 };
    Run {
        code: out.status.code().unwrap_or(-1),
        printed,
        peak_bytes: peak.trim().parse::<u64>().expect("a count") * unit,
    }
}

/// Whether the process `pid` is gone or a zombie (dead, not yet reaped by whoever inherited
/// it), as `ps` sees it.
fn dead(pid: &str) -> bool {
    let out = std::process::Command::new("ps")
        .args(["-o", "stat=", "-p", pid])
        .output()
        .expect("ps runs");
    let stat = String::from_utf8_lossy(&out.stdout);
    stat.trim().is_empty() || stat.trim_start().starts_with('Z')
}

#[test]
fn a_timeout_kills_the_models_whole_process_group() {
    super::external::require_python3();
    // The model starts a child that would sleep for 1000 s, writes its pid, and waits on it.
    let dir = suite_with(
        "group",
        "[sh, -c, \"sleep 1000 & echo $! > child.pid; wait\"]",
        1.0,
    );
    let run = validate_in(&dir);
    assert_eq!(run.code, 2, "{}", run.printed);
    assert!(
        run.printed.contains("timed out after 1 s"),
        "{}",
        run.printed
    );
    let pid = std::fs::read_to_string(dir.join("cases/child.pid")).expect("the model wrote it");
    let pid = pid.trim();
    // Killed with its parent, it is reaped by whoever inherits it: give that a moment.
    let gone = (0..100).any(|_| {
        let d = dead(pid);
        if !d {
            std::thread::sleep(Duration::from_millis(50));
        }
        d
    });
    if !gone {
        let _ = std::process::Command::new("kill")
            .args(["-9", pid])
            .status();
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        gone,
        "the model's child (pid {pid}) outlived the model's timeout: only the model was killed"
    );
}

#[test]
fn a_flood_of_stderr_is_cut_and_costs_bounded_memory() {
    super::external::require_python3();
    // One 50 MB line (written 1 MB at a time, so the model holds little), then a last line,
    // then exit 3.
    let dir = suite_with(
        "stderr",
        "[python3, -c, \"import sys\\nfor _ in range(50): sys.stderr.write('x' * 1000000)\\n\
         sys.stderr.write('\\\\nthe last line of the flood\\\\n'); sys.exit(3)\"]",
        60.0,
    );
    let run = validate_in(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    let p = &run.printed;
    assert_eq!(run.code, 2, "{}", &p[..p.len().min(2000)]);
    assert!(
        p.len() < MAX_PRINTED_BYTES,
        "{} bytes printed: {}",
        p.len(),
        &p[..2000]
    );
    for want in [
        "exited 3",
        "the last line of the flood",
        "... (",
        "bytes)",
        "more characters)",
    ] {
        assert!(p.contains(want), "no `{want}` in:\n{p}");
    }
    assert!(
        run.peak_bytes < MAX_RUN_BYTES,
        "the run took {} MB",
        run.peak_bytes / 1_000_000
    );
}

#[test]
fn a_response_that_grows_without_end_is_refused_while_it_is_written() {
    super::external::require_python3();
    // 440 MB written 1 MB at a time (a trim may take 1 MiB), then a marker that it finished.
    let dir = suite_with(
        "oversized",
        "[python3, -c, \"import sys, json\\nr = json.load(open(sys.argv[1]))\\n\
         f = open(r['response'], 'w')\\nfor _ in range(440): f.write('x' * 1000000); f.flush()\\n\
         open('finished', 'w').write('it was not stopped')\"]",
        120.0,
    );
    let run = validate_in(&dir);
    let finished = dir.join("cases/finished").exists();
    let _ = std::fs::remove_dir_all(&dir);
    let p = &run.printed;
    assert_eq!(run.code, 2, "{p}");
    assert!(p.contains("passed 1048576 bytes while it ran"), "{p}");
    assert!(!finished, "the model wrote all 440 MB: it was not stopped");
    assert!(
        run.peak_bytes < MAX_RUN_BYTES,
        "the run took {} MB",
        run.peak_bytes / 1_000_000
    );
}

#[test]
fn identical_requests_asked_at_once_run_the_command_once() {
    super::external::require_python3();
    let dir = crate::common::scratch("once");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // Each run appends a line to runs.txt, then answers after 0.3 s.
    let script = "import sys, json, time\n\
                  r = json.load(open(sys.argv[1]))\n\
                  open('runs.txt', 'a').write(r['compute'] + '\\n')\n\
                  time.sleep(0.3)\n\
                  open(r['response'], 'w').write(json.dumps({'protocol': 'cierva-external/1', \
                  'trim': {'pitch_deg': r['condition']['airspeed_mph'] / 10}}))\n";
    let model = ExternalCommand::new(
        vec!["python3".into(), "-c".into(), script.into()],
        dir.clone(),
        Duration::from_secs(30),
    );
    let loading = Loading {
        mass_kg: Some(450.0),
        density_altitude_ft: 0.0,
    };
    // Six checks at 60 mph and six at 70 mph, all asking at once.
    let barrier = std::sync::Barrier::new(12);
    let answers: Vec<f64> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..12)
            .map(|k| {
                let (model, barrier) = (&model, &barrier);
                s.spawn(move || {
                    barrier.wait();
                    let at = TrimRequest::level(if k % 2 == 0 { 60.0 } else { 70.0 });
                    let q = model
                        .trim(&Request::at(at, loading))
                        .expect("the model answers");
                    q.iter().find(|(n, _)| *n == "pitch_deg").unwrap().1
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let runs = std::fs::read_to_string(dir.join("runs.txt")).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(
        runs.lines().count(),
        2,
        "two distinct requests ran the command {} times",
        runs.lines().count()
    );
    for (k, a) in answers.iter().enumerate() {
        let want = if k % 2 == 0 { 6.0 } else { 7.0 };
        assert_eq!(*a, want, "check {k}");
    }
}

#[test]
fn a_number_too_small_for_a_double_is_refused() {
    super::external::require_python3();
    let dir = suite_with(
        "underflow",
        "[python3, -c, \"import sys, json; r = json.load(open(sys.argv[1])); \
         open(r['response'], 'w').write('{\\\"protocol\\\": \\\"cierva-external/1\\\", \
         \\\"trim\\\": {\\\"stick_longitudinal_percent\\\": 1e-400}}')\"]",
        30.0,
    );
    let run = validate_in(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(run.code, 2, "{}", run.printed);
    assert!(
        run.printed
            .contains("at line 1 column 74: `1e-400` is too small for a double"),
        "{}",
        run.printed
    );
}
