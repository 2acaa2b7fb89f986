//! `mode`: the characteristics of one mode of a linear model (or of a linearised aircraft):
//! eigenvalue, natural frequency, and where they apply damping ratio, period, time to half or
//! double amplitude.

use super::linear::{self, Computed, LinearSetup, OnLinear, System};
use super::{At, CheckSpec, Cx, Evaluate, Evaluated, Expectation, Kind, Placed, Refusal, Trivial};
use crate::checks::subject::Subject;
use crate::inputs::quantity::{self as q, Quantity as Q};
use crate::inputs::yaml::InputError;
use cierva_model::analysis::modes::Complex;
use cierva_model::{LinearModel, ModeKind};

/// A `mode` check.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeCheck {
    pub mode: ModeKind,
    pub system: System,
    pub linear: LinearSetup,
}

linear::linear_spec! {
    /// A `mode` check's own fields, as written.
    pub struct ModeSpec {
        /// The mode class to look at.
        pub mode: ModeKind,
        /// The system looked at.
        #[serde(default)]
        pub system: System,
    }
}

impl Kind for ModeCheck {
    type Spec = ModeSpec;
    const SUBJECTS: &'static str = linear::SUBJECTS;

    fn runs_on(subject: &Subject) -> bool {
        linear::runs_on(subject)
    }

    fn resolve(cx: &Cx, own: ModeSpec, _: &CheckSpec) -> Result<Self, InputError> {
        Ok(Self {
            mode: own.mode,
            system: own.system,
            linear: linear::resolve_setup(cx, &own.linear())?,
        })
    }
}

impl Evaluate for ModeCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::MODE)
    }

    /// The mode of the model as it is, over the case's airspeeds.
    fn series(&self) -> Option<String> {
        self.linear
            .plain_at_a_condition()
            .then(|| format!("mode {:?} {:?}", self.mode, self.system))
    }

    fn linear(&self) -> Option<&LinearSetup> {
        Some(&self.linear)
    }

    fn placed(&self) -> Option<Placed<'_>> {
        Some(linear::placed_among_eigenvalues(
            self.system,
            &self.linear,
            false,
        ))
    }

    /// Zero damping; a constant verdict (stable, or unstable) where the check is of a sign;
    /// and, where the check is of an approximation (seed 002's weakly coupled systems) on a
    /// linear model, the exact eigenvalue of the same mode of the full system.
    fn trivial(
        &self,
        subject: &Subject,
        expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        let mut out = vec![
            Trivial::value(Q::EigenvalueRealPerS.name(), 0.0, "zero damping"),
            Trivial::value(Q::DampingRatio.name(), 0.0, "zero damping"),
        ];
        out.extend(super::constant_verdicts(
            expectations,
            &[Q::EigenvalueRealPerS, Q::DampingRatio],
            "a constant verdict (every mode stable, or every mode unstable)",
        ));
        if let (
            System::Eq13 | System::Reduced | System::ShortPeriod,
            Subject::Linear { model, .. },
        ) = (self.system, subject)
        {
            let exact = Self {
                system: System::Full,
                ..self.clone()
            };
            // A mode the full system does not classify has no exact value to compare.
            let computed = linear::prepare(model, &self.linear)
                .and_then(|base| exact.compute(&base, None, model, expectations));
            if let Ok(c) = computed {
                out.extend(c.values.iter().map(|(n, v)| {
                    Trivial::value(n, *v, "the exact eigenvalue (the full system's mode)")
                }));
            }
        }
        if let Subject::Linear { model, .. } = subject {
            out.extend(self.neighbours(model, None));
        }
        Ok(out)
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        linear::evaluate(self, at, expectations)
    }
}

