//! A body (a gyroplane's pod) in sideslip: the prolate spheroid of its length and cross-section,
//! its apparent-mass factors, the destabilising couple of its potential flow (Munk's), and the
//! sidewash its cross-flow makes at a point behind it.
//!
//! In potential flow a body moving with velocity `(u, v, w)` through still air carries the
//! momentum of its apparent masses, `k1 rho Vol` along its axis and `k2 rho Vol` across it, and
//! feels the couple `-(U x P)` of that momentum: a pure couple (no net force), yawing the nose
//! away from the wind. For a body of revolution along body x it is
//! `N = -(k2 - k1) rho Vol u v` (and the same about the pitch axis with `w`): with `q = rho V^2
//! / 2` and no angle of attack, `N = -(k2 - k1) Vol q sin 2 beta`, Munk's airship-hull moment,
//! whose derivative at zero sideslip is `N_beta = -2 (k2 - k1) Vol q`. The real body's
//! boundary layer separates on its after body and gives back part of it, so potential flow is
//! the upper end of what it can be.
//!
//! The cross-flow round the body is, far from it, a doublet across the stream of strength
//! `(1 + k2) Vol v / (4 pi)` (the sphere's `a^3 v / 2` when `k2 = 1/2`). At a point a distance
//! `r` behind it on its axis (normal to the doublet's axis) the flow speeds up as it does at a
//! sphere's equator: the fluid alongside a body moving sideways flows against the body's motion,
//! so relative to the body the cross-flow there is `(1 + k2) Vol / (4 pi r^3)` larger than the
//! sideslip's. A fin there sees more sideslip, not less: the pod's sidewash gradient is
//! negative, `-(1 + k2) Vol / (4 pi r^3)`.

use super::{Estimate, EstimateError, Method, positive};
use serde::Serialize;
use std::f64::consts::PI;

/// A pod as the prolate spheroid of its length and of the cross-section of its width and
/// height (an ellipse of the same area: diameter `sqrt(width height)`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Pod {
    pub length_m: f64,
    pub width_m: f64,
    pub height_m: f64,
}

impl Pod {
    /// Checks the pod: positive dimensions, and at least as long as its equivalent diameter
    /// (the apparent masses here are a prolate spheroid's).
    pub fn checked(&self) -> Result<&Self, EstimateError> {
        positive("length_m", self.length_m)?;
        positive("width_m", self.width_m)?;
        positive("height_m", self.height_m)?;
        if self.length_m < self.diameter_m() {
            return Err(EstimateError::Domain {
                name: "length over equivalent diameter",
                value: self.fineness(),
                method: "a prolate spheroid's apparent masses (Lamb)",
                domain: "at least 1: a pod shorter than it is wide is not a slender body",
            });
        }
        Ok(self)
    }

    /// The diameter of the circle with the cross-section's area, `sqrt(width height)`.
    pub fn diameter_m(&self) -> f64 {
        (self.width_m * self.height_m).sqrt()
    }

    /// Length over equivalent diameter.
    pub fn fineness(&self) -> f64 {
        self.length_m / self.diameter_m()
    }

    /// The spheroid's volume, `pi L d^2 / 6`.
    pub fn volume_m3(&self) -> f64 {
        PI * self.length_m * self.diameter_m().powi(2) / 6.0
    }
}

/// A prolate spheroid's apparent-mass factors.
pub const APPARENT_MASS: Method = Method {
    name: "apparent-mass factors of a prolate spheroid",
    source: "Lamb 1932 Art. 373: with e = sqrt(1 - (d / L)^2), alpha0 = 2 (1 - e^2) / e^3 (artanh e - e), beta0 = 1 / e^2 - (1 - e^2) / e^3 artanh e, k1 = alpha0 / (2 - alpha0) along the axis and k2 = beta0 / (2 - beta0) across it (Munk 1924 tabulates the same)",
    accuracy: "exact for the spheroid in potential flow; the pod is not a spheroid, which the Munk couple's range carries",
};

