//! Non-parametric frequency responses from records: Welch's spectra ([`spectra`]) over several
//! window lengths, composited per frequency ([`composite`]), with coherence, the random error
//! it implies, and responses conditioned on correlated inputs; or, where the records carry the
//! excitation added to a control, estimated against it ([`referenced`]).
//!
//! Pure numerics: runs in, responses out, errors as [`FrError`] (the command line locates
//! them in the files). Several runs (records) are averaged as CIFER concatenates them: each
//! segment of each run is one average; the signals are never joined end to end.
//!
//! Settings: Hann windows ([`crate::ident::fourier::hann`]) overlapping by
//! [`DEFAULT_OVERLAP`]; a log-spaced grid of `points` frequencies over a band, by default from
//! [`composite::MIN_CYCLES`] periods of the longest window to [`DEFAULT_TOP_FRACTION`] of the
//! sample rate.

pub mod composite;
pub mod referenced;
/// Welch's spectra, built in `cierva-fft` (optimised in test builds: the crate's doc).
pub use cierva_fft::spectra;

use composite::MIN_CYCLES;
use rustfft::num_complex::Complex64 as C;
use spectra::Segmenting;
use thiserror::Error;

/// Default overlap of consecutive segments, a fraction of the window. At an overlap of two
/// thirds or more (a hop of `L / m`, `m >= 3`) the squared Hann windows of consecutive
/// segments add to a constant, so every instant of a record weighs the same in the averaged
/// spectra; at 50 % their sum ripples with the hop. Random data do not mind (50 % recovers
/// most of the averages tapering costs, Welch 1967), but a sweep ties frequency to time and
/// sees the ripple as bias: the known-answer test
/// (`a_linear_models_record_gives_its_analytic_response`) found the stated 95 % intervals
/// holding the model's response at 56 of 100 frequencies at 50 % overlap, 92 at 67 %, 93 at
/// 75 %, 96 at 80 % and 95 at 90 %, the worst phase error 2.5 deg at 50 % and 1.5 at 80 %.
/// [`spectra::averages_covariance`] counts the overlap's correlated averages either way; 80 %
/// costs 9.5 ms against 5.2 ms at 50 % (`cierva bench`). `--overlap` sets it.
pub const DEFAULT_OVERLAP: f64 = 0.8;

/// Largest overlap accepted: at 95 % consecutive segments are 20 samples of a 400-sample
/// window apart and nearly identical; beyond it the transforms multiply for no averages.
pub const MAX_OVERLAP: f64 = 0.95;

/// The default band's top, a fraction of the sample rate (two fifths of the Nyquist
/// frequency): the upper part of the band below Nyquist is where a record's anti-aliasing
/// filter lags and aliased content lands. A choice, not a source's number; `--band-hz` sets it.
pub const DEFAULT_TOP_FRACTION: f64 = 0.2;

/// Most windows in a composite: the weights are found by trying every subset of the windows
/// ([`composite::weights`], `2^w - 1` small solves at each frequency): a composite is of a
/// handful of windows, and eight is already 255 solves a frequency.
pub const MAX_WINDOWS: usize = 8;

/// Default frequencies in the grid (the 100).
pub const DEFAULT_POINTS: usize = 100;

/// Most frequencies in the grid: the transform table is frequencies times the longest window's
/// samples (2000 by the 6000 samples of a 60 s window at 100 Hz is 192 MB); a Bode plot needs a
/// few hundred.
pub const MAX_POINTS: usize = 2000;

/// Fewest samples in a window: a window this short holds four points of a Hann taper's main
/// lobe per side; shorter windows have no frequencies inside the band's grid worth estimating.
pub const MIN_WINDOW_SAMPLES: usize = 16;

/// An input whose power in the band is below this fraction of its variance has no power there:
/// a real excitation puts a sizeable part of its variance in the band (a sweep nearly all of
/// it, white noise the band's share of the Nyquist band), whereas a channel held constant, or
/// moved only outside the band, leaves rounding and the Hann window's leakage (its sidelobes
/// fall 18 dB an octave from -31 dB) far below it.
pub const NO_POWER_FRACTION: f64 = 1e-6;

/// A channel whose standard deviation is below this fraction of its largest magnitude is
/// constant (double precision's rounding of its values is 1e-16 of them).
pub const CONSTANT_FRACTION: f64 = 1e-12;

