//! Case files: what is checked, against what, with which tolerance and why.
//!
//! The schema is documented with an example in docs/writing-cases.md. Every field is
//! checked: unknown fields are rejected, a tolerance must have a reason, an expectation must
//! name a quantity that its check kind computes, and a check that is expected to fail says why.

pub use crate::checks::subject::{
    AircraftModelSpec, DescentSpec, FlapRecordSpec, InflowSpec, ModelSpec, RotorModelSpec,
    SkewSpec, Subject, TableColumnSpec,
};
pub use crate::checks::tolerance::{RoundingSpec, Sign, Tolerance, ToleranceKind};
pub use crate::checks::{Check, CheckClass, CheckKind, CheckSpec, ExpectSpec, Expectation, System};
pub use crate::inputs::condition::TunnelSpec;
use crate::inputs::reference::{self, Entry, Provenance};
use crate::inputs::yaml::{self, InputError};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A case file as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    pub id: String,
    pub title: String,
    /// What the case's checks are evidence of (a check may say otherwise for itself).
    pub class: CheckClass,
    pub provenance: Provenance,
    pub model: ModelSpec,
    #[serde(default)]
    pub tolerances: BTreeMap<String, ToleranceSpec>,
    /// Each check as written: what every check has ([`CheckSpec`]) and its kind's own fields,
    /// read by its kind.
    pub checks: Vec<serde_yaml::Mapping>,
    /// The data set's scores on the scoreboard (see [`crate::suite::scoreboard`]).
    #[serde(default)]
    pub scores: Vec<crate::suite::scoreboard::ScoreSpec>,
    /// A sensitivity study for the report (an aircraft case): what would close each
    /// discrepancy (see [`crate::fit::sensitivity`]).
    #[serde(default)]
    pub sensitivity: Option<SensitivitySpec>,
}

/// A case's sensitivity study as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensitivitySpec {
    /// The parameters to move (default: those the aircraft file gives plausible ranges).
    #[serde(default)]
    pub parameters: Option<Vec<String>>,
}

/// A named tolerance as written: exactly one of the kinds, and a reason.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToleranceSpec {
    #[serde(default)]
    pub absolute: Option<f64>,
    #[serde(default)]
    pub relative: Option<f64>,
    #[serde(default)]
    pub interval: Option<[f64; 2]>,
    #[serde(default)]
    pub interval_from: Option<TableColumnSpec>,
    #[serde(default)]
    pub rounding: Option<RoundingSpec>,
    /// The same sign as the expected value and within this factor of it (> 1).
    #[serde(default)]
    pub factor: Option<f64>,
    /// Strictly positive or strictly negative (no expected value).
    #[serde(default)]
    pub sign: Option<Sign>,
    /// For an interval that is a confidence interval of the measurement: its level (0.95 for a
    /// 95 % flight bound). The data's standard uncertainty is then the half-width over the
    /// normal quantile (`cierva uncertainty`).
    #[serde(default)]
    pub confidence: Option<f64>,
    /// For an `absolute` or `relative` tolerance: the measurement's standard deviation, in the
    /// tolerance's own terms (a fraction of the value for `relative`), from repeat runs. The
    /// data's standard uncertainty (`cierva uncertainty`).
    #[serde(default)]
    pub standard_deviation: Option<f64>,
    /// With a `standard_deviation`: the degrees of freedom it was estimated with (repeat pairs
    /// pooled: one per pair). The comparison's coverage factor then follows Student's t at the
    /// effective degrees of freedom (Welch-Satterthwaite) instead of 2.
    #[serde(default)]
    pub degrees_of_freedom: Option<f64>,
    pub reason: String,
}

/// A loaded, checked case.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub path: PathBuf,
    pub id: String,
    pub title: String,
    /// The class of its checks, where a check does not say otherwise.
    pub class: CheckClass,
    pub provenance: Provenance,
    pub subject: Subject,
    pub checks: Vec<Check>,
    /// What the model gave for the case's expected failures (see [`crate::suite::discrepancy`]).
    pub recorded: Option<crate::suite::discrepancy::CaseRecord>,
    /// The folder of records of the suite that holds the case
    /// ([`crate::suite::Suite::containing`]); `None` when no suite holds it.
    pub records_dir: Option<PathBuf>,
    /// The data set's scores.
    pub scores: Vec<crate::suite::scoreboard::ScoreSpec>,
    /// The parameters of a sensitivity study `validate` runs for the report, if the case asks
    /// for one.
    pub sensitivity: Option<Vec<String>>,
    /// Checks that run on the subject as it was before corrections were applied (a corrections
    /// file's `not_applied_to`): set by [`with_corrections`], `None` as loaded.
    pub uncorrected: Option<Uncorrected>,
    /// The calibrations applied to the subject (corrections files, by id), with their stated
    /// predictive errors: set by [`with_corrections`], empty as loaded.
    pub calibrations: Vec<Calibration>,
}

