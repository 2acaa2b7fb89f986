//! What a fit moves and matches: its parameters, the targets (a measure at a condition, a
//! reference with its standard error, optional bounds), the model's value of every target
//! (`evaluate*`, conditions in parallel, trims warm-started), their sensitivities and the
//! problem's own consistency (`check`).

use super::Problem;
use crate::inputs::condition::Loading;
use crate::inputs::condition::TrimRequest;
use crate::inputs::corrections::CorrectionSet;
use crate::suite::case::TunnelSpec;
use cierva_model::components::rotor::InflowModel;
use serde::Serialize;

/// A parameter the fit can move: one of the model's empirical corrections, an aircraft
/// file's estimated physical parameter (a name of [`crate::inputs::parameters::PARAMETERS`]),
/// or a parameter a model behind the model interface declares
/// ([`crate::external::FlightModel::parameters`]).
///
/// A fit file may name a physical parameter only where the aircraft file's source for it says
/// "estimated", and only within the plausible range the file gives it (see
/// [`crate::fit::file`]): a parameter with a published value is not the fit's to move.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ParameterKind {
    /// Seed 000 Sec. VII.A: the fraction of the free stream the rotor's wake takes from the
    /// propeller disc (0..1).
    PropellerBlockage,
    /// Seed 000 Sec. VII.A: the hub's angle of attack as a factor on the c.g.'s.
    HubAoaFactor,
    /// Multiplies the main rotor's section drag coefficient.
    ProfileDragScale,
    /// Added to the main rotor's section drag coefficient.
    ProfileDragIncrement,
    /// Added to the main rotor's blade pitch, deg (a pitch-setting offset).
    PitchOffsetDeg,
    /// Added to the main rotor's lateral induced velocity `v1s`, m/s (seed 003).
    LateralInflowOffsetMS,
    /// The main rotor's elastic torsion: the tip's pitch change (nose up) per kPa of tip
    /// dynamic pressure in hover, deg/kPa.
    ElasticTwistDegPerKpa,
    /// The main rotor's hub drag as an equivalent flat-plate area, m^2.
    HubDragAreaM2,
    /// The main rotor's section-drag Reynolds-number exponent (needs the rotor file's
    /// `drag_reynolds_number`).
    ProfileDragReynoldsExponent,
    /// An aircraft's estimated physical parameter, by its name in
    /// [`crate::inputs::parameters::PARAMETERS`] (`airframe.fin.area_m2`).
    Estimated(&'static str),
    /// A parameter a model declares, by its declared name (a [`FitSubject::Model`]'s: every
    /// request carries its value).
    Declared(String),
}

impl serde::Serialize for ParameterKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl ParameterKind {
    /// Every correction, in the order of [`CorrectionSet`]'s fields.
    pub const ALL: [ParameterKind; 9] = [
        Self::PropellerBlockage,
        Self::HubAoaFactor,
        Self::ProfileDragScale,
        Self::ProfileDragIncrement,
        Self::PitchOffsetDeg,
        Self::LateralInflowOffsetMS,
        Self::ElasticTwistDegPerKpa,
        Self::HubDragAreaM2,
        Self::ProfileDragReynoldsExponent,
    ];

    /// The name as written (the [`CorrectionSet`] field it sets, or the physical parameter's
    /// dotted name).
    pub fn name(&self) -> &str {
        match self {
            Self::PropellerBlockage => "propeller_blockage",
            Self::HubAoaFactor => "hub_aoa_factor",
            Self::ProfileDragScale => "profile_drag_scale",
            Self::ProfileDragIncrement => "profile_drag_increment",
            Self::PitchOffsetDeg => "pitch_offset_deg",
            Self::LateralInflowOffsetMS => "lateral_inflow_offset_m_s",
            Self::ElasticTwistDegPerKpa => "elastic_twist_deg_per_kpa",
            Self::HubDragAreaM2 => "hub_drag_area_m2",
            Self::ProfileDragReynoldsExponent => "profile_drag_reynolds_exponent",
            Self::Estimated(name) => name,
            Self::Declared(name) => name,
        }
    }

    /// Its name behind the model interface: a declared or an estimated parameter's own, a
    /// correction's `corrections.<name>` (as cierva's aircraft declares it).
    pub fn model_name(&self) -> String {
        match self {
            Self::Estimated(name) => name.to_string(),
            Self::Declared(name) => name.clone(),
            other => format!("corrections.{}", other.name()),
        }
    }

