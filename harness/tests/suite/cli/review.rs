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
