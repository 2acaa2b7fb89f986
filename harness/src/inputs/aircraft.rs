//! Aircraft files (`aircraft/*.yaml`): an assembled autogyro and where every number comes from.
//!
//! ```yaml
//! id: vpm-m16                          # equals the file stem
//! title: VPM M16 gyroplane
//! provenance: {source: "...", notes: "..."}
//! aircraft:
//!   mass: {mass_kg: 450, max_kg: 450, ixx_kg_m2: 250, iyy_kg_m2: 650, izz_kg_m2: 450, ixz_kg_m2: 40}  # max_kg: optional, the maximum all-up mass
//!   cg_m: [0.0, 0.0, 0.0]              # body axes from the datum: x fwd, y stbd, z down
//!   main_rotor:
//!     rotor_file: vpm-m16-rotor.yaml   # a rotor file, relative to this file
//!     pivot_m: [0.0, 0.0, -1.6]
//!     spindle_length_m: 0.2
//!     # inflow, skew and descent: the rotor file's `physics` (one answer per rotor); an aircraft
//!     # file may state one its rotor file leaves out, never one that differs from it
//!     inflow_dynamics: dynamic         # optional: or quasi_steady (full model only)
//!     azimuth_step_deg: 5
//!   propeller:
//!     rotor_file: vpm-m16-propeller.yaml   # hub: rigid
//!     position_m: [-1.3, 0.0, -0.35]
//!     rotation: clockwise              # seen from behind
//!     drive: {engine: {max_power_w: 84500, rated_rpm: 2388, polar_inertia_kg_m2: 1.2}}
//!     #   or {governed: {rpm_at_0_percent: 1800, rpm_at_100_percent: 2600}}
//!   airframe:
//!     reference_area_m2: 1.0
//!     reference_length_m: 1.0
//!     reference_span_m: 1.0
//!     reference_point_m: [0, 0, 0]
//!     side_force_centre_m: [0.1, 0, 0.2]   # optional: where cy acts (default the reference
//!                                          # point); cl and cn then exclude its moments
//!     coefficients: {cx: TABLE, cy: TABLE, cz: TABLE, cl: TABLE, cm: TABLE, cn: TABLE}
//!     #   TABLE = {alpha_deg: [...], beta_deg: [...], values: [[...] one row per alpha]}
//!     munk_yaw_m3: 0.57                    # optional: the pod's Munk couple (k2 - k1) Vol
//!     tailplane: {position_m: [..], area_m2: .., lift_slope_per_rad: .., incidence_deg: ..,
//!                 stall_alpha_deg: .., cd0: .., control_effectiveness: ..,
//!                 slipstream_fraction: ..,  # optional: share of its area in the slipstream
//!                 wash_gradient: ..,        # optional: sidewash (fin) or downwash gradient
//!                 dynamic_pressure_ratio: .., # optional: q at it over the free stream's (1)
//!                 planform: {span_m: .., root_chord_m: .., tip_chord_m: ..}}
//!                 #   optional, for `cierva estimate`: straight-tapered; a tailplane's span
//!                 #   tip to tip, a fin's root to tip; also half_chord_sweep_deg (0),
//!                 #   section_lift_slope_per_rad (2 pi) and, for the fin, body_depth_m (the
//!                 #   keel's or fuselage's depth at its root, 0)
//!     fin: {...}
//!     pod: {length_m: .., width_m: .., height_m: .., centroid_m: [..]}   # optional, for
//!                                          # `cierva estimate` (the pod's Munk couple, sidewash)
//!     estimates_at: {airspeed_mph: 70, mass_kg: 450, density_altitude_ft: 2000}
//!                                          # optional: where `cierva estimate` trims for the
//!                                          # propeller's slipstream
//!   controls:                          # linear maps from % of travel
//!     shaft_pitch_deg: {at_0_percent: -2, at_100_percent: 18}    # stick fwd -> aft
//!     shaft_roll_deg: {at_0_percent: -8, at_100_percent: 8}      # stick left -> right
//!     rudder_deg: {at_0_percent: -25, at_100_percent: 25}        # pedal left -> right
//!   corrections:                       # optional; absent means none
//!     propeller_blockage: 0.0          # seed 000 Sec. VII.A (0 none, 1 total)
//!     hub_aoa_factor: 0.5              # seed 000 Sec. VII.A; omit for the kinematic angle
//!     # and the main rotor's blade corrections, over its rotor file's: profile_drag_scale,
//!     # profile_drag_increment, pitch_offset_deg, lateral_inflow_offset_m_s,
//!     # elastic_twist_deg_per_kpa, hub_drag_area_m2 (the hub's flat-plate area),
//!     # profile_drag_reynolds_exponent (needs the rotor's drag_reynolds_number)
//! sources:                             # dotted paths; an entry covers everything below it
//!   mass.mass_kg: "seed 001: maximum all-up mass 450 kg"
//!   airframe.coefficients: "estimated: ..."
//! ranges:                              # optional: plausible ranges for `cierva sensitivity`
//!   mass.izz_kg_m2: {lower: 380, upper: 560, source: "estimated: ..."}
//!   # and the distribution `cierva uncertainty` samples: uniform (the default), triangular
//!   # (mode at the file's value) or normal (mean at the file's value, truncated to the range)
//!   mass.ixx_kg_m2: {lower: 200, upper: 320, distribution: normal, sigma: 25, source: "..."}
//! ```
//!
//! Every number under `aircraft` must be covered by a `sources` entry (its own path or a
//! parent's), and every entry must name a path that exists. A range names a parameter of
//! [`crate::inputs::parameters::PARAMETERS`], holds the file's value and has a source.

