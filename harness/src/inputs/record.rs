//! Flight records: a CSV of named channels, units in the names, and a YAML sidecar.
//!
//! `RECORD.csv` starts with a header of channel names carrying their units
//! (`time_s,airspeed_m_s,alpha_vane_rad,...`) followed by one row per sample. Required channels
//! are [`REQUIRED`] plus the controls named in the sidecar; others are kept as they are (or
//! left out where they are not numbers). A column may be named otherwise and mapped by the
//! sidecar's `channels:`, and a required channel may come in another unit (`theta_deg` for
//! `theta_rad`): [`crate::inputs::channels`] converts it.
//!
//! `RECORD.yaml`, beside it:
//!
//! ```yaml
//! id: synthetic-vpm-m16-sweep          # equals the file stem
//! title: ...
//! provenance: {source: "synthetic: cierva synth ..."}
//! synthetic: {generator: "cierva synth 0.1.0", seed: 42, truth: "../flight-refs/..."}  # synthetic only
//! aircraft: VPM M16
//! sample_rate_hz: 100
//! sensors:                              # body axes (x forward, y starboard, z down) from a datum
//!   probe_position_m: [2.0, 0.0, -0.3]  # the air-data vanes
//!   cg_position_m: [0.0, 0.0, 0.0]
//! condition: {airspeed_kn: 60}          # free-form, keys with units
//! channels: {PITCH: theta_deg}           # optional: a column's cierva name, its unit the suffix
//! trim: {u_m_s: 30.8, w_m_s: 0.0, theta_rad: 0.0, omega_rotor_rad_s: 38.0, eta_s_rad: 0.0}
//! controls: [eta_s_rad]
//! excitation: {eta_s_rad: sweep_command_v}  # optional: the column recording what an
//!                                           # excitation system added to the control
//! ```
//!
//! A control in % of travel is `<control>_percent` (`eta_s_percent`). Records written before
//! the spelling was made one (issue 34) have `<control>_pct`: [`load_with`] reads any channel,
//! control or trim value named `<x>_pct` as `<x>_percent` ([`current_name`]), so nothing past
//! the reader sees the old spelling, and a record that names one channel both ways is a
//! located error.

use crate::inputs::reference::{Provenance, check_id};
use crate::inputs::yaml::{self, InputError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Channels every record must have.
pub const REQUIRED: [&str; 10] = [
    "time_s",
    "airspeed_m_s",
    "alpha_vane_rad",
    "beta_vane_rad",
    "p_rad_s",
    "q_rad_s",
    "r_rad_s",
    "phi_rad",
    "theta_rad",
    "omega_rotor_rad_s",
];

/// The unit suffix of a channel in % (a control's travel): `eta_s_percent`.
pub const PERCENT: &str = "_percent";

/// The old spelling of [`PERCENT`], read as it on load.
const OLD_PERCENT: &str = "_pct";

/// A channel's name as cierva spells it: `<x>_pct` (the old spelling) is `<x>_percent`; any
/// other name is itself.
pub fn current_name(name: &str) -> String {
    match name.strip_suffix(OLD_PERCENT) {
        Some(stem) if !stem.is_empty() => format!("{stem}{PERCENT}"),
        _ => name.to_string(),
    }
}

/// Where the sensors are.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Sensors {
    pub probe_position_m: [f64; 3],
    pub cg_position_m: [f64; 3],
}

/// How a synthetic record was made.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Synthetic {
    pub generator: String,
    pub seed: u64,
    /// The model that flew (a path, relative to the sidecar, or a description).
    pub truth: String,
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub settings: BTreeMap<String, String>,
}

