//! Time-domain verification, as CIFER's VERIFY does (Tischler and Remple, *Aircraft and
//! Rotorcraft System Identification*, 2nd ed., 2012; the chapter is not confirmed here): linear
//! models are driven by a record's measured controls (perturbations about the sidecar's trim,
//! piecewise linear in time between samples) from the record's first measured state, and their
//! outputs are compared with the record's measured states.
//!
//! The measured states are what the identification uses ([`mod@super::signals`]: air data
//! converted to centre-of-mass velocities, perturbations about the trim), and the models are
//! flown by [`cierva_model::simulation::simulate::simulate`] (RK4 at the sample interval, the
//! inputs evaluated exactly at each stage).
//!
//! Per output and model: Theil's inequality coefficient
//! `TIC = rms(y - z) / (rms(y) + rms(z))` (`y` predicted, `z` measured: 0 is a perfect match, 1
//! the worst; [`super::theil_inequality`]) and the RMS error in the output's units. Tischler's
//! VERIFY also fits a bias and a reference shift per output; [`OutputFit::theil_bias_removed`]
//! takes off the mean error only, and is a note beside the plain TIC, not the headline.

use super::{ConfigSpec, FLAP_STATES, control_channel, signals, theil_inequality};
use crate::inputs::record::Record;
use crate::inputs::reference;
use crate::inputs::yaml::{self, InputError};
use cierva_model::LinearModel;
use cierva_model::analysis::linear::FORCE_STATES;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The states a derivative table can name, in the order the identified model takes them (the
/// identification set-ups' order).
pub const STATE_ORDER: [&str; 10] = ["u", "v", "w", "p", "q", "r", "phi", "theta", "psi", "Omega"];

/// The column of an identified derivative table that holds the estimates.
pub const ESTIMATE_COLUMN: &str = "estimate";

/// A state's output name, its unit in the name (`q` -> `q_rad_s`).
pub fn output_name(state: &str) -> String {
    match state {
        "u" | "v" | "w" => format!("{state}_m_s"),
        "p" | "q" | "r" => format!("{state}_rad_s"),
        "Omega" => "omega_rotor_rad_s".into(),
        other => format!("{other}_rad"),
    }
}

/// The unit in an output's name, for tables and axes.
pub fn output_unit(output: &str) -> &'static str {
    if output.ends_with("_m_s") {
        "m/s"
    } else if output.ends_with("_rad_s") {
        "rad/s"
    } else {
        "rad"
    }
}

/// A model rebuilt from an identified derivative table (what `cierva identify --format yaml`
/// writes), with the set-up that flies it.
#[derive(Debug, Clone)]
pub struct Identified {
    pub model: LinearModel,
    /// States (in [`STATE_ORDER`]) and kinematic rows (`theta: q`, `phi: p`) as the
    /// identification had them; the controls map to no channel yet ([`config_for`]).
    pub states: Vec<String>,
    pub kinematics: BTreeMap<String, String>,
}

/// The equation state of a derivative name and the variable it multiplies (`M_eta_s` ->
/// `(q, eta_s)`), or `None` when the name has no force letter.
fn split(name: &str) -> Option<(&'static str, &str)> {
    let (letter, var) = name.split_once('_')?;
    let mut chars = letter.chars();
    let (c, rest) = (chars.next()?, chars.next());
    if rest.is_some() {
        return None;
    }
    let state = FORCE_STATES.iter().find(|(f, _)| *f == c)?.1;
    (!var.is_empty()).then_some((state, var))
}

