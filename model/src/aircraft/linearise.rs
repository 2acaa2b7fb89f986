//! Numerical linearisation of the trimmed aircraft (seed 001 Eqs. 10-12).
//!
//! The nine rigid-body states `x1 = [u v w p q r phi theta psi]` and the rotorspeed `x2 = [Omega]`,
//! with the controls `eta_s` (longitudinal stick), `eta_c` (lateral stick), `eta_p` (pedal) and
//! `eta_t` (throttle), all in percent of travel. The derivatives are the partial derivatives of the
//! state rates, `A[i][j] = d xdot_i / d x_j`, in SI units: `X_u` in 1/s, `M_w` in 1/(m s), `Q_u` in
//! rad/(m s), `L_eta_c` in rad/s^2 per percent. The rolling and yawing rows include the `I_xz`
//! coupling (they are the rates `p_dot`, `r_dot`, not `L/I_xx`).
//!
//! # What is held and what follows
//! The blades are in their periodic motion at every perturbed point (quasi-steady flapping), and
//! the fast states follow quasi-steadily: the inflow `(v0, v1s, v1c)` stays in equilibrium with the
//! rotor's loads, and with an engine drive the propeller speed stays where engine and propeller
//! torques balance. Where the blades feel the hub's motion, the body's accelerations their flapping
//! is solved under (the angular acceleration, and the apparent gravity where the blades have a
//! first mass moment) agree with those the loads imply. All of them are eliminated exactly to first
//! order (implicit-function theorem) from one set of central differences: `A = F_x - F_z G_z^-1
//! G_x`, with `z` the fast variables and `G` their equilibrium residuals (for the accelerations,
//! implied less held). Each evaluation then solves the rotor's periodic motion once, where
//! iterating the accelerations to agreement in every evaluation takes about five (the two agree to
//! 2e-4 of a row: tested). The rotorspeed is held at its trim value for `A11, A21, B1, B2` and
//! perturbed only for the `Omega` column (`A12, A22`), as in seed 001.
//!
//! # Step sizes
//! Central differences with steps of 0.1 m/s in velocity (0.3 % of a 70 mph airspeed), 0.01 rad/s
//! in rates, 0.01 rad in angles, 0.1 rad/s in rotorspeed (0.25 %), 0.5 % of control travel, 0.01
//! m/s in inflow and rad/s in propeller speed, and 0.1 m/s^2 and 0.1 rad/s^2 in the apparent
//! gravity and angular acceleration the blades feel: small enough that the truncation error (second
//! order in the step) is below 0.1 % of the derivatives, large enough that the periodic solution's
//! tolerance (1e-9 rad) adds no visible noise. Halving every step changes no derivative by more
//! than 0.5 % of its row's scale (tested).
//!
//! # Cost
//! Two revolution-averaged evaluations for each of the 14 states and controls and the fast
//! variables (the inflow's 3, the propeller speed with an engine, and the accelerations the blades
//! feel: three without a first mass moment, six with one), over two threads: 42 for the VPM M16.
//! Those that leave the rotor's operating state unchanged take the trim's periodic solution: the
//! attitudes, the pedal, throttle and propeller speed (the accelerations the blades feel are held).
//! The others start their secant steps from what the trim learned of the revolution map, and each
//! column's second side starts its blade where the first side's mirrored about the trim's puts it:
//! about 2.5 revolutions of the main rotor each, where a cold solution takes 4 or more.
//!
//! # Contributions
//! Every derivative is split into the contributions of the rotor, the propeller and the airframe
//! (seed 000 Tables 1-2): each component's load perturbation, including what the eliminated fast
//! states do to it, mapped through the mass and inertia. What remains (gravity and the rigid-body
//! kinematics) is the `inertial` part. The contributions add up to the total.

