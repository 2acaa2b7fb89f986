//! Tests of the harness library's parts, one module per source module (they were its unit
//! tests; here they build into the one test binary instead of a second build of the library).

mod quantity {
    use cierva_harness::inputs::quantity::*;

    #[test]
    fn names_are_unique_and_unit_suffixed_where_they_have_units() {
        let mut seen = std::collections::BTreeSet::new();
        for q in Quantity::ALL {
            assert!(seen.insert(q.name()), "{} twice", q.name());
            assert_eq!(Quantity::parse(q.name()), Some(*q));
            let suffix = match q.unit() {
                "deg" => Some("_deg"),
                "m/s" => Some("_m_s"),
                "rad/s" => Some("_rad_s"),
                "rpm" => Some("_rpm"),
                "s" => Some("_s"),
                "N" => Some("_n"),
                "N m" => Some("_n_m"),
                "%" => Some("_percent"),
                _ => None,
            };
            if let Some(s) = suffix {
                assert!(
                    q.name().ends_with(s),
                    "{} ({}) lacks {s}",
                    q.name(),
                    q.unit()
                );
            }
        }
    }
}

mod scoreboard {
    use cierva_harness::suite::scoreboard::*;

    fn score(value: f64, metric: Metric) -> Score {
        Score {
            case: "c".into(),
            id: "s".into(),
            metric,
            quantity: Some("rpm".into()),
            value,
            count: 3,
            noise_floor: 1e-3,
            reason: "test".into(),
        }
    }

    #[test]
    fn worse_is_worse_beyond_the_noise_floor_either_way_round() {
        let c = Committed {
            value: 0.10,
            better: Better::Lower,
            noise_floor: 1e-3,
        };
        assert_eq!(
            change(&score(0.1005, Metric::RmsRelativeError), Some(&c)),
            Change::Same
        );
        assert_eq!(
            change(&score(0.12, Metric::RmsRelativeError), Some(&c)),
            Change::Worse
        );
        assert_eq!(
            change(&score(0.08, Metric::RmsRelativeError), Some(&c)),
            Change::Better
        );
        assert_eq!(
            change(&score(f64::NAN, Metric::RmsRelativeError), Some(&c)),
            Change::Worse
        );
        let h = Committed {
            value: 4.0,
            better: Better::Higher,
            noise_floor: 0.5,
        };
        assert_eq!(change(&score(3.0, Metric::Inside), Some(&h)), Change::Worse);
        assert_eq!(
            change(&score(5.0, Metric::Inside), Some(&h)),
            Change::Better
        );
        assert_eq!(change(&score(5.0, Metric::Inside), None), Change::New);
    }

    /// A score over a named subset of the checks (a regime of a data set) is computed from
    /// those checks alone; a peak's scores compare the largest value with the largest
    /// reference wherever each falls, and where in tip-speed ratio.
    #[test]
    fn a_score_over_named_checks_uses_those_alone() {
        use cierva_harness::checks::result::QuantityResult;
        use cierva_harness::suite::case::{CheckClass, CheckKind};
        use cierva_harness::suite::outcome::{CheckResult, Outcome};
        let result = |check: &str, value: f64| CheckResult {
            case: "c".into(),
            check: check.into(),
            kind: CheckKind::Autorotation,
            class: CheckClass::Validation,
            outcome: Outcome::Fail,
            passed: false,
            quantities: vec![QuantityResult {
                quantity: "lift_coefficient".into(),
                value,
                expected: Some(1.0),
                tolerance: "t".into(),
                allowed: "a".into(),
                reason: "r".into(),
                lower: 0.99,
                upper: 1.01,
                margin: -1.0,
                pass: false,
            }],
            verdict: None,
            error: None,
            finding: None,
            expected_failure: None,
            fingerprint: vec![],
            departures: vec![],
            note: None,
            extrapolation: None,
            calibrated_on: None,
            plot: None,
        };
        let results = [result("low", 1.1), result("high", 1.5)];
        let spec = |checks: Option<Vec<String>>| ScoreSpec {
            id: "s".into(),
            metric: Metric::RmsRelativeError,
            quantity: Some("lift_coefficient".into()),
            noise_floor: 1e-4,
            reason: "test".into(),
            checks,
        };
        let at = |_: &str| None;
        let all = cierva_harness::suite::review::compute("c", &spec(None), &results, &at);
        let low = cierva_harness::suite::review::compute(
            "c",
            &spec(Some(vec!["low".into()])),
            &results,
            &at,
        );
        assert!(
            (all.value - (0.5f64 * (0.01 + 0.25)).sqrt()).abs() < 1e-12,
            "{all:?}"
        );
        assert!((low.value - 0.1).abs() < 1e-12 && low.count == 1, "{low:?}");
        // The peaks, each placed at its check's tip-speed ratio: the model's largest value is
        // 0.9 at "high" (mu 0.45), the largest reference 1.0 at "low" (mu 0.3).
        let results = [result("low", 0.7), {
            let mut r = result("high", 0.9);
            r.quantities[0].expected = Some(0.5);
            r
        }];
        let mu = |id: &str| Some(if id == "low" { 0.3 } else { 0.45 });
        let peak = |metric, at: &dyn Fn(&str) -> Option<f64>| {
            let s = ScoreSpec {
                metric,
                ..spec(None)
            };
            cierva_harness::suite::review::compute("c", &s, &results, at).value
        };
        assert!((peak(Metric::PeakRelativeError, &mu) - 0.1).abs() < 1e-12);
        assert!((peak(Metric::PeakTipSpeedRatioOffset, &mu) - 0.15).abs() < 1e-12);
        // Without a tip-speed ratio there is no offset to give, and NaN passes nothing.
        assert!(peak(Metric::PeakTipSpeedRatioOffset, &|_| None).is_nan());
    }

    #[test]
    fn a_written_board_reads_back() {
        let b = with(
            &Board::default(),
            &["c"],
            &[score(0.1234567891, Metric::RmsRelativeError), {
                let mut s = score(f64::NAN, Metric::Inside);
                s.id = "t".into();
                s
            }],
        );
        let text = render(&b);
        let back = parse(&text).unwrap();
        assert!((back.scores["c"]["s"].value - 0.1234567891).abs() < 1e-8);
        assert!(back.scores["c"]["t"].value.is_nan());
    }

