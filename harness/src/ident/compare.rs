//! Identified derivatives beside a model's, and a model's prediction of a record beside the
//! record (Theil's inequality coefficient).

use super::*;

/// The derivatives issue 18 and seed 000 call primary: the damping and stiffness of each axis,
/// the rotorspeed's own derivative, and each control's moment.
pub const PRIMARY: [&str; 13] = [
    "X_u", "Z_w", "M_q", "M_w", "Q_Omega", "Y_v", "L_p", "L_v", "N_v", "N_r", "M_eta_s", "L_eta_c",
    "N_eta_p",
];

/// An identified derivative beside a model's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Against {
    pub name: String,
    pub estimate: f64,
    pub standard_error: f64,
    pub lower_95: f64,
    pub upper_95: f64,
    /// The model's value (NaN where the model has no such derivative).
    pub model: f64,
    /// The model's value lies within the identified 95 % bounds (false for NaN).
    pub inside: bool,
    pub primary: bool,
    /// What the same set-up identifies from the model with its flapping states, its response
    /// to the records' controls ([`equivalent::identify_flapping`]), where it was computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub with_flapping: Option<f64>,
    /// That value lies within the identified 95 % bounds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inside_with_flapping: Option<bool>,
}

/// Adds to each row what the set-up identifies from the model with its flapping states
/// (`as_identified`, from [`equivalent::identify_flapping`] or [`equivalent::identify_response`]).
pub fn add_with_flapping(rows: &mut [Against], as_identified: &Identification) {
    for r in rows {
        let v = as_identified
            .derivatives
            .iter()
            .find(|d| d.name == r.name)
            .map(|d| d.estimate);
        r.with_flapping = v;
        r.inside_with_flapping = v.map(|v| v.is_finite() && r.lower_95 <= v && v <= r.upper_95);
    }
}

/// Every identified derivative beside the model's (a linearisation with the identification's
/// state, control and derivative names).
pub fn against(ident: &Identification, model: &LinearModel) -> Vec<Against> {
    ident
        .derivatives
        .iter()
        .map(|d| {
            let m = model.derivative_value(&d.name).unwrap_or(f64::NAN);
            Against {
                name: d.name.clone(),
                estimate: d.estimate,
                standard_error: d.standard_error,
                lower_95: d.lower_95,
                upper_95: d.upper_95,
                model: m,
                inside: m.is_finite() && d.lower_95 <= m && m <= d.upper_95,
                primary: PRIMARY.contains(&d.name.as_str()),
                with_flapping: None,
                inside_with_flapping: None,
            }
        })
        .collect()
}

/// How well a predicted time history matches a measured one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignalComparison {
    pub signal: String,
    pub rms_error: f64,
    /// Theil's inequality coefficient, `rms(p - m) / (rms(p) + rms(m))`: 0 is a perfect match,
    /// 1 the worst.
    pub theil: f64,
}

/// Theil's inequality coefficient of a prediction against a measurement.
pub fn theil_inequality(predicted: &[f64], measured: &[f64]) -> f64 {
    let n = predicted.len().min(measured.len()).max(1) as f64;
    let rms =
        |f: &dyn Fn(usize) -> f64| ((0..n as usize).map(|k| f(k).powi(2)).sum::<f64>() / n).sqrt();
    let num = rms(&|k| predicted[k] - measured[k]);
    let den = rms(&|k| predicted[k]) + rms(&|k| measured[k]);
    if den > 0.0 { num / den } else { 0.0 }
}

/// Flies `model` (states and controls as in `config`) with the controls of `record`, from its
/// first measured state, and compares its states with the record's measured perturbations
/// (seed 000 Fig. 10; [`verify::fly`]).
pub fn predict(
    model: &LinearModel,
    record: &Record,
    config: &ConfigSpec,
) -> Result<Vec<SignalComparison>, String> {
    let (xs, flown) = verify::fly(model, record, config)?;
    Ok(config
        .states
        .iter()
        .enumerate()
        .map(|(i, name)| {
            let c = verify::compare(name, &flown[i], &xs[i]);
            SignalComparison {
                signal: name.clone(),
                rms_error: c.rms_error,
                theil: c.theil,
            }
        })
        .collect())
}