use crate::aircraft::trim::Trim;
use crate::aircraft::{
    Air, Aircraft, AircraftError, Averaged, Controls, Drive, HubAccelerations, RotorCache, State,
};
use crate::analysis::linear::{LinearModel, LinearModelError};
use crate::components::rigid_body::{self, FreeSpin, Loads, MassProperties};
use nalgebra::DMatrix;
use serde::Serialize;
use thiserror::Error;

/// State names, in order.
pub const STATES: [&str; 10] = ["u", "v", "w", "p", "q", "r", "phi", "theta", "psi", "Omega"];
/// Control names, in order (percent of travel).
pub const CONTROLS: [&str; 4] = ["eta_s", "eta_c", "eta_p", "eta_t"];
/// Component names of the breakdown, in order.
pub const COMPONENTS: [&str; 4] = ["rotor", "propeller", "airframe", "inertial"];

/// Perturbation sizes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Steps {
    pub velocity_m_s: f64,
    pub rate_rad_s: f64,
    pub angle_rad: f64,
    pub omega_rad_s: f64,
    pub control_percent: f64,
    pub inflow_m_s: f64,
    pub propeller_rad_s: f64,
    /// The tip-path plane's tilt, for the linearisation with flapping states
    /// ([`crate::aircraft::flapping`]).
    pub flap_rad: f64,
    /// The apparent gravity the blades' flapping is solved under, where the blades feel it
    /// (eliminated as the inflow is).
    pub apparent_gravity_m_s2: f64,
    /// The angular acceleration the blades' flapping is solved under, on a flapping hub.
    pub angular_acceleration_rad_s2: f64,
}

impl Default for Steps {
    fn default() -> Self {
        Self {
            velocity_m_s: 0.1,
            rate_rad_s: 0.01,
            angle_rad: 0.01,
            omega_rad_s: 0.1,
            control_percent: 0.5,
            inflow_m_s: 0.01,
            propeller_rad_s: 0.01,
            flap_rad: 0.002,
            apparent_gravity_m_s2: 0.1,
            angular_acceleration_rad_s2: 0.1,
        }
    }
}

impl Steps {
    /// Every step multiplied by `k`.
    pub fn scaled(&self, k: f64) -> Self {
        Self {
            velocity_m_s: self.velocity_m_s * k,
            rate_rad_s: self.rate_rad_s * k,
            angle_rad: self.angle_rad * k,
            omega_rad_s: self.omega_rad_s * k,
            control_percent: self.control_percent * k,
            inflow_m_s: self.inflow_m_s * k,
            propeller_rad_s: self.propeller_rad_s * k,
            flap_rad: self.flap_rad * k,
            apparent_gravity_m_s2: self.apparent_gravity_m_s2 * k,
            angular_acceleration_rad_s2: self.angular_acceleration_rad_s2 * k,
        }
    }
}

/// The linearised aircraft.
#[derive(Debug, Clone, PartialEq)]
pub struct Linearised {
    /// States [`STATES`], controls [`CONTROLS`].
    pub model: LinearModel,
    /// The same matrices split by component, in the order of [`COMPONENTS`]; they add up to
    /// `model`.
    pub components: Vec<(String, LinearModel)>,
    pub steps: Steps,
}

impl Linearised {
    /// The longitudinal subset `[u w q theta Omega]` with `eta_s` (seed 000 Eq. 3, seed 002
    /// Eq. 2).
    pub fn longitudinal(&self) -> Result<LinearModel, LinearModelError> {
        let sub = self.model.subsystem(&["u", "w", "q", "theta", "Omega"])?;
        let b = sub.b().columns(0, 1).into_owned();
        LinearModel::new(
            sub.states().to_vec(),
            vec!["eta_s".to_string()],
            sub.a().clone(),
            b,
        )
    }

    /// One derivative's contributions by component, in the order of [`COMPONENTS`].
    pub fn breakdown(&self, name: &str) -> Result<Vec<(String, f64)>, LinearModelError> {
        let e = self.model.derivative(name)?;
        self.components
            .iter()
            .map(|(c, m)| Ok((c.clone(), m.get(e))))
            .collect()
    }
}

