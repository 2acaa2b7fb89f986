//! A command as a subject: the protocol `cierva-external/1` (`docs/external-models.md`).
//!
//! cierva runs the command once per request, in the case file's folder, with the path of a
//! request file (JSON) as its last argument. The request says what to compute (`trim`,
//! `linear_model` or `time_history`), at which condition and loading, where the controls are
//! (a time history: a CSV of changes from trim, the columns `cierva simulate` reads) and where
//! to write the response (JSON; a time history as CSV). Every failure is an error that names
//! the command: not found, a non-zero exit (with the last lines of its stderr), a timeout (the
//! process is killed), a response that is missing, too large or does not parse (with where), a
//! quantity that is not cierva's, a number too small for a double.
//!
//! A misbehaving model costs bounded time and memory:
//! - on Unix the command leads a process group of its own, and at its timeout, at a response
//!   past its size limit, and when it exits, the whole group is killed: nothing it started
//!   lives on (on Windows, its process tree, by `taskkill /T`);
//! - its stderr is read as it comes through a pipe, and only its last [`STDERR_KEEP_BYTES`] are
//!   kept; an error shows its last [`STDERR_LINES`] lines, each cut to
//!   [`crate::inputs::yaml::EXCERPT_CHARS`] characters; its stdout is not read;
//! - its response's size is watched while it runs and refused past [`response_limit_bytes`];
//! - identical requests in one run are answered by one run of the command, however many checks
//!   ask at once.

use super::{ControlChanges, FlightModel, Quantities, trim_name};
use crate::inputs::condition::Loading;
use crate::inputs::condition::TrimRequest;
use crate::run::replay::Replayed;
use cierva_model::LinearModel;
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, OnceLock, PoisonError, mpsc};
use std::time::{Duration, Instant};

/// The protocol's first version's name, in every request and response of a model that speaks
/// it: trim, linear model and time history at a condition and loading.
pub const PROTOCOL: &str = "cierva-external/1";

/// The second version's name: `/1`, and a `describe` request (what the model computes, its
/// states and controls, and the parameters it declares), and `parameters` in every request.
pub const PROTOCOL_2: &str = "cierva-external/2";

/// A version of the protocol.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Protocol {
    #[default]
    V1,
    V2,
}

impl Protocol {
    /// Its name, as requests and responses carry it.
    pub fn name(self) -> &'static str {
        match self {
            Self::V1 => PROTOCOL,
            Self::V2 => PROTOCOL_2,
        }
    }

    /// The version a case names (`protocol:`), or the error that lists them.
    pub fn parse(name: &str) -> Result<Self, String> {
        match name {
            PROTOCOL => Ok(Self::V1),
            PROTOCOL_2 => Ok(Self::V2),
            other => Err(format!(
                "`{other}` is not a protocol cierva speaks: `{PROTOCOL}` or `{PROTOCOL_2}`"
            )),
        }
    }
}

/// The last lines of a failing command's stderr shown in its error.
pub const STDERR_LINES: usize = 20;

/// How often a running command is polled for its exit and its response's size (it is killed
/// at its timeout, or as soon as its response passes its limit).
const POLL: Duration = Duration::from_millis(5);

/// The end of a command's stderr kept for its error, bytes: [`STDERR_LINES`] lines of a
/// screen's width are 2 kB, and 64 KiB keeps them where lines are long. The rest is read and
/// dropped as it comes: a model that wrote one 50 MB line once took `validate` to 2.1 GB.
pub const STDERR_KEEP_BYTES: usize = 64 * 1024;

/// How long cierva waits, once the command has exited and its process group is killed, for
/// its stderr to close: a process that left the group (a new session) may still hold it, and
/// is not waited for.
const STDERR_GRACE: Duration = Duration::from_secs(1);

/// The largest response to a trim or linear-model request, bytes (1 MiB): a linear model with
/// cierva's 10 states and 4 controls, at 25 characters a number, is 4 kB.
pub const MAX_RESPONSE_BYTES: u64 = 1024 * 1024;

/// The most bytes a time-history response may take per row asked for, on top of
/// [`MAX_RESPONSE_BYTES`]: a row of `time_s` and the 10 responses at 25 characters a number is
/// under 300 B. A model that wrote 20 million rows where 501 were asked (440 MB) once took 32 s
/// and 2.9 GB before its row count was refused.
pub const MAX_HISTORY_ROW_BYTES: u64 = 4096;

/// The most bytes a frequency-response answer may take per frequency asked for, on top of
/// [`MAX_RESPONSE_BYTES`]: 20 states by 8 controls, real and imaginary parts at 25 characters
/// a number, are 8 kB.
pub const MAX_FREQUENCY_BYTES: u64 = 16 * 1024;

/// The largest response to a request for `compute` (`rows` rows for a time history, `rows`
/// frequencies for a frequency response), bytes.
pub fn response_limit_bytes(compute: Compute, rows: usize) -> u64 {
    match compute {
        Compute::TimeHistory => MAX_RESPONSE_BYTES + rows as u64 * MAX_HISTORY_ROW_BYTES,
        Compute::FrequencyResponse => MAX_RESPONSE_BYTES + rows as u64 * MAX_FREQUENCY_BYTES,
        _ => MAX_RESPONSE_BYTES,
    }
}

/// What a request carries beyond its condition, loading and parameters: a time history's
/// controls, or a frequency response's frequencies.
#[derive(Debug, Clone, Copy, Default)]
pub struct With<'a> {
    pub controls: Option<&'a ControlChanges>,
    pub frequencies_hz: Option<&'a [f64]>,
    /// An autorotation's tunnel condition (in place of a flight condition and loading).
    pub tunnel: Option<&'a crate::inputs::condition::TunnelSpec>,
}

impl With<'_> {
    /// The rows an answer has: a time history's samples, or a frequency response's
    /// frequencies (0 for another).
    pub fn rows(&self) -> usize {
        match (self.controls, self.frequencies_hz) {
            (Some(c), _) => c.samples + 1,
            (None, Some(f)) => f.len(),
            (None, None) => 0,
        }
    }
}

