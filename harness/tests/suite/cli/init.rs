//! `cierva init` and `cierva new-case`: a suite anywhere.

use std::path::{Path, PathBuf};

/// A suite is a directory (issue 35, items 1 and 2). Outside any suite, `validate` is refused
/// with what to do; `init` makes one anywhere, with an example case that validates and a report
/// written into the suite, found from any folder below it or named with `--suite`; `new-case`
/// makes the folders it names and writes a case that validates (its model written out, its
/// tolerances its own). Neither writes over a file. A malformed marker is a located error.
#[test]
fn a_suite_is_a_directory_that_init_makes_anywhere() {
    use crate::common::cierva_in;
    let dir = crate::common::scratch("suite");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let (code, _, err) = cierva_in(&dir, &["validate"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("not in a cierva suite") && err.contains("cierva init"),
        "{err}"
    );
    let (code, _, err) = cierva_in(&dir, &["init", "s"]);
    assert_eq!(code, 0, "{err}");
    let s = dir.join("s");
    assert_eq!(
        walk(&s),
        ["cases/example.yaml", "cases/tolerances.yaml", "cierva.toml"].map(|f| s.join(f)),
        "init writes the marker, the tolerances and one case"
    );
    let (code, out, err) = cierva_in(&s, &["validate"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("1 check: 1 passed"), "{out}");
    assert!(
        s.join("reports/index.html").is_file(),
        "the report is the suite's"
    );
    // From a folder below, and from elsewhere with --suite.
    let (code, out, err) = cierva_in(&s.join("cases"), &["validate", "--no-report"]);
    assert_eq!(code, 0, "{out}{err}");
    let (code, out, err) = cierva_in(&dir, &["--suite", "s", "validate", "--no-report"]);
    assert_eq!(code, 0, "{out}{err}");
    // new-case makes the folders it names; the case validates as written; no overwriting.
    let (code, _, err) = cierva_in(&s, &["new-case", "cases/more/my-first-case.yaml"]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = cierva_in(&s, &["validate", "--no-report"]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("my-first-case") && out.contains("2 checks: 2 passed"),
        "{out}"
    );
    let (code, _, err) = cierva_in(&s, &["new-case", "cases/more/my-first-case.yaml"]);
    assert_eq!(code, 2);
    assert!(err.contains("not overwritten"), "{err}");
    let (code, _, err) = cierva_in(&dir, &["init", "s"]);
    assert_eq!(code, 2);
    assert!(err.contains("exists; nothing written"), "{err}");
    // A marker with a misspelt key: file, line and column; a --suite without one: named.
    std::fs::write(
        s.join("cierva.toml"),
        "format_version = 1\n[paths]\ncase = \"cases\"\n",
    )
    .unwrap();
    let (code, _, err) = cierva_in(&s, &["validate"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("cierva.toml:3:1") && err.contains("unknown field `case`"),
        "{err}"
    );
    let (code, _, err) = cierva_in(&dir, &["--suite", ".", "validate"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("not a cierva suite: no cierva.toml here"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every file under `dir`, sorted.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out.sort();
    out
}
