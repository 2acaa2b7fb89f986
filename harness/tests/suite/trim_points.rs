//! `trim_points` checks (issue 50): flight trim points with scatter, each trimmed again, the
//! model's error judged as a level and a trend together. Known answers: the statistic's stated
//! rate on many seeded synthetic truths; a synthetic flight test of cierva's VPM M16 (its own
//! trims plus seeded scatter) that the right model passes and a wrong trend fails, read from a
//! file in other units with extra columns; a trim table interpolated between its rows.

use super::common::{SplitMix, cierva_in, new_suite, repo_root};
use cierva_harness::checks::trim_points::LevelAndTrend;
use cierva_harness::external::{FlightModel as _, Request};
use cierva_harness::inputs::condition::{Loading, TrimRequest};
use cierva_harness::inputs::trim_points::PointValue;

/// The 95 % quantile of chi-square with 2 degrees of freedom: `-2 ln 0.05`.
const CHI2_2_95: f64 = 5.991_464_547_107_979;

/// How far a pass rate over `n` seeded trials may stray from its stated value `p`: four binomial
/// standard deviations (the seeds are fixed, so the test is deterministic; a rate this far off
/// would be a wrong statistic, not chance).
fn binomial_band(p: f64, n: usize) -> f64 {
    4.0 * (p * (1.0 - p) / n as f64).sqrt()
}

/// Seeded trim points about a truth `truth(v)`: airspeeds spread over 35-75 mph, each point's
/// scatter drawn between 0.5 and 2 (its stated standard deviation), its value the truth plus
/// that scatter.
fn points(rng: &mut SplitMix, n: usize, truth: impl Fn(f64) -> f64) -> Vec<(f64, PointValue)> {
    (0..n)
        .map(|_| {
            let v = rng.uniform(35.0, 75.0);
            let sd = rng.uniform(0.5, 2.0);
            (
                v,
                PointValue {
                    value: truth(v) + sd * rng.normal(),
                    sd,
                },
            )
        })
        .collect()
}

/// Where the model is the truth, the level-and-trend statistic stays within its 95 % quantile
/// at 95 % (4,000 seeds of 4 to 12 points), each standard error covers its error at 95 %, and
/// the residual chi-square averages its `n - 2` degrees of freedom. A model whose trend is off
/// by four of its standard deviations is caught at least 90 % of the time (noncentral
/// chi-square with 2 dof and noncentrality 16 exceeds 5.991 with probability 0.957).
#[test]
fn the_level_and_trend_statistic_holds_its_stated_rate() {
    let truth = |v: f64| 80.0 - 0.5 * v;
    let trials = 4_000;
    let (mut within, mut level_covered, mut trend_covered) = (0, 0, 0);
    let (mut residual, mut dof) = (0.0, 0usize);
    let mut caught = 0;
    for seed in 0..trials {
        let mut rng = SplitMix(0x7121_0000 + seed as u64);
        let n = 4 + seed % 9;
        let pts = points(&mut rng, n, truth);
        let model: Vec<f64> = pts.iter().map(|(v, _)| truth(*v)).collect();
        let f = LevelAndTrend::fit(&pts, &model);
        within += usize::from(f.level_trend_chi2 <= CHI2_2_95);
        level_covered += usize::from(f.level.abs() <= 1.959_964 * f.level_sd);
        trend_covered += usize::from(f.trend_per_mph.abs() <= 1.959_964 * f.trend_sd);
        residual += f.residual_chi2;
        dof += f.residual_dof;
        // The same points against a model whose trend is wrong by 4 of its standard deviations.
        let wrong: Vec<f64> = pts
            .iter()
            .map(|(v, _)| truth(*v) + 4.0 * f.trend_sd * (v - f.airspeed_mph))
            .collect();
        caught += usize::from(LevelAndTrend::fit(&pts, &wrong).level_trend_chi2 > CHI2_2_95);
    }
    let rate = |k: usize| k as f64 / trials as f64;
    let band = binomial_band(0.95, trials);
    for (what, k) in [
        ("level and trend", within),
        ("level", level_covered),
        ("trend", trend_covered),
    ] {
        assert!(
            (rate(k) - 0.95).abs() <= band,
            "{what}: {:.4} of {trials} within the 95 % bound",
            rate(k)
        );
    }
    // The mean of a sum of `dof` chi-square(1) terms is `dof`, its sd sqrt(2 dof).
    let mean_sd = (2.0 * dof as f64).sqrt();
    assert!(
        (residual - dof as f64).abs() <= 4.0 * mean_sd,
        "residual chi-square {residual:.1} over {dof} dof"
    );
    assert!(
        rate(caught) >= 0.90,
        "a 4-sd trend error caught {:.3}",
        rate(caught)
    );
}

