//! `derivative`: one stability or control derivative, of a linearised aircraft (with its
//! components and, under corrections, the change of its magnitude), of a published table, or
//! the ratio of two derivatives of a model.

use super::linear::{self, Computed, LinearSetup, OnLinear};
use super::{
    At, CheckClass, CheckSpec, Cx, Evaluate, Evaluated, Expectation, Kind, Measured, Place, Placed,
    Refusal, Trivial, is_aircraft,
};
use crate::checks::subject::Subject;
use crate::inputs::quantity::{self as q, Quantity as Q};
use crate::inputs::reference::Entry;
use crate::inputs::yaml::InputError;
use cierva_model::LinearModel;
use cierva_model::analysis::modes::Complex;

/// A `derivative` check.
#[derive(Debug, Clone, PartialEq)]
pub struct DerivativeCheck {
    /// The derivative's name (`M_w`).
    pub derivative: String,
    /// On a model: the check is of the ratio `derivative / divided_by`.
    pub divided_by: Option<String>,
    /// On an aircraft: corrections applied before it is linearised.
    pub corrections: Option<crate::inputs::corrections::CorrectionSet>,
    pub linear: LinearSetup,
}

linear::linear_spec! {
    /// A `derivative` check's own fields, as written.
    pub struct DerivativeSpec {
        /// The derivative's name (`M_w`).
        pub derivative: String,
        /// On a model: check the ratio of `derivative` to this one (`Q_u` divided by `Q_w`).
        #[serde(default)]
        pub divided_by: Option<String>,
        /// On an aircraft: corrections to apply; the check then also computes
        /// `magnitude_change`, `(|corrected| - |uncorrected|) / |uncorrected|`.
        #[serde(default)]
        pub corrections: Option<crate::inputs::corrections::CorrectionSet>,
        /// On an aircraft: the derivative as this identification set-up finds it in the
        /// aircraft linearised with its flapping states, over the set-up's band
        /// ([`crate::run::linearise::identified_in_band_cached`]), not the quasi-static linearisation's.
        #[serde(default)]
        pub as_identified: Option<crate::ident::Setup>,
    }
}

impl Kind for DerivativeCheck {
    type Spec = DerivativeSpec;
    const SUBJECTS: &'static str = "a linear model, a derivative table, or an aircraft or external model linearised at the check's `condition`";

    fn runs_on(subject: &Subject) -> bool {
        matches!(
            subject,
            Subject::Linear { .. }
                | Subject::Table { .. }
                | Subject::Aircraft { .. }
                | Subject::External(_)
        )
    }

    fn resolve(cx: &Cx, own: DerivativeSpec, written: &CheckSpec) -> Result<Self, InputError> {
        let derivative = own.derivative.clone();
        let spec = &own;
        let linear = match cx.subject {
            Subject::Table { table, column, .. } => {
                resolve_on_table(cx, spec, table, column, &derivative)?;
                LinearSetup::default()
            }
            _ => {
                let mut setup = linear::resolve_setup(cx, &spec.linear())?;
                for name in std::iter::once(&derivative).chain(spec.divided_by.iter()) {
                    linear::check_derivative(cx, name, ".derivative")?;
                }
                if let Some(s) = spec.as_identified {
                    resolve_as_identified(cx, spec, written, s, &derivative)?;
                    setup.as_identified = Some(s);
                }
                setup
            }
        };
        if let Some(k) = &spec.corrections {
            let Some((model, _)) = super::flight_model(cx.subject) else {
                return Err(cx.err(
                    ".corrections",
                    "`corrections` apply to a case whose model is an aircraft or an external model",
                ));
            };
            crate::external::corrected(model.as_ref(), k).map_err(|e| cx.err(".corrections", e))?;
        }
        let magnitude = Q::MagnitudeChange.name();
        if spec.corrections.is_none() && written.expect.contains_key(magnitude) {
            return Err(cx.err(
                &format!(".expect.{magnitude}"),
                "`magnitude_change` compares with corrections: give `corrections`",
            ));
        }
        if spec.divided_by.is_some() && written.expect.keys().any(|q| q != Q::Value.name()) {
            return Err(cx.err(".divided_by", "a ratio of derivatives has only a `value`"));
        }
        let computed_here = |q: &str| {
            q == Q::Value.name()
                || (q == Q::MagnitudeChange.name() && super::is_flight_model(cx.subject))
        };
        if !is_aircraft(cx.subject)
            && let Some(q) = written.expect.keys().find(|q| !computed_here(q))
        {
            return Err(cx.err(
                &format!(".expect.{q}"),
                format!(
                    "`{q}` (a component of the derivative) is computed for aircraft cases only (a model behind the model interface gives its linear model whole); this case computes [{}]",
                    if super::is_flight_model(cx.subject) {
                        "value, magnitude_change"
                    } else {
                        "value"
                    }
                ),
            ));
        }
        Ok(Self {
            derivative,
            divided_by: own.divided_by,
            corrections: own.corrections,
            linear,
        })
    }
}

