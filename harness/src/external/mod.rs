//! Flight models as case subjects: cierva's own aircraft, or another simulation.
//!
//! A [`FlightModel`] answers, at a flight condition and loading, what the checks on an aircraft
//! ask: its trim quantities (names from [`crate::inputs::quantity::TRIM`]; a model may give a subset),
//! its linear model (cierva's state and control names, those of
//! [`cierva_model::aircraft::linearise::STATES`] and `CONTROLS`)
//! and its response to a record's control changes. Each is optional: a model that does not
//! provide one says so, and a check that needs it is an error, never a pass.
//!
//! cierva's own aircraft is one ([`CiervaAircraft`]). Another simulation is a subject two ways:
//! - [`command`]: a program cierva runs once per request (the protocol `cierva-external/1`,
//!   `docs/external-models.md`);
//! - [`files`]: its outputs as files (a trim table, a linear model, a time history).

pub mod command;
pub mod files;

use crate::inputs::controls::ControlTable;
use crate::run::replay::{Replayed, Simulation};
use crate::{Loading, TrimRequest};
use cierva_model::LinearModel;
use std::sync::Arc;

/// Named values (a trim's quantities), as the checks compare them.
pub type Quantities = Vec<(&'static str, f64)>;

/// Control changes from trim to fly: the table, and the times the response is wanted at
/// (`k * sample_s`, `k = 0..=samples`).
#[derive(Debug, Clone, PartialEq)]
pub struct ControlChanges {
    pub table: ControlTable,
    pub sample_s: f64,
    pub samples: usize,
}

/// What a model does not provide, as the error a check that needs it gives.
pub fn not_provided(model: &str, what: &str) -> String {
    format!("{model} does not provide {what}")
}

/// A flight model as a case's subject (see the module docs).
pub trait FlightModel: std::fmt::Debug + Send + Sync {
    /// The model in words, for errors ("the command `python3 model.py`").
    fn describe(&self) -> String;

    /// Its trim at `condition`: quantities named as in [`crate::inputs::quantity::TRIM`] (a subset).
    fn trim(&self, _condition: TrimRequest, _loading: Loading) -> Result<Quantities, String> {
        Err(not_provided(&self.describe(), "a trim"))
    }

    /// Its linear model about the trim at `condition` (straight flight), with cierva's state
    /// and control names and units.
    fn linear_model(
        &self,
        _condition: TrimRequest,
        _loading: Loading,
    ) -> Result<LinearModel, String> {
        Err(not_provided(&self.describe(), "a linear model"))
    }

    /// Its response (changes from the trim at `condition`) to `controls`, at the times they
    /// ask for: every response of [`crate::run::replay::SIGNALS`] it computes (an empty series
    /// for one it does not).
    fn time_history(
        &self,
        _condition: TrimRequest,
        _loading: Loading,
        _controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        Err(not_provided(&self.describe(), "a time history"))
    }
}

/// cierva's own aircraft at a loading, flown by `simulation` at `azimuth_step_rad` (the full
/// blade model's step).
#[derive(Debug, Clone, Copy)]
pub struct CiervaAircraft<'a> {
    pub file: &'a crate::inputs::aircraft::AircraftFile,
    pub simulation: Simulation,
    pub azimuth_step_rad: f64,
}

impl<'a> CiervaAircraft<'a> {
    /// The aircraft, flown by the full blade model at its file's azimuth step.
    pub fn new(file: &'a crate::inputs::aircraft::AircraftFile) -> Self {
        Self {
            file,
            simulation: Simulation::FullBlade,
            azimuth_step_rad: file.aircraft.main_rotor.numerics.azimuth_step_rad,
        }
    }
}

impl FlightModel for CiervaAircraft<'_> {
    fn describe(&self) -> String {
        format!("the aircraft {}", self.file.path.display())
    }

    fn trim(&self, condition: TrimRequest, loading: Loading) -> Result<Quantities, String> {
        let t =
            crate::run_trim(&self.file.aircraft, condition, loading).map_err(|e| e.to_string())?;
        Ok(trim_quantities_of(&self.file.aircraft, loading, &t))
    }

    fn linear_model(
        &self,
        condition: TrimRequest,
        loading: Loading,
    ) -> Result<LinearModel, String> {
        Ok(crate::linearise_cached(self.file, condition, loading)?
            .1
            .model
            .clone())
    }

    fn time_history(
        &self,
        condition: TrimRequest,
        loading: Loading,
        controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        crate::run::replay::fly(
            &self.file.aircraft,
            condition,
            loading,
            &|t| controls.table.at(t),
            crate::run::replay::FlySettings {
                simulation: self.simulation,
                sample_s: controls.sample_s,
                samples: controls.samples,
                azimuth_step_rad: self.azimuth_step_rad,
            },
        )
    }
}

