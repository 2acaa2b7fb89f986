//! `cierva validate`: every case run (on every core), the table, the scoreboard and the report.

use super::*;
use cierva_harness::inputs::corrections;
use cierva_harness::suite::{case, review, scoreboard};

/// Run validation cases and print a table of every check.
///
/// Example: `cierva validate cases/seed002-vpm-m16-60kn.yaml --format json`
///
/// With `--corrections FIT_RESULT.yaml` (as `cierva fit` writes), every case whose aircraft or
/// rotor the file names is run with those corrections; expected failures that now pass are
/// reported as unexpected passes.
///
/// In CI: `--junit results.xml` writes JUnit XML (one testcase per check, the class as the
/// suite); `-k TEXT` and `--class CLASS` run some of the checks (their scores are shown, not
/// judged: a part of the suite is not the suite).
#[derive(clap::Args)]
pub(crate) struct ValidateArgs {
    /// Case files or folders searched for `*.yaml` (default: the suite's cases folder).
    paths: Vec<PathBuf>,
    /// Corrections files to apply (repeatable).
    #[arg(long)]
    corrections: Vec<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
    /// Where to write the report: `index.html` (self-contained, with plots) and
    /// `summary.md` (default: the suite's reports folder).
    #[arg(long)]
    report_dir: Option<PathBuf>,
    /// Write no report.
    #[arg(long)]
    no_report: bool,
    /// Also each check's uncertainty and, for validation checks, its V&V 20 verdict (as
    /// `cierva uncertainty`, with --samples and --seed): under `uncertainty` in the JSON,
    /// and in the report.
    #[arg(long)]
    uncertainty: bool,
    /// With --uncertainty: base points of the Saltelli design (at least 8).
    #[arg(long, default_value_t = 64, requires = "uncertainty")]
    samples: usize,
    /// With --uncertainty: the Sobol' sequence's seed.
    #[arg(long, default_value_t = 0, requires = "uncertainty")]
    seed: u32,
    /// With --uncertainty: write the studies' evaluations as a plan in DIR and stop, to run on
    /// an engine in shards (`cierva evaluate DIR --shard I/N`), then finish with --from-plan
    /// (docs/scaling.md).
    #[arg(
        long,
        value_name = "DIR",
        requires = "uncertainty",
        conflicts_with = "from_plan"
    )]
    plan: Option<PathBuf>,
    /// With --uncertainty: the run's checks as usual, each case's uncertainty from a plan's
    /// results (written by --plan, its shards run); the plan's samples and seed.
    #[arg(long, value_name = "DIR", requires = "uncertainty", conflicts_with_all = ["samples", "seed"])]
    from_plan: Option<PathBuf>,
    /// Write the run as JUnit XML to this file (one testcase per check, the class as the
    /// suite), for CI.
    #[arg(long)]
    junit: Option<PathBuf>,
    /// Only the checks whose `case::check` contains this text (any case; repeatable: any of
    /// them).
    #[arg(short = 'k', long = "select", value_name = "TEXT")]
    select: Vec<String>,
    /// Only the checks of this class: validation, cross_code, verification or regression
    /// (repeatable).
    #[arg(long = "class", value_name = "CLASS")]
    classes: Vec<String>,
}

/// Which checks a run takes (`-k`, `--class`): all where nothing is given.
#[derive(Debug, Clone, Default)]
struct Selection {
    texts: Vec<String>,
    classes: Vec<cierva_harness::checks::CheckClass>,
}

