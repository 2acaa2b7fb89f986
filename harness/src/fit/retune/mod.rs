//! From flight records to retuned corrections (`cierva retune`): fit the named corrections (or
//! estimated physical parameters) so that the model matches the records, weighted by the
//! records' own estimation errors, within bounds from their sources.
//!
//! The records' non-parametric frequency responses ([`responses`]: coherence, random error, the
//! other controls' measured transfers) are matched by the model's responses as flown, from the
//! linearisation with the rotor's flapping states: the model structure of the records' own
//! aircraft (the quasi-static linearisation only where the hub has no flapping linearisation,
//! and the output says so). Records at several conditions fit one set of corrections across
//! all of them.
//!
//! Matching the quasi-static linearisation's derivatives to the derivatives identified from the
//! records was the other method until issue 32: its intervals held the truth in 18 of 60
//! coverage trials (a rotor whose blades flap is not a quasi-static one), so it was removed
//! (`docs/validation.md`, "Retuning the corrections").

pub mod matched;
pub mod responses;
pub mod subject;

use crate::fit::{self, FitParameter, ParameterKind, Problem, TargetCondition};
use crate::ident;
use crate::inputs::aircraft::AircraftFile;
use crate::inputs::corrections::{CorrectionSet, CorrectionsFileSpec};
use crate::inputs::record::Record;
use serde::Serialize;

/// A correction's default bounds when the command line gives none, with their source.
pub const DEFAULT_BOUNDS: [(ParameterKind, f64, f64, &str); 6] = [
    (
        ParameterKind::PropellerBlockage,
        0.0,
        1.0,
        "seed 000 Sec. VII.A: the fraction of the free stream the rotor's wake takes from the propeller disc",
    ),
    (
        ParameterKind::HubAoaFactor,
        0.0,
        1.0,
        "seed 000 Sec. VII.A: the hub sees a fraction of the c.g.'s angle of attack (the wake of the pod and mast slows and turns the flow), none to all of it",
    ),
    (
        ParameterKind::ProfileDragScale,
        0.5,
        2.0,
        "estimated: a section's drag from half to twice its tabulated value",
    ),
    (
        ParameterKind::ProfileDragIncrement,
        -0.005,
        0.02,
        "estimated: a blade's roughness and fittings add up to 0.02 to the section drag; -0.005 for a smoother blade than tabulated",
    ),
    (
        ParameterKind::PitchOffsetDeg,
        -2.0,
        2.0,
        "estimated: a blade's rigging is known to a degree or two",
    ),
    (
        ParameterKind::LateralInflowOffsetMS,
        -1.0,
        1.0,
        "estimated: seed 003's lateral inflow departs from the model's by up to about 1 m/s",
    ),
];

/// A parameter to retune: its name and optional bounds (`None`: the defaults above, or an
/// estimated physical parameter's plausible range from the aircraft file).
#[derive(Debug, Clone, PartialEq)]
pub struct RetuneParameter {
    pub name: String,
    pub bounds: Option<(f64, f64)>,
}

/// A retune's fit has converged when its step is below this fraction of every parameter's
/// range (or the cost falls by less than this fraction). The fit's default, 1e-6, is below the
/// noise of a flapping linearisation's harmonic balance and its trim: the retune benchmark's fit
/// from four records stopped at its limit of 20 iterations still taking steps of that size. A
/// retuned correction's standard error is half a percent of its range or more (the
/// benchmark's hub factor: 0.008 of 1), so a step of a hundredth of a percent moves no stated
/// interval.
pub const TOLERANCE: f64 = 1e-4;

