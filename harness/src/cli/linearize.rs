//! `cierva linearize`: the trimmed aircraft linearised (seed 001 Eqs. 10-12), derivatives by component.

use super::*;

/// Output of `linearize`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum LinearFormat {
    Text,
    Json,
    Yaml,
}

/// Trim and linearise an aircraft (seed 001 Eqs. 10-12): the nine rigid-body states and the
/// rotorspeed, controls in % of travel, blades and inflow quasi-steady. Prints the
/// derivatives, the modes with BCAR Section T, the longitudinal subset's modes and the
/// primary derivatives split by component (seed 000 Tables 1-2).
///
/// Example: `cierva linearize aircraft/vpm-m16.yaml --airspeed-mph 69 --mass-kg 425
/// --density-altitude-ft 2000 --format yaml > /tmp/model.yaml`
#[derive(clap::Args)]
pub(crate) struct LinearizeArgs {
    #[command(flatten)]
    flight: FlightArgs,
    /// text, json (derivatives and breakdown) or yaml (a flight-refs file with the model).
    #[arg(long, value_enum, default_value_t = LinearFormat::Text)]
    format: LinearFormat,
}

pub(crate) fn linearize(a: LinearizeArgs) -> Result<ExitCode, Error> {
    let LinearizeArgs { flight: f, format } = a;
    let file = load_flight(&f)?;
    let (request, loading) = (f.request(0.0), f.loading());
    let (t, lin) = cierva_harness::run::linearise::run_linearise(&file.aircraft, request, loading)
        .map_err(|e| {
            Error::of(
                e.is_input(),
                format!("error: {}: {e}", f.aircraft.display()),
            )
        })?;
    let mass = f.mass_kg.unwrap_or(file.aircraft.mass.mass_kg);
    let condition = format!(
        "{} mph, climb {} m/s, {} kg, density altitude {} ft",
        f.airspeed_mph, f.climb_m_s, mass, f.density_altitude_ft
    );
    match format {
        LinearFormat::Yaml => {
            let id = format!("{}-{}mph-{}kg", file.id, f.airspeed_mph, mass.round());
            print!(
                "{}",
                tables::linear_reference_yaml(
                    &id,
                    &format!("{} linearised at {condition}", file.title),
                    &format!(
                        "cierva linearize {} ({}), trim residual {:.1e}",
                        env!("CARGO_PKG_VERSION"),
                        f.aircraft.display(),
                        t.residual_norm
                    ),
                    &lin.model,
                    &cierva_harness::run::linearise::linear_units(),
                )
            );
        }
        LinearFormat::Json => {
            let derivs: Vec<serde_json::Value> = tables::PRIMARY_DERIVATIVES
                .iter()
                .filter_map(|n| {
                    let v = lin.model.derivative_value(n).ok()?;
                    let parts: serde_json::Map<String, serde_json::Value> = lin
                        .breakdown(n)
                        .ok()?
                        .into_iter()
                        .map(|(c, x)| (c, serde_json::json!(x)))
                        .collect();
                    Some(serde_json::json!({"name": n, "value": v, "components": parts}))
                })
                .collect();
            let m = &lin.model;
            let out = serde_json::json!({
                "condition": condition,
                "trim": t,
                "states": m.states(),
                "controls": m.controls(),
                "a": (0..m.states().len()).map(|i| (0..m.states().len()).map(|j| m.a()[(i, j)]).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "b": (0..m.states().len()).map(|i| (0..m.controls().len()).map(|j| m.b()[(i, j)]).collect::<Vec<_>>()).collect::<Vec<_>>(),
                "primary_derivatives": derivs,
            });
            print_json(&out);
        }
        LinearFormat::Text => {
            println!("{} at {condition}", file.title);
            println!(
                "trim: stick {:.2} % / {:.2} %, pedal {:.2} %, throttle {:.2} %, pitch {:.3} deg, roll {:.3} deg, rotor {:.1} rpm (residual {:.1e})",
                t.controls.stick_longitudinal_percent,
                t.controls.stick_lateral_percent,
                t.controls.pedal_percent,
                t.controls.throttle_percent,
                t.pitch_rad.to_degrees(),
                t.roll_rad.to_degrees(),
                t.rotor_rpm,
                t.residual_norm
            );
            println!("\nprimary derivatives by component (SI; controls per % of travel):");
            print!(
                "{}",
                tables::breakdown_table(&lin.model, &lin.components, tables::PRIMARY_DERIVATIVES)
            );
            match cierva_model::modes(&lin.model) {
                Ok(a) => {
                    println!("\nmodes, 10 states:");
                    print!("{}", tables::modes_table(&a));
                }
                Err(e) => println!("modes: {e}"),
            }
            if let Ok(lon) = lin.longitudinal()
                && let Ok(a) = cierva_model::modes(&lon)
            {
                println!("\nmodes, longitudinal [u w q theta Omega]:");
                print!("{}", tables::modes_table(&a));
            }
            println!("\nall derivatives:");
            print!("{}", tables::derivatives_table(&lin.model));
        }
    }
    Ok(ExitCode::SUCCESS)
}
