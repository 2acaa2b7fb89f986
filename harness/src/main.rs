//! The `cierva` command line: the commands and their arguments, parsed and dispatched to
//! `cli/`, one module per command.

mod cli;

use clap::Subcommand;
use cli::*;

/// Verification and validation of rotorcraft flight-dynamics models against flight references.
///
/// Exit codes: 0 every check passed (or failed as its case expects, with the model where its
/// record says); 1 a check failed unexpectedly, a known discrepancy moved, an expected failure
/// passed, a check could not be evaluated or a score got worse; 2 bad input (a case or reference
/// file that does not load, a missing path, no cases).
#[derive(Parser)]
#[command(name = "cierva", version)]
struct Cli {
    /// No progress bars or progress messages on stderr (results and errors are still printed).
    /// Progress bars are drawn only when stderr is a terminal.
    #[arg(long, global = true)]
    quiet: bool,
    /// The suite to work on: a folder with a `cierva.toml` (default: the nearest one in the
    /// working directory or a folder above). Default paths (cases, reports, the scoreboard,
    /// discrepancy records, retune's outputs) are relative to it.
    #[arg(long, global = true, value_name = "DIR")]
    suite: Option<PathBuf>,
    #[command(subcommand)]
    command: Command,
}

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
        /// Case files or folders searched for `*.yaml` (default: the suite's cases folder).
        paths: Vec<PathBuf>,
        /// Corrections files to apply (repeatable).
        #[arg(long)]
        corrections: Vec<PathBuf>,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
        /// Where to write the report: `index.html` (self-contained, with plots) and
        /// `summary.md` (default: the suite's reports folder).
        #[arg(long)]
        report_dir: Option<PathBuf>,
        /// Write no report.
        #[arg(long)]
        no_report: bool,
        /// Also each check's uncertainty and, for validation checks, its V&V 20 verdict (as
        /// `cierva uncertainty`, with --samples and --seed): under `uncertainty` in the JSON,
        /// and in the report.
        #[arg(long)]
        uncertainty: bool,
        /// With --uncertainty: base points of the Saltelli design (at least 8).
        #[arg(long, default_value_t = 64, requires = "uncertainty")]
        samples: usize,
        /// With --uncertainty: the Sobol' sequence's seed.
        #[arg(long, default_value_t = 0, requires = "uncertainty")]
        seed: u32,
    },
    /// Review the known discrepancies: run every check that is expected to fail and compare
    /// what the model gives with what is recorded for it in `reports/discrepancies/`.
    ///
    /// A check marked `expected_failure` stays one only while the model stays inside its
    /// recorded bands; when the model moves (better or worse), `cargo test` and `cierva validate`
    /// fail it as "discrepancy moved". This command lists what moved; `--accept` records the
    /// model's values as they are now (as `cargo insta review` accepts snapshots), with a
    /// reason (`--reason`), appending an entry to `reports/acceptances.yaml`: the date, commit,
    /// reason, each change (old, new, better or worse) and the fingerprint of the files
    /// written. Exit code 0 when nothing moved or all was accepted, 1 otherwise, 2 on bad input
    /// (`--accept` without `--reason`).
    ///
    /// Example: `cierva review cases/naca-tr515-table-iii.yaml`, then `cierva review --accept
    /// --reason "hub drag from the fitted corrections"`
    Review {
        /// Case files or folders searched for `*.yaml` (default: `cases`).
        paths: Vec<PathBuf>,
        /// Record the model's values as they are now (needs `--reason`).
        #[arg(long)]
        accept: bool,
        /// Why the scores and records may change (required with `--accept`): logged in
        /// `reports/acceptances.yaml` with what changed.
        #[arg(long, value_name = "TEXT")]
        reason: Option<String>,
        #[arg(long, value_enum, default_value_t = Format::Text)]
        format: Format,
    },
    /// Fit the model's empirical corrections (propeller blockage, hub angle-of-attack factor,
    /// profile drag and its Reynolds-number exponent, pitch offset, lateral inflow offset,
    /// elastic twist, hub drag) to flight references within bounds, and write the fitted
    /// corrections and a before/after table.
    ///
    /// The fit file names the subject (an aircraft at a mass and density altitude, or a rotor in
    /// a tunnel), the parameters with their bounds, and the targets: checks of a case (each
    /// check's expected value, with its tolerance as the standard error) or references written
    /// out, with optional hard or soft bounds. See harness/src/fit/file.rs for the format.
    ///
    /// Writes the corrections file (default: the suite's `corrections/fitted/<id>.yaml`, for
    /// `cierva validate --corrections`) and a Markdown report (default: the suite's `reports/fits/<id>.md`).
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
    /// Example: `cierva synth flight-refs/seed002-vpm-m16-60kn.yaml --control eta_s --shape sweep
    /// --amplitude-model-units 0.01 --seed 7 --output /tmp/vpm-sweep.csv`
    Synth(SynthArgs),
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
    /// Example: `cierva frequency-response /tmp/vpm-m16-70mph-sweep.csv --input eta_s_pct
    /// --output q_rad_s --windows-s 10 20 40 --format json`
    FrequencyResponse(FrequencyResponseArgs),
    /// Time-domain verification, as CIFER's VERIFY does (Tischler and Remple 2012): the
    /// identified model (a derivative table from `identify --format yaml`) and cierva's model
    /// (the aircraft linearised at the records' condition, as `identify --against`) are flown
    /// through each record's controls (perturbations about the sidecar's trim, piecewise linear
    /// between samples; RK4) from its first measured state, and compared with its measured
    /// states (air data converted to centre-of-mass velocities, as the identification does).
    ///
    /// Per output and model: Theil's inequality coefficient `TIC = rms(y - z) / (rms(y) +
    /// rms(z))` (0 perfect, 1 worst; about 0.25-0.3 or less is usually taken as good agreement,
    /// Jategaonkar 2006, ch. 11), the RMS error in the output's units, the mean error, and the
    /// TIC with the mean error taken off (VERIFY fits a bias per output; a note beside the plain
    /// TIC). Exit code 2 for bad input (a record without a control the model needs, a control
    /// in a unit the model contradicts, an unknown output, an unreadable table).
    ///
    /// Example: `cierva verify /tmp/vpm-m16-70mph-sweep.csv --identified
    /// /tmp/vpm-m16-70mph-sweep-derivatives.yaml --against aircraft/vpm-m16.yaml --figure
    /// /tmp/verify.svg` (the table from `cierva identify /tmp/vpm-m16-70mph-sweep.csv --format
    /// yaml`, saved under its id).
    Verify(VerifyArgs),
    /// Identify stability and control derivatives from a flight record (frequency-domain
    /// equation error, seed 000 Sec. IV): estimates, standard errors, 95 % bounds, fit quality,
    /// correlations and warnings.
    ///
    /// Example: `cierva identify /tmp/vpm-sweep.csv --format yaml > flight-refs/my-derivatives.yaml`
    ///
    /// Against the model: `cierva identify /tmp/vpm-m16-70mph-sweep.csv --against aircraft/vpm-m16.yaml`
    /// (the record from the `synth-flight` example).
    Identify {
        /// Record CSVs, each with its sidecar YAML beside it; several records of one condition
        /// are identified together (their spectra concatenated).
        #[arg(required = true, num_args = 1..)]
        records: Vec<PathBuf>,
        /// Identification set-up file (overrides --setup).
        #[arg(long)]
        config: Option<PathBuf>,
        /// A built-in set-up, 0.05-2 Hz at 100 points (default: longitudinal for one record,
        /// coupled for several).
        #[arg(long, value_enum)]
        setup: Option<cierva_harness::ident::Setup>,
        /// Linearise this aircraft at the records' condition (their sidecars' `condition`) and
        /// print its derivatives beside the identified ones, marking those inside the 95 %
        /// bounds.
        #[arg(long)]
        against: Option<PathBuf>,
        /// A corrections file to apply to the aircraft of --against.
        #[arg(long, requires = "against")]
        corrections: Option<PathBuf>,
        /// Average the rotor's blade-passage shaking (N_b per revolution) out of every signal
        /// before the fit: the number of blades (a moving average over one blade-passage period
        /// at the trim's rotorspeed, the same on every signal).
        #[arg(long)]
        blades: Option<u32>,
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
    /// Make a folder a suite: its `cierva.toml`, the shared tolerance library and one example
    /// case that validates (`cd DIR && cierva validate`).
    ///
    /// Example: `cierva init my-suite`
    Init(InitArgs),
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
    ///
    /// With `--tip-speed-ratio` and `--rotor-rpm` (or `--rpm`) instead, finds the angle of attack
    /// at which the rotor autorotates there (how TR 515 plots its data): `cierva autorotate
    /// aircraft/pca-2-rotor.yaml --tip-speed-ratio 0.5 --rotor-rpm 140 --collective-deg 1.9`.
    ///
    /// `--format json` gives the condition (`airspeed_m_s`, `alpha_deg`, `rpm`), the quantities
    /// by the names cases use (`rotor_alpha_deg`, `rotor_rpm`, `lift_coefficient`,
    /// `drag_coefficient`, `lift_to_drag`, ...) and the model's whole equilibrium.
    Autorotate(AutorotateArgs),
    /// Which physical parameter would close a discrepancy, and is the value it would need
    /// plausible? Trims and linearises the aircraft with each parameter moved a step either way
    /// and prints every quantity's derivative with respect to each; for a quantity outside its
    /// check's bound, the change of each parameter alone that would bring it to the nearer edge
    /// (a linear estimate), against the parameter's plausible range from the aircraft file
    /// (`ranges:`).
    ///
    /// Example: `cierva sensitivity --case cases/cierva-table2-vpm-m16-70mph-max-weight.yaml`,
    /// or `cierva sensitivity aircraft/vpm-m16.yaml --airspeed-mph 70 --quantities N_v,L_v
    /// --parameters airframe.fin.area_m2,mass.izz_kg_m2 --format json`.
    Sensitivity(SensitivityArgs),
    /// Estimate an aircraft's tail and pod coefficients from its geometry by published methods,
    /// and print the derivation step by step: each step's value and range, its inputs and its
    /// method, each method's source (with its equation or chart) and stated accuracy, and the
    /// file's values beside the estimates. The fin's and tailplane's lift slopes (Helmbold's
    /// equation in DATCOM's form, at the fin's effective aspect ratio with the end plates of
    /// the body and the tailplane, DATCOM Sec. 5.3.1.1), their shares of the propeller's
    /// slipstream and its dynamic pressure (momentum theory, at the propeller's operating point
    /// in trim), the sidewash at the fin (the propeller's straightening and the pod's
    /// cross-flow) and the pod's Munk couple (slender-body theory). The file gives the geometry
    /// under `airframe`: a surface's `planform` (span_m, root_chord_m, tip_chord_m; optional
    /// half_chord_sweep_deg, section_lift_slope_per_rad and, for the fin, body_depth_m), the
    /// `pod` (length_m, width_m, height_m, centroid_m) and `estimates_at` (airspeed_mph,
    /// mass_kg, density_altitude_ft: where to trim).
    ///
    /// Example: `cierva estimate aircraft/vpm-m16.yaml --format json`
    Estimate(EstimateArgs),
    /// The uncertainty of every check's quantities: the aircraft's estimated inputs sampled over
    /// their distributions (the aircraft file's `ranges:`; corrections excluded) on
    /// Owen-scrambled Sobol' points in a Saltelli design, every check evaluated at every point
    /// on every core; the numerical uncertainty from a refined discretisation; the data's from a
    /// tolerance's confidence level. For each validation check the comparison of ASME V&V 20:
    /// E = S - D, u_val = sqrt(u_num^2 + u_input^2 + u_D^2) and a verdict (agrees, model-form
    /// error, inconclusive), whether a pass is fragile, and the inputs by Sobol' total index.
    ///
    /// Example: `cierva uncertainty cases/cierva-table2-vpm-m16-70mph-max-weight.yaml --samples
    /// 256 --format json`
    Uncertainty(UncertaintyArgs),
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
        controls_csv: Option<PathBuf>,
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
    /// Fly a flight test with the full individual-blade model and record it in the
    /// identification format (`cierva identify` reads it): a pilot flies the input on one
    /// control with a loose attitude hold about slowly drifting references, through Dryden
    /// turbulence, and instruments with noise, bias and lag record air data at the probe,
    /// rates, attitudes, rotorspeed and every control at 100 Hz. The sidecar says it is
    /// synthetic, with the command, seed and truth.
    ///
    /// Example: `cierva synth-flight aircraft/vpm-m16.yaml --airspeed-mph 70 --manoeuvre sweep
    /// --control eta_s --amplitude-percent 4 --turbulence-m-s 0.3 --seed 1
    /// --output /tmp/vpm-m16-70mph-sweep.csv`
    SynthFlight(SynthFlightArgs),
    /// Retune corrections from flight records in one command: identify the records (each
    /// condition's together), fit the named corrections with clarabel so that the model's
    /// derivatives match the identified ones (weighted by their standard errors, within
    /// bounds), write the corrections file and a before/after report (derivatives against the
    /// bounds, modes, predictions of records not used), and run the validation suite's cases
    /// for this aircraft with the new corrections.
    ///
    /// Example: `cierva retune aircraft/vpm-m16.yaml --records /tmp/vpm-m16-70mph-sweep.csv
    /// --fit hub_aoa_factor --output /tmp/vpm-m16-retuned.yaml --report /tmp/vpm-m16-retuned.md`
    Retune(RetuneArgs),
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
    // Long: one arm per command: the dispatch
    quiet_on_broken_pipe();
    let cli = Cli::parse();
    QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    let _ = SUITE_ARG.set(cli.suite);
    match cli.command {
        Command::Validate {
            paths,
            corrections,
            format,
            report_dir,
            no_report,
            uncertainty,
            samples,
            seed,
        } => {
            if uncertainty && samples < cierva_harness::uncertainty::design::MIN_SAMPLES {
                eprintln!(
                    "error: --samples {samples}: give at least {}",
                    cierva_harness::uncertainty::design::MIN_SAMPLES
                );
                return ExitCode::from(2);
            }
            validate(
                paths,
                corrections,
                format,
                (!no_report).then_some(report_dir),
                uncertainty.then_some(cierva_harness::uncertainty::propagate::Settings {
                    samples,
                    seed,
                    validation_only: true,
                    method: cierva_harness::uncertainty::propagate::Method::Auto,
                }),
            )
        }
        Command::Review {
            paths,
            accept,
            reason,
            format,
        } => cli::review::run(paths, accept, reason, format),
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
        Command::Bench(args) => bench(args.repeat, args.format, args.only),
        Command::Init(a) => init(a),
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
            records,
            config,
            setup,
            against,
            corrections,
            blades,
            format,
            predict,
        } => identify(
            IdentifyArgs {
                records,
                config,
                setup,
                against,
                corrections,
                blades,
            },
            format,
            predict,
        ),
        Command::FrequencyResponse(a) => frequency_response(a),
        Command::Verify(a) => verify(a),
        Command::Autorotate(a) => autorotate(a),
        Command::Sensitivity(a) => sensitivity(a),
        Command::Estimate(a) => estimate(a),
        Command::Uncertainty(a) => uncertainty(a),
        Command::Linearize { flight, format } => linearize(flight, format),
        Command::Simulate {
            flight,
            controls_csv,
            shape,
            duration_s,
            azimuth_step_deg,
            every,
            output,
            format,
        } => simulate(
            flight,
            (controls_csv, shape.input(), shape.control),
            (duration_s, azimuth_step_deg, every),
            output,
            format,
        ),
        Command::SynthHistory(a) => synth_history(a),
        Command::SynthFlight(a) => synth_flight(a),
        Command::Retune(a) => retune(a),
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
