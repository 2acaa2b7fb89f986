//! A fit's or a retune's iterations through plans (`cierva fit --evaluate-with CMD`, `cierva
//! retune --evaluate-with CMD`): each batch of the fit's evaluations (the targets at a point; a
//! Jacobian's steps together) is written as a plan of its own, `DIR/batch-NNNN/`, one
//! evaluation a condition and point; the command (an engine's, which runs `cierva evaluate` on
//! the shards) is run on it; and the fit reads the results back ([`PlanBatches`], the fit
//! module's [`crate::fit::BatchEvaluator`]).
//!
//! An evaluation asks the subject for the targets at one condition with the parameters at one
//! point, as [`crate::fit::evaluate_each_here`] does on this machine, so the fit is the same bit
//! for bit. A fit's batch names its fit file, whose targets its evaluations name by place; a
//! retune's targets come from its records, so its batch holds them ([`RetuneBatch`]: each
//! response point, its condition and the records' other controls' transfers) beside the
//! aircraft file or the case it retunes. A batch already complete in `DIR` (a fit run again
//! after it stopped) is read, not run again.

use super::{
    Evaluates, Evaluation, FORMAT, FitBatch, LoadedPlan, PlanError, PlanFile, PlannedCase,
    PlannedStudy, VERSION, absolute, complete, load, write_plan_file,
};
use crate::fit::file::FitFile;
use crate::fit::{ConditionStarts, Problem, Target, TargetCondition};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// What a fit's evaluations depend on, hashed (FNV-1a, 64 bits, hex): the fit file, the
/// aircraft or rotor file it fits, and every file it names by a `file:` or `case:` (the cases
/// its targets come from, the case whose model it fits), read relative to it. A change to a
/// simulation behind the protocol that leaves these files alone is not seen.
pub fn fingerprint(f: &FitFile) -> String {
    use crate::fit::FitSubject;
    let subject = match &f.problem.subject {
        FitSubject::Aircraft { file } => Some(file.path.clone()),
        FitSubject::Rotor { file, .. } => Some(file.path.clone()),
        FitSubject::Model { .. } => None,
    };
    let bytes = file_and_named(&f.path, subject);
    format!("{:016x}", crate::suite::review::fnv1a64(&bytes))
}

/// What a retune's evaluations depend on, hashed (FNV-1a, 64 bits, hex): the aircraft file or
/// the case it retunes ([`file_fingerprint`]), and a model's declared parameters (their names,
/// nominal values and ranges, as its `describe` gives them). A change to a simulation behind
/// the protocol that leaves these alone is not seen.
pub fn retune_fingerprint(path: &Path, model: Option<&dyn crate::external::FlightModel>) -> String {
    let mut text = file_fingerprint(path);
    if let Some(model) = model {
        text += &format!("{:?}", model.parameters());
    }
    format!("{:016x}", crate::suite::review::fnv1a64(text.as_bytes()))
}

/// A file and every file it names by a `file`, `case` or `..._file` key (an aircraft's rotor
/// files), read relative to it, hashed (FNV-1a, 64 bits, hex).
pub fn file_fingerprint(path: &Path) -> String {
    let bytes = file_and_named(path, None);
    format!("{:016x}", crate::suite::review::fnv1a64(&bytes))
}

/// The bytes of the file at `path`, then of `first` where given, then of every file it names
/// (a `file`, `case` or `..._file` key, read relative to it), each file once.
fn file_and_named(path: &Path, first: Option<PathBuf>) -> Vec<u8> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let mut bytes = text.clone().into_bytes();
    let here = path.parent().unwrap_or(Path::new("."));
    let mut named: Vec<PathBuf> = Vec::new();
    if let Ok(value) = serde_yaml::from_str::<serde_yaml::Value>(&text) {
        named_files(&value, &mut named);
    }
    // Each file once (a fit file names a case for its targets and its predictions).
    let mut files: Vec<PathBuf> = first.into_iter().collect();
    for p in named.iter().map(|p| here.join(p)) {
        if !files.contains(&p) {
            files.push(p);
        }
    }
    for p in files {
        bytes.extend(std::fs::read(p).unwrap_or_default());
    }
    bytes
}

