//! Bad input gets a clear, located error, never a panic: every file in `tests/bad-input/` is a
//! broken case whose header says what the error must contain and on which line it must point
//! (see `common`).

use crate::common;

use cierva_harness::suite::case;
use std::path::Path;

#[test]
fn every_bad_case_gets_its_located_error() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-input");
    let problems = common::check_fixtures(&dir, 30, case::load);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The shared tolerance library: a case uses its tolerances by name, may not define one of the
/// same name, and the library itself is checked (a table interval depends on the check, so the
/// library refuses one). The shipped library loads, and `discover` does not take it for a case.
#[test]
fn shared_tolerances_are_used_and_never_shadowed() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let dir = crate::common::scratch("library");
    let cases = dir.join("cases");
    std::fs::create_dir_all(&cases).unwrap();
    std::fs::copy(
        root.join("cases").join(case::LIBRARY_FILE),
        dir.join(case::LIBRARY_FILE),
    )
    .unwrap();
    let model = root.join("flight-refs/seed002-vpm-m16-60kn.yaml");
    let case_text = |local: &str| {
        format!(
            "id: uses-library\ntitle: t\nclass: verification\nprovenance: {{source: seed 002 Table 1}}\n\
             model: {{linear_model_file: {}}}\n{local}checks:\n  - id: phugoid\n    kind: mode\n    \
             mode: phugoid\n    expect:\n      eigenvalue_real_per_s: {{value: -0.0737, tolerance: printed-4dp}}\n",
            model.display()
        )
    };
    let path = cases.join("uses-library.yaml");
    std::fs::write(&path, case_text("")).unwrap();
    let c = case::load(&path).expect("a case uses the shared library found above its folder");
    let t = &c.checks[0].expectations[0].tolerance;
    assert_eq!(t.name, "printed-4dp");
    assert!(t.reason.contains("4 decimals"), "{}", t.reason);

    std::fs::write(
        &path,
        case_text("tolerances:\n  printed-4dp: {absolute: 1.0, reason: wide}\n"),
    )
    .unwrap();
    let e = case::load(&path).unwrap_err().render();
    assert!(
        e.contains("uses-library.yaml:7:") && e.contains("is a shared tolerance"),
        "{e}"
    );

    std::fs::write(
        dir.join(case::LIBRARY_FILE),
        "title: t\ntolerances:\n  flight:\n    interval_from: {file: x.yaml, column: c}\n    reason: r\n",
    )
    .unwrap();
    let e = case::load(&path).unwrap_err().render();
    assert!(
        e.contains("tolerances.yaml:4:") && e.contains("cannot take its interval from a table"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);

    let shipped = case::load_library(&root.join("cases").join(case::LIBRARY_FILE)).unwrap();
    assert!(shipped.tolerances.len() >= 7);
    let found = case::discover(&[root.join("cases")]).unwrap();
    assert!(found.iter().all(|p| !p.ends_with(case::LIBRARY_FILE)));
}

/// A mass above the aircraft's stated maximum all-up mass (`mass.max_kg`) is bad input wherever
/// it is asked: a command's `--mass-kg` (exit 2, naming the option and the mass in pounds it
/// probably is) as a case's `mass_kg` (the fixture `mass-in-pounds.yaml`); the maximum itself
/// is accepted.
#[test]
fn a_mass_above_the_aircrafts_maximum_is_refused() {
    let aircraft = common::repo_root().join("aircraft/vpm-m16.yaml");
    let aircraft = aircraft.to_str().unwrap();
    let (code, out, err) =
        common::cierva(&["trim", aircraft, "--airspeed-mph", "60", "--mass-kg", "992"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains(
            "error: --mass-kg 992: 992 kg is above the maximum all-up mass of vpm-m16 (450 kg"
        ) && err.contains("a mass in pounds? 992 lb is 450.0 kg"),
        "{err}"
    );
    let (code, out, err) = common::cierva(&[
        "trim",
        aircraft,
        "--airspeed-mph",
        "60",
        "--mass-kg",
        "450",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{out}{err}");
}

/// A correction outside what the model accepts is located in its corrections file (line and
/// column of the correction), by `validate --corrections` and by a command's `--corrections`;
/// a suite marker of another format version is located at its `format_version` line (issue 50:
/// both named no line).
#[test]
fn a_correction_out_of_range_and_a_format_version_are_located() {
    let dir = crate::common::scratch("located");
    common::new_suite(&dir);
    std::os::unix::fs::symlink(common::repo_root().join("aircraft"), dir.join("aircraft")).unwrap();
    std::fs::copy(
        common::repo_root().join("cases/vpm-m16-trim-max-weight.yaml"),
        dir.join("cases/vpm-m16-trim-max-weight.yaml"),
    )
    .unwrap();
    std::fs::create_dir_all(dir.join("corrections")).unwrap();
    for (line, field) in [
        ("hub_aoa_factor: 5.0", "corrections.hub_aoa_factor"),
        ("propeller_blockage: 3.0", "corrections.propeller_blockage"),
        ("profile_drag_scale: -1.0", "corrections.profile_drag_scale"),
    ] {
        std::fs::write(
            dir.join("corrections/c1.yaml"),
            format!(
                "id: c1\ntitle: t\nprovenance: {{source: test}}\napplies_to: {{aircraft: vpm-m16}}\n\
                 corrections:\n  {line}\n"
            ),
        )
        .unwrap();
        let (code, out, err) = common::cierva_in(
            &dir,
            &[
                "validate",
                "--no-report",
                "--corrections",
                "corrections/c1.yaml",
            ],
        );
        assert_eq!(code, 2, "{out}{err}");
        assert!(
            out.contains(&format!("c1.yaml:6:3: field `{field}`")),
            "{line}: {out}"
        );
        let (code, out, err) = common::cierva_in(
            &dir,
            &[
                "trim",
                "aircraft/vpm-m16.yaml",
                "--airspeed-mph",
                "60",
                "--corrections",
                "corrections/c1.yaml",
            ],
        );
        assert_eq!(code, 2, "{out}{err}");
        assert!(
            err.contains(&format!("c1.yaml:6:3: field `{field}`")),
            "{line}: {err}"
        );
    }
    std::fs::write(
        dir.join("cierva.toml"),
        "# my suite\n\nformat_version = 7\n",
    )
    .unwrap();
    let (code, out, err) = common::cierva_in(&dir, &["validate", "--no-report"]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        format!("{out}{err}").contains("cierva.toml:3:1: format_version 7"),
        "{out}{err}"
    );
}
