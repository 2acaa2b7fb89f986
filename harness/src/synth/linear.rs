//! Synthetic flight records: a linear model flown through a test input, with seeded sensor
//! noise, atmospheric turbulence and an air-data probe away from the centre of mass.
//!
//! Turbulence enters as a first-order Gauss-Markov disturbance (intensity and correlation time
//! given) on every force equation (`X Y Z L M N Q` rows): unmeasured forcing, which is what
//! turbulence is to an equation-error estimator. The probe sees the c.g. velocity plus
//! `omega x r` (seed 000 Eqs. 5-6 read backwards), and the record holds airspeed, vane angles,
//! rates, attitudes, rotorspeed and controls, each with its own sensor noise.

use crate::inputs::record::{RecordMeta, Sensors, Synthetic};
use crate::inputs::reference::Provenance;
use cierva_model::LinearModel;
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// A small, seeded, reproducible source of normal deviates (SplitMix64 and Box-Muller).
#[derive(Debug, Clone)]
pub struct Normal {
    state: u64,
    spare: Option<f64>,
}

impl Normal {
    pub fn new(seed: u64) -> Self {
        Self {
            state: seed,
            spare: None,
        }
    }

    fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// A standard normal deviate.
    pub fn sample(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u1, u2) = (self.uniform(), self.uniform());
        let r = (-2.0 * u1.ln()).sqrt();
        self.spare = Some(r * (2.0 * PI * u2).sin());
        r * (2.0 * PI * u2).cos()
    }
}

/// Test inputs (amplitudes in the control's units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TestInput {
    /// A frequency sweep from `from_hz` to `to_hz` over `duration_s` (reversed when
    /// `descending`), faded in and out over its first and last 2 s (seed 000 Figs. 4-5).
    Sweep {
        from_hz: f64,
        to_hz: f64,
        duration_s: f64,
        amplitude: f64,
        descending: bool,
    },
    /// An exponential sweep from `from_hz` to `to_hz`, starting at `start_s` and lasting
    /// `duration_s`: the frequency `w0 + K (w1 - w0)` with `K = 0.0187 (exp(4 t / T) - 1)`, which
    /// dwells at the low frequencies a linear sweep rushes through (Tischler and Remple,
    /// *Aircraft and Rotorcraft System Identification*, 2nd ed., Sec. 5.6). Faded in and out
    /// over its first and last 2 s.
    ExponentialSweep {
        start_s: f64,
        from_hz: f64,
        to_hz: f64,
        duration_s: f64,
        amplitude: f64,
    },
    /// `+a` for `pulse_s`, then `-a` for `pulse_s`, starting at `start_s`.
    Doublet {
        start_s: f64,
        pulse_s: f64,
        amplitude: f64,
    },
    /// Pulses of 3, 2, 1 and 1 units of `unit_s`, alternating in sign.
    ThreeTwoOneOne {
        start_s: f64,
        unit_s: f64,
        amplitude: f64,
    },
    /// A step at `start_s`.
    Step { start_s: f64, amplitude: f64 },
}

