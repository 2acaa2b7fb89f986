//! The quantities checks compute: one name, unit and meaning for each, written here and nowhere
//! else. Case files name them under `expect`, fit files under `targets`, records and the
//! scoreboard by the same names; the evaluators produce them through [`Quantity::name`], so a
//! misspelt name is a compile error, not a check that never matches.
//!
//! The same physical quantity has the same name whatever computes it: the rotor speed is
//! `rotor_rpm` in a trim and in a wind tunnel, the uniform inflow `inflow_v0_m_s` from an
//! autorotation, a trim or blade flapping. Quantities that differ in convention have different
//! names: `a1_deg`/`b1_deg` are the flapping coefficients of `beta = a0 - a1 cos psi - b1 sin psi`
//! (TR 515 and the model), `beta_1c_deg`/`beta_1s_deg` seed 003's disc tilts.

/// Defines [`Quantity`] with its names, units and meanings.
macro_rules! quantities {
    ($($variant:ident => $name:literal, $unit:literal, $meaning:literal;)+) => {
        /// A quantity a check can compute (see the module docs).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum Quantity {
            $(#[doc = $meaning] $variant,)+
        }

        impl Quantity {
            /// Every quantity, in the order defined.
            pub const ALL: &'static [Quantity] = &[$(Quantity::$variant,)+];

            /// The name as written in case, fit and record files.
            pub const fn name(self) -> &'static str {
                match self {
                    $(Quantity::$variant => $name,)+
                }
            }

            /// The unit (`-` for none).
            pub const fn unit(self) -> &'static str {
                match self {
                    $(Quantity::$variant => $unit,)+
                }
            }

            /// What it is, in a few words.
            pub const fn meaning(self) -> &'static str {
                match self {
                    $(Quantity::$variant => $meaning,)+
                }
            }
        }
    };
}

