//! A flight condition as people give it (`condition:` in cases and fit files, the command
//! line's airspeed, climb and turn) and where and how heavy the aircraft flies.

use crate::units::{MPH_PER_KN, MPH_TO_M_S};

/// A trim request in the units people fly in. As written (in a case's `condition`), the airspeed
/// may be in any of `airspeed_mph`, `airspeed_kn` or `airspeed_m_s` (exactly one); it is held in
/// mph.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(try_from = "ConditionSpec")]
pub struct TrimRequest {
    /// True airspeed, mph.
    pub airspeed_mph: f64,
    /// Rate of climb, m/s (negative descends).
    #[serde(default)]
    pub climb_m_s: f64,
    /// Rate of turn, deg/s (positive to starboard).
    #[serde(default)]
    pub turn_rate_deg_s: f64,
}

impl TrimRequest {
    /// Straight and level flight at `airspeed_mph`.
    pub fn level(airspeed_mph: f64) -> Self {
        Self {
            airspeed_mph,
            climb_m_s: 0.0,
            turn_rate_deg_s: 0.0,
        }
    }
}

/// A flight condition as written: one airspeed in the unit of its key.
#[derive(Debug, Clone, Copy, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ConditionSpec {
    #[serde(default)]
    airspeed_mph: Option<f64>,
    #[serde(default)]
    airspeed_kn: Option<f64>,
    #[serde(default)]
    airspeed_m_s: Option<f64>,
    #[serde(default)]
    climb_m_s: f64,
    #[serde(default)]
    turn_rate_deg_s: f64,
}

impl TryFrom<ConditionSpec> for TrimRequest {
    type Error = String;

    fn try_from(c: ConditionSpec) -> Result<Self, String> {
        let airspeed_mph = match (c.airspeed_mph, c.airspeed_kn, c.airspeed_m_s) {
            (Some(v), None, None) => v,
            (None, Some(v), None) => v * MPH_PER_KN,
            (None, None, Some(v)) => v / MPH_TO_M_S,
            _ => {
                return Err(
                    "give exactly one airspeed: `airspeed_mph`, `airspeed_kn` or `airspeed_m_s`"
                        .into(),
                );
            }
        };
        Ok(Self {
            airspeed_mph,
            climb_m_s: c.climb_m_s,
            turn_rate_deg_s: c.turn_rate_deg_s,
        })
    }
}

/// Where and how heavy: the air (ISA at a density altitude) and the mass (the aircraft file's
/// unless given; inertias stay as the file gives them, a fuel-state change near the c.g.).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Loading {
    pub mass_kg: Option<f64>,
    pub density_altitude_ft: f64,
}

/// A wind-tunnel condition: the angle of attack and either the airspeed or the tip-speed ratio
/// with the rotor speed that the airspeed follows from (`V = mu Omega R / cos alpha`, TR 515).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
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
