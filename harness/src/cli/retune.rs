//! `cierva retune`: from flight records to retuned corrections in one command.

use super::*;
use cierva_harness::fit::retune::{self, RetuneParameter};
use cierva_harness::inputs::corrections::CorrectionsFile;
use cierva_harness::inputs::record;
use cierva_harness::plan;
use cierva_harness::suite::Suite;

/// Retune corrections from flight records in one command: estimate each condition's frequency
/// responses from its records (coherence, random error; against the excitation a record's
/// sidecar names under `excitation`, unbiased by the pilot's loops, or else from the
/// controls), fit the named corrections with
/// clarabel so that the model's responses as flown (its linearisation with the rotor's
/// flapping) match them, weighted by their random errors, within bounds with their sources;
/// write the corrections file and a before/after report (each response's mismatch cost,
/// modes, predictions of records not used), and run the validation suite's cases for this
/// aircraft with the new corrections.
///
/// Your own simulation: `--case CASE` (a case whose model is `external`, protocol
/// `cierva-external/2`) instead of the aircraft file; `--fit` then names the parameters the
/// model declares, their bounds default to its declared ranges, and its responses come from
/// its linear model's A and B at each record's condition.
///
/// For a model too slow for one machine, `--evaluate-with CMD` sends each batch of the fit's
/// evaluations (the response points at a point; a Jacobian's steps together) through a plan of
/// its own under `--plans DIR`, which CMD runs on an engine (`{plan}`: the batch's folder;
/// `{shards}`: how many shards, at most `--shards`); the retune is the same bit for bit, and a
/// retune run again reads the batches already done. The model's responses before, between and
/// after the fits (one evaluation a condition each), the modes, `--predict` and the suite's run
/// stay on this machine (docs/scaling.md).
///
/// Example: `cierva retune aircraft/vpm-m16.yaml --records /tmp/vpm-m16-70mph-sweep.csv
/// --fit hub_aoa_factor --output /tmp/vpm-m16-retuned.yaml --report /tmp/vpm-m16-retuned.md`
#[derive(clap::Args)]
pub(crate) struct RetuneArgs {
    /// The aircraft file whose corrections to retune (or give `--case`).
    #[arg(required_unless_present = "case", conflicts_with = "case")]
    pub(crate) aircraft: Option<PathBuf>,
    /// A case whose model (`external`) is retuned by the parameters it declares.
    #[arg(long)]
    pub(crate) case: Option<PathBuf>,
    /// Flight records (CSV with sidecars): records at one condition give its frequency
    /// responses together, records at several conditions fit one set of corrections across
    /// them.
    #[arg(long, required = true, num_args = 1..)]
    pub(crate) records: Vec<PathBuf>,
    /// The corrections (or estimated physical parameters) to fit.
    #[arg(long, required = true, num_args = 1..)]
    pub(crate) fit: Vec<String>,
    /// Bounds as NAME=LO:HI (default: each correction's sourced range, a physical parameter's
    /// plausible range from the aircraft file).
    #[arg(long, num_args = 1..)]
    pub(crate) bounds: Vec<String>,
    /// The responses' states, comma-separated, of u,v,w,p,q,r,Omega (default: each excited
    /// control's own axis's, u,w,q,Omega or v,p,r).
    #[arg(long, value_delimiter = ',')]
    pub(crate) outputs: Vec<String>,
    /// The responses' window lengths, s (default: an eighth, a quarter and a half of the
    /// shortest record).
    #[arg(long, num_args = 1..)]
    pub(crate) windows_s: Vec<f64>,
    /// The responses' band, Hz: LOW HIGH (default: five periods of the longest window to 2 Hz,
    /// identification's band's top, below the rotor's harmonics).
    #[arg(long, num_args = 2)]
    pub(crate) band_hz: Vec<f64>,
    /// Records not used in the fit, predicted before and after.
    #[arg(long, num_args = 1..)]
    pub(crate) predict: Vec<PathBuf>,
    /// The corrections file to write (default: the suite's `corrections/retuned/<aircraft or
    /// case id>.yaml`).
    #[arg(long)]
    pub(crate) output: Option<PathBuf>,
    /// The before/after report (default: the suite's reports/retune/<output's stem>.md).
    #[arg(long)]
    pub(crate) report: Option<PathBuf>,
    /// Skip running the validation suite's cases with the new corrections.
    #[arg(long)]
    pub(crate) no_validate: bool,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
    /// Run each batch of the fit's evaluations through a plan with this command, such as
    /// `cierva evaluate {plan} --shard 1/1` or `python3 examples/distributed/run_dask.py {plan}
    /// --shards {shards}` (default: this machine's threads).
    #[arg(long, value_name = "CMD")]
    pub(crate) evaluate_with: Option<String>,
    /// With --evaluate-with: where the batches' plans go (default: `retune-plans/<output's
    /// stem>` here).
    #[arg(long, value_name = "DIR", requires = "evaluate_with")]
    pub(crate) plans: Option<PathBuf>,
    /// With --evaluate-with: the most shards a batch is run in.
    #[arg(long, default_value_t = 2, requires = "evaluate_with")]
    pub(crate) shards: usize,
}

