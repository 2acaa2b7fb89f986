//! Trim: steady flight of the revolution-averaged aircraft ([`crate::aircraft`]).
//!
//! Given the true airspeed, rate of climb (negative to descend), turn rate, air and the
//! aircraft's mass and c.g., trim finds the stick positions, pedal, throttle, pitch and roll
//! attitude, rotorspeed, main-rotor inflow and (with an engine drive) propeller speed at which
//! every revolution-averaged acceleration vanishes: `du, dv, dw, dp, dq, dr`, `dOmega`, the
//! inflow's departure from its equilibrium and, with an engine, `dOmega_prop`. The blade's
//! periodic motion is solved inside each evaluation. Heading is zero; the flight path is fixed
//! in north-east-down axes (`V` along the track, climbing at `climb_m_s`), so sideslip is a
//! result, not an unknown (the pilot flies wings-level or banked as the moments require).
//!
//! # Convergence criterion
//! Damped Newton ([`crate::solve::newton`]) on scaled unknowns, with a finite-difference
//! Jacobian refreshed by Broyden updates (recomputed when an update fails to descend),
//! converged when every scaled
//! residual is at most `tolerance` (default `1e-7`): translational accelerations in g, angular
//! accelerations in rad/s^2, rotor and propeller accelerations divided by their speeds (1/s),
//! and the inflow mismatch divided by the tip speed. Failure returns the last residuals by
//! name.

use crate::aircraft::{
    Air, Aircraft, AircraftError, Averaged, Controls, Drive, HubAccelerations, RotorCache, State,
};
use crate::components::rigid_body::{BodyState, G_M_S2};
use crate::components::rotor::{
    Inflow, InflowModel, Numerics, Operating, RevolutionMap, Rotor, SteadyLoads,
};
use crate::solve::{self, NewtonOptions, SolveError};
use serde::Serialize;
use std::f64::consts::PI;
use thiserror::Error;

/// The flight condition to trim.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Condition {
    pub airspeed_m_s: f64,
    /// Rate of climb, m/s (negative descends).
    pub climb_m_s: f64,
    /// Rate of turn, rad/s (positive to starboard).
    pub turn_rate_rad_s: f64,
    pub air: Air,
}

/// Trim settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrimOptions {
    pub newton: NewtonOptions,
    /// The rotor tip speed to start from, m/s.
    pub tip_speed_guess_m_s: f64,
}

impl Default for TrimOptions {
    fn default() -> Self {
        Self {
            newton: NewtonOptions {
                tolerance: 1e-7,
                max_iterations: 30,
                fd_step: 1e-6,
                max_halvings: 10,
                broyden: true,
            },
            tip_speed_guess_m_s: 160.0,
        }
    }
}

/// A trimmed flight condition.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trim {
    pub controls: Controls,
    pub state: State,
    pub pitch_rad: f64,
    pub roll_rad: f64,
    /// Angle of attack and sideslip at the c.g., rad.
    pub alpha_rad: f64,
    pub sideslip_rad: f64,
    pub rotor_rpm: f64,
    pub propeller_rpm: f64,
    /// The model's evaluation at the trim point.
    pub averaged: Averaged,
    /// The scaled residuals by name, and their infinity norm.
    pub residuals: Vec<(String, f64)>,
    pub residual_norm: f64,
    pub iterations: usize,
    /// Model evaluations the solve took (finite differences and a failed warm start included).
    pub evaluations: usize,
    pub tolerance: f64,
    /// Where this trim ended, to start a nearby one from ([`trim_from`]).
    #[serde(skip)]
    pub warm_start: WarmStart,
}

/// Why trim failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TrimError {
    #[error(transparent)]
    Aircraft(#[from] AircraftError),
    #[error("{name} must be {requirement}, got {value}")]
    Condition {
        name: &'static str,
        requirement: &'static str,
        value: f64,
    },
    #[error("trim did not converge after {iterations} iterations; last scaled residuals: {}", show(.residuals))]
    NoConvergence {
        residuals: Vec<(String, f64)>,
        iterations: usize,
    },
    #[error("trim failed: {0}")]
    Solver(String),
    #[error(
        "the trim needs {control} at {percent:.1} %, outside its 0-100 % travel: the condition cannot be flown"
    )]
    OutsideTravel {
        control: &'static str,
        percent: f64,
        /// The trim found, for inspection.
        trim: Box<Trim>,
    },
}

