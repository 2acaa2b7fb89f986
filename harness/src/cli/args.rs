//! Arguments shared by several commands, and the value enums of the command line.

use super::*;

/// An aircraft and a flight condition (shared by `trim`, `linearize` and `simulate`).
#[derive(clap::Args)]
pub(crate) struct FlightArgs {
    /// An aircraft file (see aircraft/).
    pub(crate) aircraft: PathBuf,
    /// True airspeed, mph.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_mph: f64,
    /// Mass, kg (default: the aircraft file's).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) mass_kg: Option<f64>,
    /// Rate of climb, m/s; negative descends.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub(crate) climb_m_s: f64,
    /// Density altitude, ft (ISA).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub(crate) density_altitude_ft: f64,
    /// A corrections file (as `cierva fit` writes) to apply to the aircraft.
    #[arg(long)]
    pub(crate) corrections: Option<PathBuf>,
}

impl FlightArgs {
    /// The flight condition, turning at `turn_rate_deg_s`.
    pub(crate) fn request(
        &self,
        turn_rate_deg_s: f64,
    ) -> cierva_harness::inputs::condition::TrimRequest {
        cierva_harness::inputs::condition::TrimRequest {
            airspeed_mph: self.airspeed_mph,
            climb_m_s: self.climb_m_s,
            turn_rate_deg_s,
        }
    }

    /// The condition as a record's sidecar states it, with the mass flown (`mass_kg`).
    pub(crate) fn sidecar_condition(
        &self,
        mass_kg: f64,
    ) -> std::collections::BTreeMap<String, serde_yaml::Value> {
        [
            ("airspeed_mph", self.airspeed_mph),
            ("climb_m_s", self.climb_m_s),
            ("mass_kg", mass_kg),
            ("density_altitude_ft", self.density_altitude_ft),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), serde_yaml::Value::from(v)))
        .collect()
    }

    /// The mass and air.
    pub(crate) fn loading(&self) -> cierva_harness::inputs::condition::Loading {
        cierva_harness::inputs::condition::Loading {
            mass_kg: self.mass_kg,
            density_altitude_ft: self.density_altitude_ft,
        }
    }
}

/// A test input on one control (shared by `simulate` and `synth-history`).
#[derive(clap::Args)]
pub(crate) struct ShapeArgs {
    /// An input shape on one control (with --control and --amplitude-percent; `simulate` takes
    /// a CSV of control changes with --controls-csv instead).
    #[arg(long, value_enum)]
    pub(crate) shape: Option<InputChoice>,
    /// eta_s (longitudinal stick), eta_c (lateral stick), eta_p (pedal) or eta_t (throttle).
    #[arg(long, default_value = "eta_s")]
    pub(crate) control: String,
    /// Amplitude, % of travel.
    #[arg(long, allow_hyphen_values = true, default_value_t = 1.0)]
    pub(crate) amplitude_percent: f64,
    /// When a doublet, 3-2-1-1 or step starts, s.
    #[arg(long, default_value_t = 1.0)]
    pub(crate) start_s: f64,
    /// Pulse (doublet), unit (3-2-1-1) or length (sweep), s.
    #[arg(long, default_value_t = 1.0)]
    pub(crate) input_s: f64,
    /// Sweep band, Hz.
    #[arg(long, default_value_t = 0.1)]
    pub(crate) from_hz: f64,
    #[arg(long, default_value_t = 2.0)]
    pub(crate) to_hz: f64,
}

impl ShapeArgs {
    /// The input shape, if one is given.
    pub(crate) fn input(&self) -> Option<cierva_harness::synth::linear::TestInput> {
        use cierva_harness::synth::linear::TestInput;
        let (amplitude, start_s, input_s) = (self.amplitude_percent, self.start_s, self.input_s);
        self.shape.map(|c| match c {
            InputChoice::Sweep | InputChoice::SweepDown => TestInput::Sweep {
                from_hz: self.from_hz,
                to_hz: self.to_hz,
                duration_s: input_s,
                amplitude,
                descending: c == InputChoice::SweepDown,
            },
            InputChoice::Doublet => TestInput::Doublet {
                start_s,
                pulse_s: input_s,
                amplitude,
            },
            InputChoice::ThreeTwoOneOne => TestInput::ThreeTwoOneOne {
                start_s,
                unit_s: input_s,
                amplitude,
            },
            InputChoice::Step => TestInput::Step { start_s, amplitude },
        })
    }
}

