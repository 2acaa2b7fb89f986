//! Case files: what is checked, against what, with which tolerance and why.
//!
//! The schema is documented with an example in the README ("Writing a case"). Every field is
//! checked: unknown fields are rejected, a tolerance must have a reason, an expectation must
//! name a quantity that its check kind computes, and a check that is expected to fail says why.

use crate::refs::{self, DerivativeTable, Entry, LinearModelSpec, Provenance};
pub use crate::rotor_file::{InflowSpec, SkewSpec};
pub use crate::tolerance::{RoundingSpec, Sign, Tolerance, ToleranceKind};
use crate::yaml::{self, InputError};
use cierva_model::analysis::bcar::Verdict;
use cierva_model::{LinearModel, ModeKind};
use serde::{Deserialize, Serialize};
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
    pub checks: Vec<CheckSpec>,
    /// The data set's scores on the scoreboard (see [`crate::scoreboard`]).
    #[serde(default)]
    pub scores: Vec<crate::scoreboard::ScoreSpec>,
}

/// The subject of a case: exactly one of the fields.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// A reference file (path relative to the case file) holding a `linear_model`.
    #[serde(default)]
    pub linear_model_file: Option<String>,
    /// A linear model written in the case.
    #[serde(default)]
    pub linear_model: Option<LinearModelSpec>,
    /// Published derivative values: a column of a reference file's table.
    #[serde(default)]
    pub derivative_table: Option<TableColumnSpec>,
    /// A rotor file, for isolated-rotor (wind-tunnel) checks.
    #[serde(default)]
    pub rotor: Option<RotorModelSpec>,
    /// A teeter record and its rotor, for inflow-from-flapping checks (seed 003).
    #[serde(default)]
    pub flap_record: Option<FlapRecordSpec>,
    /// An aircraft file, for trim checks.
    #[serde(default)]
    pub aircraft: Option<AircraftModelSpec>,
}

/// An aircraft subject: the file, the mass and the air.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AircraftModelSpec {
    /// Path relative to the case file.
    pub file: String,
    /// Mass, kg (default: the aircraft file's).
    #[serde(default)]
    pub mass_kg: Option<f64>,
    /// ISA density altitude, ft.
    #[serde(default)]
    pub density_altitude_ft: f64,
}

/// A teeter record analysed for its inflow (seed 003).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlapRecordSpec {
    /// The record CSV, relative to the case file (its sidecar beside it).
    pub file: String,
    /// The rotor file, relative to the case file.
    pub rotor: String,
    #[serde(default)]
    pub coning: crate::ident::flap::Coning,
    #[serde(default)]
    pub skew: crate::ident::flap::HalfSkew,
    #[serde(default = "sea_level_density")]
    pub density_kg_m3: f64,
    #[serde(default)]
    pub collective_deg: Option<f64>,
}

fn sea_level_density() -> f64 {
    1.225
}

/// A rotor subject: the file and the inflow model to run it with.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotorModelSpec {
    /// Path relative to the case file.
    pub file: String,
    #[serde(default)]
    pub inflow: InflowSpec,
    #[serde(default)]
    pub skew: SkewSpec,
}

/// A wind-tunnel condition: the angle of attack and either the airspeed or the tip-speed ratio
/// with the rotor speed that the airspeed follows from (`V = mu Omega R / cos alpha`, TR 515).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TunnelSpec {
    /// Absent: the angle is found at `tip_speed_ratio` and `rotor_rpm` (how TR 515 plots its
    /// data), and the check computes it as `rotor_alpha_deg`.
    #[serde(default)]
    pub alpha_deg: Option<f64>,
    #[serde(default)]
    pub airspeed_m_s: Option<f64>,
    #[serde(default)]
    pub tip_speed_ratio: Option<f64>,
    #[serde(default)]
    pub rotor_rpm: Option<f64>,
    /// Blade pitch at the rotor's reference station, deg (default: the file's pitch as it is).
    #[serde(default)]
    pub collective_deg: Option<f64>,
    /// Air density (default ISA sea level).
    #[serde(default)]
    pub density_kg_m3: Option<f64>,
}

/// A column of a derivative table in a reference file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableColumnSpec {
    /// Path relative to the case file.
    pub file: String,
    pub column: String,
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
    pub reason: String,
}

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

/// The kinds of check.
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
    /// with the record's: `<signal>.<metric>` (see [`crate::history`]).
    TimeHistory,
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
        }
    }
}

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

