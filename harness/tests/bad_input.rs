//! Bad input gets a clear, located error, never a panic: every file in `tests/bad-input/` is a
//! broken case whose header says what the error must contain and on which line it must point
//! (see `common`).

mod common;

use cierva_harness::case;
use std::path::Path;

#[test]
fn every_bad_case_gets_its_located_error() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-input");
    let problems = common::check_fixtures(&dir, 25, case::load);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
