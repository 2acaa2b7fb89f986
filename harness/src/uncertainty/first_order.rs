//! First-order propagation (`propagate`): each estimated input at two probes, an additive
//! surrogate through them, and a residual check of its additivity. Each evaluation of a case
//! with autorotation checks is a table of autorotation searches, too slow to sample;
//! [`super::study`] chooses this for such a case on any model (`--method auto`) or when asked.

use super::distribution::Input;
use super::propagate::{
    CaseUncertainty, Contributor, Interval, NO_GRID_STUDY, Point, Quantity, QuantityUncertainty,
    failure_causes, hash, judge, mean_std, pass_fraction, percentile, refined_value, unjudged,
    with_terms,
};
use crate::suite::case::Case;
use crate::suite::outcome::CheckResult;

/// A first-order propagation's points: each input at its two probes (up, then down; the
/// moves, `(input, side)`), then the residual check's draws of every input.
pub(super) fn jobs(inputs: &[Input]) -> (Vec<(usize, f64)>, Vec<super::jobs::PointJob>) {
    let moves: Vec<(usize, f64)> = (0..inputs.len())
        .flat_map(|i| [(i, 1.0), (i, -1.0)])
        .collect();
    let moved = moves.iter().map(|&(i, side)| super::jobs::PointJob {
        values: (inputs.iter().enumerate())
            .map(|(k, x)| match k == i {
                true => (x.distribution).quantile(PROBE_QUANTILE[usize::from(side < 0.0)]),
                false => x.nominal,
            })
            .collect(),
        start: None,
        tag: format!("first-order-{i}-{side}"),
    });
    let drawn = residual_draws(inputs)
        .into_iter()
        .map(|values| super::jobs::PointJob {
            tag: format!("residual-{:x}", hash(&values)),
            values,
            start: None,
        });
    let points = moved.chain(drawn).collect();
    (moves, points)
}

