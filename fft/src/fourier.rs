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

use crate::plans;
use rustfft::Fft;
use rustfft::num_complex::Complex64 as C;
use std::sync::Arc;

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
    fwd: Arc<dyn Fft<f64>>,
    inv: Arc<dyn Fft<f64>>,
}

impl ChirpZ {
    /// A transform of `n` samples at step `dt` to the `m` frequencies `w0 + k dw` (rad/s).
    pub fn new(n: usize, dt: f64, w0: f64, dw: f64, m: usize) -> Self {
        let l = (n + m).saturating_sub(1).max(1).next_power_of_two();
        let (th0, phi) = (w0 * dt, dw * dt);
        // `chirp(k)` for every k either side needs, computed once.
        let chirp: Vec<C> = (0..m.max(n))
            .map(|k| C::from_polar(1.0, -phi * (k as f64) * (k as f64) / 2.0))
            .collect();
        let (fwd, inv) = plans(l);
        let mut kernel = vec![C::new(0.0, 0.0); l];
        for k in 0..m.max(n) {
            if k < m {
                kernel[k] = chirp[k].conj();
            }
            if k > 0 && k < n {
                kernel[l - k] = chirp[k].conj();
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
                .map(|k| C::from_polar(1.0, -th0 * k as f64) * chirp[k])
                .collect(),
            kernel,
            post: chirp[..m].to_vec(),
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
        BUFFERS.with_borrow_mut(|(y, scratch)| {
            // The signal, premultiplied, then zeros to the FFT's length.
            y.clear();
            y.extend(self.pre.iter().zip(x).map(|(a, &v)| a * v));
            y.resize(self.kernel.len(), C::new(0.0, 0.0));
            let need = self
                .fwd
                .get_inplace_scratch_len()
                .max(self.inv.get_inplace_scratch_len());
            if scratch.len() < need {
                scratch.resize(need, C::new(0.0, 0.0));
            }
            self.fwd.process_with_scratch(y, &mut scratch[..need]);
            for (a, b) in y.iter_mut().zip(&self.kernel) {
                *a *= b;
            }
            self.inv.process_with_scratch(y, &mut scratch[..need]);
            (0..m)
                .map(|k| {
                    let sum = y[k] * self.post[k];
                    let last = self.end[k] * x[n - 1];
                    (sum - (last + x[0]) * 0.5) * self.dt
                })
                .collect()
        })
    }
}

thread_local! {
    /// [`ChirpZ::apply`]'s work buffer and the FFTs' scratch, kept between calls on a thread
    /// (a transform is two FFTs of a few ten thousand points; allocating and zeroing their
    /// buffers each time was a tenth of an identification's instructions).
    static BUFFERS: std::cell::RefCell<(Vec<C>, Vec<C>)> = const {
        std::cell::RefCell::new((Vec::new(), Vec::new()))
    };
}
