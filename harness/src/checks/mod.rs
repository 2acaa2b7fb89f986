//! Checks: one module per kind, behind one interface.
//!
//! A check is written flat in a case file ([`CheckSpec`]: its `kind` and the fields that some
//! kind takes). It stays flat on input because a serde internally-tagged enum loses the
//! location of a field inside it, and every error in a case file names its line and column.
//! It is resolved into a typed [`Check`], whose [`What`] holds what its kind needs and nothing
//! else.
//!
//! Each kind's module says, through [`Kind`] and [`Evaluate`]:
//! - which fields of the flat spec it takes (every other field given is refused, by name);
//! - which subjects it runs on (a linear model, a table, a rotor, a teeter record, an aircraft);
//! - how it resolves and checks its own fields;
//! - which quantities it computes (the keys allowed under `expect`);
//! - what the trivial predictors give (a zero derivative, a model with no response), so that a
//!   check they pass is refused at load;
//! - how it is evaluated.
//!
//! What is common to every kind (ids, class, expectations and their tolerances, the refusal of
//! checks that cannot fail) is here. Running a check and judging its outcome against the case's
//! known discrepancies is [`crate::suite::outcome`].

pub mod autorotation;
pub mod bcar;
pub mod derivative;
pub mod frequency_response;
pub mod inflow_coefficients;
pub mod linear;
pub mod milne;
pub mod mode;
pub mod result;
pub mod subject;
pub mod time_history;
pub mod tolerance;
pub mod trim;
pub mod trim_sweep;

pub use linear::System;
pub use result::{Evaluated, Finding, Locus, PlotData, QuantityResult, Trace};

use crate::checks::subject::Subject;
use crate::checks::tolerance::{Tolerance, ToleranceKind};
use crate::inputs::yaml::InputError;
use cierva_model::ModeKind;
use cierva_model::analysis::bcar::Verdict;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// What a check is evidence of. Only `validation` counts as validation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CheckClass {
    /// The model against measured data (flight or wind tunnel).
    Validation,
    /// The model against another model's numbers (RASCAL's, in the seeds).
    CrossCode,
    /// A known answer: a closed form, a synthetic truth, or published matrices run through
    /// cierva's analysis.
    Verification,
    /// The model's own earlier output, or a statement without an outside source.
    Regression,
}

impl CheckClass {
    /// The class as written in case files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Validation => "validation",
            Self::CrossCode => "cross_code",
            Self::Verification => "verification",
            Self::Regression => "regression",
        }
    }

    /// Every class, in the order summaries list them.
    pub const ALL: [CheckClass; 4] = [
        Self::Validation,
        Self::CrossCode,
        Self::Verification,
        Self::Regression,
    ];
}

/// The kinds of check (each is a module of [`crate::checks`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CheckKind {
    /// Characteristics of one mode.
    Mode,
    /// BCAR Section T verdict (and margins) of one oscillatory mode.
    Bcar,
    /// Weakly coupled systems values (seed 002 Eqs. 13-25).
    Milne,
    /// One stability or control derivative.
    Derivative,
    /// An isolated rotor's autorotative equilibrium in a wind tunnel.
    Autorotation,
    /// Inflow components from a teeter record (seed 003).
    InflowCoefficients,
    /// One trimmed flight condition of an aircraft.
    Trim,
    /// Trends of trim over a sweep of airspeeds: the least and greatest slopes between
    /// neighbouring airspeeds, and the worst residual.
    TrimSweep,
    /// A reference record's control changes flown again by the model, its responses compared
    /// with the record's: `<signal>.<metric>` (see [`crate::run::replay`]).
    TimeHistory,
    /// The model's frequency response from a control to a state against a reference's (from
    /// records, or a file), judged by CIFER's mismatch cost `J`.
    FrequencyResponse,
}

impl CheckKind {
    /// The kind as written in case files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Mode => "mode",
            Self::Bcar => "bcar",
            Self::Milne => "milne",
            Self::Derivative => "derivative",
            Self::Autorotation => "autorotation",
            Self::InflowCoefficients => "inflow_coefficients",
            Self::Trim => "trim",
            Self::TrimSweep => "trim_sweep",
            Self::TimeHistory => "time_history",
            Self::FrequencyResponse => "frequency_response",
        }
    }
}

