//! Flight tests flown by the full individual-blade model: a pilot flying a test input
//! ([`pilot`]) through turbulence ([`turbulence`]), recorded by instruments ([`sensors`]) in the
//! identification format ([`crate::inputs::record`]).
//!
//! The record is what a flight-test installation gives (seed 000 Sec. II): airspeed and the
//! vanes' angles at the air-data probe (air-relative, so the gusts are in them), body rates,
//! attitudes, rotorspeed, and every control in % of travel, sampled at a regular rate. The
//! rotor's blades are individual, so the 2/rev shaking of a two-bladed rotor is in the record,
//! as in flight.

pub mod pilot;
pub mod sensors;
pub mod turbulence;

use crate::inputs::condition::Loading;
use crate::inputs::condition::TrimRequest;
use crate::synth::linear::{Normal, TestInput};
use crate::units::MPH_TO_M_S;
use cierva_model::aircraft::{Aircraft, Controls, FullState};
use cierva_model::simulation::timehistory::{self, Drivers};
use pilot::Pilot;
use sensors::Instrumentation;
use std::collections::BTreeMap;
use turbulence::Dryden;

/// The record's control channels, in the order of the model's controls: the columns of a
/// controls file.
pub const CONTROL_CHANNELS: [&str; 4] = crate::inputs::controls::CONTROL_COLUMNS;

/// A record's controls as its sidecar lists them: the one the test input moves first (what a
/// longitudinal or lateral set-up takes as the excited control), then the others.
pub fn record_controls(control: usize) -> Vec<String> {
    let mut out = vec![CONTROL_CHANNELS[control].to_string()];
    out.extend(
        CONTROL_CHANNELS
            .iter()
            .filter(|c| **c != CONTROL_CHANNELS[control])
            .map(|c| c.to_string()),
    );
    out
}

/// A flight test to fly.
#[derive(Debug, Clone)]
pub struct FlightTest {
    pub request: TrimRequest,
    pub loading: Loading,
    /// The test input, in % of travel.
    pub input: TestInput,
    /// The control it moves (index into [`CONTROL_CHANNELS`]).
    pub control: usize,
    pub duration_s: f64,
    pub sample_rate_hz: f64,
    pub turbulence: Option<Dryden>,
    pub instrumentation: Instrumentation,
    /// Fly with the pilot's attitude hold (otherwise the input alone, open loop).
    pub pilot: bool,
    pub seed: u64,
    /// Azimuth step of the full model, rad.
    pub azimuth_step_rad: f64,
}

/// A flown test: the record's channels and samples, the trim, and what flew it.
#[derive(Debug, Clone)]
pub struct FlownTest {
    pub channels: Vec<String>,
    pub data: Vec<Vec<f64>>,
    /// Trim values of the record's channels and of the c.g. velocities (`u_m_s`, `w_m_s`).
    pub trim: BTreeMap<String, f64>,
    /// The air-data probe's position in the aircraft's datum, and the c.g.'s, m.
    pub probe_position_m: [f64; 3],
    pub cg_position_m: [f64; 3],
    pub pilot: Option<Pilot>,
    /// The sidecar's `excitation`: the moved control's channel and the one recording the test
    /// input ([`excitation_channel`]).
    pub excitation: BTreeMap<String, String>,
}

/// The channel recording the test input on the `control`th of [`CONTROL_CHANNELS`]
/// (`eta_s_excitation_percent`): what an excitation system adds to the pilot's command, so
/// that the responses can be estimated against it, unbiased by the pilot's loops
/// ([`crate::ident::frequency_response::referenced`]).
pub fn excitation_channel(control: usize) -> String {
    let c = CONTROL_CHANNELS[control];
    format!(
        "{}_excitation{}",
        c.strip_suffix(crate::inputs::record::PERCENT).unwrap_or(c),
        crate::inputs::record::PERCENT
    )
}