pub(crate) fn retune(a: RetuneArgs) -> Result<ExitCode, Error> {
    let (loaded, id, shown) = load(&a)?;
    let retuned = match &loaded {
        Loaded::Aircraft(f) => retune::subject::Retuned::Aircraft(f),
        Loaded::Model(e) => retune::subject::Retuned::Model(e),
    };
    let records = a
        .records
        .iter()
        .map(|p| record::load(p))
        .collect::<Result<Vec<_>, _>>()?;
    let requests = requests(&a.fit, &a.bounds).map_err(Error::input)?;
    let output = or_in_suite(a.output.clone(), Suite::retuned, format!("{id}.yaml"))?;
    let mut how = how(&a);
    let engine = engine(&a, &loaded, &output, &id)?;
    if let Some(batches) = &engine {
        how.executor = cierva_harness::fit::Executor::Batches(batches.clone());
    }
    let busy = spinner("estimating the responses and fitting");
    let outcome = retune::retune(retuned, &records, &requests, &how);
    busy.finish_and_clear();
    // A batch the engine left without results: the fit went on without it, so what it found is
    // not the retune; nothing is written.
    if let Some(failure) = engine.as_ref().and_then(|e| e.failure()) {
        return Err(Error::failure(format!(
            "the retune of {shown} through plans stopped: {failure}"
        )));
    }
    let r = outcome.map_err(|e| match e {
        retune::RetuneError::Input(m) => Error::input(m),
        retune::RetuneError::Model(_) => Error::failure(format!("{shown}: {e}")),
    })?;
    let id = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let corrections = r.result.corrections();
    let command = std::env::args().skip(1).collect::<Vec<_>>().join(" ");
    let spec = retune::corrections_file(&r, retuned, &records, &id, &command);
    let yaml = serde_yaml::to_string(&spec).map_err(Error::input)?;
    write_making_folder(&output, &yaml).map_err(Error::input)?;
    // The assessment: the corrected model beside the uncorrected one.
    let uncorrected = cierva_harness::inputs::corrections::CorrectionSet::default();
    let both = [&uncorrected, &corrections];
    let modes = retune::modes(retuned, both, &r.conditions);
    let busy = spinner("the responses before and after");
    let comparisons = retuned
        .responses(&corrections, &r.responses, false)
        .and_then(|after| retune::responses::compare(&r.uncorrected, &after, &r.responses));
    busy.finish_and_clear();
    let comparisons =
        comparisons.map_err(|e| Error::input(format!("the responses before and after: {e}")))?;
    let predictions = predictions(&a.predict, retuned, both)?;
    let loaded = written(&output, &id, retuned, &spec);
    let revalidation = if a.no_validate {
        None
    } else {
        Some(revalidate(&loaded)?)
    };
    let report = or_in_suite(a.report.clone(), Suite::retune_reports, format!("{id}.md"))?;
    let figures = bode_figures(&report, &comparisons).map_err(Error::input)?;
    let md = cierva_harness::report::retune::markdown(
        &r,
        &shown,
        &modes,
        &predictions,
        revalidation.as_ref(),
        &figures,
    );
    write_making_folder(&report, &md).map_err(Error::input)?;
    match a.format {
        Format::Json => print_json(&serde_json::json!({
            "corrections": r.values_by_name(),
            "standard_errors": r.standard_errors_by_name(),
            "intervals_95": r.intervals_by_name(),
            "status": r.result.status.name(),
            "stalled": r.result.stalled(),
            "status_detail": r.result.status.detail(),
            "curvature_standard_errors": r
                .result
                .parameters
                .iter()
                .zip(&r.curvature_standard_errors)
                .map(|(k, s)| (k.name().to_string(), finite(*s)))
                .collect::<serde_json::Map<String, serde_json::Value>>(),
            "model": r.model,
            "reduced_chi_square": finite(r.reduced_chi_square),
            "targets": r.problem.targets.len(),
            "matched": r.matched,
            "responses": comparisons.iter().map(|c| serde_json::json!({
                "condition": c.condition,
                "input": c.input,
                "output": c.output,
                "frequencies_in_band": c.frequencies_in_band,
                "j_before": c.j_before,
                "j_after": c.j_after,
            })).collect::<Vec<_>>(),
            "modes": modes,
            "predictions": predictions,
            "revalidation": revalidation,
            "wrote": [output.display().to_string(), report.display().to_string()],
            "figures": figures.iter().filter_map(|(_, f)| f.clone()).collect::<Vec<_>>(),
        })),
        Format::Text => print_text(
            &r,
            (&retuned.name(), records.len()),
            &comparisons,
            revalidation.as_ref(),
            [&output, &report],
        ),
    }
    Ok(ExitCode::SUCCESS)
}

