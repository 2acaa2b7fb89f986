//! A record's signals as an identification uses them: perturbations about the sidecar's trim,
//! air data moved to the centre of mass, blade-passage averages, the tip-path plane from a
//! teeter record, and the flight condition the record states.

use super::*;

/// A centred moving average over one blade-passage period `2 pi / (N_b Omega)` (`window`
/// samples, fractional: the two end samples weighted by the fraction left over), applied to a
/// signal. Its gain is zero near `N_b` per revolution and its harmonics (the rotor's shaking in
/// a record; a two-bladed rotor's 2/rev) and `sin(pi f T) / (pi f T)` below: 0.967 at 2 Hz for
/// the VPM M16's 14 Hz 2/rev. Applied alike to every state and control, it leaves the
/// equations of motion as they were (they are linear in the signals), so it removes the
/// shaking without biasing the derivatives. Within half a window of a record's ends the window
/// is cut short, the same for every signal.
pub fn blade_passage_average(x: &[f64], window: f64) -> Vec<f64> {
    if !(window.is_finite() && window > 1.0) {
        return x.to_vec();
    }
    let half = (window - 1.0) / 2.0;
    let full = half.floor() as usize;
    let edge = half - full as f64;
    let n = x.len();
    (0..n)
        .map(|k| {
            let (mut sum, mut weight) = (0.0, 0.0);
            let lo = k.saturating_sub(full + 1);
            let hi = (k + full + 1).min(n - 1);
            for (j, v) in x.iter().enumerate().take(hi + 1).skip(lo) {
                let w = if j.abs_diff(k) <= full { 1.0 } else { edge };
                sum += w * v;
                weight += w;
            }
            sum / weight
        })
        .collect()
}

/// The flight condition a record's sidecar gives (`condition`: one airspeed, and optionally
/// `climb_m_s`, `turn_rate_deg_s`, `mass_kg`, `density_altitude_ft`), for linearising a model
/// there.
pub fn record_condition(
    record: &Record,
) -> Result<
    (
        crate::inputs::condition::TrimRequest,
        crate::inputs::condition::Loading,
    ),
    String,
> {
    let c = &record.meta.condition;
    let number = |k: &str| -> Result<Option<f64>, String> {
        match c.get(k) {
            None => Ok(None),
            Some(v) => v.as_f64().map(Some).ok_or_else(|| {
                format!("{}: condition `{k}` is not a number", sidecar_name(record))
            }),
        }
    };
    let mut flight = serde_yaml::Mapping::new();
    for k in [
        "airspeed_mph",
        "airspeed_kn",
        "airspeed_m_s",
        "climb_m_s",
        "turn_rate_deg_s",
    ] {
        if let Some(v) = number(k)? {
            flight.insert(k.into(), v.into());
        }
    }
    let request: crate::inputs::condition::TrimRequest =
        serde_yaml::from_value(serde_yaml::Value::Mapping(flight))
            .map_err(|e| format!("{}: condition: {e}", sidecar_name(record)))?;
    Ok((
        request,
        crate::inputs::condition::Loading {
            mass_kg: number("mass_kg")?,
            density_altitude_ft: number("density_altitude_ft")?.unwrap_or(0.0),
        },
    ))
}

fn sidecar_name(record: &Record) -> String {
    record::sidecar_path(&record.path).display().to_string()
}

/// State and control time histories, one vector per variable.
pub type Histories = (Vec<Vec<f64>>, Vec<Vec<f64>>);