/// A check as written: its kind, and the fields that some kind takes (each kind's module says
/// which it takes; the others are refused when given).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckSpec {
    pub id: String,
    pub kind: CheckKind,
    /// What this check is evidence of, where it differs from the case's `class`.
    #[serde(default)]
    pub class: Option<CheckClass>,
    #[serde(default)]
    pub description: Option<String>,
    /// `mode`, `bcar`: the system looked at.
    #[serde(default)]
    pub system: System,
    /// `mode`, `bcar`: the mode class to look at.
    #[serde(default)]
    pub mode: Option<ModeKind>,
    /// `derivative`: the derivative's name (`M_w`).
    #[serde(default)]
    pub derivative: Option<String>,
    /// `derivative` on a model: check the ratio of `derivative` to this one (`Q_u` divided by
    /// `Q_w`).
    #[serde(default)]
    pub divided_by: Option<String>,
    /// `bcar`: the expected verdict.
    #[serde(default)]
    pub verdict: Option<Verdict>,
    /// `autorotation`: the tunnel condition.
    #[serde(default)]
    pub tunnel: Option<autorotation::TunnelSpec>,
    /// `trim`, `time_history`, `frequency_response` and linear kinds on an aircraft: the flight
    /// condition.
    #[serde(default)]
    pub condition: Option<crate::TrimRequest>,
    /// `trim_sweep`: the airspeeds, mph, rising.
    #[serde(default)]
    pub sweep_mph: Option<Vec<f64>>,
    /// `derivative` and `time_history` on an aircraft: corrections to apply; a derivative
    /// check then also computes `magnitude_change`, `(|corrected| - |uncorrected|) /
    /// |uncorrected|`.
    #[serde(default)]
    pub corrections: Option<crate::inputs::corrections::CorrectionSet>,
    /// `time_history`: the reference record CSV (its sidecar beside it), relative to the case
    /// file; `frequency_response`: a response file (`frequency_hz,magnitude_db,phase_deg,
    /// coherence`).
    #[serde(default)]
    pub reference: Option<String>,
    /// `frequency_response`: the control whose response is compared (`eta_s`).
    #[serde(default)]
    pub input: Option<String>,
    /// `frequency_response`: the state that responds (`q`).
    #[serde(default)]
    pub output: Option<String>,
    /// `frequency_response`: flight records (CSV, sidecars beside them) the reference response
    /// is estimated from, relative to the case file.
    #[serde(default)]
    pub records: Option<Vec<String>>,
    /// `frequency_response` from records: other controls the response is conditioned on.
    #[serde(default)]
    pub conditioned_on: Option<Vec<String>>,
    /// `frequency_response` from records: the windows, s (default an eighth, a quarter and a
    /// half of the shortest record).
    #[serde(default)]
    pub windows_s: Option<Vec<f64>>,
    /// `frequency_response` from records: the band of the estimate, Hz (default the
    /// estimator's: five periods of the longest window to a fifth of the sample rate).
    #[serde(default)]
    pub band_hz: Option<[f64; 2]>,
    /// `time_history`: the model that flies the record (default the full blade model).
    #[serde(default)]
    pub simulation: Option<crate::run::replay::Simulation>,
    /// `time_history` with the full blade model: the azimuth step, deg (default the aircraft
    /// file's).
    #[serde(default)]
    pub azimuth_step_deg: Option<f64>,
    /// `derivative` on an aircraft: the derivative as this identification set-up finds it in
    /// the aircraft linearised with its flapping states, over the set-up's band
    /// ([`crate::identified_in_band_cached`]), not the quasi-static linearisation's.
    #[serde(default)]
    pub as_identified: Option<crate::ident::Setup>,
    /// Linear kinds: derivatives set to these values before the check (a what-if variant).
    #[serde(default)]
    pub set: BTreeMap<String, f64>,
    /// Linear kinds: zero every rotorspeed coupling derivative first (seed 002 Tables 2 and 5).
    #[serde(default)]
    pub without_rotorspeed_coupling: bool,
    /// Quantity -> expectation.
    #[serde(default)]
    pub expect: BTreeMap<String, ExpectSpec>,
    /// The check is known to fail, and this is why.
    #[serde(default)]
    pub expected_failure: Option<String>,
}