/// The corrections file just written, as `validate --corrections` would load it.
fn written(
    output: &Path,
    id: &str,
    retuned: retune::subject::Retuned<'_>,
    spec: &cierva_harness::inputs::corrections::CorrectionsFileSpec,
) -> CorrectionsFile {
    CorrectionsFile {
        path: output.to_path_buf(),
        id: id.to_string(),
        target: retuned.corrects(),
        corrections: spec.corrections.clone(),
        not_applied_to: vec![],
        // retune is not cross-validated: it states no predictive error.
        predictive_error: None,
        domain: spec.domain.clone(),
        calibrated_on: spec.calibrated_on.clone(),
        posterior: spec.posterior.clone(),
    }
}

/// The records `paths` (not used in the fit) predicted by `retuned` with each set of `both`.
fn predictions(
    paths: &[PathBuf],
    retuned: retune::subject::Retuned<'_>,
    both: [&cierva_harness::inputs::corrections::CorrectionSet; 2],
) -> Result<Vec<retune::Prediction>, Error> {
    let mut out = Vec::new();
    for p in paths {
        let rec = record::load(p)?;
        out.extend(
            retune::predict(retuned, both, &rec)
                .map_err(|e| Error::input(format!("predicting {}: {e}", p.display())))?,
        );
    }
    Ok(out)
}

/// With `--evaluate-with`: the batches through plans (under `--plans`, default
/// `retune-plans/<output's stem>`) that the retune's fit sends its evaluations to.
fn engine(
    a: &RetuneArgs,
    loaded: &Loaded,
    output: &Path,
    id: &str,
) -> Result<Option<std::sync::Arc<plan::fit::PlanBatches>>, Error> {
    let Some(command) = &a.evaluate_with else {
        return Ok(None);
    };
    let retuned = match loaded {
        Loaded::Aircraft(f) => retune::subject::Retuned::Aircraft(f),
        Loaded::Model(e) => retune::subject::Retuned::Model(e),
    };
    let stem = output
        .file_stem()
        .map_or(id.to_string(), |s| s.to_string_lossy().into_owned());
    let dir = (a.plans.clone()).unwrap_or_else(|| Path::new("retune-plans").join(stem));
    let Some(path) = a.aircraft.as_ref().or(a.case.as_ref()) else {
        return Err(Error::input("give the aircraft file or --case"));
    };
    let batches = plan::fit::retune_batches((retuned, path, id), &dir, command, a.shards)
        .map_err(Error::input)?;
    Ok(Some(std::sync::Arc::new(batches)))
}