/// A check as written.
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
    /// For `mode` and `bcar`.
    #[serde(default)]
    pub system: System,
    /// For `mode` and `bcar`: the mode class to look at.
    #[serde(default)]
    pub mode: Option<ModeKind>,
    /// For `derivative`: the derivative's name (`M_w`).
    #[serde(default)]
    pub derivative: Option<String>,
    /// For `derivative` on a model: check the ratio of `derivative` to this one (`Q_u` divided
    /// by `Q_w`).
    #[serde(default)]
    pub divided_by: Option<String>,
    /// For `bcar`: the expected verdict.
    #[serde(default)]
    pub verdict: Option<Verdict>,
    /// For `autorotation`: the tunnel condition.
    #[serde(default)]
    pub tunnel: Option<TunnelSpec>,
    /// For `trim`: the flight condition.
    #[serde(default)]
    pub condition: Option<crate::TrimRequest>,
    /// For `trim_sweep`: the airspeeds, mph, rising.
    #[serde(default)]
    pub sweep_mph: Option<Vec<f64>>,
    /// For `derivative` on an aircraft: seed 000's corrections to apply; the check then also
    /// computes `magnitude_change`, `(|corrected| - |uncorrected|) / |uncorrected|`.
    #[serde(default)]
    pub corrections: Option<crate::corrections::CorrectionSet>,
    /// For `time_history`: the reference record CSV (its sidecar beside it), relative to the
    /// case file.
    #[serde(default)]
    pub reference: Option<String>,
    /// For `time_history`: the model that flies the record (default the full blade model).
    #[serde(default)]
    pub simulation: Option<crate::history::Simulation>,
    /// For `time_history` with the full blade model: the azimuth step, deg (default the
    /// aircraft file's).
    #[serde(default)]
    pub azimuth_step_deg: Option<f64>,
    /// Derivatives set to these values before the check (a what-if variant).
    #[serde(default)]
    pub set: BTreeMap<String, f64>,
    /// Zero every rotorspeed coupling derivative first (seed 002 Tables 2 and 5).
    #[serde(default)]
    pub without_rotorspeed_coupling: bool,
    /// Quantity -> expectation.
    #[serde(default)]
    pub expect: BTreeMap<String, ExpectSpec>,
    /// The check is known to fail, and this is why.
    #[serde(default)]
    pub expected_failure: Option<String>,
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

/// A resolved check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    pub id: String,
    pub kind: CheckKind,
    pub class: CheckClass,
    pub description: Option<String>,
    pub system: System,
    pub mode: Option<ModeKind>,
    pub derivative: Option<String>,
    pub divided_by: Option<String>,
    pub verdict: Option<Verdict>,
    pub tunnel: Option<TunnelSpec>,
    pub condition: Option<crate::TrimRequest>,
    pub sweep_mph: Option<Vec<f64>>,
    pub corrections: Option<crate::corrections::CorrectionSet>,
    /// For `time_history`: the reference record.
    #[serde(skip)]
    pub reference: Option<Box<crate::ident::record::Record>>,
    pub simulation: crate::history::Simulation,
    pub azimuth_step_deg: Option<f64>,
    pub set: BTreeMap<String, f64>,
    pub without_rotorspeed_coupling: bool,
    pub expectations: Vec<Expectation>,
    pub expected_failure: Option<String>,
}

/// What a case checks.
#[derive(Debug, Clone, PartialEq)]
pub enum Subject {
    /// A linear model, with the file it came from (if any) and its units.
    Linear {
        model: LinearModel,
        file: Option<PathBuf>,
        units: BTreeMap<String, String>,
    },
    /// Published derivative values: one column of a table.
    Table {
        table: DerivativeTable,
        file: PathBuf,
        column: String,
    },
    /// An isolated rotor, run with the given inflow model.
    Rotor {
        file: Box<crate::rotor_file::RotorFile>,
        inflow: cierva_model::components::rotor::InflowModel,
    },
    /// An aircraft, its mass and air.
    Aircraft {
        file: Box<crate::aircraft_file::AircraftFile>,
        loading: crate::Loading,
    },
    /// A teeter record, its rotor and the analysis settings.
    FlapRecord {
        record: Box<crate::ident::record::Record>,
        rotor: Box<crate::rotor_file::RotorFile>,
        settings: crate::ident::flap::FlapSettings,
    },
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
    /// What the model gave for the case's expected failures (see [`crate::discrepancy`]).
    pub recorded: Option<crate::discrepancy::CaseRecord>,
    /// The data set's scores.
    pub scores: Vec<crate::scoreboard::ScoreSpec>,
}

/// Names of the quantities each check kind computes (the keys allowed under `expect`; a
/// `time_history` check's `<signal>.<metric>` names come from its record). The quantities
/// themselves are defined in [`crate::quantity`].
pub fn quantities(kind: CheckKind) -> Vec<String> {
    use crate::quantity as q;
    let list: &[q::Quantity] = match kind {
        CheckKind::Mode => q::MODE,
        CheckKind::Bcar => q::BCAR,
        CheckKind::Milne => q::MILNE,
        CheckKind::Derivative => q::DERIVATIVE,
        CheckKind::Autorotation => q::AUTOROTATION,
        CheckKind::InflowCoefficients => q::INFLOW_COEFFICIENTS,
        CheckKind::Trim => q::TRIM,
        CheckKind::TrimSweep => return q::sweep_names(),
        CheckKind::TimeHistory => &[],
    };
    list.iter().map(|x| x.name().to_string()).collect()
}

