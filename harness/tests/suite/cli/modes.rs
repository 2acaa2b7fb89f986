//! `cierva modes`: modes, BCAR and Milne tables, derivative sweeps.

use super::*;

#[test]
fn modes_prints_modes_bcar_and_milne() {
    let (code, out, err) = cierva(&["modes", "flight-refs/seed002-vpm-m16-60kn.yaml"]);
    assert_eq!(code, 0, "{err}");
    for s in [
        "short_period",
        "phugoid",
        "rotorspeed",
        "complies",
        "Eq. 13",
        "lambda_Omega",
    ] {
        assert!(out.contains(s), "missing {s}:\n{out}");
    }
    let (code, out, _) = cierva(&[
        "modes",
        "flight-refs/seed002-puma-autorotation-70kn.yaml",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["modes"].as_array().unwrap().len(), 3);
    assert_eq!(v["modes"][0]["bcar"]["verdict"], "complies");
    let (code, _, err) = cierva(&["modes", "flight-refs/seed001-table2-vpm-m16-70mph.yaml"]);
    assert_eq!(code, 2);
    assert!(err.contains("no `linear_model`"), "{err}");
}

#[test]
fn modes_sweeps_a_derivative() {
    let (code, out, err) = cierva(&[
        "modes",
        "flight-refs/seed002-vpm-m16-60kn.yaml",
        "--sweep",
        "Q_u=0.06:0.26:5",
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        out.lines().filter(|l| l.starts_with("Q_u =")).count(),
        5,
        "{out}"
    );
    let (code, _, err) = cierva(&[
        "modes",
        "flight-refs/seed002-vpm-m16-60kn.yaml",
        "--sweep",
        "Q_x=0:1:3",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown state or control `x`"), "{err}");
    let (code, _, err) = cierva(&[
        "modes",
        "flight-refs/seed002-vpm-m16-60kn.yaml",
        "--sweep",
        "Q_u=0:1",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("DERIVATIVE=FROM:TO:POINTS"), "{err}");
}
