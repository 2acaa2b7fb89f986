//! The rotor's steady periodic solution: one blade integrated round the azimuth to its periodic
//! flapping (secant steps on the revolution map), and the mean loads over the revolution.

use super::{Angles, Blade, BladeLoads, Hub, Operating, RotorError};
use serde::Serialize;
use std::f64::consts::PI;

/// Mean loads of the whole rotor in hub axes and the blade motion, over one revolution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SteadyLoads {
    /// Force on the rotor, hub axes, N.
    pub force_n: [f64; 3],
    /// Aerodynamic moment about the hub centre, hub axes, N m (roll, pitch, yaw).
    pub moment_n_m: [f64; 3],
    /// Aerodynamic torque driving the rotor in its direction of rotation, N m (zero in autorotation).
    pub driving_torque_n_m: f64,
    /// Flapping `beta = a0 - a1 cos psi - b1 sin psi`, rad (Glauert/NACA convention).
    pub a0_rad: f64,
    pub a1_rad: f64,
    pub b1_rad: f64,
    /// Flap state at `psi = 0` (periodic), rad and rad/s.
    pub beta0: [f64; 2],
    /// Mean angular momentum of the blades' motion relative to the hub (rotation and
    /// flapping) about the hub centre, hub axes, kg m^2/s (about `-I_polar Omega` along `z`).
    /// On a rotating hub the blades' inertial moment on it averages to `-omega_hub x H` (the
    /// gyroscopic couple); on a non-rotating hub it averages to zero.
    pub angular_momentum_kg_m2_s: [f64; 3],
    /// Mean inertia of the blades about the hub centre beyond the frozen disc the airframe's
    /// inertia holds, hub axes, kg m^2, by rows: the hub's angular acceleration `w'` takes
    /// `J w'` of moment from the hub on average ([`Blade::inertia_beyond_disc_times`]; zero for
    /// unflapped blades; left at zero for a rigid rotor, whose blades never see the hub's
    /// motion, so that `w'` is zero there).
    pub inertia_beyond_disc_kg_m2: [[f64; 3]; 3],
    /// Mean angular momentum of the blades per unit rotorspeed, hub axes, kg m^2
    /// ([`Blade::spin_momentum_per_omega`]): a change of rotorspeed `Omega'` takes `Omega'`
    /// times it from the hub on average (along the shaft, `-I_R` and the flapping's share; across
    /// it, the tilted disc's).
    pub spin_momentum_per_omega_kg_m2: [f64; 3],
}

impl SteadyLoads {
    /// Thrust, along the shaft upwards (`-z`), N.
    pub fn thrust_n(&self) -> f64 {
        -self.force_n[2]
    }
}

/// Sums over one revolution's step points: the blades' loads (both blades of a teetering
/// rotor, one blade otherwise), one blade's angular momentum beyond the frozen disc (both for a
/// teeter) and blade 1's flapping harmonics.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct RevolutionSums {
    loads: BladeLoads,
    momentum: [f64; 3],
    inertia: [[f64; 3]; 3],
    spin: [f64; 3],
    a0: f64,
    c1: f64,
    s1: f64,
}

/// A blade's angles, flap angle, flap rate and loads at one point of its revolution.
type Sampled = (Angles, f64, f64, BladeLoads);

