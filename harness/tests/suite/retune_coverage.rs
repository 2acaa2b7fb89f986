//! The coverage of `cierva retune`'s 95 % intervals, per parameter (issue 32, item 4; issue 51,
//! item 6): known-answer trials whose intervals must hold the truth at their stated rate.
//!
//! Each trial hides the three default corrections (the hub factor, the propeller blockage and
//! the profile-drag scale), drawn anywhere within their default bounds, flies the full
//! individual-blade VPM M16 with them (`cierva synth-flight`: the pilot's attitude hold, Dryden
//! turbulence of 0 to 0.5 m/s, the default instruments) through a longitudinal stick sweep and a
//! throttle sweep at one to three airspeeds, and retunes the uncorrected aircraft from those
//! records. Each parameter is judged alone.
//!
//! Every draw comes from wyrand (the `fastrand` crate) seeded with [`SEED`] and the trial's
//! number: a generator the method was not developed on (its earlier trials drew from SplitMix64
//! with other seeds), so the method was not tuned to these trials.

/// The corrections hidden and retuned, with their default bounds
/// (`cierva_harness::fit::retune::DEFAULT_BOUNDS`).
const HIDDEN: [(&str, f64, f64); 3] = [
    ("hub_aoa_factor", 0.0, 1.0),
    ("propeller_blockage", 0.0, 1.0),
    ("profile_drag_scale", 0.5, 2.0),
];

/// The seed of the trials' generator: issue 51, item 6, written as a number.
const SEED: u64 = 0x0051_0006;

/// Trials, each giving one interval per parameter. At a true coverage of 95 % a parameter's
/// misses are binomial (40, 0.05), mean 2, and the 90-99 % band (36 to 39 of 40 holding the
/// truth, 1 to 4 misses) holds them with probability 0.82; at 85 % (6 misses expected) with
/// probability 0.13. (The band is the issue's; 40 trials keep the test's run in a test build
/// near 8 minutes.)
const TRIALS: u64 = 40;

/// The band for the rate at which each parameter's 95 % intervals hold the truth.
const COVERAGE_BAND: (f64, f64) = (0.90, 0.99);

/// Parameters whose intervals are known to miss the band: the name, the count of the
/// [`TRIALS`] intervals that held the truth when it was measured, and why. Each is a known
/// discrepancy, reported by the test and guarded at its count; the band is not moved for it.
/// A parameter listed here that comes into the band fails the test until it is taken off.
///
/// Before the matched processing (`fit::retune::matched`, 2026-12-01), with the responses
/// estimated against the records' excitations (`ident::frequency_response::referenced`;
/// `cierva synth-flight` records its test input), measured 2026-11-30: the hub factor 36 of 40
/// (the band's floor), the propeller blockage 37, the profile drag 37, none listed. From the
/// controls (the estimator before that, on the same flights) they were 34, 35 and 38. The
/// profile drag's errors leaned high (mean +0.71 standard errors here, +1.06 held back), in
/// calm air as in turbulence: the estimator's bias (its smoothing, leakage and the other
/// controls' transfers), which the matched processing corrects for. With it, measured
/// 2026-12-01 (`.ci/run` on 15a3039): the hub factor 38, the blockage 34, the drag scale 40,
/// the last two listed below with their reasons. Held back (docs/validation.md, 60 trials
/// each) it gives 56, 57 and 56 on seed 7 (55, 50, 50 before) and 53, 47 and 54 on seed 8 (51,
/// 49, 50 before).
const KNOWN_MISSES: [(&str, usize, &str); 2] = [
    (
        "propeller_blockage",
        34,
        "37 of 40 before the matched processing: a worse count accepted because the matched \
         processing removes a bias shown on known answers (the drag scale's), and over this \
         test and the 120 held-back trials the blockage holds 138 of 160 with it against 136 \
         without; its misses are errors its standard errors do not carry, in calm air as in \
         turbulence (seed 8: 53 of 60 calm, 47 in turbulence); one missed condition flown \
         again 12 times gives the same wrong blockage each time (scatter a seventh of its \
         standard error, error 2.6 standard errors): cierva's own model reduction, the difference \
         between the individual blades flown and the flapping linearisation fitted, which \
         the blockage absorbs (flown by that linearisation instead, seed 8's 60 calm trials \
         hold it 59 times; reports/investigations.md, \"Where the blockage's misses come \
         from\"; issue 51, item 6, open until the reduction is taken out)",
    ),
    (
        "profile_drag_scale",
        40,
        "above the band (40 of 40; at a true 95 % that comes with probability 0.13), since the \
         matched processing took out its high lean; held back it holds 56 and 54 of 60, \
         inside the band: listed until more trials tell wide intervals from chance",
    ),
];

/// Airspeeds a trial picks from, mph: the VPM M16's cruise range (seed 001 flew 30-70 mph).
const AIRSPEEDS_MPH: [u32; 3] = [50, 60, 70];

/// The stick sweep's amplitude, % of travel.
const SWEEP_PERCENT: &str = "3";

/// The throttle sweep's amplitude, % of travel: the test's choice, enough for the propeller's
/// thrust to give coherent responses of `u`, `w`, `q` and the rotor speed over the band.
const THROTTLE_SWEEP_PERCENT: &str = "5";

/// The most turbulence a trial flies in, sigma_w m/s (the range: 0 to 0.5).
const TURBULENCE_MAX_M_S: f64 = 0.5;

