//! `autorotation`: an isolated rotor's autorotative equilibrium in a wind tunnel (NACA TR 515,
//! TR 487): rotor speed, lift and drag coefficients, inflow and flapping at a tunnel condition;
//! or, at a tip-speed ratio and rotor speed, the angle of attack at which it autorotates.

use super::result::{Evaluated, Finding, Found, Quantities, compare_all};
use super::{At, CheckSpec, Cx, Evaluate, Expectation, Kind, Measured, Place, Placed, Snapshotted};
use crate::checks::subject::Subject;
use crate::inputs::quantity::{self as q, Quantity as Q};
use crate::inputs::yaml::InputError;
use serde::{Deserialize, Serialize};

/// A wind-tunnel condition: the angle of attack and either the airspeed or the tip-speed ratio
/// with the rotor speed that the airspeed follows from (`V = mu Omega R / cos alpha`, TR 515).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TunnelSpec {
    /// Absent: the angle is found at `tip_speed_ratio` and `rotor_rpm` (how TR 515 plots its
    /// data), and the check computes it as `rotor_alpha_deg`.
    #[serde(default)]
    pub alpha_deg: Option<f64>,
    #[serde(default)]
    pub airspeed_m_s: Option<f64>,
    #[serde(default)]
    pub tip_speed_ratio: Option<f64>,
    /// Rotor speed, rpm (`rpm` is the same key).
    #[serde(default, alias = "rpm")]
    pub rotor_rpm: Option<f64>,
    /// Blade pitch at the rotor's reference station, deg (default: the file's pitch as it is).
    #[serde(default)]
    pub collective_deg: Option<f64>,
    /// Air density (default ISA sea level).
    #[serde(default)]
    pub density_kg_m3: Option<f64>,
}

/// An `autorotation` check: its tunnel condition.
#[derive(Debug, Clone, PartialEq)]
pub struct AutorotationCheck {
    pub tunnel: TunnelSpec,
}

/// An `autorotation` check's own fields, as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AutorotationSpec {
    /// The tunnel condition.
    pub tunnel: TunnelSpec,
}

impl Kind for AutorotationCheck {
    type Spec = AutorotationSpec;
    const SUBJECTS: &'static str = "a rotor";

    fn runs_on(subject: &Subject) -> bool {
        matches!(subject, Subject::Rotor { .. })
    }

    fn resolve(cx: &Cx, own: AutorotationSpec, written: &CheckSpec) -> Result<Self, InputError> {
        let tunnel = own.tunnel;
        check_tunnel(cx, &tunnel)?;
        if tunnel.alpha_deg.is_some() && written.expect.contains_key(Q::RotorAlphaDeg.name()) {
            return Err(cx.err(
                ".expect.rotor_alpha_deg",
                "the tunnel gives `alpha_deg`, so `rotor_alpha_deg` reads it back: check it with the angle left out (`tunnel: {tip_speed_ratio, rotor_rpm}`), where it is found",
            ));
        }
        Ok(Self { tunnel })
    }
}

impl Evaluate for AutorotationCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::AUTOROTATION)
    }

    fn tunnel(&self) -> Option<&TunnelSpec> {
        Some(&self.tunnel)
    }

    fn is_table_row(&self) -> bool {
        true
    }

    fn measured(&self) -> Measured<'_> {
        Measured::At(Place::Tunnel(&self.tunnel))
    }

    fn placed(&self) -> Option<Placed<'_>> {
        Some(Placed::Tunnel(&self.tunnel))
    }

    fn snapshotted(&self) -> Vec<Snapshotted<'_>> {
        vec![Snapshotted::Autorotation(&self.tunnel)]
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let Subject::Rotor {
            file,
            solver,
            overrides,
        } = at.subject
        else {
            return Err("an autorotation check needs a rotor".into());
        };
        let note = (!overrides.is_empty()).then(|| overrides.join("; "));
        match autorotation_quantities(&file.rotor, *solver, &self.tunnel)? {
            Ok(a) => Ok(Evaluated {
                quantities: compare_all(expectations, &a.quantities)?,
                finding: a.outside_validity(),
                note,
                ..Evaluated::default()
            }),
            Err((finding, fingerprint)) => Ok(Evaluated {
                finding: Some(finding),
                fingerprint,
                note,
                ..Evaluated::default()
            }),
        }
    }
}

fn check_tunnel(cx: &Cx, t: &TunnelSpec) -> Result<(), InputError> {
    let finite = |v: Option<f64>| v.is_none_or(f64::is_finite);
    if !finite(t.alpha_deg)
        || !finite(t.airspeed_m_s)
        || !finite(t.tip_speed_ratio)
        || !finite(t.rotor_rpm)
        || !finite(t.collective_deg)
        || !finite(t.density_kg_m3)
    {
        return Err(cx.err(
            ".tunnel",
            "every number of the tunnel condition must be finite",
        ));
    }
    match (t.alpha_deg, t.airspeed_m_s, t.tip_speed_ratio, t.rotor_rpm) {
        (Some(_), Some(_), None, None) | (_, None, Some(_), Some(_)) => Ok(()),
        _ => Err(cx.err(
            ".tunnel",
            "give `alpha_deg` with either `airspeed_m_s`, or `tip_speed_ratio` with `rotor_rpm` (the airspeed then follows as mu Omega R / cos alpha); or `tip_speed_ratio` with `rotor_rpm` alone (the angle is then found)",
        )),
    }
}

