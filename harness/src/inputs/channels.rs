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

use std::collections::BTreeMap;

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
    /// What was mapped and converted, in words (`PITCH as theta_deg, deg to rad: theta_rad`).
    pub notes: Vec<String>,
}

/// The plan for a header (names as written, in today's spelling), the sidecar's map and the
/// channels asked for (`needed`, then those used where present). An error is the sidecar's field and what is wrong: a map key that is no
/// column, a name two columns would take, a unit cierva does not know.
pub fn plan(
    header: &[String],
    map: &BTreeMap<String, String>,
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
        if !known
            .iter()
            .any(|u| name.ends_with(u) && name.len() > u.len())
        {
            return Err((
                field,
                format!(
                    "`{name}`: name the channel with its unit as a suffix, one of {}",
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
    for need in needed {
        if names.iter().any(|n| n == need) {
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
        notes,
    })
}
