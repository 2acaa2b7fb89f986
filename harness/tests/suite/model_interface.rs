//! The model interface (issue 49): a model declares its parameters, every request carries
//! values for any of them, and a study (`cierva sensitivity`) runs on any model that declares
//! them, cierva's own aircraft and another simulation alike.
//!
//! The known answer: a model behind protocol `cierva-external/2` whose trim pitch is
//! `3 + pitch_offset_deg` and whose `M_q` is `-1.2 * m_q_scale`, so that the study's
//! derivatives are 1 and -1.2, the cross terms 0, and the change that brings `M_q` to its bound
//! is known in closed form.

use super::common::{cierva_in, repo_root};
use cierva_harness::external::{FlightModel as _, Request};
use cierva_harness::inputs::condition::{Loading, TrimRequest};
use std::path::{Path, PathBuf};

/// The test model (Python 3, standard library): `describe`, trim and linear model, with two
/// declared parameters; it refuses a parameter it does not declare, as a model should. Run with
/// a request file's path it answers once (one-shot); run with `--serve` it answers JSON lines
/// on stdin (persistent mode), and notes each start in `starts.txt`. The tests put code at
/// `# HOOK` to make it misbehave.
const MODEL: &str = r#"import json, sys
PROTOCOL = 'cierva-external/2'
def answer(r):
    assert r['protocol'] == PROTOCOL, r['protocol']
    if r['compute'] == 'describe':
        return {'describe': {
            'computes': ['trim', 'linear_model'],
            'states': ['u', 'w', 'q', 'theta'],
            'controls': ['eta_s'],
            'parameters': [
                {'name': 'pitch_offset_deg', 'unit': 'deg', 'meaning': 'a pitch datum offset',
                 'nominal': 0.0,
                 'range': {'lower': -2.0, 'upper': 2.0, 'source': 'the test model own'}},
                {'name': 'm_q_scale', 'unit': '1', 'meaning': 'a pitch damping factor',
                 'nominal': 1.0,
                 'range': {'lower': 0.5, 'upper': 1.5, 'source': 'the test model own'}}]}}
    p = {'pitch_offset_deg': 0.0, 'm_q_scale': 1.0}
    for k, v in r['parameters'].items():
        if k not in p:
            raise ValueError('unknown parameter ' + k)
        p[k] = v
    v = r['condition']['airspeed_mph']
    # HOOK
    if r['compute'] == 'trim':
        return {'trim': {'pitch_deg': 3.0 + p['pitch_offset_deg'],
                         'stick_longitudinal_percent': 80.0 - 0.5 * v}}
    if r['compute'] == 'linear_model':
        return {'linear_model': {'states': ['u', 'w', 'q', 'theta'], 'controls': ['eta_s'],
            'a': [[-0.05, 0.1, 0.0, -9.81], [-0.3, -0.8, 30.0, 0.0],
                  [0.01, -0.05, -1.2 * p['m_q_scale'], 0.0], [0.0, 0.0, 1.0, 0.0]],
            'b': [[0.0], [0.1], [-0.02], [0.0]]}}
    raise ValueError('no ' + r['compute'])
if sys.argv[1:] == ['--serve']:
    open('starts.txt', 'a').write('start\n')
    for line in sys.stdin:
        r = json.loads(line)
        try:
            body = answer(r)
        except ValueError as e:
            body = {'error': str(e)}
        body['protocol'] = PROTOCOL
        body['id'] = r['id']
        sys.stdout.write(json.dumps(body) + '\n')
        sys.stdout.flush()
else:
    r = json.load(open(sys.argv[1]))
    try:
        body = answer(r)
    except ValueError as e:
        sys.stderr.write(str(e) + '\n')
        sys.exit(4)
    body['protocol'] = PROTOCOL
    open(r['response'], 'w').write(json.dumps(body))
"#;

/// A suite in a fresh folder with the test model and a case on it: `M_q` against
/// [-1.0, -0.9] (outside: the model gives -1.2) and the trim pitch against 3 +- 0.5 (inside).
fn suite(name: &str, protocol: &str) -> PathBuf {
    suite_in(name, protocol, false)
}

/// [`suite`], the model run in persistent mode where `persistent` says so.
fn suite_in(name: &str, protocol: &str, persistent: bool) -> PathBuf {
    let dir = crate::common::scratch(&format!("model-interface-{name}"));
    super::common::new_suite(&dir);
    std::fs::write(dir.join("cases/model.py"), MODEL).unwrap();
    std::fs::write(
        dir.join("cases/model.yaml"),
        format!(
            "id: model\ntitle: a model that declares its parameters\nclass: regression\n\
             provenance: {{source: a test of harness/tests/suite/model_interface.rs}}\n\
             model:\n  external:\n    command: [python3, model.py{serve}]\n    protocol: {protocol}\n\
             \x20   persistent: {persistent}\n\
             \x20   timeout_s: 30\n    mass_kg: 400.0\n\
             tolerances:\n  band:\n    absolute: 0.05\n    reason: the test's own\n\
             \x20 pitch:\n    absolute: 0.5\n    reason: the test's own\n\
             checks:\n  - id: damping\n    kind: derivative\n    derivative: M_q\n\
             \x20   condition: {{airspeed_mph: 60.0}}\n\
             \x20   expect:\n      value: {{value: -0.95, tolerance: band}}\n\
             \x20   expected_failure: the test model's M_q is -1.2, outside on purpose\n\
             \x20 - id: pitch\n    kind: trim\n    condition: {{airspeed_mph: 60.0}}\n\
             \x20   expect:\n      pitch_deg: {{value: 3.0, tolerance: pitch}}\n",
            serve = if persistent { ", --serve" } else { "" },
        ),
    )
    .unwrap();
    dir
}