/// A retune has also converged when a fresh linearisation predicts the cost to fall by at most
/// this much ([`fit::FitOptions::distance_to_minimum`]; an accepted step that lowers it by at
/// most this much sends the fit to that check): the linearisation's minimum is then within 0.1
/// of a standard error of every parameter, which moves a 95 % interval's coverage to 94.9 % at
/// worst. The retune's cost is a chi-square (each response point weighted by its random
/// error). Measured on the coverage trials (`scripts/retune-trials --throttle`, three
/// corrections): near the minimum the model's texture (below, [`DIFFERENCE_STEP`]) makes
/// predicted falls of 0.2-1 that the evaluated cost does not follow, and accepted steps of
/// 1e-4; 9 of 60 fits ran to their iteration limit there before this rule and the wider step,
/// none of 60 after.
pub const DISTANCE_TO_MINIMUM: f64 = 0.01;

/// A retune's finite-difference step, a fraction of each parameter's range (the fit's default
/// is 1e-3). The responses come from a trim and a harmonic balance whose tolerances leave a
/// ripple in them, and from tabulated section data whose breakpoints put kinks in the cost: on
/// a coverage trial's records, the cost along the profile-drag scale changes its slope by 19
/// chi-square units per unit at the optimum within 0.003 of it. A step of 1e-3 of the range
/// (0.0015 of the drag scale) differences that texture, and the fitted direction changed sign
/// between fresh Jacobians; a step of 1e-2 spans it and measures the slope over a tenth of a
/// standard error or so. Measured on 30 trials with three corrections, stick and throttle
/// sweeps (`scripts/retune-trials --throttle`, seed 1): 5 fits ran to their iteration limit
/// with 1e-3 (4 with the distance rule above), none with 1e-2 and the rule; the profile drag's
/// intervals held 24 of 30 with 1e-3 and the rule, 29 with 1e-2.
pub const DIFFERENCE_STEP: f64 = 1e-2;

/// A retune's iteration limit (the fit's default is 20): three corrections from the
/// uncorrected aircraft, far from a truth near a bound, were still falling after 20 iterations
/// in one coverage trial of 40, and converged after 29 (the first fit's and the second's
/// together).
pub const MAX_ITERATIONS: usize = 50;

/// How to retune: the responses' estimation, and where the fit's evaluations run (this
/// machine's threads by default; through plans for a model too slow for one machine:
/// [`crate::plan::fit::retune_batches`]). The responses before the fit and after it, one
/// evaluation a condition each, run on this machine.
#[derive(Debug, Clone, Default)]
pub struct How {
    pub responses: responses::ResponseSettings,
    pub executor: crate::fit::Executor,
}

/// A retune: the records' responses, the fit problem and its result.
#[derive(Debug, Clone)]
pub struct Retune {
    /// Each condition and its records' ids.
    pub conditions: Vec<(TargetCondition, Vec<String>)>,
    /// The records' responses.
    pub responses: Vec<responses::RecordedResponse>,
    pub problem: Problem,
    pub result: fit::FitResult,
    /// Where each parameter's bounds come from, in the order of the problem's parameters.
    pub bounds_sources: Vec<String>,
    /// The cost at the optimum over its degrees of freedom (targets less parameters): about 1
    /// when the targets' standard errors describe the misfit (NaN with no degrees of freedom).
    pub reduced_chi_square: f64,
    /// The model the targets were matched with, in words.
    pub model: String,
    /// The standard errors from the cost's curvature alone (`(J' J)^-1`); `result`'s are the
    /// the larger of these and the cluster-robust ones ([`responses::robust_standard_errors`]).
    pub curvature_standard_errors: Vec<f64>,
    /// The uncorrected aircraft's responses at every frequency of every response (and its
    /// neighbours), by condition: the targets' standard errors came from them, and they are the
    /// "before" of [`responses::compare`].
    pub uncorrected: Vec<(TargetCondition, crate::run::responses::Responses)>,
    /// What the matched processing did to the targets ([`matched`]); `None` where the fit
    /// before it did not converge, or where it could not be done or its fit did not converge
    /// (a warning says which).
    pub matched: Option<matched::Matched>,
}

