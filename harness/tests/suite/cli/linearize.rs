//! `cierva linearize`.

use super::*;

/// A fit's estimated physical parameters travel to the flight commands through
/// `--corrections`: the VPM M16 linearised with the Table 2 fit has L_p inside seed 001's
/// flight bound (-2.727 to -2.377), where the file's own estimates give about -1.94.
#[test]
fn linearize_applies_fitted_estimated_parameters() {
    let l_p = |extra: &[&str]| {
        let mut args = vec![
            "linearize",
            "aircraft/vpm-m16.yaml",
            "--airspeed-mph",
            "70",
            "--mass-kg",
            "450",
            "--density-altitude-ft",
            "2000",
            "--quiet",
        ];
        args.extend(extra);
        let (code, out, err) = cierva(&args);
        assert_eq!(code, 0, "{err}");
        out.lines()
            .find_map(|l| l.strip_prefix("L_p "))
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no L_p in {out}"))
    };
    let own = l_p(&[]);
    let fitted = l_p(&[
        "--corrections",
        "corrections/fitted/vpm-m16-table2-reachable.yaml",
    ]);
    assert!(own > -2.0 && own < -1.9, "{own}");
    assert!((-2.727..=-2.377).contains(&fitted), "{fitted}");
}
