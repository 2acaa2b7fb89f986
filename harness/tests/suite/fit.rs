//! Fitting corrections: a synthetic truth is recovered, and degenerate problems end with a
//! status.

use cierva_harness::fit::{
    self, Bounds, Enforce, FitOptions, FitParameter, FitSubject, Measure, ParameterKind, Problem,
    Status, Target, TargetCondition,
};
use cierva_harness::inputs::condition::Loading;
use cierva_harness::inputs::condition::TrimRequest;

fn vpm_file() -> cierva_harness::inputs::aircraft::AircraftFile {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap();
    cierva_harness::inputs::aircraft::load(&root.join("aircraft/vpm-m16.yaml")).unwrap()
}

fn vpm() -> cierva_model::aircraft::Aircraft {
    vpm_file().aircraft
}

fn at(mph: f64) -> TargetCondition {
    TargetCondition::Flight(TrimRequest::level(mph), LOADING)
}

fn vpm_subject() -> FitSubject {
    FitSubject::Aircraft {
        file: Box::new(vpm_file()),
    }
}

const LOADING: Loading = Loading {
    mass_kg: Some(425.0),
    density_altitude_ft: 2000.0,
};

fn blockage_and_hub(start: [f64; 2]) -> Vec<FitParameter> {
    vec![
        FitParameter {
            kind: ParameterKind::PropellerBlockage,
            lower: 0.0,
            upper: 1.0,
            start: start[0],
            regularisation: 0.0,
        },
        FitParameter {
            kind: ParameterKind::HubAoaFactor,
            lower: 0.0,
            upper: 1.5,
            start: start[1],
            regularisation: 0.0,
        },
    ]
}

/// X_u and Z_w at 40, 55 and 70 mph as the model gives them with blockage 1.0 and hub factor
/// 0.5 (seed 000's corrected model), each with a 5 % standard error; the fit starts at the
/// truth.
fn synthetic_truth() -> Problem {
    let mut problem = Problem {
        subject: vpm_subject(),
        parameters: blockage_and_hub([1.0, 0.5]),
        targets: vec![],
        options: FitOptions::default(),
        executor: cierva_harness::fit::Executor::Local,
    };
    for v in [40.0, 55.0, 70.0] {
        for n in ["X_u", "Z_w"] {
            problem.targets.push(Target {
                condition: at(v),
                measure: Measure::Derivative(n.into()),
                reference: 0.0,
                standard_error: 1.0,
                bounds: None,
            });
        }
    }
    let y = fit::evaluate(&problem, &[1.0, 0.5]).unwrap();
    for (t, v) in problem.targets.iter_mut().zip(&y) {
        t.reference = *v;
        t.standard_error = 0.05 * v.abs();
    }
    problem
}

/// References made by the model with blockage 1.0 and hub factor 0.5 (seed 000's corrected
/// model), X_u and Z_w at 40, 55 and 70 mph with 5 % standard errors: the fit from the
/// uncorrected model (blockage 0, hub factor 1) recovers both within 1e-3.
#[test]
fn a_synthetic_truth_is_recovered() {
    let mut problem = synthetic_truth();
    problem.parameters = blockage_and_hub([0.0, 1.0]);
    let started = std::time::Instant::now();
    let r = fit::fit(&problem);
    eprintln!(
        "{:?} after {} iterations in {:.2} s: {:?} +- {:?}, cost {:.3e} -> {:.3e}; {:?}",
        r.status,
        r.iterations,
        started.elapsed().as_secs_f64(),
        r.values,
        r.standard_errors,
        r.cost_start,
        r.cost,
        r.warnings
    );
    assert_eq!(r.status, Status::Converged);
    assert!(r.cost_start > 1.0, "the start misfits: {}", r.cost_start);
    assert!((r.values[0] - 1.0).abs() < 1e-3, "{:?}", r.values);
    assert!((r.values[1] - 0.5).abs() < 1e-3, "{:?}", r.values);
    assert!(r.standard_errors.iter().all(|s| s.is_finite() && *s > 0.0));
    for (after, t) in r.after.iter().zip(&problem.targets) {
        assert!(
            (after - t.reference).abs() < 1e-2 * t.standard_error,
            "{after} {t:?}"
        );
    }
}

/// Parameters with no effect on the targets (X_phi is zero by kinematics) are reported with
/// infinite standard errors and a warning; contradictory hard bounds are infeasible; a condition that
/// will not trim is a model failure; bad bounds are a bad problem. None panics.
#[test]
fn degenerate_problems_end_with_a_status() {
    let base = Problem {
        subject: vpm_subject(),
        parameters: blockage_and_hub([0.0, 1.0]),
        targets: vec![Target {
            condition: at(60.0),
            measure: Measure::Derivative("X_u".into()),
            reference: -0.1,
            standard_error: 0.01,
            bounds: None,
        }],
        options: FitOptions {
            max_iterations: 3,
            ..FitOptions::default()
        },
        executor: cierva_harness::fit::Executor::Local,
    };
    let mut blind = base.clone();
    blind.targets[0].measure = Measure::Derivative("X_phi".into());
    blind.targets[0].reference = 1.0;
    let r = fit::fit(&blind);
    assert_eq!(r.status, Status::Converged, "{r:?}");
    assert!(r.standard_errors.iter().all(|s| s.is_infinite()), "{r:?}");
    assert_eq!(
        r.values,
        vec![0.0, 1.0],
        "blind parameters keep their start"
    );
    assert!(
        r.warnings
            .iter()
            .filter(|w| w.contains("no effect"))
            .count()
            == 2,
        "{:?}",
        r.warnings
    );

    let mut contradictory = base.clone();
    contradictory.targets[0].bounds = Some(Bounds {
        lower: -1e-6,
        upper: 1e-6,
        enforce: Enforce::Hard,
    });
    contradictory.targets[0].measure = Measure::Derivative("M_u".into());
    contradictory.parameters.truncate(1);
    contradictory.parameters[0].upper = 0.01;
    let r = fit::fit(&contradictory);
    assert!(matches!(r.status, Status::Infeasible(_)), "{r:?}");

    let mut no_trim = base.clone();
    no_trim.targets[0].condition = at(400.0);
    let r = fit::fit(&no_trim);
    assert!(matches!(r.status, Status::ModelFailure(_)), "{r:?}");

    let mut bad = base.clone();
    bad.parameters[0].lower = 2.0;
    let r = fit::fit(&bad);
    assert!(matches!(r.status, Status::BadProblem(_)), "{r:?}");
}

