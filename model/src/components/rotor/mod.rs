//! The rotor: individual rigid blades, each flapping about an (optionally offset, optionally
//! sprung) hinge, with aerodynamic loads from blade elements and inflow from the
//! Peters-HaQuang model (seed 001 Eqs. 2-9, seed 003 Eqs. 1-12). One module serves a main
//! rotor and a propeller (seed 000 Sec. III).
//!
//! # Hub axes and azimuth
//! Hub axes: `x` forward, `y` to starboard, `z` down along the shaft. The rotor turns
//! anticlockwise seen from above (angular velocity along `-z`). Blade azimuth `psi` is zero
//! with the blade over the tail (pointing along `-x`) and increases in the direction of
//! rotation, so the blade advances at `psi = 90 deg` (starboard). The unflapped blade points
//! along `r(psi) = (-cos psi, sin psi, 0)` and moves along `t(psi) = (sin psi, cos psi, 0)`.
//! Flap `beta` is positive up (towards `-z`).
//!
//! # Element velocities and loads
//! For an element at distance `rho` from the hinge (hinge at `e` from the shaft), the velocity
//! relative to the air is built from the hub velocity, rotation, flapping and the induced
//! velocity (positive down, `v_i = v0 + (r/R)(v1s sin psi + v1c cos psi)`), without small-angle
//! approximations. `U_T` is its component along the direction of motion, `U_P` the downward
//! flow through the element normal to the flapped blade (seed 003 Eqs. 8-9), the inflow angle
//! is `phi = atan2(U_P, U_T)` and the angle of attack `alpha = theta - phi` (Eq. 10). Lift is
//! normal to the local flow in the plane of `U_T` and `U_P` and depends on them alone (the
//! independence principle for a yawed section). Drag is parallel to that flow, with its dynamic
//! pressure; with [`Rotor::yawed_flow_drag`] it acts instead along the whole relative flow,
//! including its component `U_R` along the flapped blade, with the dynamic pressure of
//! `U_T^2 + U_P^2 + U_R^2` (yawed-flow profile drag: the profile power of a rotor in forward
//! flight grows about as `1 + 4.6 mu^2` rather than `1 + 3 mu^2`; Johnson, Helicopter Theory,
//! 1980, ch. 5). The radial drag loads the hub along the blade and turns nothing about the shaft.
//!
//! The empirical [`Corrections`] act here: the section drag coefficient is scaled and
//! incremented, a pitch offset is added to every element's pitch, and a lateral inflow offset to
//! `v1s` (on top of the inflow model's state, which is not changed by it). The drag can also
//! depend on the element's chord Reynolds number `Re = w c / nu`, as `(Re / Re_ref)^-n`
//! ([`Corrections::profile_drag_reynolds_exponent`], [`Rotor::drag_reynolds_number`]), with the
//! air's kinematic viscosity `nu` from Sutherland's law at the temperature the operating
//! condition's speed of sound gives.
//!
//! # Steady periodic solution
//! In a steady condition every blade flies the same periodic motion, shifted by `2 pi / N_b`.
//! One blade is integrated in azimuth (fourth-order Runge-Kutta at a fixed azimuth step) from a
//! warm start until its flapping is periodic, and the rotor's mean forces and moments are `N_b`
//! times that blade's average over a revolution: exact for the mean, since the mean of a
//! periodic blade's inertial loads is zero. The blades' weight and the hub's acceleration act on
//! their flapping through their first mass moment about the hinge (below); the blades' weight on
//! the hub is the aircraft's, not the rotor's load.
//!
//! # The blades' weight and the hub's acceleration
//! The hub centre accelerates at `a_hub`, and the hub's axes (the non-rotating shaft frame) turn
//! at `w` with angular acceleration `w'`. An element `dm` of a blade, at `p = e r + rho e_b` from
//! the hub centre (`e` the hinge offset, `r` the unflapped blade's direction, `e_b` the flapped
//! blade's, `rho` from the hinge), weighs `g dm` and has, besides its motion relative to the
//! hub's axes, the acceleration `a_hub + w' x p + w x (w x p)`. A force `F` at `rho` along the
//! blade turns it about the hinge, flapping up, by `rho F.n`, `n = d e_b / d beta =
//! (sin b cos psi, -sin b sin psi, -cos b)`. With `r x n = -cos b t` and `e_b x n = -t`
//! (`t = (sin psi, cos psi, 0)`, the direction of motion), the weight and these accelerations
//! turn the blade about its hinge by (derived here)
//!
//! ```text
//! int rho (g - a_hub - w' x p - w x (w x p)).n dm
//!   = S (g - a_hub).n + (e S cos b + I) w'.t - [the w x (w x p) terms]
//! ```
//!
//! with `S` and `I` the blade's first and second mass moments about the hinge. The `w x (w x p)`
//! terms are the hub rotation's centripetal terms of [`Blade::inertial_flap_moment`]. What acts
//! through `S` is the apparent gravity at the hinge, `f = g - a_hub - w' x (e r)`, from the
//! operating condition's `g - a_hub` and `w'` in hub axes ([`Operating::apparent_gravity_m_s2`],
//! [`Operating::hub_angular_acceleration_rad_s2`]; how the aircraft finds them is in
//! [`crate::aircraft`]). The blade's own inertia under the hub's angular acceleration, `I w'.t`,
//! does not act through `S` (it vanishes in steady flight; tested against D'Alembert's
//! principle summed over a blade). A uniform blade
//! of mass `m` hinged on the axis has `S = m R / 2` and `I = m R^2 / 3`, so that in hover its
//! weight droops it by `S g / (I Omega^2) = 3 g / (2 Omega^2 R)` (tested).
//!
//! A teetering pair (blades at `precone +- delta`, half a revolution apart, on a hinge on the
//! axis) turns about the teeter hinge by blade 1's moment less blade 2's, `S f.(n_1 - n_2)` with
//! `n_1 - n_2 = 2 sin(precone) (cos delta cos psi, -cos delta sin psi, sin delta)`. Without
//! precone the pair's weights and the hub's acceleration cancel about the hinge exactly. With
//! it, the coned pair's mass centre sits above the hinge (a first moment `2 S sin(precone)`
//! along the shaft; the model has no undersling, which would take `2 m u` from it): the
//! apparent gravity across the shaft forces the teeter once per revolution, and along the
//! shaft it softens the teeter's centrifugal stiffness (both tested). The pair's `I w'.t`
//! terms add: a roll or pitch acceleration of the hub teeters the pair even without precone.
//!
//! # The hub's own drag
//! The hub, blade-root fittings and spindle head are bluff bodies in the free stream. Their
//! drag is an equivalent flat-plate area `f` ([`Rotor::hub_drag_area_m2`]): a force
//! `-(rho/2) f |V| V` at the hub centre, `V` the hub's velocity through the air (the parasite
//! drag of Hoerner, Fluid-Dynamic Drag, 1965, ch. 13 and 14; Johnson, Helicopter Theory, 1980,
//! ch. 6). It is the hub's, not the blades': it is left out of the rotor's loads
//! ([`SteadyLoads`], which drive the inflow and the flapping) and added by whoever puts the
//! rotor on a body ([`Rotor::hub_drag_n`]: the aircraft, the tunnel's balance). The induced
//! velocity through the disc does not reach it (the hub sits at the disc's centre, in the
//! free stream's flow past it; its own wake is left out).

