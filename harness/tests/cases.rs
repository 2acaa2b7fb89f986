//! The validation suite: every check of every case under `cases/` is one trial, named
//! `<case-id>::<check-id>`; every case with a linear model also gets regression snapshots
//! (`<case-id>::snapshot-derivatives`, `::snapshot-modes`, `::snapshot-milne`) kept in
//! `reports/snapshots/` and reviewed with `cargo insta review`.
//!
//! A case whose expected failures are recorded (`reports/discrepancies/`) also gets
//! `<case-id>::discrepancy-records`, which fails on a record left for a check that is no longer
//! an expected failure.
//!
//! A case file that does not load is one failing trial, `<file-stem>::load`, whose message
//! names the file, line, column and field. No case files at all is a failing trial too.
//!
//! Each check is evaluated once, however many trials read its result (its own, the case's
//! `::scores`, `docs::readme-validation-table`).

use cierva_harness::checks::What;
use cierva_harness::report::tables;
use cierva_harness::suite::case::{Case, Subject};
use cierva_harness::suite::outcome;
use cierva_harness::{checks, load_cases};
use libtest_mimic::{Arguments, Failed, Trial};
use std::sync::{Arc, OnceLock};

/// A case and its checks' results, each computed on first use by whichever trial needs it first
/// (a trial that needs one being computed waits for it).
struct Evaluated {
    case: Case,
    results: Vec<OnceLock<outcome::CheckResult>>,
}

impl Evaluated {
    fn new(case: Case) -> Self {
        let results = case.checks.iter().map(|_| OnceLock::new()).collect();
        Self { case, results }
    }

    fn result(&self, index: usize) -> &outcome::CheckResult {
        self.results[index].get_or_init(|| outcome::run_check(&self.case, &self.case.checks[index]))
    }

    /// Every check's result, in the case's order.
    fn all(&self) -> Vec<outcome::CheckResult> {
        (0..self.results.len())
            .map(|i| self.result(i).clone())
            .collect()
    }
}

/// The repository's root: the suite this repository is (its `cierva.toml`).
fn repo_root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("harness/ sits in the repository root")
        .to_path_buf()
}

/// The repository's suite.
fn suite() -> cierva_harness::suite::Suite {
    cierva_harness::suite::Suite::open(&repo_root()).expect("the repository is a suite")
}

fn main() {
    let args = Arguments::from_args();
    let root = repo_root();
    let mut trials = Vec::new();
    match load_cases(&[root.join("cases")]) {
        Err(e) => trials.push(Trial::test("cases::discover", move || {
            Err(e.to_string().into())
        })),
        Ok(loaded) if loaded.is_empty() => trials.push(Trial::test("cases::discover", || {
            Err(
                "no case files (*.yaml) under cases/: the validation suite would check nothing"
                    .into(),
            )
        })),
        Ok(loaded) => {
            let mut cases = Vec::new();
            for c in loaded {
                match c {
                    Ok(case) => {
                        let case = Arc::new(Evaluated::new(case));
                        cases.push(case.clone());
                        add_case(&mut trials, case);
                    }
                    Err(e) => {
                        let stem = e
                            .path
                            .file_stem()
                            .map(|s| s.to_string_lossy().to_string())
                            .unwrap_or_default();
                        let msg = e.render();
                        trials.push(Trial::test(
                            format!("{stem}::load"),
                            move || Err(msg.into()),
                        ));
                    }
                }
            }
            let cases = Arc::new(cases);
            let docs: [(&str, DocsCheck); 7] = [
                ("docs::readme-validation-table", readme_validation_table),
                ("docs::readme-class-table", |c| {
                    generated(
                        "README.md",
                        "class-table",
                        &tables::class_table(&all_results(c)),
                    )
                }),
                ("docs::validation-class-table", |c| {
                    generated(
                        "docs/validation.md",
                        "class-table",
                        &tables::class_table(&all_results(c)),
                    )
                }),
                ("docs::validation-scoreboard", docs_scoreboard_table),
                ("docs::readme-how-sure-table", |c| {
                    how_sure(c, "README.md", "how-sure-table")
                }),
                ("docs::uncertainty-how-sure-table", |c| {
                    how_sure(c, "docs/uncertainty.md", "how-sure-table")
                }),
                ("docs::uncertainty-how-sure-cases", |c| {
                    how_sure(c, "docs/uncertainty.md", "how-sure-cases")
                }),
            ];
            for (name, check) in docs {
                let cases = cases.clone();
                trials.push(Trial::test(name, move || check(&cases)).with_kind("docs"));
            }
        }
    }
    libtest_mimic::run(&args, trials).exit();
}

