//! A study as a plan of independent evaluations, for models too slow for one machine
//! (`cierva uncertainty --plan`, `cierva evaluate`, `cierva uncertainty --from-plan`).
//!
//! - [`write()`] writes every evaluation a study needs to `DIR/plan.yaml` ([`PlanFile`]): each
//!   case's nominal run, its grid study's refined cases and its propagation's points, each
//!   point with the parameter values its model is asked with (the model interface's request:
//!   the case's conditions and loadings, these values). Evaluations that share a model's
//!   answers (a row of `A` and the `A_B^(i)` points that start from it) form a group, the unit
//!   a shard takes.
//! - [`evaluate`] runs shard `I` of `N` (an `N`th of the groups, dealt by [`shard_of`]) and writes its results to
//!   `DIR/results/shard-I-of-N.yaml` at once (written to a temporary file and renamed), each
//!   evaluation first to a file of its own under `DIR/results/shard-I-of-N/`: a killed shard
//!   loses only the evaluation it was running, and a rerun takes up where it stopped; a shard
//!   already done is skipped.
//! - [`finish`] reads the results and finishes each case's study with the same code as the
//!   one-machine run ([`crate::uncertainty::jobs::CaseJobs::finish`]): the same numbers, bit
//!   for bit. A missing shard is named, and no study is finished without every evaluation.
//!
//! A plan is checked before it is used: its format and the cierva version that wrote it, and
//! each case's fingerprint (its file, its aircraft or rotor file, the corrections files and
//! the inputs its model declares), so that results are never merged into a study of other
//! cases. Any engine runs the shards: `cierva evaluate` is a command (docs/scaling.md).

use crate::fit::sensitivity::{BoundedQuantity, SensitivityJobs, Study};
use crate::inputs::yaml::InputError;
use crate::suite::case::Case;
use crate::suite::outcome::CheckResult;
use crate::uncertainty::jobs::{CaseJobs, Runs};
use crate::uncertainty::propagate::{CaseUncertainty, Propagation, PropagationSettings};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub mod fit;

/// The plan's format, in `plan.yaml` and every results file.
pub const FORMAT: &str = "cierva-plan/2";

/// The cierva version that writes a plan, which only the same version evaluates and finishes:
/// another version may evaluate the same point differently.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The largest plan or results file read (1 GiB): a plan of 43,000 points of 40 inputs is
/// about 100 MB.
pub const MAX_PLAN_FILE_BYTES: u64 = 1 << 30;

/// `DIR/plan.yaml`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanFile {
    pub format: String,
    pub cierva_version: String,
    /// The study and its settings, as the command was given them.
    pub study: PlannedStudy,
    /// The folder the plan was written from (absolute): the case and corrections paths are as
    /// they were given there, and `cierva evaluate` and `--from-plan` work from it, so that
    /// every path a result names reads as in the one-machine run.
    pub folder: PathBuf,
    /// The corrections files applied to every case.
    pub corrections: Vec<PathBuf>,
    pub cases: Vec<PlannedCase>,
    /// Groups of evaluations, numbered from 0: shard `I` of `N` takes those [`shard_of`] deals
    /// it.
    pub groups: usize,
    pub evaluations: Vec<Evaluation>,
}

/// The study a plan is of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PlannedStudy {
    /// `cierva uncertainty`'s, of every case.
    Uncertainty(StudySettings),
    /// `cierva sensitivity --case`'s, of the one case's model at one of its conditions.
    Sensitivity(SensitivitySettings),
    /// A batch of `cierva fit --evaluate-with`'s evaluations (the fit file in `cases`): the
    /// targets at a point, or a Jacobian's steps ([`fit`]).
    Fit(FitBatch),
    /// A batch of `cierva retune --evaluate-with`'s evaluations (the aircraft file or the case
    /// retuned in `cases`): the batch's response points at a point, or a Jacobian's steps
    /// ([`fit`]).
    Retune(fit::RetuneBatch),
}

/// Which batch of a fit a plan is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitBatch {
    /// The batch's number in the fit, from 1.
    pub batch: usize,
}

/// What a sensitivity study was asked for (as `cierva sensitivity --case` takes it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensitivitySettings {
    pub airspeed_mph: Option<f64>,
    /// The parameters moved (none: the model's default, those it gives a range).
    pub parameters: Vec<String>,
    /// The quantities differentiated (none: the case's).
    pub quantities: Vec<String>,
}

/// What an uncertainty study was asked for.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySettings {
    pub samples: usize,
    pub seed: u32,
    pub method: Propagation,
    pub validation_only: bool,
}

impl StudySettings {
    fn propagation(self) -> PropagationSettings {
        PropagationSettings {
            samples: self.samples,
            seed: self.seed,
            validation_only: self.validation_only,
            method: self.method,
        }
    }
}

/// A case of the plan: where it is, what it was, and what its study evaluates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlannedCase {
    /// The case file, as given (relative to the plan's `folder`).
    pub path: PathBuf,
    pub id: String,
    /// FNV-1a (64 bits, hex) of what the study depends on ([`fingerprint`]).
    pub fingerprint: String,
    /// The uncertain inputs, in the order of each point's `values`.
    pub inputs: Vec<String>,
}

/// One evaluation: a case's nominal run, a refined case of its grid study, or a point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Evaluation {
    /// Its place in the plan, from 0.
    pub index: usize,
    /// Its case's place in `cases`.
    pub case: usize,
    pub group: usize,
    pub what: Evaluates,
}