use crate::components::airfoil::{Airfoil, AirfoilError};
use serde::Serialize;
use std::f64::consts::PI;
use thiserror::Error;

mod blade;
mod corrections;
mod loads;
mod steady;
#[cfg(test)]
mod tests;

pub use blade::Blade;
pub use corrections::{Corrections, elastic_twist_rad};
pub use loads::BladeLoads;
pub use steady::{RevolutionMap, SteadyLoads};

/// A spanwise distribution: linear interpolation in `r/R` between stations (a repeated
/// station gives a step). Values outside the stations are held at the end values.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Distribution {
    pub stations_r_over_r: Vec<f64>,
    pub values: Vec<f64>,
}

impl Distribution {
    /// A constant distribution.
    pub fn constant(v: f64) -> Self {
        Self {
            stations_r_over_r: vec![0.0, 1.0],
            values: vec![v, v],
        }
    }

    /// The value at `x = r/R`; at a step, the outboard value.
    pub fn at(&self, x: f64) -> f64 {
        let s = &self.stations_r_over_r;
        let v = &self.values;
        if x <= s[0] {
            return v[0];
        }
        for i in 0..s.len() - 1 {
            if x < s[i + 1] {
                let w = s[i + 1] - s[i];
                return if w > 0.0 {
                    v[i] + (v[i + 1] - v[i]) * (x - s[i]) / w
                } else {
                    v[i + 1]
                };
            }
        }
        v[v.len() - 1]
    }

