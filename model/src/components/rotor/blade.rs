//! One blade's dynamics: its flap (teeter) equation, its inertial and weight moments, its
//! angular momentum and the motion of its centre of mass.

use super::steady::RevolutionSums;
use super::{Angles, Element, Hub, Numerics, Operating, Rotor, cross};
use std::f64::consts::PI;

/// An azimuth and the sines and cosines the flap equation takes there ([`Blade::azimuth`]):
/// found once where the right-hand side is evaluated twice at one azimuth (RK4's middle
/// stages), as `Angles::new` would find them.
#[derive(Debug, Clone, Copy)]
pub(super) struct Azimuth {
    psi: f64,
    first: (f64, f64),
    second: (f64, f64),
}

/// The steady periodic solution of a rotor at an operating state.
pub struct Blade<'a> {
    pub(super) rotor: &'a Rotor,
    pub(super) elements: Vec<Element>,
    pub(super) numerics: Numerics,
}

impl<'a> Blade<'a> {
    /// Prepares the blade elements of a (validated) rotor.
    pub fn new(rotor: &'a Rotor, numerics: Numerics) -> Self {
        Self {
            rotor,
            elements: rotor.elements(),
            numerics,
        }
    }

    /// The right-hand side of one blade's flap equation, `d/dpsi [beta, beta']`, with the
    /// blade-element loads it needs (the rotor's share of one model evaluation). For a
    /// teetering hub the state is the teeter angle and its azimuth rate.
    pub fn flap_derivative(&self, op: &Operating, psi_rad: f64, state: [f64; 2]) -> [f64; 2] {
        self.flap_rhs(op, psi_rad, state)
    }

    /// The blades' flap angles and rates `(beta, d beta / dt)` for a flap state
    /// `[angle, d angle / d psi]`: blade 1, and for a teetering hub blade 2 (half a
    /// revolution behind). Articulated and rigid hubs return blade 1 twice.
    pub fn blade_flap(&self, op: &Operating, state: [f64; 2]) -> [(f64, f64); 2] {
        self.blade_angles(op, state)
    }

    /// One blade's angular momentum about the hub centre, hub axes, kg m^2/s, beyond what the
    /// airframe's inertia holds: the airframe's inertia tensor carries the blades as a frozen
    /// disc (each blade's inertia, unflapped, averaged over azimuth:
    /// `K diag(1/2, 1/2, 1)` with `K = m e^2 + 2 e S + I`), so this is the blade's whole angular
    /// momentum (its rotation and flapping relative to the hub, and the hub's rates acting on
    /// its actual, flapped and azimuth-dependent inertia) less the frozen disc's share
    /// `K diag(1/2, 1/2, 1) omega_hub`.
    ///
    /// For three or more blades the azimuth-dependent parts cancel between blades. For two,
    /// they do not: a two-bladed rotor's inertia turns with it, and a body rate `omega` then
    /// gives the classical 2/rev gyroscopic couple of about `I_R Omega omega` (two-bladed
    /// propellers shake aircraft this way).
    pub fn angular_momentum_beyond_disc(
        &self,
        op: &Operating,
        psi_rad: f64,
        beta: f64,
        beta_dot: f64,
    ) -> [f64; 3] {
        self.angular_momentum_and_rate(op, Angles::new(psi_rad, beta), beta_dot, 0.0, 0.0)
            .0
    }

    /// The frozen disc's share of one blade's angular momentum, `K diag(1/2, 1/2, 1) omega_hub`
    /// with `K = m e^2 + 2 e S + I` (see [`Self::angular_momentum_beyond_disc`]).
    fn disc_share(&self, op: &Operating) -> [f64; 3] {
        let (d, w) = (self.disc(), op.hub_rates_rad_s);
        [d[0] * w[0], d[1] * w[1], d[2] * w[2]]
    }

    /// The frozen disc's inertia, one blade's share, `K diag(1/2, 1/2, 1)` (its diagonal).
    fn disc(&self) -> [f64; 3] {
        let (i, s_m, e, m) = self.mass_data();
        let k = m * e * e + 2.0 * e * s_m + i;
        [0.5 * k, 0.5 * k, k]
    }

