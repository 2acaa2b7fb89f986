//! Six-degree-of-freedom rigid-body equations with Euler angles (seed 001 Eq. 1's airframe
//! states; the usual flat-Earth form, e.g. Padfield, Helicopter Flight Dynamics, Ch. 3).
//!
//! Body axes at the centre of mass: `x` forward, `y` starboard, `z` down. The aircraft is
//! symmetric about its `xz` plane (`I_xy = I_yz = 0`), with the product of inertia
//! `I_xz = integral x z dm` entering the angular momentum as `h_x = I_xx p - I_xz r`,
//! `h_z = I_zz r - I_xz p`. Euler angles are the 3-2-1
//! sequence `psi, theta, phi` from north-east-down axes; they are singular at `theta = +-90 deg`,
//! which is an error here, never a NaN.
//!
//! # Free rotors
//! `MassProperties` are the whole aircraft's, with every rotor as a frozen (non-spinning) disc.
//! A rotor on a bearing that carries no torque about its shaft (an autogyro's main rotor, a
//! propeller driven at a set engine torque) does not follow the airframe's angular acceleration
//! about its shaft: only the rest of the aircraft does. [`derivatives_with_free_spins`] solves
//! the moment equations with each such rotor's polar moment taken out about its shaft,
//! `(I - sum I_k s_k s_k^T) omega' = M - omega x (I omega)`. The gyroscopic term keeps the whole
//! inertia: the rotors' angular momentum about their shafts stays in the balance, and the loads
//! carry what they have beyond the frozen disc (their spin relative to the airframe).

use serde::Serialize;
use thiserror::Error;

/// Standard gravity, m/s^2.
pub const G_M_S2: f64 = 9.806_65;

/// Mass properties.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MassProperties {
    pub mass_kg: f64,
    pub ixx_kg_m2: f64,
    pub iyy_kg_m2: f64,
    pub izz_kg_m2: f64,
    pub ixz_kg_m2: f64,
}

/// Body state: velocities, rates, attitudes and position (north, east, down).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct BodyState {
    pub u_m_s: f64,
    pub v_m_s: f64,
    pub w_m_s: f64,
    pub p_rad_s: f64,
    pub q_rad_s: f64,
    pub r_rad_s: f64,
    pub phi_rad: f64,
    pub theta_rad: f64,
    pub psi_rad: f64,
    pub north_m: f64,
    pub east_m: f64,
    pub down_m: f64,
}

impl BodyState {
    /// As an array in the order of the fields.
    pub fn to_array(&self) -> [f64; 12] {
        [
            self.u_m_s,
            self.v_m_s,
            self.w_m_s,
            self.p_rad_s,
            self.q_rad_s,
            self.r_rad_s,
            self.phi_rad,
            self.theta_rad,
            self.psi_rad,
            self.north_m,
            self.east_m,
            self.down_m,
        ]
    }

    /// From an array in the order of the fields.
    pub fn from_array(a: [f64; 12]) -> Self {
        Self {
            u_m_s: a[0],
            v_m_s: a[1],
            w_m_s: a[2],
            p_rad_s: a[3],
            q_rad_s: a[4],
            r_rad_s: a[5],
            phi_rad: a[6],
            theta_rad: a[7],
            psi_rad: a[8],
            north_m: a[9],
            east_m: a[10],
            down_m: a[11],
        }
    }
}

/// External forces (N) and moments (N m) about the centre of mass, body axes, gravity excluded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct Loads {
    pub x_n: f64,
    pub y_n: f64,
    pub z_n: f64,
    pub l_n_m: f64,
    pub m_n_m: f64,
    pub n_n_m: f64,
}

/// Why the derivatives cannot be formed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BodyError {
    #[error("pitch attitude {0} rad is at the Euler-angle singularity (+-90 deg)")]
    Singular(f64),
    #[error("mass properties are not physical: {0}")]
    MassProperties(&'static str),
    #[error("non-finite state or loads")]
    NotFinite,
}