/// First-order propagation (a case with autorotation checks: each evaluation is a table of
/// autorotation searches, too slow to sample). Each input is moved to its 5 % and 95 % quantiles ([`PROBE_QUANTILE`]),
/// all others nominal (`2 d` evaluations, on every core). The quantity is then taken as
/// additive in its inputs, `S(x) = S0 + sum_i g_i(x_i)`, each `g_i` the parabola through the
/// input's three values (the line through two where one side finds no equilibrium): the
/// first-order cut-HDMR or univariate dimension-reduction surrogate (Rahman and Xu 2004;
/// REFERENCES.md). It is exact for a quantity that is quadratic in each input without
/// interactions, and unlike a linear model it carries a response's curvature into the mean and
/// a skewed one into the interval. The surrogate, evaluated at [`SURROGATE_DRAWS`] draws of the
/// inputs (no model evaluations), gives the mean, `u_input` (its standard deviation), the 95 %
/// interval (its 2.5 and 97.5 percentiles), the check's pass probability (the share of draws
/// in which every quantity is inside its tolerance) and each input's share of the variance,
/// `Var g_i / sum_j Var g_j`, which stands for both Sobol' indices (equal in an additive
/// model). The grid study's refined cases (`u_num`) run in the same batch as the moves, first,
/// as the longest ([`super::jobs::CaseJobs::run_locally`]).
pub(super) fn summary(
    study: &super::jobs::CaseJobs,
    nominal: &[CheckResult],
    moves: &[(usize, f64)],
    evaluated: Vec<Point>,
    refined_results: Vec<Vec<CheckResult>>,
) -> CaseUncertainty {
    let (case, inputs, grid) = (&study.case, &study.inputs, study.grid.as_ref());
    // Each moved input's value and point (in `moves`' order), then the draws and theirs.
    let mut evaluated = evaluated.into_iter();
    let points: Vec<(f64, Point)> = (moves.iter().zip(&study.points))
        .map(|(&(i, _), job)| (job.values[i], evaluated.next().expect("a point a move")))
        .collect();
    let drawn: Vec<(Vec<f64>, Point)> = (study.points[moves.len()..].iter())
        .map(|job| {
            (
                job.values.clone(),
                evaluated.next().expect("a point a draw"),
            )
        })
        .collect();
    let refinement = grid.map_or(
        NO_GRID_STUDY.to_string(),
        super::numerics::GridStudy::describe,
    );
    // A point fails where a check the nominal inputs evaluate gets no value (rows that find no
    // equilibrium at the nominal inputs already say so in their own results).
    let lost = |p: &Point| {
        nominal.iter().enumerate().find(|(j, n)| {
            n.error.is_none() && n.finding.is_none() && p.values[*j].iter().any(|v| !v.is_finite())
        })
    };
    let failed_points = points.iter().filter(|(_, p)| lost(p).is_some()).count();
    let first_error = points.iter().zip(moves).find_map(|((x, p), &(i, side))| {
        lost(p).map(|(_, n)| {
            format!(
                "{}: no value with {} at {x} (its {} % quantile)",
                n.check,
                inputs[i].name,
                100.0 * PROBE_QUANTILE[usize::from(side < 0.0)]
            )
        })
    });
    let draws = surrogate_draws(inputs);
    let mut results = Vec::new();
    for (j, (check, n)) in case.checks.iter().zip(nominal).enumerate() {
        let mut rows = Vec::new();
        let mut surrogate = Vec::new();
        // Each quantity's normal spread beyond the surrogate's draws.
        let mut spread = Vec::new();
        for (k, q) in n.quantities.iter().enumerate() {
            let numerics =
                grid.map(|g| g.numerical(&refined_results, j, q.value, &|r| refined_value(r, q)));
            let (out, values, u_interactions) = first_order_quantity(
                case,
                (check, n, q),
                (j, k),
                Probes {
                    moved: &points,
                    drawn: &drawn,
                    draws: &draws,
                },
                inputs,
                numerics,
            );
            spread.push(out.u_calibration.hypot(u_interactions));
            rows.push(out);
            surrogate.push(values);
        }
        // The check passes where every quantity does, draw by draw.
        let pass = if n.quantities.is_empty() {
            f64::from(u8::from(n.passed))
        } else {
            let draws: Vec<&[f64]> = surrogate.iter().map(Vec::as_slice).collect();
            pass_fraction(&n.quantities, &spread, &draws)
        };
        for r in &mut rows {
            r.set_pass_fraction(pass);
        }
        results.extend(rows);
    }
    CaseUncertainty {
        case: case.id.clone(),
        method: format!(
            "first order: each of {} inputs moved to its 5 % and 95 % quantiles ({} evaluations of the case); an additive surrogate (first-order cut-HDMR: the parabola through each input's three values) evaluated at {SURROGATE_DRAWS} draws of the inputs gives the mean, u_input, the 95 % interval, the pass probability and each input's share of the variance",
            inputs.len(),
            moves.len()
        ),
        inputs: inputs.clone(),
        evaluations: moves.len() + drawn.len() + 1 + refined_results.len(),
        failed_points,
        first_error,
        refinement,
        results,
    }
}

/// Where a first-order propagation moves each input, up then down: its 95 % and 5 % quantiles,
/// so that with the nominal value the three points span the bulk of the distribution (the
/// parabola through them interpolates over 90 % of its mass), wherever the nominal value sits
/// in it. Moves of one standard deviation about the nominal left an input at the end of its
/// range (a hinge offset from 0) probed on one side over a third of it, and a skewed one (the
/// pitch station) with half its mass beyond the upper probe; the surrogate's 95 % interval then
/// held 0.86-0.89 of TR 487's sampled draws.
const PROBE_QUANTILE: [f64; 2] = [0.95, 0.05];

/// Draws of the inputs on which a first-order surrogate is evaluated ([`SURROGATE_SEED`]'s
/// scrambled Sobol' points through each input's quantile): enough that its percentiles move by
/// well under a percent of the spread between seeds, and cheap (no model evaluations).
const SURROGATE_DRAWS: usize = 4096;
/// The surrogate's Sobol' seed (fixed: a propagation is reproducible).
const SURROGATE_SEED: u32 = 0x5eed;

