//! `cierva synth`: synthetic flight records flown by a linear model, for identification.

use super::*;

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
