//! Known answers for `cierva uncertainty`'s parts (`cierva_harness::uncertainty`): the Sobol'
//! indices of the Ishigami function, propagation through a linear model of Gaussian inputs, the
//! distributions' quantiles, the design, and the verdicts of V&V 20.

use super::common::SplitMix;
use cierva_harness::uncertainty::design::Design;
use cierva_harness::uncertainty::distribution::InputDistribution;
use cierva_harness::uncertainty::propagate::{mean_std, percentile};
use cierva_harness::uncertainty::sobol;
use cierva_harness::uncertainty::vv20::{self, Vv20Verdict};
use std::f64::consts::PI;

/// Values of `f` at every point of a design whose unit points are mapped through `dists`.
fn evaluate(design: &Design, dists: &[InputDistribution], f: impl Fn(&[f64]) -> f64) -> Vec<f64> {
    design
        .points()
        .iter()
        .map(|u| {
            let x: Vec<f64> = dists.iter().zip(u).map(|(d, &u)| d.quantile(u)).collect();
            f(&x)
        })
        .collect()
}

/// A test function of the inputs.
type Model = fn(&[f64]) -> f64;

/// The Ishigami function (a = 7, b = 0.1) on [-pi, pi]^3, whose indices are known in closed form
/// (Ishigami and Homma 1990; Saltelli et al. 2010 use it): with V = a^2/8 + b pi^4/5 +
/// b^2 pi^8/18 + 1/2, V1 = (1 + b pi^4/5)^2 / 2, V2 = a^2/8, V13 = b^2 pi^8 (1/18 - 1/50).
/// The function, its variance, and its first-order and total indices.
fn ishigami() -> (Model, f64, [f64; 3], [f64; 3]) {
    const A: f64 = 7.0;
    const B: f64 = 0.1;
    let v1 = 0.5 * (1.0 + B * PI.powi(4) / 5.0).powi(2);
    let v2 = A * A / 8.0;
    let v13 = B * B * PI.powi(8) * (1.0 / 18.0 - 1.0 / 50.0);
    let v = v1 + v2 + v13;
    let f = |x: &[f64]| x[0].sin() + A * x[1].sin().powi(2) + B * x[2].powi(4) * x[0].sin();
    (
        f,
        v,
        [v1 / v, v2 / v, 0.0],
        [(v1 + v13) / v, v2 / v, v13 / v],
    )
}

/// The Ishigami function's inputs: uniform on [-pi, pi].
const ISHIGAMI_INPUT: InputDistribution = InputDistribution::Uniform {
    lower: -PI,
    upper: PI,
};

/// The Ishigami indices within 0.02 of the closed form at 4096 base points.
#[test]
fn the_ishigami_indices_come_within_0_02_of_the_analytic_values() {
    let (f, v, first, total) = ishigami();
    let uniform = ISHIGAMI_INPUT;
    // Several seeds: the answer must hold for the sequence, not one lucky scramble.
    for seed in [0, 1, 7, 42, 1234] {
        let design = Design::sobol(4096, 3, seed).unwrap();
        let y = evaluate(&design, &[uniform; 3], f);
        let (fa, fb, fab) = design.split(&y);
        let e = sobol::estimate(fa, fb, &fab).unwrap();
        assert!(
            (e.variance - v).abs() < 0.02 * v,
            "seed {seed}: V {} against {v}",
            e.variance
        );
        for i in 0..3 {
            assert!(
                (e.indices[i].first - first[i]).abs() < 0.02,
                "seed {seed}: S_{} = {} against {}",
                i + 1,
                e.indices[i].first,
                first[i]
            );
            assert!(
                (e.indices[i].total - total[i]).abs() < 0.02,
                "seed {seed}: S_T{} = {} against {}",
                i + 1,
                e.indices[i].total,
                total[i]
            );
        }
    }
}

/// `y = c0 + sum c_i x_i` with independent normal inputs: mean `c0 + sum c_i mu_i`, variance
/// `sum c_i^2 sigma_i^2`, first-order and total index of input `i` both `c_i^2 sigma_i^2 / V`,
/// and the 2.5 and 97.5 percentiles at the mean -+ 1.96 standard deviations.
#[test]
fn propagation_through_a_linear_model_of_gaussian_inputs_gives_the_analytic_moments() {
    let (dists, f, shares) = linear_gaussian();
    let (mean, var) = linear_moments();
    for seed in [3, 11, 99] {
        let design = Design::sobol(1024, 4, seed).unwrap();
        let y = evaluate(&design, &dists, f);
        let sample = &y[..2 * design.n];
        let (m, s) = mean_std(sample);
        let n = sample.len() as f64;
        // Three standard errors of plain Monte Carlo: the Sobol' points do better.
        assert!(
            (m - mean).abs() < 3.0 * var.sqrt() / n.sqrt(),
            "seed {seed}: mean {m} against {mean}"
        );
        assert!(
            (s * s - var).abs() < 3.0 * var * (2.0 / n).sqrt(),
            "seed {seed}: variance {} against {var}",
            s * s
        );
        let (lo, hi) = (percentile(sample, 2.5), percentile(sample, 97.5));
        let z = 1.959_963_985;
        for (got, want) in [(lo, mean - z * var.sqrt()), (hi, mean + z * var.sqrt())] {
            assert!(
                (got - want).abs() < 0.05 * var.sqrt(),
                "seed {seed}: percentile {got} against {want}"
            );
        }
        let (fa, fb, fab) = design.split(&y);
        let e = sobol::estimate(fa, fb, &fab).unwrap();
        for (i, &share) in shares.iter().enumerate() {
            assert!(
                (e.indices[i].first - share).abs() < 0.02,
                "seed {seed}: S_{i} {} against {share}",
                e.indices[i].first
            );
            assert!(
                (e.indices[i].total - share).abs() < 0.02,
                "seed {seed}: S_T{i} {} against {share}",
                e.indices[i].total
            );
        }
    }
}

/// Each distribution's sampled mean and standard deviation against its closed form, and a
/// truncated normal never leaves its range.
#[test]
fn the_distributions_sample_their_own_moments_and_stay_in_range() {
    let cases = [
        (
            InputDistribution::Uniform {
                lower: 200.0,
                upper: 320.0,
            },
            260.0,
            120.0 / 12f64.sqrt(),
        ),
        (
            InputDistribution::Triangular {
                lower: 0.0,
                mode: 1.0,
                upper: 4.0,
            },
            5.0 / 3.0,
            ((0.0 + 1.0 + 16.0 - 0.0 - 0.0 - 4.0) / 18f64).sqrt(),
        ),
    ];
    for (d, mean, std) in cases {
        let u: Vec<f64> = (0..4096).map(|i| (i as f64 + 0.5) / 4096.0).collect();
        let x: Vec<f64> = u.iter().map(|&u| d.quantile(u)).collect();
        let (m, s) = mean_std(&x);
        assert!(
            (m - mean).abs() < 1e-3 * std,
            "{d:?}: mean {m} against {mean}"
        );
        assert!((s - std).abs() < 1e-3 * std, "{d:?}: std {s} against {std}");
        assert!((d.std_dev() - std).abs() < 1e-12 * std, "{d:?}");
        assert!((d.mean() - mean).abs() < 1e-12 * std, "{d:?}");
    }
    let truncated = InputDistribution::Normal {
        mean: 1.0,
        sigma: 2.0,
        lower: 0.0,
        upper: 2.0,
    };
    for i in 0..=1000 {
        let x = truncated.quantile(i as f64 / 1000.0);
        assert!((0.0..=2.0).contains(&x), "{x}");
    }
    assert_eq!(truncated.quantile(0.5), 1.0);
    // A truncated normal off centre: its mean against the mean of its quantiles.
    let off = InputDistribution::Normal {
        mean: 0.5,
        sigma: 1.0,
        lower: 0.0,
        upper: 3.0,
    };
    let x: Vec<f64> = (0..20000)
        .map(|i| off.quantile((i as f64 + 0.5) / 20000.0))
        .collect();
    let (m, _) = mean_std(&x);
    assert!((off.mean() - m).abs() < 1e-3, "{} against {m}", off.mean());
}