impl TestInput {
    /// The input at time `t`.
    pub fn at(&self, t: f64) -> f64 {
        match *self {
            Self::Sweep {
                from_hz,
                to_hz,
                duration_s,
                amplitude,
                descending,
            } => {
                if !(0.0..=duration_s).contains(&t) {
                    return 0.0;
                }
                let (f0, f1) = if descending {
                    (to_hz, from_hz)
                } else {
                    (from_hz, to_hz)
                };
                let phase = 2.0 * PI * (f0 * t + (f1 - f0) * t * t / (2.0 * duration_s));
                let fade = 2.0f64.min(duration_s / 4.0);
                let edge = (t / fade).min((duration_s - t) / fade).min(1.0);
                let taper = 0.5 - 0.5 * (PI * edge).cos();
                amplitude * taper * phase.sin()
            }
            Self::ExponentialSweep {
                start_s,
                from_hz,
                to_hz,
                duration_s,
                amplitude,
            } => {
                let s = t - start_s;
                if !(0.0..=duration_s).contains(&s) {
                    return 0.0;
                }
                let (c1, c2) = (4.0, 0.0187);
                let (w0, w1) = (2.0 * PI * from_hz, 2.0 * PI * to_hz);
                // The phase: the integral of w0 + c2 (exp(c1 s / T) - 1) (w1 - w0).
                let k_integral = c2 * (duration_s / c1 * ((c1 * s / duration_s).exp() - 1.0) - s);
                let phase = w0 * s + (w1 - w0) * k_integral;
                let fade = 2.0f64.min(duration_s / 4.0);
                let edge = (s / fade).min((duration_s - s) / fade).min(1.0);
                let taper = 0.5 - 0.5 * (PI * edge).cos();
                amplitude * taper * phase.sin()
            }
            Self::Doublet {
                start_s,
                pulse_s,
                amplitude,
            } => {
                let s = t - start_s;
                if (0.0..pulse_s).contains(&s) {
                    amplitude
                } else if (pulse_s..2.0 * pulse_s).contains(&s) {
                    -amplitude
                } else {
                    0.0
                }
            }
            Self::ThreeTwoOneOne {
                start_s,
                unit_s,
                amplitude,
            } => {
                let s = (t - start_s) / unit_s;
                let bounds = [
                    (0.0, 3.0, 1.0),
                    (3.0, 5.0, -1.0),
                    (5.0, 6.0, 1.0),
                    (6.0, 7.0, -1.0),
                ];
                bounds
                    .iter()
                    .find(|(a, b, _)| s >= *a && s < *b)
                    .map_or(0.0, |(_, _, sg)| amplitude * sg)
            }
            Self::Step { start_s, amplitude } => {
                if t >= start_s {
                    amplitude
                } else {
                    0.0
                }
            }
        }
    }
}

/// Sensor noise standard deviations (zero for a noise-free record).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorNoise {
    pub airspeed_m_s: f64,
    pub vane_rad: f64,
    pub rate_rad_s: f64,
    pub attitude_rad: f64,
    pub rotor_rad_s: f64,
    pub control: f64,
}

impl SensorNoise {
    pub const NONE: Self = Self {
        airspeed_m_s: 0.0,
        vane_rad: 0.0,
        rate_rad_s: 0.0,
        attitude_rad: 0.0,
        rotor_rad_s: 0.0,
        control: 0.0,
    };
}

/// Turbulence: Gauss-Markov forcing on each force equation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turbulence {
    /// Standard deviation of the forcing (acceleration units of each row).
    pub intensity: f64,
    pub correlation_time_s: f64,
}

/// The trim the perturbations are about.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrimPoint {
    pub u_m_s: f64,
    pub w_m_s: f64,
    pub theta_rad: f64,
    pub omega_rotor_rad_s: f64,
}

/// The trim of the synthetic records of seed 002's linear VPM M16 at 60 kn (the
/// identification's known answers, the frequency-response known answer, their benchmarks): the
/// model's states are perturbations, so any level-flight trim near 60 kn serves; this one is
/// 30 m/s forward, 1.5 m/s down, 0.05 rad nose up, 38 rad/s of rotor speed.
pub const SEED002_TRIM: TrimPoint = TrimPoint {
    u_m_s: 30.0,
    w_m_s: 1.5,
    theta_rad: 0.05,
    omega_rotor_rad_s: 38.0,
};

/// Those records' air-data probe: 2 m ahead of and 0.3 m above the centre of mass, so that the
/// vanes see the rates' `omega x r` (seed 000 Eqs. 5-6).
pub const SEED002_SENSORS: Sensors = Sensors {
    probe_position_m: [2.0, 0.0, -0.3],
    cg_position_m: [0.0; 3],
};