fn show(r: &[(String, f64)]) -> String {
    r.iter()
        .map(|(n, v)| format!("{n} {v:.3e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The names of the scaled residuals, in order.
pub fn residual_names(with_engine: bool) -> Vec<&'static str> {
    let mut v = vec![
        "du/dt [g]",
        "dv/dt [g]",
        "dw/dt [g]",
        "dp/dt [rad/s^2]",
        "dq/dt [rad/s^2]",
        "dr/dt [rad/s^2]",
        "dOmega/dt / Omega [1/s]",
        "v0 mismatch / tip speed",
        "v1s mismatch / tip speed",
        "v1c mismatch / tip speed",
    ];
    if with_engine {
        v.push("dOmega_prop/dt / Omega_prop [1/s]");
    }
    v
}

pub(crate) struct Problem<'a> {
    pub(crate) aircraft: &'a Aircraft,
    pub(crate) condition: Condition,
    pub(crate) omega0: f64,
    pub(crate) tip0: f64,
    pub(crate) prop0: f64,
    pub(crate) engine: bool,
    pub(crate) harmonics: bool,
    pub(crate) warm: [f64; 2],
    /// The rotor's periodic solutions so far (a Jacobian column that moves only the pedal or
    /// throttle finds the rotor as it was) and what they learned of its revolution map.
    pub(crate) rotor: RotorCache,
    /// The body's accelerations the rotor's flapping is solved under: the steady motion's
    /// while the solver steps (the same root, at a periodic solution an evaluation), then the
    /// model's own to confirm it ([`Problem::solve`]).
    pub(crate) hub: HubAccelerations,
    /// The last evaluation (the solver's last call is at its solution), and whether it is the
    /// model's own (the accelerations it was solved under agree with those it implies).
    pub(crate) last: Option<(Vec<f64>, Vec<f64>, Averaged, bool)>,
    /// Model evaluations so far.
    pub(crate) calls: usize,
}

impl Problem<'_> {
    pub(crate) fn unpack(&self, x: &[f64]) -> (State, Controls) {
        let c = &self.condition;
        let (theta, phi) = (x[4], x[5]);
        let v = c.airspeed_m_s;
        let vh = (v * v - c.climb_m_s * c.climb_m_s).max(0.0).sqrt();
        // North-east-down velocity to body axes (heading zero): R_x(phi) R_y(theta).
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        let (vn, vd) = (vh, -c.climb_m_s);
        let u = ct * vn - st * vd;
        let vb = sp * st * vn + sp * ct * vd;
        let w = cp * st * vn + cp * ct * vd;
        let psi_dot = c.turn_rate_rad_s;
        let body = BodyState {
            u_m_s: u,
            v_m_s: vb,
            w_m_s: w,
            p_rad_s: -psi_dot * st,
            q_rad_s: psi_dot * sp * ct,
            r_rad_s: psi_dot * cp * ct,
            phi_rad: phi,
            theta_rad: theta,
            ..BodyState::default()
        };
        let inflow = if self.harmonics {
            Inflow {
                v0: x[7] * self.tip0,
                v1s: x[8] * self.tip0,
                v1c: x[9] * self.tip0,
            }
        } else {
            Inflow {
                v0: x[7] * self.tip0,
                v1s: 0.0,
                v1c: 0.0,
            }
        };
        let inflow = match self.aircraft.main_rotor.inflow {
            InflowModel::Prescribed { v0, v1s, v1c } => Inflow { v0, v1s, v1c },
            _ => inflow,
        };
        let state = State {
            body,
            rotor_omega_rad_s: x[6] * self.omega0,
            inflow,
            propeller_omega_rad_s: if self.engine { x[10] * self.prop0 } else { 0.0 },
        };
        let controls = Controls {
            stick_longitudinal_percent: 100.0 * x[0],
            stick_lateral_percent: 100.0 * x[1],
            pedal_percent: 100.0 * x[2],
            throttle_percent: 100.0 * x[3],
        };
        (state, controls)
    }

    fn evaluate(&mut self, x: &[f64]) -> Result<(Vec<f64>, Averaged), AircraftError> {
        if let Some((lx, r, a, agrees)) = &self.last
            && lx.as_slice() == x
            && (*agrees || self.hub != HubAccelerations::Agreed)
        {
            return Ok((r.clone(), a.clone()));
        }
        let (r, a, agrees) = self.evaluate_afresh(x)?;
        self.last = Some((x.to_vec(), r.clone(), a.clone(), agrees));
        Ok((r, a))
    }

    /// The scaled residuals at `x`, as the solver takes them.
    fn residuals(&mut self, x: &[f64]) -> Result<Vec<f64>, String> {
        self.evaluate(x).map(|(r, _)| r).map_err(|e| e.to_string())
    }

    fn evaluate_afresh(&mut self, x: &[f64]) -> Result<(Vec<f64>, Averaged, bool), AircraftError> {
        let (state, controls) = self.unpack(x);
        self.calls += 1;
        let (a, _, agrees) = self.aircraft.averaged_under(
            &state,
            &controls,
            self.condition.air,
            self.warm,
            &mut self.rotor,
            self.hub,
        )?;
        self.warm = a.flap_start;
        let d = &a.body_dot;
        let tip = self.tip0;
        let mut r = vec![
            d.u_m_s / G_M_S2,
            d.v_m_s / G_M_S2,
            d.w_m_s / G_M_S2,
            d.p_rad_s,
            d.q_rad_s,
            d.r_rad_s,
            a.rotor_omega_dot_rad_s2 / self.omega0,
        ];
        let fixed = matches!(
            self.aircraft.main_rotor.inflow,
            InflowModel::Prescribed { .. }
        );
        let eq = a.inflow_equilibrium;
        if fixed {
            r.extend([x[7], x[8], x[9]]);
        } else if self.harmonics {
            r.extend([
                (eq.v0 - state.inflow.v0) / tip,
                (eq.v1s - state.inflow.v1s) / tip,
                (eq.v1c - state.inflow.v1c) / tip,
            ]);
        } else {
            r.extend([(eq.v0 - state.inflow.v0) / tip, x[8], x[9]]);
        }
        if self.engine {
            r.push(a.propeller_omega_dot_rad_s2 / self.prop0);
        }
        Ok((r, a, agrees))
    }

    /// The trim's unknowns from the warm start if it fits (its rotor solution spares its first
    /// evaluation a revolution, what it learned of the revolution map a few more), then (or
    /// else) from the cold start `x0`: solved with the rotor's flapping under the steady
    /// motion's accelerations, then confirmed under the model's own. Where no root is found so,
    /// the model's own equations are tried from the same starts, and a failure reports their
    /// residuals.
    fn solve(
        &mut self,
        x0: Vec<f64>,
        start: Option<&WarmStart>,
        newton: NewtonOptions,
    ) -> Result<solve::Converged, SolveError> {
        self.hub = HubAccelerations::Steady;
        let held = self.attempts(&x0, start, newton);
        self.hub = HubAccelerations::Agreed;
        match held {
            // The root found with the hub's motion held at the steady motion's is the model's:
            // there the accelerations the loads imply are the steady motion's (to the trim's
            // tolerance), so the model's own evaluation, which starts its iteration from them,
            // stops at once with the same periodic solution: the solver's last evaluation is
            // the model's. Confirmed so, and stepped on under the model's own accelerations
            // should it not be (the solver's Jacobian carried over).
            Ok(held) => solve::newton_from(|x| self.residuals(x), &held.x, held.jacobian, newton)
                .map(|agreed| solve::Converged {
                    iterations: held.iterations + agreed.iterations,
                    ..agreed
                }),
            Err(_) => self.attempts(&x0, start, newton),
        }
    }

    /// Newton from the warm start if it fits, then (or else) from the cold start `x0`, under
    /// the accelerations `self.hub` says.
    fn attempts(
        &mut self,
        x0: &[f64],
        start: Option<&WarmStart>,
        newton: NewtonOptions,
    ) -> Result<solve::Converged, SolveError> {
        let warm = start
            .filter(|w| w.x.len() == x0.len() && w.tip0 == self.tip0)
            .map(|w| {
                (
                    w.x.clone(),
                    w.jacobian.clone(),
                    w.flap,
                    (w.rotor_seed(self.aircraft), Some(w.map)),
                )
            });
        let cold = (x0.to_vec(), None, [0.0, 0.0], (None, None));
        let mut sol = Err(SolveError::Singular {
            x: Vec::new(),
            residuals: Vec::new(),
        });
        for (x, jacobian, flap, (seed, map)) in warm.into_iter().chain(std::iter::once(cold)) {
            self.warm = flap;
            self.last = None;
            self.rotor.seed(seed);
            if let Some(map) = map {
                self.rotor.learned(map);
            }
            sol = solve::newton_from(|x| self.residuals(x), &x, jacobian, newton);
            if sol.is_ok() {
                break;
            }
        }
        sol
    }
}

