//! An isolated rotor in a wind tunnel, turning freely: the rotorspeed at which the mean
//! aerodynamic torque is zero, with the inflow in equilibrium (NACA TR 487, TR 515).
//!
//! The rotor's angle of attack `alpha` is between the free stream and the plane normal to the
//! shaft, positive when the air meets the disc from below (an autogyro's rotor, tilted back).
//! The hub then moves through the air at `u = V cos alpha` forward and `w = V sin alpha` down
//! the shaft; `alpha = 90 deg` is vertical descent. Lift and drag are perpendicular and
//! parallel to the free stream; coefficients are on `q pi R^2` with `q = rho V^2 / 2`.
//!
//! The unknowns `Omega, v0, v1s, v1c` are solved together by Newton's method (residuals: the
//! torque coefficient over solidity, and the inflow's departure from its static equilibrium over
//! the tip speed), started from a rotorspeed bracketed by the sign of the torque.

use crate::components::inflow;
use crate::components::rotor::{
    Blade, DescentInflow, HubVelocity, Inflow, InflowModel, Numerics, Operating, RevolutionMap,
    Rotor, RotorError, SteadyLoads,
};
use crate::solve::{self, NewtonOptions, SolveError};
use nalgebra::DMatrix;
use serde::Serialize;
use std::cell::{Cell, RefCell};
use std::f64::consts::PI;
use thiserror::Error;

/// The most blade revolutions one autorotation may integrate, over all its blade solutions
/// (the brackets' coarse ones, Newton's and the checks after it): nine times the most a row of
/// the TR 515 case takes, in the case or in its fits (335 where it converges, 330 where it
/// finds no equilibrium). A rotor whose blades are barely damped (a lift slope, a chord or a
/// radius near zero, a huge flap inertia) has no periodic flapping at most rotor speeds, and
/// each speed the search tries integrates the 200 revolutions [`Numerics::max_revolutions`]
/// allows: 10,000 revolutions and 3 s a row at 20 elements, 19 s at 200. Past this limit the
/// search gives up with the last residuals it met.
pub const MAX_REVOLUTIONS: usize = 3000;

/// What one autorotation solve has spent of its [`MAX_REVOLUTIONS`], and the last residuals
/// and blade failure it met: what the error says when it gives up.
#[derive(Default)]
struct Spent {
    revolutions: Cell<usize>,
    /// The last residuals computed, with what they are.
    residuals: RefCell<Option<(&'static str, Vec<f64>)>>,
    /// The last blade solution that failed, and why.
    failure: RefCell<Option<String>>,
}

impl Spent {
    /// The error that says the solve gave up, where it spent its revolutions.
    fn gave_up(&self) -> Option<AutorotationError> {
        let revolutions = self.revolutions.get();
        if revolutions < MAX_REVOLUTIONS {
            return None;
        }
        let last = match (&*self.residuals.borrow(), &*self.failure.borrow()) {
            (Some((what, r)), _) => format!("its last residuals ({what}): {r:?}"),
            (None, Some(f)) => format!("no blade solution it tried was periodic (the last: {f})"),
            (None, None) => "it computed no residuals".to_string(),
        };
        Some(AutorotationError::RevolutionLimit {
            revolutions,
            limit: MAX_REVOLUTIONS,
            last,
        })
    }

    /// `result`, or the error that says the solve gave up where it spent its revolutions.
    fn judge<T>(&self, result: Result<T, AutorotationError>) -> Result<T, AutorotationError> {
        result.map_err(|e| self.gave_up().unwrap_or(e))
    }
}

/// What the residuals of [`Problem::residuals`] are.
const RESIDUALS: &str =
    "torque coefficient over solidity, then the inflow's mismatches over the tip speed";

/// The tunnel condition.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tunnel {
    pub alpha_rad: f64,
    pub airspeed_m_s: f64,
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
    /// Added to the blade pitch everywhere (from a collective or pitch setting), rad.
    pub collective_shift_rad: f64,
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AutorotationOptions {
    pub inflow: InflowModel,
    pub numerics: Numerics,
    pub newton: NewtonOptions,
}

/// The default solver with the given inflow model.
impl From<InflowModel> for AutorotationOptions {
    fn from(inflow: InflowModel) -> Self {
        Self {
            inflow,
            ..Self::default()
        }
    }
}

impl Default for AutorotationOptions {
    fn default() -> Self {
        Self {
            inflow: InflowModel::PetersHaQuang {
                wake: crate::components::rotor::WakeModel::SEED_001,
            },
            numerics: Numerics::default(),
            newton: NewtonOptions::default(),
        }
    }
}

/// The autorotative equilibrium.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Autorotation {
    pub omega_rad_s: f64,
    pub rpm: f64,
    /// `mu = V cos alpha / (Omega R)`.
    pub tip_speed_ratio: f64,
    pub inflow: Inflow,
    /// Inflow ratio through the disc `lambda = (v0 - w_hub) / (Omega R)`, positive down.
    pub inflow_ratio: f64,
    pub skew_rad: f64,
    /// The blades' thrust (the hub's drag is not in it).
    pub thrust_n: f64,
    /// The blades' in-plane force, positive rearwards.
    pub h_force_n: f64,
    pub side_force_n: f64,
    /// The hub's own drag, along the free stream ([`crate::components::rotor::Rotor::hub_drag_n`]).
    pub hub_drag_n: f64,
    /// Lift and drag in wind axes, of the blades and the hub together (what a balance weighs).
    pub lift_n: f64,
    pub drag_n: f64,
    pub lift_coefficient: f64,
    pub drag_coefficient: f64,
    pub lift_to_drag: f64,
    /// `T / (rho pi R^2 (Omega R)^2)`.
    pub thrust_coefficient: f64,
    pub rolling_moment_n_m: f64,
    pub pitching_moment_n_m: f64,
    /// Flapping, `beta = a0 - a1 cos psi - b1 sin psi`, rad.
    pub a0_rad: f64,
    pub a1_rad: f64,
    pub b1_rad: f64,
    pub residual_norm: f64,
    pub iterations: usize,
    /// The model's equations used outside their stated validity at this equilibrium, in words
    /// (momentum theory in descent through the rotor's own wake:
    /// [`inflow::momentum_outside_validity`]), and whether the equilibrium is unstable in rotor
    /// speed, so that a tunnel does not hold it ([`judge`]); empty where neither is. No check
    /// passes on an answer with any.
    pub outside_validity: Vec<String>,
}

/// Why the equilibrium was not found.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AutorotationError {
    #[error(transparent)]
    Rotor(#[from] RotorError),
    #[error("{name} must be {requirement}, got {value}")]
    Condition {
        name: &'static str,
        requirement: &'static str,
        value: f64,
    },
    #[error(
        "no autorotative rotorspeed found between {low_rad_s:.3} and {high_rad_s:.3} rad/s: the driving torque does not change sign (torque coefficients {torques:?})"
    )]
    NoBracket {
        low_rad_s: f64,
        high_rad_s: f64,
        torques: Vec<f64>,
    },
    #[error("the equilibrium did not converge: {0}")]
    Solve(#[from] SolveError),
    #[error(
        "no angle of attack between 0.25 and 40 deg autorotates at tip-speed ratio {tip_speed_ratio} and {omega_rad_s:.3} rad/s: the driving torque does not change sign ((alpha deg, torque coefficient over solidity) {torques:?})"
    )]
    NoAngle {
        tip_speed_ratio: f64,
        omega_rad_s: f64,
        torques: Vec<(f64, f64)>,
    },
    #[error(
        "gave up after {revolutions} blade revolutions, the limit for one autorotation being {limit} (MAX_REVOLUTIONS); {last}"
    )]
    RevolutionLimit {
        revolutions: usize,
        limit: usize,
        last: String,
    },
    #[error(
        "at tip-speed ratio {tip_speed_ratio} and {omega_rad_s:.3} rad/s the rotor's equilibrium at the smallest angle that autorotates ({alpha_deg:.4} deg) is not the one a tunnel holds: {why}. The tip-speed ratio is beyond the largest at which the rotor autorotates"
    )]
    SlowBranch {
        tip_speed_ratio: f64,
        omega_rad_s: f64,
        alpha_deg: f64,
        why: String,
    },
    #[error(
        "the inflow found no equilibrium at {omega_rad_s:.4} rad/s (the blades' flapping not periodic, or Newton on the inflow not converging)"
    )]
    NoInflowEquilibrium { omega_rad_s: f64 },
    #[error(
        "the rotor is driven at {omega_rad_s:.3} rad/s (C_Q/sigma {torque:.3e}), faster than the equilibrium found, and no equilibrium was found above it (up to {fastest_rad_s:.3} rad/s, the fastest rotor speed tried)"
    )]
    DrivenToTheEnd {
        omega_rad_s: f64,
        torque: f64,
        fastest_rad_s: f64,
    },
    #[error(
        "Newton was started {restarts} times from a faster rotor's root and a faster rotor was still driven (at {faster_rad_s:.3} rad/s, above the last equilibrium's {omega_rad_s:.3} rad/s)"
    )]
    Restarts {
        restarts: usize,
        omega_rad_s: f64,
        faster_rad_s: f64,
    },
}

