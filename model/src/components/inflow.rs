//! Peters-HaQuang dynamic inflow in Chen's skew-angle form (seed 001 Eqs. 2-5 and 13-15,
//! seed 003 Eqs. 2-6).
//!
//! The static gains relate the induced velocity components to the rotor's aerodynamic thrust
//! and its rolling and pitching moments in wind axes:
//!
//! ```text
//! v0  = T / (2 rho pi R^2 v_T)                    + 15 pi tan(chi/2) / (64 rho pi R^3 v_m) M
//! v1s =                 -4 / (rho pi R^3 v_m (1 + cos chi)) L
//! v1c = 15 pi tan(chi/2) / (64 rho pi R^2 v_T) T  - 4 cos chi / (rho pi R^3 v_m (1 + cos chi)) M
//! ```
//!
//! with `v_T = sqrt(V^2 + (v_i0m - w_hub)^2)`, `v_m = (V^2 + (v_i0m - w_hub)(2 v_i0m - w_hub)) / v_T`,
//! `V` the hub's in-plane speed, `w_hub` its speed along the shaft (down) and `v_i0m` the
//! momentum induced velocity, taken as the uniform component `v0` (at equilibrium the first
//! row is Glauert's momentum theory). The skew angle takes one of three forms
//! ([`SkewConvention`]): seed 001 Eq. 15 (signed, negative when the flow is up through the
//! disc, as in autorotation), seed 003 Eq. 5 as Chen presents it (geometric, above 90 deg
//! then), or seed 003 Eq. 6 (modulus, Peters and HaQuang's disc angle).
//!
//! Wind axes are hub axes turned about the shaft so that `x` points along the hub's in-plane
//! motion; wind azimuth is `psi + psi_w`, with `psi_w = atan2(v, u)`.

use crate::components::rotor::{HubVelocity, Inflow, SkewConvention, SteadyLoads};
use serde::Serialize;
use std::f64::consts::PI;

/// The wake quantities of the gains.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Wake {
    pub v_t_m_s: f64,
    pub v_m_m_s: f64,
    pub skew_rad: f64,
}

/// Wake velocities and skew for a hub motion and a uniform induced velocity.
pub fn wake(hub: HubVelocity, v0: f64, skew: SkewConvention) -> Wake {
    let v_inplane = hub.u.hypot(hub.v);
    let d = v0 - hub.w;
    let v_t = v_inplane.hypot(d).max(1e-9);
    let v_m = (v_inplane * v_inplane + d * (2.0 * v0 - hub.w)) / v_t;
    let skew_rad = match skew {
        SkewConvention::Signed => {
            if d == 0.0 {
                PI / 2.0
            } else {
                (v_inplane / d).atan()
            }
        }
        SkewConvention::Geometric => v_inplane.atan2(d),
        SkewConvention::Modulus => v_inplane.atan2(d.abs()),
    };
    Wake {
        v_t_m_s: v_t,
        v_m_m_s: v_m,
        skew_rad,
    }
}

/// The rotor's aerodynamic loads that drive the inflow, hub axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DrivingLoads {
    /// Thrust along the shaft, upwards, N.
    pub thrust_n: f64,
    /// Moment about `x` (right side down positive), N m.
    pub roll_n_m: f64,
    /// Moment about `y` (nose up positive), N m.
    pub pitch_n_m: f64,
}

impl DrivingLoads {
    /// The driving loads of a rotor's revolution-mean loads.
    pub fn of(loads: &SteadyLoads) -> Self {
        Self {
            thrust_n: loads.thrust_n(),
            roll_n_m: loads.moment_n_m[0],
            pitch_n_m: loads.moment_n_m[1],
        }
    }
}

