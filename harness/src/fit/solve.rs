//! The fit's sequential linearisation (`fit`): the problem and its options, the residuals and
//! cost, the trust-region loop with Broyden updates between finite-difference Jacobians, and
//! the result with its standard errors and warnings.

use super::qp::qp_step;
use super::targets::{ConditionStarts, HARD_SLACK, check, evaluate_from, jacobian};
use super::{Enforce, FitParameter, FitSubject, ParameterKind, Target};
use crate::inputs::corrections::CorrectionSet;
use serde::Serialize;

/// Iteration limits and tolerances.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FitOptions {
    pub max_iterations: usize,
    /// Converged when the step is below this fraction of every parameter's range, or the cost
    /// falls by less than this fraction.
    pub tolerance: f64,
    /// Forward-difference step as a fraction of each parameter's range.
    pub difference_step: f64,
    /// Initial trust region as a fraction of each parameter's range.
    pub trust_region: f64,
    /// Converged also when, on a finite-difference Jacobian, the step to the linearisation's
    /// minimum (within the parameters' bounds and the initial trust region, [`Self::trust_region`])
    /// is predicted to lower the cost by at most this much: MINUIT's estimated distance to the
    /// minimum, EDM (James 1994). Only for a cost in chi-square units (every target weighted by
    /// its standard error, the cost not halved), where that fall is the squared Mahalanobis
    /// distance to the linearisation's minimum: every parameter, and every linear combination,
    /// is then within `sqrt(d)` of its own standard error of it; `None` for a cost in other
    /// units. It ends a fit whose model evaluations carry numerical noise (a trim, a harmonic
    /// balance) that keeps every step above [`FitOptions::tolerance`] without lowering the cost.
    /// A step that lowers the cost by at most this much, even one the trust region held back,
    /// sends the fit to a fresh Jacobian, where this check decides.
    pub distance_to_minimum: Option<f64>,
    /// Update the Jacobian by Broyden's rank-one formula between finite-difference refreshes
    /// (`true`), or difference it afresh every iteration (`false`). Convergence is judged,
    /// and standard errors computed, on a fresh one either way.
    pub broyden: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            max_iterations: 20,
            tolerance: 1e-6,
            difference_step: 1e-3,
            trust_region: 0.5,
            distance_to_minimum: None,
            broyden: true,
        }
    }
}

/// How a fit ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "status", content = "detail")]
pub enum Status {
    Converged,
    IterationLimit,
    /// The bounds (parameter or target) admit no solution.
    Infeasible(String),
    /// The model could not be evaluated (a condition that will not trim, ...).
    ModelFailure(String),
    /// The problem as given is malformed.
    BadProblem(String),
}

impl Status {
    /// The status's name as written.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Converged => "converged",
            Self::IterationLimit => "iteration_limit",
            Self::Infeasible(_) => "infeasible",
            Self::ModelFailure(_) => "model_failure",
            Self::BadProblem(_) => "bad_problem",
        }
    }

    /// Why it ended so, where a failure says (empty for a converged fit or the iteration
    /// limit).
    pub fn detail(&self) -> &str {
        match self {
            Self::Infeasible(m) | Self::ModelFailure(m) | Self::BadProblem(m) => m,
            Self::Converged | Self::IterationLimit => "",
        }
    }

    /// The name, and the detail after a colon where there is one.
    pub fn described(&self) -> String {
        match self.detail() {
            "" => self.name().to_string(),
            d => format!("{}: {d}", self.name()),
        }
    }
}

/// What a fit that [stalled](FitResult::stalled) means, wherever its status is written.
pub const STALLED_MEANS: &str = "stopped at the edge of the model's equilibria (every trial step \
     lost one): the end may be where the fit's path met that edge, not the cost's minimum";