/// What an evaluation runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Evaluates {
    /// Every check of the case with its model's nominal parameters.
    Nominal,
    /// Every check with the model refined ([`crate::uncertainty::numerics`]): the `level`-th
    /// refined case of the grid study, in its order.
    Refined { level: usize, model: String },
    /// One request of a sensitivity study (the `request`-th: the nominal one, then each
    /// parameter down and up), the model asked its trim (and linear model) at the case's
    /// condition and loading with `parameters`.
    Request {
        request: usize,
        parameters: BTreeMap<String, f64>,
    },
    /// A fit's targets at one condition (`targets`: their places among the fit file's targets
    /// and then its predictions), the parameters at `values` (the fit file's order): what
    /// [`crate::fit::evaluate_each`] gives for them.
    Targets {
        targets: Vec<usize>,
        values: Vec<f64>,
        /// Where the model's trims start (the fit's iterate's answers' end there:
        /// [`crate::external::Start`]), where the fit gives one.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        start: Option<serde_json::Value>,
    },
    /// Every check with the inputs at `values` (the case's `inputs`' order): the model asked
    /// with `parameters` (what the values set, by the model's parameter names), started from
    /// point `start`'s answers where it can.
    Point {
        point: usize,
        values: Vec<f64>,
        parameters: BTreeMap<String, f64>,
        start: Option<usize>,
        tag: String,
    },
}

/// One evaluation's results: every check's, or why the case could not be made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvaluationResult {
    pub evaluation: usize,
    /// Its wall time, s.
    pub seconds: f64,
    /// Every check's results (the nominal run, a refined case).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub results: Option<Vec<CheckResult>>,
    /// What an uncertainty study reads of every check's results at a point.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checks: Option<Vec<crate::uncertainty::propagate::CheckValues>>,
    /// The quantities' values (a sensitivity study's request), or the targets' (a fit's
    /// batch: NaN where `errors` gives why not).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<f64>>,
    /// A fit's batch: why each target has no value (`None` where it has one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub errors: Option<Vec<Option<String>>>,
    pub error: Option<String>,
    /// A fit's batch: where the model's answers ended ([`crate::external::Start`]), where it
    /// says.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<serde_json::Value>,
}

/// A results file: one evaluation's (under `results/shard-I-of-N/`) or a whole shard's
/// (`results/shard-I-of-N.yaml`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResultsFile {
    pub format: String,
    /// The plan's id ([`plan_id`]).
    pub plan: String,
    pub shard: usize,
    pub of: usize,
    pub evaluations: Vec<EvaluationResult>,
}

/// Why a plan could not be written, run or finished: bad input (exit 2; located where a file
/// is at fault), or a study not yet complete (a missing shard, named; exit 1).
#[derive(Debug, Clone, PartialEq)]
pub enum PlanError {
    Input(String),
    Incomplete(String),
}

impl From<InputError> for PlanError {
    /// The file's error with its location and excerpt (without the `error: ` the command line
    /// puts before every message).
    fn from(e: InputError) -> Self {
        let text = e.render();
        Self::Input(text.strip_prefix("error: ").unwrap_or(&text).to_string())
    }
}

/// A plan read back and checked: the file, its id, and each case's uncertainty study, or the
/// case and the requests of its sensitivity study.
pub struct LoadedPlan {
    pub dir: PathBuf,
    pub file: PlanFile,
    pub id: String,
    pub studies: Vec<CaseJobs>,
    pub sensitivity: Option<(Case, SensitivityJobs)>,
    /// A fit's or a retune's batch: the problem whose targets its evaluations name by place
    /// (a fit file's targets and then its predictions; a retune's batch's response points).
    pub fit: Option<Box<crate::fit::Problem>>,
}

impl From<PropagationSettings> for StudySettings {
    fn from(s: PropagationSettings) -> Self {
        Self {
            samples: s.samples,
            seed: s.seed,
            method: s.method,
            validation_only: s.validation_only,
        }
    }
}

/// What a plan just written in `dir` holds and what to run next: its shards, then `cierva
/// <finish> --from-plan DIR` (`uncertainty`, `validate --uncertainty`).
pub fn next_steps(dir: &Path, file: &PlanFile, finish: &str) -> String {
    let d = dir.display();
    format!(
        "wrote {}: {} of {} in {} (a group shares a model's answers: the unit a shard takes)\nnext: `cierva evaluate {d} --shard I/N` for I = 1 to N, N at most {} (one command a worker: a Slurm job array, Dask; docs/scaling.md), then `cierva {finish} --from-plan {d}`",
        plan_path(dir).display(),
        counted(file.evaluations.len(), "evaluation", "evaluations"),
        counted(file.cases.len(), "case", "cases"),
        counted(file.groups, "group", "groups"),
        file.groups
    )
}

/// `n` and the noun, singular for one.
fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The path of the plan in `dir`.
pub fn plan_path(dir: &Path) -> PathBuf {
    dir.join("plan.yaml")
}

/// A plan's id: FNV-1a (64 bits, hex) of its file's text.
pub fn plan_id(text: &str) -> String {
    format!("{:016x}", crate::suite::review::fnv1a64(text.as_bytes()))
}

/// What a case's study depends on, hashed (FNV-1a, 64 bits, hex): the case file, its aircraft
/// or rotor file, the corrections files and each uncertain input (name, nominal value and
/// distribution). A change to a simulation behind the protocol that leaves its declared
/// parameters alone is not seen.
pub fn fingerprint(case: &Case, corrections: &[PathBuf], inputs: &str) -> String {
    use crate::checks::subject::Subject;
    let mut bytes = std::fs::read(&case.path).unwrap_or_default();
    let file = match &case.subject {
        Subject::Aircraft { file, .. } => Some(file.path.clone()),
        Subject::Rotor { file, .. } => Some(file.path.clone()),
        _ => None,
    };
    for p in file.iter().chain(corrections) {
        bytes.extend(std::fs::read(p).unwrap_or_default());
    }
    bytes.extend(inputs.bytes());
    format!("{:016x}", crate::suite::review::fnv1a64(&bytes))
}

/// An uncertainty study's inputs as its fingerprint reads them: each name, nominal value and
/// distribution.
fn inputs_text(jobs: &CaseJobs) -> String {
    (jobs.inputs.iter())
        .map(|i| format!("{}={:?};{:?}", i.name, i.nominal, i.distribution))
        .collect()
}

