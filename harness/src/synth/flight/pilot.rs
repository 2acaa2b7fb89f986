//! A pilot flying a test input: the input on one control, and a loose attitude hold on the
//! stick and pedals about references that drift slowly, as a pilot's trim does.
//!
//! Without the hold, a two-minute open-loop sweep of an aircraft with an unstable or
//! near-neutral phugoid or spiral departs. With it, the record stays near its trim and the
//! controls carry both the input and the pilot's corrections, as flight records do; the
//! estimator regresses on the measured controls, so it is indifferent to who moved them.
//!
//! Each axis is a proportional-derivative loop on its attitude (pitch on the longitudinal
//! stick, roll on the lateral stick, heading on the pedals), with gains from the aircraft's own
//! control derivative (`M_eta_s`, `L_eta_c`, `N_eta_p`) that place the loop's closed-loop
//! frequency and damping ([`LOOPS`]) as if the aircraft were a pure inertia:
//! `delta = -(w^2 e + 2 zeta w rate) / M_delta`.

use crate::synth::linear::Normal;
use cierva_model::LinearModel;
use serde::Serialize;

/// Each loop's control, controlled derivative, frequency (rad/s) and damping ratio, and the
/// drift of its reference (standard deviation, rad, and correlation time, s).
///
/// Estimated: a pilot's loose hold, with a closed-loop frequency below the identification band's
/// middle (0.5-1 rad/s against a band of 0.3-12 rad/s), damped as a pilot flies; references
/// wandering 0.5 deg over half a minute.
pub const LOOPS: [(&str, &str, f64, f64); 3] = [
    ("pitch", "M_eta_s", 0.5, 0.7),
    ("roll", "L_eta_c", 1.0, 0.7),
    ("heading", "N_eta_p", 0.5, 0.7),
];
const DRIFT_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;
const DRIFT_CORRELATION_S: f64 = 30.0;
/// Interval of the drift's samples, s (it is interpolated between them).
const DRIFT_STEP_S: f64 = 0.1;

/// The pilot's loops: gains on attitude error (% per rad) and on rate (% per rad/s), per axis
/// (pitch, roll, heading), and the drifting references.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Pilot {
    pub attitude_gain_percent_per_rad: [f64; 3],
    pub rate_gain_percent_per_rad_s: [f64; 3],
    #[serde(skip)]
    drift: Vec<[f64; 3]>,
}

impl Pilot {
    /// The loops for an aircraft's linearisation about the trim (controls in %), with drifts
    /// realised over `duration_s` from `seed`.
    pub fn new(model: &LinearModel, duration_s: f64, seed: u64) -> Result<Self, String> {
        let mut attitude = [0.0; 3];
        let mut rate = [0.0; 3];
        for (k, (axis, derivative, w, zeta)) in LOOPS.iter().enumerate() {
            let m = model
                .derivative_value(derivative)
                .map_err(|e| format!("the pilot's {axis} loop: {e}"))?;
            if !(m.is_finite() && m.abs() > 1e-9) {
                return Err(format!(
                    "the pilot's {axis} loop: {derivative} is {m}, too small to fly with"
                ));
            }
            attitude[k] = -w * w / m;
            rate[k] = -2.0 * zeta * w / m;
        }
        let n = (duration_s / DRIFT_STEP_S).ceil() as usize + 2;
        let mut rng = Normal::new(seed);
        let phi = (-DRIFT_STEP_S / DRIFT_CORRELATION_S).exp();
        let q = DRIFT_RAD * (1.0 - phi * phi).sqrt();
        let mut d = [0.0; 3];
        let drift = (0..n)
            .map(|_| {
                let now = d;
                for v in &mut d {
                    *v = phi * *v + q * rng.sample();
                }
                now
            })
            .collect();
        Ok(Self {
            attitude_gain_percent_per_rad: attitude,
            rate_gain_percent_per_rad_s: rate,
            drift,
        })
    }

    /// The references' drift from trim (pitch, roll, heading), rad, at `t`; it starts at zero.
    pub fn drift(&self, t: f64) -> [f64; 3] {
        let pos = (t / DRIFT_STEP_S).max(0.0);
        let k = (pos.floor() as usize).min(self.drift.len() - 2);
        let f = (pos - k as f64).min(1.0);
        let (a, b) = (self.drift[k], self.drift[k + 1]);
        [0, 1, 2].map(|i| a[i] + f * (b[i] - a[i]))
    }

    /// The pilot's stick and pedal changes from trim, %: from the attitude errors (pitch, roll,
    /// heading, from trim, rad) and the body rates `[p, q, r]`, at `t`.
    pub fn corrections(&self, t: f64, attitude_error: [f64; 3], rates: [f64; 3]) -> [f64; 3] {
        let d = self.drift(t);
        // Pitch on q, roll on p, heading on r.
        let rate = [rates[1], rates[0], rates[2]];
        [0, 1, 2].map(|k| {
            self.attitude_gain_percent_per_rad[k] * (attitude_error[k] - d[k])
                + self.rate_gain_percent_per_rad_s[k] * rate[k]
        })
    }
}