/// A fit's outcome.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitResult {
    pub status: Status,
    pub parameters: Vec<ParameterKind>,
    pub values: Vec<f64>,
    /// Approximate standard errors (infinite for a parameter the targets do not see).
    pub standard_errors: Vec<f64>,
    pub iterations: usize,
    /// Model evaluations (each a trim, linearisation or autorotation at every condition).
    pub evaluations: usize,
    pub cost_start: f64,
    pub cost: f64,
    /// Every target's model value at the start and at the end (NaN where not evaluated).
    pub before: Vec<f64>,
    pub after: Vec<f64>,
    /// Remarks: parameters with no effect, active bounds.
    pub warnings: Vec<String>,
    /// The targets' information about the parameters at the end, `J' W J` of the
    /// finite-difference Jacobian weighted by the targets' standard errors
    /// (`[parameter][parameter]`; empty where none was computed): what the fit's posterior
    /// ([`posterior`]) is made of.
    #[serde(skip)]
    pub information: Vec<Vec<f64>>,
    /// The trial steps lost where the fit stopped because every step its trust region allowed
    /// left the model without an equilibrium at some target (its warning says so too); `None`
    /// for any other end.
    #[serde(skip)]
    pub stall: Option<usize>,
}

impl FitResult {
    /// The fitted values as a correction set.
    pub fn corrections(&self) -> CorrectionSet {
        let mut c = CorrectionSet::default();
        for (k, v) in self.parameters.iter().zip(&self.values) {
            k.set(&mut c, *v);
        }
        c
    }

    /// Whether the fit stopped because every trial step its trust region allowed left the model
    /// without an equilibrium at some target ([`FitResult::stall`]): its end is where its path
    /// met the edge of the model's equilibria, which need not be the cost's minimum.
    pub fn stalled(&self) -> bool {
        self.stall.is_some()
    }

    /// The status in words ([`Status::described`]), and for a fit that [stalled](Self::stalled),
    /// that it did: a status of converged alone would read as the cost's minimum.
    pub fn status_described(&self) -> String {
        format!("{}{}", self.status.described(), self.stalled_described())
    }

    /// `, but stopped at the edge ...` for a fit that [stalled](Self::stalled), else nothing:
    /// what follows its status wherever the status is written.
    pub fn stalled_described(&self) -> String {
        if self.stalled() {
            format!(", but {STALLED_MEANS}")
        } else {
            String::new()
        }
    }
}

/// The fit problem.
#[derive(Debug, Clone)]
pub struct Problem {
    pub subject: FitSubject,
    pub parameters: Vec<FitParameter>,
    pub targets: Vec<Target>,
    pub options: FitOptions,
    /// Where its evaluations run: this machine's threads (the default), or an engine through
    /// a plan a batch (`cierva fit --evaluate-with`).
    pub executor: Executor,
}

/// Runs a batch of a fit's evaluations somewhere else than this process: each parameter
/// vector of `points`, every target of `problem` at it, as [`crate::fit::evaluate_each`] gives
/// them (the outer error where the corrections themselves are invalid). The plan module
/// implements it ([`crate::plan::fit`]); the fit module knows only this.
pub trait BatchEvaluator: Send + Sync {
    /// Each point's trims start from `from` (the fit's iterate's answers); each evaluation
    /// says where its own ended.
    fn evaluate_batch(
        &self,
        problem: &Problem,
        points: &[Vec<f64>],
        from: &ConditionStarts,
    ) -> Vec<Result<super::targets::PointEvaluation, String>>;
    /// In words, for the report and errors ("plans in runs/ run by `...`").
    fn describe(&self) -> String;
}

/// Where a fit's evaluations run.
#[derive(Clone, Default)]
pub enum Executor {
    /// On this machine's threads, conditions in parallel.
    #[default]
    Local,
    /// A batch at a time (the targets at a point, or a Jacobian's steps together) through a
    /// [`BatchEvaluator`].
    Batches(std::sync::Arc<dyn BatchEvaluator>),
}

impl std::fmt::Debug for Executor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Executor::Local => write!(f, "Local"),
            Executor::Batches(b) => write!(f, "Batches({})", b.describe()),
        }
    }
}

impl Problem {
    /// The parameters' values `p` by the names the subject declares them behind the model
    /// interface ([`ParameterKind::model_name`]): what each request to it carries.
    pub fn declared_values(&self, p: &[f64]) -> crate::external::Values {
        self.parameters
            .iter()
            .zip(p)
            .map(|(q, v)| (q.kind.model_name(), *v))
            .collect()
    }
}

