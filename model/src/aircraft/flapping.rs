//! Linearisation with the rotor's flapping and inflow as states: the individual-blade model
//! averaged over the azimuth in tip-path-plane coordinates.
//!
//! The quasi-static linearisation ([`crate::aircraft::linearise`]) holds the blades in their
//! periodic motion at every perturbed state: the flapping follows the body without lag. The
//! blades' own dynamics (the regressing flap mode, time constant about `16 / (gamma Omega)`)
//! and the inflow's lag are then outside the linear model, while a flight (or the full model's
//! simulation) has them. This module keeps them.
//!
//! # Coordinates
//! A teetering rotor's one degree of freedom, the teeter angle `beta` of blade 1 (blade 1 up),
//! is written at blade 1's azimuth `psi` as a first harmonic with slowly varying coefficients
//! (variation of parameters, the osculating form of a multiblade transformation):
//!
//! ```text
//! beta     = beta_1c cos(psi) + beta_1s sin(psi)
//! beta_dot = Omega (-beta_1c sin(psi) + beta_1s cos(psi))        (so  beta_1c' cos + beta_1s' sin = 0)
//! beta_1c' = -g sin(psi),  beta_1s' = g cos(psi),  g = (beta_ddot + Omega^2 beta - Omega_dot (-beta_1c sin + beta_1s cos)) / Omega
//! ```
//!
//! `beta_1c` tilts the tip-path plane down at the front (blade 1 up over the tail at `psi = 0`),
//! `beta_1s` down on the left (blade 1 up on the advancing side, `psi = 90 deg`), as the
//! flapping of blade 1 `a cos psi + b sin psi`: a teeter rotor's disc tilts back by `beta_1c`
//! and to the left by `beta_1s`.
//!
//! # The periodic system and its average
//! The full model's right-hand side ([`Aircraft::derivatives`]) is evaluated at `N` azimuths
//! of blade 1 spread evenly over a revolution, with the teeter angle and rate of those
//! coefficients, and every rate is taken (the rigid body's, the rotorspeed's, the inflow's, the
//! propeller's, and the coefficients' from the teeter acceleration). Differenced at each
//! azimuth, these give a linear time-periodic system ([`Periodic`]). Its average over the
//! azimuths is the time-invariant model ([`WithFlapping::model`], the constant-coefficient
//! approximation), which leaves out the periodic coefficients' couplings through the 2/rev and
//! higher harmonics. Its baseband frequency response by harmonic balance
//! ([`WithFlapping::baseband_response`]) keeps them: what a record's low-frequency analysis of
//! the periodic system sees. For the VPM M16 (Lock number about 8, the flap mode's damping half
//! the rotor speed) the two differ by up to 3.5 % in the derivatives identified from them (L_q;
//! M_p 2.8 %).
//! The equilibrium and the average are taken as the trim's periodic solution gives them; the
//! teeter's own higher harmonics are left out of the coordinates.
//!
//! # States, equilibrium and derivatives
//! States: the ten of the quasi-static model ([`STATES`]), then `beta_1c`, `beta_1s` (rad), then
//! the inflow `v0`, `v1s`, `v1c` (m/s, hub axes) when the inflow is dynamic, then the
//! propeller speed `Omega_p` (rad/s) when an engine drives it. The equilibrium is found at the
//! trim's body state and controls: Newton on the averaged flap, inflow and propeller rates from
//! the trim's periodic solution. The averaged rigid-body and rotorspeed rates left there are
//! the approximation's residual (reported). The derivatives are central differences about
//! that point with [`Steps`] (flapping perturbed by `Steps::flap_rad`).
//!
//! Only a teetering hub is supported: a hinged rotor of `N` blades needs the full multiblade
//! transformation (coning, cyclic and reactionless modes), which no aircraft in this project
//! flies with. [`with_flapping`] says so rather than guessing.

use crate::aircraft::linearise::{CONTROLS, LinearisationError, STATES, Steps};
use crate::aircraft::trim::Trim;
use crate::aircraft::{Air, Aircraft, AircraftError, Controls, Drive, FullState, InflowDynamics};
use crate::analysis::linear::LinearModel;
use crate::components::rigid_body::BodyState;
use crate::components::rotor::{Blade, Hub, Inflow};
use nalgebra::{Complex, DMatrix, DVector};
use serde::Serialize;
use std::f64::consts::PI;

/// The flapping states' names, in order.
pub const FLAP_STATES: [&str; 2] = ["beta_1c", "beta_1s"];
/// The inflow states' names, in order (hub axes, m/s).
pub const INFLOW_STATES: [&str; 3] = ["v0", "v1s", "v1c"];
/// The engine-driven propeller's speed.
pub const PROPELLER_STATE: &str = "Omega_p";
/// Azimuths of blade 1 the right-hand side is averaged over (every 7.5 deg: harmonics below
/// 48/rev average exactly).
pub const AZIMUTH_SAMPLES: usize = 48;

