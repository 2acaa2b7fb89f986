//! The fit's sequential linearisation (`fit`): the problem and its options, the residuals and
//! cost, the trust-region loop with Broyden updates between finite-difference Jacobians, and
//! the result with its standard errors and warnings.

use super::qp::qp_step;
use super::targets::{HARD_SLACK, check, evaluate_from, jacobian};
use super::{Enforce, FitSubject, Parameter, ParameterKind, Target, WarmStarts};
use crate::inputs::corrections::CorrectionSet;
use serde::Serialize;

/// Iteration limits and tolerances.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Options {
    pub max_iterations: usize,
    /// Converged when the step is below this fraction of every parameter's range, or the cost
    /// falls by less than this fraction.
    pub tolerance: f64,
    /// Forward-difference step as a fraction of each parameter's range.
    pub difference_step: f64,
    /// Initial trust region as a fraction of each parameter's range.
    pub trust_region: f64,
    /// Update the Jacobian by Broyden's rank-one formula between finite-difference refreshes
    /// (`true`), or difference it afresh every iteration (`false`). Convergence is judged,
    /// and standard errors computed, on a fresh one either way.
    pub broyden: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            max_iterations: 20,
            tolerance: 1e-6,
            difference_step: 1e-3,
            trust_region: 0.5,
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
}

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
}

