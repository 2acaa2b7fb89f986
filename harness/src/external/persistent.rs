//! Persistent mode of the protocol `cierva-external/2` (`docs/external-models.md`): the command
//! is started once and answers requests as JSON lines, one request a line on its stdin, one
//! answer a line on its stdout, in order, so that a study of thousands of evaluations does not
//! start thousands of processes.
//!
//! A request is the one-shot request without its file paths: its controls (a time history's)
//! are inline, as columns (`{"time_s": [...], "eta_s_percent": [...], ...}`), and it carries an
//! `id`. The answer carries the same `id` and, in place of a response file, the response itself
//! (`trim`, `linear_model`, `describe`, or `time_history` as columns), or `error`: why the model
//! cannot answer (what a non-zero exit says in one-shot mode).
//!
//! Checks that ask at once are answered by up to one process a core ([`Pool`]), each answering
//! one request at a time. A process costs what a one-shot command does, and is bounded the
//! same way: its own process group, its stderr's end kept, each answer's size watched as it is
//! read (past its limit the process is killed and the answer refused), its timeout per request.
//! A process that exits or is killed is not reused: its request is an error that says so (the
//! requests it had answered stand), and the next request starts a new one.

use super::command::{
    Answer, Compute, ExternalCommand, StderrTail, With, kill_group, parse_autorotation,
    parse_describe, parse_frequency_response, parse_linear, parse_trim, response_limit_bytes,
};
use super::{ControlChanges, FlightModel as _, Request};
use crate::run::replay::{Replayed, SIGNALS};
use std::io::{BufRead as _, BufReader, Write as _};
use std::process::{Child, ChildStdin};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, PoisonError, mpsc};
use std::time::Duration;

/// The processes of a command in persistent mode: those idle, and how many are alive.
#[derive(Debug)]
pub(super) struct Pool {
    state: Mutex<State>,
    freed: Condvar,
    /// The most processes at once: one a core.
    most: usize,
    /// Requests sent, for their ids.
    next_id: AtomicU64,
}

#[derive(Debug, Default)]
struct State {
    idle: Vec<Worker>,
    alive: usize,
}

impl Pool {
    pub(super) fn new() -> Self {
        Self {
            state: Mutex::new(State::default()),
            freed: Condvar::new(),
            most: crate::run::parallel::threads(),
            next_id: AtomicU64::new(0),
        }
    }

    /// Asks one request of an idle process (started if none is and fewer than one a core
    /// are alive; else waits for one).
    pub(super) fn ask(
        &self,
        command: &ExternalCommand,
        compute: Compute,
        request: &Request,
        with: With<'_>,
    ) -> Result<Answer, String> {
        let worker = {
            let mut s = self.state.lock().unwrap_or_else(PoisonError::into_inner);
            loop {
                if let Some(w) = s.idle.pop() {
                    break Some(w);
                }
                if s.alive < self.most {
                    s.alive += 1;
                    break None;
                }
                s = self.freed.wait(s).unwrap_or_else(PoisonError::into_inner);
            }
        };
        let worker = match worker {
            Some(w) => Ok(w),
            None => Worker::start(command),
        };
        let mut worker = match worker {
            Ok(w) => w,
            Err(e) => {
                self.lost();
                return Err(e);
            }
        };
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        match worker.ask(command, id, compute, request, with) {
            Ok(answer) => {
                let mut s = self.state.lock().unwrap_or_else(PoisonError::into_inner);
                s.idle.push(worker);
                self.freed.notify_one();
                answer
            }
            // The process is gone or killed: not reused.
            Err(e) => {
                drop(worker);
                self.lost();
                Err(e)
            }
        }
    }

    /// One process fewer alive.
    fn lost(&self) {
        let mut s = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        s.alive = s.alive.saturating_sub(1);
        self.freed.notify_one();
    }
}

/// How many times, 5 ms apart, a process being ended is asked whether it has exited before it
/// is killed (0.25 s): one whose stdout closed has its exit status by then.
const EXIT_POLLS: usize = 50;

/// What the reader of a process's stdout passes on: a line, or why there is none.
#[derive(Debug)]
enum Line {
    Text(String),
    /// The line passed its limit, bytes (the reader stops).
    TooLong(u64),
    /// Its stdout closed (the process exited) or could not be read.
    Closed(String),
}

/// One process of a persistent command.
#[derive(Debug)]
struct Worker {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: mpsc::Receiver<Line>,
    /// The longest line the reader accepts now, bytes (set before each request).
    limit: Arc<AtomicU64>,
    stderr: StderrTail,
}

impl Worker {
    /// Starts the command as written (nothing appended: its own arguments say how it starts
    /// serving), in its own process group, its stdout read line by line on a thread.
    fn start(command: &ExternalCommand) -> Result<Self, String> {
        let mut child = command.spawn(None, true)?;
        let stderr = StderrTail::read(&mut child);
        let stdin = child.stdin.take();
        let stdout = child.stdout.take().ok_or("its stdout could not be read")?;
        let limit = Arc::new(AtomicU64::new(0));
        let (send, lines) = mpsc::channel();
        let max = Arc::clone(&limit);
        std::thread::spawn(move || read_lines(stdout, &max, &send));
        Ok(Self {
            child,
            stdin,
            lines,
            limit,
            stderr,
        })
    }