/// The parameters, with their bounds: a correction's from the request or [`DEFAULT_BOUNDS`], a
/// physical parameter's within the aircraft file's plausible range.
pub fn parameters(
    file: &AircraftFile,
    requests: &[RetuneParameter],
) -> Result<Vec<(FitParameter, String)>, String> {
    requests
        .iter()
        .map(|r| {
            let kind = ParameterKind::parse(&r.name).ok_or_else(|| {
                format!(
                    "`{}` is not a correction or parameter (known: {})",
                    r.name,
                    ParameterKind::names().join(", ")
                )
            })?;
            let asked = "asked for on the command line (--bounds)".to_string();
            let ((lower, upper, start), source) = match kind {
                ParameterKind::Estimated(name) => (
                    crate::fit::file::estimated_parameter(
                        Some(file),
                        name,
                        (r.bounds.map(|b| b.0), r.bounds.map(|b| b.1), None),
                    )?,
                    match r.bounds {
                        Some(_) => asked,
                        None => file
                            .ranges
                            .get(name)
                            .map_or(String::new(), |x| x.source.clone()),
                    },
                ),
                _ => {
                    let default = DEFAULT_BOUNDS.iter().find(|d| d.0 == kind);
                    let (lo, hi) = r
                        .bounds
                        .unwrap_or_else(|| default.map_or((0.0, 0.0), |d| (d.1, d.2)));
                    // From the uncorrected model.
                    let start = kind.neutral().unwrap_or(0.5 * (lo + hi));
                    let source = match r.bounds {
                        Some(_) => asked,
                        None => default.map_or(String::new(), |d| d.3.to_string()),
                    };
                    ((lo, hi, start.clamp(lo, hi)), source)
                }
            };
            if !(lower.is_finite() && upper.is_finite() && lower < upper) {
                return Err(format!(
                    "`{}`: bounds [{lower}, {upper}] must be finite with lower < upper",
                    r.name
                ));
            }
            Ok((
                FitParameter {
                    kind,
                    lower,
                    upper,
                    start,
                    regularisation: 0.0,
                },
                source,
            ))
        })
        .collect()
}

/// Why a retune did not run: bad input (the records, the parameters asked for), or the model
/// failing where the records were flown (a trim that does not converge), which is no fault of
/// the input (`cierva retune` exits 1 for it, 2 for bad input).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RetuneError {
    #[error("{0}")]
    Input(String),
    #[error("the model where the records were flown: {0}")]
    Model(String),
}

impl From<String> for RetuneError {
    fn from(message: String) -> Self {
        Self::Input(message)
    }
}

impl From<&str> for RetuneError {
    fn from(message: &str) -> Self {
        Self::Input(message.to_string())
    }
}

