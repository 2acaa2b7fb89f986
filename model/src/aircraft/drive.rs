//! The propeller's drive (governed or engine), its rotation and installation, and the speeds
//! of the rotors that turn freely on their shafts.

use super::{
    Air, Aircraft, AircraftError, Controls, LinearMap, RotorFrame, State, as_loads, cross, sub,
};
use crate::components::airframe::Slipstream;
use crate::components::propeller::{Propeller, PropellerState};
use crate::components::rigid_body::{BodyState, FreeSpin, Loads};
use serde::Serialize;
use std::f64::consts::PI;

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

impl Aircraft {
    /// The propeller's speed for a state and throttle.
    pub fn propeller_omega(&self, state: &State, controls: &Controls) -> f64 {
        match self.propeller.drive {
            Drive::Governed { rpm } => rpm.at(controls.throttle_percent) * PI / 30.0,
            Drive::Engine { .. } => state.propeller_omega_rad_s,
        }
    }

    /// The rotors that turn freely about their shafts (see
    /// [`crate::components::rigid_body::derivatives_with_free_spins`]): the main rotor, on a bearing that carries no torque about its shaft (an autogyro's rotor
    /// is driven by the air alone), and the propeller when an engine drives it at a set torque.
    /// A governed propeller is held at its speed relative to the airframe, so it turns with the
    /// airframe as part of it (its polar moment 0 here).
    pub fn free_spins(&self, controls: &Controls) -> [FreeSpin; 2] {
        self.free_spins_at(&self.rotor_frame_rotation(controls))
    }

    /// [`Aircraft::free_spins`] with the shaft from a body-to-hub rotation already formed.
    pub(super) fn free_spins_at(&self, c: &[[f64; 3]; 3]) -> [FreeSpin; 2] {
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
    /// their own torques (`driven`) and the airframe's angular acceleration. The rotor turns
    /// about `-z_hub` on a bearing that carries no torque, so the blades' angular momentum
    /// about the shaft changes by the torques on them alone, and its absolute spin `Omega -
    /// r_hub` by `T / I_Rb`: `T` the aerodynamic torque and the inertial torques of the blades'
    /// flapping and of the hub's rates and angular acceleration across the shaft on them (the
    /// full model's `respond`, the averaged model's means), `I_Rb` the flapped blades' polar
    /// inertia; with unflapped blades and no inertial torques, `I_R (Omega' - r_hub') = Q`. An
    /// engine-driven propeller turning clockwise seen from behind spins about `+x` at
    /// `Omega_p + p`, so `I_p (Omega_p' + p') = Q_e - Q_p`. The shaft's tilt rate is
    /// neglected, as in the hub's rates.
    pub(super) fn spin_rates(
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
    pub(super) fn propeller_and_airframe(
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
        // The engine's torque, the propeller's spin acceleration and the spin's angular
        // momentum beyond the airframe's frozen share, `I_p sense Omega_p` along `+x` (a
        // governed propeller has no spin state and no inertia in the model).
        let (engine_torque, prop_omega_dot, spin) = match pi.drive {
            Drive::Governed { .. } => (ps.torque_n_m, 0.0, 0.0),
            Drive::Engine {
                max_power_w,
                rated_rpm,
                polar_inertia_kg_m2,
            } => {
                let q = controls.throttle_percent / 100.0 * max_power_w / (rated_rpm * PI / 30.0);
                (
                    q,
                    (q - ps.torque_n_m) / polar_inertia_kg_m2,
                    polar_inertia_kg_m2 * sense * prop_omega,
                )
            }
        };
        let [fx_h, fy_h] = ps.inplane_force_n;
        let [mx_h, my_h] = ps.inplane_moment_n_m;
        let pf = [ps.thrust_n, sense * fy_h, fx_h];
        let pm = cross(parm, pf);
        // Propeller turning clockwise seen from behind: its angular velocity is along +x, the
        // engine's reaction on the airframe along -x. Its hub moments: hub x is body z, hub y
        // body y (mirrored with the propeller's sense). The spin's gyroscopic couple on the
        // airframe, `-w x (h, 0, 0)`: a yaw rate pitches, a pitch rate yaws.
        let prop_loads = as_loads(
            pf,
            [
                pm[0] - sense * engine_torque,
                pm[1] + my_h - pqr[2] * spin,
                pm[2] + sense * mx_h + pqr[1] * spin,
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

    /// The aircraft with its propeller on its map ([`Propeller::with_map`]), as a simulation
    /// flies it; unchanged if it has a map already or one cannot be built.
    pub(crate) fn with_propeller_map(&self) -> Aircraft {
        let mut mapped = self.clone();
        if mapped.propeller.propeller.map.is_none()
            && let Ok(p) = mapped.propeller.propeller.with_map()
        {
            mapped.propeller.propeller = p;
        }
        mapped
    }
}
