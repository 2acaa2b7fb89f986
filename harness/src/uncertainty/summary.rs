//! A whole suite's verdicts, per case: what `cierva uncertainty --write-summary` commits as
//! the suite's `reports/uncertainty-summary.yaml`. The documents' "How sure" tables are
//! generated from it ([`table`], [`cases_list`]) and checked by `cargo test`
//! (`cases::docs::*-how-sure-*`); CI reruns the uncertainty and fails when the file it writes
//! differs from the committed one.
//!
//! It holds only what a run gives exactly, so that the same cases, settings and seed give the
//! same bytes: each validation quantity's verdict, counts of evaluations, and a fragile pass's
//! share of passing draws in whole percent (a count over the draws). No mean, interval or index
//! is written: their last digits are floating point's.

use super::propagate::{
    CaseUncertainty, FLIPPING_TOTAL_INDEX, Propagation, PropagationSettings, QuantityUncertainty,
};
use super::vv20::Vv20Verdict;
use crate::checks::CheckClass;
use crate::inputs::yaml::{self, InputError};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::Path;

/// The summary's file name, in the suite's reports folder.
pub const FILE: &str = crate::suite::UNCERTAINTY_SUMMARY_FILE;

/// How many names a table cell lists beside its count; more are counted only (the summary
/// file lists them all).
pub const NAMED_AT_MOST: usize = 3;

/// The verdicts of one uncertainty run over a whole suite.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Summary {
    /// The run's settings: `--samples`, `--seed`, `--method`.
    pub samples: usize,
    pub seed: u32,
    pub method: Propagation,
    /// Each case with validation quantities, by id.
    pub cases: BTreeMap<String, CaseVerdicts>,
}

/// One case's validation quantities by verdict, each named as [`quantity_names`] names it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseVerdicts {
    /// How its inputs were propagated: `sampled`, `first order` or `none`.
    pub method: String,
    pub inputs: usize,
    /// Evaluations of the case, and the points at which some check could not be evaluated.
    pub evaluations: usize,
    pub failed_points: usize,
    pub agrees: Vec<String>,
    pub model_form_error: Vec<String>,
    pub inconclusive: Vec<String>,
    /// Compared with data that state no uncertainty: `E` given, not weighed.
    pub no_data_uncertainty: Vec<String>,
    /// No verdict: no reference value, no uncertain inputs, or too many failed samples.
    pub without_verdict: Vec<String>,
    pub fragile: Vec<FragilePass>,
    /// Judged with an input range taken from their own data (`taken_from`): apart from the
    /// verdicts above, no evidence.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub circular: Vec<String>,
}

/// A nominal pass that fails somewhere in the inputs' distribution.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FragilePass {
    pub quantity: String,
    /// The share of the evaluated draws in which its check passes, in whole percent.
    pub passes_percent: u32,
    /// The inputs whose total Sobol' index reaches the flipping threshold.
    pub flipped_by: Vec<String>,
}

impl CaseVerdicts {
    /// The validation quantities, counted.
    pub fn quantities(&self) -> usize {
        self.agrees.len()
            + self.model_form_error.len()
            + self.inconclusive.len()
            + self.no_data_uncertainty.len()
            + self.without_verdict.len()
    }
}

/// The name of each validation quantity among `results`, in order: its check's id when the
/// check has one quantity (a derivative, a period), `check quantity` when it has several (a
/// tunnel row's rotor speed, C_L, ...).
pub fn quantity_names(results: &[&QuantityUncertainty]) -> Vec<String> {
    let mut per_check: BTreeMap<&str, usize> = BTreeMap::new();
    for r in results {
        *per_check.entry(r.check.as_str()).or_default() += 1;
    }
    results
        .iter()
        .map(|r| {
            if per_check[r.check.as_str()] == 1 {
                r.check.clone()
            } else {
                format!("{} {}", r.check, r.quantity)
            }
        })
        .collect()
}

/// The summary of a run with `settings` over `cases`: each case with at least one validation
/// quantity.
pub fn of<'a>(
    settings: &PropagationSettings,
    cases: impl IntoIterator<Item = &'a CaseUncertainty>,
) -> Summary {
    let mut out = BTreeMap::new();
    for u in cases {
        let results: Vec<&QuantityUncertainty> = u
            .results
            .iter()
            .filter(|r| r.class == CheckClass::Validation)
            .collect();
        if results.is_empty() {
            continue;
        }
        let mut c = CaseVerdicts {
            method: u.method.split(':').next().unwrap_or_default().to_string(),
            inputs: u.inputs.len(),
            evaluations: u.evaluations,
            failed_points: u.failed_points,
            agrees: Vec::new(),
            model_form_error: Vec::new(),
            inconclusive: Vec::new(),
            no_data_uncertainty: Vec::new(),
            without_verdict: Vec::new(),
            fragile: Vec::new(),
            circular: Vec::new(),
        };
        for (r, name) in results.iter().zip(quantity_names(&results)) {
            if r.circular.is_some() {
                c.circular.push(name);
                continue;
            }
            if r.fragile {
                c.fragile.push(FragilePass {
                    quantity: name.clone(),
                    passes_percent: (100.0 * r.pass_fraction).round() as u32,
                    flipped_by: r.flipped_by.clone(),
                });
            }
            match r.verdict {
                Some(Vv20Verdict::Agrees) => c.agrees.push(name),
                Some(Vv20Verdict::ModelFormError) => c.model_form_error.push(name),
                Some(Vv20Verdict::Inconclusive) => c.inconclusive.push(name),
                Some(Vv20Verdict::NoDataUncertainty) => c.no_data_uncertainty.push(name),
                None => c.without_verdict.push(name),
            }
        }
        out.insert(u.case.clone(), c);
    }
    Summary {
        samples: settings.samples,
        seed: settings.seed,
        method: settings.method,
        cases: out,
    }
}

