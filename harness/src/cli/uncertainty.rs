//! `cierva uncertainty`: every check's quantities with the uncertainty of the model's estimated
//! inputs, its numerics and the data, and the V&V 20 verdict of each validation check (see
//! [`cierva_harness::uncertainty`]).

use super::*;
use cierva_harness::uncertainty::design::MIN_SAMPLES;
use cierva_harness::uncertainty::propagate::{
    self, CaseUncertainty, MAX_FAILED_SHARE, PropagationSettings, VerdictCounts,
};
use cierva_harness::uncertainty::summary;

/// The uncertainty of every check's quantities: the model's estimated inputs sampled over
/// their distributions (an aircraft file's `ranges:`, an external model's declared ranges;
/// corrections excluded, except those a `--corrections` file fitted: drawn from its fit's
/// `posterior:`) on Owen-scrambled Sobol' points in a Saltelli design, every check
/// evaluated at every point on every core; the numerical uncertainty from a grid study, each
/// discretisation parameter the model names refined alone (cierva's aircraft and rotors; an
/// external model's declared `refinements`), by Roache's grid convergence index; the data's
/// from a tolerance's confidence level. For each validation check the comparison of ASME V&V 20:
/// E = S - D, u_val = sqrt(u_num^2 + u_input^2 + u_D^2) and a verdict (agrees, model-form
/// error, inconclusive), whether a pass is fragile, and the inputs by Sobol' total index.
///
/// Example: `cierva uncertainty cases/cierva-table2-vpm-m16-70mph-max-weight.yaml --samples
/// 256 --format json`
#[derive(clap::Args)]
pub(crate) struct UncertaintyArgs {
    /// Case files or folders (default: cases/, and then only their validation checks, as with
    /// --validation-only).
    pub(crate) paths: Vec<PathBuf>,
    /// Base points of the Saltelli design (at least 8; a power of two balances the Sobol'
    /// points best): a case of d uncertain inputs takes samples x (d + 2) evaluations.
    #[arg(long, default_value_t = 256)]
    pub(crate) samples: usize,
    /// Seed of the scrambled Sobol' sequence (a whole number, 0 to 4294967295).
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u32,
    /// Only the validation checks (the comparison with measured data), as `validate
    /// --uncertainty` samples them: much cheaper on cases whose other checks are slow (the
    /// self-consistency cases' flapping linearisations), and what a run over the whole suite
    /// wants.
    #[arg(long)]
    pub(crate) validation_only: bool,
    /// How the inputs are propagated: auto (first order for a case with autorotation checks,
    /// whose evaluations are tables of autorotation searches, on any model; sampled for any
    /// other), sampled (the Saltelli design),
    /// or first-order (an additive surrogate from each input at its 5 % and 95 % quantiles,
    /// checked at four draws of every input: 2 d + 4 evaluations).
    #[arg(long, value_enum, default_value_t = cierva_harness::uncertainty::propagate::Propagation::Auto)]
    pub(crate) method: cierva_harness::uncertainty::propagate::Propagation,
    /// Corrections files (as `cierva fit` writes) applied as `validate --corrections` applies
    /// them: the parameters a file's fit fitted are drawn from its `posterior:` (not their
    /// ranges), and a cross-validated one adds its stated predictive error to `u_input`.
    #[arg(long, num_args = 1..)]
    pub(crate) corrections: Vec<PathBuf>,
    /// Also write every case's verdicts to the suite's reports/uncertainty-summary.yaml (which
    /// the README's "How sure" table is generated from and CI compares with a rerun). Only for
    /// the whole suite of the committed model: no case paths, no --corrections.
    #[arg(long)]
    pub(crate) write_summary: bool,
    /// Grow the design until every total Sobol' index (of every quantity the inputs move; the
    /// index the tables show) has a standard error at most this (0 to 1; 0.05 ranks inputs whose shares
    /// differ by a tenth): each case starts at --samples and doubles them, to at most
    /// 16384 base points (MAX_TARGET_SAMPLES), and says where it stopped and why. Sampled
    /// propagations only (a first-order one states no sampling error).
    #[arg(long)]
    pub(crate) target_se: Option<f64>,
    /// Write the study as a plan of independent evaluations to this folder, and stop: run its
    /// shards with `cierva evaluate DIR --shard I/N` on any engine (a Slurm job array, Dask),
    /// then finish it with `--from-plan DIR` (docs/scaling.md).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["from_plan", "target_se", "write_summary"])]
    pub(crate) plan: Option<PathBuf>,
    /// Finish the study a plan in this folder describes, from its shards' results (every
    /// setting is the plan's: give no case paths, samples, seed, method or corrections). The
    /// same numbers as the one-machine run; a missing shard is named, and no verdict drawn.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["paths", "samples", "seed", "method", "corrections", "validation_only", "target_se", "write_summary"])]
    pub(crate) from_plan: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

/// What `--format json` prints: every case's propagation, and every quantity's result in one
/// list.
#[derive(serde::Serialize)]
struct Output<'a> {
    samples: usize,
    seed: u32,
    cases: Vec<CaseSummary<'a>>,
    results: Vec<&'a propagate::QuantityUncertainty>,
    verdicts: VerdictCounts,
}