/// Write a synthetic time-history reference record (for `time_history` checks): the
/// aircraft flown by the full blade model (or its linearisation) through a test input,
/// responses as changes from trim plus seeded sensor noise, with a sidecar that says it is
/// synthetic and how it was made.
///
/// Example: `cierva synth-history aircraft/vpm-m16.yaml --airspeed-mph 70 --shape doublet
/// --amplitude-percent 2 --duration-s 8 --noise-rate-deg-s 0.2 --seed 7
/// --output flight-refs/synthetic-vpm-m16-70mph-doublet.csv`
#[derive(clap::Args)]
pub(crate) struct SynthHistoryArgs {
    #[command(flatten)]
    pub(crate) flight: FlightArgs,
    /// `text` for people, `json` for programs (what was written, as an object).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,

    #[command(flatten)]
    pub(crate) shape: ShapeArgs,
    /// The model that flies: full-blade (the individual-blade model) or linear.
    #[arg(long, value_enum, default_value_t = cierva_harness::run::replay::Simulation::FullBlade)]
    pub(crate) simulation: cierva_harness::run::replay::Simulation,
    /// Seed 000's propeller blockage factor to fly with (0..1; default the aircraft file's).
    #[arg(long)]
    pub(crate) propeller_blockage: Option<f64>,
    /// Seed 000's hub angle-of-attack factor to fly with (default the aircraft file's).
    #[arg(long)]
    pub(crate) hub_aoa_factor: Option<f64>,
    /// Length of the record, s.
    #[arg(long, default_value_t = 10.0)]
    pub(crate) duration_s: f64,
    #[arg(long, default_value_t = 50.0)]
    pub(crate) sample_rate_hz: f64,
    /// Azimuth step of the full model, deg (default: the aircraft file's).
    #[arg(long)]
    pub(crate) azimuth_step_deg: Option<f64>,
    /// Standard deviations of the sensor noise: speeds m/s, rates deg/s, angles deg, rotor rpm.
    #[arg(long, default_value_t = 0.0)]
    pub(crate) noise_speed_m_s: f64,
    #[arg(long, default_value_t = 0.0)]
    pub(crate) noise_rate_deg_s: f64,
    #[arg(long, default_value_t = 0.0)]
    pub(crate) noise_angle_deg: f64,
    #[arg(long, default_value_t = 0.0)]
    pub(crate) noise_rpm: f64,
    #[arg(long, default_value_t = 1)]
    pub(crate) seed: u64,
    /// The record's title (its id is the output file's stem).
    #[arg(long)]
    pub(crate) title: Option<String>,
    /// The record CSV to write (its sidecar YAML goes beside it).
    #[arg(long)]
    pub(crate) output: PathBuf,
}

/// Output of `linearize`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum LinearFormat {
    Text,
    Json,
    Yaml,
}

/// A rotor in a wind tunnel: the rotor file and the condition (shared by `autorotate` and
/// `synth-teeter`).
#[derive(clap::Args)]
pub(crate) struct TunnelArgs {
    /// A rotor file (see aircraft/).
    pub(crate) rotor: PathBuf,
    /// Rotor angle of attack, deg: between the free stream and the plane normal to the
    /// shaft, positive with the air meeting the disc from below; 90 is vertical descent.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) alpha_deg: f64,
    /// Tunnel speed, m/s.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_m_s: f64,
    /// Blade pitch at the rotor file's pitch reference station, deg; shifts the whole pitch
    /// distribution (default: the file's distribution as it is).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) collective_deg: Option<f64>,
}

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
#[derive(clap::Args)]
pub(crate) struct AutorotateArgs {
    /// A rotor file (see aircraft/).
    pub(crate) rotor: PathBuf,
    /// Rotor angle of attack, deg: between the free stream and the plane normal to the
    /// shaft, positive with the air meeting the disc from below; 90 is vertical descent (with
    /// --airspeed-m-s).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) alpha_deg: Option<f64>,
    /// Tunnel speed, m/s (with --alpha-deg).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_m_s: Option<f64>,
    /// Tip-speed ratio mu (with --rotor-rpm, instead of --alpha-deg and --airspeed-m-s): finds
    /// the angle of attack at which the rotor autorotates at this mu and rotor speed.
    #[arg(long)]
    pub(crate) tip_speed_ratio: Option<f64>,
    /// Rotor speed, rpm (with --tip-speed-ratio; `--rpm` is the same).
    #[arg(long, alias = "rpm")]
    pub(crate) rotor_rpm: Option<f64>,
    /// Blade pitch at the rotor file's pitch reference station, deg; shifts the whole pitch
    /// distribution (default: the file's distribution as it is).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) collective_deg: Option<f64>,
    /// A corrections file for this rotor (as `cierva fit` writes), applied before solving.
    #[arg(long)]
    pub(crate) corrections: Option<PathBuf>,
    /// Air density, kg/m^3 (default 1.225, ISA sea level); the speed of sound is taken
    /// from the standard atmosphere at that density altitude.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) density_kg_m3: Option<f64>,
    /// Inflow model.
    #[arg(long, value_enum, default_value_t = InflowSpec::PetersHaquang)]
    pub(crate) inflow: InflowSpec,
    /// Wake skew angle convention in autorotation: seed 003 Eq. 5 (signed) or Eq. 6 (modulus).
    #[arg(long, value_enum, default_value_t = SkewSpec::Signed)]
    pub(crate) skew: SkewSpec,
    /// The wake's mass flow in descent: momentum theory, or Johnson's empirical curve in the
    /// vortex-ring and turbulent-wake states.
    #[arg(long, value_enum, default_value_t = DescentSpec::Momentum)]
    pub(crate) descent: DescentSpec,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

/// Output of `identify`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum IdentFormat {
    Text,
    Json,
    /// A flight-refs derivative table that cases can check models against.
    Yaml,
}

