//! Matched processing: the model flown with the records' own controls and put through the
//! records' own estimator, so that a retune compares like with like.
//!
//! A response estimated from a record is not the aircraft's response at that frequency: Welch's
//! averaged spectra smooth it over the windows' spectral window, leak power from the rest of
//! the band through its sidelobes, and the records' other controls enter through transfers
//! measured on the same grid. For a linear aircraft all of that is fixed by the controls: the
//! estimate of a model's output flown with the recorded controls differs from the model's own
//! response as the record's estimate differs from the aircraft's, less the disturbance's part
//! (which averages out), where the model's flight from rest is the record's (its modes stable
//! and died away within the padding, [`PADDING_RECORDS`]; for an unstable mode the response
//! `h` is the bounded, non-causal one its frequency response implies, which the fit compares
//! with anyway). Measured on known answers (issue 51, item 6; `reports/investigations.md`,
//! "What leans retune's drag scale high"), that difference leaned the profile-drag scale high
//! by +0.0665 (1.57 standard errors on average) where the flown system was the very
//! linearisation retune matches, as much as flying the individual blades did (+0.061): the
//! estimator's, not the model's form.
//!
//! The correction, a plug-in estimate of the estimator's bias in the manner of Efron and
//! Tibshirani (1993, ch. 10), taken once, conditional on the recorded controls, with no
//! disturbance and nothing random to draw: at the fitted values, every record's outputs are
//! replaced by the model's, `y = sum_j h_j * u_j` over the recorded controls `u_j`
//! ([`flown_output`]); the same estimator on the same grid gives the model's estimated
//! responses; each target's reference is moved by what the estimator adds to the model's
//! response there (the estimate less the model's value as flown); and the fit runs again from
//! where it ended ([`refit`]). The bias is held at the fitted values (its change with the
//! parameters is left out, second order). The standard errors stay the records' random
//! errors: the flown outputs carry no noise, and the controls are the records' own in both.

use super::responses::{self, RecordedResponse};
use super::subject::Retuned;
use crate::fit::{self, Measure, Problem, TargetCondition};
use crate::inputs::record::Record;
use crate::run::responses::Responses;
use rustfft::num_complex::Complex64 as C;
use serde::Serialize;

/// How far above the band's top the model's responses drive a flown output, in multiples of
/// the top: the controls' content above (their sensors' noise, the pilot's quick corrections)
/// reaches an estimate in the band only through its windows' sidelobes, at least a band's
/// width (tens of resolution bins) away, where a Hann window's sidelobes (-31 dB, falling 18 dB
/// an octave) are below -90 dB. At the default 2 Hz top it stays below a two-bladed rotor's
/// 1/rev (about 6 Hz for the VPM M16), where a baseband response means little.
pub const FLOWN_TOP_FACTOR: f64 = 2.0;

/// The transform's length in records: the record and three more of zeros, so that the model's
/// response to the record's last controls runs three record lengths before it wraps round
/// onto the record's start. A mode of time constant `tau` wraps by `exp(-3 T / tau)`: for a
/// lightly damped phugoid (`tau` 75 s) on a 90 s record, 3 %.
pub const PADDING_RECORDS: usize = 4;

/// What the matched processing did to a retune's targets.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Matched {
    /// The fitted values it started from (the fit against the records' estimates as they are),
    /// where the model was flown, by the parameters' names.
    pub values_before: std::collections::BTreeMap<String, f64>,
    /// The targets whose references it moved.
    pub corrected: usize,
    /// The targets with no flown estimate or no model value (left as they are).
    pub missing: usize,
    /// The estimator's bias at the targets, in their standard errors: root mean square and
    /// largest.
    pub bias_rms_se: f64,
    pub bias_max_se: f64,
}

impl Matched {
    /// What it did, in words.
    pub fn described(&self) -> String {
        let sig = crate::units::sig;
        let before: Vec<String> = self
            .values_before
            .iter()
            .map(|(n, v)| format!("{n} {}", sig(*v, 4)))
            .collect();
        format!(
            "{} moved by the estimator's own bias (RMS {}, at most {} standard errors{}), found by flying the model with the records' controls at the values fitted first ({}) through the same estimator; the cost and the reduced chi-square are against the moved targets, each response's J against the records' estimates",
            crate::units::count(self.corrected, "target", "targets"),
            sig(self.bias_rms_se, 2),
            sig(self.bias_max_se, 2),
            match self.missing {
                0 => String::new(),
                m => format!("; {m} with no flown estimate or model value left as they are"),
            },
            before.join(", "),
        )
    }
}

/// How far a frequency of [`grid`] may sit from its bin, in bins: rounding only (a frequency
/// is `k / (m dt)`, a few ulps).
const GRID_ROUNDING: f64 = 1e-6;

