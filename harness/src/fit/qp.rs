//! The step's quadratic program, solved by clarabel: the scaled misfit within the parameter
//! bounds and the trust region, with a slack for each bounded target.

use super::{Problem, Status};
use clarabel::algebra::CscMatrix;

/// The step's quadratic program: minimise `|r + J d|^2` (rows scaled as the residuals) within
/// the parameter bounds and the trust region. Each bounded target gets a slack `s >= 0` with
/// `lower - s <= y + J d <= upper + s`, costing `weight (s / standard_error)^2`: the
/// linearised violation, exactly.
pub(super) fn qp_step(
    problem: &Problem,
    p: &[f64],
    y: &[f64],
    r: &[f64],
    jt: &[Vec<f64>],
    radius: &[f64],
) -> Result<Vec<f64>, Status> {
    use clarabel::solver::{
        DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    };
    let n = p.len();
    let bounded: Vec<usize> = (0..problem.targets.len())
        .filter(|&k| problem.targets[k].penalty().is_some())
        .collect();
    let nx = n + bounded.len();
    let (pm, q) = objective(problem, r, jt, &bounded, nx);
    let (rows, b) = constraints(problem, p, y, jt, radius, &bounded, nx);
    // clarabel takes the upper triangle of P.
    let upper: Vec<Vec<f64>> = (0..nx)
        .map(|a| {
            (0..nx)
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
        &to_csc(&upper, nx),
        &q,
        &to_csc(&rows, nx),
        &b,
        &cones,
        settings,
    )
    .map_err(|e| Status::BadProblem(format!("QP set-up: {e:?}")))?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(solver.solution.x[..n].to_vec()),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => Err(
            Status::Infeasible("the parameter bounds and trust region admit no step".into()),
        ),
        other => Err(Status::ModelFailure(format!(
            "the step's quadratic program ended {other:?}"
        ))),
    }
}

/// The objective `x' P x / 2 + q' x` over the step and the slacks (`nx` of them in all, the
/// step's `n` first): `P = J_r' J_r` and `q = J_r' r` of the misfit and regularisation rows
/// (the bound rows are the slacks, each weighted by its penalty over its squared standard
/// error).
fn objective(
    problem: &Problem,
    r: &[f64],
    jt: &[Vec<f64>],
    bounded: &[usize],
    nx: usize,
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let n = problem.parameters.len();
    // Residual Jacobian of the misfit and regularisation rows (the bound rows are the slacks).
    let mut jr: Vec<Vec<f64>> = problem
        .targets
        .iter()
        .zip(jt)
        .map(|(t, row)| row.iter().map(|v| v / t.standard_error).collect())
        .collect();
    let mut rr: Vec<f64> = r[..problem.targets.len()].to_vec();
    let regularisation = &r[problem.targets.len() + bounded.len()..];
    let mut next = 0;
    for (i, par) in problem.parameters.iter().enumerate() {
        if par.regularisation > 0.0 {
            let mut row = vec![0.0; n];
            row[i] = par.regularisation.sqrt() / (par.upper - par.lower);
            jr.push(row);
            rr.push(regularisation[next]);
            next += 1;
        }
    }
    let mut pm = vec![vec![0.0; nx]; nx];
    let mut q = vec![0.0; nx];
    for (row, ri) in jr.iter().zip(&rr) {
        for a in 0..n {
            q[a] += row[a] * ri;
            for b in 0..n {
                pm[a][b] += row[a] * row[b];
            }
        }
    }
    for (j, &k) in bounded.iter().enumerate() {
        let t = &problem.targets[k];
        let (_, w) = t.penalty().expect("bounded");
        pm[n + j][n + j] = w / (t.standard_error * t.standard_error);
    }
    (pm, q)
}

/// Constraints `A x <= b`: upper and lower bounds with the trust region, then the target
/// bounds with their slacks (and each slack nonnegative).
fn constraints(
    problem: &Problem,
    p: &[f64],
    y: &[f64],
    jt: &[Vec<f64>],
    radius: &[f64],
    bounded: &[usize],
    nx: usize,
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let n = p.len();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut b: Vec<f64> = Vec::new();
    for (i, par) in problem.parameters.iter().enumerate() {
        let mut up = vec![0.0; nx];
        up[i] = 1.0;
        rows.push(up);
        b.push((par.upper - p[i]).min(radius[i]).max(0.0));
        let mut down = vec![0.0; nx];
        down[i] = -1.0;
        rows.push(down);
        b.push((p[i] - par.lower).min(radius[i]).max(0.0));
    }
    for (j, &k) in bounded.iter().enumerate() {
        let (bounds, _) = problem.targets[k].penalty().expect("bounded");
        let mut above = padded(&jt[k], 1.0, nx);
        above[n + j] = -1.0;
        rows.push(above);
        b.push(bounds.upper - y[k]);
        let mut below = padded(&jt[k], -1.0, nx);
        below[n + j] = -1.0;
        rows.push(below);
        b.push(y[k] - bounds.lower);
        let mut nonnegative = vec![0.0; nx];
        nonnegative[n + j] = -1.0;
        rows.push(nonnegative);
        b.push(0.0);
    }
    (rows, b)
}

/// A Jacobian row times `sign`, padded with zeros to `nx` columns (the slacks').
fn padded(row: &[f64], sign: f64, nx: usize) -> Vec<f64> {
    let mut v: Vec<f64> = row.iter().map(|x| sign * x).collect();
    v.resize(nx, 0.0);
    v
}

/// A dense matrix (rows of `cols` entries) in clarabel's compressed sparse columns, zeros left
/// out.
fn to_csc(m: &[Vec<f64>], cols: usize) -> CscMatrix<f64> {
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
}
