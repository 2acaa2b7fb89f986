//! `cierva synth`: synthetic flight records flown by a linear model, for identification.

use super::*;

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

pub(crate) fn synth(a: SynthArgs) -> Result<ExitCode, Error> {
    use cierva_harness::inputs::record;
    use cierva_harness::synth::linear;
    let r = reference::load(&a.model)?;
    let Some(model) = r.linear_model else {
        return Err(Error::input(format!(
            "{}: no `linear_model` block",
            a.model.display()
        )));
    };
    let probe: Vec<f64> = a
        .probe_m
        .split(',')
        .filter_map(|v| v.trim().parse().ok())
        .collect();
    let [px, py, pz] = probe[..] else {
        return Err(Error::input(format!(
            "--probe-m `{}`: expected x,y,z in metres",
            a.probe_m
        )));
    };
    let input = match a.shape {
        InputChoice::Sweep | InputChoice::SweepDown => {
            cierva_harness::synth::linear::TestInput::Sweep {
                from_hz: a.from_hz,
                to_hz: a.to_hz,
                duration_s: a.input_s,
                amplitude: a.amplitude_model_units,
                descending: a.shape == InputChoice::SweepDown,
            }
        }
        InputChoice::Doublet => cierva_harness::synth::linear::TestInput::Doublet {
            start_s: 2.0,
            pulse_s: a.input_s,
            amplitude: a.amplitude_model_units,
        },
        InputChoice::ThreeTwoOneOne => cierva_harness::synth::linear::TestInput::ThreeTwoOneOne {
            start_s: 2.0,
            unit_s: a.input_s,
            amplitude: a.amplitude_model_units,
        },
        InputChoice::Step => cierva_harness::synth::linear::TestInput::Step {
            start_s: 2.0,
            amplitude: a.amplitude_model_units,
        },
    };
    let k = a.noise_scale;
    let id = a
        .output
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_default();
    let settings = linear::LinearTest {
        id,
        aircraft: r.title.clone(),
        truth: a.model.display().to_string(),
        control: a.control.clone(),
        input,
        duration_s: a.duration_s,
        sample_rate_hz: a.sample_rate_hz,
        seed: a.seed,
        noise: linear::SensorNoise {
            airspeed_m_s: 0.02 * k,
            vane_rad: 5e-4 * k,
            rate_rad_s: 5e-4 * k,
            attitude_rad: 5e-4 * k,
            rotor_rad_s: 0.01 * k,
            control: 0.0,
        },
        turbulence: (a.turbulence_si > 0.0).then_some(linear::Turbulence {
            intensity: a.turbulence_si,
            correlation_time_s: 0.5,
        }),
        trim: linear::TrimPoint {
            u_m_s: a.trim_u_m_s,
            w_m_s: a.trim_w_m_s,
            theta_rad: a.trim_theta_rad,
            omega_rotor_rad_s: a.trim_rotor_rad_s,
        },
        sensors: record::Sensors {
            probe_position_m: [px, py, pz],
            cg_position_m: [0.0, 0.0, 0.0],
        },
        condition: r.condition.clone(),
        control_channel: format!(
            "{}_{}",
            a.control,
            match r.units.get(&a.control).map(|u| u.trim()) {
                Some("%" | "percent" | "% of travel") => "percent",
                Some("deg") => "deg",
                _ => "rad",
            }
        ),
    };
    let (channels, data, meta) = linear::generate(&model, &settings).map_err(Error::input)?;
    write_record(
        &a.output,
        &meta,
        (&channels, &data),
        a.format,
        format!(
            "wrote {} and {} ({} samples, seed {})",
            a.output.display(),
            record::sidecar_path(&a.output).display(),
            data[0].len(),
            a.seed
        ),
        serde_json::json!({"samples": data[0].len(), "seed": a.seed}),
    )
}
