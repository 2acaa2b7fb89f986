//! `cierva autorotate`: the isolated rotor's autorotative equilibrium in a wind tunnel, at a
//! given angle and airspeed, or at a given tip-speed ratio and rotor speed (the angle found).

use super::*;

/// The rotor file with `--corrections` applied (the file must name this rotor).
fn load_rotor(a: &AutorotateArgs) -> Result<cierva_harness::inputs::rotor::RotorFile, Error> {
    use cierva_harness::inputs::corrections::{self, Corrects};

    let mut file = cierva_harness::inputs::rotor::load(&a.rotor)?;
    let Some(path) = &a.corrections else {
        return Ok(file);
    };
    let c = corrections::load(path)?;
    if c.target != Corrects::Rotor(file.id.clone()) {
        return Err(Error::input(format!(
            "{} corrects {:?}, not the rotor {}",
            path.display(),
            c.target,
            file.id
        )));
    }
    c.corrections
        .apply_to_rotor(&mut file.rotor)
        .map_err(|e| Error::input(format!("{}: {e}", path.display())))?;
    Ok(file)
}

pub(crate) fn autorotate(a: AutorotateArgs) -> Result<ExitCode, Error> {
    let file = load_rotor(&a)?;
    let inflow = a.inflow.model(a.skew, a.descent);
    let run = match (a.alpha_deg, a.airspeed_m_s, a.tip_speed_ratio, a.rotor_rpm) {
        (Some(alpha_deg), Some(airspeed_m_s), None, None) => run_autorotation(
            &file.rotor,
            alpha_deg,
            airspeed_m_s,
            a.collective_deg,
            a.density_kg_m3,
            inflow,
        )
        .map(|e| (alpha_deg, airspeed_m_s, e, None)),
        (None, None, Some(mu), Some(rpm)) => {
            cierva_harness::run::autorotation::run_autorotation_at_tip_speed_ratio(
                &file.rotor,
                mu,
                rpm,
                a.collective_deg,
                a.density_kg_m3,
                inflow,
            )
            .map(|f| {
                (
                    f.alpha_rad.to_degrees(),
                    f.airspeed_m_s,
                    f.autorotation,
                    Some(f.rotor_speed_stiffness),
                )
            })
        }
        _ => {
            return Err(Error::input(
                "give --alpha-deg with --airspeed-m-s, or --tip-speed-ratio with --rotor-rpm",
            ));
        }
    };
    let (alpha_deg, airspeed_m_s, e, stiffness) =
        run.map_err(|e| Error::of(e.is_input(), format!("error: {}: {e}", a.rotor.display())))?;
    match a.format {
        Format::Json => {
            // The quantities by the names cases and fits use; the model's whole equilibrium
            // (its own field names, SI) under `equilibrium`.
            let mut m = serde_json::Map::new();
            m.insert("rotor".into(), serde_json::json!(file.id));
            // The condition, given or found, as the tunnel plots it: angle and rotor speed.
            m.insert("airspeed_m_s".into(), serde_json::json!(airspeed_m_s));
            m.insert("alpha_deg".into(), serde_json::json!(alpha_deg));
            m.insert("rpm".into(), serde_json::json!(e.rpm));
            for (name, value) in cierva_harness::checks::autorotation::quantities_of(alpha_deg, &e)
            {
                m.insert(name.into(), serde_json::json!(value));
            }
            // Where the angle was found: how firmly the rotor holds its speed there.
            if let Some(s) = stiffness {
                m.insert("rotor_speed_stiffness".into(), serde_json::json!(s));
            }
            m.insert(
                "equilibrium".into(),
                serde_json::to_value(&e).unwrap_or_default(),
            );
            print_json(&serde_json::Value::Object(m))
        }
        Format::Text => print_text(&file, alpha_deg, airspeed_m_s, &e),
    }
    Ok(ExitCode::SUCCESS)
}

fn print_text(
    file: &cierva_harness::inputs::rotor::RotorFile,
    alpha_deg: f64,
    airspeed_m_s: f64,
    e: &cierva_model::components::autorotation::Autorotation,
) {
    let d = |r: f64| r.to_degrees();
    println!(
        "{} ({}) at alpha {alpha_deg:.4} deg, {airspeed_m_s:.4} m/s",
        file.title, file.id
    );
    println!(
        "rotorspeed           {:.3} rad/s ({:.1} rpm)",
        e.omega_rad_s, e.rpm
    );
    println!("tip-speed ratio mu   {:.4}", e.tip_speed_ratio);
    println!(
        "lift coefficient     {:.5}  (on q pi R^2)",
        e.lift_coefficient
    );
    println!("drag coefficient     {:.5}", e.drag_coefficient);
    println!("L/D                  {:.3}", e.lift_to_drag);
    println!(
        "thrust coefficient   {:.6}  (T / rho pi R^2 (Omega R)^2)",
        e.thrust_coefficient
    );
    println!(
        "thrust, H-force      {:.1} N, {:.1} N",
        e.thrust_n, e.h_force_n
    );
    println!(
        "flapping a0 a1 b1    {:.3} {:.3} {:.3} deg",
        d(e.a0_rad),
        d(e.a1_rad),
        d(e.b1_rad)
    );
    println!(
        "inflow v0 v1s v1c    {:.3} {:.3} {:.3} m/s; lambda {:.5}; skew {:.2} deg",
        e.inflow.v0,
        e.inflow.v1s,
        e.inflow.v1c,
        e.inflow_ratio,
        d(e.skew_rad)
    );
    println!(
        "converged            residual {:.1e} in {} Newton iterations",
        e.residual_norm, e.iterations
    );
}