/// The equilibrium induced velocity (hub axes) for given loads, at the current uniform
/// component `v0` (for the wake velocities). `harmonics = false` zeroes `v1s` and `v1c`.
pub fn static_inflow(
    loads: DrivingLoads,
    hub: HubVelocity,
    v0: f64,
    density_kg_m3: f64,
    radius_m: f64,
    (skew, harmonics): (SkewConvention, bool),
) -> (Inflow, Wake) {
    let DrivingLoads {
        thrust_n: t_n,
        roll_n_m,
        pitch_n_m,
    } = loads;
    let wk = wake(hub, v0, skew);
    let (sw, cw) = wind_azimuth(hub).sin_cos();
    let l_w = roll_n_m * cw + pitch_n_m * sw;
    let m_w = -roll_n_m * sw + pitch_n_m * cw;
    let (rho, r) = (density_kg_m3, radius_m);
    let a = rho * PI * r * r;
    let chi = wk.skew_rad;
    let coupling = 15.0 * PI * (chi / 2.0).tan() / 64.0;
    let vm = if wk.v_m_m_s.abs() < 1e-9 {
        1e-9f64.copysign(wk.v_m_m_s)
    } else {
        wk.v_m_m_s
    };
    let v0_new = t_n / (2.0 * a * wk.v_t_m_s) + coupling * m_w / (a * r * vm);
    if !harmonics {
        return (
            Inflow {
                v0: v0_new,
                v1s: 0.0,
                v1c: 0.0,
            },
            wk,
        );
    }
    let v1s_w = -4.0 * l_w / (a * r * vm * (1.0 + chi.cos()));
    let v1c_w = coupling * t_n / (a * wk.v_t_m_s)
        - 4.0 * chi.cos() * m_w / (a * r * vm * (1.0 + chi.cos()));
    (
        Inflow {
            v0: v0_new,
            v1s: v1s_w * cw - v1c_w * sw,
            v1c: v1s_w * sw + v1c_w * cw,
        },
        wk,
    )
}

/// The wind-axis azimuth `psi_w = atan2(v, u)` of the hub's in-plane motion (zero in hover).
fn wind_azimuth(hub: HubVelocity) -> f64 {
    if hub.u == 0.0 && hub.v == 0.0 {
        0.0
    } else {
        hub.v.atan2(hub.u)
    }
}

/// The time-constant matrix of seed 001 Eq. 4 (Chen's form of Peters-HaQuang), s, acting on
/// the wind-axis components `(v0, v1s, v1c)`:
///
/// ```text
///       | 4R/(3 pi v_T)            0                            -R tan(chi/2)/(12 v_m)        |
/// tau = | 0                        64R/(45 pi v_m (1+cos chi))   0                            |
///       | 5R tan(chi/2)/(8 v_T)    0                             64R cos chi/(45 pi v_m (1+cos chi)) |
/// ```
///
/// The extracted seed text of Eq. 4 is garbled; this is the product `L M` of the gain matrix
/// of Eq. 5 (as [`static_inflow`] implements it, normalised by `rho pi R^3`) and the
/// Peters-HaQuang apparent mass `M = rho pi R^3 diag(8/(3 pi), -16 R/(45 pi), -16 R/(45 pi))`
/// (the moment rows carry the extra `R`), which
/// reproduces every legible entry of Eq. 4, the sign of the `(1,3)` entry included (tested).
pub fn time_constants(wake: Wake, radius_m: f64) -> [[f64; 3]; 3] {
    let r = radius_m;
    let chi = wake.skew_rad;
    let vt = wake.v_t_m_s;
    let vm = if wake.v_m_m_s.abs() < 1e-9 {
        1e-9f64.copysign(wake.v_m_m_s)
    } else {
        wake.v_m_m_s
    };
    let t = (chi / 2.0).tan();
    let harmonic = 64.0 * r / (45.0 * PI * vm * (1.0 + chi.cos()));
    [
        [4.0 * r / (3.0 * PI * vt), 0.0, -r * t / (12.0 * vm)],
        [0.0, harmonic, 0.0],
        [5.0 * r * t / (8.0 * vt), 0.0, harmonic * chi.cos()],
    ]
}