    /// Sends one request and reads its answer, within the command's timeout. An `Err` means
    /// the process is not to be used again.
    fn ask(
        &mut self,
        command: &ExternalCommand,
        id: u64,
        compute: Compute,
        request: &Request,
        with: With<'_>,
    ) -> Result<Result<Answer, String>, String> {
        let rows = with.rows();
        let limit = response_limit_bytes(compute, rows);
        self.limit.store(limit, Ordering::Relaxed);
        let mut json = command.request_json(compute, request, with);
        json["id"] = serde_json::json!(id);
        if let Some(c) = with.controls {
            json["controls"] = controls_json(c);
        }
        let mut line = serde_json::to_string(&json).map_err(|e| e.to_string())?;
        line.push('\n');
        let sent = self
            .stdin
            .as_mut()
            .ok_or_else(|| "its stdin is closed".to_string())
            .and_then(|s| {
                s.write_all(line.as_bytes())
                    .and_then(|()| s.flush())
                    .map_err(|e| format!("writing the request to its stdin: {e}"))
            });
        if let Err(e) = sent {
            return Err(self.end(&e));
        }
        let answer = match self.lines.recv_timeout(command.timeout) {
            Ok(Line::Text(text)) => text,
            Ok(Line::TooLong(n)) => {
                return Err(self.end(&format!(
                    "was killed: its answer passed {n} bytes as it was read (the most a \
                     {} answer may take{}, `MAX_RESPONSE_BYTES` and `MAX_HISTORY_ROW_BYTES` or \
                     `MAX_FREQUENCY_BYTES`)",
                    compute.name(),
                    match (rows > 0, compute) {
                        (true, Compute::FrequencyResponse) => format!(" for {rows} frequencies"),
                        (true, _) => format!(" for {rows} rows"),
                        (false, _) => String::new(),
                    }
                )));
            }
            Ok(Line::Closed(why)) => return Err(self.end(&why)),
            Err(mpsc::RecvTimeoutError::Timeout) => {
                return Err(self.end(&format!(
                    "timed out after {} s (`timeout_s`) on this request and was killed",
                    command.timeout.as_secs_f64()
                )));
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(self.end("its stdout's reader stopped"));
            }
        };
        let asked = Asked {
            with,
            protocol: command.protocol.name(),
            model: command.describe(),
        };
        match parse_answer(&answer, id, compute, &asked) {
            Ok(answer) => Ok(answer),
            // An answer that is not an answer to this request: the stream is out of step.
            Err(Fatal(e)) => Err(self.end(&e)),
        }
    }