/// A bound between the start and the reference: a hard bound stops the fit on it; a soft bound
/// of weight `w` lets it through by about `1 / (1 + w)` of the way to the reference (for a
/// locally linear model), and the soft fit's cost counts the violation.
#[test]
fn hard_and_soft_bounds_hold_the_fit_back() {
    let mut problem = Problem {
        subject: vpm_subject(),
        parameters: blockage_and_hub([0.0, 1.0]),
        targets: vec![Target {
            condition: at(55.0),
            measure: Measure::Derivative("X_u".into()),
            reference: 0.0,
            standard_error: 1.0,
            bounds: None,
        }],
        options: FitOptions::default(),
        executor: cierva_harness::fit::Executor::Local,
    };
    problem.parameters.truncate(1);
    let y0 = fit::evaluate(&problem, &[0.0]).unwrap()[0];
    let y1 = fit::evaluate(&problem, &[1.0]).unwrap()[0];
    assert!(y1 > y0, "blockage reduces |X_u|: {y0} -> {y1}");
    let mid = 0.5 * (y0 + y1);
    problem.targets[0].reference = y1;
    problem.targets[0].standard_error = (y1 - y0).abs();
    let with = |enforce| {
        let mut p = problem.clone();
        p.targets[0].bounds = Some(Bounds {
            lower: -10.0,
            upper: mid,
            enforce,
        });
        let r = fit::fit(&p);
        assert_eq!(r.status, Status::Converged, "{r:?}");
        r
    };
    let free = fit::fit(&problem);
    assert!((free.after[0] - y1).abs() < 1e-3 * (y1 - y0), "{free:?}");
    let hard = with(Enforce::Hard);
    let gap = y1 - mid;
    assert!(
        (hard.after[0] - mid).abs() < 0.02 * gap,
        "hard: {} against the bound {mid}",
        hard.after[0]
    );
    let weight = 9.0;
    let soft = with(Enforce::Soft { weight });
    let through = (soft.after[0] - mid) / gap;
    assert!(
        (through - 1.0 / (1.0 + weight)).abs() < 0.03,
        "soft: {through:.4} of the way past the bound, 1/(1+w) = {:.4}",
        1.0 / (1.0 + weight)
    );
    eprintln!(
        "free {:.5}, hard {:.5}, soft {:.5} ({through:.4} of the way), bound {mid:.5}; blockage {:.4} {:.4} {:.4}",
        free.after[0], hard.after[0], soft.after[0], free.values[0], hard.values[0], soft.values[0]
    );
}

fn repo() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Runs a shipped fit file and checks it against its committed result
/// (`corrections/fitted/<id>.yaml`): converged (or, with `converged` false, infeasible: the
/// bounds do not let it reach every hard bound), the same corrections within a
/// hundredth of their standard errors (or of their bounds' width, if narrower), and the fitted
/// targets closer to their references than before.
fn shipped_fit(
    id: &str,
    converged: bool,
) -> (
    cierva_harness::fit::file::FitFile,
    cierva_harness::fit::file::FitRun,
) {
    // A converged fit takes at least 40 % off the RMS error; an infeasible one, stopped by its
    // bounds, must at least reduce it.
    shipped_fit_by(id, converged, if converged { 0.6 } else { 1.0 })
}

/// [`shipped_fit`], the fitted targets' RMS error to fall below `factor` times the start's.
fn shipped_fit_by(
    id: &str,
    converged: bool,
    factor: f64,
) -> (
    cierva_harness::fit::file::FitFile,
    cierva_harness::fit::file::FitRun,
) {
    use cierva_harness::fit;
    use cierva_harness::inputs::corrections;
    let f = fit::file::load(&repo().join(format!("fits/{id}.yaml"))).unwrap();
    let run = fit::file::run(&f);
    let r = &run.result;
    eprintln!(
        "{id}: {:?} after {} iterations ({} evaluations) in {:.2} s: {:?} +- {:?}",
        r.status, r.iterations, r.evaluations, run.seconds, r.values, r.standard_errors
    );
    if converged {
        assert_eq!(r.status, Status::Converged, "{r:?}");
    } else {
        assert!(matches!(r.status, Status::Infeasible(_)), "{r:?}");
    }
    let committed =
        corrections::load(&repo().join(format!("corrections/fitted/{id}.yaml"))).unwrap();
    assert_eq!(committed.target, f.applies_to);
    let fresh = r.corrections();
    for ((k, p), (v, se)) in r
        .parameters
        .iter()
        .zip(&f.problem.parameters)
        .zip(r.values.iter().zip(&r.standard_errors))
    {
        // A hundredth of the standard error, or of the bounds' width where the standard error
        // is wider (a parameter the targets barely see).
        let within = 0.01 * se.min(p.upper - p.lower);
        let was = k
            .get(&committed.corrections)
            .expect("the committed file has it");
        assert_eq!(k.get(&fresh), Some(*v));
        assert!(
            (was - v).abs() <= within,
            "{}: committed {was}, fitted now {v} (standard error {se}): re-run `cierva fit fits/{id}.yaml`",
            k.name()
        );
    }
    let (before, after, n) =
        fit::file::rms_relative_error_percent(&f.problem.targets, &r.before, &r.after);
    assert_eq!(n, f.problem.targets.len());
    assert!(after < factor * before, "{before} -> {after}");
    // The committed file's summary of the errors, which the documents quote, is this run's.
    let text =
        std::fs::read_to_string(repo().join(format!("corrections/fitted/{id}.yaml"))).unwrap();
    let doc: serde_yaml::Value = serde_yaml::from_str(&text).unwrap();
    let summary = &doc["fit"]["errors"]["fitted"];
    for (key, now) in [("rms_before_percent", before), ("rms_after_percent", after)] {
        let was = summary[key]
            .as_f64()
            .unwrap_or_else(|| panic!("{id}: no fit.errors.fitted.{key}: re-run `cierva fit`"));
        assert!(
            (was - now).abs() <= 0.01 * now,
            "{id}: committed {key} {was}, now {now}: re-run `cierva fit fits/{id}.yaml`"
        );
    }
    (f, run)
}

