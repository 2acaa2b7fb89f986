//! The full individual-blade model: its state (blades, inflow, body, speeds) and its
//! derivatives, the blades' and body's accelerations solved together.

use super::{
    Air, Aircraft, AircraftError, Controls, Drive, HubMotion, InflowDynamics, RotorFrame, State,
    cross, positive_state, sum_loads,
};
use crate::components::inflow;
use crate::components::rigid_body::{self, BodyState, Loads};
use crate::components::rotor::{Angles, Blade, BladeLoads, Hub, Inflow, Operating, Rotor};
use serde::Serialize;
use std::f64::consts::PI;

/// The full model's accelerations for a given hub motion: the flap (teeter) states' rates, the
/// loads on the body about the c.g. (gravity apart), and the body's state derivative.
struct Response {
    flap_dot: Vec<[f64; 2]>,
    total: Loads,
    body_dot: BodyState,
    /// The rotor's spin acceleration relative to the airframe's along the shaft,
    /// `Omega' - r_hub'`, rad/s^2.
    spin: f64,
}

/// The full individual-blade state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FullState {
    pub body: BodyState,
    /// Azimuth of blade 1, rad.
    pub rotor_azimuth_rad: f64,
    pub rotor_omega_rad_s: f64,
    /// Per flap degree of freedom: angle (rad) and rate (rad/s). Articulated: blade k at
    /// `psi + 2 pi k / N`; teetering: the teeter angle (blade 1 up).
    pub flap: Vec<[f64; 2]>,
    /// Main-rotor inflow, hub axes, m/s.
    pub inflow: Inflow,
    pub propeller_omega_rad_s: f64,
}

/// Time derivative of a [`FullState`] (same layout).
pub type FullDerivative = FullState;

impl Aircraft {
    /// The number of flap degrees of freedom of the main rotor: one per blade for an
    /// articulated hub, one teeter angle for a teetering hub, none for a rigid one.
    pub fn flap_dofs(&self) -> usize {
        match self.main_rotor.rotor.hub {
            Hub::Articulated => self.main_rotor.rotor.blades,
            Hub::Teetering => 1,
            Hub::Rigid => 0,
        }
    }

