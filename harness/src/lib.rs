//! # cierva harness
//!
//! Everything between the model and the people who use it: case files and reference files
//! (`case`, `refs`, `yaml`), running checks (`eval`), and text output (`text`). The `cierva`
//! binary and the generated test suite (`tests/cases.rs`) are thin layers over this library.
//!
//! The model (`cierva-model`) does no I/O; everything that reads files lives here.

pub mod aircraft_file;
pub mod case;
pub mod checks;
pub mod controls_file;
pub mod corrections;
pub mod discrepancy;
pub mod estimate;
pub mod eval;
pub mod external;
pub mod fit;
pub mod fit_file;
pub mod flight_test;
pub mod history;
pub mod ident;
pub mod inputs;
pub mod parameters;
pub mod quantity;
pub mod refs;
pub mod report;
pub mod retune;
pub mod review;
pub mod rotor_file;
pub mod scoreboard;
pub mod sensitivity;
pub mod subject;
pub mod suite;
pub mod text;
pub mod tolerance;
pub mod uncertainty;
pub mod yaml;

use case::Case;
use std::path::PathBuf;
use yaml::InputError;

/// Every case file found under `paths`, loaded (or the error that stopped it).
///
/// Fails only when a path does not exist or cannot be listed; an empty result is the caller's
/// to reject.
pub fn load_cases(paths: &[PathBuf]) -> Result<Vec<Result<Case, InputError>>, InputError> {
    Ok(case::discover(paths)?
        .iter()
        .map(|p| case::load(p))
        .collect())
}

/// `f` over `items` on every core, results in the order of `items`. Items are handed out one at
/// a time as threads come free, so a slow item (a case of 81 tunnel rows) does not hold back a
/// whole chunk; each item runs on one thread, and the output does not depend on the schedule.
pub fn parallel_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(items.len().max(1));
    let next = AtomicUsize::new(0);
    let mut out: Vec<(usize, R)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                let (f, next) = (&f, &next);
                s.spawn(move || {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else { break };
                        mine.push((i, f(item)));
                    }
                    mine
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    out.sort_by_key(|(i, _)| *i);
    out.into_iter().map(|(_, r)| r).collect()
}