/// Residuals: scaled target misfits, bound violations (penalised), then the regularisation
/// rows.
fn residuals(problem: &Problem, p: &[f64], y: &[f64]) -> Vec<f64> {
    let mut r: Vec<f64> = problem
        .targets
        .iter()
        .zip(y)
        .map(|(t, v)| (v - t.reference) / t.standard_error)
        .collect();
    for (t, v) in problem.targets.iter().zip(y) {
        if let Some((b, w)) = t.penalty() {
            r.push(w.sqrt() * b.violation(*v) / t.standard_error);
        }
    }
    for (par, v) in problem.parameters.iter().zip(p) {
        if par.regularisation > 0.0 {
            r.push(par.regularisation.sqrt() * (v - par.start) / (par.upper - par.lower));
        }
    }
    r
}

fn cost(r: &[f64]) -> f64 {
    let c: f64 = r.iter().map(|v| v * v).sum();
    if c.is_finite() { c } else { f64::INFINITY }
}

/// Broyden's rank-one update of the Jacobian from an accepted step `p -> q` (`y -> yq`):
/// `J += (dy - J dp) dp' / (dp' dp)`.
fn broyden_update(jt: &mut [Vec<f64>], p: &[f64], q: &[f64], y: &[f64], yq: &[f64]) {
    let dp: Vec<f64> = q.iter().zip(p).map(|(a, b)| a - b).collect();
    let norm: f64 = dp.iter().map(|v| v * v).sum();
    if norm <= 0.0 {
        return;
    }
    for (k, row) in jt.iter_mut().enumerate() {
        let predicted: f64 = row.iter().zip(&dp).map(|(a, b)| a * b).sum();
        let miss = (yq[k] - y[k]) - predicted;
        for (j, d) in row.iter_mut().zip(&dp) {
            *j += miss * d / norm;
        }
    }
}

/// The targets' information `J' W J` about the parameters: the Jacobian `jt`
/// (`[target][parameter]`) weighted by each target's standard error.
fn information(problem: &Problem, jt: &[Vec<f64>]) -> nalgebra::DMatrix<f64> {
    let n = problem.parameters.len();
    let mut m = nalgebra::DMatrix::<f64>::zeros(n, n);
    for (t, row) in problem.targets.iter().zip(jt) {
        for a in 0..n {
            for b in 0..n {
                m[(a, b)] += row[a] * row[b] / (t.standard_error * t.standard_error);
            }
        }
    }
    m
}

/// Standard errors from `(J' J)^-1` of the scaled residual Jacobian (targets only), given as
/// the targets' information `m` ([`information`]).
fn standard_errors(problem: &Problem, m: &nalgebra::DMatrix<f64>) -> (Vec<f64>, Vec<String>) {
    let n = problem.parameters.len();
    let mut warnings = Vec::new();
    let mut se = vec![f64::INFINITY; n];
    // Blind: moving the parameter across its whole range moves the targets by less than a
    // millionth of their standard errors.
    let blind: Vec<usize> = (0..n)
        .filter(|&i| {
            let range = problem.parameters[i].upper - problem.parameters[i].lower;
            m[(i, i)].max(0.0).sqrt() * range < 1e-6
        })
        .collect();
    for &i in &blind {
        warnings.push(format!(
            "parameter `{}` has no effect on the fitted targets: it keeps its start and its standard error is infinite",
            problem.parameters[i].kind.name()
        ));
    }
    let seen: Vec<usize> = (0..n).filter(|i| !blind.contains(i)).collect();
    let sub = nalgebra::DMatrix::from_fn(seen.len(), seen.len(), |a, b| m[(seen[a], seen[b])]);
    // Identifiable only where J'J is well conditioned: as many independent directions as
    // parameters seen. More parameters than targets, or two that act alike, leave it singular
    // (in floating point, an inverse of garbage).
    let (lo, hi) = if seen.is_empty() {
        (1.0, 1.0)
    } else if !sub.iter().all(|v| v.is_finite()) {
        (f64::NAN, f64::NAN)
    } else {
        let singular = sub.clone().singular_values();
        (singular.min(), singular.max())
    };
    let conditioned = lo.is_finite() && hi > 0.0 && lo > 1e-12 * hi;
    match sub.clone().try_inverse() {
        Some(inv)
            if conditioned
                && inv.iter().all(|v| v.is_finite())
                && (0..seen.len()).all(|a| inv[(a, a)] > 0.0) =>
        {
            for (a, &i) in seen.iter().enumerate() {
                se[i] = inv[(a, a)].sqrt();
            }
        }
        _ => warnings.push(format!(
            "the fitted parameters are not separately identifiable from these targets (J'J is singular: {} parameters seen by {} targets, condition {:.1e}): standard errors are infinite",
            seen.len(),
            problem.targets.len(),
            hi / lo
        )),
    }
    (se, warnings)
}

