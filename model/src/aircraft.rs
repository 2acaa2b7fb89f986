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
//! collective would enter as a collective shift of the rotor ([`MainRotor::collective_shift_rad`]).
//!
//! # The revolution-averaged model
//! [`Aircraft::averaged`] evaluates the rigid-body, rotorspeed, propeller-speed and inflow
//! equations with the rotor in its steady periodic motion at the present body state (the
//! trim model: every load is a mean over one rotor revolution). The rotor's mean forces and
//! aerodynamic moments reach the airframe at the hub, plus the gyroscopic couple
//! `-omega_hub x H` when the body rotates. The rotor turns freely (no shaft torque: an
//! autogyro), so the mean aerodynamic torque accelerates it: `I_R dOmega/dt = Q`.
//!
//! # Propeller and engine
//! The propeller thrusts along body `+x` (a pusher), in the axial component of the local air
//! velocity (non-axial inflow effects are not modelled). Its speed is governed (rpm from
//! throttle by a linear map) or driven by an engine whose shaft torque is
//! `throttle x P_max / Omega_rated`, a constant-torque piston engine; the torque reaction
//! rolls the airframe against the propeller's rotation.
//!
//! # Hub angle-of-attack correction
//! Seed 000 Sec. VII replaces the kinematic angle of attack at the hub by a factor times the
//! angle of attack at the c.g. (0.5 in the seed), to stand for the wake's skew as it approaches
//! the disc. With `hub_aoa_factor = Some(k)` the hub's air velocity keeps its magnitude in the
//! body x-z plane and its sideslip, and its angle is `k alpha_cg`. `None` is the kinematic
//! value (no correction).

