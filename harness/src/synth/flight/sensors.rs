//! The flight-test instrumentation: where the air-data probe is, and each channel's noise, bias
//! and lag.
//!
//! A sensors file (`--sensors FILE`) overrides any of the defaults, each value with a source:
//!
//! ```yaml
//! id: vpm-m16-nose-boom            # equals the file stem
//! title: VPM M16 flight-test instrumentation
//! probe_from_cg_m: [1.8, 0.0, -0.3]   # body axes (x forward, y starboard, z down)
//! channels:
//!   alpha_vane_rad: {noise: 0.0035, lag_s: 0.03}
//! sources:
//!   probe_from_cg_m: "estimated: ..."
//!   channels.alpha_vane_rad: "..."   # or channels.alpha_vane_rad.noise, for one value
//! ```
//!
//! A channel is measured as `lag(truth) + bias + noise`: a first-order lag of time constant
//! `lag_s` (the anti-aliasing filter, exact for samples held over an interval), a constant bias,
//! and seeded Gaussian noise of standard deviation `noise`, all in the channel's units.
//! `controls_percent` applies to every control channel (`eta_*_percent`); a teetering rotor's
//! hub speeds take the airspeed's sensor, and its azimuth is exact (a once-per-revolution
//! pulse). A file written before the spelling was made one (issue 34) names it `controls_pct`,
//! read as `controls_percent` (under `channels` and in `sources`), as a record's `_pct`
//! channels are ([`crate::inputs::record::current_name`]).

use crate::inputs::record::current_name;
use crate::inputs::yaml::{self, InputError};
use crate::synth::linear::Normal;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// One channel's sensor.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Channel {
    /// Standard deviation of the noise, channel units.
    pub noise: f64,
    pub bias: f64,
    /// First-order lag, s (0: none).
    pub lag_s: f64,
}

/// The channels a sensors file may name (as in the record; `controls_percent` for all
/// controls).
pub const CHANNELS: [&str; 11] = [
    "airspeed_m_s",
    "alpha_vane_rad",
    "beta_vane_rad",
    "p_rad_s",
    "q_rad_s",
    "r_rad_s",
    "phi_rad",
    "theta_rad",
    "omega_rotor_rad_s",
    "controls_percent",
    "teeter_rad",
];

const ANTI_ALIAS: &str = "estimated: seed 000 Sec. II says anti-aliasing filters were fitted but not their corner; a first-order lag of 0.02 s (an 8 Hz corner) suits sampling at 100 Hz";

/// The defaults: `(channel, noise, bias, lag_s, source of the noise)`. Seed 000 Sec. II names
/// the sensors (a nose boom with vanes, an inertial unit for the rates, a vertical gyro for the
/// attitudes, potentiometers on the controls, a rotorspeed pick-up) but not their accuracy.
const DEFAULTS: [(&str, f64, f64, f64, &str); 11] = [
    (
        "airspeed_m_s",
        0.15,
        0.0,
        0.02,
        "estimated: a boom's airspeed at 1 % of full scale (15 m/s-scale pressure transducer noise, 0.15 m/s)",
    ),
    (
        "alpha_vane_rad",
        0.001_745,
        0.0,
        0.02,
        "estimated: a vane's resolution and buffeting, 0.1 deg",
    ),
    (
        "beta_vane_rad",
        0.001_745,
        0.0,
        0.02,
        "estimated: a vane's resolution and buffeting, 0.1 deg",
    ),
    (
        "p_rad_s",
        0.000_873,
        0.0,
        0.02,
        "estimated: a tactical-grade rate gyro's noise, 0.05 deg/s",
    ),
    (
        "q_rad_s",
        0.000_873,
        0.0,
        0.02,
        "estimated: a tactical-grade rate gyro's noise, 0.05 deg/s",
    ),
    (
        "r_rad_s",
        0.000_873,
        0.0,
        0.02,
        "estimated: a tactical-grade rate gyro's noise, 0.05 deg/s",
    ),
    (
        "phi_rad",
        0.000_873,
        0.0,
        0.02,
        "estimated: a vertical gyro's noise, 0.05 deg",
    ),
    (
        "theta_rad",
        0.000_873,
        0.0,
        0.02,
        "estimated: a vertical gyro's noise, 0.05 deg",
    ),
    (
        "omega_rotor_rad_s",
        0.05,
        0.0,
        0.02,
        "estimated: a once-per-revolution pick-up's speed, 0.5 rpm",
    ),
    (
        "controls_percent",
        0.05,
        0.0,
        0.02,
        "estimated: a potentiometer's noise, 0.05 % of travel",
    ),
    (
        "teeter_rad",
        0.000_873,
        0.0,
        0.0,
        "estimated: a teeter-angle potentiometer's noise, 0.05 deg, sampled without a lag (seed 003 reads the disc's tilt from the 1/rev signal's phase, which a 0.02 s lag would turn by 40 deg)",
    ),
];