/// A sensitivity study's moved parameters as its fingerprint reads them (name, value, step,
/// range), and its quantities.
fn requests_text(jobs: &SensitivityJobs) -> String {
    format!(
        "{:?}{:?}{:?}",
        jobs.moved, jobs.quantities, jobs.requests[0]
    )
}

/// The plan of every case's study (`cases`: each case as loaded from its path, with the
/// corrections applied), written to `dir/plan.yaml`. A folder that holds another plan is
/// refused (its results would be mixed); the same plan again is left as it is.
pub fn write(
    dir: &Path,
    cases: &[Case],
    corrections: &[PathBuf],
    study: StudySettings,
) -> Result<PlanFile, PlanError> {
    let corrections = corrections.to_vec();
    let mut planned = Vec::new();
    let mut studies = Vec::new();
    for case in cases {
        let jobs = CaseJobs::of(case, study.propagation())
            .map_err(|e| PlanError::Input(format!("{}: {e}", case.path.display())))?;
        planned.push(PlannedCase {
            path: case.path.clone(),
            id: case.id.clone(),
            fingerprint: fingerprint(case, &corrections, &inputs_text(&jobs)),
            inputs: jobs.inputs.iter().map(|i| i.name.clone()).collect(),
        });
        studies.push(jobs);
    }
    let (evaluations, groups) = planned_evaluations(&studies);
    let file = PlanFile {
        format: FORMAT.into(),
        cierva_version: VERSION.into(),
        study: PlannedStudy::Uncertainty(study),
        folder: absolute(Path::new(".")),
        corrections,
        cases: planned,
        groups,
        evaluations,
    };
    write_plan_file(dir, file)
}

/// The plan of a sensitivity study of `case`'s model (see [`crate::fit::sensitivity`]): each
/// request its own group.
pub fn write_sensitivity(
    dir: &Path,
    case: &Case,
    settings: SensitivitySettings,
) -> Result<PlanFile, PlanError> {
    let jobs = sensitivity_jobs(case, &settings).map_err(PlanError::Input)?;
    let (evaluations, groups) = sensitivity_evaluations(&jobs);
    let file = PlanFile {
        format: FORMAT.into(),
        cierva_version: VERSION.into(),
        study: PlannedStudy::Sensitivity(settings),
        folder: absolute(Path::new(".")),
        corrections: Vec::new(),
        cases: vec![PlannedCase {
            path: case.path.clone(),
            id: case.id.clone(),
            fingerprint: fingerprint(case, &[], &requests_text(&jobs)),
            inputs: jobs.moved.iter().map(|p| p.name.clone()).collect(),
        }],
        groups,
        evaluations,
    };
    write_plan_file(dir, file)
}

/// A sensitivity study's requests of `case`'s model, as `cierva sensitivity --case` makes
/// them: the case's condition (`airspeed_mph` picks one), its quantities (or those named),
/// the parameters named (or the model's default).
pub fn sensitivity_jobs(case: &Case, s: &SensitivitySettings) -> Result<SensitivityJobs, String> {
    use crate::fit::sensitivity;
    let (loading, request, bounded) = sensitivity::from_case(case, s.airspeed_mph)?;
    let (model, _) =
        crate::checks::flight_model(&case.subject).expect("from_case took a flight model");
    let quantities: Vec<BoundedQuantity> = if s.quantities.is_empty() {
        bounded
    } else {
        (s.quantities.iter())
            .map(|n| {
                (bounded.iter().find(|q| &q.name == n).cloned()).unwrap_or(BoundedQuantity {
                    name: n.clone(),
                    bound: None,
                })
            })
            .collect()
    };
    let parameters = if s.parameters.is_empty() {
        sensitivity::default_parameters(&model.parameters()?)
    } else {
        s.parameters.clone()
    };
    if parameters.is_empty() {
        return Err(format!(
            "{} declares no parameters to move (an external model declares them in its `describe` response, protocol `cierva-external/2`)",
            model.describe()
        ));
    }
    sensitivity::jobs(model.as_ref(), request, loading, &parameters, &quantities)
}

/// A sensitivity study's requests that are asked, in order (a moved parameter at its own value
/// is not asked again).
fn requests_of(jobs: &SensitivityJobs) -> Vec<Evaluates> {
    (0..jobs.requests.len())
        .filter(|&k| jobs.asked(k))
        .map(|k| Evaluates::Request {
            request: k,
            parameters: jobs.requests[k].parameters.clone(),
        })
        .collect()
}

/// Writes a plan file to `dir/plan.yaml`: refused where another plan is there, left as it is
/// where the same one is.
fn write_plan_file(dir: &Path, file: PlanFile) -> Result<PlanFile, PlanError> {
    let text = serde_yaml::to_string(&file).map_err(|e| PlanError::Input(e.to_string()))?;
    let path = plan_path(dir);
    if let Ok(old) = std::fs::read_to_string(&path) {
        if old == text {
            return Ok(file);
        }
        return Err(PlanError::Input(format!(
            "{} holds another plan: give a new folder, or remove it and its results first",
            path.display()
        )));
    }
    write_atomically(&path, &text)?;
    Ok(file)
}

/// Every case's study's evaluations, numbered, each case's groups after the one before's, and
/// how many groups there are.
fn planned_evaluations(studies: &[CaseJobs]) -> (Vec<Evaluation>, usize) {
    let mut evaluations = Vec::new();
    let mut groups = 0;
    for (c, jobs) in studies.iter().enumerate() {
        for (what, group) in evaluations_of(jobs) {
            evaluations.push(Evaluation {
                index: evaluations.len(),
                case: c,
                group: groups + group,
                what,
            });
        }
        groups = evaluations.last().map_or(groups, |e| e.group + 1);
    }
    (evaluations, groups)
}