use crate::inputs::corrections::CorrectionSet;
use crate::inputs::parameters::{PARAMETERS, parameter};
use crate::inputs::reference::{Provenance, check_id};
use crate::inputs::rotor::RotorFile;
use crate::inputs::yaml::{self, InputError};
use cierva_model::aircraft::{
    Aircraft, AircraftError, ControlMaps, Drive, InflowDynamics, LinearMap, MainRotor,
    PropellerInstallation, Rotation,
};
use cierva_model::components::airframe::{Airframe, AirframeError, Surface, Table2};
use cierva_model::components::propeller::Propeller;
use cierva_model::components::rigid_body::MassProperties;
use cierva_model::components::rotor::{Hub, Numerics, Rotor};
use cierva_model::estimate::EstimateError;
use cierva_model::estimate::airframe::{
    FinGeometry, Geometry, Part, PartError, PodGeometry, SurfaceGeometry,
};
use cierva_model::estimate::body::Pod;
use cierva_model::estimate::lifting_surface::{Planform, THIN_AEROFOIL_SLOPE_PER_RAD};
use cierva_model::estimate::slipstream::Disc;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MassSpec {
    pub mass_kg: f64,
    /// The maximum all-up mass, kg, where the aircraft's documents state it: a case, a command
    /// or a trim point that asks for more is an error (a mass in pounds, most often).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_kg: Option<f64>,
    pub ixx_kg_m2: f64,
    pub iyy_kg_m2: f64,
    pub izz_kg_m2: f64,
    pub ixz_kg_m2: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MainRotorSpec {
    pub rotor_file: String,
    pub pivot_m: [f64; 3],
    pub spindle_length_m: f64,
    /// The rotor's physics settings belong in its rotor file (`physics:`); one stated here
    /// must agree with the rotor file's, and needs a source (older files state them here).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inflow: Option<crate::inputs::rotor::InflowSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skew: Option<crate::inputs::rotor::SkewSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub descent: Option<crate::inputs::rotor::DescentSpec>,
    /// In the full model: `dynamic` (seed 001 Eq. 3, the default) or `quasi_steady`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inflow_dynamics: Option<InflowDynamicsSpec>,
    pub azimuth_step_deg: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InflowDynamicsSpec {
    Dynamic,
    QuasiSteady,
}

#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MapSpec {
    pub at_0_percent: f64,
    pub at_100_percent: f64,
}

#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EngineSpec {
    pub max_power_w: f64,
    pub rated_rpm: f64,
    pub polar_inertia_kg_m2: f64,
}

#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GovernedSpec {
    pub rpm_at_0_percent: f64,
    pub rpm_at_100_percent: f64,
}

/// The drive: exactly one of the two.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DriveSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub engine: Option<EngineSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub governed: Option<GovernedSpec>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RotationSpec {
    Clockwise,
    Anticlockwise,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PropellerSpec {
    pub rotor_file: String,
    pub position_m: [f64; 3],
    pub rotation: RotationSpec,
    pub drive: DriveSpec,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    pub position_m: [f64; 3],
    pub area_m2: f64,
    pub lift_slope_per_rad: f64,
    pub incidence_deg: f64,
    pub stall_alpha_deg: f64,
    pub cd0: f64,
    pub control_effectiveness: f64,
    /// Fraction of the surface's area in the propeller's slipstream (0 to 1; absent: 0).
    #[serde(default)]
    pub slipstream_fraction: f64,
    /// Sidewash (fin) or downwash (tailplane) gradient from the airframe ahead (absent: 0).
    #[serde(default)]
    pub wash_gradient: f64,
    /// Dynamic pressure at the surface over the free stream's (absent: 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamic_pressure_ratio: Option<f64>,
    /// The planform `cierva estimate` works from (absent: none to estimate from).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub planform: Option<PlanformSpec>,
}