impl Selection {
    fn of(a: &ValidateArgs) -> Result<Self, Error> {
        use cierva_harness::checks::CheckClass;
        let names: Vec<String> = CheckClass::ALL
            .iter()
            .map(|c| c.name().to_string())
            .collect();
        let classes = a
            .classes
            .iter()
            .map(|c| {
                CheckClass::ALL
                    .into_iter()
                    .find(|k| k.name() == c.trim())
                    .ok_or_else(|| {
                        let hint = cierva_harness::inputs::yaml::nearest(c, &names)
                            .map(|n| format!(" (did you mean `{n}`?)"))
                            .unwrap_or_default();
                        Error::input(format!("--class `{c}`: one of {}{hint}", names.join(", ")))
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            texts: a.select.iter().map(|t| t.to_lowercase()).collect(),
            classes,
        })
    }

    fn everything(&self) -> bool {
        self.texts.is_empty() && self.classes.is_empty()
    }

    fn picks(&self, case: &case::Case, check: &cierva_harness::checks::Check) -> bool {
        let named = format!("{}::{}", case.id, check.id).to_lowercase();
        (self.texts.is_empty() || self.texts.iter().any(|t| named.contains(t)))
            && (self.classes.is_empty() || self.classes.contains(&check.class))
    }
}

pub(crate) fn validate(a: ValidateArgs) -> Result<ExitCode, Error> {
    use cierva_harness::uncertainty::{design::MIN_SAMPLES, propagate};
    if a.uncertainty && a.samples < MIN_SAMPLES {
        return Err(Error::input(format!(
            "--samples {}: give at least {MIN_SAMPLES}",
            a.samples
        )));
    }
    let uncertainty = a.uncertainty.then_some(propagate::PropagationSettings {
        samples: a.samples,
        seed: a.seed,
        validation_only: true,
        method: propagate::Propagation::Auto,
    });
    let selection = Selection::of(&a)?;
    if let (Some(dir), Some(settings)) = (&a.plan, uncertainty) {
        return write_plan(dir, &a.paths, &a.corrections, settings, &selection);
    }
    let uncertainty = match (&a.from_plan, uncertainty) {
        (Some(dir), Some(_)) => Some(Uncertainty::FromPlan(dir.clone())),
        (None, Some(settings)) => Some(Uncertainty::Run(settings)),
        (_, None) => None,
    };
    let report_dir = (!a.no_report).then_some(a.report_dir.clone());
    validate_with(
        a.paths,
        a.corrections,
        (a.format, a.junit),
        report_dir,
        uncertainty,
        &selection,
    )
}

/// Where a run's uncertainty comes from: computed here with these settings, or from a plan's
/// results.
enum Uncertainty {
    Run(cierva_harness::uncertainty::propagate::PropagationSettings),
    FromPlan(PathBuf),
}

/// `validate --uncertainty --plan DIR`: the studies of the cases (with the corrections) written
/// as a plan, as `cierva uncertainty --plan` writes them, and what to run next. A plan is of
/// whole cases: `-k` and `--class` are refused.
fn write_plan(
    dir: &std::path::Path,
    paths: &[PathBuf],
    corrections: &[PathBuf],
    settings: cierva_harness::uncertainty::propagate::PropagationSettings,
    selection: &Selection,
) -> Result<ExitCode, Error> {
    if !selection.everything() {
        return Err(Error::input(
            "--plan: a plan is of whole cases; give case paths, not -k or --class (--from-plan then takes them)",
        ));
    }
    let suite = suite()?;
    let paths = match paths.is_empty() {
        true => vec![suite.cases().to_path_buf()],
        false => paths.to_vec(),
    };
    let (correction_files, loaded, _, _) = inputs(&suite, &paths, corrections)?;
    let mut cases = Vec::new();
    for case in loaded {
        let case = case.map_err(Error::from)?;
        let (c, _) = cierva_harness::suite::case::with_corrections(&case, &correction_files)
            .map_err(|e| Error::input(format!("the corrections {e}")))?;
        cases.push(c);
    }
    use cierva_harness::plan;
    let file = plan::write(dir, &cases, corrections, settings.into()).map_err(Error::from)?;
    println!("{}", plan::next_steps(dir, &file, "validate --uncertainty"));
    Ok(ExitCode::SUCCESS)
}

/// How near a plan's nominal value of a quantity must be to the run's, relative: the same
/// computation on the same inputs gives the same number, so anything beyond rounding says the
/// plan is of another case, model or build.
const PLAN_NOMINAL_MATCH: f64 = 1e-9;

/// The finished studies of the plan in `dir`, checked before the run takes its time: a plan of
/// `validate --uncertainty` (validation checks, the automatic method), written with the same
/// corrections. Read without leaving the working folder (the run's paths stay its own).
fn studies_from_plan(
    dir: &std::path::Path,
    corrections: &[PathBuf],
) -> Result<Vec<cierva_harness::uncertainty::propagate::CaseUncertainty>, Error> {
    use cierva_harness::plan::{self, PlannedStudy};
    use cierva_harness::uncertainty::propagate::Propagation;
    let at = std::path::absolute(dir).unwrap_or_else(|_| dir.to_path_buf());
    let loaded = plan::load(&at).map_err(Error::from)?;
    match &loaded.file.study {
        PlannedStudy::Uncertainty(s) if s.validation_only && s.method == Propagation::Auto => {}
        _ => {
            return Err(Error::input(format!(
                "--from-plan {}: not a plan of `validate --uncertainty` (its validation checks, the automatic method): write it with `cierva validate --uncertainty --plan`, or finish it with `cierva uncertainty --from-plan`",
                dir.display()
            )));
        }
    }
    let canonical = |c: Vec<PathBuf>| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = (c.into_iter())
            .map(|p| std::fs::canonicalize(&p).unwrap_or(p))
            .collect();
        v.sort();
        v
    };
    let planned: Vec<PathBuf> = (loaded.file.corrections.iter())
        .map(|p| loaded.file.folder.join(p))
        .collect();
    if canonical(planned) != canonical(corrections.to_vec()) {
        return Err(Error::input(format!(
            "--from-plan {}: the plan was written with --corrections [{}], this run applies [{}]: give the same corrections",
            dir.display(),
            show(&loaded.file.corrections),
            show(corrections)
        )));
    }
    let done = plan::finish(&loaded).map_err(Error::from)?;
    Ok(done.into_iter().map(|(u, _)| u).collect())
}

/// Each case's uncertainty from a plan's studies (`studies_from_plan`): every case of the run
/// must be one of the plan's, its quantities kept for the checks the run took (`-k`,
/// `--class`), and each nominal value the run's within [`PLAN_NOMINAL_MATCH`].
fn attach_from_plan(
    run: &mut cierva_harness::report::Run,
    dir: &std::path::Path,
    mut done: Vec<cierva_harness::uncertainty::propagate::CaseUncertainty>,
) -> Result<(), Error> {
    let held: Vec<String> = done.iter().map(|u| format!("`{}`", u.case)).collect();
    for c in &mut run.cases {
        let id = &c.ran.case.id;
        let Some(k) = done.iter().position(|u| u.case == *id) else {
            return Err(Error::input(format!(
                "--from-plan {}: case `{id}` ({}) is not in the plan (it holds {}): write the plan for the cases this run takes",
                dir.display(),
                c.ran.case.path.display(),
                held.join(", ")
            )));
        };
        let mut u = done.swap_remove(k);
        u.results
            .retain(|q| c.ran.results.iter().any(|r| r.check == q.check));
        for q in &u.results {
            let value = (c.ran.results.iter())
                .filter(|r| r.check == q.check)
                .flat_map(|r| &r.quantities)
                .find(|x| x.quantity == q.quantity)
                .map(|x| x.value);
            let near = value.is_some_and(|v| {
                v == q.nominal
                    || (v - q.nominal).abs() <= PLAN_NOMINAL_MATCH * v.abs().max(q.nominal.abs())
            });
            if !near && q.quantity != "passes" {
                return Err(Error::input(format!(
                    "--from-plan {}: `{id}::{}` {}: the plan's nominal value is {}, this run's {}: the plan is of another case, model or build; write it again",
                    dir.display(),
                    q.check,
                    q.quantity,
                    q.nominal,
                    value.map_or("none".to_string(), |v| v.to_string())
                )));
            }
        }
        c.uncertainty = Some(u);
    }
    Ok(())
}

/// `validate` with its arguments checked: the report's folder (`None`: no report; `Some(None)`:
/// the suite's) and the uncertainty's settings (`None`: none).
fn validate_with(
    paths: Vec<PathBuf>,
    corrections: Vec<PathBuf>,
    (format, junit): (Format, Option<PathBuf>),
    report_dir: Option<Option<PathBuf>>,
    uncertainty: Option<Uncertainty>,
    selection: &Selection,
) -> Result<ExitCode, Error> {
    let started = std::time::Instant::now();
    let suite = suite()?;
    let whole_suite = paths.is_empty();
    let paths = if paths.is_empty() {
        vec![suite.cases().to_path_buf()]
    } else {
        paths
    };
    let report_dir = report_dir.map(|d| d.unwrap_or_else(|| suite.reports().to_path_buf()));
    let (correction_files, loaded, board, log) = inputs(&suite, &paths, &corrections)?;
    // A plan's studies are read and checked before the run.
    let planned = match &uncertainty {
        Some(Uncertainty::FromPlan(dir)) => Some((dir, studies_from_plan(dir, &corrections)?)),
        _ => None,
    };
    let loaded = selected(loaded, selection)?;
    let (mut run, corrected, errors, judged) =
        run_cases(&loaded, &correction_files, selection, &board);
    if let Some(Uncertainty::Run(settings)) = &uncertainty {
        attach_uncertainty(&mut run, *settings).map_err(Error::input)?;
    }
    if let Some((dir, done)) = planned {
        attach_from_plan(&mut run, dir, done)?;
    }
    run.input_errors = errors.clone();
    run.corrections = correction_files
        .iter()
        .map(|f| (f.path.clone(), f.corrections.describe()))
        .collect();
    run.seconds = started.elapsed().as_secs_f64();
    // Scores against corrected models are not the committed model's: shown, never judged.
    let judged_here = correction_files.is_empty() && selection.everything();
    let scores_failing = failing_scores(&judged, !judged_here);
    let ran_cases: Vec<&case::Case> = run.cases.iter().map(|c| &c.ran.case).collect();
    let (undeclared, unaccepted) = if judged_here {
        committed_state(&suite, &board, &ran_cases, whole_suite)
    } else {
        (Vec::new(), None)
    };
    run.scores = judged.clone();
    if report_dir.is_some() {
        run.score_versions = scoreboard::versions(&suite);
    }
    run.acceptances = log.acceptances;
    let results: Vec<CheckResult> = run
        .cases
        .iter()
        .flat_map(|c| c.ran.results.iter().cloned())
        .collect();
    let mut written = write_report(&run, report_dir.as_deref())?;
    if let Some(path) = junit {
        written.push(write_junit(path, &results, &errors)?);
    }
    let counts = tables::counts(&results);
    let corrections_used: Vec<serde_json::Value> = correction_files
        .iter()
        .map(|f| {
            serde_json::json!({
                "file": f.path.display().to_string(),
                "corrections": f.corrections,
            })
        })
        .collect();
    match format {
        Format::Json => {
            let out = serde_json::json!({
                "cases": loaded.len(),
                "corrections": corrections_used,
                "corrected_cases": corrected,
                "counts": counts,
                "scores": judged,
                "scores_no_longer_declared": undeclared,
                "acceptance_state": unaccepted,
                "counts_by_class": tables::counts_by_class(&results)
                    .into_iter()
                    .map(|(k, c)| (k.name(), c))
                    .collect::<std::collections::BTreeMap<_, _>>(),
                "input_errors": errors,
                "results": with_uncertainty(&run, &results),
                "report": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            });
            let mut out = out;
            if let (Some(_), serde_json::Value::Object(m)) = (uncertainty, &mut out) {
                m.insert("uncertainty".into(), uncertainty_cases(&run));
            }
            print_json(&out);
        }
        Format::Text => {
            print_text(
                &results,
                &judged,
                &errors,
                &correction_files,
                &corrected,
                (loaded.len(), &written),
                &suite,
            );
            if uncertainty.is_some() {
                print_uncertainty(&run);
            }
        }
    }
    if !errors.is_empty() {
        Ok(ExitCode::from(2))
    } else {
        let committed = (scores_failing.as_slice(), undeclared.as_slice(), unaccepted);
        Ok(failing(counts.failing() > 0, committed, format))
    }
}

/// Exit 1 when a check fails, a score moved or is no longer declared, or the committed files
/// are not what the acceptance log accepted (said in the text output), 0 otherwise.
fn failing(
    checks_fail: bool,
    (scores, undeclared, unaccepted): (&[&review::Judged], &[String], Option<String>),
    format: Format,
) -> ExitCode {
    if !checks_fail && scores.is_empty() && undeclared.is_empty() && unaccepted.is_none() {
        return ExitCode::SUCCESS;
    }
    if format == Format::Text {
        print_score_failures(scores, undeclared);
        if let Some(e) = &unaccepted {
            println!("the acceptance log: {e}");
        }
    }
    ExitCode::from(1)
}

/// Every case run on every core (with the corrections that apply,
/// [`cierva_harness::suite::validation::validate`]), in the order the cases were found, with the
/// sensitivity studies the cases ask for: the run, the cases that ran corrected, the input
/// errors, and the scores judged against `board`.
fn run_cases(
    loaded: &Loaded,
    correction_files: &[corrections::CorrectionsFile],
    selection: &Selection,
    board: &scoreboard::Board,
) -> (
    cierva_harness::report::Run,
    Vec<String>,
    Vec<String>,
    Vec<review::Judged>,
) {
    use cierva_harness::report;
    use cierva_harness::suite::validation;
    let checks: usize = loaded
        .iter()
        .flatten()
        .map(|c| c.checks.iter().filter(|k| selection.picks(c, k)).count())
        .sum();
    let bar = progress(checks as u64, "validate");
    let ran = validation::validate(
        loaded
            .iter()
            .map(|c| c.clone().map_err(|e| e.render()))
            .collect(),
        &validation::Options {
            corrections: correction_files,
            select: &|case, check| selection.picks(case, check),
            done: &|case, _| {
                bar.set_message(case.id.clone());
                bar.inc(1);
            },
        },
    );
    bar.finish_and_clear();
    // The sensitivity studies, one per case that asks for one, on every core.
    let studied = cierva_harness::run::parallel::parallel_map(&ran.cases, |c| {
        let parameters = c.case.sensitivity.as_ref()?;
        Some(
            cierva_harness::fit::sensitivity::from_case(&c.case, None).and_then(
                |(loading, request, quantities)| {
                    let (model, _) = cierva_harness::checks::flight_model(&c.case.subject)
                        .expect("from_case took a flight model");
                    cierva_harness::fit::sensitivity::run(
                        model.as_ref(),
                        request,
                        loading,
                        parameters,
                        &quantities,
                    )
                },
            ),
        )
    });
    let judged = ran.judged(board);
    let mut corrected: Vec<String> = Vec::new();
    let mut run = report::Run::default();
    for (c, sensitivity) in ran.cases.into_iter().zip(studied) {
        if !c.corrections.is_empty() {
            // Checks a file is not applied to by default say so, with why.
            let held_back = c
                .case
                .uncorrected
                .as_ref()
                .map(|u| format!(" [{}]", u.reasons.join("; ")))
                .unwrap_or_default();
            corrected.push(format!(
                "{} ({}){held_back}",
                c.case.id,
                c.corrections.join(", ")
            ));
        }
        run.cases.push(report::CaseRun {
            ran: c,
            sensitivity,
            uncertainty: None,
        });
    }
    (run, corrected, ran.errors, judged)
}

/// The text output: every check, the scoreboard, what needs a look, the counts by class.
fn print_text(
    results: &[CheckResult],
    judged: &[review::Judged],
    errors: &[String],
    correction_files: &[corrections::CorrectionsFile],
    corrected: &[String],
    (cases, written): (usize, &[PathBuf]),
    suite: &cierva_harness::suite::Suite,
) {
    print!("{}", tables::results_table(results));
    if !judged.is_empty() {
        println!("\nscoreboard ({}):", suite.scoreboard().display());
        for j in judged {
            println!("  {}", j.describe());
        }
    }
    for r in results.iter().filter(|r| !r.outcome.ok()) {
        println!("\n{}", r.explain());
    }
    for e in errors {
        println!("\n{e}");
    }
    for f in correction_files {
        println!(
            "\ncorrections {}: {}",
            f.path.display(),
            f.corrections.describe()
        );
    }
    if !correction_files.is_empty() {
        println!(
            "cases run with corrections: {}",
            if corrected.is_empty() {
                "none (no case's aircraft or rotor matches)".to_string()
            } else {
                corrected.join("; ")
            }
        );
    }
    println!(
        "\n{}, {}: {}, {}\nby class (only validation compares the model with measured data):\n{}",
        cierva_harness::units::count(cases, "case", "cases"),
        cierva_harness::units::count(results.len(), "check", "checks"),
        tables::counts(results).describe(),
        cierva_harness::units::count(errors.len(), "input error", "input errors"),
        tables::class_summary(results).trim_end()
    );
    if !written.is_empty() {
        println!("report: {}", show(written));
    }
}

/// Writes the run as JUnit XML (`--junit`), its folder made; the path written.
fn write_junit(
    path: PathBuf,
    results: &[CheckResult],
    errors: &[String],
) -> Result<PathBuf, Error> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::input(format!("cannot make {}: {e}", dir.display())))?;
    }
    let xml = cierva_harness::report::junit::junit_xml(results, errors);
    std::fs::write(&path, xml)
        .map_err(|e| Error::input(format!("cannot write {}: {e}", path.display())))?;
    Ok(path)
}

