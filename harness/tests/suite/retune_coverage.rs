//! The coverage of `cierva retune`'s standard errors (issue 32, item 4): known-answer trials
//! whose 95 % intervals must hold the truth at their stated rate.
//!
//! Each trial hides corrections drawn anywhere within their default bounds, flies the full
//! individual-blade VPM M16 with them (`cierva synth-flight`: the pilot's attitude hold,
//! Dryden turbulence of 0 to 0.5 m/s, the default instruments) through a longitudinal stick
//! sweep at one to three airspeeds, and retunes the uncorrected aircraft from those records.
//! Every draw is seeded from the trial's number.

use super::common::SplitMix;

/// The corrections hidden and retuned, with their default bounds
/// (`cierva_harness::fit::retune::DEFAULT_BOUNDS`, the README's retune example's pair).
const HIDDEN: [(&str, f64, f64); 2] = [
    ("hub_aoa_factor", 0.0, 1.0),
    ("profile_drag_scale", 0.5, 2.0),
];

/// Trials. With 2 parameters each, 60 intervals: at a true coverage of 95 % the misses are
/// binomial (60, 0.05), mean 3, and the 90-99 % band (54 to 59 intervals holding the truth, 1
/// to 6 misses) holds them with probability 0.92 (P(misses <= 6) = 0.970 less P(0) = 0.046);
/// at a true coverage of 85 % (9 misses expected) the band holds with probability 0.18, at
/// 99.5 % (0.3 expected) 0.26. (Intervals of one trial share its records, so the misses are
/// not quite independent; the band is the issue's.)
const TRIALS: u64 = 30;

/// The band for the rate at which the 95 % intervals hold the truth.
const COVERAGE_BAND: (f64, f64) = (0.90, 0.99);

/// Airspeeds a trial picks from, mph: the VPM M16's cruise range (seed 001 flew 30-70 mph).
const AIRSPEEDS_MPH: [u32; 3] = [50, 60, 70];

/// The stick sweep's amplitude, % of travel.
const SWEEP_PERCENT: &str = "3";

/// The most turbulence a trial flies in, sigma_w m/s (the range: 0 to 0.5).
const TURBULENCE_MAX_M_S: f64 = 0.5;

/// One trial's outcome: each parameter's truth, value and standard error.
#[derive(Debug)]
struct Outcome {
    trial: u64,
    speeds: Vec<u32>,
    turbulence_m_s: f64,
    parameters: Vec<(String, f64, f64, f64)>,
    reduced_chi_square: f64,
}

