//! Propagation through a case: its aircraft's estimated inputs sampled over their distributions
//! (a Saltelli design of Sobol' points), every check evaluated at every sample, each quantity's
//! statistics and Sobol' indices; a grid study of the discretisation for the numerical
//! uncertainty; and, for each validation check, the comparison of ASME V&V 20 ([`super::vv20`]).
//!
//! The inputs are the parameters the aircraft file gives a plausible range (`ranges:`), except
//! corrections (`corrections.*`): a correction is a choice of model form, fitted or not, not an
//! input whose value is uncertain. Each sample is a copy of the case whose aircraft has the
//! sampled values (checked as the file's loader checks them) and its own path, so no cached
//! linearisation of another sample is reused.

use super::design::Design;
use super::distribution::{Input, InputDistribution};
use super::numerics::Numerical;
use super::sobol;
use super::vv20::{self, Comparison, Vv20Verdict};
use crate::checks::CheckClass;
use crate::checks::subject::Subject;
use crate::external::Values;
use crate::suite::case::Case;
use crate::suite::outcome::CheckResult;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal};

/// What to sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PropagationSettings {
    /// Base points `n` of the design: `n (d + 2)` evaluations for `d` inputs.
    pub samples: usize,
    pub seed: u32,
    /// Only the validation checks (`validate --uncertainty`: the comparison of V&V 20 is of the
    /// model against measured data; a case with none is not sampled).
    pub validation_only: bool,
    /// How `u_input` is obtained.
    pub method: Propagation,
}

/// How a case's inputs are propagated.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Propagation {
    /// First order for a case with `autorotation` checks (each evaluation a table of
    /// autorotation searches, too slow to sample), whatever model answers them; sampled for
    /// any other case.
    #[default]
    Auto,
    /// The Saltelli design: `samples (d + 2)` evaluations.
    Sampled,
    /// An additive surrogate from each input at its 5 % and 95 % quantiles, checked at four
    /// draws: `2 d + 4` evaluations.
    FirstOrder,
}

/// The share of samples in which a passing check must fail to be called fragile: its verdict
/// flips inside the central 95 % of the input distribution.
pub const FRAGILE_FAIL_FRACTION: f64 = 0.05;
/// The total Sobol' index above which an input is named among those that flip a fragile check.
pub const FLIPPING_TOTAL_INDEX: f64 = 0.1;
/// The largest share of a check's samples the model may fail to evaluate before its quantities
/// get no verdict: beyond it the samples left are not a draw of the inputs' distribution (the
/// failures cluster where the inputs take the aircraft out of its envelope), so their mean and
/// spread are biased (issue 51: `phugoid-30mph` lost 239 of 1152, its mean 9.61 s against a
/// nominal 10.66). 5 %, the share a 95 % interval leaves out.
pub const MAX_FAILED_SHARE: f64 = 0.05;

/// The largest standard error a Sobol' index may have and still be read as a number: beyond it
/// the index is shown as "not resolved at N samples" (issue 51: at 64 base points of 16
/// inputs, standard errors of 0.46 to 1.18 were printed as if the indices meant something; an
/// index spans [0, 1], so an error above a tenth of that range cannot rank the inputs).
pub const UNRESOLVED_INDEX_SE: f64 = 0.1;

/// One input's share of a quantity's variance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Contributor {
    pub input: String,
    /// Sobol' total index.
    pub total: f64,
    /// Sobol' first-order index.
    pub first: f64,
    /// The standard error of `total` ([`sobol`]'s delta method). `None` (null in JSON) from the
    /// first-order propagation: its shares `c_i^2 / u_input^2` are not sampled and have no
    /// sampling error to state (their error is the linearisation's).
    pub total_se: Option<f64>,
    /// The standard error of `first`, as `total_se`.
    pub first_se: Option<f64>,
}

impl Contributor {
    /// Its total index in words: `0.42 +- 0.03` where sampled, `0.42` where not (a first-order
    /// share), and "not resolved at N samples" where its standard error exceeds
    /// [`UNRESOLVED_INDEX_SE`].
    pub fn total_in_words(&self, samples: usize) -> String {
        match self.total_se {
            Some(se) if se > UNRESOLVED_INDEX_SE || !se.is_finite() => format!(
                "{:.2} +- {se:.2}: not resolved at {samples} samples",
                self.total
            ),
            Some(se) => format!("{:.2} +- {se:.2}", self.total),
            None => format!("{:.2}", self.total),
        }
    }
}

/// One quantity of one check, propagated and (for a validation check with a reference value)
/// compared.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuantityUncertainty {
    pub case: String,
    pub check: String,
    pub class: CheckClass,
    pub quantity: String,
    /// The model's value with every input at its nominal value (`S`).
    pub nominal: f64,
    /// The reference value `D`: the expected value, or the middle of an interval.
    pub reference: Option<f64>,
    /// Over the samples of the inputs.
    pub mean: f64,
    pub p2_5: f64,
    pub p97_5: f64,
    /// `E = S - D`.
    pub estimate_error: Option<f64>,
    /// Over the inputs, the calibrations' stated predictive error included (`u_calibration`).
    pub u_input: f64,
    /// The part of `u_input` that the corrections files applied state as their predictive
    /// error here (their cross-validated model-discrepancy term times the nominal value;
    /// `calibration_terms`); zero without one.
    pub u_calibration: f64,
    /// The grid convergence indices of the discretisation parameters, each refined alone,
    /// root-sum-squared ([`super::numerics`]): 0 where the subject has no grid study; NaN
    /// where a refined run gave no value, `u_num_missing` says why.
    pub u_num: f64,
    /// Each parameter's index and what it came from (empty without a grid study).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub u_num_terms: Vec<super::numerics::GciTerm>,
    /// Why a refined run gave no value for the quantity, where one gave none: the quantity
    /// then has no verdict.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub u_num_missing: Option<String>,
    pub u_data: Option<f64>,
    /// The degrees of freedom of `u_data`, where its tolerance states them (a standard
    /// deviation from few repeats); none where it is taken as known.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub u_data_dof: Option<f64>,
    /// Where `u_data` comes from, or why there is none.
    pub u_data_source: String,
    pub u_val: Option<f64>,
    /// The corrections files applied whose fit was fitted to its check: its verdict is
    /// reported apart and never counted as validation evidence ([`VerdictCounts`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub calibrated_on: Option<String>,
    /// The inputs whose plausible ranges were taken from this check's own data (their ranges'
    /// `taken_from`), in words: the verdict is circular, reported apart and never counted as
    /// validation evidence ([`VerdictCounts`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub circular: Option<String>,
    /// The verdict of V&V 20 (validation checks with a reference value only).
    pub verdict: Option<Vv20Verdict>,
    /// Why the verdict is what it is (or why there is none), with its numbers.
    pub reason: String,
    /// Whether the check passes with the nominal inputs.
    pub passes_nominal: bool,
    /// The share of evaluated samples in which the check passes.
    pub pass_fraction: f64,
    /// A nominal pass that fails in at least [`FRAGILE_FAIL_FRACTION`] of the samples.
    pub fragile: bool,
    /// For a fragile check: the inputs whose total index reaches [`FLIPPING_TOTAL_INDEX`].
    pub flipped_by: Vec<String>,
    /// Inputs by their total index, largest first.
    pub contributors: Vec<Contributor>,
    /// Samples the model could not evaluate for this quantity (left out of every statistic).
    pub failed_samples: usize,
    /// Samples drawn for it, evaluated or not.
    pub samples: usize,
    /// Why its check's samples failed, most frequent first: `<count> x <cause>` (the cause is
    /// the first such error in words, its numbers left in; causes that differ only in their
    /// numbers are counted together).
    pub failure_causes: Vec<String>,
    /// The quantity's values at the sampled points of `A` and `B` (independent draws of the
    /// inputs; NaN where the model gave none), in the design's order; empty from a first-order
    /// propagation. Not written out: the tests judge a propagation's intervals on them.
    #[serde(skip)]
    pub draws: Vec<f64>,
}

