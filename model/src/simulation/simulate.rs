//! Time response of a linear model, `x' = A x + B u(t)`, by fourth-order Runge-Kutta with the
//! input evaluated exactly at every stage (inputs are functions of time, not samples).

use crate::analysis::linear::LinearModel;
use nalgebra::DVector;

/// States at `t = k dt` for `k = 0..=steps`, from `x0`.
///
/// `input(t)` returns the control vector at time `t` (one value per control).
pub fn simulate(
    model: &LinearModel,
    x0: &[f64],
    input: &dyn Fn(f64) -> Vec<f64>,
    dt_s: f64,
    steps: usize,
) -> Vec<Vec<f64>> {
    let a = model.a();
    let b = model.b();
    let f = |t: f64, x: &DVector<f64>| a * x + b * DVector::from_vec(input(t));
    let mut x = DVector::from_column_slice(x0);
    let mut out = Vec::with_capacity(steps + 1);
    out.push(x.as_slice().to_vec());
    for k in 0..steps {
        let t = k as f64 * dt_s;
        let k1 = f(t, &x);
        let k2 = f(t + 0.5 * dt_s, &(&x + &k1 * (0.5 * dt_s)));
        let k3 = f(t + 0.5 * dt_s, &(&x + &k2 * (0.5 * dt_s)));
        let k4 = f(t + dt_s, &(&x + &k3 * dt_s));
        x += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt_s / 6.0);
        out.push(x.as_slice().to_vec());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_order_step_matches_the_exponential() {
        let m = LinearModel::from_rows(
            vec!["x".into()],
            vec!["u".into()],
            &[vec![-2.0]],
            &[vec![2.0]],
        )
        .unwrap();
        let xs = simulate(&m, &[0.0], &|_| vec![1.0], 0.01, 100);
        let exact = 1.0 - (-2.0f64).exp();
        assert!((xs[100][0] - exact).abs() < 1e-9, "{}", xs[100][0]);
    }
}
