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