/// What a request asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Compute {
    Trim,
    LinearModel,
    TimeHistory,
    /// Every state's response to every control about the trim, at frequencies (protocol `/2`;
    /// a model that does not compute it is asked its linear model, and its responses follow
    /// from A and B).
    FrequencyResponse,
    /// A rotor's autorotation in a wind tunnel (protocol `/2`): its equilibrium's quantities,
    /// or no equilibrium.
    Autorotation,
    /// What the model is (protocol `/2`): asked once, before any other request.
    Describe,
}

impl Compute {
    /// What a model may say it computes, in its `describe` response.
    pub const ANSWERS: [Compute; 5] = [
        Self::Trim,
        Self::LinearModel,
        Self::TimeHistory,
        Self::FrequencyResponse,
        Self::Autorotation,
    ];

    /// What a flight model answers (cierva's aircraft: everything but an autorotation).
    pub const FLIGHT: [Compute; 4] = [
        Self::Trim,
        Self::LinearModel,
        Self::TimeHistory,
        Self::FrequencyResponse,
    ];

    /// What a model of the first version computes (it has no `describe` to say).
    pub const FIRST_VERSION: [Compute; 3] = [Self::Trim, Self::LinearModel, Self::TimeHistory];

    pub fn name(self) -> &'static str {
        match self {
            Self::Trim => "trim",
            Self::LinearModel => "linear_model",
            Self::TimeHistory => "time_history",
            Self::FrequencyResponse => "frequency_response",
            Self::Autorotation => "autorotation",
            Self::Describe => "describe",
        }
    }
}

/// What a model says of itself in its `describe` response (protocol `/2`).
#[derive(Debug, Clone, PartialEq)]
pub struct Description {
    /// What it computes, among [`Compute::ANSWERS`].
    pub computes: Vec<Compute>,
    /// Its states and controls, cierva's names (empty where it does not say).
    pub states: Vec<String>,
    pub controls: Vec<String>,
    pub parameters: Vec<super::Parameter>,
    /// Its discretisation parameters, each of which it refines alone when a request says
    /// `refine` (empty: no grid study).
    pub refinements: Vec<GridParameter>,
}

/// A discretisation parameter a model declares in its `describe` (protocol `/2`): a request
/// with `"refine": {"parameter": name, "level": k}` asks the model with this parameter refined
/// `k` times by `ratio`, everything else as it is ([`super::FlightModel::refinements`]).
#[derive(Debug, Clone, PartialEq)]
pub struct GridParameter {
    pub name: String,
    /// Its value before and after each refinement, in words, level by level (may be fewer).
    pub words: Vec<String>,
    pub ratio: f64,
    pub formal_order: f64,
    /// How many times the model refines it (a request's `level` is 1 to this).
    pub levels: usize,
}

/// An external command: the program and its arguments, the folder it runs in (the case
/// file's), and how long one request may take.
#[derive(Debug)]
pub struct ExternalCommand {
    pub command: Vec<String>,
    pub dir: PathBuf,
    pub timeout: Duration,
    /// The version it speaks.
    pub protocol: Protocol,
    /// Its `describe` response (protocol `/2`), asked once.
    description: OnceLock<Result<Description, String>>,
    /// Its processes, where it runs in persistent mode (protocol `/2`: started once, answering
    /// requests as JSON lines on stdin and stdout).
    persistent: Option<super::persistent::Pool>,
    /// The discretisation parameter this command's requests refine and how many times
    /// ([`GridParameter`]): a refined model of a grid study; `None` for the model as it is.
    refine: Option<(String, usize)>,
    /// Answers by request (what the request asks, without its paths): a case's checks at one
    /// condition share one run. Each request has one cell, filled once: a check that asks
    /// while another's identical request runs waits for its answer. With each, the request's
    /// parameter values as the key writes them, for [`FlightModel::forget`] to compare whole
    /// (searching every key for them was most of an external model's study's own time).
    answers: Mutex<HashMap<String, (String, Arc<AnswerCell>)>>,
}

/// One request's answer, filled once.
type AnswerCell = OnceLock<Result<Answer, String>>;

#[derive(Debug, Clone)]
pub(super) enum Answer {
    Trim(Quantities, Option<super::Start>),
    Linear(LinearModel, Option<super::Start>),
    History(Replayed),
    Responses(crate::run::responses::Responses, Option<super::Start>),
    Autorotated(crate::run::autorotation::Autorotated),
    Described(Description),
}

impl ExternalCommand {
    /// A command that speaks `cierva-external/1`.
    pub fn new(command: Vec<String>, dir: PathBuf, timeout: Duration) -> Self {
        Self::speaking(command, dir, timeout, Protocol::V1)
    }

    /// A command that speaks `protocol`.
    pub fn speaking(
        command: Vec<String>,
        dir: PathBuf,
        timeout: Duration,
        protocol: Protocol,
    ) -> Self {
        Self {
            command,
            dir,
            timeout,
            protocol,
            description: OnceLock::new(),
            persistent: None,
            refine: None,
            answers: Mutex::new(HashMap::new()),
        }
    }

    /// The same command asked with `parameter` refined `level` times: its description known
    /// (not asked again), processes of its own in persistent mode, and answers of its own.
    fn refined_at(&self, parameter: &str, level: usize) -> Self {
        let description = OnceLock::new();
        if let Some(d) = self.description.get() {
            let _ = description.set(d.clone());
        }
        Self {
            command: self.command.clone(),
            dir: self.dir.clone(),
            timeout: self.timeout,
            protocol: self.protocol,
            description,
            persistent: self
                .persistent
                .as_ref()
                .map(|_| super::persistent::Pool::new()),
            refine: Some((parameter.to_string(), level)),
            answers: Mutex::new(HashMap::new()),
        }
    }