/// A sensitivity study's evaluations: each request asked, its own group.
fn sensitivity_evaluations(jobs: &SensitivityJobs) -> (Vec<Evaluation>, usize) {
    let evaluations: Vec<Evaluation> = (requests_of(jobs).into_iter().enumerate())
        .map(|(index, what)| Evaluation {
            index,
            case: 0,
            group: index,
            what,
        })
        .collect();
    let groups = evaluations.len();
    (evaluations, groups)
}

/// A case study's evaluations in plan order, each with its group (from 0 within the case):
/// the nominal run, each refined case, then the points, a start with the points that start
/// from it (in their order), each other point alone.
fn evaluations_of(jobs: &CaseJobs) -> Vec<(Evaluates, usize)> {
    let mut out = vec![(Evaluates::Nominal, 0)];
    for (level, model) in jobs.refined_words().into_iter().enumerate() {
        out.push((Evaluates::Refined { level, model }, out.len()));
    }
    let point = |k: usize| {
        let p = &jobs.points[k];
        Evaluates::Point {
            point: k,
            values: p.values.clone(),
            parameters: jobs.parameters_of(k).into_iter().collect(),
            start: p.start,
            tag: p.tag.clone(),
        }
    };
    let starts = jobs.starts();
    let mut followers: Vec<Vec<usize>> = vec![Vec::new(); jobs.points.len()];
    for (k, p) in jobs.points.iter().enumerate() {
        if let Some(s) = p.start {
            followers[s].push(k);
        }
    }
    for k in (0..jobs.points.len()).filter(|&k| jobs.points[k].start.is_none()) {
        let group = out.last().map_or(0, |(_, g)| g + 1);
        out.push((point(k), group));
        if starts[k] {
            for &f in &followers[k] {
                out.push((point(f), group));
            }
        }
    }
    out
}

/// The path made absolute against the current folder (as it is, where that fails).
fn absolute(p: &Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

/// Writes `text` to `path` at once: to a temporary file beside it, then renamed over it, so
/// that a reader (or a killed writer) never sees half a file.
fn write_atomically(path: &Path, text: &str) -> Result<(), PlanError> {
    let cannot =
        |e: std::io::Error| PlanError::Input(format!("cannot write {}: {e}", path.display()));
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(cannot)?;
    }
    let name = path
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy());
    // Unique to this host, process and moment: two workers that run the same shard at once on
    // a shared file system (an engine that started it again) never write the same file.
    let host = std::env::var("HOSTNAME").unwrap_or_default();
    let nanos = (std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH))
        .map_or(0, |d| d.as_nanos());
    let tmp = path.with_file_name(format!(".{name}.{host}.{}.{nanos}.tmp", std::process::id()));
    std::fs::write(&tmp, text).map_err(cannot)?;
    std::fs::rename(&tmp, path).map_err(cannot)
}

/// Reads and parses a plan's or a results file, its errors located.
fn read_yaml<T: serde::de::DeserializeOwned>(path: &Path) -> Result<(T, String), PlanError> {
    let text = crate::inputs::yaml::read_limited(path, MAX_PLAN_FILE_BYTES)?;
    let value = crate::inputs::yaml::parse(path, &text)?;
    Ok((value, text))
}

/// The plan in `dir`, checked: its format and version, each case loaded as it was planned
/// (with the corrections applied) and unchanged (its fingerprint), and its evaluations those
/// its study needs now.
pub fn load(dir: &Path) -> Result<LoadedPlan, PlanError> {
    let path = plan_path(dir);
    if !path.exists() {
        return Err(PlanError::Input(format!(
            "{}: no plan here (write one with `cierva uncertainty CASES --plan {}`, or `cierva sensitivity --case CASE --plan {}`)",
            path.display(),
            dir.display(),
            dir.display()
        )));
    }
    let (file, text): (PlanFile, String) = read_yaml(&path)?;
    let at = |field: &str, m: String| PlanError::from(InputError::field(&path, &text, field, m));
    if file.format != FORMAT {
        return Err(at(
            "format",
            format!("`{}`: this cierva reads plans of `{FORMAT}`", file.format),
        ));
    }
    if file.cierva_version != VERSION {
        return Err(at(
            "cierva_version",
            format!(
                "the plan was written by cierva {} and this is {VERSION}: another version may evaluate a point differently; write the plan again with this one",
                file.cierva_version
            ),
        ));
    }
    let changed = |c: usize, planned: &PlannedCase| {
        at(
            &format!("cases[{c}].fingerprint"),
            format!(
                "{} has changed since the plan was written (its file, its aircraft or rotor file, the corrections or its model's declared inputs): write the plan again",
                planned.path.display()
            ),
        )
    };
    let mut studies = Vec::new();
    let mut sensitivity = None;
    let mut fit = None;
    // A path as given where the plan was written: as it is from that folder (the command line
    // works from it), else from the folder joined.
    let here = absolute(Path::new("."));
    let resolve = |p: &Path| match p.is_relative() && here != file.folder {
        true => file.folder.join(p),
        false => p.to_path_buf(),
    };
    let expected: (Vec<Evaluation>, usize) = match &file.study {
        PlannedStudy::Uncertainty(settings) => {
            let paths: Vec<PathBuf> = file.corrections.iter().map(|p| resolve(p)).collect();
            let corrections = (paths.iter())
                .map(|p| crate::inputs::corrections::load(p))
                .collect::<Result<Vec<_>, _>>()?;
            for (c, planned) in file.cases.iter().enumerate() {
                let case = crate::suite::case::load(&resolve(&planned.path))?;
                let (case, _) = crate::suite::case::with_corrections(&case, &corrections)
                    .map_err(|e| at(&format!("cases[{c}]"), format!("the corrections {e}")))?;
                let jobs = CaseJobs::of(&case, settings.propagation())
                    .map_err(|e| at(&format!("cases[{c}]"), e))?;
                let print = fingerprint(&case, &paths, &inputs_text(&jobs));
                if print != planned.fingerprint || case.id != planned.id {
                    return Err(changed(c, planned));
                }
                studies.push(jobs);
            }
            planned_evaluations(&studies)
        }
        PlannedStudy::Sensitivity(settings) => {
            let Some(planned) = file.cases.first() else {
                return Err(at("cases", "a sensitivity plan names its case".into()));
            };
            let case = crate::suite::case::load(&resolve(&planned.path))?;
            let jobs = sensitivity_jobs(&case, settings).map_err(|e| at("cases[0]", e))?;
            if fingerprint(&case, &[], &requests_text(&jobs)) != planned.fingerprint {
                return Err(changed(0, planned));
            }
            let expected = sensitivity_evaluations(&jobs);
            sensitivity = Some((case, jobs));
            expected
        }
        PlannedStudy::Fit(_) | PlannedStudy::Retune(_) => {
            let planned = (file.cases.first())
                .ok_or_else(|| at("cases", "no fit file, aircraft file or case".into()))?;
            let problem = batch_problem(&file, &resolve(&planned.path), &at)
                .map_err(|e| e.unwrap_or_else(|| changed(0, planned)))?;
            fit = Some(Box::new(problem));
            (file.evaluations.clone(), file.evaluations.len())
        }
    };
    // Every evaluation as its study needs it: its place, case, group and what it runs.
    let (expected, groups) = expected;
    let planned = &file.evaluations;
    if let Some(k) =
        (0..expected.len().max(planned.len())).find(|&k| expected.get(k) != planned.get(k))
    {
        return Err(at(
            &format!("evaluations[{k}]"),
            "not the evaluation its case's study needs (the plan was edited, or written for other settings): write the plan again".into(),
        ));
    }
    if file.groups != groups {
        return Err(at(
            "groups",
            format!(
                "{}: the evaluations make {groups} groups; write the plan again",
                file.groups
            ),
        ));
    }
    Ok(LoadedPlan {
        dir: dir.to_path_buf(),
        id: plan_id(&text),
        file,
        studies,
        sensitivity,
        fit,
    })
}

