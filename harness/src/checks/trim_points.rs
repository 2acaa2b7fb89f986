//! `trim_points`: the model trimmed at each of a flight test's trim points (their airspeeds,
//! and their masses and density altitudes where the file gives them), compared with the
//! points as a level and a trend judged together against the points' own scatter.
//!
//! For each quantity measured at points `i` with scatter `s_i`, the model's error `r_i =
//! model_i - flight_i` is fitted by weighted least squares (`w_i = 1 / s_i^2`) as `r = a + b
//! (v - v_w)`, `v_w` the weighted mean airspeed:
//! - `<q>.level_error` = `a`, the model's offset at `v_w`, with variance `1 / sum w`;
//! - `<q>.trend_error_per_mph` = `b`, its error in slope, variance `1 / sum w (v - v_w)^2` (the
//!   two are uncorrelated about `v_w`);
//! - `<q>.level_trend_chi2` = `a^2 sum w + b^2 sum w (v - v_w)^2`: chi-square with 2 degrees
//!   of freedom where the model is right and the scatter is the points' standard deviation
//!   (95 % of such checks give at most 5.991);
//! - `<q>.residual_chi2` = `sum w (r - a - b (v - v_w))^2`: the scatter about the fitted error,
//!   chi-square with `n - 2` degrees of freedom (a curvature the model misses, or a scatter
//!   stated too small).
//!
//! A constant trim (the points' weighted mean at every airspeed) is the trivial predictor: a
//! check it passes cannot tell the model from a constant, and is refused at load.

use super::result::{Evaluated, compare_all};
use super::{At, CheckSpec, Cx, Evaluate, Expectation, Kind, Refusal, Trivial};
use crate::checks::subject::Subject;
use crate::inputs::trim_points::{MIN_POINTS, PointValue, TrimPoints};
use crate::inputs::yaml::InputError;

/// A `trim_points` check.
#[derive(Debug, Clone, PartialEq)]
pub struct TrimPointsCheck {
    /// The points (loaded, checked).
    pub points: Box<TrimPoints>,
}

/// A `trim_points` check's own fields, as written.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrimPointsSpec {
    /// The trim points CSV (its sidecar beside it), relative to the case file.
    pub points: String,
}

/// What a `trim_points` check computes of each quantity.
pub const METRICS: [&str; 4] = [
    "level_error",
    "trend_error_per_mph",
    "level_trend_chi2",
    "residual_chi2",
];

impl Kind for TrimPointsCheck {
    type Spec = TrimPointsSpec;
    const SUBJECTS: &'static str = super::FLIGHT_MODELS;

    fn runs_on(subject: &Subject) -> bool {
        super::is_flight_model(subject)
    }

    fn resolve(cx: &Cx, own: TrimPointsSpec, written: &CheckSpec) -> Result<Self, InputError> {
        let points = crate::inputs::trim_points::load(&cx.dir.join(&own.points))
            .map_err(|e| cx.err(".points", format!("in the trim points: {e}")))?;
        // Each quantity the check judges has a level and a trend to fit: enough points, at two
        // airspeeds or more (a quantity only carried along may have fewer).
        for q in judged(written.expect.keys().map(String::as_str)) {
            let series = points.series(&q);
            if series.is_empty() {
                continue;
            }
            let (lo, hi) = series
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (v, _)| {
                    (lo.min(*v), hi.max(*v))
                });
            if series.len() < MIN_POINTS || hi <= lo {
                return Err(cx.err(
                    ".points",
                    format!(
                        "{}: `{q}` is measured at {} point(s){}: a level and a trend need at \
                         least {MIN_POINTS} points at two airspeeds or more (MIN_POINTS)",
                        points.path.display(),
                        series.len(),
                        if series.len() > 1 && hi <= lo {
                            ", all at one airspeed"
                        } else {
                            ""
                        }
                    ),
                ));
            }
        }
        // Each point's loading is one the model can be asked at (cierva's aircraft: within
        // its maximum all-up mass): an error at the point's line, not at its trim.
        if let Some((model, loading)) = super::flight_model(cx.subject) {
            for p in &points.points {
                let at = point_loading(p, loading);
                model.check_loading(&at).map_err(|e| {
                    cx.err(
                        ".points",
                        format!("{}:{}: {e}", points.path.display(), p.line),
                    )
                })?;
            }
        }
        Ok(Self {
            points: Box::new(points),
        })
    }
}