/// Every case file found, loaded or the error that stopped it.
type Loaded = Vec<Result<case::Case, cierva_harness::inputs::yaml::InputError>>;

/// The cases with a check the selection takes (files that did not load stay: their errors are
/// the run's whatever it selects); an error where it takes none.
fn selected(loaded: Loaded, selection: &Selection) -> Result<Loaded, Error> {
    if selection.everything() {
        return Ok(loaded);
    }
    let total: usize = loaded.iter().flatten().map(|c| c.checks.len()).sum();
    let kept: Loaded = loaded
        .into_iter()
        .filter(|c| match c {
            Ok(case) => case.checks.iter().any(|k| selection.picks(case, k)),
            Err(_) => true,
        })
        .collect();
    if !kept.iter().any(|c| c.is_ok()) {
        let asked: Vec<String> = selection
            .texts
            .iter()
            .map(|t| format!("-k `{t}`"))
            .chain(
                selection
                    .classes
                    .iter()
                    .map(|c| format!("--class {}", c.name())),
            )
            .collect();
        return Err(Error::input(format!(
            "no check matches {} among {} (-k matches text in `case-id::check-id`)",
            asked.join(" "),
            cierva_harness::units::count(total, "check", "checks")
        )));
    }
    Ok(kept)
}

/// The corrections files, the cases, the committed scoreboard and the acceptance log.
type Inputs = (
    Vec<corrections::CorrectionsFile>,
    Loaded,
    scoreboard::Board,
    review::Log,
);