    /// Accepting a case's scores drops the ones it no longer declares (a renamed score does
    /// not linger on the board) and leaves the cases not reviewed alone.
    #[test]
    fn accepting_a_case_replaces_its_scores() {
        let mut old = score(0.2, Metric::RmsRelativeError);
        old.id = "old".into();
        let mut other = score(0.3, Metric::RmsRelativeError);
        other.case = "d".into();
        let board = with(&Board::default(), &["c", "d"], &[old, other]);
        let b = with(&board, &["c"], &[score(0.1, Metric::RmsRelativeError)]);
        assert_eq!(b.scores["c"].keys().collect::<Vec<_>>(), ["s"]);
        assert_eq!(b.scores["d"]["s"].value, 0.3);
    }
}

mod history {
    use cierva_harness::inputs::record::{Record, RecordMeta};
    use cierva_harness::inputs::reference::Provenance;
    use cierva_harness::run::replay::*;
    use std::collections::BTreeMap;

    fn record(signal: &[f64], model: &[f64]) -> (Record, Replayed) {
        let n = signal.len();
        let time_s: Vec<f64> = (0..n).map(|k| k as f64 * 0.1).collect();
        let meta = RecordMeta {
            id: "r".into(),
            title: "t".into(),
            provenance: Provenance {
                source: "test".into(),
                notes: None,
            },
            synthetic: None,
            aircraft: "a".into(),
            sample_rate_hz: 10.0,
            sensors: None,
            condition: BTreeMap::new(),
            trim: BTreeMap::new(),
            controls: vec![],
            channels: Default::default(),
            travel: Default::default(),
            excitation: Default::default(),
        };
        let rec = Record {
            path: "r.csv".into(),
            meta,
            channels: vec!["time_s".into(), "theta_deg".into()],
            data: vec![time_s.clone(), signal.to_vec()],
            notes: Vec::new(),
        };
        let mut signals = vec![vec![0.0; n]; SIGNALS.len()];
        signals[7] = model.to_vec();
        (rec, Replayed { time_s, signals })
    }

    #[test]
    fn metrics_of_a_known_error() {
        let (rec, flown) = record(&[0.0, 1.0, 2.0, 1.0], &[0.0, 1.5, 2.0, 1.0]);
        let m = compare(&rec, &flown).unwrap();
        assert_eq!(m.len(), 1);
        assert_eq!(m[0].signal, "theta_deg");
        assert!((m[0].max_abs_error - 0.5).abs() < 1e-12);
        assert!((m[0].time_of_max_s - 0.1).abs() < 1e-12);
        assert!((m[0].rms_error - 0.25).abs() < 1e-12);
        // rms(p) = sqrt(7.25/4), rms(m) = sqrt(6/4).
        let theil = 0.25 / ((7.25f64 / 4.0).sqrt() + 1.5f64.sqrt());
        assert!((m[0].theil - theil).abs() < 1e-12);
    }

    #[test]
    fn nan_fails_every_metric() {
        let (rec, flown) = record(&[0.0, 1.0, 2.0], &[0.0, f64::NAN, 2.0]);
        let m = compare(&rec, &flown).unwrap();
        assert!(m[0].max_abs_error.is_nan());
        assert!(m[0].rms_error.is_nan());
    }
}

mod fourier {
    use cierva_harness::ident::fourier::*;
    use rustfft::num_complex::Complex64 as C;

    #[test]
    fn direct_transform_matches_an_analytic_pair() {
        // x(t) = exp(-a t) on [0, T]: X(w) = (1 - exp(-(a + i w) T)) / (a + i w).
        let (a, dt, n) = (0.7, 0.01, 4001);
        let x: Vec<f64> = (0..n).map(|k| (-a * k as f64 * dt).exp()).collect();
        let t = (n - 1) as f64 * dt;
        for w in [0.1, 1.0, 5.0] {
            let s = C::new(a, w);
            let exact = (C::new(1.0, 0.0) - (-s * t).exp()) / s;
            let got = transform(&x, dt, &[w])[0];
            // The trapezoidal rule's error is about dt^2 |f'(T) - f'(0)| / 12, here
            // dt^2 |s| / 12 against |X| ~ 1 / |s|: relative dt^2 |s|^2 / 12. Allow twice that.
            let bound = dt * dt * s.norm_sqr() / 6.0;
            assert!(
                (got - exact).norm() < bound * exact.norm(),
                "w {w}: {got} vs {exact}"
            );
        }
    }

    #[test]
    fn chirp_z_equals_the_direct_sum() {
        let x: Vec<f64> = (0..3000)
            .map(|k| ((k as f64) * 0.013).sin() * (1.0 + 0.001 * k as f64))
            .collect();
        let (w0, dw, m) = (0.3, 0.05, 200);
        let fast = transform_uniform(&x, 0.01, w0, dw, m);
        let omegas: Vec<f64> = (0..m).map(|k| w0 + k as f64 * dw).collect();
        let slow = transform(&x, 0.01, &omegas);
        for (a, b) in fast.iter().zip(&slow) {
            assert!((a - b).norm() < 1e-9 * (1.0 + b.norm()), "{a} vs {b}");
        }
    }

    #[test]
    fn a_prepared_chirp_z_serves_many_signals_and_other_lengths() {
        let (w0, dw, m, dt) = (0.2, 0.04, 120, 0.01);
        let plan = ChirpZ::new(2000, dt, w0, dw, m);
        let omegas: Vec<f64> = (0..m).map(|k| w0 + k as f64 * dw).collect();
        for (n, f) in [(2000usize, 0.011), (2000, 0.027), (1500, 0.019)] {
            let x: Vec<f64> = (0..n).map(|k| (k as f64 * f).cos() + 0.3).collect();
            let fast = plan.apply(&x);
            let slow = transform(&x, dt, &omegas);
            assert_eq!(fast.len(), m);
            for (a, b) in fast.iter().zip(&slow) {
                assert!(
                    (a - b).norm() < 1e-9 * (1.0 + b.norm()),
                    "n {n}: {a} vs {b}"
                );
            }
        }
        assert_eq!(plan.len(), 2000);
        assert!(
            ChirpZ::new(0, dt, w0, dw, m)
                .apply(&[])
                .iter()
                .all(|c| c.norm() == 0.0)
        );
    }

