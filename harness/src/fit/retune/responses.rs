//! retune's targets by frequency-response matching: each condition's records give the
//! non-parametric responses of the states they measure to the controls they excite
//! ([`crate::ident::frequency_response`]: Welch's spectra composited over several windows,
//! conditioned on the records' other controls), and each frequency where a response is coherent
//! gives two targets, its real and imaginary parts.
//!
//! # The estimator, and why its standard errors are what they are
//! This is complex-response least squares weighted by the random error from coherence: the
//! cost is `sum_f |H_model(f) - H(f)|^2 / (|H(f)| e_r(f))^2` over the frequencies kept, with
//! `e_r = sqrt(1 - g^2) / (|g| sqrt(2 n_d))` the normalised random error of `|H|` (Bendat and
//! Piersol, *Random Data*, 4th ed., 2010, ch. 9; Tischler and Remple, *Aircraft and Rotorcraft
//! System Identification*, 2nd ed., 2012, ch. 7, give the same form; `n_d` the composite's
//! degrees of freedom). `e_r` is also the standard deviation of the phase in radians, so the
//! error of `H` is about circular with standard deviation `|H| e_r` in each of its real and
//! imaginary parts: those are the targets' standard errors. With residuals so scaled, the
//! cost's curvature, the fit's Gauss-Newton `J' J` at the optimum, is the inverse covariance of
//! the parameters (`crate::fit`'s standard errors) when the targets are independent.
//!
//! Two choices keep them so, each stated where it is made:
//! - frequencies are kept at least [`INDEPENDENT_BINS`] resolution bins apart
//!   (`spaced`): estimates closer than that share data through the window's lobe;
//! - the attitudes are not outputs ([`OUTPUTS`]): each is its rate's integral, measured again,
//!   and its response's error is the rate's.
//!
//! # The record's other controls
//! A pilot holding the other axes moves the other controls with the test input: their part of
//! each output is in the records' single-input responses, and not in the model's response to
//! the one control. Conditioning on them does not remove it without bias, because they are
//! fed back: they answer the disturbances too. So the model's response is taken as flown
//! instead: its response to the excited control plus its responses to the others times their
//! measured transfers from it ([`crate::run::responses::Responses::as_flown`],
//! exact for a linear aircraft whoever moves the controls). Each target's standard error is
//! then that of what no control explains ([`RecordedResponse::standard_error`]), with the model's
//! responses to the other controls at the uncorrected aircraft for a first fit and at its
//! corrections for the second ([`crate::fit::retune::retune`]). Seen on the model's own flights
//! under its pilot's hold (the VPM M16's linearisation flown in a simulation with the pilot,
//! 5 sets of four 120 s sweeps): at 0.15 Hz, where the pilot's roll and heading loops act,
//! `q / eta_s` missed by 10 of its standard errors (rms over the real and imaginary parts) with
//! the control alone and by 1.3 as flown.
//!
//! # Records with a recorded excitation
//! A pilot's attitude hold answers turbulence at the band's low end, so the swept control
//! carries a part correlated with the output's noise, and a response estimated from the
//! control's spectra is biased there (closed-loop identification). Where every record at a
//! condition names, in its sidecar's `excitation`, the channel recording what an excitation
//! system added to the control it moves, the responses are estimated against those
//! excitations instead ([`fr::referenced`]: `G_RU^-1 G_Ry`, the other controls' transfers
//! `G_RU^-1 G_RO`, and what the controls leave unexplained for the standard error): the
//! excitation is independent of the disturbance, so the estimate is consistent under the
//! pilot's loops (no closed-loop bias as the records grow). A frequency is judged by the
//! coherence its own random error implies, and the resolution bias is taken with the
//! magnitude of the control's cross-spectrum with its excitation in place of its autospectrum
//! (its phase's slope, small away from the pilot's crossover, is left out). A record
//! that does not excite a control has a zero excitation for it. Without an excitation in every
//! record the responses come from the controls ([`ResponseEstimator::Direct`]) and the report says so.
//!
//! # The estimator's resolution bias
//! A response estimated with windows of length `T` is the true one smoothed over a spectral
//! window of second moment `1 / (3 T^2)` (Hann), which biases it where the response bends
//! sharply (next to a lightly damped pole: the phugoid, at the band's low end, where only the
//! longest window reaches) or where the input's spectrum falls away (a sweep's ends). The bias
//! is not random, so no standard error covers it: a point whose bias, by the model's own
//! response and the input's measured spectrum ([`resolution_bias`]), exceeds
//! [`RESOLUTION_BIAS_MAX`] of its random error is no target.
//!
//! CIFER's identification weights by `J`'s coherence weighting of the dB and degree errors
//! (Tischler and Remple 2012, ch. 11) rather than by the random error; that cost's curvature is
//! not an inverse covariance, which is why this fit does not use it. `J` is reported, before
//! and after, per response.

use crate::checks::frequency_response::{COHERENCE_MIN, Point};
use crate::fit::{Measure, ResponsePoint, Target, TargetCondition};
use crate::ident::frequency_response as fr;
use crate::inputs::record::Record;
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64 as C;
use serde::Serialize;

/// The states a retune can match responses of, as the records measure them: the air data's
/// `u v w` (moved to the c.g.), the rates and the rotor speed. The attitudes are left out: each
/// is its rate's integral (`theta' = q` at level flight) measured by another instrument, so its
/// response carries the same information and the same estimation error (the part of the output
/// the input does not explain is integrated too); counting both would count that information
/// twice and halve the stated variances.
pub const OUTPUTS: [&str; 7] = ["u", "v", "w", "p", "q", "r", "Omega"];

/// The outputs matched by default for a control: its own axis's. The off-axis responses of a
/// single-axis test input are the pilot's hold on the other axis as much as the aircraft's
/// coupling (the pilot's lateral stick and pedals answer the roll and yaw the stick sweep
/// causes), which the model's open-loop response does not have. Seen on the VPM M16's own
/// calm-air 60 mph stick sweep: J of 121, 281 and 219 for `v`, `p` and `r` against 22, 8.4, 3.7
/// and 20 for `u`, `w`, `q` and `Omega`, and a reduced chi-square of 13 with all seven against
/// 1.27 with the four. `--outputs` names others.
pub fn on_axis(control: &str) -> &'static [&'static str] {
    match control {
        "eta_c" | "eta_p" => &["v", "p", "r"],
        _ => &["u", "w", "q", "Omega"],
    }
}

