//! From flight records to derivatives: the set-up ([`config`]), a record's signals
//! ([`mod@signals`]), Fourier transforms ([`fourier`]), equation-error regression ([`estimate`]),
//! and identified derivatives beside a model's ([`compare`]); records are
//! [`crate::inputs::record`], synthetic ones [`crate::synth`].
//!
//! [`identify_record`] converts air data to centre-of-mass velocities (seed 000 Eqs. 5-6),
//! takes perturbations about the sidecar's trim, and identifies each force equation in the
//! frequency domain.

pub mod compare;
pub mod config;
pub mod equivalent;
pub mod estimate;
pub mod flap;
pub mod fourier;
pub mod frequency_response;
pub mod signals;
pub mod verify;

use crate::inputs::record::{self, Record};
use cierva_model::LinearModel;
use cierva_model::analysis::linear::FORCE_STATES;
use estimate::{Equation, EquationFit, Frequencies, IdentError, Signals, Windowing};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

pub use compare::*;
pub use config::*;
pub use signals::*;

/// One identified derivative, for tables.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Derivative {
    pub name: String,
    pub estimate: f64,
    pub standard_error: f64,
    pub lower_95: f64,
    pub upper_95: f64,
}

/// The result of identifying a record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identification {
    pub record: String,
    pub fits: Vec<EquationFit>,
    pub derivatives: Vec<Derivative>,
    /// `ok`, or `warnings` when any equation has warnings.
    pub status: &'static str,
    #[serde(skip)]
    pub model: Option<LinearModel>,
}

fn force_letter(state: &str) -> Option<char> {
    FORCE_STATES
        .iter()
        .find(|(_, s)| *s == state)
        .map(|(f, _)| *f)
}

/// Identifies a record with a set-up.
pub fn identify_record(record: &Record, config: &ConfigSpec) -> Result<Identification, String> {
    identify_records(std::slice::from_ref(record), config)
}

/// Identifies several records of one condition together (their spectra concatenated,
/// [`estimate::Spectra::concatenate`]) with one set-up.
pub fn identify_records(records: &[Record], config: &ConfigSpec) -> Result<Identification, String> {
    if records.is_empty() {
        return Err("no record to identify".into());
    }
    let parts = records
        .iter()
        .map(|r| Ok((r.path.display().to_string(), signals(r, config)?, r.dt_s())))
        .collect::<Result<Vec<_>, String>>()?;
    let id = records
        .iter()
        .map(|r| r.meta.id.as_str())
        .collect::<Vec<_>>()
        .join(" + ");
    identify_histories(&id, parts, config).map_err(|e| {
        let paths: Vec<String> = records
            .iter()
            .map(|r| r.path.display().to_string())
            .collect();
        // A sidecar with no trim values (cut short, or written for perturbations) leaves
        // the histories about zero: say so where the fit fails.
        let untrimmed: Vec<String> = records
            .iter()
            .filter(|r| r.meta.trim.is_empty())
            .map(|r| record::sidecar_path(&r.path).display().to_string())
            .collect();
        let hint = if untrimmed.is_empty() {
            String::new()
        } else {
            format!(
                " ({} give{} no `trim:` values, so the histories are taken about zero; give \
                 each state's and control's trim value there, or check the records are \
                 perturbations)",
                untrimmed.join(", "),
                if untrimmed.len() == 1 { "s" } else { "" }
            )
        };
        format!("{}: {e}{hint}", paths.join(" + "))
    })
}

/// One run's perturbation histories for [`identify_histories`]: its name (for messages), the
/// configured states' and controls' histories ([`fn@signals`]), and the sample interval, s.
pub type RunHistories = (String, Histories, f64);

/// Identifies runs of one condition together from their histories: what
/// [`identify_records`] does after reading the records.
pub fn identify_histories(
    id: &str,
    runs: Vec<RunHistories>,
    config: &ConfigSpec,
) -> Result<Identification, String> {
    if runs.is_empty() {
        return Err("no record to identify".into());
    }
    identify_from(id, Source::Runs(runs), config)
}

