//! `cierva autorotate`: the isolated rotor's equilibrium, at an angle or a tip-speed ratio.

use super::*;

#[test]
fn autorotate_finds_the_pca2_equilibrium() {
    let (code, out, err) = cierva(&[
        "autorotate",
        "aircraft/pca-2-rotor.yaml",
        "--alpha-deg",
        "6.6",
        "--airspeed-m-s",
        "18.16",
        "--collective-deg",
        "1.9",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    // TR 515 Table III row 15 was run near this condition at 98.8 rpm.
    let rpm = v["rotor_rpm"].as_f64().unwrap();
    assert!((90.0..110.0).contains(&rpm), "{rpm}");
    assert!(v["inflow_v0_m_s"].as_f64().unwrap() > 0.0);
    assert!(v["equilibrium"]["residual_norm"].as_f64().unwrap() <= 1e-9);
    let (code, _, err) = cierva(&[
        "autorotate",
        "aircraft/pca-2-rotor.yaml",
        "--alpha-deg",
        "6.6",
        "--airspeed-m-s",
        "-3",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("airspeed_m_s must be positive"), "{err}");
    let (code, _, err) = cierva(&[
        "autorotate",
        "cases/naca-tr515-table-iii.yaml",
        "--alpha-deg",
        "6.6",
        "--airspeed-m-s",
        "18",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown field"), "{err}");
}

/// The tip-speed-ratio mode finds the angle back: the equilibrium at 6.6 deg and 18.16 m/s,
/// asked for at its own mu and rotor speed, is at 6.6 deg again; the fitted corrections apply;
/// half a condition is refused.
#[test]
fn autorotate_at_a_tip_speed_ratio_finds_the_angle() {
    let json = |args: &[&str]| {
        let mut a = vec![
            "autorotate",
            "aircraft/pca-2-rotor.yaml",
            "--collective-deg",
            "1.9",
        ];
        a.extend(args);
        a.extend(["--format", "json"]);
        let (code, out, err) = cierva(&a);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let at = json(&["--alpha-deg", "6.6", "--airspeed-m-s", "18.16"]);
    let (mu, rpm) = (
        at["tip_speed_ratio"].as_f64().unwrap(),
        at["rotor_rpm"].as_f64().unwrap(),
    );
    let back = json(&[
        "--tip-speed-ratio",
        &mu.to_string(),
        "--rpm",
        &rpm.to_string(),
    ]);
    for key in [
        "alpha_deg",
        "rpm",
        "rotor_alpha_deg",
        "rotor_rpm",
        "lift_coefficient",
        "drag_coefficient",
        "lift_to_drag",
    ] {
        assert!(back[key].is_f64(), "{key}: {back}");
    }
    let alpha = back["rotor_alpha_deg"].as_f64().unwrap();
    assert!((alpha - 6.6).abs() < 1e-4, "{alpha}");
    assert_eq!(back["alpha_deg"], back["rotor_alpha_deg"]);
    assert_eq!(back["rpm"], back["rotor_rpm"]);
    assert!((back["airspeed_m_s"].as_f64().unwrap() - 18.16).abs() < 1e-3);
    let corrected = json(&[
        "--tip-speed-ratio",
        &mu.to_string(),
        "--rotor-rpm",
        &rpm.to_string(),
        "--corrections",
        "corrections/fitted/pca-2-tr515.yaml",
    ]);
    assert!(
        (corrected["rotor_alpha_deg"].as_f64().unwrap() - alpha).abs() > 0.01,
        "the fitted pitch offset moves the angle: {corrected}"
    );
    let (code, _, err) = cierva(&[
        "autorotate",
        "aircraft/pca-2-rotor.yaml",
        "--tip-speed-ratio",
        "0.3",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--tip-speed-ratio with --rotor-rpm"), "{err}");
}

/// At the edge of autorotation. TR 515 row 71's mu 0.591 at 100 rpm is just inside the model's
/// reach: it autorotates there at 1.039 deg, and holds its rotor speed (the driving torque falls
/// as the rotor speeds up). The search that scaled the airspeed at fixed angles found no angle
/// there (its equilibria fold, two rotor speeds at one angle), and the fixed-angle solver at
/// that angle and airspeed found no rotor speed; now both find 100 rpm. Past the reach the smallest angle
/// that autorotates is a slow rotor's equilibrium, which a tunnel does not hold: at mu 0.597 it
/// runs away; with 3 deg of pitch at mu 0.59 it lies at 19 deg, where the fixed-angle solver
/// (from a fast rotor, as a rotor spun up) finds a rotor five times as fast. Both are model
/// failures (exit 1) that say so, not refused inputs. All with seed 001's wake (the signed skew
/// form, momentum theory), where these numbers were found, set over the rotor file's physics:
/// its modulus form moves the edge (mu 0.591 autorotates at 1.004 deg, and mu 0.597 at 0.998).
#[test]
fn autorotate_at_the_edge_of_autorotation_finds_the_tunnels_equilibrium_or_says_why_not() {
    let run = |args: &[&str]| {
        let mut a = vec![
            "autorotate",
            "aircraft/pca-2-rotor.yaml",
            "--skew",
            "signed",
            "--descent",
            "momentum",
            "--format",
            "json",
        ];
        a.extend(args);
        cierva(&a)
    };
    let at_mu = |mu: &'static str, pitch_deg: &'static str| {
        run(&[
            "--tip-speed-ratio",
            mu,
            "--rotor-rpm",
            "100",
            "--collective-deg",
            pitch_deg,
        ])
    };
    let (code, out, err) = at_mu("0.591", "1.9");
    assert_eq!(code, 0, "{err}");
    let at: serde_json::Value = serde_json::from_str(&out).unwrap();
    let alpha = at["rotor_alpha_deg"].as_f64().unwrap();
    assert!((alpha - 1.039).abs() < 1e-3, "{at}");
    let stiffness = at["rotor_speed_stiffness"].as_f64().unwrap();
    assert!(stiffness < -1e-4, "{at}");
    // The fixed-angle solver at that angle and airspeed finds the same rotor speed. Its scan of
    // rotor speeds passed over this one (the autorotating range is 0.6 % of rotor speed wide
    // there, and the coarse torque's peak -1.2e-5): the peak is now looked at with the full
    // numerics, and its fast root bisected for, not the slow one beside it (99.7 rpm).
    let (code, out, err) = run(&[
        "--alpha-deg",
        &alpha.to_string(),
        "--airspeed-m-s",
        &at["airspeed_m_s"].as_f64().unwrap().to_string(),
        "--collective-deg",
        "1.9",
    ]);
    assert_eq!(code, 0, "{err}");
    let fixed: serde_json::Value = serde_json::from_str(&out).unwrap();
    let rpm = fixed["rotor_rpm"].as_f64().unwrap();
    assert!((rpm / 100.0 - 1.0).abs() < 1e-5, "{fixed}");

    let (code, _, err) = at_mu("0.597", "1.9");
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("unstable in rotor speed"), "{err}");

    let (code, _, err) = at_mu("0.59", "3.0");
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("a faster rotor is driven"), "{err}");
    let alpha_deg: f64 = err
        .split("autorotates (")
        .nth(1)
        .and_then(|r| r.split(" deg)").next())
        .and_then(|a| a.parse().ok())
        .unwrap_or_else(|| panic!("no angle in {err}"));
    assert!(alpha_deg > 10.0, "{err}");
    let radius_m = 6.858;
    let airspeed_m_s =
        0.59 * 100.0 * std::f64::consts::PI / 30.0 * radius_m / alpha_deg.to_radians().cos();
    let (code, out, err) = run(&[
        "--alpha-deg",
        &alpha_deg.to_string(),
        "--airspeed-m-s",
        &airspeed_m_s.to_string(),
        "--collective-deg",
        "3.0",
    ]);
    assert_eq!(code, 0, "{err}");
    let fixed: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(fixed["rotor_rpm"].as_f64().unwrap() > 300.0, "{fixed}");
}

/// One answer per rotor (issue 54): TR 487's vertical descent asked of the command with no
/// physics flag runs with the rotor file's settings and gives its case's 137.6 rpm (the flight's
/// 143.6); asked with momentum theory, which has no physical solution there, it says so in the
/// text and the JSON, and names the flag that set it over the file.
#[test]
fn the_command_gives_the_rotor_files_answer_and_warns_outside_momentum_theorys_validity() {
    let tr487 = [
        "autorotate",
        "aircraft/pca-2-rotor.yaml",
        "--alpha-deg",
        "90",
        "--airspeed-m-s",
        "10.790",
        "--density-kg-m3",
        "1.0823",
    ];
    let json = |extra: &[&str]| {
        let mut a = tr487.to_vec();
        a.extend(extra);
        a.extend(["--format", "json"]);
        let (code, out, err) = cierva(&a);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let own = json(&[]);
    let rpm = own["rotor_rpm"].as_f64().unwrap();
    assert!((rpm - 137.6).abs() < 0.05, "{own}");
    assert_eq!(own["physics"]["descent"], "johnson");
    assert_eq!(own["physics"]["skew"], "modulus");
    assert_eq!(own["warnings"], serde_json::json!([]));
    assert_eq!(own["overrides"], serde_json::json!([]));

    let momentum = json(&["--descent", "momentum"]);
    let rpm = momentum["rotor_rpm"].as_f64().unwrap();
    assert!((rpm - 81.9).abs() < 0.05, "{momentum}");
    let warning = momentum["warnings"][0].as_str().unwrap_or_default();
    assert!(
        warning.contains("momentum theory outside its validity") && warning.contains("3.10 v_h"),
        "{momentum}"
    );
    let said = momentum["overrides"][0].as_str().unwrap_or_default();
    assert!(
        said.contains("`descent: momentum` over the rotor file's johnson"),
        "{momentum}"
    );

    let mut a = tr487.to_vec();
    a.extend(["--descent", "momentum"]);
    let (code, text, err) = cierva(&a);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("WARNING: momentum theory outside its validity"),
        "{text}"
    );
    assert!(
        text.contains("note: the command line sets `descent: momentum`"),
        "{text}"
    );
    assert!(!text.contains("hint:"), "{text}");

    // A rotor file of the user's that states no physics runs with the defaults, and the text
    // says so and how to give them.
    let dir = crate::common::scratch("no-physics");
    std::fs::create_dir_all(&dir).unwrap();
    let src = std::fs::read_to_string(root().join("aircraft/pca-2-rotor.yaml")).unwrap();
    let (head, rest) = src.split_once("physics:\n").unwrap();
    let (_, sources) = rest.split_once("sources:\n").unwrap();
    let sources: String = sources
        .lines()
        .skip_while(|l| l.starts_with("  physics.") || l.starts_with("    "))
        .map(|l| format!("{l}\n"))
        .collect();
    let file = dir.join("pca-2-rotor.yaml");
    std::fs::write(&file, format!("{head}sources:\n{sources}")).unwrap();
    let path = file.display().to_string();
    let mut a = tr487.to_vec();
    a[1] = &path;
    let (code, text, err) = cierva(&a);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("physics              inflow peters_haquang, skew signed, descent momentum")
            && text.contains("states no `physics:`, so these are the defaults")
            && text.contains("WARNING: momentum theory outside its validity"),
        "{text}"
    );
}

/// A case that sets momentum theory over the rotor file's curve at TR 487's descent: its check
/// shows the values and does not pass on them (a finding, "outside validity"), and its note says
/// what the case set over the file.
#[test]
fn a_check_on_an_answer_outside_an_equations_validity_does_not_pass() {
    use cierva_harness::checks::result::Finding;
    let dir = crate::common::scratch("validity");
    std::fs::create_dir_all(&dir).unwrap();
    let src = std::fs::read_to_string(root().join("cases/naca-tr487-vertical-descent.yaml"))
        .unwrap()
        .replace(
            "    file: ../aircraft/pca-2-rotor.yaml\n",
            &format!(
                "    file: {}\n    descent: momentum\n",
                root().join("aircraft/pca-2-rotor.yaml").display()
            ),
        )
        .replace("id: naca-tr487-vertical-descent", "id: tr487-momentum");
    let path = dir.join("tr487-momentum.yaml");
    std::fs::write(&path, src).unwrap();
    let case = cierva_harness::suite::case::load(&path).unwrap();
    let r = &cierva_harness::suite::outcome::run_case(&case)[0];
    assert!(!r.passed, "{}", r.explain());
    assert!(
        matches!(&r.finding, Some(Finding::OutsideValidity { reason }) if reason.contains("unphysical root")),
        "{}",
        r.explain()
    );
    let omega = r
        .quantities
        .iter()
        .find(|q| q.quantity == "rotor_omega_rad_s");
    assert!(
        omega.is_some_and(|q| (q.value - 8.581).abs() < 1e-3),
        "{}",
        r.explain()
    );
    assert!(
        r.note.as_deref().is_some_and(
            |n| n.contains("the case sets `descent: momentum` over the rotor file's johnson")
        ),
        "{}",
        r.explain()
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Every command's default answer for a shipped rotor or aircraft is its case's at the case's
/// condition (issue 54): `autorotate` with no physics flag at the first condition of every case
/// of a rotor, and `trim` at the first condition of every case of an aircraft; and every aircraft's
/// main rotor runs with the physics its rotor file gives `autorotate`.
#[test]
fn every_commands_default_answer_for_a_shipped_rotor_or_aircraft_is_its_cases() {
    use cierva_harness::checks::subject::Subject;
    use cierva_harness::external::FlightModel;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-9);
    let mut compared = Vec::new();
    let mut cases: Vec<_> = std::fs::read_dir(root().join("cases"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .filter(|p| p.file_name().is_some_and(|n| n != "tolerances.yaml"))
        .collect();
    cases.sort();
    for path in cases {
        let case = cierva_harness::suite::case::load(&path).unwrap();
        match &case.subject {
            Subject::Rotor { file, solver, .. } => {
                let Some(t) = case.checks.iter().find_map(|k| k.behaviour().tunnel()) else {
                    continue;
                };
                let request = cierva_harness::external::TunnelRequest {
                    tunnel: *t,
                    parameters: Default::default(),
                };
                let want = cierva_harness::external::rotor::CiervaRotor::new(file, *solver)
                    .autorotation(&request)
                    .unwrap()
                    .quantities_or_reason()
                    .unwrap();
                let mut args = vec![
                    "autorotate".to_string(),
                    file.path.display().to_string(),
                    "--format".into(),
                    "json".into(),
                ];
                let mut flag = |name: &str, v: Option<f64>| {
                    if let Some(v) = v {
                        args.extend([format!("--{name}"), v.to_string()]);
                    }
                };
                flag("alpha-deg", t.alpha_deg);
                flag(
                    "airspeed-m-s",
                    t.alpha_deg.map(|_| {
                        cierva_harness::inputs::condition::tunnel_airspeed_m_s(
                            t,
                            file.rotor.radius_m,
                        )
                    }),
                );
                if t.alpha_deg.is_none() {
                    flag("tip-speed-ratio", t.tip_speed_ratio);
                    flag("rotor-rpm", t.rotor_rpm);
                }
                flag("collective-deg", t.collective_deg);
                flag("density-kg-m3", t.density_kg_m3);
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                let (code, out, err) = cierva(&args);
                assert_eq!(code, 0, "{}: {err}", case.id);
                let got: serde_json::Value = serde_json::from_str(&out).unwrap();
                for (name, value) in &want {
                    let g = got[name].as_f64().unwrap_or(f64::NAN);
                    assert!(
                        close(g, *value),
                        "{}: {name} {g} against the case's {value}",
                        case.id
                    );
                }
                compared.push(case.id.clone());
            }
            Subject::Aircraft { file, loading } => {
                let Some(c) = case.checks.iter().find_map(|k| k.condition()) else {
                    continue;
                };
                let model = cierva_harness::external::CiervaAircraft::new(file);
                let want = model
                    .trim(&cierva_harness::external::Request::at(c, *loading))
                    .unwrap();
                let rpm = want.iter().find(|(n, _)| *n == "rotor_rpm").unwrap().1;
                let mut args = vec![
                    "trim".to_string(),
                    file.path.display().to_string(),
                    "--airspeed-mph".into(),
                    c.airspeed_mph.to_string(),
                    "--density-altitude-ft".into(),
                    loading.density_altitude_ft.to_string(),
                    "--format".into(),
                    "json".into(),
                ];
                if let Some(m) = loading.mass_kg {
                    args.extend(["--mass-kg".into(), m.to_string()]);
                }
                let args: Vec<&str> = args.iter().map(String::as_str).collect();
                let (code, out, err) = cierva(&args);
                assert_eq!(code, 0, "{}: {err}", case.id);
                let got: serde_json::Value = serde_json::from_str(&out).unwrap();
                let g = got["rotor_rpm"].as_f64().unwrap_or(f64::NAN);
                assert!(
                    close(g, rpm),
                    "{}: rotor_rpm {g} against the case's {rpm}",
                    case.id
                );
                compared.push(case.id.clone());
            }
            _ => {}
        }
    }
    for id in [
        "naca-tr487-vertical-descent",
        "naca-tr515-table-iii",
        "cierva-table2-vpm-m16-70mph-max-weight",
        "montgomerie-parsons-trim",
    ] {
        assert!(
            compared.iter().any(|c| c == id),
            "{id} not compared: {compared:?}"
        );
    }
    for aircraft in ["vpm-m16", "montgomerie-parsons"] {
        let a = cierva_harness::inputs::aircraft::load(
            &root().join(format!("aircraft/{aircraft}.yaml")),
        )
        .unwrap();
        assert_eq!(
            a.aircraft.main_rotor.inflow,
            a.main_rotor_file.physics().model(),
            "{aircraft}'s main rotor runs with other physics than its rotor file gives `autorotate`"
        );
    }
}