/// Loads and checks a case file.
pub fn load(path: &Path) -> Result<Case, InputError> {
    let src = yaml::read(path)?;
    let spec: CaseSpec = yaml::parse(path, &src)?;
    refs::check_id(path, &src, &spec.id)?;
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
    let subject = load_subject(path, &src, dir, &spec.model)?;
    let mut seen = std::collections::BTreeSet::new();
    let mut checks = Vec::new();
    if spec.checks.is_empty() {
        return Err(err("checks", "a case needs at least one check".into()));
    }
    for (i, c) in spec.checks.iter().enumerate() {
        let here = format!("checks[{i}]");
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
        checks.push(resolve_check(
            path,
            &src,
            dir,
            &spec,
            library.as_ref(),
            &subject,
            &here,
            c,
        )?);
    }
    let recorded = crate::discrepancy::load(&spec.id)?;
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
        match (&sc.quantity, sc.metric.needs_quantity()) {
            (None, true) => {
                return Err(err(
                    &here,
                    format!("a `{:?}` score needs a `quantity`", sc.metric),
                ));
            }
            (Some(q), _)
                if !checks
                    .iter()
                    .any(|c| c.expectations.iter().any(|e| &e.quantity == q)) =>
            {
                return Err(err(
                    &format!("{here}.quantity"),
                    format!("no check of the case expects `{q}`"),
                ));
            }
            _ => {}
        }
    }
    Ok(Case {
        path: path.to_path_buf(),
        id: spec.id,
        title: spec.title,
        class: spec.class,
        provenance: spec.provenance,
        subject,
        checks,
        recorded,
        scores: spec.scores,
    })
}

