//! The physical parameters of an assembled aircraft that `cierva sensitivity` studies and
//! `cierva fit` can move (where the aircraft file calls them estimated): their names, units and
//! meanings, and how to read and set them on an [`Aircraft`].
//!
//! A name is the dotted path of the aircraft file's field (`airframe.fin.area_m2`; `.x`, `.z` pick
//! a position's component). Two are derived: `controls.shaft_roll_deg.travel` and
//! `controls.shaft_pitch_deg.travel`, a control's travel (its gearing) with its middle kept.
//! Values are in the unit [`PARAMETERS`] gives, which is the file's.

use cierva_model::aircraft::{Aircraft, ControlMaps, LinearMap};
use cierva_model::components::airfoil::Airfoil;
use cierva_model::components::airframe::Surface;
use cierva_model::components::rotor::Rotor;
use serde::Serialize;

/// A physical parameter of an assembled aircraft that `cierva sensitivity` can move, by its
/// dotted name in the aircraft file (`.x`, `.z` pick a position's component).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ParameterInfo {
    pub name: &'static str,
    pub unit: &'static str,
    pub meaning: &'static str,
}

/// Every parameter [`parameter`] and [`set_parameter`] reach.
pub const PARAMETERS: &[ParameterInfo] = &[
    ParameterInfo {
        name: "mass.ixx_kg_m2",
        unit: "kg m^2",
        meaning: "roll moment of inertia (whole aircraft, rotors as frozen discs)",
    },
    ParameterInfo {
        name: "mass.iyy_kg_m2",
        unit: "kg m^2",
        meaning: "pitch moment of inertia",
    },
    ParameterInfo {
        name: "mass.izz_kg_m2",
        unit: "kg m^2",
        meaning: "yaw moment of inertia",
    },
    ParameterInfo {
        name: "mass.ixz_kg_m2",
        unit: "kg m^2",
        meaning: "product of inertia",
    },
    ParameterInfo {
        name: "main_rotor.pivot_m.x",
        unit: "m",
        meaning: "spindle pivot ahead of the datum",
    },
    ParameterInfo {
        name: "main_rotor.pivot_m.z",
        unit: "m",
        meaning: "spindle pivot below the datum (negative: above)",
    },
    ParameterInfo {
        name: "propeller.position_m.z",
        unit: "m",
        meaning: "propeller disc centre below the datum (the thrust line)",
    },
    ParameterInfo {
        name: "airframe.reference_point_m.x",
        unit: "m",
        meaning: "where the pod's coefficient forces act, ahead of the datum",
    },
    ParameterInfo {
        name: "airframe.reference_point_m.z",
        unit: "m",
        meaning: "where the pod's coefficient forces act, below the datum",
    },
    ParameterInfo {
        name: "airframe.side_force_centre_m.x",
        unit: "m",
        meaning: "where the pod's side force acts (its side-area centre), ahead of the datum",
    },
    ParameterInfo {
        name: "airframe.side_force_centre_m.z",
        unit: "m",
        meaning: "where the pod's side force acts (its side-area centre), below the datum",
    },
    ParameterInfo {
        name: "airframe.fin.area_m2",
        unit: "m^2",
        meaning: "fin and rudder area",
    },
    ParameterInfo {
        name: "airframe.fin.position_m.x",
        unit: "m",
        meaning: "fin's aerodynamic centre ahead of the datum (negative: behind)",
    },
    ParameterInfo {
        name: "airframe.fin.position_m.z",
        unit: "m",
        meaning: "fin's aerodynamic centre below the datum (negative: above)",
    },
    ParameterInfo {
        name: "airframe.fin.lift_slope_per_rad",
        unit: "1/rad",
        meaning: "fin lift-curve slope (effectiveness, sidewash)",
    },
    ParameterInfo {
        name: "airframe.fin.slipstream_fraction",
        unit: "-",
        meaning: "share of the fin's area in the propeller's slipstream",
    },
    ParameterInfo {
        name: "airframe.fin.wash_gradient",
        unit: "-",
        meaning: "sidewash gradient at the fin from the pod ahead (share of the sideslip taken)",
    },
    ParameterInfo {
        name: "airframe.fin.dynamic_pressure_ratio",
        unit: "-",
        meaning: "dynamic pressure at the fin over the free stream's (the airframe's wakes ahead of it)",
    },
    ParameterInfo {
        name: "airframe.munk_yaw_m3",
        unit: "m^3",
        meaning: "the pod's Munk couple (k2 - k1) Vol: a yawing moment -rho u v times it, away from the wind",
    },
    ParameterInfo {
        name: "airframe.tailplane.wash_gradient",
        unit: "-",
        meaning: "downwash gradient at the tailplane (share of the angle of attack taken)",
    },
    ParameterInfo {
        name: "airframe.tailplane.slipstream_fraction",
        unit: "-",
        meaning: "share of the tailplane's area in the propeller's slipstream",
    },
    ParameterInfo {
        name: "airframe.tailplane.area_m2",
        unit: "m^2",
        meaning: "tailplane area",
    },
    ParameterInfo {
        name: "airframe.tailplane.position_m.x",
        unit: "m",
        meaning: "tailplane's aerodynamic centre ahead of the datum",
    },
    ParameterInfo {
        name: "airframe.tailplane.lift_slope_per_rad",
        unit: "1/rad",
        meaning: "tailplane lift-curve slope",
    },
    ParameterInfo {
        name: "airframe.tailplane.dynamic_pressure_ratio",
        unit: "-",
        meaning: "dynamic pressure at the tailplane over the free stream's (the airframe's wakes ahead of it)",
    },
    ParameterInfo {
        name: "controls.shaft_roll_deg.travel",
        unit: "deg",
        meaning: "the rotor head's lateral travel over the stick's (at 100 % less at 0 %, about its middle): the lateral stick's gearing",
    },
    ParameterInfo {
        name: "controls.shaft_pitch_deg.travel",
        unit: "deg",
        meaning: "the rotor head's longitudinal travel over the stick's (about its middle): the longitudinal stick's gearing",
    },
    ParameterInfo {
        name: "corrections.propeller_blockage",
        unit: "-",
        meaning: "seed 000's propeller blockage (0 none, 1 total)",
    },
];

