//! Atmospheric turbulence: the Dryden forms of MIL-F-8785C (Sec. 3.7.3; the same forms and
//! low-altitude scales are in MIL-HDBK-1797), as gust velocities for the full model's
//! aerodynamics (`Aircraft::derivatives_in_wind`), not as forces.
//!
//! Spectra (one-sided, in circular frequency `omega`, rad/s, of a frozen field flown through at
//! airspeed `V`; `T = L / V`):
//!
//! ```text
//! Phi_u(omega) = sigma_u^2 (2 T / pi) / (1 + (T omega)^2)
//! Phi_w(omega) = sigma_w^2 (T / pi) (1 + 3 (T omega)^2) / (1 + (T omega)^2)^2   (and v)
//! ```
//!
//! each integrating to its `sigma^2`. They are realised as unit white noise through the shaping
//! filters `sigma sqrt(2 T) / (1 + T s)` and `sigma sqrt(T) (1 + sqrt(3) T s) / (1 + T s)^2`,
//! discretised exactly (the filters' own transition and noise covariance over a sample interval)
//! and started from their stationary distribution, so a record has no start-up transient. The
//! autocorrelations are `sigma_u^2 exp(-tau/T)` and `sigma_w^2 (1 - tau/(2T)) exp(-tau/T)`, which
//! a test checks on a long realisation.
//!
//! The components are along the body axes (the specification's axes are those of the mean
//! flight path; the difference is the angle of attack, a few degrees in level flight). The
//! gust's gradients (its rotational components) are not modelled.

use crate::synth::linear::Normal;
use crate::units::FT_TO_M;
use serde::Serialize;

/// The turbulence: intensities and scale lengths of the three components.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Dryden {
    /// `sigma_u, sigma_v, sigma_w`, m/s.
    pub sigma_m_s: [f64; 3],
    /// `L_u, L_v, L_w`, m.
    pub scale_m: [f64; 3],
}

impl Dryden {
    /// MIL-F-8785C's low-altitude model (from 10 to 1000 ft above ground): `L_w = h`,
    /// `L_u = L_v = h / (0.177 + 0.000823 h)^1.2` and
    /// `sigma_u = sigma_v = sigma_w / (0.177 + 0.000823 h)^0.4`, with `h` in ft.
    pub fn low_altitude(sigma_w_m_s: f64, height_m: f64) -> Result<Self, String> {
        if !(sigma_w_m_s.is_finite() && sigma_w_m_s >= 0.0) {
            return Err(format!(
                "the vertical gust intensity must be finite and not negative (got {sigma_w_m_s} m/s)"
            ));
        }
        let h = height_m / FT_TO_M;
        if !(10.0..=1000.0).contains(&h) {
            return Err(format!(
                "MIL-F-8785C's low-altitude turbulence holds from 10 to 1000 ft above ground (got {h:.0} ft)"
            ));
        }
        let d = 0.177 + 0.000823 * h;
        let l_uv = h / d.powf(1.2) * FT_TO_M;
        let s_uv = sigma_w_m_s / d.powf(0.4);
        Ok(Self {
            sigma_m_s: [s_uv, s_uv, sigma_w_m_s],
            scale_m: [l_uv, l_uv, height_m],
        })
    }