impl MassProperties {
    /// Checks positivity and the triangle inequalities of the principal moments.
    pub fn validate(&self) -> Result<(), BodyError> {
        let all = [
            self.mass_kg,
            self.ixx_kg_m2,
            self.iyy_kg_m2,
            self.izz_kg_m2,
            self.ixz_kg_m2,
        ];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(BodyError::MassProperties("a value is not finite"));
        }
        if self.mass_kg <= 0.0
            || self.ixx_kg_m2 <= 0.0
            || self.iyy_kg_m2 <= 0.0
            || self.izz_kg_m2 <= 0.0
        {
            return Err(BodyError::MassProperties(
                "mass and moments of inertia must be positive",
            ));
        }
        if self.ixx_kg_m2 * self.izz_kg_m2 <= self.ixz_kg_m2 * self.ixz_kg_m2 {
            return Err(BodyError::MassProperties("I_xx I_zz must exceed I_xz^2"));
        }
        Ok(())
    }
}

/// The state derivative for given loads.
pub fn derivatives(m: &MassProperties, s: &BodyState, f: &Loads) -> Result<BodyState, BodyError> {
    if s.to_array().iter().any(|v| !v.is_finite())
        || [f.x_n, f.y_n, f.z_n, f.l_n_m, f.m_n_m, f.n_n_m]
            .iter()
            .any(|v| !v.is_finite())
    {
        return Err(BodyError::NotFinite);
    }
    let (sphi, cphi) = s.phi_rad.sin_cos();
    let (sth, cth) = s.theta_rad.sin_cos();
    let (spsi, cpsi) = s.psi_rad.sin_cos();
    if cth.abs() < 1e-9 {
        return Err(BodyError::Singular(s.theta_rad));
    }
    let (u, v, w, p, q, r) = (s.u_m_s, s.v_m_s, s.w_m_s, s.p_rad_s, s.q_rad_s, s.r_rad_s);
    let g = G_M_S2;
    let (ixx, iyy, izz, ixz) = (m.ixx_kg_m2, m.iyy_kg_m2, m.izz_kg_m2, m.ixz_kg_m2);
    let gamma = ixx * izz - ixz * ixz;
    let pd = (izz * f.l_n_m + ixz * f.n_n_m + ixz * (ixx - iyy + izz) * p * q
        - (izz * (izz - iyy) + ixz * ixz) * q * r)
        / gamma;
    let qd = (f.m_n_m - (ixx - izz) * p * r - ixz * (p * p - r * r)) / iyy;
    let rd = (ixz * f.l_n_m + ixx * f.n_n_m + (ixx * (ixx - iyy) + ixz * ixz) * p * q
        - ixz * (ixx - iyy + izz) * q * r)
        / gamma;
    // Body to north-east-down velocity (transpose of the 3-2-1 rotation).
    let north = cth * cpsi * u
        + (sphi * sth * cpsi - cphi * spsi) * v
        + (cphi * sth * cpsi + sphi * spsi) * w;
    let east = cth * spsi * u
        + (sphi * sth * spsi + cphi * cpsi) * v
        + (cphi * sth * spsi - sphi * cpsi) * w;
    let down = -sth * u + sphi * cth * v + cphi * cth * w;
    Ok(BodyState {
        u_m_s: f.x_n / m.mass_kg - g * sth - q * w + r * v,
        v_m_s: f.y_n / m.mass_kg + g * cth * sphi - r * u + p * w,
        w_m_s: f.z_n / m.mass_kg + g * cth * cphi - p * v + q * u,
        p_rad_s: pd,
        q_rad_s: qd,
        r_rad_s: rd,
        phi_rad: p + sth / cth * (q * sphi + r * cphi),
        theta_rad: q * cphi - r * sphi,
        psi_rad: (q * sphi + r * cphi) / cth,
        north_m: north,
        east_m: east,
        down_m: down,
    })
}

/// A rotor that turns freely about its shaft: the shaft's direction in body axes (a unit
/// vector, either sense) and the rotor's polar moment of inertia about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeSpin {
    pub axis: [f64; 3],
    pub polar_inertia_kg_m2: f64,
}

/// The state derivative for given loads, with free rotors' polar moments taken out of the
/// inertia the angular accelerations see (see the module docs). The same as [`derivatives`]
/// with no free rotors; an error if what is left of the inertia is not positive definite.
pub fn derivatives_with_free_spins(
    m: &MassProperties,
    s: &BodyState,
    f: &Loads,
    free: &[FreeSpin],
) -> Result<BodyState, BodyError> {
    let mut d = derivatives(m, s, f)?;
    if free.is_empty() {
        return Ok(d);
    }
    // `M - omega x (I omega)` is `I omega'` of the frozen-disc solution.
    let rhs = whole_inertia(m) * nalgebra::Vector3::new(d.p_rad_s, d.q_rad_s, d.r_rad_s);
    let w = airframe_inertia(m, free)?.solve(&rhs);
    (d.p_rad_s, d.q_rad_s, d.r_rad_s) = (w[0], w[1], w[2]);
    Ok(d)
}

