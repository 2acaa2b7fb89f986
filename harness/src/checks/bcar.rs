//! `bcar`: the BCAR Section T verdict of one oscillatory mode, with its damping, boundary and
//! margin indices (see [`cierva_model::analysis::bcar`]).

use super::linear::{self, Computed, LinearSetup, OnLinear, System};
use super::{At, CheckSpec, Cx, Evaluate, Evaluated, Expectation, Kind, Placed, Refusal, Trivial};
use crate::checks::subject::Subject;
use crate::inputs::quantity::{self as q, Quantity as Q};
use crate::inputs::yaml::InputError;
use cierva_model::analysis::bcar::{self, Verdict};
use cierva_model::analysis::modes::Complex;
use cierva_model::{LinearModel, ModeKind};

/// A `bcar` check: the mode, and the verdict expected of it (if any) and its indices.
#[derive(Debug, Clone, PartialEq)]
pub struct BcarCheck {
    pub mode: ModeKind,
    pub system: System,
    /// The verdict expected. A constant verdict passes it, so it is accepted only in a
    /// `verification` check (see [`super::Trivial::verdict`]).
    pub verdict: Option<Verdict>,
    pub linear: LinearSetup,
}

linear::linear_spec! {
    /// A `bcar` check's own fields, as written.
    pub struct BcarSpec {
        /// The mode class to look at.
        pub mode: ModeKind,
        /// The system looked at.
        #[serde(default)]
        pub system: System,
        /// The expected verdict.
        #[serde(default)]
        pub verdict: Option<Verdict>,
    }
}

impl Kind for BcarCheck {
    type Spec = BcarSpec;
    const SUBJECTS: &'static str = linear::SUBJECTS;

    fn runs_on(subject: &Subject) -> bool {
        linear::runs_on(subject)
    }

    fn resolve(cx: &Cx, own: BcarSpec, _: &CheckSpec) -> Result<Self, InputError> {
        Ok(Self {
            mode: own.mode,
            system: own.system,
            verdict: own.verdict,
            linear: linear::resolve_setup(cx, &own.linear())?,
        })
    }
}

impl Evaluate for BcarCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::BCAR)
    }

    /// The mode's BCAR margins, of the model as it is, over the case's airspeeds.
    fn series(&self) -> Option<String> {
        self.linear
            .plain_at_a_condition()
            .then(|| format!("bcar {:?} {:?}", self.mode, self.system))
    }

    /// The expected verdict is judged without an entry under `expect`.
    fn judges_without_expect(&self) -> bool {
        self.verdict.is_some()
    }

    fn linear(&self) -> Option<&LinearSetup> {
        Some(&self.linear)
    }

    fn placed(&self) -> Option<Placed<'_>> {
        Some(linear::placed_among_eigenvalues(
            self.system,
            &self.linear,
            true,
        ))
    }

    /// A constant verdict (every mode complies, or every mode fails): it passes the expected
    /// verdict and a margin's sign.
    fn trivial(
        &self,
        _subject: &Subject,
        expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        let predictor = "a constant verdict (every mode complies, or every mode fails)";
        let mut out = super::constant_verdicts(
            expectations,
            &[Q::MarginIndex, Q::MarginRealPerS],
            predictor,
        );
        if self.verdict.is_some() {
            out.push(Trivial::verdict(super::VERDICT, 0.0, predictor));
        }
        Ok(out)
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        linear::evaluate(self, at, expectations)
    }
}

impl OnLinear for BcarCheck {
    fn setup(&self) -> &LinearSetup {
        &self.linear
    }

    fn mode(&self) -> Option<(ModeKind, System)> {
        Some((self.mode, self.system))
    }

    fn verdict(&self) -> Option<Verdict> {
        self.verdict
    }

    fn compute(
        &self,
        model: &LinearModel,
        anchor: Option<Complex>,
        unmodified: &LinearModel,
        _expectations: &[Expectation],
    ) -> Result<Computed, String> {
        let m = linear::select_mode(model, (self.mode, self.system), anchor, unmodified)?;
        let mut c = Computed {
            anchor: Some(m.eigenvalue),
            ..Computed::values(vec![])
        };
        if let Some(a) = bcar::assess(&m) {
            c.values = vec![
                (Q::DampingIndex.name(), a.damping_index),
                (Q::BoundaryIndex.name(), a.boundary_index),
                (Q::MarginIndex.name(), a.margin_index),
                (Q::MarginRealPerS.name(), a.margin_real_per_s),
                (Q::PeriodS.name(), a.period_s),
            ];
            c.verdict = Some(a.verdict);
        }
        Ok(c)
    }

    /// The mode's eigenvalue and its margin from the boundary, beyond the verdict.
    fn fingerprint(&self, c: &Computed) -> Vec<(String, f64)> {
        let mut out = Vec::new();
        if let Some(a) = c.anchor {
            out.push((Q::EigenvalueRealPerS.name().to_string(), a.re));
            out.push((Q::EigenvalueImagRadS.name().to_string(), a.im));
        }
        if let Ok(v) = c.get(Q::MarginRealPerS.name()) {
            out.push((Q::MarginRealPerS.name().to_string(), v));
        }
        out
    }
}