/// Where a trim ended, to start a nearby trim from: the solver's unknowns, its last Jacobian,
/// the blade-flapping start of the periodic solution, that solution itself, and what the
/// periodic solutions learned of the rotor's revolution map. Opaque; taken from
/// [`Trim::warm_start`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WarmStart {
    x: Vec<f64>,
    jacobian: Option<nalgebra::DMatrix<f64>>,
    flap: [f64; 2],
    tip0: f64,
    rotor: Option<Box<RotorStart>>,
    map: RevolutionMap,
}

/// The main rotor's periodic solution where a trim ended, with the rotor it is of: a nearby
/// trim's first evaluation, at the same unknowns, finds the rotor in the same operating state
/// when what changed is not the rotor or its motion (the mass, an airframe correction), and
/// takes the solution instead of integrating its revolution again.
#[derive(Debug, Clone, PartialEq)]
struct RotorStart {
    rotor: Rotor,
    numerics: Numerics,
    operating: Operating,
    loads: SteadyLoads,
}

/// A warm start as plain numbers, to carry between processes (a model behind cierva's
/// command protocol hands it out with an answer and takes it back with a request near it):
/// the trim's unknowns, its last Jacobian by rows, the flapping start of its periodic
/// solution, the tip-speed guess it was found with and what it learned of the revolution map.
/// The periodic solution itself is not carried (it is a rotor's: [`WarmStart::point`] leaves
/// it), so a start read back ([`WarmStart::from_point`]) finds the same trim as the start it
/// came from, from the same unknowns, at the cost of its first revolution.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct StartPoint {
    pub x: Vec<f64>,
    pub jacobian: Option<Vec<Vec<f64>>>,
    pub flap: [f64; 2],
    pub tip0: f64,
    pub map: Option<[[f64; 2]; 2]>,
}

