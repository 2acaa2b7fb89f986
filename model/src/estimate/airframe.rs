//! An aircraft's tail and pod estimated step by step from its geometry and its propeller's
//! operating point: the fin's and tailplane's lift slopes, their shares in the slipstream, the
//! sidewash and dynamic-pressure ratio at the fin, and the pod's Munk couple. Each step names
//! its method and inputs, so the derivation can be printed and checked.
//!
//! Where the model's one-point surface needs one number for a surface partly in the slipstream,
//! the estimates are composed linearly: the fin's sidewash gradient is its slipstream share
//! times the propeller's straightening plus the pod's sidewash; its dynamic-pressure ratio is
//! the free stream's at the part outside (the model adds the slipstream's own from the
//! propeller's solution at each condition).
//!
//! The surface's aerodynamic centre (the model's `position_m`) is taken as its planform's
//! centroid: a fin's root is then the centroid's height from the root below it, and its leading
//! edge a quarter of the mean aerodynamic chord ahead of it.

use super::body::{self, Pod};
use super::lifting_surface::{self, EndPlates, Planform, TailplaneOnFin};
use super::slipstream::{self, Disc, OperatingPoint, Placement};
use super::{Estimate, EstimateError, Method, non_negative};
use serde::Serialize;

/// A lifting surface: where the model puts its aerodynamic centre, its planform and its
/// section's lift-curve slope.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SurfaceGeometry {
    /// Body axes from the datum, m (the model's `position_m`).
    pub position_m: [f64; 3],
    pub planform: Planform,
    pub section_lift_slope_per_rad: f64,
}

/// A fin and the depth of the body (a keel, a boom, a fuselage) it stands on, m (0: none).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FinGeometry {
    pub surface: SurfaceGeometry,
    pub body_depth_m: f64,
}

/// The pod and its centroid, body axes from the datum, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PodGeometry {
    pub pod: Pod,
    pub centroid_m: [f64; 3],
}

/// What the estimates start from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Geometry {
    pub fin: Option<FinGeometry>,
    pub tailplane: Option<SurfaceGeometry>,
    pub pod: Option<PodGeometry>,
    pub disc: Disc,
}

/// The part of the geometry a bad input belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Part {
    Fin,
    Tailplane,
    Pod,
    Propeller,
}

/// A bad input and the part it belongs to.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{part:?}: {error}")]
pub struct PartError {
    pub part: Part,
    pub error: EstimateError,
}

fn at(part: Part) -> impl Fn(EstimateError) -> PartError {
    move |error| PartError { part, error }
}

/// A surface's estimates: what the model's `Surface` takes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SurfaceEstimates {
    pub lift_slope_per_rad: Estimate,
    pub slipstream_fraction: Estimate,
    /// `None` where not estimated (the tailplane's downwash needs the rotor's wake).
    pub wash_gradient: Option<Estimate>,
    pub dynamic_pressure_ratio: Estimate,
}

/// One step of the derivation: a quantity, its value and range, the method that gave it
/// (`None`: geometry or arithmetic on earlier steps) and the numbers it came from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Step {
    pub quantity: &'static str,
    pub unit: &'static str,
    pub value: Estimate,
    pub method: Option<Method>,
    pub inputs: Vec<(&'static str, f64)>,
}

/// Every estimate, and the steps that gave them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimates {
    pub fin: Option<SurfaceEstimates>,
    pub tailplane: Option<SurfaceEstimates>,
    /// The pod's Munk couple `(k2 - k1) Vol`, m^3 (the model's `munk_yaw_m3`).
    pub munk_yaw_m3: Option<Estimate>,
    pub steps: Vec<Step>,
}

/// The dynamic pressure at a surface outside the slipstream.
pub const FREE_STREAM: Method = Method {
    name: "the dynamic pressure at a surface outside the slipstream",
    source: "none reached for a gyroplane's tail: DATCOM's wing-body correlation for the fin (Sec. 5.4.1.1) needs a wing; taken as the free stream's",
    accuracy: "estimated: 0.9 to 1.0: up to a tenth lost where the mast's, the crew's and the engine's wakes reach the surface",
};

