//! `frequency_response`: the model's frequency response from a control to a state, against a
//! reference response, judged by CIFER's mismatch cost `J` (Tischler and Remple 2012).
//!
//! The reference is a non-parametric response estimated from flight records at load
//! ([`crate::ident::frequency_response`]: Welch's spectra composited over several windows,
//! conditioned on the other controls the check names), or a response file as `cierva
//! frequency-response --format csv` writes it (`frequency_hz,magnitude_db,phase_deg,coherence`,
//! more columns ignored; a row without a magnitude or a phase has nothing estimated and is
//! left out).
//!
//! The model's response is `e_output (i omega I - A)^-1 B e_input`:
//! - a linear model's own `A`, `B`;
//! - an aircraft linearised at the check's condition with its rotor's flapping (and inflow,
//!   and propeller speed) as states where its hub has that linearisation (a teetering hub,
//!   [`cierva_model::aircraft::flapping`]), its baseband response by harmonic balance: what a
//!   record's analysis sees of a rotor whose blades lag;
//! - otherwise the aircraft's quasi-static linearisation ([`cierva_model::aircraft::linearise`]).
//!
//! The result's `note` says which. The cost is computed over the reference's frequencies whose
//! coherence is at least [`COHERENCE_MIN`] ([`mismatch_cost`]); a reference with none gives
//! the finding "inconclusive: coherence", which never passes. The band used and the number of
//! frequencies are reported in the result's fingerprint (`band_low_hz`, `band_high_hz`,
//! `frequencies_in_band`).
//!
//! # Sources, and what is not confirmed
//! The cost, its weights, the coherence threshold and the guidelines are Tischler and Remple's
//! (*Aircraft and Rotorcraft System Identification*, 2nd ed., 2012) as issue 32 states them and
//! as CIFER's literature quotes them. They could not be checked against the book's text here:
//! the searchable sources reach only its chapter summaries (the 1st edition's, which put the
//! identification cost in Eq. 12.20 and the guidelines in Eqs. 12.23-12.24), not the equations.
//! Not confirmed in particular: the chapter and equation numbers in the 2nd edition; whether the
//! guideline of 100 is meant for one response's J or for the average over a model's responses
//! (`J_ave`; a single response is then allowed somewhat more); and the phase difference's
//! wrapping to +-180 deg (taken here, as a phase error beyond that is the same error).

use super::result::{Evaluated, Finding, PlotData, compare_all};
use super::{At, CheckSpec, Cx, Evaluate, Expectation, Kind, Refusal, Trivial};
use crate::checks::subject::Subject;
use crate::ident::frequency_response as fr;
use crate::inputs::quantity::Quantity as Q;
use crate::inputs::record::{self, Record};
use crate::inputs::yaml::InputError;
use rustfft::num_complex::Complex64 as C;
use serde::Deserialize;
use std::path::Path;

/// Least coherence of a frequency that enters the cost: Tischler and Remple (2012) compute
/// `J` over the frequency range where the coherence is at least 0.6, below which the random
/// error of the estimate is too large for it to judge a model (the threshold, the
/// book's guideline).
pub const COHERENCE_MIN: f64 = 0.6;

/// `J`'s scale: `J = (20 / n_omega) sum ...` (Tischler and Remple 2012, the frequency-response
/// cost function; the factor makes `J` about 1 to 100 for the errors that matter).
pub const COST_SCALE: f64 = 20.0;

/// `W_g`, the weight of the squared magnitude error in dB^2 (Tischler and Remple 2012).
pub const MAGNITUDE_WEIGHT_PER_DB2: f64 = 1.0;

/// `W_p`, the weight of the squared phase error in deg^2: 0.01745 (`pi / 180`), which makes
/// 1 dB of magnitude cost what 7.57 deg of phase costs (Tischler and Remple 2012).
pub const PHASE_WEIGHT_PER_DEG2: f64 = 0.01745;

/// The coherence weight's scale: `W_gamma = [1.58 (1 - exp(-gamma^2))]^2` (Tischler and
/// Remple 2012). `1.58` is about `1 / (1 - e^-1)`: the weight is 1.0 at a coherence of 1 and
/// 0.51 at the band's least, 0.6.
pub const COHERENCE_WEIGHT_SCALE: f64 = 1.58;