/// Least spacing of the frequencies a fit uses, in resolution bins (`1 / T` of the shortest
/// window the composite leans on there). A Hann window's segment estimates at two frequencies
/// `k` bins apart are correlated by `|W2(k)|^2 / |W2(0)|^2`, `W2` the transform of the squared
/// window (`sin^4`, whose Fourier series has terms at 0, 1 and 2 bins of 3/8, 1/4 and 1/16):
/// 0.44 one bin apart, 0.028 two bins apart and 0 beyond (Bendat and Piersol 2010, ch. 11,
/// for the spectral window's correlation; the numbers are the Hann window's own). Two bins
/// leaves the kept targets nearly independent.
pub const INDEPENDENT_BINS: f64 = 2.0;

/// A window whose weight in the composite at a frequency is below this takes no part in the
/// spacing there: the composite's weights come from its variance minimisation, and a weight of
/// a hundredth changes the estimate's correlation with its neighbours by about as much.
pub const WEIGHT_MIN: f64 = 0.01;

/// The top of a retune's default band, Hz: that of seed 000's identification band (0.05-2 Hz,
/// [`crate::ident::BandSpec::SEED_000`]), which the built-in set-ups use. Above it the records
/// carry the rotor's harmonics (the VPM M16's rotor turns at about 6 Hz) as vibration that can
/// be coherent with the input by chance and that the baseband response does not have: on a
/// 50 mph stick sweep, one such point (8 Hz, coherence 0.79, the records' `q / eta_s` 33 dB
/// above the model's) made `J` 396 where the response below 2 Hz matched within a dB.
/// `--band-hz` sets another band.
pub const TOP_HZ: f64 = 2.0;

/// How the responses are estimated.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ResponseSettings {
    /// Window lengths, s (default: [`fr::SpectralSettings::default_windows_s`] of the shortest
    /// record).
    pub windows_s: Option<Vec<f64>>,
    /// The band, Hz (default: five periods of the longest window to [`TOP_HZ`]).
    pub band_hz: Option<[f64; 2]>,
    /// The states to match (default: each control's own axis's, [`on_axis`]).
    pub outputs: Option<Vec<String>>,
}

/// One response estimated from a condition's records.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordedResponse {
    #[serde(skip)]
    pub condition: TargetCondition,
    pub input: String,
    pub output: String,
    /// Against the records' excitations, or from their controls.
    pub estimator: ResponseEstimator,
    /// Every frequency of the grid where the response is estimated.
    #[serde(skip)]
    pub points: Vec<Point>,
    /// The normalised random error at each point.
    pub random_error: Vec<f64>,
    /// The points that are targets (coherent, and spaced by [`INDEPENDENT_BINS`]).
    pub used: Vec<usize>,
    /// The records' other controls (`other_controls`): a pilot's hold moves them with the
    /// input. (Under [`ResponseEstimator::Referenced`], the transfers below are `G_RU^-1 G_RO` and
    /// the spectra those of the other controls and the output less their parts through the
    /// excited controls: [`fr::referenced::Referenced`]; [`Self::standard_error`] is then
    /// `sqrt(K_ii G_rr / (2 n_d))` exactly.)
    pub other_controls: Vec<String>,
    /// At each point, each other control's measured transfer from `input`, in the order of
    /// `other_controls` (conditioned on the other excited controls: `G_EE^-1 G_EO`), which the
    /// model's response adds ([`crate::run::responses::Responses::as_flown`]).
    #[serde(skip)]
    pub others: Vec<Vec<(String, C)>>,
    /// At each point, the auto- and cross-spectra of the other controls and the output (in
    /// that order, the output last) conditioned on the excited controls, row-major: what the
    /// excited controls do not explain, from which [`Self::standard_error`] takes the part
    /// the model's responses to the other controls do not explain either.
    #[serde(skip)]
    pub unexplained: Vec<Vec<C>>,
    /// At each point, the second moment of the composite's spectral window, Hz^2
    /// ([`spectral_window_moment`]).
    #[serde(skip)]
    pub window_moment_hz2: Vec<f64>,
    /// At each point, the slope of the log of the input's autospectrum, 1/Hz.
    #[serde(skip)]
    pub input_log_slope_per_hz: Vec<f64>,
}

impl RecordedResponse {
    /// The standard error of the real and of the imaginary part of point `k`'s difference from
    /// the model's response as flown, given the model's responses to [`Self::other_controls`]
    /// there (`secondary`, in that order).
    ///
    /// That difference is `G_EE^-1 G_E,r`, `r = y - sum_j G_j u_j` what no control explains (the
    /// disturbance: turbulence, and the sensors' noise), so its variance is
    /// `G_rr [G_EE^-1]_ii / n_d` (Bendat and Piersol 2010, ch. 9, for the cross-spectrum of an
    /// input with an independent signal). The coherence's random error `|H| e_r` is the same
    /// with `G_nn`, what the excited controls alone do not explain, in place of `G_rr`; so the
    /// error is `|H| e_r sqrt(G_rr / G_nn)`, the degrees of freedom as the coherence's. `G_rr`
    /// is `c^H M c` with `M` [`Self::unexplained`] and `c = (-G_o..., 1)`: under a pilot's
    /// hold the two differ, because the pilot's stick and pedals answer the disturbance and
    /// take some of it out of the output (`G_nn` smaller at the frequencies the pilot's loops
    /// reach), and they answer the input's own effects on the other axes, which is then in
    /// `G_nn` but not in `G_rr`.
    pub fn standard_error(&self, k: usize, secondary: &[C]) -> f64 {
        let plain = self.points[k].response.norm() * self.random_error[k];
        residual_standard_error(plain, &self.unexplained[k], secondary)
    }
}

