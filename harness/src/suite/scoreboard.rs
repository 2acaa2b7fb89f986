//! The validation scoreboard: a few numbers per outside data set that say how well the model
//! does against it (an RMS relative error, how many checks are inside their bounds), committed in
//! `reports/scoreboard.yaml`, so that a change that makes the model worse against a data set
//! fails `cargo test` even when every check of it is a known discrepancy.
//!
//! Scores are declared in the case that holds the data set (`scores:`), computed from that
//! case's results, and accepted with `cierva review --accept` (with the known discrepancies).
//!
//! # Metrics
//! Over the case's checks that compute the score's `quantity` (every check for `inside` and
//! `unsolved` without one), or those of them its `checks` list names, with `ref` the expected value or the middle of the allowed range and
//! `h` the tolerance's half-width:
//! - `rms_relative_error`: `sqrt(mean(((value - ref) / ref)^2))`, lower is better;
//! - `rms_error`: `sqrt(mean((value - ref)^2))`, in the quantity's unit (an angle's RMS error
//!   in degrees), lower is better;
//! - `rms_error_in_half_widths`: `sqrt(mean(((value - ref) / h)^2))`, lower is better;
//! - `max_error_in_half_widths`: `max |value - ref| / h`, lower is better (for a 95 % bound,
//!   1.96 times this is the error in standard errors);
//! - `peak_relative_error`: `|max(value) - max(ref)| / max(ref)`, the error of the peak (of
//!   L/D over a tunnel sweep, say) wherever each falls, lower is better;
//! - `peak_tip_speed_ratio_offset`: `|mu(argmax value) - mu(argmax ref)|`, how far apart in
//!   tip-speed ratio the two peaks are, each at its check's stated `tip_speed_ratio` (the
//!   tunnel's), lower is better;
//! - `inside`: how many are inside their tolerance, higher is better;
//! - `unsolved`: how many checks found no equilibrium or could not be evaluated, lower is
//!   better. Checks without a value are left out of the other metrics and counted here.

use crate::inputs::yaml::{self, InputError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The metrics a score can use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Metric {
    RmsRelativeError,
    RmsError,
    RmsErrorInHalfWidths,
    MaxErrorInHalfWidths,
    PeakRelativeError,
    PeakTipSpeedRatioOffset,
    Inside,
    Unsolved,
}

/// Which way is better.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Better {
    Lower,
    Higher,
}

impl Metric {
    /// Which way the metric is better.
    pub fn better(self) -> Better {
        match self {
            Self::Inside => Better::Higher,
            _ => Better::Lower,
        }
    }

    /// The metric as written in case files.
    pub fn name(self) -> &'static str {
        match self {
            Self::RmsRelativeError => "rms_relative_error",
            Self::RmsError => "rms_error",
            Self::RmsErrorInHalfWidths => "rms_error_in_half_widths",
            Self::MaxErrorInHalfWidths => "max_error_in_half_widths",
            Self::PeakRelativeError => "peak_relative_error",
            Self::PeakTipSpeedRatioOffset => "peak_tip_speed_ratio_offset",
            Self::Inside => "inside",
            Self::Unsolved => "unsolved",
        }
    }

    /// Whether the metric is about one quantity (the others may count whole checks).
    pub fn needs_quantity(self) -> bool {
        !matches!(self, Self::Inside | Self::Unsolved)
    }
}

/// A score as declared in a case file.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ScoreSpec {
    pub id: String,
    pub metric: Metric,
    /// The quantity scored (`rpm`, `lift_coefficient`, `value`); optional for `inside` and
    /// `unsolved`, which then count whole checks.
    #[serde(default)]
    pub quantity: Option<String>,
    /// Changes smaller than this are noise (the model's convergence), not a change of score.
    pub noise_floor: f64,
    /// What the score measures, and why that noise floor.
    pub reason: String,
    /// The checks it is computed over, by id (absent: every check of the case): a regime of
    /// a data set, say.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checks: Option<Vec<String>>,
}

/// A score computed from a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Score {
    pub case: String,
    pub id: String,
    pub metric: Metric,
    pub quantity: Option<String>,
    pub value: f64,
    /// How many values (or checks) it was computed from.
    pub count: usize,
    pub noise_floor: f64,
    pub reason: String,
}

/// A committed score.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Committed {
    pub value: f64,
    pub better: Better,
    pub noise_floor: f64,
}

/// The committed scoreboard: case -> score id -> score.
#[derive(Debug, Clone, PartialEq, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Board {
    #[serde(default)]
    pub scores: BTreeMap<String, BTreeMap<String, Committed>>,
}

/// How a score compares with its committed value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Change {
    /// Within the noise floor.
    Same,
    Better,
    Worse,
    /// Nothing committed for it.
    New,
}

