//! Flight trim points: a CSV of trimmed flight conditions as a flight test gives them, one row
//! a point, each measured quantity with its scatter, and a YAML sidecar (what `trim_points`
//! checks read).
//!
//! `POINTS.csv`:
//!
//! ```text
//! airspeed_mph,mass_kg,stick_longitudinal_percent,sd_stick_longitudinal_percent,pitch_deg,sd_pitch_deg,oat_c
//! 41.0,452,71.2,1.5,9.1,0.5,14
//! 52.5,449,63.0,1.5,,,14
//! 60.2,447,59.4,1.5,4.6,0.5,15
//! 68.0,446,56.8,1.5,3.1,0.5,15
//! ```
//!
//! - `airspeed_mph` (or `airspeed_kn`, `airspeed_m_s`: converted) on every row;
//! - optional `mass_kg` (or `mass_lb`) and `density_altitude_ft` (or `density_altitude_m`) per
//!   point; without them a point is flown at its case's loading;
//! - any trim quantity cierva computes ([`crate::inputs::quantity::TRIM`], those the trim
//!   solves for excepted), each with `sd_<quantity>`: the point's scatter, one standard
//!   deviation in the same unit (a quantity in another unit converts, its scatter with it). A
//!   blank cell is a quantity not measured at that point;
//! - other columns (a temperature, a note) are not read; the load's notes name them.
//!
//! `POINTS.yaml`, beside it:
//!
//! ```yaml
//! id: vpm-m16-trim-points            # equals the file stem
//! title: ...
//! provenance: {source: "..."}
//! synthetic: {generator: ..., seed: 7, truth: ...}   # synthetic only
//! aircraft: VPM M16
//! channels: {IAS_KT: airspeed_kn}     # optional: a column's cierva name, its unit the suffix
//! ```

use crate::inputs::record::{Synthetic, at, at_field, current_name};
use crate::inputs::reference::{Provenance, check_id};
use crate::inputs::yaml::{self, InputError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The prefix of a quantity's scatter column: `sd_pitch_deg`.
pub const SCATTER: &str = "sd_";

/// The most points a file may have: far more than a flight campaign's trims, few enough that a
/// check asks its model a bounded number of trims.
pub const MAX_TRIM_POINTS: usize = 1_000;

/// The fewest points of a quantity: its level and its trend are two numbers fitted to them, and
/// a third point leaves one degree of freedom for the scatter about them.
pub const MIN_POINTS: usize = 3;

/// The sidecar.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TrimPointsMeta {
    pub id: String,
    pub title: String,
    pub provenance: Provenance,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub synthetic: Option<Synthetic>,
    pub aircraft: String,
    /// Columns as written mapped to cierva's names, with their units as the names' suffixes
    /// ([`crate::inputs::channels`]).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub channels: BTreeMap<String, String>,
}

/// One measured value at a point: the value and its scatter (one standard deviation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointValue {
    pub value: f64,
    pub sd: f64,
}

/// One trimmed flight condition.
#[derive(Debug, Clone, PartialEq)]
pub struct FlightTrimPoint {
    /// Its line in the CSV (1-based), for errors.
    pub line: usize,
    pub airspeed_mph: f64,
    pub mass_kg: Option<f64>,
    pub density_altitude_ft: Option<f64>,
    /// The quantities measured at it, by cierva's name.
    pub values: BTreeMap<String, PointValue>,
}

/// A loaded, checked file of trim points.
#[derive(Debug, Clone, PartialEq)]
pub struct TrimPoints {
    pub path: PathBuf,
    pub meta: TrimPointsMeta,
    pub points: Vec<FlightTrimPoint>,
    /// The quantities measured, in the header's order.
    pub quantities: Vec<String>,
    /// What the load mapped, converted or left out, in words.
    pub notes: Vec<String>,
}

impl TrimPoints {
    /// The points at which `quantity` was measured: (airspeed, mph; the measurement).
    pub fn series(&self, quantity: &str) -> Vec<(f64, PointValue)> {
        self.points
            .iter()
            .filter_map(|p| Some((p.airspeed_mph, *p.values.get(quantity)?)))
            .collect()
    }
}

/// The trim quantities a point may carry: what cierva's trim computes, less what it solves for.
pub fn comparable() -> Vec<&'static str> {
    crate::inputs::quantity::TRIM
        .iter()
        .filter(|q| !crate::inputs::quantity::ENFORCED_BY_TRIM.contains(q))
        .map(|q| q.name())
        .collect()
}

const AIRSPEED: &str = "airspeed_mph";
const MASS: &str = "mass_kg";
const ALTITUDE: &str = "density_altitude_ft";
/// A point's condition columns.
const CONDITIONS: [&str; 3] = [AIRSPEED, MASS, ALTITUDE];