    /// The parameter by name: a correction, or a physical parameter of
    /// [`crate::inputs::parameters::PARAMETERS`] (`corrections.propeller_blockage` is the
    /// correction `propeller_blockage`).
    pub fn parse(name: &str) -> Option<Self> {
        let name = name.strip_prefix("corrections.").unwrap_or(name);
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .or_else(|| {
                crate::inputs::parameters::PARAMETERS
                    .iter()
                    .find(|p| p.name == name)
                    .map(|p| Self::Estimated(p.name))
            })
    }

    /// Every name [`Self::parse`] knows, for error messages.
    pub fn names() -> Vec<String> {
        let corrections = Self::ALL.iter().map(|k| k.name().to_string());
        corrections
            .chain(crate::inputs::parameters::physical_names())
            .collect()
    }

    /// The uncorrected model's value of a correction; `None` for a physical parameter, whose
    /// start is the aircraft file's value.
    pub fn neutral(&self) -> Option<f64> {
        match self {
            Self::PropellerBlockage
            | Self::ProfileDragIncrement
            | Self::PitchOffsetDeg
            | Self::LateralInflowOffsetMS
            | Self::ElasticTwistDegPerKpa
            | Self::HubDragAreaM2
            | Self::ProfileDragReynoldsExponent => Some(0.0),
            Self::HubAoaFactor | Self::ProfileDragScale => Some(1.0),
            Self::Estimated(_) | Self::Declared(_) => None,
        }
    }

    /// Whether it needs an aircraft (rather than the blades, which a rotor alone has).
    pub fn needs_aircraft(&self) -> bool {
        matches!(
            self,
            Self::PropellerBlockage | Self::HubAoaFactor | Self::Estimated(_)
        )
    }

    /// The parameter's value in a correction set, where the set gives it.
    pub fn get(&self, c: &CorrectionSet) -> Option<f64> {
        match self {
            Self::PropellerBlockage => c.propeller_blockage,
            Self::HubAoaFactor => c.hub_aoa_factor,
            Self::ProfileDragScale => c.profile_drag_scale,
            Self::ProfileDragIncrement => c.profile_drag_increment,
            Self::PitchOffsetDeg => c.pitch_offset_deg,
            Self::LateralInflowOffsetMS => c.lateral_inflow_offset_m_s,
            Self::ElasticTwistDegPerKpa => c.elastic_twist_deg_per_kpa,
            Self::HubDragAreaM2 => c.hub_drag_area_m2,
            Self::ProfileDragReynoldsExponent => c.profile_drag_reynolds_exponent,
            Self::Estimated(name) => c.estimated.get(*name).copied(),
            Self::Declared(name) => c.parameters.get(name).copied(),
        }
    }

    /// Sets the parameter in a correction set.
    pub fn set(&self, c: &mut CorrectionSet, value: f64) {
        let field = match self {
            Self::PropellerBlockage => &mut c.propeller_blockage,
            Self::HubAoaFactor => &mut c.hub_aoa_factor,
            Self::ProfileDragScale => &mut c.profile_drag_scale,
            Self::ProfileDragIncrement => &mut c.profile_drag_increment,
            Self::PitchOffsetDeg => &mut c.pitch_offset_deg,
            Self::LateralInflowOffsetMS => &mut c.lateral_inflow_offset_m_s,
            Self::ElasticTwistDegPerKpa => &mut c.elastic_twist_deg_per_kpa,
            Self::HubDragAreaM2 => &mut c.hub_drag_area_m2,
            Self::ProfileDragReynoldsExponent => &mut c.profile_drag_reynolds_exponent,
            Self::Estimated(name) => {
                c.estimated.insert(name.to_string(), value);
                return;
            }
            Self::Declared(name) => {
                c.parameters.insert(name.clone(), value);
                return;
            }
        };
        *field = Some(value);
    }
}

/// A fitted parameter: bounds and start.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitParameter {
    pub kind: ParameterKind,
    pub lower: f64,
    pub upper: f64,
    pub start: f64,
    /// Weight of the regularisation towards `start` (0: none), per squared bound range.
    pub regularisation: f64,
}