#[derive(serde::Serialize)]
struct CaseSummary<'a> {
    case: &'a str,
    method: &'a str,
    inputs: &'a [cierva_harness::uncertainty::distribution::Input],
    evaluations: usize,
    failed_points: usize,
    first_error: Option<&'a str>,
    refinement: &'a str,
    /// Its wall time, s (`--from-plan`: its evaluations' wall times added over the shards).
    seconds: f64,
    /// The base points the case was sampled at (`--samples`, or as `--target-se` grew them).
    samples: usize,
    /// Where `--target-se` stopped, and why.
    target_se: Option<&'a str>,
}

pub(crate) fn uncertainty(a: UncertaintyArgs) -> Result<ExitCode, Error> {
    if let Some(dir) = &a.from_plan {
        return from_plan(dir, a.format);
    }
    if a.samples < MIN_SAMPLES {
        return Err(Error::input(format!(
            "--samples {}: give at least {MIN_SAMPLES} (the percentiles and Sobol' indices of fewer mean nothing)",
            a.samples
        )));
    }
    if let Some(t) = a.target_se
        && !(t > 0.0 && t < 1.0)
    {
        return Err(Error::input(format!(
            "--target-se {t}: give a standard error between 0 and 1 (an index spans [0, 1]; 0.05 ranks inputs whose shares differ by a tenth)"
        )));
    }
    if a.write_summary && a.target_se.is_some() {
        return Err(Error::input(
            "--write-summary takes the committed --samples (64) and no --target-se: the summary is compared with a rerun at a fixed design",
        ));
    }
    if a.write_summary && !(a.paths.is_empty() && a.corrections.is_empty()) {
        return Err(Error::input(
            "--write-summary: the summary is the whole suite's, of its committed model: give no case paths and no --corrections",
        ));
    }
    // Found before the run, which takes minutes.
    let summary_path = if a.write_summary {
        Some(suite()?.uncertainty_summary())
    } else {
        None
    };
    let paths = if a.paths.is_empty() {
        vec![suite()?.cases().to_path_buf()]
    } else {
        a.paths.clone()
    };
    let cases = load_all(&paths)?;
    let files = load_corrections(&a.corrections)?;
    let mut corrected = Vec::with_capacity(cases.len());
    for case in cases {
        match cierva_harness::suite::case::with_corrections(&case, &files) {
            Ok((c, _)) => corrected.push(c),
            Err(e) => return Err(Error::input(format!("the corrections {e}"))),
        }
    }
    let cases = corrected;
    let settings = PropagationSettings {
        samples: a.samples,
        seed: a.seed,
        // The whole suite: its validation checks (the others include the self-consistency
        // cases' flapping linearisations, seconds a sample). Named cases: every check.
        validation_only: a.validation_only || a.paths.is_empty(),
        method: a.method,
    };
    if let Some(dir) = &a.plan {
        return write_plan(dir, &cases, &a.corrections, settings);
    }
    let mut done: Vec<(CaseUncertainty, f64)> = Vec::new();
    let mut sizes: Vec<(usize, Option<String>)> = Vec::new();
    for case in &cases {
        let (u, seconds, samples, said) = study(case, settings, a.target_se)?;
        done.push((u, seconds));
        sizes.push((samples, said));
    }
    if let Some(path) = &summary_path {
        let text = summary::render(&summary::of(&settings, done.iter().map(|(u, _)| u)));
        match cierva_harness::inputs::yaml::write_if_changed(path, &text) {
            Ok(changed) => eprintln!(
                "{} {}",
                if changed { "wrote" } else { "unchanged:" },
                path.display()
            ),
            Err(e) => {
                return Err(Error::failure(format!(
                    "cannot write {}: {e}",
                    path.display()
                )));
            }
        }
    }
    print_studies(&done, &sizes, (a.samples, a.seed), a.format, false);
    Ok(ExitCode::SUCCESS)
}

