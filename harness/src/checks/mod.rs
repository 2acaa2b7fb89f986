//! Checks: one module per kind, behind one interface.
//!
//! One list, `registry!`, names every kind: its variant, its name in case files and its
//! module's type. [`CheckKind`], [`What`] and every dispatch over kinds are generated from it.
//!
//! A check as written is what every check has ([`CheckSpec`]) and its kind's own fields, which
//! the kind deserialises into its [`Kind::Spec`] (refusing any it does not take). Errors are
//! located by serde's path to the field ([`split_written`], `from_written`), since a value
//! already parsed carries no line. It is resolved into a typed [`Check`], whose [`What`] holds
//! what its kind needs and nothing else.
//!
//! Each kind's module says, through [`Kind`] and [`Evaluate`]:
//! - its own fields ([`Kind::Spec`]) and which subjects it runs on;
//! - how it resolves and checks its own fields;
//! - which quantities it computes (the keys allowed under `expect`);
//! - what the trivial predictors give (a zero derivative, a model with no response), so that a
//!   check they pass is refused at load;
//! - how it is evaluated;
//! - what the rest of cierva asks of a check: its condition, what it measures for a fit
//!   ([`Measured`]), where the report's figures place it ([`Placed`]), and what it adds to the
//!   snapshots ([`Snapshotted`]). Nothing outside `checks/` matches on a kind.
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
pub mod trim_points;
pub mod trim_sweep;

pub use linear::System;
pub use result::{Evaluated, Finding, Locus, PlotData, QuantityResult, Trace};

use crate::checks::subject::Subject;
use crate::checks::tolerance::{Tolerance, ToleranceKind};
use crate::inputs::yaml::InputError;
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

