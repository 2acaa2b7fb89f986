//! The `cierva` command line.

use cierva_harness::case::{InflowSpec, SkewSpec};
use cierva_harness::eval::{self, CheckResult};
use cierva_harness::run_autorotation;
use cierva_harness::{load_cases, refs, text};
use cierva_model::rotor::{InflowModel, SkewConvention};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod cli;

/// Verification and validation of rotorcraft flight-dynamics models against flight references.
///
/// Exit codes: 0 every check passed (or failed as its case expects); 1 a check failed
/// unexpectedly or an expected failure passed; 2 bad input (a case or reference file that does
/// not load, a missing path, no cases).
#[derive(Parser)]
#[command(name = "cierva", version)]
struct Cli {
    /// No progress bars or progress messages on stderr (results and errors are still printed).
    /// Progress bars are drawn only when stderr is a terminal.
    #[arg(long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

/// A progress bar on stderr for `len` steps (hidden with `--quiet` or off a terminal).
fn progress(len: u64, what: &str) -> indicatif::ProgressBar {
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
fn spinner(what: &str) -> indicatif::ProgressBar {
    if QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        return indicatif::ProgressBar::hidden();
    }
    let s = indicatif::ProgressBar::new_spinner();
    s.set_message(what.to_string());
    s.enable_steady_tick(std::time::Duration::from_millis(120));
    s
}

/// What a command that writes files prints when it is done: a sentence, or a JSON object.
fn done(format: Format, text: String, json: serde_json::Value) {
    match format {
        Format::Text => println!("{text}"),
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(&json).expect("serialisable")
        ),
    }
}

static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

