//! `cierva synth` then `cierva identify`: a synthetic record identified back.

use super::*;

#[test]
fn synth_then_identify_round_trips() {
    let dir = crate::common::scratch("cli");
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("sweep.csv");
    let (code, out, err) = cierva(&[
        "synth",
        "flight-refs/seed002-vpm-m16-60kn.yaml",
        "--control",
        "eta_s",
        "--amplitude-model-units",
        "0.01",
        "--seed",
        "3",
        "--output",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}{err}");
    let side = std::fs::read_to_string(dir.join("sweep.yaml")).unwrap();
    assert!(
        side.contains("synthetic:") && side.contains("seed: 3"),
        "{side}"
    );
    let (code, out, err) = cierva(&["identify", csv.to_str().unwrap(), "--format", "yaml"]);
    assert_eq!(code, 0, "{err}");
    // The output is a flight-refs derivative table that loads.
    let refs_path = dir.join("sweep-derivatives.yaml");
    std::fs::write(&refs_path, &out).unwrap();
    let r = cierva_harness::inputs::reference::load(&refs_path).unwrap();
    match r.table.entry("M_q", "estimate") {
        Some(cierva_harness::inputs::reference::Entry::Value(v)) => {
            assert!((v - -1.001).abs() < 1e-3, "{v}")
        }
        other => panic!("{other:?}"),
    }
    let (code, _, err) = cierva(&["identify", "no-such.csv"]);
    assert_eq!(code, 2);
    assert!(err.contains("no-such.yaml"), "{err}");
}