/// Why the linearisation failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinearisationError {
    #[error(transparent)]
    Aircraft(#[from] AircraftError),
    #[error(
        "the fast variables' equilibrium is singular (no quasi-steady inflow, propeller speed or agreement of the body's accelerations with the rotor's flapping)"
    )]
    Singular,
    #[error(transparent)]
    Model(#[from] LinearModelError),
    #[error("a linearisation worker thread stopped unexpectedly")]
    Worker,
}

/// What one evaluation gives: the slow rates (10), the fast residuals (the inflow's 3, the
/// propeller speed's with an engine, one for each acceleration the blades feel), and each
/// component's loads as accelerations (3 x 6).
struct Sample {
    slow: [f64; 10],
    fast: Vec<f64>,
    parts: [[f64; 6]; 3],
}

impl Sample {
    /// The sample of the evaluation `a` at `state` and `controls`: its slow rates, its fast
    /// residuals (the inflow's, the propeller speed's with an engine, then `disagree`), and its
    /// components' loads as accelerations.
    fn of(
        aircraft: &Aircraft,
        a: &Averaged,
        state: &State,
        controls: &Controls,
        engine: bool,
        disagree: impl Iterator<Item = f64>,
    ) -> Result<Sample, AircraftError> {
        // The body's rates but the position's, and the rotorspeed's.
        let mut slow = [0.0; 10];
        slow[..9].copy_from_slice(&a.body_dot.to_array()[..9]);
        slow[9] = a.rotor_omega_dot_rad_s2;
        let eq = a.inflow_equilibrium;
        let mut fast = vec![
            eq.v0 - state.inflow.v0,
            eq.v1s - state.inflow.v1s,
            eq.v1c - state.inflow.v1c,
        ];
        if engine {
            fast.push(a.propeller_omega_dot_rad_s2);
        }
        fast.extend(disagree);
        let l = &a.loads;
        let free = aircraft.free_spins(controls);
        let parts = [
            accelerations(&aircraft.mass, &free, &l.rotor)?,
            accelerations(&aircraft.mass, &free, &l.propeller)?,
            accelerations(&aircraft.mass, &free, &l.airframe)?,
        ];
        Ok(Sample { slow, fast, parts })
    }
}

/// Accelerations `[u v w p q r]` that loads alone produce (no gravity, no rates), with the
/// free rotors' polar moments out of the inertia, as in the equations of motion.
fn accelerations(
    m: &MassProperties,
    free: &[FreeSpin],
    l: &Loads,
) -> Result<[f64; 6], AircraftError> {
    let [p, q, r] = rigid_body::angular_accelerations(m, [l.l_n_m, l.m_n_m, l.n_n_m], free)?;
    Ok([
        l.x_n / m.mass_kg,
        l.y_n / m.mass_kg,
        l.z_n / m.mass_kg,
        p,
        q,
        r,
    ])
}

/// Linearises the aircraft about a trim.
pub fn linearise(
    aircraft: &Aircraft,
    trim: &Trim,
    air: Air,
    steps: Steps,
) -> Result<Linearised, LinearisationError> {
    linearise_by(aircraft, trim, air, steps, Hub::FastStates)
}

/// How a linearisation's evaluations treat the body's accelerations that the blades' flapping
/// is solved under, where the blades feel them.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Hub {
    /// Held, and moved as fast variables of their own, their agreement with what the loads
    /// imply eliminated with the inflow's: a periodic solution an evaluation at most (42
    /// evaluations for the VPM M16: an engine and three accelerations felt).
    FastStates,
    /// Iterated to agreement in each evaluation (the model's own evaluation, about five
    /// periodic solutions each): what [`Hub::FastStates`] must give to first order, kept to
    /// test that it does.
    #[cfg(test)]
    Agreed,
}