/// What `validate` reads before it runs: the corrections files, the cases, the committed
/// scoreboard and the acceptance log (exit code 2 on bad input).
fn inputs(
    suite: &cierva_harness::suite::Suite,
    paths: &[PathBuf],
    corrections: &[PathBuf],
) -> Result<Inputs, Error> {
    let correction_files = load_corrections(corrections)?;
    let loaded = load_cases(paths).map_err(Error::input)?;
    if loaded.is_empty() {
        return Err(Error::input(format!(
            "no case files (*.yaml) under {}",
            show(paths)
        )));
    }
    let board = scoreboard::load(suite)?;
    let log = review::load_log(&suite.acceptances())?;
    Ok((correction_files, loaded, board, log))
}

/// Every case's uncertainty (`--uncertainty`): the cases one after another, each one's samples
/// on every core.
fn attach_uncertainty(
    run: &mut cierva_harness::report::Run,
    settings: cierva_harness::uncertainty::propagate::PropagationSettings,
) -> Result<(), String> {
    use cierva_harness::uncertainty::propagate;
    for c in &mut run.cases {
        let d = propagate::inputs(&c.ran.case).map_or(0, |i| i.len());
        let bar = progress(
            if d == 0 {
                0
            } else {
                (settings.samples * (d + 2)) as u64
            },
            &format!("uncertainty {}", c.ran.case.id),
        );
        // The study of the checks the run took (`-k`, `--class`), each with its own nominal
        // result: a study pairs a case's checks with their results in order.
        let (case, nominal) = ran_checks(&c.ran.case, &c.ran.results);
        let u =
            cierva_harness::uncertainty::study::propagate_from(&case, &nominal, settings, || {
                bar.inc(1)
            })
            .map_err(|e| format!("{}: {e}", c.ran.case.path.display()))?;
        bar.finish_and_clear();
        c.uncertainty = Some(u);
    }
    Ok(())
}