impl CheckSpec {
    /// The kind-specific fields given, by name, in the order the spec lists them.
    fn given(&self) -> Vec<&'static str> {
        [
            ("system", self.system != System::Full),
            ("mode", self.mode.is_some()),
            ("derivative", self.derivative.is_some()),
            ("divided_by", self.divided_by.is_some()),
            ("verdict", self.verdict.is_some()),
            ("tunnel", self.tunnel.is_some()),
            ("condition", self.condition.is_some()),
            ("sweep_mph", self.sweep_mph.is_some()),
            ("corrections", self.corrections.is_some()),
            ("reference", self.reference.is_some()),
            ("input", self.input.is_some()),
            ("output", self.output.is_some()),
            ("records", self.records.is_some()),
            ("conditioned_on", self.conditioned_on.is_some()),
            ("windows_s", self.windows_s.is_some()),
            ("band_hz", self.band_hz.is_some()),
            ("simulation", self.simulation.is_some()),
            ("azimuth_step_deg", self.azimuth_step_deg.is_some()),
            ("as_identified", self.as_identified.is_some()),
            ("set", !self.set.is_empty()),
            (
                "without_rotorspeed_coupling",
                self.without_rotorspeed_coupling,
            ),
        ]
        .into_iter()
        .filter_map(|(name, given)| given.then_some(name))
        .collect()
    }
}

/// An expectation as written: a value and a named tolerance, or an interval tolerance alone.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExpectSpec {
    #[serde(default)]
    pub value: Option<f64>,
    pub tolerance: String,
}

/// A resolved expectation on one quantity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Expectation {
    pub quantity: String,
    pub value: Option<f64>,
    pub tolerance: Tolerance,
}

/// A resolved check: what every kind has, and what its own kind needs ([`What`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    pub id: String,
    pub class: CheckClass,
    pub description: Option<String>,
    pub what: What,
    pub expectations: Vec<Expectation>,
    pub expected_failure: Option<String>,
}

/// What a check of each kind needs, typed.
#[derive(Debug, Clone, PartialEq)]
pub enum What {
    Mode(mode::ModeCheck),
    Bcar(bcar::BcarCheck),
    Milne(milne::MilneCheck),
    Derivative(derivative::DerivativeCheck),
    Autorotation(autorotation::AutorotationCheck),
    InflowCoefficients(inflow_coefficients::InflowCoefficientsCheck),
    Trim(trim::TrimCheck),
    TrimSweep(trim_sweep::TrimSweepCheck),
    TimeHistory(time_history::TimeHistoryCheck),
    FrequencyResponse(frequency_response::FrequencyResponseCheck),
}

impl What {
    /// The check's kind.
    pub fn kind(&self) -> CheckKind {
        match self {
            Self::Mode(_) => CheckKind::Mode,
            Self::Bcar(_) => CheckKind::Bcar,
            Self::Milne(_) => CheckKind::Milne,
            Self::Derivative(_) => CheckKind::Derivative,
            Self::Autorotation(_) => CheckKind::Autorotation,
            Self::InflowCoefficients(_) => CheckKind::InflowCoefficients,
            Self::Trim(_) => CheckKind::Trim,
            Self::TrimSweep(_) => CheckKind::TrimSweep,
            Self::TimeHistory(_) => CheckKind::TimeHistory,
            Self::FrequencyResponse(_) => CheckKind::FrequencyResponse,
        }
    }