/// A generated section of a document, checked against every case's results.
type DocsCheck = fn(&[Arc<Evaluated>]) -> Result<(), Failed>;

/// Renders one snapshot of a linear model.
type Snapshotter = fn(&cierva_model::LinearModel) -> Result<String, String>;

/// Every check's result, every case's.
fn all_results(cases: &[Arc<Evaluated>]) -> Vec<outcome::CheckResult> {
    cases
        .iter()
        .flat_map(|e| (0..e.case.checks.len()).map(|i| e.result(i).clone()))
        .collect()
}

/// The README's validation table must be what the validation checks give (every case is
/// loaded here, so the table is the suite's).
fn readme_validation_table(cases: &[Arc<Evaluated>]) -> Result<(), Failed> {
    let validation: Vec<outcome::CheckResult> = all_results(cases)
        .into_iter()
        .filter(|r| r.class == cierva_harness::suite::case::CheckClass::Validation)
        .collect();
    generated(
        "README.md",
        "validation-table",
        &tables::validation_table(&validation),
    )
}

/// A "How sure" section (`how-sure-table` or `how-sure-cases`) must be what the committed
/// uncertainty summary gives, and the summary must name the suite's cases with validation
/// checks (CI reruns the uncertainty and compares the summary; too slow for `cargo test`).
fn how_sure(cases: &[Arc<Evaluated>], file: &str, name: &str) -> Result<(), Failed> {
    use cierva_harness::uncertainty::summary;
    let s = summary::load(&suite()).map_err(|e| e.render())?;
    let validated: Vec<&str> = (cases.iter())
        .filter(|e| (e.case.checks.iter()).any(|k| k.class == checks::CheckClass::Validation))
        .map(|e| e.case.id.as_str())
        .collect();
    summary::check_cases(&s, &validated)?;
    let want = match name {
        "how-sure-table" => summary::table(&s),
        _ => summary::cases_list(&s),
    };
    generated(file, name, &want)
}

/// `docs/validation.md`'s scoreboard table must be the committed scoreboard's (which the
/// `::scores` trials hold to the run, and the acceptance log to its last entry).
fn docs_scoreboard_table(cases: &[Arc<Evaluated>]) -> Result<(), Failed> {
    let board = cierva_harness::suite::scoreboard::load(&suite()).map_err(|e| e.render())?;
    let cases: Vec<&cierva_harness::suite::case::Case> = cases.iter().map(|e| &e.case).collect();
    generated(
        "docs/validation.md",
        "scoreboard-table",
        &tables::scoreboard_table(&board, &cases),
    )
}

/// A generated section of a document: the text between `<!-- NAME:start ... -->` (to the end
/// of its line) and `<!-- NAME:end -->` in `file` (relative to the repository) must be `want`.
fn generated(file: &str, name: &str, want: &str) -> Result<(), Failed> {
    let text = std::fs::read_to_string(repo_root().join(file))?;
    cierva_harness::report::generated::check(file, &text, name, want).map_err(Into::into)
}

