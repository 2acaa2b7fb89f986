//! Unit conversions the harness shares (people fly in mph, knots and feet, the model works in SI),
//! and the one number format of its tables and snapshots ([`sig`]).

/// Miles per hour in a knot (1852 m / 1609.344 m).
pub const MPH_PER_KN: f64 = 1852.0 / 1609.344;
/// Miles per hour to metres per second (exact: 1 mile = 1609.344 m).
pub const MPH_TO_M_S: f64 = 0.44704;
/// Feet to metres (exact), the model's own constant.
pub use cierva_model::components::atmosphere::FT_TO_M;

/// Significant digits in snapshots and tables.
pub const SIG: usize = 6;

/// `x` to `digits` significant digits: plain decimals for 1e-4 <= |x| < 1e6, scientific
/// otherwise; zero (of either sign) as `0`.
pub fn sig(x: f64, digits: usize) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return format!("{x}");
    }
    let digits = digits.max(1);
    let mag = x.abs().log10().floor() as i32;
    if (-4..6).contains(&mag) {
        let decimals = (digits as i32 - 1 - mag).max(0) as usize;
        let s = format!("{x:.decimals$}");
        // Rounding can carry into a new digit (9.99999 -> 10.0000); that is still fine.
        if s.trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
        {
            "0".into()
        } else {
            s
        }
    } else {
        format!("{x:.*e}", digits - 1)
    }
}

/// `n` things in words, with the singular for one: `1 case`, `17 checks`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}
