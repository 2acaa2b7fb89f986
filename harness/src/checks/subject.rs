//! A case's subject: what its checks run on (a linear model, a published derivative table,
//! an isolated rotor, a teeter record, or an aircraft), as written and as loaded.

use crate::inputs::reference::{self, DerivativeTable, LinearModelSpec};
pub use crate::inputs::rotor::{DescentSpec, InflowSpec, SkewSpec};
use crate::inputs::yaml::InputError;
use cierva_model::LinearModel;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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
    /// Another simulation, run as a command (protocol `cierva-external/1`).
    #[serde(default)]
    pub external: Option<ExternalSpec>,
    /// Another simulation's outputs as files.
    #[serde(default)]
    pub files: Option<FilesSpec>,
}

/// Another simulation's outputs as files (see [`crate::external::files`]), each optional,
/// paths relative to the case file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilesSpec {
    /// A trim table (CSV, one row per level-flight airspeed).
    #[serde(default)]
    pub trim_table: Option<String>,
    /// A reference file holding a `linear_model`, at `at`.
    #[serde(default)]
    pub linear_model_file: Option<String>,
    /// The response to a reference record's controls (CSV), at `at`.
    #[serde(default)]
    pub time_history: Option<String>,
    /// The condition of the linear model and the time history.
    #[serde(default)]
    pub at: Option<crate::inputs::condition::TrimRequest>,
    /// Mass, kg, the files are at (as the checks' records and discrepancy records say).
    #[serde(default)]
    pub mass_kg: Option<f64>,
    /// ISA density altitude, ft.
    #[serde(default)]
    pub density_altitude_ft: f64,
}

/// Another simulation as a command: the program and its arguments (a path is relative to the
/// case file's folder, where it runs), the time one request may take, and the loading it is
/// asked at.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExternalSpec {
    pub command: Vec<String>,
    /// The protocol it speaks: `cierva-external/1` (the default) or `cierva-external/2`
    /// (`describe`, and parameters in requests).
    #[serde(default)]
    pub protocol: Option<String>,
    /// Started once and asked every request as a JSON line on its stdin (protocol `/2`'s
    /// persistent mode), instead of run once per request.
    #[serde(default)]
    pub persistent: bool,
    /// The longest one request may run, s; the process is killed after it (default
    /// [`DEFAULT_TIMEOUT_S`]).
    #[serde(default = "default_timeout_s")]
    pub timeout_s: f64,
    /// Mass, kg (passed to the model; none: the model's own).
    #[serde(default)]
    pub mass_kg: Option<f64>,
    /// ISA density altitude, ft.
    #[serde(default)]
    pub density_altitude_ft: f64,
}

/// The time one request may run where a case gives no `timeout_s`, s: a flight model's trim or
/// linearisation takes seconds, and a minute bounds a hung model without cutting a slow one
/// short (a case whose model needs longer says so).
pub const DEFAULT_TIMEOUT_S: f64 = 60.0;

fn default_timeout_s() -> f64 {
    DEFAULT_TIMEOUT_S
}

/// The longest `timeout_s` a case may give, s: an hour per request is already beyond a suite.
pub const MAX_TIMEOUT_S: f64 = 3600.0;

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

/// A rotor subject: the file, and any of its physics settings set otherwise (each absent one
/// is the rotor file's: [`crate::inputs::rotor::PhysicsSpec`]).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotorModelSpec {
    /// Path relative to the case file.
    pub file: String,
    #[serde(default)]
    pub inflow: Option<InflowSpec>,
    #[serde(default)]
    pub skew: Option<SkewSpec>,
    /// The wake's mass flow in descent.
    #[serde(default)]
    pub descent: Option<DescentSpec>,
}

impl RotorModelSpec {
    /// The settings it states.
    pub fn physics(&self) -> crate::inputs::rotor::PhysicsSpec {
        crate::inputs::rotor::PhysicsSpec {
            inflow: self.inflow,
            skew: self.skew,
            descent: self.descent,
        }
    }
}