/// The design: `n (d + 2)` points in the unit cube, `A_B^(i)` equal to `A` but in column `i`,
/// and the same seed giving the same points.
#[test]
fn the_saltelli_design_has_its_structure_and_refuses_too_few_samples() {
    let d = Design::sobol(16, 3, 5).unwrap();
    let p = d.points();
    assert_eq!(p.len(), 16 * 5);
    assert!(p.iter().flatten().all(|u| (0.0..1.0).contains(u)));
    for i in 0..3 {
        for j in 0..16 {
            let (a, b, ab) = (&p[j], &p[16 + j], &p[(2 + i) * 16 + j]);
            for k in 0..3 {
                assert_eq!(ab[k], if k == i { b[k] } else { a[k] });
            }
        }
    }
    assert_eq!(Design::sobol(16, 3, 5).unwrap(), d);
    assert_ne!(Design::sobol(16, 3, 6).unwrap(), d);
    assert!(Design::sobol(7, 3, 0).unwrap_err().contains("at least 8"));
    assert!(Design::sobol(16, 0, 0).is_err());
}

fn u(u_num: f64, u_input: f64, u_data: f64) -> vv20::Uncertainties {
    vv20::Uncertainties {
        u_num,
        u_input,
        u_data,
        data_dof: None,
    }
}

/// The coverage factor where the data's standard deviation comes from few repeats (issue 51,
/// item 4): Student's t at the Welch-Satterthwaite degrees of freedom. Data alone with 6
/// degrees of freedom give t(0.975, 6) = 2.447 (the table's value); a model term as large as
/// the data's quadruples the effective degrees of freedom (24: t = 2.064); a model term that
/// swamps the data gives 2, the least factor; with the degrees of freedom not stated, 2. A
/// miss of 2.2 u_val, a model-form error at k = 2, is not one at t = 2.447.
#[test]
fn few_repeats_widen_the_coverage_by_students_t() {
    /// Student's t quantiles as tabulated (0.975; 6 and 24 degrees of freedom), to the table's
    /// three decimals.
    const TABLE: f64 = 5e-4;
    let (k, nu) = vv20::coverage(1.0, 1.0, Some(6.0));
    assert!((k - 2.447).abs() < TABLE && nu == Some(6.0), "{k} {nu:?}");
    let (k, nu) = vv20::coverage(2f64.sqrt(), 1.0, Some(6.0));
    assert!(
        (nu.unwrap() - 24.0).abs() < 1e-9 && (k - 2.064).abs() < TABLE,
        "{k}"
    );
    assert_eq!(vv20::coverage(10.0, 1.0, Some(6.0)).0, vv20::COVERAGE);
    assert_eq!(vv20::coverage(1.0, 1.0, None), (vv20::COVERAGE, None));
    let few = vv20::Uncertainties {
        data_dof: Some(6.0),
        ..u(0.0, 0.0, 0.1)
    };
    let miss = |us| vv20::compare(1.22, 1.0, us, 1.0, None).unwrap();
    assert_eq!(miss(u(0.0, 0.0, 0.1)).verdict, Vv20Verdict::ModelFormError);
    let c = miss(few);
    assert_ne!(c.verdict, Vv20Verdict::ModelFormError, "{c:?}");
    assert!((c.model_form_interval[0] - (0.22 - c.coverage * 0.1)).abs() < 1e-12);
}

/// The verdicts at their boundaries, and none from a number that is not finite.
#[test]
fn the_vv20_verdicts_follow_their_definitions() {
    // |E| = 0.3 > 2 u_val = 0.2: model-form error, whatever the tolerance.
    let c = vv20::compare(1.3, 1.0, u(0.0, 0.06, 0.08), 1.0, None).unwrap();
    assert_eq!(c.verdict, Vv20Verdict::ModelFormError);
    assert!((c.u_val - 0.1).abs() < 1e-12);
    assert!((c.model_form_interval[0] - 0.1).abs() < 1e-12);
    let verdict = |s, d, us, half| vv20::compare(s, d, us, half, None).unwrap().verdict;
    // |E| = 0.1 <= 0.2, model's own 2 u = 0.12 <= 0.15: agrees.
    assert_eq!(
        verdict(1.1, 1.0, u(0.0, 0.06, 0.08), 0.15),
        Vv20Verdict::Agrees
    );
    // The same with a tolerance of 0.1 narrower than 0.12: inconclusive.
    assert_eq!(
        verdict(1.1, 1.0, u(0.0, 0.06, 0.08), 0.1),
        Vv20Verdict::Inconclusive
    );
    // The numerical part counts with the input part.
    assert_eq!(
        verdict(1.0, 1.0, u(0.05, 0.0, 0.0), 0.09),
        Vv20Verdict::Inconclusive
    );
    assert!(vv20::compare(f64::NAN, 1.0, u(0.0, 0.1, 0.1), 1.0, None).is_none());
    assert!(vv20::compare(1.0, 1.0, u(0.0, f64::INFINITY, 0.1), 1.0, None).is_none());
}

/// A quantity the inputs spread one way (every sample above the data) is a model-form error
/// though |E| <= 2 u_val: the sampled interval, widened by the numerics and the data, decides.
/// Where it reaches the data, the symmetric test stands.
#[test]
fn a_one_sided_spread_that_misses_the_data_is_a_model_form_error() {
    // N_v-like: S = 0.32, D = 0.059, u_input = 0.14 (2 u_val = 0.28 > E = 0.26), samples in
    // [0.145, 0.66].
    let us = u(0.0, 0.14, 0.002);
    let c = vv20::compare(0.32, 0.059, us, 0.004, Some([0.145, 0.66])).unwrap();
    assert_eq!(c.verdict, Vv20Verdict::ModelFormError);
    let [lo, _] = c.sampled_interval.unwrap();
    assert!((lo - (0.145 - 0.004)).abs() < 1e-12);
    // The same spread reaching down past the data: inconclusive (the inputs might explain it).
    let c = vv20::compare(0.32, 0.059, us, 0.004, Some([0.05, 0.66])).unwrap();
    assert_eq!(c.verdict, Vv20Verdict::Inconclusive);
    // Not sampled: the symmetric test alone.
    let c = vv20::compare(0.32, 0.059, us, 0.004, None).unwrap();
    assert_eq!(c.verdict, Vv20Verdict::Inconclusive);
}

