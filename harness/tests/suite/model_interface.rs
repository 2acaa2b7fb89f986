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
use std::path::PathBuf;

/// The test model (Python 3, standard library): `describe`, trim and linear model, with two
/// declared parameters; it refuses a parameter it does not declare, as a model should.
const MODEL: &str = r#"import json, sys
r = json.load(open(sys.argv[1]))
assert r['protocol'] == 'cierva-external/2', r['protocol']
def answer(body):
    body['protocol'] = 'cierva-external/2'
    open(r['response'], 'w').write(json.dumps(body))
if r['compute'] == 'describe':
    answer({'describe': {
        'computes': ['trim', 'linear_model'],
        'states': ['u', 'w', 'q', 'theta'],
        'controls': ['eta_s'],
        'parameters': [
            {'name': 'pitch_offset_deg', 'unit': 'deg', 'meaning': 'a pitch datum offset',
             'nominal': 0.0,
             'range': {'lower': -2.0, 'upper': 2.0, 'source': 'the test model own'}},
            {'name': 'm_q_scale', 'unit': '1', 'meaning': 'a pitch damping factor',
             'nominal': 1.0,
             'range': {'lower': 0.5, 'upper': 1.5, 'source': 'the test model own'}}]}})
    sys.exit(0)
p = {'pitch_offset_deg': 0.0, 'm_q_scale': 1.0}
for k, v in r['parameters'].items():
    if k not in p:
        sys.stderr.write('unknown parameter ' + k + '\n'); sys.exit(4)
    p[k] = v
v = r['condition']['airspeed_mph']
if r['compute'] == 'trim':
    answer({'trim': {'pitch_deg': 3.0 + p['pitch_offset_deg'],
                     'stick_longitudinal_percent': 80.0 - 0.5 * v}})
elif r['compute'] == 'linear_model':
    answer({'linear_model': {'states': ['u', 'w', 'q', 'theta'], 'controls': ['eta_s'],
        'a': [[-0.05, 0.1, 0.0, -9.81], [-0.3, -0.8, 30.0, 0.0],
              [0.01, -0.05, -1.2 * p['m_q_scale'], 0.0], [0.0, 0.0, 1.0, 0.0]],
        'b': [[0.0], [0.1], [-0.02], [0.0]]}})
else:
    sys.stderr.write('no ' + r['compute'] + '\n'); sys.exit(5)
"#;

/// A suite in a fresh folder with the test model and a case on it: `M_q` against
/// [-1.0, -0.9] (outside: the model gives -1.2) and the trim pitch against 3 +- 0.5 (inside).
fn suite(name: &str, protocol: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "cierva-model-interface-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("cases")).unwrap();
    std::fs::write(dir.join("cierva.toml"), "format_version = 1\n").unwrap();
    std::fs::copy(
        repo_root().join("cases/tolerances.yaml"),
        dir.join("cases/tolerances.yaml"),
    )
    .unwrap();
    std::fs::write(dir.join("cases/model.py"), MODEL).unwrap();
    std::fs::write(
        dir.join("cases/model.yaml"),
        format!(
            "id: model\ntitle: a model that declares its parameters\nclass: regression\n\
             provenance: {{source: a test of harness/tests/suite/model_interface.rs}}\n\
             model:\n  external:\n    command: [python3, model.py]\n    protocol: {protocol}\n\
             \x20   timeout_s: 30\n    mass_kg: 400.0\n\
             tolerances:\n  band:\n    absolute: 0.05\n    reason: the test's own\n\
             \x20 pitch:\n    absolute: 0.5\n    reason: the test's own\n\
             checks:\n  - id: damping\n    kind: derivative\n    derivative: M_q\n\
             \x20   condition: {{airspeed_mph: 60.0}}\n\
             \x20   expect:\n      value: {{value: -0.95, tolerance: band}}\n\
             \x20   expected_failure: the test model's M_q is -1.2, outside on purpose\n\
             \x20 - id: pitch\n    kind: trim\n    condition: {{airspeed_mph: 60.0}}\n\
             \x20   expect:\n      pitch_deg: {{value: 3.0, tolerance: pitch}}\n"
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