/// The case with only the checks a run took, in the case's order, and their results in that
/// order (matched by check id).
fn ran_checks(case: &case::Case, results: &[CheckResult]) -> (case::Case, Vec<CheckResult>) {
    let mut kept = case.clone();
    kept.checks
        .retain(|k| results.iter().any(|r| r.check == k.id));
    let nominal = (kept.checks.iter())
        .filter_map(|k| results.iter().find(|r| r.check == k.id).cloned())
        .collect();
    (kept, nominal)
}

/// The results as JSON, each with its quantities' uncertainty under `uncertainty` when it was
/// computed (`--uncertainty`); as they are otherwise.
fn with_uncertainty(
    run: &cierva_harness::report::Run,
    results: &[CheckResult],
) -> Vec<serde_json::Value> {
    let of =
        |r: &CheckResult| -> Vec<&cierva_harness::uncertainty::propagate::QuantityUncertainty> {
            run.cases
                .iter()
                .filter(|c| c.ran.case.id == r.case)
                .filter_map(|c| c.uncertainty.as_ref())
                .flat_map(|u| u.results.iter().filter(|q| q.check == r.check))
                .collect()
        };
    results
        .iter()
        .map(|r| {
            let mut v = serde_json::to_value(r).unwrap_or(serde_json::Value::Null);
            let u = of(r);
            if let (serde_json::Value::Object(m), false) = (&mut v, u.is_empty()) {
                m.insert(
                    "uncertainty".into(),
                    serde_json::to_value(u).unwrap_or(serde_json::Value::Null),
                );
            }
            v
        })
        .collect()
}

