//! `time_history`: a reference record's control changes flown again by the model from trim,
//! its responses compared with the record's, signal by signal (`<signal>.<metric>`, see
//! [`crate::run::replay`]).

use super::result::{Evaluated, PlotData, Trace, compare_all};
use super::{At, CheckSpec, Cx, Evaluate, Expectation, Kind, Refusal, Snapshotted, Trivial};
use crate::checks::subject::Subject;
use crate::checks::tolerance::ToleranceKind;
use crate::inputs::record::Record;
use crate::inputs::yaml::InputError;
use crate::run::replay::{self, Simulation};

/// A `time_history` check.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeHistoryCheck {
    /// The reference record (loaded, its channels checked).
    pub reference: Box<Record>,
    /// The trim the record starts from.
    pub condition: crate::inputs::condition::TrimRequest,
    /// The model that flies it.
    pub simulation: Simulation,
    /// The full blade model's azimuth step, deg (default the aircraft file's).
    pub azimuth_step_deg: Option<f64>,
    /// Corrections applied to the aircraft first.
    pub corrections: Option<crate::inputs::corrections::CorrectionSet>,
}

/// A `time_history` check's own fields, as written.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeHistorySpec {
    /// The reference record CSV (its sidecar beside it), relative to the case file.
    pub reference: String,
    /// The trim the record starts from.
    pub condition: crate::inputs::condition::TrimRequest,
    /// The model that flies the record (default the full blade model).
    #[serde(default)]
    pub simulation: Option<Simulation>,
    /// With the full blade model: the azimuth step, deg (default the aircraft file's).
    #[serde(default)]
    pub azimuth_step_deg: Option<f64>,
    /// Corrections applied to the aircraft first.
    #[serde(default)]
    pub corrections: Option<crate::inputs::corrections::CorrectionSet>,
    /// Why the check's condition or loading differs from its record's sidecar, where it does
    /// on purpose (otherwise a difference is an error).
    #[serde(default)]
    pub condition_differs_from_record: Option<String>,
}

impl Kind for TimeHistoryCheck {
    type Spec = TimeHistorySpec;
    const SUBJECTS: &'static str = super::FLIGHT_MODELS;

    fn runs_on(subject: &Subject) -> bool {
        super::is_flight_model(subject)
    }

    fn resolve(cx: &Cx, own: TimeHistorySpec, _: &CheckSpec) -> Result<Self, InputError> {
        let spec = &own;
        let reference = &spec.reference;
        let (model, _) = super::flight_model(cx.subject).ok_or_else(|| {
            cx.err(
                "",
                format!("a time_history check needs {}", super::FLIGHT_MODELS),
            )
        })?;
        let simulation = spec.simulation.unwrap_or_default();
        if model
            .simulated_by(simulation, spec.azimuth_step_deg.map(f64::to_radians))
            .is_none()
        {
            for (field, given) in [
                ("simulation", spec.simulation.is_some()),
                ("azimuth_step_deg", spec.azimuth_step_deg.is_some()),
            ] {
                if given {
                    return Err(cx.err(
                        &format!(".{field}"),
                        format!(
                            "`{field}` chooses one of a model's simulations; {} has one, and \
                             flies the record as it is",
                            model.describe()
                        ),
                    ));
                }
            }
        }
        let condition = spec.condition;
        let linear = simulation == Simulation::Linear;
        if let Some(a) = spec.azimuth_step_deg {
            if linear {
                return Err(cx.err(
                    ".azimuth_step_deg",
                    "`azimuth_step_deg` applies to the full blade model only",
                ));
            }
            if !crate::inputs::limits::azimuth_step_ok(a, 30.0) {
                return Err(cx.err(
                    ".azimuth_step_deg",
                    format!(
                        "must be in [{}, 30] deg (MIN_AZIMUTH_STEP_DEG), got {a}",
                        crate::inputs::limits::MIN_AZIMUTH_STEP_DEG
                    ),
                ));
            }
        }
        super::check_condition(cx, &condition, linear)?;
        if let Some(k) = &spec.corrections {
            crate::external::corrected(model.as_ref(), k).map_err(|e| cx.err(".corrections", e))?;
        }
        let record = load_reference(cx, reference)?;
        super::condition_matches_record(
            cx,
            ".condition",
            &condition,
            &record,
            spec.condition_differs_from_record.as_deref(),
        )?;
        Ok(Self {
            reference: Box::new(record),
            condition,
            simulation,
            azimuth_step_deg: spec.azimuth_step_deg,
            corrections: own.corrections,
        })
    }
}