/// The one list of check kinds: each kind's variant, its name in case files and its module's
/// type. [`CheckKind`], [`What`] and every dispatch over kinds are generated from it, so a new
/// kind is one module and one line here.
macro_rules! registry {
    ($( $(#[$doc:meta])* $variant:ident = $name:literal => $ty:ty; )*) => {
        /// The kinds of check (each is a module of [`crate::checks`]).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
        pub enum CheckKind {
            $( $(#[$doc])* #[serde(rename = $name)] $variant, )*
        }

        impl CheckKind {
            /// Every kind, in the registry's order.
            pub const ALL: &[CheckKind] = &[$(Self::$variant),*];

            /// The kind as written in case files.
            pub fn name(self) -> &'static str {
                match self {
                    $( Self::$variant => $name, )*
                }
            }

            /// How checks of this kind resolve.
            fn entry(self) -> Entry {
                match self {
                    $( Self::$variant => Entry::of::<$ty>(), )*
                }
            }
        }

        /// What a check of each kind needs, typed.
        #[derive(Debug, Clone, PartialEq)]
        pub enum What {
            $( $variant($ty), )*
        }

        $(
            impl From<$ty> for What {
                fn from(k: $ty) -> Self {
                    Self::$variant(k)
                }
            }
        )*

        impl What {
            /// The check's kind.
            pub fn kind(&self) -> CheckKind {
                match self {
                    $( Self::$variant(_) => CheckKind::$variant, )*
                }
            }

            /// The kind's behaviour.
            pub fn as_evaluate(&self) -> &dyn Evaluate {
                match self {
                    $( Self::$variant(k) => k, )*
                }
            }
        }
    };
}

registry! {
    /// Characteristics of one mode.
    Mode = "mode" => mode::ModeCheck;
    /// BCAR Section T verdict (and margins) of one oscillatory mode.
    Bcar = "bcar" => bcar::BcarCheck;
    /// Weakly coupled systems values (seed 002 Eqs. 13-25).
    Milne = "milne" => milne::MilneCheck;
    /// One stability or control derivative.
    Derivative = "derivative" => derivative::DerivativeCheck;
    /// An isolated rotor's autorotative equilibrium in a wind tunnel.
    Autorotation = "autorotation" => autorotation::AutorotationCheck;
    /// Inflow components from a teeter record (seed 003).
    InflowCoefficients = "inflow_coefficients" => inflow_coefficients::InflowCoefficientsCheck;
    /// One trimmed flight condition of an aircraft.
    Trim = "trim" => trim::TrimCheck;
    /// Trends of trim over a sweep of airspeeds: the least and greatest slopes between
    /// neighbouring airspeeds, and the worst residual.
    TrimSweep = "trim_sweep" => trim_sweep::TrimSweepCheck;
    /// A flight test's trim points, each trimmed again: a level and a trend of the model's
    /// error judged together against the points' scatter.
    TrimPoints = "trim_points" => trim_points::TrimPointsCheck;
    /// A reference record's control changes flown again by the model, its responses compared
    /// with the record's: `<signal>.<metric>` (see [`crate::run::replay`]).
    TimeHistory = "time_history" => time_history::TimeHistoryCheck;
    /// The model's frequency response from a control to a state against a reference's (from
    /// records, or a file), judged by CIFER's mismatch cost `J`.
    FrequencyResponse = "frequency_response" => frequency_response::FrequencyResponseCheck;
}

/// A kind's row of the registry: the subjects it runs on, and how it resolves its own fields.
struct Entry {
    /// The fields of its own it takes.
    fields: fn() -> &'static [&'static str],
    subjects: &'static str,
    runs_on: fn(&Subject) -> bool,
    resolve: fn(&Cx, serde_yaml::Mapping, &CheckSpec) -> Result<What, InputError>,
}

impl Entry {
    fn of<K: Kind + Into<What>>() -> Self {
        Self {
            fields: fields_of::<K::Spec>,
            subjects: K::SUBJECTS,
            runs_on: K::runs_on,
            resolve: |cx, own, spec| {
                let own: K::Spec = from_written(cx.path, cx.src, cx.here, own, Some(cx.kind))?;
                Ok(K::resolve(cx, own, spec)?.into())
            },
        }
    }
}

/// What every check has, as written. The rest of a check's fields are its kind's own: its
/// module's `Spec`, which refuses any field it does not take ([`Kind::Spec`]).
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
    /// Quantity -> expectation.
    #[serde(default)]
    pub expect: BTreeMap<String, ExpectSpec>,
    /// The check is known to fail, and this is why.
    #[serde(default)]
    pub expected_failure: Option<String>,
}

/// The fields of [`CheckSpec`]: every other field of a check is its kind's.
const COMMON_FIELDS: [&str; 6] = [
    "id",
    "kind",
    "class",
    "description",
    "expect",
    "expected_failure",
];

/// A check as the case file wrote it (`here`, `checks[3]`): what every check has, and its
/// kind's own fields, still to be read by its kind.
pub fn split_written(
    path: &Path,
    src: &str,
    here: &str,
    written: serde_yaml::Mapping,
) -> Result<(CheckSpec, serde_yaml::Mapping), InputError> {
    let (mut common, mut own) = (serde_yaml::Mapping::new(), serde_yaml::Mapping::new());
    for (k, v) in written {
        if k.as_str().is_some_and(|k| COMMON_FIELDS.contains(&k)) {
            common.insert(k, v);
        } else {
            own.insert(k, v);
        }
    }
    Ok((from_written(path, src, here, common, None)?, own))
}

/// Deserialises fields of the check at `here` from what was written, each error located at its
/// field in the case file. Of a kind's own fields (`kind`), a field it does not take is said to
/// belong to another kind, or to none, and a field it needs and is not given is named.
fn from_written<T: serde::de::DeserializeOwned>(
    path: &Path,
    src: &str,
    here: &str,
    fields: serde_yaml::Mapping,
    kind: Option<CheckKind>,
) -> Result<T, InputError> {
    serde_path_to_error::deserialize(serde_yaml::Value::Mapping(fields)).map_err(|e| {
        let at = match e.path().to_string().as_str() {
            "." => String::new(),
            p => format!(".{p}"),
        };
        let message = e.into_inner().to_string();
        let quoted = |prefix: &str| {
            let rest = message.strip_prefix(prefix)?;
            Some(rest.split_once('`')?.0.to_string())
        };
        if let Some(field) = quoted("unknown field `") {
            // The path ends at the unknown field; its parent is where it was written.
            let own_field = at == format!(".{field}");
            let msg = match kind {
                Some(k) if own_field => not_taken(k, &field),
                _ => match crate::inputs::yaml::suggestion(&message) {
                    Some(hint) => format!("{message}; {hint}"),
                    None => message.clone(),
                },
            };
            return InputError::field(path, src, &format!("{here}{at}"), msg);
        }
        if let (Some(k), Some(field), true) = (kind, quoted("missing field `"), at.is_empty()) {
            return InputError::field(
                path,
                src,
                here,
                format!("a `{}` check needs `{field}`", k.name()),
            );
        }
        InputError::field(path, src, &format!("{here}{at}"), message)
    })
}

/// Why a `kind` check refuses its field `field`: another kind's, or no kind's (with the nearest
/// field a check of this kind takes).
fn not_taken(kind: CheckKind, field: &str) -> String {
    let own = (kind.entry().fields)();
    let takes = if own.is_empty() {
        "no fields of its own".to_string()
    } else {
        format!("`{}`", own.join("`, `"))
    };
    let others: Vec<&str> = CheckKind::ALL
        .iter()
        .filter(|k| (k.entry().fields)().contains(&field))
        .map(|k| k.name())
        .collect();
    if !others.is_empty() {
        return format!(
            "`{field}` does not apply to a `{}` check, which takes {takes}; it is a field of `{}` checks",
            kind.name(),
            others.join("`, `")
        );
    }
    let known: Vec<String> = own
        .iter()
        .chain(&COMMON_FIELDS)
        .map(|f| f.to_string())
        .collect();
    let hint = crate::inputs::yaml::nearest(field, &known)
        .map(|n| format!("; did you mean `{n}`?"))
        .unwrap_or_default();
    format!(
        "unknown field `{field}`: a `{}` check takes {takes}, besides every check's `{}`{hint}",
        kind.name(),
        COMMON_FIELDS.join("`, `"),
    )
}

/// The fields a struct's `Deserialize` asks for: serde's derive names them when it asks for a
/// struct, which a probe records (and then stops).
fn fields_of<T: serde::de::DeserializeOwned>() -> &'static [&'static str] {
    use serde::de::{self, Visitor};
    struct Probe(&'static [&'static str]);
    impl<'de> de::Deserializer<'de> for &mut Probe {
        type Error = de::value::Error;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
            Err(de::Error::custom("not a struct"))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Self::Error> {
            self.0 = fields;
            Err(de::Error::custom("probed"))
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes
            byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map enum
            identifier ignored_any
        }
    }
    let mut probe = Probe(&[]);
    let _ = T::deserialize(&mut probe);
    probe.0
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

