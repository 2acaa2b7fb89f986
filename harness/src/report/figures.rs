//! The report's figures, built from check results alone.
//!
//! - Across cases: every aircraft derivative checked at two airspeeds or more, or at two masses,
//!   by aircraft and derivative, the model at each mass as a line and the references as bars
//!   (seed 001 Fig. 5).
//! - In a case: trim quantities against airspeed; a trim sweep's controls, attitudes and
//!   rotorspeed; an isolated rotor's quantities against tip-speed ratio (TR 515); the
//!   eigenvalues on the complex plane, one series per condition, the checked modes ringed; the
//!   a flight test's trim points with their 95 % scatter and the model at each; the
//!   BCAR Section T chart (seed 000 Figs. 3 and 14: period against damping index, with the
//!   boundary); time histories, reference and model, with the allowed error as a band.

use super::plot::{Bar, Figure, Series, Shade, Style};
use super::{CaseRun, Run};
use crate::checks::Placed;
use crate::suite::case::{Check, Subject};
use crate::suite::outcome::{CheckResult, PlotData};
use std::collections::BTreeMap;

fn check_of<'a>(c: &'a CaseRun, r: &CheckResult) -> Option<&'a Check> {
    c.ran.case.checks.iter().find(|k| k.id == r.check)
}

/// Where the figures that gather checks place a result's check.
fn placed<'a>(c: &'a CaseRun, r: &CheckResult) -> Option<Placed<'a>> {
    check_of(c, r)?.behaviour().placed()
}

fn bar(x: f64, q: &crate::suite::outcome::QuantityResult) -> Bar {
    Bar {
        x,
        lower: q.lower,
        upper: q.upper,
        expected: q.expected,
    }
}

fn distinct(xs: impl Iterator<Item = f64>) -> usize {
    let mut v: Vec<f64> = xs.filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v.len()
}

/// An eigenvalue as points on the complex plane: a complex mode is listed once, so its
/// conjugate is drawn too.
fn with_conjugate(e: &cierva_model::Complex) -> Vec<(f64, f64)> {
    if e.im == 0.0 {
        vec![(e.re, 0.0)]
    } else {
        vec![(e.re, e.im), (e.re, -e.im)]
    }
}

fn sorted(mut p: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    p.sort_by(|a, b| a.0.total_cmp(&b.0));
    p
}

/// The unit of a derivative `X_u`: force or moment per unit of the state or control.
fn derivative_unit(name: &str) -> String {
    let Some((f, x)) = name.split_once('_') else {
        return String::new();
    };
    let units = crate::run::linearise::linear_units();
    let of = units.get(x).map_or("?", |s| s.as_str());
    let of = if of.starts_with('%') { "%" } else { of };
    let numerator = match f {
        "X" | "Y" | "Z" => "m/s^2",
        "L" | "M" | "N" | "Q" => "rad/s^2",
        _ => "?",
    };
    format!("{numerator} per {of}")
}

