//! `cierva inflow` and `cierva synth-teeter`: inflow from blade flapping (seed 003), and synthetic teeter records.

use super::*;

/// Write a synthetic teeter record of a rotor's autorotative equilibrium in a wind tunnel
/// (for testing `cierva inflow`), labelled synthetic with its generator, seed and truth.
///
/// Example: `cierva synth-teeter aircraft/vpm-m16-rotor.yaml --alpha-deg 10 --airspeed-m-s 30 --output /tmp/teeter.csv`
#[derive(clap::Args)]
pub(crate) struct SynthTeeterArgs {
    #[command(flatten)]
    tunnel: TunnelArgs,
    #[command(flatten)]
    physics: PhysicsArgs,
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
}

/// Inflow components from a teeter record (seed 003): disc tilts by a harmonic fit over
/// whole revolutions, then v0, v1s, v1c and coning (Eqs. 13-19).
///
/// Example: `cierva inflow flight-refs/synthetic-vpm-m16-rotor-teeter.csv --rotor aircraft/vpm-m16-rotor.yaml`
#[derive(clap::Args)]
pub(crate) struct InflowArgs {
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
}

pub(crate) fn inflow(a: InflowArgs) -> Result<ExitCode, Error> {
    let InflowArgs {
        record: path,
        rotor,
        coning,
        skew,
        density_kg_m3,
        collective_deg,
        format,
    } = a;
    let settings = cierva_harness::ident::flap::FlapSettings {
        coning,
        skew,
        density_kg_m3,
        collective_deg,
    };
    use cierva_harness::ident::flap;
    use cierva_harness::inputs::record;
    let loaded = record::load_with(&path, &flap::FLAP_REQUIRED, false)
        .and_then(|rec| cierva_harness::inputs::rotor::load(&rotor).map(|r| (rec, r)));
    let (rec, file) = loaded?;
    match flap::inflow_from_record(&rec, &file.rotor, &settings) {
        Ok(r) => {
            match format {
                Format::Json => print_json(&r),
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
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(Error::input(e)),
    }
}

pub(crate) fn synth_teeter(a: SynthTeeterArgs) -> Result<ExitCode, Error> {
    let SynthTeeterArgs {
        tunnel:
            TunnelArgs {
                rotor,
                alpha_deg,
                airspeed_m_s,
                collective_deg,
            },
        physics,
        duration_s,
        sample_rate_hz,
        seed,
        noise_deg,
        output,
        format,
    } = a;
    if let Err(e) = cierva_harness::inputs::limits::record_samples(duration_s, sample_rate_hz) {
        return Err(Error::input(e));
    }
    let file = cierva_harness::inputs::rotor::load(&rotor)?;
    let (physics, overrides) = physics.over(&file);
    for o in &overrides {
        eprintln!("note: {o}");
    }
    let inflow = physics.model();
    let a = run_autorotation(
        &file.rotor,
        alpha_deg,
        airspeed_m_s,
        collective_deg,
        None,
        inflow,
    )
    .map_err(|e| Error::of(e.is_input(), format!("error: {e}")))?;
    let id = output
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let (sa, ca) = alpha_deg.to_radians().sin_cos();
    let truth = format!(
        "{} at alpha {alpha_deg} deg, {airspeed_m_s} m/s",
        rotor.display()
    );
    let (channels, data, meta) = cierva_harness::synth::teeter::synthesize_teeter(
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
    write_record(
        &output,
        &meta,
        (&channels, &data),
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
            "model_inflow_m_s": {"v0": a.inflow.v0, "v1s": a.inflow.v1s, "v1c": a.inflow.v1c},
            "coning_deg": a.a0_rad.to_degrees(),
        }),
    )
}
