//! Flight models as case subjects: cierva's own aircraft, or another simulation.
//!
//! A [`FlightModel`] answers, at a flight condition and loading, what the checks on an aircraft
//! ask: its trim quantities (names from [`crate::inputs::quantity::TRIM`]; a model may give a subset),
//! its linear model (cierva's state and control names, those of
//! [`cierva_model::aircraft::linearise::STATES`] and `CONTROLS`)
//! and its response to a record's control changes. Each is optional: a model that does not
//! provide one says so, and a check that needs it is an error, never a pass.
//!
//! A model may **declare parameters** ([`FlightModel::parameters`]): corrections and estimated
//! physical inputs, each with its unit, nominal value and plausible range with the range's
//! source. Every [`Request`] carries values for any of them (the rest at their nominal values),
//! so that the fit, the retune and the sensitivity and uncertainty studies drive any model that
//! declares them (a study also asks a model for its refined self and where its answers start:
//! [`FlightModel::refinements`], [`FlightModel::starting_from`]), and a
//! value the model does not declare, or one outside its declared range, is refused
//! ([`check_values`]).
//!
//! cierva's own aircraft is one ([`CiervaAircraft`]: its parameters are the aircraft file's
//! physical parameters, [`crate::inputs::parameters::PARAMETERS`], with the file's `ranges:`).
//! Another simulation is a subject two ways:
//! - [`command`]: a program cierva runs once per request (the protocol `cierva-external/1`, or
//!   `/2` with parameters, `docs/external-models.md`);
//! - [`files`]: its outputs as files (a trim table, a linear model, a time history).

pub mod command;
pub mod files;
mod persistent;
pub mod rotor;
pub mod serve;

use crate::inputs::condition::Loading;
use crate::inputs::condition::TrimRequest;
use crate::inputs::controls::ControlTable;
use crate::inputs::ranges::Range;
use crate::run::replay::{Replayed, Simulation};
use cierva_model::LinearModel;
use serde::Serialize;
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Values for some of a model's declared parameters, by name, in their declared units.
pub type Values = BTreeMap<String, f64>;

/// What a model is asked at: a flight condition, a loading, and values for any of its declared
/// parameters (those not given stay at their nominal values), and where its answer may start
/// (`start`: none, the model's own start). Plain data: two requests are the same question
/// when they are equal.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub condition: TrimRequest,
    pub loading: Loading,
    pub parameters: Values,
    /// Where an earlier answer near this one ended ([`FlightModel::start_after`]), for the
    /// model to start from: a fit's trial steps and finite differences start from its
    /// iterate's answers.
    pub start: Option<Start>,
}

impl Request {
    /// At `condition` and `loading`, every parameter at its nominal value.
    pub fn at(condition: TrimRequest, loading: Loading) -> Self {
        Self {
            condition,
            loading,
            parameters: Values::new(),
            start: None,
        }
    }

    /// The same request started from `start`.
    pub fn starting_at(self, start: Option<Start>) -> Self {
        Self { start, ..self }
    }

    /// The same request with `name` set to `value`.
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.parameters.insert(name.to_string(), value);
        self
    }
}

/// Where a model's answer ended, for a request near it to start from
/// ([`FlightModel::start_after`], [`Request::start`]): a value the model made, opaque to
/// cierva, handed back unchanged. cierva's aircraft's is its trim's unknowns and last Jacobian
/// ([`cierva_model::aircraft::trim::StartPoint`]); a model behind the command protocol gives
/// its own as an answer's `start` and reads it back from a request's.
///
/// A start saves a model iterations; the answer is the one it finds from that start, to its
/// convergence tolerance. cierva asks the same requests with the same starts whichever process
/// answers them, so the same model gives the same answers through the protocol as in
/// process.
#[derive(Clone, PartialEq)]
pub struct Start(pub Arc<serde_json::Value>);

impl Start {
    /// The start as its compact JSON text (what a memo of answers keys it by).
    pub fn text(&self) -> String {
        self.0.to_string()
    }
}

/// Which of a model's answers to a request a start is asked of ([`FlightModel::start_after`]):
/// a model may end each its own way (cierva's aircraft ends all three at the same trim).
#[derive(Debug, Clone, PartialEq)]
pub enum AnswerOf {
    Trim,
    LinearModel,
    /// Its frequency responses at these frequencies, Hz.
    Responses(Vec<f64>),
}

impl std::fmt::Debug for Start {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Start({})", self.0)
    }
}

/// What a model of a rotor in a wind tunnel is asked: a tunnel condition and values for any of
/// its declared parameters (those not given stay at their nominal values).
#[derive(Debug, Clone, PartialEq)]
pub struct TunnelRequest {
    pub tunnel: crate::inputs::condition::TunnelSpec,
    pub parameters: Values,
}

/// A parameter a model declares: what a study may move, in what unit, from what nominal value,
/// and within what plausible range (with the range's source; `None` where the model states no
/// range, which a study that samples or bounds the parameter refuses).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Parameter {
    pub name: String,
    pub unit: String,
    pub meaning: String,
    pub nominal: f64,
    pub range: Option<Range>,
    /// An empirical correction (what a fit tunes), not an estimated physical input: an
    /// uncertainty study samples the estimated inputs and leaves corrections at their values.
    pub correction: bool,
}

/// The parameters a study moves when it names none: those declared with a plausible range, by
/// name (a case's `sensitivity:` block and `cierva sensitivity` alike).
pub fn ranged_names(declared: &[Parameter]) -> Vec<String> {
    let mut ranged: Vec<String> = declared
        .iter()
        .filter(|p| p.range.is_some())
        .map(|p| p.name.clone())
        .collect();
    ranged.sort();
    ranged
}

/// Checks values against the parameters a model declares: each one declared (an unknown name
/// gets the nearest declared one), finite, and inside its declared range.
pub fn check_values(model: &str, declared: &[Parameter], values: &Values) -> Result<(), String> {
    for (name, &v) in values {
        let Some(p) = declared.iter().find(|p| &p.name == name) else {
            if declared.is_empty() {
                return Err(format!(
                    "{model} declares no parameters, so `{name}` cannot be set"
                ));
            }
            let names: Vec<String> = declared.iter().map(|p| p.name.clone()).collect();
            let hint = crate::inputs::yaml::nearest(name, &names)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(format!(
                "`{name}` is not a parameter {model} declares{hint}; it declares [{}]",
                names.join(", ")
            ));
        };
        if !v.is_finite() {
            return Err(format!("`{name}` = {v} is not a finite value"));
        }
        if let Some(r) = &p.range
            && !(r.lower..=r.upper).contains(&v)
        {
            return Err(format!(
                "`{name}` = {v} {} is outside the range {model} declares for it, [{}, {}] \
                 ({})",
                p.unit, r.lower, r.upper, r.source
            ));
        }
    }
    Ok(())
}