/// Step of the model's response either side of a point for its slope and curvature
/// ([`resolution_bias`]), a fraction of the frequency: a thousandth of the narrowest feature the
/// band meets (a pole 0.03 Hz off at 0.08 Hz) is 3e-5 Hz; a hundredth of 0.08 Hz is 8e-4 Hz, and
/// the differences' rounding (1e-12 of `|H|` over the step squared) stays below 1e-5 of the
/// windows' second moments.
pub const RESOLUTION_STEP: f64 = 0.01;

/// Largest resolution bias a target may carry, in its random errors ([`resolution_bias`]): a
/// bias of half the random error moves a 95 % interval's coverage to 92 % (`z ~ N(0.5, 1)`).
pub const RESOLUTION_BIAS_MAX: f64 = 0.5;

/// The frequencies either side of `f` where the model's response gives its slope and
/// curvature.
pub fn neighbours(frequency_hz: f64) -> [f64; 2] {
    [
        frequency_hz * (1.0 - RESOLUTION_STEP),
        frequency_hz * (1.0 + RESOLUTION_STEP),
    ]
}

/// The second moment of a Hann window's spectral window (`|W(nu)|^2`, normalised), Hz^2, for
/// a window of `window_s`: `int nu^2 |W|^2 / int |W|^2 = int w'^2 / (4 pi^2 int w^2)` (Parseval),
/// which for `w = sin^2(pi t / T)` is `(pi^2 / (2 T)) / (4 pi^2 3 T / 8) = 1 / (3 T^2)`. The
/// composite of several windows with weights `a` (summing to one) has `sum a / (3 T^2)`.
pub fn spectral_window_moment(windows_s: &[f64], weights: &[f64]) -> f64 {
    windows_s
        .iter()
        .zip(weights)
        .map(|(t, a)| a / (3.0 * t * t))
        .sum()
}

/// The relative bias of a smoothed response estimate at `f` (Bendat and Piersol 2010, ch. 8-9,
/// the resolution bias of spectral estimates, carried to the ratio that is the response):
/// `H_est = int K H S / int K S` over a spectral window `K` of second moment `m2`, with `S` the
/// input's autospectrum, is `H (1 + m2/2 (H''/H + 2 (H'/H)(S'/S)))` to second order. `h` the
/// model's response at `neighbours(f)` and at `f`, `log_slope` `S'/S`. Large next to a lightly
/// damped pole (the phugoid, for the longest windows at the band's low end) and where the
/// input's spectrum falls away (a sweep's ends).
pub fn resolution_bias(frequency_hz: f64, h: [C; 3], m2: f64, log_slope: f64) -> C {
    let [below, at, above] = h;
    let step = frequency_hz * RESOLUTION_STEP;
    let d1 = (above - below) / (2.0 * step);
    let d2 = (above - at * 2.0 + below) / (step * step);
    (d2 / at + d1 / at * (2.0 * log_slope)) * (0.5 * m2)
}

/// [`RecordedResponse::standard_error`] from the coherence's error `plain` (`|H| e_r`), the spectra
/// of the other controls and the output conditioned on the excited controls (`unexplained`,
/// [`conditioned`]'s second part) and the model's responses to those controls (`secondary`):
/// `plain sqrt(G_rr / G_nn)`. `plain` itself where there is no other control or the spectra
/// give no positive power.
pub fn residual_standard_error(plain: f64, unexplained: &[C], secondary: &[C]) -> f64 {
    let n = secondary.len() + 1;
    if secondary.is_empty() || unexplained.len() != n * n {
        return plain;
    }
    let c: Vec<C> = secondary
        .iter()
        .map(|g| -g)
        .chain([C::new(1.0, 0.0)])
        .collect();
    let mut g_rr = C::new(0.0, 0.0);
    for a in 0..n {
        for b in 0..n {
            g_rr += c[a].conj() * c[b] * unexplained[a * n + b];
        }
    }
    let g_nn = unexplained[n * n - 1].re;
    if g_nn > 0.0 && g_rr.re.is_finite() && g_rr.re > 0.0 {
        plain * (g_rr.re / g_nn).sqrt()
    } else {
        plain
    }
}

/// What the records' other controls say at one frequency of an estimate whose inputs are the
/// `e` excited controls and then the others: each other control's transfer from excited input
/// `i` (`G_EE^-1 G_EO`, row `i`), and the spectra of the others and the output conditioned on
/// the excited controls (`G_ab - G_aE G_EE^-1 G_Eb`). None where `G_EE` is singular.
pub fn conditioned(g: &[C], p: usize, e: usize, i: usize) -> Option<(Vec<C>, Vec<C>)> {
    let at = |a: usize, b: usize| g[a * p + b];
    let g_ee = DMatrix::from_fn(e, e, at);
    let inv = g_ee.try_inverse()?;
    let rest: Vec<usize> = (e..p).collect();
    let g_er = DMatrix::from_fn(e, rest.len(), |a, b| at(a, rest[b]));
    let t = &inv * &g_er;
    let transfers = (0..rest.len() - 1).map(|o| t[(i, o)]).collect();
    let mut m = Vec::with_capacity(rest.len() * rest.len());
    for &a in &rest {
        for (bi, &b) in rest.iter().enumerate() {
            let through: C = (0..e).map(|x| at(a, x) * t[(x, bi)]).sum();
            m.push(at(a, b) - through);
        }
    }
    Some((transfers, m))
}

/// A condition and its records.
#[derive(Debug, Clone, PartialEq)]
pub struct ConditionRecords<'a> {
    pub condition: TargetCondition,
    pub records: Vec<&'a Record>,
}

/// The records grouped by flight condition (their sidecars' `condition`), in the order they
/// come.
pub fn by_condition(records: &[Record]) -> Result<Vec<ConditionRecords<'_>>, String> {
    let mut out: Vec<ConditionRecords<'_>> = Vec::new();
    for r in records {
        let (request, loading) = crate::ident::record_condition(r)?;
        let c = TargetCondition::Flight(request, loading);
        match out.iter_mut().find(|g| g.condition == c) {
            Some(g) => g.records.push(r),
            None => out.push(ConditionRecords {
                condition: c,
                records: vec![r],
            }),
        }
    }
    Ok(out)
}

/// A record's control channel's model name (`eta_s_percent` -> `eta_s`).
fn control_of(channel: &str) -> &str {
    channel
        .strip_suffix("_percent")
        .or_else(|| channel.strip_suffix("_rad"))
        .unwrap_or(channel)
}

