//! A file's plausible ranges of its estimated parameters (`ranges:` in aircraft and rotor
//! files): as written, checked, and the shape of each one's distribution. `cierva sensitivity`
//! weighs a needed change against a range; `cierva uncertainty` propagates the distribution.

use crate::inputs::yaml::InputError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A parameter's plausible range as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangeSpec {
    pub lower: f64,
    pub upper: f64,
    pub source: String,
    /// How likely the values in the range are (`cierva uncertainty` samples it): uniform
    /// unless the source gives a central value and a spread.
    #[serde(default)]
    pub distribution: Shape,
    /// The standard deviation of a `normal` distribution, in the parameter's unit.
    #[serde(default)]
    pub sigma: Option<f64>,
    /// The estimating method whose error this range shares with every other range of the
    /// file that names it (one contraction model for two of the fin's inputs, one lift-slope
    /// equation for the fin and the tailplane): `cierva uncertainty` draws that method's error
    /// once, each such parameter at the same quantile of its own distribution.
    #[serde(default)]
    pub shares: Option<String>,
    /// The cases (`case-id`) or checks (`case-id/check-id`) whose reference data the range was
    /// taken from (the flat plate that closes a table's drag deficit, a band read off the
    /// flight it is judged against): a study judging one of them with this range is circular,
    /// and its verdict is reported apart, never counted as validation evidence.
    #[serde(default)]
    pub taken_from: Vec<String>,
}

/// The shape of a parameter's distribution over its plausible range. The file's value is the
/// centre (the mode of a triangle, the mean of a normal), and the range bounds every shape (a
/// normal is truncated to it).
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// Every value in the range equally likely: what a range without a central value says.
    #[default]
    Uniform,
    /// Most likely at the file's value, falling linearly to zero at the range's ends.
    Triangular,
    /// Normal about the file's value with the range's `sigma`, truncated to the range.
    Normal,
}

/// A parameter's plausible range, checked: `lower <= value <= upper`, with a source.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Range {
    pub lower: f64,
    pub upper: f64,
    pub source: String,
    /// Its distribution's shape (the file's value is its centre).
    pub distribution: Shape,
    /// A normal distribution's standard deviation (`None` for the other shapes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// The estimating method whose error it shares with the other ranges that name it
    /// ([`RangeSpec::shares`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shares: Option<String>,
    /// The cases or checks whose data it was taken from ([`RangeSpec::taken_from`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub taken_from: Vec<String>,
}

/// A `taken_from` entry checked: a case id, or a case id and a check id as `case/check`
/// (ids are letters, digits, `-`, `_` and `.`); what is wrong with it otherwise.
pub fn check_taken_from(entry: &str) -> Result<(), String> {
    let id = |s: &str| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
    };
    let ok = match entry.split_once('/') {
        None => id(entry),
        Some((case, check)) => id(case) && id(check),
    };
    match ok {
        true => Ok(()),
        false => Err(format!(
            "`{entry}` is not a case id or `case-id/check-id` (the case or check whose data the range was taken from)"
        )),
    }
}

/// Ranges of a file's parameters, checked: each names one of `names` that `value_of` reads
/// (`what` is the file in words), holds the file's value, has a source and a well-formed
/// distribution. Shared by aircraft and rotor files.
pub(crate) fn checked(
    spec: &BTreeMap<String, RangeSpec>,
    value_of: &dyn Fn(&str) -> Option<f64>,
    names: &[String],
    what: &str,
    err: &dyn Fn(&str, String) -> InputError,
) -> Result<BTreeMap<String, Range>, InputError> {
    let mut out = BTreeMap::new();
    for (name, r) in spec {
        let field = format!("ranges.{name}");
        let Some(value) = value_of(name) else {
            let hint = crate::inputs::yaml::nearest(name, names)
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Err(err(
                &field,
                format!("`{name}` is not a parameter of {what}{hint}"),
            ));
        };
        if !(r.lower.is_finite() && r.upper.is_finite() && r.lower < r.upper) {
            return Err(err(&field, "give finite `lower` < `upper`".into()));
        }
        if !(r.lower..=r.upper).contains(&value) {
            return Err(err(
                &field,
                format!(
                    "the file's value {value} is outside its own plausible range [{}, {}]",
                    r.lower, r.upper
                ),
            ));
        }
        if r.source.trim().is_empty() {
            return Err(err(
                &format!("{field}.source"),
                "say where the range comes from (or \"estimated: why\")".into(),
            ));
        }
        let sigma = match (r.distribution, r.sigma) {
            (Shape::Normal, Some(s)) if s.is_finite() && s > 0.0 => Some(s),
            (Shape::Normal, Some(s)) => {
                return Err(err(
                    &format!("{field}.sigma"),
                    format!("a normal distribution's sigma must be finite and > 0, got {s}"),
                ));
            }
            (Shape::Normal, None) => {
                return Err(err(
                    &format!("{field}.sigma"),
                    "a normal distribution needs `sigma` (its standard deviation, in the parameter's unit)".into(),
                ));
            }
            (_, Some(_)) => {
                return Err(err(
                    &format!("{field}.sigma"),
                    "only a `normal` distribution takes `sigma`".into(),
                ));
            }
            (_, None) => None,
        };
        for (k, t) in r.taken_from.iter().enumerate() {
            check_taken_from(t).map_err(|m| err(&format!("{field}.taken_from[{k}]"), m))?;
        }
        out.insert(
            name.clone(),
            Range {
                lower: r.lower,
                upper: r.upper,
                source: r.source.clone(),
                distribution: r.distribution,
                sigma,
                shares: r.shares.clone(),
                taken_from: r.taken_from.clone(),
            },
        );
    }
    for (name, r) in &out {
        if let Some(method) = &r.shares {
            let with = out
                .values()
                .filter(|o| o.shares.as_ref() == Some(method))
                .count();
            if method.trim().is_empty() || with < 2 {
                return Err(err(
                    &format!("ranges.{name}.shares"),
                    format!(
                        "`{method}`: a method's error is shared by two ranges or more; no other range of {what} names it"
                    ),
                ));
            }
        }
    }
    Ok(out)
}