/// A corrections file applied to a case's subject, and what it states of its predictions.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    pub id: String,
    /// The case's checks outside the domain the file was fitted on, each with why
    /// ([`crate::inputs::corrections::Domain`]): run with the corrections, labelled an
    /// extrapolation.
    pub extrapolated: BTreeMap<String, String>,
    /// The case's checks the file was fitted to (its `calibrated_on` for this case), with the
    /// corrections applied: no evidence for them.
    pub calibrated_on: std::collections::BTreeSet<String>,
    /// `None`: its fit was not cross-validated, so it states no predictive error.
    pub predictive_error: Option<crate::inputs::corrections::PredictiveError>,
    /// Its fitted parameters' joint distribution, where its fit stated one: what an
    /// uncertainty study samples them from.
    pub posterior: Option<crate::inputs::corrections::Posterior>,
}

/// The checks of a corrected case that keep the uncorrected subject, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Uncorrected {
    pub subject: Subject,
    pub checks: std::collections::BTreeSet<String>,
    /// One line per corrections file and regime: which, and why.
    pub reasons: Vec<String>,
}

impl Case {
    /// The subject a check runs on: the uncorrected one for a check a corrections file is not
    /// applied to, else the case's.
    pub fn subject_of(&self, check: &str) -> &Subject {
        match &self.uncorrected {
            Some(u) if u.checks.contains(check) => &u.subject,
            _ => &self.subject,
        }
    }
}

/// Loads and checks a case file.
pub fn load(path: &Path) -> Result<Case, InputError> {
    let src = yaml::read(path)?;
    let spec: CaseSpec = yaml::parse(path, &src)?;
    reference::check_id(path, &src, &spec.id)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let err = |field: &str, msg: String| InputError::field(path, &src, field, msg);
    if spec.provenance.source.trim().is_empty() {
        return Err(err(
            "provenance.source",
            "the source must not be empty".into(),
        ));
    }

    let library = match find_library(dir) {
        Some(p) => Some(load_library(&p)?),
        None => None,
    };
    if let Some(lib) = &library
        && let Some(name) = spec
            .tolerances
            .keys()
            .find(|n| lib.tolerances.contains_key(*n))
    {
        return Err(err(
            &format!("tolerances.{name}"),
            format!(
                "`{name}` is a shared tolerance ({}): use it as it is, or give yours another name",
                lib.path.display()
            ),
        ));
    }
    let subject = crate::checks::subject::load(path, &src, dir, &spec.model)?;
    let mut seen = std::collections::BTreeSet::new();
    let mut checks = Vec::new();
    if spec.checks.is_empty() {
        return Err(err("checks", "a case needs at least one check".into()));
    }
    for (i, written) in spec.checks.iter().enumerate() {
        let here = format!("checks[{i}]");
        let (c, own) = crate::checks::split_written(path, &src, &here, written.clone())?;
        let c = &c;
        if !seen.insert(c.id.clone()) {
            return Err(err(
                &format!("{here}.id"),
                format!("check id `{}` is used twice", c.id),
            ));
        }
        if c.id.contains("::") || c.id.contains("__") || c.id.trim().is_empty() {
            return Err(err(
                &format!("{here}.id"),
                "a check id must be non-empty and contain neither `::` nor `__`".into(),
            ));
        }
        let cx = crate::checks::Cx {
            path,
            src: &src,
            dir,
            subject: &subject,
            here: &here,
            kind: c.kind,
            class: c.class.unwrap_or(spec.class),
        };
        let tolerance = |field: &str, name: &str, derivative: Option<&str>| {
            resolve_tolerance(
                path,
                &src,
                dir,
                &spec,
                library.as_ref(),
                field,
                name,
                derivative,
            )
        };
        checks.push(crate::checks::resolve(&cx, c, own, &tolerance)?);
    }
    crate::checks::refuse_reference_mean(&checks)
        .map_err(|(i, msg)| err(&format!("checks[{i}].expect"), msg))?;
    check_scores(path, &src, &spec, &checks)?;
    let sensitivity = check_sensitivity(path, &src, &spec, &subject)?;
    let records_dir = crate::suite::Suite::containing(path)?.map(|s| s.discrepancies());
    let recorded = match &records_dir {
        Some(dir) => crate::suite::discrepancy::load(dir, &spec.id)?,
        None => None,
    };
    Ok(Case {
        path: path.to_path_buf(),
        id: spec.id,
        title: spec.title,
        class: spec.class,
        provenance: spec.provenance,
        subject,
        checks,
        recorded,
        records_dir,
        scores: spec.scores,
        sensitivity,
        uncorrected: None,
        calibrations: vec![],
    })
}