/// [`linearise`] with the hub's accelerations treated as `hub` says.
fn linearise_by(
    aircraft: &Aircraft,
    trim: &Trim,
    air: Air,
    steps: Steps,
    hub: Hub,
) -> Result<Linearised, LinearisationError> {
    let engine = matches!(aircraft.propeller.drive, Drive::Engine { .. });
    let base_state = trim.state;
    let base_controls = trim.controls;
    let warm = trim.averaged.flap_start;
    // The body's accelerations the blades' flapping is solved under, held at the trim's (the
    // steady motion's) and moved as variables of their own where the blades feel them, their
    // agreement with what the loads imply a fast residual: eliminated with the inflow.
    let held = Aircraft::steady_accelerations(&base_state.body);
    let felt = match aircraft.blades_feel_the_hub() && hub == Hub::FastStates {
        true => aircraft.first_felt_acceleration()..6,
        false => 6..6,
    };
    let solved_under = |y: [f64; 6]| match hub {
        Hub::FastStates => HubAccelerations::Held(y),
        #[cfg(test)]
        Hub::Agreed => HubAccelerations::Agreed,
    };
    let eval = |(state, controls, y): &(State, Controls, [f64; 6]),
                cache: &mut RotorCache,
                warm: [f64; 2]|
     -> Result<Sample, AircraftError> {
        let (a, implied, _): (Averaged, _, _) =
            aircraft.averaged_under(state, controls, air, warm, cache, solved_under(*y))?;
        // What the blades felt less what the loads imply: a fast residual.
        let disagree = felt.clone().map(|k| implied[k] - y[k]);
        Sample::of(aircraft, &a, state, controls, engine, disagree)
    };
    // The fast variables: the inflow, the propeller speed with an engine, then the felt
    // accelerations; `felt_at(j)` is the acceleration variable `j` moves, if it moves one.
    let first_felt_variable = 14 + if engine { 4 } else { 3 };
    let nz = first_felt_variable - 14 + felt.len();
    let felt_at = |j: usize| j.checked_sub(first_felt_variable).map(|k| felt.start + k);
    let perturb = |j: usize, h: f64| match felt_at(j) {
        Some(k) => {
            let mut y = held;
            y[k] += h;
            (base_state, base_controls, y)
        }
        None => {
            let (s, c) = perturbed(base_state, base_controls, j, h);
            (s, c, held)
        }
    };
    let nv = 14 + nz;
    // Columns: d(slow)/d var, d(fast)/d var, d(parts)/d var.
    let mut d_slow = DMatrix::<f64>::zeros(10, nv);
    let mut d_fast = DMatrix::<f64>::zeros(nz, nv);
    let mut d_parts = vec![DMatrix::<f64>::zeros(6, nv); 3];
    // Central differences, the columns shared between two threads (the machine's two
    // cores); each keeps its own cache of rotor solutions, which starts with the trim's
    // solution and what the trim learned of the revolution map.
    let (trimmed, map) = (
        trim.warm_start.rotor_seed(aircraft),
        trim.warm_start.revolution_map(),
    );
    let columns = |js: Vec<usize>| -> Result<Vec<(usize, f64, Sample, Sample)>, AircraftError> {
        let mut cache = RotorCache::default();
        cache.hold(trimmed);
        cache.learned(map);
        js.into_iter()
            .map(|j| {
                let h = match felt_at(j) {
                    Some(k) if k < 3 => steps.apparent_gravity_m_s2,
                    Some(_) => steps.angular_acceleration_rad_s2,
                    None => step_of(&steps, j),
                };
                let plus = eval(&perturb(j, h), &mut cache, warm)?;
                // The blade's periodic start moves to first order with the perturbation: the
                // other side's starts where the first side's, mirrored about the trim's, puts
                // it (to second order in the step).
                let mirrored = cache.last().map_or(warm, |(_, l)| {
                    [2.0 * warm[0] - l.beta0[0], 2.0 * warm[1] - l.beta0[1]]
                });
                Ok((j, h, plus, eval(&perturb(j, -h), &mut cache, mirrored)?))
            })
            .collect()
    };
    let (even, odd): (Vec<usize>, Vec<usize>) = (0..nv).partition(|j| j % 2 == 0);
    let (a_cols, b_cols) = std::thread::scope(|scope| {
        let other = scope.spawn(|| columns(odd));
        let mine = columns(even);
        (mine, other.join())
    });
    let b_cols = b_cols.map_err(|_| LinearisationError::Worker)?;
    for (j, h, p, m) in a_cols?.into_iter().chain(b_cols?) {
        for i in 0..10 {
            d_slow[(i, j)] = (p.slow[i] - m.slow[i]) / (2.0 * h);
        }
        for i in 0..nz {
            d_fast[(i, j)] = (p.fast[i] - m.fast[i]) / (2.0 * h);
        }
        for (c, d) in d_parts.iter_mut().enumerate() {
            for i in 0..6 {
                d[(i, j)] = (p.parts[c][i] - m.parts[c][i]) / (2.0 * h);
            }
        }
    }
    let (total, parts) = eliminate(&d_slow, &d_fast, &d_parts)?;
    let (a, b) = split(&total);
    let model = LinearModel::from_rows(names(&STATES), names(&CONTROLS), &a, &b)?;
    let components = component_models(aircraft, &base_controls, &total, &parts)?;
    Ok(Linearised {
        model,
        components,
        steps,
    })
}

