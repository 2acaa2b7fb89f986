//! Inputs that ask for too much get a located error that states the limit, never an abort or a
//! run without end (issue 35, "Bad input", found by fuzzing the shipped files): a count that
//! sizes an allocation past its limit, a YAML file nested too deep or too large, and a line too
//! long to show whole.

use crate::common;
use cierva_harness::inputs::limits::{MAX_FIT_ITERATIONS, MAX_RECORD_SAMPLES};
use cierva_harness::inputs::yaml::{
    self, EXCERPT_CHARS, MAX_YAML_DEPTH_LEVELS, MAX_YAML_FILE_BYTES,
};
use std::path::{Path, PathBuf};

/// The fuzzer's rotor file: the VPM M16's with `elements: 999999999999`. `cierva autorotate`
/// aborted on the allocation (signal 6); it exits 2 with the limit, at the field.
#[test]
fn a_rotor_with_a_trillion_elements_is_a_located_error_not_an_abort() {
    let dir = scratch("elements");
    let path = dir.join("elements.yaml");
    let shipped =
        std::fs::read_to_string(super::common::repo_root().join("aircraft/vpm-m16-rotor.yaml"))
            .unwrap();
    let text = shipped
        .replace("id: vpm-m16-rotor", "id: elements")
        .replace("  elements: 20\n", "  elements: 999999999999\n");
    assert_ne!(text, shipped);
    std::fs::write(&path, &text).unwrap();
    let line = text
        .lines()
        .position(|l| l == "  elements: 999999999999")
        .unwrap()
        + 1;
    let (code, out, err) = common::cierva(&[
        "autorotate",
        path.to_str().unwrap(),
        "--alpha-deg",
        "8",
        "--airspeed-m-s",
        "25",
    ]);
    assert_eq!(
        code, 2,
        "not a located error (-1 is a signal):\n{out}\n{err}"
    );
    assert!(
        err.contains(&format!("elements.yaml:{line}:3: field `rotor.elements`"))
            && err.contains("elements must be at most 1000 (MAX_ELEMENTS_PER_BLADE"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// An identification set-up asking for a trillion frequencies aborted `cierva identify` on the
/// allocation; it exits 2 with the limit, at the field.
#[test]
fn an_identification_set_up_with_a_trillion_frequencies_is_a_located_error() {
    let dir = scratch("points");
    let config = dir.join("setup.yaml");
    std::fs::write(
        &config,
        "states: [u, w, q, theta]\ncontrols: {eta_s: eta_s_percent}\n\
         frequencies: {from_hz: 0.05, to_hz: 2.0, points: 999999999999}\nkinematics: {theta: q}\n",
    )
    .unwrap();
    let (code, out, err) = common::cierva(&[
        "identify",
        "flight-refs/synthetic-flight-vpm-m16-60mph-stick-sweep.csv",
        "--config",
        config.to_str().unwrap(),
    ]);
    assert_eq!(
        code, 2,
        "not a located error (-1 is a signal):\n{out}\n{err}"
    );
    assert!(
        err.contains("setup.yaml:3:")
            && err.contains("field `frequencies.points`")
            && err.contains("give at most 10000 (MAX_FREQUENCY_POINTS)"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A control history longer than a record may be is refused at the first row past the limit.
#[test]
fn a_control_history_past_the_sample_limit_is_refused_at_its_row() {
    let dir = scratch("rows");
    let path = dir.join("long.csv");
    let mut text = String::from("time_s,eta_s_percent\n");
    for k in 0..=MAX_RECORD_SAMPLES {
        text.push_str(&format!("{k},0\n"));
    }
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::inputs::controls::read(&path).unwrap_err();
    assert_eq!(e.line, Some(MAX_RECORD_SAMPLES + 2), "{e}");
    assert!(
        e.column.is_some() && e.message.contains("MAX_RECORD_SAMPLES"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A simulation longer than the time history's step limit is bad input (exit code 2, the
/// limit named), refused before it flies: a mistyped duration, not a model that failed.
#[test]
fn a_simulation_past_the_step_limit_is_bad_input() {
    let dir = scratch("simulate");
    let out = dir.join("x.csv");
    let (code, _, err) = common::cierva(&[
        "simulate",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        "70",
        "--duration-s",
        "1e12",
        "--shape",
        "step",
        "--control",
        "eta_s",
        "--amplitude-percent",
        "1",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("MAX_STEPS") && !out.exists(), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A fit file asking for more iterations than the limit is refused at the field: each
/// iteration flies every target, so a mistyped count would run for days.
#[test]
fn a_fit_past_the_iteration_limit_is_refused_at_its_field() {
    let root = super::common::repo_root();
    let dir = scratch("fit");
    let path = dir.join("many-iterations.yaml");
    let shipped = std::fs::read_to_string(root.join("fits/pca-2-tr515-low-mu.yaml")).unwrap();
    let text = shipped
        .replace("id: pca-2-tr515-low-mu", "id: many-iterations")
        .replace("../", &format!("{}/", root.display()))
        .replace(
            "options: {tolerance: 1.0e-4}",
            "options: {tolerance: 1.0e-4, max_iterations: 1000000000000}",
        );
    assert!(text.contains("max_iterations: 1000000000000"));
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::fit::file::load(&path).unwrap_err();
    let line = text
        .lines()
        .position(|l| l.starts_with("options:"))
        .unwrap()
        + 1;
    assert_eq!(e.line, Some(line), "{e}");
    assert!(
        e.to_string().contains(&format!(
            "give at most {MAX_FIT_ITERATIONS} (MAX_FIT_ITERATIONS"
        )),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// An autorotation gives up at its stated limit of blade revolutions, with its last residuals:
/// the fuzzer's mutated PCA-2 rotors (a lift slope of 1e-9 per rad, whose blades have no
/// aerodynamic damping; a pitch that swings between +89 and -89 deg along the blade) ran each
/// row of the TR 515 case for seconds (19 s at 200 elements), the brackets' scans and Newton's
/// halvings trying rotor speed after rotor speed, each blade solution integrating up to 200
/// revolutions. (Four elements and 10 deg steps here, so that the 3000 revolutions take a
/// tenth of a second.)
#[test]
fn an_autorotation_gives_up_at_its_revolution_limit_with_its_residuals() {
    use cierva_model::components::autorotation::{
        AutorotationError, AutorotationOptions, MAX_REVOLUTIONS, autorotate,
    };
    let shipped = cierva_harness::inputs::rotor::load(
        &super::common::repo_root().join("aircraft/pca-2-rotor.yaml"),
    )
    .unwrap()
    .rotor;
    let options = AutorotationOptions {
        numerics: cierva_model::components::rotor::Numerics {
            azimuth_step_rad: 10f64.to_radians(),
            ..Default::default()
        },
        ..Default::default()
    };
    let solve = |rotor: &cierva_model::components::rotor::Rotor| {
        let tunnel = cierva_model::components::autorotation::Tunnel {
            alpha_rad: 6.6f64.to_radians(),
            airspeed_m_s: 17.7,
            density_kg_m3: 1.225,
            speed_of_sound_m_s: 340.3,
            collective_shift_rad: rotor.collective_shift_for(1.9f64.to_radians()),
        };
        autorotate(rotor, tunnel, options)
    };
    let mut twisted = shipped.clone();
    twisted.elements = 4;
    twisted.pitch_rad.values = [89.0, -89.0, 89.0, -89.0f64].map(f64::to_radians).to_vec();
    let mut undamped = shipped.clone();
    undamped.elements = 4;
    if let cierva_model::components::airfoil::Airfoil::Analytical(a) = &mut undamped.airfoil {
        a.lift_slope_per_rad = 1e-9;
    }
    for (rotor, says) in [
        (
            &twisted,
            "its last residuals (torque coefficient over solidity",
        ),
        (
            &undamped,
            "no blade solution it tried was periodic (the last: the flapping did not become periodic within 200 revolutions (last change",
        ),
    ] {
        match solve(rotor) {
            Err(
                e @ AutorotationError::RevolutionLimit {
                    revolutions, limit, ..
                },
            ) => {
                assert!(limit == MAX_REVOLUTIONS && revolutions >= limit, "{e}");
                let m = e.to_string();
                assert!(m.contains("(MAX_REVOLUTIONS)") && m.contains(says), "{m}");
            }
            other => panic!("{other:?}"),
        }
    }
    // The shipped rotor, solved the same way, is well within the limit.
    assert!(solve(&shipped).is_ok());
}

/// A scratch folder of this test's own.
fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::scratch(&format!("limits-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every line of a rendered error fits a screen: the excerpt, its `...` marks and the line
/// number's gutter.
fn fits_a_screen(rendered: &str) -> bool {
    rendered
        .lines()
        .skip(1)
        .all(|l| l.chars().count() <= EXCERPT_CHARS + 20)
}

/// The fuzzer's file: a rotor file whose `rotor` is 100,000 flow mappings deep on one 400 kB
/// line. The parser took 25 s to refuse it and the error echoed the whole line; it is refused
/// before parsing, where the depth passes the limit, and the error shows a screen's width of
/// the line.
#[test]
fn a_yaml_file_nested_100000_deep_is_refused_before_parsing() {
    let dir = scratch("deep");
    let path = dir.join("deep.yaml");
    let n = 100_000;
    let text = format!("id: deep\nrotor: {}1{}\n", "{a: ".repeat(n), "}".repeat(n));
    assert!(text.len() > 400_000);
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::inputs::rotor::load(&path).unwrap_err();
    assert!(
        e.message.contains(&format!(
            "nested deeper than {MAX_YAML_DEPTH_LEVELS} levels"
        )),
        "{e}"
    );
    // The top mapping is the first level, `rotor`'s value the second: the 64th `{` opens the
    // 65th, at column 8 + 4 * 63.
    assert_eq!((e.line, e.column), (Some(2), Some(8 + 4 * 63)), "{e}");
    let r = e.render();
    assert!(r.len() < 1000 && fits_a_screen(&r), "{r}");
    assert!(r.contains("| ...") && r.contains("{a: {a: {a:"), "{r}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Block nesting counts as flow nesting does, and what only looks nested does not count: a
/// bracket in a quoted scalar, a comment or a block scalar.
#[test]
fn the_depth_scan_counts_collections_not_brackets() {
    let deepest = |src: &str| {
        (1..100)
            .find(|&d| yaml::too_deep(src, d).is_none())
            .unwrap()
    };
    assert_eq!(deepest("a: 1\n"), 1);
    assert_eq!(deepest("a:\n  b: [1, {c: [2]}]\n"), 5);
    assert_eq!(deepest("a:\n- - x\n  - y\n- z\n"), 3);
    assert_eq!(deepest("- a: 1\n  b:\n    - c\n"), 3);
    assert_eq!(deepest("a: \"[[[[\" # {{{{\nb: '{{''[['\n"), 1);
    assert_eq!(
        deepest("a: >-\n  [[[[ {{{{\n  ]]\nb: [\n  [1],\n  [2]]\n"),
        3
    );
    assert_eq!(deepest("a: {b: [1,\n  2], c: 3}\nd: see [1] and {2}\n"), 3);
    assert_eq!(yaml::too_deep("a:\n  b:\n    c: 1\n", 2), Some((3, 5)));
    // The scan goes by bytes; the column it reports counts characters ("ü" and "é" are two
    // bytes each, so a byte column would be 13), and brackets in a quoted scalar among
    // longer characters are still only text.
    assert_eq!(yaml::too_deep("über: {é: [1]}\n", 2), Some((1, 11)));
    assert_eq!(deepest("tëxt: \"[[ü]]\"\n"), 1);
}

/// The shipped inputs (and the tests' own) nest far less than the limit: the limit leaves them
/// room and refuses none.
#[test]
fn every_shipped_yaml_file_nests_well_within_the_limit() {
    fn yaml_files(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                yaml_files(&p, out);
            } else if p.extension().is_some_and(|x| x == "yaml") {
                out.push(p);
            }
        }
    }
    let root = super::common::repo_root();
    let mut files = Vec::new();
    for dir in super::common::DATA_DIRS.iter().chain(&["harness/tests"]) {
        yaml_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 100, "{}", files.len());
    let (depth, deepest) = files
        .iter()
        .map(|f| {
            let src = std::fs::read_to_string(f).unwrap();
            let d = (1..=MAX_YAML_DEPTH_LEVELS)
                .find(|&d| yaml::too_deep(&src, d).is_none())
                .unwrap_or(usize::MAX);
            (d, f)
        })
        .max()
        .unwrap();
    assert!(
        depth * 8 <= MAX_YAML_DEPTH_LEVELS,
        "{} nests {depth} levels",
        deepest.display()
    );
}

/// A file larger than the limit is refused unread, with an error that says so.
#[test]
fn a_yaml_file_beyond_the_size_limit_is_refused_unread() {
    let dir = scratch("large");
    let path = dir.join("large.yaml");
    let mut text = "id: large\n".to_string();
    text.push_str(&"#".repeat(MAX_YAML_FILE_BYTES as usize));
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::inputs::rotor::load(&path).unwrap_err();
    assert!(
        e.message.contains("larger than 16 MiB") && e.line.is_none(),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Any error shows a screen's width of a long line, around its column, and shortens what its
/// message quotes from the file.
#[test]
fn an_error_on_a_long_line_shows_a_screens_width_of_it() {
    let dir = scratch("long");
    let path = dir.join("long.yaml");
    // A bad value in the middle of a 60 kB line.
    let values: Vec<String> = (0..20_000)
        .map(|k| {
            if k == 10_000 {
                "x".into()
            } else {
                "0.5".into()
            }
        })
        .collect();
    let text = format!(
        "id: long\ntitle: t\nprovenance: {{source: s}}\nrotor:\n  chord_m: {{r_over_r: [{}], values: [1]}}\n",
        values.join(", ")
    );
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::inputs::rotor::load(&path).unwrap_err();
    let r = e.render();
    assert!(fits_a_screen(&r) && r.len() < 1000, "{r}");
    // The caret is under the bad value.
    let lines: Vec<&str> = r.lines().collect();
    let (shown, caret) = (lines[2], lines[3]);
    let at = caret.find('^').expect("a caret");
    assert_eq!(&shown[at..at + 1], "x", "{r}");

    // A value 10,000 characters long that the message quotes is shortened.
    let value = "k".repeat(10_000);
    std::fs::write(&path, format!("id: long\nrotor: {{hub: {value}}}\n")).unwrap();
    let e = cierva_harness::inputs::rotor::load(&path).unwrap_err();
    let shown = e.to_string();
    assert!(
        shown.contains("unknown variant `kkkk") && shown.len() < 1000,
        "{shown}"
    );
    assert!(fits_a_screen(&e.render()), "{}", e.render());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Counts each within its limit but together past the work a model can do in good time (issue
/// 50, found by fuzzing): 64 blades of 100 elements (6,400 blade elements; an autorotation took
/// 6 s to give up) is refused at the rotor file's `elements` with `MAX_BLADE_ELEMENTS`; a
/// teetering rotor of 2 x 1000 elements at the finest azimuth step (7.2 million blade-element
/// evaluations a revolution) is refused at the aircraft file's step with
/// `MAX_ELEMENT_STEPS_PER_REVOLUTION`, before any study refines it.
#[test]
fn counts_that_together_ask_too_much_work_are_refused_with_the_limit() {
    let dir = scratch("work");
    let root = super::common::repo_root().join("aircraft");
    let pca = std::fs::read_to_string(root.join("pca-2-rotor.yaml")).unwrap();
    let text = pca
        .replace("id: pca-2-rotor", "id: many")
        .replace("  blades: 4\n", "  blades: 64\n")
        .replace("  elements: 20\n", "  elements: 100\n");
    let path = dir.join("many.yaml");
    std::fs::write(&path, &text).unwrap();
    let line = text.lines().position(|l| l == "  elements: 100").unwrap() + 1;
    let (code, out, err) = common::cierva(&[
        "autorotate",
        path.to_str().unwrap(),
        "--alpha-deg",
        "5",
        "--airspeed-m-s",
        "30",
    ]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains(&format!("many.yaml:{line}:3: field `rotor.elements`"))
            && err.contains("must be at most 2000 (MAX_BLADE_ELEMENTS"),
        "{err}"
    );

    for f in ["vpm-m16.yaml", "vpm-m16-propeller.yaml"] {
        std::fs::copy(root.join(f), dir.join(f)).unwrap();
    }
    let rotor = std::fs::read_to_string(root.join("vpm-m16-rotor.yaml")).unwrap();
    std::fs::write(
        dir.join("vpm-m16-rotor.yaml"),
        rotor.replace("  elements: 20\n", "  elements: 1000\n"),
    )
    .unwrap();
    let aircraft = std::fs::read_to_string(root.join("vpm-m16.yaml")).unwrap();
    let fine = aircraft.replace("azimuth_step_deg: 5.0", "azimuth_step_deg: 0.1");
    assert_ne!(fine, aircraft);
    std::fs::write(dir.join("vpm-m16.yaml"), fine).unwrap();
    let (code, out, err) = common::cierva(&[
        "trim",
        dir.join("vpm-m16.yaml").to_str().unwrap(),
        "--airspeed-mph",
        "60",
    ]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("field `aircraft.main_rotor.azimuth_step_deg`")
            && err.contains("2 blades x 1000 elements x 3600 azimuth steps")
            && err.contains("(MAX_ELEMENT_STEPS_PER_REVOLUTION)"),
        "{err}"
    );
}