    /// Ends the process (its whole group) and says why, with how it exited and its stderr.
    fn end(&mut self, why: &str) -> String {
        // A process whose stdout closed is exiting: give it a moment to say how.
        let mut exited = None;
        for _ in 0..EXIT_POLLS {
            exited = self.child.try_wait().ok().flatten();
            if exited.is_some() {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        kill_group(&mut self.child);
        let how = match exited.map(|s| s.code()) {
            Some(Some(c)) => format!("; its process had exited {c}"),
            Some(None) => "; its process had been killed by a signal".into(),
            None => String::new(),
        };
        format!(
            "{why}{how} (a persistent process: its earlier answers stand, the next request \
             starts another){}",
            self.stderr.finish()
        )
    }
}

impl Drop for Worker {
    /// Its stdin closed (a model that reads to its end then exits), then its group killed.
    fn drop(&mut self) {
        self.stdin.take();
        for _ in 0..EXIT_POLLS {
            if matches!(self.child.try_wait(), Ok(Some(_))) {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        kill_group(&mut self.child);
    }
}

/// Reads `stdout` a line at a time, each within the limit set for the request it answers.
fn read_lines(stdout: std::process::ChildStdout, limit: &AtomicU64, send: &mpsc::Sender<Line>) {
    let mut r = BufReader::new(stdout);
    loop {
        let mut line = Vec::new();
        let closed = loop {
            let buf = match r.fill_buf() {
                Ok([]) => break Some("its stdout closed (the process ended)".to_string()),
                Ok(b) => b,
                Err(e) => break Some(format!("reading its stdout: {e}")),
            };
            let (take, done) = match buf.iter().position(|&b| b == b'\n') {
                Some(i) => (i + 1, true),
                None => (buf.len(), false),
            };
            line.extend_from_slice(&buf[..take]);
            r.consume(take);
            let max = limit.load(Ordering::Relaxed);
            if line.len() as u64 > max.saturating_add(1) {
                let _ = send.send(Line::TooLong(max));
                return;
            }
            if done {
                break None;
            }
        };
        if let Some(why) = closed {
            let _ = send.send(Line::Closed(why));
            return;
        }
        let text = String::from_utf8_lossy(&line).trim_end().to_string();
        if text.is_empty() {
            continue;
        }
        if send.send(Line::Text(text)).is_err() {
            return;
        }
    }
}

/// The controls inline: `time_s` and the four changes from trim, as columns.
fn controls_json(c: &ControlChanges) -> serde_json::Value {
    let mut o = serde_json::Map::new();
    o.insert("time_s".into(), serde_json::json!(c.table.time_s));
    for (name, col) in crate::inputs::controls::CONTROL_COLUMNS
        .iter()
        .zip(&c.table.changes)
    {
        o.insert((*name).into(), serde_json::json!(col));
    }
    serde_json::Value::Object(o)
}

/// An answer line that is not an answer to the request sent (not a JSON object, or another
/// `id`): the process's answers are out of step, so it is not used again.
struct Fatal(String);

/// What an answer must answer: what the request carried, in which protocol, of which model.
struct Asked<'a> {
    with: With<'a>,
    protocol: &'a str,
    model: String,
}

/// One answer line: its `id` checked, an `error` passed on, else the response the one-shot
/// parsers read (the line less its `id`).
fn parse_answer(
    text: &str,
    id: u64,
    compute: Compute,
    asked: &Asked<'_>,
) -> Result<Result<Answer, String>, Fatal> {
    let mut v: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        Fatal(format!(
            "its answer line is not JSON ({e}): `{}` (a persistent model writes nothing but \
             answers on its stdout)",
            crate::inputs::yaml::shorten(text, crate::inputs::yaml::EXCERPT_CHARS)
        ))
    })?;
    let Some(o) = v.as_object_mut() else {
        return Err(Fatal("its answer is not a JSON object".into()));
    };
    match o.remove("id").and_then(|i| i.as_u64()) {
        Some(got) if got == id => {}
        Some(got) => {
            return Err(Fatal(format!(
                "its answer has `id` {got} where the request's is {id} (answers come in order, \
                 one a request)"
            )));
        }
        None => {
            return Err(Fatal(format!(
                "its answer has no `id` (the request's is {id})"
            )));
        }
    }
    Ok(parse_response(v, text, compute, asked))
}

/// The response in an answer whose `id` was right.
fn parse_response(
    mut v: serde_json::Value,
    text: &str,
    compute: Compute,
    asked: &Asked<'_>,
) -> Result<Answer, String> {
    let (protocol, rows) = (asked.protocol, asked.with.rows());
    if let Some(e) = v.as_object_mut().and_then(|o| o.remove("error")) {
        return Err(format!(
            "it answered with an error: {}",
            crate::inputs::yaml::shorten(e.as_str().unwrap_or(&e.to_string()), 1000)
        ));
    }
    let rest = serde_json::to_string(&v).map_err(|e| e.to_string())?;
    if let Some((line, column, message)) = crate::inputs::yaml::json_underflow(text) {
        return Err(format!(
            "its answer at line {line} column {column}: {message}"
        ));
    }
    let parsed = match compute {
        Compute::Trim => parse_trim(&rest, protocol).map(|(q, s)| Answer::Trim(q, s)),
        Compute::LinearModel => parse_linear(&rest, protocol).map(|(m, s)| Answer::Linear(m, s)),
        Compute::Describe => parse_describe(&rest).map(Answer::Described),
        Compute::TimeHistory => parse_history_columns(&rest, protocol, rows).map(Answer::History),
        Compute::FrequencyResponse => {
            let frequencies = asked.with.frequencies_hz.unwrap_or(&[]);
            parse_frequency_response(&rest, protocol, frequencies, &asked.model)
                .map(|(r, s)| Answer::Responses(r, s))
        }
        Compute::Autorotation => parse_autorotation(&rest, protocol).map(Answer::Autorotated),
    };
    parsed.map_err(|e| format!("its answer {e}"))
}

/// A time history as columns: `time_s` and any responses of [`SIGNALS`], each `rows` long.
fn parse_history_columns(text: &str, protocol: &str, rows: usize) -> Result<Replayed, String> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Response {
        #[allow(dead_code)]
        protocol: String,
        time_history: std::collections::BTreeMap<String, Vec<f64>>,
    }
    let r: Response = super::command::parse_json(text, protocol)?;
    let mut time_s = None;
    let mut signals = vec![Vec::new(); SIGNALS.len()];
    for (name, column) in r.time_history {
        if column.len() != rows {
            return Err(format!(
                "`time_history.{name}` has {} rows; {rows} were asked for",
                column.len()
            ));
        }
        if column.iter().any(|x| !x.is_finite()) {
            return Err(format!(
                "`time_history.{name}` has a value that is not finite"
            ));
        }
        if name == "time_s" {
            time_s = Some(column);
        } else if let Some(i) = SIGNALS.iter().position(|s| *s == name) {
            signals[i] = column;
        } else {
            return Err(format!(
                "`time_history.{name}` is not `time_s` or a response cierva compares ({})",
                SIGNALS.join(", ")
            ));
        }
    }
    Ok(Replayed {
        time_s: time_s.ok_or("`time_history` has no `time_s`")?,
        signals,
    })
}
