//! International Standard Atmosphere (ICAO Doc 7488): troposphere and lower stratosphere, with
//! offsets of sea-level temperature and pressure (seed 000 Sec. III, seed 001 Table 1).
//!
//! Pressure follows the standard lapse from the (offset) sea-level pressure as a function of
//! geopotential altitude; temperature is the standard temperature plus the sea-level offset
//! (an ISA+dT day); density is `p / (R T)`. Density altitude is the altitude at which the
//! *standard* atmosphere has a given density.

use serde::Serialize;
use thiserror::Error;

/// Sea-level standard temperature, K.
pub const T0_K: f64 = 288.15;
/// Sea-level standard pressure, Pa.
pub const P0_PA: f64 = 101_325.0;
/// Sea-level standard density, kg/m^3.
pub const RHO0_KG_M3: f64 = 1.225;
/// Troposphere lapse rate, K/m.
pub const LAPSE_K_M: f64 = 0.0065;
/// Specific gas constant of dry air, J/(kg K).
pub const R_J_KG_K: f64 = 287.052_87;
/// Standard gravity, m/s^2.
pub const G0_M_S2: f64 = 9.806_65;
/// Ratio of specific heats of air.
pub const GAMMA: f64 = 1.4;
/// Top of the troposphere, m.
pub const TROPOPAUSE_M: f64 = 11_000.0;
/// Highest altitude modelled (top of the isothermal layer), m.
pub const CEILING_M: f64 = 20_000.0;
/// Lowest altitude accepted, m.
pub const FLOOR_M: f64 = -1_000.0;

/// The atmosphere of the day.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Atmosphere {
    /// Sea-level temperature minus the standard 288.15 K.
    pub sea_level_temperature_offset_k: f64,
    /// Sea-level pressure minus the standard 101 325 Pa.
    pub sea_level_pressure_offset_pa: f64,
}

impl Default for Atmosphere {
    fn default() -> Self {
        Self::standard()
    }
}

/// Air properties at one altitude.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AirState {
    pub temperature_k: f64,
    pub pressure_pa: f64,
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
}

/// Out-of-range atmosphere inputs.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AtmosphereError {
    #[error("altitude {0} m is outside the modelled range {FLOOR_M} m to {CEILING_M} m")]
    AltitudeOutOfRange(f64),
    #[error("density {0} kg/m^3 is not a positive finite number within the modelled range")]
    DensityOutOfRange(f64),
    #[error(
        "the day's offsets give a non-physical atmosphere (temperature {temperature_k} K, pressure {pressure_pa} Pa)"
    )]
    NonPhysical {
        temperature_k: f64,
        pressure_pa: f64,
    },
}

impl Atmosphere {
    /// The standard day.
    pub const fn standard() -> Self {
        Self {
            sea_level_temperature_offset_k: 0.0,
            sea_level_pressure_offset_pa: 0.0,
        }
    }

    /// Air at a geopotential altitude.
    pub fn at(&self, altitude_m: f64) -> Result<AirState, AtmosphereError> {
        if !(FLOOR_M..=CEILING_M).contains(&altitude_m) {
            return Err(AtmosphereError::AltitudeOutOfRange(altitude_m));
        }
        let (t_std, p_ratio) = standard_ratios(altitude_m);
        let temperature_k = t_std + self.sea_level_temperature_offset_k;
        let pressure_pa = (P0_PA + self.sea_level_pressure_offset_pa) * p_ratio;
        if temperature_k <= 0.0 || pressure_pa <= 0.0 || !temperature_k.is_finite() {
            return Err(AtmosphereError::NonPhysical {
                temperature_k,
                pressure_pa,
            });
        }
        Ok(state(temperature_k, pressure_pa))
    }
}

/// Standard temperature and pressure ratio `p/p0` at a geopotential altitude.
fn standard_ratios(h: f64) -> (f64, f64) {
    let n = G0_M_S2 / (R_J_KG_K * LAPSE_K_M);
    if h <= TROPOPAUSE_M {
        let t = T0_K - LAPSE_K_M * h;
        (t, (t / T0_K).powf(n))
    } else {
        let t11 = T0_K - LAPSE_K_M * TROPOPAUSE_M;
        let p11 = (t11 / T0_K).powf(n);
        (
            t11,
            p11 * (-G0_M_S2 * (h - TROPOPAUSE_M) / (R_J_KG_K * t11)).exp(),
        )
    }
}

fn state(temperature_k: f64, pressure_pa: f64) -> AirState {
    AirState {
        temperature_k,
        pressure_pa,
        density_kg_m3: pressure_pa / (R_J_KG_K * temperature_k),
        speed_of_sound_m_s: (GAMMA * R_J_KG_K * temperature_k).sqrt(),
    }
}

/// The standard atmosphere at a density altitude (the air a density altitude stands for).
pub fn at_density_altitude(density_altitude_m: f64) -> Result<AirState, AtmosphereError> {
    Atmosphere::standard().at(density_altitude_m)
}

