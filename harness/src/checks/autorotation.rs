//! `autorotation`: an isolated rotor's autorotative equilibrium in a wind tunnel (NACA TR 515,
//! TR 487): rotor speed, lift and drag coefficients, inflow and flapping at a tunnel condition;
//! or, at a tip-speed ratio and rotor speed, the angle of attack at which it autorotates.

use super::result::{Evaluated, Finding, Found, compare_all};
use super::{At, CheckSpec, Cx, Evaluate, Expectation, Kind, Measured, Place, Placed, Snapshotted};
use crate::checks::subject::Subject;
use crate::external::TunnelRequest;
use crate::inputs::condition::TunnelSpec;
use crate::inputs::quantity::{self as q, Quantity as Q};
use crate::inputs::yaml::InputError;
use crate::run::autorotation::Autorotated;
use serde::Deserialize;

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
    const SUBJECTS: &'static str = "a rotor, or an external model that autorotates";

    fn runs_on(subject: &Subject) -> bool {
        matches!(subject, Subject::Rotor { .. } | Subject::External(_))
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

    fn series(&self) -> Option<String> {
        Some("autorotation".into())
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
        let model = super::model_of(at.subject)
            .ok_or("an autorotation check needs a model that autorotates in a tunnel")?;
        let note = match at.subject {
            Subject::Rotor { overrides, .. } if !overrides.is_empty() => Some(overrides.join("; ")),
            _ => None,
        };
        let a = model.autorotation(&TunnelRequest {
            tunnel: self.tunnel,
            parameters: Default::default(),
        })?;
        let found = finding_of(&a);
        match a {
            Autorotated::Equilibrium(e) => Ok(Evaluated {
                quantities: compare_all(expectations, &e.quantities)?,
                finding: found.map(|f| f.0),
                note,
                ..Evaluated::default()
            }),
            Autorotated::NoEquilibrium { .. } => {
                let (finding, fingerprint) = found.expect("no equilibrium is a finding");
                Ok(Evaluated {
                    finding: Some(finding),
                    fingerprint,
                    note,
                    ..Evaluated::default()
                })
            }
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

/// An autorotation's finding where there is one: no equilibrium (with the number that says how
/// far from one), or quantities found with an equation used outside its validity.
fn finding_of(a: &Autorotated) -> Option<Found> {
    match a {
        Autorotated::Equilibrium(e) => (!e.outside_validity.is_empty()).then(|| {
            (
                Finding::OutsideValidity {
                    reason: e.outside_validity.join("; "),
                },
                Vec::new(),
            )
        }),
        Autorotated::NoEquilibrium { reason, numbers } => Some((
            Finding::NoEquilibrium {
                reason: reason.clone(),
            },
            numbers.clone(),
        )),
    }
}
