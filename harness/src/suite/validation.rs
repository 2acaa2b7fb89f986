//! The one place that runs cases, scores and judges: each case with the corrections files that
//! apply to it, the checks a selection takes on every core, each case's scores, and the errors
//! that are the input's (a case that did not load or take its corrections; an external model
//! that failed, located at its check). `cierva validate`, `cierva review`, the retune's
//! revalidation and the test generator's score trials all go through it.

use crate::checks::Check;
use crate::inputs::corrections::CorrectionsFile;
use crate::suite::case::{Case, Subject};
use crate::suite::outcome::{CheckResult, run_cases};
use crate::suite::review::{self, Judged};
use crate::suite::scoreboard::{Board, Score};

/// What a run takes: the corrections files (each case runs with those that apply to it),
/// which checks (`select`; all by default) and what to call as each check ends (`done`: a
/// progress bar).
pub struct Options<'a> {
    pub corrections: &'a [CorrectionsFile],
    pub select: &'a (dyn Fn(&Case, &Check) -> bool + Sync),
    pub done: &'a (dyn Fn(&Case, &Check) + Sync),
}

impl Default for Options<'_> {
    fn default() -> Self {
        Self {
            corrections: &[],
            select: &|_, _| true,
            done: &|_, _| {},
        }
    }
}

/// One case run: the case as it ran (with its corrections), the results of the checks the
/// selection took in check order, the seconds they took (summed over threads), the
/// corrections it ran with (described) and its scores.
#[derive(Debug, Clone)]
pub struct CaseRan {
    pub case: Case,
    pub results: Vec<CheckResult>,
    pub seconds: f64,
    pub corrections: Vec<String>,
    pub scores: Vec<Score>,
}

/// A run: every case that ran, in the order given, and the input errors (rendered).
#[derive(Debug, Clone, Default)]
pub struct Ran {
    pub cases: Vec<CaseRan>,
    pub errors: Vec<String>,
}

impl Ran {
    /// Every case's scores.
    pub fn scores(&self) -> Vec<Score> {
        self.cases.iter().flat_map(|c| c.scores.clone()).collect()
    }

    /// Every score judged against the committed board.
    pub fn judged(&self, board: &Board) -> Vec<Judged> {
        review::judge(board, self.scores())
    }
}

/// Runs `cases` (those that did not load are input errors, rendered) with `options`. The
/// errors come in the cases' order.
pub fn validate(cases: Vec<Result<Case, String>>, options: &Options) -> Ran {
    // Each case with the corrections that apply to it, or the error that stopped it.
    let prepared: Vec<Result<(Case, Vec<String>), String>> = cases
        .into_iter()
        .map(|c| {
            c.and_then(|case| {
                crate::suite::case::with_corrections(&case, options.corrections)
                    .map_err(|e| format!("error: the corrections {e}"))
            })
        })
        .collect();
    let all: Vec<&Case> = prepared.iter().flatten().map(|(c, _)| c).collect();
    let mut ran = run_cases(&all, options.select, options.done).into_iter();
    let mut out = Ran::default();
    for p in prepared {
        let (case, corrections) = match p {
            Ok(p) => p,
            Err(e) => {
                out.errors.push(e);
                continue;
            }
        };
        let (results, seconds) = ran.next().expect("one result set per prepared case");
        out.errors.extend(external_errors(&case, &results));
        let scores = review::scores_of(&case, &results);
        out.cases.push(CaseRan {
            case,
            results,
            seconds,
            corrections,
            scores,
        });
    }
    out
}

/// One case's scores, from its results, judged against the committed board.
pub fn judge_case(board: &Board, case: &Case, results: &[CheckResult]) -> Vec<Judged> {
    review::judge(board, review::scores_of(case, results))
}

/// An external model that fails (not found, a non-zero exit, a timeout, output that does not
/// parse, a quantity it does not give) is bad input (exit 2): each such check's error, located
/// at the check in its case file.
fn external_errors(case: &Case, results: &[CheckResult]) -> Vec<String> {
    if !matches!(case.subject, Subject::External(_)) {
        return Vec::new();
    }
    let src = std::fs::read_to_string(&case.path).unwrap_or_default();
    // Checks that fail with the same error (a command not found fails every check) are one
    // error, located at the first of them, naming them all.
    let mut same: Vec<(&str, Vec<&str>)> = Vec::new();
    for r in results {
        let Some(e) = r.error.as_deref() else {
            continue;
        };
        match same.iter_mut().find(|(m, _)| *m == e) {
            Some((_, checks)) => checks.push(&r.check),
            None => same.push((e, vec![&r.check])),
        }
    }
    same.into_iter()
        .map(|(e, checks)| {
            let i = case.checks.iter().position(|c| c.id == checks[0]);
            let field = i.map_or("checks".to_string(), |i| format!("checks[{i}]"));
            let msg = match checks.as_slice() {
                [one] => format!("check `{one}`: {e}"),
                many => format!("{} checks (`{}`): {e}", many.len(), many.join("`, `")),
            };
            format!(
                "error: {}",
                crate::inputs::yaml::InputError::field(&case.path, &src, &field, msg)
            )
        })
        .collect()
}
