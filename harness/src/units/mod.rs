//! Unit conversions the harness shares: people fly in mph, knots and feet, the model works in SI.

/// Miles per hour in a knot (1852 m / 1609.344 m).
pub const MPH_PER_KN: f64 = 1852.0 / 1609.344;
/// Miles per hour to metres per second (exact: 1 mile = 1609.344 m).
pub const MPH_TO_M_S: f64 = 0.44704;
/// Feet to metres (exact), the model's own constant.
pub use cierva_model::components::atmosphere::FT_TO_M;