/// The scatter of a fit's targets about the fitted model against their stated standard
/// errors, and the factor its standard errors were scaled by ([`scale_by_birge`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Birge {
    /// `sum ((y - reference) / standard_error)^2` over the targets the fitted model solves.
    pub chi_square: f64,
    /// Those targets less the parameters the fit identifies (a finite standard error).
    pub degrees_of_freedom: usize,
    /// `sqrt(chi^2 / nu)` where that exceeds 1 (the standard errors were multiplied by it),
    /// else 1.
    pub factor: f64,
}

/// Scales a fit's standard errors by Birge's ratio `sqrt(chi^2 / nu)` where it exceeds 1:
/// targets that scatter about the fitted model by more than their standard errors say carry
/// more error than stated (the model's own form, a systematic part of the data), and the
/// parameters' standard errors from `(J'J)^-1` alone are too small by that factor (Birge 1932;
/// the Particle Data Group's scale factor for inconsistent measurements; REFERENCES.md). Where the
/// scatter is within the stated errors the standard errors are kept: a fit does not shrink
/// them on a lucky draw. `None` where no degree of freedom is left (as many identified
/// parameters as solved targets, or none identified).
pub fn scale_by_birge(problem: &Problem, result: &mut FitResult) -> Option<Birge> {
    let solved: Vec<f64> = problem
        .targets
        .iter()
        .zip(&result.after)
        .filter(|(_, y)| y.is_finite())
        .map(|(t, y)| (y - t.reference) / t.standard_error)
        .collect();
    let identified = result
        .standard_errors
        .iter()
        .filter(|s| s.is_finite())
        .count();
    if identified == 0 || solved.len() <= identified {
        return None;
    }
    let chi_square: f64 = solved.iter().map(|r| r * r).sum();
    let degrees_of_freedom = solved.len() - identified;
    let ratio = chi_square / degrees_of_freedom as f64;
    let factor = if ratio > 1.0 { ratio.sqrt() } else { 1.0 };
    if factor > 1.0 {
        for s in result.standard_errors.iter_mut().filter(|s| s.is_finite()) {
            *s *= factor;
        }
        result.warnings.push(format!(
            "the targets scatter about the fitted model by chi^2/nu = {chi_square:.1}/{degrees_of_freedom} = {ratio:.2}, more than their standard errors say: the standard errors are scaled by sqrt(chi^2/nu) = {factor:.2} (Birge)"
        ));
    }
    Some(Birge {
        chi_square,
        degrees_of_freedom,
        factor,
    })
}

/// What [`posterior`] says of how it was made.
pub const POSTERIOR_METHOD: &str = "Laplace approximation about the fitted values: the targets' information J'WJ there, rescaled so that each identified parameter's variance is its stated standard error squared (Birge's factor, or retune's cluster-robust errors, with the curvature's correlations kept), plus each parameter's bounds as a normal of a uniform's variance (width^2/12); drawn values outside the bounds are reflected into them";

