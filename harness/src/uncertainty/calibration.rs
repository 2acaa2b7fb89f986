//! Calibrations that state their predictive error: a fit's targets left out a group at a time
//! (a rotor-speed group, a mu band, a condition), the fit redone on the rest, and the left-out
//! targets predicted. The predictive error per quantity and regime is what a calibration claims
//! for data it did not see; the model-discrepancy term is the spread of those errors beyond the
//! data's own scatter, so that an interval `prediction +- 1.96 sqrt(se^2 + sd_d^2)` covers
//! held-out rows at its stated rate (a known answer over synthetic calibrations in
//! `harness/tests/suite/uncertainty.rs`).
//!
//! Errors are relative to each target's reference (`(model - reference) / reference`), as the
//! fit's own before/after table has them, and over the targets the model solved.

use crate::fit;
use crate::fit::file::{FitFile, FitRun, NamedChecks, check_of};
use serde::Serialize;
use std::collections::BTreeMap;

/// The 95 % coverage factor of a normal distribution.
pub const Z95: f64 = 1.959_963_985;

/// The discrepancy's standard deviation from held-out relative errors `e` and the data's
/// relative standard errors `se`: the spread of the errors beyond the data's scatter,
/// `sqrt(max(0, mean(e^2 - se^2)))` (a method of moments; zero where the data's scatter
/// explains the errors). NaN errors are left out; NaN for no finite error.
pub fn discrepancy_sd(e: &[f64], se: &[f64]) -> f64 {
    let pairs: Vec<(f64, f64)> = e
        .iter()
        .zip(se)
        .filter(|(e, s)| e.is_finite() && s.is_finite())
        .map(|(e, s)| (*e, *s))
        .collect();
    if pairs.is_empty() {
        return f64::NAN;
    }
    let excess = pairs.iter().map(|(e, s)| e * e - s * s).sum::<f64>() / pairs.len() as f64;
    excess.max(0.0).sqrt()
}

/// Whether a held-out relative error `e` lies inside the stated 95 % predictive interval of a
/// target whose data have relative standard error `se`, given the discrepancy's `sd`.
pub fn covered(e: f64, se: f64, sd: f64) -> bool {
    e.is_finite() && e.abs() <= Z95 * (se * se + sd * sd).sqrt()
}

/// The RMS of the finite values (NaN for none).
pub fn rms(values: &[f64]) -> f64 {
    let v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
}

/// One held-out target.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldOut {
    /// `case-id/check-id`.
    pub label: String,
    /// The group left out with it, or `predicted` for a prediction of the fit file (never
    /// fitted).
    pub group: String,
    pub quantity: String,
    pub reference: f64,
    /// The data's standard error, relative to the reference.
    pub relative_standard_error: f64,
    /// The relative error predicted by the fit without this target's group (NaN: no solution).
    pub relative_error: f64,
    /// The uncorrected model's relative error.
    pub uncorrected_relative_error: f64,
}

/// The errors of one regime (or of all targets), per quantity.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Errors {
    /// Held-out targets per quantity that both the calibrated and the uncorrected model solved.
    pub targets: BTreeMap<String, usize>,
    /// Held-out targets without a solution: calibrated, and uncorrected.
    pub unsolved: BTreeMap<String, usize>,
    pub uncorrected_unsolved: BTreeMap<String, usize>,
    /// RMS relative error of the held-out predictions.
    pub rms_relative_error: BTreeMap<String, f64>,
    /// RMS relative error of the uncorrected model on the same targets.
    pub uncorrected_rms_relative_error: BTreeMap<String, f64>,
    /// The discrepancy's relative standard deviation beyond the data's scatter.
    pub discrepancy_relative_sd: BTreeMap<String, f64>,
    /// Quantities the calibration predicts worse than the uncorrected model, held out: a
    /// larger RMS error, or more targets without a solution.
    pub worse_than_uncorrected: Vec<String>,
}

