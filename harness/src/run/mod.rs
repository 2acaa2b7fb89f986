//! Running the model for the harness: trims, linearisations, autorotations and simulations at
//! the conditions and loadings cases give, with the errors that say whose fault a failure is;
//! and running work on every core.

pub mod autorotation;
pub mod linearise;
pub mod memo;
pub mod parallel;
pub mod replay;
pub mod responses;
pub mod simulate;
pub mod trim;