impl QuantityUncertainty {
    /// Its check's pass fraction, and with it whether a nominal pass is fragile and which
    /// inputs flip it.
    pub(super) fn set_pass_fraction(&mut self, pass_fraction: f64) {
        self.pass_fraction = pass_fraction;
        self.fragile = self.passes_nominal && 1.0 - pass_fraction >= FRAGILE_FAIL_FRACTION;
        if self.fragile {
            self.flipped_by = self
                .contributors
                .iter()
                .filter(|c| c.total >= FLIPPING_TOTAL_INDEX)
                .map(|c| c.input.clone())
                .collect();
        }
    }
}

/// A case's propagation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseUncertainty {
    pub case: String,
    /// How `u_input` was obtained, in words.
    pub method: String,
    pub inputs: Vec<Input>,
    /// Model evaluations of the case (every check at a point counts once).
    pub evaluations: usize,
    /// Points at which some check could not be evaluated, and the first such error.
    pub failed_points: usize,
    pub first_error: Option<String>,
    /// The grid study the numerical uncertainty comes from, in words.
    pub refinement: String,
    pub results: Vec<QuantityUncertainty>,
}

impl CaseUncertainty {
    /// The largest standard error of any total Sobol' index of any quantity whose inputs move
    /// it (`u_input > 0`), and of which quantity and input: what `--target-se` grows the design
    /// until it is small enough, and the index shown as resolved or not
    /// ([`Contributor::total_in_words`]). Not the first-order indices': their estimator is not
    /// centred, so its error grows with a quantity's mean against its spread (`M_q`'s -1.2
    /// against a spread of 0.35 leaves 0.08 at 4096 base points where the total index is
    /// resolved at a few hundred; docs/uncertainty.md). A non-finite one counts as unresolved
    /// (infinite). `None` where no index was sampled (a first-order propagation, no inputs).
    pub fn worst_index_se(&self) -> Option<(f64, String)> {
        let mut worst: Option<(f64, String)> = None;
        for r in self.results.iter().filter(|r| r.u_input > 0.0) {
            for c in &r.contributors {
                if let Some(se) = c.total_se {
                    let se = if se.is_finite() { se } else { f64::INFINITY };
                    if worst.as_ref().is_none_or(|(w, _)| se > *w) {
                        worst = Some((se, format!("{}::{} by {}", r.check, r.quantity, c.input)));
                    }
                }
            }
        }
        worst
    }
}