/// Estimates the records' responses and fits the parameters of `retuned` (an aircraft file, or
/// a model behind the model interface) to them.
pub fn retune(
    retuned: subject::Retuned<'_>,
    records: &[Record],
    requests: &[RetuneParameter],
    how: &How,
) -> Result<Retune, RetuneError> {
    if records.is_empty() {
        return Err("no records to retune from".into());
    }
    let (parameters, bounds_sources): (Vec<FitParameter>, Vec<String>) =
        retuned.parameters(requests)?.into_iter().unzip();
    if parameters.is_empty() {
        return Err("name at least one correction or parameter to fit".into());
    }
    let conditions = responses::by_condition(records)?
        .into_iter()
        .map(|g| {
            (
                g.condition,
                g.records.iter().map(|r| r.meta.id.clone()).collect(),
            )
        })
        .collect();
    let estimated = responses::responses(records, &how.responses)?;
    let uncorrected = crate::inputs::corrections::CorrectionSet::default();
    let models = retuned
        .responses(&uncorrected, &estimated, true)
        .map_err(RetuneError::Model)?;
    let (estimated, left_out) = answerable(estimated, &models);
    if estimated.is_empty() {
        return Err(format!(
            "the model answers none of the records' responses: {}",
            left_out.join("; ")
        )
        .into());
    }
    let targets = responses::targets(&estimated, &models)?;
    if targets.is_empty() {
        return Err(format!(
            "no response of the records reaches a coherence of {} at any frequency: nothing to match (inconclusive: coherence)",
            crate::checks::frequency_response::COHERENCE_MIN
        )
        .into());
    }
    // Which model gave the responses, as they say (every condition's come from one model).
    let model = models
        .first()
        .map_or(String::new(), |(_, m)| m.model().to_string());
    let problem = Problem {
        subject: retuned.fit_subject(),
        parameters,
        targets,
        options: fit::FitOptions {
            tolerance: TOLERANCE,
            distance_to_minimum: Some(DISTANCE_TO_MINIMUM),
            difference_step: DIFFERENCE_STEP,
            max_iterations: MAX_ITERATIONS,
            ..fit::FitOptions::default()
        },
        executor: how.executor.clone(),
    };
    let mut problem = problem;
    let mut result = fit::fit(&problem);
    if result.status == fit::Status::Converged
        && estimated.iter().any(|r| !r.other_controls.is_empty())
    {
        result = refit_with_errors_at_fit(retuned, &estimated, &mut problem, result)?;
    }
    let (mut result, matched) =
        with_matched_processing(retuned, records, how, &mut problem, result);
    result.warnings.extend(left_out);
    let curvature_standard_errors = result.standard_errors.clone();
    if result.status == fit::Status::Converged {
        result.standard_errors = match fit::sensitivities(&problem, &result.values) {
            Ok((y, j)) => {
                responses::robust_standard_errors(&problem, &y, &j, &result.standard_errors)
            }
            Err(e) => {
                result.warnings.push(format!(
                    "the sensitivities at the optimum could not be evaluated again ({e}): no standard errors"
                ));
                vec![f64::INFINITY; problem.parameters.len()]
            }
        };
    }
    let dof = problem.targets.len() as f64 - problem.parameters.len() as f64;
    let reduced_chi_square = if dof > 0.0 {
        result.cost / dof
    } else {
        f64::NAN
    };
    Ok(Retune {
        conditions,
        responses: estimated,
        problem,
        result,
        bounds_sources,
        reduced_chi_square,
        model,
        curvature_standard_errors,
        uncorrected: models,
        matched,
    })
}

impl Retune {
    /// Each parameter's fitted value by its name.
    pub fn values_by_name(&self) -> serde_json::Map<String, serde_json::Value> {
        self.result
            .parameters
            .iter()
            .zip(&self.result.values)
            .map(|(k, v)| (k.name().to_string(), serde_json::json!(v)))
            .collect()
    }

    /// Each parameter's 95 % interval within its bounds ([`fit::interval`]: one-sided where the
    /// estimate ends on a bound), in the order of the problem's parameters.
    pub fn intervals(&self) -> Vec<Option<fit::Interval>> {
        self.problem
            .parameters
            .iter()
            .zip(&self.result.values)
            .zip(&self.result.standard_errors)
            .map(|((q, v), se)| {
                fit::interval(*v, *se, (q.lower, q.upper), self.problem.options.tolerance)
            })
            .collect()
    }

    /// [`Self::intervals`] by the parameters' names (null where the standard error is not
    /// finite).
    pub fn intervals_by_name(&self) -> serde_json::Map<String, serde_json::Value> {
        self.result
            .parameters
            .iter()
            .zip(self.intervals())
            .map(|(k, i)| (k.name().to_string(), serde_json::json!(i)))
            .collect()
    }

    /// Each parameter's standard error by its name (null where it is not finite: a parameter
    /// the records cannot tell apart from another).
    pub fn standard_errors_by_name(&self) -> serde_json::Map<String, serde_json::Value> {
        self.result
            .parameters
            .iter()
            .zip(&self.result.standard_errors)
            .map(|(k, s)| {
                (
                    k.name().to_string(),
                    serde_json::json!(s.is_finite().then_some(*s)),
                )
            })
            .collect()
    }
}

