//! Plain-text tables: modes, derivatives, Milne values and validation results.
//!
//! Numbers are written to a fixed number of significant digits ([`crate::units::sig`]) so that snapshots do
//! not churn on the last bits of floating point.

use crate::suite::case::CheckClass;
use crate::suite::outcome::{CheckResult, Outcome};
use crate::suite::scoreboard::{Board, Metric};
use crate::units::{SIG, sig};
use cierva_model::analysis::bcar;
use cierva_model::analysis::milne;
use cierva_model::{LinearModel, ModalAnalysis};
use std::fmt::Write;

fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| sig(v, SIG))
}

/// The modes with their characteristics and BCAR Section T assessment.
pub fn modes_table(a: &ModalAnalysis) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<16} {:>24} {:>10} {:>10} {:>10} {:>10} {:>10}  {:<34} dominant states",
        "mode",
        "eigenvalue (1/s)",
        "zeta",
        "wn rad/s",
        "period s",
        "t_half s",
        "t_double s",
        "BCAR Section T (margin, 1/s)"
    );
    // An eigenvalue at round-off from zero (the heading mode) prints as an exact zero.
    let scale = a
        .modes
        .iter()
        .fold(0.0f64, |x, m| x.max(m.eigenvalue.re.hypot(m.eigenvalue.im)));
    for m in &a.modes {
        if m.eigenvalue.re.hypot(m.eigenvalue.im) <= 1e-12 * scale {
            let _ = writeln!(
                s,
                "{:<16} {:>24} {:>10} {:>10} {:>10} {:>10} {:>10}  {:<34} (a zero eigenvalue)",
                m.kind.name(),
                "0",
                "-",
                "0",
                "-",
                "-",
                "-",
                "n/a (not oscillatory)",
            );
            continue;
        }
        let ev = if m.is_oscillatory() {
            format!(
                "{} ± {}i",
                sig(m.eigenvalue.re, SIG),
                sig(m.eigenvalue.im, SIG)
            )
        } else {
            sig(m.eigenvalue.re, SIG)
        };
        let b = bcar::assess(m).map_or_else(
            || "n/a (not oscillatory)".to_string(),
            |x| {
                format!(
                    "{} ({})",
                    match x.verdict {
                        bcar::Verdict::Complies => "complies",
                        bcar::Verdict::DoesNotComply => "DOES NOT COMPLY",
                    },
                    sig(x.margin_real_per_s, 4)
                )
            },
        );
        let mut dom: Vec<(f64, &str)> = m
            .participation
            .iter()
            .zip(&a.states)
            .map(|(p, s)| (*p, s.as_str()))
            .collect();
        dom.sort_by(|x, y| y.0.total_cmp(&x.0));
        let dom = dom
            .iter()
            .take(3)
            .map(|(p, s)| format!("{s} {:.2}", p))
            .collect::<Vec<_>>()
            .join(", ");
        let _ = writeln!(
            s,
            "{:<16} {:>24} {:>10} {:>10} {:>10} {:>10} {:>10}  {:<34} {}",
            m.kind.name(),
            ev,
            opt(m.damping_ratio),
            sig(m.natural_frequency_rad_s, SIG),
            opt(m.period_s),
            opt(m.time_to_half_s),
            opt(m.time_to_double_s),
            b,
            dom
        );
    }
    if a.defective {
        s += "(the eigenvector matrix is singular: participation and classification are unavailable)\n";
    }
    s
}

/// Every element of A and B, one per line, with its derivative name.
pub fn derivatives_table(m: &LinearModel) -> String {
    let mut s = String::new();
    let n = m.states().len();
    for i in 0..n {
        for j in 0..n {
            let e = cierva_model::Element::A { row: i, col: j };
            let _ = writeln!(s, "{:<22} {:>14}", m.element_name(e), sig(m.get(e), SIG));
        }
        for j in 0..m.controls().len() {
            let e = cierva_model::Element::B { row: i, col: j };
            let _ = writeln!(s, "{:<22} {:>14}", m.element_name(e), sig(m.get(e), SIG));
        }
    }
    s
}

