//! `cierva validate`: exit codes, counts, JSON, corrections and the report.

use super::*;

#[test]
fn shipped_cases_pass_with_their_expected_failures() {
    let mut args = vec!["validate"];
    args.extend(QUICK_CASES);
    let (code, out, err) = cierva(&args);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(
        out.contains("0 failed") && out.contains("0 unexpected passes"),
        "{out}"
    );
    assert!(
        out.contains("seed002-vpm-m16-60kn") && out.contains("xfail"),
        "{out}"
    );
}

#[test]
fn json_output_parses_and_counts() {
    let mut args = vec!["validate", "--format", "json"];
    args.extend(QUICK_CASES);
    let (code, out, _) = cierva(&args);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).expect("valid JSON");
    assert!(v["counts"]["pass"].as_u64().unwrap() > 0);
    assert!(
        v["counts"]["expected_failure"].as_u64().unwrap() > 0,
        "{out}"
    );
    assert_eq!(v["counts"]["fail"], 0);
    let results = v["results"].as_array().unwrap();
    assert!(results.iter().all(|r| r["case"].is_string()));
    for case in ["seed002-vpm-m16-60kn", "seed002-puma-autorotation-70kn"] {
        assert!(results.iter().any(|r| r["case"] == case), "{case}");
    }
}

#[test]
fn an_unexpected_pass_fails_the_run_loudly() {
    let (code, out, _) = cierva(&["validate", "harness/tests/fixtures/unexpected-pass.yaml"]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("XPASS") && out.contains("but it passes"),
        "{out}"
    );
}

#[test]
fn an_unexpected_failure_exits_1() {
    let (code, out, _) = cierva(&["validate", "harness/tests/fixtures/unexpected-fail.yaml"]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("FAIL") && out.contains("out of tolerance"),
        "{out}"
    );
}

#[test]
fn bad_input_exits_2_with_a_located_message() {
    let (code, out, _) = cierva(&["validate", "harness/tests/bad-input/typo-field.yaml"]);
    assert_eq!(code, 2);
    assert!(
        out.contains("typo-field.yaml:25:") && out.contains("unknown field `tolerence`"),
        "{out}"
    );
    let (code, _, err) = cierva(&["validate", "no/such/dir"]);
    assert_eq!(code, 2);
    assert!(err.contains("no/such/dir"), "{err}");
    let (code, _, err) = cierva(&["validate", "reports/snapshots"]);
    assert_eq!(code, 2);
    assert!(err.contains("no case files"), "{err}");
}

