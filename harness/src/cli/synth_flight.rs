//! `cierva synth-flight`: a flight test flown by the full model, recorded for identification.

use super::*;
use cierva_harness::inputs::record::{self, RecordMeta, Sensors, Synthetic};
use cierva_harness::synth::flight::{self, CONTROL_CHANNELS, sensors::Instrumentation};
use cierva_harness::synth::linear::Input;
use std::collections::BTreeMap;

/// The input starts after this much trim, s, and ends this long before the record does.
const QUIET_S: f64 = 3.0;

pub(crate) fn synth_flight(a: SynthFlightArgs) -> Result<ExitCode, Error> {
    // Long: one command, in the order it works: the aircraft, the instruments, the test, the
    // flight, then the record and its sidecar with the truth
    let fail =
        |msg: String| -> Result<ExitCode, Error> { Err(Error::Input(format!("error: {msg}"))) };
    let file = load_flight(&a.flight)?;
    let control = match control_index(&a.control) {
        Ok(i) => i,
        Err(e) => return fail(e),
    };
    let instrumentation = match &a.sensors {
        None => Instrumentation::default(),
        Some(p) => Instrumentation::load(p).map_err(|e| Error::Input(e.render()))?,
    };
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(a.duration_s) && a.duration_s > 2.0 * QUIET_S + 1.0) {
        return fail(format!(
            "--duration-s must exceed {} s (the input runs between {QUIET_S} s of trim at each end)",
            2.0 * QUIET_S + 1.0
        ));
    }
    if !(ok(a.sample_rate_hz) && ok(a.pulse_s) && a.amplitude_percent.is_finite()) {
        return fail(
            "--sample-rate-hz and --pulse-s must be positive, the amplitude finite".into(),
        );
    }
    let span = a.duration_s - 2.0 * QUIET_S;
    let input = match a.manoeuvre {
        Manoeuvre::Sweep => {
            if !(ok(a.from_hz) && a.to_hz > a.from_hz && a.to_hz < a.sample_rate_hz / 2.0) {
                return fail(format!(
                    "the sweep needs 0 < --from-hz < --to-hz < half the sample rate (got {} to {} Hz)",
                    a.from_hz, a.to_hz
                ));
            }
            Input::ExponentialSweep {
                start_s: QUIET_S,
                from_hz: a.from_hz,
                to_hz: a.to_hz,
                duration_s: span,
                amplitude: a.amplitude_percent,
            }
        }
        Manoeuvre::ThreeTwoOneOne => Input::ThreeTwoOneOne {
            start_s: QUIET_S,
            unit_s: a.pulse_s,
            amplitude: a.amplitude_percent,
        },
        Manoeuvre::Doublet => Input::Doublet {
            start_s: QUIET_S,
            pulse_s: a.pulse_s,
            amplitude: a.amplitude_percent,
        },
    };
    let turbulence = if a.turbulence_m_s > 0.0 {
        match cierva_harness::synth::flight::turbulence::Dryden::low_altitude(
            a.turbulence_m_s,
            a.height_ft * cierva_harness::units::FT_TO_M,
        ) {
            Ok(d) => Some(d),
            Err(e) => return fail(e),
        }
    } else if a.turbulence_m_s == 0.0 {
        None
    } else {
        return fail("--turbulence-m-s must not be negative".into());
    };
    let step = azimuth_step_rad(a.azimuth_step_deg, &file)?;
    let test = flight::FlightTest {
        request: a.flight.request(0.0),
        loading: a.flight.loading(),
        input,
        control,
        duration_s: a.duration_s,
        sample_rate_hz: a.sample_rate_hz,
        turbulence,
        instrumentation: instrumentation.clone(),
        pilot: !a.no_pilot,
        seed: a.seed,
        azimuth_step_rad: step,
    };
    let busy = spinner(&format!("flying {} s", a.duration_s));
    let flown = flight::fly(&file.aircraft, &test);
    busy.finish_and_clear();
    let flown = match flown {
        Ok(f) => f,
        Err(e) => {
            return Err(Error::Failure(format!(
                "error: {}: {e}",
                a.flight.aircraft.display()
            )));
        }
    };
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
    settings.insert(
        "input".into(),
        format!("{input:?} on {}", CONTROL_CHANNELS[control]),
    );
    settings.insert(
        "turbulence".into(),
        match &turbulence {
            Some(d) => format!(
                "Dryden (MIL-F-8785C low altitude, {} ft): sigma_u,v,w {:.3}, {:.3}, {:.3} m/s, scales {:.0}, {:.0}, {:.0} m, along body axes",
                a.height_ft,
                d.sigma_m_s[0],
                d.sigma_m_s[1],
                d.sigma_m_s[2],
                d.scale_m[0],
                d.scale_m[1],
                d.scale_m[2]
            ),
            None => "none (calm air)".into(),
        },
    );
    settings.insert(
        "pilot".into(),
        match &flown.pilot {
            Some(p) => format!(
                "attitude hold (pitch, roll, heading) about references drifting 0.5 deg over 30 s: gains {:?} %/rad and {:?} %/(rad/s)",
                p.attitude_gain_pct_per_rad, p.rate_gain_pct_per_rad_s
            ),
            None => "none: the input open loop".into(),
        },
    );
    settings.insert(
        "sensors".into(),
        format!("{}: {}", instrumentation.id, instrumentation.title),
    );
    for (name, ch) in &instrumentation.channels {
        settings.insert(
            format!("sensor.{name}"),
            format!(
                "noise {}, bias {}, lag {} s; source: {}",
                ch.noise,
                ch.bias,
                ch.lag_s,
                instrumentation
                    .sources
                    .get(&format!("channels.{name}"))
                    .map_or("", String::as_str)
            ),
        );
    }
    settings.insert(
        "sensor.probe_from_cg_m".into(),
        format!(
            "{:?}; source: {}",
            instrumentation.probe_from_cg_m,
            instrumentation
                .sources
                .get("probe_from_cg_m")
                .map_or("", String::as_str)
        ),
    );
    let mut condition = BTreeMap::new();
    for (k, v) in [
        ("airspeed_mph", a.flight.airspeed_mph),
        ("climb_m_s", a.flight.climb_m_s),
        ("mass_kg", mass),
        ("density_altitude_ft", a.flight.density_altitude_ft),
    ] {
        condition.insert(k.to_string(), serde_yaml::Value::from(v));
    }
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
    };
    match record::write(&a.output, &meta, &flown.channels, &flown.data) {
        Ok(()) => {
            done(
                a.format,
                format!(
                    "wrote {} and its sidecar ({} samples)",
                    a.output.display(),
                    flown.data[0].len()
                ),
                serde_json::json!({
                    "wrote": [
                        a.output.display().to_string(),
                        record::sidecar_path(&a.output).display().to_string()
                    ],
                    "samples": flown.data[0].len(),
                }),
            );
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => fail(format!("cannot write {}: {e}", a.output.display())),
    }
}