/// Named values (a trim's quantities), as the checks compare them.
pub type Quantities = Vec<(&'static str, f64)>;

/// Control changes from trim to fly: the table, and the times the response is wanted at
/// (`k * sample_s`, `k = 0..=samples`); and the record's first sample of each response it
/// carries (changes from trim, named as [`crate::run::replay::SIGNALS`]), where a model may
/// start its flight (cierva's own starts from its periodic trim, as the records it flies start
/// in trim).
#[derive(Debug, Clone, PartialEq)]
pub struct ControlChanges {
    pub table: ControlTable,
    pub sample_s: f64,
    pub samples: usize,
    pub initial_state: BTreeMap<String, f64>,
}

/// What a model does not provide, as the error a check that needs it gives.
pub fn not_provided(model: &str, what: &str) -> String {
    format!("{model} does not provide {what}")
}

/// A flight model as a case's subject (see the module docs).
pub trait FlightModel: std::fmt::Debug + Send + Sync {
    /// The model in words, for errors ("the command `python3 model.py`").
    fn describe(&self) -> String;

    /// The parameters it declares (none by default): what a request may set.
    fn parameters(&self) -> Result<Vec<Parameter>, String> {
        Ok(Vec::new())
    }

    /// What it answers, by the protocol's requests: what `cierva serve` says of it in
    /// `describe` (a flight model's, [`command::Compute::FLIGHT`], by default).
    fn computes(&self) -> Vec<command::Compute> {
        command::Compute::FLIGHT.to_vec()
    }

    /// Its trim at the request: quantities named as in [`crate::inputs::quantity::TRIM`] (a
    /// subset).
    fn trim(&self, _request: &Request) -> Result<Quantities, String> {
        Err(not_provided(&self.describe(), "a trim"))
    }

    /// Its linear model about the trim at the request (straight flight), with cierva's state
    /// and control names and units.
    fn linear_model(&self, _request: &Request) -> Result<LinearModel, String> {
        Err(not_provided(&self.describe(), "a linear model"))
    }

    /// Its trim and its linear model about it, at one request: a model that finds both from
    /// one trim says so here (cierva's aircraft does).
    fn trim_and_linear_model(
        &self,
        request: &Request,
    ) -> Result<(Quantities, LinearModel), String> {
        Ok((self.trim(request)?, self.linear_model(request)?))
    }

    /// Its response (changes from the trim at the request's condition) to `controls`, at the
    /// times they ask for: every response of [`crate::run::replay::SIGNALS`] it computes (an
    /// empty series for one it does not).
    fn time_history(
        &self,
        _request: &Request,
        _controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        Err(not_provided(&self.describe(), "a time history"))
    }

    /// Every state's response to every control about its trim at the request, at each of
    /// `frequencies_hz`: by default from its linear model's A and B
    /// ([`crate::run::responses::Responses::of_linear_model`]); a model with a
    /// better linearisation for it says so here (cierva's aircraft with a teetering rotor: with
    /// its flapping states, by harmonic balance).
    fn responses(
        &self,
        request: &Request,
        frequencies_hz: &[f64],
    ) -> Result<crate::run::responses::Responses, String> {
        crate::run::responses::Responses::of_linear_model(
            &self.linear_model(request)?,
            frequencies_hz,
            crate::run::responses::from_a_and_b(&self.describe()),
        )
    }

    /// Its linear model at the request split by component (rotor, propeller, airframe...),
    /// the parts adding up to [`FlightModel::linear_model`]: what a derivative check's
    /// components compare.
    fn components(&self, _request: &Request) -> Result<Vec<(String, LinearModel)>, String> {
        Err(not_provided(
            &self.describe(),
            "its linear model split by component",
        ))
    }

    /// Its rotor's autorotation in a wind tunnel at the request's condition: the equilibrium's
    /// quantities, or no equilibrium there (cierva's isolated rotor, NACA TR 515 and TR 487).
    fn autorotation(
        &self,
        _request: &TunnelRequest,
    ) -> Result<crate::run::autorotation::Autorotated, String> {
        Err(not_provided(
            &self.describe(),
            "an autorotation in a tunnel",
        ))
    }

    /// The derivatives `setup` identifies from its linearisation with its rotor's flapping
    /// states over the set-up's band: what the identification of a flight of the model should
    /// find (a derivative check's `as_identified`).
    fn identified_in_band(
        &self,
        _request: &Request,
        _setup: crate::ident::Setup,
    ) -> Result<LinearModel, String> {
        Err(not_provided(
            &self.describe(),
            "a linearisation with its rotor's flapping states (which `as_identified` identifies from)",
        ))
    }

    /// The model with a check's corrections applied, where it applies them its own way
    /// (cierva's aircraft takes every correction its file has); `None`, the default: it takes
    /// them as values of the parameters it declares ([`corrected`]).
    fn corrected<'s>(
        &'s self,
        _corrections: &crate::inputs::corrections::CorrectionSet,
    ) -> Result<Option<Box<dyn FlightModel + 's>>, String> {
        Ok(None)
    }

    /// Whether the model can be asked at `loading`, or why not (cierva's aircraft: a mass above
    /// its stated maximum all-up mass); any loading by default. What a check asks of its
    /// inputs' loadings when it loads (a trim point's mass).
    fn check_loading(&self, _loading: &Loading) -> Result<(), String> {
        Ok(())
    }

    /// The model whose answers with parameter values start from its answer with `values` at
    /// the same condition and loading (a nearby point's: a sampled study's `A_B^(i)` point
    /// starts from its row of `A`), where it finds an answer by iterating from a start
    /// (cierva's aircraft: its trims). `None`, the default: it answers as it does.
    fn starting_from(&self, _values: &Values) -> Option<Arc<dyn FlightModel>> {
        None
    }

    /// Where its answer `of` the request ended, once it has given it, for a request near it to
    /// start from ([`Request::start`]): what a fit's trial steps and finite differences start
    /// from, its iterate's answers. `None`, the default: it gives none, and every request
    /// starts where the model starts it.
    fn start_after(&self, _request: &Request, _of: &AnswerOf) -> Option<Start> {
        None
    }

    /// Its discretisation parameters, each refined alone ([`Refinement`]): what an uncertainty
    /// study's numerical uncertainty comes from, a grid convergence index per parameter. A
    /// refined model that refines the same parameter again gives the study a third level, and
    /// with it the observed order. Empty, the default: no grid study.
    fn refinements(&self) -> Vec<Refinement> {
        Vec::new()
    }

    /// Forgets what it remembers of its answers with these parameter values (a study's point,
    /// once its checks have run), so that thousands of points do not fill the memory; nothing
    /// by default.
    fn forget(&self, _values: &Values) {}

    /// The model flown by another of its simulations, where it has more than one (cierva's
    /// aircraft: the full blade model at an azimuth step, `azimuth_step_rad` (default its
    /// file's), or the linear model): what a `time_history` check's `simulation` and
    /// `azimuth_step_deg` choose. `None`, the default: it has one simulation, flown as it is.
    fn simulated_by<'s>(
        &'s self,
        _simulation: Simulation,
        _azimuth_step_rad: Option<f64>,
    ) -> Option<Box<dyn FlightModel + 's>> {
        None
    }
}