/// The names of the physical parameters (all of [`PARAMETERS`] but the corrections, which a
/// corrections file sets by their own names).
pub fn physical_names() -> Vec<String> {
    PARAMETERS
        .iter()
        .filter(|p| !p.name.starts_with("corrections."))
        .map(|p| p.name.to_string())
        .collect()
}

/// The value of parameter `name` of an aircraft (in the unit [`PARAMETERS`] gives); `None` for
/// an unknown name or a part the aircraft does not have (a fin).
pub fn parameter(a: &Aircraft, name: &str) -> Option<f64> {
    match control_travel(name) {
        Some(pick) => {
            let mut controls = a.controls;
            let m = pick(&mut controls);
            Some((m.at_100_percent - m.at_0_percent).to_degrees())
        }
        // One accessor serves reading and setting; a read clones the aircraft (a few kB), which
        // the callers (loading, a study's setup) can afford.
        None => parameter_mut(&mut a.clone(), name).map(|v| *v),
    }
}

/// Sets parameter `name` of an aircraft (in the unit [`PARAMETERS`] gives); `None` for an unknown
/// name or a part the aircraft does not have. A control's travel keeps its middle.
pub fn set_parameter(a: &mut Aircraft, name: &str, value: f64) -> Option<()> {
    match control_travel(name) {
        Some(pick) => {
            let m = pick(&mut a.controls);
            let middle = 0.5 * (m.at_0_percent + m.at_100_percent);
            let half = 0.5 * value.to_radians();
            m.at_0_percent = middle - half;
            m.at_100_percent = middle + half;
        }
        None => *parameter_mut(a, name)? = value,
    }
    Some(())
}

/// A control map's travel, by parameter name.
fn control_travel(name: &str) -> Option<fn(&mut ControlMaps) -> &mut LinearMap> {
    match name {
        "controls.shaft_roll_deg.travel" => Some(|c| &mut c.shaft_roll_rad),
        "controls.shaft_pitch_deg.travel" => Some(|c| &mut c.shaft_pitch_rad),
        _ => None,
    }
}