/// `validate --corrections` runs the cases of the corrected aircraft with the fitted
/// corrections: seed 000's synthetic X_u and Z_w checks, all expected failures of the
/// uncorrected model, become unexpected passes (exit 1, and said so), all but the 40 mph pair
/// the fit no longer reaches (fit.rs); a corrections file for another aircraft changes nothing;
/// a bad one is bad input.
#[test]
fn validate_with_fitted_corrections_reports_the_checks_that_now_pass() {
    let case = "cases/seed000-synthetic-xu-zw-vpm-m16.yaml";
    let (code, out, err) = cierva(&["validate", case]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(out.contains("8 expected failures"), "{out}");
    let (code, out, err) = cierva(&[
        "validate",
        case,
        "--corrections",
        "corrections/fitted/vpm-m16-seed000.yaml",
    ]);
    assert_eq!(code, 1, "{out}\n{err}");
    assert!(out.contains("7 unexpected passes"), "{out}");
    assert!(
        out.contains(
            "cases run with corrections: seed000-synthetic-xu-zw-vpm-m16 (vpm-m16-seed000)"
        ),
        "{out}"
    );
    let (code, out, err) = cierva(&[
        "validate",
        case,
        "--corrections",
        "corrections/fitted/pca-2-tr515.yaml",
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(out.contains("no case's aircraft or rotor matches"), "{out}");
    let (code, _, err) = cierva(&["validate", case, "--corrections", case]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(case), "{err}");
}

/// `validate` writes a self-contained HTML report with a section per case and plots that have
/// data, and a Markdown summary with the counts; the JSON output names the files.
#[test]
fn validate_writes_a_report_with_plots_and_a_summary() {
    let dir = crate::common::scratch("report");
    let _ = std::fs::remove_dir_all(&dir);
    let d = dir.to_str().unwrap();
    let (code, out, err) = cierva(&[
        "validate",
        "cases/vpm-m16-stability-max-weight.yaml",
        "cases/vpm-m16-stability-min-weight.yaml",
        "cases/synthetic-time-history-vpm-m16-70mph.yaml",
        "cases/seed002-vpm-m16-60kn.yaml",
        "cases/seed003-synthetic-vpm-m16-teeter.yaml",
        "cases/seed003-synthetic-vpm-m16-teeter-20-m-s.yaml",
        "--report-dir",
        d,
        "--format",
        "json",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("valid JSON");
    assert_eq!(v["report"].as_array().map(Vec::len), Some(2), "{out}");
    let html = std::fs::read_to_string(dir.join("index.html")).expect("index.html");
    for id in [
        "seed002-vpm-m16-60kn",
        "vpm-m16-stability-max-weight",
        "vpm-m16-stability-min-weight",
        "synthetic-time-history-vpm-m16-70mph",
    ] {
        assert!(
            html.contains(&format!("id=\"case-{id}\"")),
            "no section for {id}"
        );
    }
    // The acceptance log's last entry, newest first, beside the scoreboard.
    let log =
        cierva_harness::suite::review::load_log(&crate::common::suite().acceptances()).unwrap();
    let last = log.acceptances.last().expect("the log has entries");
    let section = html
        .split("<h2 id=\"acceptances\">")
        .nth(1)
        .expect("an acceptances section");
    assert!(
        section.contains(&format!(
            "<tr><td>{}</td><td><code>{}</code></td>",
            last.date, last.commit
        )),
        "{}",
        &section[..600.min(section.len())]
    );
    // Self-contained: nothing fetched from elsewhere.
    assert!(!html.contains("<link ") && !html.contains(" src="));
    // Every figure has points and an SVG with marks; nothing drawn from a NaN.
    let figures: Vec<&str> = html.split("<figure class=\"plot\"").skip(1).collect();
    assert!(figures.len() >= 20, "{} figures", figures.len());
    for f in &figures {
        let svg = &f[..f.find("</figure>").unwrap()];
        let points: usize = svg
            .split("data-points=\"")
            .nth(1)
            .and_then(|s| s.split('"').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or(0);
        assert!(
            points > 0 && svg.contains("<svg"),
            "{}",
            &svg[..200.min(svg.len())]
        );
        assert!(
            !svg.contains("NaN"),
            "a NaN in {}",
            &svg[..200.min(svg.len())]
        );
    }
    // The plots engineers expect: derivatives against airspeed at both weights, the complex
    // plane, the BCAR chart, time histories with tolerance bands.
    for title in [
        "vpm-m16: Q_u against airspeed",
        "vpm-m16-stability-max-weight: eigenvalues",
        "BCAR Section T boundary",
        "largest error allowed",
        "seed002-vpm-m16-60kn: root locus in M_Omega",
        "vpm-m16-rotor: inflow_v0_m_s from teeter flapping against airspeed",
    ] {
        assert!(html.contains(title), "no `{title}` in the report");
    }
    assert!(html.contains("model, 410 kg") && html.contains("model, 450 kg"));
    let md = std::fs::read_to_string(dir.join("summary.md")).expect("summary.md");
    assert!(md.contains("6 cases") && md.contains("0 failed"), "{md}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--junit` (issue 50): one testcase per check, the class as the suite, an unexpected pass as
/// a failure with its numbers and an expected failure as skipped, read by Python's XML parser
/// (ElementTree, as CI tools read it); `-k` and `--class` pick checks.
#[test]
fn junit_xml_has_one_testcase_per_check_and_selection_picks_checks() {
    crate::external::require_python3();
    let dir = crate::common::scratch("junit");
    let xml = dir.join("out/junit.xml");
    let fixture = root().join("harness/tests/fixtures/unexpected-pass.yaml");
    let mut args = vec!["validate", "--format", "json", "--junit"];
    let xml_arg = xml.display().to_string();
    let fixture_arg = fixture.display().to_string();
    args.extend([xml_arg.as_str(), fixture_arg.as_str()]);
    args.extend(QUICK_CASES);
    let (code, out, err) = cierva(&args);
    assert_eq!(code, 1, "the unexpected pass fails the run: {err}");
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    let checks = json["results"].as_array().unwrap().len();
    let script = format!(
        "import xml.etree.ElementTree as ET\n\
         root = ET.parse({xml:?}).getroot()\n\
         cases = root.findall('./testsuite/testcase')\n\
         print(len(cases), root.get('tests'), root.get('failures'), root.get('skipped'))\n\
         print(' '.join(sorted(s.get('name') for s in root.findall('./testsuite'))))\n\
         bad = root.find(\"./testsuite/testcase[@classname='unexpected-pass']/failure\")\n\
         print(bad.get('message'))\n\
         print(bad.text)\n",
        xml = xml_arg
    );
    let py = std::process::Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    let parsed = String::from_utf8_lossy(&py.stdout).into_owned();
    assert!(
        py.status.success(),
        "{parsed}{}",
        String::from_utf8_lossy(&py.stderr)
    );
    let mut lines = parsed.lines();
    let counts: Vec<&str> = lines.next().unwrap().split(' ').collect();
    let expected_failures = json["counts"]["expected_failure"].as_u64().unwrap();
    assert_eq!(
        counts,
        [
            checks.to_string(),
            checks.to_string(),
            "1".to_string(),
            expected_failures.to_string()
        ],
        "{parsed}"
    );
    assert_eq!(lines.next().unwrap(), "verification", "{parsed}");
    assert_eq!(lines.next().unwrap(), "unexpected pass", "{parsed}");
    // The failure says what the check computed and what was expected.
    let text: String = lines.collect::<Vec<_>>().join("\n");
    assert!(text.contains("expected 1.933000e-1"), "{text}");
    // Selection: the verification checks of one case, by text and class.
    let (code, out, err) = cierva(&[
        "validate",
        "--format",
        "json",
        "-k",
        "seed002-vpm-m16-60kn::",
        "--class",
        "verification",
        QUICK_CASES[0],
        QUICK_CASES[1],
    ]);
    assert_eq!(code, 0, "{err}");
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    let results = json["results"].as_array().unwrap();
    assert!(!results.is_empty());
    assert!(
        results
            .iter()
            .all(|r| r["case"] == "seed002-vpm-m16-60kn" && r["class"] == "verification"),
        "{out}"
    );
    // Both quick cases are verification: a class they do not hold picks nothing, and says so.
    let (code, _, err) = cierva(&["validate", "--class", "validation", QUICK_CASES[0]]);
    assert_eq!(code, 2);
    assert!(
        err.contains("no check matches --class validation among"),
        "{err}"
    );
    let (code, _, err) = cierva(&["validate", "--class", "crosscode", QUICK_CASES[0]]);
    assert_eq!(code, 2);
    assert!(err.contains("did you mean `cross_code`?"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
