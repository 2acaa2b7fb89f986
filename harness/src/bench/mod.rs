//! `cierva bench`'s timings of the model and the harness (reports/benchmarks.md): the rotor,
//! the aircraft, identification, frequency responses, fitting and retuning, uncertainty, and
//! the command protocol's cost a request. Each group times this repository's own files and
//! gives its rows as `reports/benchmarks.md` holds them (a Markdown table row each: operation,
//! median, notes); the command line prints them or gathers them as JSON.

use crate::inputs::reference;
use crate::run::autorotation::run_autorotation;
use cierva_model::components::rotor::{InflowModel, WakeModel};
use std::path::PathBuf;
use std::time::Instant;

/// The benchmark's groups of rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchGroup {
    Rotor,
    Aircraft,
    Identification,
    FrequencyResponse,
    Fitting,
    Uncertainty,
    /// The command protocol's cost a request (a trivial model, one-shot and persistent).
    External,
}

/// The benchmark table: each row is handed to `each` as it is measured.
pub struct Rows<'a> {
    each: &'a dyn Fn(&str),
    /// What a group could not time, for the caller to warn of.
    warnings: std::cell::RefCell<Vec<String>>,
    /// The repository whose files are timed.
    root: PathBuf,
}

impl Rows<'_> {
    /// A file of the repository's, by its path from the root.
    fn file(&self, path: &str) -> PathBuf {
        self.root.join(path)
    }

    fn push(&self, line: String) {
        (self.each)(&line)
    }

    fn warn(&self, warning: String) {
        self.warnings.borrow_mut().push(warning);
    }
}

macro_rules! row {
    ($out:expr, $($t:tt)*) => {
        $out.push(format!($($t)*))
    };
}

/// The median of repeated timings.
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Seconds `f` takes.
fn time(f: &mut dyn FnMut()) -> f64 {
    let t = Instant::now();
    f();
    t.elapsed().as_secs_f64()
}

/// Times the groups `only` picks (all where `None`) of the repository at `root`, each timed
/// operation `repeat` times (at least 3), handing each row (the table's header first) to
/// `each` as it is measured; what to warn of after (what a group could not time, a timed
/// result that was not finite). An error where `root` is not cierva's repository, or a group
/// cannot run.
pub fn run(
    root: &std::path::Path,
    repeat: usize,
    only: Option<BenchGroup>,
    each: &dyn Fn(&str),
) -> Result<Vec<String>, String> {
    // The rows time this repository's own aircraft, records and scripts.
    let marker = root.join("aircraft/vpm-m16.yaml");
    if !marker.is_file() {
        return Err(format!(
            "{}: not found: `cierva bench` times cierva's own aircraft and records; run it in cierva's repository",
            marker.display()
        ));
    }
    let out = Rows {
        each,
        warnings: Default::default(),
        root: root.to_path_buf(),
    };
    let repeat = repeat.max(3);
    row!(out, "| operation | median | notes |");
    row!(out, "| --- | --- | --- |");
    let runs = |g: BenchGroup| only.is_none_or(|o| o == g);
    let mut sink = 0.0;
    if runs(BenchGroup::Rotor) {
        sink += rotor(&out, repeat)?;
    }
    if runs(BenchGroup::Aircraft) {
        sink += aircraft(&out, repeat);
    }
    if runs(BenchGroup::Identification) {
        sink += identification(&out, repeat);
    }
    if runs(BenchGroup::FrequencyResponse) {
        sink += frequency_responses(&out, repeat);
    }
    if runs(BenchGroup::Fitting) {
        fitting(&out);
        retuning(&out);
    }
    if runs(BenchGroup::Uncertainty) {
        uncertainty(&out);
    }
    if runs(BenchGroup::External) {
        external(&out)?;
    }
    if !sink.is_finite() {
        out.warn("a timed result was not finite".into());
    }
    Ok(out.warnings.take())
}

/// The isolated rotor: blade right-hand side, periodic blade solution, autorotation (the PCA-2
/// at TR 515 Table III row 19).
fn rotor(out: &Rows, repeat: usize) -> Result<f64, String> {
    use cierva_model::components::rotor::{Blade, HubVelocity, Inflow, Numerics, Operating};
    let path = out.file("aircraft/pca-2-rotor.yaml");
    let file = crate::inputs::rotor::load(&path).map_err(|e| e.render())?;
    let rotor = &file.rotor;
    // TR 515 Table III row 19 conditions (mu 0.275, alpha 5.5 deg, 100 rpm), 1.9 deg pitch.
    let omega = 100.0 * std::f64::consts::PI / 30.0;
    let v = 0.275 * omega * rotor.radius_m / 5.5f64.to_radians().cos();
    let op = Operating {
        omega_rad_s: omega,
        hub: HubVelocity {
            u: v * 5.5f64.to_radians().cos(),
            v: 0.0,
            w: v * 5.5f64.to_radians().sin(),
        },
        inflow: Inflow {
            v0: 0.5,
            v1s: 0.0,
            v1c: -0.8,
        },
        density_kg_m3: 1.225,
        speed_of_sound_m_s: 340.3,
        collective_shift_rad: rotor.collective_shift_for(1.9f64.to_radians()),
        hub_rates_rad_s: [0.0; 3],
        apparent_gravity_m_s2: [0.0; 3],
        hub_angular_acceleration_rad_s2: [0.0; 3],
    };
    let blade = Blade::new(rotor, Numerics::default());
    let n_rhs = 10_000;
    let mut sink = 0.0;
    let rhs: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                for k in 0..n_rhs {
                    sink += blade.flap_derivative(&op, k as f64 * 1e-3, [0.1, 0.01])[1];
                }
            }) / n_rhs as f64
        })
        .collect();
    let warm = blade
        .steady(&op, [0.1, 0.0])
        .map(|l| l.beta0)
        .unwrap_or([0.1, 0.0]);
    let steady: Vec<f64> = (0..repeat)
        .map(|_| time(&mut || sink += blade.steady(&op, warm).map_or(0.0, |l| l.thrust_n())))
        .collect();
    let inflow = InflowModel::PetersHaQuang {
        wake: WakeModel::SEED_001,
    };
    let auto: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                sink +=
                    run_autorotation(rotor, 5.5, v, Some(1.9), None, inflow).map_or(0.0, |a| a.rpm)
            })
        })
        .collect();
    row!(
        out,
        "| blade right-hand side (flap equation with {} elements) | {:.2} us | one blade at one azimuth; {} blades per rotor evaluation |",
        rotor.elements + 1,
        1e6 * median(rhs),
        rotor.blades
    );
    row!(
        out,
        "| periodic blade solution (warm start, 2.5 deg steps, RK4) | {:.2} ms | one blade to a periodic state, then one revolution of loads |",
        1e3 * median(steady)
    );
    // TR 515 row 80's condition as the tunnel gives it (mu 0.525 at 140 rpm): the angle found.
    let at_mu: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                sink += crate::run::autorotation::run_autorotation_at_tip_speed_ratio(
                    rotor,
                    0.525,
                    140.0,
                    Some(1.9),
                    None,
                    inflow,
                )
                .map_or(0.0, |f| f.alpha_rad)
            })
        })
        .collect();
    row!(
        out,
        "| PCA-2 autorotation (bracket + Newton on Omega, v0, v1s, v1c) | {:.1} ms | TR 515 row 19 condition, from a cold start |",
        1e3 * median(auto.clone())
    );
    row!(
        out,
        "| PCA-2 autorotation at a tip-speed ratio and rotor speed (the angle found) | {:.1} ms | TR 515 row 80 condition (mu 0.525, 140 rpm); {:.1} times the autorotation at a given angle above (target: 3) |",
        1e3 * median(at_mu.clone()),
        median(at_mu) / median(auto.clone())
    );
    Ok(sink)
}