/// `model` with a check's corrections applied: its own way ([`FlightModel::corrected`]), or
/// as values of the parameters it declares (the set's `parameters:`, checked against them).
pub fn corrected<'s>(
    model: &'s dyn FlightModel,
    corrections: &crate::inputs::corrections::CorrectionSet,
) -> Result<Box<dyn FlightModel + 's>, String> {
    if let Some(own) = model.corrected(corrections)? {
        return Ok(own);
    }
    let only_declared = crate::inputs::corrections::CorrectionSet {
        parameters: corrections.parameters.clone(),
        ..Default::default()
    };
    if *corrections != only_declared {
        return Err(format!(
            "{} takes corrections as values of the parameters it declares (`parameters:` of \
             the corrections), not as {}",
            model.describe(),
            corrections.describe()
        ));
    }
    check_values(
        &model.describe(),
        &model.parameters()?,
        &corrections.parameters,
    )?;
    Ok(Box::new(WithValues {
        model,
        values: corrections.parameters.clone(),
    }))
}

/// `model` with a check's corrections where it has any ([`corrected`]), itself otherwise.
pub fn corrected_by<'s>(
    model: &'s dyn FlightModel,
    corrections: Option<&crate::inputs::corrections::CorrectionSet>,
) -> Result<Box<dyn FlightModel + 's>, String> {
    match corrections {
        Some(c) => corrected(model, c),
        None => Ok(Box::new(model)),
    }
}

/// [`CiervaAircraft`]'s linearisations with parameter values (or started elsewhere), by file,
/// values, condition and loading ([`CiervaAircraft::key_of`]).
static WITH_VALUES: crate::run::memo::Memo<crate::run::linearise::Linearisation> =
    crate::run::memo::Memo::bounded(MEMO_LIMIT);

/// How many trims (and as many linearisations) with parameter values [`CiervaAircraft`]
/// remembers before it forgets them all (each is a function of its key, found again the same
/// when asked again): a few fits' worth of conditions and steps. A study forgets each point's
/// once its checks have run ([`FlightModel::forget`]); a served aircraft (`cierva serve`) is
/// never told to, and this bounds its memory.
const MEMO_LIMIT: usize = 2048;

/// [`CiervaAircraft`]'s trims with parameter values (or started elsewhere), keyed as
/// [`WITH_VALUES`] ([`CiervaAircraft::key_of_request`]).
static TRIMMED_WITH_VALUES: crate::run::memo::Memo<cierva_model::aircraft::trim::Trim> =
    crate::run::memo::Memo::bounded(MEMO_LIMIT);

/// The warm start a [`Start`] describes, if it is one of cierva's aircraft's
/// ([`cierva_model::aircraft::trim::StartPoint`]); an error that says why not.
fn start_of(start: &Start) -> Result<cierva_model::aircraft::trim::WarmStart, String> {
    let point: cierva_model::aircraft::trim::StartPoint =
        serde_json::from_value((*start.0).clone()).map_err(|e| {
            format!("the request's `start` is not a start cierva's aircraft gave: {e}")
        })?;
    cierva_model::aircraft::trim::WarmStart::from_point(&point)
        .map_err(|e| format!("the request's `start` is not a start of a trim: {e}"))
}

/// `values` set on one of cierva's own files: each physical parameter by `set_physical` (`None`
/// for a name it does not have), and each correction (`corrections.<name>`) into the set
/// returned, for the caller to apply; a name neither takes is an error naming `model`.
pub(crate) fn set_values(
    model: &str,
    values: &Values,
    mut set_physical: impl FnMut(&str, f64) -> Option<()>,
) -> Result<crate::inputs::corrections::CorrectionSet, String> {
    let mut corrections = crate::inputs::corrections::CorrectionSet::default();
    for (name, &v) in values {
        let set = match name.strip_prefix("corrections.") {
            Some(c) => corrections.set_named(c, v),
            None => set_physical(name, v),
        };
        set.ok_or_else(|| format!("`{name}` cannot be set on {model}"))?;
    }
    Ok(corrections)
}

/// What cierva's own file declares: each of `physical` it has (`value` gives its value, `None`
/// where it has none), then each correction `now` gives as `corrections.<name>`
/// ([`crate::inputs::corrections::CORRECTIONS`]); each with the file's `ranges:` entry where it
/// gives one.
pub(crate) fn declared<'p>(
    physical: impl Iterator<Item = &'p crate::inputs::parameters::ParameterInfo>,
    value: impl Fn(&str) -> Option<f64>,
    now: &crate::inputs::corrections::CorrectionSet,
    ranges: &BTreeMap<String, Range>,
) -> Vec<Parameter> {
    let physical = physical.filter_map(|p| {
        Some(Parameter {
            nominal: value(p.name)?,
            name: p.name.to_string(),
            unit: p.unit.to_string(),
            meaning: p.meaning.to_string(),
            range: ranges.get(p.name).cloned(),
            correction: false,
        })
    });
    let corrections =
        crate::inputs::corrections::CORRECTIONS
            .iter()
            .filter_map(|(name, unit, meaning)| {
                let full = format!("corrections.{name}");
                Some(Parameter {
                    nominal: now.get_named(name)?,
                    range: ranges.get(&full).cloned(),
                    name: full,
                    unit: unit.to_string(),
                    meaning: meaning.to_string(),
                    correction: true,
                })
            });
    physical.chain(corrections).collect()
}