/// Every string under a `file`, `case` or `..._file` key of a YAML value, in order.
fn named_files(value: &serde_yaml::Value, out: &mut Vec<PathBuf>) {
    use serde_yaml::Value;
    match value {
        Value::Mapping(m) => {
            for (k, v) in m {
                let named = k
                    .as_str()
                    .is_some_and(|k| k == "file" || k == "case" || k.ends_with("_file"));
                if let (true, Value::String(p)) = (named, v) {
                    out.push(PathBuf::from(p));
                }
                named_files(v, out);
            }
        }
        Value::Sequence(items) => items.iter().for_each(|v| named_files(v, out)),
        _ => {}
    }
}

/// The fit file's targets and then its predictions: what a batch's evaluations name by place.
fn all_targets(f: &FitFile) -> Vec<&Target> {
    f.problem.targets.iter().chain(&f.predict).collect()
}

/// The fit file's problem with its targets and then its predictions as its targets, evaluated
/// on this machine: what a fit's batch's evaluations name by place.
pub(super) fn every_target(f: &FitFile) -> Problem {
    let mut problem = f.problem.clone();
    problem.targets = all_targets(f).into_iter().cloned().collect();
    problem.executor = crate::fit::Executor::Local;
    problem
}

/// A batch of a retune's evaluations: what it retunes (`cases[0]` of the plan), the parameters
/// by name, and the response points its evaluations name by place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RetuneBatch {
    /// The batch's number in the retune, from 1.
    pub batch: usize,
    pub retuned: RetunedFile,
    /// The parameters as `cierva retune --fit` names them, in the order of each evaluation's
    /// values.
    pub parameters: Vec<String>,
    pub targets: Vec<PlannedResponse>,
}

/// What a retune's batch retunes: cierva's aircraft file, or a case whose model is `external`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RetunedFile {
    Aircraft,
    Case,
}

/// One point of a frequency response a retune matches ([`crate::fit::Measure::Response`]), with
/// its condition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlannedResponse {
    pub airspeed_mph: f64,
    pub climb_m_s: f64,
    pub turn_rate_deg_s: f64,
    pub mass_kg: Option<f64>,
    pub density_altitude_ft: f64,
    pub input: String,
    pub output: String,
    pub frequency_hz: f64,
    pub imaginary: bool,
    /// The records' other controls' measured transfers from `input` at this frequency.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub others: Vec<OtherTransfer>,
}

/// A record's other control's measured transfer from a response's input at its frequency
/// ([`crate::fit::ResponsePoint::others`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OtherTransfer {
    pub control: String,
    pub re: f64,
    pub im: f64,
}

impl PlannedResponse {
    /// A retune's target as a batch holds it; `None` for a target that is not a response at a
    /// flight condition.
    fn of(t: &Target) -> Option<Self> {
        let (TargetCondition::Flight(c, l), crate::fit::Measure::Response(r)) =
            (&t.condition, &t.measure)
        else {
            return None;
        };
        Some(Self {
            airspeed_mph: c.airspeed_mph,
            climb_m_s: c.climb_m_s,
            turn_rate_deg_s: c.turn_rate_deg_s,
            mass_kg: l.mass_kg,
            density_altitude_ft: l.density_altitude_ft,
            input: r.input.clone(),
            output: r.output.clone(),
            frequency_hz: r.frequency_hz,
            imaginary: r.imaginary,
            others: (r.others.iter())
                .map(|(n, h)| OtherTransfer {
                    control: n.clone(),
                    re: h.re,
                    im: h.im,
                })
                .collect(),
        })
    }

    /// The target to evaluate (its reference and standard error are not the batch's: an
    /// evaluation gives the model's value only).
    fn target(&self) -> Target {
        let mut point = crate::fit::ResponsePoint::new(
            &self.input,
            &self.output,
            self.frequency_hz,
            self.imaginary,
        );
        point.others = (self.others.iter())
            .map(|o| {
                let h = rustfft::num_complex::Complex64::new(o.re, o.im);
                (o.control.clone(), h)
            })
            .collect();
        Target {
            condition: TargetCondition::Flight(
                crate::inputs::condition::TrimRequest {
                    airspeed_mph: self.airspeed_mph,
                    climb_m_s: self.climb_m_s,
                    turn_rate_deg_s: self.turn_rate_deg_s,
                },
                crate::inputs::condition::Loading {
                    mass_kg: self.mass_kg,
                    density_altitude_ft: self.density_altitude_ft,
                },
            ),
            measure: crate::fit::Measure::Response(point),
            reference: 0.0,
            standard_error: 1.0,
            bounds: None,
        }
    }
}

