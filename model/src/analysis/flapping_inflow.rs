//! Induced velocity from blade flapping (seed 003, Eqs. 13-19).
//!
//! The harmonic balance of the flap equation (seed 003 Eqs. 7-12: linear lift `a0 + a1 alpha`,
//! `theta = theta_0 + r theta_tw`, small angles, constant chord, first harmonics) relates the
//! disc's coning and tilts to the inflow components:
//!
//! ```text
//! (15) beta_0 = gamma / (2 Omega^2 R^2) { (a0/a1 + theta_0)(Omega^2 R^2 + V^2)/4
//!                 + R theta_tw (Omega^2 R^2 + 5 V^2/6)/5 - Omega R (v0 - w_hub)/3 - V v1s/6 }
//! (16) beta_1s (Omega R + V^2/(Omega R)) = -4 V beta_0 / 3 - v1c
//! (17) beta_1c = -8 V / (Omega^2 R^2 - V^2) { -(v0 - w_hub + Omega R v1s / (2V))/4
//!                 + Omega R (a0/a1 + theta_0)/3 + Omega R^2 theta_tw / 4 }
//! (19) v1c = (15/32) pi tan(chi/2) v0          (when the coning is unknown)
//! ```
//!
//! with `beta = beta_0 + beta_1c cos psi + beta_1s sin psi` (azimuth from the rear), `V` the
//! in-plane speed and `w_hub` the speed along the shaft, down. Two differences from the seed's
//! extracted text, both following from its own Eq. 7: the inflow terms of Eq. 15 carry the lift
//! slope (written here with `a0/a1 + theta_0` factored as `gamma` includes `a1`), and Eq. 17 has
//! no `a1` in its leading factor; with these, Eqs. 15 and 17 reduce to the classical
//! articulated-rotor coning and longitudinal flapping for uniform inflow (the unit tests check
//! this). Eqs. 15-17 are linear in `v0, v1s, v1c`.

use serde::Serialize;
use thiserror::Error;

/// What is known: the disc's motion and the rotor's state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlapMeasurement {
    /// Coning, rad (`None` for a teetering rotor whose blades cone elastically: Eq. 19 is used).
    pub beta_0_rad: Option<f64>,
    pub beta_1c_rad: f64,
    pub beta_1s_rad: f64,
    /// In-plane speed of the hub through the air, m/s.
    pub v_inplane_m_s: f64,
    /// Speed of the hub along the shaft (down), m/s: positive in autorotation.
    pub w_hub_m_s: f64,
    pub omega_rad_s: f64,
    pub radius_m: f64,
    pub lock_number: f64,
    /// Section lift at zero angle of attack and lift slope (Eq. 7).
    pub a0: f64,
    pub a1_per_rad: f64,
    /// Blade pitch at the shaft (`theta_0`) and its gradient along the span, rad and rad/m.
    pub theta_0_rad: f64,
    pub theta_tw_rad_per_m: f64,
    /// `tan(chi/2)` for Eq. 19 (seed 003 takes 1, or Eqs. 5-6 with `v_i0m << w_hub`).
    pub tan_half_skew: f64,
}

/// The inflow (and coning) that the flapping implies.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlapInflow {
    pub v0_m_s: f64,
    pub v1s_m_s: f64,
    pub v1c_m_s: f64,
    pub beta_0_rad: f64,
}

/// Why no inflow follows.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FlapInflowError {
    #[error("{0} must be finite and positive")]
    Input(&'static str),
    #[error(
        "the equations are singular at this condition (V = {0} m/s): the in-plane speed must be positive and below the tip speed"
    )]
    Singular(f64),
}