/// Another simulation as a subject: the model, the loading it is asked at, and what it is
/// (its command or files, as written: two subjects are the same when these are).
#[derive(Debug, Clone)]
pub struct External {
    pub model: Arc<dyn FlightModel>,
    pub loading: Loading,
    /// The subject as written, for comparison and reports.
    pub written: String,
}

impl PartialEq for External {
    fn eq(&self, other: &Self) -> bool {
        self.written == other.written && self.loading == other.loading
    }
}

/// A shared model is a model.
impl<T: FlightModel + ?Sized> FlightModel for Arc<T> {
    fn describe(&self) -> String {
        self.as_ref().describe()
    }
    fn trim(&self, condition: TrimRequest, loading: Loading) -> Result<Quantities, String> {
        self.as_ref().trim(condition, loading)
    }
    fn linear_model(
        &self,
        condition: TrimRequest,
        loading: Loading,
    ) -> Result<LinearModel, String> {
        self.as_ref().linear_model(condition, loading)
    }
    fn time_history(
        &self,
        condition: TrimRequest,
        loading: Loading,
        controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        self.as_ref().time_history(condition, loading, controls)
    }
}

/// A trim quantity's static name, from what a model wrote: unknown names are an error that
/// lists the known ones.
pub fn trim_name(name: &str) -> Result<&'static str, String> {
    crate::inputs::quantity::TRIM
        .iter()
        .map(|q| q.name())
        .find(|n| *n == name)
        .ok_or_else(|| {
            let known: Vec<String> = crate::inputs::quantity::TRIM
                .iter()
                .map(|q| q.name().to_string())
                .collect();
            let hint = crate::inputs::yaml::nearest(name, &known)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            format!(
                "`{name}` is not a trim quantity{hint}; they are [{}]",
                known.join(", ")
            )
        })
}

/// Checks a model's response against what a record needs: each response it carries, sampled
/// `samples + 1` times.
pub fn check_response(
    model: &str,
    flown: &Replayed,
    signals: &[String],
    samples: usize,
) -> Result<(), String> {
    for s in signals {
        let got = flown.signal(s).map_or(0, <[f64]>::len);
        if got == 0 {
            return Err(format!("{model}'s time history has no `{s}`"));
        }
        if got != samples + 1 {
            return Err(format!(
                "{model}'s time history has {got} samples of `{s}`, the record {}",
                samples + 1
            ));
        }
    }
    Ok(())
}

/// The quantities of a trim of `aircraft` at `loading`.
pub fn trim_quantities_of(
    aircraft: &cierva_model::aircraft::Aircraft,
    loading: crate::Loading,
    t: &cierva_model::aircraft::trim::Trim,
) -> Quantities {
    let d = f64::to_degrees;
    use crate::inputs::quantity::Quantity as Q;
    let r = &t.averaged.rotor;
    let c = &t.controls;
    vec![
        (Q::ResidualNorm.name(), t.residual_norm),
        (
            Q::StickLongitudinalPercent.name(),
            c.stick_longitudinal_percent,
        ),
        (Q::StickLateralPercent.name(), c.stick_lateral_percent),
        (Q::PedalPercent.name(), c.pedal_percent),
        (Q::ThrottlePercent.name(), c.throttle_percent),
        (Q::PitchDeg.name(), d(t.pitch_rad)),
        (Q::RollDeg.name(), d(t.roll_rad)),
        (Q::AlphaDeg.name(), d(t.alpha_rad)),
        (Q::SideslipDeg.name(), d(t.sideslip_rad)),
        (Q::RotorRpm.name(), t.rotor_rpm),
        (Q::PropellerRpm.name(), t.propeller_rpm),
        (Q::RotorTorqueNM.name(), r.driving_torque_n_m),
        (Q::ThrustN.name(), r.thrust_n),
        (Q::DiscAlphaDeg.name(), d(r.disc_alpha_rad)),
        (Q::TipSpeedRatio.name(), r.tip_speed_ratio),
        (Q::ThrustCoefficientOverSolidity.name(), {
            let rotor = &aircraft.main_rotor.rotor;
            let rho = cierva_model::components::atmosphere::at_density_altitude(
                loading.density_altitude_ft * crate::FT_TO_M,
            )
            .map_or(f64::NAN, |a| a.density_kg_m3);
            let tip = t.state.rotor_omega_rad_s * rotor.radius_m;
            r.thrust_n
                / (rho * std::f64::consts::PI * rotor.radius_m.powi(2) * tip * tip)
                / rotor.solidity()
        }),
        (Q::A1Deg.name(), d(r.a1_rad)),
        (Q::B1Deg.name(), d(r.b1_rad)),
        (Q::InflowV0MS.name(), t.state.inflow.v0),
        (Q::InflowV1cMS.name(), t.state.inflow.v1c),
    ]
}
