//! The assembled autogyro: a main rotor on a tilting spindle, a pusher propeller driven by an
//! engine, the airframe, and the rigid body (seed 000 Sec. III, seed 001 Table 1).
//!
//! # Geometry and controls
//! Positions are body axes from a datum (x forward, y starboard, z down), m. The main rotor's
//! hub sits `spindle_length_m` up the shaft from a pivot; the pilot's stick tilts the whole
//! rotor about the pivot (seed 000: "this spindle pivots about its lower end to tilt the entire
//! rotor fore and aft and laterally"). The shaft's aft tilt `theta_s` and its right tilt
//! `phi_s` come from the stick through linear maps in percent of travel:
//!
//! * longitudinal stick: 0 % fully forward, 100 % fully aft; aft stick tilts the rotor back;
//! * lateral stick: 0 % fully left, 100 % fully right; right stick tilts the rotor right;
//! * pedal: 0 % full left, 100 % full right; rudder trailing edge to starboard is positive;
//! * throttle: 0-100 %.
//!
//! Hub axes follow from body axes by a pitch of `theta_s` (back) and then a roll of `phi_s`
//! (right): `v_hub = R_x(phi_s) R_y(theta_s) v_body`, so the shaft's "up" (`-z_hub`) leans back
//! with `theta_s > 0`. Blade pitch is fixed (an autogyro has no cyclic); a helicopter's
//! collective would enter as a collective shift of the rotor ([`crate::components::rotor::Operating::collective_shift_rad`]).
//!
//! # The revolution-averaged model
//! [`Aircraft::averaged`] evaluates the rigid-body, rotorspeed, propeller-speed and inflow
//! equations with the rotor in its steady periodic motion at the present body state (the
//! trim model: every load is a mean over one rotor revolution). The rotor's mean forces and
//! aerodynamic moments reach the airframe at the hub, plus the gyroscopic couple
//! `-omega_hub x H` when the body rotates (`H` the blades' angular momentum beyond the frozen
//! disc the airframe's inertia holds), the hub's angular acceleration on the blades' inertia
//! beyond that disc, and the rotorspeed's change on the blades' angular momentum (a tilted
//! disc's across the shaft). The rotor turns freely on its bearing (no torque about the shaft:
//! an autogyro), so the blades' angular momentum about the shaft changes by the aerodynamic
//! torque alone. `Omega` is the rotor speed relative to the airframe (as a rotor tachometer
//! reads it), and the rotor turns about `-z_hub`, so its absolute spin is `Omega - r_hub` and
//! `I_Rb (dOmega/dt - dr_hub/dt) = Q + (omega_hub x H)_z + ((J - disc) w')_z - (I_Rb - I_R)
//! dr_hub/dt` (and, in the full model, the Coriolis torque of the flapping; `I_Rb` the flapped
//! blades' polar inertia, `I_R` the frozen disc's, `J - disc` the blades' inertia beyond it,
//! whose `zz` element the last term takes out): a tilted disc on a pitching or rolling
//! airframe, or a two-bladed rotor's inertia on a turning one, trades spin with the airframe
//! (tested by the full model's conservation of angular momentum in a vacuum). The airframe's angular
//! accelerations see the aircraft's inertia without the rotor's polar moment about the shaft
//! ([`rigid_body::derivatives_with_free_spins`]): yawing the airframe does not drag the rotor
//! round with it.
//!
//! # The blades' weight and the hub's acceleration
//! The blades' flap (teeter) equations see the apparent gravity at the hub, gravity less the
//! hub's acceleration, through their first mass moment ([`crate::components::rotor`]). The
//! hub accelerates with the body: `a_hub = a_cg + w' x arm + w x (w x arm)`, and by the rigid
//! body's translational equation the apparent gravity at the c.g., `g - a_cg`, is `-F/m` (`F`
//! every load but gravity). Both models take the body's accelerations from its loads, which
//! the blades' flapping changes in turn. The full model solves the two together at each
//! evaluation (`Aircraft::coupled`). The revolution-averaged model iterates its rotor's
//! periodic solution, from the steady motion's accelerations (`a_cg = w x V`, `w' = 0`: a
//! trim's, where a turn's load factor enters), to the accelerations its loads imply, within
//! the trim's tolerance on them; at a trim the first solution is the answer. A trim's Newton
//! steps solve under the steady motion's accelerations (the same root), and a linearisation
//! holds them and eliminates them as fast variables (`HubAccelerations`). Blades without a
//! first mass moment feel the angular acceleration alone; a rigid hub feels neither.
//!
//! # Propeller and engine
//! The propeller thrusts along body `+x` (a pusher), in the axial component of the local air
//! velocity. The air crossing its disc (angle of attack and sideslip at the propeller, body
//! rates included) gives an in-plane force and hub moments to first order in the crossing
//! speed ([`crate::components::propeller`], "At incidence"); the propeller's hub axes are body
//! `z`, body `y` and body `-x` for a propeller turning clockwise seen from behind (the rotor
//! module's sense), mirrored in the `x-z` plane for one turning anticlockwise. Its speed is governed (rpm from
//! throttle by a linear map) or driven by an engine whose shaft torque is
//! `throttle x P_max / Omega_rated`, a constant-torque piston engine; the torque reaction
//! rolls the airframe against the propeller's rotation. The engine's shaft carries only that
//! torque, so an engine-driven propeller is a free rotor about `x` as the main rotor is about
//! its shaft: `I_p (dOmega_p/dt + dp/dt) = Q_engine - Q_propeller` for a propeller turning
//! clockwise seen from behind, and its polar moment is out of the airframe's roll inertia. Its
//! spin's angular momentum beyond the airframe's, `I_p Omega_p` along `x` (with the
//! propeller's sense), gives the airframe the gyroscopic couple `-omega x h_p`: a yaw rate
//! pitches it, a pitch rate yaws it. A governed propeller is held at its speed relative to the
//! airframe, so it rolls with the airframe as part of its inertia, and the model gives it no
//! spin inertia.
//!
//! # Hub angle-of-attack correction
//! Seed 000 Sec. VII replaces the kinematic angle of attack at the hub by a factor times the
//! angle of attack at the c.g. (0.5 in the seed), to stand for the wake's skew as it approaches
//! the disc. With `hub_aoa_factor = Some(k)` the hub's air velocity turns in the body x-z
//! plane by `(k - 1) alpha_cg`, keeping its magnitude and its sideslip: in steady straight
//! flight, where the hub moves with the c.g., its angle is `k alpha_cg` as the seed says, and
//! what the airframe's rotation adds at the hub (pitch rate times the hub's arm) stays
//! kinematic, since the wake's skew acts on the free stream, not on the hub's own motion.
//! `k = 1` is the kinematic value exactly, as `None` is (no correction).