/// Tischler's guideline: a mismatch cost at or below 100 generally reflects an acceptable level
/// of accuracy for flight-dynamics modelling (Tischler and Remple 2012; the issue's "J <= 100
/// acceptable"). A case's tolerance states it with its reason; this is the figure docs and
/// tests name.
pub const J_ACCEPTABLE: f64 = 100.0;

/// Tischler's guideline: at or below 50 the model's response is nearly indistinguishable from
/// the data's (Tischler and Remple 2012; the "J <= 50 hard to tell apart").
pub const J_INDISTINGUISHABLE: f64 = 50.0;

/// One frequency of the reference response.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    pub frequency_hz: f64,
    pub response: C,
    pub coherence: f64,
}

/// Where the reference response came from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// Estimated from records (their paths, as the case gives them) with these windows.
    Records {
        files: Vec<String>,
        windows_s: Vec<f64>,
        /// What the records' loads mapped, converted or did not compare, by record.
        notes: Vec<(std::path::PathBuf, String)>,
    },
    /// Read from a response file.
    File(String),
}

/// A `frequency_response` check.
#[derive(Debug, Clone, PartialEq)]
pub struct FrequencyResponseCheck {
    /// The control (`eta_s`): a column of the model's `B`.
    pub input: String,
    /// The state (`q`): a row of the model's `C`.
    pub output: String,
    /// Other controls the records' response is conditioned on.
    pub conditioned_on: Vec<String>,
    /// An aircraft's flight condition.
    pub condition: Option<crate::inputs::condition::TrimRequest>,
    /// The reference response, every frequency where it is estimated.
    pub reference: Vec<Point>,
    pub source: Source,
}

/// The mismatch cost of a model's response over a reference's band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    /// `J`.
    pub j: f64,
    /// Frequencies in the band (coherence at least [`COHERENCE_MIN`]).
    pub frequencies: usize,
    pub band_low_hz: f64,
    pub band_high_hz: f64,
}

/// `W_gamma = [1.58 (1 - exp(-gamma^2))]^2` for a coherence `gamma^2`.
pub fn coherence_weight(coherence: f64) -> f64 {
    (COHERENCE_WEIGHT_SCALE * (1.0 - (-coherence).exp())).powi(2)
}

/// `T_c`'s phase less `T`'s, wrapped to (-180, 180] deg.
fn phase_error_deg(model: C, reference: C) -> f64 {
    let d = (model.arg() - reference.arg()).to_degrees();
    let wrapped = d - 360.0 * (d / 360.0).round();
    if wrapped <= -180.0 {
        wrapped + 360.0
    } else {
        wrapped
    }
}

/// CIFER's mismatch cost (Tischler and Remple 2012): over the `n_omega` frequencies of the
/// reference whose coherence `gamma^2` is at least [`COHERENCE_MIN`],
/// `J = (20 / n_omega) sum W_gamma [W_g (|T_c| - |T|)^2 + W_p (angle T_c - angle T)^2]`,
/// magnitudes in dB, phases in deg (their difference wrapped to +-180), `W_g = 1`,
/// `W_p = 0.01745`, `W_gamma = [1.58 (1 - exp(-gamma^2))]^2`. `model` is the model's response
/// at each of the reference's frequencies. `None` when no frequency is in the band. A model
/// with no response at a frequency of the band (`|T_c| = 0`, minus infinity dB) costs
/// infinitely much.
pub fn mismatch_cost(reference: &[Point], model: &[C]) -> Option<Cost> {
    let mut sum = 0.0;
    let mut n = 0usize;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (p, tc) in reference.iter().zip(model) {
        if p.coherence < COHERENCE_MIN {
            continue;
        }
        let db = 20.0 * tc.norm().log10() - 20.0 * p.response.norm().log10();
        let deg = phase_error_deg(*tc, p.response);
        sum += coherence_weight(p.coherence)
            * (MAGNITUDE_WEIGHT_PER_DB2 * db * db + PHASE_WEIGHT_PER_DEG2 * deg * deg);
        n += 1;
        lo = lo.min(p.frequency_hz);
        hi = hi.max(p.frequency_hz);
    }
    (n > 0).then(|| Cost {
        j: COST_SCALE / n as f64 * sum,
        frequencies: n,
        band_low_hz: lo,
        band_high_hz: hi,
    })
}