    fn validate(&self, name: &'static str) -> Result<(), RotorError> {
        let s = &self.stations_r_over_r;
        let ok = s.len() >= 2
            && s.len() == self.values.len()
            && s.windows(2).all(|w| w[1] >= w[0])
            && s.iter().chain(&self.values).all(|x| x.is_finite());
        if ok {
            Ok(())
        } else {
            Err(RotorError::Distribution(name))
        }
    }
}

/// How the induced velocity is obtained.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum InflowModel {
    /// Peters-HaQuang, uniform and first harmonics (seed 001 Eqs. 2-5).
    PetersHaQuang { wake: WakeModel },
    /// Peters-HaQuang with the harmonics set to zero (seed 001 Fig. 4).
    UniformOnly { wake: WakeModel },
    /// Given components (m/s), for verification against closed-form theory.
    Prescribed { v0: f64, v1s: f64, v1c: f64 },
}

/// The wake skew angle `chi` from the hub's in-plane speed `V` and the flow through the disc
/// `d = v_i0m - w_hub` (down positive). All three agree when the flow is down through the disc
/// (`d > 0`, a helicopter's rotor); they part when it is up (`d < 0`, autorotation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SkewConvention {
    /// Seed 001 Eq. 15: `chi = atan(V / d)` on the principal branch, so `chi < 0` in
    /// autorotation, as seed 001's text after Eq. 15 says. Discontinuous where the flow through
    /// the disc changes direction: `chi` jumps from +90 deg (`d` just above 0) to -90 deg (just
    /// below), and `tan(chi/2)` from +1 to -1, a trap for Newton and for finite differences
    /// there (tested).
    Signed,
    /// Seed 003 Eq. 5 as Chen presents it, the wake's geometric angle: `chi = atan2(V, d)` in
    /// `[0, 180 deg]`, above 90 deg when the wake skews above the disc (seed 003's closing
    /// discussion). Continuous where the flow changes direction (through 90 deg); singular as
    /// the flow turns straight up (`V = 0`, `d < 0`: vertical autorotative descent), where
    /// `tan(chi/2)` and `1 / (1 + cos chi)` diverge, so not for axial descent.
    Geometric,
    /// Seed 003 Eq. 6, Peters and HaQuang's disc angle: `tan alpha = |d| / V`,
    /// `chi = 90 deg - alpha`, in `[0, 90 deg]`. Continuous everywhere (a kink at `d = 0`); the
    /// form seed 003 finds agrees best with the longitudinal inflow from flight flapping
    /// (its Fig. 5).
    Modulus,
}

/// How the inflow model forms its wake: the skew angle and the mass flow in descent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct WakeModel {
    pub skew: SkewConvention,
    pub descent: DescentInflow,
}

impl WakeModel {
    /// Seed 001's wake: the signed skew and momentum theory throughout.
    pub const SEED_001: Self = Self {
        skew: SkewConvention::Signed,
        descent: DescentInflow::Momentum,
    };
}

/// How the wake's mass flow is formed where the rotor descends into its own wake (between
/// hover and the windmill-brake state, the vortex-ring and turbulent-wake states), where
/// momentum theory has no physical solution. See [`crate::components::inflow`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum DescentInflow {
    /// Momentum theory throughout, as Peters and HaQuang publish it. In those states its mass
    /// flow parameter `v_m` can fall to zero and below (negative inflow time constants), and
    /// an axial descent between `0` and `2 v_h` has no equilibrium but a rotor with almost no
    /// flow through it.
    Momentum,
    /// Johnson's empirical induced velocity for axial descent (Helicopter Theory, 1980),
    /// blended into the mass flow below an in-plane speed of `v_h`.
    Johnson,
}

