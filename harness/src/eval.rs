//! Running checks: compute each quantity, compare with its expectation, decide the outcome.
//!
//! # Margins and outcomes
//! Each quantity is judged by [`crate::tolerance::judge`] (margins are positive when it
//! passes; NaN never passes). A check passes when every expectation passes (and, for `bcar`,
//! the verdict matches). An expected failure stays one only while the model gives what was
//! recorded for it ([`crate::discrepancy`]); a check that cannot be evaluated, or computes a
//! value that is not finite, is an `error`, whatever the case expects.
//!
//! # Rounding tolerance
//! Published matrices are rounded, so a quantity computed from them differs from the
//! published value computed from the unrounded matrices. The `rounding` tolerance bounds this
//! difference to first order: every entry of A and B outside the kinematic rows (`phi`,
//! `theta`, `psi`) is moved by half a unit of `input_decimals` either way, the change in the
//! quantity is taken by central difference, and the absolute changes are summed (the worst
//! case over all sign combinations, to first order). Half a unit of `output_decimals` is added
//! for the rounding of the published value itself.

use crate::case::{
    Case, Check, CheckClass, CheckKind, Expectation, Subject, System, ToleranceKind,
};
use crate::quantity::Quantity as Q;
use crate::refs::Entry;
use cierva_model::analysis::bcar::{self, Verdict};
use cierva_model::analysis::milne;
use cierva_model::analysis::modes::{self, Complex, Mode};
use cierva_model::{Element, LinearModel};
use serde::Serialize;

/// The outcome of a check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    Pass,
    Fail,
    /// Failed, as the case says it would, and the model gives what was recorded for it (see
    /// [`crate::discrepancy`]).
    ExpectedFailure,
    /// Failed as the case says it would, but the model has left its recorded band (better or
    /// worse), or nothing was recorded: the discrepancy is to be reviewed
    /// (`cierva review`).
    DiscrepancyMoved,
    /// Passed although the case says it fails: the case (or the model) must be looked at.
    UnexpectedPass,
    /// The check could not be evaluated (an error, or a value that is not a number). Always
    /// fails, whatever the case expects.
    Error,
}

impl Outcome {
    /// Whether this outcome is acceptable (the run stays green).
    pub fn ok(self) -> bool {
        matches!(self, Self::Pass | Self::ExpectedFailure)
    }

    /// Short label for tables.
    pub fn label(self) -> &'static str {
        match self {
            Self::Pass => "pass",
            Self::Fail => "FAIL",
            Self::ExpectedFailure => "xfail",
            Self::DiscrepancyMoved => "MOVED",
            Self::UnexpectedPass => "XPASS",
            Self::Error => "ERROR",
        }
    }

    /// Every outcome, in the order tables list them.
    pub const ALL: [Outcome; 6] = [
        Self::Pass,
        Self::Fail,
        Self::ExpectedFailure,
        Self::DiscrepancyMoved,
        Self::UnexpectedPass,
        Self::Error,
    ];
}

/// What the model found instead of the quantities a check asks for: a physical answer, not an
/// evaluation error.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "finding", rename_all = "snake_case")]
pub enum Finding {
    /// The model has no equilibrium where the reference has one (an isolated rotor whose
    /// driving torque never changes sign, or whose inflow has no solution). A validation
    /// failure; the check's `fingerprint` holds the numbers that describe it (the largest
    /// driving-torque coefficient over the bracket, the solver's last residual).
    NoEquilibrium { reason: String },
}

/// One quantity compared with its expectation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QuantityResult {
    pub quantity: String,
    pub value: f64,
    pub expected: Option<f64>,
    pub tolerance: String,
    /// The tolerance in words (`± 1.2e-3`, `[-0.133, -0.044]`).
    pub allowed: String,
    pub reason: String,
    /// The allowed range as numbers (for plots): `expected ± bound`, the interval, or
    /// `expected / factor .. expected * factor`.
    pub lower: f64,
    pub upper: f64,
    pub margin: f64,
    pub pass: bool,
}

/// The result of one check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckResult {
    pub case: String,
    pub check: String,
    pub kind: CheckKind,
    /// What the check is evidence of (validation, cross-code, verification, regression).
    pub class: CheckClass,
    pub outcome: Outcome,
    /// Whether every expectation held (and the verdict matched), whatever the case expects.
    pub passed: bool,
    pub quantities: Vec<QuantityResult>,
    /// For `bcar`: (expected, computed) verdicts.
    pub verdict: Option<(Verdict, Verdict)>,
    /// Why the check could not be computed, if it could not.
    pub error: Option<String>,
    /// What the model found instead of the quantities (no equilibrium).
    pub finding: Option<Finding>,
    pub expected_failure: Option<String>,
    /// Numbers that describe the check's result beyond its expectations (a BCAR margin, what
    /// a search without a solution ended on), so that a recorded known discrepancy notices
    /// when they move.
    pub fingerprint: Vec<(String, f64)>,
    /// For an expected failure: how the model has left what was recorded for it.
    pub departures: Vec<String>,
    /// What the report plots beyond the quantities (not in the JSON results).
    #[serde(skip)]
    pub plot: Option<PlotData>,
}

/// A check's data for the report's plots.
#[derive(Debug, Clone, PartialEq)]
pub enum PlotData {
    /// Every eigenvalue of the system the check looked at, and the check's mode; for a check
    /// that sets a derivative, the root locus from its nominal value to the one set.
    Modes {
        eigenvalues: Vec<Complex>,
        selected: Option<Complex>,
        locus: Option<Locus>,
    },
    /// The reference record and the model's responses, signal by signal.
    TimeHistory { traces: Vec<Trace> },
    /// The trims of a sweep: airspeed, mph, and the quantities at it.
    Sweep { points: Vec<(f64, Quantities)> },
}

/// A root locus (seed 002 Figs. 2, 3, 6-8): the system's eigenvalues as one derivative moves
/// from its nominal value to the value a check sets, and a quarter of the way beyond both.
#[derive(Debug, Clone, PartialEq)]
pub struct Locus {
    pub derivative: String,
    pub nominal: f64,
    pub set: f64,
    /// `(value, eigenvalues)` along the sweep.
    pub points: Vec<(f64, Vec<Complex>)>,
}