quantities! {
    // Modes (any linear model).
    EigenvalueRealPerS => "eigenvalue_real_per_s", "1/s", "real part of the mode's eigenvalue";
    EigenvalueImagRadS => "eigenvalue_imag_rad_s", "rad/s", "imaginary part of the mode's eigenvalue";
    DampingRatio => "damping_ratio", "-", "damping ratio";
    NaturalFrequencyRadS => "natural_frequency_rad_s", "rad/s", "undamped natural frequency";
    PeriodS => "period_s", "s", "period of an oscillatory mode";
    TimeToHalfS => "time_to_half_s", "s", "time to half amplitude of a stable mode";
    TimeToDoubleS => "time_to_double_s", "s", "time to double amplitude of an unstable mode";
    // BCAR Section T.
    DampingIndex => "damping_index", "-", "BCAR Section T damping index of the mode";
    BoundaryIndex => "boundary_index", "-", "BCAR Section T boundary's damping index at the mode's period";
    MarginIndex => "margin_index", "-", "damping index above the BCAR boundary (positive complies)";
    MarginRealPerS => "margin_real_per_s", "1/s", "real part to spare before the BCAR boundary";
    // Seed 002's weakly coupled systems (Eqs. 13-25).
    OmegaSpSquared => "omega_sp_squared", "rad^2/s^2", "short-period frequency squared, Z_w M_q - Z_q M_w (seed 002 Eq. 13)";
    Eq13A11 => "eq13_a11", "-", "seed 002 Eq. 13 matrix entry (1,1)";
    Eq13A12 => "eq13_a12", "-", "seed 002 Eq. 13 matrix entry (1,2)";
    Eq13A13 => "eq13_a13", "-", "seed 002 Eq. 13 matrix entry (1,3)";
    Eq13A21 => "eq13_a21", "-", "seed 002 Eq. 13 matrix entry (2,1)";
    Eq13A23 => "eq13_a23", "-", "seed 002 Eq. 13 matrix entry (2,3)";
    Eq13A31 => "eq13_a31", "-", "seed 002 Eq. 13 matrix entry (3,1)";
    Eq13A33 => "eq13_a33", "-", "seed 002 Eq. 13 matrix entry (3,3)";
    SchurA11 => "schur_a11", "-", "exact Schur complement on [u theta Omega], entry (1,1)";
    SchurA12 => "schur_a12", "-", "exact Schur complement on [u theta Omega], entry (1,2)";
    SchurA13 => "schur_a13", "-", "exact Schur complement on [u theta Omega], entry (1,3)";
    SchurA21 => "schur_a21", "-", "exact Schur complement on [u theta Omega], entry (2,1)";
    SchurA22 => "schur_a22", "-", "exact Schur complement on [u theta Omega], entry (2,2)";
    SchurA23 => "schur_a23", "-", "exact Schur complement on [u theta Omega], entry (2,3)";
    SchurA31 => "schur_a31", "-", "exact Schur complement on [u theta Omega], entry (3,1)";
    SchurA32 => "schur_a32", "-", "exact Schur complement on [u theta Omega], entry (3,2)";
    SchurA33 => "schur_a33", "-", "exact Schur complement on [u theta Omega], entry (3,3)";
    CubicA => "cubic_a", "-", "A of the low-frequency cubic (seed 002 Eq. 14)";
    CubicB => "cubic_b", "-", "B of the low-frequency cubic (seed 002 Eq. 14)";
    CubicC => "cubic_c", "-", "C of the low-frequency cubic (seed 002 Eq. 14)";
    DeltaB => "delta_b", "-", "rotorspeed-phugoid coupling term of B (seed 002, after Eq. 19)";
    DeltaC => "delta_c", "-", "rotorspeed-phugoid coupling term of C (seed 002, after Eq. 19)";
    DeltaAPh => "delta_a_ph", "-", "first-order change of the phugoid factor's a_ph (seed 002 Eqs. 17-19)";
    DeltaBPh => "delta_b_ph", "-", "first-order change of the phugoid factor's b_ph (seed 002 Eqs. 17-19)";
    DeltaLambdaOmega => "delta_lambda_omega", "1/s", "first-order change of the rotorspeed root (seed 002 Eqs. 17-19)";
    MOmegaEq24 => "m_omega_eq24", "1/s", "M_Omega = Z_Omega M_w / Z_w (seed 002 Eq. 24)";
    MOmegaEq25 => "m_omega_eq25", "1/s", "M_Omega = M_q Z_Omega / Z_q (seed 002 Eq. 25)";
    // Stability and control derivatives.
    Value => "value", "derivative's own", "the derivative (or ratio of derivatives)";
    Rotor => "rotor", "derivative's own", "the main rotor's part of the derivative";
    Propeller => "propeller", "derivative's own", "the propeller's part of the derivative";
    Airframe => "airframe", "derivative's own", "the airframe's part of the derivative";
    Inertial => "inertial", "derivative's own", "the inertial (gravity and rate) part of the derivative";
    MagnitudeChange => "magnitude_change", "-", "(|corrected| - |uncorrected|) / |uncorrected|";
    // The rotor (in a tunnel, in trim, from flapping).
    RotorRpm => "rotor_rpm", "rpm", "main rotor speed";
    RotorAlphaDeg => "rotor_alpha_deg", "deg", "rotor angle of attack in a tunnel, free stream to the plane normal to the shaft";
    RotorOmegaRadS => "rotor_omega_rad_s", "rad/s", "main rotor speed";
    TipSpeedRatio => "tip_speed_ratio", "-", "advance ratio mu, in-plane speed over tip speed";
    LiftCoefficient => "lift_coefficient", "-", "rotor lift / (rho/2 V^2 pi R^2), TR 515's C_L";
    DragCoefficient => "drag_coefficient", "-", "rotor drag / (rho/2 V^2 pi R^2), TR 515's C_D";
    LiftToDrag => "lift_to_drag", "-", "rotor lift over drag";
    ThrustCoefficient => "thrust_coefficient", "-", "thrust / (rho pi R^2 (Omega R)^2)";
    ThrustCoefficientOverSolidity => "thrust_coefficient_over_solidity", "-", "C_T / sigma";
    InflowV0MS => "inflow_v0_m_s", "m/s", "uniform induced velocity, positive down the shaft";
    InflowV1sMS => "inflow_v1s_m_s", "m/s", "lateral (sine) induced velocity at the tip";
    InflowV1cMS => "inflow_v1c_m_s", "m/s", "longitudinal (cosine) induced velocity at the tip";
    ConingDeg => "coning_deg", "deg", "coning a0 (mean flapping)";
    A1Deg => "a1_deg", "deg", "longitudinal flapping a1 (back positive, beta = a0 - a1 cos psi - b1 sin psi)";
    B1Deg => "b1_deg", "deg", "lateral flapping b1 (beta = a0 - a1 cos psi - b1 sin psi)";
    Beta1cDeg => "beta_1c_deg", "deg", "seed 003's longitudinal disc tilt beta_1c";
    Beta1sDeg => "beta_1s_deg", "deg", "seed 003's lateral disc tilt beta_1s";
    // Trim of the aircraft.
    ResidualNorm => "residual_norm", "-", "norm of the trim's scaled residuals";
    MaxResidualNorm => "max_residual_norm", "-", "worst residual norm over a sweep of trims";
    StickLongitudinalPercent => "stick_longitudinal_percent", "%", "longitudinal stick, 0 fully forward";
    StickLateralPercent => "stick_lateral_percent", "%", "lateral stick, 0 fully left";
    PedalPercent => "pedal_percent", "%", "pedal, 0 full left";
    ThrottlePercent => "throttle_percent", "%", "throttle";
    PitchDeg => "pitch_deg", "deg", "pitch attitude";
    RollDeg => "roll_deg", "deg", "bank angle";
    AlphaDeg => "alpha_deg", "deg", "fuselage angle of attack";
    SideslipDeg => "sideslip_deg", "deg", "sideslip";
    PropellerRpm => "propeller_rpm", "rpm", "propeller speed";
    RotorTorqueNM => "rotor_torque_n_m", "N m", "driving torque on the main rotor (zero when it autorotates)";
    ThrustN => "thrust_n", "N", "main rotor thrust";
    DiscAlphaDeg => "disc_alpha_deg", "deg", "main rotor disc angle of attack";
    // Frequency responses.
    MismatchCost => "mismatch_cost", "-", "CIFER's mismatch cost J of a frequency response against a reference's (Tischler and Remple 2012), over the band of coherence >= 0.6";
}

