//! `cierva estimate`: an aircraft's tail and pod coefficients estimated from its geometry by
//! published methods, step by step with sources and ranges (see
//! [`cierva_harness::estimate`] and `cierva_model::estimate`).

use super::*;
use cierva_harness::estimate::{self, Derivation};
use cierva_harness::inputs::aircraft::ConditionSpec;
use cierva_model::estimate::{Estimate, Method};

/// Estimate an aircraft's tail and pod coefficients from its geometry by published methods,
/// and print the derivation step by step: each step's value and range, its inputs and its
/// method, each method's source (with its equation or chart) and stated accuracy, and the
/// file's values beside the estimates. The fin's and tailplane's lift slopes (Helmbold's
/// equation in DATCOM's form, at the fin's effective aspect ratio with the end plates of
/// the body and the tailplane, DATCOM Sec. 5.3.1.1), their shares of the propeller's
/// slipstream and its dynamic pressure (momentum theory, at the propeller's operating point
/// in trim), the sidewash at the fin (the propeller's straightening and the pod's
/// cross-flow) and the pod's Munk couple (slender-body theory). The file gives the geometry
/// under `airframe`: a surface's `planform` (span_m, root_chord_m, tip_chord_m; optional
/// half_chord_sweep_deg, section_lift_slope_per_rad and, for the fin, body_depth_m), the
/// `pod` (length_m, width_m, height_m, centroid_m) and `estimates_at` (airspeed_mph,
/// mass_kg, density_altitude_ft: where to trim).
///
/// Example: `cierva estimate aircraft/vpm-m16.yaml --format json`
#[derive(clap::Args)]
pub(crate) struct EstimateArgs {
    /// An aircraft file with a surface's `planform` or a `pod` under `airframe` (see aircraft/).
    pub(crate) aircraft: PathBuf,
    /// True airspeed, mph, for the propeller's operating point (default: the file's
    /// `airframe.estimates_at`; with it, give --mass-kg and --density-altitude-ft or take the
    /// file's).
    #[arg(long)]
    pub(crate) airspeed_mph: Option<f64>,
    /// Mass, kg (default: the file's `estimates_at`, else its mass).
    #[arg(long)]
    pub(crate) mass_kg: Option<f64>,
    /// Density altitude, ft (default: the file's `estimates_at`, else 0).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) density_altitude_ft: Option<f64>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

pub(crate) fn estimate(a: EstimateArgs) -> Result<ExitCode, Error> {
    let file = load_aircraft(&a.aircraft)?;
    let given = file.estimate_inputs.as_ref().and_then(|i| i.at);
    let at = a.airspeed_mph.map(|v| ConditionSpec {
        airspeed_mph: v,
        mass_kg: a
            .mass_kg
            .or(given.map(|c| c.mass_kg))
            .unwrap_or(file.aircraft.mass.mass_kg),
        density_altitude_ft: a
            .density_altitude_ft
            .or(given.map(|c| c.density_altitude_ft))
            .unwrap_or(0.0),
    });
    let at = at.or_else(|| {
        given.map(|c| ConditionSpec {
            mass_kg: a.mass_kg.unwrap_or(c.mass_kg),
            density_altitude_ft: a.density_altitude_ft.unwrap_or(c.density_altitude_ft),
            ..c
        })
    });
    let spin = spinner("trimming at the estimates' condition");
    let result = estimate::derive(&file, at);
    spin.finish_and_clear();
    let d = match result {
        Ok(d) => d,
        Err(e) => {
            let input = matches!(
                e,
                estimate::EstimateRunError::NoGeometry(_)
                    | estimate::EstimateRunError::NoCondition(_)
                    | estimate::EstimateRunError::Blocked(..)
                    | estimate::EstimateRunError::Estimate(_)
                    | estimate::EstimateRunError::Input(_)
            );
            return Err(Error::of(
                input,
                format!("error: {}: {e}", a.aircraft.display()),
            ));
        }
    };
    match a.format {
        Format::Json => print_json(&d),
        Format::Text => print!("{}", text_report(&d)),
    }
    Ok(ExitCode::SUCCESS)
}

fn range(e: &Estimate) -> String {
    if e.lower == e.upper {
        format!("{:.4}", e.value)
    } else {
        format!("{:.4} [{:.4}, {:.4}]", e.value, e.lower, e.upper)
    }
}

/// The derivation as text: the condition, each step with its inputs and method, the methods'
/// sources and accuracies once each, and the file's values beside the estimates.
fn text_report(d: &Derivation) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let c = &d.condition;
    let op = &d.operating_point;
    let _ = writeln!(
        out,
        "{}: airframe estimates by published methods\n\npropeller in trim at {} mph, {} kg, density altitude {} ft: thrust {:.1} N, airspeed at the disc {:.2} m/s, density {:.4} kg/m^3, side force {:.3} N per m/s of sideslip",
        d.aircraft,
        c.airspeed_mph,
        c.mass_kg,
        c.density_altitude_ft,
        op.thrust_n,
        op.airspeed_m_s,
        op.density_kg_m3,
        op.side_force_per_m_s
    );
    let mut methods: Vec<Method> = Vec::new();
    let _ = writeln!(out, "\nsteps (value [range]):");
    for (k, s) in d.estimates.steps.iter().enumerate() {
        let tag = match s.method {
            Some(m) => {
                let i = methods.iter().position(|x| *x == m).unwrap_or_else(|| {
                    methods.push(m);
                    methods.len() - 1
                });
                format!("[M{}]", i + 1)
            }
            None => "[geometry]".to_string(),
        };
        let unit = if s.unit == "-" { "" } else { s.unit };
        let _ = writeln!(
            out,
            "{:>3}. {}: {} {unit} {tag}",
            k + 1,
            s.quantity,
            range(&s.value),
        );
        if !s.inputs.is_empty() {
            let inputs: Vec<String> = s
                .inputs
                .iter()
                .map(|(n, v)| format!("{n} {}", cierva_harness::units::sig(*v, 4)))
                .collect();
            let _ = writeln!(out, "     from {}", inputs.join(", "));
        }
    }
    let _ = writeln!(out, "\nmethods:");
    for (i, m) in methods.iter().enumerate() {
        let _ = writeln!(
            out,
            "[M{}] {}\n     source: {}\n     accuracy: {}",
            i + 1,
            m.name,
            m.source,
            m.accuracy
        );
    }
    let _ = writeln!(out, "\nthe file's values beside the estimates:");
    for x in &d.compared {
        let range = x
            .file_range
            .map(|(l, u)| format!(", its range [{l}, {u}]"))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "  {:<42} file {:<8} estimate {}{range}",
            x.field,
            cierva_harness::units::sig(x.file, 4),
            self::range(&x.estimate)
        );
    }
    out
}