/// The record: its controls (named in the sidecar) and the responses cierva computes
/// ([`replay::SIGNALS`], converted from other units where the record has them so), which the
/// check compares; other channels are kept and not compared, the record's notes say which. A
/// channel a letter or two from a response the record lacks is a misnamed one: an error that
/// names both, not a response silently left out.
fn load_reference(cx: &Cx, file: &str) -> Result<Record, InputError> {
    let mut rec =
        crate::inputs::record::load_using(&cx.dir.join(file), &["time_s"], true, &replay::SIGNALS)
            .map_err(|e| cx.err(".reference", format!("in the referenced record: {e}")))?;
    let absent: Vec<&str> = replay::SIGNALS
        .iter()
        .copied()
        .filter(|s| rec.channel(s).is_none())
        .collect();
    let mut ignored = Vec::new();
    for ch in &rec.channels {
        if ch == "time_s"
            || rec.meta.controls.contains(ch)
            || replay::SIGNALS.contains(&ch.as_str())
        {
            continue;
        }
        if let Some(near) = absent.iter().find(|s| {
            crate::inputs::yaml::edit_distance(ch, s) <= crate::inputs::yaml::NEAR_MISS_EDITS
        }) {
            return Err(cx.err(
                ".reference",
                format!(
                    "the record's channel `{ch}` is neither a control nor a response cierva computes; did you mean `{near}`? (rename it, or map it in the sidecar's `channels:`)"
                ),
            ));
        }
        ignored.push(ch.clone());
    }
    if !ignored.is_empty() {
        rec.notes.push(format!(
            "not compared (neither a control nor a response cierva computes: {}): `{}`",
            replay::SIGNALS.join(", "),
            ignored.join("`, `")
        ));
    }
    if replay::record_signals(&rec).is_empty() {
        return Err(cx.err(
            ".reference",
            format!(
                "the record has none of the responses cierva computes ({}) to compare",
                replay::SIGNALS.join(", ")
            ),
        ));
    }
    replay::record_controls(&rec).map_err(|e| cx.err(".reference", e))?;
    Ok(rec)
}

impl Evaluate for TimeHistoryCheck {
    fn condition(&self) -> Option<crate::inputs::condition::TrimRequest> {
        Some(self.condition)
    }

    fn corrections(&self) -> Option<&crate::inputs::corrections::CorrectionSet> {
        self.corrections.as_ref()
    }

    fn snapshotted(&self) -> Vec<Snapshotted<'_>> {
        vec![Snapshotted::TimeHistory(self)]
    }

    fn input_notes(&self) -> Vec<(std::path::PathBuf, String)> {
        super::notes_of(&self.reference.path, &self.reference.notes)
    }

    fn quantities(&self) -> Vec<String> {
        replay::record_signals(&self.reference)
            .iter()
            .flat_map(|s| replay::METRICS.iter().map(move |m| format!("{s}.{m}")))
            .collect()
    }

    /// Its metrics are errors (zero is a perfect fit): a model with no response stands in.
    fn zero_predicts(&self, _quantity: &str) -> bool {
        false
    }

    /// A model with no response, and one that holds still at the record's own mean.
    fn trivial(
        &self,
        _subject: &Subject,
        _expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        let record = &self.reference;
        let zero =
            replay::zero_response_metrics(record).map_err(|e| (".reference".to_string(), e))?;
        let mean =
            replay::mean_response_metrics(record).map_err(|e| (".reference".to_string(), e))?;
        let who = [
            "a model with no response",
            "a model that holds still at the record's own mean",
        ];
        Ok(zero
            .iter()
            .map(|m| (m, who[0]))
            .chain(mean.iter().map(|m| (m, who[1])))
            .flat_map(|(m, predictor)| {
                replay::METRICS.iter().map(move |q| Trivial {
                    quantity: format!("{}.{q}", m.signal),
                    value: m.get(q).unwrap_or(f64::NAN),
                    predictor,
                    verdict: false,
                })
            })
            .collect())
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let (metrics, flown) = self.flown(at.subject)?;
        let values: Vec<(String, f64)> = metrics
            .iter()
            .flat_map(|m| {
                replay::METRICS
                    .iter()
                    .map(|q| (format!("{}.{q}", m.signal), m.get(q).unwrap_or(f64::NAN)))
            })
            .collect();
        let values: Vec<(&str, f64)> = values.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        Ok(Evaluated {
            plot: self.plot(expectations, &flown),
            ..Evaluated::of(compare_all(expectations, &values)?)
        })
    }
}