/// What is fitted: an aircraft in flight, a rotor alone in a wind tunnel, or any model behind
/// the model interface in flight.
#[derive(Debug, Clone)]
pub enum FitSubject {
    /// cierva's aircraft file, flown at each target's loading: asked through the model
    /// interface ([`crate::external::CiervaAircraft`]) as any model is, its corrections and
    /// estimated parameters by their declared names ([`ParameterKind::model_name`]).
    Aircraft {
        file: Box<crate::inputs::aircraft::AircraftFile>,
    },
    /// cierva's rotor of a rotor file in a tunnel, solved with `inflow`: asked through the
    /// model interface ([`crate::external::rotor::CiervaRotor`]) at each target's tunnel
    /// condition, its corrections by their declared names.
    Rotor {
        file: Box<crate::inputs::rotor::RotorFile>,
        inflow: InflowModel,
    },
    /// A model behind the model interface (an external simulation, or cierva's own aircraft
    /// served through it), asked at each target's condition and loading with the parameters'
    /// values by their declared names ([`ParameterKind::Declared`]): its trim, and its linear
    /// model where a target is a derivative or a frequency response (from its `A` and `B`).
    Model {
        model: std::sync::Arc<dyn crate::external::FlightModel>,
    },
}

impl FitSubject {
    /// The subject as a flight model (cierva's aircraft or a model behind the model
    /// interface); `None` for a rotor.
    pub fn flight_model(&self) -> Option<Box<dyn crate::external::FlightModel + '_>> {
        match self {
            Self::Aircraft { file } => Some(Box::new(crate::external::CiervaAircraft::new(file))),
            Self::Model { model } => Some(Box::new(model.clone())),
            Self::Rotor { .. } => None,
        }
    }
}

/// Where a target is measured: a trimmed flight condition at a loading (aircraft) or a tunnel
/// condition (rotor, autorotating).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TargetCondition {
    Flight(TrimRequest, Loading),
    Tunnel(TunnelSpec),
}

impl TargetCondition {
    /// A short label: `55 mph 425 kg`, `alpha 8.3 deg mu 0.216`.
    pub fn label(&self) -> String {
        match self {
            Self::Flight(t, loading) => {
                // As written where that is short (`62.5 mph`); a converted speed (60 kn is
                // 69.04676688141255 mph) to two decimals.
                let written = format!("{}", t.airspeed_mph);
                let speed = if written.len() <= 6 {
                    written
                } else {
                    format!("{:.2}", t.airspeed_mph)
                };
                let mut s = format!("{speed} mph");
                if let Some(m) = loading.mass_kg {
                    s += &format!(" {m} kg");
                }
                if t.climb_m_s != 0.0 {
                    s += &format!(" climb {} m/s", t.climb_m_s);
                }
                if t.turn_rate_deg_s != 0.0 {
                    s += &format!(" turn {} deg/s", t.turn_rate_deg_s);
                }
                s
            }
            Self::Tunnel(t) => {
                let mut s = match t.alpha_deg {
                    Some(a) => format!("alpha {a} deg"),
                    None => "alpha found".to_string(),
                };
                if let Some(mu) = t.tip_speed_ratio {
                    s += &format!(" mu {mu}");
                }
                if let Some(v) = t.airspeed_m_s {
                    s += &format!(" V {v} m/s");
                }
                s
            }
        }
    }
}

/// What a target measures.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "name")]
pub enum Measure {
    /// A derivative of the linearised model (`X_u`, `Q_Omega`), at a flight condition.
    Derivative(String),
    /// A trim quantity ([`crate::inputs::quantity::TRIM`]), at a flight condition.
    Trim(String),
    /// An autorotation quantity ([`TUNNEL_QUANTITIES`]), at a tunnel condition.
    Tunnel(String),
    /// The real or imaginary part of the aircraft's frequency response from a control to a
    /// state at one frequency, at a flight condition: the linearisation with the rotor's
    /// flapping states where the hub has one (its baseband response by harmonic balance), the
    /// quasi-static linearisation otherwise
    /// ([`crate::run::responses::aircraft_responses`]).
    Response(ResponsePoint),
}

/// One part of a frequency response at one frequency (a [`Measure::Response`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResponsePoint {
    /// As reports name it: `q/eta_s 0.5234 Hz re`.
    pub name: String,
    /// The control (a column of the linearised model's `B`).
    pub input: String,
    /// The state (a row of the model's `A`).
    pub output: String,
    pub frequency_hz: f64,
    /// The imaginary part (`false`: the real part).
    pub imaginary: bool,
    /// The record's other controls' measured transfers from `input` at this frequency, which
    /// the model's response adds through its own responses to them
    /// ([`crate::run::responses::Responses::as_flown`]); empty: none moved.
    #[serde(skip)]
    pub others: Vec<(String, rustfft::num_complex::Complex64)>,
}