/// The angular accelerations `[p' q' r']` that moments alone give (no rates), with free
/// rotors' polar moments taken out (see [`derivatives_with_free_spins`]).
pub fn angular_accelerations(
    m: &MassProperties,
    moments_n_m: [f64; 3],
    free: &[FreeSpin],
) -> Result<[f64; 3], BodyError> {
    let w = airframe_inertia(m, free)?.solve(&nalgebra::Vector3::from(moments_n_m));
    Ok([w[0], w[1], w[2]])
}

fn whole_inertia(m: &MassProperties) -> nalgebra::Matrix3<f64> {
    nalgebra::Matrix3::new(
        m.ixx_kg_m2,
        0.0,
        -m.ixz_kg_m2,
        0.0,
        m.iyy_kg_m2,
        0.0,
        -m.ixz_kg_m2,
        0.0,
        m.izz_kg_m2,
    )
}

/// The inertia the angular accelerations see, factorised: the whole aircraft's without its
/// free rotors' polar moments about their shafts.
fn airframe_inertia(
    m: &MassProperties,
    free: &[FreeSpin],
) -> Result<nalgebra::Cholesky<f64, nalgebra::U3>, BodyError> {
    let mut airframe = whole_inertia(m);
    for k in free {
        let a = nalgebra::Vector3::from(k.axis);
        if !(k.polar_inertia_kg_m2.is_finite()
            && k.polar_inertia_kg_m2 >= 0.0
            && a.iter().all(|v| v.is_finite()))
        {
            return Err(BodyError::NotFinite);
        }
        airframe -= k.polar_inertia_kg_m2 * a * a.transpose();
    }
    airframe.cholesky().ok_or(BodyError::MassProperties(
        "the airframe's inertia without its free rotors' polar moments is not positive definite",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A free rotor about the z axis, with no product of inertia: a yawing moment accelerates
    /// only what is left, `r' = N / (I_zz - I_R)`; the roll and pitch equations do not change;
    /// with no free rotor the result is the frozen-disc one.
    #[test]
    fn a_free_rotor_is_taken_out_of_the_yaw_inertia() {
        let m = MassProperties {
            ixz_kg_m2: 0.0,
            ..mass()
        };
        let s = BodyState::default();
        let f = Loads {
            l_n_m: 30.0,
            m_n_m: -20.0,
            n_n_m: 100.0,
            ..Loads::default()
        };
        let free = [FreeSpin {
            axis: [0.0, 0.0, 1.0],
            polar_inertia_kg_m2: 110.0,
        }];
        let d = derivatives_with_free_spins(&m, &s, &f, &free).unwrap();
        assert!((d.r_rad_s - 100.0 / (580.0 - 110.0)).abs() < 1e-12);
        assert!((d.p_rad_s - 30.0 / 220.0).abs() < 1e-12);
        assert!((d.q_rad_s + 20.0 / 870.0).abs() < 1e-12);
        assert_eq!(
            derivatives_with_free_spins(&mass(), &s, &f, &[]).unwrap(),
            derivatives(&mass(), &s, &f).unwrap()
        );
        let too_big = [FreeSpin {
            axis: [0.0, 0.0, 1.0],
            polar_inertia_kg_m2: 600.0,
        }];
        assert!(derivatives_with_free_spins(&m, &s, &f, &too_big).is_err());
    }

    fn mass() -> MassProperties {
        // Test values of light-gyroplane size (estimated), with a product of inertia.
        MassProperties {
            mass_kg: 425.0,
            ixx_kg_m2: 220.0,
            iyy_kg_m2: 870.0,
            izz_kg_m2: 580.0,
            ixz_kg_m2: 40.0,
        }
    }

    fn rk4(m: &MassProperties, s: BodyState, f: &Loads, dt: f64) -> BodyState {
        let add = |a: &BodyState, k: &BodyState, h: f64| {
            let (x, y) = (a.to_array(), k.to_array());
            BodyState::from_array(std::array::from_fn(|i| x[i] + h * y[i]))
        };
        let k1 = derivatives(m, &s, f).unwrap();
        let k2 = derivatives(m, &add(&s, &k1, dt / 2.0), f).unwrap();
        let k3 = derivatives(m, &add(&s, &k2, dt / 2.0), f).unwrap();
        let k4 = derivatives(m, &add(&s, &k3, dt), f).unwrap();
        let (x, a, b, c, d) = (
            s.to_array(),
            k1.to_array(),
            k2.to_array(),
            k3.to_array(),
            k4.to_array(),
        );
        BodyState::from_array(std::array::from_fn(|i| {
            x[i] + dt / 6.0 * (a[i] + 2.0 * b[i] + 2.0 * c[i] + d[i])
        }))
    }

    #[test]
    fn torque_free_rotation_conserves_energy_and_angular_momentum() {
        let m = mass();
        let mut s = BodyState {
            p_rad_s: 0.7,
            q_rad_s: -0.3,
            r_rad_s: 0.5,
            ..BodyState::default()
        };
        let invariants = |s: &BodyState| {
            let (p, q, r) = (s.p_rad_s, s.q_rad_s, s.r_rad_s);
            let h = [
                m.ixx_kg_m2 * p - m.ixz_kg_m2 * r,
                m.iyy_kg_m2 * q,
                m.izz_kg_m2 * r - m.ixz_kg_m2 * p,
            ];
            (
                0.5 * (h[0] * p + h[1] * q + h[2] * r),
                (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt(),
            )
        };
        let (e0, h0) = invariants(&s);
        // Gravity acts on the translation only; the rotation is torque-free.
        for _ in 0..5000 {
            s = rk4(&m, s, &Loads::default(), 0.002);
        }
        let (e1, h1) = invariants(&s);
        assert!(
            ((e1 - e0) / e0).abs() < 1e-9 && ((h1 - h0) / h0).abs() < 1e-9,
            "{e0} {e1} {h0} {h1}"
        );
    }

    #[test]
    fn balanced_loads_give_steady_flight() {
        // 30 m/s, 5 deg nose up and 3 deg of bank: the loads that cancel gravity give zero
        // accelerations and a constant heading.
        let m = mass();
        let (th, ph) = (5f64.to_radians(), 3f64.to_radians());
        let s = BodyState {
            u_m_s: 30.0 * th.cos(),
            w_m_s: 30.0 * th.sin(),
            theta_rad: th,
            phi_rad: ph,
            ..BodyState::default()
        };
        let g = m.mass_kg * G_M_S2;
        let f = Loads {
            x_n: g * th.sin(),
            y_n: -g * th.cos() * ph.sin(),
            z_n: -g * th.cos() * ph.cos(),
            ..Loads::default()
        };
        let d = derivatives(&m, &s, &f).unwrap();
        for (i, v) in d.to_array()[..9].iter().enumerate() {
            assert!(v.abs() < 1e-12, "component {i}: {v}");
        }
        // The body-to-earth transform is a rotation: the speed is kept.
        let speed = (d.north_m.powi(2) + d.east_m.powi(2) + d.down_m.powi(2)).sqrt();
        assert!((speed - 30.0).abs() < 1e-12, "{d:?}");
        // Wings level, the flight path is level and due north.
        let level = BodyState { phi_rad: 0.0, ..s };
        let d = derivatives(
            &m,
            &level,
            &Loads {
                y_n: 0.0,
                z_n: -g * th.cos(),
                ..f
            },
        )
        .unwrap();
        assert!(
            (d.north_m - 30.0).abs() < 1e-12 && d.east_m.abs() < 1e-12 && d.down_m.abs() < 1e-12,
            "{d:?}"
        );
    }

    #[test]
    fn free_fall_and_singularities() {
        let d = derivatives(&mass(), &BodyState::default(), &Loads::default()).unwrap();
        assert!((d.w_m_s - G_M_S2).abs() < 1e-15 && d.u_m_s == 0.0);
        let s = BodyState {
            theta_rad: std::f64::consts::FRAC_PI_2,
            ..BodyState::default()
        };
        assert!(matches!(
            derivatives(&mass(), &s, &Loads::default()),
            Err(BodyError::Singular(_))
        ));
        let bad = MassProperties {
            ixz_kg_m2: 400.0,
            ..mass()
        };
        assert!(bad.validate().is_err());
        let nan = BodyState {
            u_m_s: f64::NAN,
            ..BodyState::default()
        };
        assert_eq!(
            derivatives(&mass(), &nan, &Loads::default()),
            Err(BodyError::NotFinite)
        );
    }
}