/// The frequencies a record's flown output is built from: the bins of a transform of
/// [`PADDING_RECORDS`] times its `samples` (the zeros make the circular convolution the linear
/// one over the record, as far as the model's response has died away within them), from the
/// first to `top_hz` (below the Nyquist frequency).
pub fn grid(samples: usize, dt_s: f64, top_hz: f64) -> Vec<f64> {
    let df = 1.0 / ((PADDING_RECORDS * samples) as f64 * dt_s);
    let top = top_hz.min(0.5 / dt_s - df);
    (1..)
        .map(|k| k as f64 * df)
        .take_while(|f| *f <= top)
        .collect()
}

/// The band's top a record's estimates reach (the retune's `--band-hz`, or
/// [`responses::TOP_HZ`] within the estimator's share of the sample rate).
fn band_top_hz(rec: &Record, settings: &responses::ResponseSettings) -> f64 {
    settings.band_hz.map_or_else(
        || {
            responses::TOP_HZ
                .min(crate::ident::frequency_response::DEFAULT_TOP_FRACTION / rec.dt_s())
        },
        |b| b[1],
    )
}

/// Where a record's control stood at trim, which the model's flight starts from at rest: 0 for
/// a control logged as changes from trim, else the sidecar's `trim` value of the channel (a
/// position), or the mean of the record's first second.
fn trim_level(rec: &Record, control: &str, u: &[f64]) -> f64 {
    let changes = rec
        .meta
        .travel
        .get(control)
        .is_some_and(|t| t.logged == crate::inputs::channels::Logged::ChangeFromTrim);
    if changes {
        return 0.0;
    }
    rec.meta
        .trim
        .get(&format!("{control}_percent"))
        .copied()
        .unwrap_or_else(|| {
            let first = ((1.0 / rec.dt_s()).round() as usize).clamp(1, u.len().max(1));
            u.iter().take(first).sum::<f64>() / first as f64
        })
}

/// The model's `output` flown with `rec`'s recorded controls: `y = sum_j h_j * u_j` by
/// transforms (each control less its level at trim, the sidecar's `trim` or the mean of the
/// record's first second, where the model is at rest; zero padded, [`PADDING_RECORDS`]), `h`
/// the model's responses on [`grid`]'s frequencies for the record (states x controls), nothing
/// above them; its mean the record's own output's (`measured`, which also sets the length;
/// returned as it is for an output the model has no state for).
pub fn flown_output(
    rec: &Record,
    output: &str,
    h: &Responses,
    measured: &[f64],
) -> Result<Vec<f64>, String> {
    let n = measured.len();
    let m = PADDING_RECORDS * n;
    let on_grid = h.frequencies_hz.len() < m / 2
        && h.frequencies_hz
            .iter()
            .enumerate()
            .all(|(k, f)| (f * m as f64 * rec.dt_s() - (k + 1) as f64).abs() < GRID_ROUNDING);
    if !on_grid {
        return Err(format!(
            "{}: the model's responses are not on the record's grid ({} frequencies from {} Hz)",
            rec.path.display(),
            h.frequencies_hz.len(),
            h.frequencies_hz.first().copied().unwrap_or(f64::NAN)
        ));
    }
    let Some(o) = h.states.iter().position(|s| s == output) else {
        // An output the model has no state for is no target (`answerable`): its records'
        // estimate is left as it is.
        return Ok(measured.to_vec());
    };
    let (forward, inverse) = cierva_fft::plans(m);
    let zero = C::new(0.0, 0.0);
    let mut y = vec![zero; m];
    for (i, control) in h.controls.iter().enumerate() {
        let Some(u) = rec.channel(&format!("{control}_percent")) else {
            continue;
        };
        if u.len() != n {
            return Err(format!(
                "{}: control `{control}_percent` has {} samples, the output {n}",
                rec.path.display(),
                u.len()
            ));
        }
        let level = trim_level(rec, control, u);
        let mut spectrum: Vec<C> = u.iter().map(|v| C::new(v - level, 0.0)).collect();
        spectrum.resize(m, zero);
        forward.process(&mut spectrum);
        for (k, at) in h.at.iter().enumerate() {
            let bin = k + 1;
            let v = at[(o, i)] * spectrum[bin];
            y[bin] += v;
            y[m - bin] += v.conj();
        }
    }
    inverse.process(&mut y);
    // The transform's constant (the zero frequency, where a model with a heading state has
    // no response) is left out, so the flight's mean is set: the record's own.
    let flown: Vec<f64> = y.iter().take(n).map(|v| v.re / m as f64).collect();
    let shift = mean(measured) - mean(&flown);
    Ok(flown.into_iter().map(|v| v + shift).collect())
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len().max(1) as f64
}

