//! A command as a subject: the protocol `cierva-external/1` (`docs/external-models.md`).
//!
//! cierva runs the command once per request, in the case file's folder, with the path of a
//! request file (JSON) as its last argument. The request says what to compute (`trim`,
//! `linear_model` or `time_history`), at which condition and loading, where the controls are
//! (a time history: a CSV of changes from trim, the columns `cierva simulate` reads) and where
//! to write the response (JSON; a time history as CSV). Every failure is an error that names
//! the command: not found, a non-zero exit (with the last lines of its stderr), a timeout (the
//! process is killed), a response that is missing or does not parse (with where), a quantity
//! that is not cierva's.

use super::{ControlChanges, FlightModel, Quantities, trim_name};
use crate::run::replay::Replayed;
use crate::{Loading, TrimRequest};
use cierva_model::LinearModel;
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The protocol's name and version, in every request and response.
pub const PROTOCOL: &str = "cierva-external/1";

/// The last lines of a failing command's stderr shown in its error.
const STDERR_LINES: usize = 20;

/// How often a running command is polled for its exit (it is killed at its timeout).
const POLL: Duration = Duration::from_millis(5);

/// What a request asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Compute {
    Trim,
    LinearModel,
    TimeHistory,
}

impl Compute {
    pub fn name(self) -> &'static str {
        match self {
            Self::Trim => "trim",
            Self::LinearModel => "linear_model",
            Self::TimeHistory => "time_history",
        }
    }
}

/// An external command: the program and its arguments, the folder it runs in (the case
/// file's), and how long one request may take.
#[derive(Debug)]
pub struct ExternalCommand {
    pub command: Vec<String>,
    pub dir: PathBuf,
    pub timeout: Duration,
    /// Answers by request (the request's JSON without its paths): a case's checks at one
    /// condition share one run.
    answers: Mutex<HashMap<String, Result<Answer, String>>>,
}

#[derive(Debug, Clone)]
enum Answer {
    Trim(Quantities),
    Linear(LinearModel),
    History(Replayed),
}

impl ExternalCommand {
    pub fn new(command: Vec<String>, dir: PathBuf, timeout: Duration) -> Self {
        Self {
            command,
            dir,
            timeout,
            answers: Mutex::new(HashMap::new()),
        }
    }

    /// The command as written.
    pub fn written(&self) -> String {
        self.command.join(" ")
    }

    /// Runs one request (remembered: the same request is not run twice).
    fn ask(
        &self,
        compute: Compute,
        condition: TrimRequest,
        loading: Loading,
        controls: Option<&ControlChanges>,
    ) -> Result<Answer, String> {
        let key = format!("{}|{condition:?}|{loading:?}|{controls:?}", compute.name());
        if let Some(hit) = self.answers.lock().ok().and_then(|a| a.get(&key).cloned()) {
            return hit;
        }
        let answer = self.run(compute, condition, loading, controls);
        if let Ok(mut a) = self.answers.lock() {
            a.insert(key, answer.clone());
        }
        answer
    }

    fn run(
        &self,
        compute: Compute,
        condition: TrimRequest,
        loading: Loading,
        controls: Option<&ControlChanges>,
    ) -> Result<Answer, String> {
        let dir = scratch_dir().map_err(|e| format!("{}: {e}", self.describe()))?;
        let out = self.run_in(&dir, compute, condition, loading, controls);
        let _ = std::fs::remove_dir_all(&dir);
        out.map_err(|e| format!("{} ({} request): {e}", self.describe(), compute.name()))
    }

