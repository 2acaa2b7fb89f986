//! Sensitivity of checked quantities to a model's parameters: which parameter would close a
//! discrepancy, and is the value it would need plausible?
//!
//! The study runs on any model behind the model interface
//! ([`crate::external::FlightModel`]) that declares parameters: cierva's own aircraft (its
//! physical parameters, [`crate::inputs::parameters::PARAMETERS`], with the aircraft file's
//! ranges) or another simulation (protocol `cierva-external/2`). For each parameter the model
//! is asked its trim and linear model with the parameter moved a step either way, and each
//! quantity's derivative with respect to it is the central difference. For a quantity outside
//! its bound, the change that alone would bring it to the nearer edge is the linear estimate
//! `(edge - value) / (dq/dp)`, weighed against the parameter's plausible range as the model
//! declares it. It is a first-order answer: a change that is large against the step is an
//! extrapolation, and the table says by how many steps.

use crate::external::{FlightModel, Parameter, Request};
use crate::inputs::aircraft::Range;
use crate::inputs::condition::Loading;
use crate::inputs::condition::TrimRequest;
use serde::Serialize;

/// A quantity to differentiate: a derivative of the linearised model or a trim quantity, with
/// the bound a check puts on it (if any).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundedQuantity {
    pub name: String,
    /// `[lower, upper]` of the check's tolerance, where it is an interval.
    pub bound: Option<[f64; 2]>,
}

/// A parameter as the study moved it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MovedParameter {
    pub name: String,
    pub unit: String,
    pub meaning: String,
    pub value: f64,
    /// The step of the central difference, either way.
    pub step: f64,
    pub range: Option<Range>,
}

/// One quantity's sensitivity to one parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Effect {
    pub parameter: String,
    /// `d quantity / d parameter`, per the parameter's unit.
    pub derivative: f64,
    /// For a quantity outside its bound: the change of this parameter alone that brings it to
    /// the nearer edge (linear estimate), `None` where the quantity does not move with it (a
    /// change over the step below a millionth of its value).
    pub needed_change: Option<f64>,
    /// The parameter's value after that change.
    pub needed_value: Option<f64>,
    /// Whether that value lies in the parameter's plausible range (`None` without a range).
    pub plausible: Option<bool>,
}

/// One quantity: its value, bound, and sensitivity to every parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    pub quantity: String,
    pub value: f64,
    pub bound: Option<[f64; 2]>,
    /// Whether the value is inside its bound (`None` without one).
    pub inside: Option<bool>,
    pub effects: Vec<Effect>,
}

/// The whole study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Study {
    /// The model, in words ("the aircraft aircraft/vpm-m16.yaml", "the command `...`").
    pub model: String,
    pub condition: TrimRequest,
    pub loading: Loading,
    pub parameters: Vec<MovedParameter>,
    pub rows: Vec<Row>,
}

/// The step a parameter is moved by: 2 % of its value, or 0.02 of its unit where the value is
/// near zero (positions, products of inertia, a correction), so that the trims either side
/// differ well above their convergence.
fn step_of(value: f64) -> f64 {
    (0.02 * value.abs()).max(0.02)
}

/// Whether `name` is a trim quantity (else a derivative of the linear model).
fn is_trim_quantity(name: &str) -> bool {
    crate::inputs::quantity::TRIM
        .iter()
        .any(|q| q.name() == name)
}

/// Every quantity's value at the request, by name: a trim quantity from the model's trim, a
/// derivative from its linear model (asked only where a quantity needs it).
fn values(
    model: &dyn FlightModel,
    request: &Request,
    quantities: &[BoundedQuantity],
) -> Result<Vec<f64>, String> {
    let at = |e: String| format!("at {} mph: {e}", request.condition.airspeed_mph);
    let (trims, linear) = if quantities.iter().all(|q| is_trim_quantity(&q.name)) {
        (model.trim(request).map_err(at)?, None)
    } else {
        let (t, l) = model.trim_and_linear_model(request).map_err(at)?;
        (t, Some(l))
    };
    quantities
        .iter()
        .map(|q| {
            if let Some((_, v)) = trims.iter().find(|(n, _)| *n == q.name) {
                return Ok(*v);
            }
            if is_trim_quantity(&q.name) {
                return Err(format!(
                    "{} gives no `{}` in its trim",
                    model.describe(),
                    q.name
                ));
            }
            linear
                .as_ref()
                .expect("asked for where a quantity is a derivative")
                .derivative_value(&q.name)
                .map_err(|e| format!("`{}`: {e}", q.name))
        })
        .collect()
}

/// Checks names: every parameter one the model declares, every quantity a trim quantity or a
/// derivative of a linear model.
pub fn check_names(
    model: &str,
    declared: &[Parameter],
    parameters: &[String],
    quantities: &[BoundedQuantity],
) -> Result<(), String> {
    // Each name at its nominal value: `check_values` refuses a name the model does not declare.
    let at_nominal: crate::external::Values = parameters
        .iter()
        .map(|p| {
            let nominal = declared
                .iter()
                .find(|d| &d.name == p)
                .map_or(0.0, |d| d.nominal);
            (p.clone(), nominal)
        })
        .collect();
    crate::external::check_values(model, declared, &at_nominal)?;
    let flight = crate::fit::TargetCondition::Flight(
        TrimRequest::level(50.0),
        Loading {
            mass_kg: None,
            density_altitude_ft: 0.0,
        },
    );
    for q in quantities {
        crate::fit::Measure::parse(&flight, &q.name)?;
    }
    Ok(())
}