/// The equilibrium of the averaged model at the trim's body state and controls.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Equilibrium {
    pub beta_1c_rad: f64,
    pub beta_1s_rad: f64,
    pub inflow: Inflow,
    pub propeller_omega_rad_s: f64,
    /// The averaged rates of the ten quasi-static states there (`u v w p q r`, m/s^2 and
    /// rad/s^2; `phi theta psi`, rad/s; `Omega`, rad/s^2): zero for the trim, so these measure
    /// what the constant-coefficient approximation leaves out.
    pub residual: [f64; 10],
    /// Newton iterations to the equilibrium.
    pub iterations: usize,
}

/// The aircraft linearised with its flapping (and inflow, and propeller speed) as states.
#[derive(Debug, Clone, PartialEq)]
pub struct WithFlapping {
    /// States: [`STATES`], [`FLAP_STATES`], then [`INFLOW_STATES`] (dynamic inflow) and
    /// [`PROPELLER_STATE`] (an engine drive); controls [`CONTROLS`].
    pub model: LinearModel,
    /// The periodic system `model` is the average of, in the same states and controls.
    pub periodic: Periodic,
    pub equilibrium: Equilibrium,
    pub steps: Steps,
    /// The harmonic balance's frequency-independent part with [`SIDEBANDS`], reduced once
    /// ([`Periodic::baseband`]) for every frequency asked of [`WithFlapping::baseband_response`].
    pub(crate) baseband: BasebandCache,
}

/// A [`Baseband`] made on first use and kept: equal to any other (it is derived from the
/// periodic system beside it).
#[derive(Debug, Clone, Default)]
pub(crate) struct BasebandCache(std::sync::OnceLock<Result<Baseband, PeriodicError>>);

impl PartialEq for BasebandCache {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// The sidebands harmonic balance keeps for the aircraft's baseband response
/// ([`WithFlapping::baseband_response`]): up to 4/rev on either side. For the VPM M16 at 70 mph,
/// 8 changes no derivative identified from the response in its fifth digit; none (the average
/// alone) moves L_p by 0.3 % and M_p by 3 %.
pub const SIDEBANDS: usize = 4;

impl WithFlapping {
    /// The periodic model's baseband response at `omega` rad/s ([`Periodic::baseband_response`]
    /// with [`SIDEBANDS`]): states x controls, in the order of [`WithFlapping::model`].
    pub fn baseband_response(&self, omega: f64) -> Result<DMatrix<Complex<f64>>, PeriodicError> {
        self.baseband
            .0
            .get_or_init(|| self.periodic.baseband(SIDEBANDS))
            .as_ref()
            .map_err(Clone::clone)?
            .at(omega)
    }

    /// The quasi-static model of the same states as [`crate::aircraft::linearise`]: every
    /// state beyond [`STATES`] eliminated at its own equilibrium (`A11 - A12 A22^-1 A21`,
    /// `B1 - A12 A22^-1 B2`).
    pub fn quasi_static(&self) -> Result<LinearModel, LinearisationError> {
        let n = STATES.len();
        let a = self.model.a();
        let b = self.model.b();
        let nf = a.nrows() - n;
        let a22 = a.view((n, n), (nf, nf)).into_owned();
        let lu = a22.lu();
        let a21 = a.view((n, 0), (nf, n)).into_owned();
        let b2 = b.rows(n, nf).into_owned();
        let za = lu.solve(&a21).ok_or(LinearisationError::Singular)?;
        let zb = lu.solve(&b2).ok_or(LinearisationError::Singular)?;
        let a12 = a.view((0, n), (n, nf));
        let a_qs = a.view((0, 0), (n, n)) - a12 * za;
        let b_qs = b.rows(0, n) - a12 * zb;
        Ok(LinearModel::new(
            self.model.states()[..n].to_vec(),
            self.model.controls().to_vec(),
            a_qs,
            b_qs,
        )?)
    }
}

/// The averaged right-hand side over a state vector laid out as [`WithFlapping::model`]'s.
struct Averager<'a> {
    aircraft: &'a Aircraft,
    blade: Blade<'a>,
    air: Air,
    dynamic_inflow: bool,
    engine: bool,
    /// The inflow to start the full model's quasi-steady inflow from (quasi-steady inflow).
    inflow_start: Inflow,
    /// The propeller speed when it is not a state.
    propeller_omega_rad_s: f64,
}

