//! Malformed aircraft files get a clear, located error, never a panic: every file in
//! `tests/bad-aircraft/` is a broken copy of `aircraft/vpm-m16.yaml` whose header says what the
//! error must contain and on which line of the file it must point (see `common`).

use crate::common;

use cierva_harness::inputs::aircraft;
use std::path::Path;

#[test]
fn every_bad_aircraft_gets_its_located_error() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-aircraft");
    let problems = common::check_fixtures(&dir, 28, aircraft::load);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// Rotor files too: a range on a parameter a rotor file's `ranges:` cannot move, or on one its
/// source does not call estimated, is refused where it is written; so is a blade or element
/// count past its limit (issue 35: `elements: 999999999999` aborted the process), and what no
/// rotor can be, which made every autorotation search run to its end: a section whose drag
/// goes negative, a blade pitched past edge-on.
#[test]
fn every_bad_rotor_gets_its_located_error() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-rotor");
    let problems = common::check_fixtures(&dir, 7, cierva_harness::inputs::rotor::load);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