/// Seed 000's story: from the uncorrected model, the fit finds seed 000's corrections
/// (blockage at its bound 1, hub factor 0.486 +- 0.039, seed 000's 0.5 within two standard
/// errors), and the phugoid's damping falls (seed 000 Fig. 14: "the unmodified simulation
/// predicts too much damping") at every speed. At 40 mph it missed that story while the
/// phugoid was neutral before the fit (issue 52 item 12's rotor and propeller inertial terms:
/// the fit moved it 1.8e-4 1/s the other way); since the blades' flap inertia feels the hub's
/// angular acceleration it is damped before the fit (-0.0062 1/s) and the fit raises its real
/// part by 1.0e-3 1/s, as at the other speeds. Every derivative was outside its flight bound; the
/// bounds are soft (issue 52, item 13), and what seed 000 claims is checked on the result: each
/// derivative inside its bounds "over most of the speed range", 3 or more of the 4 airspeeds.
/// The one miss, X_u at 40 mph (the VPM M16's tailplane in the propeller's slipstream: the fit
/// file's notes), is a known discrepancy guarded at its measured size.
#[test]
fn seed000_story_fit_brings_x_u_and_z_w_inside_and_lightens_the_phugoid() {
    // "Over most of the speed range" (seed 000, beside Fig. 13) of its four airspeeds.
    const MOST_OF_FOUR: usize = 3;
    // X_u at 40 mph ends 1.081 standard errors outside its bound (measured at 0.4862 hub
    // factor; 0.995 at 0.4868 before the blades' flap inertia felt the hub's angular
    // acceleration, issue 52 item 12); the guard moves with the model, not to meet the bound
    // (issue 52, item 13).
    const X_U_40_MISS_SE: f64 = 1.081;
    // How far the miss may move before the test says so: 0.05 standard errors, five times the
    // hundredth of a standard error to which `shipped_fit` holds the fitted parameters against
    // the committed file: a rerun's scatter passes, a change of the model's X_u at 40 mph by a
    // twentieth of its standard error does not.
    const MISS_MOVES: f64 = 0.05;
    let (f, run) = shipped_fit("vpm-m16-seed000", true);
    let r = &run.result;
    assert_eq!(r.status, cierva_harness::fit::Status::Converged, "{r:?}");
    assert!(
        (r.values[0] - 0.5).abs() < 2.0 * r.standard_errors[0],
        "{r:?}"
    );
    assert!((r.values[1] - 1.0).abs() < 1e-6, "{r:?}");
    let mut inside: std::collections::BTreeMap<&str, usize> = Default::default();
    let mut outside = Vec::new();
    for (t, (b, a)) in f.problem.targets.iter().zip(r.before.iter().zip(&r.after)) {
        let bounds = t.bounds.unwrap();
        assert!(!(bounds.lower..=bounds.upper).contains(b), "{t:?}: {b}");
        if (bounds.lower..=bounds.upper).contains(a) {
            *inside.entry(t.measure.name()).or_default() += 1;
        } else {
            let by = (bounds.lower - a).max(a - bounds.upper) / t.standard_error;
            outside.push((t.measure.name(), t.condition.label(), by));
        }
    }
    for name in ["X_u", "Z_w"] {
        let n = inside.get(name).copied().unwrap_or(0);
        assert!(
            n >= MOST_OF_FOUR,
            "{name} inside at {n} of 4 airspeeds: {outside:?}"
        );
    }
    assert_eq!(outside.len(), 1, "{outside:?}");
    let (name, at, by) = &outside[0];
    assert_eq!(
        (*name, at.as_str()),
        ("X_u", "40 mph 425 kg"),
        "{outside:?}"
    );
    assert!(
        (by - X_U_40_MISS_SE).abs() < MISS_MOVES,
        "X_u at 40 mph {by:.3} standard errors outside, guarded at {X_U_40_MISS_SE}"
    );
    let phugoids: Vec<_> = run.modes.iter().filter(|m| m.mode == "phugoid").collect();
    assert_eq!(phugoids.len(), 4);
    for m in phugoids {
        assert!(m.after[0] > m.before[0], "{m:?}");
    }
}

/// A shipped fit restarted from its committed result (`corrections/fitted/<id>.yaml`): it
/// converges there again, to within a hundredth of each standard error (or of the bounds'
/// width, if narrower), so the committed corrections are still the fit's optimum for today's
/// model; and the fitted targets are closer to their references than at the fit file's start.
/// Returns the fit and the prediction rows' values at the committed corrections.
///
/// Cheaper than [`shipped_fit`]'s fit from the start (the PCA-2 fit's 20 evaluations of its
/// rows take 90 s in the test profile, the long pole of a cold `cargo test`): what it cannot see
/// is a second optimum that a fit from the start would now reach instead, which
/// `scripts/regenerate-references --check` covers by refitting from the start.
fn shipped_fit_restarted(
    id: &str,
) -> (cierva_harness::fit::file::FitFile, fit::FitResult, Vec<f64>) {
    use cierva_harness::fit;
    use cierva_harness::inputs::corrections;
    let f = fit::file::load(&repo().join(format!("fits/{id}.yaml"))).unwrap();
    let committed =
        corrections::load(&repo().join(format!("corrections/fitted/{id}.yaml"))).unwrap();
    assert_eq!(committed.target, f.applies_to);
    let start: Vec<f64> = f.problem.parameters.iter().map(|p| p.start).collect();
    let mut restarted = f.problem.clone();
    for p in &mut restarted.parameters {
        p.start = p
            .kind
            .get(&committed.corrections)
            .expect("the committed file has it");
    }
    let r = fit::fit(&restarted);
    eprintln!(
        "{id} restarted: {:?} after {} iterations ({} evaluations), cost {} -> {}: {:?} +- {:?}",
        r.status, r.iterations, r.evaluations, r.cost_start, r.cost, r.values, r.standard_errors
    );
    assert_eq!(r.status, Status::Converged, "{r:?}");
    for ((p, q), (v, se)) in restarted
        .parameters
        .iter()
        .zip(&f.problem.parameters)
        .zip(r.values.iter().zip(&r.standard_errors))
    {
        let within = 0.01 * se.min(q.upper - q.lower);
        assert!(
            (p.start - v).abs() <= within,
            "{}: committed {}, fitted now {v} (standard error {se}): re-run `cierva fit fits/{id}.yaml`",
            p.kind.name(),
            p.start
        );
    }
    let before = fit::evaluate(&f.problem, &start).unwrap();
    let (before, after, n) =
        fit::file::rms_relative_error_percent(&f.problem.targets, &before, &r.after);
    assert_eq!(n, f.problem.targets.len());
    assert!(after < 0.6 * before, "{before} -> {after}");
    let predicted = fit::values_or_nan(&f.prediction_problem(), &r.values);
    (f, r, predicted)
}

