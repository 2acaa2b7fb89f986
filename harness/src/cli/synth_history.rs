//! `cierva synth-history`: synthetic time-history records flown by the full or linear model.

use super::*;

pub(crate) fn synth_history(a: SynthHistoryArgs) -> Result<ExitCode, Error> {
    use cierva_harness::run::replay;
    use cierva_harness::synth::history;
    let file = load_flight(&a.flight)?;
    let corrections = cierva_harness::inputs::corrections::CorrectionSet {
        propeller_blockage: a.propeller_blockage,
        hub_aoa_factor: a.hub_aoa_factor,
        ..Default::default()
    };
    let file = file
        .with_corrections(&corrections)
        .map_err(|e| Error::input(format!("the corrections: {e}")))?;
    let Some(shape) = a.shape.input() else {
        return Err(Error::input("give --shape"));
    };
    let index = control_index(&a.shape.control).map_err(Error::input)?;
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(a.duration_s) && ok(a.sample_rate_hz)) {
        return Err(Error::input(
            "--duration-s and --sample-rate-hz must be positive",
        ));
    }
    let noise = noise(&a)?;
    let changes = |t: f64| {
        let mut d = [0.0; 4];
        d[index] = shape.at(t);
        d
    };
    let sample_s = 1.0 / a.sample_rate_hz;
    let step = azimuth_step_rad(a.azimuth_step_deg, &file)?;
    let (request, loading) = (a.flight.request(0.0), a.flight.loading());
    let busy = spinner(&format!("flying {} s", a.duration_s));
    let flown = replay::fly(
        &file.aircraft,
        request,
        loading,
        &changes,
        replay::FlySettings {
            simulation: a.simulation,
            sample_s,
            samples: (a.duration_s / sample_s).round() as usize,
            azimuth_step_rad: step,
        },
    );
    busy.finish_and_clear();
    let flown =
        flown.map_err(|e| Error::failure(format!("{}: {e}", a.flight.aircraft.display())))?;
    let id = a
        .output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mass = a.flight.mass_kg.unwrap_or(file.aircraft.mass.mass_kg);
    let simulation = match a.simulation {
        replay::Simulation::FullBlade => format!(
            "the full individual-blade model (RK4, azimuth step {:.1} deg)",
            step.to_degrees()
        ),
        replay::Simulation::Linear => "its linearisation about trim".to_string(),
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
    let condition = a.flight.sidecar_condition(mass);
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
    let column = cierva_harness::inputs::controls::CONTROL_COLUMNS[index];
    let (meta, channels, data) =
        history::synthesize(&flown, &changes, &[column], noise, &spec).map_err(Error::input)?;
    write_record(
        &a.output,
        &meta,
        (&channels, &data),
        a.format,
        format!(
            "wrote {} and its sidecar ({} samples)",
            a.output.display(),
            flown.time_s.len()
        ),
        serde_json::json!({"samples": flown.time_s.len()}),
    )
}

/// The sensor noise the arguments ask for (standard deviations, each finite and >= 0).
fn noise(a: &SynthHistoryArgs) -> Result<cierva_harness::synth::history::Noise, Error> {
    let noise = cierva_harness::synth::history::Noise {
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
        return Err(Error::input(
            "noise standard deviations must be finite and >= 0",
        ));
    }
    Ok(noise)
}
