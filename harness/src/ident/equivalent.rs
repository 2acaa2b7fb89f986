//! What the estimator finds in a linear model: the model's response to the records' own
//! controls (or to a flat spectrum over the band), identified with the same set-up as the
//! records.
//!
//! A flight's identified derivatives are those of the set-up's model that best fits the
//! aircraft's response in the identification band. When the aircraft has dynamics the set-up
//! leaves out (the blades' flapping, the inflow's lag), the best fit is not the quasi-static
//! linearisation: it absorbs what those dynamics do in the band, weighted by the inputs the
//! records carry. A linear model that keeps those dynamics
//! ([`cierva_model::aircraft::flapping`]) gives the identified values a flight should find: its
//! states' transforms are its frequency response times the records' control transforms, at
//! the estimator's own (segment, frequency) points, and the same fit runs on them. Noise and
//! turbulence are absent, so the result is the estimator's limit for that model and those
//! inputs; and no simulation is needed, so a model whose open-loop response diverges under a
//! pilot's inputs (the slow spiral) is compared as well as a stable one.

use super::estimate::C;
use super::{ConfigSpec, Identification, Source, control_channel, identify_from, signals};
use crate::inputs::record::Record;
use cierva_model::LinearModel;
use cierva_model::aircraft::flapping::WithFlapping;
use nalgebra::DMatrix;

/// What the set-up identifies from a model's response to the records' own controls: for each
/// record, the transforms of every control the model has (its channel `<control>_percent`,
/// perturbed from the sidecar's trim; one the record does not carry stays at trim) at the
/// estimator's (segment, frequency) points, exactly as the record's identification takes them,
/// and the states' transforms the model's frequency response gives them, `X = H(i w) U`. The
/// records' weighting of frequencies and controls is kept, noise and turbulence are not, and
/// a model whose open-loop response would diverge under a pilot's inputs (a slow spiral, say)
/// needs no simulation. The set-up's states must be states of the response.
pub fn identify_with_records(
    records: &[Record],
    config: &ConfigSpec,
    response: Response,
) -> Result<Identification, String> {
    if records.is_empty() {
        return Err("no record to identify".into());
    }
    let index = state_index(config, response.states)?;
    let mut excitations = Vec::with_capacity(records.len());
    // The response at each distinct frequency, once (segments and records repeat them).
    let mut at: Vec<(f64, DMatrix<C>)> = Vec::new();
    for r in records {
        // Every model control the record carries in percent, in the response's order.
        let mut all = config.clone();
        all.controls = response
            .controls
            .iter()
            .filter_map(|c| {
                control_channel(r, c)
                    .filter(|ch| ch.ends_with("_percent"))
                    .map(|ch| (c.clone(), ch))
            })
            .collect();
        for (c, ch) in &config.controls {
            if all.controls.get(c) != Some(ch) {
                return Err(format!(
                    "{}: the set-up's control `{c}` ({ch}) is not a control of the model in percent",
                    r.path.display()
                ));
            }
        }
        let controls: Vec<String> = all.controls.keys().cloned().collect();
        let (xs, us) = signals(r, &all)?;
        let spectra = super::estimate::spectra(
            super::estimate::Signals {
                states: &config.states,
                controls: &controls,
                x: &xs,
                u: &us,
                dt_s: r.dt_s(),
            },
            &super::frequencies(config)?,
            config.windowing.settings(),
        )
        .map_err(|e| format!("{}: {e}", r.path.display()))?;
        let (omegas, ft) = (spectra.omegas(), spectra.transforms());
        let n = config.states.len();
        let columns: Vec<usize> = controls
            .iter()
            .map(|c| {
                response
                    .controls
                    .iter()
                    .position(|m| m == c)
                    .ok_or_else(|| format!("the model has no control `{c}`"))
            })
            .collect::<Result<_, _>>()?;
        let mut var_ft: Vec<Vec<C>> = vec![Vec::with_capacity(omegas.len()); n];
        for (k, &w) in omegas.iter().enumerate() {
            let h = match at.iter().find(|(x, _)| *x == w) {
                Some((_, h)) => h.clone(),
                None => {
                    let h = (response.at)(w)?;
                    at.push((w, h.clone()));
                    h
                }
            };
            for (i, &row) in index.iter().enumerate() {
                let x: C = columns
                    .iter()
                    .enumerate()
                    .map(|(j, &col)| h[(row, col)] * ft[n + j][k])
                    .sum();
                var_ft[i].push(x);
            }
        }
        // The set-up's own controls, in its order.
        for c in config.controls.keys() {
            let j = controls.iter().position(|x| x == c).unwrap_or(0);
            var_ft.push(ft[n + j].clone());
        }
        excitations.push((omegas.to_vec(), var_ft));
    }
    let id = records
        .iter()
        .map(|r| r.meta.id.as_str())
        .collect::<Vec<_>>()
        .join(" + ");
    identify_from(
        &format!("{id} (model)"),
        Source::Response(excitations),
        config,
    )
}