/// Aircraft derivative checks across cases: one figure per aircraft and derivative checked at
/// two or more airspeeds or masses.
pub fn across_cases(run: &Run) -> Vec<Figure> {
    /// (aircraft, derivative) -> (model points by series, reference bars, the model's 95 %
    /// band over its inputs by series).
    type Group = (
        BTreeMap<String, Vec<(f64, f64)>>,
        Vec<Bar>,
        BTreeMap<String, Vec<(f64, f64, f64)>>,
    );
    let mut groups: BTreeMap<(String, String), Group> = BTreeMap::new();
    for c in &run.cases {
        let Subject::Aircraft { file, loading } = &c.ran.case.subject else {
            continue;
        };
        let mass = loading.mass_kg.unwrap_or(file.aircraft.mass.mass_kg);
        for r in &c.ran.results {
            let Some(Placed::Derivative {
                label,
                airspeed_mph,
                corrected,
                as_identified,
            }) = placed(c, r)
            else {
                continue;
            };
            let Some(q) = r.quantities.iter().find(|q| q.quantity == "value") else {
                continue;
            };
            let corrected = corrected || !c.ran.corrections.is_empty();
            let series = format!(
                "model, {mass:.0} kg{}{}",
                if corrected { ", corrected" } else { "" },
                if as_identified {
                    ", with flapping, as identified"
                } else {
                    ""
                }
            );
            let g = groups.entry((file.id.clone(), label)).or_default();
            let spread = c
                .uncertainty
                .as_ref()
                .and_then(|u| {
                    u.results
                        .iter()
                        .find(|x| x.check == r.check && x.quantity == q.quantity)
                })
                .filter(|x| {
                    x.p2_5.is_finite() && x.p97_5.is_finite() && !x.contributors.is_empty()
                });
            if let Some(x) = spread {
                let band = g.2.entry(series.clone()).or_default();
                if !band.iter().any(|p| p.0 == airspeed_mph) {
                    band.push((airspeed_mph, x.p2_5, x.p97_5));
                }
            }
            let pts = g.0.entry(series).or_default();
            if !pts.iter().any(|p| p.0 == airspeed_mph) {
                pts.push((airspeed_mph, q.value));
            }
            g.1.push(bar(airspeed_mph, q));
        }
    }
    groups
        .into_iter()
        // Against airspeed, or at one airspeed at two masses or more (seed 001 Table 2's flight
        // bounds at 70 mph, the model at minimum and maximum weight).
        .filter(|(_, (s, _, _))| distinct(s.values().flatten().map(|p| p.0)) >= 2 || s.len() >= 2)
        .map(|((aircraft, label), (series, bars, bands))| Figure {
            y_label: if label.contains('/') {
                "ratio".into()
            } else {
                derivative_unit(&label)
            },
            title: format!("{aircraft}: {label} against airspeed"),
            x_label: "airspeed, mph".into(),
            series: series
                .into_iter()
                .map(|(name, p)| Series {
                    name,
                    points: sorted(p),
                    style: Style::LineMarkers,
                    colour: None,
                })
                .collect(),
            bars,
            bars_name: "reference (allowed range)".into(),
            bands: bands
                .into_iter()
                .map(|(name, mut points)| {
                    points.sort_by(|a, b| a.0.total_cmp(&b.0));
                    Shade {
                        name: format!("{name}: 95 % of its inputs"),
                        points,
                    }
                })
                .collect(),
            ..Figure::default()
        })
        .collect()
}

/// Inflow from blade flapping against airspeed (seed 003 Figs. 4-6): every teeter-record case,
/// by rotor, one figure per component. The airspeed is the record's mean hub speed; the model's
/// recovered value is the line, each reference's allowed range a bar with its expected value.
pub fn inflow_against_airspeed(run: &Run) -> Vec<Figure> {
    type Group = (Vec<(f64, f64)>, Vec<Bar>);
    let mut groups: BTreeMap<(String, String), Group> = BTreeMap::new();
    for c in &run.cases {
        let Subject::FlapRecord { record, rotor, .. } = &c.ran.case.subject else {
            continue;
        };
        let mean = |n: &str| {
            record
                .channel(n)
                .map_or(f64::NAN, |v| v.iter().sum::<f64>() / v.len().max(1) as f64)
        };
        let speed = mean("hub_inplane_speed_m_s").hypot(mean("hub_normal_speed_m_s"));
        for r in c
            .ran
            .results
            .iter()
            .filter(|r| placed(c, r) == Some(Placed::FlapRecord))
        {
            for q in &r.quantities {
                let g = groups
                    .entry((rotor.id.clone(), q.quantity.clone()))
                    .or_default();
                if !g.0.iter().any(|p| p.0 == speed) {
                    g.0.push((speed, q.value));
                }
                g.1.push(bar(speed, q));
            }
        }
    }
    groups
        .into_iter()
        .filter(|(_, (p, _))| distinct(p.iter().map(|p| p.0)) >= 2)
        .map(|((rotor, quantity), (points, bars))| Figure {
            title: format!("{rotor}: {quantity} from teeter flapping against airspeed"),
            x_label: "airspeed at the hub, m/s".into(),
            y_label: quantity,
            series: vec![Series {
                name: "recovered from the record (seed 003 Eqs. 13-19)".into(),
                points: sorted(points),
                style: Style::LineMarkers,
                colour: None,
            }],
            bars,
            bars_name: "reference (allowed range; x the expected value)".into(),
            ..Figure::default()
        })
        .collect()
}