impl Quantity {
    /// The quantity of this name.
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|q| q.name() == name)
    }
}

impl std::fmt::Display for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

use Quantity as Q;

/// What a `mode` check computes.
pub const MODE: &[Quantity] = &[
    Q::EigenvalueRealPerS,
    Q::EigenvalueImagRadS,
    Q::DampingRatio,
    Q::NaturalFrequencyRadS,
    Q::PeriodS,
    Q::TimeToHalfS,
    Q::TimeToDoubleS,
];

/// What a `bcar` check computes.
pub const BCAR: &[Quantity] = &[
    Q::DampingIndex,
    Q::BoundaryIndex,
    Q::MarginIndex,
    Q::MarginRealPerS,
    Q::PeriodS,
];

/// What a `milne` check computes.
pub const MILNE: &[Quantity] = &[
    Q::OmegaSpSquared,
    Q::Eq13A11,
    Q::Eq13A12,
    Q::Eq13A13,
    Q::Eq13A21,
    Q::Eq13A23,
    Q::Eq13A31,
    Q::Eq13A33,
    Q::SchurA11,
    Q::SchurA12,
    Q::SchurA13,
    Q::SchurA21,
    Q::SchurA22,
    Q::SchurA23,
    Q::SchurA31,
    Q::SchurA32,
    Q::SchurA33,
    Q::CubicA,
    Q::CubicB,
    Q::CubicC,
    Q::DeltaB,
    Q::DeltaC,
    Q::DeltaAPh,
    Q::DeltaBPh,
    Q::DeltaLambdaOmega,
    Q::MOmegaEq24,
    Q::MOmegaEq25,
];