/// One response of a time-history check: the reference, the model, and the allowed error.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub signal: String,
    pub time_s: Vec<f64>,
    pub reference: Vec<f64>,
    pub model: Vec<f64>,
    /// The tolerance on the largest error, where the check sets an absolute one.
    pub band: Option<f64>,
}

impl CheckResult {
    /// A one-paragraph explanation, for test failures and logs.
    pub fn explain(&self) -> String {
        let mut s = format!(
            "{}::{} [{}, {}]",
            self.case,
            self.check,
            self.outcome.label(),
            self.class.name()
        );
        if let Some(e) = &self.error {
            s += &format!("\n  error: {e}");
        }
        if let Some(Finding::NoEquilibrium { reason, .. }) = &self.finding {
            s += &format!("\n  the model has no equilibrium here: {reason}");
        }
        if let Some((want, got)) = self.verdict {
            s += &format!("\n  verdict: expected {want:?}, computed {got:?}");
        }
        for q in &self.quantities {
            s += &format!(
                "\n  {}: value {:.6e}, expected {} {} ({}: {}), margin {:.3e} -> {}",
                q.quantity,
                q.value,
                q.expected.map_or("-".into(), |v| format!("{v:.6e}")),
                q.allowed,
                q.tolerance,
                q.reason,
                q.margin,
                if q.pass { "ok" } else { "out of tolerance" }
            );
        }
        match (self.outcome, &self.expected_failure) {
            (Outcome::UnexpectedPass, Some(r)) => {
                s += &format!(
                    "\n  this check is marked as an expected failure ({r}) but it passes: \
                     review the case and remove `expected_failure` if the discrepancy is gone, \
                     then run `cargo run --release -- review --accept`"
                )
            }
            (Outcome::DiscrepancyMoved, Some(r)) => {
                s += &format!("\n  known discrepancy ({r}) moved:");
                for d in &self.departures {
                    s += &format!("\n    {d}");
                }
                s += "\n  if the change is intended, record the model's new values with \
                      `cargo run --release -- review --accept` and say why in the commit";
            }
            (Outcome::ExpectedFailure, Some(r)) => s += &format!("\n  expected failure: {r}"),
            (Outcome::Error, Some(_)) => {
                s += "\n  an error fails even a check that is expected to fail"
            }
            _ => {}
        }
        s
    }
}

/// Every way the model has left its record, in words ("rpm 97.52: recorded 96.91 in [96.90,
/// 96.92]"); empty when it has not.
pub fn departures(result: &CheckResult, recorded: &crate::discrepancy::Recorded) -> Vec<String> {
    let mut out = Vec::new();
    let fmt = |b: &crate::discrepancy::Band| {
        format!(
            "recorded {:.6e} in [{:.6e}, {:.6e}]",
            b.value, b.lower, b.upper
        )
    };
    for q in &result.quantities {
        match recorded.quantities.get(&q.quantity) {
            Some(b) if b.holds(q.value) => {}
            Some(b) => out.push(format!("{} {:.6e}: {}", q.quantity, q.value, fmt(b))),
            None => out.push(format!("{} {:.6e}: not recorded", q.quantity, q.value)),
        }
    }
    for q in recorded.quantities.keys() {
        if !result.quantities.iter().any(|r| &r.quantity == q) {
            out.push(format!("{q}: recorded, but not computed now"));
        }
    }
    let got = result.verdict.map(|(_, got)| got);
    if got != recorded.verdict {
        out.push(format!("verdict {got:?}: recorded {:?}", recorded.verdict));
    }
    let no_equilibrium = matches!(result.finding, Some(Finding::NoEquilibrium { .. }));
    match (no_equilibrium, recorded.no_equilibrium) {
        (true, false) => out.push("no equilibrium now: recorded with one".into()),
        (false, true) => out.push("an equilibrium now: recorded without one".into()),
        _ => {}
    }
    for (n, v) in &result.fingerprint {
        match recorded.fingerprint.get(n) {
            Some(b) if b.holds(*v) => {}
            Some(b) => out.push(format!("{n} {v:.6e}: {}", fmt(b))),
            None => out.push(format!("{n} {v:.6e}: not recorded")),
        }
    }
    out
}

/// Runs every check of a case.
pub fn run_case(case: &Case) -> Vec<CheckResult> {
    case.checks.iter().map(|c| run_check(case, c)).collect()
}

/// Runs one check.
pub fn run_check(case: &Case, check: &Check) -> CheckResult {
    let mut result = CheckResult {
        case: case.id.clone(),
        check: check.id.clone(),
        kind: check.kind,
        class: check.class,
        outcome: Outcome::Error,
        passed: false,
        quantities: vec![],
        verdict: None,
        error: None,
        finding: None,
        expected_failure: check.expected_failure.clone(),
        fingerprint: vec![],
        departures: vec![],
        plot: None,
    };
    match evaluate(case, check) {
        Ok(e) => {
            let verdict_ok = e.verdict.is_none_or(|(want, got)| want == got);
            result.passed =
                e.finding.is_none() && verdict_ok && e.quantities.iter().all(|q| q.pass);
            let finite = e.quantities.iter().all(|q| q.value.is_finite());
            result.quantities = e.quantities;
            result.verdict = e.verdict;
            result.plot = e.plot;
            result.finding = e.finding;
            result.fingerprint = e.fingerprint;
            if !finite {
                result.error = Some("a computed value is not a finite number".into());
                return result;
            }
        }
        Err(e) => {
            result.error = Some(e);
            return result;
        }
    }
    result.outcome = match (result.passed, check.expected_failure.is_some()) {
        (true, false) => Outcome::Pass,
        (false, false) => Outcome::Fail,
        (true, true) => Outcome::UnexpectedPass,
        (false, true) => {
            let recorded = case.recorded.as_ref().and_then(|r| r.checks.get(&check.id));
            result.departures = match recorded {
                Some(r) => departures(&result, r),
                None => vec![format!(
                    "nothing is recorded for this check in {}",
                    crate::discrepancy::path_for(&case.id).display()
                )],
            };
            if result.departures.is_empty() {
                Outcome::ExpectedFailure
            } else {
                Outcome::DiscrepancyMoved
            }
        }
    };
    result
}