/// The VPM M16 as cierva trims it at 450 kg, sea level: a synthetic flight test's truth.
fn vpm_m16_trims(airspeeds: &[f64]) -> Vec<(f64, f64)> {
    let file =
        cierva_harness::inputs::aircraft::load(&repo_root().join("aircraft/vpm-m16.yaml")).unwrap();
    let model = cierva_harness::external::CiervaAircraft::new(&file);
    airspeeds
        .iter()
        .map(|&v| {
            let q = model
                .trim(&Request::at(
                    TrimRequest::level(v),
                    Loading {
                        mass_kg: Some(450.0),
                        density_altitude_ft: 0.0,
                    },
                ))
                .unwrap();
            let get = |n: &str| q.iter().find(|(m, _)| *m == n).unwrap().1;
            (get("stick_longitudinal_percent"), get("pitch_deg"))
        })
        .collect()
}

/// A suite with a case of the VPM M16 and a file of trim points as a flight test gives them:
/// airspeed in knots under the logger's own name (mapped in the sidecar), pitch in radians, an
/// outside air temperature cierva does not compare, a rotor speed read at two points (too few
/// for a trend, and no expectation judges it). `stick_error_per_mph` is added to the
/// truth's stick trend about 55 mph (a model whose trend is that much off).
fn flight_test_suite(name: &str, stick_error_per_mph: f64) -> std::path::PathBuf {
    let dir = crate::common::scratch(&format!("trim-points-{name}"));
    new_suite(&dir);
    std::os::unix::fs::symlink(repo_root().join("aircraft"), dir.join("aircraft")).unwrap();
    std::fs::create_dir_all(dir.join("flight-refs")).unwrap();
    let airspeeds: Vec<f64> = (0..9).map(|k| 35.0 + 5.0 * k as f64).collect();
    let truth = vpm_m16_trims(&airspeeds);
    let mut rng = SplitMix(20261128);
    let (sd_stick, sd_pitch_deg) = (1.5, 0.5);
    let mut csv = String::from(
        "IAS_KT,stick_longitudinal_percent,sd_stick_longitudinal_percent,pitch_rad,sd_pitch_rad,oat_c,rotor_rpm,sd_rotor_rpm\n",
    );
    for (k, (v, (stick, pitch))) in airspeeds.iter().zip(&truth).enumerate() {
        let stick = stick + stick_error_per_mph * (v - 55.0) + sd_stick * rng.normal();
        let pitch = pitch + sd_pitch_deg * rng.normal();
        csv.push_str(&format!(
            "{},{stick},{sd_stick},{},{},14,{}\n",
            v * 1609.344 / 1852.0,
            pitch.to_radians(),
            sd_pitch_deg.to_radians(),
            // Rotor speed read at two points only: carried along, judged by no expectation.
            if k < 2 { "420,4" } else { "," }
        ));
    }
    std::fs::write(dir.join("flight-refs/vpm-m16-trim-points.csv"), csv).unwrap();
    std::fs::write(
        dir.join("flight-refs/vpm-m16-trim-points.yaml"),
        "id: vpm-m16-trim-points\ntitle: synthetic trim points of the VPM M16\n\
         provenance: {source: \"synthetic: harness/tests/suite/trim_points.rs, SplitMix seed \
         20261128, cierva's own trims plus scatter\"}\n\
         aircraft: VPM M16\nchannels: {IAS_KT: airspeed_kn}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("cases/trim-points.yaml"),
        "id: trim-points\ntitle: VPM M16 against a synthetic flight test's trim points\n\
         class: verification\n\
         provenance: {source: \"synthetic: flight-refs/vpm-m16-trim-points\"}\n\
         model:\n  aircraft:\n    file: ../aircraft/vpm-m16.yaml\n    mass_kg: 450.0\n\
         checks:\n  - id: stick-and-pitch\n    kind: trim_points\n\
         \x20   points: ../flight-refs/vpm-m16-trim-points.csv\n    expect:\n\
         \x20     stick_longitudinal_percent.level_trend_chi2: {tolerance: chi2-2dof-95}\n\
         \x20     pitch_deg.level_trend_chi2: {tolerance: chi2-2dof-95}\n",
    )
    .unwrap();
    dir
}