    /// The blade's flap inertia `I` and first mass moment `S` about its hinge, the hinge's offset
    /// `e`, and its mass `m` (thin rigid blade: the uniform rod's `4 S^2 / (3 I)`).
    fn mass_data(&self) -> (f64, f64, f64, f64) {
        let rot = self.rotor;
        (
            rot.flap_inertia_kg_m2,
            rot.flap_mass_moment_kg_m,
            rot.hinge_offset_m,
            rot.blade_mass_kg(),
        )
    }

    /// One blade's angular momentum about the hub centre per unit rotorspeed, hub axes,
    /// kg m^2: `(m e^2 + e S cos b) r x t + (e S + I cos b) e_b x t`, the blade turning at
    /// `Omega` about the shaft at its flap angle ([`Self::angular_momentum_and_rate`]'s
    /// rotation terms). A change of rotorspeed `Omega'` takes `Omega'` times it from the hub.
    pub fn spin_momentum_per_omega(&self, angles: Angles) -> [f64; 3] {
        let (i, s_m, e, m) = self.mass_data();
        let cb = angles.cb;
        let [r_hat, t_hat, e_b, _] = unit_vectors(angles);
        let (rt, et) = (cross(r_hat, t_hat), cross(e_b, t_hat));
        let (a, b) = (e * e * m + e * s_m * cb, e * s_m + i * cb);
        std::array::from_fn(|k| a * rt[k] + b * et[k])
    }

    /// The blade's mass times its centre of mass's distance from the shaft, along the tangent
    /// `t = (sin psi, cos psi, 0)`, hub axes, kg m: `(m e + S cos b) t`. A change of rotorspeed
    /// `Omega'` accelerates its centre of mass by `Omega'` times this over its mass
    /// ([`Self::centre_of_mass_motion`]'s tangential term). Zero for weightless blades.
    pub fn tangential_mass_moment(&self, angles: Angles) -> [f64; 3] {
        let (_, s_m, e, m) = self.mass_data();
        if m <= 0.0 {
            return [0.0; 3];
        }
        let arm = m * e + s_m * angles.cb;
        [arm * angles.sp, arm * angles.cp, 0.0]
    }

    /// One blade's inertia about the hub centre, less the frozen disc's share that the
    /// airframe's inertia holds, times the hub's angular acceleration `w_dot` (hub axes),
    /// kg m^2/s^2: the part of the blade's angular momentum rate that the hub's angular
    /// acceleration gives and the airframe's equations do not (they carry the frozen disc;
    /// [`Self::angular_momentum_and_rate`] holds the hub's rates). The blade's inertia is that
    /// of [`Self::angular_momentum_and_rate`]'s `J omega_hub` terms:
    /// `J = (m e^2 + 2 e S cos b + I) 1 - m e^2 r r' - e S (e_b r' + r e_b') - I e_b e_b'`.
    /// Summed over three or more unflapped blades it is the frozen disc's, and this vanishes;
    /// over two it turns with the rotor (the pair has no inertia about its span, twice its
    /// share across it); flapping tilts and shrinks it.
    pub fn inertia_beyond_disc_times(&self, angles: Angles, w_dot: [f64; 3]) -> [f64; 3] {
        let j = self.inertia_beyond_disc(angles);
        std::array::from_fn(|k| j[k][0] * w_dot[0] + j[k][1] * w_dot[1] + j[k][2] * w_dot[2])
    }

    /// The matrix of [`Self::inertia_beyond_disc_times`], hub axes, kg m^2, by rows: the blade's
    /// `J` less the frozen disc's share `K diag(1/2, 1/2, 1)`.
    pub fn inertia_beyond_disc(&self, angles: Angles) -> [[f64; 3]; 3] {
        let (i, s_m, e, m) = self.mass_data();
        let [r, _, e_b, _] = unit_vectors(angles);
        let x2 = e * e * m + 2.0 * e * s_m * angles.cb + i;
        let disc = self.disc();
        std::array::from_fn(|row| {
            std::array::from_fn(|col| {
                let diagonal = if row == col { x2 - disc[row] } else { 0.0 };
                diagonal
                    - (e * e * m * r[row] * r[col]
                        + e * s_m * (e_b[row] * r[col] + r[row] * e_b[col])
                        + i * e_b[row] * e_b[col])
            })
        })
    }

