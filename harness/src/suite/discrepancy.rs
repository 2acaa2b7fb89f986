//! Known discrepancies as numbers.
//!
//! A check marked `expected_failure` says *why* the model disagrees with its reference. What
//! the model gives today is recorded here, per quantity, as a value and a band: the check then
//! stays an expected failure only while the model stays inside every band. A model that moves,
//! better or worse, fails the check as "discrepancy moved" with both numbers, so a regression
//! cannot hide behind a known discrepancy.
//!
//! The records live in `reports/discrepancies/<case-id>.yaml`, beside the insta snapshots, and
//! are written by `cierva review --accept`, never by hand (as `cargo insta review` writes
//! snapshots).
//!
//! # The band
//! Half-width `max(1e-4 |value|, 1e-2 h, 1e-12)`, where `h` is the half-width of the check's
//! own tolerance (so a move of a hundredth of what the reference can resolve is noticed) and
//! `1e-4 |value|` covers the model's convergence (trims to 1e-7 scaled residuals, finite
//! differences in the linearisation, warm and cold starts).

use crate::inputs::yaml::{self, InputError};
use cierva_model::analysis::bcar::Verdict;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Relative half-width of a recorded band.
pub const BAND_RELATIVE: f64 = 1e-4;
/// Half-width of a recorded band as a fraction of the check's tolerance half-width.
pub const BAND_OF_TOLERANCE: f64 = 1e-2;

/// The records of one case, as written in its file.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseRecord {
    pub case: String,
    #[serde(default)]
    pub checks: BTreeMap<String, Recorded>,
}

/// What the model gave for one expected failure.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recorded {
    /// Quantity -> the model's value and its band.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub quantities: BTreeMap<String, RecordedBand>,
    /// The computed BCAR verdict, for `bcar` checks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verdict: Option<Verdict>,
    /// The model found no equilibrium (see `outcome::Finding`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub no_equilibrium: bool,
    /// The check's numbers beyond its expectations (see `CheckResult::fingerprint`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub fingerprint: BTreeMap<String, RecordedBand>,
}

/// A recorded value and the band the model must stay in.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordedBand {
    pub value: f64,
    pub lower: f64,
    pub upper: f64,
}

impl RecordedBand {
    /// The band around `value` for a tolerance of half-width `tolerance_half_width` (0 or
    /// non-finite when the tolerance has none).
    pub fn around(value: f64, tolerance_half_width: f64) -> RecordedBand {
        let h = if tolerance_half_width.is_finite() {
            tolerance_half_width.abs()
        } else {
            0.0
        };
        let half = (BAND_RELATIVE * value.abs())
            .max(BAND_OF_TOLERANCE * h)
            .max(1e-12);
        RecordedBand {
            value,
            lower: value - half,
            upper: value + half,
        }
    }

    /// Whether `v` lies in the band (never for a non-finite `v`).
    pub fn holds(&self, v: f64) -> bool {
        v.is_finite() && self.lower <= v && v <= self.upper
    }
}

/// The file holding a case's records in the folder of records `dir`
/// ([`crate::suite::Suite::discrepancies`]).
pub fn path_for(dir: &Path, case_id: &str) -> PathBuf {
    dir.join(format!("{case_id}.yaml"))
}

/// Loads a case's records from the folder of records `dir` (`None` when it has no file).
pub fn load(dir: &Path, case_id: &str) -> Result<Option<CaseRecord>, InputError> {
    let path = path_for(dir, case_id);
    if !path.exists() {
        return Ok(None);
    }
    load_file(&path).map(Some)
}

/// Loads a record file.
pub fn load_file(path: &Path) -> Result<CaseRecord, InputError> {
    let src = yaml::read(path)?;
    let r: CaseRecord = yaml::parse(path, &src)?;
    for (id, rec) in &r.checks {
        let bands = rec.quantities.iter().chain(rec.fingerprint.iter());
        for (q, b) in bands {
            if !(b.value.is_finite() && b.lower <= b.value && b.value <= b.upper) {
                return Err(InputError::field(
                    path,
                    &src,
                    &format!("checks.{id}"),
                    format!("`{q}`: a recorded band needs lower <= value <= upper, all finite"),
                ));
            }
        }
    }
    Ok(r)
}

/// Writes a case's records into the folder of records `dir` (or removes its file when it has
/// none). Returns whether the file changed.
pub fn write(dir: &Path, record: &CaseRecord) -> std::io::Result<bool> {
    let path = path_for(dir, &record.case);
    if record.checks.is_empty() {
        if path.exists() {
            std::fs::remove_file(&path)?;
            return Ok(true);
        }
        return Ok(false);
    }
    let body = render(record);
    let text = format!(
        "# Written by `cierva review --accept`: what the model gives today for each check of\n\
         # `{}` that is expected to fail. Do not edit by hand. A check whose model leaves a band\n\
         # fails as \"discrepancy moved\". Band half-width: max({BAND_RELATIVE:e} |value|, \
         {BAND_OF_TOLERANCE:e} x the tolerance's half-width).\n{body}",
        record.case
    );
    yaml::write_if_changed(&path, &text)
}

/// A record file's body: one flow map per band, numbers to 8 significant digits (far finer than
/// any band).
pub fn render(record: &CaseRecord) -> String {
    use std::fmt::Write as _;
    let band = |b: &RecordedBand| {
        format!(
            "{{value: {:.7e}, lower: {:.7e}, upper: {:.7e}}}",
            b.value, b.lower, b.upper
        )
    };
    let mut o = format!("case: {}\nchecks:\n", record.case);
    for (id, r) in &record.checks {
        let _ = write!(o, "  {id}:");
        o += if r.quantities.is_empty()
            && r.verdict.is_none()
            && !r.no_equilibrium
            && r.fingerprint.is_empty()
        {
            " {}\n"
        } else {
            "\n"
        };
        if !r.quantities.is_empty() {
            o += "    quantities:\n";
            for (q, b) in &r.quantities {
                let _ = writeln!(o, "      {q}: {}", band(b));
            }
        }
        if let Some(v) = r.verdict {
            let name = match v {
                Verdict::Complies => "complies",
                Verdict::DoesNotComply => "does_not_comply",
            };
            let _ = writeln!(o, "    verdict: {name}");
        }
        if r.no_equilibrium {
            o += "    no_equilibrium: true\n";
        }

        if !r.fingerprint.is_empty() {
            o += "    fingerprint:\n";
            for (q, b) in &r.fingerprint {
                let _ = writeln!(o, "      {q}: {}", band(b));
            }
        }
    }
    o
}