impl ResponsePoint {
    /// The point, named as reports name it.
    pub fn new(input: &str, output: &str, frequency_hz: f64, imaginary: bool) -> Self {
        Self {
            name: format!(
                "{output}/{input} {frequency_hz:.4} Hz {}",
                if imaginary { "im" } else { "re" }
            ),
            input: input.to_string(),
            output: output.to_string(),
            frequency_hz,
            imaginary,
            others: Vec::new(),
        }
    }
}

/// The autorotation quantities a tunnel target can fit (all but the rotor speed in rad/s,
/// which is `rotor_rpm` again, and the inflow, which a tunnel does not measure; the angle only
/// where the tunnel condition leaves it out).
pub const TUNNEL_QUANTITIES: &[crate::inputs::quantity::Quantity] = {
    use crate::inputs::quantity::Quantity as Q;
    &[
        Q::RotorAlphaDeg,
        Q::RotorRpm,
        Q::TipSpeedRatio,
        Q::LiftCoefficient,
        Q::DragCoefficient,
        Q::LiftToDrag,
        Q::ThrustCoefficient,
        Q::ConingDeg,
        Q::A1Deg,
        Q::B1Deg,
    ]
};

impl Measure {
    /// The measure by name at a kind of condition: a trim quantity or a derivative in flight,
    /// an autorotation quantity in a tunnel. An unknown name is an error that suggests the
    /// nearest.
    pub fn parse(condition: &TargetCondition, name: &str) -> Result<Self, String> {
        let trim = crate::inputs::quantity::names(crate::inputs::quantity::TRIM);
        let tunnel = crate::inputs::quantity::names(TUNNEL_QUANTITIES);
        let hint = |have: &[&str]| {
            let have: Vec<String> = have.iter().map(|s| s.to_string()).collect();
            crate::inputs::yaml::nearest(name, &have)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default()
        };
        match condition {
            TargetCondition::Flight(..) => {
                if trim.contains(&name) {
                    return Ok(Self::Trim(name.into()));
                }
                match crate::checks::linear::linearised_template().derivative(name) {
                    Ok(_) => Ok(Self::Derivative(name.into())),
                    Err(e) => Err(format!(
                        "`{name}` is neither a trim quantity nor a derivative of the linearised model ({e}){}",
                        hint(&trim)
                    )),
                }
            }
            TargetCondition::Tunnel(_) => {
                if tunnel.contains(&name) {
                    Ok(Self::Tunnel(name.into()))
                } else {
                    Err(format!(
                        "`{name}` is not an autorotation quantity (one of {}){}",
                        tunnel.join(", "),
                        hint(&tunnel)
                    ))
                }
            }
        }
    }

    /// The name as written.
    pub fn name(&self) -> &str {
        match self {
            Self::Derivative(d) | Self::Trim(d) | Self::Tunnel(d) => d,
            Self::Response(r) => &r.name,
        }
    }
}

/// How a target's bounds act.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Enforce {
    /// The fitted value must lie within them (linearised at each step).
    Hard,
    /// A violation costs `weight * (violation / standard_error)^2`.
    Soft { weight: f64 },
}

/// Bounds a fitted value should lie within (for example the 95 % flight bounds).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Bounds {
    pub lower: f64,
    pub upper: f64,
    pub enforce: Enforce,
}

impl Bounds {
    /// How far `y` lies outside (negative below, positive above, zero within).
    pub(super) fn violation(&self, y: f64) -> f64 {
        if y > self.upper {
            y - self.upper
        } else if y < self.lower {
            y - self.lower
        } else if y.is_nan() {
            f64::NAN
        } else {
            0.0
        }
    }
}

/// A flight reference to fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Target {
    pub condition: TargetCondition,
    pub measure: Measure,
    pub reference: f64,
    /// Its standard error (or a bound width): the residual's scale. Positive.
    pub standard_error: f64,
    /// Optional bounds, hard or soft.
    pub bounds: Option<Bounds>,
}

/// The penalty weight that stands for a hard bound: a violation costs as much as being a
/// thousand standard errors from the reference, so the fit gives up at most a millionth of the
/// way. A hard bound still violated at the end (by more than [`HARD_SLACK`] standard errors)
/// makes the fit infeasible.
const HARD_WEIGHT: f64 = 1e6;
/// How far (in standard errors) a fitted value may lie outside its hard bounds.
pub(super) const HARD_SLACK: f64 = 1e-3;
/// How far inside its hard bounds (in standard errors) the penalty aims: a penalty leaves a
/// violation of about a millionth of the way, so a fit held by a hard bound would end a hair
/// outside it (3e-6 standard errors, seen on the Table 2 fit). Aiming this far inside lands it
/// inside instead, at a cost far below any bound's meaning.
const HARD_MARGIN: f64 = 1e-4;

