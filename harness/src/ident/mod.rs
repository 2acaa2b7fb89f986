//! From flight records to derivatives: records ([`record`]), Fourier transforms ([`fourier`]),
//! equation-error regression ([`estimate`]) and synthetic records ([`synth`]).
//!
//! [`identify_record`] converts air data to centre-of-mass velocities (seed 000 Eqs. 5-6),
//! takes perturbations about the sidecar's trim, and identifies each force equation in the
//! frequency domain.

pub mod equivalent;
pub mod estimate;
pub mod flap;
pub mod fourier;
pub mod frequency_response;
pub mod verify;

use crate::inputs::record::{self, Record};
use cierva_model::LinearModel;
use cierva_model::analysis::linear::FORCE_STATES;
use estimate::{Equation, EquationFit, Frequencies, IdentError, Signals, Windowing};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
    pub method: Method,
    /// Average the rotor's blade-passage shaking out of every signal before the fit: the
    /// number of blades (see [`blade_passage_average`]); none by default.
    #[serde(default)]
    pub blade_passage_blades: Option<u32>,
}

/// A centred moving average over one blade-passage period `2 pi / (N_b Omega)` (`window`
/// samples, fractional: the two end samples weighted by the fraction left over), applied to a
/// signal. Its gain is zero near `N_b` per revolution and its harmonics (the rotor's shaking in
/// a record; a two-bladed rotor's 2/rev) and `sin(pi f T) / (pi f T)` below: 0.967 at 2 Hz for
/// the VPM M16's 14 Hz 2/rev. Applied alike to every state and control, it leaves the
/// equations of motion as they were (they are linear in the signals), so it removes the
/// shaking without biasing the derivatives. Within half a window of a record's ends the window
/// is cut short, the same for every signal.
pub fn blade_passage_average(x: &[f64], window: f64) -> Vec<f64> {
    if !(window.is_finite() && window > 1.0) {
        return x.to_vec();
    }
    let half = (window - 1.0) / 2.0;
    let full = half.floor() as usize;
    let edge = half - full as f64;
    let n = x.len();
    (0..n)
        .map(|k| {
            let (mut sum, mut weight) = (0.0, 0.0);
            let lo = k.saturating_sub(full + 1);
            let hi = (k + full + 1).min(n - 1);
            for (j, v) in x.iter().enumerate().take(hi + 1).skip(lo) {
                let w = if j.abs_diff(k) <= full { 1.0 } else { edge };
                sum += w * v;
                weight += w;
            }
            sum / weight
        })
        .collect()
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
pub enum Method {
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
                .or_else(|| c.strip_suffix("_pct"))
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
            method: Method::default(),
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

/// A record's channel for a control (`eta_s` -> `eta_s_pct` or `eta_s_rad`).
pub(crate) fn control_channel(record: &Record, control: &str) -> Option<String> {
    [format!("{control}_pct"), format!("{control}_rad")]
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
                    "{}: the {setup:?} set-up needs the control `{c}` ({c}_pct or {c}_rad among the sidecar's controls)",
                    record.path.display()
                )
            })?;
            map.insert(c.to_string(), channel);
        }
        Ok(Self::with_controls(setup, map))
    }

    /// A set-up for a model rather than records: the longitudinal one with the longitudinal
    /// stick, every control read from `<control>_pct`.
    pub fn for_model(setup: Setup) -> Self {
        let map = setup
            .layout()
            .1
            .iter()
            .map(|c| (c.to_string(), format!("{c}_pct")))
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
            method: Method::default(),
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

/// The flight condition a record's sidecar gives (`condition`: one airspeed, and optionally
/// `climb_m_s`, `turn_rate_deg_s`, `mass_kg`, `density_altitude_ft`), for linearising a model
/// there.
pub fn record_condition(record: &Record) -> Result<(crate::TrimRequest, crate::Loading), String> {
    let c = &record.meta.condition;
    let number = |k: &str| -> Result<Option<f64>, String> {
        match c.get(k) {
            None => Ok(None),
            Some(v) => v.as_f64().map(Some).ok_or_else(|| {
                format!("{}: condition `{k}` is not a number", sidecar_name(record))
            }),
        }
    };
    let mut flight = serde_yaml::Mapping::new();
    for k in [
        "airspeed_mph",
        "airspeed_kn",
        "airspeed_m_s",
        "climb_m_s",
        "turn_rate_deg_s",
    ] {
        if let Some(v) = number(k)? {
            flight.insert(k.into(), v.into());
        }
    }
    let request: crate::TrimRequest = serde_yaml::from_value(serde_yaml::Value::Mapping(flight))
        .map_err(|e| format!("{}: condition: {e}", sidecar_name(record)))?;
    Ok((
        request,
        crate::Loading {
            mass_kg: number("mass_kg")?,
            density_altitude_ft: number("density_altitude_ft")?.unwrap_or(0.0),
        },
    ))
}

fn sidecar_name(record: &Record) -> String {
    record::sidecar_path(&record.path).display().to_string()
}

/// The derivatives issue 18 and seed 000 call primary: the damping and stiffness of each axis,
/// the rotorspeed's own derivative, and each control's moment.
pub const PRIMARY: [&str; 13] = [
    "X_u", "Z_w", "M_q", "M_w", "Q_Omega", "Y_v", "L_p", "L_v", "N_v", "N_r", "M_eta_s", "L_eta_c",
    "N_eta_p",
];

/// An identified derivative beside a model's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Against {
    pub name: String,
    pub estimate: f64,
    pub standard_error: f64,
    pub lower_95: f64,
    pub upper_95: f64,
    /// The model's value (NaN where the model has no such derivative).
    pub model: f64,
    /// The model's value lies within the identified 95 % bounds (false for NaN).
    pub inside: bool,
    pub primary: bool,
    /// What the same set-up identifies from the model with its flapping states, its response
    /// to the records' controls ([`equivalent::identify_flapping`]), where it was computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub with_flapping: Option<f64>,
    /// That value lies within the identified 95 % bounds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inside_with_flapping: Option<bool>,
}

