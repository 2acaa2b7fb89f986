//! The `frequency_response` check kind (`checks::frequency_response`): CIFER's mismatch cost
//! against known answers, a reference without coherence as "inconclusive", the trivial
//! predictors refused at load, and bad response files located.

use cierva_harness::checks::frequency_response::{
    self as frc, COHERENCE_MIN, J_ACCEPTABLE, Point, mismatch_cost,
};
use cierva_harness::inputs::record;
use cierva_harness::suite::case;
use cierva_harness::suite::outcome::{self, Finding, Outcome};
use cierva_harness::synth::linear;
use rustfft::num_complex::Complex64 as C;
use std::path::{Path, PathBuf};

/// The known answer: a linear model's analytic response against its own simulated
/// record costs less than this.
const KNOWN_ANSWER_J: f64 = 5.0;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::scratch(&format!("frc-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A case on seed 002's linear model with one `frequency_response` check whose other lines are
/// `check` (indented under the check).
fn linear_case(dir: &Path, id: &str, check: &str) -> PathBuf {
    let text = format!(
        "id: {id}\ntitle: t\nclass: verification\nprovenance: {{source: test}}\n\
         model: {{linear_model_file: {}}}\n\
         tolerances:\n  acceptable: {{interval: [0.0, {J_ACCEPTABLE:?}], reason: Tischler's guideline}}\n  \
         wide: {{interval: [0.0, 1.0e12], reason: test}}\n\
         checks:\n  - id: fr\n    kind: frequency_response\n{check}",
        root()
            .join("flight-refs/seed002-vpm-m16-60kn.yaml")
            .display()
    );
    let path = dir.join(format!("{id}.yaml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// A check of `output`'s response to the shaft tilt, its reference estimated from the record
/// `rec` over 0.09-3 Hz (where the sweep is at full amplitude), its cost judged by `tolerance`.
fn record_check(output: &str, rec: &Path, tolerance: &str) -> String {
    format!(
        "    input: eta_s\n    output: {output}\n    records: [{}]\n    band_hz: [0.09, 3.0]\n    \
         expect:\n      mismatch_cost: {{tolerance: {tolerance}}}\n",
        rec.display()
    )
}

/// Seed 002's VPM M16 model flown through an exponential sweep of the shaft tilt (0.02-4 Hz,
/// 120 s at 100 Hz) with a little sensor noise, written as a record in `dir`.
fn sweep_record(dir: &Path) -> PathBuf {
    let model = cierva_harness::inputs::reference::load(
        &root().join("flight-refs/seed002-vpm-m16-60kn.yaml"),
    )
    .unwrap()
    .linear_model
    .unwrap();
    let settings = linear::LinearTest::exponential_sweep("known-sweep", 11);
    let (channels, data, meta) = linear::generate(&model, &settings).unwrap();
    let path = dir.join("known-sweep.csv");
    record::write(&path, &meta, &channels, &data).unwrap();
    path
}

/// The known answer: seed 002's linear model's analytic responses against its own
/// simulated sweep record (the reference estimated by the check from the record, band 0.09-3
/// Hz where the stick is swept at full amplitude) cost J < 5 for the pitch rate, the pitch
/// attitude and the heave velocity (from the air data), and pass Tischler's J <= 100.
#[test]
fn a_linear_models_response_against_its_own_record_costs_j_under_5() {
    let dir = scratch("known");
    let rec = sweep_record(&dir);
    for (output, id) in [("q", "known-q"), ("theta", "known-theta"), ("w", "known-w")] {
        let path = linear_case(&dir, id, &record_check(output, &rec, "acceptable"));
        let c = case::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
        let r = outcome::run_check(&c, &c.checks[0]);
        let j = r.quantities[0].value;
        let n = r
            .fingerprint
            .iter()
            .find(|(k, _)| k == "frequencies_in_band")
            .unwrap()
            .1;
        println!(
            "known answer {output}/eta_s: J = {j:.3} over {n} frequencies ({})",
            r.note.as_deref().unwrap_or("")
        );
        assert_eq!(r.outcome, Outcome::Pass, "{}", r.explain());
        assert!(j < KNOWN_ANSWER_J, "{output}: J = {j}");
        assert!(n >= 50.0, "{output}: {n} frequencies in the band");
        assert!(
            r.note
                .as_deref()
                .is_some_and(|s| s.contains("its own A and B")),
            "{:?}",
            r.note
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// validate's report draws a frequency-response check as a Bode figure (issue 32, item 1): its
/// magnitude, phase and the reference's coherence against a log frequency axis, stacked in one
/// figure (issue 50), the reference as markers and the model's response as a line.
#[test]
fn the_report_draws_a_frequency_response_check_as_bode_figures() {
    let dir = scratch("report");
    let rec = sweep_record(&dir);
    let path = linear_case(&dir, "bode", &record_check("q", &rec, "acceptable"));
    let out = dir.join("report");
    let (code, _, err) = super::common::cierva(&[
        "validate",
        path.to_str().unwrap(),
        "--quiet",
        "--report-dir",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    // One figure, its three panels stacked on one frequency axis (issue 50), each titled.
    assert!(
        html.contains("<figcaption>fr: q / eta_s: magnitude, phase and coherence</figcaption>"),
        "no stacked Bode figure"
    );
    for title in [
        "fr: q / eta_s: magnitude",
        "fr: q / eta_s: phase",
        // (the SVG escapes the apostrophe of "the records' estimate")
        "fr: q / eta_s: coherence of the records",
    ] {
        assert!(html.contains(title), "no panel `{title}`");
    }
    assert_eq!(html.matches("frequency, Hz (log scale)").count(), 3);
    for series in ["reference", "model", "magnitude, dB", "phase, deg"] {
        assert!(html.contains(series), "no `{series}`");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The cost's arithmetic: one frequency off by 1 dB at coherence 1 costs
/// `20 * [1.58 (1 - 1/e)]^2 * 1`; 10 deg of phase `20 W * 0.01745 * 100`; frequencies below
/// the coherence threshold do not count; no frequency in the band gives no cost; a phase error
/// wraps (359 deg is -1 deg).
#[test]
fn the_mismatch_cost_is_tischlers() {
    let w1 = (1.58f64 * (1.0 - (-1.0f64).exp())).powi(2);
    let at = |f: f64, coherence: f64| Point {
        frequency_hz: f,
        response: C::new(1.0, 0.0),
        coherence,
    };
    let reference = [at(1.0, 1.0), at(2.0, 0.5)];
    let db1 = C::new(10f64.powf(1.0 / 20.0), 0.0);
    let c = mismatch_cost(&reference, &[db1, C::new(100.0, 0.0)]).unwrap();
    assert_eq!(c.frequencies, 1);
    assert!((c.j - 20.0 * w1).abs() < 1e-9, "{}", c.j);
    assert_eq!((c.band_low_hz, c.band_high_hz), (1.0, 1.0));
    let deg10 = C::from_polar(1.0, 10f64.to_radians());
    let c = mismatch_cost(&reference, &[deg10, deg10]).unwrap();
    assert!((c.j - 20.0 * w1 * 0.01745 * 100.0).abs() < 1e-9, "{}", c.j);
    let wrapped = C::from_polar(1.0, 359f64.to_radians());
    let c = mismatch_cost(&reference, &[wrapped, wrapped]).unwrap();
    assert!((c.j - 20.0 * w1 * 0.01745).abs() < 1e-6, "{}", c.j);
    assert!(mismatch_cost(&[at(1.0, COHERENCE_MIN - 1e-9)], &[db1]).is_none());
    assert_eq!(
        mismatch_cost(&[at(1.0, 1.0)], &[C::new(0.0, 0.0)])
            .unwrap()
            .j,
        f64::INFINITY
    );
}

/// A response file whose coherence is below 0.6 everywhere: the check is inconclusive
/// ("inconclusive: coherence"), and does not pass.
#[test]
fn a_reference_without_coherence_is_inconclusive_never_a_pass() {
    let dir = scratch("inconclusive");
    let mut csv = String::from("frequency_hz,magnitude_db,phase_deg,coherence,random_error\n");
    for k in 0..20 {
        let f = 0.1 * 1.2f64.powi(k);
        csv += &format!("{f},-10.0,-45.0,0.4,0.3\n");
    }
    std::fs::write(dir.join("weak.csv"), csv).unwrap();
    let path = linear_case(
        &dir,
        "weak",
        "    input: eta_s\n    output: q\n    reference: weak.csv\n    \
         expect:\n      mismatch_cost: {tolerance: wide}\n",
    );
    let c = case::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
    let r = outcome::run_check(&c, &c.checks[0]);
    assert!(!r.passed);
    assert_eq!(r.outcome, Outcome::Fail, "{}", r.explain());
    let Some(f @ Finding::Inconclusive { .. }) = &r.finding else {
        panic!("{}", r.explain())
    };
    assert!(
        f.describe().starts_with("inconclusive: coherence"),
        "{}",
        f.describe()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The trivial predictors: a bound wide enough that a pure gain at the reference's mean
/// magnitude passes it is refused at load, naming the predictor; and a model with no response
/// costs infinitely much.
#[test]
fn a_bound_a_pure_gain_passes_is_refused_at_load() {
    let dir = scratch("trivial");
    let rec = sweep_record(&dir);
    let path = linear_case(&dir, "trivial", &record_check("q", &rec, "wide"));
    let e = case::load(&path).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("a pure gain"), "{msg}");
    assert_eq!(e.line, Some(17), "{msg}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad input is a located error: a response file's bad cell names the file, line, column and
/// column name; a record without the input control names the record; an output the model does
/// not have names the case's field.
#[test]
fn bad_frequency_response_input_is_located() {
    let dir = scratch("bad");
    std::fs::write(
        dir.join("bad.csv"),
        "frequency_hz,magnitude_db,phase_deg,coherence\n0.1,-10,-45,0.9\n0.2,-11,x,0.9\n",
    )
    .unwrap();
    let e = frc::read_response(&dir.join("bad.csv")).unwrap_err();
    assert_eq!((e.line, e.column), (Some(3), Some(9)), "{e}");
    assert!(e.to_string().contains("phase_deg"), "{e}");
    std::fs::write(
        dir.join("falling.csv"),
        "frequency_hz,magnitude_db,phase_deg,coherence\n0.2,-10,-45,0.9\n0.1,-11,-50,0.9\n",
    )
    .unwrap();
    let e = frc::read_response(&dir.join("falling.csv")).unwrap_err();
    assert!(
        e.line == Some(3) && e.to_string().contains("must rise"),
        "{e}"
    );
    let path = linear_case(
        &dir,
        "bad-reference",
        "    input: eta_s\n    output: q\n    reference: bad.csv\n    \
         expect:\n      mismatch_cost: {tolerance: acceptable}\n",
    );
    let e = case::load(&path).unwrap_err();
    let msg = e.to_string();
    assert!(
        e.line == Some(14) && msg.contains("bad.csv:3:9") && msg.contains("phase_deg"),
        "{msg}"
    );
    let path = linear_case(
        &dir,
        "bad-output",
        "    input: eta_s\n    output: r\n    reference: bad.csv\n    \
         expect:\n      mismatch_cost: {tolerance: acceptable}\n",
    );
    let e = case::load(&path).unwrap_err();
    assert!(
        e.line == Some(13) && e.to_string().contains("not a state of the model"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A `frequency_response` check on another simulation (issue 49, item 2): seed 002's A and B,
/// given three ways (the linear model file; a `files:` subject with that file at its condition;
/// the example external command, `examples/vpm-m16-external/model/vpm_m16.py`, which serves
/// the same matrix at 60 kn, 425 kg, 2000 ft) against one reference response, cost the same J.
/// The reference is made up (a flat -10 dB at -120 deg, coherence 0.9): what is tested is that
/// the three paths give one number, not the model's agreement.
#[test]
fn an_external_model_and_files_cost_what_their_linear_model_costs() {
    let dir = scratch("external");
    let mut csv = String::from("frequency_hz,magnitude_db,phase_deg,coherence\n");
    for k in 0..20 {
        csv += &format!("{},-10.0,-120.0,0.9\n", 0.1 * 1.2f64.powi(k));
    }
    std::fs::write(dir.join("reference.csv"), csv).unwrap();
    let check = "    input: eta_s\n    output: q\n    reference: reference.csv\n    \
                 condition: {airspeed_kn: 60}\n    \
                 expect:\n      mismatch_cost: {tolerance: acceptable}\n";
    let refs = root().join("flight-refs/seed002-vpm-m16-60kn.yaml");
    let script = root().join("examples/vpm-m16-external/model/vpm_m16.py");
    let header = |id: &str, model: String| {
        format!(
            "id: {id}\ntitle: t\nclass: verification\nprovenance: {{source: test}}\n\
             model:\n{model}\
             tolerances:\n  acceptable: {{interval: [0.0, {J_ACCEPTABLE:?}], reason: Tischler's guideline}}\n\
             checks:\n  - id: fr\n    kind: frequency_response\n{check}"
        )
    };
    let subjects = [
        (
            "files",
            format!(
                "  files:\n    linear_model_file: {}\n    at: {{airspeed_kn: 60}}\n    \
                 mass_kg: 425.0\n    density_altitude_ft: 2000.0\n",
                refs.display()
            ),
        ),
        (
            "command",
            format!(
                "  external:\n    command: [python3, {}]\n    timeout_s: 30\n    \
                 mass_kg: 425.0\n    density_altitude_ft: 2000.0\n",
                script.display()
            ),
        ),
    ];
    // The linear model itself: its check has no condition.
    let linear = linear_case(
        &dir,
        "linear",
        &check.replace("    condition: {airspeed_kn: 60}\n", ""),
    );
    let cost = |path: &Path| {
        let c = case::load(path).unwrap_or_else(|e| panic!("{}", e.render()));
        let r = outcome::run_check(&c, &c.checks[0]);
        assert!(r.error.is_none(), "{}", r.explain());
        (r.quantities[0].value, r.note.clone().unwrap_or_default())
    };
    let (j, _) = cost(&linear);
    assert!(j.is_finite() && j > 0.0, "J = {j}");
    for (id, model) in subjects {
        let path = dir.join(format!("{id}.yaml"));
        std::fs::write(&path, header(id, model)).unwrap();
        let (got, note) = cost(&path);
        assert_eq!(got, j, "{id}: J {got} against the linear model's {j}");
        assert!(note.contains("the A and B"), "{id}: {note}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