impl TimeHistoryCheck {
    /// The record flown by `subject`'s flight model (by the check's simulation where the
    /// model has more than one, with the check's corrections), compared response by response;
    /// and the flight.
    pub fn flown(
        &self,
        subject: &Subject,
    ) -> Result<(Vec<replay::SignalMetrics>, replay::Replayed), String> {
        let (plain, loading) = super::flight_model(subject)
            .ok_or_else(|| format!("a time_history check needs {}", super::FLIGHT_MODELS))?;
        let simulated = plain
            .simulated_by(self.simulation, self.azimuth_step_deg.map(f64::to_radians))
            .unwrap_or_else(|| Box::new(plain.as_ref()));
        let model = crate::external::corrected_by(simulated.as_ref(), self.corrections.as_ref())?;
        fly_model(model.as_ref(), loading, self)
    }

    /// The reference and flown responses, with the largest-error tolerance of each signal
    /// where it is absolute.
    fn plot(&self, expectations: &[Expectation], flown: &replay::Replayed) -> Option<PlotData> {
        let record = &self.reference;
        let time_s = record.channel("time_s")?.to_vec();
        let traces = replay::record_signals(record)
            .into_iter()
            .filter_map(|signal| {
                let reference = record.channel(&signal)?.to_vec();
                let model = flown.signal(&signal)?.to_vec();
                let band = expectations
                    .iter()
                    .find(|e| e.quantity == format!("{signal}.max_abs_error"))
                    .and_then(|e| match e.tolerance.kind {
                        ToleranceKind::Absolute(b) => Some(b),
                        ToleranceKind::Interval(_, hi) => Some(hi),
                        _ => None,
                    });
                Some(Trace {
                    signal,
                    time_s: time_s.clone(),
                    reference,
                    model,
                    band,
                })
            })
            .collect();
        Some(PlotData::TimeHistory { traces })
    }
}

/// A `time_history` check's record flown by a flight model, compared response by response:
/// a response the record carries and the model does not give, or gives at other times, is an
/// error.
fn fly_model(
    model: &dyn crate::external::FlightModel,
    loading: crate::inputs::condition::Loading,
    check: &TimeHistoryCheck,
) -> Result<(Vec<replay::SignalMetrics>, replay::Replayed), String> {
    let record = &check.reference;
    let table = replay::record_controls(record)?;
    let samples = table.time_s.len().saturating_sub(1);
    let initial_state = replay::record_signals(record)
        .into_iter()
        .filter_map(|name| {
            let first = *record.channel(&name)?.first()?;
            Some((name, first))
        })
        .collect();
    let controls = crate::external::ControlChanges {
        table,
        sample_s: record.dt_s(),
        samples,
        initial_state,
    };
    let flown = model.time_history(
        &crate::external::Request::at(check.condition, loading),
        &controls,
    )?;
    crate::external::check_response(
        &model.describe(),
        &flown,
        &replay::record_signals(record),
        samples,
    )?;
    Ok((replay::compare(record, &flown)?, flown))
}