impl Check {
    /// The check's kind.
    pub fn kind(&self) -> CheckKind {
        self.what.kind()
    }

    /// What its kind does with it.
    pub fn behaviour(&self) -> &dyn Evaluate {
        self.what.as_evaluate()
    }

    /// The tip-speed ratio the check's tunnel condition states, if it states one (where a
    /// score places a peak).
    pub fn tunnel_tip_speed_ratio(&self) -> Option<f64> {
        self.behaviour().tunnel()?.tip_speed_ratio
    }

    /// The flight condition the check trims or linearises its subject at.
    pub fn condition(&self) -> Option<crate::inputs::condition::TrimRequest> {
        self.behaviour().condition()
    }

    /// The modifications of a check on a linear model (linear kinds).
    pub fn linear(&self) -> Option<&linear::LinearSetup> {
        self.behaviour().linear()
    }

    /// The corrections the check applies on top of its subject's.
    pub fn corrections(&self) -> Option<&crate::inputs::corrections::CorrectionSet> {
        self.behaviour().corrections()
    }

    /// The quantities the check can compute (the keys allowed under `expect`).
    pub fn quantities(&self) -> Vec<String> {
        self.behaviour().quantities()
    }

    /// Computes the check's quantities and compares them with its expectations. `siblings` are
    /// the other checks of its case (a mode is followed from a neighbouring airspeed).
    pub fn evaluate(&self, subject: &Subject, siblings: &[Check]) -> Result<Evaluated, String> {
        let at = At { subject, siblings };
        self.behaviour().evaluate(&at, &self.expectations)
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

/// How a kind of check resolves from what the case file wrote.
pub trait Kind: Sized {
    /// Its own fields as written (every check's are [`CheckSpec`]'s). It refuses the fields it
    /// does not take (`deny_unknown_fields`): the error names the field, its line and column.
    type Spec: serde::de::DeserializeOwned;
    /// The subjects it runs on, in words, for the error that refuses the others.
    const SUBJECTS: &'static str;
    /// Whether it runs on `subject`.
    fn runs_on(subject: &Subject) -> bool;
    /// Resolves and checks its own fields (and the expectation keys where they depend on
    /// them; `written` is what every check has).
    fn resolve(cx: &Cx, own: Self::Spec, written: &CheckSpec) -> Result<Self, InputError>;
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

    /// Whether zero is a prediction of `quantity` (a derivative, a slope, an eigenvalue, a
    /// coefficient), which every kind is tried against (`generic_trivial`); not where zero is
    /// a perfect score (an error, a cost: smaller is better), which the kind's own predictors
    /// stand in for (a model with no response).
    fn zero_predicts(&self, _quantity: &str) -> bool {
        true
    }
    /// Whether it checks a ratio of two of the model's quantities (`derivative / divided_by`),
    /// whose interval (a qualitative inequality: `Q_u < Q_w`, both positive) is passed by its
    /// own midpoint, a constant ratio.
    fn is_ratio(&self) -> bool {
        false
    }

    /// Whether it judges something with no entry under `expect` (a BCAR check's verdict).
    fn judges_without_expect(&self) -> bool {
        false
    }
    /// The derivative it checks, whose entry in a derivative table a tolerance may take its
    /// interval from.
    fn derivative(&self) -> Option<&str> {
        None
    }
    /// The flight condition it trims or linearises its subject at (a check on a linear model:
    /// its setup's).
    fn condition(&self) -> Option<crate::inputs::condition::TrimRequest> {
        self.linear()?.condition
    }
    /// The tunnel condition of a check on an isolated rotor.
    fn tunnel(&self) -> Option<&crate::inputs::condition::TunnelSpec> {
        None
    }
    /// On a linear model: where the model is taken and how the check modifies it.
    fn linear(&self) -> Option<&linear::LinearSetup> {
        None
    }
    /// The corrections it applies on top of its subject's.
    fn corrections(&self) -> Option<&crate::inputs::corrections::CorrectionSet> {
        None
    }
    /// What makes it one row of a series over a case's conditions (a trim, an autorotation,
    /// one derivative or one mode at several airspeeds): the other rows' mean reference is a
    /// constant predictor it must beat ([`refuse_reference_mean`]). `None`: not a row.
    fn series(&self) -> Option<String> {
        None
    }
    /// What it measures of its subject, for a fit or a sensitivity study.
    fn measured(&self) -> Measured<'_> {
        Measured::Elsewhere
    }
    /// The name the model gives its quantity `quantity` (a derivative check's `value` is the
    /// derivative, `M_w`), or `None` where that quantity is not one of the subject's (a
    /// derivative's change under corrections).
    fn model_name(&self, quantity: &str) -> Option<String> {
        Some(quantity.to_string())
    }
    /// Where the report's figures that gather checks place it (its own figures come from its
    /// result's [`PlotData`]).
    fn placed(&self) -> Option<Placed<'_>> {
        None
    }
    /// What loading its inputs (records, trim points) mapped, converted or kept and did not
    /// compare, in words, each with its file: what the report says of the check's data.
    fn input_notes(&self) -> Vec<(std::path::PathBuf, String)> {
        Vec::new()
    }
    /// What it adds to its case's regression snapshots (`reports/snapshots/`; a check on a
    /// linear model: its aircraft trimmed and linearised at its condition).
    fn snapshotted(&self) -> Vec<Snapshotted<'_>> {
        self.linear().map(linear::snapshotted).unwrap_or_default()
    }
}