/// Solves Eqs. 15-17 (with Eq. 19 when the coning is unknown) for the inflow.
pub fn inflow_from_flapping(m: &FlapMeasurement) -> Result<FlapInflow, FlapInflowError> {
    for (n, v) in [
        ("omega_rad_s", m.omega_rad_s),
        ("radius_m", m.radius_m),
        ("lock_number", m.lock_number),
        ("a1_per_rad", m.a1_per_rad),
        ("v_inplane_m_s", m.v_inplane_m_s),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(FlapInflowError::Input(n));
        }
    }
    let (w, r, v) = (m.omega_rad_s, m.radius_m, m.v_inplane_m_s);
    let tip = w * r;
    if v >= tip {
        return Err(FlapInflowError::Singular(v));
    }
    let k = m.lock_number / (2.0 * tip * tip);
    let pitch = m.a0 / m.a1_per_rad + m.theta_0_rad;
    let a0_terms = pitch * (tip * tip + v * v) / 4.0
        + r * m.theta_tw_rad_per_m * (tip * tip + 5.0 * v * v / 6.0) / 5.0;
    // Eq. 17 as  beta_1c = f (c17 + (v0 - w)/4 + tip v1s/(8V))  with f = 8V/(tip^2 - V^2):
    let f = 8.0 * v / (tip * tip - v * v);
    let c17 = -(tip * pitch / 3.0 + tip * r * m.theta_tw_rad_per_m / 4.0);
    // Unknowns: d = v0 - w_hub, v1s (and beta_0, v1c).
    //  Eq. 15: beta_0 = k (a0_terms - tip d / 3 - V v1s / 6)
    //  Eq. 17: beta_1c / f - c17 = d / 4 + tip v1s / (8V)
    //  Eq. 16: v1c = -beta_1s (tip + V^2 / tip) - 4 V beta_0 / 3
    //  Eq. 19: v1c = (15/32) pi tan(chi/2) (d + w_hub)
    let rhs17 = m.beta_1c_rad / f - c17;
    let e16 = -m.beta_1s_rad * (tip + v * v / tip);
    let (d, v1s, beta_0) = match m.beta_0_rad {
        Some(b0) => {
            // [tip/3, V/6; 1/4, tip/(8V)] [d; v1s] = [a0_terms - b0/k; rhs17]
            let (a11, a12, a21, a22) = (tip / 3.0, v / 6.0, 0.25, tip / (8.0 * v));
            let (r1, r2) = (a0_terms - b0 / k, rhs17);
            let det = a11 * a22 - a12 * a21;
            if det.abs() < 1e-12 * (a11 * a22).abs() {
                return Err(FlapInflowError::Singular(v));
            }
            ((r1 * a22 - a12 * r2) / det, (a11 * r2 - a21 * r1) / det, b0)
        }
        None => {
            // Eliminate beta_0 with Eqs. 16 and 19: e16 - 4V k (a0_terms - tip d/3 - V v1s/6)/3
            //   = c19 (d + w) with c19 = (15/32) pi tan(chi/2).
            let c19 = 15.0 / 32.0 * std::f64::consts::PI * m.tan_half_skew;
            let g = 4.0 * v * k / 3.0;
            // (g tip/3 - c19) d + (g V/6) v1s = c19 w - e16 + g a0_terms
            let (a11, a12, r1) = (
                g * tip / 3.0 - c19,
                g * v / 6.0,
                c19 * m.w_hub_m_s - e16 + g * a0_terms,
            );
            let (a21, a22, r2) = (0.25, tip / (8.0 * v), rhs17);
            let det = a11 * a22 - a12 * a21;
            if det.abs() < 1e-12 {
                return Err(FlapInflowError::Singular(v));
            }
            let d = (r1 * a22 - a12 * r2) / det;
            let v1s = (a11 * r2 - a21 * r1) / det;
            (d, v1s, k * (a0_terms - tip * d / 3.0 - v * v1s / 6.0))
        }
    };
    let v1c = e16 - 4.0 * v * beta_0 / 3.0;
    Ok(FlapInflow {
        v0_m_s: d + m.w_hub_m_s,
        v1s_m_s: v1s,
        v1c_m_s: v1c,
        beta_0_rad: beta_0,
    })
}

/// Disc tilts from a teeter angle and the azimuth of the reference blade measured from the
/// front of the disc (seed 003 Eqs. 13-14): `(beta_1s, beta_1c)`.
pub fn disc_tilts(teeter_rad: f64, azimuth_from_front_rad: f64) -> (f64, f64) {
    (
        -teeter_rad * azimuth_from_front_rad.sin(),
        -teeter_rad * azimuth_from_front_rad.cos(),
    )
}

