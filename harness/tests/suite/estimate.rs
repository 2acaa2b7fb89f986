//! `cierva estimate`: an aircraft's tail and pod coefficients from its geometry by published
//! methods, printed step by step with sources and ranges; bad input refused.

use super::common::repo_root;
use crate::common::cierva;
use cierva_harness::estimate;
use cierva_harness::inputs;

/// The text derivation names every method's source and accuracy, gives each step's value and
/// range, and sets the file's values beside the estimates; the JSON carries the same steps,
/// each estimate inside its range.
#[test]
fn estimate_prints_the_derivation_with_sources_and_ranges() {
    let (code, out, err) = cierva(&["estimate", "aircraft/vpm-m16.yaml", "--quiet"]);
    assert_eq!(code, 0, "{err}");
    for needle in [
        "propeller in trim at 70 mph, 450 kg, density altitude 2000 ft",
        "fin: effective aspect ratio",
        "fin: lift slope at its effective aspect ratio",
        "fin: the body's factor on its side force, k_v",
        "fin: lift slope against sideslip, k_v x the slope (lift_slope_per_rad)",
        "fin: share in the slipstream (slipstream_fraction)",
        "pod: Munk couple (k2 - k1) Vol (munk_yaw_m3)",
        "DATCOM Sec. 5.3.1.1",
        "Helmbold 1942",
        "Munk 1924 (NACA TR 184)",
        "Lamb 1932 Art. 373",
        "actuator-disc momentum theory",
        "accuracy: estimated:",
        "the file's values beside the estimates:",
        "airframe.fin.lift_slope_per_rad",
    ] {
        assert!(out.contains(needle), "`{needle}` missing from:\n{out}");
    }
    let (code, out, err) = cierva(&[
        "estimate",
        "aircraft/vpm-m16.yaml",
        "--format",
        "json",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let steps = v["estimates"]["steps"].as_array().unwrap();
    assert!(steps.len() >= 15, "{steps:?}");
    for s in steps {
        let (lo, x, hi) = (
            s["value"]["lower"].as_f64().unwrap(),
            s["value"]["value"].as_f64().unwrap(),
            s["value"]["upper"].as_f64().unwrap(),
        );
        assert!(x.is_finite() && lo <= x && x <= hi, "{s}");
        if let Some(m) = s["method"].as_object() {
            assert!(!m["source"].as_str().unwrap().is_empty(), "{s}");
            assert!(!m["accuracy"].as_str().unwrap().is_empty(), "{s}");
        }
    }
    let slope = &v["estimates"]["fin"]["lift_slope_per_rad"];
    assert!(slope["lower"].as_f64() < slope["value"].as_f64(), "{slope}");
    assert_eq!(v["condition"]["airspeed_mph"], 70.0);
}

/// The condition can be given on the command line: the slipstream's share and excess follow
/// the propeller's operating point, the lift slopes (geometry alone) do not move.
#[test]
fn estimate_at_another_airspeed_moves_only_the_flow() {
    let file = inputs::aircraft::load(&repo_root().join("aircraft/vpm-m16.yaml")).unwrap();
    let at = |mph: f64| {
        let c = inputs::aircraft::ConditionSpec {
            airspeed_mph: mph,
            mass_kg: 450.0,
            density_altitude_ft: 2000.0,
        };
        estimate::derive(&file, Some(c)).unwrap()
    };
    let (slow, fast) = (at(40.0), at(70.0));
    let fin = |d: &estimate::Derivation| d.estimates.fin.unwrap();
    assert_eq!(fin(&slow).lift_slope_per_rad, fin(&fast).lift_slope_per_rad);
    assert!(slow.operating_point.thrust_n != fast.operating_point.thrust_n);
    assert!(slow.operating_point.side_force_per_m_s < 0.0);
    let excess = |d: &estimate::Derivation| {
        d.estimates
            .steps
            .iter()
            .find(|s| s.quantity == "fin: slipstream dynamic pressure over the free stream's")
            .unwrap()
            .value
            .value
    };
    // At 40 mph the propeller's excess is a larger share of the airspeed.
    assert!(
        excess(&slow) > excess(&fast),
        "{} {}",
        excess(&slow),
        excess(&fast)
    );
}

/// The gyroplane files use their estimates (the VPM M16's tail and pod; the
/// Montgomerie-Parsons' tail, issue 33 item 5, which gives no pod): every coefficient `cierva
/// estimate` gives is the file's value to the three figures the file writes (half a unit in the
/// third figure), and the file's plausible range for it is the estimate's (the method's
/// accuracy), rounded outward in the third figure; where the estimate has no width (a tailplane
/// wholly in the slipstream) the file gives no range.
#[test]
fn the_gyroplane_files_use_their_estimates() {
    for (name, coefficients) in [("vpm-m16", 8), ("montgomerie-parsons", 7)] {
        file_uses_its_estimates(name, coefficients);
    }
}

fn file_uses_its_estimates(name: &str, coefficients: usize) {
    let file = inputs::aircraft::load(&repo_root().join(format!("aircraft/{name}.yaml"))).unwrap();
    let d = estimate::derive(&file, None).unwrap();
    assert_eq!(d.compared.len(), coefficients, "{name}: {:?}", d.compared);
    // Half a unit in the third significant figure of `x`.
    let rounding = |x: f64| {
        if x == 0.0 {
            0.0
        } else {
            0.5 * 10f64.powf(x.abs().log10().floor() - 2.0)
        }
    };
    for c in &d.compared {
        let e = c.estimate;
        assert!(
            (c.file - e.value).abs() <= rounding(e.value) + 1e-12,
            "{}: the file has {}, the estimate is {e:?}",
            c.field,
            c.file
        );
        match c.file_range {
            None => assert_eq!(e.lower, e.upper, "{}: no range for {e:?}", c.field),
            Some((lo, hi)) => {
                // Outward to the third figure: at most one unit in it.
                assert!(
                    (lo - e.lower).abs() <= 2.0 * rounding(e.lower) + 1e-12
                        && (hi - e.upper).abs() <= 2.0 * rounding(e.upper) + 1e-12,
                    "{}: the file's range [{lo}, {hi}], the estimate's {e:?}",
                    c.field
                );
                assert!(
                    lo <= e.lower + 1e-12 && hi >= e.upper - 1e-12,
                    "{}: rounded inward",
                    c.field
                );
            }
        }
        assert!(
            file.source_of(&c.field)
                .is_some_and(|s| s.starts_with("estimated by `cierva estimate`")),
            "{}: its source does not cite the estimate",
            c.field
        );
    }
}

/// A file with no geometry to estimate from (the Montgomerie-Parsons' without its planforms), and
/// a file that does not load, are bad input (exit 2) with the reason.
#[test]
fn estimate_refuses_a_file_with_nothing_to_estimate() {
    let dir = crate::common::scratch("no-geometry");
    std::fs::create_dir_all(&dir).unwrap();
    let aircraft = repo_root().join("aircraft");
    for f in [
        "montgomerie-parsons-rotor.yaml",
        "montgomerie-parsons-propeller.yaml",
    ] {
        std::fs::copy(aircraft.join(f), dir.join(f)).unwrap();
    }
    let text = std::fs::read_to_string(aircraft.join("montgomerie-parsons.yaml")).unwrap();
    let stripped = without_geometry(&text);
    assert!(
        !stripped.contains("planform: {") && !stripped.contains("    estimates_at: {"),
        "{stripped}"
    );
    let path = dir.join("montgomerie-parsons.yaml");
    std::fs::write(&path, stripped).unwrap();
    let (code, _, err) = cierva(&["estimate", path.to_str().unwrap(), "--quiet"]);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("gives no geometry to estimate from"), "{err}");
    let (code, _, err) = cierva(&[
        "estimate",
        "harness/tests/bad-aircraft/fin-behind-nothing.yaml",
        "--quiet",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("the fin must stand behind the pod"), "{err}");
}

/// An aircraft file's text without its geometry for the estimates: each surface's `planform`
/// entry (with the comma and line break before it), the `estimates_at` line, and their sources
/// (a source written over several lines with its continuation).
fn without_geometry(text: &str) -> String {
    let mut t = text.to_string();
    while let Some(i) = t.find("planform: {") {
        let start = t[..i].rfind(',').expect("a planform follows another entry");
        let end = i + t[i..].find('}').unwrap() + 1;
        t.replace_range(start..end, "");
    }
    let mut out = String::new();
    let mut continuation = false;
    for line in t.lines() {
        if continuation && line.starts_with("    ") {
            continue;
        }
        let entry = line.trim_start();
        continuation = false;
        if entry.starts_with("estimates_at:")
            || entry.starts_with("airframe.estimates_at:")
            || entry.starts_with("airframe.tailplane.planform:")
            || entry.starts_with("airframe.fin.planform:")
        {
            continuation = entry.ends_with(">-");
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}