/// The case's uncertain inputs: its model's declared parameters with a plausible range other
/// than corrections, by name (cierva's aircraft's and rotor's: their files' ranged physical
/// parameters), an `Err` where it cannot say (its `describe` failed). Empty for a subject
/// that is not a model (a table, a linear model given).
pub fn inputs(case: &Case) -> Result<Vec<Input>, String> {
    let Some(model) = crate::checks::model_of(&case.subject) else {
        return Ok(Vec::new());
    };
    let parameters = model.parameters()?;
    let methods: std::collections::BTreeMap<String, String> = (parameters.iter())
        .filter_map(|p| Some((p.name.clone(), p.range.as_ref()?.shares.clone()?)))
        .collect();
    let shares = |name: &str| methods.get(name).cloned();
    let mut declared: Vec<Input> = parameters
        .into_iter()
        .filter(|p| !p.correction)
        .filter_map(|p| {
            let r = p.range?;
            Some(Input {
                distribution: InputDistribution::of_range(p.nominal, &r),
                name: p.name,
                nominal: p.nominal,
                source: r.source,
                moves: Vec::new(),
                taken_from: r.taken_from,
            })
        })
        .collect();
    declared.sort_by(|a, b| a.name.cmp(&b.name));
    // A range taken from one of this case's checks names a check the case has.
    for i in &declared {
        for t in &i.taken_from {
            if let Some((c, check)) = t.split_once('/')
                && c == case.id
                && !case.checks.iter().any(|k| k.id == check)
            {
                return Err(format!(
                    "`{}`'s range is `taken_from` `{t}`, but case `{c}` has no check `{check}` (its checks: {})",
                    i.name,
                    (case.checks.iter())
                        .map(|k| k.id.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
        }
    }
    // A calibration's fitted parameters are no longer priors: drawn from its fit's joint
    // distribution, not from their ranges (nor with a method's shared error).
    let posteriors: Vec<_> = (case.calibrations.iter())
        .filter_map(|c| Some((c.id.as_str(), c.posterior.as_ref()?)))
        .collect();
    declared.retain(|i| {
        !(posteriors.iter()).any(|(_, p)| p.parameters.iter().any(|q| q.name == i.name))
    });
    // Inputs estimated by one method share its error: drawn once.
    let mut declared = super::distribution::shared_by_method(declared, &shares);
    for (id, p) in posteriors {
        declared.extend(Input::factors_of(id, p));
    }
    Ok(declared)
}

/// The case with its inputs at `values` (in the order of `inputs`), checked, under a path of
/// its own (`tag`): its model asked with the values as parameters
/// ([`crate::external::WithValues`]), its answers started from its answers at `start` (a
/// nearby point's values) where it can ([`crate::external::FlightModel::starting_from`]).
pub(super) fn with_values(
    case: &Case,
    inputs: &[Input],
    values: &[f64],
    (tag, start): (&str, Option<&Values>),
) -> Result<Case, String> {
    let mut c = case.clone();
    set_values(&mut c.subject, inputs, values, (tag, start))?;
    // Checks a corrections file is not applied to run on the uncorrected subject: it takes the
    // same inputs.
    if let Some(u) = &mut c.uncorrected {
        let tag = format!("{tag}-uncorrected");
        set_values(&mut u.subject, inputs, values, (&tag, start))?;
    }
    Ok(c)
}

/// `values` (in the order of `inputs`) as a point's parameters. A factor input
/// ([`Input::moves`]) sets each parameter it moves at its quantile, or adds to it linearly
/// with the other factors that move it, each such parameter reflected into its bounds once
/// every factor is added.
pub(super) fn values_of(inputs: &[Input], values: &[f64]) -> Values {
    use super::distribution::{Move, reflected};
    let mut out = Values::new();
    // Linearly moved parameters: (name, value so far, bounds).
    let mut linear: Vec<(&str, f64, f64, f64)> = Vec::new();
    for (i, v) in inputs.iter().zip(values) {
        if i.moves.is_empty() {
            out.insert(i.name.clone(), *v);
        }
        for m in &i.moves {
            match m.by {
                Move::AtQuantile(d) => {
                    out.insert(m.parameter.clone(), d.quantile(*v));
                }
                Move::Linear {
                    value,
                    per_unit,
                    lower,
                    upper,
                } => match linear.iter_mut().find(|(n, ..)| *n == m.parameter) {
                    Some((_, x, ..)) => *x += per_unit * v,
                    None => linear.push((&m.parameter, value + per_unit * v, lower, upper)),
                },
            }
        }
    }
    for (name, x, lower, upper) in linear {
        out.insert(name.to_string(), reflected(x, lower, upper));
    }
    out
}

/// `values` (in the order of `inputs`) set on a subject, checked, under a path of its own
/// (`tag`); see [`with_values`].
fn set_values(
    subject: &mut Subject,
    inputs: &[Input],
    values: &[f64],
    (tag, start): (&str, Option<&Values>),
) -> Result<(), String> {
    let mut e = as_model(subject).ok_or("the subject is not a model")?;
    let declared = e.model.parameters()?;
    let values = values_of(inputs, values);
    crate::external::check_values(&e.model.describe(), &declared, &values)?;
    let model = start
        .and_then(|v| e.model.starting_from(v))
        .unwrap_or_else(|| e.model.clone());
    e.model = std::sync::Arc::new(crate::external::WithValues { model, values });
    e.written = format!("{}#{tag}", e.written);
    *subject = Subject::External(Box::new(e));
    Ok(())
}

/// A subject that is a model as a model behind the model interface, owned: another simulation
/// as it is, cierva's aircraft as [`crate::external::CiervaAircraft`] and its rotor in a
/// tunnel as [`crate::external::rotor::CiervaRotor`]. What a study asks with its values, the
/// same way for every model.
pub(super) fn as_model(subject: &Subject) -> Option<crate::external::External> {
    let (model, loading, written, path): (
        std::sync::Arc<dyn crate::external::FlightModel>,
        _,
        _,
        _,
    ) = match subject {
        Subject::External(e) => return Some((**e).clone()),
        Subject::Aircraft { file, loading } => (
            std::sync::Arc::new(crate::external::CiervaAircraft::owned((**file).clone())),
            *loading,
            "aircraft",
            &file.path,
        ),
        Subject::Rotor { file, solver, .. } => (
            std::sync::Arc::new(crate::external::rotor::CiervaRotor::owned(
                (**file).clone(),
                *solver,
            )),
            crate::inputs::condition::Loading {
                mass_kg: None,
                density_altitude_ft: 0.0,
            },
            "rotor",
            &file.path,
        ),
        _ => return None,
    };
    Some(crate::external::External {
        model,
        loading,
        written: format!("{written}: {}", path.display()),
        folder: path.parent().map(Into::into).unwrap_or_default(),
    })
}

/// Forgets what the point's model remembers of its answers (its values'), once its checks
/// have run (the uncorrected subject's too).
pub(super) fn forget(case: &Case, values: &Values) {
    let uncorrected = case.uncorrected.as_ref().map(|u| &u.subject);
    for subject in std::iter::once(&case.subject).chain(uncorrected) {
        if let Some(e) = as_model(subject) {
            e.model.forget(values);
        }
    }
}

/// What a case without a refinement says about its numerical uncertainty.
pub(super) const NO_GRID_STUDY: &str =
    "none: no grid study for this subject (its model names no discretisation parameter to refine)";

/// One evaluation of every check: each quantity's value (NaN where it could not be computed)
/// and whether the check passed, by check then quantity, in the nominal results' order.
pub(super) struct Point {
    pub(super) values: Vec<Vec<f64>>,
    pub(super) passed: Vec<Option<bool>>,
    pub(super) error: Option<String>,
    /// Why each check gave no values here (an error or a finding), by check.
    pub(super) check_errors: Vec<Option<String>>,
}

/// What an uncertainty study reads of one check's results at a point: whether it passed, why it
/// gave no values (an error or a finding), and each quantity's value by name and tolerance. A
/// plan's point results hold only this, about a ninth of the whole [`CheckResult`]'s text (its
/// words, bounds and margins), so that a study of thousands of points writes and reads little.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckValues {
    pub check: String,
    pub passed: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The finding's reason, where the check drew one (no equilibrium, inconclusive).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub finding: Option<String>,
    pub quantities: Vec<QuantityValue>,
}

/// A quantity's value, by its name and tolerance (a check's list may vary between points).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuantityValue {
    pub quantity: String,
    pub tolerance: String,
    pub value: f64,
}

impl CheckValues {
    /// What the study reads of `r`.
    pub fn of(r: &CheckResult) -> Self {
        Self {
            check: r.check.clone(),
            passed: r.passed,
            error: r.error.clone(),
            finding: r.finding.as_ref().map(|f| f.reason().to_string()),
            quantities: (r.quantities.iter())
                .map(|q| QuantityValue {
                    quantity: q.quantity.clone(),
                    tolerance: q.tolerance.clone(),
                    value: q.value,
                })
                .collect(),
        }
    }
}

pub(super) fn point_of(nominal: &[CheckResult], results: &[CheckValues]) -> Point {
    let mut error = None;
    let mut values = Vec::new();
    let mut passed = Vec::new();
    let mut check_errors = Vec::new();
    for (j, n) in nominal.iter().enumerate() {
        // A point whose case could not be made (an input the aircraft refuses) has no results.
        let Some(r) = results.get(j) else {
            passed.push(None);
            values.push(vec![f64::NAN; n.quantities.len()]);
            check_errors.push(None);
            continue;
        };
        let why = r.error.as_deref().or(r.finding.as_deref());
        if let Some(e) = why {
            error.get_or_insert_with(|| format!("{}: {e}", r.check));
        }
        check_errors.push(why.map(String::from));
        let evaluated = r.error.is_none() && r.finding.is_none();
        passed.push((r.error.is_none()).then_some(r.passed));
        // The same quantities in the same order as the nominal run's, or (a check whose list
        // varies) found by name and tolerance.
        let same = r.quantities.len() == n.quantities.len()
            && r.quantities
                .iter()
                .zip(&n.quantities)
                .all(|(x, q)| x.quantity == q.quantity && x.tolerance == q.tolerance);
        values.push(
            n.quantities
                .iter()
                .enumerate()
                .map(|(k, q)| {
                    let found = if same {
                        r.quantities.get(k)
                    } else {
                        r.quantities
                            .iter()
                            .find(|x| x.quantity == q.quantity && x.tolerance == q.tolerance)
                    };
                    found.filter(|_| evaluated).map_or(f64::NAN, |x| x.value)
                })
                .collect(),
        );
    }
    Point {
        values,
        passed,
        error,
        check_errors,
    }
}

pub(super) use super::numerics::refined_value;

/// The longest a failure's cause is printed: the autorotation search's longest reasons (about
/// 400 characters, the verdict at their end) whole.
pub const CAUSE_CHARS: usize = 480;

/// Why check `j` gave no values at the points where it gave none, most frequent first, each as
/// `<count> x <cause>`: causes that differ only in their numbers are counted together, and each
/// is shown by its first occurrence (shortened to [`CAUSE_CHARS`]). A point whose case could
/// not be made at all is counted by the point's own error.
pub(super) fn failure_causes<'a>(
    points: impl IntoIterator<Item = &'a Point>,
    j: usize,
) -> Vec<String> {
    let mut causes: Vec<(String, String, usize)> = Vec::new();
    for p in points {
        let failed = p
            .values
            .get(j)
            .is_some_and(|v| v.iter().any(|x| !x.is_finite()));
        if !failed {
            continue;
        }
        let Some(why) = p
            .check_errors
            .get(j)
            .cloned()
            .flatten()
            .or_else(|| p.error.clone())
        else {
            continue;
        };
        let key: String = why
            .chars()
            .map(|c| if c.is_ascii_digit() { '#' } else { c })
            .collect();
        match causes.iter_mut().find(|(k, _, _)| *k == key) {
            Some(c) => c.2 += 1,
            None => causes.push((key, why, 1)),
        }
    }
    causes.sort_by_key(|c| std::cmp::Reverse(c.2));
    causes
        .into_iter()
        .map(|(_, why, n)| format!("{n} x {}", crate::inputs::yaml::shorten(&why, CAUSE_CHARS)))
        .collect()
}

/// The `p`-th percentile (0-100) of finite values, by linear interpolation between order
/// statistics (NaN for none).
pub fn percentile(values: &[f64], p: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let h = (v.len() - 1) as f64 * p / 100.0;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    v[lo] + (h - lo as f64) * (v[hi] - v[lo])
}

/// Mean and sample standard deviation of the finite values.
pub fn mean_std(values: &[f64]) -> (f64, f64) {
    let v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}

/// The sampled propagation's points: Saltelli's design over the `inputs` and its points,
/// `A` and `B` first, then each `A_B^(i)` point, which differs from its row of `A` in one input
/// and starts from that row's answers where its model can
/// ([`crate::external::FlightModel::starting_from`]; cierva's aircraft's trims): a nearer
/// start, and fewer of the model's evaluations to the same tolerance.
pub(super) fn sampled_jobs(
    inputs: &[Input],
    settings: PropagationSettings,
) -> Result<(Design, Vec<super::jobs::PointJob>), String> {
    let design = Design::sobol(settings.samples, inputs.len(), settings.seed)?;
    let units = design.points();
    let n = design.n;
    let jobs = (units.iter().enumerate())
        .map(|(k, u)| {
            let values: Vec<f64> = (inputs.iter().zip(u))
                .map(|(i, &x)| i.distribution.quantile(x))
                .collect();
            super::jobs::PointJob {
                tag: format!("u{}-{}-{:x}", settings.seed, units.len(), hash(&values)),
                values,
                start: (k >= 2 * n).then(|| (k - 2 * n) % n),
            }
        })
        .collect();
    Ok((design, jobs))
}

/// The sampled propagation of a case from its evaluations (see [`super::jobs`]): each check's
/// statistics, indices and verdicts over the design's `points`, the numerical uncertainty from
/// the grid study's results.
pub(super) fn sampled_summary(
    study: &super::jobs::CaseJobs,
    nominal: &[CheckResult],
    design: &Design,
    points: Vec<Point>,
    grid: Option<(&super::numerics::GridStudy, &[Vec<CheckResult>])>,
) -> CaseUncertainty {
    let (case, inputs, settings) = (&study.case, &study.inputs, study.settings);
    let refinement = grid.map_or(NO_GRID_STUDY.to_string(), |(g, _)| g.describe());
    let failed_points = points.iter().filter(|p| p.error.is_some()).count();
    let first_error = points.iter().find_map(|p| p.error.clone());
    let mut results = Vec::new();
    for (j, (check, n)) in case.checks.iter().zip(nominal).enumerate() {
        results.extend(check_results(
            case,
            (j, check, n),
            &points,
            design,
            grid,
            inputs,
        ));
    }
    let method = format!(
        "sampled: {} Sobol' points (seed {}) of {} inputs in a Saltelli design, {} evaluations; statistics over the {} points of A and B",
        design.n,
        settings.seed,
        design.d,
        points.len(),
        2 * design.n
    );
    CaseUncertainty {
        case: case.id.clone(),
        method,
        inputs: inputs.clone(),
        evaluations: points.len() + 1 + grid.map_or(0, |(_, r)| r.len()),
        failed_points,
        first_error,
        refinement,
        results,
    }
}

/// One check's quantities over the samples: statistics, indices, comparison, pass fraction
/// and fragility. A check with no number (a BCAR verdict) is propagated as whether it passes:
/// its pass fraction, and the Sobol' indices of the pass (1) or fail (0) say which inputs flip
/// it. `grid` is the case's grid study and its refined runs' results.
fn check_results(
    case: &Case,
    (j, check, n): (usize, &crate::checks::Check, &CheckResult),
    points: &[Point],
    design: &Design,
    grid: Option<(&super::numerics::GridStudy, &[Vec<CheckResult>])>,
    inputs: &[Input],
) -> Vec<QuantityUncertainty> {
    let verdict_only = n.quantities.is_empty();
    let quantities = if verdict_only {
        vec![passes(n)]
    } else {
        n.quantities.clone()
    };
    let as_number = |b: bool| f64::from(u8::from(b));
    let evaluated: Vec<bool> = points[..2 * design.n]
        .iter()
        .filter_map(|p| p.passed[j])
        .collect();
    let causes = failure_causes(points, j);
    let mut out = Vec::new();
    for (k, q) in quantities.iter().enumerate() {
        let all: Vec<f64> = points
            .iter()
            .map(|p| match verdict_only {
                true => p.passed[j].map_or(f64::NAN, as_number),
                false => p.values[j][k],
            })
            .collect();
        let nominal = match verdict_only {
            true => as_number(n.passed),
            false => q.value,
        };
        let numerics = grid.map(|(g, results)| {
            g.numerical(results, j, nominal, &|r| match verdict_only {
                true => Ok(as_number(r.passed)),
                false => refined_value(r, q),
            })
        });
        let mut r = summarise(
            case,
            check,
            n,
            q,
            &all,
            numerics,
            Some(design),
            (inputs, &causes),
        );
        if verdict_only {
            r.reason = "no verdict: a check of a verdict (BCAR, a mode's class) has no number to compare; the quantity `passes` is 1 where it passes, and its indices say which inputs flip it".into();
        }
        mark_circular(&mut r, inputs);
        out.push(r);
    }
    let pass_fraction = if evaluated.is_empty() {
        as_number(n.passed)
    } else if verdict_only || out.iter().all(|r| r.u_calibration == 0.0) {
        evaluated.iter().filter(|b| **b).count() as f64 / evaluated.len() as f64
    } else {
        let draws: Vec<&[f64]> = out.iter().map(|r| r.draws.as_slice()).collect();
        let spread: Vec<f64> = out.iter().map(|r| r.u_calibration).collect();
        pass_fraction(&quantities, &spread, &draws)
    };
    for r in &mut out {
        r.set_pass_fraction(pass_fraction);
    }
    out
}

/// The share of draws in which a check passes: at each draw where every quantity has a value,
/// the product over quantities of the chance that the value, plus a normal spread of
/// `spread[k]` where it has one (a calibration's predictive error, a surrogate's residual:
/// independent of the inputs and of each other), stays inside its bounds (without one: inside
/// or not), averaged. `draws[k]` are quantity `k`'s values.
pub(super) fn pass_fraction(
    quantities: &[crate::suite::outcome::QuantityResult],
    spread: &[f64],
    draws: &[&[f64]],
) -> f64 {
    let unit = Normal::standard();
    let n = draws.first().map_or(0, |d| d.len());
    let chances: Vec<f64> = (0..n)
        .filter(|&i| draws.iter().all(|d| d[i].is_finite()))
        .map(|i| {
            quantities
                .iter()
                .zip(spread)
                .zip(draws)
                .map(|((q, &u), d)| {
                    let y = d[i];
                    match u > 0.0 {
                        true => unit.cdf((q.upper - y) / u) - unit.cdf((q.lower - y) / u),
                        false => f64::from(u8::from((q.lower..=q.upper).contains(&y))),
                    }
                })
                .product::<f64>()
        })
        .collect();
    // (NaN where no draw has every value.)
    chances.iter().sum::<f64>() / chances.len() as f64
}

/// A case whose subject has no uncertain inputs: each quantity with its reference and the
/// data's uncertainty, but no verdict (an unsampled estimate is not a known input).
pub(super) fn without_inputs(case: &Case, nominal: &[CheckResult]) -> CaseUncertainty {
    let why = match &case.subject {
        Subject::Aircraft { file, .. } => format!(
            "no verdict: {} gives none of its estimated parameters a plausible range (`ranges:`), so the inputs' uncertainty is unknown",
            file.id
        ),
        Subject::Rotor { file, .. } => format!(
            "no verdict: {} gives none of its estimated parameters a plausible range (`ranges:`), so the inputs' uncertainty is unknown",
            file.id
        ),
        Subject::External(e) => format!(
            "no verdict: {} declares no parameter with a plausible range (protocol \
             `cierva-external/2`'s `describe`), so the inputs' uncertainty is unknown",
            e.model.describe()
        ),
        s => format!(
            "no verdict: the estimated inputs of {} carry no distributions (only aircraft and rotor files' ranges are propagated), so the inputs' uncertainty is unknown",
            s.describe()
        ),
    };
    let mut results = Vec::new();
    for (check, n) in case.checks.iter().zip(nominal) {
        let quantities = if n.quantities.is_empty() {
            vec![passes(n)]
        } else {
            n.quantities.clone()
        };
        for q in &quantities {
            let mut r = summarise(case, check, n, q, &[], None, None, (&[], &[]));
            r.verdict = None;
            r.u_val = None;
            r.reason = why.clone();
            r.pass_fraction = if n.passed { 1.0 } else { 0.0 };
            results.push(r);
        }
    }
    CaseUncertainty {
        case: case.id.clone(),
        method: "none: the case's subject has no uncertain inputs".into(),
        inputs: Vec::new(),
        evaluations: 0,
        failed_points: 0,
        first_error: None,
        refinement: "none".into(),
        results,
    }
}

/// A verdict-only check as a quantity: `passes`, 1 when it passes.
fn passes(n: &CheckResult) -> crate::suite::outcome::QuantityResult {
    crate::suite::outcome::QuantityResult {
        quantity: "passes".into(),
        value: f64::from(u8::from(n.passed)),
        expected: None,
        tolerance: String::new(),
        allowed: "1 (passes)".into(),
        reason: "the check's verdict".into(),
        lower: f64::NAN,
        upper: f64::NAN,
        margin: f64::NAN,
        pass: n.passed,
    }
}

impl Point {
    pub(super) fn with_error(mut self, e: String) -> Self {
        self.error = Some(e);
        self
    }
}

/// A stable hash of sampled values (the acceptance log's FNV-1a over their bits): a sample's
/// path, so cached linearisations never mix samples.
pub(super) fn hash(values: &[f64]) -> u64 {
    let bytes: Vec<u8> = values
        .iter()
        .flat_map(|v| v.to_bits().to_le_bytes())
        .collect();
    crate::suite::review::fnv1a64(&bytes)
}

/// The data's standard uncertainty from a check's tolerance, and where it comes from.
fn data_uncertainty(
    check: &crate::checks::Check,
    q: &crate::suite::outcome::QuantityResult,
) -> (Option<f64>, Option<f64>, String) {
    let tolerance = check
        .expectations
        .iter()
        .find(|e| e.tolerance.name == q.tolerance)
        .map(|e| &e.tolerance);
    if let Some(t) = tolerance
        && let Some(sd) = t.standard_deviation
    {
        let (u, what) = match t.kind {
            crate::checks::tolerance::ToleranceKind::Relative(_) => (
                sd * q.expected.unwrap_or(f64::NAN).abs(),
                format!("{:.2} % of the value", 100.0 * sd),
            ),
            _ => (sd, format!("{sd:.4e}")),
        };
        return (
            Some(u),
            t.degrees_of_freedom,
            format!(
                "the measurement's standard deviation from repeat runs ({what}{}; tolerance `{}`)",
                t.degrees_of_freedom
                    .map_or(String::new(), |n| format!(", {n} degrees of freedom")),
                t.name
            ),
        );
    }
    match tolerance.and_then(|t| t.confidence) {
        Some(c) => {
            let z = Normal::standard().inverse_cdf(0.5 + 0.5 * c);
            let half = 0.5 * (q.upper - q.lower);
            (
                Some(half / z),
                None,
                format!(
                    "the half-width of the {} % confidence interval ({half:.4e}) over {z:.3}",
                    100.0 * c
                ),
            )
        }
        None => (
            None,
            None,
            format!(
                "not stated: tolerance `{}` gives no confidence level",
                q.tolerance
            ),
        ),
    }
}

/// One quantity's statistics, indices and comparison (pass fraction and fragility are the
/// caller's).
#[allow(clippy::too_many_arguments)]
fn summarise(
    case: &Case,
    check: &crate::checks::Check,
    n: &CheckResult,
    q: &crate::suite::outcome::QuantityResult,
    all: &[f64],
    numerics: Option<Result<Numerical, String>>,
    design: Option<&Design>,
    (inputs, causes): (&[Input], &[String]),
) -> QuantityUncertainty {
    let (stats, contributors, failed) = match design {
        Some(d) => {
            let ab = &all[..2 * d.n];
            let (f_a, f_b, f_ab) = d.split(all);
            let contributors = sobol::estimate(f_a, f_b, &f_ab)
                .map(|e| {
                    let mut c: Vec<Contributor> = inputs
                        .iter()
                        .zip(e.indices)
                        .map(|(i, x)| Contributor {
                            input: i.name.clone(),
                            total: x.total,
                            first: x.first,
                            total_se: Some(x.total_se),
                            first_se: Some(x.first_se),
                        })
                        .collect();
                    c.sort_by(|a, b| b.total.total_cmp(&a.total));
                    c
                })
                .unwrap_or_default();
            let (mean, std) = mean_std(ab);
            (
                (mean, percentile(ab, 2.5), percentile(ab, 97.5), std),
                contributors,
                all.iter().filter(|x| !x.is_finite()).count(),
            )
        }
        None => ((q.value, q.value, q.value, 0.0), Vec::new(), 0),
    };
    let mut out = unjudged(case, (check, n, q), stats, numerics, contributors, failed);
    if let Some(d) = design {
        out.draws = all[..2 * d.n].to_vec();
        out.samples = all.len();
        out.failure_causes = causes.to_vec();
    }
    judge(&mut out, q, Interval::Sampled);
    out
}

/// Marks a judged quantity whose inputs include ranges taken from its check's own data
/// ([`crate::inputs::ranges::RangeSpec::taken_from`]): `circular` names them, and the reason
/// says the verdict is no evidence.
pub(super) fn mark_circular(out: &mut QuantityUncertainty, inputs: &[Input]) {
    let names: Vec<&str> = inputs
        .iter()
        .filter(|i| i.taken_from_check(&out.case, &out.check))
        .map(|i| i.name.as_str())
        .collect();
    if names.is_empty() {
        return;
    }
    let why = format!(
        "{} {} taken from this check's own data",
        names.join(", "),
        if names.len() == 1 {
            "has a range"
        } else {
            "have ranges"
        }
    );
    out.reason = format!(
        "{} Circular: {why}, so the verdict is reported apart and is no evidence.",
        out.reason
    );
    out.circular = Some(why);
}

/// A quantity of a check: the check, its nominal result, and the quantity's result.
pub(super) type Quantity<'a> = (
    &'a crate::checks::Check,
    &'a CheckResult,
    &'a crate::suite::outcome::QuantityResult,
);