/// One trial's outcome: each parameter's truth, value, standard error and whether its 95 %
/// interval holds the truth.
#[derive(Debug)]
struct Outcome {
    trial: u64,
    speeds: Vec<u32>,
    turbulence_m_s: f64,
    parameters: Vec<Judged>,
    reduced_chi_square: f64,
    status: String,
}

/// One parameter of one trial.
#[derive(Debug)]
struct Judged {
    name: String,
    truth: f64,
    value: f64,
    se: f64,
    held: bool,
    one_sided: bool,
}

/// Flies one trial's records and retunes from them; `Err` with the reason when
/// the hidden aircraft cannot be flown (it will not trim within the controls' travel, or the
/// flight diverges): such a draw is no trial, as no flight test flies it.
fn trial(n: u64, dir: &std::path::Path) -> Result<Outcome, String> {
    let mut rng = fastrand::Rng::with_seed(SEED.wrapping_mul(1_000_003).wrapping_add(n));
    let truth: Vec<(String, f64)> = HIDDEN
        .iter()
        .map(|(name, lo, hi)| (name.to_string(), lo + (hi - lo) * rng.f64()))
        .collect();
    let turbulence = TURBULENCE_MAX_M_S * rng.f64();
    let count = rng.usize(1..=3);
    let first = rng.usize(0..3);
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
        for (control, amplitude) in [("eta_s", SWEEP_PERCENT), ("eta_t", THROTTLE_SWEEP_PERCENT)] {
            let out = dir.join(format!("{control}-{v}.csv"));
            let (speed, sigma, seed) = (
                v.to_string(),
                format!("{turbulence:.4}"),
                rng.u32(1..u32::MAX).to_string(),
            );
            let (code, stdout, stderr) = super::common::synth_sweep(
                &out, control, &speed, amplitude, &sigma, &seed, &secret,
            );
            if code != 0 {
                return Err(format!(
                    "trial {n} at {v} mph ({control}): {stdout}{stderr}"
                ));
            }
            records.push(out);
        }
    }
    let paths: Vec<&std::path::Path> = records.iter().map(|p| p.as_path()).collect();
    let names: Vec<&str> = HIDDEN.iter().map(|h| h.0).collect();
    let (code, stdout, stderr) = super::common::retune_corrections(&dir, &paths, &names, &[]);
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
                let interval = &v["intervals_95"][&k];
                let (lo, hi) = (interval["lower"].as_f64(), interval["upper"].as_f64());
                // NaN never passes: an interval that is not stated does not hold the truth.
                let held = converged && lo.zip(hi).is_some_and(|(lo, hi)| (lo..=hi).contains(&t));
                Judged {
                    value: v["corrections"][&k].as_f64().unwrap_or(f64::NAN),
                    se: v["standard_errors"][&k].as_f64().unwrap_or(f64::NAN),
                    one_sided: interval["one_sided"].as_bool().unwrap_or(false),
                    name: k,
                    truth: t,
                    held,
                }
            })
            .collect(),
        reduced_chi_square: v["reduced_chi_square"].as_f64().unwrap_or(f64::NAN),
        status: v["status"].as_str().unwrap_or("").to_string(),
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
    let dir = crate::common::scratch("retune-coverage");
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
    let mut table = String::from(
        "trial speeds turbulence chi2_red status | parameter truth value se error_in_se held\n",
    );
    let mut per: Vec<(String, usize, usize)> =
        HIDDEN.iter().map(|h| (h.0.to_string(), 0, 0)).collect();
    for o in outcomes {
        for (k, j) in o.parameters.iter().enumerate() {
            per[k].1 += 1;
            per[k].2 += usize::from(j.held);
            table += &format!(
                "{} {:?} {:.3} {:.2} {} | {} {:.4} {:.4} {:.4} {:+.2} {}{}\n",
                o.trial,
                o.speeds,
                o.turbulence_m_s,
                o.reduced_chi_square,
                o.status,
                j.name,
                j.truth,
                j.value,
                j.se,
                (j.value - j.truth) / j.se,
                if j.held { "held" } else { "MISSED" },
                if j.one_sided { " (one-sided)" } else { "" }
            );
        }
    }
    (per, table)
}

#[test]
#[ignore = "slow coverage test (40 trials of two to six synthetic flights and a retune; about 8 minutes in a test build): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn retune_intervals_hold_the_truth_at_their_stated_rate_per_parameter() {
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
    eprintln!("{table}");
    let mut failures = Vec::new();
    for (name, n, held) in &per {
        let rate = *held as f64 / *n as f64;
        let inside = (COVERAGE_BAND.0..=COVERAGE_BAND.1).contains(&rate);
        let known = KNOWN_MISSES.iter().find(|k| k.0 == name);
        eprintln!(
            "{name}: {held} of {n} intervals hold the truth ({rate:.3}){}",
            match (inside, known) {
                (true, _) => String::new(),
                (false, Some((_, _, why))) => format!(
                    ": MISSES the issue's band {COVERAGE_BAND:?}, a known discrepancy ({why})"
                ),
                (false, None) => format!(": MISSES the issue's band {COVERAGE_BAND:?}"),
            }
        );
        match known {
            None if !inside => failures.push(format!("{name} {held} of {n} ({rate:.3})")),
            Some((_, measured, _)) if !inside && held < measured => failures.push(format!(
                "{name} {held} of {n}, below its known discrepancy's {measured}"
            )),
            Some(_) if inside => failures.push(format!(
                "{name} {held} of {n} is inside the band now: take it off KNOWN_MISSES"
            )),
            _ => {}
        }
    }
    assert!(
        failures.is_empty(),
        "the issue's band is {COVERAGE_BAND:?}: {}\n{table}",
        failures.join("; ")
    );
}