impl RevolutionSums {
    /// Adds blade 1 at its angles (and a teetering rotor's blade 2, half a revolution behind:
    /// its angles, flap rate and loads).
    pub(super) fn add(
        &mut self,
        blade: &Blade<'_>,
        op: &Operating,
        (a1, b1, d1, mut l): Sampled,
        second: Option<(Angles, f64, BladeLoads)>,
    ) {
        let hb = blade.angular_momentum_and_rate(op, a1, d1, 0.0, 0.0).0;
        for (m, h) in self.momentum.iter_mut().zip(hb) {
            *m += h;
        }
        self.add_inertia(blade, a1);
        if let Some((a2, d2, l2)) = second {
            let h2 = blade.angular_momentum_and_rate(op, a2, d2, 0.0, 0.0).0;
            for (m, h) in self.momentum.iter_mut().zip(h2) {
                *m += h;
            }
            self.add_inertia(blade, a2);
            l.torque_n_m += l2.torque_n_m;
            for j in 0..3 {
                l.force_n[j] += l2.force_n[j];
                l.moment_n_m[j] += l2.moment_n_m[j];
            }
        }
        self.loads.torque_n_m += l.torque_n_m;
        for j in 0..3 {
            self.loads.force_n[j] += l.force_n[j];
            self.loads.moment_n_m[j] += l.moment_n_m[j];
        }
        // Blade 1's azimuth sines and cosines, already in its angles.
        self.a0 += b1;
        self.c1 += b1 * a1.cp;
        self.s1 += b1 * a1.sp;
    }

    /// Adds a blade's inertia beyond the frozen disc at its angles, and its angular momentum per
    /// unit rotorspeed.
    fn add_inertia(&mut self, blade: &Blade<'_>, angles: Angles) {
        for (sum, v) in self
            .spin
            .iter_mut()
            .zip(blade.spin_momentum_per_omega(angles))
        {
            *sum += v;
        }
        let j = blade.inertia_beyond_disc(angles);
        for (sum, row) in self.inertia.iter_mut().zip(j) {
            for (s, v) in sum.iter_mut().zip(row) {
                *s += v;
            }
        }
    }
}

/// What a periodic solution learned about its rotor's revolution map `P` (the flap state after
/// one revolution from a state at zero azimuth): the Jacobian of `P(x) - x`. A nearby solution
/// (the same rotor at a neighbouring operating state: a trim's next iterate, a linearisation's
/// perturbation) starts its secant steps from it and saves the revolutions it would spend
/// learning it again ([`Blade::steady_with`]). Opaque; empty by default.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RevolutionMap {
    pub(super) jacobian: Option<[[f64; 2]; 2]>,
}

impl RevolutionMap {
    /// What it learned, as numbers: the Jacobian of `P(x) - x` by rows, where it has one
    /// (a warm start carried as plain data: [`crate::aircraft::trim::StartPoint`]).
    pub fn jacobian(&self) -> Option<[[f64; 2]; 2]> {
        self.jacobian
    }

    /// The map that learned `jacobian` (none: an empty map).
    pub fn with_jacobian(jacobian: Option<[[f64; 2]; 2]>) -> Self {
        Self { jacobian }
    }
}

/// The fixed point of the revolution map, by secant steps. The plain iteration `x <- P(x)`
/// converges at the blade's damping per revolution (about 0.05 for a Lock number near 8: a
/// decade in every 0.8 revolution). With the Jacobian `J` of `f(x) = P(x) - x`, the step
/// `x - J^-1 f` lands on the fixed point up to the map's curvature. `J` comes from the last
/// three pairs `(x_j, f_j)` (their differences give it exactly for an affine map: a 2 x 2 form
/// of Anderson acceleration, Walker and Ni 2011), or, before there are three, from a nearby
/// solution's, updated by Broyden's rank-one formula with each new pair. Each step is checked:
/// it must land within [`JUMP_LIMIT`] times `|f|` of the plain iterate, as the fixed point of
/// any map contracting by 0.8 or less per revolution does; otherwise the plain iterate is
/// kept. The periodic solution is still the one revolution that returns to within the
/// tolerance of where it began, so a step changes how soon it is found, never what is found.
#[derive(Debug, Default)]
struct FixedPoint {
    pairs: Vec<([f64; 2], [f64; 2])>,
    jacobian: Option<[[f64; 2]; 2]>,
}