/// Test inputs.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum InputChoice {
    /// Frequency sweep, low to high.
    Sweep,
    /// Frequency sweep, high to low (seed 000 Fig. 5).
    SweepDown,
    Doublet,
    /// 3-2-1-1.
    ThreeTwoOneOne,
    Step,
}

/// Fly a linear model through a test input and write a synthetic flight record
/// (RECORD.csv and its sidecar RECORD.yaml), labelled synthetic with its generator, seed and
/// truth.
///
/// Example: `cierva synth flight-refs/seed002-vpm-m16-60kn.yaml --control eta_s --shape sweep
/// --amplitude-model-units 0.01 --seed 7 --output /tmp/vpm-sweep.csv`
#[derive(Parser)]
pub(crate) struct SynthArgs {
    /// A reference file with a `linear_model` block (the truth).
    pub(crate) model: PathBuf,
    /// `text` for people, `json` for programs (what was written, as an object).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,

    /// The control to excite.
    #[arg(long)]
    pub(crate) control: String,
    /// The input shape (as `--shape` of `simulate` and `synth-history`).
    #[arg(long, value_enum, default_value_t = InputChoice::Sweep)]
    pub(crate) shape: InputChoice,
    /// Input amplitude, in the control's own units as the model file's `units` gives them
    /// (a linear model's controls need not be in percent of travel).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) amplitude_model_units: f64,
    /// Sweep band, Hz.
    #[arg(long, default_value_t = 0.02)]
    pub(crate) from_hz: f64,
    #[arg(long, default_value_t = 2.5)]
    pub(crate) to_hz: f64,
    /// Length of the sweep (or the pulse unit of a doublet or 3-2-1-1, s).
    #[arg(long, default_value_t = 100.0)]
    pub(crate) input_s: f64,
    /// Length of the record, s.
    #[arg(long, default_value_t = 120.0)]
    pub(crate) duration_s: f64,
    #[arg(long, default_value_t = 100.0)]
    pub(crate) sample_rate_hz: f64,
    #[arg(long, default_value_t = 1)]
    pub(crate) seed: u64,
    /// Multiplies the default sensor noise (airspeed 0.02 m/s, vanes, rates and attitudes
    /// 5e-4 rad(/s), rotor 0.01 rad/s); 0 for a noise-free record.
    #[arg(long, default_value_t = 0.0)]
    pub(crate) noise_scale: f64,
    /// Turbulence: the standard deviation of a random forcing on each equation of u, v, w, p, q,
    /// r and Omega, in that equation's SI acceleration unit (m/s^2 or rad/s^2); 0 for none.
    #[arg(long, default_value_t = 0.0)]
    pub(crate) turbulence_si: f64,
    /// Trim about which the record is written (estimated defaults for the VPM M16 at 60 kn).
    #[arg(long, default_value_t = 30.0)]
    pub(crate) trim_u_m_s: f64,
    #[arg(long, default_value_t = 1.5, allow_hyphen_values = true)]
    pub(crate) trim_w_m_s: f64,
    #[arg(long, default_value_t = 0.05, allow_hyphen_values = true)]
    pub(crate) trim_theta_rad: f64,
    #[arg(long, default_value_t = 38.0)]
    pub(crate) trim_rotor_rad_s: f64,
    /// Air-data probe position relative to the c.g., body axes, m: x,y,z.
    #[arg(long, default_value = "2.0,0.0,-0.3", allow_hyphen_values = true)]
    pub(crate) probe_m: String,
    /// The record to write (its sidecar goes beside it, .yaml).
    #[arg(long)]
    pub(crate) output: PathBuf,
}

