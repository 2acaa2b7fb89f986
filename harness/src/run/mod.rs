//! Running the model for the harness: trims, linearisations, autorotations and simulations at
//! the conditions and loadings cases give, with the errors that say whose fault a failure is;
//! and running work on every core.

pub mod autorotation;
pub mod linearise;
pub mod parallel;
pub mod replay;
pub mod simulate;
pub mod trim;

pub use autorotation::{AutorotateError, run_autorotation, run_autorotation_at_tip_speed_ratio};
pub use linearise::{
    LinearRunError, forget_linearisations, identified_in_band_cached, linear_units,
    linearise_cached, linearise_cached_from, run_linearise, run_linearise_from,
    run_linearise_with_flapping,
};
pub use parallel::parallel_map;
pub use simulate::{SimulationRunError, SimulationStart, run_simulation, simulation_start};
pub use trim::{TrimRunError, run_trim, run_trim_from};
