//! Blade section aerodynamics: lift and drag coefficients against angle of attack and Mach
//! number, from tables (bilinear interpolation) or from an analytical section.
//!
//! Angles of attack are wrapped to (-pi, pi]: a blade element in reverse flow (the inboard
//! retreating side) sees angles near +-pi.

use serde::Serialize;
use std::f64::consts::{FRAC_PI_2, PI};
use thiserror::Error;

/// A blade section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Airfoil {
    /// Linear lift up to stall, a drag polar, and a continuous post-stall extension.
    Analytical(AnalyticalSection),
    /// Tables in angle of attack and Mach number.
    Table(SectionTable),
}

/// The analytical section.
///
/// * `|alpha| <= stall`: `cl = a (alpha - alpha_0)`, `cd = cd0 + cd1 alpha + cd2 alpha^2`;
/// * `stall < |alpha| <= pi/2`: `cl` falls linearly from its stall value to zero at 90 deg;
///   `cd` rises as `cd_stall + 2 (sin^2 alpha - sin^2 stall)` (a flat plate's 2 at 90 deg);
/// * `|alpha| > pi/2` (reverse flow): flat plate, `cl = sin 2 alpha`; the drag is the mirror
///   image of the above about 90 deg (the flow meets the reversed section at `pi - |alpha|`),
///   so it falls back to the polar near 180 deg and is never below the section's least drag.
///
/// Both coefficients are continuous in `alpha`. Mach number is ignored unless the section has
/// [`Compressibility`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AnalyticalSection {
    pub lift_slope_per_rad: f64,
    pub zero_lift_alpha_rad: f64,
    pub cd0: f64,
    pub cd1_per_rad: f64,
    pub cd2_per_rad2: f64,
    pub stall_alpha_rad: f64,
    /// Compressibility (none: the incompressible section at every Mach number).
    pub compressibility: Option<Compressibility>,
}

/// Compressibility of an analytical section, below the speed of sound:
///
/// * lift: Prandtl-Glauert, the lift of the attached and stalling section (to 90 deg) divided
///   by `sqrt(1 - M^2)` (Glauert 1928), with `M` held at [`PRANDTL_GLAUERT_MACH_LIMIT`] above
///   it (the small-disturbance rule fails as the flow goes transonic);
/// * drag: Lock's fourth-power drag rise above the drag-divergence Mach number `M_dd`,
///   `cd += 20 (M - M_dd)^4` (Lock 1951, as Leishman gives it), at every angle of attack.
///
/// The stall angle does not move with Mach number, and reverse flow (a flat plate) is left as
/// it is: both are beyond what the two rules describe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Compressibility {
    pub drag_divergence_mach: f64,
}

/// The Mach number above which Prandtl-Glauert's factor is held (its value there, 2.29).
pub const PRANDTL_GLAUERT_MACH_LIMIT: f64 = 0.9;

impl Compressibility {
    /// Prandtl-Glauert's lift factor `1 / sqrt(1 - M^2)`, held above the limit.
    pub fn lift_factor(&self, mach: f64) -> f64 {
        let m = mach.abs().min(PRANDTL_GLAUERT_MACH_LIMIT);
        1.0 / (1.0 - m * m).sqrt()
    }

    /// Lock's drag rise `20 (M - M_dd)^4` above drag divergence, zero below.
    pub fn drag_rise(&self, mach: f64) -> f64 {
        let excess = (mach.abs() - self.drag_divergence_mach).max(0.0);
        20.0 * excess.powi(4)
    }
}

/// Coefficient tables: `cl[m][a]` and `cd[m][a]` at `mach[m]` and `alpha_deg[a]`.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionTable {
    pub alpha_deg: Vec<f64>,
    pub mach: Vec<f64>,
    pub cl: Vec<Vec<f64>>,
    pub cd: Vec<Vec<f64>>,
}