/// The set-up's frequencies.
pub(crate) fn frequencies(config: &ConfigSpec) -> Result<Frequencies, String> {
    let f = &config.frequencies;
    match (f.from_hz, f.to_hz, f.points, &f.list_hz) {
        (Some(a), Some(b), Some(n), None)
            if a > 0.0
                && b > a
                && (2..=crate::inputs::limits::MAX_FREQUENCY_POINTS).contains(&n) =>
        {
            Ok(Frequencies::Band {
                from_hz: a,
                to_hz: b,
                points: n,
            })
        }
        (None, None, None, Some(l))
            if !l.is_empty() && l.len() <= crate::inputs::limits::MAX_FREQUENCY_POINTS =>
        {
            Ok(Frequencies::List(l.clone()))
        }
        _ => Err(format!(
            "frequencies: give `from_hz` < `to_hz` with `points` from 2 to {} \
             (MAX_FREQUENCY_POINTS), or a non-empty `list_hz`",
            crate::inputs::limits::MAX_FREQUENCY_POINTS
        )),
    }
}

/// What an identification's transforms come from.
pub(crate) enum Source {
    /// Time histories, transformed as the set-up says.
    Runs(Vec<RunHistories>),
    /// Transforms already computed: per excitation, its frequencies (rad/s) and the states'
    /// and controls' transforms at them, `[variable][frequency]`.
    Response(Vec<(Vec<f64>, Vec<Vec<estimate::C>>)>),
}

/// The estimation proper, from either source.
pub(crate) fn identify_from(
    id: &str,
    source: Source,
    config: &ConfigSpec,
) -> Result<Identification, String> {
    let controls: Vec<String> = config.controls.keys().cloned().collect();
    let all: Vec<String> = config.states.iter().chain(&controls).cloned().collect();
    // Every force equation with every state and control free: the default, and the first model
    // that instrumental variables need even when the user identifies only some equations.
    let full: Vec<Equation> = config
        .states
        .iter()
        .filter(|s| force_letter(s).is_some() || FLAP_STATES.contains(&s.as_str()))
        .map(|s| Equation {
            state: s.clone(),
            estimate: all.clone(),
            fixed: vec![],
        })
        .collect();
    let equations: Vec<Equation> = if config.equations.is_empty() {
        full.clone()
    } else {
        config
            .equations
            .iter()
            .map(|e| Equation {
                state: e.state.clone(),
                estimate: e.estimate.clone(),
                fixed: e.fixed.iter().map(|(k, v)| (k.clone(), *v)).collect(),
            })
            .collect()
    };
    let freqs = frequencies(config)?;
    let w = config.windowing.settings();
    let err = |e: IdentError| format!("{id}: {e}");
    // The transforms are computed once; least squares and each instrumental-variable pass use them.
    let mut parts = Vec::new();
    match source {
        Source::Runs(runs) => {
            for (name, (xs, us), dt_s) in &runs {
                let sig = Signals {
                    states: &config.states,
                    controls: &controls,
                    x: xs,
                    u: us,
                    dt_s: *dt_s,
                };
                parts.push(estimate::spectra(sig, &freqs, w).map_err(|e| format!("{name}: {e}"))?);
            }
        }
        Source::Response(excitations) => {
            for (omegas, var_ft) in excitations {
                parts.push(
                    estimate::Spectra::from_response(
                        all.clone(),
                        config.states.len(),
                        &omegas,
                        var_ft,
                    )
                    .map_err(err)?,
                );
            }
        }
    }
    let spectra = estimate::Spectra::concatenate(parts).map_err(err)?;
    let mut fits = estimate::fit_equations(&spectra, &equations, None).map_err(err)?;
    if config.method == Estimator::InstrumentalVariables {
        // The first model: the full least-squares fit, with the user's equations in their rows
        // (instruments need every state's response, not only the identified equations').
        let mut base = if equations == full {
            fits.clone()
        } else {
            estimate::fit_equations(&spectra, &full, None).map_err(err)?
        };
        for _ in 0..2 {
            let merged: Vec<EquationFit> = base
                .iter()
                .map(|b| {
                    fits.iter()
                        .find(|f| f.state == b.state)
                        .unwrap_or(b)
                        .clone()
                })
                .collect();
            let first = identified_model(config, &controls, &merged)?;
            fits =
                estimate::identify_iv(&spectra, &equations, first.a(), first.b()).map_err(err)?;
            base = merged;
        }
    }
    let mut derivatives = Vec::new();
    for fit in &fits {
        let letter = force_letter(&fit.state).map_or(fit.state.clone(), |c| c.to_string());
        for e in &fit.estimates {
            derivatives.push(Derivative {
                name: format!("{letter}_{}", e.variable),
                estimate: e.value,
                standard_error: e.standard_error,
                lower_95: e.lower_95,
                upper_95: e.upper_95,
            });
        }
    }
    let model = identified_model(config, &controls, &fits).ok();
    let status = if fits.iter().any(|f| !f.warnings.is_empty()) {
        "warnings"
    } else {
        "ok"
    };
    Ok(Identification {
        record: id.to_string(),
        fits,
        derivatives,
        status,
        model,
    })
}

