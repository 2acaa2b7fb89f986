//! The `cierva` commands, one module each; `main.rs` parses the command line and dispatches
//! here. This module holds what several commands share: progress on stderr, output as text or
//! JSON, and loading an aircraft for a flight condition.

pub(crate) use cierva_harness::inputs::reference;
pub(crate) use cierva_harness::report::tables;
pub(crate) use cierva_harness::run::autorotation::run_autorotation;
pub(crate) use cierva_harness::suite::case::load_cases;
pub(crate) use cierva_harness::suite::case::{DescentSpec, InflowSpec, SkewSpec};
pub(crate) use cierva_harness::suite::outcome::CheckResult;
pub(crate) use clap::{Parser, ValueEnum};
pub(crate) use std::path::{Path, PathBuf};
pub(crate) use std::process::ExitCode;

mod args;
mod autorotate;
mod bench;
mod estimate;
mod evaluate;
mod fit;
mod frequency_response;
mod identify;
mod inflow;
mod init;
mod linearize;
mod modes;
mod new_case;
mod retune;
mod review;
mod sensitivity;
mod serve;
mod simulate;
mod synth;
mod synth_flight;
mod synth_history;
mod trim;
mod uncertainty;
mod validate;
mod verify;

pub(crate) use args::*;
pub(crate) use autorotate::{AutorotateArgs, autorotate};
pub(crate) use bench::{BenchArgs, bench};
pub(crate) use estimate::{EstimateArgs, estimate};
pub(crate) use evaluate::{EvaluateArgs, evaluate};
pub(crate) use fit::{FitArgs, fit};
pub(crate) use frequency_response::{FrequencyResponseArgs, frequency_response};
pub(crate) use identify::{IdentifyArgs, identify};
pub(crate) use inflow::{InflowArgs, SynthTeeterArgs, inflow, synth_teeter};
pub(crate) use init::{InitArgs, init};
pub(crate) use linearize::{LinearizeArgs, linearize};
pub(crate) use modes::{ModesArgs, modes};
pub(crate) use new_case::{NewCaseArgs, new_case};
pub(crate) use retune::{RetuneArgs, retune};
pub(crate) use review::{ReviewArgs, review};
pub(crate) use sensitivity::{SensitivityArgs, sensitivity};
pub(crate) use serve::{ServeArgs, serve};
pub(crate) use simulate::{SimulateArgs, simulate};
pub(crate) use synth::{SynthArgs, synth};
pub(crate) use synth_flight::{SynthFlightArgs, synth_flight};
pub(crate) use synth_history::{SynthHistoryArgs, synth_history};
pub(crate) use trim::{TrimArgs, trim};
pub(crate) use uncertainty::{UncertaintyArgs, uncertainty};
pub(crate) use validate::{ValidateArgs, validate};
pub(crate) use verify::{VerifyArgs, verify};

/// A progress bar on stderr for `len` steps (hidden with `--quiet` or off a terminal).
pub(crate) fn progress(len: u64, what: &str) -> indicatif::ProgressBar {
    if QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix} [{bar:30}] {pos}/{len} {elapsed} {wide_msg}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_prefix(what.to_string());
    bar
}

/// A spinner on stderr for work of unknown length (hidden with `--quiet` or off a terminal).
pub(crate) fn spinner(what: &str) -> indicatif::ProgressBar {
    if QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        return indicatif::ProgressBar::hidden();
    }
    let s = indicatif::ProgressBar::new_spinner();
    s.set_message(what.to_string());
    s.enable_steady_tick(std::time::Duration::from_millis(120));
    s
}

/// Prints a value as pretty JSON on stdout (what `--format json` gives).
pub(crate) fn print_json(value: &impl serde::Serialize) {
    println!(
        "{}",
        serde_json::to_string_pretty(value).expect("serialisable")
    );
}

/// What a command that writes files prints when it is done: a sentence, or a JSON object.
pub(crate) fn done(format: Format, text: String, json: serde_json::Value) {
    match format {
        Format::Text => println!("{text}"),
        Format::Json => print_json(&json),
    }
}

/// Why a command stopped: bad input (exit code 2: a file that does not load, an argument out of
/// range, a suite that is not there) or a failure (exit code 1: the model found no answer, a
/// file could not be written). Each holds what is printed on stderr, once, by `main`.
#[derive(Debug)]
pub(crate) enum Error {
    Input(String),
    Failure(String),
}

impl Error {
    /// Bad input: `error: ` and the message.
    pub(crate) fn input(message: impl std::fmt::Display) -> Self {
        Self::Input(format!("error: {message}"))
    }