/// Relative slack when comparing numbers computed two ways (a sample interval from two
/// sidecars' rates, a band's bottom from a window's length and the grid's first point from its
/// logarithm): their rounding, about 1e-15, with room to spare, and far below any real
/// difference (a record at 100 Hz against one at 100.0001 Hz is 1e-6 apart).
pub const ROUNDING: f64 = 1e-9;

/// One record's signals.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordSignals {
    /// What the run is called in messages (its file).
    pub name: String,
    /// The inputs, the first the one whose response is wanted, the others conditioned on.
    pub inputs: Vec<Vec<f64>>,
    pub output: Vec<f64>,
    pub dt_s: f64,
}

/// How the spectra are estimated.
#[derive(Debug, Clone, PartialEq)]
pub struct SpectralSettings {
    pub windows_s: Vec<f64>,
    /// Fraction of a window by which consecutive segments overlap.
    pub overlap: f64,
    pub points: usize,
    /// The band, Hz; by default from the longest window and the sample rate.
    pub band_hz: Option<[f64; 2]>,
}

impl SpectralSettings {
    /// Default windows for records whose shortest lasts `record_s`: half, a quarter and an
    /// eighth of it (at 80 % overlap the longest gives six segments, the shortest thirty-six).
    pub fn default_windows_s(record_s: f64) -> Vec<f64> {
        vec![record_s / 8.0, record_s / 4.0, record_s / 2.0]
    }
}

/// What is wrong with the runs or settings; `run` is an index into the runs.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FrError {
    #[error("no records")]
    NoRuns,
    #[error("the runs have different numbers of inputs")]
    Inputs,
    #[error(
        "sampled every {dt_s} s where the first record is sampled every {first_dt_s} s: spectra of records at different sample rates cannot be averaged"
    )]
    SampleRate {
        run: usize,
        dt_s: f64,
        first_dt_s: f64,
    },
    #[error("signal {signal} is not finite at sample {sample}")]
    NotFinite {
        run: usize,
        signal: usize,
        sample: usize,
    },
    #[error("signals of different lengths")]
    Lengths { run: usize },
    #[error("window {window_s} s is longer than the record ({record_s} s)")]
    WindowTooLong {
        run: usize,
        window_s: f64,
        record_s: f64,
    },
    #[error(
        "input {input} has no power in the band {lo_hz:.4}-{hi_hz:.4} Hz ({fraction:.1e} of its variance there; below {NO_POWER_FRACTION:e} is none)"
    )]
    NoPower {
        run: usize,
        input: usize,
        lo_hz: f64,
        hi_hz: f64,
        fraction: f64,
    },
    #[error("{0}")]
    Settings(String),
}

/// One input's (conditioned) response over the grid; `None` where it cannot be estimated.
#[derive(Debug, Clone, PartialEq)]
pub struct InputResponse {
    pub response: Vec<Option<C>>,
    /// Partial coherence (ordinary with one input); 0 where nothing is estimated.
    pub coherence: Vec<f64>,
    /// The normalised random error of `|H|`, also the phase's standard deviation in radians.
    pub random_error: Vec<Option<f64>>,
    /// The half-width of the 95 % interval of `ln |H|` and of the phase (rad).
    pub random_error_95: Vec<Option<f64>>,
}

impl InputResponse {
    /// `20 log10 |H|`, dB.
    pub fn magnitude_db(&self) -> Vec<Option<f64>> {
        self.response
            .iter()
            .map(|h| h.map(|h| 20.0 * h.norm().log10()).filter(|v| v.is_finite()))
            .collect()
    }

    /// The phase in (-180, 180], deg (not unwrapped).
    pub fn phase_deg(&self) -> Vec<Option<f64>> {
        self.response
            .iter()
            .map(|h| h.map(|h| h.arg().to_degrees()))
            .collect()
    }
}

