//! Airframe aerodynamics: body-axis force and moment coefficients from two-dimensional tables
//! in angle of attack and sideslip (seed 000 Sec. III, seed 001 Table 1), plus a tailplane and
//! fin as lifting surfaces in their local flow.
//!
//! Coefficients are on the dynamic pressure of the free stream, a reference area, and a
//! reference length (pitch) or span (roll, yaw), about a reference point; the loads are moved
//! to the centre of mass. The side force may act at a point of its own, the centre of the
//! pod's side area (`side_force_centre_m`): then the `cl` and `cn` tables hold only the moments
//! the side force does not make.
//!
//! A surface may sit partly in the propeller's slipstream ([`Slipstream`]): on that fraction
//! of its area the air arrives faster along the shaft, by the momentum-theory excess (the
//! induced velocity at the disc, growing to twice it far behind, as an actuator disc's does
//! along its axis), and turning with the propeller's swirl (the torque's angular momentum, as a
//! solid-body rotation: linear across the slipstream, so that its value at a surface's centre
//! is its mean over a surface centred there, which a free vortex's is not near the shaft; this
//! is a choice for a one-point surface, not a claim about the swirl's profile). Slipstream and
//! free stream are blended by area, velocity by velocity, so the surface sees a higher dynamic
//! pressure and a flow turned toward the shaft. The slipstream is taken along the shaft: its
//! drift with the sideslip or the angle of attack before it reaches the tail is not modelled.
//! Where the airframe ahead blocks the propeller (seed 000's blockage), the air reaches the disc
//! slower than the free stream, and the jet leaves at that speed plus the induced velocity's
//! growth: its excess over the free stream is the induced growth less the blocked share of the
//! free stream's axial speed at the disc (the same speed the propeller sees before blockage).
//!
//! A surface's `dynamic_pressure_ratio` scales the loads of its part outside the slipstream:
//! the share of the free stream's dynamic pressure that reaches it past the airframe ahead
//! (DATCOM's `q_v / q`; 1: all of it). The part in the slipstream meets the propeller's jet.
//!
//! The pod's potential flow in sideslip makes a couple of its own, Munk's (`munk_yaw_m3`): a
//! body of revolution along x moving with `(u_p, v_p)` at its centroid through still air
//! carries the momentum of its apparent masses, `P = rho (A11 u_p, A22 v_p)` with `A11 = k1 Vol`
//! (`munk_axial_m3`) and `A22 = A11 + K`, `K = (k2 - k1) Vol` (Munk 1924;
//! [`crate::estimate::body`]). Kirchhoff's equations for steady motion give the couple `-rho K
//! u_p v_p` about the centroid, which yaws its nose away from the wind, and, when it turns at
//! yaw rate `r`, the force `-r x P` at the centroid (`r A22 v_p` along x, `-r A11 u_p` across).
//! The centroid (`munk_centre_m`) is not the centre of mass: its velocity `v_p = v + x_p r`
//! carries the yaw rate, and the force's arm adds `-A11 rho u x_p r`, so the pod gives `N_r =
//! -k2 rho Vol u x_p` as well as `N_v = -K rho u`. The apparent masses' inertia (their
//! accelerations) is left out, a small share of the aircraft's mass and inertia. `K` is a
//! parameter rather than part of the `cn` table so that its estimated range (separation gives
//! part of it back) can be sampled; the pod's pitching counterpart is in the `cm` table, where
//! the aircraft files put their pod's instability in pitch.
//!
//! `alpha = atan2(w, u)`, `beta = asin(v / V)` of the air-relative velocity at the centre of
//! mass (body axes: x forward, y starboard, z down). Angles outside a table are an error naming
//! the table, never a silent clamp.

use crate::components::rigid_body::Loads;
use serde::Serialize;
use std::f64::consts::PI;
use thiserror::Error;

/// A table in angle of attack (rows) and sideslip (columns), degrees; bilinear interpolation.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table2 {
    pub alpha_deg: Vec<f64>,
    pub beta_deg: Vec<f64>,
    /// `values[i][j]` at `alpha_deg[i]`, `beta_deg[j]`.
    pub values: Vec<Vec<f64>>,
}

/// A lifting surface (tailplane or fin).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Surface {
    /// Position of its aerodynamic centre, body axes from the datum, m.
    pub position_m: [f64; 3],
    pub area_m2: f64,
    pub lift_slope_per_rad: f64,
    /// Incidence to the body x axis (positive leading edge up for a tailplane, left for a fin).
    pub incidence_rad: f64,
    /// Lift stays at its value here beyond it.
    pub stall_alpha_rad: f64,
    pub cd0: f64,
    /// Change of the surface's effective angle of attack per unit deflection of its control
    /// surface (flap effectiveness, 0 with no control surface). A positive deflection (rudder
    /// trailing edge to starboard, elevator trailing edge down) adds to the angle: for a
    /// surface behind the c.g., a yawing moment to starboard or a nose-down pitching moment.
    pub control_effectiveness: f64,
    /// Fraction of its area in the propeller's slipstream, 0 to 1.
    pub slipstream_fraction: f64,
    /// Share of the free stream's flow angle at the c.g. that the airframe ahead turns away
    /// before the surface: the sidewash gradient `d sigma / d beta` of a fin behind a pod, the
    /// downwash gradient `d epsilon / d alpha` of a tailplane (0: none). It acts on the
    /// free stream's angle only, not on the flow the body's rotation makes at the surface.
    pub wash_gradient: f64,
    /// The dynamic pressure at the part of the surface outside the slipstream over what it
    /// would be with nothing ahead of it (DATCOM's `q_v / q`, the airframe's wakes; 1: none), a
    /// factor on that part's loads (the part in the slipstream meets the propeller's).
    pub dynamic_pressure_ratio: f64,
}