/// The aircraft: the VPM M16 trim at 70 mph, the model's right-hand sides there, linearisation and simulation.
fn aircraft(out: &Rows, repeat: usize) -> f64 {
    let mut sink = 0.0;
    // The aircraft: VPM M16 trim at 70 mph and the model's right-hand sides at that trim.
    let ac_path = out.file("aircraft/vpm-m16.yaml");
    match crate::inputs::aircraft::load(&ac_path) {
        Err(e) => out.warn(e.render()),
        Ok(ac) => {
            let request = crate::inputs::condition::TrimRequest::level(70.0);
            let loading = crate::inputs::condition::Loading {
                mass_kg: None,
                density_altitude_ft: 0.0,
            };
            let mut last = None;
            let trims: Vec<f64> = (0..repeat)
                .map(|_| {
                    time(&mut || {
                        last = crate::run::trim::run_trim(&ac.aircraft, request, loading).ok();
                    })
                })
                .collect();
            // The fit's case: the same condition with a correction moved a little (here the
            // mass, by 5 kg), started from the last trim's end.
            let heavier = crate::inputs::condition::Loading {
                mass_kg: Some(ac.aircraft.mass.mass_kg + 5.0),
                ..loading
            };
            let (warm_trims, warm_last) =
                warm_trims(&ac.aircraft, request, heavier, last.as_ref(), repeat);
            if let Some(t) = last {
                let air = cierva_model::aircraft::Air {
                    density_kg_m3: 1.225,
                    speed_of_sound_m_s: 340.294,
                };
                let a = &ac.aircraft;
                let x = a.full_state(&t.state, &t.controls, air, t.averaged.flap_start);
                let full = rhs_times(a, &x, &t.controls, air, repeat, &mut sink);
                // The same with the propeller on its map, as a simulation runs it.
                let mut mapped = a.clone();
                if let Ok(p) = a.propeller.propeller.with_map() {
                    mapped.propeller.propeller = p;
                }
                let full_mapped = rhs_times(&mapped, &x, &t.controls, air, repeat, &mut sink);
                let map_build: Vec<f64> = (0..repeat.min(5))
                    .map(|_| {
                        time(&mut || {
                            sink += a.propeller.propeller.build_map().nodes() as f64;
                        })
                    })
                    .collect();
                let averaged: Vec<f64> = (0..repeat)
                    .map(|_| {
                        time(&mut || {
                            sink += a
                                .averaged(&t.state, &t.controls, air, t.averaged.flap_start)
                                .map_or(0.0, |d| d.body_dot.u_m_s)
                        })
                    })
                    .collect();
                let lins: Vec<f64> = (0..repeat)
                    .map(|_| {
                        time(&mut || {
                            sink +=
                                crate::run::linearise::run_linearise(&ac.aircraft, request, loading)
                                    .map_or(0.0, |(_, l)| l.model.a()[(0, 0)])
                        })
                    })
                    .collect();
                row!(
                    out,
                    "| VPM M16 trim and linearisation at 70 mph | {:.1} ms | the trim, then central differences in 10 states, 4 controls and 7 fast variables (the inflow, the propeller speed, the angular acceleration the blades feel): 42 revolution-averaged evaluations of one periodic solution at most on two threads, those that leave the rotor as trimmed taking the trim's solution, the others starting from what it learned; target: under 100 ms |",
                    1e3 * median(lins)
                );
                simulation_rows(out, &ac.aircraft, air, repeat, &mut sink);
                row!(
                    out,
                    "| VPM M16 trim at 70 mph, 450 kg, sea level (cold start) | {:.1} ms | {} Newton iterations (finite-difference Jacobian, then Broyden updates); target: under 50 ms |",
                    1e3 * median(trims),
                    t.iterations
                );
                if let Some(w) = warm_last {
                    row!(
                        out,
                        "| VPM M16 trim at 70 mph, 455 kg, warm-started from the 450 kg trim | {:.1} ms | {} model evaluations against {} cold: the last Jacobian carried over, as in a fit |",
                        1e3 * median(warm_trims),
                        w.evaluations,
                        t.evaluations
                    );
                }
                row!(
                    out,
                    "| full model right-hand side (individual blades, {} flap states, inflow, rotorspeed, propeller, airframe, 6-DOF) | {:.1} us | one evaluation at the 70 mph trim, including the propeller's inflow solution |",
                    x.flap.len(),
                    1e6 * median(full)
                );
                row!(
                    out,
                    "| full model right-hand side, the propeller on its map | {:.1} us | what a simulation evaluates; the map (101 by 61 nodes of the axial solve, 41 by 13 of the in-plane coefficients) takes {:.0} ms to build, once per process and propeller |",
                    1e6 * median(full_mapped),
                    1e3 * median(map_build)
                );
                row!(
                    out,
                    "| revolution-averaged model evaluation (periodic blade solution, warm) | {:.2} ms | what trim evaluates: the rotor's periodic flapping at 5 deg steps, then its mean loads |",
                    1e3 * median(averaged)
                );
            }
        }
    }
    sink
}

