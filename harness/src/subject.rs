//! A case's subject: what its checks run on (a linear model, a published derivative table,
//! an isolated rotor, a teeter record, or an aircraft), as written and as loaded.

use crate::refs::{self, DerivativeTable, LinearModelSpec};
pub use crate::rotor_file::{DescentSpec, InflowSpec, SkewSpec};
use crate::yaml::InputError;
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
    /// The wake's mass flow in descent (default momentum theory).
    #[serde(default)]
    pub descent: DescentSpec,
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
        file: Box<crate::rotor_file::RotorFile>,
        /// The tunnel solver: the inflow model the case names, and the blade integration's
        /// numerics and Newton tolerances (the model's defaults; a grid study refines them).
        solver: cierva_model::components::autorotation::Options,
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

impl Subject {
    /// The kind of subject, in words ("a rotor").
    pub fn describe(&self) -> &'static str {
        match self {
            Self::Linear { .. } => "a linear model",
            Self::Table { .. } => "a derivative table",
            Self::Rotor { .. } => "a rotor",
            Self::Aircraft { .. } => "an aircraft",
            Self::FlapRecord { .. } => "a teeter record (`flap_record`)",
        }
    }
}

pub fn load(path: &Path, src: &str, dir: &Path, m: &ModelSpec) -> Result<Subject, InputError> {
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
            solver: r.inflow.model(r.skew, r.descent).into(),
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

pub fn load_table(
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
