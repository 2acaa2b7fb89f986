//! A damped Newton solver for small nonlinear systems `f(x) = 0` with a finite-difference
//! Jacobian, used by the rotor equilibrium (and by trim).
//!
//! Convergence criterion: the infinity norm of the residual vector at most `tolerance`. The
//! caller scales unknowns and residuals to order one. Failure returns the last iterate and its
//! residuals, never a silent NaN.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use thiserror::Error;

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NewtonOptions {
    /// Converged when every residual is at most this in magnitude.
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Forward-difference step on the (scaled) unknowns.
    pub fd_step: f64,
    /// Times a step may be halved while the residual norm does not fall.
    pub max_halvings: usize,
    /// Update the Jacobian by Broyden's rank-one formula after each accepted step instead of
    /// recomputing it by finite differences (which is done again whenever an updated
    /// Jacobian fails to give a descent step). Saves model evaluations when they are costly.
    pub broyden: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-9,
            max_iterations: 40,
            fd_step: 1e-6,
            max_halvings: 8,
            broyden: false,
        }
    }
}

/// A converged solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Converged {
    pub x: Vec<f64>,
    pub residuals: Vec<f64>,
    pub residual_norm: f64,
    pub iterations: usize,
    /// Calls of the residual function, finite differences included.
    pub evaluations: usize,
    /// The last Jacobian the solver stepped with (finite differences or their Broyden update),
    /// to start a nearby solve from; `None` when `x0` was already a solution.
    #[serde(skip)]
    pub jacobian: Option<DMatrix<f64>>,
}

/// Why the solver stopped without converging.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolveError {
    #[error(
        "no convergence after {iterations} iterations: residuals {residuals:?} at x = {x:?} (tolerance {tolerance:e})"
    )]
    NoConvergence {
        x: Vec<f64>,
        residuals: Vec<f64>,
        iterations: usize,
        tolerance: f64,
    },
    #[error("the Jacobian is singular at x = {x:?} (residuals {residuals:?})")]
    Singular { x: Vec<f64>, residuals: Vec<f64> },
    #[error("the model failed at x = {x:?}: {message}")]
    Model { x: Vec<f64>, message: String },
}

fn norm(r: &[f64]) -> f64 {
    r.iter().fold(0.0f64, |m, v| {
        if v.is_nan() {
            f64::INFINITY
        } else {
            m.max(v.abs())
        }
    })
}

/// Solves `f(x) = 0` from `x0`.
pub fn newton<F>(f: F, x0: &[f64], opts: NewtonOptions) -> Result<Converged, SolveError>
where
    F: FnMut(&[f64]) -> Result<Vec<f64>, String>,
{
    newton_from(f, x0, None, opts)
}