/// The propeller's slipstream, as the tail surfaces meet it (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Slipstream {
    /// Centre of the propeller disc, body axes from the datum, m.
    pub disc_centre_m: [f64; 3],
    pub disc_radius_m: f64,
    /// Momentum theory's induced velocity at the disc, m/s (negative when the propeller
    /// windmills and slows the air).
    pub induced_m_s: f64,
    /// The swirl's angular velocity, rad/s, positive right-handed about body x (a propeller
    /// turning clockwise seen from behind).
    pub swirl_rad_s: f64,
    /// The axial airspeed reaching the disc, m/s: the free stream's there, less what the
    /// airframe ahead blocks.
    pub disc_airspeed_m_s: f64,
}

impl Slipstream {
    /// The slipstream of a propeller of radius `disc_radius_m` centred at `disc_centre_m`,
    /// turning right-handed about body x (`sense` +1, clockwise seen from behind) or
    /// left-handed (-1), with the axial speed `disc_airspeed_m_s` reaching the disc, the induced
    /// velocity `induced_m_s` and the absorbed torque `torque_n_m`.
    ///
    /// The swirl carries the torque's angular momentum away: with the mass flow through the
    /// disc `rho (V + v) dA` and `v_theta = w r`, `Q = rho (V + v) w pi R^4 / 2`.
    pub fn of_propeller(
        disc_centre_m: [f64; 3],
        disc_radius_m: f64,
        sense: f64,
        (disc_airspeed_m_s, induced_m_s): (f64, f64),
        torque_n_m: f64,
        density_kg_m3: f64,
    ) -> Self {
        let r2 = disc_radius_m * disc_radius_m;
        let flux = density_kg_m3 * (disc_airspeed_m_s + induced_m_s) * PI * r2 * r2 / 2.0;
        let swirl_rad_s = if flux > 1e-9 {
            sense * torque_n_m / flux
        } else {
            0.0
        };
        Self {
            disc_centre_m,
            disc_radius_m,
            induced_m_s,
            swirl_rad_s,
            disc_airspeed_m_s,
        }
    }

    /// The velocity of the slipstream's air relative to the free stream at `point_m` (body
    /// axes from the datum), m/s, where the free stream's axial speed at the disc is
    /// `free_axial_m_s` (unblocked, the disc's own airspeed): the excess along -x from the disc's
    /// plane aft, and the swirl. Zero ahead of the disc.
    pub fn velocity_at(&self, point_m: [f64; 3], free_axial_m_s: f64) -> [f64; 3] {
        let behind = self.disc_centre_m[0] - point_m[0];
        if behind <= 0.0 {
            return [0.0; 3];
        }
        let r = self.disc_radius_m;
        // Without blockage the two speeds are one and the same number: the excess is the
        // induced velocity's growth alone.
        let blocked = free_axial_m_s - self.disc_airspeed_m_s;
        let excess = self.induced_m_s * (1.0 + behind / (behind * behind + r * r).sqrt()) - blocked;
        let (dy, dz) = (
            point_m[1] - self.disc_centre_m[1],
            point_m[2] - self.disc_centre_m[2],
        );
        // Beyond the slipstream's edge the swirl is held at the edge's (a surface there is
        // outside it, and its slipstream fraction says how much).
        let radius = (dy * dy + dz * dz).sqrt();
        let k = self.swirl_rad_s * if radius > r { r / radius } else { 1.0 };
        // w x r with w along +x: (0, -dz, dy).
        [-excess, -k * dz, k * dy]
    }
}

/// The airframe.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Airframe {
    pub reference_area_m2: f64,
    pub reference_length_m: f64,
    pub reference_span_m: f64,
    /// Moment reference point, body axes from the datum, m.
    pub reference_point_m: [f64; 3],
    /// Where the side force (`cy`) acts, body axes from the datum, m; `None`: the reference
    /// point. In sideslip, a side area below the centre of mass rolls the aircraft toward the
    /// wind (positive `L_v`, as flight's), one above it away from the wind; one ahead of the
    /// centre of mass yaws the nose away from the wind (less weathercock stability).
    pub side_force_centre_m: Option<[f64; 3]>,
    /// Body-axis coefficients: `cx, cy, cz, cl, cm, cn`.
    pub coefficients: [Table2; 6],
    /// The pod's Munk couple `K = (k2 - k1) Vol`, m^3: a yawing moment `-K rho u_p v_p` about
    /// its centroid (module docs; 0: none).
    pub munk_yaw_m3: f64,
    /// The pod's axial apparent volume `k1 Vol`, m^3: the momentum along its axis that its
    /// turning makes a side force (module docs; 0: none).
    pub munk_axial_m3: f64,
    /// The pod's centroid, where its apparent masses move, body axes from the datum, m.
    pub munk_centre_m: [f64; 3],
    pub tailplane: Option<Surface>,
    pub fin: Option<Surface>,
}

/// Why the loads cannot be formed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AirframeError {
    #[error("table `{table}`: {what} = {value:.3} deg is outside the table's [{lo}, {hi}] deg")]
    OutOfRange {
        table: &'static str,
        what: &'static str,
        value: f64,
        lo: f64,
        hi: f64,
    },
    #[error(
        "table `{0}`: the axes must rise strictly and the values be one row per alpha of one value per beta, all finite"
    )]
    Table(&'static str),
    #[error("the airspeed is zero: the angles of attack and sideslip are undefined")]
    NoAirspeed,
    #[error(
        "{0}: areas, lift slope and stall angle must be positive, drag non-negative, all finite"
    )]
    Surface(&'static str),
}

