//! A suite: the directory cierva works on. A `cierva.toml` file marks it ([`MARKER`]) and says
//! where its cases, reports and corrections are; every path cierva reads or writes by default
//! is relative to it, none is in the build tree.
//!
//! The command line finds the suite from the working directory upward, or takes it from
//! `--suite DIR`. A case belongs to the suite whose marker is nearest above it
//! ([`Suite::containing`]): its known discrepancies' records are that suite's.
//!
//! ```toml
//! format_version = 1
//! [paths]                    # each optional, relative to the marker's folder
//! cases = "cases"            # the case files and the shared tolerance library
//! reports = "reports"        # the report; the scoreboard, discrepancy records, acceptance log
//! corrections = "corrections"  # retune's corrections (retuned/)
//! ```

pub mod case;
pub mod discrepancy;
pub mod outcome;
pub mod review;
pub mod scoreboard;
pub mod snapshots;
pub mod validation;

use crate::inputs::yaml::InputError;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The file that marks a suite's root.
pub const MARKER: &str = "cierva.toml";

/// The acceptance log's file name, in the reports folder beside what it accepts.
pub const ACCEPTANCES_FILE: &str = "acceptances.yaml";

/// The committed verdicts of the last whole-suite uncertainty run, in the reports folder
/// (`crate::uncertainty::summary`).
pub const UNCERTAINTY_SUMMARY_FILE: &str = "uncertainty-summary.yaml";

/// The marker's format version this cierva reads.
pub const FORMAT_VERSION: u32 = 1;

/// The marker a new suite gets (`cierva init`): every setting at its default, each explained.
pub const MARKER_TEMPLATE: &str = include_str!("../../templates/cierva.toml");

/// The example case a new suite gets: `cierva new-case`'s template, which validates anywhere.
pub const EXAMPLE_CASE: &str = include_str!("../../templates/case.yaml");

/// The shared tolerance library a new suite gets: this repository's own.
pub const TOLERANCES: &str = include_str!("../../../cases/tolerances.yaml");

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MarkerSpec {
    format_version: u32,
    #[serde(default)]
    paths: PathsSpec,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct PathsSpec {
    cases: Option<PathBuf>,
    reports: Option<PathBuf>,
    corrections: Option<PathBuf>,
}

/// A suite: its root (the marker's folder) and its folders.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Suite {
    pub root: PathBuf,
    cases: PathBuf,
    reports: PathBuf,
    corrections: PathBuf,
}

impl Suite {
    /// The suite whose marker is in `dir` (`--suite DIR`): an error naming the folder when it
    /// has none.
    pub fn open(dir: &Path) -> Result<Suite, InputError> {
        let marker = dir.join(MARKER);
        if !marker.is_file() {
            return Err(InputError::file(
                dir,
                format!(
                    "not a cierva suite: no {MARKER} here (make one with `cierva init {}`)",
                    dir.display()
                ),
            ));
        }
        Self::load(&marker)
    }

    /// The suite of the working directory `start`: the nearest marker in it or a folder above.
    pub fn find(start: &Path) -> Result<Suite, InputError> {
        match Self::containing(start)? {
            Some(s) => Ok(s),
            None => Err(InputError::file(
                start,
                format!(
                    "not in a cierva suite: no {MARKER} here or in any folder above (make one with `cierva init .`, or name one with --suite DIR)"
                ),
            )),
        }
    }

    /// The suite that holds `path` (a file or folder): the nearest marker in its folder or a
    /// folder above; `None` when there is none. A malformed marker is an error.
    pub fn containing(path: &Path) -> Result<Option<Suite>, InputError> {
        let absolute = if path.is_absolute() {
            path.to_path_buf()
        } else {
            std::env::current_dir()
                .map_err(|e| InputError::file(path, format!("the working directory: {e}")))?
                .join(path)
        };
        let start = if absolute.is_dir() {
            absolute.as_path()
        } else {
            absolute.parent().unwrap_or(&absolute)
        };
        for dir in start.ancestors() {
            let marker = dir.join(MARKER);
            if marker.is_file() {
                return Self::load(&marker).map(Some);
            }
        }
        Ok(None)
    }

