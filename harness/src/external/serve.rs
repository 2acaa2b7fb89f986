//! The protocol's other side: any [`FlightModel`] answering requests of `cierva-external/2`
//! (`cierva serve` serves cierva's own aircraft so). One-shot, a request file in and a response
//! file out ([`answer_file`]); persistent, JSON lines on stdin and stdout ([`answer_lines`]).
//!
//! It is the protocol's known answer: cierva's aircraft served through it and asked by cierva
//! as an external model gives the numbers the built-in path gives (JSON carries every `f64` to
//! the bit: serde_json writes the shortest text that reads back to the same number).

use super::command::{Compute, PROTOCOL, PROTOCOL_2};
use super::{AnswerOf, ControlChanges, FlightModel, Request, Values};
use crate::inputs::condition::{Loading, TrimRequest};
use crate::inputs::controls::{CONTROL_COLUMNS, ControlTable};
use crate::run::replay::{Replayed, SIGNALS};
use rustfft::num_complex::Complex64 as C;
use serde_json::{Value, json};
use std::io::{BufRead, Write};
use std::path::Path;

/// What a request asks, read from its JSON.
struct Read {
    compute: Compute,
    request: Request,
    /// A time history's (the one-shot request's CSV read from its path, the persistent
    /// one's columns inline).
    controls: Option<ControlChanges>,
    /// A frequency response's, Hz.
    frequencies_hz: Vec<f64>,
    /// An autorotation's tunnel condition.
    tunnel: Option<crate::inputs::condition::TunnelSpec>,
    /// The discretisation parameter refined and how many times, where the request says
    /// (`refine`).
    refine: Option<(String, usize)>,
}

/// What a request asks, read from its JSON (see [`Read`]).
fn read_request(v: &Value) -> Result<Read, String> {
    let protocol = v["protocol"].as_str().unwrap_or_default();
    if protocol != PROTOCOL && protocol != PROTOCOL_2 {
        return Err(format!(
            "the request's protocol is `{protocol}`; this model speaks `{PROTOCOL_2}` and \
             `{PROTOCOL}`"
        ));
    }
    let name = v["compute"].as_str().unwrap_or_default();
    let compute = Compute::ANSWERS
        .into_iter()
        .chain([Compute::Describe])
        .find(|c| c.name() == name)
        .ok_or_else(|| format!("`{name}` is not a request of the protocol"))?;
    let number = |x: &Value, what: &str| {
        x.as_f64()
            .ok_or_else(|| format!("the request's `{what}` is not a number"))
    };
    if compute == Compute::Describe {
        let nowhere = Request::at(
            TrimRequest::level(0.0),
            Loading {
                mass_kg: None,
                density_altitude_ft: 0.0,
            },
        );
        return Ok(Read {
            compute,
            request: nowhere,
            controls: None,
            frequencies_hz: Vec::new(),
            tunnel: None,
            refine: None,
        });
    }
    if compute == Compute::Autorotation {
        let tunnel = serde_json::from_value(v["tunnel"].clone())
            .map_err(|e| format!("the request's `tunnel`: {e}"))?;
        let mut request = Request::at(
            TrimRequest::level(0.0),
            Loading {
                mass_kg: None,
                density_altitude_ft: 0.0,
            },
        );
        request.parameters = parameters_of(v)?;
        return Ok(Read {
            compute,
            request,
            controls: None,
            frequencies_hz: Vec::new(),
            tunnel: Some(tunnel),
            refine: refine_of(v)?,
        });
    }
    let c = &v["condition"];
    let condition = TrimRequest {
        airspeed_mph: number(&c["airspeed_mph"], "condition.airspeed_mph")?,
        climb_m_s: number(&c["climb_m_s"], "condition.climb_m_s")?,
        turn_rate_deg_s: number(&c["turn_rate_deg_s"], "condition.turn_rate_deg_s")?,
    };
    let l = &v["loading"];
    let loading = Loading {
        mass_kg: match &l["mass_kg"] {
            Value::Null => None,
            m => Some(number(m, "loading.mass_kg")?),
        },
        density_altitude_ft: number(&l["density_altitude_ft"], "loading.density_altitude_ft")?,
    };
    let parameters = parameters_of(v)?;
    let controls = controls_of(v)?;
    let frequencies_hz = match &v["frequencies_hz"] {
        Value::Null => Vec::new(),
        Value::Array(f) => f
            .iter()
            .map(|x| number(x, "frequencies_hz"))
            .collect::<Result<_, _>>()?,
        _ => return Err("the request's `frequencies_hz` is not a list".into()),
    };
    Ok(Read {
        compute,
        request: Request {
            condition,
            loading,
            parameters,
            start: start_of(v),
        },
        controls,
        frequencies_hz,
        tunnel: None,
        refine: refine_of(v)?,
    })
}

