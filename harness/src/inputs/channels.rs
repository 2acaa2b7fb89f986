//! A flight record's columns as cierva's channels: the sidecar's `channels:` map (a column's
//! cierva name, with its unit as the name's suffix) and the unit conversions that bring a
//! column to the unit cierva asks for.
//!
//! ```yaml
//! channels:                 # in the record's sidecar: column as written -> cierva name_unit
//!   PITCH: theta_deg        # converted to theta_rad where theta_rad is asked for
//!   IAS: airspeed_kn        # to airspeed_m_s
//!   NR: omega_rotor_rpm     # to omega_rotor_rad_s
//!   STICK_LON: eta_s_percent
//! ```
//!
//! A channel cierva needs (`theta_rad`) that the record lacks is taken from a column of the
//! same name in another unit (`theta_deg`, written so or mapped so), converted by the factor of
//! [`CONVERSIONS`]. Columns nobody asks for are kept as they are, or left out where they are not
//! numbers (a status word); the load says which.
//!
//! A control logged in its own unit (a stick's angle, a pedal's travel in mm) comes to % of
//! travel through the sidecar's `travel:` ([`Travel`]): the control's positions at 0 % and 100 %
//! in that unit, and whether the column is the control's position or its change from trim.
//!
//! ```yaml
//! travel:                   # in the record's sidecar: control -> its travel in its own unit
//!   eta_s: {unit: deg, at_0_percent: -12.0, at_100_percent: 14.0, logged: position}
//! ```

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A control logged in its own unit: the column `<control>_<unit>` becomes
/// `<control>_percent`. A position `x` is `100 (x - at_0_percent) / (at_100_percent -
/// at_0_percent)` % of travel; a change from trim `dx` is `100 dx / (at_100_percent -
/// at_0_percent)` (a time history's controls are changes from trim, an identification record's
/// are positions, so the sidecar says which).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Travel {
    /// The column's unit, as the column's suffix (`deg` for `eta_s_deg`).
    pub unit: String,
    /// The control's position at 0 % of travel, in `unit`.
    pub at_0_percent: f64,
    /// The control's position at 100 % of travel, in `unit`.
    pub at_100_percent: f64,
    /// What the column holds.
    pub logged: Logged,
}

/// What a control's column in its own unit holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Logged {
    /// The control's position (an affine map to % of travel).
    Position,
    /// Its change from trim (a scale).
    ChangeFromTrim,
}

impl Travel {
    /// `(factor, offset)`: % of travel = factor x logged + offset.
    pub fn to_percent(&self) -> (f64, f64) {
        let factor = 100.0 / (self.at_100_percent - self.at_0_percent);
        match self.logged {
            Logged::Position => (factor, -factor * self.at_0_percent),
            Logged::ChangeFromTrim => (factor, 0.0),
        }
    }

    /// A position in `unit` as % of travel (a trim value is a position, whatever the columns
    /// hold).
    pub fn position_percent(&self, x: f64) -> f64 {
        100.0 * (x - self.at_0_percent) / (self.at_100_percent - self.at_0_percent)
    }

    /// What is wrong with it, if anything: its ends must be finite and differ, and its unit a
    /// name's suffix (letters and digits) that is not `percent`.
    pub fn problem(&self) -> Option<String> {
        if !(self.at_0_percent.is_finite() && self.at_100_percent.is_finite()) {
            return Some(format!(
                "the travel's ends must be finite numbers, got {} and {}",
                self.at_0_percent, self.at_100_percent
            ));
        }
        if self.at_0_percent == self.at_100_percent {
            return Some(format!(
                "`at_0_percent` and `at_100_percent` are both {}: a travel has two ends",
                self.at_0_percent
            ));
        }
        let plain = !self.unit.is_empty()
            && self
                .unit
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit());
        if !plain || self.unit == "percent" {
            return Some(format!(
                "`unit: {}`: the unit the column is logged in, as its name's suffix (`deg` for \
                 `eta_s_deg`, `mm`, `in`), lower-case letters and digits, not `percent`",
                self.unit
            ));
        }
        None
    }
}

/// How a column in one unit becomes the channel in the unit cierva asks for: the asked
/// suffix, the written suffix, the factor (asked = factor x written) and the conversion in
/// words. Exact by definition: 1 kn = 1852/3600 m/s, 1 ft = 0.3048 m (international foot),
/// 1 mph = 0.44704 m/s, 1 lb = 0.45359237 kg (international pound).
pub const CONVERSIONS: &[(&str, &str, f64, &str)] = &[
    (
        "_rad_s",
        "_deg_s",
        std::f64::consts::PI / 180.0,
        "deg/s to rad/s",
    ),
    (
        "_rad_s",
        "_rpm",
        2.0 * std::f64::consts::PI / 60.0,
        "rpm to rad/s",
    ),
    ("_rad", "_deg", std::f64::consts::PI / 180.0, "deg to rad"),
    // A time history's responses are in degrees and rpm (`crate::run::replay::SIGNALS`).
    (
        "_deg_s",
        "_rad_s",
        180.0 / std::f64::consts::PI,
        "rad/s to deg/s",
    ),
    ("_deg", "_rad", 180.0 / std::f64::consts::PI, "rad to deg"),
    (
        "_rpm",
        "_rad_s",
        60.0 / (2.0 * std::f64::consts::PI),
        "rad/s to rpm",
    ),
    ("_m_s", "_kn", 1852.0 / 3600.0, "kn to m/s"),
    ("_m_s", "_mph", 0.44704, "mph to m/s"),
    ("_m_s", "_ft_s", 0.3048, "ft/s to m/s"),
    ("_m_s", "_km_h", 1.0 / 3.6, "km/h to m/s"),
    ("_m", "_ft", 0.3048, "ft to m"),
    // A trim point's airspeed is in mph and its density altitude in ft, as a case's condition.
    ("_mph", "_kn", 1852.0 / 1609.344, "kn to mph"),
    ("_mph", "_m_s", 1.0 / 0.44704, "m/s to mph"),
    ("_ft", "_m", 1.0 / 0.3048, "m to ft"),
    ("_kg", "_lb", KG_PER_LB, "lb to kg"),
    ("_s", "_ms", 1e-3, "ms to s"),
];