/// Everything the generator needs.
#[derive(Debug, Clone)]
pub struct LinearTest {
    pub id: String,
    pub aircraft: String,
    /// The path or description of the truth model, written into the sidecar.
    pub truth: String,
    pub control: String,
    pub input: TestInput,
    pub duration_s: f64,
    pub sample_rate_hz: f64,
    pub seed: u64,
    pub noise: SensorNoise,
    pub turbulence: Option<Turbulence>,
    pub trim: TrimPoint,
    pub sensors: Sensors,
    /// The flight condition the record's sidecar states (the truth's, where its reference file
    /// gives one; free-form, keys with units): what a retune or an identification asks the
    /// model at.
    pub condition: std::collections::BTreeMap<String, serde_yaml::Value>,
    /// The record's column for the control, named with the unit the model takes it in
    /// (`eta_s_rad`; `eta_s_percent` for a model whose `B` is per percent of travel).
    pub control_channel: String,
}

impl LinearTest {
    /// The frequency-response known answer's record (its tests and `cierva bench`): seed 002's
    /// linear VPM M16 (Eq. 20) at 60 kn flown through an exponential sweep of the longitudinal
    /// stick, 0.02 to 4 Hz over 116 s from 2 s, amplitude 0.01; 120 s at 100 Hz; sensor noise
    /// 1e-4 on the rates and the control and none elsewhere, no turbulence; the trim and the
    /// air-data probe (2 m ahead of and 0.3 m above the centre of mass) of the identification's
    /// synthetic records. `id` names it and `seed` draws its noise.
    pub fn exponential_sweep(id: &str, seed: u64) -> Self {
        Self {
            id: id.into(),
            aircraft: "VPM M16".into(),
            truth: "seed 002 Eq. 20".into(),
            control: "eta_s".into(),
            input: TestInput::ExponentialSweep {
                start_s: 2.0,
                from_hz: 0.02,
                to_hz: 4.0,
                duration_s: 116.0,
                amplitude: 0.01,
            },
            duration_s: 120.0,
            sample_rate_hz: 100.0,
            seed,
            noise: SensorNoise {
                rate_rad_s: 1e-4,
                control: 1e-4,
                ..SensorNoise::NONE
            },
            turbulence: None,
            trim: SEED002_TRIM,
            sensors: SEED002_SENSORS,
            condition: Default::default(),
            control_channel: "eta_s_rad".into(),
        }
    }
}

const FORCE_ROWS: [&str; 7] = ["u", "v", "w", "p", "q", "r", "Omega"];

/// A generated record: channel names, one vector per channel, and the sidecar.
pub type Generated = (Vec<String>, Vec<Vec<f64>>, RecordMeta);