/// Trims at `heavier` warm-started from the `last` trim's end (none without it): their
/// timings and the last one's result.
fn warm_trims(
    aircraft: &cierva_model::aircraft::Aircraft,
    request: crate::inputs::condition::TrimRequest,
    heavier: crate::inputs::condition::Loading,
    last: Option<&cierva_model::aircraft::trim::Trim>,
    repeat: usize,
) -> (Vec<f64>, Option<cierva_model::aircraft::trim::Trim>) {
    let mut warm_last = None;
    let warm_trims: Vec<f64> = match last {
        None => vec![],
        Some(t) => (0..repeat)
            .map(|_| {
                time(&mut || {
                    warm_last = crate::run::trim::run_trim_from(
                        aircraft,
                        request,
                        heavier,
                        Some(&t.warm_start),
                    )
                    .ok();
                })
            })
            .collect(),
    };
    (warm_trims, warm_last)
}

/// Timings of one right-hand side of `craft` at the state `x` (its rotor azimuth stepped over
/// 1000 azimuths a repeat, the time divided among them), added to `sink`.
fn rhs_times(
    craft: &cierva_model::aircraft::Aircraft,
    x: &cierva_model::aircraft::FullState,
    controls: &cierva_model::aircraft::Controls,
    air: cierva_model::aircraft::Air,
    repeat: usize,
    sink: &mut f64,
) -> Vec<f64> {
    let n = 1000;
    (0..repeat)
        .map(|_| {
            time(&mut || {
                for k in 0..n {
                    let mut y = x.clone();
                    y.rotor_azimuth_rad = k as f64 * 0.01;
                    *sink += craft
                        .derivatives(&y, controls, air)
                        .map_or(0.0, |d| d.body.u_m_s);
                }
            }) / n as f64
        })
        .collect()
}

/// The simulation rows: 60 s of level flight from the full model's periodic trim, with 10 and
/// 20 elements per blade, one thread.
fn simulation_rows(
    out: &Rows,
    aircraft: &cierva_model::aircraft::Aircraft,
    air: cierva_model::aircraft::Air,
    repeat: usize,
    sink: &mut f64,
) {
    for elements in [10usize, 20] {
        let mut a2 = aircraft.clone();
        a2.main_rotor.rotor.elements = elements;
        let c = cierva_model::aircraft::trim::Condition {
            airspeed_m_s: 70.0 * crate::units::MPH_TO_M_S,
            climb_m_s: 0.0,
            turn_rate_rad_s: 0.0,
            air,
        };
        let Ok(t2) = cierva_model::aircraft::trim::trim(&a2, c, Default::default()) else {
            continue;
        };
        let Ok(pt) =
            cierva_model::simulation::periodic_trim::periodic_trim(&a2, c, &t2, Default::default())
        else {
            continue;
        };
        let u = pt.controls;
        let settings = cierva_model::simulation::timehistory::Settings {
            azimuth_step_rad: a2.main_rotor.numerics.azimuth_step_rad,
            duration_s: 60.0,
            output_every: 72,
        };
        let runs: Vec<f64> = (0..repeat.min(5))
            .map(|_| {
                time(&mut || {
                    *sink += cierva_model::simulation::timehistory::run(
                        &a2,
                        pt.start.clone(),
                        &|_| u,
                        air,
                        settings,
                    )
                    .map_or(0.0, |h| h.step_s)
                })
            })
            .collect();
        let m = median(runs);
        row!(
            out,
            "| VPM M16 simulation, 60 s, {elements} elements per blade | {:.2} s | {:.0} times faster than real time on one core; RK4 at 5 deg of azimuth (about 2 ms), 4 right-hand sides a step; target: 200 times with 10 elements |",
            m,
            60.0 / m
        );
    }
}