/// The corrections file a retune writes (`id`, for `cierva validate --corrections`): the fitted
/// corrections for what was retuned, the command and records they came from, and the fit's
/// bounds with their sources, status, standard errors and warnings.
pub fn corrections_file(
    r: &Retune,
    retuned: subject::Retuned<'_>,
    records: &[Record],
    id: &str,
    command: &str,
) -> CorrectionsFileSpec {
    let title = match retuned {
        subject::Retuned::Aircraft(file) => file.title.clone(),
        subject::Retuned::Model(e) => e.model.describe(),
    };
    CorrectionsFileSpec {
        id: id.to_string(),
        title: format!("Corrections of {title} retuned from flight records"),
        applies_to: (&retuned.corrects()).into(),
        corrections: r.result.corrections(),
        provenance: crate::inputs::reference::Provenance {
            source: format!(
                "retuned by `cierva {command}` (cierva {})",
                env!("CARGO_PKG_VERSION")
            ),
            notes: Some(format!(
                "Records: {}",
                records
                    .iter()
                    .map(|x| format!("{} ({})", x.meta.id, x.meta.provenance.source))
                    .collect::<Vec<_>>()
                    .join("; ")
            )),
        },
        fit: Some(serde_json::json!({
            "bounds": r
                .problem
                .parameters
                .iter()
                .zip(&r.bounds_sources)
                .map(|(p, source)| {
                    (
                        p.kind.name().to_string(),
                        serde_json::json!({"lower": p.lower, "upper": p.upper, "source": source}),
                    )
                })
                .collect::<serde_json::Map<String, serde_json::Value>>(),
            "status": r.result.status.name(),
            "stalled": r.result.stalled(),
            "detail": r.result.status.detail(),
            "model": r.model,
            "reduced_chi_square": r.reduced_chi_square.is_finite().then_some(r.reduced_chi_square),
            "iterations": r.result.iterations,
            "evaluations": r.result.evaluations,
            "standard_errors": r.standard_errors_by_name(),
            "intervals_95": r.intervals_by_name(),
            "targets": r.problem.targets.len(),
            "warnings": r.result.warnings,
        })),
        cross_validation: None,
        not_applied_to: vec![],
        domain: Some(crate::fit::file::domain_of(&r.problem.targets)),
        // Fitted to records' responses, not to any case's checks.
        calibrated_on: Default::default(),
        posterior: fit::posterior(&r.problem, &r.result),
    }
}

/// The records' responses the model can give (its responses name the input, the output and
/// every other control the record moved), and a sentence for each group it cannot: a model of
/// four longitudinal states has no rotorspeed response to compare with a record's.
fn answerable(
    estimated: Vec<responses::RecordedResponse>,
    models: &[(TargetCondition, crate::run::responses::Responses)],
) -> (Vec<responses::RecordedResponse>, Vec<String>) {
    let mut kept = Vec::new();
    let mut left_out: Vec<String> = Vec::new();
    for r in estimated {
        let Some((_, m)) = models.iter().find(|(c, _)| *c == r.condition) else {
            continue;
        };
        let missing = if !m.states.contains(&r.output) {
            Some(format!("state `{}`", r.output))
        } else {
            std::iter::once(&r.input)
                .chain(&r.other_controls)
                .find(|c| !m.controls.contains(c))
                .map(|c| format!("control `{c}`"))
        };
        match missing {
            None => kept.push(r),
            Some(what) => left_out.push(format!(
                "the records' {}/{} response at {} is left out: the model has no {what}",
                r.output,
                r.input,
                r.condition.label()
            )),
        }
    }
    (kept, left_out)
}