/// A column of a derivative table in a reference file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TableColumnSpec {
    /// Path relative to the case file.
    pub file: String,
    pub column: String,
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
        file: Box<crate::inputs::rotor::RotorFile>,
        /// The tunnel solver: the rotor file's inflow model (or the one the case sets), and the
        /// blade integration's numerics and Newton tolerances (the model's defaults; a grid
        /// study refines them).
        solver: cierva_model::components::autorotation::AutorotationOptions,
        /// Each physics setting the case sets over the rotor file's, in words (every check's
        /// note says so).
        overrides: Vec<String>,
    },
    /// An aircraft, its mass and air.
    Aircraft {
        file: Box<crate::inputs::aircraft::AircraftFile>,
        loading: crate::inputs::condition::Loading,
    },
    /// Another simulation (a command, or its outputs as files) at a loading.
    External(Box<crate::external::External>),
    /// A teeter record, its rotor and the analysis settings.
    FlapRecord {
        record: Box<crate::inputs::record::Record>,
        rotor: Box<crate::inputs::rotor::RotorFile>,
        settings: crate::ident::flap::FlapSettings,
    },
}

impl Subject {
    /// The kind of subject, in words ("a rotor").
    pub fn describe(&self) -> &'static str {
        match self {
            Self::Linear { .. } => "a linear model",
            Self::Table { .. } => "a derivative table",
            Self::Rotor { .. } => "a rotor",
            Self::Aircraft { .. } => "an aircraft",
            Self::External(_) => "an external model",
            Self::FlapRecord { .. } => "a teeter record (`flap_record`)",
        }
    }
}

