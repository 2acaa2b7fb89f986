//! Responses from a spectral matrix, and the windows composited per frequency.
//!
//! **Responses** (Bendat and Piersol 2010, ch. 6 and 7). With inputs `x_1..x_q` and the
//! output `y` last in the spectral matrix `G`, the conditioned responses are
//! `H = G_xx^-1 G_xy`; the residual (noise) spectrum is `G_nn = G_yy - G_xy^H G_xx^-1 G_xy` and
//! the multiple coherence `1 - G_nn / G_yy`. Input `i`'s partial coherence is
//! `1 - G_nn / G_yy.(others)`, with `G_yy.(others)` the output's residual on the other inputs
//! alone; with one input it is the ordinary coherence `|G_xy|^2 / (G_xx G_yy)`.
//!
//! **Random error** (Bendat and Piersol 2010, ch. 9; Tischler and Remple 2012, ch. 7 give the
//! same form): the normalised random error of `|H_i|`, which is also the standard deviation of
//! its phase in radians, `e = sqrt(1 - g^2) / (|g| sqrt(2 n))`, `g^2` input `i`'s partial
//! coherence. The books' `n` is the number of averages, a large-sample form; here `n` is the
//! degrees of freedom the fit leaves, the equivalent number of independent averages less the
//! `q` responses fitted (`(1 - g^2) G_yy` is the mean square of the segments' residuals, whose
//! mean is `(n_d - q) / n_d` of the noise's: with `n_d - q` the variance estimate is
//! unbiased). The 95 % interval is `t e`, `t` Student's 97.5 % quantile with `2 (n_d - q)`
//! degrees of freedom: given the inputs, each component (the log magnitude's and the phase's)
//! of a least-squares fit's error over `n_d - q` complex residuals has that distribution
//! (ordinary linear-regression theory; Bendat and Piersol state the joint region with the F
//! distribution). With 1.96 instead, the coverage test found 0.89 for 40 s windows on a 120 s
//! record (five segments) and 0.91 for the composite.
//!
//! **Composite** (after CIFER's composite windowing, Tischler and Remple 2012, ch. 8): at each
//! frequency the windows' averaged spectral matrices are combined, `G_c = sum_i a_i G_i`,
//! `a_i >= 0`, `sum a_i = 1`, with the weights that minimise the variance of the response,
//! `a' C a`, `C_ij = e_i e_j rho_ij`: `e_i` window `i`'s random error and `rho_ij` the
//! correlation of the two windows' averages ([`super::spectra::averages_covariance`]: the
//! windows cut the same data, so their estimates are far from independent). A window enters
//! only at frequencies with at least [`MIN_CYCLES`] periods in it. The composite's equivalent
//! number of averages is `1 / (a' R a)`; its response, coherences and random error follow from
//! `G_c` as above.
//!
//! CIFER weights each window by its own random error, from its own coherence. Tried here, that
//! understated the composite's error: the windows whose coherence came out high by chance got
//! the weight, and the stated 95 % interval held 0.939-0.944 of 6000 checks (test
//! `the_random_error_holds_at_its_stated_rate`, 50 % overlap). The windows' errors are
//! therefore taken at a coherence they share, `e_i` proportional to `1 / sqrt(n_i - q)` (the
//! shared coherence cancels from the weights): the weights follow from the windows' averages
//! and shared data alone, and the interval holds 0.947-0.954 (50 %) and 0.953-0.954 (80 %).

use nalgebra::{Complex, DMatrix, DVector};
use rustfft::num_complex::Complex64 as C;

/// Fewest periods of a frequency in a window for that window's estimate to be used. The Hann
/// window's main lobe spans `f (1 +- 2 / k)` at `k` periods, and the estimate there is the
/// response smoothed over that span, weighted by the input's power; the random error says
/// nothing of that bias. Found with the known-answer test
/// (`a_linear_models_record_gives_its_analytic_response`: seed 002's VPM M16, whose phugoid is
/// at 0.021 Hz, through an exponential sweep): at two periods (the lobe reaching zero
/// frequency) 40 s windows were 1.4 dB off at 0.05 Hz with coherence 0.998; at four, 60 s
/// windows 0.42 dB and 2.9 deg off at 0.067 Hz with coherence 1.000; at five, the band up to
/// 3 Hz within 0.37 dB and 2.5 deg (all at 50 % overlap; 0.27 dB and 1.5 deg at 80 %).
pub const MIN_CYCLES: f64 = 5.0;

/// A conditioned input whose spectrum is less than this fraction of its own once the other
/// inputs are conditioned out (`1 - ` its multiple coherence with them) cannot be told apart
/// from them at that frequency: double precision leaves about 1e-16 of a spectrum, and a
/// response solved through such a matrix has lost ten of its sixteen digits.
pub const SEPARABLE_FRACTION: f64 = 1e-10;

/// The responses solved from one spectral matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct Solved {
    /// Each input's conditioned response.
    pub response: Vec<C>,
    /// Each input's partial coherence (ordinary with one input), in `[0, 1]`.
    pub coherence: Vec<f64>,
    pub multiple_coherence: f64,
}

fn block(g: &[C], p: usize, rows: &[usize], cols: &[usize]) -> DMatrix<Complex<f64>> {
    DMatrix::from_fn(rows.len(), cols.len(), |i, j| {
        let v = g[rows[i] * p + cols[j]];
        Complex::new(v.re, v.im)
    })
}

