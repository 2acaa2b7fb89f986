//! `cierva autorotate`: the isolated rotor's autorotative equilibrium in a wind tunnel, at a
//! given angle and airspeed, or at a given tip-speed ratio and rotor speed (the angle found).

use super::*;

/// Find the autorotative equilibrium of an isolated rotor in a wind tunnel: the rotorspeed
/// at which the mean aerodynamic torque is zero, with lift and drag coefficients on
/// q pi R^2, L/D, tip-speed ratio, thrust coefficient, flapping and inflow.
///
/// Example: `cierva autorotate aircraft/pca-2-rotor.yaml --alpha-deg 6.6 --airspeed-m-s 17.7
/// --collective-deg 1.9`. `--alpha-deg 90` is vertical descent.
///
/// With `--tip-speed-ratio` and `--rotor-rpm` (or `--rpm`) instead, finds the angle of attack
/// at which the rotor autorotates there (how TR 515 plots its data): `cierva autorotate
/// aircraft/pca-2-rotor.yaml --tip-speed-ratio 0.5 --rotor-rpm 140 --collective-deg 1.9`.
///
/// `--format json` gives the condition (`airspeed_m_s`, `alpha_deg`, `rpm`), the quantities
/// by the names cases use (`rotor_alpha_deg`, `rotor_rpm`, `lift_coefficient`,
/// `drag_coefficient`, `lift_to_drag`, ...) and the model's whole equilibrium.
#[derive(clap::Args)]
pub(crate) struct AutorotateArgs {
    /// A rotor file (see aircraft/).
    pub(crate) rotor: PathBuf,
    /// Rotor angle of attack, deg: between the free stream and the plane normal to the
    /// shaft, positive with the air meeting the disc from below; 90 is vertical descent (with
    /// --airspeed-m-s).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) alpha_deg: Option<f64>,
    /// Tunnel speed, m/s (with --alpha-deg).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_m_s: Option<f64>,
    /// Tip-speed ratio mu (with --rotor-rpm, instead of --alpha-deg and --airspeed-m-s): finds
    /// the angle of attack at which the rotor autorotates at this mu and rotor speed.
    #[arg(long)]
    pub(crate) tip_speed_ratio: Option<f64>,
    /// Rotor speed, rpm (with --tip-speed-ratio; `--rpm` is the same).
    #[arg(long, alias = "rpm")]
    pub(crate) rotor_rpm: Option<f64>,
    /// Blade pitch at the rotor file's pitch reference station, deg; shifts the whole pitch
    /// distribution (default: the file's distribution as it is).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) collective_deg: Option<f64>,
    /// A corrections file for this rotor (as `cierva fit` writes), applied before solving.
    #[arg(long)]
    pub(crate) corrections: Option<PathBuf>,
    /// Air density, kg/m^3 (default 1.225, ISA sea level); the speed of sound is taken
    /// from the standard atmosphere at that density altitude.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) density_kg_m3: Option<f64>,
    #[command(flatten)]
    pub(crate) physics: PhysicsArgs,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

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
    let (physics, overrides) = a.physics.over(&file);
    let inflow = physics.model();
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
            for (name, value) in cierva_harness::run::autorotation::quantities_of(alpha_deg, &e) {
                m.insert(name.into(), serde_json::json!(value));
            }
            // Where the angle was found: how firmly the rotor holds its speed there.
            if let Some(s) = stiffness {
                m.insert("rotor_speed_stiffness".into(), serde_json::json!(s));
            }
            // The physics it ran with, what the command line set over the rotor file's, and
            // where an equation was used outside its validity (the answer is then a warning).
            m.insert("physics".into(), serde_json::json!(physics));
            m.insert("overrides".into(), serde_json::json!(overrides));
            m.insert("warnings".into(), serde_json::json!(e.outside_validity));
            m.insert(
                "equilibrium".into(),
                serde_json::to_value(&e).unwrap_or_default(),
            );
            print_json(&serde_json::Value::Object(m))
        }
        Format::Text => {
            print_text(&file, alpha_deg, airspeed_m_s, &e);
            print_physics(&physics, &overrides, &e.outside_validity);
            if file.physics == cierva_harness::inputs::rotor::PhysicsSpec::default() {
                println!(
                    "hint: {} states no `physics:`, so these are the defaults; give the settings \
                     this rotor is validated with, each with its evidence under `sources` \
                     (docs/physics.md, \"Where the equations hold\")",
                    a.rotor.display()
                );
            }
        }
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

/// The physics the answer was found with, what the command line set over the rotor file's,
/// and each equation used outside its validity (the answer is then not to be trusted).
fn print_physics(
    physics: &cierva_harness::inputs::rotor::Physics,
    overrides: &[String],
    outside_validity: &[String],
) {
    let words = |v: serde_json::Value| v.as_str().unwrap_or_default().to_string();
    println!(
        "physics              inflow {}, skew {}, descent {}",
        words(serde_json::json!(physics.inflow)),
        words(serde_json::json!(physics.skew)),
        words(serde_json::json!(physics.descent)),
    );
    for o in overrides {
        println!("note: {o}");
    }
    for w in outside_validity {
        println!("WARNING: {w}: this answer is not the rotor's");
    }
}