/// A request's `refine` (`{"parameter": name, "level": k}`), where it has one.
fn refine_of(v: &Value) -> Result<Option<(String, usize)>, String> {
    match &v["refine"] {
        Value::Null => Ok(None),
        r => {
            let parameter = r["parameter"]
                .as_str()
                .ok_or("the request's `refine.parameter` is not a name")?;
            let level = r["level"]
                .as_u64()
                .and_then(|k| usize::try_from(k).ok())
                .filter(|k| *k >= 1)
                .ok_or("the request's `refine.level` is not a whole number from 1")?;
            Ok(Some((parameter.to_string(), level)))
        }
    }
}

/// `model` with `parameter` refined `level` times, each time by its own refinement of that
/// name ([`FlightModel::refinements`]).
fn refined(
    model: &dyn FlightModel,
    parameter: &str,
    level: usize,
) -> Result<std::sync::Arc<dyn FlightModel>, String> {
    let next = |m: &dyn FlightModel, k: usize| {
        m.refinements()
            .into_iter()
            .find(|r| r.parameter == parameter)
            .map(|r| r.model)
            .ok_or_else(|| {
                format!(
                    "{} has no refinement {k} of `{parameter}` (its `describe` lists what it \
                     refines and to how many levels)",
                    m.describe()
                )
            })
    };
    let mut m = next(model, 1)?;
    for k in 2..=level {
        m = next(m.as_ref(), k)?;
    }
    Ok(m)
}

/// What `model` says it refines, for its `describe`: each parameter with its words level by
/// level, to as many levels as it refines it (at most the grid study's).
fn refinements_declared(model: &dyn FlightModel) -> Vec<Value> {
    model
        .refinements()
        .into_iter()
        .map(|r| {
            let mut words = vec![r.words.clone()];
            let mut at = r.model.clone();
            while words.len() < super::GRID_LEVELS {
                let Some(n) = at
                    .refinements()
                    .into_iter()
                    .find(|x| x.parameter == r.parameter)
                else {
                    break;
                };
                words.push(n.words);
                at = n.model;
            }
            json!({
                "name": r.parameter, "words": words, "ratio": r.ratio,
                "formal_order": r.formal_order, "levels": words.len(),
            })
        })
        .collect()
}

/// A time-history request's controls: the one-shot request's CSV read from its path, the
/// persistent one's columns inline; `None` for another request.
fn controls_of(v: &Value) -> Result<Option<ControlChanges>, String> {
    let number = |x: &Value, what: &str| {
        x.as_f64()
            .ok_or_else(|| format!("the request's `{what}` is not a number"))
    };
    let controls = match &v["controls"] {
        Value::Null => None,
        Value::String(path) => {
            Some(crate::inputs::controls::read(Path::new(path)).map_err(|e| e.to_string())?)
        }
        Value::Object(columns) => {
            let column = |name: &str| -> Result<Vec<f64>, String> {
                columns
                    .get(name)
                    .and_then(Value::as_array)
                    .ok_or_else(|| format!("the request's controls have no `{name}`"))?
                    .iter()
                    .map(|x| number(x, &format!("controls.{name}")))
                    .collect()
            };
            Some(ControlTable {
                time_s: column("time_s")?,
                changes: [
                    column(CONTROL_COLUMNS[0])?,
                    column(CONTROL_COLUMNS[1])?,
                    column(CONTROL_COLUMNS[2])?,
                    column(CONTROL_COLUMNS[3])?,
                ],
            })
        }
        _ => return Err("the request's `controls` is neither a path nor columns".into()),
    };
    let controls = match controls {
        None => None,
        Some(table) => {
            let rows = v["samples"]
                .as_u64()
                .ok_or("a time-history request needs `samples`")?;
            let mut initial_state = std::collections::BTreeMap::new();
            if let Some(o) = v["initial_state"].as_object() {
                for (name, x) in o {
                    initial_state
                        .insert(name.clone(), number(x, &format!("initial_state.{name}"))?);
                }
            }
            Some(ControlChanges {
                table,
                sample_s: number(&v["sample_s"], "sample_s")?,
                samples: usize::try_from(rows.max(1) - 1).map_err(|e| e.to_string())?,
                initial_state,
            })
        }
    };
    Ok(controls)
}

