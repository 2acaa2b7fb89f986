//! `cierva synth-history`: synthetic time-history records flown by the full or linear model.

use super::*;

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