/// `as_identified`: on an aircraft, unmodified, of a derivative the set-up identifies, and only
/// its value (the components and the corrections' change belong to the quasi-static
/// linearisation).
fn resolve_as_identified(
    cx: &Cx,
    spec: &DerivativeSpec,
    written: &CheckSpec,
    setup: crate::ident::Setup,
    derivative: &str,
) -> Result<(), InputError> {
    if !is_aircraft(cx.subject) {
        return Err(cx.err(
            ".as_identified",
            "`as_identified` applies to a case whose model is an aircraft",
        ));
    }
    if !spec.set.is_empty() || spec.without_rotorspeed_coupling || spec.divided_by.is_some() {
        return Err(cx.err(
            ".as_identified",
            "`as_identified` takes the identified model as it is: no `set`, \
             `without_rotorspeed_coupling` or `divided_by`",
        ));
    }
    if let Some(q) = written.expect.keys().find(|q| *q != Q::Value.name()) {
        return Err(cx.err(
            &format!(".expect.{q}"),
            "an identified derivative has only a `value`",
        ));
    }
    let config = crate::ident::ConfigSpec::for_model(setup);
    let template =
        crate::ident::identified_template(&config).map_err(|e| cx.err(".as_identified", e))?;
    template.derivative(derivative).map_err(|e| {
        cx.err(
            ".derivative",
            format!("the {setup:?} set-up does not identify `{derivative}`: {e}"),
        )
    })?;
    Ok(())
}

/// A check of a published table: the table has the derivative, nothing modifies it, and it is
/// `verification` (of the transcription against the paper's statements).
fn resolve_on_table(
    cx: &Cx,
    spec: &DerivativeSpec,
    table: &crate::inputs::reference::DerivativeTable,
    column: &str,
    derivative: &str,
) -> Result<(), InputError> {
    if !spec.set.is_empty() || spec.without_rotorspeed_coupling {
        return Err(cx.err("", "a published derivative table cannot be modified"));
    }
    for field in ["divided_by", "condition"] {
        let given = match field {
            "divided_by" => spec.divided_by.is_some(),
            _ => spec.condition.is_some(),
        };
        if given {
            return Err(cx.err(
                &format!(".{field}"),
                format!("`{field}` does not apply to a check of a derivative table"),
            ));
        }
    }
    if table.entry(derivative, column).is_none() {
        return Err(cx.err(
            ".derivative",
            format!("the table has no `{derivative}` in column `{column}`"),
        ));
    }
    if !matches!(cx.class, CheckClass::Verification | CheckClass::Regression) {
        return Err(cx.err(
            ".class",
            "a derivative table's checks compare published numbers with published numbers and \
             run no model: they are `verification` (of the transcription against the paper's \
             statements)",
        ));
    }
    Ok(())
}

impl Evaluate for DerivativeCheck {
    fn quantities(&self) -> Vec<String> {
        super::names(q::DERIVATIVE)
    }

    fn derivative(&self) -> Option<&str> {
        Some(&self.derivative)
    }

    /// The derivative of the aircraft as it is, over the case's airspeeds.
    fn series(&self) -> Option<String> {
        matches!(self.measured(), Measured::At(_))
            .then(|| format!("derivative {}", self.derivative))
    }

    fn linear(&self) -> Option<&LinearSetup> {
        Some(&self.linear)
    }

    fn corrections(&self) -> Option<&crate::inputs::corrections::CorrectionSet> {
        self.corrections.as_ref()
    }

