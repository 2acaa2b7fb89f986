//! Reference files in `flight-refs/`: published linear models and derivative tables, each with
//! its provenance.
//!
//! ```yaml
//! id: seed002-vpm-m16-60kn            # equals the file stem
//! title: RASCAL linear model of the VPM M16 at 60 kn
//! provenance:
//!   source: "seed 002, Eq. 20"       # required: where the numbers come from
//!   notes: "..."                     # optional
//! condition:                         # optional, free-form; keys carry units
//!   airspeed_kn: 60
//! linear_model:                      # a linear model ...
//!   states: [w, q, u, theta, Omega]
//!   controls: [eta_s]
//!   units: {w: m/s, q: rad/s, u: m/s, theta: rad, Omega: rad/s, eta_s: rad}
//!   a: [[...], ...]                  # rows in state order
//!   b: [[...], ...]
//! columns:                           # ... and/or a derivative table
//!   flight_95: {kind: interval, description: "95 % confidence bounds from flight"}
//!   model_min_weight: {kind: value, description: "model at minimum weight"}
//! derivatives:
//!   - {name: L_p, units: 1/s, flight_95: [-2.727, -2.377], model_min_weight: -2.714}
//! ```

use crate::inputs::yaml::{self, InputError};
use cierva_model::LinearModel;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where numbers come from.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Provenance {
    /// The source: seed file and table or equation, report and table, or "estimated: why".
    pub source: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub notes: Option<String>,
}

/// A linear model as written in YAML.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinearModelSpec {
    pub states: Vec<String>,
    pub controls: Vec<String>,
    /// Units of every state and control.
    pub units: BTreeMap<String, String>,
    pub a: Vec<Vec<f64>>,
    pub b: Vec<Vec<f64>>,
}

impl LinearModelSpec {
    /// Builds and checks the model; `field` is the YAML path of this block, for errors.
    pub fn build(&self, path: &Path, src: &str, field: &str) -> Result<LinearModel, InputError> {
        for name in self.states.iter().chain(&self.controls) {
            if !self.units.contains_key(name) {
                return Err(InputError::field(
                    path,
                    src,
                    &format!("{field}.units"),
                    format!("no units given for `{name}`: every state and control needs its units"),
                ));
            }
        }
        if let Some(extra) = self
            .units
            .keys()
            .find(|k| !self.states.contains(k) && !self.controls.contains(k))
        {
            return Err(InputError::field(
                path,
                src,
                &format!("{field}.units"),
                format!("units given for `{extra}`, which is neither a state nor a control"),
            ));
        }
        LinearModel::from_rows(self.states.clone(), self.controls.clone(), &self.a, &self.b)
            .map_err(|e| {
                use cierva_model::LinearModelError as E;
                let key =
                    match &e {
                        E::ShapeA { .. } => "a",
                        E::ShapeB { .. } => "b",
                        E::Ragged { matrix, .. } | E::NotFinite { matrix, .. } => {
                            if *matrix == "A" { "a" } else { "b" }
                        }
                        _ => "states",
                    };
                InputError::field(path, src, &format!("{field}.{key}"), e.to_string())
            })
    }
}

/// What a column of a derivative table holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ColumnKind {
    /// One value per derivative.
    Value,
    /// A `[lower, upper]` interval per derivative (for example a 95 % flight bound).
    Interval,
}

/// A column of a derivative table.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ColumnSpec {
    pub kind: ColumnKind,
    pub description: String,
}

/// A reference file as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSpec {
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    #[serde(default)]
    pub condition: BTreeMap<String, serde_yaml::Value>,
    #[serde(default)]
    pub linear_model: Option<LinearModelSpec>,
    #[serde(default)]
    pub columns: BTreeMap<String, ColumnSpec>,
    #[serde(default)]
    pub derivatives: Vec<BTreeMap<String, serde_yaml::Value>>,
}

/// One entry of a derivative table column.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Entry {
    Value(f64),
    Interval(f64, f64),
}

/// A loaded derivative table: for each derivative, its units and its entry in each column.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DerivativeTable {
    pub columns: BTreeMap<String, ColumnSpec>,
    /// Derivative name -> (units, column -> entry), in file order.
    pub rows: Vec<(String, String, BTreeMap<String, Entry>)>,
}

impl DerivativeTable {
    /// The entry of a derivative in a column.
    pub fn entry(&self, derivative: &str, column: &str) -> Option<Entry> {
        self.rows
            .iter()
            .find(|(n, _, _)| n == derivative)
            .and_then(|(_, _, e)| e.get(column).copied())
    }
}