    /// Reads a marker file.
    fn load(marker: &Path) -> Result<Suite, InputError> {
        let src = std::fs::read_to_string(marker)
            .map_err(|e| InputError::file(marker, format!("cannot read: {e}")))?;
        let spec: MarkerSpec = toml::from_str(&src).map_err(|e| {
            let (line, column) = e.span().map_or((None, None), |s| {
                let before = &src[..s.start.min(src.len())];
                let line = before.matches('\n').count() + 1;
                let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
                (Some(line), Some(column))
            });
            InputError {
                path: marker.to_path_buf(),
                line,
                column,
                field: None,
                message: e.message().to_string(),
            }
        })?;
        if spec.format_version != FORMAT_VERSION {
            // At the key's line and column (TOML: `format_version = 2`, at the line's start).
            let line = src
                .lines()
                .position(|l| l.trim_start().starts_with("format_version"))
                .map(|k| k + 1);
            let column = line.and_then(|k| {
                let l = src.lines().nth(k - 1)?;
                Some(l.len() - l.trim_start().len() + 1)
            });
            return Err(InputError {
                line,
                column,
                ..InputError::file(
                    marker,
                    format!(
                        "format_version {}: this cierva reads format_version {FORMAT_VERSION} \
                         (the suite was written for another version of cierva)",
                        spec.format_version
                    ),
                )
            });
        }
        // Canonical, so that the suite of a case found from its path and the suite named on
        // the command line compare equal however each was spelt.
        let root = marker
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        let root = std::fs::canonicalize(&root).unwrap_or(root);
        let folder = |given: Option<PathBuf>, default: &str| {
            root.join(given.unwrap_or_else(|| PathBuf::from(default)))
        };
        Ok(Suite {
            cases: folder(spec.paths.cases, "cases"),
            reports: folder(spec.paths.reports, "reports"),
            corrections: folder(spec.paths.corrections, "corrections"),
            root,
        })
    }

    /// The case files' folder.
    pub fn cases(&self) -> &Path {
        &self.cases
    }

    /// The report's folder, which also holds the files committed with the cases.
    pub fn reports(&self) -> &Path {
        &self.reports
    }

    /// The committed scores.
    pub fn scoreboard(&self) -> PathBuf {
        self.reports.join("scoreboard.yaml")
    }

    /// The verdicts of the last whole-suite uncertainty run (`cierva uncertainty
    /// --write-summary`), committed.
    pub fn uncertainty_summary(&self) -> PathBuf {
        self.reports.join(UNCERTAINTY_SUMMARY_FILE)
    }

    /// The known discrepancies' records, one file per case.
    pub fn discrepancies(&self) -> PathBuf {
        self.reports.join("discrepancies")
    }

    /// The acceptance log (`cierva review --accept`).
    pub fn acceptances(&self) -> PathBuf {
        self.reports.join(ACCEPTANCES_FILE)
    }

    /// Where `cierva retune` writes the corrections it fits.
    pub fn retuned(&self) -> PathBuf {
        self.corrections.join("retuned")
    }

    /// Where `cierva fit` writes the corrections it fits.
    pub fn fitted(&self) -> PathBuf {
        self.corrections.join("fitted")
    }

    /// Where `cierva fit` writes its reports.
    pub fn fit_reports(&self) -> PathBuf {
        self.reports.join("fits")
    }

    /// Where `cierva retune` writes its reports.
    pub fn retune_reports(&self) -> PathBuf {
        self.reports.join("retune")
    }
}

/// Makes `dir` a suite (`cierva init`): its marker, the shared tolerance library and one
/// example case that validates, in folders made as needed. Returns the files written. Writes
/// over no file. (A suite inside another is allowed: the nearest marker wins.)
pub fn init(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let files = [
        (dir.join(MARKER), MARKER_TEMPLATE.to_string()),
        (dir.join("cases/tolerances.yaml"), TOLERANCES.to_string()),
        (
            dir.join("cases/example.yaml"),
            EXAMPLE_CASE.replace("CASE_ID", "example"),
        ),
    ];
    if let Some((p, _)) = files.iter().find(|(p, _)| p.exists()) {
        return Err(format!("{} exists; nothing written", p.display()));
    }
    for (path, text) in &files {
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("cannot make {}: {e}", parent.display()))?;
        }
        std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(files.into_iter().map(|(p, _)| p).collect())
}
