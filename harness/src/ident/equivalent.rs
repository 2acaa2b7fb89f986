//! What the estimator finds in a linear model: the model flown with the records' own control
//! histories, its response identified with the same set-up as the records.
//!
//! A flight's identified derivatives are those of the set-up's model that best fits the
//! aircraft's response in the identification band. When the aircraft has dynamics the set-up
//! leaves out (the blades' flapping, the inflow's lag), the best fit is not the quasi-static
//! linearisation: it absorbs what those dynamics do in the band, weighted by the inputs the
//! records carry. A linear model that keeps those dynamics
//! ([`cierva_model::aircraft::flapping`]) gives the identified values a flight should find:
//! fly it with the records' measured controls (perturbations from the records' trim, at their
//! sample times, linear between samples), take its response in the set-up's states, and
//! identify that with the records' set-up. Noise and turbulence are absent, so the result is
//! the estimator's limit for that model and those inputs.

use super::estimate::C;
use super::record::Record;
use super::{ConfigSpec, Identification, Run, control_channel, identify_histories, signals};
use cierva_model::LinearModel;
use cierva_model::aircraft::flapping::{Periodic, WithFlapping};
use nalgebra::{DMatrix, DVector};

/// The model's exact discretisation for inputs linear between samples (first-order hold):
/// `x[k+1] = Phi x[k] + Gamma0 u[k] + Gamma1 (u[k+1] - u[k])`.
struct Discrete {
    phi: DMatrix<f64>,
    gamma0: DMatrix<f64>,
    gamma1: DMatrix<f64>,
}

fn discretise(a: &DMatrix<f64>, b: &DMatrix<f64>, dt_s: f64) -> Discrete {
    let (n, m) = (a.nrows(), b.ncols());
    // exp([[A dt, B dt, 0], [0, 0, I], [0, 0, 0]]) holds Phi, Gamma0 and Gamma1 in its top rows.
    let mut big = DMatrix::<f64>::zeros(n + 2 * m, n + 2 * m);
    big.view_mut((0, 0), (n, n)).copy_from(&(a * dt_s));
    big.view_mut((0, n), (n, m)).copy_from(&(b * dt_s));
    for k in 0..m {
        big[(n + k, n + m + k)] = 1.0;
    }
    let e = big.exp();
    Discrete {
        phi: e.view((0, 0), (n, n)).into_owned(),
        gamma0: e.view((0, n), (n, m)).into_owned(),
        gamma1: e.view((0, n + m), (n, m)).into_owned(),
    }
}

impl Discrete {
    fn step(&self, x: &DVector<f64>, u0: &DVector<f64>, u1: &DVector<f64>) -> DVector<f64> {
        &self.phi * x + &self.gamma0 * u0 + &self.gamma1 * (u1 - u0)
    }
}

/// The inputs at sample `k` as a vector.
fn inputs_at(u: &[Vec<f64>], k: usize) -> DVector<f64> {
    DVector::from_iterator(u.len(), u.iter().map(|h| h[k]))
}

/// The inputs at time `t`, linear between samples (held at the last).
fn inputs_between(u: &[Vec<f64>], dt_s: f64, t: f64) -> DVector<f64> {
    let samples = u.first().map_or(0, Vec::len);
    let s = (t / dt_s).max(0.0);
    let k = (s.floor() as usize).min(samples.saturating_sub(1));
    let f = if k + 1 < samples { s - k as f64 } else { 0.0 };
    DVector::from_iterator(
        u.len(),
        u.iter()
            .map(|h| h[k] + f * (h.get(k + 1).copied().unwrap_or(h[k]) - h[k])),
    )
}