/// The fitted parameters' joint distribution ([`crate::inputs::corrections::Posterior`]): a
/// normal about the fitted values, of covariance `(K^-1 J'WJ K^-1 + P)^-1`, where `J'WJ` is
/// the targets' information at the end, `K` rescales each parameter whose standard error is
/// finite to the stated one (`result.standard_errors`, after Birge's factor or a retune's
/// cluster-robust errors; the curvature's correlations are kept) and `P` holds each
/// parameter's bounds as a normal of a uniform's variance, `12 / width^2`: where the targets
/// do not see a direction (more parameters than targets), the bounds set its spread. `None`
/// for a fit that did not converge or has no information.
pub fn posterior(
    problem: &Problem,
    result: &FitResult,
) -> Option<crate::inputs::corrections::Posterior> {
    use crate::inputs::corrections::{Posterior, PosteriorParameter};
    let n = problem.parameters.len();
    if result.status != Status::Converged || result.information.len() != n || n == 0 {
        return None;
    }
    let info = nalgebra::DMatrix::from_fn(n, n, |a, b| result.information[a][b]);
    if !info.iter().all(|v| v.is_finite()) {
        return None;
    }
    // Each identified parameter's curvature standard error (as the fit found its own, the
    // parameters the targets do not see left out), against its stated one.
    let (curvature, _) = standard_errors(problem, &info);
    let scale: Vec<f64> = (0..n)
        .map(|i| {
            let (stated, own) = (result.standard_errors[i], curvature[i]);
            if stated.is_finite() && own.is_finite() && own > 0.0 {
                stated / own
            } else {
                1.0
            }
        })
        .collect();
    let mut precision =
        nalgebra::DMatrix::from_fn(n, n, |a, b| info[(a, b)] / (scale[a] * scale[b]));
    for (i, q) in problem.parameters.iter().enumerate() {
        precision[(i, i)] += 12.0 / (q.upper - q.lower).powi(2);
    }
    let covariance = precision.try_inverse()?;
    // Symmetric to the bit, as a file states it.
    let covariance: Vec<Vec<f64>> = (0..n)
        .map(|a| {
            (0..n)
                .map(|b| 0.5 * (covariance[(a, b)] + covariance[(b, a)]))
                .collect()
        })
        .collect();
    let posterior = Posterior {
        method: POSTERIOR_METHOD.into(),
        parameters: problem
            .parameters
            .iter()
            .zip(&result.values)
            .map(|(q, v)| PosteriorParameter {
                name: q.kind.model_name(),
                value: *v,
                lower: q.lower,
                upper: q.upper,
            })
            .collect(),
        covariance,
    };
    posterior.problem().is_none().then_some(posterior)
}

/// Whether a step reaches its trust region's edge in any parameter.
fn limited_by(step: &[f64], radius: &[f64]) -> bool {
    step.iter().zip(radius).any(|(d, r)| d.abs() >= 0.99 * r)
}

/// Where the fit stands: the parameters `p`, the targets' values `y` and residuals `r` there,
/// the cost `c`, the Jacobian `jt`, the trust region and the model evaluations so far.
struct Iterate {
    p: Vec<f64>,
    y: Vec<f64>,
    r: Vec<f64>,
    c: f64,
    jt: Vec<Vec<f64>>,
    /// Whether `jt` is a finite-difference Jacobian at `p` (else a Broyden update of one).
    fresh: bool,
    radius: Vec<f64>,
    evaluations: usize,
    /// Where the model's answers at `p` ended: where the trial steps' and finite differences'
    /// start.
    starts: ConditionStarts,
}

impl Iterate {
    /// A finite-difference Jacobian at `p` (its evaluations counted).
    fn refresh(&mut self, problem: &Problem) -> Result<Vec<Vec<f64>>, String> {
        self.evaluations += self.p.len();
        jacobian(problem, &self.p, &self.y, &self.starts)
    }
}

/// How one iteration's trial steps ended.
struct Trials {
    /// A step lowered the cost and was taken.
    accepted: bool,
    /// The step (or the cost's fall) was below the tolerance.
    small: bool,
    /// A step on an updated Jacobian did not lower the cost.
    stale: bool,
    /// Trial steps the model could and could not evaluate.
    evaluated: usize,
    lost: usize,
    /// The status the step's quadratic program ended the iteration with, if it failed.
    failed: Option<Status>,
}

/// A fit that ends before its first iteration: the start, no standard errors.
fn unstarted(problem: &Problem, status: Status) -> FitResult {
    let start: Vec<f64> = problem.parameters.iter().map(|p| p.start).collect();
    FitResult {
        status,
        parameters: problem.parameters.iter().map(|p| p.kind.clone()).collect(),
        values: start.clone(),
        standard_errors: vec![f64::INFINITY; start.len()],
        iterations: 0,
        evaluations: 0,
        cost_start: f64::NAN,
        cost: f64::NAN,
        before: vec![f64::NAN; problem.targets.len()],
        after: vec![f64::NAN; problem.targets.len()],
        warnings: vec![],
        information: Vec::new(),
        stall: None,
    }
}

