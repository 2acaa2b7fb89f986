//! `trim`: one trimmed flight condition of an aircraft: controls, attitudes, rotor speed,
//! rotor thrust, flapping and inflow.

use super::result::{Evaluated, Quantities, compare_all};
use super::{At, CheckKind, CheckSpec, Cx, Evaluate, Expectation, Kind, Refusal, Trivial};
use crate::quantity::{self as q, Quantity as Q};
use crate::subject::Subject;
use crate::yaml::InputError;

/// A `trim` check: its flight condition.
#[derive(Debug, Clone, PartialEq)]
pub struct TrimCheck {
    pub condition: crate::TrimRequest,
}

impl Kind for TrimCheck {
    const KIND: CheckKind = CheckKind::Trim;
    const FIELDS: &'static [&'static str] = &["condition"];
    const SUBJECTS: &'static str = "an aircraft";

    fn runs_on(subject: &Subject) -> bool {
        super::is_aircraft(subject)
    }

    fn resolve(cx: &Cx, spec: &CheckSpec) -> Result<Self, InputError> {
        let condition = cx.needs(&spec.condition, "condition")?;
        super::check_condition(cx, &condition, false)?;
        Ok(Self { condition })
    }
}

impl Evaluate for TrimCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::TRIM)
    }

    fn trivial(
        &self,
        _subject: &Subject,
        expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        refuse_enforced(expectations)?;
        Ok(vec![])
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let Subject::Aircraft { file, loading } = at.subject else {
            return Err("a trim check needs an aircraft".into());
        };
        let values = trim_quantities(file, *loading, self.condition)?;
        Ok(Evaluated::of(compare_all(expectations, &values)?))
    }
}

/// Refuses an expectation of what the trim solves for: a trim whose scaled residuals exceed
/// 1e-7, or whose rotor is not free, is an error, so such a check cannot fail.
pub fn refuse_enforced(expectations: &[Expectation]) -> Result<(), Refusal> {
    for q in q::ENFORCED_BY_TRIM {
        if expectations.iter().any(|e| e.quantity == q.name()) {
            return Err((
                format!(".expect.{q}"),
                format!(
                    "`{q}` is what the trim solves for (a trim whose scaled residuals exceed \
                     1e-7, or whose rotor is not free, is an error): a check of it cannot fail"
                ),
            ));
        }
    }
    Ok(())
}

/// The quantities of one trim (see [`crate::quantity::TRIM`]).
pub fn trim_quantities(
    file: &crate::aircraft_file::AircraftFile,
    loading: crate::Loading,
    request: crate::TrimRequest,
) -> Result<Quantities, String> {
    let t = crate::run_trim(&file.aircraft, request, loading).map_err(|e| e.to_string())?;
    Ok(trim_quantities_of(&file.aircraft, loading, &t))
}

/// The quantities of a trim of `aircraft` at `loading`.
pub fn trim_quantities_of(
    aircraft: &cierva_model::aircraft::Aircraft,
    loading: crate::Loading,
    t: &cierva_model::aircraft::trim::Trim,
) -> Quantities {
    let d = f64::to_degrees;
    let r = &t.averaged.rotor;
    let c = &t.controls;
    vec![
        (Q::ResidualNorm.name(), t.residual_norm),
        (
            Q::StickLongitudinalPercent.name(),
            c.stick_longitudinal_percent,
        ),
        (Q::StickLateralPercent.name(), c.stick_lateral_percent),
        (Q::PedalPercent.name(), c.pedal_percent),
        (Q::ThrottlePercent.name(), c.throttle_percent),
        (Q::PitchDeg.name(), d(t.pitch_rad)),
        (Q::RollDeg.name(), d(t.roll_rad)),
        (Q::AlphaDeg.name(), d(t.alpha_rad)),
        (Q::SideslipDeg.name(), d(t.sideslip_rad)),
        (Q::RotorRpm.name(), t.rotor_rpm),
        (Q::PropellerRpm.name(), t.propeller_rpm),
        (Q::RotorTorqueNM.name(), r.driving_torque_n_m),
        (Q::ThrustN.name(), r.thrust_n),
        (Q::DiscAlphaDeg.name(), d(r.disc_alpha_rad)),
        (Q::TipSpeedRatio.name(), r.tip_speed_ratio),
        (Q::ThrustCoefficientOverSolidity.name(), {
            let rotor = &aircraft.main_rotor.rotor;
            let rho = cierva_model::components::atmosphere::at_density_altitude(
                loading.density_altitude_ft * crate::FT_TO_M,
            )
            .map_or(f64::NAN, |a| a.density_kg_m3);
            let tip = t.state.rotor_omega_rad_s * rotor.radius_m;
            r.thrust_n
                / (rho * std::f64::consts::PI * rotor.radius_m.powi(2) * tip * tip)
                / rotor.solidity()
        }),
        (Q::A1Deg.name(), d(r.a1_rad)),
        (Q::B1Deg.name(), d(r.b1_rad)),
        (Q::InflowV0MS.name(), t.state.inflow.v0),
        (Q::InflowV1cMS.name(), t.state.inflow.v1c),
    ]
}
