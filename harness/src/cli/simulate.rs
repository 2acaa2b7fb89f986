//! `cierva simulate`: the full individual-blade model flown from its periodic trim, written as CSV.

use super::*;

/// Fly the full individual-blade model from trim (refined to the full model's periodic
/// orbit) with control inputs: a shape on one control, or a CSV of control changes from
/// trim. Fixed-step fourth-order Runge-Kutta at the aircraft's azimuth step (or
/// `--azimuth-step-deg`). Writes time, controls, body states, rotor and propeller speeds,
/// flapping and inflow as CSV.
///
/// Example: `cierva simulate aircraft/vpm-m16.yaml --airspeed-mph 70 --shape doublet
/// --control eta_s --amplitude-percent 2 --start-s 1 --input-s 1 --duration-s 10
/// --output /tmp/doublet.csv`
#[derive(clap::Args)]
pub(crate) struct SimulateArgs {
    #[command(flatten)]
    flight: FlightArgs,
    /// A CSV of control changes from trim (time_s and any of eta_s_percent, eta_c_percent,
    /// eta_p_percent, eta_t_percent); instead of --shape.
    #[arg(long)]
    controls_csv: Option<PathBuf>,
    #[command(flatten)]
    shape: ShapeArgs,
    /// Length of the run, s.
    #[arg(long, default_value_t = 10.0)]
    duration_s: f64,
    /// Azimuth step of the integration, deg (default: the aircraft file's).
    #[arg(long)]
    azimuth_step_deg: Option<f64>,
    /// Keep every n-th step.
    #[arg(long, default_value_t = 1)]
    every: usize,
    /// The CSV to write.
    #[arg(long)]
    output: PathBuf,
    /// `text` for people, `json` for programs (what was written, as an object).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

pub(crate) fn simulate(a: SimulateArgs) -> Result<ExitCode, Error> {
    let SimulateArgs {
        flight: f,
        controls_csv: input,
        shape,
        duration_s,
        azimuth_step_deg,
        every,
        output,
        format,
    } = a;
    // The command line's own values are its errors (exit 2, naming the option), before any
    // file is read: a length the run can never reach is not the aircraft's fault.
    if !(duration_s.is_finite() && duration_s > 0.0) {
        return Err(Error::input(format!(
            "--duration-s {duration_s}: give the run's length as a positive, finite number of seconds"
        )));
    }
    if every == 0 {
        return Err(Error::input(
            "--every 0: keep every n-th step with n at least 1",
        ));
    }
    let (shape, control) = (shape.input(), shape.control);
    use cierva_harness::inputs::controls;
    let file = load_flight(&f)?;
    let table = match (&input, &shape) {
        (Some(p), None) => Some(controls::read(p)?),
        (None, Some(_)) => None,
        _ => {
            return Err(Error::input(
                "give exactly one of --controls-csv or --shape",
            ));
        }
    };
    let index = control_index(&control).map_err(Error::input)?;
    let changes = |t: f64| -> [f64; 4] {
        match (&table, &shape) {
            (Some(tb), _) => tb.at(t),
            (None, Some(s)) => {
                let mut d = [0.0; 4];
                d[index] = s.at(t);
                d
            }
            _ => [0.0; 4],
        }
    };
    let step = azimuth_step_rad(azimuth_step_deg, &file)?;
    let (request, loading) = (f.request(0.0), f.loading());
    let settings = cierva_model::simulation::timehistory::Settings {
        azimuth_step_rad: step,
        duration_s,
        output_every: every,
    };
    let started = std::time::Instant::now();
    let busy = spinner(&format!("flying {duration_s} s"));
    let flown = cierva_harness::run::simulate::run_simulation(
        &file.aircraft,
        request,
        loading,
        &changes,
        settings,
    );
    busy.finish_and_clear();
    match flown {
        Ok(h) => {
            if let Err(e) = std::fs::write(&output, controls::to_csv(&h)) {
                return Err(Error::input(format!(
                    "cannot write {}: {e}",
                    output.display()
                )));
            }
            let seconds = started.elapsed().as_secs_f64();
            done(
                format,
                format!(
                    "wrote {} ({} samples, step {:.2} ms, {:.2} s of flight in {:.2} s)",
                    output.display(),
                    h.samples.len(),
                    1e3 * h.step_s,
                    duration_s,
                    seconds
                ),
                serde_json::json!({
                    "wrote": [output.display().to_string()],
                    "samples": h.samples.len(),
                    "step_s": h.step_s,
                    "duration_s": duration_s,
                    "seconds": seconds,
                }),
            );
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(Error::of(
            e.is_input(),
            format!("error: {}: {e}", f.aircraft.display()),
        )),
    }
}