/// The airspeed of a tunnel condition (given, or `mu Omega R / cos alpha`; unknown, NaN, while
/// the angle is to be found).
pub fn tunnel_airspeed_m_s(t: &TunnelSpec, radius_m: f64) -> f64 {
    match (t.airspeed_m_s, t.tip_speed_ratio, t.rotor_rpm, t.alpha_deg) {
        (Some(v), _, _, _) => v,
        (None, Some(mu), Some(rpm), Some(alpha)) => {
            mu * rpm * std::f64::consts::PI / 30.0 * radius_m / alpha.to_radians().cos()
        }
        _ => f64::NAN,
    }
}

/// An autorotative equilibrium's quantities, and where the model's equations were used
/// outside their validity to find them (empty where nowhere).
#[derive(Debug, Clone, PartialEq)]
pub struct TunnelAnswer {
    pub quantities: Quantities,
    pub outside_validity: Vec<String>,
}

impl TunnelAnswer {
    /// The finding where an equation was used outside its validity (the check does not pass).
    pub fn outside_validity(&self) -> Option<Finding> {
        (!self.outside_validity.is_empty()).then(|| Finding::OutsideValidity {
            reason: self.outside_validity.join("; "),
        })
    }
}

/// The quantities of an autorotation check, or what the model found instead (no
/// equilibrium). An error is a condition the model could not be run at.
pub fn autorotation_quantities(
    rotor: &cierva_model::components::rotor::Rotor,
    solver: cierva_model::components::autorotation::AutorotationOptions,
    t: &TunnelSpec,
) -> Result<Result<TunnelAnswer, Found>, String> {
    let run = match (t.alpha_deg, t.tip_speed_ratio, t.rotor_rpm) {
        (Some(alpha), ..) => crate::run::autorotation::run_autorotation(
            rotor,
            alpha,
            tunnel_airspeed_m_s(t, rotor.radius_m),
            t.collective_deg,
            t.density_kg_m3,
            solver,
        )
        .map(|a| (alpha, a)),
        (None, Some(mu), Some(rpm)) => {
            crate::run::autorotation::run_autorotation_at_tip_speed_ratio(
                rotor,
                mu,
                rpm,
                t.collective_deg,
                t.density_kg_m3,
                solver,
            )
            .map(|f| (f.alpha_rad.to_degrees(), f.autorotation))
        }
        _ => return Err("the tunnel condition is incomplete".into()),
    };
    let (alpha_deg, a) = match run {
        Ok(a) => a,
        Err(crate::run::autorotation::AutorotateError::Autorotation(e)) => {
            return match no_equilibrium(&e) {
                Some(numbers) => Ok(Err((
                    Finding::NoEquilibrium {
                        reason: e.to_string(),
                    },
                    numbers,
                ))),
                None => Err(e.to_string()),
            };
        }
        Err(e) => return Err(e.to_string()),
    };
    Ok(Ok(TunnelAnswer {
        quantities: quantities_of(alpha_deg, &a),
        outside_validity: a.outside_validity.clone(),
    }))
}

/// The quantities of an autorotative equilibrium at `alpha_deg`, by the names checks use.
pub fn quantities_of(
    alpha_deg: f64,
    a: &cierva_model::components::autorotation::Autorotation,
) -> Quantities {
    vec![
        (Q::RotorAlphaDeg.name(), alpha_deg),
        (Q::RotorRpm.name(), a.rpm),
        (Q::RotorOmegaRadS.name(), a.omega_rad_s),
        (Q::TipSpeedRatio.name(), a.tip_speed_ratio),
        (Q::LiftCoefficient.name(), a.lift_coefficient),
        (Q::DragCoefficient.name(), a.drag_coefficient),
        (Q::LiftToDrag.name(), a.lift_to_drag),
        (Q::ThrustCoefficient.name(), a.thrust_coefficient),
        (Q::InflowV0MS.name(), a.inflow.v0),
        (Q::ConingDeg.name(), a.a0_rad.to_degrees()),
        (Q::A1Deg.name(), a.a1_rad.to_degrees()),
        (Q::B1Deg.name(), a.b1_rad.to_degrees()),
    ]
}

/// An autorotation's quantities, or why there are none in words (a finding or an error):
/// quantities found with an equation outside its validity are not an answer (a fit does not
/// fit to them).
pub fn quantities_or_reason(
    r: Result<Result<TunnelAnswer, Found>, String>,
) -> Result<Quantities, String> {
    match r {
        Ok(Ok(a)) => match a.outside_validity() {
            None => Ok(a.quantities),
            Some(f) => Err(f.describe()),
        },
        Ok(Err((Finding::NoEquilibrium { reason }, _))) | Err(reason) => Err(reason),
        Ok(Err((f, _))) => Err(f.describe()),
    }
}

/// When an autorotation error is the model finding no equilibrium (not a condition it cannot
/// be run at): the number that says how far it was from one.
fn no_equilibrium(
    e: &cierva_model::components::autorotation::AutorotationError,
) -> Option<Vec<(String, f64)>> {
    use cierva_model::components::autorotation::AutorotationError as A;
    use cierva_model::solve::SolveError;
    let largest = |v: &mut dyn Iterator<Item = f64>| v.fold(f64::NEG_INFINITY, f64::max);
    let (name, value) = match e {
        A::NoAngle { torques, .. } => (
            "largest_torque_coefficient_over_solidity",
            largest(&mut torques.iter().map(|t| t.1)),
        ),
        A::SlowBranch { alpha_deg, .. } => ("slow_branch_alpha_deg", *alpha_deg),
        A::NoBracket { torques, .. } => (
            "largest_torque_coefficient_over_solidity",
            largest(&mut torques.iter().copied()),
        ),
        A::Solve(SolveError::NoConvergence { residuals, .. }) => (
            "largest_scaled_residual",
            residuals.iter().fold(0.0f64, |m, r| m.max(r.abs())),
        ),
        _ => return None,
    };
    Some(vec![(name.to_string(), value)])
}