/// The weakly coupled systems values of a longitudinal model, or why they do not exist.
pub fn milne_table(m: &LinearModel) -> String {
    let mut s = String::new();
    let row3 = |s: &mut String, title: &str, a: &[[f64; 3]; 3]| {
        let _ = writeln!(s, "{title} (rows and columns u, theta, Omega):");
        for r in a {
            let _ = writeln!(
                s,
                "  {:>12} {:>12} {:>12}",
                sig(r[0], SIG),
                sig(r[1], SIG),
                sig(r[2], SIG)
            );
        }
    };
    match milne::reduced(m).and_then(|r| milne::as_array3(&r)) {
        Ok(a) => row3(&mut s, "Schur complement A22 - A21 A11^-1 A12 (Eq. 12)", &a),
        Err(e) => {
            let _ = writeln!(s, "Schur complement: {e}");
        }
    }
    match milne::eq13(m) {
        Ok(e) => {
            let _ = writeln!(s, "omega_sp^2 = {}", sig(e.omega_sp_squared, SIG));
            row3(
                &mut s,
                "Eq. 13 closed form (neglects Q_q, Z_theta, M_theta)",
                &e.a,
            );
            match e.cubic() {
                Ok(c) => {
                    let u = c.sensitivity();
                    let _ = writeln!(
                        s,
                        "cubic (Eq. 14): A = {}, B = {}, C = {}",
                        sig(c.a, SIG),
                        sig(c.b, SIG),
                        sig(c.c, SIG)
                    );
                    let _ = writeln!(
                        s,
                        "factors (Eq. 16): lambda_Omega = {}, a_ph = {}, b_ph = {}",
                        sig(c.lambda_omega, SIG),
                        sig(c.a_ph, SIG),
                        sig(c.b_ph, SIG)
                    );
                    let _ = writeln!(
                        s,
                        "coupling: dB = {}, dC = {}; first order (Eqs. 17-19): d a_ph = {}, d b_ph = {}, d lambda_Omega = {}",
                        sig(c.coupling.delta_b, SIG),
                        sig(c.coupling.delta_c, SIG),
                        sig(u.delta_a_ph, SIG),
                        sig(u.delta_b_ph, SIG),
                        sig(u.delta_lambda_omega, SIG)
                    );
                }
                Err(e) => {
                    let _ = writeln!(s, "cubic: {e}");
                }
            }
        }
        Err(e) => {
            let _ = writeln!(s, "Eq. 13: {e}");
        }
    }
    if let (Ok(a), Ok(b)) = (milne::m_omega_eq24(m), milne::m_omega_eq25(m)) {
        let _ = writeln!(
            s,
            "M_Omega for a23 = 0 (Eq. 24): {}; for no augmentation of Q_Omega (Eq. 25): {}",
            sig(a, SIG),
            sig(b, SIG)
        );
    }
    s
}

/// The autorotative equilibria of a rotor case's checks, one line per check (for snapshots).
///
/// A check whose equilibrium was not found shows the kind of failure only (the solver's last
/// iterate is not reproducible to the digit across platforms).
pub fn autorotation_table(
    rows: &[(String, Result<crate::checks::result::Quantities, String>)],
) -> String {
    let mut s = String::new();
    let names = crate::inputs::quantity::names(crate::inputs::quantity::AUTOROTATION);
    let _ = write!(s, "{:<10}", "check");
    for n in &names {
        let _ = write!(s, " {n:>12}");
    }
    s.push('\n');
    for (id, r) in rows {
        let _ = write!(s, "{id:<10}");
        match r {
            Ok(values) => {
                for n in &names {
                    let v = values
                        .iter()
                        .find(|(q, _)| q == n)
                        .map_or(f64::NAN, |(_, v)| *v);
                    let _ = write!(s, " {:>12}", sig(v, 5));
                }
            }
            Err(e) => {
                let _ = write!(s, " no equilibrium: {}", e.split(':').next().unwrap_or(""));
            }
        }
        s.push('\n');
    }
    s
}

/// The validation table: one line per quantity (or per check without quantities).
pub fn results_table(results: &[CheckResult]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<34} {:<30} {:<6} {:<12} {:<24} {:>13} {:>13} {:>11}",
        "case", "check", "result", "class", "quantity", "value", "expected", "margin"
    );
    for r in results {
        let head = format!(
            "{:<34} {:<30} {:<6} {:<12}",
            r.case,
            r.check,
            r.outcome.label(),
            r.class.name()
        );
        if let Some(e) = &r.error {
            let _ = writeln!(s, "{head} error: {e}");
        }
        if let Some(f) = &r.finding {
            let _ = writeln!(s, "{head} {}", f.describe());
        }
        if let Some(n) = &r.note {
            let _ = writeln!(s, "{head} note: {n}");
        }
        if let Some(x) = &r.extrapolation {
            let _ = writeln!(s, "{head} {x}");
        }
        if let Some(by) = &r.calibrated_on {
            let _ = writeln!(
                s,
                "{head} calibrated on: a target of the fit of {by}, so no evidence for it"
            );
        }
        if let Some((want, got)) = r.verdict {
            let _ = writeln!(
                s,
                "{head} {:<24} {:>13} {:>13}",
                "verdict",
                format!("{got:?}"),
                format!("{want:?}")
            );
        }
        for q in &r.quantities {
            let expected = match q.expected {
                Some(v) => sig(v, 5),
                None => q.allowed.trim_start_matches("in ").to_string(),
            };
            let _ = writeln!(
                s,
                "{head} {:<24} {:>13} {:>13} {:>11}{}",
                q.quantity,
                sig(q.value, 5),
                expected,
                sig(q.margin, 3),
                if q.pass { "" } else { "  (out)" }
            );
        }
    }
    s
}

