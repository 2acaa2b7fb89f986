//! The equation-error regression's arithmetic: one equation's rows from the transforms, its
//! solution by least squares or instrumental variables, and the sandwich covariance
//! ([`equation_error`]); the instruments' transforms from a first model
//! ([`state_instruments`]). The harness's `ident::estimate` turns what these return into fits,
//! errors and warnings; the derivation is in its module documentation.

use nalgebra::{DMatrix, DVector};
use rustfft::num_complex::Complex64 as C;

/// Why an equation has no solution; the harness names the equation and the variable.
#[derive(Debug, Clone, PartialEq)]
pub enum Failure {
    /// No estimated variable, or no more rows (twice the points) than estimated variables.
    TooFewRows,
    /// The regressor of the estimated variable at this position is zero or not finite.
    ZeroColumn(usize),
    /// The scaled regressors' singular values, from the largest down to the smallest, span more
    /// than 1e13 (or the smallest is not a number).
    Singular { largest: f64, smallest: f64 },
    /// The normal equations (or the instruments' cross products) cannot be inverted.
    NotInvertible,
}

/// One equation's solution, in the scaled variables (each regressor column divided by its norm,
/// `scales`): an estimate is `theta[c] / scales[c]`, its variance `covariance[(c, c)] /
/// scales[c]^2`.
#[derive(Debug, Clone)]
pub struct Solved {
    pub theta: DVector<f64>,
    pub covariance: DMatrix<f64>,
    pub scales: Vec<f64>,
    /// The largest singular value of the scaled regressors over the smallest.
    pub condition_number: f64,
    /// The residual sum of squares and the total sum of squares about the mean.
    pub rss: f64,
    pub tss: f64,
    /// Rows less estimated parameters.
    pub dof: usize,
}

/// Solves one equation: `y_c` the state derivative's transform at each point, `var_ft` every
/// variable's, `cols` the estimated variables' positions in it, `fixed` the known ones with
/// their values (moved to the left), `ins_ft` the instruments' transforms (instrumental
/// variables) or none (least squares). Needs more rows (twice the points) than columns.
pub fn equation_error(
    y_c: &[C],
    var_ft: &[Vec<C>],
    ins_ft: Option<&[Vec<C>]>,
    cols: &[usize],
    fixed: &[(usize, f64)],
) -> Result<Solved, Failure> {
    let m = y_c.len();
    let (rows, p) = (2 * m, cols.len());
    if p == 0 || rows <= p {
        return Err(Failure::TooFewRows);
    }
    let (y, x) = regression(y_c, var_ft, cols, fixed);
    // Scale columns to unit norm for a meaningful condition number and a stable solve.
    let scales: Vec<f64> = (0..p).map(|c| x.column(c).norm()).collect();
    if let Some(c) = scales
        .iter()
        .position(|s| s.is_nan() || *s <= 0.0 || s.is_infinite())
    {
        return Err(Failure::ZeroColumn(c));
    }
    let xs = DMatrix::from_fn(rows, p, |i, c| x[(i, c)] / scales[c]);
    let svd = xs.clone().svd(true, true);
    let sv = &svd.singular_values;
    let (smax, smin) = (sv.max(), sv.min());
    if smin.is_nan() || smin <= smax * 1e-13 {
        return Err(Failure::Singular {
            largest: smax,
            smallest: smin,
        });
    }
    let dof = rows - p;
    // Least squares by SVD; instrumental variables: the instruments Zs are built like Xs (same
    // column scales) and theta = (Zs'Xs)^-1 Zs'y.
    let zs = ins_ft.map(|z| instruments(z, cols, &scales, m, p));
    let theta = match &zs {
        None => svd.solve(&y, 0.0).map_err(|_| Failure::NotInvertible)?,
        Some(zs) => {
            let zx_inv = (zs.transpose() * &xs)
                .try_inverse()
                .ok_or(Failure::NotInvertible)?;
            &zx_inv * (zs.transpose() * &y)
        }
    };
    let resid = &y - &xs * &theta;
    let rss = resid.norm_squared();
    let mean = y.mean();
    let tss = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>();
    let covariance = sandwich(zs.as_ref().unwrap_or(&xs), &xs, &resid, dof)?;
    Ok(Solved {
        theta,
        covariance,
        scales,
        condition_number: smax / smin,
        rss,
        tss,
        dof,
    })
}