/// A section that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AirfoilError {
    #[error("{0} must be finite")]
    NotFinite(&'static str),
    #[error("the stall angle must be in (0, 90) deg, got {0} rad")]
    StallAngle(f64),
    #[error("lift slope must be positive, got {0} per rad")]
    LiftSlope(f64),
    #[error(
        "the section's drag must not be negative (no section has a thrust of its own), but it is {least} at {alpha_deg} deg"
    )]
    NegativeDrag { least: f64, alpha_deg: f64 },
    #[error(
        "table angles of attack must rise strictly and span -180 to 180 deg (got {first} to {last})"
    )]
    AlphaRange { first: f64, last: f64 },
    #[error("table Mach numbers must rise strictly from a value >= 0")]
    MachRange,
    #[error("the drag-divergence Mach number must be in (0, 1), got {0}")]
    DragDivergence(f64),
    #[error(
        "table `{name}` must be {rows} rows (one per Mach number) of {cols} values (one per angle)"
    )]
    TableShape {
        name: &'static str,
        rows: usize,
        cols: usize,
    },
}

/// Wraps an angle to (-pi, pi].
pub fn wrap_pi(a: f64) -> f64 {
    // Almost every angle of attack is already in range: no division then.
    if a > -PI && a <= PI {
        return a;
    }
    let mut x = (a + PI).rem_euclid(2.0 * PI) - PI;
    if x <= -PI {
        x += 2.0 * PI;
    }
    x
}

impl AnalyticalSection {
    /// Checks the section's numbers.
    pub fn validate(&self) -> Result<(), AirfoilError> {
        for (n, v) in [
            ("lift_slope_per_rad", self.lift_slope_per_rad),
            ("zero_lift_alpha_rad", self.zero_lift_alpha_rad),
            ("cd0", self.cd0),
            ("cd1_per_rad", self.cd1_per_rad),
            ("cd2_per_rad2", self.cd2_per_rad2),
            ("stall_alpha_rad", self.stall_alpha_rad),
        ] {
            if !v.is_finite() {
                return Err(AirfoilError::NotFinite(n));
            }
        }
        if self.lift_slope_per_rad <= 0.0 {
            return Err(AirfoilError::LiftSlope(self.lift_slope_per_rad));
        }
        if !(0.0 < self.stall_alpha_rad && self.stall_alpha_rad < FRAC_PI_2) {
            return Err(AirfoilError::StallAngle(self.stall_alpha_rad));
        }
        // The polar's least below stall: at either end, or at its vertex between them.
        let s = self.stall_alpha_rad;
        let polar = |x: f64| self.cd0 + self.cd1_per_rad * x + self.cd2_per_rad2 * x * x;
        let vertex = if self.cd2_per_rad2 > 0.0 {
            Some(-self.cd1_per_rad / (2.0 * self.cd2_per_rad2)).filter(|x| x.abs() <= s)
        } else {
            None
        };
        let (least, at) = [-s, s]
            .into_iter()
            .chain(vertex)
            .map(|x| (polar(x), x))
            .fold((f64::INFINITY, 0.0), |m, p| if p.0 < m.0 { p } else { m });
        if least < 0.0 {
            return Err(AirfoilError::NegativeDrag {
                least,
                alpha_deg: at.to_degrees(),
            });
        }
        if let Some(c) = self.compressibility {
            let m = c.drag_divergence_mach;
            if !(m.is_finite() && 0.0 < m && m < 1.0) {
                return Err(AirfoilError::DragDivergence(m));
            }
        }
        Ok(())
    }

    /// The coefficients at a Mach number: the incompressible section's, with
    /// [`Compressibility`] where the section has it.
    fn coefficients_at(&self, alpha: f64, mach: f64) -> (f64, f64) {
        let (cl, cd) = self.coefficients(alpha);
        match self.compressibility {
            None => (cl, cd),
            Some(c) => {
                let lift = if wrap_pi(alpha).abs() <= FRAC_PI_2 {
                    c.lift_factor(mach)
                } else {
                    1.0
                };
                (cl * lift, cd + c.drag_rise(mach))
            }
        }
    }