/// The international pound, kg (exact by definition).
pub const KG_PER_LB: f64 = 0.45359237;

/// Units a mapped name may end in: those of [`CONVERSIONS`], and the ones cierva reads as
/// they are (% of a control's travel, newtons, newton-metres, hertz).
pub fn known_units() -> Vec<&'static str> {
    let mut u: Vec<&'static str> = CONVERSIONS.iter().flat_map(|c| [c.0, c.1]).collect();
    u.extend(["_percent", "_n", "_n_m", "_hz"]);
    u.sort_unstable();
    u.dedup();
    u
}

/// How a record's columns become its channels.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Plan {
    /// Each column's channel name (as mapped, then as converted).
    pub names: Vec<String>,
    /// Each column's factor to the asked unit (`None`: as written).
    pub factors: Vec<Option<f64>>,
    /// Each column's offset after its factor (a control's position through its travel; 0
    /// otherwise): asked = factor x written + offset.
    pub offsets: Vec<f64>,
    /// What was mapped and converted, in words (`PITCH as theta_deg, deg to rad: theta_rad`).
    pub notes: Vec<String>,
}

/// The plan for a header (names as written, in today's spelling), the sidecar's map, its
/// controls' travel and the channels asked for (`needed`, then those used where present). An
/// error is the sidecar's field and what is wrong: a map key that is no column, a name two
/// columns would take, a unit cierva does not know.
pub fn plan(
    header: &[String],
    map: &BTreeMap<String, String>,
    travel: &BTreeMap<String, Travel>,
    needed: &[&str],
) -> Result<Plan, (String, String)> {
    let known = known_units();
    let mut names = header.to_vec();
    let mut notes = Vec::new();
    for (column, name) in map {
        let field = format!("channels.{column}");
        let Some(k) = header.iter().position(|h| h == column) else {
            let hint = crate::inputs::yaml::nearest(column, header)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err((field, format!("the record has no column `{column}`{hint}")));
        };
        // A control in its own unit is named by its travel (`eta_p_mm` with `travel: {eta_p:
        // {unit: mm, ..}}`), whatever the unit.
        let by_travel = travel
            .iter()
            .any(|(control, t)| *name == format!("{control}_{}", t.unit));
        if !by_travel
            && !known
                .iter()
                .any(|u| name.ends_with(u) && name.len() > u.len())
        {
            return Err((
                field,
                format!(
                    "`{name}`: name the channel with its unit as a suffix, one of {} (or a \
                     control's own unit, given with its travel under `travel:`)",
                    known.join(", ")
                ),
            ));
        }
        if let Some(other) = header
            .iter()
            .position(|h| h == name)
            .filter(|&i| i != k && !map.contains_key(&header[i]))
        {
            return Err((
                field,
                format!(
                    "`{name}` is already column {} of the record: map one of them",
                    other + 1
                ),
            ));
        }
        if let Some((other, _)) = map.iter().find(|(c, n)| *n == name && *c != column) {
            return Err((
                field,
                format!("`{other}` is mapped to `{name}` too: one column a channel"),
            ));
        }
        names[k] = name.clone();
        notes.push(format!("column `{column}` read as `{name}`"));
    }
    let mut factors = vec![None; names.len()];
    let mut offsets = vec![0.0; names.len()];
    for need in needed {
        if names.iter().any(|n| n == need) {
            continue;
        }
        let through_travel = need.strip_suffix("_percent").and_then(|control| {
            let t = travel.get(control)?;
            let written = format!("{control}_{}", t.unit);
            let k = names.iter().position(|n| *n == written)?;
            Some((k, written, t))
        });
        if let Some((k, written, t)) = through_travel {
            let (factor, offset) = t.to_percent();
            let what = match t.logged {
                Logged::Position => "positions",
                Logged::ChangeFromTrim => "changes from trim",
            };
            notes.push(format!(
                "`{written}` converted to `{need}` through its travel ({} {u} at 0 %, {} {u} at \
                 100 %; {what})",
                t.at_0_percent,
                t.at_100_percent,
                u = t.unit
            ));
            names[k] = need.to_string();
            factors[k] = Some(factor);
            offsets[k] = offset;
            continue;
        }
        let found = CONVERSIONS.iter().find_map(|&(to, from, factor, words)| {
            let stem = need.strip_suffix(to)?;
            let written = format!("{stem}{from}");
            let k = names.iter().position(|n| *n == written)?;
            Some((k, written, factor, words))
        });
        if let Some((k, written, factor, words)) = found {
            notes.push(format!("`{written}` converted to `{need}` ({words})"));
            names[k] = need.to_string();
            factors[k] = Some(factor);
        }
    }
    Ok(Plan {
        names,
        factors,
        offsets,
        notes,
    })
}