    /// The blade angles `(beta, d beta / dt)` of blade 1 and, for a teetering hub, blade 2
    /// (half a revolution behind), from the flap state.
    fn blade_angles(&self, op: &Operating, s: [f64; 2]) -> [(f64, f64); 2] {
        let p = self.rotor.precone_rad;
        let w = op.omega_rad_s;
        match self.rotor.hub {
            Hub::Articulated => [(s[0], s[1] * w), (s[0], s[1] * w)],
            Hub::Teetering => [(p + s[0], s[1] * w), (p - s[0], -s[1] * w)],
            Hub::Rigid => [(p, 0.0), (p, 0.0)],
        }
    }

    /// Flap (or teeter) acceleration per unit azimuth squared.
    pub(super) fn flap_rhs(&self, op: &Operating, psi: f64, s: [f64; 2]) -> [f64; 2] {
        let angles = |second: bool, beta: f64| match second {
            false => Angles::new(psi, beta),
            true => Angles::new(psi + PI, beta),
        };
        self.flap_rhs_with(op, psi, angles, s, None)
    }

    /// The sines and cosines of azimuth `psi` that the flap equation uses: blade 1's, and a
    /// teetering rotor's blade 2's at `psi + pi`. A rigid rotor's are found where its loads are
    /// sampled, the only place it uses them.
    pub(super) fn azimuth(&self, psi: f64) -> Azimuth {
        let (first, second) = match self.rotor.hub {
            Hub::Rigid => ((0.0, 0.0), (0.0, 0.0)),
            Hub::Articulated => (psi.sin_cos(), (0.0, 0.0)),
            Hub::Teetering => (psi.sin_cos(), (psi + PI).sin_cos()),
        };
        Azimuth { psi, first, second }
    }

    /// [`Self::flap_rhs`] at an azimuth whose sines and cosines are known, adding the blades'
    /// loads at this point to a revolution's `sums` when given (the loads the right-hand side
    /// needs anyway, so sampling them costs nothing more).
    pub(super) fn flap_rhs_sampled(
        &self,
        op: &Operating,
        azimuth: &Azimuth,
        s: [f64; 2],
        sums: Option<&mut RevolutionSums>,
    ) -> [f64; 2] {
        let angles = |second: bool, beta: f64| match second {
            false => Angles::at(azimuth.first, beta),
            true => Angles::at(azimuth.second, beta),
        };
        self.flap_rhs_with(op, azimuth.psi, angles, s, sums)
    }

    /// The flap equation at azimuth `psi`, `angles(second, beta)` giving blade 1's angles
    /// (`second` false) or a teetering rotor's blade 2's, half a revolution on.
    #[inline]
    fn flap_rhs_with(
        &self,
        op: &Operating,
        psi: f64,
        angles: impl Fn(bool, f64) -> Angles,
        s: [f64; 2],
        sums: Option<&mut RevolutionSums>,
    ) -> [f64; 2] {
        let rot = self.rotor;
        let w = op.omega_rad_s;
        match rot.hub {
            Hub::Rigid => {
                if let Some(sums) = sums {
                    let [(b1, d1), _] = self.blade_angles(op, s);
                    let a1 = Angles::new(psi, b1);
                    sums.add(self, op, (a1, b1, d1, self.loads_at(op, a1, d1)), None);
                }
                return [0.0, 0.0];
            }
            Hub::Teetering => {
                // I_t = 2 I_beta; the moments of the two blades oppose about the teeter hinge,
                // and so do their centrifugal moments: -I Omega^2 (sin b1 cos b1 - sin b2 cos b2).
                let [(b1, d1), (b2, d2)] = self.blade_angles(op, s);
                let (a1, a2) = (angles(false, b1), angles(true, b2));
                let (l1, l2) = (self.loads_at(op, a1, d1), self.loads_at(op, a2, d2));
                let (m1, m2) = (l1.flap_moment_n_m, l2.flap_moment_n_m);
                if let Some(sums) = sums {
                    sums.add(self, op, (a1, b1, d1, l1), Some((a2, d2, l2)));
                }
                let i = rot.flap_inertia_kg_m2;
                // The blades' inertial moments oppose about the teeter hinge.
                let inertial =
                    self.inertial_flap_moment_at(op, a1) - self.inertial_flap_moment_at(op, a2);
                // Their weights and the hub's acceleration too: they cancel about the hinge
                // unless the blades are coned (the module's docs).
                let (f, w_dot) = (op.apparent_gravity_m_s2, op.hub_angular_acceleration_rad_s2);
                let weight = self.apparent_gravity_flap_moment_at(f, w_dot, a1)
                    - self.apparent_gravity_flap_moment_at(f, w_dot, a2);
                let spring = rot.flap_spring_n_m_per_rad * s[0];
                return [
                    s[1],
                    (m1 - m2 - inertial + weight - spring) / (2.0 * i * w * w),
                ];
            }
            Hub::Articulated => {}
        }
        let beta = s[0];
        let beta_dot = s[1] * w;
        let angles = angles(false, beta);
        let l = self.loads_at(op, angles, beta_dot);
        if let Some(sums) = sums {
            sums.add(self, op, (angles, beta, beta_dot, l), None);
        }
        let m_aero = l.flap_moment_n_m;
        let inertial = self.inertial_flap_moment_at(op, angles);
        let weight = self.apparent_gravity_flap_moment_at(
            op.apparent_gravity_m_s2,
            op.hub_angular_acceleration_rad_s2,
            angles,
        );
        let spring = rot.flap_spring_n_m_per_rad * (beta - rot.precone_rad);
        [
            s[1],
            (m_aero - inertial + weight - spring) / (rot.flap_inertia_kg_m2 * w * w),
        ]
    }

