//! Lifting surfaces: a straight-tapered planform, its lift-curve slope from aspect ratio and
//! sweep, and a fin's effective aspect ratio with the end-plate effect of the body it stands on
//! and of the tailplane.
//!
//! The fin's end plates are DATCOM's: the body below its root and the tailplane across it stop
//! part of the flow round the fin's root, so it lifts as a fin of a larger aspect ratio. Its
//! three charts are tabulated here as read by hand from them (every 0.05-0.5 along each axis;
//! the tables give the readings), and interpolated linearly. A point outside a chart is refused
//! where extrapolating would be a guess, and taken at the chart's edge, with its range widened,
//! where the chart's trend is plain (a body far thinner than the fin is nearly no end plate).

use super::{Estimate, EstimateError, Method, finite, interpolate, non_negative, positive};
use serde::Serialize;
use std::f64::consts::PI;

/// A straight-tapered planform: one panel from root to tip (a fin), or two mirrored about the
/// root (a tailplane, its span from tip to tip).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Planform {
    pub span_m: f64,
    pub root_chord_m: f64,
    pub tip_chord_m: f64,
    /// Sweep of the half-chord line, positive back.
    pub half_chord_sweep_rad: f64,
    /// Two panels mirrored about the root (`span_m` tip to tip), or one (root to tip).
    pub mirrored: bool,
}

impl Planform {
    /// Checks the planform: a positive span and root chord, a tip chord from 0 to the root's
    /// (an inverse taper is outside the fin's end-plate chart), a sweep under 60 deg.
    pub fn checked(&self) -> Result<&Self, EstimateError> {
        positive("span_m", self.span_m)?;
        positive("root_chord_m", self.root_chord_m)?;
        non_negative("tip_chord_m", self.tip_chord_m)?;
        if self.tip_chord_m > self.root_chord_m {
            return Err(EstimateError::Input {
                name: "tip_chord_m",
                requirement: "at most the root chord (a tip wider than the root is outside the methods here)",
                value: self.tip_chord_m,
            });
        }
        finite("half_chord_sweep_deg", self.half_chord_sweep_rad)?;
        if self.half_chord_sweep_rad.abs() >= 60f64.to_radians() {
            return Err(EstimateError::Input {
                name: "half_chord_sweep_deg",
                requirement: "under 60 deg either way",
                value: self.half_chord_sweep_rad.to_degrees(),
            });
        }
        Ok(self)
    }

    /// The span of one panel, root to tip.
    pub fn panel_span_m(&self) -> f64 {
        if self.mirrored {
            self.span_m / 2.0
        } else {
            self.span_m
        }
    }

    pub fn area_m2(&self) -> f64 {
        self.span_m * (self.root_chord_m + self.tip_chord_m) / 2.0
    }

    /// `b^2 / S`.
    pub fn aspect_ratio(&self) -> f64 {
        self.span_m * self.span_m / self.area_m2()
    }

    pub fn taper_ratio(&self) -> f64 {
        self.tip_chord_m / self.root_chord_m
    }

    /// The chord at `s` from the root along a panel's span (0 to its span).
    pub fn chord_at(&self, s: f64) -> f64 {
        let f = (s / self.panel_span_m()).clamp(0.0, 1.0);
        self.root_chord_m + (self.tip_chord_m - self.root_chord_m) * f
    }

    /// The mean aerodynamic chord, `2/3 c_r (1 + l + l^2) / (1 + l)`.
    pub fn mean_aerodynamic_chord_m(&self) -> f64 {
        let l = self.taper_ratio();
        2.0 / 3.0 * self.root_chord_m * (1.0 + l + l * l) / (1.0 + l)
    }

    /// Where along a panel's span, from the root, the mean aerodynamic chord and the panel's
    /// centroid of area lie: `b_p / 3 (1 + 2 l) / (1 + l)`.
    pub fn centroid_from_root_m(&self) -> f64 {
        let l = self.taper_ratio();
        self.panel_span_m() / 3.0 * (1.0 + 2.0 * l) / (1.0 + l)
    }

    /// The leading edge's sweep (positive back): `tan L_le = tan L_c/2 + (c_r - c_t) / (2 b_p)`.
    pub fn leading_edge_sweep_tan(&self) -> f64 {
        self.half_chord_sweep_rad.tan()
            + (self.root_chord_m - self.tip_chord_m) / (2.0 * self.panel_span_m())
    }
}

