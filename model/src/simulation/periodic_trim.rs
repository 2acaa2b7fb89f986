//! The full individual-blade model's trim: the averaged trim ([`crate::aircraft::trim`])
//! refined on the periodic orbit that a simulation ([`super::timehistory`]) flies.

use crate::aircraft::trim::{Condition, Problem, Trim, TrimError, TrimOptions, residual_names};
use crate::aircraft::{
    Air, Aircraft, AircraftError, Controls, Drive, FullState, HubAccelerations, RotorCache,
};
use crate::components::rotor::Blade;
use crate::solve::{self, SolveError};
use serde::Serialize;

/// The slow states of the full model: `u v w p q r phi theta Omega Omega_prop`.
fn slow_of(x: &FullState) -> [f64; 10] {
    let b = &x.body;
    [
        b.u_m_s,
        b.v_m_s,
        b.w_m_s,
        b.p_rad_s,
        b.q_rad_s,
        b.r_rad_s,
        b.phi_rad,
        b.theta_rad,
        x.rotor_omega_rad_s,
        x.propeller_omega_rad_s,
    ]
}

fn set_slow(x: &mut FullState, v: &[f64]) {
    let b = &mut x.body;
    b.u_m_s = v[0];
    b.v_m_s = v[1];
    b.w_m_s = v[2];
    b.p_rad_s = v[3];
    b.q_rad_s = v[4];
    b.r_rad_s = v[5];
    b.phi_rad = v[6];
    b.theta_rad = v[7];
    x.rotor_omega_rad_s = v[8];
    x.propeller_omega_rad_s = v[9];
}

/// A trim of the full individual-blade model: the controls, attitudes and speeds at which its
/// periodic motion has zero revolution-averaged accelerations.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PeriodicTrim {
    /// The full state with blade 1 at azimuth zero, on the periodic orbit.
    pub start: FullState,
    pub controls: Controls,
    pub residuals: Vec<(String, f64)>,
    pub residual_norm: f64,
    pub iterations: usize,
}