/// A retune's batch as a problem to evaluate on this machine: the aircraft file or the case at
/// `path` loaded, the parameters by name, the batch's targets. The field at fault and why.
pub(super) fn retune_problem(
    batch: &RetuneBatch,
    path: &Path,
) -> Result<Problem, (String, String)> {
    use crate::fit::{FitParameter, FitSubject, ParameterKind};
    let at = |field: &str| {
        let field = field.to_string();
        move |m: String| (field.clone(), m)
    };
    let subject = match batch.retuned {
        RetunedFile::Aircraft => FitSubject::Aircraft {
            file: Box::new(
                crate::inputs::aircraft::load(path)
                    .map_err(|e| e.render())
                    .map_err(at("cases[0]"))?,
            ),
        },
        RetunedFile::Case => {
            let case = crate::suite::case::load(path)
                .map_err(|e| e.render())
                .map_err(at("cases[0]"))?;
            let crate::checks::subject::Subject::External(e) = case.subject else {
                return Err(at("cases[0]")(format!(
                    "{}: a retune's case has an `external` model",
                    path.display()
                )));
            };
            FitSubject::Model { model: e.model }
        }
    };
    let parameters = (batch.parameters.iter().enumerate())
        .map(|(k, name)| {
            let kind = match batch.retuned {
                RetunedFile::Aircraft => ParameterKind::parse(name).ok_or_else(|| {
                    at(&format!("study.retune.parameters[{k}]"))(format!(
                        "`{name}` is not a correction or parameter"
                    ))
                })?,
                RetunedFile::Case => ParameterKind::Declared(name.clone()),
            };
            Ok(FitParameter {
                kind,
                lower: f64::NEG_INFINITY,
                upper: f64::INFINITY,
                start: 0.0,
                regularisation: 0.0,
            })
        })
        .collect::<Result<Vec<_>, (String, String)>>()?;
    Ok(Problem {
        subject,
        parameters,
        targets: batch.targets.iter().map(PlannedResponse::target).collect(),
        options: crate::fit::FitOptions::default(),
        executor: crate::fit::Executor::Local,
    })
}

/// A batch's evaluations checked against its problem (every target a batch may name, in
/// order): each names targets it has, all at one condition, and a value for each of its
/// parameters; each its own group. The field at fault (`evaluations[k]`) and why.
pub(super) fn check_evaluations(
    problem: &Problem,
    evaluations: &[Evaluation],
) -> Result<(), (String, String)> {
    check_each(problem, evaluations).map_err(|(k, m)| (format!("evaluations[{k}]"), m))
}

fn check_each(problem: &Problem, evaluations: &[Evaluation]) -> Result<(), (usize, String)> {
    let all = &problem.targets;
    for (k, e) in evaluations.iter().enumerate() {
        let Evaluates::Targets {
            targets, values, ..
        } = &e.what
        else {
            return Err((k, "a fit's batch holds targets' evaluations only".into()));
        };
        if e.index != k || e.group != k || e.case != 0 {
            return Err((
                k,
                "its index, group and case are its place, its place and 0".into(),
            ));
        }
        if values.len() != problem.parameters.len() {
            return Err((
                k,
                format!(
                    "{} values for the {} parameters",
                    values.len(),
                    problem.parameters.len()
                ),
            ));
        }
        let Some(first) = targets.first().and_then(|&t| all.get(t)) else {
            return Err((k, "names no target of the batch".into()));
        };
        if let Some(t) = targets
            .iter()
            .find(|&&t| all.get(t).is_none_or(|x| x.condition != first.condition))
        {
            return Err((
                k,
                format!(
                    "target {t}: not a target at this evaluation's condition (the batch has {})",
                    all.len()
                ),
            ));
        }
    }
    Ok(())
}

/// A fit's evaluation as a results file holds it: the targets' values (NaN where a target has
/// none), why each has none, or the error that stopped them all.
type TargetsResult = (
    Option<Vec<f64>>,
    Option<Vec<Option<String>>>,
    Option<String>,
);