impl Target {
    /// The bounds and their penalty weight (hard bounds: [`HARD_WEIGHT`]). The penalty is an
    /// "elastic" form of the constraint: a step is always possible, even from an iterate that
    /// overshot a bound, and contradictory bounds show as a violation left at the end.
    /// Hard bounds aim [`HARD_MARGIN`] standard errors inside themselves (where they are wider
    /// than twice that).
    pub(super) fn penalty(&self) -> Option<(Bounds, f64)> {
        self.bounds.map(|b| match b.enforce {
            Enforce::Soft { weight } => (b, weight),
            Enforce::Hard => {
                let m = HARD_MARGIN * self.standard_error;
                let aimed = if b.upper - b.lower > 2.0 * m {
                    Bounds {
                        lower: b.lower + m,
                        upper: b.upper - m,
                        ..b
                    }
                } else {
                    b
                };
                (aimed, HARD_WEIGHT)
            }
        })
    }
}

/// One condition's computed quantities, its linear model where a target needs one, and its
/// frequency responses where a target needs them.
type AtCondition = (
    crate::checks::result::Quantities,
    Option<cierva_model::analysis::linear::LinearModel>,
    Option<crate::run::responses::Responses>,
    Option<crate::external::Start>,
);

/// Where a fit's evaluations at each condition start: where the model's answers there ended
/// at a point (its iterate), condition by condition
/// ([`crate::external::FlightModel::start_after`]). Empty (the default): where the model
/// starts them.
///
/// The fit's trial steps and finite differences start from its iterate's answers, and an
/// accepted step's answers become the next iterate's starts: a chain the fit's own path
/// decides, so an evaluation does not depend on which evaluations ran before it or where
/// (threads, a model's processes, an engine's shards).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ConditionStarts(pub Vec<(TargetCondition, crate::external::Start)>);

impl ConditionStarts {
    /// The start at condition `c`, if there is one.
    pub fn at(&self, c: &TargetCondition) -> Option<crate::external::Start> {
        self.0.iter().find(|(k, _)| k == c).map(|(_, s)| s.clone())
    }
}

/// Every target's value (or why not) at a point, and where the model's answers there ended.
pub type PointEvaluation = (Vec<Result<f64, String>>, ConditionStarts);

/// The distinct frequencies of a condition's response targets, in the order they come.
fn response_frequencies(problem: &Problem, c: &TargetCondition) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for t in &problem.targets {
        if let (true, Measure::Response(r)) = (t.condition == *c, &t.measure)
            && !out.contains(&r.frequency_hz)
        {
            out.push(r.frequency_hz);
        }
    }
    out
}

/// The model's value of every target at parameter values `p`, conditions in parallel; the
/// first failure if any target cannot be evaluated.
///
/// cierva's aircraft starts each trim with parameter values from its own trim at the
/// condition ([`crate::external::CiervaAircraft`]): an evaluation does not depend on the ones
/// before it, and a fit of the aircraft through the model interface (`cierva serve`) makes the
/// same trims.
pub fn evaluate(problem: &Problem, p: &[f64]) -> Result<Vec<f64>, String> {
    Ok(evaluate_from(problem, p, &ConditionStarts::default())?.0)
}

/// [`evaluate`] with each condition's trims started from `from`, and where they ended.
pub fn evaluate_from(
    problem: &Problem,
    p: &[f64],
    from: &ConditionStarts,
) -> Result<(Vec<f64>, ConditionStarts), String> {
    let (each, starts) = evaluate_each_from(problem, p, from)?;
    Ok((each.into_iter().collect::<Result<_, _>>()?, starts))
}

/// [`evaluate_each`] as numbers: NaN for a target whose condition fails, and for every target
/// when the corrections themselves are invalid (what a report prints as "not solved").
pub fn values_or_nan(problem: &Problem, p: &[f64]) -> Vec<f64> {
    evaluate_each(problem, p).map_or(vec![f64::NAN; problem.targets.len()], |v| {
        v.into_iter().map(|y| y.unwrap_or(f64::NAN)).collect()
    })
}

/// The model's value of every target at parameter values `p`, each on its own (a condition that
/// fails leaves the others); an error only when the corrections themselves are invalid. Run
/// where the problem's [`crate::fit::Executor`] says.
pub fn evaluate_each(problem: &Problem, p: &[f64]) -> Result<Vec<Result<f64, String>>, String> {
    Ok(evaluate_each_from(problem, p, &ConditionStarts::default())?.0)
}

