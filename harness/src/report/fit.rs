//! The before/after report of a fit (`cierva fit`): Markdown for people (`reports/fits/<id>.md`)
//! and one figure of every target's error before and after (`reports/fits/<id>.svg`). Reads a
//! fit file and its run; computes nothing of its own.

use crate::fit::file::{ErrorSummary, FitFile, FitRun, Origin};
use crate::fit::{self, Enforce};

/// The before/after report of a fit, as Markdown.
pub fn markdown(f: &FitFile, run: &FitRun) -> String {
    use std::fmt::Write;
    let r = &run.result;
    let mut s = String::new();
    let _ = writeln!(s, "# Fit `{}`: {}\n", f.id, f.title);
    let _ = writeln!(s, "Source: {}\n", f.provenance.source);
    if let Some(n) = &f.provenance.notes {
        let _ = writeln!(s, "{n}\n");
    }
    for o in &f.physics_overrides {
        let _ = writeln!(s, "**Note:** {o}.\n");
    }
    let detail = match &r.status {
        fit::Status::Infeasible(m) | fit::Status::ModelFailure(m) | fit::Status::BadProblem(m) => {
            format!(": {m}")
        }
        _ => String::new(),
    };
    let _ = writeln!(
        s,
        "**Status: {}**{detail}. {} iterations, {} model evaluations, {:.2} s. Cost {:.4e} -> {:.4e}.\n",
        r.status.name(),
        r.iterations,
        r.evaluations,
        run.seconds,
        r.cost_start,
        r.cost
    );
    if let fit::Executor::Batches(b) = &f.problem.executor {
        let _ = writeln!(s, "Evaluations through {}.\n", b.describe());
    }
    parameters_table(&mut s, f, r);
    if let Some(st) = &run.starts {
        s += &starts_markdown(st);
    }
    let _ = writeln!(s, "\n## Fitted targets\n");
    targets_table(&mut s, &f.problem.targets, &f.origins, &r.before, &r.after);
    if !f.predict.is_empty() {
        let _ = writeln!(s, "## Predicted (not fitted)\n");
        targets_table(
            &mut s,
            &f.predict,
            &f.predict_origins,
            &run.predict_before,
            &run.predict_after,
        );
    }
    if !run.modes.is_empty() {
        modes_table(&mut s, &run.modes);
    }
    s
}

/// Whether a mode was found before or after (a model that gives no linear model, or a mode its
/// eigenvalues do not hold, has neither).
fn found(m: &crate::fit::file::ModeShift) -> bool {
    m.before.iter().chain(&m.after).any(|x| x.is_finite())
}

/// The fitted parameters' table (bounds, start, fitted value and standard error, or "not
/// identifiable"), then the fit's warnings.
fn parameters_table(s: &mut String, f: &FitFile, r: &fit::FitResult) {
    use std::fmt::Write;
    let _ = writeln!(s, "## Parameters\n");
    let _ = writeln!(
        s,
        "| parameter | bounds | start | fitted | standard error |"
    );
    let _ = writeln!(s, "| --- | --- | ---: | ---: | ---: |");
    for (p, (v, se)) in f
        .problem
        .parameters
        .iter()
        .zip(r.values.iter().zip(&r.standard_errors))
    {
        let _ = writeln!(
            s,
            "| {} | [{}, {}] | {} | {v:.5} | {} |",
            p.kind.name(),
            p.lower,
            p.upper,
            p.start,
            if se.is_finite() {
                format!("{se:.5}")
            } else {
                "not identifiable".into()
            }
        );
    }
    for w in &r.warnings {
        let _ = writeln!(s, "\n- warning: {w}");
    }
}

