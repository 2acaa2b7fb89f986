//! What the checks on a linear model share (`mode`, `bcar`, `milne`, `derivative`): the model
//! they run on (a linear model given, or an aircraft linearised at the check's condition), its
//! modification (`set`, `without_rotorspeed_coupling`), the selection of a mode and its
//! continuation, and the `rounding` tolerance.
//!
//! # Rounding tolerance
//! Published matrices are rounded, so a quantity computed from them differs from the
//! published value computed from the unrounded matrices. The `rounding` tolerance bounds this
//! difference to first order: every entry of A and B outside the kinematic rows (`phi`,
//! `theta`, `psi`) is moved by half a unit of `input_decimals` either way, the change in the
//! quantity is taken by central difference, and the absolute changes are summed (the worst
//! case over all sign combinations, to first order). Half a unit of `output_decimals` is added
//! for the rounding of the published value itself.

use super::result::{Evaluated, Locus, PlotData, compare};
use super::{At, Check, Cx, Expectation, check_condition, is_flight_model};
use crate::checks::subject::Subject;
use crate::checks::tolerance::ToleranceKind;
use crate::inputs::yaml::InputError;
use cierva_model::analysis::bcar::Verdict;
use cierva_model::analysis::milne;
use cierva_model::analysis::modes::{self, Complex, Mode};
use cierva_model::{Element, LinearModel, ModeKind};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Which system a mode or BCAR check looks at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum System {
    /// The model itself.
    #[default]
    Full,
    /// `A11` on `[w q]` (seed 002 Eq. 11).
    ShortPeriod,
    /// The exact Schur complement on `[u theta Omega]` (seed 002 Eq. 12).
    Reduced,
    /// The closed form of seed 002 Eq. 13.
    Eq13,
}

/// Declares a linear kind's fields as written: its own, then those every check on a linear
/// model takes ([`LinearFields`]). Every field it does not declare is refused by name.
macro_rules! linear_spec {
    ($(#[$m:meta])* pub struct $name:ident { $($body:tt)* }) => {
        $(#[$m])*
        #[derive(Debug, Clone, serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            $($body)*
            /// On an aircraft or an external model: the condition it is linearised at.
            #[serde(default)]
            pub condition: Option<crate::inputs::condition::TrimRequest>,
            /// Derivatives set to these values before the check (a what-if variant).
            #[serde(default)]
            pub set: std::collections::BTreeMap<String, f64>,
            /// Zero every rotorspeed coupling derivative first (seed 002 Tables 2 and 5).
            #[serde(default)]
            pub without_rotorspeed_coupling: bool,
        }

        impl $name {
            /// The fields every check on a linear model takes.
            pub fn linear(&self) -> $crate::checks::linear::LinearFields {
                $crate::checks::linear::LinearFields {
                    condition: self.condition,
                    set: self.set.clone(),
                    without_rotorspeed_coupling: self.without_rotorspeed_coupling,
                }
            }
        }
    };
}
pub(crate) use linear_spec;

/// The fields every check on a linear model takes, as written.
#[derive(Debug, Clone, Default)]
pub struct LinearFields {
    pub condition: Option<crate::inputs::condition::TrimRequest>,
    pub set: BTreeMap<String, f64>,
    pub without_rotorspeed_coupling: bool,
}

/// The subjects checks on a linear model run on, in words.
pub const SUBJECTS: &str = "a linear model, or an aircraft linearised at the check's `condition`, or an external model's linear model there";

/// Whether a check on a linear model runs on `subject`.
pub fn runs_on(subject: &Subject) -> bool {
    matches!(
        subject,
        Subject::Linear { .. } | Subject::Aircraft { .. } | Subject::External(_)
    )
}

/// Where a check on a linear model takes its model, and how it modifies it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LinearSetup {
    /// On an aircraft: the condition it is linearised at (straight flight).
    pub condition: Option<crate::inputs::condition::TrimRequest>,
    /// Derivatives set to these values before the check (a what-if variant).
    pub set: BTreeMap<String, f64>,
    /// Zero every rotorspeed coupling derivative first (seed 002 Tables 2 and 5).
    pub without_rotorspeed_coupling: bool,
    /// On an aircraft: the model is what this set-up identifies from the aircraft linearised
    /// with its flapping states ([`crate::run::linearise::identified_in_band_cached`]).
    pub as_identified: Option<crate::ident::Setup>,
}

