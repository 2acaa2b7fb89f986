//! The revolution-averaged model: its state, its evaluation with the rotor in its steady
//! periodic motion, and what it reports.

use super::{Air, Aircraft, AircraftError, Controls, MainRotor, cross, positive_state, sum_loads};
use crate::components::inflow;
use crate::components::propeller::PropellerState;
use crate::components::rigid_body::{self, BodyState, Loads};
use crate::components::rotor::{Blade, HubVelocity, Inflow, Operating, RevolutionMap, SteadyLoads};
use serde::Serialize;

/// The state of the revolution-averaged model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct State {
    pub body: BodyState,
    pub rotor_omega_rad_s: f64,
    /// Main-rotor inflow, hub axes, m/s.
    pub inflow: Inflow,
    /// Propeller speed (ignored when the drive is governed), rad/s.
    pub propeller_omega_rad_s: f64,
}

/// What the main rotor is doing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RotorReport {
    pub shaft_pitch_rad: f64,
    pub shaft_roll_rad: f64,
    /// The hub's air velocity in hub axes, m/s (after any hub angle-of-attack correction).
    pub hub_velocity: HubVelocity,
    /// Angle of attack of the disc (shaft normal plane) to the hub's air velocity, positive
    /// with the air meeting the disc from below, rad.
    pub disc_alpha_rad: f64,
    pub tip_speed_ratio: f64,
    pub thrust_n: f64,
    pub driving_torque_n_m: f64,
    pub a0_rad: f64,
    pub a1_rad: f64,
    pub b1_rad: f64,
    pub skew_rad: f64,
}

/// Loads of each component about the c.g., body axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ComponentLoads {
    pub rotor: Loads,
    pub propeller: Loads,
    pub airframe: Loads,
}

/// One evaluation of the revolution-averaged model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Averaged {
    /// Time derivative of the body state.
    pub body_dot: BodyState,
    pub rotor_omega_dot_rad_s2: f64,
    pub propeller_omega_dot_rad_s2: f64,
    /// The main-rotor inflow in equilibrium with the present loads, hub axes, m/s.
    pub inflow_equilibrium: Inflow,
    /// `d/dt` of the inflow (seed 001 Eq. 3), hub axes, m/s^2.
    pub inflow_dot: Inflow,
    pub rotor: RotorReport,
    pub propeller: PropellerState,
    pub propeller_omega_rad_s: f64,
    pub loads: ComponentLoads,
    /// The flap state at azimuth zero (a warm start for the next evaluation).
    pub flap_start: [f64; 2],
}

/// How closely the revolution-averaged model's body accelerations must agree with those its
/// rotor's flapping was solved under (the apparent gravity at the c.g. in g, the angular
/// acceleration in rad/s^2): the default trim's tolerance on them. A trim at this tolerance
/// or tighter ends where its evaluation under the steady motion's accelerations agrees, and is
/// the model's own; a looser one is confirmed by the model's own evaluation, which then
/// iterates.
const HUB_MOTION_TOLERANCE: f64 = 1e-7;

/// The unit [`HUB_MOTION_TOLERANCE`] measures component `k` of the body's accelerations
/// `[g - a_cg, w']` in: the apparent gravity in g, the angular acceleration in rad/s^2.
fn hub_motion_unit(k: usize) -> f64 {
    if k < 3 { rigid_body::G_M_S2 } else { 1.0 }
}

/// The body's accelerations `[g - a_cg, w']` a revolution-averaged evaluation solves the
/// rotor's flapping under ([`Aircraft::averaged_under`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum HubAccelerations {
    /// Those the evaluation's own loads imply, iterated to agreement: the model's equations.
    Agreed,
    /// The steady motion's at the evaluated state (`w' = 0`, the c.g. turning with the body's
    /// rates). A trim's root is the same as under [`HubAccelerations::Agreed`]: where the state
    /// derivative is zero, the implied accelerations are the steady motion's.
    Steady,
    /// These, whatever the loads imply: a linearisation's columns, which eliminate the
    /// difference to first order as they do the inflow's.
    Held([f64; 6]),
}

/// How many periodic solutions the revolution-averaged model may take to find them.
const HUB_MOTION_ITERATIONS: usize = 20;

/// How many differences of earlier iterates [`Anderson`] mixes (a window of six iterates).
/// Measured on the model tests' heavy gyroplanes (`cargo test -p cierva-model heavy`, 274
/// evaluations): 4.18 periodic solutions an evaluation, at most 5, against 4.57 and at most 7
/// for the plain iteration. With the blades' flap inertia under the hub's angular acceleration
/// (reports/investigations.md, issue 52 item 12; measured before it landed) the plain iteration
/// ran out of its 20 solutions on the heavy test teetering rotor, and on the VPM M16 (coupling
/// about 0.23) a trim took 0.119 s with this one against 0.257 s, a linearisation 0.163 s
/// against 0.300 s.
const ANDERSON_DEPTH: usize = 5;