impl WarmStart {
    /// The periodic solution to seed `aircraft`'s first evaluation with: only for the same
    /// rotor and numerics, and started where the solution starts (so that solving it afresh
    /// would close in its first revolution, with the same sums).
    pub(crate) fn rotor_seed(&self, aircraft: &Aircraft) -> Option<(Operating, SteadyLoads)> {
        let mr = &aircraft.main_rotor;
        self.rotor
            .as_deref()
            .filter(|r| r.rotor == mr.rotor && r.numerics == mr.numerics)
            .filter(|r| r.loads.beta0 == self.flap)
            .map(|r| (r.operating, r.loads))
    }

    /// What the trim's periodic solutions learned of the rotor's revolution map (see
    /// [`RevolutionMap`]): where a nearby solution's secant steps start.
    pub(crate) fn revolution_map(&self) -> RevolutionMap {
        self.map
    }

    /// The start as plain numbers (without its periodic solution: [`StartPoint`]).
    pub fn point(&self) -> StartPoint {
        StartPoint {
            x: self.x.clone(),
            jacobian: self.jacobian.as_ref().map(|j| {
                (0..j.nrows())
                    .map(|r| j.row(r).iter().copied().collect())
                    .collect()
            }),
            flap: self.flap,
            tip0: self.tip0,
            map: self.map.jacobian(),
        }
    }

    /// The start a [`StartPoint`] describes, or what is wrong with it: its Jacobian square, of
    /// the unknowns' size, and every number finite. A start that does not fit the aircraft it
    /// is given to (another number of unknowns, another tip-speed guess) is left by the trim
    /// for a cold one, as any warm start is ([`trim_from`]).
    pub fn from_point(p: &StartPoint) -> Result<Self, String> {
        let n = p.x.len();
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if n == 0 || !finite(&p.x) || !finite(&p.flap) || !p.tip0.is_finite() {
            return Err("its `x`, `flap` and `tip0` must be finite numbers, `x` not empty".into());
        }
        if p.map.is_some_and(|m| !finite(&m.concat())) {
            return Err("its `map` must be finite".into());
        }
        let jacobian = match &p.jacobian {
            None => None,
            Some(rows) => {
                if rows.len() != n || rows.iter().any(|r| r.len() != n || !finite(r)) {
                    return Err(format!(
                        "its `jacobian` must be {n} rows of {n} finite numbers (one a trim unknown)"
                    ));
                }
                Some(nalgebra::DMatrix::from_fn(n, n, |r, c| rows[r][c]))
            }
        };
        Ok(Self {
            x: p.x.clone(),
            jacobian,
            flap: p.flap,
            tip0: p.tip0,
            rotor: None,
            map: RevolutionMap::with_jacobian(p.map),
        })
    }
}