/// A model of the set-up's states and controls with every entry zero: what names a set-up's
/// derivatives can take, before anything is identified.
pub fn identified_template(config: &ConfigSpec) -> Result<LinearModel, String> {
    let (n, m) = (config.states.len(), config.controls.len());
    LinearModel::new(
        config.states.clone(),
        config.controls.keys().cloned().collect(),
        nalgebra::DMatrix::zeros(n, n),
        nalgebra::DMatrix::zeros(n, m),
    )
    .map_err(|e| e.to_string())
}

/// The identified linear model: estimated and fixed rows, kinematic rows from the set-up; rows
/// neither identified nor kinematic are zero.
pub fn identified_model(
    config: &ConfigSpec,
    controls: &[String],
    fits: &[EquationFit],
) -> Result<LinearModel, String> {
    let n = config.states.len();
    let mut a = vec![vec![0.0; n]; n];
    let mut b = vec![vec![0.0; controls.len()]; n];
    let col = |name: &str| -> Option<(bool, usize)> {
        config
            .states
            .iter()
            .position(|s| s == name)
            .map(|i| (true, i))
            .or_else(|| controls.iter().position(|c| c == name).map(|i| (false, i)))
    };
    for fit in fits {
        let row = config
            .states
            .iter()
            .position(|s| *s == fit.state)
            .ok_or("unknown state")?;
        let values = fit
            .estimates
            .iter()
            .map(|e| (e.variable.as_str(), e.value))
            .chain(fit.fixed.iter().map(|(k, v)| (k.as_str(), *v)));
        for (name, v) in values {
            match col(name) {
                Some((true, j)) => a[row][j] = v,
                Some((false, j)) => b[row][j] = v,
                None => return Err(format!("unknown variable {name}")),
            }
        }
    }
    for (state, rate) in &config.kinematics {
        let (row, c) = (
            config
                .states
                .iter()
                .position(|s| s == state)
                .ok_or("unknown kinematic state")?,
            config
                .states
                .iter()
                .position(|s| s == rate)
                .ok_or("unknown kinematic rate")?,
        );
        a[row][c] = 1.0;
    }
    LinearModel::from_rows(config.states.clone(), controls.to_vec(), &a, &b)
        .map_err(|e| e.to_string())
}

/// The identified derivatives as a flight-refs derivative table (YAML text).
pub fn reference_yaml(id: &str, ident: &Identification, records: &[Record]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let synthetic = records.iter().any(|r| r.meta.synthetic.is_some());
    let _ = writeln!(s, "id: {id}");
    let _ = writeln!(
        s,
        "title: Derivatives identified from {}{}",
        ident.record,
        if synthetic {
            " (synthetic records)"
        } else {
            ""
        }
    );
    let _ = writeln!(s, "provenance:");
    let _ = writeln!(
        s,
        "  source: \"cierva identify {}: frequency-domain equation error (seed 000 Sec. IV) on {}\"",
        env!("CARGO_PKG_VERSION"),
        records
            .iter()
            .map(|r| r.path.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        s,
        "  notes: \"records' provenance: {}\"",
        records
            .iter()
            .map(|r| r.meta.provenance.source.replace('"', "'"))
            .collect::<Vec<_>>()
            .join("; ")
    );
    let _ = writeln!(s, "columns:");
    let _ = writeln!(
        s,
        "  estimate: {{kind: value, description: identified value}}"
    );
    let _ = writeln!(
        s,
        "  standard_error: {{kind: value, description: standard error of the estimate}}"
    );
    let _ = writeln!(
        s,
        "  flight_95: {{kind: interval, description: 95 % confidence bounds}}"
    );
    let _ = writeln!(s, "derivatives:");
    for d in &ident.derivatives {
        let _ = writeln!(
            s,
            "  - {{name: {}, units: as the record's, estimate: {:e}, standard_error: {:e}, flight_95: [{:e}, {:e}]}}",
            d.name, d.estimate, d.standard_error, d.lower_95, d.upper_95
        );
    }
    s
}