/// One table of targets (fitted or predicted) with their values before and after, each
/// error in its standard errors, then the RMS relative error over all and, where there are
/// several, per quantity.
fn targets_table(
    s: &mut String,
    targets: &[fit::Target],
    origins: &[Origin],
    before: &[f64],
    after: &[f64],
) {
    use std::fmt::Write;
    let _ = writeln!(
        s,
        "| reference from | quantity | condition | reference | standard error | bounds | before | after | before (SE) | after (SE) |"
    );
    let _ = writeln!(
        s,
        "| --- | --- | --- | ---: | ---: | --- | ---: | ---: | ---: | ---: |"
    );
    for ((t, o), (b, a)) in targets.iter().zip(origins).zip(before.iter().zip(after)) {
        let bounds = t.bounds.map_or("-".to_string(), |b| {
            format!(
                "[{:.4}, {:.4}] {}",
                b.lower,
                b.upper,
                match b.enforce {
                    Enforce::Hard => "hard".to_string(),
                    Enforce::Soft { weight } => format!("soft, weight {weight}"),
                }
            )
        });
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.5} | {:.5} | {bounds} | {b:.5} | {a:.5} | {:+.2} | {:+.2} |",
            o.label,
            t.measure.name(),
            t.condition.label(),
            t.reference,
            t.standard_error,
            (b - t.reference) / t.standard_error,
            (a - t.reference) / t.standard_error,
        );
    }
    let e = ErrorSummary::of(targets, before, after);
    let _ = writeln!(
        s,
        "\nRMS relative error over the targets solved before and after: {}.\n",
        e.line()
    );
    if !e.by_quantity.is_empty() {
        for (name, q) in &e.by_quantity {
            let _ = writeln!(s, "- `{name}`: {}", q.line());
        }
        let _ = writeln!(s);
    }
}

/// The longitudinal modes' table: each mode's eigenvalue, damping ratio and period before and
/// after.
fn modes_table(s: &mut String, modes: &[crate::fit::file::ModeShift]) {
    use std::fmt::Write;
    let _ = writeln!(s, "## Longitudinal modes before and after\n");
    if !modes.iter().any(found) {
        let _ = writeln!(
            s,
            "None found: the model gives no linear model at the targets' conditions, or its \
             eigenvalues hold no phugoid or short period there.\n"
        );
        return;
    }
    let _ = writeln!(
        s,
        "| condition | mode | eigenvalue before | eigenvalue after | damping ratio before | after | period before, s | after, s |"
    );
    let _ = writeln!(s, "| --- | --- | --- | --- | ---: | ---: | ---: | ---: |");
    let zeta = |e: [f64; 2]| -e[0] / e[0].hypot(e[1]);
    let period = |e: [f64; 2]| 2.0 * std::f64::consts::PI / e[1];
    for m in modes.iter().filter(|m| found(m)) {
        let _ = writeln!(
            s,
            "| {} | {} | {:.4} {:+.4}i | {:.4} {:+.4}i | {:.4} | {:.4} | {:.2} | {:.2} |",
            m.condition,
            m.mode,
            m.before[0],
            m.before[1],
            m.after[0],
            m.after[1],
            zeta(m.before),
            zeta(m.after),
            period(m.before),
            period(m.after)
        );
    }
    let _ = writeln!(s);
}

/// The fit's before/after figure: every target's error in its own standard errors, at the
/// start and fitted, against the 95 % band (±1.96); predicted targets after a gap.
pub fn figure(f: &FitFile, run: &FitRun) -> crate::report::plot::Figure {
    use crate::report::plot::{Figure, Series, Shade, Style};
    let r = &run.result;
    let z = |t: &fit::Target, v: f64| (v - t.reference) / t.standard_error;
    let mut before = Vec::new();
    let mut after = Vec::new();
    for (i, t) in f.problem.targets.iter().enumerate() {
        let x = (i + 1) as f64;
        before.push((x, z(t, r.before.get(i).copied().unwrap_or(f64::NAN))));
        after.push((x, z(t, r.after.get(i).copied().unwrap_or(f64::NAN))));
    }
    let n = f.problem.targets.len();
    let mut pb = Vec::new();
    let mut pa = Vec::new();
    for (i, t) in f.predict.iter().enumerate() {
        let x = (n + 2 + i) as f64;
        pb.push((
            x,
            z(t, run.predict_before.get(i).copied().unwrap_or(f64::NAN)),
        ));
        pa.push((
            x,
            z(t, run.predict_after.get(i).copied().unwrap_or(f64::NAN)),
        ));
    }
    let last = (n + 1 + f.predict.len()) as f64 + 0.5;
    let series = |name: &str, points, colour| Series {
        name: name.into(),
        points,
        style: Style::Markers,
        colour: Some(colour),
    };
    let mut s = vec![
        series("fitted targets, at the start", before, 7),
        series("fitted targets, fitted", after, 0),
    ];
    if !f.predict.is_empty() {
        s.push(series("predicted (not fitted), at the start", pb, 4));
        s.push(series("predicted (not fitted), fitted", pa, 1));
    }
    Figure {
        title: format!("{}: error before and after, in standard errors", f.id),
        x_label: if f.predict.is_empty() {
            "target".into()
        } else {
            format!("target (1-{n} fitted, then predicted)")
        },
        y_label: "(model - reference) / standard error".into(),
        series: s,
        bands: vec![Shade {
            name: "95 % (±1.96)".into(),
            points: vec![(0.5, -1.96, 1.96), (last, -1.96, 1.96)],
        }],
        ..Figure::default()
    }
}