impl Averager<'_> {
    fn len(&self) -> usize {
        STATES.len() + 2 + if self.dynamic_inflow { 3 } else { 0 } + usize::from(self.engine)
    }

    /// The averaged rates.
    fn rates(&self, z: &[f64], controls: &Controls) -> Result<Vec<f64>, AircraftError> {
        let per = self.rates_by_azimuth(z, controls)?;
        let mut mean = vec![0.0; self.len()];
        for r in &per {
            for (m, v) in mean.iter_mut().zip(r) {
                *m += v / AZIMUTH_SAMPLES as f64;
            }
        }
        Ok(mean)
    }

    /// The rates at each of the [`AZIMUTH_SAMPLES`] azimuths of blade 1.
    fn rates_by_azimuth(
        &self,
        z: &[f64],
        controls: &Controls,
    ) -> Result<Vec<Vec<f64>>, AircraftError> {
        let n = STATES.len();
        let (a, b) = (z[n], z[n + 1]);
        let omega = z[9];
        let mut k = n + 2;
        let inflow = if self.dynamic_inflow {
            k += 3;
            Inflow {
                v0: z[n + 2],
                v1s: z[n + 3],
                v1c: z[n + 4],
            }
        } else {
            self.inflow_start
        };
        let prop = if self.engine {
            z[k]
        } else {
            self.propeller_omega_rad_s
        };
        // The body's state but its position (zero).
        let mut body = [0.0; 12];
        body[..9].copy_from_slice(&z[..9]);
        let body = BodyState::from_array(body);
        let mut out = Vec::with_capacity(AZIMUTH_SAMPLES);
        for j in 0..AZIMUTH_SAMPLES {
            let mut sum = vec![0.0; self.len()];
            let psi = 2.0 * PI * j as f64 / AZIMUTH_SAMPLES as f64;
            let (s, c) = psi.sin_cos();
            let beta = a * c + b * s;
            let beta_rate_per_omega = -a * s + b * c;
            let x = FullState {
                body,
                rotor_azimuth_rad: psi,
                rotor_omega_rad_s: omega,
                flap: vec![[beta, omega * beta_rate_per_omega]],
                inflow,
                propeller_omega_rad_s: prop,
            };
            let d =
                self.aircraft
                    .derivatives_with(&self.blade, &x, controls, self.air, [0.0; 3])?;
            // The body's rates but the position's, and the rotorspeed's.
            sum[..9].copy_from_slice(&d.body.to_array()[..9]);
            sum[9] = d.rotor_omega_rad_s;
            let g = (d.flap[0][1] + omega * omega * beta
                - d.rotor_omega_rad_s * beta_rate_per_omega)
                / omega;
            sum[n] = -g * s;
            sum[n + 1] = g * c;
            let mut k = n + 2;
            if self.dynamic_inflow {
                sum[k] = d.inflow.v0;
                sum[k + 1] = d.inflow.v1s;
                sum[k + 2] = d.inflow.v1c;
                k += 3;
            }
            if self.engine {
                sum[k] = d.propeller_omega_rad_s;
            }
            out.push(sum);
        }
        Ok(out)
    }
}

/// A linear time-periodic system `x' = A(psi) x + B(psi) u`, `psi = Omega t`: the aircraft
/// linearised about its periodic motion, sampled at evenly spaced azimuths of blade 1 over one
/// revolution.
#[derive(Debug, Clone, PartialEq)]
pub struct Periodic {
    pub omega_rad_s: f64,
    /// `A` at azimuths `2 pi k / N`, `k = 0 .. N - 1`.
    pub a_at: Vec<DMatrix<f64>>,
    /// `B` at the same azimuths.
    pub b_at: Vec<DMatrix<f64>>,
}

/// Why a periodic system's response could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PeriodicError {
    #[error(
        "a periodic system needs matrices at two azimuths or more, A square and B with A's rows"
    )]
    Shape,
    #[error("the harmonic-balance equations are singular at {omega_rad_s} rad/s")]
    Singular { omega_rad_s: f64 },
}

impl Periodic {
    /// The time-invariant approximation: the mean of `A` and of `B` over a revolution (the
    /// constant-coefficient approximation).
    pub fn average(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let k = self.a_at.len() as f64;
        let mut a = self.a_at[0].clone() * 0.0;
        let mut b = self.b_at[0].clone() * 0.0;
        for (x, y) in self.a_at.iter().zip(&self.b_at) {
            a += x / k;
            b += y / k;
        }
        (a, b)
    }

    /// The `m`th complex Fourier coefficient of a periodic matrix over its samples.
    fn harmonic(samples: &[DMatrix<f64>], m: i64) -> DMatrix<Complex<f64>> {
        let k = samples.len();
        let (r, c) = samples[0].shape();
        let mut out = DMatrix::<Complex<f64>>::zeros(r, c);
        for (j, x) in samples.iter().enumerate() {
            let psi = -2.0 * PI * (m * j as i64) as f64 / k as f64;
            let e = Complex::new(psi.cos(), psi.sin()) / k as f64;
            out += x.map(|v| e * v);
        }
        out
    }

    /// The baseband frequency response at `omega` rad/s: the part of the states' response at
    /// the input's own frequency to an input `u = U exp(i omega t)`, per unit `U` (states x
    /// controls). A periodic system answers a sinusoid at `omega` with sidebands at
    /// `omega + n Omega` as well; the baseband is what a record's low-frequency analysis sees
    /// (Wereley's harmonic transfer function, its zeroth entry). Found by harmonic balance with
    /// the sidebands `n = -harmonics ..= harmonics`: `i (omega + n Omega) X_n - sum_m A_m
    /// X_(n-m) = B_n`, with `A_m`, `B_m` the samples' Fourier coefficients (exact for a system
    /// whose coefficients have no harmonic above `N/2`).
    /// Each call reduces the balance anew: for many frequencies keep [`Periodic::baseband`]
    /// and ask it [`Baseband::at`] each (as [`WithFlapping::baseband_response`] does).
    pub fn baseband_response(
        &self,
        omega: f64,
        harmonics: usize,
    ) -> Result<DMatrix<Complex<f64>>, PeriodicError> {
        self.baseband(harmonics)?.at(omega)
    }