/// Loads an identified derivative table and rebuilds its model: each `X_var` is the entry of
/// the state `u`'s row in the column of `var` (a state or, otherwise, a control); `theta` and
/// `phi` without an equation of their own are the kinematic rows `theta' = q` and `phi' = p`
/// that the identification set-ups use. Errors name the file and the field.
pub fn load_identified(path: &Path) -> Result<Identified, InputError> {
    let reference = reference::load(path)?;
    let src = yaml::read(path)?;
    let at = |i: usize, msg: String| {
        InputError::field(path, &src, &format!("derivatives[{i}].name"), msg)
    };
    if reference.table.rows.is_empty() {
        return Err(InputError::field(
            path,
            &src,
            "derivatives",
            "no derivative table: give an identified table (`cierva identify RECORD --format yaml`)",
        ));
    }
    let mut entries: Vec<(&'static str, String, f64)> = Vec::new();
    for (i, (name, _, columns)) in reference.table.rows.iter().enumerate() {
        if FLAP_STATES.iter().any(|f| name.starts_with(f)) {
            return Err(at(
                i,
                format!(
                    "`{name}`: verifying a model with flapping states is not supported (its signals are averaged over a revolution, cierva's quasi-static model has no such states)"
                ),
            ));
        }
        let (state, var) = split(name).ok_or_else(|| {
            at(
                i,
                format!(
                    "`{name}` is not a derivative name: a force letter ({}) then `_` and a state or control",
                    FORCE_STATES.iter().map(|(f, _)| f.to_string()).collect::<Vec<_>>().join(" ")
                ),
            )
        })?;
        let value = match columns.get(ESTIMATE_COLUMN) {
            Some(reference::Entry::Value(v)) => *v,
            _ => {
                return Err(InputError::field(
                    path,
                    &src,
                    &format!("derivatives[{i}]"),
                    format!(
                        "`{name}` has no `{ESTIMATE_COLUMN}` value (the column `cierva identify --format yaml` writes)"
                    ),
                ));
            }
        };
        entries.push((state, var.to_string(), value));
    }
    let equations: Vec<&str> = entries.iter().map(|e| e.0).collect();
    let mut kinematics = BTreeMap::new();
    for (angle, rate) in [("theta", "q"), ("phi", "p")] {
        let named = entries.iter().any(|e| e.1 == angle);
        if named && !equations.contains(&angle) {
            kinematics.insert(angle.to_string(), rate.to_string());
        }
    }
    let is_state = |v: &str| STATE_ORDER.contains(&v);
    let states: Vec<String> = STATE_ORDER
        .iter()
        .filter(|s| {
            equations.contains(s)
                || entries.iter().any(|e| e.1 == **s)
                || kinematics.values().any(|r| r == *s)
        })
        .map(|s| s.to_string())
        .collect();
    let mut controls: Vec<String> = Vec::new();
    for e in &entries {
        if !is_state(&e.1) && !controls.contains(&e.1) {
            controls.push(e.1.clone());
        }
    }
    if let Some(s) = states
        .iter()
        .find(|s| !equations.contains(&s.as_str()) && !kinematics.contains_key(*s))
    {
        let i = entries.iter().position(|e| e.1 == *s).unwrap_or(0);
        return Err(at(
            i,
            format!(
                "the state `{s}` enters the table but has no equation (no `{}_...` rows) and no kinematic row",
                FORCE_STATES
                    .iter()
                    .find(|(_, st)| st == s)
                    .map_or(s.clone(), |(f, _)| f.to_string())
            ),
        ));
    }
    let (n, m) = (states.len(), controls.len());
    let mut a = vec![vec![0.0; n]; n];
    let mut b = vec![vec![0.0; m]; n];
    let pos = |list: &[String], v: &str| list.iter().position(|x| x == v);
    for (state, var, value) in &entries {
        let row = pos(&states, state).unwrap_or_default();
        match pos(&states, var) {
            Some(j) => a[row][j] = *value,
            None => b[row][pos(&controls, var).unwrap_or_default()] = *value,
        }
    }
    for (angle, rate) in &kinematics {
        if let (Some(i), Some(j)) = (pos(&states, angle), pos(&states, rate)) {
            a[i][j] = 1.0;
        }
    }
    let model = LinearModel::from_rows(states.clone(), controls, &a, &b)
        .map_err(|e| InputError::field(path, &src, "derivatives", e.to_string()))?;
    Ok(Identified {
        model,
        states,
        kinematics,
    })
}

/// The set-up that reads `identified`'s states and controls from `record`: each control from
/// its channel in the sidecar's controls (`<control>_percent` or `<control>_rad`). A control the
/// record lacks is an error naming the sidecar and the channel.
pub fn config_for(identified: &Identified, record: &Record) -> Result<ConfigSpec, InputError> {
    let mut controls = BTreeMap::new();
    for c in identified.model.controls() {
        match control_channel(record, c) {
            Some(ch) => {
                controls.insert(c.clone(), ch);
            }
            None => {
                let side = crate::inputs::record::sidecar_path(&record.path);
                let src = yaml::read(&side)?;
                return Err(InputError::field(
                    &side,
                    &src,
                    "controls",
                    format!(
                        "the identified model needs the control `{c}`: no channel `{c}_percent` or `{c}_rad` among the record's controls [{}]",
                        record.meta.controls.join(", ")
                    ),
                ));
            }
        }
    }
    Ok(ConfigSpec {
        states: identified.states.clone(),
        controls,
        frequencies: super::BandSpec::SEED_000,
        windowing: super::WindowingSpec::default(),
        equations: vec![],
        kinematics: identified.kinematics.clone(),
        method: super::Estimator::default(),
        blade_passage_blades: None,
    })
}

/// A model flown through a record: its states' time histories, `[state][sample]`, in the
/// set-up's state order.
pub type Traces = Vec<Vec<f64>>;

/// The record's measured perturbation states (`[state][sample]`, in `config`'s order) and
/// `model` flown through its controls from its first measured state.
pub fn fly(
    model: &LinearModel,
    record: &Record,
    config: &ConfigSpec,
) -> Result<(Vec<Vec<f64>>, Traces), String> {
    let (xs, us) = signals(record, config)?;
    let model = model
        .reorder(&config.states.iter().map(String::as_str).collect::<Vec<_>>())
        .map_err(|e| e.to_string())?;
    if model.controls().len() != us.len()
        || model
            .controls()
            .iter()
            .zip(config.controls.keys())
            .any(|(a, b)| a != b)
    {
        return Err(format!(
            "the model's controls {:?} are not the set-up's {:?}",
            model.controls(),
            config.controls.keys().collect::<Vec<_>>()
        ));
    }
    let dt = record.dt_s();
    let n = xs.first().map_or(0, Vec::len);
    if n < 2 {
        return Err(format!(
            "{}: the record is too short to fly",
            record.path.display()
        ));
    }
    // The controls piecewise linear between samples.
    let input = |t: f64| -> Vec<f64> {
        let pos = (t / dt).clamp(0.0, (n - 1) as f64);
        let (k, f) = (pos.floor() as usize, pos - pos.floor());
        us.iter()
            .map(|u| u[k] + (u[(k + 1).min(n - 1)] - u[k]) * f)
            .collect()
    };
    let x0: Vec<f64> = xs.iter().map(|x| x[0]).collect();
    let sim = cierva_model::simulation::simulate::simulate(&model, &x0, &input, dt, n - 1);
    let flown = (0..xs.len())
        .map(|i| sim.iter().map(|s| s[i]).collect())
        .collect();
    Ok((xs, flown))
}

/// One output of one model against the record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutputFit {
    /// The output, its unit in the name (`q_rad_s`).
    pub output: String,
    /// Theil's inequality coefficient (0 perfect, 1 worst).
    pub theil: f64,
    /// The RMS of the error, in the output's units.
    pub rms_error: f64,
    /// The mean error (predicted minus measured), in the output's units.
    pub bias: f64,
    /// Theil's coefficient with the mean error taken off the prediction (a note: VERIFY fits a
    /// bias per output).
    pub theil_bias_removed: f64,
}