/// How the blades are attached.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Hub {
    /// Each blade flaps on its own hinge (offset, spring and precone as given).
    Articulated,
    /// Two blades on a teeter bar: one teeter angle, the blades at `precone +- teeter` (the
    /// light-gyroplane rotor of seeds 000-003). Coning is the precone: elastic coning is not
    /// modelled.
    Teetering,
    /// No flapping: the blades stay at the precone (a propeller).
    Rigid,
}

/// A rotor's data.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Rotor {
    pub hub: Hub,
    pub blades: usize,
    pub radius_m: f64,
    /// Start of the aerodynamic span, from the shaft axis.
    pub root_cutout_m: f64,
    pub hinge_offset_m: f64,
    pub chord_m: Distribution,
    /// Blade pitch against `r/R`, rad (twist included), before any collective shift.
    pub pitch_rad: Distribution,
    /// The station (`r/R`) at which a collective or pitch setting is defined.
    pub pitch_reference_r_over_r: f64,
    /// Flap moment of inertia about the hinge.
    pub flap_inertia_kg_m2: f64,
    /// First mass moment of the blade about the hinge (enters with hinge offset).
    pub flap_mass_moment_kg_m: f64,
    pub flap_spring_n_m_per_rad: f64,
    /// Neutral angle of the flap spring (precone).
    pub precone_rad: f64,
    /// Lift is zero outboard of `B R` (Prandtl's tip loss in its simple form).
    pub tip_loss_factor: f64,
    pub airfoil: Airfoil,
    /// Number of blade elements carrying lift (a drag-only tip strip is added when `B < 1`).
    pub elements: usize,
    pub corrections: Corrections,
    /// Yawed-flow profile drag: section drag along the whole relative flow, the component
    /// along the blade included (see the module's docs). Off, drag sees `U_T` and `U_P` only.
    pub yawed_flow_drag: bool,
    /// The hub's drag as an equivalent flat-plate area, m^2 (see the module's docs): zero, no
    /// hub drag.
    pub hub_drag_area_m2: f64,
    /// The chord Reynolds number at which the airfoil's drag coefficients hold, when the rotor
    /// file gives one: the reference of [`Corrections::profile_drag_reynolds_exponent`], which
    /// needs it.
    pub drag_reynolds_number: Option<f64>,
}

/// The most blades a rotor may have. Rotors and propellers flown have 2 to 8 (the Mi-26's
/// rotor, the A400M's propellers); 64 is eight times that. A blade count sizes the full
/// model's state (two flap states a blade): a mistyped one must be refused, not allocated.
pub const MAX_BLADES: usize = 64;

/// The most lifting elements a blade may have. Blade-element codes use 10 to 100 (RASCAL up
/// to 20, seed 000 Sec. III; the shipped rotors 8 to 20); 1000 is ten times the finest. The
/// count sizes the blade's element table and the work of every evaluation: `elements:
/// 999999999999` once aborted the process on the allocation.
pub const MAX_ELEMENTS_PER_BLADE: usize = 1000;

/// The most blade elements a rotor may have, blades times elements: the work of every
/// evaluation of its loads. Rotors flown have 2 to 8 blades, blade-element codes 10 to 100
/// elements (at most 800); the numerical uncertainty doubles the elements (1,600). Each count
/// alone within its limit, 64 blades of 100 elements (6,400) took 6 s for an autorotation to
/// give up.
pub const MAX_BLADE_ELEMENTS: usize = 2_000;

/// The most blade-element evaluations one revolution may take, blades times elements times
/// azimuth steps: the shipped rotors at 5 deg take 2 x 20 x 72 = 2,880, the numerical
/// uncertainty's refinement of a three-bladed rotor at the finest step 3 x 40 x 7,200 = 864,000.
pub const MAX_ELEMENT_STEPS_PER_REVOLUTION: usize = 2_000_000;