/// Refines a trim of the revolution-averaged model into a trim of the full model
/// ([`Aircraft::derivatives`]). Everything is free within a revolution: the blades, the
/// dynamic inflow, and the airframe, rotorspeed and propeller speed, which a two-bladed rotor
/// shakes twice a revolution. The orbit is found by repeating revolutions, each started where
/// the last ended but with the slow states shifted so that their means over the revolution
/// are the flight condition's (flap to 1e-9 rad, inflow to 1e-7 m/s, means to 1e-9). The mean
/// accelerations over that orbit are driven to zero by the same Newton-Broyden solver and
/// criterion as [`crate::aircraft::trim::trim`]. The two trims differ because the airframe's
/// and inflow's response to the individual blades' pulsing loads rectifies into mean loads
/// that the averaged model does not see. Simulations start from this trim, at blade 1 over
/// the tail.
pub fn periodic_trim(
    aircraft: &Aircraft,
    condition: Condition,
    averaged: &Trim,
    options: TrimOptions,
) -> Result<PeriodicTrim, TrimError> {
    // The orbit of the model a simulation flies: the propeller on its map, as
    // `timehistory::run` has it (within 3e-5 of the exact solve, at a seventh of the cost).
    let mapped = aircraft.with_propeller_map();
    let aircraft = &mapped;
    let r = aircraft.main_rotor.rotor.radius_m;
    let omega0 = averaged.state.rotor_omega_rad_s;
    let (engine, prop0) = match aircraft.propeller.drive {
        Drive::Engine { .. } => (true, averaged.state.propeller_omega_rad_s),
        Drive::Governed { .. } => (false, 1.0),
    };
    let p = Problem {
        aircraft,
        condition,
        omega0,
        tip0: omega0 * r,
        prop0,
        engine,
        harmonics: false,
        warm: averaged.averaged.flap_start,
        rotor: RotorCache::default(),
        hub: HubAccelerations::Agreed,
        last: None,
        calls: 0,
    };
    let air = condition.air;
    let z0 = start_unknowns(averaged, engine);
    let step = aircraft.main_rotor.numerics.azimuth_step_rad;
    let n = aircraft
        .main_rotor
        .rotor
        .steps_per_revolution(step)
        .map_err(AircraftError::from)?;
    let mut warm_flap: Vec<[f64; 2]> = aircraft
        .full_state(
            &averaged.state,
            &averaged.controls,
            air,
            averaged.averaged.flap_start,
        )
        .flap;
    let mut warm_inflow = averaged.state.inflow;
    let mut last_start: Option<FullState> = None;
    // The blade elements, prepared once for every revolution.
    let blade = crate::components::rotor::Blade::new(
        &aircraft.main_rotor.rotor,
        aircraft.main_rotor.numerics,
    );
    let mut evaluate = |z: &[f64]| -> Result<Vec<f64>, AircraftError> {
        let (state, controls) = p.unpack(&averaged_unknowns(z, engine));
        let fs = FullState {
            body: state.body,
            rotor_azimuth_rad: 0.0,
            rotor_omega_rad_s: state.rotor_omega_rad_s,
            flap: warm_flap.clone(),
            inflow: warm_inflow,
            propeller_omega_rad_s: if engine {
                state.propeller_omega_rad_s
            } else {
                aircraft.propeller_omega(&state, &controls)
            },
        };
        let (fs, mean_rates) = orbit(aircraft, &blade, fs, controls, air, n)?;
        warm_flap = fs.flap.clone();
        warm_inflow = fs.inflow;
        last_start = Some(fs.clone());
        Ok(mean_residuals(mean_rates, omega0, prop0, engine))
    };
    let sol = solve::newton(
        |z| evaluate(z).map_err(|e| e.to_string()),
        &z0,
        options.newton,
    );
    let names = periodic_residual_names(engine);
    let sol = match sol {
        Ok(s) => s,
        Err(SolveError::NoConvergence {
            residuals,
            iterations,
            ..
        }) => {
            return Err(TrimError::NoConvergence {
                residuals: names.into_iter().zip(residuals).collect(),
                iterations,
            });
        }
        Err(e) => return Err(TrimError::Solver(e.to_string())),
    };
    let residuals = evaluate(&sol.x)?;
    let start = last_start.ok_or_else(|| TrimError::Solver("no periodic solution".into()))?;
    let (_, controls) = p.unpack(&averaged_unknowns(&sol.x, engine));
    Ok(PeriodicTrim {
        start,
        controls,
        residual_norm: residuals.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        residuals: names.into_iter().zip(residuals).collect(),
        iterations: sol.iterations,
    })
}

/// The periodic orbit of the whole model at constant controls through the start `fs` (blade 1
/// at azimuth zero), in `n` steps a revolution: revolutions repeated, each started where the
/// last ended but with the slow states shifted so that their means over the revolution are
/// `fs`'s (flap to 1e-9 rad, inflow to 1e-7 m/s, means to 1e-9). The start on the orbit and
/// the mean rates of the slow states over it.
fn orbit(
    aircraft: &Aircraft,
    blade: &Blade,
    mut fs: FullState,
    controls: Controls,
    air: Air,
    n: usize,
) -> Result<(FullState, [f64; 10]), AircraftError> {
    let omega = fs.rotor_omega_rad_s;
    let dt = 2.0 * std::f64::consts::PI / n as f64 / omega;
    // The slow states' targets: their means over the orbit.
    let target = slow_of(&fs);
    let mut converged = false;
    let mut mean_rates = [0.0; 10];
    for _ in 0..60 {
        let (end, mean_x, mean_d) = revolution(aircraft, blade, &fs, controls, air, n, dt)?;
        mean_rates = mean_d;
        let change_flap = fs
            .flap
            .iter()
            .zip(&end.flap)
            .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs() / omega))
            .fold(0.0, f64::max);
        let change_inflow = (fs.inflow.v0 - end.inflow.v0)
            .abs()
            .max((fs.inflow.v1s - end.inflow.v1s).abs())
            .max((fs.inflow.v1c - end.inflow.v1c).abs());
        let off: Vec<f64> = (0..10).map(|i| target[i] - mean_x[i]).collect();
        let off_max = off.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        // Next start: the fast states where the revolution ended, the slow states moved
        // so that their means over the orbit hit the targets.
        let mut next = end;
        let start_slow = slow_of(&fs);
        let shifted: Vec<f64> = (0..10).map(|i| start_slow[i] + off[i]).collect();
        set_slow(&mut next, &shifted);
        next.rotor_azimuth_rad = 0.0;
        fs = next;
        if change_flap <= 1e-9 && change_inflow <= 1e-7 && off_max <= 1e-9 {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(AircraftError::Rotor(
            crate::components::rotor::RotorError::FlapNotPeriodic {
                revolutions: 60,
                change: f64::NAN,
            },
        ));
    }
    Ok((fs, mean_rates))
}