/// Adds to each row what the set-up identifies from the model with its flapping states
/// (`as_identified`, from [`equivalent::identify_flapping`] or [`equivalent::identify_response`]).
pub fn add_with_flapping(rows: &mut [Against], as_identified: &Identification) {
    for r in rows {
        let v = as_identified
            .derivatives
            .iter()
            .find(|d| d.name == r.name)
            .map(|d| d.estimate);
        r.with_flapping = v;
        r.inside_with_flapping = v.map(|v| v.is_finite() && r.lower_95 <= v && v <= r.upper_95);
    }
}

/// Every identified derivative beside the model's (a linearisation with the identification's
/// state, control and derivative names).
pub fn against(ident: &Identification, model: &LinearModel) -> Vec<Against> {
    ident
        .derivatives
        .iter()
        .map(|d| {
            let m = model.derivative_value(&d.name).unwrap_or(f64::NAN);
            Against {
                name: d.name.clone(),
                estimate: d.estimate,
                standard_error: d.standard_error,
                lower_95: d.lower_95,
                upper_95: d.upper_95,
                model: m,
                inside: m.is_finite() && d.lower_95 <= m && m <= d.upper_95,
                primary: PRIMARY.contains(&d.name.as_str()),
                with_flapping: None,
                inside_with_flapping: None,
            }
        })
        .collect()
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

/// One identified derivative, for tables.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Derivative {
    pub name: String,
    pub estimate: f64,
    pub standard_error: f64,
    pub lower_95: f64,
    pub upper_95: f64,
}

/// The result of identifying a record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identification {
    pub record: String,
    pub fits: Vec<EquationFit>,
    pub derivatives: Vec<Derivative>,
    /// `ok`, or `warnings` when any equation has warnings.
    pub status: &'static str,
    #[serde(skip)]
    pub model: Option<LinearModel>,
}

