//! The propeller's effect on the flow at the tail, by momentum theory: the slipstream's
//! velocity, radius and dynamic pressure at a surface behind the disc, the share of a surface
//! inside it, and how much of the sideslip the propeller's normal force takes out of the air
//! that passes through it.
//!
//! The slipstream is the one [`crate::components::airframe::Slipstream`] gives the model: the
//! momentum-theory induced velocity `v` at the disc, `T = 2 rho A (V + v) v`, growing along the
//! axis as the vortex cylinder of a uniformly loaded actuator disc makes it on its axis, `v (1 +
//! x / sqrt(x^2 + R^2))` at `x` behind the disc (twice `v` far behind), and taken along the
//! shaft. Its radius follows from continuity, `R sqrt((V + v) / (V + v_x))`.

use super::lifting_surface::Planform;
use super::{Estimate, EstimateError, Method, non_negative, positive};
use serde::Serialize;
use std::f64::consts::PI;

/// The propeller disc: centre in body axes from the datum, m, and radius, m. Its shaft is
/// along body x.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Disc {
    pub centre_m: [f64; 3],
    pub radius_m: f64,
}

/// The propeller's operating point at a flight condition.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OperatingPoint {
    /// The axial airspeed reaching the disc, m/s.
    pub airspeed_m_s: f64,
    pub density_kg_m3: f64,
    pub thrust_n: f64,
    /// The propeller's side force per m/s of sideslip velocity, `dY / dv`, N s/m (negative: it
    /// opposes the sideslip, as a normal force at incidence does).
    pub side_force_per_m_s: f64,
}

/// The slipstream's velocity, radius and dynamic pressure by momentum theory.
pub const MOMENTUM: Method = Method {
    name: "the slipstream by momentum theory",
    source: "actuator-disc momentum theory: T = 2 rho A (V + v) v at the disc; the excess along the shaft v (1 + x / sqrt(x^2 + R^2)) at x behind it (a uniformly loaded disc's vortex cylinder on its axis; twice v far behind); the radius R sqrt((V + v) / (V + v_x)) by continuity; the dynamic pressure ((V + v_x) / V)^2 of the free stream's",
    accuracy: "estimated: the excess from 70 % to 100 % of momentum theory's: its slipstream is uniform, a real one carries the hub's and the pod's wake at its centre and mixes with the outer flow before the tail",
};

/// A surface's place: its planform and the point its span starts from (a fin's root, a
/// tailplane's centre), with the span's direction (a unit vector in body axes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Placement {
    pub planform: Planform,
    pub root_m: [f64; 3],
    pub span_direction: [f64; 3],
}

/// The share of a surface inside the slipstream.
pub const FRACTION: Method = Method {
    name: "the share of a surface inside the slipstream",
    source: "geometry: the surface's area (its chord along its span) inside the slipstream's circle at the surface (momentum theory's radius there), the slipstream along the shaft as the model takes it",
    accuracy: "estimated: the range spans the slipstream's radius from its contracted value to the disc's (mixing widens it) and its axis moved up and down by the distance behind the disc times tan 5 deg (its drift with the flow angle in trim, which the model does not follow)",
};

/// The propeller's straightening of the flow in its slipstream.
pub const STRAIGHTENING: Method = Method {
    name: "the sideslip the propeller's normal force takes out of its slipstream",
    source: "momentum: the air through the disc, m = rho pi R^2 (V + v) per second, loses the lateral momentum the propeller's side force takes, so its sideslip velocity falls by -(dY/dv) / m per m/s (the side force from the model's propeller at the condition)",
    accuracy: "estimated: 0.5 to 1.0 of the value: the momentum is taken out at the disc, and the slipstream mixes with the outer flow before the tail",
};

/// Momentum theory's induced velocity at the disc, m/s.
pub fn induced_velocity(disc: &Disc, op: &OperatingPoint) -> Result<f64, EstimateError> {
    let r = positive("propeller radius", disc.radius_m)?;
    let rho = positive("density", op.density_kg_m3)?;
    let v = non_negative("airspeed at the disc", op.airspeed_m_s)?;
    let t = non_negative(
        "thrust (a windmilling propeller's wake is not a slipstream this method covers)",
        op.thrust_n,
    )?;
    let area = PI * r * r;
    Ok(-v / 2.0 + (v * v / 4.0 + t / (2.0 * rho * area)).sqrt())
}