/// The command that writes a summary with these settings.
pub fn command(s: &Summary) -> String {
    let method = match s.method {
        Propagation::Auto => "",
        Propagation::Sampled => " --method sampled",
        Propagation::FirstOrder => " --method first-order",
    };
    format!(
        "cierva uncertainty --samples {} --seed {}{method} --write-summary",
        s.samples, s.seed
    )
}

/// The file as written: a header that says what wrote it, then the summary.
pub fn render(s: &Summary) -> String {
    let body = serde_yaml::to_string(s).unwrap_or_else(|e| format!("# not written: {e}\n"));
    format!(
        "# Written by `{}`:\n\
         # the ASME V&V 20 verdict of each validation quantity, per case (harness/src/uncertainty/\n\
         # summary.rs). The README's and docs/uncertainty.md's \"How sure\" sections are generated\n\
         # from it; CI reruns the command and fails when the file moves. Do not edit by hand.\n{body}",
        command(s)
    )
}

/// Reads a summary, with a located error for a malformed one or one that names a quantity
/// twice.
pub fn parse(path: &Path, src: &str) -> Result<Summary, InputError> {
    let s: Summary = yaml::parse(path, src)?;
    for (id, c) in &s.cases {
        let mut seen = BTreeSet::new();
        for (list, names) in [
            ("agrees", &c.agrees),
            ("model_form_error", &c.model_form_error),
            ("inconclusive", &c.inconclusive),
            ("no_data_uncertainty", &c.no_data_uncertainty),
            ("without_verdict", &c.without_verdict),
        ] {
            for name in names {
                if !seen.insert(name.as_str()) {
                    return Err(InputError::field(
                        path,
                        src,
                        &format!("cases.{id}.{list}"),
                        format!("{name} is listed twice: a quantity has one verdict"),
                    ));
                }
            }
        }
        if let Some(f) = c
            .fragile
            .iter()
            .find(|f| !seen.contains(f.quantity.as_str()))
        {
            return Err(InputError::field(
                path,
                src,
                &format!("cases.{id}.fragile"),
                format!(
                    "{} is fragile but has no verdict listed: a fragile pass is one of the case's quantities",
                    f.quantity
                ),
            ));
        }
        if let Some(f) = c.fragile.iter().find(|f| f.passes_percent > 100) {
            return Err(InputError::field(
                path,
                src,
                &format!("cases.{id}.fragile"),
                format!(
                    "{}: passes_percent {} is more than 100",
                    f.quantity, f.passes_percent
                ),
            ));
        }
    }
    Ok(s)
}

/// The suite's committed summary; an error naming the file and the command that writes it when
/// there is none.
pub fn load(suite: &crate::suite::Suite) -> Result<Summary, InputError> {
    let path = suite.uncertainty_summary();
    if !path.is_file() {
        return Err(InputError::file(
            &path,
            "no uncertainty summary: write it with `cierva uncertainty --samples 64 --seed 0 --write-summary` (7.6 min of processor time in release)",
        ));
    }
    parse(&path, &yaml::read(&path)?)
}