/// A quantity's error against the points, fitted as a level and a trend (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelAndTrend {
    /// The weighted mean airspeed the level is at, mph.
    pub airspeed_mph: f64,
    pub level: f64,
    pub level_sd: f64,
    pub trend_per_mph: f64,
    pub trend_sd: f64,
    pub level_trend_chi2: f64,
    pub residual_chi2: f64,
    /// The residual's degrees of freedom, `n - 2`.
    pub residual_dof: usize,
}

impl LevelAndTrend {
    /// The fit of the model's values `model[i]` against the points `(airspeed, measured)`.
    pub fn fit(points: &[(f64, PointValue)], model: &[f64]) -> Self {
        let w: Vec<f64> = points.iter().map(|(_, m)| m.sd.powi(-2)).collect();
        let r: Vec<f64> = points
            .iter()
            .zip(model)
            .map(|((_, m), y)| y - m.value)
            .collect();
        let sw: f64 = w.iter().sum();
        let v_w = points.iter().zip(&w).map(|((v, _), w)| w * v).sum::<f64>() / sw;
        let dv: Vec<f64> = points.iter().map(|(v, _)| v - v_w).collect();
        let sxx: f64 = w.iter().zip(&dv).map(|(w, d)| w * d * d).sum();
        let level = w.iter().zip(&r).map(|(w, r)| w * r).sum::<f64>() / sw;
        let trend = w
            .iter()
            .zip(&dv)
            .zip(&r)
            .map(|((w, d), r)| w * d * r)
            .sum::<f64>()
            / sxx;
        let residual_chi2 = w
            .iter()
            .zip(&dv)
            .zip(&r)
            .map(|((w, d), r)| w * (r - level - trend * d).powi(2))
            .sum();
        Self {
            airspeed_mph: v_w,
            level,
            level_sd: sw.powf(-0.5),
            trend_per_mph: trend,
            trend_sd: sxx.powf(-0.5),
            level_trend_chi2: level * level * sw + trend * trend * sxx,
            residual_chi2,
            residual_dof: points.len().saturating_sub(2),
        }
    }

    /// The metric named `m` ([`METRICS`]).
    fn get(&self, m: &str) -> f64 {
        match m {
            "level_error" => self.level,
            "trend_error_per_mph" => self.trend_per_mph,
            "level_trend_chi2" => self.level_trend_chi2,
            "residual_chi2" => self.residual_chi2,
            _ => f64::NAN,
        }
    }
}

/// The quantities expectations judge (`<quantity>.<metric>`), each once, in order.
fn judged<'a>(expected: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for e in expected {
        if let Some((q, m)) = e.rsplit_once('.')
            && METRICS.contains(&m)
            && !out.iter().any(|o| o == q)
        {
            out.push(q.to_string());
        }
    }
    out
}

impl TrimPointsCheck {
    /// The metrics of every quantity, named `<quantity>.<metric>`.
    fn values(fits: &[(String, LevelAndTrend)]) -> Vec<(String, f64)> {
        fits.iter()
            .flat_map(|(q, f)| METRICS.iter().map(move |m| (format!("{q}.{m}"), f.get(m))))
            .collect()
    }
}

impl Evaluate for TrimPointsCheck {
    fn input_notes(&self) -> Vec<(std::path::PathBuf, String)> {
        super::notes_of(&self.points.path, &self.points.notes)
    }

    fn quantities(&self) -> Vec<String> {
        self.points
            .quantities
            .iter()
            .flat_map(|q| METRICS.iter().map(move |m| format!("{q}.{m}")))
            .collect()
    }

    /// Its metrics are errors and chi-squares (zero is a perfect fit).
    fn zero_predicts(&self, _quantity: &str) -> bool {
        false
    }

    /// A quantity judged by its level alone, or by the scatter about its fitted error alone:
    /// a trim that does not change with airspeed, at the points' mean, has no level error by
    /// construction, and the scatter says nothing of level or trend, so such a check cannot
    /// tell the model from a constant. Each judged quantity needs its trend judged
    /// (`trend_error_per_mph`, or `level_trend_chi2`, level and trend together). A quantity
    /// flat within its scatter is still judged: the chi-square then weighs the model's level.
    fn trivial(
        &self,
        _subject: &Subject,
        expectations: &[Expectation],
    ) -> Result<Vec<Trivial>, Refusal> {
        for q in judged(expectations.iter().map(|e| e.quantity.as_str())) {
            let of_q: Vec<&Expectation> = expectations
                .iter()
                .filter(|e| e.quantity.rsplit_once('.').is_some_and(|(p, _)| p == q))
                .collect();
            let trend = of_q.iter().any(|e| {
                e.quantity.ends_with(".trend_error_per_mph")
                    || e.quantity.ends_with(".level_trend_chi2")
            });
            if !trend {
                return Err((
                    format!(".expect.{}", of_q[0].quantity),
                    format!(
                        "`{q}` is judged by its level or its scatter alone: a trim that does not \
                         change with airspeed (at the points' mean) passes a level by \
                         construction, so the check cannot tell the model from a constant. Judge \
                         its trend too (`{q}.trend_error_per_mph`, or `{q}.level_trend_chi2`: \
                         level and trend together)"
                    ),
                ));
            }
        }
        Ok(vec![])
    }