/// The levels beyond the nominal that a grid study refines a parameter to, where the model
/// refines it again: three levels in all, which give the observed order
/// (`crate::uncertainty::numerics`).
pub const GRID_LEVELS: usize = 2;

/// One discretisation parameter of a model refined alone ([`FlightModel::refinements`]).
#[derive(Clone)]
pub struct Refinement {
    /// The parameter, in words and the same at every level ("main rotor azimuth step"): a
    /// refined model's refinement of the same name is the next level.
    pub parameter: String,
    /// Its value before and after, in words ("5.000 -> 2.500 deg").
    pub words: String,
    /// The refinement ratio `r > 1`: 2 for a step halved or elements doubled, 10 for a
    /// tolerance a tenth.
    pub ratio: f64,
    /// The order `p` at which the error falls with the parameter in theory (4 for a
    /// fourth-order Runge-Kutta step, 2 for midpoint sums over elements, 1 for an iteration's
    /// tolerance, whose error is at most of its order).
    pub formal_order: f64,
    /// The model with this parameter refined and the others as they were.
    pub model: Arc<dyn FlightModel>,
}

/// cierva's own aircraft at a loading, flown by `simulation` at `azimuth_step_rad` (the full
/// blade model's step).
#[derive(Debug, Clone)]
pub struct CiervaAircraft<'a> {
    pub file: Cow<'a, crate::inputs::aircraft::AircraftFile>,
    pub simulation: Simulation,
    pub azimuth_step_rad: f64,
    /// Where a trim with parameter values (and any trim of a refined aircraft) starts: the
    /// trim of this file with these values at the request's condition and loading
    /// ([`FlightModel::starting_from`], [`FlightModel::refinements`]); `None`: the file's own trim.
    pub starts_from: Option<(Arc<crate::inputs::aircraft::AircraftFile>, Values)>,
}

impl<'a> CiervaAircraft<'a> {
    /// The aircraft, flown by the full blade model at its file's azimuth step.
    pub fn new(file: &'a crate::inputs::aircraft::AircraftFile) -> Self {
        Self {
            file: Cow::Borrowed(file),
            simulation: Simulation::FullBlade,
            azimuth_step_rad: file.aircraft.main_rotor.numerics.azimuth_step_rad,
            starts_from: None,
        }
    }

    /// The aircraft, owned: a model a study can share ([`Arc<dyn FlightModel>`]).
    pub fn owned(file: crate::inputs::aircraft::AircraftFile) -> CiervaAircraft<'static> {
        CiervaAircraft {
            azimuth_step_rad: file.aircraft.main_rotor.numerics.azimuth_step_rad,
            file: Cow::Owned(file),
            simulation: Simulation::FullBlade,
            starts_from: None,
        }
    }
}