    fn as_evaluate(&self) -> &dyn Evaluate {
        match self {
            Self::Mode(k) => k,
            Self::Bcar(k) => k,
            Self::Milne(k) => k,
            Self::Derivative(k) => k,
            Self::Autorotation(k) => k,
            Self::InflowCoefficients(k) => k,
            Self::Trim(k) => k,
            Self::TrimSweep(k) => k,
            Self::TimeHistory(k) => k,
            Self::FrequencyResponse(k) => k,
        }
    }
}

impl Check {
    /// The check's kind.
    pub fn kind(&self) -> CheckKind {
        self.what.kind()
    }

    /// The tip-speed ratio the check's tunnel condition states, if it states one (where a
    /// score places a peak).
    pub fn tunnel_tip_speed_ratio(&self) -> Option<f64> {
        match &self.what {
            What::Autorotation(a) => a.tunnel.tip_speed_ratio,
            _ => None,
        }
    }

    /// The flight condition the check runs at (a check on an aircraft, at one condition).
    pub fn condition(&self) -> Option<crate::TrimRequest> {
        match &self.what {
            What::Trim(t) => Some(t.condition),
            What::TimeHistory(t) => Some(t.condition),
            _ => self.linear()?.condition,
        }
    }

    /// The modifications of a check on a linear model (linear kinds).
    pub fn linear(&self) -> Option<&linear::LinearSetup> {
        match &self.what {
            What::Mode(mode::ModeCheck { linear, .. })
            | What::Bcar(bcar::BcarCheck { linear, .. })
            | What::Milne(milne::MilneCheck { linear })
            | What::Derivative(derivative::DerivativeCheck { linear, .. }) => Some(linear),
            _ => None,
        }
    }

    /// The corrections the check applies on top of its subject's.
    pub fn corrections(&self) -> Option<&crate::inputs::corrections::CorrectionSet> {
        match &self.what {
            What::Derivative(d) => d.corrections.as_ref(),
            What::TimeHistory(t) => t.corrections.as_ref(),
            _ => None,
        }
    }

    /// The quantities the check can compute (the keys allowed under `expect`).
    pub fn quantities(&self) -> Vec<String> {
        self.what.as_evaluate().quantities()
    }

    /// Computes the check's quantities and compares them with its expectations. `siblings` are
    /// the other checks of its case (a mode is followed from a neighbouring airspeed).
    pub fn evaluate(&self, subject: &Subject, siblings: &[Check]) -> Result<Evaluated, String> {
        let at = At { subject, siblings };
        self.what.as_evaluate().evaluate(&at, &self.expectations)
    }
}

/// Where a check is evaluated: its case's subject and the case's other checks.
pub struct At<'a> {
    pub subject: &'a Subject,
    pub siblings: &'a [Check],
}

/// What a trivial predictor gives for one quantity.
pub struct Trivial {
    pub quantity: String,
    pub value: f64,
    /// The predictor, in words ("a zero derivative").
    pub predictor: &'static str,
    /// A constant verdict (stable, complies): it passes every check of a sign or a verdict.
    /// Such a check is refused unless the sign is its point, which makes it `verification`
    /// with its reason in `description`.
    pub verdict: bool,
}

impl Trivial {
    /// A predictor's value for `quantity`.
    pub fn value(quantity: &str, value: f64, predictor: &'static str) -> Self {
        Self {
            quantity: quantity.to_string(),
            value,
            predictor,
            verdict: false,
        }
    }

    /// A constant verdict's value for `quantity`.
    pub fn verdict(quantity: &str, value: f64, predictor: &'static str) -> Self {
        Self {
            verdict: true,
            ..Self::value(quantity, value, predictor)
        }
    }
}

/// A constant verdict's value for each expectation of a sign on `quantities` (a stable mode's
/// real part, a complying margin): the sign's own unit, which every such check admits.
pub fn constant_verdicts(
    expectations: &[Expectation],
    quantities: &[crate::inputs::quantity::Quantity],
    predictor: &'static str,
) -> Vec<Trivial> {
    expectations
        .iter()
        .filter(|e| quantities.iter().any(|q| q.name() == e.quantity))
        .filter_map(|e| {
            match e.tolerance.kind {
                ToleranceKind::Sign(crate::checks::tolerance::Sign::Positive) => Some(1.0),
                ToleranceKind::Sign(crate::checks::tolerance::Sign::Negative) => Some(-1.0),
                _ => None,
            }
            .map(|v| Trivial::verdict(&e.quantity, v, predictor))
        })
        .collect()
}