/// [`evaluate_each`] with each condition's trims started from `from`, and where they ended.
pub fn evaluate_each_from(
    problem: &Problem,
    p: &[f64],
    from: &ConditionStarts,
) -> Result<PointEvaluation, String> {
    evaluate_many(problem, &[p.to_vec()], from)
        .pop()
        .unwrap_or_else(|| Err("the batch returned no evaluation".into()))
}

/// [`evaluate_each`] at each of `points`: one batch where the problem's executor sends its
/// evaluations elsewhere (a Jacobian's steps together), else one after the other here.
fn evaluate_many(
    problem: &Problem,
    points: &[Vec<f64>],
    from: &ConditionStarts,
) -> Vec<Result<PointEvaluation, String>> {
    match &problem.executor {
        crate::fit::Executor::Local => points
            .iter()
            .map(|p| evaluate_each_here_from(problem, p, from))
            .collect(),
        crate::fit::Executor::Batches(b) if !points.is_empty() => {
            b.evaluate_batch(problem, points, from)
        }
        crate::fit::Executor::Batches(_) => Vec::new(),
    }
}

/// [`evaluate_each`] on this machine's threads, conditions in parallel: what every executor
/// runs in the end (`cierva evaluate` runs it on a plan's evaluations).
pub fn evaluate_each_here(
    problem: &Problem,
    p: &[f64],
) -> Result<Vec<Result<f64, String>>, String> {
    Ok(evaluate_each_here_from(problem, p, &ConditionStarts::default())?.0)
}

/// [`evaluate_each_here`] with each condition's trims started from `from`, and where they
/// ended.
pub fn evaluate_each_here_from(
    problem: &Problem,
    p: &[f64],
    from: &ConditionStarts,
) -> Result<PointEvaluation, String> {
    let mut conditions: Vec<TargetCondition> = Vec::new();
    for t in &problem.targets {
        if !conditions.contains(&t.condition) {
            conditions.push(t.condition);
        }
    }
    let at = |c: &TargetCondition| format!("at {} with {}", c.label(), describe(problem, p));
    let results: Vec<Result<AtCondition, String>> = match &problem.subject {
        FitSubject::Aircraft { .. } | FitSubject::Model { .. } => {
            let model = problem.subject.flight_model().expect("a flight model");
            on_model(problem, model.as_ref(), p, &conditions, from, &at)
        }
        FitSubject::Rotor { file, inflow } => {
            let model = crate::external::rotor::CiervaRotor::new(file, (*inflow).into());
            let parameters = problem.declared_values(p);
            crate::run::parallel::parallel_map(&conditions, |c| {
                let TargetCondition::Tunnel(t) = c else {
                    return Err(format!("{}: a rotor alone is tested in a tunnel", at(c)));
                };
                let request = crate::external::TunnelRequest {
                    tunnel: *t,
                    parameters: parameters.clone(),
                };
                crate::external::FlightModel::autorotation(&model, &request)
                    .and_then(crate::run::autorotation::Autorotated::quantities_or_reason)
                    .map(|q| (q, None, None, None))
                    .map_err(|e| format!("{}: {e}", at(c)))
            })
        }
    };
    let value = |t: &Target| -> Result<f64, String> {
        let k = conditions
            .iter()
            .position(|c| *c == t.condition)
            .expect("listed");
        let (quantities, lin, responses, _) = results[k].as_ref().map_err(Clone::clone)?;
        match (&t.measure, lin) {
            (Measure::Derivative(d), Some(lin)) => {
                lin.derivative_value(d).map_err(|e| e.to_string())
            }
            (Measure::Response(r), _) => {
                let h = responses
                    .as_ref()
                    .ok_or_else(|| format!("no responses computed {}", at(&t.condition)))?
                    .as_flown(&r.input, &r.output, r.frequency_hz, &r.others)
                    .map_err(|e| format!("{e} {}", at(&t.condition)))?;
                Ok(if r.imaginary { h.im } else { h.re })
            }
            (m, _) => quantities
                .iter()
                .find(|(n, _)| *n == m.name())
                .map(|(_, v)| *v)
                .ok_or_else(|| format!("`{}` is not computed {}", m.name(), at(&t.condition))),
        }
    };
    let starts = conditions
        .iter()
        .zip(&results)
        .filter_map(|(c, r)| Some((*c, r.as_ref().ok()?.3.clone()?)))
        .collect();
    Ok((
        problem.targets.iter().map(value).collect(),
        ConditionStarts(starts),
    ))
}