/// The aircraft linearised with its flapping states ([`WithFlapping`]), as the set-up
/// identifies it from its baseband response to the records' controls
/// ([`identify_with_records`]).
pub fn identify_flapping(
    records: &[Record],
    config: &ConfigSpec,
    model: &WithFlapping,
) -> Result<Identification, String> {
    let at = |w: f64| model.baseband_response(w).map_err(|e| e.to_string());
    identify_with_records(
        records,
        config,
        Response {
            states: model.model.states(),
            controls: model.model.controls(),
            at: &at,
        },
    )
}

fn state_index(config: &ConfigSpec, states: &[String]) -> Result<Vec<usize>, String> {
    config
        .states
        .iter()
        .map(|s| {
            states
                .iter()
                .position(|m| m == s)
                .ok_or_else(|| format!("the model has no state `{s}` of the set-up"))
        })
        .collect()
}

/// A frequency response to identify: the model's state and control names, and its response
/// (states x controls) at a frequency in rad/s.
pub struct Response<'a> {
    pub states: &'a [String],
    pub controls: &'a [String],
    pub at: &'a dyn Fn(f64) -> Result<DMatrix<C>, String>,
}

/// What the set-up identifies from `model`'s own frequency response in its band
/// ([`identify_response`] of `(i w I - A)^-1 B`).
pub fn identify_in_band(
    config: &ConfigSpec,
    model: &LinearModel,
) -> Result<Identification, String> {
    let at = lti_response(model);
    identify_response(
        config,
        Response {
            states: model.states(),
            controls: model.controls(),
            at: &at,
        },
    )
}

/// A time-invariant model's frequency response `(i w I - A)^-1 B` (states x controls).
pub fn lti_response(model: &LinearModel) -> impl Fn(f64) -> Result<DMatrix<C>, String> + '_ {
    move |w: f64| {
        let (a, b) = (model.a(), model.b());
        let n = a.nrows();
        let m = DMatrix::<C>::from_fn(n, n, |i, j| {
            C::new(-a[(i, j)], if i == j { w } else { 0.0 })
        });
        m.lu()
            .solve(&b.map(|v| C::new(v, 0.0)))
            .ok_or_else(|| format!("the model has a pole at {w} rad/s on the imaginary axis"))
    }
}

/// What the set-up identifies from a frequency response in its band: each of the set-up's
/// controls excited alone with a unit input at every frequency (a flat spectrum), the states'
/// responses stacked as the runs of several records are, and fitted by the set-up's method.
/// Independent of any record, so a case can ask for it; the records' own inputs ([`crate::ident::estimate::identify`])
/// weight the frequencies and controls as the flights did. The set-up's states and controls
/// must be the response's.
pub fn identify_response(
    config: &ConfigSpec,
    response: Response,
) -> Result<Identification, String> {
    let index = state_index(config, response.states)?;
    let controls = config
        .controls
        .keys()
        .map(|c| {
            response
                .controls
                .iter()
                .position(|m| m == c)
                .ok_or_else(|| format!("the model has no control `{c}` of the set-up"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let omegas = super::frequencies(config)?.omegas();
    // Per frequency, the response of every state to every control.
    let responses = omegas
        .iter()
        .map(|&w| (response.at)(w))
        .collect::<Result<Vec<_>, String>>()?;
    let excitations = controls
        .iter()
        .enumerate()
        .map(|(k, &col)| {
            let mut var_ft: Vec<Vec<C>> = index
                .iter()
                .map(|&i| responses.iter().map(|r| r[(i, col)]).collect())
                .collect();
            for j in 0..controls.len() {
                let u = if j == k { 1.0 } else { 0.0 };
                var_ft.push(vec![C::new(u, 0.0); omegas.len()]);
            }
            (omegas.clone(), var_ft)
        })
        .collect();
    super::identify_from(
        "frequency response",
        super::Source::Response(excitations),
        config,
    )
}