/// The air-data probe's default position from the centre of mass, and its source.
const PROBE: ([f64; 3], &str) = (
    [1.8, 0.0, -0.3],
    "estimated: seed 000 Sec. II fits a nose-mounted air-data probe to the VPM M16; its position is not published (1.8 m ahead of and 0.3 m above the c.g., the nose of a 4.7 m airframe)",
);

/// The instrumentation, with the source of every value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Instrumentation {
    /// Where it came from: `defaults`, or the sensors file's id.
    pub id: String,
    pub title: String,
    /// The air-data probe from the centre of mass, body axes, m.
    pub probe_from_cg_m: [f64; 3],
    pub channels: BTreeMap<String, Channel>,
    /// Source of each value (`probe_from_cg_m`, `channels.<name>`).
    pub sources: BTreeMap<String, String>,
}

impl Default for Instrumentation {
    fn default() -> Self {
        let mut channels = BTreeMap::new();
        let mut sources = BTreeMap::new();
        for (name, noise, bias, lag_s, source) in DEFAULTS {
            channels.insert(name.to_string(), Channel { noise, bias, lag_s });
            let lag = if lag_s > 0.0 {
                format!("lag {ANTI_ALIAS}")
            } else {
                "no lag".to_string()
            };
            sources.insert(
                format!("channels.{name}"),
                format!("{source}; no bias; {lag}"),
            );
        }
        sources.insert("probe_from_cg_m".into(), PROBE.1.into());
        Self {
            id: "defaults".into(),
            title: "cierva's default flight-test instrumentation (estimated)".into(),
            probe_from_cg_m: PROBE.0,
            channels,
            sources,
        }
    }
}

/// A sensors file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct SensorsFile {
    id: String,
    title: String,
    #[serde(default)]
    probe_from_cg_m: Option<[f64; 3]>,
    #[serde(default)]
    channels: BTreeMap<String, ChannelSpec>,
    #[serde(default)]
    sources: BTreeMap<String, String>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct ChannelSpec {
    noise: Option<f64>,
    bias: Option<f64>,
    lag_s: Option<f64>,
}