fn check(
    name: &'static str,
    value: f64,
    ok: bool,
    requirement: &'static str,
) -> Result<(), AutorotationError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(AutorotationError::Condition {
            name,
            requirement,
            value,
        })
    }
}

/// Gravity in hub axes for a rotor in a horizontal free stream (a wind tunnel, or level
/// flight), its shaft tilted back by the disc's angle of attack: earth's down is normal to the
/// hub's velocity, toward the shaft's foot. In purely axial flow (vertical descent) the shaft
/// is upright. The hub does not accelerate, so this is the apparent gravity at the hub too.
fn gravity_in_tunnel(hub: HubVelocity) -> [f64; 3] {
    let g = crate::components::atmosphere::G0_M_S2;
    let speed = (hub.u * hub.u + hub.w * hub.w).sqrt();
    if hub.u.abs() <= 1e-9 * speed.max(1.0) {
        return [0.0, 0.0, g];
    }
    [-g * hub.w / speed, 0.0, g * hub.u / speed]
}

struct Problem<'a> {
    rotor: &'a Rotor,
    blade: Blade<'a>,
    tunnel: Tunnel,
    hub: HubVelocity,
    model: InflowModel,
    warm: [f64; 2],
    /// What the periodic solutions so far learned of the blade's revolution map.
    map: RevolutionMap,
    /// The solve's revolutions, shared by its problems.
    spent: &'a Spent,
}

impl<'a> Problem<'a> {
    fn new(
        rotor: &'a Rotor,
        numerics: Numerics,
        tunnel: Tunnel,
        model: InflowModel,
        spent: &'a Spent,
    ) -> Self {
        Problem {
            rotor,
            blade: Blade::new(rotor, numerics),
            tunnel,
            hub: hub_in(&tunnel),
            model,
            warm: [0.05, 0.0],
            map: RevolutionMap::default(),
            spent,
        }
    }

    /// Moves the rotor to another tunnel condition; the flapping and what was learned of the
    /// revolution map are kept, to start from.
    fn set_tunnel(&mut self, tunnel: Tunnel) {
        self.tunnel = tunnel;
        self.hub = hub_in(&tunnel);
    }

    fn operating(&self, omega: f64, inflow: Inflow) -> Operating {
        Operating {
            omega_rad_s: omega,
            hub: self.hub,
            inflow,
            density_kg_m3: self.tunnel.density_kg_m3,
            speed_of_sound_m_s: self.tunnel.speed_of_sound_m_s,
            collective_shift_rad: self.tunnel.collective_shift_rad,
            hub_rates_rad_s: [0.0; 3],
            apparent_gravity_m_s2: gravity_in_tunnel(self.hub),
            hub_angular_acceleration_rad_s2: [0.0; 3],
        }
    }

    /// The blades' periodic solution, within what is left of the solve's [`MAX_REVOLUTIONS`].
    fn steady(&mut self, omega: f64, inflow: Inflow) -> Result<SteadyLoads, RotorError> {
        let spent = self.spent.revolutions.get();
        if spent >= MAX_REVOLUTIONS {
            return Err(RotorError::RevolutionLimit {
                limit: MAX_REVOLUTIONS,
            });
        }
        let op = self.operating(omega, inflow);
        let mut used = 0;
        let loads = self
            .blade
            .steady_counted(&op, self.warm, &mut self.map, &mut used);
        self.spent.revolutions.set(spent + used);
        let loads =
            loads.inspect_err(|e| *self.spent.failure.borrow_mut() = Some(e.to_string()))?;
        self.warm = loads.beta0;
        Ok(loads)
    }

    /// The inflow the loads call for (the prescribed inflow when it is prescribed).
    fn equilibrium_inflow(&self, loads: &SteadyLoads, current: Inflow) -> Inflow {
        let (skew, harmonics) = match self.model {
            InflowModel::Prescribed { v0, v1s, v1c } => return Inflow { v0, v1s, v1c },
            InflowModel::PetersHaQuang { wake } => (wake, true),
            InflowModel::UniformOnly { wake } => (wake, false),
        };
        inflow::static_inflow(
            inflow::DrivingLoads::of(loads),
            self.hub,
            current.v0,
            self.tunnel.density_kg_m3,
            self.rotor.radius_m,
            (skew, harmonics),
        )
        .0
    }

    fn torque_coefficient(&self, loads: &SteadyLoads, omega: f64) -> f64 {
        let r = self.rotor.radius_m;
        loads.driving_torque_n_m
            / (self.tunnel.density_kg_m3
                * PI
                * r
                * r
                * (omega * r).powi(2)
                * r
                * self.rotor.solidity())
    }

    /// Torque coefficient over solidity at a rotorspeed, with the inflow relaxed towards
    /// equilibrium in a few fixed-point passes (for bracketing only).
    fn rough_torque(&mut self, omega: f64, inflow: &mut Inflow) -> Result<f64, RotorError> {
        let mut loads = self.steady(omega, *inflow)?;
        for _ in 0..4 {
            let target = self.equilibrium_inflow(&loads, *inflow);
            *inflow = Inflow {
                v0: 0.5 * (inflow.v0 + target.v0),
                v1s: 0.5 * (inflow.v1s + target.v1s),
                v1c: 0.5 * (inflow.v1c + target.v1c),
            };
            loads = self.steady(omega, *inflow)?;
        }
        let q = self.torque_coefficient(&loads, omega);
        *self.spent.residuals.borrow_mut() = Some((
            "torque coefficient over solidity, coarse numerics, the inflow relaxed",
            vec![q],
        ));
        Ok(q)
    }
}

/// Finds the autorotative equilibrium of an isolated rotor in a wind tunnel.
pub fn autorotate(
    rotor: &Rotor,
    tunnel: Tunnel,
    options: AutorotationOptions,
) -> Result<Autorotation, AutorotationError> {
    autorotate_from(rotor, tunnel, options, None)
}

/// [`autorotate`] from a guess of the equilibrium, `(Omega, inflow)` (a neighbouring
/// condition's equilibrium): Newton from the guess first, and the bracket from a fast rotor
/// only if that does not converge. The same equilibrium as [`autorotate`] wherever the guess
/// lies on its branch.
///
/// Gives up past [`MAX_REVOLUTIONS`] blade revolutions, with the last residuals.
pub fn autorotate_from(
    rotor: &Rotor,
    tunnel: Tunnel,
    options: AutorotationOptions,
    guess: Option<(f64, Inflow)>,
) -> Result<Autorotation, AutorotationError> {
    let spent = Spent::default();
    spent.judge(autorotate_within(rotor, tunnel, options, guess, &spent))
}