impl CiervaAircraft<'_> {
    /// The aircraft file with the request's parameter values set (the file itself where it
    /// sets none), its loading checked first ([`FlightModel::check_loading`]): each value a
    /// physical parameter the aircraft has or one of its corrections (`corrections.<name>`,
    /// [`crate::inputs::corrections::CORRECTIONS`]), the aircraft checked after.
    fn with_values(
        &self,
        request: &Request,
    ) -> Result<Cow<'_, crate::inputs::aircraft::AircraftFile>, String> {
        self.check_loading(&request.loading)?;
        let values = &request.parameters;
        if values.is_empty() {
            return Ok(Cow::Borrowed(&*self.file));
        }
        check_values(&self.describe(), &self.parameters()?, values)?;
        let mut f = self.file.as_ref().clone();
        let corrections = set_values(&self.describe(), values, |name, v| {
            crate::inputs::parameters::set_parameter(&mut f.aircraft, name, v)
        })?;
        corrections
            .apply_to_aircraft(&mut f.aircraft)
            .map_err(|e| {
                format!(
                    "{} with {}: {e}",
                    self.describe(),
                    values
                        .iter()
                        .map(|(n, v)| format!("{n} = {v}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })?;
        Ok(Cow::Owned(f))
    }

    /// Where a trim of the file with a request's values starts: the file's own trim at the
    /// request's condition and loading (remembered), so that a request's answer does not depend
    /// on which requests came before it or on which process answers it (`cierva serve`); or,
    /// where the model was made to start elsewhere ([`Self::starts_from`]), that file's trim
    /// with its values (remembered: a study's row of `A`, found before its `A_B^(i)` points).
    /// A request's own `start` comes first: a start this aircraft gave
    /// ([`FlightModel::start_after`]), or an error that says why it is not one.
    fn start(
        &self,
        request: &Request,
    ) -> Result<Option<cierva_model::aircraft::trim::WarmStart>, String> {
        if let Some(s) = &request.start {
            return start_of(s).map(Some);
        }
        Ok(self.start_elsewhere(request))
    }

    /// [`Self::start`] for a request without its own.
    fn start_elsewhere(
        &self,
        request: &Request,
    ) -> Option<cierva_model::aircraft::trim::WarmStart> {
        let (c, l) = (request.condition, request.loading);
        let Some((file, values)) = &self.starts_from else {
            return crate::run::trim::trim_cached(&self.file, c, l)
                .ok()
                .map(|t| t.warm_start.clone());
        };
        if values.is_empty() {
            return crate::run::trim::trim_cached(file, c, l)
                .ok()
                .map(|t| t.warm_start.clone());
        }
        let from = CiervaAircraft {
            file: Cow::Borrowed(&**file),
            starts_from: None,
            ..self.clone()
        };
        let at = Request {
            parameters: values.clone(),
            start: None,
            ..request.clone()
        };
        from.linearised(&at)
            .ok()
            .map(|(_, l)| l.0.warm_start.clone())
    }

    /// The memo key of the file with `values` (every request's with them starts with it):
    /// what [`FlightModel::forget`] forgets.
    fn key_of(&self, values: &Values) -> String {
        format!("{}|{values:?}|", self.file.path.display())
    }

    /// The memo key of a request: its file and values ([`Self::key_of`]), condition, loading,
    /// start, and where the model was made to start elsewhere ([`Self::starts_from`]): an
    /// answer is a function of its key.
    fn key_of_request(&self, request: &Request) -> String {
        let elsewhere = self.starts_from.as_ref().map_or(String::new(), |(f, v)| {
            format!("{}|{v:?}", f.path.display())
        });
        format!(
            "{}{:?}|{:?}|{}|{elsewhere}",
            self.key_of(&request.parameters),
            request.condition,
            request.loading,
            request.start.as_ref().map_or(String::new(), Start::text),
        )
    }

    /// Whether the request is the file's own question (no values, no start of its own or
    /// elsewhere): answered from the run's shared memo of the file's trims.
    fn plain(&self, request: &Request) -> bool {
        request.parameters.is_empty() && request.start.is_none() && self.starts_from.is_none()
    }

    /// The trim of the file with the request's values from [`Self::start`], remembered as
    /// [`Self::linearised`] is (a fit's trim targets, and where its next trims start).
    fn trimmed(
        &self,
        request: &Request,
    ) -> Result<
        (
            Cow<'_, crate::inputs::aircraft::AircraftFile>,
            Arc<cierva_model::aircraft::trim::Trim>,
        ),
        String,
    > {
        let file = self.with_values(request)?;
        let (c, l) = (request.condition, request.loading);
        if self.plain(request) {
            let t = crate::run::trim::trim_cached(&file, c, l)?;
            return Ok((file, t));
        }
        let start = self.start(request)?;
        let t = TRIMMED_WITH_VALUES.get_or(self.key_of_request(request), || {
            crate::run::trim::run_trim_from(&file.aircraft, c, l, start.as_ref())
                .map_err(|e| e.to_string())
        })?;
        Ok((file, t))
    }

    /// The file with the request's values, trimmed and linearised at it: remembered per file,
    /// values, condition and loading (a case's checks at one condition share it, a study's
    /// sample as the nominal aircraft), each trim with values started from [`Self::start`].
    #[allow(clippy::type_complexity)]
    fn linearised(
        &self,
        request: &Request,
    ) -> Result<
        (
            Cow<'_, crate::inputs::aircraft::AircraftFile>,
            Arc<crate::run::linearise::Linearisation>,
        ),
        String,
    > {
        let (c, l) = (request.condition, request.loading);
        let file = self.with_values(request)?;
        if self.plain(request) {
            let both = crate::run::linearise::linearise_cached(&file, c, l)?;
            return Ok((file, both));
        }
        let start = self.start(request)?;
        let both = WITH_VALUES.get_or(self.key_of_request(request), || {
            crate::run::linearise::run_linearise_from(&file.aircraft, c, l, start.as_ref())
                .map_err(|e| format!("at {} mph: {e}", c.airspeed_mph))
        })?;
        Ok((file, both))
    }
}

impl FlightModel for CiervaAircraft<'_> {
    fn describe(&self) -> String {
        format!("the aircraft {}", self.file.path.display())
    }

    /// Every physical parameter of [`crate::inputs::parameters::PARAMETERS`] the aircraft has,
    /// at the file's value, and every correction as `corrections.<name>`
    /// ([`crate::inputs::corrections::CORRECTIONS`]); each with the file's `ranges:` entry
    /// where it gives one.
    fn parameters(&self) -> Result<Vec<Parameter>, String> {
        let a = &self.file.aircraft;
        let physical = crate::inputs::parameters::PARAMETERS
            .iter()
            .filter(|p| !p.name.starts_with("corrections."));
        Ok(declared(
            physical,
            |name| crate::inputs::parameters::parameter(a, name),
            &crate::inputs::corrections::CorrectionSet::of_aircraft(a),
            &self.file.ranges,
        ))
    }

    fn trim(&self, request: &Request) -> Result<Quantities, String> {
        let (file, t) = self.trimmed(request)?;
        Ok(trim_quantities_of(&file.aircraft, request.loading, &t))
    }

    /// Its trim's end as plain numbers ([`cierva_model::aircraft::trim::StartPoint`]), the
    /// same whichever answer it is of (each is at the request's one trim): the linearisation's
    /// trim where the request was linearised, else its trim (remembered, or found now). None
    /// where the point would not read back as a start (a number not finite).
    fn start_after(&self, request: &Request, _of: &AnswerOf) -> Option<Start> {
        let key = self.key_of_request(request);
        let trim = match WITH_VALUES.get(&key).and_then(Result::ok) {
            Some(both) if !self.plain(request) => both.0.warm_start.clone(),
            _ => self.trimmed(request).ok()?.1.warm_start.clone(),
        };
        let point = trim.point();
        cierva_model::aircraft::trim::WarmStart::from_point(&point).ok()?;
        serde_json::to_value(point).ok().map(|v| Start(Arc::new(v)))
    }

    fn linear_model(&self, request: &Request) -> Result<LinearModel, String> {
        Ok(self.trim_and_linear_model(request)?.1)
    }

    /// One trim and its linearisation: remembered per file, condition and loading where the
    /// request sets no parameter (a case's checks at one condition share it).
    fn trim_and_linear_model(
        &self,
        request: &Request,
    ) -> Result<(Quantities, LinearModel), String> {
        let (file, both) = self.linearised(request)?;
        Ok((
            trim_quantities_of(&file.aircraft, request.loading, &both.0),
            both.1.model.clone(),
        ))
    }

    /// [`crate::run::responses::aircraft_responses`] at its trim for the request.
    fn responses(
        &self,
        request: &Request,
        frequencies_hz: &[f64],
    ) -> Result<crate::run::responses::Responses, String> {
        if request.parameters.is_empty() && request.start.is_none() {
            let (file, both) = self.linearised(request)?;
            return crate::run::responses::aircraft_responses(
                &file.aircraft,
                request.loading,
                &both.0,
                || Ok(both.1.model.clone()),
                frequencies_hz,
            );
        }
        // With values: the trim alone where the responses need no quasi-static linearisation
        // (a teetering rotor's come with its flapping states).
        let (c, l) = (request.condition, request.loading);
        let (file, trim) = self
            .trimmed(request)
            .map_err(|e| format!("at {} mph: {e}", c.airspeed_mph))?;
        let start = self.start(request)?;
        crate::run::responses::aircraft_responses(
            &file.aircraft,
            l,
            &trim,
            || {
                crate::run::linearise::run_linearise_from(&file.aircraft, c, l, start.as_ref())
                    .map(|(_, lin)| lin.model)
                    .map_err(|e| format!("at {} mph: {e}", c.airspeed_mph))
            },
            frequencies_hz,
        )
    }

    /// The linearisation's components ([`cierva_model::aircraft::linearise::COMPONENTS`]).
    fn components(&self, request: &Request) -> Result<Vec<(String, LinearModel)>, String> {
        Ok(self.linearised(request)?.1.1.components.clone())
    }

    /// [`crate::run::linearise::identified_in_band_cached`] where the request sets no
    /// parameter; from the linearisation with the values otherwise.
    fn identified_in_band(
        &self,
        request: &Request,
        setup: crate::ident::Setup,
    ) -> Result<LinearModel, String> {
        let (c, l) = (request.condition, request.loading);
        if request.parameters.is_empty() && self.starts_from.is_none() {
            self.check_loading(&l)?;
            return Ok(
                crate::run::linearise::identified_in_band_cached(&self.file, c, l, setup)?
                    .as_ref()
                    .clone(),
            );
        }
        let (file, both) = self.linearised(request)?;
        crate::run::linearise::identified_at(&file.aircraft, &both.0, l, setup)
    }

    /// The aircraft file with the corrections set ([`crate::inputs::aircraft::AircraftFile::with_corrections`]).
    fn corrected<'s>(
        &'s self,
        corrections: &crate::inputs::corrections::CorrectionSet,
    ) -> Result<Option<Box<dyn FlightModel + 's>>, String> {
        let file = self.file.with_corrections(corrections)?;
        Ok(Some(Box::new(CiervaAircraft {
            file: Cow::Owned(file),
            ..self.clone()
        })))
    }

    /// A mass above the aircraft's stated maximum all-up mass is refused.
    fn check_loading(&self, loading: &Loading) -> Result<(), String> {
        loading.mass_kg.map_or(Ok(()), |m| self.file.check_mass(m))
    }

    /// The aircraft flown by `simulation`, at `azimuth_step_rad` or its file's step.
    fn simulated_by<'s>(
        &'s self,
        simulation: Simulation,
        azimuth_step_rad: Option<f64>,
    ) -> Option<Box<dyn FlightModel + 's>> {
        Some(Box::new(CiervaAircraft {
            file: Cow::Borrowed(&*self.file),
            simulation,
            azimuth_step_rad: azimuth_step_rad
                .unwrap_or(self.file.aircraft.main_rotor.numerics.azimuth_step_rad),
            starts_from: self.starts_from.clone(),
        }))
    }

    /// The aircraft whose trims with values start from its trim with `values`.
    fn starting_from(&self, values: &Values) -> Option<Arc<dyn FlightModel>> {
        let file = Arc::new(self.file.as_ref().clone());
        Some(Arc::new(CiervaAircraft {
            file: Cow::Owned(file.as_ref().clone()),
            simulation: self.simulation,
            azimuth_step_rad: self.azimuth_step_rad,
            starts_from: Some((file, values.clone())),
        }))
    }

    /// Each alone: the main rotor's azimuth step halved (the trim's and a simulation's; its
    /// blade is integrated by fourth-order Runge-Kutta), the main rotor's and the propeller's
    /// blade elements doubled (midpoint sums), and the periodicity tolerance a tenth. Each
    /// refined trim starts from the aircraft's own (the same unknowns, to a finer tolerance).
    fn refinements(&self) -> Vec<Refinement> {
        let file = self.file.as_ref();
        let main = &file.aircraft.main_rotor;
        let propeller = &file.aircraft.propeller.propeller.rotor;
        let step_deg = main.numerics.azimuth_step_rad.to_degrees();
        // Where every refined trim starts: this aircraft's, shared by the four.
        let start = Arc::new(file.clone());
        let refined =
            |tag: &str, change: &dyn Fn(&mut crate::inputs::aircraft::AircraftFile), step: f64| {
                let mut f = file.clone();
                change(&mut f);
                f.path = format!("{}#{tag}", f.path.display()).into();
                Arc::new(CiervaAircraft {
                    file: Cow::Owned(f),
                    simulation: self.simulation,
                    azimuth_step_rad: step,
                    starts_from: Some((start.clone(), Values::new())),
                }) as Arc<dyn FlightModel>
            };
        let step = self.azimuth_step_rad;
        vec![
            Refinement {
                parameter: "main rotor azimuth step".into(),
                words: format!("{step_deg:.3} -> {:.3} deg", 0.5 * step_deg),
                ratio: 2.0,
                formal_order: 4.0,
                model: refined(
                    "azimuth-step",
                    &|f| f.aircraft.main_rotor.numerics.azimuth_step_rad *= 0.5,
                    0.5 * step,
                ),
            },
            Refinement {
                parameter: "main rotor blade elements".into(),
                words: format!("{} -> {}", main.rotor.elements, 2 * main.rotor.elements),
                ratio: 2.0,
                formal_order: 2.0,
                model: refined(
                    "main-elements",
                    &|f| f.aircraft.main_rotor.rotor.elements *= 2,
                    step,
                ),
            },
            Refinement {
                parameter: "propeller blade elements".into(),
                words: format!("{} -> {}", propeller.elements, 2 * propeller.elements),
                ratio: 2.0,
                formal_order: 2.0,
                model: refined(
                    "propeller-elements",
                    &|f| f.aircraft.propeller.propeller.rotor.elements *= 2,
                    step,
                ),
            },
            Refinement {
                parameter: "periodicity tolerance".into(),
                words: format!(
                    "{:.2e} -> {:.2e}",
                    main.numerics.periodic_tolerance,
                    0.1 * main.numerics.periodic_tolerance
                ),
                ratio: 10.0,
                formal_order: 1.0,
                model: refined(
                    "periodicity",
                    &|f| f.aircraft.main_rotor.numerics.periodic_tolerance *= 0.1,
                    step,
                ),
            },
        ]
    }

    fn forget(&self, values: &Values) {
        WITH_VALUES.forget(&self.key_of(values));
        TRIMMED_WITH_VALUES.forget(&self.key_of(values));
    }

    fn time_history(
        &self,
        request: &Request,
        controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        let file = self.with_values(request)?;
        crate::run::replay::fly(
            &file.aircraft,
            request.condition,
            request.loading,
            &|t| controls.table.at(t),
            crate::run::replay::FlySettings {
                simulation: self.simulation,
                sample_s: controls.sample_s,
                samples: controls.samples,
                azimuth_step_rad: self.azimuth_step_rad,
            },
        )
    }
}