    /// A realisation flown at `airspeed_m_s`: the gust velocities `[u, v, w]` at the times
    /// `k dt_s`, `k = 0..=n`, from the seeded generator.
    pub fn realise(
        &self,
        airspeed_m_s: f64,
        dt_s: f64,
        n: usize,
        seed: u64,
    ) -> Result<Vec<[f64; 3]>, String> {
        if !(airspeed_m_s.is_finite() && airspeed_m_s > 0.0 && dt_s.is_finite() && dt_s > 0.0) {
            return Err(format!(
                "turbulence needs a positive airspeed and sample interval (got {airspeed_m_s} m/s, {dt_s} s)"
            ));
        }
        let mut rng = Normal::new(seed);
        let mut out = vec![[0.0; 3]; n + 1];
        for axis in 0..3 {
            let sigma = self.sigma_m_s[axis];
            let t = self.scale_m[axis] / airspeed_m_s;
            if sigma == 0.0 {
                continue;
            }
            if axis == 0 {
                // First order: an exact AR(1), started stationary.
                let phi = (-dt_s / t).exp();
                let q = sigma * (1.0 - phi * phi).sqrt();
                let mut x = sigma * rng.sample();
                for sample in out.iter_mut() {
                    sample[axis] = x;
                    x = phi * x + q * rng.sample();
                }
            } else {
                let mut f = SecondOrder::new(t, dt_s);
                let mut z = f.stationary(&mut rng);
                let gain = sigma * t.sqrt();
                let root3 = 3f64.sqrt();
                for sample in out.iter_mut() {
                    sample[axis] = gain * (z[1] + root3 * (z[0] - z[1]));
                    z = f.step(z, &mut rng);
                }
            }
        }
        Ok(out)
    }
}

/// The cascade `T z1' = -z1 + n`, `T z2' = -z2 + z1` driven by unit white noise `n`, discretised
/// exactly: `A = -I/T + N` with `N` nilpotent, so `exp(A dt) = exp(-dt/T) (I + N dt)`, and the
/// noise covariance is the integral of `exp(A tau) b b' exp(A tau)'` over the interval.
struct SecondOrder {
    phi: f64,
    coupling: f64,
    /// The lower Cholesky factor of the interval's noise covariance.
    chol: [[f64; 2]; 2],
    t: f64,
}

impl SecondOrder {
    fn new(t: f64, dt: f64) -> Self {
        let phi = (-dt / t).exp();
        let a = 2.0 / t;
        let x = a * dt;
        // The integrals of tau^j exp(-a tau) over the interval, j = 0, 1, 2.
        let i0 = poisson_tail(x, 0) / a;
        let i1 = poisson_tail(x, 1) / (a * a);
        let i2 = 2.0 * poisson_tail(x, 2) / (a * a * a);
        let (q11, q12, q22) = (i0 / t.powi(2), i1 / t.powi(3), i2 / t.powi(4));
        Self {
            phi,
            coupling: phi * dt / t,
            chol: cholesky2(q11, q12, q22),
            t,
        }
    }

    /// A draw from the stationary covariance `[[1, 1/2], [1/2, 1/2]] / (2 T)`.
    fn stationary(&self, rng: &mut Normal) -> [f64; 2] {
        let c = cholesky2(0.5 / self.t, 0.25 / self.t, 0.25 / self.t);
        draw(&c, rng)
    }

    fn step(&mut self, z: [f64; 2], rng: &mut Normal) -> [f64; 2] {
        let w = draw(&self.chol, rng);
        [
            self.phi * z[0] + w[0],
            self.coupling * z[0] + self.phi * z[1] + w[1],
        ]
    }
}

/// `1 - exp(-x) sum_{j <= m} x^j / j!` (the chance a Poisson count of mean `x` exceeds `m`),
/// summed term by term for small `x`, where the difference would cancel.
fn poisson_tail(x: f64, m: u32) -> f64 {
    if x >= 1.0 {
        let mut term = 1.0;
        let mut sum = 1.0;
        for j in 1..=m {
            term *= x / f64::from(j);
            sum += term;
        }
        return 1.0 - (-x).exp() * sum;
    }
    let mut term = 1.0;
    for j in 1..=m {
        term *= x / f64::from(j);
    }
    let mut sum = 0.0;
    for j in m + 1..m + 40 {
        term *= x / f64::from(j);
        sum += term;
    }
    (-x).exp() * sum
}

fn cholesky2(a11: f64, a12: f64, a22: f64) -> [[f64; 2]; 2] {
    let l11 = a11.sqrt();
    let l21 = a12 / l11;
    let l22 = (a22 - l21 * l21).max(0.0).sqrt();
    [[l11, 0.0], [l21, l22]]
}

fn draw(l: &[[f64; 2]; 2], rng: &mut Normal) -> [f64; 2] {
    let (a, b) = (rng.sample(), rng.sample());
    [l[0][0] * a, l[1][0] * a + l[1][1] * b]
}
