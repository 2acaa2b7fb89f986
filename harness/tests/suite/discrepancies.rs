//! Known discrepancies catch regressions: a case whose checks are all expected failures still
//! fails when the model moves, and an evaluation error fails whatever the case expects.

use cierva_harness::suite::case::{self, Case, Subject};
use cierva_harness::suite::outcome::{self, Outcome};
use cierva_model::components::airfoil::Airfoil;

/// The TR 515 case with only a few rows (the whole table takes seconds).
fn tr515(rows: &[&str]) -> Case {
    let mut c = case::load(&super::common::repo_root().join("cases/naca-tr515-table-iii.yaml"))
        .expect("the shipped case loads");
    c.checks.retain(|k| rows.contains(&k.id.as_str()));
    assert_eq!(c.checks.len(), rows.len());
    assert!(
        c.recorded.is_some(),
        "the case's discrepancies are recorded"
    );
    c
}

fn outcomes(c: &Case) -> Vec<(String, Outcome, Vec<String>)> {
    outcome::run_case(c)
        .into_iter()
        .map(|r| (r.check, r.outcome, r.departures))
        .collect()
}

const ROWS: [&str; 3] = ["row-01", "row-40", "row-81"];

#[test]
fn the_shipped_rotor_gives_its_recorded_discrepancies() {
    for (id, o, d) in outcomes(&tr515(&ROWS)) {
        assert_eq!(o, Outcome::ExpectedFailure, "{id}: {d:?}");
    }
}

/// A deliberate regression: the PCA-2's lift slope 2 % lower. Every row is still an expected
/// failure by its text, and every row now fails as a moved discrepancy.
#[test]
fn a_changed_rotor_constant_fails_every_row_as_a_moved_discrepancy() {
    let mut c = tr515(&ROWS);
    let Subject::Rotor { file, .. } = &mut c.subject else {
        panic!("TR 515 is a rotor case")
    };
    let Airfoil::Analytical(section) = &mut file.rotor.airfoil else {
        panic!("the PCA-2 has an analytical section")
    };
    section.lift_slope_per_rad *= 0.98;
    for (id, o, d) in outcomes(&c) {
        assert_eq!(o, Outcome::DiscrepancyMoved, "{id}");
        assert!(
            d.iter().any(|s| s.contains("recorded")),
            "{id}: the departure names both numbers: {d:?}"
        );
    }
}

/// A broken model (a non-number in the rotor) is an error, even in a check that is expected
/// to fail.
#[test]
fn an_error_fails_an_expected_failure() {
    let mut c = tr515(&["row-01"]);
    let Subject::Rotor { file, .. } = &mut c.subject else {
        panic!("TR 515 is a rotor case")
    };
    file.rotor.tip_loss_factor = f64::NAN;
    let r = outcome::run_case(&c);
    assert_eq!(r[0].outcome, Outcome::Error, "{}", r[0].explain());
    assert!(!r[0].outcome.ok());
}

/// Without a record, an expected failure is not taken on trust.
#[test]
fn an_unrecorded_expected_failure_is_a_moved_discrepancy() {
    let mut c = tr515(&["row-01"]);
    c.recorded = None;
    let (_, o, d) = outcomes(&c).remove(0);
    assert_eq!(o, Outcome::DiscrepancyMoved);
    assert!(d[0].contains("nothing is recorded"), "{d:?}");
}

/// The same regression on a whole regime of the table makes its score worse than committed,
/// which fails `naca-tr515-table-iii::scores`. (That the shipped rotor scores as committed is
/// that trial's own check; it is not run a second time here.) The regime at mu <= 0.35 alone
/// is run: its score is the one judged, and the angle searches above it would add a minute.
#[test]
fn a_changed_rotor_constant_worsens_the_tr515_scoreboard() {
    use cierva_harness::suite::scoreboard::{self, Change};
    use cierva_harness::suite::validation;
    let mut c = case::load(&super::common::repo_root().join("cases/naca-tr515-table-iii.yaml"))
        .expect("the shipped case loads");
    let regime = c
        .scores
        .iter()
        .find(|s| s.id == "low-mu-lift-rms")
        .and_then(|s| s.checks.clone())
        .expect("the case scores C_L over its low-mu regime");
    c.checks.retain(|k| regime.contains(&k.id));
    c.scores.retain(|s| s.checks.as_ref() == Some(&regime));
    assert_eq!(c.checks.len(), 48);
    let board = scoreboard::load(&super::common::suite()).expect("the scoreboard loads");
    let judge =
        |c: &Case| validation::validate(vec![Ok(c.clone())], &Default::default()).judged(&board);
    let Subject::Rotor { file, .. } = &mut c.subject else {
        panic!("TR 515 is a rotor case")
    };
    let Airfoil::Analytical(section) = &mut file.rotor.airfoil else {
        panic!("the PCA-2 has an analytical section")
    };
    section.lift_slope_per_rad *= 0.98;
    let worse: Vec<String> = judge(&c)
        .iter()
        .filter(|j| j.change == Change::Worse)
        .map(|j| j.score.id.clone())
        .collect();
    assert!(
        worse.contains(&"low-mu-lift-rms".to_string()),
        "C_L is already low: a smaller lift slope makes it worse ({worse:?})"
    );
}