/// The straight line through `(x, y)` weighted by `1 / se^2`: `[intercept, slope]`.
fn line_fit(x: &[f64], y: &[f64], se: &[f64]) -> [f64; 2] {
    let (mut sw, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for ((x, y), s) in x.iter().zip(y).zip(se) {
        let w = 1.0 / (s * s);
        sw += w;
        sx += w * x;
        sy += w * y;
        sxx += w * x * x;
        sxy += w * x * y;
    }
    let slope = (sw * sxy - sx * sy) / (sw * sxx - sx * sx);
    [(sy - slope * sx) / sw, slope]
}

/// Coverage of a calibration's stated predictive intervals. Each synthetic calibration fits a
/// straight line (the model) to 40 rows of a hidden curve `a + b x + c x^2` (the truth: the
/// model's form is wrong by the hidden `c x^2`) measured with 2 % scatter; five groups of eight
/// rows are left out in turn (cross-validation) to find the discrepancy term; then 20 rows the
/// calibration never saw are predicted with `prediction +- 1.96 sqrt(se^2 + sd_d^2)`. Over 500
/// calibrations with hidden values drawn anew, the intervals must cover at their stated 95 %
/// within 0.01 (the sampling error of 10000 rows is 0.002; the rest allows for the discrepancy,
/// a smooth curve, not being normal). Without the discrepancy term (the fit's own scatter
/// alone) they must fall well short, or the test would not tell the term does anything.
#[test]
fn calibration_intervals_cover_held_out_rows_at_their_stated_rate() {
    for seed in [2026, 1, 77] {
        let (rate, without) = calibration_coverage(seed);
        eprintln!("seed {seed}: coverage {rate}, without the discrepancy term {without}");
        assert!((rate - 0.95).abs() <= 0.01, "seed {seed}: coverage {rate}");
        assert!(
            without < 0.85,
            "seed {seed}: without the discrepancy term {without}"
        );
    }
}

/// One run of the coverage test: the coverage with the discrepancy term and without it.
fn calibration_coverage(seed: u64) -> (f64, f64) {
    use cierva_harness::uncertainty::calibration::{covered, discrepancy_sd};
    let mut rng = SplitMix(seed);
    let (mut inside, mut inside_without, mut total) = (0usize, 0usize, 0usize);
    for _ in 0..500 {
        let (a, b, c) = (
            rng.uniform(4.0, 6.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(-3.0, 3.0),
        );
        let truth = |x: f64| a + b * x + c * x * x;
        let rows = |n: usize, rng: &mut SplitMix| -> (Vec<f64>, Vec<f64>, Vec<f64>) {
            let x: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let se: Vec<f64> = x.iter().map(|&x| 0.02 * truth(x)).collect();
            let y = x
                .iter()
                .zip(&se)
                .map(|(&x, s)| truth(x) + s * rng.normal())
                .collect();
            (x, y, se)
        };
        let (x, y, se) = rows(40, &mut rng);
        let (mut e, mut se_rel) = (Vec::new(), Vec::new());
        for g in 0..5 {
            let keep = |i: &usize| i % 5 != g;
            let pick = |v: &[f64]| -> Vec<f64> { (0..40).filter(keep).map(|i| v[i]).collect() };
            let [t0, t1] = line_fit(&pick(&x), &pick(&y), &pick(&se));
            for i in (0..40).filter(|i| !keep(i)) {
                e.push((t0 + t1 * x[i] - y[i]) / y[i]);
                se_rel.push(se[i] / y[i]);
            }
        }
        let sd = discrepancy_sd(&e, &se_rel);
        let [t0, t1] = line_fit(&x, &y, &se);
        let (xn, yn, sen) = rows(20, &mut rng);
        for i in 0..20 {
            let err = (t0 + t1 * xn[i] - yn[i]) / yn[i];
            inside += usize::from(covered(err, sen[i] / yn[i], sd));
            inside_without += usize::from(covered(err, sen[i] / yn[i], 0.0));
            total += 1;
        }
    }
    let rate = inside as f64 / total as f64;
    let without = inside_without as f64 / total as f64;
    (rate, without)
}

/// A sample the aircraft refuses (a range reaching a negative roll inertia) is counted as a
/// failed point with its first error, and left out of the statistics: never a panic, never a
/// silent drop.
#[test]
#[ignore = "slow (about 4 s in a release test run since the VPM M16's blades feel the hub's angular acceleration, 2026-11-30; out of the cold `cargo test`, held under 5 minutes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn samples_the_model_refuses_are_counted_with_their_first_error() {
    use cierva_harness::uncertainty::propagate::{self, PropagationSettings};
    let root = super::common::repo_root();
    let mut case = cierva_harness::suite::case::load(
        &root.join("cases/cierva-table2-vpm-m16-70mph-max-weight.yaml"),
    )
    .unwrap();
    let cierva_harness::checks::subject::Subject::Aircraft { file, .. } = &mut case.subject else {
        panic!("an aircraft case");
    };
    // Only the roll inertia, from -250 to 750: a third of the samples negative.
    let mut r = file.ranges["mass.ixx_kg_m2"].clone();
    (r.lower, r.upper) = (-250.0, 750.0);
    file.ranges.clear();
    file.ranges.insert("mass.ixx_kg_m2".into(), r);
    case.checks.retain(|k| k.id == "L_p");
    let settings = PropagationSettings {
        samples: 16,
        seed: 3,
        validation_only: false,
        method: propagate::Propagation::Auto,
    };
    let u = cierva_harness::uncertainty::study::propagate(&case, settings, || {}).unwrap();
    // The design, the nominal, and 4 discretisation parameters at 2 refined levels each.
    assert_eq!(u.evaluations, 16 * 3 + 1 + 8);
    assert!(u.failed_points > 0 && u.failed_points < 48, "{u:?}");
    assert!(
        u.first_error.as_deref().is_some_and(|e| !e.is_empty()),
        "{u:?}"
    );
    let l_p = &u.results[0];
    assert!(l_p.failed_samples > 0, "{l_p:?}");
    assert!(l_p.mean.is_finite() && l_p.u_input.is_finite(), "{l_p:?}");
    // A third of the draws failing (more than MAX_FAILED_SHARE) leaves no verdict: the draws
    // left are not the inputs' distribution. The check's failures are counted by cause.
    assert_eq!(l_p.samples, 48, "{l_p:?}");
    assert!(
        l_p.failed_samples as f64 > propagate::MAX_FAILED_SHARE * 48.0,
        "{l_p:?}"
    );
    assert_eq!(l_p.verdict, None, "{}", l_p.reason);
    assert!(
        l_p.reason
            .starts_with("no verdict: the inputs' range leaves the model's envelope at"),
        "{}",
        l_p.reason
    );
    let counted: usize = l_p
        .failure_causes
        .iter()
        .map(|c| c.split(" x ").next().unwrap().parse::<usize>().unwrap())
        .sum();
    assert_eq!(counted, l_p.failed_samples, "{:?}", l_p.failure_causes);
}

/// A rotor case is propagated to first order (each input one standard deviation either way):
/// on TR 487's descent (the PCA-2 rotor's five ranged inputs; the hub's drag area has none
/// since issue 51, item 2) it gives the sampled `u_input` within 15 %, the same verdicts and the
/// same largest contributor, at 21 evaluations against 231. The bound is the sampled estimate's own: at 32 base points its rotor-speed `u_input`
/// ranges over 1.54e-2 to 1.84e-2 rad/s across seeds 0-3 (+-9 %; first order gives 1.71e-2).
///
/// And its 95 % interval holds at its stated rate: the sampled run's 64 draws of the inputs
/// (the rows of `A` and `B`, which the first order never saw) fall inside the first order's
/// interval in at least [`FIRST_ORDER_COVERAGE_FLOOR`] of cases, per quantity.
#[test]
#[ignore = "slow (about 9 s in a release test run since the VPM M16's blades feel the hub's angular acceleration, 2026-11-30; out of the cold `cargo test`, held under 5 minutes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn first_order_propagation_of_a_rotor_agrees_with_sampling() {
    use cierva_harness::uncertainty::propagate::{Propagation, PropagationSettings};
    let root = super::common::repo_root();
    let case =
        cierva_harness::suite::case::load(&root.join("cases/naca-tr487-vertical-descent.yaml"))
            .unwrap();
    let run = |method| {
        let settings = PropagationSettings {
            samples: 32,
            seed: 1,
            validation_only: false,
            method,
        };
        cierva_harness::uncertainty::study::propagate(&case, settings, || {}).unwrap()
    };
    let (first, sampled) = (run(Propagation::Auto), run(Propagation::Sampled));
    assert_eq!(first.inputs.len(), 5);
    // Each with the nominal and the rotor's 3 discretisation parameters at 2 refined levels.
    assert_eq!(first.evaluations, 2 * 5 + 4 + 1 + 6);
    assert_eq!(sampled.evaluations, 32 * 7 + 1 + 6);
    assert!(first.method.starts_with("first order"), "{}", first.method);
    for (f, s) in first.results.iter().zip(&sampled.results) {
        eprintln!(
            "{}: first order u_input {:.4e} (sampled {:.4e}); {:?}",
            f.quantity,
            f.u_input,
            s.u_input,
            f.contributors
                .iter()
                .map(|c| (c.input.clone(), c.total))
                .collect::<Vec<_>>()
        );
        assert_eq!(f.quantity, s.quantity);
        assert!(
            (f.u_input / s.u_input - 1.0).abs() < 0.15,
            "{}: first order {} against sampled {}",
            f.quantity,
            f.u_input,
            s.u_input
        );
        assert_eq!(f.verdict, s.verdict, "{}", f.quantity);
        // TR 487 gives its flight point without scatter: E is given and weighed against the
        // model's own uncertainty, and the verdict says the data state none (issue 51: it read
        // inconclusive, like a model too uncertain for its tolerance).
        assert_eq!(
            f.verdict,
            Some(cierva_harness::uncertainty::vv20::Vv20Verdict::NoDataUncertainty),
            "{}",
            f.quantity
        );
        assert!(
            f.reason.starts_with("no data uncertainty")
                && f.reason.contains("times the model's own u"),
            "{}",
            f.reason
        );
        // The largest input (the first order's residual term, interactions, is not one).
        let largest = f
            .contributors
            .iter()
            .find(|c| !c.input.starts_with("interactions"));
        assert_eq!(largest.unwrap().input, s.contributors[0].input);
        // The first order's shares are not sampled: no standard errors; the sampled indices'.
        assert!(
            f.contributors
                .iter()
                .all(|c| c.first_se.is_none() && c.total_se.is_none())
        );
        assert!(
            s.contributors
                .iter()
                .all(|c| c.first_se.is_some_and(f64::is_finite)
                    && c.total_se.is_some_and(f64::is_finite))
        );
        // `u_num` is the grid study's: each parameter's index, root-sum-squared, each index at
        // least Fs 1.25 times its first refinement's change (issue 51, item 3). (With Fs 3 on
        // the blade elements' oscillating sequence, the rotor speed's is now about its
        // `u_input`, where the old single refinement's change was a fraction of it.)
        assert!(f.u_num > 0.0 && f.u_num.is_finite(), "{f:?}");
        let rss = f
            .u_num_terms
            .iter()
            .map(|t| t.gci * t.gci)
            .sum::<f64>()
            .sqrt();
        assert!((rss - f.u_num).abs() <= 1e-12 * f.u_num, "{f:?}");
        assert_eq!(f.u_num_terms.len(), 3, "{f:?}");
        for t in &f.u_num_terms {
            assert!(t.gci >= 1.25 * (t.values[1] - t.values[0]).abs(), "{t:?}");
        }
        let draws: Vec<f64> = s.draws.iter().copied().filter(|v| v.is_finite()).collect();
        assert_eq!(draws.len(), 64, "{}", f.quantity);
        let inside = draws
            .iter()
            .filter(|v| (f.p2_5..=f.p97_5).contains(*v))
            .count() as f64
            / draws.len() as f64;
        eprintln!(
            "{}: first order's 95 % interval [{:.6e}, {:.6e}] holds {:.3} of 64 draws (sampled 2.5-97.5 % [{:.6e}, {:.6e}], below {}, above {})",
            f.quantity,
            f.p2_5,
            f.p97_5,
            inside,
            s.p2_5,
            s.p97_5,
            draws.iter().filter(|v| **v < f.p2_5).count(),
            draws.iter().filter(|v| **v > f.p97_5).count()
        );
        assert!(
            inside >= FIRST_ORDER_COVERAGE_FLOOR,
            "{}: the first order's 95 % interval holds only {inside:.3} of the sampled draws",
            f.quantity
        );
    }
}

