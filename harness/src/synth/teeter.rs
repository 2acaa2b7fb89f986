//! Synthetic teeter records (seed 003's measurements, made by the model): the reference blade's
//! first-harmonic flapping at a rotor's autorotative equilibrium, with seeded noise, in the
//! format [`crate::ident::flap`] reads.

use crate::ident::flap::FLAP_REQUIRED;
use crate::inputs::record::{RecordMeta, Synthetic};
use crate::inputs::reference::Provenance;
use crate::synth::linear::{Generated, Normal};
use cierva_model::components::autorotation::Autorotation;
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// A synthetic teeter record of a rotor's autorotative equilibrium: the reference blade's
/// first-harmonic flapping about the coning, `beta_t(psi_m) = -beta_1c cos psi_m - beta_1s sin
/// psi_m` with `beta_1c = -a1`, `beta_1s = -b1` (azimuth from the front), plus seeded Gaussian
/// noise on the teeter angle. The sidecar names the generator, seed and truth (the
/// equilibrium's inflow).
#[allow(clippy::too_many_arguments)]
pub fn synthesize_teeter(
    id: &str,
    truth: &str,
    a: &Autorotation,
    hub_inplane_m_s: f64,
    hub_normal_m_s: f64,
    duration_s: f64,
    sample_rate_hz: f64,
    seed: u64,
    noise_rad: f64,
) -> Generated {
    let mut rng = Normal::new(seed);
    let dt = 1.0 / sample_rate_hz;
    let n = (duration_s * sample_rate_hz).round() as usize + 1;
    let names: Vec<String> = FLAP_REQUIRED.iter().map(|s| s.to_string()).collect();
    let mut data = vec![Vec::with_capacity(n); names.len()];
    for k in 0..n {
        let t = k as f64 * dt;
        let psi_m = (a.omega_rad_s * t).rem_euclid(2.0 * PI);
        let teeter = a.a1_rad * psi_m.cos() + a.b1_rad * psi_m.sin() + noise_rad * rng.sample();
        for (col, v) in data.iter_mut().zip([
            t,
            teeter,
            psi_m,
            a.omega_rad_s,
            hub_inplane_m_s,
            hub_normal_m_s,
        ]) {
            col.push(v);
        }
    }
    let mut settings = BTreeMap::new();
    for (k, v) in [
        ("truth_v0_m_s", a.inflow.v0),
        ("truth_v1s_m_s", a.inflow.v1s),
        ("truth_v1c_m_s", a.inflow.v1c),
        ("truth_coning_deg", a.a0_rad.to_degrees()),
        ("teeter_noise_rad", noise_rad),
    ] {
        settings.insert(k.to_string(), format!("{v}"));
    }
    let meta = RecordMeta {
        id: id.to_string(),
        title: format!("Synthetic teeter record: {truth} in autorotation at mu {:.3}", a.tip_speed_ratio),
        provenance: Provenance {
            source: format!("synthetic: cierva synth-teeter {} from {truth}, seed {seed}", env!("CARGO_PKG_VERSION")),
            notes: Some("Not flight data: the first-harmonic teeter motion of the rotor model's own autorotative equilibrium.".into()),
        },
        synthetic: Some(Synthetic {
            generator: format!("cierva synth-teeter {}", env!("CARGO_PKG_VERSION")),
            seed,
            truth: truth.to_string(),
            settings,
        }),
        aircraft: truth.to_string(),
        sample_rate_hz,
        sensors: None,
        condition: BTreeMap::new(),
        trim: BTreeMap::new(),
        controls: vec![],
        channels: Default::default(),
        travel: Default::default(),
        excitation: Default::default(),
    };
    (names, data, meta)
}
