//! `cierva simulate`: doublets and control CSVs.

use super::*;
use std::path::Path;

#[test]
fn simulate_flies_a_doublet_and_reads_a_control_csv() {
    let dir = crate::common::scratch("sim");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("doublet.csv");
    let (code, _, err) = cierva(&[
        "simulate",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        "70",
        "--shape",
        "doublet",
        "--control",
        "eta_s",
        "--amplitude-percent",
        "2",
        "--start-s",
        "0.5",
        "--input-s",
        "0.5",
        "--duration-s",
        "2",
        "--every",
        "10",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(&out).unwrap();
    let header = csv.lines().next().unwrap();
    for col in [
        "time_s",
        "eta_s_percent",
        "q_rad_s",
        "rotor_omega_rad_s",
        "flap1_rad",
        "inflow_v0_m_s",
    ] {
        assert!(
            header.split(',').any(|c| c == col),
            "{col} missing: {header}"
        );
    }
    // Aft stick pitches the nose up: the pitch rate is positive during the first pulse.
    let cols: Vec<&str> = header.split(',').collect();
    let (it, iq) = (
        cols.iter().position(|c| *c == "time_s").unwrap(),
        cols.iter().position(|c| *c == "q_rad_s").unwrap(),
    );
    let q_at = |t: f64| {
        csv.lines()
            .skip(1)
            .map(|l| {
                l.split(',')
                    .map(|x| x.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .min_by(|a, b| (a[it] - t).abs().total_cmp(&(b[it] - t).abs()))
            .unwrap()[iq]
    };
    assert!(
        q_at(0.95) > q_at(0.4) + 1e-3,
        "{} vs {}",
        q_at(0.95),
        q_at(0.4)
    );
    // A control CSV with a bad time column is a located error.
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "time_s,eta_s_percent\n0,0\n1,1\n0.5,2\n").unwrap();
    let (code, _, err) = cierva(&[
        "simulate",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        "70",
        "--controls-csv",
        bad.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains(":4:") && err.contains("does not rise"),
        "{err}"
    );
    let good = dir.join("good.csv");
    std::fs::write(&good, "time_s,eta_c_percent\n0,0\n0.5,0\n0.6,1\n").unwrap();
    let (code, _, err) = cierva(&[
        "simulate",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        "60",
        "--controls-csv",
        good.to_str().unwrap(),
        "--duration-s",
        "1",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
}

/// A typo in an input CSV's header, and a bad number: the error names the file, line and
/// column, puts a caret under the field, and suggests the nearest column name.
#[test]
fn a_bad_control_csv_is_located_with_a_caret_and_a_suggestion() {
    let dir = crate::common::scratch("csv");
    std::fs::create_dir_all(&dir).unwrap();
    let typo = dir.join("typo.csv");
    std::fs::write(&typo, "time_s,eta_s_percnt\n0,0\n1,1\n").unwrap();
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "time_s, eta_s_percent\n0, 0\n1, abc\n").unwrap();
    let run = |p: &Path| {
        cierva(&[
            "simulate",
            "aircraft/vpm-m16.yaml",
            "--airspeed-mph",
            "70",
            "--controls-csv",
            p.to_str().unwrap(),
            "--output",
            dir.join("out.csv").to_str().unwrap(),
        ])
    };
    let (code, _, err) = run(&typo);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("typo.csv:1:8:"), "{err}");
    assert!(err.contains("did you mean `eta_s_percent`?"), "{err}");
    assert!(err.contains("\n  |        ^"), "{err}");
    let (code, _, err) = run(&bad);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("bad.csv:3:4:") && err.contains("`abc`"),
        "{err}"
    );
    assert!(err.contains("\n  |    ^"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A command-line value the run cannot take is blamed on its option, exit 2 (issue 50's
/// fuzzing: `--duration-s inf` exited 1 blaming `aircraft/vpm-m16.yaml: at 0.000 s`).
#[test]
fn a_bad_duration_is_blamed_on_its_option() {
    for (value, option) in [
        ("inf", "--duration-s"),
        ("-1", "--duration-s"),
        ("NaN", "--duration-s"),
        ("0", "--every"),
    ] {
        let mut args = vec![
            "simulate",
            "aircraft/vpm-m16.yaml",
            "--airspeed-mph",
            "70",
            "--shape",
            "step",
            "--control",
            "eta_s",
            "--output",
            "/dev/null",
        ];
        let given = format!("{option}={value}");
        args.push(&given);
        if option != "--duration-s" {
            args.extend(["--duration-s", "1"]);
        }
        let (code, _, err) = cierva(&args);
        assert_eq!(code, 2, "{option} {value}: {err}");
        assert!(err.contains(&format!("{option} {value}")), "{err}");
        assert!(
            !err.contains("vpm-m16.yaml"),
            "blamed on the aircraft: {err}"
        );
    }
}