/// The matched processing's fit ([`matched::refit`]) after a converged `result`: its result
/// and what it did, or `result` with a warning (and `problem` as it was) where it cannot be
/// done or its fit does not converge.
fn with_matched_processing(
    retuned: subject::Retuned<'_>,
    records: &[Record],
    how: &How,
    problem: &mut Problem,
    mut result: fit::FitResult,
) -> (fit::FitResult, Option<matched::Matched>) {
    if result.status != fit::Status::Converged {
        return (result, None);
    }
    let before = problem.clone();
    match matched::refit(retuned, records, &how.responses, problem, &result) {
        Ok((again, m)) if again.status == fit::Status::Converged => (again, Some(m)),
        Ok((again, _)) => {
            *problem = before;
            result.warnings.push(format!(
                "the fit with the matched processing's targets ended {}: the fit before it is kept, against the records' estimates as they are, the estimator's bias in them",
                again.status.described()
            ));
            (result, None)
        }
        Err(e) => {
            result.warnings.push(format!(
                "the matched processing could not be done ({e}): the fit before it is kept, against the records' estimates as they are, the estimator's bias in them"
            ));
            (result, None)
        }
    }
}

/// The fit again with the targets' standard errors taken at the fitted corrections.
///
/// A response's standard error depends on the model's responses to the records' other
/// controls ([`responses::RecordedResponse::standard_error`]): the first fit takes them from the
/// uncorrected aircraft, which may be far from the corrections the records hold. The second
/// starts where the first ended, with the errors at its corrections. Its `before` and
/// `cost_start` stay the uncorrected aircraft's (the cost with the new errors); iterations and
/// evaluations are both fits'.
fn refit_with_errors_at_fit(
    retuned: subject::Retuned<'_>,
    estimated: &[responses::RecordedResponse],
    problem: &mut Problem,
    first: fit::FitResult,
) -> Result<fit::FitResult, String> {
    let models = retuned.responses(&first.corrections(), estimated, true)?;
    problem.targets = responses::targets(estimated, &models)?;
    Ok(again_from(problem, first))
}

/// `problem` fitted again, started where `first` ended: its `before` stays `first`'s and its
/// `cost_start` the cost there with `problem`'s targets; iterations and evaluations are both
/// fits'.
fn again_from(problem: &Problem, first: fit::FitResult) -> fit::FitResult {
    let mut again = problem.clone();
    for (p, v) in again.parameters.iter_mut().zip(&first.values) {
        p.start = *v;
    }
    let mut second = fit::fit(&again);
    second.cost_start = problem
        .targets
        .iter()
        .zip(&first.before)
        .map(|(t, y)| ((y - t.reference) / t.standard_error).powi(2))
        .sum();
    second.before = first.before;
    second.iterations += first.iterations;
    second.evaluations += first.evaluations;
    second
}

/// A check whose verdict the corrections changed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Changed {
    /// `case::check`.
    pub check: String,
    pub class: &'static str,
    pub passed_before: bool,
    pub passed_after: bool,
}

/// The validation suite's cases that the corrections apply to, run without and with them.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Revalidation {
    /// Cases the corrections apply to (the others are unchanged by construction).
    pub cases: Vec<String>,
    /// Per class: checks, passed before, passed after.
    pub classes: std::collections::BTreeMap<&'static str, [usize; 3]>,
    pub changed: Vec<Changed>,
    /// Scores (`case::score`) before and after.
    pub scores: Vec<(String, f64, f64)>,
}

/// Runs every case the corrections apply to without and with them, and says what changed.
pub fn revalidate(
    cases: &[crate::suite::case::Case],
    corrections: &crate::inputs::corrections::CorrectionsFile,
) -> Result<Revalidation, String> {
    use crate::suite::validation::{Options, validate};
    let files = std::slice::from_ref(corrections);
    let mut touched = Vec::new();
    for c in cases {
        let (_, used) = crate::suite::case::with_corrections(c, files)?;
        if !used.is_empty() {
            touched.push(c.clone());
        }
    }
    let before = validate(
        touched.iter().cloned().map(Ok).collect(),
        &Options::default(),
    );
    let after = validate(
        touched.into_iter().map(Ok).collect(),
        &Options {
            corrections: files,
            ..Default::default()
        },
    );
    let ran = before
        .cases
        .into_iter()
        .zip(after.cases)
        .map(|(b, a)| (b.case.id.clone(), b.results, a.results, b.scores, a.scores));
    let mut out = Revalidation::default();
    for (id, rb, ra, sb, sa) in ran {
        out.cases.push(id);
        for (b, a) in rb.iter().zip(&ra) {
            let class = b.class.name();
            let row = out.classes.entry(class).or_insert([0; 3]);
            row[0] += 1;
            row[1] += usize::from(b.passed);
            row[2] += usize::from(a.passed);
            if b.passed != a.passed {
                out.changed.push(Changed {
                    check: format!("{}::{}", b.case, b.check),
                    class,
                    passed_before: b.passed,
                    passed_after: a.passed,
                });
            }
        }
        for (b, a) in sb.iter().zip(&sa) {
            out.scores
                .push((format!("{}::{}", b.case, b.id), b.value, a.value));
        }
    }
    Ok(out)
}

