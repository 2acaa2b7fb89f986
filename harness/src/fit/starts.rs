//! A fit from several starts: the fit file's own, then points of a scrambled Sobol' sequence
//! around the path its fit took ([`points`]). Where the cost is rough the end depends on the path: a
//! fit that stops at the edge of the model's equilibria (every step its trust region allows
//! loses some row's autorotation) ends wherever its path met that edge, and the standard
//! errors from the cost's curvature there do not say so. Between starts, the spread of the ends
//! the data cannot tell apart (their cost within [`EQUIVALENT_COST`] of the best) does, and the
//! best end is the one kept.

use crate::fit::{self, FitResult, Problem, Status};
use serde::Serialize;

/// The scrambled Sobol' sequence's seed for the starts after the file's own (any fixed value:
/// a fit file's starts are the same on every run).
pub const SEED: u32 = 0x05ee_df17;

/// Ends whose cost is within this of the best are ones the data cannot tell apart: the cost is
/// a chi-square (the targets' residuals over their standard errors, squared and summed), and a
/// rise of 1 from its minimum bounds one parameter's one-standard-error interval (Press et al.,
/// *Numerical Recipes*, 3rd ed., 2007, Sec. 15.6.5).
pub const EQUIVALENT_COST: f64 = 1.0;

/// The most starts a fit file may ask for (each is a whole fit).
pub const MAX_STARTS: usize = 32;

/// One start's fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct End {
    /// Where it started, in the problem's parameter order.
    pub start: Vec<f64>,
    /// Where it ended.
    pub values: Vec<f64>,
    pub cost: f64,
    pub status: &'static str,
    pub evaluations: usize,
    /// Whether its fit stopped because every trial step lost an equilibrium.
    pub stalled: bool,
}

/// A fit's starts and what they say about its end.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Starts {
    /// The parameters' names, in order.
    pub parameters: Vec<String>,
    /// Every start's end, the file's own first.
    pub ends: Vec<End>,
    /// The end kept: the lowest cost among those that converged or reached the iteration limit.
    pub best: usize,
    /// The ends within [`EQUIVALENT_COST`] of the best's cost.
    pub equivalent: Vec<usize>,
    /// Half the range of each parameter over the equivalent ends (0 with one of them).
    pub spread: Vec<f64>,
}

/// The starts after the file's own: `n - 1` points of the scrambled Sobol' sequence in the box
/// around the path the first fit took, from `start` to `end`, widened by half its size each way
/// (by [`MIN_BOX`] of a parameter's bounds where the fit hardly moved it), within the bounds.
/// Starts drawn over the whole bounds mostly begin where the model has no equilibrium at some
/// target (the PCA-2's pitch over +-4 deg), and tell nothing; these ask whether the fit ends
/// in the same place from near where it went.
pub fn points(problem: &Problem, start: &[f64], end: &[f64], n: usize) -> Vec<Vec<f64>> {
    (0..n.saturating_sub(1))
        .map(|i| {
            problem
                .parameters
                .iter()
                .enumerate()
                .map(|(k, p)| {
                    let (a, b) = (start[k].min(end[k]), start[k].max(end[k]));
                    let half = (0.5 * (b - a)).max(MIN_BOX * (p.upper - p.lower));
                    let (lo, hi) = ((a - half).max(p.lower), (b + half).min(p.upper));
                    let u = f64::from(sobol_burley::sample(i as u32, k as u32, SEED));
                    lo + u * (hi - lo)
                })
                .collect()
        })
        .collect()
}

/// The box's least half-width, as a fraction of a parameter's bounds.
pub const MIN_BOX: f64 = 0.02;