/// The controls a group's records excite: each record's first control, as its sidecar lists
/// it (the one its test input moves).
///
/// Only these are inputs, each response conditioned on the others. The controls a pilot moves
/// to hold the aircraft are not conditioned on: they are the outputs fed back, so conditioning
/// on them correlates the inputs with the part of the output they do not explain, which biases
/// every response (closed-loop identification, Ljung, *System Identification*, 2nd ed., 1999,
/// ch. 13). Seen on the VPM M16's own calm-air 60 mph stick sweep: `q / eta_s` at 0.48 Hz came
/// out at -36.1 dB and -63 deg (the model's flapping linearisation: -35.7 dB, -62 deg) alone,
/// and at -38.3 dB and -48 deg conditioned on the pilot's lateral stick, pedals and throttle.
fn controls(g: &ConditionRecords<'_>) -> Result<Vec<String>, String> {
    let model = cierva_model::aircraft::linearise::CONTROLS;
    let mut excited: Vec<String> = Vec::new();
    for r in &g.records {
        let first = r.meta.controls.first().ok_or_else(|| {
            format!(
                "{}: the sidecar lists no `controls`: the first is the one the test input moves",
                r.path.display()
            )
        })?;
        let c = control_of(first);
        if !first.ends_with("_percent") || !model.contains(&c) {
            return Err(format!(
                "{}: the excited control `{first}` is not one of the aircraft's controls in % of travel ({})",
                r.path.display(),
                model.map(|c| format!("{c}_percent")).join(", ")
            ));
        }
        if !excited.iter().any(|e| e == c) {
            excited.push(c.to_string());
        }
    }
    for r in &g.records {
        if let Some(c) = excited
            .iter()
            .find(|c| !r.meta.controls.contains(&format!("{c}_percent")))
        {
            return Err(format!(
                "{}: the record has no control `{c}_percent` among its sidecar's `controls`, which another record at {} excites",
                r.path.display(),
                g.condition.label()
            ));
        }
    }
    Ok(excited)
}

/// The controls the records of a group carry besides the excited ones (every record's sidecar
/// lists them, in %): a pilot's hold moves them with the test input.
fn other_controls(g: &ConditionRecords<'_>, excited: &[String]) -> Vec<String> {
    cierva_model::aircraft::linearise::CONTROLS
        .iter()
        .filter(|c| !excited.iter().any(|e| e == *c))
        .filter(|c| {
            g.records
                .iter()
                .all(|r| r.meta.controls.contains(&format!("{c}_percent")))
        })
        .map(|c| c.to_string())
        .collect()
}

/// A record's output and inputs (changes from its trim, as identification takes them), as a
/// run of the estimator.
fn run_of(
    rec: &Record,
    inputs: &[String],
    output: &str,
    flown: Option<Flown<'_>>,
) -> Result<fr::RecordSignals, String> {
    let mut config = crate::ident::ConfigSpec::for_model(crate::ident::Setup::Longitudinal);
    config.states = vec![output.to_string()];
    config.kinematics.clear();
    config.controls = inputs
        .iter()
        .map(|c| (c.clone(), format!("{c}_percent")))
        .collect();
    let (xs, us) = crate::ident::signals(rec, &config)?;
    // `signals` gives the controls in the map's (alphabetical) order.
    let names: Vec<&String> = config.controls.keys().collect();
    let ordered = inputs
        .iter()
        .map(|c| {
            let k = names.iter().position(|n| *n == c).unwrap_or(0);
            us[k].clone()
        })
        .collect();
    let measured = xs.into_iter().next().unwrap_or_default();
    let output = match flown {
        Some(f) => f(rec, output, &measured)?,
        None => measured,
    };
    Ok(fr::RecordSignals {
        name: rec.path.display().to_string(),
        inputs: ordered,
        output,
        dt_s: rec.dt_s(),
    })
}

/// A model's output flown with a record's recorded controls, in place of the record's own
/// (`(record, output, the record's output)`): what [`responses_flown`] estimates from
/// ([`super::matched`]).
pub type Flown<'a> = &'a (dyn Fn(&Record, &str, &[f64]) -> Result<Vec<f64>, String> + Sync);

/// The estimator's settings for a group's records.
fn settings(g: &ConditionRecords<'_>, s: &ResponseSettings) -> fr::SpectralSettings {
    // From the first sample to the last, to a tenth of a second, as `cierva
    // frequency-response` takes it.
    let shortest_s = g
        .records
        .iter()
        .map(|r| {
            (r.data.first().map_or(0, Vec::len).saturating_sub(1) as f64 * r.dt_s() * 10.0).floor()
                / 10.0
        })
        .fold(f64::INFINITY, f64::min);
    let windows_s = s
        .windows_s
        .clone()
        .unwrap_or_else(|| fr::SpectralSettings::default_windows_s(shortest_s));
    let longest_s = windows_s.iter().copied().fold(0.0, f64::max);
    let rate_top_hz = g
        .records
        .first()
        .map_or(f64::INFINITY, |r| fr::DEFAULT_TOP_FRACTION / r.dt_s());
    fr::SpectralSettings {
        band_hz: s.band_hz.or(Some([
            fr::composite::MIN_CYCLES / longest_s,
            TOP_HZ.min(rate_top_hz),
        ])),
        windows_s,
        overlap: fr::DEFAULT_OVERLAP,
        points: fr::DEFAULT_POINTS,
    }
}

/// An estimator's error, located in the records.
fn located(e: &fr::FrError, g: &ConditionRecords<'_>, inputs: &[String], output: &str) -> String {
    let file = |run: usize| {
        g.records
            .get(run)
            .map_or(String::new(), |r| r.path.display().to_string())
    };
    match e {
        fr::FrError::NoPower { run, input, .. } => format!(
            "{}: control `{}_percent`: {e}",
            file(*run),
            inputs.get(*input).map_or("?", String::as_str)
        ),
        fr::FrError::NotFinite {
            run,
            signal,
            sample,
        } => {
            let name = inputs
                .get(*signal)
                .map_or(format!("output `{output}`"), |c| {
                    format!("control `{c}_percent`")
                });
            format!("{}: {name} is not finite at sample {sample}", file(*run))
        }
        fr::FrError::WindowTooLong { run, .. }
        | fr::FrError::SampleRate { run, .. }
        | fr::FrError::Lengths { run } => format!("{}: {e}", file(*run)),
        _ => format!("at {}: {e}", g.condition.label()),
    }
}