/// The most azimuth steps a revolution may take (the finest step, 0.05 deg). The shipped
/// aircraft step 5 deg and the default is 2.5 deg (72 and 144 steps); the numerical
/// uncertainty halves a file's step, whose finest is 0.1 deg. Beyond it a tiny step would make
/// one revolution's integration run without end.
pub const MAX_AZIMUTH_STEPS_PER_REVOLUTION: usize = 7200;

/// Rotor data or conditions that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RotorError {
    #[error("{name} must be {requirement}, got {value}")]
    Invalid {
        name: &'static str,
        requirement: &'static str,
        value: f64,
    },
    #[error("{name} must be at most {limit} ({why}), got {value}")]
    TooMany {
        name: &'static str,
        limit: usize,
        why: &'static str,
        value: f64,
    },
    #[error(
        "the solve's blade solutions reached their limit of {limit} revolutions in all, without an answer"
    )]
    RevolutionLimit { limit: usize },
    #[error("distribution `{0}` needs at least two rising stations, as many values, all finite")]
    Distribution(&'static str),
    #[error(transparent)]
    Airfoil(#[from] AirfoilError),
    #[error(
        "the flapping did not become periodic within {revolutions} revolutions (last change {change:e} rad): the blade is unstable or the azimuth step too large"
    )]
    FlapNotPeriodic { revolutions: usize, change: f64 },
    #[error("non-finite {0} in the blade solution")]
    NonFinite(&'static str),
    #[error(
        "the periodic flapping reaches {largest_deg:.1} deg (coning {coning_deg:.1} deg): past the vertical the blades no longer form a disc, outside the model"
    )]
    FlapPastVertical { largest_deg: f64, coning_deg: f64 },
}

/// The azimuth steps of one revolution at a step of `step_rad` (at least 8), or an error for a
/// step that is not positive or would take more than [`MAX_AZIMUTH_STEPS_PER_REVOLUTION`].
pub fn azimuth_steps(step_rad: f64) -> Result<usize, RotorError> {
    let n = (2.0 * PI / step_rad).round().max(8.0);
    if !(step_rad > 0.0 && n.is_finite()) {
        return Err(RotorError::Invalid {
            name: "azimuth_step_rad",
            requirement: "positive and finite",
            value: step_rad,
        });
    }
    if n > MAX_AZIMUTH_STEPS_PER_REVOLUTION as f64 {
        return Err(RotorError::TooMany {
            name: "azimuth steps per revolution",
            limit: MAX_AZIMUTH_STEPS_PER_REVOLUTION,
            why: "MAX_AZIMUTH_STEPS_PER_REVOLUTION: a step of 0.05 deg",
            value: n,
        });
    }
    Ok(n as usize)
}

fn positive(name: &'static str, value: f64) -> Result<(), RotorError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(RotorError::Invalid {
            name,
            requirement: "positive and finite",
            value,
        })
    }
}

fn non_negative(name: &'static str, value: f64) -> Result<(), RotorError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(RotorError::Invalid {
            name,
            requirement: "non-negative and finite",
            value,
        })
    }
}

/// One blade element.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Element {
    /// Distance from the hinge along the blade, m.
    rho: f64,
    /// Width, m.
    dr: f64,
    chord: f64,
    /// Pitch before the collective shift, rad.
    pitch: f64,
    /// 1 where the element carries lift, 0 in the tip-loss strip.
    lift: f64,
}

/// The hub's motion through the air, in hub axes (m/s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct HubVelocity {
    pub u: f64,
    pub v: f64,
    pub w: f64,
}

/// Induced velocity components in hub axes, m/s (positive down).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct Inflow {
    pub v0: f64,
    pub v1s: f64,
    pub v1c: f64,
}