/// The model's value at a target's point from its flown estimates: the real or imaginary part
/// of the estimate at the same condition, input, output and frequency.
fn flown_value(flown: &[RecordedResponse], t: &fit::Target) -> Option<f64> {
    let Measure::Response(p) = &t.measure else {
        return None;
    };
    let r = flown
        .iter()
        .find(|r| r.condition == t.condition && r.input == p.input && r.output == p.output)?;
    let q = r.points.iter().find(|q| q.frequency_hz == p.frequency_hz)?;
    Some(if p.imaginary {
        q.response.im
    } else {
        q.response.re
    })
}

/// Every record's model responses on its [`grid`] at the fitted values, and the record's
/// output flown with them.
struct Flights<'r> {
    records: Vec<&'r Record>,
    /// For each of `records`, the index of its responses.
    index: Vec<usize>,
    responses: Vec<Responses>,
}

impl<'r> Flights<'r> {
    /// One request of the model per condition and grid (records of one length at one
    /// condition share it), in parallel.
    fn new(
        retuned: Retuned<'_>,
        records: &'r [Record],
        settings: &responses::ResponseSettings,
        values: &crate::inputs::corrections::CorrectionSet,
    ) -> Result<Self, String> {
        let model = retuned.flight_model();
        let mut requests: Vec<(TargetCondition, Vec<f64>)> = Vec::new();
        let (mut keys, mut index) = (Vec::new(), Vec::new());
        for g in responses::by_condition(records)? {
            for rec in g.records {
                let samples = rec.data.first().map_or(0, Vec::len);
                let top = FLOWN_TOP_FACTOR * band_top_hz(rec, settings);
                let request = (g.condition, grid(samples, rec.dt_s(), top));
                let k = requests
                    .iter()
                    .position(|r| *r == request)
                    .unwrap_or_else(|| {
                        requests.push(request);
                        requests.len() - 1
                    });
                keys.push(rec);
                index.push(k);
            }
        }
        let responses = crate::run::parallel::parallel_map(&requests, |(c, frequencies)| {
            retuned.responses_at(model.as_ref(), values, c, frequencies)
        })
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            records: keys,
            index,
            responses,
        })
    }

    /// [`flown_output`] for one of the records.
    fn flown(&self, rec: &Record, output: &str, measured: &[f64]) -> Result<Vec<f64>, String> {
        let k = self
            .records
            .iter()
            .position(|r| std::ptr::eq(*r, rec))
            .ok_or_else(|| format!("{}: not one of the retune's records", rec.path.display()))?;
        flown_output(rec, output, &self.responses[self.index[k]], measured)
    }
}

/// The fit again with every response target's reference moved by the estimator's bias at
/// `fitted`'s values (the module's doc), started where `fitted` ended. `problem`'s targets are
/// left moved; the result keeps `fitted`'s `before` and `cost_start` (the cost there with the
/// moved targets), with both fits' iterations and evaluations. An error leaves `problem` as it
/// was.
pub fn refit(
    retuned: Retuned<'_>,
    records: &[Record],
    settings: &responses::ResponseSettings,
    problem: &mut Problem,
    fitted: &fit::FitResult,
) -> Result<(fit::FitResult, Matched), String> {
    if fitted.after.len() != problem.targets.len() {
        return Err(format!(
            "{} model values for {} targets",
            fitted.after.len(),
            problem.targets.len()
        ));
    }
    let flights = Flights::new(retuned, records, settings, &fitted.corrections())?;
    let flown = |rec: &Record, output: &str, measured: &[f64]| flights.flown(rec, output, measured);
    let estimated = responses::responses_flown(records, settings, Some(&flown))?;
    let mut moved = problem.clone();
    let (mut corrected, mut missing, mut sum2, mut max) = (0, 0, 0.0_f64, 0.0_f64);
    for (t, model_value) in moved.targets.iter_mut().zip(&fitted.after) {
        if !matches!(t.measure, Measure::Response(_)) {
            continue;
        }
        match flown_value(&estimated, t) {
            Some(v) if v.is_finite() && model_value.is_finite() => {
                let bias = v - model_value;
                t.reference -= bias;
                let z = (bias / t.standard_error).abs();
                sum2 += z * z;
                max = max.max(z);
                corrected += 1;
            }
            _ => missing += 1,
        }
    }
    *problem = moved;
    let again = super::again_from(problem, fitted.clone());
    let matched = Matched {
        values_before: fitted
            .parameters
            .iter()
            .zip(&fitted.values)
            .map(|(k, v)| (k.name().to_string(), *v))
            .collect(),
        corrected,
        missing,
        bias_rms_se: (sum2 / corrected.max(1) as f64).sqrt(),
        bias_max_se: max,
    };
    Ok((again, matched))
}