    /// A failure: `error: ` and the message.
    pub(crate) fn failure(message: impl std::fmt::Display) -> Self {
        Self::Failure(format!("error: {message}"))
    }

    /// Bad input where `input`, a failure otherwise (a model run's error says which it is).
    pub(crate) fn of(input: bool, message: String) -> Self {
        if input {
            Self::Input(message)
        } else {
            Self::Failure(message)
        }
    }

    /// Prints the message and gives the exit code.
    pub(crate) fn exit(self) -> ExitCode {
        let (message, code) = match self {
            Self::Input(m) => (m, 2),
            Self::Failure(m) => (m, 1),
        };
        eprintln!("{message}");
        ExitCode::from(code)
    }
}

impl From<cierva_harness::plan::PlanError> for Error {
    /// A plan's bad input (exit 2), or a study whose shards are not all done (exit 1).
    fn from(e: cierva_harness::plan::PlanError) -> Self {
        match e {
            cierva_harness::plan::PlanError::Input(m) => Self::input(m),
            cierva_harness::plan::PlanError::Incomplete(m) => Self::failure(m),
        }
    }
}

impl From<cierva_harness::inputs::yaml::InputError> for Error {
    /// A file that does not load, with its location.
    fn from(e: cierva_harness::inputs::yaml::InputError) -> Self {
        Self::Input(e.render())
    }
}

/// Writes a record (its CSV and sidecar) and says so: `text` for people; for programs `json`
/// with the two paths added under `wrote`. A file that cannot be written is exit code 2.
pub(crate) fn write_record(
    path: &Path,
    meta: &cierva_harness::inputs::record::RecordMeta,
    (channels, data): (&[String], &[Vec<f64>]),
    format: Format,
    text: String,
    mut json: serde_json::Value,
) -> Result<ExitCode, Error> {
    use cierva_harness::inputs::record;
    // The record's folder is made, as every command makes its outputs' folders.
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::input(format!("cannot make {}: {e}", dir.display())))?;
    }
    record::write(path, meta, channels, data)
        .map_err(|e| Error::input(format!("cannot write {}: {e}", path.display())))?;
    json["wrote"] = serde_json::json!([
        path.display().to_string(),
        record::sidecar_path(path).display().to_string()
    ]);
    done(format, text, json);
    Ok(ExitCode::SUCCESS)
}

pub(crate) static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `given`, or `name` in the suite's `folder` (the suite is looked for only then).
/// Writes `text` at `path`, its folder made (as every command makes its outputs' folders).
pub(crate) fn write_making_folder(path: &Path, text: &str) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

pub(crate) fn or_in_suite(
    given: Option<PathBuf>,
    folder: fn(&cierva_harness::suite::Suite) -> PathBuf,
    name: String,
) -> Result<PathBuf, Error> {
    match given {
        Some(p) => Ok(p),
        None => suite().map(|s| folder(&s).join(name)),
    }
}

/// `--suite DIR`, as given (set once by `main`).
pub(crate) static SUITE_ARG: std::sync::OnceLock<Option<PathBuf>> = std::sync::OnceLock::new();