/// Identification (the identification benchmark), each row side by side with the same
/// estimator in numpy (`scripts/ident_numpy.py`; issue 32: "at least 10x a numpy implementation
/// of the same estimator, measured side by side in one run").
fn identification(out: &Rows, repeat: usize) -> f64 {
    let mut sink = 0.0;
    // Identification: the five-state longitudinal model from 120 s at 100 Hz over 100
    // frequencies (the identification benchmark), on a synthetic record of seed 002's Eq. 20.
    use crate::ident;
    use crate::inputs::record;
    use crate::synth::linear;
    let truth = reference::load(&out.file("flight-refs/seed002-vpm-m16-60kn.yaml"))
        .ok()
        .and_then(|r| r.linear_model);
    let numpy = numpy::Numpy::find(&out.root);
    if let Some(model) = truth {
        for (seconds, points) in [(120.0, 100), (240.0, 100), (120.0, 200)] {
            let settings = linear::LinearTest {
                id: "bench".into(),
                aircraft: "VPM M16".into(),
                truth: "seed 002 Eq. 20".into(),
                control: "eta_s".into(),
                input: crate::synth::linear::TestInput::Sweep {
                    from_hz: 0.02,
                    to_hz: 2.5,
                    duration_s: seconds - 20.0,
                    amplitude: 0.01,
                    descending: false,
                },
                duration_s: seconds,
                sample_rate_hz: 100.0,
                seed: 1,
                noise: linear::SensorNoise::NONE,
                turbulence: None,
                trim: linear::SEED002_TRIM,
                sensors: linear::SEED002_SENSORS,
                condition: Default::default(),
                control_channel: "eta_s_rad".into(),
            };
            let Ok((channels, data, meta)) = linear::generate(&model, &settings) else {
                continue;
            };
            let rec = record::Record {
                path: "bench.csv".into(),
                meta,
                channels,
                data,
                notes: Vec::new(),
            };
            let mut cfg = ident::ConfigSpec::longitudinal(&rec);
            cfg.frequencies.points = Some(points);
            let what = format!("5 states, {seconds} s at 100 Hz, {points} frequencies");
            let mut side = numpy.as_ref().ok().map(|n| n.side(&rec, points));
            // Rounds alternate between cierva and numpy, so that a slow spell of a shared
            // machine falls on both; each side's median is over all its rounds.
            let rounds = if side.is_some() { numpy::ROUNDS } else { 1 };
            let per_round = repeat.div_ceil(rounds).max(3);
            let mut t = Vec::new();
            for _ in 0..rounds {
                t.extend((0..per_round).map(|_| {
                    time(&mut || {
                        sink += ident::identify_record(&rec, &cfg)
                            .map_or(0.0, |r| r.derivatives.len() as f64)
                    })
                }));
                if let Some(Ok(s)) = side.as_mut() {
                    s.time(per_round);
                }
            }
            let ours = median(t);
            row!(
                out,
                "| identification, {what} | {:.1} ms | air data to c.g., chirp-z transforms once, least squares then 2 instrumental-variable passes |",
                1e3 * ours
            );
            numpy::row(out, &what, &numpy, side, ours);
        }
    }
    sink + records_together(out, repeat)
}

/// The same estimator in numpy, run by `python3 scripts/ident_numpy.py` beside cierva's rows.
mod numpy {
    use super::{Rows, median};
    use crate::inputs::record;
    use std::path::PathBuf;
    use std::process::Command;

    /// Rounds of each side per row.
    pub(super) const ROUNDS: usize = 3;

    /// What cierva's row must be, at least, times faster (issue 32).
    const TARGET: f64 = 10.0;

    /// python3 with numpy, found.
    pub(super) struct Numpy {
        script: PathBuf,
        version: String,
        dir: PathBuf,
    }

    /// One row's record written for numpy, its timings, and whether it agrees with cierva.
    pub(super) struct Side {
        script: PathBuf,
        csv: PathBuf,
        points: usize,
        times_s: Vec<f64>,
        agreement: Result<String, String>,
        failed: Option<String>,
    }

    /// `python3` with one BLAS thread (cierva's estimator runs on one core).
    fn python() -> Command {
        let mut c = Command::new("python3");
        for v in ["OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"] {
            c.env(v, "1");
        }
        c
    }

    /// Runs the script; its standard output as JSON, or why not.
    fn run(mut c: Command) -> Result<serde_json::Value, String> {
        let o = c
            .output()
            .map_err(|e| format!("python3 did not run: {e}"))?;
        if !o.status.success() && o.stdout.is_empty() {
            return Err(String::from_utf8_lossy(&o.stderr).trim().replace('|', "/"));
        }
        serde_json::from_slice(&o.stdout).map_err(|e| format!("unreadable output ({e})"))
    }

    impl Numpy {
        /// python3 and numpy, or the reason they cannot be used.
        pub(super) fn find(root: &std::path::Path) -> Result<Self, String> {
            let script = root.join("scripts/ident_numpy.py");
            if !script.is_file() {
                return Err(format!("{} is not there", script.display()));
            }
            let mut c = python();
            c.args(["-c", "import numpy; print(numpy.__version__)"]);
            let o = c
                .output()
                .map_err(|e| format!("python3 is not installed ({e})"))?;
            if !o.status.success() {
                return Err("numpy is not installed for python3 (pip install numpy)".into());
            }
            let dir =
                std::env::temp_dir().join(format!("cierva-bench-numpy-{}", std::process::id()));
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            Ok(Self {
                script,
                version: String::from_utf8_lossy(&o.stdout).trim().to_string(),
                dir,
            })
        }

        /// The record written where numpy reads it (the same numbers: the CSV holds each
        /// sample's shortest round-trip form), and its agreement with `cierva identify`.
        pub(super) fn side(&self, rec: &record::Record, points: usize) -> Result<Side, String> {
            let n = rec.data.first().map_or(0, Vec::len);
            let dir = self.dir.join(format!("{n}-{points}"));
            std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
            let csv = dir.join(format!("{}.csv", rec.meta.id));
            record::write(&csv, &rec.meta, &rec.channels, &rec.data).map_err(|e| e.to_string())?;
            let mut c = python();
            c.arg(&self.script)
                .arg(&csv)
                .args([
                    "--points",
                    &points.to_string(),
                    "--check",
                    "--format",
                    "json",
                ])
                .arg("--cierva")
                .arg(std::env::current_exe().map_err(|e| e.to_string())?);
            let agreement = run(c).map(|v| {
                let f = |k: &str, f: &str| v[k][f].as_f64().unwrap_or(f64::NAN);
                format!(
                    "{} cierva identify on the same record: estimates' terms within {:.0e} of their equation, standard errors within {:.0e} relative (tolerance: the script's `--check`)",
                    if v["ok"].as_bool() == Some(true) { "agrees with" } else { "DIFFERS from" },
                    f("estimate_in_equation", "value"),
                    f("standard_error_plain", "value"),
                )
            });
            Ok(Side {
                script: self.script.clone(),
                csv,
                points,
                times_s: Vec::new(),
                agreement,
                failed: None,
            })
        }
    }

    impl Drop for Numpy {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }

