//! `cierva simulate`: the full individual-blade model flown from its periodic trim, written as CSV.

use super::*;

pub(crate) fn simulate(
    f: FlightArgs,
    (input, shape, control): (
        Option<PathBuf>,
        Option<cierva_harness::synth::linear::Input>,
        String,
    ),
    (duration_s, azimuth_step_deg, every): (f64, Option<f64>, usize),
    output: PathBuf,
    format: Format,
) -> ExitCode {
    use cierva_harness::inputs::controls;
    let file = match load_flight(&f) {
        Ok(f) => f,
        Err(code) => return code,
    };
    let table = match (&input, &shape) {
        (Some(p), None) => match controls::read(p) {
            Ok(t) => Some(t),
            Err(e) => {
                eprintln!("{}", e.render());
                return ExitCode::from(2);
            }
        },
        (None, Some(_)) => None,
        _ => {
            eprintln!("error: give exactly one of --controls-csv or --shape");
            return ExitCode::from(2);
        }
    };
    let index = match control_index(&control) {
        Ok(i) => i,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
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
    let step = match azimuth_step_rad(azimuth_step_deg, &file) {
        Ok(s) => s,
        Err(code) => return code,
    };
    let (request, loading) = (f.request(0.0), f.loading());
    let settings = cierva_model::simulation::timehistory::Settings {
        azimuth_step_rad: step,
        duration_s,
        output_every: every,
    };
    let started = std::time::Instant::now();
    let busy = spinner(&format!("flying {duration_s} s"));
    let flown =
        cierva_harness::run_simulation(&file.aircraft, request, loading, &changes, settings);
    busy.finish_and_clear();
    match flown {
        Ok(h) => {
            if let Err(e) = std::fs::write(&output, controls::to_csv(&h)) {
                eprintln!("error: cannot write {}: {e}", output.display());
                return ExitCode::from(2);
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
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}: {e}", f.aircraft.display());
            ExitCode::from(1)
        }
    }
}
