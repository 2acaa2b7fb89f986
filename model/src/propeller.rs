//! A propeller: the rotor module with a rigid hub, in axial flow (seed 000 Sec. III: "the rotor
//! module is called twice"), with the blockage factor of seed 000 Sec. VII.A.
//!
//! The propeller's own axes are rotor hub axes with `-z` along its thrust: the air approaches
//! along `+z` at the airspeed reaching the disc. With a blockage factor `k` (0 none, 1 total
//! blockage of the oncoming airstream by the airframe ahead of a pusher propeller), the
//! airspeed reaching the disc is `(1 - k) V`. The inflow is Peters-HaQuang's uniform
//! component, which in axial flow is momentum theory: `v0 = T / (2 rho A (V_d + v0))`.

use crate::rotor::{Blade, Hub, HubVelocity, Inflow, Numerics, Operating, Rotor, RotorError};
use crate::solve::SolveError;
use serde::Serialize;
use std::f64::consts::PI;
use thiserror::Error;

/// A propeller and its installation correction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Propeller {
    pub rotor: Rotor,
    /// Blockage factor (seed 000 Sec. VII.A): 0 no blockage, 1 total.
    pub blockage: f64,
}

/// The propeller's operating point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PropellerState {
    pub thrust_n: f64,
    /// Torque the engine must supply, N m.
    pub torque_n_m: f64,
    pub power_w: f64,
    /// Uniform induced velocity through the disc, m/s.
    pub v0_m_s: f64,
    /// Airspeed reaching the disc after blockage, m/s.
    pub disc_airspeed_m_s: f64,
    /// Advance ratio `V / (n D)` (with the free-stream airspeed).
    pub advance_ratio: f64,
}