/// Each condition's quantities, linear model and responses from a model behind the model
/// interface, asked with the parameters' values `p` by their declared names: its trim, or its
/// trim and linear model where a target at the condition is a derivative or a response (the
/// responses from its `A` and `B`). `at` says where, for errors.
fn on_model(
    problem: &Problem,
    model: &dyn crate::external::FlightModel,
    p: &[f64],
    conditions: &[TargetCondition],
    from: &ConditionStarts,
    at: &(dyn Fn(&TargetCondition) -> String + Sync),
) -> Vec<Result<AtCondition, String>> {
    let values = problem.declared_values(p);
    crate::run::parallel::parallel_map(conditions, |c| {
        let TargetCondition::Flight(condition, loading) = c else {
            return Err(format!(
                "{}: a model is asked in flight, not in a tunnel",
                at(c)
            ));
        };
        let request = crate::external::Request {
            condition: *condition,
            loading: *loading,
            parameters: values.clone(),
            start: from.at(c),
        };
        let frequencies = response_frequencies(problem, c);
        let here = |m: fn(&Measure) -> bool| {
            problem
                .targets
                .iter()
                .any(|t| t.condition == *c && m(&t.measure))
        };
        let linear = here(|m| matches!(m, Measure::Derivative(_)));
        let trimmed = here(|m| matches!(m, Measure::Trim(_)));
        let located = |e: String| format!("{}: {e}", at(c));
        // Only what the targets need: a model that gives its linear model alone can be fitted
        // to derivatives and responses (its responses come from its A and B).
        let (q, lin) = match (trimmed, linear) {
            (false, false) => (Vec::new(), None),
            (true, false) => (model.trim(&request).map_err(located)?, None),
            (false, true) => (
                Vec::new(),
                Some(model.linear_model(&request).map_err(located)?),
            ),
            (true, true) => {
                let (q, lin) = model.trim_and_linear_model(&request).map_err(located)?;
                (q, Some(lin))
            }
        };
        let responses = if frequencies.is_empty() {
            None
        } else {
            Some(model.responses(&request, &frequencies).map_err(located)?)
        };
        // Where the condition's answers ended: its linear model's where it was asked, else its
        // trim's, else its responses' (one rule, whatever else a run asked before).
        let of = match (linear, trimmed) {
            (true, _) => crate::external::AnswerOf::LinearModel,
            (false, true) => crate::external::AnswerOf::Trim,
            (false, false) => crate::external::AnswerOf::Responses(frequencies),
        };
        Ok((q, lin, responses, model.start_after(&request, &of)))
    })
}