/// The PCA-2 fit to TR 515 (rotor speed, C_L and C_D of every eighth row at mu <= 0.35; the
/// angle, C_L and C_D above): the fitted targets' RMS relative error falls (20.9 % to 9.2 %)
/// and the prediction on the rows not fitted is computed and reported. Its known discrepancy
/// is a number guarded here: the fitted pitch offset (+1.113 deg, the wake skew in seed 003's
/// modulus form since issue 33) leaves 14 of the 31 rows not fitted above mu 0.35 without an
/// autorotative equilibrium (42 targets), and none below; a change that loses more, or loses
/// one below mu 0.35, fails.
///
/// The number was 17 rows (51 targets) until the fit's trust-region fix (CHANGELOG, Fixed):
/// the fit had stopped short at pitch +1.038 deg and drag x1.1425; its optimum then, +1.030 deg
/// and x1.1476 (cost 361.6 -> 357.5), lost 78 targets. With the rotor's periodic solution found
/// by secant steps (changes in the sixth figure) the fit took another path, to +1.0595 deg and
/// x1.1481 (cost 359.9, 1.5 standard errors from +1.030), which loses 69. With the angle
/// solved for directly (the old search missed equilibria at its fold, and once at mu 0.373 far
/// from it) the fit goes to +1.044 deg and x1.168 (cost 350.2) and loses 42, 14 rows above mu
/// 0.35: the guard is that. From four starts the file kept +1.057 deg and x1.166 (cost 349.6),
/// which lost the same 42; with the modulus form the four starts end together at +1.113 deg and
/// x1.162 (cost 381.6), which loses the same 42 again; restarted from there, the fit stays.
///
/// Slow for the cold `cargo test` (6 s in a test build, 2026-11-26; it was 100 s, then 20 s),
/// so `.ci/run` runs it with `cargo test --test suite -- --ignored`.
#[test]
#[ignore = "slow reference check (about 6 s in a test build, 2026-11-26; it was 100 s): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn pca2_fit_to_tr515_improves_its_rows_and_reports_the_others() {
    // Restarted from the committed corrections: still the optimum, the fitted targets' RMS
    // below 0.6 of the start's.
    let (f, _, predicted) = shipped_fit_restarted("pca-2-tr515");
    // With the signed wake-skew form it stopped where every step the trust region allowed lost
    // an equilibrium somewhere, and said so; with the modulus form it converges short of that
    // edge (issue 33, item 4), which the committed report shows.
    assert_eq!(predicted.len(), f.predict.len());
    let unsolved: Vec<String> = predicted
        .iter()
        .zip(&f.predict_origins)
        .filter(|(v, _)| !v.is_finite())
        .map(|(_, o)| cierva_harness::fit::file::check_of(&o.label))
        .collect();
    assert!(
        unsolved.len() <= 42,
        "{} of {} predicted targets unsolved (42 when last accepted)",
        unsolved.len(),
        f.predict.len()
    );
    let above = f
        .cross_validation
        .as_ref()
        .and_then(|cv| cv.regimes.iter().find(|r| r.name == "mu > 0.35"))
        .expect("the fit file's regime above mu 0.35");
    for c in &unsolved {
        assert!(
            above.checks.contains(c),
            "{c} (at mu <= 0.35) lost its equilibrium"
        );
    }
}

/// Every shipped fit file loads: its cases, checks and quantities resolve.
#[test]
fn every_shipped_fit_file_loads() {
    let mut n = 0;
    for e in std::fs::read_dir(repo().join("fits")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "yaml") {
            let f =
                cierva_harness::fit::file::load(&p).unwrap_or_else(|e| panic!("{}", e.render()));
            assert!(!f.problem.targets.is_empty());
            n += 1;
        }
    }
    assert!(n >= 2);
}