/// A cross-validation of a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrossValidation {
    /// Its folds' names (bands or groups).
    pub groups: Vec<String>,
    /// Whether its folds are bands that hold every row in them (else groups of fitted checks,
    /// the predictions by the whole fit).
    pub bands: bool,
    /// Every target's group fit's status (`converged`, ...), by group.
    pub fits: BTreeMap<String, String>,
    pub all: Errors,
    pub regimes: BTreeMap<String, Errors>,
    pub held_out: Vec<HeldOut>,
}

/// The errors of the held-out targets `rows`.
pub fn errors<'a>(rows: impl IntoIterator<Item = &'a HeldOut>) -> Errors {
    let mut by: BTreeMap<String, Vec<&HeldOut>> = BTreeMap::new();
    for r in rows {
        by.entry(r.quantity.clone()).or_default().push(r);
    }
    let mut out = Errors::default();
    for (q, rows) in by {
        let solved: Vec<&&HeldOut> = rows
            .iter()
            .filter(|r| r.relative_error.is_finite() && r.uncorrected_relative_error.is_finite())
            .collect();
        let unsolved = rows
            .iter()
            .filter(|r| !r.relative_error.is_finite())
            .count();
        let uncorrected_unsolved = rows
            .iter()
            .filter(|r| !r.uncorrected_relative_error.is_finite())
            .count();
        out.targets.insert(q.clone(), solved.len());
        out.unsolved.insert(q.clone(), unsolved);
        out.uncorrected_unsolved
            .insert(q.clone(), uncorrected_unsolved);
        if solved.is_empty() {
            continue;
        }
        let e: Vec<f64> = solved.iter().map(|r| r.relative_error).collect();
        let u: Vec<f64> = solved
            .iter()
            .map(|r| r.uncorrected_relative_error)
            .collect();
        let se: Vec<f64> = solved.iter().map(|r| r.relative_standard_error).collect();
        let (cv, unc) = (rms(&e), rms(&u));
        out.rms_relative_error.insert(q.clone(), cv);
        out.uncorrected_rms_relative_error.insert(q.clone(), unc);
        out.discrepancy_relative_sd
            .insert(q.clone(), discrepancy_sd(&e, &se));
        if cv > unc || unsolved > uncorrected_unsolved {
            out.worse_than_uncorrected.push(q);
        }
    }
    out
}

/// One fold of a cross-validation: its name, and the fit's targets and predictions it holds
/// out (by index).
struct Fold {
    name: String,
    fitted: Vec<usize>,
    predicted: Vec<usize>,
}

/// The fit file's folds: its bands, each with every row in it
/// ([`crate::fit::file::Bands`]), or its groups of fitted checks (its predictions then by the
/// whole fit).
fn folds(f: &FitFile, spec: &crate::fit::file::CrossValidationSpec) -> Result<Vec<Fold>, String> {
    if let Some(b) = &spec.bands {
        return Ok(b
            .of(&f.problem.targets, &f.predict)?
            .into_iter()
            .map(|b| Fold {
                name: b.name,
                fitted: b.fitted,
                predicted: b.predicted,
            })
            .collect());
    }
    Ok(spec
        .groups
        .iter()
        .map(|g| Fold {
            name: g.name.clone(),
            fitted: (f.origins.iter().enumerate())
                .filter(|(_, o)| g.checks.contains(&check_of(&o.label)))
                .map(|(i, _)| i)
                .collect(),
            predicted: Vec::new(),
        })
        .collect())
}