/// The slow rates' and the components' derivatives with the fast variables (the columns after
/// the 14 states and controls) eliminated: `dz/d(x,u) = -G_z^-1 G_(x,u)`.
fn eliminate(
    d_slow: &DMatrix<f64>,
    d_fast: &DMatrix<f64>,
    d_parts: &[DMatrix<f64>],
) -> Result<(DMatrix<f64>, Vec<DMatrix<f64>>), LinearisationError> {
    let nz = d_fast.nrows();
    let g_z = d_fast.columns(14, nz).into_owned();
    let g_xu = d_fast.columns(0, 14).into_owned();
    let lu = g_z.lu();
    let dz = lu.solve(&(-&g_xu)).ok_or(LinearisationError::Singular)?;
    if dz.iter().any(|v| !v.is_finite()) {
        return Err(LinearisationError::Singular);
    }
    let total = d_slow.columns(0, 14) + d_slow.columns(14, nz) * &dz;
    let parts: Vec<DMatrix<f64>> = d_parts
        .iter()
        .map(|d| d.columns(0, 14) + d.columns(14, nz) * &dz)
        .collect();
    Ok((total, parts))
}

/// The trim's state and controls with variable `j` (in the order of the linearisation's
/// columns: the states, the controls, the inflow, the propeller speed; not the accelerations
/// after them) moved by `h`.
fn perturbed(base_state: State, base_controls: Controls, j: usize, h: f64) -> (State, Controls) {
    let mut s = base_state;
    let mut c = base_controls;
    let b = &mut s.body;
    match j {
        0 => b.u_m_s += h,
        1 => b.v_m_s += h,
        2 => b.w_m_s += h,
        3 => b.p_rad_s += h,
        4 => b.q_rad_s += h,
        5 => b.r_rad_s += h,
        6 => b.phi_rad += h,
        7 => b.theta_rad += h,
        8 => b.psi_rad += h,
        9 => s.rotor_omega_rad_s += h,
        10 => c.stick_longitudinal_percent += h,
        11 => c.stick_lateral_percent += h,
        12 => c.pedal_percent += h,
        13 => c.throttle_percent += h,
        14 => s.inflow.v0 += h,
        15 => s.inflow.v1s += h,
        16 => s.inflow.v1c += h,
        _ => s.propeller_omega_rad_s += h,
    }
    (s, c)
}

