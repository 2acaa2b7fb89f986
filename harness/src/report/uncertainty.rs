//! The report's uncertainty section (`validate --uncertainty`): the verdicts counted, a table
//! of every validation quantity's comparison (ASME V&V 20: `E`, `u_input`, `u_num`, `u_D`,
//! `u_val`, the verdict and its largest contributor), and each quantity's Sobol' indices as
//! bars. It draws what the propagation computed and computes nothing.

use super::{Run, esc, num};
use crate::checks::CheckClass;
use crate::uncertainty::propagate::{QuantityUncertainty, VerdictCounts};
use std::fmt::Write as _;

/// The section, or nothing when no case carries an uncertainty.
pub fn html(run: &Run) -> String {
    let cases: Vec<_> = run
        .cases
        .iter()
        .filter_map(|c| c.uncertainty.as_ref())
        .filter(|u| !u.results.is_empty())
        .collect();
    if cases.is_empty() {
        return String::new();
    }
    let all = VerdictCounts::of(cases.iter().flat_map(|c| &c.results));
    let mut h = format!(
        "<h2 id=\"uncertainty\">Uncertainty (ASME V&amp;V 20)</h2><p class=\"muted\">Each \
         validation quantity's comparison error E = S - D against its validation uncertainty \
         u_val = sqrt(u_num² + u_input² + u_D²): the model's estimated inputs sampled over \
         their plausible ranges, the numerics refined, the data's confidence interval. \
         <b>agrees</b>: |E| ≤ 2 u_val with the model's own uncertainty inside the tolerance; \
         <b>model-form error</b>: |E| &gt; 2 u_val, no plausible input explains it; \
         <b>inconclusive</b>: the inputs must be known better first; <b>no data \
         uncertainty</b>: the data state none, so E is given but not weighed. A <b>fragile</b> pass \
         fails somewhere in the inputs' distribution. In all: {}.</p>",
        esc(&all.describe())
    );
    h += "<table><tr><th>case</th><th>method</th><th>inputs</th><th>evaluations</th>\
          <th>failed points</th><th>verdicts</th></tr>";
    for c in &cases {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td>\
             <td class=\"n\">{}</td><td>{}</td></tr>",
            esc(&c.case),
            esc(&c.method),
            c.inputs.len(),
            c.evaluations,
            c.failed_points,
            esc(&VerdictCounts::of(&c.results).describe())
        );
    }
    h += "</table>";
    h += &table(cases.iter().flat_map(|c| &c.results));
    h += &indices(cases.iter().flat_map(|c| &c.results));
    h
}

fn verdict_cell(r: &QuantityUncertainty) -> String {
    let (label, class) = match r.verdict {
        Some(v) => (
            v.label(),
            match v {
                crate::uncertainty::vv20::Vv20Verdict::Agrees => "pass",
                crate::uncertainty::vv20::Vv20Verdict::ModelFormError => "fail",
                crate::uncertainty::vv20::Vv20Verdict::Inconclusive
                | crate::uncertainty::vv20::Vv20Verdict::NoDataUncertainty => "xfail",
            },
        ),
        None => ("-", "muted"),
    };
    format!(
        "<td class=\"{class}\" title=\"{}\">{label}{}</td>",
        esc(&r.reason),
        match (r.fragile, r.circular.is_some()) {
            (_, true) => ", circular: no evidence",
            (true, false) => ", fragile",
            (false, false) => "",
        }
    )
}

/// A row per validation quantity.
fn table<'a>(results: impl Iterator<Item = &'a QuantityUncertainty>) -> String {
    let mut h = String::from(
        "<table><tr><th>case</th><th>check</th><th>S (nominal)</th><th>D</th><th>E = S - D</th>\
         <th>95 % of inputs</th><th>u_input</th><th>u_num</th><th>u_D</th><th>u_val</th>\
         <th>passes</th><th>verdict</th><th>largest contributor (total index)</th></tr>",
    );
    let opt = |x: Option<f64>| x.map_or("-".to_string(), num);
    for r in results.filter(|r| r.class == CheckClass::Validation) {
        let top = r.contributors.first().map_or("-".to_string(), |c| {
            // (The draws are the design's rows of A and B: two per base point.)
            format!("{} ({})", c.input, c.total_in_words(r.draws.len() / 2))
        });
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{} {}</td><td class=\"n\">{}</td><td class=\"n\">{}</td>\
             <td class=\"n\">{}</td><td class=\"n\">[{}, {}]</td><td class=\"n\">{}</td>\
             <td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td>\
             <td class=\"n\">{:.0} %</td>{}<td>{}</td></tr>",
            esc(&r.case),
            esc(&r.check),
            esc(&r.quantity),
            num(r.nominal),
            opt(r.reference),
            opt(r.estimate_error),
            num(r.p2_5),
            num(r.p97_5),
            num(r.u_input),
            num(r.u_num),
            opt(r.u_data),
            opt(r.u_val),
            100.0 * r.pass_fraction,
            verdict_cell(r),
            esc(&top)
        );
    }
    h + "</table>"
}

/// Each validation quantity's indices as horizontal bars: total (dark) over first order
/// (light), inputs by total index, each index's value with its standard error where it was
/// sampled.
fn indices<'a>(results: impl Iterator<Item = &'a QuantityUncertainty>) -> String {
    let mut h = String::from(
        "<h3>Sobol' indices</h3><p class=\"muted\">Per validation quantity, each input's share \
         of the variance: first order (light, the input alone) and total (dark, with its \
         interactions), each ± its standard error where sampled (the delta method's over the \
         design's rows: on the Sobol' points at 256 samples it overstates the error of a smooth \
         quantity, the first order's the more as the quantity's mean is large against its \
         spread; at 64 samples of 13 inputs a total index's may understate it; \
         docs/uncertainty.md); \"not resolved\" where the error exceeds 0.1: the samples \
         cannot rank the inputs there.</p>\
         <div class=\"sobol\">",
    );
    let with_se = |x: f64, se: Option<f64>| match se {
        Some(se) if se > crate::uncertainty::propagate::UNRESOLVED_INDEX_SE || !se.is_finite() => {
            format!("{x:.2} ± {se:.2} (not resolved)")
        }
        Some(se) => format!("{x:.2} ± {se:.2}"),
        None => format!("{x:.2}"),
    };
    for r in results.filter(|r| r.class == CheckClass::Validation && !r.contributors.is_empty()) {
        let _ = write!(
            h,
            "<figure class=\"bars\"><figcaption>{} {}</figcaption>",
            esc(&r.case),
            esc(&r.check)
        );
        for c in r.contributors.iter().filter(|c| c.total >= 0.01) {
            let width = |x: f64| (100.0 * x.clamp(0.0, 1.0)).round();
            let _ = write!(
                h,
                "<div class=\"bar-row\"><span class=\"bar-name\">{}</span>\
                 <span class=\"bar-track\"><span class=\"bar-total\" style=\"width:{}%\"></span>\
                 <span class=\"bar-first\" style=\"width:{}%\"></span></span>\
                 <span class=\"n\">{} / {}</span></div>",
                esc(&c.input),
                width(c.total),
                width(c.first),
                with_se(c.first, c.first_se),
                with_se(c.total, c.total_se)
            );
        }
        h += "</figure>";
    }
    h + "</div>"
}