/// The sidecar.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RecordMeta {
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub synthetic: Option<Synthetic>,
    pub aircraft: String,
    pub sample_rate_hz: f64,
    /// Air-data probe and c.g. positions (flight records for identification need them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensors: Option<Sensors>,
    #[serde(default)]
    pub condition: BTreeMap<String, serde_yaml::Value>,
    /// Trim values of channels or derived states (`u_m_s`, `w_m_s`, `theta_rad`, ...).
    #[serde(default)]
    pub trim: BTreeMap<String, f64>,
    #[serde(default)]
    pub controls: Vec<String>,
    /// Columns as written in the CSV mapped to cierva's channel names, with their units as the
    /// names' suffixes ([`crate::inputs::channels`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub channels: BTreeMap<String, String>,
    /// Controls logged in their own unit, by control (`eta_s`): their travel, and whether the
    /// columns are positions or changes from trim ([`crate::inputs::channels::Travel`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub travel: BTreeMap<String, crate::inputs::channels::Travel>,
    /// The excitation added to a control, by the control's channel (`eta_s_percent`): the
    /// channel that records it, in any unit (a response estimated against it does not depend on
    /// its scale). A computer-generated input summed with the pilot's command is recorded so; a
    /// pilot's own sweep has none. Where each record at a condition names one, `cierva retune`
    /// estimates the responses against it, unbiased by the pilot's loops
    /// ([`crate::ident::frequency_response::referenced`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub excitation: BTreeMap<String, String>,
}

/// A loaded, checked record.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub path: PathBuf,
    pub meta: RecordMeta,
    pub channels: Vec<String>,
    /// One vector per channel, in `channels` order.
    pub data: Vec<Vec<f64>>,
    /// What the load mapped, converted or left out, in words (empty for a record in cierva's
    /// own names and units).
    pub notes: Vec<String>,
}

impl Record {
    /// The samples of a channel.
    pub fn channel(&self, name: &str) -> Option<&[f64]> {
        self.channels
            .iter()
            .position(|c| c == name)
            .map(|i| self.data[i].as_slice())
    }

    /// The time step, s.
    pub fn dt_s(&self) -> f64 {
        1.0 / self.meta.sample_rate_hz
    }