/// A case's figures.
pub fn of_case(c: &CaseRun) -> Vec<Figure> {
    let mut out = Vec::new();
    out.extend(trim_against_airspeed(c));
    out.extend(sweeps(c));
    out.extend(trim_points(c));
    out.extend(tunnel(c));
    out.extend(eigenvalues(c));
    out.extend(bcar_chart(c));
    out.extend(loci(c));
    out.extend(time_histories(c));
    out.extend(bode(c));
    out
}

/// Per-quantity figures of `(x, result quantity)` points: the model's values and the
/// references' ranges, and by quantity the model's 95 % over its inputs at each point where
/// the case was propagated (`intervals`).
fn by_quantity(
    points: Vec<(f64, &crate::suite::outcome::QuantityResult)>,
    title: impl Fn(&str) -> String,
    x_label: &str,
    style: Style,
    intervals: &BTreeMap<String, Vec<(f64, f64, f64)>>,
) -> Vec<Figure> {
    let mut groups: BTreeMap<String, Vec<(f64, &crate::suite::outcome::QuantityResult)>> =
        BTreeMap::new();
    for (x, q) in points {
        groups.entry(q.quantity.clone()).or_default().push((x, q));
    }
    groups
        .into_iter()
        .filter(|(_, v)| distinct(v.iter().map(|p| p.0)) >= 2)
        .map(|(name, v)| Figure {
            title: title(&name),
            x_label: x_label.into(),
            y_label: name.clone(),
            series: vec![Series {
                name: "model".into(),
                points: sorted(v.iter().map(|(x, q)| (*x, q.value)).collect()),
                style,
                colour: None,
            }],
            bars: v.iter().map(|(x, q)| bar(*x, q)).collect(),
            bars_name: "reference (allowed range)".into(),
            intervals: intervals.get(&name).map(|p| Shade {
                name: "model: 95 % of its inputs".into(),
                points: p.clone(),
            }),
            ..Figure::default()
        })
        .collect()
}

fn trim_against_airspeed(c: &CaseRun) -> Vec<Figure> {
    let pts: Vec<(f64, &crate::suite::outcome::QuantityResult)> = c
        .ran
        .results
        .iter()
        .filter_map(|r| match placed(c, r)? {
            Placed::Airspeed(x) => Some((x, r)),
            _ => None,
        })
        .flat_map(|(x, r)| r.quantities.iter().map(move |q| (x, q)))
        .collect();
    by_quantity(
        pts,
        |q| format!("trim: {q} against airspeed"),
        "airspeed, mph",
        Style::LineMarkers,
        &BTreeMap::new(),
    )
}

fn sweeps(c: &CaseRun) -> Vec<Figure> {
    let groups: [(&str, &str, &[&str]); 3] = [
        (
            "controls",
            "% of travel",
            &[
                "stick_longitudinal_percent",
                "stick_lateral_percent",
                "pedal_percent",
                "throttle_percent",
            ],
        ),
        (
            "attitudes",
            "deg",
            &["pitch_deg", "roll_deg", "alpha_deg", "disc_alpha_deg"],
        ),
        ("rotorspeed", "rpm", &["rotor_rpm"]),
    ];
    let mut out = Vec::new();
    for r in &c.ran.results {
        let Some(PlotData::Sweep { points }) = &r.plot else {
            continue;
        };
        for (what, unit, names) in groups {
            out.push(Figure {
                title: format!("{}: trimmed {what} against airspeed", r.check),
                x_label: "airspeed, mph".into(),
                y_label: unit.into(),
                series: names
                    .iter()
                    .map(|n| Series {
                        name: (*n).into(),
                        points: points
                            .iter()
                            .filter_map(|(v, q)| {
                                q.iter().find(|(k, _)| k == n).map(|(_, y)| (*v, *y))
                            })
                            .collect(),
                        style: Style::LineMarkers,
                        colour: None,
                    })
                    .collect(),
                ..Figure::default()
            });
        }
    }
    out
}

