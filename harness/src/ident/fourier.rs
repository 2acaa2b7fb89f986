//! Fourier transforms of sampled signals at chosen frequencies.
//!
//! The transform is the finite Fourier integral `X(w) = integral_0^T x(t) exp(-i w t) dt`
//! (seed 000 Eq. 7 is its rectangle-rule form), evaluated by the trapezoidal rule, which is
//! second-order accurate for smooth signals. Frequencies are in rad/s; nothing is normalised
//! beyond the factor `dt`.
//!
//! Two evaluations give the same numbers: a direct sum at any list of frequencies (a phasor
//! recurrence, re-seeded every 256 samples against drift) and a chirp-z transform on rustfft
//! for evenly spaced frequencies (Bluestein's algorithm), which the tests check against it.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex64 as C;
use std::f64::consts::PI;

/// Trapezoidal finite Fourier integral of `x` (sampled at `dt`, from `t = 0`) at each `w`.
pub fn transform(x: &[f64], dt: f64, omegas: &[f64]) -> Vec<C> {
    let n = x.len();
    omegas
        .iter()
        .map(|&w| {
            if n == 0 {
                return C::new(0.0, 0.0);
            }
            let step = C::from_polar(1.0, -w * dt);
            let mut phasor = C::new(1.0, 0.0);
            let mut sum = C::new(0.0, 0.0);
            for (k, &v) in x.iter().enumerate() {
                if k % 256 == 0 {
                    phasor = C::from_polar(1.0, -w * dt * k as f64);
                }
                sum += phasor * v;
                phasor *= step;
            }
            let last = C::from_polar(1.0, -w * dt * (n - 1) as f64) * x[n - 1];
            (sum - (last + x[0]) * 0.5) * dt
        })
        .collect()
}

/// The same transform at `m` evenly spaced frequencies `w0 + k dw`, by chirp-z.
pub fn transform_uniform(x: &[f64], dt: f64, w0: f64, dw: f64, m: usize) -> Vec<C> {
    ChirpZ::new(x.len(), dt, w0, dw, m).apply(x)
}

/// A chirp-z transform prepared for signals of one length, step and set of frequencies: the
/// FFT plans, the chirps and the transformed kernel are computed once, so each further signal
/// costs two FFTs and no trigonometry (an identification transforms a dozen signals per
/// segment on the same grid).
pub struct ChirpZ {
    n: usize,
    dt: f64,
    w0: f64,
    dw: f64,
    /// `exp(-i th0 k) chirp(k)` for the samples, `k < n`.
    pre: Vec<C>,
    /// The FFT of the conjugate chirp, over the FFT's length (the inverse's normalisation).
    kernel: Vec<C>,
    /// `chirp(k)` for the outputs, `k < m`.
    post: Vec<C>,
    /// `exp(-i w_k (n - 1) dt)`: the trapezoidal rule's end correction at each frequency.
    end: Vec<C>,
    fwd: std::sync::Arc<dyn rustfft::Fft<f64>>,
    inv: std::sync::Arc<dyn rustfft::Fft<f64>>,
}

impl ChirpZ {
    /// A transform of `n` samples at step `dt` to the `m` frequencies `w0 + k dw` (rad/s).
    pub fn new(n: usize, dt: f64, w0: f64, dw: f64, m: usize) -> Self {
        let l = (n + m).saturating_sub(1).max(1).next_power_of_two();
        let (th0, phi) = (w0 * dt, dw * dt);
        let chirp = |k: usize| C::from_polar(1.0, -phi * (k as f64) * (k as f64) / 2.0);
        let mut planner = FftPlanner::new();
        let (fwd, inv) = (planner.plan_fft_forward(l), planner.plan_fft_inverse(l));
        let mut kernel = vec![C::new(0.0, 0.0); l];
        for k in 0..m.max(n) {
            if k < m {
                kernel[k] = chirp(k).conj();
            }
            if k > 0 && k < n {
                kernel[l - k] = chirp(k).conj();
            }
        }
        fwd.process(&mut kernel);
        for v in &mut kernel {
            *v /= l as f64;
        }
        let last = n.saturating_sub(1) as f64;
        Self {
            n,
            dt,
            w0,
            dw,
            pre: (0..n)
                .map(|k| C::from_polar(1.0, -th0 * k as f64) * chirp(k))
                .collect(),
            kernel,
            post: (0..m).map(chirp).collect(),
            end: (0..m)
                .map(|k| C::from_polar(1.0, -(w0 + k as f64 * dw) * dt * last))
                .collect(),
            fwd,
            inv,
        }
    }