    fn evaluate(&self, at: &At, expectations: &[Expectation]) -> Result<Evaluated, String> {
        let (model, loading) = super::flight_model(at.subject)
            .ok_or_else(|| format!("a trim_points check needs {}", super::FLIGHT_MODELS))?;
        let path = self.points.path.display();
        let judged = judged(expectations.iter().map(|e| e.quantity.as_str()));
        // The points that carry a quantity the check judges, each trimmed once.
        let needed: Vec<&crate::inputs::trim_points::FlightTrimPoint> = self
            .points
            .points
            .iter()
            .filter(|p| judged.iter().any(|q| p.values.contains_key(q)))
            .collect();
        let trims = needed
            .iter()
            .map(|p| {
                let request = crate::external::Request::at(
                    crate::inputs::condition::TrimRequest::level(p.airspeed_mph),
                    point_loading(p, loading),
                );
                model.trim(&request).map_err(|e| {
                    format!(
                        "the point at {path}:{} ({:.2} mph) is outside the model's envelope, or \
                         its trim failed: {e}",
                        p.line, p.airspeed_mph
                    )
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
        // Each judged quantity at its points, against the model there, and its fit.
        let mut drawn = Vec::new();
        let mut fits = Vec::new();
        for q in &judged {
            let mut at_points = Vec::new();
            for (p, t) in needed.iter().zip(&trims) {
                let Some(m) = p.values.get(q) else { continue };
                let model_value = t.iter().find(|(n, _)| n == q).map(|x| x.1).ok_or_else(|| {
                    format!(
                        "{} gives no `{q}` in its trim at {:.2} mph ({path} measures it)",
                        model.describe(),
                        p.airspeed_mph
                    )
                })?;
                at_points.push(super::result::PointAgainstModel {
                    airspeed_mph: p.airspeed_mph,
                    flight: m.value,
                    sd: m.sd,
                    model: model_value,
                });
            }
            let series: Vec<(f64, PointValue)> = at_points
                .iter()
                .map(|a| {
                    (
                        a.airspeed_mph,
                        PointValue {
                            value: a.flight,
                            sd: a.sd,
                        },
                    )
                })
                .collect();
            let model_values: Vec<f64> = at_points.iter().map(|a| a.model).collect();
            fits.push((q.clone(), LevelAndTrend::fit(&series, &model_values)));
            drawn.push((q.clone(), at_points));
        }
        let values = Self::values(&fits);
        let values: Vec<(&str, f64)> = values.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        let note = fits
            .iter()
            .map(|(q, f)| {
                format!(
                    "{q}: level {:+.3} +- {:.3} at {:.1} mph, trend {:+.4} +- {:.4} per mph \
                     (1 sd, from the points' scatter), residual chi-square {:.2} on {} dof",
                    f.level,
                    f.level_sd,
                    f.airspeed_mph,
                    f.trend_per_mph,
                    f.trend_sd,
                    f.residual_chi2,
                    f.residual_dof
                )
            })
            .collect::<Vec<_>>()
            .join("; ");
        Ok(Evaluated {
            note: Some(note),
            plot: Some(super::result::PlotData::TrimPoints { quantities: drawn }),
            ..Evaluated::of(compare_all(expectations, &values)?)
        })
    }
}

/// A point's loading: its own mass and density altitude where the file gives them, its case's
/// otherwise.
fn point_loading(
    p: &crate::inputs::trim_points::FlightTrimPoint,
    case: crate::inputs::condition::Loading,
) -> crate::inputs::condition::Loading {
    crate::inputs::condition::Loading {
        mass_kg: p.mass_kg.or(case.mass_kg),
        density_altitude_ft: p.density_altitude_ft.unwrap_or(case.density_altitude_ft),
    }
}