impl LinearSetup {
    /// Whether it is the model as it is at a flight condition (nothing set, cut or
    /// identified): a row of a series over a case's airspeeds ([`super::Evaluate::series`]).
    pub fn plain_at_a_condition(&self) -> bool {
        self.condition.is_some()
            && self.set.is_empty()
            && !self.without_rotorspeed_coupling
            && self.as_identified.is_none()
    }
}

/// Resolves the shared fields: a condition exactly on an aircraft, in straight flight; `set`
/// names derivatives of the model, with finite values.
pub fn resolve_setup(cx: &Cx, spec: &LinearFields) -> Result<LinearSetup, InputError> {
    match (is_flight_model(cx.subject), &spec.condition) {
        (true, None) => {
            return Err(cx.err(
                "",
                format!(
                    "a `{}` check on {} needs `condition` (it runs on the model linearised there)",
                    cx.kind.name(),
                    cx.subject.describe()
                ),
            ));
        }
        (true, Some(t)) => check_condition(cx, t, true)?,
        (false, Some(_)) => {
            return Err(cx.err(
                ".condition",
                "`condition` applies to a case whose model is an aircraft or an external model",
            ));
        }
        (false, None) => {}
    }
    for (name, v) in &spec.set {
        check_derivative(cx, name, ".set")?;
        if !v.is_finite() {
            return Err(cx.err(&format!(".set.{name}"), "must be finite"));
        }
    }
    Ok(LinearSetup {
        condition: spec.condition,
        set: spec.set.clone(),
        without_rotorspeed_coupling: spec.without_rotorspeed_coupling,
        as_identified: None,
    })
}

/// Where the report places a mode's check: among its system's eigenvalues, at its condition.
/// `bcar`: the check judges the mode by BCAR Section T.
pub fn placed_among_eigenvalues(
    system: System,
    setup: &LinearSetup,
    bcar: bool,
) -> super::Placed<'static> {
    super::Placed::Eigenvalues {
        system,
        condition: setup.condition,
        modified: !setup.set.is_empty() || setup.without_rotorspeed_coupling,
        bcar,
    }
}

/// What a check on a linear model adds to its case's snapshots: on an aircraft, its condition
/// trimmed, and the linear model there.
pub fn snapshotted(setup: &LinearSetup) -> Vec<super::Snapshotted<'static>> {
    setup
        .condition
        .map(|c| {
            vec![
                super::Snapshotted::Trims(vec![c]),
                super::Snapshotted::Linearised(c),
            ]
        })
        .unwrap_or_default()
}

/// Checks that `name` is a derivative of the check's model (the linearised aircraft's states
/// and controls on an aircraft).
pub fn check_derivative(cx: &Cx, name: &str, field: &str) -> Result<(), InputError> {
    let found = match cx.subject {
        Subject::Linear { model, .. } => model.derivative(name).map(|_| ()),
        _ => linearised_template().derivative(name).map(|_| ()),
    };
    found.map_err(|e| cx.err(field, e.to_string()))
}

/// A model with the linearised aircraft's states and controls, all zero (for checking names).
pub fn linearised_template() -> LinearModel {
    use cierva_model::aircraft::linearise::{CONTROLS, STATES};
    LinearModel::from_rows(
        STATES.iter().map(|s| s.to_string()).collect(),
        CONTROLS.iter().map(|s| s.to_string()).collect(),
        &vec![vec![0.0; STATES.len()]; STATES.len()],
        &vec![vec![0.0; CONTROLS.len()]; STATES.len()],
    )
    .expect("the linearised model's names are valid")
}

