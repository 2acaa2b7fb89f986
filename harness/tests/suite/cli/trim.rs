//! `cierva trim`.

use super::*;

#[test]
fn trim_flies_the_vpm_m16_and_refuses_what_cannot_be_flown() {
    let (code, out, err) = cierva(&[
        "trim",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        "70",
        "--mass-kg",
        "410",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["residual_norm"].as_f64().unwrap() <= 1e-7);
    let rpm = v["rotor_rpm"].as_f64().unwrap();
    assert!((300.0..500.0).contains(&rpm), "{rpm}");
    assert!(v["controls"]["stick_longitudinal_percent"].is_f64());
    assert_eq!(v["residuals"].as_array().unwrap().len(), 11);
    let (code, out, err) = cierva(&["trim", "aircraft/vpm-m16.yaml", "--airspeed-mph", "60"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("stick long/lat") && out.contains("converged"),
        "{out}"
    );
    // Impossible conditions: no airspeed; a climb beyond the engine's power.
    let (code, _, err) = cierva(&["trim", "aircraft/vpm-m16.yaml", "--airspeed-mph", "0"]);
    assert_eq!(code, 2);
    assert!(err.contains("airspeed_m_s must be positive"), "{err}");
    let (code, _, err) = cierva(&[
        "trim",
        "aircraft/vpm-m16.yaml",
        "--airspeed-mph",
        "60",
        "--climb-m-s",
        "12",
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("throttle") || err.contains("did not converge"),
        "{err}"
    );
    // A rotor file is not an aircraft file.
    let (code, _, err) = cierva(&[
        "trim",
        "aircraft/vpm-m16-rotor.yaml",
        "--airspeed-mph",
        "60",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown field"), "{err}");
}