    /// The harmonic balance's frequency-independent part, reduced once for any number of
    /// frequencies. The balance is `(i omega I - K) X = R`, with `K` holding `A_(n-p)` in block
    /// `(n, p)` less `i n Omega` on the diagonal and `R` the `B_n`: `K = Q H Q*` (Householder, to
    /// upper Hessenberg form) leaves a Hessenberg system at each frequency, `O(n^2)` where a
    /// factorisation of the whole is `O(n^3)` (Laub's method for frequency responses;
    /// numerically stable, unlike a decomposition by eigenvectors).
    pub fn baseband(&self, harmonics: usize) -> Result<Baseband, PeriodicError> {
        let nz = self.a_at.first().map_or(0, |a| a.nrows());
        if self.a_at.len() < 2
            || self.a_at.len() != self.b_at.len()
            || self.a_at.iter().any(|a| a.shape() != (nz, nz))
            || self.b_at.iter().any(|b| b.nrows() != nz)
        {
            return Err(PeriodicError::Shape);
        }
        let m = self.b_at[0].ncols();
        let h = harmonics as i64;
        let blocks = 2 * harmonics + 1;
        let a_m: Vec<DMatrix<Complex<f64>>> = (-2 * h..=2 * h)
            .map(|q| Self::harmonic(&self.a_at, q))
            .collect();
        let mut k = DMatrix::<Complex<f64>>::zeros(blocks * nz, blocks * nz);
        let mut rhs = DMatrix::<Complex<f64>>::zeros(blocks * nz, m);
        for (bi, n) in (-h..=h).enumerate() {
            let shift = Complex::new(0.0, n as f64 * self.omega_rad_s);
            for (bj, p) in (-h..=h).enumerate() {
                // A_(n - p) couples sideband p into sideband n.
                let coupling = &a_m[(n - p + 2 * h) as usize];
                k.view_mut((bi * nz, bj * nz), (nz, nz)).copy_from(coupling);
            }
            for i in 0..nz {
                k[(bi * nz + i, bi * nz + i)] -= shift;
            }
            let b_n = Self::harmonic(&self.b_at, n);
            rhs.view_mut((bi * nz, 0), (nz, m)).copy_from(&b_n);
        }
        let (q, hess) = nalgebra::linalg::Hessenberg::new(k).unpack();
        let q_star_rhs = q.adjoint() * rhs;
        let baseband_rows = q.rows(harmonics * nz, nz).into_owned();
        Ok(Baseband {
            hessenberg: hess,
            q_star_rhs,
            baseband_rows,
        })
    }
}

/// A periodic system's harmonic balance reduced to Hessenberg form ([`Periodic::baseband`]):
/// its baseband response at any frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Baseband {
    /// `H` of `K = Q H Q*`.
    hessenberg: DMatrix<Complex<f64>>,
    /// `Q* R`.
    q_star_rhs: DMatrix<Complex<f64>>,
    /// The rows of `Q` that give the baseband (sideband 0).
    baseband_rows: DMatrix<Complex<f64>>,
}

impl Baseband {
    /// The baseband response at `omega` rad/s (states x controls): `(i omega I - H) Y = Q* R`
    /// by Gaussian elimination with partial pivoting on the Hessenberg form (one row below the
    /// diagonal to eliminate in each column), then `X_0 = Q_0 Y`.
    pub fn at(&self, omega: f64) -> Result<DMatrix<Complex<f64>>, PeriodicError> {
        let singular = PeriodicError::Singular { omega_rad_s: omega };
        let n = self.hessenberg.nrows();
        let mut a = -self.hessenberg.clone();
        for i in 0..n {
            a[(i, i)] += Complex::new(0.0, omega);
        }
        let mut y = self.q_star_rhs.clone();
        for c in 0..n.saturating_sub(1) {
            if a[(c + 1, c)].norm() > a[(c, c)].norm() {
                a.swap_rows(c, c + 1);
                y.swap_rows(c, c + 1);
            }
            let pivot = a[(c, c)];
            if pivot.norm() == 0.0 || !pivot.is_finite() {
                return Err(singular);
            }
            let f = a[(c + 1, c)] / pivot;
            if f.norm() != 0.0 {
                for j in c..n {
                    let v = a[(c, j)];
                    a[(c + 1, j)] -= f * v;
                }
                for j in 0..y.ncols() {
                    let v = y[(c, j)];
                    y[(c + 1, j)] -= f * v;
                }
            }
        }
        for c in (0..n).rev() {
            let pivot = a[(c, c)];
            if pivot.norm() == 0.0 || !pivot.is_finite() {
                return Err(singular);
            }
            for j in 0..y.ncols() {
                let mut v = y[(c, j)];
                for k in c + 1..n {
                    v -= a[(c, k)] * y[(k, j)];
                }
                y[(c, j)] = v / pivot;
            }
        }
        let x = &self.baseband_rows * y;
        if x.iter().any(|v| !v.is_finite()) {
            return Err(singular);
        }
        Ok(x)
    }
}