/// The pseudo-quantity under which a `bcar` check's expected verdict meets the trivial
/// predictors.
pub const VERDICT: &str = "verdict";

/// A refusal at load: the field (a suffix of the check's own location, `.expect.q`) and why.
pub type Refusal = (String, String);

/// How a kind of check resolves from the flat spec.
pub trait Kind: Sized {
    const KIND: CheckKind;
    /// The kind-specific fields of [`CheckSpec`] it takes.
    const FIELDS: &'static [&'static str];
    /// The subjects it runs on, in words, for the error that refuses the others.
    const SUBJECTS: &'static str;
    /// Whether it runs on `subject`.
    fn runs_on(subject: &Subject) -> bool;
    /// Resolves and checks its own fields (those in `FIELDS`, and the expectation keys where
    /// they depend on them).
    fn resolve(cx: &Cx, spec: &CheckSpec) -> Result<Self, InputError>;
}

/// What a resolved check of any kind does.
pub trait Evaluate {
    /// The quantities it computes.
    fn quantities(&self) -> Vec<String>;
    /// What the trivial predictors give for its expectations, or why the check cannot fail at
    /// all. Asked of every class: a `regression` check a trivial predictor passes guards
    /// nothing either.
    fn trivial(
        &self,
        _subject: &Subject,
        _expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        Ok(vec![])
    }
    /// Computes its quantities at `at` and compares them with `expectations`.
    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String>;
}

/// A check's place in its case file, for located errors.
pub struct Cx<'a> {
    pub path: &'a Path,
    pub src: &'a str,
    pub dir: &'a Path,
    pub subject: &'a Subject,
    /// The check's own location (`checks[3]`).
    pub here: &'a str,
    pub kind: CheckKind,
    /// The check's class (its own, or its case's).
    pub class: CheckClass,
}

impl Cx<'_> {
    /// An error at the check's field `suffix` (`.tunnel`; empty for the check itself).
    pub fn err(&self, suffix: &str, msg: impl Into<String>) -> InputError {
        InputError::field(
            self.path,
            self.src,
            &format!("{}{suffix}", self.here),
            msg.into(),
        )
    }

    /// The field a kind needs, or an error that names it.
    pub fn needs<T: Clone>(&self, value: &Option<T>, field: &str) -> Result<T, InputError> {
        value.clone().ok_or_else(|| {
            self.err(
                "",
                format!("a `{}` check needs `{field}`", self.kind.name()),
            )
        })
    }
}

/// Resolves a tolerance by name, for a check of `derivative` (a tolerance may take its interval
/// from a derivative table): the case's tolerances, then the shared library's.
pub type ToleranceResolver<'a> =
    dyn Fn(&str, &str, Option<&str>) -> Result<Tolerance, InputError> + 'a;

/// Resolves one check (`cx` says where it is, its kind and class). `tolerance(field, name,
/// derivative)` finds a named tolerance.
pub fn resolve(
    cx: &Cx,
    spec: &CheckSpec,
    tolerance: &ToleranceResolver,
) -> Result<Check, InputError> {
    let (fields, subjects, runs_on) = kind_table(spec.kind);
    for f in spec.given() {
        if !fields.contains(&f) {
            return Err(cx.err(
                &format!(".{f}"),
                format!("`{f}` does not apply to a `{}` check", spec.kind.name()),
            ));
        }
    }
    if !runs_on(cx.subject) {
        return Err(cx.err(
            ".kind",
            format!(
                "`{}` checks run on {subjects}; this case's model is {}",
                spec.kind.name(),
                cx.subject.describe()
            ),
        ));
    }
    let what = resolve_what(cx, spec)?;
    if spec.expect.is_empty() && !(spec.kind == CheckKind::Bcar && spec.verdict.is_some()) {
        return Err(cx.err(
            "",
            "a check needs at least one entry under `expect` (a `bcar` check: `expect` or a \
             `verdict`)",
        ));
    }
    if let Some(r) = &spec.expected_failure
        && r.trim().is_empty()
    {
        return Err(cx.err(".expected_failure", "say why the check is expected to fail"));
    }
    let expectations = resolve_expectations(cx, spec, &what, tolerance)?;
    let class = cx.class;
    refuse_trivial(
        cx.subject,
        &what,
        &expectations,
        class,
        spec.description.as_deref(),
    )
    .map_err(|(field, msg)| cx.err(&field, msg))?;
    Ok(Check {
        id: spec.id.clone(),
        class,
        description: spec.description.clone(),
        what,
        expectations,
        expected_failure: spec.expected_failure.clone(),
    })
}