/// A straight-tapered planform as written (see the module docs).
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlanformSpec {
    pub span_m: f64,
    pub root_chord_m: f64,
    pub tip_chord_m: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub half_chord_sweep_deg: Option<f64>,
    /// Absent: thin-aerofoil theory's `2 pi`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section_lift_slope_per_rad: Option<f64>,
    /// A fin's: the depth of the keel, boom or fuselage at its root (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_depth_m: Option<f64>,
}

/// The pod as written: its length, width and height and its centroid (body axes from the
/// datum).
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PodSpec {
    pub length_m: f64,
    pub width_m: f64,
    pub height_m: f64,
    pub centroid_m: [f64; 3],
}

/// The flight condition at which the estimates that need the propeller's operating point are
/// made.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConditionSpec {
    pub airspeed_mph: f64,
    pub mass_kg: f64,
    pub density_altitude_ft: f64,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CoefficientsSpec {
    pub cx: Table2,
    pub cy: Table2,
    pub cz: Table2,
    pub cl: Table2,
    pub cm: Table2,
    pub cn: Table2,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AirframeSpec {
    pub reference_area_m2: f64,
    pub reference_length_m: f64,
    pub reference_span_m: f64,
    pub reference_point_m: [f64; 3],
    /// Where the side force acts (the pod's side-area centre); absent: the reference point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub side_force_centre_m: Option<[f64; 3]>,
    pub coefficients: CoefficientsSpec,
    /// The pod's Munk couple `(k2 - k1) Vol`, m^3 (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub munk_yaw_m3: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tailplane: Option<SurfaceSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fin: Option<SurfaceSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pod: Option<PodSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimates_at: Option<ConditionSpec>,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ControlsSpec {
    pub shaft_pitch_deg: MapSpec,
    pub shaft_roll_deg: MapSpec,
    pub rudder_deg: MapSpec,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AircraftSpec {
    pub mass: MassSpec,
    pub cg_m: [f64; 3],
    pub main_rotor: MainRotorSpec,
    pub propeller: PropellerSpec,
    pub airframe: AirframeSpec,
    pub controls: ControlsSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corrections: Option<CorrectionSet>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AircraftFileSpec {
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    pub aircraft: AircraftSpec,
    pub sources: BTreeMap<String, String>,
    /// Plausible ranges of parameters (names of [`PARAMETERS`]), each with its source: what
    /// `cierva sensitivity` weighs a needed change against.
    #[serde(default)]
    pub ranges: BTreeMap<String, RangeSpec>,
}

pub use crate::inputs::ranges::{Range, RangeSpec, Shape};

/// A loaded aircraft file.
#[derive(Debug, Clone, PartialEq)]
pub struct AircraftFile {
    pub path: PathBuf,
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    pub aircraft: Aircraft,
    pub main_rotor_file: RotorFile,
    pub propeller_file: RotorFile,
    pub sources: BTreeMap<String, String>,
    /// Plausible ranges of parameters, by name.
    pub ranges: BTreeMap<String, Range>,
    /// What `cierva estimate` works from, where the file gives a planform or a pod.
    pub estimate_inputs: Option<EstimateInputs>,
    /// Its maximum all-up mass, kg, where the file states it (`mass.max_kg`).
    pub max_mass_kg: Option<f64>,
}

/// An aircraft file's geometry for the estimates, checked, and the condition they are made at.
#[derive(Debug, Clone, PartialEq)]
pub struct EstimateInputs {
    pub geometry: Geometry,
    pub at: Option<ConditionSpec>,
}

/// Dotted paths of the leaves of a YAML value (a coefficient table is one leaf, as is a
/// position vector).
fn leaves(v: &serde_yaml::Value, prefix: &str, out: &mut Vec<String>) {
    match v.as_mapping() {
        Some(m) if !m.contains_key("alpha_deg") => {
            for (k, v) in m {
                let k = k.as_str().unwrap_or_default();
                let p = if prefix.is_empty() {
                    k.to_string()
                } else {
                    format!("{prefix}.{k}")
                };
                leaves(v, &p, out);
            }
        }
        _ => out.push(prefix.to_string()),
    }
}

fn covers(key: &str, path: &str) -> bool {
    path == key || path.starts_with(&format!("{key}."))
}

fn deg(m: MapSpec) -> LinearMap {
    LinearMap {
        at_0_percent: m.at_0_percent.to_radians(),
        at_100_percent: m.at_100_percent.to_radians(),
    }
}

/// Loads and checks an aircraft file, with its rotor files.
pub fn load(path: &Path) -> Result<AircraftFile, InputError> {
    let src = yaml::read(path)?;
    let spec: AircraftFileSpec = yaml::parse(path, &src)?;
    check_id(path, &src, &spec.id)?;
    let err = |field: &str, msg: String| InputError::field(path, &src, field, msg);
    check_sources(path, &spec, &err)?;
    let a = &spec.aircraft;
    let dir = path.parent().unwrap_or(Path::new("."));
    let nested = |field: &str, file: &str| {
        super::rotor::load(&dir.join(file))
            .map_err(|e| err(field, format!("in the referenced file: {e}")))
    };
    let main_rotor_file = nested("aircraft.main_rotor.rotor_file", &a.main_rotor.rotor_file)?;
    let physics = main_rotor_physics(&a.main_rotor, &main_rotor_file, &err)?;
    let propeller_file = nested("aircraft.propeller.rotor_file", &a.propeller.rotor_file)?;
    check_propeller_file(&a.propeller, &propeller_file, &err)?;
    check_step_and_controls(a, &err)?;
    let drive = drive_of(&a.propeller.drive, &err)?;
    let corrections = a.corrections.clone().unwrap_or_default();
    if !corrections.estimated.is_empty() {
        return Err(err(
            "aircraft.corrections.estimated",
            "an aircraft file gives its physical parameters where they belong (with their sources); `estimated` is for a corrections file's fitted values".into(),
        ));
    }
    let mut main_rotor = main_rotor_file.rotor.clone();
    CorrectionSet {
        propeller_blockage: None,
        hub_aoa_factor: None,
        ..corrections.clone()
    }
    .apply_to_rotor(&mut main_rotor)
    .map_err(|m| err("aircraft.corrections", m))?;
    let aircraft = Aircraft {
        mass: MassProperties {
            mass_kg: a.mass.mass_kg,
            ixx_kg_m2: a.mass.ixx_kg_m2,
            iyy_kg_m2: a.mass.iyy_kg_m2,
            izz_kg_m2: a.mass.izz_kg_m2,
            ixz_kg_m2: a.mass.ixz_kg_m2,
        },
        cg_m: a.cg_m,
        main_rotor: main_rotor_of(&a.main_rotor, main_rotor, physics),
        propeller: PropellerInstallation {
            propeller: Propeller {
                rotor: propeller_file.rotor.clone(),
                blockage: corrections.propeller_blockage.unwrap_or(0.0),
                map: None,
            },
            position_m: a.propeller.position_m,
            drive,
            rotation: match a.propeller.rotation {
                RotationSpec::Clockwise => Rotation::Clockwise,
                RotationSpec::Anticlockwise => Rotation::Anticlockwise,
            },
        },
        airframe: airframe_of(&a.airframe, &err)?,
        controls: ControlMaps {
            shaft_pitch_rad: deg(a.controls.shaft_pitch_deg),
            shaft_roll_rad: deg(a.controls.shaft_roll_deg),
            rudder_rad: deg(a.controls.rudder_deg),
        },
        hub_aoa_factor: corrections.hub_aoa_factor,
    };
    aircraft
        .validate()
        .map_err(|e| err(&field_of(&e), e.to_string()))?;
    check_work(&aircraft, &err)?;
    if let Some(max) = a.mass.max_kg
        && !(max.is_finite() && max >= a.mass.mass_kg)
    {
        return Err(err(
            "aircraft.mass.max_kg",
            format!(
                "the maximum all-up mass is at least the file's own mass ({} kg), got {max}",
                a.mass.mass_kg
            ),
        ));
    }
    let ranges = check_ranges(&spec.ranges, &mut aircraft.clone(), &err)?;
    let estimate_inputs = estimate_inputs(a, propeller_file.rotor.radius_m, &err)?;
    Ok(AircraftFile {
        path: path.to_path_buf(),
        id: spec.id,
        title: spec.title,
        provenance: spec.provenance,
        aircraft,
        main_rotor_file,
        propeller_file,
        sources: spec.sources,
        ranges,
        estimate_inputs,
        max_mass_kg: a.mass.max_kg,
    })
}

/// The `sources` checked against the numbers under `aircraft`: every leaf is covered by an
/// entry (its own path or a parent's), and every entry names a path that exists and is not
/// empty.
fn check_sources(
    path: &Path,
    spec: &AircraftFileSpec,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<(), InputError> {
    let written =
        serde_yaml::to_value(&spec.aircraft).map_err(|e| InputError::file(path, e.to_string()))?;
    let mut paths = Vec::new();
    leaves(&written, "", &mut paths);
    for p in &paths {
        if !spec.sources.keys().any(|k| covers(k, p)) {
            return Err(err(
                &format!("aircraft.{p}"),
                format!(
                    "`{p}` has no entry under `sources` (its own or a parent's): say where the number comes from (or \"estimated: why\")"
                ),
            ));
        }
    }
    for (k, s) in &spec.sources {
        if !paths.iter().any(|p| covers(k, p)) {
            return Err(err(
                &format!("sources.{k}"),
                format!("`{k}` is not a path under `aircraft`"),
            ));
        }
        if s.trim().is_empty() {
            return Err(err(
                &format!("sources.{k}"),
                "a source must not be empty".into(),
            ));
        }
    }
    Ok(())
}

/// The propeller's rotor file checked for what a propeller is: a rigid hub, and no hub drag
/// of its own.
fn check_propeller_file(
    p: &PropellerSpec,
    propeller_file: &RotorFile,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<(), InputError> {
    if propeller_file.rotor.hub != Hub::Rigid {
        return Err(err(
            "aircraft.propeller.rotor_file",
            format!(
                "the propeller's rotor file `{}` must have `hub: rigid` (a propeller's blades do not flap)",
                p.rotor_file
            ),
        ));
    }
    if propeller_file.rotor.hub_drag_area_m2 != 0.0 {
        return Err(err(
            "aircraft.propeller.rotor_file",
            format!(
                "the propeller's rotor file `{}` gives hub_drag_area_m2: a spinner's drag is the airframe's (its drag table), not the propeller's",
                p.rotor_file
            ),
        ));
    }
    Ok(())
}

/// The main rotor's work a revolution (blades x elements x azimuth steps) within the model's
/// limit with room for the numerical uncertainty's refinement, which doubles the elements and
/// halves the step (four times the work): a file is refused here, not a study later.
fn check_work(
    aircraft: &Aircraft,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<(), InputError> {
    use cierva_model::components::rotor::MAX_ELEMENT_STEPS_PER_REVOLUTION as MAX;
    let r = &aircraft.main_rotor;
    let steps = cierva_model::components::rotor::azimuth_steps(r.numerics.azimuth_step_rad)
        .map_err(|e| err("aircraft.main_rotor.azimuth_step_deg", e.to_string()))?;
    let work = r.rotor.blades * r.rotor.elements * steps;
    if 4 * work > MAX {
        return Err(err(
            "aircraft.main_rotor.azimuth_step_deg",
            format!(
                "{} blades x {} elements x {steps} azimuth steps is {work} blade-element \
                 evaluations a revolution; refined for the numerical uncertainty (twice the \
                 elements, half the step) it would be {}, past the model's {MAX} \
                 (MAX_ELEMENT_STEPS_PER_REVOLUTION): a coarser step or fewer elements",
                r.rotor.blades,
                r.rotor.elements,
                4 * work
            ),
        ));
    }
    Ok(())
}

/// The main rotor's azimuth step checked against its limits, then each control map's two ends
/// (finite and distinct).
fn check_step_and_controls(
    a: &AircraftSpec,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<(), InputError> {
    let step = a.main_rotor.azimuth_step_deg;
    if !crate::inputs::limits::azimuth_step_ok(step, 15.0) {
        return Err(err(
            "aircraft.main_rotor.azimuth_step_deg",
            format!(
                "must be in [{}, 15] deg (MIN_AZIMUTH_STEP_DEG), got {step}",
                crate::inputs::limits::MIN_AZIMUTH_STEP_DEG
            ),
        ));
    }
    for (name, m) in [
        ("shaft_pitch_deg", a.controls.shaft_pitch_deg),
        ("shaft_roll_deg", a.controls.shaft_roll_deg),
        ("rudder_deg", a.controls.rudder_deg),
    ] {
        if !(m.at_0_percent.is_finite()
            && m.at_100_percent.is_finite()
            && m.at_0_percent != m.at_100_percent)
        {
            return Err(err(
                &format!("aircraft.controls.{name}"),
                format!(
                    "the map's two ends must be finite and distinct, got {} and {} deg",
                    m.at_0_percent, m.at_100_percent
                ),
            ));
        }
    }
    Ok(())
}

/// The propeller's drive: an engine or a governed speed, exactly one of the two.
fn drive_of(d: &DriveSpec, err: &dyn Fn(&str, String) -> InputError) -> Result<Drive, InputError> {
    Ok(match (d.engine, d.governed) {
        (Some(e), None) => Drive::Engine {
            max_power_w: e.max_power_w,
            rated_rpm: e.rated_rpm,
            polar_inertia_kg_m2: e.polar_inertia_kg_m2,
        },
        (None, Some(g)) => Drive::Governed {
            rpm: LinearMap {
                at_0_percent: g.rpm_at_0_percent,
                at_100_percent: g.rpm_at_100_percent,
            },
        },
        _ => {
            return Err(err(
                "aircraft.propeller.drive",
                "give exactly one of `engine` or `governed`".into(),
            ));
        }
    })
}

/// The main rotor's physics settings: its rotor file's, with any the aircraft file states
/// where the rotor file leaves them out; one that differs from the rotor file's is an error at
/// its line (one answer per rotor).
fn main_rotor_physics(
    m: &MainRotorSpec,
    file: &crate::inputs::rotor::RotorFile,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<crate::inputs::rotor::Physics, InputError> {
    let stated = crate::inputs::rotor::PhysicsSpec {
        inflow: m.inflow,
        skew: m.skew,
        descent: m.descent,
    };
    let (physics, differ) = stated.over_named(file, "the aircraft file");
    let theirs = &file.physics;
    let in_rotor_file = |name: &str| match name {
        "inflow" => theirs.inflow.is_some(),
        "skew" => theirs.skew.is_some(),
        _ => theirs.descent.is_some(),
    };
    for (name, d) in &differ {
        if in_rotor_file(name) {
            return Err(err(
                &format!("aircraft.main_rotor.{name}"),
                format!(
                    "{d}; a rotor's physics settings live in its rotor file (`physics:`), so \
                     that every case, fit and command of the rotor gives one answer: remove \
                     `{name}` here, or change the rotor file with its evidence"
                ),
            ));
        }
    }
    Ok(physics)
}

/// The main rotor as installed: the (corrected) rotor on its pivot and spindle, with its
/// physics settings (its rotor file's) and the aircraft file's azimuth step.
fn main_rotor_of(
    m: &MainRotorSpec,
    rotor: Rotor,
    physics: crate::inputs::rotor::Physics,
) -> MainRotor {
    MainRotor {
        rotor,
        pivot_m: m.pivot_m,
        spindle_length_m: m.spindle_length_m,
        collective_shift_rad: 0.0,
        inflow: physics.model(),
        inflow_dynamics: match m.inflow_dynamics {
            Some(InflowDynamicsSpec::QuasiSteady) => InflowDynamics::QuasiSteady,
            _ => InflowDynamics::Dynamic,
        },
        numerics: Numerics {
            azimuth_step_rad: m.azimuth_step_deg.to_radians(),
            periodic_tolerance: 1e-9,
            ..Numerics::default()
        },
    }
}

/// A tail surface in the model's units (angles in radians; an absent dynamic-pressure ratio
/// is 1).
fn surface(s: &SurfaceSpec) -> Surface {
    Surface {
        position_m: s.position_m,
        area_m2: s.area_m2,
        lift_slope_per_rad: s.lift_slope_per_rad,
        incidence_rad: s.incidence_deg.to_radians(),
        stall_alpha_rad: s.stall_alpha_deg.to_radians(),
        cd0: s.cd0,
        control_effectiveness: s.control_effectiveness,
        slipstream_fraction: s.slipstream_fraction,
        wash_gradient: s.wash_gradient,
        dynamic_pressure_ratio: s.dynamic_pressure_ratio.unwrap_or(1.0),
    }
}

/// The airframe: its reference geometry, its six coefficient tables, the pod's apparent masses
/// (absent: none) and its tail surfaces. A Munk couple needs the pod: its centroid is where the
/// apparent masses move, and its shape gives their axial part (`k1 Vol`, Lamb's spheroid).
fn airframe_of(
    af: &AirframeSpec,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<Airframe, InputError> {
    let c = &af.coefficients;
    let munk_yaw_m3 = af.munk_yaw_m3.unwrap_or(0.0);
    let (munk_axial_m3, munk_centre_m) = match (&af.pod, munk_yaw_m3 > 0.0) {
        (_, false) => (0.0, af.reference_point_m),
        (None, true) => {
            return Err(err(
                "aircraft.airframe.munk_yaw_m3",
                "the pod's Munk couple acts where its apparent mass moves: give the pod's shape and centroid under `airframe.pod` ({length_m, width_m, height_m, centroid_m})".into(),
            ));
        }
        (Some(p), true) => {
            let pod = cierva_model::estimate::body::Pod {
                length_m: p.length_m,
                width_m: p.width_m,
                height_m: p.height_m,
            };
            let (k1, _) = pod
                .checked()
                .and_then(|pod| cierva_model::estimate::body::apparent_mass_factors(pod.fineness()))
                .map_err(|e| err("aircraft.airframe.pod", e.to_string()))?;
            (k1 * pod.volume_m3(), p.centroid_m)
        }
    };
    Ok(Airframe {
        reference_area_m2: af.reference_area_m2,
        reference_length_m: af.reference_length_m,
        reference_span_m: af.reference_span_m,
        reference_point_m: af.reference_point_m,
        side_force_centre_m: af.side_force_centre_m,
        coefficients: [
            c.cx.clone(),
            c.cy.clone(),
            c.cz.clone(),
            c.cl.clone(),
            c.cm.clone(),
            c.cn.clone(),
        ],
        munk_yaw_m3,
        munk_axial_m3,
        munk_centre_m,
        tailplane: af.tailplane.as_ref().map(surface),
        fin: af.fin.as_ref().map(surface),
    })
}

/// The geometry the estimates work from, checked (`None` where the file gives no planform and
/// no pod): every input that gives no finite estimate is a located error.
fn estimate_inputs(
    a: &AircraftSpec,
    propeller_radius_m: f64,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<Option<EstimateInputs>, InputError> {
    let af = &a.airframe;
    let (fin, tail) = (planform_of(&af.fin), planform_of(&af.tailplane));
    if fin.is_none() && tail.is_none() && af.pod.is_none() {
        if af.estimates_at.is_some() {
            return Err(err(
                "aircraft.airframe.estimates_at",
                "there is nothing to estimate: give a surface's `planform` or the `pod`".into(),
            ));
        }
        return Ok(None);
    }
    if let Some((_, p)) = tail
        && p.body_depth_m.is_some()
    {
        return Err(err(
            "aircraft.airframe.tailplane.planform.body_depth_m",
            "only a fin stands on a body: body_depth_m belongs to the fin's planform".into(),
        ));
    }
    let surface = |name: &str, (s, p): (&SurfaceSpec, PlanformSpec), mirrored: bool| {
        let planform = Planform {
            span_m: p.span_m,
            root_chord_m: p.root_chord_m,
            tip_chord_m: p.tip_chord_m,
            half_chord_sweep_rad: p.half_chord_sweep_deg.unwrap_or(0.0).to_radians(),
            mirrored,
        };
        let field = format!("aircraft.airframe.{name}.planform");
        planform.checked().map_err(|e| located(&field, &e, err))?;
        let area = planform.area_m2();
        if (area - s.area_m2).abs() > 0.02 * s.area_m2 {
            return Err(err(
                &field,
                format!(
                    "the planform's area (span times mean chord) is {area:.4} m^2 and the {name}'s area_m2 {}: they must agree within 2 %",
                    s.area_m2
                ),
            ));
        }
        Ok(SurfaceGeometry {
            position_m: s.position_m,
            planform,
            section_lift_slope_per_rad: p
                .section_lift_slope_per_rad
                .unwrap_or(THIN_AEROFOIL_SLOPE_PER_RAD),
        })
    };
    let geometry = Geometry {
        fin: match fin {
            None => None,
            Some(f) => Some(FinGeometry {
                surface: surface("fin", f, false)?,
                body_depth_m: f.1.body_depth_m.unwrap_or(0.0),
            }),
        },
        tailplane: tail.map(|t| surface("tailplane", t, true)).transpose()?,
        pod: af.pod.map(|p| PodGeometry {
            pod: Pod {
                length_m: p.length_m,
                width_m: p.width_m,
                height_m: p.height_m,
            },
            centroid_m: p.centroid_m,
        }),
        disc: Disc {
            centre_m: a.propeller.position_m,
            radius_m: propeller_radius_m,
        },
    };
    cierva_model::estimate::airframe::check(&geometry).map_err(|e| part_error(&e, err))?;
    if let Some(c) = af.estimates_at
        && !(c.airspeed_mph.is_finite()
            && c.airspeed_mph > 0.0
            && c.mass_kg.is_finite()
            && c.mass_kg > 0.0
            && c.density_altitude_ft.is_finite())
    {
        return Err(err(
            "aircraft.airframe.estimates_at",
            "give a positive airspeed and mass and a finite density altitude".into(),
        ));
    }
    Ok(Some(EstimateInputs {
        geometry,
        at: af.estimates_at,
    }))
}

/// A surface and its planform, where it gives one.
fn planform_of(s: &Option<SurfaceSpec>) -> Option<(&SurfaceSpec, PlanformSpec)> {
    s.as_ref().and_then(|s| s.planform.map(|p| (s, p)))
}

/// An estimate's bad input at the field it came from under `prefix` (a planform's or the pod's
/// own field where the error names one, else the part).
fn located(
    prefix: &str,
    e: &EstimateError,
    err: &dyn Fn(&str, String) -> InputError,
) -> InputError {
    let name = match e {
        EstimateError::Input { name, .. } => *name,
        EstimateError::Domain { .. } => "",
    };
    let own = [
        "span_m",
        "root_chord_m",
        "tip_chord_m",
        "half_chord_sweep_deg",
        "body_depth_m",
        "section_lift_slope_per_rad",
        "length_m",
        "width_m",
        "height_m",
    ];
    if own.contains(&name) {
        err(&format!("{prefix}.{name}"), e.to_string())
    } else {
        err(prefix, e.to_string())
    }
}

/// A part's bad input at its field: the fin's and tailplane's planforms, the pod, and a fin
/// that does not stand behind the pod at its position.
pub fn part_error(e: &PartError, err: &dyn Fn(&str, String) -> InputError) -> InputError {
    let prefix = match e.part {
        Part::Fin if e.error.to_string().contains("behind the pod") => {
            "aircraft.airframe.fin.position_m"
        }
        Part::Fin => "aircraft.airframe.fin.planform",
        Part::Tailplane => "aircraft.airframe.tailplane.planform",
        Part::Pod => "aircraft.airframe.pod",
        Part::Propeller => "aircraft.propeller",
    };
    located(prefix, &e.error, err)
}

/// The ranges, checked: each names a parameter, holds the file's value, and has a source.
fn check_ranges(
    spec: &BTreeMap<String, RangeSpec>,
    aircraft: &mut Aircraft,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<BTreeMap<String, Range>, InputError> {
    let names: Vec<String> = PARAMETERS.iter().map(|p| p.name.to_string()).collect();
    crate::inputs::ranges::checked(
        spec,
        &|name| parameter(aircraft, name),
        &names,
        "this aircraft",
        err,
    )
}

/// The field of the aircraft file an error points at.
fn field_of(e: &AircraftError) -> String {
    match e {
        AircraftError::Body(_) => "aircraft.mass".into(),
        AircraftError::Airframe(AirframeError::Table(t)) => {
            format!("aircraft.airframe.coefficients.{t}")
        }
        AircraftError::Airframe(AirframeError::Surface(s)) if *s == "tailplane" || *s == "fin" => {
            format!("aircraft.airframe.{s}")
        }
        AircraftError::Airframe(_) => "aircraft.airframe".into(),
        AircraftError::Rotor(_) => "aircraft.main_rotor.rotor_file".into(),
        AircraftError::Propeller(_) => "aircraft.propeller".into(),
        AircraftError::Invalid { name, .. } => match *name {
            "spindle_length_m" => "aircraft.main_rotor.spindle_length_m".into(),
            "blockage" => "aircraft.corrections.propeller_blockage".into(),
            "hub_aoa_factor" => "aircraft.corrections.hub_aoa_factor".into(),
            "shaft_pitch map" => "aircraft.controls.shaft_pitch_deg".into(),
            "shaft_roll map" => "aircraft.controls.shaft_roll_deg".into(),
            "rudder map" => "aircraft.controls.rudder_deg".into(),
            "positions" => "aircraft.cg_m".into(),
            _ => "aircraft.propeller.drive".into(),
        },
        // A run's steps, set by its azimuth step.
        AircraftError::TooMany { .. } => "aircraft.main_rotor.azimuth_step_deg".into(),
    }
}

impl AircraftFile {
    /// Whether `mass_kg` is within the aircraft's stated masses (at most its maximum all-up
    /// mass, where the file states one), or why not, with the mass in pounds where it would
    /// fit as such.
    pub fn check_mass(&self, mass_kg: f64) -> Result<(), String> {
        let Some(max) = self.max_mass_kg else {
            return Ok(());
        };
        if mass_kg <= max {
            return Ok(());
        }
        let as_pounds = mass_kg * crate::inputs::channels::KG_PER_LB;
        let hint = if as_pounds <= max {
            format!(" (a mass in pounds? {mass_kg} lb is {as_pounds:.1} kg)")
        } else {
            String::new()
        };
        Err(format!(
            "{mass_kg} kg is above the maximum all-up mass of {} ({max} kg, `mass.max_kg` of \
             {}){hint}",
            self.id,
            self.path.display()
        ))
    }

    /// The source the file gives a parameter of [`PARAMETERS`]: its own entry or the nearest
    /// parent's (`airframe.fin.position_m.x` is covered by `airframe.fin.position_m`,
    /// `airframe.fin` or `airframe`); `None` where nothing covers it.
    pub fn source_of(&self, parameter: &str) -> Option<&str> {
        let path = ["x", "y", "z"]
            .iter()
            .find_map(|c| parameter.strip_suffix(&format!(".{c}")))
            .unwrap_or(parameter);
        self.sources
            .iter()
            .filter(|(k, _)| covers(k, path))
            .max_by_key(|(k, _)| k.len())
            .map(|(_, v)| v.as_str())
    }

    /// A copy with corrections set (those given; the rest as in the file), checked. Its path is
    /// marked with the corrections, so cached results keep them apart.
    pub fn with_corrections(&self, c: &CorrectionSet) -> Result<AircraftFile, String> {
        let mut f = self.clone();
        c.apply_to_aircraft(&mut f.aircraft)?;
        f.path = PathBuf::from(format!("{}#{}", self.path.display(), c.describe()));
        Ok(f)
    }
}