    fn coefficients(&self, alpha: f64) -> (f64, f64) {
        let a = wrap_pi(alpha);
        let s = self.stall_alpha_rad;
        let polar = |x: f64| self.cd0 + self.cd1_per_rad * x + self.cd2_per_rad2 * x * x;
        if a.abs() <= s {
            return (
                self.lift_slope_per_rad * (a - self.zero_lift_alpha_rad),
                polar(a),
            );
        }
        let sign = a.signum();
        // Drag beyond stall, and in reverse flow its mirror image about 90 deg: the flow meets
        // the reversed section at `pi - |alpha|`, so the drag falls back to the polar's near
        // 180 deg and never below the section's least drag.
        let forward = |x: f64| {
            if x.abs() <= s {
                polar(x)
            } else {
                polar(x.signum() * s) + 2.0 * (x.sin().powi(2) - s.sin().powi(2))
            }
        };
        if a.abs() <= FRAC_PI_2 {
            let cl_stall = self.lift_slope_per_rad * (sign * s - self.zero_lift_alpha_rad);
            (
                cl_stall * (FRAC_PI_2 - a.abs()) / (FRAC_PI_2 - s),
                forward(a),
            )
        } else {
            ((2.0 * a).sin(), forward(sign * (PI - a.abs())))
        }
    }
}

impl SectionTable {
    /// Checks shapes and ranges.
    pub fn validate(&self) -> Result<(), AirfoilError> {
        let (na, nm) = (self.alpha_deg.len(), self.mach.len());
        let first = self.alpha_deg.first().copied().unwrap_or(f64::NAN);
        let last = self.alpha_deg.last().copied().unwrap_or(f64::NAN);
        let rising =
            |v: &[f64]| v.windows(2).all(|w| w[1] > w[0]) && v.iter().all(|x| x.is_finite());
        if na < 2 || !rising(&self.alpha_deg) || first > -180.0 || last < 180.0 {
            return Err(AirfoilError::AlphaRange { first, last });
        }
        if nm == 0 || !rising(&self.mach) || self.mach[0] < 0.0 {
            return Err(AirfoilError::MachRange);
        }
        for (name, t) in [("cl", &self.cl), ("cd", &self.cd)] {
            if t.len() != nm || t.iter().any(|r| r.len() != na) {
                return Err(AirfoilError::TableShape {
                    name,
                    rows: nm,
                    cols: na,
                });
            }
            if t.iter().flatten().any(|x| !x.is_finite()) {
                return Err(AirfoilError::NotFinite(name));
            }
        }
        for row in &self.cd {
            if let Some((k, least)) = row.iter().enumerate().find(|(_, c)| **c < 0.0) {
                return Err(AirfoilError::NegativeDrag {
                    least: *least,
                    alpha_deg: self.alpha_deg[k],
                });
            }
        }
        Ok(())
    }

    fn coefficients(&self, alpha: f64, mach: f64) -> (f64, f64) {
        let a = wrap_pi(alpha).to_degrees();
        let (ia, fa) = bracket(&self.alpha_deg, a);
        let (im, fm) = bracket(&self.mach, mach);
        let lerp2 = |t: &Vec<Vec<f64>>| {
            let row = |m: usize| t[m][ia] * (1.0 - fa) + t[m][ia + 1] * fa;
            if self.mach.len() == 1 {
                row(0)
            } else {
                row(im) * (1.0 - fm) + row(im + 1) * fm
            }
        };
        (lerp2(&self.cl), lerp2(&self.cd))
    }
}