/// One output's estimate over a group's records, each excited control's response conditioned
/// on the others'.
fn estimate(
    g: &ConditionRecords<'_>,
    inputs: &[String],
    output: &str,
    s: &fr::SpectralSettings,
    flown: Option<Flown<'_>>,
) -> Result<fr::CompositeEstimate, String> {
    let runs = g
        .records
        .iter()
        .map(|r| run_of(r, inputs, output, flown))
        .collect::<Result<Vec<_>, _>>()?;
    fr::estimate(&runs, s).map_err(|e| located(&e, g, inputs, output))
}

/// An estimate's grid: its frequencies, and each window's weight in the composite at each.
struct Grid<'a> {
    frequencies_hz: &'a [f64],
    weights: &'a [Vec<f64>],
    windows_s: &'a [f64],
}

/// The indices of the points to fit, from one input's coherence, random error and response
/// on `grid`: coherent (at least [`COHERENCE_MIN`]), with a finite random error, and each at
/// least [`INDEPENDENT_BINS`] bins of the shortest window the composite leans on (weight at
/// least [`WEIGHT_MIN`]) above the last one kept.
fn spaced(
    grid: &Grid<'_>,
    coherence: &[f64],
    random_error: &[Option<f64>],
    response: &[Option<C>],
) -> Vec<usize> {
    let mut kept: Vec<usize> = Vec::new();
    for (k, &f) in grid.frequencies_hz.iter().enumerate() {
        let usable = coherence[k] >= COHERENCE_MIN
            && random_error[k].is_some_and(f64::is_finite)
            && response[k].is_some_and(|h| h.norm() > 0.0 && h.norm().is_finite());
        if !usable {
            continue;
        }
        let shortest_s = grid.weights[k]
            .iter()
            .zip(grid.windows_s)
            .filter(|(w, _)| **w >= WEIGHT_MIN)
            .map(|(_, t)| *t)
            .fold(f64::INFINITY, f64::min);
        let bin_hz = 1.0 / shortest_s;
        if kept.last().is_none_or(|&j| {
            f - grid.frequencies_hz[j] >= INDEPENDENT_BINS * bin_hz * (1.0 - fr::ROUNDING)
        }) {
            kept.push(k);
        }
    }
    kept
}

/// One input's estimate over a grid, from either estimator: at each frequency, the response,
/// its coherence and normalised random error, the other controls' transfers and the spectra
/// left unexplained ([`RecordedResponse`]'s fields), and the log of the spectrum that weights
/// the estimate's smoothing (the input's, or its cross-spectrum with the excitation).
struct InputEstimate {
    response: Vec<Option<C>>,
    coherence: Vec<f64>,
    random_error: Vec<Option<f64>>,
    split: Vec<Option<(Vec<C>, Vec<C>)>>,
    ln_weighting: Vec<f64>,
}

/// How a condition's responses were estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ResponseEstimator {
    /// From the controls' spectra (`G_uu^-1 G_uy`): biased where a pilot's loop answers the
    /// disturbance.
    Direct,
    /// Against the excitations the records carry ([`fr::referenced`]).
    Referenced,
}

impl ResponseEstimator {
    /// In words, for reports.
    pub fn describe(self) -> &'static str {
        match self {
            ResponseEstimator::Direct => {
                "from the controls (no recorded excitation: biased where a pilot's loop answers the disturbance)"
            }
            ResponseEstimator::Referenced => "against the records' excitations",
        }
    }
}

/// Each record's excitation channels, one per excited control in order, `None` for a control
/// the record does not excite (its excitation is zero there); `None` in all when some record
/// names no excitation for the control it moves (its sidecar's first): the responses are then
/// estimated from the controls.
fn excitations(g: &ConditionRecords<'_>, excited: &[String]) -> Option<Vec<Vec<Option<String>>>> {
    g.records
        .iter()
        .map(|r| {
            let own = r.meta.controls.first()?;
            r.meta.excitation.get(own)?;
            Some(
                excited
                    .iter()
                    .map(|c| r.meta.excitation.get(&format!("{c}_percent")).cloned())
                    .collect(),
            )
        })
        .collect()
}