/// A sensitivity study's parameters: a case of a flight model (an aircraft, or an external
/// model that declares parameters), parameters the model declares (default: those it declares
/// a plausible range for, which must then exist). An external model is asked its `describe`
/// here, so that a study it cannot run is an input error.
fn check_sensitivity(
    path: &Path,
    src: &str,
    spec: &CaseSpec,
    subject: &Subject,
) -> Result<Option<Vec<String>>, InputError> {
    let Some(s) = &spec.sensitivity else {
        return Ok(None);
    };
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let Some((model, _)) = crate::checks::flight_model(subject) else {
        return Err(err(
            "sensitivity",
            "a sensitivity study moves a flight model's parameters: give it in a case of an \
             aircraft or an external model"
                .into(),
        ));
    };
    let declared = model.parameters().map_err(|e| err("sensitivity", e))?;
    let names: Vec<String> = match &s.parameters {
        Some(p) => p.clone(),
        None => crate::external::ranged_names(&declared),
    };
    if names.is_empty() {
        return Err(err(
            "sensitivity",
            format!(
                "name the `parameters`: {} declares no plausible ranges to take them from",
                model.describe()
            ),
        ));
    }
    for (i, n) in names.iter().enumerate() {
        if !declared.iter().any(|p| &p.name == n) {
            return Err(err(
                &format!("sensitivity.parameters[{i}]"),
                format!("`{n}` is not a parameter {} declares", model.describe()),
            ));
        }
    }
    Ok(Some(names))
}