const NAMES: [&str; 6] = ["cx", "cy", "cz", "cl", "cm", "cn"];

impl Table2 {
    fn validate(&self, name: &'static str) -> Result<(), AirframeError> {
        let rising = |v: &[f64]| {
            !v.is_empty() && v.windows(2).all(|w| w[1] > w[0]) && v.iter().all(|x| x.is_finite())
        };
        let ok = rising(&self.alpha_deg)
            && rising(&self.beta_deg)
            && self.values.len() == self.alpha_deg.len()
            && self
                .values
                .iter()
                .all(|r| r.len() == self.beta_deg.len() && r.iter().all(|x| x.is_finite()));
        if ok {
            Ok(())
        } else {
            Err(AirframeError::Table(name))
        }
    }

    fn at(&self, name: &'static str, alpha_deg: f64, beta_deg: f64) -> Result<f64, AirframeError> {
        let locate =
            |axis: &[f64], x: f64, what: &'static str| -> Result<(usize, f64), AirframeError> {
                let (lo, hi) = (axis[0], axis[axis.len() - 1]);
                if !(lo..=hi).contains(&x) {
                    return Err(AirframeError::OutOfRange {
                        table: name,
                        what,
                        value: x,
                        lo,
                        hi,
                    });
                }
                if axis.len() == 1 {
                    return Ok((0, 0.0));
                }
                let i = axis.partition_point(|&a| a <= x).clamp(1, axis.len() - 1) - 1;
                Ok((i, (x - axis[i]) / (axis[i + 1] - axis[i])))
            };
        let (i, fa) = locate(&self.alpha_deg, alpha_deg, "alpha")?;
        let (j, fb) = locate(&self.beta_deg, beta_deg, "beta")?;
        let v = |i: usize, j: usize| {
            self.values[i.min(self.alpha_deg.len() - 1)][j.min(self.beta_deg.len() - 1)]
        };
        let row = |i: usize| v(i, j) * (1.0 - fb) + v(i, j + 1) * fb;
        Ok(row(i) * (1.0 - fa) + row(i + 1) * fa)
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Airframe {
    /// Checks the tables and surfaces.
    pub fn validate(&self) -> Result<(), AirframeError> {
        for (t, n) in self.coefficients.iter().zip(NAMES) {
            t.validate(n)?;
        }
        for (sf, name) in [(&self.tailplane, "tailplane"), (&self.fin, "fin")] {
            if let Some(sf) = sf {
                let ok = sf.area_m2 > 0.0
                    && sf.lift_slope_per_rad > 0.0
                    && sf.stall_alpha_rad > 0.0
                    && sf.cd0 >= 0.0
                    && sf.position_m.iter().all(|x| x.is_finite())
                    && sf.incidence_rad.is_finite()
                    && sf.control_effectiveness.is_finite()
                    && (0.0..=1.0).contains(&sf.slipstream_fraction)
                    && sf.wash_gradient.is_finite()
                    && sf.wash_gradient < 1.0
                    && sf.dynamic_pressure_ratio.is_finite()
                    && sf.dynamic_pressure_ratio > 0.0;
                if !ok {
                    return Err(AirframeError::Surface(name));
                }
            }
        }
        let refs = [
            self.reference_area_m2,
            self.reference_length_m,
            self.reference_span_m,
        ];
        if refs.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(AirframeError::Surface("reference area and lengths"));
        }
        if !(self.munk_yaw_m3.is_finite() && self.munk_yaw_m3 >= 0.0) {
            return Err(AirframeError::Surface("the Munk couple (munk_yaw_m3)"));
        }
        if !(self.munk_axial_m3.is_finite() && self.munk_axial_m3 >= 0.0) {
            return Err(AirframeError::Surface(
                "the pod's axial apparent volume (munk_axial_m3)",
            ));
        }
        let points = [
            Some(self.reference_point_m),
            self.side_force_centre_m,
            Some(self.munk_centre_m),
        ];
        if points.iter().flatten().flatten().any(|x| !x.is_finite()) {
            return Err(AirframeError::Surface(
                "reference point and side-force centre",
            ));
        }
        Ok(())
    }