fn force_letter(state: &str) -> Option<char> {
    FORCE_STATES
        .iter()
        .find(|(_, s)| *s == state)
        .map(|(f, _)| *f)
}

/// State and control time histories, one vector per variable.
pub type Histories = (Vec<Vec<f64>>, Vec<Vec<f64>>);

/// The perturbation time histories of the configured states and controls.
pub fn signals(record: &Record, config: &ConfigSpec) -> Result<Histories, String> {
    let ch = |name: &str| {
        record
            .channel(name)
            .ok_or_else(|| format!("{}: channel `{name}` is missing", record.path.display()))
    };
    let trim = |key: &str| record.meta.trim.get(key).copied().unwrap_or(0.0);
    let (v, a, b) = (
        ch("airspeed_m_s")?,
        ch("alpha_vane_rad")?,
        ch("beta_vane_rad")?,
    );
    let (p, q, r) = (ch("p_rad_s")?, ch("q_rad_s")?, ch("r_rad_s")?);
    let s = record.meta.sensors.as_ref().ok_or_else(|| {
        format!(
            "{}: the sidecar gives no `sensors` (probe and c.g. positions)",
            record.path.display()
        )
    })?;
    let off = [
        s.probe_position_m[0] - s.cg_position_m[0],
        s.probe_position_m[1] - s.cg_position_m[1],
        s.probe_position_m[2] - s.cg_position_m[2],
    ];
    let n = v.len();
    // Seed 000 Eqs. 5-6: probe velocity from airspeed and vanes, then the c.g. velocity.
    let (mut u, mut vv, mut w) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for k in 0..n {
        let up = v[k] * b[k].cos() * a[k].cos();
        let vp = v[k] * b[k].sin();
        let wp = v[k] * b[k].cos() * a[k].sin();
        u[k] = up - (q[k] * off[2] - r[k] * off[1]);
        vv[k] = vp - (r[k] * off[0] - p[k] * off[2]);
        w[k] = wp - (p[k] * off[1] - q[k] * off[0]);
    }
    let mut xs: Vec<Vec<f64>> = Vec::new();
    for st in &config.states {
        let (series, key): (Vec<f64>, String) = match st.as_str() {
            "u" => (u.clone(), "u_m_s".into()),
            "v" => (vv.clone(), "v_m_s".into()),
            "w" => (w.clone(), "w_m_s".into()),
            "p" | "q" | "r" => (ch(&format!("{st}_rad_s"))?.to_vec(), format!("{st}_rad_s")),
            "phi" | "theta" | "psi" => (ch(&format!("{st}_rad"))?.to_vec(), format!("{st}_rad")),
            "Omega" => (
                ch("omega_rotor_rad_s")?.to_vec(),
                "omega_rotor_rad_s".into(),
            ),
            "beta_1c" | "beta_1s" => {
                let (c, s) = flapping_products(record)?;
                let raw = if st == "beta_1c" { c } else { s };
                // No trim value is recorded for the tilts: the record's mean is taken off (the
                // band starts well above the frequencies a mean leaks to).
                let mean = raw.iter().sum::<f64>() / raw.len().max(1) as f64;
                xs.push(raw.iter().map(|x| x - mean).collect());
                continue;
            }
            other => return Err(format!("no measurement gives the state `{other}`")),
        };
        let t0 = trim(&key);
        xs.push(series.iter().map(|x| x - t0).collect());
    }
    let mut us: Vec<Vec<f64>> = Vec::new();
    for channel in config.controls.values() {
        let t0 = trim(channel);
        us.push(ch(channel)?.iter().map(|x| x - t0).collect());
    }
    if let Some(window) = flapping_window(record, config)? {
        for s in xs.iter_mut().chain(us.iter_mut()) {
            *s = blade_passage_average(s, window);
        }
    }
    if let Some(blades) = config.blade_passage_blades {
        let revolution = revolution_window(record, "averaging out the blade passage")?;
        if blades == 0 {
            return Err("blade_passage_blades must be at least 1".into());
        }
        let window = revolution / f64::from(blades);
        for s in xs.iter_mut().chain(us.iter_mut()) {
            *s = blade_passage_average(s, window);
        }
    }
    Ok((xs, us))
}