    /// The derivative of the aircraft as it is at its condition; of the aircraft as the check
    /// changes it (corrections, derivatives set or cut, a ratio, as identified), a modified one.
    fn measured(&self) -> Measured<'_> {
        let Some(condition) = self.linear.condition else {
            return Measured::Elsewhere;
        };
        let l = &self.linear;
        let modified = self.corrections.is_some()
            || self.divided_by.is_some()
            || !l.set.is_empty()
            || l.without_rotorspeed_coupling
            || l.as_identified.is_some();
        if modified {
            Measured::Modified
        } else {
            Measured::At(Place::Flight(condition))
        }
    }

    /// `value` is the derivative; its components and its change under corrections are not the
    /// aircraft's derivatives.
    fn model_name(&self, quantity: &str) -> Option<String> {
        (quantity == Q::Value.name()).then(|| self.derivative.clone())
    }

    fn placed(&self) -> Option<Placed<'_>> {
        let condition = self.linear.condition?;
        Some(Placed::Derivative {
            label: match &self.divided_by {
                Some(by) => format!("{} / {by}", self.derivative),
                None => self.derivative.clone(),
            },
            airspeed_mph: condition.airspeed_mph,
            corrected: self.corrections.is_some(),
            as_identified: self.linear.as_identified.is_some(),
        })
    }

    /// A ratio of two derivatives (`divided_by`).
    fn is_ratio(&self) -> bool {
        self.divided_by.is_some()
    }

    fn trivial(
        &self,
        subject: &Subject,
        expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        match subject {
            Subject::Linear { .. } => Err((
                ".kind".into(),
                "a `derivative` check on a linear model reads back an entry of the model's own \
                 file: it cannot fail (check what cierva computes from it: modes, Milne \
                 values)"
                    .into(),
            )),
            // A ratio of two zero derivatives is not a number, which never passes.
            Subject::Aircraft { .. } | Subject::External(_) if self.divided_by.is_none() => {
                let mut out: Vec<Trivial> = expectations
                    .iter()
                    .map(|e| Trivial {
                        quantity: e.quantity.clone(),
                        value: 0.0,
                        predictor: if e.quantity == Q::MagnitudeChange.name() {
                            "corrections that change nothing"
                        } else {
                            "a zero derivative"
                        },
                        verdict: false,
                    })
                    .collect();
                let kinematic = self
                    .linear
                    .condition
                    .and_then(|c| kinematic_or_gravity(&self.derivative, c.airspeed_mph));
                if let Some((value, predictor)) = kinematic {
                    out.extend(
                        expectations
                            .iter()
                            .filter(|e| e.quantity == Q::Value.name())
                            .map(|e| Trivial {
                                quantity: e.quantity.clone(),
                                value,
                                predictor,
                                verdict: false,
                            }),
                    );
                }
                Ok(out)
            }
            _ => Ok(vec![]),
        }
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let Subject::Table { table, column, .. } = at.subject else {
            return linear::evaluate(self, at, expectations);
        };
        let d = &self.derivative;
        let value = match table.entry(d, column) {
            Some(Entry::Value(v)) => v,
            _ => return Err(format!("no value of `{d}` in column `{column}`")),
        };
        let q = expectations
            .iter()
            .map(|e| super::result::compare(e, value, || Ok(0.0)))
            .collect::<Result<_, _>>()?;
        Ok(Evaluated::of(q))
    }
}

impl OnLinear for DerivativeCheck {
    fn setup(&self) -> &LinearSetup {
        &self.linear
    }

    fn corrections(&self) -> Option<&crate::inputs::corrections::CorrectionSet> {
        self.corrections.as_ref()
    }

    fn compute(
        &self,
        model: &LinearModel,
        _anchor: Option<Complex>,
        _unmodified: &LinearModel,
        _expectations: &[Expectation],
    ) -> Result<Computed, String> {
        let mut v = model
            .derivative_value(&self.derivative)
            .map_err(|e| e.to_string())?;
        if let Some(by) = &self.divided_by {
            v /= model.derivative_value(by).map_err(|e| e.to_string())?;
        }
        Ok(Computed::values(vec![(Q::Value.name(), v)]))
    }

    /// `magnitude_change`, `(|corrected| - |uncorrected|) / |uncorrected|`, and the
    /// derivative's components (rotor, propeller, airframe...).
    fn of_linearisation(
        &self,
        q: &str,
        at: &linear::AtCondition<'_>,
    ) -> Option<Result<f64, String>> {
        let d = &self.derivative;
        if q == Q::MagnitudeChange.name() {
            return Some((|| {
                let b = at.uncorrected(d)?;
                let c = at.linear.derivative_value(d).map_err(|e| e.to_string())?;
                Ok((c.abs() - b.abs()) / b.abs())
            })());
        }
        if q == Q::Value.name() {
            return None;
        }
        Some((|| {
            at.breakdown(d)?
                .iter()
                .find(|(c, _)| c == q)
                .map(|(_, v)| *v)
                .ok_or_else(|| format!("no component `{q}`"))
        })())
    }
}

/// What any aircraft that trims at `airspeed_mph` gives for a derivative that is (nearly) a
/// kinematic or gravity term of the body equations, with the trim's attitude and angle of attack
/// taken as small: `Z_q = u0`, `Y_r = -u0`, `X_theta = -g cos theta0`, `Y_phi = g cos theta0`
/// (`u0` the airspeed). A check such a predictor passes is a check of the trim speed or of
/// gravity, not of the aircraft.
pub fn kinematic_or_gravity(derivative: &str, airspeed_mph: f64) -> Option<(f64, &'static str)> {
    const G: f64 = 9.80665;
    let u0 = airspeed_mph * crate::units::MPH_TO_M_S;
    match derivative {
        "Z_q" => Some((u0, "the kinematic term alone (Z_q = u0, the trim airspeed)")),
        "Y_r" => Some((
            -u0,
            "the kinematic term alone (Y_r = -u0, the trim airspeed)",
        )),
        "X_theta" => Some((-G, "gravity alone (X_theta = -g cos theta0, level)")),
        "Y_phi" => Some((G, "gravity alone (Y_phi = g cos theta0, level)")),
        _ => None,
    }
}