/// [`autorotate_from`], its blade revolutions counted in `spent`.
fn autorotate_within(
    rotor: &Rotor,
    tunnel: Tunnel,
    options: AutorotationOptions,
    guess: Option<(f64, Inflow)>,
    spent: &Spent,
) -> Result<Autorotation, AutorotationError> {
    rotor.validate()?;
    check_tunnel(&tunnel)?;
    let mut p = Problem::new(rotor, options.numerics, tunnel, options.inflow, spent);
    // A warm start is kept only where it lands on the equilibrium a tunnel holds: near the fold
    // it can converge to the slow rotor's, which the bracket from a fast rotor never gives.
    if let Some((omega, inflow)) = guess
        && omega.is_finite()
        && omega > 0.0
        && let Ok(a) = solve_from(&mut p, options, omega, inflow)
        && p.judge(options, a.omega_rad_s, a.inflow)?.holds()
    {
        return Ok(a);
    }

    // Bracket the rotorspeed, from a fast rotor (the torque is negative: profile drag wins) to
    // a slow one, with coarse numerics (only the torque's sign matters here) and the inflow
    // carried from point to point as a fraction of the tip speed.
    let (v, r) = (tunnel.airspeed_m_s, rotor.radius_m);
    let coarse_rotor = coarse(rotor);
    let mut coarse = Problem::new(
        &coarse_rotor,
        coarse_numerics(options.numerics),
        tunnel,
        options.inflow,
        spent,
    );
    let ratios: Vec<f64> = (0..20)
        .map(|k| 40.0 * (1.2f64 / 40.0).powf(k as f64 / 19.0))
        .collect();
    let mut inflow = start_inflow(options.inflow);
    let mut torques = Vec::new();
    let mut start = None;
    // (rotor speed, torque, inflow) of each point the scan solved.
    let mut samples: Vec<(f64, f64, Inflow)> = Vec::new();
    let mut previous_omega = ratios[0] * v / r;
    for ratio in &ratios {
        let omega = ratio * v / r;
        inflow = scaled(options.inflow, inflow, omega / previous_omega);
        previous_omega = omega;
        let q = match coarse.rough_torque(omega, &mut inflow) {
            Ok(q) => q,
            // A rotor speed without periodic flapping is passed over, the inflow started
            // again: a very fast rotor (compressible sections with supersonic tips, where the
            // drag rise runs away), a blade twisted far by its elastic torsion (the twist grows
            // with Omega^2: a fast rotor's blades may lose their periodic flapping between two
            // rotor speeds that flap), or a very slow rotor (the scan then ends without a
            // bracket). A change of sign is looked for between rotor speeds that were solved.
            Err(e) if no_periodic_flapping(&e) => {
                inflow = start_inflow(options.inflow);
                continue;
            }
            Err(e) => return Err(e.into()),
        };
        let previous = torques.last().copied();
        torques.push(q);
        samples.push((omega, q, inflow));
        // The driving torque rises as the rotor slows: look for its change of sign.
        if let Some(qp) = previous
            && qp < 0.0
            && q >= 0.0
        {
            let w0 = samples[samples.len() - 2].0;
            let t = qp / (qp - q);
            start = Some((w0 + t * (omega - w0), inflow));
            break;
        }
    }
    // At the edge of autorotation the rotor speeds that autorotate can lie between two points
    // of the scan, and the coarse numerics put the torque's peak below zero there (TR 515 row
    // 71's angle and airspeed: -1.2e-5 coarse where the full numerics autorotate): look at the
    // peak between the scan's highest point's neighbours with the full numerics.
    if start.is_none() {
        start = bracket_at_peak(&mut p, options, &samples)?
            .filter(|d| d.bracketed)
            .map(|d| (d.omega_rad_s, d.inflow));
    }
    let (omega0, inflow0) = start.ok_or_else(|| AutorotationError::NoBracket {
        low_rad_s: ratios[ratios.len() - 1] * v / r,
        high_rad_s: ratios[0] * v / r,
        torques: torques.clone(),
    })?;

    // From a fast rotor the first change of sign is the fast rotor's equilibrium where the
    // coarse scan saw the torque as the full numerics do. It is judged as every path judges
    // (`Problem::judge`, full numerics): where a faster rotor is driven after all, Newton starts
    // again from that rotor's root; where the equilibrium is unstable in rotor speed (momentum
    // theory's unphysical root in descent: TR 487 with `--descent momentum`) it is returned
    // marked so, and no check passes on it.
    let a = solve_from(&mut p, options, omega0, inflow0)?;
    // The bracket's points faster than the equilibrium are the judgement's coarse scan.
    let scanned: Vec<(f64, f64, Inflow)> = samples
        .iter()
        .rev()
        .filter(|s| s.0 > a.omega_rad_s * (1.0 + JUST_ABOVE))
        .copied()
        .collect();
    hold(&mut p, options, a, scanned)
}

/// The fixed-angle search's equilibrium `a` judged ([`Problem::judge`], first on the
/// bracket's own coarse points above it, `scanned`): kept where a tunnel holds it; solved
/// again from a faster rotor's root where one is driven (at most [`RESTARTS`] times); marked
/// in its `outside_validity` where it is unstable in rotor speed.
fn hold(
    p: &mut Problem,
    options: AutorotationOptions,
    mut a: Autorotation,
    scanned: Vec<(f64, f64, Inflow)>,
) -> Result<Autorotation, AutorotationError> {
    let mut scanned = Some(scanned);
    let mut restart = 0;
    loop {
        let judgement = p.judge_scanned(options, a.omega_rad_s, a.inflow, scanned.take())?;
        match judgement.faster {
            Some(DrivenFaster {
                omega_rad_s: faster,
                start: Some(_),
                ..
            }) if restart == RESTARTS => {
                return Err(AutorotationError::Restarts {
                    restarts: RESTARTS,
                    omega_rad_s: a.omega_rad_s,
                    faster_rad_s: faster,
                });
            }
            Some(DrivenFaster {
                start: Some((omega, inflow)),
                ..
            }) => {
                a = solve_from(p, options, omega, inflow)?;
                restart += 1;
            }
            Some(DrivenFaster {
                omega_rad_s,
                torque,
                start: None,
            }) => {
                return Err(AutorotationError::DrivenToTheEnd {
                    omega_rad_s,
                    torque,
                    fastest_rad_s: fastest(p),
                });
            }
            None => {
                if judgement.stiffness.is_nan() || judgement.stiffness >= 0.0 {
                    a.outside_validity
                        .push(unstable_in_rotor_speed(judgement.stiffness));
                }
                return Ok(a);
            }
        }
    }
}

/// How many times the fixed-angle search starts Newton again from a faster rotor's root the
/// judgement found: each start is a faster root than the one before, and a torque curve with
/// more than three roots above the bracket's is not one a rotor in TR 487, TR 515 or the
/// VPM M16's range has shown.
const RESTARTS: usize = 3;

/// An inflow carried to a rotor speed `s` times faster, as a fraction of the tip speed (the
/// prescribed inflow as it is).
fn scaled(model: InflowModel, inflow: Inflow, s: f64) -> Inflow {
    match model {
        InflowModel::Prescribed { .. } => inflow,
        _ => Inflow {
            v0: inflow.v0 * s,
            v1s: inflow.v1s * s,
            v1c: inflow.v1c * s,
        },
    }
}

/// The fastest rotor speed the searches try: 40 times the airspeed over the radius (a
/// tip-speed ratio of 0.025).
fn fastest(p: &Problem) -> f64 {
    40.0 * p.tunnel.airspeed_m_s / p.rotor.radius_m
}

