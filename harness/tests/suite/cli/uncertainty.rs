//! `cierva uncertainty`: verdicts and bad sampling input.

use super::*;

/// `cierva uncertainty` of seed 001 Table 2's maximum weight at 8 samples, with `extra`
/// arguments: its JSON (and the text, for messages).
fn table2_uncertainty(extra: &[&str]) -> (serde_json::Value, String) {
    let mut args = vec![
        "uncertainty",
        "cases/cierva-table2-vpm-m16-70mph-max-weight.yaml",
        "--samples",
        "8",
        "--format",
        "json",
        "--quiet",
    ];
    args.extend(extra);
    let (code, out, err) = cierva(&args);
    assert_eq!(code, 0, "{err}");
    (serde_json::from_str(&out).unwrap(), out)
}

/// `cierva uncertainty --format json`: the keys on every result, a verdict on every
/// validation quantity of seed 001 Table 2, and N_v's (every sampled input combination above
/// flight's bound) a model-form error.
#[test]
fn uncertainty_json_gives_each_validation_quantity_its_verdict() {
    let (v, out) = table2_uncertainty(&[]);
    let results = v["results"].as_array().unwrap();
    let validation: Vec<&serde_json::Value> = results
        .iter()
        .filter(|r| r["class"] == "validation")
        .collect();
    assert_eq!(validation.len(), 6, "{out}");
    for r in &validation {
        for key in [
            "case",
            "check",
            "quantity",
            "nominal",
            "estimate_error",
            "u_input",
            "u_num",
            "u_data",
            "u_val",
            "verdict",
            "fragile",
            "contributors",
        ] {
            assert!(r.get(key).is_some(), "{key} missing in {r}");
        }
        assert!(
            ["agrees", "model_form_error", "inconclusive"]
                .contains(&r["verdict"].as_str().unwrap()),
            "{r}"
        );
        assert!(r["u_input"].as_f64().unwrap() > 0.0, "{r}");
        let c = r["contributors"].as_array().unwrap();
        assert_eq!(c.len(), 16, "{r}");
        assert!(c[0]["input"].is_string() && c[0]["total"].is_f64(), "{r}");
        // Sampled: every index has its standard error.
        for key in ["first_se", "total_se"] {
            assert!(
                c.iter()
                    .all(|c| c[key].as_f64().is_some_and(|se| se >= 0.0)),
                "{key} in {r}"
            );
        }
    }
    let n_v = validation.iter().find(|r| r["check"] == "N_v").unwrap();
    assert_eq!(n_v["verdict"], "model_form_error", "{n_v}");
    // 8 base points of the Saltelli design over the VPM M16's 16 ranged inputs, and the
    // nominal and refined evaluations.
    assert_eq!(v["cases"][0]["evaluations"], 8 * 18 + 2, "{}", v["cases"]);
}

/// Bad sampling input is refused with exit code 2: too few samples, a seed that is not a whole
/// number, and --samples without --uncertainty.
#[test]
fn uncertainty_refuses_bad_sampling_input() {
    let case = "cases/cierva-table2-vpm-m16-70mph-max-weight.yaml";
    let (code, _, err) = cierva(&["uncertainty", case, "--samples", "7"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("at least 8"), "{err}");
    let (code, _, err) = cierva(&["uncertainty", case, "--seed", "1.5"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--seed"), "{err}");
    let (code, _, err) = cierva(&["validate", case, "--uncertainty", "--samples", "4"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("at least 8"), "{err}");
    let (code, _, err) = cierva(&["validate", case, "--samples", "64"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--uncertainty"), "{err}");
}

/// `--validation-only` samples the validation checks alone: Table 2's BCAR regression check is
/// left out, and a verdict-only check shows as `passes`.
#[test]
fn uncertainty_validation_only_leaves_other_classes_out() {
    let (v, out) = table2_uncertainty(&["--validation-only"]);
    let results = v["results"].as_array().unwrap();
    assert_eq!(results.len(), 6, "{out}");
    assert!(results.iter().all(|r| r["class"] == "validation"), "{out}");
    assert!(
        results.iter().all(|r| r["check"] != "dutch-roll-bcar"),
        "{out}"
    );
}