fn load_subject(path: &Path, src: &str, dir: &Path, m: &ModelSpec) -> Result<Subject, InputError> {
    // Long: one arm per kind of subject, each loading and checking its files
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let given = [
        m.linear_model_file.is_some(),
        m.linear_model.is_some(),
        m.derivative_table.is_some(),
        m.rotor.is_some(),
        m.flap_record.is_some(),
        m.aircraft.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        return Err(err(
            "model",
            "give exactly one of `linear_model_file`, `linear_model`, `derivative_table`, `rotor`, `flap_record` or `aircraft`"
                .into(),
        ));
    }
    if let Some(a) = &m.aircraft {
        let file = crate::aircraft_file::load(&dir.join(&a.file)).map_err(|e| {
            err(
                "model.aircraft.file",
                format!("in the referenced file: {e}"),
            )
        })?;
        if let Some(mass) = a.mass_kg
            && !(mass.is_finite() && mass > 0.0)
        {
            return Err(err(
                "model.aircraft.mass_kg",
                format!("must be positive, got {mass}"),
            ));
        }
        if !(-2000.0..=20000.0).contains(&a.density_altitude_ft) {
            return Err(err(
                "model.aircraft.density_altitude_ft",
                format!(
                    "must be in [-2000, 20000] ft, got {}",
                    a.density_altitude_ft
                ),
            ));
        }
        return Ok(Subject::Aircraft {
            file: Box::new(file),
            loading: crate::Loading {
                mass_kg: a.mass_kg,
                density_altitude_ft: a.density_altitude_ft,
            },
        });
    }
    if let Some(f) = &m.flap_record {
        let rec = crate::ident::record::load_with(
            &dir.join(&f.file),
            &crate::ident::flap::FLAP_REQUIRED,
            false,
        )
        .map_err(|e| {
            err(
                "model.flap_record.file",
                format!("in the referenced record: {e}"),
            )
        })?;
        let rotor = crate::rotor_file::load(&dir.join(&f.rotor)).map_err(|e| {
            err(
                "model.flap_record.rotor",
                format!("in the referenced file: {e}"),
            )
        })?;
        if !(f.density_kg_m3.is_finite() && f.density_kg_m3 > 0.0) {
            return Err(err(
                "model.flap_record.density_kg_m3",
                "must be positive".into(),
            ));
        }
        return Ok(Subject::FlapRecord {
            record: Box::new(rec),
            rotor: Box::new(rotor),
            settings: crate::ident::flap::FlapSettings {
                coning: f.coning,
                skew: f.skew,
                density_kg_m3: f.density_kg_m3,
                collective_deg: f.collective_deg,
            },
        });
    }
    if let Some(r) = &m.rotor {
        let rpath = dir.join(&r.file);
        let file = crate::rotor_file::load(&rpath)
            .map_err(|e| err("model.rotor.file", format!("in the referenced file: {e}")))?;
        return Ok(Subject::Rotor {
            file: Box::new(file),
            inflow: r.inflow.model(r.skew),
        });
    }
    if let Some(file) = &m.linear_model_file {
        let rpath = dir.join(file);
        let r = refs::load(&rpath).map_err(|e| {
            err(
                "model.linear_model_file",
                format!("in the referenced file: {e}"),
            )
        })?;
        let model = r.linear_model.ok_or_else(|| {
            err(
                "model.linear_model_file",
                format!("{} has no `linear_model` block", rpath.display()),
            )
        })?;
        return Ok(Subject::Linear {
            model,
            file: Some(rpath),
            units: r.units,
        });
    }
    if let Some(spec) = &m.linear_model {
        return Ok(Subject::Linear {
            model: spec.build(path, src, "model.linear_model")?,
            file: None,
            units: spec.units.clone(),
        });
    }
    let t = m.derivative_table.as_ref().expect("one subject is given");
    let tpath = dir.join(&t.file);
    let table = load_table(path, src, &tpath, "model.derivative_table.file")?;
    match table.columns.get(&t.column) {
        Some(c) if c.kind == refs::ColumnKind::Value => {}
        Some(_) => {
            return Err(err(
                "model.derivative_table.column",
                format!("column `{}` holds intervals, not values", t.column),
            ));
        }
        None => {
            return Err(err(
                "model.derivative_table.column",
                format!(
                    "{} has no column `{}`; it has [{}]",
                    tpath.display(),
                    t.column,
                    table.columns.keys().cloned().collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    }
    Ok(Subject::Table {
        table,
        file: tpath,
        column: t.column.clone(),
    })
}

fn load_table(
    path: &Path,
    src: &str,
    tpath: &Path,
    field: &str,
) -> Result<DerivativeTable, InputError> {
    let r = refs::load(tpath)
        .map_err(|e| InputError::field(path, src, field, format!("in the referenced file: {e}")))?;
    if r.table.rows.is_empty() {
        return Err(InputError::field(
            path,
            src,
            field,
            format!("{} has no `derivatives` table", tpath.display()),
        ));
    }
    Ok(r.table)
}

#[allow(clippy::too_many_arguments)]
fn resolve_check(
    path: &Path,
    src: &str,
    dir: &Path,
    spec: &CaseSpec,
    library: Option<&Library>,
    subject: &Subject,
    here: &str,
    c: &CheckSpec,
) -> Result<Check, InputError> {
    // Long: validates the flat check spec for every kind in one place, field by field; one module
    // per check kind behind a typed, tagged spec is the planned split (ARCHITECTURE.md)
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let needs = |present: bool, field: &str| -> Result<(), InputError> {
        if present {
            Ok(())
        } else {
            Err(err(
                here,
                format!("a `{}` check needs `{field}`", c.kind.name()),
            ))
        }
    };
    let refuses = |present: bool, field: &str| -> Result<(), InputError> {
        if present {
            Err(err(
                &format!("{here}.{field}"),
                format!("`{field}` does not apply to a `{}` check", c.kind.name()),
            ))
        } else {
            Ok(())
        }
    };
    let check_condition = |t: &crate::TrimRequest| -> Result<(), InputError> {
        let ok = t.airspeed_mph.is_finite()
            && t.airspeed_mph > 0.0
            && t.climb_m_s.is_finite()
            && t.turn_rate_deg_s.is_finite();
        if ok {
            Ok(())
        } else {
            Err(err(
                &format!("{here}.condition"),
                "the airspeed must be positive, climb and turn rates finite".into(),
            ))
        }
    };
    match c.kind {
        CheckKind::Mode | CheckKind::Bcar => {
            needs(c.mode.is_some(), "mode")?;
            refuses(c.derivative.is_some(), "derivative")?;
            if c.kind == CheckKind::Bcar {
                needs(c.verdict.is_some(), "verdict")?;
            } else {
                refuses(c.verdict.is_some(), "verdict")?;
            }
        }
        CheckKind::Milne => {
            refuses(c.mode.is_some(), "mode")?;
            refuses(c.derivative.is_some(), "derivative")?;
            refuses(c.verdict.is_some(), "verdict")?;
            refuses(c.system != System::Full, "system")?;
        }
        CheckKind::Derivative => {
            needs(c.derivative.is_some(), "derivative")?;
            refuses(c.mode.is_some(), "mode")?;
            refuses(c.verdict.is_some(), "verdict")?;
            refuses(c.system != System::Full, "system")?;
        }
        CheckKind::Autorotation => {
            needs(c.tunnel.is_some(), "tunnel")?;
            refuses(c.mode.is_some(), "mode")?;
            refuses(c.derivative.is_some(), "derivative")?;
            refuses(c.verdict.is_some(), "verdict")?;
            refuses(c.system != System::Full, "system")?;
            refuses(!c.set.is_empty(), "set")?;
            refuses(c.without_rotorspeed_coupling, "without_rotorspeed_coupling")?;
            check_tunnel(&err, here, c.tunnel.as_ref().expect("needed above"))?;
        }
        CheckKind::Trim | CheckKind::TrimSweep => {
            refuses(c.mode.is_some(), "mode")?;
            refuses(c.derivative.is_some(), "derivative")?;
            refuses(c.verdict.is_some(), "verdict")?;
            refuses(c.system != System::Full, "system")?;
            refuses(!c.set.is_empty(), "set")?;
            refuses(c.without_rotorspeed_coupling, "without_rotorspeed_coupling")?;
            if c.kind == CheckKind::Trim {
                needs(c.condition.is_some(), "condition")?;
                refuses(c.sweep_mph.is_some(), "sweep_mph")?;
            } else {
                needs(c.sweep_mph.is_some(), "sweep_mph")?;
                refuses(c.condition.is_some(), "condition")?;
                let s = c.sweep_mph.as_deref().unwrap_or_default();
                if s.len() < 2
                    || s.windows(2)
                        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
                    || s[0] <= 0.0
                {
                    return Err(err(
                        &format!("{here}.sweep_mph"),
                        "give at least two positive airspeeds, rising".into(),
                    ));
                }
            }
            if let Some(t) = &c.condition {
                check_condition(t)?;
            }
        }
        CheckKind::TimeHistory => {
            needs(c.reference.is_some(), "reference")?;
            needs(c.condition.is_some(), "condition")?;
            refuses(c.mode.is_some(), "mode")?;
            refuses(c.derivative.is_some(), "derivative")?;
            refuses(c.verdict.is_some(), "verdict")?;
            refuses(c.system != System::Full, "system")?;
            refuses(!c.set.is_empty(), "set")?;
            refuses(c.without_rotorspeed_coupling, "without_rotorspeed_coupling")?;
            refuses(c.sweep_mph.is_some(), "sweep_mph")?;
            if let Some(a) = c.azimuth_step_deg
                && !(a.is_finite() && a > 0.0 && a <= 30.0)
            {
                return Err(err(
                    &format!("{here}.azimuth_step_deg"),
                    format!("must be in (0, 30] deg, got {a}"),
                ));
            }
            if c.simulation == Some(crate::history::Simulation::Linear) {
                refuses(c.azimuth_step_deg.is_some(), "azimuth_step_deg")?;
            }
            if let Some(t) = &c.condition {
                check_condition(t)?;
                if c.simulation == Some(crate::history::Simulation::Linear)
                    && t.turn_rate_deg_s != 0.0
                {
                    return Err(err(
                        &format!("{here}.condition.turn_rate_deg_s"),
                        "the model is linearised about straight flight".into(),
                    ));
                }
            }
        }
        CheckKind::InflowCoefficients => {
            refuses(c.mode.is_some(), "mode")?;
            refuses(c.derivative.is_some(), "derivative")?;
            refuses(c.verdict.is_some(), "verdict")?;
            refuses(c.system != System::Full, "system")?;
            refuses(!c.set.is_empty(), "set")?;
            refuses(c.without_rotorspeed_coupling, "without_rotorspeed_coupling")?;
        }
    }
    if c.kind != CheckKind::Autorotation && c.tunnel.is_some() {
        refuses(true, "tunnel")?;
    }
    if c.kind != CheckKind::TimeHistory {
        refuses(c.reference.is_some(), "reference")?;
        refuses(c.simulation.is_some(), "simulation")?;
        refuses(c.azimuth_step_deg.is_some(), "azimuth_step_deg")?;
    }
    let reference = match (&c.reference, subject) {
        (Some(r), Subject::Aircraft { .. }) => {
            let rec =
                crate::ident::record::load_with(&dir.join(r), &["time_s"], true).map_err(|e| {
                    err(
                        &format!("{here}.reference"),
                        format!("in the referenced record: {e}"),
                    )
                })?;
            for ch in crate::history::record_signals(&rec) {
                if !crate::history::SIGNALS.contains(&ch.as_str()) {
                    return Err(err(
                        &format!("{here}.reference"),
                        format!(
                            "the record's channel `{ch}` is neither a control (the sidecar's `controls`) nor a response cierva computes ({})",
                            crate::history::SIGNALS.join(", ")
                        ),
                    ));
                }
            }
            crate::history::record_controls(&rec)
                .map_err(|e| err(&format!("{here}.reference"), e))?;
            Some(Box::new(rec))
        }
        _ => None,
    };
    let trim_kind = matches!(
        c.kind,
        CheckKind::Trim | CheckKind::TrimSweep | CheckKind::TimeHistory
    );
    let aircraft = matches!(subject, Subject::Aircraft { .. });
    let linear_kind = matches!(
        c.kind,
        CheckKind::Mode | CheckKind::Bcar | CheckKind::Milne | CheckKind::Derivative
    );
    if trim_kind && !aircraft {
        return Err(err(
            &format!("{here}.kind"),
            "`trim`, `trim_sweep` and `time_history` checks need a case whose model is an `aircraft`".into(),
        ));
    }
    if aircraft && !trim_kind && !linear_kind {
        return Err(err(
            &format!("{here}.kind"),
            "an `aircraft` model has `trim`, `trim_sweep`, `time_history`, and (with a `condition`, on the linearised model) `derivative`, `mode`, `bcar` and `milne` checks".into(),
        ));
    }
    if aircraft && linear_kind {
        needs(c.condition.is_some(), "condition")?;
        refuses(c.sweep_mph.is_some(), "sweep_mph")?;
        if let Some(t) = &c.condition
            && t.turn_rate_deg_s != 0.0
        {
            return Err(err(
                &format!("{here}.condition.turn_rate_deg_s"),
                "the model is linearised about straight flight".into(),
            ));
        }
        let template = cierva_model::LinearModel::from_rows(
            cierva_model::aircraft::linearise::STATES
                .iter()
                .map(|s| s.to_string())
                .collect(),
            cierva_model::aircraft::linearise::CONTROLS
                .iter()
                .map(|s| s.to_string())
                .collect(),
            &vec![vec![0.0; 10]; 10],
            &vec![vec![0.0; 4]; 10],
        )
        .expect("the linearised model's names are valid");
        for name in c
            .set
            .keys()
            .chain(c.derivative.iter())
            .chain(c.divided_by.iter())
        {
            template
                .derivative(name)
                .map_err(|e| err(&format!("{here}.derivative"), e.to_string()))?;
        }
    }
    if let Some(k) = &c.corrections {
        if !(aircraft && matches!(c.kind, CheckKind::Derivative | CheckKind::TimeHistory)) {
            refuses(true, "corrections")?;
        }
        if let Subject::Aircraft { file, .. } = subject {
            file.with_corrections(k)
                .map_err(|e| err(&format!("{here}.corrections"), e.to_string()))?;
        }
    }
    if c.corrections.is_none() && c.expect.contains_key("magnitude_change") {
        return Err(err(
            &format!("{here}.expect.magnitude_change"),
            "`magnitude_change` compares with corrections: give `corrections`".into(),
        ));
    }
    if c.divided_by.is_some() && c.kind != CheckKind::Derivative {
        refuses(true, "divided_by")?;
    }
    if c.divided_by.is_some() && c.expect.keys().any(|q| q != "value") {
        return Err(err(
            &format!("{here}.divided_by"),
            "a ratio of derivatives has only a `value`".into(),
        ));
    }
    if c.divided_by.is_some() && matches!(subject, Subject::Table { .. }) {
        refuses(true, "divided_by")?;
    }
    if !aircraft {
        refuses(c.condition.is_some(), "condition")?;
        refuses(c.sweep_mph.is_some(), "sweep_mph")?;
        if c.kind == CheckKind::Derivative {
            for q in c.expect.keys() {
                if q != "value" {
                    return Err(err(
                        &format!("{here}.expect.{q}"),
                        format!(
                            "`{q}` (a component of the derivative) is computed for aircraft cases only; this case computes [value]"
                        ),
                    ));
                }
            }
        }
    }
    if c.kind != CheckKind::Bcar && c.expect.is_empty() {
        return Err(err(
            here,
            "a check needs at least one entry under `expect`".into(),
        ));
    }
    if let Some(r) = &c.expected_failure
        && r.trim().is_empty()
    {
        return Err(err(
            &format!("{here}.expected_failure"),
            "say why the check is expected to fail".into(),
        ));
    }
    let flap_subject = matches!(subject, Subject::FlapRecord { .. });
    if flap_subject != (c.kind == CheckKind::InflowCoefficients) {
        return Err(err(
            &format!("{here}.kind"),
            "`inflow_coefficients` checks go with a `flap_record` model, and a `flap_record` model only has those".into(),
        ));
    }
    match subject {
        Subject::FlapRecord { .. } | Subject::Aircraft { .. } => {}
        Subject::Rotor { .. } => {
            if c.kind != CheckKind::Autorotation {
                return Err(err(
                    &format!("{here}.kind"),
                    "a case whose model is a rotor can only have `autorotation` checks".into(),
                ));
            }
        }
        Subject::Linear { .. } | Subject::Table { .. } if c.kind == CheckKind::Autorotation => {
            return Err(err(
                &format!("{here}.kind"),
                "an `autorotation` check needs a case whose model is a `rotor`".into(),
            ));
        }
        Subject::Table { table, column, .. } => {
            if c.kind != CheckKind::Derivative {
                return Err(err(
                    &format!("{here}.kind"),
                    "a case whose model is a derivative table can only have `derivative` checks"
                        .into(),
                ));
            }
            if !c.set.is_empty() || c.without_rotorspeed_coupling {
                return Err(err(
                    here,
                    "a published derivative table cannot be modified".into(),
                ));
            }
            let d = c.derivative.as_deref().unwrap_or_default();
            if table.entry(d, column).is_none() {
                return Err(err(
                    &format!("{here}.derivative"),
                    format!("the table has no `{d}` in column `{column}`"),
                ));
            }
        }
        Subject::Linear { model, .. } => {
            for name in c.set.keys().chain(c.derivative.iter()) {
                model
                    .derivative(name)
                    .map_err(|e| err(&format!("{here}.derivative"), e.to_string()))?;
            }
            for (name, v) in &c.set {
                if !v.is_finite() {
                    return Err(err(&format!("{here}.set.{name}"), "must be finite".into()));
                }
            }
        }
    }

    if let Some(t) = &c.tunnel
        && t.alpha_deg.is_some()
        && c.expect
            .contains_key(crate::quantity::Quantity::RotorAlphaDeg.name())
    {
        return Err(err(
            &format!("{here}.expect.rotor_alpha_deg"),
            "the tunnel gives `alpha_deg`, so `rotor_alpha_deg` reads it back: check it with the angle left out (`tunnel: {tip_speed_ratio, rotor_rpm}`), where it is found".into(),
        ));
    }
    let mut allowed: Vec<String> = quantities(c.kind);
    if let Some(rec) = &reference {
        for s in crate::history::record_signals(rec) {
            for m in crate::history::METRICS {
                allowed.push(format!("{s}.{m}"));
            }
        }
    }
    let mut expectations = Vec::new();
    for (q, e) in &c.expect {
        let field = format!("{here}.expect.{q}");
        if !allowed.contains(q) {
            let hint = crate::yaml::nearest(q, &allowed)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(err(
                &field,
                format!(
                    "a `{}` check does not compute `{q}`{hint}; it computes [{}]",
                    c.kind.name(),
                    allowed.join(", ")
                ),
            ));
        }
        let tolerance = resolve_tolerance(path, src, dir, spec, library, c, &field, &e.tolerance)?;
        if matches!(tolerance.kind, ToleranceKind::Rounding(_))
            && !matches!(subject, Subject::Linear { .. })
        {
            return Err(err(
                &format!("{field}.tolerance"),
                format!(
                    "`{}` is a rounding tolerance, which applies to linear models only",
                    tolerance.name
                ),
            ));
        }
        let interval = tolerance.kind.is_bound_only();
        match (e.value, interval) {
            (Some(_), true) => {
                return Err(err(
                    &format!("{field}.value"),
                    format!(
                        "tolerance `{}` is a bound (an interval or a sign): give no value",
                        tolerance.name
                    ),
                ));
            }
            (None, false) => {
                return Err(err(
                    &field,
                    format!("tolerance `{}` needs an expected `value`", tolerance.name),
                ));
            }
            (Some(v), _) if !v.is_finite() => {
                return Err(err(&format!("{field}.value"), "must be finite".into()));
            }
            _ => {}
        }
        expectations.push(Expectation {
            quantity: q.clone(),
            value: e.value,
            tolerance,
        });
    }
    let class = c.class.unwrap_or(spec.class);
    refuse_trivial(subject, c, class, reference.as_deref(), &expectations)
        .map_err(|(field, msg)| err(&format!("{here}{field}"), msg))?;
    Ok(Check {
        id: c.id.clone(),
        kind: c.kind,
        class,
        description: c.description.clone(),
        system: c.system,
        mode: c.mode,
        derivative: c.derivative.clone(),
        verdict: c.verdict,
        divided_by: c.divided_by.clone(),
        tunnel: c.tunnel,
        condition: c.condition,
        sweep_mph: c.sweep_mph.clone(),
        corrections: c.corrections,
        reference,
        simulation: c.simulation.unwrap_or_default(),
        azimuth_step_deg: c.azimuth_step_deg,
        set: c.set.clone(),
        without_rotorspeed_coupling: c.without_rotorspeed_coupling,
        expectations,
        expected_failure: c.expected_failure.clone(),
    })
}

/// Refuses a check that cannot fail: one that reads back its own input, or that a trivial
/// predictor passes (a zero derivative, a model with no response at all). Regression checks
/// are the model's own earlier output and exempt. The error is `(field suffix, message)`.
fn refuse_trivial(
    subject: &Subject,
    c: &CheckSpec,
    class: CheckClass,
    reference: Option<&crate::ident::record::Record>,
    expectations: &[Expectation],
) -> Result<(), (String, String)> {
    if class == CheckClass::Regression {
        return Ok(());
    }
    match (subject, c.kind) {
        (Subject::Linear { .. }, CheckKind::Derivative) => {
            return Err((
                ".kind".into(),
                "a `derivative` check on a linear model reads back an entry of the model's own \
                 file: it cannot fail (check what cierva computes from it: modes, Milne \
                 values)"
                    .into(),
            ));
        }
        (Subject::Table { .. }, _) if class != CheckClass::Verification => {
            return Err((
                ".class".into(),
                "a derivative table's checks compare published numbers with published numbers \
                 and run no model: they are `verification` (of the transcription against the \
                 paper's statements)"
                    .into(),
            ));
        }
        _ => {}
    }
    if matches!(c.kind, CheckKind::Trim | CheckKind::TrimSweep) {
        for q in crate::quantity::ENFORCED_BY_TRIM {
            if c.expect.contains_key(q.name()) {
                return Err((
                    format!(".expect.{q}"),
                    format!(
                        "`{q}` is what the trim solves for (a trim whose scaled residuals exceed \
                         1e-7, or whose rotor is not free, is an error): a check of it cannot fail"
                    ),
                ));
            }
        }
    }
    let trivial: Vec<(String, f64, &str)> = match c.kind {
        // A ratio of two zero derivatives is not a number, which never passes.
        CheckKind::Derivative
            if matches!(subject, Subject::Aircraft { .. }) && c.divided_by.is_none() =>
        {
            expectations
                .iter()
                .map(|e| {
                    let who = if e.quantity == "magnitude_change" {
                        "corrections that change nothing"
                    } else {
                        "a zero derivative"
                    };
                    (e.quantity.clone(), 0.0, who)
                })
                .collect()
        }
        CheckKind::TrimSweep => expectations
            .iter()
            .map(|e| {
                (
                    e.quantity.clone(),
                    0.0,
                    "a trim that does not change with airspeed",
                )
            })
            .collect(),
        CheckKind::TimeHistory => {
            let Some(record) = reference else {
                return Ok(());
            };
            let zero = crate::history::zero_response_metrics(record)
                .map_err(|e| (".reference".to_string(), e))?;
            let mean = crate::history::mean_response_metrics(record)
                .map_err(|e| (".reference".to_string(), e))?;
            let who = [
                "a model with no response",
                "a model that holds still at the record's own mean",
            ];
            zero.iter()
                .map(|m| (m, who[0]))
                .chain(mean.iter().map(|m| (m, who[1])))
                .flat_map(|(m, who)| {
                    crate::history::METRICS.iter().map(move |q| {
                        (
                            format!("{}.{q}", m.signal),
                            m.get(q).unwrap_or(f64::NAN),
                            who,
                        )
                    })
                })
                .collect()
        }
        _ => return Ok(()),
    };
    for e in expectations {
        for (_, v, who) in trivial.iter().filter(|(q, ..)| *q == e.quantity) {
            if crate::tolerance::admits(&e.tolerance.kind, e.value, *v) != Some(true) {
                continue;
            }
            return Err((
                format!(".expect.{}", e.quantity),
                format!(
                    "{who} ({} = {v:.4e}) passes this expectation under tolerance `{}`: the check \
                     cannot fail. Tighten it with a reason, or remove it (a sign is `sign: \
                     positive` or `sign: negative`, which refuses zero)",
                    e.quantity, e.tolerance.name
                ),
            ));
        }
    }
    Ok(())
}

fn check_tunnel(
    err: &dyn Fn(&str, String) -> InputError,
    here: &str,
    t: &TunnelSpec,
) -> Result<(), InputError> {
    let field = format!("{here}.tunnel");
    let finite = |v: Option<f64>| v.is_none_or(f64::is_finite);
    if !finite(t.alpha_deg)
        || !finite(t.airspeed_m_s)
        || !finite(t.tip_speed_ratio)
        || !finite(t.rotor_rpm)
        || !finite(t.collective_deg)
        || !finite(t.density_kg_m3)
    {
        return Err(err(
            &field,
            "every number of the tunnel condition must be finite".into(),
        ));
    }
    match (t.alpha_deg, t.airspeed_m_s, t.tip_speed_ratio, t.rotor_rpm) {
        (Some(_), Some(_), None, None) | (_, None, Some(_), Some(_)) => Ok(()),
        _ => Err(err(
            &field,
            "give `alpha_deg` with either `airspeed_m_s`, or `tip_speed_ratio` with `rotor_rpm` (the airspeed then follows as mu Omega R / cos alpha); or `tip_speed_ratio` with `rotor_rpm` alone (the angle is then found)"
                .into(),
        )),
    }
}

#[allow(clippy::too_many_arguments)]
fn resolve_tolerance(
    path: &Path,
    src: &str,
    dir: &Path,
    spec: &CaseSpec,
    library: Option<&Library>,
    check: &CheckSpec,
    field: &str,
    name: &str,
) -> Result<Tolerance, InputError> {
    let Some(t) = spec.tolerances.get(name) else {
        if let Some(t) = library.and_then(|l| l.tolerances.get(name)) {
            return Ok(t.clone());
        }
        let mut names: Vec<String> = spec.tolerances.keys().cloned().collect();
        let shared: Vec<String> = library
            .map(|l| l.tolerances.keys().cloned().collect())
            .unwrap_or_default();
        let hint = crate::yaml::nearest(name, &[names.clone(), shared.clone()].concat())
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
    tolerance_of(path, src, dir, t, check.derivative.as_deref(), field, name)
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
    // Long: one arm per tolerance kind, each checking its numbers
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
        let d = derivative.ok_or_else(|| {
            err(
                &format!("{field}.tolerance"),
                format!("`{name}` takes its interval from a derivative table, so it only applies to `derivative` checks"),
            )
        })?;
        let table = load_table(
            path,
            src,
            &dir.join(&from.file),
            &format!("{tfield}.interval_from.file"),
        )?;
        match table.entry(d, &from.column) {
            Some(Entry::Interval(lo, hi)) => ToleranceKind::Interval(lo, hi),
            Some(Entry::Value(_)) => {
                return Err(err(
                    &format!("{tfield}.interval_from.column"),
                    format!("column `{}` holds values, not intervals", from.column),
                ));
            }
            None => {
                return Err(err(
                    &format!("{tfield}.interval_from"),
                    format!("the table has no `{d}` in column `{}`", from.column),
                ));
            }
        }
    };
    Ok(Tolerance {
        name: name.to_string(),
        kind,
        reason: t.reason.clone(),
    })
}

/// A case with corrections files applied to its subject: an aircraft file whose id a file
/// names, or whose main rotor's id a rotor file names; a rotor (alone, or under a teeter
/// record) whose id a file names. Returns the case unchanged when none applies, and which files
/// applied. A check's own `corrections` still act on top.
pub fn with_corrections(
    case: &Case,
    files: &[crate::corrections::CorrectionsFile],
) -> Result<(Case, Vec<String>), String> {
    use crate::corrections::Target;
    let mut c = case.clone();
    let mut used = Vec::new();
    for f in files {
        let here = |e: String| format!("{} on {}: {e}", f.path.display(), case.id);
        match (&mut c.subject, &f.target) {
            (Subject::Aircraft { file, .. }, Target::Aircraft(id)) if file.id == *id => {
                **file = file.with_corrections(&f.corrections).map_err(here)?;
                used.push(f.id.clone());
            }
            (Subject::Aircraft { file, .. }, Target::Rotor(id))
                if file.main_rotor_file.id == *id =>
            {
                **file = file.with_corrections(&f.corrections).map_err(here)?;
                used.push(f.id.clone());
            }
            (Subject::Rotor { file, .. }, Target::Rotor(id))
            | (Subject::FlapRecord { rotor: file, .. }, Target::Rotor(id))
                if file.id == *id =>
            {
                f.corrections
                    .apply_to_rotor(&mut file.rotor)
                    .map_err(here)?;
                file.path = PathBuf::from(format!(
                    "{}#{}",
                    file.path.display(),
                    f.corrections.describe()
                ));
                used.push(f.id.clone());
            }
            _ => {}
        }
    }
    Ok((c, used))
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
