//! Trims an aircraft at a condition and loading, in the units people fly in.

use crate::inputs::condition::{Loading, TrimRequest};
use crate::units::{FT_TO_M, MPH_TO_M_S};

/// Why a trim run did not produce a trim.
#[derive(Debug, thiserror::Error)]
pub enum TrimRunError {
    #[error("{0}")]
    Atmosphere(#[from] cierva_model::components::atmosphere::AtmosphereError),
    #[error("{0}")]
    Trim(#[from] cierva_model::aircraft::trim::TrimError),
}

impl TrimRunError {
    /// Whether the inputs were at fault (rather than the solution).
    pub fn is_input(&self) -> bool {
        use cierva_model::aircraft::trim::TrimError as T;
        matches!(
            self,
            Self::Atmosphere(_) | Self::Trim(T::Condition { .. } | T::Aircraft(_))
        )
    }
}

/// Trims an aircraft.
pub fn run_trim(
    aircraft: &cierva_model::aircraft::Aircraft,
    request: TrimRequest,
    loading: Loading,
) -> Result<cierva_model::aircraft::trim::Trim, TrimRunError> {
    run_trim_from(aircraft, request, loading, None)
}

/// [`run_trim`] started from a nearby trim's end ([`cierva_model::aircraft::trim::trim_from`]).
pub fn run_trim_from(
    aircraft: &cierva_model::aircraft::Aircraft,
    request: TrimRequest,
    loading: Loading,
    start: Option<&cierva_model::aircraft::trim::WarmStart>,
) -> Result<cierva_model::aircraft::trim::Trim, TrimRunError> {
    use cierva_model::{aircraft::Air, aircraft::trim, components::atmosphere};
    let air = atmosphere::at_density_altitude(loading.density_altitude_ft * FT_TO_M)?;
    let mut a = aircraft.clone();
    if let Some(m) = loading.mass_kg {
        a.mass.mass_kg = m;
    }
    let condition = trim::Condition {
        airspeed_m_s: request.airspeed_mph * MPH_TO_M_S,
        climb_m_s: request.climb_m_s,
        turn_rate_rad_s: request.turn_rate_deg_s.to_radians(),
        air: Air {
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
        },
    };
    Ok(trim::trim_from(
        &a,
        condition,
        trim::TrimOptions::default(),
        start,
    )?)
}

static TRIMS: super::memo::Memo<cierva_model::aircraft::trim::Trim> = super::memo::Memo::new();

/// [`run_trim`] of an aircraft file, remembered per file, condition and loading: the trim a
/// request with parameter values starts from (cierva's aircraft through the model interface).
pub fn trim_cached(
    file: &crate::inputs::aircraft::AircraftFile,
    request: TrimRequest,
    loading: Loading,
) -> Result<std::sync::Arc<cierva_model::aircraft::trim::Trim>, String> {
    TRIMS.get_or(
        format!("{}|{request:?}|{loading:?}", file.path.display()),
        || run_trim(&file.aircraft, request, loading).map_err(|e| e.to_string()),
    )
}