    /// The full individual-blade state at a trim point, with blade 1 at azimuth zero: the
    /// trim's periodic flapping, its inflow (held by Eq. 3 at its equilibrium), rotor and
    /// propeller speeds. For an articulated hub the other blades' states are found by
    /// integrating blade 1's periodic motion to their azimuths.
    pub fn full_state(
        &self,
        state: &State,
        controls: &Controls,
        air: Air,
        flap_start: [f64; 2],
    ) -> FullState {
        let mr = &self.main_rotor;
        let omega = state.rotor_omega_rad_s;
        let frame = self.rotor_frame(&state.body, controls);
        let steady = self.hub_motion(
            &frame,
            &state.body,
            &Self::steady_accelerations(&state.body),
        );
        let op = self.operating(&frame, omega, state.inflow, air, &steady);
        let blade = Blade::new(&mr.rotor, mr.numerics);
        let n = self.flap_dofs();
        let mut flap = Vec::with_capacity(n);
        if n > 0 {
            flap.push([flap_start[0], flap_start[1] * omega]);
        }
        if mr.rotor.hub == Hub::Articulated {
            // Blade k trails blade 1 by 2 pi k / N: it is where blade 1 was at -2 pi k / N,
            // i.e. where blade 1 will be at 2 pi (N - k) / N on its periodic path.
            let nb = mr.rotor.blades;
            let steps = 720;
            let h = 2.0 * PI / steps as f64;
            let mut s = flap_start;
            let mut at = vec![[0.0; 2]; nb];
            at[0] = s;
            for k in 0..steps {
                let next = {
                    let f = |psi: f64, x: [f64; 2]| blade.flap_derivative(&op, psi, x);
                    let psi = k as f64 * h;
                    let k1 = f(psi, s);
                    let k2 = f(
                        psi + h / 2.0,
                        [s[0] + h / 2.0 * k1[0], s[1] + h / 2.0 * k1[1]],
                    );
                    let k3 = f(
                        psi + h / 2.0,
                        [s[0] + h / 2.0 * k2[0], s[1] + h / 2.0 * k2[1]],
                    );
                    let k4 = f(psi + h, [s[0] + h * k3[0], s[1] + h * k3[1]]);
                    [
                        s[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
                        s[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
                    ]
                };
                s = next;
                let done = k + 1;
                if (done * nb).is_multiple_of(steps) {
                    // Blade 1 has reached 2 pi j / N, where blade j is now.
                    let j = done * nb / steps;
                    if j < nb {
                        at[j] = s;
                    }
                }
            }
            for x in at.iter().skip(1) {
                flap.push([x[0], x[1] * omega]);
            }
        }
        FullState {
            body: state.body,
            rotor_azimuth_rad: 0.0,
            rotor_omega_rad_s: omega,
            flap,
            inflow: state.inflow,
            propeller_omega_rad_s: self.propeller_omega(state, controls),
        }
    }

    /// The inflow in equilibrium with the rotor's instantaneous loads (quasi-steady inflow):
    /// damped fixed-point iteration from the state's inflow, to 1e-9 of the tip speed.
    fn quasi_steady_inflow(
        &self,
        frame: &RotorFrame,
        op: &Operating,
        air: Air,
        driving_at: &dyn Fn(&Operating) -> inflow::DrivingLoads,
    ) -> Result<Inflow, AircraftError> {
        let tip = op.omega_rad_s * self.main_rotor.rotor.radius_m;
        let mut o = *op;
        for _ in 0..200 {
            let (eq, _, _) = self.inflow_response(frame, driving_at(&o), o.inflow, air);
            let next = Inflow {
                v0: 0.5 * (o.inflow.v0 + eq.v0),
                v1s: 0.5 * (o.inflow.v1s + eq.v1s),
                v1c: 0.5 * (o.inflow.v1c + eq.v1c),
            };
            let change = (next.v0 - o.inflow.v0)
                .abs()
                .max((next.v1s - o.inflow.v1s).abs())
                .max((next.v1c - o.inflow.v1c).abs());
            o.inflow = next;
            if change <= 1e-9 * tip {
                return Ok(o.inflow);
            }
        }
        Err(AircraftError::Invalid {
            name: "quasi-steady inflow (no fixed point in 200 damped iterations), v0 m/s",
            requirement: "convergent",
            value: o.inflow.v0,
        })
    }

    /// The full model's right-hand side: individual blades at their azimuths with their own
    /// flap (or teeter) equations, dynamic inflow (seed 001 Eq. 3), the rotorspeed, propeller
    /// speed and rigid-body equations (seed 001 Eq. 1).
    ///
    /// The airframe's mass and inertia include the rotor as a frozen disc; the blades'
    /// motion relative to the hub enters the hub moment as `-(dH_rel/dt + omega_hub x H_rel)`
    /// (time derivative exact along the state's own rates, by the chain rule:
    /// [`Blade::angular_momentum_and_rate`]) and, through
    /// the blades' first mass moment, the hub force. The flap equations include the hub's
    /// rotation, and through the blades' first mass moment their weight and the hub's
    /// acceleration (the body's, solved with the blades': `Aircraft::coupled`; about a teeter
    /// hinge these cancel unless the blades are coned), and the blades' own inertia under the
    /// hub's angular acceleration (`I w'.t`, [`crate::components::rotor`]); the hub moment
    /// takes the hub's angular acceleration on the blades' inertia beyond the frozen disc
    /// (a two-bladed rotor's turns with it). The rotorspeed's rate balances the torques about
    /// the shaft over the flapped blades' polar inertia. Lag is not modelled.
    pub fn derivatives(
        &self,
        x: &FullState,
        controls: &Controls,
        air: Air,
    ) -> Result<FullDerivative, AircraftError> {
        let mr = &self.main_rotor;
        let blade = Blade::new(&mr.rotor, mr.numerics);
        self.derivatives_with(&blade, x, controls, air, [0.0; 3])
    }

    /// [`Aircraft::derivatives`] in moving air: `wind_body_m_s` is the air's velocity over the
    /// ground in body axes (a gust; `+x` a tailwind, `+z` a downdraught). Every aerodynamic
    /// load (rotor, propeller, airframe and tail) sees the body's velocity less the wind's; the
    /// rigid-body equations keep the body's own. The wind is uniform over the aircraft: the
    /// gust's gradients (its rotational components) are not modelled.
    pub fn derivatives_in_wind(
        &self,
        x: &FullState,
        controls: &Controls,
        air: Air,
        wind_body_m_s: [f64; 3],
    ) -> Result<FullDerivative, AircraftError> {
        let mr = &self.main_rotor;
        let blade = Blade::new(&mr.rotor, mr.numerics);
        self.derivatives_with(&blade, x, controls, air, wind_body_m_s)
    }

    /// [`Aircraft::derivatives`] with the main rotor's blade elements prepared once
    /// (`Blade::new(&self.main_rotor.rotor, self.main_rotor.numerics)`), as a simulation does.
    pub(crate) fn derivatives_with(
        &self,
        blade: &Blade,
        x: &FullState,
        controls: &Controls,
        air: Air,
        wind_body_m_s: [f64; 3],
    ) -> Result<FullDerivative, AircraftError> {
        self.derivatives_given(blade, x, controls, air, wind_body_m_s, None)
    }

    /// [`Aircraft::derivatives_with`], the flap equations seeing the hub's motion that follows
    /// from the body's own accelerations (`given` none: the coupled solution of
    /// [`Aircraft::coupled`]) or from given ones: `[g - a_cg, w']`, the apparent gravity at the
    /// c.g. (m/s^2) and the body's angular acceleration (rad/s^2), body axes. Given the steady
    /// motion's (`g - w x V` and zero), the body is held as a trim holds it: the flap equations
    /// see what the rotor's periodic solution sees, and the body's accelerations returned are
    /// what it would do if let go.
    pub(crate) fn derivatives_given(
        &self,
        blade: &Blade,
        x: &FullState,
        controls: &Controls,
        air: Air,
        wind_body_m_s: [f64; 3],
        given: Option<[f64; 6]>,
    ) -> Result<FullDerivative, AircraftError> {
        let mr = &self.main_rotor;
        let rotor = &mr.rotor;
        let omega = x.rotor_omega_rad_s;
        positive_state("rotor_omega_rad_s", omega)?;
        if x.flap.len() != self.flap_dofs() {
            return Err(AircraftError::Invalid {
                name: "flap states",
                requirement: "one per flap degree of freedom of the hub",
                value: x.flap.len() as f64,
            });
        }
        // The air's velocity relative to the body: what every aerodynamic load sees.
        let air_body = BodyState {
            u_m_s: x.body.u_m_s - wind_body_m_s[0],
            v_m_s: x.body.v_m_s - wind_body_m_s[1],
            w_m_s: x.body.w_m_s - wind_body_m_s[2],
            ..x.body
        };
        let frame = self.rotor_frame(&air_body, controls);
        // The blades' loads do not depend on the hub's acceleration; the flap equations below
        // take it from the body's (`respond`), not from `op`.
        let still = HubMotion {
            apparent_gravity: [0.0; 3],
            angular_acceleration: [0.0; 3],
        };
        let op = self.operating(&frame, omega, x.inflow, air, &still);
        // Each blade's place, with its angles' sines and cosines, once.
        let placed = blade_positions(rotor, blade, &op, x);
        let driving_at = |op: &Operating| driving_loads(blade, &placed, op);
        let mut op = op;
        if mr.inflow_dynamics == InflowDynamics::QuasiSteady {
            op.inflow = self.quasi_steady_inflow(&frame, &op, air, &driving_at)?;
        }
        let op = op;
        // Each blade's aerodynamic loads, once; the flap (teeter) accelerations from them.
        let blades = Blades::new(rotor, blade, op, placed);
        let (force, moment, torque) = blades.sums();
        let i_r = self.rotor_polar_inertia_kg_m2();
        let driving = inflow::DrivingLoads {
            thrust_n: -force[2],
            roll_n_m: moment[0],
            pitch_n_m: moment[1],
        };
        let inflow_dot = match mr.inflow_dynamics {
            InflowDynamics::Dynamic => self.inflow_response(&frame, driving, x.inflow, air).2,
            InflowDynamics::QuasiSteady => Inflow::default(),
        };
        let prop_omega = match self.propeller.drive {
            Drive::Governed { rpm } => rpm.at(controls.throttle_percent) * PI / 30.0,
            Drive::Engine { .. } => x.propeller_omega_rad_s,
        };
        let (_, prop_loads, prop_omega_dot, af) =
            self.propeller_and_airframe(&air_body, prop_omega, controls, air)?;
        let free = self.free_spins_at(&frame.c);
        // The flap (teeter) accelerations and the body's, with the hub's motion as the flap
        // equations see it (none: a rigid hub's blades do not flap).
        let respond = |hub: Option<&HubMotion>| -> Result<Response, AircraftError> {
            let flap_dot = blades.flap_rates(&x.flap, hub);
            // Inertial reaction of the blades' relative motion: H_rel along the state's rates.
            let beta_ddot = |k: usize| match rotor.hub {
                Hub::Articulated => flap_dot[k][1],
                Hub::Teetering if k == 0 => flap_dot[0][1],
                Hub::Teetering => -flap_dot[0][1],
                Hub::Rigid => 0.0,
            };
            let (m_hub, f_hub, spin) = blades.reaction(
                frame.hub_rates,
                beta_ddot,
                hub,
                (force, moment, torque),
                i_r,
            );
            let rotor_loads =
                Self::rotor_to_body(&frame, self.hub_force(f_hub, &frame, air), m_hub);
            let total = sum_loads(&[rotor_loads, prop_loads, af]);
            let body_dot =
                rigid_body::derivatives_with_free_spins(&self.mass, &x.body, &total, &free)?;
            Ok(Response {
                flap_dot,
                total,
                body_dot,
                spin,
            })
        };
        let feel = self.blades_feel_the_hub();
        let Response {
            flap_dot,
            body_dot,
            spin,
            ..
        } = if feel {
            self.coupled(&frame, &x.body, &respond, given)?
        } else {
            respond(None)?
        };
        let (omega_dot, prop_omega_dot) = self.spin_rates(&frame, spin, prop_omega_dot, &body_dot);
        Ok(FullDerivative {
            body: body_dot,
            rotor_azimuth_rad: omega,
            rotor_omega_rad_s: omega_dot,
            flap: flap_dot,
            inflow: inflow_dot,
            propeller_omega_rad_s: prop_omega_dot,
        })
    }

    /// The full model's accelerations with the blades' weight and the hub's acceleration in
    /// their flap equations, `respond` giving them for a given hub motion.
    ///
    /// The blades' and the body's accelerations are coupled. A flap equation sees the apparent
    /// gravity at the hub, `g - a_hub` with `a_hub = a_cg + w' x arm + w x (w x arm)`, and the
    /// hub's angular acceleration `w'` (the hinge's share, [`crate::components::rotor`]); the
    /// body's accelerations depend in turn on the blades' flap accelerations, through the
    /// motion of their mass centres (the hub force) and their angular momentum (the hub
    /// moment). By the rigid body's translational equation (`V' + w x V = F/m + g`) the apparent
    /// gravity at the c.g., `g - a_cg`, is `-F/m`, `F` every load but gravity. Every term is
    /// affine in the accelerations, so the coupled equations are solved exactly at each
    /// evaluation and the right-hand side stays a function of the state alone: with
    /// `y = (-F/m, w')` in body axes, `respond` (the blades' aerodynamic loads, the propeller
    /// and the airframe computed once, outside it) maps an assumed `y` to the `y` it implies,
    /// `b + A y`; seven calls give `b` and `A` (exactly: the map is affine; four for blades
    /// without a first mass moment, which do not feel the apparent gravity), and `(1 - A) y =
    /// b` is solved by LU. This is the mass matrix's coupling solved as a linear
    /// system, as an individual-blade simulation that carries the blades' inertia does; taking
    /// the accelerations from the previous evaluation instead would make the derivative depend
    /// on the integrator's history. The coupling is small but not neglected: along the shaft,
    /// each blade's flap acceleration answers an acceleration `a` with `S a / I` and pushes back
    /// on the body with `S^2 a / (I m)`, so `A`'s largest eigenvalue is about
    /// `(3/4) N_b m_blade / m` for uniform blades (`S^2 / I = 3 m_blade / 4`). Measured for the
    /// test gyroplane with uniform blades: 0.077 with three articulated blades of 14.7 kg on
    /// 450 kg (0.074 by the formula), 0.012 with its two teetering blades of 9.8 kg, which feel
    /// the hub's acceleration only through their precone. In roll and pitch the blades' flap
    /// inertia couples more, whether or not they have a first moment: a flapping hinge carries no
    /// moment, so the body's angular acceleration answers without the rotor's in-plane inertia
    /// (about 0.23 of the VPM M16's roll inertia).
    ///
    /// With `given` accelerations (`y`), the flap equations see the hub's motion they imply
    /// instead ([`Aircraft::derivatives_given`]).
    fn coupled(
        &self,
        frame: &RotorFrame,
        body: &BodyState,
        respond: &dyn Fn(Option<&HubMotion>) -> Result<Response, AircraftError>,
        given: Option<[f64; 6]>,
    ) -> Result<Response, AircraftError> {
        let hub = |y: &[f64; 6]| self.hub_motion(frame, body, y);
        if let Some(y) = given {
            return respond(Some(&hub(&y)));
        }
        let image = |r: &Response| self.accelerations(&r.total, &r.body_dot);
        let base = image(&respond(Some(&hub(&[0.0; 6])))?);
        let mut system = nalgebra::Matrix6::<f64>::identity();
        // The columns of what the blades do not feel are zero, and are not evaluated.
        for j in self.first_felt_acceleration()..6 {
            let mut unit = [0.0; 6];
            unit[j] = 1.0;
            let column = image(&respond(Some(&hub(&unit)))?);
            for i in 0..6 {
                system[(i, j)] -= column[i] - base[i];
            }
        }
        let y =
            system
                .lu()
                .solve(&nalgebra::Vector6::from(base))
                .ok_or(AircraftError::Invalid {
                    name: "the blades' and the body's coupled accelerations (a singular system)",
                    requirement: "solvable",
                    value: f64::NAN,
                })?;
        respond(Some(&hub(&std::array::from_fn(|k| y[k]))))
    }
}

/// One blade at an instant of the full model: its flap angle and rate, its angles' sines and
/// cosines, and its aerodynamic loads (once [`Blades::new`] has them). One vector of these
/// per evaluation, where there were three (every right-hand side allocates them).
#[derive(Debug, Clone, Copy)]
struct Placed {
    beta: f64,
    beta_dot: f64,
    angles: Angles,
    loads: BladeLoads,
}

/// The blades' azimuths, flap angles and flap rates in the full state `x` (an articulated
/// rotor's from its flap states, a teetering rotor's two from its teeter, half a revolution
/// apart, a rigid rotor's at the precone), with their angles; no loads yet.
fn blade_positions(rotor: &Rotor, blade: &Blade, op: &Operating, x: &FullState) -> Vec<Placed> {
    let omega = x.rotor_omega_rad_s;
    let psi1 = x.rotor_azimuth_rad;
    let place = |psi: f64, beta: f64, beta_dot: f64| Placed {
        beta,
        beta_dot,
        angles: Angles::new(psi, beta),
        loads: BladeLoads::default(),
    };
    let mut blades = Vec::new();
    match rotor.hub {
        Hub::Articulated => {
            let nb = rotor.blades;
            for (k, f) in x.flap.iter().enumerate() {
                blades.push(place(psi1 + 2.0 * PI * k as f64 / nb as f64, f[0], f[1]));
            }
        }
        Hub::Teetering => {
            let f = x.flap[0];
            let [(b1, d1), (b2, d2)] = blade.blade_flap(op, [f[0], f[1] / omega]);
            blades.push(place(psi1, b1, d1));
            blades.push(place(psi1 + PI, b2, d2));
        }
        Hub::Rigid => {
            for k in 0..rotor.blades {
                let psi = psi1 + 2.0 * PI * k as f64 / rotor.blades as f64;
                blades.push(place(psi, rotor.precone_rad, 0.0));
            }
        }
    }
    blades
}

/// The thrust and the aerodynamic roll and pitch moments of the blades `placed` at `op`: what
/// drives the inflow.
fn driving_loads(blade: &Blade, placed: &[Placed], op: &Operating) -> inflow::DrivingLoads {
    let mut d = inflow::DrivingLoads {
        thrust_n: 0.0,
        roll_n_m: 0.0,
        pitch_n_m: 0.0,
    };
    for p in placed {
        let l = blade.loads_at(op, p.angles, p.beta_dot);
        d.thrust_n -= l.force_n[2];
        d.roll_n_m += l.moment_n_m[0];
        d.pitch_n_m += l.moment_n_m[1];
    }
    d
}

/// The main rotor's blades at one instant of the full model: each blade's flap angle and flap
/// rate, its angles' sines and cosines, and its aerodynamic loads at `op`.
struct Blades<'a> {
    rotor: &'a Rotor,
    blade: &'a Blade<'a>,
    op: Operating,
    placed: Vec<Placed>,
}

impl<'a> Blades<'a> {
    /// The blades `placed` with their aerodynamic loads at `op`.
    fn new(rotor: &'a Rotor, blade: &'a Blade<'a>, op: Operating, mut placed: Vec<Placed>) -> Self {
        for p in &mut placed {
            p.loads = blade.loads_at(&op, p.angles, p.beta_dot);
        }
        Self {
            rotor,
            blade,
            op,
            placed,
        }
    }