/// Trims the aircraft.
pub fn trim(
    aircraft: &Aircraft,
    condition: Condition,
    options: TrimOptions,
) -> Result<Trim, TrimError> {
    trim_from(aircraft, condition, options, None)
}

/// Trims the aircraft, starting from a nearby trim (the same aircraft with a correction moved a
/// little, say, or a neighbouring airspeed) when one is given. A warm start saves most of the
/// model evaluations of a cold one. It converges to the same tolerance; when it fails, or the
/// start does not fit this aircraft (engine or not, another tip-speed guess), the trim starts
/// cold, so the result never depends on the start beyond the tolerance.
pub fn trim_from(
    aircraft: &Aircraft,
    condition: Condition,
    options: TrimOptions,
    start: Option<&WarmStart>,
) -> Result<Trim, TrimError> {
    aircraft.validate()?;
    check_condition(&condition)?;
    let r = aircraft.main_rotor.rotor.radius_m;
    let omega0 = options.tip_speed_guess_m_s / r;
    let tip0 = options.tip_speed_guess_m_s;
    let (engine, prop0) = match aircraft.propeller.drive {
        Drive::Engine { rated_rpm, .. } => (true, rated_rpm * PI / 30.0),
        Drive::Governed { .. } => (false, 1.0),
    };
    let harmonics = matches!(
        aircraft.main_rotor.inflow,
        InflowModel::PetersHaQuang { .. }
    );
    let mut p = Problem {
        aircraft,
        condition,
        omega0,
        tip0,
        prop0,
        engine,
        harmonics,
        warm: [0.0, 0.0],
        rotor: RotorCache::default(),
        hub: HubAccelerations::Steady,
        last: None,
        calls: 0,
    };
    let x0 = cold_start(aircraft, &condition, tip0, engine);
    let sol = p.solve(x0, start, options.newton);
    let names = residual_names(engine);
    let sol = match sol {
        Ok(s) => s,
        Err(SolveError::NoConvergence {
            residuals,
            iterations,
            ..
        }) => {
            return Err(TrimError::NoConvergence {
                residuals: names.iter().map(|n| n.to_string()).zip(residuals).collect(),
                iterations,
            });
        }
        Err(e) => return Err(TrimError::Solver(e.to_string())),
    };
    let (residuals, averaged) = p.evaluate(&sol.x)?;
    let averaged_flap = averaged.flap_start;
    let (state, controls) = p.unpack(&sol.x);
    let b = state.body;
    let speed = (b.u_m_s * b.u_m_s + b.v_m_s * b.v_m_s + b.w_m_s * b.w_m_s).sqrt();
    let t = Trim {
        controls,
        pitch_rad: b.theta_rad,
        roll_rad: b.phi_rad,
        alpha_rad: b.w_m_s.atan2(b.u_m_s),
        sideslip_rad: (b.v_m_s / speed).asin(),
        rotor_rpm: state.rotor_omega_rad_s * 30.0 / PI,
        propeller_rpm: averaged.propeller_omega_rad_s * 30.0 / PI,
        state,
        averaged,
        residual_norm: residuals.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        residuals: names.iter().map(|n| n.to_string()).zip(residuals).collect(),
        iterations: sol.iterations,
        evaluations: p.calls,
        tolerance: options.newton.tolerance,
        warm_start: WarmStart {
            flap: averaged_flap,
            x: sol.x,
            jacobian: sol.jacobian,
            tip0,
            rotor: p.rotor.last().map(|(operating, loads)| {
                Box::new(RotorStart {
                    rotor: aircraft.main_rotor.rotor.clone(),
                    numerics: aircraft.main_rotor.numerics,
                    operating,
                    loads,
                })
            }),
            map: p.rotor.map(),
        },
    };
    within_travel(t)
}

