//! Fit files: what `cierva fit` reads, how a fit runs, and the corrections file it writes. The
//! fit's report for people (Markdown and its figure) is [`crate::report::fit`].
//!
//! ```yaml
//! id: pca-2-tr515                        # the file's stem
//! title: PCA-2 pitch offset and profile drag against NACA TR 515 Table III
//! provenance: {source: "...", notes: "..."}
//! subject:                               # exactly one
//!   rotor: {file: ../aircraft/pca-2-rotor.yaml}   # its `physics`; inflow, skew, descent set over
//!                                                 # them are in the fit's report
//!   # aircraft: {file: ../aircraft/vpm-m16.yaml, mass_kg: 425, density_altitude_ft: 2000}
//!   # case: ../cases/my-model-trim.yaml    # the model a case checks (`external`: a model
//!                                          # behind the model interface), at its loading
//! parameters:                            # name: bounds, start (default: uncorrected), weight
//!   pitch_offset_deg: {lower: -3, upper: 3}
//!   profile_drag_scale: {lower: 0.5, upper: 3, regularisation: 0}
//!   airframe.fin.area_m2: {}              # an aircraft's estimated physical parameter: bounds
//!                                          # default to (and must lie in) its file's range
//! targets:                               # what the fit matches
//!   - case: ../cases/naca-tr515-table-iii.yaml   # a case's checks: condition, value, tolerance
//!     checks: [row-01, row-05]           # default: every check
//!     quantities: [rotor_rpm, drag_coefficient]
//!     bounds: none                       # none | hard | soft (interval tolerances only)
//!   - condition: {airspeed_mph: 40}      # or written out (tunnel: {alpha_deg: .., ...})
//!     quantity: X_u
//!     reference: -0.10
//!     standard_error: 0.01
//!     bounds: {lower: -0.12, upper: -0.08, enforce: hard}  # or enforce: {soft: {weight: 10}}
//!     source: "where the number comes from"
//! predict: [...]                         # as targets: not fitted, reported before and after
//! options: {max_iterations: 20, tolerance: 1.0e-6, difference_step: 1.0e-3, trust_region: 0.5,
//!           broyden: true,             # false: difference the Jacobian every iteration
//!           starts: 4}                 # fits from the file's start and 3 more around its path,
//!                                      # keeps the best, states the ends' spread
//!                                      # (crate::fit::starts)
//! ```
//!
//! A physical parameter (a name of [`crate::inputs::parameters::PARAMETERS`]) can be fitted only
//! where the aircraft file's source for it begins "estimated" and the file gives it a plausible
//! range with a source: the fit moves what nobody measured, and no further than its sources
//! allow. It starts from the file's value. An aircraft's targets are flown at their own loading
//! (a case's mass and density altitude; written-out ones at the subject's).
//!
//! A model behind the model interface (`subject: {case: ...}`, the model a case checks with
//! `external:`) is fitted by the parameters it declares
//! ([`crate::external::FlightModel::parameters`]): each by its declared name, its bounds
//! defaulting to (and lying within) its declared range, starting at its nominal value. Its
//! targets come from cases that check the same model (the same command, written from the same
//! folder), each at its own loading, and written-out ones at the subject case's.
//!
//! A target taken from a case check uses the check's expected value as its reference and its
//! tolerance as the scale: an absolute tolerance is the standard error, a relative one times
//! the value, and an interval (95 % flight bounds) gives its midpoint with a standard error of
//! the half-width over 1.96; such an interval can also be a hard or soft bound.

