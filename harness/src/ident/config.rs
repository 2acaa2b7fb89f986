//! An identification's set-up: the states, controls and equations identified, the frequency
//! band and windowing, the built-in set-ups (longitudinal, lateral, coupled) and the set-up
//! for given records.

use super::*;

/// An identification set-up as written (`--config ID.yaml`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ConfigSpec {
    /// Model states, from: `u v w` (air data), `p q r phi theta psi` (channels `<name>_rad_s` or
    /// `<name>_rad`), `Omega` (`omega_rotor_rad_s`).
    pub states: Vec<String>,
    /// Model control name -> record channel.
    pub controls: BTreeMap<String, String>,
    pub frequencies: BandSpec,
    #[serde(default)]
    pub windowing: WindowingSpec,
    /// Equations to identify; by default every force state with every state and control free.
    #[serde(default)]
    pub equations: Vec<EquationSpec>,
    /// Kinematic rows, not identified: `theta: q` means theta' = q.
    #[serde(default)]
    pub kinematics: BTreeMap<String, String>,
    #[serde(default)]
    pub method: Estimator,
    /// Average the rotor's blade-passage shaking out of every signal before the fit: the
    /// number of blades (see [`blade_passage_average`]); none by default.
    #[serde(default)]
    pub blade_passage_blades: Option<u32>,
}

/// The estimator.
///
/// Both use heteroscedasticity-consistent (sandwich) standard errors. Plain least squares is
/// seed 000's estimator; under turbulence it is biased (the disturbance drives the regressors at
/// the same frequency) and its bounds miss the truth (M_q: 0 of 40 seeded records). Instrumental
/// variables remove that bias: over 200 seeded records every parameter's 95 % bounds held the
/// truth 94-99 % of the time (test `instrumental_variable_bounds_cover_the_truth`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimator {
    /// Ordinary least squares (seed 000 Eq. 11).
    LeastSquares,
    /// Least squares, then instrumental variables: the first model's frequency response to the
    /// measured inputs, free of turbulence, is the instrument for the states (two passes).
    #[default]
    InstrumentalVariables,
}

/// A frequency band, or a list.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BandSpec {
    #[serde(default)]
    pub from_hz: Option<f64>,
    #[serde(default)]
    pub to_hz: Option<f64>,
    #[serde(default)]
    pub points: Option<usize>,
    #[serde(default)]
    pub list_hz: Option<Vec<f64>>,
}

impl BandSpec {
    /// 0.05-2 Hz at 100 points: the band of seeds 000 and 002's identifications, and the
    /// built-in set-ups'.
    pub const SEED_000: Self = Self {
        from_hz: Some(0.05),
        to_hz: Some(2.0),
        points: Some(100),
        list_hz: None,
    };
}

/// Segments and taper.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WindowingSpec {
    #[serde(default = "one")]
    pub segments: usize,
    #[serde(default)]
    pub overlap: f64,
    #[serde(default)]
    pub hann: bool,
}

impl WindowingSpec {
    /// The estimator's settings.
    pub fn settings(&self) -> Windowing {
        Windowing {
            segments: self.segments,
            overlap: self.overlap,
            hann: self.hann,
        }
    }
}

fn one() -> usize {
    1
}

impl Default for WindowingSpec {
    fn default() -> Self {
        Self {
            segments: 1,
            overlap: 0.0,
            hann: false,
        }
    }
}

/// One equation as written.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EquationSpec {
    pub state: String,
    pub estimate: Vec<String>,
    #[serde(default)]
    pub fixed: BTreeMap<String, f64>,
}

