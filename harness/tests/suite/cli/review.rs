//! `cierva review`: accepting needs a reason.

use super::*;

/// `review --accept` needs a reason, and `--reason` needs `--accept`: each refused with exit 2
/// before any case runs, and nothing written.
#[test]
fn review_accept_needs_a_reason() {
    let watched = ["reports/scoreboard.yaml", "reports/acceptances.yaml"];
    let before: Vec<Option<Vec<u8>>> = watched
        .iter()
        .map(|f| std::fs::read(root().join(f)).ok())
        .collect();
    let case = "cases/seed002-vpm-m16-60kn.yaml";
    for (args, says) in [
        (
            vec!["review", "--accept", case],
            "`--accept` needs `--reason TEXT`",
        ),
        (
            vec!["review", "--accept", "--reason", " ", case],
            "`--reason` is empty",
        ),
        (
            vec!["review", "--reason", "why", case],
            "`--reason` goes with `--accept`",
        ),
    ] {
        let (code, out, err) = cierva(&args);
        assert_eq!(code, 2, "{args:?}: {out}\n{err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?}: nothing runs: {out}");
    }
    let after: Vec<Option<Vec<u8>>> = watched
        .iter()
        .map(|f| std::fs::read(root().join(f)).ok())
        .collect();
    assert_eq!(before, after, "nothing was written");
}

/// The scoreboard ratchets, item by item (issue 51, item 8), in a suite made by `cierva init`
/// with one score added to its example case:
/// - a score not committed fails `validate`; `review --accept` without a reason for the item is
///   refused with the `--because` line to fill, and writes nothing;
/// - with it, the score is committed and the log's entry is chained, with the item's reason;
/// - a better score fails `validate` until accepted, and `review --accept` writes it back, so
///   that falling back to the old value then fails as worse;
/// - a score removed from its case fails `validate` until `review --accept` drops it;
/// - an entry appended to the log by hand fails `validate`.
#[test]
fn the_scoreboard_ratchets_item_by_item() {
    use crate::common::cierva_in;
    use cierva_harness::suite::{review::acceptance_state, scoreboard};
    let dir = crate::common::scratch("ratchet");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    assert_eq!(cierva_in(&dir, &["init", "s"]).0, 0);
    let s = dir.join("s");
    let case = s.join("cases/example.yaml");
    let published = std::fs::read_to_string(&case).unwrap();
    let score = "\nscores:\n  - id: frequency-error\n    metric: rms_error\n    \
                 quantity: eigenvalue_imag_rad_s\n    noise_floor: 1.0e-7\n    \
                 reason: the phugoid's frequency against Eq. 20's\n";
    let scored = format!("{published}{score}");
    std::fs::write(&case, &scored).unwrap();
    let validate = || cierva_in(&s, &["validate", "--no-report"]);
    let (code, out, _) = validate();
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("not committed"), "{out}");
    let accept = |because: &[&str]| {
        let mut args = vec!["review", "--accept", "--reason", "the example's score"];
        for b in because {
            args.extend(["--because", b]);
        }
        cierva_in(&s, &args)
    };
    let (code, _, err) = accept(&[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--because 'example/frequency-error=TEXT'   # new"),
        "{err}"
    );
    assert!(
        !s.join("reports/acceptances.yaml").exists(),
        "nothing written"
    );
    let (code, out, err) = accept(&["example/frequency-error=the example's first score"]);
    assert_eq!(code, 0, "{out}{err}");
    assert_eq!(acceptance_state(&s.join("reports")), Ok(()));
    let log = std::fs::read_to_string(s.join("reports/acceptances.yaml")).unwrap();
    assert!(
        log.contains("reason: the example's first score") && log.contains("chain: fnv1a64:"),
        "{log}"
    );
    assert_eq!(validate().0, 0);
    let committed = || {
        scoreboard::load_file(&s.join("reports/scoreboard.yaml"))
            .unwrap()
            .scores["example"]["frequency-error"]
            .value
    };
    let first = committed();
    // Better: Eq. 20's 0.1335 read as the model's 0.1342.
    let closer = scored.replace(
        "eigenvalue_imag_rad_s: {value: 0.1335",
        "eigenvalue_imag_rad_s: {value: 0.1342",
    );
    assert_ne!(closer, scored);
    std::fs::write(&case, &closer).unwrap();
    let (code, out, _) = validate();
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("scores better than committed: example frequency-error"),
        "{out}"
    );
    let (code, out, _) = cierva_in(&s, &["review"]);
    assert_eq!(code, 1);
    assert!(
        out.contains("--because 'example/frequency-error=TEXT'   # better"),
        "{out}"
    );
    assert_eq!(accept(&["example/frequency-error=closer"]).0, 0);
    assert!(committed() < 0.1 * first, "{} {first}", committed());
    assert_eq!(validate().0, 0);
    // Back to the published value: the gain was written back, so this is worse now.
    std::fs::write(&case, &scored).unwrap();
    let (code, out, _) = validate();
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("scores worse than committed"), "{out}");
    // The score removed from its case.
    std::fs::write(&case, &published).unwrap();
    let (code, out, _) = validate();
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("example frequency-error: committed, but its case no longer declares it"),
        "{out}"
    );
    assert_eq!(
        accept(&["example/frequency-error=removed from the example"]).0,
        0
    );
    assert_eq!(validate().0, 0);
    assert_eq!(acceptance_state(&s.join("reports")), Ok(()));
    // An entry appended by hand fails `validate` too, not only the repository's `cargo test`.
    let log = s.join("reports/acceptances.yaml");
    let mut text = std::fs::read_to_string(&log).unwrap();
    text += "- date: 2026-11-29T10:00:00Z\n  commit: abc\n  reason: by hand\n  changes: []\n  fingerprint: {}\n";
    std::fs::write(&log, text).unwrap();
    let (code, out, _) = validate();
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("the acceptance log:") && out.contains("no chain link after chained entries"),
        "{out}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