/// What an equilibrium unstable in rotor speed is marked with (in
/// [`Autorotation::outside_validity`]): a tunnel does not hold it.
fn unstable_in_rotor_speed(stiffness: f64) -> String {
    format!(
        "the equilibrium is unstable in rotor speed (d(C_Q/sigma)/d(ln Omega) = {stiffness:.3e} with the inflow in equilibrium: the driving torque rises as the rotor speeds up), so a tunnel does not hold it"
    )
}

/// A rotor speed faster than an equilibrium's at which the rotor is driven (the torque
/// coefficient over solidity `torque >= 0`, full numerics, the inflow in equilibrium), and
/// where Newton may start for the root above it (`None` where the rotor is driven up to the
/// fastest speed tried).
#[derive(Debug, Clone, Copy)]
pub struct DrivenFaster {
    pub omega_rad_s: f64,
    /// The torque coefficient over solidity there.
    pub torque: f64,
    /// Where Newton starts for the root above it: rotor speed and inflow.
    pub start: Option<(f64, Inflow)>,
}

/// Whether an equilibrium is the one a tunnel holds, decided the same way on every path (a
/// cold start at a fixed angle, a warm start, the tip-speed-ratio search), at the problem's own
/// numerics: stable in rotor speed, and no faster rotor driven (a rotor spun up settles there
/// first).
#[derive(Debug, Clone, Copy)]
pub struct StabilityJudgement {
    /// `d(C_Q / sigma) / d(ln Omega)` with the inflow in equilibrium.
    pub stiffness: f64,
    pub faster: Option<DrivenFaster>,
}

impl StabilityJudgement {
    /// Stable in rotor speed, and no faster rotor driven.
    pub fn holds(&self) -> bool {
        self.stiffness < 0.0 && self.faster.is_none()
    }
}

/// Where a scan of the driving torque from a fast rotor to a slow one (`samples`: rotor speed,
/// torque, inflow) found no change of sign: the largest torque between the scan's highest
/// point's neighbours, with the inflow in equilibrium and the full numerics, by golden-section
/// search on `ln Omega` ([`PEAK_STEPS`] steps), and, where it is positive, the start found by
/// bisection between it and the faster neighbour: the fast rotor's equilibrium, which a tunnel
/// holds.
fn bracket_at_peak(
    p: &mut Problem,
    options: AutorotationOptions,
    samples: &[(f64, f64, Inflow)],
) -> Result<Option<DrivenPeak>, AutorotationError> {
    let Some(k) =
        (1..samples.len().saturating_sub(1)).max_by(|&a, &b| samples[a].1.total_cmp(&samples[b].1))
    else {
        return Ok(None);
    };
    let (fast, peak, slow) = (samples[k - 1], samples[k], samples[k + 1]);
    let mut torque_at = |ln_omega: f64| -> Option<(f64, Inflow)> {
        let omega = ln_omega.exp();
        p.torque_in_equilibrium(
            options,
            omega,
            scaled(options.inflow, peak.2, omega / peak.0),
        )
    };
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (slow.0.ln(), fast.0.ln());
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let worst = (f64::NEG_INFINITY, peak.2);
    let (mut qc, mut qd) = (torque_at(c).unwrap_or(worst), torque_at(d).unwrap_or(worst));
    for _ in 0..PEAK_STEPS {
        let (x, best) = if qc.0 >= qd.0 { (c, qc) } else { (d, qd) };
        if best.0 >= 0.0 {
            // The fast rotor's root, between the faster neighbour and the peak, by bisection:
            // near the fold Newton from anywhere between may fall to the slow rotor's.
            let (mut lo, mut hi) = (x, b);
            // Driven there, whether or not the root above it is bracketed.
            let driven = |lo: f64, (torque, inflow): (f64, Inflow), bracketed| DrivenPeak {
                omega_rad_s: lo.exp(),
                torque,
                inflow,
                bracketed,
            };
            if torque_at(hi).is_none_or(|q| q.0 >= 0.0) {
                return Ok(Some(driven(lo, best, false)));
            }
            let mut found = best;
            for _ in 0..ROOT_STEPS {
                let m = 0.5 * (lo + hi);
                match torque_at(m) {
                    Some((q, i)) if q >= 0.0 => (lo, found) = (m, (q, i)),
                    Some(_) => hi = m,
                    None => return Ok(Some(driven(lo, found, false))),
                }
            }
            return Ok(Some(driven(lo, found, true)));
        }
        if qc.0 >= qd.0 {
            (b, d, qd) = (d, c, qc);
            c = b - g * (b - a);
            qc = torque_at(c).unwrap_or(worst);
        } else {
            (a, c, qc) = (c, d, qd);
            d = a + g * (b - a);
            qd = torque_at(d).unwrap_or(worst);
        }
    }
    Ok(None)
}

/// The ratio of one rotor speed to the next in [`Problem::faster_driving`]'s scan: about the
/// cold search's (20 points from 40 to 1.2 times the airspeed over the radius, a ratio of
/// 1.2025), so that [`bracket_at_peak`] looks between neighbours as far apart as there.
const SCAN_STEP: f64 = 1.2;

/// How far the coarse numerics' torque coefficient over solidity (8 elements, 7.5 deg steps,
/// the inflow relaxed in four passes) may lie from the full numerics' (the inflow in
/// equilibrium): a coarse torque further below zero than this is taken as negative by [`judge`]'s
/// scan of faster rotor speeds without computing it
/// again: five times the largest difference measured, 2.0e-5, over the 1,101 rotor speeds the
/// TR 515 case's judgements scan (rows 1-81, the PCA-2 rotor at 20 elements and 2.5 deg
/// steps), and guarded by a test that measures it again.
pub const COARSE_TORQUE_ERROR: f64 = 1e-4;

/// The largest value of the parabola through three points `(rotor speed, torque, _)` in
/// `ln Omega` (the middle one the highest): where the torque peaks between them; the highest
/// of the three where they do not bend down.
fn parabola_peak(points: [(f64, f64, Inflow); 3]) -> f64 {
    let [(w0, q0, _), (w1, q1, _), (w2, q2, _)] = points;
    let (x0, x1, x2) = (w0.ln(), w1.ln(), w2.ln());
    // The parabola a + b x + c x^2 from divided differences; its vertex at -b / 2c.
    let d01 = (q1 - q0) / (x1 - x0);
    let d12 = (q2 - q1) / (x2 - x1);
    let c = (d12 - d01) / (x2 - x0);
    if c.is_nan() || c >= 0.0 {
        return q1.max(q0).max(q2);
    }
    let b = d01 - c * (x0 + x1);
    let a = q0 - b * x0 - c * x0 * x0;
    a - b * b / (4.0 * c)
}

/// Where [`Problem::faster_driving`]'s scan starts above an equilibrium, relative: a stable
/// equilibrium's torque is negative there by its stiffness times this (about 1e-5 to 1e-4 of
/// C_Q/sigma on TR 515's rows), far above the inflow's convergence, and a driven band closer
/// than this lies where the stiffness itself is near zero (the fold), which the stiffness
/// judges.
const JUST_ABOVE: f64 = 1e-2;

/// A driven rotor speed [`bracket_at_peak`] found between a scan's points: its torque
/// coefficient over solidity and inflow, and whether it is the fast rotor's root's start
/// (bisected to [`ROOT_STEPS`]) or only a driven speed whose root above was not bracketed.
#[derive(Debug, Clone, Copy)]
struct DrivenPeak {
    omega_rad_s: f64,
    torque: f64,
    inflow: Inflow,
    bracketed: bool,
}

/// Bisection steps of [`bracket_at_peak`] towards the fast rotor's root: from the peak to the
/// faster neighbour (at most a factor 1.44) to 0.05 % of rotor speed, Newton's start.
const ROOT_STEPS: usize = 10;

/// Golden-section steps of [`bracket_at_peak`]: the scan's neighbours are a factor 1.44 of
/// rotor speed apart, and 12 steps narrow that to 0.2 % of it, about the width of the
/// autorotating range at TR 515 row 71's edge (mu 0.591 to about 0.595).
const PEAK_STEPS: usize = 12;