/// A mode's eigenvalue before and after, at a condition.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeRow {
    pub condition: String,
    pub mode: String,
    /// Real and imaginary parts, 1/s.
    pub before: [f64; 2],
    pub after: [f64; 2],
}

/// Each condition's modes (the first of each kind) before and after: `retuned` with the
/// values of `before` and `after` (an empty set: as it is).
pub fn modes(
    retuned: subject::Retuned<'_>,
    [before, after]: [&CorrectionSet; 2],
    conditions: &[(TargetCondition, Vec<String>)],
) -> Vec<ModeRow> {
    use cierva_model::analysis::modes;
    let mut out = Vec::new();
    for (c, _) in conditions {
        let TargetCondition::Flight(request, loading) = *c else {
            continue;
        };
        let analyse = |values: &CorrectionSet| {
            retuned
                .linear_model(values, request, loading)
                .ok()
                .and_then(|lin| modes::modes(&lin).ok())
        };
        let (Some(mb), Some(ma)) = (analyse(before), analyse(after)) else {
            continue;
        };
        let mut seen = Vec::new();
        for m in &mb.modes {
            if seen.contains(&m.kind) || m.eigenvalue.im < 0.0 {
                continue;
            }
            seen.push(m.kind);
            if let Some(n) = ma
                .modes
                .iter()
                .find(|n| n.kind == m.kind && n.eigenvalue.im >= 0.0)
            {
                out.push(ModeRow {
                    condition: c.label(),
                    mode: m.kind.name().to_string(),
                    before: [m.eigenvalue.re, m.eigenvalue.im],
                    after: [n.eigenvalue.re, n.eigenvalue.im],
                });
            }
        }
    }
    out
}

/// How well the model before and after predicts one signal of a record not used in the fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    pub record: String,
    pub signal: String,
    pub theil_before: f64,
    pub theil_after: f64,
    pub rms_error_before: f64,
    pub rms_error_after: f64,
}

/// Flies a record's measured controls (changes from its trim) through the model linearised at
/// its condition, with the values of `before` and `after`, and compares the states with the
/// record's (seed 000 Fig. 10; Theil's inequality coefficient, 0 a perfect match).
pub fn predict(
    retuned: subject::Retuned<'_>,
    [before, after]: [&CorrectionSet; 2],
    record: &Record,
) -> Result<Vec<Prediction>, String> {
    let (request, loading) = ident::record_condition(record)?;
    let config = ident::ConfigSpec::for_setup(ident::setup_for(&[record]), record)?;
    let fly = |values: &CorrectionSet| -> Result<Vec<ident::SignalComparison>, String> {
        let lin = retuned.linear_model(values, request, loading)?;
        let model = ident::model_for(&lin, &config)?;
        ident::predict(&model, record, &config)
    };
    let (b, a) = (fly(before)?, fly(after)?);
    Ok(b.iter()
        .zip(&a)
        .map(|(b, a)| Prediction {
            record: record.meta.id.clone(),
            signal: b.signal.clone(),
            theil_before: b.theil,
            theil_after: a.theil,
            rms_error_before: b.rms_error,
            rms_error_after: a.rms_error,
        })
        .collect())
}