/// The output's residual spectrum on the inputs `set` and their responses; None when the
/// inputs' matrix is not positive definite or an input is not separable from the others.
fn residual(g: &[C], p: usize, set: &[usize]) -> Option<(f64, Vec<C>)> {
    let y = p - 1;
    let gyy = g[y * p + y].re;
    if set.is_empty() {
        return Some((gyy, Vec::new()));
    }
    let gxx = block(g, p, set, set);
    let gxy = block(g, p, set, &[y]);
    let chol = gxx.clone().cholesky()?;
    let h = chol.solve(&gxy);
    let inv = chol.inverse();
    for (k, &i) in set.iter().enumerate() {
        let conditioned = 1.0 / inv[(k, k)].re;
        let own = g[i * p + i].re;
        if !(conditioned.is_finite() && conditioned > SEPARABLE_FRACTION * own) {
            return None;
        }
    }
    let explained: f64 = (0..set.len()).map(|k| (gxy[k].conj() * h[k]).re).sum();
    let h: Vec<C> = h.iter().map(|v| C::new(v.re, v.im)).collect();
    if !h.iter().all(|v| v.re.is_finite() && v.im.is_finite()) {
        return None;
    }
    Some(((gyy - explained).max(0.0), h))
}

/// Solves a `p x p` spectral matrix (inputs first, the output last) for every input's
/// conditioned response and coherence. None where the inputs carry no separable power.
pub fn solve(g: &[C], p: usize) -> Option<Solved> {
    let q = p.checked_sub(1).filter(|q| *q > 0)?;
    if g.len() != p * p || !g.iter().all(|v| v.re.is_finite() && v.im.is_finite()) {
        return None;
    }
    let all: Vec<usize> = (0..q).collect();
    let (noise, response) = residual(g, p, &all)?;
    let gyy = g[(p - 1) * p + p - 1].re;
    let ratio = |num: f64, den: f64| {
        if den > 0.0 {
            (1.0 - num / den).clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    let coherence = (0..q)
        .map(|i| {
            let others: Vec<usize> = all.iter().copied().filter(|&k| k != i).collect();
            residual(g, p, &others).map_or(0.0, |(without, _)| ratio(noise, without))
        })
        .collect();
    Some(Solved {
        response,
        coherence,
        multiple_coherence: ratio(noise, gyy),
    })
}

/// The normalised random error of `|H|` (and the phase's standard deviation, rad) from a
/// coherence and the degrees of freedom left (averages less responses fitted); None where it
/// is unbounded (no coherence, no degrees of freedom).
pub fn random_error(coherence: f64, dof: f64) -> Option<f64> {
    (coherence > 0.0 && coherence.is_finite() && dof > 0.0)
        .then(|| ((1.0 - coherence.min(1.0)) / (2.0 * dof * coherence)).sqrt())
}

/// The half-width of the 95 % interval of the log magnitude and of the phase (rad): Student's
/// 97.5 % quantile with `2 dof` degrees of freedom times the random error.
pub fn interval_95(random_error: Option<f64>, dof: f64) -> Option<f64> {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    let e = random_error?;
    // The upper 2.5 % point: a two-sided 95 % interval.
    let t = StudentsT::new(0.0, 1.0, 2.0 * dof).ok()?.inverse_cdf(0.975);
    (t.is_finite() && t > 0.0).then_some(t * e)
}

/// The composite's weights over the windows `cand` (indices into `r`, with their random errors
/// `eps`, infinite for a window with no estimate): the non-negative weights summing to one
/// that minimise `a' C a`, by trying every subset's unconstrained optimum (a handful of
/// windows: at most `2^w - 1` small solves) and keeping the best whose weights are all
/// positive (the constrained optimum is one of them). Returns one weight per entry of `cand`.
pub fn weights(cand: &[usize], eps: &[f64], r: &DMatrix<f64>) -> Vec<f64> {
    let w = cand.len();
    let finite: Vec<bool> = eps.iter().map(|e| e.is_finite() && *e > 0.0).collect();
    // No window with a finite error (no coherence anywhere): the spectra's own variance.
    let e: Vec<f64> = if finite.iter().any(|f| *f) {
        eps.to_vec()
    } else {
        vec![1.0; w]
    };
    let usable: Vec<bool> = e.iter().map(|e| e.is_finite() && *e > 0.0).collect();
    let cov = |a: usize, b: usize| {
        let (i, j) = (cand[a], cand[b]);
        e[a] * e[b] * r[(i, j)] / (r[(i, i)] * r[(j, j)]).sqrt()
    };
    let mut best: Option<(f64, Vec<f64>)> = None;
    for mask in 1u32..(1u32 << w.min(16)) {
        let set: Vec<usize> = (0..w).filter(|k| mask & (1 << k) != 0).collect();
        if set.iter().any(|&k| !usable[k]) {
            continue;
        }
        let m = DMatrix::from_fn(set.len(), set.len(), |a, b| cov(set[a], set[b]));
        let Some(a) = m.lu().solve(&DVector::from_element(set.len(), 1.0)) else {
            continue;
        };
        let total: f64 = a.iter().sum();
        if !(total > 0.0 && a.iter().all(|v| *v > 0.0 && v.is_finite())) {
            continue;
        }
        let variance = 1.0 / total;
        if best.as_ref().is_none_or(|(v, _)| variance < *v) {
            let mut out = vec![0.0; w];
            for (k, &s) in set.iter().enumerate() {
                out[s] = a[k] / total;
            }
            best = Some((variance, out));
        }
    }
    best.map_or_else(|| vec![1.0 / w.max(1) as f64; w], |(_, a)| a)
}

/// The equivalent number of independent averages of the combination `a` of the windows
/// `cand`: `1 / (a' R a)`.
pub fn equivalent_averages(cand: &[usize], a: &[f64], r: &DMatrix<f64>) -> f64 {
    let mut v = 0.0;
    for (x, &i) in cand.iter().enumerate() {
        for (y, &j) in cand.iter().enumerate() {
            v += a[x] * a[y] * r[(i, j)];
        }
    }
    if v > 0.0 { 1.0 / v } else { 0.0 }
}