/// One evaluation of a fit's or a retune's batch: `problem`'s targets at places `targets` (one
/// condition) with the parameters at `values`, the model's trims started from `start` where
/// given, on this machine: the values (NaN where a target has none), why each has none, or the
/// error that stopped them all; and where the model's answers ended.
pub(super) fn evaluate(
    problem: &Problem,
    targets: &[usize],
    values: &[f64],
    start: Option<&serde_json::Value>,
) -> (TargetsResult, Option<serde_json::Value>) {
    let all = &problem.targets;
    let mut problem = problem.clone();
    problem.targets = targets.iter().map(|&t| all[t].clone()).collect();
    let from = match (start, problem.targets.first()) {
        (Some(s), Some(t)) => ConditionStarts(vec![(
            t.condition,
            crate::external::Start(std::sync::Arc::new(s.clone())),
        )]),
        _ => ConditionStarts::default(),
    };
    match crate::fit::evaluate_each_here_from(&problem, values, &from) {
        Ok((each, ended)) => (
            (
                Some(
                    each.iter()
                        .map(|r| *r.as_ref().unwrap_or(&f64::NAN))
                        .collect(),
                ),
                Some(each.into_iter().map(Result::err).collect()),
                None,
            ),
            ended.0.into_iter().next().map(|(_, s)| (*s.0).clone()),
        ),
        Err(e) => ((None, None, Some(e)), None),
    }
}

/// What a batch's evaluations ask: a fit file's targets, by place; or a retune's, which the
/// batch holds.
enum Source {
    Fit(Box<FitFile>),
    Retune {
        /// The aircraft file or the case, as given.
        path: PathBuf,
        id: String,
        retuned: RetunedFile,
    },
}

/// A fit's evaluations sent through plans, a batch a plan: written to `dir/batch-NNNN/`, run by
/// `command` (its `{plan}` the batch's folder, `{shards}` the shards to run it in), read back.
pub struct PlanBatches {
    source: Source,
    /// The fit file's (or the retuned file's) fingerprint when the fit started: every batch's.
    fingerprint: String,
    dir: PathBuf,
    command: String,
    shards: usize,
    batches: AtomicUsize,
    /// The first batch the engine left without results, and why: the fit's result is then not
    /// the one-machine fit's, and no batch after it is sent.
    failed: std::sync::Mutex<Option<String>>,
}

/// Why a fit cannot be sent through plans (a located message for the command line).
pub fn batches(
    file: &FitFile,
    dir: &Path,
    command: &str,
    shards: usize,
) -> Result<PlanBatches, String> {
    through(
        Source::Fit(Box::new(file.clone())),
        fingerprint(file),
        dir,
        command,
        shards,
    )
}