impl FlownTest {
    /// The flight as a record in memory, for the identifier: `id` (its path `<id>.csv`), the
    /// `control`th of [`CONTROL_CHANNELS`] the one moved, sampled at `sample_rate_hz`, with
    /// `source` as its provenance and `condition` as its sidecar's. (`cierva synth-flight`
    /// writes the full sidecar, with the synthetic settings and truth.)
    pub fn into_record(
        self,
        id: &str,
        control: usize,
        sample_rate_hz: f64,
        source: &str,
        condition: BTreeMap<String, serde_yaml::Value>,
    ) -> crate::inputs::record::Record {
        use crate::inputs::record::{Record, RecordMeta, Sensors};
        Record {
            path: format!("{id}.csv").into(),
            meta: RecordMeta {
                id: id.to_string(),
                title: id.to_string(),
                provenance: crate::inputs::reference::Provenance {
                    source: source.to_string(),
                    notes: None,
                },
                synthetic: None,
                aircraft: String::new(),
                sample_rate_hz,
                sensors: Some(Sensors {
                    probe_position_m: self.probe_position_m,
                    cg_position_m: self.cg_position_m,
                }),
                condition,
                trim: self.trim,
                controls: record_controls(control),
                channels: Default::default(),
                travel: Default::default(),
                excitation: self.excitation,
            },
            channels: self.channels,
            data: self.data,
            notes: Vec::new(),
        }
    }
}

/// The rotor channels of a teetering rotor's record: the teeter angle (blade 1 up), its
/// azimuth from the front of the disc, and the hub's air speeds in shaft axes, as seed 003's
/// teeter records have them ([`crate::ident::flap::FLAP_REQUIRED`]), so that `cierva inflow`
/// reads the record.
pub const TEETER_CHANNELS: [&str; 4] = [
    "teeter_rad",
    "azimuth_from_front_rad",
    "hub_inplane_speed_m_s",
    "hub_normal_speed_m_s",
];

/// What the record holds, in order (the identification format's required channels, the
/// controls, and a teetering rotor's channels).
fn channel_names(teetering: bool) -> Vec<String> {
    let rotor: &[&str] = if teetering { &TEETER_CHANNELS } else { &[] };
    crate::inputs::record::REQUIRED
        .iter()
        .chain(CONTROL_CHANNELS.iter())
        .chain(rotor)
        .map(|c| c.to_string())
        .collect()
}

/// SplitMix64's output function (Steele, Lea and Flood 2014, *OOPSLA*): a bijective mix of
/// 64 bits.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of one random source (1 the pilot's drift, 2 the turbulence, 3 the instruments'
/// noise) of the test seeded `seed`: the pair hashed (`mix`), so that the streams of
/// different seeds and sources start at unrelated points of the generator's cycle.
///
/// [`Normal`]'s stream from a seed `s` is the mix of `s + k gamma`, `gamma` SplitMix64's
/// increment. This was `seed gamma + source c`: consecutive seeds then started one step
/// apart on the same stream, and seeds two apart gave the same normal deviates shifted by
/// two, so flights seeded 1000 apart (the coverage trials') flew the same turbulence and
/// noise a few seconds apart.
pub fn seed_for(seed: u64, source: u64) -> u64 {
    mix(mix(seed) ^ source.wrapping_add(1).wrapping_mul(0xD1B5_4A32_D192_ED03))
}

