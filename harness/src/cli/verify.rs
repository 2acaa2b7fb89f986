//! `cierva verify`: time-domain verification, as CIFER's VERIFY does: the identified model and
//! cierva's model flown through each record's controls and compared with its measured states
//! (`ident::verify`).

use super::*;
use cierva_harness::ident::verify::{self as v, ModelRun, Verification};
use cierva_harness::ident::{ConfigSpec, model_for};
use cierva_harness::inputs::record::{self, Record};
use cierva_harness::inputs::yaml::InputError;
use cierva_harness::report::plot::{Figure, Series, Style, panels_svg};

/// Time-domain verification, as CIFER's VERIFY does (Tischler and Remple 2012): the
/// identified model (a derivative table from `identify --format yaml`) and cierva's model
/// (the aircraft linearised at the records' condition, as `identify --against`) are flown
/// through each record's controls (perturbations about the sidecar's trim, piecewise linear
/// between samples; RK4) from its first measured state, and compared with its measured
/// states (air data converted to centre-of-mass velocities, as the identification does).
///
/// Per output and model: Theil's inequality coefficient `TIC = rms(y - z) / (rms(y) +
/// rms(z))` (0 perfect, 1 worst; about 0.25-0.3 or less is usually taken as good agreement,
/// Jategaonkar 2006, ch. 11), the RMS error in the output's units, the mean error, and the
/// TIC with the mean error taken off (VERIFY fits a bias per output; a note beside the plain
/// TIC). Exit code 2 for bad input (a record without a control the model needs, a control
/// in a unit the model contradicts, an unknown output, an unreadable table).
///
/// Example: `cierva verify /tmp/vpm-m16-70mph-sweep.csv --identified
/// /tmp/vpm-m16-70mph-sweep-derivatives.yaml --against aircraft/vpm-m16.yaml --figure
/// /tmp/verify.svg` (the table from `cierva identify /tmp/vpm-m16-70mph-sweep.csv --format
/// yaml`, saved under its id).
#[derive(clap::Args)]
pub(crate) struct VerifyArgs {
    /// Records (CSV, with the YAML sidecar beside each), all at one flight condition: each is
    /// flown on its own, from its own first sample.
    #[arg(required = true)]
    pub(crate) records: Vec<PathBuf>,
    /// The identified model: a derivative table as `cierva identify RECORD --format yaml`
    /// writes it (its `estimate` column).
    #[arg(long)]
    pub(crate) identified: PathBuf,
    /// The aircraft, linearised at the records' condition (their sidecars' `condition`), as
    /// `identify --against` does: cierva's model, cut to the identified model's states and
    /// controls.
    #[arg(long)]
    pub(crate) against: PathBuf,
    /// A corrections file to apply to the aircraft of --against.
    #[arg(long)]
    pub(crate) corrections: Option<PathBuf>,
    /// The outputs to compare, units in the names (default: every state of the identified
    /// model): u_m_s, v_m_s, w_m_s, p_rad_s, q_rad_s, r_rad_s, phi_rad, theta_rad,
    /// omega_rotor_rad_s.
    #[arg(long, value_delimiter = ',')]
    pub(crate) outputs: Vec<String>,
    /// Write one SVG figure: a panel per output, the records (one after another in time), the
    /// identified model and cierva's model.
    #[arg(long)]
    pub(crate) figure: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

/// The level of TIC below which a match is usually taken as good.
const GOOD_TIC: &str = "TIC <= 0.25-0.3 is usually taken as good agreement (Jategaonkar, Flight Vehicle System Identification, 2006, ch. 11)";

/// The model names, in the order they are flown.
const IDENTIFIED: &str = "identified";
const CIERVA: &str = "cierva";

/// Panels wider than tall, one per output; at most this many points per line in the figure.
const FIGURE_WIDTH: u32 = 960;
const PANEL_HEIGHT: u32 = 260;
const FIGURE_POINTS: usize = 3000;

pub(crate) fn verify(a: VerifyArgs) -> Result<ExitCode, Error> {
    let mut records = Vec::with_capacity(a.records.len());
    for p in &a.records {
        records.push(record::load(p)?)
    }
    let identified = v::load_identified(&a.identified)?;
    let mut configs = Vec::with_capacity(records.len());
    for r in &records {
        configs.push(v::config_for(&identified, r)?)
    }
    // cierva's controls are in % of travel: a record's control in rad contradicts them.
    for (r, c) in records.iter().zip(&configs) {
        if let Some((control, channel)) =
            c.controls.iter().find(|(_, ch)| !ch.ends_with("_percent"))
        {
            let side = record::sidecar_path(&r.path);
            let src = cierva_harness::inputs::yaml::read(&side)?;
            return Err(Error::from(InputError::field(
                &side,
                &src,
                "controls",
                format!(
                    "`{channel}`: an aircraft's controls are in % of travel, so cierva's model needs `{control}_percent`"
                ),
            )));
        }
    }
    let available: Vec<String> = identified
        .states
        .iter()
        .map(|s| v::output_name(s))
        .collect();
    let outputs = if a.outputs.is_empty() {
        available.clone()
    } else {
        a.outputs.clone()
    };
    if let Some(bad) = outputs.iter().find(|o| !available.contains(o)) {
        return Err(Error::input(format!(
            "--outputs: `{bad}` is not an output of the identified model {} (it has {})",
            a.identified.display(),
            available.join(", ")
        )));
    }
    let spin = spinner("linearising the aircraft at the records' condition");
    let linearised = linearised_against(&a.against, a.corrections.as_ref(), &records, false);
    spin.finish_and_clear();
    let (lin, _) = linearised?;
    let mut results = Vec::with_capacity(records.len());
    for (r, c) in records.iter().zip(&configs) {
        let cierva = model_for(&lin, c).map_err(|e| {
            Error::input(format!(
                "{}: cierva's model in the identified model's structure: {e}",
                a.against.display()
            ))
        })?;
        let models: [(&str, &cierva_model::LinearModel, &ConfigSpec); 2] =
            [(IDENTIFIED, &identified.model, c), (CIERVA, &cierva, c)];
        match v::verify(r, &models, &outputs) {
            Ok(res) => results.push(res),
            Err(e) => return Err(Error::input(e)),
        }
    }
    let together = all_records(&results, &outputs);
    match a.format {
        Format::Json => print_json(&serde_json::json!({
            "identified": a.identified.display().to_string(),
            "against": a.against.display().to_string(),
            "corrections": a.corrections.as_ref().map(|p| p.display().to_string()),
            "cierva_model": "the aircraft's quasi-static linearisation at the records' condition, cut to the identified model's states and controls",
            "outputs": outputs,
            "records": results,
            "all_records": together,
            "guideline": GOOD_TIC,
        })),
        Format::Text => print_text(&a, &records, &results, &together),
    }
    if let Some(path) = &a.figure {
        let svg = panels_svg(
            &figure(&results, &outputs, &together),
            FIGURE_WIDTH,
            PANEL_HEIGHT,
        );
        let Some(svg) = svg else {
            return Err(Error::failure(format!(
                "nothing finite to draw in {}",
                path.display()
            )));
        };
        if let Err(e) = std::fs::write(path, svg) {
            return Err(Error::input(format!(
                "cannot write {}: {e}",
                path.display()
            )));
        }
        if a.format == Format::Text {
            println!("wrote {}", path.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Each model over every record, the records' samples joined.
fn all_records(results: &[Verification], outputs: &[String]) -> Vec<ModelRun> {
    [IDENTIFIED, CIERVA]
        .iter()
        .enumerate()
        .map(|(m, name)| {
            let fits = outputs
                .iter()
                .enumerate()
                .map(|(o, out)| {
                    let joined = |f: &dyn Fn(&Verification) -> &[f64]| -> Vec<f64> {
                        results.iter().flat_map(|r| f(r).to_vec()).collect()
                    };
                    let y = joined(&|r| &r.models[m].predicted[o]);
                    let z = joined(&|r| &r.measured[o]);
                    v::compare(out, &y, &z)
                })
                .collect();
            ModelRun {
                model: name.to_string(),
                outputs: fits,
                predicted: vec![],
            }
        })
        .collect()
}

fn print_text(a: &VerifyArgs, records: &[Record], results: &[Verification], all: &[ModelRun]) {
    println!(
        "identified: {} (its `estimate` column); cierva: {}{} linearised at the records' condition (quasi-static), cut to the identified model's states and controls",
        a.identified.display(),
        a.against.display(),
        a.corrections
            .as_ref()
            .map_or(String::new(), |c| format!(" with {}", c.display()))
    );
    let table = |runs: &[ModelRun]| {
        println!(
            "  {:<18} {:<11} {:>7} {:>15} {:>15} {:>17}",
            "output", "model", "TIC", "RMS error", "mean error", "TIC without mean"
        );
        for o in 0..runs.first().map_or(0, |r| r.outputs.len()) {
            for run in runs {
                let f = &run.outputs[o];
                let unit = v::output_unit(&f.output);
                println!(
                    "  {:<18} {:<11} {:>7.4} {:>15} {:>15} {:>17.4}",
                    f.output,
                    run.model,
                    f.theil,
                    format!("{} {unit}", cierva_harness::units::sig(f.rms_error, 3)),
                    format!("{} {unit}", cierva_harness::units::sig(f.bias, 3)),
                    f.theil_bias_removed
                );
            }
        }
    };
    for (r, res) in records.iter().zip(results) {
        println!(
            "{} ({}): {:.2} s, {} samples",
            r.path.display(),
            r.meta.id,
            res.duration_s,
            res.samples
        );
        table(&res.models);
    }
    if results.len() > 1 {
        println!("all records together:");
        table(all);
    }
    println!("{GOOD_TIC}");
}

/// One panel per output: the records one after another in time, and each model.
fn figure(results: &[Verification], outputs: &[String], all: &[ModelRun]) -> Vec<Figure> {
    let total: usize = results.iter().map(|r| r.samples).sum();
    let stride = total.div_ceil(FIGURE_POINTS).max(1);
    // The records' times, each starting where the one before ended.
    let mut times = Vec::with_capacity(total);
    let mut start = 0.0;
    for r in results {
        let dt = r.time_s.get(1).copied().unwrap_or(0.0);
        times.extend(r.time_s.iter().map(|t| start + t));
        start += r.duration_s + dt;
    }
    let thin = |values: Vec<f64>| -> Vec<(f64, f64)> {
        times
            .iter()
            .zip(values)
            .step_by(stride)
            .map(|(t, y)| (*t, y))
            .collect()
    };
    outputs
        .iter()
        .enumerate()
        .map(|(o, out)| {
            let measured = results.iter().flat_map(|r| r.measured[o].clone()).collect();
            let mut series = vec![Series {
                name: "record".into(),
                points: thin(measured),
                style: Style::Line,
                colour: Some(7),
            }];
            for (m, run) in all.iter().enumerate() {
                let predicted = results
                    .iter()
                    .flat_map(|r| r.models[m].predicted[o].clone())
                    .collect();
                series.push(Series {
                    name: format!("{} (TIC {:.3})", run.model, run.outputs[o].theil),
                    points: thin(predicted),
                    style: Style::Line,
                    colour: Some(m),
                });
            }
            Figure {
                title: format!("{out}: the record and the models flown through its controls"),
                x_label: "time, s".into(),
                y_label: format!("{out} perturbation, {}", v::output_unit(out)),
                series,
                ..Figure::default()
            }
        })
        .collect()
}