/// The tunnel condition's checks (a located error for each).
fn check_tunnel(tunnel: &Tunnel) -> Result<(), AutorotationError> {
    check(
        "airspeed_m_s",
        tunnel.airspeed_m_s,
        tunnel.airspeed_m_s > 0.0,
        "positive",
    )?;
    check(
        "alpha_rad",
        tunnel.alpha_rad,
        tunnel.alpha_rad > 0.0 && tunnel.alpha_rad <= PI / 2.0 + 1e-12,
        "in (0, 90] deg (air meeting the disc from below)",
    )?;
    check(
        "density_kg_m3",
        tunnel.density_kg_m3,
        tunnel.density_kg_m3 > 0.0,
        "positive",
    )?;
    check(
        "speed_of_sound_m_s",
        tunnel.speed_of_sound_m_s,
        tunnel.speed_of_sound_m_s > 0.0,
        "positive",
    )?;
    check(
        "collective_shift_rad",
        tunnel.collective_shift_rad,
        true,
        "finite",
    )
}

/// The hub's velocity in the tunnel: `V cos alpha` forward, `V sin alpha` down the shaft.
fn hub_in(tunnel: &Tunnel) -> HubVelocity {
    let (sa, ca) = tunnel.alpha_rad.sin_cos();
    let v = tunnel.airspeed_m_s;
    HubVelocity {
        u: v * ca.max(0.0),
        v: 0.0,
        w: v * sa,
    }
}

/// The rotor with at most 8 blade elements, for bracketing (only the torque's sign matters).
fn coarse(rotor: &Rotor) -> Rotor {
    Rotor {
        elements: rotor.elements.min(8),
        ..rotor.clone()
    }
}

/// Bracketing's numerics: 7.5 deg azimuth steps, periodic to 1e-7.
fn coarse_numerics(numerics: Numerics) -> Numerics {
    Numerics {
        azimuth_step_rad: 7.5f64.to_radians(),
        periodic_tolerance: 1e-7,
        ..numerics
    }
}

/// The inflow a search starts from: the prescribed one, or none.
fn start_inflow(model: InflowModel) -> Inflow {
    match model {
        InflowModel::Prescribed { v0, v1s, v1c } => Inflow { v0, v1s, v1c },
        _ => Inflow::default(),
    }
}

/// How many unknowns the equilibrium has: the rotor speed (or angle), and the inflow's free
/// components.
fn unknowns(model: InflowModel) -> usize {
    match model {
        InflowModel::Prescribed { .. } => 1,
        InflowModel::UniformOnly { .. } => 2,
        InflowModel::PetersHaQuang { .. } => 4,
    }
}

/// The inflow from its scaled unknowns (`x` after the first unknown, times `scale`).
fn inflow_from(model: InflowModel, x: &[f64], scale: f64) -> Inflow {
    match model {
        InflowModel::Prescribed { v0, v1s, v1c } => Inflow { v0, v1s, v1c },
        _ => Inflow {
            v0: x.first().map_or(0.0, |a| a * scale),
            v1s: x.get(1).map_or(0.0, |a| a * scale),
            v1c: x.get(2).map_or(0.0, |a| a * scale),
        },
    }
}

/// Newton on the rotor speed and inflow from `(omega0, inflow0)`, and the equilibrium's loads
/// and coefficients.
fn solve_from(
    p: &mut Problem,
    options: AutorotationOptions,
    omega0: f64,
    inflow0: Inflow,
) -> Result<Autorotation, AutorotationError> {
    // Newton on the scaled unknowns [Omega / omega0, v0 / Vs, v1s / Vs, v1c / Vs].
    let vs = p.tunnel.airspeed_m_s.max(1.0);
    let free = unknowns(options.inflow);
    let unpack = |x: &[f64]| (x[0] * omega0, inflow_from(options.inflow, &x[1..], vs));
    let x0: Vec<f64> = [1.0, inflow0.v0 / vs, inflow0.v1s / vs, inflow0.v1c / vs][..free].to_vec();
    let sol = solve::newton(
        |x| {
            let (omega, inflow) = unpack(x);
            // Newton stays near the bracketed rotorspeed; leaving it means no equilibrium nearby.
            if omega.is_nan() || !(0.2 * omega0..=5.0 * omega0).contains(&omega) {
                return Err(format!(
                    "rotorspeed {omega:.4} rad/s left the range 0.2-5 times the bracketed {omega0:.4} rad/s"
                ));
            }
            p.residuals(omega, inflow, free).map_err(|e| e.to_string())
        },
        &x0,
        options.newton,
    )?;
    let (omega, inflow) = unpack(&sol.x);
    p.equilibrium(omega, inflow, &sol)
}