/// What evaluating a check gives.
#[derive(Default)]
struct Evaluated {
    quantities: Vec<QuantityResult>,
    verdict: Option<(Verdict, Verdict)>,
    plot: Option<PlotData>,
    finding: Option<Finding>,
    fingerprint: Vec<(String, f64)>,
}

impl Evaluated {
    fn of(quantities: Vec<QuantityResult>) -> Self {
        Self {
            quantities,
            ..Self::default()
        }
    }
}

/// The airspeed of a tunnel condition (given, or `mu Omega R / cos alpha`; unknown, NaN, while
/// the angle is to be found).
pub fn tunnel_airspeed_m_s(t: &crate::case::TunnelSpec, radius_m: f64) -> f64 {
    match (t.airspeed_m_s, t.tip_speed_ratio, t.rotor_rpm, t.alpha_deg) {
        (Some(v), _, _, _) => v,
        (None, Some(mu), Some(rpm), Some(alpha)) => {
            mu * rpm * std::f64::consts::PI / 30.0 * radius_m / alpha.to_radians().cos()
        }
        _ => f64::NAN,
    }
}

/// Named computed values of a check.
pub type Quantities = Vec<(&'static str, f64)>;

/// What the model found instead of a check's quantities, with the numbers that describe it.
pub type Found = (Finding, Vec<(String, f64)>);

/// The quantities of an autorotation check, or what the model found instead (no
/// equilibrium). An error is a condition the model could not be run at.
pub fn autorotation_quantities(
    rotor: &cierva_model::components::rotor::Rotor,
    inflow: cierva_model::components::rotor::InflowModel,
    t: &crate::case::TunnelSpec,
) -> Result<Result<Quantities, Found>, String> {
    let run = match (t.alpha_deg, t.tip_speed_ratio, t.rotor_rpm) {
        (Some(alpha), ..) => crate::run_autorotation(
            rotor,
            alpha,
            tunnel_airspeed_m_s(t, rotor.radius_m),
            t.collective_deg,
            t.density_kg_m3,
            inflow,
        )
        .map(|a| (alpha, a)),
        (None, Some(mu), Some(rpm)) => crate::run_autorotation_at_tip_speed_ratio(
            rotor,
            mu,
            rpm,
            t.collective_deg,
            t.density_kg_m3,
            inflow,
        )
        .map(|f| (f.alpha_rad.to_degrees(), f.autorotation)),
        _ => return Err("the tunnel condition is incomplete".into()),
    };
    let (alpha_deg, a) = match run {
        Ok(a) => a,
        Err(crate::AutorotateError::Autorotation(e)) => {
            return match no_equilibrium(&e) {
                Some(numbers) => Ok(Err((
                    Finding::NoEquilibrium {
                        reason: e.to_string(),
                    },
                    numbers,
                ))),
                None => Err(e.to_string()),
            };
        }
        Err(e) => return Err(e.to_string()),
    };
    Ok(Ok(vec![
        (Q::RotorAlphaDeg.name(), alpha_deg),
        (Q::RotorRpm.name(), a.rpm),
        (Q::RotorOmegaRadS.name(), a.omega_rad_s),
        (Q::TipSpeedRatio.name(), a.tip_speed_ratio),
        (Q::LiftCoefficient.name(), a.lift_coefficient),
        (Q::DragCoefficient.name(), a.drag_coefficient),
        (Q::LiftToDrag.name(), a.lift_to_drag),
        (Q::ThrustCoefficient.name(), a.thrust_coefficient),
        (Q::InflowV0MS.name(), a.inflow.v0),
        (Q::ConingDeg.name(), a.a0_rad.to_degrees()),
        (Q::A1Deg.name(), a.a1_rad.to_degrees()),
        (Q::B1Deg.name(), a.b1_rad.to_degrees()),
    ]))
}

/// An autorotation's quantities, or why there are none in words (a finding or an error).
pub fn quantities_or_reason(
    r: Result<Result<Quantities, Found>, String>,
) -> Result<Quantities, String> {
    match r {
        Ok(Ok(q)) => Ok(q),
        Ok(Err((Finding::NoEquilibrium { reason }, _))) | Err(reason) => Err(reason),
    }
}

/// When an autorotation error is the model finding no equilibrium (not a condition it cannot
/// be run at): the number that says how far it was from one.
fn no_equilibrium(
    e: &cierva_model::components::autorotation::AutorotationError,
) -> Option<Vec<(String, f64)>> {
    use cierva_model::components::autorotation::AutorotationError as A;
    use cierva_model::solve::SolveError;
    let largest = |v: &mut dyn Iterator<Item = f64>| v.fold(f64::NEG_INFINITY, f64::max);
    let (name, value) = match e {
        A::NoAngle { found, .. } => (
            "largest_tip_speed_ratio_found",
            largest(&mut found.iter().map(|f| f.1)),
        ),
        A::NoBracket { torques, .. } => (
            "largest_torque_coefficient_over_solidity",
            largest(&mut torques.iter().copied()),
        ),
        A::Solve(SolveError::NoConvergence { residuals, .. }) => (
            "largest_scaled_residual",
            residuals.iter().fold(0.0f64, |m, r| m.max(r.abs())),
        ),
        _ => return None,
    };
    Some(vec![(name.to_string(), value)])
}

/// The quantities of one trim (see [`crate::case::TRIM_QUANTITIES`]).
pub fn trim_quantities(
    file: &crate::aircraft_file::AircraftFile,
    loading: crate::Loading,
    request: crate::TrimRequest,
) -> Result<Quantities, String> {
    let t = crate::run_trim(&file.aircraft, request, loading).map_err(|e| e.to_string())?;
    Ok(trim_quantities_of(&file.aircraft, loading, &t))
}

/// The quantities of a trim of `aircraft` at `loading`.
pub fn trim_quantities_of(
    aircraft: &cierva_model::aircraft::Aircraft,
    loading: crate::Loading,
    t: &cierva_model::aircraft::trim::Trim,
) -> Quantities {
    let d = f64::to_degrees;
    let r = &t.averaged.rotor;
    let c = &t.controls;
    vec![
        (Q::ResidualNorm.name(), t.residual_norm),
        (
            Q::StickLongitudinalPercent.name(),
            c.stick_longitudinal_percent,
        ),
        (Q::StickLateralPercent.name(), c.stick_lateral_percent),
        (Q::PedalPercent.name(), c.pedal_percent),
        (Q::ThrottlePercent.name(), c.throttle_percent),
        (Q::PitchDeg.name(), d(t.pitch_rad)),
        (Q::RollDeg.name(), d(t.roll_rad)),
        (Q::AlphaDeg.name(), d(t.alpha_rad)),
        (Q::SideslipDeg.name(), d(t.sideslip_rad)),
        (Q::RotorRpm.name(), t.rotor_rpm),
        (Q::PropellerRpm.name(), t.propeller_rpm),
        (Q::RotorTorqueNM.name(), r.driving_torque_n_m),
        (Q::ThrustN.name(), r.thrust_n),
        (Q::DiscAlphaDeg.name(), d(r.disc_alpha_rad)),
        (Q::TipSpeedRatio.name(), r.tip_speed_ratio),
        (Q::ThrustCoefficientOverSolidity.name(), {
            let rotor = &aircraft.main_rotor.rotor;
            let rho = cierva_model::components::atmosphere::at_density_altitude(
                loading.density_altitude_ft * crate::FT_TO_M,
            )
            .map_or(f64::NAN, |a| a.density_kg_m3);
            let tip = t.state.rotor_omega_rad_s * rotor.radius_m;
            r.thrust_n
                / (rho * std::f64::consts::PI * rotor.radius_m.powi(2) * tip * tip)
                / rotor.solidity()
        }),
        (Q::A1Deg.name(), d(r.a1_rad)),
        (Q::B1Deg.name(), d(r.b1_rad)),
        (Q::InflowV0MS.name(), t.state.inflow.v0),
        (Q::InflowV1cMS.name(), t.state.inflow.v1c),
    ]
}

/// Trims over a sweep of airspeeds: each point's quantities, or the first failure (named by
/// its airspeed).
pub fn trim_sweep(
    file: &crate::aircraft_file::AircraftFile,
    loading: crate::Loading,
    sweep_mph: &[f64],
) -> Result<Vec<(f64, Quantities)>, String> {
    sweep_mph
        .iter()
        .map(|&v| {
            let request = crate::TrimRequest {
                airspeed_mph: v,
                climb_m_s: 0.0,
                turn_rate_deg_s: 0.0,
            };
            trim_quantities(file, loading, request)
                .map(|q| (v, q))
                .map_err(|e| format!("at {v} mph: {e}"))
        })
        .collect()
}

/// The trend quantities of a sweep (see [`crate::quantity::sweep_names`]).
pub fn sweep_trends(points: &[(f64, Quantities)]) -> Vec<(String, f64)> {
    let get = |q: &Quantities, name: &str| {
        q.iter()
            .find(|(n, _)| *n == name)
            .map_or(f64::NAN, |(_, v)| *v)
    };
    let mut out = vec![(
        Q::MaxResidualNorm.name().to_string(),
        points
            .iter()
            .map(|(_, q)| get(q, Q::ResidualNorm.name()))
            .fold(0.0f64, |m, v| if v.is_nan() { f64::NAN } else { m.max(v) }),
    )];
    for name in crate::quantity::TREND.iter().map(|q| q.name()) {
        let slopes: Vec<f64> = points
            .windows(2)
            .map(|w| (get(&w[1].1, name) - get(&w[0].1, name)) / (w[1].0 - w[0].0))
            .collect();
        let lo = slopes.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = slopes.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let nan = slopes.iter().any(|v| v.is_nan());
        out.push((
            format!("{name}_per_mph_min"),
            if nan { f64::NAN } else { lo },
        ));
        out.push((
            format!("{name}_per_mph_max"),
            if nan { f64::NAN } else { hi },
        ));
    }
    out
}

fn evaluate(case: &Case, check: &Check) -> Result<Evaluated, String> {
    // Long: one arm per kind of subject, each a short sequence: compute, compare, keep what the
    // report plots
    let subject = &case.subject;
    match subject {
        Subject::Aircraft { file, loading } if check.kind == CheckKind::TimeHistory => {
            let (metrics, flown) = time_history_metrics(file, *loading, check)?;
            let plot = time_history_plot(check, &flown);
            let values: Vec<(String, f64)> = metrics
                .iter()
                .flat_map(|m| {
                    crate::history::METRICS
                        .iter()
                        .map(|q| (format!("{}.{q}", m.signal), m.get(q).unwrap_or(f64::NAN)))
                })
                .collect();
            let values: Vec<(&str, f64)> = values.iter().map(|(n, v)| (n.as_str(), *v)).collect();
            Ok(Evaluated {
                plot,
                ..Evaluated::of(compare_all(check, &values)?)
            })
        }
        Subject::Aircraft { file, loading }
            if check.kind != CheckKind::Trim && check.kind != CheckKind::TrimSweep =>
        {
            let request = check
                .condition
                .ok_or("a check on the linearised aircraft needs a condition")?;
            let corrected;
            let file = match &check.corrections {
                Some(c) => {
                    corrected = file.with_corrections(c).map_err(|e| e.to_string())?;
                    &corrected
                }
                None => file.as_ref(),
            };
            let lin = crate::linearise_cached(file, request, *loading)?;
            let full = &lin.1.model;
            let model = if check.kind == CheckKind::Milne {
                lin.1.longitudinal().map_err(|e| e.to_string())?
            } else {
                full.clone()
            };
            let base = prepare(&model, check)?;
            let nominal = match compute(&base, check, None, &model) {
                Err(e) if e.starts_with(UNCLASSIFIED) && check.set.is_empty() => {
                    // Follow the mode from the nearest airspeed of the case where it is
                    // classified (see `neighbour_for_continuity`).
                    let from = neighbour_for_continuity(case, check, file, *loading)?.ok_or_else(
                        || format!("{e}; and no other airspeed of the case classifies it"),
                    )?;
                    compute(&base, check, None, &from)?
                }
                other => other?,
            };
            let mut out = Vec::new();
            for e in &check.expectations {
                let value = match (check.kind, e.quantity.as_str()) {
                    (CheckKind::Derivative, "magnitude_change") => {
                        let Subject::Aircraft { file: plain, .. } = subject else {
                            unreachable!()
                        };
                        let d = check.derivative.as_deref().unwrap_or_default();
                        let base = crate::linearise_cached(plain, request, *loading)?;
                        let b = base
                            .1
                            .model
                            .derivative_value(d)
                            .map_err(|e| e.to_string())?;
                        let c = lin.1.model.derivative_value(d).map_err(|e| e.to_string())?;
                        (c.abs() - b.abs()) / b.abs()
                    }
                    (CheckKind::Derivative, q) if q != "value" => {
                        let d = check.derivative.as_deref().unwrap_or_default();
                        let parts = lin.1.breakdown(d).map_err(|e| e.to_string())?;
                        parts
                            .iter()
                            .find(|(c, _)| c == q)
                            .map(|(_, v)| *v)
                            .ok_or_else(|| format!("no component `{q}`"))?
                    }
                    _ => nominal.get(&e.quantity)?,
                };
                out.push(compare(e, value, || Ok(0.0))?);
            }
            let plot = modes_plot(&model, &base, check, nominal.anchor);
            Ok(Evaluated {
                verdict: verdict_pair(check, &nominal)?,
                plot,
                fingerprint: nominal.fingerprint(check),
                ..Evaluated::of(out)
            })
        }
        Subject::Aircraft { file, loading } => {
            if let Some(request) = check.condition {
                let values = trim_quantities(file, *loading, request)?;
                return Ok(Evaluated::of(compare_all(check, &values)?));
            }
            let sweep = check
                .sweep_mph
                .as_deref()
                .ok_or("a trim_sweep check needs sweep_mph")?;
            let points = trim_sweep(file, *loading, sweep)?;
            let trends = sweep_trends(&points);
            let values: Vec<(&str, f64)> = trends.iter().map(|(n, v)| (n.as_str(), *v)).collect();
            Ok(Evaluated {
                plot: Some(PlotData::Sweep { points }),
                ..Evaluated::of(compare_all(check, &values)?)
            })
        }
        Subject::FlapRecord {
            record,
            rotor,
            settings,
        } => {
            let r = crate::ident::flap::inflow_from_record(record, &rotor.rotor, settings)?;
            let values = [
                (Q::InflowV0MS.name(), r.v0_m_s),
                (Q::InflowV1sMS.name(), r.v1s_m_s),
                (Q::InflowV1cMS.name(), r.v1c_m_s),
                (Q::ConingDeg.name(), r.coning_deg),
                (Q::Beta1cDeg.name(), r.beta_1c_deg),
                (Q::Beta1sDeg.name(), r.beta_1s_deg),
            ];
            Ok(Evaluated::of(compare_all(check, &values)?))
        }
        Subject::Rotor { file, inflow } => {
            let t = check
                .tunnel
                .as_ref()
                .ok_or("an autorotation check needs a tunnel")?;
            match autorotation_quantities(&file.rotor, *inflow, t)? {
                Ok(values) => Ok(Evaluated::of(compare_all(check, &values)?)),
                Err((finding, fingerprint)) => Ok(Evaluated {
                    finding: Some(finding),
                    fingerprint,
                    ..Evaluated::default()
                }),
            }
        }
        Subject::Table { table, column, .. } => {
            let d = check.derivative.as_deref().unwrap_or_default();
            let value = match table.entry(d, column) {
                Some(Entry::Value(v)) => v,
                _ => return Err(format!("no value of `{d}` in column `{column}`")),
            };
            let q = check
                .expectations
                .iter()
                .map(|e| compare(e, value, || Ok(0.0)))
                .collect::<Result<_, _>>()?;
            Ok(Evaluated::of(q))
        }
        Subject::Linear { model, .. } => {
            let base = prepare(model, check)?;
            let nominal = compute(&base, check, None, model)?;
            let mut out = Vec::new();
            for e in &check.expectations {
                let value = nominal.get(&e.quantity)?;
                out.push(compare(e, value, || {
                    propagated_rounding(model, check, &nominal, &e.quantity, e)
                })?);
            }
            let plot = modes_plot(model, &base, check, nominal.anchor);
            Ok(Evaluated {
                verdict: verdict_pair(check, &nominal)?,
                plot,
                fingerprint: nominal.fingerprint(check),
                ..Evaluated::of(out)
            })
        }
    }
}

/// The linearised model at the airspeed of `case` nearest to `check`'s (same climb, another
/// airspeed) at which `check`'s mode is classified, if any: the start of the continuation
/// that names the mode at `check`'s own airspeed.
///
/// Classification by participation can fail where modes couple (at 30 mph the VPM M16's pitch
/// oscillation takes roll and sideslip), while the mode is plainly there: followed by the
/// nearest eigenvalue along the straight path between the two linearisations, as a root locus
/// names its branches, it keeps the name it has at the neighbouring airspeed.
fn neighbour_for_continuity(
    case: &Case,
    check: &Check,
    file: &crate::aircraft_file::AircraftFile,
    loading: crate::Loading,
) -> Result<Option<LinearModel>, String> {
    let (Some(here), Some(kind)) = (check.condition, check.mode) else {
        return Ok(None);
    };
    let mut others: Vec<crate::TrimRequest> = case
        .checks
        .iter()
        .filter_map(|k| k.condition)
        .filter(|c| c.climb_m_s == here.climb_m_s && c.turn_rate_deg_s == 0.0)
        .filter(|c| c.airspeed_mph != here.airspeed_mph)
        .collect();
    others.sort_by(|a, b| {
        (a.airspeed_mph - here.airspeed_mph)
            .abs()
            .total_cmp(&(b.airspeed_mph - here.airspeed_mph).abs())
            .then(a.airspeed_mph.total_cmp(&b.airspeed_mph))
    });
    others.dedup();
    for request in others {
        let lin = crate::linearise_cached(file, request, loading)?;
        let sys = system_model(&lin.1.model, check.system)?;
        let analysis = modes::modes(&sys).map_err(|e| e.to_string())?;
        if analysis.of_kind(kind).count() == 1 {
            return Ok(Some(lin.1.model.clone()));
        }
    }
    Ok(None)
}

/// A `time_history` check's record flown by its model (with its corrections), compared
/// response by response.
pub fn time_history_metrics(
    file: &crate::aircraft_file::AircraftFile,
    loading: crate::Loading,
    check: &Check,
) -> Result<(Vec<crate::history::SignalMetrics>, crate::history::Flown), String> {
    let record = check
        .reference
        .as_deref()
        .ok_or("a time_history check needs a reference record")?;
    let request = check
        .condition
        .ok_or("a time_history check needs a condition")?;
    let corrected;
    let file = match &check.corrections {
        Some(c) => {
            corrected = file.with_corrections(c).map_err(|e| e.to_string())?;
            &corrected
        }
        None => file,
    };
    let step = check.azimuth_step_deg.map_or(
        file.aircraft.main_rotor.numerics.azimuth_step_rad,
        f64::to_radians,
    );
    crate::history::fly_record(
        &file.aircraft,
        request,
        loading,
        record,
        check.simulation,
        step,
    )
}

/// The eigenvalues of a mode or BCAR check's system (`model` as the check modified it), its
/// mode, and the root locus when the check sets one derivative of `unmodified`.
fn modes_plot(
    unmodified: &LinearModel,
    model: &LinearModel,
    check: &Check,
    selected: Option<Complex>,
) -> Option<PlotData> {
    if !matches!(check.kind, CheckKind::Mode | CheckKind::Bcar) {
        return None;
    }
    let sys = system_model(model, check.system).ok()?;
    let analysis = modes::modes(&sys).ok()?;
    let locus = match (check.set.len(), check.without_rotorspeed_coupling) {
        (1, false) => {
            let (name, &set) = check.set.iter().next().expect("one");
            locus_of(unmodified, check, name, set)
        }
        _ => None,
    };
    Some(PlotData::Modes {
        eigenvalues: analysis.modes.iter().map(|m| m.eigenvalue).collect(),
        selected,
        locus,
    })
}

/// Points on a root locus.
const LOCUS_POINTS: usize = 41;

fn locus_of(model: &LinearModel, check: &Check, name: &str, set: f64) -> Option<Locus> {
    let e = model.derivative(name).ok()?;
    let nominal = model.derivative_value(name).ok()?;
    let (lo, hi) = (nominal.min(set), nominal.max(set));
    let pad = 0.25 * (hi - lo).max(1e-9);
    let values = cierva_model::analysis::locus::linspace(lo - pad, hi + pad, LOCUS_POINTS);
    let points = values
        .iter()
        .filter_map(|&v| {
            let m = model.with(e, v).ok()?;
            let sys = system_model(&m, check.system).ok()?;
            let a = modes::modes(&sys).ok()?;
            Some((v, a.modes.iter().map(|m| m.eigenvalue).collect()))
        })
        .collect();
    Some(Locus {
        derivative: name.to_string(),
        nominal,
        set,
        points,
    })
}

/// The reference and flown responses of a time-history check, with the largest-error
/// tolerance of each signal where it is absolute.
fn time_history_plot(check: &Check, flown: &crate::history::Flown) -> Option<PlotData> {
    let record = check.reference.as_deref()?;
    let time_s = record.channel("time_s")?.to_vec();
    let traces = crate::history::record_signals(record)
        .into_iter()
        .filter_map(|signal| {
            let reference = record.channel(&signal)?.to_vec();
            let model = flown.signal(&signal)?.to_vec();
            let band = check
                .expectations
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

/// The expected and computed BCAR verdicts of a check, if it expects one.
fn verdict_pair(check: &Check, nominal: &Computed) -> Result<Option<(Verdict, Verdict)>, String> {
    match (check.verdict, nominal.verdict) {
        (Some(want), Some(got)) => Ok(Some((want, got))),
        (Some(_), None) => Err("the mode is not oscillatory: BCAR Section T does not apply".into()),
        _ => Ok(None),
    }
}

/// Compares every expectation of a check with its value among `values` (quantities computed
/// without a rounding tolerance: rotor and flap-record subjects).
fn compare_all(check: &Check, values: &[(&str, f64)]) -> Result<Vec<QuantityResult>, String> {
    check
        .expectations
        .iter()
        .map(|e| {
            let v = values
                .iter()
                .find(|(n, _)| *n == e.quantity)
                .map(|(_, v)| *v)
                .ok_or_else(|| format!("`{}` is not computed", e.quantity))?;
            compare(e, v, || Ok(0.0))
        })
        .collect()
}

/// The model after the check's modifications (`without_rotorspeed_coupling`, then `set`).
fn prepare(model: &LinearModel, check: &Check) -> Result<LinearModel, String> {
    let mut m = if check.without_rotorspeed_coupling {
        milne::without_rotorspeed_coupling(model).map_err(|e| e.to_string())?
    } else {
        model.clone()
    };
    for (name, value) in &check.set {
        let e = m.derivative(name).map_err(|e| e.to_string())?;
        m = m.with(e, *value).map_err(|e| e.to_string())?;
    }
    Ok(m)
}

/// The quantities a check computes on one model.
struct Computed {
    values: Vec<(&'static str, f64)>,
    /// The eigenvalue of the selected mode (to follow it under perturbation).
    anchor: Option<Complex>,
    verdict: Option<Verdict>,
}

impl Computed {
    /// A BCAR check's numbers beyond its verdict: the mode's eigenvalue and its margin from
    /// the boundary.
    fn fingerprint(&self, check: &Check) -> Vec<(String, f64)> {
        if check.kind != CheckKind::Bcar {
            return vec![];
        }
        [
            Q::EigenvalueRealPerS,
            Q::EigenvalueImagRadS,
            Q::MarginRealPerS,
        ]
        .iter()
        .filter_map(|q| {
            let n = q.name().to_string();
            match q {
                Q::EigenvalueRealPerS => self.anchor.map(|a| (n, a.re)),
                Q::EigenvalueImagRadS => self.anchor.map(|a| (n, a.im)),
                _ => self.get(q.name()).ok().map(|v| (n, v)),
            }
        })
        .collect()
    }

    fn get(&self, q: &str) -> Result<f64, String> {
        self.values
            .iter()
            .find(|(n, _)| *n == q)
            .map(|(_, v)| *v)
            .ok_or_else(|| {
                format!("`{q}` is not defined here (for example a period of a real mode)")
            })
    }
}

fn system_model(model: &LinearModel, system: System) -> Result<LinearModel, String> {
    match system {
        System::Full => Ok(model.clone()),
        System::ShortPeriod => milne::short_period(model).map_err(|e| e.to_string()),
        System::Reduced => milne::reduced(model).map_err(|e| e.to_string()),
        System::Eq13 => milne::eq13(model)
            .map(|e| e.model())
            .map_err(|e| e.to_string()),
    }
}

/// How the error for a mode that no eigenvalue is classified as begins.
const UNCLASSIFIED: &str = "no";

/// Steps of the path along which a mode is followed from the unmodified model.
const CONTINUATION_STEPS: usize = 50;

fn nearest(analysis: modes::ModalAnalysis, a: Complex) -> Result<Mode, String> {
    analysis
        .modes
        .into_iter()
        .min_by(|x, y| {
            let d = |m: &Mode| (m.eigenvalue.re - a.re).hypot(m.eigenvalue.im - a.im);
            d(x).total_cmp(&d(y))
        })
        .ok_or_else(|| "no modes".to_string())
}

/// Selects the mode of a check.
///
/// * On a perturbed model (rounding propagation), the mode nearest to `anchor`, the nominal
///   mode's eigenvalue: classification can flip under perturbation, the mode cannot jump.
/// * Otherwise by its class. When the check modifies the model (`set`,
///   `without_rotorspeed_coupling`) and the modified mode is not classified unambiguously (a
///   mixed mode), it is followed by continuity from its class on the unmodified model, along
///   the straight path between the two models' matrices, as a root locus names its branches.
fn select_mode(
    model: &LinearModel,
    check: &Check,
    anchor: Option<Complex>,
    unmodified: &LinearModel,
) -> Result<Mode, String> {
    let sys = system_model(model, check.system)?;
    let analysis = modes::modes(&sys).map_err(|e| e.to_string())?;
    let kind = check.mode.expect("mode checks have a mode");
    if let Some(a) = anchor {
        return nearest(analysis, a);
    }
    let found: Vec<Mode> = analysis.of_kind(kind).cloned().collect();
    if found.len() != 1 && model != unmodified {
        let start = select_mode(unmodified, check, None, unmodified)?;
        let mut at = start.eigenvalue;
        let mut mode = start;
        for k in 1..=CONTINUATION_STEPS {
            let t = k as f64 / CONTINUATION_STEPS as f64;
            let m = LinearModel::new(
                model.states().to_vec(),
                model.controls().to_vec(),
                unmodified.a() * (1.0 - t) + model.a() * t,
                unmodified.b() * (1.0 - t) + model.b() * t,
            )
            .map_err(|e| e.to_string())?;
            let sys = system_model(&m, check.system)?;
            mode = nearest(modes::modes(&sys).map_err(|e| e.to_string())?, at)?;
            at = mode.eigenvalue;
        }
        return Ok(mode);
    }
    match found.len() {
        1 => Ok(found.into_iter().next().expect("one")),
        0 => Err(format!(
            "{UNCLASSIFIED} {} mode in the {:?} system; its modes are: {}",
            kind.name(),
            check.system,
            analysis
                .modes
                .iter()
                .map(|m| format!("{} {:.4}", m.kind.name(), m.eigenvalue))
                .collect::<Vec<_>>()
                .join("; ")
        )),
        n => Err(format!(
            "{n} modes are classified {}: ambiguous",
            kind.name()
        )),
    }
}

fn compute(
    model: &LinearModel,
    check: &Check,
    anchor: Option<Complex>,
    unmodified: &LinearModel,
) -> Result<Computed, String> {
    let mut values: Vec<(&'static str, f64)> = Vec::new();
    let mut verdict = None;
    let mut selected = None;
    match check.kind {
        CheckKind::Mode => {
            let m = select_mode(model, check, anchor, unmodified)?;
            values.push((Q::EigenvalueRealPerS.name(), m.eigenvalue.re));
            values.push((Q::EigenvalueImagRadS.name(), m.eigenvalue.im));
            values.push((Q::NaturalFrequencyRadS.name(), m.natural_frequency_rad_s));
            let optional = [
                (Q::DampingRatio.name(), m.damping_ratio),
                (Q::PeriodS.name(), m.period_s),
                (Q::TimeToHalfS.name(), m.time_to_half_s),
                (Q::TimeToDoubleS.name(), m.time_to_double_s),
            ];
            values.extend(optional.into_iter().filter_map(|(n, v)| v.map(|v| (n, v))));
            selected = Some(m.eigenvalue);
        }
        CheckKind::Bcar => {
            let m = select_mode(model, check, anchor, unmodified)?;
            if let Some(a) = bcar::assess(&m) {
                values.push((Q::DampingIndex.name(), a.damping_index));
                values.push((Q::BoundaryIndex.name(), a.boundary_index));
                values.push((Q::MarginIndex.name(), a.margin_index));
                values.push((Q::MarginRealPerS.name(), a.margin_real_per_s));
                values.push((Q::PeriodS.name(), a.period_s));
                verdict = Some(a.verdict);
            }
            selected = Some(m.eigenvalue);
        }
        CheckKind::Milne => {
            for q in &check.expectations {
                values.push((
                    static_name(&q.quantity),
                    milne_quantity(model, &q.quantity)?,
                ));
            }
        }
        CheckKind::Derivative => {
            let d = check.derivative.as_deref().unwrap_or_default();
            let mut v = model.derivative_value(d).map_err(|e| e.to_string())?;
            if let Some(by) = &check.divided_by {
                v /= model.derivative_value(by).map_err(|e| e.to_string())?;
            }
            values.push((Q::Value.name(), v));
        }
        CheckKind::Autorotation => return Err("an autorotation check needs a rotor".into()),
        CheckKind::Trim | CheckKind::TrimSweep | CheckKind::TimeHistory => {
            return Err("a trim check needs an aircraft".into());
        }
        CheckKind::InflowCoefficients => return Err("an inflow check needs a flap record".into()),
    }
    Ok(Computed {
        values,
        anchor: selected,
        verdict,
    })
}

fn static_name(q: &str) -> &'static str {
    crate::quantity::Quantity::parse(q).map_or("unknown", |q| q.name())
}

fn milne_quantity(model: &LinearModel, q: &str) -> Result<f64, String> {
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

const KINEMATIC: [&str; 3] = ["phi", "theta", "psi"];

/// First-order worst-case change of a quantity when the published matrix entries move by half
/// a unit in their last printed decimal (see the module docs). Entries that the check `set`s
/// are exact and are not moved.
fn propagated_rounding(
    model: &LinearModel,
    check: &Check,
    nominal: &Computed,
    quantity: &str,
    e: &Expectation,
) -> Result<f64, String> {
    let ToleranceKind::Rounding(r) = e.tolerance.kind else {
        return Ok(0.0);
    };
    let h = 0.5 * 10f64.powi(-(r.input_decimals as i32));
    let fixed: Vec<Element> = check
        .set
        .keys()
        .filter_map(|n| model.derivative(n).ok())
        .collect();
    let mut elements = Vec::new();
    for (i, s) in model.states().iter().enumerate() {
        if KINEMATIC.contains(&s.as_str()) {
            continue;
        }
        elements.extend((0..model.states().len()).map(|j| Element::A { row: i, col: j }));
        elements.extend((0..model.controls().len()).map(|j| Element::B { row: i, col: j }));
    }
    let mut total = 0.0;
    for el in elements.into_iter().filter(|el| !fixed.contains(el)) {
        let v0 = model.get(el);
        let side = |sign: f64| -> Result<f64, String> {
            let m = model.with(el, v0 + sign * h).map_err(|e| e.to_string())?;
            let prepared = prepare(&m, check)?;
            compute(&prepared, check, nominal.anchor, &m)?.get(quantity)
        };
        let (up, down) = (side(1.0)?, side(-1.0)?);
        total += 0.5 * (up - down).abs();
    }
    Ok(total + 0.5 * 10f64.powi(-(r.output_decimals as i32)))
}

fn compare(
    e: &Expectation,
    value: f64,
    rounding: impl FnOnce() -> Result<f64, String>,
) -> Result<QuantityResult, String> {
    let bound = match e.tolerance.kind {
        ToleranceKind::Rounding(_) => Some(rounding()?),
        _ => None,
    };
    let j = crate::tolerance::judge(&e.tolerance.kind, e.value, value, bound)
        .ok_or("expectation and tolerance do not fit (checked at load)")?;
    Ok(QuantityResult {
        quantity: e.quantity.clone(),
        value,
        expected: e.value,
        tolerance: e.tolerance.name.clone(),
        allowed: j.allowed,
        reason: e.tolerance.reason.clone(),
        lower: j.lower,
        upper: j.upper,
        margin: j.margin,
        pass: j.pass,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::Tolerance;

    fn exp(kind: ToleranceKind, value: Option<f64>) -> Expectation {
        Expectation {
            quantity: "q".into(),
            value,
            tolerance: Tolerance {
                name: "t".into(),
                kind,
                reason: "test".into(),
            },
        }
    }

    /// The `rounding` bound is a first-order worst case over every sign combination, so random
    /// corner perturbations of the printed matrix (every entry moved by +-half a unit) must stay
    /// within it (allowing 10 % for second-order effects), and the worst of them should come
    /// close to it (the bound is not loose).
    #[test]
    fn rounding_bound_covers_random_corner_perturbations() {
        use crate::case::{CheckKind, RoundingSpec, System};
        use cierva_model::ModeKind;
        let r =
            crate::refs::load(&crate::repo_root().join("flight-refs/seed002-vpm-m16-60kn.yaml"))
                .unwrap();
        let model = r.linear_model.unwrap();
        let spec = RoundingSpec {
            input_decimals: 4,
            output_decimals: 12,
        };
        let mut e = exp(ToleranceKind::Rounding(spec), Some(0.0));
        e.quantity = "eigenvalue_imag_rad_s".into();
        for (system, mode) in [
            (System::Full, ModeKind::Phugoid),
            (System::Eq13, ModeKind::Phugoid),
            (System::Full, ModeKind::ShortPeriod),
        ] {
            let check = Check {
                id: "c".into(),
                kind: CheckKind::Mode,
                class: crate::case::CheckClass::Verification,
                description: None,
                system,
                mode: Some(mode),
                derivative: None,
                divided_by: None,
                corrections: None,
                reference: None,
                simulation: Default::default(),
                azimuth_step_deg: None,
                verdict: None,
                tunnel: None,
                condition: None,
                sweep_mph: None,
                set: Default::default(),
                without_rotorspeed_coupling: false,
                expectations: vec![e.clone()],
                expected_failure: None,
            };
            let nominal = compute(&model, &check, None, &model).unwrap();
            let v0 = nominal.get(&e.quantity).unwrap();
            let bound = propagated_rounding(&model, &check, &nominal, &e.quantity, &e).unwrap();
            // Deterministic pseudo-random signs (64-bit LCG, fixed seed).
            let mut state: u64 = 0x5eed_0002;
            let mut worst = 0.0f64;
            for _ in 0..400 {
                let mut a = model.a().clone();
                let mut b = model.b().clone();
                for i in [0usize, 1, 2, 4] {
                    for j in 0..5 {
                        state = state
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        a[(i, j)] += if state >> 63 == 1 { 0.5e-4 } else { -0.5e-4 };
                    }
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    b[(i, 0)] += if state >> 63 == 1 { 0.5e-4 } else { -0.5e-4 };
                }
                let m = LinearModel::new(model.states().to_vec(), model.controls().to_vec(), a, b)
                    .unwrap();
                let v = compute(&m, &check, nominal.anchor, &m)
                    .unwrap()
                    .get(&e.quantity)
                    .unwrap();
                worst = worst.max((v - v0).abs());
            }
            assert!(
                worst <= 1.1 * bound,
                "{system:?} {mode:?}: worst {worst:e} > bound {bound:e}"
            );
            assert!(
                worst >= 0.3 * bound,
                "{system:?} {mode:?}: worst {worst:e} << bound {bound:e}"
            );
        }
    }
}
