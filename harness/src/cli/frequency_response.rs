//! `cierva frequency-response`: a non-parametric frequency response from flight records, with
//! coherence and random error (`ident::frequency_response`).

use super::*;
use cierva_harness::ident::frequency_response::{self as fr, CompositeEstimate, FrError};
use cierva_harness::inputs::record::{self, Record};
use cierva_harness::inputs::yaml::InputError;

/// Output of `frequency-response`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ResponseFormat {
    Text,
    Json,
    /// One row per frequency: `frequency_hz,magnitude_db,phase_deg,coherence,random_error`.
    Csv,
}

/// A non-parametric frequency response from flight records: Welch's auto- and
/// cross-spectra (Hann windows, 80 % overlap by default) over several window lengths,
/// composited per frequency to minimise the random error (after CIFER, Tischler and Remple
/// 2012, ch. 7-8), with coherence and the random error it implies (Bendat and Piersol 2010,
/// ch. 9), on a log-spaced grid. Several records are averaged (not joined). With
/// `--conditioned-on`, the response is conditioned on the other inputs (`H = G_xx^-1 G_xy`)
/// and its coherence is the partial coherence.
///
/// `random_error` is the normalised random error of the magnitude (its standard deviation
/// over |H|), which is also the phase's standard deviation in radians; `random_error_95`
/// the half-width of the 95 % interval of ln|H| and of the phase. Exit code 2 for bad
/// input (records at different sample rates, a missing channel, a window longer than a
/// record, an input with no power in the band).
///
/// Example: `cierva frequency-response /tmp/vpm-m16-70mph-sweep.csv --input eta_s_percent
/// --output q_rad_s --windows-s 10 20 40 --format json`
#[derive(clap::Args)]
pub(crate) struct FrequencyResponseArgs {
    /// Records (CSV, with the YAML sidecar beside each): their spectra are averaged together.
    #[arg(required = true)]
    pub(crate) records: Vec<PathBuf>,
    /// The input channel as the records name it, units in the name (e.g. `eta_s_rad`).
    #[arg(long)]
    pub(crate) input: String,
    /// The output channel (e.g. `q_rad_s`).
    #[arg(long)]
    pub(crate) output: String,
    /// Window lengths, s (default: an eighth, a quarter and half of the shortest record).
    #[arg(long, num_args = 1..)]
    pub(crate) windows_s: Vec<f64>,
    /// Overlap of consecutive segments, a fraction of the window.
    #[arg(long, default_value_t = cierva_harness::ident::frequency_response::DEFAULT_OVERLAP)]
    pub(crate) overlap: f64,
    /// Frequencies in the log-spaced grid.
    #[arg(long, default_value_t = cierva_harness::ident::frequency_response::DEFAULT_POINTS)]
    pub(crate) frequencies: usize,
    /// The band, Hz (default: five periods of the longest window to a fifth of the sample rate).
    #[arg(long, num_args = 2, value_names = ["LO", "HI"])]
    pub(crate) band_hz: Option<Vec<f64>>,
    /// Other inputs (channels) to condition the response on, when the records' inputs are
    /// correlated (a pilot's hold moves the other controls with the one swept).
    #[arg(long, num_args = 1..)]
    pub(crate) conditioned_on: Vec<String>,
    #[arg(long, value_enum, default_value_t = ResponseFormat::Text)]
    pub(crate) format: ResponseFormat,
}

/// Loads the records with the channels the response needs, all at one sample rate.
fn load(a: &FrequencyResponseArgs) -> Result<Vec<Record>, Error> {
    let mut needed = vec!["time_s", a.input.as_str(), a.output.as_str()];
    needed.extend(a.conditioned_on.iter().map(String::as_str));
    let mut records: Vec<Record> = Vec::new();
    for p in &a.records {
        let r = record::load_with(p, &needed, false)?;
        if let Some(first) = records.first()
            && (r.meta.sample_rate_hz - first.meta.sample_rate_hz).abs()
                > fr::ROUNDING * first.meta.sample_rate_hz
        {
            let side = record::sidecar_path(p);
            let src = cierva_harness::inputs::yaml::read(&side)?;
            return Err(Error::from(InputError::field(
                &side,
                &src,
                "sample_rate_hz",
                format!(
                    "{} Hz where {} is sampled at {} Hz: spectra of records at different sample rates cannot be averaged (resample one)",
                    r.meta.sample_rate_hz,
                    first.path.display(),
                    first.meta.sample_rate_hz
                ),
            )));
        }
        records.push(r);
    }
    Ok(records)
}

/// An estimator's error, located in the record it concerns.
fn located(e: &FrError, records: &[Record], inputs: &[&str]) -> String {
    let path = |run: &usize| records[*run].path.display().to_string();
    match e {
        FrError::WindowTooLong { run, .. }
        | FrError::SampleRate { run, .. }
        | FrError::Lengths { run }
        | FrError::NotFinite { run, .. } => format!("error: {}: {e}", path(run)),
        FrError::NoPower {
            run,
            input,
            lo_hz,
            hi_hz,
            fraction,
        } => format!(
            "error: {}: channel `{}` (an input) has no power in the band {lo_hz:.4}-{hi_hz:.4} Hz ({fraction:.1e} of its variance there; below {:e} is none): a constant channel, or a band its excitation misses",
            path(run),
            inputs[*input],
            fr::NO_POWER_FRACTION
        ),
        FrError::NoRuns | FrError::Inputs | FrError::Settings(_) => format!("error: {e}"),
    }
}