/// A quantity's uncertainties before its verdict: the reference value, `u_num` from the grid
/// study, `u_D` from the tolerance, and the spread `(mean, p2_5, p97_5, u_input)` and contributors
/// over the inputs; the verdict, pass fraction and fragility are the caller's.
pub(super) fn unjudged(
    case: &Case,
    (check, n, q): Quantity,
    (mean, p2_5, p97_5, u_input): (f64, f64, f64, f64),
    numerics: Option<Result<Numerical, String>>,
    contributors: Vec<Contributor>,
    failed_samples: usize,
) -> QuantityUncertainty {
    let reference = q.expected.or_else(|| {
        let mid = 0.5 * (q.lower + q.upper);
        mid.is_finite().then_some(mid)
    });
    let (u_data, u_data_dof, u_data_source) = data_uncertainty(check, q);
    let calibrations = calibration_terms(case, check, q);
    let u_calibration = calibrations.iter().map(|(_, u)| u * u).sum::<f64>().sqrt();
    let (u_input, p2_5, p97_5, contributors) = if u_calibration > 0.0 {
        with_terms((mean, p2_5, p97_5, u_input), contributors, &calibrations)
    } else {
        (u_input, p2_5, p97_5, contributors)
    };
    QuantityUncertainty {
        case: case.id.clone(),
        check: check.id.clone(),
        class: check.class,
        quantity: q.quantity.clone(),
        nominal: q.value,
        reference,
        mean,
        p2_5,
        p97_5,
        estimate_error: reference.map(|d| q.value - d),
        u_input,
        u_calibration,
        u_num: match &numerics {
            None => 0.0,
            Some(Ok(n)) => n.u_num,
            Some(Err(_)) => f64::NAN,
        },
        u_num_terms: match &numerics {
            Some(Ok(n)) => n.terms.clone(),
            _ => Vec::new(),
        },
        u_num_missing: numerics.and_then(Result::err),
        u_data,
        u_data_dof,
        u_data_source,
        u_val: None,
        calibrated_on: n.calibrated_on.clone(),
        circular: None,
        verdict: None,
        reason: String::new(),
        passes_nominal: n.passed,
        pass_fraction: 0.0,
        fragile: false,
        flipped_by: Vec::new(),
        contributors,
        failed_samples,
        samples: 0,
        failure_causes: Vec::new(),
        draws: Vec::new(),
    }
}