/// The least share of 64 draws a stated 95 % interval may hold: 0.95 less three binomial
/// standard deviations over 64 independent draws (3 x 0.027). Scrambled Sobol' rows spread
/// more evenly than independent draws, so this is conservative. Measured on TR 487's descent:
/// 0.984, 0.969 and 0.938 (rotor speed, C_T, C_D); 0.891 for rotor speed and C_T with the first
/// version's linear model, and 0.859 for rotor speed with the surrogate but no residual check.
const FIRST_ORDER_COVERAGE_FLOOR: f64 = 0.95 - 3.0 * 0.027;

/// A prediction made with a cross-validated corrections file carries the calibration's stated
/// predictive error (issue 36, item 7): its model-discrepancy term for the check's regime, or
/// the pooled one for a check in none of its regimes, times the nominal value, added to the
/// inputs' spread in quadrature and named among the contributors. A quantity the calibration
/// states nothing for, and a check it is not applied to, carry none. Known answers: TR 487's
/// descent with a neutral correction (pitch offset 0, so the nominal values are the
/// uncorrected ones) and made-up discrepancy terms.
#[test]
fn a_calibrations_predictive_error_is_carried_into_u_input() {
    use cierva_harness::uncertainty::propagate::{self, Propagation, PropagationSettings};
    let root = super::common::repo_root();
    let case =
        cierva_harness::suite::case::load(&root.join("cases/naca-tr487-vertical-descent.yaml"))
            .unwrap();
    let dir = crate::common::scratch("calibration");
    std::fs::create_dir_all(&dir).unwrap();
    let file = |name: &str, regimes: &str, not_applied: &str| {
        let path = dir.join(format!("{name}.yaml"));
        std::fs::write(
            &path,
            format!(
                "id: {name}\ntitle: t\napplies_to: {{rotor: pca-2-rotor}}\ncorrections: {{pitch_offset_deg: 0.0}}\nprovenance: {{source: a test}}\ncross_validation:\n  discrepancy_relative_sd: {{rotor_rpm: 0.05, drag_coefficient: 0.2}}\n  regimes:\n{regimes}{not_applied}"
            ),
        )
        .unwrap();
        cierva_harness::inputs::corrections::load(&path).unwrap()
    };
    let run = |files: &[cierva_harness::inputs::corrections::CorrectionsFile]| {
        let (c, used) = cierva_harness::suite::case::with_corrections(&case, files).unwrap();
        assert_eq!(used.len(), files.len());
        let settings = PropagationSettings {
            samples: 8,
            seed: 0,
            validation_only: false,
            method: Propagation::FirstOrder,
        };
        cierva_harness::uncertainty::study::propagate(&c, settings, || {})
            .unwrap()
            .results
    };
    let plain = run(&[]);
    let in_regime = run(&[file(
        "in-regime",
        "    descent: {checks: {naca-tr487-vertical-descent: [flight]}, discrepancy_relative_sd: {rotor_rpm: 0.02}}\n",
        "",
    )]);
    let pooled = run(&[file(
        "pooled",
        "    other: {checks: {another-case: [flight]}, discrepancy_relative_sd: {rotor_rpm: 0.02}}\n",
        "",
    )]);
    let not_applied = run(&[file(
        "not-applied",
        "    descent: {checks: {naca-tr487-vertical-descent: [flight]}, discrepancy_relative_sd: {rotor_rpm: 0.02}}\n",
        "not_applied_to:\n  - {case: naca-tr487-vertical-descent, regime: descent, checks: [flight], reason: a test}\n",
    )]);
    let by = |r: &[propagate::QuantityUncertainty], q: &str| {
        r.iter().find(|x| x.quantity == q).unwrap().clone()
    };
    // (quantity, relative sd in the regime's file, in the pooled file)
    for (q, regime_sd, pooled_sd) in [
        ("rotor_omega_rad_s", 0.02, 0.05),
        ("drag_coefficient", 0.0, 0.2),
        ("thrust_coefficient", 0.0, 0.0),
    ] {
        let p = by(&plain, q);
        assert_eq!(p.u_calibration, 0.0);
        for (r, sd) in [(by(&in_regime, q), regime_sd), (by(&pooled, q), pooled_sd)] {
            assert_eq!(r.nominal, p.nominal, "{q}: the correction is neutral");
            let u_cal = sd * p.nominal.abs();
            assert!(
                (r.u_calibration - u_cal).abs() <= 1e-12 * u_cal.max(1e-300),
                "{q}: {r:?}"
            );
            let total = (p.u_input.powi(2) + u_cal.powi(2)).sqrt();
            assert!(
                (r.u_input - total).abs() <= 1e-12 * total,
                "{q}: {} against {total}",
                r.u_input
            );
            let named = r
                .contributors
                .iter()
                .find(|c| c.input.starts_with("calibration"));
            assert_eq!(named.is_some(), sd > 0.0, "{q}: {:?}", r.contributors);
            if let Some(c) = named {
                assert!((c.total - u_cal.powi(2) / total.powi(2)).abs() < 1e-12);
                let shares: f64 = r.contributors.iter().map(|c| c.total).sum();
                assert!((shares - 1.0).abs() < 1e-9, "{q}: shares sum to {shares}");
                // The 95 % interval widens with it.
                assert!(r.p97_5 - r.p2_5 > p.p97_5 - p.p2_5);
            }
        }
        assert_eq!(by(&not_applied, q).u_calibration, 0.0, "{q}");
    }
    assert!(
        by(&in_regime, "rotor_omega_rad_s").contributors[0]
            .input
            .contains("regime `descent`")
    );
}