/// A `trim_points` check's figures, one a quantity: each flight point with its 95 % scatter
/// (1.96 standard deviations) as a bar, and the model trimmed at each point.
fn trim_points(c: &CaseRun) -> Vec<Figure> {
    let mut out = Vec::new();
    for r in &c.ran.results {
        let Some(PlotData::TrimPoints { quantities }) = &r.plot else {
            continue;
        };
        for (q, points) in quantities {
            out.push(Figure {
                title: format!("{}: {q} at the flight test's trim points", r.check),
                x_label: "airspeed, mph".into(),
                y_label: q.clone(),
                series: vec![Series {
                    name: "model, trimmed at each point".into(),
                    points: sorted(points.iter().map(|p| (p.airspeed_mph, p.model)).collect()),
                    style: Style::LineMarkers,
                    colour: None,
                }],
                bars: points
                    .iter()
                    .map(|p| Bar {
                        x: p.airspeed_mph,
                        lower: p.flight - 1.96 * p.sd,
                        upper: p.flight + 1.96 * p.sd,
                        expected: Some(p.flight),
                    })
                    .collect(),
                bars_name: "flight point (95 % of its scatter)".into(),
                ..Figure::default()
            });
        }
    }
    out
}

fn tunnel(c: &CaseRun) -> Vec<Figure> {
    let rows: Vec<(&CheckResult, &crate::suite::case::TunnelSpec)> = c
        .ran
        .results
        .iter()
        .filter_map(|r| match placed(c, r)? {
            Placed::Tunnel(t) => Some((r, t)),
            _ => None,
        })
        .collect();
    if rows.is_empty() {
        return vec![];
    }
    let by_mu = rows.iter().all(|(_, t)| t.tip_speed_ratio.is_some());
    let x_of = |t: &crate::suite::case::TunnelSpec| {
        if by_mu {
            t.tip_speed_ratio.unwrap_or(f64::NAN)
        } else {
            t.alpha_deg.unwrap_or(f64::NAN)
        }
    };
    let pts: Vec<(f64, &crate::suite::outcome::QuantityResult)> = rows
        .iter()
        .flat_map(|(r, t)| r.quantities.iter().map(move |q| (x_of(t), q)))
        .collect();
    // The model's 95 % over its inputs at each row, where the case was propagated.
    let mut intervals: BTreeMap<String, Vec<(f64, f64, f64)>> = BTreeMap::new();
    if let Some(u) = &c.uncertainty {
        for (r, t) in &rows {
            for x in u.results.iter().filter(|x| x.check == r.check) {
                if x.p2_5.is_finite() && x.p97_5.is_finite() && !x.contributors.is_empty() {
                    intervals.entry(x.quantity.clone()).or_default().push((
                        x_of(t),
                        x.p2_5,
                        x.p97_5,
                    ));
                }
            }
        }
    }
    by_quantity(
        pts,
        |q| format!("isolated rotor: {q}"),
        if by_mu {
            "tip-speed ratio mu"
        } else {
            "disc angle of attack, deg"
        },
        Style::Markers,
        &intervals,
    )
}

