//! `cierva sensitivity`.

use super::*;

#[test]
fn sensitivity_studies_a_case_and_refuses_unknown_parameters() {
    let case = root().join("cases/cierva-table2-vpm-m16-70mph-min-weight.yaml");
    let case = case.to_str().unwrap();
    let (code, out, err) = cierva(&[
        "sensitivity",
        "--case",
        case,
        "--parameters",
        "mass.ixx_kg_m2,airframe.fin.area_m2",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let rows = v["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 6, "the case's six derivatives");
    assert_eq!(v["parameters"][0]["range"]["lower"], 200.0);
    // L_eta_c is just outside; a roll inertia inside its plausible range brings it in.
    let l_eta_c = rows.iter().find(|r| r["quantity"] == "L_eta_c").unwrap();
    assert_eq!(l_eta_c["inside"], false);
    assert_eq!(l_eta_c["effects"][0]["plausible"], true);

    let (code, _, err) = cierva(&["sensitivity", "--case", case, "--parameters", "fin_area"]);
    assert_eq!(code, 2);
    assert!(err.contains("`fin_area` is not a parameter"), "{err}");
    let (code, out, err) = cierva(&[
        "sensitivity",
        root().join("aircraft/vpm-m16.yaml").to_str().unwrap(),
        "--airspeed-mph",
        "70",
        "--quantities",
        "N_v",
        "--parameters",
        "airframe.fin.area_m2",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("N_v = ") && out.contains("airframe.fin.area_m2"),
        "{out}"
    );
}

/// What a user meets first: a case given where the aircraft file goes is named as a case, with
/// the option to give it by; a case without a derivative or trim check says which kinds it has
/// and which the study reads.
#[test]
fn sensitivity_names_a_case_given_as_an_aircraft_and_the_kinds_it_cannot_study() {
    let case = root().join("cases/vpm-m16-trim-max-weight.yaml");
    let case = case.to_str().unwrap();
    let (code, _, err) = cierva(&["sensitivity", case]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("is a case, not an aircraft file: give it with --case"),
        "{err}"
    );
    let (code, _, err) = cierva(&["sensitivity", "--case", case]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("has no derivative or trim check (its checks are of kind trim_sweep)")
            && err.contains("reads the `derivative` and `trim` checks"),
        "{err}"
    );
}