/// The central-difference step of variable `j` (see [`perturbed`]).
fn step_of(steps: &Steps, j: usize) -> f64 {
    match j {
        0..=2 => steps.velocity_m_s,
        3..=5 => steps.rate_rad_s,
        6..=8 => steps.angle_rad,
        9 => steps.omega_rad_s,
        10..=13 => steps.control_percent,
        14..=16 => steps.inflow_m_s,
        _ => steps.propeller_rad_s,
    }
}

/// Owned names.
fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect::<Vec<_>>()
}

/// A 10 x 14 Jacobian's state and control columns, `A` and `B` by rows.
fn split(m: &DMatrix<f64>) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let a = (0..10)
        .map(|i| (0..10).map(|j| m[(i, j)]).collect())
        .collect();
    let b = (0..10)
        .map(|i| (10..14).map(|j| m[(i, j)]).collect())
        .collect();
    (a, b)
}

/// Component models: the six acceleration rows of each part. The rotorspeed is relative to
/// the airframe, so its row holds the airframe's angular acceleration about the shaft: the
/// propeller and airframe own their share of it, and the rotor the rest (its torque, and the
/// gyroscopic terms). The kinematic rows and the rest are inertial.
fn component_models(
    aircraft: &Aircraft,
    base_controls: &Controls,
    total: &DMatrix<f64>,
    parts: &[DMatrix<f64>],
) -> Result<Vec<(String, LinearModel)>, LinearModelError> {
    let shaft = aircraft.free_spins(base_controls)[0].axis;
    let about_shaft =
        |p: &DMatrix<f64>, j: usize| (0..3).map(|k| shaft[k] * p[(3 + k, j)]).sum::<f64>();
    let mut comps = Vec::new();
    let mut accounted = DMatrix::<f64>::zeros(10, 14);
    for (c, p) in parts.iter().enumerate() {
        let mut m = DMatrix::<f64>::zeros(10, 14);
        for i in 0..6 {
            for j in 0..14 {
                m[(i, j)] = p[(i, j)];
            }
        }
        for j in 0..14 {
            m[(9, j)] = if c == 0 {
                total[(9, j)] - about_shaft(&parts[1], j) - about_shaft(&parts[2], j)
            } else {
                about_shaft(p, j)
            };
        }
        accounted += &m;
        comps.push((COMPONENTS[c].to_string(), m));
    }
    comps.push((COMPONENTS[3].to_string(), total - &accounted));
    comps
        .iter()
        .map(|(n, m)| {
            let (a, b) = split(m);
            Ok((
                n.clone(),
                LinearModel::from_rows(names(&STATES), names(&CONTROLS), &a, &b)?,
            ))
        })
        .collect::<Result<Vec<_>, LinearModelError>>()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testdata::{sea_level_air as air, trimmed_gyroplane};

    /// Halving every step changes no derivative by more than 0.5 % of its row's largest
    /// state derivative (and 1e-6 absolute), at two airspeeds.
    #[test]
    fn two_step_sizes_agree() {
        for v in [20.0, 31.3] {
            let (a, t) = trimmed_gyroplane(v);
            let l1 = linearise(&a, &t, air(), Steps::default()).unwrap();
            let l2 = linearise(&a, &t, air(), Steps::default().scaled(0.5)).unwrap();
            let (a1, a2) = (l1.model.a(), l2.model.a());
            let (b1, b2) = (l1.model.b(), l2.model.b());
            for i in 0..10 {
                let scale = (0..10).map(|j| a1[(i, j)].abs()).fold(0.0, f64::max);
                for j in 0..10 {
                    let d = (a1[(i, j)] - a2[(i, j)]).abs();
                    assert!(
                        d <= 5e-3 * scale + 1e-6,
                        "A[{},{}] at {v} m/s: {} vs {}",
                        STATES[i],
                        STATES[j],
                        a1[(i, j)],
                        a2[(i, j)]
                    );
                }
                let bscale = (0..4).map(|j| b1[(i, j)].abs()).fold(0.0, f64::max);
                for j in 0..4 {
                    let d = (b1[(i, j)] - b2[(i, j)]).abs();
                    assert!(
                        d <= 5e-3 * bscale + 1e-6,
                        "B[{},{}]",
                        STATES[i],
                        CONTROLS[j]
                    );
                }
            }
        }
    }

    /// What a linearisation takes from its trim (the main rotor's periodic solution, what the
    /// trim learned of the revolution map) changes how soon its periodic solutions are found,
    /// not what they are: without it (the trim's warm start emptied) no derivative moves by
    /// more than `PERIODIC_NOISE` of its row's largest. Both start each column's second side
    /// from the first's mirrored about the trim's.
    #[test]
    fn what_the_trim_learned_changes_no_derivative() {
        // The periodic solution closes to 5e-11 rad (`SAMPLED_CLOSURE` times the tolerance):
        // over central-difference steps of 0.01 that is derivatives to about 1e-8 of their
        // row's scale; measured 1.2e-8 at most here (L_r at 31.3 m/s).
        const PERIODIC_NOISE: f64 = 1e-6;
        for v in [20.0, 31.3] {
            let (a, t) = trimmed_gyroplane(v);
            let emptied = Trim {
                warm_start: Default::default(),
                ..t.clone()
            };
            let l1 = linearise(&a, &t, air(), Steps::default()).unwrap();
            let l2 = linearise(&a, &emptied, air(), Steps::default()).unwrap();
            for (m1, m2) in [(l1.model.a(), l2.model.a()), (l1.model.b(), l2.model.b())] {
                for i in 0..10 {
                    let scale = (0..m1.ncols())
                        .map(|j| m1[(i, j)].abs())
                        .fold(0.0, f64::max);
                    for j in 0..m1.ncols() {
                        let d = (m1[(i, j)] - m2[(i, j)]).abs();
                        assert!(
                            d <= PERIODIC_NOISE * scale,
                            "row {} column {j} at {v} m/s: {} vs {} ({:e} of the row)",
                            STATES[i],
                            m1[(i, j)],
                            m2[(i, j)],
                            d / scale
                        );
                    }
                }
            }
        }
    }

    /// The body's accelerations that the blades' flapping is solved under, held in each
    /// evaluation and eliminated with the inflow as fast states of their own, give the
    /// derivatives that the model's own evaluations (iterated until the accelerations agree)
    /// give: every derivative and every component's share within `ELIMINATED_AGREEMENT` of its
    /// row's largest. The test gyroplane's weightless teetering pair (the angular acceleration
    /// felt) at two airspeeds, and the same with heavy blades (the apparent gravity felt too)
    /// on its teetering hub and on an articulated one.
    #[test]
    fn the_hubs_accelerations_eliminated_give_the_models_own_derivatives() {
        // Both are central differences with the same steps; they differ in truncation error
        // (the elimination takes the accelerations' own differences) and in the iterated
        // evaluations' agreement (1e-7 rad/s^2 over twice a rate's step: 5e-6 in L_p's units),
        // measured at 8.6e-5 of the row at most (Z_q, heavy articulated blades), where halving
        // the steps may move a derivative by 5e-3 (`two_step_sizes_agree`). Leaving the
        // accelerations held, not eliminated, misses by 13 % (X_p, 20 m/s).
        const ELIMINATED_AGREEMENT: f64 = 2e-4;
        // Rows that are round-off (a component with no share in a rate): 1e-9 absolute.
        const ROUND_OFF: f64 = 1e-9;
        let heavy = |articulated: bool| {
            let mut a = crate::testdata::gyroplane();
            let r = &mut a.main_rotor.rotor;
            if articulated {
                r.hub = crate::components::rotor::Hub::Articulated;
                r.blades = 3;
                r.flap_inertia_kg_m2 *= 1.5;
                r.precone_rad = 0.0;
            }
            r.flap_mass_moment_kg_m = 1.5 * r.flap_inertia_kg_m2 / r.radius_m;
            a
        };
        let cases = [
            ("weightless, 20 m/s", crate::testdata::gyroplane(), 20.0),
            ("weightless, 31.3 m/s", crate::testdata::gyroplane(), 31.3),
            ("heavy teetering, 31.3 m/s", heavy(false), 31.3),
            ("heavy articulated, 31.3 m/s", heavy(true), 31.3),
        ];
        for (label, a, v) in cases {
            let c = crate::aircraft::trim::Condition {
                airspeed_m_s: v,
                ..crate::testdata::level_70mph()
            };
            let t = crate::aircraft::trim::trim(&a, c, Default::default()).unwrap();
            let eliminated = linearise_by(&a, &t, air(), Steps::default(), Hub::FastStates);
            let agreed = linearise_by(&a, &t, air(), Steps::default(), Hub::Agreed);
            let (e, g) = (eliminated.unwrap(), agreed.unwrap());
            let models = std::iter::once((&e.model, &g.model)).chain(
                e.components
                    .iter()
                    .zip(&g.components)
                    .map(|(x, y)| (&x.1, &y.1)),
            );
            for (m1, m2) in models {
                for (x1, x2) in [(m1.a(), m2.a()), (m1.b(), m2.b())] {
                    for i in 0..10 {
                        let scale = (0..x2.ncols())
                            .map(|j| x2[(i, j)].abs())
                            .fold(0.0, f64::max);
                        for j in 0..x2.ncols() {
                            let d = (x1[(i, j)] - x2[(i, j)]).abs();
                            assert!(
                                d <= ELIMINATED_AGREEMENT * scale + ROUND_OFF,
                                "{label}: row {} column {j}: {} eliminated, {} agreed",
                                STATES[i],
                                x1[(i, j)],
                                x2[(i, j)],
                            );
                        }
                    }
                }
            }
        }
    }

    /// The component contributions add up, the inertial part of the aerodynamic damping
    /// derivatives is nil, and the derivatives have the signs of autorotative flight
    /// (seed 002: Q_u > 0, Q_w > 0, Q_u < Q_w; damping derivatives negative).
    #[test]
    fn breakdown_and_signs() {
        let (a, t) = trimmed_gyroplane(31.3);
        let l = linearise(&a, &t, air(), Steps::default()).unwrap();
        for d in ["X_u", "Z_w", "M_q", "L_p", "N_r", "Y_v"] {
            let total = l.model.derivative_value(d).unwrap();
            let parts = l.breakdown(d).unwrap();
            let sum: f64 = parts.iter().map(|(_, v)| v).sum();
            assert!((sum - total).abs() < 1e-12, "{d}: {sum} vs {total}");
            let inertial = parts.iter().find(|(c, _)| c == "inertial").unwrap().1;
            assert!(inertial.abs() < 1e-9, "{d}: inertial part {inertial}");
            assert!(total < 0.0, "{d} = {total}");
        }
        let v = |d: &str| l.model.derivative_value(d).unwrap();
        assert!(v("Q_u") > 0.0 && v("Q_w") > 0.0 && v("Q_u") < v("Q_w"));
        assert!(v("Q_Omega") < 0.0 && v("N_v") > 0.0);
        // The Euler kinematics: phi_dot = p, theta_dot = q cos(phi) (level flight).
        assert!((v("L_p") - l.model.a()[(3, 3)]).abs() < 1e-15);
        assert!((l.model.a()[(6, 3)] - 1.0).abs() < 1e-6);
        // The longitudinal subset keeps its states and eta_s.
        let lon = l.longitudinal().unwrap();
        assert_eq!(lon.states(), ["u", "w", "q", "theta", "Omega"]);
        assert_eq!(lon.controls(), ["eta_s"]);
    }
}