/// Counts of each outcome.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Counts {
    pub pass: usize,
    pub fail: usize,
    pub expected_failure: usize,
    pub discrepancy_moved: usize,
    pub unexpected_pass: usize,
    pub error: usize,
}

impl Counts {
    /// Tallies one outcome.
    pub fn add(&mut self, o: Outcome) {
        *self.slot(o) += 1;
    }

    fn slot(&mut self, o: Outcome) -> &mut usize {
        match o {
            Outcome::Pass => &mut self.pass,
            Outcome::Fail => &mut self.fail,
            Outcome::ExpectedFailure => &mut self.expected_failure,
            Outcome::DiscrepancyMoved => &mut self.discrepancy_moved,
            Outcome::UnexpectedPass => &mut self.unexpected_pass,
            Outcome::Error => &mut self.error,
        }
    }

    /// How many checks had this outcome.
    pub fn of(&self, o: Outcome) -> usize {
        let mut c = *self;
        *c.slot(o)
    }

    /// Adds another tally to this one.
    pub fn merge(&mut self, other: &Counts) {
        for o in Outcome::ALL {
            *self.slot(o) += other.of(o);
        }
    }

    /// Every check counted.
    pub fn total(&self) -> usize {
        Outcome::ALL.iter().map(|o| self.of(*o)).sum()
    }

    /// Checks whose outcome turns the run red.
    pub fn failing(&self) -> usize {
        Outcome::ALL
            .iter()
            .filter(|o| !o.ok())
            .map(|o| self.of(*o))
            .sum()
    }

    /// "157 passed, 0 failed, ..." in words.
    pub fn describe(&self) -> String {
        use crate::units::count;
        format!(
            "{} passed, {} failed, {}, {}, {}, {}",
            self.pass,
            self.fail,
            count(
                self.expected_failure,
                "expected failure",
                "expected failures"
            ),
            count(
                self.discrepancy_moved,
                "discrepancy moved",
                "discrepancies moved"
            ),
            count(self.unexpected_pass, "unexpected pass", "unexpected passes"),
            count(self.error, "error", "errors")
        )
    }
}

/// Tallies outcomes.
pub fn counts(results: &[CheckResult]) -> Counts {
    let mut c = Counts::default();
    for r in results {
        c.add(r.outcome);
    }
    c
}

/// Tallies outcomes by class of check, every class listed (in [`CheckClass::ALL`] order).
pub fn counts_by_class(results: &[CheckResult]) -> Vec<(CheckClass, Counts)> {
    CheckClass::ALL
        .iter()
        .map(|k| {
            let mut c = Counts::default();
            for r in results.iter().filter(|r| r.class == *k) {
                c.add(r.outcome);
            }
            (*k, c)
        })
        .collect()
}

/// The Markdown table of validation checks by case (the README's "Validation" table): checks,
/// passes and known discrepancies (expected failures), and a total row.
pub fn validation_table(results: &[CheckResult]) -> String {
    let mut by_case: Vec<(String, Counts)> = Vec::new();
    for r in results.iter().filter(|r| r.class == CheckClass::Validation) {
        match by_case.iter_mut().find(|(c, _)| *c == r.case) {
            Some((_, k)) => k.add(r.outcome),
            None => {
                let mut k = Counts::default();
                k.add(r.outcome);
                by_case.push((r.case.clone(), k));
            }
        }
    }
    by_case.sort_by(|a, b| a.0.cmp(&b.0));
    let rows: Vec<(String, Counts)> = by_case
        .into_iter()
        .map(|(case, k)| (format!("`{case}`"), k))
        .collect();
    counts_table(["case", "validation checks"], &rows)
}