fn describe(problem: &Problem, p: &[f64]) -> String {
    problem
        .parameters
        .iter()
        .zip(p)
        .map(|(q, v)| format!("{} = {v:.4}", q.kind.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The problem's own consistency: bounds, starts, weights, targets that suit the subject.
pub fn check(problem: &Problem) -> Result<(), String> {
    if problem.parameters.is_empty() {
        return Err("no parameters to fit".into());
    }
    if problem.targets.is_empty() {
        return Err("no targets to fit".into());
    }
    for (i, p) in problem.parameters.iter().enumerate() {
        let name = p.kind.name();
        if problem.parameters[..i].iter().any(|q| q.kind == p.kind) {
            return Err(format!("parameter `{name}` is given twice"));
        }
        if !(p.lower.is_finite() && p.upper.is_finite() && p.lower < p.upper) {
            return Err(format!(
                "parameter `{name}`: bounds [{}, {}] must be finite with lower < upper",
                p.lower, p.upper
            ));
        }
        if !(p.lower..=p.upper).contains(&p.start) {
            return Err(format!(
                "parameter `{name}`: start {} is outside its bounds [{}, {}]",
                p.start, p.lower, p.upper
            ));
        }
        if !(p.regularisation.is_finite() && p.regularisation >= 0.0) {
            return Err(format!("parameter `{name}`: regularisation must be >= 0"));
        }
    }
    for t in &problem.targets {
        let name = t.measure.name();
        if !(t.reference.is_finite() && t.standard_error.is_finite() && t.standard_error > 0.0) {
            return Err(format!(
                "target `{name}` at {}: the reference must be finite and the standard error positive",
                t.condition.label()
            ));
        }
        if let Some(b) = t.bounds {
            if b.lower.is_nan() || b.upper.is_nan() || b.lower > b.upper {
                return Err(format!(
                    "target `{name}` at {}: bounds [{}, {}] are empty",
                    t.condition.label(),
                    b.lower,
                    b.upper
                ));
            }
            if let Enforce::Soft { weight } = b.enforce
                && !(weight.is_finite() && weight > 0.0)
            {
                return Err(format!(
                    "target `{name}` at {}: a soft bound's weight must be positive",
                    t.condition.label()
                ));
            }
        }
        let fits = matches!(
            (&problem.subject, &t.condition),
            (
                FitSubject::Aircraft { .. } | FitSubject::Model { .. },
                TargetCondition::Flight(..)
            ) | (FitSubject::Rotor { .. }, TargetCondition::Tunnel(_))
        );
        if !fits {
            return Err(format!(
                "target `{name}` at {}: an aircraft or a model is fitted at flight conditions, a rotor at tunnel conditions",
                t.condition.label()
            ));
        }
    }
    let declared = |p: &&FitParameter| matches!(p.kind, ParameterKind::Declared(_));
    match &problem.subject {
        FitSubject::Model { model } => {
            if let Some(p) = problem.parameters.iter().find(|p| !declared(p)) {
                return Err(format!(
                    "parameter `{}` is cierva's own; {} is fitted by the parameters it declares",
                    p.kind.name(),
                    model.describe()
                ));
            }
        }
        _ => {
            if let Some(p) = problem.parameters.iter().find(declared) {
                return Err(format!(
                    "parameter `{}` is a model's declared parameter; this subject is cierva's own aircraft or rotor file",
                    p.kind.name()
                ));
            }
        }
    }
    if matches!(problem.subject, FitSubject::Rotor { .. })
        && let Some(p) = problem.parameters.iter().find(|p| p.kind.needs_aircraft())
    {
        return Err(format!(
            "parameter `{}` corrects an aircraft; a rotor alone cannot take it",
            p.kind.name()
        ));
    }
    Ok(())
}

/// The targets' values at `p` and their forward-difference sensitivities to the parameters
/// there (`[target][parameter]`), as the fit differences them: for a covariance beyond the
/// fit's own (`crate::fit::retune`'s cluster-robust one).
pub fn sensitivities(problem: &Problem, p: &[f64]) -> Result<(Vec<f64>, Vec<Vec<f64>>), String> {
    let (y, starts) = evaluate_from(problem, p, &ConditionStarts::default())?;
    let j = jacobian(problem, p, &y, &starts)?;
    Ok((y, j))
}

/// Forward-difference sensitivities of the targets to the parameters, each step's trims started
/// from `from` (the answers at `p`); each step goes inwards from a bound.
pub(super) fn jacobian(
    problem: &Problem,
    p: &[f64],
    y: &[f64],
    from: &ConditionStarts,
) -> Result<Vec<Vec<f64>>, String> {
    let n = p.len();
    let mut j = vec![vec![0.0; n]; y.len()];
    let stepped = |i: usize, h: f64| {
        let mut q = p.to_vec();
        q[i] += h;
        q
    };
    let steps: Vec<f64> = (0..n)
        .map(|i| {
            let par = &problem.parameters[i];
            let h = problem.options.difference_step * (par.upper - par.lower);
            if p[i] + h > par.upper { -h } else { h }
        })
        .collect();
    // Every parameter's step in one batch; then, near the edge of the model's domain (a rotor
    // at the edge of autorotation), where the model fails on one side of a point it solves, the
    // other way, in a second batch.
    let forward: Vec<Vec<f64>> = (0..n).map(|i| stepped(i, steps[i])).collect();
    let all = |r: Result<PointEvaluation, String>| r?.0.into_iter().collect();
    let mut answers: Vec<Result<Vec<f64>, String>> = evaluate_many(problem, &forward, from)
        .into_iter()
        .map(all)
        .collect();
    let back: Vec<usize> = (0..n)
        .filter(|&i| {
            let par = &problem.parameters[i];
            answers[i].is_err() && (par.lower..=par.upper).contains(&(p[i] - steps[i]))
        })
        .collect();
    let backward: Vec<Vec<f64>> = back.iter().map(|&i| stepped(i, -steps[i])).collect();
    let mut h = steps;
    for (&i, answer) in back.iter().zip(evaluate_many(problem, &backward, from)) {
        if let Ok(yq) = all(answer) {
            (answers[i], h[i]) = (Ok(yq), -h[i]);
        }
    }
    for (i, answer) in answers.into_iter().enumerate() {
        let yq = answer?;
        for k in 0..y.len() {
            j[k][i] = (yq[k] - y[k]) / h[i];
        }
    }
    Ok(j)
}