/// The lift-curve slope of a straight-tapered surface in incompressible flow.
pub const LIFT_SLOPE: Method = Method {
    name: "lift-curve slope from aspect ratio and sweep",
    source: "Helmbold's equation with the half-chord sweep and the section's slope, DATCOM Sec. 4.1.3.2 at Mach 0 (as Raymer Eq. 12.6 writes it): C_L_alpha = 2 pi A / (2 + sqrt(A^2 (1 + tan^2 L_c/2) / kappa^2 + 4)), kappa = c_l_alpha / (2 pi); unswept and with kappa = 1 it is Helmbold 1942's equation for low-aspect-ratio straight wings (Anderson 1999 Eq. 2.18a)",
    accuracy: "estimated: +-10 % (no accuracy stated for it was reached): it is exact in both its limits (the slender wing's pi A / 2 and lifting-line theory) and lies between them; a rudder's gap and the section's thickness and Reynolds number, which it sees only through kappa, move measured slopes by several per cent",
};

/// The relative accuracy of [`LIFT_SLOPE`] (see its `accuracy`).
const LIFT_SLOPE_ACCURACY: f64 = 0.10;

/// The section lift-curve slope of thin-aerofoil theory, `2 pi` per rad: the default where a
/// surface's section is not known.
pub const THIN_AEROFOIL_SLOPE_PER_RAD: f64 = 2.0 * PI;

/// [`LIFT_SLOPE`] for `aspect_ratio`, the half-chord sweep and the section's slope, per rad.
pub fn lift_slope(
    aspect_ratio: f64,
    half_chord_sweep_rad: f64,
    section_slope_per_rad: f64,
) -> Result<Estimate, EstimateError> {
    let a = positive("aspect_ratio", aspect_ratio)?;
    let kappa = positive("section_lift_slope_per_rad", section_slope_per_rad)? / (2.0 * PI);
    let t = finite("half_chord_sweep_deg", half_chord_sweep_rad)?.tan();
    let slope = 2.0 * PI * a / (2.0 + (a * a * (1.0 + t * t) / (kappa * kappa) + 4.0).sqrt());
    Ok(Estimate::relative(
        slope,
        LIFT_SLOPE_ACCURACY,
        LIFT_SLOPE_ACCURACY,
    ))
}

/// A fin's effective aspect ratio with its end plates.
pub const FIN_ASPECT_RATIO: Method = Method {
    name: "a fin's effective aspect ratio with the end-plate effect of the body and the tailplane",
    source: "DATCOM Sec. 5.3.1.1: A_eff = (A_v(B) / A_v) A_v [1 + K_H (A_v(HB) / A_v(B) - 1)], with A_v(B) / A_v against the fin's span from the body's centre line over the body's depth at the fin (b_v / 2 r_1; taper <= 0.6 and 1.0), A_v(HB) / A_v(B) against the tailplane's height on the fin (z_H / b_v, 0 at the body's centre line, -1 at the fin's tip) and its aerodynamic centre behind the fin's leading edge (x / c_v, 0.5 to 0.8), and K_H against S_h / S_v; the three charts as Roskam Part VI Figs. 10.14-10.16 reproduce them, read by hand (DATCOM's own figure and equation numbers not confirmed here)",
    accuracy: "estimated: each chart's reading +-0.03 (DATCOM's stated accuracy for a fin's side force was not reached); beyond a chart's edge the edge's reading with a wider range (b_v / 2 r_1 over 7: 1.02, from 1.0 to 1.05; S_h / S_v over 2: 1.13 +-0.05); a tailplane whose x / c_v is outside 0.5-0.8 takes the nearest curve, and the four curves span its range",
};

/// The reading uncertainty of a chart value.
const CHART_READING: f64 = 0.03;

/// The body's empirical factor on a fin's side force.
pub const FIN_BODY_FACTOR: Method = Method {
    name: "the body's empirical factor on a fin's side force (k_v)",
    source: "DATCOM Sec. 5.3.1.1: (C_Y_beta)_v = -k_v C_L_alpha_v (1 + d sigma / d beta) eta_v S_v / S, with k_v against the fin's span from the body's centre line over the body's depth at the fin (b_v / 2 r_1): 0.75 up to 2, rising linearly to 1 at 3.5, and 1 beyond (Roskam Part VI Eq. 10.28 and Fig. 10.12, read by hand; DATCOM's own figure number not confirmed here)",
    accuracy: "estimated: the chart's reading +-0.03 below b_v / 2 r_1 = 3.5 (no accuracy stated for it was reached), never above 1; from 3.5 on, exactly 1 (the fin without the body's interference)",
};

