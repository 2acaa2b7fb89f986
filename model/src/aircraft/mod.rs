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
//! `-omega_hub x H` when the body rotates. The rotor turns freely on its bearing (no torque
//! about the shaft: an autogyro), so only the aerodynamic torque changes its absolute spin.
//! `Omega` is the rotor speed relative to the airframe (as a rotor tachometer reads it), and
//! the rotor turns about `-z_hub`, so its absolute spin is `Omega - r_hub` and
//! `I_R (dOmega/dt - dr_hub/dt) = Q`. The airframe's angular accelerations see the aircraft's
//! inertia without the rotor's polar moment about the shaft
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
//! evaluation ([`Aircraft::coupled`]). The revolution-averaged model iterates its rotor's
//! periodic solution, from the steady motion's accelerations (`a_cg = w x V`, `w' = 0`: a
//! trim's, where a turn's load factor enters), to the accelerations its loads imply, within
//! the trim's tolerance on them; at a trim the first solution is the answer. Rotors whose
//! blades have no first mass moment skip both.
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
//! clockwise seen from behind, and its polar moment is out of the airframe's roll inertia. A
//! governed propeller is held at its speed relative to the airframe, so it rolls with the
//! airframe as part of its inertia.
//!
//! # Hub angle-of-attack correction
//! Seed 000 Sec. VII replaces the kinematic angle of attack at the hub by a factor times the
//! angle of attack at the c.g. (0.5 in the seed), to stand for the wake's skew as it approaches
//! the disc. With `hub_aoa_factor = Some(k)` the hub's air velocity keeps its magnitude in the
//! body x-z plane and its sideslip, and its angle is `k alpha_cg`. `None` is the kinematic
//! value (no correction).

pub mod flapping;
pub mod linearise;
pub mod trim;

use crate::components::airframe::{Airframe, AirframeError, Slipstream};
use crate::components::inflow;
use crate::components::propeller::{Propeller, PropellerError, PropellerState};
use crate::components::rigid_body::{self, BodyError, BodyState, FreeSpin, Loads, MassProperties};
use crate::components::rotor::{
    Angles, Blade, Hub, HubVelocity, Inflow, InflowModel, Numerics, Operating, RevolutionMap,
    Rotor, RotorError, SteadyLoads,
};
use serde::Serialize;
use std::f64::consts::PI;
use thiserror::Error;

/// A linear map from a control position in percent of travel to an angle or speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LinearMap {
    pub at_0_percent: f64,
    pub at_100_percent: f64,
}

impl LinearMap {
    /// The mapped value at `percent` (not clamped: a trim outside 0-100 % is reported as such).
    pub fn at(&self, percent: f64) -> f64 {
        self.at_0_percent + (self.at_100_percent - self.at_0_percent) * percent / 100.0
    }

    /// The inverse map.
    pub fn percent_for(&self, value: f64) -> f64 {
        100.0 * (value - self.at_0_percent) / (self.at_100_percent - self.at_0_percent)
    }
}

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

/// How the propeller is driven.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Drive {
    /// Propeller rpm set by the throttle (a governed engine): no propeller-speed state.
    Governed { rpm: LinearMap },
    /// A constant-torque piston engine: shaft torque `throttle/100 x max_power_w / rated
    /// speed`, propeller speed a state with the polar inertia of engine and propeller.
    Engine {
        max_power_w: f64,
        rated_rpm: f64,
        polar_inertia_kg_m2: f64,
    },
}

/// Sense of the propeller's rotation, seen from behind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Rotation {
    Clockwise,
    Anticlockwise,
}

impl Rotation {
    /// The sign of the propeller's angular velocity along body `+x`.
    pub fn sense(self) -> f64 {
        match self {
            Self::Clockwise => 1.0,
            Self::Anticlockwise => -1.0,
        }
    }
}

/// The propeller and its installation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PropellerInstallation {
    pub propeller: Propeller,
    /// Disc centre, m from the datum.
    pub position_m: [f64; 3],
    pub drive: Drive,
    pub rotation: Rotation,
}

/// Control maps: stick, pedal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ControlMaps {
    /// Longitudinal stick (%) to the shaft's aft tilt, rad.
    pub shaft_pitch_rad: LinearMap,
    /// Lateral stick (%) to the shaft's right tilt, rad.
    pub shaft_roll_rad: LinearMap,
    /// Pedal (%) to rudder deflection, rad.
    pub rudder_rad: LinearMap,
}

/// Pilot's controls, percent of travel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct Controls {
    pub stick_longitudinal_percent: f64,
    pub stick_lateral_percent: f64,
    pub pedal_percent: f64,
    pub throttle_percent: f64,
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

/// The state of the revolution-averaged model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct State {
    pub body: BodyState,
    pub rotor_omega_rad_s: f64,
    /// Main-rotor inflow, hub axes, m/s.
    pub inflow: Inflow,
    /// Propeller speed (ignored when the drive is governed), rad/s.
    pub propeller_omega_rad_s: f64,
}

/// What the main rotor is doing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RotorReport {
    pub shaft_pitch_rad: f64,
    pub shaft_roll_rad: f64,
    /// The hub's air velocity in hub axes, m/s (after any hub angle-of-attack correction).
    pub hub_velocity: HubVelocity,
    /// Angle of attack of the disc (shaft normal plane) to the hub's air velocity, positive
    /// with the air meeting the disc from below, rad.
    pub disc_alpha_rad: f64,
    pub tip_speed_ratio: f64,
    pub thrust_n: f64,
    pub driving_torque_n_m: f64,
    pub a0_rad: f64,
    pub a1_rad: f64,
    pub b1_rad: f64,
    pub skew_rad: f64,
}

/// Loads of each component about the c.g., body axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ComponentLoads {
    pub rotor: Loads,
    pub propeller: Loads,
    pub airframe: Loads,
}

