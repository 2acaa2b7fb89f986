//! `cierva inflow` and `cierva synth-teeter`: teeter records.

use super::*;

#[test]
fn inflow_reads_a_teeter_record() {
    let (code, out, err) = cierva(&[
        "inflow",
        "flight-refs/synthetic-vpm-m16-rotor-teeter.csv",
        "--rotor",
        "aircraft/vpm-m16-rotor.yaml",
        "--skew",
        "signed",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["revolutions"].as_f64().unwrap() > 60.0);
    assert!(v["v0_m_s"].as_f64().unwrap() > 0.0);
    // A flight record for identification is not a teeter record.
    let (code, _, err) = cierva(&[
        "inflow",
        "cases/naca-tr515-table-iii.yaml",
        "--rotor",
        "aircraft/vpm-m16-rotor.yaml",
    ]);
    assert_eq!(code, 2, "{err}");
}

/// The synthetic teeter records regenerate bit for bit from committed code with the command
/// scripts/regenerate-references gives (the record and its sidecar, byte for byte): seed 001's
/// wake set over the rotor file's physics, which the command says.
#[test]
fn a_synthetic_teeter_record_regenerates_bit_for_bit() {
    let dir = crate::common::scratch("teeter-regen");
    std::fs::create_dir_all(dir.join("flight-refs")).unwrap();
    let link = dir.join("aircraft");
    if !link.exists() {
        std::os::unix::fs::symlink(root().join("aircraft"), &link).unwrap();
    }
    let name = "flight-refs/synthetic-vpm-m16-rotor-teeter-15-m-s";
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_cierva"))
        .current_dir(&dir)
        .args([
            "synth-teeter",
            "aircraft/vpm-m16-rotor.yaml",
            "--alpha-deg",
            "25.8",
            "--airspeed-m-s",
            "15",
            "--seed",
            "12",
            "--noise-deg",
            "0.05",
            "--duration-s",
            "10",
            "--sample-rate-hz",
            "100",
            "--skew",
            "signed",
            "--descent",
            "momentum",
            "--output",
            &format!("{name}.csv"),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("the command line sets `skew: signed` over the rotor file's modulus"),
        "{said}"
    );
    for ext in ["csv", "yaml"] {
        let fresh = std::fs::read(dir.join(format!("{name}.{ext}"))).unwrap();
        let committed = std::fs::read(root().join(format!("{name}.{ext}"))).unwrap();
        assert!(
            fresh == committed,
            "{name}.{ext} does not regenerate bit for bit: run scripts/regenerate-references \
             and commit what it rewrites"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