/// A fit's or a retune's batch's problem (its subject at `path`, the first of the plan's
/// `cases`), its evaluations checked against it; `Err(None)` where the file has changed since
/// the batch was written (its fingerprint), else the error located by `at`.
fn batch_problem(
    file: &PlanFile,
    path: &Path,
    at: &dyn Fn(&str, String) -> PlanError,
) -> Result<crate::fit::Problem, Option<PlanError>> {
    let planned = &file.cases[0];
    let problem = match &file.study {
        PlannedStudy::Retune(batch) => {
            let problem =
                self::fit::retune_problem(batch, path).map_err(|(k, m)| Some(at(&k, m)))?;
            let model = match &problem.subject {
                crate::fit::FitSubject::Model { model } => Some(model.as_ref()),
                _ => None,
            };
            if self::fit::retune_fingerprint(path, model) != planned.fingerprint {
                return Err(None);
            }
            problem
        }
        _ => {
            let f = crate::fit::file::load(path).map_err(|e| Some(PlanError::from(e)))?;
            if self::fit::fingerprint(&f) != planned.fingerprint || f.id != planned.id {
                return Err(None);
            }
            self::fit::every_target(&f)
        }
    };
    self::fit::check_evaluations(&problem, &file.evaluations).map_err(|(k, m)| Some(at(&k, m)))?;
    Ok(problem)
}

/// For the command line: the plan's folder `dir` made absolute, and the working folder set to
/// the one the plan was written from (where it still exists), so that its cases' paths, and
/// every path a result names, read as they did there. A library caller that leaves the working
/// folder alone gets the same numbers, the paths in its messages joined to that folder.
pub fn enter(dir: &Path) -> Result<PathBuf, PlanError> {
    #[derive(Deserialize)]
    struct Folder {
        folder: PathBuf,
    }
    let dir = absolute(dir);
    let text = std::fs::read_to_string(plan_path(&dir)).unwrap_or_default();
    if let Ok(Folder { folder }) = serde_yaml::from_str::<Folder>(&text)
        && folder.is_dir()
    {
        std::env::set_current_dir(&folder)
            .map_err(|e| PlanError::Input(format!("cannot work from {}: {e}", folder.display())))?;
    }
    Ok(dir)
}

/// A shard, `I` of `N` (from 1), as `--shard I/N` gives it.
pub fn parse_shard(text: &str) -> Result<(usize, usize), String> {
    let bad = || format!("--shard {text}: give I/N, shard I (1 to N) of N shards, such as 2/8");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if n == 0 || i == 0 || i > n {
        return Err(format!(
            "--shard {text}: shard {i} is out of range: shards are numbered 1 to {n}"
        ));
    }
    Ok((i, n))
}

/// The shard (1 to `n`) that group `g` belongs to: the groups dealt to the shards in a snake
/// (1 to `n`, then `n` to 1, and again), so that a run of costly groups (the grid study's
/// refined cases, each finer than the one before, all at the start) is spread over the shards
/// instead of every other one falling to the same shard.
pub fn shard_of(g: usize, n: usize) -> usize {
    let (round, place) = (g / n, g % n);
    if round % 2 == 0 { place + 1 } else { n - place }
}

/// The evaluations of shard `(I, N)`, in plan order.
pub fn shard_evaluations(plan: &LoadedPlan, (i, n): (usize, usize)) -> Vec<&Evaluation> {
    (plan.file.evaluations.iter())
        .filter(|e| shard_of(e.group, n) == i)
        .collect()
}

/// A result's value, or the error that stopped it, as a `Result` (what a results file holds
/// apart).
fn outcome<T>(value: Option<T>, error: Option<String>) -> Result<T, String> {
    value.ok_or_else(|| error.unwrap_or_default())
}

/// A `Result` as a results file holds it: the value, or the error ([`outcome`]'s inverse).
fn split<T>(r: Result<T, String>) -> (Option<T>, Option<String>) {
    match r {
        Ok(x) => (Some(x), None),
        Err(e) => (None, Some(e)),
    }
}