/// The fit's targets left out a fold at a time (the fit file's `cross_validation`: `bands`, or
/// `groups`): each fold's fit on the rest, and its held-out rows predicted (a band's fitted
/// and unfitted rows alike); a prediction no fold holds, by the whole fit (`run`). The regimes
/// report apart. `done` is called after each fold's fit (a progress bar). The fits run one
/// after another (each uses the cores).
pub fn cross_validate(
    f: &FitFile,
    run: &FitRun,
    done: impl Fn(&str),
) -> Result<Option<CrossValidation>, String> {
    let Some(spec) = &f.cross_validation else {
        return Ok(None);
    };
    let folds = folds(f, spec)?;
    let mut held_out = Vec::new();
    let mut fits = BTreeMap::new();
    for g in &folds {
        let mut rest = f.problem.clone();
        rest.targets = (f.problem.targets.iter().enumerate())
            .filter(|(i, _)| !g.fitted.contains(i))
            .map(|(_, t)| t.clone())
            .collect();
        let r = fit::fit(&rest);
        fits.insert(g.name.clone(), r.status.name().to_string());
        let mut left = f.problem.clone();
        left.targets = (g.fitted.iter().map(|&i| f.problem.targets[i].clone()))
            .chain(g.predicted.iter().map(|&i| f.predict[i].clone()))
            .collect();
        let predicted =
            fit::evaluate_each(&left, &r.values).map_err(|e| format!("fold `{}`: {e}", g.name))?;
        let rows = (g.fitted.iter())
            .map(|&i| {
                let before = run.result.before.get(i).copied().unwrap_or(f64::NAN);
                (&f.problem.targets[i], &f.origins[i].label, before)
            })
            .chain(g.predicted.iter().map(|&i| {
                (
                    &f.predict[i],
                    &f.predict_origins[i].label,
                    run.predict_before[i],
                )
            }));
        for ((t, label, before), p) in rows.zip(predicted) {
            held_out.push(held(t, label, &g.name, p.unwrap_or(f64::NAN), before));
        }
        done(&g.name);
    }
    let in_a_fold = |i: usize| folds.iter().any(|g| g.predicted.contains(&i));
    for (i, t) in f.predict.iter().enumerate().filter(|(i, _)| !in_a_fold(*i)) {
        held_out.push(held(
            t,
            &f.predict_origins[i].label,
            "predicted",
            run.predict_after[i],
            run.predict_before[i],
        ));
    }
    let regimes = spec
        .regimes
        .iter()
        .map(|reg: &NamedChecks| {
            (
                reg.name.clone(),
                errors(
                    held_out
                        .iter()
                        .filter(|h| reg.checks.contains(&check_of(&h.label))),
                ),
            )
        })
        .collect();
    Ok(Some(CrossValidation {
        groups: folds.iter().map(|g| g.name.clone()).collect(),
        fits,
        all: errors(&held_out),
        regimes,
        held_out,
        bands: spec.bands.is_some(),
    }))
}

/// A held-out target's row: the calibrated and uncorrected values as relative errors.
fn held(t: &fit::Target, label: &str, group: &str, calibrated: f64, uncorrected: f64) -> HeldOut {
    let rel = |v: f64| (v - t.reference) / t.reference;
    HeldOut {
        label: label.to_string(),
        group: group.to_string(),
        quantity: t.measure.name().to_string(),
        reference: t.reference,
        relative_standard_error: (t.standard_error / t.reference).abs(),
        relative_error: rel(calibrated),
        uncorrected_relative_error: rel(uncorrected),
    }
}

