//! The limits on what an input file may ask for, each with its unit and why it is where it is.
//! A number in a file that sizes an allocation or a loop (a count, a step, a duration) is
//! checked against its limit when the file loads, and one beyond it is a located error: a
//! mistyped `elements: 999999999999` once aborted the process on its allocation.
//!
//! The model keeps the limits on its own data, which any caller meets
//! ([`cierva_model::components::rotor::MAX_BLADES`],
//! [`cierva_model::components::rotor::MAX_ELEMENTS_PER_BLADE`],
//! [`cierva_model::components::rotor::MAX_BLADE_ELEMENTS`],
//! [`cierva_model::components::rotor::MAX_ELEMENT_STEPS_PER_REVOLUTION`],
//! [`cierva_model::components::rotor::MAX_AZIMUTH_STEPS_PER_REVOLUTION`],
//! [`cierva_model::simulation::timehistory::MAX_STEPS`],
//! [`cierva_model::components::autorotation::MAX_REVOLUTIONS`]); the files' sizes and nesting
//! are [`crate::inputs::yaml`]'s ([`crate::inputs::yaml::MAX_YAML_FILE_BYTES`],
//! [`crate::inputs::yaml::MAX_CSV_FILE_BYTES`], [`crate::inputs::yaml::MAX_YAML_DEPTH_LEVELS`]).

/// The finest azimuth step an aircraft file, a case or a command may ask for, deg: 3600 steps
/// a revolution. The shipped aircraft step 5 deg and the model's default is 2.5 deg;
/// blade-element simulations use 1 to 10 deg. Twice the model's finest
/// ([`cierva_model::components::rotor::MAX_AZIMUTH_STEPS_PER_REVOLUTION`]), so that the
/// numerical uncertainty's halved step stays within it.
pub const MIN_AZIMUTH_STEP_DEG: f64 = 0.1;

/// The most samples (data rows) a flight record or a control history may have, and a
/// synthetic record may be made with: an hour at 256 Hz. The identification records flown are
/// 1 to 5 minutes at 10 to 100 Hz (600 to 30,000 samples), a teeter record 1000.
pub const MAX_RECORD_SAMPLES: usize = 1_000_000;

/// The most frequencies an identification set-up or a frequency response may be estimated
/// at: seed 000's set-ups use 100, CIFER's grids a few hundred; 10,000 is 100 times the
/// first. The count sizes the transforms' tables (frequencies by samples).
pub const MAX_FREQUENCY_POINTS: usize = 10_000;

/// The most iterations a fit file's `options.max_iterations` may ask for: the default is 20
/// and the shipped fits converge in 6 to 15; 1000 is fifty times the default. Each iteration
/// evaluates every target (a trim and a linearisation, or an autorotation), so a mistyped
/// count would run for days where a fit does not reach its tolerance.
pub const MAX_FIT_ITERATIONS: usize = 1000;

/// Whether `step_deg` is an azimuth step a file or a command may ask for: from
/// [`MIN_AZIMUTH_STEP_DEG`] to `max_deg`.
pub fn azimuth_step_ok(step_deg: f64, max_deg: f64) -> bool {
    step_deg.is_finite() && (MIN_AZIMUTH_STEP_DEG..=max_deg).contains(&step_deg)
}

/// The samples of a record `duration_s` long at `sample_rate_hz` (one every `1 / rate` from
/// zero, the last at the duration): what a synthetic record is made with. An error for a
/// duration or rate that is not positive, or a record past [`MAX_RECORD_SAMPLES`], which no
/// loader would read back.
pub fn record_samples(duration_s: f64, sample_rate_hz: f64) -> Result<usize, String> {
    let n = (duration_s * sample_rate_hz).round();
    if !(duration_s > 0.0 && sample_rate_hz > 0.0 && n.is_finite()) {
        return Err(format!(
            "the duration and sample rate must be positive and finite (got {duration_s} s, \
             {sample_rate_hz} Hz)"
        ));
    }
    if n + 1.0 > MAX_RECORD_SAMPLES as f64 {
        return Err(format!(
            "{duration_s} s at {sample_rate_hz} Hz is {n} samples: a record may have at most \
             {MAX_RECORD_SAMPLES} (MAX_RECORD_SAMPLES)"
        ));
    }
    Ok(n as usize)
}