impl Problem<'_> {
    /// The equilibrium's residuals: the torque coefficient over solidity, then the inflow's
    /// departure from its static equilibrium over the tip speed (the first `free - 1`
    /// components).
    fn residuals(
        &mut self,
        omega: f64,
        inflow: Inflow,
        free: usize,
    ) -> Result<Vec<f64>, RotorError> {
        let loads = self.steady(omega, inflow)?;
        let target = self.equilibrium_inflow(&loads, inflow);
        let tip = omega * self.rotor.radius_m;
        let mut res = vec![self.torque_coefficient(&loads, omega)];
        res.extend(
            [
                inflow.v0 - target.v0,
                inflow.v1s - target.v1s,
                inflow.v1c - target.v1c,
            ][..free - 1]
                .iter()
                .map(|d| d / tip),
        );
        *self.spent.residuals.borrow_mut() = Some((RESIDUALS, res.clone()));
        Ok(res)
    }

    /// How the driving torque moves with the rotor speed at an equilibrium, the inflow kept in
    /// its equilibrium: `d(C_Q / sigma) / d(ln Omega)`, by forward differences of relative size
    /// `step` in the rotor speed and the inflow (over the airspeed), the inflow's part taken
    /// out by the Schur complement. Negative where the rotor returns to its speed when
    /// disturbed: the equilibrium a tunnel holds.
    fn rotor_speed_stiffness(
        &mut self,
        omega: f64,
        inflow: Inflow,
        free: usize,
        step: f64,
    ) -> Result<f64, RotorError> {
        let r0 = self.residuals(omega, inflow, free)?;
        let dv = step * self.tunnel.airspeed_m_s.max(1.0);
        let mut jac = DMatrix::zeros(free, free);
        for j in 0..free {
            let r = match j {
                0 => self.residuals(omega * (1.0 + step), inflow, free)?,
                1 => self.residuals(
                    omega,
                    Inflow {
                        v0: inflow.v0 + dv,
                        ..inflow
                    },
                    free,
                )?,
                2 => self.residuals(
                    omega,
                    Inflow {
                        v1s: inflow.v1s + dv,
                        ..inflow
                    },
                    free,
                )?,
                _ => self.residuals(
                    omega,
                    Inflow {
                        v1c: inflow.v1c + dv,
                        ..inflow
                    },
                    free,
                )?,
            };
            for i in 0..free {
                jac[(i, j)] = (r[i] - r0[i]) / step;
            }
        }
        if free == 1 {
            return Ok(jac[(0, 0)]);
        }
        let n = free - 1;
        let inflow_block = jac.view((1, 1), (n, n)).into_owned();
        let Some(x) = inflow_block
            .lu()
            .solve(&jac.view((1, 0), (n, 1)).into_owned())
        else {
            return Ok(f64::NAN);
        };
        Ok(jac[(0, 0)] - (jac.view((0, 1), (1, n)) * x)[(0, 0)])
    }

    /// Whether the equilibrium at `(omega, inflow)` is the one a tunnel holds
    /// ([`StabilityJudgement`]): its stiffness in rotor speed ([`Self::rotor_speed_stiffness`], the
    /// solver's step) and the first faster rotor speed that is driven
    /// ([`Self::faster_driving`]), both at the problem's own numerics.
    fn judge(
        &mut self,
        options: AutorotationOptions,
        omega: f64,
        inflow: Inflow,
    ) -> Result<StabilityJudgement, AutorotationError> {
        self.judge_scanned(options, omega, inflow, None)
    }

    /// [`Self::judge`], with the coarse scan above `omega` given where a search already made
    /// it (`scanned`: (rotor speed, coarse torque, inflow), slow to fast, every point above
    /// `omega`): the fixed-angle search's own bracket, in about the same steps.
    fn judge_scanned(
        &mut self,
        options: AutorotationOptions,
        omega: f64,
        inflow: Inflow,
        scanned: Option<Vec<(f64, f64, Inflow)>>,
    ) -> Result<StabilityJudgement, AutorotationError> {
        let free = unknowns(options.inflow);
        let stiffness = self.rotor_speed_stiffness(omega, inflow, free, options.newton.fd_step)?;
        let faster = match scanned {
            Some(samples) => self.screen(options, samples, false)?,
            None => self.faster_driving(options, omega, inflow)?,
        };
        Ok(StabilityJudgement { stiffness, faster })
    }

    /// The torque coefficient over solidity at rotor speed `omega` with the inflow solved into
    /// its equilibrium (Newton from `start`), and that inflow; `None` where it does not solve.
    fn torque_in_equilibrium(
        &mut self,
        options: AutorotationOptions,
        omega: f64,
        start: Inflow,
    ) -> Option<(f64, Inflow)> {
        let free = unknowns(options.inflow);
        let vs = self.tunnel.airspeed_m_s.max(1.0);
        let inflow = if free > 1 {
            let x0 = [start.v0 / vs, start.v1s / vs, start.v1c / vs][..free - 1].to_vec();
            let sol = solve::newton(
                |x| {
                    let r = self
                        .residuals(omega, inflow_from(options.inflow, x, vs), free)
                        .map_err(|e| e.to_string())?;
                    Ok(r[1..].to_vec())
                },
                &x0,
                options.newton,
            )
            .ok()?;
            inflow_from(options.inflow, &sol.x, vs)
        } else {
            start_inflow(options.inflow)
        };
        let r = self.residuals(omega, inflow, free).ok()?;
        Some((r[0], inflow))
    }

    /// The first rotor speed faster than `omega` at which the driving torque is positive
    /// (where a rotor spun up would settle before slowing to `omega`), judged at the problem's
    /// own numerics with the inflow in equilibrium, with where Newton may start for the root
    /// above it.
    ///
    /// A scan from just above `omega` ([`JUST_ABOVE`]) to [`fastest`] in the bracket's steps
    /// ([`SCAN_STEP`]) screens with coarse numerics and the inflow relaxed: a point whose
    /// torque comes within [`COARSE_TORQUE_ERROR`] of zero is computed again at the full
    /// numerics, and only the full numerics' sign counts. Where no point is driven, the peak
    /// between the highest point's neighbours (a driven band narrower than a step, as at the
    /// edge of autorotation) is searched at the full numerics ([`bracket_at_peak`]) where a
    /// parabola through the three puts it within [`COARSE_TORQUE_ERROR`] of zero.
    fn faster_driving(
        &mut self,
        options: AutorotationOptions,
        omega: f64,
        inflow: Inflow,
    ) -> Result<Option<DrivenFaster>, AutorotationError> {
        let samples = self.coarse_scan_above(options, omega, inflow)?;
        self.screen(options, samples, true)
    }

    /// The coarse torque (coarse numerics, the inflow relaxed) from just above `omega`
    /// ([`JUST_ABOVE`]) to [`fastest`] in steps of [`SCAN_STEP`], the inflow carried from
    /// point to point: (rotor speed, torque, inflow), slow to fast. A rotor speed without
    /// periodic flapping is passed over, the inflow started again from `inflow` scaled.
    fn coarse_scan_above(
        &mut self,
        options: AutorotationOptions,
        omega: f64,
        inflow: Inflow,
    ) -> Result<Vec<(f64, f64, Inflow)>, AutorotationError> {
        let fastest = fastest(self);
        let coarse_rotor = coarse(self.rotor);
        let mut coarse = Problem::new(
            &coarse_rotor,
            coarse_numerics(options.numerics),
            self.tunnel,
            options.inflow,
            self.spent,
        );
        let mut samples = Vec::new();
        let mut w = omega * (1.0 + JUST_ABOVE);
        let mut current = scaled(options.inflow, inflow, 1.0 + JUST_ABOVE);
        while w <= fastest {
            match coarse.rough_torque(w, &mut current) {
                Ok(q) => samples.push((w, q, current)),
                Err(e) if no_periodic_flapping(&e) => {
                    current = scaled(options.inflow, inflow, w / omega)
                }
                Err(e) => return Err(e.into()),
            }
            w *= SCAN_STEP;
            current = scaled(options.inflow, current, SCAN_STEP);
        }
        Ok(samples)
    }

    /// [`Self::faster_driving`]'s decision on coarse `samples` of the torque above an
    /// equilibrium (slow to fast): each within [`COARSE_TORQUE_ERROR`] of zero computed again
    /// at the full numerics (the first one too unless `skip_first`: just above the equilibrium
    /// it is near zero by the stiffness, which judges it), then the peak between the highest
    /// point's neighbours.
    fn screen(
        &mut self,
        options: AutorotationOptions,
        mut samples: Vec<(f64, f64, Inflow)>,
        skip_first: bool,
    ) -> Result<Option<DrivenFaster>, AutorotationError> {
        for (k, &(w, q, inflow)) in samples.iter().enumerate() {
            if (k > 0 || !skip_first)
                && q >= -COARSE_TORQUE_ERROR
                && let Some((q, i)) = self.torque_in_equilibrium(options, w, inflow)
                && q >= 0.0
            {
                return Ok(Some(self.driven_from(options, w, q, i)));
            }
        }
        let Some(k) = (1..samples.len().saturating_sub(1))
            .max_by(|&a, &b| samples[a].1.total_cmp(&samples[b].1))
        else {
            return Ok(None);
        };
        // A peak is where the torque rises from the slower neighbour; where it falls from the
        // equilibrium throughout, the highest torque is the equilibrium's own.
        if samples[k - 1].1 >= samples[k].1
            || parabola_peak([samples[k - 1], samples[k], samples[k + 1]]) < -COARSE_TORQUE_ERROR
        {
            return Ok(None);
        }
        samples.reverse();
        Ok(
            bracket_at_peak(self, options, &samples)?.map(|d| DrivenFaster {
                omega_rad_s: d.omega_rad_s,
                torque: d.torque,
                start: d.bracketed.then_some((d.omega_rad_s, d.inflow)),
            }),
        )
    }

    /// A driven rotor speed `omega` (torque `q`, inflow `inflow`, full numerics) and the root
    /// above it: the scan goes on up at the full numerics until the torque turns negative, and
    /// Newton's start is interpolated between the two points.
    fn driven_from(
        &mut self,
        options: AutorotationOptions,
        omega: f64,
        q: f64,
        inflow: Inflow,
    ) -> DrivenFaster {
        let fastest = fastest(self);
        let (mut w0, mut q0, mut i0) = (omega, q, inflow);
        let mut start = None;
        while w0 * SCAN_STEP <= fastest {
            let w = w0 * SCAN_STEP;
            let guess = scaled(options.inflow, i0, SCAN_STEP);
            let Some((q, i)) = self.torque_in_equilibrium(options, w, guess) else {
                break;
            };
            if q < 0.0 {
                let t = q0 / (q0 - q);
                let mix = |x: f64, y: f64| x + t * (y - x);
                start = Some((
                    mix(w0, w),
                    Inflow {
                        v0: mix(i0.v0, i.v0),
                        v1s: mix(i0.v1s, i.v1s),
                        v1c: mix(i0.v1c, i.v1c),
                    },
                ));
                break;
            }
            (w0, q0, i0) = (w, q, i);
        }
        DrivenFaster {
            omega_rad_s: omega,
            torque: q,
            start,
        }
    }

    /// The equilibrium Newton found at `(omega, inflow)`: its loads and coefficients.
    fn equilibrium(
        &mut self,
        omega: f64,
        inflow: Inflow,
        sol: &solve::Converged,
    ) -> Result<Autorotation, AutorotationError> {
        let (tunnel, hub, r) = (self.tunnel, self.hub, self.rotor.radius_m);
        let (sa, ca) = tunnel.alpha_rad.sin_cos();
        let v = tunnel.airspeed_m_s;
        let loads = self.steady(omega, inflow)?;
        let thrust = loads.thrust_n();
        let h = -loads.force_n[0];
        // The balance weighs the hub too: its drag, along the free stream, joins the blades'
        // loads.
        let hub_drag = self.rotor.hub_drag_n(tunnel.density_kg_m3, hub);
        let (thrust_all, h_all) = (thrust - hub_drag[2], h - hub_drag[0]);
        let lift = thrust_all * ca - h_all * sa;
        let drag = thrust_all * sa + h_all * ca;
        let q_area = 0.5 * tunnel.density_kg_m3 * v * v * PI * r * r;
        let (skew, outside_validity) = match self.model {
            InflowModel::PetersHaQuang { wake } | InflowModel::UniformOnly { wake } => {
                let v_h = inflow::hover_induced_m_s(thrust, tunnel.density_kg_m3, r);
                let outside = match wake.descent {
                    DescentInflow::Momentum => {
                        inflow::momentum_outside_validity(hub, inflow.v0, v_h)
                    }
                    DescentInflow::Johnson => None,
                };
                (
                    inflow::wake(hub, inflow.v0, wake, v_h).skew_rad,
                    outside.into_iter().collect(),
                )
            }
            InflowModel::Prescribed { .. } => (f64::NAN, Vec::new()),
        };
        Ok(Autorotation {
            omega_rad_s: omega,
            rpm: omega * 30.0 / PI,
            tip_speed_ratio: hub.u / (omega * r),
            inflow,
            inflow_ratio: (inflow.v0 - hub.w) / (omega * r),
            skew_rad: skew,
            thrust_n: thrust,
            h_force_n: h,
            side_force_n: loads.force_n[1],
            hub_drag_n: hub_drag[0].hypot(hub_drag[2]),
            lift_n: lift,
            drag_n: drag,
            lift_coefficient: lift / q_area,
            drag_coefficient: drag / q_area,
            lift_to_drag: lift / drag,
            thrust_coefficient: thrust / (tunnel.density_kg_m3 * PI * r * r * (omega * r).powi(2)),
            rolling_moment_n_m: loads.moment_n_m[0],
            pitching_moment_n_m: loads.moment_n_m[1],
            a0_rad: loads.a0_rad,
            a1_rad: loads.a1_rad,
            b1_rad: loads.b1_rad,
            residual_norm: sol.residual_norm,
            iterations: sol.iterations,
            outside_validity,
        })
    }
}