/// The predictive errors the calibrations applied to a case state for one of its quantities,
/// each with its label (`calibration <id>, <where>`) and its size in the quantity's units: the
/// relative model-discrepancy term of the check's regime (or pooled, for a check in none)
/// times the nominal value. None for a check a calibration is not applied to, or a quantity it
/// states nothing for.
fn calibration_terms(
    case: &Case,
    check: &crate::checks::Check,
    q: &crate::suite::outcome::QuantityResult,
) -> Vec<(String, f64)> {
    if case
        .uncorrected
        .as_ref()
        .is_some_and(|u| u.checks.contains(&check.id))
    {
        return Vec::new();
    }
    case.calibrations
        .iter()
        .filter_map(|c| {
            let (sd, at) =
                c.predictive_error
                    .as_ref()?
                    .relative_sd(&case.id, &check.id, &q.quantity)?;
            Some((
                format!(
                    "calibration {} ({:.1} % predictive error, {at})",
                    c.id,
                    100.0 * sd
                ),
                sd * q.value.abs(),
            ))
        })
        .filter(|(_, u)| u.is_finite() && *u > 0.0)
        .collect()
}

/// A quantity's spread over its inputs `(mean, p2_5, p97_5, u_input)` and contributors with
/// further terms added (a calibration's predictive error, a surrogate's residual), each
/// independent of the inputs and normal: the variances add, each side of the 95 % interval
/// widens in quadrature by `1.96 u`, and each input's indices scale by its share of the new
/// variance; each term joins the contributors with its share (first order and total alike, as
/// it acts alone).
pub(super) fn with_terms(
    (mean, p2_5, p97_5, u_input): (f64, f64, f64, f64),
    mut contributors: Vec<Contributor>,
    terms: &[(String, f64)],
) -> (f64, f64, f64, Vec<Contributor>) {
    let z = Normal::standard().inverse_cdf(0.975);
    let added: f64 = terms.iter().map(|(_, u)| u * u).sum();
    let variance = u_input * u_input + added;
    let scale = if variance > 0.0 {
        u_input * u_input / variance
    } else {
        0.0
    };
    for c in &mut contributors {
        c.total *= scale;
        c.first *= scale;
        c.total_se = c.total_se.map(|v| v * scale);
        c.first_se = c.first_se.map(|v| v * scale);
    }
    contributors.extend(terms.iter().map(|(label, u)| Contributor {
        input: label.clone(),
        total: u * u / variance,
        first: u * u / variance,
        total_se: None,
        first_se: None,
    }));
    contributors.sort_by(|a, b| b.total.total_cmp(&a.total));
    let widen = |half: f64| (half * half + z * z * added).sqrt();
    (
        variance.sqrt(),
        mean - widen(mean - p2_5),
        mean + widen(p97_5 - mean),
        contributors,
    )
}