/// Why an autorotation run did not produce an equilibrium.
#[derive(Debug, thiserror::Error)]
pub enum AutorotateError {
    #[error("{0}")]
    Atmosphere(#[from] cierva_model::components::atmosphere::AtmosphereError),
    #[error("{0}")]
    Autorotation(#[from] cierva_model::components::autorotation::AutorotationError),
}

impl AutorotateError {
    /// Whether the inputs were at fault (rather than the solution).
    pub fn is_input(&self) -> bool {
        use cierva_model::components::autorotation::AutorotationError as A;
        matches!(
            self,
            Self::Atmosphere(_) | Self::Autorotation(A::Condition { .. } | A::Rotor(_))
        )
    }
}

/// The isolated rotor in a tunnel at `alpha_deg` and `airspeed_m_s`, with the blade pitch at the
/// reference station set to `collective_deg` (or the file's pitch as it is) and the density
/// given (or ISA sea level; the speed of sound follows from the density altitude).
pub fn run_autorotation(
    rotor: &cierva_model::components::rotor::Rotor,
    alpha_deg: f64,
    airspeed_m_s: f64,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
    options: impl Into<cierva_model::components::autorotation::Options>,
) -> Result<cierva_model::components::autorotation::Autorotation, AutorotateError> {
    use cierva_model::components::autorotation::{Tunnel, autorotate};
    let (air, collective_shift_rad) = tunnel_air(rotor, collective_deg, density_kg_m3)?;
    let tunnel = Tunnel {
        alpha_rad: alpha_deg.to_radians(),
        airspeed_m_s,
        density_kg_m3: air.density_kg_m3,
        speed_of_sound_m_s: air.speed_of_sound_m_s,
        collective_shift_rad,
    };
    Ok(autorotate(rotor, tunnel, options.into())?)
}

/// A tunnel's air (at `density_kg_m3`, or ISA sea level; the speed of sound from the density
/// altitude) and the pitch shift that sets the rotor's reference pitch to `collective_deg`
/// (none: the file's pitch as it is).
fn tunnel_air(
    rotor: &cierva_model::components::rotor::Rotor,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
) -> Result<(cierva_model::components::atmosphere::AirState, f64), AutorotateError> {
    use cierva_model::components::atmosphere;
    let air = match density_kg_m3 {
        Some(rho) => atmosphere::at_density_altitude(atmosphere::density_altitude_m(rho)?)?,
        None => atmosphere::Atmosphere::standard().at(0.0)?,
    };
    let shift = collective_deg.map_or(0.0, |c| rotor.collective_shift_for(c.to_radians()));
    Ok((air, shift))
}

/// The isolated rotor at a tip-speed ratio and rotor speed (rpm): the angle of attack and
/// airspeed at which it autorotates there, with the equilibrium (the collective and air as
/// [`run_autorotation`] takes them).
pub fn run_autorotation_at_tip_speed_ratio(
    rotor: &cierva_model::components::rotor::Rotor,
    tip_speed_ratio: f64,
    rotor_rpm: f64,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
    options: impl Into<cierva_model::components::autorotation::Options>,
) -> Result<cierva_model::components::autorotation::AtTipSpeedRatio, AutorotateError> {
    use cierva_model::components::autorotation::{
        TipSpeedCondition, autorotate_at_tip_speed_ratio,
    };
    let (air, collective_shift_rad) = tunnel_air(rotor, collective_deg, density_kg_m3)?;
    Ok(autorotate_at_tip_speed_ratio(
        rotor,
        TipSpeedCondition {
            tip_speed_ratio,
            omega_rad_s: rotor_rpm * std::f64::consts::PI / 30.0,
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
            collective_shift_rad,
        },
        options.into(),
    )?)
}

/// A trim request in the units people fly in. As written (in a case's `condition`), the airspeed
/// may be in any of `airspeed_mph`, `airspeed_kn` or `airspeed_m_s` (exactly one); it is held in
/// mph.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(try_from = "ConditionSpec")]
pub struct TrimRequest {
    /// True airspeed, mph.
    pub airspeed_mph: f64,
    /// Rate of climb, m/s (negative descends).
    #[serde(default)]
    pub climb_m_s: f64,
    /// Rate of turn, deg/s (positive to starboard).
    #[serde(default)]
    pub turn_rate_deg_s: f64,
}

/// Miles per hour in a knot (1852 m / 1609.344 m).
pub const MPH_PER_KN: f64 = 1852.0 / 1609.344;

/// A flight condition as written: one airspeed in the unit of its key.
#[derive(Debug, Clone, Copy, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ConditionSpec {
    #[serde(default)]
    airspeed_mph: Option<f64>,
    #[serde(default)]
    airspeed_kn: Option<f64>,
    #[serde(default)]
    airspeed_m_s: Option<f64>,
    #[serde(default)]
    climb_m_s: f64,
    #[serde(default)]
    turn_rate_deg_s: f64,
}

impl TryFrom<ConditionSpec> for TrimRequest {
    type Error = String;

    fn try_from(c: ConditionSpec) -> Result<Self, String> {
        let airspeed_mph = match (c.airspeed_mph, c.airspeed_kn, c.airspeed_m_s) {
            (Some(v), None, None) => v,
            (None, Some(v), None) => v * MPH_PER_KN,
            (None, None, Some(v)) => v / MPH_TO_M_S,
            _ => {
                return Err(
                    "give exactly one airspeed: `airspeed_mph`, `airspeed_kn` or `airspeed_m_s`"
                        .into(),
                );
            }
        };
        Ok(Self {
            airspeed_mph,
            climb_m_s: c.climb_m_s,
            turn_rate_deg_s: c.turn_rate_deg_s,
        })
    }
}

/// Where and how heavy: the air (ISA at a density altitude) and the mass (the aircraft file's
/// unless given; inertias stay as the file gives them, a fuel-state change near the c.g.).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Loading {
    pub mass_kg: Option<f64>,
    pub density_altitude_ft: f64,
}

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

/// Miles per hour to metres per second (exact: 1 mile = 1609.344 m).
pub const MPH_TO_M_S: f64 = 0.44704;
/// Feet to metres (exact).
pub const FT_TO_M: f64 = 0.3048;

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
        trim::Options::default(),
        start,
    )?)
}

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