/// A fit file in a scratch directory, naming the shipped aircraft file by its absolute path.
fn scratch_fit(name: &str, parameters: &str) -> std::path::PathBuf {
    let dir = crate::common::scratch("fit");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.yaml"));
    let text = format!(
        "id: {name}\ntitle: t\nprovenance: {{source: a test}}\nsubject:\n  aircraft: {{file: {}, mass_kg: 450.0, density_altitude_ft: 2000.0}}\nparameters:\n{parameters}targets:\n  - condition: {{airspeed_mph: 70.0}}\n    quantity: N_v\n    reference: 0.059\n    standard_error: 0.002\n    source: a test\n",
        repo().join("aircraft/vpm-m16.yaml").display()
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// A fit file's number of starts is 1 to 32 (each a whole fit): 0 and 33 are refused at
/// `options.starts`, with the line; 4 loads.
#[test]
fn a_fit_files_starts_are_bounded() {
    use cierva_harness::fit;
    for (n, ok) in [(0usize, false), (4, true), (33, false)] {
        let path = scratch_fit(&format!("starts-{n}"), "  airframe.fin.area_m2: {}\n");
        let text = std::fs::read_to_string(&path).unwrap() + &format!("options: {{starts: {n}}}\n");
        std::fs::write(&path, &text).unwrap();
        match fit::file::load(&path) {
            Ok(f) => assert!(ok && f.starts == n, "{n} starts loaded"),
            Err(e) => {
                let m = e.render();
                assert!(!ok, "{n}: {m}");
                assert!(
                    m.contains("options.starts") && m.contains("give 1 to 32"),
                    "{m}"
                );
                assert!(e.line.is_some(), "{m}");
            }
        }
    }
}

/// A fit moves an aircraft's physical parameter only where the file calls it estimated and
/// gives it a plausible range, and only within that range; it starts from the file's value. A
/// refusal names the parameter's line.
#[test]
fn a_fit_moves_only_estimated_parameters_within_their_sourced_ranges() {
    use cierva_harness::fit;
    let f = fit::file::load(&scratch_fit("fin", "  airframe.fin.area_m2: {}\n")).unwrap();
    let p = f.problem.parameters[0].clone();
    assert_eq!(p.kind, ParameterKind::Estimated("airframe.fin.area_m2"));
    assert_eq!((p.lower, p.upper, p.start), (0.5, 0.9, 0.7));
    let narrower = fit::file::load(&scratch_fit(
        "narrow",
        "  airframe.fin.area_m2: {lower: 0.6, upper: 0.8}\n",
    ))
    .unwrap();
    assert_eq!(narrower.problem.parameters[0].lower, 0.6);
    for (name, line, says) in [
        (
            "convention",
            "  airframe.reference_point_m.x: {}\n",
            "is not an estimate",
        ),
        (
            "unranged",
            "  main_rotor.pivot_m.x: {}\n",
            "no plausible range",
        ),
        (
            "wide",
            "  airframe.fin.area_m2: {lower: 0.3, upper: 0.9}\n",
            "reach outside",
        ),
        (
            "unknown",
            "  airframe.fin.area_m3: {}\n",
            "did you mean `airframe.fin.area_m2`",
        ),
        (
            "unbounded",
            "  propeller_blockage: {}\n",
            "needs its bounds",
        ),
    ] {
        let e = fit::file::load(&scratch_fit(name, line))
            .unwrap_err()
            .render();
        assert!(e.contains(says), "{name}: {e}");
        assert!(e.contains("parameters."), "{name}: {e}");
        assert!(e.contains(":7:"), "{name}: not located on its line: {e}");
    }
}

/// Fitted physical parameters travel in a corrections file as `estimated:` and are applied to
/// the aircraft; a name that is not a physical parameter, or a rotor as the target, is refused.
#[test]
fn estimated_parameters_in_a_corrections_file_are_applied_and_checked() {
    use cierva_harness::inputs::corrections::{self, CorrectionSet};
    let mut set = CorrectionSet::default();
    ParameterKind::Estimated("mass.izz_kg_m2").set(&mut set, 400.0);
    ParameterKind::PropellerBlockage.set(&mut set, 0.5);
    let mut a = vpm();
    set.apply_to_aircraft(&mut a).unwrap();
    assert_eq!(a.mass.izz_kg_m2, 400.0);
    assert_eq!(a.propeller.propeller.blockage, 0.5);
    assert!(set.needs_aircraft());
    assert!(set.describe().contains("mass.izz_kg_m2=400"));
    // A control's travel is its gearing: the middle stays.
    let roll = a.controls.shaft_roll_rad;
    let travel = "controls.shaft_roll_deg.travel";
    assert!(
        (cierva_harness::inputs::parameters::parameter(&a, travel).unwrap() - 16.0).abs() < 1e-12
    );
    cierva_harness::inputs::parameters::set_parameter(&mut a, travel, 12.0).unwrap();
    let m = a.controls.shaft_roll_rad;
    assert!((m.at_100_percent - m.at_0_percent - 12f64.to_radians()).abs() < 1e-12);
    assert!(
        ((m.at_100_percent + m.at_0_percent) - (roll.at_100_percent + roll.at_0_percent)).abs()
            < 1e-12
    );
    let dir = crate::common::scratch("corr");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, applies, estimated, says) in [
        ("ok", "aircraft: vpm-m16", "mass.izz_kg_m2: 400.0", ""),
        (
            "typo",
            "aircraft: vpm-m16",
            "mass.izz_kg_m3: 400.0",
            "did you mean `mass.izz_kg_m2`",
        ),
        (
            "rotor",
            "rotor: pca-2",
            "mass.izz_kg_m2: 400.0",
            "correct an aircraft",
        ),
    ] {
        let path = dir.join(format!("{name}.yaml"));
        std::fs::write(
            &path,
            format!(
                "id: {name}\ntitle: t\napplies_to: {{{applies}}}\ncorrections:\n  estimated: {{{estimated}}}\nprovenance: {{source: a test}}\n"
            ),
        )
        .unwrap();
        match corrections::load(&path) {
            Ok(c) => {
                assert!(says.is_empty(), "{name} loaded");
                assert_eq!(c.corrections.estimated["mass.izz_kg_m2"], 400.0);
            }
            Err(e) => assert!(
                !says.is_empty() && e.render().contains(says),
                "{name}: {}",
                e.render()
            ),
        }
    }
}

/// Seed 001 Table 2 (issue 17's honest fit): the estimated fin, pod side-force centre, inertias
/// and lateral stick gearing, within their files' ranges, bring Y_v, N_r, L_p and L_eta_c
/// inside the flight bounds at both weights. Since the fin's sidewash and slipstream share are
/// estimated by published methods (`cierva estimate`), their ranges are the methods' (sidewash
/// 0.0215-0.0756, where it was -0.3 to 0.3): with the signed wake-skew form the fit ended
/// infeasible, Y_v, L_p and N_r at minimum weight outside by 0.10, 0.28 and 0.003 standard
/// errors; with the modulus form (issue 33, item 4) it converges with all eight inside, eight of
/// its ten parameters on a bound (guarded here: none outside). Its RMS relative error falls by
/// half (36.3 % to 18.1 %): Y_v's reference is its bound's middle and it ends near the
/// bound. L_v and N_v stay outside (the prediction rows). Since the blades' flap inertia took the
/// hub's angular acceleration (issue 52, item 12), L_p is inside before the fit and I_xx ends
/// inside its range (about 255 kg m^2), where it ended at its end (200) before; L_eta_c, outside
/// before, needs the lateral gearing at its range's end. Ten parameters from eight targets are
/// not separately identifiable, and the fit says so rather than print standard errors.
#[test]
fn table2_fit_brings_four_of_six_inside_at_each_weight_and_says_the_rest_cannot() {
    let (f, run) = shipped_fit_by("vpm-m16-table2-reachable", true, 0.7);
    let r = &run.result;
    assert_eq!(f.problem.targets.len(), 8);
    let mut outside = 0;
    for (t, (b, a)) in f.problem.targets.iter().zip(r.before.iter().zip(&r.after)) {
        let bounds = t.bounds.unwrap();
        let slack = 1e-3 * t.standard_error;
        if !(bounds.lower - slack..=bounds.upper + slack).contains(a) {
            let by = (bounds.lower - a).max(a - bounds.upper) / t.standard_error;
            assert!(by < 0.5, "{t:?}: {a}, {by} standard errors outside");
            outside += 1;
        }
        if t.measure.name() == "L_eta_c" {
            assert!(!(bounds.lower..=bounds.upper).contains(b), "{t:?}: {b}");
        }
        if t.measure.name() == "L_p" {
            assert!((bounds.lower..=bounds.upper).contains(b), "{t:?}: {b}");
        }
    }
    assert_eq!(outside, 0, "{:?}", r.after);
    assert_eq!(f.predict.len(), 4);
    for (t, a) in f.predict.iter().zip(&run.predict_after) {
        let half = 1.96 * t.standard_error;
        assert!((a - t.reference).abs() > half, "{t:?}: {a} came inside");
    }
    let i = r
        .parameters
        .iter()
        .position(|k| k.name() == "mass.ixx_kg_m2")
        .unwrap();
    assert!(
        r.values[i] > 201.0 && r.values[i] < 319.0,
        "I_xx: {} (range 200-320)",
        r.values[i]
    );
    assert!(r.standard_errors.iter().all(|s| s.is_infinite()));
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("not separately identifiable"))
    );
}

