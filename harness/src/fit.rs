//! Constrained fitting of the model's empirical corrections against flight references.
//!
//! # Problem
//! Parameters `p` (corrections with bounds), targets `y_k(p)` (derivatives or trim quantities
//! at flight conditions) with references `d_k` and standard errors `s_k`. The cost is
//!
//! ```text
//! C(p) = sum_k ((y_k(p) - d_k) / s_k)^2 + sum_i w_i ((p_i - p0_i) / range_i)^2
//! ```
//!
//! (the second sum is the optional regularisation towards the uncorrected model `p0`), subject
//! to the parameter bounds and, optionally, hard bounds on targets (`y_k` within its flight
//! bounds).
//!
//! # Method
//! Sequential linearisation: forward-difference sensitivities `J = dy/dp` through trim and
//! linearisation (conditions in parallel), then a quadratic program for the step, solved by
//! clarabel, with the parameter bounds, the linearised target bounds and a box trust region.
//! A step is taken when it lowers the cost; the trust region shrinks when the prediction was
//! poor and grows when it was good and the step reached it.
//!
//! # Result
//! A status (never a panic), the parameters with approximate standard errors from
//! `(J' J)^-1` at the solution (targets are normalised by their standard errors, so this is
//! the usual linearised covariance), and every target before and after.

use crate::{Loading, TrimRequest};
use cierva_model::aircraft::Aircraft;
use serde::{Deserialize, Serialize};

/// A correction the fit can move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ParameterKind {
    /// Seed 000 Sec. VII.A: the fraction of the free stream the rotor's wake takes from the
    /// propeller disc (0..1).
    PropellerBlockage,
    /// Seed 000 Sec. VII.B: the hub's angle of attack as a factor on the c.g.'s.
    HubAoaFactor,
    /// Multiplies the main rotor's section drag coefficient.
    ProfileDragScale,
    /// Added to the main rotor's section drag coefficient.
    ProfileDragIncrement,
    /// Added to the main rotor's blade pitch, deg (a pitch-setting offset).
    PitchOffsetDeg,
}

impl ParameterKind {
    /// The name as written.
    pub fn name(self) -> &'static str {
        match self {
            Self::PropellerBlockage => "propeller_blockage",
            Self::HubAoaFactor => "hub_aoa_factor",
            Self::ProfileDragScale => "profile_drag_scale",
            Self::ProfileDragIncrement => "profile_drag_increment",
            Self::PitchOffsetDeg => "pitch_offset_deg",
        }
    }

    /// The uncorrected model's value.
    pub fn neutral(self) -> f64 {
        match self {
            Self::PropellerBlockage | Self::ProfileDragIncrement | Self::PitchOffsetDeg => 0.0,
            Self::HubAoaFactor | Self::ProfileDragScale => 1.0,
        }
    }

    /// Sets the parameter on an aircraft.
    pub fn apply(self, a: &mut Aircraft, value: f64) {
        match self {
            Self::PropellerBlockage => a.propeller.propeller.blockage = value,
            Self::HubAoaFactor => a.hub_aoa_factor = Some(value),
            Self::ProfileDragScale => a.main_rotor.rotor.corrections.profile_drag_scale = value,
            Self::ProfileDragIncrement => {
                a.main_rotor.rotor.corrections.profile_drag_increment = value
            }
            Self::PitchOffsetDeg => a.main_rotor.collective_shift_rad = value.to_radians(),
        }
    }
}

/// A fitted parameter: bounds and start.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Parameter {
    pub kind: ParameterKind,
    pub lower: f64,
    pub upper: f64,
    pub start: f64,
    /// Weight of the regularisation towards `start` (0: none), per squared bound range.
    pub regularisation: f64,
}

/// What a target measures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Measure {
    /// A derivative of the linearised model (`X_u`, `Q_Omega`).
    Derivative(String),
    /// Trimmed rotor speed, rpm.
    RotorRpm,
    /// Trimmed pitch attitude, deg.
    PitchDeg,
    /// Trimmed longitudinal stick, % of travel.
    StickLongitudinalPercent,
}

impl Measure {
    /// The measure by name: a trim quantity (`rotor_rpm`, `pitch_deg`,
    /// `stick_longitudinal_percent`) or a derivative name.
    pub fn parse(name: &str) -> Self {
        match name {
            "rotor_rpm" => Self::RotorRpm,
            "pitch_deg" => Self::PitchDeg,
            "stick_longitudinal_percent" => Self::StickLongitudinalPercent,
            d => Self::Derivative(d.to_string()),
        }
    }

