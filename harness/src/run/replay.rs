//! Time histories compared with a reference: a record of control changes and responses (flight,
//! or synthetic and labelled so), flown again by the model with the same control changes.
//!
//! # The reference record
//! A record CSV with its sidecar YAML ([`crate::inputs::record`]). Its `controls` (named in the
//! sidecar) are among [`crate::inputs::controls::CONTROL_COLUMNS`]: changes from the trimmed
//! controls, % of travel. Every other channel but `time_s` is a response among [`SIGNALS`]:
//! a change from trim, in the units its name carries. Time starts at the record's first sample.
//!
//! # What the model's "trim" is
//! The linear model starts at zero. The full individual-blade model starts on its periodic
//! orbit, which a two-bladed rotor shakes at 2/rev; its trim values are the means over the first
//! revolution of the orbit flown with the controls held, so the 2/rev content stays in the
//! response, as it does in a flight record.
//!
//! # Metrics
//! For every response: the largest absolute error over the record (FAA Part 60 tolerance
//! bands), the RMS error, and Theil's inequality coefficient
//! `rms(model - ref) / (rms(model) + rms(ref))` (0 is a perfect match, 1 the worst;
//! seed 000 Fig. 10 uses it).

use crate::inputs::condition::Loading;
use crate::inputs::condition::TrimRequest;
use crate::inputs::record::Record;
use cierva_model::aircraft::Aircraft;
use cierva_model::simulation::timehistory::{Sample, TimeHistory};
use serde::{Deserialize, Serialize};

/// Responses a reference record may carry (changes from trim).
pub const SIGNALS: [&str; 10] = [
    "u_m_s",
    "v_m_s",
    "w_m_s",
    "p_deg_s",
    "q_deg_s",
    "r_deg_s",
    "phi_deg",
    "theta_deg",
    "psi_deg",
    "rotor_rpm",
];

/// What a `time_history` check computes per response: `<signal>.<metric>`.
pub const METRICS: [&str; 3] = ["max_abs_error", "rms_error", "theil"];

/// Which model flies the record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Simulation {
    /// The nonlinear individual-blade model, by RK4 at an azimuth step.
    #[default]
    FullBlade,
    /// The model linearised about trim (quasi-steady blades and inflow), by RK4 at the
    /// record's sample interval.
    Linear,
}

/// A flown time history: responses (changes from trim) at regular times from zero.
#[derive(Debug, Clone, PartialEq)]
pub struct Replayed {
    pub time_s: Vec<f64>,
    /// One entry per [`SIGNALS`] name, in that order.
    pub signals: Vec<Vec<f64>>,
}

impl Replayed {
    /// The samples of a response.
    pub fn signal(&self, name: &str) -> Option<&[f64]> {
        SIGNALS
            .iter()
            .position(|s| *s == name)
            .map(|i| self.signals[i].as_slice())
    }
}

/// How to fly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlySettings {
    pub simulation: Simulation,
    /// Samples wanted at `k * sample_s`, `k = 0..=n`.
    pub sample_s: f64,
    pub samples: usize,
    /// Azimuth step of the full model, rad.
    pub azimuth_step_rad: f64,
}

fn responses(b: &[f64; 12], omega_rad_s: f64) -> [f64; 10] {
    let d = f64::to_degrees;
    [
        b[0],
        b[1],
        b[2],
        d(b[3]),
        d(b[4]),
        d(b[5]),
        d(b[6]),
        d(b[7]),
        d(b[8]),
        omega_rad_s * 30.0 / std::f64::consts::PI,
    ]
}