/// Linearises the aircraft about a trim with the rotor's flapping, inflow and (with an engine)
/// propeller speed as states. See the module's documentation for the coordinates, the averaging
/// and what it leaves out.
pub fn with_flapping(
    aircraft: &Aircraft,
    trim: &Trim,
    air: Air,
    steps: Steps,
) -> Result<WithFlapping, LinearisationError> {
    if aircraft.main_rotor.rotor.hub != Hub::Teetering {
        return Err(LinearisationError::Aircraft(AircraftError::Invalid {
            name: "main rotor hub for a linearisation with flapping states (only a teetering hub is supported)",
            requirement: "teetering",
            value: aircraft.flap_dofs() as f64,
        }));
    }
    // The model a simulation flies: the propeller on its map.
    let mapped = aircraft.with_propeller_map();
    let aircraft = &mapped;
    let mr = &aircraft.main_rotor;
    let engine = matches!(aircraft.propeller.drive, Drive::Engine { .. });
    let dynamic_inflow = mr.inflow_dynamics == InflowDynamics::Dynamic;
    let state = &trim.state;
    let controls = trim.controls;
    let avg = Averager {
        aircraft,
        blade: Blade::new(&mr.rotor, mr.numerics),
        air,
        dynamic_inflow,
        engine,
        inflow_start: state.inflow,
        propeller_omega_rad_s: aircraft.propeller_omega(state, &controls),
    };
    let nz = avg.len();
    let n = STATES.len();
    let mut z = start_states(trim, dynamic_inflow, engine, avg.propeller_omega_rad_s);
    let fast: Vec<usize> = (n..nz).collect();
    let step_of = |i: usize| state_step(&steps, dynamic_inflow, n, i);
    let tip = state.rotor_omega_rad_s * mr.rotor.radius_m;
    let (rates, iterations) = fast_equilibrium(&avg, &mut z, &controls, &fast, tip, &step_of)?;
    let mut residual = [0.0; 10];
    residual.copy_from_slice(&rates[..n]);
    // Central differences: every state, then every control.
    let nv = nz + CONTROLS.len();
    let column = |j: usize| -> Result<Vec<Vec<f64>>, AircraftError> {
        let eval = |sign: f64| -> Result<(Vec<Vec<f64>>, f64), AircraftError> {
            let mut zz = z.clone();
            let mut cc = controls;
            let h = if j < nz {
                let h = step_of(j);
                zz[j] += sign * h;
                h
            } else {
                let h = steps.control_percent;
                match j - nz {
                    0 => cc.stick_longitudinal_percent += sign * h,
                    1 => cc.stick_lateral_percent += sign * h,
                    2 => cc.pedal_percent += sign * h,
                    _ => cc.throttle_percent += sign * h,
                }
                h
            };
            Ok((avg.rates_by_azimuth(&zz, &cc)?, h))
        };
        let ((p, h), (m, _)) = (eval(1.0)?, eval(-1.0)?);
        Ok(p.iter()
            .zip(&m)
            .map(|(p, m)| p.iter().zip(m).map(|(a, b)| (a - b) / (2.0 * h)).collect())
            .collect())
    };
    let (even, odd): (Vec<usize>, Vec<usize>) = (0..nv).partition(|j| j % 2 == 0);
    // Each variable's column: the rates' derivatives at every azimuth.
    type Columns = Vec<(usize, Vec<Vec<f64>>)>;
    let run = |js: Vec<usize>| -> Result<Columns, AircraftError> {
        js.into_iter().map(|j| Ok((j, column(j)?))).collect()
    };
    let (mine, other) = std::thread::scope(|scope| {
        let other = scope.spawn(|| run(odd));
        (run(even), other.join())
    });
    let other = other.map_err(|_| LinearisationError::Worker)?;
    let (a_at, b_at) = periodic_matrices(nz, mine?.into_iter().chain(other?));
    let periodic = Periodic {
        omega_rad_s: state.rotor_omega_rad_s,
        a_at,
        b_at,
    };
    let (a, b) = periodic.average();
    let names = state_names(dynamic_inflow, engine);
    let model = LinearModel::new(
        names,
        CONTROLS.iter().map(|s| s.to_string()).collect(),
        a,
        b,
    )?;
    let k_inflow = n + 2;
    Ok(WithFlapping {
        baseband: BasebandCache::default(),
        model,
        periodic,
        equilibrium: Equilibrium {
            beta_1c_rad: z[n],
            beta_1s_rad: z[n + 1],
            inflow: if dynamic_inflow {
                Inflow {
                    v0: z[k_inflow],
                    v1s: z[k_inflow + 1],
                    v1c: z[k_inflow + 2],
                }
            } else {
                state.inflow
            },
            propeller_omega_rad_s: if engine {
                z[nz - 1]
            } else {
                avg.propeller_omega_rad_s
            },
            residual,
            iterations,
        },
        steps,
    })
}

/// The linearisation's states at the trim: the body's state but its position, the rotorspeed,
/// the teeter's first harmonic, and (as the model has them) the inflow and the propeller speed
/// `propeller_omega_rad_s`.
fn start_states(
    trim: &Trim,
    dynamic_inflow: bool,
    engine: bool,
    propeller_omega_rad_s: f64,
) -> Vec<f64> {
    // The body's state but its position, and the rotorspeed.
    let mut z = trim.state.body.to_array()[..9].to_vec();
    z.extend([
        trim.state.rotor_omega_rad_s,
        // The periodic solution's teeter angle and slope at psi = 0 are its first harmonic's
        // coefficients.
        trim.averaged.flap_start[0],
        trim.averaged.flap_start[1],
    ]);
    if dynamic_inflow {
        z.extend([
            trim.state.inflow.v0,
            trim.state.inflow.v1s,
            trim.state.inflow.v1c,
        ]);
    }
    if engine {
        z.push(propeller_omega_rad_s);
    }
    z
}