/// A results file of shard `(I, N)` holding `evaluations`, written at once to `path`.
fn write_results(
    plan: &LoadedPlan,
    (shard, of): (usize, usize),
    evaluations: Vec<EvaluationResult>,
    path: &Path,
) -> Result<(), PlanError> {
    let file = ResultsFile {
        format: FORMAT.into(),
        plan: plan.id.clone(),
        shard,
        of,
        evaluations,
    };
    let text = serde_yaml::to_string(&file).map_err(|x| PlanError::Input(x.to_string()))?;
    write_atomically(path, &text)
}

/// The results file of shard `i` of `n`, and the folder of its evaluations' files while it runs.
fn shard_paths(dir: &Path, (i, n): (usize, usize)) -> (PathBuf, PathBuf) {
    let results = dir.join("results");
    (
        results.join(format!("shard-{i}-of-{n}.yaml")),
        results.join(format!("shard-{i}-of-{n}")),
    )
}

/// What [`evaluate`] did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShardReport {
    pub shard: usize,
    pub of: usize,
    pub evaluations: usize,
    /// Evaluations already done by an earlier run of the shard (0 for a fresh one; all of them
    /// for a shard already complete, which is skipped).
    pub already_done: usize,
    pub path: PathBuf,
    pub seconds: f64,
}

/// Runs shard `shard = (I, N)` of the plan (its groups: [`shard_of`]): each of its groups on a core of its own, each
/// group's evaluations in order (a start before the points that start from it), each
/// evaluation's results written as it finishes; then the shard's file, and the evaluations'
/// files removed. A complete shard is skipped; an interrupted one takes up where it stopped.
/// `done` is called after each evaluation.
pub fn evaluate(
    plan: &LoadedPlan,
    shard: (usize, usize),
    done: impl Fn() + Sync,
) -> Result<ShardReport, PlanError> {
    let started = std::time::Instant::now();
    let (i, n) = shard;
    let (path, partial) = shard_paths(&plan.dir, shard);
    let mine = shard_evaluations(plan, shard);
    if n > plan.file.groups {
        return Err(PlanError::Input(format!(
            "--shard {i}/{n}: the plan has {} of evaluations (the unit a shard takes), so at most {} {}",
            counted(plan.file.groups, "group", "groups"),
            plan.file.groups,
            if plan.file.groups == 1 {
                "shard: --shard 1/1"
            } else {
                "shards"
            }
        )));
    }
    let report = |already_done: usize| ShardReport {
        shard: i,
        of: n,
        evaluations: mine.len(),
        already_done,
        path: path.clone(),
        seconds: started.elapsed().as_secs_f64(),
    };
    let mut have: BTreeMap<usize, EvaluationResult> = BTreeMap::new();
    if path.exists() {
        for r in read_results(plan, &path, Some(shard))? {
            have.insert(r.evaluation, r);
        }
        if mine.iter().all(|e| have.contains_key(&e.index)) {
            return Ok(report(mine.len()));
        }
    }
    if partial.is_dir() {
        // An evaluation that failed before is asked again: its failure may have been the
        // worker's (a process killed, the memory short), not the model's at its values.
        for r in read_partial(plan, &partial, shard)? {
            if r.error.is_none() {
                have.insert(r.evaluation, r);
            }
        }
    }
    let already_done = have.len();
    let mut groups: BTreeMap<usize, Vec<&Evaluation>> = BTreeMap::new();
    for e in mine.iter().filter(|e| !have.contains_key(&e.index)) {
        groups.entry(e.group).or_default().push(e);
    }
    let groups: Vec<Vec<&Evaluation>> = groups.into_values().collect();
    // A sensitivity study's model, made once for the shard (a simulation's processes shared).
    let model = (plan.sensitivity.as_ref())
        .and_then(|(case, _)| crate::checks::flight_model(&case.subject))
        .map(|(m, _)| m);
    let ran = crate::run::parallel::parallel_map(&groups, |group| {
        let mut out = Vec::new();
        for e in group {
            let r = run_one(plan, model.as_deref(), e);
            let file = partial.join(format!("evaluation-{}.yaml", e.index));
            write_results(plan, shard, vec![r.clone()], &file)?;
            out.push(r);
            done();
        }
        // What the group's model remembers, once every point of it has run.
        for e in group {
            if let Evaluates::Point { point, .. } = e.what {
                plan.studies[e.case].forget(point);
            }
        }
        Ok::<_, PlanError>(out)
    });
    for r in ran {
        for e in r? {
            have.insert(e.evaluation, e);
        }
    }
    write_results(plan, shard, have.into_values().collect(), &path)?;
    // The evaluations' files are in the shard's now (a failure to remove them leaves
    // duplicates, which read the same).
    let _ = std::fs::remove_dir_all(&partial);
    Ok(report(already_done))
}

/// One evaluation run: its case's checks, nominal, refined or at the point's values.
fn run_one(
    plan: &LoadedPlan,
    model: Option<&dyn crate::external::FlightModel>,
    e: &Evaluation,
) -> EvaluationResult {
    let started = std::time::Instant::now();
    let (mut errors, mut start, mut checks) = (None, None, None);
    let (results, values, error) = match (&e.what, &plan.sensitivity, model) {
        (Evaluates::Request { request, .. }, Some((_, jobs)), Some(model)) => {
            let (values, error) = split(jobs.evaluate(model, *request));
            (None, values, error)
        }
        (Evaluates::Request { .. }, ..) => (None, None, Some("not a sensitivity plan".into())),
        (
            Evaluates::Targets {
                targets,
                values,
                start: from,
            },
            ..,
        ) => match &plan.fit {
            Some(problem) => {
                let ((values, each, error), ended) =
                    self::fit::evaluate(problem, targets, values, from.as_ref());
                (errors, start) = (each, ended);
                (None, values, error)
            }
            None => (None, None, Some("not a fit's plan".into())),
        },
        (Evaluates::Point { point, .. }, ..) => {
            let error;
            (checks, error) = split(plan.studies[e.case].evaluate(*point));
            (None, None, error)
        }
        (what, ..) => {
            let jobs = &plan.studies[e.case];
            let results = match what {
                Evaluates::Nominal => crate::suite::outcome::run_case(&jobs.case),
                Evaluates::Refined { level, .. } => {
                    crate::suite::outcome::run_case(jobs.refined_cases()[*level])
                }
                Evaluates::Point { .. } | Evaluates::Request { .. } | Evaluates::Targets { .. } => {
                    unreachable!("matched above")
                }
            };
            (Some(results), None, None)
        }
    };
    EvaluationResult {
        evaluation: e.index,
        seconds: started.elapsed().as_secs_f64(),
        results,
        checks,
        values,
        errors,
        error,
        start,
    }
}