/// A request's parameter values, by name.
fn parameters_of(v: &Value) -> Result<Values, String> {
    let mut parameters = Values::new();
    if let Some(p) = v["parameters"].as_object() {
        for (name, x) in p {
            let x = x
                .as_f64()
                .ok_or_else(|| format!("the request's `parameters.{name}` is not a number"))?;
            parameters.insert(name.clone(), x);
        }
    }
    Ok(parameters)
}

/// What the model answers to one request, as the response's JSON fields (a time history as
/// columns), without `protocol` and `id`.
fn respond(model: &dyn FlightModel, v: &Value) -> Result<(Compute, Value), String> {
    let Read {
        compute,
        request,
        controls,
        frequencies_hz,
        tunnel,
        refine,
    } = read_request(v)?;
    let refined_model;
    let model = match refine {
        None => model,
        Some((parameter, level)) => {
            refined_model = refined(model, &parameter, level)?;
            refined_model.as_ref()
        }
    };
    let body = match compute {
        Compute::Describe => described(model)?,
        Compute::Trim => {
            let q: serde_json::Map<String, Value> = model
                .trim(&request)?
                .into_iter()
                .map(|(n, x)| (n.to_string(), json!(x)))
                .collect();
            with_start(json!({ "trim": q }), model, &request, &AnswerOf::Trim, v)
        }
        Compute::LinearModel => {
            let m = model.linear_model(&request)?;
            let rows = |x: &nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
                x.row_iter().map(|r| r.iter().copied().collect()).collect()
            };
            let body = json!({"linear_model": {
                "states": m.states(), "controls": m.controls(),
                "a": rows(m.a()), "b": rows(m.b()),
            }});
            with_start(body, model, &request, &AnswerOf::LinearModel, v)
        }
        Compute::TimeHistory => {
            let controls = controls.ok_or("a time-history request needs `controls`")?;
            let flown = model.time_history(&request, &controls)?;
            json!({ "time_history": columns(&flown) })
        }
        Compute::FrequencyResponse => {
            let r = model.responses(&request, &frequencies_hz)?;
            let part = |f: fn(&C) -> f64| -> Vec<Vec<Vec<f64>>> {
                r.at.iter()
                    .map(|h| {
                        h.row_iter()
                            .map(|row| row.iter().map(f).collect())
                            .collect()
                    })
                    .collect()
            };
            let body = json!({"frequency_response": {
                "states": r.states, "controls": r.controls, "frequencies_hz": r.frequencies_hz,
                "real": part(|c| c.re), "imag": part(|c| c.im), "method": r.from,
            }});
            let of = AnswerOf::Responses(frequencies_hz.clone());
            with_start(body, model, &request, &of, v)
        }
        Compute::Autorotation => {
            let tunnel = tunnel.ok_or("an autorotation request needs `tunnel`")?;
            let a = model.autorotation(&super::TunnelRequest {
                tunnel,
                parameters: request.parameters,
            })?;
            match a {
                crate::run::autorotation::Autorotated::Equilibrium(e) => {
                    let q: serde_json::Map<String, Value> = e
                        .quantities
                        .into_iter()
                        .map(|(n, x)| (n.to_string(), json!(x)))
                        .collect();
                    json!({"autorotation": {
                        "quantities": q, "outside_validity": e.outside_validity,
                    }})
                }
                crate::run::autorotation::Autorotated::NoEquilibrium { reason, numbers } => {
                    let n: serde_json::Map<String, Value> =
                        numbers.into_iter().map(|(k, x)| (k, json!(x))).collect();
                    json!({"autorotation": {"no_equilibrium": reason, "numbers": n}})
                }
            }
        }
    };
    Ok((compute, body))
}