/// [`FIN_BODY_FACTOR`]'s `k_v` against `b_v / 2 r_1` (infinite for a fin on no body: 1).
pub fn fin_body_factor(span_over_body_depth: f64) -> Result<Estimate, EstimateError> {
    let r = span_over_body_depth;
    if r.is_nan() || r <= 0.0 {
        return Err(EstimateError::Domain {
            name: "b_v / 2 r_1 (the fin's span from the body's centre line over the body's depth)",
            value: r,
            method: "DATCOM's k_v",
            domain: "positive",
        });
    }
    if r >= 3.5 {
        // The chart's upper plateau is the fin without the body's interference.
        return Ok(Estimate::exact(1.0));
    }
    let k = 0.75 + 0.25 * ((r - 2.0) / 1.5).clamp(0.0, 1.0);
    Ok(Estimate::within(
        k,
        k - CHART_READING,
        (k + CHART_READING).min(1.0),
    ))
}

/// `A_v(B) / A_v` against `b_v / 2 r_1`, taper ratio 0.6 and below (read from the chart).
const BODY_TAPER_06: [(f64, f64); 18] = [
    (0.25, 0.92),
    (0.5, 1.16),
    (0.75, 1.34),
    (1.0, 1.45),
    (1.25, 1.53),
    (1.5, 1.59),
    (1.75, 1.62),
    (2.0, 1.63),
    (2.5, 1.52),
    (2.75, 1.44),
    (3.0, 1.36),
    (3.25, 1.27),
    (3.5, 1.21),
    (4.0, 1.13),
    (4.5, 1.10),
    (5.0, 1.07),
    (6.0, 1.04),
    (7.0, 1.02),
];

/// `A_v(B) / A_v` against `b_v / 2 r_1`, taper ratio 1 (read from the chart).
const BODY_TAPER_10: [(f64, f64); 16] = [
    (0.25, 0.69),
    (0.5, 0.96),
    (0.75, 1.17),
    (1.0, 1.31),
    (1.5, 1.46),
    (1.75, 1.50),
    (2.0, 1.51),
    (2.5, 1.41),
    (2.75, 1.35),
    (3.0, 1.27),
    (3.5, 1.16),
    (4.0, 1.10),
    (4.5, 1.07),
    (5.0, 1.05),
    (6.0, 1.04),
    (7.0, 1.02),
];

/// `K_H` against `S_h / S_v` (read from the chart).
const K_H: [(f64, f64); 16] = [
    (0.0, 0.0),
    (0.1, 0.14),
    (0.2, 0.27),
    (0.3, 0.39),
    (0.4, 0.51),
    (0.5, 0.62),
    (0.6, 0.70),
    (0.7, 0.77),
    (0.8, 0.83),
    (0.9, 0.875),
    (1.0, 0.915),
    (1.2, 0.98),
    (1.4, 1.04),
    (1.6, 1.06),
    (1.8, 1.10),
    (2.0, 1.13),
];

/// The curves' `x / c_v` in [`TAILPLANE_ON_FIN`].
const TAILPLANE_X: [f64; 4] = [0.5, 0.6, 0.7, 0.8];

/// `A_v(HB) / A_v(B)` against `z_H / b_v` (rising from the fin's tip, -1, to the body's centre
/// line, 0), one column per `x / c_v` of [`TAILPLANE_X`] (read from the chart).
const TAILPLANE_ON_FIN: [(f64, [f64; 4]); 15] = [
    (-1.0, [1.68, 1.68, 1.68, 1.68]),
    (-0.95, [1.48, 1.49, 1.50, 1.52]),
    (-0.9, [1.33, 1.34, 1.35, 1.36]),
    (-0.8, [1.065, 1.08, 1.095, 1.11]),
    (-0.7, [0.925, 0.94, 0.955, 0.968]),
    (-0.6, [0.87, 0.885, 0.90, 0.925]),
    (-0.5, [0.855, 0.885, 0.91, 0.94]),
    (-0.4, [0.87, 0.915, 0.94, 0.965]),
    (-0.3, [0.90, 0.955, 0.99, 1.02]),
    (-0.25, [0.92, 0.98, 1.025, 1.06]),
    (-0.2, [0.94, 1.01, 1.06, 1.10]),
    (-0.15, [0.965, 1.04, 1.10, 1.14]),
    (-0.1, [0.99, 1.07, 1.135, 1.19]),
    (-0.05, [1.03, 1.11, 1.18, 1.24]),
    (0.0, [1.05, 1.145, 1.215, 1.29]),
];