/// The composite estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct CompositeEstimate {
    pub frequencies_hz: Vec<f64>,
    pub windows_s: Vec<f64>,
    pub overlap: f64,
    /// One per input, in the runs' order.
    pub inputs: Vec<InputResponse>,
    pub multiple_coherence: Vec<f64>,
    /// The composite's equivalent number of independent averages, per frequency.
    pub averages: Vec<f64>,
    /// Each window's weight in the composite, `[frequency][window]`.
    pub weights: Vec<Vec<f64>>,
    /// The composite's auto- and cross-spectra at each frequency: `p x p` row-major, `p` the
    /// inputs and then the output, `[a * p + b]` being `G_ab = E[X_a* X_b]` (the convention of
    /// `H = G_xx^-1 G_xy`).
    pub spectra: Vec<Vec<C>>,
}

/// `points` frequencies evenly spaced in logarithm from `lo` to `hi`.
pub fn log_grid(lo_hz: f64, hi_hz: f64, points: usize) -> Vec<f64> {
    let (a, b) = (lo_hz.ln(), hi_hz.ln());
    let step = (b - a) / (points.max(2) - 1) as f64;
    (0..points).map(|k| (a + step * k as f64).exp()).collect()
}

/// Checks the runs: at least one, one sample interval, signals of one length per run, finite.
fn check_runs(runs: &[RecordSignals]) -> Result<(f64, usize), FrError> {
    let first = runs.first().ok_or(FrError::NoRuns)?;
    let dt = first.dt_s;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(FrError::Settings(
            "the sample interval must be positive".into(),
        ));
    }
    let q = first.inputs.len();
    if q == 0 {
        return Err(FrError::Settings("no input".into()));
    }
    for (run, r) in runs.iter().enumerate() {
        if r.inputs.len() != q {
            return Err(FrError::Inputs);
        }
        if (r.dt_s - dt).abs() > ROUNDING * dt {
            return Err(FrError::SampleRate {
                run,
                dt_s: r.dt_s,
                first_dt_s: dt,
            });
        }
        let n = r.output.len();
        for (signal, x) in r.inputs.iter().chain([&r.output]).enumerate() {
            if x.len() != n {
                return Err(FrError::Lengths { run });
            }
            if let Some(sample) = x.iter().position(|v| !v.is_finite()) {
                return Err(FrError::NotFinite {
                    run,
                    signal,
                    sample,
                });
            }
        }
    }
    Ok((dt, q))
}

/// The windows' segmenting and the band, checked against the runs.
fn plan(
    runs: &[RecordSignals],
    dt: f64,
    s: &SpectralSettings,
) -> Result<(Vec<Segmenting>, Vec<f64>), FrError> {
    let bad = |m: String| Err(FrError::Settings(m));
    if s.windows_s.is_empty() || !s.windows_s.iter().all(|w| w.is_finite() && *w > 0.0) {
        return bad("windows must be positive lengths in seconds".into());
    }
    if s.windows_s.len() > MAX_WINDOWS {
        return bad(format!(
            "{} windows: give at most {MAX_WINDOWS}",
            s.windows_s.len()
        ));
    }
    if !(s.overlap.is_finite() && (0.0..=MAX_OVERLAP).contains(&s.overlap)) {
        return bad(format!(
            "overlap {} is not in [0, {MAX_OVERLAP}]",
            s.overlap
        ));
    }
    if !(2..=MAX_POINTS).contains(&s.points) {
        return bad(format!("{} frequencies: give 2 to {MAX_POINTS}", s.points));
    }
    let mut segs = Vec::new();
    for &w in &s.windows_s {
        let len = (w / dt).round() as usize;
        if len < MIN_WINDOW_SAMPLES {
            return bad(format!(
                "window {w} s is {len} samples: give at least {MIN_WINDOW_SAMPLES}"
            ));
        }
        for (run, r) in runs.iter().enumerate() {
            if len > r.output.len() {
                return Err(FrError::WindowTooLong {
                    run,
                    window_s: w,
                    record_s: r.output.len() as f64 * dt,
                });
            }
        }
        let hop = ((len as f64) * (1.0 - s.overlap)).round().max(1.0) as usize;
        segs.push(Segmenting { len, hop });
    }
    let longest = s.windows_s.iter().copied().fold(0.0, f64::max);
    let floor = MIN_CYCLES / longest;
    let nyquist = 0.5 / dt;
    let [lo, hi] = s.band_hz.unwrap_or([floor, DEFAULT_TOP_FRACTION / dt]);
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo && hi <= nyquist) {
        return bad(format!(
            "band {lo}-{hi} Hz: give 0 < low < high <= the Nyquist frequency {nyquist} Hz"
        ));
    }
    if lo < floor * (1.0 - ROUNDING) {
        return bad(format!(
            "band starts at {lo} Hz, below {MIN_CYCLES} periods of the longest window ({longest} s: {floor:.4} Hz); give a longer window or a higher band"
        ));
    }
    Ok((segs, log_grid(lo, hi, s.points)))
}