/// A calibration that predicts a held-out regime worse than the uncorrected model is not applied
/// there by default (issue 36, item 7): `cierva fit` lists the regime's checks under
/// `not_applied_to` with the numbers, `validate` runs them on the uncorrected rotor and says so,
/// and an entry that gives no reason is refused.
#[test]
fn corrections_are_not_applied_to_a_regime_they_make_worse() {
    use cierva_harness::fit;
    use cierva_harness::inputs::corrections;
    use cierva_harness::suite::{case, outcome};
    use cierva_harness::uncertainty::calibration::{CrossValidation, Errors};
    let f = fit::file::load(&repo().join("fits/pca-2-tr515.yaml")).unwrap();
    let worse = Errors {
        worse_than_uncorrected: vec!["drag_coefficient".into()],
        rms_relative_error: [("drag_coefficient".to_string(), 0.25)].into(),
        uncorrected_rms_relative_error: [("drag_coefficient".to_string(), 0.23)].into(),
        ..Default::default()
    };
    let cv = CrossValidation {
        groups: vec![],
        bands: true,
        fits: Default::default(),
        all: Errors::default(),
        regimes: [
            ("mu <= 0.35".to_string(), Errors::default()),
            ("mu > 0.35".to_string(), worse),
        ]
        .into_iter()
        .collect(),
        held_out: vec![],
    };
    let held = cierva_harness::uncertainty::calibration::not_applied_to(&f, &cv);
    assert_eq!(held.len(), 1, "{held:?}");
    assert_eq!(held[0].case, "naca-tr515-table-iii");
    assert_eq!(held[0].regime, "mu > 0.35");
    assert!(held[0].checks.contains(&"row-65".to_string()));
    assert!(!held[0].checks.contains(&"row-01".to_string()));
    assert!(
        held[0]
            .reason
            .contains("drag_coefficient 25.0 % RMS against 23.0 % uncorrected"),
        "{}",
        held[0].reason
    );

    // On TR 487's descent: the profile drag doubled moves the rotor speed, except where the
    // file is not applied.
    let dir = crate::common::scratch("not-applied");
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, extra: &str| {
        let path = dir.join(format!("{name}.yaml"));
        std::fs::write(
            &path,
            format!(
                "id: {name}\ntitle: t\napplies_to: {{rotor: pca-2-rotor}}\ncorrections: \
                 {{profile_drag_scale: 2.0}}\nprovenance: {{source: a test}}\n{extra}"
            ),
        )
        .unwrap();
        path
    };
    let everywhere = corrections::load(&write("everywhere", "")).unwrap();
    let not_here = corrections::load(&write(
        "not-here",
        "not_applied_to:\n  - {case: naca-tr487-vertical-descent, regime: descent, checks: \
         [flight], reason: held out it was worse}\n",
    ))
    .unwrap();
    let tr487 = case::load(&repo().join("cases/naca-tr487-vertical-descent.yaml")).unwrap();
    let check = &tr487.checks[0];
    assert_eq!(check.id, "flight");
    let values = |c: &case::Case| -> Vec<f64> {
        outcome::run_check(c, check)
            .quantities
            .iter()
            .map(|q| q.value)
            .collect()
    };
    let plain = values(&tr487);
    let (doubled, used) = case::with_corrections(&tr487, &[everywhere]).unwrap();
    assert_eq!(used, ["everywhere"]);
    assert!(doubled.uncorrected.is_none());
    assert_ne!(values(&doubled), plain);
    let (kept, used) = case::with_corrections(&tr487, &[not_here]).unwrap();
    assert_eq!(used, ["not-here"]);
    assert_eq!(values(&kept), plain);
    let reasons = &kept.uncorrected.as_ref().unwrap().reasons;
    assert!(
        reasons[0].contains("not-here not applied to 1 check(s) (descent): held out it was worse"),
        "{reasons:?}"
    );
    let e = corrections::load(&write(
        "no-reason",
        "not_applied_to:\n  - {case: c, regime: r, checks: [a], reason: ' '}\n",
    ))
    .unwrap_err();
    assert!(e.render().contains("say why"), "{}", e.render());
    std::fs::remove_dir_all(&dir).ok();
}