/// A `frequency_response` check's own fields, as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrequencyResponseSpec {
    /// The control whose response is compared (`eta_s`).
    pub input: String,
    /// The state that responds (`q`).
    pub output: String,
    /// Flight records (CSV, sidecars beside them) the reference response is estimated from,
    /// relative to the case file.
    #[serde(default)]
    pub records: Option<Vec<String>>,
    /// A response file (`frequency_hz,magnitude_db,phase_deg,coherence`), relative to the case
    /// file.
    #[serde(default)]
    pub reference: Option<String>,
    /// From records: other controls the response is conditioned on.
    #[serde(default)]
    pub conditioned_on: Option<Vec<String>>,
    /// From records: the windows, s (default an eighth, a quarter and a half of the shortest
    /// record).
    #[serde(default)]
    pub windows_s: Option<Vec<f64>>,
    /// From records: the band of the estimate, Hz (default the estimator's: five periods of the
    /// longest window to a fifth of the sample rate).
    #[serde(default)]
    pub band_hz: Option<[f64; 2]>,
    /// On an aircraft or an external model: the condition its linear model is asked at.
    #[serde(default)]
    pub condition: Option<crate::inputs::condition::TrimRequest>,
    /// Why the condition or the loading differs from the records' sidecars, where it does on
    /// purpose (otherwise a difference is an error).
    #[serde(default)]
    pub condition_differs_from_record: Option<String>,
}

impl Kind for FrequencyResponseCheck {
    type Spec = FrequencyResponseSpec;
    const SUBJECTS: &'static str = "a linear model, an aircraft or an external model";

    fn runs_on(subject: &Subject) -> bool {
        matches!(
            subject,
            Subject::Linear { .. } | Subject::Aircraft { .. } | Subject::External(_)
        )
    }

    fn resolve(cx: &Cx, own: FrequencyResponseSpec, _: &CheckSpec) -> Result<Self, InputError> {
        let spec = &own;
        let input = spec.input.clone();
        let output = spec.output.clone();
        let conditioned_on = spec.conditioned_on.clone().unwrap_or_default();
        let (states, controls) = layout(cx.subject);
        if !states.contains(&output) {
            return Err(cx.err(
                ".output",
                format!(
                    "`{output}` is not a state of the model; its states are [{}]",
                    states.join(", ")
                ),
            ));
        }
        for (field, c) in std::iter::once((".input".to_string(), &input)).chain(
            conditioned_on
                .iter()
                .enumerate()
                .map(|(i, c)| (format!(".conditioned_on[{i}]"), c)),
        ) {
            if !controls.contains(c) {
                return Err(cx.err(
                    &field,
                    format!(
                        "`{c}` is not a control of the model; its controls are [{}]",
                        controls.join(", ")
                    ),
                ));
            }
        }
        if conditioned_on.contains(&input) {
            return Err(cx.err(".conditioned_on", format!("`{input}` is the input itself")));
        }
        let condition = match cx.subject {
            Subject::Aircraft { .. } | Subject::External(_) => {
                let c = cx.needs(&spec.condition, "condition")?;
                super::check_condition(cx, &c, true)?;
                Some(c)
            }
            _ => None,
        };
        let (reference, source) = match (&spec.records, &spec.reference) {
            (Some(files), None) => from_records(cx, spec, files, &input, &output, &conditioned_on)?,
            (None, Some(file)) => {
                let estimator_fields = [
                    ("conditioned_on", spec.conditioned_on.is_some()),
                    ("windows_s", spec.windows_s.is_some()),
                    ("band_hz", spec.band_hz.is_some()),
                ];
                if let Some((f, _)) = estimator_fields.iter().find(|(_, given)| *given) {
                    return Err(cx.err(
                        &format!(".{f}"),
                        format!(
                            "`{f}` applies to a reference estimated from `records`, not to a response file"
                        ),
                    ));
                }
                (
                    read_response(&cx.dir.join(file))
                        .map_err(|e| cx.err(".reference", format!("in the response file: {e}")))?,
                    Source::File(file.clone()),
                )
            }
            _ => {
                return Err(cx.err(
                    "",
                    "a `frequency_response` check needs its reference: `records` (flight records \
                     to estimate it from) or `reference` (a response file), exactly one",
                ));
            }
        };
        Ok(Self {
            input,
            output,
            conditioned_on,
            condition,
            reference,
            source,
        })
    }
}