    impl Side {
        /// One round: `repeat` timings of the estimator on the record in memory.
        pub(super) fn time(&mut self, repeat: usize) {
            if self.failed.is_some() {
                return;
            }
            let mut c = python();
            c.arg(&self.script).arg(&self.csv).args([
                "--points",
                &self.points.to_string(),
                "--repeat",
                &repeat.to_string(),
            ]);
            match run(c) {
                Ok(v) => match v["times_s"].as_array() {
                    Some(t) => self.times_s.extend(t.iter().filter_map(|x| x.as_f64())),
                    None => self.failed = Some("no timings in its output".into()),
                },
                Err(e) => self.failed = Some(e),
            }
        }
    }

    /// numpy's row beside cierva's: its median and the ratio, or why there is none.
    pub(super) fn row(
        out: &Rows,
        what: &str,
        numpy: &Result<Numpy, String>,
        side: Option<Result<Side, String>>,
        ours: f64,
    ) {
        let name = format!("numpy, the same estimator (scripts/ident_numpy.py), {what}");
        let why_not = match (numpy, side) {
            (Err(e), _) => e.clone(),
            (Ok(_), None) => "not run".into(),
            (Ok(_), Some(Err(e))) => format!("its record could not be written: {e}"),
            (Ok(_), Some(Ok(s))) if s.failed.is_some() || s.times_s.is_empty() => {
                format!(
                    "scripts/ident_numpy.py failed: {}",
                    s.failed.unwrap_or_default()
                )
            }
            (Ok(n), Some(Ok(s))) => {
                let theirs = median(s.times_s);
                let ratio = theirs / ours;
                row!(
                    out,
                    "| {name} | {:.1} ms | cierva {ratio:.2} times as fast in this run (target {TARGET:.0} times: {}); {} rounds alternating with cierva's row above, each side's median; both time the estimator on the record in memory, air data to c.g. to the standard errors (numpy's CSV parsing excluded); numpy {}, one BLAS thread; {} |",
                    1e3 * theirs,
                    if ratio >= TARGET { "met" } else { "not met" },
                    ROUNDS,
                    n.version,
                    s.agreement.unwrap_or_else(|e| format!(
                        "its agreement with cierva was not checked: {e}"
                    ))
                );
                return;
            }
        };
        row!(
            out,
            "| {name} | not measured | {why_not}: no side-by-side figure |"
        );
    }
}

/// Frequency responses (issue 32): four 120 s records at 100 Hz of seed 002's linear VPM M16
/// through exponential sweeps with sensor noise, `q_rad_s` to `eta_s_rad`, windows of 10, 20
/// and 40 s, 100 frequencies.
fn frequency_responses(out: &Rows, repeat: usize) -> f64 {
    use crate::ident::frequency_response as fr;
    use crate::synth::linear;
    let Some(model) = reference::load(&out.file("flight-refs/seed002-vpm-m16-60kn.yaml"))
        .ok()
        .and_then(|r| r.linear_model)
    else {
        return 0.0;
    };
    let mut runs = Vec::new();
    for seed in 1..=4 {
        let settings = linear::LinearTest::exponential_sweep("bench", seed);
        let Ok((channels, data, _)) = linear::generate(&model, &settings) else {
            return 0.0;
        };
        let col = |name: &str| {
            channels
                .iter()
                .position(|c| c == name)
                .map_or_else(Vec::new, |i| data[i].clone())
        };
        runs.push(fr::RecordSignals {
            name: format!("bench-{seed}"),
            inputs: vec![col("eta_s_rad")],
            output: col("q_rad_s"),
            dt_s: 0.01,
        });
    }
    let mut sink = 0.0;
    for overlap in [fr::DEFAULT_OVERLAP, 0.5] {
        let settings = fr::SpectralSettings {
            windows_s: vec![10.0, 20.0, 40.0],
            overlap,
            points: 100,
            band_hz: None,
        };
        let t: Vec<f64> = (0..repeat)
            .map(|_| {
                time(&mut || {
                    sink += fr::estimate(&runs, &settings)
                        .map_or(0.0, |e| e.inputs[0].coherence.iter().sum::<f64>())
                })
            })
            .collect();
        row!(
            out,
            "| frequency response: four 120 s records at 100 Hz, windows 10, 20 and 40 s, 100 frequencies, {:.0} % overlap | {:.1} ms | Welch spectra (Hann) by one matrix product per window, composite, coherence and random error; target: under 50 ms |",
            100.0 * overlap,
            1e3 * median(t)
        );
    }
    sink
}

/// Three 120 s flight tests of the VPM M16 flown by the full model (sweeps on stick, lateral
/// stick and pedal at 70 mph, 1 % turbulence), identified together with the coupled set-up.
fn records_together(out: &Rows, repeat: usize) -> f64 {
    use crate::ident;
    use crate::synth::flight;
    let Ok(file) = crate::inputs::aircraft::load(&out.file("aircraft/vpm-m16.yaml")) else {
        return 0.0;
    };
    let mut records = Vec::new();
    for (control, amplitude) in [(0usize, 4.0), (1, 3.0), (2, 5.0)] {
        let test = sweep_flight(
            (70.0, control),
            amplitude,
            0.313,
            700 + control as u64,
            file.aircraft.main_rotor.numerics.azimuth_step_rad,
        );
        let started = std::time::Instant::now();
        let Ok(f) = flight::fly(&file.aircraft, &test) else {
            return 0.0;
        };
        if control == 0 {
            row!(
                out,
                "| synth-flight's flight: VPM M16, 120 s at 100 Hz, 20 elements, pilot and turbulence | {:.2} s | the periodic trim, the pilot's linearisation and the full model's run (one sample, not a median); target: under 1.5 s |",
                started.elapsed().as_secs_f64()
            );
        }
        let mut condition = std::collections::BTreeMap::new();
        condition.insert("airspeed_mph".to_string(), serde_yaml::Value::from(70.0));
        records.push(f.into_record(
            &format!("bench-{control}"),
            control,
            100.0,
            "synthetic: the benchmark",
            condition,
        ));
    }
    let Ok(cfg) = ident::ConfigSpec::for_setup(ident::Setup::Coupled, &records[0]) else {
        return 0.0;
    };
    let mut sink = 0.0;
    let t: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                sink += ident::identify_records(&records, &cfg)
                    .map_or(0.0, |r| r.derivatives.len() as f64)
            })
        })
        .collect();
    row!(
        out,
        "| identification of three 120 s records together (full-model flights, coupled set-up: 9 states, 3 controls, 100 frequencies) | {:.1} ms | transforms of every record, stacked, least squares then 2 instrumental-variable passes; target: under 50 ms |",
        1e3 * median(t)
    );
    sink + flapping(out, repeat, &file.aircraft, &records, &cfg)
}