/// One evaluation of the revolution-averaged model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Averaged {
    /// Time derivative of the body state.
    pub body_dot: BodyState,
    pub rotor_omega_dot_rad_s2: f64,
    pub propeller_omega_dot_rad_s2: f64,
    /// The main-rotor inflow in equilibrium with the present loads, hub axes, m/s.
    pub inflow_equilibrium: Inflow,
    /// `d/dt` of the inflow (seed 001 Eq. 3), hub axes, m/s^2.
    pub inflow_dot: Inflow,
    pub rotor: RotorReport,
    pub propeller: PropellerState,
    pub propeller_omega_rad_s: f64,
    pub loads: ComponentLoads,
    /// The flap state at azimuth zero (a warm start for the next evaluation).
    pub flap_start: [f64; 2],
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

    /// The propeller's speed for a state and throttle.
    pub fn propeller_omega(&self, state: &State, controls: &Controls) -> f64 {
        match self.propeller.drive {
            Drive::Governed { rpm } => rpm.at(controls.throttle_percent) * PI / 30.0,
            Drive::Engine { .. } => state.propeller_omega_rad_s,
        }
    }

    /// The main rotor's frame at a body state and stick setting.
    /// The shaft's tilt `(theta_s, phi_s)` at a stick position.
    fn shaft_tilt(&self, controls: &Controls) -> (f64, f64) {
        let theta_s = self
            .controls
            .shaft_pitch_rad
            .at(controls.stick_longitudinal_percent);
        let phi_s = self
            .controls
            .shaft_roll_rad
            .at(controls.stick_lateral_percent);
        (theta_s, phi_s)
    }

    /// The body-to-hub rotation at a stick position (rows: the hub axes in body axes).
    fn rotor_frame_rotation(&self, controls: &Controls) -> [[f64; 3]; 3] {
        let (theta_s, phi_s) = self.shaft_tilt(controls);
        body_to_hub(theta_s, phi_s)
    }

    /// The main rotor hub's velocity through the air in hub axes (shaft axes: `w` along the
    /// shaft downwards, positive with the air coming up through the disc), at a body state and
    /// stick setting in a wind (body axes, m/s): what a flight test derives from air data,
    /// attitudes and the shaft's tilt (seed 003).
    pub fn hub_air_velocity(
        &self,
        body: &BodyState,
        controls: &Controls,
        wind_body_m_s: [f64; 3],
    ) -> HubVelocity {
        let air_body = BodyState {
            u_m_s: body.u_m_s - wind_body_m_s[0],
            v_m_s: body.v_m_s - wind_body_m_s[1],
            w_m_s: body.w_m_s - wind_body_m_s[2],
            ..*body
        };
        self.rotor_frame(&air_body, controls).hub
    }

    fn rotor_frame(&self, b: &BodyState, controls: &Controls) -> RotorFrame {
        let uvw = [b.u_m_s, b.v_m_s, b.w_m_s];
        let pqr = [b.p_rad_s, b.q_rad_s, b.r_rad_s];
        let (theta_s, phi_s) = self.shaft_tilt(controls);
        let c = body_to_hub(theta_s, phi_s);
        let arm = sub(self.hub_position_m(theta_s, phi_s), self.cg_m);
        let rot = cross(pqr, arm);
        let mut v_hub_body = [uvw[0] + rot[0], uvw[1] + rot[1], uvw[2] + rot[2]];
        if let Some(k) = self.hub_aoa_factor {
            let alpha_cg = uvw[2].atan2(uvw[0]);
            let vxz = v_hub_body[0].hypot(v_hub_body[2]);
            let (sa, ca) = (k * alpha_cg).sin_cos();
            v_hub_body = [vxz * ca, v_hub_body[1], vxz * sa];
        }
        let vh = apply(&c, v_hub_body);
        RotorFrame {
            theta_s,
            phi_s,
            c,
            arm,
            hub: HubVelocity {
                u: vh[0],
                v: vh[1],
                w: vh[2],
            },
            hub_rates: apply(&c, pqr),
        }
    }

    /// The main rotor's operating state, its hub moving as `hub` says (hub axes).
    fn operating(
        &self,
        frame: &RotorFrame,
        omega: f64,
        inflow: Inflow,
        air: Air,
        hub: &HubMotion,
    ) -> Operating {
        Operating {
            omega_rad_s: omega,
            hub: frame.hub,
            inflow,
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
            collective_shift_rad: self.main_rotor.collective_shift_rad,
            hub_rates_rad_s: frame.hub_rates,
            apparent_gravity_m_s2: hub.apparent_gravity,
            hub_angular_acceleration_rad_s2: hub.angular_acceleration,
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

    /// The rotors that turn freely about their shafts (see [`rigid_body::derivatives_with_free_spins`]):
    /// the main rotor, on a bearing that carries no torque about its shaft (an autogyro's rotor
    /// is driven by the air alone), and the propeller when an engine drives it at a set torque.
    /// A governed propeller is held at its speed relative to the airframe, so it turns with the
    /// airframe as part of it (its polar moment 0 here).
    pub fn free_spins(&self, controls: &Controls) -> [FreeSpin; 2] {
        self.free_spins_at(&self.rotor_frame_rotation(controls))
    }

    /// [`Aircraft::free_spins`] with the shaft from a body-to-hub rotation already formed.
    fn free_spins_at(&self, c: &[[f64; 3]; 3]) -> [FreeSpin; 2] {
        let propeller = match self.propeller.drive {
            Drive::Engine {
                polar_inertia_kg_m2,
                ..
            } => polar_inertia_kg_m2,
            Drive::Governed { .. } => 0.0,
        };
        [
            FreeSpin {
                axis: c[2],
                polar_inertia_kg_m2: self.rotor_polar_inertia_kg_m2(),
            },
            FreeSpin {
                axis: [1.0, 0.0, 0.0],
                polar_inertia_kg_m2: propeller,
            },
        ]
    }

    /// The rotor and propeller speeds' rates, relative to the airframe, from their rates under
    /// their own torques (`driven`: `Q / I`) and the airframe's angular acceleration. The
    /// rotor's absolute spin about the shaft is `Omega - r_hub` (it turns about `-z_hub`), so
    /// `I_R (Omega' - r_hub') = Q`; an engine-driven propeller turning clockwise seen from
    /// behind spins about `+x` at `Omega_p + p`, so `I_p (Omega_p' + p') = Q_e - Q_p`. The
    /// shaft's tilt rate is neglected, as in the hub's rates.
    fn spin_rates(
        &self,
        frame: &RotorFrame,
        rotor_driven: f64,
        propeller_driven: f64,
        body_dot: &BodyState,
    ) -> (f64, f64) {
        let w = [body_dot.p_rad_s, body_dot.q_rad_s, body_dot.r_rad_s];
        let z = frame.c[2];
        let r_hub_dot = z[0] * w[0] + z[1] * w[1] + z[2] * w[2];
        let propeller = match self.propeller.drive {
            Drive::Engine { .. } => propeller_driven - self.propeller.rotation.sense() * w[0],
            Drive::Governed { .. } => propeller_driven,
        };
        (rotor_driven + r_hub_dot, propeller)
    }

    /// Propeller and airframe: (propeller state, its loads, propeller acceleration, airframe loads).
    fn propeller_and_airframe(
        &self,
        b: &BodyState,
        prop_omega: f64,
        controls: &Controls,
        air: Air,
    ) -> Result<(PropellerState, Loads, f64, Loads), AircraftError> {
        let uvw = [b.u_m_s, b.v_m_s, b.w_m_s];
        let pqr = [b.p_rad_s, b.q_rad_s, b.r_rad_s];
        let pi = &self.propeller;
        if !(prop_omega.is_finite() && prop_omega > 0.0) {
            return Err(AircraftError::Invalid {
                name: "propeller speed (from the throttle or the state), rad/s",
                requirement: "positive",
                value: prop_omega,
            });
        }
        let parm = sub(pi.position_m, self.cg_m);
        let prot = cross(pqr, parm);
        let local = [uvw[0] + prot[0], uvw[1] + prot[1], uvw[2] + prot[2]];
        let axial = local[0].max(0.0);
        // The propeller's hub axes (module docs): x_h = body z, y_h = sense x body y, z_h =
        // -body x, so that it turns about -z_h as the rotor module's rotors do; an anticlockwise
        // propeller is the mirror image of a clockwise one in the body's x-z plane.
        let sense = pi.rotation.sense();
        let ps = pi.propeller.operate_checked(
            prop_omega,
            axial,
            [local[2], sense * local[1]],
            air.density_kg_m3,
            air.speed_of_sound_m_s,
        )?;
        let (engine_torque, prop_omega_dot) = match pi.drive {
            Drive::Governed { .. } => (ps.torque_n_m, 0.0),
            Drive::Engine {
                max_power_w,
                rated_rpm,
                polar_inertia_kg_m2,
            } => {
                let q = controls.throttle_percent / 100.0 * max_power_w / (rated_rpm * PI / 30.0);
                (q, (q - ps.torque_n_m) / polar_inertia_kg_m2)
            }
        };
        let [fx_h, fy_h] = ps.inplane_force_n;
        let [mx_h, my_h] = ps.inplane_moment_n_m;
        let pf = [ps.thrust_n, sense * fy_h, fx_h];
        let pm = cross(parm, pf);
        // Propeller turning clockwise seen from behind: its angular velocity is along +x, the
        // engine's reaction on the airframe along -x. Its hub moments: hub x is body z, hub y
        // body y (mirrored with the propeller's sense).
        let prop_loads = as_loads(
            pf,
            [
                pm[0] - sense * engine_torque,
                pm[1] + my_h,
                pm[2] + sense * mx_h,
            ],
        );
        let rudder = self.controls.rudder_rad.at(controls.pedal_percent);
        let slipstream = Slipstream::of_propeller(
            pi.position_m,
            pi.propeller.rotor.radius_m,
            sense,
            (ps.disc_airspeed_m_s, ps.v0_m_s),
            ps.torque_n_m,
            air.density_kg_m3,
        );
        let af = self.airframe.loads(
            uvw,
            pqr,
            air.density_kg_m3,
            self.cg_m,
            [0.0, rudder],
            Some(&slipstream),
        )?;
        Ok((ps, prop_loads, prop_omega_dot, af))
    }

    /// The revolution-averaged equations at a state and control setting.
    ///
    /// `warm` is the main rotor's flap state at azimuth zero to start the periodic solution
    /// from (pass the previous evaluation's `flap_start`).
    pub fn averaged(
        &self,
        state: &State,
        controls: &Controls,
        air: Air,
        warm: [f64; 2],
    ) -> Result<Averaged, AircraftError> {
        self.averaged_cached(state, controls, air, warm, &mut RotorCache::default())
    }

    /// [`Aircraft::averaged`], reusing the rotor's periodic solution when the rotor's operating
    /// state is one the cache has seen (perturbations of attitude, pedal, throttle or
    /// propeller speed leave it unchanged).
    pub fn averaged_cached(
        &self,
        state: &State,
        controls: &Controls,
        air: Air,
        warm: [f64; 2],
        cache: &mut RotorCache,
    ) -> Result<Averaged, AircraftError> {
        let b = &state.body;
        let mr = &self.main_rotor;
        let omega = state.rotor_omega_rad_s;
        positive_state("rotor_omega_rad_s", omega)?;
        let frame = self.rotor_frame(b, controls);
        let prop_omega = self.propeller_omega(state, controls);
        let (ps, prop_loads, prop_omega_dot, af) =
            self.propeller_and_airframe(b, prop_omega, controls, air)?;
        // The rotor's periodic solution with the hub's motion that the body's accelerations
        // imply, those accelerations depending on the rotor's loads in turn: from the steady
        // motion's (a trim's, exact there), until they agree (weightless blades: at once).
        let heavy = mr.rotor.flap_mass_moment_kg_m != 0.0 && mr.rotor.hub != Hub::Rigid;
        let mut y = Self::steady_accelerations(b);
        let mut warm = warm;
        let mut change = f64::INFINITY;
        for _ in 0..HUB_MOTION_ITERATIONS {
            let hub_motion = self.hub_motion(&frame, b, &y);
            let op = self.operating(&frame, omega, state.inflow, air, &hub_motion);
            let rl: SteadyLoads = match cache.entries.iter().find(|(o, _)| *o == op) {
                Some((_, l)) => *l,
                None => {
                    let l = Blade::new(&mr.rotor, mr.numerics).steady_with(
                        &op,
                        warm,
                        &mut cache.map,
                    )?;
                    cache.entries.push((op, l));
                    l
                }
            };
            // Loads on the airframe at the hub: mean force, mean aerodynamic moment with no
            // shaft torque (a free rotor), and the gyroscopic couple of the blades' motion
            // relative to the hub (the airframe's inertia holds the rotor as a frozen disc).
            let gyro = cross(op.hub_rates_rad_s, rl.angular_momentum_kg_m2_s);
            // The shaft's bearing carries no torque about the shaft: that part of the couple
            // would change the rotorspeed, as in the full model.
            let m_hub = [rl.moment_n_m[0] - gyro[0], rl.moment_n_m[1] - gyro[1], 0.0];
            let rotor_loads =
                Self::rotor_to_body(&frame, self.hub_force(rl.force_n, &frame, air), m_hub);
            let total = sum_loads(&[rotor_loads, prop_loads, af]);
            let body_dot = rigid_body::derivatives_with_free_spins(
                &self.mass,
                b,
                &total,
                &self.free_spins_at(&frame.c),
            )?;
            if heavy {
                let next = self.accelerations(&total, &body_dot);
                let g = rigid_body::G_M_S2;
                change = (0..6)
                    .map(|k| (next[k] - y[k]).abs() / if k < 3 { g } else { 1.0 })
                    .fold(0.0, f64::max);
                if change > HUB_MOTION_TOLERANCE {
                    (y, warm) = (next, rl.beta0);
                    continue;
                }
            }
            let driving = inflow::DrivingLoads::of(&rl);
            let (equilibrium, wake, inflow_dot) =
                self.inflow_response(&frame, driving, state.inflow, air);
            let (rotor_omega_dot, prop_omega_dot) = self.spin_rates(
                &frame,
                rl.driving_torque_n_m / self.rotor_polar_inertia_kg_m2(),
                prop_omega_dot,
                &body_dot,
            );
            let hub = frame.hub;
            let v_inplane = hub.u.hypot(hub.v);
            return Ok(Averaged {
                body_dot,
                rotor_omega_dot_rad_s2: rotor_omega_dot,
                propeller_omega_dot_rad_s2: prop_omega_dot,
                inflow_equilibrium: equilibrium,
                inflow_dot,
                rotor: RotorReport {
                    shaft_pitch_rad: frame.theta_s,
                    shaft_roll_rad: frame.phi_s,
                    hub_velocity: hub,
                    disc_alpha_rad: hub.w.atan2(v_inplane),
                    tip_speed_ratio: v_inplane / (omega * mr.rotor.radius_m),
                    thrust_n: rl.thrust_n(),
                    driving_torque_n_m: rl.driving_torque_n_m,
                    a0_rad: rl.a0_rad,
                    a1_rad: rl.a1_rad,
                    b1_rad: rl.b1_rad,
                    skew_rad: wake.skew_rad,
                },
                propeller: ps,
                propeller_omega_rad_s: prop_omega,
                loads: ComponentLoads {
                    rotor: rotor_loads,
                    propeller: prop_loads,
                    airframe: af,
                },
                flap_start: rl.beta0,
            });
        }
        Err(AircraftError::Invalid {
            name: "the body's accelerations and the rotor's flapping under them (no agreement in 20 periodic solutions; largest change, g or rad/s^2)",
            requirement: "convergent",
            value: change,
        })
    }

    /// The number of flap degrees of freedom of the main rotor: one per blade for an
    /// articulated hub, one teeter angle for a teetering hub, none for a rigid one.
    pub fn flap_dofs(&self) -> usize {
        match self.main_rotor.rotor.hub {
            Hub::Articulated => self.main_rotor.rotor.blades,
            Hub::Teetering => 1,
            Hub::Rigid => 0,
        }
    }

    /// The full individual-blade state at a trim point, with blade 1 at azimuth zero: the
    /// trim's periodic flapping, its inflow (held by Eq. 3 at its equilibrium), rotor and
    /// propeller speeds. For an articulated hub the other blades' states are found by
    /// integrating blade 1's periodic motion to their azimuths.
    pub fn full_state(
        &self,
        state: &State,
        controls: &Controls,
        air: Air,
        flap_start: [f64; 2],
    ) -> FullState {
        let mr = &self.main_rotor;
        let omega = state.rotor_omega_rad_s;
        let frame = self.rotor_frame(&state.body, controls);
        let steady = self.hub_motion(
            &frame,
            &state.body,
            &Self::steady_accelerations(&state.body),
        );
        let op = self.operating(&frame, omega, state.inflow, air, &steady);
        let blade = Blade::new(&mr.rotor, mr.numerics);
        let n = self.flap_dofs();
        let mut flap = Vec::with_capacity(n);
        if n > 0 {
            flap.push([flap_start[0], flap_start[1] * omega]);
        }
        if mr.rotor.hub == Hub::Articulated {
            // Blade k trails blade 1 by 2 pi k / N: it is where blade 1 was at -2 pi k / N,
            // i.e. where blade 1 will be at 2 pi (N - k) / N on its periodic path.
            let nb = mr.rotor.blades;
            let steps = 720;
            let h = 2.0 * PI / steps as f64;
            let mut s = flap_start;
            let mut at = vec![[0.0; 2]; nb];
            at[0] = s;
            for k in 0..steps {
                let next = {
                    let f = |psi: f64, x: [f64; 2]| blade.flap_derivative(&op, psi, x);
                    let psi = k as f64 * h;
                    let k1 = f(psi, s);
                    let k2 = f(
                        psi + h / 2.0,
                        [s[0] + h / 2.0 * k1[0], s[1] + h / 2.0 * k1[1]],
                    );
                    let k3 = f(
                        psi + h / 2.0,
                        [s[0] + h / 2.0 * k2[0], s[1] + h / 2.0 * k2[1]],
                    );
                    let k4 = f(psi + h, [s[0] + h * k3[0], s[1] + h * k3[1]]);
                    [
                        s[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
                        s[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
                    ]
                };
                s = next;
                let done = k + 1;
                if (done * nb).is_multiple_of(steps) {
                    // Blade 1 has reached 2 pi j / N, where blade j is now.
                    let j = done * nb / steps;
                    if j < nb {
                        at[j] = s;
                    }
                }
            }
            for x in at.iter().skip(1) {
                flap.push([x[0], x[1] * omega]);
            }
        }
        FullState {
            body: state.body,
            rotor_azimuth_rad: 0.0,
            rotor_omega_rad_s: omega,
            flap,
            inflow: state.inflow,
            propeller_omega_rad_s: self.propeller_omega(state, controls),
        }
    }

    /// The inflow in equilibrium with the rotor's instantaneous loads (quasi-steady inflow):
    /// damped fixed-point iteration from the state's inflow, to 1e-9 of the tip speed.
    fn quasi_steady_inflow(
        &self,
        frame: &RotorFrame,
        op: &Operating,
        air: Air,
        driving_at: &dyn Fn(&Operating) -> inflow::DrivingLoads,
    ) -> Result<Inflow, AircraftError> {
        let tip = op.omega_rad_s * self.main_rotor.rotor.radius_m;
        let mut o = *op;
        for _ in 0..200 {
            let (eq, _, _) = self.inflow_response(frame, driving_at(&o), o.inflow, air);
            let next = Inflow {
                v0: 0.5 * (o.inflow.v0 + eq.v0),
                v1s: 0.5 * (o.inflow.v1s + eq.v1s),
                v1c: 0.5 * (o.inflow.v1c + eq.v1c),
            };
            let change = (next.v0 - o.inflow.v0)
                .abs()
                .max((next.v1s - o.inflow.v1s).abs())
                .max((next.v1c - o.inflow.v1c).abs());
            o.inflow = next;
            if change <= 1e-9 * tip {
                return Ok(o.inflow);
            }
        }
        Err(AircraftError::Invalid {
            name: "quasi-steady inflow (no fixed point in 200 damped iterations), v0 m/s",
            requirement: "convergent",
            value: o.inflow.v0,
        })
    }

    /// The full model's right-hand side: individual blades at their azimuths with their own
    /// flap (or teeter) equations, dynamic inflow (seed 001 Eq. 3), the rotorspeed, propeller
    /// speed and rigid-body equations (seed 001 Eq. 1).
    ///
    /// The airframe's mass and inertia include the rotor as a frozen disc; the blades'
    /// motion relative to the hub enters the hub moment as `-(dH_rel/dt + omega_hub x H_rel)`
    /// (time derivative exact along the state's own rates, by the chain rule:
    /// [`Blade::angular_momentum_and_rate`]) and, through
    /// the blades' first mass moment, the hub force. The flap equations include the hub's
    /// rotation, and through the blades' first mass moment their weight and the hub's
    /// acceleration (the body's, solved with the blades': [`Aircraft::coupled`]; about a teeter
    /// hinge these cancel unless the blades are coned). The blades' own inertia under the hub's
    /// angular acceleration (`I w'.t`, [`crate::components::rotor`]) is not modelled. Lag is
    /// not modelled.
    pub fn derivatives(
        &self,
        x: &FullState,
        controls: &Controls,
        air: Air,
    ) -> Result<FullDerivative, AircraftError> {
        let mr = &self.main_rotor;
        let blade = Blade::new(&mr.rotor, mr.numerics);
        self.derivatives_with(&blade, x, controls, air, [0.0; 3])
    }

    /// [`Aircraft::derivatives`] in moving air: `wind_body_m_s` is the air's velocity over the
    /// ground in body axes (a gust; `+x` a tailwind, `+z` a downdraught). Every aerodynamic
    /// load (rotor, propeller, airframe and tail) sees the body's velocity less the wind's; the
    /// rigid-body equations keep the body's own. The wind is uniform over the aircraft: the
    /// gust's gradients (its rotational components) are not modelled.
    pub fn derivatives_in_wind(
        &self,
        x: &FullState,
        controls: &Controls,
        air: Air,
        wind_body_m_s: [f64; 3],
    ) -> Result<FullDerivative, AircraftError> {
        let mr = &self.main_rotor;
        let blade = Blade::new(&mr.rotor, mr.numerics);
        self.derivatives_with(&blade, x, controls, air, wind_body_m_s)
    }

    /// [`Aircraft::derivatives`] with the main rotor's blade elements prepared once
    /// (`Blade::new(&self.main_rotor.rotor, self.main_rotor.numerics)`), as a simulation does.
    pub(crate) fn derivatives_with(
        &self,
        blade: &Blade,
        x: &FullState,
        controls: &Controls,
        air: Air,
        wind_body_m_s: [f64; 3],
    ) -> Result<FullDerivative, AircraftError> {
        self.derivatives_given(blade, x, controls, air, wind_body_m_s, None)
    }

    /// [`Aircraft::derivatives_with`], the flap equations seeing the hub's motion that follows
    /// from the body's own accelerations (`given` none: the coupled solution of
    /// [`Aircraft::coupled`]) or from given ones: `[g - a_cg, w']`, the apparent gravity at the
    /// c.g. (m/s^2) and the body's angular acceleration (rad/s^2), body axes. Given the steady
    /// motion's (`g - w x V` and zero), the body is held as a trim holds it: the flap equations
    /// see what the rotor's periodic solution sees, and the body's accelerations returned are
    /// what it would do if let go.
    pub(crate) fn derivatives_given(
        &self,
        blade: &Blade,
        x: &FullState,
        controls: &Controls,
        air: Air,
        wind_body_m_s: [f64; 3],
        given: Option<[f64; 6]>,
    ) -> Result<FullDerivative, AircraftError> {
        // Long: the full right-hand side, load by load in the order of seed 001 Table 1; a hot
        // path, kept in one place so that the blades' angles are computed once
        let mr = &self.main_rotor;
        let rotor = &mr.rotor;
        let omega = x.rotor_omega_rad_s;
        positive_state("rotor_omega_rad_s", omega)?;
        if x.flap.len() != self.flap_dofs() {
            return Err(AircraftError::Invalid {
                name: "flap states",
                requirement: "one per flap degree of freedom of the hub",
                value: x.flap.len() as f64,
            });
        }
        // The air's velocity relative to the body: what every aerodynamic load sees.
        let air_body = BodyState {
            u_m_s: x.body.u_m_s - wind_body_m_s[0],
            v_m_s: x.body.v_m_s - wind_body_m_s[1],
            w_m_s: x.body.w_m_s - wind_body_m_s[2],
            ..x.body
        };
        let frame = self.rotor_frame(&air_body, controls);
        // The blades' loads do not depend on the hub's acceleration; the flap equations below
        // take it from the body's (`respond`), not from `op`.
        let still = HubMotion {
            apparent_gravity: [0.0; 3],
            angular_acceleration: [0.0; 3],
        };
        let op = self.operating(&frame, omega, x.inflow, air, &still);
        let psi1 = x.rotor_azimuth_rad;
        // Blades: (azimuth, beta, beta_dot).
        let mut blades: Vec<(f64, f64, f64)> = Vec::new();
        match rotor.hub {
            Hub::Articulated => {
                let nb = rotor.blades;
                for (k, f) in x.flap.iter().enumerate() {
                    blades.push((psi1 + 2.0 * PI * k as f64 / nb as f64, f[0], f[1]));
                }
            }
            Hub::Teetering => {
                let f = x.flap[0];
                let [(b1, d1), (b2, d2)] = blade.blade_flap(&op, [f[0], f[1] / omega]);
                blades.push((psi1, b1, d1));
                blades.push((psi1 + PI, b2, d2));
            }
            Hub::Rigid => {
                for k in 0..rotor.blades {
                    let psi = psi1 + 2.0 * PI * k as f64 / rotor.blades as f64;
                    blades.push((psi, rotor.precone_rad, 0.0));
                }
            }
        }
        // Each blade's angles' sines and cosines, once.
        let angles: Vec<Angles> = blades
            .iter()
            .map(|&(psi, beta, _)| Angles::new(psi, beta))
            .collect();
        let driving_at = |op: &Operating| {
            let mut d = inflow::DrivingLoads {
                thrust_n: 0.0,
                roll_n_m: 0.0,
                pitch_n_m: 0.0,
            };
            for (&(_, _, beta_dot), &ang) in blades.iter().zip(&angles) {
                let l = blade.loads_at(op, ang, beta_dot);
                d.thrust_n -= l.force[2];
                d.roll_n_m += l.moment[0];
                d.pitch_n_m += l.moment[1];
            }
            d
        };
        let mut op = op;
        if mr.inflow_dynamics == InflowDynamics::QuasiSteady {
            op.inflow = self.quasi_steady_inflow(&frame, &op, air, &driving_at)?;
        }
        let op = op;
        // Each blade's aerodynamic loads, once; the flap (teeter) accelerations from them.
        let loads: Vec<crate::components::rotor::BladeLoads> = blades
            .iter()
            .zip(&angles)
            .map(|(&(_, _, beta_dot), &ang)| blade.loads_at(&op, ang, beta_dot))
            .collect();
        let (i_b, k_b) = (rotor.flap_inertia_kg_m2, rotor.flap_spring_n_m_per_rad);
        let mut force = [0.0; 3];
        let mut moment = [0.0; 3];
        let mut torque = 0.0;
        let mut coriolis_torque = 0.0;
        for (&(_, beta, beta_dot), l) in blades.iter().zip(&loads) {
            for k in 0..3 {
                force[k] += l.force[k];
                moment[k] += l.moment[k];
            }
            torque += l.torque;
            // A blade flapping up comes nearer the shaft and speeds the rotor up.
            let (s_m, e) = (rotor.flap_mass_moment_kg_m, rotor.hinge_offset_m);
            coriolis_torque += 2.0 * omega * beta_dot * beta.sin() * (e * s_m + i_b * beta.cos());
        }
        let i_r = self.rotor_polar_inertia_kg_m2();
        let omega_dot = (torque + coriolis_torque) / i_r;
        let driving = inflow::DrivingLoads {
            thrust_n: -force[2],
            roll_n_m: moment[0],
            pitch_n_m: moment[1],
        };
        let inflow_dot = match mr.inflow_dynamics {
            InflowDynamics::Dynamic => self.inflow_response(&frame, driving, x.inflow, air).2,
            InflowDynamics::QuasiSteady => Inflow::default(),
        };
        let prop_omega = match self.propeller.drive {
            Drive::Governed { rpm } => rpm.at(controls.throttle_percent) * PI / 30.0,
            Drive::Engine { .. } => x.propeller_omega_rad_s,
        };
        let (_, prop_loads, prop_omega_dot, af) =
            self.propeller_and_airframe(&air_body, prop_omega, controls, air)?;
        let free = self.free_spins_at(&frame.c);
        // The flap (teeter) accelerations and the body's, with the hub's motion as the flap
        // equations see it (none: weightless blades).
        let respond = |hub: Option<&HubMotion>| -> Result<Response, AircraftError> {
            let mut flap_dot = Vec::with_capacity(x.flap.len());
            match rotor.hub {
                Hub::Articulated => {
                    for ((&(_, beta, beta_dot), l), &ang) in blades.iter().zip(&loads).zip(&angles)
                    {
                        let mut m = l.flap_moment
                            - blade.inertial_flap_moment_at(&op, ang)
                            - k_b * (beta - rotor.precone_rad);
                        if let Some(h) = hub {
                            m += blade.apparent_gravity_flap_moment_at(
                                h.apparent_gravity,
                                h.angular_acceleration,
                                ang,
                            );
                        }
                        flap_dot.push([beta_dot, m / i_b]);
                    }
                }
                Hub::Teetering => {
                    let f = x.flap[0];
                    let mut m = loads[0].flap_moment
                        - loads[1].flap_moment
                        - (blade.inertial_flap_moment_at(&op, angles[0])
                            - blade.inertial_flap_moment_at(&op, angles[1]))
                        - k_b * f[0];
                    if let Some(h) = hub {
                        let (g, w) = (h.apparent_gravity, h.angular_acceleration);
                        m += blade.apparent_gravity_flap_moment_at(g, w, angles[0])
                            - blade.apparent_gravity_flap_moment_at(g, w, angles[1]);
                    }
                    flap_dot.push([f[1], m / (2.0 * i_b)]);
                }
                Hub::Rigid => {}
            }
            // Inertial reaction of the blades' relative motion: H_rel along the state's rates.
            let beta_ddot: Vec<f64> = match rotor.hub {
                Hub::Articulated => flap_dot.iter().map(|d| d[1]).collect(),
                Hub::Teetering => vec![flap_dot[0][1], -flap_dot[0][1]],
                Hub::Rigid => vec![0.0; blades.len()],
            };
            // The blades' angular momentum beyond the frozen disc, its rate, and the motion of
            // their centres of mass, along the blades' motion (exact rates: the chain rule).
            let mut h0 = [0.0; 3];
            let mut dh = [0.0; 3];
            let mut f_hub = force;
            let cg_mass = rotor.blade_mass_kg();
            for (k, (&(_, _, beta_dot), &ang)) in blades.iter().zip(&angles).enumerate() {
                let (hb, hb_dot) =
                    blade.angular_momentum_and_rate(&op, ang, beta_dot, beta_ddot[k], omega_dot);
                for j in 0..3 {
                    h0[j] += hb[j];
                    dh[j] += hb_dot[j];
                }
                // The blade's centre of mass: relative acceleration and Coriolis.
                if cg_mass > 0.0 {
                    let [_, v, a] =
                        blade.centre_of_mass_motion(&op, ang, beta_dot, beta_ddot[k], omega_dot);
                    let cor = cross(frame.hub_rates, v);
                    for j in 0..3 {
                        f_hub[j] -= cg_mass * (a[j] + 2.0 * cor[j]);
                    }
                }
            }
            let gyro = cross(frame.hub_rates, h0);
            let m_hub = [
                moment[0] - dh[0] - gyro[0],
                moment[1] - dh[1] - gyro[1],
                // A free rotor: no torque through the shaft.
                0.0,
            ];
            let rotor_loads =
                Self::rotor_to_body(&frame, self.hub_force(f_hub, &frame, air), m_hub);
            let total = sum_loads(&[rotor_loads, prop_loads, af]);
            let body_dot =
                rigid_body::derivatives_with_free_spins(&self.mass, &x.body, &total, &free)?;
            Ok(Response {
                flap_dot,
                total,
                body_dot,
            })
        };
        let heavy = rotor.flap_mass_moment_kg_m != 0.0 && rotor.hub != Hub::Rigid;
        let Response {
            flap_dot, body_dot, ..
        } = if heavy {
            self.coupled(&frame, &x.body, &respond, given)?
        } else {
            respond(None)?
        };
        let (omega_dot, prop_omega_dot) =
            self.spin_rates(&frame, omega_dot, prop_omega_dot, &body_dot);
        Ok(FullDerivative {
            body: body_dot,
            rotor_azimuth_rad: omega,
            rotor_omega_rad_s: omega_dot,
            flap: flap_dot,
            inflow: inflow_dot,
            propeller_omega_rad_s: prop_omega_dot,
        })
    }

    /// The full model's accelerations with the blades' weight and the hub's acceleration in
    /// their flap equations, `respond` giving them for a given hub motion.
    ///
    /// The blades' and the body's accelerations are coupled. A flap equation sees the apparent
    /// gravity at the hub, `g - a_hub` with `a_hub = a_cg + w' x arm + w x (w x arm)`, and the
    /// hub's angular acceleration `w'` (the hinge's share, [`crate::components::rotor`]); the
    /// body's accelerations depend in turn on the blades' flap accelerations, through the
    /// motion of their mass centres (the hub force) and their angular momentum (the hub
    /// moment). By the rigid body's translational equation (`V' + w x V = F/m + g`) the apparent
    /// gravity at the c.g., `g - a_cg`, is `-F/m`, `F` every load but gravity. Every term is
    /// affine in the accelerations, so the coupled equations are solved exactly at each
    /// evaluation and the right-hand side stays a function of the state alone: with
    /// `y = (-F/m, w')` in body axes, `respond` (the blades' aerodynamic loads, the propeller
    /// and the airframe computed once, outside it) maps an assumed `y` to the `y` it implies,
    /// `b + A y`; seven calls give `b` and `A` (exactly: the map is affine), and
    /// `(1 - A) y = b` is solved by LU. This is the mass matrix's coupling solved as a linear
    /// system, as an individual-blade simulation that carries the blades' inertia does; taking
    /// the accelerations from the previous evaluation instead would make the derivative depend
    /// on the integrator's history. The coupling is small but not neglected: along the shaft,
    /// each blade's flap acceleration answers an acceleration `a` with `S a / I` and pushes back
    /// on the body with `S^2 a / (I m)`, so `A`'s largest eigenvalue is about
    /// `(3/4) N_b m_blade / m` for uniform blades (`S^2 / I = 3 m_blade / 4`). Measured for the
    /// test gyroplane with uniform blades: 0.077 with three articulated blades of 14.7 kg on
    /// 450 kg (0.074 by the formula), 0.012 with its two teetering blades of 9.8 kg, which feel
    /// the hub's acceleration only through their precone.
    ///
    /// With `given` accelerations (`y`), the flap equations see the hub's motion they imply
    /// instead ([`Aircraft::derivatives_given`]).
    fn coupled(
        &self,
        frame: &RotorFrame,
        body: &BodyState,
        respond: &dyn Fn(Option<&HubMotion>) -> Result<Response, AircraftError>,
        given: Option<[f64; 6]>,
    ) -> Result<Response, AircraftError> {
        let hub = |y: &[f64; 6]| self.hub_motion(frame, body, y);
        if let Some(y) = given {
            return respond(Some(&hub(&y)));
        }
        let image = |r: &Response| self.accelerations(&r.total, &r.body_dot);
        let base = image(&respond(Some(&hub(&[0.0; 6])))?);
        let mut system = nalgebra::Matrix6::<f64>::identity();
        for j in 0..6 {
            let mut unit = [0.0; 6];
            unit[j] = 1.0;
            let column = image(&respond(Some(&hub(&unit)))?);
            for i in 0..6 {
                system[(i, j)] -= column[i] - base[i];
            }
        }
        let y =
            system
                .lu()
                .solve(&nalgebra::Vector6::from(base))
                .ok_or(AircraftError::Invalid {
                    name: "the blades' and the body's coupled accelerations (a singular system)",
                    requirement: "solvable",
                    value: f64::NAN,
                })?;
        respond(Some(&hub(&std::array::from_fn(|k| y[k]))))
    }
}

/// How closely the revolution-averaged model's body accelerations must agree with those its
/// rotor's flapping was solved under (the apparent gravity at the c.g. in g, the angular
/// acceleration in rad/s^2): the trim's own tolerance on them.
const HUB_MOTION_TOLERANCE: f64 = 1e-7;

/// How many periodic solutions the revolution-averaged model may take to find them.
const HUB_MOTION_ITERATIONS: usize = 20;

/// The hub's motion as a blade's flap equation sees it, hub axes: the apparent gravity at the
/// hub centre (`g - a_hub`, m/s^2) and the hub's angular acceleration (rad/s^2).
struct HubMotion {
    apparent_gravity: [f64; 3],
    angular_acceleration: [f64; 3],
}

/// The full model's accelerations for a given hub motion: the flap (teeter) states' rates, the
/// loads on the body about the c.g. (gravity apart), and the body's state derivative.
struct Response {
    flap_dot: Vec<[f64; 2]>,
    total: Loads,
    body_dot: BodyState,
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

/// Rotor periodic solutions already computed, by operating state, and what the last of them
/// learned about the rotor's revolution map (to find the next nearby one in fewer
/// revolutions).
#[derive(Debug, Clone, Default)]
pub struct RotorCache {
    entries: Vec<(Operating, SteadyLoads)>,
    map: RevolutionMap,
}

/// The full individual-blade state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FullState {
    pub body: BodyState,
    /// Azimuth of blade 1, rad.
    pub rotor_azimuth_rad: f64,
    pub rotor_omega_rad_s: f64,
    /// Per flap degree of freedom: angle (rad) and rate (rad/s). Articulated: blade k at
    /// `psi + 2 pi k / N`; teetering: the teeter angle (blade 1 up).
    pub flap: Vec<[f64; 2]>,
    /// Main-rotor inflow, hub axes, m/s.
    pub inflow: Inflow,
    pub propeller_omega_rad_s: f64,
}

/// Time derivative of a [`FullState`] (same layout).
pub type FullDerivative = FullState;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aircraft::trim::{self, Condition, Options};
    use crate::testdata::gyroplane;

    use crate::testdata::sea_level_air as air;

    /// The individual-blade right-hand side, averaged over one revolution along the blades'
    /// own periodic motion, gives back the trim: the revolution-averaged and full models are
    /// the same physics. Teetering and articulated hubs; level flight and a turn (hub rates,
    /// gyroscopic terms).
    #[test]
    fn the_full_model_averages_to_the_trim() {
        for (hub, turn, qs) in [
            (Hub::Teetering, 0.0, false),
            (Hub::Teetering, 0.15, false),
            (Hub::Articulated, 0.15, false),
            (Hub::Articulated, 0.0, true),
        ] {
            let mut a = gyroplane();
            if qs {
                a.main_rotor.inflow_dynamics = InflowDynamics::QuasiSteady;
            }
            if hub == Hub::Articulated {
                a.main_rotor.rotor.hub = Hub::Articulated;
                a.main_rotor.rotor.blades = 3;
                a.main_rotor.rotor.flap_inertia_kg_m2 *= 1.5;
                a.main_rotor.rotor.precone_rad = 0.0;
            }
            let c = Condition {
                airspeed_m_s: 31.3,
                climb_m_s: 0.0,
                turn_rate_rad_s: turn,
                air: air(),
            };
            let t = trim::trim(&a, c, Options::default()).unwrap();
            let x = a.full_state(&t.state, &t.controls, air(), t.averaged.flap_start);
            let start = x.flap.clone();
            let (mean, x) = full_mean(&a, x, &t.controls, 0);
            // Quasi-steady inflow follows the instantaneous loads, so the trim's flapping (with
            // the mean-load inflow) is only nearly periodic under it.
            for (s, e) in x.flap.iter().zip(&start).filter(|_| !qs) {
                assert!(
                    (s[0] - e[0]).abs() < 1e-6,
                    "{hub:?}: flapping not periodic: {s:?} vs {e:?}"
                );
            }
            // The trim's accelerations are zero to 1e-7 g and rad/s^2; the full model's mean
            // matches them to the azimuth discretisation (5 deg in the trim, 2.5 deg here):
            // measured below 4e-6 g, 2e-3 rad/s^2 and 5e-6 /s in rotorspeed (quasi-steady
            // inflow: 1.3e-4 g, 3.5e-3 rad/s^2, 5e-5 /s).
            assert_mean_accelerations_small(
                &mean,
                x.rotor_omega_rad_s,
                &format!("{hub:?} turn {turn}"),
            );
        }
    }

    /// The full model's accelerations averaged over a revolution at a trim are the trim's
    /// zeros to the azimuth discretisation: below 2e-3 g (`u v w`), 2e-2 rad/s^2 (`p q r`)
    /// and 1e-3 of the rotor speed per second (measured below 4e-6 g, 2e-3 rad/s^2 and
    /// 5e-6 /s with dynamic inflow; 1.3e-4 g, 3.5e-3 rad/s^2 and 5e-5 /s quasi-steady).
    fn assert_mean_accelerations_small(mean: &[f64], rotor_omega_rad_s: f64, label: &str) {
        let g = rigid_body::G_M_S2;
        assert!(
            mean[..3].iter().all(|v| (v / g).abs() < 2e-3),
            "{label}: {mean:?}"
        );
        assert!(
            mean[3..6].iter().all(|v| v.abs() < 2e-2),
            "{label}: {mean:?}"
        );
        assert!(
            mean[6].abs() / rotor_omega_rad_s < 1e-3,
            "{label}: {mean:?}"
        );
    }

    /// The test gyroplane with heavy blades: a first mass moment `S = 3 I / (2 R)` (a uniform
    /// blade from the axis, as the PCA-2 rotor file estimates its own), on its teetering hub
    /// or on an articulated one (three blades, half as much inertia again, no precone, the hinge
    /// at `hinge_offset_m`).
    fn heavy(hub: Hub, hinge_offset_m: f64) -> Aircraft {
        let mut a = gyroplane();
        let r = &mut a.main_rotor.rotor;
        if hub == Hub::Articulated {
            r.hub = Hub::Articulated;
            r.blades = 3;
            r.flap_inertia_kg_m2 *= 1.5;
            r.precone_rad = 0.0;
            r.hinge_offset_m = hinge_offset_m;
        }
        r.flap_mass_moment_kg_m = 1.5 * r.flap_inertia_kg_m2 / r.radius_m;
        a
    }

    /// The blades' weight and the hub's acceleration are the same physics in the trim and the
    /// full model. With heavy blades, in level flight and in a steady level turn at 0.25 rad/s
    /// (load factor 1.28 at 31.3 m/s), teetering (its precone leaves the pair's weight and the
    /// hub's acceleration a teeter moment) and articulated, on the axis and with a hinge offset:
    ///
    /// * held in the trim's steady motion (the flap equations seeing the trim's hub motion), the
    ///   full model flies the trim's periodic flapping round a revolution back to where it
    ///   began, with the trim's harmonics, within `HELD_FLAP_RAD`;
    /// * free (the flap equations seeing the body's own accelerations, solved with the
    ///   blades'), its mean accelerations are the trim's zero within the bounds of
    ///   `the_full_model_averages_to_the_trim`, and an articulated rotor's flapping is the
    ///   trim's within `FREE_FLAP_RAD`. A teeter's is not: see `TEETER_SHAKE_RAD`.
    ///
    /// The weight and the hub's acceleration move the trim's flapping by at least 20 times
    /// these bounds (the same state with weightless blades).
    #[test]
    fn the_full_model_averages_to_the_trim_with_heavy_blades_level_and_turning() {
        let g = rigid_body::G_M_S2;
        for (hub, e, turn) in [
            (Hub::Teetering, 0.0, 0.0),
            (Hub::Teetering, 0.0, 0.25),
            (Hub::Articulated, 0.0, 0.0),
            (Hub::Articulated, 0.0, 0.25),
            (Hub::Articulated, 0.2, 0.25),
        ] {
            let case = format!("{hub:?} e {e} m, turn {turn} rad/s");
            let a = heavy(hub, e);
            let c = Condition {
                airspeed_m_s: 31.3,
                climb_m_s: 0.0,
                turn_rate_rad_s: turn,
                air: air(),
            };
            let t = trim::trim(&a, c, Options::default()).unwrap();
            let r = &t.averaged.rotor;
            let trimmed = [r.a0_rad, r.a1_rad, r.b1_rad];
            // What the blades' weight and the hub's acceleration do to the trim's flapping: the
            // same state with weightless blades.
            let mut light = a.clone();
            light.main_rotor.rotor.flap_mass_moment_kg_m = 0.0;
            let w = light
                .averaged(&t.state, &t.controls, air(), t.averaged.flap_start)
                .unwrap()
                .rotor;
            let effect = [w.a0_rad, w.a1_rad, w.b1_rad]
                .iter()
                .zip(trimmed)
                .map(|(w, t)| (t - w).abs())
                .fold(0.0, f64::max);
            let tested = match hub {
                Hub::Articulated => FREE_FLAP_RAD,
                _ => HELD_FLAP_RAD,
            };
            assert!(
                effect > 20.0 * tested,
                "{case}: the weight moves the flapping by only {effect:e} rad"
            );
            // The steady motion's accelerations, by the rigid body's kinematics: the apparent
            // gravity at the c.g. g - w x V, and no angular acceleration.
            let b = &t.state.body;
            let (st, ct) = b.theta_rad.sin_cos();
            let (sf, cf) = b.phi_rad.sin_cos();
            let turning = cross(
                [b.p_rad_s, b.q_rad_s, b.r_rad_s],
                [b.u_m_s, b.v_m_s, b.w_m_s],
            );
            let held = [
                -g * st - turning[0],
                g * sf * ct - turning[1],
                g * cf * ct - turning[2],
                0.0,
                0.0,
                0.0,
            ];
            let blade = Blade::new(&a.main_rotor.rotor, a.main_rotor.numerics);
            let x = a.full_state(&t.state, &t.controls, air(), t.averaged.flap_start);
            for (body, deriv) in [
                (
                    "held",
                    &(|x: &FullState| {
                        a.derivatives_given(&blade, x, &t.controls, air(), [0.0; 3], Some(held))
                            .unwrap()
                    }) as &dyn Fn(&FullState) -> FullDerivative,
                ),
                ("free", &|x: &FullState| {
                    a.derivatives(x, &t.controls, air()).unwrap()
                }),
            ] {
                let (mean, flap, end) = full_revolution(&a, x.clone(), 0, deriv);
                let departure = end
                    .flap
                    .iter()
                    .zip(&x.flap)
                    .map(|(s, e)| (s[0] - e[0]).abs())
                    .fold(0.0, f64::max);
                let harmonics = (0..3)
                    .map(|k| (flap[k] - trimmed[k]).abs())
                    .fold(0.0, f64::max);
                eprintln!(
                    "{case}, {body}: effect {effect:.3e} rad, departure {departure:.3e} rad, harmonics {harmonics:.3e} rad"
                );
                let bound = match (body, hub) {
                    ("held", _) => HELD_FLAP_RAD,
                    (_, Hub::Articulated) => FREE_FLAP_RAD,
                    _ => TEETER_SHAKE_RAD,
                };
                assert!(
                    departure < bound && harmonics < bound,
                    "{case}, {body}: the trim's flapping is not the full model's: back by \
                     {departure:e} rad after a revolution; harmonics {flap:?} against the \
                     trim's {trimmed:?} (the weight moves them by {effect:e})"
                );
                assert_mean_accelerations_small(
                    &mean,
                    x.rotor_omega_rad_s,
                    &format!("{case}, {body}"),
                );
            }
        }
    }

    /// How far the full model's flapping may stray from the trim's in a revolution, with the
    /// body held in the trim's steady motion, rad: the trim's azimuth step (5 deg) against the
    /// full model's here (2.5 deg). Measured at most 8.4e-8 rad over the five cases.
    const HELD_FLAP_RAD: f64 = 2e-7;

    /// How far an articulated rotor's flapping may stray from the trim's in a revolution with
    /// the body free, rad. Three blades shake the body three times a revolution, and through
    /// `S` the flap equations feel that shaking, which the trim's steady hub does not have.
    /// Measured 1.0e-5 rad in level flight, 5e-7 rad turning; three times the larger.
    const FREE_FLAP_RAD: f64 = 3e-5;

    /// How far a teeter's flapping strays from the trim's with the body free, rad: a known
    /// difference between the two models, guarded at its measured size. The coned pair (3.4 deg
    /// of precone, and no undersling: the model has none) moves its mass centre off the shaft
    /// as it teeters, and the Coriolis forces of the blades' motion in and out shake the hub in
    /// its plane twice a revolution: 3.2 m/s^2 at the hub in level flight (0.6 m/s^2 with
    /// weightless blades; measured). Through the precone that shaking forces the teeter once a
    /// revolution, where it is tuned, and moves its flapping by 2.2e-5 rad in level flight and
    /// 7.5e-6 rad turning, as much as the weight itself (2.3e-5 and 2.8e-5 rad). A rotor on a
    /// hub in steady motion (the trim) cannot have it; the full model's own periodic orbit
    /// ([`crate::simulation::periodic_trim::periodic_trim`]) does. Real teetering hubs are underslung to keep the pair's
    /// mass centre on the shaft.
    const TEETER_SHAKE_RAD: f64 = 3e-5;

    /// The full model solves the blades' and the body's accelerations together: its flap
    /// equations see the hub's motion that the body's accelerations it returns imply. Given
    /// those accelerations back (the apparent gravity at the c.g. `g - (V' + w x V)` by the
    /// rigid body's kinematics, and `w'`), it returns the same derivative, to rounding. Heavy
    /// blades, teetering and articulated with a hinge offset, off trim (body rates, sideslip
    /// and a rotor azimuth between blades) so that every term is alive. And the hub's motion
    /// matters as the rotor module's derivation says: against the c.g. in free fall, the flap
    /// accelerations differ by `S (f - w' x e r).n / I` per blade, and for a teeter by
    /// `2 S sin(precone) (cos delta (f_x cos psi - f_y sin psi) + f_z sin delta) / (2 I)`, `f`
    /// the apparent gravity at the hub and `w'` the angular acceleration (hub axes).
    #[test]
    fn the_full_models_blade_and_body_accelerations_are_solved_together() {
        let g = rigid_body::G_M_S2;
        for (hub, e) in [(Hub::Teetering, 0.0), (Hub::Articulated, 0.2)] {
            let a = heavy(hub, e);
            let t = trim::trim(&a, crate::testdata::level_70mph(), Options::default()).unwrap();
            let mut x = a.full_state(&t.state, &t.controls, air(), t.averaged.flap_start);
            x.body.p_rad_s += 0.1;
            x.body.q_rad_s -= 0.05;
            x.body.r_rad_s += 0.08;
            x.body.v_m_s += 1.0;
            x.rotor_azimuth_rad = 0.7;
            let free = a.derivatives(&x, &t.controls, air()).unwrap();
            let (b, d) = (&x.body, &free.body);
            let (st, ct) = b.theta_rad.sin_cos();
            let (sf, cf) = b.phi_rad.sin_cos();
            let w = [b.p_rad_s, b.q_rad_s, b.r_rad_s];
            let turning = cross(w, [b.u_m_s, b.v_m_s, b.w_m_s]);
            let implied = [
                -g * st - d.u_m_s - turning[0],
                g * sf * ct - d.v_m_s - turning[1],
                g * cf * ct - d.w_m_s - turning[2],
                d.p_rad_s,
                d.q_rad_s,
                d.r_rad_s,
            ];
            let blade = Blade::new(&a.main_rotor.rotor, a.main_rotor.numerics);
            let given = |y: [f64; 6]| {
                a.derivatives_given(&blade, &x, &t.controls, air(), [0.0; 3], Some(y))
                    .unwrap()
            };
            let back = given(implied);
            let (fb, bb) = (free.body.to_array(), back.body.to_array());
            for k in 0..6 {
                assert!(
                    (fb[k] - bb[k]).abs() < ROUNDING * fb[k].abs().max(1.0),
                    "{hub:?}: body {k}: {} against {}",
                    fb[k],
                    bb[k]
                );
            }
            for (f, b) in free.flap.iter().zip(&back.flap) {
                assert!(
                    (f[1] - b[1]).abs() < ROUNDING * f[1].abs().max(1.0),
                    "{hub:?}: flap {f:?} against {b:?}"
                );
            }
            // The flap accelerations' share of the hub's motion, by the closed forms of the
            // rotor module's docs: against `y = 0` (the c.g. in free fall, no angular
            // acceleration), the apparent gravity at the hub differs by `y - w' x arm` and the
            // angular acceleration by `w'`.
            let falling = given([0.0; 6]);
            let frame = a.rotor_frame(&x.body, &t.controls);
            let w_dot = [implied[3], implied[4], implied[5]];
            let about = cross(w_dot, frame.arm);
            let f = apply(&frame.c, std::array::from_fn(|k| implied[k] - about[k]));
            let w_hub = apply(&frame.c, w_dot);
            let rot = &a.main_rotor.rotor;
            let (s_m, i_b) = (rot.flap_mass_moment_kg_m, rot.flap_inertia_kg_m2);
            let want: Vec<f64> = match hub {
                Hub::Teetering => {
                    let (d, (sp, cp)) = (x.flap[0][0], x.rotor_azimuth_rad.sin_cos());
                    let pair = 2.0
                        * rot.precone_rad.sin()
                        * (d.cos() * (f[0] * cp - f[1] * sp) + f[2] * d.sin());
                    vec![s_m * pair / (2.0 * i_b)]
                }
                _ => (0..rot.blades)
                    .map(|k| {
                        let psi = x.rotor_azimuth_rad + 2.0 * PI * k as f64 / rot.blades as f64;
                        let ((sp, cp), (sb, cb)) = (psi.sin_cos(), x.flap[k][0].sin_cos());
                        let n = [sb * cp, -sb * sp, -cb];
                        let dot =
                            |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
                        // The hinge's acceleration from the hub's turning, w' x (e r).
                        let hinge = cross(w_hub, [-e * cp, e * sp, 0.0]);
                        s_m * (dot(f, n) - dot(hinge, n)) / i_b
                    })
                    .collect(),
            };
            for (k, want) in want.iter().enumerate() {
                let got = free.flap[k][1] - falling.flap[k][1];
                eprintln!(
                    "{hub:?} {k}: the hub's motion moves the flap acceleration by {got:e}, closed form {want:e}"
                );
                assert!(
                    (got - want).abs() < ROUNDING * want.abs().max(1.0) && want.abs() > 1e-3,
                    "{hub:?}, flap state {k}: the hub's motion moves the flap acceleration by \
                     {got:e} rad/s^2, the closed form by {want:e}"
                );
            }
        }
    }

    /// Rounding, relative: the coupled solution against its own accelerations given back (a
    /// 6 x 6 LU solve and the rigid body's kinematics, each of a few operations at 1e-16).
    const ROUNDING: f64 = 1e-9;

    /// Heavy blades on a hinge on the axis, with no spring, cone down by `S f_z / (I Omega^2)`,
    /// `f_z` the apparent gravity along the shaft (gravity less the hub's acceleration): the
    /// revolution mean of the flap equation, `I Omega^2 sin a0 cos a0 = M_aero + S f.n`
    /// (derived in [`crate::components::rotor`]), with `cos a0` taken as 1 and the
    /// aerodynamic moment held. Level flight (`f_z` about `g`) and a steady level turn at
    /// 0.25 rad/s (load factor 1.28). The apparent gravity is worked out here by hand in
    /// north-east-down axes, from the trim's attitudes and shaft tilt.
    #[test]
    fn heavy_blades_cone_down_by_the_apparent_gravity_at_the_hub() {
        let a = heavy(Hub::Articulated, 0.0);
        let mut light = a.clone();
        light.main_rotor.rotor.flap_mass_moment_kg_m = 0.0;
        let rot = &a.main_rotor.rotor;
        let (s_m, i_b) = (rot.flap_mass_moment_kg_m, rot.flap_inertia_kg_m2);
        let g = rigid_body::G_M_S2;
        let speed = 31.3;
        for turn in [0.0, 0.25] {
            let c = Condition {
                airspeed_m_s: speed,
                climb_m_s: 0.0,
                turn_rate_rad_s: turn,
                air: air(),
            };
            let t = trim::trim(&a, c, Options::default()).unwrap();
            let b = &t.state.body;
            let (theta_s, phi_s) = (
                t.averaged.rotor.shaft_pitch_rad,
                t.averaged.rotor.shaft_roll_rad,
            );
            // Heading zero: body axes are R_x(phi) R_y(theta) of north-east-down axes (the
            // form of the shaft's tilt, so `body_to_hub` writes it).
            let to_body = body_to_hub(b.theta_rad, b.phi_rad);
            let arm_earth = apply_t(&to_body, sub(a.hub_position_m(theta_s, phi_s), a.cg_m));
            // The c.g. flies north at V, turning at `turn` about down: its acceleration is
            // turn x V, toward the turn's centre; the hub's adds turn x (turn x arm).
            let spin = [0.0, 0.0, turn];
            let cg = cross(spin, [speed, 0.0, 0.0]);
            let about = cross(spin, cross(spin, arm_earth));
            let apparent_earth = [-cg[0] - about[0], -cg[1] - about[1], g - cg[2] - about[2]];
            let f_z = apply(
                &body_to_hub(theta_s, phi_s),
                apply(&to_body, apparent_earth),
            )[2];
            // The apparent gravity is the load factor's `n g` (and the hub's own centripetal
            // share, at most `turn^2 |arm|`, 0.9 % of it); along the shaft, tilted from the
            // apparent vertical by its tilt and the body's pitch, a few per cent less (measured
            // 0.9 % level, 1.9 % turning).
            let load_factor = (1.0 + (speed * turn / g).powi(2)).sqrt();
            assert!(
                f_z > 0.95 * load_factor * g && f_z < load_factor * g,
                "{f_z} against n g {}",
                load_factor * g
            );
            let heavy_a0 = t.averaged.rotor.a0_rad;
            let light_a0 = light
                .averaged(&t.state, &t.controls, air(), t.averaged.flap_start)
                .unwrap()
                .rotor
                .a0_rad;
            let omega = t.state.rotor_omega_rad_s;
            let want = -s_m * f_z / (i_b * omega * omega);
            let got = heavy_a0 - light_a0;
            eprintln!(
                "turn {turn}: n {load_factor}, f_z {f_z}, a0 {heavy_a0}, d a0 {got:e} against {want:e}, ratio {}",
                got / want
            );
            assert!(
                (got / want - 1.0).abs() < CONING_PER_G,
                "turn {turn} (load factor {load_factor:.3}): the blades cone down by {got:e} rad, \
                 S f_z / (I Omega^2) is {want:e}"
            );
        }
    }

    /// The hand formula's share of error, relative: it takes `cos a0` as 1 (0.2 % at the 2 deg
    /// of coning here) and holds the aerodynamic moment, which the coning's change moves in
    /// edgewise flow. Measured 0.2 % level and 0.8 % turning. (Without the hub's acceleration,
    /// the turn's coning change is `1 / n^2` of it, 40 % short.)
    const CONING_PER_G: f64 = 0.03;

    /// The hub's drag (a flat plate of area `f` at the hub) adds `-(rho/2) f |V| V` at the
    /// hub in both models, the revolution-averaged and the individual-blade one, and changes
    /// nothing else: at the trim (no rates, still air) the hub moves with the body, so the
    /// force lies along the body's velocity, and with the hub above the c.g. its moment is nose
    /// up.
    #[test]
    fn the_hubs_drag_is_a_flat_plate_at_the_hub_in_both_models() {
        let (a, t) = crate::testdata::trimmed_gyroplane(31.3);
        let f = 0.4;
        let mut dragged = a.clone();
        dragged.main_rotor.rotor.hub_drag_area_m2 = f;
        let b = &t.state.body;
        let v = [b.u_m_s, b.v_m_s, b.w_m_s];
        let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let want = v.map(|c| -0.5 * air().density_kg_m3 * f * speed * c);
        // 0.5 x 1.225 x 0.4 x 31.3^2: about 240 N against the flight path.
        assert!((want[0] + 240.0).abs() < 5.0, "{want:?}");
        let warm = t.averaged.flap_start;
        let before = a.averaged(&t.state, &t.controls, air(), warm).unwrap();
        let after = dragged
            .averaged(&t.state, &t.controls, air(), warm)
            .unwrap();
        let (l0, l1) = (before.loads.rotor, after.loads.rotor);
        let got = [l1.x_n - l0.x_n, l1.y_n - l0.y_n, l1.z_n - l0.z_n];
        for j in 0..3 {
            assert!(
                (got[j] - want[j]).abs() < 1e-9 * want[0].abs(),
                "{got:?} {want:?}"
            );
        }
        assert!(l1.m_n_m > l0.m_n_m, "{l0:?} {l1:?}");
        assert_eq!(before.rotor.thrust_n, after.rotor.thrust_n);
        assert_eq!(before.loads.airframe, after.loads.airframe);
        let x = a.full_state(&t.state, &t.controls, air(), warm);
        let d0 = a.derivatives(&x, &t.controls, air()).unwrap();
        let d1 = dragged.derivatives(&x, &t.controls, air()).unwrap();
        let m = a.mass.mass_kg;
        let du = [
            d1.body.u_m_s - d0.body.u_m_s,
            d1.body.v_m_s - d0.body.v_m_s,
            d1.body.w_m_s - d0.body.w_m_s,
        ];
        for j in 0..3 {
            assert!((du[j] - want[j] / m).abs() < 1e-9, "{du:?} {want:?}");
        }
        assert!(d1.body.q_rad_s > d0.body.q_rad_s);
    }

    /// A gust is air-relative velocity: flying at body velocity `V` in a wind `W` loads the
    /// aircraft exactly as flying at `V - W` in still air. Only the rigid body's kinematic terms
    /// (`r v - q w` and the like, and the position rates) see the body's own velocity. And a
    /// downdraught (air moving down) unloads the rotor: the body accelerates downward.
    #[test]
    fn a_gust_loads_the_aircraft_as_the_air_relative_velocity_does() {
        let a = gyroplane();
        let c = Condition {
            airspeed_m_s: 31.3,
            climb_m_s: 0.0,
            turn_rate_rad_s: 0.0,
            air: air(),
        };
        let t = trim::trim(&a, c, Options::default()).unwrap();
        let mut x = a.full_state(&t.state, &t.controls, air(), t.averaged.flap_start);
        (x.body.p_rad_s, x.body.q_rad_s, x.body.r_rad_s) = (0.05, 0.03, -0.04);
        let wind = [1.5, -0.8, 2.0];
        let in_wind = a.derivatives_in_wind(&x, &t.controls, air(), wind).unwrap();
        let mut relative = x.clone();
        relative.body.u_m_s -= wind[0];
        relative.body.v_m_s -= wind[1];
        relative.body.w_m_s -= wind[2];
        let still = a.derivatives(&relative, &t.controls, air()).unwrap();
        let (p, q, r) = (x.body.p_rad_s, x.body.q_rad_s, x.body.r_rad_s);
        let [du, dv, dw] = wind;
        // u' = X/m + r v - q w, v' = Y/m + p w - r u, w' = Z/m + q u - p v.
        let kinematic = [r * dv - q * dw, p * dw - r * du, q * du - p * dv];
        let (dw_, ds_) = (in_wind.body.to_array(), still.body.to_array());
        for k in 0..3 {
            assert!(
                (dw_[k] - ds_[k] - kinematic[k]).abs() < 1e-9,
                "axis {k}: {} vs {} + {}",
                dw_[k],
                ds_[k],
                kinematic[k]
            );
        }
        for k in 3..9 {
            assert!((dw_[k] - ds_[k]).abs() < 1e-12, "{k}: {dw_:?} vs {ds_:?}");
        }
        assert_eq!(in_wind.rotor_omega_rad_s, still.rotor_omega_rad_s);
        assert_eq!(in_wind.flap, still.flap);
        assert_eq!(in_wind.inflow, still.inflow);
        assert_eq!(in_wind.propeller_omega_rad_s, still.propeller_omega_rad_s);
        // A 2 m/s downdraught: the rotor and airframe lose lift, the body accelerates down.
        let calm = a.derivatives(&x, &t.controls, air()).unwrap();
        let down = a
            .derivatives_in_wind(&x, &t.controls, air(), [0.0, 0.0, 2.0])
            .unwrap();
        assert!(
            down.body.w_m_s > calm.body.w_m_s + 1.0,
            "{} vs {}",
            down.body.w_m_s,
            calm.body.w_m_s
        );
    }

    /// The pusher propeller at incidence: air from starboard (sideslip) pushes the disc to
    /// port behind the c.g., a weathercock yawing moment like the fin's; air from below (angle
    /// of attack) pushes it up behind the c.g., nose down. An anticlockwise propeller is the
    /// mirror image: the same weathercock moment, the opposite yawing moment from angle of attack.
    #[test]
    fn the_pusher_at_incidence_weathercocks_and_pitches_nose_down() {
        let a = gyroplane();
        let c = Condition {
            airspeed_m_s: 31.3,
            climb_m_s: 0.0,
            turn_rate_rad_s: 0.0,
            air: air(),
        };
        let t = trim::trim(&a, c, Options::default()).unwrap();
        let loads = |a: &Aircraft, dv: f64, dw: f64| {
            let mut x = t.state;
            x.body.v_m_s += dv;
            x.body.w_m_s += dw;
            a.averaged(&x, &t.controls, air(), t.averaged.flap_start)
                .unwrap()
                .loads
                .propeller
        };
        let (base, side, up) = (
            loads(&a, 0.0, 0.0),
            loads(&a, 1.0, 0.0),
            loads(&a, 0.0, 1.0),
        );
        assert!(
            side.y_n - base.y_n < 0.0 && side.n_n_m - base.n_n_m > 0.0,
            "{side:?}"
        );
        assert!(
            up.z_n - base.z_n < 0.0 && up.m_n_m - base.m_n_m < 0.0,
            "{up:?}"
        );
        // Measured for the test aircraft at 70 mph: -3.5 N and +3.3 N m per m/s of sideslip
        // velocity, -3.5 N and -3.3 N m per m/s of w, and a yawing moment of -5.9 N m per m/s
        // of w.
        assert!((side.y_n - base.y_n).abs() > 1.0, "{side:?}");
        let mut mirrored = a.clone();
        mirrored.propeller.rotation = match a.propeller.rotation {
            Rotation::Clockwise => Rotation::Anticlockwise,
            Rotation::Anticlockwise => Rotation::Clockwise,
        };
        let (mb, ms, mu) = (
            loads(&mirrored, 0.0, 0.0),
            loads(&mirrored, 1.0, 0.0),
            loads(&mirrored, 0.0, 1.0),
        );
        // Sideslip and yaw are mirrored together, so the weathercock moment does not depend on
        // the sense; the yawing moment from angle of attack (the "P-factor": the advancing
        // blades' extra thrust on one side) does, and changes sign.
        assert!(((ms.y_n - mb.y_n) - (side.y_n - base.y_n)).abs() < 1e-9);
        assert!(((ms.n_n_m - mb.n_n_m) - (side.n_n_m - base.n_n_m)).abs() < 1e-9);
        let p_factor = up.n_n_m - base.n_n_m;
        assert!(p_factor.abs() > 0.1, "{p_factor}");
        assert!(((mu.n_n_m - mb.n_n_m) + p_factor).abs() < 1e-9);
    }

    /// The assembled aircraft passes its propeller's slipstream to the tail: a fin wholly in it
    /// meets sideslip at the slipstream's speed, so its side force per m/s of sideslip grows by
    /// between `1 + v0 / u` (at the disc) and `1 + 2 v0 / u` (far behind); and the swirl, which
    /// runs to starboard above a clockwise pusher's shaft, pushes a fin above the shaft to
    /// starboard, a nose-left yawing moment that changes sign with the sense of rotation.
    #[test]
    fn the_pusher_slipstream_stiffens_the_fin_and_its_swirl_yaws_the_aircraft() {
        let c = Condition {
            airspeed_m_s: 31.3,
            climb_m_s: 0.0,
            turn_rate_rad_s: 0.0,
            air: air(),
        };
        let dry = gyroplane();
        let t = trim::trim(&dry, c, Options::default()).unwrap();
        let mut wet = dry.clone();
        wet.airframe.fin.as_mut().unwrap().slipstream_fraction = 1.0;
        let airframe = |a: &Aircraft, dv: f64| {
            let mut x = t.state;
            x.body.v_m_s += dv;
            let m = a
                .averaged(&x, &t.controls, air(), t.averaged.flap_start)
                .unwrap();
            (m.loads.airframe, m.propeller)
        };
        let side = |a: &Aircraft| (airframe(a, 0.1).0.y_n - airframe(a, -0.1).0.y_n) / 0.2;
        let (y_dry, y_wet) = (side(&dry), side(&wet));
        let (_, prop) = airframe(&dry, 0.0);
        let (u, v0) = (t.state.body.u_m_s, prop.v0_m_s);
        let ratio = y_wet / y_dry;
        assert!(v0 > 1.0, "{prop:?}");
        // The pod's side force is in both: the fin's share grows, so the whole grows by less.
        assert!(
            ratio > 1.0 && ratio < 1.0 + 2.0 * v0 / u,
            "{ratio} (v0 {v0}, u {u})"
        );
        let mut mirrored = wet.clone();
        mirrored.propeller.rotation = Rotation::Anticlockwise;
        let n = |a: &Aircraft| airframe(a, 0.0).0.n_n_m;
        let swirl = 0.5 * (n(&wet) - n(&mirrored));
        assert!(
            swirl < -1.0,
            "clockwise pusher's swirl yaws nose left: {swirl} N m"
        );
    }

    /// The revolution mean of the full model's accelerations with the body frozen (RK4 on
    /// azimuth and flap only, as in the trim), after `settle` revolutions for the blades to
    /// reach their periodic motion; and the state at the end.
    fn full_mean(
        a: &Aircraft,
        x: FullState,
        controls: &Controls,
        settle: usize,
    ) -> ([f64; 7], FullState) {
        let deriv = |x: &FullState| a.derivatives(x, controls, air()).unwrap();
        let (mean, _, x) = full_revolution(a, x, settle, &deriv);
        (mean, x)
    }

    /// [`full_mean`] with the full model's right-hand side `deriv`, and blade 1's flapping
    /// harmonics over the last revolution as the trim reports them
    /// (`beta = a0 - a1 cos psi - b1 sin psi`, rad; for a teeter, blade 1 is at the precone
    /// plus the teeter angle).
    fn full_revolution(
        a: &Aircraft,
        mut x: FullState,
        settle: usize,
        deriv: &dyn Fn(&FullState) -> FullDerivative,
    ) -> ([f64; 7], [f64; 3], FullState) {
        let n = 144;
        let h = 2.0 * PI / n as f64 / x.rotor_omega_rad_s;
        let mut mean = [0.0; 7];
        let mut harmonics = [0.0; 3];
        let cone = match a.main_rotor.rotor.hub {
            Hub::Teetering => a.main_rotor.rotor.precone_rad,
            _ => 0.0,
        };
        for rev in 0..=settle {
            for _ in 0..n {
                let step = |x: &FullState, d: &FullDerivative, f: f64| {
                    let mut y = x.clone();
                    y.rotor_azimuth_rad += f * d.rotor_azimuth_rad;
                    for (s, ds) in y.flap.iter_mut().zip(&d.flap) {
                        s[0] += f * ds[0];
                        s[1] += f * ds[1];
                    }
                    y
                };
                let k1 = deriv(&x);
                if rev == settle {
                    let beta = cone + x.flap[0][0];
                    let (sp, cp) = x.rotor_azimuth_rad.sin_cos();
                    harmonics[0] += beta / n as f64;
                    harmonics[1] -= 2.0 * beta * cp / n as f64;
                    harmonics[2] -= 2.0 * beta * sp / n as f64;
                    let b = k1.body;
                    for (m, v) in mean.iter_mut().zip([
                        b.u_m_s,
                        b.v_m_s,
                        b.w_m_s,
                        b.p_rad_s,
                        b.q_rad_s,
                        b.r_rad_s,
                        k1.rotor_omega_rad_s,
                    ]) {
                        *m += v / n as f64;
                    }
                }
                let k2 = deriv(&step(&x, &k1, h / 2.0));
                let k3 = deriv(&step(&x, &k2, h / 2.0));
                let k4 = deriv(&step(&x, &k3, h));
                x.rotor_azimuth_rad += h * x.rotor_omega_rad_s;
                for (j, s) in x.flap.iter_mut().enumerate() {
                    for (i, si) in s.iter_mut().enumerate() {
                        *si += h / 6.0
                            * (k1.flap[j][i]
                                + 2.0 * k2.flap[j][i]
                                + 2.0 * k3.flap[j][i]
                                + k4.flap[j][i]);
                    }
                }
            }
        }
        (mean, harmonics, x)
    }

    /// With the body pitching or rolling, the full model's revolution mean gives the averaged
    /// model's accelerations: the gyroscopic and flapping terms are the same physics in both.
    /// Measured (0.05 rad/s of pitch or roll rate, teetering rotor): within 2e-5 g and
    /// 1.4e-3 rad/s^2 (the azimuth discretisation, as in the trim test above).
    #[test]
    fn the_full_model_averages_to_the_averaged_model_under_body_rates() {
        let a = gyroplane();
        let c = crate::testdata::level_70mph();
        let t = trim::trim(&a, c, Options::default()).unwrap();
        for (dp, dq) in [(0.0, 0.05), (0.05, 0.0)] {
            let mut s = t.state;
            s.body.p_rad_s += dp;
            s.body.q_rad_s += dq;
            let avg = a
                .averaged(&s, &t.controls, air(), t.averaged.flap_start)
                .unwrap();
            let x = a.full_state(&s, &t.controls, air(), avg.flap_start);
            let (m, _) = full_mean(&a, x, &t.controls, 3);
            let b = avg.body_dot;
            let g = rigid_body::G_M_S2;
            for (k, want) in [b.u_m_s, b.v_m_s, b.w_m_s].into_iter().enumerate() {
                assert!(
                    (m[k] - want).abs() < 1e-3 * g,
                    "p {dp} q {dq}: linear acceleration {k}: full {} averaged {want}",
                    m[k]
                );
            }
            for (k, want) in [b.p_rad_s, b.q_rad_s, b.r_rad_s].into_iter().enumerate() {
                assert!(
                    (m[3 + k] - want).abs() < 3e-3,
                    "p {dp} q {dq}: angular acceleration {k}: full {} averaged {want}",
                    m[3 + k]
                );
            }
            let w = avg.rotor_omega_dot_rad_s2;
            assert!(
                (m[6] - w).abs() < 2e-2 * w.abs().max(0.1),
                "p {dp} q {dq}: rotor acceleration: full {} averaged {w}",
                m[6]
            );
        }
    }

    /// Off trim the body accelerates, and the averaged model's flap equations see those
    /// accelerations, as the full model's do, not a steady motion's: its periodic solution is
    /// iterated to the accelerations it implies (held steady, a pitch rate of 0.05 rad/s at
    /// 31.3 m/s would read as a pull-up of `q V` = 1.6 m/s^2). Heavy blades, teetering and
    /// articulated with a hinge offset, pitching or rolling at 0.05 rad/s off the level trim:
    ///
    /// * the full model given the averaged model's accelerations flies its flapping, within
    ///   `HELD_FLAP_RAD`, with its mean accelerations (the bounds of
    ///   `the_full_model_averages_to_the_averaged_model_under_body_rates`); given the steady
    ///   motion's instead, it flies flapping well away (articulated: 20 times that bound;
    ///   measured 4.3e-4 rad pitching, 7.9e-5 rolling);
    /// * free, the articulated rotor flaps as the averaged model says within `FREE_FLAP_RAD`
    ///   (a teeter does not: `TEETER_SHAKE_RAD`; measured 3.2e-5 rad here).
    #[test]
    fn the_averaged_models_heavy_blades_see_the_bodys_accelerations_off_trim() {
        let c = crate::testdata::level_70mph();
        let g = rigid_body::G_M_S2;
        for (hub, e) in [(Hub::Teetering, 0.0), (Hub::Articulated, 0.2)] {
            let a = heavy(hub, e);
            let t = trim::trim(&a, c, Options::default()).unwrap();
            let blade = Blade::new(&a.main_rotor.rotor, a.main_rotor.numerics);
            for (dp, dq) in [(0.0, 0.05), (0.05, 0.0)] {
                let case = format!("{hub:?}, p {dp} q {dq}");
                let mut s = t.state;
                s.body.p_rad_s += dp;
                s.body.q_rad_s += dq;
                let avg = a
                    .averaged(&s, &t.controls, air(), t.averaged.flap_start)
                    .unwrap();
                let l = &avg.loads;
                let y = a.accelerations(
                    &sum_loads(&[l.rotor, l.propeller, l.airframe]),
                    &avg.body_dot,
                );
                let steady = Aircraft::steady_accelerations(&s.body);
                let r = &avg.rotor;
                let averaged = [r.a0_rad, r.a1_rad, r.b1_rad];
                let x = a.full_state(&s, &t.controls, air(), avg.flap_start);
                // The full model's revolution, its flap equations seeing the hub's motion of the
                // given accelerations (none: its own).
                let run = |y: Option<[f64; 6]>| {
                    let deriv = |x: &FullState| {
                        a.derivatives_given(&blade, x, &t.controls, air(), [0.0; 3], y)
                            .unwrap()
                    };
                    full_revolution(&a, x.clone(), 3, &deriv)
                };
                let apart = |flap: [f64; 3]| {
                    (0..3)
                        .map(|k| (flap[k] - averaged[k]).abs())
                        .fold(0.0, f64::max)
                };
                let (m, flap, _) = run(Some(y));
                let (_, steady_flap, _) = run(Some(steady));
                let (_, free_flap, _) = run(None);
                eprintln!(
                    "{case}: flapping apart by {:.2e} rad given its accelerations, {:.2e} given the steady motion's, {:.2e} free",
                    apart(flap),
                    apart(steady_flap),
                    apart(free_flap)
                );
                assert!(
                    apart(flap) < HELD_FLAP_RAD,
                    "{case}: flapping: full {flap:?} averaged {averaged:?}"
                );
                // A teeter feels the hub's acceleration through its precone alone: the steady
                // motion's flapping is 2.0e-6 rad away in pitch, 7.5e-7 in roll (measured).
                let sensitivity = if hub == Hub::Teetering { 3.0 } else { 20.0 };
                assert!(
                    apart(steady_flap) > sensitivity * HELD_FLAP_RAD,
                    "{case}: the steady motion's flapping {steady_flap:?} is the averaged model's {averaged:?}"
                );
                if hub == Hub::Articulated {
                    assert!(
                        apart(free_flap) < FREE_FLAP_RAD,
                        "{case}: free flapping {free_flap:?} averaged {averaged:?}"
                    );
                }
                let b = avg.body_dot.to_array();
                for k in 0..6 {
                    let bound = if k < 3 { 1e-3 * g } else { 3e-3 };
                    assert!(
                        (m[k] - b[k]).abs() < bound,
                        "{case}: acceleration {k}: full {} averaged {}",
                        m[k],
                        b[k]
                    );
                }
            }
        }
    }

    /// The main rotor turns freely on a frictionless bearing, and the engine drives the
    /// propeller with a set torque: neither bearing transmits a torque about its shaft. So a
    /// yawing moment on the airframe alone (a pedal step from trim, which the rotor does not
    /// feel at that instant) changes neither rotor's absolute spin, `Omega - r_hub` for the
    /// main rotor (`U_T = (Omega - omega_z) r`) and `Omega_p + p` for the propeller turning
    /// about `+x`; and the airframe that accelerates is the aircraft without the two rotors'
    /// polar moments about their shafts. Averaged and full models alike.
    #[test]
    fn a_yawing_moment_leaves_the_free_rotors_absolute_spin_alone() {
        let a = gyroplane();
        let c = crate::testdata::level_70mph();
        let t = trim::trim(&a, c, Options::default()).unwrap();
        let mut stepped = t.controls;
        stepped.pedal_percent += 10.0;
        let frame = a.rotor_frame(&t.state.body, &t.controls);
        let shaft = frame.c[2];
        let i_r = a.rotor_polar_inertia_kg_m2();
        let Drive::Engine {
            polar_inertia_kg_m2: i_p,
            ..
        } = a.propeller.drive
        else {
            panic!("the test aircraft's engine drives its propeller")
        };
        let sense = a.propeller.rotation.sense();
        let m = &a.mass;
        let airframe = |axis: [f64; 3], i: f64, k: usize, l: usize| -> f64 {
            let full = [
                [m.ixx_kg_m2, 0.0, -m.ixz_kg_m2],
                [0.0, m.iyy_kg_m2, 0.0],
                [-m.ixz_kg_m2, 0.0, m.izz_kg_m2],
            ];
            full[k][l] - i * axis[k] * axis[l] - i_p * [1.0, 0.0, 0.0][k] * [1.0, 0.0, 0.0][l]
        };
        let rates = |b: &BodyState| [b.p_rad_s, b.q_rad_s, b.r_rad_s];
        let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];

        let before = a
            .averaged(&t.state, &t.controls, air(), t.averaged.flap_start)
            .unwrap();
        let after = a
            .averaged(&t.state, &stepped, air(), t.averaged.flap_start)
            .unwrap();
        let dw = {
            let (x, y) = (rates(&after.body_dot), rates(&before.body_dot));
            [x[0] - y[0], x[1] - y[1], x[2] - y[2]]
        };
        assert!(
            dw[2].abs() > 1e-3,
            "the pedal step yaws the airframe: {dw:?}"
        );
        // The airframe's moment balance with the free rotors' polar moments taken out.
        let dm = {
            let (x, y) = (after.loads.airframe, before.loads.airframe);
            [x.l_n_m - y.l_n_m, x.m_n_m - y.m_n_m, x.n_n_m - y.n_n_m]
        };
        for k in 0..3 {
            let got: f64 = (0..3).map(|l| airframe(shaft, i_r, k, l) * dw[l]).sum();
            assert!(
                (got - dm[k]).abs() < 1e-6 * dm[2].abs(),
                "moment {k}: airframe inertia x acceleration {got}, applied {}",
                dm[k]
            );
        }
        let d_omega = after.rotor_omega_dot_rad_s2 - before.rotor_omega_dot_rad_s2;
        assert!(
            (d_omega - dot(shaft, dw)).abs() < 1e-9,
            "main rotor: d(Omega)/dt changed by {d_omega}, r_hub by {}",
            dot(shaft, dw)
        );
        let d_prop = after.propeller_omega_dot_rad_s2 - before.propeller_omega_dot_rad_s2;
        assert!(
            (d_prop + sense * dw[0]).abs() < 1e-9,
            "propeller: d(Omega_p)/dt changed by {d_prop}, p by {}",
            dw[0]
        );

        // The same in the individual-blade model, at one instant of its periodic motion.
        let x = a.full_state(&t.state, &t.controls, air(), t.averaged.flap_start);
        let f0 = a.derivatives(&x, &t.controls, air()).unwrap();
        let f1 = a.derivatives(&x, &stepped, air()).unwrap();
        let dw = {
            let (x, y) = (rates(&f1.body), rates(&f0.body));
            [x[0] - y[0], x[1] - y[1], x[2] - y[2]]
        };
        let d_omega = f1.rotor_omega_rad_s - f0.rotor_omega_rad_s;
        assert!(
            (d_omega - dot(shaft, dw)).abs() < 1e-9,
            "full model, main rotor: {d_omega} against {}",
            dot(shaft, dw)
        );
        let d_prop = f1.propeller_omega_rad_s - f0.propeller_omega_rad_s;
        assert!(
            (d_prop + sense * dw[0]).abs() < 1e-9,
            "full model, propeller: {d_prop} against {}",
            -sense * dw[0]
        );
    }
}
