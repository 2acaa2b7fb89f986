//! Sobol' sensitivity indices from a Saltelli design ([`super::design`]).
//!
//! For a quantity `Y = f(X_1, ..., X_d)` of independent inputs, the first-order index
//! `S_i = V[E(Y | X_i)] / V(Y)` is the share of the variance that `X_i` alone explains, and the
//! total index `S_Ti = E[V(Y | X_~i)] / V(Y)` the share it has a hand in, interactions included
//! (`S_Ti - S_i` is what it does only together with others). Estimators (Saltelli et al. 2010,
//! Table 2: (b) for the first order, (f), Jansen 1999, for the total):
//!
//! ```text
//! V_i  = 1/n   sum_j f(B)_j (f(A_B^i)_j - f(A)_j)
//! V_Ti = 1/(2n) sum_j (f(A)_j - f(A_B^i)_j)^2
//! ```
//!
//! with `V(Y)` over the rows of `A` and `B` together. A row in which any matrix's value is not
//! finite (a sample the model could not evaluate) is left out of every estimate and counted.

use serde::Serialize;

/// One input's indices for one quantity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Indices {
    pub first: f64,
    pub total: f64,
}

/// Indices of every input, and what they were computed from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// The variance of the quantity over the rows of `A` and `B` used.
    pub variance: f64,
    /// The rows used (of `n`): those where every matrix's value is finite.
    pub rows: usize,
    pub indices: Vec<Indices>,
}

/// The indices from `f(A)`, `f(B)` and `f(A_B^(i))`; `None` where fewer than two rows are
/// finite or the quantity does not vary (no variance to share out).
pub fn estimate(f_a: &[f64], f_b: &[f64], f_ab: &[&[f64]]) -> Option<Estimate> {
    let n = f_a.len();
    let rows: Vec<usize> = (0..n)
        .filter(|&j| {
            f_a[j].is_finite() && f_b[j].is_finite() && f_ab.iter().all(|m| m[j].is_finite())
        })
        .collect();
    if rows.len() < 2 {
        return None;
    }
    let m = rows.len() as f64;
    let all: Vec<f64> = rows.iter().flat_map(|&j| [f_a[j], f_b[j]]).collect();
    let mean = all.iter().sum::<f64>() / all.len() as f64;
    let variance = all.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (all.len() - 1) as f64;
    // A spread at the level of rounding is no variance: the quantity does not move.
    if variance.is_nan() || variance <= (1e-12 * mean.abs()).powi(2) {
        return None;
    }
    let indices = f_ab
        .iter()
        .map(|ab| {
            let first = rows.iter().map(|&j| f_b[j] * (ab[j] - f_a[j])).sum::<f64>() / m;
            let total = rows.iter().map(|&j| (f_a[j] - ab[j]).powi(2)).sum::<f64>() / (2.0 * m);
            Indices {
                first: first / variance,
                total: total / variance,
            }
        })
        .collect();
    Some(Estimate {
        variance,
        rows: rows.len(),
        indices,
    })
}