/// What a corrections file records of a cross-validation: the groups, and per quantity (all
/// held-out targets, then each regime) the held-out RMS relative error, the uncorrected model's
/// on the same targets, the discrepancy term, the unsolved counts and the quantities made worse;
/// each regime with its checks by case (which checks a prediction takes the regime's error for).
pub fn summary(f: &FitFile, cv: &CrossValidation) -> serde_json::Value {
    let errors = |e: &Errors| {
        serde_json::json!({
            "rms_relative_error": e.rms_relative_error,
            "uncorrected_rms_relative_error": e.uncorrected_rms_relative_error,
            "discrepancy_relative_sd": e.discrepancy_relative_sd,
            "targets": e.targets,
            "unsolved": e.unsolved,
            "uncorrected_unsolved": e.uncorrected_unsolved,
            "worse_than_uncorrected": e.worse_than_uncorrected,
        })
    };
    let mut all = errors(&cv.all);
    if let serde_json::Value::Object(m) = &mut all {
        m.insert("groups".into(), serde_json::json!(cv.groups));
        // Each group's refit: one that did not converge predicted from its last iterate.
        m.insert("group_fits".into(), serde_json::json!(cv.fits));
        m.insert(
            "method".into(),
            serde_json::json!(format!(
                "{}; relative errors (model - reference) / reference; discrepancy sd = sqrt(max(0, mean(e^2 - se^2)))",
                match cv.bands {
                    true => format!(
                        "leave one band out ({} contiguous bands, each refitted on the fitted rows outside it and predicting every row in it, fitted or not)",
                        cv.groups.len()
                    ),
                    false => format!(
                        "leave one group out ({} groups, each refitted), and the fit file's predictions by the whole fit",
                        cv.groups.len()
                    ),
                }
            )),
        );
        m.insert(
            "regimes".into(),
            serde_json::Value::Object(
                cv.regimes
                    .iter()
                    .map(|(k, v)| {
                        let mut e = errors(v);
                        let spec = f.cross_validation.iter().flat_map(|s| &s.regimes);
                        if let (serde_json::Value::Object(m), Some(r)) =
                            (&mut e, spec.into_iter().find(|r| r.name == *k))
                        {
                            m.insert("checks".into(), serde_json::json!(regime_checks(f, r)));
                        }
                        (k.clone(), e)
                    })
                    .collect(),
            ),
        );
    }
    all
}

/// A regime's checks, by the case each comes from (the fit file's targets and predictions name
/// them `case/check`).
fn regime_checks(f: &FitFile, regime: &NamedChecks) -> BTreeMap<String, Vec<String>> {
    let labels: Vec<&str> = f
        .origins
        .iter()
        .chain(&f.predict_origins)
        .map(|o| o.label.as_str())
        .collect();
    let mut by_case: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for c in &regime.checks {
        if let Some(label) = labels.iter().find(|l| check_of(l) == *c)
            && let Some((case, _)) = label.rsplit_once('/')
        {
            let checks = by_case.entry(case.to_string()).or_default();
            if !checks.contains(c) {
                checks.push(c.clone());
            }
        }
    }
    by_case
}

/// The regimes a fit's corrections are not applied to by default: those where, held out, the
/// calibrated model predicts some quantity worse than the uncorrected one (a larger RMS error, or
/// more targets without a solution), with the case and checks of each and the numbers.
pub fn not_applied_to(
    f: &FitFile,
    cv: &CrossValidation,
) -> Vec<crate::inputs::corrections::NotApplied> {
    let Some(spec) = &f.cross_validation else {
        return vec![];
    };
    let mut out = Vec::new();
    for regime in &spec.regimes {
        let Some(e) = cv.regimes.get(&regime.name) else {
            continue;
        };
        if e.worse_than_uncorrected.is_empty() {
            continue;
        }
        let pct = |m: &BTreeMap<String, f64>, q: &str| {
            m.get(q)
                .map(|v| format!("{:.1} %", 100.0 * v))
                .unwrap_or_else(|| "-".into())
        };
        let count = |m: &BTreeMap<String, usize>, q: &str| m.get(q).copied().unwrap_or(0);
        let numbers: Vec<String> = e
            .worse_than_uncorrected
            .iter()
            .map(|q| {
                format!(
                    "{q} {} RMS against {} uncorrected, {} held-out targets unsolved against {}",
                    pct(&e.rms_relative_error, q),
                    pct(&e.uncorrected_rms_relative_error, q),
                    count(&e.unsolved, q),
                    count(&e.uncorrected_unsolved, q)
                )
            })
            .collect();
        let reason = format!(
            "cross-validated (leave one group out), the corrected model predicts this regime \
             worse than the uncorrected one: {}",
            numbers.join("; ")
        );
        for (case, checks) in regime_checks(f, regime) {
            out.push(crate::inputs::corrections::NotApplied {
                case,
                regime: regime.name.clone(),
                checks,
                reason: reason.clone(),
            });
        }
    }
    out
}