    /// The command run in persistent mode (protocol `/2`): started once (up to one process a
    /// core, as checks ask at once), each process answering one request at a time as JSON
    /// lines on its stdin and stdout (`docs/external-models.md`).
    pub fn persistent(mut self) -> Self {
        self.persistent = Some(super::persistent::Pool::new());
        self
    }

    /// The program to run: a program named by a path is relative to the case file's folder; a
    /// bare name is found on PATH.
    fn program(&self) -> Result<(PathBuf, &[String]), String> {
        let Some((program, args)) = self.command.split_first() else {
            return Err("the command is empty".into());
        };
        let program = if program.contains('/') {
            self.dir.join(program)
        } else {
            PathBuf::from(program)
        };
        Ok((program, args))
    }

    /// Starts the command in the case's folder, `last` appended to its arguments, in a process
    /// group of its own (Unix: what it starts is killed with it), its stderr piped; its stdin
    /// and stdout piped where `piped` (persistent mode), else closed and not read.
    pub(super) fn spawn(&self, last: Option<&Path>, piped: bool) -> Result<Child, String> {
        let (program, args) = self.program()?;
        let mut command = Command::new(&program);
        let io = || if piped { Stdio::piped() } else { Stdio::null() };
        command
            .args(args)
            .args(last)
            .current_dir(&self.dir)
            .stdin(io())
            .stdout(io())
            .stderr(Stdio::piped());
        #[cfg(unix)]
        {
            use std::os::unix::process::CommandExt as _;
            command.process_group(0);
        }
        command.spawn().map_err(|e| self.not_started(&program, &e))
    }

    /// The error for a program that could not be started.
    fn not_started(&self, program: &Path, e: &std::io::Error) -> String {
        match e.kind() {
            std::io::ErrorKind::NotFound => format!(
                "`{}` was not found (a bare name is looked up on PATH, a path is relative to \
                 the case file's folder {})",
                program.display(),
                self.dir.display()
            ),
            _ => format!("`{}` could not be started: {e}", program.display()),
        }
    }

    /// What the model says of itself: its `describe` response (protocol `/2`, asked once), or
    /// for `/1` a model that may compute anything and declares no parameters.
    pub fn description(&self) -> Result<Description, String> {
        if self.protocol == Protocol::V1 {
            return Ok(Description {
                computes: Compute::FIRST_VERSION.to_vec(),
                states: Vec::new(),
                controls: Vec::new(),
                parameters: Vec::new(),
                refinements: Vec::new(),
            });
        }
        self.description
            .get_or_init(|| {
                let request = super::Request::at(
                    TrimRequest::level(0.0),
                    Loading {
                        mass_kg: None,
                        density_altitude_ft: 0.0,
                    },
                );
                match self.run(Compute::Describe, &request, With::default())? {
                    Answer::Described(d) => Ok(d),
                    _ => Err("a describe request answered as another".into()),
                }
            })
            .clone()
    }