    /// The flap moment of the blade's weight and the hub's motion, positive flapping up (see the
    /// module's docs): `S f.n + (e S cos b + I) (w'.t)`, with `f` the apparent gravity at the
    /// hub (`g - a_hub`) and `w'` the hub's angular acceleration, both in hub axes; `n = d e_b /
    /// d beta` (the flapped blade's direction `e_b = (-cos b cos psi, cos b sin psi, -sin b)`)
    /// and `t = (sin psi, cos psi, 0)`. That is `S` times the apparent gravity at the hinge
    /// along `n`, and the blade's own flap inertia `I` under the hub's angular acceleration.
    /// With the shaft upright in unaccelerated flight it is `-S g cos b`: the blade droops.
    pub(crate) fn apparent_gravity_flap_moment_at(
        &self,
        apparent_gravity_m_s2: [f64; 3],
        hub_angular_acceleration_rad_s2: [f64; 3],
        angles: Angles,
    ) -> f64 {
        let (s_m, i_m) = (
            self.rotor.flap_mass_moment_kg_m,
            self.rotor.flap_inertia_kg_m2,
        );
        let Angles { sp, cp, sb, cb } = angles;
        let f = apparent_gravity_m_s2;
        let mut moment = 0.0;
        if s_m != 0.0 && f != [0.0; 3] {
            let n = [sb * cp, -sb * sp, -cb];
            moment = s_m * (f[0] * n[0] + f[1] * n[1] + f[2] * n[2]);
        }
        let (e, w) = (self.rotor.hinge_offset_m, hub_angular_acceleration_rad_s2);
        if w != [0.0; 3] {
            moment += (e * s_m * cb + i_m) * (w[0] * sp + w[1] * cp);
        }
        moment
    }

    /// The inertial flap moment of one blade apart from `I d2beta/dt2`: centrifugal, and with
    /// a rotating hub, Coriolis and centripetal terms (thin rigid blade, hinge at `e` on a
    /// hub turning at `omega_hub`, rotor at `Omega` about `-z`):
    ///
    /// ```text
    /// Omega^2 sin b (eS + I cos b) + 2 Omega (w.e_b)(eS + I cos b)
    ///   + (w.n)(eS (w.r) + I (w.e_b)) + |w|^2 e S sin b
    /// ```
    ///
    /// with `e_b` along the flapped blade, `n = d e_b / d beta` and `r` the unflapped blade
    /// direction. In hover this gives the classical response to a pitch rate: the disc lags
    /// the shaft by `16 q / (gamma Omega)` (tested).
    pub fn inertial_flap_moment(&self, op: &Operating, psi: f64, beta: f64) -> f64 {
        self.inertial_flap_moment_at(op, Angles::new(psi, beta))
    }

