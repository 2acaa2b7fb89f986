//! A fit's iterations through plans (`cierva fit --evaluate-with CMD`): each batch of the
//! fit's evaluations (the targets at a point; a Jacobian's steps together) is written as a plan
//! of its own, `DIR/batch-NNNN/`, one evaluation a condition and point; the command (an
//! engine's, which runs `cierva evaluate` on the shards) is run on it; and the fit reads the
//! results back ([`PlanBatches`], the fit module's [`crate::fit::BatchEvaluator`]).
//!
//! An evaluation asks the fit file's subject for the targets at one condition with the
//! parameters at one point, as [`crate::fit::evaluate_each_here`] does on this machine, so the
//! fit is the same bit for bit. A batch already complete in `DIR` (a fit run again after it
//! stopped) is read, not run again.

use super::{
    Evaluates, Evaluation, FORMAT, FitBatch, LoadedPlan, PlanError, PlanFile, PlannedCase,
    PlannedStudy, VERSION, absolute, complete, load, write_plan_file,
};
use crate::fit::file::FitFile;
use crate::fit::{ConditionStarts, Problem, Target, TargetCondition};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// What a fit's evaluations depend on, hashed (FNV-1a, 64 bits, hex): the fit file, the
/// aircraft or rotor file it fits, and every file it names by a `file:` or `case:` (the cases
/// its targets come from, the case whose model it fits), read relative to it. A change to a
/// simulation behind the protocol that leaves these files alone is not seen.
pub fn fingerprint(f: &FitFile) -> String {
    use crate::fit::FitSubject;
    let text = std::fs::read_to_string(&f.path).unwrap_or_default();
    let mut bytes = text.clone().into_bytes();
    let subject = match &f.problem.subject {
        FitSubject::Aircraft { file } => Some(file.path.clone()),
        FitSubject::Rotor { file, .. } => Some(file.path.clone()),
        FitSubject::Model { .. } => None,
    };
    let here = f.path.parent().unwrap_or(Path::new("."));
    let mut named: Vec<PathBuf> = Vec::new();
    if let Ok(value) = serde_yaml::from_str::<serde_yaml::Value>(&text) {
        named_files(&value, &mut named);
    }
    // Each file once, where the fit file names a case for its targets and its predictions.
    let mut files: Vec<PathBuf> = subject.into_iter().collect();
    for p in named.iter().map(|p| here.join(p)) {
        if !files.contains(&p) {
            files.push(p);
        }
    }
    for p in files {
        bytes.extend(std::fs::read(p).unwrap_or_default());
    }
    format!("{:016x}", crate::suite::review::fnv1a64(&bytes))
}

/// Every string under a `file` or `case` key of a YAML value, in order.
fn named_files(value: &serde_yaml::Value, out: &mut Vec<PathBuf>) {
    use serde_yaml::Value;
    match value {
        Value::Mapping(m) => {
            for (k, v) in m {
                if let (Some("file" | "case"), Value::String(p)) = (k.as_str(), v) {
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

/// A batch's evaluations checked against its fit file: each names targets it has, all at one
/// condition, and a value for each of its parameters; each its own group. The field at fault
/// (`evaluations[k]`) and why.
pub(super) fn check_evaluations(
    f: &FitFile,
    evaluations: &[Evaluation],
) -> Result<(), (String, String)> {
    check_each(f, evaluations).map_err(|(k, m)| (format!("evaluations[{k}]"), m))
}

fn check_each(f: &FitFile, evaluations: &[Evaluation]) -> Result<(), (usize, String)> {
    let all = all_targets(f);
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
        if values.len() != f.problem.parameters.len() {
            return Err((
                k,
                format!(
                    "{} values for the fit file's {} parameters",
                    values.len(),
                    f.problem.parameters.len()
                ),
            ));
        }
        let Some(first) = targets.first().and_then(|&t| all.get(t)) else {
            return Err((k, "names no target of the fit file".into()));
        };
        if let Some(t) = targets
            .iter()
            .find(|&&t| all.get(t).is_none_or(|x| x.condition != first.condition))
        {
            return Err((
                k,
                format!(
                    "target {t}: not a target of the fit file at this evaluation's condition ({} targets and predictions)",
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

/// One evaluation of a fit's batch: the fit file's targets at places `targets` (one condition)
/// with the parameters at `values`, the model's trims started from `start` where given, on
/// this machine: the values (NaN where a target has none), why each has none, or the error
/// that stopped them all; and where the model's answers ended.
pub(super) fn evaluate(
    f: &FitFile,
    targets: &[usize],
    values: &[f64],
    start: Option<&serde_json::Value>,
) -> (TargetsResult, Option<serde_json::Value>) {
    let all = all_targets(f);
    let mut problem = f.problem.clone();
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

/// A fit's evaluations sent through plans, a batch a plan: written to `dir/batch-NNNN/`, run by
/// `command` (its `{plan}` the batch's folder, `{shards}` the shards to run it in), read back.
pub struct PlanBatches {
    file: Box<FitFile>,
    /// The fit file's fingerprint when the fit started: every batch's.
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
    if !command.contains("{plan}") {
        return Err(format!(
            "--evaluate-with `{command}`: the command names the batch's plan folder as {{plan}} (for example `cierva evaluate {{plan}} --shard 1/1`, or `python3 examples/distributed/run_dask.py {{plan}} --shards {{shards}}`)"
        ));
    }
    if shards == 0 {
        return Err("--shards 0: give at least 1".into());
    }
    Ok(PlanBatches {
        file: Box::new(file.clone()),
        fingerprint: fingerprint(file),
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

    /// The places among the fit file's targets and predictions of `problem`'s targets (the
    /// fit's own, a cross-validation band's, the predictions).
    fn places(&self, problem: &Problem) -> Result<Vec<usize>, String> {
        let all = all_targets(&self.file);
        let same = problem.parameters.len() == self.file.problem.parameters.len()
            && (problem.parameters.iter())
                .zip(&self.file.problem.parameters)
                .all(|(a, b)| a.kind == b.kind);
        if !same {
            return Err("a fit through plans asks the fit file's parameters only".into());
        }
        (problem.targets.iter())
            .map(|t| {
                all.iter().position(|x| *x == t).ok_or_else(|| {
                    format!(
                        "a target at {} is not the fit file's: a fit through plans asks its file's targets only",
                        t.condition.label()
                    )
                })
            })
            .collect()
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
        let content = format!("{}{:?}", self.fingerprint, evaluations);
        let hash = crate::suite::review::fnv1a64(content.as_bytes());
        let dir = self
            .dir
            .join(format!("batch-{batch:04}-{:08x}", hash >> 32));
        let groups = evaluations.len();
        let file = PlanFile {
            format: FORMAT.into(),
            cierva_version: VERSION.into(),
            study: PlannedStudy::Fit(FitBatch { batch }),
            folder: absolute(Path::new(".")),
            corrections: Vec::new(),
            cases: vec![PlannedCase {
                path: self.file.path.clone(),
                id: self.file.id.clone(),
                fingerprint: self.fingerprint.clone(),
                inputs: (self.file.problem.parameters.iter())
                    .map(|p| p.kind.model_name())
                    .collect(),
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
                .map_err(|e| format!("cannot run `{command}`: {e}"))?;
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
        let places = match self.places(problem) {
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
        let (_, mut have) = match self.run(evaluations) {
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
