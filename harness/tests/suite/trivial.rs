//! Trivial predictors that need the model run: an aircraft's modes exist only once it is
//! trimmed and linearised, so its mode checks are tried against their neighbouring modes when
//! they run, not when the case loads.

use super::common::cierva;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap()
}

/// `cierva validate` on a case written to a temporary file: exit code and stdout.
fn validate_case(name: &str, yaml: &str) -> (i32, String) {
    let dir = crate::common::scratch("trivial");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.yaml"));
    std::fs::write(&path, yaml).unwrap();
    let (code, out, _) = cierva(&["validate", path.to_str().unwrap(), "--no-report", "--quiet"]);
    (code, out)
}

fn phugoid_case(name: &str, interval: [f64; 2]) -> String {
    let aircraft = root().join("aircraft/vpm-m16.yaml");
    format!(
        "id: {name}\ntitle: a phugoid period bound\nclass: validation\nprovenance:\n  source: \"test: the bound is the test's\"\nmodel:\n  aircraft:\n    file: {}\n    mass_kg: 425.0\n    density_altitude_ft: 2000.0\ntolerances:\n  period:\n    interval: [{}, {}]\n    reason: \"test: the bound under test\"\nchecks:\n  - id: phugoid-60mph-period\n    kind: mode\n    mode: phugoid\n    condition: {{airspeed_mph: 60.0}}\n    expect:\n      period_s: {{tolerance: period}}\n",
        aircraft.display(),
        interval[0],
        interval[1]
    )
}

/// A phugoid period bound of 1-1000 s on the linearised VPM M16 also holds its Dutch roll's
/// and short period's periods (a few seconds): the check is refused when it runs, naming the
/// neighbour, and never passes. The flight's 12-15 s holds no other mode of the aircraft, and
/// the same check with it runs to a verdict (a failure: cierva's phugoid is slower).
#[test]
fn an_aircraft_mode_check_a_neighbouring_mode_passes_is_refused_when_it_runs() {
    let (code, out) = validate_case("wide", &phugoid_case("wide", [1.0, 1000.0]));
    assert_ne!(code, 0, "{out}");
    assert!(
        out.contains("refused when it ran")
            && out.contains("a neighbouring mode of the same model"),
        "{out}"
    );
    let (_, out) = validate_case("flight", &phugoid_case("flight", [12.0, 15.0]));
    assert!(!out.contains("refused"), "{out}");
    assert!(out.contains("phugoid-60mph-period"), "{out}");
}
