//! `cierva identify`: frequency-domain equation-error identification of flight records, alone
//! or beside a model's linearisation.

use super::*;
use cierva_harness::ident;
use cierva_harness::inputs::record;

/// Output of `identify`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum IdentFormat {
    Text,
    Json,
    /// A flight-refs derivative table that cases can check models against.
    Yaml,
}

/// Identify stability and control derivatives from a flight record (frequency-domain
/// equation error, seed 000 Sec. IV): estimates, standard errors, 95 % bounds, fit quality,
/// correlations and warnings.
///
/// Example: `cierva identify /tmp/vpm-sweep.csv --format yaml > flight-refs/my-derivatives.yaml`
///
/// Against the model: `cierva identify /tmp/vpm-m16-70mph-sweep.csv --against aircraft/vpm-m16.yaml`
/// (the record from the `synth-flight` example).
#[derive(clap::Args)]
pub(crate) struct IdentifyArgs {
    /// Record CSVs, each with its sidecar YAML beside it; several records of one condition
    /// are identified together (their spectra concatenated).
    #[arg(required = true, num_args = 1..)]
    records: Vec<PathBuf>,
    /// Identification set-up file (overrides --setup).
    #[arg(long)]
    config: Option<PathBuf>,
    /// A built-in set-up, 0.05-2 Hz at 100 points (default: longitudinal for one record,
    /// coupled for several).
    #[arg(long, value_enum)]
    setup: Option<cierva_harness::ident::Setup>,
    /// Linearise this aircraft at the records' condition (their sidecars' `condition`) and
    /// print its derivatives beside the identified ones, marking those inside the 95 %
    /// bounds.
    #[arg(long)]
    against: Option<PathBuf>,
    /// A corrections file to apply to the aircraft of --against.
    #[arg(long, requires = "against")]
    corrections: Option<PathBuf>,
    /// Average the rotor's blade-passage shaking (N_b per revolution) out of every signal
    /// before the fit: the number of blades (a moving average over one blade-passage period
    /// at the trim's rotorspeed, the same on every signal).
    #[arg(long)]
    blades: Option<u32>,
    /// text, json, or yaml (a flight-refs derivative table).
    #[arg(long, value_enum, default_value_t = IdentFormat::Text)]
    format: IdentFormat,
    /// Another record (not used in the fit) to predict with the identified model: RMS error
    /// and Theil's inequality coefficient per state (seed 000 Fig. 10).
    #[arg(long)]
    predict: Option<PathBuf>,
}