/// One model's run through the record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelRun {
    pub model: String,
    pub outputs: Vec<OutputFit>,
    /// The outputs' predicted perturbations, `[output][sample]`.
    #[serde(skip)]
    pub predicted: Vec<Vec<f64>>,
}

/// A record and the models flown through it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verification {
    pub record: String,
    pub outputs: Vec<String>,
    pub samples: usize,
    pub duration_s: f64,
    pub models: Vec<ModelRun>,
    /// The outputs' measured perturbations, `[output][sample]`.
    #[serde(skip)]
    pub measured: Vec<Vec<f64>>,
    #[serde(skip)]
    pub time_s: Vec<f64>,
}

/// A prediction against a measurement.
pub fn compare(output: &str, predicted: &[f64], measured: &[f64]) -> OutputFit {
    let n = predicted.len().min(measured.len()).max(1) as f64;
    let error: Vec<f64> = predicted.iter().zip(measured).map(|(y, z)| y - z).collect();
    let rms_error = (error.iter().map(|e| e * e).sum::<f64>() / n).sqrt();
    let bias = error.iter().sum::<f64>() / n;
    let shifted: Vec<f64> = predicted.iter().map(|y| y - bias).collect();
    OutputFit {
        output: output.to_string(),
        theil: theil_inequality(predicted, measured),
        rms_error,
        bias,
        theil_bias_removed: theil_inequality(&shifted, measured),
    }
}

/// Flies each model (named, with the set-up that reads its states and controls from the
/// record) through `record` and compares the `outputs` (names with units, as
/// [`output_name`] gives them) with the record's measurements. Every model must have every
/// output among its states. Errors name the record.
pub fn verify(
    record: &Record,
    models: &[(&str, &LinearModel, &ConfigSpec)],
    outputs: &[String],
) -> Result<Verification, String> {
    let path = record.path.display().to_string();
    let located = |e: String| {
        if e.starts_with(&path) {
            e
        } else {
            format!("{path}: {e}")
        }
    };
    let mut runs = Vec::new();
    let mut measured: Vec<Vec<f64>> = Vec::new();
    for (name, model, config) in models {
        let (xs, flown) = fly(model, record, config).map_err(located)?;
        let mut fits = Vec::new();
        let mut predicted = Vec::new();
        let mut this_measured = Vec::new();
        for out in outputs {
            let i = config
                .states
                .iter()
                .position(|s| output_name(s) == *out)
                .ok_or_else(|| {
                    located(format!(
                        "{name} has no output `{out}` (it has {})",
                        config
                            .states
                            .iter()
                            .map(|s| output_name(s))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ))
                })?;
            fits.push(compare(out, &flown[i], &xs[i]));
            predicted.push(flown[i].clone());
            this_measured.push(xs[i].clone());
        }
        if measured.is_empty() {
            measured = this_measured;
        }
        runs.push(ModelRun {
            model: name.to_string(),
            outputs: fits,
            predicted,
        });
    }
    let samples = measured.first().map_or(0, Vec::len);
    let dt = record.dt_s();
    let time_s: Vec<f64> = match record.channel("time_s") {
        Some(t) if t.len() == samples => t.iter().map(|v| v - t[0]).collect(),
        _ => (0..samples).map(|k| k as f64 * dt).collect(),
    };
    Ok(Verification {
        record: record.path.display().to_string(),
        outputs: outputs.to_vec(),
        samples,
        duration_s: time_s.last().copied().unwrap_or(0.0),
        models: runs,
        measured,
        time_s,
    })
}