/// The studies, as text or JSON: each case's with its wall time (`summed`: its evaluations'
/// wall times added, a plan's), and the base points it ended at with what `--target-se` said
/// of it.
fn print_studies(
    done: &[(CaseUncertainty, f64)],
    sizes: &[(usize, Option<String>)],
    (samples, seed): (usize, u32),
    format: Format,
    summed: bool,
) {
    let results: Vec<&propagate::QuantityUncertainty> =
        done.iter().flat_map(|(u, _)| &u.results).collect();
    let verdicts = VerdictCounts::of(results.iter().copied());
    match format {
        Format::Json => print_json(&Output {
            samples,
            seed,
            cases: done
                .iter()
                .enumerate()
                .map(|(i, (u, s))| CaseSummary {
                    case: &u.case,
                    method: &u.method,
                    inputs: &u.inputs,
                    evaluations: u.evaluations,
                    failed_points: u.failed_points,
                    first_error: u.first_error.as_deref(),
                    refinement: &u.refinement,
                    seconds: *s,
                    samples: sizes[i].0,
                    target_se: sizes[i].1.as_deref(),
                })
                .collect(),
            results: results.clone(),
            verdicts,
        }),
        Format::Text => {
            for ((u, s), (n, said)) in done.iter().zip(sizes) {
                print!("{}", text_of(u, (*s, summed), *n));
                if let Some(said) = said {
                    println!("  --target-se: {said}");
                }
            }
            println!("validation quantities: {}", verdicts.describe());
        }
    }
}

/// `--plan DIR`: the studies' evaluations written as a plan, and what to run next.
fn write_plan(
    dir: &Path,
    cases: &[cierva_harness::suite::case::Case],
    corrections: &[PathBuf],
    settings: PropagationSettings,
) -> Result<ExitCode, Error> {
    use cierva_harness::plan;
    let file = plan::write(dir, cases, corrections, settings.into()).map_err(Error::from)?;
    println!("{}", plan::next_steps(dir, &file, "uncertainty"));
    Ok(ExitCode::SUCCESS)
}

/// `--from-plan DIR`: the studies finished from a plan's results.
fn from_plan(dir: &Path, format: Format) -> Result<ExitCode, Error> {
    use cierva_harness::plan;
    let loaded = plan::load(&plan::enter(dir)?).map_err(Error::from)?;
    let done = plan::finish(&loaded).map_err(Error::from)?;
    let cierva_harness::plan::PlannedStudy::Uncertainty(s) = loaded.file.study else {
        // `finish` refused it above.
        return Err(Error::input("not an uncertainty study's plan"));
    };
    let sizes: Vec<(usize, Option<String>)> = done.iter().map(|_| (s.samples, None)).collect();
    print_studies(&done, &sizes, (s.samples, s.seed), format, true);
    Ok(ExitCode::SUCCESS)
}

/// Every case under `paths`, loaded; exit 2 on the first that does not load.
fn load_all(paths: &[PathBuf]) -> Result<Vec<cierva_harness::suite::case::Case>, Error> {
    let loaded = match load_cases(paths) {
        Ok(l) if !l.is_empty() => l,
        Ok(_) => {
            return Err(Error::input(format!(
                "no case files (*.yaml) under {}",
                show(paths)
            )));
        }
        Err(e) => return Err(Error::input(e)),
    };
    loaded.into_iter().map(|c| c.map_err(Error::from)).collect()
}