use crate::checks::{Measured, Place};
use crate::fit::{self, Bounds, Enforce, FitParameter, Measure, ParameterKind, TargetCondition};
use crate::inputs::reference::Provenance;
use crate::inputs::yaml::{self, InputError};
use crate::suite::case::{self, AircraftModelSpec, RotorModelSpec, ToleranceKind, TunnelSpec};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct SubjectSpec {
    #[serde(default)]
    aircraft: Option<AircraftModelSpec>,
    #[serde(default)]
    rotor: Option<RotorModelSpec>,
    /// A case whose subject is a model behind the model interface (`external`).
    #[serde(default)]
    case: Option<String>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct ParameterSpec {
    /// Required for a correction; a physical parameter's default to its plausible range.
    #[serde(default)]
    lower: Option<f64>,
    #[serde(default)]
    upper: Option<f64>,
    #[serde(default)]
    start: Option<f64>,
    #[serde(default)]
    regularisation: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
enum CaseBounds {
    #[default]
    None,
    Hard,
    Soft,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum EnforceSpec {
    Hard,
    Soft { weight: f64 },
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct BoundsSpec {
    lower: f64,
    upper: f64,
    enforce: EnforceSpec,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct TargetSpec {
    // From a case.
    #[serde(default)]
    case: Option<String>,
    #[serde(default)]
    checks: Option<Vec<String>>,
    #[serde(default)]
    quantities: Option<Vec<String>>,
    /// For case targets: how interval tolerances act (default none).
    #[serde(default)]
    case_bounds: Option<CaseBounds>,
    /// For case targets: the weight of soft bounds (default 1).
    #[serde(default)]
    soft_weight: Option<f64>,
    // Written out.
    #[serde(default)]
    condition: Option<crate::inputs::condition::TrimRequest>,
    #[serde(default)]
    tunnel: Option<TunnelSpec>,
    #[serde(default)]
    quantity: Option<String>,
    #[serde(default)]
    reference: Option<f64>,
    #[serde(default)]
    standard_error: Option<f64>,
    #[serde(default)]
    bounds: Option<BoundsSpec>,
    #[serde(default)]
    source: Option<String>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
struct OptionsSpec {
    #[serde(default)]
    max_iterations: Option<usize>,
    #[serde(default)]
    tolerance: Option<f64>,
    #[serde(default)]
    difference_step: Option<f64>,
    #[serde(default)]
    trust_region: Option<f64>,
    #[serde(default)]
    broyden: Option<bool>,
    /// Fits from this many starts (the file's own, then points spread over the bounds) and
    /// keeps the best, with the spread of the ends the data cannot tell apart
    /// ([`crate::fit::starts`]). 1 when absent.
    #[serde(default)]
    starts: Option<usize>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct FitFileSpec {
    id: String,
    title: String,
    provenance: Provenance,
    subject: SubjectSpec,
    parameters: BTreeMap<String, ParameterSpec>,
    targets: Vec<TargetSpec>,
    #[serde(default)]
    predict: Vec<TargetSpec>,
    #[serde(default)]
    options: Option<OptionsSpec>,
    #[serde(default)]
    cross_validation: Option<CrossValidationSpec>,
}

/// Named checks (ids within their case): a cross-validation group or a regime.
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct NamedChecks {
    pub name: String,
    pub checks: Vec<String>,
}

/// How a fit is cross-validated (`cierva fit`; [`crate::uncertainty::calibration`]): the
/// groups of its targets left out one at a time, and the regimes its predictive error is
/// reported for (of the targets and the predictions).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrossValidationSpec {
    /// Groups of the fitted targets' checks, each left out in turn (the predictions by the
    /// whole fit). Give these or `bands`.
    #[serde(default)]
    pub groups: Vec<NamedChecks>,
    /// Contiguous bands of one condition, each left out in turn with every row in it, fitted
    /// or not ([`Bands`]). Give these or `groups`.
    #[serde(default)]
    pub bands: Option<Bands>,
    #[serde(default)]
    pub regimes: Vec<NamedChecks>,
}

/// Cross-validation by bands: the fitted targets' distinct values of one condition (`by`),
/// sorted, are cut into `count` contiguous runs of near-equal size; each band reaches halfway
/// to the next run's first value, and holds every target and prediction of the fit in it. A
/// band's fit is redone on the fitted targets outside it and predicts every row in it: data
/// it did not see, beyond its own neighbours, and a repeat run is held out with the row it
/// repeats.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Bands {
    pub by: BandCondition,
    pub count: usize,
}

/// The condition a fit's rows are banded by ([`Bands`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BandCondition {
    /// A tunnel's tip-speed ratio.
    TipSpeedRatio,
    /// A flight condition's airspeed.
    AirspeedMph,
    /// A flight condition's mass.
    MassKg,
}

impl BandCondition {
    /// A target's value of it (`None` where its condition does not state it).
    pub fn of(self, t: &fit::Target) -> Option<f64> {
        match (self, &t.condition) {
            (Self::TipSpeedRatio, TargetCondition::Tunnel(s)) => s.tip_speed_ratio,
            (Self::AirspeedMph, TargetCondition::Flight(c, _)) => Some(c.airspeed_mph),
            (Self::MassKg, TargetCondition::Flight(_, l)) => l.mass_kg,
            _ => None,
        }
    }

    /// In words, for a band's name.
    pub fn words(self) -> &'static str {
        match self {
            Self::TipSpeedRatio => "mu",
            Self::AirspeedMph => "airspeed (mph)",
            Self::MassKg => "mass (kg)",
        }
    }
}

/// One band of a cross-validation ([`Bands`]): its name, and the fit's targets and
/// predictions in it, by index.
#[derive(Debug, Clone, PartialEq)]
pub struct CrossValidationBand {
    pub name: String,
    pub fitted: Vec<usize>,
    pub predicted: Vec<usize>,
}

impl Bands {
    /// The fit's bands: an error where a target or prediction does not state the condition,
    /// or where the fitted targets have fewer distinct values of it than bands.
    pub fn of(
        &self,
        targets: &[fit::Target],
        predict: &[fit::Target],
    ) -> Result<Vec<CrossValidationBand>, String> {
        let value = |t: &fit::Target, what: &str, i: usize| {
            self.by.of(t).filter(|v| v.is_finite()).ok_or_else(|| {
                format!(
                    "{what} {} ({}) states no {}: bands cannot hold it",
                    i + 1,
                    t.measure.name(),
                    self.by.words()
                )
            })
        };
        let fitted: Vec<f64> = (targets.iter().enumerate())
            .map(|(i, t)| value(t, "target", i))
            .collect::<Result<_, _>>()?;
        let predicted: Vec<f64> = (predict.iter().enumerate())
            .map(|(i, t)| value(t, "prediction", i))
            .collect::<Result<_, _>>()?;
        let mut xs = fitted.clone();
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        if self.count < 2 || xs.len() < self.count {
            return Err(format!(
                "{} bands of {} over {} distinct fitted values: give at least 2 bands, and at most one per distinct value",
                self.count,
                self.by.words(),
                xs.len()
            ));
        }
        // Run k holds xs[k n / count .. (k + 1) n / count]; its upper edge is halfway to the
        // next run's first value.
        let n = xs.len();
        let starts: Vec<usize> = (0..self.count).map(|k| k * n / self.count).collect();
        let edges: Vec<f64> = starts[1..]
            .iter()
            .map(|&s| 0.5 * (xs[s - 1] + xs[s]))
            .collect();
        let band_of = |x: f64| edges.iter().take_while(|e| x > **e).count();
        let mut bands: Vec<CrossValidationBand> = (0..self.count)
            .map(|_| CrossValidationBand {
                name: String::new(),
                fitted: Vec::new(),
                predicted: Vec::new(),
            })
            .collect();
        for (i, x) in fitted.iter().enumerate() {
            bands[band_of(*x)].fitted.push(i);
        }
        for (i, x) in predicted.iter().enumerate() {
            bands[band_of(*x)].predicted.push(i);
        }
        for b in &mut bands {
            let all = b
                .fitted
                .iter()
                .map(|&i| fitted[i])
                .chain(b.predicted.iter().map(|&i| predicted[i]));
            let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
            b.name = match round3(lo) == round3(hi) {
                true => format!("{} {}", self.by.words(), round3(lo)),
                false => format!("{} {} to {}", self.by.words(), round3(lo), round3(hi)),
            };
        }
        Ok(bands)
    }
}

/// `x` to 3 significant decimals, as a band's name writes it.
fn round3(x: f64) -> String {
    let s = format!("{x:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Where a target's reference comes from (for the before/after table).
#[derive(Debug, Clone, PartialEq)]
pub struct Origin {
    /// `case-id/check-id`, or the written-out source.
    pub label: String,
    /// The tolerance's name and reason, or the source.
    pub reason: String,
}

/// A loaded, checked fit file.
#[derive(Debug, Clone)]
pub struct FitFile {
    pub path: PathBuf,
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    /// The id of the aircraft or rotor file fitted (what the corrections apply to).
    pub applies_to: crate::inputs::corrections::Corrects,
    pub problem: fit::Problem,
    pub origins: Vec<Origin>,
    /// Targets reported but not fitted (the fit's prediction error).
    pub predict: Vec<fit::Target>,
    pub predict_origins: Vec<Origin>,
    /// How the fit is cross-validated, if it is.
    pub cross_validation: Option<CrossValidationSpec>,
    /// How many starts the fit runs from ([`crate::fit::starts`]; 1: the file's own).
    pub starts: usize,
    /// Each physics setting a rotor fit sets over its rotor file's, in words (its report says
    /// so).
    pub physics_overrides: Vec<String>,
}

/// The solver's options and the number of starts from a fit file's `options` (defaults where
/// absent); an error, with its field, for a number of starts out of 1 to
/// [`fit::starts::MAX_STARTS`] or more iterations than
/// [`crate::inputs::limits::MAX_FIT_ITERATIONS`].
fn options_of(
    spec: Option<OptionsSpec>,
) -> Result<(fit::FitOptions, usize), (&'static str, String)> {
    let starts = spec.and_then(|o| o.starts).unwrap_or(1);
    let max = fit::starts::MAX_STARTS;
    if !(1..=max).contains(&starts) {
        return Err((
            "options.starts",
            format!("{starts} starts: give 1 to {max} (each is a whole fit)"),
        ));
    }
    let most = crate::inputs::limits::MAX_FIT_ITERATIONS;
    if let Some(n) = spec.and_then(|o| o.max_iterations).filter(|n| *n > most) {
        return Err((
            "options.max_iterations",
            format!("{n} iterations: give at most {most} (MAX_FIT_ITERATIONS; the default is 20)"),
        ));
    }
    let mut options = fit::FitOptions::default();
    if let Some(o) = spec {
        options.max_iterations = o.max_iterations.unwrap_or(options.max_iterations);
        options.tolerance = o.tolerance.unwrap_or(options.tolerance);
        options.difference_step = o.difference_step.unwrap_or(options.difference_step);
        options.trust_region = o.trust_region.unwrap_or(options.trust_region);
        options.broyden = o.broyden.unwrap_or(options.broyden);
    }
    Ok((options, starts))
}

/// Loads and checks a fit file (and the cases and model files it names).
pub fn load(path: &Path) -> Result<FitFile, InputError> {
    let src = yaml::read(path)?;
    let spec: FitFileSpec = yaml::parse(path, &src)?;
    let err = |field: &str, m: String| InputError::field(path, &src, field, m);
    crate::inputs::reference::check_id(path, &src, &spec.id)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut aircraft_file = None;
    let mut declared = None;
    let mut physics_overrides = Vec::new();
    let (subject, applies_to, subject_key) = match (
        &spec.subject.aircraft,
        &spec.subject.rotor,
        &spec.subject.case,
    ) {
        (None, None, Some(c)) => {
            let e = external_of_case(dir, c).map_err(|m| err("subject.case", m))?;
            let parameters = e.model.parameters().map_err(|m| err("subject.case", m))?;
            declared = Some(parameters);
            (
                fit::FitSubject::Model {
                    model: e.model.clone(),
                },
                crate::inputs::corrections::Corrects::Model(e.written.clone()),
                SubjectKey::Model(e.written.clone(), e.folder.clone(), e.loading),
            )
        }
        (Some(a), None, None) => {
            let file = crate::inputs::aircraft::load(&dir.join(&a.file))?;
            let loading = crate::inputs::condition::Loading {
                mass_kg: a.mass_kg,
                density_altitude_ft: a.density_altitude_ft,
            };
            let key = SubjectKey::Aircraft(file.id.clone(), loading);
            let subject = fit::FitSubject::Aircraft {
                file: Box::new(file.clone()),
            };
            let applies = crate::inputs::corrections::Corrects::Aircraft(file.id.clone());
            aircraft_file = Some(file);
            (subject, applies, key)
        }
        (None, Some(r), None) => {
            let file = crate::inputs::rotor::load(&dir.join(&r.file))?;
            let (physics, notes) = r.physics().over(&file, "the fit");
            physics_overrides = notes;
            let inflow = physics.model();
            let key = SubjectKey::Rotor(file.id.clone(), inflow);
            (
                fit::FitSubject::Rotor {
                    file: Box::new(file.clone()),
                    inflow,
                },
                crate::inputs::corrections::Corrects::Rotor(file.id),
                key,
            )
        }
        _ => {
            return Err(err(
                "subject",
                "give exactly one of `aircraft`, `rotor` or `case` (a case whose model is `external`)".into(),
            ));
        }
    };
    let parameters = spec
        .parameters
        .iter()
        .map(|(name, p)| {
            fit_parameter(name, p, declared.as_deref(), aircraft_file.as_ref())
                .map_err(|m| err(&format!("parameters.{name}"), m))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (options, starts) = options_of(spec.options).map_err(|(f, m)| err(f, m))?;
    let read = |list: &[TargetSpec], section: &str| {
        let mut targets = Vec::new();
        let mut origins = Vec::new();
        for (i, t) in list.iter().enumerate() {
            let here = format!("{section}[{i}]");
            let (ts, os) = targets_of(dir, t, &subject_key).map_err(|m| err(&here, m))?;
            targets.extend(ts);
            origins.extend(os);
        }
        Ok::<_, InputError>((targets, origins))
    };
    let (targets, origins) = read(&spec.targets, "targets")?;
    let (predict, predict_origins) = read(&spec.predict, "predict")?;
    let problem = fit::Problem {
        subject,
        parameters,
        targets,
        options,
        executor: fit::Executor::Local,
    };
    // The problem's own checks (bounds, kinds), as a located input error.
    fit::check(&problem).map_err(|m| err("parameters", m))?;
    check_cross_validation(spec.cross_validation.as_ref(), &origins, &predict_origins)
        .map_err(|(field, m)| err(&format!("cross_validation.{field}"), m))?;
    if let Some(b) = spec.cross_validation.as_ref().and_then(|c| c.bands) {
        b.of(&problem.targets, &predict)
            .map_err(|m| err("cross_validation.bands", m))?;
    }
    Ok(FitFile {
        path: path.to_path_buf(),
        id: spec.id,
        title: spec.title,
        provenance: spec.provenance,
        applies_to,
        problem,
        origins,
        predict,
        predict_origins,
        cross_validation: spec.cross_validation,
        starts,
        physics_overrides,
    })
}

/// A fit file's parameter: a model's declared parameter where the subject is a model behind
/// the model interface (`declared`: what it declares), else a correction (its bounds given,
/// starting uncorrected) or an aircraft file's estimated physical parameter.
fn fit_parameter(
    name: &str,
    p: &ParameterSpec,
    declared: Option<&[crate::external::Parameter]>,
    aircraft_file: Option<&crate::inputs::aircraft::AircraftFile>,
) -> Result<FitParameter, String> {
    let asked = (p.lower, p.upper, p.start);
    let (kind, (lower, upper, start)) = if let Some(declared) = declared {
        (
            ParameterKind::Declared(name.to_string()),
            declared_parameter(declared, name, asked)?,
        )
    } else {
        let Some(kind) = ParameterKind::parse(name) else {
            let names = ParameterKind::names();
            let hint = yaml::nearest(name, &names)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(format!(
                "unknown parameter; one of {}{hint}",
                names.join(", ")
            ));
        };
        let bounds = match kind.neutral() {
            Some(neutral) => {
                let (Some(lower), Some(upper)) = (p.lower, p.upper) else {
                    return Err("a correction needs its bounds, `lower` and `upper`".into());
                };
                (lower, upper, p.start.unwrap_or(neutral))
            }
            None => estimated_parameter(aircraft_file, name, asked)?,
        };
        (kind, bounds)
    };
    Ok(FitParameter {
        kind,
        lower,
        upper,
        start,
        regularisation: p.regularisation,
    })
}

/// A check's id from a target's label (`case-id/check-id`).
pub fn check_of(label: &str) -> String {
    label.rsplit('/').next().unwrap_or(label).to_string()
}

/// A cross-validation's groups and regimes, checked: each group names targets of the fit and
/// leaves some to fit, no check is in two groups, and each regime names targets or predictions.
fn check_cross_validation(
    cv: Option<&CrossValidationSpec>,
    origins: &[Origin],
    predict_origins: &[Origin],
) -> Result<(), (String, String)> {
    let Some(cv) = cv else { return Ok(()) };
    let check_of = |o: &Origin| check_of(&o.label);
    let fitted: Vec<String> = origins.iter().map(check_of).collect();
    let predicted: Vec<String> = predict_origins.iter().map(check_of).collect();
    match (cv.groups.is_empty(), cv.bands.is_some()) {
        (false, true) => {
            return Err(("bands".into(), "give `groups` or `bands`, not both".into()));
        }
        (true, false) => {
            return Err((
                "groups".into(),
                "give `bands` (contiguous bands of one condition, each left out with every row in it) or `groups` of the fitted checks".into(),
            ));
        }
        _ => {}
    }
    if cv.groups.is_empty() {
        return check_regimes(cv, &fitted, &predicted);
    }
    if cv.groups.len() < 2 {
        return Err((
            "groups".into(),
            "give at least two groups to leave out one at a time".into(),
        ));
    }
    let mut seen: Vec<&String> = Vec::new();
    for (i, g) in cv.groups.iter().enumerate() {
        for c in &g.checks {
            if !fitted.contains(c) {
                return Err((
                    format!("groups[{i}].checks"),
                    format!("`{c}` is not a check the fit's targets take"),
                ));
            }
            if seen.contains(&c) {
                return Err((
                    format!("groups[{i}].checks"),
                    format!("`{c}` is in two groups"),
                ));
            }
            seen.push(c);
        }
        if fitted.iter().all(|c| g.checks.contains(c)) {
            return Err((
                format!("groups[{i}]"),
                "the group holds every target: nothing would be left to fit".into(),
            ));
        }
    }
    check_regimes(cv, &fitted, &predicted)
}

/// Each regime names targets or predictions of the fit.
fn check_regimes(
    cv: &CrossValidationSpec,
    fitted: &[String],
    predicted: &[String],
) -> Result<(), (String, String)> {
    for (i, r) in cv.regimes.iter().enumerate() {
        if let Some(c) = r
            .checks
            .iter()
            .find(|c| !fitted.contains(c) && !predicted.contains(c))
        {
            return Err((
                format!("regimes[{i}].checks"),
                format!("`{c}` is neither a target nor a prediction of the fit"),
            ));
        }
    }
    Ok(())
}

/// A physical parameter's bounds and start: the aircraft file must call it estimated and give
/// it a plausible range, which the bounds default to and must lie within; it starts at the
/// file's value.
/// A physical parameter's bounds and start, `(lower, upper, start)`, from the bounds and start
/// asked for (each optional): admitted only where the aircraft file's source for it says
/// estimated and the file gives it a plausible range, which the bounds default to and may not
/// leave; the start defaults to the file's value.
pub fn estimated_parameter(
    file: Option<&crate::inputs::aircraft::AircraftFile>,
    name: &str,
    (lower, upper, start): (Option<f64>, Option<f64>, Option<f64>),
) -> Result<(f64, f64, f64), String> {
    let Some(file) = file else {
        return Err("a physical parameter belongs to an aircraft: the subject is a rotor".into());
    };
    let Some(value) = crate::inputs::parameters::parameter(&file.aircraft, name) else {
        return Err(format!("{} has no `{name}`", file.id));
    };
    let source = file.source_of(name).unwrap_or_default();
    if !source.trim_start().to_lowercase().starts_with("estimated") {
        return Err(format!(
            "{}'s source for `{name}` is not an estimate (\"{source}\"): a fit moves estimated parameters only",
            file.id
        ));
    }
    let Some(range) = file.ranges.get(name) else {
        return Err(format!(
            "{} gives `{name}` no plausible range (`ranges.{name}` with its source): a fit needs bounds from the sources",
            file.id
        ));
    };
    let (lower, upper) = (lower.unwrap_or(range.lower), upper.unwrap_or(range.upper));
    if lower < range.lower || upper > range.upper {
        return Err(format!(
            "bounds [{lower}, {upper}] reach outside {}'s plausible range [{}, {}] ({})",
            file.id, range.lower, range.upper, range.source
        ));
    }
    Ok((lower, upper, start.unwrap_or(value)))
}

/// A declared parameter's bounds and start, `(lower, upper, start)`, from the bounds and start
/// asked for (each optional): the name must be declared; the bounds default to its declared
/// range and may not leave it (a parameter declared without a range needs both bounds); the
/// start defaults to its nominal value.
pub fn declared_parameter(
    declared: &[crate::external::Parameter],
    name: &str,
    (lower, upper, start): (Option<f64>, Option<f64>, Option<f64>),
) -> Result<(f64, f64, f64), String> {
    let Some(p) = declared.iter().find(|p| p.name == name) else {
        let names: Vec<String> = declared.iter().map(|p| p.name.clone()).collect();
        let hint = yaml::nearest(name, &names)
            .map(|n| format!(" (did you mean `{n}`?)"))
            .unwrap_or_default();
        return Err(format!(
            "the model declares no parameter `{name}`{hint}; it declares [{}]",
            names.join(", ")
        ));
    };
    let (lower, upper) = match (&p.range, lower, upper) {
        (Some(r), lower, upper) => {
            let (lower, upper) = (lower.unwrap_or(r.lower), upper.unwrap_or(r.upper));
            if lower < r.lower || upper > r.upper {
                return Err(format!(
                    "bounds [{lower}, {upper}] reach outside the range the model declares for `{name}`, [{}, {}] ({})",
                    r.lower, r.upper, r.source
                ));
            }
            (lower, upper)
        }
        (None, Some(lower), Some(upper)) => (lower, upper),
        (None, _, _) => {
            return Err(format!(
                "the model declares no range for `{name}`: give `lower` and `upper` (and their source in the file's provenance)"
            ));
        }
    };
    Ok((lower, upper, start.unwrap_or(p.nominal)))
}

/// The model a case checks, where it is one behind the model interface (`external` or
/// `files`).
fn external_of_case(dir: &Path, file: &str) -> Result<crate::external::External, String> {
    let c = case::load(&dir.join(file)).map_err(|e| format!("the case {file}: {}", e.render()))?;
    match c.subject {
        case::Subject::External(e) => Ok(*e),
        other => Err(format!(
            "the case {file} checks {}: `subject.case` names a case whose model is `external` (cierva's own aircraft and rotors are `aircraft` and `rotor` subjects)",
            other.describe()
        )),
    }
}

/// What a case's subject must match: the same file (aircraft; each case flies at its own
/// loading), the same file and inflow (rotor), or the same model (one behind the model
/// interface: its command or files as written, from the same folder). The aircraft's or the
/// model's loading is the one written-out targets fly at.
#[derive(Debug, Clone, PartialEq)]
enum SubjectKey {
    Aircraft(String, crate::inputs::condition::Loading),
    Rotor(String, cierva_model::components::rotor::InflowModel),
    Model(String, PathBuf, crate::inputs::condition::Loading),
}

fn targets_of(
    dir: &Path,
    t: &TargetSpec,
    subject: &SubjectKey,
) -> Result<(Vec<fit::Target>, Vec<Origin>), String> {
    let written = t.condition.is_some()
        || t.tunnel.is_some()
        || t.quantity.is_some()
        || t.reference.is_some()
        || t.standard_error.is_some()
        || t.bounds.is_some();
    match (&t.case, written) {
        (Some(c), false) => from_case(dir, c, t, subject),
        (None, true) => {
            if t.checks.is_some()
                || t.quantities.is_some()
                || t.case_bounds.is_some()
                || t.soft_weight.is_some()
            {
                return Err(
                    "`checks`, `quantities`, `case_bounds` and `soft_weight` go with `case`".into(),
                );
            }
            let condition = match (t.condition, t.tunnel, subject) {
                (
                    Some(c),
                    None,
                    SubjectKey::Aircraft(_, loading) | SubjectKey::Model(.., loading),
                ) => TargetCondition::Flight(c, *loading),
                (Some(_), None, SubjectKey::Rotor(..)) => {
                    return Err("a rotor alone is fitted at `tunnel` conditions, not in flight".into());
                }
                (None, Some(tu), _) => TargetCondition::Tunnel(tu),
                _ => return Err("give exactly one of `condition` (flight) or `tunnel`".into()),
            };
            let (Some(q), Some(reference), Some(standard_error)) =
                (&t.quantity, t.reference, t.standard_error)
            else {
                return Err("a written-out target needs `quantity`, `reference` and `standard_error`".into());
            };
            let source = t
                .source
                .clone()
                .ok_or("a written-out target needs its `source` (every number has one)")?;
            let measure = Measure::parse(&condition, q)?;
            let bounds = t.bounds.map(|b| Bounds {
                lower: b.lower,
                upper: b.upper,
                enforce: match b.enforce {
                    EnforceSpec::Hard => Enforce::Hard,
                    EnforceSpec::Soft { weight } => Enforce::Soft { weight },
                },
            });
            Ok((
                vec![fit::Target {
                    condition,
                    measure,
                    reference,
                    standard_error,
                    bounds,
                }],
                vec![Origin {
                    label: format!("{} at {}", q, condition.label()),
                    reason: source,
                }],
            ))
        }
        _ => Err("give either `case` (with optional `checks` and `quantities`) or a written-out target (`condition` or `tunnel`, `quantity`, `reference`, `standard_error`, `source`)".into()),
    }
}

/// A case's checks as fit targets (those `t` names, or every derivative, trim and autorotation
/// check at one condition on the model as it is), each expectation's tolerance giving the
/// reference, the standard error and any bounds.
fn from_case(
    dir: &Path,
    file: &str,
    t: &TargetSpec,
    subject: &SubjectKey,
) -> Result<(Vec<fit::Target>, Vec<Origin>), String> {
    let (c, case_loading) = case_of(dir, file, subject)?;
    if let Some(ids) = &t.checks {
        for id in ids {
            if !c.checks.iter().any(|k| &k.id == id) {
                let have: Vec<String> = c.checks.iter().map(|k| k.id.clone()).collect();
                let hint = yaml::nearest(id, &have)
                    .map(|n| format!(" (did you mean `{n}`?)"))
                    .unwrap_or_default();
                return Err(format!("the case {file} has no check `{id}`{hint}"));
            }
        }
    }
    let weight = t.soft_weight.unwrap_or(1.0);
    let enforce = match t.case_bounds.unwrap_or_default() {
        CaseBounds::None => None,
        CaseBounds::Hard => Some(Enforce::Hard),
        CaseBounds::Soft => Some(Enforce::Soft { weight }),
    };
    let mut targets = Vec::new();
    let mut origins = Vec::new();
    for check in &c.checks {
        if t.checks
            .as_ref()
            .is_some_and(|ids| !ids.contains(&check.id))
        {
            continue;
        }
        let condition = match (check.behaviour().measured(), case_loading) {
            (Measured::At(Place::Flight(cond)), Some(loading)) => {
                TargetCondition::Flight(cond, loading)
            }
            (Measured::At(Place::Tunnel(tunnel)), _) => TargetCondition::Tunnel(*tunnel),
            (Measured::Modified, _) if t.checks.is_some() => {
                return Err(format!(
                    "check `{}` of {file} sets its own corrections or derivatives, or checks a ratio or an identified model: it is not a reference to fit",
                    check.id
                ));
            }
            _ if t.checks.is_some() => {
                return Err(format!(
                    "check `{}` of {file} is not a derivative, trim or autorotation check at one condition",
                    check.id
                ));
            }
            _ => continue,
        };
        for e in &check.expectations {
            if t.quantities
                .as_ref()
                .is_some_and(|qs| !qs.contains(&e.quantity))
            {
                continue;
            }
            let Some(name) = check.behaviour().model_name(&e.quantity) else {
                continue;
            };
            let measure = Measure::parse(&condition, &name)
                .map_err(|m| format!("check `{}` of {file}: {m}", check.id))?;
            let (reference, standard_error, bounds) = scale_of(e, enforce)
                .map_err(|m| format!("check `{}` of {file}, `{}`: {m}", check.id, e.quantity))?;
            targets.push(fit::Target {
                condition,
                measure,
                reference,
                standard_error,
                bounds,
            });
            origins.push(Origin {
                label: format!("{}/{}", c.id, check.id),
                reason: format!("{}: {}", e.tolerance.name, e.tolerance.reason),
            });
        }
    }
    if targets.is_empty() {
        return Err(format!(
            "no targets from {file}: no derivative, trim or autorotation check there has the quantities asked for"
        ));
    }
    Ok((targets, origins))
}

/// The case a target names, with its loading (an aircraft's), where it checks this fit's
/// subject (an aircraft by its file, whatever the loading; a rotor by its file and inflow).
fn case_of(
    dir: &Path,
    file: &str,
    subject: &SubjectKey,
) -> Result<(case::Case, Option<crate::inputs::condition::Loading>), String> {
    let path = dir.join(file);
    let c = case::load(&path).map_err(|e| format!("the case {file}: {}", e.render()))?;
    let (key, case_loading) = match &c.subject {
        case::Subject::Aircraft { file, loading } => (
            SubjectKey::Aircraft(file.id.clone(), *loading),
            Some(*loading),
        ),
        case::Subject::Rotor { file, solver, .. } => {
            (SubjectKey::Rotor(file.id.clone(), solver.inflow), None)
        }
        case::Subject::External(e) => (
            SubjectKey::Model(e.written.clone(), e.folder.clone(), e.loading),
            Some(e.loading),
        ),
        _ => {
            return Err(format!(
                "the case {file} checks neither an aircraft, a rotor nor a model behind the model interface"
            ));
        }
    };
    let same = match (&key, subject) {
        (SubjectKey::Aircraft(a, _), SubjectKey::Aircraft(b, _)) => a == b,
        (SubjectKey::Model(a, f, _), SubjectKey::Model(b, g, _)) => a == b && f == g,
        _ => key == *subject,
    };
    if !same {
        return Err(format!(
            "the case {file} checks {key:?}, but this fit's subject is {subject:?}"
        ));
    }
    Ok((c, case_loading))
}

/// A check expectation's reference, standard error and bounds from its tolerance: an absolute
/// tolerance is the standard error, a relative one times the value; an interval gives its
/// midpoint, its half-width over 1.96, and bounds enforced as `enforce` says (`None`: none).
fn scale_of(
    e: &crate::checks::Expectation,
    enforce: Option<Enforce>,
) -> Result<(f64, f64, Option<Bounds>), String> {
    match (e.tolerance.kind.clone(), e.value) {
        (ToleranceKind::Absolute(a), Some(v)) => Ok((v, a, None)),
        (ToleranceKind::Relative(r), Some(v)) => Ok((v, r * v.abs(), None)),
        (ToleranceKind::Interval(lo, hi), _) => Ok((
            0.5 * (lo + hi),
            0.5 * (hi - lo) / 1.96,
            enforce.map(|enforce| Bounds {
                lower: lo,
                upper: hi,
                enforce,
            }),
        )),
        (k, _) => Err(format!(
            "a {k:?} tolerance gives no standard error to fit with (absolute, relative or interval tolerances do)"
        )),
    }
}

/// A longitudinal mode's eigenvalue before and after the fit at one flight condition.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ModeShift {
    pub condition: String,
    pub mode: &'static str,
    /// `[re, im]`, 1/s and rad/s; NaN where the model has no such mode.
    pub before: [f64; 2],
    pub after: [f64; 2],
}

/// A fit file's run: the fit, the predictions before and after, and (for an aircraft) how the
/// longitudinal modes moved.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FitRun {
    pub result: fit::FitResult,
    pub seconds: f64,
    pub predict_before: Vec<f64>,
    pub predict_after: Vec<f64>,
    pub modes: Vec<ModeShift>,
    /// The fit's starts, where the file asks for more than one.
    pub starts: Option<crate::fit::starts::Starts>,
    /// The targets' scatter against their standard errors, and the factor the standard errors
    /// were scaled by (`None`: no degree of freedom left).
    pub birge: Option<fit::Birge>,
}

impl FitFile {
    /// The fit's problem with its predictions as the targets: what the fitted values are
    /// evaluated on to report the data the fit did not see.
    pub fn prediction_problem(&self) -> fit::Problem {
        let mut p = self.problem.clone();
        p.targets = self.predict.clone();
        p
    }
}

/// Runs a fit file's fit, then its predictions and mode shifts.
pub fn run(f: &FitFile) -> FitRun {
    let started = std::time::Instant::now();
    let (mut result, starts) = if f.starts > 1 {
        let (r, s) = crate::fit::starts::fit_from_starts(&f.problem, f.starts, |_| {});
        (r, Some(s))
    } else {
        (fit::fit(&f.problem), None)
    };
    let birge = fit::scale_by_birge(&f.problem, &mut result);
    let seconds = started.elapsed().as_secs_f64();
    let start: Vec<f64> = f.problem.parameters.iter().map(|p| p.start).collect();
    let mut predict_before = vec![f64::NAN; f.predict.len()];
    let mut predict_after = predict_before.clone();
    if !f.predict.is_empty() {
        let p = f.prediction_problem();
        predict_before = fit::values_or_nan(&p, &start);
        predict_after = fit::values_or_nan(&p, &result.values);
    }
    let mut conditions: Vec<(
        crate::inputs::condition::TrimRequest,
        crate::inputs::condition::Loading,
    )> = Vec::new();
    for t in &f.problem.targets {
        if let TargetCondition::Flight(c, l) = t.condition
            && !conditions.contains(&(c, l))
        {
            conditions.push((c, l));
        }
    }
    // The linear model at parameter values `values` and a flight condition, where the subject
    // flies and the model solves.
    let linear = |values: &[f64],
                  (c, loading): (
        crate::inputs::condition::TrimRequest,
        crate::inputs::condition::Loading,
    )|
     -> Option<cierva_model::LinearModel> {
        let model = f.problem.subject.flight_model()?;
        let request = crate::external::Request {
            parameters: f.problem.declared_values(values),
            ..crate::external::Request::at(c, loading)
        };
        model.linear_model(&request).ok()
    };
    let eig = |values: &[f64], at| {
        let analysis =
            linear(values, at).and_then(|lin| cierva_model::analysis::modes::modes(&lin).ok());
        [
            cierva_model::analysis::modes::ModeKind::Phugoid,
            cierva_model::analysis::modes::ModeKind::ShortPeriod,
        ]
        .map(|k| {
            analysis
                .as_ref()
                .and_then(|m| {
                    m.of_kind(k)
                        .next()
                        .map(|m| [m.eigenvalue.re, m.eigenvalue.im])
                })
                .unwrap_or([f64::NAN; 2])
        })
    };
    let mut modes = Vec::new();
    for c in conditions {
        let (b, a) = (eig(&start, c), eig(&result.values, c));
        for (k, name) in ["phugoid", "short_period"].into_iter().enumerate() {
            modes.push(ModeShift {
                condition: TargetCondition::Flight(c.0, c.1).label(),
                mode: name,
                before: b[k],
                after: a[k],
            });
        }
    }
    FitRun {
        result,
        seconds,
        starts,
        predict_before,
        predict_after,
        modes,
        birge,
    }
}

/// RMS of `(model - reference) / reference`, %, before and after, over the targets with a
/// non-zero reference that the model solved both before and after (so the two compare like
/// with like), and how many that is.
pub fn rms_relative_error_percent(
    targets: &[fit::Target],
    before: &[f64],
    after: &[f64],
) -> (f64, f64, usize) {
    let rows: Vec<(f64, f64)> = targets
        .iter()
        .zip(before.iter().zip(after))
        .filter(|(t, (b, a))| t.reference != 0.0 && b.is_finite() && a.is_finite())
        .map(|(t, (b, a))| {
            (
                (b - t.reference) / t.reference,
                (a - t.reference) / t.reference,
            )
        })
        .collect();
    let rms = |f: fn(&(f64, f64)) -> f64| {
        100.0 * (rows.iter().map(|r| f(r).powi(2)).sum::<f64>() / rows.len() as f64).sqrt()
    };
    (rms(|r| r.0), rms(|r| r.1), rows.len())
}

/// A fit's errors over a set of targets (fitted or predicted): the RMS relative error before
/// and after over all of them and per quantity, and how many the model did not solve. The
/// report prints it, and the corrections file keeps it (`fit.errors`) so that documents can
/// quote it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ErrorSummary {
    /// Targets solved before and after, with a non-zero reference.
    pub targets: usize,
    /// Every target, solved or not: what the unsolved counts are a rate of.
    pub of: usize,
    pub rms_before_percent: f64,
    pub rms_after_percent: f64,
    pub unsolved_before: usize,
    pub unsolved_after: usize,
    /// Per quantity (by its name), where there are several.
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub by_quantity: std::collections::BTreeMap<String, ErrorSummary>,
}

impl ErrorSummary {
    /// Its RMS errors and, beside them, the targets the model did not solve as a rate of all
    /// (an RMS over the solved targets alone improves when the worst stop solving):
    /// "9.19 % before, 12.03 % after over 112 solved; not solved: 12 of 171 (7.0 %) before,
    /// 42 of 171 (24.6 %) after".
    pub fn line(&self) -> String {
        let rate = |n: usize| {
            format!(
                "{n} of {} ({:.1} %)",
                self.of,
                100.0 * n as f64 / self.of.max(1) as f64
            )
        };
        format!(
            "{:.2} % before, {:.2} % after over {} solved; not solved: {} before, {} after",
            self.rms_before_percent,
            self.rms_after_percent,
            self.targets,
            rate(self.unsolved_before),
            rate(self.unsolved_after)
        )
    }

    pub fn of(targets: &[fit::Target], before: &[f64], after: &[f64]) -> Self {
        let mut names: Vec<&str> = targets.iter().map(|t| t.measure.name()).collect();
        names.sort_unstable();
        names.dedup();
        let mut whole = Self::one(targets, before, after);
        if names.len() > 1 {
            for name in names {
                let keep: Vec<usize> = (0..targets.len())
                    .filter(|&k| targets[k].measure.name() == name)
                    .collect();
                let pick = |y: &[f64]| keep.iter().map(|&k| y[k]).collect::<Vec<f64>>();
                let sub: Vec<fit::Target> = keep.iter().map(|&k| targets[k].clone()).collect();
                whole.by_quantity.insert(
                    name.to_string(),
                    Self::one(&sub, &pick(before), &pick(after)),
                );
            }
        }
        whole
    }

    fn one(targets: &[fit::Target], before: &[f64], after: &[f64]) -> Self {
        let unsolved = |y: &[f64]| y.iter().filter(|v| !v.is_finite()).count();
        let (rb, ra, n) = rms_relative_error_percent(targets, before, after);
        Self {
            targets: n,
            of: targets.len(),
            rms_before_percent: rb,
            rms_after_percent: ra,
            unsolved_before: unsolved(before),
            unsolved_after: unsolved(after),
            by_quantity: Default::default(),
        }
    }
}

/// The corrections file a fit writes (id: the output file's stem).
pub fn corrections_file(
    f: &FitFile,
    run: &FitRun,
    id: &str,
    command: &str,
) -> crate::inputs::corrections::CorrectionsFileSpec {
    use crate::inputs::corrections::{AppliesTo, CorrectionsFileSpec};
    let r = &run.result;
    let se: serde_json::Map<String, serde_json::Value> = r
        .parameters
        .iter()
        .zip(&r.standard_errors)
        .map(|(k, s)| (k.name().to_string(), serde_json::json!(finite_or_null(*s))))
        .collect();
    CorrectionsFileSpec {
        id: id.to_string(),
        title: format!("Corrections fitted by {}: {}", f.id, f.title),
        applies_to: AppliesTo::from(&f.applies_to),
        corrections: r.corrections(),
        provenance: Provenance {
            source: format!(
                "fitted by `{command}` (cierva {})",
                env!("CARGO_PKG_VERSION")
            ),
            notes: Some(format!(
                "Fit file {}: {}",
                f.path.display(),
                f.provenance.source
            )),
        },
        fit: Some(serde_json::json!({
            "status": r.status.name(),
            "detail": r.status.detail(),
            "iterations": r.iterations,
            "evaluations": r.evaluations,
            "cost_start": finite_or_null(r.cost_start),
            "cost": finite_or_null(r.cost),
            "standard_errors": se,
            "chi_square": run.birge.map(|b| b.chi_square),
            "degrees_of_freedom": run.birge.map(|b| b.degrees_of_freedom),
            "standard_errors_scaled_by": run.birge.map(|b| b.factor),
            "targets": f.problem.targets.len(),
            "warnings": r.warnings,
            "errors": {
                "fitted": ErrorSummary::of(&f.problem.targets, &r.before, &r.after),
                "predicted": (!f.predict.is_empty()).then(|| {
                    ErrorSummary::of(&f.predict, &run.predict_before, &run.predict_after)
                }),
            },
        }))
        .map(|mut fit| {
            if let (Some(s), Some(m)) = (&run.starts, fit.as_object_mut()) {
                m.insert("starts".into(), serde_json::json!(s));
            }
            fit
        }),
        cross_validation: None,
        not_applied_to: vec![],
        domain: Some(domain_of(&f.problem.targets)),
        calibrated_on: calibrated_on(&f.origins),
        posterior: fit::posterior(&f.problem, r),
    }
}

/// The checks a fit's targets come from, by case (an origin `case-id/check-id`; a written-out
/// target names no check).
pub fn calibrated_on(origins: &[Origin]) -> std::collections::BTreeMap<String, Vec<String>> {
    let mut by_case: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    for o in origins {
        if let Some((case, check)) = o.label.split_once('/') {
            let checks = by_case.entry(case.to_string()).or_default();
            if !checks.iter().any(|c| c == check) {
                checks.push(check.to_string());
            }
        }
    }
    by_case
}

/// The span of the conditions `targets` were fitted at: what a corrections file states as its
/// domain ([`crate::inputs::corrections::Domain`]).
pub fn domain_of(targets: &[fit::Target]) -> crate::inputs::corrections::Domain {
    use crate::inputs::corrections::Domain;
    let tunnels = || {
        targets.iter().filter_map(|t| match &t.condition {
            TargetCondition::Tunnel(s) => Some(s),
            TargetCondition::Flight(..) => None,
        })
    };
    let flights = || {
        targets.iter().filter_map(|t| match &t.condition {
            TargetCondition::Flight(c, l) => Some((c, l)),
            TargetCondition::Tunnel(_) => None,
        })
    };
    Domain {
        tip_speed_ratio: Domain::span(tunnels().filter_map(|s| s.tip_speed_ratio)),
        tunnel_airspeed_m_s: Domain::span(tunnels().filter_map(|s| s.airspeed_m_s)),
        airspeed_mph: Domain::span(flights().map(|(c, _)| c.airspeed_mph)),
        mass_kg: Domain::span(flights().filter_map(|(_, l)| l.mass_kg)),
    }
}

fn finite_or_null(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}
