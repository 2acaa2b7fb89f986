//! A case's regression snapshots (`reports/snapshots/`, reviewed with `cargo insta review`):
//! the tables its checks ask for ([`crate::checks::Snapshotted`]) and, for a linear model given,
//! the model's own tables. `cargo test` keeps one trial per snapshot
//! (`<case-id>::snapshot-<what>`).

use super::tables;
use crate::checks::Snapshotted;
use crate::suite::case::{Case, Subject};

/// One snapshot of a case: its name and what it holds.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// `trim`, `linear-70mph`, `derivatives`: the file is `<case-id>-<what>.snap`.
    pub what: String,
    body: Body,
}

#[derive(Debug, Clone, PartialEq)]
enum Body {
    /// The isolated rotor's autorotation table, a row per check.
    Autorotation,
    /// The table of time-history metrics, a row per record.
    TimeHistories,
    /// The aircraft trimmed at each condition its checks use.
    Trim(Vec<crate::inputs::condition::TrimRequest>),
    /// The aircraft linearised at one condition: the primary derivatives' breakdown, the
    /// modes and the derivatives.
    Linearised(crate::inputs::condition::TrimRequest),
    /// A linear model given: its derivatives, its modes, its weakly coupled systems values.
    Derivatives,
    Modes,
    Milne,
}

/// The snapshots of `case`.
pub fn of_case(case: &Case) -> Vec<Snapshot> {
    let asked: Vec<Snapshotted> = case
        .checks
        .iter()
        .flat_map(|k| k.behaviour().snapshotted())
        .collect();
    let any = |f: fn(&Snapshotted) -> bool| asked.iter().any(f);
    let snapshot = |what: &str, body| Snapshot {
        what: what.to_string(),
        body,
    };
    let mut out = Vec::new();
    match &case.subject {
        Subject::Rotor { .. } => out.push(snapshot("autorotation", Body::Autorotation)),
        Subject::Aircraft { .. } => {
            if any(|s| matches!(s, Snapshotted::TimeHistory(_))) {
                out.push(snapshot("time-histories", Body::TimeHistories));
            }
            let mut trims: Vec<crate::inputs::condition::TrimRequest> = asked
                .iter()
                .filter_map(|s| match s {
                    Snapshotted::Trims(t) => Some(t.iter().copied()),
                    _ => None,
                })
                .flatten()
                .collect();
            trims.sort_by(|a, b| {
                (a.airspeed_mph, a.climb_m_s, a.turn_rate_deg_s)
                    .partial_cmp(&(b.airspeed_mph, b.climb_m_s, b.turn_rate_deg_s))
                    .expect("finite conditions")
            });
            trims.dedup();
            if !trims.is_empty() {
                out.push(snapshot("trim", Body::Trim(trims)));
            }
            let mut linearised: Vec<crate::inputs::condition::TrimRequest> = asked
                .iter()
                .filter_map(|s| match s {
                    Snapshotted::Linearised(c) => Some(*c),
                    _ => None,
                })
                .collect();
            linearised.sort_by(|a, b| {
                (a.airspeed_mph, a.climb_m_s)
                    .partial_cmp(&(b.airspeed_mph, b.climb_m_s))
                    .expect("finite conditions")
            });
            linearised.dedup();
            for r in linearised {
                let climb = if r.climb_m_s != 0.0 {
                    format!("-climb{}", r.climb_m_s)
                } else {
                    String::new()
                };
                let what = format!("linear-{}mph{climb}", r.airspeed_mph);
                out.push(snapshot(&what, Body::Linearised(r)));
            }
        }
        Subject::Linear { model, .. } => {
            out.push(snapshot("derivatives", Body::Derivatives));
            out.push(snapshot("modes", Body::Modes));
            if model.has_state("Omega") {
                out.push(snapshot("milne", Body::Milne));
            }
        }
        _ => {}
    }
    out
}

impl Snapshot {
    /// The snapshot's text, or why it could not be computed.
    pub fn render(&self, case: &Case) -> Result<String, String> {
        match (&self.body, &case.subject) {
            (Body::Autorotation, Subject::Rotor { file, solver }) => {
                use crate::checks::autorotation::{autorotation_quantities, quantities_or_reason};
                let rows: Vec<_> = case
                    .checks
                    .iter()
                    .flat_map(|k| {
                        k.behaviour()
                            .snapshotted()
                            .into_iter()
                            .filter_map(move |s| match s {
                                Snapshotted::Autorotation(t) => Some((k.id.clone(), t)),
                                _ => None,
                            })
                    })
                    .map(|(id, t)| {
                        let q = autorotation_quantities(&file.rotor, *solver, t);
                        (id, quantities_or_reason(q))
                    })
                    .collect();
                Ok(tables::autorotation_table(&rows))
            }
            (Body::TimeHistories, Subject::Aircraft { file, loading }) => {
                let mut rows = Vec::new();
                for k in &case.checks {
                    for s in k.behaviour().snapshotted() {
                        if let Snapshotted::TimeHistory(t) = s {
                            let (m, _) = crate::checks::time_history::time_history_metrics(
                                file, *loading, t,
                            )?;
                            rows.push((k.id.clone(), m));
                        }
                    }
                }
                Ok(tables::time_history_table(&rows))
            }
            (Body::Trim(requests), Subject::Aircraft { file, loading }) => {
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
                        (
                            label,
                            crate::checks::trim::trim_quantities(file, *loading, *r),
                        )
                    })
                    .collect();
                Ok(tables::trim_table(&columns))
            }
            (Body::Linearised(r), Subject::Aircraft { file, loading }) => {
                let l = crate::run::linearise::linearise_cached(file, *r, *loading)?;
                let modes = cierva_model::modes(&l.1.model).map_err(|e| e.to_string())?;
                Ok(format!(
                    "{}\n{}\n{}",
                    tables::breakdown_table(&l.1, tables::PRIMARY_DERIVATIVES),
                    tables::modes_table(&modes),
                    tables::derivatives_table(&l.1.model)
                ))
            }
            (Body::Derivatives, Subject::Linear { model, .. }) => {
                Ok(tables::derivatives_table(model))
            }
            (Body::Modes, Subject::Linear { model, .. }) => cierva_model::modes(model)
                .map(|a| tables::modes_table(&a))
                .map_err(|e| e.to_string()),
            (Body::Milne, Subject::Linear { model, .. }) => Ok(tables::milne_table(model)),
            _ => Err(format!(
                "the snapshot `{}` is not one of {}'s ({})",
                self.what,
                case.id,
                case.subject.describe()
            )),
        }
    }
}