/// The verdicts of the validation quantities, per case and in all.
fn print_uncertainty(run: &cierva_harness::report::Run) {
    use cierva_harness::uncertainty::propagate::VerdictCounts;
    let cases: Vec<_> = run
        .cases
        .iter()
        .filter_map(|c| c.uncertainty.as_ref())
        .collect();
    println!("\nuncertainty (ASME V&V 20; validation quantities):");
    for c in &cases {
        let k = VerdictCounts::of(&c.results);
        if k.total() + k.apart() > 0 {
            println!("  {:48} {}", c.case, k.describe());
        }
    }
    let all = VerdictCounts::of(cases.iter().flat_map(|c| &c.results));
    println!("  {:48} {}", "all", all.describe());
}

/// Each case's propagation in the JSON (`--uncertainty`): how, what it cost, what failed.
fn uncertainty_cases(run: &cierva_harness::report::Run) -> serde_json::Value {
    run.cases
        .iter()
        .filter_map(|c| c.uncertainty.as_ref())
        .map(|u| {
            serde_json::json!({
                "case": u.case,
                "method": u.method,
                "inputs": u.inputs,
                "evaluations": u.evaluations,
                "failed_points": u.failed_points,
                "first_error": u.first_error,
                "refinement": u.refinement,
                "verdicts": cierva_harness::uncertainty::propagate::VerdictCounts::of(&u.results),
            })
        })
        .collect()
}

