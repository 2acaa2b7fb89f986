//! The report's figures, built from check results through each check's placement
//! (`Evaluate::placed`).

use super::common::repo_root;
use cierva_harness::report::{CaseRun, figures};
use cierva_harness::suite::{case, outcome};

/// A scratch case on seed 002's VPM M16 matrices (60 kn) with one BCAR check of the short
/// period's margin and no expected verdict.
fn bcar_case_without_a_verdict() -> case::Case {
    let dir = crate::common::scratch("bcar-report");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bcar-margin.yaml");
    let text = format!(
        "id: bcar-margin\ntitle: t\nclass: verification\nprovenance: {{source: a test}}\n\
         model:\n  linear_model_file: {}\n\
         tolerances:\n  wide: {{interval: [5.0, 20.0], reason: a test}}\n\
         checks:\n  - id: sp\n    kind: bcar\n    mode: short_period\n    expect:\n      margin_index: {{tolerance: wide}}\n",
        repo_root()
            .join("flight-refs/seed002-vpm-m16-60kn.yaml")
            .display()
    );
    std::fs::write(&path, text).unwrap();
    let c = case::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
    let _ = std::fs::remove_dir_all(&dir);
    c
}

/// The BCAR Section T chart places a mode by its own verdict. Seed 002's short period at 60 kn
/// (-1.064 +- 0.864i 1/s, period 7.3 s, damping index 11, far right of the boundary) complies;
/// a check of its margin alone, with no expected verdict, once drew it as "does not comply".
#[test]
fn the_bcar_chart_places_a_mode_by_its_own_verdict() {
    let case = bcar_case_without_a_verdict();
    let results: Vec<_> = case
        .checks
        .iter()
        .map(|k| outcome::run_check(&case, k))
        .collect();
    assert!(results[0].outcome.ok(), "{}", results[0].explain());
    let run = CaseRun {
        ran: cierva_harness::suite::validation::CaseRan {
            case,
            results,
            seconds: 0.0,
            corrections: vec![],
            scores: vec![],
        },
        sensitivity: None,
        uncertainty: None,
    };
    let figures = figures::of_case(&run);
    let chart = figures
        .iter()
        .find(|f| f.title.contains("BCAR Section T"))
        .expect("a BCAR chart");
    let points = |name: &str| {
        chart
            .series
            .iter()
            .find(|s| s.name == name)
            .map_or(0, |s| s.points.len())
    };
    assert_eq!((points("complies"), points("does not comply")), (1, 0));
    let (x, t) = chart
        .series
        .iter()
        .find(|s| s.name == "complies")
        .unwrap()
        .points[0];
    assert!(
        (t - 7.276).abs() < 0.01 && (x - 11.17).abs() < 0.05,
        "({x}, {t})"
    );
}

/// A frequency response is drawn as CIFER's readers expect it (issue 50): magnitude, phase and
/// coherence stacked on one frequency axis in one figure, the reference's frequencies below the
/// coherence threshold set apart as hollow grey points (they are not in `J`), with the
/// threshold drawn on the coherence panel.
#[test]
fn a_bode_diagram_is_stacked_and_sets_incoherent_points_apart() {
    use cierva_harness::report::plot::{Style, bode_panels};
    use rustfft::num_complex::Complex64;
    let f = [0.1, 0.2, 0.5, 1.0, 2.0];
    let coherence = [0.3, 0.7, 0.9, 0.95, 0.5];
    let h: Vec<Option<Complex64>> = f.iter().map(|x| Some(Complex64::new(1.0, *x))).collect();
    let figs = bode_panels(
        "q/eta_s",
        &f,
        &[("reference", h.clone()), ("model", h)],
        &coherence,
        0.6,
    );
    assert_eq!(figs.len(), 3);
    let stack = figs[0].stack.clone().expect("stacked");
    assert!(
        figs.iter().all(|g| g.stack.as_ref() == Some(&stack)),
        "{stack}"
    );
    for g in &figs[..2] {
        let apart = g
            .series
            .iter()
            .find(|s| s.style == Style::Hollow)
            .expect("hollow points");
        assert_eq!(apart.name, "reference, coherence below 0.6: not compared");
        assert_eq!(apart.colour, Some(7));
        let xs: Vec<f64> = apart.points.iter().map(|p| p.0).collect();
        assert_eq!(xs, [0.1f64.log10(), 2.0f64.log10()]);
        let kept = g.series.iter().find(|s| s.name == "reference").unwrap();
        assert_eq!(kept.points.len(), 3);
    }
    assert!(figs[2].series.iter().any(|s| s.name == "threshold 0.6"));

    // In the report: one figure under the stack's caption, three panels in its SVG.
    let dir = crate::common::scratch("bode");
    let case =
        super::common::repo_root().join("cases/cierva-frequency-response-vpm-m16-60mph.yaml");
    let (code, out, err) = super::common::cierva(&[
        "validate",
        case.to_str().unwrap(),
        "--report-dir",
        dir.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(code == 0 || code == 1, "{out}{err}");
    let captions = html
        .matches(": magnitude, phase and coherence</figcaption>")
        .count();
    assert!(captions >= 1, "no stacked Bode figure");
    assert!(
        !html.contains(": magnitude</figcaption>"),
        "a Bode panel drawn alone"
    );
}