/// One revolution of the whole model from `fs` at constant controls, in `n` steps of `dt`: the
/// end state, the mean of the slow states and the mean of their rates.
fn revolution(
    aircraft: &Aircraft,
    blade: &Blade,
    fs: &FullState,
    controls: Controls,
    air: Air,
    n: usize,
    dt: f64,
) -> Result<(FullState, [f64; 10], [f64; 10]), AircraftError> {
    let mut x = fs.clone();
    let (mut mean_x, mut mean_d) = ([0.0; 10], [0.0; 10]);
    for k in 0..n {
        let d = aircraft.derivatives_with(blade, &x, &controls, air, [0.0; 3])?;
        let (sx, sd) = (slow_of(&x), slow_of(&d));
        for i in 0..10 {
            mean_x[i] += sx[i] / n as f64;
            mean_d[i] += sd[i] / n as f64;
        }
        x = crate::simulation::timehistory::step_with(
            aircraft,
            blade,
            &x,
            k as f64 * dt,
            dt,
            crate::simulation::timehistory::Drivers {
                controls: &|_, _| controls,
                wind: &crate::simulation::timehistory::still,
            },
            air,
        )?;
    }
    Ok((x, mean_x, mean_d))
}

/// The periodic trim's unknowns from an averaged trim: controls, attitudes, rotorspeed (and
/// propeller speed), scaled as in [`crate::aircraft::trim::trim`].
fn start_unknowns(averaged: &Trim, engine: bool) -> Vec<f64> {
    let c = averaged.controls;
    let b = averaged.state.body;
    let mut z0 = vec![
        c.stick_longitudinal_percent / 100.0,
        c.stick_lateral_percent / 100.0,
        c.pedal_percent / 100.0,
        c.throttle_percent / 100.0,
        b.theta_rad,
        b.phi_rad,
        1.0,
    ];
    if engine {
        z0.push(1.0);
    }
    z0
}

/// The averaged trim's unknowns for the periodic trim's `z` (its inflow unknowns zero).
fn averaged_unknowns(z: &[f64], engine: bool) -> Vec<f64> {
    let mut x = vec![z[0], z[1], z[2], z[3], z[4], z[5], z[6], 0.0, 0.0, 0.0];
    if engine {
        x.push(z[7]);
    }
    x
}

/// The periodic trim's residuals from the slow states' mean rates over the orbit, scaled as
/// the averaged trim's (translational accelerations in g, rotor and propeller accelerations
/// divided by the trim's speeds `omega0` and `prop0`).
fn mean_residuals(m: [f64; 10], omega0: f64, prop0: f64, engine: bool) -> Vec<f64> {
    let g = crate::components::rigid_body::G_M_S2;
    let mut res = vec![
        m[0] / g,
        m[1] / g,
        m[2] / g,
        m[3],
        m[4],
        m[5],
        m[8] / omega0,
    ];
    if engine {
        res.push(m[9] / prop0);
    }
    res
}

/// The names of [`mean_residuals`]: the averaged trim's but the inflow's.
fn periodic_residual_names(engine: bool) -> Vec<String> {
    let mut names: Vec<String> = residual_names(false)[..7]
        .iter()
        .map(|s| s.to_string())
        .collect();
    if engine {
        names.push(residual_names(true)[10].to_string());
    }
    names
}