    /// The name as written.
    pub fn name(&self) -> String {
        match self {
            Self::Derivative(d) => d.clone(),
            Self::RotorRpm => "rotor_rpm".into(),
            Self::PitchDeg => "pitch_deg".into(),
            Self::StickLongitudinalPercent => "stick_longitudinal_percent".into(),
        }
    }
}

/// A flight reference to fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Target {
    pub condition: TrimRequest,
    pub measure: Measure,
    pub reference: f64,
    /// Its standard error (or a bound width): the residual's scale. Positive.
    pub standard_error: f64,
    /// Optional hard bounds the fitted value must lie within (for example the 95 % flight
    /// bounds).
    pub hard_bounds: Option<[f64; 2]>,
}

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
}

impl Default for Options {
    fn default() -> Self {
        Self {
            max_iterations: 20,
            tolerance: 1e-6,
            difference_step: 1e-3,
            trust_region: 0.5,
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

/// A fit's outcome.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitResult {
    pub status: Status,
    pub parameters: Vec<ParameterKind>,
    pub values: Vec<f64>,
    /// Approximate standard errors (infinite for a parameter the targets do not see).
    pub standard_errors: Vec<f64>,
    pub iterations: usize,
    pub cost_start: f64,
    pub cost: f64,
    /// Every target's model value at the start and at the end (NaN where not evaluated).
    pub before: Vec<f64>,
    pub after: Vec<f64>,
    /// Remarks: parameters with no effect, active bounds.
    pub warnings: Vec<String>,
}

/// The fit problem.
#[derive(Debug, Clone)]
pub struct Problem {
    pub aircraft: Aircraft,
    pub loading: Loading,
    pub parameters: Vec<Parameter>,
    pub targets: Vec<Target>,
    pub options: Options,
}

/// The model's value of every target at parameter values `p`, conditions in parallel.
pub fn evaluate(problem: &Problem, p: &[f64]) -> Result<Vec<f64>, String> {
    let mut a = problem.aircraft.clone();
    for (par, v) in problem.parameters.iter().zip(p) {
        par.kind.apply(&mut a, *v);
    }
    let mut conditions: Vec<TrimRequest> = Vec::new();
    for t in &problem.targets {
        if !conditions.contains(&t.condition) {
            conditions.push(t.condition);
        }
    }
    let results: Vec<Result<_, String>> = std::thread::scope(|s| {
        let handles: Vec<_> = conditions
            .iter()
            .map(|c| {
                let a = &a;
                s.spawn(move || {
                    crate::run_linearise(a, *c, problem.loading).map_err(|e| {
                        format!(
                            "at {} mph with {}: {e}",
                            c.airspeed_mph,
                            describe(problem, p)
                        )
                    })
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("evaluation panicked".into()))
            })
            .collect()
    });
    let mut out = Vec::with_capacity(problem.targets.len());
    for t in &problem.targets {
        let k = conditions
            .iter()
            .position(|c| *c == t.condition)
            .expect("listed");
        let (trim, lin) = results[k].as_ref().map_err(Clone::clone)?;
        let v = match &t.measure {
            Measure::Derivative(d) => lin.model.derivative_value(d).map_err(|e| e.to_string())?,
            Measure::RotorRpm => trim.rotor_rpm,
            Measure::PitchDeg => trim.pitch_rad.to_degrees(),
            Measure::StickLongitudinalPercent => trim.controls.stick_longitudinal_percent,
        };
        out.push(v);
    }
    Ok(out)
}

fn describe(problem: &Problem, p: &[f64]) -> String {
    problem
        .parameters
        .iter()
        .zip(p)
        .map(|(q, v)| format!("{} = {v:.4}", q.kind.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Residuals: scaled target misfits, then the regularisation rows.
fn residuals(problem: &Problem, p: &[f64], y: &[f64]) -> Vec<f64> {
    let mut r: Vec<f64> = problem
        .targets
        .iter()
        .zip(y)
        .map(|(t, v)| (v - t.reference) / t.standard_error)
        .collect();
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

fn check(problem: &Problem) -> Result<(), String> {
    if problem.parameters.is_empty() {
        return Err("no parameters to fit".into());
    }
    if problem.targets.is_empty() {
        return Err("no targets to fit".into());
    }
    for (i, p) in problem.parameters.iter().enumerate() {
        let name = p.kind.name();
        if problem.parameters[..i].iter().any(|q| q.kind == p.kind) {
            return Err(format!("parameter `{name}` is given twice"));
        }
        if !(p.lower.is_finite() && p.upper.is_finite() && p.lower < p.upper) {
            return Err(format!(
                "parameter `{name}`: bounds [{}, {}] must be finite with lower < upper",
                p.lower, p.upper
            ));
        }
        if !(p.lower..=p.upper).contains(&p.start) {
            return Err(format!(
                "parameter `{name}`: start {} is outside its bounds [{}, {}]",
                p.start, p.lower, p.upper
            ));
        }
        if !(p.regularisation.is_finite() && p.regularisation >= 0.0) {
            return Err(format!("parameter `{name}`: regularisation must be >= 0"));
        }
    }
    for t in &problem.targets {
        let name = t.measure.name();
        if !(t.reference.is_finite() && t.standard_error.is_finite() && t.standard_error > 0.0) {
            return Err(format!(
                "target `{name}` at {} mph: the reference must be finite and the standard error positive",
                t.condition.airspeed_mph
            ));
        }
        if let Some([lo, hi]) = t.hard_bounds
            && (lo.is_nan() || hi.is_nan() || lo > hi)
        {
            return Err(format!(
                "target `{name}` at {} mph: hard bounds [{lo}, {hi}] are empty",
                t.condition.airspeed_mph
            ));
        }
    }
    Ok(())
}

/// Forward-difference sensitivities of the targets to the parameters; each step goes inwards
/// from a bound.
fn jacobian(problem: &Problem, p: &[f64], y: &[f64]) -> Result<Vec<Vec<f64>>, String> {
    let n = p.len();
    let mut j = vec![vec![0.0; n]; y.len()];
    for i in 0..n {
        let par = &problem.parameters[i];
        let mut h = problem.options.difference_step * (par.upper - par.lower);
        if p[i] + h > par.upper {
            h = -h;
        }
        let mut q = p.to_vec();
        q[i] += h;
        let yq = evaluate(problem, &q)?;
        for k in 0..y.len() {
            j[k][i] = (yq[k] - y[k]) / h;
        }
    }
    Ok(j)
}

/// The step's quadratic program: minimise `|r + J d|^2` (rows scaled as the residuals) within
/// the parameter bounds, the trust region and the linearised hard target bounds.
fn qp_step(
    problem: &Problem,
    p: &[f64],
    y: &[f64],
    r: &[f64],
    jt: &[Vec<f64>],
    radius: &[f64],
) -> Result<Vec<f64>, Status> {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{
        DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    };
    let n = p.len();
    // Residual Jacobian: the targets' rows scaled by their standard errors, then the
    // regularisation rows.
    let mut jr: Vec<Vec<f64>> = problem
        .targets
        .iter()
        .zip(jt)
        .map(|(t, row)| row.iter().map(|v| v / t.standard_error).collect())
        .collect();
    for (i, par) in problem.parameters.iter().enumerate() {
        if par.regularisation > 0.0 {
            let mut row = vec![0.0; n];
            row[i] = par.regularisation.sqrt() / (par.upper - par.lower);
            jr.push(row);
        }
    }
    let mut pm = vec![vec![0.0; n]; n];
    let mut q = vec![0.0; n];
    for (row, ri) in jr.iter().zip(r) {
        for a in 0..n {
            q[a] += row[a] * ri;
            for b in 0..n {
                pm[a][b] += row[a] * row[b];
            }
        }
    }
    // Constraints A d <= b: upper and lower bounds with the trust region, then the hard target
    // bounds.
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut b: Vec<f64> = Vec::new();
    for (i, par) in problem.parameters.iter().enumerate() {
        let mut up = vec![0.0; n];
        up[i] = 1.0;
        rows.push(up);
        b.push((par.upper - p[i]).min(radius[i]).max(0.0));
        let mut down = vec![0.0; n];
        down[i] = -1.0;
        rows.push(down);
        b.push((p[i] - par.lower).min(radius[i]).max(0.0));
    }
    for (k, t) in problem.targets.iter().enumerate() {
        if let Some([lo, hi]) = t.hard_bounds {
            rows.push(jt[k].clone());
            b.push(hi - y[k]);
            rows.push(jt[k].iter().map(|v| -v).collect());
            b.push(y[k] - lo);
        }
    }
    let to_csc = |m: &[Vec<f64>], cols: usize| {
        let mut colptr = vec![0usize];
        let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
        for c in 0..cols {
            for (rix, row) in m.iter().enumerate() {
                if row[c] != 0.0 {
                    rowval.push(rix);
                    nzval.push(row[c]);
                }
            }
            colptr.push(rowval.len());
        }
        CscMatrix::new(m.len(), cols, colptr, rowval, nzval)
    };
    // clarabel takes the upper triangle of P.
    let upper: Vec<Vec<f64>> = (0..n)
        .map(|a| {
            (0..n)
                .map(|c| if c >= a { pm[a][c] } else { 0.0 })
                .collect()
        })
        .collect();
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .build()
        .map_err(|e| Status::BadProblem(format!("QP settings: {e:?}")))?;
    let cones = [NonnegativeConeT(rows.len())];
    let mut solver = DefaultSolver::new(
        &to_csc(&upper, n),
        &q,
        &to_csc(&rows, n),
        &b,
        &cones,
        settings,
    )
    .map_err(|e| Status::BadProblem(format!("QP set-up: {e:?}")))?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(solver.solution.x.clone()),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            Err(Status::Infeasible(
                "the parameter bounds, trust region and hard target bounds admit no step (linearised)"
                    .into(),
            ))
        }
        other => Err(Status::ModelFailure(format!(
            "the step's quadratic program ended {other:?}"
        ))),
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
    match sub.clone().try_inverse() {
        Some(inv) if inv.iter().all(|v| v.is_finite()) => {
            for (a, &i) in seen.iter().enumerate() {
                se[i] = inv[(a, a)].max(0.0).sqrt();
            }
        }
        _ => warnings.push(
            "the fitted parameters are not separately identifiable from these targets (J'J is singular): standard errors are infinite".into(),
        ),
    }
    (se, warnings)
}

/// Fits the parameters. Never panics on a problem: a malformed problem, a model that will not
/// trim or an infeasible set of bounds each end with their status.
pub fn fit(problem: &Problem) -> FitResult {
    let kinds: Vec<ParameterKind> = problem.parameters.iter().map(|p| p.kind).collect();
    let start: Vec<f64> = problem.parameters.iter().map(|p| p.start).collect();
    // A fit that ends before its first iteration: the start, no standard errors.
    let unstarted = |status| FitResult {
        status,
        parameters: kinds.clone(),
        values: start.clone(),
        standard_errors: vec![f64::INFINITY; start.len()],
        iterations: 0,
        cost_start: f64::NAN,
        cost: f64::NAN,
        before: vec![f64::NAN; problem.targets.len()],
        after: vec![f64::NAN; problem.targets.len()],
        warnings: vec![],
    };
    if let Err(e) = check(problem) {
        return unstarted(Status::BadProblem(e));
    }
    let y0 = match evaluate(problem, &start) {
        Ok(y) => y,
        Err(e) => return unstarted(Status::ModelFailure(e)),
    };
    let mut p = start.clone();
    let mut y = y0.clone();
    let mut r = residuals(problem, &p, &y);
    let c0 = cost(&r);
    let mut c = c0;
    let mut radius: Vec<f64> = problem
        .parameters
        .iter()
        .map(|q| problem.options.trust_region * (q.upper - q.lower))
        .collect();
    let mut jt = Vec::new();
    let mut status = Status::IterationLimit;
    let mut iterations = 0;
    for it in 0..problem.options.max_iterations {
        iterations = it + 1;
        jt = match jacobian(problem, &p, &y) {
            Ok(j) => j,
            Err(e) => {
                status = Status::ModelFailure(e);
                break;
            }
        };
        // Inner loop: shrink the trust region until a step lowers the cost.
        let mut accepted = false;
        let mut small = false;
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
            match evaluate(problem, &trial) {
                Ok(yt) => {
                    let rt = residuals(problem, &trial, &yt);
                    let ct = cost(&rt);
                    let ratio = (c - ct) / (c - predicted).max(f64::MIN_POSITIVE);
                    if ct < c {
                        let at_edge = d.iter().zip(&radius).any(|(di, ra)| di.abs() >= 0.99 * ra);
                        if ratio > 0.75 && at_edge {
                            radius.iter_mut().for_each(|v| *v *= 2.0);
                        } else if ratio < 0.25 {
                            radius.iter_mut().for_each(|v| *v *= 0.5);
                        }
                        let drop = (c - ct) / c.max(f64::MIN_POSITIVE);
                        (p, y, r, c) = (trial, yt, rt, ct);
                        accepted = true;
                        if drop <= problem.options.tolerance {
                            small = true;
                        }
                        break;
                    }
                    radius.iter_mut().for_each(|v| *v *= 0.25);
                }
                // A trial the model cannot trim: a smaller step.
                Err(_) => radius.iter_mut().for_each(|v| *v *= 0.25),
            }
        }
        if matches!(status, Status::Infeasible(_) | Status::ModelFailure(_)) {
            break;
        }
        if small || !accepted {
            status = Status::Converged;
            break;
        }
    }
    let (se, mut warnings) = if jt.is_empty() {
        (vec![f64::INFINITY; p.len()], vec![])
    } else {
        standard_errors(problem, &jt)
    };
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
        cost_start: c0,
        cost: c,
        before: y0,
        after: y,
        warnings,
    }
}