/// The perturbation time histories of the configured states and controls.
pub fn signals(record: &Record, config: &ConfigSpec) -> Result<Histories, String> {
    let ch = |name: &str| {
        record
            .channel(name)
            .ok_or_else(|| format!("{}: channel `{name}` is missing", record.path.display()))
    };
    let trim = |key: &str| record.meta.trim.get(key).copied().unwrap_or(0.0);
    let (v, a, b) = (
        ch("airspeed_m_s")?,
        ch("alpha_vane_rad")?,
        ch("beta_vane_rad")?,
    );
    let (p, q, r) = (ch("p_rad_s")?, ch("q_rad_s")?, ch("r_rad_s")?);
    let s = record.meta.sensors.as_ref().ok_or_else(|| {
        format!(
            "{}: the sidecar gives no `sensors` (probe and c.g. positions)",
            record.path.display()
        )
    })?;
    let off = [
        s.probe_position_m[0] - s.cg_position_m[0],
        s.probe_position_m[1] - s.cg_position_m[1],
        s.probe_position_m[2] - s.cg_position_m[2],
    ];
    let n = v.len();
    // Seed 000 Eqs. 5-6: probe velocity from airspeed and vanes, then the c.g. velocity.
    let (mut u, mut vv, mut w) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for k in 0..n {
        let up = v[k] * b[k].cos() * a[k].cos();
        let vp = v[k] * b[k].sin();
        let wp = v[k] * b[k].cos() * a[k].sin();
        u[k] = up - (q[k] * off[2] - r[k] * off[1]);
        vv[k] = vp - (r[k] * off[0] - p[k] * off[2]);
        w[k] = wp - (p[k] * off[1] - q[k] * off[0]);
    }
    let mut xs: Vec<Vec<f64>> = Vec::new();
    for st in &config.states {
        let (series, key): (Vec<f64>, String) = match st.as_str() {
            "u" => (u.clone(), "u_m_s".into()),
            "v" => (vv.clone(), "v_m_s".into()),
            "w" => (w.clone(), "w_m_s".into()),
            "p" | "q" | "r" => (ch(&format!("{st}_rad_s"))?.to_vec(), format!("{st}_rad_s")),
            "phi" | "theta" | "psi" => (ch(&format!("{st}_rad"))?.to_vec(), format!("{st}_rad")),
            "Omega" => (
                ch("omega_rotor_rad_s")?.to_vec(),
                "omega_rotor_rad_s".into(),
            ),
            "beta_1c" | "beta_1s" => {
                let (c, s) = flapping_products(record)?;
                let raw = if st == "beta_1c" { c } else { s };
                // No trim value is recorded for the tilts: the record's mean is taken off (the
                // band starts well above the frequencies a mean leaks to).
                let mean = raw.iter().sum::<f64>() / raw.len().max(1) as f64;
                xs.push(raw.iter().map(|x| x - mean).collect());
                continue;
            }
            other => return Err(format!("no measurement gives the state `{other}`")),
        };
        let t0 = trim(&key);
        xs.push(series.iter().map(|x| x - t0).collect());
    }
    let mut us: Vec<Vec<f64>> = Vec::new();
    for channel in config.controls.values() {
        let t0 = trim(channel);
        us.push(ch(channel)?.iter().map(|x| x - t0).collect());
    }
    if let Some(window) = flapping_window(record, config)? {
        for s in xs.iter_mut().chain(us.iter_mut()) {
            *s = blade_passage_average(s, window);
        }
    }
    if let Some(blades) = config.blade_passage_blades {
        let revolution = revolution_window(record, "averaging out the blade passage")?;
        if blades == 0 {
            return Err("blade_passage_blades must be at least 1".into());
        }
        let window = revolution / f64::from(blades);
        for s in xs.iter_mut().chain(us.iter_mut()) {
            *s = blade_passage_average(s, window);
        }
    }
    Ok((xs, us))
}

/// The teeter channel demodulated at the rotor's azimuth, before averaging:
/// `-2 teeter cos(psi_f)` and `-2 teeter sin(psi_f)` with `psi_f` the azimuth from the front
/// (seed 003's convention: `teeter = -beta_1c cos(psi_f) - beta_1s sin(psi_f)`, so the model's
/// `beta = beta_1c cos(psi) + beta_1s sin(psi)` with `psi = psi_f - pi`). Their mean over a
/// revolution is the tip-path plane's tilt ([`flapping_window`]).
fn flapping_products(record: &Record) -> Result<(Vec<f64>, Vec<f64>), String> {
    let ch = |name: &str| {
        record.channel(name).ok_or_else(|| {
            format!(
                "{}: the flapping states need the channel `{name}` (a teetering rotor's record)",
                record.path.display()
            )
        })
    };
    let (teeter, az) = (ch("teeter_rad")?, ch("azimuth_from_front_rad")?);
    Ok(teeter
        .iter()
        .zip(az)
        .map(|(b, a)| (-2.0 * b * a.cos(), -2.0 * b * a.sin()))
        .unzip())
}

/// The tip-path plane's tilts `(beta_1c, beta_1s)` through a teetering rotor's record, rad:
/// the teeter channel demodulated at the azimuth and averaged over a revolution at the trim's
/// rotor speed (what a set-up with flapping states identifies from, before its mean is taken
/// off).
pub fn tip_path_plane(record: &Record) -> Result<(Vec<f64>, Vec<f64>), String> {
    let (c, s) = flapping_products(record)?;
    let window = revolution_window(record, "the tip-path plane")?;
    Ok((
        blade_passage_average(&c, window),
        blade_passage_average(&s, window),
    ))
}

/// One revolution at the trim's rotor speed, in samples; `what` needs it (for the message when
/// the sidecar does not give the speed).
fn revolution_window(record: &Record, what: &str) -> Result<f64, String> {
    let omega = record
        .meta
        .trim
        .get("omega_rotor_rad_s")
        .copied()
        .filter(|w| w.is_finite() && *w > 0.0)
        .ok_or_else(|| {
            format!(
                "{}: {what} needs the trim's `omega_rotor_rad_s` in the sidecar",
                record.path.display()
            )
        })?;
    Ok(2.0 * std::f64::consts::PI / omega / record.dt_s())
}

/// With flapping states in the set-up, the window (in samples) of one revolution at the
/// trim's rotor speed: every signal is averaged over it ([`blade_passage_average`] with one
/// blade), which turns the demodulated teeter into the tip-path plane's tilts (the products'
/// 2/rev parts average to nothing over a revolution) and treats every other signal alike, so
/// the equations hold as they did (they are linear in the signals). The average keeps
/// `sin(pi f T) / (pi f T)` of a signal at `f`: 0.87 at 2 Hz for the VPM M16's 0.14 s
/// revolution, the same for every signal. `None` without flapping states.
pub fn flapping_window(record: &Record, config: &ConfigSpec) -> Result<Option<f64>, String> {
    if config
        .states
        .iter()
        .any(|s| FLAP_STATES.contains(&s.as_str()))
    {
        revolution_window(
            record,
            "averaging over a revolution for the flapping states",
        )
        .map(Some)
    } else {
        Ok(None)
    }
}