    /// The blades' aerodynamic force and moment on the hub (hub axes) and their aerodynamic
    /// torque.
    fn sums(&self) -> ([f64; 3], [f64; 3], f64) {
        let mut force = [0.0; 3];
        let mut moment = [0.0; 3];
        let mut torque = 0.0;
        for Placed { loads: l, .. } in &self.placed {
            for k in 0..3 {
                force[k] += l.force_n[k];
                moment[k] += l.moment_n_m[k];
            }
            torque += l.torque_n_m;
        }
        (force, moment, torque)
    }

    /// The flap (teeter) states' rates for the flap states `flap`, the flap equations seeing
    /// the hub's motion `hub` (none: blades that do not feel it).
    fn flap_rates(&self, flap: &[[f64; 2]], hub: Option<&HubMotion>) -> Vec<[f64; 2]> {
        let (rotor, blade, op) = (self.rotor, self.blade, &self.op);
        let placed = &self.placed;
        let (i_b, k_b) = (rotor.flap_inertia_kg_m2, rotor.flap_spring_n_m_per_rad);
        let mut flap_dot = Vec::with_capacity(flap.len());
        match rotor.hub {
            Hub::Articulated => {
                for p in placed {
                    let (beta, beta_dot, ang) = (p.beta, p.beta_dot, p.angles);
                    let mut m = p.loads.flap_moment_n_m
                        - blade.inertial_flap_moment_at(op, ang)
                        - k_b * (beta - rotor.precone_rad);
                    if let Some(h) = hub {
                        m += blade.apparent_gravity_flap_moment_at(
                            h.apparent_gravity,
                            h.angular_acceleration,
                            ang,
                        );
                    }
                    flap_dot.push([beta_dot, m / i_b]);
                }
            }
            Hub::Teetering => {
                let f = flap[0];
                let (a0, a1) = (placed[0].angles, placed[1].angles);
                let mut m = placed[0].loads.flap_moment_n_m
                    - placed[1].loads.flap_moment_n_m
                    - (blade.inertial_flap_moment_at(op, a0)
                        - blade.inertial_flap_moment_at(op, a1))
                    - k_b * f[0];
                if let Some(h) = hub {
                    let (g, w) = (h.apparent_gravity, h.angular_acceleration);
                    m += blade.apparent_gravity_flap_moment_at(g, w, a0)
                        - blade.apparent_gravity_flap_moment_at(g, w, a1);
                }
                flap_dot.push([f[1], m / (2.0 * i_b)]);
            }
            Hub::Rigid => {}
        }
        flap_dot
    }

