//! Responses estimated against a recorded excitation: the indirect (instrumental) estimator of
//! closed-loop identification.
//!
//! Under a pilot's or a controller's feedback the controls answer the disturbance, so the
//! response estimated from a control's spectra (`G_uu^-1 G_uy`, the direct estimator) is biased
//! wherever the loop is active: the control carries a part correlated with the output's noise.
//! When the excitation `r` added to the control is recorded, it is independent of the
//! disturbance, and the response is the ratio of the two responses to it,
//! `H = G_ry / G_ru` (with several excitations, `G_RU^-1 G_Ry`): consistent whatever the loop
//! (Schoukens, Pintelon and Rolain, *Mastering System Identification in 100 Exercises*, 2012,
//! ch. 3, exercises 49-50, the indirect method `S_YR / S_UR`; Tischler and Remple, *Aircraft and
//! Rotorcraft System Identification*, 2nd ed., 2012, ch. 8, on feedback's bias "the same
//! considerations also apply to piloted feedback").
//!
//! # Its random error
//! With `res = y - U h` what the controls do not explain (independent of the excitations), the
//! estimate's error is `G_RU^-1 G_R,res`, and the averaged cross-spectrum `G_R,res` of `n_d`
//! independent averages has covariance `G_RR G_res / n_d` (Bendat and Piersol, *Random Data*,
//! 4th ed., 2010, ch. 9, for the cross-spectrum of two independent Gaussian signals). So the
//! error of input `i`'s response has variance `K_ii G_res / n_d`, `K = G_RU^-1 G_RR G_RU^-H`,
//! half of it in each of its real and imaginary parts. With one excitation `K = 1 / (g2_ru
//! G_uu)`: the direct estimator's variance in open loop (`G_res / (G_uu n_d)`) over the
//! coherence of the control with its excitation, which is 1 when the control is its
//! excitation. The test
//! `a_recorded_excitation_gives_closed_loop_responses_that_hold_their_errors` holds the
//! stated errors at their rate on a known closed loop, where the direct estimator misses.

use nalgebra::DMatrix;
use rustfft::num_complex::Complex64 as C;

/// One frequency's estimate against `e` recorded excitations, from the spectra of the
/// signals `(R_1..R_e, U_1..U_e, O_1..O_m, y)`: the excitations, the controls they are added
/// to, other recorded controls, and the output.
#[derive(Debug, Clone, PartialEq)]
pub struct Referenced {
    /// Each excited control's response as flown (`G_RU^-1 G_Ry`): the other controls are not
    /// regressed on, so their part of the output travels with the control that moved them.
    pub response: Vec<C>,
    /// Each other control's transfer from each excited one, `[i][j]` (`G_RU^-1 G_RO`).
    pub transfers: Vec<Vec<C>>,
    /// The spectra of the other controls and the output less their parts through the excited
    /// controls (`o_j - sum_i u_i T_ij`, then `y - sum_i u_i h_i`), row-major: the form
    /// [`crate::fit::retune::responses::residual_standard_error`] takes.
    pub unexplained: Vec<C>,
    /// `K_ii = [G_RU^-1 G_RR G_RU^-H]_ii` per excited control: its response's error variance
    /// per unit of what the controls leave unexplained and per average.
    pub variance_factor: Vec<f64>,
    /// Per excited control, the coherence that gives the estimate's random error by the
    /// ordinary formula (`e_r = sqrt((1 - g2) / (2 n_d g2))`): `|h|^2 / (|h|^2 + K_ii G_res)`,
    /// the ordinary coherence when the control is its excitation. Not the output's multiple
    /// coherence with the excitations: pooled over records that each excite one control, that
    /// is high wherever any control explains the output, and admitted frequencies where the
    /// control at hand explains little.
    pub coherence: Vec<f64>,
}