/// The normal quantile at 97.5 %: an index's 95 % interval is `estimate -+ Z95 SE`.
const Z95: f64 = 1.959_963_985;

/// Over many seeds, per index: how often `|estimate - truth| <= Z95 SE`, the sum of the
/// standard errors and the sum of the squared errors.
struct Coverage {
    seeds: usize,
    /// `(hits, sum of SE, sum of squared errors)` per input: first order, then total.
    first: Vec<(usize, f64, f64)>,
    total: Vec<(usize, f64, f64)>,
}

impl Coverage {
    fn new(d: usize) -> Self {
        Self {
            seeds: 0,
            first: vec![(0, 0.0, 0.0); d],
            total: vec![(0, 0.0, 0.0); d],
        }
    }

    /// One seed's estimate against the truth.
    fn add(&mut self, e: &sobol::SobolEstimate, first: &[f64], total: &[f64]) {
        self.seeds += 1;
        for (i, x) in e.indices.iter().enumerate() {
            for (t, estimate, se, truth) in [
                (&mut self.first[i], x.first, x.first_se, first[i]),
                (&mut self.total[i], x.total, x.total_se, total[i]),
            ] {
                t.0 += usize::from((estimate - truth).abs() <= Z95 * se);
                t.1 += se;
                t.2 += (estimate - truth).powi(2);
            }
        }
    }

    /// Per input: the share of seeds covered.
    fn rates(&self, t: &[(usize, f64, f64)]) -> Vec<f64> {
        t.iter().map(|t| t.0 as f64 / self.seeds as f64).collect()
    }

    /// Over every input and seed: the share covered.
    fn pooled(&self, t: &[(usize, f64, f64)]) -> f64 {
        t.iter().map(|t| t.0).sum::<usize>() as f64 / (self.seeds * t.len()) as f64
    }

    /// Per input: the mean standard error over the root-mean-square error (above 1, the
    /// standard error overstates the error).
    fn overstatement(&self, t: &[(usize, f64, f64)]) -> Vec<f64> {
        let n = self.seeds as f64;
        t.iter().map(|t| (t.1 / n) / (t.2 / n).sqrt()).collect()
    }

