//! The sensitivity study's tables ([`crate::fit::sensitivity`]): as text for `cierva
//! sensitivity`, and as the report's HTML table of what would close each discrepancy.

use super::{esc, num};
use crate::fit::sensitivity::{Effect, MovedParameter, Study};
use std::fmt::Write as _;

/// The study as text: the parameters, then for each quantity outside its bound the change each
/// parameter alone would need (and whether that is plausible), then the derivatives.
pub fn table(s: &Study) -> String {
    let mut out = format!(
        "{} at {} mph, climb {} m/s, mass {}, density altitude {} ft\n\nparameters (step either way; plausible range as the model declares it):\n",
        s.model,
        crate::units::sig(s.condition.airspeed_mph, 4),
        s.condition.climb_m_s,
        s.loading
            .mass_kg
            .map_or("the model's own".to_string(), |m| format!("{m} kg")),
        s.loading.density_altitude_ft
    );
    for p in &s.parameters {
        let range = p
            .range
            .as_ref()
            .map_or("no range declared".to_string(), |r| {
                format!("[{}, {}] ({})", r.lower, r.upper, r.source)
            });
        out += &format!(
            "  {:34} {:>10.4} {:7} step {:.3}: {}\n",
            p.name, p.value, p.unit, p.step, range
        );
    }
    for r in &s.rows {
        let bound = r.bound.map_or(String::new(), |[lo, hi]| {
            // The bound as written, without the float noise its arithmetic left
            // (`3.6000000000000005`).
            let g = |x: f64| {
                let t = crate::units::sig(x, 12);
                if t.contains('e') || !t.contains('.') {
                    return t;
                }
                t.trim_end_matches('0').trim_end_matches('.').to_string()
            };
            format!(" against [{}, {}]", g(lo), g(hi))
        });
        let verdict = match r.inside {
            Some(true) => ", inside",
            Some(false) => ", OUTSIDE",
            None => "",
        };
        out += &format!("\n{} = {:.6}{bound}{verdict}\n", r.quantity, r.value);
        out += &format!(
            "  {:34} {:>13} {:>13} {:>13} {:>9} {}\n",
            "parameter", "d/dparameter", "change", "value", "steps", "plausible"
        );
        for (e, p) in r.effects.iter().zip(&s.parameters) {
            let (change, value, steps) = match (e.needed_change, e.needed_value) {
                (Some(c), Some(v)) => (
                    format!("{c:+.4}"),
                    format!("{v:.4}"),
                    format!("{:.0}", (c / p.step).abs()),
                ),
                _ => ("-".into(), "-".into(), "-".into()),
            };
            let plausible = match e.plausible {
                Some(true) => "yes",
                Some(false) => "no",
                None => "-",
            };
            out += &format!(
                "  {:34} {:>13.5e} {:>13} {:>13} {:>9} {}\n",
                e.parameter, e.derivative, change, value, steps, plausible
            );
        }
    }
    out
}

/// A case's sensitivity study: for each quantity outside its bound, what each parameter alone
/// would need, plausible changes first.
pub fn html(study: &Result<Study, String>) -> String {
    let study = match study {
        Ok(s) => s,
        Err(e) => {
            return format!(
                "<h3>What would close each discrepancy</h3><p class=\"fail\">The sensitivity \
                 study could not be run: {}</p>",
                esc(e)
            );
        }
    };
    let mut h = String::from(
        "<h3>What would close each discrepancy</h3><p class=\"muted\"><code>cierva sensitivity</code>: \
         the change of each parameter alone that brings a quantity outside its bound to the \
         nearer edge (a linear estimate; \"steps\" says how far it extrapolates), against the \
         parameter's plausible range as the model declares it (an aircraft's: its file's \
         `ranges:`). Parameters that do not move the \
         quantity are left out.</p><table><tr><th>quantity</th><th>value</th><th>bound</th>\
         <th>parameter</th><th>now</th><th>needed</th><th>plausible range</th><th>steps</th>\
         <th>plausible</th></tr>",
    );
    for r in study.rows.iter().filter(|r| r.inside == Some(false)) {
        let mut effects: Vec<_> = r
            .effects
            .iter()
            .zip(&study.parameters)
            .filter(|(e, _)| e.needed_value.is_some())
            .collect();
        effects.sort_by(|(a, pa), (b, pb)| {
            let steps = |e: &Effect, p: &MovedParameter| {
                (e.needed_change.unwrap_or(f64::INFINITY) / p.step).abs()
            };
            (b.plausible == Some(true))
                .cmp(&(a.plausible == Some(true)))
                .then(steps(a, pa).total_cmp(&steps(b, pb)))
        });
        let bound = r.bound.map_or("-".to_string(), |[lo, hi]| {
            format!("[{}, {}]", num(lo), num(hi))
        });
        if effects.is_empty() {
            let _ = write!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{bound}</td><td colspan=\"6\">no parameter \
                 moves it</td></tr>",
                esc(&r.quantity),
                num(r.value)
            );
        }
        for (k, (e, p)) in effects.iter().enumerate() {
            let head = if k == 0 {
                format!(
                    "<td rowspan=\"{n}\">{q}</td><td rowspan=\"{n}\">{v}</td><td rowspan=\"{n}\">{bound}</td>",
                    n = effects.len(),
                    q = esc(&r.quantity),
                    v = num(r.value)
                )
            } else {
                String::new()
            };
            let range = p.range.as_ref().map_or("-".to_string(), |g| {
                format!("[{}, {}]", num(g.lower), num(g.upper))
            });
            let (class, word) = match e.plausible {
                Some(true) => ("pass", "yes"),
                Some(false) => ("fail", "no"),
                None => ("", "-"),
            };
            let _ = write!(
                h,
                "<tr>{head}<td><code>{name}</code> ({unit})</td><td>{now}</td><td>{need}</td>\
                 <td>{range}</td><td>{steps:.0}</td><td class=\"{class}\">{word}</td></tr>",
                name = esc(&p.name),
                unit = esc(&p.unit),
                now = num(p.value),
                need = num(e.needed_value.unwrap_or(f64::NAN)),
                steps = (e.needed_change.unwrap_or(f64::NAN) / p.step).abs(),
            );
        }
    }
    h += "</table>";
    h
}