/// The parameters a study moves by default: those the model declares a range for (by name), or
/// every one it declares where it gives no range.
pub fn default_parameters(declared: &[Parameter]) -> Vec<String> {
    let ranged = crate::external::ranged_names(declared);
    if ranged.is_empty() {
        return declared.iter().map(|p| p.name.clone()).collect();
    }
    ranged
}

/// A study's requests, before any is asked: the nominal one first, then each parameter moved
/// down and up (central differences, one-sided at the edge of a plausible range: a correction
/// at its bound). What [`run`] asks on this machine's cores, and what a plan's shards ask
/// anywhere ([`crate::plan`]); [`finish`] reads the answers either way.
#[derive(Debug, Clone, PartialEq)]
pub struct SensitivityJobs {
    pub model: String,
    pub condition: TrimRequest,
    pub loading: Loading,
    pub moved: Vec<MovedParameter>,
    pub quantities: Vec<BoundedQuantity>,
    /// The requests in order: the nominal one, then each parameter's down and up.
    pub requests: Vec<Request>,
}

/// The study's requests (see [`SensitivityJobs`]), its names checked against the model's.
pub fn jobs(
    model: &dyn FlightModel,
    request: TrimRequest,
    loading: Loading,
    parameters: &[String],
    quantities: &[BoundedQuantity],
) -> Result<SensitivityJobs, String> {
    let declared = model.parameters()?;
    check_names(&model.describe(), &declared, parameters, quantities)?;
    let nominal = Request::at(request, loading);
    let moved: Vec<MovedParameter> = parameters
        .iter()
        .map(|name| {
            let p = declared
                .iter()
                .find(|p| &p.name == name)
                .expect("checked above");
            MovedParameter {
                name: name.clone(),
                unit: p.unit.clone(),
                meaning: p.meaning.clone(),
                value: p.nominal,
                step: step_of(p.nominal),
                range: p.range.clone(),
            }
        })
        .collect();
    let mut requests = vec![nominal.clone()];
    for p in &moved {
        let (lo, hi) = span(p);
        requests.push(nominal.clone().with(&p.name, lo));
        requests.push(nominal.clone().with(&p.name, hi));
    }
    Ok(SensitivityJobs {
        model: model.describe(),
        condition: request,
        loading,
        moved,
        quantities: quantities.to_vec(),
        requests,
    })
}

/// Where a parameter is moved to, down and up: a step either way, cut at its plausible range.
fn span(p: &MovedParameter) -> (f64, f64) {
    let (mut lo, mut hi) = (p.value - p.step, p.value + p.step);
    if let Some(r) = &p.range {
        (lo, hi) = (lo.max(r.lower), hi.min(r.upper));
    }
    (lo, hi)
}

impl SensitivityJobs {
    /// Whether request `k` is asked: a moved parameter at its own nominal value (its range
    /// ends there) is not asked again, the nominal request's answer standing for it.
    pub fn asked(&self, k: usize) -> bool {
        if k == 0 {
            return true;
        }
        let p = &self.moved[(k - 1) / 2];
        let (lo, hi) = span(p);
        [lo, hi][(k - 1) % 2] != p.value
    }

    /// Request `k` asked: the quantities' values there.
    pub fn evaluate(&self, model: &dyn FlightModel, k: usize) -> Result<Vec<f64>, String> {
        values(model, &self.requests[k], &self.quantities)
    }
}

/// Runs the study: each parameter moved either way, each quantity differentiated, and the
/// change each failing quantity needs from each parameter alone.
pub fn run(
    model: &dyn FlightModel,
    request: TrimRequest,
    loading: Loading,
    parameters: &[String],
    quantities: &[BoundedQuantity],
) -> Result<Study, String> {
    let jobs = jobs(model, request, loading, parameters, quantities)?;
    let base = jobs.evaluate(model, 0)?;
    let moved: Vec<usize> = (1..jobs.requests.len()).collect();
    let answers = crate::run::parallel::parallel_map(&moved, |&k| {
        jobs.asked(k).then(|| jobs.evaluate(model, k))
    });
    finish(
        &jobs,
        std::iter::once(Some(Ok(base))).chain(answers).collect(),
    )
}

