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

pub(crate) fn trim(a: TrimArgs) -> Result<ExitCode, Error> {
    let TrimArgs {
        flight,
        turn_rate_deg_s,
        format,
    } = a;
    let (request, loading) = (flight.request(turn_rate_deg_s), flight.loading());
    let flight = &flight;
    let file = load_flight(flight)?;
    let path = &flight.aircraft;
    let t = cierva_harness::run::trim::run_trim(&file.aircraft, request, loading)
        .map_err(|e| Error::of(e.is_input(), format!("error: {}: {e}", path.display())))?;
    match format {
        Format::Json => print_json(&t),
        Format::Text => print!("{}", tables::trim_report(&file.title, request, loading, &t)),
    }
    Ok(ExitCode::SUCCESS)
}