/// A loaded, checked reference file.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    pub path: PathBuf,
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    pub condition: BTreeMap<String, serde_yaml::Value>,
    pub linear_model: Option<LinearModel>,
    pub units: BTreeMap<String, String>,
    pub table: DerivativeTable,
}

/// Loads and checks a reference file.
pub fn load(path: &Path) -> Result<Reference, InputError> {
    let src = yaml::read(path)?;
    let spec: ReferenceSpec = yaml::parse(path, &src)?;
    check_id(path, &src, &spec.id)?;
    let linear_model = spec
        .linear_model
        .as_ref()
        .map(|m| m.build(path, &src, "linear_model"))
        .transpose()?;
    let units = spec
        .linear_model
        .as_ref()
        .map(|m| m.units.clone())
        .unwrap_or_default();
    let table = build_table(path, &src, &spec)?;
    if linear_model.is_none() && table.rows.is_empty() {
        return Err(InputError::field(
            path,
            &src,
            "derivatives",
            "a reference file needs a `linear_model` or a `derivatives` table",
        ));
    }
    Ok(Reference {
        path: path.to_path_buf(),
        id: spec.id,
        title: spec.title,
        provenance: spec.provenance,
        condition: spec.condition,
        linear_model,
        units,
        table,
    })
}

/// The id of a file must equal its stem, so that test names point at files.
pub fn check_id(path: &Path, src: &str, id: &str) -> Result<(), InputError> {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    if id != stem {
        return Err(InputError::field(
            path,
            src,
            "id",
            format!("the id `{id}` must equal the file name without extension (`{stem}`)"),
        ));
    }
    if id.contains("::") || id.contains("__") || id.trim().is_empty() {
        return Err(InputError::field(
            path,
            src,
            "id",
            format!("the id `{id}` must be non-empty and contain neither `::` nor `__`"),
        ));
    }
    Ok(())
}

fn build_table(
    path: &Path,
    src: &str,
    spec: &ReferenceSpec,
) -> Result<DerivativeTable, InputError> {
    let mut rows = Vec::new();
    for (i, row) in spec.derivatives.iter().enumerate() {
        let here = format!("derivatives[{i}]");
        let err = |field: &str, msg: String| InputError::field(path, src, field, msg);
        let text = |key: &str| -> Result<String, InputError> {
            match row.get(key) {
                Some(serde_yaml::Value::String(s)) => Ok(s.clone()),
                Some(_) => Err(err(&format!("{here}.{key}"), "expected a string".into())),
                None => Err(err(&here, format!("missing `{key}`"))),
            }
        };
        let name = text("name")?;
        let units = text("units")?;
        if rows
            .iter()
            .any(|(n, _, _): &(String, String, _)| *n == name)
        {
            return Err(err(&here, format!("derivative `{name}` appears twice")));
        }
        let mut entries = BTreeMap::new();
        for (key, value) in row {
            if key == "name" || key == "units" {
                continue;
            }
            let field = format!("{here}.{key}");
            let column = spec.columns.get(key).ok_or_else(|| {
                err(
                    &field,
                    format!(
                        "`{key}` is not a declared column; columns are [{}]",
                        spec.columns.keys().cloned().collect::<Vec<_>>().join(", ")
                    ),
                )
            })?;
            let entry = match (column.kind, value) {
                (ColumnKind::Value, v) => Entry::Value(number(v).ok_or_else(|| {
                    err(&field, format!("column `{key}` holds numbers, got {v:?}"))
                })?),
                (ColumnKind::Interval, serde_yaml::Value::Sequence(s)) if s.len() == 2 => {
                    match (number(&s[0]), number(&s[1])) {
                        (Some(lo), Some(hi)) if lo <= hi => Entry::Interval(lo, hi),
                        _ => {
                            return Err(err(
                                &field,
                                "an interval is [lower, upper] with finite lower <= upper".into(),
                            ));
                        }
                    }
                }
                (ColumnKind::Interval, _) => {
                    return Err(err(&field, "an interval is [lower, upper]".into()));
                }
            };
            entries.insert(key.clone(), entry);
        }
        rows.push((name, units, entries));
    }
    Ok(DerivativeTable {
        columns: spec.columns.clone(),
        rows,
    })
}

fn number(v: &serde_yaml::Value) -> Option<f64> {
    v.as_f64().filter(|x| x.is_finite())
}