/// The quantities a check computes on one model.
pub struct Computed {
    pub values: Vec<(&'static str, f64)>,
    /// The eigenvalue of the selected mode (to follow it under perturbation).
    pub anchor: Option<Complex>,
    /// The BCAR verdict, where the check computes one.
    pub verdict: Option<Verdict>,
}

impl Computed {
    /// Values alone (no mode, no verdict).
    pub fn values(values: Vec<(&'static str, f64)>) -> Self {
        Self {
            values,
            anchor: None,
            verdict: None,
        }
    }

    /// One of its values, by name.
    pub fn get(&self, q: &str) -> Result<f64, String> {
        self.values
            .iter()
            .find(|(n, _)| *n == q)
            .map(|(_, v)| *v)
            .ok_or_else(|| {
                format!("`{q}` is not defined here (for example a period of a real mode)")
            })
    }
}

/// What a check on a linear model computes, beyond what all of them share.
pub trait OnLinear {
    fn setup(&self) -> &LinearSetup;
    /// The mode it looks at and in which system (mode and BCAR checks).
    fn mode(&self) -> Option<(ModeKind, System)> {
        None
    }
    /// Whether it looks at the longitudinal subsystem of a linearised aircraft.
    fn longitudinal(&self) -> bool {
        false
    }
    /// Corrections applied to the aircraft before it is linearised.
    fn corrections(&self) -> Option<&crate::inputs::corrections::CorrectionSet> {
        None
    }
    /// The expected BCAR verdict.
    fn verdict(&self) -> Option<Verdict> {
        None
    }
    /// Its quantities on `model` (as the check modified it). `anchor` is the nominal mode's
    /// eigenvalue when `model` is a perturbation of the nominal one; `unmodified` is the model
    /// before the check's modifications.
    fn compute(
        &self,
        model: &LinearModel,
        anchor: Option<Complex>,
        unmodified: &LinearModel,
        expectations: &[Expectation],
    ) -> Result<Computed, String>;
    /// A quantity of a flight model's linearisation that is not a value of the check's model
    /// (a derivative's components, its change under the check's corrections): `None` when `q`
    /// is computed by [`OnLinear::compute`].
    fn of_linearisation(&self, _q: &str, _at: &AtCondition<'_>) -> Option<Result<f64, String>> {
        None
    }
    /// On a flight model's linear model, the trivial predictors that need it (which loading
    /// does not build: a model is asked only when the check runs): the first that passes
    /// an expectation, as the refusal's reason. `own` is the eigenvalue of the mode the check
    /// selected (by continuity where the model does not classify it), which is no neighbour of
    /// itself. None by default.
    fn refused_on(
        &self,
        _model: &LinearModel,
        _own: Option<Complex>,
        _expectations: &[Expectation],
    ) -> Option<String> {
        None
    }
    /// Numbers that describe the result beyond its expectations (for known discrepancies).
    fn fingerprint(&self, _computed: &Computed) -> Vec<(String, f64)> {
        vec![]
    }
}

/// A flight model's linearisation at a check's condition, as a check's quantities beyond its
/// model's values ask it ([`OnLinear::of_linearisation`]).
pub struct AtCondition<'a> {
    /// The model with the check's corrections.
    pub model: &'a dyn crate::external::FlightModel,
    /// The model without them.
    pub uncorrected: &'a dyn crate::external::FlightModel,
    pub request: &'a crate::external::Request,
    /// `model`'s linear model at `request`.
    pub linear: &'a LinearModel,
}

impl AtCondition<'_> {
    /// A derivative's contributions by component ([`crate::external::FlightModel::components`]).
    pub fn breakdown(&self, derivative: &str) -> Result<Vec<(String, f64)>, String> {
        let e = self
            .linear
            .derivative(derivative)
            .map_err(|e| e.to_string())?;
        Ok(self
            .model
            .components(self.request)?
            .iter()
            .map(|(c, m)| (c.clone(), m.get(e)))
            .collect())
    }

    /// A derivative of the model without the check's corrections.
    pub fn uncorrected(&self, derivative: &str) -> Result<f64, String> {
        self.uncorrected
            .linear_model(self.request)?
            .derivative_value(derivative)
            .map_err(|e| e.to_string())
    }
}

/// Evaluates a check on a linear model, or on its case's flight model (cierva's aircraft or
/// another simulation, [`super::flight_model`]) linearised at its condition.
pub fn evaluate<K: OnLinear>(
    k: &K,
    at: &At,
    expectations: &[Expectation],
) -> Result<Evaluated, String> {
    if let Subject::Linear { model, .. } = at.subject {
        return on_model(k, model, expectations, None);
    }
    let (plain, loading) = super::flight_model(at.subject).ok_or(
        "a check on a linear model needs a linear model, an aircraft or an external model",
    )?;
    let condition = k
        .setup()
        .condition
        .ok_or("a check on a flight model's linear model needs a condition")?;
    let request = crate::external::Request::at(condition, loading);
    let corrected = crate::external::corrected_by(plain.as_ref(), k.corrections())?;
    let model = corrected.as_ref();
    let full = model.linear_model(&request)?;
    let linear = if let Some(setup) = k.setup().as_identified {
        model.identified_in_band(&request, setup)?
    } else if k.longitudinal() {
        longitudinal(&full)?
    } else {
        full.clone()
    };
    let at_condition = AtCondition {
        model,
        uncorrected: plain.as_ref(),
        request: &request,
        linear: &full,
    };
    let follow = || -> Result<LinearModel, String> {
        neighbour_for_continuity(at.siblings, condition, k.mode(), model, loading)?
            .ok_or_else(|| "no other airspeed of the case classifies it".to_string())
    };
    on_model(k, &linear, expectations, Some((&at_condition, &follow)))
}

