//! `mode`: the characteristics of one mode of a linear model (or of a linearised aircraft):
//! eigenvalue, natural frequency, and where they apply damping ratio, period, time to half or
//! double amplitude.

use super::linear::{self, Computed, LinearSetup, OnLinear, System};
use super::{At, CheckKind, CheckSpec, Cx, Evaluate, Evaluated, Expectation, Kind};
use crate::quantity::{self as q, Quantity as Q};
use crate::subject::Subject;
use crate::yaml::InputError;
use cierva_model::analysis::modes::Complex;
use cierva_model::{LinearModel, ModeKind};

/// A `mode` check.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeCheck {
    pub mode: ModeKind,
    pub system: System,
    pub linear: LinearSetup,
}

impl Kind for ModeCheck {
    const KIND: CheckKind = CheckKind::Mode;
    const FIELDS: &'static [&'static str] = &[
        "mode",
        "system",
        "condition",
        "set",
        "without_rotorspeed_coupling",
    ];
    const SUBJECTS: &'static str = linear::SUBJECTS;

    fn runs_on(subject: &Subject) -> bool {
        linear::runs_on(subject)
    }

    fn resolve(cx: &Cx, spec: &CheckSpec) -> Result<Self, InputError> {
        Ok(Self {
            mode: cx.needs(&spec.mode, "mode")?,
            system: spec.system,
            linear: linear::resolve_setup(cx, spec)?,
        })
    }
}

impl Evaluate for ModeCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::MODE)
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        linear::evaluate(self, at, expectations)
    }
}

impl OnLinear for ModeCheck {
    fn setup(&self) -> &LinearSetup {
        &self.linear
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