/// A case's propagation as text: the inputs, then a row per quantity.
fn text_of(u: &CaseUncertainty, (seconds, summed): (f64, bool), samples: usize) -> String {
    let time = match summed {
        true => format!("{seconds:.1} s of evaluation, summed over a plan's shards"),
        false => format!("{seconds:.1} s"),
    };
    let mut out = format!(
        "{}\n  inputs ({}): {}\n  numerics (a grid convergence index per parameter): {}\n  {} evaluations in {time}; {} points failed{}\n",
        u.case,
        u.method,
        u.inputs.len(),
        u.refinement,
        u.evaluations,
        u.failed_points,
        u.first_error
            .as_ref()
            .map_or(String::new(), |e| format!(" (first: {e})"))
    );
    for i in &u.inputs {
        out += &format!(
            "    {:38} {:>10.4}  {}\n",
            i.name,
            i.nominal,
            i.distribution.describe()
        );
    }
    out += &format!(
        "  {:24} {:>11} {:>11} {:>23} {:>10} {:>9} {:>9} {:>9} {:>9}  {:16} {}\n",
        "check",
        "nominal S",
        "E = S - D",
        "95 % of inputs",
        "u_input",
        "u_num",
        "u_D",
        "u_val",
        "passes",
        "verdict",
        "largest contributor (total index)"
    );
    for r in &u.results {
        let num = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.3e}"));
        let verdict = match (r.verdict, r.fragile) {
            (Some(v), true) => format!("{}, FRAGILE", v.label()),
            (Some(v), false) => v.label().to_string(),
            (None, true) => "-, FRAGILE".into(),
            (None, false) => "-".into(),
        };
        let verdict = match r.circular {
            Some(_) => format!("{verdict}, CIRCULAR"),
            None => verdict,
        };
        let top = r.contributors.first().map_or("-".to_string(), |c| {
            format!("{} ({})", c.input, c.total_in_words(samples))
        });
        out += &format!(
            "  {:24} {:>11.4e} {:>11} [{:>10.3e}, {:>10.3e}] {:>10.3e} {:>9.2e} {:>9} {:>9} {:>8.0}%  {:16} {top}\n",
            format!("{} {}", r.check, r.quantity),
            r.nominal,
            num(r.estimate_error),
            r.p2_5,
            r.p97_5,
            r.u_input,
            r.u_num,
            num(r.u_data),
            num(r.u_val),
            100.0 * r.pass_fraction,
            verdict
        );
        // Failed draws: the reason where they leave no verdict (it names the causes), else
        // their count and causes.
        if r.verdict.is_none() && r.failed_samples as f64 > MAX_FAILED_SHARE * r.samples as f64 {
            out += &format!("      {}\n", r.reason);
        } else if r.failed_samples > 0 {
            out += &format!(
                "      failed at {} of {} draws: {}\n",
                r.failed_samples,
                r.samples,
                r.failure_causes.join("; ")
            );
        }
    }
    out + "\n"
}

/// The most base points `--target-se` grows a case's design to: 16384 (a Table 2 case of 16
/// inputs is 295,000 evaluations there, hours on 2 cores; the delta-method standard error
/// falls as 1/sqrt(N), so an index at 0.1 at 64 points reaches 0.05 at about 256).
pub(crate) const MAX_TARGET_SAMPLES: usize = 16384;

/// Whether `--target-se` wants the design doubled after a study at `samples` base points, and
/// what to say where it stops: reached (the largest index standard error and where), not
/// reached at the cap, or not applicable (nothing sampled).
fn target_reached(
    target: Option<f64>,
    u: &CaseUncertainty,
    samples: usize,
) -> (bool, Option<String>) {
    let Some(t) = target else {
        return (false, None);
    };
    match u.worst_index_se() {
        None => (
            false,
            Some(format!(
                "not applicable: {} states no sampled index",
                u.method
            )),
        ),
        Some((se, _)) if se > t && samples * 2 <= MAX_TARGET_SAMPLES => (true, None),
        Some((se, at)) if se > t => (
            false,
            Some(format!(
                "not reached: the largest index standard error is {se:.3} ({at}) at {samples} base points, the most it grows to (MAX_TARGET_SAMPLES)"
            )),
        ),
        Some((se, at)) => (
            false,
            Some(format!(
                "reached at {samples} base points: the largest index standard error is {se:.3} ({at}), at most {t}"
            )),
        ),
    }
}

/// One case's study at `settings`, its design doubled while `--target-se` wants it
/// ([`target_reached`]): the study, its wall time, the base points it ended at and what
/// `--target-se` says of it.
fn study(
    case: &cierva_harness::suite::case::Case,
    mut settings: PropagationSettings,
    target_se: Option<f64>,
) -> Result<(CaseUncertainty, f64, usize, Option<String>), Error> {
    let d = propagate::inputs(case).map_or(0, |i| i.len());
    let started = std::time::Instant::now();
    loop {
        let bar = progress(
            if d == 0 {
                0
            } else {
                (settings.samples * (d + 2)) as u64
            },
            &case.id,
        );
        let u = cierva_harness::uncertainty::study::propagate(case, settings, || bar.inc(1));
        bar.finish_and_clear();
        let u = u.map_err(|e| Error::input(format!("{}: {e}", case.path.display())))?;
        match target_reached(target_se, &u, settings.samples) {
            (true, _) => settings.samples *= 2,
            (false, said) => {
                return Ok((u, started.elapsed().as_secs_f64(), settings.samples, said));
            }
        }
    }
}
