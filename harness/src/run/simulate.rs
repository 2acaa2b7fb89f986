//! The full individual-blade model flown from its periodic trim.

use crate::inputs::condition::{Loading, TrimRequest};
use crate::units::{FT_TO_M, MPH_TO_M_S};

use super::trim::run_trim;

/// Where a simulation of the full model starts: the aircraft at its mass, the state on the
/// full model's periodic orbit (blade 1 at azimuth zero), the trimmed controls and the air.
#[derive(Debug, Clone)]
pub struct SimulationStart {
    pub aircraft: cierva_model::aircraft::Aircraft,
    pub state: cierva_model::aircraft::FullState,
    pub controls: cierva_model::aircraft::Controls,
    pub air: cierva_model::aircraft::Air,
}

/// Trims the aircraft and refines the trim to the full model's periodic orbit.
pub fn simulation_start(
    aircraft: &cierva_model::aircraft::Aircraft,
    request: TrimRequest,
    loading: Loading,
) -> Result<SimulationStart, String> {
    use cierva_model::simulation::periodic_trim::periodic_trim;
    use cierva_model::{aircraft::Air, aircraft::trim, components::atmosphere};
    let mut a = aircraft.clone();
    if let Some(m) = loading.mass_kg {
        a.mass.mass_kg = m;
    }
    let t = run_trim(
        &a,
        request,
        Loading {
            mass_kg: None,
            ..loading
        },
    )
    .map_err(|e| e.to_string())?;
    let air = atmosphere::at_density_altitude(loading.density_altitude_ft * FT_TO_M)
        .map_err(|e| e.to_string())?;
    let air = Air {
        density_kg_m3: air.density_kg_m3,
        speed_of_sound_m_s: air.speed_of_sound_m_s,
    };
    let condition = trim::Condition {
        airspeed_m_s: request.airspeed_mph * MPH_TO_M_S,
        climb_m_s: request.climb_m_s,
        turn_rate_rad_s: request.turn_rate_deg_s.to_radians(),
        air,
    };
    let pt = periodic_trim(&a, condition, &t, trim::TrimOptions::default())
        .map_err(|e| format!("periodic trim of the full model: {e}"))?;
    Ok(SimulationStart {
        aircraft: a,
        state: pt.start,
        controls: pt.controls,
        air,
    })
}

impl SimulationStart {
    /// Flies the full model from the start with the given control changes from trim
    /// (`changes(t)` in % of travel: longitudinal stick, lateral stick, pedal, throttle).
    pub fn run(
        &self,
        changes: &dyn Fn(f64) -> [f64; 4],
        settings: cierva_model::simulation::timehistory::Settings,
    ) -> Result<cierva_model::simulation::timehistory::TimeHistory, SimulationRunError> {
        let u0 = self.controls;
        let controls = |time: f64| {
            let d = changes(time);
            cierva_model::aircraft::Controls {
                stick_longitudinal_percent: u0.stick_longitudinal_percent + d[0],
                stick_lateral_percent: u0.stick_lateral_percent + d[1],
                pedal_percent: u0.pedal_percent + d[2],
                throttle_percent: u0.throttle_percent + d[3],
            }
        };
        cierva_model::simulation::timehistory::run(
            &self.aircraft,
            self.state.clone(),
            &controls,
            self.air,
            settings,
        )
        .map_err(|(time_s, error)| SimulationRunError::Run { time_s, error })
    }
}

/// Why a simulation stopped: it could not start (the trim or the full model's periodic orbit),
/// or the model failed at a time (or refused what it was asked before the first step).
#[derive(Debug, Clone, PartialEq)]
pub enum SimulationRunError {
    Start(String),
    Run {
        time_s: f64,
        error: cierva_model::aircraft::AircraftError,
    },
}

impl SimulationRunError {
    /// Whether the error is the input's: a run longer than the time history's step limit
    /// (`timehistory::MAX_STEPS`: a mistyped duration or azimuth step), refused before the
    /// first step. Anything else is the model's.
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            Self::Run {
                time_s,
                error: cierva_model::aircraft::AircraftError::TooMany { .. },
            } if *time_s == 0.0
        )
    }
}

impl std::fmt::Display for SimulationRunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Start(e) => write!(f, "{e}"),
            Self::Run { time_s, error } => write!(f, "at {time_s:.3} s: {error}"),
        }
    }
}

impl From<SimulationRunError> for String {
    fn from(e: SimulationRunError) -> Self {
        e.to_string()
    }
}

/// Trims the aircraft, refines the trim to the full model's periodic orbit, and flies the
/// full model from there with the given control changes from trim (`changes(t)` in % of
/// travel: longitudinal stick, lateral stick, pedal, throttle).
pub fn run_simulation(
    aircraft: &cierva_model::aircraft::Aircraft,
    request: TrimRequest,
    loading: Loading,
    changes: &dyn Fn(f64) -> [f64; 4],
    settings: cierva_model::simulation::timehistory::Settings,
) -> Result<cierva_model::simulation::timehistory::TimeHistory, SimulationRunError> {
    simulation_start(aircraft, request, loading)
        .map_err(SimulationRunError::Start)?
        .run(changes, settings)
}