/// A retune's evaluations sent through plans (`cierva retune --evaluate-with`): of cierva's
/// aircraft file, or of the model of the case (`external`), at `path` as given, `id` its id.
pub fn retune_batches(
    (retuned, path, id): (crate::fit::retune::subject::Retuned<'_>, &Path, &str),
    dir: &Path,
    command: &str,
    shards: usize,
) -> Result<PlanBatches, String> {
    use crate::fit::retune::subject::Retuned;
    let source = Source::Retune {
        path: path.to_path_buf(),
        id: id.to_string(),
        retuned: match retuned {
            Retuned::Aircraft(_) => RetunedFile::Aircraft,
            Retuned::Model(_) => RetunedFile::Case,
        },
    };
    let model = match retuned {
        Retuned::Aircraft(_) => None,
        Retuned::Model(e) => Some(e.model.as_ref() as &dyn crate::external::FlightModel),
    };
    let fingerprint = retune_fingerprint(path, model);
    through(source, fingerprint, dir, command, shards)
}

/// Batches through plans of `source`, the command checked.
fn through(
    source: Source,
    fingerprint: String,
    dir: &Path,
    command: &str,
    shards: usize,
) -> Result<PlanBatches, String> {
    if !command.contains("{plan}") {
        return Err(format!(
            "--evaluate-with `{command}`: the command names the batch's plan folder as {{plan}} (for example `cierva evaluate {{plan}} --shard 1/1`, or `python3 examples/distributed/run_dask.py {{plan}} --shards {{shards}}`)"
        ));
    }
    if shards == 0 {
        return Err("--shards 0: give at least 1".into());
    }
    Ok(PlanBatches {
        source,
        fingerprint,
        dir: absolute(dir),
        command: command.to_string(),
        shards,
        batches: AtomicUsize::new(0),
        failed: std::sync::Mutex::new(None),
    })
}

impl PlanBatches {
    /// Why the engine left a batch without results, if it did: the fit that ran is not the
    /// one-machine fit, and its result must not be used (`cierva fit` exits 1 and writes
    /// nothing).
    pub fn failure(&self) -> Option<String> {
        self.failed.lock().map_or(None, |f| f.clone())
    }

    /// The places of `problem`'s targets among those the batch's evaluations name: among the
    /// fit file's targets and predictions (the fit's own, a cross-validation band's, the
    /// predictions); a retune's own, in order, with the targets its batch holds.
    fn places(
        &self,
        problem: &Problem,
    ) -> Result<(Vec<usize>, Option<Vec<PlannedResponse>>), String> {
        let file = match &self.source {
            Source::Fit(file) => file,
            Source::Retune { .. } => {
                let planned = (problem.targets.iter())
                    .map(|t| {
                        PlannedResponse::of(t).ok_or_else(|| {
                            format!(
                                "`{}` at {}: a retune through plans asks frequency responses at flight conditions only",
                                t.measure.name(),
                                t.condition.label()
                            )
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                return Ok(((0..planned.len()).collect(), Some(planned)));
            }
        };
        let all = all_targets(file);
        let same = problem.parameters.len() == file.problem.parameters.len()
            && (problem.parameters.iter())
                .zip(&file.problem.parameters)
                .all(|(a, b)| a.kind == b.kind);
        if !same {
            return Err("a fit through plans asks the fit file's parameters only".into());
        }
        let places = (problem.targets.iter())
            .map(|t| {
                all.iter().position(|x| *x == t).ok_or_else(|| {
                    format!(
                        "a target at {} is not the fit file's: a fit through plans asks its file's targets only",
                        t.condition.label()
                    )
                })
            })
            .collect::<Result<_, _>>()?;
        Ok((places, None))
    }

    /// Records the first batch the engine failed (see [`Self::failure`]), and gives its message.
    fn fail(&self, m: String) -> String {
        if let Ok(mut f) = self.failed.lock() {
            f.get_or_insert_with(|| m.clone());
        }
        m
    }

    /// Writes the batch's plan, runs the command on it, and reads its results: each
    /// evaluation's, by its place.
    fn run(
        &self,
        evaluations: Vec<Evaluation>,
        (parameters, targets): (&[crate::fit::FitParameter], Option<Vec<PlannedResponse>>),
    ) -> Result<
        (
            LoadedPlan,
            std::collections::BTreeMap<usize, super::EvaluationResult>,
        ),
        String,
    > {
        if let Some(f) = self.failure() {
            return Err(f);
        }
        let batch = self.batches.fetch_add(1, Ordering::SeqCst) + 1;
        // Named by its number and what it evaluates: the same fit run again finds its batches
        // where they were, and a fit that went another way (other values, another fit file)
        // never meets another's plan.
        let names: Vec<&str> = parameters.iter().map(|p| p.kind.name()).collect();
        let content = format!(
            "{}{:?}{:?}{names:?}",
            self.fingerprint, evaluations, targets
        );
        let hash = crate::suite::review::fnv1a64(content.as_bytes());
        let dir = self
            .dir
            .join(format!("batch-{batch:04}-{:08x}", hash >> 32));
        let groups = evaluations.len();
        let (study, path, id) = match (&self.source, targets) {
            (Source::Fit(file), _) => (
                PlannedStudy::Fit(FitBatch { batch }),
                file.path.clone(),
                file.id.clone(),
            ),
            (Source::Retune { path, id, retuned }, targets) => (
                PlannedStudy::Retune(RetuneBatch {
                    batch,
                    retuned: *retuned,
                    parameters: parameters
                        .iter()
                        .map(|p| p.kind.name().to_string())
                        .collect(),
                    targets: targets.unwrap_or_default(),
                }),
                path.clone(),
                id.clone(),
            ),
        };
        let file = PlanFile {
            format: FORMAT.into(),
            cierva_version: VERSION.into(),
            study,
            folder: absolute(Path::new(".")),
            corrections: Vec::new(),
            cases: vec![PlannedCase {
                path,
                id,
                fingerprint: self.fingerprint.clone(),
                inputs: parameters.iter().map(|p| p.kind.model_name()).collect(),
            }],
            groups,
            evaluations,
        };
        let message = |e: PlanError| match e {
            PlanError::Input(m) | PlanError::Incomplete(m) => m,
        };
        write_plan_file(&dir, file).map_err(|e| self.fail(message(e)))?;
        let plan = load(&dir).map_err(|e| self.fail(message(e)))?;
        // A batch already complete (the fit run again after it stopped) is read as it is.
        if complete(&plan).is_err() {
            let shards = self.shards.min(groups).max(1);
            // The folder quoted for the shell (a working folder with a space in it).
            let quoted = format!("'{}'", dir.display().to_string().replace('\'', "'\\''"));
            let command = self
                .command
                .replace("{plan}", &quoted)
                .replace("{shards}", &shards.to_string());
            // The command's output goes to stderr: stdout is the fit's (its JSON).
            let status = std::process::Command::new("sh")
                .arg("-c")
                .arg(&command)
                .stdout(std::io::stderr())
                .status()
                .map_err(|e| self.fail(format!("cannot run `{command}`: {e}")))?;
            if !status.success() {
                // What it finished is read; what it did not is named below.
                eprintln!("note: `{command}` exited with {status}");
            }
        }
        let have = complete(&plan).map_err(|e| {
            let m = match e {
                PlanError::Incomplete(m) => format!(
                    "batch {batch} of the fit ({}): {m} (the command ran no shard or not all: run the fit again with the same --plans to go on from the batches done)",
                    dir.display()
                ),
                PlanError::Input(m) => m,
            };
            self.fail(m)
        })?;
        Ok((plan, have))
    }
}

impl crate::fit::BatchEvaluator for PlanBatches {
    fn evaluate_batch(
        &self,
        problem: &Problem,
        points: &[Vec<f64>],
        from: &ConditionStarts,
    ) -> Vec<Result<crate::fit::PointEvaluation, String>> {
        let failed = |e: String| (0..points.len()).map(|_| Err(e.clone())).collect();
        let (places, planned) = match self.places(problem) {
            Ok(p) => p,
            Err(e) => return failed(e),
        };
        let mut conditions: Vec<TargetCondition> = Vec::new();
        for t in &problem.targets {
            if !conditions.contains(&t.condition) {
                conditions.push(t.condition);
            }
        }
        // One evaluation a point and condition: the point's targets there, in their order.
        let mut evaluations = Vec::new();
        let mut index: Vec<Vec<usize>> = Vec::new();
        for p in points {
            let mut mine = Vec::new();
            for c in &conditions {
                let targets: Vec<usize> = (problem.targets.iter().zip(&places))
                    .filter(|(t, _)| t.condition == *c)
                    .map(|(_, &k)| k)
                    .collect();
                mine.push(evaluations.len());
                let k = evaluations.len();
                evaluations.push(Evaluation {
                    index: k,
                    case: 0,
                    group: k,
                    what: Evaluates::Targets {
                        targets,
                        values: p.clone(),
                        start: from.at(c).map(|s| (*s.0).clone()),
                    },
                });
            }
            index.push(mine);
        }
        let (_, mut have) = match self.run(evaluations, (&problem.parameters, planned)) {
            Ok(x) => x,
            Err(e) => return failed(e),
        };
        let mut out = Vec::new();
        for mine in index {
            // Each condition's results, as the fit's targets come.
            let mut at: Vec<std::vec::IntoIter<Result<f64, String>>> = Vec::new();
            let mut stopped = None;
            let mut ended = ConditionStarts::default();
            for (k, c) in mine.into_iter().zip(&conditions) {
                let r = have.remove(&k).expect("a complete batch");
                if let Some(s) = r.start {
                    ended
                        .0
                        .push((*c, crate::external::Start(std::sync::Arc::new(s))));
                }
                match (r.values, r.errors, r.error) {
                    (Some(v), errors, None) => {
                        let errors = errors.unwrap_or_else(|| vec![None; v.len()]);
                        let each: Vec<Result<f64, String>> = (v.into_iter().zip(errors))
                            .map(|(v, e)| e.map_or(Ok(v), Err))
                            .collect();
                        at.push(each.into_iter());
                    }
                    (_, _, error) => {
                        stopped.get_or_insert(error.unwrap_or_default());
                        at.push(Vec::new().into_iter());
                    }
                }
            }
            if let Some(e) = stopped {
                out.push(Err(e));
                continue;
            }
            let each = (problem.targets.iter())
                .map(|t| {
                    let c = conditions.iter().position(|c| *c == t.condition);
                    c.and_then(|c| at[c].next())
                        .unwrap_or_else(|| Err("no result for the target".into()))
                })
                .collect();
            out.push(Ok((each, ended)));
        }
        out
    }

    fn describe(&self) -> String {
        format!(
            "plans in {} run by `{}` in up to {} shards",
            self.dir.display(),
            self.command,
            self.shards
        )
    }
}
