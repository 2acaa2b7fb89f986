//! `cierva uncertainty`: every check's quantities with the uncertainty of the model's estimated
//! inputs, its numerics and the data, and the V&V 20 verdict of each validation check (see
//! [`cierva_harness::uncertainty`]).

use super::*;
use cierva_harness::uncertainty::design::MIN_SAMPLES;
use cierva_harness::uncertainty::propagate::{
    self, CaseUncertainty, PropagationSettings, VerdictCounts,
};
use cierva_harness::uncertainty::summary;

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
    seconds: f64,
}

pub(crate) fn uncertainty(a: UncertaintyArgs) -> Result<ExitCode, Error> {
    if a.samples < MIN_SAMPLES {
        return Err(Error::input(format!(
            "--samples {}: give at least {MIN_SAMPLES} (the percentiles and Sobol' indices of fewer mean nothing)",
            a.samples
        )));
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
    let mut done: Vec<(CaseUncertainty, f64)> = Vec::new();
    for case in &cases {
        let d = propagate::inputs(case).map_or(0, |i| i.len());
        let bar = progress(
            if d == 0 {
                0
            } else {
                (a.samples * (d + 2)) as u64
            },
            &case.id,
        );
        let started = std::time::Instant::now();
        match propagate::propagate(case, settings, || bar.inc(1)) {
            Ok(u) => done.push((u, started.elapsed().as_secs_f64())),
            Err(e) => {
                bar.finish_and_clear();
                return Err(Error::input(format!("{}: {e}", case.path.display())));
            }
        }
        bar.finish_and_clear();
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
    let results: Vec<&propagate::QuantityUncertainty> =
        done.iter().flat_map(|(u, _)| &u.results).collect();
    let verdicts = VerdictCounts::of(results.iter().copied());
    match a.format {
        Format::Json => print_json(&Output {
            samples: a.samples,
            seed: a.seed,
            cases: done
                .iter()
                .map(|(u, s)| CaseSummary {
                    case: &u.case,
                    method: &u.method,
                    inputs: &u.inputs,
                    evaluations: u.evaluations,
                    failed_points: u.failed_points,
                    first_error: u.first_error.as_deref(),
                    refinement: &u.refinement,
                    seconds: *s,
                })
                .collect(),
            results: results.clone(),
            verdicts,
        }),
        Format::Text => {
            for (u, s) in &done {
                print!("{}", text_of(u, *s));
            }
            println!("validation quantities: {}", verdicts.describe());
        }
    }
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
fn text_of(u: &CaseUncertainty, seconds: f64) -> String {
    let mut out = format!(
        "{}\n  inputs ({}): {}\n  numerics: refined {}\n  {} evaluations in {seconds:.1} s; {} points failed{}\n",
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
        let top = r
            .contributors
            .first()
            .map_or("-".to_string(), |c| format!("{} ({:.2})", c.input, c.total));
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
    }
    out + "\n"
}
