//! # cierva-model
//!
//! The flight-dynamics side of cierva: linear-model analysis now (modes, BCAR Section T,
//! weakly coupled systems with the rotorspeed degree of freedom, root loci); the nonlinear
//! individual-blade rotorcraft model, trim and linearisation are to come (see the issues).
//!
//! This crate does no I/O and knows nothing about case files: it takes numbers and returns
//! numbers, statuses and errors. It never panics on data.
//!
//! ## Conventions
//! * **Axes.** Body axes with the origin at the centre of mass: x forward along the keel,
//!   y to starboard, z down (right-handed), as in seeds 000-002. Velocities `u, v, w` (m/s),
//!   rates `p, q, r` (rad/s), Euler attitudes `phi, theta, psi` (rad), rotorspeed `Omega`
//!   (rad/s).
//! * **Derivatives.** Accelerations per unit perturbation, named `<force>_<variable>`:
//!   `X, Y, Z` act on `u, v, w`; `L, M, N` on `p, q, r`; `Q` on `Omega` (rotor torque divided
//!   by rotor inertia). So `X_u` is in 1/s, `M_w` in 1/(m s), `Q_u` in rad/(m s) and `Q_Omega`
//!   in 1/s. Control columns use the control's name (`M_eta_s`).
//! * **Controls.** `eta_s` longitudinal, `eta_c` lateral (stick or shaft tilt, units as the
//!   source states them), `theta_0` collective.
//! * **Signs.** A positive real part is an unstable mode. Oscillatory modes are reported once,
//!   by the member of the conjugate pair with positive imaginary part.
//! * **Azimuth** (for the rotor model, when it lands): zero downstream (blade over the tail),
//!   increasing in the direction of rotation.

pub mod bcar;
pub mod linear;
pub mod locus;
pub mod milne;
pub mod modes;
#[cfg(test)]
pub(crate) mod testdata;

pub use linear::{Element, LinearModel, LinearModelError};
pub use modes::{Complex, ModalAnalysis, Mode, ModeKind, modes};