    /// The number of samples this transform takes.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether it takes no samples.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The transform of `x`; a signal of another length gets a transform prepared for it.
    pub fn apply(&self, x: &[f64]) -> Vec<C> {
        let m = self.post.len();
        if x.len() != self.n {
            return Self::new(x.len(), self.dt, self.w0, self.dw, m).apply(x);
        }
        let n = self.n;
        if n == 0 || m == 0 {
            return vec![C::new(0.0, 0.0); m];
        }
        let mut y = vec![C::new(0.0, 0.0); self.kernel.len()];
        for (k, (a, &v)) in self.pre.iter().zip(x).enumerate() {
            y[k] = a * v;
        }
        self.fwd.process(&mut y);
        for (a, b) in y.iter_mut().zip(&self.kernel) {
            *a *= b;
        }
        self.inv.process(&mut y);
        (0..m)
            .map(|k| {
                let sum = y[k] * self.post[k];
                let last = self.end[k] * x[n - 1];
                (sum - (last + x[0]) * 0.5) * self.dt
            })
            .collect()
    }
}

/// A Hann taper over `n` samples and its time derivative (per second) at step `dt`.
pub fn hann(n: usize, dt: f64) -> (Vec<f64>, Vec<f64>) {
    let t = (n.max(2) - 1) as f64 * dt;
    let w = (0..n)
        .map(|k| 0.5 - 0.5 * (2.0 * PI * k as f64 * dt / t).cos())
        .collect();
    let dw = (0..n)
        .map(|k| PI / t * (2.0 * PI * k as f64 * dt / t).sin())
        .collect();
    (w, dw)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direct_transform_matches_an_analytic_pair() {
        // x(t) = exp(-a t) on [0, T]: X(w) = (1 - exp(-(a + i w) T)) / (a + i w).
        let (a, dt, n) = (0.7, 0.01, 4001);
        let x: Vec<f64> = (0..n).map(|k| (-a * k as f64 * dt).exp()).collect();
        let t = (n - 1) as f64 * dt;
        for w in [0.1, 1.0, 5.0] {
            let s = C::new(a, w);
            let exact = (C::new(1.0, 0.0) - (-s * t).exp()) / s;
            let got = transform(&x, dt, &[w])[0];
            // The trapezoidal rule's error is about dt^2 |f'(T) - f'(0)| / 12, here
            // dt^2 |s| / 12 against |X| ~ 1 / |s|: relative dt^2 |s|^2 / 12. Allow twice that.
            let bound = dt * dt * s.norm_sqr() / 6.0;
            assert!(
                (got - exact).norm() < bound * exact.norm(),
                "w {w}: {got} vs {exact}"
            );
        }
    }

    #[test]
    fn chirp_z_equals_the_direct_sum() {
        let x: Vec<f64> = (0..3000)
            .map(|k| ((k as f64) * 0.013).sin() * (1.0 + 0.001 * k as f64))
            .collect();
        let (w0, dw, m) = (0.3, 0.05, 200);
        let fast = transform_uniform(&x, 0.01, w0, dw, m);
        let omegas: Vec<f64> = (0..m).map(|k| w0 + k as f64 * dw).collect();
        let slow = transform(&x, 0.01, &omegas);
        for (a, b) in fast.iter().zip(&slow) {
            assert!((a - b).norm() < 1e-9 * (1.0 + b.norm()), "{a} vs {b}");
        }
    }

    #[test]
    fn a_prepared_chirp_z_serves_many_signals_and_other_lengths() {
        let (w0, dw, m, dt) = (0.2, 0.04, 120, 0.01);
        let plan = ChirpZ::new(2000, dt, w0, dw, m);
        let omegas: Vec<f64> = (0..m).map(|k| w0 + k as f64 * dw).collect();
        for (n, f) in [(2000usize, 0.011), (2000, 0.027), (1500, 0.019)] {
            let x: Vec<f64> = (0..n).map(|k| (k as f64 * f).cos() + 0.3).collect();
            let fast = plan.apply(&x);
            let slow = transform(&x, dt, &omegas);
            assert_eq!(fast.len(), m);
            for (a, b) in fast.iter().zip(&slow) {
                assert!(
                    (a - b).norm() < 1e-9 * (1.0 + b.norm()),
                    "n {n}: {a} vs {b}"
                );
            }
        }
        assert_eq!(plan.len(), 2000);
        assert!(
            ChirpZ::new(0, dt, w0, dw, m)
                .apply(&[])
                .iter()
                .all(|c| c.norm() == 0.0)
        );
    }

    #[test]
    fn hann_derivative_is_consistent() {
        let (w, dw) = hann(1001, 0.01);
        for k in 1..1000 {
            let fd = (w[k + 1] - w[k - 1]) / 0.02;
            assert!((fd - dw[k]).abs() < 1e-3);
        }
        assert_eq!(w[0], 0.0);
    }
}
