//! Another simulation's outputs as files: a trim table, a linear model, a time history.
//!
//! - The trim table is a CSV, one row per level-flight condition: the airspeed
//!   (`airspeed_mph`, `airspeed_kn` or `airspeed_m_s`) and any trim quantities, named with their
//!   units as in [`crate::inputs::quantity::TRIM`] (`pitch_deg`). Lines that begin with `#` are
//!   comments (the table's provenance).
//! - The linear model is a reference file's `linear_model` (as `linear_model_file` reads it),
//!   at the condition `at`.
//! - The time history is the model's response to a reference record's controls, at `at`: a CSV
//!   of `time_s` and responses named as in [`crate::run::replay::SIGNALS`] (changes from trim), one
//!   row per sample of the record.
//!
//! Files are read and checked when the case loads; errors name the file, line and column.

use super::{ControlChanges, FlightModel, Quantities, Request, check_values, trim_name};
use crate::inputs::condition::TrimRequest;
use crate::inputs::yaml::InputError;
use crate::run::replay::{Replayed, SIGNALS};
use cierva_model::LinearModel;
use std::path::{Path, PathBuf};

/// How near a requested airspeed must be to a row's, mph: a case's airspeed and a table's are
/// written in decimals and converted between units in double precision.
pub const AIRSPEED_MATCH_MPH: f64 = 1e-6;

/// A located error in a CSV file: 1-based line and column.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvError {
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub message: String,
}

impl CsvError {
    fn at(line: usize, column: Option<usize>, message: impl Into<String>) -> Self {
        Self {
            line: Some(line),
            column,
            message: message.into(),
        }
    }

    /// As an error in `path`.
    pub fn in_file(self, path: &Path) -> InputError {
        InputError {
            path: path.to_path_buf(),
            line: self.line,
            column: self.column,
            field: None,
            message: self.message,
        }
    }
}

impl std::fmt::Display for CsvError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.line, self.column) {
            (Some(l), Some(c)) => write!(f, "line {l}, column {c}: {}", self.message),
            (Some(l), None) => write!(f, "line {l}: {}", self.message),
            _ => write!(f, "{}", self.message),
        }
    }
}

/// A CSV's header and rows of finite numbers (lines beginning with `#` and blank lines
/// skipped), each row with its 1-based line.
type Table = (Vec<String>, Vec<(usize, Vec<f64>)>);

fn read_csv(text: &str) -> Result<Table, CsvError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines.next().ok_or(CsvError {
        line: None,
        column: None,
        message: "is empty (a CSV with a header was expected)".into(),
    })?;
    let columns: Vec<String> = header.split(',').map(|c| c.trim().to_string()).collect();
    let mut rows = Vec::new();
    for (n, line) in lines {
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != columns.len() {
            return Err(CsvError::at(
                n,
                None,
                format!("{} cells; the header has {}", cells.len(), columns.len()),
            ));
        }
        let mut row = Vec::with_capacity(cells.len());
        for (k, c) in cells.iter().enumerate() {
            row.push(crate::inputs::yaml::number(c).map_err(|e| {
                CsvError::at(
                    n,
                    Some(crate::inputs::yaml::csv_field_column(line, k)),
                    format!("`{}`: {e}", columns[k]),
                )
            })?);
        }
        rows.push((n, row));
    }
    Ok((columns, rows))
}