/// Loads and checks a file of trim points and its sidecar.
pub fn load(csv_path: &Path) -> Result<TrimPoints, InputError> {
    let side = crate::inputs::record::sidecar_path(csv_path);
    let side_src = yaml::read(&side)?;
    let meta: TrimPointsMeta = yaml::parse(&side, &side_src)?;
    check_id(&side, &side_src, &meta.id)?;
    let src = yaml::read_csv(csv_path)?;
    let mut lines = src
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (header_no, header) = lines
        .next()
        .ok_or_else(|| InputError::file(csv_path, "the file is empty"))?;
    let header_no = header_no + 1;
    let written: Vec<String> = header.split(',').map(|w| current_name(w.trim())).collect();
    for (i, c) in written.iter().enumerate() {
        if c.is_empty() {
            return Err(at(
                csv_path,
                header_no,
                format!("column {} has no name", i + 1),
            ));
        }
        if written[..i].contains(c) {
            return Err(at(
                csv_path,
                header_no,
                format!("column `{c}` appears twice"),
            ));
        }
    }
    let quantities = comparable();
    let mut wanted: Vec<String> = CONDITIONS.iter().map(|c| c.to_string()).collect();
    for q in &quantities {
        wanted.push((*q).to_string());
        wanted.push(format!("{SCATTER}{q}"));
    }
    let wanted: Vec<&str> = wanted.iter().map(String::as_str).collect();
    let plan = crate::inputs::channels::plan(&written, &meta.channels, &BTreeMap::new(), &wanted)
        .map_err(|(field, m)| InputError::field(&side, &side_src, &field, m))?;
    let names = plan.names;
    let mut notes = plan.notes;
    for (i, c) in names.iter().enumerate() {
        if names[..i].contains(c) {
            return Err(at(
                csv_path,
                header_no,
                format!("column `{c}` appears twice (as written or as mapped)"),
            ));
        }
    }
    if !names.iter().any(|n| n == AIRSPEED) {
        return Err(at(
            csv_path,
            header_no,
            format!(
                "no `{AIRSPEED}` column (or `airspeed_kn`, `airspeed_m_s`, or a column mapped to \
                 one of them in the sidecar's `channels:`): every point needs its airspeed"
            ),
        ));
    }
    let (measured, ignored) = roles(&|m| at(csv_path, header_no, m), &names, &quantities)?;
    if measured.is_empty() {
        return Err(at(
            csv_path,
            header_no,
            format!(
                "no trim quantity to compare: name columns among {} (each with its `{SCATTER}` \
                 column)",
                quantities.join(", ")
            ),
        ));
    }
    if !ignored.is_empty() {
        notes.push(format!(
            "not compared (not a trim quantity cierva computes, or another unit of a column it \
             reads): `{}`",
            ignored.join("`, `")
        ));
    }
    let points = points(csv_path, lines, &names, &plan.factors, &measured)?;
    Ok(TrimPoints {
        path: csv_path.to_path_buf(),
        meta,
        points,
        quantities: measured,
        notes,
    })
}

/// Each column's role: a condition, a measured quantity (returned, in the header's order), its
/// scatter, or kept and not compared (returned). A column a letter or two from a quantity's
/// name, in any unit it converts from, is a misspelt one: an error before any pairing of
/// values and scatters.
fn roles(
    at_header: &dyn Fn(String) -> InputError,
    names: &[String],
    quantities: &[&str],
) -> Result<(Vec<String>, Vec<String>), InputError> {
    // Every name a column is read as, in every unit it converts from: the quantities and the
    // point's conditions.
    let spellings: Vec<String> = quantities
        .iter()
        .chain(&CONDITIONS)
        .flat_map(|q| {
            std::iter::once(q.to_string()).chain(
                crate::inputs::channels::CONVERSIONS
                    .iter()
                    .filter_map(|(to, from, _, _)| Some(format!("{}{from}", q.strip_suffix(to)?))),
            )
        })
        .collect();
    let known = |n: &str| {
        let q = n.strip_prefix(SCATTER).unwrap_or(n);
        CONDITIONS.contains(&n) || quantities.contains(&q)
    };
    let mut ignored: Vec<String> = Vec::new();
    for n in names.iter().filter(|n| !known(n)) {
        let q = n.strip_prefix(SCATTER).unwrap_or(n);
        // Another unit's spelling of a name the file already has (`pitch_rad` beside
        // `pitch_deg`): the one in cierva's unit is read.
        if spellings.iter().any(|s| s == q) {
            ignored.push(n.clone());
            continue;
        }
        if let Some(near) = crate::inputs::yaml::nearest(q, &spellings).filter(|m| {
            crate::inputs::yaml::edit_distance(q, m) <= crate::inputs::yaml::NEAR_MISS_EDITS
        }) {
            return Err(at_header(format!(
                "column `{n}` is nothing cierva reads from trim points; did you mean `{near}`? \
                 (rename it; or, to keep it and not compare it, map it to another name in the \
                 sidecar's `channels:`)"
            )));
        }
        ignored.push(n.clone());
    }
    let mut measured: Vec<String> = Vec::new();
    for n in names.iter().filter(|n| known(n)) {
        if CONDITIONS.contains(&n.as_str()) {
            continue;
        }
        if let Some(q) = n.strip_prefix(SCATTER) {
            if !names.iter().any(|m| m == q) {
                return Err(at_header(format!(
                    "`{n}` is the scatter of `{q}`, which the file has no column of"
                )));
            }
            continue;
        }
        if !names.iter().any(|m| *m == format!("{SCATTER}{n}")) {
            return Err(at_header(format!(
                "`{n}` has no scatter: give `{SCATTER}{n}`, one standard deviation of each point \
                 in its unit (a point's repeatability, or the test's estimate of it)"
            )));
        }
        measured.push(n.clone());
    }
    Ok((measured, ignored))
}

