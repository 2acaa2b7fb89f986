//! `cierva trim`: one trimmed flight condition, for people or as JSON.

use super::*;

pub(crate) fn trim(
    flight: &FlightArgs,
    request: cierva_harness::TrimRequest,
    loading: cierva_harness::Loading,
    format: Format,
) -> ExitCode {
    let file = match load_flight(flight) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let path = &flight.aircraft;
    let t = match cierva_harness::run_trim(&file.aircraft, request, loading) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: {e}", path.display());
            return ExitCode::from(if e.is_input() { 2 } else { 1 });
        }
    };
    match format {
        Format::Json => print_json(&t),
        Format::Text => print!("{}", tables::trim_report(&file.title, request, loading, &t)),
    }
    ExitCode::SUCCESS
}