/// Operating state of the rotor for a steady solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Operating {
    pub omega_rad_s: f64,
    pub hub: HubVelocity,
    pub inflow: Inflow,
    pub density_kg_m3: f64,
    pub speed_of_sound_m_s: f64,
    /// Added to the blade pitch everywhere, rad.
    pub collective_shift_rad: f64,
    /// Angular velocity of the hub (the non-rotating shaft frame) in hub axes, rad/s: the
    /// body's rates seen along the hub axes. Zero in a wind tunnel; constant in a steady turn.
    pub hub_rates_rad_s: [f64; 3],
    /// The apparent gravity at the hub, hub axes, m/s^2: gravity less the hub centre's
    /// acceleration, `g - a_hub` (minus what an accelerometer at the hub reads). `[0, 0, g]`
    /// with the shaft upright in unaccelerated flight; about `n g` in a turn at load factor `n`.
    /// It acts on the blades' flapping through their first mass moment (see the module's docs).
    /// Zero: weightless blades, or a hub in free fall.
    pub apparent_gravity_m_s2: [f64; 3],
    /// The hub's angular acceleration, hub axes, rad/s^2: it acts on a blade's own flap inertia
    /// (`I w'.t`), and through its first mass moment and the hinge offset it accelerates the
    /// hinge (see the module's docs). Zero in steady motion (a tunnel, a trim).
    pub hub_angular_acceleration_rad_s2: [f64; 3],
}

/// Numerical settings of the blade integration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Numerics {
    /// Azimuth step of the integration, rad.
    pub azimuth_step_rad: f64,
    /// Periodicity tolerance on the flap state (rad, and rad per rad of azimuth): the
    /// periodic state is found to about this, and the revolution whose loads are taken closes
    /// to `steady::SAMPLED_CLOSURE` of it.
    pub periodic_tolerance: f64,
    pub max_revolutions: usize,
}

impl Default for Numerics {
    fn default() -> Self {
        Self {
            azimuth_step_rad: 2.5f64.to_radians(),
            periodic_tolerance: 1e-11,
            max_revolutions: 200,
        }
    }
}

impl Rotor {
    /// The hub's drag, hub axes, N: `-(rho/2) f |V| V` for a hub moving at `hub` through air of
    /// density `density_kg_m3` (the module's docs). Acts at the hub centre.
    pub fn hub_drag_n(&self, density_kg_m3: f64, hub: HubVelocity) -> [f64; 3] {
        let f = self.hub_drag_area_m2;
        if f == 0.0 {
            return [0.0; 3];
        }
        let speed = (hub.u * hub.u + hub.v * hub.v + hub.w * hub.w).sqrt();
        let k = -0.5 * density_kg_m3 * f * speed;
        [k * hub.u, k * hub.v, k * hub.w]
    }