/// What a check measures of its subject, for a fit or a sensitivity study.
#[derive(Debug, Clone, PartialEq)]
pub enum Measured<'a> {
    /// Its quantities of the subject as it is, at one condition.
    At(Place<'a>),
    /// At one condition, of the subject as the check modifies it (its own corrections,
    /// derivatives set or cut, a ratio, a model identified from it): not a reference to fit.
    Modified,
    /// Not a measurement at one condition (a sweep, a record, a mode, a table).
    Elsewhere,
}

/// One condition of a subject.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Place<'a> {
    /// An aircraft's trimmed flight condition.
    Flight(crate::inputs::condition::TrimRequest),
    /// An isolated rotor's tunnel condition.
    Tunnel(&'a crate::inputs::condition::TunnelSpec),
}

/// Where the report's figures that gather checks place one.
#[derive(Debug, Clone, PartialEq)]
pub enum Placed<'a> {
    /// A trimmed condition's quantities, against airspeed, mph.
    Airspeed(f64),
    /// An isolated rotor's quantities, against tip-speed ratio (or disc angle).
    Tunnel(&'a crate::inputs::condition::TunnelSpec),
    /// An aircraft's derivative at an airspeed, across cases and masses.
    Derivative {
        /// `M_w`, or a ratio `Q_u / Q_w`.
        label: String,
        airspeed_mph: f64,
        /// The check applies corrections of its own.
        corrected: bool,
        /// The derivative as an identification set-up finds it.
        as_identified: bool,
    },
    /// Inflow recovered from a flapping record, against the record's airspeed.
    FlapRecord,
    /// A mode among its system's eigenvalues; `modified` when the check sets derivatives or
    /// cuts couplings (its eigenvalues are then not the model's).
    Eigenvalues {
        system: System,
        condition: Option<crate::inputs::condition::TrimRequest>,
        modified: bool,
        /// The check judges the mode by BCAR Section T: it is drawn on the BCAR chart too.
        bcar: bool,
    },
}