/// The estimates of each excited control's response of `output` against the records'
/// excitations (`refs`, per record as [`excitations`] gives them), with the other controls'
/// transfers and what none of the controls explains.
fn referenced_estimates(
    g: &ConditionRecords<'_>,
    excited: &[String],
    other: &[String],
    output: &str,
    refs: &[Vec<Option<String>>],
    s: &fr::SpectralSettings,
    flown: Option<Flown<'_>>,
) -> Result<(Vec<InputEstimate>, fr::JointSpectra), String> {
    let (e, m) = (excited.len(), other.len());
    let controls: Vec<String> = excited.iter().chain(other).cloned().collect();
    let mut runs = Vec::with_capacity(g.records.len());
    for (rec, names) in g.records.iter().zip(refs) {
        let run = run_of(rec, &controls, output, flown)?;
        let n = run.output.len();
        let mut inputs: Vec<Vec<f64>> = names
            .iter()
            .map(|name| match name {
                Some(c) => rec.channel(c).map(<[f64]>::to_vec).ok_or_else(|| {
                    format!(
                        "{}: no channel `{c}` (its sidecar's `excitation`)",
                        rec.path.display()
                    )
                }),
                None => Ok(vec![0.0; n]),
            })
            .collect::<Result<_, _>>()?;
        inputs.extend(run.inputs);
        runs.push(fr::RecordSignals { inputs, ..run });
    }
    // Each record's own excitation and the control it moves must have power in the band; the
    // other excitations are zero there, and the other controls may be still.
    let own: Vec<Option<usize>> = g
        .records
        .iter()
        .map(|r| {
            let first = r.meta.controls.first()?;
            excited
                .iter()
                .position(|c| format!("{c}_percent") == *first)
        })
        .collect();
    let required =
        |run: usize, input: usize| own[run].is_some_and(|i| input == i || input == e + i);
    let joint = fr::joint_spectra(&runs, s, e, &required).map_err(|err| {
        let file = |run: usize| {
            g.records
                .get(run)
                .map_or(String::new(), |r| r.path.display().to_string())
        };
        match &err {
            fr::FrError::NoPower { run, input, .. } if *input < e => format!(
                "{}: the excitation `{}` of `{}_percent` (its sidecar's `excitation`): {err}",
                file(*run),
                refs[*run][*input].as_deref().unwrap_or("?"),
                excited[*input]
            ),
            fr::FrError::NoPower { run, input, .. } => format!(
                "{}: control `{}_percent`: {err}",
                file(*run),
                controls.get(*input - e).map_or("?", String::as_str)
            ),
            fr::FrError::NotFinite {
                run,
                signal,
                sample,
            } => {
                let name = match *signal {
                    k if k < e => format!("the excitation of `{}_percent`", excited[k]),
                    k if k < e + controls.len() => format!("control `{}_percent`", controls[k - e]),
                    _ => format!("output `{output}`"),
                };
                format!("{}: {name} is not finite at sample {sample}", file(*run))
            }
            _ => located(&err, g, &controls, output),
        }
    })?;
    let p = 2 * e + m + 1;
    let mut out: Vec<InputEstimate> = (0..e)
        .map(|_| InputEstimate {
            response: Vec::new(),
            coherence: Vec::new(),
            random_error: Vec::new(),
            split: Vec::new(),
            ln_weighting: Vec::new(),
        })
        .collect();
    for (g_k, &n) in joint.spectra.iter().zip(&joint.averages) {
        let r = fr::referenced::referenced(g_k, e, m);
        for (i, o) in out.iter_mut().enumerate() {
            o.ln_weighting.push(g_k[i * p + e + i].norm().ln());
            match &r {
                Some(r) => {
                    o.response.push(Some(r.response[i]));
                    o.coherence.push(r.coherence[i]);
                    o.random_error.push(r.random_error(i, n - e as f64));
                    o.split
                        .push(Some((r.transfers[i].clone(), r.unexplained.clone())));
                }
                None => {
                    o.response.push(None);
                    o.coherence.push(0.0);
                    o.random_error.push(None);
                    o.split.push(None);
                }
            }
        }
    }
    Ok((out, joint))
}

/// The estimates of each excited control's response of `output` from the controls' spectra,
/// each conditioned on the other excited controls, with the other controls' transfers and
/// spectra conditioned on the excited ones.
fn direct_estimates(
    g: &ConditionRecords<'_>,
    excited: &[String],
    other: &[String],
    output: &str,
    s: &fr::SpectralSettings,
    flown: Option<Flown<'_>>,
) -> Result<(Vec<InputEstimate>, fr::CompositeEstimate), String> {
    let all: Vec<String> = excited.iter().chain(other).cloned().collect();
    let est = estimate(g, excited, output, s, flown)?;
    // The same output against every control, for the spectra of what the excited ones leave
    // (the responses themselves are the excited controls' alone).
    let with_all = if other.is_empty() {
        None
    } else {
        Some(estimate(g, &all, output, s, flown)?)
    };
    let p = excited.len() + 1;
    let out = (0..excited.len())
        .map(|i| {
            let r = &est.inputs[i];
            InputEstimate {
                response: r.response.clone(),
                coherence: r.coherence.clone(),
                random_error: r.random_error.clone(),
                split: (0..est.frequencies_hz.len())
                    .map(|k| match &with_all {
                        Some(w) => conditioned(&w.spectra[k], all.len() + 1, excited.len(), i),
                        None => Some((Vec::new(), Vec::new())),
                    })
                    .collect(),
                ln_weighting: est.spectra.iter().map(|g| g[i * p + i].re.ln()).collect(),
            }
        })
        .collect();
    Ok((out, est))
}

/// Every response of every condition's records: each excited control to each output,
/// estimated against the records' excitations where each record carries one for the control
/// it moves ([`ResponseEstimator::Referenced`]), from the controls otherwise.
pub fn responses(
    records: &[Record],
    s: &ResponseSettings,
) -> Result<Vec<RecordedResponse>, String> {
    responses_flown(records, s, None)
}

/// [`responses`], each record's outputs replaced by `flown`'s (a model flown with the
/// record's controls, [`super::matched`]) where it is given: the same estimator, the same
/// grid, the same targets' frequencies.
pub fn responses_flown(
    records: &[Record],
    s: &ResponseSettings,
    flown: Option<Flown<'_>>,
) -> Result<Vec<RecordedResponse>, String> {
    if let Some(o) = &s.outputs
        && let Some(name) = o.iter().find(|n| !OUTPUTS.contains(&n.as_str()))
    {
        return Err(format!(
            "output `{name}` is not one the records measure for a retune (one of {})",
            OUTPUTS.join(", ")
        ));
    }
    let wanted = |input: &str, output: &str| match &s.outputs {
        Some(o) => o.iter().any(|n| n == output),
        None => on_axis(input).contains(&output),
    };
    let mut out = Vec::new();
    for g in by_condition(records)? {
        let excited = controls(&g)?;
        let other = other_controls(&g, &excited);
        let settings = settings(&g, s);
        let refs = excitations(&g, &excited);
        for output in OUTPUTS {
            if !excited.iter().any(|i| wanted(i, output)) {
                continue;
            }
            let (estimates, frequencies_hz, windows_s, weights, estimator) = match &refs {
                Some(refs) => {
                    let (e, j) =
                        referenced_estimates(&g, &excited, &other, output, refs, &settings, flown)?;
                    (
                        e,
                        j.frequencies_hz,
                        j.windows_s,
                        j.weights,
                        ResponseEstimator::Referenced,
                    )
                }
                None => {
                    let (e, est) =
                        direct_estimates(&g, &excited, &other, output, &settings, flown)?;
                    (
                        e,
                        est.frequencies_hz,
                        est.windows_s,
                        est.weights,
                        ResponseEstimator::Direct,
                    )
                }
            };
            let grid = Grid {
                frequencies_hz: &frequencies_hz,
                weights: &weights,
                windows_s: &windows_s,
            };
            for (i, input) in excited.iter().enumerate() {
                if !wanted(input, output) {
                    continue;
                }
                out.push(recorded(
                    &g,
                    input,
                    output,
                    &other,
                    &estimates[i],
                    &grid,
                    estimator,
                ));
            }
        }
    }
    Ok(out)
}

