//! `cierva trim`: one trimmed flight condition, for people or as JSON.

use super::*;

/// Trim an aircraft in steady flight: stick, pedal and throttle positions, pitch and roll
/// attitude, rotor and propeller speeds, inflow and flapping, with the residuals the
/// Newton solver reached (converged when every scaled residual is at most 1e-7).
///
/// Example: `cierva trim aircraft/vpm-m16.yaml --airspeed-mph 70 --mass-kg 410`
#[derive(clap::Args)]
pub(crate) struct TrimArgs {
    #[command(flatten)]
    flight: FlightArgs,
    /// Rate of turn, deg/s; positive to starboard.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    turn_rate_deg_s: f64,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

pub(crate) fn trim(a: TrimArgs) -> ExitCode {
    let TrimArgs {
        flight,
        turn_rate_deg_s,
        format,
    } = a;
    let (request, loading) = (flight.request(turn_rate_deg_s), flight.loading());
    let flight = &flight;
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
