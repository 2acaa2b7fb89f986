//! The FFTs cierva's identification takes ([`plans`]), planned once per process.
//!
//! A crate of its own for the build, not for the numbers: rustfft's algorithms are generic
//! over the scalar, so their code is generated in the crate that plans an `f64` transform, at
//! that crate's optimisation level. Planned in the harness, they were built at the harness's
//! level; planned here, they are built at this crate's (`opt-level = 2` in test builds, the
//! workspace's `Cargo.toml`), and the harness can be built unoptimised in test builds, a cold
//! `cargo test`'s largest cost. Release builds optimise every crate alike, so there the crate
//! changes nothing.

use rustfft::{Fft, FftPlanner};
use std::sync::{Arc, Mutex, OnceLock};

pub use rustfft::num_complex::Complex64;

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

#[cfg(test)]
mod tests {
    use super::*;

    /// A transform and its inverse return the signal times its length, and a unit impulse's
    /// transform is flat, at a length with every kind of factor rustfft plans (2, 3, 5, 7).
    #[test]
    fn a_round_trip_returns_the_signal() {
        let l = 2 * 3 * 5 * 7 * 4;
        let (f, i) = plans(l);
        let x: Vec<Complex64> = (0..l)
            .map(|k| Complex64::new((k as f64 * 0.37).sin(), (k as f64 * 0.11).cos()))
            .collect();
        let mut y = x.clone();
        f.process(&mut y);
        i.process(&mut y);
        let worst = (x.iter().zip(&y))
            .map(|(a, b)| (a - b / l as f64).norm())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "round trip off by {worst}");
        let mut impulse = vec![Complex64::new(0.0, 0.0); l];
        impulse[0] = Complex64::new(1.0, 0.0);
        f.process(&mut impulse);
        assert!(
            impulse
                .iter()
                .all(|c| (c - Complex64::new(1.0, 0.0)).norm() < 1e-12)
        );
    }
}