impl ConfigSpec {
    /// The longitudinal set-up of seeds 000 and 002: `[u w q theta Omega]`, the record's first
    /// control, 0.05-2 Hz at 100 points, theta' = q, instrumental variables.
    pub fn longitudinal(record: &Record) -> Self {
        let mut controls = BTreeMap::new();
        if let Some(c) = record.meta.controls.first() {
            let name = c
                .strip_suffix("_rad")
                .or_else(|| c.strip_suffix("_percent"))
                .unwrap_or(c);
            controls.insert(name.to_string(), c.clone());
        }
        let mut kinematics = BTreeMap::new();
        kinematics.insert("theta".to_string(), "q".to_string());
        Self {
            states: ["u", "w", "q", "theta", "Omega"].map(String::from).to_vec(),
            controls,
            frequencies: BandSpec::SEED_000,
            windowing: WindowingSpec::default(),
            equations: vec![],
            kinematics,
            method: Estimator::default(),
            blade_passage_blades: None,
        }
    }
}

/// The identification set-ups `identify --setup` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Setup {
    /// `[u w q theta Omega]` with the first record's first control (seeds 000 and 002).
    Longitudinal,
    /// `[v p r phi Omega]` with the lateral stick and the pedals.
    Lateral,
    /// `[u v w p q r phi theta Omega]` with stick and pedals: the teetering rotor couples the
    /// axes (`M_p`, `L_q`), and a longitudinal set-up leaves that coupling in the residual.
    /// Needs records that excite every axis (a longitudinal and a lateral sweep, identified
    /// together).
    Coupled,
    /// The coupled set-up with the tip-path plane's tilts `beta_1c`, `beta_1s` as states (a
    /// hybrid model: the rotor's flapping in its own equations, the moments on it), from a
    /// teetering rotor's teeter channel ([`flapping_window`]). Needs `teeter_rad`,
    /// `azimuth_from_front_rad` and the trim's rotor speed.
    Flapping,
}

/// The flapping states a set-up may have: the model's tip-path-plane tilts.
pub use cierva_model::aircraft::flapping::FLAP_STATES;

/// A record's channel for a control (`eta_s` -> `eta_s_percent` or `eta_s_rad`).
pub(crate) fn control_channel(record: &Record, control: &str) -> Option<String> {
    [format!("{control}_percent"), format!("{control}_rad")]
        .into_iter()
        .find(|c| record.meta.controls.contains(c))
}

impl ConfigSpec {
    /// Reads a set-up file (`cierva identify --config`), its counts within their limits: the
    /// frequencies' `points` ([`crate::inputs::limits::MAX_FREQUENCY_POINTS`]) and
    /// `blade_passage_blades` ([`cierva_model::components::rotor::MAX_BLADES`]), each error at
    /// its field.
    pub fn load(path: &std::path::Path) -> Result<Self, crate::inputs::yaml::InputError> {
        let src = crate::inputs::yaml::read(path)?;
        let config: Self = crate::inputs::yaml::parse(path, &src)?;
        let err = |field: &str, msg: String| {
            crate::inputs::yaml::InputError::field(path, &src, field, msg)
        };
        let most = crate::inputs::limits::MAX_FREQUENCY_POINTS;
        if let Some(n) = config.frequencies.points.filter(|n| *n > most) {
            return Err(err(
                "frequencies.points",
                format!("{n} frequencies: give at most {most} (MAX_FREQUENCY_POINTS)"),
            ));
        }
        let most = cierva_model::components::rotor::MAX_BLADES;
        if let Some(n) = config.blade_passage_blades.filter(|n| *n as usize > most) {
            return Err(err(
                "blade_passage_blades",
                format!("{n} blades: give at most {most} (MAX_BLADES)"),
            ));
        }
        Ok(config)
    }

    /// A set-up for records, 0.05-2 Hz at 100 points, instrumental variables. The coupled and
    /// lateral set-ups need the records to carry the controls they name.
    pub fn for_setup(setup: Setup, record: &Record) -> Result<Self, String> {
        if setup == Setup::Longitudinal {
            return Ok(Self::longitudinal(record));
        }
        let mut map = BTreeMap::new();
        for c in setup.layout().1 {
            let channel = control_channel(record, c).ok_or_else(|| {
                format!(
                    "{}: the {setup:?} set-up needs the control `{c}` ({c}_percent or {c}_rad among the sidecar's controls)",
                    record.path.display()
                )
            })?;
            map.insert(c.to_string(), channel);
        }
        Ok(Self::with_controls(setup, map))
    }