/// What a retune corrects: cierva's aircraft file, or the model a case checks.
enum Loaded {
    Aircraft(Box<cierva_harness::inputs::aircraft::AircraftFile>),
    Model(cierva_harness::external::External),
}

/// The aircraft file or the case's model the arguments name, its id (the outputs' default
/// stem) and its path as given.
fn load(a: &RetuneArgs) -> Result<(Loaded, String, String), Error> {
    Ok(match (&a.aircraft, &a.case) {
        (Some(path), _) => {
            let file = load_aircraft(path)?;
            let id = file.id.clone();
            (
                Loaded::Aircraft(Box::new(file)),
                id,
                path.display().to_string(),
            )
        }
        (None, Some(path)) => {
            let case = cierva_harness::suite::case::load(path)?;
            let cierva_harness::suite::case::Subject::External(e) = case.subject else {
                return Err(Error::input(format!(
                    "{}: --case names a case whose model is `external` (its model is {}); retune cierva's own aircraft by its file",
                    path.display(),
                    case.subject.describe()
                )));
            };
            (Loaded::Model(*e), case.id, path.display().to_string())
        }
        (None, None) => return Err(Error::input("give the aircraft file or --case")),
    })
}

/// The parameters asked for, with `NAME=LO:HI` bounds.
fn requests(fit: &[String], bounds: &[String]) -> Result<Vec<RetuneParameter>, String> {
    let mut parsed = Vec::new();
    for b in bounds {
        let bad = || format!("--bounds `{b}`: write NAME=LO:HI");
        let (name, range) = b.split_once('=').ok_or_else(bad)?;
        let (lo, hi) = range.split_once(':').ok_or_else(bad)?;
        let lo: f64 = lo.trim().parse().map_err(|_| bad())?;
        let hi: f64 = hi.trim().parse().map_err(|_| bad())?;
        if !fit.iter().any(|f| f == name) {
            return Err(format!("--bounds names `{name}`, which --fit does not"));
        }
        parsed.push((name.to_string(), (lo, hi)));
    }
    Ok(fit
        .iter()
        .map(|name| RetuneParameter {
            name: name.clone(),
            bounds: parsed.iter().find(|(n, _)| n == name).map(|(_, b)| *b),
        })
        .collect())
}

/// A number for JSON: `null` when not finite.
fn finite(v: f64) -> serde_json::Value {
    serde_json::json!(v.is_finite().then_some(v))
}

/// The responses' estimation settings from the arguments.
fn how(a: &RetuneArgs) -> retune::How {
    retune::How {
        responses: retune::responses::ResponseSettings {
            windows_s: (!a.windows_s.is_empty()).then(|| a.windows_s.clone()),
            band_hz: (a.band_hz.len() == 2).then(|| [a.band_hz[0], a.band_hz[1]]),
            outputs: (!a.outputs.is_empty()).then(|| a.outputs.clone()),
        },
        executor: cierva_harness::fit::Executor::Local,
    }
}