/// Flies the aircraft at a condition with control changes from trim and returns the responses
/// as changes from trim, sampled at the requested times.
pub fn fly(
    aircraft: &Aircraft,
    request: TrimRequest,
    loading: Loading,
    changes: &dyn Fn(f64) -> [f64; 4],
    s: FlySettings,
) -> Result<Replayed, String> {
    if !(s.sample_s.is_finite() && s.sample_s > 0.0) || s.samples == 0 {
        return Err(format!(
            "the sample interval must be positive and there must be samples (got {} s, {})",
            s.sample_s, s.samples
        ));
    }
    let most = crate::inputs::limits::MAX_RECORD_SAMPLES;
    if s.samples >= most {
        return Err(format!(
            "{} samples: a record may have at most {most} (MAX_RECORD_SAMPLES)",
            s.samples + 1
        ));
    }
    let duration_s = s.sample_s * s.samples as f64;
    let time_s: Vec<f64> = (0..=s.samples).map(|k| k as f64 * s.sample_s).collect();
    match s.simulation {
        Simulation::Linear => {
            let (_, lin) = crate::run::linearise::run_linearise(aircraft, request, loading)
                .map_err(|e| e.to_string())?;
            let m = &lin.model;
            let x0 = vec![0.0; m.states().len()];
            let input = |t: f64| changes(t).to_vec();
            let xs =
                cierva_model::simulation::simulate::simulate(m, &x0, &input, s.sample_s, s.samples);
            let mut signals = vec![Vec::with_capacity(xs.len()); SIGNALS.len()];
            for x in &xs {
                // STATES: u v w p q r phi theta psi Omega.
                let body = [
                    x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], x[8], 0.0, 0.0, 0.0,
                ];
                for (sig, v) in signals.iter_mut().zip(responses(&body, x[9])) {
                    sig.push(v);
                }
            }
            Ok(Replayed { time_s, signals })
        }
        Simulation::FullBlade => {
            let start = crate::run::simulate::simulation_start(aircraft, request, loading)?;
            let settings = |duration_s| cierva_model::simulation::timehistory::Settings {
                azimuth_step_rad: s.azimuth_step_rad,
                duration_s,
                output_every: 1,
            };
            // Trim: the mean over one revolution with the controls held.
            let revolution_s = 2.0 * std::f64::consts::PI / start.state.rotor_omega_rad_s;
            let row = |x: &Sample| {
                responses(&x.state.body.to_array(), x.state.rotor_omega_rad_s).to_vec()
            };
            let held = start.run(&|_| [0.0; 4], settings(revolution_s))?;
            let trim = revolution_mean(&held, &row);
            let h = start.run(changes, settings(duration_s))?;
            let mut signals = vec![Vec::with_capacity(time_s.len()); SIGNALS.len()];
            for r in resample(&h, &time_s, &row) {
                for i in 0..SIGNALS.len() {
                    signals[i].push(r[i] - trim[i]);
                }
            }
            Ok(Replayed { time_s, signals })
        }
    }
}