    #[test]
    fn hann_derivative_is_consistent() {
        let (w, dw) = hann(1001, 0.01);
        for k in 1..1000 {
            let fd = (w[k + 1] - w[k - 1]) / 0.02;
            assert!((fd - dw[k]).abs() < 1e-3);
        }
        assert_eq!(w[0], 0.0);
    }
}

mod estimate {
    use cierva_harness::ident::estimate::*;

    #[test]
    fn t_quantiles_match_the_tables() {
        // Tables of Student's t, 97.5 %: dof 5, 10, 30, 120.
        for (dof, t) in [(5, 2.571), (10, 2.228), (30, 2.042), (120, 1.980)] {
            assert!(
                (student_t_975(dof) - t).abs() < 0.01 * t,
                "{dof}: {}",
                student_t_975(dof)
            );
        }
    }
}

mod linear {
    use cierva_harness::checks::Expectation;
    use cierva_harness::checks::linear::*;
    use cierva_harness::checks::mode::ModeCheck;
    use cierva_harness::checks::tolerance::{RoundingSpec, Tolerance, ToleranceKind};
    use cierva_model::{LinearModel, ModeKind};

    /// The `rounding` bound is a first-order worst case over every sign combination, so random
    /// corner perturbations of the printed matrix (every entry moved by +-half a unit) must stay
    /// within it (allowing 10 % for second-order effects), and the worst of them should come
    /// close to it (the bound is not loose).
    #[test]
    fn rounding_bound_covers_random_corner_perturbations() {
        let r = cierva_harness::inputs::reference::load(
            &crate::common::repo_root().join("flight-refs/seed002-vpm-m16-60kn.yaml"),
        )
        .unwrap();
        let model = r.linear_model.unwrap();
        let spec = RoundingSpec {
            input_decimals: 4,
            output_decimals: 12,
        };
        let e = Expectation {
            quantity: "eigenvalue_imag_rad_s".into(),
            value: Some(0.0),
            tolerance: Tolerance {
                name: "t".into(),
                kind: ToleranceKind::Rounding(spec),
                reason: "test".into(),
                confidence: None,
                standard_deviation: None,
                degrees_of_freedom: None,
            },
        };
        let es = [e.clone()];
        for (system, mode) in [
            (System::Full, ModeKind::Phugoid),
            (System::Eq13, ModeKind::Phugoid),
            (System::Full, ModeKind::ShortPeriod),
        ] {
            let check = ModeCheck {
                mode,
                system,
                linear: LinearSetup::default(),
            };
            let nominal = check.compute(&model, None, &model, &es).unwrap();
            let v0 = nominal.get(&e.quantity).unwrap();
            let bound = propagated_rounding(&model, &check, &nominal, &es, &e).unwrap();
            // Deterministic pseudo-random signs (64-bit LCG, fixed seed).
            let mut state: u64 = 0x5eed_0002;
            let mut worst = 0.0f64;
            for _ in 0..400 {
                let mut a = model.a().clone();
                let mut b = model.b().clone();
                for i in [0usize, 1, 2, 4] {
                    for j in 0..5 {
                        state = state
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        a[(i, j)] += if state >> 63 == 1 { 0.5e-4 } else { -0.5e-4 };
                    }
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    b[(i, 0)] += if state >> 63 == 1 { 0.5e-4 } else { -0.5e-4 };
                }
                let m = LinearModel::new(model.states().to_vec(), model.controls().to_vec(), a, b)
                    .unwrap();
                let v = check
                    .compute(&m, nominal.anchor, &m, &es)
                    .unwrap()
                    .get(&e.quantity)
                    .unwrap();
                worst = worst.max((v - v0).abs());
            }
            assert!(
                worst <= 1.1 * bound,
                "{system:?} {mode:?}: worst {worst:e} > bound {bound:e}"
            );
            assert!(
                worst >= 0.3 * bound,
                "{system:?} {mode:?}: worst {worst:e} << bound {bound:e}"
            );
        }
    }
}

mod plot {
    use cierva_harness::report::plot::*;

    #[test]
    fn draws_lines_bars_bands_and_intervals_and_refuses_nothing() {
        let f = Figure {
            title: "X_u".into(),
            x_label: "airspeed, mph".into(),
            y_label: "1/s".into(),
            series: vec![Series {
                name: "model".into(),
                points: vec![(30.0, -0.1), (50.0, -0.2), (70.0, f64::NAN)],
                style: Style::LineMarkers,
                colour: None,
            }],
            bars: vec![Bar {
                x: 50.0,
                lower: -0.3,
                upper: 1e6,
                expected: None,
            }],
            bars_name: "flight".into(),
            bands: vec![Shade {
                name: "tolerance".into(),
                points: vec![(30.0, -0.15, -0.05), (50.0, -0.25, -0.15)],
            }],
            intervals: Some(Shade {
                name: "model: 95 % of its inputs".into(),
                points: vec![(30.0, -0.12, -0.08), (50.0, f64::NAN, -0.1)],
            }),
            x_zero: false,
            log_x: false,
            stack: None,
        };
        assert_eq!(f.points(), 7);
        let svg = f.svg(400, 300).expect("drawn");
        assert!(
            svg.starts_with("<svg") && svg.contains("airspeed, mph"),
            "{svg}"
        );
        assert!(svg.contains("model: 95 % of its inputs"), "{svg}");
        assert!(svg.contains("<circle") && svg.contains("<polyline"));
        assert!(!svg.contains("NaN"));
        let empty = Figure {
            series: vec![Series {
                name: "model".into(),
                points: vec![(f64::NAN, 1.0)],
                style: Style::Line,
                colour: None,
            }],
            ..Figure::default()
        };
        assert_eq!(empty.points(), 0);
        assert!(empty.svg(400, 300).is_none());
    }

    /// An axis tick summed from a negative start lands at -2.2e-16, not 0: its label said
    /// `-0.0000000000000002220446049250313` in every report's eigenvalue plot (issue 50).
    #[test]
    fn tick_labels_are_as_long_as_the_axis_needs() {
        let near_zero = -0.6 + 0.2 + 0.2 + 0.2;
        assert_ne!(near_zero, 0.0);
        assert_eq!(tick_label(near_zero, 1.2), "0");
        assert_eq!(tick_label(-0.4, 1.2), "-0.4");
        assert_eq!(tick_label(0.25, 1.2), "0.25");
        assert_eq!(tick_label(30.0, 40.0), "30");
        assert_eq!(tick_label(0.0015, 0.004), "0.0015");
        assert_eq!(tick_label(-1e-13, 0.004), "0");
    }
}