/// Whose 95 % interval of the model a verdict's second model-form test may use: a sampled
/// propagation's (its draws are the model's), or none (a first-order surrogate's, whose residual
/// term rests on [`super::first_order`]'s few draws, is not an interval of the model to test
/// against: issue 51, item 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Interval {
    Sampled,
    None,
}

/// The V&V 20 verdict of a validation quantity, or why there is none. `interval` says whether
/// the second model-form test (the data outside the model's own 95 % interval, widened) runs.
pub(super) fn judge(
    out: &mut QuantityUncertainty,
    q: &crate::suite::outcome::QuantityResult,
    interval: Interval,
) {
    let half = 0.5 * (q.upper - q.lower);
    if let Some(why) = &out.u_num_missing {
        out.reason = format!(
            "no verdict: a refined discretisation gave no value, so the numerical uncertainty is not known: {why}"
        );
        return;
    }
    if out.class == CheckClass::Validation
        && out.failed_samples as f64 > MAX_FAILED_SHARE * out.samples as f64
    {
        out.reason = format!(
            "no verdict: the inputs' range leaves the model's envelope at {:.0} % of draws ({} of {}; more than {:.0} %), so the statistics of the rest are not the inputs'{}",
            100.0 * out.failed_samples as f64 / out.samples as f64,
            out.failed_samples,
            out.samples,
            100.0 * MAX_FAILED_SHARE,
            match out.failure_causes.first() {
                Some(c) => format!(": {c}"),
                None => String::new(),
            }
        );
        return;
    }
    out.reason = match (out.class, out.reference, out.u_data) {
        (CheckClass::Validation, Some(d), Some(u_d)) => {
            let u = vv20::Uncertainties {
                u_num: out.u_num,
                u_input: out.u_input,
                u_data: u_d,
                data_dof: out.u_data_dof,
            };
            let sampled = (interval == Interval::Sampled && !out.contributors.is_empty())
                .then_some([out.p2_5, out.p97_5]);
            match vv20::compare(out.nominal, d, u, half, sampled) {
                Some(c) => {
                    out.u_val = Some(c.u_val);
                    out.verdict = Some(c.verdict);
                    explain(&c)
                }
                None => "no verdict: a number of the comparison is not finite".into(),
            }
        }
        (CheckClass::Validation, Some(d), None) => {
            let model = (out.u_num.powi(2) + out.u_input.powi(2)).sqrt();
            let e = out.nominal - d;
            out.u_val = Some(model);
            out.verdict = Some(Vv20Verdict::NoDataUncertainty);
            format!(
                "no data uncertainty: the data state none, so E = {e:.4e} cannot be weighed; it is {:.1} times the model's own u = {model:.3e} (u_num {:.3e}, u_input {:.3e})",
                e.abs() / model,
                out.u_num,
                out.u_input
            )
        }
        (CheckClass::Validation, None, _) => {
            "no verdict: the check has no reference value (a sign or a one-sided bound)".into()
        }
        (class, _, _) => format!(
            "no verdict: a {} check is not compared with measured data",
            class.name()
        ),
    };
}

