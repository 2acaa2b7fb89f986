//! `cierva fit`: the empirical corrections fitted within bounds, with the fitted file and report.

use super::*;

/// Fit the model's empirical corrections (propeller blockage, hub angle-of-attack factor,
/// profile drag and its Reynolds-number exponent, pitch offset, lateral inflow offset,
/// elastic twist, hub drag) to flight references within bounds, and write the fitted
/// corrections and a before/after table.
///
/// The fit file names the subject (an aircraft at a mass and density altitude, a rotor in a
/// tunnel, or `case: cases/x.yaml` for the model behind the model interface that a case checks
/// with `external:`, fitted by the parameters it declares), the parameters with their bounds,
/// and the targets: checks of a case (each check's expected value, with its tolerance as the
/// standard error) or references written out, with optional hard or soft bounds. See
/// harness/src/fit/file.rs for the format.
///
/// Writes the corrections file (default: the suite's `corrections/fitted/<id>.yaml`, for
/// `cierva validate --corrections`) and a Markdown report (default: the suite's `reports/fits/<id>.md`).
/// Exit code 0 when the fit converged, 1 when it did not (iteration limit, infeasible, model
/// failure), 2 on bad input.
///
/// For a model too slow for one machine, `--evaluate-with CMD` sends each batch of the fit's
/// evaluations (the targets at a point; a Jacobian's steps together) through a plan of its own
/// under `--plans DIR`, which CMD runs on an engine (`{plan}`: the batch's folder; `{shards}`:
/// how many shards to run it in, at most `--shards`); the fit is the same bit for bit, and a fit
/// run again reads the batches already done (docs/scaling.md).
///
/// Example: `cierva fit fits/pca-2-tr515.yaml`
#[derive(clap::Args)]
pub(crate) struct FitArgs {
    /// The fit file.
    file: PathBuf,
    /// Where to write the fitted corrections.
    #[arg(long)]
    output: Option<PathBuf>,
    /// Where to write the Markdown before/after report.
    #[arg(long)]
    report: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
    /// Run each batch of evaluations through a plan with this command, such as `cierva
    /// evaluate {plan} --shard 1/1` or `python3 examples/distributed/run_dask.py {plan} --shards
    /// {shards}` (default: this machine's threads).
    #[arg(long, value_name = "CMD")]
    evaluate_with: Option<String>,
    /// With --evaluate-with: where the batches' plans go (default: `fit-plans/<fit id>` here).
    #[arg(long, value_name = "DIR", requires = "evaluate_with")]
    plans: Option<PathBuf>,
    /// With --evaluate-with: the most shards a batch is run in.
    #[arg(long, default_value_t = 2, requires = "evaluate_with")]
    shards: usize,
}

pub(crate) fn fit(a: FitArgs) -> Result<ExitCode, Error> {
    let FitArgs {
        file,
        output,
        report,
        format,
        evaluate_with,
        plans,
        shards,
    } = a;
    use cierva_harness::fit;
    let (mut f, output, report) = inputs(&file, output, report)?;
    let mut engine = None;
    if let Some(command) = &evaluate_with {
        let dir = plans.unwrap_or_else(|| Path::new("fit-plans").join(&f.id));
        let batches = std::sync::Arc::new(
            cierva_harness::plan::fit::batches(&f, &dir, command, shards).map_err(Error::input)?,
        );
        f.problem.executor = fit::Executor::Batches(batches.clone());
        engine = Some(batches);
    }
    let busy = spinner(&if f.starts > 1 {
        format!("fitting {} from {} starts", f.id, f.starts)
    } else {
        format!("fitting {}", f.id)
    });
    let run = fit::file::run(&f);
    busy.set_message(format!("cross-validating {}", f.id));
    let cv = cierva_harness::uncertainty::calibration::cross_validate(&f, &run, |g| {
        busy.set_message(format!("cross-validating {}: {g} done", f.id))
    });
    busy.finish_and_clear();
    // A batch the engine left without results: the fit went on without it, so what it found is
    // not the fit; nothing is written.
    if let Some(failure) = engine.as_ref().and_then(|e| e.failure()) {
        return Err(Error::failure(format!(
            "the fit of {} through plans stopped: {failure}",
            f.id
        )));
    }
    let cv = cv.map_err(|e| Error::failure(format!("cross-validation of {}: {e}", f.id)))?;
    let id = output
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(&f.id)
        .to_string();
    let command = format!("cierva fit {}", file.display());
    let mut spec = fit::file::corrections_file(&f, &run, &id, &command);
    spec.cross_validation = cv
        .as_ref()
        .map(|cv| cierva_harness::uncertainty::calibration::summary(&f, cv));
    spec.not_applied_to = cv
        .as_ref()
        .map(|cv| cierva_harness::uncertainty::calibration::not_applied_to(&f, cv))
        .unwrap_or_default();
    let mut md = cierva_harness::report::fit::markdown(&f, &run);
    if let Some(cv) = &cv {
        md += &cierva_harness::report::fit::cross_validation_markdown(cv);
    }
    // The before/after figure beside the Markdown (which shows it), and in `validate`'s report.
    let svg_path = report.with_extension("svg");
    let svg = cierva_harness::report::fit::figure(&f, &run).svg(640, 380);
    if let (Some(_), Some(name)) = (&svg, svg_path.file_name()) {
        md += &format!(
            "\n![Every target's error before and after, in standard errors]({})\n",
            name.to_string_lossy()
        );
    }
    let written = (|| -> Result<(), String> {
        let mut files = vec![
            (
                &output,
                serde_yaml::to_string(&spec).map_err(|e| e.to_string())?,
            ),
            (&report, md.clone()),
        ];
        if let Some(svg) = &svg {
            files.push((&svg_path, svg.clone()));
        }
        for (path, text) in files {
            write_making_folder(path, &text)?;
        }
        Ok(())
    })();
    if let Err(e) = written {
        return Err(Error::input(format!("writing the fit's results: {e}")));
    }
    match format {
        Format::Json => print_json(&serde_json::json!({
            "fit": f.id,
            "run": run,
            "cross_validation": cv,
            "corrections_file": output.display().to_string(),
            "report": report.display().to_string(),
            "figure": svg.as_ref().map(|_| svg_path.display().to_string()),
        })),
        Format::Text => {
            print!("{md}");
            println!(
                "wrote {}, {}{}",
                output.display(),
                report.display(),
                if svg.is_some() {
                    format!(" and {}", svg_path.display())
                } else {
                    String::new()
                }
            );
        }
    }
    if run.result.status == cierva_harness::fit::Status::Converged {
        Ok(ExitCode::SUCCESS)
    } else {
        Ok(ExitCode::from(1))
    }
}

/// The fit file, and where to write the corrections and the report (by default in the suite's
/// folders); a bad file or no suite is printed, exit code 2.
fn inputs(
    file: &Path,
    output: Option<PathBuf>,
    report: Option<PathBuf>,
) -> Result<(cierva_harness::fit::file::FitFile, PathBuf, PathBuf), Error> {
    use cierva_harness::suite::Suite;
    let f = cierva_harness::fit::file::load(file)?;
    let output = or_in_suite(output, Suite::fitted, format!("{}.yaml", f.id))?;
    let report = or_in_suite(report, Suite::fit_reports, format!("{}.md", f.id))?;
    Ok((f, output, report))
}