/// Index `i` and fraction `f` with `x = v[i] (1-f) + v[i+1] f`, clamped to the table's ends.
fn bracket(v: &[f64], x: f64) -> (usize, f64) {
    if v.len() < 2 || x <= v[0] {
        return (0, 0.0);
    }
    let n = v.len();
    if x >= v[n - 1] {
        return (n - 2, 1.0);
    }
    let i = v.partition_point(|&y| y <= x) - 1;
    (i, (x - v[i]) / (v[i + 1] - v[i]))
}

impl Airfoil {
    /// Checks the section.
    pub fn validate(&self) -> Result<(), AirfoilError> {
        match self {
            Self::Analytical(s) => s.validate(),
            Self::Table(t) => t.validate(),
        }
    }

    /// Lift and drag coefficients at an angle of attack (rad) and Mach number.
    ///
    /// Table Mach numbers outside the table are clamped to its first or last column.
    pub fn coefficients(&self, alpha_rad: f64, mach: f64) -> (f64, f64) {
        match self {
            Self::Analytical(s) => s.coefficients_at(alpha_rad, mach),
            Self::Table(t) => t.coefficients(alpha_rad, mach),
        }
    }

    /// The lift-curve slope at zero lift, per rad (for Lock number and classical estimates).
    pub fn lift_slope_per_rad(&self) -> f64 {
        match self {
            Self::Analytical(s) => s.lift_slope_per_rad,
            Self::Table(t) => {
                let h = 1e-3;
                (t.coefficients(h, 0.0).0 - t.coefficients(-h, 0.0).0) / (2.0 * h)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section() -> AnalyticalSection {
        AnalyticalSection {
            lift_slope_per_rad: 5.85,
            zero_lift_alpha_rad: 0.0,
            cd0: 0.012,
            cd1_per_rad: 0.0,
            cd2_per_rad2: 0.0,
            stall_alpha_rad: 12f64.to_radians(),
            compressibility: None,
        }
    }

    /// Compressibility: at Mach 0 the section is the incompressible one; at Mach 0.6 the lift
    /// slope is Prandtl-Glauert's 1.25 times, held at the limit beyond 0.9; the drag rises as
    /// Lock's `20 (M - M_dd)^4` from drag divergence (0.002 at 0.1 above it), continuously, at
    /// any angle; lift stays continuous through stall and 90 deg; a drag-divergence Mach number
    /// outside (0, 1) is refused.
    #[test]
    fn compressibility_is_prandtl_glauert_lift_and_lock_s_drag_rise() {
        let plain = section();
        let s = AnalyticalSection {
            compressibility: Some(Compressibility {
                drag_divergence_mach: 0.7,
            }),
            ..plain
        };
        let a = Airfoil::Analytical(s);
        let p = Airfoil::Analytical(plain);
        for alpha in [-0.3, 0.05, 0.5, 2.0, 3.0] {
            assert_eq!(a.coefficients(alpha, 0.0), p.coefficients(alpha, 0.0));
        }
        let slope = |m: f64| (a.coefficients(0.01, m).0 - a.coefficients(-0.01, m).0) / 0.02;
        assert!((slope(0.6) / slope(0.0) - 1.25).abs() < 1e-12);
        let held = 1.0 / (1.0 - 0.81f64).sqrt();
        assert!((slope(0.95) / slope(0.0) - held).abs() < 1e-12);
        for alpha in [0.05, 0.3, 2.5] {
            let rise = |m: f64| a.coefficients(alpha, m).1 - p.coefficients(alpha, m).1;
            assert_eq!(rise(0.7), 0.0);
            assert!((rise(0.8) - 0.002).abs() < 1e-12, "{}", rise(0.8));
            assert!(rise(0.7 + 1e-6) < 1e-20);
        }
        let stall = s.stall_alpha_rad;
        for at in [stall, FRAC_PI_2] {
            let (below, above) = (
                a.coefficients(at - 1e-9, 0.6).0,
                a.coefficients(at + 1e-9, 0.6).0,
            );
            assert!((below - above).abs() < 1e-6, "{at}: {below} {above}");
        }
        for bad in [0.0, 1.0, f64::NAN] {
            let s = AnalyticalSection {
                compressibility: Some(Compressibility {
                    drag_divergence_mach: bad,
                }),
                ..plain
            };
            assert!(s.validate().is_err(), "{bad}");
        }
    }

    #[test]
    fn analytical_section_is_continuous_everywhere() {
        let s = section();
        let mut prev = s.coefficients(-PI + 1e-9);
        let n = 20_000;
        for k in 1..=n {
            let a = -PI + 2.0 * PI * k as f64 / n as f64;
            let c = s.coefficients(a);
            assert!(
                (c.0 - prev.0).abs() < 0.01 && (c.1 - prev.1).abs() < 0.01,
                "jump at {a}"
            );
            prev = c;
        }
        assert!((s.coefficients(0.1).0 - 0.585).abs() < 1e-12);
        assert!(
            (s.coefficients(FRAC_PI_2).1 - (0.012 + 2.0 - 2.0 * 12f64.to_radians().sin().powi(2)))
                .abs()
                < 1e-12
        );
    }

    /// Section drag never falls below the section's least forward drag, at any angle: a drag
    /// below it (negative at 180 deg, as the reverse-flow extension once gave) is a spurious
    /// forward force and driving torque on the retreating side.
    #[test]
    fn analytical_drag_never_falls_below_its_minimum() {
        let cambered = AnalyticalSection {
            zero_lift_alpha_rad: -2f64.to_radians(),
            cd1_per_rad: -0.02,
            cd2_per_rad2: 0.9,
            ..section()
        };
        for s in [section(), cambered] {
            let n = 36_000;
            let forward_min = (0..=n)
                .map(|k| -s.stall_alpha_rad + 2.0 * s.stall_alpha_rad * k as f64 / n as f64)
                .map(|a| s.coefficients(a).1)
                .fold(f64::INFINITY, f64::min);
            assert!(forward_min > 0.0);
            for k in 0..=n {
                let a = -PI + 2.0 * PI * k as f64 / n as f64;
                let cd = s.coefficients(a).1;
                assert!(
                    cd >= forward_min - 1e-12,
                    "cd {cd} below the minimum {forward_min} at {:.2} deg",
                    a.to_degrees()
                );
            }
            // Reverse flow along the chord is the section's least drag again, not a thrust.
            let (cl, cd) = s.coefficients(PI);
            assert!(cl.abs() < 1e-12 && cd > 0.0, "{cl} {cd}");
        }
    }

    #[test]
    fn tables_interpolate_and_validate() {
        let t = SectionTable {
            alpha_deg: vec![-180.0, 0.0, 180.0],
            mach: vec![0.0, 1.0],
            cl: vec![vec![0.0, 0.0, 0.0], vec![1.0, 1.0, 1.0]],
            cd: vec![vec![1.0, 0.0, 1.0], vec![1.0, 0.0, 1.0]],
        };
        t.validate().unwrap();
        let (cl, cd) = t.coefficients(FRAC_PI_2, 0.25);
        assert!((cl - 0.25).abs() < 1e-12 && (cd - 0.5).abs() < 1e-12);
        let mut bad = t.clone();
        bad.alpha_deg = vec![-10.0, 0.0, 10.0];
        assert!(matches!(
            bad.validate(),
            Err(AirfoilError::AlphaRange { .. })
        ));
        let mut bad = t.clone();
        bad.cl.pop();
        assert!(matches!(
            bad.validate(),
            Err(AirfoilError::TableShape { .. })
        ));
    }

    #[test]
    fn angles_wrap() {
        assert!((wrap_pi(3.0 * PI / 2.0) - -FRAC_PI_2).abs() < 1e-12);
        assert_eq!(wrap_pi(PI), PI);
        assert!((wrap_pi(-PI) - PI).abs() < 1e-12);
    }
}