/// Anderson's acceleration of the fixed-point iteration `y = G(y)` for the body's accelerations
/// the rotor's flapping was solved under (Anderson 1965, J. ACM 12(4); Walker and Ni 2011, SIAM
/// J. Numer. Anal. 49(4), Alg. AA): each next iterate mixes the last few `G(y)` with the weights
/// that make the mixed residual `G(y) - y` least. The map is nearly affine in `y` (the hub's
/// motion enters the flap equations linearly), where the plain iteration converges only as fast
/// as the coupling (the rotor's answer to the body's accelerations over the body's inertia)
/// dies away. The residuals are weighed as the tolerance weighs them (the apparent gravity in
/// g, the angular accelerations in rad/s^2).
#[derive(Debug, Default)]
struct Anderson {
    /// The latest iterates' `G(y)` and scaled residuals, oldest first.
    history: Vec<([f64; 6], [f64; 6])>,
}

impl Anderson {
    /// The next iterate after `y`, whose image is `image`.
    fn next(&mut self, y: [f64; 6], image: [f64; 6]) -> [f64; 6] {
        let residual: [f64; 6] = std::array::from_fn(|k| (image[k] - y[k]) / hub_motion_unit(k));
        self.history.push((image, residual));
        if self.history.len() > ANDERSON_DEPTH + 1 {
            self.history.remove(0);
        }
        let m = self.history.len() - 1;
        if m == 0 {
            return image;
        }
        // Differences of consecutive residuals and images; the weights `gamma` least-square
        // `f_k - dF gamma`.
        let d_f = nalgebra::DMatrix::from_fn(6, m, |r, c| {
            self.history[c + 1].1[r] - self.history[c].1[r]
        });
        let d_g = nalgebra::DMatrix::from_fn(6, m, |r, c| {
            self.history[c + 1].0[r] - self.history[c].0[r]
        });
        // A residual that is not finite is not mixed (an SVD of it would not end).
        if !d_f.iter().all(|x| x.is_finite()) || !residual.iter().all(|x| x.is_finite()) {
            self.history.clear();
            return image;
        }
        let f = nalgebra::DVector::from_column_slice(&residual);
        let svd = d_f.svd(true, true);
        // Directions among the differences below a ten-billionth of the largest are the
        // periodic solutions' own noise near convergence: left out.
        let cut = 1e-10 * svd.singular_values.max();
        let mixed: Option<[f64; 6]> = svd.solve(&f, cut).ok().and_then(|gamma| {
            let mixed = d_g * gamma;
            let next: [f64; 6] = std::array::from_fn(|k| image[k] - mixed[k]);
            next.iter().all(|x| x.is_finite()).then_some(next)
        });
        mixed.unwrap_or(image)
    }
}

/// Rotor periodic solutions already computed, by operating state, and what the last of them
/// learned about the rotor's revolution map (to find the next nearby one in fewer
/// revolutions).
#[derive(Debug, Clone, Default)]
pub struct RotorCache {
    entries: Vec<(Operating, SteadyLoads)>,
    map: RevolutionMap,
    /// A periodic solution known before the next lookup, with its operating state: used by that
    /// lookup if it is at that state, dropped otherwise ([`RotorCache::seed`]).
    seed: Option<(Operating, SteadyLoads)>,
    /// The latest evaluation's operating state and periodic solution (its `flap_start`'s).
    last: Option<(Operating, SteadyLoads)>,
}

impl RotorCache {
    /// Makes the next lookup find `solution` if it is at that lookup's operating state: the same
    /// rotor's periodic solution there, with the evaluation started from its `beta0`. Solved
    /// afresh from that start, its first revolution would close at once with the same sums, so
    /// the cache hands out the same loads, bit for bit, without the revolution. A next lookup
    /// elsewhere drops it, and later lookups go on as they would have.
    pub(crate) fn seed(&mut self, solution: Option<(Operating, SteadyLoads)>) {
        self.seed = solution;
    }

    /// The operating state and periodic solution of the latest evaluation's main rotor.
    pub(crate) fn last(&self) -> Option<(Operating, SteadyLoads)> {
        self.last
    }

    /// What the periodic solutions so far learned of the rotor's revolution map.
    pub(crate) fn map(&self) -> RevolutionMap {
        self.map
    }

    /// Starts the next periodic solution's secant steps from what a nearby one learned of the
    /// revolution map (a trim's, for the next trim or a linearisation about it): they find the
    /// same solution, in fewer revolutions.
    pub(crate) fn learned(&mut self, map: RevolutionMap) {
        self.map = map;
    }