/// The states and controls of the model a subject gives (an aircraft's as it is linearised).
fn layout(subject: &Subject) -> (Vec<String>, Vec<String>) {
    use cierva_model::aircraft::linearise::{CONTROLS, STATES};
    match subject {
        Subject::Linear { model, .. } => (model.states().to_vec(), model.controls().to_vec()),
        _ => (
            STATES.iter().map(|s| s.to_string()).collect(),
            CONTROLS.iter().map(|s| s.to_string()).collect(),
        ),
    }
}

/// The reference estimated from the records at load: each record loaded as identification
/// loads it (its air data give `u v w`), the output and controls as changes from the sidecar's
/// trim ([`crate::ident::signals`]), then the composite estimate.
fn from_records(
    cx: &Cx,
    spec: &FrequencyResponseSpec,
    files: &[String],
    input: &str,
    output: &str,
    conditioned_on: &[String],
) -> Result<(Vec<Point>, Source), InputError> {
    if files.is_empty() {
        return Err(cx.err(".records", "give at least one record"));
    }
    let mut runs = Vec::new();
    let mut notes = Vec::new();
    for (i, file) in files.iter().enumerate() {
        let field = format!(".records[{i}]");
        let path = cx.dir.join(file);
        let rec = record::load(&path)
            .map_err(|e| cx.err(&field, format!("in the referenced record: {e}")))?;
        if let Some(c) = &spec.condition {
            super::condition_matches_record(
                cx,
                &field,
                c,
                &rec,
                spec.condition_differs_from_record.as_deref(),
            )?;
        }
        runs.push(run_of(cx, &field, &rec, input, output, conditioned_on)?);
        notes.extend(rec.notes.iter().map(|n| (path.clone(), n.clone())));
    }
    if let Some(w) = &spec.windows_s
        && (w.is_empty() || w.iter().any(|v| !(v.is_finite() && *v > 0.0)))
    {
        return Err(cx.err(
            ".windows_s",
            "give one or more window lengths, positive, in seconds",
        ));
    }
    // From the first sample to the last, to a tenth of a second, as `cierva
    // frequency-response` takes it.
    let shortest_s = runs
        .iter()
        .map(|r| (r.output.len().saturating_sub(1) as f64 * r.dt_s * 10.0).floor() / 10.0)
        .fold(f64::INFINITY, f64::min);
    let settings = fr::SpectralSettings {
        windows_s: spec
            .windows_s
            .clone()
            .unwrap_or_else(|| fr::SpectralSettings::default_windows_s(shortest_s)),
        overlap: fr::DEFAULT_OVERLAP,
        points: fr::DEFAULT_POINTS,
        band_hz: spec.band_hz,
    };
    let est = fr::estimate(&runs, &settings).map_err(|e| {
        let (field, inputs) = (
            match &e {
                fr::FrError::WindowTooLong { .. } => ".windows_s".to_string(),
                fr::FrError::Settings(_) if spec.band_hz.is_some() => ".band_hz".to_string(),
                fr::FrError::Settings(_) if spec.windows_s.is_some() => ".windows_s".to_string(),
                _ => ".records".to_string(),
            },
            std::iter::once(input)
                .chain(conditioned_on.iter().map(String::as_str))
                .collect::<Vec<_>>(),
        );
        let msg = match &e {
            fr::FrError::NoPower { run, input, .. } => {
                format!("{}: control `{}`: {e}", files[*run], inputs[*input])
            }
            fr::FrError::WindowTooLong { run, .. }
            | fr::FrError::SampleRate { run, .. }
            | fr::FrError::Lengths { run }
            | fr::FrError::NotFinite { run, .. } => format!("{}: {e}", files[*run]),
            _ => e.to_string(),
        };
        cx.err(&field, msg)
    })?;
    let r = &est.inputs[0];
    let points = est
        .frequencies_hz
        .iter()
        .zip(&r.response)
        .zip(&r.coherence)
        .filter_map(|((f, h), g)| {
            h.filter(|h| h.norm() > 0.0 && h.norm().is_finite())
                .map(|h| Point {
                    frequency_hz: *f,
                    response: h,
                    coherence: *g,
                })
        })
        .collect();
    Ok((
        points,
        Source::Records {
            files: files.to_vec(),
            windows_s: est.windows_s.clone(),
            notes,
        },
    ))
}