/// A fit's cross-validation, for its Markdown report: per regime and quantity, the held-out
/// RMS relative error against the uncorrected model's on the same targets, the discrepancy
/// term, and which regimes the calibration makes worse.
pub fn cross_validation_markdown(cv: &crate::uncertainty::calibration::CrossValidation) -> String {
    let fits = cv
        .fits
        .iter()
        .map(|(g, s)| format!("{g}: {s}"))
        .collect::<Vec<_>>()
        .join(", ");
    let how = match cv.bands {
        true => format!(
            "Each of {} contiguous bands left out with every row in it, fitted or not, and the \
             fit redone on the fitted rows outside it ({fits}), which predicts the band",
            cv.groups.len()
        ),
        false => format!(
            "Each of {} groups of the fitted targets left out and the fit redone on the rest \
             ({fits}), plus the fit file's predictions by the whole fit",
            cv.groups.len()
        ),
    };
    let mut m = format!(
        "\n## Predictive error (cross-validation)\n\n{how}: data the calibration did not see. \
         Relative errors, RMS over the targets both models solved; the discrepancy term is the \
         spread beyond the data's scatter.\n\n\
         | regime | quantity | targets | held-out RMS | uncorrected RMS | discrepancy sd | \
         unsolved (uncorrected) | verdict |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | --- |\n"
    );
    let rows =
        std::iter::once(("all", &cv.all)).chain(cv.regimes.iter().map(|(k, v)| (k.as_str(), v)));
    for (regime, e) in rows {
        for (q, n) in &e.targets {
            let pct = |map: &std::collections::BTreeMap<String, f64>| {
                map.get(q)
                    .map_or("-".to_string(), |v| format!("{:.1} %", 100.0 * v))
            };
            m += &format!(
                "| {regime} | {q} | {n} | {} | {} | {} | {} ({}) | {} |\n",
                pct(&e.rms_relative_error),
                pct(&e.uncorrected_rms_relative_error),
                pct(&e.discrepancy_relative_sd),
                e.unsolved.get(q).copied().unwrap_or(0),
                e.uncorrected_unsolved.get(q).copied().unwrap_or(0),
                if e.worse_than_uncorrected.contains(q) {
                    "**worse than uncorrected**"
                } else {
                    "better"
                }
            );
        }
    }
    m
}

/// The fit's starts: where each began and ended, its cost, and which the data cannot tell apart.
fn starts_markdown(st: &crate::fit::starts::Starts) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## Starts\n\nThe fit ran from {} starts: the file's own, then points of a scrambled Sobol' sequence around the path its fit took (the box from its start to its end, widened by half each way). Ends within cost {} of the best (marked) are ones the data cannot tell apart; half their range is the spread.\n",
        st.ends.len(),
        crate::fit::starts::EQUIVALENT_COST
    );
    let names = st.parameters.join(", ");
    let _ = writeln!(
        s,
        "| start | from ({names}) | to | cost | status | evaluations | |"
    );
    let _ = writeln!(s, "| ---: | --- | --- | ---: | --- | ---: | --- |");
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for (i, e) in st.ends.iter().enumerate() {
        let mark = match (i == st.best, st.equivalent.contains(&i)) {
            (true, _) => "kept",
            (false, true) => "equivalent",
            _ => "",
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.3} | {}{} | {} | {mark} |",
            i + 1,
            list(&e.start),
            list(&e.values),
            e.cost,
            e.status,
            if e.stalled { " (stalled)" } else { "" },
            e.evaluations
        );
    }
    let _ = writeln!(
        s,
        "\nSpread over the equivalent ends: {}.",
        st.parameters
            .iter()
            .zip(&st.spread)
            .map(|(n, v)| format!("{n} +- {v:.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    s
}