/// A fin's root, the body's centre line under it and its span from that line, m (z down).
struct FinFrame {
    root_z: f64,
    centre_line_z: f64,
    span_from_centre_line: f64,
}

fn fin_frame(f: &FinGeometry) -> FinFrame {
    let p = &f.surface.planform;
    let root_z = f.surface.position_m[2] + p.centroid_from_root_m();
    FinFrame {
        root_z,
        centre_line_z: root_z + f.body_depth_m / 2.0,
        span_from_centre_line: p.span_m + f.body_depth_m / 2.0,
    }
}

/// The DATCOM end plates of a fin, from where the model puts it and the tailplane.
fn end_plates(
    f: &FinGeometry,
    tailplane: Option<&SurfaceGeometry>,
) -> Result<EndPlates, EstimateError> {
    let p = f.surface.planform;
    p.checked()?;
    non_negative("body_depth_m", f.body_depth_m)?;
    let frame = fin_frame(f);
    let span_over_body_depth = if f.body_depth_m > 0.0 {
        frame.span_from_centre_line / f.body_depth_m
    } else {
        f64::INFINITY
    };
    let tailplane = match tailplane {
        None => None,
        Some(t) => {
            t.planform.checked()?;
            // Up the fin from its root to the tailplane, and the fin's leading edge there.
            let s = frame.root_z - t.position_m[2];
            let x_le = f.surface.position_m[0]
                + p.mean_aerodynamic_chord_m() / 4.0
                + (p.centroid_from_root_m() - s) * p.leading_edge_sweep_tan();
            let chord = p.chord_at(s.clamp(0.0, p.span_m));
            Some(TailplaneOnFin {
                area_ratio: t.planform.area_m2() / p.area_m2(),
                height_ratio: (t.position_m[2] - frame.centre_line_z) / frame.span_from_centre_line,
                chordwise_ratio: (x_le - t.position_m[0]) / chord,
            })
        }
    };
    Ok(EndPlates {
        span_over_body_depth,
        taper_ratio: p.taper_ratio(),
        tailplane,
    })
}

/// Checks what needs no operating point: the planforms, the pod, the fin's end plates against
/// their charts, and a fin behind the pod.
pub fn check(g: &Geometry) -> Result<(), PartError> {
    if let Some(t) = &g.tailplane {
        t.planform.checked().map_err(at(Part::Tailplane))?;
    }
    if let Some(p) = &g.pod {
        p.pod.checked().map_err(at(Part::Pod))?;
    }
    if let Some(f) = &g.fin {
        let plates = end_plates(f, g.tailplane.as_ref()).map_err(at(Part::Fin))?;
        lifting_surface::fin_effective_aspect_ratio(f.surface.planform.aspect_ratio(), &plates)
            .map_err(at(Part::Fin))?;
        if let Some(p) = &g.pod {
            pod_to_fin(p, f)?;
        }
    }
    Ok(())
}