/// Draws of every input at which a first-order propagation also evaluates the model, to check
/// the surrogate's one assumption, that the inputs act additively: the surrogate's residual
/// there (an interaction it cannot see, such as hinge offset with root cut-out on TR 487's
/// rotor speed, 0.016 rad/s over the two ranges' corners) joins `u_input` as its RMS. Four, on
/// the scrambled Sobol' points of [`RESIDUAL_SEED`]: a residual of the size of the inputs' own
/// spread shows at four draws, and each costs one evaluation of the case.
const RESIDUAL_DRAWS: usize = 4;
/// The residual draws' Sobol' seed (fixed, and not the surrogate's).
const RESIDUAL_SEED: u32 = 0x7e51d;

/// The residual check's draws of every input, by draw then input.
fn residual_draws(inputs: &[Input]) -> Vec<Vec<f64>> {
    (0..RESIDUAL_DRAWS)
        .map(|k| {
            inputs
                .iter()
                .enumerate()
                .map(|(i, x)| {
                    let u = f64::from(sobol_burley::sample(k as u32, i as u32, RESIDUAL_SEED));
                    x.distribution.quantile(u)
                })
                .collect()
        })
        .collect()
}

/// The inputs' surrogate draws, by input then draw.
fn surrogate_draws(inputs: &[Input]) -> Vec<Vec<f64>> {
    let margin = 0.5 / SURROGATE_DRAWS as f64;
    inputs
        .iter()
        .enumerate()
        .map(|(i, x)| {
            (0..SURROGATE_DRAWS)
                .map(|k| {
                    let u = f64::from(sobol_burley::sample(k as u32, i as u32, SURROGATE_SEED));
                    x.distribution.quantile(u.clamp(margin, 1.0 - margin))
                })
                .collect()
        })
        .collect()
}

/// One input's part of the first-order surrogate, `g(x) = alpha t + beta t^2` with
/// `t = x - x0`: the parabola through the nominal point `(x0, 0)` and the two moved ones
/// (`(x, S(x) - S0)`), or the line through the nominal and the one side that has a value (or
/// that moved: an input at the end of its support moves one way only). `None` where neither
/// side has a value.
fn univariate(x0: f64, (xp, dp): (f64, f64), (xm, dm): (f64, f64)) -> Option<(f64, f64)> {
    let (tp, tm) = (xp - x0, xm - x0);
    // A probe at the nominal value (to a thousandth of the probes' span) says nothing of slope.
    let near = 1e-3 * (xp - xm).abs();
    let (tp, tm) = (
        if tp.abs() <= near { 0.0 } else { tp },
        if tm.abs() <= near { 0.0 } else { tm },
    );
    let (up, um) = (dp.is_finite() && tp != 0.0, dm.is_finite() && tm != 0.0);
    match (up, um) {
        (true, true) if tp != tm => {
            // alpha tp + beta tp^2 = dp, alpha tm + beta tm^2 = dm
            let det = tp * tm * (tm - tp);
            Some((
                (dp * tm * tm - dm * tp * tp) / det,
                (dm * tp - dp * tm) / det,
            ))
        }
        (true, _) => Some((dp / tp, 0.0)),
        (_, true) => Some((dm / tm, 0.0)),
        // Moved nowhere (no spread), or one side lost where the other did not move.
        _ if (dp.is_finite() || tp == 0.0) && (dm.is_finite() || tm == 0.0) => Some((0.0, 0.0)),
        _ => None,
    }
}

/// One input's part of the surrogate at `x`: `alpha t + beta t^2` with `t = x - nominal`
/// ([`univariate`]'s coefficients), NaN where the input has none.
fn cut(part: Option<(f64, f64)>, nominal: f64, x: f64) -> f64 {
    part.map_or(f64::NAN, |(alpha, beta)| {
        let t = x - nominal;
        alpha * t + beta * t * t
    })
}

/// What a first-order propagation evaluated, for each of its quantities.
#[derive(Clone, Copy)]
struct Probes<'a> {
    /// Each moved input's value and evaluation, two an input (up, then down).
    moved: &'a [(f64, Point)],
    /// The residual check's draws of every input and their evaluations.
    drawn: &'a [(Vec<f64>, Point)],
    /// The inputs' surrogate draws, by input.
    draws: &'a [Vec<f64>],
}