    fn run_in(
        &self,
        dir: &Path,
        compute: Compute,
        condition: TrimRequest,
        loading: Loading,
        controls: Option<&ControlChanges>,
    ) -> Result<Answer, String> {
        let response = dir.join(match compute {
            Compute::TimeHistory => "response.csv",
            _ => "response.json",
        });
        let mut request = serde_json::json!({
            "protocol": PROTOCOL,
            "compute": compute.name(),
            "condition": {
                "airspeed_mph": condition.airspeed_mph,
                "airspeed_m_s": condition.airspeed_mph * crate::MPH_TO_M_S,
                "airspeed_kn": condition.airspeed_mph / crate::MPH_PER_KN,
                "climb_m_s": condition.climb_m_s,
                "turn_rate_deg_s": condition.turn_rate_deg_s,
            },
            "loading": {
                "mass_kg": loading.mass_kg,
                "density_altitude_ft": loading.density_altitude_ft,
            },
            "response": response,
        });
        if let Some(c) = controls {
            let path = dir.join("controls.csv");
            std::fs::write(&path, controls_csv(c))
                .map_err(|e| format!("writing {}: {e}", path.display()))?;
            request["controls"] = serde_json::json!(path);
            request["sample_s"] = serde_json::json!(c.sample_s);
            request["samples"] = serde_json::json!(c.samples + 1);
        }
        let request_path = dir.join("request.json");
        let text = serde_json::to_string_pretty(&request).map_err(|e| e.to_string())?;
        std::fs::write(&request_path, text)
            .map_err(|e| format!("writing {}: {e}", request_path.display()))?;
        self.execute(dir, &request_path)?;
        let text = std::fs::read_to_string(&response).map_err(|e| {
            format!(
                "exited 0 but wrote no response at {} ({e})",
                response.display()
            )
        })?;
        match compute {
            Compute::Trim => parse_trim(&text).map(Answer::Trim),
            Compute::LinearModel => parse_linear(&text).map(Answer::Linear),
            Compute::TimeHistory => {
                super::files::parse_history(&text, Some(controls.map_or(0, |c| c.samples + 1)))
                    .map(Answer::History)
                    .map_err(|e| format!("(CSV): {e}"))
            }
        }
        .map_err(|e| format!("its response {e}"))
    }

    /// Runs the command with `request` as its last argument, in the case's folder; its stdout
    /// and stderr go to files in `dir`.
    fn execute(&self, dir: &Path, request: &Path) -> Result<(), String> {
        let Some((program, args)) = self.command.split_first() else {
            return Err("the command is empty".into());
        };
        // A program named by a path is relative to the case file; a bare name is found on PATH.
        let program = if program.contains('/') {
            self.dir.join(program)
        } else {
            PathBuf::from(program)
        };
        let stdout_path = dir.join("stdout.txt");
        let stderr_path = dir.join("stderr.txt");
        let file = |p: &Path| {
            std::fs::File::create(p).map_err(|e| format!("creating {}: {e}", p.display()))
        };
        let mut child = Command::new(&program)
            .args(args)
            .arg(request)
            .current_dir(&self.dir)
            .stdin(Stdio::null())
            .stdout(file(&stdout_path)?)
            .stderr(file(&stderr_path)?)
            .spawn()
            .map_err(|e| match e.kind() {
                std::io::ErrorKind::NotFound => format!(
                    "`{}` was not found (a bare name is looked up on PATH, a path is relative to \
                     the case file's folder {})",
                    program.display(),
                    self.dir.display()
                ),
                _ => format!("`{}` could not be started: {e}", program.display()),
            })?;
        let start = Instant::now();
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) if start.elapsed() >= self.timeout => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(format!(
                        "timed out after {} s (`timeout_s`) and was killed{}",
                        self.timeout.as_secs_f64(),
                        tail(&stderr_path)
                    ));
                }
                Ok(None) => std::thread::sleep(POLL),
                Err(e) => return Err(format!("waiting for it: {e}")),
            }
        };
        if !status.success() {
            let code = status.code().map_or_else(
                || "was killed by a signal".to_string(),
                |c| format!("exited {c}"),
            );
            return Err(format!("{code}{}", tail(&stderr_path)));
        }
        Ok(())
    }
}

/// The last lines of a command's stderr, as the end of an error message.
fn tail(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    if lines.is_empty() {
        return "; its stderr is empty".into();
    }
    let from = lines.len().saturating_sub(STDERR_LINES);
    format!(
        "; its stderr{}:\n{}",
        if from > 0 {
            format!(" (last {STDERR_LINES} lines)")
        } else {
            String::new()
        },
        lines[from..]
            .iter()
            .map(|l| format!("  | {l}"))
            .collect::<Vec<_>>()
            .join("\n")
    )
}