    /// The request checked against what the model says of itself: it computes `compute`, and
    /// every parameter value is one it declares, inside its range.
    fn admissible(&self, compute: Compute, request: &super::Request) -> Result<(), String> {
        let d = self.description()?;
        if !d.computes.contains(&compute) {
            return Err(format!(
                "{} does not compute a {} (its `describe` says it computes [{}])",
                self.describe(),
                compute.name(),
                d.computes
                    .iter()
                    .map(|c| c.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        super::check_values(&self.describe(), &d.parameters, &request.parameters)
    }

    /// The command as written.
    pub fn written(&self) -> String {
        self.command.join(" ")
    }

    /// Runs one request (remembered: the same request is not run twice).
    fn ask(
        &self,
        compute: Compute,
        request: &super::Request,
        with: With<'_>,
    ) -> Result<Answer, String> {
        self.admissible(compute, request)?;
        let key = Self::key(compute, request, with);
        // The map's lock is held only to find the request's cell; the cell's own lock is held
        // while the command runs, by the first check that asks.
        let cell = Arc::clone(
            &self
                .answers
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .entry(key)
                .or_insert_with(|| (format!("{:?}", request.parameters), Arc::default()))
                .1,
        );
        cell.get_or_init(|| self.run(compute, request, with))
            .clone()
    }

    /// What a request is remembered by: what it computes, the request and what it carries.
    fn key(compute: Compute, request: &super::Request, with: With<'_>) -> String {
        format!("{}|{request:?}|{with:?}", compute.name())
    }

    fn run(
        &self,
        compute: Compute,
        request: &super::Request,
        with: With<'_>,
    ) -> Result<Answer, String> {
        let out = match &self.persistent {
            Some(pool) => pool.ask(self, compute, request, with),
            None => {
                let dir = scratch_dir().map_err(|e| format!("{}: {e}", self.describe()))?;
                let out = self.run_in(&dir, compute, request, with);
                let _ = std::fs::remove_dir_all(&dir);
                out
            }
        };
        out.map_err(|e| format!("{} ({} request): {e}", self.describe(), compute.name()))
    }

    /// A request as JSON, without where its controls are and where its answer goes (which
    /// the two modes say each their own way).
    pub(super) fn request_json(
        &self,
        compute: Compute,
        request: &super::Request,
        with: With<'_>,
    ) -> serde_json::Value {
        let (condition, loading) = (request.condition, request.loading);
        let mut json = serde_json::json!({
            "protocol": self.protocol.name(),
            "compute": compute.name(),
        });
        if compute == Compute::Describe {
            // What the model is does not depend on a condition.
            return json;
        }
        if let Some(t) = with.tunnel {
            json["tunnel"] = serde_json::json!(t);
            json["parameters"] = serde_json::json!(request.parameters);
            if let Some((parameter, level)) = &self.refine {
                json["refine"] = serde_json::json!({"parameter": parameter, "level": level});
            }
            return json;
        }
        json["condition"] = serde_json::json!({
            "airspeed_mph": condition.airspeed_mph,
            "airspeed_m_s": condition.airspeed_mph * crate::units::MPH_TO_M_S,
            "airspeed_kn": condition.airspeed_mph / crate::units::MPH_PER_KN,
            "climb_m_s": condition.climb_m_s,
            "turn_rate_deg_s": condition.turn_rate_deg_s,
        });
        json["loading"] = serde_json::json!({
            "mass_kg": loading.mass_kg,
            "density_altitude_ft": loading.density_altitude_ft,
        });
        if self.protocol == Protocol::V2 {
            json["parameters"] = serde_json::json!(request.parameters);
        }
        if let Some((parameter, level)) = &self.refine {
            json["refine"] = serde_json::json!({"parameter": parameter, "level": level});
        }
        if let Some(f) = with.frequencies_hz {
            json["frequencies_hz"] = serde_json::json!(f);
        }
        if let Some(s) = request
            .start
            .as_ref()
            .filter(|_| self.protocol == Protocol::V2)
        {
            json["start"] = (*s.0).clone();
        }
        if let Some(c) = with.controls {
            json["sample_s"] = serde_json::json!(c.sample_s);
            json["samples"] = serde_json::json!(c.samples + 1);
            if self.protocol == Protocol::V2 {
                json["initial_state"] = serde_json::json!(c.initial_state);
            }
        }
        json
    }

    fn run_in(
        &self,
        dir: &Path,
        compute: Compute,
        request: &super::Request,
        with: With<'_>,
    ) -> Result<Answer, String> {
        let response = dir.join(match compute {
            Compute::TimeHistory => "response.csv",
            _ => "response.json",
        });
        let mut json = self.request_json(compute, request, with);
        json["response"] = serde_json::json!(response);
        if let Some(c) = with.controls {
            let path = dir.join("controls.csv");
            std::fs::write(&path, controls_csv(c))
                .map_err(|e| format!("writing {}: {e}", path.display()))?;
            json["controls"] = serde_json::json!(path);
        }
        let request_path = dir.join("request.json");
        let text = serde_json::to_string_pretty(&json).map_err(|e| e.to_string())?;
        std::fs::write(&request_path, text)
            .map_err(|e| format!("writing {}: {e}", request_path.display()))?;
        let rows = with.rows();
        let limit = response_limit_bytes(compute, rows);
        self.execute(&request_path, &response, limit)?;
        let size = std::fs::metadata(&response).map_err(|e| {
            format!(
                "exited 0 but wrote no response at {} ({e})",
                response.display()
            )
        })?;
        if size.len() > limit {
            return Err(too_large(size.len(), limit, compute, rows));
        }
        let text = std::fs::read_to_string(&response)
            .map_err(|e| format!("its response at {} ({e})", response.display()))?;
        let protocol = self.protocol.name();
        match compute {
            Compute::Trim => parse_trim(&text, protocol).map(|(q, s)| Answer::Trim(q, s)),
            Compute::LinearModel => {
                parse_linear(&text, protocol).map(|(m, s)| Answer::Linear(m, s))
            }
            Compute::Describe => parse_describe(&text).map(Answer::Described),
            Compute::TimeHistory => super::files::parse_history(&text, Some(rows))
                .map(Answer::History)
                .map_err(|e| format!("(CSV): {e}")),
            Compute::FrequencyResponse => {
                let asked = with.frequencies_hz.unwrap_or(&[]);
                parse_frequency_response(&text, protocol, asked, &self.describe())
                    .map(|(r, s)| Answer::Responses(r, s))
            }
            Compute::Autorotation => parse_autorotation(&text, protocol).map(Answer::Autorotated),
        }
        .map_err(|e| format!("its response {e}"))
    }

    /// Runs the command with `request` as its last argument, in the case's folder, until it
    /// exits, passes its timeout, or writes a response past `limit` bytes.
    fn execute(&self, request: &Path, response: &Path, limit: u64) -> Result<(), String> {
        let mut child = self.spawn(Some(request), false)?;
        let stderr = StderrTail::read(&mut child);
        let start = Instant::now();
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) => {}
                Err(e) => {
                    kill_group(&mut child);
                    return Err(format!("waiting for it: {e}"));
                }
            }
            if start.elapsed() >= self.timeout {
                kill_group(&mut child);
                return Err(format!(
                    "timed out after {} s (`timeout_s`) and was killed{}",
                    self.timeout.as_secs_f64(),
                    stderr.finish()
                ));
            }
            let written = std::fs::metadata(response).map_or(0, |m| m.len());
            if written > limit {
                kill_group(&mut child);
                return Err(format!(
                    "was killed: its response at {} passed {limit} bytes while it ran (the most \
                     a response may take, `MAX_RESPONSE_BYTES` and `MAX_HISTORY_ROW_BYTES` a row \
                     asked for){}",
                    response.display(),
                    stderr.finish()
                ));
            }
            std::thread::sleep(POLL);
        };
        // It has exited: whatever it left running in its group goes too (and lets go of the
        // stderr pipe).
        kill_group(&mut child);
        let tail = stderr.finish();
        if !status.success() {
            let code = status.code().map_or_else(
                || "was killed by a signal".to_string(),
                |c| format!("exited {c}"),
            );
            return Err(format!("{code}{tail}"));
        }
        Ok(())
    }
}

/// Kills a command's process group (on Unix; its process tree on Windows) and reaps the
/// command. The group is the command's own ([`Command::process_group`]), so no other process
/// of cierva's is in it.
pub(super) fn kill_group(child: &mut Child) {
    #[cfg(unix)]
    if let Ok(pid) = libc::pid_t::try_from(child.id()) {
        // SAFETY: `kill` takes plain integers and touches no memory of ours; a negative pid
        // names the process group the command leads, which only it and what it started are in.
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
        }
    }
    #[cfg(windows)]
    {
        let _ = Command::new("taskkill")
            .args(["/T", "/F", "/PID", &child.id().to_string()])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// The end of a command's stderr, read as it comes by a thread of its own (see
/// [`STDERR_KEEP_BYTES`]).
#[derive(Debug)]
pub(super) struct StderrTail {
    kept: Arc<Mutex<Kept>>,
    closed: mpsc::Receiver<()>,
}

#[derive(Debug, Default)]
struct Kept {
    bytes: Vec<u8>,
    /// Bytes read and dropped before `bytes`.
    dropped: u64,
}

impl StderrTail {
    pub(super) fn read(child: &mut Child) -> Self {
        let kept = Arc::new(Mutex::new(Kept::default()));
        let (done, closed) = mpsc::channel();
        if let Some(mut pipe) = child.stderr.take() {
            let into = Arc::clone(&kept);
            std::thread::spawn(move || {
                let mut buf = [0u8; 8192];
                while let Ok(n) = pipe.read(&mut buf) {
                    if n == 0 {
                        break;
                    }
                    let mut k = into.lock().unwrap_or_else(PoisonError::into_inner);
                    k.bytes.extend_from_slice(&buf[..n]);
                    if k.bytes.len() > 2 * STDERR_KEEP_BYTES {
                        let cut = k.bytes.len() - STDERR_KEEP_BYTES;
                        k.bytes.drain(..cut);
                        k.dropped += cut as u64;
                    }
                }
                let _ = done.send(());
            });
        }
        Self { kept, closed }
    }

    /// What it wrote, as the end of an error message, once the pipe has closed (or after
    /// [`STDERR_GRACE`]).
    pub(super) fn finish(&self) -> String {
        let _ = self.closed.recv_timeout(STDERR_GRACE);
        let k = self.kept.lock().unwrap_or_else(PoisonError::into_inner);
        let total = k.dropped + k.bytes.len() as u64;
        // The window's first bytes may fall inside a UTF-8 character or a line: the text starts
        // at the first whole one.
        let text = String::from_utf8_lossy(&k.bytes);
        let lines: Vec<&str> = text.lines().collect();
        if lines.is_empty() {
            return "; its stderr is empty".into();
        }
        let from = lines.len().saturating_sub(STDERR_LINES);
        let shown: Vec<String> = lines[from..]
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let begun_before = i == 0 && from == 0 && k.dropped > 0;
                format!(
                    "  | {}{}",
                    if begun_before { "..." } else { "" },
                    cut_line(l)
                )
            })
            .collect();
        let what = if k.dropped > 0 || from > 0 {
            format!(" (its last {} lines of {total} bytes)", shown.len())
        } else {
            String::new()
        };
        format!("; its stderr{what}:\n{}", shown.join("\n"))
    }
}

