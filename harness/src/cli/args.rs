//! Arguments shared by several commands and the value enums they share; each command's own
//! arguments sit beside it, in its module.

use super::*;

/// An aircraft and a flight condition (shared by `trim`, `linearize` and `simulate`).
#[derive(clap::Args)]
pub(crate) struct FlightArgs {
    /// An aircraft file (see aircraft/).
    pub(crate) aircraft: PathBuf,
    /// True airspeed, mph.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_mph: f64,
    /// Mass, kg (default: the aircraft file's).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) mass_kg: Option<f64>,
    /// Rate of climb, m/s; negative descends.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub(crate) climb_m_s: f64,
    /// Density altitude, ft (ISA).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub(crate) density_altitude_ft: f64,
    /// A corrections file (as `cierva fit` writes) to apply to the aircraft.
    #[arg(long)]
    pub(crate) corrections: Option<PathBuf>,
}

impl FlightArgs {
    /// The flight condition, turning at `turn_rate_deg_s`.
    pub(crate) fn request(
        &self,
        turn_rate_deg_s: f64,
    ) -> cierva_harness::inputs::condition::TrimRequest {
        cierva_harness::inputs::condition::TrimRequest {
            airspeed_mph: self.airspeed_mph,
            climb_m_s: self.climb_m_s,
            turn_rate_deg_s,
        }
    }

    /// The condition as a record's sidecar states it, with the mass flown (`mass_kg`).
    pub(crate) fn sidecar_condition(
        &self,
        mass_kg: f64,
    ) -> std::collections::BTreeMap<String, serde_yaml::Value> {
        [
            ("airspeed_mph", self.airspeed_mph),
            ("climb_m_s", self.climb_m_s),
            ("mass_kg", mass_kg),
            ("density_altitude_ft", self.density_altitude_ft),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), serde_yaml::Value::from(v)))
        .collect()
    }

    /// The mass and air.
    pub(crate) fn loading(&self) -> cierva_harness::inputs::condition::Loading {
        cierva_harness::inputs::condition::Loading {
            mass_kg: self.mass_kg,
            density_altitude_ft: self.density_altitude_ft,
        }
    }
}

/// A test input on one control (shared by `simulate` and `synth-history`).
#[derive(clap::Args)]
pub(crate) struct ShapeArgs {
    /// An input shape on one control (with --control and --amplitude-percent; `simulate` takes
    /// a CSV of control changes with --controls-csv instead).
    #[arg(long, value_enum)]
    pub(crate) shape: Option<InputChoice>,
    /// eta_s (longitudinal stick), eta_c (lateral stick), eta_p (pedal) or eta_t (throttle).
    #[arg(long, default_value = "eta_s")]
    pub(crate) control: String,
    /// Amplitude, % of travel.
    #[arg(long, allow_hyphen_values = true, default_value_t = 1.0)]
    pub(crate) amplitude_percent: f64,
    /// When a doublet, 3-2-1-1 or step starts, s.
    #[arg(long, default_value_t = 1.0)]
    pub(crate) start_s: f64,
    /// Pulse (doublet), unit (3-2-1-1) or length (sweep), s.
    #[arg(long, default_value_t = 1.0)]
    pub(crate) input_s: f64,
    /// Sweep band, Hz.
    #[arg(long, default_value_t = 0.1)]
    pub(crate) from_hz: f64,
    #[arg(long, default_value_t = 2.0)]
    pub(crate) to_hz: f64,
}

impl ShapeArgs {
    /// The input shape, if one is given.
    pub(crate) fn input(&self) -> Option<cierva_harness::synth::linear::TestInput> {
        use cierva_harness::synth::linear::TestInput;
        let (amplitude, start_s, input_s) = (self.amplitude_percent, self.start_s, self.input_s);
        self.shape.map(|c| match c {
            InputChoice::Sweep | InputChoice::SweepDown => TestInput::Sweep {
                from_hz: self.from_hz,
                to_hz: self.to_hz,
                duration_s: input_s,
                amplitude,
                descending: c == InputChoice::SweepDown,
            },
            InputChoice::Doublet => TestInput::Doublet {
                start_s,
                pulse_s: input_s,
                amplitude,
            },
            InputChoice::ThreeTwoOneOne => TestInput::ThreeTwoOneOne {
                start_s,
                unit_s: input_s,
                amplitude,
            },
            InputChoice::Step => TestInput::Step { start_s, amplitude },
        })
    }
}

/// A rotor in a wind tunnel: the rotor file and the condition (shared by `autorotate` and
/// `synth-teeter`).
#[derive(clap::Args)]
pub(crate) struct TunnelArgs {
    /// A rotor file (see aircraft/).
    pub(crate) rotor: PathBuf,
    /// Rotor angle of attack, deg: between the free stream and the plane normal to the
    /// shaft, positive with the air meeting the disc from below; 90 is vertical descent.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) alpha_deg: f64,
    /// Tunnel speed, m/s.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_m_s: f64,
    /// Blade pitch at the rotor file's pitch reference station, deg; shifts the whole pitch
    /// distribution (default: the file's distribution as it is).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) collective_deg: Option<f64>,
}

/// A rotor's physics settings on the command line (shared by `autorotate` and
/// `synth-teeter`): each absent one is the rotor file's (`physics:`), and one given says so in
/// the output when it differs.
#[derive(clap::Args)]
pub(crate) struct PhysicsArgs {
    /// Inflow model [default: the rotor file's `physics.inflow`, else peters-haquang].
    #[arg(long, value_enum)]
    pub(crate) inflow: Option<InflowSpec>,
    /// Wake skew angle convention: seed 001 Eq. 15 (signed), seed 003 Eq. 5 (geometric) or
    /// Eq. 6 (modulus) [default: the rotor file's `physics.skew`, else signed].
    #[arg(long, value_enum)]
    pub(crate) skew: Option<SkewSpec>,
    /// The wake's mass flow in descent: momentum theory, or Johnson's empirical curve in the
    /// vortex-ring and turbulent-wake states [default: the rotor file's `physics.descent`, else
    /// momentum].
    #[arg(long, value_enum)]
    pub(crate) descent: Option<DescentSpec>,
}

impl PhysicsArgs {
    /// The settings the rotor runs with: these over its file's, and each that differs from the
    /// file's in words.
    pub(crate) fn over(
        &self,
        file: &cierva_harness::inputs::rotor::RotorFile,
    ) -> (cierva_harness::inputs::rotor::Physics, Vec<String>) {
        cierva_harness::inputs::rotor::PhysicsSpec {
            inflow: self.inflow,
            skew: self.skew,
            descent: self.descent,
        }
        .over(file, "the command line")
    }
}

/// Test inputs.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum InputChoice {
    /// Frequency sweep, low to high.
    Sweep,
    /// Frequency sweep, high to low (seed 000 Fig. 5).
    SweepDown,
    Doublet,
    /// 3-2-1-1.
    ThreeTwoOneOne,
    Step,
}