fn add_case(trials: &mut Vec<Trial>, evaluated: Arc<Evaluated>) {
    let case = &evaluated.case;
    for (index, check) in case.checks.iter().enumerate() {
        let e = evaluated.clone();
        trials.push(
            Trial::test(format!("{}::{}", case.id, check.id), move || {
                let r = e.result(index);
                if r.outcome.ok() {
                    Ok(())
                } else {
                    Err(r.explain().into())
                }
            })
            .with_kind("validation"),
        );
    }
    if !case.scores.is_empty() {
        let e = evaluated.clone();
        trials.push(
            Trial::test(format!("{}::scores", case.id), move || {
                use cierva_harness::suite::{review, scoreboard};
                let suite = suite();
                let board = scoreboard::load(&suite).map_err(|e| e.render())?;
                let results = e.all();
                let judged = review::judge(&board, review::scores_of(&e.case, &results));
                let bad: Vec<String> = judged
                    .iter()
                    .filter(|j| {
                        matches!(j.change, scoreboard::Change::Worse | scoreboard::Change::New)
                    })
                    .map(|j| format!("  {}", j.describe()))
                    .collect();
                if bad.is_empty() {
                    Ok(())
                } else {
                    Err(format!(
                        "scores worse than committed in {} by more than their noise floor, or not committed:\n{}\n\
                         if the change is intended, `cargo run --release -- review --accept --reason TEXT` \
                         commits the new values (an improvement is committed the same way) and logs why",
                        suite.scoreboard().display(),
                        bad.join("\n")
                    )
                    .into())
                }
            })
            .with_kind("scoreboard"),
        );
    }
    if let Some(rec) = &case.recorded {
        let (ev, rec) = (evaluated.clone(), rec.clone());
        trials.push(
            Trial::test(format!("{}::discrepancy-records", case.id), move || {
                let c = &ev.case;
                let stale: Vec<&String> = rec
                    .checks
                    .keys()
                    .filter(|id| {
                        !c.checks
                            .iter()
                            .any(|k| &k.id == *id && k.expected_failure.is_some())
                    })
                    .collect();
                if stale.is_empty() {
                    Ok(())
                } else {
                    Err(format!(
                        "{}: records for checks that are not expected failures of the case: {stale:?}; \
                         run `cargo run --release -- review --accept --reason TEXT`",
                        c.records_dir.as_deref().map_or_else(|| c.path.clone(), |d| cierva_harness::suite::discrepancy::path_for(d, &c.id)).display()
                    )
                    .into())
                }
            })
            .with_kind("regression"),
        );
    }
    if let Subject::Rotor { .. } = &case.subject {
        let ev = evaluated.clone();
        trials.push(
            Trial::test(format!("{}::snapshot-autorotation", case.id), move || {
                let c = &ev.case;
                let Subject::Rotor { file, solver } = &c.subject else {
                    unreachable!()
                };
                let rows: Vec<_> = c
                    .checks
                    .iter()
                    .filter_map(|k| match &k.what {
                        What::Autorotation(a) => Some((k.id.clone(), &a.tunnel)),
                        _ => None,
                    })
                    .map(|(id, t)| {
                        let q =
                            checks::autorotation::autorotation_quantities(&file.rotor, *solver, t);
                        (id, checks::autorotation::quantities_or_reason(q))
                    })
                    .collect();
                snapshot(c, "autorotation", Ok(tables::autorotation_table(&rows)))
            })
            .with_kind("snapshot"),
        );
    }
    let has_time_history = case
        .checks
        .iter()
        .any(|k| matches!(k.what, What::TimeHistory(_)));
    if let Subject::Aircraft { file, loading } = &case.subject
        && has_time_history
    {
        let (ev, file, loading) = (evaluated.clone(), file.clone(), *loading);
        trials.push(
            Trial::test(format!("{}::snapshot-time-histories", case.id), move || {
                let c = &ev.case;
                let mut rows = Vec::new();
                for k in &c.checks {
                    if let What::TimeHistory(t) = &k.what {
                        let (m, _) = checks::time_history::time_history_metrics(&file, loading, t)?;
                        rows.push((k.id.clone(), m));
                    }
                }
                snapshot(c, "time-histories", Ok(tables::time_history_table(&rows)))
            })
            .with_kind("snapshot"),
        );
    }
    let trim_requested = case.checks.iter().any(|k| {
        matches!(k.what, What::Trim(_) | What::TrimSweep(_))
            || k.linear().is_some_and(|l| l.condition.is_some())
    });
    if let Subject::Aircraft { .. } = &case.subject
        && trim_requested
    {
        let ev = evaluated.clone();
        trials.push(
            Trial::test(format!("{}::snapshot-trim", case.id), move || {
                let c = &ev.case;
                let Subject::Aircraft { file, loading } = &c.subject else {
                    unreachable!()
                };
                let mut requests = Vec::new();
                for k in c.checks.iter() {
                    if matches!(k.what, What::TimeHistory(_)) {
                        continue;
                    }
                    if let Some(r) = k.condition() {
                        requests.push(r);
                    }
                    let sweep = match &k.what {
                        What::TrimSweep(s) => s.sweep_mph.as_slice(),
                        _ => &[],
                    };
                    for v in sweep {
                        requests.push(cierva_harness::TrimRequest {
                            airspeed_mph: *v,
                            climb_m_s: 0.0,
                            turn_rate_deg_s: 0.0,
                        });
                    }
                }
                requests.sort_by(|a, b| {
                    (a.airspeed_mph, a.climb_m_s, a.turn_rate_deg_s)
                        .partial_cmp(&(b.airspeed_mph, b.climb_m_s, b.turn_rate_deg_s))
                        .expect("finite conditions")
                });
                requests.dedup();
                let columns: Vec<_> = requests
                    .iter()
                    .map(|r| {
                        let mut label = format!("{} mph", r.airspeed_mph);
                        if r.climb_m_s != 0.0 {
                            label += &format!(" {:+} m/s", r.climb_m_s);
                        }
                        if r.turn_rate_deg_s != 0.0 {
                            label += &format!(" {:+} deg/s", r.turn_rate_deg_s);
                        }
                        (label, checks::trim::trim_quantities(file, *loading, *r))
                    })
                    .collect();
                snapshot(c, "trim", Ok(tables::trim_table(&columns)))
            })
            .with_kind("snapshot"),
        );
    }
    if let Subject::Aircraft { .. } = &case.subject {
        // One snapshot of the linearised model per condition its derivative, mode, BCAR or
        // Milne checks use.
        let mut conditions: Vec<cierva_harness::TrimRequest> = case
            .checks
            .iter()
            .filter_map(|k| k.linear()?.condition)
            .collect();
        conditions.sort_by(|a, b| {
            (a.airspeed_mph, a.climb_m_s)
                .partial_cmp(&(b.airspeed_mph, b.climb_m_s))
                .expect("finite conditions")
        });
        conditions.dedup();
        for r in conditions {
            let ev = evaluated.clone();
            let label = format!("{}mph", r.airspeed_mph)
                + &if r.climb_m_s != 0.0 {
                    format!("-climb{}", r.climb_m_s)
                } else {
                    String::new()
                };
            let what = format!("linear-{label}");
            trials.push(
                Trial::test(format!("{}::snapshot-{what}", case.id), move || {
                    let c = &ev.case;
                    let Subject::Aircraft { file, loading } = &c.subject else {
                        unreachable!()
                    };
                    let body = cierva_harness::linearise_cached(file, r, *loading).and_then(|l| {
                        let modes = cierva_model::modes(&l.1.model).map_err(|e| e.to_string())?;
                        Ok(format!(
                            "{}\n{}\n{}",
                            tables::breakdown_table(&l.1, tables::PRIMARY_DERIVATIVES),
                            tables::modes_table(&modes),
                            tables::derivatives_table(&l.1.model)
                        ))
                    });
                    snapshot(c, &what, body)
                })
                .with_kind("snapshot"),
            );
        }
    }
    if let Subject::Linear { model, .. } = &case.subject {
        let snaps: Vec<(&str, Snapshotter)> = vec![
            ("derivatives", |m| Ok(tables::derivatives_table(m))),
            ("modes", |m| {
                cierva_model::modes(m)
                    .map(|a| tables::modes_table(&a))
                    .map_err(|e| e.to_string())
            }),
            ("milne", |m| Ok(tables::milne_table(m))),
        ];
        for (what, f) in snaps {
            if what == "milne" && !model.has_state("Omega") {
                continue;
            }
            let (m, ev) = (model.clone(), evaluated.clone());
            trials.push(
                Trial::test(format!("{}::snapshot-{what}", case.id), move || {
                    let c = &ev.case;
                    snapshot(c, what, f(&m))
                })
                .with_kind("snapshot"),
            );
        }
    }
}

fn snapshot(case: &Case, what: &str, body: Result<String, String>) -> Result<(), Failed> {
    let body = body?;
    let mut s = insta::Settings::clone_current();
    s.set_snapshot_path(repo_root().join("reports/snapshots"));
    s.set_prepend_module_to_snapshot(false);
    s.set_input_file(&case.path);
    s.set_description(format!("{}: {} ({})", case.id, what, case.title));
    s.set_omit_expression(true);
    let name = format!("{}-{what}", case.id);
    s.bind(|| insta::assert_snapshot!(name, body));
    Ok(())
}