    fn table(&self, name: &str) -> String {
        let f = |v: Vec<f64>| {
            v.iter()
                .map(|x| format!("{x:.3}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        format!(
            "{name}, {} seeds\n  first: coverage {} (pooled {:.3}), SE / RMS error {}\n  \
             total: coverage {} (pooled {:.3}), SE / RMS error {}",
            self.seeds,
            f(self.rates(&self.first)),
            self.pooled(&self.first),
            f(self.overstatement(&self.first)),
            f(self.rates(&self.total)),
            self.pooled(&self.total),
            f(self.overstatement(&self.total)),
        )
    }
}

/// `y = c0 + sum c_i x_i` of four independent Gaussian inputs: the inputs, the function, and
/// each input's index (first order and total alike) `c_i^2 sigma_i^2 / V`; its mean and
/// variance from [`linear_moments`].
fn linear_gaussian() -> (Vec<InputDistribution>, Model, Vec<f64>) {
    let dists = LINEAR_MU
        .iter()
        .zip(&LINEAR_SIGMA)
        .map(|(&mean, &sigma)| InputDistribution::Normal {
            mean,
            sigma,
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
        })
        .collect();
    let shares = LINEAR_C
        .iter()
        .zip(&LINEAR_SIGMA)
        .map(|(c, s)| (c * s).powi(2) / linear_moments().1)
        .collect();
    (
        dists,
        |x| LINEAR_C0 + LINEAR_C.iter().zip(x).map(|(c, x)| c * x).sum::<f64>(),
        shares,
    )
}

/// [`linear_gaussian`]'s constant, coefficients, and inputs' means and standard deviations.
const LINEAR_C0: f64 = 3.0;
const LINEAR_C: [f64; 4] = [2.0, -1.0, 0.5, 4.0];
const LINEAR_MU: [f64; 4] = [1.0, -2.0, 10.0, 0.0];
const LINEAR_SIGMA: [f64; 4] = [0.3, 1.0, 2.0, 0.05];
/// The mean `c0 + sum c_i mu_i` and variance `sum c_i^2 sigma_i^2` of [`linear_gaussian`].
fn linear_moments() -> (f64, f64) {
    let mean = LINEAR_C0
        + LINEAR_C
            .iter()
            .zip(&LINEAR_MU)
            .map(|(c, m)| c * m)
            .sum::<f64>();
    let var = LINEAR_C
        .iter()
        .zip(&LINEAR_SIGMA)
        .map(|(c, s)| (c * s).powi(2))
        .sum();
    (mean, var)
}

/// Sobol's G function of 13 inputs uniform on [0, 1] (13, as the VPM M16's ranged inputs were; 16 since its tail was estimated):
/// `prod (|4 x_i - 2| + a_i) / (1 + a_i)`, with `V_i = 1 / (3 (1 + a_i)^2)`,
/// `V = prod (1 + V_i) - 1`, `S_i = V_i / V` and `S_Ti = V_i prod_(j != i) (1 + V_j) / V`
/// (Saltelli and Sobol' 1995). Its kinks and products make the estimators' summands heavy
/// tailed: the hard case.
fn g_function() -> (Model, Vec<f64>, Vec<f64>) {
    const G_A: [f64; 13] = [
        0.0, 1.0, 4.5, 9.0, 2.0, 0.5, 99.0, 3.0, 9.0, 99.0, 1.5, 6.0, 20.0,
    ];
    let vi: Vec<f64> = G_A
        .iter()
        .map(|a| 1.0 / (3.0 * (1.0 + a).powi(2)))
        .collect();
    let v = vi.iter().map(|v| 1.0 + v).product::<f64>() - 1.0;
    let first = vi.iter().map(|vi| vi / v).collect();
    let total = vi
        .iter()
        .map(|vi| vi * (1.0 + v) / (1.0 + vi) / v)
        .collect();
    let f = |x: &[f64]| {
        G_A.iter()
            .zip(x)
            .map(|(a, x)| ((4.0 * x - 2.0).abs() + a) / (1.0 + a))
            .product::<f64>()
    };
    (f, first, total)
}

/// `y = sum x_i / i` of 13 inputs uniform on [0, 1] (i from 1): each input's index, first order
/// and total alike, `(1 / i^2) / sum (1 / j^2)`.
fn linear13() -> (Model, Vec<f64>) {
    let weight = |i: usize| 1.0 / (1.0 + i as f64);
    let v: f64 = (0..13).map(|i| weight(i).powi(2)).sum();
    let shares = (0..13).map(|i| weight(i).powi(2) / v).collect();
    let f = |x: &[f64]| {
        x.iter()
            .enumerate()
            .map(|(i, x)| x / (1.0 + i as f64))
            .sum::<f64>()
    };
    (f, shares)
}

/// The coverage of the scrambled design of `n` base points over seeds 0 to 199.
fn design_coverage(
    n: usize,
    dists: &[InputDistribution],
    f: Model,
    first: &[f64],
    total: &[f64],
) -> Coverage {
    let mut c = Coverage::new(dists.len());
    for seed in 0..SEEDS {
        let design = Design::sobol(n, dists.len(), seed).unwrap();
        let y = evaluate(&design, dists, f);
        let (fa, fb, fab) = design.split(&y);
        c.add(&sobol::estimate(fa, fb, &fab).unwrap(), first, total);
    }
    c
}

/// The seeds of each coverage run. At a true coverage of 0.95 the share of 200 seeds covered has
/// a binomial standard deviation of sqrt(0.95 x 0.05 / 200) = 0.015.
const SEEDS: u32 = 200;
/// The least coverage of one index over [`SEEDS`] seeds that a stated 95 % may show: three
/// binomial standard deviations (0.015) below it.
const LEAST_COVERAGE: f64 = 0.90;

/// The standard errors where their assumption holds: rows of independent draws (SplitMix64, not
/// the Sobol' points), where the delta method's standard error is the estimator's own to first
/// order. Ishigami and the linear model at 256 base points (cierva's default), 200 draws each:
/// - pooled over the inputs, the coverage of `estimate -+ 1.96 SE` must be 0.95 within
///   [`IID_BELOW`] and [`IID_ABOVE`]: two-sided, a standard error too large fails as well as one
///   too small;
/// - per index, the mean standard error over the RMS error must be 1 within [`IID_RATIO`].
///
/// Measured here: pooled 0.947 first order and 0.948 total for Ishigami, 0.959 and 0.944 for
/// the linear model; the mean SE 0.93-1.07 times the RMS error. Over 2000 draws (outside the
/// suite): 0.942 and 0.938 for Ishigami, 0.952 and 0.944 for the linear model: the delta method
/// runs about 0.01 short at this size (the total index's summands are squares, and skewed; at
/// 512 base points Ishigami's are 0.950 and 0.943).
#[test]
fn sobol_standard_errors_cover_at_95_percent_over_independent_rows() {
    // A pooled share of 600 (800) estimates has a binomial standard deviation of 0.009 (0.008)
    // if they are independent; the inputs of one draw share `f(A)` and `f(B)`, so take 0.01.
    // Above: three of them. Below: three, and the delta method's measured 0.01 shortfall.
    const IID_ABOVE: f64 = 0.03;
    const IID_BELOW: f64 = 0.04;
    // The RMS error of 200 draws has a relative standard deviation of about 1 / sqrt(2 x 200)
    // = 0.035 for normal errors, more for the skewed total index: three of 0.06.
    const IID_RATIO: f64 = 0.2;
    let n = 256;
    let run = |dists: &[InputDistribution], f: Model, first: &[f64], total: &[f64]| {
        let d = dists.len();
        let mut c = Coverage::new(d);
        let mut rng = SplitMix(2026);
        for _ in 0..SEEDS {
            let mut draw =
                || -> Vec<f64> { dists.iter().map(|x| x.quantile(rng.next())).collect() };
            let (a, b): (Vec<Vec<f64>>, Vec<Vec<f64>>) = (0..n).map(|_| (draw(), draw())).unzip();
            let fa: Vec<f64> = a.iter().map(|x| f(x)).collect();
            let fb: Vec<f64> = b.iter().map(|x| f(x)).collect();
            let fab: Vec<Vec<f64>> = (0..d)
                .map(|i| {
                    a.iter()
                        .zip(&b)
                        .map(|(a, b)| {
                            let mut x = a.clone();
                            x[i] = b[i];
                            f(&x)
                        })
                        .collect()
                })
                .collect();
            let fab: Vec<&[f64]> = fab.iter().map(Vec::as_slice).collect();
            c.add(&sobol::estimate(&fa, &fb, &fab).unwrap(), first, total);
        }
        c
    };
    let (f, _, first, total) = ishigami();
    let ishigami = run(&[ISHIGAMI_INPUT; 3], f, &first, &total);
    let (dists, f, shares) = linear_gaussian();
    let linear = run(&dists, f, &shares, &shares);
    let table = format!(
        "{}\n{}",
        ishigami.table("Ishigami, independent rows"),
        linear.table("linear, independent rows")
    );
    eprintln!("{table}");
    for c in [&ishigami, &linear] {
        for t in [&c.first, &c.total] {
            let rate = c.pooled(t);
            assert!(
                (0.95 - IID_BELOW..=0.95 + IID_ABOVE).contains(&rate),
                "coverage {rate}\n{table}"
            );
            for over in c.overstatement(t) {
                assert!(
                    (over - 1.0).abs() <= IID_RATIO,
                    "SE / error {over}\n{table}"
                );
            }
        }
    }
}

/// The standard errors on the design cierva samples: `A` and `B` from one scrambled Sobol'
/// sequence, whose rows are not independent. The standard error is the independent rows' (the
/// test above), and the scrambled points integrate smooth functions better than independent
/// draws: it overstates the error. Over seeds 0 to 199 at 64 base points, per index, the
/// coverage of `estimate -+ 1.96 SE` must reach [`LEAST_COVERAGE`], and the mean SE over the
/// RMS error must be at least 1 (conservative) and, for Ishigami, at most 3 (measured 1.23-2.29;
/// the RMS of 200 seeds is good to about 5 %, so 3 is a clear margin over the most and states
/// how far the overstatement goes). Measured: Ishigami's coverage 0.975-1.000 per index (pooled
/// 0.987 first order and total); the linear model's 1.000 everywhere, its SE 12.3-13.2 times the
/// RMS error for the first order and 2.4-3.9 for the total. That ratio is not bounded above:
/// the Sobol' points integrate an additive function's estimators almost exactly, and estimator
/// (b) is not centred, so its SE grows with the quantity's mean (here 12 against a standard
/// deviation of 1.5) where its error on these points does not.
///
/// And the hard case, where the SE falls short of its 95 %: the G function of 13 inputs at 256
/// base points (the VPM M16's inputs and cierva's default), whose summands are heavy tailed
/// (over independent rows, outside the suite: 0.94 first order and 0.92 total, pooled over 1000
/// draws). Measured here: pooled 0.988 first order and 0.951 total, per input 0.925-1.000 and
/// 0.860-0.980 (the least total, 0.860, on an input of index 7e-5; the next 0.920). Pooled, the
/// first order must hold its stated 0.95 (2600 estimates: a binomial standard deviation of
/// 0.004, against a measured margin of 0.038), and the total reach 0.90: 0.95 less three
/// binomial standard deviations of one input's 200 seeds (0.015), since its shortfall is in a
/// few inputs. `docs/uncertainty.md` states it.
///
/// And 13 inputs at 64 base points, even on a linear function ([`linear13`]): the total index
/// of input `i` is the mean of `(x_i(A) - x_i(B))^2`, a function of the sequence's dimensions
/// `i` and `13 + i` alone, and for inputs 5 and 12 those pairs are spread worse than independent
/// draws at 64 points (Owen 1997's small factor): coverage 0.665 and 0.725, the SE 0.62 times
/// the RMS error. Pooled 1.000 first order and 0.950 total; the same bounds as the G function's.
/// At 256 base points every index of it is covered (1.000, the SE 2.5-58 times the error) and
/// is held as the smooth functions are (at 128, measured once: 0.955 or more).
#[test]
fn sobol_standard_errors_are_conservative_on_the_scrambled_design() {
    let (f, _, first, total) = ishigami();
    let ishigami = design_coverage(64, &[ISHIGAMI_INPUT; 3], f, &first, &total);
    let (dists, f, shares) = linear_gaussian();
    let linear = design_coverage(64, &dists, f, &shares, &shares);
    let (f, first, total) = g_function();
    let uniform = InputDistribution::Uniform {
        lower: 0.0,
        upper: 1.0,
    };
    let g = design_coverage(256, &[uniform; 13], f, &first, &total);
    let (f, shares) = linear13();
    let linear13_64 = design_coverage(64, &[uniform; 13], f, &shares, &shares);
    let linear13_256 = design_coverage(256, &[uniform; 13], f, &shares, &shares);
    let table = format!(
        "{}\n{}\n{}\n{}\n{}",
        ishigami.table("Ishigami, 64 base points"),
        linear.table("linear, 64 base points"),
        g.table("G function, 256 base points"),
        linear13_64.table("linear of 13 inputs, 64 base points"),
        linear13_256.table("linear of 13 inputs, 256 base points"),
    );
    eprintln!("{table}");
    for (c, most) in [
        (&ishigami, 3.0),
        (&linear, f64::INFINITY),
        (&linear13_256, f64::INFINITY),
    ] {
        for t in [&c.first, &c.total] {
            for (rate, over) in c.rates(t).into_iter().zip(c.overstatement(t)) {
                assert!(rate >= LEAST_COVERAGE, "coverage {rate}\n{table}");
                assert!((1.0..=most).contains(&over), "SE / error {over}\n{table}");
            }
        }
    }
    assert!(g.pooled(&g.first) >= 0.95, "{table}");
    assert!(g.pooled(&g.total) >= 0.90, "{table}");
    assert!(linear13_64.pooled(&linear13_64.first) >= 0.95, "{table}");
    assert!(linear13_64.pooled(&linear13_64.total) >= 0.90, "{table}");
}

/// Two cases as a whole-suite summary holds them: one with every verdict and a fragile pass,
/// one without any verdict (no uncertain inputs).
fn small_summary() -> cierva_harness::uncertainty::summary::Summary {
    use cierva_harness::uncertainty::propagate::Propagation;
    use cierva_harness::uncertainty::summary::{CaseVerdicts, FragilePass, Summary};
    let names = |n: &[&str]| n.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let mut cases = std::collections::BTreeMap::new();
    cases.insert(
        "table-2".to_string(),
        CaseVerdicts {
            method: "sampled".into(),
            inputs: 16,
            evaluations: 1154,
            failed_points: 3,
            agrees: names(&["Y_v"]),
            model_form_error: names(&["L_p", "L_v", "N_v"]),
            inconclusive: names(&["N_r", "Y_r", "L_r", "N_p"]),
            no_data_uncertainty: names(&["T_ph"]),
            without_verdict: Vec::new(),
            fragile: vec![FragilePass {
                quantity: "Y_v".into(),
                passes_percent: 63,
                flipped_by: names(&["fin.area_m2"]),
            }],
            circular: Vec::new(),
        },
    );
    cases.insert(
        "trim-trend".to_string(),
        CaseVerdicts {
            method: "none".into(),
            inputs: 0,
            evaluations: 1,
            failed_points: 0,
            agrees: Vec::new(),
            model_form_error: Vec::new(),
            inconclusive: Vec::new(),
            no_data_uncertainty: Vec::new(),
            without_verdict: names(&["trends stick", "trends nose"]),
            fragile: Vec::new(),
            circular: Vec::new(),
        },
    );
    Summary {
        samples: 64,
        seed: 0,
        method: Propagation::Auto,
        cases,
    }
}

/// The committed summary's format (`reports/uncertainty-summary.yaml`): a header naming the
/// command that wrote it, the settings, and per case its propagation and each validation
/// quantity under its verdict; it reads back to what was written.
#[test]
fn the_uncertainty_summary_file_has_its_format_and_reads_back() {
    use cierva_harness::uncertainty::summary;
    let s = small_summary();
    let text = summary::render(&s);
    assert_eq!(text, SMALL_SUMMARY_FILE, "{text}");
    let back = summary::parse(std::path::Path::new("summary.yaml"), &text).unwrap();
    assert_eq!(back, s);
    assert_eq!(
        summary::render(&back),
        text,
        "written twice, the same bytes"
    );
}

/// The "How sure" table: a row per case with a verdict (names where there are at most three,
/// counts beyond), the cases without any verdict in its sentence, the sums over every case; and
/// the list of propagations, quantities by kind and fragile passes.
#[test]
fn the_how_sure_table_counts_names_and_sums_the_summary() {
    use cierva_harness::uncertainty::summary;
    let s = small_summary();
    assert_eq!(
        summary::table(&s),
        "Validation quantities per case, from `cierva uncertainty --samples 64 --seed 0 \
         --write-summary` (`reports/uncertainty-summary.yaml`, which CI reruns and compares; \
         names where there are at most 3); no verdict at all (no uncertain inputs or no \
         reference value): `trim-trend` (2):\n\
         \n\
         | case | quantities | agree | model-form error | inconclusive | no data uncertainty | no verdict | fragile |\n\
         | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n\
         | `table-2` | 9 | 1 (Y_v) | 3 (L_p, L_v, N_v) | 4 | 1 (T_ph) | 0 | 1 (Y_v) |\n\
         | **all 2 cases** | **11** | **1** | **3** | **4** | **1** | **2** | **1** |\n"
    );
    assert_eq!(
        summary::cases_list(&s),
        "- `table-2`: sampled, 16 inputs, 1154 evaluations, failed points: 3; fragile: Y_v \
         (passes in 63 % of the evaluated draws; flipped by `fin.area_m2`).\n\
         - `trim-trend`: none, 0 inputs, 1 evaluations, failed points: 0; by quantity: nose 1 \
         (1 no verdict); stick 1 (1 no verdict); no fragile pass.\n"
    );
}

/// The docs trial (`cases::docs::readme-how-sure-table`) passes on the README as committed and
/// fails on one whose table disagrees with the summary, with the wanted table in its message
/// as `scripts/update-generated-docs` reads it; a document without the markers fails too.
#[test]
fn a_readme_whose_how_sure_table_disagrees_with_the_summary_fails_its_docs_check() {
    use cierva_harness::report::generated;
    use cierva_harness::uncertainty::summary;
    let s = summary::load(&super::common::suite()).unwrap();
    let want = summary::table(&s);
    let readme = std::fs::read_to_string(super::common::repo_root().join("README.md")).unwrap();
    generated::check("README.md", &readme, "how-sure-table", &want).unwrap();
    let section = generated::section(&readme, "how-sure-table").unwrap();
    let all = s.cases.values().map(|c| c.quantities()).sum::<usize>();
    let row = format!("| **{all}** |");
    assert!(section.contains(&row), "{section}");
    let mutated = readme.replacen(&row, &format!("| **{}** |", all + 1), 1);
    let err = generated::check("README.md", &mutated, "how-sure-table", &want).unwrap_err();
    assert_eq!(
        err,
        format!("README.md's how-sure-table is not what the run gives; replace it with:\n{want}")
    );
    let err = generated::check("README.md", "# cierva\n", "how-sure-table", &want).unwrap_err();
    assert_eq!(err, "README.md has no how-sure-table markers");
}

/// A summary that is not well formed is refused with the file, line and field: a field
/// misspelt, a quantity under two verdicts, a fragile pass that is no quantity of its case; and
/// a suite without one says which command writes it.
#[test]
fn a_malformed_uncertainty_summary_is_a_located_error() {
    use cierva_harness::uncertainty::summary;
    let path = std::path::Path::new("summary.yaml");
    let good = summary::render(&small_summary());
    let err = summary::parse(path, &good.replace("samples:", "sampels:")).unwrap_err();
    assert_eq!(err.line, Some(5), "{}", err.render());
    assert!(
        err.message.contains("did you mean `samples`"),
        "{}",
        err.render()
    );
    let twice = good.replace("    - N_r\n", "    - Y_v\n");
    let err = summary::parse(path, &twice).unwrap_err();
    assert!(
        err.message.contains("Y_v is listed twice")
            && err.field.as_deref() == Some("cases.table-2.inconclusive")
            && err.line.is_some(),
        "{}",
        err.render()
    );
    let stray = good.replace("  - quantity: Y_v", "  - quantity: N_q");
    let err = summary::parse(path, &stray).unwrap_err();
    assert!(
        err.message.contains("N_q is fragile but has no verdict") && err.line.is_some(),
        "{}",
        err.render()
    );
    let over = good.replace("passes_percent: 63", "passes_percent: 163");
    let err = summary::parse(path, &over).unwrap_err();
    assert!(err.message.contains("more than 100"), "{}", err.render());
    let dir = crate::common::scratch("no-summary");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("cierva.toml"), "format_version = 1\n").unwrap();
    let suite = cierva_harness::suite::Suite::open(&dir).unwrap();
    let err = summary::load(&suite).unwrap_err();
    assert!(
        err.path.ends_with("reports/uncertainty-summary.yaml")
            && err.message.contains("--write-summary"),
        "{}",
        err.render()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A summary whose cases are not the suite's cases with validation checks (one added or
/// renamed since it was written) is stale, found without the run; the message says what to
/// rerun.
#[test]
fn a_summary_whose_cases_are_not_the_suites_is_stale() {
    use cierva_harness::uncertainty::summary;
    let s = small_summary();
    summary::check_cases(&s, &["trim-trend", "table-2"]).unwrap();
    let err = summary::check_cases(&s, &["table-2", "trim-trend", "new-case"]).unwrap_err();
    assert!(
        err.contains("no verdicts for `new-case`")
            && err.contains("cierva uncertainty --samples 64 --seed 0 --write-summary"),
        "{err}"
    );
    let err = summary::check_cases(&s, &["table-2"]).unwrap_err();
    assert!(
        err.contains("verdicts for `trim-trend`, which are not"),
        "{err}"
    );
}

/// What [`small_summary`] is written as.
const SMALL_SUMMARY_FILE: &str = "\
# Written by `cierva uncertainty --samples 64 --seed 0 --write-summary`:
# the ASME V&V 20 verdict of each validation quantity, per case (harness/src/uncertainty/
# summary.rs). The README's and docs/uncertainty.md's \"How sure\" sections are generated
# from it; CI reruns the command and fails when the file moves. Do not edit by hand.
samples: 64
seed: 0
method: auto
cases:
  table-2:
    method: sampled
    inputs: 16
    evaluations: 1154
    failed_points: 3
    agrees:
    - Y_v
    model_form_error:
    - L_p
    - L_v
    - N_v
    inconclusive:
    - N_r
    - Y_r
    - L_r
    - N_p
    no_data_uncertainty:
    - T_ph
    without_verdict: []
    fragile:
    - quantity: Y_v
      passes_percent: 63
      flipped_by:
      - fin.area_m2
  trim-trend:
    method: none
    inputs: 0
    evaluations: 1
    failed_points: 0
    agrees: []
    model_form_error: []
    inconclusive: []
    no_data_uncertainty: []
    without_verdict:
    - trends stick
    - trends nose
    fragile: []
";

/// A first-order propagation's surrogate interval does not judge a model-form error (issue 51,
/// item 4): its residual term rests on four draws, too few to bound its tails. TR 515's row 1
/// C_D (`|E|` 0.0199 against `2 u_val` 0.0212) was called a model-form error by the surrogate's
/// interval alone; now only `|E| > 2 u_val` can call one, and the row is judged by it.
#[test]
fn a_first_order_surrogates_interval_does_not_judge_a_model_form_error() {
    use cierva_harness::uncertainty::propagate::{Propagation, PropagationSettings};
    use cierva_harness::uncertainty::vv20::Vv20Verdict;
    let root = super::common::repo_root();
    let mut case =
        cierva_harness::suite::case::load(&root.join("cases/naca-tr515-table-iii.yaml")).unwrap();
    case.checks.retain(|c| c.id == "row-01");
    let settings = PropagationSettings {
        samples: 16,
        seed: 0,
        validation_only: true,
        method: Propagation::Auto,
    };
    let u = cierva_harness::uncertainty::study::propagate(&case, settings, || {}).unwrap();
    assert!(u.method.starts_with("first order"), "{}", u.method);
    let drag = u
        .results
        .iter()
        .find(|r| r.quantity == "drag_coefficient")
        .unwrap();
    let (e, u_val) = (drag.estimate_error.unwrap().abs(), drag.u_val.unwrap());
    assert!(e <= 2.0 * u_val, "{drag:?}");
    assert_ne!(
        drag.verdict,
        Some(Vv20Verdict::ModelFormError),
        "{}",
        drag.reason
    );
    assert!(
        !drag.reason.contains("spread the model one way"),
        "{}",
        drag.reason
    );
}