    /// Duration from the first to the last sample, s.
    pub fn duration_s(&self) -> f64 {
        let t = self.channel("time_s").unwrap_or(&[]);
        match (t.first(), t.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }
}

/// The sidecar of a CSV record: same path, `.yaml`.
pub fn sidecar_path(csv: &Path) -> PathBuf {
    csv.with_extension("yaml")
}

/// Relative tolerance on the time step.
const DT_TOLERANCE: f64 = 0.01;

/// Loads a flight record for identification (the [`REQUIRED`] channels, the sidecar's controls
/// and its sensor positions) and checks everything a real record gets wrong.
pub fn load(csv_path: &Path) -> Result<Record, InputError> {
    let r = load_with(csv_path, &REQUIRED, true)?;
    if r.meta.sensors.is_none() {
        let side = sidecar_path(csv_path);
        let src = yaml::read(&side)?;
        return Err(InputError::field(
            &side,
            &src,
            "sensors",
            "identification needs the probe and c.g. positions under `sensors`",
        ));
    }
    Ok(r)
}

/// Loads a record that must have the given channels (and the sidecar's controls when
/// `with_controls`), with the same checks.
pub fn load_with(
    csv_path: &Path,
    required: &[&str],
    with_controls: bool,
) -> Result<Record, InputError> {
    load_using(csv_path, required, with_controls, &[])
}

/// [`load_with`], with channels the caller uses where the record has them (`used`: a time
/// history's responses), converted to their units as the required ones are.
pub fn load_using(
    csv_path: &Path,
    required: &[&str],
    with_controls: bool,
    used: &[&str],
) -> Result<Record, InputError> {
    let side = sidecar_path(csv_path);
    let side_src = yaml::read(&side)?;
    let mut meta: RecordMeta = yaml::parse(&side, &side_src)?;
    check_id(&side, &side_src, &meta.id)?;
    current_names_of_sidecar(&side, &side_src, &mut meta)?;
    if !(meta.sample_rate_hz.is_finite()
        && meta.sample_rate_hz > 0.0
        && (1.0 / meta.sample_rate_hz).is_finite())
    {
        return Err(InputError::field(
            &side,
            &side_src,
            "sample_rate_hz",
            format!(
                "must be a positive number whose time step (1 / rate) is finite, got {:e} Hz",
                meta.sample_rate_hz
            ),
        ));
    }
    if let Some((name, v)) = meta.trim.iter().find(|(_, v)| !v.is_finite()) {
        return Err(InputError::field(
            &side,
            &side_src,
            &format!("trim.{name}"),
            format!("must be a finite number, got {v}"),
        ));
    }
    check_travel(&side, &side_src, &mut meta)?;
    let src = yaml::read_csv(csv_path)?;
    let mut lines = src
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines
        .next()
        .ok_or_else(|| InputError::file(csv_path, "the file is empty"))?;
    let written = current_names_of_header(csv_path, header)?;
    let controls: &[String] = if with_controls { &meta.controls } else { &[] };
    // Time is every record's axis, whoever asks.
    let needed: Vec<&str> = std::iter::once("time_s")
        .chain(required.iter().copied().filter(|c| *c != "time_s"))
        .chain(controls.iter().map(String::as_str))
        .collect();
    let excitations: Vec<&str> = meta.excitation.values().map(String::as_str).collect();
    let wanted: Vec<&str> = needed
        .iter()
        .chain(used)
        .chain(&excitations)
        .copied()
        .collect();
    let plan = crate::inputs::channels::plan(&written, &meta.channels, &meta.travel, &wanted)
        .map_err(|(field, m)| InputError::field(&side, &side_src, &field, m))?;
    let mut channels = plan.names;
    let mut notes = plan.notes;
    check_excitation(&side, &side_src, &meta, &channels, csv_path)?;
    let needed: Vec<&str> = needed.into_iter().chain(excitations).collect();
    check_channels(csv_path, &channels, &needed)?;
    let (mut data, left_out) = samples(csv_path, lines, &channels, &needed)?;
    for (k, factor) in plan.factors.iter().enumerate() {
        if let Some(f) = factor {
            let offset = plan.offsets[k];
            data[k].iter_mut().for_each(|x| *x = *x * f + offset);
        }
    }
    for (k, why) in left_out.into_iter().enumerate().rev() {
        if let Some(why) = why {
            notes.push(format!("column `{}` left out: {why}", channels[k]));
            channels.remove(k);
            data.remove(k);
        }
    }
    let t = &data[channels
        .iter()
        .position(|c| c == "time_s")
        .expect("checked")];
    check_time(csv_path, t, meta.sample_rate_hz)?;
    Ok(Record {
        path: csv_path.to_path_buf(),
        meta,
        channels,
        data,
        notes,
    })
}

/// The sidecar's `field` names `control`, which is none of the record's `controls`.
fn not_a_control(
    side: &Path,
    src: &str,
    field: &str,
    control: &str,
    controls: &[String],
) -> InputError {
    let hint = yaml::nearest(control, controls)
        .map(|n| format!(" (did you mean `{n}`?)"))
        .unwrap_or_default();
    InputError::field(
        side,
        src,
        field,
        format!(
            "`{control}` is not a control of this record{hint}: `controls:` lists {}",
            if controls.is_empty() {
                "none".to_string()
            } else {
                format!("`{}`", controls.join("`, `"))
            }
        ),
    )
}

/// A sidecar's `excitation:` checked against the record's controls and channels: each key a
/// control the sidecar lists, each value a channel of the CSV.
fn check_excitation(
    side: &Path,
    src: &str,
    meta: &RecordMeta,
    channels: &[String],
    csv_path: &Path,
) -> Result<(), InputError> {
    for (control, column) in &meta.excitation {
        let field = format!("excitation.{control}");
        if !meta.controls.contains(control) {
            return Err(not_a_control(side, src, &field, control, &meta.controls));
        }
        if !channels.contains(column) {
            let hint = yaml::nearest(column, channels)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(InputError::field(
                side,
                src,
                &field,
                format!("no channel `{column}` in {}{hint}", csv_path.display()),
            ));
        }
        if let Some((other, _)) = meta
            .excitation
            .iter()
            .find(|(c, v)| *v == column && *c != control)
        {
            return Err(InputError::field(
                side,
                src,
                &field,
                format!(
                    "`{column}` is named for `{other}` too: each excited control's excitation is a channel of its own"
                ),
            ));
        }
        if column == "time_s" || REQUIRED.contains(&column.as_str()) {
            return Err(InputError::field(
                side,
                src,
                &field,
                format!(
                    "`{column}` is a measured channel: the excitation is the signal an excitation system added to `{control}`, recorded in a channel of its own"
                ),
            ));
        }
        if meta.controls.contains(column) {
            return Err(InputError::field(
                side,
                src,
                &field,
                format!(
                    "`{column}` is a control: the excitation is the signal added to `{control}` (an excitation system's command), recorded in a channel of its own"
                ),
            ));
        }
    }
    Ok(())
}

/// A sidecar's `travel:` checked, and its trim values in a control's own unit taken to % of
/// travel (a trim value is a position). Each control must be one the record lists, its travel
/// well formed, and its trim given once.
fn check_travel(side: &Path, src: &str, meta: &mut RecordMeta) -> Result<(), InputError> {
    let controls: Vec<String> = meta
        .controls
        .iter()
        .filter_map(|c| c.strip_suffix(PERCENT).map(str::to_string))
        .collect();
    for (control, t) in &meta.travel {
        let field = format!("travel.{control}");
        if !controls.contains(control) {
            return Err(not_a_control(side, src, &field, control, &controls));
        }
        if let Some(problem) = t.problem() {
            return Err(InputError::field(side, src, &field, problem));
        }
        let own = format!("{control}_{}", t.unit);
        if let Some(x) = meta.trim.remove(&own) {
            let percent = format!("{control}{PERCENT}");
            if meta.trim.contains_key(&percent) {
                return Err(InputError::field(
                    side,
                    src,
                    &format!("trim.{own}"),
                    format!("the trim gives `{percent}` too: give the control's trim once"),
                ));
            }
            meta.trim.insert(percent, t.position_percent(x));
        }
    }
    Ok(())
}

/// The header's channel names in today's spelling ([`current_name`]); two columns that are one
/// channel spelled both ways are an error at the second.
fn current_names_of_header(csv_path: &Path, header: &str) -> Result<Vec<String>, InputError> {
    let written: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut channels: Vec<String> = Vec::with_capacity(written.len());
    for (k, w) in written.iter().enumerate() {
        let name = current_name(w);
        if let Some(i) = channels.iter().position(|c| *c == name)
            && written[i] != *w
        {
            return Err(at_field(
                csv_path,
                1,
                header,
                k,
                format!(
                    "channels `{}` (column {}) and `{w}` (column {}) are one channel, `{name}` (`{OLD_PERCENT}` is the old spelling of `{PERCENT}`): keep one",
                    written[i],
                    i + 1,
                    k + 1
                ),
            ));
        }
        channels.push(name);
    }
    Ok(channels)
}

/// The sidecar's `controls` and `trim` names in today's spelling ([`current_name`]); one
/// channel named both ways is an error (in `controls` at the second name, in `trim` at the old
/// one).
fn current_names_of_sidecar(
    side: &Path,
    src: &str,
    meta: &mut RecordMeta,
) -> Result<(), InputError> {
    let clash = |field: String, old: &str, new: &str| {
        InputError::field(
            side,
            src,
            &field,
            format!(
                "`{old}` and `{new}` are one channel (`{OLD_PERCENT}` is the old spelling of `{PERCENT}`): keep one"
            ),
        )
    };
    let mut controls: Vec<String> = Vec::with_capacity(meta.controls.len());
    for (k, c) in meta.controls.iter().enumerate() {
        let name = current_name(c);
        if let Some(i) = controls.iter().position(|d| *d == name)
            && meta.controls[i] != *c
        {
            let (old, new) = if c.ends_with(OLD_PERCENT) {
                (c, &meta.controls[i])
            } else {
                (&meta.controls[i], c)
            };
            return Err(clash(format!("controls[{k}]"), old, new));
        }
        controls.push(name);
    }
    meta.controls = controls;
    let mut trim = BTreeMap::new();
    for (key, value) in &meta.trim {
        let name = current_name(key);
        if name != *key && meta.trim.contains_key(&name) {
            return Err(clash(format!("trim.{key}"), key, &name));
        }
        trim.insert(name, *value);
    }
    meta.trim = trim;
    let mut excitation = BTreeMap::new();
    for (key, value) in &meta.excitation {
        let name = current_name(key);
        if name != *key && meta.excitation.contains_key(&name) {
            return Err(clash(format!("excitation.{key}"), key, &name));
        }
        excitation.insert(name, current_name(value));
    }
    meta.excitation = excitation;
    Ok(())
}

/// An error at a line of a CSV record.
pub(crate) fn at(csv_path: &Path, line: usize, msg: String) -> InputError {
    InputError {
        path: csv_path.to_path_buf(),
        line: Some(line),
        column: None,
        field: None,
        message: msg,
    }
}

/// The same, with the caret under the `k`-th comma-separated field of `text`.
pub(crate) fn at_field(
    csv_path: &Path,
    line: usize,
    text: &str,
    k: usize,
    msg: String,
) -> InputError {
    let mut e = at(csv_path, line, msg);
    e.column = Some(crate::inputs::yaml::csv_field_column(text, k));
    e
}

/// The header's channels checked: each named, none twice, and every `needed` one there (a
/// missing one named with the unneeded channel nearest it, as a misnamed channel, or with its
/// new spelling when it is asked for in the old).
fn check_channels(csv_path: &Path, channels: &[String], needed: &[&str]) -> Result<(), InputError> {
    for (i, c) in channels.iter().enumerate() {
        if c.is_empty() {
            return Err(at(csv_path, 1, format!("column {} has no name", i + 1)));
        }
        if channels[..i].contains(c) {
            return Err(at(csv_path, 1, format!("channel `{c}` appears twice")));
        }
    }
    // A misnamed channel is one the record has but does not need.
    let unexpected: Vec<String> = channels
        .iter()
        .filter(|c| !needed.contains(&c.as_str()))
        .cloned()
        .collect();
    for need in needed {
        if !channels.iter().any(|c| c == need) {
            // Asked for in the old spelling (a command line from before the rename).
            let current = current_name(need);
            let hint = if current != *need && channels.contains(&current) {
                format!(
                    "; `{current}` is there (`{OLD_PERCENT}` is the old spelling of `{PERCENT}`): ask for `{current}`"
                )
            } else {
                crate::inputs::yaml::nearest(need, &unexpected)
                    .map(|c| format!("; `{c}` is there: misnamed, or in other units?"))
                    .unwrap_or_default()
            };
            return Err(at(
                csv_path,
                1,
                format!("channel `{need}` is missing{hint}"),
            ));
        }
    }
    Ok(())
}

/// The samples of the rows after the header (`(index, line)` pairs), one vector per channel:
/// at most [`crate::inputs::limits::MAX_RECORD_SAMPLES`] rows, each with a finite number for
/// every `needed` channel. A column nobody needs that holds something else (a status word, a
/// gap) is left out, with the first such value and its line: the second vector says which.
#[allow(clippy::type_complexity)]
fn samples<'a>(
    csv_path: &Path,
    lines: impl Iterator<Item = (usize, &'a str)>,
    channels: &[String],
    needed: &[&str],
) -> Result<(Vec<Vec<f64>>, Vec<Option<String>>), InputError> {
    let mut data = vec![Vec::new(); channels.len()];
    let mut left_out: Vec<Option<String>> = vec![None; channels.len()];
    let optional: Vec<bool> = channels
        .iter()
        .map(|c| !needed.contains(&c.as_str()))
        .collect();
    let most = crate::inputs::limits::MAX_RECORD_SAMPLES;
    for (row, (line_no, line)) in lines.enumerate() {
        if row == most {
            return Err(at_field(
                csv_path,
                line_no + 1,
                line,
                0,
                format!(
                    "a record may have at most {most} samples (MAX_RECORD_SAMPLES); this one has more"
                ),
            ));
        }
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != channels.len() {
            return Err(at(
                csv_path,
                line_no + 1,
                format!(
                    "{} values where the header has {} channels",
                    fields.len(),
                    channels.len()
                ),
            ));
        }
        for (k, f) in fields.iter().enumerate() {
            let v = f.trim();
            if left_out[k].is_some() {
                continue;
            }
            if optional[k] {
                match v.parse::<f64>() {
                    Ok(x) if x.is_finite() && crate::inputs::yaml::number(v).is_ok() => {
                        data[k].push(x)
                    }
                    _ => {
                        left_out[k] = Some(format!(
                            "`{v}` at line {} is not a number (no check asks for it)",
                            line_no + 1
                        ))
                    }
                }
                continue;
            }
            let x: f64 = v.parse().map_err(|_| {
                at_field(
                    csv_path,
                    line_no + 1,
                    line,
                    k,
                    if v.is_empty() {
                        format!("channel `{}` has a gap (empty value)", channels[k])
                    } else {
                        format!("channel `{}`: `{v}` is not a number", channels[k])
                    },
                )
            })?;
            if !x.is_finite() {
                return Err(at_field(
                    csv_path,
                    line_no + 1,
                    line,
                    k,
                    format!("channel `{}` is {x}", channels[k]),
                ));
            }
            if let Err(e) = crate::inputs::yaml::number(v) {
                return Err(at_field(
                    csv_path,
                    line_no + 1,
                    line,
                    k,
                    format!("channel `{}`: {e}", channels[k]),
                ));
            }
            data[k].push(x);
        }
    }
    Ok((data, left_out))
}

/// The time channel checked: at least two samples, increasing everywhere, then at the
/// sidecar's sample rate (within [`DT_TOLERANCE`]).
fn check_time(csv_path: &Path, t: &[f64], sample_rate_hz: f64) -> Result<(), InputError> {
    if t.len() < 2 {
        // Where the missing second sample would be (the header is line 1).
        return Err(at(
            csv_path,
            t.len() + 2,
            format!(
                "a record needs at least two samples; it ends after {}",
                t.len()
            ),
        ));
    }
    let dt = 1.0 / sample_rate_hz;
    // Time must increase everywhere (the graver fault) before it is checked for regularity.
    if let Some(k) = (1..t.len()).find(|&k| t[k] <= t[k - 1]) {
        return Err(at(
            csv_path,
            k + 2,
            format!(
                "channel `time_s` does not increase ({} after {})",
                t[k],
                t[k - 1]
            ),
        ));
    }
    for k in 1..t.len() {
        let step = t[k] - t[k - 1];
        if (step - dt).abs() > DT_TOLERANCE * dt {
            return Err(at(
                csv_path,
                k + 2,
                format!(
                    "channel `time_s` is irregular: step {step} s where the sidecar's {} Hz means {dt} s (a gap or a dropped sample?)",
                    sample_rate_hz
                ),
            ));
        }
    }
    Ok(())
}

/// Writes a record (CSV and sidecar).
pub fn write(
    csv_path: &Path,
    meta: &RecordMeta,
    channels: &[String],
    data: &[Vec<f64>],
) -> std::io::Result<()> {
    use std::fmt::Write as _;
    let mut s = channels.join(",");
    s.push('\n');
    let n = data.first().map_or(0, Vec::len);
    for k in 0..n {
        for (i, col) in data.iter().enumerate() {
            if i > 0 {
                s.push(',');
            }
            let _ = write!(s, "{}", col[k]);
        }
        s.push('\n');
    }
    std::fs::write(csv_path, s)?;
    let y = serde_yaml::to_string(meta).map_err(std::io::Error::other)?;
    std::fs::write(sidecar_path(csv_path), y)
}
