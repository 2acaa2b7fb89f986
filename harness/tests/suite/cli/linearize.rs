//! `cierva linearize`.

use super::*;

/// A fit's estimated physical parameters travel to the flight commands through
/// `--corrections`: the VPM M16 linearised with the Table 2 fit has N_r inside seed 001's
/// flight bound (-0.996 to -0.812), where the file's own estimates give about -0.80.
#[test]
fn linearize_applies_fitted_estimated_parameters() {
    let n_r = |extra: &[&str]| {
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
            .find_map(|l| l.strip_prefix("N_r "))
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no N_r in {out}"))
    };
    let own = n_r(&[]);
    let fitted = n_r(&[
        "--corrections",
        "corrections/fitted/vpm-m16-table2-reachable.yaml",
    ]);
    assert!(own > -0.812 && own < -0.78, "{own}");
    assert!((-0.996..=-0.812).contains(&fitted), "{fitted}");
}
