//! `cierva retune` by frequency-response matching: its bad inputs (each a located error, exit
//! 2) and its report (the Bode figures before and after, J per response).

use super::common::cierva;
use cierva_harness::fit::retune::matched::{flown_output, grid};
use cierva_harness::inputs::record::Record;
use cierva_harness::run::responses::Responses;
use std::path::{Path, PathBuf};

/// A short calm-air stick sweep of the uncorrected VPM M16 at `mph`, sampled at `rate_hz`:
/// enough for the estimator's checks, which come before any fit.
fn sweep(dir: &Path, name: &str, mph: u32, rate_hz: u32, seed: u32) -> PathBuf {
    let out = dir.join(format!("{name}.csv"));
    let (code, stdout, stderr) = cierva(&[
        "synth-flight",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        &mph.to_string(),
        "--manoeuvre",
        "sweep",
        "--control",
        "eta_s",
        "--amplitude-percent",
        "6",
        "--duration-s",
        "40",
        "--sample-rate-hz",
        &rate_hz.to_string(),
        "--seed",
        &seed.to_string(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    out
}

/// `cierva retune` of the uncorrected VPM M16 from `records` with `extra` arguments.
fn retune(dir: &Path, records: &[&Path], extra: &[&str]) -> (i32, String, String) {
    let mut args = vec!["retune", "aircraft/vpm-m16.yaml", "--records"];
    let paths: Vec<String> = records
        .iter()
        .map(|p| p.to_str().unwrap().to_string())
        .collect();
    args.extend(paths.iter().map(String::as_str));
    let (output, report) = (dir.join("retuned.yaml"), dir.join("report.md"));
    args.extend([
        "--fit",
        "hub_aoa_factor",
        "--no-validate",
        "--output",
        output.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    args.extend(extra);
    cierva(&args)
}

/// A copy of a record (CSV and sidecar) under another name with `edit` applied to its CSV's
/// header and rows.
fn edited(
    record: &Path,
    name: &str,
    edit: impl Fn(&mut Vec<String>, &mut Vec<Vec<String>>),
) -> PathBuf {
    let text = std::fs::read_to_string(record).unwrap();
    let mut lines = text.lines();
    let mut header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    edit(&mut header, &mut rows);
    let out = record.with_file_name(format!("{name}.csv"));
    let mut csv = header.join(",") + "\n";
    for r in &rows {
        csv += &(r.join(",") + "\n");
    }
    std::fs::write(&out, csv).unwrap();
    let sidecar = std::fs::read_to_string(record.with_extension("yaml")).unwrap();
    let stem = record.file_stem().unwrap().to_string_lossy().into_owned();
    std::fs::write(
        out.with_extension("yaml"),
        sidecar.replacen(&format!("id: {stem}"), &format!("id: {name}"), 1),
    )
    .unwrap();
    out
}

/// Each bad input is a located error with exit code 2: records at different sample rates, an
/// excited control with no power in the band (with its excitation recorded, and without), an
/// excitation with none, a window longer than the record, a missing
/// output channel, an output no record measures.
#[test]
fn retune_refuses_bad_records_with_located_errors() {
    let dir = crate::common::scratch("retune-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let a = sweep(&dir, "a", 60, 100, 1);
    let b = sweep(&dir, "b", 60, 50, 2);
    // Records at different sample rates: the second is named.
    let (code, stdout, stderr) = retune(&dir, &[&a, &b], &[]);
    assert_eq!(code, 2, "{stdout}{stderr}");
    assert!(
        stderr.contains(b.to_str().unwrap()) && stderr.contains("different sample rates"),
        "{stderr}"
    );
    // The excited control held still: no power in the band, the file and the control named.
    let still = edited(&a, "still", |header, rows| {
        let k = header.iter().position(|h| h == "eta_s_percent").unwrap();
        for r in rows.iter_mut() {
            r[k] = "50".into();
        }
    });
    let still_is_named = || {
        let (code, stdout, stderr) = retune(&dir, &[&still], &[]);
        assert_eq!(code, 2, "{stdout}{stderr}");
        assert!(
            stderr.contains(still.to_str().unwrap())
                && stderr.contains("eta_s_percent")
                && stderr.contains("no power in the band"),
            "{stderr}"
        );
    };
    still_is_named();
    // The same record without its excitation: the responses from the controls, the same error.
    let side = still.with_extension("yaml");
    let kept: Vec<String> = std::fs::read_to_string(&side)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with("excitation:") && !l.contains(": eta_s_excitation_percent"))
        .map(String::from)
        .collect();
    std::fs::write(&side, kept.join("\n") + "\n").unwrap();
    still_is_named();
    // The excitation held still: the file and the excitation's channel named.
    let flat = edited(&a, "flat", |header, rows| {
        let k = header
            .iter()
            .position(|h| h == "eta_s_excitation_percent")
            .unwrap();
        for r in rows.iter_mut() {
            r[k] = "0".into();
        }
    });
    let (code, stdout, stderr) = retune(&dir, &[&flat], &[]);
    assert_eq!(code, 2, "{stdout}{stderr}");
    assert!(
        stderr.contains(flat.to_str().unwrap())
            && stderr.contains("the excitation `eta_s_excitation_percent`")
            && stderr.contains("no power in the band"),
        "{stderr}"
    );
    // A window longer than the record (40 s).
    let (code, stdout, stderr) = retune(&dir, &[&a], &["--windows-s", "10", "60"]);
    assert_eq!(code, 2, "{stdout}{stderr}");
    assert!(
        stderr.contains(a.to_str().unwrap()) && stderr.contains("longer than the record"),
        "{stderr}"
    );
    // A missing output channel: the rotor speed taken out of the record.
    let blind = edited(&a, "blind", |header, rows| {
        let k = header
            .iter()
            .position(|h| h == "omega_rotor_rad_s")
            .unwrap();
        header.remove(k);
        for r in rows.iter_mut() {
            r.remove(k);
        }
    });
    let text = std::fs::read_to_string(&blind).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    assert!(!header.contains(&"omega_rotor_rad_s"));
    let (code, stdout, stderr) = retune(&dir, &[&blind], &[]);
    assert_eq!(code, 2, "{stdout}{stderr}");
    assert!(
        stderr.contains(blind.to_str().unwrap()) && stderr.contains("omega_rotor_rad_s"),
        "{stderr}"
    );
    // A model that fails where the record was flown (a 12 m/s climb the engine cannot give) is
    // the model's failure, exit 1, naming the aircraft (issue 50's fuzzing: it was exit 2, no
    // file named).
    let steep = edited(&a, "steep", |_, _| {});
    let side = std::fs::read_to_string(steep.with_extension("yaml")).unwrap();
    let climb = side
        .lines()
        .find(|l| l.trim_start().starts_with("climb_m_s:"))
        .unwrap()
        .to_string();
    std::fs::write(
        steep.with_extension("yaml"),
        side.replacen(&climb, "  climb_m_s: 12.0", 1),
    )
    .unwrap();
    let (code, stdout, stderr) = retune(&dir, &[&steep], &[]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    assert!(
        stderr.contains("aircraft/vpm-m16.yaml")
            && stderr.contains("the model where the records were flown"),
        "{stderr}"
    );
    // An output that is not a measured state.
    let (code, _, stderr) = retune(&dir, &[&a], &["--outputs", "theta"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("output `theta`"), "{stderr}");
    // A bound the fit does not name, and a malformed one.
    for (bounds, says) in [
        ("propeller_blockage=0:1", "which --fit does not"),
        ("hub_aoa_factor=0", "write NAME=LO:HI"),
    ] {
        let (code, _, stderr) = retune(&dir, &[&a], &["--bounds", bounds]);
        assert_eq!(code, 2, "{stderr}");
        assert!(stderr.contains(says), "{stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The README's retune example (docs/validation.md, "Retuning the corrections"): one 120 s
/// stick sweep of 6 % at 60 mph in turbulence of 0.268 m/s (seed 60) of the VPM M16 with
/// corrections the test keeps to itself (hub factor 0.55, profile drag 1.3), retuned by
/// frequency-response matching from the uncorrected aircraft. Returns the JSON output and the
/// folder it wrote to.
fn readme_example(tag: &str) -> (serde_json::Value, PathBuf) {
    let dir = crate::common::scratch(&format!("retune-{tag}"));
    std::fs::create_dir_all(&dir).unwrap();
    let record = super::common::readme_record(&dir);
    let (code, stdout, stderr) = super::common::retune_hub_and_drag(&dir, &[&record], &[]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["status"], "converged", "{stdout}");
    (v, dir)
}

/// The README example's retune by responses: the model named (the flapping linearisation), J
/// per response before and after (lower after for each), and the report's J table linking a
/// Bode figure per response, written beside it on a log frequency axis with the records'
/// response, the model before and after, and the coherence. The corrections file loads, and
/// it and the report name each bound's source.
#[test]
fn retune_by_responses_reports_j_and_bode_figures_per_response() {
    let (v, dir) = readme_example("report");
    assert!(
        v["model"].as_str().unwrap().contains("flapping states"),
        "{v}"
    );
    let responses = v["responses"].as_array().unwrap();
    let outputs: Vec<&str> = responses
        .iter()
        .map(|r| r["output"].as_str().unwrap())
        .collect();
    assert_eq!(outputs, ["u", "w", "q", "Omega"], "{v}");
    for r in responses {
        let (b, a) = (
            r["j_before"].as_f64().unwrap(),
            r["j_after"].as_f64().unwrap(),
        );
        assert!(b.is_finite() && a.is_finite() && a < b, "{r}");
    }
    let md = std::fs::read_to_string(dir.join("retuned.md")).unwrap();
    assert!(
        md.contains("| condition | response | frequencies in band | J before | J after | Bode |"),
        "{md}"
    );
    assert!(md.contains("Reduced chi-square"), "{md}");
    // Every bound names its source: the hub factor's is seed 000's.
    assert!(md.contains("seed 000 Sec. VII.A"), "{md}");
    let output = dir.join("retuned.yaml");
    let written = std::fs::read_to_string(&output).unwrap();
    assert!(written.contains("seed 000 Sec. VII.A"), "{written}");
    let loaded = cierva_harness::inputs::corrections::load(&output).unwrap();
    assert!(loaded.corrections.hub_aoa_factor.is_some());
    assert!(loaded.corrections.profile_drag_scale.is_some());
    let figures = v["figures"].as_array().unwrap();
    assert_eq!(figures.len(), 4, "{v}");
    for f in figures {
        let name = f.as_str().unwrap();
        assert!(md.contains(&format!("]({name})")), "{md}");
        let svg = std::fs::read_to_string(dir.join(name)).unwrap();
        for panel in [
            "magnitude, dB",
            "phase, deg",
            "coherence",
            "frequency, Hz (log scale)",
            "records",
            "model before",
            "model after",
        ] {
            assert!(svg.contains(panel), "{name} has no `{panel}`");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The README example's known answer (issue 32's "done when": each correction back within 2
/// standard errors, and the uncorrected value outside that; issue 51, item 6: guarded at 2 for
/// both). Measured 2026-11-29 with the retune's finite-difference step of 1e-2 of the range
/// (`retune::DIFFERENCE_STEP`): the hub factor +0.90 standard errors (0.5678 +- 0.0198 against
/// 0.55), the profile drag +0.62 (1.3958 +- 0.154 against 1.3), its uncorrected 1 now 2.57
/// standard errors away. With the step of 1e-3 the drag scale's standard error was 0.208 and
/// the uncorrected 1 only 1.90 of them away: the finite differences measured the texture of
/// the cost (its kinks from tabulated section data), not its slope, and the separation was
/// guarded below the 2 at its measured value. Measured 2026-11-30 with the responses
/// estimated against the record's excitation (`synth-flight` records its sweep): the hub factor
/// +0.68 standard errors (0.5639 +- 0.0204), the profile drag +1.11 (1.518 +- 0.197), its
/// uncorrected 1 then 2.63 standard errors away. Measured 2026-12-01 with the matched
/// processing (`retune::matched`): the hub factor -0.05 standard errors (0.5489 +- 0.0192),
/// the profile drag +0.45 (1.375 +- 0.167), its uncorrected 1 2.24 standard errors away. Slow
/// for the cold `cargo test`;
/// `.ci/run` runs it with the other ignored tests.
#[test]
#[ignore = "slow known answer (synthetic flights and a retune): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn retune_by_responses_recovers_the_readme_examples_corrections() {
    let (v, dir) = readme_example("readme");
    for (name, truth, neutral, apart) in [
        ("hub_aoa_factor", 0.55, 1.0, 2.0),
        ("profile_drag_scale", 1.3, 1.0, 2.0),
    ] {
        let got = v["corrections"][name].as_f64().unwrap();
        let se = v["standard_errors"][name].as_f64().unwrap();
        eprintln!(
            "{name}: retuned {got} +- {se}, truth {truth}: {:+.2} standard errors",
            (got - truth) / se
        );
        assert!(
            (got - truth).abs() <= 2.0 * se,
            "{name}: retuned {got} +- {se}, truth {truth}, more than 2 standard errors"
        );
        assert!(
            (got - neutral).abs() > apart * se,
            "{name}: the uncorrected {neutral} is within {apart} standard errors of {got} +- {se}: the test proves nothing"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// The matched processing's own parts (`fit::retune::matched`).

/// How close the flown output comes to the same system integrated in time, relative to the
/// output's RMS: the control is smooth and band-limited (its content below 1 Hz, the grid
/// to 20 Hz), so what is left is the trapezoidal integration's error at 1 ms steps and the
/// transforms' rounding: 2.8e-6 measured (2026-12-01), the tolerance 35 times that.
const FLOWN_RELATIVE: f64 = 1e-4;

/// A record with one control channel, `eta_s_percent`, at 100 Hz, its trim 30 %, with the
/// sidecar's `travel` lines `travel` (empty: the control's position in % of travel).
fn matched_record(u: Vec<f64>, travel: &str) -> Record {
    let meta: cierva_harness::inputs::record::RecordMeta = serde_yaml::from_str(&format!(
        "id: t\ntitle: a test record\nprovenance: {{source: a unit test}}\naircraft: none\nsample_rate_hz: 100\ntrim: {{eta_s_percent: 30.0}}\n{travel}"
    ))
    .unwrap();
    Record {
        path: "t.csv".into(),
        meta,
        channels: vec!["eta_s_percent".into()],
        data: vec![u],
        notes: Vec::new(),
    }
}

#[test]
fn the_flown_output_is_the_linear_system_flown_in_time() {
    // q' = -2 q + 0.5 eta (a first-order pitch-rate response), from rest.
    let (a, b) = (-2.0, 0.5);
    let model = cierva_model::LinearModel::new(
        vec!["q".into()],
        vec!["eta_s".into()],
        nalgebra::DMatrix::from_element(1, 1, a),
        nalgebra::DMatrix::from_element(1, 1, b),
    )
    .unwrap();
    let (n, dt) = (3000, 0.01);
    // Smooth, starting and ending at the trim's 30 %: a tapered sum of low tones.
    let control = |t: f64| {
        let taper = (std::f64::consts::PI * t / (n as f64 * dt)).sin().powi(2);
        30.0 + taper
            * [(0.05, 0.3), (0.21, 1.1), (0.47, 2.0), (0.83, 0.7)]
                .iter()
                .map(|(f, phase)| (2.0 * std::f64::consts::PI * f * t + phase).sin())
                .sum::<f64>()
    };
    let u: Vec<f64> = (0..n).map(|k| control(k as f64 * dt)).collect();
    let rec = matched_record(u.clone(), "");
    let h = Responses::of_linear_model(&model, &grid(n, dt, 20.0), String::new()).unwrap();
    let measured = vec![0.1; n];
    let flown = flown_output(&rec, "q", &h, &measured).unwrap();
    // The same system in time, from rest at the trim's 30 %.
    let steps = 10;
    let h_s = dt / steps as f64;
    let mut q = 0.0;
    let mut truth = Vec::with_capacity(n);
    for k in 0..n {
        truth.push(q + 0.1);
        for j in 0..steps {
            let t = k as f64 * dt + j as f64 * h_s;
            let (u0, u1) = (control(t) - 30.0, control(t + h_s) - 30.0);
            // Trapezoidal in the control, exact in the decay.
            let e = (a * h_s).exp();
            q = e * q + b * h_s * 0.5 * (e * u0 + u1);
        }
    }
    // Compared about their means (the flown output takes the record's).
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    let shift = mean(&flown) - mean(&truth);
    let rms = (truth.iter().map(|v| (v - 0.1).powi(2)).sum::<f64>() / n as f64).sqrt();
    let worst = flown
        .iter()
        .zip(&truth)
        .map(|(f, t)| (f - shift - t).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < FLOWN_RELATIVE * rms,
        "largest difference {worst:.3e} against an RMS of {rms:.3e}"
    );
    // The same control logged as its changes from trim (the sidecar's trim still a position):
    // the same flight, from rest at zero change, not from a step of the trim's 30 %.
    let changes = matched_record(
        u.iter().map(|v| v - 30.0).collect(),
        "travel: {eta_s: {unit: deg, at_0_percent: 0.0, at_100_percent: 100.0, logged: change_from_trim}}\n",
    );
    let flown_changes = flown_output(&changes, "q", &h, &measured).unwrap();
    let apart = flown
        .iter()
        .zip(&flown_changes)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        apart < FLOWN_RELATIVE * rms,
        "logged as changes, the flight differs by {apart:.3e}"
    );
    // A record whose responses are not on its grid is refused, not misread.
    let other = Responses::of_linear_model(&model, &grid(n + 1, dt, 20.0), String::new()).unwrap();
    let refused = flown_output(&rec, "q", &other, &measured).unwrap_err();
    assert!(refused.contains("not on the record's grid"), "{refused}");
}

#[test]
fn the_grid_is_the_padded_transforms_bins_up_to_the_top() {
    let g = grid(1000, 0.01, 2.0);
    assert_eq!(g.len(), 80);
    assert!((g[0] - 0.025).abs() < 1e-12 && (g[79] - 2.0).abs() < 1e-9);
    // Never at or above the Nyquist frequency.
    assert!(grid(100, 0.01, 1e3).iter().all(|f| *f < 50.0));
}