/// A plain field's parameter, to read or set in the model's own unit.
fn parameter_mut<'a>(a: &'a mut Aircraft, name: &str) -> Option<&'a mut f64> {
    let surface = |s: &'a mut Option<Surface>| s.as_mut();
    Some(match name {
        "mass.ixx_kg_m2" => &mut a.mass.ixx_kg_m2,
        "mass.iyy_kg_m2" => &mut a.mass.iyy_kg_m2,
        "mass.izz_kg_m2" => &mut a.mass.izz_kg_m2,
        "mass.ixz_kg_m2" => &mut a.mass.ixz_kg_m2,
        "main_rotor.pivot_m.x" => &mut a.main_rotor.pivot_m[0],
        "main_rotor.pivot_m.z" => &mut a.main_rotor.pivot_m[2],
        "propeller.position_m.z" => &mut a.propeller.position_m[2],
        "airframe.reference_point_m.x" => &mut a.airframe.reference_point_m[0],
        "airframe.reference_point_m.z" => &mut a.airframe.reference_point_m[2],
        "airframe.side_force_centre_m.x" => &mut a.airframe.side_force_centre_m.as_mut()?[0],
        "airframe.side_force_centre_m.z" => &mut a.airframe.side_force_centre_m.as_mut()?[2],
        "airframe.fin.area_m2" => &mut surface(&mut a.airframe.fin)?.area_m2,
        "airframe.fin.position_m.x" => &mut surface(&mut a.airframe.fin)?.position_m[0],
        "airframe.fin.position_m.z" => &mut surface(&mut a.airframe.fin)?.position_m[2],
        "airframe.fin.lift_slope_per_rad" => &mut surface(&mut a.airframe.fin)?.lift_slope_per_rad,
        "airframe.fin.slipstream_fraction" => {
            &mut surface(&mut a.airframe.fin)?.slipstream_fraction
        }
        "airframe.fin.wash_gradient" => &mut surface(&mut a.airframe.fin)?.wash_gradient,
        "airframe.fin.dynamic_pressure_ratio" => {
            &mut surface(&mut a.airframe.fin)?.dynamic_pressure_ratio
        }
        "airframe.munk_yaw_m3" => &mut a.airframe.munk_yaw_m3,
        "airframe.tailplane.dynamic_pressure_ratio" => {
            &mut surface(&mut a.airframe.tailplane)?.dynamic_pressure_ratio
        }
        "airframe.tailplane.wash_gradient" => {
            &mut surface(&mut a.airframe.tailplane)?.wash_gradient
        }
        "airframe.tailplane.slipstream_fraction" => {
            &mut surface(&mut a.airframe.tailplane)?.slipstream_fraction
        }
        "airframe.tailplane.area_m2" => &mut surface(&mut a.airframe.tailplane)?.area_m2,
        "airframe.tailplane.position_m.x" => &mut surface(&mut a.airframe.tailplane)?.position_m[0],
        "airframe.tailplane.lift_slope_per_rad" => {
            &mut surface(&mut a.airframe.tailplane)?.lift_slope_per_rad
        }
        "corrections.propeller_blockage" => &mut a.propeller.propeller.blockage,
        _ => return None,
    })
}

/// The parameters of a rotor file that its `ranges:` may give a plausible range (those its
/// sources call estimated on the shipped rotors): the uncertain inputs of a rotor case.
pub const ROTOR_PARAMETERS: &[ParameterInfo] = &[
    ParameterInfo {
        name: "root_cutout_m",
        unit: "m",
        meaning: "blade root station (the lifting blade starts here), from the shaft axis",
    },
    ParameterInfo {
        name: "hinge_offset_m",
        unit: "m",
        meaning: "flapping hinge's distance from the shaft axis",
    },
    ParameterInfo {
        name: "flap_mass_moment_kg_m",
        unit: "kg m",
        meaning: "blade's first mass moment about the flapping hinge",
    },
    ParameterInfo {
        name: "pitch_reference_r_over_r",
        unit: "-",
        meaning: "station at which a collective (pitch) setting is defined",
    },
    ParameterInfo {
        name: "hub_drag_area_m2",
        unit: "m^2",
        meaning: "hub's flat-plate drag area",
    },
    ParameterInfo {
        name: "airfoil.stall_alpha_deg",
        unit: "deg",
        meaning: "section stall angle (analytical section)",
    },
];

/// The value of a rotor parameter (in the unit [`ROTOR_PARAMETERS`] gives); `None` for an unknown
/// name or one the rotor does not have (a stall angle of a tabulated section).
pub fn rotor_parameter(r: &Rotor, name: &str) -> Option<f64> {
    Some(match name {
        "root_cutout_m" => r.root_cutout_m,
        "hinge_offset_m" => r.hinge_offset_m,
        "flap_mass_moment_kg_m" => r.flap_mass_moment_kg_m,
        "pitch_reference_r_over_r" => r.pitch_reference_r_over_r,
        "hub_drag_area_m2" => r.hub_drag_area_m2,
        "airfoil.stall_alpha_deg" => match &r.airfoil {
            Airfoil::Analytical(s) => s.stall_alpha_rad.to_degrees(),
            Airfoil::Table(_) => return None,
        },
        _ => return None,
    })
}

/// Sets a rotor parameter (in the unit [`ROTOR_PARAMETERS`] gives); `None` for an unknown name or
/// one the rotor does not have.
pub fn set_rotor_parameter(r: &mut Rotor, name: &str, value: f64) -> Option<()> {
    match name {
        "root_cutout_m" => r.root_cutout_m = value,
        "hinge_offset_m" => r.hinge_offset_m = value,
        "flap_mass_moment_kg_m" => r.flap_mass_moment_kg_m = value,
        "pitch_reference_r_over_r" => r.pitch_reference_r_over_r = value,
        "hub_drag_area_m2" => r.hub_drag_area_m2 = value,
        "airfoil.stall_alpha_deg" => match &mut r.airfoil {
            Airfoil::Analytical(s) => s.stall_alpha_rad = value.to_radians(),
            Airfoil::Table(_) => return None,
        },
        _ => return None,
    }
    Some(())
}