/// A line of stderr cut to [`crate::inputs::yaml::EXCERPT_CHARS`] characters, saying how many
/// more there were.
fn cut_line(line: &str) -> String {
    let max = crate::inputs::yaml::EXCERPT_CHARS;
    let n = line.chars().count();
    if n <= max {
        return line.to_string();
    }
    let head: String = line.chars().take(max).collect();
    format!("{head}... ({} more characters)", n - max)
}

/// The error for a response of `size` bytes past `limit`.
pub(super) fn too_large(size: u64, limit: u64, compute: Compute, rows: usize) -> String {
    let asked = match compute {
        Compute::TimeHistory => format!(" for {rows} rows"),
        Compute::FrequencyResponse => format!(" for {rows} frequencies"),
        _ => String::new(),
    };
    format!(
        "its response is {size} bytes, past the {limit} a {} response{asked} may take \
         (`MAX_RESPONSE_BYTES`, `MAX_HISTORY_ROW_BYTES`); it was not read",
        compute.name()
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
pub(super) fn parse_json<T: serde::de::DeserializeOwned>(
    text: &str,
    protocol: &str,
) -> Result<T, String> {
    #[derive(Deserialize)]
    struct Head {
        protocol: Option<String>,
    }
    let head: Head = serde_json::from_str(text).map_err(|e| format!("is not JSON: {e}"))?;
    match head.protocol.as_deref() {
        Some(p) if p == protocol => {}
        Some(p) => {
            return Err(format!(
                "says protocol `{p}`; the case asks it in `{protocol}` (`protocol:` in the case's \
                 `external`)"
            ));
        }
        None => return Err(format!("has no `protocol` (`{protocol}`)")),
    }
    if let Some((line, column, message)) = crate::inputs::yaml::json_underflow(text) {
        return Err(format!("at line {line} column {column}: {message}"));
    }
    serde_json::from_str(text).map_err(|e| format!("does not parse: {e}"))
}

/// An answer's `start` (protocol `/2`): where the model's answer ended, any JSON it makes,
/// for cierva to hand back with a request near it ([`super::Start`]).
fn start_in(
    start: Option<serde_json::Value>,
    protocol: &str,
) -> Result<Option<super::Start>, String> {
    match start.filter(|s| !s.is_null()) {
        None => Ok(None),
        Some(_) if protocol != PROTOCOL_2 => Err(format!(
            "has a `start`, which is `{PROTOCOL_2}`'s (the case asks in `{protocol}`)"
        )),
        Some(s) => Ok(Some(super::Start(Arc::new(s)))),
    }
}

pub(super) fn parse_trim(
    text: &str,
    protocol: &str,
) -> Result<(Quantities, Option<super::Start>), String> {
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Response {
        #[allow(dead_code)]
        protocol: String,
        trim: BTreeMap<String, f64>,
        #[serde(default)]
        start: Option<serde_json::Value>,
    }
    let r: Response = parse_json(text, protocol)?;
    let mut out = Vec::new();
    for (name, v) in r.trim {
        let name = trim_name(&name).map_err(|e| format!("`trim`: {e}"))?;
        if !v.is_finite() {
            return Err(format!("`trim.{name}` is not finite"));
        }
        out.push((name, v));
    }
    Ok((out, start_in(r.start, protocol)?))
}

pub(super) fn parse_linear(
    text: &str,
    protocol: &str,
) -> Result<(LinearModel, Option<super::Start>), String> {
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Response {
        #[allow(dead_code)]
        protocol: String,
        linear_model: Linear,
        #[serde(default)]
        start: Option<serde_json::Value>,
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
    let r: Response = parse_json(text, protocol)?;
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
    let start = start_in(r.start, protocol)?;
    LinearModel::from_rows(m.states, m.controls, &m.a, &m.b)
        .map(|m| (m, start))
        .map_err(|e| format!("`linear_model`: {e}"))
}

/// A `frequency_response` answer: every state's response to every control at each of the
/// `asked` frequencies (the same numbers, in order), as `real` and `imag` parts indexed
/// `[frequency][state][control]`, each finite; cierva's state and control names; `method`, what
/// gave them in words (optional), said with `model`, the model in words.
pub(super) fn parse_frequency_response(
    text: &str,
    protocol: &str,
    asked: &[f64],
    model: &str,
) -> Result<(crate::run::responses::Responses, Option<super::Start>), String> {
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Response {
        #[allow(dead_code)]
        protocol: String,
        frequency_response: Answered,
        #[serde(default)]
        start: Option<serde_json::Value>,
    }
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Answered {
        states: Vec<String>,
        controls: Vec<String>,
        frequencies_hz: Vec<f64>,
        real: Vec<Vec<Vec<f64>>>,
        imag: Vec<Vec<Vec<f64>>>,
        #[serde(default)]
        method: Option<String>,
    }
    use cierva_model::aircraft::linearise::{CONTROLS, STATES};
    let r: Response = parse_json(text, protocol)?;
    let m = r.frequency_response;
    let at = "`frequency_response`";
    for (names, known, what) in [
        (&m.states, &STATES[..], "state"),
        (&m.controls, &CONTROLS[..], "control"),
    ] {
        if let Some(n) = names.iter().find(|n| !known.contains(&n.as_str())) {
            return Err(format!(
                "{at}: `{n}` is not one of cierva's {what}s [{}]",
                known.join(", ")
            ));
        }
    }
    if m.frequencies_hz != asked {
        return Err(format!(
            "{at}: `frequencies_hz` are not the {} frequencies asked for, in their order",
            asked.len()
        ));
    }
    let (n, i, j) = (asked.len(), m.states.len(), m.controls.len());
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let mut h = nalgebra::DMatrix::<rustfft::num_complex::Complex64>::zeros(i, j);
        for (part, name) in [(&m.real, "real"), (&m.imag, "imag")] {
            let rows = part.get(k).filter(|rows| rows.len() == i);
            let ok = rows.is_some_and(|rows| rows.iter().all(|r| r.len() == j));
            let Some(rows) = rows.filter(|_| ok) else {
                return Err(format!(
                    "{at}: `{name}` is not {n} frequencies of {i} states by {j} controls"
                ));
            };
            for (s, row) in rows.iter().enumerate() {
                for (c, &x) in row.iter().enumerate() {
                    if !x.is_finite() {
                        return Err(format!("{at}: `{name}[{k}][{s}][{c}]` is not finite"));
                    }
                    match name {
                        "real" => h[(s, c)].re = x,
                        _ => h[(s, c)].im = x,
                    }
                }
            }
        }
        out.push(h);
    }
    let responses = crate::run::responses::Responses {
        states: m.states,
        controls: m.controls,
        frequencies_hz: m.frequencies_hz,
        at: out,
        from: match m.method {
            Some(method) => format!("{method} ({model}'s frequency response)"),
            None => format!("the frequency response {model} gives"),
        },
    };
    Ok((responses, start_in(r.start, protocol)?))
}

/// An `autorotation` answer: `{"quantities": {...}, "outside_validity": [...]}` (an
/// equilibrium: quantities named as an `autorotation` check's, each finite; where the model's
/// equations were used outside their validity, optional) or `{"no_equilibrium": "why",
/// "numbers": {...}}` (none there: why, and the numbers that say how far from one, optional).
pub(super) fn parse_autorotation(
    text: &str,
    protocol: &str,
) -> Result<crate::run::autorotation::Autorotated, String> {
    use crate::run::autorotation::{Autorotated, TunnelAnswer};
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Response {
        #[allow(dead_code)]
        protocol: String,
        autorotation: Answered,
    }
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Answered {
        #[serde(default)]
        quantities: Option<BTreeMap<String, f64>>,
        #[serde(default)]
        outside_validity: Vec<String>,
        #[serde(default)]
        no_equilibrium: Option<String>,
        #[serde(default)]
        numbers: BTreeMap<String, f64>,
    }
    let r: Response = parse_json(text, protocol)?;
    let a = r.autorotation;
    let at = "`autorotation`";
    match (a.quantities, a.no_equilibrium) {
        (Some(q), None) => {
            let known = crate::inputs::quantity::AUTOROTATION;
            let mut quantities = Vec::new();
            for (name, v) in q {
                let Some(k) = known.iter().find(|k| k.name() == name) else {
                    let names: Vec<&str> = known.iter().map(|k| k.name()).collect();
                    return Err(format!(
                        "{at}: `{name}` is not an autorotation quantity; they are [{}]",
                        names.join(", ")
                    ));
                };
                if !v.is_finite() {
                    return Err(format!("{at}: `quantities.{name}` is not finite"));
                }
                quantities.push((k.name(), v));
            }
            Ok(Autorotated::Equilibrium(TunnelAnswer {
                quantities,
                outside_validity: a.outside_validity,
            }))
        }
        (None, Some(reason)) => Ok(Autorotated::NoEquilibrium {
            reason,
            numbers: a.numbers.into_iter().collect(),
        }),
        _ => Err(format!(
            "{at}: give `quantities` (an equilibrium) or `no_equilibrium` (why there is none), one of them"
        )),
    }
}

/// A `describe` response as written (see [`parse_describe`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DescribeResponse {
    #[allow(dead_code)]
    protocol: String,
    describe: Described,
}

/// What the model says of itself, as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Described {
    computes: Vec<String>,
    #[serde(default)]
    states: Vec<String>,
    #[serde(default)]
    controls: Vec<String>,
    #[serde(default)]
    parameters: Vec<Declared>,
    #[serde(default)]
    refinements: Vec<DeclaredGrid>,
}