/// A case's scores: unique ids, a noise floor, a reason, and a quantity that a check expects
/// where the metric needs one.
fn check_scores(
    path: &Path,
    src: &str,
    spec: &CaseSpec,
    checks: &[Check],
) -> Result<(), InputError> {
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let mut ids = std::collections::BTreeSet::new();
    for (i, sc) in spec.scores.iter().enumerate() {
        let here = format!("scores[{i}]");
        if !ids.insert(sc.id.clone()) || sc.id.contains("::") || sc.id.trim().is_empty() {
            return Err(err(
                &format!("{here}.id"),
                format!("score id `{}` is empty, used twice or contains `::`", sc.id),
            ));
        }
        if !(sc.noise_floor.is_finite() && sc.noise_floor >= 0.0) {
            return Err(err(
                &format!("{here}.noise_floor"),
                format!("must be finite and >= 0, got {}", sc.noise_floor),
            ));
        }
        if sc.reason.trim().is_empty() {
            return Err(err(
                &format!("{here}.reason"),
                "every score needs a reason".into(),
            ));
        }
        let scored: Vec<&Check> = match &sc.checks {
            None => checks.iter().collect(),
            Some(ids) => {
                if let Some(missing) = ids.iter().find(|id| !checks.iter().any(|c| &c.id == *id)) {
                    return Err(err(
                        &format!("{here}.checks"),
                        format!("the case has no check `{missing}`"),
                    ));
                }
                checks.iter().filter(|c| ids.contains(&c.id)).collect()
            }
        };
        match (&sc.quantity, sc.metric.needs_quantity()) {
            (None, true) => {
                return Err(err(
                    &here,
                    format!("a `{:?}` score needs a `quantity`", sc.metric),
                ));
            }
            (Some(q), _)
                if !scored
                    .iter()
                    .any(|c| c.expectations.iter().any(|e| &e.quantity == q)) =>
            {
                return Err(err(
                    &format!("{here}.quantity"),
                    format!("no check the score is over expects `{q}`"),
                ));
            }
            _ => {}
        }
        if sc.metric == crate::suite::scoreboard::Metric::PeakTipSpeedRatioOffset
            && let Some(c) = scored.iter().find(|c| c.tunnel_tip_speed_ratio().is_none())
        {
            return Err(err(
                &format!("{here}.metric"),
                format!(
                    "check `{}` states no tunnel `tip_speed_ratio` to place a peak at",
                    c.id
                ),
            ));
        }
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn resolve_tolerance(
    path: &Path,
    src: &str,
    dir: &Path,
    spec: &CaseSpec,
    library: Option<&Library>,
    field: &str,
    name: &str,
    derivative: Option<&str>,
) -> Result<Tolerance, InputError> {
    let Some(t) = spec.tolerances.get(name) else {
        if let Some(t) = library.and_then(|l| l.tolerances.get(name)) {
            return Ok(t.clone());
        }
        let mut names: Vec<String> = spec.tolerances.keys().cloned().collect();
        let shared: Vec<String> = library
            .map(|l| l.tolerances.keys().cloned().collect())
            .unwrap_or_default();
        let hint = crate::inputs::yaml::nearest(name, &[names.clone(), shared.clone()].concat())
            .map(|n| format!(" (did you mean `{n}`?)"))
            .unwrap_or_default();
        names.sort();
        return Err(InputError::field(
            path,
            src,
            &format!("{field}.tolerance"),
            format!(
                "no tolerance named `{name}`{hint}; the case defines [{}] and the shared library [{}]",
                names.join(", "),
                shared.join(", ")
            ),
        ));
    };
    tolerance_of(path, src, dir, t, derivative, field, name)
}

/// A tolerance as written, checked: exactly one kind, sound numbers, a reason. `derivative` is
/// the check's derivative, for a tolerance that takes its interval from a derivative table
/// (`None` in the shared library, which refuses those).
fn tolerance_of(
    path: &Path,
    src: &str,
    dir: &Path,
    t: &ToleranceSpec,
    derivative: Option<&str>,
    field: &str,
    name: &str,
) -> Result<Tolerance, InputError> {
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let tfield = format!("tolerances.{name}");
    if t.reason.trim().is_empty() {
        return Err(err(
            &format!("{tfield}.reason"),
            "every tolerance needs a reason".into(),
        ));
    }
    let kinds = [
        t.absolute.is_some(),
        t.relative.is_some(),
        t.interval.is_some(),
        t.interval_from.is_some(),
        t.rounding.is_some(),
        t.factor.is_some(),
        t.sign.is_some(),
    ];
    if kinds.iter().filter(|k| **k).count() != 1 {
        return Err(err(
            &tfield,
            "give exactly one of `absolute`, `relative`, `interval`, `interval_from`, `rounding`, `factor` or `sign`"
                .into(),
        ));
    }
    let positive = |v: f64, key: &str| -> Result<f64, InputError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(err(
                &format!("{tfield}.{key}"),
                format!("must be finite and >= 0, got {v}"),
            ))
        }
    };
    let kind = if let Some(sign) = t.sign {
        ToleranceKind::Sign(sign)
    } else if let Some(f) = t.factor {
        if !(f.is_finite() && f > 1.0) {
            return Err(err(
                &format!("{tfield}.factor"),
                format!("must be finite and > 1, got {f}"),
            ));
        }
        ToleranceKind::Factor(f)
    } else if let Some(v) = t.absolute {
        ToleranceKind::Absolute(positive(v, "absolute")?)
    } else if let Some(v) = t.relative {
        ToleranceKind::Relative(positive(v, "relative")?)
    } else if let Some([lo, hi]) = t.interval {
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(err(
                &format!("{tfield}.interval"),
                "expected [lower, upper] with lower <= upper".into(),
            ));
        }
        ToleranceKind::Interval(lo, hi)
    } else if let Some(r) = t.rounding {
        if r.input_decimals > 12 || r.output_decimals > 12 {
            return Err(err(
                &format!("{tfield}.rounding"),
                "decimals must be at most 12".into(),
            ));
        }
        ToleranceKind::Rounding(r)
    } else {
        let from = t.interval_from.as_ref().expect("one kind is given");
        interval_from(path, src, dir, from, derivative, field, name)?
    };
    check_uncertainty(t, &kind, &tfield, &err)?;
    Ok(Tolerance {
        name: name.to_string(),
        kind,
        reason: t.reason.clone(),
        confidence: t.confidence,
        standard_deviation: t.standard_deviation,
        degrees_of_freedom: t.degrees_of_freedom,
    })
}

