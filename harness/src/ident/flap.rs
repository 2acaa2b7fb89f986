//! Inflow from teeter records (seed 003): disc tilts by a harmonic fit over whole revolutions
//! (Eqs. 13-14), then the inflow components and coning (Eqs. 15-17 and 19).
//!
//! A teeter record has [`FLAP_REQUIRED`] channels: the teeter angle of the reference blade
//! (positive flapping back when that blade is over the nose), its azimuth measured from the
//! front of the disc, the rotor speed, and the hub's speeds in shaft axes (in-plane, and along
//! the shaft downwards, positive with the air coming up through the disc), which the data
//! reduction derives from air data, attitudes and the shaft's tilt.

use crate::inputs::record::Record;
use cierva_model::analysis::flapping_inflow::{FlapMeasurement, inflow_from_flapping};
use cierva_model::components::rotor::Rotor;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Channels a teeter record must have.
pub const FLAP_REQUIRED: [&str; 6] = [
    "time_s",
    "teeter_rad",
    "azimuth_from_front_rad",
    "omega_rotor_rad_s",
    "hub_inplane_speed_m_s",
    "hub_normal_speed_m_s",
];

/// Where the coning comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Coning {
    /// Unknown (a teetering rotor cones elastically): Eq. 19 closes the system.
    #[default]
    Unknown,
    /// The mean of the flap channel (an articulated blade's flap angle).
    Mean,
}

/// `tan(chi/2)` for Eq. 19.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum HalfSkew {
    /// `tan(chi/2) = 1`, as seed 003 takes for its speed range.
    #[default]
    One,
    /// From seed 003 Eq. 5 with `v_i0m << w_hub`: `tan chi = V / (-w_hub)`.
    Signed,
    /// From seed 003 Eq. 6 with `v_i0m << w_hub`: `tan chi = V / |w_hub|`.
    Modulus,
}

/// Settings of the inflow analysis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlapSettings {
    pub coning: Coning,
    pub skew: HalfSkew,
    pub density_kg_m3: f64,
    /// Blade pitch at the rotor's reference station, deg (default: the rotor file's pitch).
    pub collective_deg: Option<f64>,
}

/// The disc's motion and the inflow it implies.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FlapInflowResult {
    pub revolutions: f64,
    pub tip_speed_ratio: f64,
    pub beta_1c_deg: f64,
    pub beta_1s_deg: f64,
    pub coning_deg: f64,
    pub v0_m_s: f64,
    pub v1s_m_s: f64,
    pub v1c_m_s: f64,
    pub tan_half_skew: f64,
}

/// Linear fit of the pitch distribution over the span: `(theta_0 at the shaft, theta_tw per m)`.
fn linear_pitch(rotor: &Rotor, shift: f64) -> (f64, f64) {
    let n = 200;
    let xs: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) / n as f64).collect();
    let ys: Vec<f64> = xs.iter().map(|x| rotor.pitch_rad.at(*x) + shift).collect();
    let (mx, my) = (
        xs.iter().sum::<f64>() / n as f64,
        ys.iter().sum::<f64>() / n as f64,
    );
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    let slope = sxy / sxx;
    (my - slope * mx, slope / rotor.radius_m)
}

/// Inflow components from a teeter record and the rotor's data.
pub fn inflow_from_record(
    record: &Record,
    rotor: &Rotor,
    s: &FlapSettings,
) -> Result<FlapInflowResult, String> {
    let ch = |n: &str| {
        record
            .channel(n)
            .ok_or_else(|| format!("{}: channel `{n}` is missing", record.path.display()))
    };
    let (teeter, az) = (ch("teeter_rad")?, ch("azimuth_from_front_rad")?);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let (omega, v, w) = (
        mean(ch("omega_rotor_rad_s")?),
        mean(ch("hub_inplane_speed_m_s")?),
        mean(ch("hub_normal_speed_m_s")?),
    );
    let revolutions = omega * record.duration_s() / (2.0 * PI);
    if revolutions < 2.0 {
        return Err(format!(
            "{}: {revolutions:.2} revolutions: a harmonic fit needs at least two",
            record.path.display()
        ));
    }
    // Least squares: teeter = c0 + c1 cos psi_m + c2 sin psi_m; Eqs. 13-14 give
    // beta_1c = -c1 and beta_1s = -c2.
    let n = teeter.len();
    let x = DMatrix::from_fn(n, 3, |k, j| match j {
        0 => 1.0,
        1 => az[k].cos(),
        _ => az[k].sin(),
    });
    let c = x
        .svd(true, true)
        .solve(&DVector::from_column_slice(teeter), 1e-12)
        .map_err(|e| format!("harmonic fit: {e}"))?;
    let (beta_1c, beta_1s) = (-c[1], -c[2]);
    let shift = s
        .collective_deg
        .map_or(0.0, |d| rotor.collective_shift_for(d.to_radians()));
    let (theta_0, theta_tw) = linear_pitch(rotor, shift);
    let (a0, a1) = match &rotor.airfoil {
        cierva_model::components::airfoil::Airfoil::Analytical(a) => (
            -a.lift_slope_per_rad * a.zero_lift_alpha_rad,
            a.lift_slope_per_rad,
        ),
        t => (t.coefficients(0.0, 0.0).0, t.lift_slope_per_rad()),
    };
    let tan_half_skew = match s.skew {
        HalfSkew::One => 1.0,
        HalfSkew::Signed => ((v / -w).atan() / 2.0).tan(),
        HalfSkew::Modulus => (v.atan2(w.abs()) / 2.0).tan(),
    };
    let m = FlapMeasurement {
        beta_0_rad: match s.coning {
            Coning::Unknown => None,
            Coning::Mean => Some(c[0]),
        },
        beta_1c_rad: beta_1c,
        beta_1s_rad: beta_1s,
        v_inplane_m_s: v,
        w_hub_m_s: w,
        omega_rad_s: omega,
        radius_m: rotor.radius_m,
        lock_number: rotor.lock_number(s.density_kg_m3),
        a0,
        a1_per_rad: a1,
        theta_0_rad: theta_0,
        theta_tw_rad_per_m: theta_tw,
        tan_half_skew,
    };
    let r = inflow_from_flapping(&m).map_err(|e| format!("{}: {e}", record.path.display()))?;
    Ok(FlapInflowResult {
        revolutions,
        tip_speed_ratio: v / (omega * rotor.radius_m),
        beta_1c_deg: beta_1c.to_degrees(),
        beta_1s_deg: beta_1s.to_degrees(),
        coning_deg: r.beta_0_rad.to_degrees(),
        v0_m_s: r.v0_m_s,
        v1s_m_s: r.v1s_m_s,
        v1c_m_s: r.v1c_m_s,
        tan_half_skew,
    })
}