/// The coverage factor as the reasons write it: `2`, or `2.31` with the effective degrees of
/// freedom where Student's t sets it.
fn k_label(c: &Comparison) -> String {
    match c.effective_dof {
        Some(nu) if c.coverage > vv20::COVERAGE => {
            format!(
                "{:.2} (Student's t, {nu:.1} effective degrees of freedom)",
                c.coverage
            )
        }
        _ => "2".into(),
    }
}

fn explain(c: &Comparison) -> String {
    let [lo, hi] = c.model_form_interval;
    let (k, ku) = (k_label(c), c.coverage * c.u_val);
    match c.verdict {
        Vv20Verdict::ModelFormError if c.estimate_error.abs() > ku => format!(
            "|E| = {:.3e} > {k} u_val = {ku:.3e}: the model-form error lies in [{lo:.3e}, {hi:.3e}]",
            c.estimate_error.abs(),
        ),
        Vv20Verdict::ModelFormError => {
            let [a, b] = c.sampled_interval.unwrap_or([f64::NAN; 2]);
            format!(
                "|E| = {:.3e} <= {k} u_val = {ku:.3e}, but the inputs spread the model one way: D lies outside the sampled 95 % interval widened by the numerics and the data, [{a:.4e}, {b:.4e}], so no plausible input explains it",
                c.estimate_error.abs(),
            )
        }
        Vv20Verdict::Inconclusive => format!(
            "|E| = {:.3e} <= {k} u_val = {ku:.3e}, but the model's own 2 sqrt(u_num^2 + u_input^2) = {:.3e} exceeds the tolerance's half-width {:.3e}",
            c.estimate_error.abs(),
            vv20::COVERAGE * (c.u_num.powi(2) + c.u_input.powi(2)).sqrt(),
            c.tolerance_half_width
        ),
        // (Not a comparison's verdict: `judge` gives it where the data state no uncertainty.)
        Vv20Verdict::NoDataUncertainty => format!(
            "no data uncertainty: E = {:.3e} against the model's own u = {:.3e}",
            c.estimate_error,
            (c.u_num.powi(2) + c.u_input.powi(2)).sqrt()
        ),
        Vv20Verdict::Agrees => format!(
            "|E| = {:.3e} <= {k} u_val = {ku:.3e}, and the model's uncertainty is inside the tolerance",
            c.estimate_error.abs(),
        ),
    }
}