/// A tolerance's interval taken from a derivative table (`interval_from`): the entry of the
/// check's `derivative` in the named column, which must hold intervals.
fn interval_from(
    path: &Path,
    src: &str,
    dir: &Path,
    from: &TableColumnSpec,
    derivative: Option<&str>,
    field: &str,
    name: &str,
) -> Result<ToleranceKind, InputError> {
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let tfield = format!("tolerances.{name}");
    let d = derivative.ok_or_else(|| {
        err(
            &format!("{field}.tolerance"),
            format!("`{name}` takes its interval from a derivative table, so it only applies to `derivative` checks"),
        )
    })?;
    let table = crate::checks::subject::load_table(
        path,
        src,
        &dir.join(&from.file),
        &format!("{tfield}.interval_from.file"),
    )?;
    match table.entry(d, &from.column) {
        Some(Entry::Interval(lo, hi)) => Ok(ToleranceKind::Interval(lo, hi)),
        Some(Entry::Value(_)) => Err(err(
            &format!("{tfield}.interval_from.column"),
            format!("column `{}` holds values, not intervals", from.column),
        )),
        None => Err(err(
            &format!("{tfield}.interval_from"),
            format!("the table has no `{d}` in column `{}`", from.column),
        )),
    }
}

/// A tolerance's statement of uncertainty checked against its kind: a `confidence` level (in
/// (0, 1)) only on an interval, a measurement's `standard_deviation` (finite, > 0) only on an
/// absolute or relative tolerance, its `degrees_of_freedom` (at least 1) only with it.
fn check_uncertainty(
    t: &ToleranceSpec,
    kind: &ToleranceKind,
    tfield: &str,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<(), InputError> {
    if let Some(c) = t.confidence {
        if !matches!(kind, ToleranceKind::Interval(..)) {
            return Err(err(
                &format!("{tfield}.confidence"),
                "only an interval (`interval` or `interval_from`) is a confidence interval".into(),
            ));
        }
        if !(c > 0.0 && c < 1.0) {
            return Err(err(
                &format!("{tfield}.confidence"),
                format!("a confidence level is between 0 and 1 (0.95 for 95 %), got {c}"),
            ));
        }
    }
    if let Some(sd) = t.standard_deviation {
        if !matches!(
            kind,
            ToleranceKind::Absolute(_) | ToleranceKind::Relative(_)
        ) {
            return Err(err(
                &format!("{tfield}.standard_deviation"),
                "only an `absolute` or `relative` tolerance takes the measurement's standard deviation (an interval says its `confidence`)".into(),
            ));
        }
        if !(sd.is_finite() && sd > 0.0) {
            return Err(err(
                &format!("{tfield}.standard_deviation"),
                format!("a standard deviation is finite and > 0, got {sd}"),
            ));
        }
    }
    if let Some(n) = t.degrees_of_freedom {
        if t.standard_deviation.is_none() {
            return Err(err(
                &format!("{tfield}.degrees_of_freedom"),
                "degrees of freedom belong to a `standard_deviation` (what it was estimated with)"
                    .into(),
            ));
        }
        if !(n.is_finite() && n >= 1.0) {
            return Err(err(
                &format!("{tfield}.degrees_of_freedom"),
                format!("degrees of freedom are finite and at least 1, got {n}"),
            ));
        }
    }
    Ok(())
}

/// A case with corrections files applied to its subject: an aircraft file whose id a file
/// names, or whose main rotor's id a rotor file names; a rotor (alone, or under a teeter
/// record) whose id a file names; a model behind the model interface written as a file's
/// `applies_to.model` says (its declared parameters sent with every request, each checked
/// against what the model declares). Returns the case unchanged when none applies, and which files
/// applied. A check's own `corrections` still act on top. The checks a file that applies is
/// not applied to (its `not_applied_to` for this case) keep the subject as it was before any
/// file, with the reason (see [`Case::subject_of`]).
pub fn with_corrections(
    case: &Case,
    files: &[crate::inputs::corrections::CorrectionsFile],
) -> Result<(Case, Vec<String>), String> {
    use crate::inputs::corrections::Corrects;
    let mut c = case.clone();
    let mut used = Vec::new();
    let before = case.subject.clone();
    for f in files {
        let here = |e: String| format!("{} on {}: {e}", f.path.display(), case.id);
        let applied = used.len();
        match (&mut c.subject, &f.target) {
            (Subject::Aircraft { file, .. }, Corrects::Aircraft(id)) if file.id == *id => {
                **file = corrected_aircraft(file, f, &case.id)?;
                used.push(f.id.clone());
            }
            (Subject::Aircraft { file, .. }, Corrects::Rotor(id))
                if file.main_rotor_file.id == *id =>
            {
                **file = corrected_aircraft(file, f, &case.id)?;
                used.push(f.id.clone());
            }
            (Subject::Rotor { file, .. }, Corrects::Rotor(id))
            | (Subject::FlapRecord { rotor: file, .. }, Corrects::Rotor(id))
                if file.id == *id =>
            {
                let before = file.rotor.clone();
                f.corrections.apply_to_rotor(&mut file.rotor).map_err(|e| {
                    match f.locate(|one| one.apply_to_rotor(&mut before.clone())) {
                        Some(located) => format!("{located} (applied to {})", case.id),
                        None => here(e),
                    }
                })?;
                file.path = PathBuf::from(format!(
                    "{}#{}",
                    file.path.display(),
                    f.corrections.describe()
                ));
                used.push(f.id.clone());
            }
            (Subject::External(e), Corrects::Model(written)) if e.written == *written => {
                let values = f.corrections.parameters.clone();
                crate::external::check_values(
                    &e.model.describe(),
                    &e.model.parameters().map_err(here)?,
                    &values,
                )
                .map_err(here)?;
                e.model = std::sync::Arc::new(crate::external::WithValues {
                    model: e.model.clone(),
                    values,
                });
                used.push(f.id.clone());
            }
            _ => {}
        }
        if used.len() > applied {
            let (extrapolated, calibrated_on) = marks(case, f);
            c.calibrations.push(Calibration {
                extrapolated,
                calibrated_on,
                id: f.id.clone(),
                predictive_error: f.predictive_error.clone(),
                posterior: f.posterior.clone(),
            });
            for n in f.not_applied_to.iter().filter(|n| n.case == case.id) {
                let u = c.uncorrected.get_or_insert_with(|| Uncorrected {
                    subject: before.clone(),
                    checks: Default::default(),
                    reasons: vec![],
                });
                u.checks.extend(n.checks.iter().cloned());
                u.reasons.push(format!(
                    "{} not applied to {} check(s) ({}): {}",
                    f.id,
                    n.checks.len(),
                    n.regime,
                    n.reason
                ));
            }
        }
    }
    Ok((c, used))
}

/// The case's checks that a corrections file applied to it marks: those outside the domain it
/// was fitted on, each with why, and those it was fitted to; the checks it is not applied to
/// are neither.
fn marks(
    case: &Case,
    f: &crate::inputs::corrections::CorrectionsFile,
) -> (BTreeMap<String, String>, std::collections::BTreeSet<String>) {
    let held_back: Vec<&String> = f
        .not_applied_to
        .iter()
        .filter(|n| n.case == case.id)
        .flat_map(|n| &n.checks)
        .collect();
    let mass_kg =
        crate::checks::flight_model(&case.subject).and_then(|(_, loading)| loading.mass_kg);
    let extrapolated = f
        .domain
        .as_ref()
        .map(|d| {
            case.checks
                .iter()
                .filter(|k| !held_back.contains(&&k.id))
                .filter_map(|k| {
                    let b = k.behaviour();
                    let flight = b.condition().map(|t| (t.airspeed_mph, mass_kg));
                    let why = d.outside(b.tunnel(), flight)?;
                    Some((
                        k.id.clone(),
                        format!(
                            "extrapolation: {} was fitted on {}; this check's {why}",
                            f.id,
                            domain_words(d)
                        ),
                    ))
                })
                .collect()
        })
        .unwrap_or_default();
    let calibrated_on = f
        .calibrated_on
        .get(&case.id)
        .into_iter()
        .flatten()
        .filter(|k| !held_back.contains(k))
        .cloned()
        .collect();
    (extrapolated, calibrated_on)
}

/// A domain in words: "tip-speed ratio [0.15, 0.35], tunnel airspeed [...] m/s".
fn domain_words(d: &crate::inputs::corrections::Domain) -> String {
    [
        ("tip-speed ratio", "", d.tip_speed_ratio),
        ("tunnel airspeed", " m/s", d.tunnel_airspeed_m_s),
        ("airspeed", " mph", d.airspeed_mph),
        ("mass", " kg", d.mass_kg),
    ]
    .into_iter()
    .filter_map(|(name, unit, span)| span.map(|[lo, hi]| format!("{name} [{lo}, {hi}]{unit}")))
    .collect::<Vec<_>>()
    .join(", ")
}

/// Finds case files (`*.yaml`, `*.yml`) under the given paths, sorted; a file is taken as given.
/// The file name of the shared tolerance library.
pub const LIBRARY_FILE: &str = "tolerances.yaml";

/// The shared tolerance library as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct LibrarySpec {
    #[allow(dead_code)]
    title: String,
    tolerances: BTreeMap<String, ToleranceSpec>,
}

