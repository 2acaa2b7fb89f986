//! `cierva identify`: frequency-domain equation-error identification of a flight record.

use super::*;

pub(crate) fn identify(
    path: PathBuf,
    config: Option<PathBuf>,
    format: IdentFormat,
    predict: Option<PathBuf>,
) -> ExitCode {
    use cierva_harness::ident::{self, record};
    let rec = match record::load(&path) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{}", e.render());
            return ExitCode::from(2);
        }
    };
    let cfg = match config {
        None => ident::ConfigSpec::longitudinal(&rec),
        Some(p) => match cierva_harness::yaml::read(&p)
            .and_then(|src| cierva_harness::yaml::parse(&p, &src))
        {
            Ok(c) => c,
            Err(e) => {
                eprintln!("{}", e.render());
                return ExitCode::from(2);
            }
        },
    };
    let result = match ident::identify_record(&rec, &cfg) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    match format {
        IdentFormat::Json => print_json(&result),
        IdentFormat::Yaml => print!(
            "{}",
            ident::reference_yaml(&format!("{}-derivatives", rec.meta.id), &result, &rec)
        ),
        IdentFormat::Text => {
            println!(
                "{} ({}): {}",
                rec.meta.title, rec.meta.id, rec.meta.provenance.source
            );
            println!(
                "{:<14} {:>13} {:>12} {:>26}",
                "derivative", "estimate", "std error", "95 % bounds"
            );
            for d in &result.derivatives {
                println!(
                    "{:<14} {:>13} {:>12} {:>26}",
                    d.name,
                    text::sig(d.estimate, 5),
                    text::sig(d.standard_error, 3),
                    format!(
                        "[{}, {}]",
                        text::sig(d.lower_95, 4),
                        text::sig(d.upper_95, 4)
                    )
                );
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
                        text::sig(c.rms_error, 3),
                        c.theil
                    );
                }
            }
            Err(e) => {
                eprintln!("error: {e}");
                return ExitCode::from(2);
            }
        }
    }
    ExitCode::SUCCESS
}