/// Refuses a flight condition that cannot be trimmed: a non-positive airspeed, a climb as fast
/// as the airspeed, a turn of 1 rad/s or more, or non-physical air.
fn check_condition(condition: &Condition) -> Result<(), TrimError> {
    let checks = [
        (
            "airspeed_m_s",
            condition.airspeed_m_s,
            condition.airspeed_m_s > 0.0,
            "positive",
        ),
        (
            "climb_m_s",
            condition.climb_m_s,
            condition.climb_m_s.abs() < condition.airspeed_m_s,
            "smaller in magnitude than the airspeed",
        ),
        (
            "turn_rate_rad_s",
            condition.turn_rate_rad_s,
            condition.turn_rate_rad_s.abs() < 1.0,
            "below 1 rad/s in magnitude",
        ),
        (
            "density_kg_m3",
            condition.air.density_kg_m3,
            condition.air.density_kg_m3 > 0.0,
            "positive",
        ),
        (
            "speed_of_sound_m_s",
            condition.air.speed_of_sound_m_s,
            condition.air.speed_of_sound_m_s > 0.0,
            "positive",
        ),
    ];
    for (name, value, ok, requirement) in checks {
        if !(ok && value.is_finite()) {
            return Err(TrimError::Condition {
                name,
                requirement,
                value,
            });
        }
    }
    Ok(())
}

/// The cold start: mid controls, level attitudes, Glauert's inflow for the weight, rotorspeed
/// at the guessed tip speed `tip0` (and the propeller's at 90 % of rated with an engine).
fn cold_start(aircraft: &Aircraft, condition: &Condition, tip0: f64, engine: bool) -> Vec<f64> {
    let r = aircraft.main_rotor.rotor.radius_m;
    let weight = aircraft.mass.mass_kg * G_M_S2;
    let area = PI * r * r;
    let v = condition.airspeed_m_s;
    let v0 = weight / (2.0 * condition.air.density_kg_m3 * area * v.max(5.0));
    let cm = &aircraft.controls;
    let mut x0 = vec![
        cm.shaft_pitch_rad
            .percent_for(8f64.to_radians())
            .clamp(0.0, 100.0)
            / 100.0,
        cm.shaft_roll_rad.percent_for(0.0).clamp(0.0, 100.0) / 100.0,
        cm.rudder_rad.percent_for(0.0).clamp(0.0, 100.0) / 100.0,
        0.6,
        0.0,
        0.0,
        1.0,
        v0 / tip0,
        0.0,
        0.0,
    ];
    if engine {
        x0.push(0.9);
    }
    x0
}