/// The linearisation with flapping states at the records' condition, and what the set-up
/// identifies from it: over the band by harmonic balance (the case's check), and from its
/// response to the records' controls (`identify --against`).
fn flapping(
    out: &Rows,
    repeat: usize,
    aircraft: &cierva_model::aircraft::Aircraft,
    records: &[crate::inputs::record::Record],
    cfg: &crate::ident::ConfigSpec,
) -> f64 {
    use crate::ident;
    let mut sink = 0.0;
    let Some(Ok((req, loading))) = records.first().map(ident::record_condition) else {
        return sink;
    };
    let Ok(trim) = crate::run::trim::run_trim(aircraft, req, loading) else {
        return sink;
    };
    let mut flapping = None;
    let t: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                flapping =
                    crate::run::linearise::run_linearise_with_flapping(aircraft, &trim, loading)
                        .ok();
            })
        })
        .collect();
    let Some(wf) = flapping else {
        return sink;
    };
    row!(
        out,
        "| VPM M16 linearisation with flapping states at 70 mph (16 states) | {:.1} ms | the averaged flap, inflow and propeller equilibrium by Newton, then central differences in 16 states and 4 controls, each the full model at 48 azimuths, on two threads |",
        1e3 * median(t)
    );
    let model_cfg = ident::ConfigSpec::for_model(ident::Setup::Coupled);
    let band: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                let at = |w: f64| wf.baseband_response(w).map_err(|e| e.to_string());
                sink += ident::equivalent::identify_response(
                    &model_cfg,
                    ident::equivalent::Response {
                        states: wf.model.states(),
                        controls: wf.model.controls(),
                        at: &at,
                    },
                )
                .map_or(0.0, |r| r.derivatives.len() as f64)
            })
        })
        .collect();
    row!(
        out,
        "| the same identified over the band from its baseband response (coupled set-up, 100 frequencies, 4 sidebands) | {:.1} ms | harmonic balance at each frequency (a 144-unknown complex solve), then the set-up's fit: what an `as_identified` check computes |",
        1e3 * median(band)
    );
    let flown: Vec<f64> = (0..repeat)
        .map(|_| {
            time(&mut || {
                sink += ident::equivalent::identify_flapping(records, cfg, &wf)
                    .map_or(0.0, |r| r.derivatives.len() as f64)
            })
        })
        .collect();
    row!(
        out,
        "| the same from its response to the three records' controls | {:.1} ms | the records' control transforms at the estimator's points, times the baseband response (harmonic balance), then the fit: what `identify --against` adds |",
        1e3 * median(flown)
    );
    sink
}

/// Fitting (the fit benchmark).
fn fitting(out: &Rows) {
    // Fitting (the fit benchmark): 3 parameters over 5 flight conditions, from the
    // uncorrected model to a synthetic truth (blockage 1.0, hub factor 0.5, drag +15 %), with X_u,
    // Z_w and the rotor speed at 40-70 mph as targets (at 30 mph the truth needs more than full
    // throttle).
    if let Ok(ac) = crate::inputs::aircraft::load(&out.file("aircraft/vpm-m16.yaml")) {
        use crate::fit::{
            self, FitOptions, FitParameter, FitSubject, Measure, ParameterKind, Problem, Target,
            TargetCondition,
        };
        let par = |kind: ParameterKind, lower, upper| FitParameter {
            start: kind.neutral().unwrap_or(lower),
            kind,
            lower,
            upper,
            regularisation: 0.0,
        };
        let loading = crate::inputs::condition::Loading {
            mass_kg: Some(425.0),
            density_altitude_ft: 2000.0,
        };
        let mut problem = Problem {
            subject: FitSubject::Aircraft {
                file: Box::new(ac.clone()),
            },
            parameters: vec![
                par(ParameterKind::PropellerBlockage, 0.0, 1.0),
                par(ParameterKind::HubAoaFactor, 0.0, 1.5),
                par(ParameterKind::ProfileDragScale, 0.5, 2.0),
            ],
            targets: vec![],
            options: FitOptions::default(),
            executor: crate::fit::Executor::Local,
        };
        for mph in [40.0, 45.0, 55.0, 62.5, 70.0] {
            for (m, se) in [("X_u", 0.05), ("Z_w", 0.05), ("rotor_rpm", 0.01)] {
                let condition = TargetCondition::Flight(
                    crate::inputs::condition::TrimRequest::level(mph),
                    loading,
                );
                problem.targets.push(Target {
                    measure: Measure::parse(&condition, m).expect("known"),
                    condition,
                    reference: 0.0,
                    standard_error: se,
                    bounds: None,
                });
            }
        }
        let truth = [1.0, 0.5, 1.15];
        match fit::evaluate(&problem, &truth) {
            Err(e) => out.warn(format!("fit benchmark: the truth does not evaluate: {e}")),
            Ok(y) => {
                for (t, v) in problem.targets.iter_mut().zip(y) {
                    t.reference = v;
                    t.standard_error *= v.abs();
                }
                let started = Instant::now();
                let r = fit::fit(&problem);
                let total = started.elapsed().as_secs_f64();
                row!(
                    out,
                    "| fit: 3 parameters, 5 conditions, 15 targets (synthetic truth) | {total:.2} s | {} in {} iterations ({:.2} s each), {} evaluations (trim, started from the fit's current point's at its condition, and linearisation at 5 conditions on two threads); found {:.4}, {:.4}, {:.4} against 1, 0.5, 1.15; target: under 5 s |",
                    r.status.name(),
                    r.iterations,
                    total / r.iterations.max(1) as f64,
                    r.evaluations,
                    r.values[0],
                    r.values[1],
                    r.values[2]
                );
            }
        }
    }
}