pub(crate) fn identify(a: IdentifyArgs) -> Result<ExitCode, Error> {
    let (format, predict) = (a.format, a.predict.clone());
    let mut recs = Vec::with_capacity(a.records.len());
    for p in &a.records {
        recs.push(record::load(p)?);
    }
    let rec = &recs[0];
    let mut cfg = match &a.config {
        None => {
            let setup = a.setup.unwrap_or(if recs.len() > 1 {
                ident::Setup::Coupled
            } else {
                ident::Setup::Longitudinal
            });
            ident::ConfigSpec::for_setup(setup, rec).map_err(Error::input)?
        }
        Some(p) => ident::ConfigSpec::load(p)?,
    };
    // The command line's blade count over the set-up's.
    if a.blades.is_some() {
        cfg.blade_passage_blades = a.blades;
    }
    let result = ident::identify_records(&recs, &cfg).map_err(Error::input)?;
    let compared = match &a.against {
        None => None,
        Some(aircraft) => match linearised_against(aircraft, a.corrections.as_ref(), &recs, true) {
            Ok((model, flapping)) => {
                let flapping = flapping.unwrap_or_else(|| Err("not linearised".into()));
                let mut rows = ident::against(&result, &model);
                // The model with its flapping states: what the same set-up identifies from its
                // response to these records' controls, as the flights' identification should.
                match flapping.and_then(|f| ident::equivalent::identify_flapping(&recs, &cfg, &f)) {
                    Ok(as_identified) => ident::add_with_flapping(&mut rows, &as_identified),
                    Err(e) => {
                        eprintln!("note: no comparison with the model's flapping states: {e}")
                    }
                }
                Some(rows)
            }
            Err(e) => return Err(e),
        },
    };
    match format {
        IdentFormat::Json => match &compared {
            None => print_json(&result),
            Some(c) => print_json(&serde_json::json!({
                "identification": result,
                "against": c,
            })),
        },
        IdentFormat::Yaml => print!(
            "{}",
            ident::reference_yaml(&format!("{}-derivatives", rec.meta.id), &result, &recs)
        ),
        IdentFormat::Text => print_text(&recs, &result, compared.as_deref()),
    }
    if let Some(other) = predict {
        let outcome = record::load(&other)
            .map_err(|e| e.to_string())
            .and_then(|check| {
                let model = result.model.as_ref().ok_or("no identified model to fly")?;
                ident::predict(model, &check, &cfg)
            });
        match outcome {
            Ok(cmp) => {
                println!("prediction of {}:", other.display());
                for c in &cmp {
                    println!(
                        "  {:<8} RMS error {:>10}  Theil {:.4}",
                        c.signal,
                        cierva_harness::units::sig(c.rms_error, 3),
                        c.theil
                    );
                }
            }
            Err(e) => return Err(Error::input(e)),
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn print_text(
    recs: &[record::Record],
    result: &ident::Identification,
    compared: Option<&[ident::Against]>,
) {
    for rec in recs {
        println!(
            "{} ({}): {}",
            rec.meta.title, rec.meta.id, rec.meta.provenance.source
        );
        // How its columns were read (mapped, converted, left out), so that a wrong map or
        // travel shows before its numbers are trusted.
        for note in &rec.notes {
            println!("  read: {note}");
        }
    }
    match compared {
        None => {
            println!(
                "{:<14} {:>13} {:>12} {:>26}",
                "derivative", "estimate", "std error", "95 % bounds"
            );
            for d in &result.derivatives {
                println!(
                    "{:<14} {:>13} {:>12} {:>26}",
                    d.name,
                    cierva_harness::units::sig(d.estimate, 5),
                    cierva_harness::units::sig(d.standard_error, 3),
                    format!(
                        "[{}, {}]",
                        cierva_harness::units::sig(d.lower_95, 4),
                        cierva_harness::units::sig(d.upper_95, 4)
                    )
                );
            }
        }
        Some(rows) => {
            let inside = |b: bool| if b { "inside" } else { "OUTSIDE" };
            println!(
                "{:<14} {:>13} {:>26} {:>13} {:>8} {:>15} {:>8}",
                "derivative", "identified", "95 % bounds", "model", "", "with flapping", ""
            );
            for r in rows {
                println!(
                    "{:<14} {:>13} {:>26} {:>13} {:>8} {:>15} {:>8}{}",
                    r.name,
                    cierva_harness::units::sig(r.estimate, 5),
                    format!(
                        "[{}, {}]",
                        cierva_harness::units::sig(r.lower_95, 4),
                        cierva_harness::units::sig(r.upper_95, 4)
                    ),
                    cierva_harness::units::sig(r.model, 5),
                    inside(r.inside),
                    r.with_flapping
                        .map_or("-".into(), |v| cierva_harness::units::sig(v, 5)),
                    r.inside_with_flapping.map_or("", inside),
                    if r.primary { " (primary)" } else { "" }
                );
            }
            let primary: Vec<&ident::Against> = rows.iter().filter(|r| r.primary).collect();
            println!(
                "model (quasi-static linearisation) inside the identified bounds: {} of {} derivatives, {} of {} primary",
                rows.iter().filter(|r| r.inside).count(),
                rows.len(),
                primary.iter().filter(|r| r.inside).count(),
                primary.len()
            );
            if rows.iter().any(|r| r.with_flapping.is_some()) {
                let count = |rs: &[&ident::Against]| {
                    rs.iter()
                        .filter(|r| r.inside_with_flapping == Some(true))
                        .count()
                };
                let all: Vec<&ident::Against> = rows.iter().collect();
                println!(
                    "model with flapping states, identified from its response to these records' controls: {} of {} derivatives, {} of {} primary",
                    count(&all),
                    rows.len(),
                    count(&primary),
                    primary.len()
                );
            }
        }
    }
    for f in &result.fits {
        println!(
            "equation {}: R^2 {:.5}, condition number {:.2e}, {} dof",
            f.state, f.r_squared, f.condition_number, f.dof
        );
        for w in &f.warnings {
            println!("  warning: {w}");
        }
    }
    println!("status: {}", result.status);
}