/// A model with some of its parameters set: every request it is asked carries these values
/// (a request's own value for the same name wins). A study's design point on any model, and a
/// check's corrections on a model behind the model interface.
#[derive(Debug)]
pub struct WithValues<M: FlightModel = Arc<dyn FlightModel>> {
    pub model: M,
    pub values: Values,
}

impl<M: FlightModel> WithValues<M> {
    fn merged(&self, request: &Request) -> Request {
        let mut parameters = self.values.clone();
        parameters.extend(request.parameters.clone());
        Request {
            parameters,
            ..request.clone()
        }
    }
}

impl<M: FlightModel> FlightModel for WithValues<M> {
    fn describe(&self) -> String {
        self.model.describe()
    }
    fn parameters(&self) -> Result<Vec<Parameter>, String> {
        self.model.parameters()
    }
    fn computes(&self) -> Vec<command::Compute> {
        self.model.computes()
    }
    fn trim(&self, request: &Request) -> Result<Quantities, String> {
        self.model.trim(&self.merged(request))
    }
    fn linear_model(&self, request: &Request) -> Result<LinearModel, String> {
        self.model.linear_model(&self.merged(request))
    }
    fn trim_and_linear_model(
        &self,
        request: &Request,
    ) -> Result<(Quantities, LinearModel), String> {
        self.model.trim_and_linear_model(&self.merged(request))
    }
    fn time_history(
        &self,
        request: &Request,
        controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        self.model.time_history(&self.merged(request), controls)
    }
    fn components(&self, request: &Request) -> Result<Vec<(String, LinearModel)>, String> {
        self.model.components(&self.merged(request))
    }
    fn responses(
        &self,
        request: &Request,
        frequencies_hz: &[f64],
    ) -> Result<crate::run::responses::Responses, String> {
        self.model.responses(&self.merged(request), frequencies_hz)
    }
    fn identified_in_band(
        &self,
        request: &Request,
        setup: crate::ident::Setup,
    ) -> Result<LinearModel, String> {
        self.model.identified_in_band(&self.merged(request), setup)
    }
    fn autorotation(
        &self,
        request: &TunnelRequest,
    ) -> Result<crate::run::autorotation::Autorotated, String> {
        let mut parameters = self.values.clone();
        parameters.extend(request.parameters.clone());
        self.model.autorotation(&TunnelRequest {
            parameters,
            ..request.clone()
        })
    }
    /// The model's own corrected model, with these values still set.
    fn corrected<'s>(
        &'s self,
        corrections: &crate::inputs::corrections::CorrectionSet,
    ) -> Result<Option<Box<dyn FlightModel + 's>>, String> {
        Ok(self.model.corrected(corrections)?.map(|model| {
            Box::new(WithValues {
                model,
                values: self.values.clone(),
            }) as Box<dyn FlightModel + 's>
        }))
    }
    fn check_loading(&self, loading: &Loading) -> Result<(), String> {
        self.model.check_loading(loading)
    }
    /// The model starting from its answer with `values` over these.
    fn starting_from(&self, values: &Values) -> Option<Arc<dyn FlightModel>> {
        let mut all = self.values.clone();
        all.extend(values.clone());
        let model = self.model.starting_from(&all)?;
        Some(Arc::new(WithValues {
            model,
            values: self.values.clone(),
        }))
    }
    /// The model's refinements, with these values still set.
    fn refinements(&self) -> Vec<Refinement> {
        self.model
            .refinements()
            .into_iter()
            .map(|r| Refinement {
                model: Arc::new(WithValues {
                    model: r.model,
                    values: self.values.clone(),
                }),
                ..r
            })
            .collect()
    }
    fn forget(&self, values: &Values) {
        let mut all = self.values.clone();
        all.extend(values.clone());
        self.model.forget(&all)
    }
    fn start_after(&self, request: &Request, of: &AnswerOf) -> Option<Start> {
        self.model.start_after(&self.merged(request), of)
    }
    /// The model's other simulation, with these values still set.
    fn simulated_by<'s>(
        &'s self,
        simulation: Simulation,
        azimuth_step_rad: Option<f64>,
    ) -> Option<Box<dyn FlightModel + 's>> {
        self.model
            .simulated_by(simulation, azimuth_step_rad)
            .map(|model| {
                Box::new(WithValues {
                    model,
                    values: self.values.clone(),
                }) as Box<dyn FlightModel + 's>
            })
    }
}