/// One input's [`RecordedResponse`] from its estimate on `grid`.
fn recorded(
    g: &ConditionRecords<'_>,
    input: &str,
    output: &str,
    other: &[String],
    est: &InputEstimate,
    grid: &Grid<'_>,
    estimator: ResponseEstimator,
) -> RecordedResponse {
    let f = grid.frequencies_hz;
    let mut points = Vec::new();
    let mut random_error = Vec::new();
    let (mut window_moment_hz2, mut input_log_slope_per_hz) = (Vec::new(), Vec::new());
    let (mut others, mut unexplained) = (Vec::new(), Vec::new());
    let mut index = vec![None; f.len()];
    for k in 0..f.len() {
        if let (Some(h), Some(e), Some((t, m))) =
            (est.response[k], est.random_error[k], est.split[k].clone())
            && h.norm() > 0.0
            && h.norm().is_finite()
            && e.is_finite()
        {
            others.push(other.iter().cloned().zip(t).collect());
            unexplained.push(m);
            index[k] = Some(points.len());
            points.push(Point {
                frequency_hz: f[k],
                response: h,
                coherence: est.coherence[k],
            });
            random_error.push(e);
            window_moment_hz2.push(spectral_window_moment(grid.windows_s, &grid.weights[k]));
            let (a, b) = (k.saturating_sub(1), (k + 1).min(f.len() - 1));
            input_log_slope_per_hz
                .push((est.ln_weighting[b] - est.ln_weighting[a]) / (f[b] - f[a]));
        }
    }
    let used = spaced(grid, &est.coherence, &est.random_error, &est.response)
        .into_iter()
        .filter_map(|k| index[k])
        .collect();
    RecordedResponse {
        condition: g.condition,
        input: input.to_string(),
        output: output.to_string(),
        estimator,
        points,
        random_error,
        used,
        other_controls: other.to_vec(),
        others,
        unexplained,
        window_moment_hz2,
        input_log_slope_per_hz,
    }
}

/// The fit's targets: each used point's real and imaginary parts, with the record's other
/// controls' transfers, and the standard error [`RecordedResponse::standard_error`] with `models`'s
/// responses to those controls (one per condition, [`super::subject::Retuned::responses`]
/// with its neighbourhood). A point whose [`resolution_bias`] by `models` exceeds
/// [`RESOLUTION_BIAS_MAX`] of its random error is left out.
pub fn targets(
    responses: &[RecordedResponse],
    models: &[(TargetCondition, crate::run::responses::Responses)],
) -> Result<Vec<Target>, String> {
    let mut out = Vec::new();
    for r in responses {
        let model = models
            .iter()
            .find(|(c, _)| *c == r.condition)
            .map(|(_, m)| m)
            .ok_or_else(|| format!("no model responses at {}", r.condition.label()))?;
        for &k in &r.used {
            let p = &r.points[k];
            // The bias of the response to the swept control (the other controls' transfers are
            // measured on the grid only, too coarse for their curvature).
            let [below, above] = neighbours(p.frequency_hz);
            let h = [
                model.at(&r.input, &r.output, below)?,
                model.at(&r.input, &r.output, p.frequency_hz)?,
                model.at(&r.input, &r.output, above)?,
            ];
            let bias = resolution_bias(
                p.frequency_hz,
                h,
                r.window_moment_hz2[k],
                r.input_log_slope_per_hz[k],
            );
            // A NaN bias is no target either.
            let small = bias.norm() <= RESOLUTION_BIAS_MAX * r.random_error[k];
            if !small {
                continue;
            }
            let secondary = r
                .other_controls
                .iter()
                .map(|c| model.at(c, &r.output, p.frequency_hz))
                .collect::<Result<Vec<_>, _>>()?;
            let se = r.standard_error(k, &secondary);
            for (imaginary, value) in [(false, p.response.re), (true, p.response.im)] {
                let point = ResponsePoint {
                    others: r.others[k].clone(),
                    ..ResponsePoint::new(&r.input, &r.output, p.frequency_hz, imaginary)
                };
                out.push(Target {
                    condition: r.condition,
                    measure: Measure::Response(point),
                    reference: value,
                    standard_error: se,
                    bounds: None,
                });
            }
        }
    }
    Ok(out)
}

/// Each condition of `responses` with every frequency its responses are estimated at, and
/// with `neighbourhood` the [`neighbours`] of every used point too: where a model's responses
/// are wanted.
pub fn frequencies_by_condition(
    responses: &[RecordedResponse],
    neighbourhood: bool,
) -> Vec<(TargetCondition, Vec<f64>)> {
    let mut out: Vec<(TargetCondition, Vec<f64>)> = Vec::new();
    for r in responses {
        let k = match out.iter().position(|(c, _)| *c == r.condition) {
            Some(k) => k,
            None => {
                out.push((r.condition, Vec::new()));
                out.len() - 1
            }
        };
        let frequencies = &mut out[k].1;
        for (i, p) in r.points.iter().enumerate() {
            let [below, above] = neighbours(p.frequency_hz);
            let with: &[f64] = if neighbourhood && r.used.contains(&i) {
                &[below, p.frequency_hz, above]
            } else {
                &[p.frequency_hz]
            };
            for f in with {
                if !frequencies.contains(f) {
                    frequencies.push(*f);
                }
            }
        }
    }
    out
}

/// One response of the records beside the model's, before and after the retune.
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseComparison {
    pub condition: String,
    pub input: String,
    pub output: String,
    /// The records' response at every frequency it is estimated.
    pub points: Vec<Point>,
    /// The model's at the same frequencies.
    pub before: Vec<rustfft::num_complex::Complex64>,
    pub after: Vec<rustfft::num_complex::Complex64>,
    /// Tischler's mismatch cost `J` over the coherent band
    /// ([`crate::checks::frequency_response::mismatch_cost`]); None with no coherent frequency.
    pub j_before: Option<f64>,
    pub j_after: Option<f64>,
    pub frequencies_in_band: usize,
}