/// Checks shared out across cores give each case what running it alone gives: its selected
/// checks, in its order, with the same values and outcomes.
#[test]
fn checks_run_on_every_core_give_each_case_its_own_results() {
    let (a, b) = (
        tr515(&["row-01", "row-40", "row-81"]),
        tr515(&["row-02", "row-33"]),
    );
    let skip = "row-40";
    let ran = outcome::run_cases(&[&a, &b], |_, k| k.id != skip, |_, _| {});
    assert_eq!(ran.len(), 2);
    for (case, (results, seconds)) in [&a, &b].into_iter().zip(&ran) {
        let alone: Vec<_> = outcome::run_case(case)
            .into_iter()
            .filter(|r| r.check != skip)
            .collect();
        assert_eq!(results.len(), alone.len(), "{}", case.id);
        assert!(*seconds > 0.0);
        for (r, s) in results.iter().zip(&alone) {
            assert_eq!((&r.check, r.outcome), (&s.check, s.outcome));
            let values = |r: &outcome::CheckResult| -> Vec<u64> {
                r.quantities.iter().map(|q| q.value.to_bits()).collect()
            };
            assert_eq!(values(r), values(s), "{}", r.check);
        }
        assert!(results.iter().any(|r| !r.quantities.is_empty()));
    }
}

/// The committed scoreboard and discrepancy records are what the acceptance log's last entry
/// accepted (`reports/acceptances.yaml`): a score or a record changed by hand, or accepted
/// without its log entry, fails here.
#[test]
fn the_committed_scores_and_records_are_the_last_accepted() {
    let reports = super::common::repo_root().join("reports");
    if let Err(e) = cierva_harness::suite::review::acceptance_state(&reports) {
        panic!("{e}");
    }
}

/// The check above catches a hand edit: the committed files copied, the copy passes; a value
/// changed in the scoreboard, a record changed, added or removed, or the log's last entry
/// missing, each fails it with the file named.
#[test]
fn a_hand_edited_scoreboard_is_not_what_was_accepted() {
    use cierva_harness::suite::review::{LOG_FILE, acceptance_state};
    let from = super::common::repo_root().join("reports");
    let dir = crate::common::scratch("accepted");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("discrepancies")).unwrap();
    for f in ["scoreboard.yaml", LOG_FILE] {
        std::fs::copy(from.join(f), dir.join(f)).unwrap();
    }
    let mut records = Vec::new();
    for e in std::fs::read_dir(from.join("discrepancies")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.join("discrepancies").join(p.file_name().unwrap())).unwrap();
        records.push(p.file_name().unwrap().to_string_lossy().into_owned());
    }
    assert!(!records.is_empty());
    assert_eq!(acceptance_state(&dir), Ok(()), "the copy is as accepted");
    let fails_naming = |file: &str, why: &str| {
        let e = acceptance_state(&dir).expect_err("an edit fails the check");
        assert!(e.contains(&format!("{file}: {why}")), "{e}");
    };
    // A score edited by hand: 5.2e-2 becomes 15.2e-2.
    let board = dir.join("scoreboard.yaml");
    let text = std::fs::read_to_string(&board).unwrap();
    assert!(text.contains("{value: "));
    std::fs::write(&board, text.replacen("{value: ", "{value: 1", 1)).unwrap();
    fails_naming("scoreboard.yaml", "differs from what was accepted");
    std::fs::write(&board, &text).unwrap();
    assert_eq!(acceptance_state(&dir), Ok(()));
    // A record edited, removed, or one never accepted.
    let record = dir.join("discrepancies").join(&records[0]);
    let rec = std::fs::read_to_string(&record).unwrap();
    std::fs::write(&record, rec.replacen("value: ", "value: 1", 1)).unwrap();
    fails_naming(&format!("discrepancies/{}", records[0]), "differs");
    std::fs::remove_file(&record).unwrap();
    fails_naming(
        &format!("discrepancies/{}", records[0]),
        "accepted, now missing",
    );
    std::fs::write(dir.join("discrepancies/new-case.yaml"), &rec).unwrap();
    fails_naming("discrepancies/new-case.yaml", "never accepted");
    // No log, no acceptance.
    std::fs::remove_file(dir.join(LOG_FILE)).unwrap();
    let e = acceptance_state(&dir).unwrap_err();
    assert!(e.contains("no acceptance logged"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
