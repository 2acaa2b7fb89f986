//! Shared by the suite's tests: [`cierva`], the command run from the repository's root;
//! [`scratch`], the run's folders for tests to write in; [`SplitMix`], the seeded draws of
//! known-answer trials; and, for the bad-input tests, [`check_fixtures`]: every YAML file in a
//! folder is a broken input whose header says what the error must contain and on which line it
//! must point.
//!
//! ```yaml
//! # error: <text the message must contain>
//! # line: <1-based line the error must name>
//! ```

use cierva_harness::inputs::yaml::InputError;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The repository's root: the suite this repository is (its `cierva.toml`), where its cases,
/// aircraft and references are.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("harness/ sits in the repository root")
        .to_path_buf()
}

/// The folders of the data the repository ships (its inputs, references and committed
/// outputs), from its root.
pub const DATA_DIRS: [&str; 6] = [
    "cases",
    "aircraft",
    "flight-refs",
    "fits",
    "corrections",
    "reports",
];

/// The repository's suite.
pub fn suite() -> cierva_harness::suite::Suite {
    cierva_harness::suite::Suite::open(&repo_root()).expect("the repository is a suite")
}

/// Runs the `cierva` binary from the repository's root: its exit code, stdout and stderr.
pub fn cierva(args: &[&str]) -> (i32, String, String) {
    cierva_in(&repo_root(), args)
}

/// Runs the `cierva` binary in `dir`: its exit code, stdout and stderr.
pub fn cierva_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cierva"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A scratch folder for a test, `<temp>/cierva-tests-<pid>/<name>` (`<temp>` the system's
/// temporary folder, `<pid>` this test process's id); the caller creates `name` itself, and
/// gives each of its folders a name of its own in the run.
///
/// Many tests' folders are shared by a module's tests (a suite one test builds and others
/// read), so no single test can remove them when done. Instead all of a run's folders sit
/// under the run's one root, and the first call in a process (the root is made once, with
/// [`OnceLock`]) sweeps the roots earlier runs left: every `cierva-tests-<pid>` folder in
/// `<temp>` that is not this process's and is stale ([`is_stale`]). A root of this process's
/// own id left by an earlier process is emptied first. Only names of exactly that form are
/// read, so folders of other tools (such as `scripts/retune-trials`'
/// `cierva-retune-trials-<random>`) are never touched. Sweeping ignores every error (another
/// run may be sweeping at the same time).
pub fn scratch(name: &str) -> PathBuf {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    ROOT.get_or_init(|| {
        let temp = std::env::temp_dir();
        sweep_stale_scratch(&temp);
        let root = temp.join(format!("cierva-tests-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let _ = std::fs::create_dir_all(&root);
        root
    })
    .join(name)
}

/// Removes the stale scratch folders of other runs from `temp` (see [`scratch`]), ignoring
/// every error.
fn sweep_stale_scratch(temp: &Path) {
    let Ok(entries) = std::fs::read_dir(temp) else {
        return;
    };
    let me = std::process::id();
    for entry in entries.flatten() {
        let Some(pid) = entry.file_name().to_str().and_then(scratch_pid) else {
            continue;
        };
        let is_dir = entry.file_type().is_ok_and(|kind| kind.is_dir());
        if pid != me && is_dir && is_stale(pid, &entry.path()) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

/// The process id in a run's scratch root's name, `cierva-tests-<pid>`; `None` for any other
/// name.
fn scratch_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix("cierva-tests-")?;
    (!rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit()))
        .then(|| rest.parse::<u32>().ok())
        .flatten()
}

/// Whether the scratch root `dir` of process `pid` is stale. On Linux, that process is gone
/// (no `/proc/<pid>`) and the root was last changed over an hour ago: a run in another PID
/// namespace that shares the temporary folder is invisible in `/proc`, and a root a run is
/// still filling keeps changing. Elsewhere (or without `/proc`), the root was last changed over
/// a day ago.
fn is_stale(pid: u32, dir: &Path) -> bool {
    let older_than = |hours: u64| {
        std::fs::metadata(dir)
            .and_then(|meta| meta.modified())
            .ok()
            .and_then(|modified| modified.elapsed().ok())
            .is_some_and(|age| age > std::time::Duration::from_secs(hours * 60 * 60))
    };
    if cfg!(target_os = "linux") && Path::new("/proc/self").exists() {
        return !Path::new("/proc").join(pid.to_string()).exists() && older_than(1);
    }
    older_than(24)
}

/// Loads every fixture in `dir` with `load` and returns what went wrong (empty when every
/// fixture gets its error, at its line, with a column, starting with the file's path).
pub fn check_fixtures<T>(
    dir: &Path,
    at_least: usize,
    load: impl Fn(&Path) -> Result<T, InputError> + std::panic::RefUnwindSafe,
) -> Vec<String> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    files.sort();
    assert!(
        files.len() >= at_least,
        "the fixtures in {} are missing",
        dir.display()
    );
    let mut problems = Vec::new();
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap();
        let header = |key: &str| {
            src.lines()
                .find_map(|l| l.strip_prefix(&format!("# {key}: ")))
                .unwrap_or_else(|| panic!("{} has no `# {key}:` header", f.display()))
                .to_string()
        };
        let (want, line) = (header("error"), header("line").parse::<usize>().unwrap());
        match std::panic::catch_unwind(|| load(f)) {
            Err(_) => problems.push(format!("{}: panicked", f.display())),
            Ok(Ok(_)) => problems.push(format!("{}: loaded without error", f.display())),
            Ok(Err(e)) => {
                let msg = e.to_string();
                if !msg.contains(&want)
                    || e.line != Some(line)
                    || e.column.is_none()
                    || !msg.starts_with(&f.display().to_string())
                {
                    problems.push(format!(
                        "{}:\n  got      {msg}\n  (line {:?}, column {:?})\n  expected `{want}` at line {line}",
                        f.file_name().unwrap().to_string_lossy(),
                        e.line,
                        e.column
                    ));
                }
            }
        }
    }
    problems
}