/// The verdicts of validation quantities, counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct VerdictCounts {
    pub agrees: usize,
    pub model_form_error: usize,
    pub inconclusive: usize,
    /// Compared with data that state no uncertainty: `E` given, not weighed.
    pub no_data_uncertainty: usize,
    /// Nominal passes whose verdict flips within the input distribution.
    pub fragile: usize,
    /// Validation quantities without a verdict (no reference value, or inputs not sampled).
    pub without_verdict: usize,
    /// Validation quantities of checks a corrections file applied was fitted to
    /// (`calibrated_on`): apart from every count above, since their agreement is the fit's.
    pub calibrated_on: usize,
    /// Validation quantities judged with an input whose range was taken from their own data
    /// (`circular`): apart from every count above, since the range was chosen to fit them.
    pub circular: usize,
}

impl VerdictCounts {
    /// The validation quantities among `results`, tallied.
    pub fn of<'a>(results: impl IntoIterator<Item = &'a QuantityUncertainty>) -> Self {
        let mut c = Self::default();
        for r in results
            .into_iter()
            .filter(|r| r.class == CheckClass::Validation)
        {
            if r.calibrated_on.is_some() {
                c.calibrated_on += 1;
                continue;
            }
            if r.circular.is_some() {
                c.circular += 1;
                continue;
            }
            match r.verdict {
                Some(Vv20Verdict::Agrees) => c.agrees += 1,
                Some(Vv20Verdict::ModelFormError) => c.model_form_error += 1,
                Some(Vv20Verdict::Inconclusive) => c.inconclusive += 1,
                Some(Vv20Verdict::NoDataUncertainty) => c.no_data_uncertainty += 1,
                None => c.without_verdict += 1,
            }
            c.fragile += usize::from(r.fragile);
        }
        c
    }

    /// Validation quantities counted apart from the verdicts: calibrated on, or circular.
    pub fn apart(&self) -> usize {
        self.calibrated_on + self.circular
    }

    /// Validation quantities counted.
    pub fn total(&self) -> usize {
        self.agrees
            + self.model_form_error
            + self.inconclusive
            + self.no_data_uncertainty
            + self.without_verdict
    }

    /// In words, for summaries.
    pub fn describe(&self) -> String {
        let mut apart = String::new();
        if self.calibrated_on > 0 {
            apart += &format!(
                "; apart, {} calibrated on (targets of the corrections' fit: no evidence for them)",
                self.calibrated_on
            );
        }
        if self.circular > 0 {
            apart += &format!(
                "; apart, {} circular (judged with an input range taken from their own data: no evidence)",
                self.circular
            );
        }
        format!(
            "{} agree, {} model-form error, {} inconclusive, {} without data uncertainty, {} without a verdict; {} fragile passes{apart}",
            self.agrees,
            self.model_form_error,
            self.inconclusive,
            self.no_data_uncertainty,
            self.without_verdict,
            self.fragile
        )
    }
}
