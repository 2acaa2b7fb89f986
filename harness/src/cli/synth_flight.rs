//! `cierva synth-flight`: a flight test flown by the full model, recorded for identification.

use super::*;
use cierva_harness::inputs::record::{RecordMeta, Sensors, Synthetic};
use cierva_harness::synth::flight::{self, sensors::Instrumentation};
use cierva_harness::synth::linear::TestInput;
use std::collections::BTreeMap;

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
/// rates, attitudes, rotorspeed and every control at 100 Hz. The test input is recorded as
/// `<control>_excitation_percent`, named by the sidecar's `excitation` (what an excitation
/// system logs; `cierva retune` estimates the responses against it). The sidecar says it is
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

/// The input starts after this much trim, s, and ends this long before the record does.
const QUIET_S: f64 = 3.0;

pub(crate) fn synth_flight(a: SynthFlightArgs) -> Result<ExitCode, Error> {
    let file = load_flight(&a.flight)?;
    let control = control_index(&a.control).map_err(Error::input)?;
    let instrumentation = match &a.sensors {
        None => Instrumentation::default(),
        Some(p) => Instrumentation::load(p)?,
    };
    let input = test_input(&a)?;
    let turbulence = turbulence(&a)?;
    let step = azimuth_step_rad(a.azimuth_step_deg, &file)?;
    let test = flight::FlightTest {
        request: a.flight.request(0.0),
        loading: a.flight.loading(),
        input,
        control,
        duration_s: a.duration_s,
        sample_rate_hz: a.sample_rate_hz,
        turbulence,
        instrumentation,
        pilot: !a.no_pilot,
        seed: a.seed,
        azimuth_step_rad: step,
    };
    let busy = spinner(&format!("flying {} s", a.duration_s));
    let flown = flight::fly(&file.aircraft, &test);
    busy.finish_and_clear();
    let flown =
        flown.map_err(|e| Error::failure(format!("{}: {e}", a.flight.aircraft.display())))?;
    let id = a
        .output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mass = a.flight.mass_kg.unwrap_or(file.aircraft.mass.mass_kg);
    let truth = format!(
        "{}{} ({}), the full individual-blade model (RK4, azimuth step {:.1} deg)",
        a.flight.aircraft.display(),
        a.flight
            .corrections
            .as_ref()
            .map_or(String::new(), |c| format!(
                " with the corrections {}",
                c.display()
            )),
        file.title,
        step.to_degrees()
    );
    let mut settings = BTreeMap::new();
    settings.insert(
        "command".to_string(),
        std::env::args().skip(1).collect::<Vec<_>>().join(" "),
    );
    settings.extend(flight::describe(&test, &flown, a.height_ft));
    let condition = a.flight.sidecar_condition(mass);
    let controls = flight::record_controls(control);
    let generator = format!("cierva synth-flight {}", env!("CARGO_PKG_VERSION"));
    let meta = RecordMeta {
        id: id.clone(),
        title: a.title.clone().unwrap_or_else(|| {
            format!(
                "Synthetic flight test: {:?} on {} of the {} at {} mph",
                a.manoeuvre, a.control, file.title, a.flight.airspeed_mph
            )
        }),
        provenance: cierva_harness::inputs::reference::Provenance {
            source: format!("synthetic: {generator}, {truth}, seed {}", a.seed),
            notes: Some(
                "Not flight data. Flown by the model named to test identification; the truth is that model."
                    .into(),
            ),
        },
        synthetic: Some(Synthetic {
            generator,
            seed: a.seed,
            truth,
            settings,
        }),
        aircraft: file.title.clone(),
        sample_rate_hz: a.sample_rate_hz,
        sensors: Some(Sensors {
            probe_position_m: flown.probe_position_m,
            cg_position_m: flown.cg_position_m,
        }),
        condition,
        trim: flown.trim.clone(),
        controls,
        channels: Default::default(),
        travel: Default::default(),
        excitation: flown.excitation.clone(),
    };
    write_record(
        &a.output,
        &meta,
        (&flown.channels, &flown.data),
        a.format,
        format!(
            "wrote {} and its sidecar ({} samples)",
            a.output.display(),
            flown.data[0].len()
        ),
        serde_json::json!({"samples": flown.data[0].len()}),
    )
}

/// The test input the arguments ask for, between `QUIET_S` of trim at each end; arguments
/// out of range are bad input.
fn test_input(a: &SynthFlightArgs) -> Result<TestInput, Error> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(a.duration_s) && a.duration_s > 2.0 * QUIET_S + 1.0) {
        return Err(Error::input(format!(
            "--duration-s must exceed {} s (the input runs between {QUIET_S} s of trim at each end)",
            2.0 * QUIET_S + 1.0
        )));
    }
    if !(ok(a.sample_rate_hz) && ok(a.pulse_s) && a.amplitude_percent.is_finite()) {
        return Err(Error::input(
            "--sample-rate-hz and --pulse-s must be positive, the amplitude finite",
        ));
    }
    Ok(match a.manoeuvre {
        Manoeuvre::Sweep => {
            if !(ok(a.from_hz) && a.to_hz > a.from_hz && a.to_hz < a.sample_rate_hz / 2.0) {
                return Err(Error::input(format!(
                    "the sweep needs 0 < --from-hz < --to-hz < half the sample rate (got {} to {} Hz)",
                    a.from_hz, a.to_hz
                )));
            }
            TestInput::ExponentialSweep {
                start_s: QUIET_S,
                from_hz: a.from_hz,
                to_hz: a.to_hz,
                duration_s: a.duration_s - 2.0 * QUIET_S,
                amplitude: a.amplitude_percent,
            }
        }
        Manoeuvre::ThreeTwoOneOne => TestInput::ThreeTwoOneOne {
            start_s: QUIET_S,
            unit_s: a.pulse_s,
            amplitude: a.amplitude_percent,
        },
        Manoeuvre::Doublet => TestInput::Doublet {
            start_s: QUIET_S,
            pulse_s: a.pulse_s,
            amplitude: a.amplitude_percent,
        },
    })
}

/// The turbulence the arguments ask for: Dryden's at `--height-ft` with `--turbulence-m-s`, or
/// calm air at zero.
fn turbulence(a: &SynthFlightArgs) -> Result<Option<flight::turbulence::Dryden>, Error> {
    if a.turbulence_m_s > 0.0 {
        flight::turbulence::Dryden::low_altitude(
            a.turbulence_m_s,
            a.height_ft * cierva_harness::units::FT_TO_M,
        )
        .map(Some)
        .map_err(Error::input)
    } else if a.turbulence_m_s == 0.0 {
        Ok(None)
    } else {
        Err(Error::input("--turbulence-m-s must not be negative"))
    }
}
