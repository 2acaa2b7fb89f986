//! Published linear models used by the unit tests (the case files carry the same numbers in
//! `flight-refs/`; model/ does no I/O, so the tests keep their own copy).

use crate::linear::LinearModel;

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

/// Seed 002 Eq. 20: RASCAL's VPM M16, 425 kg, level flight at 60 kn, 2000 ft density altitude,
/// states `[w q u theta Omega]`, control `eta_s`, as printed (4 decimals).
pub fn vpm_eq20() -> LinearModel {
    LinearModel::from_rows(
        names(&["w", "q", "u", "theta", "Omega"]),
        names(&["eta_s"]),
        &[
            vec![-1.2019, 28.6824, -0.2336, 0.1218, -0.3143],
            vec![-0.0239, -1.001, -0.0010, 0.0, -0.0016],
            vec![-0.2388, 0.6993, -0.2579, -9.2219, -0.0518],
            vec![0.0, 1.0, 0.0, 0.0, 0.0],
            vec![0.6692, -1.5088, 0.1557, 0.0, -0.1052],
        ],
        &[
            vec![-29.7685],
            vec![12.4604],
            vec![-15.0729],
            vec![0.0],
            vec![-19.1078],
        ],
    )
    .expect("seed 002 Eq. 20 is a valid model")
}

/// Seed 002 Eq. 26: RASCAL's Puma, 5500 kg, 1900 ft/min autorotative descent at 70 kn IAS,
/// 4000 ft density altitude, states `[w q u theta Omega]`, control `theta_0`, as printed.
pub fn puma_eq26() -> LinearModel {
    LinearModel::from_rows(
        names(&["w", "q", "u", "theta", "Omega"]),
        names(&["theta_0"]),
        &[
            vec![-0.6562, 36.2593, -0.0183, 0.0, -0.3864],
            vec![-0.0084, -0.7597, 0.0049, 0.0, -0.0062],
            vec![-0.0151, -9.6090, -0.0129, -9.2081, 0.0379],
            vec![0.0, 1.0, 0.0, 0.0, 0.0],
            vec![0.1056, -0.0604, 0.0034, 0.0, -0.0677],
        ],
        &[
            vec![-94.1647],
            vec![5.7640],
            vec![-4.2271],
            vec![0.0],
            vec![-0.2007],
        ],
    )
    .expect("seed 002 Eq. 26 is a valid model")
}