    /// Holds `solution` for every lookup at its operating state, not only the next
    /// ([`RotorCache::seed`]; the same conditions): a linearisation's evaluations that leave
    /// the rotor where its trim left it (an attitude, the pedal) take the trim's solution.
    pub(crate) fn hold(&mut self, solution: Option<(Operating, SteadyLoads)>) {
        self.entries.extend(solution);
    }

    /// The rotor's periodic solution at `op`: the one held for it, or solved from
    /// the flap state `warm` and held. It becomes the latest ([`RotorCache::last`]).
    fn periodic(
        &mut self,
        op: &Operating,
        warm: [f64; 2],
        rotor: &MainRotor,
    ) -> Result<SteadyLoads, AircraftError> {
        if let Some(seed) = self.seed.take()
            && seed.0 == *op
        {
            self.entries.push(seed);
        }
        let rl = match self.entries.iter().find(|(o, _)| o == op) {
            Some((_, l)) => *l,
            None => {
                let l = Blade::new(&rotor.rotor, rotor.numerics).steady_with(
                    op,
                    warm,
                    &mut self.map,
                )?;
                self.entries.push((*op, l));
                l
            }
        };
        self.last = Some((*op, rl));
        Ok(rl)
    }

    /// How many periodic solutions it holds.
    #[cfg(test)]
    pub(crate) fn solutions(&self) -> usize {
        self.entries.len()
    }
}

impl Aircraft {
    /// The rotor's mean moment on the airframe at the hub (hub axes) and its spin acceleration
    /// relative to the airframe's along the shaft, `Omega' - r_hub'`, from its periodic solution
    /// `rl` at `op`: the mean aerodynamic moment with no shaft torque (a free rotor), the
    /// gyroscopic couple of the blades' motion relative to the hub (the airframe's inertia
    /// holds the rotor as a frozen disc), and the hub's angular acceleration on the blades'
    /// inertia beyond that disc. The shaft's bearing carries no torque about the shaft: that part
    /// changes the rotorspeed instead (the full model's balance, averaged); the rotorspeed's
    /// change relative to the hub (with the airframe's `r_hub'` where the flapping sees the
    /// hub's motion) takes its share of the blades' angular momentum from the hub.
    fn mean_hub_moment(&self, rl: &SteadyLoads, op: &Operating) -> ([f64; 3], f64) {
        let gyro = cross(op.hub_rates_rad_s, rl.angular_momentum_kg_m2_s);
        let j = rl.inertia_beyond_disc_kg_m2;
        let w_dot = op.hub_angular_acceleration_rad_s2;
        let turning: [f64; 3] =
            std::array::from_fn(|k| (0..3).map(|i| j[k][i] * w_dot[i]).sum::<f64>());
        let k = rl.spin_momentum_per_omega_kg_m2;
        let polar = -k[2];
        let beyond = polar - self.rotor_polar_inertia_kg_m2();
        let spin = (rl.driving_torque_n_m + gyro[2] + turning[2] - beyond * w_dot[2]) / polar;
        let relative = spin + w_dot[2];
        let m_hub = [
            rl.moment_n_m[0] - gyro[0] - turning[0] - relative * k[0],
            rl.moment_n_m[1] - gyro[1] - turning[1] - relative * k[1],
            0.0,
        ];
        (m_hub, spin)
    }

    /// The revolution-averaged equations at a state and control setting.
    ///
    /// `warm` is the main rotor's flap state at azimuth zero to start the periodic solution
    /// from (pass the previous evaluation's `flap_start`).
    pub fn averaged(
        &self,
        state: &State,
        controls: &Controls,
        air: Air,
        warm: [f64; 2],
    ) -> Result<Averaged, AircraftError> {
        self.averaged_cached(state, controls, air, warm, &mut RotorCache::default())
    }

    /// [`Aircraft::averaged`], reusing the rotor's periodic solution when the rotor's operating
    /// state is one the cache has seen (perturbations of attitude where the blades do not feel
    /// their weight leave it unchanged; of pedal, throttle and propeller speed too on a rigid
    /// hub, for elsewhere the body's angular acceleration they change reaches the flapping).
    pub fn averaged_cached(
        &self,
        state: &State,
        controls: &Controls,
        air: Air,
        warm: [f64; 2],
        cache: &mut RotorCache,
    ) -> Result<Averaged, AircraftError> {
        self.averaged_under(state, controls, air, warm, cache, HubAccelerations::Agreed)
            .map(|(a, _, _)| a)
    }