/// An input with no power in the band in a run where `required(run, input)` says it must
/// have some.
fn check_power(
    runs: &[RecordSignals],
    shortest: &spectra::WindowSpectra,
    freqs: &[f64],
    required: &dyn Fn(usize, usize) -> bool,
) -> Result<(), FrError> {
    for (run, r) in runs.iter().enumerate() {
        for (input, x) in r.inputs.iter().enumerate() {
            if !required(run, input) {
                continue;
            }
            let n = x.len() as f64;
            let mean = x.iter().sum::<f64>() / n;
            let variance = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
            let largest = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let power = shortest.band_power[run][input];
            let fraction = if variance.sqrt() <= CONSTANT_FRACTION * largest || variance == 0.0 {
                0.0
            } else {
                power / variance
            };
            if fraction < NO_POWER_FRACTION {
                return Err(FrError::NoPower {
                    run,
                    input,
                    lo_hz: freqs[0],
                    hi_hz: freqs[freqs.len() - 1],
                    fraction,
                });
            }
        }
    }
    Ok(())
}

/// The windows' spectra of the runs over the band's grid, checked (`required(run, input)`:
/// the inputs that must have power in the band), with the normalised covariance of their
/// averages.
#[allow(clippy::type_complexity)]
fn windows_of(
    runs: &[RecordSignals],
    dt: f64,
    settings: &SpectralSettings,
    required: &dyn Fn(usize, usize) -> bool,
) -> Result<
    (
        Vec<spectra::WindowSpectra>,
        nalgebra::DMatrix<f64>,
        Vec<f64>,
    ),
    FrError,
> {
    let (segs, freqs) = plan(runs, dt, settings)?;
    let signals: Vec<Vec<Vec<f64>>> = runs
        .iter()
        .map(|r| r.inputs.iter().cloned().chain([r.output.clone()]).collect())
        .collect();
    let views: Vec<&[Vec<f64>]> = signals.iter().map(Vec::as_slice).collect();
    let windows: Vec<spectra::WindowSpectra> = segs
        .iter()
        .map(|&seg| spectra::window_spectra(&views, dt, seg, &freqs))
        .collect();
    let shortest = (0..segs.len())
        .min_by_key(|&i| segs[i].len)
        .expect("at least one window");
    check_power(runs, &windows[shortest], &freqs, required)?;
    let lengths: Vec<usize> = runs.iter().map(|r| r.output.len()).collect();
    let r = spectra::averages_covariance(&lengths, dt, &segs);
    Ok((windows, r, freqs))
}

/// The composite frequency responses of the runs' output to each of their inputs (the first
/// conditioned on the others, and each of the others likewise).
pub fn estimate(
    runs: &[RecordSignals],
    settings: &SpectralSettings,
) -> Result<CompositeEstimate, FrError> {
    let (dt, q) = check_runs(runs)?;
    let (windows, r, freqs) = windows_of(runs, dt, settings, &|_, _| true)?;
    Ok(combine(&windows, &r, &freqs, settings, q))
}

/// The composite's spectra of every signal of the runs (their inputs, then their output),
/// without responses, for an estimator of its own ([`referenced`]): the windows are weighted
/// for a response to the first `fitted` inputs. `required(run, input)` says which inputs must
/// have power in the band in which run (an excitation applied in some records and not others
/// is zero in the others).
pub fn joint_spectra(
    runs: &[RecordSignals],
    settings: &SpectralSettings,
    fitted: usize,
    required: &dyn Fn(usize, usize) -> bool,
) -> Result<JointSpectra, FrError> {
    let (dt, q) = check_runs(runs)?;
    if !(1..=q).contains(&fitted) {
        return Err(FrError::Settings(format!(
            "{fitted} fitted inputs of {q}: give 1 to {q}"
        )));
    }
    let (windows, r, freqs) = windows_of(runs, dt, settings, required)?;
    let (spectra, averages, weights) = composite_spectra(&windows, &r, &freqs, settings, fitted);
    Ok(JointSpectra {
        frequencies_hz: freqs,
        windows_s: settings.windows_s.clone(),
        overlap: settings.overlap,
        averages,
        weights,
        spectra,
    })
}

