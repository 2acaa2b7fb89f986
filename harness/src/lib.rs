//! # cierva harness
//!
//! Everything between the model and the people who use it: case files and reference files
//! (`case`, `refs`, `yaml`), running checks (`eval`), and text output (`text`). The `cierva`
//! binary and the generated test suite (`tests/cases.rs`) are thin layers over this library.
//!
//! The model (`cierva-model`) does no I/O; everything that reads files lives here.

pub mod aircraft_file;
pub mod case;
pub mod checks;
pub mod controls_file;
pub mod corrections;
pub mod discrepancy;
pub mod estimate;
pub mod eval;
pub mod external;
pub mod fit;
pub mod fit_file;
pub mod flight_test;
pub mod history;
pub mod ident;
pub mod inputs;
pub mod parameters;
pub mod quantity;
pub mod refs;
pub mod report;
pub mod retune;
pub mod review;
pub mod rotor_file;
pub mod run;
pub mod scoreboard;
pub mod sensitivity;
pub mod subject;
pub mod suite;
pub mod text;
pub mod tolerance;
pub mod uncertainty;
pub mod units;
pub mod yaml;

pub use case::load_cases;
pub use inputs::condition::{Loading, TrimRequest};
pub use run::*;
pub use units::{FT_TO_M, MPH_PER_KN, MPH_TO_M_S};