/// A tailplane on a fin, in the terms of the DATCOM chart.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TailplaneOnFin {
    /// `S_h / S_v`.
    pub area_ratio: f64,
    /// `z_H / b_v`: the tailplane's aerodynamic centre above the body's centre line over the
    /// fin's span from it, negative up (0 at the centre line, -1 at the fin's tip).
    pub height_ratio: f64,
    /// `x / c_v`: its aerodynamic centre behind the fin's leading edge at its height, over the
    /// fin's chord there.
    pub chordwise_ratio: f64,
}

/// What a fin stands on and what crosses it, in the terms of the DATCOM charts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EndPlates {
    /// `b_v / 2 r_1`: the fin's span from the body's centre line over the body's depth at the
    /// fin (infinite where there is no body).
    pub span_over_body_depth: f64,
    pub taper_ratio: f64,
    pub tailplane: Option<TailplaneOnFin>,
}

/// A fin's effective aspect ratio and the chart readings it came from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EffectiveAspectRatio {
    /// `A_v(B) / A_v`.
    pub body_factor: Estimate,
    /// `A_v(HB) / A_v(B)` (exactly 1 with no tailplane).
    pub tailplane_factor: Estimate,
    /// `K_H` (0 with no tailplane).
    pub k_h: Estimate,
    pub aspect_ratio: Estimate,
}

/// [`FIN_ASPECT_RATIO`] for a fin of geometric aspect ratio `aspect_ratio` (`b_v^2 / S_v`).
pub fn fin_effective_aspect_ratio(
    aspect_ratio: f64,
    plates: &EndPlates,
) -> Result<EffectiveAspectRatio, EstimateError> {
    let a = positive("aspect_ratio", aspect_ratio)?;
    let body_factor = body_factor(plates.span_over_body_depth, plates.taper_ratio)?;
    let (tailplane_factor, k_h) = match &plates.tailplane {
        None => (Estimate::exact(1.0), Estimate::exact(0.0)),
        Some(t) => (tailplane_factor(t)?, k_h(t.area_ratio)?),
    };
    let combine = |b: f64, t: f64, k: f64| a * b * (1.0 + k * (t - 1.0));
    let value = combine(body_factor.value, tailplane_factor.value, k_h.value);
    let mut corners = Vec::with_capacity(8);
    for b in [body_factor.lower, body_factor.upper] {
        for t in [tailplane_factor.lower, tailplane_factor.upper] {
            for k in [k_h.lower, k_h.upper] {
                corners.push(combine(b, t, k));
            }
        }
    }
    let lower = corners.iter().copied().fold(f64::INFINITY, f64::min);
    let upper = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(EffectiveAspectRatio {
        body_factor,
        tailplane_factor,
        k_h,
        aspect_ratio: Estimate::within(value, lower, upper),
    })
}

/// `A_v(B) / A_v`, between the chart's two taper curves.
fn body_factor(ratio: f64, taper: f64) -> Result<Estimate, EstimateError> {
    if ratio.is_nan() || ratio < BODY_TAPER_06[0].0 {
        return Err(EstimateError::Domain {
            name: "b_v / 2 r_1 (the fin's span from the body's centre line over the body's depth)",
            value: ratio,
            method: "DATCOM's chart of A_v(B) / A_v",
            domain: "from 0.25 (a fin shorter than a quarter of the body's depth is not a fin on it)",
        });
    }
    if !(0.0..=1.0).contains(&taper) {
        return Err(EstimateError::Domain {
            name: "the fin's taper ratio",
            value: taper,
            method: "DATCOM's chart of A_v(B) / A_v",
            domain: "0 to 1",
        });
    }
    let last = BODY_TAPER_06[BODY_TAPER_06.len() - 1];
    if ratio > last.0 {
        // Past the chart both curves have come down to 1.02 and are still falling toward 1.
        return Ok(Estimate::within(last.1, 1.0, 1.05));
    }
    let at = |table: &[(f64, f64)]| interpolate(table, ratio).unwrap_or(1.0);
    let (low_taper, square) = (at(&BODY_TAPER_06), at(&BODY_TAPER_10));
    let f = ((taper - 0.6) / 0.4).clamp(0.0, 1.0);
    let value = low_taper + (square - low_taper) * f;
    Ok(Estimate::within(
        value,
        value - CHART_READING,
        value + CHART_READING,
    ))
}