pub mod flapping;
pub mod linearise;
pub mod trim;

mod averaged;
mod controls;
mod drive;
mod full;
#[cfg(test)]
mod tests;

use crate::components::airframe::{Airframe, AirframeError};
use crate::components::inflow;
use crate::components::propeller::PropellerError;
use crate::components::rigid_body::{self, BodyError, BodyState, Loads, MassProperties};
use crate::components::rotor::{
    Hub, HubVelocity, Inflow, InflowModel, Numerics, Operating, Rotor, RotorError,
};
use serde::Serialize;
use thiserror::Error;

pub(crate) use averaged::HubAccelerations;
pub use averaged::{Averaged, ComponentLoads, RotorCache, RotorReport, State};
pub use controls::{ControlMaps, Controls, LinearMap};
pub use drive::{Drive, PropellerInstallation, Rotation};
pub use full::{FullDerivative, FullState};

/// The main rotor and its installation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MainRotor {
    pub rotor: Rotor,
    /// The point the spindle pivots about, m from the datum.
    pub pivot_m: [f64; 3],
    /// From the pivot up the shaft to the hub centre (teeter bolt), m.
    pub spindle_length_m: f64,
    /// Added to the blade pitch (zero for an autogyro: fixed-pitch blades).
    pub collective_shift_rad: f64,
    pub inflow: InflowModel,
    /// Dynamic inflow (seed 001 Eq. 3) or quasi-steady (in equilibrium with the loads at
    /// every instant) in the full model; the averaged model and trim use the equilibrium.
    pub inflow_dynamics: InflowDynamics,
    pub numerics: Numerics,
}