    /// Loads about the centre of mass for the air-relative velocity `uvw` (m/s) and body rates
    /// `pqr` (rad/s) at the centre of mass `cg_m` (body axes from the datum), with the
    /// tailplane's and fin's control surfaces at `deflections_rad` (elevator, rudder), and the
    /// propeller's slipstream if there is one.
    pub fn loads(
        &self,
        uvw: [f64; 3],
        pqr: [f64; 3],
        density_kg_m3: f64,
        cg_m: [f64; 3],
        deflections_rad: [f64; 2],
        slipstream: Option<&Slipstream>,
    ) -> Result<Loads, AirframeError> {
        let speed = (uvw[0] * uvw[0] + uvw[1] * uvw[1] + uvw[2] * uvw[2]).sqrt();
        if speed.is_nan() || speed <= 1e-9 {
            return Err(AirframeError::NoAirspeed);
        }
        let alpha = uvw[2].atan2(uvw[0]).to_degrees();
        let beta = (uvw[1] / speed).asin().to_degrees();
        let q = 0.5 * density_kg_m3 * speed * speed;
        let mut c = [0.0; 6];
        for (k, (t, n)) in self.coefficients.iter().zip(NAMES).enumerate() {
            c[k] = t.at(n, alpha, beta)?;
        }
        let s = self.reference_area_m2;
        let f = [q * s * c[0], q * s * c[1], q * s * c[2]];
        let m_ref = [
            q * s * self.reference_span_m * c[3],
            q * s * self.reference_length_m * c[4],
            q * s * self.reference_span_m * c[5],
        ];
        // The drag and normal force act at the reference point, the side force at its own
        // centre (the reference point unless one is given).
        let arm_from = |p: [f64; 3]| [p[0] - cg_m[0], p[1] - cg_m[1], p[2] - cg_m[2]];
        let side_centre = self.side_force_centre_m.unwrap_or(self.reference_point_m);
        let along = cross(arm_from(self.reference_point_m), [f[0], 0.0, f[2]]);
        let side = cross(arm_from(side_centre), [0.0, f[1], 0.0]);
        let transfer = [along[0] + side[0], along[1] + side[1], along[2] + side[2]];
        // The pod's apparent masses (module docs): Munk's couple about its centroid, at the
        // centroid's velocity, and the force its yawing makes of their momentum, there.
        let pod_arm = arm_from(self.munk_centre_m);
        let at_pod = cross(pqr, pod_arm);
        let (u_p, v_p) = (uvw[0] + at_pod[0], uvw[1] + at_pod[1]);
        let (a11, a22) = (
            density_kg_m3 * self.munk_axial_m3,
            density_kg_m3 * (self.munk_axial_m3 + self.munk_yaw_m3),
        );
        let munk = -(a22 - a11) * u_p * v_p;
        let pod_force = [pqr[2] * a22 * v_p, -pqr[2] * a11 * u_p, 0.0];
        let pod_moment = cross(pod_arm, pod_force);
        let mut total = [
            f[0] + pod_force[0],
            f[1] + pod_force[1],
            f[2],
            m_ref[0] + transfer[0] + pod_moment[0],
            m_ref[1] + transfer[1] + pod_moment[1],
            m_ref[2] + transfer[2] + pod_moment[2] + munk,
        ];
        for (surface, vertical, deflection) in [
            (&self.tailplane, false, deflections_rad[0]),
            (&self.fin, true, deflections_rad[1]),
        ] {
            if let Some(sf) = surface {
                // The slipstream's velocity over the surface's share in it, and that share
                // (none without a slipstream: all of the surface is outside it then).
                let (stream, inside) = match slipstream {
                    Some(st) if sf.slipstream_fraction > 0.0 => {
                        // The free stream's axial speed at the disc, as the propeller takes it.
                        let at_disc = cross(pqr, sub(st.disc_centre_m, cg_m));
                        let free_axial = (uvw[0] + at_disc[0]).max(0.0);
                        let jet = st.velocity_at(sf.position_m, free_axial);
                        (
                            jet.map(|c| sf.slipstream_fraction * c),
                            sf.slipstream_fraction,
                        )
                    }
                    _ => ([0.0; 3], 0.0),
                };
                let flow = (uvw, pqr, density_kg_m3);
                let (fs, ms) =
                    surface_loads(sf, vertical, flow, (stream, inside), cg_m, deflection);
                for k in 0..3 {
                    total[k] += fs[k];
                    total[k + 3] += ms[k];
                }
            }
        }
        Ok(Loads {
            x_n: total[0],
            y_n: total[1],
            z_n: total[2],
            l_n_m: total[3],
            m_n_m: total[4],
            n_n_m: total[5],
        })
    }
}