/// The model flown from rest with control perturbations `u` (one history per model control,
/// each of `samples` values), sampled every `dt_s`: the state perturbations, one history per
/// model state.
pub fn fly(model: &LinearModel, u: &[Vec<f64>], dt_s: f64) -> Vec<Vec<f64>> {
    let d = discretise(model.a(), model.b(), dt_s);
    let n = model.a().nrows();
    let samples = u.first().map_or(0, Vec::len);
    let mut out = vec![Vec::with_capacity(samples); n];
    let mut x = DVector::<f64>::zeros(n);
    for k in 0..samples {
        for (i, o) in out.iter_mut().enumerate() {
            o.push(x[i]);
        }
        if k + 1 < samples {
            x = d.step(&x, &inputs_at(u, k), &inputs_at(u, k + 1));
        }
    }
    out
}

/// A periodic linear system ([`Periodic`], blade 1 at azimuth zero at the start) flown from
/// rest with control perturbations `u` sampled every `dt_s`: the state perturbations at the
/// samples. Over each azimuth interval of the system's samples, `A` and `B` are held at their
/// mean over the interval and the inputs are linear (the discretisation is exact for that
/// piecewise-constant system); the states are linear between the azimuth steps where a sample
/// falls.
pub fn fly_periodic(p: &Periodic, u: &[Vec<f64>], dt_s: f64) -> Vec<Vec<f64>> {
    let k = p.a_at.len();
    let n = p.a_at.first().map_or(0, |a| a.nrows());
    let h = 2.0 * std::f64::consts::PI / k as f64 / p.omega_rad_s;
    let steps: Vec<Discrete> = (0..k)
        .map(|j| {
            let next = (j + 1) % k;
            let a = (&p.a_at[j] + &p.a_at[next]) * 0.5;
            let b = (&p.b_at[j] + &p.b_at[next]) * 0.5;
            discretise(&a, &b, h)
        })
        .collect();
    let samples = u.first().map_or(0, Vec::len);
    let mut out = vec![Vec::with_capacity(samples); n];
    let mut x = DVector::<f64>::zeros(n);
    let mut t = 0.0;
    let mut j = 0;
    for s in 0..samples {
        let ts = s as f64 * dt_s;
        // Step on the azimuth grid until the next step would pass the sample.
        let mut next = steps[j].step(
            &x,
            &inputs_between(u, dt_s, t),
            &inputs_between(u, dt_s, t + h),
        );
        while t + h <= ts {
            x = next;
            t += h;
            j = (j + 1) % k;
            next = steps[j].step(
                &x,
                &inputs_between(u, dt_s, t),
                &inputs_between(u, dt_s, t + h),
            );
        }
        let f = (ts - t) / h;
        for (i, o) in out.iter_mut().enumerate() {
            o.push(x[i] + f * (next[i] - x[i]));
        }
    }
    out
}

/// What the set-up identifies from `model` flown with the records' controls (see the module's
/// documentation). Every control of the model is driven by the record's channel of that name in
/// percent (`<control>_pct`, perturbed from the sidecar's trim); a control the record does not
/// carry is held at trim. The set-up's states must be states of the model.
pub fn identify(
    records: &[Record],
    config: &ConfigSpec,
    model: &LinearModel,
) -> Result<Identification, String> {
    identify_flown(
        records,
        config,
        (model.states(), model.controls()),
        &|u, dt| fly(model, u, dt),
    )
}

/// [`identify`] for a periodic model (the aircraft linearised about its periodic motion,
/// [`cierva_model::aircraft::flapping::WithFlapping`]), flown by [`fly_periodic`].
pub fn identify_periodic(
    records: &[Record],
    config: &ConfigSpec,
    model: &WithFlapping,
) -> Result<Identification, String> {
    identify_flown(
        records,
        config,
        (model.model.states(), model.model.controls()),
        &|u, dt| fly_periodic(&model.periodic, u, dt),
    )
}

/// A model's state and control names.
type Names<'a> = (&'a [String], &'a [String]);

/// A model flown from rest: control perturbations (one history per control) and the sample
/// interval to state perturbations (one history per state).
type Flyer<'a> = dyn Fn(&[Vec<f64>], f64) -> Vec<Vec<f64>> + 'a;