/// The axial excess of the slipstream over the free stream at `behind_m` behind the disc, m/s
/// (zero ahead of it).
pub fn excess_at(induced_m_s: f64, radius_m: f64, behind_m: f64) -> f64 {
    if behind_m <= 0.0 {
        return 0.0;
    }
    induced_m_s * (1.0 + behind_m / (behind_m * behind_m + radius_m * radius_m).sqrt())
}

/// The slipstream's radius where its excess is `excess_m_s`, by continuity.
pub fn radius_at(disc: &Disc, airspeed_m_s: f64, induced_m_s: f64, excess_m_s: f64) -> f64 {
    let through = airspeed_m_s + induced_m_s;
    let there = airspeed_m_s + excess_m_s;
    if there <= 0.0 {
        return disc.radius_m;
    }
    disc.radius_m * (through / there).sqrt()
}

/// The slipstream's dynamic pressure over the free stream's where its excess is `excess_m_s`,
/// with [`MOMENTUM`]'s range.
pub fn dynamic_pressure_ratio(
    airspeed_m_s: f64,
    excess_m_s: f64,
) -> Result<Estimate, EstimateError> {
    let v = positive("airspeed", airspeed_m_s)?;
    let ratio = |e: f64| ((v + e) / v).powi(2);
    Ok(Estimate::within(
        ratio(excess_m_s),
        ratio(0.7 * excess_m_s),
        ratio(excess_m_s),
    ))
}

/// The share of a placed surface's area within `radius_m` of the shaft line through
/// `axis_m` (its y and z: the slipstream's circle in the y-z plane), by midpoint strips.
pub fn share_inside(surface: &Placement, axis_m: [f64; 3], radius_m: f64) -> f64 {
    let p = &surface.planform;
    let strips = 2000;
    let (from, to) = if p.mirrored {
        (-p.span_m / 2.0, p.span_m / 2.0)
    } else {
        (0.0, p.span_m)
    };
    let ds = (to - from) / strips as f64;
    let (mut inside, mut all) = (0.0, 0.0);
    for k in 0..strips {
        let s = from + (k as f64 + 0.5) * ds;
        let at = |i: usize| surface.root_m[i] + s * surface.span_direction[i];
        let (dy, dz) = (at(1) - axis_m[1], at(2) - axis_m[2]);
        let chord = p.chord_at(s.abs());
        all += chord;
        if dy * dy + dz * dz <= radius_m * radius_m {
            inside += chord;
        }
    }
    if all > 0.0 { inside / all } else { 0.0 }
}

/// [`FRACTION`] for a placed surface behind the disc, with the slipstream's excess there
/// (`excess_m_s`, at the airspeed reaching the disc and its induced velocity) setting its
/// radius. `behind_m` is the surface's distance behind the disc.
pub fn fraction(
    surface: &Placement,
    disc: &Disc,
    flow: (f64, f64, f64),
    behind_m: f64,
) -> Result<Estimate, EstimateError> {
    surface.planform.checked()?;
    positive("propeller radius", disc.radius_m)?;
    let (airspeed, induced, excess) = flow;
    if behind_m <= 0.0 {
        return Ok(Estimate::exact(0.0));
    }
    let contracted = radius_at(disc, airspeed, induced, excess);
    let drift = behind_m * 5f64.to_radians().tan();
    let value = share_inside(surface, disc.centre_m, contracted);
    let mut ends = Vec::new();
    for r in [contracted, disc.radius_m] {
        for dz in [-drift, 0.0, drift] {
            let c = disc.centre_m;
            ends.push(share_inside(surface, [c[0], c[1], c[2] + dz], r));
        }
    }
    let lower = ends.iter().copied().fold(f64::INFINITY, f64::min);
    let upper = ends.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(Estimate::within(value, lower, upper))
}

