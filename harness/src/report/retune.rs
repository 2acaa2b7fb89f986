//! The report for people of `cierva retune` ([`crate::fit::retune`]): the fit, the parameters
//! with their standard errors and sources, the frequency responses before and after, the
//! modes, predictions of records not used and the suite rerun with the new corrections.

use crate::fit::retune::responses::ResponseComparison;
use crate::fit::retune::{ModeRow, Prediction, Retune, Revalidation};
use std::fmt::Write;

/// The report's first line: the version, the fit's status (and that it stopped at the edge of
/// the model's equilibria, where it did), its iterations and cost.
fn written_by(r: &Retune) -> String {
    let g = crate::units::sig;
    format!(
        "Written by `cierva retune` (cierva {}). Fit status: **{}**{}, {} iterations, {} model evaluations; cost {} -> {}.{}",
        env!("CARGO_PKG_VERSION"),
        r.result.status.name(),
        match r.result.status.detail() {
            "" => String::new(),
            d => format!(" ({d})"),
        },
        r.result.iterations,
        r.result.evaluations,
        g(r.result.cost_start, 4),
        g(r.result.cost, 4),
        if r.result.stalled() {
            format!(" **It {}.**", crate::fit::STALLED_MEANS)
        } else {
            String::new()
        }
    )
}

/// The before/after report for people (markdown).
pub fn markdown(
    r: &Retune,
    aircraft: &str,
    modes: &[ModeRow],
    predictions: &[Prediction],
    revalidation: Option<&Revalidation>,
    comparisons: &[(ResponseComparison, Option<String>)],
) -> String {
    let g = crate::units::sig;
    let mut s = String::new();
    let _ = writeln!(s, "# Retune of {aircraft}\n");
    let _ = writeln!(s, "{}\n", written_by(r));
    let _ = writeln!(s, "## Records\n");
    for (c, ids) in &r.conditions {
        let _ = writeln!(s, "- {}: {}", c.label(), ids.join(", "));
    }
    let _ = writeln!(
        s,
        "\nMatched: the records' frequency responses as flown, {}, real and imaginary parts at coherent frequencies two resolution bins apart, each weighted by its random error ({} targets), against {}. Reduced chi-square at the optimum: {} ({} degrees of freedom; about 1 when the targets' standard errors describe the misfit).",
        estimators(&r.responses),
        r.problem.targets.len(),
        r.model,
        g(r.reduced_chi_square, 3),
        r.problem
            .targets
            .len()
            .saturating_sub(r.problem.parameters.len())
    );
    if let Some(m) = &r.matched {
        let _ = writeln!(
            s,
            "\nMatched processing: {} (`fit::retune::matched`; docs/validation.md, \"Retuning the corrections\").",
            m.described()
        );
    }
    let _ = writeln!(
        s,
        "\n## Fitted\n\nStandard errors: the larger of the cost's curvature, `(J'J)^-1`, and a cluster-robust sandwich around it (the residuals grouped by frequency; Liang and Zeger 1986). The coverage test checks them against known answers (docs/validation.md, \"Retuning the corrections\").\n\n| parameter | value | standard error | from the curvature alone | 95 % interval | bounds | the bounds' source |\n| --- | --- | --- | --- | --- | --- | --- |"
    );
    for (((((p, v), se), curvature), source), i) in r
        .problem
        .parameters
        .iter()
        .zip(&r.result.values)
        .zip(&r.result.standard_errors)
        .zip(&r.curvature_standard_errors)
        .zip(&r.bounds_sources)
        .zip(r.intervals())
    {
        let interval = i.map_or("none".to_string(), |i| i.described());
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {interval} | [{}, {}] | {source} |",
            p.kind.name(),
            g(*v, 5),
            g(*se, 3),
            g(*curvature, 3),
            g(p.lower, 4),
            g(p.upper, 4)
        );
    }
    for w in &r.result.warnings {
        let _ = writeln!(s, "\nWarning: {w}");
    }
    if !comparisons.is_empty() {
        s += &comparisons_markdown(comparisons);
    }
    if !modes.is_empty() {
        let _ = writeln!(
            s,
            "\n## Modes (eigenvalues, 1/s)\n\n| condition | mode | before | after |\n| --- | --- | --- | --- |"
        );
        for m in modes {
            let _ = writeln!(
                s,
                "| {} | {} | {} ± {}i | {} ± {}i |",
                m.condition,
                m.mode,
                g(m.before[0], 4),
                g(m.before[1], 4),
                g(m.after[0], 4),
                g(m.after[1], 4)
            );
        }
    }
    if !predictions.is_empty() {
        let _ = writeln!(
            s,
            "\n## Prediction of records not used in the fit\n\nTheil's inequality coefficient (0 a perfect match) of the linearised model flown with the record's measured controls.\n\n| record | state | Theil before | Theil after |\n| --- | --- | --- | --- |"
        );
        for p in predictions {
            let _ = writeln!(
                s,
                "| {} | {} | {:.4} | {:.4} |",
                p.record, p.signal, p.theil_before, p.theil_after
            );
        }
    }
    if let Some(v) = revalidation {
        s += &revalidation_markdown(v);
    }
    s
}