/// A Markdown table of checks, passes and known discrepancies (expected failures), a row per
/// `(label, counts)` and a total row; `header` names the first two columns.
fn counts_table(header: [&str; 2], rows: &[(String, Counts)]) -> String {
    let mut s = format!(
        "| {} | {} | pass | known discrepancies |\n| --- | ---: | ---: | ---: |\n",
        header[0], header[1]
    );
    let mut all = Counts::default();
    for (label, k) in rows {
        all.merge(k);
        let _ = writeln!(
            s,
            "| {label} | {} | {} | {} |",
            k.total(),
            k.pass,
            k.expected_failure
        );
    }
    let _ = writeln!(
        s,
        "| **all** | **{}** | **{}** | **{}** |",
        all.total(),
        all.pass,
        all.expected_failure
    );
    s
}

/// The Markdown table of every check by class (the README's and `docs/validation.md`'s
/// "Cross-code and verification"): checks, passes and known discrepancies (expected
/// failures), one row per class that has checks, and a total row.
pub fn class_table(results: &[CheckResult]) -> String {
    let rows: Vec<(String, Counts)> = counts_by_class(results)
        .into_iter()
        .filter(|(_, k)| k.total() > 0)
        .map(|(class, k)| (class.name().to_string(), k))
        .collect();
    counts_table(["class", "checks"], &rows)
}

/// A committed score as people read it: a relative error in percent, a count of checks or
/// rows as a whole number, anything else to three significant digits.
pub fn score_value(metric: Metric, value: f64) -> String {
    match metric {
        Metric::RmsRelativeError | Metric::PeakRelativeError => {
            format!("{} %", sig(100.0 * value, 3))
        }
        Metric::Inside | Metric::Unsolved => format!("{value:.0}"),
        _ => sig(value, 3),
    }
}

/// The Markdown table of the committed scoreboard (`docs/validation.md`'s "The scoreboard"),
/// generated from it rather than typed: every declared score of the given cases, by case, with
/// its metric, quantity and committed value (`-` where nothing is committed).
pub fn scoreboard_table(board: &Board, cases: &[&crate::suite::case::Case]) -> String {
    let mut s = String::from(
        "| data set (case) | score | metric | quantity | committed value |\n| --- | --- | --- | --- | ---: |\n",
    );
    let mut cases: Vec<_> = cases.iter().filter(|c| !c.scores.is_empty()).collect();
    cases.sort_by(|a, b| a.id.cmp(&b.id));
    for case in cases {
        for spec in &case.scores {
            let value = board
                .scores
                .get(&case.id)
                .and_then(|s| s.get(&spec.id))
                .map_or("-".to_string(), |c| score_value(spec.metric, c.value));
            let _ = writeln!(
                s,
                "| `{}` | `{}` | {} | {} | {value} |",
                case.id,
                spec.id,
                spec.metric.name(),
                spec.quantity.as_deref().unwrap_or("checks"),
            );
        }
    }
    s
}

/// One line per class: "validation      101 checks: 3 passed, ...".
pub fn class_summary(results: &[CheckResult]) -> String {
    let mut s = String::new();
    for (k, c) in counts_by_class(results) {
        let _ = writeln!(
            s,
            "  {:<13} {:>4} {}: {}",
            k.name(),
            c.total(),
            if c.total() == 1 { "check" } else { "checks" },
            c.describe()
        );
    }
    // Checks a corrections file applied was fitted to: their agreement is the fit's, so they
    // are counted apart, by class.
    let calibrated: Vec<&CheckResult> = results
        .iter()
        .filter(|r| r.calibrated_on.is_some())
        .collect();
    if !calibrated.is_empty() {
        let mut c = Counts::default();
        for r in &calibrated {
            c.add(r.outcome);
        }
        let validation = calibrated
            .iter()
            .filter(|r| r.class == CheckClass::Validation)
            .count();
        let _ = writeln!(
            s,
            "  calibrated on {:>4} {} above, {validation} of them validation: targets of the corrections' fit, no evidence for it: {}",
            calibrated.len(),
            if calibrated.len() == 1 {
                "check"
            } else {
                "checks"
            },
            c.describe()
        );
    }
    s
}