    /// A set-up for a model rather than records: the longitudinal one with the longitudinal
    /// stick, every control read from `<control>_percent`.
    pub fn for_model(setup: Setup) -> Self {
        let map = setup
            .layout()
            .1
            .iter()
            .map(|c| (c.to_string(), format!("{c}_percent")))
            .collect();
        Self::with_controls(setup, map)
    }

    fn with_controls(setup: Setup, controls: BTreeMap<String, String>) -> Self {
        let (states, _, kinematics) = setup.layout();
        Self {
            states: states.iter().map(|s| s.to_string()).collect(),
            controls,
            frequencies: BandSpec::SEED_000,
            windowing: WindowingSpec::default(),
            equations: vec![],
            kinematics: kinematics
                .iter()
                .map(|(a, b)| (a.to_string(), b.to_string()))
                .collect(),
            method: Estimator::default(),
            blade_passage_blades: None,
        }
    }
}

impl Setup {
    /// The set-up's states, controls and kinematic rows.
    #[allow(clippy::type_complexity)]
    fn layout(
        self,
    ) -> (
        &'static [&'static str],
        &'static [&'static str],
        &'static [(&'static str, &'static str)],
    ) {
        match self {
            Setup::Longitudinal => (
                &["u", "w", "q", "theta", "Omega"],
                &["eta_s"],
                &[("theta", "q")],
            ),
            Setup::Lateral => (
                &["v", "p", "r", "phi", "Omega"],
                &["eta_c", "eta_p"],
                &[("phi", "p")],
            ),
            Setup::Coupled => (
                &["u", "v", "w", "p", "q", "r", "phi", "theta", "Omega"],
                &["eta_s", "eta_c", "eta_p"],
                &[("theta", "q"), ("phi", "p")],
            ),
            Setup::Flapping => (
                &[
                    "u", "v", "w", "p", "q", "r", "phi", "theta", "Omega", "beta_1c", "beta_1s",
                ],
                &["eta_s", "eta_c", "eta_p"],
                &[("theta", "q"), ("phi", "p")],
            ),
        }
    }
}

/// The set-up for records by the controls they excite (each record's first control): the
/// stick alone is longitudinal, the lateral stick and pedals lateral, a mix coupled.
pub fn setup_for(records: &[&Record]) -> Setup {
    let excited: Vec<&str> = records
        .iter()
        .filter_map(|r| r.meta.controls.first().map(String::as_str))
        .collect();
    let lon = |c: &str| c.starts_with("eta_s");
    let lat = |c: &str| c.starts_with("eta_c") || c.starts_with("eta_p");
    if excited.iter().all(|c| lon(c)) {
        Setup::Longitudinal
    } else if excited.iter().all(|c| lat(c)) {
        Setup::Lateral
    } else {
        Setup::Coupled
    }
}

/// A model (an aircraft's linearisation) cut to a set-up's states and controls, in the
/// set-up's order, for flying a record's measured controls ([`predict`]).
pub fn model_for(model: &LinearModel, config: &ConfigSpec) -> Result<LinearModel, String> {
    let states: Vec<&str> = config.states.iter().map(String::as_str).collect();
    let sub = model.subsystem(&states).map_err(|e| e.to_string())?;
    let cols = config
        .controls
        .keys()
        .map(|c| {
            model
                .controls()
                .iter()
                .position(|m| m == c)
                .ok_or_else(|| format!("the model has no control `{c}`"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let b = nalgebra::DMatrix::from_fn(sub.a().nrows(), cols.len(), |i, j| sub.b()[(i, cols[j])]);
    LinearModel::new(
        sub.states().to_vec(),
        config.controls.keys().cloned().collect(),
        sub.a().clone(),
        b,
    )
    .map_err(|e| e.to_string())
}