/// The suite a command works on: `--suite DIR`, or the nearest `cierva.toml` from the working
/// directory upward. None is a located error, printed, and exit code 2.
pub(crate) fn suite() -> Result<cierva_harness::suite::Suite, Error> {
    use cierva_harness::suite::Suite;
    let found = match SUITE_ARG.get().and_then(Option::as_deref) {
        Some(dir) => Suite::open(dir),
        None => Suite::find(&std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."))),
    };
    found.map_err(Error::from)
}

/// Loads an aircraft file; a bad file is printed with its location and is exit code 2.
pub(crate) fn load_aircraft(
    path: &Path,
) -> Result<cierva_harness::inputs::aircraft::AircraftFile, Error> {
    cierva_harness::inputs::aircraft::load(path).map_err(Error::from)
}

/// Loads corrections files (`--corrections`, repeatable); a bad file is exit code 2.
pub(crate) fn load_corrections(
    paths: &[PathBuf],
) -> Result<Vec<cierva_harness::inputs::corrections::CorrectionsFile>, Error> {
    paths
        .iter()
        .map(|p| cierva_harness::inputs::corrections::load(p).map_err(Error::from))
        .collect()
}

/// The aircraft of a flight command, with its `--corrections` applied (the file must name this
/// aircraft or its main rotor).
pub(crate) fn load_flight(
    f: &FlightArgs,
) -> Result<cierva_harness::inputs::aircraft::AircraftFile, Error> {
    use cierva_harness::inputs::corrections::{self, Corrects};
    let file = load_aircraft(&f.aircraft)?;
    if let Some(m) = f.mass_kg {
        file.check_mass(m)
            .map_err(|e| Error::input(format!("--mass-kg {m}: {e}")))?;
    }
    let Some(path) = &f.corrections else {
        return Ok(file);
    };
    let c = corrections::load(path)?;
    let applies = match &c.target {
        Corrects::Aircraft(id) => *id == file.id,
        Corrects::Rotor(id) => *id == file.main_rotor_file.id,
        Corrects::Model(_) => false,
    };
    if !applies {
        return Err(Error::input(format!(
            "{} corrects {:?}, not the aircraft {} or its main rotor {}",
            path.display(),
            c.target,
            file.id,
            file.main_rotor_file.id
        )));
    }
    file.with_corrections(&c.corrections).map_err(|e| {
        match c.locate(|one| file.with_corrections(one).map(|_| ())) {
            Some(located) => Error::from(located),
            None => Error::input(format!("{}: {e}", path.display())),
        }
    })
}

/// The azimuth step of a flight, rad: `--azimuth-step-deg` where given (from
/// `MIN_AZIMUTH_STEP_DEG` to 30 deg, as a case's), the aircraft file's otherwise; a step out of
/// range is printed and is exit code 2.
pub(crate) fn azimuth_step_rad(
    arg_deg: Option<f64>,
    file: &cierva_harness::inputs::aircraft::AircraftFile,
) -> Result<f64, Error> {
    use cierva_harness::inputs::limits::{MIN_AZIMUTH_STEP_DEG, azimuth_step_ok};
    match arg_deg {
        None => Ok(file.aircraft.main_rotor.numerics.azimuth_step_rad),
        Some(d) if azimuth_step_ok(d, 30.0) => Ok(d.to_radians()),
        Some(d) => Err(Error::input(format!(
            "--azimuth-step-deg must be in [{MIN_AZIMUTH_STEP_DEG}, 30] deg (MIN_AZIMUTH_STEP_DEG), got {d}"
        ))),
    }
}

/// The index of a control named on the command line (eta_s, eta_c, eta_p, eta_t).
pub(crate) fn control_index(control: &str) -> Result<usize, String> {
    cierva_model::aircraft::linearise::CONTROLS
        .iter()
        .position(|c| *c == control)
        .ok_or_else(|| format!("unknown control `{control}`: eta_s, eta_c, eta_p or eta_t"))
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
    Text,
    Json,
}

pub(crate) fn show(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The aircraft (with its corrections) linearised at the records' condition, which must be
/// one condition: quasi-statically, and (with `flapping`) with its flapping states (or why
/// not). `identify --against` and `verify` both use it.
pub(crate) fn linearised_against(
    aircraft: &Path,
    corrections: Option<&PathBuf>,
    recs: &[cierva_harness::inputs::record::Record],
    flapping: bool,
) -> Result<
    (
        cierva_model::LinearModel,
        Option<Result<cierva_model::aircraft::flapping::WithFlapping, String>>,
    ),
    Error,
> {
    let conditions = recs
        .iter()
        .map(cierva_harness::ident::record_condition)
        .collect::<Result<Vec<_>, _>>()
        .map_err(Error::input)?;
    let (request, loading) = conditions[0];
    if let Some((k, _)) = conditions
        .iter()
        .enumerate()
        .find(|(_, c)| **c != conditions[0])
    {
        return Err(Error::input(format!(
            "{} and {} are not at one condition ({:?} against {:?}): identify each condition on its own",
            recs[0].path.display(),
            recs[k].path.display(),
            conditions[0],
            conditions[k]
        )));
    }
    let flight = FlightArgs {
        aircraft: aircraft.to_path_buf(),
        airspeed_mph: request.airspeed_mph,
        mass_kg: loading.mass_kg,
        climb_m_s: request.climb_m_s,
        density_altitude_ft: loading.density_altitude_ft,
        corrections: corrections.cloned(),
    };
    let file = load_flight(&flight)?;
    cierva_harness::run::linearise::run_linearise(&file.aircraft, request, loading)
        .map(|(trim, lin)| {
            let with_flapping = flapping.then(|| {
                cierva_harness::run::linearise::run_linearise_with_flapping(
                    &file.aircraft,
                    &trim,
                    loading,
                )
            });
            (lin.model, with_flapping)
        })
        .map_err(|e| Error::failure(format!("{}: {e}", aircraft.display())))
}