/// Flies the test with the full model and records it.
pub fn fly(aircraft: &Aircraft, test: &FlightTest) -> Result<FlownTest, String> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(test.duration_s) && ok(test.sample_rate_hz) && ok(test.azimuth_step_rad)) {
        return Err("the duration, sample rate and azimuth step must be positive".into());
    }
    if test.control >= CONTROL_CHANNELS.len() {
        return Err(format!("no control {}", test.control));
    }
    let start = crate::run::simulate::simulation_start(aircraft, test.request, test.loading)?;
    let dt = 1.0 / test.sample_rate_hz;
    let n = crate::inputs::limits::record_samples(test.duration_s, test.sample_rate_hz)?;
    let pilot = if test.pilot {
        let (_, lin) =
            crate::run::linearise::run_linearise(&start.aircraft, test.request, test.loading)
                .map_err(|e| format!("linearising for the pilot's gains: {e}"))?;
        Some(Pilot::new(
            &lin.model,
            test.duration_s,
            seed_for(test.seed, 1),
        )?)
    } else {
        None
    };
    let airspeed = test.request.airspeed_mph * MPH_TO_M_S;
    let gusts = match &test.turbulence {
        Some(d) => d.realise(airspeed, dt, n + 1, seed_for(test.seed, 2))?,
        None => vec![[0.0; 3]; n + 2],
    };
    let wind = |t: f64| -> [f64; 3] {
        let pos = (t / dt).max(0.0);
        let k = (pos.floor() as usize).min(gusts.len() - 2);
        let f = (pos - k as f64).min(1.0);
        [0, 1, 2].map(|i| gusts[k][i] + f * (gusts[k + 1][i] - gusts[k][i]))
    };
    let u0 = start.controls;
    let b0 = start.state.body;
    let trim_percent = [
        u0.stick_longitudinal_percent,
        u0.stick_lateral_percent,
        u0.pedal_percent,
        u0.throttle_percent,
    ];
    let controls = |t: f64, x: &FullState| -> Controls {
        let mut d = [0.0; 4];
        d[test.control] = test.input.at(t);
        if let Some(p) = &pilot {
            let b = &x.body;
            let c = p.corrections(
                t,
                [
                    b.theta_rad - b0.theta_rad,
                    b.phi_rad - b0.phi_rad,
                    b.psi_rad - b0.psi_rad,
                ],
                [b.p_rad_s, b.q_rad_s, b.r_rad_s],
            );
            for k in 0..3 {
                d[k] += c[k];
            }
        }
        // The controls stop at the ends of their travel.
        let at = |k: usize| (trim_percent[k] + d[k]).clamp(0.0, 100.0);
        Controls {
            stick_longitudinal_percent: at(0),
            stick_lateral_percent: at(1),
            pedal_percent: at(2),
            throttle_percent: at(3),
        }
    };
    let settings = timehistory::Settings {
        azimuth_step_rad: test.azimuth_step_rad,
        duration_s: test.duration_s + dt,
        output_every: 1,
    };
    let drivers = Drivers {
        controls: &controls,
        wind: &wind,
    };
    let h = timehistory::run_with(
        &start.aircraft,
        start.state.clone(),
        drivers,
        start.air,
        settings,
    )
    .map_err(|(t, e)| format!("the flight diverged at {t:.2} s: {e}"))?;
    // The true channels at each sample time, interpolated between the integration steps.
    let cg = start.aircraft.cg_m;
    let probe = start_probe(&test.instrumentation, cg);
    let arm = [probe[0] - cg[0], probe[1] - cg[1], probe[2] - cg[2]];
    let teetering = matches!(
        start.aircraft.main_rotor.rotor.hub,
        cierva_model::components::rotor::Hub::Teetering
    );
    let names = channel_names(teetering);
    let row = |x: &FullState, c: &Controls, wind: [f64; 3]| {
        true_row(&start.aircraft, x, c, wind, arm, teetering)
    };
    let times: Vec<f64> = (0..=n).map(|k| k as f64 * dt).collect();
    let rows = crate::run::replay::resample(&h, &times, &|s: &timehistory::Sample| {
        row(&s.state, &s.controls, wind(s.time_s))
    });
    let truth = columns(&times, rows, names.len());
    if truth.iter().flatten().any(|v| !v.is_finite()) {
        return Err("the flight's record is not finite".into());
    }
    let mut data = instruments(test, &names, &truth, dt)?;
    let trim = trim_mean(&start, settings, &names, &row)?;
    let mut names = names;
    let excitation = record_excitation(test, &times, &mut names, &mut data);
    Ok(FlownTest {
        channels: names,
        data,
        trim,
        probe_position_m: probe,
        cg_position_m: cg,
        pilot,
        excitation,
    })
}