/// Whether the equilibrium at rotor speed `omega_rad_s` and inflow `inflow` in `tunnel` is the
/// one a tunnel holds, judged as every search judges its answer: `d(C_Q/sigma)/d(ln Omega)`
/// with the inflow in equilibrium, and the first faster rotor speed that is driven
/// ([`StabilityJudgement`]).
pub fn judge(
    rotor: &Rotor,
    tunnel: Tunnel,
    options: AutorotationOptions,
    omega_rad_s: f64,
    inflow: Inflow,
) -> Result<StabilityJudgement, AutorotationError> {
    check_at(rotor, &tunnel, omega_rad_s)?;
    let spent = Spent::default();
    let mut p = Problem::new(rotor, options.numerics, tunnel, options.inflow, &spent);
    spent.judge(p.judge(options, omega_rad_s, inflow))
}

/// The checks of a rotor, a tunnel and a rotor speed asked of [`judge`] and
/// [`torque_over_solidity`] (a located error for each).
fn check_at(rotor: &Rotor, tunnel: &Tunnel, omega_rad_s: f64) -> Result<(), AutorotationError> {
    rotor.validate()?;
    check_tunnel(tunnel)?;
    check("omega_rad_s", omega_rad_s, omega_rad_s > 0.0, "positive")
}

/// The numerics [`torque_over_solidity`] computes the torque with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TorqueNumerics {
    /// The rotor's own numerics, the inflow solved into its equilibrium.
    Full,
    /// The brackets' (at most 8 elements, 7.5 deg steps), the inflow relaxed toward its
    /// equilibrium in four passes.
    Coarse,
}

/// The driving torque coefficient over solidity at rotor speed `omega_rad_s` in `tunnel`, the
/// inflow started from `inflow`: how the searches see the torque curve (positive: the rotor is
/// driven and speeds up).
pub fn torque_over_solidity(
    rotor: &Rotor,
    tunnel: Tunnel,
    options: AutorotationOptions,
    omega_rad_s: f64,
    inflow: Inflow,
    numerics: TorqueNumerics,
) -> Result<f64, AutorotationError> {
    check_at(rotor, &tunnel, omega_rad_s)?;
    let spent = Spent::default();
    match numerics {
        TorqueNumerics::Full => {
            let mut p = Problem::new(rotor, options.numerics, tunnel, options.inflow, &spent);
            p.torque_in_equilibrium(options, omega_rad_s, inflow)
                .map(|(q, _)| q)
                .ok_or_else(|| {
                    spent
                        .gave_up()
                        .unwrap_or(AutorotationError::NoInflowEquilibrium { omega_rad_s })
                })
        }
        TorqueNumerics::Coarse => {
            let coarse_rotor = coarse(rotor);
            let mut p = Problem::new(
                &coarse_rotor,
                coarse_numerics(options.numerics),
                tunnel,
                options.inflow,
                &spent,
            );
            let mut inflow = inflow;
            Ok(p.rough_torque(omega_rad_s, &mut inflow)?)
        }
    }
}

/// A tunnel condition given as the tunnel reports its rows: tip-speed ratio and rotor speed,
/// the angle of attack to be found (see [`autorotate_at_tip_speed_ratio`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TipSpeedCondition {
    pub tip_speed_ratio: f64,
    pub omega_rad_s: f64,
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
    /// Added to the blade pitch everywhere, rad.
    pub collective_shift_rad: f64,
}

/// The angle of attack and airspeed at which a rotor autorotates at a given tip-speed ratio
/// and rotor speed, with the equilibrium there.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AtTipSpeedRatio {
    pub alpha_rad: f64,
    pub airspeed_m_s: f64,
    pub autorotation: Autorotation,
    /// `d(C_Q / sigma) / d(ln Omega)` at the equilibrium with the inflow in its equilibrium:
    /// negative, the rotor returns to its speed when disturbed (how close to zero says how near
    /// the largest tip-speed ratio at which the rotor autorotates it is).
    pub rotor_speed_stiffness: f64,
}

/// Finds the angle of attack at which `rotor` autorotates at the condition's tip-speed ratio
/// and rotor speed: how the tunnel data of NACA TR 515 are plotted, and at small angles the
/// well-conditioned comparison (a fixed-angle comparison moves mu by 0.1-0.3 per degree there).
///
/// The tip-speed ratio and rotor speed fix the flow along the disc, `u = mu Omega R`; the angle
/// sets the flow up through it, `w = u tan alpha`. So the angle takes the rotor speed's place
/// among the unknowns of [`autorotate`], `alpha, v0, v1s, v1c`, with the same residuals. The
/// driving torque rises with the angle. The angle is bracketed by the torque's sign on a grid
/// from 40 deg down to 0.25 deg, with coarse numerics and the inflow relaxed (as [`autorotate`]
/// brackets its rotor speed), and Newton's method solves from there. Coming down from large
/// angles, where the rotor is driven, the first change of sign is the equilibrium a tunnel
/// holds: the one [`autorotate`] finds at that angle (see the tests).
///
/// Gives up past [`MAX_REVOLUTIONS`] blade revolutions, with the last residuals.
pub fn autorotate_at_tip_speed_ratio(
    rotor: &Rotor,
    c: TipSpeedCondition,
    options: AutorotationOptions,
) -> Result<AtTipSpeedRatio, AutorotationError> {
    let spent = Spent::default();
    spent.judge(at_tip_speed_ratio_within(rotor, c, options, &spent))
}