fn eigenvalues(c: &CaseRun) -> Vec<Figure> {
    let mut series: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
    let mut selected = Vec::new();
    for r in &c.ran.results {
        let Some(PlotData::Modes {
            eigenvalues,
            selected: s,
            ..
        }) = &r.plot
        else {
            continue;
        };
        let Some(Placed::Eigenvalues {
            system,
            condition,
            modified,
            ..
        }) = placed(c, r)
        else {
            continue;
        };
        let label = match condition {
            Some(cond) => format!("{:>5.1} mph, {system:?}", cond.airspeed_mph),
            None => format!("{system:?} system"),
        };
        if modified {
            continue;
        }
        series
            .entry(label)
            .or_insert_with(|| eigenvalues.iter().flat_map(with_conjugate).collect());
        if let Some(s) = s {
            selected.extend(with_conjugate(s));
        }
    }
    if series.is_empty() {
        return vec![];
    }
    let mut s: Vec<Series> = series
        .into_iter()
        .map(|(name, points)| Series {
            name,
            points,
            style: Style::Markers,
            colour: None,
        })
        .collect();
    if s.len() > 7 {
        s.truncate(7);
    }
    s.push(Series {
        name: "modes the checks select".into(),
        points: selected,
        style: Style::Rings,
        colour: Some(7),
    });
    vec![Figure {
        title: format!("{}: eigenvalues", c.ran.case.id),
        x_label: "real part, 1/s".into(),
        y_label: "imaginary part, rad/s".into(),
        series: s,
        x_zero: true,
        ..Figure::default()
    }]
}

/// Root loci of checks that set a derivative, one figure per derivative and value set.
fn loci(c: &CaseRun) -> Vec<Figure> {
    let mut seen: Vec<(String, u64)> = Vec::new();
    let mut out = Vec::new();
    for r in &c.ran.results {
        let Some(PlotData::Modes {
            locus: Some(l),
            selected,
            ..
        }) = &r.plot
        else {
            continue;
        };
        let key = (l.derivative.clone(), l.set.to_bits());
        if seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let sweep: Vec<(f64, f64)> = l
            .points
            .iter()
            .flat_map(|(_, es)| es.iter().flat_map(with_conjugate))
            .collect();
        let at = |v: f64| -> Vec<(f64, f64)> {
            l.points
                .iter()
                .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
                .map(|(_, es)| es.iter().flat_map(with_conjugate).collect())
                .unwrap_or_default()
        };
        let mut series = vec![
            Series {
                name: format!(
                    "{} from {:.4} to {:.4}",
                    l.derivative,
                    l.points.first().map_or(f64::NAN, |p| p.0),
                    l.points.last().map_or(f64::NAN, |p| p.0)
                ),
                points: sweep,
                style: Style::Markers,
                colour: Some(7),
            },
            Series {
                name: format!("nominal, {} = {:.5}", l.derivative, l.nominal),
                points: at(l.nominal),
                style: Style::Markers,
                colour: Some(0),
            },
            Series {
                name: format!("set, {} = {:.5}", l.derivative, l.set),
                points: at(l.set),
                style: Style::Markers,
                colour: Some(1),
            },
        ];
        if let Some(s) = selected {
            series.push(Series {
                name: format!("{}'s mode", r.check),
                points: with_conjugate(s),
                style: Style::Rings,
                colour: Some(2),
            });
        }
        out.push(Figure {
            title: format!("{}: root locus in {}", c.ran.case.id, l.derivative),
            x_label: "real part, 1/s".into(),
            y_label: "imaginary part, rad/s".into(),
            series,
            x_zero: true,
            ..Figure::default()
        });
    }
    out
}