/// The shared tolerance library (`cases/tolerances.yaml`): tolerances common to many cases
/// (a sign, printed decimals, FAA Part 60 bands), each with its reason. A case names them as it
/// names its own; a case may not define a tolerance of the same name.
#[derive(Debug, Clone, PartialEq)]
pub struct Library {
    pub path: PathBuf,
    pub tolerances: BTreeMap<String, Tolerance>,
}

/// The library that applies to cases in `dir`: the nearest `tolerances.yaml` in `dir` or a
/// folder above it.
pub fn find_library(dir: &Path) -> Option<PathBuf> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let start = dir.canonicalize().ok()?;
    start
        .ancestors()
        .map(|d| d.join(LIBRARY_FILE))
        .find(|p| p.is_file())
}

/// Loads and checks a tolerance library. Its tolerances cannot take intervals from a table
/// (that depends on the check).
pub fn load_library(path: &Path) -> Result<Library, InputError> {
    let src = yaml::read(path)?;
    let spec: LibrarySpec = yaml::parse(path, &src)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut tolerances = BTreeMap::new();
    for (name, t) in &spec.tolerances {
        let field = format!("tolerances.{name}");
        if t.interval_from.is_some() {
            return Err(InputError::field(
                path,
                &src,
                &format!("{field}.interval_from"),
                "a shared tolerance cannot take its interval from a table (it depends on the check)"
                    .to_string(),
            ));
        }
        tolerances.insert(
            name.clone(),
            tolerance_of(path, &src, dir, t, None, &field, name)?,
        );
    }
    Ok(Library {
        path: path.to_path_buf(),
        tolerances,
    })
}