impl Change {
    pub fn label(self) -> &'static str {
        match self {
            Self::Same => "same",
            Self::Better => "better",
            Self::Worse => "WORSE",
            Self::New => "new",
        }
    }
}

/// Compares a score with the committed one. A score that is not a number now, but was one, is
/// worse.
pub fn change(score: &Score, committed: Option<&Committed>) -> Change {
    let Some(c) = committed else {
        return Change::New;
    };
    let (now, then) = (score.value, c.value);
    match (now.is_nan(), then.is_nan()) {
        (true, true) => return Change::Same,
        (true, false) => return Change::Worse,
        (false, true) => return Change::Better,
        _ => {}
    }
    let d = match c.better {
        Better::Lower => then - now,
        Better::Higher => now - then,
    };
    if d.abs() <= c.noise_floor {
        Change::Same
    } else if d > 0.0 {
        Change::Better
    } else {
        Change::Worse
    }
}

/// Loads a suite's committed scoreboard (empty when there is none).
pub fn load(suite: &crate::suite::Suite) -> Result<Board, InputError> {
    load_file(&suite.scoreboard())
}

/// Loads a scoreboard file (empty when it does not exist).
pub fn load_file(path: &Path) -> Result<Board, InputError> {
    if !path.exists() {
        return Ok(Board::default());
    }
    let src = yaml::read(path)?;
    yaml::parse(path, &src)
}

/// Parses a scoreboard from text (an older version from git, say).
pub fn parse(text: &str) -> Option<Board> {
    serde_yaml::from_str(text).ok()
}

/// The board with these cases' scores replaced by these: a score a reviewed case no longer
/// declares is dropped; cases not reviewed keep theirs.
pub fn with(board: &Board, cases: &[&str], scores: &[Score]) -> Board {
    let mut b = board.clone();
    for case in cases {
        b.scores.remove(*case);
    }
    for s in scores {
        b.scores.entry(s.case.clone()).or_default().insert(
            s.id.clone(),
            Committed {
                value: s.value,
                better: s.metric.better(),
                noise_floor: s.noise_floor,
            },
        );
    }
    b
}

/// Writes a suite's scoreboard; returns whether the file changed.
pub fn write(suite: &crate::suite::Suite, board: &Board) -> std::io::Result<bool> {
    yaml::write_if_changed(&suite.scoreboard(), &render(board))
}

/// The scoreboard file's text: one flow map per score.
pub fn render(board: &Board) -> String {
    use std::fmt::Write as _;
    let mut o = String::from(
        "# Written by `cierva review --accept`: each data set's scores (see harness/src/suite/scoreboard.rs\n\
         # and the `scores` of its case). `cargo test` fails when a score gets worse than this by\n\
         # more than its noise floor. Do not edit by hand.\nscores:\n",
    );
    for (case, scores) in &board.scores {
        let _ = writeln!(o, "  {case}:");
        for (id, c) in scores {
            let better = match c.better {
                Better::Lower => "lower",
                Better::Higher => "higher",
            };
            let _ = writeln!(
                o,
                "    {id}: {{value: {}, better: {better}, noise_floor: {:e}}}",
                if c.value.is_nan() {
                    ".nan".to_string()
                } else {
                    format!("{:.7e}", c.value)
                },
                c.noise_floor
            );
        }
    }
    o
}

/// A committed version of the scoreboard: date, short commit, board.
pub type Version = (String, String, Board);

/// One score's values over the committed versions of the scoreboard, oldest first: `(date,
/// short commit, value)`. Empty when git or the history is not there.
pub fn history(
    case: &str,
    id: &str,
    versions: &[(String, String, Board)],
) -> Vec<(String, String, f64)> {
    versions
        .iter()
        .filter_map(|(date, commit, b)| {
            b.scores
                .get(case)
                .and_then(|s| s.get(id))
                .map(|c| (date.clone(), commit.clone(), c.value))
        })
        .collect()
}

/// The committed versions of a suite's scoreboard from git, oldest first: `(date, short commit,
/// board)`. Empty without git or outside a repository.
pub fn versions(suite: &crate::suite::Suite) -> Vec<Version> {
    // Git runs in the scoreboard's folder, which may lie anywhere in a repository: `./` makes
    // `git show`'s path relative to it.
    let file = suite.scoreboard();
    let (Some(dir), Some(name)) = (file.parent(), file.file_name()) else {
        return vec![];
    };
    let name = name.to_string_lossy();
    let run = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("-C")
            .arg(dir)
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
    };
    let Some(log) = run(&["log", "--reverse", "--format=%h %cs", "--", &name]) else {
        return vec![];
    };
    log.lines()
        .filter_map(|l| {
            let (commit, date) = l.split_once(' ')?;
            let text = run(&["show", &format!("{commit}:./{name}")])?;
            Some((date.to_string(), commit.to_string(), parse(&text)?))
        })
        .collect()
}