/// The teeter channel demodulated at the rotor's azimuth, before averaging:
/// `-2 teeter cos(psi_f)` and `-2 teeter sin(psi_f)` with `psi_f` the azimuth from the front
/// (seed 003's convention: `teeter = -beta_1c cos(psi_f) - beta_1s sin(psi_f)`, so the model's
/// `beta = beta_1c cos(psi) + beta_1s sin(psi)` with `psi = psi_f - pi`). Their mean over a
/// revolution is the tip-path plane's tilt ([`flapping_window`]).
fn flapping_products(record: &Record) -> Result<(Vec<f64>, Vec<f64>), String> {
    let ch = |name: &str| {
        record.channel(name).ok_or_else(|| {
            format!(
                "{}: the flapping states need the channel `{name}` (a teetering rotor's record)",
                record.path.display()
            )
        })
    };
    let (teeter, az) = (ch("teeter_rad")?, ch("azimuth_from_front_rad")?);
    Ok(teeter
        .iter()
        .zip(az)
        .map(|(b, a)| (-2.0 * b * a.cos(), -2.0 * b * a.sin()))
        .unzip())
}

/// The tip-path plane's tilts `(beta_1c, beta_1s)` through a teetering rotor's record, rad:
/// the teeter channel demodulated at the azimuth and averaged over a revolution at the trim's
/// rotor speed (what a set-up with flapping states identifies from, before its mean is taken
/// off).
pub fn tip_path_plane(record: &Record) -> Result<(Vec<f64>, Vec<f64>), String> {
    let (c, s) = flapping_products(record)?;
    let window = revolution_window(record, "the tip-path plane")?;
    Ok((
        blade_passage_average(&c, window),
        blade_passage_average(&s, window),
    ))
}

/// One revolution at the trim's rotor speed, in samples; `what` needs it (for the message when
/// the sidecar does not give the speed).
fn revolution_window(record: &Record, what: &str) -> Result<f64, String> {
    let omega = record
        .meta
        .trim
        .get("omega_rotor_rad_s")
        .copied()
        .filter(|w| w.is_finite() && *w > 0.0)
        .ok_or_else(|| {
            format!(
                "{}: {what} needs the trim's `omega_rotor_rad_s` in the sidecar",
                record.path.display()
            )
        })?;
    Ok(2.0 * std::f64::consts::PI / omega / record.dt_s())
}

/// With flapping states in the set-up, the window (in samples) of one revolution at the
/// trim's rotor speed: every signal is averaged over it ([`blade_passage_average`] with one
/// blade), which turns the demodulated teeter into the tip-path plane's tilts (the products'
/// 2/rev parts average to nothing over a revolution) and treats every other signal alike, so
/// the equations hold as they did (they are linear in the signals). The average keeps
/// `sin(pi f T) / (pi f T)` of a signal at `f`: 0.87 at 2 Hz for the VPM M16's 0.14 s
/// revolution, the same for every signal. `None` without flapping states.
pub fn flapping_window(record: &Record, config: &ConfigSpec) -> Result<Option<f64>, String> {
    if config
        .states
        .iter()
        .any(|s| FLAP_STATES.contains(&s.as_str()))
    {
        revolution_window(
            record,
            "averaging over a revolution for the flapping states",
        )
        .map(Some)
    } else {
        Ok(None)
    }
}

/// Identifies a record with a set-up.
pub fn identify_record(record: &Record, config: &ConfigSpec) -> Result<Identification, String> {
    identify_records(std::slice::from_ref(record), config)
}