    /// [`Self::inertial_flap_moment`] with the blade's angles' sines and cosines given.
    pub(crate) fn inertial_flap_moment_at(&self, op: &Operating, angles: Angles) -> f64 {
        let Angles { sp, cp, sb, cb } = angles;
        let rot = self.rotor;
        let (i, es) = (
            rot.flap_inertia_kg_m2,
            rot.hinge_offset_m * rot.flap_mass_moment_kg_m,
        );
        let w = op.omega_rad_s;
        let centrifugal = w * w * sb * (es + i * cb);
        let [p, q, r] = op.hub_rates_rad_s;
        if p == 0.0 && q == 0.0 && r == 0.0 {
            return centrifugal;
        }
        let w_r = -p * cp + q * sp;
        let w_e = cb * w_r - sb * r;
        let w_n = -sb * w_r - cb * r;
        let coriolis = 2.0 * w * w_e * (es + i * cb);
        let centripetal = w_n * (es * w_r + i * w_e) + (p * p + q * q + r * r) * es * sb;
        centrifugal + coriolis + centripetal
    }

    /// One blade's angular momentum about the hub centre (thin rigid blade; the blade mass
    /// for the hinge-offset terms from the uniform-rod relation `m = 4 S^2 / (3 I)`).
    pub(super) fn angular_momentum(
        &self,
        op: &Operating,
        psi: f64,
        beta: f64,
        beta_dot: f64,
    ) -> [f64; 3] {
        self.momentum(op, Angles::new(psi, beta), beta_dot, 0.0, 0.0)
            .0
    }

    /// [`Self::angular_momentum_beyond_disc`] and its time derivative along the blade's motion:
    /// the azimuth advancing at `op.omega_rad_s`, the rotorspeed changing at
    /// `omega_dot_rad_s2`, the flap angle at `beta_dot` and `beta_ddot`; the hub's rates held
    /// (their change enters the airframe's equations, not the blades'). Exact: the chain rule
    /// through the blade's unit vectors (`d r/dpsi = t`, `d t/dpsi = -r`,
    /// `d e_b/dt = Omega cos b t + beta_dot n`, `d n/dt = -Omega sin b t - beta_dot e_b`),
    /// where central differences of the angular momentum used to cost three evaluations and
    /// lose half the digits.
    pub fn angular_momentum_and_rate(
        &self,
        op: &Operating,
        angles: Angles,
        beta_dot: f64,
        beta_ddot: f64,
        omega_dot_rad_s2: f64,
    ) -> ([f64; 3], [f64; 3]) {
        let (h, h_dot) = self.momentum(op, angles, beta_dot, beta_ddot, omega_dot_rad_s2);
        let disc = self.disc_share(op);
        (std::array::from_fn(|k| h[k] - disc[k]), h_dot)
    }