/// One iteration's inner loop: shrink the trust region until a step lowers the cost, and take
/// it. With an updated (not fresh) Jacobian, a failed or tiny step first refreshes the
/// Jacobian instead.
fn trial_steps(problem: &Problem, at: &mut Iterate, initial_radius: &[f64]) -> Trials {
    let mut accepted = false;
    let mut small = false;
    let mut stale = false;
    let mut reopened = false;
    let (mut evaluated, mut lost) = (0usize, 0usize);
    let mut failed = None;
    if at.fresh && near_minimum(problem, at, initial_radius) {
        return Trials {
            accepted,
            small: true,
            stale,
            evaluated,
            lost,
            failed,
        };
    }
    for _ in 0..8 {
        let d = match qp_step(problem, &at.p, &at.y, &at.r, &at.jt, &at.radius) {
            Ok(d) => d,
            Err(s) => {
                failed = Some(s);
                break;
            }
        };
        small = problem
            .parameters
            .iter()
            .zip(&d)
            .all(|(q, di)| di.abs() <= problem.options.tolerance * (q.upper - q.lower));
        // A step held small by a trust region that earlier failures shrank says nothing
        // of convergence: on a fresh Jacobian, the region opens again (once an
        // iteration) and the step is taken as the linearisation wants it.
        if small && at.fresh && !reopened && limited_by(&d, &at.radius) {
            at.radius = initial_radius.to_vec();
            reopened = true;
            small = false;
            continue;
        }
        if small {
            break;
        }
        let trial: Vec<f64> =
            at.p.iter()
                .zip(&d)
                .zip(&problem.parameters)
                .map(|((v, di), q)| (v + di).clamp(q.lower, q.upper))
                .collect();
        let predicted = predicted_cost(problem, at, &d);
        at.evaluations += 1;
        match evaluate_from(problem, &trial, &at.starts) {
            Ok((yt, st)) => {
                evaluated += 1;
                let rt = residuals(problem, &trial, &yt);
                let ct = cost(&rt);
                let c = at.c;
                let ratio = (c - ct) / (c - predicted).max(f64::MIN_POSITIVE);
                if ct < c {
                    let at_edge = limited_by(&d, &at.radius);
                    if ratio > 0.75 && at_edge {
                        at.radius.iter_mut().for_each(|v| *v *= 2.0);
                    } else if ratio < 0.25 {
                        at.radius.iter_mut().for_each(|v| *v *= 0.5);
                    }
                    let drop = (c - ct) / c.max(f64::MIN_POSITIVE);
                    if problem.options.broyden {
                        broyden_update(&mut at.jt, &at.p, &trial, &at.y, &yt);
                    }
                    at.fresh = false;
                    (at.p, at.y, at.r, at.c, at.starts) = (trial, yt, rt, ct, st);
                    accepted = true;
                    // (A small drop from a step the region held back is not convergence; on a
                    // chi-square cost a drop below `distance_to_minimum` has the fit judged
                    // again on a fresh Jacobian, where `near_minimum` decides.)
                    let below_noise = problem
                        .options
                        .distance_to_minimum
                        .is_some_and(|edm| c - ct <= edm);
                    if (drop <= problem.options.tolerance && !at_edge) || below_noise {
                        small = true;
                    }
                    break;
                }
                if !at.fresh {
                    stale = true;
                    break;
                }
                at.radius.iter_mut().for_each(|v| *v *= 0.25);
            }
            // A trial the model cannot trim: a smaller step.
            Err(_) => {
                lost += 1;
                at.radius.iter_mut().for_each(|v| *v *= 0.25);
            }
        }
    }
    Trials {
        accepted,
        small,
        stale,
        evaluated,
        lost,
        failed,
    }
}

/// Whether the linearisation's minimum within the bounds (the trust region opened to its
/// initial size) is predicted to lower the cost by at most [`FitOptions::distance_to_minimum`].
fn near_minimum(problem: &Problem, at: &Iterate, initial_radius: &[f64]) -> bool {
    let Some(edm) = problem.options.distance_to_minimum else {
        return false;
    };
    qp_step(problem, &at.p, &at.y, &at.r, &at.jt, initial_radius).is_ok_and(|d| {
        let fall = at.c - predicted_cost(problem, at, &d);
        fall <= edm
    })
}

/// The cost the linearisation predicts for the step `d` (unclamped).
fn predicted_cost(problem: &Problem, at: &Iterate, d: &[f64]) -> f64 {
    let stepped: Vec<f64> = at.p.iter().zip(d).map(|(v, di)| v + di).collect();
    let linear: Vec<f64> =
        at.y.iter()
            .zip(&at.jt)
            .map(|(v, row)| v + row.iter().zip(d).map(|(a, b)| a * b).sum::<f64>())
            .collect();
    cost(&residuals(problem, &stepped, &linear))
}