/// The rows as points: each value converted to its asked unit by `factors`, each error at its
/// line and column.
fn points<'a>(
    csv_path: &Path,
    lines: impl Iterator<Item = (usize, &'a str)>,
    names: &[String],
    factors: &[Option<f64>],
    measured: &[String],
) -> Result<Vec<FlightTrimPoint>, InputError> {
    let column = |name: &str| names.iter().position(|n| n == name);
    let mut points = Vec::new();
    for (line_no, line) in lines {
        let line_no = line_no + 1;
        if points.len() == MAX_TRIM_POINTS {
            return Err(at(
                csv_path,
                line_no,
                format!("a file may have at most {MAX_TRIM_POINTS} points (MAX_TRIM_POINTS)"),
            ));
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(at(
                csv_path,
                line_no,
                format!(
                    "{} values where the header has {} columns",
                    fields.len(),
                    names.len()
                ),
            ));
        }
        let bad = |k: usize, why: String| at_field(csv_path, line_no, line, k, why);
        // A column's value at this row, converted to its asked unit; `None` where blank.
        let value = |k: usize| -> Result<Option<f64>, InputError> {
            let v = fields[k];
            if v.is_empty() {
                return Ok(None);
            }
            crate::inputs::yaml::number(v)
                .ok()
                .map(|x| x * factors[k].unwrap_or(1.0))
                .filter(|x| x.is_finite())
                .map(Some)
                .ok_or_else(|| {
                    bad(
                        k,
                        format!("`{}`: `{v}` is not a finite number (in its unit)", names[k]),
                    )
                })
        };
        let k = column(AIRSPEED).expect("checked");
        let airspeed_mph = value(k)?
            .filter(|v| *v > 0.0)
            .ok_or_else(|| bad(k, "every point needs a positive airspeed".into()))?;
        let optional = |name: &str| column(name).map(&value).transpose().map(Option::flatten);
        let mass_kg = optional(MASS)?;
        if let Some(m) = mass_kg
            && m <= 0.0
        {
            return Err(bad(
                column(MASS).expect("read"),
                "a mass is positive".into(),
            ));
        }
        let density_altitude_ft = optional(ALTITUDE)?;
        if let Some(h) = density_altitude_ft
            && !(-2000.0..=20000.0).contains(&h)
        {
            return Err(bad(
                column(ALTITUDE).expect("read"),
                format!("a density altitude is in [-2000, 20000] ft, as a case's; got {h}"),
            ));
        }
        let mut values = BTreeMap::new();
        for q in measured {
            let (kq, ks) = (
                column(q).expect("measured"),
                column(&format!("{SCATTER}{q}")).expect("checked"),
            );
            match (value(kq)?, value(ks)?) {
                (None, None) => {}
                (Some(v), Some(sd)) if sd > 0.0 && sd.powi(-2).is_finite() => {
                    values.insert(q.clone(), PointValue { value: v, sd });
                }
                (Some(_), Some(sd)) => {
                    return Err(bad(
                        ks,
                        format!(
                            "a scatter is a standard deviation, > 0 (and above 1e-150, so that its \
                             weight 1 / sd^2 is finite); got {sd}"
                        ),
                    ));
                }
                (Some(_), None) => {
                    return Err(bad(ks, format!("`{q}` is given here without its scatter")));
                }
                (None, Some(_)) => {
                    return Err(bad(kq, format!("a scatter is given here without `{q}`")));
                }
            }
        }
        points.push(FlightTrimPoint {
            line: line_no,
            airspeed_mph,
            mass_kg,
            density_altitude_ft,
            values,
        });
    }
    Ok(points)
}