/// The case's subject (`model`), loaded and checked: exactly one kind, with its files.
pub fn load(path: &Path, src: &str, dir: &Path, m: &ModelSpec) -> Result<Subject, InputError> {
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let given = [
        m.linear_model_file.is_some(),
        m.linear_model.is_some(),
        m.derivative_table.is_some(),
        m.rotor.is_some(),
        m.flap_record.is_some(),
        m.aircraft.is_some(),
        m.external.is_some(),
        m.files.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        return Err(err(
            "model",
            "give exactly one of `linear_model_file`, `linear_model`, `derivative_table`, `rotor`, `flap_record`, `aircraft`, `external` or `files`"
                .into(),
        ));
    }
    if let Some(x) = &m.external {
        return external(&err, dir, x, "model.external").map(|e| Subject::External(Box::new(e)));
    }
    if let Some(a) = &m.aircraft {
        let file = crate::inputs::aircraft::load(&dir.join(&a.file)).map_err(|e| {
            err(
                "model.aircraft.file",
                format!("in the referenced file: {e}"),
            )
        })?;
        let loading = check_loading(&err, "model.aircraft", a.mass_kg, a.density_altitude_ft)?;
        crate::external::FlightModel::check_loading(
            &crate::external::CiervaAircraft::new(&file),
            &loading,
        )
        .map_err(|e| err("model.aircraft.mass_kg", e))?;
        return Ok(Subject::Aircraft {
            file: Box::new(file),
            loading,
        });
    }
    if let Some(f) = &m.files {
        return load_files(path, src, dir, f);
    }
    if let Some(f) = &m.flap_record {
        return flap_record(&err, dir, f);
    }
    if let Some(r) = &m.rotor {
        let rpath = dir.join(&r.file);
        let file = crate::inputs::rotor::load(&rpath)
            .map_err(|e| err("model.rotor.file", format!("in the referenced file: {e}")))?;
        let (physics, overrides) = r.physics().over(&file, "the case");
        return Ok(Subject::Rotor {
            file: Box::new(file),
            solver: physics.model().into(),
            overrides,
        });
    }
    if let Some(file) = &m.linear_model_file {
        let (rpath, model, units) =
            linear_model_file(dir, file, |msg| err("model.linear_model_file", msg))?;
        return Ok(Subject::Linear {
            model,
            file: Some(rpath),
            units,
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
    derivative_table(path, src, dir, t)
}

/// Another simulation run as a command (`external`, written at `field` of a case or a fit
/// file): its loading, its command line and its time limit checked.
pub fn external(
    err: &dyn Fn(&str, String) -> InputError,
    dir: &Path,
    x: &ExternalSpec,
    field: &str,
) -> Result<crate::external::External, InputError> {
    let loading = check_loading(err, field, x.mass_kg, x.density_altitude_ft)?;
    if x.command.is_empty() || x.command[0].trim().is_empty() {
        return Err(err(
            &format!("{field}.command"),
            "give the program and its arguments, `[python3, model.py]`".into(),
        ));
    }
    if !(x.timeout_s.is_finite() && x.timeout_s > 0.0 && x.timeout_s <= MAX_TIMEOUT_S) {
        return Err(err(
            &format!("{field}.timeout_s"),
            format!("must be in (0, {MAX_TIMEOUT_S}] s, got {}", x.timeout_s),
        ));
    }
    let protocol = match &x.protocol {
        None => crate::external::command::Protocol::V1,
        Some(p) => crate::external::command::Protocol::parse(p)
            .map_err(|e| err(&format!("{field}.protocol"), e))?,
    };
    let mut command = crate::external::command::ExternalCommand::speaking(
        x.command.clone(),
        dir.to_path_buf(),
        std::time::Duration::from_secs_f64(x.timeout_s),
        protocol,
    );
    if x.persistent {
        if protocol != crate::external::command::Protocol::V2 {
            return Err(err(
                &format!("{field}.persistent"),
                format!(
                    "persistent mode is protocol `{}`'s: say `protocol: {}`",
                    crate::external::command::PROTOCOL_2,
                    crate::external::command::PROTOCOL_2
                ),
            ));
        }
        command = command.persistent();
    }
    Ok(crate::external::External {
        written: format!("command: {}", command.written()),
        model: std::sync::Arc::new(command),
        loading,
        folder: crate::external::folder_of(dir),
    })
}

/// A teeter record (`flap_record`): the record with the flapping channels, its rotor file,
/// and the analysis settings (a positive density).
fn flap_record(
    err: &dyn Fn(&str, String) -> InputError,
    dir: &Path,
    f: &FlapRecordSpec,
) -> Result<Subject, InputError> {
    let rec = crate::inputs::record::load_with(
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
    let rotor = crate::inputs::rotor::load(&dir.join(&f.rotor)).map_err(|e| {
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
    Ok(Subject::FlapRecord {
        record: Box::new(rec),
        rotor: Box::new(rotor),
        settings: crate::ident::flap::FlapSettings {
            coning: f.coning,
            skew: f.skew,
            density_kg_m3: f.density_kg_m3,
            collective_deg: f.collective_deg,
        },
    })
}

/// Published derivative values (`derivative_table`): the table file and its column, which
/// must hold values.
fn derivative_table(
    path: &Path,
    src: &str,
    dir: &Path,
    t: &TableColumnSpec,
) -> Result<Subject, InputError> {
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let tpath = dir.join(&t.file);
    let table = load_table(path, src, &tpath, "model.derivative_table.file")?;
    match table.columns.get(&t.column) {
        Some(c) if c.kind == reference::ColumnKind::Value => {}
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

/// Another simulation's outputs as files, each read and checked.
fn load_files(path: &Path, src: &str, dir: &Path, f: &FilesSpec) -> Result<Subject, InputError> {
    use crate::external::files;
    let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
    let loading = check_loading(&err, "model.files", f.mass_kg, f.density_altitude_ft)?;
    if f.trim_table.is_none() && f.linear_model_file.is_none() && f.time_history.is_none() {
        return Err(err(
            "model.files",
            "give at least one of `trim_table`, `linear_model_file` or `time_history`".into(),
        ));
    }
    let needs_at = f.linear_model_file.is_some() || f.time_history.is_some();
    match (&f.at, needs_at) {
        (None, true) => {
            return Err(err(
                "model.files",
                "give `at`, the condition of the linear model and the time history".into(),
            ));
        }
        (Some(_), false) => {
            return Err(err(
                "model.files.at",
                "`at` is the condition of a linear model or a time history; there is neither"
                    .into(),
            ));
        }
        (Some(t), true)
            if !(t.airspeed_mph.is_finite()
                && t.airspeed_mph > 0.0
                && t.climb_m_s.is_finite()
                && t.turn_rate_deg_s.is_finite()) =>
        {
            return Err(err(
                "model.files.at",
                "the airspeed must be positive, climb and turn rates finite".into(),
            ));
        }
        _ => {}
    }
    let read = |field: &str, file: &str| -> Result<(PathBuf, String), InputError> {
        let p = dir.join(file);
        std::fs::read_to_string(&p)
            .map(|t| (p.clone(), t))
            .map_err(|e| err(field, format!("cannot read {}: {e}", p.display())))
    };
    let csv = |field: &str, p: &Path, e: files::CsvError| {
        err(field, format!("in the referenced file: {}", e.in_file(p)))
    };
    let trim_table = match &f.trim_table {
        Some(file) => {
            let (p, text) = read("model.files.trim_table", file)?;
            let rows =
                files::parse_trim_table(&text).map_err(|e| csv("model.files.trim_table", &p, e))?;
            Some((p, rows))
        }
        None => None,
    };
    let time_history = match &f.time_history {
        Some(file) => {
            let (p, text) = read("model.files.time_history", file)?;
            let flown = files::parse_history(&text, None)
                .map_err(|e| csv("model.files.time_history", &p, e))?;
            Some((p, flown))
        }
        None => None,
    };
    let linear_model = match &f.linear_model_file {
        Some(file) => {
            let (rpath, model, _) =
                linear_model_file(dir, file, |msg| err("model.files.linear_model_file", msg))?;
            Some((rpath, model))
        }
        None => None,
    };
    let model = crate::external::files::Files {
        trim_table,
        linear_model,
        time_history,
        at: f.at,
    };
    Ok(Subject::External(Box::new(crate::external::External {
        written: format!("files: {}", model.written()),
        model: std::sync::Arc::new(model),
        loading,
        folder: crate::external::folder_of(dir),
    })))
}

/// A reference file's linear model (`file` relative to the case's folder `dir`): its path,
/// the model and its units; `err` locates what is wrong at the case's field.
fn linear_model_file(
    dir: &Path,
    file: &str,
    err: impl Fn(String) -> InputError,
) -> Result<(PathBuf, LinearModel, BTreeMap<String, String>), InputError> {
    let rpath = dir.join(file);
    let r = reference::load(&rpath).map_err(|e| err(format!("in the referenced file: {e}")))?;
    let model = r
        .linear_model
        .ok_or_else(|| err(format!("{} has no `linear_model` block", rpath.display())))?;
    Ok((rpath, model, r.units))
}

/// A subject's mass and air, checked: a positive mass, a density altitude in [-2000, 20000] ft.
fn check_loading(
    err: &dyn Fn(&str, String) -> InputError,
    field: &str,
    mass_kg: Option<f64>,
    density_altitude_ft: f64,
) -> Result<crate::inputs::condition::Loading, InputError> {
    if let Some(mass) = mass_kg
        && !(mass.is_finite() && mass > 0.0)
    {
        return Err(err(
            &format!("{field}.mass_kg"),
            format!("must be positive, got {mass}"),
        ));
    }
    if !(-2000.0..=20000.0).contains(&density_altitude_ft) {
        return Err(err(
            &format!("{field}.density_altitude_ft"),
            format!("must be in [-2000, 20000] ft, got {density_altitude_ft}"),
        ));
    }
    Ok(crate::inputs::condition::Loading {
        mass_kg,
        density_altitude_ft,
    })
}

pub fn load_table(
    path: &Path,
    src: &str,
    tpath: &Path,
    field: &str,
) -> Result<DerivativeTable, InputError> {
    let r = reference::load(tpath)
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