/// A trim, for people.
pub fn trim_report(
    title: &str,
    request: crate::inputs::condition::TrimRequest,
    loading: crate::inputs::condition::Loading,
    t: &cierva_model::aircraft::trim::Trim,
) -> String {
    use std::fmt::Write;
    let d = |r: f64| r.to_degrees();
    let a = &t.averaged;
    let r = &a.rotor;
    let mut o = String::new();
    let mass = loading
        .mass_kg
        .map_or("the file's mass".to_string(), |m| format!("{m} kg"));
    let _ = writeln!(
        o,
        "{title}: {} mph, climb {} m/s, turn {} deg/s, {mass}, density altitude {} ft",
        request.airspeed_mph,
        request.climb_m_s,
        request.turn_rate_deg_s,
        loading.density_altitude_ft
    );
    let c = &t.controls;
    let _ = writeln!(
        o,
        "stick long/lat       {:.2} % / {:.2} %   (0 % forward / left)",
        c.stick_longitudinal_percent, c.stick_lateral_percent
    );
    let _ = writeln!(
        o,
        "pedal, throttle      {:.2} %, {:.2} %",
        c.pedal_percent, c.throttle_percent
    );
    let _ = writeln!(
        o,
        "pitch, roll          {:.3} deg, {:.3} deg",
        d(t.pitch_rad),
        d(t.roll_rad)
    );
    let _ = writeln!(
        o,
        "alpha, sideslip      {:.3} deg, {:.3} deg (at the c.g.)",
        d(t.alpha_rad),
        d(t.sideslip_rad)
    );
    let _ = writeln!(
        o,
        "rotor                {:.1} rpm, mu {:.4}, disc alpha {:.2} deg, thrust {:.1} N",
        t.rotor_rpm,
        r.tip_speed_ratio,
        d(r.disc_alpha_rad),
        r.thrust_n
    );
    let _ = writeln!(
        o,
        "shaft tilt           {:.3} deg aft, {:.3} deg right",
        d(r.shaft_pitch_rad),
        d(r.shaft_roll_rad)
    );
    let _ = writeln!(
        o,
        "flapping a0 a1 b1    {:.3} {:.3} {:.3} deg",
        d(r.a0_rad),
        d(r.a1_rad),
        d(r.b1_rad)
    );
    let i = &t.state.inflow;
    let _ = writeln!(
        o,
        "inflow v0 v1s v1c    {:.3} {:.3} {:.3} m/s; skew {:.2} deg",
        i.v0,
        i.v1s,
        i.v1c,
        d(r.skew_rad)
    );
    let p = &a.propeller;
    let _ = writeln!(
        o,
        "propeller            {:.0} rpm, thrust {:.1} N, power {:.1} kW",
        t.propeller_rpm,
        p.thrust_n,
        p.power_w / 1000.0
    );
    let _ = writeln!(
        o,
        "converged            max scaled residual {:.1e} (tolerance {:.0e}) in {} iterations",
        t.residual_norm, t.tolerance, t.iterations
    );
    for (n, v) in &t.residuals {
        let _ = writeln!(o, "  {n:<36} {v:+.2e}");
    }
    o
}

/// Trim values over a set of conditions, one row per quantity and one column per condition,
/// at fixed decimals (three for angles, percent and m/s, one for rpm and N): the trim's own
/// convergence (scaled residuals at most 1e-7) settles them far below the last digit.
pub fn trim_table(
    columns: &[(String, Result<crate::checks::result::Quantities, String>)],
) -> String {
    let rows: [(&str, usize); 18] = [
        ("stick_longitudinal_percent", 3),
        ("stick_lateral_percent", 3),
        ("pedal_percent", 3),
        ("throttle_percent", 3),
        ("pitch_deg", 3),
        ("roll_deg", 3),
        ("alpha_deg", 3),
        ("sideslip_deg", 3),
        ("rotor_rpm", 1),
        ("propeller_rpm", 1),
        ("thrust_n", 1),
        ("disc_alpha_deg", 3),
        ("tip_speed_ratio", 4),
        ("thrust_coefficient_over_solidity", 4),
        ("a1_deg", 3),
        ("b1_deg", 3),
        ("inflow_v0_m_s", 3),
        ("inflow_v1c_m_s", 3),
    ];
    let mut s = String::new();
    let _ = write!(s, "{:<28}", "quantity");
    for (label, _) in columns {
        let _ = write!(s, " {label:>12}");
    }
    s.push('\n');
    for (name, decimals) in rows {
        let _ = write!(s, "{name:<28}");
        for (_, r) in columns {
            let cell = match r {
                Ok(values) => {
                    values
                        .iter()
                        .find(|(q, _)| *q == name)
                        .map_or("-".to_string(), |(_, v)| {
                            // No negative zero in a snapshot.
                            let t = format!("{v:.decimals$}");
                            if t.trim_start_matches('-')
                                .chars()
                                .all(|c| c == '0' || c == '.')
                            {
                                t.trim_start_matches('-').to_string()
                            } else {
                                t
                            }
                        })
                }
                Err(_) => "no trim".to_string(),
            };
            let _ = write!(s, " {cell:>12}");
        }
        s.push('\n');
    }
    for (label, r) in columns {
        if let Err(e) = r {
            let _ = writeln!(s, "{label}: {e}");
        }
    }
    s
}