/// Fits `problem` from `n` starts (its own, then [`points`]) and keeps the best end (its cost and
/// targets before the fit stay the file's own start's), with a warning when the
/// ends the data cannot tell apart spread by more than a standard error, or when a start other
/// than the file's reached a lower cost. `done` is called after each start (a progress bar).
pub fn fit_from_starts(problem: &Problem, n: usize, done: impl Fn(usize)) -> (FitResult, Starts) {
    let own: Vec<f64> = problem.parameters.iter().map(|p| p.start).collect();
    let first = fit::fit(problem);
    done(1);
    let others = points(problem, &own, &first.values, n);
    let mut results = vec![(own, first)];
    for (i, start) in others.into_iter().enumerate() {
        let mut p = problem.clone();
        for (par, v) in p.parameters.iter_mut().zip(&start) {
            par.start = *v;
        }
        results.push((start, fit::fit(&p)));
        done(i + 2);
    }
    let (best, equivalent, spread) = choose(&results);
    let starts = Starts {
        parameters: problem
            .parameters
            .iter()
            .map(|p| p.kind.name().to_string())
            .collect(),
        ends: results
            .iter()
            .map(|(start, r)| End {
                start: start.clone(),
                values: r.values.clone(),
                cost: r.cost,
                status: r.status.name(),
                evaluations: r.evaluations,
                stalled: r.stalled(),
            })
            .collect(),
        best,
        equivalent,
        spread,
    };
    // "Before" stays the file's own start (the uncorrected model, say), whichever end is kept.
    let (cost_start, before) = (results[0].1.cost_start, results[0].1.before.clone());
    let mut result = results.swap_remove(best).1;
    result.cost_start = cost_start;
    result.before = before;
    result.warnings.extend(warnings(&starts, &result));
    (result, starts)
}

/// Among fits from several starts (the file's own first): the one kept (the lowest cost among
/// those that converged or reached the iteration limit; the file's own unless another is lower
/// by more than rounding), those within [`EQUIVALENT_COST`] of it, and half the range of each
/// parameter over them.
pub fn choose(results: &[(Vec<f64>, FitResult)]) -> (usize, Vec<usize>, Vec<f64>) {
    let usable = |r: &FitResult| {
        matches!(r.status, Status::Converged | Status::IterationLimit) && r.cost.is_finite()
    };
    let best = (0..results.len())
        .filter(|&i| usable(&results[i].1))
        .min_by(|&a, &b| results[a].1.cost.total_cmp(&results[b].1.cost))
        .filter(|&i| !usable(&results[0].1) || results[i].1.cost < results[0].1.cost - 1e-9)
        .unwrap_or(0);
    let best_cost = results[best].1.cost;
    let equivalent: Vec<usize> = (0..results.len())
        .filter(|&i| usable(&results[i].1) && results[i].1.cost <= best_cost + EQUIVALENT_COST)
        .collect();
    let m = results[0].1.values.len();
    let spread = (0..m)
        .map(|k| {
            let (lo, hi) = equivalent
                .iter()
                .map(|&i| results[i].1.values[k])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                });
            if equivalent.is_empty() {
                f64::NAN
            } else {
                0.5 * (hi - lo)
            }
        })
        .collect();
    (best, equivalent, spread)
}

/// What the starts say that the kept fit's own numbers do not.
pub fn warnings(s: &Starts, kept: &FitResult) -> Vec<String> {
    let mut out = Vec::new();
    if s.best != 0 {
        out.push(format!(
            "of {} starts, start {} (from {}) reached cost {:.3}, below the file's own start's {:.3} ({}): its end is kept",
            s.ends.len(),
            s.best + 1,
            values(&s.parameters, &s.ends[s.best].start),
            s.ends[s.best].cost,
            s.ends[0].cost,
            s.ends[0].status
        ));
    }
    let wide: Vec<String> = s
        .parameters
        .iter()
        .zip(&s.spread)
        .zip(&kept.standard_errors)
        .filter(|((_, sp), se)| sp.is_finite() && **sp > **se)
        .map(|((name, sp), se)| format!("{name} +- {sp:.4} ({:.1} standard errors)", sp / se))
        .collect();
    if !wide.is_empty() {
        out.push(format!(
            "the end depends on the start: {} of {} starts end within cost {EQUIVALENT_COST} of the best, spread over {}; the standard errors describe the cost's curvature at the kept end only",
            s.equivalent.len(),
            s.ends.len(),
            wide.join(", ")
        ));
    }
    out
}

fn values(names: &[String], v: &[f64]) -> String {
    names
        .iter()
        .zip(v)
        .map(|(n, x)| format!("{n} = {x:.4}"))
        .collect::<Vec<_>>()
        .join(", ")
}