/// The density altitude of a density: the standard-atmosphere altitude with that density.
pub fn density_altitude_m(density_kg_m3: f64) -> Result<f64, AtmosphereError> {
    let lo = at_density_altitude(CEILING_M)
        .expect("in range")
        .density_kg_m3;
    let hi = at_density_altitude(FLOOR_M)
        .expect("in range")
        .density_kg_m3;
    if !(lo..=hi).contains(&density_kg_m3) {
        return Err(AtmosphereError::DensityOutOfRange(density_kg_m3));
    }
    // Density decreases monotonically with altitude: bisection to 1 mm.
    let (mut a, mut b) = (FLOOR_M, CEILING_M);
    while b - a > 1e-3 {
        let m = 0.5 * (a + b);
        if at_density_altitude(m).expect("in range").density_kg_m3 > density_kg_m3 {
            a = m;
        } else {
            b = m;
        }
    }
    Ok(0.5 * (a + b))
}

/// Feet to metres.
pub const FT_TO_M: f64 = 0.3048;

/// Sutherland's constant `beta_s` of ICAO Doc 7488's viscosity law, kg/(m s K^0.5).
pub const SUTHERLAND_BETA: f64 = 1.458e-6;
/// Sutherland's temperature `S` of ICAO Doc 7488's viscosity law, K.
pub const SUTHERLAND_S_K: f64 = 110.4;

/// The dynamic viscosity of air at a temperature, Pa s: Sutherland's law as ICAO Doc 7488
/// gives it, `beta_s T^1.5 / (T + S)` (1.7894e-5 Pa s at 288.15 K).
pub fn dynamic_viscosity_pa_s(temperature_k: f64) -> f64 {
    SUTHERLAND_BETA * temperature_k.powf(1.5) / (temperature_k + SUTHERLAND_S_K)
}

/// The temperature of air whose speed of sound is `a`: `a^2 / (gamma R)`, K. The rotor's
/// operating condition carries the speed of sound; this recovers the temperature its
/// viscosity needs.
pub fn temperature_from_speed_of_sound_k(speed_of_sound_m_s: f64) -> f64 {
    speed_of_sound_m_s * speed_of_sound_m_s / (GAMMA * R_J_KG_K)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viscosity_is_the_standard_atmosphere_s() {
        // ICAO Doc 7488's tabulated viscosity: 1.7894e-5 Pa s at sea level, 1.4216e-5 Pa s at
        // 11 km (216.65 K); printed to 5 figures.
        assert!((dynamic_viscosity_pa_s(T0_K) - 1.7894e-5).abs() < 0.00005e-5);
        assert!((dynamic_viscosity_pa_s(216.65) - 1.4216e-5).abs() < 0.00005e-5);
        let sea = Atmosphere::standard().at(0.0).unwrap();
        let t = temperature_from_speed_of_sound_k(sea.speed_of_sound_m_s);
        assert!((t - T0_K).abs() < 1e-9, "{t}");
    }

    #[test]
    fn standard_values_match_the_icao_table() {
        // ICAO Doc 7488 (1993), Table I: sea level and 11 000 m; 2000 ft = 609.6 m.
        let sl = Atmosphere::standard().at(0.0).unwrap();
        assert!((sl.density_kg_m3 - 1.225).abs() < 1e-4);
        assert!((sl.speed_of_sound_m_s - 340.294).abs() < 1e-2);
        let t = Atmosphere::standard().at(11_000.0).unwrap();
        assert!((t.temperature_k - 216.65).abs() < 1e-9);
        assert!((t.pressure_pa - 22_632.0).abs() < 2.0);
        assert!((t.density_kg_m3 - 0.3639).abs() < 1e-3);
        let h = Atmosphere::standard().at(2000.0 * FT_TO_M).unwrap();
        assert!((h.density_kg_m3 - 1.1549).abs() < 5e-4, "{h:?}");
    }

    #[test]
    fn density_altitude_inverts_the_standard_atmosphere() {
        for h in [-500.0, 0.0, 609.6, 3000.0, 12_000.0] {
            let rho = at_density_altitude(h).unwrap().density_kg_m3;
            assert!((density_altitude_m(rho).unwrap() - h).abs() < 1e-2);
        }
        // A hot day has a density altitude above its pressure altitude.
        let hot = Atmosphere {
            sea_level_temperature_offset_k: 20.0,
            ..Atmosphere::standard()
        };
        let rho = hot.at(0.0).unwrap().density_kg_m3;
        assert!(density_altitude_m(rho).unwrap() > 500.0);
    }

    #[test]
    fn out_of_range_is_an_error() {
        assert!(Atmosphere::standard().at(25_000.0).is_err());
        assert!(Atmosphere::standard().at(f64::NAN).is_err());
        assert!(density_altitude_m(-1.0).is_err());
        let absurd = Atmosphere {
            sea_level_temperature_offset_k: -400.0,
            ..Atmosphere::standard()
        };
        assert!(matches!(
            absurd.at(0.0),
            Err(AtmosphereError::NonPhysical { .. })
        ));
    }
}