/// What a check adds to its case's regression snapshots.
#[derive(Debug, Clone, PartialEq)]
pub enum Snapshotted<'a> {
    /// Conditions its aircraft is trimmed at (columns of the trim table).
    Trims(Vec<crate::inputs::condition::TrimRequest>),
    /// A condition its aircraft is linearised at (a table of the linear model there).
    Linearised(crate::inputs::condition::TrimRequest),
    /// A row of the isolated rotor's autorotation table.
    Autorotation(&'a crate::inputs::condition::TunnelSpec),
    /// A row of the table of time-history metrics.
    TimeHistory(&'a time_history::TimeHistoryCheck),
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

/// Resolves one check (`cx` says where it is, its kind and class) from what every check has
/// and its kind's own fields as written. `tolerance(field, name, derivative)` finds a named
/// tolerance.
pub fn resolve(
    cx: &Cx,
    spec: &CheckSpec,
    own: serde_yaml::Mapping,
    tolerance: &ToleranceResolver,
) -> Result<Check, InputError> {
    let entry = spec.kind.entry();
    if !(entry.runs_on)(cx.subject) {
        return Err(cx.err(
            ".kind",
            format!(
                "`{}` checks run on {}; this case's model is {}",
                spec.kind.name(),
                entry.subjects,
                cx.subject.describe()
            ),
        ));
    }
    let what = (entry.resolve)(cx, own, spec)?;
    if spec.expect.is_empty() && !what.as_evaluate().judges_without_expect() {
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

/// The check's expectations: each names a quantity its kind computes, a tolerance that
/// resolves, and a value exactly when the tolerance is not a bound.
fn resolve_expectations(
    cx: &Cx,
    spec: &CheckSpec,
    what: &What,
    tolerance: &ToleranceResolver,
) -> Result<Vec<Expectation>, InputError> {
    let allowed = what.as_evaluate().quantities();
    let derivative = what.as_evaluate().derivative();
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
            Subject::External(_) => what.as_evaluate().linear().is_some(),
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
/// as `verification`, where the sign is the point, or as `regression`, where the side is the
/// model's own (no source gives the flight's), with the reason in its `description`.
fn refuse_trivial(
    subject: &Subject,
    what: &What,
    expectations: &[Expectation],
    class: CheckClass,
    description: Option<&str>,
) -> Result<(), Refusal> {
    let mut trivial = what.as_evaluate().trivial(subject, expectations)?;
    trivial.extend(generic_trivial(what.as_evaluate(), expectations));
    // The classes that say a constant verdict is not evidence against the data.
    let verification = matches!(class, CheckClass::Verification | CheckClass::Regression);
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
                "; a verification check whose point is the sign, or a regression check that \
                 guards the side the model's own mode is on, says why in `description`"
            } else {
                ". Give the number the source gives (a value or an interval), or, where the \
                 sign is the point, make the check `class: verification`, or, where no source \
                 gives the verdict and it guards the model's own side, `class: regression`, and \
                 say why in its `description`"
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

/// The predictors every kind is tried against (issue 51, item 7), besides its own:
/// - **sign-only**: any value of the expected sign passes an expectation of a sign;
/// - **zero**: no effect at all, on every quantity of which zero is a prediction
///   ([`Evaluate::zero_predicts`]);
/// - **a constant ratio**: a ratio's interval is passed by its own midpoint.
///
/// Each is a verdict in the sense of [`refuse_trivial`]: a check it passes says nothing a
/// constant would not, so it is refused as `validation` or `cross_code`, and accepted as
/// `verification` (where the sign or the zero is the point: a symmetry, a law) or `regression`
/// (guarding the model's own side) with its reason in `description`. The constant across a
/// case's conditions is [`refuse_reference_mean`]'s.
fn generic_trivial(kind: &dyn Evaluate, expectations: &[Expectation]) -> Vec<Trivial> {
    use crate::checks::tolerance::Sign;
    let mut out = Vec::new();
    for e in expectations {
        match e.tolerance.kind {
            ToleranceKind::Sign(s) => out.push(Trivial::verdict(
                &e.quantity,
                if s == Sign::Positive { 1.0 } else { -1.0 },
                "a sign-only predictor (any value of the expected sign)",
            )),
            ToleranceKind::Interval(lower, upper) if kind.is_ratio() => {
                out.push(Trivial::verdict(
                    &e.quantity,
                    0.5 * (lower + upper),
                    "a constant ratio (the interval's own midpoint)",
                ));
            }
            _ => {}
        }
        if kind.zero_predicts(&e.quantity) {
            out.push(Trivial::verdict(
                &e.quantity,
                0.0,
                "a zero (no effect at all)",
            ));
        }
    }
    out
}

/// The reference's mean as a constant predictor, for the rows of a series over a case's
/// conditions ([`Evaluate::series`]: a trim, an autorotation, one derivative, mode or BCAR
/// margin at several airspeeds): for each check, the mean of every other row's reference of
/// each quantity (its expected value or its interval's middle; leave one out: a row's own value
/// is not a prediction of it). A check all of whose references that mean passes cannot tell
/// the model from a constant: its index and why, unless it is `verification` or `regression`
/// with its reason in `description` (as for a constant verdict, `refuse_trivial`). A quantity that
/// fewer than two checks expect, or that every check expects at one value (a source quoting one
/// figure for all its conditions), gives no prediction beyond the reference itself.
pub fn refuse_reference_mean(checks: &[Check]) -> Result<(), (usize, String)> {
    let series: Vec<Option<String>> = checks.iter().map(|c| c.behaviour().series()).collect();
    // Per series and quantity: the sum and count of the references, and whether they differ.
    let mut sums: BTreeMap<(&str, &str), (f64, usize, f64, bool)> = BTreeMap::new();
    for (c, key) in checks.iter().zip(&series) {
        let Some(key) = key else { continue };
        for e in &c.expectations {
            if let Some(v) = reference_of(e) {
                let s = sums
                    .entry((key.as_str(), e.quantity.as_str()))
                    .or_insert((0.0, 0, v, false));
                s.0 += v;
                s.1 += 1;
                s.3 |= v != s.2;
            }
        }
    }
    for (i, (c, key)) in checks.iter().zip(&series).enumerate() {
        let Some(key) = key else { continue };
        // A verification or regression check says in its description why a constant is no
        // objection (a self-consistency whose point is the level, not the trend).
        let reasoned = matches!(c.class, CheckClass::Verification | CheckClass::Regression)
            && c.description
                .as_deref()
                .is_some_and(|d| !d.trim().is_empty());
        if reasoned {
            continue;
        }
        let mut passed = Vec::new();
        let mut valued = 0;
        for e in &c.expectations {
            let Some(v) = reference_of(e) else { continue };
            valued += 1;
            let (sum, n, _, varies) = sums[&(key.as_str(), e.quantity.as_str())];
            if n < 2 || !varies {
                continue;
            }
            let mean = (sum - v) / (n - 1) as f64;
            if crate::checks::tolerance::admits(&e.tolerance.kind, e.value, mean) == Some(true) {
                passed.push(format!("{} = {mean:.4e}", e.quantity));
            }
        }
        if valued > 0 && passed.len() == valued {
            return Err((
                i,
                format!(
                    "the mean of the other rows' references ({}; the same quantity at the \
                     case's other conditions) passes every expectation of this check: it cannot \
                     tell the model from a constant. Give a tighter tolerance with its reason, \
                     leave the row out, or, where the level and not the trend is the point, make \
                     it `class: verification` or `class: regression` and say why in its \
                     `description`",
                    passed.join(", ")
                ),
            ));
        }
    }
    Ok(())
}

/// An expectation's reference value, for the mean of a series: its expected value, or its
/// interval's middle; none for a sign.
fn reference_of(e: &Expectation) -> Option<f64> {
    match e.tolerance.kind {
        ToleranceKind::Interval(lower, upper) => Some(0.5 * (lower + upper)),
        _ => e.value,
    }
}

/// Names of quantities, as the `expect` keys write them.
fn names(list: &[crate::inputs::quantity::Quantity]) -> Vec<String> {
    list.iter().map(|q| q.name().to_string()).collect()
}

/// A flight condition as a check may give it: a positive airspeed, finite climb and turn rates;
/// `straight` when the check's model is linearised about straight flight.
fn check_condition(
    cx: &Cx,
    t: &crate::inputs::condition::TrimRequest,
    straight: bool,
) -> Result<(), InputError> {
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

/// How far a check's airspeed may lie from its record's before the two are different flights: 5
/// % (3 kn at 60 kn; a test point is flown to a knot or two of its target, and the sidecar
/// states the target or the mean).
pub const RECORD_AIRSPEED_MATCH: f64 = 0.05;
/// How far the check's mass may lie from its record's: 5 % (22 kg at 450 kg; an autogyro burns
/// 15-20 kg of fuel in an hour's sortie).
pub const RECORD_MASS_MATCH: f64 = 0.05;
/// How far the check's density altitude may lie from its record's, ft: 1000 ft (about 3 % in
/// density; a sortie's test points span a few hundred feet).
pub const RECORD_DENSITY_ALTITUDE_MATCH_FT: f64 = 1000.0;
/// How far the check's rate of climb may lie from its record's, m/s (a level point is held to
/// about 100 ft/min).
pub const RECORD_CLIMB_MATCH_M_S: f64 = 0.5;

/// A check's condition and its subject's loading against a record's sidecar (where the sidecar
/// states a condition): a difference beyond [`RECORD_AIRSPEED_MATCH`] and the others is an
/// error at `field` that names both conditions, unless the check says why it differs
/// (`condition_differs_from_record: REASON`).
fn condition_matches_record(
    cx: &Cx,
    field: &str,
    condition: &crate::inputs::condition::TrimRequest,
    record: &crate::inputs::record::Record,
    differs: Option<&str>,
) -> Result<(), InputError> {
    if record.meta.condition.is_empty() || differs.is_some_and(|r| !r.trim().is_empty()) {
        return Ok(());
    }
    let (flown, at) = crate::ident::record_condition(record).map_err(|e| cx.err(field, e))?;
    let loading = match cx.subject {
        Subject::Aircraft { loading, .. } => Some(*loading),
        Subject::External(e) => Some(e.loading),
        _ => None,
    };
    let mut differ = Vec::new();
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-9);
    if rel(condition.airspeed_mph, flown.airspeed_mph) > RECORD_AIRSPEED_MATCH {
        differ.push(format!(
            "airspeed {:.1} mph against the record's {:.1} mph (RECORD_AIRSPEED_MATCH, 5 %)",
            condition.airspeed_mph, flown.airspeed_mph
        ));
    }
    if (condition.climb_m_s - flown.climb_m_s).abs() > RECORD_CLIMB_MATCH_M_S {
        differ.push(format!(
            "climb {} m/s against the record's {} m/s (RECORD_CLIMB_MATCH_M_S, 0.5 m/s)",
            condition.climb_m_s, flown.climb_m_s
        ));
    }
    if let Some(l) = loading {
        if let (Some(m), Some(r)) = (l.mass_kg, at.mass_kg)
            && rel(m, r) > RECORD_MASS_MATCH
        {
            differ.push(format!(
                "mass {m} kg against the record's {r} kg (RECORD_MASS_MATCH, 5 %)"
            ));
        }
        if record.meta.condition.contains_key("density_altitude_ft")
            && (l.density_altitude_ft - at.density_altitude_ft).abs()
                > RECORD_DENSITY_ALTITUDE_MATCH_FT
        {
            differ.push(format!(
                "density altitude {} ft against the record's {} ft (RECORD_DENSITY_ALTITUDE_MATCH_FT, 1000 ft)",
                l.density_altitude_ft, at.density_altitude_ft
            ));
        }
    }
    if differ.is_empty() {
        return Ok(());
    }
    Err(cx.err(
        field,
        format!(
            "the check is not where its record was flown: {}; fix the condition or the case's loading, or say why they differ with `condition_differs_from_record: REASON`",
            differ.join("; ")
        ),
    ))
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
) -> Option<(
    Box<dyn crate::external::FlightModel + '_>,
    crate::inputs::condition::Loading,
)> {
    match subject {
        Subject::Aircraft { file, loading } => Some((
            Box::new(crate::external::CiervaAircraft::new(file)),
            *loading,
        )),
        Subject::External(e) => Some((Box::new(e.model.clone()), e.loading)),
        _ => None,
    }
}

/// A case's subject as a model behind the model interface, if it is one: a flight model
/// ([`flight_model`]), or cierva's rotor in a tunnel
/// ([`crate::external::rotor::CiervaRotor`], solved as the case says).
pub fn model_of(subject: &Subject) -> Option<Box<dyn crate::external::FlightModel + '_>> {
    match subject {
        Subject::Rotor { file, solver, .. } => Some(Box::new(
            crate::external::rotor::CiervaRotor::new(file, *solver),
        )),
        _ => flight_model(subject).map(|(model, _)| model),
    }
}

/// A loaded file's notes ([`Evaluate::input_notes`]), each with the file.
fn notes_of(path: &Path, notes: &[String]) -> Vec<(std::path::PathBuf, String)> {
    notes
        .iter()
        .map(|n| (path.to_path_buf(), n.clone()))
        .collect()
}

/// The subjects that are flight models, in words.
const FLIGHT_MODELS: &str = "an aircraft or an external model";