mod text {
    use cierva_harness::units::sig;

    #[test]
    fn significant_digits() {
        assert_eq!(sig(-1.064475117, 6), "-1.06448");
        assert_eq!(sig(0.0023217, 3), "0.00232");
        assert_eq!(sig(28.6824, 6), "28.6824");
        assert_eq!(sig(-0.0, 6), "0");
        assert_eq!(sig(1.5e-7, 3), "1.50e-7");
        assert_eq!(sig(-4e-20, 3), "-4.00e-20");
        assert_eq!(sig(123456789.0, 3), "1.23e8");
    }
}

mod discrepancy {
    use cierva_harness::suite::discrepancy::*;
    use cierva_model::analysis::bcar::Verdict;
    use std::collections::BTreeMap;

    #[test]
    fn a_written_record_reads_back() {
        let mut checks = BTreeMap::new();
        checks.insert(
            "row-01".to_string(),
            Recorded {
                quantities: [("rpm".to_string(), RecordedBand::around(96.869352374, 0.99))].into(),
                verdict: Some(Verdict::DoesNotComply),
                no_equilibrium: true,
                fingerprint: [("q".to_string(), RecordedBand::around(-5.06e-6, 0.0))].into(),
            },
        );
        let r = CaseRecord {
            case: "c".into(),
            checks,
        };
        let back: CaseRecord = serde_yaml::from_str(&render(&r)).unwrap();
        let (a, b) = (&r.checks["row-01"], &back.checks["row-01"]);
        assert_eq!(a.verdict, b.verdict);
        let (x, y) = (a.quantities["rpm"], b.quantities["rpm"]);
        assert!((x.value - y.value).abs() < 1e-6 && (x.lower - y.lower).abs() < 1e-6);
        assert!(b.no_equilibrium && b.fingerprint["q"].holds(-5.06e-6));
    }

    #[test]
    fn a_band_holds_its_value_and_not_nan() {
        let b = RecordedBand::around(96.9, 0.99);
        assert!(b.holds(96.9));
        assert!(b.holds(96.905));
        assert!(!b.holds(96.92));
        assert!(!b.holds(f64::NAN));
        // The relative part wins when the tolerance is tight or absent.
        let c = RecordedBand::around(-2.0, 0.0);
        assert!((c.upper - c.lower - 4e-4).abs() < 1e-15);
        // A zero value still has a band.
        assert!(RecordedBand::around(0.0, f64::INFINITY).upper > 0.0);
    }
}

mod acceptance_log {
    use cierva_harness::suite::review::*;
    use std::collections::BTreeMap;

    fn entry(reason: &str, old: f64) -> Acceptance {
        Acceptance {
            date: utc_iso8601(1_700_000_000),
            commit: "1234567+dirty".into(),
            reason: reason.into(),
            changes: vec![
                Accepted {
                    case: "naca-tr515-table-iii".into(),
                    item: "low-mu-rpm-rms".into(),
                    old: Some(Value::Number(old)),
                    new: Some(Value::Number(0.05)),
                    direction: Direction::Better,
                    reason: Some("the hub drag's new estimate".into()),
                },
                Accepted {
                    case: "c".into(),
                    item: "row-01".into(),
                    old: None,
                    new: Some(Value::Text("rotor_rpm 96.8694; no equilibrium".into())),
                    direction: Direction::New,
                    reason: Some("row 1 is now an expected failure".into()),
                },
            ],
            fingerprint: BTreeMap::from([("scoreboard.yaml".into(), "fnv1a64:00ff".into())]),
            chain: None,
        }
    }