    /// Checks every number of the rotor.
    pub fn validate(&self) -> Result<(), RotorError> {
        if self.blades == 0 {
            return Err(RotorError::Invalid {
                name: "blades",
                requirement: "at least 1",
                value: 0.0,
            });
        }
        if self.elements == 0 {
            return Err(RotorError::Invalid {
                name: "elements",
                requirement: "at least 1",
                value: 0.0,
            });
        }
        self.validate_counts()?;
        positive("radius_m", self.radius_m)?;
        positive("flap_inertia_kg_m2", self.flap_inertia_kg_m2)?;
        if self.hub == Hub::Teetering && (self.blades != 2 || self.hinge_offset_m != 0.0) {
            return Err(RotorError::Invalid {
                name: "blades",
                requirement: "2, with a zero hinge offset, for a teetering hub",
                value: self.blades as f64,
            });
        }
        non_negative("hinge_offset_m", self.hinge_offset_m)?;
        non_negative("root_cutout_m", self.root_cutout_m)?;
        non_negative("flap_mass_moment_kg_m", self.flap_mass_moment_kg_m)?;
        non_negative("flap_spring_n_m_per_rad", self.flap_spring_n_m_per_rad)?;
        non_negative("hub_drag_area_m2", self.hub_drag_area_m2)?;
        if let Some(re) = self.drag_reynolds_number {
            positive("drag_reynolds_number", re)?;
        }
        let n = self.corrections.profile_drag_reynolds_exponent;
        if !(0.0..=1.0).contains(&n) {
            return Err(RotorError::Invalid {
                name: "corrections.profile_drag_reynolds_exponent",
                requirement: "in [0, 1]",
                value: n,
            });
        }
        if n != 0.0 && self.drag_reynolds_number.is_none() {
            return Err(RotorError::Invalid {
                name: "corrections.profile_drag_reynolds_exponent",
                requirement: "zero unless the rotor gives drag_reynolds_number (the Reynolds number its section drag holds at)",
                value: n,
            });
        }
        positive(
            "corrections.profile_drag_scale",
            self.corrections.profile_drag_scale,
        )?;
        for (name, value) in [
            (
                "corrections.profile_drag_increment",
                self.corrections.profile_drag_increment,
            ),
            (
                "corrections.pitch_offset_rad",
                self.corrections.pitch_offset_rad,
            ),
            (
                "corrections.lateral_inflow_offset_m_s",
                self.corrections.lateral_inflow_offset_m_s,
            ),
            (
                "corrections.elastic_twist_rad_per_pa",
                self.corrections.elastic_twist_rad_per_pa,
            ),
        ] {
            if !value.is_finite() {
                return Err(RotorError::Invalid {
                    name,
                    requirement: "finite",
                    value,
                });
            }
        }
        if !self.precone_rad.is_finite() {
            return Err(RotorError::Invalid {
                name: "precone_rad",
                requirement: "finite",
                value: self.precone_rad,
            });
        }
        if !(self.tip_loss_factor > 0.5 && self.tip_loss_factor <= 1.0) {
            return Err(RotorError::Invalid {
                name: "tip_loss_factor",
                requirement: "in (0.5, 1]",
                value: self.tip_loss_factor,
            });
        }
        let lift_end = self.tip_loss_factor * self.radius_m;
        if self.root_cutout_m.max(self.hinge_offset_m) >= lift_end {
            return Err(RotorError::Invalid {
                name: "root_cutout_m",
                requirement: "inboard of the hinge offset and the tip-loss radius",
                value: self.root_cutout_m,
            });
        }
        if !(0.0..=1.0).contains(&self.pitch_reference_r_over_r) {
            return Err(RotorError::Invalid {
                name: "pitch_reference_r_over_r",
                requirement: "in [0, 1]",
                value: self.pitch_reference_r_over_r,
            });
        }
        self.validate_distributions()?;
        self.airfoil.validate()?;
        Ok(())
    }

    /// The chord and pitch along the blade: each a distribution, the chord positive and the
    /// pitch short of edge-on.
    fn validate_distributions(&self) -> Result<(), RotorError> {
        self.chord_m.validate("chord_m")?;
        self.pitch_rad.validate("pitch_rad")?;
        if self.chord_m.values.iter().any(|c| *c <= 0.0) {
            return Err(RotorError::Distribution("chord_m"));
        }
        if let Some(p) = self.pitch_rad.values.iter().find(|p| p.abs() >= PI / 2.0) {
            return Err(RotorError::Invalid {
                name: "pitch_rad",
                requirement: "within +-pi/2 rad (+-90 deg) at every station: a section turned past edge-on faces the flow backwards",
                value: *p,
            });
        }
        Ok(())
    }

    /// The blade and element counts within [`MAX_BLADES`] and [`MAX_ELEMENTS_PER_BLADE`].
    fn validate_counts(&self) -> Result<(), RotorError> {
        if self.blades > MAX_BLADES {
            return Err(RotorError::TooMany {
                name: "blades",
                limit: MAX_BLADES,
                why: "MAX_BLADES: rotors and propellers flown have 2 to 8",
                value: self.blades as f64,
            });
        }
        if self.elements > MAX_ELEMENTS_PER_BLADE {
            return Err(RotorError::TooMany {
                name: "elements",
                limit: MAX_ELEMENTS_PER_BLADE,
                why: "MAX_ELEMENTS_PER_BLADE: blade-element codes use 10 to 100",
                value: self.elements as f64,
            });
        }
        if self.blades * self.elements > MAX_BLADE_ELEMENTS {
            return Err(RotorError::TooMany {
                name: "blades x elements",
                limit: MAX_BLADE_ELEMENTS,
                why: "MAX_BLADE_ELEMENTS: the work of every evaluation; rotors flown have at most 8 blades of 100 elements, 800",
                value: (self.blades * self.elements) as f64,
            });
        }
        Ok(())
    }