/// Dynamic inflow (seed 001 Eq. 3): `tau d/dt v = -v + L F`, with `L F` the equilibrium
/// inflow of the present loads ([`static_inflow`]). Returns `d/dt (v0, v1s, v1c)` in hub axes,
/// m/s^2, for the present inflow `current` and the equilibrium `target`, both in hub axes; the
/// matrix is applied in wind axes.
pub fn inflow_rate(
    current: Inflow,
    target: Inflow,
    hub: HubVelocity,
    wake: Wake,
    radius_m: f64,
) -> Inflow {
    let (sw, cw) = wind_azimuth(hub).sin_cos();
    let to_wind = |v: Inflow| [v.v0, v.v1s * cw + v.v1c * sw, -v.v1s * sw + v.v1c * cw];
    let (c, t) = (to_wind(current), to_wind(target));
    let d = [t[0] - c[0], t[1] - c[1], t[2] - c[2]];
    let tau = time_constants(wake, radius_m);
    // v1s decouples; (v0, v1c) is a 2x2 system.
    let v1s_dot = d[1] / tau[1][1];
    let det = tau[0][0] * tau[2][2] - tau[0][2] * tau[2][0];
    let v0_dot = (tau[2][2] * d[0] - tau[0][2] * d[2]) / det;
    let v1c_dot = (-tau[2][0] * d[0] + tau[0][0] * d[2]) / det;
    Inflow {
        v0: v0_dot,
        v1s: v1s_dot * cw - v1c_dot * sw,
        v1c: v1s_dot * sw + v1c_dot * cw,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hover_reduces_to_momentum_theory() {
        // Hover: v0 = sqrt(T / (2 rho A)) at the fixed point.
        let (t, rho, r) = (10_000.0, 1.225, 5.0);
        let vh = (t / (2.0 * rho * PI * r * r)).sqrt();
        let loads = DrivingLoads {
            thrust_n: t,
            roll_n_m: 0.0,
            pitch_n_m: 0.0,
        };
        let (inflow, w) = static_inflow(
            loads,
            HubVelocity::default(),
            vh,
            rho,
            r,
            (SkewConvention::Signed, true),
        );
        assert!((inflow.v0 - vh).abs() < 1e-12);
        assert_eq!((inflow.v1s, inflow.v1c), (0.0, 0.0));
        assert!((w.v_t_m_s - vh).abs() < 1e-12);
    }

    /// Where the flow through the disc changes direction (`d = v0 - w_hub` through zero at 30
    /// m/s in-plane), the geometric and modulus forms move by no more than the flow does
    /// (continuous), and the signed form jumps by 180 deg (seed 001's form is discontinuous
    /// there, and says so). In upflow the geometric angle is 180 deg less the modulus one, the
    /// signed angle minus it.
    #[test]
    fn the_skew_forms_where_the_flow_changes_direction() {
        let at = |d: f64, skew| {
            wake(
                HubVelocity {
                    u: 30.0,
                    v: 0.0,
                    w: 2.0 - d,
                },
                2.0,
                skew,
            )
            .skew_rad
        };
        let eps = 1e-7;
        for skew in [SkewConvention::Geometric, SkewConvention::Modulus] {
            let jump = (at(eps, skew) - at(-eps, skew)).abs();
            assert!(jump < 1e-8, "{skew:?}: {jump}");
            assert!((at(0.0, skew) - PI / 2.0).abs() < 1e-12);
        }
        let jump = at(eps, SkewConvention::Signed) - at(-eps, SkewConvention::Signed);
        assert!((jump - PI).abs() < 1e-6, "signed: {jump}");
        for d in [-5.0, -0.5] {
            let (s, g, m) = (
                at(d, SkewConvention::Signed),
                at(d, SkewConvention::Geometric),
                at(d, SkewConvention::Modulus),
            );
            assert!(
                (g - (PI - m)).abs() < 1e-12 && (s + m).abs() < 1e-12,
                "{s} {g} {m}"
            );
            assert!(g > PI / 2.0 && s < 0.0 && m < PI / 2.0);
        }
        for d in [0.5, 5.0] {
            let s = at(d, SkewConvention::Signed);
            assert!((at(d, SkewConvention::Geometric) - s).abs() < 1e-12);
            assert!((at(d, SkewConvention::Modulus) - s).abs() < 1e-12);
        }
    }

    #[test]
    fn skew_conventions_differ_only_in_autorotation() {
        let hub = HubVelocity {
            u: 30.0,
            v: 0.0,
            w: -2.0,
        };
        let a = wake(hub, 3.0, SkewConvention::Signed);
        let b = wake(hub, 3.0, SkewConvention::Modulus);
        assert!((a.skew_rad - b.skew_rad).abs() < 1e-15 && a.skew_rad > 0.0);
        // Flow up through the disc (w_hub > v0): Eq. 5 gives chi < 0, Eq. 6 chi > 0.
        let up = HubVelocity {
            u: 30.0,
            v: 0.0,
            w: 5.0,
        };
        let a = wake(up, 2.0, SkewConvention::Signed);
        let b = wake(up, 2.0, SkewConvention::Modulus);
        assert!(a.skew_rad < 0.0 && b.skew_rad > 0.0);
        assert!((a.skew_rad.abs() - b.skew_rad).abs() < 1e-15);
    }

    #[test]
    fn moments_drive_the_harmonics_with_the_right_signs() {
        // A nose-up pitching moment (more lift at the front, psi = 180 deg) gives more downwash
        // at the front: v1c < 0. A right-wing-down rolling moment (more lift on the left,
        // psi = 270 deg) gives v1s < 0.
        let moments = |hub: HubVelocity, roll_n_m: f64, pitch_n_m: f64| {
            let loads = DrivingLoads {
                thrust_n: 0.0,
                roll_n_m,
                pitch_n_m,
            };
            static_inflow(loads, hub, 2.0, 1.225, 5.0, (SkewConvention::Signed, true))
        };
        let hub = HubVelocity {
            u: 40.0,
            v: 0.0,
            w: 0.0,
        };
        let (p, _) = moments(hub, 0.0, 1000.0);
        assert!(p.v1c < 0.0);
        let (r, _) = moments(hub, 1000.0, 0.0);
        assert!(r.v1s < 0.0);
        // The same physics seen from a hub moving to starboard (wind axes turned by 90 deg):
        // the wind-axis pitching moment is -L, and the front of the wind frame is hub azimuth
        // 90 deg, so the extra downwash there appears as v1s = -v1c(forward case) > 0.
        let side = HubVelocity {
            u: 0.0,
            v: 40.0,
            w: 0.0,
        };
        let (s, _) = moments(side, -1000.0, 0.0);
        assert!(
            (s.v1s + p.v1c).abs() < 1e-12 && s.v1c.abs() < 1e-12,
            "{s:?} vs {p:?}"
        );
    }

    /// Eq. 4 is `L M`: the gains of Eq. 5 (probed from [`static_inflow`] with unit loads,
    /// scaled by `rho pi R^3`) times the apparent mass `diag(8/(3 pi), -16 R/(45 pi), -16 R/(45 pi))`.
    /// In hover `tau_11 = 4 R / (3 pi v_h)`, the Pitt-Peters value. A step away from the
    /// equilibrium decays with the rate the matrix gives.
    #[test]
    fn time_constants_are_the_gains_times_the_apparent_mass() {
        let (rho, r) = (1.1, 4.1);
        for (hub, v0, skew) in [
            (
                HubVelocity {
                    u: 35.0,
                    v: 0.0,
                    w: 3.0,
                },
                2.0,
                SkewConvention::Signed,
            ),
            (
                HubVelocity {
                    u: 20.0,
                    v: 10.0,
                    w: -1.0,
                },
                4.0,
                SkewConvention::Signed,
            ),
            (
                HubVelocity {
                    u: 25.0,
                    v: 0.0,
                    w: 6.0,
                },
                2.5,
                SkewConvention::Modulus,
            ),
        ] {
            let wk = wake(hub, v0, skew);
            let psi_w = hub.v.atan2(hub.u);
            let (sw, cw) = psi_w.sin_cos();
            // Columns of L in wind axes: unit thrust, unit wind-axis roll, unit wind-axis pitch.
            let probe = |t: f64, l_w: f64, m_w: f64| {
                let loads = DrivingLoads {
                    thrust_n: t,
                    roll_n_m: l_w * cw - m_w * sw,
                    pitch_n_m: l_w * sw + m_w * cw,
                };
                let (v, _) = static_inflow(loads, hub, v0, rho, r, (skew, true));
                [v.v0, v.v1s * cw + v.v1c * sw, -v.v1s * sw + v.v1c * cw]
            };
            let cols = [
                probe(1.0, 0.0, 0.0),
                probe(0.0, 1.0, 0.0),
                probe(0.0, 0.0, 1.0),
            ];
            let m = [
                8.0 / (3.0 * PI),
                -16.0 * r / (45.0 * PI),
                -16.0 * r / (45.0 * PI),
            ];
            let tau = time_constants(wk, r);
            let scale = rho * PI * r.powi(3);
            for i in 0..3 {
                for j in 0..3 {
                    let lm = scale * cols[j][i] * m[j];
                    assert!(
                        (tau[i][j] - lm).abs() < 1e-12 * (1.0 + lm.abs()),
                        "tau[{i}][{j}] = {} vs L M = {lm}",
                        tau[i][j]
                    );
                }
            }
            // Relaxation: the rate solves tau v_dot = target - current.
            let current = Inflow {
                v0: 1.0,
                v1s: 0.3,
                v1c: -0.2,
            };
            let target = Inflow {
                v0: 2.0,
                v1s: -0.1,
                v1c: 0.4,
            };
            let rate = inflow_rate(current, target, hub, wk, r);
            let wind = |v: Inflow| [v.v0, v.v1s * cw + v.v1c * sw, -v.v1s * sw + v.v1c * cw];
            let (rd, d) = (wind(rate), {
                let (c, t) = (wind(current), wind(target));
                [t[0] - c[0], t[1] - c[1], t[2] - c[2]]
            });
            for i in 0..3 {
                let lhs: f64 = (0..3).map(|j| tau[i][j] * rd[j]).sum();
                assert!((lhs - d[i]).abs() < 1e-12, "row {i}: {lhs} vs {}", d[i]);
            }
        }
        let vh = 9.0;
        let hover = time_constants(wake(HubVelocity::default(), vh, SkewConvention::Signed), r);
        assert!((hover[0][0] - 4.0 * r / (3.0 * PI * vh)).abs() < 1e-12);
        assert!(hover[0][2].abs() < 1e-15 && hover[2][0].abs() < 1e-15);
    }
}