/// A time history: `time_s` and responses named as in [`SIGNALS`]; `samples` rows where given.
pub fn parse_history(text: &str, samples: Option<usize>) -> Result<Replayed, CsvError> {
    let (columns, rows) = read_csv(text)?;
    let header_line = text
        .lines()
        .position(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map_or(1, |i| i + 1);
    let mut index = vec![None; SIGNALS.len()];
    let mut time_col = None;
    for (c, name) in columns.iter().enumerate() {
        let seen = if name == "time_s" {
            time_col.replace(c).is_some()
        } else if let Some(i) = SIGNALS.iter().position(|s| s == name) {
            index[i].replace(c).is_some()
        } else {
            return Err(CsvError::at(
                header_line,
                Some(c + 1),
                format!(
                    "`{name}` is not `time_s` or a response cierva compares ({})",
                    SIGNALS.join(", ")
                ),
            ));
        };
        if seen {
            return Err(CsvError::at(
                header_line,
                Some(c + 1),
                format!("column `{name}` is given twice"),
            ));
        }
    }
    let time_col = time_col.ok_or_else(|| CsvError::at(header_line, None, "no `time_s` column"))?;
    if let Some(n) = samples
        && rows.len() != n
    {
        return Err(CsvError {
            line: None,
            column: None,
            message: format!("has {} rows; {n} were asked for", rows.len()),
        });
    }
    Ok(Replayed {
        time_s: rows.iter().map(|(_, r)| r[time_col]).collect(),
        signals: index
            .iter()
            .map(|c| c.map_or_else(Vec::new, |c| rows.iter().map(|(_, r)| r[c]).collect()))
            .collect(),
    })
}

/// A trim table: each row's airspeed, mph, and quantities.
pub fn parse_trim_table(text: &str) -> Result<Vec<(f64, Quantities)>, CsvError> {
    let (columns, rows) = read_csv(text)?;
    let header_line = text
        .lines()
        .position(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map_or(1, |i| i + 1);
    let mut airspeed: Option<(usize, f64)> = None;
    let mut names = Vec::new();
    for (c, name) in columns.iter().enumerate() {
        let to_mph = match name.as_str() {
            "airspeed_mph" => Some(1.0),
            "airspeed_kn" => Some(crate::units::MPH_PER_KN),
            "airspeed_m_s" => Some(1.0 / crate::units::MPH_TO_M_S),
            _ => None,
        };
        match to_mph {
            Some(_) if airspeed.is_some() => {
                return Err(CsvError::at(
                    header_line,
                    Some(c + 1),
                    "give one airspeed column",
                ));
            }
            Some(f) => airspeed = Some((c, f)),
            None => {
                let q = trim_name(name).map_err(|e| CsvError::at(header_line, Some(c + 1), e))?;
                if names.iter().any(|(_, n)| *n == q) {
                    return Err(CsvError::at(
                        header_line,
                        Some(c + 1),
                        format!("column `{q}` is given twice"),
                    ));
                }
                names.push((c, q));
            }
        }
    }
    let (ac, factor) = airspeed.ok_or_else(|| {
        CsvError::at(
            header_line,
            None,
            "no airspeed column (`airspeed_mph`, `airspeed_kn` or `airspeed_m_s`)",
        )
    })?;
    let mut out: Vec<(f64, Quantities)> = Vec::new();
    for (n, row) in rows {
        let v = row[ac] * factor;
        if v <= 0.0 {
            return Err(CsvError::at(n, None, "the airspeed must be positive"));
        }
        if out.iter().any(|(w, _)| (w - v).abs() <= AIRSPEED_MATCH_MPH) {
            return Err(CsvError::at(n, None, "a second row at this airspeed"));
        }
        out.push((v, names.iter().map(|(c, q)| (*q, row[*c])).collect()));
    }
    if out.is_empty() {
        return Err(CsvError {
            line: None,
            column: None,
            message: "has no rows".into(),
        });
    }
    Ok(out)
}

/// Another simulation's outputs, loaded and checked.
#[derive(Debug, Clone)]
pub struct Files {
    /// The trim table, its file and rows (airspeed, mph, and quantities).
    pub trim_table: Option<(PathBuf, Vec<(f64, Quantities)>)>,
    /// The linear model and its file.
    pub linear_model: Option<(PathBuf, LinearModel)>,
    /// The time history and its file.
    pub time_history: Option<(PathBuf, Replayed)>,
    /// The condition of the linear model and the time history.
    pub at: Option<TrimRequest>,
}

impl Files {
    /// The files in words.
    pub fn written(&self) -> String {
        [
            self.trim_table.as_ref().map(|t| &t.0),
            self.linear_model.as_ref().map(|t| &t.0),
            self.time_history.as_ref().map(|t| &t.0),
        ]
        .iter()
        .flatten()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
    }

    /// Whether `condition` is the one the files give, or the error that says which they give.
    fn at(&self, condition: TrimRequest, what: &str, file: &Path) -> Result<(), String> {
        let at = self.at.ok_or("no `at` condition")?;
        if (at.airspeed_mph - condition.airspeed_mph).abs() <= AIRSPEED_MATCH_MPH
            && at.climb_m_s == condition.climb_m_s
            && at.turn_rate_deg_s == condition.turn_rate_deg_s
        {
            Ok(())
        } else {
            Err(format!(
                "{} gives {what} at {} mph (climb {} m/s, turn {} deg/s) only; the check asks \
                 for {} mph (climb {} m/s, turn {} deg/s)",
                file.display(),
                at.airspeed_mph,
                at.climb_m_s,
                at.turn_rate_deg_s,
                condition.airspeed_mph,
                condition.climb_m_s,
                condition.turn_rate_deg_s
            ))
        }
    }
}

impl FlightModel for Files {
    fn describe(&self) -> String {
        format!("the files {}", self.written())
    }

    fn trim(&self, request: &Request) -> Result<Quantities, String> {
        check_values(&self.describe(), &[], &request.parameters)?;
        let condition = request.condition;
        let Some((path, rows)) = &self.trim_table else {
            return Err(super::not_provided(
                &self.describe(),
                "a trim (no `trim_table`)",
            ));
        };
        if condition.climb_m_s != 0.0 || condition.turn_rate_deg_s != 0.0 {
            return Err(format!("{} is a table of level flight", path.display()));
        }
        interpolated(rows, condition.airspeed_mph).ok_or_else(|| {
            format!(
                "{} has no row at or around {} mph: it gives {} mph, and a trim is interpolated \
                 between its rows, never beyond them (the model's envelope as the table gives it)",
                path.display(),
                condition.airspeed_mph,
                rows.iter()
                    .map(|(v, _)| format!("{v}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
    }

    fn linear_model(&self, request: &Request) -> Result<LinearModel, String> {
        check_values(&self.describe(), &[], &request.parameters)?;
        let condition = request.condition;
        let Some((path, model)) = &self.linear_model else {
            return Err(super::not_provided(
                &self.describe(),
                "a linear model (no `linear_model_file`)",
            ));
        };
        self.at(condition, "its linear model", path)?;
        Ok(model.clone())
    }

    fn time_history(
        &self,
        request: &Request,
        controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        check_values(&self.describe(), &[], &request.parameters)?;
        let condition = request.condition;
        let Some((path, flown)) = &self.time_history else {
            return Err(super::not_provided(
                &self.describe(),
                "a time history (no `time_history`)",
            ));
        };
        self.at(condition, "its time history", path)?;
        if flown.time_s.len() != controls.samples + 1 {
            return Err(format!(
                "{} has {} rows; the record has {} samples",
                path.display(),
                flown.time_s.len(),
                controls.samples + 1
            ));
        }
        Ok(flown.clone())
    }
}

/// A trim table's quantities at `airspeed_mph`: its row there (within
/// [`AIRSPEED_MATCH_MPH`]), or linearly interpolated between the rows either side of it (each
/// quantity both rows give); `None` outside the table's airspeeds. Linear interpolation errs by
/// about an eighth of the change in slope across the interval times its width: the table's own
/// spacing decides how near a check between rows comes to the model.
pub fn interpolated(rows: &[(f64, Quantities)], airspeed_mph: f64) -> Option<Quantities> {
    if let Some((_, q)) = rows
        .iter()
        .find(|(v, _)| (v - airspeed_mph).abs() <= AIRSPEED_MATCH_MPH)
    {
        return Some(q.clone());
    }
    let below = rows
        .iter()
        .filter(|(v, _)| *v < airspeed_mph)
        .max_by(|a, b| a.0.total_cmp(&b.0))?;
    let above = rows
        .iter()
        .filter(|(v, _)| *v > airspeed_mph)
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    let t = (airspeed_mph - below.0) / (above.0 - below.0);
    Some(
        below
            .1
            .iter()
            .filter_map(|(n, lo)| {
                let (_, hi) = above.1.iter().find(|(m, _)| m == n)?;
                Some((*n, lo + t * (hi - lo)))
            })
            .collect(),
    )
}