/// The central-difference step of state `i` (`n` rigid-body states and the rotorspeed first).
fn state_step(steps: &Steps, dynamic_inflow: bool, n: usize, i: usize) -> f64 {
    match i {
        0..=2 => steps.velocity_m_s,
        3..=5 => steps.rate_rad_s,
        6..=8 => steps.angle_rad,
        9 => steps.omega_rad_s,
        10 | 11 => steps.flap_rad,
        _ if dynamic_inflow && i < n + 5 => steps.inflow_m_s,
        _ => steps.propeller_rad_s,
    }
}

/// Newton on the fast states' averaged rates, with a central-difference Jacobian: moves the
/// fast states of `z` to their equilibrium (rates scaled by the tip speed `tip` for the
/// inflow), and returns the averaged rates there and the iterations it took.
fn fast_equilibrium(
    avg: &Averager,
    z: &mut [f64],
    controls: &Controls,
    fast: &[usize],
    tip: f64,
    step_of: &dyn Fn(usize) -> f64,
) -> Result<(Vec<f64>, usize), LinearisationError> {
    let n = STATES.len();
    let mut iterations = 0;
    let mut rates = avg.rates(z, controls)?;
    loop {
        let norm = fast
            .iter()
            .map(|&i| (rates[i] / if i < n + 2 { 1.0 } else { tip }).abs())
            .fold(0.0, f64::max);
        if norm < 1e-10 {
            break;
        }
        if iterations >= 20 {
            return Err(LinearisationError::Aircraft(AircraftError::Invalid {
                name: "averaged flapping equilibrium (no convergence in 20 Newton iterations), largest scaled rate",
                requirement: "below 1e-10",
                value: norm,
            }));
        }
        let mut jac = DMatrix::<f64>::zeros(fast.len(), fast.len());
        for (c, &i) in fast.iter().enumerate() {
            let h = step_of(i) * 0.1;
            let mut zp = z.to_vec();
            zp[i] += h;
            let mut zm = z.to_vec();
            zm[i] -= h;
            let (rp, rm) = (avg.rates(&zp, controls)?, avg.rates(&zm, controls)?);
            for (r, &k) in fast.iter().enumerate() {
                jac[(r, c)] = (rp[k] - rm[k]) / (2.0 * h);
            }
        }
        let rhs = DVector::from_iterator(fast.len(), fast.iter().map(|&k| -rates[k]));
        let dz = jac.lu().solve(&rhs).ok_or(LinearisationError::Singular)?;
        for (c, &i) in fast.iter().enumerate() {
            z[i] += dz[c];
        }
        rates = avg.rates(z, controls)?;
        iterations += 1;
    }
    Ok((rates, iterations))
}

/// The periodic system's matrices at each azimuth from each variable's column (the rates'
/// derivatives at every azimuth; states first, `nz` of them, then controls).
fn periodic_matrices(
    nz: usize,
    columns: impl Iterator<Item = (usize, Vec<Vec<f64>>)>,
) -> (Vec<DMatrix<f64>>, Vec<DMatrix<f64>>) {
    let mut a_at = vec![DMatrix::<f64>::zeros(nz, nz); AZIMUTH_SAMPLES];
    let mut b_at = vec![DMatrix::<f64>::zeros(nz, CONTROLS.len()); AZIMUTH_SAMPLES];
    for (j, col) in columns {
        for (k, rates) in col.into_iter().enumerate() {
            for (i, v) in rates.into_iter().enumerate() {
                if j < nz {
                    a_at[k][(i, j)] = v;
                } else {
                    b_at[k][(i, j - nz)] = v;
                }
            }
        }
    }
    (a_at, b_at)
}

