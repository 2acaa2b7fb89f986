//! A case's study as the evaluations it needs, apart from how they are run: the nominal run,
//! the grid study's refined cases and the propagation's points ([`CaseJobs`]), and what their
//! results make ([`CaseJobs::finish`]). This machine's cores run them
//! ([`CaseJobs::run_locally`]); a plan's shards run the same evaluations anywhere
//! ([`crate::plan`]), and the same [`CaseJobs::finish`] reads their results, so that a study
//! finished from a plan equals the one-machine study bit for bit.

use super::design::Design;
use super::distribution::Input;
use super::numerics::GridStudy;
use super::propagate::{
    CaseUncertainty, CheckValues, Point, Propagation, PropagationSettings, forget, inputs,
    point_of, values_of, with_values, without_inputs,
};
use crate::checks::CheckClass;
use crate::suite::case::Case;
use crate::suite::outcome::CheckResult;
use serde::{Deserialize, Serialize};

/// One point of a propagation: the case with its inputs at `values` (in the order of the
/// study's inputs), its model's answers started from those of point `start` (a row of `A` for
/// an `A_B^(i)` point: [`crate::external::FlightModel::starting_from`]), under a path of its
/// own (`tag`), so that no cached answer of another point is reused.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointJob {
    pub values: Vec<f64>,
    pub start: Option<usize>,
    pub tag: String,
}

/// How a case's inputs are propagated, once its study knows them.
#[derive(Debug, Clone)]
pub enum StudyMethod {
    /// Nothing to propagate: no uncertain inputs, or (`validation_only`) no validation check;
    /// the words say which, where the study says it.
    Nothing(Option<String>),
    /// Saltelli's design ([`super::propagate`]).
    Sampled(Design),
    /// Each input moved up and down, then the residual draws ([`super::first_order`]).
    FirstOrder(Vec<(usize, f64)>),
}

/// A case's study: what it evaluates, and how it reads the results.
#[derive(Clone)]
pub struct CaseJobs {
    /// The case as studied (only its validation checks, where the settings ask so).
    pub case: Case,
    /// Which of the given case's checks the study keeps, in order.
    pub kept: Vec<bool>,
    pub settings: PropagationSettings,
    pub inputs: Vec<Input>,
    pub method: StudyMethod,
    pub grid: Option<GridStudy>,
    /// The propagation's points, in the order [`Self::finish`] reads them.
    pub points: Vec<PointJob>,
}

/// What a study's evaluations gave: the nominal run's results, the grid study's refined cases'
/// (in [`GridStudy::cases`]' order), and each point's, as a `Point` (in [`CaseJobs::points`]'
/// order).
pub struct Runs {
    nominal: Vec<CheckResult>,
    refined: Vec<Vec<CheckResult>>,
    points: Vec<Point>,
}

impl Runs {
    /// The runs from the evaluations' results (a plan's shards'): each point's results, or why
    /// its case could not be made, read about the nominal results.
    pub fn from_results(
        nominal: Vec<CheckResult>,
        refined: Vec<Vec<CheckResult>>,
        points: impl IntoIterator<Item = Result<Vec<CheckValues>, String>>,
    ) -> Self {
        let points = (points.into_iter())
            .map(|p| point_from(&nominal, p))
            .collect();
        Self {
            nominal,
            refined,
            points,
        }
    }
}

impl CaseJobs {
    /// The study of `case` at `settings`: its checks (only the validation ones where asked),
    /// its inputs, the method that suits it, its grid study and its points. `Err` where its
    /// inputs cannot be found (a model's `describe` failed) or its design cannot be made.
    pub fn of(case: &Case, settings: PropagationSettings) -> Result<Self, String> {
        let kept: Vec<bool> = (case.checks.iter())
            .map(|k| !settings.validation_only || k.class == CheckClass::Validation)
            .collect();
        let mut studied = case.clone();
        studied.checks = (case.checks.iter().zip(&kept))
            .filter(|(_, k)| **k)
            .map(|(c, _)| c.clone())
            .collect();
        let settings = PropagationSettings {
            validation_only: false,
            ..settings
        };
        let nothing = |why: Option<String>| Self {
            case: studied.clone(),
            kept: kept.clone(),
            settings,
            inputs: Vec::new(),
            method: StudyMethod::Nothing(why),
            grid: None,
            points: Vec::new(),
        };
        if studied.checks.is_empty() {
            return Ok(nothing(Some(
                "none: the case has no validation checks".into(),
            )));
        }
        let inputs = inputs(&studied)?;
        if inputs.is_empty() {
            return Ok(nothing(None));
        }
        let first = match settings.method {
            Propagation::Auto => (studied.checks.iter()).any(|c| c.behaviour().tunnel().is_some()),
            Propagation::Sampled => false,
            Propagation::FirstOrder => true,
        };
        let (method, points) = if first {
            let (moves, points) = super::first_order::jobs(&inputs);
            (StudyMethod::FirstOrder(moves), points)
        } else {
            let (design, points) = super::propagate::sampled_jobs(&inputs, settings)?;
            (StudyMethod::Sampled(design), points)
        };
        Ok(Self {
            grid: super::numerics::grid_study(&studied),
            case: studied,
            kept,
            settings,
            inputs,
            method,
            points,
        })
    }

    /// The given case's nominal results, only those of the checks the study keeps.
    pub fn nominal_of(&self, nominal: &[CheckResult]) -> Vec<CheckResult> {
        (nominal.iter().zip(&self.kept))
            .filter(|(_, k)| **k)
            .map(|(r, _)| r.clone())
            .collect()
    }