/// `K_H` for `S_h / S_v`.
fn k_h(area_ratio: f64) -> Result<Estimate, EstimateError> {
    non_negative("S_h / S_v", area_ratio)?;
    let last = K_H[K_H.len() - 1];
    if area_ratio > last.0 {
        return Ok(Estimate::within(last.1, last.1 - 0.05, last.1 + 0.05));
    }
    let value = interpolate(&K_H, area_ratio).unwrap_or(last.1);
    Ok(Estimate::within(
        value,
        (value - CHART_READING).max(0.0),
        value + CHART_READING,
    ))
}

/// `A_v(HB) / A_v(B)` for a tailplane on the fin.
fn tailplane_factor(t: &TailplaneOnFin) -> Result<Estimate, EstimateError> {
    let h = t.height_ratio;
    if !(-1.0..=0.0).contains(&h) {
        return Err(EstimateError::Domain {
            name: "z_H / b_v (the tailplane's height on the fin)",
            value: h,
            method: "DATCOM's chart of A_v(HB) / A_v(B)",
            domain: "-1 (the fin's tip) to 0 (the body's centre line): the tailplane must cross the fin",
        });
    }
    finite(
        "x / c_v (the tailplane behind the fin's leading edge)",
        t.chordwise_ratio,
    )?;
    let curves: Vec<f64> = (0..4)
        .map(|k| {
            let column: Vec<(f64, f64)> = TAILPLANE_ON_FIN.iter().map(|r| (r.0, r.1[k])).collect();
            interpolate(&column, h).unwrap_or(1.0)
        })
        .collect();
    let x = t.chordwise_ratio;
    let (lo, hi) = (TAILPLANE_X[0], TAILPLANE_X[3]);
    if (lo..=hi).contains(&x) {
        let curve: Vec<(f64, f64)> = TAILPLANE_X
            .iter()
            .copied()
            .zip(curves.iter().copied())
            .collect();
        let value = interpolate(&curve, x).unwrap_or(curves[0]);
        return Ok(Estimate::within(
            value,
            value - CHART_READING,
            value + CHART_READING,
        ));
    }
    let value = if x < lo { curves[0] } else { curves[3] };
    let min = curves.iter().copied().fold(f64::INFINITY, f64::min);
    let max = curves.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(Estimate::within(
        value,
        min - CHART_READING,
        max + CHART_READING,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fin() -> Planform {
        Planform {
            span_m: 1.0,
            root_chord_m: 0.8,
            tip_chord_m: 0.6,
            half_chord_sweep_rad: 0.0,
            mirrored: false,
        }
    }

    /// Helmbold's equation in its two limits: the slender wing's `pi A / 2` (Jones) and
    /// lifting-line theory's `2 pi A / (A + 2)` with an elliptic loading; between them a known
    /// value (Anderson 1999 Example 2.8: A = 6, a0 = 6.02 per rad gives 4.4 per rad).
    #[test]
    fn helmbolds_slope_meets_its_limits_and_andersons_example() {
        let slope = |a: f64, k: f64| lift_slope(a, 0.0, k).unwrap().value;
        let slender = slope(1e-4, 2.0 * PI);
        assert!(
            (slender / (PI * 1e-4 / 2.0) - 1.0).abs() < 1e-4,
            "{slender}"
        );
        let long = slope(1e4, 2.0 * PI);
        let lifting_line = 2.0 * PI * 1e4 / (1e4 + 2.0);
        assert!((long / lifting_line - 1.0).abs() < 1e-6, "{long}");
        let example = slope(6.0, 6.02);
        assert!((example - 4.4).abs() < 0.05, "{example}");
        // Sweep lowers it; the range is the stated 10 %.
        let e = lift_slope(1.5, 30f64.to_radians(), 2.0 * PI).unwrap();
        assert!(e.value < slope(1.5, 2.0 * PI));
        assert!((e.upper / e.value - 1.1).abs() < 1e-12 && (e.lower / e.value - 0.9).abs() < 1e-12);
    }

    #[test]
    fn a_planforms_shape_is_its_geometry() {
        let f = fin();
        assert!((f.area_m2() - 0.7).abs() < 1e-12);
        assert!((f.aspect_ratio() - 1.0 / 0.7).abs() < 1e-12);
        // The centroid of a trapezoid's area: b/3 (1 + 2 l)/(1 + l), l = 0.75.
        assert!((f.centroid_from_root_m() - 2.5 / 5.25).abs() < 1e-12);
        assert!((f.chord_at(0.5) - 0.7).abs() < 1e-12);
        let tail = Planform {
            mirrored: true,
            ..f
        };
        assert_eq!(tail.panel_span_m(), 0.5);
        assert!((tail.leading_edge_sweep_tan() - 0.2).abs() < 1e-12);
        for bad in [
            Planform { span_m: 0.0, ..f },
            Planform {
                root_chord_m: -0.1,
                ..f
            },
            Planform {
                tip_chord_m: 0.9,
                ..f
            },
            Planform {
                span_m: f64::NAN,
                ..f
            },
        ] {
            assert!(bad.checked().is_err(), "{bad:?}");
        }
        assert!(f.checked().is_ok());
    }

    /// No body and no tailplane: the fin's own aspect ratio (the chart's far edge, 1.02, and a
    /// range down to 1). A tailplane at the fin's tip doubles nearly all of it (the chart's
    /// 1.68 with a large tailplane); one at mid-height lowers it.
    #[test]
    fn end_plates_raise_a_fins_aspect_ratio_as_the_charts_say() {
        let bare = EndPlates {
            span_over_body_depth: f64::INFINITY,
            taper_ratio: 0.75,
            tailplane: None,
        };
        let e = fin_effective_aspect_ratio(1.5, &bare).unwrap();
        assert!((e.aspect_ratio.value - 1.5 * 1.02).abs() < 1e-12);
        assert!((e.aspect_ratio.lower - 1.5).abs() < 1e-12);
        let t_tail = EndPlates {
            tailplane: Some(TailplaneOnFin {
                area_ratio: 2.0,
                height_ratio: -1.0,
                chordwise_ratio: 0.6,
            }),
            ..bare
        };
        let t = fin_effective_aspect_ratio(1.5, &t_tail).unwrap();
        let expected = 1.5 * 1.02 * (1.0 + 1.13 * 0.68);
        assert!((t.aspect_ratio.value - expected).abs() < 1e-9, "{t:?}");
        let mid = EndPlates {
            tailplane: Some(TailplaneOnFin {
                area_ratio: 1.0,
                height_ratio: -0.5,
                chordwise_ratio: 0.6,
            }),
            ..bare
        };
        let m = fin_effective_aspect_ratio(1.5, &mid).unwrap();
        assert!(m.aspect_ratio.value < e.aspect_ratio.value, "{m:?}");
        // A body as deep as the fin is long, with a taper of 0.6: the chart's peak region.
        let deep = EndPlates {
            span_over_body_depth: 2.0,
            taper_ratio: 0.6,
            tailplane: None,
        };
        let d = fin_effective_aspect_ratio(1.5, &deep).unwrap();
        assert!((d.body_factor.value - 1.63).abs() < 1e-12, "{d:?}");
        // Between the taper curves, linearly.
        let between = body_factor(2.0, 0.8).unwrap().value;
        assert!((between - (1.63 + 1.51) / 2.0).abs() < 1e-12);
    }

    /// A tailplane off the chart's x / c_v takes the nearest curve, and the range spans the
    /// four; one off the fin, or a fin far shorter than the body is deep, is refused.
    #[test]
    fn charts_refuse_what_they_do_not_cover() {
        let ahead = TailplaneOnFin {
            area_ratio: 0.6,
            height_ratio: -0.2,
            chordwise_ratio: 0.0,
        };
        let f = tailplane_factor(&ahead).unwrap();
        assert!((f.value - 0.94).abs() < 1e-12, "{f:?}");
        assert!((f.upper - (1.10 + CHART_READING)).abs() < 1e-12, "{f:?}");
        let off = TailplaneOnFin {
            height_ratio: 0.3,
            ..ahead
        };
        assert!(matches!(
            tailplane_factor(&off),
            Err(EstimateError::Domain { .. })
        ));
        assert!(body_factor(0.1, 0.5).is_err());
        assert!(body_factor(2.0, 1.5).is_err());
        assert!(k_h(-0.1).is_err());
        assert!(
            fin_effective_aspect_ratio(
                0.0,
                &EndPlates {
                    span_over_body_depth: 3.0,
                    taper_ratio: 0.5,
                    tailplane: None,
                }
            )
            .is_err()
        );
    }
}