/// How closely the revolution whose loads are taken must return to where it began, as a
/// fraction of [`Numerics::periodic_tolerance`]. A revolution that closes to the tolerance
/// starts within about the tolerance of the periodic state; one further revolution from where
/// it ended starts within the blade's contraction per revolution times that (0.06 for the VPM
/// M16's teeter at 60 mph, measured from the secant Jacobian). Sampling the revolution that
/// closes to 0.05 of the tolerance gives that accuracy without the further revolution. At
/// the VPM M16's tolerance the trim residuals' noise is then at most 8.8e-9 (measured over a
/// 60 mph trim's evaluations, each solved with and without a nearby solution's Jacobian):
/// 5.4e-9 with the further revolution, 8.5e-8 sampling the revolution that closes to the
/// tolerance itself, against a trim tolerance of 1e-7.
pub(super) const SAMPLED_CLOSURE: f64 = 0.05;

/// How far a secant step may land from the plain iterate, in units of the last revolution's
/// change: `rho / (1 - rho)` for a map contracting by `rho` per revolution, 4 for 0.8.
const JUMP_LIMIT: f64 = 4.0;

/// The inverse of a 2 x 2 matrix applied to `b`, if the matrix is well conditioned (its
/// determinant above `1e-8` of the product of its columns' lengths).
fn solve2(m: [[f64; 2]; 2], b: [f64; 2]) -> Option<[f64; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let scale = m[0][0].hypot(m[1][0]) * m[0][1].hypot(m[1][1]);
    if !(det.is_finite() && det.abs() > 1e-8 * scale) {
        return None;
    }
    Some([
        (b[0] * m[1][1] - b[1] * m[0][1]) / det,
        (m[0][0] * b[1] - m[1][0] * b[0]) / det,
    ])
}

impl FixedPoint {
    fn new(map: RevolutionMap) -> Self {
        Self {
            pairs: Vec::with_capacity(3),
            jacobian: map.jacobian,
        }
    }

    /// The state to start the next revolution from, after one from `x` ended at `px`.
    fn next(&mut self, x: [f64; 2], px: [f64; 2]) -> [f64; 2] {
        let f = [px[0] - x[0], px[1] - x[1]];
        if self.pairs.len() == 3 {
            self.pairs.remove(0);
        }
        self.pairs.push((x, f));
        let diff = |a: ([f64; 2], [f64; 2]), b: ([f64; 2], [f64; 2])| {
            (
                [a.0[0] - b.0[0], a.0[1] - b.0[1]],
                [a.1[0] - b.1[0], a.1[1] - b.1[1]],
            )
        };
        match *self.pairs.as_slice() {
            [p0, p1, p2] => {
                // J (dx0 dx1) = (df0 df1), the differences from the latest pair.
                let ((dx0, df0), (dx1, df1)) = (diff(p0, p2), diff(p1, p2));
                // Row i of J solves (dx0 dx1)^T J_i^T = (df0_i, df1_i).
                let r0 = solve2([dx0, dx1], [df0[0], df1[0]]);
                let r1 = solve2([dx0, dx1], [df0[1], df1[1]]);
                if let (Some(r0), Some(r1)) = (r0, r1) {
                    self.jacobian = Some([r0, r1]);
                }
            }
            [p0, p1] => {
                if let Some(j) = &mut self.jacobian {
                    // Broyden: J += (df - J dx) dx^T / (dx^T dx).
                    let (dx, df) = diff(p1, p0);
                    let norm2 = dx[0] * dx[0] + dx[1] * dx[1];
                    if norm2 > 0.0 {
                        for (i, row) in j.iter_mut().enumerate() {
                            let miss = df[i] - (row[0] * dx[0] + row[1] * dx[1]);
                            row[0] += miss * dx[0] / norm2;
                            row[1] += miss * dx[1] / norm2;
                        }
                    }
                }
            }
            _ => {}
        }
        let Some(step) = self.jacobian.and_then(|j| solve2(j, f)) else {
            return px;
        };
        let jump = [x[0] - step[0], x[1] - step[1]];
        let size = f[0].abs().max(f[1].abs());
        let off = (jump[0] - px[0]).abs().max((jump[1] - px[1]).abs());
        if jump.iter().all(|v| v.is_finite()) && off <= JUMP_LIMIT * size {
            jump
        } else {
            px
        }
    }
}

