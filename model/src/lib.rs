//! # cierva-model
//!
//! The flight-dynamics side of cierva, in four groups:
//! * [`components`]: the atmosphere, blade sections, the individual-blade rotor (articulated,
//!   teetering or rigid hubs) with Peters-HaQuang inflow (static gains and the dynamic time
//!   constants), the isolated rotor in autorotation, the propeller with blockage, the airframe,
//!   the 6-DOF rigid body;
//! * [`aircraft`]: the assembled autogyro with its revolution-averaged and full individual-blade
//!   equations, its trim ([`aircraft::trim`]) and linearisation ([`aircraft::linearise`]);
//! * [`analysis`]: linear models, their modes, BCAR Section T, weakly coupled systems with the
//!   rotorspeed degree of freedom, root loci, and inflow from blade flapping;
//! * [`simulation`]: time histories of the full and the linear model.
//!
//! Beside them, [`estimate`]: airframe coefficients from geometry by published methods, for
//! aircraft files where nothing was measured.
//!
//! This crate does no I/O and knows nothing about case files: it takes numbers and returns
//! numbers, statuses and errors. It never panics on data.
//!
//! ## Conventions
//! * **Axes.** Body axes with the origin at the centre of mass: x forward along the keel,
//!   y to starboard, z down (right-handed), as in seeds 000-002. Velocities `u, v, w` (m/s),
//!   rates `p, q, r` (rad/s), Euler attitudes `phi, theta, psi` (rad), rotorspeed `Omega`
//!   (rad/s), relative to the airframe as a rotor tachometer reads it. The rotor turns freely
//!   on its shaft: the airframe's inertia excludes its polar moment about the shaft, and `Q`
//!   (below) includes the airframe's acceleration about the shaft (see [`aircraft`]).
//! * **Derivatives.** Accelerations per unit perturbation, named `<force>_<variable>`:
//!   `X, Y, Z` act on `u, v, w`; `L, M, N` on `p, q, r`; `Q` on `Omega` (rotor torque divided
//!   by rotor inertia, plus the airframe's angular acceleration about the shaft). So `X_u` is in 1/s, `M_w` in 1/(m s), `Q_u` in rad/(m s) and `Q_Omega`
//!   in 1/s. Control columns use the control's name (`M_eta_s`).
//! * **Controls.** `eta_s` longitudinal, `eta_c` lateral (stick or shaft tilt, units as the
//!   source states them), `theta_0` collective.
//! * **Signs.** A positive real part is an unstable mode. Oscillatory modes are reported once,
//!   by the member of the conjugate pair with positive imaginary part.
//! * **Rotor hub axes and azimuth** (module [`components::rotor`]): `x` forward, `y` starboard, `z` down
//!   the shaft; the rotor turns anticlockwise seen from above; azimuth is zero with the blade
//!   over the tail and increases with rotation, so the blade advances at 90 deg. Flapping is
//!   positive up, `beta = a0 - a1 cos psi - b1 sin psi`; induced velocity is positive down,
//!   `v_i = v0 + (r/R)(v1s sin psi + v1c cos psi)`.
//! * **Aircraft geometry** (module [`aircraft`]): positions in body axes from a datum, m. Hub
//!   axes follow from body axes by the shaft's aft tilt `theta_s` (a pitch) then its right tilt
//!   `phi_s` (a roll): `v_hub = R_x(phi_s) R_y(theta_s) v_body`. The hub sits up the shaft from
//!   the spindle's pivot.
//! * **Pilot's controls** in percent of travel: longitudinal stick 0 % fully forward, 100 %
//!   fully aft (aft stick tilts the rotor back); lateral stick 0 % left, 100 % right (right stick
//!   tilts it right); pedal 0 % left, 100 % right (rudder trailing edge to starboard positive);
//!   throttle 0-100 %. The aircraft file maps them linearly to angles.
//! * **Propeller**: thrust along body `+x`; its rotation is given as seen from behind, and the
//!   engine's torque reaction rolls the airframe the other way.
//! * **Trim state**: heading zero, the flight path fixed in north-east-down axes (airspeed along
//!   the track, climbing at the given rate), sideslip a result.
//! * **Units.** SI throughout (m, s, kg, N, rad); names carry units where they are not obvious.

/// The parts of an autogyro, each on its own: the atmosphere, blade sections, the rotor and
/// its inflow, the isolated rotor in autorotation, the propeller, the airframe, the rigid body.
pub mod components {
    pub mod airfoil;
    pub mod airframe;
    pub mod atmosphere;
    pub mod autorotation;
    pub mod inflow;
    pub mod propeller;
    pub mod rigid_body;
    pub mod rotor;
}

// The assembled autogyro, its trim and its linearisation (documented in the module).
pub mod aircraft;

/// Analysis of linear models (modes, BCAR Section T, weakly coupled systems, root loci) and of
/// blade flapping (inflow from flapping).
pub mod analysis {
    pub mod bcar;
    pub mod flapping_inflow;
    pub mod linear;
    pub mod locus;
    pub mod milne;
    pub mod modes;
}

/// Flying the models in time: the full individual-blade model and the linear model, and the
/// full model's trim on its periodic orbit.
pub mod simulation {
    pub mod periodic_trim;
    pub mod simulate;
    pub mod timehistory;
}

pub mod estimate;

pub mod solve;
#[cfg(test)]
pub(crate) mod testdata;

pub use analysis::linear::{Element, LinearModel, LinearModelError};

/// This crate's version, for reports.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
pub use analysis::modes::{Complex, ModalAnalysis, Mode, ModeKind, modes};