/// The trim, or an error that carries it if a control is outside its travel (0-100 %).
fn within_travel(t: Trim) -> Result<Trim, TrimError> {
    let c = t.controls;
    for (control, percent) in [
        ("longitudinal stick", c.stick_longitudinal_percent),
        ("lateral stick", c.stick_lateral_percent),
        ("pedal", c.pedal_percent),
        ("throttle", c.throttle_percent),
    ] {
        if !(0.0..=100.0).contains(&percent) {
            return Err(TrimError::OutsideTravel {
                control,
                percent,
                trim: Box::new(t),
            });
        }
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testdata::gyroplane;

    fn condition(airspeed_m_s: f64) -> Condition {
        Condition {
            airspeed_m_s,
            climb_m_s: 0.0,
            turn_rate_rad_s: 0.0,
            air: Air {
                density_kg_m3: 1.225,
                speed_of_sound_m_s: 340.3,
            },
        }
    }

    /// Level flight at 70 mph: converged to the stated criterion, a free rotor in
    /// autorotation (zero mean torque, flow slowed through the disc, v0 > 0, seed 001), the
    /// disc meeting the air from below and the rotor carrying about the weight.
    #[test]
    fn level_flight_trims_in_autorotation() {
        let a = gyroplane();
        let t = trim(&a, condition(31.3), TrimOptions::default()).unwrap();
        assert!(t.residual_norm <= t.tolerance, "{:?}", t.residuals);
        let r = &t.averaged.rotor;
        assert!(r.driving_torque_n_m.abs() < 1e-3, "{r:?}");
        assert!(t.state.inflow.v0 > 0.0 && r.disc_alpha_rad > 0.0, "{r:?}");
        let weight = a.mass.mass_kg * G_M_S2;
        assert!((r.thrust_n / weight - 1.0).abs() < 0.1, "{r:?}");
        assert!((300.0..500.0).contains(&t.rotor_rpm), "{}", t.rotor_rpm);
        // The forces balance the weight in body axes (the residuals say so; check directly).
        let l = &t.averaged.loads;
        let fz = l.rotor.z_n + l.propeller.z_n + l.airframe.z_n;
        let gz = weight * t.pitch_rad.cos() * t.roll_rad.cos();
        assert!((fz + gz).abs() < 1e-3 * weight, "{fz} vs {gz}");
    }

    /// A trim started from a neighbour's (5 kg heavier, as a fit's finite difference moves a
    /// correction) lands on the cold trim within the convergence tolerance, with a third of the
    /// model evaluations or fewer; a start that does not fit is ignored.
    #[test]
    fn a_warm_start_lands_on_the_cold_trim_for_less() {
        let a = gyroplane();
        let first = trim(&a, condition(31.3), TrimOptions::default()).unwrap();
        let mut heavier = gyroplane();
        heavier.mass.mass_kg += 5.0;
        let cold = trim(&heavier, condition(31.3), TrimOptions::default()).unwrap();
        let warm = trim_from(
            &heavier,
            condition(31.3),
            TrimOptions::default(),
            Some(&first.warm_start),
        )
        .unwrap();
        assert!(warm.residual_norm <= warm.tolerance);
        assert!(
            3 * warm.evaluations <= cold.evaluations,
            "{} warm against {} cold",
            warm.evaluations,
            cold.evaluations
        );
        // Residuals within 1e-7 (scaled): the two solutions agree to a few times that.
        let (cw, cc) = (warm.controls, cold.controls);
        assert!((cw.stick_longitudinal_percent - cc.stick_longitudinal_percent).abs() < 1e-3);
        assert!((warm.pitch_rad - cold.pitch_rad).abs() < 1e-6);
        assert!((warm.rotor_rpm - cold.rotor_rpm).abs() < 1e-3);
        let ignored = WarmStart {
            x: vec![0.5; 3],
            ..WarmStart::default()
        };
        let again = trim_from(
            &heavier,
            condition(31.3),
            TrimOptions::default(),
            Some(&ignored),
        )
        .unwrap();
        assert_eq!(again.evaluations, cold.evaluations);
        assert_eq!(again.controls, cold.controls);
    }

    /// The gyroplane 5 kg heavier at 31.3 m/s, trimmed from `start`.
    fn heavier_from(start: &WarmStart) -> Trim {
        let mut heavier = gyroplane();
        heavier.mass.mass_kg += 5.0;
        trim_from(
            &heavier,
            condition(31.3),
            TrimOptions::default(),
            Some(start),
        )
        .unwrap()
    }

    /// A warm start carried as numbers ([`StartPoint`]) is the start it came from, less its
    /// rotor solution: the trim from it is the trim from the start itself, bit for bit. A point
    /// that does not describe a start is refused, saying why.
    #[test]
    fn a_start_carried_as_numbers_finds_the_same_trim() {
        let first = trim(&gyroplane(), condition(31.3), TrimOptions::default()).unwrap();
        let point = first.warm_start.point();
        let back = WarmStart::from_point(&point).unwrap();
        assert_eq!(back.point(), point);
        assert_eq!(
            back,
            WarmStart {
                rotor: None,
                ..first.warm_start.clone()
            }
        );
        let [from_start, from_point] = [&first.warm_start, &back].map(heavier_from);
        assert_eq!(from_start, from_point);
        let short = StartPoint {
            jacobian: Some(vec![vec![1.0; 2]; 2]),
            ..point.clone()
        };
        assert!(
            WarmStart::from_point(&short)
                .unwrap_err()
                .contains("rows of")
        );
        let nan = StartPoint {
            tip0: f64::NAN,
            ..point
        };
        assert!(WarmStart::from_point(&nan).unwrap_err().contains("finite"));
    }

    /// The rotor's periodic solution that a warm start carries spares the first evaluation a
    /// revolution and changes nothing: the trim is the one started without it, bit for bit. A
    /// start from another rotor does not offer it.
    #[test]
    fn a_warm_starts_rotor_solution_changes_nothing() {
        let a = gyroplane();
        let first = trim(&a, condition(31.3), TrimOptions::default()).unwrap();
        let mut heavier = gyroplane();
        heavier.mass.mass_kg += 5.0;
        assert!(first.warm_start.rotor_seed(&heavier).is_some());
        let bare = WarmStart {
            rotor: None,
            ..first.warm_start.clone()
        };
        let [with, without] = [&first.warm_start, &bare].map(heavier_from);
        assert_eq!(with, without);
        let mut other = gyroplane();
        other.main_rotor.rotor.flap_inertia_kg_m2 *= 1.01;
        assert!(first.warm_start.rotor_seed(&other).is_none());
    }

    /// Seed 001 Fig. 3 trends: from 30 to 70 mph the stick moves forward (speed stability)
    /// and the nose drops; a heavier aircraft turns its rotor faster.
    #[test]
    fn trends_with_speed_and_weight() {
        let a = gyroplane();
        let mph = 0.44704;
        let slow = trim(&a, condition(30.0 * mph), TrimOptions::default()).unwrap();
        let fast = trim(&a, condition(70.0 * mph), TrimOptions::default()).unwrap();
        assert!(
            fast.controls.stick_longitudinal_percent < slow.controls.stick_longitudinal_percent
        );
        assert!(fast.pitch_rad < slow.pitch_rad);
        let mut light = gyroplane();
        light.mass.mass_kg = 380.0;
        let l = trim(&light, condition(70.0 * mph), TrimOptions::default()).unwrap();
        assert!(
            l.rotor_rpm < fast.rotor_rpm,
            "{} vs {}",
            l.rotor_rpm,
            fast.rotor_rpm
        );
    }

    /// A climb needs more throttle; a coordinated-ish turn banks by about atan(V psi_dot / g).
    #[test]
    fn climbs_and_turns() {
        let a = gyroplane();
        let level = trim(&a, condition(31.3), TrimOptions::default()).unwrap();
        let climb = trim(
            &a,
            Condition {
                climb_m_s: 2.0,
                ..condition(31.3)
            },
            TrimOptions::default(),
        )
        .unwrap();
        assert!(climb.controls.throttle_percent > level.controls.throttle_percent);
        let rate = 0.15;
        let turn = trim(
            &a,
            Condition {
                turn_rate_rad_s: rate,
                ..condition(31.3)
            },
            TrimOptions::default(),
        )
        .unwrap();
        let coordinated = (31.3 * rate / G_M_S2).atan();
        assert!(
            (turn.roll_rad - coordinated).abs() < 3f64.to_radians(),
            "{} vs {}",
            turn.roll_rad.to_degrees(),
            coordinated.to_degrees()
        );
        assert!(
            turn.rotor_rpm > level.rotor_rpm,
            "load factor spins the rotor up"
        );
    }

    /// Conditions that cannot be flown, or data that are not physical, are errors that say
    /// why, with the last residuals where the solver ran.
    #[test]
    fn impossible_conditions_are_clear_errors() {
        let a = gyroplane();
        let steep = trim(
            &a,
            Condition {
                climb_m_s: 12.0,
                ..condition(31.3)
            },
            TrimOptions::default(),
        );
        match steep {
            // The climb needs more power than the engine has; the stick may leave its travel
            // first (it does with the propeller's normal force, 148 % against 158 % throttle).
            Err(TrimError::OutsideTravel { ref trim, .. }) => {
                assert!(trim.controls.throttle_percent > 100.0, "{steep:#?}")
            }
            Err(TrimError::NoConvergence { residuals, .. }) => assert_eq!(residuals.len(), 11),
            other => panic!("{other:?}"),
        }
        let mut heavy = gyroplane();
        heavy.mass.mass_kg = -1.0;
        assert!(matches!(
            trim(&heavy, condition(31.3), TrimOptions::default()),
            Err(TrimError::Aircraft(AircraftError::Body(_)))
        ));
        assert!(matches!(
            trim(&a, condition(0.0), TrimOptions::default()),
            Err(TrimError::Condition {
                name: "airspeed_m_s",
                ..
            })
        ));
        // Beyond the airframe tables (alpha to 60 deg): a steep descent at low speed.
        let e = trim(
            &a,
            Condition {
                climb_m_s: -9.0,
                ..condition(10.0)
            },
            TrimOptions::default(),
        );
        match e {
            Err(TrimError::Solver(m)) => assert!(m.contains("outside the table"), "{m}"),
            other => panic!("{other:?}"),
        }
    }
}