/// A declared discretisation parameter as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DeclaredGrid {
    name: String,
    #[serde(default)]
    words: Vec<String>,
    ratio: f64,
    formal_order: f64,
    #[serde(default = "two_levels")]
    levels: usize,
}

/// A declared discretisation parameter's levels where it does not say: the grid study's
/// ([`super::GRID_LEVELS`]).
fn two_levels() -> usize {
    super::GRID_LEVELS
}

/// A declared parameter as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Declared {
    name: String,
    unit: String,
    #[serde(default)]
    meaning: String,
    nominal: f64,
    #[serde(default)]
    range: Option<DeclaredRange>,
    #[serde(default)]
    correction: bool,
}

/// A declared parameter's range as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DeclaredRange {
    lower: f64,
    upper: f64,
    source: String,
    #[serde(default)]
    distribution: crate::inputs::ranges::Shape,
    #[serde(default)]
    sigma: Option<f64>,
    #[serde(default)]
    shares: Option<String>,
    #[serde(default)]
    taken_from: Vec<String>,
}

/// A `describe` response: what the model computes, its states and controls, and its
/// parameters, each checked (names unique, nominal values finite and inside their ranges, every
/// range with its source).
pub(super) fn parse_describe(text: &str) -> Result<Description, String> {
    use cierva_model::aircraft::linearise::{CONTROLS, STATES};
    let r: DescribeResponse = parse_json(text, PROTOCOL_2)?;
    let d = r.describe;
    let mut computes = Vec::new();
    for (i, c) in d.computes.iter().enumerate() {
        let Some(known) = Compute::ANSWERS.iter().find(|k| k.name() == c) else {
            return Err(format!(
                "`describe.computes[{i}]`: `{c}` is not a request cierva makes; they are [{}]",
                Compute::ANSWERS.map(Compute::name).join(", ")
            ));
        };
        computes.push(*known);
    }
    for (names, known, what) in [
        (&d.states, &STATES[..], "states"),
        (&d.controls, &CONTROLS[..], "controls"),
    ] {
        if let Some(n) = names.iter().find(|n| !known.contains(&n.as_str())) {
            return Err(format!(
                "`describe.{what}`: `{n}` is not one of cierva's {what} [{}]",
                known.join(", ")
            ));
        }
    }
    let mut parameters: Vec<super::Parameter> = Vec::new();
    for (i, p) in d.parameters.into_iter().enumerate() {
        let at = format!("`describe.parameters[{i}]` (`{}`)", p.name);
        named_once(
            &at,
            &p.name,
            "a parameter",
            parameters.iter().map(|q| &q.name),
        )?;
        if !p.nominal.is_finite() {
            return Err(format!("{at}: its nominal value is not finite"));
        }
        let range = p
            .range
            .map(|r| declared_range(&at, p.nominal, r))
            .transpose()?;
        parameters.push(super::Parameter {
            name: p.name,
            unit: p.unit,
            meaning: p.meaning,
            nominal: p.nominal,
            range,
            correction: p.correction,
        });
    }
    let mut refinements: Vec<GridParameter> = Vec::new();
    for (i, g) in d.refinements.into_iter().enumerate() {
        let at = format!("`describe.refinements[{i}]` (`{}`)", g.name);
        named_once(
            &at,
            &g.name,
            "a discretisation parameter",
            refinements.iter().map(|r| &r.name),
        )?;
        if !(g.ratio.is_finite() && g.ratio > 1.0) {
            return Err(format!(
                "{at}: its `ratio` {} is not a refinement ratio (a finite number above 1: 2 \
                 for a step halved, 10 for a tolerance a tenth)",
                g.ratio
            ));
        }
        if !(g.formal_order.is_finite() && g.formal_order > 0.0) {
            return Err(format!(
                "{at}: its `formal_order` {} is not an order (a finite number above 0)",
                g.formal_order
            ));
        }
        if g.levels == 0 {
            return Err(format!(
                "{at}: `levels` is 0 (how many times the model refines it, at least 1)"
            ));
        }
        refinements.push(GridParameter {
            name: g.name,
            words: g.words,
            ratio: g.ratio,
            formal_order: g.formal_order,
            levels: g.levels,
        });
    }
    Ok(Description {
        computes,
        states: d.states,
        controls: d.controls,
        parameters,
        refinements,
    })
}

