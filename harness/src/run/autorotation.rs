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
