//! A propeller: the rotor module with a rigid hub, in axial flow (seed 000 Sec. III: "the rotor
//! module is called twice"), with the blockage factor of seed 000 Sec. VII.A.
//!
//! The propeller's own axes are rotor hub axes with `-z` along its thrust: the air approaches
//! along `+z` at the airspeed reaching the disc. With a blockage factor `k` (0 none, 1 total
//! blockage of the oncoming airstream by the airframe ahead of a pusher propeller), the
//! airspeed reaching the disc is `(1 - k) V`. The inflow is Peters-HaQuang's uniform
//! component, which in axial flow is momentum theory: `v0 = T / (2 rho A (V_d + v0))`.
//!
//! # The propeller map
//! In axial flow a rigid propeller's solution is non-dimensional: with the airfoil's
//! coefficients a function of angle of attack and Mach number only, `C_T = T / (rho A (Omega
//! R)^2)`, `C_Q = Q / (rho A R (Omega R)^2)` and `lambda_i = v0 / (Omega R)` depend on the
//! disc's inflow ratio `lambda_c = V_d / (Omega R)` and the tip Mach number alone. A [`Map`]
//! tabulates them from the exact solve and interpolates (Catmull-Rom in both directions, exact
//! for quadratics); a simulation carries one so each right-hand side costs one interpolation
//! instead of about seven blade solutions. Outside the table the exact solve runs.

use crate::components::rotor::{
    Blade, Hub, HubVelocity, Inflow, Numerics, Operating, Rotor, RotorError,
};
use crate::solve::SolveError;
use serde::Serialize;
use std::f64::consts::PI;
use std::sync::Arc;
use thiserror::Error;

/// A propeller and its installation correction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Propeller {
    pub rotor: Rotor,
    /// Blockage factor (seed 000 Sec. VII.A): 0 no blockage, 1 total.
    pub blockage: f64,
    /// A map of this propeller's solution ([`Propeller::with_map`]), or `None` for the exact
    /// solve at every call. A map belongs to the rotor it was built from: set it on a copy that
    /// will not change (a simulation's).
    #[serde(skip)]
    pub map: Option<Arc<Map>>,
}

/// The tabulated non-dimensional solution of a propeller in axial flow (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Map {
    /// Inflow ratio `V_d / (Omega R)`: from 0 by `lambda_step`.
    lambda_step: f64,
    lambdas: usize,
    /// Tip Mach number: from `mach_min` by `mach_step`.
    mach_min: f64,
    mach_step: f64,
    machs: usize,
    /// `[C_T, C_Q, lambda_i]` at each node, `lambda` fastest; NaN where the solve failed.
    nodes: Vec<[f64; 3]>,
}

/// The map's grid: inflow ratio 0 to 0.4 in steps of 0.004, tip Mach number 0.3 to 0.9 in
/// steps of 0.01 (the VPM M16's propeller flies at about 0.64 and inflow ratios up to 0.2).
/// Interpolation error is tested below 3e-5 of the static thrust and torque.
const MAP_LAMBDA_STEP: f64 = 0.004;
const MAP_LAMBDAS: usize = 101;
const MAP_MACH_MIN: f64 = 0.3;
const MAP_MACH_STEP: f64 = 0.01;
const MAP_MACHS: usize = 61;

/// Maps built in this process, by the rotor they tabulate (a few at most: one per propeller
/// simulated), so that repeated simulations of one aircraft build its map once.
static MAPS: std::sync::Mutex<Vec<(Rotor, Arc<Map>)>> = std::sync::Mutex::new(Vec::new());
const MAPS_KEPT: usize = 8;

/// Catmull-Rom weights at fraction `t` of the interval between the middle two of four nodes.
fn catmull_rom(t: f64) -> [f64; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    ]
}

impl Map {
    /// Nodes in the table.
    pub fn nodes(&self) -> usize {
        self.nodes.len()
    }

    /// `[C_T, C_Q, lambda_i]` at a point, or `None` outside the table's interior or next to a
    /// node where the solve failed.
    fn at(&self, lambda: f64, mach: f64) -> Option<[f64; 3]> {
        let u = lambda / self.lambda_step;
        let v = (mach - self.mach_min) / self.mach_step;
        if !(u >= 1.0 && v >= 1.0) {
            return None;
        }
        let (i, j) = (u.floor() as usize, v.floor() as usize);
        if i + 2 >= self.lambdas || j + 2 >= self.machs {
            return None;
        }
        let (wu, wv) = (catmull_rom(u - i as f64), catmull_rom(v - j as f64));
        let mut out = [0.0; 3];
        for (b, wb) in wv.iter().enumerate() {
            for (a, wa) in wu.iter().enumerate() {
                let n = self.nodes[(j + b - 1) * self.lambdas + (i + a - 1)];
                for k in 0..3 {
                    out[k] += wa * wb * n[k];
                }
            }
        }
        out.iter().all(|v| v.is_finite()).then_some(out)
    }
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
    /// This propeller with a map of its solution (about 6,000 exact solves, some tens of
    /// milliseconds, or none when this process has mapped the same rotor before). The rotor must
    /// be valid.
    pub fn with_map(&self) -> Result<Propeller, PropellerError> {
        self.rotor.validate()?;
        let mut p = self.clone();
        p.map = None;
        let kept = |maps: &Vec<(Rotor, Arc<Map>)>| {
            maps.iter()
                .find(|(r, _)| *r == self.rotor)
                .map(|(_, m)| m.clone())
        };
        if let Some(m) = MAPS.lock().ok().and_then(|maps| kept(&maps)) {
            p.map = Some(m);
            return Ok(p);
        }
        let map = Arc::new(p.build_map());
        if let Ok(mut maps) = MAPS.lock() {
            if maps.len() >= MAPS_KEPT {
                maps.remove(0);
            }
            maps.push((self.rotor.clone(), map.clone()));
        }
        p.map = Some(map);
        Ok(p)
    }

