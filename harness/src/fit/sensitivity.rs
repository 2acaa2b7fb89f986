//! Sensitivity of checked quantities to an aircraft's physical parameters: which parameter
//! would close a discrepancy, and is the value it would need plausible?
//!
//! For each parameter (see [`crate::inputs::parameters::PARAMETERS`]) the aircraft is trimmed and
//! linearised with the parameter moved a step either way, and each quantity's derivative with
//! respect to it is the central difference. For a quantity outside its bound, the change that
//! alone would bring it to the nearer edge is the linear estimate `(edge - value) / (dq/dp)`,
//! weighed against the parameter's plausible range from the aircraft file. It is a first-order
//! answer: a change that is large against the step is an extrapolation, and the table says by
//! how many steps.

use crate::inputs::aircraft::{AircraftFile, Range};
use crate::inputs::parameters::{PARAMETERS, parameter, set_parameter};
use crate::{Loading, TrimRequest};
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
    pub aircraft: String,
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

/// Every quantity's value at the aircraft as given, by name.
fn values(
    file: &AircraftFile,
    request: TrimRequest,
    loading: Loading,
    quantities: &[BoundedQuantity],
) -> Result<Vec<f64>, String> {
    let (trim, lin) = crate::run_linearise(&file.aircraft, request, loading)
        .map_err(|e| format!("at {} mph: {e}", request.airspeed_mph))?;
    let trims = crate::checks::trim::trim_quantities_of(&file.aircraft, loading, &trim);
    quantities
        .iter()
        .map(|q| {
            if let Some((_, v)) = trims.iter().find(|(n, _)| *n == q.name) {
                return Ok(*v);
            }
            lin.model
                .derivative_value(&q.name)
                .map_err(|e| format!("`{}`: {e}", q.name))
        })
        .collect()
}

/// Checks names: every parameter one the aircraft has, every quantity a trim quantity or a
/// derivative of the linearised model.
pub fn check_names(
    file: &AircraftFile,
    parameters: &[String],
    quantities: &[BoundedQuantity],
) -> Result<(), String> {
    for p in parameters {
        if parameter(&file.aircraft, p).is_none() {
            let names: Vec<String> = PARAMETERS.iter().map(|p| p.name.to_string()).collect();
            let hint = crate::inputs::yaml::nearest(p, &names)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(format!(
                "`{p}` is not a parameter of {}{hint}; the parameters are {}",
                file.id,
                names.join(", ")
            ));
        }
    }
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

/// Runs the study: each parameter moved either way, each quantity differentiated, and the
/// change each failing quantity needs from each parameter alone.
pub fn run(
    file: &AircraftFile,
    request: TrimRequest,
    loading: Loading,
    parameters: &[String],
    quantities: &[BoundedQuantity],
) -> Result<Study, String> {
    check_names(file, parameters, quantities)?;
    let base = values(file, request, loading, quantities)?;
    let moved: Vec<MovedParameter> = parameters
        .iter()
        .map(|name| {
            let value = parameter(&file.aircraft, name).expect("checked above");
            let info = PARAMETERS
                .iter()
                .find(|p| p.name == name)
                .expect("a known parameter");
            MovedParameter {
                name: name.clone(),
                unit: info.unit.to_string(),
                meaning: info.meaning.to_string(),
                value,
                step: step_of(value),
                range: file.ranges.get(name).cloned(),
            }
        })
        .collect();
    // The quantities with the parameter at `x` (the base values at its own value).
    let at = |p: &MovedParameter, x: f64| -> Result<Vec<f64>, String> {
        if x == p.value {
            return Ok(base.clone());
        }
        let mut f = file.clone();
        set_parameter(&mut f.aircraft, &p.name, x).expect("checked above");
        f.aircraft
            .validate()
            .map_err(|e| format!("{} at {x}: {e}", p.name))?;
        values(&f, request, loading, quantities).map_err(|e| format!("{} at {x}: {e}", p.name))
    };
    // Central differences, one-sided at the edge of a plausible range (a correction at its
    // bound).
    let slopes: Vec<Result<Vec<f64>, String>> = crate::parallel_map(&moved, |p| {
        let (mut lo, mut hi) = (p.value - p.step, p.value + p.step);
        if let Some(r) = &p.range {
            (lo, hi) = (lo.max(r.lower), hi.min(r.upper));
        }
        let (down, up) = (at(p, lo)?, at(p, hi)?);
        Ok(up
            .iter()
            .zip(&down)
            .map(|(u, d)| (u - d) / (hi - lo))
            .collect())
    });
    let slopes: Vec<Vec<f64>> = slopes.into_iter().collect::<Result<_, _>>()?;
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
        aircraft: file.id.clone(),
        condition: request,
        loading,
        parameters: moved,
        rows,
    })
}

/// What a case asks of its aircraft at one condition: the aircraft, its loading, the condition
/// (`airspeed_mph` picks one where the case has several), and the quantities of its
/// `derivative` and `trim` checks there (those on the aircraft as it is: no `set`, ratio or
/// corrections of their own), each with the bound its tolerance puts on it.
pub fn from_case(
    case: &crate::suite::case::Case,
    airspeed_mph: Option<f64>,
) -> Result<(AircraftFile, Loading, TrimRequest, Vec<BoundedQuantity>), String> {
    use crate::checks::{Measured, Place};
    let crate::checks::subject::Subject::Aircraft { file, loading } = &case.subject else {
        return Err(format!("{} is not a case of an aircraft", case.id));
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
            return Err(format!(
                "{} has no derivative or trim check{}",
                case.id,
                airspeed_mph.map_or(String::new(), |v| format!(" at {v} mph"))
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
    Ok((file.as_ref().clone(), *loading, request, quantities))
}