/// The composite's spectra, without responses ([`joint_spectra`]); fields as
/// [`CompositeEstimate`]'s, `spectra` over every signal (the inputs, then the output).
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpectra {
    pub frequencies_hz: Vec<f64>,
    pub windows_s: Vec<f64>,
    pub overlap: f64,
    pub averages: Vec<f64>,
    pub weights: Vec<Vec<f64>>,
    pub spectra: Vec<Vec<C>>,
}

/// At every frequency, the windows' composite of the spectra for a response to `fitted`
/// inputs: the spectra (`p x p` row-major), the equivalent number of averages and each window's
/// weight.
#[allow(clippy::type_complexity)]
fn composite_spectra(
    windows: &[spectra::WindowSpectra],
    r: &nalgebra::DMatrix<f64>,
    freqs: &[f64],
    settings: &SpectralSettings,
    fitted: usize,
) -> (Vec<Vec<C>>, Vec<f64>, Vec<Vec<f64>>) {
    let fitted = fitted as f64;
    let (mut out, mut averages, mut weights) = (Vec::new(), Vec::new(), Vec::new());
    for (f, &hz) in freqs.iter().enumerate() {
        let cand: Vec<usize> = (0..windows.len())
            .filter(|&i| hz * settings.windows_s[i] >= MIN_CYCLES * (1.0 - ROUNDING))
            .collect();
        // Each window's random error relative to the others' at a coherence they share (see
        // `composite`): `1 / sqrt(n_i - q)`.
        let eps: Vec<f64> = cand
            .iter()
            .map(|&i| {
                let dof = 1.0 / r[(i, i)] - fitted;
                if dof > 0.0 {
                    dof.recip().sqrt()
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        let a = composite::weights(&cand, &eps, r);
        let n = composite::equivalent_averages(&cand, &a, r);
        let p2 = windows[0].g[f].len();
        let mut g = vec![C::new(0.0, 0.0); p2];
        for (k, &i) in cand.iter().enumerate() {
            for (v, w) in g.iter_mut().zip(&windows[i].g[f]) {
                *v += w * a[k];
            }
        }
        let mut all = vec![0.0; windows.len()];
        for (k, &i) in cand.iter().enumerate() {
            all[i] = a[k];
        }
        weights.push(all);
        averages.push(n);
        out.push(g);
    }
    (out, averages, weights)
}

/// The composite at every frequency.
fn combine(
    windows: &[spectra::WindowSpectra],
    r: &nalgebra::DMatrix<f64>,
    freqs: &[f64],
    settings: &SpectralSettings,
    q: usize,
) -> CompositeEstimate {
    let p = q + 1;
    let fitted = q as f64;
    let mut inputs = vec![
        InputResponse {
            response: Vec::new(),
            coherence: Vec::new(),
            random_error: Vec::new(),
            random_error_95: Vec::new(),
        };
        q
    ];
    let (spectra, averages, weights) = composite_spectra(windows, r, freqs, settings, q);
    let mut multiple = Vec::with_capacity(freqs.len());
    for (g, &n) in spectra.iter().zip(&averages) {
        let solved = composite::solve(g, p);
        multiple.push(solved.as_ref().map_or(0.0, |s| s.multiple_coherence));
        for (i, out) in inputs.iter_mut().enumerate() {
            let gamma = solved.as_ref().map_or(0.0, |s| s.coherence[i]);
            out.response.push(solved.as_ref().map(|s| s.response[i]));
            out.coherence.push(gamma);
            let e = composite::random_error(gamma, n - fitted);
            out.random_error.push(e);
            out.random_error_95
                .push(composite::interval_95(e, n - fitted));
        }
    }
    CompositeEstimate {
        frequencies_hz: freqs.to_vec(),
        windows_s: settings.windows_s.clone(),
        overlap: settings.overlap,
        inputs,
        multiple_coherence: multiple,
        averages,
        weights,
        spectra,
    }
}