/// The equation's regression in the frequency domain, real and imaginary parts as rows: the
/// state derivative's transform less the fixed terms (`y`), and the estimated variables'
/// transforms (`X`).
fn regression(
    y_c: &[C],
    var_ft: &[Vec<C>],
    cols: &[usize],
    fixed: &[(usize, f64)],
) -> (DVector<f64>, DMatrix<f64>) {
    let m = y_c.len();
    let (rows, p) = (2 * m, cols.len());
    let mut y = DVector::zeros(rows);
    let mut x = DMatrix::zeros(rows, p);
    for k in 0..m {
        let mut yk = y_c[k];
        for (j, v) in fixed {
            yk -= var_ft[*j][k] * *v;
        }
        y[2 * k] = yk.re;
        y[2 * k + 1] = yk.im;
        for (c, &j) in cols.iter().enumerate() {
            x[(2 * k, c)] = var_ft[j][k].re;
            x[(2 * k + 1, c)] = var_ft[j][k].im;
        }
    }
    (y, x)
}

/// Heteroscedasticity-consistent (sandwich) covariance of the scaled estimates:
/// `G^-1 (sum_r s_r^2 z_r z_r') G^-T` with `G = Z'X` (`Z = X` for least squares), each
/// frequency point's variance its own squared residual (real and imaginary parts pooled) times
/// the small-sample factor `n/(n - p)`. The equation error's variance changes with frequency
/// (turbulence and sensor noise are coloured, and the derivative's transform weights noise by
/// `w`), so one pooled variance would misstate the errors.
fn sandwich(
    z_rows: &DMatrix<f64>,
    xs: &DMatrix<f64>,
    resid: &DVector<f64>,
    dof: usize,
) -> Result<DMatrix<f64>, Failure> {
    let (rows, p) = xs.shape();
    let m = rows / 2;
    let g_inv = (z_rows.transpose() * xs)
        .try_inverse()
        .ok_or(Failure::NotInvertible)?;
    let small_sample = rows as f64 / dof as f64;
    let mut meat = DMatrix::zeros(p, p);
    for k in 0..m {
        let s2k = 0.5 * (resid[2 * k].powi(2) + resid[2 * k + 1].powi(2)) * small_sample;
        for r in [2 * k, 2 * k + 1] {
            for b in 0..p {
                for a in 0..p {
                    meat[(a, b)] += z_rows[(r, a)] * z_rows[(r, b)] * s2k;
                }
            }
        }
    }
    Ok(&g_inv * meat * g_inv.transpose())
}

/// The scaled instrument matrix, built like the regressors.
fn instruments(
    z_ft: &[Vec<C>],
    cols: &[usize],
    scales: &[f64],
    m: usize,
    p: usize,
) -> DMatrix<f64> {
    let mut zs = DMatrix::zeros(2 * m, p);
    for k in 0..m {
        for (c, &j) in cols.iter().enumerate() {
            zs[(2 * k, c)] = z_ft[j][k].re / scales[c];
            zs[(2 * k + 1, c)] = z_ft[j][k].im / scales[c];
        }
    }
    zs
}

/// Instrument transforms: for every stacked (segment, frequency) point, the states' response
/// `(i w I - a)^-1 b U` to the controls' transforms (`var_ft`'s first `n` are the states, the
/// rest the controls); the controls themselves follow unchanged.
pub fn state_instruments(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    omegas: &[f64],
    var_ft: &[Vec<C>],
    n: usize,
) -> Vec<Vec<C>> {
    let points = var_ft.first().map_or(0, Vec::len);
    let m = var_ft.len() - n;
    let mut out: Vec<Vec<C>> = vec![Vec::with_capacity(points); n];
    for idx in 0..points {
        let w = omegas[idx];
        let sys = DMatrix::from_fn(n, n, |i, j| {
            C::new(-a[(i, j)], if i == j { w } else { 0.0 })
        });
        let rhs = DMatrix::from_fn(n, 1, |i, _| {
            (0..m)
                .map(|k| C::new(b[(i, k)], 0.0) * var_ft[n + k][idx])
                .sum::<C>()
        });
        let z = sys.lu().solve(&rhs).unwrap_or_else(|| DMatrix::zeros(n, 1));
        for i in 0..n {
            out[i].push(z[(i, 0)]);
        }
    }
    out.extend(var_ft[n..].iter().cloned());
    out
}