/// The record's channel names and data, and its sidecar.
pub fn generate(model: &LinearModel, s: &LinearTest) -> Result<Generated, String> {
    let ci = model
        .controls()
        .iter()
        .position(|c| *c == s.control)
        .ok_or_else(|| {
            format!(
                "the model has no control `{}` (it has {:?})",
                s.control,
                model.controls()
            )
        })?;
    let steps = crate::inputs::limits::record_samples(s.duration_s, s.sample_rate_hz)?;
    let dt = 1.0 / s.sample_rate_hz;
    let mut rng = Normal::new(s.seed);
    // Turbulence on the force rows, as extra inputs.
    let force_rows: Vec<usize> = model
        .states()
        .iter()
        .enumerate()
        .filter(|(_, n)| FORCE_ROWS.contains(&n.as_str()))
        .map(|(i, _)| i)
        .collect();
    let n = model.states().len();
    let nu = model.controls().len();
    let gusts = gusts(s.turbulence, force_rows.len(), steps, dt, &mut rng);
    let extra = gusts.len();
    let augmented = with_gust_inputs(model, &force_rows, extra)?;
    let input = s.input;
    let input_fn = |t: f64| -> Vec<f64> {
        let mut u = vec![0.0; nu + extra];
        u[ci] = input.at(t);
        let pos = t / dt;
        let (k, f) = (pos.floor() as usize, pos - pos.floor());
        for (g, series) in gusts.iter().enumerate() {
            let a = series[k.min(series.len() - 1)];
            let b = series[(k + 1).min(series.len() - 1)];
            u[nu + g] = a + (b - a) * f;
        }
        u
    };
    let xs = cierva_model::simulation::simulate::simulate(
        &augmented,
        &vec![0.0; n],
        &input_fn,
        dt,
        steps,
    );
    let control_channel = s.control_channel.clone();
    let names: Vec<String> = crate::inputs::record::REQUIRED
        .iter()
        .map(|c| c.to_string())
        .chain([control_channel.clone()])
        .collect();
    let data = sensed(model, s, &xs, steps, dt, names.len(), &mut rng);
    if data.iter().flatten().any(|v| !v.is_finite()) {
        return Err(
            "the simulated record is not finite (an unstable model, or a too large input?)".into(),
        );
    }
    let meta = sidecar(s, dt, control_channel);
    Ok((names, data, meta))
}

/// One Gauss-Markov gust series per force row (`steps + 2` samples each, started from the
/// stationary distribution), or none without turbulence.
fn gusts(
    turbulence: Option<Turbulence>,
    force_rows: usize,
    steps: usize,
    dt: f64,
    rng: &mut Normal,
) -> Vec<Vec<f64>> {
    match turbulence {
        Some(t) if t.intensity > 0.0 => {
            let phi = (-dt / t.correlation_time_s.max(dt)).exp();
            let q = t.intensity * (1.0 - phi * phi).sqrt();
            (0..force_rows)
                .map(|_| {
                    let mut g = t.intensity * rng.sample();
                    (0..=steps + 1)
                        .map(|_| {
                            let v = g;
                            g = phi * g + q * rng.sample();
                            v
                        })
                        .collect()
                })
                .collect()
        }
        _ => Vec::new(),
    }
}

/// The model with one extra input per gust series, `gust_<g>`, entering its force row with
/// unit gain.
fn with_gust_inputs(
    model: &LinearModel,
    force_rows: &[usize],
    extra: usize,
) -> Result<LinearModel, String> {
    let n = model.states().len();
    let nu = model.controls().len();
    let mut b = nalgebra::DMatrix::zeros(n, nu + extra);
    b.view_mut((0, 0), (n, nu)).copy_from(model.b());
    for (g, &row) in force_rows.iter().enumerate().take(extra) {
        b[(row, nu + g)] = 1.0;
    }
    let mut controls = model.controls().to_vec();
    controls.extend((0..extra).map(|g| format!("gust_{g}")));
    LinearModel::new(model.states().to_vec(), controls, model.a().clone(), b)
        .map_err(|e| e.to_string())
}