/// What a `derivative` check computes.
pub const DERIVATIVE: &[Quantity] = &[
    Q::Value,
    Q::Rotor,
    Q::Propeller,
    Q::Airframe,
    Q::Inertial,
    Q::MagnitudeChange,
];

/// What an `autorotation` check computes (an isolated rotor in a tunnel); also what a fit's
/// tunnel target can fit.
pub const AUTOROTATION: &[Quantity] = &[
    Q::RotorAlphaDeg,
    Q::RotorRpm,
    Q::RotorOmegaRadS,
    Q::TipSpeedRatio,
    Q::LiftCoefficient,
    Q::DragCoefficient,
    Q::LiftToDrag,
    Q::ThrustCoefficient,
    Q::InflowV0MS,
    Q::ConingDeg,
    Q::A1Deg,
    Q::B1Deg,
];

/// What an `inflow_coefficients` check computes (seed 003, from a teeter record).
pub const INFLOW_COEFFICIENTS: &[Quantity] = &[
    Q::InflowV0MS,
    Q::InflowV1sMS,
    Q::InflowV1cMS,
    Q::ConingDeg,
    Q::Beta1cDeg,
    Q::Beta1sDeg,
];

/// What a `trim` check computes.
pub const TRIM: &[Quantity] = &[
    Q::ResidualNorm,
    Q::StickLongitudinalPercent,
    Q::StickLateralPercent,
    Q::PedalPercent,
    Q::ThrottlePercent,
    Q::PitchDeg,
    Q::RollDeg,
    Q::AlphaDeg,
    Q::SideslipDeg,
    Q::RotorRpm,
    Q::PropellerRpm,
    Q::RotorTorqueNM,
    Q::ThrustN,
    Q::DiscAlphaDeg,
    Q::TipSpeedRatio,
    Q::ThrustCoefficientOverSolidity,
    Q::A1Deg,
    Q::B1Deg,
    Q::InflowV0MS,
    Q::InflowV1cMS,
];

/// What a `frequency_response` check computes.
pub const FREQUENCY_RESPONSE: &[Quantity] = &[Q::MismatchCost];

/// Trim quantities the trim enforces (it fails otherwise): computed and snapshotted, never
/// checked.
pub const ENFORCED_BY_TRIM: &[Quantity] = &[Q::ResidualNorm, Q::MaxResidualNorm, Q::RotorTorqueNM];

/// The trim quantities whose trends over airspeed a `trim_sweep` check reports, as
/// `<name>_per_mph_min` and `<name>_per_mph_max` (see [`sweep_names`]).
pub const TREND: &[Quantity] = &[
    Q::StickLongitudinalPercent,
    Q::StickLateralPercent,
    Q::PedalPercent,
    Q::ThrottlePercent,
    Q::PitchDeg,
    Q::RollDeg,
    Q::RotorRpm,
];

/// The names a `trim_sweep` check computes: `max_residual_norm`, then the least and greatest
/// slope between neighbouring airspeeds of each trend quantity.
pub fn sweep_names() -> Vec<String> {
    let mut out = vec![Q::MaxResidualNorm.name().to_string()];
    for q in TREND {
        out.push(format!("{}_per_mph_min", q.name()));
        out.push(format!("{}_per_mph_max", q.name()));
    }
    out
}

/// Names of a list of quantities.
pub fn names(list: &[Quantity]) -> Vec<&'static str> {
    list.iter().map(|q| q.name()).collect()
}
