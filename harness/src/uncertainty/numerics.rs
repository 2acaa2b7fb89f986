//! The numerical uncertainty `u_num` of a case's quantities: a grid study of each
//! discretisation parameter refined alone, and Roache's grid convergence index for each.
//!
//! # Method
//! The model names its discretisation parameters ([`crate::external::FlightModel::refinements`]):
//! for cierva's aircraft the main rotor's azimuth step, each rotor's blade elements and the
//! periodicity tolerance. Each is refined alone by its ratio `r`, and again where the refined
//! model refines it further, giving the nominal value `S1` and the refined `S2` (and `S3`). The
//! nominal run is the one compared with the data, so the index is the coarse value's (Roache
//! 1998, Ch. 5; REFERENCES.md):
//!
//! ```text
//! GCI = Fs |S2 - S1| r^p / (r^p - 1)
//! ```
//!
//! - With three levels converging monotonically (`0 < (S3 - S2) / (S2 - S1) < 1`), the observed
//!   order `p_obs = ln((S2 - S1) / (S3 - S2)) / ln r`. Where it lies within a factor of
//!   [`ORDER_AGREEMENT`] of the scheme's formal order, `Fs = 1.25` ([`FS_OBSERVED`]) and `p` is
//!   the smaller of the two (the larger index).
//! - Otherwise (two levels, an oscillating or diverging sequence, an order far from the
//!   scheme's) `Fs = 3` ([`FS_TWO_GRIDS`]) at the formal order; with three levels the larger of
//!   the two differences is used.
//!
//! `u_num` is the root sum of squares of the parameters' indices (their errors independent),
//! taken whole as a standard uncertainty: conservative, since Roache intends the index as an
//! error band of about 95 %. A level that gives no value for a quantity leaves its numerical
//! uncertainty unknown, and the quantity without a verdict.

use crate::external::Refinement;
use crate::suite::case::{Case, Subject};
use crate::suite::outcome::{CheckResult, QuantityResult};
use serde::Serialize;

/// Roache's factor of safety with the observed order of three grids that agree with the
/// scheme's order.
pub const FS_OBSERVED: f64 = 1.25;

/// Roache's factor of safety for two grids, or three whose observed order cannot be trusted.
pub const FS_TWO_GRIDS: f64 = 3.0;

/// How far the observed order may lie from the formal one, as a factor either way, and still
/// be trusted: Roache reverts to the formal order and `Fs = 3` where `p_obs` is "unreasonable";
/// a factor of 2 admits a scheme whose error is not yet in its asymptotic range (a fourth-order
/// step whose error shows second order, say, through the inflow's interpolation), and refuses
/// one whose two differences are nearly equal (an order near 0) or that converges
/// implausibly fast.
pub const ORDER_AGREEMENT: f64 = 2.0;

/// The levels beyond the nominal that a parameter is refined to, where the model refines it
/// again: three levels in all, which give the observed order ([`crate::external::GRID_LEVELS`],
/// which a model behind the protocol is refined to by default).
pub const LEVELS: usize = crate::external::GRID_LEVELS;

/// One discretisation parameter's cases, refined once and (where the model refines it again)
/// twice.
#[derive(Clone)]
pub struct ParameterStudy {
    pub parameter: String,
    /// The parameter's values over the levels, in words ("5.000 -> 2.500 deg; 2.500 -> 1.250 deg").
    pub words: String,
    pub ratio: f64,
    pub formal_order: f64,
    pub levels: Vec<Case>,
}

/// A case's grid study: each discretisation parameter its model names, refined alone.
#[derive(Clone)]
pub struct GridStudy {
    pub parameters: Vec<ParameterStudy>,
}

/// What a parameter's index came from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GciTerm {
    pub parameter: String,
    /// The quantity at the nominal and each refined level.
    pub values: Vec<f64>,
    pub ratio: f64,
    /// The order observed over three levels converging monotonically (none otherwise).
    pub observed_order: Option<f64>,
    /// The order the index uses.
    pub order: f64,
    pub safety_factor: f64,
    pub gci: f64,
}

/// A quantity's numerical uncertainty: the parameters' indices, root-sum-squared.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Numerical {
    pub u_num: f64,
    pub terms: Vec<GciTerm>,
}

/// The grid convergence index of the nominal value `values[0]` from its refined levels
/// (`values[1]`, and `values[2]` where there is a third), see the module's method.
pub fn gci(parameter: &str, values: &[f64], ratio: f64, formal_order: f64) -> GciTerm {
    let factor = |p: f64| ratio.powf(p) / (ratio.powf(p) - 1.0);
    let e21 = values[1] - values[0];
    let observed = values.get(2).and_then(|s3| {
        let e32 = s3 - values[1];
        let q = e32 / e21;
        (q > 0.0 && q < 1.0).then(|| (1.0 / q).ln() / ratio.ln())
    });
    let trusted = observed
        .filter(|p| *p >= formal_order / ORDER_AGREEMENT && *p <= formal_order * ORDER_AGREEMENT);
    let (order, safety_factor, difference) = match trusted {
        Some(p) => (p.min(formal_order), FS_OBSERVED, e21.abs()),
        None => {
            let e32 = values.get(2).map_or(0.0, |s3| (s3 - values[1]).abs());
            (formal_order, FS_TWO_GRIDS, e21.abs().max(e32))
        }
    };
    GciTerm {
        parameter: parameter.to_string(),
        values: values.to_vec(),
        ratio,
        observed_order: observed,
        order,
        safety_factor,
        gci: if difference == 0.0 {
            0.0
        } else {
            safety_factor * difference * factor(order)
        },
    }
}