#[derive(Subcommand)]
enum Command {
    /// Run validation cases and print a table of every check.
    ///
    /// Example: `cierva validate cases/seed002-vpm-m16-60kn.yaml --format json`
    ///
    /// With `--corrections FIT_RESULT.yaml` (as `cierva fit` writes), every case whose aircraft or
    /// rotor the file names is run with those corrections; expected failures that now pass are
    /// reported as unexpected passes.
    Validate {
        /// Case files or folders searched for `*.yaml` (default: `cases`).
        paths: Vec<PathBuf>,
        /// Corrections files to apply (repeatable).
        #[arg(long)]
        corrections: Vec<PathBuf>,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
        /// Where to write the report: `index.html` (self-contained, with plots) and
        /// `summary.md`.
        #[arg(long, default_value = "reports")]
        report_dir: PathBuf,
        /// Write no report.
        #[arg(long)]
        no_report: bool,
    },
    /// Review the known discrepancies: run every check that is expected to fail and compare
    /// what the model gives with what is recorded for it in `reports/discrepancies/`.
    ///
    /// A check marked `expected_failure` stays one only while the model stays inside its
    /// recorded bands; when the model moves (better or worse), `cargo test` and `cierva validate`
    /// fail it as "discrepancy moved". This command lists what moved; `--accept` records the
    /// model's values as they are now (as `cargo insta review` accepts snapshots). Exit code 0
    /// when nothing moved or all was accepted, 1 otherwise.
    ///
    /// Example: `cierva review cases/naca-tr515-table-iii.yaml`, then `cierva review --accept`
    Review {
        /// Case files or folders searched for `*.yaml` (default: `cases`).
        paths: Vec<PathBuf>,
        /// Record the model's values as they are now.
        #[arg(long)]
        accept: bool,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Fit the model's empirical corrections (propeller blockage, hub angle-of-attack factor,
    /// profile drag, pitch offset, lateral inflow offset) to flight references within bounds,
    /// and write the fitted corrections and a before/after table.
    ///
    /// The fit file names the subject (an aircraft at a mass and density altitude, or a rotor in
    /// a tunnel), the parameters with their bounds, and the targets: checks of a case (each
    /// check's expected value, with its tolerance as the standard error) or references written
    /// out, with optional hard or soft bounds. See harness/src/fit_file.rs for the format.
    ///
    /// Writes the corrections file (default `<fit file's folder>/results/<id>.yaml`, for
    /// `cierva validate --corrections`) and a Markdown report (default `reports/fits/<id>.md`).
    /// Exit code 0 when the fit converged, 1 when it did not (iteration limit, infeasible, model
    /// failure), 2 on bad input.
    ///
    /// Example: `cierva fit fits/pca-2-tr515.yaml`
    Fit {
        /// The fit file.
        file: PathBuf,
        /// Where to write the fitted corrections.
        #[arg(long)]
        output: Option<PathBuf>,
        /// Where to write the Markdown before/after report.
        #[arg(long)]
        report: Option<PathBuf>,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Print the modes, BCAR Section T verdicts and weakly coupled systems values of a linear
    /// model held in a reference file.
    ///
    /// Example: `cierva modes flight-refs/seed002-vpm-m16-60kn.yaml`
    ///
    /// With `--sweep Q_u=0.06:0.26:11`, prints the root locus instead: the modes at 11 evenly
    /// spaced values of the derivative Q_u from 0.06 to 0.26 (in the derivative's own units).
    Modes {
        /// A reference file with a `linear_model` block.
        file: PathBuf,
        /// Root-locus sweep: `DERIVATIVE=FROM:TO:POINTS`, for example `M_Omega=-0.0096:0.0096:9`.
        #[arg(long)]
        sweep: Option<String>,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Fly a linear model through a test input and write a synthetic flight record
    /// (RECORD.csv and its sidecar RECORD.yaml), labelled synthetic with its generator, seed and
    /// truth.
    ///
    /// Example: `cierva synth flight-refs/seed002-vpm-m16-60kn.yaml --control eta_s --input sweep
    /// --amplitude 0.01 --seed 7 --output /tmp/vpm-sweep.csv`
    Synth(SynthArgs),
    /// Identify stability and control derivatives from a flight record (frequency-domain
    /// equation error, seed 000 Sec. IV): estimates, standard errors, 95 % bounds, fit quality,
    /// correlations and warnings.
    ///
    /// Example: `cierva identify /tmp/vpm-sweep.csv --format yaml > flight-refs/my-derivatives.yaml`
    Identify {
        /// A record CSV with its sidecar YAML beside it.
        record: PathBuf,
        /// Identification set-up (default: longitudinal [u w q theta Omega], 0.05-2 Hz, 100 points).
        #[arg(long)]
        config: Option<PathBuf>,
        /// text, json, or yaml (a flight-refs derivative table).
        #[arg(long, value_enum, default_value_t = IdentFormat::Text)]
        format: IdentFormat,
        /// Another record (not used in the fit) to predict with the identified model: RMS error
        /// and Theil's inequality coefficient per state (seed 000 Fig. 10).
        #[arg(long)]
        predict: Option<PathBuf>,
    },
    /// Inflow components from a teeter record (seed 003): disc tilts by a harmonic fit over
    /// whole revolutions, then v0, v1s, v1c and coning (Eqs. 13-19).
    ///
    /// Example: `cierva inflow flight-refs/synthetic-vpm-m16-rotor-teeter.csv --rotor aircraft/vpm-m16-rotor.yaml`
    Inflow {
        /// A teeter record (channels time_s, teeter_rad, azimuth_from_front_rad,
        /// omega_rotor_rad_s, hub_inplane_speed_m_s, hub_normal_speed_m_s) with its sidecar.
        record: PathBuf,
        /// The rotor file (radius, chord, pitch, section, flap inertia).
        #[arg(long)]
        rotor: PathBuf,
        /// Coning: unknown (a teetering rotor; Eq. 19) or the mean of the flap channel.
        #[arg(long, value_enum, default_value_t = cierva_harness::ident::flap::Coning::Unknown)]
        coning: cierva_harness::ident::flap::Coning,
        /// tan(chi/2) for Eq. 19: one, or from Eq. 5 (signed) or Eq. 6 (modulus).
        #[arg(long, value_enum, default_value_t = cierva_harness::ident::flap::HalfSkew::One)]
        skew: cierva_harness::ident::flap::HalfSkew,
        /// Air density, kg/m^3 (for the Lock number).
        #[arg(long, default_value_t = 1.225)]
        density_kg_m3: f64,
        /// Blade pitch at the rotor's reference station, deg (default: the file's pitch).
        #[arg(long, allow_hyphen_values = true)]
        collective_deg: Option<f64>,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Write a synthetic teeter record of a rotor's autorotative equilibrium in a wind tunnel
    /// (for testing `cierva inflow`), labelled synthetic with its generator, seed and truth.
    ///
    /// Example: `cierva synth-teeter aircraft/vpm-m16-rotor.yaml --alpha-deg 10 --airspeed-m-s 30 --output /tmp/teeter.csv`
    SynthTeeter {
        #[command(flatten)]
        tunnel: TunnelArgs,
        #[arg(long, default_value_t = 20.0)]
        duration_s: f64,
        #[arg(long, default_value_t = 200.0)]
        sample_rate_hz: f64,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Standard deviation of the teeter angle's noise, deg.
        #[arg(long, default_value_t = 0.0)]
        noise_deg: f64,
        #[arg(long)]
        output: PathBuf,
        /// `text` for people, `json` for programs (what was written, as an object).
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Write a commented case file to start from (it validates as it is written).
    ///
    /// Example: `cierva new-case cases/my-aircraft-70mph.yaml`
    NewCase {
        /// The case file to write; its id is the file name without `.yaml`.
        path: PathBuf,
        /// `text` for people, `json` for programs (what was written, as an object).
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Time the model's building blocks on the PCA-2 rotor (aircraft/pca-2-rotor.yaml) and
    /// print medians: the blade right-hand side, one periodic blade solution, one autorotation.
    ///
    /// Example: `cargo run --release -- bench --repeat 51`
    Bench(BenchArgs),
    /// Find the autorotative equilibrium of an isolated rotor in a wind tunnel: the rotorspeed
    /// at which the mean aerodynamic torque is zero, with lift and drag coefficients on
    /// q pi R^2, L/D, tip-speed ratio, thrust coefficient, flapping and inflow.
    ///
    /// Example: `cierva autorotate aircraft/pca-2-rotor.yaml --alpha-deg 6.6 --airspeed-m-s 17.7
    /// --collective-deg 1.9`. `--alpha-deg 90` is vertical descent.
    Autorotate {
        #[command(flatten)]
        tunnel: TunnelArgs,
        /// Air density, kg/m^3 (default 1.225, ISA sea level); the speed of sound is taken
        /// from the standard atmosphere at that density altitude.
        #[arg(long, allow_hyphen_values = true)]
        density_kg_m3: Option<f64>,
        /// Inflow model.
        #[arg(long, value_enum, default_value_t = InflowSpec::PetersHaquang)]
        inflow: InflowSpec,
        /// Wake skew angle convention in autorotation: seed 003 Eq. 5 (signed) or Eq. 6 (modulus).
        #[arg(long, value_enum, default_value_t = SkewSpec::Signed)]
        skew: SkewSpec,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Trim and linearise an aircraft (seed 001 Eqs. 10-12): the nine rigid-body states and the
    /// rotorspeed, controls in % of travel, blades and inflow quasi-steady. Prints the
    /// derivatives, the modes with BCAR Section T, the longitudinal subset's modes and the
    /// primary derivatives split by component (seed 000 Tables 1-2).
    ///
    /// Example: `cierva linearize aircraft/vpm-m16.yaml --airspeed-mph 69 --mass-kg 425
    /// --density-altitude-ft 2000 --format yaml > /tmp/model.yaml`
    Linearize {
        #[command(flatten)]
        flight: FlightArgs,
        /// text, json (derivatives and breakdown) or yaml (a flight-refs file with the model).
        #[arg(long, value_enum, default_value_t = LinearFormat::Text)]
        format: LinearFormat,
    },
    /// Fly the full individual-blade model from trim (refined to the full model's periodic
    /// orbit) with control inputs: a shape on one control, or a CSV of control changes from
    /// trim. Fixed-step fourth-order Runge-Kutta at the aircraft's azimuth step (or
    /// `--azimuth-step-deg`). Writes time, controls, body states, rotor and propeller speeds,
    /// flapping and inflow as CSV.
    ///
    /// Example: `cierva simulate aircraft/vpm-m16.yaml --airspeed-mph 70 --shape doublet
    /// --control eta_s --amplitude-percent 2 --start-s 1 --input-s 1 --duration-s 10
    /// --output /tmp/doublet.csv`
    Simulate {
        #[command(flatten)]
        flight: FlightArgs,
        /// A CSV of control changes from trim (time_s and any of eta_s_percent, eta_c_percent,
        /// eta_p_percent, eta_t_percent); instead of --shape.
        #[arg(long)]
        input: Option<PathBuf>,
        #[command(flatten)]
        shape: ShapeArgs,
        /// Length of the run, s.
        #[arg(long, default_value_t = 10.0)]
        duration_s: f64,
        /// Azimuth step of the integration, deg (default: the aircraft file's).
        #[arg(long)]
        azimuth_step_deg: Option<f64>,
        /// Keep every n-th step.
        #[arg(long, default_value_t = 1)]
        every: usize,
        /// The CSV to write.
        #[arg(long)]
        output: PathBuf,
        /// `text` for people, `json` for programs (what was written, as an object).
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Write a synthetic time-history reference record (for `time_history` checks): the
    /// aircraft flown by the full blade model (or its linearisation) through a test input,
    /// responses as changes from trim plus seeded sensor noise, with a sidecar that says it is
    /// synthetic and how it was made.
    ///
    /// Example: `cierva synth-history aircraft/vpm-m16.yaml --airspeed-mph 70 --shape doublet
    /// --amplitude-percent 2 --duration-s 8 --noise-rate-deg-s 0.2 --seed 7
    /// --output flight-refs/synthetic-vpm-m16-70mph-doublet.csv`
    SynthHistory(SynthHistoryArgs),
    /// Trim an aircraft in steady flight: stick, pedal and throttle positions, pitch and roll
    /// attitude, rotor and propeller speeds, inflow and flapping, with the residuals the
    /// Newton solver reached (converged when every scaled residual is at most 1e-7).
    ///
    /// Example: `cierva trim aircraft/vpm-m16.yaml --airspeed-mph 70 --mass-kg 410`
    Trim {
        #[command(flatten)]
        flight: FlightArgs,
        /// Rate of turn, deg/s; positive to starboard.
        #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
        turn_rate_deg_s: f64,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
}

/// An aircraft and a flight condition (shared by `trim`, `linearize` and `simulate`).
#[derive(clap::Args)]
struct FlightArgs {
    /// An aircraft file (see aircraft/).
    aircraft: PathBuf,
    /// True airspeed, mph.
    #[arg(long, allow_hyphen_values = true)]
    airspeed_mph: f64,
    /// Mass, kg (default: the aircraft file's).
    #[arg(long, allow_hyphen_values = true)]
    mass_kg: Option<f64>,
    /// Rate of climb, m/s; negative descends.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    climb_m_s: f64,
    /// Density altitude, ft (ISA).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    density_altitude_ft: f64,
    /// A corrections file (as `cierva fit` writes) to apply to the aircraft.
    #[arg(long)]
    corrections: Option<PathBuf>,
}

impl FlightArgs {
    /// The flight condition, turning at `turn_rate_deg_s`.
    fn request(&self, turn_rate_deg_s: f64) -> cierva_harness::TrimRequest {
        cierva_harness::TrimRequest {
            airspeed_mph: self.airspeed_mph,
            climb_m_s: self.climb_m_s,
            turn_rate_deg_s,
        }
    }

    /// The mass and air.
    fn loading(&self) -> cierva_harness::Loading {
        cierva_harness::Loading {
            mass_kg: self.mass_kg,
            density_altitude_ft: self.density_altitude_ft,
        }
    }
}

/// A test input on one control (shared by `simulate` and `synth-history`).
#[derive(clap::Args)]
struct ShapeArgs {
    /// An input shape on one control (with --control and --amplitude-percent).
    #[arg(long, value_enum)]
    shape: Option<InputChoice>,
    /// eta_s (longitudinal stick), eta_c (lateral stick), eta_p (pedal) or eta_t (throttle).
    #[arg(long, default_value = "eta_s")]
    control: String,
    /// Amplitude, % of travel.
    #[arg(long, allow_hyphen_values = true, default_value_t = 1.0)]
    amplitude_percent: f64,
    /// When a doublet, 3-2-1-1 or step starts, s.
    #[arg(long, default_value_t = 1.0)]
    start_s: f64,
    /// Pulse (doublet), unit (3-2-1-1) or length (sweep), s.
    #[arg(long, default_value_t = 1.0)]
    input_s: f64,
    /// Sweep band, Hz.
    #[arg(long, default_value_t = 0.1)]
    from_hz: f64,
    #[arg(long, default_value_t = 2.0)]
    to_hz: f64,
}

impl ShapeArgs {
    /// The input shape, if one is given.
    fn input(&self) -> Option<cierva_harness::ident::synth::Input> {
        use cierva_harness::ident::synth::Input;
        let (amplitude, start_s, input_s) = (self.amplitude_percent, self.start_s, self.input_s);
        self.shape.map(|c| match c {
            InputChoice::Sweep | InputChoice::SweepDown => Input::Sweep {
                from_hz: self.from_hz,
                to_hz: self.to_hz,
                duration_s: input_s,
                amplitude,
                descending: c == InputChoice::SweepDown,
            },
            InputChoice::Doublet => Input::Doublet {
                start_s,
                pulse_s: input_s,
                amplitude,
            },
            InputChoice::ThreeTwoOneOne => Input::ThreeTwoOneOne {
                start_s,
                unit_s: input_s,
                amplitude,
            },
            InputChoice::Step => Input::Step { start_s, amplitude },
        })
    }
}

/// Loads an aircraft file; a bad file is printed with its location and is exit code 2.
fn load_aircraft(path: &Path) -> Result<cierva_harness::aircraft_file::AircraftFile, ExitCode> {
    cierva_harness::aircraft_file::load(path).map_err(|e| {
        eprintln!("{}", e.render());
        ExitCode::from(2)
    })
}

/// The aircraft of a flight command, with its `--corrections` applied (the file must name this
/// aircraft or its main rotor).
fn load_flight(f: &FlightArgs) -> Result<cierva_harness::aircraft_file::AircraftFile, ExitCode> {
    use cierva_harness::corrections::{self, Target};
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

/// The index of a control named on the command line (eta_s, eta_c, eta_p, eta_t).
fn control_index(control: &str) -> Result<usize, String> {
    cierva_model::linearise::CONTROLS
        .iter()
        .position(|c| *c == control)
        .ok_or_else(|| format!("unknown control `{control}`: eta_s, eta_c, eta_p or eta_t"))
}

/// Arguments of `synth-history`.
#[derive(clap::Args)]
struct SynthHistoryArgs {
    #[command(flatten)]
    flight: FlightArgs,
    /// `text` for people, `json` for programs (what was written, as an object).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,

    #[command(flatten)]
    shape: ShapeArgs,
    /// The model that flies: full-blade (the individual-blade model) or linear.
    #[arg(long, value_enum, default_value_t = cierva_harness::history::Simulation::FullBlade)]
    simulation: cierva_harness::history::Simulation,
    /// Seed 000's propeller blockage factor to fly with (0..1; default the aircraft file's).
    #[arg(long)]
    propeller_blockage: Option<f64>,
    /// Seed 000's hub angle-of-attack factor to fly with (default the aircraft file's).
    #[arg(long)]
    hub_aoa_factor: Option<f64>,
    /// Length of the record, s.
    #[arg(long, default_value_t = 10.0)]
    duration_s: f64,
    #[arg(long, default_value_t = 50.0)]
    sample_rate_hz: f64,
    /// Azimuth step of the full model, deg (default: the aircraft file's).
    #[arg(long)]
    azimuth_step_deg: Option<f64>,
    /// Standard deviations of the sensor noise: speeds m/s, rates deg/s, angles deg, rotor rpm.
    #[arg(long, default_value_t = 0.0)]
    noise_speed_m_s: f64,
    #[arg(long, default_value_t = 0.0)]
    noise_rate_deg_s: f64,
    #[arg(long, default_value_t = 0.0)]
    noise_angle_deg: f64,
    #[arg(long, default_value_t = 0.0)]
    noise_rpm: f64,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The record's title (its id is the output file's stem).
    #[arg(long)]
    title: Option<String>,
    /// The record CSV to write (its sidecar YAML goes beside it).
    #[arg(long)]
    output: PathBuf,
}

/// Output of `linearize`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum LinearFormat {
    Text,
    Json,
    Yaml,
}

/// A rotor in a wind tunnel: the rotor file and the condition (shared by `autorotate` and
/// `synth-teeter`).
#[derive(clap::Args)]
struct TunnelArgs {
    /// A rotor file (see aircraft/).
    rotor: PathBuf,
    /// Rotor angle of attack, deg: between the free stream and the plane normal to the
    /// shaft, positive with the air meeting the disc from below; 90 is vertical descent.
    #[arg(long, allow_hyphen_values = true)]
    alpha_deg: f64,
    /// Tunnel speed, m/s.
    #[arg(long, allow_hyphen_values = true)]
    airspeed_m_s: f64,
    /// Blade pitch at the rotor file's pitch reference station, deg; shifts the whole pitch
    /// distribution (default: the file's distribution as it is).
    #[arg(long, allow_hyphen_values = true)]
    collective_deg: Option<f64>,
}

/// Output of `identify`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum IdentFormat {
    Text,
    Json,
    /// A flight-refs derivative table that cases can check models against.
    Yaml,
}

/// Test inputs.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum InputChoice {
    /// Frequency sweep, low to high.
    Sweep,
    /// Frequency sweep, high to low (seed 000 Fig. 5).
    SweepDown,
    Doublet,
    /// 3-2-1-1.
    ThreeTwoOneOne,
    Step,
}

/// Arguments of `synth`.
#[derive(Parser)]
struct SynthArgs {
    /// A reference file with a `linear_model` block (the truth).
    model: PathBuf,
    /// `text` for people, `json` for programs (what was written, as an object).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,

    /// The control to excite.
    #[arg(long)]
    control: String,
    #[arg(long, value_enum, default_value_t = InputChoice::Sweep)]
    input: InputChoice,
    /// Input amplitude, in the control's units.
    #[arg(long, allow_hyphen_values = true)]
    amplitude: f64,
    /// Sweep band, Hz.
    #[arg(long, default_value_t = 0.02)]
    from_hz: f64,
    #[arg(long, default_value_t = 2.5)]
    to_hz: f64,
    /// Length of the sweep (or the pulse unit of a doublet or 3-2-1-1, s).
    #[arg(long, default_value_t = 100.0)]
    input_s: f64,
    /// Length of the record, s.
    #[arg(long, default_value_t = 120.0)]
    duration_s: f64,
    #[arg(long, default_value_t = 100.0)]
    sample_rate_hz: f64,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Multiplies the default sensor noise (airspeed 0.02 m/s, vanes, rates and attitudes
    /// 5e-4 rad(/s), rotor 0.01 rad/s); 0 for a noise-free record.
    #[arg(long, default_value_t = 0.0)]
    noise_scale: f64,
    /// Turbulence intensity on each force equation (acceleration units); 0 for none.
    #[arg(long, default_value_t = 0.0)]
    turbulence: f64,
    /// Trim about which the record is written (estimated defaults for the VPM M16 at 60 kn).
    #[arg(long, default_value_t = 30.0)]
    trim_u_m_s: f64,
    #[arg(long, default_value_t = 1.5, allow_hyphen_values = true)]
    trim_w_m_s: f64,
    #[arg(long, default_value_t = 0.05, allow_hyphen_values = true)]
    trim_theta_rad: f64,
    #[arg(long, default_value_t = 38.0)]
    trim_rotor_rad_s: f64,
    /// Air-data probe position relative to the c.g., body axes, m: x,y,z.
    #[arg(long, default_value = "2.0,0.0,-0.3", allow_hyphen_values = true)]
    probe_m: String,
    /// The record to write (its sidecar goes beside it, .yaml).
    #[arg(long)]
    output: PathBuf,
}

/// Benchmarks of the model's building blocks (medians over repeats; see reports/benchmarks.md).
#[derive(Parser)]
struct BenchArgs {
    /// Repeats of each timed operation.
    #[arg(long, default_value_t = 21)]
    repeat: usize,
    /// `text` (a Markdown table, as in reports/benchmarks.md) or `json` (rows of operation,
    /// median and notes).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Format {
    Text,
    Json,
}

/// Output piped into a reader that stops early (`cierva validate | head`): `println!` panics on
/// the broken pipe. Leave quietly instead, with the exit status a shell gives a process that
/// SIGPIPE ended (128 + 13), so a pipeline can still tell the run was cut short.
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    quiet_on_broken_pipe();
    let cli = Cli::parse();
    QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    match cli.command {
        Command::Validate {
            paths,
            corrections,
            format,
            report_dir,
            no_report,
        } => validate(
            paths,
            corrections,
            format,
            (!no_report).then_some(report_dir),
        ),
        Command::Review {
            paths,
            accept,
            format,
        } => cli::review::run(paths, accept, format),
        Command::Fit {
            file,
            output,
            report,
            format,
        } => fit(file, output, report, format),
        Command::Modes {
            file,
            sweep,
            format,
        } => modes(file, sweep, format),
        Command::Bench(args) => bench(args.repeat, args.format),
        Command::NewCase { path, format } => new_case(path, format),
        Command::Inflow {
            record,
            rotor,
            coning,
            skew,
            density_kg_m3,
            collective_deg,
            format,
        } => inflow(
            record,
            rotor,
            cierva_harness::ident::flap::FlapSettings {
                coning,
                skew,
                density_kg_m3,
                collective_deg,
            },
            format,
        ),
        Command::SynthTeeter {
            tunnel:
                TunnelArgs {
                    rotor,
                    alpha_deg,
                    airspeed_m_s,
                    collective_deg,
                },
            duration_s,
            sample_rate_hz,
            seed,
            noise_deg,
            output,
            format,
        } => synth_teeter(
            rotor,
            alpha_deg,
            airspeed_m_s,
            collective_deg,
            (duration_s, sample_rate_hz, seed, noise_deg),
            (output, format),
        ),
        Command::Synth(args) => synth(args),
        Command::Identify {
            record,
            config,
            format,
            predict,
        } => identify(record, config, format, predict),
        Command::Autorotate {
            tunnel:
                TunnelArgs {
                    rotor,
                    alpha_deg,
                    airspeed_m_s,
                    collective_deg,
                },
            density_kg_m3,
            inflow,
            skew,
            format,
        } => autorotate(
            rotor,
            alpha_deg,
            airspeed_m_s,
            collective_deg,
            density_kg_m3,
            inflow.model(skew),
            format,
        ),
        Command::Linearize { flight, format } => linearize(flight, format),
        Command::Simulate {
            flight,
            input,
            shape,
            duration_s,
            azimuth_step_deg,
            every,
            output,
            format,
        } => simulate(
            flight,
            (input, shape.input(), shape.control),
            (duration_s, azimuth_step_deg, every),
            output,
            format,
        ),
        Command::SynthHistory(a) => synth_history(a),
        Command::Trim {
            flight,
            turn_rate_deg_s,
            format,
        } => trim(
            &flight,
            flight.request(turn_rate_deg_s),
            flight.loading(),
            format,
        ),
    }
}

fn simulate(
    f: FlightArgs,
    (input, shape, control): (
        Option<PathBuf>,
        Option<cierva_harness::ident::synth::Input>,
        String,
    ),
    (duration_s, azimuth_step_deg, every): (f64, Option<f64>, usize),
    output: PathBuf,
    format: Format,
) -> ExitCode {
    use cierva_harness::controls_file;
    let file = match load_flight(&f) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let table = match (&input, &shape) {
        (Some(p), None) => match controls_file::read(p) {
            Ok(t) => Some(t),
            Err(e) => {
                eprintln!("{}", e.render());
                return ExitCode::from(2);
            }
        },
        (None, Some(_)) => None,
        _ => {
            eprintln!("error: give exactly one of --input CSV or --shape");
            return ExitCode::from(2);
        }
    };
    let index = match control_index(&control) {
        Ok(i) => i,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let changes = |t: f64| -> [f64; 4] {
        match (&table, &shape) {
            (Some(tb), _) => tb.at(t),
            (None, Some(s)) => {
                let mut d = [0.0; 4];
                d[index] = s.at(t);
                d
            }
            _ => [0.0; 4],
        }
    };
    let step = azimuth_step_deg.map_or(
        file.aircraft.main_rotor.numerics.azimuth_step_rad,
        f64::to_radians,
    );
    let (request, loading) = (f.request(0.0), f.loading());
    let settings = cierva_model::timehistory::Settings {
        azimuth_step_rad: step,
        duration_s,
        output_every: every,
    };
    let started = std::time::Instant::now();
    let busy = spinner(&format!("flying {duration_s} s"));
    let flown =
        cierva_harness::run_simulation(&file.aircraft, request, loading, &changes, settings);
    busy.finish_and_clear();
    match flown {
        Ok(h) => {
            if let Err(e) = std::fs::write(&output, controls_file::to_csv(&h)) {
                eprintln!("error: cannot write {}: {e}", output.display());
                return ExitCode::from(2);
            }
            let seconds = started.elapsed().as_secs_f64();
            done(
                format,
                format!(
                    "wrote {} ({} samples, step {:.2} ms, {:.2} s of flight in {:.2} s)",
                    output.display(),
                    h.samples.len(),
                    1e3 * h.step_s,
                    duration_s,
                    seconds
                ),
                serde_json::json!({
                    "wrote": [output.display().to_string()],
                    "samples": h.samples.len(),
                    "step_s": h.step_s,
                    "duration_s": duration_s,
                    "seconds": seconds,
                }),
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}: {e}", f.aircraft.display());
            ExitCode::from(1)
        }
    }
}

fn linearize(f: FlightArgs, format: LinearFormat) -> ExitCode {
    let file = match load_flight(&f) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let (request, loading) = (f.request(0.0), f.loading());
    let (t, lin) = match cierva_harness::run_linearise(&file.aircraft, request, loading) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("error: {}: {e}", f.aircraft.display());
            return ExitCode::from(if e.is_input() { 2 } else { 1 });
        }
    };
    let mass = f.mass_kg.unwrap_or(file.aircraft.mass.mass_kg);
    let condition = format!(
        "{} mph, climb {} m/s, {} kg, density altitude {} ft",
        f.airspeed_mph, f.climb_m_s, mass, f.density_altitude_ft
    );
    match format {
        LinearFormat::Yaml => {
            let id = format!("{}-{}mph-{}kg", file.id, f.airspeed_mph, mass.round());
            print!(
                "{}",
                text::linear_reference_yaml(
                    &id,
                    &format!("{} linearised at {condition}", file.title),
                    &format!(
                        "cierva linearize {} ({}), trim residual {:.1e}",
                        env!("CARGO_PKG_VERSION"),
                        f.aircraft.display(),
                        t.residual_norm
                    ),
                    &lin.model,
                    &cierva_harness::linear_units(),
                )
            );
        }
        LinearFormat::Json => {
            let derivs: Vec<serde_json::Value> = text::PRIMARY_DERIVATIVES
                .iter()
                .filter_map(|n| {
                    let v = lin.model.derivative_value(n).ok()?;
                    let parts: serde_json::Map<String, serde_json::Value> = lin
                        .breakdown(n)
                        .ok()?
                        .into_iter()
                        .map(|(c, x)| (c, serde_json::json!(x)))
                        .collect();
                    Some(serde_json::json!({"name": n, "value": v, "components": parts}))
                })
                .collect();
            let m = &lin.model;
            let out = serde_json::json!({
                "condition": condition,
                "trim": t,
                "states": m.states(),
                "controls": m.controls(),
                "a": (0..m.states().len()).map(|i| (0..m.states().len()).map(|j| m.a()[(i, j)]).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "b": (0..m.states().len()).map(|i| (0..m.controls().len()).map(|j| m.b()[(i, j)]).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "primary_derivatives": derivs,
            });
            println!(
                "{}",
                serde_json::to_string_pretty(&out).expect("serialisable")
            );
        }
        LinearFormat::Text => {
            println!("{} at {condition}", file.title);
            println!(
                "trim: stick {:.2} % / {:.2} %, pedal {:.2} %, throttle {:.2} %, pitch {:.3} deg, roll {:.3} deg, rotor {:.1} rpm (residual {:.1e})",
                t.controls.stick_longitudinal_percent,
                t.controls.stick_lateral_percent,
                t.controls.pedal_percent,
                t.controls.throttle_percent,
                t.pitch_rad.to_degrees(),
                t.roll_rad.to_degrees(),
                t.rotor_rpm,
                t.residual_norm
            );
            println!("\nprimary derivatives by component (SI; controls per % of travel):");
            print!("{}", text::breakdown_table(&lin, text::PRIMARY_DERIVATIVES));
            match cierva_model::modes(&lin.model) {
                Ok(a) => {
                    println!("\nmodes, 10 states:");
                    print!("{}", text::modes_table(&a));
                }
                Err(e) => println!("modes: {e}"),
            }
            if let Ok(lon) = lin.longitudinal()
                && let Ok(a) = cierva_model::modes(&lon)
            {
                println!("\nmodes, longitudinal [u w q theta Omega]:");
                print!("{}", text::modes_table(&a));
            }
            println!("\nall derivatives:");
            print!("{}", text::derivatives_table(&lin.model));
        }
    }
    ExitCode::SUCCESS
}

fn trim(
    flight: &FlightArgs,
    request: cierva_harness::TrimRequest,
    loading: cierva_harness::Loading,
    format: Format,
) -> ExitCode {
    let file = match load_flight(flight) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let path = &flight.aircraft;
    let t = match cierva_harness::run_trim(&file.aircraft, request, loading) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: {e}", path.display());
            return ExitCode::from(if e.is_input() { 2 } else { 1 });
        }
    };
    match format {
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(&t).expect("serialisable")
        ),
        Format::Text => print!("{}", text::trim_report(&file.title, request, loading, &t)),
    }
    ExitCode::SUCCESS
}

fn validate(
    paths: Vec<PathBuf>,
    corrections: Vec<PathBuf>,
    format: Format,
    report_dir: Option<PathBuf>,
) -> ExitCode {
    use cierva_harness::report;
    let started = std::time::Instant::now();
    let paths = if paths.is_empty() {
        vec![PathBuf::from("cases")]
    } else {
        paths
    };
    let mut correction_files = Vec::new();
    for p in &corrections {
        match cierva_harness::corrections::load(p) {
            Ok(f) => correction_files.push(f),
            Err(e) => {
                eprintln!("{}", e.render());
                return ExitCode::from(2);
            }
        }
    }
    let loaded = match load_cases(&paths) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    if loaded.is_empty() {
        eprintln!("error: no case files (*.yaml) under {}", show(&paths));
        return ExitCode::from(2);
    }
    let board = match cierva_harness::scoreboard::load() {
        Ok(b) => b,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let mut errors = Vec::new();
    let mut corrected: Vec<String> = Vec::new();
    let mut run = report::Run::default();
    let mut scores = Vec::new();
    let bar = progress(loaded.len() as u64, "validate");
    // Cases on every core; results in the order the cases were found.
    type Ran = Result<(report::CaseRun, Vec<cierva_harness::scoreboard::Score>), String>;
    let ran: Vec<Ran> = cierva_harness::parallel_map(&loaded, |c| {
        let out = match c {
            Ok(case) => match cierva_harness::corrections::apply_to_case(case, &correction_files) {
                Ok((case, used)) => {
                    bar.set_message(case.id.clone());
                    let t = std::time::Instant::now();
                    let results = eval::run_case(&case);
                    let scores = cierva_harness::scoreboard::scores_of(&case, &results);
                    Ok((
                        report::CaseRun {
                            case,
                            results,
                            seconds: t.elapsed().as_secs_f64(),
                            corrections: used,
                        },
                        scores,
                    ))
                }
                Err(e) => Err(format!("error: the corrections {e}")),
            },
            Err(e) => Err(e.render()),
        };
        bar.inc(1);
        out
    });
    for r in ran {
        match r {
            Ok((case_run, case_scores)) => {
                if !case_run.corrections.is_empty() {
                    corrected.push(format!(
                        "{} ({})",
                        case_run.case.id,
                        case_run.corrections.join(", ")
                    ));
                }
                scores.extend(case_scores);
                run.cases.push(case_run);
            }
            Err(e) => errors.push(e),
        }
    }
    bar.finish_and_clear();
    run.input_errors = errors.clone();
    run.corrections = correction_files
        .iter()
        .map(|f| (f.path.clone(), f.corrections.describe()))
        .collect();
    run.seconds = started.elapsed().as_secs_f64();
    // Scores against corrected models are not the committed model's: shown, never judged.
    let judged = cierva_harness::scoreboard::judge(&board, scores);
    let scores_failing: Vec<&cierva_harness::scoreboard::Judged> = if correction_files.is_empty() {
        judged
            .iter()
            .filter(|j| {
                matches!(
                    j.change,
                    cierva_harness::scoreboard::Change::Worse
                        | cierva_harness::scoreboard::Change::New
                )
            })
            .collect()
    } else {
        vec![]
    };
    run.scores = judged.clone();
    if report_dir.is_some() {
        run.score_versions = cierva_harness::scoreboard::versions();
    }
    let results: Vec<CheckResult> = run
        .cases
        .iter()
        .flat_map(|c| c.results.iter().cloned())
        .collect();
    let written = match &report_dir {
        Some(dir) => match report::write(&run, dir) {
            Ok(w) => w,
            Err(e) => {
                eprintln!(
                    "error: could not write the report to {}: {e}",
                    dir.display()
                );
                return ExitCode::from(2);
            }
        },
        None => vec![],
    };
    let counts = text::counts(&results);
    let corrections_used: Vec<serde_json::Value> = correction_files
        .iter()
        .map(|f| {
            serde_json::json!({
                "file": f.path.display().to_string(),
                "corrections": f.corrections,
            })
        })
        .collect();
    match format {
        Format::Json => {
            let out = serde_json::json!({
                "cases": loaded.len(),
                "corrections": corrections_used,
                "corrected_cases": corrected,
                "counts": counts,
                "scores": judged,
                "counts_by_class": text::counts_by_class(&results)
                    .into_iter()
                    .map(|(k, c)| (k.name(), c))
                    .collect::<std::collections::BTreeMap<_, _>>(),
                "input_errors": errors,
                "results": results,
                "report": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            });
            println!(
                "{}",
                serde_json::to_string_pretty(&out).expect("serialisable")
            );
        }
        Format::Text => {
            print!("{}", text::results_table(&results));
            if !judged.is_empty() {
                println!(
                    "\nscoreboard ({}):",
                    cierva_harness::scoreboard::path().display()
                );
                for j in &judged {
                    println!("  {}", j.describe());
                }
            }
            for r in results.iter().filter(|r| !r.outcome.ok()) {
                println!("\n{}", r.explain());
            }
            for e in &errors {
                println!("\n{e}");
            }
            for f in &correction_files {
                println!(
                    "\ncorrections {}: {}",
                    f.path.display(),
                    f.corrections.describe()
                );
            }
            if !correction_files.is_empty() {
                println!(
                    "cases run with corrections: {}",
                    if corrected.is_empty() {
                        "none (no case's aircraft or rotor matches)".to_string()
                    } else {
                        corrected.join("; ")
                    }
                );
            }
            println!(
                "\n{} cases, {} checks: {}, {} files with errors\nby class (only validation compares the model with measured data):\n{}",
                loaded.len(),
                results.len(),
                counts.describe(),
                errors.len(),
                text::class_summary(&results).trim_end()
            );
            if !written.is_empty() {
                println!("report: {}", show(&written));
            }
        }
    }
    if !errors.is_empty() {
        ExitCode::from(2)
    } else if counts.failing() > 0 || !scores_failing.is_empty() {
        if !scores_failing.is_empty() && format == Format::Text {
            println!(
                "scores worse than committed or not committed: {}; if intended, `cierva review --accept`",
                scores_failing
                    .iter()
                    .map(|j| format!("{} {}", j.score.case, j.score.id))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

fn fit(
    file: PathBuf,
    output: Option<PathBuf>,
    report: Option<PathBuf>,
    format: Format,
) -> ExitCode {
    use cierva_harness::fit_file;
    let f = match fit_file::load(&file) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let output = output.unwrap_or_else(|| {
        file.parent()
            .unwrap_or(Path::new("."))
            .join("results")
            .join(format!("{}.yaml", f.id))
    });
    let report = report.unwrap_or_else(|| PathBuf::from(format!("reports/fits/{}.md", f.id)));
    let busy = spinner(&format!("fitting {}", f.id));
    let run = fit_file::run(&f);
    busy.finish_and_clear();
    let id = output
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(&f.id)
        .to_string();
    let command = format!("cierva fit {}", file.display());
    let spec = fit_file::corrections_file(&f, &run, &id, &command);
    let mut md = fit_file::markdown(&f, &run);
    // The before/after figure beside the Markdown (which shows it), and in `validate`'s report.
    let svg_path = report.with_extension("svg");
    let svg = fit_file::figure(&f, &run).svg(640, 380);
    if let (Some(_), Some(name)) = (&svg, svg_path.file_name()) {
        md += &format!(
            "\n![Every target's error before and after, in standard errors]({})\n",
            name.to_string_lossy()
        );
    }
    let written = (|| -> Result<(), String> {
        let mut files = vec![
            (
                &output,
                serde_yaml::to_string(&spec).map_err(|e| e.to_string())?,
            ),
            (&report, md.clone()),
        ];
        if let Some(svg) = &svg {
            files.push((&svg_path, svg.clone()));
        }
        for (path, text) in files {
            if let Some(dir) = path.parent()
                && !dir.as_os_str().is_empty()
            {
                std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            }
            std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        Ok(())
    })();
    if let Err(e) = written {
        eprintln!("error: writing the fit's results: {e}");
        return ExitCode::from(2);
    }
    match format {
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({
                "fit": f.id,
                "run": run,
                "corrections_file": output.display().to_string(),
                "report": report.display().to_string(),
                "figure": svg.as_ref().map(|_| svg_path.display().to_string()),
            }))
            .expect("serialisable")
        ),
        Format::Text => {
            print!("{md}");
            println!(
                "wrote {}, {}{}",
                output.display(),
                report.display(),
                if svg.is_some() {
                    format!(" and {}", svg_path.display())
                } else {
                    String::new()
                }
            );
        }
    }
    if run.result.status == cierva_harness::fit::Status::Converged {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

fn modes(file: PathBuf, sweep: Option<String>, format: Format) -> ExitCode {
    let r = match refs::load(&file) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let Some(model) = r.linear_model else {
        eprintln!("error: {}: no `linear_model` block", file.display());
        return ExitCode::from(2);
    };
    if let Some(spec) = sweep {
        return locus(&model, &spec, format);
    }
    let analysis = match cierva_model::modes(&model) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {}: {e}", file.display());
            return ExitCode::from(2);
        }
    };
    match format {
        Format::Json => {
            let assessed: Vec<_> = analysis
                .modes
                .iter()
                .map(|m| serde_json::json!({ "mode": m, "bcar": cierva_model::bcar::assess(m) }))
                .collect();
            let out = serde_json::json!({
                "file": file,
                "id": r.id,
                "states": analysis.states,
                "modes": assessed,
                "milne": milne_json(&model),
            });
            println!(
                "{}",
                serde_json::to_string_pretty(&out).expect("serialisable")
            );
        }
        Format::Text => {
            println!("{} ({})\n{}\n", r.title, r.id, r.provenance.source);
            print!("{}", text::modes_table(&analysis));
            println!();
            print!("{}", text::milne_table(&model));
        }
    }
    ExitCode::SUCCESS
}

fn locus(model: &cierva_model::LinearModel, spec: &str, format: Format) -> ExitCode {
    use cierva_model::locus;
    let parsed = spec.split_once('=').and_then(|(d, range)| {
        let p: Vec<&str> = range.split(':').collect();
        match p.as_slice() {
            [a, b, n] => Some((
                d,
                a.parse::<f64>().ok()?,
                b.parse::<f64>().ok()?,
                n.parse::<usize>().ok()?,
            )),
            _ => None,
        }
    });
    let Some((name, from, to, n)) = parsed.filter(|(_, a, b, _)| a.is_finite() && b.is_finite())
    else {
        eprintln!(
            "error: --sweep `{spec}`: expected DERIVATIVE=FROM:TO:POINTS, for example Q_u=0.06:0.26:11"
        );
        return ExitCode::from(2);
    };
    let element = match model.derivative(name) {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: --sweep: {e}");
            return ExitCode::from(2);
        }
    };
    let points = match locus::root_locus(model, element, &locus::linspace(from, to, n)) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: --sweep: {e}");
            return ExitCode::from(2);
        }
    };
    match format {
        Format::Json => {
            let out: Vec<_> = points
                .iter()
                .map(|p| serde_json::json!({ "value": p.value, "modes": p.analysis.modes }))
                .collect();
            let out = serde_json::json!({ "derivative": name, "points": out });
            println!(
                "{}",
                serde_json::to_string_pretty(&out).expect("serialisable")
            );
        }
        Format::Text => {
            println!("root locus: {name} from {from} to {to} ({n} points)");
            for p in &points {
                let modes: Vec<String> = p
                    .analysis
                    .modes
                    .iter()
                    .map(|m| format!("{} {:.4}", m.kind.name(), m.eigenvalue))
                    .collect();
                println!(
                    "{name} = {:>12}  {}",
                    text::sig(p.value, 6),
                    modes.join("; ")
                );
            }
        }
    }
    ExitCode::SUCCESS
}

fn milne_json(m: &cierva_model::LinearModel) -> serde_json::Value {
    use cierva_model::milne;
    let eq13 = milne::eq13(m);
    serde_json::json!({
        "reduced": milne::reduced(m).and_then(|r| milne::as_array3(&r)).map_err(|e| e.to_string()),
        "eq13": eq13.as_ref().map_err(|e| e.to_string()),
        "cubic": eq13.map_err(|e| e.to_string()).and_then(|e| e.cubic().map_err(|e| e.to_string())).map(|c| {
            serde_json::json!({ "cubic": c, "sensitivity": c.sensitivity() })
        }),
    })
}

fn show(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn autorotate(
    path: PathBuf,
    alpha_deg: f64,
    airspeed_m_s: f64,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
    inflow: InflowModel,
    format: Format,
) -> ExitCode {
    let file = match cierva_harness::rotor_file::load(&path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let a = match run_autorotation(
        &file.rotor,
        alpha_deg,
        airspeed_m_s,
        collective_deg,
        density_kg_m3,
        inflow,
    ) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {}: {e}", path.display());
            return ExitCode::from(if e.is_input() { 2 } else { 1 });
        }
    };
    match format {
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(&a).expect("serialisable")
        ),
        Format::Text => {
            let d = |r: f64| r.to_degrees();
            println!(
                "{} ({}) at alpha {alpha_deg} deg, {airspeed_m_s} m/s",
                file.title, file.id
            );
            println!(
                "rotorspeed           {:.3} rad/s ({:.1} rpm)",
                a.omega_rad_s, a.rpm
            );
            println!("tip-speed ratio mu   {:.4}", a.tip_speed_ratio);
            println!(
                "lift coefficient     {:.5}  (on q pi R^2)",
                a.lift_coefficient
            );
            println!("drag coefficient     {:.5}", a.drag_coefficient);
            println!("L/D                  {:.3}", a.lift_to_drag);
            println!(
                "thrust coefficient   {:.6}  (T / rho pi R^2 (Omega R)^2)",
                a.thrust_coefficient
            );
            println!(
                "thrust, H-force      {:.1} N, {:.1} N",
                a.thrust_n, a.h_force_n
            );
            println!(
                "flapping a0 a1 b1    {:.3} {:.3} {:.3} deg",
                d(a.a0_rad),
                d(a.a1_rad),
                d(a.b1_rad)
            );
            println!(
                "inflow v0 v1s v1c    {:.3} {:.3} {:.3} m/s; lambda {:.5}; skew {:.2} deg",
                a.inflow.v0,
                a.inflow.v1s,
                a.inflow.v1c,
                a.inflow_ratio,
                d(a.skew_rad)
            );
            println!(
                "converged            residual {:.1e} in {} Newton iterations",
                a.residual_norm, a.iterations
            );
        }
    }
    ExitCode::SUCCESS
}

fn bench(repeat: usize, format: Format) -> ExitCode {
    // Rows print as they are measured (text), or are gathered into JSON at the end.
    let rows = std::cell::RefCell::new(Vec::<String>::new());
    macro_rules! row {
        ($($t:tt)*) => {{
            let line = format!($($t)*);
            match format {
                Format::Text => println!("{line}"),
                Format::Json => rows.borrow_mut().push(line),
            }
        }};
    }
    use cierva_model::rotor::{Blade, HubVelocity, Inflow, Numerics, Operating};
    use std::time::Instant;
    let path = cierva_harness::repo_root().join("aircraft/pca-2-rotor.yaml");
    let file = match cierva_harness::rotor_file::load(&path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let rotor = &file.rotor;
    let repeat = repeat.max(3);
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let time = |f: &mut dyn FnMut()| {
        let t = Instant::now();
        f();
        t.elapsed().as_secs_f64()
    };
    // TR 515 Table III row 19 conditions (mu 0.275, alpha 5.5 deg, 100 rpm), 1.9 deg pitch.
    let omega = 100.0 * std::f64::consts::PI / 30.0;
    let v = 0.275 * omega * rotor.radius_m / 5.5f64.to_radians().cos();
    let op = Operating {
        omega_rad_s: omega,
        hub: HubVelocity {
            u: v * 5.5f64.to_radians().cos(),
            v: 0.0,
            w: v * 5.5f64.to_radians().sin(),
        },
        inflow: Inflow {
            v0: 0.5,
            v1s: 0.0,
            v1c: -0.8,
        },
        density_kg_m3: 1.225,
        speed_of_sound_m_s: 340.3,
        collective_shift_rad: rotor.collective_shift_for(1.9f64.to_radians()),
        hub_rates_rad_s: [0.0; 3],
    };
    let blade = Blade::new(rotor, Numerics::default());
    let n_rhs = 10_000;
    let mut sink = 0.0;
    let rhs: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                for k in 0..n_rhs {
                    sink += blade.flap_derivative(&op, k as f64 * 1e-3, [0.1, 0.01])[1];
                }
            }) / n_rhs as f64
        })
        .collect();
    let warm = blade
        .steady(&op, [0.1, 0.0])
        .map(|l| l.beta0)
        .unwrap_or([0.1, 0.0]);
    let steady: Vec<f64> = (0..repeat)
        .map(|_| time(&mut || sink += blade.steady(&op, warm).map_or(0.0, |l| l.thrust_n())))
        .collect();
    let inflow = InflowModel::PetersHaQuang {
        skew: SkewConvention::Signed,
    };
    let auto: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                sink +=
                    run_autorotation(rotor, 5.5, v, Some(1.9), None, inflow).map_or(0.0, |a| a.rpm)
            })
        })
        .collect();
    row!("| operation | median | notes |");
    row!("| --- | --- | --- |");
    row!(
        "| blade right-hand side (flap equation with {} elements) | {:.2} us | one blade at one azimuth; {} blades per rotor evaluation |",
        rotor.elements + 1,
        1e6 * median(rhs),
        rotor.blades
    );
    row!(
        "| periodic blade solution (warm start, 2.5 deg steps, RK4) | {:.2} ms | one blade to a periodic state, then one revolution of loads |",
        1e3 * median(steady)
    );
    row!(
        "| PCA-2 autorotation (bracket + Newton on Omega, v0, v1s, v1c) | {:.1} ms | TR 515 row 19 condition, from a cold start |",
        1e3 * median(auto)
    );
    // The aircraft: VPM M16 trim at 70 mph and the model's right-hand sides at that trim.
    let ac_path = cierva_harness::repo_root().join("aircraft/vpm-m16.yaml");
    match cierva_harness::aircraft_file::load(&ac_path) {
        Err(e) => eprintln!("{}", e.render()),
        Ok(ac) => {
            let request = cierva_harness::TrimRequest {
                airspeed_mph: 70.0,
                climb_m_s: 0.0,
                turn_rate_deg_s: 0.0,
            };
            let loading = cierva_harness::Loading {
                mass_kg: None,
                density_altitude_ft: 0.0,
            };
            let mut last = None;
            let trims: Vec<f64> = (0..repeat)
                .map(|_| {
                    time(&mut || {
                        last = cierva_harness::run_trim(&ac.aircraft, request, loading).ok();
                    })
                })
                .collect();
            // The fit's case: the same condition with a correction moved a little (here the
            // mass, by 5 kg), started from the last trim's end.
            let heavier = cierva_harness::Loading {
                mass_kg: Some(ac.aircraft.mass.mass_kg + 5.0),
                ..loading
            };
            let mut warm_last = None;
            let warm_trims: Vec<f64> = match &last {
                None => vec![],
                Some(t) => (0..repeat)
                    .map(|_| {
                        time(&mut || {
                            warm_last = cierva_harness::run_trim_from(
                                &ac.aircraft,
                                request,
                                heavier,
                                Some(&t.warm_start),
                            )
                            .ok();
                        })
                    })
                    .collect(),
            };
            if let Some(t) = last {
                let air = cierva_model::aircraft::Air {
                    density_kg_m3: 1.225,
                    speed_of_sound_m_s: 340.294,
                };
                let a = &ac.aircraft;
                let x = a.full_state(&t.state, &t.controls, air, t.averaged.flap_start);
                let n = 1000;
                // Median time of one right-hand side of `craft`, over `n` azimuths a repeat.
                let mut rhs = |craft: &cierva_model::aircraft::Aircraft| -> Vec<f64> {
                    (0..repeat)
                        .map(|_| {
                            time(&mut || {
                                for k in 0..n {
                                    let mut y = x.clone();
                                    y.rotor_azimuth_rad = k as f64 * 0.01;
                                    sink += craft
                                        .derivatives(&y, &t.controls, air)
                                        .map_or(0.0, |d| d.body.u_m_s);
                                }
                            }) / n as f64
                        })
                        .collect()
                };
                let full = rhs(a);
                // The same with the propeller on its map, as a simulation runs it.
                let mut mapped = a.clone();
                if let Ok(p) = a.propeller.propeller.with_map() {
                    mapped.propeller.propeller = p;
                }
                let full_mapped = rhs(&mapped);
                let map_build: Vec<f64> = (0..repeat.min(5))
                    .map(|_| {
                        time(&mut || {
                            sink += a.propeller.propeller.build_map().nodes() as f64;
                        })
                    })
                    .collect();
                let averaged: Vec<f64> = (0..repeat)
                    .map(|_| {
                        time(&mut || {
                            sink += a
                                .averaged(&t.state, &t.controls, air, t.averaged.flap_start)
                                .map_or(0.0, |d| d.body_dot.u_m_s)
                        })
                    })
                    .collect();
                let lins: Vec<f64> = (0..repeat)
                    .map(|_| {
                        time(&mut || {
                            sink += cierva_harness::run_linearise(&ac.aircraft, request, loading)
                                .map_or(0.0, |(_, l)| l.model.a()[(0, 0)])
                        })
                    })
                    .collect();
                row!(
                    "| VPM M16 trim and linearisation at 70 mph | {:.1} ms | the trim, then central differences in 10 states, 4 controls and 4 fast states: 36 revolution-averaged evaluations on two threads, 12 of them reusing the rotor solution; target: under 100 ms |",
                    1e3 * median(lins)
                );
                // Simulation: 60 s of level flight from the full model's periodic trim, with 10
                // and 20 elements per blade, one thread.
                for elements in [10usize, 20] {
                    let mut a2 = ac.aircraft.clone();
                    a2.main_rotor.rotor.elements = elements;
                    let c = cierva_model::trim::Condition {
                        airspeed_m_s: 70.0 * cierva_harness::MPH_TO_M_S,
                        climb_m_s: 0.0,
                        turn_rate_rad_s: 0.0,
                        air,
                    };
                    let Ok(t2) = cierva_model::trim::trim(&a2, c, Default::default()) else {
                        continue;
                    };
                    let Ok(pt) = cierva_model::trim::periodic_trim(&a2, c, &t2, Default::default())
                    else {
                        continue;
                    };
                    let u = pt.controls;
                    let settings = cierva_model::timehistory::Settings {
                        azimuth_step_rad: a2.main_rotor.numerics.azimuth_step_rad,
                        duration_s: 60.0,
                        output_every: 72,
                    };
                    let runs: Vec<f64> = (0..repeat.min(5))
                        .map(|_| {
                            time(&mut || {
                                sink += cierva_model::timehistory::run(
                                    &a2,
                                    pt.start.clone(),
                                    &|_| u,
                                    air,
                                    settings,
                                )
                                .map_or(0.0, |h| h.step_s)
                            })
                        })
                        .collect();
                    let m = median(runs);
                    row!(
                        "| VPM M16 simulation, 60 s, {elements} elements per blade | {:.2} s | {:.0} times faster than real time on one core; RK4 at 5 deg of azimuth (about 2 ms), 4 right-hand sides a step; target: 200 times with 10 elements |",
                        m,
                        60.0 / m
                    );
                }
                row!(
                    "| VPM M16 trim at 70 mph, 450 kg, sea level (cold start) | {:.1} ms | {} Newton iterations (finite-difference Jacobian, then Broyden updates); target: under 50 ms |",
                    1e3 * median(trims),
                    t.iterations
                );
                if let Some(w) = warm_last {
                    row!(
                        "| VPM M16 trim at 70 mph, 455 kg, warm-started from the 450 kg trim | {:.1} ms | {} model evaluations against {} cold: the last Jacobian carried over, as in a fit |",
                        1e3 * median(warm_trims),
                        w.evaluations,
                        t.evaluations
                    );
                }
                row!(
                    "| full model right-hand side (individual blades, {} flap states, inflow, rotorspeed, propeller, airframe, 6-DOF) | {:.1} us | one evaluation at the 70 mph trim, including the propeller's inflow solution |",
                    x.flap.len(),
                    1e6 * median(full)
                );
                row!(
                    "| full model right-hand side, the propeller on its map | {:.1} us | what a simulation evaluates; the map (101 by 61 nodes of the exact solve) takes {:.0} ms to build, once per process and propeller |",
                    1e6 * median(full_mapped),
                    1e3 * median(map_build)
                );
                row!(
                    "| revolution-averaged model evaluation (periodic blade solution, warm) | {:.2} ms | what trim evaluates: the rotor's periodic flapping at 5 deg steps, then its mean loads |",
                    1e3 * median(averaged)
                );
            }
        }
    }
    // Identification: the five-state longitudinal model from 120 s at 100 Hz over 100
    // frequencies (the identification benchmark), on a synthetic record of seed 002's Eq. 20.
    use cierva_harness::ident::{self, record, synth};
    let truth =
        refs::load(&cierva_harness::repo_root().join("flight-refs/seed002-vpm-m16-60kn.yaml"))
            .ok()
            .and_then(|r| r.linear_model);
    if let Some(model) = truth {
        for (seconds, points) in [(120.0, 100), (240.0, 100), (120.0, 200)] {
            let settings = synth::Settings {
                id: "bench".into(),
                aircraft: "VPM M16".into(),
                truth: "seed 002 Eq. 20".into(),
                control: "eta_s".into(),
                input: cierva_harness::ident::synth::Input::Sweep {
                    from_hz: 0.02,
                    to_hz: 2.5,
                    duration_s: seconds - 20.0,
                    amplitude: 0.01,
                    descending: false,
                },
                duration_s: seconds,
                sample_rate_hz: 100.0,
                seed: 1,
                noise: synth::SensorNoise::NONE,
                turbulence: None,
                trim: synth::Trim {
                    u_m_s: 30.0,
                    w_m_s: 1.5,
                    theta_rad: 0.05,
                    omega_rotor_rad_s: 38.0,
                },
                sensors: record::Sensors {
                    probe_position_m: [2.0, 0.0, -0.3],
                    cg_position_m: [0.0; 3],
                },
            };
            let Ok((channels, data, meta)) = synth::generate(&model, &settings) else {
                continue;
            };
            let rec = record::Record {
                path: "bench.csv".into(),
                meta,
                channels,
                data,
            };
            let mut cfg = ident::ConfigSpec::longitudinal(&rec);
            cfg.frequencies.points = Some(points);
            let t: Vec<f64> = (0..repeat)
                .map(|_| {
                    time(&mut || {
                        sink += ident::identify_record(&rec, &cfg)
                            .map_or(0.0, |r| r.derivatives.len() as f64)
                    })
                })
                .collect();
            row!(
                "| identification, 5 states, {seconds} s at 100 Hz, {points} frequencies | {:.1} ms | air data to c.g., chirp-z transforms once, least squares then 2 instrumental-variable passes |",
                1e3 * median(t)
            );
        }
    }
    // Fitting (the fit benchmark): 3 parameters over 5 flight conditions, from the
    // uncorrected model to a synthetic truth (blockage 1.0, hub factor 0.5, drag +15 %), with X_u,
    // Z_w and the rotor speed at 40-70 mph as targets (at 30 mph the truth needs more than full
    // throttle).
    if let Ok(ac) = cierva_harness::aircraft_file::load(
        &cierva_harness::repo_root().join("aircraft/vpm-m16.yaml"),
    ) {
        use cierva_harness::fit::{
            self, Condition, Measure, Options, Parameter, ParameterKind, Problem, Subject, Target,
        };
        let par = |kind, lower, upper| Parameter {
            kind,
            lower,
            upper,
            start: ParameterKind::neutral(kind),
            regularisation: 0.0,
        };
        let mut problem = Problem {
            subject: Subject::Aircraft {
                aircraft: Box::new(ac.aircraft.clone()),
                loading: cierva_harness::Loading {
                    mass_kg: Some(425.0),
                    density_altitude_ft: 2000.0,
                },
            },
            parameters: vec![
                par(ParameterKind::PropellerBlockage, 0.0, 1.0),
                par(ParameterKind::HubAoaFactor, 0.0, 1.5),
                par(ParameterKind::ProfileDragScale, 0.5, 2.0),
            ],
            targets: vec![],
            options: Options::default(),
        };
        for mph in [40.0, 45.0, 55.0, 62.5, 70.0] {
            for (m, se) in [("X_u", 0.05), ("Z_w", 0.05), ("rotor_rpm", 0.01)] {
                let condition = Condition::Flight(cierva_harness::TrimRequest {
                    airspeed_mph: mph,
                    climb_m_s: 0.0,
                    turn_rate_deg_s: 0.0,
                });
                problem.targets.push(Target {
                    measure: Measure::parse(&condition, m).expect("known"),
                    condition,
                    reference: 0.0,
                    standard_error: se,
                    bounds: None,
                });
            }
        }
        let truth = [1.0, 0.5, 1.15];
        match fit::evaluate(&problem, &truth) {
            Err(e) => eprintln!("fit benchmark: the truth does not evaluate: {e}"),
            Ok(y) => {
                for (t, v) in problem.targets.iter_mut().zip(y) {
                    t.reference = v;
                    t.standard_error *= v.abs();
                }
                let started = Instant::now();
                let r = fit::fit(&problem);
                let total = started.elapsed().as_secs_f64();
                row!(
                    "| fit: 3 parameters, 5 conditions, 15 targets (synthetic truth) | {total:.2} s | {} in {} iterations ({:.2} s each), {} evaluations (trim, warm-started from the last at its condition, and linearisation at 5 conditions on two threads); found {:.4}, {:.4}, {:.4} against 1, 0.5, 1.15; target: under 5 s |",
                    r.status.name(),
                    r.iterations,
                    total / r.iterations.max(1) as f64,
                    r.evaluations,
                    r.values[0],
                    r.values[1],
                    r.values[2]
                );
            }
        }
    }

    if !sink.is_finite() {
        eprintln!("(a timed result was not finite)");
    }
    if format == Format::Json {
        let cells = |l: &str| -> Vec<String> {
            l.trim()
                .trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect()
        };
        let measured: Vec<serde_json::Value> = rows
            .borrow()
            .iter()
            .skip(2)
            .map(|l| {
                let c = cells(l);
                serde_json::json!({
                    "operation": c.first(),
                    "median": c.get(1),
                    "notes": c.get(2),
                })
            })
            .collect();
        done(
            format,
            String::new(),
            serde_json::json!({"repeat": repeat, "rows": measured}),
        );
    }
    ExitCode::SUCCESS
}