/// Another simulation as a subject: the model, the loading it is asked at, and what it is
/// (its command or files as written, and the folder they are written from: two subjects are
/// the same model when these are).
#[derive(Debug, Clone)]
pub struct External {
    pub model: Arc<dyn FlightModel>,
    pub loading: Loading,
    /// The subject as written, for comparison and reports.
    pub written: String,
    /// The folder its command runs in and its files' paths start from
    /// ([`folder_of`]): the same words in two folders can be two models.
    pub folder: std::path::PathBuf,
}

impl External {
    /// Whether `other` is the same model (whatever the loading it is asked at).
    pub fn same_model(&self, other: &Self) -> bool {
        self.written == other.written && self.folder == other.folder
    }
}

impl PartialEq for External {
    fn eq(&self, other: &Self) -> bool {
        self.same_model(other) && self.loading == other.loading
    }
}

/// A subject's folder as compared: canonical where it exists (`cases/../cases` is `cases`).
pub fn folder_of(dir: &std::path::Path) -> std::path::PathBuf {
    let dir = if dir.as_os_str().is_empty() {
        std::path::Path::new(".")
    } else {
        dir
    };
    dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf())
}

/// Implements [`FlightModel`] for a pointer to a model by asking the model.
macro_rules! forward_flight_model {
    ($($pointer:ty),*) => {$(
        impl<T: FlightModel + ?Sized> FlightModel for $pointer {
            fn describe(&self) -> String {
                (**self).describe()
            }
            fn parameters(&self) -> Result<Vec<Parameter>, String> {
                (**self).parameters()
            }
            fn computes(&self) -> Vec<command::Compute> {
                (**self).computes()
            }
            fn trim(&self, request: &Request) -> Result<Quantities, String> {
                (**self).trim(request)
            }
            fn linear_model(&self, request: &Request) -> Result<LinearModel, String> {
                (**self).linear_model(request)
            }
            fn trim_and_linear_model(
                &self,
                request: &Request,
            ) -> Result<(Quantities, LinearModel), String> {
                (**self).trim_and_linear_model(request)
            }
            fn time_history(
                &self,
                request: &Request,
                controls: &ControlChanges,
            ) -> Result<Replayed, String> {
                (**self).time_history(request, controls)
            }
            fn components(&self, request: &Request) -> Result<Vec<(String, LinearModel)>, String> {
                (**self).components(request)
            }
            fn responses(
                &self,
                request: &Request,
                frequencies_hz: &[f64],
            ) -> Result<crate::run::responses::Responses, String> {
                (**self).responses(request, frequencies_hz)
            }
            fn identified_in_band(
                &self,
                request: &Request,
                setup: crate::ident::Setup,
            ) -> Result<LinearModel, String> {
                (**self).identified_in_band(request, setup)
            }
            fn autorotation(
                &self,
                request: &TunnelRequest,
            ) -> Result<crate::run::autorotation::Autorotated, String> {
                (**self).autorotation(request)
            }
            fn corrected<'s>(
                &'s self,
                corrections: &crate::inputs::corrections::CorrectionSet,
            ) -> Result<Option<Box<dyn FlightModel + 's>>, String> {
                (**self).corrected(corrections)
            }
            fn simulated_by<'s>(
                &'s self,
                simulation: Simulation,
                azimuth_step_rad: Option<f64>,
            ) -> Option<Box<dyn FlightModel + 's>> {
                (**self).simulated_by(simulation, azimuth_step_rad)
            }
            fn check_loading(&self, loading: &Loading) -> Result<(), String> {
                (**self).check_loading(loading)
            }
            fn starting_from(&self, values: &Values) -> Option<Arc<dyn FlightModel>> {
                (**self).starting_from(values)
            }
            fn refinements(&self) -> Vec<Refinement> {
                (**self).refinements()
            }
            fn forget(&self, values: &Values) {
                (**self).forget(values)
            }
            fn start_after(&self, request: &Request, of: &AnswerOf) -> Option<Start> {
                (**self).start_after(request, of)
            }
        }
    )*};
}