impl Referenced {
    /// The normalised random error of input `i`'s response (the standard deviation of its real
    /// or imaginary part over `|h|`, as [`super::composite::random_error`]'s), with `dof` degrees of
    /// freedom (the composite's averages less the excitations).
    pub fn random_error(&self, i: usize, dof: f64) -> Option<f64> {
        let h = self.response.get(i)?.norm();
        let gain = *self.variance_factor.get(i)?;
        let g_aa = self.unexplained.last()?.re;
        (dof > 0.0 && h > 0.0 && g_aa >= 0.0 && gain > 0.0)
            .then(|| (gain * g_aa / (2.0 * dof)).sqrt() / h)
            .filter(|v| v.is_finite())
    }
}

/// The estimate at one frequency from the composite's spectra `g` (`p x p` row-major,
/// `G_ab = E[X_a* X_b]`, `p = 2 e + m + 1`); None where the excitations do not determine the
/// controls (`G_RU` singular) or the spectra are not finite.
pub fn referenced(g: &[C], e: usize, m: usize) -> Option<Referenced> {
    let p = 2 * e + m + 1;
    if e == 0 || g.len() != p * p || !g.iter().all(|v| v.re.is_finite() && v.im.is_finite()) {
        return None;
    }
    let at = |a: usize, b: usize| g[a * p + b];
    let (r0, u0, o0, y) = (0, e, 2 * e, p - 1);
    let g_ru = DMatrix::from_fn(e, e, |a, i| at(r0 + a, u0 + i));
    let g_rr = DMatrix::from_fn(e, e, |a, b| at(r0 + a, r0 + b));
    let inv = g_ru.try_inverse()?;
    let h = &inv * DMatrix::from_fn(e, 1, |a, _| at(r0 + a, y));
    let t = &inv * DMatrix::from_fn(e, m, |a, j| at(r0 + a, o0 + j));
    let k = &inv * &g_rr * inv.adjoint();
    // Each derived signal as coefficients over the p signals: w_j = o_j - sum_i u_i T_ij,
    // a = y - sum_i u_i h_i.
    let zero = C::new(0.0, 0.0);
    let mut rows: Vec<Vec<C>> = Vec::with_capacity(m + 1);
    for j in 0..m {
        let mut c = vec![zero; p];
        c[o0 + j] = C::new(1.0, 0.0);
        for i in 0..e {
            c[u0 + i] = -t[(i, j)];
        }
        rows.push(c);
    }
    let mut c = vec![zero; p];
    c[y] = C::new(1.0, 0.0);
    for i in 0..e {
        c[u0 + i] = -h[(i, 0)];
    }
    rows.push(c);
    // `C^H G C`, C's columns the rows above.
    let mut unexplained = Vec::with_capacity((m + 1) * (m + 1));
    for a in &rows {
        for b in &rows {
            let mut v = zero;
            for (s, a_s) in a.iter().enumerate().filter(|(_, a_s)| **a_s != zero) {
                for (col, b_t) in b.iter().enumerate() {
                    v += a_s.conj() * b_t * at(s, col);
                }
            }
            unexplained.push(v);
        }
    }
    let g_aa = unexplained[(m + 1) * (m + 1) - 1].re;
    let out = Referenced {
        response: (0..e).map(|i| h[(i, 0)]).collect(),
        transfers: (0..e)
            .map(|i| (0..m).map(|j| t[(i, j)]).collect())
            .collect(),
        unexplained,
        variance_factor: (0..e).map(|i| k[(i, i)].re).collect(),
        coherence: (0..e)
            .map(|i| {
                let h2 = h[(i, 0)].norm_sqr();
                let noise = k[(i, i)].re * g_aa;
                if h2 > 0.0 && noise >= 0.0 {
                    h2 / (h2 + noise)
                } else {
                    0.0
                }
            })
            .collect(),
    };
    out.response
        .iter()
        .all(|v| v.re.is_finite() && v.im.is_finite())
        .then_some(out)
}