/// A kind's fields, subjects and test of its subject.
fn kind_table(kind: CheckKind) -> (&'static [&'static str], &'static str, fn(&Subject) -> bool) {
    fn row<K: Kind>() -> (&'static [&'static str], &'static str, fn(&Subject) -> bool) {
        (K::FIELDS, K::SUBJECTS, K::runs_on)
    }
    match kind {
        CheckKind::Mode => row::<mode::ModeCheck>(),
        CheckKind::Bcar => row::<bcar::BcarCheck>(),
        CheckKind::Milne => row::<milne::MilneCheck>(),
        CheckKind::Derivative => row::<derivative::DerivativeCheck>(),
        CheckKind::Autorotation => row::<autorotation::AutorotationCheck>(),
        CheckKind::InflowCoefficients => row::<inflow_coefficients::InflowCoefficientsCheck>(),
        CheckKind::Trim => row::<trim::TrimCheck>(),
        CheckKind::TrimSweep => row::<trim_sweep::TrimSweepCheck>(),
        CheckKind::TimeHistory => row::<time_history::TimeHistoryCheck>(),
        CheckKind::FrequencyResponse => row::<frequency_response::FrequencyResponseCheck>(),
    }
}

fn resolve_what(cx: &Cx, spec: &CheckSpec) -> Result<What, InputError> {
    Ok(match spec.kind {
        CheckKind::Mode => What::Mode(Kind::resolve(cx, spec)?),
        CheckKind::Bcar => What::Bcar(Kind::resolve(cx, spec)?),
        CheckKind::Milne => What::Milne(Kind::resolve(cx, spec)?),
        CheckKind::Derivative => What::Derivative(Kind::resolve(cx, spec)?),
        CheckKind::Autorotation => What::Autorotation(Kind::resolve(cx, spec)?),
        CheckKind::InflowCoefficients => What::InflowCoefficients(Kind::resolve(cx, spec)?),
        CheckKind::Trim => What::Trim(Kind::resolve(cx, spec)?),
        CheckKind::TrimSweep => What::TrimSweep(Kind::resolve(cx, spec)?),
        CheckKind::TimeHistory => What::TimeHistory(Kind::resolve(cx, spec)?),
        CheckKind::FrequencyResponse => What::FrequencyResponse(Kind::resolve(cx, spec)?),
    })
}