    /// The refined cases of the grid study, in the order a study's runs hold their results.
    pub fn refined_cases(&self) -> Vec<&Case> {
        self.grid.as_ref().map(GridStudy::cases).unwrap_or_default()
    }

    /// Each refined case in words, in [`Self::refined_cases`]' order: the parameter refined and
    /// how many times ("main rotor azimuth step, refined twice").
    pub fn refined_words(&self) -> Vec<String> {
        let Some(g) = &self.grid else {
            return Vec::new();
        };
        (g.parameters.iter())
            .flat_map(|p| {
                (1..=p.levels.len()).map(move |l| match l {
                    1 => format!("{}, refined once", p.parameter),
                    2 => format!("{}, refined twice", p.parameter),
                    _ => format!("{}, refined {l} times", p.parameter),
                })
            })
            .collect()
    }

    /// Point `k` evaluated: every check of the case with the point's values, its model started
    /// from its start's; `Err` where the case cannot be made with them (a value the model
    /// refuses). What the point's model remembers is kept: see [`Self::forget`].
    pub fn evaluate(&self, k: usize) -> Result<Vec<CheckValues>, String> {
        let job = &self.points[k];
        let start = (job.start).map(|s| self.parameters_of(s));
        let c = with_values(
            &self.case,
            &self.inputs,
            &job.values,
            (&job.tag, start.as_ref()),
        )?;
        Ok((crate::suite::outcome::run_case(&c).iter())
            .map(CheckValues::of)
            .collect())
    }

    /// The parameter values point `k` asks its model with, by the model's names (what its
    /// values set: a factor input moves several).
    pub fn parameters_of(&self, k: usize) -> crate::external::Values {
        values_of(&self.inputs, &self.points[k].values)
    }

    /// Forgets what the model remembers of point `k`'s answers.
    pub fn forget(&self, k: usize) {
        forget(&self.case, &self.parameters_of(k));
    }

    /// Whether another point starts from each point's answers (which are then kept until it
    /// has run), by point.
    pub fn starts(&self) -> Vec<bool> {
        let mut out = vec![false; self.points.len()];
        for s in self.points.iter().filter_map(|p| p.start) {
            out[s] = true;
        }
        out
    }

    /// Every evaluation on this machine's cores about the nominal results given: the refined
    /// cases (first, as the longest) and the points that start from nothing in one batch, then
    /// the points that start from another's. What a point's model remembers is forgotten once
    /// its checks have run (a start's once every point started from it has), so that
    /// thousands of points do not fill the memory. `done` is called after each point.
    pub fn run_locally(&self, nominal: Vec<CheckResult>, done: impl Fn() + Sync) -> Runs {
        enum Job<'c> {
            Refined(&'c Case),
            Point(usize),
        }
        enum Run {
            Refined(Vec<CheckResult>),
            Point(usize, Point),
        }
        let starts = self.starts();
        let point = |k: usize| {
            let p = point_from(&nominal, self.evaluate(k));
            if !starts[k] {
                self.forget(k);
            }
            done();
            Run::Point(k, p)
        };
        let first: Vec<Job> = (self.refined_cases().into_iter().map(Job::Refined))
            .chain(
                (0..self.points.len())
                    .filter(|&k| self.points[k].start.is_none())
                    .map(Job::Point),
            )
            .collect();
        let mut runs = crate::run::parallel::parallel_map(&first, |job| match job {
            Job::Refined(c) => Run::Refined(crate::suite::outcome::run_case(c)),
            Job::Point(k) => point(*k),
        });
        let second: Vec<usize> = (0..self.points.len())
            .filter(|&k| self.points[k].start.is_some())
            .collect();
        runs.extend(crate::run::parallel::parallel_map(&second, |k| point(*k)));
        for k in (0..self.points.len()).filter(|&k| starts[k]) {
            self.forget(k);
        }
        let mut refined = Vec::new();
        let mut points: Vec<Option<Point>> = (0..self.points.len()).map(|_| None).collect();
        for r in runs {
            match r {
                Run::Refined(results) => refined.push(results),
                Run::Point(k, p) => points[k] = Some(p),
            }
        }
        Runs {
            nominal,
            refined,
            points: (points.into_iter())
                .map(|p| p.expect("every point ran"))
                .collect(),
        }
    }

    /// The study from its evaluations' results.
    pub fn finish(&self, runs: Runs) -> CaseUncertainty {
        let Runs {
            nominal,
            refined,
            points,
        } = runs;
        match &self.method {
            StudyMethod::Nothing(why) => {
                let mut none = without_inputs(&self.case, &nominal);
                if let Some(why) = why {
                    none.method = why.clone();
                }
                none
            }
            StudyMethod::Sampled(design) => super::propagate::sampled_summary(
                self,
                &nominal,
                design,
                points,
                (self.grid.as_ref()).map(|g| (g, refined.as_slice())),
            ),
            StudyMethod::FirstOrder(moves) => {
                super::first_order::summary(self, &nominal, moves, points, refined)
            }
        }
    }
}

/// A point from its evaluation: its results, or why the case could not be made with its
/// values (no results).
fn point_from(nominal: &[CheckResult], evaluated: Result<Vec<CheckValues>, String>) -> Point {
    match evaluated {
        Ok(results) => point_of(nominal, &results),
        Err(e) => point_of(nominal, &[]).with_error(e),
    }
}