/// The right model passes its synthetic flight test; a stick trend off by 0.2 % per mph (five
/// of the points' trend standard deviations, 1.5 / sqrt(sum (v - 55)^2) = 0.039) fails it. The
/// report draws the points with their scatter and the model at each, and says how it read the
/// file (the column it mapped, the one it did not compare).
#[test]
fn a_synthetic_flight_test_passes_the_right_trend_and_fails_a_wrong_one() {
    for (name, error, passes) in [("right", 0.0, true), ("wrong", 0.2, false)] {
        let dir = flight_test_suite(name, error);
        let (code, out, err) = cierva_in(&dir, &["validate", "--no-report", "--format", "json"]);
        let v: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|e| {
            panic!("{e}: {out}{err}");
        });
        let r = &v["results"][0];
        assert!(r["error"].is_null(), "{r}");
        let chi2 = |q: &str| {
            r["quantities"]
                .as_array()
                .unwrap()
                .iter()
                .find(|x| x["quantity"] == format!("{q}.level_trend_chi2"))
                .unwrap()["value"]
                .as_f64()
                .unwrap()
        };
        assert_eq!(r["passed"].as_bool(), Some(passes), "{name}: {r}");
        assert_eq!(code, if passes { 0 } else { 1 }, "{out}{err}");
        assert!(chi2("pitch_deg") <= CHI2_2_95, "{r}");
        if !passes {
            assert!(chi2("stick_longitudinal_percent") > CHI2_2_95, "{r}");
        } else {
            // The report draws each quantity: the points with their 95 % scatter, the model.
            let (_, out, err) = cierva_in(&dir, &["validate"]);
            let html = std::fs::read_to_string(dir.join("reports/index.html"))
                .unwrap_or_else(|e| panic!("{e}: {out}{err}"));
            for q in ["stick_longitudinal_percent", "pitch_deg"] {
                assert!(
                    html.contains(&format!(
                        "stick-and-pitch: {q} at the flight test&#39;s trim points"
                    )) || html.contains(&format!(
                        "stick-and-pitch: {q} at the flight test's trim points"
                    )),
                    "no figure of {q}"
                );
            }
            assert!(html.contains("flight point (95 % of its scatter)"));
            // And says how it read the file: the column it mapped, the one it did not compare.
            assert!(
                html.contains("Data as read.")
                    && html.contains("<code>flight-refs/vpm-m16-trim-points.csv</code>")
                    && html.contains("column `IAS_KT` read as `airspeed_kn`")
                    && html.contains("or another unit of a column it reads): `oat_c`"),
                "{}",
                &html[html.find("Data as read").unwrap_or(0)..][..600.min(html.len())]
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// A check a constant trim passes is refused at load (only a level judged); a quantity without
/// its scatter, a scatter of zero, misspelt columns, a point's mass above the aircraft's maximum
/// and a point outside the model's envelope are errors that name the file, line and column or
/// the point.
#[test]
fn trim_points_a_constant_passes_or_that_are_malformed_are_refused() {
    let dir = flight_test_suite("refused", 0.0);
    let case = dir.join("cases/trim-points.yaml");
    let text = std::fs::read_to_string(&case).unwrap();
    let level_only =
        text.replace(
            "stick_longitudinal_percent.level_trend_chi2: {tolerance: chi2-2dof-95}",
            "stick_longitudinal_percent.level_error: {value: 0.0, tolerance: level}",
        )
        .replace(
            "      pitch_deg.level_trend_chi2: {tolerance: chi2-2dof-95}\n",
            "",
        ) + "tolerances:\n  level:\n    absolute: 3.0\n    reason: the test's own\n";
    std::fs::write(&case, level_only).unwrap();
    let e = cierva_harness::suite::case::load(&case)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("checks[0].expect.stick_longitudinal_percent.level_error")
            && e.contains("cannot tell the model from a constant"),
        "{e}"
    );
    std::fs::write(&case, &text).unwrap();

    let csv_path = dir.join("flight-refs/vpm-m16-trim-points.csv");
    let csv = std::fs::read_to_string(&csv_path).unwrap();
    let mut lines: Vec<String> = csv.lines().map(String::from).collect();
    for (edit, says) in [
        (
            (0, "sd_pitch_rad", "sd_pitch_x"),
            "`pitch_deg` has no scatter: give `sd_pitch_deg`",
        ),
        ((3, ",1.5,", ",0,"), "trim-points.csv:4:"),
        ((0, "pitch_rad,", "pitch_rda,"), "did you mean `pitch_rad`"),
        ((0, "oat_c", "mass_lbs"), "did you mean `mass_lb`"),
    ] {
        let (row, from, to) = edit;
        let mut bad = lines.clone();
        bad[row] = bad[row].replacen(from, to, 1);
        std::fs::write(&csv_path, bad.join("\n") + "\n").unwrap();
        let e = cierva_harness::suite::case::load(&case)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("checks[0].points") && e.contains(says),
            "{edit:?}: {e}"
        );
    }
    // A point's mass above the aircraft's maximum all-up mass: refused at load, at its line.
    let mut heavy = lines.clone();
    heavy[0] = heavy[0].replacen("oat_c", "mass_kg", 1);
    for (k, row) in heavy.iter_mut().enumerate().skip(1) {
        *row = row.replacen(",14,", if k == 3 { ",992," } else { ",450," }, 1);
    }
    std::fs::write(&csv_path, heavy.join("\n") + "\n").unwrap();
    let e = cierva_harness::suite::case::load(&case)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("checks[0].points")
            && e.contains("vpm-m16-trim-points.csv:4: 992 kg is above the maximum all-up mass"),
        "{e}"
    );
    // A point at 400 kn: beyond what the aircraft can trim.
    lines[5] = lines[5].replacen(lines[5].split(',').next().unwrap(), "400", 1);
    std::fs::write(&csv_path, lines.join("\n") + "\n").unwrap();
    let (_, out, _) = cierva_in(&dir, &["validate", "--no-report"]);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        out.contains("trim-points.csv:6 (460.3") && out.contains("is outside the model's envelope"),
        "{out}"
    );
}

/// A trim table (`model: files:`) answers between its rows by linear interpolation, exactly
/// at a row, and refuses beyond them, naming the rows it has.
#[test]
fn a_trim_table_is_interpolated_between_its_rows_never_beyond() {
    let rows = vec![
        (40.0, vec![("pitch_deg", 10.0), ("rotor_rpm", 400.0)]),
        (60.0, vec![("pitch_deg", 4.0), ("rotor_rpm", 420.0)]),
    ];
    let mid = cierva_harness::external::files::interpolated(&rows, 45.0).unwrap();
    assert_eq!(mid, vec![("pitch_deg", 8.5), ("rotor_rpm", 405.0)]);
    assert_eq!(
        cierva_harness::external::files::interpolated(&rows, 60.0).unwrap(),
        rows[1].1
    );
    assert!(cierva_harness::external::files::interpolated(&rows, 61.0).is_none());
    assert!(cierva_harness::external::files::interpolated(&rows, 39.0).is_none());
}