/// The test input as the excitation system commands it, appended to the record's channels
/// (recorded digitally, so without the instruments' noise, lag or quantisation): the sidecar's
/// `excitation`, the moved control's channel to the new one.
fn record_excitation(
    test: &FlightTest,
    times: &[f64],
    names: &mut Vec<String>,
    data: &mut Vec<Vec<f64>>,
) -> BTreeMap<String, String> {
    let column = excitation_channel(test.control);
    names.push(column.clone());
    data.push(times.iter().map(|&t| test.input.at(t)).collect());
    BTreeMap::from([(CONTROL_CHANNELS[test.control].to_string(), column)])
}

/// The true record's columns: the sample times, then each row's channels in order
/// (`channels` columns in all).
fn columns(times: &[f64], rows: Vec<Vec<f64>>, channels: usize) -> Vec<Vec<f64>> {
    let mut truth = vec![Vec::with_capacity(times.len()); channels];
    for (&t, r) in times.iter().zip(rows) {
        truth[0].push(t);
        for (column, v) in truth[1..].iter_mut().zip(r) {
            column.push(v);
        }
    }
    truth
}

/// The instruments: the time column as it is, then each true channel measured by its sensor
/// (one noise stream, seeded from the test's seed, source 3), a teeter record's azimuth
/// wrapped to `[0, 2 pi)`.
fn instruments(
    test: &FlightTest,
    names: &[String],
    truth: &[Vec<f64>],
    dt: f64,
) -> Result<Vec<Vec<f64>>, String> {
    let mut rng = Normal::new(seed_for(test.seed, 3));
    let mut data = vec![truth[0].clone()];
    for (name, series) in names.iter().zip(truth).skip(1) {
        let ch = test
            .instrumentation
            .channel(name)
            .ok_or_else(|| format!("no sensor for the channel `{name}`"))?;
        let mut measured = ch.measure(series, dt, &mut rng);
        if name == "azimuth_from_front_rad" {
            for a in &mut measured {
                *a = a.rem_euclid(2.0 * std::f64::consts::PI);
            }
        }
        data.push(measured);
    }
    Ok(data)
}

/// The trim: the mean over one revolution of the periodic orbit, controls held, calm air, of
/// the true channels after the time (`row`) and the body velocities and inflow states, by
/// name.
fn trim_mean<R>(
    start: &crate::run::simulate::SimulationStart,
    settings: timehistory::Settings,
    names: &[String],
    row: &R,
) -> Result<BTreeMap<String, f64>, String>
where
    R: Fn(&FullState, &Controls, [f64; 3]) -> Vec<f64>,
{
    let u0 = start.controls;
    let revolution = timehistory::run(
        &start.aircraft,
        start.state.clone(),
        &|_| u0,
        start.air,
        timehistory::Settings {
            duration_s: 2.0 * std::f64::consts::PI / start.state.rotor_omega_rad_s,
            ..settings
        },
    )
    .map_err(|(t, e)| format!("the trim's revolution failed at {t:.3} s: {e}"))?;
    let mean = crate::run::replay::revolution_mean(&revolution, &|x: &timehistory::Sample| {
        let b = &x.state.body;
        let i = &x.state.inflow;
        let mut r = row(&x.state, &x.controls, [0.0; 3]);
        r.extend([b.u_m_s, b.v_m_s, b.w_m_s, i.v0, i.v1s, i.v1c]);
        r
    });
    let keys = names.iter().skip(1).map(String::as_str).chain([
        "u_m_s",
        "v_m_s",
        "w_m_s",
        "inflow_v0_m_s",
        "inflow_v1s_m_s",
        "inflow_v1c_m_s",
    ]);
    Ok(keys.zip(mean).map(|(k, v)| (k.to_string(), v)).collect())
}

/// The probe's position in the datum.
fn start_probe(inst: &Instrumentation, cg: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| cg[i] + inst.probe_from_cg_m[i])
}