/// Writes each response's Bode figure (the records' response, the model's before and after,
/// the coherence) beside the report, `<report stem>-<condition>-<output>-<input>.svg`, and
/// gives each comparison with its file's name (None where nothing finite is drawn).
fn bode_figures(
    report: &Path,
    comparisons: &[retune::responses::ResponseComparison],
) -> Result<Vec<(retune::responses::ResponseComparison, Option<String>)>, String> {
    use cierva_harness::report::plot;
    let stem = report
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "retune".into());
    let dir = report.parent().filter(|d| !d.as_os_str().is_empty());
    let mut out = Vec::new();
    for c in comparisons {
        let frequencies: Vec<f64> = c.points.iter().map(|p| p.frequency_hz).collect();
        let records: Vec<_> = c.points.iter().map(|p| Some(p.response)).collect();
        let coherence: Vec<f64> = c.points.iter().map(|p| p.coherence).collect();
        let figures = plot::bode_panels(
            &format!("{} {}/{}", c.condition, c.output, c.input),
            &frequencies,
            &[
                ("records", records),
                ("model before", c.before.iter().copied().map(Some).collect()),
                ("model after", c.after.iter().copied().map(Some).collect()),
            ],
            &coherence,
            cierva_harness::checks::frequency_response::COHERENCE_MIN,
        );
        let name = format!(
            "{stem}-{}-{}-{}.svg",
            c.condition.replace(' ', "-"),
            c.output,
            c.input
        );
        let file = match plot::log_x_panels_svg(&figures, 720, 260) {
            Some(svg) => {
                let path = dir.map_or(PathBuf::from(&name), |d| d.join(&name));
                if let Some(d) = dir {
                    std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
                }
                std::fs::write(&path, svg)
                    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                Some(name)
            }
            None => None,
        };
        out.push((c.clone(), file));
    }
    Ok(out)
}

/// The retune's summary for people: the fitted values with their standard errors, the fit, the
/// responses' J before and after, the suite's changes, and the files written.
fn print_text(
    r: &retune::Retune,
    (aircraft, records): (&str, usize),
    comparisons: &[retune::responses::ResponseComparison],
    revalidation: Option<&retune::Revalidation>,
    [output, report]: [&Path; 2],
) {
    use cierva_harness::units::count;
    println!(
        "retuned {} from {} at {}: {}",
        aircraft,
        count(records, "record", "records"),
        count(r.conditions.len(), "condition", "conditions"),
        r.result.status_described()
    );
    let sig = cierva_harness::units::sig;
    for (((k, v), se), i) in r
        .result
        .parameters
        .iter()
        .zip(&r.result.values)
        .zip(&r.result.standard_errors)
        .zip(r.intervals())
    {
        let interval = i.map_or("no interval".to_string(), |i| {
            format!("95 %: {}", i.described())
        });
        println!(
            "  {:<28} {:>12} +- {} ({interval})",
            k.name(),
            sig(*v, 5),
            sig(*se, 3),
        );
    }
    println!(
        "matched the records' frequency responses ({}, {}) with {}; reduced chi-square {}",
        count(r.problem.targets.len(), "target", "targets"),
        cierva_harness::report::retune::estimators(&r.responses),
        r.model,
        cierva_harness::units::sig(r.reduced_chi_square, 3)
    );
    if let Some(m) = &r.matched {
        println!("  matched processing: {}", m.described());
    }
    for w in &r.result.warnings {
        println!("  warning: {w}");
    }
    for c in comparisons {
        let j = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1}"));
        println!(
            "  {} {}/{}: J {} -> {} ({} frequencies in band)",
            c.condition,
            c.output,
            c.input,
            j(c.j_before),
            j(c.j_after),
            c.frequencies_in_band
        );
    }
    if let Some(v) = revalidation {
        for (class, [n, b, a]) in &v.classes {
            println!(
                "  suite, {class}: {}, {b} inside before, {a} after",
                count(*n, "check", "checks")
            );
        }
        for c in &v.changed {
            println!(
                "  changed: {} ({}) {} -> {}",
                c.check,
                c.class,
                if c.passed_before { "inside" } else { "outside" },
                if c.passed_after { "inside" } else { "outside" }
            );
        }
    }
    println!("wrote {} and {}", output.display(), report.display());
}

/// The suite's cases the retuned corrections apply to, run without and with them.
fn revalidate(loaded: &CorrectionsFile) -> Result<retune::Revalidation, Error> {
    let suite = suite()?;
    let busy = spinner("the validation suite with the new corrections");
    let cases: Vec<_> = load_cases(&[suite.cases().to_path_buf()])
        .map_err(|e| Error::input(format!("the validation suite: {e}")))?
        .into_iter()
        .filter_map(Result::ok)
        .collect();
    let v = retune::revalidate(&cases, loaded);
    busy.finish_and_clear();
    v.map_err(Error::input)
}
