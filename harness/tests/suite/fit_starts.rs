//! How a fit from several starts keeps one and says what the others show (moved from
//! `fit/starts.rs`, whose unit tests never ran: the library builds no tests of its own).

use cierva_harness::fit::starts::{End, Starts, choose, warnings};
use cierva_harness::fit::{FitResult, Status};

fn ended(values: [f64; 2], cost: f64, status: Status) -> FitResult {
    FitResult {
        status,
        parameters: vec![
            cierva_harness::fit::ParameterKind::PitchOffsetDeg,
            cierva_harness::fit::ParameterKind::ProfileDragScale,
        ],
        values: values.to_vec(),
        standard_errors: vec![0.02, 0.008],
        iterations: 5,
        evaluations: 20,
        cost_start: 1000.0,
        cost,
        before: vec![],
        after: vec![],
        warnings: vec![],
        information: vec![],
        stall: None,
    }
}

/// The lowest cost is kept, the file's own on a tie; ends within a cost of 1 are the
/// equivalent ones and give the spread; a model failure and a far costlier end do not.
#[test]
fn the_best_end_is_kept_and_the_equivalent_ones_give_the_spread() {
    let start = vec![0.0, 1.0];
    let fail = Status::ModelFailure("no equilibrium".into());
    let mut results = vec![
        (
            start.clone(),
            ended([1.04, 1.168], 350.2, Status::Converged),
        ),
        (
            start.clone(),
            ended([1.06, 1.166], 349.6, Status::Converged),
        ),
        (
            start.clone(),
            ended([1.30, 1.120], 706.7, Status::Converged),
        ),
        (start.clone(), ended([0.80, 1.250], f64::NAN, fail)),
        (
            start.clone(),
            ended([1.05, 1.167], 350.7, Status::IterationLimit),
        ),
    ];
    let (best, equivalent, spread) = choose(&results);
    assert_eq!(best, 1);
    assert_eq!(equivalent, vec![0, 1]);
    assert!((spread[0] - 0.01).abs() < 1e-12 && (spread[1] - 0.001).abs() < 1e-12);
    // The file's own end is kept when nothing is lower by more than rounding.
    results[1].1.cost = 350.2 - 1e-12;
    let (best, equivalent, _) = choose(&results);
    assert_eq!(best, 0);
    assert_eq!(equivalent, vec![0, 1, 4]);
}

/// The warnings: a kept end not the file's own says so, and a spread beyond a standard
/// error says the end depends on the start; a spread within it says nothing.
#[test]
fn a_spread_beyond_a_standard_error_warns_and_one_within_does_not() {
    let end = |values: Vec<f64>, cost: f64| End {
        start: vec![0.0, 1.0],
        values,
        cost,
        status: "converged",
        evaluations: 20,
        stalled: true,
    };
    let mut s = Starts {
        parameters: vec!["pitch_offset_deg".into(), "profile_drag_scale".into()],
        ends: vec![end(vec![1.04, 1.168], 350.2), end(vec![1.06, 1.166], 349.6)],
        best: 1,
        equivalent: vec![0, 1],
        spread: vec![0.01, 0.001],
    };
    let kept = ended([1.06, 1.166], 349.6, Status::Converged);
    let w = warnings(&s, &kept);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("start 2"), "{w:?}");
    s.spread = vec![0.05, 0.001];
    let w = warnings(&s, &kept);
    assert!(
        w.iter().any(|x| x.contains("depends on the start")
            && x.contains("pitch_offset_deg")
            && x.contains("2.5 standard errors")),
        "{w:?}"
    );
    assert!(
        !w.iter().any(|x| x.contains("profile_drag_scale +-")),
        "{w:?}"
    );
}

/// A fit that stopped because every trial step left the model without an equilibrium says so
/// after its status, where a status of converged alone would read as the cost's minimum (issue
/// 51, item 6: a held-back retune ended that way at the blockage's lower bound, reduced
/// chi-square 8, and read "converged"); the solver marks it with the trial steps it lost.
#[test]
fn a_stalled_fit_says_so_after_its_status() {
    let mut r = ended([0.4, 1.7], 846.0, Status::Converged);
    assert!(!r.stalled());
    assert_eq!(r.status_described(), "converged");
    assert_eq!(r.stalled_described(), "");
    r.stall = Some(7);
    assert!(r.stalled());
    assert!(
        r.status_described()
            .starts_with("converged, but stopped at the edge of the model's equilibria"),
        "{}",
        r.status_described()
    );
    let bare = ended([0.4, 1.7], 846.0, Status::IterationLimit);
    assert!(!bare.status_described().contains("edge"));
}