/// How the inflow follows the loads in the full model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Default)]
pub enum InflowDynamics {
    /// Seed 001 Eq. 3: `tau dv/dt = -v + L F`, three states.
    #[default]
    Dynamic,
    /// `v = L F` at every instant; the state's inflow is only the starting guess and its
    /// rate is zero.
    QuasiSteady,
}

/// The aircraft.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Aircraft {
    pub mass: MassProperties,
    /// Centre of mass, m from the datum.
    pub cg_m: [f64; 3],
    pub main_rotor: MainRotor,
    pub propeller: PropellerInstallation,
    pub airframe: Airframe,
    pub controls: ControlMaps,
    /// Seed 000's hub angle-of-attack factor; `None` for the kinematic angle.
    pub hub_aoa_factor: Option<f64>,
}

/// The air the aircraft flies in.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Air {
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
}

/// Why the model cannot be evaluated.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AircraftError {
    #[error("main rotor: {0}")]
    Rotor(#[from] RotorError),
    #[error("propeller: {0}")]
    Propeller(#[from] PropellerError),
    #[error("airframe: {0}")]
    Airframe(#[from] AirframeError),
    #[error("rigid body: {0}")]
    Body(#[from] BodyError),
    #[error("{name} must be {requirement}, got {value}")]
    Invalid {
        name: &'static str,
        requirement: &'static str,
        value: f64,
    },
    #[error("{name} must be at most {limit} ({why}), got {value}")]
    TooMany {
        name: &'static str,
        limit: usize,
        why: &'static str,
        value: f64,
    },
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Body-to-hub rotation `R_x(phi_s) R_y(theta_s)`, rows are the hub axes in body axes.
fn body_to_hub(theta_s: f64, phi_s: f64) -> [[f64; 3]; 3] {
    let (st, ct) = theta_s.sin_cos();
    let (sp, cp) = phi_s.sin_cos();
    [
        [ct, 0.0, -st],
        [sp * st, cp, sp * ct],
        [cp * st, -sp, cp * ct],
    ]
}

fn apply(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

fn apply_t(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

fn as_loads(f: [f64; 3], m: [f64; 3]) -> Loads {
    Loads {
        x_n: f[0],
        y_n: f[1],
        z_n: f[2],
        l_n_m: m[0],
        m_n_m: m[1],
        n_n_m: m[2],
    }
}

/// The hub's motion as a blade's flap equation sees it, hub axes: the apparent gravity at the
/// hub centre (`g - a_hub`, m/s^2) and the hub's angular acceleration (rad/s^2).
struct HubMotion {
    apparent_gravity: [f64; 3],
    angular_acceleration: [f64; 3],
}

/// The main rotor's frame: shaft tilt, body-to-hub rotation, the hub's arm from the c.g., its
/// air velocity and rates in hub axes.
struct RotorFrame {
    theta_s: f64,
    phi_s: f64,
    c: [[f64; 3]; 3],
    arm: [f64; 3],
    hub: HubVelocity,
    hub_rates: [f64; 3],
}

fn positive_state(name: &'static str, value: f64) -> Result<(), AircraftError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(AircraftError::Invalid {
            name,
            requirement: "positive and finite",
            value,
        })
    }
}

fn sum_loads(parts: &[Loads]) -> Loads {
    parts.iter().fold(Loads::default(), |a, l| Loads {
        x_n: a.x_n + l.x_n,
        y_n: a.y_n + l.y_n,
        z_n: a.z_n + l.z_n,
        l_n_m: a.l_n_m + l.l_n_m,
        m_n_m: a.m_n_m + l.m_n_m,
        n_n_m: a.n_n_m + l.n_n_m,
    })
}

impl Aircraft {
    /// Checks every component.
    pub fn validate(&self) -> Result<(), AircraftError> {
        self.mass.validate()?;
        self.main_rotor.rotor.validate()?;
        self.propeller.propeller.rotor.validate()?;
        self.airframe.validate()?;
        let finite3 = |v: &[f64; 3]| v.iter().all(|x| x.is_finite());
        if !(finite3(&self.cg_m)
            && finite3(&self.main_rotor.pivot_m)
            && finite3(&self.propeller.position_m))
        {
            return Err(AircraftError::Invalid {
                name: "positions",
                requirement: "finite",
                value: f64::NAN,
            });
        }
        let check = |name, value: f64, ok: bool, requirement| {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err(AircraftError::Invalid {
                    name,
                    requirement,
                    value,
                })
            }
        };
        let l = self.main_rotor.spindle_length_m;
        check("spindle_length_m", l, l >= 0.0, "non-negative")?;
        let b = self.propeller.propeller.blockage;
        check("blockage", b, (0.0..=1.0).contains(&b), "in [0, 1]")?;
        if let Some(k) = self.hub_aoa_factor {
            check("hub_aoa_factor", k, (0.0..=2.0).contains(&k), "in [0, 2]")?;
        }
        match self.propeller.drive {
            Drive::Governed { rpm } => {
                check(
                    "rpm at 0 %",
                    rpm.at_0_percent,
                    rpm.at_0_percent > 0.0,
                    "positive",
                )?;
                check(
                    "rpm at 100 %",
                    rpm.at_100_percent,
                    rpm.at_100_percent > 0.0,
                    "positive",
                )?;
            }
            Drive::Engine {
                max_power_w,
                rated_rpm,
                polar_inertia_kg_m2,
            } => {
                check("max_power_w", max_power_w, max_power_w > 0.0, "positive")?;
                check("rated_rpm", rated_rpm, rated_rpm > 0.0, "positive")?;
                check(
                    "polar_inertia_kg_m2",
                    polar_inertia_kg_m2,
                    polar_inertia_kg_m2 > 0.0,
                    "positive",
                )?;
            }
        }
        for (name, m) in [
            ("shaft_pitch map", self.controls.shaft_pitch_rad),
            ("shaft_roll map", self.controls.shaft_roll_rad),
            ("rudder map", self.controls.rudder_rad),
        ] {
            let ok = m.at_0_percent.is_finite()
                && m.at_100_percent.is_finite()
                && m.at_0_percent != m.at_100_percent;
            check(name, m.at_100_percent, ok, "finite with distinct ends")?;
        }
        // The airframe without its free rotors must keep a positive-definite inertia at every
        // stick position (the shaft tilts with the stick; the corners bound it).
        for (lon, lat) in [(0.0, 0.0), (0.0, 100.0), (100.0, 0.0), (100.0, 100.0)] {
            let stick = Controls {
                stick_longitudinal_percent: lon,
                stick_lateral_percent: lat,
                pedal_percent: 50.0,
                throttle_percent: 50.0,
            };
            rigid_body::angular_accelerations(&self.mass, [0.0; 3], &self.free_spins(&stick))?;
        }
        Ok(())
    }

    /// The main rotor's polar moment of inertia about its shaft, from the blades' flap data
    /// (thin rigid blades: `N_b (I_beta + 2 e S + e^2 m)` with `m = 4 S^2 / (3 I_beta)`).
    pub fn rotor_polar_inertia_kg_m2(&self) -> f64 {
        let r = &self.main_rotor.rotor;
        let (i, s, e) = (
            r.flap_inertia_kg_m2,
            r.flap_mass_moment_kg_m,
            r.hinge_offset_m,
        );
        let m = 4.0 * s * s / (3.0 * i);
        r.blades as f64 * (i + 2.0 * e * s + e * e * m)
    }

    /// The hub centre, m from the datum, at a shaft tilt.
    pub fn hub_position_m(&self, theta_s: f64, phi_s: f64) -> [f64; 3] {
        let c = body_to_hub(theta_s, phi_s);
        let up = apply_t(&c, [0.0, 0.0, -self.main_rotor.spindle_length_m]);
        let p = self.main_rotor.pivot_m;
        [p[0] + up[0], p[1] + up[1], p[2] + up[2]]
    }

    /// Whether the main rotor's flapping feels the hub's motion: on a hub that lets its blades
    /// flap, always, for every blade has a flap inertia `I` (a rotor file's is validated
    /// positive). The hub's angular acceleration acts through it and the first mass moment `S`,
    /// `(e S cos b + I) (w'.t)` (`Blade::apparent_gravity_flap_moment_at`), and the blades'
    /// weight and the hub's acceleration through `S` alone ([`Aircraft::blades_feel_weight`]).
    /// A rotor file with `S = 0` declares blades whose first moment about the hinge is nothing
    /// (a teetering pair underslung so that the coned pair's centre of mass is on the teeter
    /// bolt: issue 52, item 12; reports/investigations.md): their weight leaves the flapping
    /// alone, and the hub's angular acceleration does not (before, a gate on `S` left it out).
    fn blades_feel_the_hub(&self) -> bool {
        self.main_rotor.rotor.hub != Hub::Rigid
    }

    /// Whether the main rotor's flapping feels its blades' weight and the hub's acceleration:
    /// its blades have a first mass moment `S` about a hinge (or the teeter bar), on a hub that
    /// lets them flap.
    fn blades_feel_weight(&self) -> bool {
        let r = &self.main_rotor.rotor;
        r.flap_mass_moment_kg_m != 0.0 && r.hub != Hub::Rigid
    }

    /// The first of the body's accelerations `[g - a_cg, w']` ([`Aircraft::hub_motion`]) that
    /// the blades feel: all of them where they feel their weight, else the angular acceleration
    /// alone (index 3).
    fn first_felt_acceleration(&self) -> usize {
        if self.blades_feel_weight() { 0 } else { 3 }
    }

    /// The main rotor's operating state, its hub moving as `hub` says (hub axes). What the
    /// blades do not feel ([`Aircraft::blades_feel_the_hub`], [`Aircraft::blades_feel_weight`])
    /// changes none of the rotor's loads, and the operating state leaves it out: evaluations
    /// that differ only in attitude (a trim's, a linearisation's) then find the rotor in one
    /// operating state and share its periodic solution, unless its blades feel their weight.
    fn operating(
        &self,
        frame: &RotorFrame,
        omega: f64,
        inflow: Inflow,
        air: Air,
        hub: &HubMotion,
    ) -> Operating {
        let apparent_gravity = match self.blades_feel_weight() {
            true => hub.apparent_gravity,
            false => [0.0; 3],
        };
        let angular_acceleration = match self.blades_feel_the_hub() {
            true => hub.angular_acceleration,
            false => [0.0; 3],
        };
        Operating {
            omega_rad_s: omega,
            hub: frame.hub,
            inflow,
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
            collective_shift_rad: self.main_rotor.collective_shift_rad,
            hub_rates_rad_s: frame.hub_rates,
            apparent_gravity_m_s2: apparent_gravity,
            hub_angular_acceleration_rad_s2: angular_acceleration,
        }
    }

    /// The hub's motion, hub axes, for the body's accelerations
    /// `y = [g - a_cg, w']` (body axes: the apparent gravity at the c.g., m/s^2, and the angular
    /// acceleration, rad/s^2) at the body's rates `w`: the apparent gravity at the hub,
    /// `g - a_cg - w' x arm - w x (w x arm)` (`arm` from the c.g. to the hub), and `w'`.
    fn hub_motion(&self, frame: &RotorFrame, body: &BodyState, y: &[f64; 6]) -> HubMotion {
        let w = [body.p_rad_s, body.q_rad_s, body.r_rad_s];
        let w_dot = [y[3], y[4], y[5]];
        let about = cross(w_dot, frame.arm);
        let centripetal = cross(w, cross(w, frame.arm));
        HubMotion {
            apparent_gravity: apply(
                &frame.c,
                std::array::from_fn(|k| y[k] - about[k] - centripetal[k]),
            ),
            angular_acceleration: apply(&frame.c, w_dot),
        }
    }

    /// The body's accelerations in steady motion, `[g - a_cg, w']` (see
    /// [`Aircraft::hub_motion`]): the body holding its velocity `V` and rates `w`, the c.g.
    /// accelerates at `w x V` (a turn's centripetal acceleration; none in straight flight) and
    /// `w'` is zero. A trim's.
    fn steady_accelerations(b: &BodyState) -> [f64; 6] {
        let g = rigid_body::G_M_S2;
        let (st, ct) = b.theta_rad.sin_cos();
        let (sf, cf) = b.phi_rad.sin_cos();
        let turning = cross(
            [b.p_rad_s, b.q_rad_s, b.r_rad_s],
            [b.u_m_s, b.v_m_s, b.w_m_s],
        );
        [
            -g * st - turning[0],
            g * sf * ct - turning[1],
            g * cf * ct - turning[2],
            0.0,
            0.0,
            0.0,
        ]
    }

    /// The body's accelerations `[g - a_cg, w']` (see [`Aircraft::hub_motion`]) that the loads
    /// on it (gravity apart) and its state derivative imply: by the rigid body's translational
    /// equation (`V' + w x V = F/m + g`), the apparent gravity at the c.g. is `-F/m`.
    fn accelerations(&self, total: &Loads, body_dot: &BodyState) -> [f64; 6] {
        let m = self.mass.mass_kg;
        [
            -total.x_n / m,
            -total.y_n / m,
            -total.z_n / m,
            body_dot.p_rad_s,
            body_dot.q_rad_s,
            body_dot.r_rad_s,
        ]
    }

    /// The equilibrium inflow for the rotor's thrust and aerodynamic moments, the wake, and
    /// the inflow's rate (seed 001 Eq. 3) from the present inflow.
    fn inflow_response(
        &self,
        frame: &RotorFrame,
        loads: inflow::DrivingLoads,
        current: Inflow,
        air: Air,
    ) -> (Inflow, inflow::Wake, Inflow) {
        let mr = &self.main_rotor;
        let r = mr.rotor.radius_m;
        match mr.inflow {
            InflowModel::Prescribed { v0, v1s, v1c } => (
                Inflow { v0, v1s, v1c },
                inflow::wake(
                    frame.hub,
                    v0,
                    crate::components::rotor::WakeModel::SEED_001,
                    0.0,
                ),
                Inflow::default(),
            ),
            InflowModel::PetersHaQuang { wake } | InflowModel::UniformOnly { wake } => {
                let harmonics = matches!(mr.inflow, InflowModel::PetersHaQuang { .. });
                let (eq, wake) = inflow::static_inflow(
                    loads,
                    frame.hub,
                    current.v0,
                    air.density_kg_m3,
                    r,
                    (wake, harmonics),
                );
                let rate = inflow::inflow_rate(current, eq, frame.hub, wake, r);
                (eq, wake, rate)
            }
        }
    }

    /// The force on the airframe at the hub, hub axes: the rotor's `force` and the hub's own
    /// drag in the air it moves through.
    fn hub_force(&self, force: [f64; 3], frame: &RotorFrame, air: Air) -> [f64; 3] {
        let drag = self
            .main_rotor
            .rotor
            .hub_drag_n(air.density_kg_m3, frame.hub);
        [force[0] + drag[0], force[1] + drag[1], force[2] + drag[2]]
    }

    /// Rotor hub loads (hub axes, with no shaft torque: a free rotor) to body loads about the c.g.
    fn rotor_to_body(frame: &RotorFrame, force_hub: [f64; 3], moment_hub: [f64; 3]) -> Loads {
        let f_body = apply_t(&frame.c, force_hub);
        let m_body = apply_t(&frame.c, moment_hub);
        let transfer = cross(frame.arm, f_body);
        as_loads(
            f_body,
            [
                m_body[0] + transfer[0],
                m_body[1] + transfer[1],
                m_body[2] + transfer[2],
            ],
        )
    }
}