impl ModeCheck {
    /// The other modes of the linear model (as the check prepares it): a check that one of them
    /// also passes cannot tell its mode from a neighbour. On a linear model the check is refused
    /// at load; an aircraft's modes need its trim, which loading does not run, so its mode
    /// checks are refused when they run ([`OnLinear::refused_on`]).
    fn neighbours(&self, model: &LinearModel, own: Option<Complex>) -> Vec<Trivial> {
        let Ok(analysis) = linear::prepare(model, &self.linear)
            .and_then(|m| cierva_model::analysis::modes::modes(&m).map_err(|e| e.to_string()))
        else {
            return Vec::new();
        };
        let mut out = Vec::new();
        // The check's own mode: of its kind, or the eigenvalue it followed by continuity.
        let is_own = |m: &cierva_model::Mode| {
            m.kind == self.mode
                || own.is_some_and(|e| {
                    let near = 1e-12 * e.re.hypot(e.im).max(1.0);
                    (e.re - m.eigenvalue.re).abs() <= near
                        && (e.im.abs() - m.eigenvalue.im.abs()).abs() <= near
                })
        };
        for m in analysis.modes.iter().filter(|m| !is_own(m)) {
            let values = [
                (Q::EigenvalueRealPerS, Some(m.eigenvalue.re)),
                (Q::EigenvalueImagRadS, Some(m.eigenvalue.im.abs())),
                (Q::NaturalFrequencyRadS, Some(m.natural_frequency_rad_s)),
                (Q::DampingRatio, m.damping_ratio),
                (Q::PeriodS, m.period_s),
                (Q::TimeToHalfS, m.time_to_half_s),
                (Q::TimeToDoubleS, m.time_to_double_s),
            ];
            let predictor = match m.kind {
                ModeKind::ShortPeriod => "a neighbouring mode of the same model (short period)",
                ModeKind::Phugoid => "a neighbouring mode of the same model (phugoid)",
                ModeKind::Rotorspeed => "a neighbouring mode of the same model (rotorspeed)",
                ModeKind::DutchRoll => "a neighbouring mode of the same model (Dutch roll)",
                ModeKind::RollSubsidence => {
                    "a neighbouring mode of the same model (roll subsidence)"
                }
                ModeKind::Spiral => "a neighbouring mode of the same model (spiral)",
                ModeKind::Heading => "a neighbouring mode of the same model (heading)",
                ModeKind::Unclassified => "a neighbouring mode of the same model (unclassified)",
            };
            out.extend(
                values
                    .into_iter()
                    .filter_map(|(q, v)| v.map(|v| Trivial::value(q.name(), v, predictor))),
            );
        }
        out
    }
}

impl OnLinear for ModeCheck {
    fn setup(&self) -> &LinearSetup {
        &self.linear
    }

    fn refused_on(
        &self,
        model: &LinearModel,
        own: Option<Complex>,
        expectations: &[Expectation],
    ) -> Option<String> {
        self.neighbours(model, own).into_iter().find_map(|t| {
            expectations
                .iter()
                .filter(|e| e.quantity == t.quantity)
                .find(|e| {
                    crate::checks::tolerance::admits(&e.tolerance.kind, e.value, t.value)
                        == Some(true)
                })
                .map(|e| {
                    format!(
                        "{} ({} = {:.4e}) passes this expectation under tolerance `{}`: the check \
                         cannot tell its mode from a neighbour",
                        t.predictor, e.quantity, t.value, e.tolerance.name
                    )
                })
        })
    }

    fn mode(&self) -> Option<(ModeKind, System)> {
        Some((self.mode, self.system))
    }

    fn compute(
        &self,
        model: &LinearModel,
        anchor: Option<Complex>,
        unmodified: &LinearModel,
        _expectations: &[Expectation],
    ) -> Result<Computed, String> {
        let m = linear::select_mode(model, (self.mode, self.system), anchor, unmodified)?;
        let mut values = vec![
            (Q::EigenvalueRealPerS.name(), m.eigenvalue.re),
            (Q::EigenvalueImagRadS.name(), m.eigenvalue.im),
            (Q::NaturalFrequencyRadS.name(), m.natural_frequency_rad_s),
        ];
        let optional = [
            (Q::DampingRatio.name(), m.damping_ratio),
            (Q::PeriodS.name(), m.period_s),
            (Q::TimeToHalfS.name(), m.time_to_half_s),
            (Q::TimeToDoubleS.name(), m.time_to_double_s),
        ];
        values.extend(optional.into_iter().filter_map(|(n, v)| v.map(|v| (n, v))));
        Ok(Computed {
            anchor: Some(m.eigenvalue),
            ..Computed::values(values)
        })
    }
}