    /// [`Aircraft::averaged_cached`] with the body's accelerations the rotor's flapping is
    /// solved under as `hub` says; beside the evaluation, the accelerations its loads imply,
    /// `[g - a_cg, w']`, and whether the two agree in what the blades feel (within
    /// [`HUB_MOTION_TOLERANCE`]; always under [`HubAccelerations::Agreed`]). Where they agree
    /// under [`HubAccelerations::Steady`], the evaluation is the model's own, bit for bit: the
    /// model's iteration starts from the steady motion's accelerations and stops there at once.
    pub(crate) fn averaged_under(
        &self,
        state: &State,
        controls: &Controls,
        air: Air,
        warm: [f64; 2],
        cache: &mut RotorCache,
        hub: HubAccelerations,
    ) -> Result<(Averaged, [f64; 6], bool), AircraftError> {
        let b = &state.body;
        let mr = &self.main_rotor;
        let omega = state.rotor_omega_rad_s;
        positive_state("rotor_omega_rad_s", omega)?;
        let frame = self.rotor_frame(b, controls);
        let prop_omega = self.propeller_omega(state, controls);
        let (ps, prop_loads, prop_omega_dot, af) =
            self.propeller_and_airframe(b, prop_omega, controls, air)?;
        // The rotor's periodic solution with the hub's motion that the body's accelerations
        // imply, those accelerations depending on the rotor's loads in turn: from the steady
        // motion's (a trim's, exact there), until they agree (at once where the blades do not
        // feel the hub's motion), unless they are held.
        let feel = self.blades_feel_the_hub();
        let felt = self.first_felt_acceleration();
        let held = match hub {
            HubAccelerations::Agreed => None,
            HubAccelerations::Steady => Some(Self::steady_accelerations(b)),
            HubAccelerations::Held(y) => Some(y),
        };
        let mut y = held.unwrap_or_else(|| Self::steady_accelerations(b));
        let mut warm = warm;
        let mut change = f64::INFINITY;
        let mut anderson = Anderson::default();
        for _ in 0..HUB_MOTION_ITERATIONS {
            let hub_motion = self.hub_motion(&frame, b, &y);
            let op = self.operating(&frame, omega, state.inflow, air, &hub_motion);
            let rl = cache.periodic(&op, warm, mr)?;
            let (m_hub, spin) = self.mean_hub_moment(&rl, &op);
            let rotor_loads =
                Self::rotor_to_body(&frame, self.hub_force(rl.force_n, &frame, air), m_hub);
            let total = sum_loads(&[rotor_loads, prop_loads, af]);
            let body_dot = rigid_body::derivatives_with_free_spins(
                &self.mass,
                b,
                &total,
                &self.free_spins_at(&frame.c),
            )?;
            let next = self.accelerations(&total, &body_dot);
            // What the blades do not feel need not agree, and is not mixed: taken as it is
            // (the apparent gravity, for blades without a first mass moment), so that
            // evaluations differing only in attitude keep sharing the rotor's periodic
            // solution.
            if feel {
                change = (felt..6)
                    .map(|k| (next[k] - y[k]).abs() / hub_motion_unit(k))
                    .fold(0.0, f64::max);
            }
            let agrees = !feel || change <= HUB_MOTION_TOLERANCE;
            if !agrees && held.is_none() {
                y[..felt].copy_from_slice(&next[..felt]);
                (y, warm) = (anderson.next(y, next), rl.beta0);
                continue;
            }
            let driving = inflow::DrivingLoads::of(&rl);
            let (equilibrium, wake, inflow_dot) =
                self.inflow_response(&frame, driving, state.inflow, air);
            let (rotor_omega_dot, prop_omega_dot) =
                self.spin_rates(&frame, spin, prop_omega_dot, &body_dot);
            let hub = frame.hub;
            let v_inplane = hub.u.hypot(hub.v);
            let averaged = Averaged {
                body_dot,
                rotor_omega_dot_rad_s2: rotor_omega_dot,
                propeller_omega_dot_rad_s2: prop_omega_dot,
                inflow_equilibrium: equilibrium,
                inflow_dot,
                rotor: RotorReport {
                    shaft_pitch_rad: frame.theta_s,
                    shaft_roll_rad: frame.phi_s,
                    hub_velocity: hub,
                    disc_alpha_rad: hub.w.atan2(v_inplane),
                    tip_speed_ratio: v_inplane / (omega * mr.rotor.radius_m),
                    thrust_n: rl.thrust_n(),
                    driving_torque_n_m: rl.driving_torque_n_m,
                    a0_rad: rl.a0_rad,
                    a1_rad: rl.a1_rad,
                    b1_rad: rl.b1_rad,
                    skew_rad: wake.skew_rad,
                },
                propeller: ps,
                propeller_omega_rad_s: prop_omega,
                loads: ComponentLoads {
                    rotor: rotor_loads,
                    propeller: prop_loads,
                    airframe: af,
                },
                flap_start: rl.beta0,
            };
            return Ok((averaged, next, agrees));
        }
        Err(AircraftError::Invalid {
            name: "the body's accelerations and the rotor's flapping under them (no agreement in 20 periodic solutions; largest change, g or rad/s^2)",
            requirement: "convergent",
            value: change,
        })
    }
}
