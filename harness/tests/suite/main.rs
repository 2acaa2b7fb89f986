//! The harness's integration tests, one module per subject, in one test binary: one link
//! instead of eight, and their tests run side by side on the cores instead of one binary after
//! another. The validation suite (`tests/cases.rs`, libtest-mimic) is its own binary. The
//! library has no unit tests of its own (`[lib] test = false`): its parts are tested here
//! (`units`, `architecture`), which saves a second optimised build of the whole library.

mod aircraft;
mod architecture;
mod bad_aircraft;
mod bad_input;
mod cli;
mod common;
mod discrepancies;
mod equivalent;
mod estimate;
mod external;
mod fit;
mod fit_starts;
mod flight_test;
mod frequency_response;
mod frequency_response_check;
mod identification;
mod limits;
mod misbehaving;
mod model_interface;
mod mutation;
mod old_spelling;
mod plan;
mod posterior;
mod quoted;
mod records;
mod report;
mod retune;
mod retune_coverage;
mod trim_points;
mod trivial;
mod tutorials;
mod uncertainty;
mod units;
mod verify;