/// Flies one trial's records and retunes from them; `Err` with the reason when
/// the hidden aircraft cannot be flown (it will not trim within the controls' travel, or the
/// flight diverges): such a draw is no trial, as no flight test flies it.
fn trial(n: u64, dir: &std::path::Path) -> Result<Outcome, String> {
    let mut rng = SplitMix(0xC0FE_0032 ^ n.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    let truth: Vec<(String, f64)> = HIDDEN
        .iter()
        .map(|(name, lo, hi)| (name.to_string(), rng.uniform(*lo, *hi)))
        .collect();
    let turbulence = rng.uniform(0.0, TURBULENCE_MAX_M_S);
    let count = 1 + (rng.uniform(0.0, 3.0) as usize).min(2);
    let first = rng.uniform(0.0, 3.0) as usize % 3;
    let speeds: Vec<u32> = (0..count).map(|k| AIRSPEEDS_MPH[(first + k) % 3]).collect();
    let dir = dir.join(format!("trial-{n}"));
    std::fs::create_dir_all(&dir).unwrap();
    let secret = super::common::hidden_corrections(
        &dir,
        &truth,
        "a coverage trial's corrections",
        "test: drawn by the coverage test",
    );
    let mut records = Vec::new();
    for v in &speeds {
        let out = dir.join(format!("lon-{v}.csv"));
        let (speed, sigma, seed) = (
            v.to_string(),
            format!("{turbulence:.4}"),
            (1000 * n + u64::from(*v)).to_string(),
        );
        let (code, stdout, stderr) =
            super::common::synth_stick_sweep(&out, &speed, SWEEP_PERCENT, &sigma, &seed, &secret);
        if code != 0 {
            return Err(format!("trial {n} at {v} mph: {stdout}{stderr}"));
        }
        records.push(out.to_str().unwrap().to_string());
    }
    let paths: Vec<&std::path::Path> = records.iter().map(std::path::Path::new).collect();
    let (code, stdout, stderr) = super::common::retune_hub_and_drag(&dir, &paths, &[]);
    assert_eq!(code, 0, "trial {n}: {stdout}{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    // A fit that did not converge states no interval: its parameters count as not held.
    let converged = v["status"] == "converged";
    Ok(Outcome {
        trial: n,
        speeds,
        turbulence_m_s: turbulence,
        parameters: truth
            .into_iter()
            .map(|(k, t)| {
                let value = if converged {
                    v["corrections"][&k].as_f64().unwrap_or(f64::NAN)
                } else {
                    f64::NAN
                };
                let se = v["standard_errors"][&k].as_f64().unwrap_or(f64::NAN);
                (k, t, value, se)
            })
            .collect(),
        reduced_chi_square: v["reduced_chi_square"].as_f64().unwrap_or(f64::NAN),
    })
}

/// Most draws tried for [`TRIALS`] trials: a draw the aircraft cannot fly is passed over (its
/// reason printed), and more than this many means the bounds are mostly unflyable.
const MAX_DRAWS: u64 = 3 * TRIALS;

/// The first [`TRIALS`] draws that fly, retuned two at a time (each retune runs
/// its conditions on both cores), and the draws passed over. Draws are taken in order, so the
/// trials are the same whichever worker runs them.
fn trials() -> (Vec<Outcome>, Vec<String>) {
    use std::sync::atomic::{AtomicU64, Ordering};
    let dir = std::env::temp_dir().join(format!("cierva-retune-coverage-{}", std::process::id()));
    let (next, flown) = (AtomicU64::new(0), AtomicU64::new(0));
    let results: Vec<(u64, Result<Outcome, String>)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    while flown.load(Ordering::SeqCst) < TRIALS {
                        let n = next.fetch_add(1, Ordering::SeqCst);
                        if n >= MAX_DRAWS {
                            break;
                        }
                        let r = trial(n, &dir);
                        if r.is_ok() {
                            flown.fetch_add(1, Ordering::SeqCst);
                        }
                        mine.push((n, r));
                    }
                    mine
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap())
            .collect()
    });
    let mut results = results;
    results.sort_by_key(|(n, _)| *n);
    let (mut out, mut passed_over) = (Vec::new(), Vec::new());
    for (_, r) in results {
        if out.len() == TRIALS as usize {
            break;
        }
        match r {
            Ok(o) => out.push(o),
            Err(e) => passed_over.push(e),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    (out, passed_over)
}

/// Per parameter: intervals, how many hold the truth, and a table of every trial.
fn coverage(outcomes: &[Outcome]) -> (Vec<(String, usize, usize)>, String) {
    let mut table =
        String::from("trial speeds turbulence chi2_red | parameter truth value se error_in_se\n");
    let mut per: Vec<(String, usize, usize)> =
        HIDDEN.iter().map(|h| (h.0.to_string(), 0, 0)).collect();
    for o in outcomes {
        for (k, (name, truth, value, se)) in o.parameters.iter().enumerate() {
            let z = (value - truth) / se;
            // NaN never passes: an interval that is not finite does not hold the truth.
            let held = z.is_finite() && z.abs() <= 1.96;
            per[k].1 += 1;
            per[k].2 += usize::from(held);
            table += &format!(
                "{} {:?} {:.3} {:.2} | {name} {truth:.4} {value:.4} {se:.4} {z:+.2}\n",
                o.trial, o.speeds, o.turbulence_m_s, o.reduced_chi_square
            );
        }
    }
    (per, table)
}

/// The 95 % intervals against the truth: inside the band, 90-99 % ([`COVERAGE_BAND`]).
/// Measured 2026-11-26 with the wake skew in seed 003's modulus form (issue 33, item 4): 54 of
/// 60 (0.90, the band's edge; the hub factor 25 of 30, the profile drag 29 of 30); with the
/// signed form 56 of 60 (0.93; 27 and 29), the errors' mean +0.75 and spread 0.78 standard
/// errors. (The derivatives' method, removed, held 18 of 60 with the signed form and 50, 0.83,
/// with the modulus form: below the band either way.)
#[test]
#[ignore = "slow coverage test (30 trials of one to three synthetic flights and a retune; about 3 minutes in a test build): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn retune_intervals_hold_the_truth_at_their_stated_rate() {
    let (outcomes, passed_over) = trials();
    for p in &passed_over {
        eprintln!(
            "passed over (not flyable): {}",
            p.lines().next().unwrap_or("")
        );
    }
    assert_eq!(
        outcomes.len(),
        TRIALS as usize,
        "only {} of {MAX_DRAWS} draws flew",
        outcomes.len()
    );
    let (per, table) = coverage(&outcomes);
    let (n, held) = per
        .iter()
        .fold((0, 0), |(n, h), (_, pn, ph)| (n + pn, h + ph));
    let rate = held as f64 / n as f64;
    eprintln!("{table}");
    for (name, pn, ph) in &per {
        eprintln!("{name}: {ph} of {pn} intervals hold the truth");
    }
    assert!(
        (COVERAGE_BAND.0..=COVERAGE_BAND.1).contains(&rate),
        "{held} of {n} intervals ({rate:.3}) hold the truth, outside the issue's band {COVERAGE_BAND:?}:\n{table}"
    );
}