/// `cierva retune` by frequency-response matching (the default), the responses estimated and
/// the fit, without the report: from 4 and from 12 full-model stick sweeps (120 s at 100 Hz,
/// turbulence 0.3 m/s, the pilot's hold) of the VPM M16 with hidden corrections, at one and at
/// three airspeeds. One sample each, not a median (seconds each).
fn retuning(out: &Rows) {
    use crate::fit::retune::{self, How, RetuneParameter};
    use crate::synth::flight;
    let Ok(file) = crate::inputs::aircraft::load(&out.file("aircraft/vpm-m16.yaml")) else {
        return;
    };
    let hidden = crate::inputs::corrections::CorrectionSet {
        hub_aoa_factor: Some(0.55),
        profile_drag_scale: Some(1.3),
        ..Default::default()
    };
    let Ok(truth) = file.with_corrections(&hidden) else {
        return;
    };
    let fly = |mph: f64, seed: u64| {
        let test = sweep_flight(
            (mph, 0),
            6.0,
            0.3,
            seed,
            truth.aircraft.main_rotor.numerics.azimuth_step_rad,
        );
        let f = flight::fly(&truth.aircraft, &test).ok()?;
        let mut condition = std::collections::BTreeMap::new();
        condition.insert("airspeed_mph".to_string(), serde_yaml::Value::from(mph));
        Some(f.into_record(
            &format!("bench-{mph}-{seed}"),
            0,
            100.0,
            "synthetic: the benchmark",
            condition,
        ))
    };
    let requests: Vec<RetuneParameter> = ["hub_aoa_factor", "profile_drag_scale"]
        .iter()
        .map(|n| RetuneParameter {
            name: n.to_string(),
            bounds: None,
        })
        .collect();
    for (speeds, per) in [(&[60.0][..], 4u64), (&[50.0, 60.0, 70.0][..], 4)] {
        let Some(records) = speeds
            .iter()
            .flat_map(|v| (0..per).map(move |k| (*v, k)))
            .map(|(v, k)| fly(v, 800 + k + v as u64))
            .collect::<Option<Vec<_>>>()
        else {
            out.warn("retune benchmark: a flight failed".into());
            return;
        };
        let started = Instant::now();
        let r = retune::retune(
            retune::subject::Retuned::Aircraft(&file),
            &records,
            &requests,
            &How::default(),
        );
        let total = started.elapsed().as_secs_f64();
        match r {
            Ok(r) => row!(
                out,
                "| retune (frequency responses) from {} records at {} airspeed(s), 2 corrections | {total:.2} s | {} targets, {} in {} iterations, {} evaluations (trim started from the fit's current point's, flapping linearisation and harmonic balance at each target frequency, conditions on two threads); found {:.3} +- {:.3}, {:.3} +- {:.3} against 0.55, 1.3; target: under 30 s |",
                records.len(),
                speeds.len(),
                r.problem.targets.len(),
                r.result.status.name(),
                r.result.iterations,
                r.result.evaluations,
                r.result.values[0],
                r.result.standard_errors[0],
                r.result.values[1],
                r.result.standard_errors[1]
            ),
            Err(e) => out.warn(format!("retune benchmark: {e}")),
        }
    }
}

/// `cierva uncertainty` on seed 001 Table 2's two cases (cierva's VPM M16 at both weights) at 32
/// base samples: the design's evaluations on both cores, and the cost of one.
fn uncertainty(out: &Rows) {
    use crate::uncertainty::propagate::{self, PropagationSettings};
    let root = &out.root;
    let settings = PropagationSettings {
        samples: 32,
        seed: 0,
        validation_only: false,
        method: propagate::Propagation::Auto,
    };
    let (mut seconds, mut evaluations, mut inputs) = (0.0, 0, 0);
    for weight in ["max", "min"] {
        let path = root.join(format!(
            "cases/cierva-table2-vpm-m16-70mph-{weight}-weight.yaml"
        ));
        let Ok(case) = crate::suite::case::load(&path) else {
            out.warn(format!(
                "uncertainty benchmark: {} does not load",
                path.display()
            ));
            return;
        };
        let started = Instant::now();
        match crate::uncertainty::study::propagate(&case, settings, || {}) {
            Ok(u) => {
                evaluations += u.evaluations;
                inputs = u.inputs.len();
            }
            Err(e) => {
                out.warn(format!("uncertainty benchmark: {e}"));
                return;
            }
        }
        seconds += started.elapsed().as_secs_f64();
    }
    let per = seconds / evaluations.max(1) as f64;
    // The design's size grows with the inputs (Saltelli: samples x (inputs + 2) evaluations), so
    // the cost of one evaluation is its own row, comparable when the inputs change.
    row!(
        out,
        "| uncertainty: seed 001 Table 2 at both weights, 32 samples | {seconds:.1} s | {inputs} inputs a case, {evaluations} evaluations (a trim, warm-started from the nominal one, and a linearisation) on both cores; 256 samples are 8 times as many: target under 2 minutes |"
    );
    row!(
        out,
        "| uncertainty: one evaluation of that design, wall time on both cores | {:.1} ms | the two cases' time over their {evaluations} evaluations |",
        1e3 * per
    );
    plan_overhead(out, settings);
}