    /// The blades' moment and force on the hub (hub axes) and the rotor's spin acceleration
    /// relative to the airframe's along the shaft, `Omega' - r_hub'`, for the flap accelerations
    /// `beta_ddot` and the hub's motion `hub` as the flap equations see it (none: blades
    /// that do not feel it), from the blades' aerodynamic `(force, moment, torque)`; `i_r` the frozen disc's
    /// polar inertia.
    ///
    /// A free rotor: no torque through the shaft's bearing, so the blades' angular momentum
    /// about the shaft changes by the aerodynamic torque alone. With the hub's rates `w`:
    /// `I_R r_hub' + dh_z + (w x h)_z + ((J - disc) w')_z = -Q` (the frozen disc's `I_R
    /// r_hub'`; `dh` the rate along the blades' motion, `-I_Rb Omega'` of it from the
    /// rotorspeed's change, `I_Rb` the flapped blades' polar inertia, the rest the flapping's
    /// Coriolis and the hub's rates seen by the turning blades). The inertia's `zz` element
    /// beyond the disc is `I_Rb - I_R`, so `Omega' - r_hub' = (Q + dh_z(Omega' = 0) + (w x h)_z +
    /// ((J - disc) w')_z - (I_Rb - I_R) r_hub') / I_Rb`, the absolute spin changed by the
    /// torques alone; the hub's `r_hub'` is known where the flap equations see the hub's motion,
    /// and otherwise left out of the blades' angular momentum rate, as the hub's rates are.
    fn reaction(
        &self,
        hub_rates: [f64; 3],
        beta_ddot: impl Fn(usize) -> f64,
        hub: Option<&HubMotion>,
        (force, moment, torque): ([f64; 3], [f64; 3], f64),
        i_r: f64,
    ) -> ([f64; 3], [f64; 3], f64) {
        // The hub's angular acceleration on the blades' inertia beyond the frozen disc.
        let turning = hub.map_or([0.0; 3], |h| self.beyond_disc_times(h.angular_acceleration));
        let (per_omega, tangential) = self.spin_share();
        let polar = -per_omega[2];
        let r_hub_dot = hub.map_or(0.0, |h| h.angular_acceleration[2]);
        let (h0, still, still_force) = self.inertia(hub_rates, beta_ddot, force);
        let gyro = cross(hub_rates, h0);
        let spin = (torque + still[2] + gyro[2] + turning[2] - (polar - i_r) * r_hub_dot) / polar;
        // The rotorspeed's change relative to the hub takes `Omega'` times the blades' angular
        // momentum per unit rotorspeed, and their centres of mass's tangential acceleration.
        let omega_dot = spin + r_hub_dot;
        let dh: [f64; 3] = std::array::from_fn(|k| still[k] + omega_dot * per_omega[k]);
        let f_hub: [f64; 3] = std::array::from_fn(|k| still_force[k] - omega_dot * tangential[k]);
        let m_hub = [
            moment[0] - dh[0] - gyro[0] - turning[0],
            moment[1] - dh[1] - gyro[1] - turning[1],
            0.0,
        ];
        (m_hub, f_hub, spin)
    }