/// Identifies several records of one condition together (their spectra concatenated,
/// [`estimate::Spectra::concatenate`]) with one set-up.
pub fn identify_records(records: &[Record], config: &ConfigSpec) -> Result<Identification, String> {
    if records.is_empty() {
        return Err("no record to identify".into());
    }
    let parts = records
        .iter()
        .map(|r| Ok((r.path.display().to_string(), signals(r, config)?, r.dt_s())))
        .collect::<Result<Vec<_>, String>>()?;
    let id = records
        .iter()
        .map(|r| r.meta.id.as_str())
        .collect::<Vec<_>>()
        .join(" + ");
    identify_histories(&id, parts, config)
}

/// One run's perturbation histories for [`identify_histories`]: its name (for messages), the
/// configured states' and controls' histories ([`signals`]), and the sample interval, s.
pub type Run = (String, Histories, f64);

/// Identifies runs of one condition together from their histories: what
/// [`identify_records`] does after reading the records.
pub fn identify_histories(
    id: &str,
    runs: Vec<Run>,
    config: &ConfigSpec,
) -> Result<Identification, String> {
    if runs.is_empty() {
        return Err("no record to identify".into());
    }
    identify_from(id, Source::Runs(runs), config)
}

/// The set-up's frequencies.
pub(crate) fn frequencies(config: &ConfigSpec) -> Result<Frequencies, String> {
    let f = &config.frequencies;
    match (f.from_hz, f.to_hz, f.points, &f.list_hz) {
        (Some(a), Some(b), Some(n), None)
            if a > 0.0
                && b > a
                && (2..=crate::inputs::limits::MAX_FREQUENCY_POINTS).contains(&n) =>
        {
            Ok(Frequencies::Band {
                from_hz: a,
                to_hz: b,
                points: n,
            })
        }
        (None, None, None, Some(l))
            if !l.is_empty() && l.len() <= crate::inputs::limits::MAX_FREQUENCY_POINTS =>
        {
            Ok(Frequencies::List(l.clone()))
        }
        _ => Err(format!(
            "frequencies: give `from_hz` < `to_hz` with `points` from 2 to {} \
             (MAX_FREQUENCY_POINTS), or a non-empty `list_hz`",
            crate::inputs::limits::MAX_FREQUENCY_POINTS
        )),
    }
}

/// What an identification's transforms come from.
pub(crate) enum Source {
    /// Time histories, transformed as the set-up says.
    Runs(Vec<Run>),
    /// Transforms already computed: per excitation, its frequencies (rad/s) and the states'
    /// and controls' transforms at them, `[variable][frequency]`.
    Response(Vec<(Vec<f64>, Vec<Vec<estimate::C>>)>),
}