/// The max-weight Table 2 study as a plan on this machine: written, run as one shard (every
/// core), finished; beside the same study run directly. What the plan's own work adds (its
/// checks, each evaluation's results written as it finishes, the shard's file, reading them
/// back); an engine's start and its workers' are measured apart (docs/scaling.md).
fn plan_overhead(out: &Rows, settings: crate::uncertainty::propagate::PropagationSettings) {
    use crate::plan::{self, StudySettings};
    let path = (out.root).join("cases/cierva-table2-vpm-m16-70mph-max-weight.yaml");
    let Ok(case) = crate::suite::case::load(&path) else {
        return out.warn(format!("plan benchmark: {} does not load", path.display()));
    };
    let dir = std::env::temp_dir().join(format!("cierva-bench-plan-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let started = Instant::now();
    let direct = crate::uncertainty::study::propagate(&case, settings, || {});
    let one = started.elapsed().as_secs_f64();
    let started = Instant::now();
    let study = StudySettings {
        samples: settings.samples,
        seed: settings.seed,
        method: settings.method,
        validation_only: settings.validation_only,
    };
    let planned = plan::write(&dir, std::slice::from_ref(&case), &[], study)
        .and_then(|_| plan::load(&dir))
        .and_then(|p| plan::evaluate(&p, (1, 1), || ()).and_then(|_| plan::finish(&p)));
    let seconds = started.elapsed().as_secs_f64();
    let _ = std::fs::remove_dir_all(&dir);
    let json = |u: &crate::uncertainty::propagate::CaseUncertainty| serde_json::to_string(u).ok();
    match (direct, planned) {
        (Ok(d), Ok(p)) if p.len() == 1 && json(&p[0].0) == json(&d) => row!(
            out,
            "| uncertainty as a plan on this machine: the max-weight case at {} samples, written, run as one shard, finished | {seconds:.1} s | the same study run directly {one:.1} s ({:+.0} %); the same numbers |",
            settings.samples,
            100.0 * (seconds / one - 1.0)
        ),
        (Ok(_), Ok(_)) => {
            out.warn("plan benchmark: the plan's study differs from the direct one".into())
        }
        (Err(e), _) => out.warn(format!("plan benchmark: {e}")),
        (_, Err(e)) => out.warn(format!("plan benchmark: {e:?}")),
    }
}

/// The benchmarks' flight test: level flight at `(airspeed mph, control)`, an exponential sweep
/// of that control (0.05-2 Hz over 114 s from 3 s, `amplitude` % of travel), 120 s at 100 Hz,
/// Dryden turbulence of `sigma_m_s` at low altitude (152.4 m), the default instruments and the
/// pilot's hold.
fn sweep_flight(
    (airspeed_mph, control): (f64, usize),
    amplitude: f64,
    sigma_m_s: f64,
    seed: u64,
    azimuth_step_rad: f64,
) -> crate::synth::flight::FlightTest {
    use crate::synth::flight::{FlightTest, sensors::Instrumentation, turbulence};
    use crate::synth::linear::TestInput;
    FlightTest {
        request: crate::inputs::condition::TrimRequest::level(airspeed_mph),
        loading: crate::inputs::condition::Loading {
            mass_kg: None,
            density_altitude_ft: 0.0,
        },
        input: TestInput::ExponentialSweep {
            start_s: 3.0,
            from_hz: 0.05,
            to_hz: 2.0,
            duration_s: 114.0,
            amplitude,
        },
        control,
        duration_s: 120.0,
        sample_rate_hz: 100.0,
        turbulence: turbulence::Dryden::low_altitude(sigma_m_s, 152.4).ok(),
        instrumentation: Instrumentation::default(),
        pilot: true,
        seed,
        azimuth_step_rad,
    }
}

/// A trivial model behind the protocol (Python 3): a trim of two constants, one-shot with a
/// request file's path or persistent with `--serve`.
const TRIVIAL_MODEL: &str = "import json, sys
def body(r):
    return {'trim': {'pitch_deg': 3.0, 'rotor_rpm': 400.0}} if r['compute'] == 'trim' else \\
        {'describe': {'computes': ['trim']}}
if sys.argv[1:] == ['--serve']:
    for line in sys.stdin:
        r = json.loads(line)
        b = body(r); b['protocol'] = r['protocol']; b['id'] = r['id']
        sys.stdout.write(json.dumps(b) + '\\n'); sys.stdout.flush()
else:
    r = json.load(open(sys.argv[1]))
    b = body(r); b['protocol'] = r['protocol']
    open(r['response'], 'w').write(json.dumps(b))
";

/// The protocol's cost a request: a trivial model's trims at distinct airspeeds (so none is
/// answered from memory), one after another, one-shot (a process a request) and persistent
/// (one process, JSON lines). What a request costs beyond the model's own work.
fn external(out: &Rows) -> Result<(), String> {
    use crate::external::command::{ExternalCommand, Protocol};
    use crate::external::{FlightModel as _, Request};
    let dir = std::env::temp_dir().join(format!("cierva-bench-external-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("model.py"), TRIVIAL_MODEL).map_err(|e| e.to_string())?;
    let loading = crate::inputs::condition::Loading {
        mass_kg: None,
        density_altitude_ft: 0.0,
    };
    let per_request = |persistent: bool, requests: usize| -> Result<f64, String> {
        let mut command = vec!["python3".to_string(), "model.py".to_string()];
        if persistent {
            command.push("--serve".into());
        }
        let mut model = ExternalCommand::speaking(
            command,
            dir.clone(),
            std::time::Duration::from_secs(30),
            Protocol::V2,
        );
        if persistent {
            model = model.persistent();
        }
        // The description and the first process's start, outside the timing.
        model.trim(&Request::at(
            crate::inputs::condition::TrimRequest::level(1.0),
            loading,
        ))?;
        let started = Instant::now();
        for k in 0..requests {
            let at = crate::inputs::condition::TrimRequest::level(2.0 + k as f64 * 0.01);
            model.trim(&Request::at(at, loading))?;
        }
        Ok(started.elapsed().as_secs_f64() / requests as f64)
    };
    let persistent = per_request(true, 1000)?;
    let one_shot = per_request(false, 100)?;
    let _ = std::fs::remove_dir_all(&dir);
    row!(
        out,
        "| external: one request in persistent mode, a trivial Python model | {:.0} us | 1000 trims at distinct airspeeds, one after another: the request's JSON line, the model's (Python's json both ways), the answer parsed; target at most 1 ms (issue 49) |",
        persistent * 1e6
    );
    row!(
        out,
        "| external: one request one-shot, the same model | {:.1} ms | 100 trims: a process, a request file and a response file each |",
        one_shot * 1e3
    );
    Ok(())
}