/// Fits the parameters. Never panics on a problem: a malformed problem, a model that will not
/// trim or an infeasible set of bounds each end with their status.
pub fn fit(problem: &Problem) -> FitResult {
    if let Err(e) = check(problem) {
        return unstarted(problem, Status::BadProblem(e));
    }
    let kinds: Vec<ParameterKind> = problem.parameters.iter().map(|p| p.kind.clone()).collect();
    let start: Vec<f64> = problem.parameters.iter().map(|p| p.start).collect();
    let (y0, starts) = match evaluate_from(problem, &start, &ConditionStarts::default()) {
        Ok(y) => y,
        Err(e) => return unstarted(problem, Status::ModelFailure(e)),
    };
    let r = residuals(problem, &start, &y0);
    let c0 = cost(&r);
    let initial_radius: Vec<f64> = problem
        .parameters
        .iter()
        .map(|q| problem.options.trust_region * (q.upper - q.lower))
        .collect();
    let mut at = Iterate {
        p: start,
        y: y0.clone(),
        r,
        c: c0,
        jt: Vec::new(),
        fresh: false,
        radius: initial_radius.clone(),
        evaluations: 1,
        starts,
    };
    let mut status = Status::IterationLimit;
    let mut iterations = 0;
    // Set when a step's outcome must be judged on a finite-difference Jacobian.
    let mut want_fresh = false;
    // Trial steps lost at the end: the fit stopped because every step the trust region
    // allowed left the model without an equilibrium, not because none lowered the cost.
    let mut stalled: Option<usize> = None;
    for it in 0..problem.options.max_iterations {
        iterations = it + 1;
        if !at.fresh && (at.jt.is_empty() || want_fresh || !problem.options.broyden) {
            at.jt = match at.refresh(problem) {
                Ok(j) => j,
                Err(e) => {
                    status = Status::ModelFailure(e);
                    break;
                }
            };
            at.fresh = true;
        }
        let t = trial_steps(problem, &mut at, &initial_radius);
        if let Some(s) = t.failed {
            status = s;
        }
        if matches!(status, Status::Infeasible(_) | Status::ModelFailure(_)) {
            break;
        }
        if at.fresh && (t.small || !t.accepted) {
            status = Status::Converged;
            if !t.accepted && t.evaluated == 0 && t.lost > 0 {
                stalled = Some(t.lost);
            }
            break;
        }
        // A failed or tiny step on an updated Jacobian: judge it again on a fresh one.
        want_fresh = !at.fresh && (t.stale || t.small || !t.accepted);
    }
    // Standard errors from a finite-difference Jacobian at the solution.
    if !at.fresh
        && !at.jt.is_empty()
        && !matches!(status, Status::ModelFailure(_))
        && let Ok(j) = at.refresh(problem)
    {
        at.jt = j;
    }
    let (se, mut warnings, information) = if at.jt.is_empty() {
        (vec![f64::INFINITY; at.p.len()], vec![], Vec::new())
    } else {
        let m = information(problem, &at.jt);
        let (se, warnings) = standard_errors(problem, &m);
        let rows = m.row_iter().map(|r| r.iter().copied().collect()).collect();
        (se, warnings, rows)
    };
    if !matches!(status, Status::ModelFailure(_) | Status::BadProblem(_))
        && let Some(s) = hard_bounds_left_violated(problem, &at.y)
    {
        status = s;
    }
    end_warnings(problem, &at.p, stalled, &mut warnings);
    FitResult {
        status,
        parameters: kinds,
        values: at.p,
        standard_errors: se,
        iterations,
        evaluations: at.evaluations,
        cost_start: c0,
        cost: at.c,
        before: y0,
        after: at.y,
        warnings,
        information,
        stall: stalled,
    }
}

/// The normal quantile of a two-sided 95 % interval.
pub const INTERVAL_Z: f64 = 1.96;

/// A fitted parameter's 95 % interval within its bounds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Interval {
    pub lower: f64,
    pub upper: f64,
    /// The estimate ends on a bound, so the interval reaches from that bound into the range
    /// only.
    pub one_sided: bool,
}

