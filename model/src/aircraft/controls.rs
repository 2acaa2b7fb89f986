//! The pilot's controls and their maps to the shaft's tilt and the rudder, and the main
//! rotor's frame at a stick position.

use super::{Aircraft, RotorFrame, apply, body_to_hub, cross, sub};
use crate::components::rigid_body::BodyState;
use crate::components::rotor::HubVelocity;
use serde::Serialize;

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

impl Aircraft {
    /// The main rotor's frame at a body state and stick setting.
    /// The shaft's tilt `(theta_s, phi_s)` at a stick position.
    pub(super) fn shaft_tilt(&self, controls: &Controls) -> (f64, f64) {
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
    pub(super) fn rotor_frame_rotation(&self, controls: &Controls) -> [[f64; 3]; 3] {
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

    pub(super) fn rotor_frame(&self, b: &BodyState, controls: &Controls) -> RotorFrame {
        let uvw = [b.u_m_s, b.v_m_s, b.w_m_s];
        let pqr = [b.p_rad_s, b.q_rad_s, b.r_rad_s];
        let (theta_s, phi_s) = self.shaft_tilt(controls);
        let c = body_to_hub(theta_s, phi_s);
        let arm = sub(self.hub_position_m(theta_s, phi_s), self.cg_m);
        let rot = cross(pqr, arm);
        let mut v_hub_body = [uvw[0] + rot[0], uvw[1] + rot[1], uvw[2] + rot[2]];
        if let Some(k) = self.hub_aoa_factor {
            // The free stream's angle at the hub becomes `k alpha_cg`: the hub's velocity turns
            // in the body x-z plane by `(k - 1) alpha_cg`, keeping its magnitude, its sideslip
            // and what the airframe's rotation adds (pitch rate moves the hub). `k = 1` is the
            // kinematic angle, exactly.
            let alpha_cg = uvw[2].atan2(uvw[0]);
            let (s, c) = ((k - 1.0) * alpha_cg).sin_cos();
            let [x, y, z] = v_hub_body;
            v_hub_body = [x * c - z * s, y, x * s + z * c];
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
}
