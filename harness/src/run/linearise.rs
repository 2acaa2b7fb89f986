//! An aircraft trimmed and linearised (quasi-static, or with its flapping states), remembered
//! per file, condition and loading.

use crate::inputs::condition::{Loading, TrimRequest};
use crate::units::FT_TO_M;

use super::trim::{TrimRunError, run_trim_from};

/// Why a linearisation run did not produce a model.
#[derive(Debug, thiserror::Error)]
pub enum LinearRunError {
    #[error("{0}")]
    Trim(#[from] TrimRunError),
    #[error("linearisation: {0}")]
    Linearise(#[from] cierva_model::aircraft::linearise::LinearisationError),
}

impl LinearRunError {
    /// Whether the inputs were at fault.
    pub fn is_input(&self) -> bool {
        matches!(self, Self::Trim(t) if t.is_input())
    }
}

/// Trims and linearises an aircraft (seed 001 Eqs. 10-12; see `cierva_model::aircraft::linearise`).
pub fn run_linearise(
    aircraft: &cierva_model::aircraft::Aircraft,
    request: TrimRequest,
    loading: Loading,
) -> Result<
    (
        cierva_model::aircraft::trim::Trim,
        cierva_model::aircraft::linearise::Linearised,
    ),
    LinearRunError,
> {
    run_linearise_from(aircraft, request, loading, None)
}

/// [`run_linearise`] with its trim started from a nearby trim's end.
pub fn run_linearise_from(
    aircraft: &cierva_model::aircraft::Aircraft,
    request: TrimRequest,
    loading: Loading,
    start: Option<&cierva_model::aircraft::trim::WarmStart>,
) -> Result<
    (
        cierva_model::aircraft::trim::Trim,
        cierva_model::aircraft::linearise::Linearised,
    ),
    LinearRunError,
> {
    use cierva_model::{aircraft::Air, aircraft::linearise, components::atmosphere};
    let trim = run_trim_from(aircraft, request, loading, start)?;
    let air = atmosphere::at_density_altitude(loading.density_altitude_ft * FT_TO_M)
        .map_err(TrimRunError::from)?;
    let mut a = aircraft.clone();
    if let Some(m) = loading.mass_kg {
        a.mass.mass_kg = m;
    }
    let lin = linearise::linearise(
        &a,
        &trim,
        Air {
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
        },
        linearise::Steps::default(),
    )?;
    Ok((trim, lin))
}

/// Units of the linearised model's states and controls.
pub fn linear_units() -> std::collections::BTreeMap<String, String> {
    [
        ("u", "m/s"),
        ("v", "m/s"),
        ("w", "m/s"),
        ("p", "rad/s"),
        ("q", "rad/s"),
        ("r", "rad/s"),
        ("phi", "rad"),
        ("theta", "rad"),
        ("psi", "rad"),
        ("Omega", "rad/s"),
        ("eta_s", "% of longitudinal stick travel (0 forward)"),
        ("eta_c", "% of lateral stick travel (0 left)"),
        ("eta_p", "% of pedal travel (0 left)"),
        ("eta_t", "% of throttle"),
    ]
    .iter()
    .map(|(k, v)| (k.to_string(), v.to_string()))
    .collect()
}

/// A trim and the linearisation about it.
pub type Linearisation = (
    cierva_model::aircraft::trim::Trim,
    cierva_model::aircraft::linearise::Linearised,
);

static LINEARISATIONS: super::memo::Memo<Linearisation> = super::memo::Memo::new();

/// `run_linearise`, remembered per aircraft file, condition and loading (a case's checks at
/// one condition share one linearisation).
pub fn linearise_cached(
    file: &crate::inputs::aircraft::AircraftFile,
    request: TrimRequest,
    loading: Loading,
) -> Result<std::sync::Arc<Linearisation>, String> {
    LINEARISATIONS.get_or(
        format!("{}|{request:?}|{loading:?}", file.path.display()),
        || run_linearise_from(&file.aircraft, request, loading, None).map_err(|e| e.to_string()),
    )
}

/// The aircraft linearised at a trim with its blades' flapping, its inflow and (with an engine)
/// its propeller speed as states ([`cierva_model::aircraft::flapping`]), at the trim
/// [`run_linearise`] finds.
pub fn run_linearise_with_flapping(
    aircraft: &cierva_model::aircraft::Aircraft,
    trim: &cierva_model::aircraft::trim::Trim,
    loading: Loading,
) -> Result<cierva_model::aircraft::flapping::WithFlapping, String> {
    use cierva_model::{
        aircraft::Air, aircraft::flapping, aircraft::linearise, components::atmosphere,
    };
    let air = atmosphere::at_density_altitude(loading.density_altitude_ft * FT_TO_M)
        .map_err(|e| e.to_string())?;
    let mut a = aircraft.clone();
    if let Some(m) = loading.mass_kg {
        a.mass.mass_kg = m;
    }
    flapping::with_flapping(
        &a,
        trim,
        Air {
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
        },
        linearise::Steps::default(),
    )
    .map_err(|e| e.to_string())
}

/// The derivatives a set-up identifies from the aircraft's linearisation with its flapping
/// states ([`run_linearise_with_flapping`]), over the set-up's band from the periodic model's
/// baseband frequency response (harmonic balance,
/// [`cierva_model::aircraft::flapping::WithFlapping::baseband_response`];
/// [`crate::ident::equivalent::identify_response`]): what the identification of a
/// flight of the full model should find, where the quasi-static linearisation leaves the
/// blades' lag out. Remembered per aircraft file, condition, loading and set-up.
pub fn identified_in_band_cached(
    file: &crate::inputs::aircraft::AircraftFile,
    request: TrimRequest,
    loading: Loading,
    setup: crate::ident::Setup,
) -> Result<std::sync::Arc<cierva_model::LinearModel>, String> {
    static IDENTIFIED: super::memo::Memo<cierva_model::LinearModel> = super::memo::Memo::new();
    IDENTIFIED.get_or(
        format!("{}|{request:?}|{loading:?}|{setup:?}", file.path.display()),
        || {
            let lin = linearise_cached(file, request, loading)?;
            identified_at(&file.aircraft, &lin.0, loading, setup)
        },
    )
}

/// What `setup` identifies from the aircraft's linearisation with its flapping states at
/// `trim`, over the set-up's band.
pub fn identified_at(
    aircraft: &cierva_model::aircraft::Aircraft,
    trim: &cierva_model::aircraft::trim::Trim,
    loading: Loading,
    setup: crate::ident::Setup,
) -> Result<cierva_model::LinearModel, String> {
    let flapping = run_linearise_with_flapping(aircraft, trim, loading)?;
    let config = crate::ident::ConfigSpec::for_model(setup);
    let at = |w: f64| flapping.baseband_response(w).map_err(|e| e.to_string());
    let identified = crate::ident::equivalent::identify_response(
        &config,
        crate::ident::equivalent::Response {
            states: flapping.model.states(),
            controls: flapping.model.controls(),
            at: &at,
        },
    )?;
    identified
        .model
        .ok_or_else(|| "the set-up's identified model could not be assembled".to_string())
}
