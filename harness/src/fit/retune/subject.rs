//! What a retune corrects: cierva's aircraft file (its corrections and estimated physical
//! parameters, its responses from the linearisation with the rotor's flapping), or any model
//! behind the model interface (its declared parameters, its responses from its `A` and `B`).
//! Everything a retune asks of the model (the parameters and their bounds, the responses and
//! the linear model at a set of values, what the corrections file applies to) goes through
//! here, so that the retune itself is one path for both.

use super::{RetuneParameter, responses};
use crate::fit::{FitParameter, FitSubject, ParameterKind, TargetCondition};
use crate::inputs::aircraft::AircraftFile;
use crate::inputs::corrections::{CorrectionSet, Corrects};
use crate::run::responses::Responses;

/// What a retune corrects.
#[derive(Debug, Clone, Copy)]
pub enum Retuned<'a> {
    /// cierva's aircraft file.
    Aircraft(&'a AircraftFile),
    /// A model behind the model interface, as a case writes it (the loading is each record's).
    Model(&'a crate::external::External),
}

impl Retuned<'_> {
    /// What it is, in a few words: the aircraft file's id, or the model as its cases write it.
    pub fn name(&self) -> String {
        match self {
            Self::Aircraft(f) => f.id.clone(),
            Self::Model(e) => e.written.clone(),
        }
    }

    /// What a corrections file of it applies to.
    pub fn corrects(&self) -> Corrects {
        match self {
            Self::Aircraft(f) => Corrects::Aircraft(f.id.clone()),
            Self::Model(e) => Corrects::Model(e.written.clone()),
        }
    }

    /// The fit's subject.
    pub fn fit_subject(&self) -> FitSubject {
        match self {
            Self::Aircraft(f) => FitSubject::Aircraft {
                file: Box::new((*f).clone()),
            },
            Self::Model(e) => FitSubject::Model {
                model: e.model.clone(),
            },
        }
    }

    /// The parameters, with their bounds and the bounds' sources: an aircraft's correction from
    /// the request or [`super::DEFAULT_BOUNDS`], its physical parameter within the file's plausible
    /// range; a model's declared parameter within its declared range.
    pub fn parameters(
        &self,
        requests: &[RetuneParameter],
    ) -> Result<Vec<(FitParameter, String)>, String> {
        match self {
            Self::Aircraft(file) => super::parameters(file, requests),
            Self::Model(e) => {
                let declared = e.model.parameters()?;
                requests
                    .iter()
                    .map(|r| {
                        let unbounded = |p: &&crate::external::Parameter| {
                            p.name == r.name && p.range.is_none()
                        };
                        if r.bounds.is_none() && declared.iter().any(|p| unbounded(&p)) {
                            return Err(format!(
                                "`{0}`: the model declares no range for it: give its bounds on the command line, `--bounds {0}=LO:HI`",
                                r.name
                            ));
                        }
                        let (lower, upper, start) = crate::fit::file::declared_parameter(
                            &declared,
                            &r.name,
                            (r.bounds.map(|b| b.0), r.bounds.map(|b| b.1), None),
                        )
                        .map_err(|m| format!("`{}`: {m}", r.name))?;
                        if lower >= upper {
                            return Err(format!(
                                "`{}`: bounds [{lower}, {upper}] must have lower < upper",
                                r.name
                            ));
                        }
                        let source = match r.bounds {
                            Some(_) => "asked for on the command line (--bounds)".to_string(),
                            None => declared
                                .iter()
                                .find(|p| p.name == r.name)
                                .and_then(|p| p.range.as_ref())
                                .map_or(String::new(), |x| x.source.clone()),
                        };
                        Ok((
                            FitParameter {
                                kind: ParameterKind::Declared(r.name.clone()),
                                lower,
                                upper,
                                start,
                                regularisation: 0.0,
                            },
                            source,
                        ))
                    })
                    .collect()
            }
        }
    }

    /// The model behind the model interface: cierva's aircraft file, or the model.
    pub fn flight_model(&self) -> Box<dyn crate::external::FlightModel + '_> {
        match self {
            Self::Aircraft(file) => Box::new(crate::external::CiervaAircraft::new(file)),
            Self::Model(e) => Box::new(e.model.clone()),
        }
    }

    /// A request at a flight condition with the values of `values` by the names the model
    /// declares ([`CorrectionSet::as_declared`]).
    fn request(
        values: &CorrectionSet,
        condition: crate::inputs::condition::TrimRequest,
        loading: crate::inputs::condition::Loading,
    ) -> crate::external::Request {
        crate::external::Request {
            condition,
            loading,
            parameters: values.as_declared(),
            start: None,
        }
    }

    /// The responses at every condition of `estimated` (with `neighbourhood` at the
    /// neighbours of every used point, [`responses::neighbours`]), with the values of
    /// `values` (an empty set: the file or the model as it is), conditions in parallel.
    pub fn responses(
        &self,
        values: &CorrectionSet,
        estimated: &[responses::RecordedResponse],
        neighbourhood: bool,
    ) -> Result<Vec<(TargetCondition, Responses)>, String> {
        let model = self.flight_model();
        let conditions = responses::frequencies_by_condition(estimated, neighbourhood);
        crate::run::parallel::parallel_map(&conditions, |(c, frequencies)| {
            self.responses_at(model.as_ref(), values, c, frequencies)
                .map(|m| (*c, m))
        })
        .into_iter()
        .collect()
    }

    /// `model`'s responses (this subject's [`Self::flight_model`]) at one condition and
    /// `frequencies_hz`, with the values of `values`.
    pub fn responses_at(
        &self,
        model: &dyn crate::external::FlightModel,
        values: &CorrectionSet,
        condition: &TargetCondition,
        frequencies_hz: &[f64],
    ) -> Result<Responses, String> {
        let TargetCondition::Flight(request, loading) = *condition else {
            return Err("a retune's condition is a flight condition".to_string());
        };
        model
            .responses(&Self::request(values, request, loading), frequencies_hz)
            .map_err(|e| format!("at {}: {e}", condition.label()))
    }

    /// The linear model at a flight condition with the values of `values`: the aircraft's
    /// quasi-static linearisation, or the model's linear model.
    pub fn linear_model(
        &self,
        values: &CorrectionSet,
        request: crate::inputs::condition::TrimRequest,
        loading: crate::inputs::condition::Loading,
    ) -> Result<cierva_model::LinearModel, String> {
        self.flight_model()
            .linear_model(&Self::request(values, request, loading))
            .map_err(|e| format!("at {} mph: {e}", request.airspeed_mph))
    }
}