/// Whether the summary covers exactly the cases that have validation checks (`with_validation`,
/// by id): a case added, removed or renamed since the summary was written makes it stale, which
/// this finds without the run.
pub fn check_cases(s: &Summary, with_validation: &[&str]) -> Result<(), String> {
    let want: BTreeSet<&str> = with_validation.iter().copied().collect();
    let have: BTreeSet<&str> = s.cases.keys().map(String::as_str).collect();
    if want == have {
        return Ok(());
    }
    let list = |x: Vec<&&str>| {
        x.iter()
            .map(|s| format!("`{s}`"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let missing = list(want.difference(&have).collect());
    let extra = list(have.difference(&want).collect());
    Err(format!(
        "the uncertainty summary ({FILE}) is stale: {}{}{}; rerun `{}` and then scripts/update-generated-docs",
        if missing.is_empty() {
            String::new()
        } else {
            format!("it has no verdicts for {missing}, which have validation checks")
        },
        if missing.is_empty() || extra.is_empty() {
            ""
        } else {
            "; "
        },
        if extra.is_empty() {
            String::new()
        } else {
            format!(
                "it has verdicts for {extra}, which are not the suite's cases with validation checks"
            )
        },
        command(s)
    ))
}

/// A count with its names when there are at most [`NAMED_AT_MOST`].
fn cell(names: &[String]) -> String {
    if names.is_empty() || names.len() > NAMED_AT_MOST {
        names.len().to_string()
    } else {
        format!("{} ({})", names.len(), names.join(", "))
    }
}

/// The documents' "How sure" table: a sentence with the command that wrote the summary and the
/// cases without any verdict (no uncertain inputs, no reference value), then a row per case with
/// a verdict (validation quantities by verdict, named where there are at most
/// [`NAMED_AT_MOST`]) and the sums over every case.
pub fn table(s: &Summary) -> String {
    let (judged, unjudged): (Vec<_>, Vec<_>) = s
        .cases
        .iter()
        .partition(|(_, c)| c.quantities() > c.without_verdict.len());
    let without = if unjudged.is_empty() {
        String::new()
    } else {
        format!(
            "; no verdict at all (no uncertain inputs or no reference value): {}",
            unjudged
                .iter()
                .map(|(id, c)| format!("`{id}` ({})", c.quantities()))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let mut o = format!(
        "Validation quantities per case, from `{}` (`reports/{FILE}`, which CI reruns and \
         compares; names where there are at most {NAMED_AT_MOST}){without}:\n\n",
        command(s)
    );
    o += "| case | quantities | agree | model-form error | inconclusive | no data uncertainty | no verdict | fragile |\n";
    o += "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (id, c) in &judged {
        let fragile: Vec<String> = c.fragile.iter().map(|f| f.quantity.clone()).collect();
        let _ = writeln!(
            o,
            "| `{id}` | {} | {} | {} | {} | {} | {} | {} |",
            c.quantities(),
            cell(&c.agrees),
            cell(&c.model_form_error),
            cell(&c.inconclusive),
            cell(&c.no_data_uncertainty),
            cell(&c.without_verdict),
            cell(&fragile)
        );
    }
    let sum = |f: fn(&CaseVerdicts) -> usize| s.cases.values().map(f).sum::<usize>();
    let _ = writeln!(
        o,
        "| **all {} cases** | **{}** | **{}** | **{}** | **{}** | **{}** | **{}** | **{}** |",
        s.cases.len(),
        sum(CaseVerdicts::quantities),
        sum(|c| c.agrees.len()),
        sum(|c| c.model_form_error.len()),
        sum(|c| c.inconclusive.len()),
        sum(|c| c.no_data_uncertainty.len()),
        sum(|c| c.without_verdict.len()),
        sum(|c| c.fragile.len())
    );
    o
}

/// A case's quantities by kind, where its checks have several (a tunnel row's rotor speed, C_L,
/// ...): each kind with its count and its verdicts counted; empty where each check has one.
fn by_quantity(c: &CaseVerdicts) -> String {
    let mut kinds: BTreeMap<&str, [usize; 5]> = BTreeMap::new();
    for (i, names) in [
        &c.agrees,
        &c.model_form_error,
        &c.inconclusive,
        &c.no_data_uncertainty,
        &c.without_verdict,
    ]
    .into_iter()
    .enumerate()
    {
        for name in names {
            if let Some((_, kind)) = name.split_once(' ') {
                kinds.entry(kind).or_default()[i] += 1;
            }
        }
    }
    let labels = [
        "agree",
        "model-form error",
        "inconclusive",
        "no data uncertainty",
        "no verdict",
    ];
    kinds
        .iter()
        .map(|(kind, n)| {
            let verdicts: Vec<String> = n
                .iter()
                .zip(labels)
                .filter(|(k, _)| **k > 0)
                .map(|(k, l)| format!("{k} {l}"))
                .collect();
            format!(
                "{kind} {} ({})",
                n.iter().sum::<usize>(),
                verdicts.join(", ")
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// A line per case: its propagation (method, inputs, evaluations, failed points), its
/// quantities by kind where its checks have several, and each fragile pass with its share of
/// passing draws and the inputs that flip it.
pub fn cases_list(s: &Summary) -> String {
    let mut o = String::new();
    for (id, c) in &s.cases {
        let _ = write!(
            o,
            "- `{id}`: {}, {} inputs, {} evaluations, failed points: {}",
            c.method, c.inputs, c.evaluations, c.failed_points
        );
        let kinds = by_quantity(c);
        if !kinds.is_empty() {
            let _ = write!(o, "; by quantity: {kinds}");
        }
        if c.fragile.is_empty() {
            o += "; no fragile pass.\n";
            continue;
        }
        o += "; fragile: ";
        let passes: Vec<String> = c
            .fragile
            .iter()
            .map(|f| {
                format!(
                    "{} (passes in {} % of the evaluated draws; flipped by {})",
                    f.quantity,
                    f.passes_percent,
                    if f.flipped_by.is_empty() {
                        format!("no input of total index {FLIPPING_TOTAL_INDEX} or more")
                    } else {
                        f.flipped_by
                            .iter()
                            .map(|i| format!("`{i}`"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    }
                )
            })
            .collect();
        o += &passes.join("; ");
        o += ".\n";
    }
    o
}
