//! What `cierva estimate` computes for an aircraft file: its geometry's estimates
//! ([`cierva_model::estimate::airframe`]) at the propeller's operating point in trim at the
//! file's `estimates_at` condition (or one given), and each estimate beside the value the file
//! gives for it.
//!
//! The operating point is the trimmed aircraft's: the propeller's thrust and the airspeed
//! reaching its disc, and its side force per m/s of sideslip, `dY/dv`, by central differences of
//! the averaged model about the trim (the propeller's normal force at incidence).

use crate::inputs::aircraft::{AircraftFile, ConditionSpec};
use crate::inputs::condition::Loading;
use crate::inputs::condition::TrimRequest;
use crate::units::FT_TO_M;
use cierva_model::aircraft::Air;
use cierva_model::components::atmosphere;
use cierva_model::estimate::airframe::{self, Estimates};
use cierva_model::estimate::slipstream::OperatingPoint;
use cierva_model::estimate::{Estimate, EstimateError};
use serde::Serialize;

/// The estimates for a file at a condition, and the file's values beside them.
#[derive(Debug, Clone, Serialize)]
pub struct Derivation {
    pub aircraft: String,
    pub condition: ConditionSpec,
    pub operating_point: OperatingPoint,
    pub estimates: Estimates,
    pub compared: Vec<Compared>,
}

/// A coefficient the file gives and its estimate.
#[derive(Debug, Clone, Serialize)]
pub struct Compared {
    /// The dotted path under `aircraft` (`airframe.fin.lift_slope_per_rad`).
    pub field: String,
    pub file: f64,
    pub estimate: Estimate,
    /// The file's `ranges:` entry for it, where it has one: `(lower, upper)`.
    pub file_range: Option<(f64, f64)>,
}

/// Why no estimate could be made.
#[derive(Debug, thiserror::Error)]
pub enum EstimateRunError {
    #[error(
        "{0} gives no geometry to estimate from: add a surface's `planform` or the `pod` under `airframe` (see `cierva estimate --help`)"
    )]
    NoGeometry(String),
    #[error(
        "{0} says no condition to estimate at: give `airframe.estimates_at` in the file, or --airspeed-mph"
    )]
    NoCondition(String),
    #[error(
        "{0}'s corrections block the propeller (propeller_blockage {1}): the slipstream estimates take the free stream through the disc"
    )]
    Blocked(String, f64),
    #[error("the trim at the estimates' condition failed: {0}")]
    Trim(#[from] crate::run::trim::TrimRunError),
    #[error("the propeller's side force about the trim: {0}")]
    Model(#[from] cierva_model::aircraft::AircraftError),
    #[error("{0}")]
    Estimate(#[from] airframe::PartError),
    #[error("{0}")]
    Input(#[from] EstimateError),
}

/// The estimates of `file` at `at` (default: the file's `estimates_at`).
pub fn derive(
    file: &AircraftFile,
    at: Option<ConditionSpec>,
) -> Result<Derivation, EstimateRunError> {
    let name = file.path.display().to_string();
    let inputs = file
        .estimate_inputs
        .as_ref()
        .ok_or_else(|| EstimateRunError::NoGeometry(name.clone()))?;
    let condition = at
        .or(inputs.at)
        .ok_or_else(|| EstimateRunError::NoCondition(name.clone()))?;
    let blockage = file.aircraft.propeller.propeller.blockage;
    if blockage > 0.0 {
        return Err(EstimateRunError::Blocked(name, blockage));
    }
    let operating_point = operating_point(file, condition)?;
    let estimates = airframe::estimate(&inputs.geometry, &operating_point)?;
    let compared = compare(file, &estimates);
    Ok(Derivation {
        aircraft: name,
        condition,
        operating_point,
        estimates,
        compared,
    })
}

/// The propeller's operating point in trim at `c`.
pub fn operating_point(
    file: &AircraftFile,
    c: ConditionSpec,
) -> Result<OperatingPoint, EstimateRunError> {
    let loading = Loading {
        mass_kg: Some(c.mass_kg),
        density_altitude_ft: c.density_altitude_ft,
    };
    let request = TrimRequest::level(c.airspeed_mph);
    let trim = crate::run::trim::run_trim(&file.aircraft, request, loading)?;
    let atm = atmosphere::at_density_altitude(c.density_altitude_ft * FT_TO_M)
        .map_err(crate::run::trim::TrimRunError::from)?;
    let air = Air {
        density_kg_m3: atm.density_kg_m3,
        speed_of_sound_m_s: atm.speed_of_sound_m_s,
    };
    let mut aircraft = file.aircraft.clone();
    aircraft.mass.mass_kg = c.mass_kg;
    let prop = &trim.averaged.propeller;
    // Central differences in the sideslip velocity: 0.1 m/s is 0.2 deg at 30 m/s, in the
    // propeller's linear range and far above the averaged model's rounding.
    let h = 0.1;
    let side = |dv: f64| -> Result<f64, cierva_model::aircraft::AircraftError> {
        let mut s = trim.state;
        s.body.v_m_s += dv;
        let a = aircraft.averaged(&s, &trim.controls, air, trim.averaged.flap_start)?;
        Ok(a.loads.propeller.y_n)
    };
    let side_force_per_m_s = (side(h)? - side(-h)?) / (2.0 * h);
    Ok(OperatingPoint {
        airspeed_m_s: prop.disc_airspeed_m_s,
        density_kg_m3: atm.density_kg_m3,
        thrust_n: prop.thrust_n,
        side_force_per_m_s,
    })
}

/// Each estimate beside the file's value for it (the coefficients the model takes).
pub fn compare(file: &AircraftFile, e: &Estimates) -> Vec<Compared> {
    let mut out = Vec::new();
    let mut push = |field: &str, estimate: Option<Estimate>| {
        let Some(estimate) = estimate else { return };
        let Some(value) = crate::inputs::parameters::parameter(&file.aircraft, field) else {
            return;
        };
        out.push(Compared {
            field: field.to_string(),
            file: value,
            estimate,
            file_range: file.ranges.get(field).map(|r| (r.lower, r.upper)),
        });
    };
    for (name, s) in [("fin", &e.fin), ("tailplane", &e.tailplane)] {
        let Some(s) = s else { continue };
        push(
            &format!("airframe.{name}.lift_slope_per_rad"),
            Some(s.lift_slope_per_rad),
        );
        push(
            &format!("airframe.{name}.slipstream_fraction"),
            Some(s.slipstream_fraction),
        );
        push(&format!("airframe.{name}.wash_gradient"), s.wash_gradient);
        push(
            &format!("airframe.{name}.dynamic_pressure_ratio"),
            Some(s.dynamic_pressure_ratio),
        );
    }
    push("airframe.munk_yaw_m3", e.munk_yaw_m3);
    out
}