/// The case's grid study (`None` for a subject without one): each refinement its model names,
/// applied alone, at up to [`LEVELS`] levels; a case's uncorrected twin is refined alike.
pub fn grid_study(case: &Case) -> Option<GridStudy> {
    let first = refinements(&case.subject)?;
    let same = |subject: &Subject, parameter: &str| {
        refinements(subject).and_then(|v| v.into_iter().find(|x| x.parameter == parameter))
    };
    let mut parameters = Vec::new();
    for r in first {
        let (mut levels, mut words): (Vec<Case>, Vec<String>) = (Vec::new(), Vec::new());
        let mut step = Some(r.clone());
        // Each level refines the one before; the model is asked for the next only while one
        // is wanted.
        while let Some(s) = step.take() {
            let mut c = levels.last().unwrap_or(case).clone();
            c.subject = refined_subject(&c.subject, &s);
            if let Some(u) = &mut c.uncorrected
                && let Some(twin) = same(&u.subject, &r.parameter)
            {
                u.subject = refined_subject(&u.subject, &twin);
            }
            words.push(s.words);
            if levels.len() + 1 < LEVELS {
                step = same(&c.subject, &r.parameter);
            }
            levels.push(c);
        }
        parameters.push(ParameterStudy {
            parameter: r.parameter.clone(),
            words: words.join("; "),
            ratio: r.ratio,
            formal_order: r.formal_order,
            levels,
        });
    }
    (!parameters.is_empty()).then_some(GridStudy { parameters })
}

impl GridStudy {
    /// Every refined case, parameter by parameter, level by level.
    pub fn cases(&self) -> Vec<&Case> {
        self.parameters.iter().flat_map(|p| &p.levels).collect()
    }

    /// The study in words: "main rotor azimuth step 5.000 -> 2.500 deg; 2.500 -> 1.250 deg
    /// (r 2, order 4) | ...".
    pub fn describe(&self) -> String {
        self.parameters
            .iter()
            .map(|p| {
                format!(
                    "{} {} (r {}, formal order {}), alone",
                    p.parameter, p.words, p.ratio, p.formal_order
                )
            })
            .collect::<Vec<_>>()
            .join(" | ")
    }

    /// A quantity's numerical uncertainty from the refined cases' results (`results`, in
    /// [`Self::cases`]' order): `value` finds the quantity in a check's result (its check's,
    /// index `j`); `Err` with why where a level gives none.
    pub fn numerical(
        &self,
        results: &[Vec<CheckResult>],
        j: usize,
        nominal: f64,
        value: &dyn Fn(&CheckResult) -> Result<f64, String>,
    ) -> Result<Numerical, String> {
        let mut at = results.iter();
        let mut terms = Vec::new();
        for p in &self.parameters {
            let mut values = vec![nominal];
            for _ in &p.levels {
                let r = at
                    .next()
                    .and_then(|r| r.get(j))
                    .ok_or_else(|| format!("{} refined: the run has no such check", p.parameter))?;
                values.push(value(r).map_err(|e| format!("{} refined: {e}", p.parameter))?);
            }
            terms.push(gci(&p.parameter, &values, p.ratio, p.formal_order));
        }
        Ok(Numerical {
            u_num: terms.iter().map(|t| t.gci * t.gci).sum::<f64>().sqrt(),
            terms,
        })
    }
}

/// A quantity's value in a refined run (its check's result there): found by the quantity's
/// name and tolerance, as the nominal run has it; `Err` with why where the run gave none (an
/// error or a finding there, or no such quantity).
pub fn refined_value(refined: &CheckResult, q: &QuantityResult) -> Result<f64, String> {
    if let Some(e) = &refined.error {
        return Err(e.clone());
    }
    if let Some(f) = &refined.finding {
        return Err(f.describe());
    }
    refined
        .quantities
        .iter()
        .find(|x| x.quantity == q.quantity && x.tolerance == q.tolerance)
        .map(|x| x.value)
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("the refined run has no finite `{}`", q.quantity))
}

/// The refinements of a subject's model (`None` for a subject without a model, or a model
/// without a grid study).
fn refinements(subject: &Subject) -> Option<Vec<Refinement>> {
    let e = super::propagate::as_model(subject)?;
    let r = e.model.refinements();
    (!r.is_empty()).then_some(r)
}

/// The subject with its model replaced by a refinement's.
fn refined_subject(subject: &Subject, r: &Refinement) -> Subject {
    let mut e =
        super::propagate::as_model(subject).expect("a subject with refinements has a model");
    e.model = r.model.clone();
    e.written = format!("{}#{}", e.written, r.parameter.replace(' ', "-"));
    Subject::External(Box::new(e))
}