    /// Tabulates this (validated) propeller's solution afresh: [`Propeller::with_map`] without
    /// the process's store of maps.
    pub fn build_map(&self) -> Map {
        // Any density and speed of sound: the solution is non-dimensional.
        let (rho, a) = (1.225, 340.294);
        let r = self.rotor.radius_m;
        let area = PI * r * r;
        let mut nodes = Vec::with_capacity(MAP_LAMBDAS * MAP_MACHS);
        for j in 0..MAP_MACHS {
            let tip = (MAP_MACH_MIN + j as f64 * MAP_MACH_STEP) * a;
            for i in 0..MAP_LAMBDAS {
                let v_disc = i as f64 * MAP_LAMBDA_STEP * tip;
                nodes.push(match self.solve_axial(tip / r, v_disc, rho, a) {
                    Ok((loads, v0)) => [
                        loads.thrust_n() / (rho * area * tip * tip),
                        -loads.driving_torque_n_m / (rho * area * r * tip * tip),
                        v0 / tip,
                    ],
                    Err(_) => [f64::NAN; 3],
                });
            }
        }
        Map {
            lambda_step: MAP_LAMBDA_STEP,
            lambdas: MAP_LAMBDAS,
            mach_min: MAP_MACH_MIN,
            mach_step: MAP_MACH_STEP,
            machs: MAP_MACHS,
            nodes,
        }
    }

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
        let r = self.rotor.radius_m;
        let tip = omega_rad_s * r;
        let advance_ratio = airspeed_m_s / (omega_rad_s / (2.0 * PI) * 2.0 * r);
        if let Some(map) = &self.map
            && let Some([ct, cq, li]) = map.at(v_disc / tip, tip / speed_of_sound_m_s)
        {
            let q = density_kg_m3 * PI * r * r * tip * tip;
            let torque = cq * q * r;
            return Ok(PropellerState {
                thrust_n: ct * q,
                torque_n_m: torque,
                power_w: torque * omega_rad_s,
                v0_m_s: li * tip,
                disc_airspeed_m_s: v_disc,
                advance_ratio,
            });
        }
        let (loads, v0) =
            self.solve_axial(omega_rad_s, v_disc, density_kg_m3, speed_of_sound_m_s)?;
        let torque = -loads.driving_torque_n_m;
        Ok(PropellerState {
            thrust_n: loads.thrust_n(),
            torque_n_m: torque,
            power_w: torque * omega_rad_s,
            v0_m_s: v0,
            disc_airspeed_m_s: v_disc,
            advance_ratio,
        })
    }

    /// The momentum-blade-element solution in axial flow at the disc's airspeed: the loads and
    /// the induced velocity.
    fn solve_axial(
        &self,
        omega_rad_s: f64,
        v_disc: f64,
        density_kg_m3: f64,
        speed_of_sound_m_s: f64,
    ) -> Result<(crate::components::rotor::SteadyLoads, f64), PropellerError> {
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
        Ok((loads, v0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::airfoil::{Airfoil, AnalyticalSection};
    use crate::components::rotor::{Corrections, Distribution};

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
            map: None,
        }
    }

    /// The map gives the exact solve's thrust, torque and inflow within 3e-5 of their static
    /// values (0.04 N of 1404 N) over the flight range, and leaves the table for the exact solve.
    /// Catmull-Rom interpolation errs as the cube of the grid step; the largest errors sit at
    /// the section's stall, a kink in the coefficients (measured: 5.4e-6 thrust, 1.2e-5 torque,
    /// 4.8e-6 inflow).
    #[test]
    fn the_map_matches_the_exact_solve() {
        let exact = propeller(0.3);
        let mapped = exact.with_map().unwrap();
        let s = exact.operate(270.0, 0.0, 1.225, 340.0).unwrap();
        let mut worst = [0.0f64; 3];
        for k in 0..200 {
            // A deterministic scatter over 150-350 rad/s, 0-45 m/s and two air densities.
            let f = |m: u64| ((k as u64 * m) % 1000) as f64 / 1000.0;
            let omega = 150.0 + 200.0 * f(617);
            let v = 45.0 * f(331);
            let (rho, a) = if k % 2 == 0 {
                (1.225, 340.3)
            } else {
                (1.06, 332.5)
            };
            let e = exact.operate(omega, v, rho, a).unwrap();
            let m = mapped.operate(omega, v, rho, a).unwrap();
            worst[0] = worst[0].max((m.thrust_n - e.thrust_n).abs() / s.thrust_n);
            worst[1] = worst[1].max((m.torque_n_m - e.torque_n_m).abs() / s.torque_n_m);
            worst[2] = worst[2].max((m.v0_m_s - e.v0_m_s).abs() / s.v0_m_s);
            assert_eq!(m.disc_airspeed_m_s, e.disc_airspeed_m_s);
        }
        assert!(worst.iter().all(|w| *w < 3e-5), "{worst:?}");
        // Off the table (tip Mach 0.11): the exact solve, to the bit.
        let slow = (
            mapped.operate(50.0, 10.0, 1.225, 340.0),
            exact.operate(50.0, 10.0, 1.225, 340.0),
        );
        assert_eq!(slow.0.unwrap(), slow.1.unwrap());
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