/// A declared name at `at`, checked: not blank (`what` needs a name), and not among those
/// declared before it.
fn named_once<'a>(
    at: &str,
    name: &str,
    what: &str,
    before: impl IntoIterator<Item = &'a String>,
) -> Result<(), String> {
    if name.trim().is_empty() {
        return Err(format!("{at}: {what} needs a name"));
    }
    if before.into_iter().any(|n| n == name) {
        return Err(format!("{at}: declared twice"));
    }
    Ok(())
}

/// A declared range, checked: an interval holding the nominal value, with a source and a
/// well-formed distribution.
fn declared_range(
    at: &str,
    nominal: f64,
    r: DeclaredRange,
) -> Result<crate::inputs::ranges::Range, String> {
    use crate::inputs::ranges::{Range, Shape};
    if !(r.lower.is_finite() && r.upper.is_finite() && r.lower <= r.upper) {
        return Err(format!(
            "{at}: its range [{}, {}] is not an interval",
            r.lower, r.upper
        ));
    }
    if !(r.lower..=r.upper).contains(&nominal) {
        return Err(format!(
            "{at}: its nominal value {nominal} is outside its range [{}, {}]",
            r.lower, r.upper
        ));
    }
    if r.source.trim().is_empty() {
        return Err(format!(
            "{at}: its range has no source (where the range comes from: a report and table, or \
             \"estimated: by which method\")"
        ));
    }
    if (r.distribution == Shape::Normal) != r.sigma.is_some_and(|s| s > 0.0) {
        return Err(format!(
            "{at}: a `normal` distribution needs a positive `sigma`, and only it"
        ));
    }
    for (k, t) in r.taken_from.iter().enumerate() {
        crate::inputs::ranges::check_taken_from(t)
            .map_err(|m| format!("{at}: its range's `taken_from[{k}]`: {m}"))?;
    }
    Ok(Range {
        lower: r.lower,
        upper: r.upper,
        source: r.source,
        distribution: r.distribution,
        sigma: r.sigma,
        shares: r.shares,
        taken_from: r.taken_from,
    })
}

