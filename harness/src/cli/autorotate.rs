//! `cierva autorotate`: the isolated rotor's autorotative equilibrium in a wind tunnel.

use super::*;

pub(crate) fn autorotate(
    path: PathBuf,
    alpha_deg: f64,
    airspeed_m_s: f64,
    collective_deg: Option<f64>,
    density_kg_m3: Option<f64>,
    inflow: InflowModel,
    format: Format,
) -> ExitCode {
    let file = match cierva_harness::rotor_file::load(&path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let a = match run_autorotation(
        &file.rotor,
        alpha_deg,
        airspeed_m_s,
        collective_deg,
        density_kg_m3,
        inflow,
    ) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {}: {e}", path.display());
            return ExitCode::from(if e.is_input() { 2 } else { 1 });
        }
    };
    match format {
        Format::Json => print_json(&a),
        Format::Text => {
            let d = |r: f64| r.to_degrees();
            println!(
                "{} ({}) at alpha {alpha_deg} deg, {airspeed_m_s} m/s",
                file.title, file.id
            );
            println!(
                "rotorspeed           {:.3} rad/s ({:.1} rpm)",
                a.omega_rad_s, a.rpm
            );
            println!("tip-speed ratio mu   {:.4}", a.tip_speed_ratio);
            println!(
                "lift coefficient     {:.5}  (on q pi R^2)",
                a.lift_coefficient
            );
            println!("drag coefficient     {:.5}", a.drag_coefficient);
            println!("L/D                  {:.3}", a.lift_to_drag);
            println!(
                "thrust coefficient   {:.6}  (T / rho pi R^2 (Omega R)^2)",
                a.thrust_coefficient
            );
            println!(
                "thrust, H-force      {:.1} N, {:.1} N",
                a.thrust_n, a.h_force_n
            );
            println!(
                "flapping a0 a1 b1    {:.3} {:.3} {:.3} deg",
                d(a.a0_rad),
                d(a.a1_rad),
                d(a.b1_rad)
            );
            println!(
                "inflow v0 v1s v1c    {:.3} {:.3} {:.3} m/s; lambda {:.5}; skew {:.2} deg",
                a.inflow.v0,
                a.inflow.v1s,
                a.inflow.v1c,
                a.inflow_ratio,
                d(a.skew_rad)
            );
            println!(
                "converged            residual {:.1e} in {} Newton iterations",
                a.residual_norm, a.iterations
            );
        }
    }
    ExitCode::SUCCESS
}