#[test]
fn sensitivity_runs_on_an_external_model_that_declares_parameters() {
    super::external::require_python3();
    let dir = suite("sensitivity", "cierva-external/2");
    let (code, out, err) = cierva_in(
        &dir,
        &[
            "sensitivity",
            "--case",
            "cases/model.yaml",
            "--format",
            "json",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 0, "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    // The declared parameters, both ranged, by name.
    let names: Vec<&str> = v["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["m_q_scale", "pitch_offset_deg"]);
    assert_eq!(v["parameters"][0]["range"]["source"], "the test model own");
    let row = |q: &str| {
        v["rows"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["quantity"] == q)
            .unwrap_or_else(|| panic!("no row {q}: {v}"))
            .clone()
    };
    let effect = |r: &serde_json::Value, p: &str| {
        r["effects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["parameter"] == p)
            .unwrap()
            .clone()
    };
    let f = |x: &serde_json::Value| x.as_f64().unwrap();
    // The central differences of linear functions are exact but for the rounding of the
    // model's printed JSON (17 significant digits) over a step of 0.02: 1e-12 covers it.
    let close = |got: f64, want: f64| (got - want).abs() < 1e-12;
    let m_q = row("M_q");
    assert!(close(f(&m_q["value"]), -1.2), "{m_q}");
    assert_eq!(m_q["inside"], false);
    let scale = effect(&m_q, "m_q_scale");
    assert!(close(f(&scale["derivative"]), -1.2), "{scale}");
    // (-1.0 - -1.2) / -1.2: the scale that brings M_q to -1.0.
    assert!(close(f(&scale["needed_value"]), 1.0 - 0.2 / 1.2), "{scale}");
    assert_eq!(scale["plausible"], true);
    assert!(close(
        f(&effect(&m_q, "pitch_offset_deg")["derivative"]),
        0.0
    ));
    let pitch = row("pitch_deg");
    assert_eq!(pitch["inside"], true);
    assert!(close(
        f(&effect(&pitch, "pitch_offset_deg")["derivative"]),
        1.0
    ));
    assert!(close(f(&effect(&pitch, "m_q_scale")["derivative"]), 0.0));
}

#[test]
fn a_parameter_the_model_does_not_declare_or_a_value_outside_its_range_is_refused() {
    super::external::require_python3();
    let dir = suite("refused", "cierva-external/2");
    let (code, out, err) = cierva_in(
        &dir,
        &[
            "sensitivity",
            "--case",
            "cases/model.yaml",
            "--parameters",
            "m_q_scal",
        ],
    );
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("`m_q_scal` is not a parameter the command `python3 model.py` declares (did you mean `m_q_scale`?)"),
        "{err}"
    );
    // Through the interface: a value outside the declared range is refused before the model
    // runs, and an undeclared name likewise.
    let case = cierva_harness::suite::case::load(&dir.join("cases/model.yaml")).unwrap();
    let (model, loading) = cierva_harness::checks::flight_model(&case.subject).unwrap();
    let at = Request::at(TrimRequest::level(60.0), loading);
    let e = model.trim(&at.clone().with("m_q_scale", 3.0)).unwrap_err();
    assert!(
        e.contains("`m_q_scale` = 3 1 is outside the range the command `python3 model.py` declares for it, [0.5, 1.5] (the test model own)"),
        "{e}"
    );
    let e = model.trim(&at.clone().with("nope", 1.0)).unwrap_err();
    assert!(e.contains("`nope` is not a parameter"), "{e}");
    // A declared value inside its range reaches the model.
    let q = model.trim(&at.with("pitch_offset_deg", 1.5)).unwrap();
    assert_eq!(q.iter().find(|(n, _)| *n == "pitch_deg").unwrap().1, 4.5);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_first_version_model_declares_nothing_and_a_bad_describe_is_an_error() {
    super::external::require_python3();
    // The same case on a command that speaks /1: it validates, and a study has nothing to move.
    let dir = suite("v1", "cierva-external/1");
    std::fs::write(
        dir.join("cases/model.py"),
        MODEL.replace("cierva-external/2", "cierva-external/1"),
    )
    .unwrap();
    let (code, out, err) = cierva_in(&dir, &["sensitivity", "--case", "cases/model.yaml"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(err.contains("declares no parameters to move"), "{err}");
    // A describe that does not parse: a located reason, exit 2.
    let dir2 = suite("bad-describe", "cierva-external/2");
    std::fs::write(
        dir2.join("cases/model.py"),
        MODEL.replace("'nominal': 1.0,", "'nominal': 9.0,"),
    )
    .unwrap();
    let (code, out, err) = cierva_in(&dir2, &["sensitivity", "--case", "cases/model.yaml"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("(describe request): its response `describe.parameters[1]` (`m_q_scale`): its nominal value 9 is outside its range [0.5, 1.5]"),
        "{err}"
    );
    // And a protocol cierva does not speak is a located input error.
    let text = std::fs::read_to_string(dir2.join("cases/model.yaml")).unwrap();
    std::fs::write(
        dir2.join("cases/model.yaml"),
        text.replace("cierva-external/2", "cierva-external/3"),
    )
    .unwrap();
    let e = cierva_harness::suite::case::load(&dir2.join("cases/model.yaml")).unwrap_err();
    assert!(
        e.to_string()
            .contains("`cierva-external/3` is not a protocol cierva speaks"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&dir2);
}

#[test]
fn the_models_checks_validate_through_the_second_version() {
    super::external::require_python3();
    let dir = suite("validate", "cierva-external/2");
    let (code, out, err) = cierva_in(&dir, &["validate", "--no-report"]);
    let _ = std::fs::remove_dir_all(&dir);
    // The pitch passes; M_q is the expected failure it was written as, with no record of its
    // discrepancy yet (a new suite's first run: the discrepancy is reported as moved, not an
    // error of the model).
    let row = |check: &str| {
        out.lines()
            .find(|l| l.starts_with("model ") && l.contains(&format!(" {check} ")))
            .unwrap_or_else(|| panic!("no row for {check}:\n{out}{err}"))
            .to_string()
    };
    assert!(row("pitch").contains(" pass "), "{out}");
    assert!(row("damping").contains(" MOVED "), "{out}");
    assert!(!out.contains("ERROR"), "{out}{err}");
    assert_eq!(code, 1, "{out}{err}");
}

#[test]
fn cierva_aircraft_declares_the_files_parameters_with_its_ranges() {
    let file =
        cierva_harness::inputs::aircraft::load(&repo_root().join("aircraft/vpm-m16.yaml")).unwrap();
    let model = cierva_harness::external::CiervaAircraft::new(&file);
    let declared = model.parameters().unwrap();
    let fin = declared
        .iter()
        .find(|p| p.name == "airframe.fin.area_m2")
        .expect("the fin area");
    assert_eq!(fin.unit, "m^2");
    assert_eq!(
        Some(fin.nominal),
        cierva_harness::inputs::parameters::parameter(&file.aircraft, "airframe.fin.area_m2")
    );
    assert_eq!(fin.range.as_ref(), file.ranges.get("airframe.fin.area_m2"));
    // Every ranged parameter of the file is declared with its range.
    for (name, range) in &file.ranges {
        let p = declared.iter().find(|p| &p.name == name).unwrap();
        assert_eq!(p.range.as_ref(), Some(range), "{name}");
    }
    // A value outside the file's range is refused before anything runs.
    let loading = Loading {
        mass_kg: Some(450.0),
        density_altitude_ft: 0.0,
    };
    let r = file.ranges.get("airframe.fin.area_m2").unwrap();
    let e = model
        .trim(
            &Request::at(TrimRequest::level(70.0), loading)
                .with("airframe.fin.area_m2", r.upper * 2.0),
        )
        .unwrap_err();
    assert!(e.contains("is outside the range"), "{e}");
}

/// The `cierva` run's check rows (`case check result ...`) of `out`, by check.
fn rows(out: &str) -> Vec<String> {
    out.lines()
        .filter(|l| l.starts_with("model "))
        .map(str::to_string)
        .collect()
}

#[test]
fn persistent_mode_answers_as_one_shot_does_from_one_process_a_core() {
    super::external::require_python3();
    let one = suite("one-shot", "cierva-external/2");
    let many = suite_in("persistent", "cierva-external/2", true);
    let study = |dir: &PathBuf| {
        let (code, out, err) = cierva_in(
            dir,
            &[
                "sensitivity",
                "--case",
                "cases/model.yaml",
                "--format",
                "json",
            ],
        );
        assert_eq!(code, 0, "{out}{err}");
        let mut v: serde_json::Value = serde_json::from_str(&out).unwrap();
        // The model in words names its command, which differs by `--serve`.
        v["model"] = serde_json::Value::Null;
        v
    };
    assert_eq!(study(&one), study(&many));
    let validate = |dir: &PathBuf| {
        let (code, out, err) = cierva_in(dir, &["validate", "--no-report"]);
        assert_eq!(code, 1, "{out}{err}");
        rows(&out)
    };
    assert_eq!(validate(&one), validate(&many));
    // Two runs of cierva, each with at most one process a core.
    let starts = std::fs::read_to_string(many.join("cases/starts.txt")).unwrap();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let n = starts.lines().count();
    assert!(
        (2..=2 * cores).contains(&n),
        "{n} processes started for two runs"
    );
    let _ = std::fs::remove_dir_all(&one);
    let _ = std::fs::remove_dir_all(&many);
}

#[test]
fn a_persistent_model_that_dies_hangs_floods_or_chatters_is_an_error_for_that_request() {
    super::external::require_python3();
    // Each: what the model does on its linear-model request (its trims are answered), and what
    // the damping check's error must say.
    let cases: [(&str, &str, &[&str]); 4] = [
        (
            "dies",
            "if r['compute'] == 'linear_model': sys.exit(7)",
            &[
                "its stdout closed",
                "exited 7",
                "its earlier answers stand, the next request starts another",
            ],
        ),
        (
            "hangs",
            "if r['compute'] == 'linear_model': __import__('time').sleep(60)",
            &["timed out after 1 s (`timeout_s`) on this request and was killed"],
        ),
        (
            "floods",
            "if r['compute'] == 'linear_model': sys.stdout.write('x' * 5000000)",
            &["was killed: its answer passed 1048576 bytes as it was read"],
        ),
        (
            "chatters",
            "if r['compute'] == 'linear_model': print('solving...')",
            &["its answer line is not JSON", "`solving...`"],
        ),
    ];
    let mut problems = Vec::new();
    for (name, hook, want) in cases {
        let dir = suite_in(name, "cierva-external/2", true);
        std::fs::write(dir.join("cases/model.py"), MODEL.replace("# HOOK", hook)).unwrap();
        let yaml = std::fs::read_to_string(dir.join("cases/model.yaml")).unwrap();
        std::fs::write(
            dir.join("cases/model.yaml"),
            yaml.replace("timeout_s: 30", "timeout_s: 1"),
        )
        .unwrap();
        let started = std::time::Instant::now();
        let (code, out, err) = cierva_in(&dir, &["validate", "--no-report"]);
        let all = format!("{out}{err}");
        if code != 2 {
            problems.push(format!("{name}: exit {code}, not 2:\n{all}"));
        }
        let rows = rows(&out);
        if !rows
            .iter()
            .any(|r| r.contains(" pitch ") && r.contains(" pass "))
        {
            problems.push(format!("{name}: the trim was not answered:\n{all}"));
        }
        for w in want {
            if !all.contains(w) {
                problems.push(format!("{name}: no `{w}` in:\n{all}"));
            }
        }
        // A hang is killed at its 1 s timeout, not the 60 s it would sleep.
        if started.elapsed().as_secs_f64() > 30.0 {
            problems.push(format!(
                "{name}: took {:.0} s",
                started.elapsed().as_secs_f64()
            ));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(problems.is_empty(), "{}", problems.join("\n\n"));
}

#[test]
fn persistent_mode_needs_the_second_version() {
    let dir = suite_in("persistent-v1", "cierva-external/1", true);
    let e = cierva_harness::suite::case::load(&dir.join("cases/model.yaml")).unwrap_err();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        e.to_string().contains(
            "field `model.external.persistent`: persistent mode is protocol `cierva-external/2`'s"
        ),
        "{e}"
    );
}

/// The repository's cases whose subject is cierva's VPM M16, asked again through the protocol:
/// their `model` replaced by `cierva serve` of the same aircraft file in persistent mode. The
/// kinds they hold (derivative, BCAR, trim sweep) and the sensitivity study the Table 2 case
/// asks for.
const MIRRORED: [&str; 4] = [
    "cases/cierva-table2-vpm-m16-70mph-min-weight.yaml",
    "cases/vpm-m16-trim-max-weight.yaml",
    "cases/vpm-m16-stability-min-weight.yaml",
    "cases/seed000-synthetic-xu-zw-vpm-m16.yaml",
];

/// How far a value through the protocol may be from the built-in one, relative: the issue's
/// 1e-9 (JSON carries every f64 to the bit, so the two are the same numbers unless a path
/// differs).
const THROUGH_THE_PROTOCOL: f64 = 1e-9;

/// A temporary suite holding [`MIRRORED`] with their model served by `cierva serve`, and the
/// repository's `aircraft/` and `flight-refs/` linked beside its cases (their relative paths).
/// One folder a call: tests that run at once in one process each get their own (one folder a
/// process let one test's set-up remove another's records mid-run).
fn mirrored_suite() -> PathBuf {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = crate::common::scratch(&format!("as-external-{call}"));
    super::common::new_suite(&dir);
    for linked in ["aircraft", "flight-refs"] {
        std::os::unix::fs::symlink(repo_root().join(linked), dir.join(linked)).unwrap();
    }
    for case in MIRRORED {
        let text = std::fs::read_to_string(repo_root().join(case)).unwrap();
        let mut v: serde_yaml::Value = serde_yaml::from_str(&text).unwrap();
        let a = v["model"]["aircraft"].clone();
        let file = a["file"].as_str().unwrap();
        let mut external = serde_yaml::Mapping::new();
        external.insert(
            "command".into(),
            serde_yaml::to_value(["cierva", "serve", file]).unwrap(),
        );
        external.insert("protocol".into(), "cierva-external/2".into());
        external.insert("persistent".into(), true.into());
        external.insert("timeout_s".into(), 600.into());
        external.insert("mass_kg".into(), a["mass_kg"].clone());
        external.insert(
            "density_altitude_ft".into(),
            a["density_altitude_ft"].clone(),
        );
        let mut model = serde_yaml::Mapping::new();
        model.insert("external".into(), serde_yaml::Value::Mapping(external));
        v["model"] = serde_yaml::Value::Mapping(model);
        let name = std::path::Path::new(case).file_name().unwrap();
        std::fs::write(
            dir.join("cases").join(name),
            serde_yaml::to_string(&v).unwrap(),
        )
        .unwrap();
    }
    dir
}

/// Runs `cierva` in `dir` with the test build's `cierva` first on PATH (the cases' command).
fn cierva_on_path(dir: &std::path::Path, args: &[&str]) -> (i32, String, String) {
    let bin = std::path::Path::new(env!("CARGO_BIN_EXE_cierva"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = std::process::Command::new(bin)
        .args(args)
        .current_dir(dir)
        .env("PATH", path)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Each check's quantities of a `validate --format json` run: (case, check, quantity) ->
/// (value, pass).
fn quantities(json: &str) -> std::collections::BTreeMap<(String, String, String), (f64, bool)> {
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    let mut out = std::collections::BTreeMap::new();
    for r in v["results"].as_array().unwrap() {
        assert!(r["error"].is_null(), "{r}");
        for q in r["quantities"].as_array().unwrap() {
            out.insert(
                (
                    r["case"].as_str().unwrap().to_string(),
                    r["check"].as_str().unwrap().to_string(),
                    q["quantity"].as_str().unwrap().to_string(),
                ),
                (q["value"].as_f64().unwrap(), q["pass"].as_bool().unwrap()),
            );
        }
    }
    out
}

/// The same checks' quantities built in and through the protocol: every value within
/// [`THROUGH_THE_PROTOCOL`], every pass the same.
fn same_quantities(
    built_in: &std::collections::BTreeMap<(String, String, String), (f64, bool)>,
    served: &std::collections::BTreeMap<(String, String, String), (f64, bool)>,
    err: &str,
) {
    assert_eq!(
        built_in.keys().collect::<Vec<_>>(),
        served.keys().collect::<Vec<_>>(),
        "{err}"
    );
    for (key, (value, pass)) in built_in {
        let (v, p) = served[key];
        assert!(
            close(*value, v) && *pass == p,
            "{key:?}: built in {value} ({pass}), through the protocol {v} ({p})"
        );
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= THROUGH_THE_PROTOCOL * a.abs().max(b.abs()).max(1e-300)
}

#[test]
#[ignore = "slow (about 8 s in a release test run since the VPM M16's blades feel the hub's angular acceleration, 2026-11-30; out of the cold `cargo test`, held under 5 minutes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn cierva_served_through_the_protocol_gives_the_built_in_numbers() {
    let dir = mirrored_suite();
    let mut args = vec!["validate", "--no-report", "--format", "json"];
    let built_in_cases: Vec<String> = MIRRORED
        .iter()
        .map(|c| repo_root().join(c).display().to_string())
        .collect();
    let mut built_in_args = args.clone();
    built_in_args.extend(built_in_cases.iter().map(String::as_str));
    let (_, built_in, err) = cierva_on_path(&repo_root(), &built_in_args);
    let built_in = quantities(&built_in);
    assert!(!built_in.is_empty(), "{err}");
    args.push("cases");
    let (_, served, err) = cierva_on_path(&dir, &args);
    let served = quantities(&served);
    same_quantities(&built_in, &served, &err);
    // The sensitivity study of the Table 2 case, on three of its parameters.
    let study = |dir: &std::path::Path, case: &str| {
        let (code, out, err) = cierva_on_path(
            dir,
            &[
                "sensitivity",
                "--case",
                case,
                "--parameters",
                "mass.ixx_kg_m2,airframe.fin.area_m2,controls.shaft_roll_deg.travel",
                "--format",
                "json",
            ],
        );
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        v
    };
    let a = study(&repo_root(), MIRRORED[0]);
    let b = study(&dir, MIRRORED[0]);
    for (ra, rb) in a["rows"]
        .as_array()
        .unwrap()
        .iter()
        .zip(b["rows"].as_array().unwrap())
    {
        assert_eq!(ra["quantity"], rb["quantity"]);
        for (ea, eb) in ra["effects"]
            .as_array()
            .unwrap()
            .iter()
            .zip(rb["effects"].as_array().unwrap())
        {
            let (x, y) = (
                ea["derivative"].as_f64().unwrap(),
                eb["derivative"].as_f64().unwrap(),
            );
            assert!(
                close(x, y),
                "{} by {}: {x} and {y}",
                ra["quantity"],
                ea["parameter"]
            );
            assert_eq!(ea["plausible"], eb["plausible"]);
        }
    }
    assert_eq!(a["parameters"], b["parameters"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// How near a 64-sample propagation's mean and standard deviation come to the exact ones here,
/// relative to the input's own spread: Owen-scrambled Sobol' points integrate a linear function
/// of one uniform input to well under 1 % of its spread at 64 points (A and B: 128 draws).
const QMC_64: f64 = 0.02;

#[test]
fn uncertainty_propagates_an_external_models_declared_ranges() {
    super::external::require_python3();
    let dir = suite_in("uncertainty", "cierva-external/2", true);
    let (code, out, err) = cierva_in(
        &dir,
        &[
            "uncertainty",
            "cases/model.yaml",
            "--samples",
            "64",
            "--seed",
            "0",
            "--format",
            "json",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 0, "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let case = &v["cases"][0];
    let names: Vec<&str> = case["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["m_q_scale", "pitch_offset_deg"]);
    // Saltelli's design, samples x (inputs + 2) points, and the nominal one.
    assert_eq!(case["evaluations"], 64 * 4 + 1);
    assert_eq!(case["failed_points"], 0);
    let result = |check: &str| {
        v["results"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["check"] == check)
            .unwrap_or_else(|| panic!("no {check}: {v}"))
            .clone()
    };
    let f = |x: &serde_json::Value| x.as_f64().unwrap();
    // pitch = 3 + offset, offset uniform on [-2, 2]: mean 3, standard deviation 4 / sqrt(12),
    // all of its variance from the offset. M_q = -1.2 scale, scale uniform on [0.5, 1.5]: mean
    // -1.2, standard deviation 1.2 / sqrt(12), all from the scale.
    for (check, mean, sd, input) in [
        ("pitch", 3.0, 4.0 / 12f64.sqrt(), "pitch_offset_deg"),
        ("damping", -1.2, 1.2 / 12f64.sqrt(), "m_q_scale"),
    ] {
        let r = result(check);
        assert!(
            (f(&r["mean"]) - mean).abs() < QMC_64 * sd,
            "{check}: mean {} against {mean}",
            r["mean"]
        );
        assert!(
            (f(&r["u_input"]) - sd).abs() < QMC_64 * sd,
            "{check}: u_input {} against {sd}",
            r["u_input"]
        );
        let top = &r["contributors"][0];
        assert_eq!(top["input"], input, "{r}");
        assert!((f(&top["total"]) - 1.0).abs() < 0.05, "{r}");
        let other = &r["contributors"][1];
        assert!(f(&other["total"]).abs() < 0.05, "{r}");
    }
}

/// The test model with a discretisation parameter, `pitch step` (`h = 0.2 / 2^level`, order
/// 2), whose trim pitch carries the error `0.4 h^2`: a grid study through the protocol's
/// `refine` gets 3.016, 3.004 and 3.001, the observed order 2 and Roache's index
/// `1.25 x 0.012 x 4/3 = 0.02` exactly.
fn refinable_model(refinements: &str) -> String {
    MODEL
        .replace(
            "'controls': ['eta_s'],\n            'parameters': [",
            &format!("'controls': ['eta_s'],\n            'refinements': {refinements},\n            'parameters': ["),
        )
        .replace(
            "    # HOOK",
            "    h = 0.2 / 2 ** (r.get('refine') or {}).get('level', 0)",
        )
        .replace(
            "3.0 + p['pitch_offset_deg']",
            "3.0 + p['pitch_offset_deg'] + 0.4 * h * h",
        )
}

#[test]
fn a_model_behind_the_protocol_gets_a_grid_study_from_its_declared_refinements() {
    super::external::require_python3();
    let dir = suite("grid-study", "cierva-external/2");
    let declared = "[{'name': 'pitch step', 'ratio': 2, 'formal_order': 2, \
                    'words': ['0.2 -> 0.1', '0.1 -> 0.05']}]";
    std::fs::write(dir.join("cases/model.py"), refinable_model(declared)).unwrap();
    let (code, out, err) = cierva_in(
        &dir,
        &[
            "uncertainty",
            "cases/model.yaml",
            "--samples",
            "8",
            "--format",
            "json",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let pitch = v["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["check"] == "pitch")
        .unwrap_or_else(|| panic!("no pitch: {v}"))
        .clone();
    let term = &pitch["u_num_terms"][0];
    assert_eq!(term["parameter"], "pitch step", "{pitch}");
    let values: Vec<f64> = term["values"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    for (got, want) in values.iter().zip([3.016, 3.004, 3.001]) {
        assert!((got - want).abs() < 1e-12, "{values:?}");
    }
    assert_eq!(values.len(), 3, "{values:?}");
    assert!(
        (term["observed_order"].as_f64().unwrap() - 2.0).abs() < 1e-9,
        "{term}"
    );
    assert!(
        (pitch["u_num"].as_f64().unwrap() - 0.02).abs() < 1e-9,
        "{pitch}"
    );
    // A model that refines nothing through a request it does not know: M_q does not depend on
    // the step, so its index is 0, not missing.
    let damping = v["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["check"] == "damping")
        .unwrap()
        .clone();
    assert_eq!(damping["u_num"].as_f64(), Some(0.0), "{damping}");
    // A declared refinement that is not one: a located reason, exit 2.
    std::fs::write(
        dir.join("cases/model.py"),
        refinable_model("[{'name': 'pitch step', 'ratio': 1, 'formal_order': 2}]"),
    )
    .unwrap();
    let (code, out, err) = cierva_in(&dir, &["uncertainty", "cases/model.yaml", "--samples", "8"]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains(
            "`describe.refinements[0]` (`pitch step`): its `ratio` 1 is not a refinement ratio"
        ),
        "{err}"
    );
}

/// `--target-se` doubles the design until every Sobol' index's standard error is at most the
/// target, and stops at the first size that reaches it (issue 51, item 4): on the test model
/// with its pitch made `3 + offset + 2 (scale - 1)` (two inputs sharing the variance, 4:1), the
/// size it stops at resolves every index, and half of it does not.
#[test]
fn target_se_grows_the_design_until_the_indices_are_resolved() {
    super::external::require_python3();
    let dir = suite_in("target-se", "cierva-external/2", true);
    std::fs::write(
        dir.join("cases/model.py"),
        MODEL.replace(
            "3.0 + p['pitch_offset_deg']",
            "3.0 + p['pitch_offset_deg'] + 2.0 * (p['m_q_scale'] - 1.0)",
        ),
    )
    .unwrap();
    let run = |args: &[&str]| {
        let mut all = vec!["uncertainty", "cases/model.yaml", "--format", "json"];
        all.extend_from_slice(args);
        let (code, out, err) = cierva_in(&dir, &all);
        assert_eq!(code, 0, "{out}{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    // The largest index standard error of a run's quantities that the inputs move.
    let worst = |v: &serde_json::Value| -> f64 {
        v["results"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|r| r["u_input"].as_f64().unwrap() > 0.0)
            .flat_map(|r| r["contributors"].as_array().unwrap().clone())
            .map(|c| c["total_se"].as_f64().unwrap_or(f64::INFINITY))
            .fold(0.0, f64::max)
    };
    let target = 0.05;
    let grown = run(&["--samples", "8", "--target-se", "0.05"]);
    let n = grown["cases"][0]["samples"].as_u64().unwrap();
    let said = grown["cases"][0]["target_se"].as_str().unwrap().to_string();
    assert!(
        said.starts_with(&format!("reached at {n} base points")),
        "{said}"
    );
    assert!(n > 8 && n.is_power_of_two(), "{n}");
    assert!(worst(&grown) <= target, "{}", worst(&grown));
    let half = run(&["--samples", &(n / 2).to_string()]);
    assert!(worst(&half) > target, "{} at {}", worst(&half), n / 2);
    // A target that is not a standard error is refused before anything runs.
    let (code, _, err) = cierva_in(
        &dir,
        &["uncertainty", "cases/model.yaml", "--target-se", "1.5"],
    );
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--target-se 1.5: give a standard error between 0 and 1"),
        "{err}"
    );
}

/// How far a sampled statistic through the protocol may be from the built-in one, relative:
/// the issue's 1e-9. Each sample's trims start from the nominal aircraft's trim on both paths
/// (the built-in study primes them so; `CiervaAircraft` starts every request with parameter
/// values so), so the two are the same numbers (before 2026-11-28 evening the protocol's
/// trims started cold and this was 1e-6).
const SAMPLED_TRIMS: f64 = 1e-9;

#[test]
#[ignore = "slow reference check (two uncertainty studies of Table 2, about 5 s in a test build, 2026-11-28): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn uncertainty_through_the_protocol_samples_the_built_in_inputs_and_values() {
    let dir = mirrored_suite();
    let run = |dir: &std::path::Path| {
        let (code, out, err) = cierva_on_path(
            dir,
            &[
                "uncertainty",
                MIRRORED[0],
                "--samples",
                "8",
                "--format",
                "json",
            ],
        );
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let (a, b) = (run(&repo_root()), run(&dir));
    let _ = std::fs::remove_dir_all(&dir);
    // The same inputs (the aircraft file's ranged physical parameters, its corrections left at
    // their values), so the same design.
    assert_eq!(a["cases"][0]["inputs"], b["cases"][0]["inputs"]);
    let (ra, rb) = (
        a["results"].as_array().unwrap(),
        b["results"].as_array().unwrap(),
    );
    assert_eq!(ra.len(), rb.len());
    let mut refined = 0;
    for (x, y) in ra.iter().zip(rb) {
        assert_eq!(x["check"], y["check"]);
        let f = |r: &serde_json::Value, k: &str| r[k].as_f64().unwrap();
        assert!(close(f(x, "nominal"), f(y, "nominal")), "{}", x["check"]);
        for k in ["mean", "u_input", "p2_5", "p97_5"] {
            let (p, q) = (f(x, k), f(y, k));
            assert!(
                (p - q).abs() <= SAMPLED_TRIMS * p.abs().max(q.abs()),
                "{} {k}: built in {p}, through the protocol {q}",
                x["check"]
            );
        }
        // The grid study through the protocol's `refine`: the same parameters refined alone
        // to the same levels, so the same indices (before 2026-11-29 a model behind the
        // protocol had no grid study, and `u_num` was 0 there).
        let (p, q) = (f(x, "u_num"), f(y, "u_num"));
        refined += usize::from(p > 0.0);
        assert!(
            close(p, q),
            "{} u_num: built in {p}, through the protocol {q}",
            x["check"]
        );
        assert_eq!(x["u_num_terms"], y["u_num_terms"], "{}", x["check"]);
        assert_eq!(x["verdict"], y["verdict"], "{}", x["check"]);
    }
    assert!(refined > 0, "the built-in grid study moved no quantity");
}

/// A time-history request of protocol `/2` carries the record's first sample of each response
/// (`initial_state`), inline in persistent mode as in a one-shot request file.
#[test]
fn a_time_history_request_carries_the_initial_state() {
    super::external::require_python3();
    let dir = crate::common::scratch("initial");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // Notes the initial state it is given, and answers a still response (every row zero).
    let script = "import json, sys\n\
                  def body(r):\n\
                  \x20   if r['compute'] == 'describe':\n\
                  \x20       return {'describe': {'computes': ['time_history']}}\n\
                  \x20   open('initial.json', 'a').write(json.dumps(r['initial_state']) + '\\n')\n\
                  \x20   n = r['samples']\n\
                  \x20   return {'time_history': {'time_s': [k * r['sample_s'] for k in range(n)], 'theta_deg': [0.0] * n}}\n\
                  if sys.argv[1:] == ['--serve']:\n\
                  \x20   for line in sys.stdin:\n\
                  \x20       r = json.loads(line); b = body(r); b['protocol'] = r['protocol']; b['id'] = r['id']\n\
                  \x20       sys.stdout.write(json.dumps(b) + '\\n'); sys.stdout.flush()\n\
                  else:\n\
                  \x20   r = json.load(open(sys.argv[1])); b = body(r)\n\
                  \x20   if 'time_history' in b:\n\
                  \x20       t = b['time_history']\n\
                  \x20       rows = ['time_s,theta_deg'] + ['%r,%r' % (a, c) for a, c in zip(t['time_s'], t['theta_deg'])]\n\
                  \x20       open(r['response'], 'w').write('\\n'.join(rows) + '\\n')\n\
                  \x20   else:\n\
                  \x20       b['protocol'] = r['protocol']; open(r['response'], 'w').write(json.dumps(b))\n";
    std::fs::write(dir.join("model.py"), script).unwrap();
    let controls = cierva_harness::external::ControlChanges {
        table: cierva_harness::inputs::controls::ControlTable {
            time_s: vec![0.0, 1.0],
            changes: [vec![0.0, 1.0], vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]],
        },
        sample_s: 0.5,
        samples: 2,
        initial_state: [("theta_deg".to_string(), 0.25), ("q_deg_s".into(), -1.5)]
            .into_iter()
            .collect(),
    };
    let at = Request::at(
        TrimRequest::level(70.0),
        Loading {
            mass_kg: None,
            density_altitude_ft: 0.0,
        },
    );
    for persistent in [false, true] {
        let mut command = vec!["python3".to_string(), "model.py".to_string()];
        if persistent {
            command.push("--serve".into());
        }
        let mut model = cierva_harness::external::command::ExternalCommand::speaking(
            command,
            dir.clone(),
            std::time::Duration::from_secs(30),
            cierva_harness::external::command::Protocol::V2,
        );
        if persistent {
            model = model.persistent();
        }
        let flown = model.time_history(&at, &controls).unwrap();
        assert_eq!(flown.time_s, [0.0, 0.5, 1.0]);
    }
    let noted = std::fs::read_to_string(dir.join("initial.json")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let want = r#"{"q_deg_s": -1.5, "theta_deg": 0.25}"#;
    assert_eq!(noted.lines().collect::<Vec<_>>(), [want, want]);
}

/// A command that is not found fails every check the same way: one input error naming them all,
/// and the counts in words ("1 case", issue 50).
#[test]
fn checks_that_fail_alike_are_one_input_error() {
    let dir = suite("not-found", "cierva-external/2");
    let yaml = std::fs::read_to_string(dir.join("cases/model.yaml")).unwrap();
    std::fs::write(
        dir.join("cases/model.yaml"),
        yaml.replace("[python3, model.py]", "[cierva-no-such-model]"),
    )
    .unwrap();
    let (code, out, err) = cierva_in(&dir, &["validate", "--no-report"]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{out}{err}");
    let listed: Vec<&str> = out
        .lines()
        .filter(|l| l.starts_with("error: ") && l.contains("cases/model.yaml"))
        .collect();
    assert_eq!(listed.len(), 1, "{out}");
    assert!(
        listed[0].contains("2 checks (`damping`, `pitch`): the command `cierva-no-such-model`"),
        "{out}"
    );
    assert!(out.contains("\n1 case, 2 checks: "), "{out}");
    assert!(out.contains(", 1 input error\n"), "{out}");
}

/// The shipped example `examples/cierva-as-external`: cierva's VPM M16 through `cierva serve`
/// validates (its checks are those of `cases/vpm-m16-trim-max-weight.yaml`, whose numbers the
/// known answer above holds to the built-in path's).
#[test]
fn the_cierva_as_external_example_validates() {
    let suite = repo_root().join("examples/cierva-as-external");
    let (code, out, err) = cierva_on_path(
        &repo_root(),
        &[
            "--suite",
            suite.to_str().unwrap(),
            "validate",
            "--no-report",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("\n1 case, 1 check: 1 passed"), "{out}");
    // The suite is self-contained (it runs where a user copies it): its aircraft files are the
    // repository's, byte for byte.
    for file in [
        "vpm-m16.yaml",
        "vpm-m16-rotor.yaml",
        "vpm-m16-propeller.yaml",
    ] {
        let copy = std::fs::read(suite.join("aircraft").join(file)).unwrap();
        let original = std::fs::read(repo_root().join("aircraft").join(file)).unwrap();
        assert!(
            copy == original,
            "examples/cierva-as-external/aircraft/{file} is not the repository's: copy it again"
        );
    }
}

/// The test model's fit file: its two declared parameters (bounds from their declared ranges)
/// fitted to a trim pitch and an `M_q` at 60 mph with the given references and standard
/// errors. The model is linear in both, so the fit's answer is known in closed form:
/// `pitch_offset_deg = pitch - 3`, `m_q_scale = M_q / -1.2`, with standard errors
/// `pitch_se` and `m_q_se / 1.2`.
fn fit_file(pitch: f64, pitch_se: f64, m_q: f64, m_q_se: f64) -> String {
    format!(
        "id: model\ntitle: the test model's declared parameters fitted to known answers\n\
         provenance: {{source: 'a test of harness/tests/suite/model_interface.rs: references made from known parameter values'}}\n\
         subject: {{case: ../cases/model.yaml}}\n\
         parameters:\n  pitch_offset_deg: {{}}\n  m_q_scale: {{}}\n\
         targets:\n\
         \x20 - {{condition: {{airspeed_mph: 60.0}}, quantity: pitch_deg, reference: {pitch:?}, standard_error: {pitch_se:?}, source: the test's own}}\n\
         \x20 - {{condition: {{airspeed_mph: 60.0}}, quantity: M_q, reference: {m_q:?}, standard_error: {m_q_se:?}, source: the test's own}}\n"
    )
}

#[test]
fn fit_runs_on_an_external_model_by_its_declared_parameters() {
    super::external::require_python3();
    let dir = suite_in("fit", "cierva-external/2", true);
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    // M_q -0.95: the middle of the case's band, so that the fitted corrections make the
    // damping check (an expected failure of the model as it is) pass.
    std::fs::write(
        dir.join("fits/model.yaml"),
        fit_file(3.7, 0.05, -0.95, 0.01),
    )
    .unwrap();
    // A name the model does not declare, and bounds outside its declared range, are located
    // errors before the fit runs.
    for (wrong, said) in [
        (
            "m_q_scal: {}",
            "the model declares no parameter `m_q_scal` (did you mean `m_q_scale`?)",
        ),
        (
            "m_q_scale: {lower: 0.2, upper: 1.0}",
            "bounds [0.2, 1] reach outside the range the model declares for `m_q_scale`, [0.5, 1.5]",
        ),
    ] {
        let text = fit_file(3.7, 0.05, -0.95, 0.01)
            .replace("m_q_scale: {}", wrong)
            .replace("id: model", "id: bad");
        std::fs::write(dir.join("fits/bad.yaml"), text).unwrap();
        let (code, out, err) = cierva_in(&dir, &["fit", "fits/bad.yaml"]);
        assert_eq!(code, 2, "{out}{err}");
        assert!(
            err.contains(said) && err.contains("fits/bad.yaml:"),
            "{err}"
        );
    }
    let (code, out, err) = cierva_in(&dir, &["fit", "fits/model.yaml"]);
    assert_eq!(code, 0, "{out}{err}");
    let written = std::fs::read_to_string(dir.join("corrections/fitted/model.yaml")).unwrap();
    let v: serde_json::Value = serde_yaml::from_str(&written).unwrap();
    assert_eq!(
        v["applies_to"]["model"], "command: python3 model.py --serve",
        "{written}"
    );
    let f = |x: &serde_json::Value| x.as_f64().unwrap_or(f64::NAN);
    let fitted = &v["corrections"]["parameters"];
    // Linear in both: the fit lands on the closed form but for its convergence tolerance
    // (1e-6 of a range, the fit's default) and the differencing of printed JSON.
    let tight = |got: f64, want: f64| (got - want).abs() < 1e-5;
    assert!(tight(f(&fitted["pitch_offset_deg"]), 0.7), "{written}");
    assert!(tight(f(&fitted["m_q_scale"]), 0.95 / 1.2), "{written}");
    let se = &v["fit"]["standard_errors"];
    assert!(tight(f(&se["pitch_offset_deg"]), 0.05), "{written}");
    assert!(tight(f(&se["m_q_scale"]), 0.01 / 1.2), "{written}");
    // The corrections, applied by name, move the damping check inside its band: an
    // unexpected pass.
    let (code, out, err) = cierva_in(
        &dir,
        &[
            "validate",
            "--corrections",
            "corrections/fitted/model.yaml",
            "--format",
            "json",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 1, "an unexpected pass fails the run: {out}{err}");
    let damping = quantities(&out)
        .into_iter()
        .find(|((_, check, _), _)| check == "damping")
        .unwrap_or_else(|| panic!("no damping row: {out}"));
    assert!((damping.1.0 - -0.95).abs() < 1e-5, "{out}");
    assert!(damping.1.1, "{out}");
}

/// How far a fit through the protocol may land from the built-in fit, relative: the issue's
/// 1e-9. The two are one path (`CiervaAircraft` behind the model interface, each trim with
/// parameter values started from the aircraft's own trim at its condition), the served one
/// through JSON, which carries every f64 exactly.
const SERVED_AGAINST_BUILT_IN: f64 = 1e-9;

/// A hidden propeller blockage: the built-in aircraft's X_u and Z_w at 40-70 mph with it are
/// the references (standard error 1 % of each); the fit recovers it, through the protocol and
/// built in alike.
const HIDDEN_BLOCKAGE: f64 = 0.55;

#[test]
#[ignore = "slow (about 5 s in a release test run since the VPM M16's blades feel the hub's angular acceleration, 2026-11-30; out of the cold `cargo test`, held under 5 minutes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn a_fit_through_the_protocol_recovers_the_built_in_fit() {
    let dir = mirrored_suite();
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    std::fs::create_dir_all(dir.join("corrections")).unwrap();
    std::fs::write(
        dir.join("corrections/hidden.yaml"),
        format!(
            "id: hidden\ntitle: the hidden blockage\napplies_to: {{aircraft: vpm-m16}}\n\
             corrections: {{propeller_blockage: {HIDDEN_BLOCKAGE}}}\n\
             provenance: {{source: the test's hidden value}}\n"
        ),
    )
    .unwrap();
    let mut targets = String::new();
    for v in [40.0, 50.0, 60.0, 70.0] {
        let speed = format!("{v}");
        let (code, out, err) = cierva_on_path(
            &dir,
            &[
                "linearize",
                "aircraft/vpm-m16.yaml",
                "--airspeed-mph",
                &speed,
                "--mass-kg",
                "425",
                "--density-altitude-ft",
                "2000",
                "--corrections",
                "corrections/hidden.yaml",
                "--format",
                "json",
            ],
        );
        assert_eq!(code, 0, "{err}");
        let lin: serde_json::Value = serde_json::from_str(&out).unwrap();
        for d in lin["primary_derivatives"].as_array().unwrap() {
            if d["name"] == "X_u" || d["name"] == "Z_w" {
                let value = d["value"].as_f64().unwrap();
                targets += &format!(
                    "  - {{condition: {{airspeed_mph: {v:?}}}, quantity: {}, reference: {value:?}, standard_error: {:?}, source: the built-in model at the hidden blockage}}\n",
                    d["name"].as_str().unwrap(),
                    0.01 * value.abs()
                );
            }
        }
    }
    let fit = |id: &str, subject: &str, parameter: &str| {
        std::fs::write(
            dir.join(format!("fits/{id}.yaml")),
            format!(
                "id: {id}\ntitle: the hidden blockage\nprovenance: {{source: the test's own}}\n\
                 subject: {subject}\nparameters:\n  {parameter}: {{lower: 0.0, upper: 1.0, start: 0.3}}\n\
                 targets:\n{targets}"
            ),
        )
        .unwrap();
        let (code, out, err) = cierva_on_path(&dir, &["fit", &format!("fits/{id}.yaml")]);
        assert_eq!(code, 0, "{out}{err}");
        let text =
            std::fs::read_to_string(dir.join(format!("corrections/fitted/{id}.yaml"))).unwrap();
        let v: serde_json::Value = serde_yaml::from_str(&text).unwrap();
        let value = |m: &serde_json::Value| {
            m.as_object()
                .unwrap()
                .values()
                .next()
                .and_then(|x| x.as_f64())
                .unwrap()
        };
        let fitted = if parameter.starts_with("corrections.") {
            value(&v["corrections"]["parameters"])
        } else {
            value(&v["corrections"])
        };
        (
            fitted,
            value(&v["fit"]["standard_errors"]),
            v["fit"]["cost"].as_f64().unwrap(),
        )
    };
    let built_in = fit(
        "built-in",
        "{aircraft: {file: ../aircraft/vpm-m16.yaml, mass_kg: 425.0, density_altitude_ft: 2000.0}}",
        "propeller_blockage",
    );
    let served = fit(
        "served",
        "{case: ../cases/seed000-synthetic-xu-zw-vpm-m16.yaml}",
        "corrections.propeller_blockage",
    );
    let _ = std::fs::remove_dir_all(&dir);
    // Both recover the hidden value well inside one standard error (the references are the
    // model's own: only the fit's tolerance and the trims' separate them from it).
    for (path, (fitted, se, _)) in [("built in", built_in), ("served", served)] {
        assert!(
            (fitted - HIDDEN_BLOCKAGE).abs() < 0.01 * se,
            "{path}: fitted {fitted} +- {se}, hidden {HIDDEN_BLOCKAGE}"
        );
    }
    let near = |a: f64, b: f64| (a - b).abs() <= SERVED_AGAINST_BUILT_IN * a.abs().max(b.abs());
    assert!(near(built_in.0, served.0), "{built_in:?} {served:?}");
    assert!(near(built_in.1, served.1), "{built_in:?} {served:?}");
    // The cost at a hidden value is the trims' noise (squared standard errors, near zero):
    // compared absolutely, to the same 1e-9.
    assert!(
        (built_in.2 - served.2).abs() <= SERVED_AGAINST_BUILT_IN,
        "{built_in:?} {served:?}"
    );
}

/// Trials of the external model's fit: hidden values anywhere in the declared ranges'
/// middle, references drawn about the model's values at them with their standard errors.
/// 200 trials, 2 intervals each: at a true coverage of 95 % the misses of one parameter are
/// binomial (200, 0.05), mean 10, standard deviation 3.1; 3 to 19 misses (98.5-90.5 % held)
/// holds them with probability 0.998, and misses a coverage of 89 % (22 expected) or 99 % (2
/// expected) more often than not.
const FIT_TRIALS: u64 = 200;
const FIT_MISSES: std::ops::RangeInclusive<usize> = 3..=19;

#[test]
fn an_external_models_fitted_standard_errors_cover_hidden_values_at_their_rate() {
    super::external::require_python3();
    let dir = suite_in("fit-coverage", "cierva-external/2", true);
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    let (pitch_se, m_q_se) = (0.05, 0.01);
    std::fs::write(
        dir.join("fits/model.yaml"),
        fit_file(3.0, pitch_se, -1.2, m_q_se),
    )
    .unwrap();
    let file = cierva_harness::fit::file::load(&dir.join("fits/model.yaml"));
    let file = file.unwrap_or_else(|e| panic!("{}", e.render()));
    // The parameters in the order the file's map gives them (by name).
    let names: Vec<String> = file
        .problem
        .parameters
        .iter()
        .map(|p| p.kind.name().to_string())
        .collect();
    assert_eq!(names, ["m_q_scale", "pitch_offset_deg"]);
    let mut misses = [0usize; 2];
    for n in 0..FIT_TRIALS {
        let mut rng = super::common::SplitMix(0x0049_0F17 ^ n.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let hidden = [rng.uniform(0.7, 1.3), rng.uniform(-1.0, 1.0)];
        let mut problem = file.problem.clone();
        problem.targets[0].reference = 3.0 + hidden[1] + pitch_se * rng.normal();
        problem.targets[1].reference = -1.2 * hidden[0] + m_q_se * rng.normal();
        let r = cierva_harness::fit::fit(&problem);
        assert_eq!(r.status, cierva_harness::fit::Status::Converged, "{r:?}");
        for k in 0..2 {
            if (r.values[k] - hidden[k]).abs() > 1.96 * r.standard_errors[k] {
                misses[k] += 1;
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    for (k, m) in misses.iter().enumerate() {
        assert!(
            FIT_MISSES.contains(m),
            "{}: {m} of {FIT_TRIALS} 95 % intervals missed the hidden value",
            names[k]
        );
    }
}

/// The test model's linear model at a hidden `m_q_scale`, as a reference file `cierva synth`
/// flies (`B` per percent of travel, as the model's).
fn truth_file(m_q_scale: f64) -> String {
    format!(
        "id: truth\ntitle: the test model at a hidden m_q_scale\n\
         provenance: {{source: the test model of harness/tests/suite/model_interface.rs at m_q_scale {m_q_scale}}}\n\
         condition: {{airspeed_mph: 60, mass_kg: 400}}\n\
         linear_model:\n  states: [u, w, q, theta]\n  controls: [eta_s]\n\
         \x20 units: {{u: m/s, w: m/s, q: rad/s, theta: rad, eta_s: '%'}}\n\
         \x20 a:\n    - [-0.05, 0.1, 0.0, -9.81]\n    - [-0.3, -0.8, 30.0, 0.0]\n\
         \x20   - [0.01, -0.05, {:?}, 0.0]\n    - [0.0, 0.0, 1.0, 0.0]\n\
         \x20 b: [[0.0], [0.1], [-0.02], [0.0]]\n",
        -1.2 * m_q_scale
    )
}

/// The hidden `m_q_scale` of the retune's known answer.
const HIDDEN_M_Q_SCALE: f64 = 0.8;

/// The test model flown at [`HIDDEN_M_Q_SCALE`] through a stick sweep (`cierva synth`, its
/// noise scaled by `noise_scale`) into `dir`'s records, and retuned from them (`extra`
/// arguments to `retune`): the retune's JSON.
fn flown_and_retuned(dir: &Path, noise_scale: &str, extra: &[&str]) -> serde_json::Value {
    std::fs::create_dir_all(dir.join("refs")).unwrap();
    std::fs::write(dir.join("refs/truth.yaml"), truth_file(HIDDEN_M_Q_SCALE)).unwrap();
    let (code, out, err) = cierva_in(
        dir,
        &[
            "synth",
            "refs/truth.yaml",
            "--control",
            "eta_s",
            "--shape",
            "sweep",
            "--amplitude-model-units",
            "5",
            "--noise-scale",
            noise_scale,
            "--seed",
            "7",
            "--output",
            "records/sweep.csv",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    let args = [
        "retune",
        "--case",
        "cases/model.yaml",
        "--records",
        "records/sweep.csv",
        "--fit",
        "m_q_scale",
        "--format",
        "json",
    ];
    let args: Vec<&str> = args.iter().chain(extra).copied().collect();
    let (code, out, err) = cierva_in(dir, &args);
    assert_eq!(code, 0, "{out}{err}");
    serde_json::from_str(&out).unwrap()
}

#[test]
fn retune_runs_on_an_external_model_from_its_records() {
    super::external::require_python3();
    let dir = suite_in("retune", "cierva-external/2", true);
    let v = flown_and_retuned(&dir, "1", &[]);
    let (value, se) = (
        v["corrections"]["m_q_scale"].as_f64().unwrap(),
        v["standard_errors"]["m_q_scale"].as_f64().unwrap(),
    );
    assert!(
        (value - HIDDEN_M_Q_SCALE).abs() < 2.0 * se,
        "{value} +- {se}, hidden {HIDDEN_M_Q_SCALE}"
    );
    // The rotorspeed response the record carries is one this model has no state for: left
    // out, and said.
    let written = std::fs::read_to_string(dir.join("corrections/retuned/model.yaml")).unwrap();
    assert!(
        written.contains("applies_to:\n  model: 'command: python3 model.py --serve'"),
        "{written}"
    );
    assert!(
        written.contains("the model has no state `Omega`"),
        "{written}"
    );
    // The revalidation ran the model's case with the retuned value: the damping check moved.
    let changed = v["revalidation"]["changed"].as_array().unwrap();
    assert!(
        changed.iter().any(|c| c["check"] == "model::damping"),
        "{}",
        v["revalidation"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// How close a retune from noise-free records of the model itself comes to the hidden value,
/// relative. Measured 2026-12-01: 1.2e-3 (0.80093), what the fit's stopping rule and the
/// records' discretisation leave (`cierva synth` integrates the linear model at its sample
/// step; the matched processing convolves in frequency); a second pass of the correction at the
/// refitted value left it unchanged (measured with half today's padding). Without the matched
/// processing the estimator's bias (its smoothing, leakage and transfers) left 3.7e-2 (0.7706),
/// which this fails; the tolerance is 4 times what is left, 7 times below that.
const NOISE_FREE_RETUNE_RELATIVE: f64 = 5e-3;

/// A retune of a model from noise-free records of that very model recovers its hidden value:
/// the records' responses, put through Welch's estimator, are smoothed over its windows, and
/// the matched processing (`fit::retune::matched`) takes the same smoothing of the model's
/// flown output off the targets (issue 51, item 6).
#[test]
fn a_retune_from_noise_free_records_of_the_model_itself_recovers_it() {
    super::external::require_python3();
    let dir = suite_in("retune-noise-free", "cierva-external/2", true);
    let v = flown_and_retuned(&dir, "0", &["--no-validate"]);
    let value = v["corrections"]["m_q_scale"].as_f64().unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        (value / HIDDEN_M_Q_SCALE - 1.0).abs() < NOISE_FREE_RETUNE_RELATIVE,
        "{value}, hidden {HIDDEN_M_Q_SCALE}: {}",
        v["matched"]
    );
}

/// A derivative check's `corrections` reach any model through the model interface: on a model
/// behind the protocol as values of its declared parameters (`M_q` = -1.2 * 0.8 = -0.96, its
/// magnitude change -0.2 exactly); a correction the model does not declare, and a component of
/// a derivative (which the protocol does not carry), are located errors at load.
#[test]
fn a_checks_corrections_reach_an_external_model_by_its_declared_parameters() {
    super::external::require_python3();
    let dir = suite("check-corrections", "cierva-external/2");
    let case_path = dir.join("cases/model.yaml");
    let text = std::fs::read_to_string(&case_path).unwrap();
    let corrected = "  - id: corrected\n    kind: derivative\n    derivative: M_q\n\
                     \x20   condition: {airspeed_mph: 60.0}\n\
                     \x20   corrections: {parameters: {m_q_scale: 0.8}}\n\
                     \x20   expect:\n      value: {value: -0.96, tolerance: band}\n\
                     \x20     magnitude_change: {value: -0.2, tolerance: band}\n";
    std::fs::write(&case_path, format!("{text}{corrected}")).unwrap();
    let case = cierva_harness::suite::case::load(&case_path).unwrap();
    let results = cierva_harness::suite::outcome::run_case(&case);
    let r = results.iter().find(|r| r.check == "corrected").unwrap();
    assert!(r.error.is_none(), "{:?}", r.error);
    let value = |q: &str| r.quantities.iter().find(|x| x.quantity == q).unwrap().value;
    assert!((value("value") + 0.96).abs() < 1e-12, "{r:?}");
    assert!((value("magnitude_change") + 0.2).abs() < 1e-12, "{r:?}");
    assert!(r.passed, "{r:?}");
    // The uncorrected check beside it still sees the nominal model.
    let plain = results.iter().find(|r| r.check == "damping").unwrap();
    assert!((plain.quantities[0].value + 1.2).abs() < 1e-12, "{plain:?}");

    for (edit, says) in [
        (
            "corrections: {propeller_blockage: 0.5}",
            "takes corrections as values of the parameters it declares",
        ),
        (
            "corrections: {parameters: {m_q_scal: 0.8}}",
            "did you mean `m_q_scale`?",
        ),
    ] {
        let bad = corrected.replace("corrections: {parameters: {m_q_scale: 0.8}}", edit);
        std::fs::write(&case_path, format!("{text}{bad}")).unwrap();
        let e = cierva_harness::suite::case::load(&case_path)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("checks[2].corrections") && e.contains(says),
            "{e}"
        );
    }
    let bad = corrected.replace("magnitude_change:", "rotor:");
    std::fs::write(&case_path, format!("{text}{bad}")).unwrap();
    let e = cierva_harness::suite::case::load(&case_path)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("computed for aircraft cases only") && e.contains("[value, magnitude_change]"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A case on a model behind the protocol gets the snapshots an aircraft's gets (its trims, its
/// linear model at each condition), asked through the model interface: the model's own numbers,
/// and no breakdown by component, which the protocol does not carry.
#[test]
fn an_external_models_snapshots_are_its_answers() {
    use cierva_harness::suite::snapshots::{Holds, of_case};
    super::external::require_python3();
    let dir = suite("snapshots", "cierva-external/2");
    let case = cierva_harness::suite::case::load(&dir.join("cases/model.yaml")).unwrap();
    let snaps = of_case(&case);
    let names: Vec<&str> = snaps.iter().map(|s| s.what.as_str()).collect();
    assert_eq!(names, ["trim", "linear-60mph"]);
    match snaps[0].compute(&case).unwrap() {
        Holds::Trim(columns) => {
            assert_eq!(columns.len(), 1);
            let q = columns[0].1.as_ref().unwrap();
            assert_eq!(q.iter().find(|(n, _)| *n == "pitch_deg").unwrap().1, 3.0);
        }
        other => panic!("{other:?}"),
    }
    let linear = snaps[1].compute(&case).unwrap();
    let text = cierva_harness::report::snapshots::render(&linear);
    match linear {
        Holds::Linearised {
            model, components, ..
        } => {
            assert_eq!(model.derivative_value("M_q").unwrap(), -1.2);
            assert!(components.is_none());
        }
        other => panic!("{other:?}"),
    }
    assert!(!text.contains("total"), "no breakdown: {text}");
    assert!(text.contains("M_q"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An `external:` block without `timeout_s` takes the default (a first-time user met "missing
/// field `timeout_s`", issue 50's first hour): the case loads and its checks run.
#[test]
fn an_external_model_without_a_timeout_takes_the_default() {
    super::external::require_python3();
    let dir = suite("default-timeout", "cierva-external/2");
    let path = dir.join("cases/model.yaml");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("    timeout_s: 30\n"));
    std::fs::write(&path, text.replace("    timeout_s: 30\n", "")).unwrap();
    let case =
        cierva_harness::suite::case::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
    let results = cierva_harness::suite::outcome::run_case(&case);
    let pitch = results.iter().find(|r| r.check == "pitch").unwrap();
    assert!(pitch.passed, "{pitch:?}");
    assert_eq!(cierva_harness::checks::subject::DEFAULT_TIMEOUT_S, 60.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `time_history` check flies its record through the model interface alike on every model:
/// cierva's VPM M16 built in (its correction named) and served by `cierva serve` (the same
/// correction as the value of its declared parameter `corrections.profile_drag_scale`) give
/// the same metrics within [`THROUGH_THE_PROTOCOL`], with and without the correction, and the
/// correction moves them (it is applied, not dropped). A simulation the served model does not
/// offer (`simulation: linear`: it has one) is a located error naming the model.
#[test]
fn a_time_history_through_the_protocol_flies_as_the_built_in_aircraft() {
    let dir = crate::common::scratch("served-history");
    super::common::new_suite(&dir);
    for linked in ["aircraft", "flight-refs"] {
        std::os::unix::fs::symlink(repo_root().join(linked), dir.join(linked)).unwrap();
    }
    let case = |id: &str, model: &str, corrections: &str| {
        format!(
            "id: {id}\ntitle: a stick doublet flown\nclass: verification\n\
             provenance: {{source: a test of harness/tests/suite/model_interface.rs}}\n\
             model:\n{model}\
             tolerances:\n  rate:\n    absolute: 2.0\n    reason: the test's own\n\
             \x20 angle:\n    absolute: 0.1\n    reason: the test's own\n\
             checks:\n\
             \x20 - id: plain\n    kind: time_history\n    condition: {{airspeed_mph: 70.0}}\n\
             \x20   reference: ../flight-refs/synthetic-vpm-m16-70mph-stick-doublet.csv\n\
             \x20   expect:\n      q_deg_s.max_abs_error: {{value: 0.0, tolerance: rate}}\n\
             \x20     theta_deg.rms_error: {{value: 0.0, tolerance: angle}}\n\
             \x20 - id: corrected\n    kind: time_history\n    condition: {{airspeed_mph: 70.0}}\n\
             \x20   reference: ../flight-refs/synthetic-vpm-m16-70mph-stick-doublet.csv\n\
             \x20   corrections: {corrections}\n\
             \x20   expect:\n      q_deg_s.max_abs_error: {{value: 0.0, tolerance: rate}}\n\
             \x20     theta_deg.rms_error: {{value: 0.0, tolerance: angle}}\n"
        )
    };
    std::fs::write(
        dir.join("cases/built-in.yaml"),
        case(
            "built-in",
            "  aircraft:\n    file: ../aircraft/vpm-m16.yaml\n    mass_kg: 450.0\n",
            "{profile_drag_scale: 1.3}",
        ),
    )
    .unwrap();
    let served = "  external:\n    command: [cierva, serve, ../aircraft/vpm-m16.yaml]\n\
                  \x20   protocol: cierva-external/2\n    persistent: true\n\
                  \x20   timeout_s: 600\n    mass_kg: 450.0\n";
    std::fs::write(
        dir.join("cases/served.yaml"),
        case(
            "served",
            served,
            "{parameters: {corrections.profile_drag_scale: 1.3}}",
        ),
    )
    .unwrap();
    let (_, out, err) = cierva_on_path(&dir, &["validate", "--no-report", "--format", "json"]);
    let all = quantities(&out);
    let of = |id: &str| -> std::collections::BTreeMap<(String, String), f64> {
        all.iter()
            .filter(|((c, _, _), _)| c == id)
            .map(|((_, k, q), (v, _))| ((k.clone(), q.clone()), *v))
            .collect()
    };
    let (built_in, through) = (of("built-in"), of("served"));
    assert_eq!(built_in.len(), 4, "{out}{err}");
    assert_eq!(
        built_in.keys().collect::<Vec<_>>(),
        through.keys().collect::<Vec<_>>()
    );
    for (key, value) in &built_in {
        let v = through[key];
        assert!(
            close(*value, v),
            "{key:?}: built in {value}, through the protocol {v}"
        );
    }
    let q = |check: &str| built_in[&(check.to_string(), "q_deg_s.max_abs_error".to_string())];
    assert!(
        (q("corrected") - q("plain")).abs() > 1e-6,
        "the correction changes nothing: {built_in:?}"
    );

    let text = std::fs::read_to_string(dir.join("cases/served.yaml")).unwrap();
    std::fs::write(
        dir.join("cases/served.yaml"),
        text.replacen(
            "    corrections: {parameters: {corrections.profile_drag_scale: 1.3}}\n",
            "    simulation: linear\n",
            1,
        ),
    )
    .unwrap();
    let e = cierva_harness::suite::case::load(&dir.join("cases/served.yaml"))
        .unwrap_err()
        .to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        e.contains("checks[1].simulation")
            && e.contains("the command `cierva serve ../aircraft/vpm-m16.yaml` has one"),
        "{e}"
    );
}

/// The test model's discretisation error in the trim pitch, deg, at its nominal levels: from
/// its step (falling as the step's square), its elements (falling as their count to the power
/// 1.5, where a scheme of second order is claimed) and its tolerance (a tenth per level, refined
/// once only). Each is refined alone; the `u_num` the study must report follows from these
/// exactly (`REFINABLE_U_NUM_DEG`).
const REFINABLE_ERRORS_DEG: [f64; 3] = [0.004, 0.003, 0.0009];

/// The `u_num` of the test model's pitch, deg, by the grid convergence index of each
/// parameter: the step's three levels show order 2 (its formal order), so Fs 1.25 and an index
/// of 1.25 times its error; the elements' show order 1.5, within a factor 2 of the formal 2,
/// so Fs 1.25 at order 1.5: 1.25 times its error; the tolerance has two levels, so Fs 3 at its
/// formal order 1 and ratio 10: 3 x 0.9 x 0.0009 x 10 / 9. Root-sum-squared.
const REFINABLE_U_NUM_DEG: f64 = 0.006_808_267_033_540_915;

/// What the study asked of [`Refinable`] beyond its answers./// What the study asked of [`Refinable`] beyond its answers.
#[derive(Debug, Default)]
struct Asked {
    /// The values each `starting_from` was given.
    started_from: std::sync::Mutex<Vec<cierva_harness::external::Values>>,
    /// The values each `forget` was given.
    forgotten: std::sync::Mutex<Vec<cierva_harness::external::Values>>,
}

/// The test model behind the protocol, wrapped by a model of the test's own that has a grid
/// study (three parameters, [`REFINABLE_ERRORS_DEG`]) and notes what a study asks of it.
#[derive(Debug)]
struct Refinable {
    inner: std::sync::Arc<dyn cierva_harness::external::FlightModel>,
    /// How many times each parameter was refined: step, elements, tolerance.
    levels: [i32; 3],
    asked: std::sync::Arc<Asked>,
}

impl Refinable {
    /// The pitch's discretisation error at these levels, deg.
    fn pitch_error_deg(&self) -> f64 {
        let [a, b, c] = REFINABLE_ERRORS_DEG;
        let [s, e, t] = self.levels;
        a * 0.25f64.powi(s) + b * 2f64.powf(-1.5 * f64::from(e)) + c * 0.1f64.powi(t)
    }
}

impl cierva_harness::external::FlightModel for Refinable {
    fn describe(&self) -> String {
        format!("the refinable {}", self.inner.describe())
    }
    fn parameters(&self) -> Result<Vec<cierva_harness::external::Parameter>, String> {
        self.inner.parameters()
    }
    fn trim(&self, request: &Request) -> Result<cierva_harness::external::Quantities, String> {
        let mut q = self.inner.trim(request)?;
        for (name, v) in &mut q {
            if *name == "pitch_deg" {
                *v += self.pitch_error_deg();
            }
        }
        Ok(q)
    }
    fn linear_model(&self, request: &Request) -> Result<cierva_model::LinearModel, String> {
        self.inner.linear_model(request)
    }
    fn starting_from(
        &self,
        values: &cierva_harness::external::Values,
    ) -> Option<std::sync::Arc<dyn cierva_harness::external::FlightModel>> {
        self.asked.started_from.lock().unwrap().push(values.clone());
        None
    }
    fn refinements(&self) -> Vec<cierva_harness::external::Refinement> {
        let refined = |k: usize| {
            let mut levels = self.levels;
            levels[k] += 1;
            std::sync::Arc::new(Refinable {
                inner: self.inner.clone(),
                levels,
                asked: std::sync::Arc::default(),
            }) as std::sync::Arc<dyn cierva_harness::external::FlightModel>
        };
        let one = |k: usize, parameter: &str, ratio: f64, formal_order: f64| {
            cierva_harness::external::Refinement {
                parameter: parameter.into(),
                words: format!("level {} -> {}", self.levels[k], self.levels[k] + 1),
                ratio,
                formal_order,
                model: refined(k),
            }
        };
        let mut out = vec![one(0, "step", 2.0, 2.0), one(1, "elements", 2.0, 2.0)];
        // The tolerance is refined once only: two levels.
        if self.levels[2] == 0 {
            out.push(one(2, "tolerance", 10.0, 1.0));
        }
        out
    }
    fn forget(&self, values: &cierva_harness::external::Values) {
        self.asked.forgotten.lock().unwrap().push(values.clone());
    }
}

/// The uncertainty study asks any model through the interface what it asks of cierva's
/// aircraft: its refined self for `u_num` (a model of the user's own with a grid study gets
/// one), its answers started from a nearby point's for each `A_B^(i)` point, and to forget each
/// point once its checks have run. Before, the study did all three for cierva's aircraft alone,
/// by editing its file: another model had no `u_num`.
#[test]
fn the_uncertainty_study_asks_any_model_for_its_refinement_starts_and_memory() {
    use cierva_harness::uncertainty::propagate::{Propagation, PropagationSettings};
    super::external::require_python3();
    let dir = suite_in("study-interface", "cierva-external/2", true);
    let mut case = cierva_harness::suite::case::load(&dir.join("cases/model.yaml")).unwrap();
    let asked = std::sync::Arc::new(Asked::default());
    let cierva_harness::checks::subject::Subject::External(e) = &mut case.subject else {
        panic!("the test case's model is external");
    };
    e.model = std::sync::Arc::new(Refinable {
        inner: e.model.clone(),
        levels: [0; 3],
        asked: asked.clone(),
    });
    let samples = 8;
    let settings = PropagationSettings {
        samples,
        seed: 0,
        validation_only: false,
        method: Propagation::Sampled,
    };
    let study = cierva_harness::uncertainty::study::propagate(&case, settings, || ()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(
        study.refinement,
        "step level 0 -> 1; level 1 -> 2 (r 2, formal order 2), alone | elements level 0 -> 1; \
         level 1 -> 2 (r 2, formal order 2), alone | tolerance level 0 -> 1 (r 10, formal \
         order 1), alone"
    );
    let row = |check: &str| {
        study
            .results
            .iter()
            .find(|r| r.check == check)
            .unwrap_or_else(|| panic!("no {check}"))
    };
    // Known answers, to rounding: each parameter refined alone, its index by the book.
    let pitch = row("pitch");
    assert!(
        (pitch.u_num - REFINABLE_U_NUM_DEG).abs() < 1e-9,
        "{:?}",
        pitch.u_num_terms
    );
    let orders: Vec<(Option<f64>, f64, f64)> = pitch
        .u_num_terms
        .iter()
        .map(|t| {
            let round = |p: f64| (p * 1e9).round() / 1e9;
            (t.observed_order.map(round), round(t.order), t.safety_factor)
        })
        .collect();
    assert_eq!(
        orders,
        [
            (Some(2.0), 2.0, 1.25),
            (Some(1.5), 1.5, 1.25),
            (None, 1.0, 3.0)
        ],
        "{:?}",
        pitch.u_num_terms
    );
    for (t, error) in pitch.u_num_terms.iter().zip(REFINABLE_ERRORS_DEG) {
        assert!(
            t.gci >= error,
            "the index covers the parameter's error: {t:?}"
        );
    }
    assert_eq!(row("damping").u_num, 0.0);
    // Two inputs: each of the 2 x 8 `A_B^(i)` points starts from its row of `A` (8 rows).
    let started = asked.started_from.lock().unwrap();
    assert_eq!(started.len(), 2 * samples);
    let rows: std::collections::BTreeSet<String> =
        started.iter().map(|v| format!("{v:?}")).collect();
    assert_eq!(rows.len(), samples, "{started:?}");
    // Every point of A, B and the A_B^(i), once: 8 (2 + 2) points.
    let forgotten = asked.forgotten.lock().unwrap();
    assert_eq!(forgotten.len(), samples * 4);
    let distinct: std::collections::BTreeSet<String> =
        forgotten.iter().map(|v| format!("{v:?}")).collect();
    assert_eq!(distinct.len(), samples * 4);
    assert!(rows.is_subset(&distinct));
}

/// cierva's VPM M16 served by `cierva serve` answers `frequency_response` (protocol `/2`) with
/// the built-in responses, its teetering rotor's flapping states by harmonic balance, one-shot
/// and persistent, to the bit (JSON carries every `f64` exactly). Before, a model behind the
/// protocol could give only its A and B, whose quasi-static responses miss the blades' lag.
#[test]
fn the_frequency_response_through_the_protocol_is_the_built_in_one() {
    use cierva_harness::external::command::{ExternalCommand, Protocol};
    let path = repo_root().join("aircraft/vpm-m16.yaml");
    let file = cierva_harness::inputs::aircraft::load(&path).unwrap();
    let request = Request::at(
        TrimRequest::level(60.0),
        Loading {
            mass_kg: Some(450.0),
            density_altitude_ft: 2000.0,
        },
    )
    .with("corrections.propeller_blockage", 0.5);
    let frequencies_hz = [0.1, 0.5, 1.3];
    let built_in = cierva_harness::external::CiervaAircraft::new(&file)
        .responses(&request, &frequencies_hz)
        .unwrap();
    let command = vec![
        env!("CARGO_BIN_EXE_cierva").to_string(),
        "serve".to_string(),
        path.display().to_string(),
    ];
    for persistent in [false, true] {
        let mut model = ExternalCommand::speaking(
            command.clone(),
            repo_root(),
            std::time::Duration::from_secs(600),
            Protocol::V2,
        );
        if persistent {
            model = model.persistent();
        }
        let served = model.responses(&request, &frequencies_hz).unwrap();
        assert_eq!(served.states, built_in.states);
        assert_eq!(served.controls, built_in.controls);
        assert_eq!(served.frequencies_hz, frequencies_hz);
        assert_eq!(served.at, built_in.at, "persistent: {persistent}");
        assert!(
            served
                .model()
                .contains(cierva_harness::run::responses::WITH_FLAPPING),
            "{}",
            served.model()
        );
    }
}

/// The bounds both retunes of the README example take: the hub factor's and the profile-drag
/// scale's defaults (`fit::retune::DEFAULT_BOUNDS`), which the VPM M16's file gives no range
/// for, so that the served model is asked within the same bounds.
const README_BOUNDS: [&str; 2] = [
    "corrections.hub_aoa_factor=0:1",
    "corrections.profile_drag_scale=0.5:2",
];

/// The README example's retune through the protocol: the same synthetic record, retuned built
/// in (`cierva retune aircraft/vpm-m16.yaml`) and through `cierva serve` of the same file
/// (`cierva retune --case`, persistent), gives the same corrections, standard errors and cost
/// within [`THROUGH_THE_PROTOCOL`] (and the same reduced chi-square and `J` per response): both
/// ask `CiervaAircraft` for its frequency responses with the trial values, the served one
/// through `frequency_response` requests.
#[test]
#[ignore = "slow known answer (a synthetic flight and two retunes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn the_readme_retune_through_the_protocol_is_the_built_in_one() {
    let dir = mirrored_suite();
    let record = super::common::readme_record(&dir);
    let (code, built_in, err) = super::common::retune_hub_and_drag(&dir, &[&record], &[]);
    assert_eq!(code, 0, "{built_in}{err}");
    let mut args = vec![
        "retune",
        "--case",
        "cases/vpm-m16-trim-max-weight.yaml",
        "--records",
        record.to_str().unwrap(),
        "--fit",
        "corrections.hub_aoa_factor",
        "corrections.profile_drag_scale",
    ];
    // The served aircraft declares its corrections without ranges: a retune without bounds
    // is told how to give them on its own command line (exit 2).
    let (code, _, err) = cierva_on_path(&dir, &args);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--bounds corrections.hub_aoa_factor=LO:HI"),
        "{err}"
    );
    args.push("--bounds");
    args.extend(README_BOUNDS);
    args.extend(["--no-validate", "--format", "json"]);
    let (code, served, err) = cierva_on_path(&dir, &args);
    assert_eq!(code, 0, "{served}{err}");
    // The served retune with its fit's batches through plans (issue 53, item 3), each run by
    // `cierva evaluate` as an engine would: the served retune, bit for bit.
    let engine = format!(
        "for i in $(seq 1 {{shards}}); do '{}' evaluate {{plan}} --shard $i/{{shards}} --quiet || exit 1; done",
        env!("CARGO_BIN_EXE_cierva")
    );
    args.extend(["--evaluate-with", &engine, "--plans", "plans"]);
    let (code, planned, err) = cierva_on_path(&dir, &args);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 0, "{planned}{err}");
    assert_eq!(planned, served, "{err}");
    let (a, b): (serde_json::Value, serde_json::Value) = (
        serde_json::from_str(&built_in).unwrap(),
        serde_json::from_str(&served).unwrap(),
    );
    assert_eq!(a["status"], "converged", "{built_in}");
    assert_eq!(b["status"], "converged", "{served}");
    let f = |x: &serde_json::Value| x.as_f64().unwrap_or(f64::NAN);
    for name in ["hub_aoa_factor", "profile_drag_scale"] {
        let declared = format!("corrections.{name}");
        for part in ["corrections", "standard_errors"] {
            let (p, q) = (f(&a[part][name]), f(&b[part][&declared]));
            assert!(
                close(p, q),
                "{part}.{name}: built in {p}, through the protocol {q}"
            );
        }
    }
    let k = "reduced_chi_square";
    assert!(close(f(&a[k]), f(&b[k])), "{k}: {} against {}", a[k], b[k]);
    let (ra, rb) = (
        a["responses"].as_array().unwrap(),
        b["responses"].as_array().unwrap(),
    );
    assert_eq!(ra.len(), rb.len(), "{built_in}\n{served}");
    for (x, y) in ra.iter().zip(rb) {
        assert_eq!(x["output"], y["output"]);
        for j in ["j_before", "j_after"] {
            assert!(close(f(&x[j]), f(&y[j])), "{j}: {x} against {y}");
        }
    }
}

/// TR 487's case, and the same case with its rotor behind the model interface as `wrap` makes
/// it (an `external` subject).
fn tr487_on_an_external_model(
    wrap: impl FnOnce(
        cierva_harness::external::rotor::CiervaRotor<'static>,
    ) -> std::sync::Arc<dyn cierva_harness::external::FlightModel>,
    written: &str,
) -> (
    cierva_harness::suite::case::Case,
    cierva_harness::suite::case::Case,
) {
    use cierva_harness::checks::subject::Subject;
    let case = cierva_harness::suite::case::load(
        &repo_root().join("cases/naca-tr487-vertical-descent.yaml"),
    )
    .unwrap();
    let Subject::Rotor { file, solver, .. } = &case.subject else {
        panic!("TR 487's case is of a rotor");
    };
    let rotor = cierva_harness::external::rotor::CiervaRotor::owned((**file).clone(), *solver);
    let mut other = case.clone();
    other.subject = Subject::External(Box::new(cierva_harness::external::External {
        model: wrap(rotor),
        loading: Loading {
            mass_kg: None,
            density_altitude_ft: 0.0,
        },
        written: written.into(),
        folder: repo_root(),
    }));
    (case, other)
}

/// How much the test's rotor model adds to cierva's rotor speed, rad/s.
const SPED_UP_RAD_S: f64 = 0.1;

/// cierva's rotor in a tunnel with [`SPED_UP_RAD_S`] added to its rotor speed: a model of the
/// test's own that answers `autorotation` through the model interface.
#[derive(Debug)]
struct SpedUp(cierva_harness::external::rotor::CiervaRotor<'static>);

impl cierva_harness::external::FlightModel for SpedUp {
    fn describe(&self) -> String {
        format!("the sped-up {}", self.0.describe())
    }
    fn autorotation(
        &self,
        request: &cierva_harness::external::TunnelRequest,
    ) -> Result<cierva_harness::run::autorotation::Autorotated, String> {
        use cierva_harness::run::autorotation::Autorotated;
        let mut a = self.0.autorotation(request)?;
        if let Autorotated::Equilibrium(e) = &mut a {
            for (name, v) in &mut e.quantities {
                if *name == "rotor_omega_rad_s" {
                    *v += SPED_UP_RAD_S;
                }
            }
        }
        Ok(a)
    }
}

/// An `autorotation` check asks its model through the model interface
/// (`FlightModel::autorotation`), whatever the model: TR 487's check on a model that wraps
/// cierva's rotor gives the rotor's speed plus [`SPED_UP_RAD_S`], and every other quantity as it
/// is. Before, the check read cierva's rotor file itself and refused any other subject.
#[test]
fn an_autorotation_check_asks_any_model_through_the_interface() {
    let (case, other) = tr487_on_an_external_model(
        |rotor| std::sync::Arc::new(SpedUp(rotor)),
        "the test's sped-up rotor",
    );
    let (a, b) = (
        cierva_harness::suite::outcome::run_case(&case),
        cierva_harness::suite::outcome::run_case(&other),
    );
    assert_eq!(a.len(), b.len());
    let mut sped_up = 0;
    for (x, y) in a.iter().zip(&b) {
        assert!(y.error.is_none(), "{:?}", y.error);
        for (p, q) in x.quantities.iter().zip(&y.quantities) {
            assert_eq!(p.quantity, q.quantity);
            let moved = if p.quantity == "rotor_omega_rad_s" {
                SPED_UP_RAD_S
            } else {
                0.0
            };
            assert_eq!(q.value, p.value + moved, "{}", p.quantity);
            sped_up += usize::from(moved != 0.0);
        }
    }
    assert!(sped_up > 0, "TR 487's case checks no rotor speed");
}

/// cierva's PCA-2 rotor served by `cierva serve` (a rotor file: it answers `autorotation`,
/// protocol `/2`, persistent) gives TR 487's case the built-in values, every verdict the same:
/// an `autorotation` check runs on any model that answers the request. Before, the check ran on
/// cierva's rotor file alone and the protocol had no such request.
#[test]
fn a_rotor_through_the_protocol_autorotates_as_the_built_in_one() {
    let case = "cases/naca-tr487-vertical-descent.yaml";
    let dir = crate::common::scratch("rotor-served");
    super::common::new_suite(&dir);
    std::os::unix::fs::symlink(repo_root().join("aircraft"), dir.join("aircraft")).unwrap();
    std::os::unix::fs::symlink(repo_root().join("flight-refs"), dir.join("flight-refs")).unwrap();
    let text = std::fs::read_to_string(repo_root().join(case)).unwrap();
    let mut v: serde_yaml::Value = serde_yaml::from_str(&text).unwrap();
    let file = v["model"]["rotor"]["file"].as_str().unwrap().to_string();
    let external: serde_yaml::Value = serde_yaml::from_str(&format!(
        "external: {{command: [cierva, serve, {file}], protocol: cierva-external/2, persistent: true, timeout_s: 600}}"
    ))
    .unwrap();
    v["model"] = external;
    std::fs::write(dir.join(case), serde_yaml::to_string(&v).unwrap()).unwrap();
    let args = ["validate", "--no-report", "--format", "json"];
    let (_, built_in, err) = cierva_on_path(
        &repo_root(),
        &[&args[..], &[repo_root().join(case).to_str().unwrap()]].concat(),
    );
    let built_in = quantities(&built_in);
    assert!(!built_in.is_empty(), "{err}");
    let (_, served, err) = cierva_on_path(&dir, &[&args[..], &[case]].concat());
    let _ = std::fs::remove_dir_all(&dir);
    let served = quantities(&served);
    same_quantities(&built_in, &served, &err);
}

/// The test model behind the protocol, whose refined self cannot trim (its linear model as the
/// model's).
#[derive(Debug)]
struct RefinedCannotTrim(std::sync::Arc<dyn cierva_harness::external::FlightModel>);

impl cierva_harness::external::FlightModel for RefinedCannotTrim {
    fn describe(&self) -> String {
        self.0.describe()
    }
    fn parameters(&self) -> Result<Vec<cierva_harness::external::Parameter>, String> {
        self.0.parameters()
    }
    fn trim(&self, request: &Request) -> Result<cierva_harness::external::Quantities, String> {
        self.0.trim(request)
    }
    fn linear_model(&self, request: &Request) -> Result<cierva_model::LinearModel, String> {
        self.0.linear_model(request)
    }
    fn refinements(&self) -> Vec<cierva_harness::external::Refinement> {
        #[derive(Debug)]
        struct NoTrim(std::sync::Arc<dyn cierva_harness::external::FlightModel>);
        impl cierva_harness::external::FlightModel for NoTrim {
            fn describe(&self) -> String {
                self.0.describe()
            }
            fn parameters(&self) -> Result<Vec<cierva_harness::external::Parameter>, String> {
                self.0.parameters()
            }
            fn linear_model(&self, request: &Request) -> Result<cierva_model::LinearModel, String> {
                self.0.linear_model(request)
            }
        }
        vec![cierva_harness::external::Refinement {
            parameter: "the test's refinement, which cannot trim".into(),
            words: "once".into(),
            ratio: 2.0,
            formal_order: 2.0,
            model: std::sync::Arc::new(NoTrim(self.0.clone())),
        }]
    }
}

/// A quantity the refined discretisation gives no value for has no verdict, and says why
/// (issue 51, item 3): its `u_num` is not known, not 0. The damping, which the refined model
/// gives, keeps its `u_num` (0: the same linear model).
#[test]
fn a_quantity_the_refined_run_cannot_give_has_no_verdict() {
    use cierva_harness::uncertainty::propagate::{Propagation, PropagationSettings};
    super::external::require_python3();
    let dir = suite_in("refined-cannot-trim", "cierva-external/2", true);
    let mut case = cierva_harness::suite::case::load(&dir.join("cases/model.yaml")).unwrap();
    let cierva_harness::checks::subject::Subject::External(e) = &mut case.subject else {
        panic!("the test case's model is external");
    };
    e.model = std::sync::Arc::new(RefinedCannotTrim(e.model.clone()));
    let settings = PropagationSettings {
        samples: 8,
        seed: 0,
        validation_only: false,
        method: Propagation::Sampled,
    };
    let study = cierva_harness::uncertainty::study::propagate(&case, settings, || ()).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let row = |check: &str| study.results.iter().find(|r| r.check == check).unwrap();
    let pitch = row("pitch");
    assert!(pitch.u_num.is_nan(), "{pitch:?}");
    assert!(
        pitch
            .u_num_missing
            .as_deref()
            .is_some_and(|w| w.contains("does not provide a trim")),
        "{pitch:?}"
    );
    assert!(pitch.verdict.is_none());
    assert!(
        pitch
            .reason
            .starts_with("no verdict: a refined discretisation gave no value"),
        "{}",
        pitch.reason
    );
    let damping = row("damping");
    assert_eq!(damping.u_num, 0.0);
    assert!(damping.u_num_missing.is_none());
}

/// How closely a request carrying every declared parameter at its nominal value must give the
/// model's own answer: a value declared in another unit than the file's (degrees for radians,
/// deg/kPa for rad/Pa) goes back through its conversion, a few rounding steps, which the solves
/// inside an evaluation carry on (the trim's Newton steps). Measured: 5.5e-13 in the
/// Montgomerie-Parsons' linear model at 50 mph. It was 1.4e-11, and this guard 1e-9, while
/// every evaluation iterated the rotor's flapping to the body's accelerations by Anderson's
/// mixing, whose least squares near convergence magnify a rounding difference; trims and
/// linearisations no longer iterate (issue 51's performance). A conversion's slip (degrees
/// taken as radians) moves the answer by its whole size.
const NOMINAL_REQUEST_AGREEMENT: f64 = 1e-12;

/// A declared parameter's nominal value is the model as it is: for every shipped aircraft and
/// rotor, a request that sets every declared parameter to its nominal value gets the answer of
/// a request that sets none (trim, linear model; autorotation). Before, the hub angle-of-attack
/// factor was declared at 1 where the aircraft leaves it unset, and factor 1 dropped what pitch
/// rate adds to the hub's angle, so a study's nominal point was not the model.
#[test]
fn a_request_at_every_declared_nominal_value_is_the_model_as_it_is() {
    use cierva_harness::external::Values;
    let close = |x: f64, y: f64| (x - y).abs() <= NOMINAL_REQUEST_AGREEMENT * (1.0 + y.abs());
    let nominal = |model: &dyn cierva_harness::external::FlightModel| -> Values {
        let declared = model.parameters().unwrap();
        assert!(!declared.is_empty(), "{}", model.describe());
        declared.into_iter().map(|p| (p.name, p.nominal)).collect()
    };
    for (file, airspeed_mph) in [("vpm-m16", 60.0), ("montgomerie-parsons", 50.0)] {
        let path = repo_root().join(format!("aircraft/{file}.yaml"));
        let loaded = cierva_harness::inputs::aircraft::load(&path).unwrap();
        let model = cierva_harness::external::CiervaAircraft::new(&loaded);
        let values = nominal(&model);
        assert!(
            values.contains_key("corrections.hub_aoa_factor"),
            "{values:?}"
        );
        let bare = Request::at(
            TrimRequest::level(airspeed_mph),
            Loading {
                mass_kg: None,
                density_altitude_ft: 0.0,
            },
        );
        let set = Request {
            parameters: values,
            ..bare.clone()
        };
        let (trim_a, lin_a) = model.trim_and_linear_model(&bare).unwrap();
        let (trim_b, lin_b) = model.trim_and_linear_model(&set).unwrap();
        for ((name, x), (_, y)) in trim_a.iter().zip(&trim_b) {
            assert!(close(*y, *x), "{file} trim {name}: {y} against {x}");
        }
        assert_eq!(lin_a.states(), lin_b.states());
        for (m, n, what) in [(lin_a.a(), lin_b.a(), "A"), (lin_a.b(), lin_b.b(), "B")] {
            assert_eq!(m.shape(), n.shape());
            // Column-major, as nalgebra stores them.
            for (k, (x, y)) in m.iter().zip(n.iter()).enumerate() {
                let (i, j) = (k % m.nrows(), k / m.nrows());
                assert!(close(*y, *x), "{file} {what}[{i}][{j}]: {y} against {x}");
            }
        }
    }
    for (file, case) in [
        (
            "TR 487's PCA-2 rotor",
            "cases/naca-tr487-vertical-descent.yaml",
        ),
        ("TR 515's PCA-2 rotor", "cases/naca-tr515-table-iii.yaml"),
    ] {
        let case = cierva_harness::suite::case::load(&repo_root().join(case));
        let Ok(case) = case else {
            panic!("{file}: {case:?}");
        };
        let model = cierva_harness::checks::model_of(&case.subject).unwrap();
        let values = nominal(model.as_ref());
        let tunnel = case
            .checks
            .iter()
            .find_map(|c| c.behaviour().tunnel().copied())
            .unwrap_or_else(|| panic!("{file}: no tunnel condition"));
        let ask = |parameters: Values| {
            let request = cierva_harness::external::TunnelRequest { tunnel, parameters };
            match model.autorotation(&request).unwrap() {
                cierva_harness::run::autorotation::Autorotated::Equilibrium(e) => e.quantities,
                other => panic!("{file}: {other:?}"),
            }
        };
        let (a, b) = (ask(Values::new()), ask(values));
        for ((name, x), (_, y)) in a.iter().zip(&b) {
            assert!(close(*y, *x), "{file} {name}: {y} against {x}");
        }
    }
}

/// `--method auto` chooses the first-order propagation by what a case asks (autorotation
/// checks: each evaluation a table of autorotation searches), not by the subject's type: TR
/// 487's case on cierva's rotor behind the model interface (an `external` subject) is propagated
/// as the rotor file's case is, with the same inputs and every quantity's `u_input`, `u_num` and
/// verdict the same. Before, `auto` sampled any model but a rotor file (its Saltelli design, 50
/// times the evaluations).
#[test]
fn the_automatic_propagation_follows_the_checks_not_the_subjects_type() {
    use cierva_harness::uncertainty::propagate::{Propagation, PropagationSettings};
    let (case, other) = tr487_on_an_external_model(
        |rotor| std::sync::Arc::new(rotor),
        "cierva's rotor behind the model interface",
    );
    let settings = PropagationSettings {
        samples: 8,
        seed: 0,
        validation_only: true,
        method: Propagation::Auto,
    };
    let study = |c| cierva_harness::uncertainty::study::propagate(c, settings, || ()).unwrap();
    let (a, b) = (study(&case), study(&other));
    assert!(a.method.starts_with("first order"), "{}", a.method);
    assert_eq!(b.method, a.method);
    assert_eq!(b.evaluations, a.evaluations);
    let names = |s: &cierva_harness::uncertainty::propagate::CaseUncertainty| {
        s.inputs.iter().map(|i| i.name.clone()).collect::<Vec<_>>()
    };
    assert_eq!(names(&b), names(&a));
    assert_eq!(b.results.len(), a.results.len());
    assert!(!a.results.is_empty());
    for (x, y) in a.results.iter().zip(&b.results) {
        assert_eq!((&y.check, &y.quantity), (&x.check, &x.quantity));
        assert_eq!(y.u_input, x.u_input, "{}", x.quantity);
        assert_eq!(y.u_num, x.u_num, "{}", x.quantity);
        assert_eq!(y.verdict, x.verdict, "{}", x.quantity);
    }
}

/// A start goes out with an answer and comes back with a request (`start`, protocol `/2`):
/// cierva's VPM M16 built in and served by `cierva serve` (persistent) give the same start
/// after the same trim, to the bit, and the same trim from it; the trim from a start lands on
/// the cold trim within the trim's tolerance; a start that is not one is a located error.
#[test]
fn a_start_goes_out_with_an_answer_and_comes_back_with_a_request() {
    use cierva_harness::external::command::{ExternalCommand, Protocol};
    let path = repo_root().join("aircraft/vpm-m16.yaml");
    let file = cierva_harness::inputs::aircraft::load(&path).unwrap();
    let built_in = cierva_harness::external::CiervaAircraft::new(&file);
    let served = ExternalCommand::speaking(
        vec![
            env!("CARGO_BIN_EXE_cierva").to_string(),
            "serve".to_string(),
            path.display().to_string(),
        ],
        repo_root(),
        std::time::Duration::from_secs(600),
        Protocol::V2,
    )
    .persistent();
    let at = Request::at(
        TrimRequest::level(60.0),
        Loading {
            mass_kg: Some(450.0),
            density_altitude_ft: 2000.0,
        },
    );
    let iterate = at.clone().with("corrections.propeller_blockage", 0.5);
    // The same quantities (the served answer's in the order of their names).
    let sorted = |mut q: Vec<(&'static str, f64)>| {
        q.sort_by(|a, b| a.0.cmp(b.0));
        q
    };
    assert_eq!(
        sorted(built_in.trim(&iterate).unwrap()),
        served.trim(&iterate).unwrap()
    );
    let of = cierva_harness::external::AnswerOf::Trim;
    let start = built_in
        .start_after(&iterate, &of)
        .expect("the aircraft gives a start");
    assert_eq!(served.start_after(&iterate, &of), Some(start.clone()));
    // Only the answer asked of gives it: the served model was asked no linear model.
    let linear = cierva_harness::external::AnswerOf::LinearModel;
    assert_eq!(served.start_after(&iterate, &linear), None);
    // A trial step from the iterate, started there, and the same step cold.
    let step = at.with("corrections.propeller_blockage", 0.55);
    let from = step.clone().starting_at(Some(start));
    let warm = built_in.trim(&from).unwrap();
    assert_eq!(sorted(warm.clone()), served.trim(&from).unwrap());
    let cold = built_in.trim(&step).unwrap();
    let value = |q: &[(&str, f64)], name: &str| q.iter().find(|(n, _)| *n == name).unwrap().1;
    // The trim's residuals are within 1e-7 (scaled): the two solutions agree to a few times
    // that (the model crate's `a_warm_start_lands_on_the_cold_trim_for_less`).
    assert!((value(&warm, "pitch_deg") - value(&cold, "pitch_deg")).abs() < 1e-4);
    assert!((value(&warm, "rotor_rpm") - value(&cold, "rotor_rpm")).abs() < 1e-3);
    let bad = step.starting_at(Some(cierva_harness::external::Start(std::sync::Arc::new(
        serde_json::json!({"x": "not numbers"}),
    ))));
    for e in [built_in.trim(&bad), served.trim(&bad)].map(Result::unwrap_err) {
        assert!(
            e.contains("the request's `start` is not a start cierva's aircraft gave"),
            "{e}"
        );
    }
}

/// A user's model that gives a `start` with each answer gets it back with the fit's next
/// requests near it: every request a fit sends with a start carries the start of an answer the
/// model gave before at the same condition (the fit's iterate), the first carries none, and
/// the fit is the one the model gives without starts.
#[test]
fn a_fit_hands_a_models_start_back_from_its_iterate() {
    super::external::require_python3();
    let dir = suite_in("fit-starts", "cierva-external/2", true);
    let logged = MODEL
        .replace(
            "            body = answer(r)\n",
            "            body = answer(r)\n            if 'trim' in body or 'linear_model' in body:\n                body['start'] = {'values': r['parameters'], 'airspeed_mph': r['condition']['airspeed_mph']}\n            open('requests.jsonl', 'a').write(json.dumps({'compute': r['compute'], 'parameters': r.get('parameters'), 'start': r.get('start')}) + '\\n')\n",
        );
    std::fs::write(dir.join("cases/model.py"), logged).unwrap();
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    std::fs::write(
        dir.join("fits/model.yaml"),
        fit_file(3.7, 0.05, -0.95, 0.01),
    )
    .unwrap();
    let file = cierva_harness::fit::file::load(&dir.join("fits/model.yaml"));
    let file = file.unwrap_or_else(|e| panic!("{}", e.render()));
    let r = cierva_harness::fit::fit(&file.problem);
    assert_eq!(r.status, cierva_harness::fit::Status::Converged, "{r:?}");
    let log = std::fs::read_to_string(dir.join("cases/requests.jsonl")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let requests: Vec<serde_json::Value> = log
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .filter(|r: &serde_json::Value| r["compute"] != "describe")
        .collect();
    assert!(requests[0]["start"].is_null(), "{}", requests[0]);
    let mut answered: Vec<serde_json::Value> = Vec::new();
    let mut started = 0;
    for r in &requests {
        if r["start"].is_null() {
            // Only the fit's first point (its trim and its linear model) starts where the
            // model starts it.
            assert_eq!(r["parameters"], requests[0]["parameters"], "{r}");
        } else {
            started += 1;
            assert_eq!(r["start"]["airspeed_mph"], 60.0, "{r}");
            assert!(
                answered.contains(&r["start"]["values"]),
                "a start from no earlier answer: {r}"
            );
            assert_ne!(r["start"]["values"], r["parameters"], "{r}");
        }
        answered.push(r["parameters"].clone());
    }
    // Every trial step and finite difference after it starts from an iterate.
    assert_eq!(started, requests.len() - 2, "{log}");
    // The model is exact in its parameters: the fit lands on the hidden values, started or not.
    assert!((r.values[1] - 0.7).abs() < 1e-6, "{:?}", r.values);
    assert!((r.values[0] - 0.95 / 1.2).abs() < 1e-6, "{:?}", r.values);
}

/// A model behind the command protocol forgets a study point's answers when told to
/// (`FlightModel::forget`), as cierva's aircraft does, so that a long study does not keep every
/// answer: the same request after it runs the command again. A bounded memo forgets all it
/// holds at its limit and finds the same results again.
#[test]
fn remembered_answers_are_forgotten_when_told_and_at_a_memos_limit() {
    use cierva_harness::external::command::{ExternalCommand, Protocol};
    super::external::require_python3();
    let dir = suite_in("forget", "cierva-external/2", false);
    let counted = MODEL.replace(
        "    # HOOK\n",
        "    open('asked.txt', 'a').write(r['compute'] + '\\n')\n",
    );
    std::fs::write(dir.join("cases/model.py"), counted).unwrap();
    let model = ExternalCommand::speaking(
        vec!["python3".into(), "model.py".into()],
        dir.join("cases"),
        std::time::Duration::from_secs(30),
        Protocol::V2,
    );
    let request = Request::at(
        TrimRequest::level(60.0),
        Loading {
            mass_kg: Some(400.0),
            density_altitude_ft: 0.0,
        },
    )
    .with("m_q_scale", 0.8);
    let asked = || {
        std::fs::read_to_string(dir.join("cases/asked.txt"))
            .unwrap()
            .lines()
            .filter(|l| *l == "trim")
            .count()
    };
    let first = model.trim(&request).unwrap();
    assert_eq!(model.trim(&request).unwrap(), first);
    assert_eq!(asked(), 1);
    model.forget(&[("m_q_scale".to_string(), 0.7)].into());
    assert_eq!(model.trim(&request).unwrap(), first);
    assert_eq!(
        asked(),
        1,
        "another point's answers forgotten, not this one's"
    );
    model.forget(&request.parameters);
    assert_eq!(model.trim(&request).unwrap(), first);
    assert_eq!(asked(), 2);
    let _ = std::fs::remove_dir_all(&dir);

    let memo = cierva_harness::run::memo::Memo::<usize>::bounded(2);
    let runs = std::sync::atomic::AtomicUsize::new(0);
    let get = |key: &str| {
        *memo
            .get_or(key.to_string(), || {
                runs.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                Ok(key.len())
            })
            .unwrap()
    };
    assert_eq!((get("a"), get("a"), get("bb")), (1, 1, 2));
    assert_eq!(runs.load(std::sync::atomic::Ordering::SeqCst), 2);
    // A third key finds the memo full: it forgets both, then holds the third.
    assert_eq!(get("ccc"), 3);
    assert!(memo.get("a").is_none() && memo.get("ccc").is_some());
    assert_eq!(get("a"), 1);
    assert_eq!(runs.load(std::sync::atomic::Ordering::SeqCst), 4);
}

/// A fit of a model that gives its trim alone reports no modes in words, not a table of NaN
/// (found trying a user's trim-only model with the installed binary).
#[test]
fn a_fit_of_a_trim_only_model_reports_no_modes_in_words() {
    super::external::require_python3();
    let dir = suite_in("trim-only-fit", "cierva-external/2", true);
    let trim_only = MODEL.replace(
        "'computes': ['trim', 'linear_model'],",
        "'computes': ['trim'],",
    );
    std::fs::write(dir.join("cases/model.py"), trim_only).unwrap();
    std::fs::create_dir_all(dir.join("fits")).unwrap();
    std::fs::write(
        dir.join("fits/trim-only.yaml"),
        "id: trim-only\ntitle: the test model's pitch offset\n\
         provenance: {source: 'a test of harness/tests/suite/model_interface.rs'}\n\
         subject: {case: ../cases/model.yaml}\nparameters:\n  pitch_offset_deg: {}\n\
         targets:\n  - {condition: {airspeed_mph: 60.0}, quantity: pitch_deg, reference: 3.5, standard_error: 0.05, source: the test's own}\n",
    )
    .unwrap();
    let (code, out, err) = cierva_in(&dir, &["fit", "fits/trim-only.yaml"]);
    let report = std::fs::read_to_string(dir.join("reports/fits/trim-only.md"));
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 0, "{out}{err}");
    let report = report.unwrap();
    assert!(
        report.contains(
            "## Longitudinal modes before and after\n\nNone found: the model gives no linear model"
        ),
        "{report}"
    );
    assert!(!report.contains("NaN"), "{report}");
}

/// A range taken from the data it is judged against (`taken_from`) makes that check's verdict
/// circular: reported apart with the input named, never counted as validation evidence; a
/// check whose inputs' ranges come from elsewhere is judged as before. A `taken_from` entry that
/// names a check the case does not have, or is not a case id or `case/check`, is an error.
#[test]
fn a_range_taken_from_the_data_it_is_judged_against_makes_a_circular_verdict() {
    super::external::require_python3();
    let dir = suite_in("circular", "cierva-external/2", true);
    let circular = MODEL.replace(
        "'range': {'lower': -2.0, 'upper': 2.0, 'source': 'the test model own'}}",
        "'range': {'lower': -2.0, 'upper': 2.0, 'source': 'the pitch check\\'s own band', 'taken_from': ['model/pitch']}}",
    );
    assert_ne!(circular, MODEL);
    std::fs::write(dir.join("cases/model.py"), &circular).unwrap();
    let case = std::fs::read_to_string(dir.join("cases/model.yaml")).unwrap();
    let validation = case
        .replace("class: regression", "class: validation")
        .replace(
            "  pitch:\n    absolute: 0.5\n",
            "  pitch:\n    absolute: 0.5\n    standard_deviation: 0.2\n",
        );
    assert_ne!(validation, case);
    std::fs::write(dir.join("cases/model.yaml"), validation).unwrap();
    let args = [
        "uncertainty",
        "cases/model.yaml",
        "--samples",
        "16",
        "--format",
        "json",
    ];
    let (code, out, err) = cierva_in(&dir, &args);
    assert_eq!(code, 0, "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let result = |check: &str| {
        v["results"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["check"] == check)
            .unwrap_or_else(|| panic!("no {check}: {v}"))
            .clone()
    };
    let pitch = result("pitch");
    assert_eq!(
        pitch["circular"], "pitch_offset_deg has a range taken from this check's own data",
        "{pitch}"
    );
    assert!(
        pitch["reason"]
            .as_str()
            .unwrap()
            .ends_with("so the verdict is reported apart and is no evidence."),
        "{pitch}"
    );
    assert!(result("damping")["circular"].is_null());
    let (code, text, err) = cierva_in(&dir, &args[..4]);
    assert_eq!(code, 0, "{text}{err}");
    assert!(
        text.contains(
            "apart, 1 circular (judged with an input range taken from their own data: no evidence)"
        ),
        "{text}"
    );
    let typo = circular.replace(
        "'taken_from': ['model/pitch']",
        "'taken_from': ['model/pich']",
    );
    std::fs::write(dir.join("cases/model.py"), typo).unwrap();
    let (code, out, err) = cierva_in(&dir, &args);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("`pitch_offset_deg`'s range is `taken_from` `model/pich`, but case `model` has no check `pich` (its checks: damping, pitch)"),
        "{err}"
    );
    let bad = circular.replace(
        "'taken_from': ['model/pitch']",
        "'taken_from': ['model/pitch check']",
    );
    std::fs::write(dir.join("cases/model.py"), bad).unwrap();
    let (code, out, err) = cierva_in(&dir, &args);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("its range's `taken_from[0]`: `model/pitch check` is not a case id or `case-id/check-id`"),
        "{err}"
    );
}