/// The estimation proper, from either source.
pub(crate) fn identify_from(
    id: &str,
    source: Source,
    config: &ConfigSpec,
) -> Result<Identification, String> {
    // Long: one estimation, in the order it runs: the equations, the frequencies, each run's
    // transforms, least squares, then the instrumental-variable passes
    let controls: Vec<String> = config.controls.keys().cloned().collect();
    let all: Vec<String> = config.states.iter().chain(&controls).cloned().collect();
    // Every force equation with every state and control free: the default, and the first model
    // that instrumental variables need even when the user identifies only some equations.
    let full: Vec<Equation> = config
        .states
        .iter()
        .filter(|s| force_letter(s).is_some() || FLAP_STATES.contains(&s.as_str()))
        .map(|s| Equation {
            state: s.clone(),
            estimate: all.clone(),
            fixed: vec![],
        })
        .collect();
    let equations: Vec<Equation> = if config.equations.is_empty() {
        full.clone()
    } else {
        config
            .equations
            .iter()
            .map(|e| Equation {
                state: e.state.clone(),
                estimate: e.estimate.clone(),
                fixed: e.fixed.iter().map(|(k, v)| (k.clone(), *v)).collect(),
            })
            .collect()
    };
    let freqs = frequencies(config)?;
    let w = config.windowing.settings();
    let err = |e: IdentError| format!("{id}: {e}");
    // The transforms are computed once; least squares and each instrumental-variable pass use them.
    let mut parts = Vec::new();
    match source {
        Source::Runs(runs) => {
            for (name, (xs, us), dt_s) in &runs {
                let sig = Signals {
                    states: &config.states,
                    controls: &controls,
                    x: xs,
                    u: us,
                    dt_s: *dt_s,
                };
                parts.push(estimate::spectra(sig, &freqs, w).map_err(|e| format!("{name}: {e}"))?);
            }
        }
        Source::Response(excitations) => {
            for (omegas, var_ft) in excitations {
                parts.push(
                    estimate::Spectra::from_response(
                        all.clone(),
                        config.states.len(),
                        &omegas,
                        var_ft,
                    )
                    .map_err(err)?,
                );
            }
        }
    }
    let spectra = estimate::Spectra::concatenate(parts).map_err(err)?;
    let mut fits = estimate::fit_equations(&spectra, &equations, None).map_err(err)?;
    if config.method == Method::InstrumentalVariables {
        // The first model: the full least-squares fit, with the user's equations in their rows
        // (instruments need every state's response, not only the identified equations').
        let mut base = if equations == full {
            fits.clone()
        } else {
            estimate::fit_equations(&spectra, &full, None).map_err(err)?
        };
        for _ in 0..2 {
            let merged: Vec<EquationFit> = base
                .iter()
                .map(|b| {
                    fits.iter()
                        .find(|f| f.state == b.state)
                        .unwrap_or(b)
                        .clone()
                })
                .collect();
            let first = identified_model(config, &controls, &merged)?;
            fits =
                estimate::identify_iv(&spectra, &equations, first.a(), first.b()).map_err(err)?;
            base = merged;
        }
    }
    let mut derivatives = Vec::new();
    for fit in &fits {
        let letter = force_letter(&fit.state).map_or(fit.state.clone(), |c| c.to_string());
        for e in &fit.estimates {
            derivatives.push(Derivative {
                name: format!("{letter}_{}", e.variable),
                estimate: e.value,
                standard_error: e.standard_error,
                lower_95: e.lower_95,
                upper_95: e.upper_95,
            });
        }
    }
    let model = identified_model(config, &controls, &fits).ok();
    let status = if fits.iter().any(|f| !f.warnings.is_empty()) {
        "warnings"
    } else {
        "ok"
    };
    Ok(Identification {
        record: id.to_string(),
        fits,
        derivatives,
        status,
        model,
    })
}

/// A model of the set-up's states and controls with every entry zero: what names a set-up's
/// derivatives can take, before anything is identified.
pub fn identified_template(config: &ConfigSpec) -> Result<LinearModel, String> {
    let (n, m) = (config.states.len(), config.controls.len());
    LinearModel::new(
        config.states.clone(),
        config.controls.keys().cloned().collect(),
        nalgebra::DMatrix::zeros(n, n),
        nalgebra::DMatrix::zeros(n, m),
    )
    .map_err(|e| e.to_string())
}

/// The identified linear model: estimated and fixed rows, kinematic rows from the set-up; rows
/// neither identified nor kinematic are zero.
pub fn identified_model(
    config: &ConfigSpec,
    controls: &[String],
    fits: &[EquationFit],
) -> Result<LinearModel, String> {
    let n = config.states.len();
    let mut a = vec![vec![0.0; n]; n];
    let mut b = vec![vec![0.0; controls.len()]; n];
    let col = |name: &str| -> Option<(bool, usize)> {
        config
            .states
            .iter()
            .position(|s| s == name)
            .map(|i| (true, i))
            .or_else(|| controls.iter().position(|c| c == name).map(|i| (false, i)))
    };
    for fit in fits {
        let row = config
            .states
            .iter()
            .position(|s| *s == fit.state)
            .ok_or("unknown state")?;
        let values = fit
            .estimates
            .iter()
            .map(|e| (e.variable.as_str(), e.value))
            .chain(fit.fixed.iter().map(|(k, v)| (k.as_str(), *v)));
        for (name, v) in values {
            match col(name) {
                Some((true, j)) => a[row][j] = v,
                Some((false, j)) => b[row][j] = v,
                None => return Err(format!("unknown variable {name}")),
            }
        }
    }
    for (state, rate) in &config.kinematics {
        let (row, c) = (
            config
                .states
                .iter()
                .position(|s| s == state)
                .ok_or("unknown kinematic state")?,
            config
                .states
                .iter()
                .position(|s| s == rate)
                .ok_or("unknown kinematic rate")?,
        );
        a[row][c] = 1.0;
    }
    LinearModel::from_rows(config.states.clone(), controls.to_vec(), &a, &b)
        .map_err(|e| e.to_string())
}