/// Solves `f(x) = 0` from `x0`, stepping first with `jacobian` (the Jacobian of a nearby solve,
/// say) instead of finite differences. A Jacobian of the wrong shape is ignored; one that fails
/// to give a descent step is replaced by finite differences, as a Broyden update is.
pub fn newton_from<F>(
    mut f: F,
    x0: &[f64],
    jacobian: Option<DMatrix<f64>>,
    opts: NewtonOptions,
) -> Result<Converged, SolveError>
where
    F: FnMut(&[f64]) -> Result<Vec<f64>, String>,
{
    let n = x0.len();
    let mut x = x0.to_vec();
    let calls = std::cell::Cell::new(0usize);
    let mut eval = |x: &[f64]| {
        calls.set(calls.get() + 1);
        f(x).map_err(|message| SolveError::Model {
            x: x.to_vec(),
            message,
        })
    };
    let mut r = eval(&x)?;
    let mut jac: Option<DMatrix<f64>> = jacobian.filter(|j| j.nrows() == r.len() && j.ncols() == n);
    // A Jacobian handed in is treated like a Broyden update: when it misleads, it is replaced.
    let mut fresh = jac.is_none();
    let mut it = 0;
    while it <= opts.max_iterations {
        let rn = norm(&r);
        if rn <= opts.tolerance {
            return Ok(Converged {
                x,
                residual_norm: rn,
                residuals: r,
                iterations: it,
                evaluations: calls.get(),
                jacobian: jac,
            });
        }
        if it == opts.max_iterations {
            break;
        }
        let m = r.len();
        if jac.is_none() {
            let mut fd = DMatrix::zeros(m, n);
            for j in 0..n {
                let mut xp = x.clone();
                let h = opts.fd_step * x[j].abs().max(1.0);
                xp[j] += h;
                let rp = eval(&xp)?;
                for i in 0..m {
                    fd[(i, j)] = (rp[i] - r[i]) / h;
                }
            }
            jac = Some(fd);
            fresh = true;
        }
        let jac_now = jac.clone().unwrap_or_else(|| DMatrix::zeros(m, n));
        let rhs = -DVector::from_column_slice(&r);
        let dx = if m == n {
            jac_now.clone().lu().solve(&rhs)
        } else {
            let jt = jac_now.transpose();
            (&jt * &jac_now).lu().solve(&(jt * rhs))
        }
        .filter(|d| d.iter().all(|v| v.is_finite()));
        let Some(dx) = dx else {
            if !fresh {
                jac = None;
                continue;
            }
            return Err(SolveError::Singular {
                x: x.clone(),
                residuals: r.clone(),
            });
        };
        let mut step = 1.0;
        let mut accepted = false;
        for _ in 0..=opts.max_halvings {
            let xt: Vec<f64> = x.iter().zip(dx.iter()).map(|(a, d)| a + step * d).collect();
            if let Ok(rt) = eval(&xt)
                && norm(&rt) < rn
            {
                if opts.broyden {
                    // J += (dr - J ds) ds^T / (ds^T ds)
                    let ds = DVector::from_iterator(n, dx.iter().map(|d| step * d));
                    let dr = DVector::from_iterator(m, rt.iter().zip(&r).map(|(a, b)| a - b));
                    let denom = ds.dot(&ds);
                    if denom > 0.0 {
                        let upd = (dr - &jac_now * &ds) * ds.transpose() / denom;
                        jac = Some(jac_now + upd);
                    }
                    fresh = false;
                } else {
                    jac = None;
                }
                x = xt;
                r = rt;
                accepted = true;
                break;
            }
            step *= 0.5;
        }
        if !accepted {
            if !fresh {
                // The updated (or handed-in) Jacobian misled: start again from finite differences.
                jac = None;
                continue;
            }
            break;
        }
        it += 1;
    }
    Err(SolveError::NoConvergence {
        x,
        residuals: r,
        iterations: opts.max_iterations,
        tolerance: opts.tolerance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonlinear_pair() {
        // x^2 + y^2 = 4, x = y: (sqrt 2, sqrt 2).
        let s = newton(
            |v| Ok(vec![v[0] * v[0] + v[1] * v[1] - 4.0, v[0] - v[1]]),
            &[1.0, 0.5],
            NewtonOptions::default(),
        )
        .unwrap();
        assert!((s.x[0] - 2f64.sqrt()).abs() < 1e-9 && s.iterations < 10);
    }

    #[test]
    fn reports_failure_with_residuals() {
        // x^2 + 1 = 0 has no real root.
        match newton(
            |v| Ok(vec![v[0] * v[0] + 1.0]),
            &[0.5],
            NewtonOptions::default(),
        ) {
            Err(
                SolveError::NoConvergence { residuals, .. }
                | SolveError::Singular { residuals, .. },
            ) => {
                assert!(residuals[0] >= 1.0)
            }
            other => panic!("{other:?}"),
        }
        let e = newton(
            |_| Err("boom".to_string()),
            &[0.0],
            NewtonOptions::default(),
        );
        assert!(matches!(e, Err(SolveError::Model { .. })));
    }
}