/// The scores that fail the run: worse than committed, better than committed (the board keeps
/// a gain only once it is accepted, so that losing it again fails), or not committed. None with
/// corrections (a corrected model's scores are not the committed model's: shown, never judged).
fn failing_scores(judged: &[review::Judged], corrected: bool) -> Vec<&review::Judged> {
    judged
        .iter()
        .filter(|j| !corrected && j.change != scoreboard::Change::Same)
        .collect()
}

/// What is wrong with the committed board and records, for a run that judges scores: the
/// committed scores no case that ran declares any more (a score leaves the board only through
/// `review --accept`), and, on the whole suite where it has committed any, why the scoreboard
/// and records are not what the acceptance log last accepted or why its chain does not hold
/// (an entry appended by hand).
fn committed_state(
    suite: &cierva_harness::suite::Suite,
    board: &scoreboard::Board,
    ran: &[&case::Case],
    whole_suite: bool,
) -> (Vec<String>, Option<String>) {
    let undeclared = review::undeclared(board, ran, whole_suite);
    let committed = suite.acceptances().exists() || suite.scoreboard().exists();
    let unaccepted = (whole_suite && committed)
        .then(|| review::acceptance_state(suite.reports()).err())
        .flatten();
    (undeclared, unaccepted)
}

/// What the text output says of the scores that fail the run and the committed scores no case
/// declares, with what to do.
fn print_score_failures(failing: &[&review::Judged], undeclared: &[String]) {
    use scoreboard::Change;
    let named = |which: &[Change]| {
        failing
            .iter()
            .filter(|j| which.contains(&j.change))
            .map(|j| format!("{} {}", j.score.case, j.score.id))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (worse, better) = (
        named(&[Change::Worse, Change::New]),
        named(&[Change::Better]),
    );
    if !worse.is_empty() {
        println!("scores worse than committed or not committed: {worse}");
    }
    if !better.is_empty() {
        println!(
            "scores better than committed: {better}; accept the gain so that losing it again fails"
        );
    }
    for u in undeclared {
        println!("{u}");
    }
    if !(worse.is_empty() && better.is_empty() && undeclared.is_empty()) {
        println!(
            "if intended, `cierva review --accept --reason TEXT --because CASE/ITEM=TEXT ...` \
             (`cierva review` lists the items)"
        );
    }
}

/// The report written into `dir` (nothing without one); exit 2 when it cannot be written.
fn write_report(
    run: &cierva_harness::report::Run,
    dir: Option<&Path>,
) -> Result<Vec<PathBuf>, Error> {
    let Some(dir) = dir else { return Ok(vec![]) };
    cierva_harness::report::write(run, dir).map_err(|e| {
        Error::input(format!(
            "could not write the report to {}: {e}",
            dir.display()
        ))
    })
}