/// The identified derivatives as a flight-refs derivative table (YAML text).
pub fn reference_yaml(id: &str, ident: &Identification, records: &[Record]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let synthetic = records.iter().any(|r| r.meta.synthetic.is_some());
    let _ = writeln!(s, "id: {id}");
    let _ = writeln!(
        s,
        "title: Derivatives identified from {}{}",
        ident.record,
        if synthetic {
            " (synthetic records)"
        } else {
            ""
        }
    );
    let _ = writeln!(s, "provenance:");
    let _ = writeln!(
        s,
        "  source: \"cierva identify {}: frequency-domain equation error (seed 000 Sec. IV) on {}\"",
        env!("CARGO_PKG_VERSION"),
        records
            .iter()
            .map(|r| r.path.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        s,
        "  notes: \"records' provenance: {}\"",
        records
            .iter()
            .map(|r| r.meta.provenance.source.replace('"', "'"))
            .collect::<Vec<_>>()
            .join("; ")
    );
    let _ = writeln!(s, "columns:");
    let _ = writeln!(
        s,
        "  estimate: {{kind: value, description: identified value}}"
    );
    let _ = writeln!(
        s,
        "  standard_error: {{kind: value, description: standard error of the estimate}}"
    );
    let _ = writeln!(
        s,
        "  flight_95: {{kind: interval, description: 95 % confidence bounds}}"
    );
    let _ = writeln!(s, "derivatives:");
    for d in &ident.derivatives {
        let _ = writeln!(
            s,
            "  - {{name: {}, units: as the record's, estimate: {:e}, standard_error: {:e}, flight_95: [{:e}, {:e}]}}",
            d.name, d.estimate, d.standard_error, d.lower_95, d.upper_95
        );
    }
    s
}

/// How well a predicted time history matches a measured one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignalComparison {
    pub signal: String,
    pub rms_error: f64,
    /// Theil's inequality coefficient, `rms(p - m) / (rms(p) + rms(m))`: 0 is a perfect match,
    /// 1 the worst.
    pub theil: f64,
}

/// Theil's inequality coefficient of a prediction against a measurement.
pub fn theil_inequality(predicted: &[f64], measured: &[f64]) -> f64 {
    let n = predicted.len().min(measured.len()).max(1) as f64;
    let rms =
        |f: &dyn Fn(usize) -> f64| ((0..n as usize).map(|k| f(k).powi(2)).sum::<f64>() / n).sqrt();
    let num = rms(&|k| predicted[k] - measured[k]);
    let den = rms(&|k| predicted[k]) + rms(&|k| measured[k]);
    if den > 0.0 { num / den } else { 0.0 }
}

/// Flies `model` (states and controls as in `config`) with the controls of `record`, from its
/// first measured state, and compares its states with the record's measured perturbations
/// (seed 000 Fig. 10; [`verify::fly`]).
pub fn predict(
    model: &LinearModel,
    record: &Record,
    config: &ConfigSpec,
) -> Result<Vec<SignalComparison>, String> {
    let (xs, flown) = verify::fly(model, record, config)?;
    Ok(config
        .states
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let c = verify::compare(name, &flown[i], &xs[i]);
            SignalComparison {
                signal: name.clone(),
                rms_error: c.rms_error,
                theil: c.theil,
            }
        })
        .collect())
}