/// Time the model's building blocks on the PCA-2 rotor (aircraft/pca-2-rotor.yaml) and
/// print medians: the blade right-hand side, one periodic blade solution, one autorotation.
///
/// Example: `cargo run --release -- bench --repeat 51`
#[derive(Parser)]
pub(crate) struct BenchArgs {
    /// Repeats of each timed operation.
    #[arg(long, default_value_t = 21)]
    pub(crate) repeat: usize,
    /// `text` (a Markdown table, as in reports/benchmarks.md) or `json` (rows of operation,
    /// median and notes).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
    /// Only this group of rows (all by default).
    #[arg(long, value_enum)]
    pub(crate) only: Option<BenchGroup>,
}

/// The benchmark's groups of rows.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum BenchGroup {
    Rotor,
    Aircraft,
    Identification,
    FrequencyResponse,
    Fitting,
    Uncertainty,
    /// The command protocol's cost a request (a trivial model, one-shot and persistent).
    External,
}

/// Which parameter would close a discrepancy, and is the value it would need plausible? Asks
/// the model's trim and linear model with each parameter moved a step either way and prints
/// every quantity's derivative with respect to each; for a quantity outside its check's bound,
/// the change of each parameter alone that would bring it to the nearer edge (a linear
/// estimate), against the parameter's plausible range as the model declares it (an aircraft
/// file's `ranges:`; an external model's `describe`, protocol `cierva-external/2`).
///
/// Example: `cierva sensitivity --case cases/cierva-table2-vpm-m16-70mph-max-weight.yaml`,
/// or `cierva sensitivity aircraft/vpm-m16.yaml --airspeed-mph 70 --quantities N_v,L_v
/// --parameters airframe.fin.area_m2,mass.izz_kg_m2 --format json`.
#[derive(clap::Args)]
pub(crate) struct SensitivityArgs {
    /// An aircraft file (see aircraft/); or give --case.
    pub(crate) aircraft: Option<PathBuf>,
    /// A case of an aircraft: its aircraft, loading and condition, and the quantities of its
    /// derivative and trim checks with their bounds.
    #[arg(long)]
    pub(crate) case: Option<PathBuf>,
    /// True airspeed, mph (with a case: picks one of its conditions).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_mph: Option<f64>,
    /// Mass, kg (default: the aircraft file's); with an aircraft file.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) mass_kg: Option<f64>,
    /// Density altitude, ft (ISA); with an aircraft file.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub(crate) density_altitude_ft: f64,
    /// Parameters to move, by their names in the aircraft file (default: those the file gives
    /// a plausible range, or every one it has).
    #[arg(long, value_delimiter = ',')]
    pub(crate) parameters: Vec<String>,
    /// Quantities to differentiate: derivatives or trim quantities (default: the case's, or the
    /// primary derivatives).
    #[arg(long, value_delimiter = ',')]
    pub(crate) quantities: Vec<String>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

/// A flight-test manoeuvre.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum, Debug)]
pub(crate) enum Manoeuvre {
    /// An exponential frequency sweep (--from-hz to --to-hz).
    Sweep,
    /// Pulses of 3, 2, 1 and 1 times --pulse-s, alternating.
    #[value(name = "3211")]
    ThreeTwoOneOne,
    /// One pulse each way of --pulse-s.
    Doublet,
}

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
#[derive(clap::Args)]
pub(crate) struct SynthFlightArgs {
    #[command(flatten)]
    pub(crate) flight: FlightArgs,
    /// The test input.
    #[arg(long, value_enum)]
    pub(crate) manoeuvre: Manoeuvre,
    /// The control it moves: eta_s (longitudinal stick), eta_c (lateral stick), eta_p (pedal)
    /// or eta_t (throttle).
    #[arg(long)]
    pub(crate) control: String,
    /// The input's amplitude, % of travel.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) amplitude_percent: f64,
    /// The record's length, s (the input starts after 3 s of trim and ends 3 s before the end).
    #[arg(long, default_value_t = 120.0)]
    pub(crate) duration_s: f64,
    /// The sweep's frequencies, Hz.
    #[arg(long, default_value_t = 0.05)]
    pub(crate) from_hz: f64,
    #[arg(long, default_value_t = 2.0)]
    pub(crate) to_hz: f64,
    /// The pulse unit of a doublet or 3211, s.
    #[arg(long, default_value_t = 1.0)]
    pub(crate) pulse_s: f64,
    /// Vertical gust intensity sigma_w of Dryden turbulence (MIL-F-8785C), m/s; 0 for calm air.
    #[arg(long, default_value_t = 0.0)]
    pub(crate) turbulence_m_s: f64,
    /// Height above ground for the turbulence's scale lengths, ft (10-1000).
    #[arg(long, default_value_t = 500.0)]
    pub(crate) height_ft: f64,
    /// A sensors file (probe position, each channel's noise, bias and lag); default: the
    /// built-in instrumentation, each value with its source.
    #[arg(long)]
    pub(crate) sensors: Option<PathBuf>,
    /// Fly the input open loop, without the pilot's attitude hold.
    #[arg(long)]
    pub(crate) no_pilot: bool,
    #[arg(long, default_value_t = 100.0)]
    pub(crate) sample_rate_hz: f64,
    /// Azimuth step of the integration, deg (default: the aircraft file's).
    #[arg(long)]
    pub(crate) azimuth_step_deg: Option<f64>,
    #[arg(long)]
    pub(crate) seed: u64,
    /// The record's title (default: what was flown).
    #[arg(long)]
    pub(crate) title: Option<String>,
    /// The CSV to write; the sidecar goes beside it.
    #[arg(long)]
    pub(crate) output: PathBuf,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

/// Retune corrections from flight records in one command: estimate each condition's frequency
/// responses from its records (coherence, random error), fit the named corrections with
/// clarabel so that the model's responses as flown (its linearisation with the rotor's
/// flapping) match them, weighted by their random errors, within bounds with their sources;
/// write the corrections file and a before/after report (each response's mismatch cost,
/// modes, predictions of records not used), and run the validation suite's cases for this
/// aircraft with the new corrections.
///
/// Example: `cierva retune aircraft/vpm-m16.yaml --records /tmp/vpm-m16-70mph-sweep.csv
/// --fit hub_aoa_factor --output /tmp/vpm-m16-retuned.yaml --report /tmp/vpm-m16-retuned.md`
#[derive(clap::Args)]
pub(crate) struct RetuneArgs {
    /// The aircraft file whose corrections to retune.
    pub(crate) aircraft: PathBuf,
    /// Flight records (CSV with sidecars): records at one condition give its frequency
    /// responses together, records at several conditions fit one set of corrections across
    /// them.
    #[arg(long, required = true, num_args = 1..)]
    pub(crate) records: Vec<PathBuf>,
    /// The corrections (or estimated physical parameters) to fit.
    #[arg(long, required = true, num_args = 1..)]
    pub(crate) fit: Vec<String>,
    /// Bounds as NAME=LO:HI (default: each correction's sourced range, a physical parameter's
    /// plausible range from the aircraft file).
    #[arg(long, num_args = 1..)]
    pub(crate) bounds: Vec<String>,
    /// The responses' states, comma-separated, of u,v,w,p,q,r,Omega (default: each excited
    /// control's own axis's, u,w,q,Omega or v,p,r).
    #[arg(long, value_delimiter = ',')]
    pub(crate) outputs: Vec<String>,
    /// The responses' window lengths, s (default: an eighth, a quarter and a half of the
    /// shortest record).
    #[arg(long, num_args = 1..)]
    pub(crate) windows_s: Vec<f64>,
    /// The responses' band, Hz: LOW HIGH (default: five periods of the longest window to 2 Hz,
    /// identification's band's top, below the rotor's harmonics).
    #[arg(long, num_args = 2)]
    pub(crate) band_hz: Vec<f64>,
    /// Records not used in the fit, predicted before and after.
    #[arg(long, num_args = 1..)]
    pub(crate) predict: Vec<PathBuf>,
    /// The corrections file to write (default: the suite's `corrections/retuned/<aircraft id>.yaml`).
    #[arg(long)]
    pub(crate) output: Option<PathBuf>,
    /// The before/after report (default: the suite's reports/retune/<output's stem>.md).
    #[arg(long)]
    pub(crate) report: Option<PathBuf>,
    /// Skip running the validation suite's cases with the new corrections.
    #[arg(long)]
    pub(crate) no_validate: bool,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

/// The uncertainty of every check's quantities: the model's estimated inputs sampled over
/// their distributions (an aircraft file's `ranges:`, an external model's declared ranges;
/// corrections excluded) on Owen-scrambled Sobol' points in a Saltelli design, every check
/// evaluated at every point on every core; the numerical uncertainty from a refined
/// discretisation (cierva's own aircraft and rotors); the data's from a
/// tolerance's confidence level. For each validation check the comparison of ASME V&V 20:
/// E = S - D, u_val = sqrt(u_num^2 + u_input^2 + u_D^2) and a verdict (agrees, model-form
/// error, inconclusive), whether a pass is fragile, and the inputs by Sobol' total index.
///
/// Example: `cierva uncertainty cases/cierva-table2-vpm-m16-70mph-max-weight.yaml --samples
/// 256 --format json`
#[derive(clap::Args)]
pub(crate) struct UncertaintyArgs {
    /// Case files or folders (default: cases/, and then only their validation checks, as with
    /// --validation-only).
    pub(crate) paths: Vec<PathBuf>,
    /// Base points of the Saltelli design (at least 8; a power of two balances the Sobol'
    /// points best): a case of d uncertain inputs takes samples x (d + 2) evaluations.
    #[arg(long, default_value_t = 256)]
    pub(crate) samples: usize,
    /// Seed of the scrambled Sobol' sequence (a whole number, 0 to 4294967295).
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u32,
    /// Only the validation checks (the comparison with measured data), as `validate
    /// --uncertainty` samples them: much cheaper on cases whose other checks are slow (the
    /// self-consistency cases' flapping linearisations), and what a run over the whole suite
    /// wants.
    #[arg(long)]
    pub(crate) validation_only: bool,
    /// How the inputs are propagated: auto (sampled for an aircraft, first order for a rotor,
    /// whose evaluations are tables of autorotation searches), sampled (the Saltelli design),
    /// or first-order (an additive surrogate from each input at its 5 % and 95 % quantiles,
    /// checked at four draws of every input: 2 d + 4 evaluations).
    #[arg(long, value_enum, default_value_t = cierva_harness::uncertainty::propagate::Propagation::Auto)]
    pub(crate) method: cierva_harness::uncertainty::propagate::Propagation,
    /// Corrections files (as `cierva fit` writes) applied as `validate --corrections` applies
    /// them; a cross-validated one adds its stated predictive error to `u_input`.
    #[arg(long, num_args = 1..)]
    pub(crate) corrections: Vec<PathBuf>,
    /// Also write every case's verdicts to the suite's reports/uncertainty-summary.yaml (which
    /// the README's "How sure" table is generated from and CI compares with a rerun). Only for
    /// the whole suite of the committed model: no case paths, no --corrections.
    #[arg(long)]
    pub(crate) write_summary: bool,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

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
#[derive(clap::Args)]
pub(crate) struct VerifyArgs {
    /// Records (CSV, with the YAML sidecar beside each), all at one flight condition: each is
    /// flown on its own, from its own first sample.
    #[arg(required = true)]
    pub(crate) records: Vec<PathBuf>,
    /// The identified model: a derivative table as `cierva identify RECORD --format yaml`
    /// writes it (its `estimate` column).
    #[arg(long)]
    pub(crate) identified: PathBuf,
    /// The aircraft, linearised at the records' condition (their sidecars' `condition`), as
    /// `identify --against` does: cierva's model, cut to the identified model's states and
    /// controls.
    #[arg(long)]
    pub(crate) against: PathBuf,
    /// A corrections file to apply to the aircraft of --against.
    #[arg(long)]
    pub(crate) corrections: Option<PathBuf>,
    /// The outputs to compare, units in the names (default: every state of the identified
    /// model): u_m_s, v_m_s, w_m_s, p_rad_s, q_rad_s, r_rad_s, phi_rad, theta_rad,
    /// omega_rotor_rad_s.
    #[arg(long, value_delimiter = ',')]
    pub(crate) outputs: Vec<String>,
    /// Write one SVG figure: a panel per output, the records (one after another in time), the
    /// identified model and cierva's model.
    #[arg(long)]
    pub(crate) figure: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}