    /// What a change of rotorspeed takes from the hub, per unit `Omega'` (hub axes): the
    /// blades' angular momentum per unit rotorspeed ([`Blade::spin_momentum_per_omega`]; along
    /// `-z` the flapped blades' polar inertia, kg m^2) and the mass times the distance from the
    /// shaft of their centres of mass along their tangents, `m (e + (S / m) cos b) t`, kg m (the
    /// exact `Omega'` terms of [`Self::inertia`]).
    fn spin_share(&self) -> ([f64; 3], [f64; 3]) {
        let (mut per_omega, mut tangential) = ([0.0; 3], [0.0; 3]);
        for p in &self.placed {
            let k = self.blade.spin_momentum_per_omega(p.angles);
            let t = self.blade.tangential_mass_moment(p.angles);
            for j in 0..3 {
                per_omega[j] += k[j];
                tangential[j] += t[j];
            }
        }
        (per_omega, tangential)
    }

    /// The blades' inertia beyond the frozen disc times the hub's angular acceleration `w_dot`
    /// (hub axes; [`Blade::inertia_beyond_disc_times`]).
    fn beyond_disc_times(&self, w_dot: [f64; 3]) -> [f64; 3] {
        let mut sum = [0.0; 3];
        for p in &self.placed {
            let j = self.blade.inertia_beyond_disc_times(p.angles, w_dot);
            for k in 0..3 {
                sum[k] += j[k];
            }
        }
        sum
    }

