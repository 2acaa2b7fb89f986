//! `cierva synth-history`: records a time-history check reads.

use super::*;

/// `synth-history` writes a record that says it is synthetic, and a `time_history` check that
/// flies it with the model that made it finds nothing but the noise it was given.
#[test]
fn synth_history_writes_a_record_a_time_history_check_reads() {
    let dir = crate::common::scratch("synth-history");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("lin-doublet.csv");
    let (code, _, err) = cierva(&[
        "synth-history",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        "60",
        "--shape",
        "doublet",
        "--amplitude-percent",
        "2",
        "--duration-s",
        "6",
        "--simulation",
        "linear",
        "--noise-rate-deg-s",
        "0.2",
        "--seed",
        "3",
        "--output",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let side = std::fs::read_to_string(dir.join("lin-doublet.yaml")).unwrap();
    assert!(
        side.contains("synthetic:") && side.contains("seed: 3") && side.contains("linearisation"),
        "{side}"
    );
    let case = dir.join("c.yaml");
    std::fs::write(
        &case,
        format!(
            "id: c\ntitle: t\nclass: verification\nprovenance: {{source: \"test\"}}\nmodel:\n  aircraft: {{file: {}}}\n\
             tolerances:\n  noise: {{interval: [0.15, 0.25], reason: \"the record's rate noise sd is 0.2 deg/s\"}}\n\
             checks:\n  - id: q\n    kind: time_history\n    simulation: linear\n    condition: {{airspeed_mph: 60.0}}\n\
             \x20   reference: lin-doublet.csv\n    expect:\n      q_deg_s.rms_error: {{tolerance: noise}}\n",
            root().join("aircraft/vpm-m16.yaml").display()
        ),
    )
    .unwrap();
    let (code, out, err) = cierva(&["validate", case.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(out.contains("1 passed"), "{out}");
}