fn identify_flown(
    records: &[Record],
    config: &ConfigSpec,
    (states, controls): Names,
    fly: &Flyer,
) -> Result<Identification, String> {
    if records.is_empty() {
        return Err("no record to identify".into());
    }
    let index = config
        .states
        .iter()
        .map(|s| {
            states
                .iter()
                .position(|m| m == s)
                .ok_or_else(|| format!("the model has no state `{s}` of the set-up"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut runs: Vec<Run> = Vec::with_capacity(records.len());
    for r in records {
        let (_, us) = signals(r, config)?;
        let samples = r.data.first().map_or(0, Vec::len);
        let mut inputs = Vec::with_capacity(controls.len());
        for c in controls {
            let history = match control_channel(r, c) {
                Some(ch) if ch.ends_with("_pct") => {
                    let trim = r.meta.trim.get(&ch).copied().unwrap_or(0.0);
                    r.channel(&ch)
                        .ok_or_else(|| format!("{}: channel `{ch}` is missing", r.path.display()))?
                        .iter()
                        .map(|v| v - trim)
                        .collect()
                }
                Some(ch) => {
                    return Err(format!(
                        "{}: the model's control `{c}` is in percent, the record's `{ch}` is not",
                        r.path.display()
                    ));
                }
                None => vec![0.0; samples],
            };
            inputs.push(history);
        }
        let response = fly(&inputs, r.dt_s());
        let mut xs: Vec<Vec<f64>> = index.iter().map(|&i| response[i].clone()).collect();
        // The same averaging the records' signals had (`signals`), on the response.
        if let Some(window) = super::flapping_window(r, config)? {
            for s in &mut xs {
                *s = super::blade_passage_average(s, window);
            }
        }
        if let Some(blades) = config.blade_passage_blades {
            let omega = r.meta.trim.get("omega_rotor_rad_s").copied().unwrap_or(0.0);
            if blades > 0 && omega > 0.0 {
                let window = 2.0 * std::f64::consts::PI / (f64::from(blades) * omega) / r.dt_s();
                for s in &mut xs {
                    *s = super::blade_passage_average(s, window);
                }
            }
        }
        runs.push((format!("{} (model)", r.path.display()), (xs, us), r.dt_s()));
    }
    let id = records
        .iter()
        .map(|r| r.meta.id.as_str())
        .collect::<Vec<_>>()
        .join(" + ");
    identify_histories(&format!("{id} (model)"), runs, config)
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
    let (a, b) = (model.a(), model.b());
    let n = a.nrows();
    let at = |w: f64| -> Result<DMatrix<C>, String> {
        let m = DMatrix::<C>::from_fn(n, n, |i, j| {
            C::new(-a[(i, j)], if i == j { w } else { 0.0 })
        });
        let rhs = b.map(|v| C::new(v, 0.0));
        m.lu()
            .solve(&rhs)
            .ok_or_else(|| format!("the model has a pole at {w} rad/s on the imaginary axis"))
    };
    identify_response(
        config,
        Response {
            states: model.states(),
            controls: model.controls(),
            at: &at,
        },
    )
}

/// What the set-up identifies from a frequency response in its band: each of the set-up's
/// controls excited alone with a unit input at every frequency (a flat spectrum), the states'
/// responses stacked as the runs of several records are, and fitted by the set-up's method.
/// Independent of any record, so a case can ask for it; the records' own inputs ([`identify`])
/// weight the frequencies and controls as the flights did. The set-up's states and controls
/// must be the response's.
pub fn identify_response(
    config: &ConfigSpec,
    response: Response,
) -> Result<Identification, String> {
    let index = config
        .states
        .iter()
        .map(|s| {
            response
                .states
                .iter()
                .position(|m| m == s)
                .ok_or_else(|| format!("the model has no state `{s}` of the set-up"))
        })
        .collect::<Result<Vec<_>, _>>()?;
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
            var_ft
        })
        .collect();
    super::identify_from(
        "frequency response",
        super::Source::Response(excitations),
        config,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A model of the set-up's own form is identified as itself from its frequency response
    /// (no noise, an exact structure): every derivative within 1e-9 of its own value.
    #[test]
    fn a_model_of_the_set_ups_form_is_identified_as_itself() {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let a = vec![
            vec![-0.13, 0.17, -0.7, -9.8, -0.04],
            vec![-0.17, -1.1, 31.0, -0.5, -0.29],
            vec![0.015, -0.086, -1.13, 0.0, -0.003],
            vec![0.0, 0.0, 1.0, 0.0, 0.0],
            vec![0.23, 1.16, -3.2, 0.0, -0.19],
        ];
        let b = vec![
            vec![-0.05],
            vec![-0.10],
            vec![0.041],
            vec![0.0],
            vec![0.126],
        ];
        let model = LinearModel::from_rows(
            names(&["u", "w", "q", "theta", "Omega"]),
            names(&["eta_s"]),
            &a,
            &b,
        )
        .unwrap();
        let config = ConfigSpec::for_model(super::super::Setup::Longitudinal);
        let found = identify_in_band(&config, &model).unwrap();
        assert_eq!(found.derivatives.len(), 4 * 6);
        for d in &found.derivatives {
            let want = model.derivative_value(&d.name).unwrap();
            assert!(
                (d.estimate - want).abs() < 1e-9 * (1.0 + want.abs()),
                "{}: {} against {want}",
                d.name,
                d.estimate
            );
        }
    }

    /// A periodic system whose coefficients do not vary flies as the time-invariant one: the
    /// azimuth grid's steps and the states' interpolation between them agree with the exact
    /// discretisation at the samples within 1e-6 of the response (a damped oscillator, a
    /// 1.3 Hz input, a grid step a third of the sample interval).
    #[test]
    fn a_periodic_system_with_constant_coefficients_flies_as_the_time_invariant_one() {
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -40.0, -3.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
        let model = LinearModel::new(
            vec!["x".into(), "v".into()],
            vec!["u".into()],
            a.clone(),
            b.clone(),
        )
        .unwrap();
        let p = Periodic {
            omega_rad_s: 2.0 * std::f64::consts::PI * 10.0,
            a_at: vec![a; 30],
            b_at: vec![b; 30],
        };
        let dt = 0.01;
        let u = vec![
            (0..500)
                .map(|k| (2.0 * std::f64::consts::PI * 1.3 * k as f64 * dt).sin())
                .collect::<Vec<f64>>(),
        ];
        let (x1, x2) = (fly(&model, &u, dt), fly_periodic(&p, &u, dt));
        let peak = x1[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in x1[0].iter().zip(&x2[0]) {
            assert!((a - b).abs() < 1e-6 * peak.max(1e-3), "{a} against {b}");
        }
    }

    /// A first-order lag `x' = -x/T + u/T` driven by a ramp from rest: the discretisation is
    /// exact for inputs linear between samples, so it matches `t - T (1 - exp(-t/T))` to
    /// rounding, at any step.
    #[test]
    fn a_lag_flown_through_a_ramp_is_exact() {
        let t_c = 0.3;
        let model = LinearModel::from_rows(
            vec!["x".into()],
            vec!["u".into()],
            &[vec![-1.0 / t_c]],
            &[vec![1.0 / t_c]],
        )
        .unwrap();
        for dt in [0.01, 0.1] {
            let n = (3.0 / dt) as usize;
            let u: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
            let x = fly(&model, &[u], dt);
            for (k, v) in x[0].iter().enumerate() {
                let t = k as f64 * dt;
                let want = t - t_c * (1.0 - (-t / t_c).exp());
                assert!(
                    (v - want).abs() < 1e-12,
                    "dt {dt}, t {t}: {v} against {want}"
                );
            }
        }
    }
}