/// Each response of the records against the model's before (`before`: the uncorrected
/// model's responses the retune computed for its targets, at every frequency of every
/// response) and after (`after`: the retuned model's, at least at every frequency of every
/// response, [`super::subject::Retuned::responses`]).
pub fn compare(
    before: &[(TargetCondition, crate::run::responses::Responses)],
    after: &[(TargetCondition, crate::run::responses::Responses)],
    responses: &[RecordedResponse],
) -> Result<Vec<ResponseComparison>, String> {
    use crate::checks::frequency_response::mismatch_cost;
    let (b, a) = (before, after);
    let mut out = Vec::new();
    for r in responses {
        let model = |m: &[(TargetCondition, crate::run::responses::Responses)]| {
            let (_, m) = m
                .iter()
                .find(|(c, _)| *c == r.condition)
                .expect("every condition");
            r.points
                .iter()
                .zip(&r.others)
                .map(|(p, o)| m.as_flown(&r.input, &r.output, p.frequency_hz, o))
                .collect::<Result<Vec<_>, _>>()
        };
        let (mb, ma) = (model(b)?, model(a)?);
        let (cb, ca) = (mismatch_cost(&r.points, &mb), mismatch_cost(&r.points, &ma));
        out.push(ResponseComparison {
            condition: r.condition.label(),
            input: r.input.clone(),
            output: r.output.clone(),
            points: r.points.clone(),
            before: mb,
            after: ma,
            j_before: cb.map(|c| c.j),
            j_after: ca.map(|c| c.j),
            frequencies_in_band: cb.map_or(0, |c| c.frequencies),
        });
    }
    Ok(out)
}

/// Fewest clusters (frequencies) for the cluster-robust covariance: with fewer, its estimate of
/// the misfit's spread rests on too few independent residual groups to be trusted (the
/// small-sample correction `C / (C - 1)` alone is already 1.1 at ten), and the curvature's
/// standard errors stand.
pub const MIN_CLUSTERS: usize = 10;

/// Cluster-robust ("sandwich") standard errors of the fitted parameters (Liang and Zeger 1986,
/// *Biometrika* 73, 13-22; White 1980 for uncorrelated residuals), clusters being the
/// frequencies of one condition:
/// `(A' A)^-1 [sum_c (A_c' r_c)(A_c' r_c)'] (A' A)^-1 x C / (C - 1) x (N - 1) / (N - p)`
/// (the CR1 small-sample factors), `A` the Jacobian and `r` the residuals, each scaled by its
/// target's standard error, `C` clusters, `N` targets, `p` parameters.
///
/// Why not the curvature's `(A' A)^-1` alone: that holds when every target's error is
/// independent and as large as its standard error says. A frequency's responses of the
/// several outputs (and its real and imaginary parts) share the input's spectrum and, in
/// turbulence or under a pilot, the disturbances the input does not explain, so their errors
/// are correlated. The sandwich takes the misfit's spread from the residuals, grouped by
/// frequency, instead of from the targets' stated errors.
///
/// Why never below the curvature's: the sandwich's middle is estimated from the clusters' own
/// scores, and with a dozen or two clusters (one record's coherent frequencies) it scatters
/// widely and most often low (the small-sample bias of cluster-robust variances, Cameron and
/// Miller 2015, *J. Human Resources* 50, 317-372, Sec. VI). Seen in the coverage trials: one
/// record at 50 mph in turbulence of 0.25 m/s gave the hub factor a sandwich error of 0.013
/// against the curvature's 0.045, and missed the truth by 5.9 of the former. Where the stated
/// errors hold, the curvature's error is right and the sandwich can only lose coverage by
/// going below it; where they are too small, the sandwich is the larger. So each parameter's
/// error is the larger of the two. `curvature` is returned where there are fewer than
/// [`MIN_CLUSTERS`] clusters, and for a parameter the curvature already calls unseen
/// (infinite).
pub fn robust_standard_errors(
    problem: &crate::fit::Problem,
    y: &[f64],
    jacobian: &[Vec<f64>],
    curvature: &[f64],
) -> Vec<f64> {
    let n = problem.parameters.len();
    let mut keys: Vec<(TargetCondition, f64)> = Vec::new();
    let mut cluster = Vec::with_capacity(problem.targets.len());
    for t in &problem.targets {
        let f = match &t.measure {
            Measure::Response(r) => r.frequency_hz,
            _ => f64::NAN,
        };
        let k = keys
            .iter()
            .position(|(c, g)| *c == t.condition && g.to_bits() == f.to_bits())
            .unwrap_or_else(|| {
                keys.push((t.condition, f));
                keys.len() - 1
            });
        cluster.push(k);
    }
    let clusters = keys.len();
    let targets = problem.targets.len();
    if clusters < MIN_CLUSTERS || targets <= n || curvature.iter().any(|s| !s.is_finite()) {
        return curvature.to_vec();
    }
    let mut bread = nalgebra::DMatrix::<f64>::zeros(n, n);
    let mut scores = vec![nalgebra::DVector::<f64>::zeros(n); clusters];
    for (k, t) in problem.targets.iter().enumerate() {
        let a = nalgebra::DVector::from_fn(n, |i, _| jacobian[k][i] / t.standard_error);
        let r = (y[k] - t.reference) / t.standard_error;
        bread += &a * a.transpose();
        scores[cluster[k]] += &a * r;
    }
    let Some(inverse) = bread.try_inverse() else {
        return curvature.to_vec();
    };
    let mut meat = nalgebra::DMatrix::<f64>::zeros(n, n);
    for g in &scores {
        meat += g * g.transpose();
    }
    let factor = clusters as f64 / (clusters as f64 - 1.0) * (targets as f64 - 1.0)
        / (targets as f64 - n as f64);
    let covariance = &inverse * meat * &inverse * factor;
    (0..n)
        .map(|i| {
            let v = covariance[(i, i)];
            if v.is_finite() && v > 0.0 {
                v.sqrt().max(curvature[i])
            } else {
                curvature[i]
            }
        })
        .collect()
}