/// The fit problem.
#[derive(Debug, Clone)]
pub struct Problem {
    pub subject: FitSubject,
    pub parameters: Vec<Parameter>,
    pub targets: Vec<Target>,
    pub options: Options,
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

/// Standard errors from `(J' J)^-1` of the scaled residual Jacobian (targets only).
fn standard_errors(problem: &Problem, jt: &[Vec<f64>]) -> (Vec<f64>, Vec<String>) {
    let n = problem.parameters.len();
    let mut warnings = Vec::new();
    let mut m = nalgebra::DMatrix::<f64>::zeros(n, n);
    for (t, row) in problem.targets.iter().zip(jt) {
        for a in 0..n {
            for b in 0..n {
                m[(a, b)] += row[a] * row[b] / (t.standard_error * t.standard_error);
            }
        }
    }
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

/// Whether a step reaches its trust region's edge in any parameter.
fn limited_by(step: &[f64], radius: &[f64]) -> bool {
    step.iter().zip(radius).any(|(d, r)| d.abs() >= 0.99 * r)
}

/// Fits the parameters. Never panics on a problem: a malformed problem, a model that will not
/// trim or an infeasible set of bounds each end with their status.
pub fn fit(problem: &Problem) -> FitResult {
    // Long: the fit's outer loop (step, judge, refresh the Jacobian, stop) is one algorithm whose
    // state every branch shares
    let kinds: Vec<ParameterKind> = problem.parameters.iter().map(|p| p.kind).collect();
    let start: Vec<f64> = problem.parameters.iter().map(|p| p.start).collect();
    // A fit that ends before its first iteration: the start, no standard errors.
    let unstarted = |status| FitResult {
        status,
        parameters: kinds.clone(),
        values: start.clone(),
        standard_errors: vec![f64::INFINITY; start.len()],
        iterations: 0,
        evaluations: 0,
        cost_start: f64::NAN,
        cost: f64::NAN,
        before: vec![f64::NAN; problem.targets.len()],
        after: vec![f64::NAN; problem.targets.len()],
        warnings: vec![],
    };
    if let Err(e) = check(problem) {
        return unstarted(Status::BadProblem(e));
    }
    let warm = WarmStarts::default();
    let y0 = match evaluate_from(problem, &start, Some(&warm)) {
        Ok(y) => y,
        Err(e) => return unstarted(Status::ModelFailure(e)),
    };
    let mut evaluations = 1;
    let mut p = start.clone();
    let mut y = y0.clone();
    let mut r = residuals(problem, &p, &y);
    let c0 = cost(&r);
    let mut c = c0;
    let initial_radius: Vec<f64> = problem
        .parameters
        .iter()
        .map(|q| problem.options.trust_region * (q.upper - q.lower))
        .collect();
    let mut radius = initial_radius.clone();
    let mut jt: Vec<Vec<f64>> = Vec::new();
    // Whether `jt` is a finite-difference Jacobian at `p` (else a Broyden update of one).
    let mut fresh = false;
    let mut status = Status::IterationLimit;
    let mut iterations = 0;
    let refresh = |p: &[f64], y: &[f64], evaluations: &mut usize| {
        *evaluations += p.len();
        jacobian(problem, &warm, p, y)
    };
    // Set when a step's outcome must be judged on a finite-difference Jacobian.
    let mut want_fresh = false;
    // Trial steps lost at the end: the fit stopped because every step the trust region
    // allowed left the model without an equilibrium, not because none lowered the cost.
    let mut stalled: Option<usize> = None;
    for it in 0..problem.options.max_iterations {
        iterations = it + 1;
        if !fresh && (jt.is_empty() || want_fresh || !problem.options.broyden) {
            jt = match refresh(&p, &y, &mut evaluations) {
                Ok(j) => j,
                Err(e) => {
                    status = Status::ModelFailure(e);
                    break;
                }
            };
            fresh = true;
        }
        // Inner loop: shrink the trust region until a step lowers the cost. With an updated
        // (not fresh) Jacobian, a failed or tiny step first refreshes the Jacobian instead.
        let mut accepted = false;
        let mut small = false;
        let mut stale = false;
        let mut reopened = false;
        // Trial steps this iteration the model could and could not evaluate.
        let (mut evaluated, mut lost) = (0usize, 0usize);
        for _ in 0..8 {
            let d = match qp_step(problem, &p, &y, &r, &jt, &radius) {
                Ok(d) => d,
                Err(s) => {
                    status = s;
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
            if small && fresh && !reopened && limited_by(&d, &radius) {
                radius.clone_from(&initial_radius);
                reopened = true;
                small = false;
                continue;
            }
            if small {
                break;
            }
            let trial: Vec<f64> = p
                .iter()
                .zip(&d)
                .zip(&problem.parameters)
                .map(|((v, di), q)| (v + di).clamp(q.lower, q.upper))
                .collect();
            // The predicted cost from the linearisation.
            let predicted = {
                let stepped: Vec<f64> = p.iter().zip(&d).map(|(v, di)| v + di).collect();
                let linear: Vec<f64> = y
                    .iter()
                    .zip(&jt)
                    .map(|(v, row)| v + row.iter().zip(&d).map(|(a, b)| a * b).sum::<f64>())
                    .collect();
                cost(&residuals(problem, &stepped, &linear))
            };
            evaluations += 1;
            match evaluate_from(problem, &trial, Some(&warm)) {
                Ok(yt) => {
                    evaluated += 1;
                    let rt = residuals(problem, &trial, &yt);
                    let ct = cost(&rt);
                    let ratio = (c - ct) / (c - predicted).max(f64::MIN_POSITIVE);
                    if ct < c {
                        let at_edge = limited_by(&d, &radius);
                        if ratio > 0.75 && at_edge {
                            radius.iter_mut().for_each(|v| *v *= 2.0);
                        } else if ratio < 0.25 {
                            radius.iter_mut().for_each(|v| *v *= 0.5);
                        }
                        let drop = (c - ct) / c.max(f64::MIN_POSITIVE);
                        if problem.options.broyden {
                            broyden_update(&mut jt, &p, &trial, &y, &yt);
                        }
                        fresh = false;
                        (p, y, r, c) = (trial, yt, rt, ct);
                        accepted = true;
                        // (A small drop from a step the region held back is not convergence.)
                        if drop <= problem.options.tolerance && !at_edge {
                            small = true;
                        }
                        break;
                    }
                    if !fresh {
                        stale = true;
                        break;
                    }
                    radius.iter_mut().for_each(|v| *v *= 0.25);
                }
                // A trial the model cannot trim: a smaller step.
                Err(_) => {
                    lost += 1;
                    radius.iter_mut().for_each(|v| *v *= 0.25);
                }
            }
        }
        if matches!(status, Status::Infeasible(_) | Status::ModelFailure(_)) {
            break;
        }
        if fresh && (small || !accepted) {
            status = Status::Converged;
            if !accepted && evaluated == 0 && lost > 0 {
                stalled = Some(lost);
            }
            break;
        }
        // A failed or tiny step on an updated Jacobian: judge it again on a fresh one.
        want_fresh = !fresh && (stale || small || !accepted);
    }
    // Standard errors from a finite-difference Jacobian at the solution.
    if !fresh
        && !jt.is_empty()
        && !matches!(status, Status::ModelFailure(_))
        && let Ok(j) = refresh(&p, &y, &mut evaluations)
    {
        jt = j;
    }
    let (se, mut warnings) = if jt.is_empty() {
        (vec![f64::INFINITY; p.len()], vec![])
    } else {
        standard_errors(problem, &jt)
    };
    // A hard bound left violated: the bounds contradict each other or the model cannot reach
    // them.
    if !matches!(status, Status::ModelFailure(_) | Status::BadProblem(_)) {
        let violated: Vec<String> = problem
            .targets
            .iter()
            .zip(&y)
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
        if !violated.is_empty() {
            status = Status::Infeasible(format!(
                "the parameter bounds do not let the model reach every hard bound: {}",
                violated.join("; ")
            ));
        }
    }
    if let Some(lost) = stalled {
        warnings.push(format!(
            "stopped where every trial step ({lost}, the trust region shrunk by 4 each time) left \
             the model without an equilibrium at some target: the cost may fall beyond the edge \
             of the model's equilibria, and the standard errors describe its curvature here only"
        ));
    }
    for (q, v) in problem.parameters.iter().zip(&p) {
        if (v - q.lower).abs() <= 1e-9 * (q.upper - q.lower)
            || (v - q.upper).abs() <= 1e-9 * (q.upper - q.lower)
        {
            warnings.push(format!(
                "parameter `{}` ends on a bound ({v}): its standard error assumes it is free",
                q.kind.name()
            ));
        }
    }
    FitResult {
        status,
        parameters: kinds,
        values: p,
        standard_errors: se,
        iterations,
        evaluations,
        cost_start: c0,
        cost: c,
        before: y0,
        after: y,
        warnings,
    }
}