impl Instrumentation {
    /// The defaults with a sensors file's values over them. Every value given needs a source
    /// (its own dotted path, or its channel's); a channel must be one of [`CHANNELS`].
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let src = yaml::read(path)?;
        let f: SensorsFile = yaml::parse(path, &src)?;
        crate::inputs::reference::check_id(path, &src, &f.id)?;
        let sources = current_sources(path, &src, &f.sources)?;
        let mut out = Self {
            id: f.id.clone(),
            title: f.title.clone(),
            ..Self::default()
        };
        let sourced = |key: &str| -> Option<&String> {
            let mut k = key.to_string();
            loop {
                if let Some(s) = sources.get(&k) {
                    return Some(s);
                }
                match k.rfind('.') {
                    Some(i) => k.truncate(i),
                    None => return None,
                }
            }
        };
        // `key` in today's spelling, `written` as the file has it (where an error points).
        let need_source = |key: &str, written: &str| {
            sourced(key).cloned().ok_or_else(|| {
                InputError::field(
                    path,
                    &src,
                    written,
                    format!("`{written}` has no entry under `sources` (every value needs one)"),
                )
            })
        };
        if let Some(p) = f.probe_from_cg_m {
            if !p.iter().all(|v| v.is_finite()) {
                return Err(InputError::field(
                    path,
                    &src,
                    "probe_from_cg_m",
                    "must be finite",
                ));
            }
            out.sources.insert(
                "probe_from_cg_m".into(),
                need_source("probe_from_cg_m", "probe_from_cg_m")?,
            );
            out.probe_from_cg_m = p;
        }
        for (as_written, spec) in &f.channels {
            let name = &current_name(as_written);
            // Where the file has it (errors point there), and its key in today's spelling.
            let written = format!("channels.{as_written}");
            if name != as_written && f.channels.contains_key(name) {
                return Err(old_and_new(
                    path,
                    &src,
                    &written,
                    as_written,
                    name,
                    "`channels`",
                ));
            }
            let key = format!("channels.{name}");
            if !CHANNELS.contains(&name.as_str()) {
                let names: Vec<String> = CHANNELS.iter().map(|c| c.to_string()).collect();
                let hint = yaml::nearest(name, &names)
                    .map(|c| format!("; did you mean `{c}`?"))
                    .unwrap_or_default();
                return Err(InputError::field(
                    path,
                    &src,
                    &written,
                    format!("unknown channel `{name}`{hint}"),
                ));
            }
            let ch = out.channels.get_mut(name).expect("a known channel");
            let mut said = Vec::new();
            for (field, value, slot) in [
                ("noise", spec.noise, &mut ch.noise),
                ("bias", spec.bias, &mut ch.bias),
                ("lag_s", spec.lag_s, &mut ch.lag_s),
            ] {
                let Some(v) = value else { continue };
                let at = format!("{written}.{field}");
                let ok = v.is_finite() && (field == "bias" || v >= 0.0);
                if !ok {
                    return Err(InputError::field(
                        path,
                        &src,
                        &at,
                        if field == "bias" {
                            "must be finite"
                        } else {
                            "must be finite and not negative"
                        },
                    ));
                }
                said.push(format!(
                    "{field} {v}: {}",
                    need_source(&format!("{key}.{field}"), &at)?
                ));
                *slot = v;
            }
            if !said.is_empty() {
                let before = out.sources.get(&key).cloned().unwrap_or_default();
                out.sources.insert(
                    key,
                    format!("{} (defaults otherwise: {before})", said.join("; ")),
                );
            }
        }
        Ok(out)
    }

    /// The sensor of a record channel: `eta_*_percent` use `controls_percent`; the hub's speeds
    /// are derived from the air data, so they take the airspeed's sensor; the rotor's azimuth
    /// comes from a once-per-revolution pulse, exact.
    pub fn channel(&self, name: &str) -> Option<Channel> {
        let key = match name {
            n if n.ends_with(crate::inputs::record::PERCENT) => "controls_percent",
            "hub_inplane_speed_m_s" | "hub_normal_speed_m_s" => "airspeed_m_s",
            "azimuth_from_front_rad" => {
                return Some(Channel {
                    noise: 0.0,
                    bias: 0.0,
                    lag_s: 0.0,
                });
            }
            n => n,
        };
        self.channels.get(key).copied()
    }
}

/// One channel under its old name (at `field`) and its new one, both in `within`.
fn old_and_new(
    path: &Path,
    src: &str,
    field: &str,
    old: &str,
    new: &str,
    within: &str,
) -> InputError {
    InputError::field(
        path,
        src,
        field,
        format!(
            "`{old}` is the old name of `{new}`, which {within} gives as well: keep one (`{new}`)"
        ),
    )
}

/// The `sources` with their channels in today's spelling (`channels.controls_pct.noise` ->
/// `channels.controls_percent.noise`); a source given under both names is an error.
fn current_sources(
    path: &Path,
    src: &str,
    sources: &BTreeMap<String, String>,
) -> Result<BTreeMap<String, String>, InputError> {
    let mut out = BTreeMap::new();
    for (key, value) in sources {
        let current = match key.split_once('.') {
            Some(("channels", rest)) => {
                let (channel, tail) = rest.split_once('.').unwrap_or((rest, ""));
                let name = current_name(channel);
                let current = if tail.is_empty() {
                    format!("channels.{name}")
                } else {
                    format!("channels.{name}.{tail}")
                };
                if current != *key && sources.contains_key(&current) {
                    let at = format!("sources.{key}");
                    return Err(old_and_new(path, src, &at, key, &current, "`sources`"));
                }
                current
            }
            _ => key.clone(),
        };
        out.insert(current, value.clone());
    }
    Ok(out)
}

impl Channel {
    /// The measurement of a true signal sampled every `dt_s`: lagged, biased and noisy.
    pub fn measure(&self, truth: &[f64], dt_s: f64, rng: &mut Normal) -> Vec<f64> {
        let gain = if self.lag_s > 0.0 {
            1.0 - (-dt_s / self.lag_s).exp()
        } else {
            1.0
        };
        let mut y = truth.first().copied().unwrap_or(0.0);
        truth
            .iter()
            .map(|&x| {
                y += gain * (x - y);
                y + self.bias + self.noise * rng.sample()
            })
            .collect()
    }
}