use crate::airframe::{Airframe, AirframeError};
use crate::inflow;
use crate::propeller::{Propeller, PropellerError, PropellerState};
use crate::rigid_body::{self, BodyError, BodyState, Loads, MassProperties};
use crate::rotor::{
    Blade, HubVelocity, Inflow, InflowModel, Numerics, Operating, Rotor, RotorError, SteadyLoads,
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
    pub numerics: Numerics,
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
        let b = &state.body;
        let uvw = [b.u_m_s, b.v_m_s, b.w_m_s];
        let pqr = [b.p_rad_s, b.q_rad_s, b.r_rad_s];
        let mr = &self.main_rotor;
        if !(state.rotor_omega_rad_s.is_finite() && state.rotor_omega_rad_s > 0.0) {
            return Err(AircraftError::Invalid {
                name: "rotor_omega_rad_s",
                requirement: "positive and finite",
                value: state.rotor_omega_rad_s,
            });
        }

        // Main rotor: shaft tilt, hub position and air velocity.
        let theta_s = self
            .controls
            .shaft_pitch_rad
            .at(controls.stick_longitudinal_percent);
        let phi_s = self
            .controls
            .shaft_roll_rad
            .at(controls.stick_lateral_percent);
        let c = body_to_hub(theta_s, phi_s);
        let hub_pos = self.hub_position_m(theta_s, phi_s);
        let arm = sub(hub_pos, self.cg_m);
        let rot = cross(pqr, arm);
        let mut v_hub_body = [uvw[0] + rot[0], uvw[1] + rot[1], uvw[2] + rot[2]];
        if let Some(k) = self.hub_aoa_factor {
            let alpha_cg = uvw[2].atan2(uvw[0]);
            let vxz = v_hub_body[0].hypot(v_hub_body[2]);
            let (sa, ca) = (k * alpha_cg).sin_cos();
            v_hub_body = [vxz * ca, v_hub_body[1], vxz * sa];
        }
        let vh = apply(&c, v_hub_body);
        let hub = HubVelocity {
            u: vh[0],
            v: vh[1],
            w: vh[2],
        };
        let omega = state.rotor_omega_rad_s;
        let op = Operating {
            omega_rad_s: omega,
            hub,
            inflow: state.inflow,
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
            collective_shift_rad: mr.collective_shift_rad,
            hub_rates_rad_s: apply(&c, pqr),
        };
        let blade = Blade::new(&mr.rotor, mr.numerics);
        let rl: SteadyLoads = blade.steady(&op, warm)?;
        let (equilibrium, wake) = match mr.inflow {
            InflowModel::Prescribed { v0, v1s, v1c } => (
                Inflow { v0, v1s, v1c },
                inflow::wake(hub, v0, crate::rotor::SkewConvention::Signed),
            ),
            InflowModel::PetersHaQuang { skew } | InflowModel::UniformOnly { skew } => {
                let harmonics = matches!(mr.inflow, InflowModel::PetersHaQuang { .. });
                inflow::static_inflow(
                    inflow::DrivingLoads {
                        thrust_n: rl.thrust_n(),
                        roll_n_m: rl.moment_n_m[0],
                        pitch_n_m: rl.moment_n_m[1],
                    },
                    hub,
                    state.inflow.v0,
                    air.density_kg_m3,
                    mr.rotor.radius_m,
                    (skew, harmonics),
                )
            }
        };
        let inflow_dot = match mr.inflow {
            InflowModel::Prescribed { .. } => Inflow::default(),
            _ => inflow::inflow_rate(state.inflow, equilibrium, hub, wake, mr.rotor.radius_m),
        };
        // Loads on the airframe at the hub: mean force, mean aerodynamic moment with no shaft
        // torque (a free rotor), and the gyroscopic couple.
        let h = rl.angular_momentum_kg_m2_s;
        let gyro = cross(op.hub_rates_rad_s, h);
        let m_hub = [
            rl.moment_n_m[0] - gyro[0],
            rl.moment_n_m[1] - gyro[1],
            -gyro[2],
        ];
        let f_body = apply_t(&c, rl.force_n);
        let m_body = apply_t(&c, m_hub);
        let transfer = cross(arm, f_body);
        let rotor_loads = as_loads(
            f_body,
            [
                m_body[0] + transfer[0],
                m_body[1] + transfer[1],
                m_body[2] + transfer[2],
            ],
        );
        let rotor_omega_dot = rl.driving_torque_n_m / self.rotor_polar_inertia_kg_m2();

        // Propeller.
        let pi = &self.propeller;
        let prop_omega = self.propeller_omega(state, controls);
        if !(prop_omega.is_finite() && prop_omega > 0.0) {
            return Err(AircraftError::Invalid {
                name: "propeller speed (from the throttle or the state), rad/s",
                requirement: "positive",
                value: prop_omega,
            });
        }
        let parm = sub(pi.position_m, self.cg_m);
        let prot = cross(pqr, parm);
        let axial = (uvw[0] + prot[0]).max(0.0);
        let ps =
            pi.propeller
                .operate(prop_omega, axial, air.density_kg_m3, air.speed_of_sound_m_s)?;
        let sense = match pi.rotation {
            Rotation::Clockwise => 1.0,
            Rotation::Anticlockwise => -1.0,
        };
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
        let pf = [ps.thrust_n, 0.0, 0.0];
        let pm = cross(parm, pf);
        // Propeller turning clockwise seen from behind: its angular velocity is along +x, the
        // engine's reaction on the airframe along -x.
        let prop_loads = as_loads(pf, [pm[0] - sense * engine_torque, pm[1], pm[2]]);

        // Airframe.
        let rudder = self.controls.rudder_rad.at(controls.pedal_percent);
        let af = self
            .airframe
            .loads(uvw, pqr, air.density_kg_m3, self.cg_m, [0.0, rudder])?;

        let total = Loads {
            x_n: rotor_loads.x_n + prop_loads.x_n + af.x_n,
            y_n: rotor_loads.y_n + prop_loads.y_n + af.y_n,
            z_n: rotor_loads.z_n + prop_loads.z_n + af.z_n,
            l_n_m: rotor_loads.l_n_m + prop_loads.l_n_m + af.l_n_m,
            m_n_m: rotor_loads.m_n_m + prop_loads.m_n_m + af.m_n_m,
            n_n_m: rotor_loads.n_n_m + prop_loads.n_n_m + af.n_n_m,
        };
        let body_dot = rigid_body::derivatives(&self.mass, b, &total)?;
        let v_inplane = hub.u.hypot(hub.v);
        Ok(Averaged {
            body_dot,
            rotor_omega_dot_rad_s2: rotor_omega_dot,
            propeller_omega_dot_rad_s2: prop_omega_dot,
            inflow_equilibrium: equilibrium,
            inflow_dot,
            rotor: RotorReport {
                shaft_pitch_rad: theta_s,
                shaft_roll_rad: phi_s,
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
        })
    }
}