/// One quantity of a first-order propagation (see [`propagate`]): its uncertainties and
/// verdict, the surrogate's value at every draw (for the check's pass probability) and the
/// surrogate's RMS residual at the residual draws (the interactions' part of `u_input`).
/// `(j, k)` are the check's and quantity's places.
fn first_order_quantity(
    case: &Case,
    (check, n, q): Quantity,
    (j, k): (usize, usize),
    Probes {
        moved: points,
        drawn,
        draws,
    }: Probes,
    inputs: &[Input],
    numerics: Option<Result<super::numerics::Numerical, String>>,
) -> (QuantityUncertainty, Vec<f64>, f64) {
    let s0 = q.value;
    let mut failed = 0;
    let parts: Vec<Option<(f64, f64)>> = inputs
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let (xp, p) = &points[2 * i];
            let (xm, m) = &points[2 * i + 1];
            let (sp, sm) = (p.values[j][k], m.values[j][k]);
            failed += usize::from(!sp.is_finite()) + usize::from(!sm.is_finite());
            univariate(x.nominal, (*xp, sp - s0), (*xm, sm - s0))
        })
        .collect();
    let surrogate = |x: &[f64]| -> f64 {
        s0 + inputs
            .iter()
            .zip(&parts)
            .zip(x)
            .map(|((input, part), v)| cut(*part, input.nominal, *v))
            .sum::<f64>()
    };
    // Each input's part at every draw, and the surrogate's value.
    let mut values = vec![s0; SURROGATE_DRAWS];
    let mut variances = Vec::with_capacity(inputs.len());
    for ((x, part), xs) in inputs.iter().zip(&parts).zip(draws) {
        let g: Vec<f64> = xs.iter().map(|v| cut(*part, x.nominal, *v)).collect();
        variances.push(mean_std(&g).1.powi(2));
        values.iter_mut().zip(&g).for_each(|(y, g)| *y += g);
    }
    // The residuals at the draws where the model has a value.
    let residuals: Vec<f64> = drawn
        .iter()
        .map(|(x, p)| p.values[j][k] - surrogate(x))
        .filter(|e| e.is_finite())
        .collect();
    failed += drawn.len() - residuals.len();
    // The residuals' mean moves the surrogate (its bias), their spread joins u_input; one
    // residual alone is its own spread.
    let (bias, u_interactions) = match residuals.len() {
        0 => (0.0, 0.0),
        1 => (0.0, residuals[0].abs()),
        _ => mean_std(&residuals),
    };
    values.iter_mut().for_each(|y| *y += bias);
    let (mean, u_input) = mean_std(&values);
    let total: f64 = variances.iter().sum();
    let mut contributors: Vec<Contributor> = inputs
        .iter()
        .zip(&variances)
        .map(|(x, v)| {
            let share = if total > 0.0 { v / total } else { 0.0 };
            Contributor {
                input: x.name.clone(),
                total: share,
                first: share,
                total_se: None,
                first_se: None,
            }
        })
        .collect();
    contributors.sort_by(|a, b| b.total.total_cmp(&a.total));
    let spread = (
        mean,
        percentile(&values, 2.5),
        percentile(&values, 97.5),
        u_input,
    );
    let residual = [(
        format!(
            "interactions (the additive surrogate's residual at {} of {RESIDUAL_DRAWS} draws: its mean moves the surrogate, its spread is this)",
            residuals.len()
        ),
        u_interactions,
    )];
    let (spread, contributors) = match u_interactions > 0.0 {
        true => {
            let (u, lo, hi, c) = with_terms(spread, contributors, &residual);
            ((mean, lo, hi, u), c)
        }
        false => (spread, contributors),
    };
    let mut out = unjudged(case, (check, n, q), spread, numerics, contributors, failed);
    out.samples = points.len() + drawn.len();
    out.failure_causes = failure_causes(
        points
            .iter()
            .map(|(_, p)| p)
            .chain(drawn.iter().map(|(_, p)| p)),
        j,
    );
    if u_input.is_finite() {
        // The surrogate's interval is not the model's (its residual rests on RESIDUAL_DRAWS
        // draws): only `|E| > 2 u_val` judges a model-form error here.
        judge(&mut out, q, Interval::None);
    } else {
        out.reason = "no verdict: a perturbed input finds no equilibrium on either side, so the inputs' uncertainty is unknown here".into();
    }
    super::propagate::mark_circular(&mut out, inputs);
    (out, values, u_interactions)
}