impl FlightModel for ExternalCommand {
    fn describe(&self) -> String {
        match &self.refine {
            None => format!("the command `{}`", self.written()),
            Some((parameter, level)) => format!(
                "the command `{}` with its {parameter} refined {level} time{}",
                self.written(),
                if *level == 1 { "" } else { "s" }
            ),
        }
    }

    fn parameters(&self) -> Result<Vec<super::Parameter>, String> {
        Ok(self.description()?.parameters)
    }

    /// Forgets its answers to requests with these values (a study's point, once its checks
    /// have run).
    fn forget(&self, values: &super::Values) {
        let with = format!("{values:?}");
        self.answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .retain(|_, (parameters, _)| *parameters != with);
    }

    /// The `start` its answer `of` the request gave, where it gave one (read from the
    /// answer remembered: never asked for it alone).
    fn start_after(&self, request: &super::Request, of: &super::AnswerOf) -> Option<super::Start> {
        let (compute, frequencies);
        let with = match of {
            super::AnswerOf::Trim => {
                compute = Compute::Trim;
                With::default()
            }
            super::AnswerOf::LinearModel => {
                compute = Compute::LinearModel;
                With::default()
            }
            super::AnswerOf::Responses(f) => {
                compute = Compute::FrequencyResponse;
                frequencies = f.as_slice();
                With {
                    frequencies_hz: Some(frequencies),
                    ..With::default()
                }
            }
        };
        let key = Self::key(compute, request, with);
        let cell = self
            .answers
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .get(&key)
            .map(|(_, cell)| Arc::clone(cell))?;
        match cell.get()? {
            Ok(Answer::Trim(_, s) | Answer::Linear(_, s) | Answer::Responses(_, s)) => s.clone(),
            _ => None,
        }
    }

    /// Each discretisation parameter its `describe` declares, refined once by a request's
    /// `refine`; a refined command refines its own parameter again, to its declared `levels`.
    /// None where its `describe` fails (which every other request then reports).
    fn refinements(&self) -> Vec<super::Refinement> {
        let Ok(d) = self.description() else {
            return Vec::new();
        };
        d.refinements
            .iter()
            .filter_map(|g| {
                let level = match &self.refine {
                    None => 1,
                    Some((name, k)) if *name == g.name && *k < g.levels => k + 1,
                    Some(_) => return None,
                };
                Some(super::Refinement {
                    parameter: g.name.clone(),
                    words: g
                        .words
                        .get(level - 1)
                        .cloned()
                        .unwrap_or_else(|| format!("refined {level} time(s) by {}", g.ratio)),
                    ratio: g.ratio,
                    formal_order: g.formal_order,
                    model: Arc::new(self.refined_at(&g.name, level)),
                })
            })
            .collect()
    }

    fn trim(&self, request: &super::Request) -> Result<Quantities, String> {
        match self.ask(Compute::Trim, request, With::default())? {
            Answer::Trim(q, _) => Ok(q),
            _ => Err("a trim request answered as another".into()),
        }
    }

    fn linear_model(&self, request: &super::Request) -> Result<LinearModel, String> {
        match self.ask(Compute::LinearModel, request, With::default())? {
            Answer::Linear(m, _) => Ok(m),
            _ => Err("a linear-model request answered as another".into()),
        }
    }

    fn time_history(
        &self,
        request: &super::Request,
        controls: &ControlChanges,
    ) -> Result<Replayed, String> {
        let with = With {
            controls: Some(controls),
            ..With::default()
        };
        match self.ask(Compute::TimeHistory, request, with)? {
            Answer::History(f) => Ok(f),
            _ => Err("a time-history request answered as another".into()),
        }
    }

    /// Its `frequency_response` answer where it says it computes one (protocol `/2`); from its
    /// linear model's A and B otherwise.
    fn responses(
        &self,
        request: &super::Request,
        frequencies_hz: &[f64],
    ) -> Result<crate::run::responses::Responses, String> {
        if !self
            .description()?
            .computes
            .contains(&Compute::FrequencyResponse)
        {
            return crate::run::responses::Responses::of_linear_model(
                &self.linear_model(request)?,
                frequencies_hz,
                crate::run::responses::from_a_and_b(&self.describe()),
            );
        }
        let with = With {
            frequencies_hz: Some(frequencies_hz),
            ..With::default()
        };
        match self.ask(Compute::FrequencyResponse, request, with)? {
            Answer::Responses(r, _) => Ok(r),
            _ => Err("a frequency-response request answered as another".into()),
        }
    }

    fn autorotation(
        &self,
        request: &super::TunnelRequest,
    ) -> Result<crate::run::autorotation::Autorotated, String> {
        let with = With {
            tunnel: Some(&request.tunnel),
            ..With::default()
        };
        // The tunnel's condition stands in for a flight condition and loading.
        let asked = super::Request {
            parameters: request.parameters.clone(),
            ..super::Request::at(
                crate::inputs::condition::TrimRequest::level(0.0),
                crate::inputs::condition::Loading {
                    mass_kg: None,
                    density_altitude_ft: 0.0,
                },
            )
        };
        match self.ask(Compute::Autorotation, &asked, with)? {
            Answer::Autorotated(a) => Ok(a),
            _ => Err("an autorotation request answered as another".into()),
        }
    }
}
