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

use cierva_harness::report::{snapshots, tables};
use cierva_harness::suite::case::Case;
use cierva_harness::suite::case::load_cases;
use cierva_harness::suite::outcome;
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
            // A case that did not load fails as itself, not as a case the board has and the
            // suite lacks.
            let all_loaded = loaded.iter().all(Result::is_ok);
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
            let docs: [(&str, DocsCheck); 8] = [
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
                ("docs::quoted-numbers", quoted_numbers),
            ];
            {
                let cases = cases.clone();
                trials.push(
                    Trial::test("scoreboard::every-committed-score-is-declared", move || {
                        use cierva_harness::suite::{review, scoreboard};
                        let suite = suite();
                        let board = scoreboard::load(&suite).map_err(|e| e.render())?;
                        let all: Vec<&cierva_harness::suite::case::Case> =
                            cases.iter().map(|e| &e.case).collect();
                        let gone = review::undeclared(&board, &all, all_loaded);
                        if gone.is_empty() {
                            Ok(())
                        } else {
                            Err(format!(
                                "committed scores in {} that no case declares:\n  {}\n\
                                 a score leaves the board only through `cargo run --release -- \
                                 review --accept --reason TEXT --because CASE/ITEM=TEXT`, which \
                                 drops it and logs why",
                                suite.scoreboard().display(),
                                gone.join("\n  ")
                            )
                            .into())
                        }
                    })
                    .with_kind("scoreboard"),
                );
            }
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
    let validated: Vec<&str> = cases
        .iter()
        .filter(|e| {
            e.case
                .checks
                .iter()
                .any(|k| k.class == cierva_harness::checks::CheckClass::Validation)
        })
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

/// Every number the documents quote from a run or a committed report, marked with its source
/// (`report::quoted`), must be that source rounded to its printed digits.
fn quoted_numbers(cases: &[Arc<Evaluated>]) -> Result<(), Failed> {
    use cierva_harness::report::quoted::{self, Field, QuoteSource};
    let root = repo_root();
    let result = |case: &str, check: &str| -> Result<outcome::CheckResult, String> {
        let e = cases
            .iter()
            .find(|e| e.case.id == case)
            .ok_or(format!("no case `{case}`"))?;
        let index = e
            .case
            .checks
            .iter()
            .position(|k| k.id == check)
            .ok_or(format!("case `{case}` has no check `{check}`"))?;
        Ok(e.result(index).clone())
    };
    let resolve = |source: &QuoteSource| -> Result<f64, String> {
        match source {
            QuoteSource::File { path, key } => quoted::from_file(&root, path, key),
            QuoteSource::Fingerprint { case, check, name } => result(case, check)?
                .fingerprint
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, v)| *v)
                .ok_or(format!("{case}::{check} has no fingerprint `{name}`")),
            QuoteSource::Check {
                case,
                check,
                quantity,
                field,
            } => {
                let r = result(case, check)?;
                let q = match quantity {
                    None => r.quantities.first(),
                    Some(name) => r.quantities.iter().find(|q| &q.quantity == name),
                }
                .ok_or(format!(
                    "{case}::{check} has no quantity {}",
                    quantity.as_deref().unwrap_or("at all")
                ))?;
                Ok(match field {
                    Field::Value => q.value,
                    Field::Expected => q.expected.unwrap_or(f64::NAN),
                    Field::Lower => q.lower,
                    Field::Upper => q.upper,
                })
            }
        }
    };
    let mut files = vec!["README.md".to_string(), "ARCHITECTURE.md".to_string()];
    for dir in ["docs", "docs/tutorials"] {
        let mut found: Vec<String> = std::fs::read_dir(root.join(dir))?
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().to_string())
            .filter(|n| n.ends_with(".md"))
            .map(|n| format!("{dir}/{n}"))
            .collect();
        found.sort();
        files.extend(found);
    }
    let mut checked = 0;
    let mut wrong = String::new();
    for file in &files {
        let text = std::fs::read_to_string(root.join(file))?;
        match quoted::check(file, &text, &resolve) {
            Ok(n) => checked += n,
            Err(e) => wrong.push_str(&e),
        }
    }
    if !wrong.is_empty() {
        return Err(format!(
            "quoted numbers that are not what their sources give \
             (`scripts/update-generated-docs` writes them):\n{wrong}"
        )
        .into());
    }
    if checked == 0 {
        return Err("no quoted number in the documents: the trial would check nothing".into());
    }
    Ok(())
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
                use cierva_harness::suite::{scoreboard, validation};
                let suite = suite();
                let board = scoreboard::load(&suite).map_err(|e| e.render())?;
                let judged = validation::judge_case(&board, &e.case, &e.all());
                let bad: Vec<String> = judged
                    .iter()
                    .filter(|j| j.change != scoreboard::Change::Same)
                    .map(|j| format!("  {}", j.describe()))
                    .collect();
                if bad.is_empty() {
                    Ok(())
                } else {
                    Err(format!(
                        "scores that differ from {} by more than their noise floor (worse; better, \
                         which the board keeps only once accepted, so that losing it again fails; \
                         or not committed):\n{}\n\
                         if the change is intended, `cargo run --release -- review --accept --reason TEXT \
                         --because CASE/ITEM=TEXT ...` commits the new values and logs why, item by item \
                         (`cargo run --release -- review` lists the items)",
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
    for snap in cierva_harness::suite::snapshots::of_case(case) {
        let ev = evaluated.clone();
        trials.push(
            Trial::test(format!("{}::snapshot-{}", case.id, snap.what), move || {
                let c = &ev.case;
                let body = snap.compute(c).map(|x| snapshots::render(&x));
                snapshot(c, &snap.what, body)
            })
            .with_kind("snapshot"),
        );
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