/// A corrections file states the domain it was fitted on, and a check outside it runs with the
/// corrections and says it is an extrapolation (issue 51, item 5): TR 515's rows above the
/// fitted tip-speed ratios, in the check's result (text and JSON) and its explanation. On the
/// old code a file had no domain and nothing said so.
#[test]
fn a_check_outside_the_fitted_domain_is_labelled_an_extrapolation() {
    use cierva_harness::inputs::corrections;
    use cierva_harness::suite::{case, outcome};
    let dir = crate::common::scratch("domain");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("low-mu.yaml");
    std::fs::write(
        &path,
        "id: low-mu\ntitle: t\napplies_to: {rotor: pca-2-rotor}\ncorrections: \
         {profile_drag_scale: 1.1}\nprovenance: {source: a test}\n\
         domain: {tip_speed_ratio: [0.1, 0.35]}\n",
    )
    .unwrap();
    let file = corrections::load(&path).unwrap();
    let tr515 = case::load(&repo().join("cases/naca-tr515-table-iii.yaml")).unwrap();
    let (corrected, used) = case::with_corrections(&tr515, &[file]).unwrap();
    assert_eq!(used, ["low-mu"]);
    let extrapolated = &corrected.calibrations[0].extrapolated;
    let mu = |id: &str| {
        tr515
            .checks
            .iter()
            .find(|c| c.id == id)
            .and_then(|c| c.behaviour().tunnel())
            .and_then(|t| t.tip_speed_ratio)
            .unwrap()
    };
    // Exactly the rows whose tip-speed ratio lies above the domain.
    for c in &tr515.checks {
        let outside = mu(&c.id) > 0.35 * (1.0 + corrections::DOMAIN_ROUNDING);
        assert_eq!(
            extrapolated.contains_key(&c.id),
            outside,
            "{} at mu {}",
            c.id,
            mu(&c.id)
        );
    }
    let (id, why) = extrapolated.iter().next().expect("rows above mu 0.35");
    assert!(
        why.contains("extrapolation: low-mu was fitted on tip-speed ratio [0.1, 0.35]"),
        "{why}"
    );
    let check = tr515.checks.iter().find(|c| &c.id == id).unwrap();
    let r = outcome::run_check(&corrected, check);
    assert_eq!(r.extrapolation.as_deref(), Some(why.as_str()));
    assert!(
        r.explain().contains("extrapolation: low-mu"),
        "{}",
        r.explain()
    );
    let json = serde_json::to_value(&r).unwrap();
    assert_eq!(json["extrapolation"].as_str(), Some(why.as_str()));
    // Inside the domain, nothing is said.
    let inside = tr515.checks.iter().find(|c| mu(&c.id) <= 0.35).unwrap();
    assert!(
        outcome::run_check(&corrected, inside)
            .extrapolation
            .is_none()
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A check the fit was fitted to is `calibrated_on` its corrections file once they are applied
/// (issue 51, item 1): `cierva fit` writes the fit's checks by case, the check's result says so
/// (text and JSON), and an uncertainty study counts its verdict apart, never as validation. On
/// the old code nothing marked a fit's own targets.
#[test]
fn a_fits_own_targets_are_calibrated_on_it_and_counted_apart() {
    use cierva_harness::inputs::corrections;
    use cierva_harness::suite::{case, outcome};
    // What the TR 515 fit writes: its ten rows, by case.
    let f = fit::file::load(&repo().join("fits/pca-2-tr515.yaml")).unwrap();
    let on = fit::file::calibrated_on(&f.origins);
    let rows = &on["naca-tr515-table-iii"];
    assert_eq!(on.len(), 1, "{on:?}");
    assert_eq!(rows.len(), 10, "{rows:?}");
    assert!(rows.contains(&"row-01".to_string()), "{rows:?}");
    // Applied to TR 487 with its one check among the fit's.
    let dir = crate::common::scratch("calibrated");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("own.yaml");
    std::fs::write(
        &path,
        "id: own\ntitle: t\napplies_to: {rotor: pca-2-rotor}\ncorrections: \
         {profile_drag_scale: 1.1}\nprovenance: {source: a test}\n\
         calibrated_on: {naca-tr487-vertical-descent: [flight]}\n",
    )
    .unwrap();
    let file = corrections::load(&path).unwrap();
    let tr487 = case::load(&repo().join("cases/naca-tr487-vertical-descent.yaml")).unwrap();
    let check = &tr487.checks[0];
    assert!(outcome::run_check(&tr487, check).calibrated_on.is_none());
    let (corrected, _) = case::with_corrections(&tr487, &[file]).unwrap();
    let r = outcome::run_check(&corrected, check);
    assert_eq!(r.calibrated_on.as_deref(), Some("own"));
    assert!(
        r.explain()
            .contains("calibrated on: a target of the fit of own"),
        "{}",
        r.explain()
    );
    assert_eq!(serde_json::to_value(&r).unwrap()["calibrated_on"], "own");
    let summary = cierva_harness::report::tables::class_summary(std::slice::from_ref(&r));
    assert!(
        summary.contains("calibrated on    1 check above, 1 of them validation"),
        "{summary}"
    );
    // Its quantities' verdicts count apart from the validation verdicts.
    let settings = cierva_harness::uncertainty::propagate::PropagationSettings {
        samples: 4,
        seed: 0,
        validation_only: true,
        method: Default::default(),
    };
    let study = cierva_harness::uncertainty::study::propagate(&corrected, settings, || ());
    std::fs::remove_dir_all(&dir).ok();
    let study = study.unwrap();
    let counts = cierva_harness::uncertainty::propagate::VerdictCounts::of(&study.results);
    assert_eq!(counts.total(), 0, "{counts:?}");
    assert_eq!(counts.calibrated_on, study.results.len(), "{counts:?}");
    assert!(
        counts.describe().contains("calibrated on"),
        "{}",
        counts.describe()
    );
}

/// Birge's ratio: a fit whose targets scatter about the fitted model by more than their
/// standard errors say has its standard errors scaled by `sqrt(chi^2 / nu)`, and says so; one
/// within them keeps its standard errors (issue 51, item 5). The synthetic truth's targets
/// with one of them moved by 10 standard errors: chi^2 is known from the fit's own residuals.
#[test]
fn standard_errors_are_scaled_by_birges_ratio_where_the_targets_scatter() {
    let mut problem = synthetic_truth();
    // At the truth, within the standard errors: nothing is scaled.
    let exact = fit::fit(&problem);
    let mut kept = exact.clone();
    let b = fit::scale_by_birge(&problem, &mut kept).unwrap();
    assert_eq!(b.factor, 1.0, "{b:?}");
    assert_eq!(kept.standard_errors, exact.standard_errors);
    assert_eq!(b.degrees_of_freedom, 6 - 2);
    // One target 10 standard errors off: chi^2/nu well above 1, and the factor is its root.
    problem.targets[3].reference += 10.0 * problem.targets[3].standard_error;
    let moved = fit::fit(&problem);
    let mut scaled = moved.clone();
    let b = fit::scale_by_birge(&problem, &mut scaled).unwrap();
    let chi2: f64 = problem
        .targets
        .iter()
        .zip(&moved.after)
        .map(|(t, y)| ((y - t.reference) / t.standard_error).powi(2))
        .sum();
    assert!((b.chi_square - chi2).abs() <= 1e-9 * chi2);
    assert!(b.chi_square / 4.0 > 1.0, "{b:?}");
    assert!((b.factor - (chi2 / 4.0).sqrt()).abs() < 1e-12, "{b:?}");
    for (s, s0) in scaled.standard_errors.iter().zip(&moved.standard_errors) {
        assert!((s / s0 - b.factor).abs() < 1e-12, "{s} {s0}");
    }
    assert!(
        scaled.warnings.iter().any(|w| w.contains("(Birge)")),
        "{:?}",
        scaled.warnings
    );
}

/// A check of a ratio of derivatives (`Q_u` divided by `Q_w`) measures the aircraft changed by
/// the check, not one derivative of it: a fit that names it is refused, where it once took the
/// ratio's interval (0 to 1, seed 002's `Q_u < Q_w`) for an interval on `Q_u`.
#[test]
fn a_fit_refuses_a_check_of_a_ratio_as_a_reference() {
    use cierva_harness::fit;
    let case = repo().join("cases/vpm-m16-stability-max-weight.yaml");
    let target = |check: &str| {
        let path = scratch_fit(&format!("ratio-{check}"), "  airframe.fin.area_m2: {}\n");
        let text = std::fs::read_to_string(&path).unwrap();
        let (head, _) = text.split_once("targets:").unwrap();
        let text = format!(
            "{head}targets:\n  - case: {}\n    checks: [{check}]\n",
            case.display()
        );
        std::fs::write(&path, text).unwrap();
        fit::file::load(&path)
    };
    let e = target("q-u-over-q-w-30mph").unwrap_err().render();
    assert!(
        e.contains("q-u-over-q-w-30mph")
            && e.contains("a ratio")
            && e.contains("not a reference to fit"),
        "{e}"
    );
}

/// Every shipped fit's committed errors (`fit.errors` of `corrections/fitted/<id>.yaml`, which
/// the documents quote) are what the model gives today at the committed corrections and at the
/// fit's start: a change of the model that moves a fit's targets fails here, naming the fit to
/// run again (`pca-2-tr515-elastic` went stale that way, unnoticed, until 2026-11-27).
///
/// Slow for the cold `cargo test` (every fit's targets and predictions evaluated twice, about a
/// minute in a test build), so `.ci/run` runs it with `cargo test --test suite -- --ignored`.
#[test]
#[ignore = "slow reference check (about a minute in a test build, 2026-11-27): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn every_shipped_fits_committed_errors_are_todays() {
    use cierva_harness::fit::file::ErrorSummary;
    use cierva_harness::inputs::corrections;
    let mut paths: Vec<std::path::PathBuf> = std::fs::read_dir(repo().join("fits"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "yaml"))
        .collect();
    paths.sort();
    let mut stale = Vec::new();
    for path in &paths {
        let f = fit::file::load(path).unwrap_or_else(|e| panic!("{}", e.render()));
        let id = path.file_stem().unwrap().to_string_lossy().to_string();
        let file = repo().join(format!("corrections/fitted/{id}.yaml"));
        let committed = corrections::load(&file).unwrap();
        let start: Vec<f64> = f.problem.parameters.iter().map(|p| p.start).collect();
        let end: Vec<f64> = f
            .problem
            .parameters
            .iter()
            .map(|p| {
                p.kind
                    .get(&committed.corrections)
                    .expect("the committed file has it")
            })
            .collect();
        let predict = f.prediction_problem();
        let today = [
            ("fitted", Some((&f.problem, &f.problem.targets))),
            (
                "predicted",
                (!f.predict.is_empty()).then_some((&predict, &f.predict)),
            ),
        ];
        let doc: serde_yaml::Value =
            serde_yaml::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
        for (part, problem) in today {
            let now = problem.map(|(p, t)| {
                ErrorSummary::of(
                    t,
                    &fit::values_or_nan(p, &start),
                    &fit::values_or_nan(p, &end),
                )
            });
            let now = serde_yaml::to_value(now).unwrap();
            let was = &doc["fit"]["errors"][part];
            if !same_numbers(&now, was) {
                stale.push(format!(
                    "{id} {part}: committed {}, today {}",
                    serde_yaml::to_string(was).unwrap(),
                    serde_yaml::to_string(&now).unwrap()
                ));
            }
        }
    }
    assert!(paths.len() >= 11, "{} fit files", paths.len());
    assert!(
        stale.is_empty(),
        "fits whose committed errors are not the model's today (re-run `cierva fit fits/<id>.yaml`):\n{}",
        stale.join("\n")
    );
}

/// Two YAML values with the same shape and numbers, each within 1e-6 of the larger (the last
/// bits of a solution evaluated again); counts and names exactly.
fn same_numbers(a: &serde_yaml::Value, b: &serde_yaml::Value) -> bool {
    use serde_yaml::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => (x - y).abs() <= 1e-6 * x.abs().max(y.abs()).max(1.0),
            _ => false,
        },
        (Value::Mapping(x), Value::Mapping(y)) => {
            x.len() == y.len()
                && x.iter()
                    .all(|(k, v)| y.get(k).is_some_and(|w| same_numbers(v, w)))
        }
        _ => a == b,
    }
}