    /// The civil date from seconds since 1970, across a leap day and a century.
    #[test]
    fn dates_are_utc_iso_8601() {
        assert_eq!(utc_iso8601(0), "1970-01-01T00:00:00Z");
        assert_eq!(utc_iso8601(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(utc_iso8601(1_700_000_000), "2023-11-14T22:13:20Z");
        assert_eq!(utc_iso8601(4_107_542_399), "2100-02-28T23:59:59Z");
        let now = now_utc();
        assert!(now.as_str() > "2024-01-01" && now.ends_with('Z'), "{now}");
    }

    /// FNV-1a 64's published test values.
    #[test]
    fn fnv1a64_is_fnv1a64() {
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
    }

    /// Entries are appended: the bytes already written stay as they were, each entry reads
    /// back (a reason with quotes and a colon, a NaN score), and a log that does not load is
    /// refused untouched rather than rewritten.
    #[test]
    fn the_log_is_only_appended_to() {
        let dir = crate::common::scratch("acceptances");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(LOG_FILE);
        let _ = std::fs::remove_file(&path);
        let first = entry("initial: \"as committed\"", f64::NAN);
        append_log(&path, &first).unwrap();
        let once = std::fs::read_to_string(&path).unwrap();
        let second = entry("a smaller hub drag", 0.06);
        let logged = append_log(&path, &second).unwrap();
        let twice = std::fs::read_to_string(&path).unwrap();
        assert!(twice.starts_with(&once) && twice.len() > once.len());
        let log = load_log(&path).unwrap();
        assert_eq!(log.acceptances.len(), 2);
        assert_eq!(log.acceptances[1], logged);
        assert_eq!(
            Acceptance {
                chain: None,
                ..logged
            },
            second
        );
        assert_eq!(chain_state(&log), Ok(()));
        assert_eq!(log.acceptances[0].reason, first.reason);
        assert!(matches!(log.acceptances[0].changes[0].old, Some(Value::Number(x)) if x.is_nan()));
        // A hand-broken log is refused, and left as it was.
        let broken = twice.replacen("reason:", "reasn:", 1);
        std::fs::write(&path, &broken).unwrap();
        let e = append_log(&path, &second).unwrap_err();
        assert!(e.contains("reasn"), "{e}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), broken);
        // An entry without a reason does not load.
        std::fs::write(
            &path,
            twice.replacen("reason: a smaller hub drag", "reason: ' '", 1),
        )
        .unwrap();
        let e = load_log(&path).unwrap_err().to_string();
        assert!(e.contains("needs a reason"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The log is hash-chained over its entries' content (issue 51, item 8): an entry appended
    /// by hand (no link, or `changes: []` under a copied link), an earlier entry edited, or an
    /// entry removed, each breaks the chain, naming the entry; a log whose chain is broken is
    /// not appended to. Entries logged before the chain began are covered by the first link.
    #[test]
    fn an_entry_appended_or_edited_by_hand_breaks_the_chain() {
        let dir = crate::common::scratch("chain");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(LOG_FILE);
        let _ = std::fs::remove_file(&path);
        // An entry from before the chain (no link, no per-item reasons), as the repository's
        // first entries are.
        let mut old = entry("before the chain", 0.07);
        for c in &mut old.changes {
            c.reason = None;
        }
        std::fs::write(
            &path,
            format!("acceptances:\n{}", serde_yaml::to_string(&[&old]).unwrap()),
        )
        .unwrap();
        let e = chain_state(&load_log(&path).unwrap()).unwrap_err();
        assert!(e.contains("has no chain link"), "{e}");
        for reason in ["starts the chain", "a smaller hub drag"] {
            append_log(&path, &entry(reason, 0.06)).unwrap();
        }
        let good = std::fs::read_to_string(&path).unwrap();
        assert_eq!(chain_state(&load_log(&path).unwrap()), Ok(()));
        let breaks = |text: &str, says: &str| {
            std::fs::write(&path, text).unwrap();
            let log = load_log(&path).unwrap();
            let e = chain_state(&log).unwrap_err();
            assert!(e.contains(says), "{e}");
            let e = append_log(&path, &entry("after", 0.05)).unwrap_err();
            assert!(e.contains("refused"), "{e}");
            assert_eq!(std::fs::read_to_string(&path).unwrap(), text, "untouched");
        };
        // A hand-appended entry with `changes: []`, without a link and with the last link.
        let last = load_log(&path).unwrap().acceptances[2].clone();
        let hand = Acceptance {
            reason: "hand".into(),
            changes: vec![],
            chain: None,
            ..last.clone()
        };
        let appended = format!("{good}{}", serde_yaml::to_string(&[&hand]).unwrap());
        breaks(&appended, "acceptances[3]");
        breaks(&appended, "no chain link after chained entries");
        let copied = Acceptance {
            chain: last.chain.clone(),
            ..hand
        };
        breaks(
            &format!("{good}{}", serde_yaml::to_string(&[&copied]).unwrap()),
            "acceptances[3]",
        );
        // An earlier entry edited: the unchained one, or a chained one's change.
        breaks(
            &good.replacen("before the chain", "before the chain!", 1),
            "acceptances[1]",
        );
        breaks(
            &good.replacen("0.07", "0.071", 1),
            "edited, inserted or removed",
        );
        // An entry removed: the middle one.
        let log = load_log(&{
            std::fs::write(&path, &good).unwrap();
            path.clone()
        })
        .unwrap();
        let mut without = log.clone();
        without.acceptances.remove(1);
        let e = chain_state(&without).unwrap_err();
        assert!(e.contains("acceptances[1]"), "{e}");
        // A chained entry's change without its own reason does not load.
        std::fs::write(
            &path,
            good.replacen("reason: the hub drag's new estimate", "reason: ' '", 2),
        )
        .unwrap();
        let e = load_log(&path).unwrap_err().to_string();
        assert!(e.contains("needs its own reason"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Every changed item takes its own reason (issue 51, item 8): named exactly, or by a `*`
    /// in its item within its case; an item without one, a reason naming nothing that changed,
    /// and a case given by pattern are each refused with what to write.
    #[test]
    fn each_changed_item_needs_its_own_reason() {
        let parse = |s: &str| s.parse::<ItemReason>();
        let mut changes = entry("r", 0.06).changes;
        let e = assign_reasons(&mut changes, &[]).unwrap_err();
        assert!(
            e.contains("--because 'naca-tr515-table-iii/low-mu-rpm-rms=TEXT'")
                && e.contains("--because 'c/row-01=TEXT'")
                && e.contains("2 without one"),
            "{e}"
        );
        let given = [
            parse("naca-tr515-table-iii/low-mu-*=hub drag").unwrap(),
            parse("c/row-01 = a new expected failure").unwrap(),
        ];
        assign_reasons(&mut changes, &given).unwrap();
        assert_eq!(changes[0].reason.as_deref(), Some("hub drag"));
        assert_eq!(changes[1].reason.as_deref(), Some("a new expected failure"));
        // Exact beats a pattern, whatever the order.
        let given = [
            parse("c/row-*=any row").unwrap(),
            parse("c/row-01=this row").unwrap(),
            parse("naca-tr515-table-iii/*=all").unwrap(),
        ];
        assign_reasons(&mut changes, &given).unwrap();
        assert_eq!(changes[1].reason.as_deref(), Some("this row"));
        // A reason for nothing that changed.
        let mut more = given.to_vec();
        more.push(parse("c/row-02=not changed").unwrap());
        let e = assign_reasons(&mut changes, &more).unwrap_err();
        assert!(
            e.contains("`c/row-02`") && e.contains("did not change"),
            "{e}"
        );
        for (bad, says) in [
            ("*/low-mu-rpm-rms=x", "the case is named in full"),
            ("c/row-01", "no `=`"),
            ("row-01=x", "no `/`"),
            ("c/row-01=  ", "each need a text"),
        ] {
            let e = parse(bad).unwrap_err();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }
}

mod tolerance {
    use cierva_harness::checks::tolerance::*;

    #[test]
    fn margins_are_positive_inside_and_negative_outside() {
        let a = ToleranceKind::Absolute(0.1);
        assert!(judge(&a, Some(1.0), 1.05, None).unwrap().pass);
        assert!(!judge(&a, Some(1.0), 1.2, None).unwrap().pass);
        let r = ToleranceKind::Relative(0.01);
        assert!((judge(&r, Some(-2.0), -2.01, None).unwrap().margin - 0.01).abs() < 1e-12);
        let i = ToleranceKind::Interval(-0.133, -0.044);
        assert!(!judge(&i, None, -0.194, None).unwrap().pass);
        assert!(judge(&i, None, -0.1, None).unwrap().pass);
    }

    #[test]
    fn a_sign_admits_neither_zero_nor_the_other_sign() {
        let p = ToleranceKind::Sign(Sign::Positive);
        assert!(judge(&p, None, 1e-9, None).unwrap().pass);
        assert!(!judge(&p, None, 0.0, None).unwrap().pass);
        assert!(!judge(&p, None, -0.0, None).unwrap().pass);
        assert!(!judge(&p, None, -1.0, None).unwrap().pass);
        let n = ToleranceKind::Sign(Sign::Negative);
        assert!(judge(&n, None, -3.0, None).unwrap().pass);
        assert_eq!(admits(&n, None, 0.0), Some(false));
    }

    #[test]
    fn nan_never_passes() {
        for kind in [
            ToleranceKind::Absolute(f64::INFINITY),
            ToleranceKind::Relative(1e300),
        ] {
            assert!(!judge(&kind, Some(1.0), f64::NAN, None).unwrap().pass);
        }
        let i = ToleranceKind::Interval(f64::NEG_INFINITY, f64::INFINITY);
        assert!(!judge(&i, None, f64::NAN, None).unwrap().pass);
        let s = ToleranceKind::Sign(Sign::Positive);
        assert!(!judge(&s, None, f64::NAN, None).unwrap().pass);
    }

    #[test]
    fn rounding_cannot_be_judged_at_load() {
        let k = ToleranceKind::Rounding(RoundingSpec {
            input_decimals: 4,
            output_decimals: 4,
        });
        assert_eq!(admits(&k, Some(0.0), 0.0), None);
    }
}

mod yaml {
    use cierva_harness::inputs::yaml::*;
    use std::path::Path;

    const SRC: &str = "id: x\nchecks:\n  - id: a\n    kind: mode\n  - id: b\n    expect:\n      period_s:\n        value: 3\n";

    #[test]
    fn locates_nested_fields() {
        assert_eq!(locate(SRC, "id"), Some((1, 1)));
        assert_eq!(locate(SRC, "checks[1]"), Some((5, 5)));
        assert_eq!(locate(SRC, "checks[1].expect.period_s"), Some((7, 7)));
        assert_eq!(locate(SRC, "checks[0].kind"), Some((4, 5)));
        assert_eq!(locate(SRC, "checks[3]"), None);
        let flow = "a:\n  mass: {mass_kg: 1, ixx: 2,\n         iyy: 3}\n  drive: {engine: {p: 1}}\nsources:\n  mass.ixx: x\n";
        assert_eq!(locate(flow, "a.mass.ixx"), Some((2, 22)));
        assert_eq!(locate(flow, "a.mass.iyy"), Some((3, 10)));
        assert_eq!(locate(flow, "a.drive.engine.p"), Some((4, 20)));
        assert_eq!(locate(flow, "sources.mass.ixx"), Some((6, 3)));
        assert_eq!(locate(flow, "a.mass.izz"), None);
    }

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct T {
        id: String,
        mass_kg: f64,
    }

    #[test]
    fn typos_get_a_suggestion_and_a_caret() {
        let dir = crate::common::scratch("yaml");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.yaml");
        std::fs::write(&path, "id: a\nmas_kg: 3\n").unwrap();
        let e = parse::<T>(&path, "id: a\nmas_kg: 3\n").unwrap_err();
        assert!(e.message.contains("did you mean `mass_kg`?"), "{e}");
        let r = e.render();
        assert!(r.contains("2 | mas_kg: 3") && r.ends_with("| ^"), "{r}");
        assert_eq!(
            suggestion("unknown field `zzzzzz`, expected `id` or `mass_kg`"),
            None
        );
    }

    #[test]
    fn parse_errors_carry_field_line_and_column() {
        let e = parse::<T>(Path::new("f.yaml"), "id: a\nmass_kg: heavy\n").unwrap_err();
        assert_eq!(e.line, Some(2));
        assert_eq!(e.field.as_deref(), Some("mass_kg"));
        assert!(e.to_string().starts_with("f.yaml:2:"), "{e}");
        let e = parse::<T>(Path::new("f.yaml"), "id: a\nmass: 3\n").unwrap_err();
        assert!(e.message.contains("unknown field `mass`"), "{e}");
        assert_eq!(e.line, Some(2));
    }
}

mod condition {
    #[test]
    fn a_condition_takes_its_airspeed_in_any_unit() {
        let parse =
            |s: &str| serde_yaml::from_str::<cierva_harness::inputs::condition::TrimRequest>(s);
        let kn = parse("{airspeed_kn: 60.0}").unwrap();
        assert!((kn.airspeed_mph - 69.0468).abs() < 1e-4, "{kn:?}");
        let ms = parse("{airspeed_m_s: 31.2928, climb_m_s: -1.0}").unwrap();
        assert!((ms.airspeed_mph - 70.0).abs() < 1e-9 && ms.climb_m_s == -1.0);
        assert_eq!(parse("{airspeed_mph: 70.0}").unwrap().airspeed_mph, 70.0);
        let two = parse("{airspeed_mph: 70.0, airspeed_kn: 60.0}").unwrap_err();
        assert!(two.to_string().contains("exactly one airspeed"), "{two}");
        assert!(parse("{climb_m_s: 1.0}").is_err());
        assert!(parse("{airspeed_knots: 60.0}").is_err());
    }
}

mod rotor_file {
    /// `yawed_flow_drag` is optional and off; set, it needs a source like every field.
    #[test]
    fn yawed_flow_drag_is_optional_and_sourced() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .unwrap();
        let text = std::fs::read_to_string(root.join("aircraft/pca-2-rotor.yaml")).unwrap();
        let shipped =
            cierva_harness::inputs::rotor::load(&root.join("aircraft/pca-2-rotor.yaml")).unwrap();
        assert!(!shipped.rotor.yawed_flow_drag);
        let dir = crate::common::scratch("yawed");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pca-2-rotor.yaml");
        let on = text.replacen("\n  elements:", "\n  yawed_flow_drag: true\n  elements:", 1);
        std::fs::write(&path, &on).unwrap();
        let e = cierva_harness::inputs::rotor::load(&path)
            .unwrap_err()
            .render();
        assert!(e.contains("rotor.yawed_flow_drag"), "{e}");
        let sourced = on.replacen(
            "\nsources:\n",
            "\nsources:\n  yawed_flow_drag: \"Johnson 1980, ch. 5\"\n",
            1,
        );
        std::fs::write(&path, sourced).unwrap();
        let f = cierva_harness::inputs::rotor::load(&path).unwrap();
        assert!(f.rotor.yawed_flow_drag);
    }

    /// `hub_drag_area_m2` is optional (none), needs a source when given, and refuses a
    /// negative area with its field; a corrections set replaces it.
    #[test]
    fn hub_drag_area_is_optional_sourced_and_correctable() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .unwrap();
        let text = std::fs::read_to_string(root.join("aircraft/pca-2-rotor.yaml")).unwrap();
        let shipped =
            cierva_harness::inputs::rotor::load(&root.join("aircraft/pca-2-rotor.yaml")).unwrap();
        assert_eq!(shipped.rotor.hub_drag_area_m2, 0.0);
        // Without its ranges (one of which is the hub's drag: a range needs its parameter).
        let text = match text.find("\nranges:\n") {
            Some(i) => text[..=i].to_string(),
            None => text,
        };
        // The shipped file without the key and its (folded, four-space indented) source:
        // none, and it loads.
        let mut in_source = false;
        let bare: String = text
            .lines()
            .filter(|l| {
                in_source = *l == "  hub_drag_area_m2: >-" || (in_source && l.starts_with("    "));
                !in_source && *l != "  hub_drag_area_m2: 0.0"
            })
            .map(|l| format!("{l}\n"))
            .collect();
        assert!(!bare.contains("hub_drag"), "{bare}");
        let dir = crate::common::scratch("hub-drag");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("pca-2-rotor.yaml");
        std::fs::write(&path, &bare).unwrap();
        let f =
            cierva_harness::inputs::rotor::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
        assert_eq!(f.rotor.hub_drag_area_m2, 0.0);
        let with = |area: &str, source: bool| {
            let mut t = bare.replacen(
                "\n  elements:",
                &format!("\n  hub_drag_area_m2: {area}\n  elements:"),
                1,
            );
            if source {
                t = t.replacen(
                    "\nsources:\n",
                    "\nsources:\n  hub_drag_area_m2: \"estimated: a test\"\n",
                    1,
                );
            }
            std::fs::write(&path, t).unwrap();
            cierva_harness::inputs::rotor::load(&path)
        };
        let e = with("0.3", false).unwrap_err().render();
        assert!(e.contains("rotor.hub_drag_area_m2"), "{e}");
        let e = with("-0.3", true).unwrap_err().render();
        assert!(
            e.contains("hub_drag_area_m2") && e.contains("non-negative"),
            "{e}"
        );
        let mut f = with("0.3", true).unwrap();
        assert_eq!(f.rotor.hub_drag_area_m2, 0.3);
        let set = cierva_harness::inputs::corrections::CorrectionSet {
            hub_drag_area_m2: Some(0.45),
            ..Default::default()
        };
        set.apply_to_rotor(&mut f.rotor).unwrap();
        assert_eq!(f.rotor.hub_drag_area_m2, 0.45);
        assert_eq!(set.describe(), "hub_drag_area_m2=0.45");
    }

    /// The PCA-2's unloaded blade (issue 33, item 3): in TR 487's flight condition (15.04 rad/s,
    /// 1.0823 kg/m^3, axial flow) its pitch plus the model's elastic twist is TR 487's in-flight
    /// distribution (aircraft/pca-2-rotor.yaml) to 0.001 deg at every station, with 2.4 deg of
    /// twist at the tip: the twist is counted once.
    #[test]
    fn pca2_unloaded_blade_twists_to_tr487_in_flight() {
        use cierva_model::components::rotor::elastic_twist_rad;
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .unwrap();
        let load = |f: &str| {
            cierva_harness::inputs::rotor::load(&root.join(f))
                .unwrap()
                .rotor
        };
        let (flight, unloaded) = (
            load("aircraft/pca-2-rotor.yaml"),
            load("aircraft/pca-2-unloaded-rotor.yaml"),
        );
        let k = unloaded.corrections.elastic_twist_rad_per_pa;
        assert_eq!(flight.corrections.elastic_twist_rad_per_pa, 0.0);
        let (rho, tip_speed) = (1.0823, 15.04 * unloaded.radius_m);
        let tip = elastic_twist_rad(k, rho, tip_speed, 0.0, 1.0).to_degrees();
        assert!((tip - 2.4).abs() < 1e-3, "tip twist {tip} deg");
        for i in 0..=1000 {
            let x = i as f64 / 1000.0;
            if (x - 0.394).abs() < 1e-9 {
                continue; // the step: either side is checked beside it
            }
            let twisted = unloaded.pitch_rad.at(x) + elastic_twist_rad(k, rho, tip_speed, 0.0, x);
            let miss = (twisted - flight.pitch_rad.at(x)).to_degrees();
            assert!(miss.abs() < 1e-3, "at r/R {x}: {miss} deg");
        }
    }

    /// A twisting blade's equilibrium is found from either side (issue 33, item 3's fault): the
    /// unloaded PCA-2 blade at TR 515's pitch setting autorotates at mu 0.181 and 98.3 rpm
    /// (the angle found, 11.0 deg at 13.0 m/s); asked for its rotor speed at that angle and
    /// airspeed, the search must find the same 98.3 rpm. It found none: its scan from a fast
    /// rotor down met rotor speeds where the twist, growing with Omega^2, leaves the blades no
    /// periodic flapping, and took them for the slow end.
    #[test]
    fn a_twisting_blade_autorotates_at_the_angle_its_tip_speed_ratio_gives() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .unwrap();
        let rotor =
            cierva_harness::inputs::rotor::load(&root.join("aircraft/pca-2-unloaded-rotor.yaml"))
                .unwrap()
                .rotor;
        let options = cierva_model::components::autorotation::AutorotationOptions::default();
        let at_mu = cierva_harness::run::autorotation::run_autorotation_at_tip_speed_ratio(
            &rotor,
            0.181,
            98.3,
            Some(1.9),
            None,
            options,
        )
        .unwrap();
        let at_angle = cierva_harness::run::autorotation::run_autorotation(
            &rotor,
            at_mu.alpha_rad.to_degrees(),
            at_mu.airspeed_m_s,
            Some(1.9),
            None,
            options,
        )
        .unwrap_or_else(|e| {
            panic!(
                "at {:.4} deg, {:.4} m/s: {e}",
                at_mu.alpha_rad.to_degrees(),
                at_mu.airspeed_m_s
            )
        });
        assert!((at_angle.rpm - 98.3).abs() < 0.1, "{} rpm", at_angle.rpm);
    }
}

/// A score's history as a sparkline (issue 35, item 5): one dot per finite value, committed
/// values first and now last (ringed), each labelled for hover; the line spans the box; equal
/// values draw a flat line; nothing finite draws nothing.
#[test]
fn a_scores_history_is_a_sparkline_of_its_finite_values() {
    use cierva_harness::report::plot::{Spark, sparkline_svg};
    let spark = |label: &str, value: f64| Spark {
        label: label.into(),
        value,
    };
    let history = [
        spark("a1 2026-11-01", 0.5),
        spark("b2 2026-11-10", f64::NAN),
        spark("c3 2026-11-20", 0.25),
    ];
    let svg = sparkline_svg(&history, &spark("now", 0.75)).unwrap();
    assert_eq!(svg.matches("<circle").count(), 3, "{svg}");
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
    for label in ["a1 2026-11-01: 0.5", "c3 2026-11-20: 0.25", "now: 0.75"] {
        assert!(svg.contains(&format!("<title>{label}</title>")), "{svg}");
    }
    // The lowest value at the bottom (y = 30 - 4), the highest at the top (y = 4), now ringed.
    assert!(
        svg.contains("points=\"4.0,15.0 66.0,26.0 128.0,4.0 \""),
        "{svg}"
    );
    assert!(svg.contains("r=\"3\" fill=\"#ffffff\""), "{svg}");
    let flat = sparkline_svg(&[spark("a", 1.0)], &spark("now", 1.0)).unwrap();
    assert!(flat.contains("points=\"4.0,15.0 128.0,15.0 \""), "{flat}");
    assert!(sparkline_svg(&[], &spark("now", f64::NAN)).is_none());
    let alone = sparkline_svg(&[], &spark("now", 2.0)).unwrap();
    assert_eq!(alone.matches("<circle").count(), 1, "{alone}");
}

mod yaml_numbers {
    use cierva_harness::inputs::yaml;

    #[test]
    fn a_number_too_small_for_a_double_is_refused_not_read_as_zero() {
        assert_eq!(yaml::number(" 1.5e-3 "), Ok(1.5e-3));
        assert_eq!(yaml::number("0"), Ok(0.0));
        assert_eq!(yaml::number("-0.000e-999"), Ok(0.0));
        assert_eq!(yaml::number("4.9e-324"), Ok(4.9e-324));
        for bad in ["1e-400", "-2.5E-330", "0.0001e-400"] {
            let e = yaml::number(bad).unwrap_err();
            assert!(e.contains("too small for a double"), "{bad}: {e}");
        }
        assert!(
            yaml::number("1e400")
                .unwrap_err()
                .contains("not a finite number")
        );
        assert!(
            yaml::number("NaN")
                .unwrap_err()
                .contains("not a finite number")
        );
        assert!(yaml::number("x").unwrap_err().contains("not a number"));
    }

    #[test]
    fn a_json_number_that_underflows_is_located() {
        assert_eq!(
            yaml::json_underflow(r#"{"a": [1e-300, 0.0, -0e-500]}"#),
            None
        );
        // Inside a string it is text, not a number.
        assert_eq!(yaml::json_underflow(r#"{"a\"1e-400": "1e-400"}"#), None);
        let (line, column, message) =
            yaml::json_underflow("{\n  \"trim\": {\"pitch_deg\": 1e-400}\n}").unwrap();
        assert_eq!((line, column), (2, 25));
        assert!(message.contains("`1e-400`"), "{message}");
    }
}

mod grid_convergence_index {
    use cierva_harness::uncertainty::numerics::*;

    /// Agreement of an index with its closed form: rounding only.
    const ROUNDING: f64 = 1e-12;

    /// Roache's index on known answers (issue 51, item 3): a quantity `S(h) = T + C h^p`
    /// refined by `r` gives back `p` over three levels and an index of 1.25 times its true
    /// error `C h^p`; two levels give Fs 3 at the formal order; an oscillating, a diverging and
    /// a barely converging sequence (an observed order far from the formal) fall back to Fs 3
    /// on the larger difference; a quantity the refinement does not move has an index of 0.
    #[test]
    fn the_index_follows_roache() {
        let s = |h: f64, p: f64| 10.0 + 0.5 * h.powf(p);
        for (p, r) in [(2.0, 2.0), (4.0, 2.0), (1.0, 10.0), (1.5, 3.0)] {
            let t = gci("x", &[s(1.0, p), s(1.0 / r, p), s(1.0 / r / r, p)], r, p);
            assert!((t.observed_order.unwrap() - p).abs() < 1e-9, "{t:?}");
            assert_eq!(t.safety_factor, FS_OBSERVED);
            assert!((t.gci - FS_OBSERVED * 0.5).abs() < ROUNDING, "{t:?}");
        }
        // Two levels: Fs 3 at the formal order, whatever the data.
        let t = gci("x", &[s(1.0, 2.0), s(0.5, 2.0)], 2.0, 2.0);
        assert_eq!(
            (t.observed_order, t.safety_factor, t.order),
            (None, 3.0, 2.0)
        );
        assert!((t.gci - 3.0 * 0.5).abs() < ROUNDING);
        // Observed order 1 against a formal 4: not trusted, Fs 3 at order 4 on the larger step.
        let t = gci("x", &[s(1.0, 1.0), s(0.5, 1.0), s(0.25, 1.0)], 2.0, 4.0);
        assert_eq!((t.safety_factor, t.order), (3.0, 4.0));
        assert!((t.gci - 3.0 * 0.25 * 16.0 / 15.0).abs() < ROUNDING, "{t:?}");
        // Oscillating and diverging sequences.
        for values in [[1.0, 1.1, 1.05], [1.0, 1.1, 1.3]] {
            let t = gci("x", &values, 2.0, 2.0);
            assert_eq!((t.observed_order, t.safety_factor), (None, 3.0), "{t:?}");
            let larger = (values[1] - values[0])
                .abs()
                .max((values[2] - values[1]).abs());
            assert!((t.gci - 3.0 * larger * 4.0 / 3.0).abs() < ROUNDING, "{t:?}");
        }
        let t = gci("x", &[2.0, 2.0, 2.0], 2.0, 2.0);
        assert_eq!(t.gci, 0.0);
    }
}