/// What the sensors record of the flown states `xs` about the trim, one vector per channel
/// (`channels` of them): the probe's airspeed and vane angles (c.g. velocity plus
/// `omega x r`), rates, attitudes, rotorspeed and the control, each with its noise.
fn sensed(
    model: &LinearModel,
    s: &LinearTest,
    xs: &[Vec<f64>],
    steps: usize,
    dt: f64,
    channels: usize,
    rng: &mut Normal,
) -> Vec<Vec<f64>> {
    // Each state's column, looked up once (a state the model lacks reads as zero).
    let column = |name: &str| model.state_index(name).ok();
    let [
        p_col,
        q_col,
        r_col,
        u_col,
        v_col,
        w_col,
        phi_col,
        theta_col,
        omega_col,
    ] = ["p", "q", "r", "u", "v", "w", "phi", "theta", "Omega"].map(column);
    let state = |col: Option<usize>, k: usize| col.map_or(0.0, |i| xs[k][i]);
    let r = [
        s.sensors.probe_position_m[0] - s.sensors.cg_position_m[0],
        s.sensors.probe_position_m[1] - s.sensors.cg_position_m[1],
        s.sensors.probe_position_m[2] - s.sensors.cg_position_m[2],
    ];
    let input = s.input;
    let mut data = vec![Vec::with_capacity(steps + 1); channels];
    let nz = s.noise;
    for k in 0..=steps {
        let t = k as f64 * dt;
        let (p, q, rr) = (state(p_col, k), state(q_col, k), state(r_col, k));
        let u = s.trim.u_m_s + state(u_col, k);
        let v = state(v_col, k);
        let w = s.trim.w_m_s + state(w_col, k);
        // Probe velocity: c.g. velocity plus omega x r.
        let up = u + q * r[2] - rr * r[1];
        let vp = v + rr * r[0] - p * r[2];
        let wp = w + p * r[1] - q * r[0];
        let airspeed = (up * up + vp * vp + wp * wp).sqrt();
        let row = [
            t,
            airspeed + nz.airspeed_m_s * rng.sample(),
            wp.atan2(up) + nz.vane_rad * rng.sample(),
            (vp / airspeed).asin() + nz.vane_rad * rng.sample(),
            p + nz.rate_rad_s * rng.sample(),
            q + nz.rate_rad_s * rng.sample(),
            rr + nz.rate_rad_s * rng.sample(),
            state(phi_col, k) + nz.attitude_rad * rng.sample(),
            s.trim.theta_rad + state(theta_col, k) + nz.attitude_rad * rng.sample(),
            s.trim.omega_rotor_rad_s + state(omega_col, k) + nz.rotor_rad_s * rng.sample(),
            input.at(t) + nz.control * rng.sample(),
        ];
        for (col, v) in data.iter_mut().zip(row) {
            col.push(v);
        }
    }
    data
}

/// The record's sidecar: what generated it (settings, seed, the truth model), the sensors and
/// the trim the record is about.
fn sidecar(s: &LinearTest, dt: f64, control_channel: String) -> RecordMeta {
    let mut settings = BTreeMap::new();
    settings.insert("input".into(), format!("{:?}", s.input));
    settings.insert("sensor_noise".into(), format!("{:?}", s.noise));
    settings.insert("turbulence".into(), format!("{:?}", s.turbulence));
    settings.insert(
        "integration".into(),
        format!("RK4 at the sample interval {dt} s"),
    );
    let mut trim = BTreeMap::new();
    trim.insert("u_m_s".into(), s.trim.u_m_s);
    trim.insert("w_m_s".into(), s.trim.w_m_s);
    trim.insert("theta_rad".into(), s.trim.theta_rad);
    trim.insert("omega_rotor_rad_s".into(), s.trim.omega_rotor_rad_s);
    trim.insert(control_channel.clone(), 0.0);
    RecordMeta {
        id: s.id.clone(),
        title: format!("Synthetic record: {} through {:?}", s.aircraft, s.input),
        provenance: Provenance {
            source: format!(
                "synthetic: cierva synth {} from the linear model {}, seed {}",
                env!("CARGO_PKG_VERSION"),
                s.truth,
                s.seed
            ),
            notes: Some(
                "Not flight data. Generated to test identification; the truth is the model named."
                    .into(),
            ),
        },
        synthetic: Some(Synthetic {
            generator: format!("cierva synth {}", env!("CARGO_PKG_VERSION")),
            seed: s.seed,
            truth: s.truth.clone(),
            settings,
        }),
        aircraft: s.aircraft.clone(),
        sample_rate_hz: s.sample_rate_hz,
        sensors: Some(s.sensors),
        condition: s.condition.clone(),
        trim,
        controls: vec![control_channel],
        channels: Default::default(),
        travel: Default::default(),
        excitation: Default::default(),
    }
}