/// The responses' section of the report: `J` per response before and after, and its Bode
/// figure.
fn comparisons_markdown(comparisons: &[(ResponseComparison, Option<String>)]) -> String {
    let j = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1}"));
    let mut s = format!(
        "\n## Frequency responses: the records' against the model's\n\nTischler's mismatch cost J over each response's band of coherence >= {} (Tischler and Remple 2012: J <= {} acceptable, J <= {} nearly indistinguishable from the data).\n\n| condition | response | frequencies in band | J before | J after | Bode |\n| --- | --- | ---: | ---: | ---: | --- |\n",
        crate::checks::frequency_response::COHERENCE_MIN,
        crate::checks::frequency_response::J_ACCEPTABLE,
        crate::checks::frequency_response::J_INDISTINGUISHABLE,
    );
    for (c, svg) in comparisons {
        let _ = writeln!(
            s,
            "| {} | {}/{} | {} | {} | {} | {} |",
            c.condition,
            c.output,
            c.input,
            c.frequencies_in_band,
            j(c.j_before),
            j(c.j_after),
            svg.as_ref()
                .map_or("(nothing finite to draw)".to_string(), |f| format!(
                    "[{f}]({f})"
                ))
        );
    }
    s
}

/// The suite's section of the report: its cases rerun with the new corrections, checks passed
/// by class before and after, the checks that changed and the scores that moved.
fn revalidation_markdown(v: &Revalidation) -> String {
    let g = crate::units::sig;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## The validation suite with the new corrections\n\n{} cases use this aircraft.\n\n| class | checks | passed before | passed after |\n| --- | --- | --- | --- |",
        v.cases.len()
    );
    for (class, [n, b, a]) in &v.classes {
        let _ = writeln!(s, "| {class} | {n} | {b} | {a} |");
    }
    if !v.changed.is_empty() {
        let _ = writeln!(s, "\nChecks that changed:\n");
        for c in &v.changed {
            let _ = writeln!(
                s,
                "- {} ({}): {} -> {}",
                c.check,
                c.class,
                if c.passed_before { "inside" } else { "outside" },
                if c.passed_after { "inside" } else { "outside" }
            );
        }
    }
    let moved: Vec<&(String, f64, f64)> = v.scores.iter().filter(|(_, b, a)| b != a).collect();
    if !moved.is_empty() {
        let _ = writeln!(
            s,
            "\nScores that moved (not judged: these are not the committed model's):\n"
        );
        for (id, b, a) in moved {
            let _ = writeln!(s, "- {id}: {} -> {}", g(*b, 5), g(*a, 5));
        }
    }
    s
}

/// How the responses were estimated, in words: against the records' excitations, from the
/// controls, or each at some conditions.
pub fn estimators(responses: &[crate::fit::retune::responses::RecordedResponse]) -> String {
    use crate::fit::retune::responses::ResponseEstimator;
    let mut by: Vec<(ResponseEstimator, Vec<String>)> = Vec::new();
    for r in responses {
        let label = r.condition.label();
        match by.iter_mut().find(|(e, _)| *e == r.estimator) {
            Some((_, c)) if !c.contains(&label) => c.push(label),
            Some(_) => {}
            None => by.push((r.estimator, vec![label])),
        }
    }
    match by.as_slice() {
        [(e, _)] => format!("estimated {}", e.describe()),
        _ => by
            .iter()
            .map(|(e, c)| format!("estimated {} at {}", e.describe(), c.join(", ")))
            .collect::<Vec<_>>()
            .join("; "),
    }
}