/// The forward problem: coning and tilts for given inflow (Eqs. 15-17), used to check the
/// inversion and by synthetic records.
pub fn flapping_from_inflow(m: &FlapMeasurement, inflow: &FlapInflow) -> (f64, f64, f64) {
    let (w, r, v) = (m.omega_rad_s, m.radius_m, m.v_inplane_m_s);
    let tip = w * r;
    let k = m.lock_number / (2.0 * tip * tip);
    let pitch = m.a0 / m.a1_per_rad + m.theta_0_rad;
    let d = inflow.v0_m_s - m.w_hub_m_s;
    let beta_0 = k
        * (pitch * (tip * tip + v * v) / 4.0
            + r * m.theta_tw_rad_per_m * (tip * tip + 5.0 * v * v / 6.0) / 5.0
            - tip * d / 3.0
            - v * inflow.v1s_m_s / 6.0);
    let beta_1s = (-4.0 * v * beta_0 / 3.0 - inflow.v1c_m_s) / (tip + v * v / tip);
    let beta_1c = -8.0 * v / (tip * tip - v * v)
        * (-(d + tip * inflow.v1s_m_s / (2.0 * v)) / 4.0
            + tip * pitch / 3.0
            + tip * r * m.theta_tw_rad_per_m / 4.0);
    (beta_0, beta_1s, beta_1c)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn measurement() -> FlapMeasurement {
        FlapMeasurement {
            beta_0_rad: None,
            beta_1c_rad: 0.0,
            beta_1s_rad: 0.0,
            v_inplane_m_s: 25.0,
            w_hub_m_s: 3.0,
            omega_rad_s: 37.0,
            radius_m: 4.2,
            lock_number: 8.0,
            a0: 0.0,
            a1_per_rad: 5.7,
            theta_0_rad: 0.03,
            theta_tw_rad_per_m: 0.0,
            tan_half_skew: 1.0,
        }
    }

    #[test]
    fn eqs_15_and_17_reduce_to_the_classical_results() {
        // Uniform inflow: beta_0 = gamma (theta/8 (1 + mu^2) - lambda/6) (Eq. 15) and
        // beta_1c = -2 mu (4 theta/3 - lambda) / (1 - mu^2) (Eq. 17; the classical denominator
        // 1 - mu^2/2 differs at order mu^2, from the harmonic balance's truncation).
        let m = measurement();
        let inflow = FlapInflow {
            v0_m_s: 1.0,
            v1s_m_s: 0.0,
            v1c_m_s: 0.0,
            beta_0_rad: 0.0,
        };
        let (b0, _, b1c) = flapping_from_inflow(&m, &inflow);
        let tip = m.omega_rad_s * m.radius_m;
        let (mu, lambda) = (m.v_inplane_m_s / tip, (1.0 - m.w_hub_m_s) / tip);
        let classical_b0 = m.lock_number * (m.theta_0_rad / 8.0 * (1.0 + mu * mu) - lambda / 6.0);
        let classical_b1c = -2.0 * mu * (4.0 * m.theta_0_rad / 3.0 - lambda) / (1.0 - mu * mu);
        assert!((b0 - classical_b0).abs() < 1e-12, "{b0} {classical_b0}");
        assert!((b1c - classical_b1c).abs() < 1e-12, "{b1c} {classical_b1c}");
    }

    #[test]
    fn inversion_recovers_the_inflow_with_and_without_coning() {
        let mut m = measurement();
        let truth = FlapInflow {
            v0_m_s: 1.3,
            v1s_m_s: -0.4,
            v1c_m_s: 0.0,
            beta_0_rad: 0.0,
        };
        // With coning known (any v1c).
        let truth = FlapInflow {
            v1c_m_s: 0.9,
            ..truth
        };
        let (b0, b1s, b1c) = flapping_from_inflow(&m, &truth);
        m.beta_0_rad = Some(b0);
        m.beta_1s_rad = b1s;
        m.beta_1c_rad = b1c;
        let got = inflow_from_flapping(&m).unwrap();
        for (g, w) in [(got.v0_m_s, 1.3), (got.v1s_m_s, -0.4), (got.v1c_m_s, 0.9)] {
            assert!((g - w).abs() < 1e-9, "{got:?}");
        }
        // Coning unknown: v1c tied to v0 by Eq. 19.
        let truth = FlapInflow {
            v1c_m_s: 15.0 / 32.0 * std::f64::consts::PI * 1.3,
            ..truth
        };
        let (b0, b1s, b1c) = flapping_from_inflow(&m, &truth);
        m.beta_0_rad = None;
        m.beta_1s_rad = b1s;
        m.beta_1c_rad = b1c;
        let got = inflow_from_flapping(&m).unwrap();
        assert!(
            (got.v0_m_s - 1.3).abs() < 1e-9 && (got.beta_0_rad - b0).abs() < 1e-12,
            "{got:?}"
        );
    }

    #[test]
    fn teeter_gives_the_disc_tilts() {
        // Reference blade over the nose (azimuth 0 from the front), flapped back by 2 deg: the
        // disc tilts back, beta_1c = -2 deg (blade down at the rear, psi = 0 from the rear).
        let (b1s, b1c) = disc_tilts(2f64.to_radians(), 0.0);
        assert!(b1s.abs() < 1e-15 && (b1c + 2f64.to_radians()).abs() < 1e-15);
    }
}