    /// The azimuth steps of one revolution at `step_rad` ([`azimuth_steps`]), the revolution's
    /// blade-element evaluations within [`MAX_ELEMENT_STEPS_PER_REVOLUTION`].
    pub fn steps_per_revolution(&self, step_rad: f64) -> Result<usize, RotorError> {
        let n = azimuth_steps(step_rad)?;
        let work = self.blades * self.elements * n;
        if work > MAX_ELEMENT_STEPS_PER_REVOLUTION {
            return Err(RotorError::TooMany {
                name: "blades x elements x azimuth steps per revolution",
                limit: MAX_ELEMENT_STEPS_PER_REVOLUTION,
                why: "MAX_ELEMENT_STEPS_PER_REVOLUTION: the work of one revolution; a coarser azimuth step or fewer elements",
                value: work as f64,
            });
        }
        Ok(n)
    }

    /// Solidity `N_b c_mean / (pi R)`, with the area-weighted mean chord over the span.
    pub fn solidity(&self) -> f64 {
        let n = 1000;
        let mean_chord: f64 = (0..n)
            .map(|i| self.chord_m.at((i as f64 + 0.5) / n as f64))
            .sum::<f64>()
            / n as f64;
        self.blades as f64 * mean_chord / (PI * self.radius_m)
    }

    /// One blade's mass, kg, for the hinge-offset and mass-centre terms: the uniform rod's
    /// `m = 4 S^2 / (3 I)` from the flap mass and inertia moments (its centre of mass then at
    /// `S / m = 3 I / (4 S)` from the hinge). Zero without a mass moment.
    pub fn blade_mass_kg(&self) -> f64 {
        let s_m = self.flap_mass_moment_kg_m;
        if s_m > 0.0 {
            4.0 * s_m * s_m / (3.0 * self.flap_inertia_kg_m2)
        } else {
            0.0
        }
    }

    /// Lock number `rho a c R^4 / I_beta` with the chord at 0.75 R.
    pub fn lock_number(&self, density_kg_m3: f64) -> f64 {
        density_kg_m3
            * self.airfoil.lift_slope_per_rad()
            * self.chord_m.at(0.75)
            * self.radius_m.powi(4)
            / self.flap_inertia_kg_m2
    }

    /// The collective shift that sets the pitch at the reference station to `pitch_rad`.
    pub fn collective_shift_for(&self, pitch_rad: f64) -> f64 {
        pitch_rad - self.pitch_rad.at(self.pitch_reference_r_over_r)
    }

    fn elements(&self) -> Vec<Element> {
        let r = self.radius_m;
        let start = self.root_cutout_m.max(self.hinge_offset_m);
        let lift_end = self.tip_loss_factor * r;
        let n = self.elements;
        let dr = (lift_end - start) / n as f64;
        let make = |mid: f64, dr: f64, lift: f64| Element {
            rho: mid - self.hinge_offset_m,
            dr,
            chord: self.chord_m.at(mid / r),
            pitch: self.pitch_rad.at(mid / r),
            lift,
        };
        let mut v: Vec<Element> = (0..n)
            .map(|i| make(start + (i as f64 + 0.5) * dr, dr, 1.0))
            .collect();
        if lift_end < r {
            v.push(make(0.5 * (lift_end + r), r - lift_end, 0.0));
        }
        v
    }
}

/// The sines and cosines of a blade's azimuth and flap angle, computed once and shared by its
/// loads, inertial moment, angular momentum and mass-centre motion.
#[derive(Debug, Clone, Copy)]
pub struct Angles {
    sp: f64,
    cp: f64,
    sb: f64,
    cb: f64,
}

impl Angles {
    /// At azimuth `psi_rad` and flap angle `beta` (rad).
    pub fn new(psi_rad: f64, beta: f64) -> Self {
        Self::at(psi_rad.sin_cos(), beta)
    }

    /// At an azimuth whose sine and cosine are `(sp, cp)`, and flap angle `beta` (rad).
    pub(crate) fn at((sp, cp): (f64, f64), beta: f64) -> Self {
        let (sb, cb) = beta.sin_cos();
        Self { sp, cp, sb, cb }
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