/// What `model` says of itself, for its `describe` answer: what it computes, cierva's states
/// and controls, its parameters with their ranges, and what it refines.
fn described(model: &dyn FlightModel) -> Result<Value, String> {
    let parameters: Vec<Value> = model
        .parameters()?
        .into_iter()
        .map(|p| {
            let mut d = json!({
                "name": p.name, "unit": p.unit, "meaning": p.meaning,
                "nominal": p.nominal, "correction": p.correction,
            });
            if let Some(r) = p.range {
                d["range"] = json!({
                    "lower": r.lower, "upper": r.upper, "source": r.source,
                    "distribution": r.distribution,
                });
                if let Some(s) = r.sigma {
                    d["range"]["sigma"] = json!(s);
                }
                if !r.taken_from.is_empty() {
                    d["range"]["taken_from"] = json!(r.taken_from);
                }
                if let Some(m) = r.shares {
                    d["range"]["shares"] = json!(m);
                }
            }
            d
        })
        .collect();
    Ok(json!({"describe": {
        "computes": model.computes().into_iter().map(Compute::name).collect::<Vec<_>>(),
        "states": cierva_model::aircraft::linearise::STATES,
        "controls": cierva_model::aircraft::linearise::CONTROLS,
        "parameters": parameters,
        "refinements": refinements_declared(model),
    }}))
}

/// An answer with where the model's answer ended, where it gives one
/// ([`FlightModel::start_after`]) and the request `v` speaks protocol `/2`: the `start` a
/// request near it may carry back.
fn with_start(
    mut body: Value,
    model: &dyn FlightModel,
    request: &Request,
    of: &AnswerOf,
    v: &Value,
) -> Value {
    if v["protocol"] == PROTOCOL_2
        && let Some(s) = model.start_after(request, of)
    {
        body["start"] = (*s.0).clone();
    }
    body
}

/// A request's `start`, carried back from an answer as it was (the model reads it).
fn start_of(v: &Value) -> Option<super::Start> {
    match &v["start"] {
        Value::Null => None,
        s => Some(super::Start(std::sync::Arc::new(s.clone()))),
    }
}

/// A time history as columns: `time_s` and every response the model gave.
fn columns(flown: &Replayed) -> serde_json::Map<String, Value> {
    let mut o = serde_json::Map::new();
    o.insert("time_s".into(), json!(flown.time_s));
    for (name, s) in SIGNALS.iter().zip(&flown.signals) {
        if !s.is_empty() {
            o.insert((*name).into(), json!(s));
        }
    }
    o
}

/// Answers one request file (one-shot): the response written where the request says (a time
/// history as CSV). An `Err` is what the model cannot answer, for its stderr and a non-zero
/// exit.
pub fn answer_file(model: &dyn FlightModel, request: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(request)
        .map_err(|e| format!("reading {}: {e}", request.display()))?;
    let v: Value = serde_json::from_str(&text)
        .map_err(|e| format!("{} is not JSON: {e}", request.display()))?;
    let response = v["response"]
        .as_str()
        .ok_or("the request has no `response` path")?
        .to_string();
    let (compute, mut body) = respond(model, &v)?;
    let text = if compute == Compute::TimeHistory {
        let cols = body["time_history"]
            .as_object()
            .cloned()
            .unwrap_or_default();
        let names: Vec<&String> = cols.keys().collect();
        let n = cols
            .get("time_s")
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        let mut csv = names
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join(",")
            + "\n";
        for k in 0..n {
            let row: Vec<String> = names
                .iter()
                .map(|c| {
                    cols[*c][k]
                        .as_f64()
                        .map_or(String::new(), |x| format!("{x:?}"))
                })
                .collect();
            csv += &(row.join(",") + "\n");
        }
        csv
    } else {
        body["protocol"] = v["protocol"].clone();
        body.to_string()
    };
    std::fs::write(&response, text).map_err(|e| format!("writing {response}: {e}"))
}

/// Answers requests as JSON lines until `input` ends (persistent mode): each answer a line
/// with the request's `id`, or `error` where the model cannot answer.
pub fn answer_lines(
    model: &dyn FlightModel,
    input: impl BufRead,
    mut output: impl Write,
) -> std::io::Result<()> {
    for line in input.lines() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let v: Value = serde_json::from_str(&line).unwrap_or(Value::Null);
        let mut body = match respond(model, &v) {
            Ok((_, body)) => body,
            Err(e) => json!({ "error": e }),
        };
        body["protocol"] = v["protocol"].clone();
        body["id"] = v["id"].clone();
        writeln!(output, "{body}")?;
        output.flush()?;
    }
    Ok(())
}