/// The check's expectations: each names a quantity its kind computes, a tolerance that
/// resolves, and a value exactly when the tolerance is not a bound.
fn resolve_expectations(
    cx: &Cx,
    spec: &CheckSpec,
    what: &What,
    tolerance: &ToleranceResolver,
) -> Result<Vec<Expectation>, InputError> {
    let allowed = what.as_evaluate().quantities();
    let derivative = match what {
        What::Derivative(d) => Some(d.derivative.as_str()),
        _ => None,
    };
    let mut expectations = Vec::new();
    for (q, e) in &spec.expect {
        let field = format!(".expect.{q}");
        if !allowed.contains(q) {
            let hint = crate::inputs::yaml::nearest(q, &allowed)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(cx.err(
                &field,
                format!(
                    "a `{}` check does not compute `{q}`{hint}; it computes [{}]",
                    spec.kind.name(),
                    allowed.join(", ")
                ),
            ));
        }
        let t = tolerance(&format!("{}{field}", cx.here), &e.tolerance, derivative)?;
        // A rounding tolerance propagates the rounding of a model's printed matrices: a linear
        // model's, given or an external model's answer to a check on its linear model.
        let on_matrices = match cx.subject {
            Subject::Linear { .. } => true,
            Subject::External(_) => what_is_linear(what),
            _ => false,
        };
        if matches!(t.kind, ToleranceKind::Rounding(_)) && !on_matrices {
            return Err(cx.err(
                &format!("{field}.tolerance"),
                format!(
                    "`{}` is a rounding tolerance, which applies to linear models (given, or an external model's) only",
                    t.name
                ),
            ));
        }
        match (e.value, t.kind.is_bound_only()) {
            (Some(_), true) => {
                return Err(cx.err(
                    &format!("{field}.value"),
                    format!(
                        "tolerance `{}` is a bound (an interval or a sign): give no value",
                        t.name
                    ),
                ));
            }
            (None, false) => {
                return Err(cx.err(
                    &field,
                    format!("tolerance `{}` needs an expected `value`", t.name),
                ));
            }
            (Some(v), _) if !v.is_finite() => {
                return Err(cx.err(&format!("{field}.value"), "must be finite"));
            }
            _ => {}
        }
        expectations.push(Expectation {
            quantity: q.clone(),
            value: e.value,
            tolerance: t,
        });
    }
    Ok(expectations)
}

/// Refuses a check that cannot fail: one that reads back its own input, or that a trivial
/// predictor passes (a zero derivative, a model with no response at all, a constant verdict).
/// A constant verdict passes every check of a sign or a verdict: such a check is accepted only
/// as `verification`, where the sign is the point, with the reason in its `description`.
fn refuse_trivial(
    subject: &Subject,
    what: &What,
    expectations: &[Expectation],
    class: CheckClass,
    description: Option<&str>,
) -> Result<(), Refusal> {
    let trivial = what.as_evaluate().trivial(subject, expectations)?;
    let verification = class == CheckClass::Verification;
    let reasoned = description.is_some_and(|d| !d.trim().is_empty());
    for t in &trivial {
        let passes: Option<(String, String)> = if t.quantity == VERDICT {
            Some((
                ".verdict".into(),
                format!(
                    "{} passes this check's verdict: a check of the verdict alone cannot tell \
                     the model from a constant",
                    t.predictor
                ),
            ))
        } else {
            expectations
                .iter()
                .filter(|e| e.quantity == t.quantity)
                .find(|e| {
                    crate::checks::tolerance::admits(&e.tolerance.kind, e.value, t.value)
                        == Some(true)
                })
                .map(|e| {
                    (
                        format!(".expect.{}", e.quantity),
                        format!(
                            "{} ({} = {:.4e}) passes this expectation under tolerance `{}`: \
                             the check cannot fail",
                            t.predictor, e.quantity, t.value, e.tolerance.name
                        ),
                    )
                })
        };
        let Some((field, msg)) = passes else {
            continue;
        };
        if t.verdict {
            if verification && reasoned {
                continue;
            }
            let why = if verification {
                "; a verification check whose point is the sign says why in `description`"
            } else {
                ". Give the number the source gives (a value or an interval), or, where the \
                 sign is the point, make the check `class: verification` and say why in its \
                 `description`"
            };
            return Err((field, format!("{msg}{why}")));
        }
        return Err((
            field,
            format!(
                "{msg}. Tighten it with a reason, or remove it (a sign is `sign: positive` or \
                 `sign: negative`, which refuses zero)"
            ),
        ));
    }
    Ok(())
}