/// [`autorotate_at_tip_speed_ratio`], its blade revolutions counted in `spent`.
fn at_tip_speed_ratio_within(
    rotor: &Rotor,
    c: TipSpeedCondition,
    options: AutorotationOptions,
    spent: &Spent,
) -> Result<AtTipSpeedRatio, AutorotationError> {
    check(
        "tip_speed_ratio",
        c.tip_speed_ratio,
        c.tip_speed_ratio > 0.0 && c.tip_speed_ratio < 2.0,
        "in (0, 2)",
    )?;
    check(
        "omega_rad_s",
        c.omega_rad_s,
        c.omega_rad_s > 0.0,
        "positive",
    )?;
    rotor.validate()?;
    let u = c.tip_speed_ratio * c.omega_rad_s * rotor.radius_m;
    let tunnel_at = |alpha_rad: f64| Tunnel {
        alpha_rad,
        airspeed_m_s: u / alpha_rad.cos(),
        density_kg_m3: c.density_kg_m3,
        speed_of_sound_m_s: c.speed_of_sound_m_s,
        collective_shift_rad: c.collective_shift_rad,
    };
    check_tunnel(&tunnel_at(ANGLE_GRID_DEG[0].to_radians()))?;
    let (alpha0, inflow0) = bracket_angle(rotor, c, options, tunnel_at, spent)?;

    // Newton on the scaled unknowns [alpha / alpha0, v0 / u, v1s / u, v1c / u].
    let mut p = Problem::new(
        rotor,
        options.numerics,
        tunnel_at(alpha0),
        options.inflow,
        spent,
    );
    let us = u.max(1.0);
    let free = unknowns(options.inflow);
    let unpack = |x: &[f64]| (x[0] * alpha0, inflow_from(options.inflow, &x[1..], us));
    let x0: Vec<f64> = [1.0, inflow0.v0 / us, inflow0.v1s / us, inflow0.v1c / us][..free].to_vec();
    let sol = solve::newton(
        |x| {
            let (alpha, inflow) = unpack(x);
            // Newton stays near the bracketed angle; leaving it means no equilibrium nearby.
            if alpha.is_nan() || !(0.25 * alpha0..=(4.0 * alpha0).min(0.5 * PI)).contains(&alpha) {
                return Err(format!(
                    "the angle of attack {:.4} deg left the range 0.25-4 times the bracketed {:.4} deg",
                    alpha.to_degrees(),
                    alpha0.to_degrees()
                ));
            }
            p.set_tunnel(tunnel_at(alpha));
            p.residuals(c.omega_rad_s, inflow, free)
                .map_err(|e| e.to_string())
        },
        &x0,
        options.newton,
    )?;
    let (alpha, inflow) = unpack(&sol.x);
    p.set_tunnel(tunnel_at(alpha));
    // The smallest angle's equilibrium is the one a tunnel holds (the fast rotor's, as
    // [`autorotate`] finds it), unless the tip-speed ratio is beyond the largest the rotor
    // reaches: there it is a slow rotor's, which runs away or which a rotor spun up never
    // reaches.
    let slow_branch = |why: String| AutorotationError::SlowBranch {
        tip_speed_ratio: c.tip_speed_ratio,
        omega_rad_s: c.omega_rad_s,
        alpha_deg: alpha.to_degrees(),
        why,
    };
    let judgement = p.judge(options, c.omega_rad_s, inflow)?;
    let stiffness = judgement.stiffness;
    if stiffness.is_nan() || stiffness >= 0.0 {
        return Err(slow_branch(format!(
            "it is unstable in rotor speed (d(C_Q/sigma)/d(ln Omega) = {stiffness:.3e} with the inflow in equilibrium: the driving torque rises as the rotor speeds up)"
        )));
    }
    if let Some(d) = judgement.faster {
        return Err(slow_branch(format!(
            "a faster rotor is driven at that angle too (C_Q/sigma {:.3e} at {:.3} rad/s, the inflow in equilibrium), and a rotor spun up settles there first",
            d.torque, d.omega_rad_s
        )));
    }
    Ok(AtTipSpeedRatio {
        alpha_rad: alpha,
        airspeed_m_s: p.tunnel.airspeed_m_s,
        autorotation: p.equilibrium(c.omega_rad_s, inflow, &sol)?,
        rotor_speed_stiffness: stiffness,
    })
}

/// The smallest and largest angles the angle search of [`autorotate_at_tip_speed_ratio`] tries.
const ANGLE_GRID_DEG: [f64; 2] = [0.25, 40.0];

/// The angle of attack where the driving torque first turns positive at the condition's
/// tip-speed ratio and rotor speed, coming up from small angles on a grid of 12 (coarse
/// numerics, the inflow relaxed), interpolated, with the inflow there: where Newton starts.
fn bracket_angle(
    rotor: &Rotor,
    c: TipSpeedCondition,
    options: AutorotationOptions,
    tunnel_at: impl Fn(f64) -> Tunnel,
    spent: &Spent,
) -> Result<(f64, Inflow), AutorotationError> {
    let [low, high] = ANGLE_GRID_DEG;
    let grid: Vec<f64> = (0..12)
        .map(|k| (low * (high / low).powf(k as f64 / 11.0)).to_radians())
        .collect();
    let coarse_rotor = coarse(rotor);
    let mut coarse = Problem::new(
        &coarse_rotor,
        coarse_numerics(options.numerics),
        tunnel_at(grid[0]),
        options.inflow,
        spent,
    );
    let mut inflow = start_inflow(options.inflow);
    let mut torques: Vec<(f64, f64)> = Vec::new();
    let mut below: Option<(f64, f64, Inflow)> = None;
    for &alpha in &grid {
        coarse.set_tunnel(tunnel_at(alpha));
        let q = match coarse.rough_torque(c.omega_rad_s, &mut inflow) {
            Ok(q) => q,
            // At the smallest angles the blades may have no periodic flapping: the bracket
            // lies above.
            Err(e) if no_periodic_flapping(&e) && below.is_none() => {
                inflow = start_inflow(options.inflow);
                continue;
            }
            Err(e) if no_periodic_flapping(&e) => break,
            Err(e) => return Err(e.into()),
        };
        torques.push((alpha.to_degrees(), q));
        if let Some((a0, q0, inflow0)) = below
            && q0 < 0.0
            && q >= 0.0
        {
            let t = q0 / (q0 - q);
            let mix = |x: f64, y: f64| x + t * (y - x);
            return Ok((
                mix(a0, alpha),
                Inflow {
                    v0: mix(inflow0.v0, inflow.v0),
                    v1s: mix(inflow0.v1s, inflow.v1s),
                    v1c: mix(inflow0.v1c, inflow.v1c),
                },
            ));
        }
        below = Some((alpha, q, inflow));
    }
    Err(AutorotationError::NoAngle {
        tip_speed_ratio: c.tip_speed_ratio,
        omega_rad_s: c.omega_rad_s,
        torques,
    })
}

/// Errors that mean the blades have no periodic flapping at a condition (a bracket skips it).
fn no_periodic_flapping(e: &RotorError) -> bool {
    matches!(
        e,
        RotorError::FlapNotPeriodic { .. }
            | RotorError::NonFinite(_)
            | RotorError::FlapPastVertical { .. }
    )
}