/// The states' names: the rigid body's and the rotorspeed, the teeter's, then the inflow's and
/// the propeller speed as the model has them.
fn state_names(dynamic_inflow: bool, engine: bool) -> Vec<String> {
    let mut names: Vec<String> = STATES.iter().map(|s| s.to_string()).collect();
    names.extend(FLAP_STATES.iter().map(|s| s.to_string()));
    if dynamic_inflow {
        names.extend(INFLOW_STATES.iter().map(|s| s.to_string()));
    }
    if engine {
        names.push(PROPELLER_STATE.to_string());
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aircraft::linearise::linearise;
    use crate::testdata::{sea_level_air as air, trimmed_gyroplane};

    /// Eliminating the flapping, inflow and propeller states of the averaged model at their
    /// equilibrium gives back the quasi-static linearisation: the two are one physics, held
    /// differently. What the constant-coefficient approximation leaves out (the teeter's higher
    /// harmonics, the periodic coefficients' products) shows as at most 1.1 % of a row's
    /// largest derivative (L_q); 2 % is allowed.
    #[test]
    fn eliminating_the_flapping_gives_back_the_quasi_static_linearisation() {
        let (a, t) = trimmed_gyroplane(31.3);
        let wf = with_flapping(&a, &t, air(), Steps::default()).unwrap();
        let qs = wf.quasi_static().unwrap();
        let lin = linearise(&a, &t, air(), Steps::default()).unwrap();
        assert_eq!(qs.states(), lin.model.states());
        let (a1, a2) = (lin.model.a(), qs.a());
        let (b1, b2) = (lin.model.b(), qs.b());
        for i in 0..10 {
            let scale = (0..10).map(|j| a1[(i, j)].abs()).fold(0.0, f64::max);
            for j in 0..10 {
                let d = (a1[(i, j)] - a2[(i, j)]).abs();
                assert!(
                    d <= 0.02 * scale + 1e-6,
                    "A[{},{}]: {} quasi-static, {} averaged",
                    STATES[i],
                    STATES[j],
                    a1[(i, j)],
                    a2[(i, j)]
                );
            }
            let scale = (0..4).map(|j| b1[(i, j)].abs()).fold(0.0, f64::max);
            for j in 0..4 {
                let d = (b1[(i, j)] - b2[(i, j)]).abs();
                assert!(d <= 0.02 * scale + 1e-9, "B[{},{}]", STATES[i], CONTROLS[j]);
            }
        }
    }

    /// The averaged model's equilibrium tilts the tip-path plane as the full model's blades
    /// flap, free, after three revolutions from the trim's flapping (`beta_1c = -a1`,
    /// `beta_1s = -b1`, within 0.5 %), and leaves the body accelerating as the full model's
    /// mean over the next revolution does (the approximation's residual: within 2e-3 m/s^2,
    /// rad/s^2 and rad/s^2 of rotorspeed, a quarter of the shake's mean below). The full model
    /// flies the aircraft [`with_flapping`] differences, the propeller on its map. Its free motion is not the trim's
    /// periodic solution: the two-bladed rotor's inertia turns with it and shakes the body
    /// twice a revolution, and the blades feel that shake through their flap inertia (`I
    /// w'.t`), at their own resonance. Measured: `b1` 1.7 % above the trim's in both (the
    /// equilibrium within 0.1 % of the full model's), the roll acceleration's mean 8.5e-3
    /// rad/s^2 in the full model's fourth revolution, the equilibrium's residual within 6e-4 of
    /// every mean.
    #[test]
    fn the_equilibrium_is_the_full_models_free_first_harmonic() {
        let (a, t) = trimmed_gyroplane(31.3);
        let e = with_flapping(&a, &t, air(), Steps::default())
            .unwrap()
            .equilibrium;
        let mapped = a.with_propeller_map();
        let x = mapped.full_state(&t.state, &t.controls, air(), t.averaged.flap_start);
        let deriv = |x: &FullState| mapped.derivatives(x, &t.controls, air()).unwrap();
        let (mean, [_, a1, b1], ..) =
            crate::aircraft::tests::full_revolution(&mapped, x, 3, &deriv);
        assert!(
            (e.beta_1c_rad + a1).abs() < 5e-3 * a1.abs(),
            "{e:?} a1 {a1}"
        );
        assert!(
            (e.beta_1s_rad + b1).abs() < 5e-3 * b1.abs(),
            "{e:?} b1 {b1}"
        );
        // The residual's rates: the rigid body's six, then (after the three attitudes) the
        // rotorspeed's; the full model's mean has the same, the rotorspeed's last.
        let full: Vec<f64> = mean[..6]
            .iter()
            .chain(&[0.0; 3])
            .chain(&mean[6..])
            .copied()
            .collect();
        assert!(
            e.residual
                .iter()
                .zip(&full)
                .all(|(v, f)| (v - f).abs() < 2e-3),
            "{:?} against the full model's {full:?}",
            e.residual
        );
    }

    /// The blades' flap damping: with the body and inflow held, the teeter's two coordinates
    /// decay at `gamma Omega / 16` each, the Lock number's (Johnson, Helicopter Theory, ch. 9)
    /// over the blade's lifting span (tip loss `B` and root cut-out `x_r`: a factor `B^4 -
    /// x_r^4`): the flap block's trace is `-(gamma Omega / 8) (B^4 - x_r^4)` within 2 % (the
    /// blade element's local inflow angle; measured 0.3 % at 31 m/s).
    #[test]
    fn the_flap_block_has_the_lock_number_s_damping() {
        let (a, t) = trimmed_gyroplane(31.3);
        let wf = with_flapping(&a, &t, air(), Steps::default()).unwrap();
        let m = wf.model.a();
        let trace = m[(10, 10)] + m[(11, 11)];
        let rotor = &a.main_rotor.rotor;
        let x_r = rotor.root_cutout_m / rotor.radius_m;
        let span = rotor.tip_loss_factor.powi(4) - x_r.powi(4);
        let want = -rotor.lock_number(air().density_kg_m3) * t.state.rotor_omega_rad_s / 8.0 * span;
        assert!((trace / want - 1.0).abs() < 0.02, "{trace} against {want}");
    }

    /// Harmonic balance against a periodic system solved in closed form: `x' = (a0 - k Omega
    /// sin(Omega t)) x + u` has the fundamental solution `exp(a0 t + k cos(Omega t))`, so its
    /// baseband response is `sum_m (-1)^m I_m(k)^2 / (i (omega + m Omega) - a0)` (modified
    /// Bessel functions). With constant coefficients it is `(i omega I - A)^-1 B`.
    /// The Hessenberg reduction's response is the harmonic balance's, solved whole by LU, at
    /// every frequency (a coupled periodic system of three states and two controls whose
    /// coefficients carry harmonics up to 3/rev), to 1e-10 of its size.
    #[test]
    fn the_hessenberg_reduction_solves_the_harmonic_balance() {
        let (nz, m, samples, big_omega, harmonics) = (3, 2, 16, 25.0, 3usize);
        let at = |j: usize, r: usize, c: usize, salt: f64| {
            let psi = 2.0 * PI * j as f64 / samples as f64;
            let base = ((r * 7 + c * 3) as f64 + salt).sin();
            base + 0.4 * (psi + r as f64).cos()
                - 0.2 * (3.0 * psi + c as f64).sin()
                - if r == c { 2.0 } else { 0.0 }
        };
        let p = Periodic {
            omega_rad_s: big_omega,
            a_at: (0..samples)
                .map(|j| DMatrix::from_fn(nz, nz, |r, c| at(j, r, c, 0.3)))
                .collect(),
            b_at: (0..samples)
                .map(|j| DMatrix::from_fn(nz, m, |r, c| at(j, r, c, 1.7)))
                .collect(),
        };
        let h = harmonics as i64;
        let blocks = 2 * harmonics + 1;
        let direct = |omega: f64| {
            let mut big = DMatrix::<Complex<f64>>::zeros(blocks * nz, blocks * nz);
            let mut rhs = DMatrix::<Complex<f64>>::zeros(blocks * nz, m);
            for (bi, n) in (-h..=h).enumerate() {
                for (bj, q) in (-h..=h).enumerate() {
                    let coupling = Periodic::harmonic(&p.a_at, n - q);
                    big.view_mut((bi * nz, bj * nz), (nz, nz))
                        .copy_from(&(-coupling));
                }
                for i in 0..nz {
                    big[(bi * nz + i, bi * nz + i)] +=
                        Complex::new(0.0, omega + n as f64 * big_omega);
                }
                rhs.view_mut((bi * nz, 0), (nz, m))
                    .copy_from(&Periodic::harmonic(&p.b_at, n));
            }
            let x = big.lu().solve(&rhs).unwrap();
            x.view((harmonics * nz, 0), (nz, m)).into_owned()
        };
        let reduced = p.baseband(harmonics).unwrap();
        for omega in [0.1, 1.0, 3.7, 12.5, 24.0, 60.0] {
            let (want, got) = (direct(omega), reduced.at(omega).unwrap());
            let miss = (&got - &want).norm() / want.norm();
            assert!(miss < 1e-10, "at {omega} rad/s: {miss:e}");
        }
    }

    #[test]
    fn harmonic_balance_finds_a_periodic_system_s_baseband_response() {
        let (a0, k, big_omega) = (-3.0, 0.8, 40.0);
        let samples = 32;
        let p = Periodic {
            omega_rad_s: big_omega,
            a_at: (0..samples)
                .map(|j| {
                    let psi = 2.0 * PI * j as f64 / samples as f64;
                    DMatrix::from_element(1, 1, a0 - k * big_omega * psi.sin())
                })
                .collect(),
            b_at: vec![DMatrix::from_element(1, 1, 1.0); samples],
        };
        let bessel_i = |m: i32, x: f64| -> f64 {
            let m = m.unsigned_abs() as i32;
            let mut term = (x / 2.0).powi(m) / (1..=m).map(f64::from).product::<f64>();
            let mut sum = term;
            for j in 1..40 {
                term *= (x / 2.0).powi(2) / (f64::from(j) * f64::from(j + m));
                sum += term;
            }
            sum
        };
        for omega in [0.5, 3.0, 12.0] {
            let want: Complex<f64> = (-12..=12)
                .map(|m: i32| {
                    let c = if m % 2 == 0 { 1.0 } else { -1.0 } * bessel_i(m, k).powi(2);
                    Complex::new(c, 0.0) / Complex::new(-a0, omega + f64::from(m) * big_omega)
                })
                .sum();
            let got = p.baseband_response(omega, 8).unwrap()[(0, 0)];
            assert!(
                (got - want).norm() < 1e-9 * want.norm(),
                "{omega}: {got} against {want}"
            );
            let first = p.baseband_response(omega, 0).unwrap()[(0, 0)];
            let lti = Complex::new(1.0, 0.0) / Complex::new(-a0, omega);
            assert!((first - lti).norm() < 1e-12, "{first} against {lti}");
        }
        assert_eq!(
            Periodic {
                omega_rad_s: 1.0,
                a_at: vec![DMatrix::zeros(2, 2)],
                b_at: vec![DMatrix::zeros(2, 1)],
            }
            .baseband_response(1.0, 2),
            Err(PeriodicError::Shape)
        );
    }

    /// A hinged rotor is refused with a reason, not linearised wrongly.
    #[test]
    fn only_a_teetering_hub_is_supported() {
        let (mut a, t) = trimmed_gyroplane(31.3);
        a.main_rotor.rotor.hub = Hub::Articulated;
        let e = with_flapping(&a, &t, air(), Steps::default()).unwrap_err();
        assert!(e.to_string().contains("teetering"), "{e}");
    }
}
