//! The isolated rotor in a tunnel: the air, the collective, and its autorotation.

/// Why an autorotation run did not produce an equilibrium.
#[derive(Debug, thiserror::Error)]
pub enum AutorotateError {
    #[error("{0}")]
    Atmosphere(#[from] cierva_model::components::atmosphere::AtmosphereError),
    #[error("{0}")]
    Autorotation(#[from] cierva_model::components::autorotation::AutorotationError),
}

impl AutorotateError {
    /// Whether the inputs were at fault (rather than the solution).
    pub fn is_input(&self) -> bool {
        use cierva_model::components::autorotation::AutorotationError as A;
        matches!(
            self,
            Self::Atmosphere(_) | Self::Autorotation(A::Condition { .. } | A::Rotor(_))
        )
    }
}

/// The isolated rotor in a tunnel at `alpha_deg` and `airspeed_m_s`, with the blade pitch at the
/// reference station set to `collective_deg` (or the file's pitch as it is) and the density
/// given (or ISA sea level; the speed of sound follows from the density altitude).
pub fn run_autorotation(
    rotor: &cierva_model::components::rotor::Rotor,
    alpha_deg: f64,
    airspeed_m_s: f64,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
    options: impl Into<cierva_model::components::autorotation::AutorotationOptions>,
) -> Result<cierva_model::components::autorotation::Autorotation, AutorotateError> {
    use cierva_model::components::autorotation::{Tunnel, autorotate};
    let (air, collective_shift_rad) = tunnel_air(rotor, collective_deg, density_kg_m3)?;
    let tunnel = Tunnel {
        alpha_rad: alpha_deg.to_radians(),
        airspeed_m_s,
        density_kg_m3: air.density_kg_m3,
        speed_of_sound_m_s: air.speed_of_sound_m_s,
        collective_shift_rad,
    };
    Ok(autorotate(rotor, tunnel, options.into())?)
}

/// A tunnel's air (at `density_kg_m3`, or ISA sea level; the speed of sound from the density
/// altitude) and the pitch shift that sets the rotor's reference pitch to `collective_deg`
/// (none: the file's pitch as it is).
fn tunnel_air(
    rotor: &cierva_model::components::rotor::Rotor,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
) -> Result<(cierva_model::components::atmosphere::AirState, f64), AutorotateError> {
    use cierva_model::components::atmosphere;
    let air = match density_kg_m3 {
        Some(rho) => atmosphere::at_density_altitude(atmosphere::density_altitude_m(rho)?)?,
        None => atmosphere::Atmosphere::standard().at(0.0)?,
    };
    let shift = collective_deg.map_or(0.0, |c| rotor.collective_shift_for(c.to_radians()));
    Ok((air, shift))
}

/// The isolated rotor at a tip-speed ratio and rotor speed (rpm): the angle of attack and
/// airspeed at which it autorotates there, with the equilibrium (the collective and air as
/// [`run_autorotation`] takes them).
pub fn run_autorotation_at_tip_speed_ratio(
    rotor: &cierva_model::components::rotor::Rotor,
    tip_speed_ratio: f64,
    rotor_rpm: f64,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
    options: impl Into<cierva_model::components::autorotation::AutorotationOptions>,
) -> Result<cierva_model::components::autorotation::AtTipSpeedRatio, AutorotateError> {
    use cierva_model::components::autorotation::{
        TipSpeedCondition, autorotate_at_tip_speed_ratio,
    };
    let (air, collective_shift_rad) = tunnel_air(rotor, collective_deg, density_kg_m3)?;
    Ok(autorotate_at_tip_speed_ratio(
        rotor,
        TipSpeedCondition {
            tip_speed_ratio,
            omega_rad_s: rotor_rpm * std::f64::consts::PI / 30.0,
            density_kg_m3: air.density_kg_m3,
            speed_of_sound_m_s: air.speed_of_sound_m_s,
            collective_shift_rad,
        },
        options.into(),
    )?)
}

/// An autorotative equilibrium's quantities (by the names checks use), and where the model's
/// equations were used outside their validity to find them (empty where nowhere).
#[derive(Debug, Clone, PartialEq)]
pub struct TunnelAnswer {
    pub quantities: Vec<(&'static str, f64)>,
    pub outside_validity: Vec<String>,
}

/// What a rotor in a tunnel does at a condition: autorotates (an equilibrium), or has no
/// equilibrium there (a physical answer, not an evaluation error), with the number that says
/// how far it was from one.
#[derive(Debug, Clone, PartialEq)]
pub enum Autorotated {
    Equilibrium(TunnelAnswer),
    NoEquilibrium {
        reason: String,
        numbers: Vec<(String, f64)>,
    },
}

impl Autorotated {
    /// Its quantities, or why there are none in words: quantities found with an equation
    /// outside its validity are not an answer (a fit does not fit to them).
    pub fn quantities_or_reason(self) -> Result<Vec<(&'static str, f64)>, String> {
        match self {
            Self::Equilibrium(a) if a.outside_validity.is_empty() => Ok(a.quantities),
            Self::Equilibrium(a) => Err(format!(
                "outside validity: {}",
                a.outside_validity.join("; ")
            )),
            Self::NoEquilibrium { reason, .. } => Err(reason),
        }
    }
}

/// The rotor's autorotation at a tunnel condition: its equilibrium's quantities, or no
/// equilibrium. An error is a condition the model could not be run at.
pub fn at_tunnel(
    rotor: &cierva_model::components::rotor::Rotor,
    solver: cierva_model::components::autorotation::AutorotationOptions,
    t: &crate::inputs::condition::TunnelSpec,
) -> Result<Autorotated, String> {
    let run = match (t.alpha_deg, t.tip_speed_ratio, t.rotor_rpm) {
        (Some(alpha), ..) => run_autorotation(
            rotor,
            alpha,
            crate::inputs::condition::tunnel_airspeed_m_s(t, rotor.radius_m),
            t.collective_deg,
            t.density_kg_m3,
            solver,
        )
        .map(|a| (alpha, a)),
        (None, Some(mu), Some(rpm)) => run_autorotation_at_tip_speed_ratio(
            rotor,
            mu,
            rpm,
            t.collective_deg,
            t.density_kg_m3,
            solver,
        )
        .map(|f| (f.alpha_rad.to_degrees(), f.autorotation)),
        _ => return Err("the tunnel condition is incomplete".into()),
    };
    let (alpha_deg, a) = match run {
        Ok(a) => a,
        Err(AutorotateError::Autorotation(e)) => {
            return match no_equilibrium(&e) {
                Some(numbers) => Ok(Autorotated::NoEquilibrium {
                    reason: e.to_string(),
                    numbers,
                }),
                None => Err(e.to_string()),
            };
        }
        Err(e) => return Err(e.to_string()),
    };
    Ok(Autorotated::Equilibrium(TunnelAnswer {
        quantities: quantities_of(alpha_deg, &a),
        outside_validity: a.outside_validity.clone(),
    }))
}

/// The quantities of an autorotative equilibrium at `alpha_deg`, by the names checks use.
pub fn quantities_of(
    alpha_deg: f64,
    a: &cierva_model::components::autorotation::Autorotation,
) -> Vec<(&'static str, f64)> {
    use crate::inputs::quantity::Quantity as Q;
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