/// `(k1, k2)` of a prolate spheroid of fineness `length / diameter` (1: a sphere, 1/2 each).
pub fn apparent_mass_factors(fineness: f64) -> Result<(f64, f64), EstimateError> {
    positive("length over diameter", fineness)?;
    if fineness < 1.0 {
        return Err(EstimateError::Domain {
            name: "length over diameter",
            value: fineness,
            method: "a prolate spheroid's apparent masses",
            domain: "at least 1",
        });
    }
    let e2 = 1.0 - 1.0 / (fineness * fineness);
    if e2 < 1e-6 {
        // The sphere (within 1e-6 of it the factors are 1/2 to 1e-7; the formulas below lose
        // their digits to cancellation there).
        return Ok((0.5, 0.5));
    }
    let e = e2.sqrt();
    let log = e.atanh();
    let alpha0 = 2.0 * (1.0 - e2) / (e2 * e) * (log - e);
    let beta0 = 1.0 / e2 - (1.0 - e2) / (e2 * e) * log;
    Ok((alpha0 / (2.0 - alpha0), beta0 / (2.0 - beta0)))
}

/// The pod's Munk couple in sideslip.
pub const MUNK_YAW: Method = Method {
    name: "the pod's destabilising potential-flow couple in sideslip (Munk)",
    source: "Munk 1924 (NACA TR 184): the couple of an airship hull is (k2 - k1) Vol q sin 2 beta, away from the wind; here N = -K rho u_p v_p about the pod's centroid with K = (k2 - k1) Vol of the pod's spheroid (N_beta = -2 K q at zero sideslip); the centroid's velocity carries the yaw rate, and with the axial apparent mass's side force the pod gives N_r = -k2 rho Vol u x_p (Kirchhoff's equations for a solid moving through a liquid, Lamb 1932 Ch. VI)",
    accuracy: "estimated: 0.5 to 1.0 of the value: potential flow is the upper end (the after body's separated boundary layer gives part of the couple back, the more so the blunter the body), and a pod with an open cockpit and an engine behind it is neither a spheroid nor closed",
};

/// [`MUNK_YAW`]'s `K = (k2 - k1) Vol`, m^3.
pub fn munk_yaw_m3(pod: &Pod) -> Result<Estimate, EstimateError> {
    pod.checked()?;
    let (k1, k2) = apparent_mass_factors(pod.fineness())?;
    let k = (k2 - k1) * pod.volume_m3();
    Ok(Estimate::within(k, 0.5 * k, k))
}

/// The sidewash of a pod's cross-flow at a point behind it.
pub const BODY_SIDEWASH: Method = Method {
    name: "sidewash of the pod's cross-flow at the fin",
    source: "the far field of the pod's cross-flow, a doublet of strength (1 + k2) Vol v / (4 pi) (potential flow, Lamb 1932 Arts. 92 and 373): at a distance r behind it on its axis the flow is sped up, as at a sphere's equator, so the share of the sideslip added is (1 + k2) Vol / (4 pi r^3) and the gradient its negative; DATCOM's wing-body sidewash correlation (Sec. 5.4.1.1) needs a wing and does not apply to a gyroplane's pod",
    accuracy: "estimated: 0 to 3 times the value: the doublet is the field far from the body and the fin is little more than a pod's length behind it; the separated wake at small sideslip adds no cross-flow of its own",
};

