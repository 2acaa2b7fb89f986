//! `cierva modes`: modes, BCAR Section T and Milne values of a linear model, or its root locus.

use super::*;

/// Print the modes, BCAR Section T verdicts and weakly coupled systems values of a linear
/// model held in a reference file.
///
/// Example: `cierva modes flight-refs/seed002-vpm-m16-60kn.yaml`
///
/// With `--sweep Q_u=0.06:0.26:11`, prints the root locus instead: the modes at 11 evenly
/// spaced values of the derivative Q_u from 0.06 to 0.26 (in the derivative's own units).
#[derive(clap::Args)]
pub(crate) struct ModesArgs {
    /// A reference file with a `linear_model` block.
    file: PathBuf,
    /// Root-locus sweep: `DERIVATIVE=FROM:TO:POINTS`, for example `M_Omega=-0.0096:0.0096:9`.
    #[arg(long)]
    sweep: Option<String>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

pub(crate) fn modes(a: ModesArgs) -> Result<ExitCode, Error> {
    let ModesArgs {
        file,
        sweep,
        format,
    } = a;
    let r = reference::load(&file)?;
    let Some(model) = r.linear_model else {
        return Err(Error::input(format!(
            "{}: no `linear_model` block",
            file.display()
        )));
    };
    if let Some(spec) = sweep {
        return locus(&model, &spec, format);
    }
    let analysis = cierva_model::modes(&model)
        .map_err(|e| Error::input(format!("{}: {e}", file.display())))?;
    match format {
        Format::Json => {
            let assessed: Vec<_> = analysis
                .modes
                .iter()
                .map(|m| serde_json::json!({ "mode": m, "bcar": cierva_model::analysis::bcar::assess(m) }))
                .collect();
            let out = serde_json::json!({
                "file": file,
                "id": r.id,
                "states": analysis.states,
                "modes": assessed,
                "milne": milne_json(&model),
            });
            print_json(&out);
        }
        Format::Text => {
            println!("{} ({})\n{}\n", r.title, r.id, r.provenance.source);
            print!("{}", tables::modes_table(&analysis));
            println!();
            print!("{}", tables::milne_table(&model));
        }
    }
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn locus(
    model: &cierva_model::LinearModel,
    spec: &str,
    format: Format,
) -> Result<ExitCode, Error> {
    use cierva_model::analysis::locus;
    let parsed = spec.split_once('=').and_then(|(d, range)| {
        let p: Vec<&str> = range.split(':').collect();
        match p.as_slice() {
            [a, b, n] => Some((
                d,
                a.parse::<f64>().ok()?,
                b.parse::<f64>().ok()?,
                n.parse::<usize>().ok()?,
            )),
            _ => None,
        }
    });
    let Some((name, from, to, n)) = parsed.filter(|(_, a, b, _)| a.is_finite() && b.is_finite())
    else {
        return Err(Error::input(format!(
            "--sweep `{spec}`: expected DERIVATIVE=FROM:TO:POINTS, for example Q_u=0.06:0.26:11"
        )));
    };
    let element = model
        .derivative(name)
        .map_err(|e| Error::input(format!("--sweep: {e}")))?;
    let points = locus::root_locus(model, element, &locus::linspace(from, to, n))
        .map_err(|e| Error::input(format!("--sweep: {e}")))?;
    match format {
        Format::Json => {
            let out: Vec<_> = points
                .iter()
                .map(|p| serde_json::json!({ "value": p.value, "modes": p.analysis.modes }))
                .collect();
            let out = serde_json::json!({ "derivative": name, "points": out });
            print_json(&out);
        }
        Format::Text => {
            println!("root locus: {name} from {from} to {to} ({n} points)");
            for p in &points {
                let modes: Vec<String> = p
                    .analysis
                    .modes
                    .iter()
                    .map(|m| format!("{} {:.4}", m.kind.name(), m.eigenvalue))
                    .collect();
                println!(
                    "{name} = {:>12}  {}",
                    cierva_harness::units::sig(p.value, 6),
                    modes.join("; ")
                );
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn milne_json(m: &cierva_model::LinearModel) -> serde_json::Value {
    use cierva_model::analysis::milne;
    let eq13 = milne::eq13(m);
    serde_json::json!({
        "reduced": milne::reduced(m).and_then(|r| milne::as_array3(&r)).map_err(|e| e.to_string()),
        "eq13": eq13.as_ref().map_err(|e| e.to_string()),
        "cubic": eq13.map_err(|e| e.to_string()).and_then(|e| e.cubic().map_err(|e| e.to_string())).map(|c| {
            serde_json::json!({ "cubic": c, "sensitivity": c.sensitivity() })
        }),
    })
}