/// Writes `dir/secret.yaml`, a corrections file for the VPM M16 that a known-answer test keeps
/// to itself (`corrections`: name and value, in order; `title` and `source` say whose), and
/// returns its path.
pub fn hidden_corrections(
    dir: &Path,
    corrections: &[(String, f64)],
    title: &str,
    source: &str,
) -> std::path::PathBuf {
    let secret = dir.join("secret.yaml");
    let list: String = corrections
        .iter()
        .map(|(k, v)| format!("  {k}: {v}\n"))
        .collect();
    std::fs::write(
        &secret,
        format!("id: secret\ntitle: {title}\napplies_to:\n  aircraft: vpm-m16\ncorrections:\n{list}provenance:\n  source: \"{source}\"\n"),
    )
    .unwrap();
    secret
}

/// `cierva synth-flight` of the VPM M16 flying a sweep of `control` with `corrections`
/// (`--airspeed-mph`, `--amplitude-percent`, `--turbulence-m-s` and `--seed` as written),
/// written to `output`: the exit code, stdout and stderr.
pub fn synth_sweep(
    output: &Path,
    control: &str,
    airspeed_mph: &str,
    amplitude_percent: &str,
    turbulence_m_s: &str,
    seed: &str,
    corrections: &Path,
) -> (i32, String, String) {
    cierva(&[
        "synth-flight",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        airspeed_mph,
        "--manoeuvre",
        "sweep",
        "--control",
        control,
        "--amplitude-percent",
        amplitude_percent,
        "--turbulence-m-s",
        turbulence_m_s,
        "--seed",
        seed,
        "--corrections",
        corrections.to_str().unwrap(),
        "--output",
        output.to_str().unwrap(),
    ])
}

/// The README example's record, written into `dir`: the VPM M16 flying a 60 mph stick sweep
/// (6 %, 0.268 m/s turbulence, seed 60) with the hub factor at 0.55 and the profile drag at 1.3
/// times its tabulated value, both hidden in `secret.yaml`.
pub fn readme_record(dir: &Path) -> std::path::PathBuf {
    let secret = hidden_corrections(
        dir,
        &[
            ("hub_aoa_factor".into(), 0.55),
            ("profile_drag_scale".into(), 1.3),
        ],
        "the test's corrections",
        "test: chosen by the known-answer test",
    );
    let record = dir.join("lon-60.csv");
    let (code, stdout, stderr) = synth_sweep(&record, "eta_s", "60", "6", "0.268", "60", &secret);
    assert_eq!(code, 0, "{stdout}{stderr}");
    record
}

/// `cierva retune` of the uncorrected VPM M16 from `records` for the hub factor and the
/// profile-drag scale (the known-answer tests' pair), `extra` arguments added, writing
/// `retuned.yaml` and `retuned.md` into `dir`, without revalidating, as JSON: the exit code,
/// stdout and stderr.
pub fn retune_hub_and_drag(dir: &Path, records: &[&Path], extra: &[&str]) -> (i32, String, String) {
    retune_corrections(
        dir,
        records,
        &["hub_aoa_factor", "profile_drag_scale"],
        extra,
    )
}

/// `cierva retune` of the uncorrected VPM M16 from `records` for the corrections `fit`, as
/// [`retune_hub_and_drag`] does for its pair.
pub fn retune_corrections(
    dir: &Path,
    records: &[&Path],
    fit: &[&str],
    extra: &[&str],
) -> (i32, String, String) {
    let (output, report) = (dir.join("retuned.yaml"), dir.join("retuned.md"));
    let paths: Vec<&str> = records.iter().map(|p| p.to_str().unwrap()).collect();
    let mut args = vec!["retune", "aircraft/vpm-m16.yaml", "--records"];
    args.extend(paths);
    args.push("--fit");
    args.extend(fit);
    args.extend(extra);
    args.extend([
        "--no-validate",
        "--format",
        "json",
        "--output",
        output.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    cierva(&args)
}

/// A new suite in `dir` (emptied first): its marker and the repository's shared tolerances in
/// `cases/`, for a test to write its cases beside.
pub fn new_suite(dir: &Path) {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir.join("cases")).unwrap();
    std::fs::write(dir.join("cierva.toml"), "format_version = 1\n").unwrap();
    std::fs::copy(
        repo_root().join("cases/tolerances.yaml"),
        dir.join("cases/tolerances.yaml"),
    )
    .unwrap();
}

/// SplitMix64 (Steele, Lea and Flood 2014): the seeded draws of the known-answer trials and
/// synthetic calibrations.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// A uniform draw on [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform draw on [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }

    /// A standard normal draw (Box-Muller).
    pub fn normal(&mut self) -> f64 {
        let (u, v) = (self.next().max(1e-300), self.next());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// The sweep of stale scratch folders reads a pid only from a run's own root's name, never
/// another tool's (`scripts/retune-trials`' random suffix may be all digits).
#[test]
fn scratch_sweeps_only_its_own_names() {
    assert_eq!(scratch_pid("cierva-tests-4242"), Some(4242));
    for other in [
        "cierva-retune-trials-12345678",
        "cierva-retune-trials-ab12cd34",
        "cierva-tests-x42",
        "cierva-tests-",
        "cierva-tests-42-1",
        "cierva-tests-99999999999",
        "cierva-ident-4242",
        "other-tests-4242",
    ] {
        assert_eq!(scratch_pid(other), None, "{other}");
    }
}