    /// One blade's whole angular momentum about the hub centre (thin rigid blade; the blade
    /// mass for the hinge-offset terms from the uniform-rod relation `m = 4 S^2 / (3 I)`) and
    /// its rate along the blade's motion (see [`Self::angular_momentum_and_rate`]).
    fn momentum(
        &self,
        op: &Operating,
        angles: Angles,
        beta_dot: f64,
        beta_ddot: f64,
        omega_dot_rad_s2: f64,
    ) -> ([f64; 3], [f64; 3]) {
        let (i, s_m, e, m) = self.mass_data();
        let (w, w_dot) = (op.omega_rad_s, omega_dot_rad_s2);
        let Angles { sb, cb, .. } = angles;
        let [r_hat, t_hat, e_b, n_hat] = unit_vectors(angles);
        let (rt, rn, et, en) = (
            cross(r_hat, t_hat),
            cross(r_hat, n_hat),
            cross(e_b, t_hat),
            cross(e_b, n_hat),
        );
        let om = op.hub_rates_rad_s;
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let (w_r, w_e) = (dot(om, r_hat), dot(om, e_b));
        let (a, b) = (e * e * m + e * s_m * cb, e * s_m + i * cb);
        let x2 = e * e * m + 2.0 * e * s_m * cb + i;
        // Rates of the unit vectors, the cross products and the scalars.
        let r_dot: [f64; 3] = std::array::from_fn(|k| w * t_hat[k]);
        let e_dot: [f64; 3] = std::array::from_fn(|k| w * cb * t_hat[k] + beta_dot * n_hat[k]);
        let (tn, rte, nt, er, outer) = (
            cross(t_hat, n_hat),
            cross(r_hat, e_b),
            cross(n_hat, t_hat),
            cross(e_b, r_hat),
            cross(e_b, t_hat),
        );
        let rn_dot: [f64; 3] =
            std::array::from_fn(|k| w * tn[k] - sb * w * rt[k] - beta_dot * rte[k]);
        let et_dot: [f64; 3] = std::array::from_fn(|k| beta_dot * nt[k] - w * er[k]);
        let en_dot: [f64; 3] = std::array::from_fn(|k| cb * w * tn[k] - sb * w * outer[k]);
        let w_r_dot = w * dot(om, t_hat);
        let w_e_dot = w * cb * dot(om, t_hat) + beta_dot * dot(om, n_hat);
        let (a_dot, b_dot, x2_dot) = (
            -e * s_m * sb * beta_dot,
            -i * sb * beta_dot,
            -2.0 * e * s_m * sb * beta_dot,
        );
        let mut h = [0.0; 3];
        let mut h_dot = [0.0; 3];
        for k in 0..3 {
            h[k] = w * a * rt[k]
                + e * s_m * beta_dot * rn[k]
                + w * b * et[k]
                + i * beta_dot * en[k]
                + x2 * om[k]
                - (e * e * m * w_r * r_hat[k]
                    + e * s_m * (w_r * e_b[k] + w_e * r_hat[k])
                    + i * w_e * e_b[k]);
            h_dot[k] = (w_dot * a + w * a_dot) * rt[k]
                + e * s_m * (beta_ddot * rn[k] + beta_dot * rn_dot[k])
                + (w_dot * b + w * b_dot) * et[k]
                + w * b * et_dot[k]
                + i * (beta_ddot * en[k] + beta_dot * en_dot[k])
                + x2_dot * om[k]
                - (e * e * m * (w_r_dot * r_hat[k] + w_r * r_dot[k])
                    + e * s_m
                        * (w_r_dot * e_b[k]
                            + w_r * e_dot[k]
                            + w_e_dot * r_hat[k]
                            + w_e * r_dot[k])
                    + i * (w_e_dot * e_b[k] + w_e * e_dot[k]));
        }
        (h, h_dot)
    }

    /// The position of one blade's centre of mass relative to the hub centre, hub axes, and
    /// its velocity and acceleration relative to the hub, along the same motion as
    /// [`Self::angular_momentum_and_rate`] (thin rigid blade: the centre of mass at
    /// `S / m` along the blade from the hinge, `m = 4 S^2 / (3 I)`).
    pub fn centre_of_mass_motion(
        &self,
        op: &Operating,
        angles: Angles,
        beta_dot: f64,
        beta_ddot: f64,
        omega_dot_rad_s2: f64,
    ) -> [[f64; 3]; 3] {
        let rot = self.rotor;
        let e = rot.hinge_offset_m;
        let d = rot.flap_mass_moment_kg_m / rot.blade_mass_kg();
        let Angles { sp, cp, sb, cb } = angles;
        let (w, w_dot) = (op.omega_rad_s, omega_dot_rad_s2);
        // Distance from the shaft R = e + d cos b, and its rates.
        let r = e + d * cb;
        let r_dot = -d * sb * beta_dot;
        let r_ddot = -d * (cb * beta_dot * beta_dot + sb * beta_ddot);
        [
            [-r * cp, r * sp, -d * sb],
            [
                -r_dot * cp + r * sp * w,
                r_dot * sp + r * cp * w,
                -d * cb * beta_dot,
            ],
            [
                -r_ddot * cp + 2.0 * r_dot * sp * w + r * cp * w * w + r * sp * w_dot,
                r_ddot * sp + 2.0 * r_dot * cp * w - r * sp * w * w + r * cp * w_dot,
                d * sb * beta_dot * beta_dot - d * cb * beta_ddot,
            ],
        ]
    }
}

/// The blade's unit vectors at `angles` (hub axes): the unflapped blade's direction
/// `r = (-cos psi, sin psi, 0)`, the in-plane tangent `t = d r / d psi`, the flapped blade's
/// direction `e_b` and `n = d e_b / d beta`.
fn unit_vectors(angles: Angles) -> [[f64; 3]; 4] {
    let Angles { sp, cp, sb, cb } = angles;
    let r = [-cp, sp, 0.0];
    [
        r,
        [sp, cp, 0.0],
        [cb * r[0], cb * r[1], -sb],
        [-sb * r[0], -sb * r[1], -cb],
    ]
}
