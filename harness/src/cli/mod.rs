//! The `cierva` commands, one module each (those not yet moved out of `main.rs` live there).

pub mod review;