pub(crate) fn frequency_response(a: FrequencyResponseArgs) -> Result<ExitCode, Error> {
    let records = load(&a)?;
    let inputs: Vec<&str> = std::iter::once(a.input.as_str())
        .chain(a.conditioned_on.iter().map(String::as_str))
        .collect();
    let runs: Vec<fr::RecordSignals> = records
        .iter()
        .map(|r| fr::RecordSignals {
            name: r.path.display().to_string(),
            inputs: inputs
                .iter()
                .map(|c| r.channel(c).unwrap_or_default().to_vec())
                .collect(),
            output: r.channel(&a.output).unwrap_or_default().to_vec(),
            dt_s: r.dt_s(),
        })
        .collect();
    // From the first sample to the last, to a tenth of a second (a 120 s record's windows are
    // 15, 30 and 60 s).
    let shortest_s = runs
        .iter()
        .map(|r| (r.output.len().saturating_sub(1) as f64 * r.dt_s * 10.0).floor() / 10.0)
        .fold(f64::INFINITY, f64::min);
    let settings = fr::SpectralSettings {
        windows_s: if a.windows_s.is_empty() {
            fr::SpectralSettings::default_windows_s(shortest_s)
        } else {
            a.windows_s.clone()
        },
        overlap: a.overlap,
        points: a.frequencies,
        band_hz: a.band_hz.as_ref().map(|b| [b[0], b[1]]),
    };
    let est = fr::estimate(&runs, &settings)
        .map_err(|e| Error::Input(located(&e, &records, &inputs).to_string()))?;
    match a.format {
        ResponseFormat::Json => print_json(&json(&a, &records, &inputs, &est)),
        ResponseFormat::Csv => print!("{}", csv(&est)),
        ResponseFormat::Text => print!("{}", table(&a, &records, &est)),
    }
    Ok(ExitCode::SUCCESS)
}

/// One input's columns as JSON (null where nothing is estimated).
fn columns(r: &fr::InputResponse) -> serde_json::Value {
    serde_json::json!({
        "magnitude_db": r.magnitude_db(),
        "phase_deg": r.phase_deg(),
        "coherence": r.coherence,
        "random_error": r.random_error,
        "random_error_95": r.random_error_95,
    })
}

fn json(
    a: &FrequencyResponseArgs,
    records: &[Record],
    inputs: &[&str],
    est: &CompositeEstimate,
) -> serde_json::Value {
    let mut v = columns(&est.inputs[0]);
    let extra = serde_json::json!({
        "input": a.input,
        "output": a.output,
        "conditioned_on": a.conditioned_on,
        "records": records.iter().map(|r| r.path.display().to_string()).collect::<Vec<_>>(),
        "windows_s": est.windows_s,
        "overlap": est.overlap,
        "window": "hann",
        "frequencies_hz": est.frequencies_hz,
        "random_error_means": "normalised random error of the magnitude (its standard deviation over |H|), also the phase's standard deviation in rad (Bendat and Piersol 2010, ch. 9); random_error_95 is the half-width of the 95 % interval of ln|H| and of the phase (rad)",
        "averages": est.averages,
        "weights": est.weights,
        "multiple_coherence": est.multiple_coherence,
        "others": inputs.iter().zip(&est.inputs).skip(1).map(|(name, r)| {
            let mut c = columns(r);
            c["input"] = serde_json::json!(name);
            c
        }).collect::<Vec<_>>(),
    });
    if let (Some(o), serde_json::Value::Object(e)) = (v.as_object_mut(), extra) {
        o.extend(e);
    }
    v
}

fn cell(x: Option<f64>, digits: usize) -> String {
    x.map_or(String::new(), |v| format!("{v:.digits$}"))
}

fn csv(est: &CompositeEstimate) -> String {
    let r = &est.inputs[0];
    let (mag, ph) = (r.magnitude_db(), r.phase_deg());
    let mut s = String::from("frequency_hz,magnitude_db,phase_deg,coherence,random_error\n");
    for k in 0..est.frequencies_hz.len() {
        s += &format!(
            "{:.6},{},{},{:.6},{}\n",
            est.frequencies_hz[k],
            cell(mag[k], 4),
            cell(ph[k], 3),
            r.coherence[k],
            cell(r.random_error[k], 5)
        );
    }
    s
}

fn table(a: &FrequencyResponseArgs, records: &[Record], est: &CompositeEstimate) -> String {
    let r = &est.inputs[0];
    let (mag, ph) = (r.magnitude_db(), r.phase_deg());
    let mut s = format!(
        "{} / {}{} from {} ({} record{}), Hann windows {:?} s at {:.0} % overlap\n",
        a.output,
        a.input,
        if a.conditioned_on.is_empty() {
            String::new()
        } else {
            format!(" conditioned on {}", a.conditioned_on.join(", "))
        },
        show(&a.records),
        records.len(),
        if records.len() == 1 { "" } else { "s" },
        est.windows_s,
        100.0 * est.overlap
    );
    s += "  f (Hz)   |H| (dB)   phase (deg)   coherence   random error   averages\n";
    for k in 0..est.frequencies_hz.len() {
        s += &format!(
            "{:>8.4} {:>10} {:>13} {:>11.3} {:>14} {:>10.1}\n",
            est.frequencies_hz[k],
            cell(mag[k], 2),
            cell(ph[k], 1),
            r.coherence[k],
            cell(r.random_error[k], 3),
            est.averages[k]
        );
    }
    s
}