/// [`STRAIGHTENING`]: the share of the sideslip taken out of the slipstream (the model's
/// `wash_gradient` on the part of a surface inside it).
pub fn straightening(disc: &Disc, op: &OperatingPoint) -> Result<Estimate, EstimateError> {
    let v = induced_velocity(disc, op)?;
    let flow = op.density_kg_m3 * PI * disc.radius_m.powi(2) * (op.airspeed_m_s + v);
    let mass_flow = positive("mass flow through the disc", flow)?;
    let side = super::finite("propeller side force per m/s", op.side_force_per_m_s)?;
    let value = -side / mass_flow;
    Ok(Estimate::within(value, 0.5 * value, value))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc() -> Disc {
        Disc {
            centre_m: [-1.3, 0.0, -0.05],
            radius_m: 0.75,
        }
    }

    /// Momentum theory: the thrust comes back from the induced velocity, twice it far behind,
    /// and the slipstream's mass flow is the same at every section.
    #[test]
    fn the_slipstream_keeps_momentum_theorys_thrust_and_mass_flow() {
        let op = OperatingPoint {
            airspeed_m_s: 31.0,
            density_kg_m3: 1.16,
            thrust_n: 700.0,
            side_force_per_m_s: -5.0,
        };
        let d = disc();
        let v = induced_velocity(&d, &op).unwrap();
        let area = PI * d.radius_m.powi(2);
        let thrust = 2.0 * op.density_kg_m3 * area * (op.airspeed_m_s + v) * v;
        assert!((thrust - op.thrust_n).abs() < 1e-9, "{thrust}");
        assert!((excess_at(v, d.radius_m, 1e5) - 2.0 * v).abs() < 1e-6);
        assert_eq!(excess_at(v, d.radius_m, -0.1), 0.0);
        let x = excess_at(v, d.radius_m, 1.5);
        let r = radius_at(&d, op.airspeed_m_s, v, x);
        let flux = |radius: f64, speed: f64| radius * radius * speed;
        assert!(
            (flux(r, op.airspeed_m_s + x) - flux(d.radius_m, op.airspeed_m_s + v)).abs() < 1e-9
        );
        let q = dynamic_pressure_ratio(op.airspeed_m_s, x).unwrap();
        assert!((q.value - ((31.0 + x) / 31.0f64).powi(2)).abs() < 1e-12 && q.lower < q.value);
        // The straightening: the side force over the mass flow.
        let s = straightening(&d, &op).unwrap();
        let flow = op.density_kg_m3 * area * (op.airspeed_m_s + v);
        assert!((s.value - 5.0 / flow).abs() < 1e-12 && s.lower == 0.5 * s.value);
        let windmill = OperatingPoint {
            thrust_n: -10.0,
            ..op
        };
        assert!(induced_velocity(&d, &windmill).is_err());
    }

    /// A rectangular fin from the shaft's height up: the share inside is the share of its span
    /// under the slipstream's top edge. A tailplane on the shaft wider than the slipstream: the
    /// chord-weighted share of its span inside.
    #[test]
    fn a_surfaces_share_is_its_area_inside_the_circle() {
        let square = Planform {
            span_m: 1.0,
            root_chord_m: 0.7,
            tip_chord_m: 0.7,
            half_chord_sweep_rad: 0.0,
            mirrored: false,
        };
        let fin = Placement {
            planform: square,
            root_m: [-2.8, 0.0, -0.05],
            span_direction: [0.0, 0.0, -1.0],
        };
        let share = share_inside(&fin, disc().centre_m, 0.6);
        assert!((share - 0.6).abs() < 1e-3, "{share}");
        let tail = Placement {
            planform: Planform {
                span_m: 2.0,
                mirrored: true,
                ..square
            },
            root_m: [-2.6, 0.0, -0.05],
            span_direction: [0.0, 1.0, 0.0],
        };
        let share = share_inside(&tail, disc().centre_m, 0.5);
        assert!((share - 0.5).abs() < 1e-3, "{share}");
        // Ahead of the disc: none. Behind it, the range holds the value.
        let ahead = fraction(&fin, &disc(), (31.0, 5.0, 0.0), -0.5).unwrap();
        assert_eq!(ahead.value, 0.0);
        let behind = fraction(&fin, &disc(), (31.0, 5.0, 9.0), 1.5).unwrap();
        assert!(
            behind.lower < behind.value && behind.value < behind.upper,
            "{behind:?}"
        );
    }
}