/// The primary derivatives of a linearised aircraft split by component (seed 000 Tables 1-2).
pub fn breakdown_table(
    model: &LinearModel,
    components: &[(String, LinearModel)],
    names: &[&str],
) -> String {
    let mut s = String::new();
    let _ = write!(s, "{:<12} {:>12}", "derivative", "total");
    for (c, _) in components {
        let _ = write!(s, " {c:>12}");
    }
    s.push('\n');
    for n in names {
        let (Ok(total), Ok(e)) = (model.derivative_value(n), model.derivative(n)) else {
            continue;
        };
        let parts: Vec<(&String, f64)> = components.iter().map(|(c, m)| (c, m.get(e))).collect();
        let _ = write!(s, "{n:<12} {:>12}", sig(total, SIG));
        // Round-off (a sum of parts minus the total) prints as 0.
        let scale = parts.iter().fold(total.abs(), |m, (_, v)| m.max(v.abs()));
        for (_, v) in parts {
            let v = if v.abs() <= 1e-9 * scale { 0.0 } else { v };
            let _ = write!(s, " {:>12}", sig(v, SIG));
        }
        s.push('\n');
    }
    s
}

/// The primary derivatives the breakdown shows.
pub const PRIMARY_DERIVATIVES: &[&str] = &[
    "X_u", "X_w", "Z_u", "Z_w", "M_u", "M_w", "M_q", "Q_u", "Q_w", "Q_q", "Q_Omega", "X_Omega",
    "Z_Omega", "M_Omega", "Y_v", "L_v", "L_p", "N_v", "N_r", "L_eta_c", "M_eta_s",
];

/// A linearised model as a flight-refs reference file (loadable by `cierva modes` and cases).
pub fn linear_reference_yaml(
    id: &str,
    title: &str,
    source: &str,
    model: &LinearModel,
    units: &std::collections::BTreeMap<String, String>,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "id: {id}");
    let _ = writeln!(s, "title: {title}");
    let _ = writeln!(s, "provenance:");
    let _ = writeln!(s, "  source: \"{}\"", source.replace('"', "'"));
    let _ = writeln!(s, "linear_model:");
    let list = |v: &[String]| v.join(", ");
    let _ = writeln!(s, "  states: [{}]", list(m_states(model)));
    let _ = writeln!(s, "  controls: [{}]", list(model.controls()));
    let _ = writeln!(s, "  units:");
    for n in model.states().iter().chain(model.controls()) {
        let _ = writeln!(
            s,
            "    {n}: \"{}\"",
            units.get(n).map_or("not stated", |u| u.as_str())
        );
    }
    let row = |r: Vec<f64>| {
        format!(
            "[{}]",
            r.iter()
                .map(|v| format!("{v:e}"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let n = model.states().len();
    let _ = writeln!(s, "  a:");
    for i in 0..n {
        let _ = writeln!(
            s,
            "    - {}",
            row((0..n).map(|j| model.a()[(i, j)]).collect())
        );
    }
    let _ = writeln!(s, "  b:");
    for i in 0..n {
        let _ = writeln!(
            s,
            "    - {}",
            row((0..model.controls().len())
                .map(|j| model.b()[(i, j)])
                .collect())
        );
    }
    s
}

fn m_states(m: &LinearModel) -> &[String] {
    m.states()
}

/// Time-history metrics of every `time_history` check of a case, response by response (for
/// snapshots; four significant figures).
pub fn time_history_table(rows: &[(String, Vec<crate::run::replay::SignalMetrics>)]) -> String {
    let mut s = format!(
        "{:<28} {:<10} {:>14} {:>12} {:>10} {:>10}\n",
        "check", "response", "max |error|", "at s", "rms error", "theil"
    );
    for (check, metrics) in rows {
        for m in metrics {
            s += &format!(
                "{:<28} {:<10} {:>14.4} {:>12.2} {:>10.4} {:>10.4}\n",
                check, m.signal, m.max_abs_error, m.time_of_max_s, m.rms_error, m.theil
            );
        }
    }
    s
}