fn synth(a: SynthArgs) -> ExitCode {
    use cierva_harness::ident::{record, synth};
    let r = match refs::load(&a.model) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let Some(model) = r.linear_model else {
        eprintln!("error: {}: no `linear_model` block", a.model.display());
        return ExitCode::from(2);
    };
    let probe: Vec<f64> = a
        .probe_m
        .split(',')
        .filter_map(|v| v.trim().parse().ok())
        .collect();
    let [px, py, pz] = probe[..] else {
        eprintln!("error: --probe-m `{}`: expected x,y,z in metres", a.probe_m);
        return ExitCode::from(2);
    };
    let input = match a.input {
        InputChoice::Sweep | InputChoice::SweepDown => cierva_harness::ident::synth::Input::Sweep {
            from_hz: a.from_hz,
            to_hz: a.to_hz,
            duration_s: a.input_s,
            amplitude: a.amplitude,
            descending: a.input == InputChoice::SweepDown,
        },
        InputChoice::Doublet => cierva_harness::ident::synth::Input::Doublet {
            start_s: 2.0,
            pulse_s: a.input_s,
            amplitude: a.amplitude,
        },
        InputChoice::ThreeTwoOneOne => cierva_harness::ident::synth::Input::ThreeTwoOneOne {
            start_s: 2.0,
            unit_s: a.input_s,
            amplitude: a.amplitude,
        },
        InputChoice::Step => cierva_harness::ident::synth::Input::Step {
            start_s: 2.0,
            amplitude: a.amplitude,
        },
    };
    let k = a.noise_scale;
    let id = a
        .output
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let settings = synth::Settings {
        id,
        aircraft: r.title.clone(),
        truth: a.model.display().to_string(),
        control: a.control.clone(),
        input,
        duration_s: a.duration_s,
        sample_rate_hz: a.sample_rate_hz,
        seed: a.seed,
        noise: synth::SensorNoise {
            airspeed_m_s: 0.02 * k,
            vane_rad: 5e-4 * k,
            rate_rad_s: 5e-4 * k,
            attitude_rad: 5e-4 * k,
            rotor_rad_s: 0.01 * k,
            control: 0.0,
        },
        turbulence: (a.turbulence > 0.0).then_some(synth::Turbulence {
            intensity: a.turbulence,
            correlation_time_s: 0.5,
        }),
        trim: synth::Trim {
            u_m_s: a.trim_u_m_s,
            w_m_s: a.trim_w_m_s,
            theta_rad: a.trim_theta_rad,
            omega_rotor_rad_s: a.trim_rotor_rad_s,
        },
        sensors: record::Sensors {
            probe_position_m: [px, py, pz],
            cg_position_m: [0.0, 0.0, 0.0],
        },
    };
    match synth::generate(&model, &settings) {
        Ok((channels, data, meta)) => match record::write(&a.output, &meta, &channels, &data) {
            Ok(()) => {
                done(
                    a.format,
                    format!(
                        "wrote {} and {} ({} samples, seed {})",
                        a.output.display(),
                        record::sidecar_path(&a.output).display(),
                        data[0].len(),
                        a.seed
                    ),
                    serde_json::json!({
                        "wrote": [
                            a.output.display().to_string(),
                            record::sidecar_path(&a.output).display().to_string()
                        ],
                        "samples": data[0].len(),
                        "seed": a.seed,
                    }),
                );
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: cannot write {}: {e}", a.output.display());
                ExitCode::from(2)
            }
        },
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn identify(
    path: PathBuf,
    config: Option<PathBuf>,
    format: IdentFormat,
    predict: Option<PathBuf>,
) -> ExitCode {
    use cierva_harness::ident::{self, record};
    let rec = match record::load(&path) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let cfg = match config {
        None => ident::ConfigSpec::longitudinal(&rec),
        Some(p) => match cierva_harness::yaml::read(&p)
            .and_then(|src| cierva_harness::yaml::parse(&p, &src))
        {
            Ok(c) => c,
            Err(e) => {
                eprintln!("{}", e.render());
                return ExitCode::from(2);
            }
        },
    };
    let result = match ident::identify_record(&rec, &cfg) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    match format {
        IdentFormat::Json => println!(
            "{}",
            serde_json::to_string_pretty(&result).expect("serialisable")
        ),
        IdentFormat::Yaml => print!(
            "{}",
            ident::reference_yaml(&format!("{}-derivatives", rec.meta.id), &result, &rec)
        ),
        IdentFormat::Text => {
            println!(
                "{} ({}): {}",
                rec.meta.title, rec.meta.id, rec.meta.provenance.source
            );
            println!(
                "{:<14} {:>13} {:>12} {:>26}",
                "derivative", "estimate", "std error", "95 % bounds"
            );
            for d in &result.derivatives {
                println!(
                    "{:<14} {:>13} {:>12} {:>26}",
                    d.name,
                    text::sig(d.estimate, 5),
                    text::sig(d.standard_error, 3),
                    format!(
                        "[{}, {}]",
                        text::sig(d.lower_95, 4),
                        text::sig(d.upper_95, 4)
                    )
                );
            }
            for f in &result.fits {
                println!(
                    "equation {}: R^2 {:.5}, condition number {:.2e}, {} dof",
                    f.state, f.r_squared, f.condition_number, f.dof
                );
                for w in &f.warnings {
                    println!("  warning: {w}");
                }
            }
            println!("status: {}", result.status);
        }
    }
    if let Some(other) = predict {
        let outcome = record::load(&other)
            .map_err(|e| e.to_string())
            .and_then(|check| {
                let model = result.model.as_ref().ok_or("no identified model to fly")?;
                ident::predict(model, &check, &cfg)
            });
        match outcome {
            Ok(cmp) => {
                println!("prediction of {}:", other.display());
                for c in &cmp {
                    println!(
                        "  {:<8} RMS error {:>10}  Theil {:.4}",
                        c.signal,
                        text::sig(c.rms_error, 3),
                        c.theil
                    );
                }
            }
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        }
    }
    ExitCode::SUCCESS
}

fn inflow(
    path: PathBuf,
    rotor: PathBuf,
    settings: cierva_harness::ident::flap::FlapSettings,
    format: Format,
) -> ExitCode {
    use cierva_harness::ident::{flap, record};
    let loaded = record::load_with(&path, &flap::FLAP_REQUIRED, false)
        .and_then(|rec| cierva_harness::rotor_file::load(&rotor).map(|r| (rec, r)));
    let (rec, file) = match loaded {
        Ok(x) => x,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    match flap::inflow_from_record(&rec, &file.rotor, &settings) {
        Ok(r) => {
            match format {
                Format::Json => println!(
                    "{}",
                    serde_json::to_string_pretty(&r).expect("serialisable")
                ),
                Format::Text => {
                    println!(
                        "{} ({}): {:.1} revolutions, mu {:.4}",
                        rec.meta.title, rec.meta.id, r.revolutions, r.tip_speed_ratio
                    );
                    println!(
                        "disc tilts   beta_1c {:.4} deg, beta_1s {:.4} deg; coning {:.4} deg",
                        r.beta_1c_deg, r.beta_1s_deg, r.coning_deg
                    );
                    println!(
                        "inflow       v0 {:.4} m/s, v1s {:.4} m/s, v1c {:.4} m/s (tan(chi/2) = {:.4})",
                        r.v0_m_s, r.v1s_m_s, r.v1c_m_s, r.tan_half_skew
                    );
                }
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn synth_teeter(
    rotor: PathBuf,
    alpha_deg: f64,
    airspeed_m_s: f64,
    collective_deg: Option<f64>,
    (duration_s, sample_rate_hz, seed, noise_deg): (f64, f64, u64, f64),
    (output, format): (PathBuf, Format),
) -> ExitCode {
    use cierva_harness::ident::{flap, record};
    let file = match cierva_harness::rotor_file::load(&rotor) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let inflow = InflowModel::PetersHaQuang {
        skew: SkewConvention::Signed,
    };
    let a = match run_autorotation(
        &file.rotor,
        alpha_deg,
        airspeed_m_s,
        collective_deg,
        None,
        inflow,
    ) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(if e.is_input() { 2 } else { 1 });
        }
    };
    let id = output
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let (sa, ca) = alpha_deg.to_radians().sin_cos();
    let truth = format!(
        "{} at alpha {alpha_deg} deg, {airspeed_m_s} m/s",
        rotor.display()
    );
    let (channels, data, meta) = flap::synthesize_teeter(
        &id,
        &truth,
        &a,
        airspeed_m_s * ca,
        airspeed_m_s * sa,
        duration_s,
        sample_rate_hz,
        seed,
        noise_deg.to_radians(),
    );
    match record::write(&output, &meta, &channels, &data) {
        Ok(()) => {
            done(
                format,
                format!(
                    "wrote {} and its sidecar: model inflow v0 {:.4}, v1s {:.4}, v1c {:.4} m/s, coning {:.4} deg",
                    output.display(),
                    a.inflow.v0,
                    a.inflow.v1s,
                    a.inflow.v1c,
                    a.a0_rad.to_degrees()
                ),
                serde_json::json!({
                    "wrote": [
                        output.display().to_string(),
                        record::sidecar_path(&output).display().to_string()
                    ],
                    "model_inflow_m_s": {"v0": a.inflow.v0, "v1s": a.inflow.v1s, "v1c": a.inflow.v1c},
                    "coning_deg": a.a0_rad.to_degrees(),
                }),
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: cannot write {}: {e}", output.display());
            ExitCode::from(2)
        }
    }
}

fn new_case(path: PathBuf, format: Format) -> ExitCode {
    let Some(id) = path.file_stem().map(|s| s.to_string_lossy().to_string()) else {
        eprintln!("error: {}: not a file name", path.display());
        return ExitCode::from(2);
    };
    if path.exists() {
        eprintln!("error: {} exists; not overwritten", path.display());
        return ExitCode::from(2);
    }
    let text = include_str!("../templates/case.yaml").replace("CASE_ID", &id);
    match std::fs::write(&path, text) {
        Ok(()) => {
            done(
                format,
                format!(
                    "wrote {}: edit it, then `cierva validate {}`",
                    path.display(),
                    path.display()
                ),
                serde_json::json!({"wrote": [path.display().to_string()], "id": id}),
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: cannot write {}: {e}", path.display());
            ExitCode::from(2)
        }
    }
}

fn synth_history(a: SynthHistoryArgs) -> ExitCode {
    use cierva_harness::history;
    let file = match load_flight(&a.flight) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let corrections = cierva_harness::corrections::CorrectionSet {
        propeller_blockage: a.propeller_blockage,
        hub_aoa_factor: a.hub_aoa_factor,
        ..Default::default()
    };
    let file = match file.with_corrections(&corrections) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: the corrections: {e}");
            return ExitCode::from(2);
        }
    };
    let Some(shape) = a.shape.input() else {
        eprintln!("error: give --shape");
        return ExitCode::from(2);
    };
    let index = match control_index(&a.shape.control) {
        Ok(i) => i,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(a.duration_s) && ok(a.sample_rate_hz)) {
        eprintln!("error: --duration-s and --sample-rate-hz must be positive");
        return ExitCode::from(2);
    }
    let noise = history::Noise {
        speed_m_s: a.noise_speed_m_s,
        rate_deg_s: a.noise_rate_deg_s,
        angle_deg: a.noise_angle_deg,
        rpm: a.noise_rpm,
    };
    if ![
        noise.speed_m_s,
        noise.rate_deg_s,
        noise.angle_deg,
        noise.rpm,
    ]
    .iter()
    .all(|v| v.is_finite() && *v >= 0.0)
    {
        eprintln!("error: noise standard deviations must be finite and >= 0");
        return ExitCode::from(2);
    }
    let changes = |t: f64| {
        let mut d = [0.0; 4];
        d[index] = shape.at(t);
        d
    };
    let sample_s = 1.0 / a.sample_rate_hz;
    let step = a.azimuth_step_deg.map_or(
        file.aircraft.main_rotor.numerics.azimuth_step_rad,
        f64::to_radians,
    );
    let (request, loading) = (a.flight.request(0.0), a.flight.loading());
    let busy = spinner(&format!("flying {} s", a.duration_s));
    let flown = history::fly(
        &file.aircraft,
        request,
        loading,
        &changes,
        history::FlySettings {
            simulation: a.simulation,
            sample_s,
            samples: (a.duration_s / sample_s).round() as usize,
            azimuth_step_rad: step,
        },
    );
    busy.finish_and_clear();
    let flown = match flown {
        Ok(f) => f,
        Err(e) => {
            eprintln!("error: {}: {e}", a.flight.aircraft.display());
            return ExitCode::from(1);
        }
    };
    let id = a
        .output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mass = a.flight.mass_kg.unwrap_or(file.aircraft.mass.mass_kg);
    let simulation = match a.simulation {
        history::Simulation::FullBlade => format!(
            "the full individual-blade model (RK4, azimuth step {:.1} deg)",
            step.to_degrees()
        ),
        history::Simulation::Linear => "its linearisation about trim".to_string(),
    };
    let truth = format!(
        "{} ({}) with propeller blockage {} and hub AoA factor {}, flown by {simulation}",
        a.flight.aircraft.display(),
        file.title,
        file.aircraft.propeller.propeller.blockage,
        file.aircraft
            .hub_aoa_factor
            .map_or("none".to_string(), |k| k.to_string()),
    );
    let mut condition = std::collections::BTreeMap::new();
    for (k, v) in [
        ("airspeed_mph", a.flight.airspeed_mph),
        ("climb_m_s", a.flight.climb_m_s),
        ("mass_kg", mass),
        ("density_altitude_ft", a.flight.density_altitude_ft),
    ] {
        condition.insert(k.to_string(), serde_yaml::Value::from(v));
    }
    let mut settings = std::collections::BTreeMap::new();
    settings.insert(
        "input".to_string(),
        format!("{shape:?} on {}", a.shape.control),
    );
    settings.insert(
        "command".to_string(),
        std::env::args().skip(1).collect::<Vec<_>>().join(" "),
    );
    let spec = history::SyntheticSpec {
        id: id.clone(),
        title: a.title.clone().unwrap_or_else(|| {
            format!(
                "Synthetic {} response of the {} at {} mph",
                a.shape.control, file.title, a.flight.airspeed_mph
            )
        }),
        aircraft: file.title.clone(),
        truth,
        generator: format!("cierva synth-history {}", env!("CARGO_PKG_VERSION")),
        seed: a.seed,
        condition,
        settings,
    };
    let column = cierva_harness::controls_file::CONTROL_COLUMNS[index];
    let (meta, channels, data) =
        match history::synthesize(&flown, &changes, &[column], noise, &spec) {
            Ok(x) => x,
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        };
    match cierva_harness::ident::record::write(&a.output, &meta, &channels, &data) {
        Ok(()) => {
            done(
                a.format,
                format!(
                    "wrote {} and its sidecar ({} samples)",
                    a.output.display(),
                    flown.time_s.len()
                ),
                serde_json::json!({
                    "wrote": [
                        a.output.display().to_string(),
                        cierva_harness::ident::record::sidecar_path(&a.output).display().to_string()
                    ],
                    "samples": flown.time_s.len(),
                }),
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: cannot write {}: {e}", a.output.display());
            ExitCode::from(2)
        }
    }
}
