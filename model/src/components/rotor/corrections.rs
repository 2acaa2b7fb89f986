//! The rotor's corrections (seed 000 Sec. VII): drag, pitch and inflow offsets, and the blade's
//! elastic twist under its dynamic pressure.

use serde::Serialize;

/// Correction parameters (seed 000 Sec. VII), defaulting to no correction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Corrections {
    /// Multiplies the section drag coefficient (rougher blades, seed 000 Sec. VII.B).
    pub profile_drag_scale: f64,
    /// Added to the section drag coefficient.
    pub profile_drag_increment: f64,
    /// Added to every element's blade pitch, rad: a pitch-setting (rigging) offset, or the
    /// mean elastic twist a rigid-blade model leaves out.
    pub pitch_offset_rad: f64,
    /// Added to the induced velocity's lateral (`sin psi`) component `v1s`, m/s, on top of the
    /// inflow model's: seed 003 derives `v1s` of about -1 m/s from flight where momentum theory
    /// gives about zero.
    pub lateral_inflow_offset_m_s: f64,
    /// Elastic torsion under the blade's dynamic pressure: the tip's pitch change, nose up
    /// positive, per pascal of tip dynamic pressure `rho (Omega R)^2 / 2` in hover, rad/Pa.
    /// See [`elastic_twist_rad`]: the twist grows with `Omega^2` and, in edgewise flow, with
    /// the advancing blade's dynamic pressure (a mean rise with `mu^2` and a once-per-revolution
    /// part). Zero: rigid blades.
    pub elastic_twist_rad_per_pa: f64,
    /// The section drag's Reynolds-number dependence: each element's drag coefficient is
    /// multiplied by `(Re / Re_ref)^-n`, `Re` the element's chord Reynolds number in the flow
    /// normal to its span and `Re_ref` [`super::Rotor::drag_reynolds_number`]. Zero: drag independent
    /// of Reynolds number. A turbulent flat plate's skin friction goes as `Re^-0.2`, a laminar
    /// one's as `Re^-0.5` (Schlichting, Boundary-Layer Theory, ch. 2 and 21).
    pub profile_drag_reynolds_exponent: f64,
}

impl Default for Corrections {
    fn default() -> Self {
        Self {
            profile_drag_scale: 1.0,
            profile_drag_increment: 0.0,
            pitch_offset_rad: 0.0,
            lateral_inflow_offset_m_s: 0.0,
            elastic_twist_rad_per_pa: 0.0,
            profile_drag_reynolds_exponent: 0.0,
        }
    }
}

/// The elastic twist at span station `x = r / R` of a blade held in torsion at the shaft, with
/// uniform torsional stiffness, loaded by a section moment proportional to the local dynamic
/// pressure `rho U^2 / 2`, `U = Omega R t + u_t` (`u_t` the hub's in-plane speed along the
/// blade's direction of rotation at this azimuth, `t` the station), quasi-statically (the
/// torsion frequency is many times the rotor's): `rad_per_pa` times
///
/// ```text
/// (rho / 2) 4 int_0^x int_s^1 U(t)^2 dt ds
///   = 2 rho [ W^2 (x - x^4/4) / 3 + W u_t (x - x^3/3) + u_t^2 (x - x^2/2) ],  W = Omega R,
/// ```
///
/// normalised so that the tip twists by `rad_per_pa` times the tip dynamic pressure in hover.
/// The section moment's coefficient is taken as constant along the span and round the
/// azimuth (a cambered section's `c_m0`, or lift acting ahead of the elastic axis); reverse
/// flow is loaded as forward flow. The measured pitch distribution the rotor file gives is
/// the twist's datum.
pub fn elastic_twist_rad(
    rad_per_pa: f64,
    density_kg_m3: f64,
    tip_speed_m_s: f64,
    hub_tangential_m_s: f64,
    x: f64,
) -> f64 {
    let (w, h) = (tip_speed_m_s, hub_tangential_m_s);
    let shape = w * w * (x - x.powi(4) / 4.0) / 3.0
        + w * h * (x - x.powi(3) / 3.0)
        + h * h * (x - x * x / 2.0);
    rad_per_pa * 2.0 * density_kg_m3 * shape
}