/// A surface's force and moment about the centre of mass: lift normal to its local flow in its
/// plane (x-z for the tailplane, x-y for the fin), drag along the local flow. `stream` is the
/// velocity of the air at the surface relative to the free stream (the slipstream's share),
/// and `inside` the share of its area in the slipstream: the dynamic-pressure ratio acts on
/// the rest alone (the slipstream's dynamic pressure is the propeller's).
fn surface_loads(
    s: &Surface,
    vertical: bool,
    (uvw, pqr, rho): ([f64; 3], [f64; 3], f64),
    (stream, inside): ([f64; 3], f64),
    cg_m: [f64; 3],
    deflection_rad: f64,
) -> ([f64; 3], [f64; 3]) {
    let arm = [
        s.position_m[0] - cg_m[0],
        s.position_m[1] - cg_m[1],
        s.position_m[2] - cg_m[2],
    ];
    let rot = cross(pqr, arm);
    // The surface's velocity relative to the air around it, the free stream's flow angle in
    // the surface's plane reduced by the wash ahead of it.
    let normal = if vertical { 1 } else { 2 };
    let mut vl = [
        uvw[0] + rot[0] - stream[0],
        uvw[1] + rot[1] - stream[1],
        uvw[2] + rot[2] - stream[2],
    ];
    vl[normal] -= s.wash_gradient * uvw[normal];
    // In-plane components: (along x, normal) with normal = z (tailplane) or y (fin).
    let (ux, un) = if vertical {
        (vl[0], vl[1])
    } else {
        (vl[0], vl[2])
    };
    let v2 = ux * ux + un * un;
    if v2 <= 0.0 {
        return ([0.0; 3], [0.0; 3]);
    }
    let v = v2.sqrt();
    // Flow angle in the surface's plane; a fin's incidence is taken leading edge to port.
    let angle = un.atan2(ux)
        + if vertical {
            -s.incidence_rad
        } else {
            s.incidence_rad
        }
        + s.control_effectiveness * deflection_rad;
    let a = angle.clamp(-s.stall_alpha_rad, s.stall_alpha_rad);
    // inside + (1 - inside) eta, written so that eta = 1 gives exactly 1.
    let ratio = 1.0 - (1.0 - inside) * (1.0 - s.dynamic_pressure_ratio);
    let q = 0.5 * rho * v2 * s.area_m2 * ratio;
    let (lift, drag) = (q * s.lift_slope_per_rad * a, q * s.cd0);
    // Lift opposes the normal flow (pushes the surface against it), drag along the flow.
    let fx = (lift * un - drag * ux) / v;
    let fn_ = (-lift * ux - drag * un) / v;
    let f = if vertical {
        [fx, fn_, 0.0]
    } else {
        [fx, 0.0, fn_]
    };
    (f, cross(arm, f))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn zero_table() -> Table2 {
        Table2 {
            alpha_deg: vec![-30.0, 30.0],
            beta_deg: vec![-30.0, 30.0],
            values: vec![vec![0.0, 0.0], vec![0.0, 0.0]],
        }
    }

    /// A test airframe: no body aerodynamics, a tailplane 3 m behind and a fin 3 m behind and
    /// 0.5 m above the c.g. (light-gyroplane proportions, estimated).
    fn airframe() -> Airframe {
        let surface = |pos: [f64; 3], area: f64| Surface {
            position_m: pos,
            area_m2: area,
            lift_slope_per_rad: 3.5,
            incidence_rad: 0.0,
            stall_alpha_rad: 0.3,
            cd0: 0.01,
            control_effectiveness: 0.5,
            slipstream_fraction: 0.0,
            wash_gradient: 0.0,
            dynamic_pressure_ratio: 1.0,
        };
        Airframe {
            reference_area_m2: 1.0,
            reference_length_m: 1.0,
            reference_span_m: 1.0,
            reference_point_m: [0.0; 3],
            side_force_centre_m: None,
            coefficients: std::array::from_fn(|_| zero_table()),
            munk_yaw_m3: 0.0,
            munk_axial_m3: 0.0,
            munk_centre_m: [0.0; 3],
            tailplane: Some(surface([-3.0, 0.0, 0.0], 0.6)),
            fin: Some(surface([-3.0, 0.0, -0.5], 0.5)),
        }
    }

    #[test]
    fn tables_interpolate_and_refuse_to_extrapolate() {
        let t = Table2 {
            alpha_deg: vec![0.0, 10.0],
            beta_deg: vec![-10.0, 10.0],
            values: vec![vec![0.0, 1.0], vec![2.0, 3.0]],
        };
        assert!((t.at("cz", 5.0, 0.0).unwrap() - 1.5).abs() < 1e-15);
        assert!(matches!(
            t.at("cz", 12.0, 0.0),
            Err(AirframeError::OutOfRange { what: "alpha", .. })
        ));
        let bad = Table2 {
            values: vec![vec![0.0, 1.0]],
            ..t
        };
        assert_eq!(bad.validate("cz"), Err(AirframeError::Table("cz")));
    }

    /// A side force acting at its own centre makes the moments a `cl`, `cn` table pair would
    /// have to carry otherwise: `cy = -0.8 sin(beta)` at 0.125 m ahead of and 0.0625 m above
    /// the c.g. is `cl = -0.05 sin(beta)`, `cn = -0.1 sin(beta)` about the c.g. (the VPM M16's
    /// estimated pod, written both ways). Low on the airframe, the same force rolls it the
    /// other way: toward the wind, flight's positive `L_v`.
    #[test]
    fn a_side_force_at_its_own_centre_makes_its_moments() {
        let sine = |k: f64| Table2 {
            alpha_deg: vec![-30.0, 30.0],
            beta_deg: vec![-30.0, -15.0, 0.0, 15.0, 30.0],
            values: vec![
                [-30.0f64, -15.0, 0.0, 15.0, 30.0]
                    .map(|b| k * b.to_radians().sin())
                    .to_vec();
                2
            ],
        };
        let mut tables = airframe();
        tables.tailplane = None;
        tables.fin = None;
        tables.coefficients[1] = sine(-0.8);
        tables.coefficients[3] = sine(-0.05);
        tables.coefficients[5] = sine(-0.1);
        let mut centred = tables.clone();
        centred.coefficients[3] = zero_table();
        centred.coefficients[5] = zero_table();
        centred.side_force_centre_m = Some([0.125, 0.0, -0.0625]);
        let flow = |a: &Airframe, cg: [f64; 3]| {
            a.loads([30.0, 4.0, 1.0], [0.0; 3], 1.2, cg, [0.0; 2], None)
                .unwrap()
        };
        // The three tables are proportional node by node, so their interpolations are too:
        // the two ways agree to rounding, about the datum and about a displaced c.g.
        for cg in [[0.0; 3], [0.1, 0.0, 0.05]] {
            let (t, c) = (flow(&tables, cg), flow(&centred, cg));
            assert!((t.y_n - c.y_n).abs() < 1e-12, "{t:?} {c:?}");
            assert!(
                (t.l_n_m - c.l_n_m).abs() < 1e-9 * t.l_n_m.abs(),
                "{t:?} {c:?}"
            );
            assert!(
                (t.n_n_m - c.n_n_m).abs() < 1e-9 * t.n_n_m.abs(),
                "{t:?} {c:?}"
            );
            assert!(
                (t.m_n_m - c.m_n_m).abs() < 1e-12,
                "pitch unchanged: {t:?} {c:?}"
            );
        }
        let l = flow(&centred, [0.0; 3]);
        assert!(l.y_n < 0.0 && l.l_n_m < 0.0 && l.n_n_m < 0.0, "{l:?}");
        let mut low = centred.clone();
        low.side_force_centre_m = Some([0.125, 0.0, 0.3]);
        let l = flow(&low, [0.0; 3]);
        assert!(
            (l.l_n_m + 0.3 * l.y_n).abs() < 1e-9 && l.l_n_m > 0.0,
            "{l:?}"
        );
        low.side_force_centre_m = Some([f64::NAN, 0.0, 0.0]);
        assert!(low.validate().is_err());
    }

    /// Momentum theory's slipstream: the excess is the induced velocity at the disc and twice
    /// it far behind, nothing ahead; the swirl carries away the torque's angular momentum, and
    /// turns with the propeller.
    #[test]
    fn the_slipstream_carries_the_thrust_and_the_torque() {
        let (rho, v_disc, v0, q, r) = (1.2, 30.0, 5.0, 150.0, 0.75);
        let st = Slipstream::of_propeller([-1.3, 0.0, -0.05], r, 1.0, (v_disc, v0), q, rho);
        let behind = |d: f64, y: f64, z: f64| st.velocity_at([-1.3 - d, y, -0.05 + z], v_disc);
        assert_eq!(st.velocity_at([-1.0, 0.0, 0.0], v_disc), [0.0; 3]);
        assert!((behind(1e-9, 0.0, 0.0)[0] + v0).abs() < 1e-6);
        assert!((behind(1e4, 0.0, 0.0)[0] + 2.0 * v0).abs() < 1e-6);
        // Angular momentum through the disc: rho (V + v) r v_theta over its area (midpoint
        // rule in radius; on the y axis the swirl is along z).
        let n = 20_000;
        let flux: f64 = (0..n)
            .map(|k| {
                let y = (k as f64 + 0.5) / n as f64 * r;
                let v_theta = behind(1e-6, y, 0.0)[2];
                rho * (v_disc + v0) * y * v_theta * 2.0 * PI * y * (r / n as f64)
            })
            .sum();
        assert!((flux - q).abs() < 1e-3 * q, "{flux} vs {q}");
        // Above the shaft a clockwise propeller's swirl (seen from behind) runs to starboard.
        assert!(behind(1.5, 0.0, -0.45)[1] > 0.0);
        let mirror = Slipstream::of_propeller([-1.3, 0.0, -0.05], r, -1.0, (v_disc, v0), q, rho);
        let (a, b) = (
            behind(1.5, 0.0, -0.45),
            mirror.velocity_at([-2.8, 0.0, -0.5], v_disc),
        );
        assert!((a[1] + b[1]).abs() < 1e-12 && a[0] == b[0], "{a:?} {b:?}");
    }

    /// With the propeller blocked (seed 000's total blockage) the jet leaves the disc at the
    /// induced velocity alone: far behind, at twice it, which over a free stream faster than
    /// that is a deficit; half blocked, its excess is the unblocked one less half the free
    /// stream. Unblocked, the free stream's speed at the disc is the disc's own and the excess
    /// is the induced growth, as before.
    #[test]
    fn a_blocked_propellers_jet_leaves_at_the_blocked_speed() {
        let (u, v0, r) = (30.0, 8.0, 0.75);
        let far = [-1e4, 0.0, -0.05];
        for (k, excess) in [(0.0, 2.0 * v0), (0.5, 2.0 * v0 - 15.0), (1.0, 2.0 * v0 - u)] {
            let v_disc = (1.0 - k) * u;
            let st = Slipstream::of_propeller([-1.3, 0.0, -0.05], r, 1.0, (v_disc, v0), 0.0, 1.2);
            let got = -st.velocity_at(far, u)[0];
            assert!((got - excess).abs() < 1e-3, "{k}: {got} against {excess}");
        }
        // Through the airframe's loads: a fin wholly in the slipstream of a totally blocked
        // propeller meets the jet's speed, 2 v0 (the free stream's 30 m/s does not reach it).
        let mut a = airframe();
        a.tailplane = None;
        a.fin.as_mut().unwrap().slipstream_fraction = 1.0;
        a.fin.as_mut().unwrap().position_m = [-600.0, 0.0, -0.05];
        let blocked = Slipstream::of_propeller([-1.3, 0.0, -0.05], r, 1.0, (0.0, v0), 0.0, 1.2);
        let drag = |st: Option<&Slipstream>| {
            a.loads([u, 0.0, 0.0], [0.0; 3], 1.2, [0.0; 3], [0.0; 2], st)
                .unwrap()
                .x_n
        };
        let ratio = drag(Some(&blocked)) / drag(None);
        let expected = (2.0 * v0 / u).powi(2);
        assert!(
            (ratio - expected).abs() < 1e-3,
            "{ratio} against {expected}"
        );
    }

    /// A fin wholly in a developed slipstream meets sideslip and yaw rate at the slipstream's
    /// speed: its dynamic pressure grows as the speed squared and its flow angle falls as the
    /// speed, so `Y_v` and `N_r` grow by the speed ratio. Half in the slipstream, half the
    /// excess.
    #[test]
    fn a_fin_in_the_slipstream_is_stiffer_by_the_speed_ratio() {
        let mut a = airframe();
        a.tailplane = None;
        let (u, v0) = (30.0, 5.0);
        // No swirl, and far enough behind for the excess to be 2 v0 within 2e-6.
        let far = Slipstream::of_propeller([600.0, 0.0, -0.5], 0.75, 1.0, (u, v0), 0.0, 1.2);
        let derivatives = |a: &Airframe, st: Option<&Slipstream>| {
            let at = |v: f64, r: f64| {
                a.loads([u, v, 0.0], [0.0, 0.0, r], 1.2, [0.0; 3], [0.0; 2], st)
                    .unwrap()
            };
            let (h, hr) = (1e-4, 1e-5);
            let y_v = (at(h, 0.0).y_n - at(-h, 0.0).y_n) / (2.0 * h);
            let n_r = (at(0.0, hr).n_n_m - at(0.0, -hr).n_n_m) / (2.0 * hr);
            (y_v, n_r)
        };
        let (y0, n0) = derivatives(&a, None);
        for fraction in [1.0, 0.5] {
            a.fin.as_mut().unwrap().slipstream_fraction = fraction;
            let (y1, n1) = derivatives(&a, Some(&far));
            let ratio = (u + fraction * 2.0 * v0) / u;
            assert!(
                (y1 / y0 - ratio).abs() < 1e-4,
                "{fraction}: Y_v {y1} / {y0}"
            );
            assert!(
                (n1 / n0 - ratio).abs() < 1e-4,
                "{fraction}: N_r {n1} / {n0}"
            );
        }
        a.fin.as_mut().unwrap().slipstream_fraction = 1.5;
        assert!(a.validate().is_err());
    }

    /// The dynamic-pressure ratio is the part of the surface outside the slipstream's (issue
    /// 52, item 3: the estimate defines it there; the slipstream carries its own dynamic
    /// pressure, the propeller's): a fin 0.7 in the slipstream at a ratio of 0.8 keeps
    /// 0.7 + 0.3 x 0.8 = 0.94 of its side force, not 0.8; with no slipstream (the propeller not
    /// modelled) all of the fin is outside it, 0.8.
    #[test]
    fn the_dynamic_pressure_ratio_acts_on_the_surface_outside_the_slipstream() {
        let mut a = airframe();
        a.tailplane = None;
        a.fin.as_mut().unwrap().slipstream_fraction = 0.7;
        let (u, v0) = (30.0, 5.0);
        let st = Slipstream::of_propeller([600.0, 0.0, -0.5], 0.75, 1.0, (u, v0), 0.0, 1.2);
        let y = |a: &Airframe, st: Option<&Slipstream>| {
            a.loads([u, 2.0, 0.0], [0.0; 3], 1.2, [0.0; 3], [0.0; 2], st)
                .unwrap()
                .y_n
        };
        let (whole, whole_free) = (y(&a, Some(&st)), y(&a, None));
        a.fin.as_mut().unwrap().dynamic_pressure_ratio = 0.8;
        let ratio = y(&a, Some(&st)) / whole;
        assert!((ratio - 0.94).abs() < 1e-12, "{ratio}");
        let ratio = y(&a, None) / whole_free;
        assert!((ratio - 0.8).abs() < 1e-12, "{ratio}");
    }

    /// Sidewash ahead of a fin takes its share of the sideslip and none of the yaw rate's flow:
    /// the fin's `Y_v` falls by `1 - d sigma / d beta` and its `N_r` stays.
    #[test]
    fn sidewash_weakens_the_fin_in_sideslip_not_in_yaw() {
        let mut a = airframe();
        a.tailplane = None;
        let derivatives = |a: &Airframe| {
            let at = |v: f64, r: f64| {
                a.loads([30.0, v, 0.0], [0.0, 0.0, r], 1.2, [0.0; 3], [0.0; 2], None)
                    .unwrap()
            };
            let y_v = (at(1e-4, 0.0).y_n - at(-1e-4, 0.0).y_n) / 2e-4;
            let n_r = (at(0.0, 1e-5).n_n_m - at(0.0, -1e-5).n_n_m) / 2e-5;
            (y_v, n_r)
        };
        let (y0, n0) = derivatives(&a);
        a.fin.as_mut().unwrap().wash_gradient = 0.4;
        let (y1, n1) = derivatives(&a);
        assert!((y1 / y0 - 0.6).abs() < 1e-6, "{y1} / {y0}");
        assert!((n1 / n0 - 1.0).abs() < 1e-9, "{n1} / {n0}");
        a.fin.as_mut().unwrap().wash_gradient = 1.0;
        assert!(
            a.validate().is_err(),
            "a fin that sees no sideslip at all is refused"
        );
    }

    /// The pod's Munk couple: `N = -K rho u v`, a pure couple (the same about a displaced
    /// c.g., no force), yawing the nose away from the wind (N < 0 for wind from starboard, where
    /// the fin gives N > 0), and its `N_v` is `-K rho u`. A dynamic-pressure ratio scales a
    /// surface's loads.
    #[test]
    fn the_pods_munk_couple_yaws_it_away_from_the_wind() {
        let mut a = airframe();
        a.tailplane = None;
        a.fin = None;
        a.munk_yaw_m3 = 0.6;
        let (rho, u) = (1.2, 30.0);
        let at = |a: &Airframe, v: f64, cg: [f64; 3]| {
            a.loads([u, v, 1.0], [0.0; 3], rho, cg, [0.0; 2], None)
                .unwrap()
        };
        let l = at(&a, 2.0, [0.0; 3]);
        assert!((l.n_n_m + 0.6 * rho * u * 2.0).abs() < 1e-12, "{l:?}");
        assert!(l.y_n.abs() < 1e-12 && l.l_n_m.abs() < 1e-12 && l.m_n_m.abs() < 1e-12);
        assert_eq!(at(&a, 2.0, [0.3, 0.0, 0.1]), l);
        let n_v = (at(&a, 1e-3, [0.0; 3]).n_n_m - at(&a, -1e-3, [0.0; 3]).n_n_m) / 2e-3;
        assert!((n_v + 0.6 * rho * u).abs() < 1e-9, "{n_v}");
        a.munk_yaw_m3 = -0.1;
        assert!(a.validate().is_err());
        // A fin at 0.8 of the free stream's dynamic pressure: 0.8 of its side force.
        let mut f = airframe();
        f.tailplane = None;
        let y = |f: &Airframe| at(f, 2.0, [0.0; 3]).y_n;
        let whole = y(&f);
        f.fin.as_mut().unwrap().dynamic_pressure_ratio = 0.8;
        assert!((y(&f) / whole - 0.8).abs() < 1e-12);
        f.fin.as_mut().unwrap().dynamic_pressure_ratio = 0.0;
        assert!(f.validate().is_err());
    }

    /// The pod's apparent masses at a centroid ahead of the centre of mass (Kirchhoff's
    /// equations for steady motion): its `N_v` is `-K rho u` and its `N_r` is `-k2 rho Vol u
    /// x_p` (`k2 Vol = K + k1 Vol`), its `Y_r` `-k1 rho Vol u`; with the centroid at the centre of
    /// mass its `N_r` is 0. The old couple, `-K rho u v` at the c.g.'s velocity, gave no `N_r`
    /// and no `Y_r` (issue 52, item 1).
    #[test]
    fn the_pods_apparent_mass_damps_yaw_rate_from_ahead_of_the_cg() {
        let mut a = airframe();
        a.tailplane = None;
        a.fin = None;
        let (k, k1_vol, x_p) = (0.57, 0.135, 0.4);
        a.munk_yaw_m3 = k;
        a.munk_axial_m3 = k1_vol;
        a.munk_centre_m = [x_p, 0.0, 0.0];
        let (rho, u) = (1.16, 31.3);
        let at = |a: &Airframe, v: f64, r: f64| {
            a.loads([u, v, 1.0], [0.0, 0.0, r], rho, [0.0; 3], [0.0; 2], None)
                .unwrap()
        };
        let h = 1e-4;
        let d = |f: &dyn Fn(f64) -> f64| (f(h) - f(-h)) / (2.0 * h);
        let n_v = d(&|v| at(&a, v, 0.0).n_n_m);
        let n_r = d(&|r| at(&a, 0.0, r).n_n_m);
        let y_r = d(&|r| at(&a, 0.0, r).y_n);
        // Central differences of step 1e-4 on loads quadratic in (v, r): exact but for
        // rounding, a few 1e-12 of the loads over 2e-4, well under 1e-7 of the derivatives.
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-7 * y.abs();
        assert!(close(n_v, -k * rho * u), "{n_v}");
        assert!(close(n_r, -(k + k1_vol) * rho * u * x_p), "{n_r}");
        assert!(close(y_r, -k1_vol * rho * u), "{y_r}");
        // About -10 N m s for the VPM M16's pod.
        assert!((-11.0..-9.0).contains(&n_r), "{n_r}");
        a.munk_centre_m = [0.0; 3];
        assert!(d(&|r| at(&a, 0.0, r).n_n_m).abs() < 1e-9);
    }

    #[test]
    fn symmetric_flight_has_no_lateral_loads() {
        let l = airframe()
            .loads([30.0, 0.0, 2.0], [0.0; 3], 1.225, [0.0; 3], [0.0; 2], None)
            .unwrap();
        assert!(
            l.y_n.abs() < 1e-12 && l.l_n_m.abs() < 1e-12 && l.n_n_m.abs() < 1e-12,
            "{l:?}"
        );
    }

    #[test]
    fn the_tail_damps_pitch_and_the_fin_weathercocks() {
        let a = airframe();
        let m = |q: f64| {
            a.loads(
                [30.0, 0.0, 0.0],
                [0.0, q, 0.0],
                1.225,
                [0.0; 3],
                [0.0; 2],
                None,
            )
            .unwrap()
            .m_n_m
        };
        // Nose-up pitch rate: the tail meets the air from below, lifts, and pitches the nose down.
        assert!(m(0.1) < 0.0 && m(-0.1) > 0.0);
        // Angle of attack stability from the tailplane: w > 0 (nose up relative to the flow)
        // gives a nose-down moment.
        let mw = a
            .loads([30.0, 0.0, 1.0], [0.0; 3], 1.225, [0.0; 3], [0.0; 2], None)
            .unwrap()
            .m_n_m;
        assert!(mw < 0.0);
        // Sideslip with the wind from starboard (v > 0): the fin yaws the nose into it, N > 0.
        let nv = a
            .loads([30.0, 1.0, 0.0], [0.0; 3], 1.225, [0.0; 3], [0.0; 2], None)
            .unwrap()
            .n_n_m;
        assert!(nv > 0.0);
        // Yaw rate: damped by the fin.
        let nr = a
            .loads(
                [30.0, 0.0, 0.0],
                [0.0, 0.0, 0.1],
                1.225,
                [0.0; 3],
                [0.0; 2],
                None,
            )
            .unwrap()
            .n_n_m;
        assert!(nr < 0.0);
        // Rudder trailing edge to starboard: nose to starboard.
        let nr = a
            .loads(
                [30.0, 0.0, 0.0],
                [0.0; 3],
                1.225,
                [0.0; 3],
                [0.0, 0.1],
                None,
            )
            .unwrap()
            .n_n_m;
        assert!(nr > 0.0);
        assert_eq!(
            a.loads([0.0; 3], [0.0; 3], 1.225, [0.0; 3], [0.0; 2], None),
            Err(AirframeError::NoAirspeed)
        );
    }
}
