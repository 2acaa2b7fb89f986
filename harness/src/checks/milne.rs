//! `milne`: the weakly coupled systems values of seed 002 (Eqs. 13-25): the closed-form
//! matrix, its cubic and the sensitivities of the phugoid and rotorspeed roots (see
//! [`cierva_model::analysis::milne`]).

use super::linear::{self, Computed, LinearSetup, OnLinear};
use super::{At, CheckSpec, Cx, Evaluate, Evaluated, Expectation, Kind};
use crate::checks::subject::Subject;
use crate::inputs::quantity as q;
use crate::inputs::yaml::InputError;
use cierva_model::LinearModel;
use cierva_model::analysis::milne;
use cierva_model::analysis::modes::Complex;

/// A `milne` check (on an aircraft, of its longitudinal subsystem).
#[derive(Debug, Clone, PartialEq)]
pub struct MilneCheck {
    pub linear: LinearSetup,
}

linear::linear_spec! {
    /// A `milne` check's fields, as written: those of every check on a linear model.
    pub struct MilneSpec {}
}

impl Kind for MilneCheck {
    type Spec = MilneSpec;
    const SUBJECTS: &'static str = linear::SUBJECTS;

    fn runs_on(subject: &Subject) -> bool {
        linear::runs_on(subject)
    }

    fn resolve(cx: &Cx, own: MilneSpec, _: &CheckSpec) -> Result<Self, InputError> {
        Ok(Self {
            linear: linear::resolve_setup(cx, &own.linear())?,
        })
    }
}

impl Evaluate for MilneCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::MILNE)
    }

    /// The weakly coupled systems' values of the model as it is, over the case's airspeeds.
    fn series(&self) -> Option<String> {
        self.linear
            .plain_at_a_condition()
            .then(|| "milne".to_string())
    }

    fn linear(&self) -> Option<&LinearSetup> {
        Some(&self.linear)
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        linear::evaluate(self, at, expectations)
    }
}

impl OnLinear for MilneCheck {
    fn setup(&self) -> &LinearSetup {
        &self.linear
    }

    fn longitudinal(&self) -> bool {
        true
    }

    fn compute(
        &self,
        model: &LinearModel,
        _anchor: Option<Complex>,
        _unmodified: &LinearModel,
        expectations: &[Expectation],
    ) -> Result<Computed, String> {
        let values = expectations
            .iter()
            .map(|e| {
                let name = q::Quantity::parse(&e.quantity).map_or("unknown", |q| q.name());
                quantity(model, &e.quantity).map(|v| (name, v))
            })
            .collect::<Result<_, String>>()?;
        Ok(Computed::values(values))
    }
}

fn quantity(model: &LinearModel, q: &str) -> Result<f64, String> {
    let s = |e: milne::MilneError| e.to_string();
    let idx = |q: &str, prefix: &str| -> Option<(usize, usize)> {
        let rest = q.strip_prefix(prefix)?;
        let b = rest.as_bytes();
        (b.len() == 2).then(|| ((b[0] - b'0') as usize, (b[1] - b'0') as usize))
    };
    if let Some((i, j)) = idx(q, "eq13_a") {
        let e = milne::eq13(model).map_err(s)?;
        return e.element(i, j).ok_or_else(|| format!("no element a{i}{j}"));
    }
    if let Some((i, j)) = idx(q, "schur_a") {
        let r = milne::reduced(model).map_err(s)?;
        let a = milne::as_array3(&r).map_err(s)?;
        return Ok(a[i - 1][j - 1]);
    }
    let e = || milne::eq13(model).map_err(s);
    let cubic = || e()?.cubic().map_err(s);
    Ok(match q {
        "omega_sp_squared" => e()?.omega_sp_squared,
        "cubic_a" => cubic()?.a,
        "cubic_b" => cubic()?.b,
        "cubic_c" => cubic()?.c,
        "delta_b" => cubic()?.coupling.delta_b,
        "delta_c" => cubic()?.coupling.delta_c,
        "delta_a_ph" => cubic()?.sensitivity().delta_a_ph,
        "delta_b_ph" => cubic()?.sensitivity().delta_b_ph,
        "delta_lambda_omega" => cubic()?.sensitivity().delta_lambda_omega,
        "m_omega_eq24" => milne::m_omega_eq24(model).map_err(s)?,
        "m_omega_eq25" => milne::m_omega_eq25(model).map_err(s)?,
        other => return Err(format!("unknown Milne quantity `{other}`")),
    })
}