/// A results file read and checked: of this plan, of the shard its name says (where given),
/// and of that shard's evaluations.
fn read_results(
    plan: &LoadedPlan,
    path: &Path,
    shard: Option<(usize, usize)>,
) -> Result<Vec<EvaluationResult>, PlanError> {
    let (file, text): (ResultsFile, String) = read_yaml(path)?;
    let at = |field: &str, m: String| PlanError::from(InputError::field(path, &text, field, m));
    if file.format != FORMAT {
        return Err(at(
            "format",
            format!("`{}`: this cierva reads `{FORMAT}`", file.format),
        ));
    }
    if file.plan != plan.id {
        return Err(at(
            "plan",
            format!(
                "results of another plan ({}; the plan in {} is {}): remove them, or finish the plan they belong to",
                file.plan,
                plan.dir.display(),
                plan.id
            ),
        ));
    }
    if let Some((i, n)) = shard
        && (file.shard, file.of) != (i, n)
    {
        return Err(at(
            "shard",
            format!(
                "shard {} of {} in a file of shard {i} of {n}",
                file.shard, file.of
            ),
        ));
    }
    if file.of == 0 || file.shard == 0 || file.shard > file.of {
        return Err(at(
            "shard",
            format!("shard {} of {}: out of range", file.shard, file.of),
        ));
    }
    for (k, r) in file.evaluations.iter().enumerate() {
        let Some(e) = plan.file.evaluations.get(r.evaluation) else {
            return Err(at(
                &format!("evaluations[{k}].evaluation"),
                format!(
                    "{}: the plan has {} evaluations",
                    r.evaluation,
                    plan.file.evaluations.len()
                ),
            ));
        };
        if shard_of(e.group, file.of) != file.shard {
            return Err(at(
                &format!("evaluations[{k}].evaluation"),
                format!(
                    "evaluation {} is not shard {} of {}'s",
                    r.evaluation, file.shard, file.of
                ),
            ));
        }
        let checks = plan.studies.get(e.case).map_or(0, |j| j.case.checks.len());
        let (given, size, what) = match (&e.what, &plan.sensitivity) {
            (Evaluates::Request { .. }, Some((_, jobs))) => (
                r.values.as_ref().map(Vec::len),
                jobs.quantities.len(),
                "quantities' values",
            ),
            (Evaluates::Targets { targets, .. }, _) => (
                r.values.as_ref().map(Vec::len),
                targets.len(),
                "targets' values",
            ),
            (Evaluates::Point { .. }, _) => {
                (r.checks.as_ref().map(Vec::len), checks, "checks' values")
            }
            _ => (r.results.as_ref().map(Vec::len), checks, "checks' results"),
        };
        // Fields of another kind of evaluation than this one.
        let other = match &e.what {
            Evaluates::Request { .. } => {
                r.results.is_some() || r.checks.is_some() || r.errors.is_some()
            }
            Evaluates::Targets { targets, .. } => {
                r.results.is_some()
                    || r.checks.is_some()
                    || r.errors.as_ref().is_some_and(|x| x.len() != targets.len())
            }
            Evaluates::Point { .. } => {
                r.results.is_some() || r.values.is_some() || r.errors.is_some()
            }
            // A nominal run or a refined case always has its results.
            _ => {
                r.checks.is_some() || r.values.is_some() || r.errors.is_some() || r.error.is_some()
            }
        };
        if other || given.is_some_and(|n| n != size) || given.is_none() == r.error.is_none() {
            return Err(at(
                &format!("evaluations[{k}]"),
                format!(
                    "evaluation {}: give its {size} {what}, or the error that stopped it",
                    r.evaluation
                ),
            ));
        }
    }
    Ok(file.evaluations)
}

/// The evaluations' files of an interrupted shard.
fn read_partial(
    plan: &LoadedPlan,
    folder: &Path,
    shard: (usize, usize),
) -> Result<Vec<EvaluationResult>, PlanError> {
    let cannot =
        |e: std::io::Error| PlanError::Input(format!("cannot read {}: {e}", folder.display()));
    let mut out = Vec::new();
    let mut paths: Vec<PathBuf> = (std::fs::read_dir(folder).map_err(cannot)?)
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "yaml"))
        .collect();
    paths.sort();
    for p in paths {
        out.extend(read_results(plan, &p, Some(shard))?);
    }
    Ok(out)
}