/// The case files among `paths` (files as given; folders searched for `.yaml` files, except the
/// tolerance library).
pub fn discover(paths: &[PathBuf]) -> Result<Vec<PathBuf>, InputError> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            walk(p, &mut out)?;
        } else if p.is_file() {
            out.push(p.clone());
        } else {
            return Err(InputError::file(p, "no such file or directory"));
        }
    }
    out.sort();
    out.dedup();
    Ok(out)
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), InputError> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| InputError::file(dir, format!("cannot list: {e}")))?;
    for entry in entries {
        let p = entry
            .map_err(|e| InputError::file(dir, format!("cannot list: {e}")))?
            .path();
        if p.is_dir() {
            walk(&p, out)?;
        } else if matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "yml"))
            && p.file_name().is_none_or(|n| n != LIBRARY_FILE)
        {
            out.push(p);
        }
    }
    Ok(())
}

/// Every case file found under `paths`, loaded (or the error that stopped it).
///
/// Fails only when a path does not exist or cannot be listed; an empty result is the caller's
/// to reject.
pub fn load_cases(paths: &[PathBuf]) -> Result<Vec<Result<Case, InputError>>, InputError> {
    Ok(discover(paths)?.iter().map(|p| load(p)).collect())
}

/// `file` with a corrections file's corrections (for case `case`), an error located at the
/// correction that causes it ([`crate::inputs::corrections::CorrectionsFile::locate`]).
fn corrected_aircraft(
    file: &crate::inputs::aircraft::AircraftFile,
    f: &crate::inputs::corrections::CorrectionsFile,
    case: &str,
) -> Result<crate::inputs::aircraft::AircraftFile, String> {
    file.with_corrections(&f.corrections).map_err(|e| {
        match f.locate(|one| file.with_corrections(one).map(|_| ())) {
            Some(located) => format!("{located} (applied to {case})"),
            None => format!("{} on {case}: {e}", f.path.display()),
        }
    })
}
