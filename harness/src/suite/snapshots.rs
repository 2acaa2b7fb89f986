//! A case's regression snapshots (`reports/snapshots/`, reviewed with `cargo insta review`):
//! which tables its checks ask for ([`crate::checks::Snapshotted`]) and, for a linear model
//! given, the model's own tables; and what they hold, computed through the model interface
//! (any flight model: cierva's aircraft or another simulation). `report::snapshots` writes
//! them out; `cargo test` keeps one trial per snapshot (`<case-id>::snapshot-<what>`).

use crate::checks::Snapshotted;
use crate::checks::result::Quantities;
use crate::external::Request;
use crate::suite::case::{Case, Subject};
use cierva_model::LinearModel;
use cierva_model::analysis::modes::ModalAnalysis;

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
    /// The flight model trimmed at each condition its checks use.
    Trim(Vec<crate::inputs::condition::TrimRequest>),
    /// The flight model linearised at one condition: the primary derivatives' breakdown
    /// (where the model splits them by component), the modes and the derivatives.
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
        Subject::Aircraft { .. } | Subject::External(_) => {
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

/// What a snapshot holds, computed through the model interface.
#[derive(Debug, Clone)]
pub enum Holds {
    /// Each check's autorotation quantities, or why there are none.
    Autorotation(Vec<(String, Result<Quantities, String>)>),
    /// Each check's time-history metrics.
    TimeHistories(Vec<(String, Vec<crate::run::replay::SignalMetrics>)>),
    /// Each condition's label and trim quantities, or why there are none.
    Trim(Vec<(String, Result<Quantities, String>)>),
    /// A linear model at a condition: its parts by component (where the model gives them) and
    /// its modes.
    Linearised {
        model: LinearModel,
        components: Option<Vec<(String, LinearModel)>>,
        modes: ModalAnalysis,
    },
    /// A linear model given: its derivatives.
    Derivatives(LinearModel),
    /// A linear model given: its modes.
    Modes(ModalAnalysis),
    /// A linear model given: its weakly coupled systems' values.
    Milne(LinearModel),
}

impl Snapshot {
    /// What the snapshot holds, or why it could not be computed.
    pub fn compute(&self, case: &Case) -> Result<Holds, String> {
        let flight = crate::checks::flight_model(&case.subject);
        match (&self.body, &case.subject, &flight) {
            (Body::Autorotation, Subject::Rotor { .. }, _) => {
                let model = crate::checks::model_of(&case.subject).ok_or("no rotor")?;
                let rows = case
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
                        let request = crate::external::TunnelRequest {
                            tunnel: *t,
                            parameters: Default::default(),
                        };
                        let q = model
                            .autorotation(&request)
                            .and_then(|a| a.quantities_or_reason());
                        (id, q)
                    })
                    .collect();
                Ok(Holds::Autorotation(rows))
            }
            (Body::TimeHistories, subject, Some(_)) => {
                let mut rows = Vec::new();
                for k in &case.checks {
                    for s in k.behaviour().snapshotted() {
                        if let Snapshotted::TimeHistory(t) = s {
                            rows.push((k.id.clone(), t.flown(subject)?.0));
                        }
                    }
                }
                Ok(Holds::TimeHistories(rows))
            }
            (Body::Trim(requests), _, Some((model, loading))) => Ok(Holds::Trim(
                requests
                    .iter()
                    .map(|r| {
                        let mut label = format!("{} mph", r.airspeed_mph);
                        if r.climb_m_s != 0.0 {
                            label += &format!(" {:+} m/s", r.climb_m_s);
                        }
                        if r.turn_rate_deg_s != 0.0 {
                            label += &format!(" {:+} deg/s", r.turn_rate_deg_s);
                        }
                        (label, model.trim(&Request::at(*r, *loading)))
                    })
                    .collect(),
            )),
            (Body::Linearised(r), _, Some((model, loading))) => {
                let request = Request::at(*r, *loading);
                let linear = model.linear_model(&request)?;
                let modes = cierva_model::modes(&linear).map_err(|e| e.to_string())?;
                Ok(Holds::Linearised {
                    components: model.components(&request).ok(),
                    model: linear,
                    modes,
                })
            }
            (Body::Derivatives, Subject::Linear { model, .. }, _) => {
                Ok(Holds::Derivatives(model.clone()))
            }
            (Body::Modes, Subject::Linear { model, .. }, _) => cierva_model::modes(model)
                .map(Holds::Modes)
                .map_err(|e| e.to_string()),
            (Body::Milne, Subject::Linear { model, .. }, _) => Ok(Holds::Milne(model.clone())),
            _ => Err(format!(
                "the snapshot `{}` is not one of {}'s ({})",
                self.what,
                case.id,
                case.subject.describe()
            )),
        }
    }
}