/// Every evaluation's results found in the plan's folder (complete shards' files and
/// interrupted shards' evaluations), by evaluation, with the shard counts they were run in.
fn gather(plan: &LoadedPlan) -> Result<(BTreeMap<usize, EvaluationResult>, Vec<usize>), PlanError> {
    let results = plan.dir.join("results");
    let mut have = BTreeMap::new();
    let mut counts = Vec::new();
    let Ok(entries) = std::fs::read_dir(&results) else {
        return Ok((have, counts));
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for p in paths {
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default();
        let Some(shard) = name
            .strip_prefix("shard-")
            .map(|s| s.trim_end_matches(".yaml").replace("-of-", "/"))
            .and_then(|s| parse_shard(&s).ok())
        else {
            continue;
        };
        let done = p.with_file_name(format!("{name}.yaml"));
        let found = if p.is_dir() && done.exists() {
            // A shard's file holds what its folder held (a leftover beside it is not read).
            continue;
        } else if p.is_dir() {
            read_partial(plan, &p, shard)?
        } else {
            read_results(plan, &p, Some(shard))?
        };
        counts.push(shard.1);
        for r in found {
            have.insert(r.evaluation, r);
        }
    }
    counts.sort_unstable();
    counts.dedup();
    Ok((have, counts))
}

/// Every case's study from the plan's results, with the wall time its evaluations took
/// (summed over them, s); [`PlanError::Incomplete`] naming the shards whose results are
/// missing, where any are.
pub fn finish(plan: &LoadedPlan) -> Result<Vec<(CaseUncertainty, f64)>, PlanError> {
    if plan.fit.is_some() {
        return Err(PlanError::Input(format!(
            "{} is a batch of a fit's or a retune's evaluations: the `cierva fit` or `cierva retune` given `--evaluate-with` reads it",
            plan_path(&plan.dir).display()
        )));
    }
    if plan.sensitivity.is_some() {
        return Err(PlanError::Input(format!(
            "{} is a sensitivity study's plan: finish it with `cierva sensitivity --from-plan {}`",
            plan_path(&plan.dir).display(),
            plan.dir.display()
        )));
    }
    let mut have = complete(plan)?;
    let mut out = Vec::new();
    for (c, jobs) in plan.studies.iter().enumerate() {
        let mut nominal = Vec::new();
        let mut refined = Vec::new();
        let mut points: Vec<Option<Result<Vec<_>, String>>> =
            (0..jobs.points.len()).map(|_| None).collect();
        let mut seconds = 0.0;
        for e in plan.file.evaluations.iter().filter(|e| e.case == c) {
            let r = have.remove(&e.index).expect("every evaluation found");
            seconds += r.seconds;
            let whole = |r: EvaluationResult| {
                outcome(r.results, r.error)
                    .map_err(|x| PlanError::Input(format!("evaluation {}: {x}", e.index)))
            };
            match &e.what {
                Evaluates::Point { point, .. } => points[*point] = Some(outcome(r.checks, r.error)),
                Evaluates::Nominal => nominal = whole(r)?,
                Evaluates::Refined { .. } => refined.push(whole(r)?),
                Evaluates::Request { .. } | Evaluates::Targets { .. } => {
                    return Err(PlanError::Input(format!(
                        "evaluation {}: another study's evaluation in an uncertainty study's plan",
                        e.index
                    )));
                }
            }
        }
        let runs = Runs::from_results(
            nominal,
            refined,
            points.into_iter().map(|p| p.expect("every point found")),
        );
        out.push((jobs.finish(runs), seconds));
    }
    Ok(out)
}

/// Every evaluation's results, by evaluation; [`PlanError::Incomplete`] naming the shards whose
/// results are missing, where any are.
fn complete(plan: &LoadedPlan) -> Result<BTreeMap<usize, EvaluationResult>, PlanError> {
    let (have, counts) = gather(plan)?;
    let missing: Vec<&Evaluation> = (plan.file.evaluations.iter())
        .filter(|e| !have.contains_key(&e.index))
        .collect();
    if !missing.is_empty() {
        return Err(PlanError::Incomplete(incomplete(plan, &missing, &counts)));
    }
    Ok(have)
}

/// A sensitivity study from its plan's results, with the wall time its requests took (summed,
/// s): the same study `cierva sensitivity --case` gives on one machine.
pub fn finish_sensitivity(plan: &LoadedPlan) -> Result<(Result<Study, String>, f64), PlanError> {
    if plan.fit.is_some() {
        return Err(PlanError::Input(format!(
            "{} is a batch of a fit's or a retune's evaluations: the `cierva fit` or `cierva retune` given `--evaluate-with` reads it",
            plan_path(&plan.dir).display()
        )));
    }
    let Some((_, jobs)) = &plan.sensitivity else {
        return Err(PlanError::Input(format!(
            "{} is an uncertainty study's plan: finish it with `cierva uncertainty --from-plan {}`",
            plan_path(&plan.dir).display(),
            plan.dir.display()
        )));
    };
    let mut have = complete(plan)?;
    let mut answers: Vec<Option<Result<Vec<f64>, String>>> = vec![None; jobs.requests.len()];
    let mut seconds = 0.0;
    for e in &plan.file.evaluations {
        let r = have.remove(&e.index).expect("every evaluation found");
        seconds += r.seconds;
        if let Evaluates::Request { request, .. } = e.what {
            answers[request] = Some(outcome(r.values, r.error));
        }
    }
    Ok((crate::fit::sensitivity::finish(jobs, answers), seconds))
}

/// The missing evaluations in words, by the shard that holds them, in the shard count the
/// results were run in (the largest, where they were run in several).
fn incomplete(plan: &LoadedPlan, missing: &[&Evaluation], counts: &[usize]) -> String {
    let total = plan.file.evaluations.len();
    let dir = plan.dir.display();
    let Some(&n) = counts.last() else {
        return format!(
            "{} of {total} evaluations have no results in {dir}/results: run `cierva evaluate {dir} --shard I/N` for each shard I of N, then finish the study",
            missing.len()
        );
    };
    let mut by_shard: BTreeMap<usize, usize> = BTreeMap::new();
    for e in missing {
        *by_shard.entry(shard_of(e.group, n)).or_default() += 1;
    }
    let shards: Vec<String> = (by_shard.iter())
        .map(|(i, k)| {
            let of = (plan.file.evaluations.iter()).filter(|e| shard_of(e.group, n) == *i).count();
            format!("shard {i} of {n} ({k} of its {of} evaluations; `cierva evaluate {dir} --shard {i}/{n}`)")
        })
        .collect();
    format!(
        "the study is not complete: {} of {total} evaluations have no results, so no verdict is drawn. Missing: {}",
        missing.len(),
        shards.join("; ")
    )
}