impl Blade<'_> {
    /// A rigid rotor in axial flow (a propeller): every blade sees the same flow at every
    /// azimuth, so one azimuth gives the mean loads exactly.
    fn axisymmetric(&self, op: &Operating) -> Result<SteadyLoads, RotorError> {
        let p = self.rotor.precone_rad;
        let l = self.loads(op, 0.0, p, 0.0);
        let nb = self.rotor.blades as f64;
        // The blade at azimuth zero points along -x: its in-plane force components average to
        // zero over a revolution, as do the in-plane moments; thrust and torque remain.
        let out = SteadyLoads {
            force_n: [0.0, 0.0, nb * l.force_n[2]],
            moment_n_m: [0.0, 0.0, nb * l.moment_n_m[2]],
            driving_torque_n_m: nb * l.torque_n_m,
            a0_rad: p,
            a1_rad: 0.0,
            b1_rad: 0.0,
            beta0: [0.0, 0.0],
            angular_momentum_kg_m2_s: {
                let h = self.angular_momentum(op, 0.0, p, 0.0);
                [0.0, 0.0, nb * h[2]]
            },
            inertia_beyond_disc_kg_m2: [[0.0; 3]; 3],
            spin_momentum_per_omega_kg_m2: [
                0.0,
                0.0,
                nb * self.spin_momentum_per_omega(Angles::new(0.0, p))[2],
            ],
        };
        if !(out.force_n[2].is_finite() && out.driving_torque_n_m.is_finite()) {
            return Err(RotorError::NonFinite("rotor load"));
        }
        Ok(out)
    }

    /// One RK4 step of the flap equation, the loads at its start added to `sums` when given.
    pub(super) fn step(
        &self,
        op: &Operating,
        psi: f64,
        s: [f64; 2],
        h: f64,
        sums: Option<&mut RevolutionSums>,
    ) -> [f64; 2] {
        if self.rotor.hub == Hub::Rigid {
            // A rigid rotor's blades do not flap: their state stays, and only the first stage's
            // loads are taken.
            self.flap_rhs_sampled(op, &self.azimuth(psi), s, sums);
            return s;
        }
        let add = |a: [f64; 2], k: [f64; 2], f: f64| [a[0] + f * k[0], a[1] + f * k[1]];
        // The middle stages share their azimuth's sines and cosines.
        let middle = self.azimuth(psi + 0.5 * h);
        let k1 = self.flap_rhs_sampled(op, &self.azimuth(psi), s, sums);
        let k2 = self.flap_rhs_sampled(op, &middle, add(s, k1, 0.5 * h), None);
        let k3 = self.flap_rhs_sampled(op, &middle, add(s, k2, 0.5 * h), None);
        let k4 = self.flap_rhs_sampled(op, &self.azimuth(psi + h), add(s, k3, h), None);
        [
            s[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
            s[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
        ]
    }

    /// Integrates one blade to its periodic flapping and returns the rotor's mean loads.
    ///
    /// `start` is the flap state `[beta, d beta / d psi]` at `psi = 0` to start from (a warm
    /// start converges in a few revolutions).
    pub fn steady(&self, op: &Operating, start: [f64; 2]) -> Result<SteadyLoads, RotorError> {
        self.steady_with(op, start, &mut RevolutionMap::default())
    }

    /// [`Self::steady`], its secant steps started from what a nearby solution learned about
    /// the revolution map, and what this one learned left in `map` for the next.
    pub fn steady_with(
        &self,
        op: &Operating,
        start: [f64; 2],
        map: &mut RevolutionMap,
    ) -> Result<SteadyLoads, RotorError> {
        self.steady_counted(op, start, map, &mut 0)
    }

    /// [`Self::steady_with`], adding the revolutions it integrates to `revolutions` (whether it
    /// finds the periodic solution or not): what a solve made of many spends
    /// ([`crate::components::autorotation::MAX_REVOLUTIONS`]).
    pub fn steady_counted(
        &self,
        op: &Operating,
        start: [f64; 2],
        map: &mut RevolutionMap,
        revolutions: &mut usize,
    ) -> Result<SteadyLoads, RotorError> {
        let axisymmetric = self.rotor.hub == Hub::Rigid
            && op.hub.u == 0.0
            && op.hub.v == 0.0
            && op.inflow.v1s == 0.0
            && self.rotor.corrections.lateral_inflow_offset_m_s == 0.0
            && op.inflow.v1c == 0.0
            && op.hub_rates_rad_s == [0.0; 3];
        if axisymmetric {
            return self.axisymmetric(op);
        }
        let n = self
            .rotor
            .steps_per_revolution(self.numerics.azimuth_step_rad)?;
        let h = 2.0 * PI / n as f64;
        // Revolutions from `start`, each sampling the loads and flapping at its step points
        // (the first stage of every RK4 step, which the step computes anyway), with a secant
        // step on the revolution map between them ([`FixedPoint`]), until one closes to within
        // [`SAMPLED_CLOSURE`] of the tolerance: that revolution's sums are the periodic
        // solution's.
        let mut s = start;
        let mut change = f64::INFINITY;
        let mut found = None;
        let mut fixed_point = FixedPoint::new(*map);
        let close = SAMPLED_CLOSURE * self.numerics.periodic_tolerance;
        for _ in 0..self.numerics.max_revolutions {
            *revolutions += 1;
            let s0 = s;
            let mut sums = RevolutionSums::default();
            for k in 0..n {
                s = self.step(op, k as f64 * h, s, h, Some(&mut sums));
            }
            if !(s[0].is_finite() && s[1].is_finite()) {
                return Err(RotorError::NonFinite("flap angle"));
            }
            change = (s[0] - s0[0]).abs().max((s[1] - s0[1]).abs());
            if change <= close {
                found = Some((sums, s0));
                break;
            }
            s = fixed_point.next(s0, s);
        }
        if fixed_point.jacobian.is_some() {
            map.jacobian = fixed_point.jacobian;
        }
        let Some((sum, start_state)) = found else {
            return Err(RotorError::FlapNotPeriodic {
                revolutions: self.numerics.max_revolutions,
                change,
            });
        };
        // An articulated or rigid rotor's blades fly the same motion, so N_b times one blade's
        // mean is the rotor's; a teetering rotor's two blades are summed as they are.
        let nb = if self.rotor.hub == Hub::Teetering {
            1.0
        } else {
            self.rotor.blades as f64
        };
        let mean = |x: f64| nb * x / n as f64;
        let out = SteadyLoads {
            force_n: sum.loads.force_n.map(mean),
            moment_n_m: sum.loads.moment_n_m.map(mean),
            driving_torque_n_m: mean(sum.loads.torque_n_m),
            a0_rad: sum.a0 / n as f64,
            a1_rad: -2.0 * sum.c1 / n as f64,
            b1_rad: -2.0 * sum.s1 / n as f64,
            beta0: start_state,
            angular_momentum_kg_m2_s: sum.momentum.map(mean),
            inertia_beyond_disc_kg_m2: sum.inertia.map(|row| row.map(mean)),
            spin_momentum_per_omega_kg_m2: sum.spin.map(mean),
        };
        if !out
            .force_n
            .iter()
            .chain(&out.moment_n_m)
            .all(|x| x.is_finite())
        {
            return Err(RotorError::NonFinite("rotor load"));
        }
        // The first harmonics' bound on the flapping (the higher ones are small).
        let largest = out.a0_rad.abs() + out.a1_rad.hypot(out.b1_rad);
        if largest >= 0.5 * PI {
            return Err(RotorError::FlapPastVertical {
                largest_deg: largest.to_degrees(),
                coning_deg: out.a0_rad.to_degrees(),
            });
        }
        Ok(out)
    }
}