type Linearisation = (
    cierva_model::aircraft::trim::Trim,
    cierva_model::aircraft::linearise::Linearised,
);

type LinearisationCache = std::sync::Mutex<
    std::collections::HashMap<String, Result<std::sync::Arc<Linearisation>, String>>,
>;
static LINEARISATIONS: std::sync::OnceLock<LinearisationCache> = std::sync::OnceLock::new();

/// `run_linearise`, remembered per aircraft file, condition and loading (a case's checks at
/// one condition share one linearisation).
pub fn linearise_cached(
    file: &aircraft_file::AircraftFile,
    request: TrimRequest,
    loading: Loading,
) -> Result<std::sync::Arc<Linearisation>, String> {
    linearise_cached_from(file, request, loading, None)
}

/// [`linearise_cached`], its trim (where not remembered yet) started from a nearby trim's end:
/// a sampled aircraft starts from the nominal one's trim (`cierva uncertainty`).
pub fn linearise_cached_from(
    file: &aircraft_file::AircraftFile,
    request: TrimRequest,
    loading: Loading,
    start: Option<&cierva_model::aircraft::trim::WarmStart>,
) -> Result<std::sync::Arc<Linearisation>, String> {
    use std::sync::{Arc, Mutex};
    let key = format!("{}|{request:?}|{loading:?}", file.path.display());
    let cache = LINEARISATIONS.get_or_init(|| Mutex::new(Default::default()));
    if let Some(hit) = cache.lock().ok().and_then(|c| c.get(&key).cloned()) {
        return hit;
    }
    let result = run_linearise_from(&file.aircraft, request, loading, start)
        .map(Arc::new)
        .map_err(|e| e.to_string());
    if let Ok(mut c) = cache.lock() {
        c.insert(key, result.clone());
    }
    result
}

/// Forgets the remembered linearisations of one aircraft file (by its path): a sampled
/// aircraft's, once its checks have run, so that thousands of samples do not fill the memory.
pub fn forget_linearisations(file: &aircraft_file::AircraftFile) {
    let prefix = format!("{}|", file.path.display());
    if let Some(Ok(mut c)) = LINEARISATIONS.get().map(|c| c.lock()) {
        c.retain(|k, _| !k.starts_with(&prefix));
    }
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
/// [`ident::equivalent::identify_response`]): what the identification of a
/// flight of the full model should find, where the quasi-static linearisation leaves the
/// blades' lag out. Remembered per aircraft file, condition, loading and set-up.
pub fn identified_in_band_cached(
    file: &aircraft_file::AircraftFile,
    request: TrimRequest,
    loading: Loading,
    setup: ident::Setup,
) -> Result<std::sync::Arc<cierva_model::LinearModel>, String> {
    use std::collections::HashMap;
    use std::sync::{Arc, Mutex, OnceLock};
    type Cache = Mutex<HashMap<String, Result<Arc<cierva_model::LinearModel>, String>>>;
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let key = format!("{}|{request:?}|{loading:?}|{setup:?}", file.path.display());
    let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
    if let Some(hit) = cache.lock().ok().and_then(|c| c.get(&key).cloned()) {
        return hit;
    }
    let result = (|| {
        let lin = linearise_cached(file, request, loading)?;
        let flapping = run_linearise_with_flapping(&file.aircraft, &lin.0, loading)?;
        let config = ident::ConfigSpec::for_model(setup);
        let at = |w: f64| flapping.baseband_response(w).map_err(|e| e.to_string());
        let identified = ident::equivalent::identify_response(
            &config,
            ident::equivalent::Response {
                states: flapping.model.states(),
                controls: flapping.model.controls(),
                at: &at,
            },
        )?;
        identified
            .model
            .map(Arc::new)
            .ok_or_else(|| "the set-up's identified model could not be assembled".to_string())
    })();
    if let Ok(mut c) = cache.lock() {
        c.insert(key, result.clone());
    }
    result
}

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
    let pt = trim::periodic_trim(&a, condition, &t, trim::Options::default())
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
    ) -> Result<cierva_model::simulation::timehistory::TimeHistory, String> {
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
        .map_err(|(time, e)| format!("at {time:.3} s: {e}"))
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
) -> Result<cierva_model::simulation::timehistory::TimeHistory, String> {
    simulation_start(aircraft, request, loading)?.run(changes, settings)
}