    /// The blades' angular momentum beyond the frozen disc and its rate, and the force on the
    /// hub (`force`, hub axes) less the motion of their centres of mass (relative acceleration
    /// and Coriolis, the hub turning at `hub_rates`), along the blades' motion (blade `k`'s flap
    /// acceleration `beta_ddot(k)`; exact rates: the chain rule) with the rotorspeed held: a
    /// change of rotorspeed adds its share linearly ([`Self::spin_share`], in
    /// [`Self::reaction`]).
    fn inertia(
        &self,
        hub_rates: [f64; 3],
        beta_ddot: impl Fn(usize) -> f64,
        force: [f64; 3],
    ) -> ([f64; 3], [f64; 3], [f64; 3]) {
        let (blade, op) = (self.blade, &self.op);
        let mut h0 = [0.0; 3];
        let mut dh = [0.0; 3];
        let mut f_hub = force;
        let cg_mass = self.rotor.blade_mass_kg();
        for (k, p) in self.placed.iter().enumerate() {
            let (ang, beta_dot) = (p.angles, p.beta_dot);
            let (hb, hb_dot) =
                blade.angular_momentum_and_rate(op, ang, beta_dot, beta_ddot(k), 0.0);
            for j in 0..3 {
                h0[j] += hb[j];
                dh[j] += hb_dot[j];
            }
            // The blade's centre of mass: relative acceleration and Coriolis.
            if cg_mass > 0.0 {
                let [_, v, a] = blade.centre_of_mass_motion(op, ang, beta_dot, beta_ddot(k), 0.0);
                let cor = cross(hub_rates, v);
                for j in 0..3 {
                    f_hub[j] -= cg_mass * (a[j] + 2.0 * cor[j]);
                }
            }
        }
        (h0, dh, f_hub)
    }
}