/// A fresh folder for one request's files.
fn scratch_dir() -> std::io::Result<PathBuf> {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let dir = std::env::temp_dir().join(format!(
        "cierva-external-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}

/// The controls as `cierva simulate` reads them: `time_s` and the four changes from trim.
fn controls_csv(c: &ControlChanges) -> String {
    let mut s = format!(
        "time_s,{}\n",
        crate::inputs::controls::CONTROL_COLUMNS.join(",")
    );
    for (k, t) in c.table.time_s.iter().enumerate() {
        s.push_str(&format!("{t}"));
        for col in &c.table.changes {
            s.push_str(&format!(",{}", col[k]));
        }
        s.push('\n');
    }
    s
}

/// A response's JSON, with its protocol checked. Errors say where (line and column).
fn parse_json<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, String> {
    #[derive(Deserialize)]
    struct Head {
        protocol: Option<String>,
    }
    let head: Head = serde_json::from_str(text).map_err(|e| format!("is not JSON: {e}"))?;
    match head.protocol.as_deref() {
        Some(PROTOCOL) => {}
        Some(p) => return Err(format!("says protocol `{p}`; cierva speaks `{PROTOCOL}`")),
        None => return Err(format!("has no `protocol` (`{PROTOCOL}`)")),
    }
    serde_json::from_str(text).map_err(|e| format!("does not parse: {e}"))
}

fn parse_trim(text: &str) -> Result<Quantities, String> {
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Response {
        #[allow(dead_code)]
        protocol: String,
        trim: BTreeMap<String, f64>,
    }
    let r: Response = parse_json(text)?;
    let mut out = Vec::new();
    for (name, v) in r.trim {
        let name = trim_name(&name).map_err(|e| format!("`trim`: {e}"))?;
        if !v.is_finite() {
            return Err(format!("`trim.{name}` is not finite"));
        }
        out.push((name, v));
    }
    Ok(out)
}

fn parse_linear(text: &str) -> Result<LinearModel, String> {
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Response {
        #[allow(dead_code)]
        protocol: String,
        linear_model: Linear,
    }
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Linear {
        states: Vec<String>,
        controls: Vec<String>,
        a: Vec<Vec<f64>>,
        b: Vec<Vec<f64>>,
    }
    use cierva_model::aircraft::linearise::{CONTROLS, STATES};
    let r: Response = parse_json(text)?;
    let m = r.linear_model;
    for (names, known, what) in [
        (&m.states, &STATES[..], "state"),
        (&m.controls, &CONTROLS[..], "control"),
    ] {
        if let Some(n) = names.iter().find(|n| !known.contains(&n.as_str())) {
            return Err(format!(
                "`linear_model`: `{n}` is not one of cierva's {what}s [{}]",
                known.join(", ")
            ));
        }
    }
    LinearModel::from_rows(m.states, m.controls, &m.a, &m.b)
        .map_err(|e| format!("`linear_model`: {e}"))
}

impl FlightModel for ExternalCommand {
    fn describe(&self) -> String {
        format!("the command `{}`", self.written())
    }

    fn trim(&self, condition: TrimRequest, loading: Loading) -> Result<Quantities, String> {
        match self.ask(Compute::Trim, condition, loading, None)? {
            Answer::Trim(q) => Ok(q),
            _ => Err("a trim request answered as another".into()),
        }
    }

    fn linear_model(
        &self,
        condition: TrimRequest,
        loading: Loading,
    ) -> Result<LinearModel, String> {
        match self.ask(Compute::LinearModel, condition, loading, None)? {
            Answer::Linear(m) => Ok(m),
            _ => Err("a linear-model request answered as another".into()),
        }
    }

    fn time_history(
        &self,
        condition: TrimRequest,
        loading: Loading,
        controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        match self.ask(Compute::TimeHistory, condition, loading, Some(controls))? {
            Answer::History(f) => Ok(f),
            _ => Err("a time-history request answered as another".into()),
        }
    }
}