/// The reference's mean as a predictor, for the checks of a table (`autorotation`, `trim`):
/// for each check, the mean of every other check's expected value of each quantity (leave one
/// out: a row's own value is not a prediction of it). A check all of whose valued expectations
/// that mean passes cannot tell the model from a constant: its index and why. A quantity that
/// fewer than two checks expect, or that every check expects at one value (a source quoting one
/// figure for all its conditions), gives no prediction beyond the reference itself.
pub fn refuse_reference_mean(checks: &[Check]) -> Result<(), (usize, String)> {
    let table = |c: &Check| matches!(c.what, What::Autorotation(_) | What::Trim(_));
    // Per quantity: the sum and count of the expected values, and whether they differ.
    let mut sums: BTreeMap<&str, (f64, usize, f64, bool)> = BTreeMap::new();
    for c in checks.iter().filter(|c| table(c)) {
        for e in &c.expectations {
            if let Some(v) = e.value {
                let s = sums
                    .entry(e.quantity.as_str())
                    .or_insert((0.0, 0, v, false));
                s.0 += v;
                s.1 += 1;
                s.3 |= v != s.2;
            }
        }
    }
    for (i, c) in checks.iter().enumerate().filter(|(_, c)| table(c)) {
        let mut passed = Vec::new();
        let mut valued = 0;
        for e in &c.expectations {
            let Some(v) = e.value else { continue };
            valued += 1;
            let (sum, n, _, varies) = sums[e.quantity.as_str()];
            if n < 2 || !varies {
                continue;
            }
            let mean = (sum - v) / (n - 1) as f64;
            if crate::checks::tolerance::admits(&e.tolerance.kind, Some(v), mean) == Some(true) {
                passed.push(format!("{} = {mean:.4e}", e.quantity));
            }
        }
        if valued > 0 && passed.len() == valued {
            return Err((
                i,
                format!(
                    "the mean of the other rows' expected values ({}) passes every expectation \
                     of this check: it cannot tell the model from a constant. Give a tighter \
                     tolerance with its reason, or leave the row out",
                    passed.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// Names of quantities, as the `expect` keys write them.
fn names(list: &[crate::inputs::quantity::Quantity]) -> Vec<String> {
    list.iter().map(|q| q.name().to_string()).collect()
}

/// A flight condition as a check may give it: a positive airspeed, finite climb and turn rates;
/// `straight` when the check's model is linearised about straight flight.
fn check_condition(cx: &Cx, t: &crate::TrimRequest, straight: bool) -> Result<(), InputError> {
    let ok = t.airspeed_mph.is_finite()
        && t.airspeed_mph > 0.0
        && t.climb_m_s.is_finite()
        && t.turn_rate_deg_s.is_finite();
    if !ok {
        return Err(cx.err(
            ".condition",
            "the airspeed must be positive, climb and turn rates finite",
        ));
    }
    if straight && t.turn_rate_deg_s != 0.0 {
        return Err(cx.err(
            ".condition.turn_rate_deg_s",
            "the model is linearised about straight flight",
        ));
    }
    Ok(())
}

/// Whether the subject is an aircraft.
fn is_aircraft(subject: &Subject) -> bool {
    matches!(subject, Subject::Aircraft { .. })
}

/// Whether the subject is a flight model ([`crate::external::FlightModel`]): an aircraft or
/// an external model.
fn is_flight_model(subject: &Subject) -> bool {
    matches!(subject, Subject::Aircraft { .. } | Subject::External(_))
}

/// A case's subject as a flight model, if it is one: cierva's aircraft (flown by the full
/// blade model at its file's azimuth step) or another simulation; with its loading.
pub fn flight_model(
    subject: &Subject,
) -> Option<(Box<dyn crate::external::FlightModel + '_>, crate::Loading)> {
    match subject {
        Subject::Aircraft { file, loading } => {
            Some((Box::new(crate::external::Aircraft::new(file)), *loading))
        }
        Subject::External(e) => Some((Box::new(e.model.clone()), e.loading)),
        _ => None,
    }
}

/// Whether the check runs on a linear model (`mode`, `bcar`, `milne`, `derivative`).
fn what_is_linear(what: &What) -> bool {
    matches!(
        what,
        What::Mode(_) | What::Bcar(_) | What::Milne(_) | What::Derivative(_)
    )
}

/// The subjects that are flight models, in words.
const FLIGHT_MODELS: &str = "an aircraft or an external model";