/// Why the operating point was not found.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PropellerError {
    #[error(transparent)]
    Rotor(#[from] RotorError),
    #[error("{name} must be {requirement}, got {value}")]
    Input {
        name: &'static str,
        requirement: &'static str,
        value: f64,
    },
    #[error("the inflow did not converge: {0}")]
    Solve(#[from] SolveError),
}

impl Propeller {
    /// Thrust, torque and inflow at a rotational speed and free-stream airspeed along the axis.
    pub fn operate(
        &self,
        omega_rad_s: f64,
        airspeed_m_s: f64,
        density_kg_m3: f64,
        speed_of_sound_m_s: f64,
    ) -> Result<PropellerState, PropellerError> {
        self.rotor.validate()?;
        self.operate_checked(omega_rad_s, airspeed_m_s, density_kg_m3, speed_of_sound_m_s)
    }

    /// [`Propeller::operate`] for a propeller whose rotor has been validated already (the
    /// aircraft validates it once; the full model calls this every evaluation).
    pub(crate) fn operate_checked(
        &self,
        omega_rad_s: f64,
        airspeed_m_s: f64,
        density_kg_m3: f64,
        speed_of_sound_m_s: f64,
    ) -> Result<PropellerState, PropellerError> {
        if self.rotor.hub != Hub::Rigid {
            return Err(PropellerError::Input {
                name: "hub",
                requirement: "rigid for a propeller (its blades do not flap)",
                value: f64::NAN,
            });
        }
        let checks = [
            (
                "blockage",
                self.blockage,
                (0.0..=1.0).contains(&self.blockage),
                "in [0, 1]",
            ),
            ("omega_rad_s", omega_rad_s, omega_rad_s > 0.0, "positive"),
            (
                "airspeed_m_s",
                airspeed_m_s,
                airspeed_m_s >= 0.0,
                "zero or positive",
            ),
            (
                "density_kg_m3",
                density_kg_m3,
                density_kg_m3 > 0.0,
                "positive",
            ),
        ];
        for (name, value, ok, requirement) in checks {
            if !(ok && value.is_finite()) {
                return Err(PropellerError::Input {
                    name,
                    requirement,
                    value,
                });
            }
        }
        let v_disc = (1.0 - self.blockage) * airspeed_m_s;
        // The air comes along +z (the hub moves along -z at v_disc).
        let hub = HubVelocity {
            u: 0.0,
            v: 0.0,
            w: -v_disc,
        };
        let blade = Blade::new(
            &self.rotor,
            Numerics {
                azimuth_step_rad: 15f64.to_radians(),
                ..Numerics::default()
            },
        );
        let r = self.rotor.radius_m;
        let area = PI * r * r;
        let tip = omega_rad_s * r;
        let op = |v0: f64| Operating {
            omega_rad_s,
            hub,
            inflow: Inflow {
                v0,
                v1s: 0.0,
                v1c: 0.0,
            },
            density_kg_m3,
            speed_of_sound_m_s,
            collective_shift_rad: 0.0,
            hub_rates_rad_s: [0.0; 3],
        };
        // Momentum theory in axial flow: v0 (v_disc + v0) 2 rho A = T, on the branch v0 >= 0
        // (a propeller producing thrust); the residual is scaled by the tip speed.
        let start = {
            let t = blade.steady(&op(0.0), [0.0, 0.0])?.thrust_n().max(0.0);
            0.5 * (-v_disc + (v_disc * v_disc + 2.0 * t / (density_kg_m3 * area)).sqrt())
        };
        // Secant iterations on the scaled residual (a smooth, nearly linear function of v0):
        // converged to 1e-12 of the tip speed in a handful of blade evaluations.
        let residual = |v0: f64| -> Result<f64, PropellerError> {
            let t = blade.steady(&op(v0), [0.0, 0.0])?.thrust_n();
            Ok((v0 - t / (2.0 * density_kg_m3 * area * (v_disc + v0).abs().max(1e-6))) / tip)
        };
        let (mut x0, mut x1) = (start, start + 1e-3 * tip.max(1.0));
        let (mut r0, mut r1) = (residual(x0)?, residual(x1)?);
        let mut converged = r1.abs() <= 1e-12;
        for _ in 0..50 {
            if converged {
                break;
            }
            let slope = (r1 - r0) / (x1 - x0);
            if !(slope.is_finite() && slope != 0.0) {
                break;
            }
            let x2 = (x1 - r1 / slope).max(-0.5 * v_disc.max(0.0));
            (x0, r0) = (x1, r1);
            x1 = x2;
            r1 = residual(x1)?;
            converged = r1.abs() <= 1e-12;
        }
        if !converged {
            return Err(PropellerError::Solve(SolveError::NoConvergence {
                x: vec![x1 / tip],
                residuals: vec![r1],
                iterations: 50,
                tolerance: 1e-12,
            }));
        }
        let v0 = x1;
        let loads = blade.steady(&op(v0), [0.0, 0.0])?;
        let torque = -loads.driving_torque_n_m;
        Ok(PropellerState {
            thrust_n: loads.thrust_n(),
            torque_n_m: torque,
            power_w: torque * omega_rad_s,
            v0_m_s: v0,
            disc_airspeed_m_s: v_disc,
            advance_ratio: airspeed_m_s / (omega_rad_s / (2.0 * PI) * 2.0 * r),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::airfoil::{Airfoil, AnalyticalSection};
    use crate::rotor::{Corrections, Distribution};

    /// A test propeller: three constant-chord blades twisted for a roughly uniform inflow angle.
    fn propeller(blockage: f64) -> Propeller {
        Propeller {
            rotor: Rotor {
                hub: Hub::Rigid,
                blades: 3,
                radius_m: 0.74,
                root_cutout_m: 0.12,
                hinge_offset_m: 0.0,
                chord_m: Distribution::constant(0.08),
                pitch_rad: Distribution {
                    stations_r_over_r: vec![0.0, 1.0],
                    values: vec![0.60, 0.22],
                },
                pitch_reference_r_over_r: 0.75,
                flap_inertia_kg_m2: 0.3,
                flap_mass_moment_kg_m: 0.0,
                flap_spring_n_m_per_rad: 0.0,
                precone_rad: 0.0,
                tip_loss_factor: 0.97,
                airfoil: Airfoil::Analytical(AnalyticalSection {
                    lift_slope_per_rad: 5.7,
                    zero_lift_alpha_rad: 0.0,
                    cd0: 0.012,
                    cd1_per_rad: 0.0,
                    cd2_per_rad2: 0.5,
                    stall_alpha_rad: 0.25,
                }),
                elements: 20,
                corrections: Corrections::default(),
            },
            blockage,
        }
    }

    /// Figures for the record (58 in, three blades, 2580 rpm, sea level): 1404 N and 31.8 kW
    /// static; 563 N and 22.7 kW at 30 m/s (advance ratio 0.47); with total blockage, the static
    /// figures at any airspeed.
    #[test]
    fn momentum_balance_and_energy_hold() {
        let p = propeller(0.0);
        let s = p.operate(270.0, 30.0, 1.225, 340.0).unwrap();
        let area = PI * 0.74 * 0.74;
        // Momentum theory: T = 2 rho A v0 (V + v0).
        let t = 2.0 * 1.225 * area * s.v0_m_s * (30.0 + s.v0_m_s);
        assert!(((t - s.thrust_n) / s.thrust_n).abs() < 1e-9, "{s:?}");
        // The shaft power covers the useful and induced power (the rest is profile drag).
        assert!(s.power_w > s.thrust_n * (30.0 + s.v0_m_s), "{s:?}");
        assert!(s.thrust_n > 0.0 && s.v0_m_s > 0.0);
    }

    #[test]
    fn total_blockage_removes_the_thrust_change_with_airspeed() {
        // Seed 000 Sec. VII.A: with the airframe blocking the oncoming stream, the propeller's
        // thrust no longer falls as the airspeed rises, which removes its share of X_u.
        let dt_dv = |k: f64| {
            let p = propeller(k);
            let a = p.operate(270.0, 29.0, 1.225, 340.0).unwrap().thrust_n;
            let b = p.operate(270.0, 31.0, 1.225, 340.0).unwrap().thrust_n;
            (b - a) / 2.0
        };
        let free = dt_dv(0.0);
        let half = dt_dv(0.5);
        let total = dt_dv(1.0);
        assert!(free < 0.0 && half < 0.0, "{free} {half}");
        assert!(half.abs() < free.abs());
        assert!(total.abs() < 1e-9, "{total}");
    }

    #[test]
    fn bad_inputs_are_errors() {
        let mut p = propeller(1.5);
        assert!(matches!(
            p.operate(270.0, 30.0, 1.225, 340.0),
            Err(PropellerError::Input {
                name: "blockage",
                ..
            })
        ));
        p.blockage = 0.0;
        p.rotor.hub = Hub::Articulated;
        assert!(matches!(
            p.operate(270.0, 30.0, 1.225, 340.0),
            Err(PropellerError::Input { name: "hub", .. })
        ));
    }
}