// A shared, owned or borrowed model is a model.
forward_flight_model!(Arc<T>, Box<T>, &T);

/// A trim quantity's static name, from what a model wrote: unknown names are an error that
/// lists the known ones.
pub fn trim_name(name: &str) -> Result<&'static str, String> {
    crate::inputs::quantity::TRIM
        .iter()
        .map(|q| q.name())
        .find(|n| *n == name)
        .ok_or_else(|| {
            let known: Vec<String> = crate::inputs::quantity::TRIM
                .iter()
                .map(|q| q.name().to_string())
                .collect();
            let hint = crate::inputs::yaml::nearest(name, &known)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            format!(
                "`{name}` is not a trim quantity{hint}; they are [{}]",
                known.join(", ")
            )
        })
}

/// Checks a model's response against what a record needs: each response it carries, sampled
/// `samples + 1` times.
pub fn check_response(
    model: &str,
    flown: &Replayed,
    signals: &[String],
    samples: usize,
) -> Result<(), String> {
    for s in signals {
        let got = flown.signal(s).map_or(0, <[f64]>::len);
        if got == 0 {
            return Err(format!("{model}'s time history has no `{s}`"));
        }
        if got != samples + 1 {
            return Err(format!(
                "{model}'s time history has {got} samples of `{s}`, the record {}",
                samples + 1
            ));
        }
    }
    Ok(())
}

/// The quantities of a trim of `aircraft` at `loading`.
pub fn trim_quantities_of(
    aircraft: &cierva_model::aircraft::Aircraft,
    loading: crate::inputs::condition::Loading,
    t: &cierva_model::aircraft::trim::Trim,
) -> Quantities {
    let d = f64::to_degrees;
    use crate::inputs::quantity::Quantity as Q;
    let r = &t.averaged.rotor;
    let c = &t.controls;
    vec![
        (Q::ResidualNorm.name(), t.residual_norm),
        (
            Q::StickLongitudinalPercent.name(),
            c.stick_longitudinal_percent,
        ),
        (Q::StickLateralPercent.name(), c.stick_lateral_percent),
        (Q::PedalPercent.name(), c.pedal_percent),
        (Q::ThrottlePercent.name(), c.throttle_percent),
        (Q::PitchDeg.name(), d(t.pitch_rad)),
        (Q::RollDeg.name(), d(t.roll_rad)),
        (Q::AlphaDeg.name(), d(t.alpha_rad)),
        (Q::SideslipDeg.name(), d(t.sideslip_rad)),
        (Q::RotorRpm.name(), t.rotor_rpm),
        (Q::PropellerRpm.name(), t.propeller_rpm),
        (Q::RotorTorqueNM.name(), r.driving_torque_n_m),
        (Q::ThrustN.name(), r.thrust_n),
        (Q::DiscAlphaDeg.name(), d(r.disc_alpha_rad)),
        (Q::TipSpeedRatio.name(), r.tip_speed_ratio),
        (Q::ThrustCoefficientOverSolidity.name(), {
            let rotor = &aircraft.main_rotor.rotor;
            let rho = cierva_model::components::atmosphere::at_density_altitude(
                loading.density_altitude_ft * crate::units::FT_TO_M,
            )
            .map_or(f64::NAN, |a| a.density_kg_m3);
            let tip = t.state.rotor_omega_rad_s * rotor.radius_m;
            r.thrust_n
                / (rho * std::f64::consts::PI * rotor.radius_m.powi(2) * tip * tip)
                / rotor.solidity()
        }),
        (Q::A1Deg.name(), d(r.a1_rad)),
        (Q::B1Deg.name(), d(r.b1_rad)),
        (Q::InflowV0MS.name(), t.state.inflow.v0),
        (Q::InflowV1cMS.name(), t.state.inflow.v1c),
    ]
}