/// The distance from the pod's centroid to the fin, m; refused unless the fin stands behind
/// the pod's tail (the pod's sidewash is its far field behind it).
fn pod_to_fin(p: &PodGeometry, f: &FinGeometry) -> Result<f64, PartError> {
    let d: Vec<f64> = (0..3)
        .map(|i| f.surface.position_m[i] - p.centroid_m[i])
        .collect();
    let behind_tail = -d[0] - p.pod.length_m / 2.0;
    if behind_tail.is_nan() || behind_tail <= 0.0 {
        return Err(PartError {
            part: Part::Fin,
            error: EstimateError::Domain {
                name: "the fin's distance behind the pod's tail, m",
                value: behind_tail,
                method: "the pod's sidewash at the fin",
                domain: "positive: the fin must stand behind the pod",
            },
        });
    }
    Ok((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
}

/// The estimates, step by step.
pub fn estimate(g: &Geometry, op: &OperatingPoint) -> Result<Estimates, PartError> {
    check(g)?;
    let mut steps = Vec::new();
    let v = slipstream::induced_velocity(&g.disc, op).map_err(at(Part::Propeller))?;
    steps.push(Step {
        quantity: "propeller: induced velocity at the disc",
        unit: "m/s",
        value: Estimate::exact(v),
        method: Some(slipstream::MOMENTUM),
        inputs: vec![
            ("thrust, N", op.thrust_n),
            ("airspeed at the disc, m/s", op.airspeed_m_s),
            ("density, kg/m^3", op.density_kg_m3),
            ("disc radius, m", g.disc.radius_m),
        ],
    });
    let straightening = slipstream::straightening(&g.disc, op).map_err(at(Part::Propeller))?;
    steps.push(Step {
        quantity: "propeller: share of the sideslip taken out of its slipstream",
        unit: "-",
        value: straightening,
        method: Some(slipstream::STRAIGHTENING),
        inputs: vec![("propeller dY/dv, N s/m", op.side_force_per_m_s)],
    });
    let munk = match &g.pod {
        None => None,
        Some(p) => Some(pod_steps(p, &mut steps)?),
    };
    let tailplane = match &g.tailplane {
        None => None,
        Some(t) => Some(tailplane_steps(t, g, op, v, &mut steps)?),
    };
    let fin = match &g.fin {
        None => None,
        Some(f) => Some(fin_steps(f, g, op, (v, straightening), &mut steps)?),
    };
    Ok(Estimates {
        fin,
        tailplane,
        munk_yaw_m3: munk,
        steps,
    })
}

/// The pod's spheroid and its Munk couple.
fn pod_steps(p: &PodGeometry, steps: &mut Vec<Step>) -> Result<Estimate, PartError> {
    let pod = &p.pod;
    let (k1, k2) = body::apparent_mass_factors(pod.fineness()).map_err(at(Part::Pod))?;
    steps.push(Step {
        quantity: "pod: volume of its spheroid",
        unit: "m^3",
        value: Estimate::exact(pod.volume_m3()),
        method: None,
        inputs: vec![
            ("length, m", pod.length_m),
            (
                "equivalent diameter sqrt(width height), m",
                pod.diameter_m(),
            ),
        ],
    });
    steps.push(Step {
        quantity: "pod: k2 - k1",
        unit: "-",
        value: Estimate::exact(k2 - k1),
        method: Some(body::APPARENT_MASS),
        inputs: vec![
            ("length over diameter", pod.fineness()),
            ("k1", k1),
            ("k2", k2),
        ],
    });
    let munk = body::munk_yaw_m3(pod).map_err(at(Part::Pod))?;
    steps.push(Step {
        quantity: "pod: Munk couple (k2 - k1) Vol (munk_yaw_m3)",
        unit: "m^3",
        value: munk,
        method: Some(body::MUNK_YAW),
        inputs: vec![],
    });
    Ok(munk)
}

/// A surface's slipstream: its distance behind the disc, the excess, radius and dynamic
/// pressure there, and its share inside.
fn slipstream_steps(
    name: [&'static str; 4],
    place: &Placement,
    g: &Geometry,
    op: &OperatingPoint,
    v: f64,
    steps: &mut Vec<Step>,
) -> Result<Estimate, EstimateError> {
    let behind = g.disc.centre_m[0] - place.root_m[0];
    let excess = slipstream::excess_at(v, g.disc.radius_m, behind);
    let radius = slipstream::radius_at(&g.disc, op.airspeed_m_s, v, excess);
    steps.push(Step {
        quantity: name[0],
        unit: "m/s",
        value: Estimate::exact(excess),
        method: Some(slipstream::MOMENTUM),
        inputs: vec![
            ("behind the disc, m", behind),
            ("slipstream radius there, m", radius),
        ],
    });
    steps.push(Step {
        quantity: name[1],
        unit: "-",
        value: slipstream::dynamic_pressure_ratio(op.airspeed_m_s, excess)?,
        method: Some(slipstream::MOMENTUM),
        inputs: vec![],
    });
    let share = slipstream::fraction(place, &g.disc, (op.airspeed_m_s, v, excess), behind)?;
    steps.push(Step {
        quantity: name[2],
        unit: "-",
        value: share,
        method: Some(slipstream::FRACTION),
        inputs: vec![("shaft height, m", g.disc.centre_m[2])],
    });
    let q = Estimate::within(1.0, 0.9, 1.0);
    steps.push(Step {
        quantity: name[3],
        unit: "-",
        value: q,
        method: Some(FREE_STREAM),
        inputs: vec![],
    });
    Ok(share)
}

/// The tailplane: its lift slope from its aspect ratio, and its slipstream.
fn tailplane_steps(
    t: &SurfaceGeometry,
    g: &Geometry,
    op: &OperatingPoint,
    v: f64,
    steps: &mut Vec<Step>,
) -> Result<SurfaceEstimates, PartError> {
    let p = &t.planform;
    let slope = lifting_surface::lift_slope(
        p.aspect_ratio(),
        p.half_chord_sweep_rad,
        t.section_lift_slope_per_rad,
    )
    .map_err(at(Part::Tailplane))?;
    steps.push(Step {
        quantity: "tailplane: lift slope (lift_slope_per_rad)",
        unit: "1/rad",
        value: slope,
        method: Some(lifting_surface::LIFT_SLOPE),
        inputs: vec![
            ("aspect ratio", p.aspect_ratio()),
            ("half-chord sweep, deg", p.half_chord_sweep_rad.to_degrees()),
            ("section slope, 1/rad", t.section_lift_slope_per_rad),
        ],
    });
    let place = Placement {
        planform: *p,
        root_m: t.position_m,
        span_direction: [0.0, 1.0, 0.0],
    };
    let names = [
        "tailplane: slipstream excess at it",
        "tailplane: slipstream dynamic pressure over the free stream's",
        "tailplane: share in the slipstream (slipstream_fraction)",
        "tailplane: dynamic-pressure ratio outside the slipstream (dynamic_pressure_ratio)",
    ];
    let share = slipstream_steps(names, &place, g, op, v, steps).map_err(at(Part::Tailplane))?;
    Ok(SurfaceEstimates {
        lift_slope_per_rad: slope,
        slipstream_fraction: share,
        wash_gradient: None,
        dynamic_pressure_ratio: Estimate::within(1.0, 0.9, 1.0),
    })
}

/// The fin's lift slope against sideslip: Helmbold's at its effective aspect ratio (over the
/// aspect ratio's range), times the body's factor `k_v`.
fn fin_slope_steps(
    f: &FinGeometry,
    plates: &EndPlates,
    aspect_ratio: Estimate,
    steps: &mut Vec<Step>,
) -> Result<Estimate, PartError> {
    let p = &f.surface.planform;
    let slope = lifting_surface::lift_slope(
        aspect_ratio.value,
        p.half_chord_sweep_rad,
        f.surface.section_lift_slope_per_rad,
    )
    .map_err(at(Part::Fin))?;
    let ends = [aspect_ratio.lower, aspect_ratio.upper].map(|a| {
        lifting_surface::lift_slope(
            a,
            p.half_chord_sweep_rad,
            f.surface.section_lift_slope_per_rad,
        )
    });
    let [lo, hi] = ends;
    let (lo, hi) = (lo.map_err(at(Part::Fin))?, hi.map_err(at(Part::Fin))?);
    let alone = Estimate::within(slope.value, lo.lower, hi.upper);
    steps.push(Step {
        quantity: "fin: lift slope at its effective aspect ratio",
        unit: "1/rad",
        value: alone,
        method: Some(lifting_surface::LIFT_SLOPE),
        inputs: vec![
            ("effective aspect ratio", aspect_ratio.value),
            ("half-chord sweep, deg", p.half_chord_sweep_rad.to_degrees()),
            ("section slope, 1/rad", f.surface.section_lift_slope_per_rad),
        ],
    });
    let k_v =
        lifting_surface::fin_body_factor(plates.span_over_body_depth).map_err(at(Part::Fin))?;
    steps.push(Step {
        quantity: "fin: the body's factor on its side force, k_v",
        unit: "-",
        value: k_v,
        method: Some(lifting_surface::FIN_BODY_FACTOR),
        inputs: vec![("b_v / 2 r_1", plates.span_over_body_depth)],
    });
    let slope = Estimate::within(
        k_v.value * alone.value,
        k_v.lower * alone.lower,
        k_v.upper * alone.upper,
    );
    steps.push(Step {
        quantity: "fin: lift slope against sideslip, k_v x the slope (lift_slope_per_rad)",
        unit: "1/rad",
        value: slope,
        method: None,
        inputs: vec![("k_v", k_v.value), ("lift slope", alone.value)],
    });
    Ok(slope)
}

/// The fin: its effective aspect ratio and lift slope, its slipstream, and the sidewash at it.
fn fin_steps(
    f: &FinGeometry,
    g: &Geometry,
    op: &OperatingPoint,
    (v, straightening): (f64, Estimate),
    steps: &mut Vec<Step>,
) -> Result<SurfaceEstimates, PartError> {
    let p = &f.surface.planform;
    let plates = end_plates(f, g.tailplane.as_ref()).map_err(at(Part::Fin))?;
    let aspect = lifting_surface::fin_effective_aspect_ratio(p.aspect_ratio(), &plates)
        .map_err(at(Part::Fin))?;
    let mut inputs = vec![
        ("aspect ratio b^2 / S", p.aspect_ratio()),
        ("taper ratio", plates.taper_ratio),
        ("b_v / 2 r_1", plates.span_over_body_depth),
        ("A_v(B) / A_v", aspect.body_factor.value),
    ];
    if let Some(t) = plates.tailplane {
        inputs.extend([
            ("S_h / S_v", t.area_ratio),
            ("z_H / b_v", t.height_ratio),
            ("x / c_v", t.chordwise_ratio),
            ("A_v(HB) / A_v(B)", aspect.tailplane_factor.value),
            ("K_H", aspect.k_h.value),
        ]);
    }
    steps.push(Step {
        quantity: "fin: effective aspect ratio",
        unit: "-",
        value: aspect.aspect_ratio,
        method: Some(lifting_surface::FIN_ASPECT_RATIO),
        inputs,
    });
    let slope = fin_slope_steps(f, &plates, aspect.aspect_ratio, steps)?;
    let frame = fin_frame(f);
    let place = Placement {
        planform: *p,
        root_m: [
            f.surface.position_m[0],
            f.surface.position_m[1],
            frame.root_z,
        ],
        span_direction: [0.0, 0.0, -1.0],
    };
    let names = [
        "fin: slipstream excess at it",
        "fin: slipstream dynamic pressure over the free stream's",
        "fin: share in the slipstream (slipstream_fraction)",
        "fin: dynamic-pressure ratio outside the slipstream (dynamic_pressure_ratio)",
    ];
    let share = slipstream_steps(names, &place, g, op, v, steps).map_err(at(Part::Fin))?;
    let pod_wash = match &g.pod {
        None => Estimate::exact(0.0),
        Some(pod) => {
            let r = pod_to_fin(pod, f)?;
            let w = body::sidewash_gradient(&pod.pod, r).map_err(at(Part::Fin))?;
            steps.push(Step {
                quantity: "fin: sidewash of the pod's cross-flow",
                unit: "-",
                value: w,
                method: Some(body::BODY_SIDEWASH),
                inputs: vec![("distance from the pod's centroid, m", r)],
            });
            w
        }
    };
    let wash = Estimate::within(
        share.value * straightening.value + pod_wash.value,
        share.lower * straightening.lower + pod_wash.lower,
        share.upper * straightening.upper + pod_wash.upper,
    );
    steps.push(Step {
        quantity: "fin: sidewash gradient, slipstream share x straightening + the pod's (wash_gradient)",
        unit: "-",
        value: wash,
        method: None,
        inputs: vec![
            ("share in the slipstream", share.value),
            ("straightening", straightening.value),
            ("the pod's sidewash", pod_wash.value),
        ],
    });
    Ok(SurfaceEstimates {
        lift_slope_per_rad: slope,
        slipstream_fraction: share,
        wash_gradient: Some(wash),
        dynamic_pressure_ratio: Estimate::within(1.0, 0.9, 1.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A light gyroplane's tail (the VPM M16 file's estimated geometry): a 1 m fin of 0.7 m^2
    /// standing on a 0.1 m keel 2.8 m behind the c.g., a 0.45 m^2 tailplane across its foot, a
    /// pod ahead and a 0.74 m propeller 1.3 m behind the c.g.
    fn geometry() -> Geometry {
        let planform = |span: f64, root: f64, tip: f64, mirrored: bool| Planform {
            span_m: span,
            root_chord_m: root,
            tip_chord_m: tip,
            half_chord_sweep_rad: 0.0,
            mirrored,
        };
        Geometry {
            fin: Some(FinGeometry {
                surface: SurfaceGeometry {
                    position_m: [-2.8, 0.0, -0.5],
                    planform: planform(1.0, 0.8, 0.6, false),
                    section_lift_slope_per_rad: lifting_surface::THIN_AEROFOIL_SLOPE_PER_RAD,
                },
                body_depth_m: 0.1,
            }),
            tailplane: Some(SurfaceGeometry {
                position_m: [-2.6, 0.0, -0.2],
                planform: planform(1.16, 0.388, 0.388, true),
                section_lift_slope_per_rad: lifting_surface::THIN_AEROFOIL_SLOPE_PER_RAD,
            }),
            pod: Some(PodGeometry {
                pod: Pod {
                    length_m: 2.3,
                    width_m: 0.75,
                    height_m: 1.0,
                },
                centroid_m: [0.4, 0.0, 0.0],
            }),
            disc: Disc {
                centre_m: [-1.3, 0.0, -0.05],
                radius_m: 0.737,
            },
        }
    }

    /// The value of the step named `quantity`.
    fn step_value(e: &Estimates, quantity: &str) -> f64 {
        e.steps
            .iter()
            .find(|s| s.quantity == quantity)
            .unwrap_or_else(|| panic!("no step `{quantity}`"))
            .value
            .value
    }

    fn cruise() -> OperatingPoint {
        OperatingPoint {
            airspeed_m_s: 31.3,
            density_kg_m3: 1.156,
            thrust_n: 700.0,
            side_force_per_m_s: -5.5,
        }
    }

    /// Every estimate is finite and inside its range; the fin's slope is below the thin
    /// aerofoil's and above the slender wing's; the composed sidewash is the share times the
    /// straightening plus the pod's; every step names its inputs or its method.
    #[test]
    fn a_gyroplanes_tail_is_estimated_step_by_step() {
        let e = estimate(&geometry(), &cruise()).unwrap();
        let fin = e.fin.unwrap();
        for x in [
            fin.lift_slope_per_rad,
            fin.slipstream_fraction,
            fin.wash_gradient.unwrap(),
            fin.dynamic_pressure_ratio,
            e.munk_yaw_m3.unwrap(),
        ] {
            assert!(
                x.value.is_finite() && x.lower <= x.value && x.value <= x.upper,
                "{x:?}"
            );
        }
        // Helmbold's slope lies under the slender wing's pi A / 2 at low aspect ratio.
        let a = fin.lift_slope_per_rad.value;
        let effective = step_value(&e, "fin: effective aspect ratio");
        let slender = std::f64::consts::PI * effective / 2.0;
        assert!(a < slender && a > 0.8 * slender, "{a} {effective}");
        assert!((0.0..=1.0).contains(&fin.slipstream_fraction.value));
        let straightening = e
            .steps
            .iter()
            .find(|s| s.quantity.starts_with("propeller: share"))
            .unwrap()
            .value
            .value;
        let pod = step_value(&e, "fin: sidewash of the pod's cross-flow");
        let wash = fin.wash_gradient.unwrap().value;
        assert!(
            (wash - (fin.slipstream_fraction.value * straightening + pod)).abs() < 1e-15,
            "{wash}"
        );
        assert!(
            e.steps
                .iter()
                .all(|s| s.method.is_some() || !s.inputs.is_empty())
        );
        assert!(e.tailplane.unwrap().wash_gradient.is_none());
    }

    /// DATCOM's `k_v` (Sec. 5.3.1.1; Roskam Part VI Eq. 10.28, Fig. 10.12): a fin on a body as
    /// deep as its span keeps 0.75 of its lift slope against sideslip, 0.875 half-way up the
    /// chart's ramp (b_v / 2 r_1 = 2.75), and all of it on a keel (10.5).
    #[test]
    fn a_fin_on_a_deep_body_loses_a_quarter_of_its_slope() {
        for (span_over_depth, k_v) in [(1.5, 0.75), (2.75, 0.875), (10.5, 1.0)] {
            let mut g = geometry();
            let fin = g.fin.as_mut().unwrap();
            // b_v / 2 r_1 = (span + d / 2) / d.
            fin.body_depth_m = fin.surface.planform.span_m / (span_over_depth - 0.5);
            let e = estimate(&g, &cruise()).unwrap();
            let effective = step_value(&e, "fin: effective aspect ratio");
            let planform = g.fin.unwrap().surface.planform;
            let helmbold = lifting_surface::lift_slope(
                effective,
                planform.half_chord_sweep_rad,
                lifting_surface::THIN_AEROFOIL_SLOPE_PER_RAD,
            )
            .unwrap()
            .value;
            let slope = e.fin.unwrap().lift_slope_per_rad;
            assert!(
                (slope.value - k_v * helmbold).abs() < 1e-12,
                "b_v / 2 r_1 = {span_over_depth}: {} against {k_v} x {helmbold}",
                slope.value
            );
            assert!(slope.lower <= slope.value && slope.value <= slope.upper);
        }
    }

    /// Bad geometry is refused with the part it belongs to: a fin of no span, a pod wider than
    /// long, a fin ahead of the pod's tail (behind nothing), a tailplane off the fin.
    #[test]
    fn bad_geometry_names_its_part() {
        let mut g = geometry();
        g.fin.as_mut().unwrap().surface.planform.span_m = 0.0;
        assert_eq!(check(&g).unwrap_err().part, Part::Fin);
        let mut g = geometry();
        g.pod.as_mut().unwrap().pod.length_m = 0.5;
        assert_eq!(check(&g).unwrap_err().part, Part::Pod);
        let mut g = geometry();
        g.fin.as_mut().unwrap().surface.position_m[0] = -0.5;
        let e = check(&g).unwrap_err();
        assert!(
            e.part == Part::Fin && e.to_string().contains("behind the pod"),
            "{e}"
        );
        let mut g = geometry();
        g.tailplane.as_mut().unwrap().position_m[2] = -2.0;
        assert_eq!(check(&g).unwrap_err().part, Part::Fin);
        let mut g = geometry();
        g.disc.radius_m = -1.0;
        assert_eq!(estimate(&g, &cruise()).unwrap_err().part, Part::Propeller);
    }
}
