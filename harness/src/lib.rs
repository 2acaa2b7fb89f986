//! # cierva harness
//!
//! Everything between the model and the people who use it, in groups (lowest first): `units`,
//! `inputs` (the file formats), `ident` (flight-data analysis), `run` (the model at a case's
//! conditions), `estimate`, `synth` (synthetic records), `external` (other simulations),
//! `checks` (the check kinds), `suite` (cases, outcomes, the scoreboard), `fit`, `uncertainty`,
//! `plan` (a study as independent evaluations, run in shards), `report` and `bench` (what `cierva bench` times). The `cierva` binary and the generated test
//! suite (`tests/cases.rs`) are thin layers over this library.
//!
//! The model (`cierva-model`) does no I/O; everything that reads files lives here. The root
//! re-exports nothing: an item is named by where it lives (`crate::run::trim::run_trim`).

pub mod bench;
pub mod checks;
pub mod estimate;
pub mod external;
pub mod fit;
pub mod ident;
pub mod inputs;
pub mod plan;
pub mod report;
pub mod run;
pub mod suite;
pub mod synth;
pub mod uncertainty;
pub mod units;