/// The true record channels after `time_s` (see [`channel_names`]) at a state: the air data at
/// the probe from the air-relative velocity (seed 000 Eqs. 5-6 read backwards), and a
/// teetering rotor's channels (the azimuth unwrapped: the caller wraps it).
fn true_row(
    aircraft: &Aircraft,
    x: &FullState,
    c: &Controls,
    wind: [f64; 3],
    arm: [f64; 3],
    teetering: bool,
) -> Vec<f64> {
    let b = &x.body;
    let (p, q, r) = (b.p_rad_s, b.q_rad_s, b.r_rad_s);
    let air = [b.u_m_s - wind[0], b.v_m_s - wind[1], b.w_m_s - wind[2]];
    let up = air[0] + q * arm[2] - r * arm[1];
    let vp = air[1] + r * arm[0] - p * arm[2];
    let wp = air[2] + p * arm[1] - q * arm[0];
    let airspeed = (up * up + vp * vp + wp * wp).sqrt();
    let mut row = vec![
        airspeed,
        wp.atan2(up),
        (vp / airspeed).asin(),
        p,
        q,
        r,
        b.phi_rad,
        b.theta_rad,
        x.rotor_omega_rad_s,
        c.stick_longitudinal_percent,
        c.stick_lateral_percent,
        c.pedal_percent,
        c.throttle_percent,
    ];
    if teetering {
        let hub = aircraft.hub_air_velocity(&x.body, c, wind);
        row.extend([
            x.flap.first().map_or(0.0, |f| f[0]),
            // Azimuth from the front: the model's is zero over the tail.
            x.rotor_azimuth_rad + std::f64::consts::PI,
            hub.u.hypot(hub.v),
            hub.w,
        ]);
    }
    row
}

/// What a flight test's record says about how it was made (its sidecar's `synthetic.settings`):
/// the input, the air, the pilot and every instrument with its source. `height_ft` is the
/// height the turbulence's scales are for.
pub fn describe(test: &FlightTest, flown: &FlownTest, height_ft: f64) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    out.insert(
        "input".into(),
        format!("{:?} on {}", test.input, CONTROL_CHANNELS[test.control]),
    );
    out.insert(
        "turbulence".into(),
        match &test.turbulence {
            Some(d) => format!(
                "Dryden (MIL-F-8785C low altitude, {} ft): sigma_u,v,w {:.3}, {:.3}, {:.3} m/s, scales {:.0}, {:.0}, {:.0} m, along body axes",
                height_ft,
                d.sigma_m_s[0],
                d.sigma_m_s[1],
                d.sigma_m_s[2],
                d.scale_m[0],
                d.scale_m[1],
                d.scale_m[2]
            ),
            None => "none (calm air)".into(),
        },
    );
    out.insert(
        "pilot".into(),
        match &flown.pilot {
            Some(p) => format!(
                "attitude hold (pitch, roll, heading) about references drifting 0.5 deg over 30 s: gains {:?} %/rad and {:?} %/(rad/s)",
                p.attitude_gain_percent_per_rad, p.rate_gain_percent_per_rad_s
            ),
            None => "none: the input open loop".into(),
        },
    );
    out.insert(
        "sensors".into(),
        format!(
            "{}: {}",
            test.instrumentation.id, test.instrumentation.title
        ),
    );
    for (name, ch) in &test.instrumentation.channels {
        out.insert(
            format!("sensor.{name}"),
            format!(
                "noise {}, bias {}, lag {} s; source: {}",
                ch.noise,
                ch.bias,
                ch.lag_s,
                test.instrumentation
                    .sources
                    .get(&format!("channels.{name}"))
                    .map_or("", String::as_str)
            ),
        );
    }
    out.insert(
        "sensor.probe_from_cg_m".into(),
        format!(
            "{:?}; source: {}",
            test.instrumentation.probe_from_cg_m,
            test.instrumentation
                .sources
                .get("probe_from_cg_m")
                .map_or("", String::as_str)
        ),
    );
    out
}