/// A record's input, conditioning controls and output, as a run of the estimator. An aircraft's
/// controls are in % of travel, so its records give them in `<control>_percent`.
fn run_of(
    cx: &Cx,
    field: &str,
    rec: &Record,
    input: &str,
    output: &str,
    conditioned_on: &[String],
) -> Result<fr::RecordSignals, InputError> {
    let mut config = crate::ident::ConfigSpec::for_model(crate::ident::Setup::Longitudinal);
    config.states = vec![output.to_string()];
    config.kinematics.clear();
    config.controls.clear();
    // A flight model's controls are in % of travel (cierva's aircraft's, and the protocol's:
    // an external model's B is per % of travel).
    let aircraft = matches!(cx.subject, Subject::Aircraft { .. } | Subject::External(_));
    let mut order = Vec::new();
    for c in std::iter::once(input).chain(conditioned_on.iter().map(String::as_str)) {
        let channel = crate::ident::control_channel(rec, c)
            .filter(|ch| !aircraft || ch.ends_with("_percent"))
            .ok_or_else(|| {
                cx.err(
                    field,
                    format!(
                        "{}: the record has no control `{c}` among its sidecar's `controls` ({})",
                        rec.path.display(),
                        if aircraft {
                            format!("an aircraft's controls are in % of travel: `{c}_percent`")
                        } else {
                            format!("`{c}_percent` or `{c}_rad`, in the model's unit")
                        }
                    ),
                )
            })?;
        if let Subject::Linear { units, .. } = cx.subject
            && let Some(unit) = units.get(c)
        {
            let clash = (unit.starts_with("rad") && channel.ends_with("_percent"))
                || (unit.contains('%') && channel.ends_with("_rad"));
            if clash {
                return Err(cx.err(
                    field,
                    format!(
                        "{}: the record gives `{c}` as `{channel}` where the model's `{c}` is in {unit}",
                        rec.path.display()
                    ),
                ));
            }
        }
        config.controls.insert(c.to_string(), channel.clone());
        order.push(channel);
    }
    let (xs, us) = crate::ident::signals(rec, &config).map_err(|e| cx.err(field, e))?;
    // `signals` gives the controls in the map's (alphabetical) order: put the input first.
    let names: Vec<&String> = config.controls.values().collect();
    let inputs = order
        .iter()
        .map(|ch| {
            let k = names.iter().position(|n| *n == ch).unwrap_or(0);
            us[k].clone()
        })
        .collect();
    Ok(fr::RecordSignals {
        name: rec.path.display().to_string(),
        inputs,
        output: xs.into_iter().next().unwrap_or_default(),
        dt_s: rec.dt_s(),
    })
}

/// The columns a response file must have.
pub const RESPONSE_COLUMNS: [&str; 4] = ["frequency_hz", "magnitude_db", "phase_deg", "coherence"];

