//! The identification's numerical kernels: the FFTs it takes ([`plans`]), planned once per
//! process, the Hann taper ([`hann`]), Welch's averaged spectra ([`spectra`]), the finite
//! Fourier transforms of the equation-error estimator ([`fourier`]) and its regression's
//! arithmetic ([`regression`]).
//!
//! A crate of its own for the build, not for the numbers: rustfft's algorithms are generic
//! over the scalar, so their code is generated in the crate that plans an `f64` transform, at
//! that crate's optimisation level. Planned in the harness, they were built at the harness's
//! level; planned here, they are built at this crate's (`opt-level = 2` in test builds, the
//! workspace's `Cargo.toml`), and the harness can be built unoptimised in test builds, a cold
//! `cargo test`'s largest cost. The spectra's loops (complex products over frequencies,
//! segments and signals, through iterator adaptors and nalgebra's indexing) are here for the
//! same reason: unoptimised in the harness they were most of its frequency-response tests'
//! time; so are the chirp-z transforms and the regression's solution and sandwich covariance
//! (nalgebra's SVD and products, generated where they are called), most of the equation-error
//! tests' time. Release builds optimise every crate alike, so there the crate changes nothing.

pub mod fourier;
pub mod regression;
pub mod spectra;

use rustfft::{Fft, FftPlanner};
use std::sync::{Arc, Mutex, OnceLock};

/// The forward and inverse FFTs of length `l`, planned once per process: the planner keeps
/// what it has planned (its twiddle factors were a twelfth of an identification's
/// instructions when each transform planned its own).
pub fn plans(l: usize) -> (Arc<dyn Fft<f64>>, Arc<dyn Fft<f64>>) {
    static PLANNER: OnceLock<Mutex<FftPlanner<f64>>> = OnceLock::new();
    let mut planner = PLANNER
        .get_or_init(|| Mutex::new(FftPlanner::new()))
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    (planner.plan_fft_forward(l), planner.plan_fft_inverse(l))
}

/// A Hann taper over `n` samples and its time derivative (per second) at step `dt`.
pub fn hann(n: usize, dt: f64) -> (Vec<f64>, Vec<f64>) {
    use std::f64::consts::PI;
    let t = (n.max(2) - 1) as f64 * dt;
    let w = (0..n)
        .map(|k| 0.5 - 0.5 * (2.0 * PI * k as f64 * dt / t).cos())
        .collect();
    let dw = (0..n)
        .map(|k| PI / t * (2.0 * PI * k as f64 * dt / t).sin())
        .collect();
    (w, dw)
}
