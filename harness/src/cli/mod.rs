//! The `cierva` commands, one module each; `main.rs` parses the command line and dispatches
//! here. This module holds what several commands share: progress on stderr, output as text or
//! JSON, and loading an aircraft for a flight condition.

pub(crate) use cierva_harness::inputs::reference;
pub(crate) use cierva_harness::load_cases;
pub(crate) use cierva_harness::report::tables;
pub(crate) use cierva_harness::run_autorotation;
pub(crate) use cierva_harness::suite::case::{DescentSpec, InflowSpec, SkewSpec};
pub(crate) use cierva_harness::suite::outcome::{self, CheckResult};
pub(crate) use cierva_model::components::rotor::{InflowModel, WakeModel};
pub(crate) use clap::{Parser, ValueEnum};
pub(crate) use std::path::{Path, PathBuf};
pub(crate) use std::process::ExitCode;

mod args;
mod autorotate;
mod bench;
mod estimate;
mod fit;
mod frequency_response;
pub(crate) mod identify;
mod inflow;
mod init;
mod linearize;
mod modes;
mod new_case;
mod retune;
pub(crate) mod review;
mod sensitivity;
mod simulate;
mod synth;
mod synth_flight;
mod synth_history;
mod trim;
pub(crate) mod uncertainty;
mod validate;
mod verify;

pub(crate) use args::*;
pub(crate) use autorotate::autorotate;
pub(crate) use bench::bench;
pub(crate) use estimate::{EstimateArgs, estimate};
pub(crate) use fit::fit;
pub(crate) use frequency_response::frequency_response;
pub(crate) use identify::{IdentifyArgs, identify};
pub(crate) use inflow::{inflow, synth_teeter};
pub(crate) use init::{InitArgs, init};
pub(crate) use linearize::linearize;
pub(crate) use modes::modes;
pub(crate) use new_case::new_case;
pub(crate) use retune::retune;
pub(crate) use sensitivity::sensitivity;
pub(crate) use simulate::simulate;
pub(crate) use synth::synth;
pub(crate) use synth_flight::synth_flight;
pub(crate) use synth_history::synth_history;
pub(crate) use trim::trim;
pub(crate) use uncertainty::uncertainty;
pub(crate) use validate::validate;
pub(crate) use verify::verify;

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

pub(crate) static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `given`, or `name` in the suite's `folder` (the suite is looked for only then).
pub(crate) fn or_in_suite(
    given: Option<PathBuf>,
    folder: fn(&cierva_harness::suite::Suite) -> PathBuf,
    name: String,
) -> Result<PathBuf, ExitCode> {
    match given {
        Some(p) => Ok(p),
        None => suite().map(|s| folder(&s).join(name)),
    }
}

/// `--suite DIR`, as given (set once by `main`).
pub(crate) static SUITE_ARG: std::sync::OnceLock<Option<PathBuf>> = std::sync::OnceLock::new();

/// The suite a command works on: `--suite DIR`, or the nearest `cierva.toml` from the working
/// directory upward. None is a located error, printed, and exit code 2.
pub(crate) fn suite() -> Result<cierva_harness::suite::Suite, ExitCode> {
    use cierva_harness::suite::Suite;
    let found = match SUITE_ARG.get().and_then(Option::as_deref) {
        Some(dir) => Suite::open(dir),
        None => Suite::find(&std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."))),
    };
    found.map_err(|e| {
        eprintln!("{}", e.render());
        ExitCode::from(2)
    })
}

/// Loads an aircraft file; a bad file is printed with its location and is exit code 2.
pub(crate) fn load_aircraft(
    path: &Path,
) -> Result<cierva_harness::inputs::aircraft::AircraftFile, ExitCode> {
    cierva_harness::inputs::aircraft::load(path).map_err(|e| {
        eprintln!("{}", e.render());
        ExitCode::from(2)
    })
}

/// The aircraft of a flight command, with its `--corrections` applied (the file must name this
/// aircraft or its main rotor).
pub(crate) fn load_flight(
    f: &FlightArgs,
) -> Result<cierva_harness::inputs::aircraft::AircraftFile, ExitCode> {
    use cierva_harness::inputs::corrections::{self, Target};
    let file = load_aircraft(&f.aircraft)?;
    let Some(path) = &f.corrections else {
        return Ok(file);
    };
    let c = corrections::load(path).map_err(|e| {
        eprintln!("{}", e.render());
        ExitCode::from(2)
    })?;
    let applies = match &c.target {
        Target::Aircraft(id) => *id == file.id,
        Target::Rotor(id) => *id == file.main_rotor_file.id,
    };
    if !applies {
        eprintln!(
            "error: {} corrects {:?}, not the aircraft {} or its main rotor {}",
            path.display(),
            c.target,
            file.id,
            file.main_rotor_file.id
        );
        return Err(ExitCode::from(2));
    }
    file.with_corrections(&c.corrections).map_err(|e| {
        eprintln!("error: {}: {e}", path.display());
        ExitCode::from(2)
    })
}

/// The azimuth step of a flight, rad: `--azimuth-step-deg` where given (from
/// `MIN_AZIMUTH_STEP_DEG` to 30 deg, as a case's), the aircraft file's otherwise; a step out of
/// range is printed and is exit code 2.
pub(crate) fn azimuth_step_rad(
    arg_deg: Option<f64>,
    file: &cierva_harness::inputs::aircraft::AircraftFile,
) -> Result<f64, ExitCode> {
    use cierva_harness::inputs::limits::{MIN_AZIMUTH_STEP_DEG, azimuth_step_ok};
    match arg_deg {
        None => Ok(file.aircraft.main_rotor.numerics.azimuth_step_rad),
        Some(d) if azimuth_step_ok(d, 30.0) => Ok(d.to_radians()),
        Some(d) => {
            eprintln!(
                "error: --azimuth-step-deg must be in [{MIN_AZIMUTH_STEP_DEG}, 30] deg (MIN_AZIMUTH_STEP_DEG), got {d}"
            );
            Err(ExitCode::from(2))
        }
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