/// Reads a response file: a CSV whose header names at least [`RESPONSE_COLUMNS`] (as `cierva
/// frequency-response --format csv` writes it); frequencies positive and rising, coherence in
/// [0, 1]. A row with an empty magnitude or phase (nothing estimated there) is left out.
pub fn read_response(path: &Path) -> Result<Vec<Point>, InputError> {
    let src = crate::inputs::yaml::read_csv(path)?;
    let at = |line: usize, column: usize, field: &str, msg: String| InputError {
        path: path.to_path_buf(),
        line: Some(line),
        column: Some(column),
        field: Some(field.to_string()),
        message: msg,
    };
    let mut lines = src
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines
        .next()
        .ok_or_else(|| InputError::file(path, "the file is empty"))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut index = [0usize; 4];
    for (k, want) in RESPONSE_COLUMNS.iter().enumerate() {
        index[k] = names.iter().position(|n| n == want).ok_or_else(|| {
            InputError::file(
                path,
                format!(
                    "the header has no column `{want}`; a response file has [{}] (as `cierva frequency-response --format csv` writes it)",
                    RESPONSE_COLUMNS.join(", ")
                ),
            )
        })?;
    }
    let mut out: Vec<Point> = Vec::new();
    for (i, line) in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let mut v = [None; 4];
        for (k, &col) in index.iter().enumerate() {
            let cell = cells.get(col).map_or("", |c| c.trim());
            let column = crate::inputs::yaml::csv_field_column(line, col.min(cells.len()));
            if cell.is_empty() {
                if k == 0 || k == 3 {
                    return Err(at(
                        i + 1,
                        column,
                        RESPONSE_COLUMNS[k],
                        "empty: every row needs a frequency and a coherence".into(),
                    ));
                }
                continue;
            }
            let x: f64 = cell.parse().map_err(|_| {
                at(
                    i + 1,
                    column,
                    RESPONSE_COLUMNS[k],
                    format!("`{cell}` is not a number"),
                )
            })?;
            let ok = match k {
                0 => x.is_finite() && x > 0.0,
                3 => (0.0..=1.0).contains(&x),
                _ => x.is_finite(),
            };
            if !ok {
                let want = match k {
                    0 => "a positive frequency",
                    3 => "a coherence in [0, 1]",
                    _ => "a finite number",
                };
                return Err(at(
                    i + 1,
                    column,
                    RESPONSE_COLUMNS[k],
                    format!("{x} is not {want}"),
                ));
            }
            v[k] = Some(x);
        }
        let (Some(f), Some(g)) = (v[0], v[3]) else {
            continue;
        };
        if let Some(last) = out.last()
            && f <= last.frequency_hz
        {
            return Err(at(
                i + 1,
                crate::inputs::yaml::csv_field_column(line, index[0]),
                "frequency_hz",
                format!(
                    "{f} Hz after {} Hz: frequencies must rise",
                    last.frequency_hz
                ),
            ));
        }
        if let (Some(db), Some(deg)) = (v[1], v[2]) {
            out.push(Point {
                frequency_hz: f,
                response: C::from_polar(10f64.powf(db / 20.0), deg.to_radians()),
                coherence: g,
            });
        }
    }
    if out.is_empty() {
        return Err(InputError::file(
            path,
            "no row has a magnitude and a phase: nothing to compare",
        ));
    }
    Ok(out)
}

impl Evaluate for FrequencyResponseCheck {
    fn input_notes(&self) -> Vec<(std::path::PathBuf, String)> {
        match &self.source {
            Source::Records { notes, .. } => notes.clone(),
            Source::File(_) => Vec::new(),
        }
    }

    fn quantities(&self) -> Vec<String> {
        super::names(crate::inputs::quantity::FREQUENCY_RESPONSE)
    }

    fn condition(&self) -> Option<crate::inputs::condition::TrimRequest> {
        self.condition
    }

    /// Its mismatch cost is zero for a perfect fit: a model with no response stands in.
    fn zero_predicts(&self, _quantity: &str) -> bool {
        false
    }