/// The longitudinal subsystem of a model with cierva's names (as
/// `cierva_model::aircraft::linearise::Linearised::longitudinal` takes it).
fn longitudinal(model: &LinearModel) -> Result<LinearModel, String> {
    let sub = model
        .subsystem(&["u", "w", "q", "theta", "Omega"])
        .map_err(|e| e.to_string())?;
    let col = sub
        .controls()
        .iter()
        .position(|c| c == "eta_s")
        .ok_or("the model has no control `eta_s`")?;
    LinearModel::new(
        sub.states().to_vec(),
        vec!["eta_s".to_string()],
        sub.a().clone(),
        sub.b().columns(col, 1).into_owned(),
    )
    .map_err(|e| e.to_string())
}

/// A check on `model`; on a flight model's linear model (`flight`), with its linearisation and
/// where to follow an unclassified mode from (the nearest airspeed of the case that classifies
/// it, [`neighbour_for_continuity`]).
#[allow(clippy::type_complexity)]
fn on_model<K: OnLinear>(
    k: &K,
    model: &LinearModel,
    expectations: &[Expectation],
    flight: Option<(&AtCondition<'_>, &dyn Fn() -> Result<LinearModel, String>)>,
) -> Result<Evaluated, String> {
    let base = prepare(model, k.setup())?;
    let nominal = match (k.compute(&base, None, model, expectations), flight) {
        (Err(e), Some((_, follow))) if e.starts_with(UNCLASSIFIED) && k.setup().set.is_empty() => {
            let from = follow().map_err(|why| format!("{e}; and {why}"))?;
            k.compute(&base, None, &from, expectations)?
        }
        (other, _) => other?,
    };
    if flight.is_some()
        && let Some(reason) = k.refused_on(model, nominal.anchor, expectations)
    {
        return Err(format!(
            "refused when it ran (a flight model's modes come with its linear model): {reason}"
        ));
    }
    let mut out = Vec::new();
    for e in expectations {
        let value = match flight.and_then(|(lin, _)| k.of_linearisation(&e.quantity, lin)) {
            Some(v) => v?,
            None => nominal.get(&e.quantity)?,
        };
        out.push(compare(e, value, || {
            propagated_rounding(model, k, &nominal, expectations, e)
        })?);
    }
    Ok(Evaluated {
        verdict: verdict_pair(k.verdict(), &nominal)?,
        plot: modes_plot(model, &base, k, nominal.anchor),
        fingerprint: k.fingerprint(&nominal),
        ..Evaluated::of(out)
    })
}

/// The linearised model at the airspeed of the case (its `siblings`' conditions) nearest to
/// `here` (same climb, another airspeed) at which the check's mode is classified, if any: the
/// start of the continuation that names the mode at `here`.
///
/// Classification by participation can fail where modes couple (at 30 mph the VPM M16's pitch
/// oscillation takes roll and sideslip), while the mode is plainly there: followed by the
/// nearest eigenvalue along the straight path between the two linearisations, as a root locus
/// names its branches, it keeps the name it has at the neighbouring airspeed.
fn neighbour_for_continuity(
    siblings: &[Check],
    here: crate::inputs::condition::TrimRequest,
    mode: Option<(ModeKind, System)>,
    model: &dyn crate::external::FlightModel,
    loading: crate::inputs::condition::Loading,
) -> Result<Option<LinearModel>, String> {
    let Some((kind, system)) = mode else {
        return Ok(None);
    };
    let mut others: Vec<crate::inputs::condition::TrimRequest> = siblings
        .iter()
        .filter_map(Check::condition)
        .filter(|c| c.climb_m_s == here.climb_m_s && c.turn_rate_deg_s == 0.0)
        .filter(|c| c.airspeed_mph != here.airspeed_mph)
        .collect();
    others.sort_by(|a, b| {
        (a.airspeed_mph - here.airspeed_mph)
            .abs()
            .total_cmp(&(b.airspeed_mph - here.airspeed_mph).abs())
            .then(a.airspeed_mph.total_cmp(&b.airspeed_mph))
    });
    others.dedup();
    for request in others {
        let lin = model.linear_model(&crate::external::Request::at(request, loading))?;
        let sys = system_model(&lin, system)?;
        let analysis = modes::modes(&sys).map_err(|e| e.to_string())?;
        if analysis.of_kind(kind).count() == 1 {
            return Ok(Some(lin));
        }
    }
    Ok(None)
}

/// The eigenvalues of a mode or BCAR check's system (`model` as the check modified it), its
/// mode, and the root locus when the check sets one derivative of `unmodified`.
fn modes_plot<K: OnLinear>(
    unmodified: &LinearModel,
    model: &LinearModel,
    k: &K,
    selected: Option<Complex>,
) -> Option<PlotData> {
    let (_, system) = k.mode()?;
    let sys = system_model(model, system).ok()?;
    let analysis = modes::modes(&sys).ok()?;
    let setup = k.setup();
    let locus = match (setup.set.len(), setup.without_rotorspeed_coupling) {
        (1, false) => {
            let (name, &set) = setup.set.iter().next().expect("one");
            locus_of(unmodified, system, name, set)
        }
        _ => None,
    };
    Some(PlotData::Modes {
        eigenvalues: analysis.modes.iter().map(|m| m.eigenvalue).collect(),
        selected,
        locus,
    })
}

/// Points on a root locus.
const LOCUS_POINTS: usize = 41;

fn locus_of(model: &LinearModel, system: System, name: &str, set: f64) -> Option<Locus> {
    let e = model.derivative(name).ok()?;
    let nominal = model.derivative_value(name).ok()?;
    let (lo, hi) = (nominal.min(set), nominal.max(set));
    let pad = 0.25 * (hi - lo).max(1e-9);
    let values = cierva_model::analysis::locus::linspace(lo - pad, hi + pad, LOCUS_POINTS);
    let points = values
        .iter()
        .filter_map(|&v| {
            let m = model.with(e, v).ok()?;
            let sys = system_model(&m, system).ok()?;
            let a = modes::modes(&sys).ok()?;
            Some((v, a.modes.iter().map(|m| m.eigenvalue).collect()))
        })
        .collect();
    Some(Locus {
        derivative: name.to_string(),
        nominal,
        set,
        points,
    })
}

/// The expected and computed BCAR verdicts, if a verdict is expected.
fn verdict_pair(
    want: Option<Verdict>,
    nominal: &Computed,
) -> Result<Option<(Verdict, Verdict)>, String> {
    match (want, nominal.verdict) {
        (Some(want), Some(got)) => Ok(Some((want, got))),
        (Some(_), None) => Err("the mode is not oscillatory: BCAR Section T does not apply".into()),
        _ => Ok(None),
    }
}

/// The model after the check's modifications (`without_rotorspeed_coupling`, then `set`).
pub fn prepare(model: &LinearModel, setup: &LinearSetup) -> Result<LinearModel, String> {
    let mut m = if setup.without_rotorspeed_coupling {
        milne::without_rotorspeed_coupling(model).map_err(|e| e.to_string())?
    } else {
        model.clone()
    };
    for (name, value) in &setup.set {
        let e = m.derivative(name).map_err(|e| e.to_string())?;
        m = m.with(e, *value).map_err(|e| e.to_string())?;
    }
    Ok(m)
}

/// The system a mode or BCAR check looks at.
pub fn system_model(model: &LinearModel, system: System) -> Result<LinearModel, String> {
    match system {
        System::Full => Ok(model.clone()),
        System::ShortPeriod => milne::short_period(model).map_err(|e| e.to_string()),
        System::Reduced => milne::reduced(model).map_err(|e| e.to_string()),
        System::Eq13 => milne::eq13(model)
            .map(|e| e.model())
            .map_err(|e| e.to_string()),
    }
}

/// How the error for a mode that no eigenvalue is classified as begins.
const UNCLASSIFIED: &str = "no";

/// Steps of the path along which a mode is followed from the unmodified model.
const CONTINUATION_STEPS: usize = 50;

fn nearest(analysis: modes::ModalAnalysis, a: Complex) -> Result<Mode, String> {
    analysis
        .modes
        .into_iter()
        .min_by(|x, y| {
            let d = |m: &Mode| (m.eigenvalue.re - a.re).hypot(m.eigenvalue.im - a.im);
            d(x).total_cmp(&d(y))
        })
        .ok_or_else(|| "no modes".to_string())
}

/// Selects the mode `kind` of `system`.
///
/// * On a perturbed model (rounding propagation), the mode nearest to `anchor`, the nominal
///   mode's eigenvalue: classification can flip under perturbation, the mode cannot jump.
/// * Otherwise by its class. When the check modifies the model (`set`,
///   `without_rotorspeed_coupling`) and the modified mode is not classified unambiguously (a
///   mixed mode), it is followed by continuity from its class on the unmodified model, along
///   the straight path between the two models' matrices, as a root locus names its branches.
pub fn select_mode(
    model: &LinearModel,
    (kind, system): (ModeKind, System),
    anchor: Option<Complex>,
    unmodified: &LinearModel,
) -> Result<Mode, String> {
    let sys = system_model(model, system)?;
    let analysis = modes::modes(&sys).map_err(|e| e.to_string())?;
    if let Some(a) = anchor {
        return nearest(analysis, a);
    }
    let found: Vec<Mode> = analysis.of_kind(kind).cloned().collect();
    if found.len() != 1 && model != unmodified {
        let start = select_mode(unmodified, (kind, system), None, unmodified)?;
        let mut at = start.eigenvalue;
        let mut mode = start;
        for k in 1..=CONTINUATION_STEPS {
            let t = k as f64 / CONTINUATION_STEPS as f64;
            let m = LinearModel::new(
                model.states().to_vec(),
                model.controls().to_vec(),
                unmodified.a() * (1.0 - t) + model.a() * t,
                unmodified.b() * (1.0 - t) + model.b() * t,
            )
            .map_err(|e| e.to_string())?;
            let sys = system_model(&m, system)?;
            mode = nearest(modes::modes(&sys).map_err(|e| e.to_string())?, at)?;
            at = mode.eigenvalue;
        }
        return Ok(mode);
    }
    match found.len() {
        1 => Ok(found.into_iter().next().expect("one")),
        0 => Err(format!(
            "{UNCLASSIFIED} {} mode in the {system:?} system; its modes are: {}",
            kind.name(),
            analysis
                .modes
                .iter()
                .map(|m| format!("{} {:.4}", m.kind.name(), m.eigenvalue))
                .collect::<Vec<_>>()
                .join("; ")
        )),
        n => Err(format!(
            "{n} modes are classified {}: ambiguous",
            kind.name()
        )),
    }
}

const KINEMATIC: [&str; 3] = ["phi", "theta", "psi"];

/// First-order worst-case change of a quantity when the published matrix entries move by half
/// a unit in their last printed decimal (see the module docs). Entries that the check `set`s
/// are exact and are not moved.
pub fn propagated_rounding<K: OnLinear>(
    model: &LinearModel,
    k: &K,
    nominal: &Computed,
    expectations: &[Expectation],
    e: &Expectation,
) -> Result<f64, String> {
    let ToleranceKind::Rounding(r) = e.tolerance.kind else {
        return Ok(0.0);
    };
    let h = 0.5 * 10f64.powi(-(r.input_decimals as i32));
    let fixed: Vec<Element> = k
        .setup()
        .set
        .keys()
        .filter_map(|n| model.derivative(n).ok())
        .collect();
    let mut elements = Vec::new();
    for (i, s) in model.states().iter().enumerate() {
        if KINEMATIC.contains(&s.as_str()) {
            continue;
        }
        elements.extend((0..model.states().len()).map(|j| Element::A { row: i, col: j }));
        elements.extend((0..model.controls().len()).map(|j| Element::B { row: i, col: j }));
    }
    let mut total = 0.0;
    for el in elements.into_iter().filter(|el| !fixed.contains(el)) {
        let v0 = model.get(el);
        let side = |sign: f64| -> Result<f64, String> {
            let m = model.with(el, v0 + sign * h).map_err(|e| e.to_string())?;
            let prepared = prepare(&m, k.setup())?;
            k.compute(&prepared, nominal.anchor, &m, expectations)?
                .get(&e.quantity)
        };
        let (up, down) = (side(1.0)?, side(-1.0)?);
        total += 0.5 * (up - down).abs();
    }
    Ok(total + 0.5 * 10f64.powi(-(r.output_decimals as i32)))
}