impl Interval {
    /// `[lower, upper]` to four significant figures, and `, one-sided: on its bound` where it is.
    pub fn described(&self) -> String {
        let g = crate::units::sig;
        format!(
            "[{}, {}]{}",
            g(self.lower, 4),
            g(self.upper, 4),
            if self.one_sided {
                ", one-sided: on its bound"
            } else {
                ""
            }
        )
    }
}

/// The 95 % interval of an estimate `value` with standard error `se` fitted within
/// `[lower, upper]`: `value -+ 1.96 se` cut at the bounds, one-sided where the estimate ends on
/// a bound (within the fit's step tolerance `tolerance`, a fraction of the range: a fit stops
/// that close to a bound it is pressing on). None where the standard error is not finite.
///
/// An estimate on a bound is the free estimate held there: the free one lies beyond it. With
/// the estimate on its upper bound `b`, `[b - 1.96 se, b]` misses a truth inside the bounds only
/// where the truth is below `b - 1.96 se`, and then the free estimate's error exceeds `1.96 se`
/// upwards (probability at most 2.5 %). The interval always contains the free interval cut at
/// the bounds, so for one parameter on one bound, the others free and the model locally
/// linear, it holds a truth within the bounds at least 95 % of the time. It is not shown for
/// several active bounds (a correlated parameter's bound can hold this one on its own bound
/// with its free estimate inside), and the standard error is the slope's at the bound, which
/// a nonlinear model may not keep beyond it.
pub fn interval(
    value: f64,
    se: f64,
    (lower, upper): (f64, f64),
    tolerance: f64,
) -> Option<Interval> {
    if !(se.is_finite() && value.is_finite()) {
        return None;
    }
    Some(Interval {
        lower: (value - INTERVAL_Z * se).max(lower),
        upper: (value + INTERVAL_Z * se).min(upper),
        one_sided: on_bound(value, (lower, upper), tolerance),
    })
}

/// Whether `v` ends on one of the bounds `[lower, upper]`, within `tolerance` of the range (and
/// at least 1e-9 of it).
fn on_bound(v: f64, (lower, upper): (f64, f64), tolerance: f64) -> bool {
    let tol = tolerance.max(1e-9) * (upper - lower);
    (v - lower).abs() <= tol || (v - upper).abs() <= tol
}

/// A hard bound left violated at the end: the bounds contradict each other or the model cannot
/// reach them, and the fit is infeasible.
fn hard_bounds_left_violated(problem: &Problem, y: &[f64]) -> Option<Status> {
    let violated: Vec<String> = problem
        .targets
        .iter()
        .zip(y)
        .filter_map(|(t, v)| {
            let b = t.bounds.filter(|b| b.enforce == Enforce::Hard)?;
            let by = b.violation(*v) / t.standard_error;
            (by.abs() > HARD_SLACK || by.is_nan()).then(|| {
                format!(
                    "`{}` at {} ends at {v:.6}, outside its hard bounds [{}, {}] by {:.3} standard errors",
                    t.measure.name(),
                    t.condition.label(),
                    b.lower,
                    b.upper,
                    by.abs()
                )
            })
        })
        .collect();
    (!violated.is_empty()).then(|| {
        Status::Infeasible(format!(
            "the parameter bounds do not let the model reach every hard bound: {}",
            violated.join("; ")
        ))
    })
}

/// The warnings of the fit's end: a stall at the edge of the model's equilibria, and each
/// parameter that ends on a bound.
fn end_warnings(problem: &Problem, p: &[f64], stalled: Option<usize>, warnings: &mut Vec<String>) {
    if let Some(lost) = stalled {
        warnings.push(format!(
            "stopped where every trial step ({lost}, the trust region shrunk by 4 each time) left \
             the model without an equilibrium at some target: the cost may fall beyond the edge \
             of the model's equilibria, and the standard errors describe its curvature here only"
        ));
    }
    for (q, v) in problem.parameters.iter().zip(p) {
        if on_bound(*v, (q.lower, q.upper), problem.options.tolerance) {
            warnings.push(format!(
                "parameter `{}` ends on a bound ({v}): its standard error is the free estimate's \
                 there, and its 95 % interval is one-sided, from the bound into the range",
                q.kind.name()
            ));
        }
    }
}