    /// A model with no response (infinitely costly wherever the reference has a band) and a
    /// pure gain: the reference's mean magnitude in dB over the band, at zero phase.
    fn trivial(
        &self,
        _subject: &Subject,
        _expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        let band: Vec<&Point> = self
            .reference
            .iter()
            .filter(|p| p.coherence >= COHERENCE_MIN)
            .collect();
        if band.is_empty() {
            // Inconclusive at every evaluation: nothing passes it.
            return Ok(vec![]);
        }
        let zero = vec![C::new(0.0, 0.0); self.reference.len()];
        let mean_db = band
            .iter()
            .map(|p| 20.0 * p.response.norm().log10())
            .sum::<f64>()
            / band.len() as f64;
        let gain = vec![C::new(10f64.powf(mean_db / 20.0), 0.0); self.reference.len()];
        let name = Q::MismatchCost.name();
        let mut out = Vec::new();
        for (model, who) in [
            (zero, "a model with no response"),
            (
                gain,
                "a pure gain (the reference's mean magnitude, zero phase)",
            ),
        ] {
            if let Some(c) = mismatch_cost(&self.reference, &model) {
                out.push(Trivial::value(name, c.j, who));
            }
        }
        Ok(out)
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let frequencies: Vec<f64> = self.reference.iter().map(|p| p.frequency_hz).collect();
        let (model, note) = self.model_response(at.subject, &frequencies)?;
        let plot = Some(PlotData::FrequencyResponse {
            title: format!("{} / {}", self.output, self.input),
            frequencies_hz: frequencies.clone(),
            reference: self.reference.iter().map(|p| p.response).collect(),
            coherence: self.reference.iter().map(|p| p.coherence).collect(),
            model: model.clone(),
        });
        let Some(cost) = mismatch_cost(&self.reference, &model) else {
            let best = self
                .reference
                .iter()
                .max_by(|a, b| a.coherence.total_cmp(&b.coherence));
            return Ok(Evaluated {
                finding: Some(Finding::Inconclusive {
                    reason: format!(
                        "coherence: below {COHERENCE_MIN} at every one of the reference's {} frequencies{}",
                        self.reference.len(),
                        best.map_or(String::new(), |p| format!(
                            " (largest {:.3} at {:.3} Hz)",
                            p.coherence, p.frequency_hz
                        ))
                    ),
                }),
                note: Some(note),
                plot,
                ..Evaluated::default()
            });
        };
        Ok(Evaluated {
            fingerprint: vec![
                ("band_low_hz".into(), cost.band_low_hz),
                ("band_high_hz".into(), cost.band_high_hz),
                ("frequencies_in_band".into(), cost.frequencies as f64),
            ],
            note: Some(format!(
                "{} / {}: J {:.2} over {} frequencies, {:.3}-{:.3} Hz (coherence >= {COHERENCE_MIN}); {note}",
                self.output,
                self.input,
                cost.j,
                cost.frequencies,
                cost.band_low_hz,
                cost.band_high_hz
            )),
            plot,
            ..Evaluated::of(compare_all(
                expectations,
                &[(Q::MismatchCost.name(), cost.j)],
            )?)
        })
    }
}

impl FrequencyResponseCheck {
    /// The model's response at each frequency, and which model gave it, in words.
    pub fn model_response(
        &self,
        subject: &Subject,
        frequencies_hz: &[f64],
    ) -> Result<(Vec<C>, String), String> {
        let (responses, from) = match subject {
            Subject::Linear { model, .. } => {
                let from = "the model's response from its own A and B".to_string();
                (
                    crate::run::responses::Responses::of_linear_model(
                        model,
                        frequencies_hz,
                        from.clone(),
                    )?,
                    from,
                )
            }
            _ => {
                let (model, loading) = super::flight_model(subject).ok_or(
                    "a frequency_response check needs a linear model, an aircraft or an external model",
                )?;
                let condition = self
                    .condition
                    .ok_or("a flight model's frequency_response check needs its condition")?;
                let responses = model.responses(
                    &crate::external::Request::at(condition, loading),
                    frequencies_hz,
                )?;
                let from = format!(
                    "the model's response at {} mph: {}",
                    condition.airspeed_mph, responses.from
                );
                (responses, from)
            }
        };
        let response = frequencies_hz
            .iter()
            .map(|f| responses.at(&self.input, &self.output, *f))
            .collect::<Result<Vec<_>, _>>()?;
        Ok((response, from))
    }
}