/// The study from its requests' answers (in [`SensitivityJobs::requests`]' order; `None` where
/// a request was not asked, [`SensitivityJobs::evaluate`]): the first failure, or each
/// quantity's derivatives and what would close it.
pub fn finish(
    jobs: &SensitivityJobs,
    answers: Vec<Option<Result<Vec<f64>, String>>>,
) -> Result<Study, String> {
    let at = jobs.requests[0].condition.airspeed_mph;
    let base = match answers.first() {
        Some(Some(Ok(v))) => v.clone(),
        Some(Some(Err(e))) => return Err(e.clone()),
        _ => return Err(format!("the nominal request at {at} mph has no answer")),
    };
    let quantities = &jobs.quantities;
    let moved = jobs.moved.clone();
    let mut slopes: Vec<Vec<f64>> = Vec::new();
    for (i, p) in moved.iter().enumerate() {
        let (lo, hi) = span(p);
        let side = |k: usize, x: f64| -> Result<Vec<f64>, String> {
            match &answers[k] {
                None => Ok(base.clone()),
                Some(Ok(v)) => Ok(v.clone()),
                Some(Err(e)) => Err(format!("{} at {x}: {e}", p.name)),
            }
        };
        let (down, up) = (side(1 + 2 * i, lo)?, side(2 + 2 * i, hi)?);
        slopes.push(
            up.iter()
                .zip(&down)
                .map(|(u, d)| (u - d) / (hi - lo))
                .collect(),
        );
    }
    let rows = quantities
        .iter()
        .zip(&base)
        .enumerate()
        .map(|(i, (q, &value))| {
            let inside = q.bound.map(|[lo, hi]| (lo..=hi).contains(&value));
            let edge = match (q.bound, inside) {
                (Some([lo, hi]), Some(false)) => Some(if value < lo { lo } else { hi }),
                _ => None,
            };
            let effects = moved
                .iter()
                .zip(&slopes)
                .map(|(p, s)| {
                    let derivative = s[i];
                    // A change over the step below a millionth of the value is the trim's
                    // convergence, not the parameter: the quantity does not move with it.
                    let moves = derivative.is_finite()
                        && (derivative * p.step).abs() > 1e-6 * value.abs().max(1e-6);
                    let needed_change = edge.filter(|_| moves).map(|e| (e - value) / derivative);
                    let needed_value = needed_change.map(|d| p.value + d);
                    Effect {
                        parameter: p.name.clone(),
                        derivative,
                        needed_change,
                        needed_value,
                        plausible: match (&p.range, needed_value) {
                            (Some(r), Some(v)) => Some((r.lower..=r.upper).contains(&v)),
                            _ => None,
                        },
                    }
                })
                .collect();
            Row {
                quantity: q.name.clone(),
                value,
                bound: q.bound,
                inside,
                effects,
            }
        })
        .collect();
    Ok(Study {
        model: jobs.model.clone(),
        condition: jobs.condition,
        loading: jobs.loading,
        parameters: moved,
        rows,
    })
}

/// What a case asks of its model at one condition: its loading, the condition
/// (`airspeed_mph` picks one where the case has several), and the quantities of its
/// `derivative` and `trim` checks there (those on the model as it is: no `set`, ratio or
/// corrections of their own), each with the bound its tolerance puts on it. The model is the
/// case's subject ([`crate::checks::flight_model`]): an aircraft or another simulation.
pub fn from_case(
    case: &crate::suite::case::Case,
    airspeed_mph: Option<f64>,
) -> Result<(Loading, TrimRequest, Vec<BoundedQuantity>), String> {
    use crate::checks::{Measured, Place};
    let Some((_, loading)) = crate::checks::flight_model(&case.subject) else {
        return Err(format!(
            "{} is not a case of a flight model (an aircraft or an external model)",
            case.id
        ));
    };
    let at = |k: &crate::checks::Check| match k.behaviour().measured() {
        Measured::At(Place::Flight(c)) => Some(c),
        _ => None,
    };
    let mut conditions: Vec<TrimRequest> = case
        .checks
        .iter()
        .filter_map(at)
        .filter(|c| airspeed_mph.is_none_or(|v| c.airspeed_mph == v))
        .collect();
    conditions.dedup();
    let request = match conditions.as_slice() {
        [one] => *one,
        [] => {
            let mut kinds: Vec<&str> = case.checks.iter().map(|c| c.kind().name()).collect();
            kinds.sort_unstable();
            kinds.dedup();
            return Err(format!(
                "{} has no derivative or trim check{} (its checks are of kind {}): sensitivity \
                 moves parameters about one trim, and reads the `derivative` and `trim` checks there",
                case.id,
                airspeed_mph.map_or(String::new(), |v| format!(" at {v} mph")),
                kinds.join(", ")
            ));
        }
        many => {
            return Err(format!(
                "{} checks at {} mph: pick one with --airspeed-mph",
                case.id,
                many.iter()
                    .map(|c| c.airspeed_mph.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
    };
    let mut quantities = Vec::new();
    for k in case.checks.iter().filter(|k| at(k) == Some(request)) {
        for e in &k.expectations {
            let Some(name) = k.behaviour().model_name(&e.quantity) else {
                continue;
            };
            let bound = crate::checks::tolerance::judge(
                &e.tolerance.kind,
                e.value,
                e.value.unwrap_or(0.0),
                None,
            )
            .map(|j| [j.lower, j.upper]);
            if !quantities.iter().any(|q: &BoundedQuantity| q.name == name) {
                quantities.push(BoundedQuantity { name, bound });
            }
        }
    }
    Ok((loading, request, quantities))
}