/// [`BODY_SIDEWASH`]: the sidewash gradient of the pod's cross-flow at `distance_m` behind its
/// centroid (the model's `wash_gradient`, which takes `wash x v` from the sideslip): negative,
/// since the pod's cross-flow adds to the sideslip there.
pub fn sidewash_gradient(pod: &Pod, distance_m: f64) -> Result<Estimate, EstimateError> {
    pod.checked()?;
    let r = positive("distance from the pod to the fin", distance_m)?;
    let (_, k2) = apparent_mass_factors(pod.fineness())?;
    let added = (1.0 + k2) * pod.volume_m3() / (4.0 * PI * r.powi(3));
    Ok(Estimate::within(-added, -3.0 * added, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The spheroid's factors: 1/2 each for the sphere, smoothly; toward 0 and 1 as it grows
    /// slender; the ellipsoid's identity `alpha0 + 2 beta0 = 2` (Lamb Art. 373); and the values
    /// usually quoted from Lamb's table to three figures (L/d = 2: 0.209 and 0.702; 4: 0.082 and
    /// 0.860; 10: 0.021 and 0.960), within 3e-3.
    #[test]
    fn apparent_masses_are_lambs() {
        for (f, k1, k2) in [
            (2.0, 0.209, 0.702),
            (4.0, 0.082, 0.860),
            (10.0, 0.021, 0.960),
        ] {
            let (a, b) = apparent_mass_factors(f).unwrap();
            assert!(
                (a - k1).abs() < 3e-3 && (b - k2).abs() < 3e-3,
                "{f}: {a} {b}"
            );
            // k = x / (2 - x) inverts to x = 2 k / (1 + k).
            let (alpha0, beta0) = (2.0 * a / (1.0 + a), 2.0 * b / (1.0 + b));
            assert!((alpha0 + 2.0 * beta0 - 2.0).abs() < 1e-12, "{f}");
        }
        let (a, b) = apparent_mass_factors(1.0).unwrap();
        assert!((a - 0.5).abs() < 1e-12 && (b - 0.5).abs() < 1e-12);
        let (a, b) = apparent_mass_factors(1.001).unwrap();
        assert!((a - 0.5).abs() < 2e-3 && (b - 0.5).abs() < 2e-3, "{a} {b}");
        let (a, b) = apparent_mass_factors(1e3).unwrap();
        assert!(a < 1e-4 && (1.0 - b) < 1e-4, "{a} {b}");
        assert!(apparent_mass_factors(0.5).is_err());
    }

    /// The couple of a sphere is zero (k1 = k2); of a long spheroid it tends to its volume.
    #[test]
    fn the_munk_couple_grows_with_slenderness() {
        let sphere = Pod {
            length_m: 1.0,
            width_m: 1.0,
            height_m: 1.0,
        };
        assert!(munk_yaw_m3(&sphere).unwrap().value.abs() < 1e-9);
        let long = Pod {
            length_m: 20.0,
            ..sphere
        };
        let k = munk_yaw_m3(&long).unwrap();
        assert!((k.value / long.volume_m3() - 0.985).abs() < 0.01, "{k:?}");
        assert_eq!(k.upper, k.value);
        assert!((k.lower - 0.5 * k.value).abs() < 1e-12);
        let flat = Pod {
            length_m: 0.5,
            ..sphere
        };
        assert!(munk_yaw_m3(&flat).is_err());
        assert!(
            munk_yaw_m3(&Pod {
                width_m: 0.0,
                ..sphere
            })
            .is_err()
        );
    }

    /// The sphere's doublet: a^3 / (2 r^3) of the cross-flow at distance r, added to it. The
    /// sphere in a cross-stream `U`, potential `U (r + a^3 / (2 r^2)) cos theta` (Lamb Art. 92),
    /// has at a point on the axis normal to the stream the lateral velocity `U (1 + a^3 / (2
    /// r^3))` (1.5 U at its equator): the fin there sees more sideslip, so the gradient is
    /// `-a^3 / (2 r^3)`, within `[-3, 0]` times the doublet's. It was `+a^3 / (2 r^3)` (issue
    /// 52, item 2).
    #[test]
    fn the_sidewash_far_behind_a_sphere_adds_its_doublets_cross_flow() {
        let sphere = Pod {
            length_m: 2.0,
            width_m: 2.0,
            height_m: 2.0,
        };
        let (a, r) = (1.0_f64, 5.0_f64);
        // The potential's lateral velocity on the normal axis, by a central difference of
        // phi = U (y + a^3 y / (2 rho^3)) along y at (x = r, y = 0), over U.
        let phi = |y: f64| {
            let rho = (r * r + y * y).sqrt();
            y + a.powi(3) * y / (2.0 * rho.powi(3))
        };
        let h = 1e-5;
        let lateral = (phi(h) - phi(-h)) / (2.0 * h);
        let s = sidewash_gradient(&sphere, r).unwrap();
        assert!((s.value - (1.0 - lateral)).abs() < 1e-9, "{s:?} {lateral}");
        assert!((s.value + 1.0 / (2.0 * 125.0)).abs() < 1e-12, "{s:?}");
        assert_eq!((s.lower, s.upper), (3.0 * s.value, 0.0));
        assert!(sidewash_gradient(&sphere, 0.0).is_err());
    }
}