fn bcar_chart(c: &CaseRun) -> Vec<Figure> {
    let mut complies = Vec::new();
    let mut not = Vec::new();
    let on_chart =
        |r: &&CheckResult| matches!(placed(c, r), Some(Placed::Eigenvalues { bcar: true, .. }));
    for r in c.ran.results.iter().filter(on_chart) {
        let Some(PlotData::Modes {
            selected: Some(e), ..
        }) = &r.plot
        else {
            continue;
        };
        if e.im == 0.0 {
            continue;
        }
        let a = cierva_model::analysis::bcar::assess_eigenvalue(
            e.re,
            2.0 * std::f64::consts::PI / e.im.abs(),
        );
        let (x, t) = (a.damping_index, a.period_s);
        match a.verdict {
            cierva_model::analysis::bcar::Verdict::Complies => complies.push((x, t)),
            _ => not.push((x, t)),
        }
    }
    if complies.is_empty() && not.is_empty() {
        return vec![];
    }
    let t_max = complies
        .iter()
        .chain(&not)
        .map(|p| p.1)
        .fold(25.0f64, f64::max)
        .min(120.0);
    let boundary = vec![
        (1.0, 0.0),
        (1.0, 5.0),
        (0.5, 5.0),
        (0.5, 10.0),
        (0.0, 10.0),
        (0.0, 20.0),
        (-1.0, 20.0),
        (-t_max / 20.0, t_max),
    ];
    vec![Figure {
        title: format!(
            "{}: BCAR Section T (complies to the right of the boundary)",
            c.ran.case.id
        ),
        x_label: "damping index T / t_half (1 / cycles to half amplitude)".into(),
        y_label: "period, s".into(),
        series: vec![
            Series {
                name: "BCAR Section T boundary".into(),
                points: boundary,
                style: Style::Line,
                colour: Some(7),
            },
            Series {
                name: "complies".into(),
                points: complies,
                style: Style::Markers,
                colour: Some(2),
            },
            Series {
                name: "does not comply".into(),
                points: not,
                style: Style::Markers,
                colour: Some(1),
            },
        ],
        x_zero: true,
        ..Figure::default()
    }]
}

fn time_histories(c: &CaseRun) -> Vec<Figure> {
    let mut out = Vec::new();
    for r in &c.ran.results {
        let Some(PlotData::TimeHistory { traces }) = &r.plot else {
            continue;
        };
        for t in traces {
            let n = t.time_s.len().min(t.reference.len()).min(t.model.len());
            // At most about 500 points a trace: enough for the eye, and the page stays small.
            let stride = n.div_ceil(500).max(1);
            let keep = |i: &usize| i.is_multiple_of(stride) || *i + 1 == n;
            let pair = |v: &[f64]| -> Vec<(f64, f64)> {
                (0..n).filter(keep).map(|i| (t.time_s[i], v[i])).collect()
            };
            out.push(Figure {
                title: format!("{}: {}", r.check, t.signal),
                x_label: "time, s".into(),
                y_label: t.signal.clone(),
                series: vec![
                    Series {
                        name: "reference".into(),
                        points: pair(&t.reference),
                        style: Style::Line,
                        colour: Some(0),
                    },
                    Series {
                        name: "model".into(),
                        points: pair(&t.model),
                        style: Style::Line,
                        colour: Some(1),
                    },
                ],
                bands: t
                    .band
                    .map(|b| Shade {
                        name: format!("reference ± {b} (largest error allowed)"),
                        points: (0..n)
                            .filter(keep)
                            .map(|i| (t.time_s[i], t.reference[i] - b, t.reference[i] + b))
                            .collect(),
                    })
                    .into_iter()
                    .collect(),
                ..Figure::default()
            });
        }
    }
    out
}

/// A frequency-response check's Bode figures (magnitude, phase, the reference's coherence;
/// log frequency): the reference's response as markers, the model's as a line.
fn bode(c: &CaseRun) -> Vec<Figure> {
    let mut out = Vec::new();
    for r in &c.ran.results {
        let Some(PlotData::FrequencyResponse {
            title,
            frequencies_hz,
            reference,
            coherence,
            model,
        }) = &r.plot
        else {
            continue;
        };
        out.extend(super::plot::bode_panels(
            &format!("{}: {title}", r.check),
            frequencies_hz,
            &[
                ("reference", reference.iter().copied().map(Some).collect()),
                ("model", model.iter().copied().map(Some).collect()),
            ],
            coherence,
            crate::checks::frequency_response::COHERENCE_MIN,
        ));
    }
    out
}