/// `row` at each of `times`, interpolated linearly between the run's samples on either side
/// (held at the run's ends), each sample's row computed once.
pub fn resample(
    h: &TimeHistory,
    times: &[f64],
    row: &dyn Fn(&Sample) -> Vec<f64>,
) -> Vec<Vec<f64>> {
    let mut j = 0;
    let mut rows: Option<(usize, Vec<f64>, Vec<f64>)> = None;
    times
        .iter()
        .map(|&t| {
            while j + 2 < h.samples.len() && h.samples[j + 1].time_s <= t {
                j += 1;
            }
            let (a, b) = (&h.samples[j], &h.samples[(j + 1).min(h.samples.len() - 1)]);
            let f = if b.time_s > a.time_s {
                ((t - a.time_s) / (b.time_s - a.time_s)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            if rows.as_ref().is_none_or(|(k, _, _)| *k != j) {
                rows = Some((j, row(a), row(b)));
            }
            let (_, ra, rb) = rows.as_ref().expect("just set");
            ra.iter()
                .zip(rb)
                .map(|(ra, rb)| ra + f * (rb - ra))
                .collect()
        })
        .collect()
}

/// The mean of `row` over one revolution's run: every sample but the last, which closes the
/// revolution.
pub fn revolution_mean(h: &TimeHistory, row: &dyn Fn(&Sample) -> Vec<f64>) -> Vec<f64> {
    let steps = &h.samples[..h.samples.len().saturating_sub(1).max(1)];
    let mut mean: Vec<f64> = Vec::new();
    for x in steps {
        let r = row(x);
        mean.resize(r.len(), 0.0);
        for (m, v) in mean.iter_mut().zip(r) {
            *m += v / steps.len() as f64;
        }
    }
    mean
}

/// One response of the model compared with the reference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignalMetrics {
    pub signal: String,
    pub max_abs_error: f64,
    pub rms_error: f64,
    pub theil: f64,
    /// When the largest error occurs, s from the record's start.
    pub time_of_max_s: f64,
}

impl SignalMetrics {
    /// A metric by name (one of [`METRICS`]).
    pub fn get(&self, metric: &str) -> Option<f64> {
        match metric {
            "max_abs_error" => Some(self.max_abs_error),
            "rms_error" => Some(self.rms_error),
            "theil" => Some(self.theil),
            _ => None,
        }
    }
}

/// The responses a record carries: its channels other than `time_s` and its controls.
pub fn record_signals(record: &Record) -> Vec<String> {
    record
        .channels
        .iter()
        .filter(|c| SIGNALS.contains(&c.as_str()) && !record.meta.controls.contains(c))
        .cloned()
        .collect()
}

/// Control changes from trim in a record, interpolated linearly and held beyond the ends.
pub fn record_controls(record: &Record) -> Result<crate::inputs::controls::ControlTable, String> {
    use crate::inputs::controls::{CONTROL_COLUMNS, ControlTable};
    let t0 = record.channel("time_s").ok_or("the record has no time_s")?;
    let time_s: Vec<f64> = t0.iter().map(|t| t - t0[0]).collect();
    let mut changes: [Vec<f64>; 4] = Default::default();
    for (k, name) in CONTROL_COLUMNS.iter().enumerate() {
        changes[k] = match record.channel(name) {
            Some(v) if record.meta.controls.iter().any(|c| c == name) => v.to_vec(),
            _ => vec![0.0; time_s.len()],
        };
    }
    for c in &record.meta.controls {
        if !CONTROL_COLUMNS.contains(&c.as_str()) {
            return Err(format!(
                "control `{c}` is not one of {}",
                CONTROL_COLUMNS.join(", ")
            ));
        }
    }
    Ok(ControlTable { time_s, changes })
}

/// The metrics a model with no response at all would score against `record` (every response
/// zero, its change from trim): a check that such a model passes cannot fail.
pub fn zero_response_metrics(record: &Record) -> Result<Vec<SignalMetrics>, String> {
    constant_response_metrics(record, |_| 0.0)
}

/// The metrics a model whose every response holds still at the reference's own mean (over the
/// record) would score: the second trivial predictor. A check that it passes only asks the
/// model to get the record's average, not its motion.
pub fn mean_response_metrics(record: &Record) -> Result<Vec<SignalMetrics>, String> {
    constant_response_metrics(record, |c| {
        if c.is_empty() {
            0.0
        } else {
            c.iter().sum::<f64>() / c.len() as f64
        }
    })
}

/// The metrics of a model holding each response at `level(the record's channel)` (0 for a
/// response the record does not carry) throughout.
fn constant_response_metrics(
    record: &Record,
    level: impl Fn(&[f64]) -> f64,
) -> Result<Vec<SignalMetrics>, String> {
    let n = record.channel("time_s").map_or(0, <[f64]>::len);
    let signals = SIGNALS
        .iter()
        .map(|name| vec![record.channel(name).map_or(0.0, &level); n])
        .collect();
    compare(
        record,
        &Replayed {
            time_s: vec![0.0; n],
            signals,
        },
    )
}

/// Compares every response of `flown` that `record` carries. The two are aligned sample by
/// sample (`flown` is flown at the record's times).
pub fn compare(record: &Record, flown: &Replayed) -> Result<Vec<SignalMetrics>, String> {
    let t = record.channel("time_s").ok_or("the record has no time_s")?;
    let mut out = Vec::new();
    for name in record_signals(record) {
        let reference = record.channel(&name).expect("a channel of the record");
        let model = flown
            .signal(&name)
            .ok_or_else(|| format!("`{name}` is not a response cierva computes"))?;
        let n = reference.len().min(model.len());
        if n == 0 {
            return Err("nothing to compare".into());
        }
        let (mut worst, mut at, mut sq) = (0.0f64, 0.0, 0.0);
        for k in 0..n {
            let e = model[k] - reference[k];
            // NaN never passes: it propagates into every metric.
            if e.is_nan() || e.abs() > worst {
                worst = if e.is_nan() { f64::NAN } else { e.abs() };
                at = t[k] - t[0];
            }
            sq += e * e;
        }
        out.push(SignalMetrics {
            signal: name.clone(),
            max_abs_error: worst,
            rms_error: (sq / n as f64).sqrt(),
            theil: crate::ident::theil_inequality(&model[..n], &reference[..n]),
            time_of_max_s: at,
        });
    }
    Ok(out)
}

/// Flies `aircraft` through `record`'s control changes and compares its responses.
pub fn fly_record(
    aircraft: &Aircraft,
    request: TrimRequest,
    loading: Loading,
    record: &Record,
    simulation: Simulation,
    azimuth_step_rad: f64,
) -> Result<(Vec<SignalMetrics>, Replayed), String> {
    let table = record_controls(record)?;
    let samples = table.time_s.len().saturating_sub(1);
    let flown = fly(
        aircraft,
        request,
        loading,
        &|t| table.at(t),
        FlySettings {
            simulation,
            sample_s: record.dt_s(),
            samples,
            azimuth_step_rad,
        },
    )?;
    Ok((compare(record, &flown)?, flown))
}
