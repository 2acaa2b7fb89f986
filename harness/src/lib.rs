//! # cierva harness
//!
//! Everything between the model and the people who use it: case files and reference files
//! (`case`, `refs`, `yaml`), running checks (`eval`), and text output (`text`). The `cierva`
//! binary and the generated test suite (`tests/cases.rs`) are thin layers over this library.
//!
//! The model (`cierva-model`) does no I/O; everything that reads files lives here.

pub mod case;
pub mod eval;
pub mod refs;
pub mod text;
pub mod yaml;

use case::Case;
use std::path::{Path, PathBuf};
use yaml::InputError;

/// The repository root (where `cases/` and `flight-refs/` live), from this crate's location.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("harness/ sits in the repository root")
        .to_path_buf()
}

/// Every case file found under `paths`, loaded (or the error that stopped it).
///
/// Fails only when a path does not exist or cannot be listed; an empty result is the caller's
/// to reject.
pub fn load_cases(paths: &[PathBuf]) -> Result<Vec<Result<Case, InputError>>, InputError> {
    Ok(case::discover(paths)?
        .iter()
        .map(|p| case::load(p))
        .collect())
}
