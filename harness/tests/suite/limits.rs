//! Inputs that ask for too much get a located error that states the limit, never an abort or a
//! run without end (issue 35, "Bad input", found by fuzzing the shipped files): a YAML file
//! nested too deep or too large, and a line too long to show whole.

use cierva_harness::yaml::{self, EXCERPT_CHARS, MAX_YAML_DEPTH_LEVELS, MAX_YAML_FILE_BYTES};
use std::path::{Path, PathBuf};

/// A scratch folder of this test's own.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cierva-limits-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every line of a rendered error fits a screen: the excerpt, its `...` marks and the line
/// number's gutter.
fn fits_a_screen(rendered: &str) -> bool {
    rendered
        .lines()
        .skip(1)
        .all(|l| l.chars().count() <= EXCERPT_CHARS + 20)
}

/// The fuzzer's file: a rotor file whose `rotor` is 100,000 flow mappings deep on one 400 kB
/// line. The parser took 25 s to refuse it and the error echoed the whole line; it is refused
/// before parsing, where the depth passes the limit, and the error shows a screen's width of
/// the line.
#[test]
fn a_yaml_file_nested_100000_deep_is_refused_before_parsing() {
    let dir = scratch("deep");
    let path = dir.join("deep.yaml");
    let n = 100_000;
    let text = format!("id: deep\nrotor: {}1{}\n", "{a: ".repeat(n), "}".repeat(n));
    assert!(text.len() > 400_000);
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::rotor_file::load(&path).unwrap_err();
    assert!(
        e.message.contains(&format!(
            "nested deeper than {MAX_YAML_DEPTH_LEVELS} levels"
        )),
        "{e}"
    );
    // The top mapping is the first level, `rotor`'s value the second: the 64th `{` opens the
    // 65th, at column 8 + 4 * 63.
    assert_eq!((e.line, e.column), (Some(2), Some(8 + 4 * 63)), "{e}");
    let r = e.render();
    assert!(r.len() < 1000 && fits_a_screen(&r), "{r}");
    assert!(r.contains("| ...") && r.contains("{a: {a: {a:"), "{r}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Block nesting counts as flow nesting does, and what only looks nested does not count: a
/// bracket in a quoted scalar, a comment or a block scalar.
#[test]
fn the_depth_scan_counts_collections_not_brackets() {
    let deepest = |src: &str| {
        (1..100)
            .find(|&d| yaml::too_deep(src, d).is_none())
            .unwrap()
    };
    assert_eq!(deepest("a: 1\n"), 1);
    assert_eq!(deepest("a:\n  b: [1, {c: [2]}]\n"), 5);
    assert_eq!(deepest("a:\n- - x\n  - y\n- z\n"), 3);
    assert_eq!(deepest("- a: 1\n  b:\n    - c\n"), 3);
    assert_eq!(deepest("a: \"[[[[\" # {{{{\nb: '{{''[['\n"), 1);
    assert_eq!(
        deepest("a: >-\n  [[[[ {{{{\n  ]]\nb: [\n  [1],\n  [2]]\n"),
        3
    );
    assert_eq!(deepest("a: {b: [1,\n  2], c: 3}\nd: see [1] and {2}\n"), 3);
    assert_eq!(yaml::too_deep("a:\n  b:\n    c: 1\n", 2), Some((3, 5)));
}

/// The shipped inputs (and the tests' own) nest far less than the limit: the limit leaves them
/// room and refuses none.
#[test]
fn every_shipped_yaml_file_nests_well_within_the_limit() {
    fn yaml_files(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                yaml_files(&p, out);
            } else if p.extension().is_some_and(|x| x == "yaml") {
                out.push(p);
            }
        }
    }
    let root = cierva_harness::repo_root();
    let mut files = Vec::new();
    for dir in [
        "cases",
        "aircraft",
        "flight-refs",
        "fits",
        "corrections",
        "reports",
        "harness/tests",
    ] {
        yaml_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 100, "{}", files.len());
    let (depth, deepest) = files
        .iter()
        .map(|f| {
            let src = std::fs::read_to_string(f).unwrap();
            let d = (1..=MAX_YAML_DEPTH_LEVELS)
                .find(|&d| yaml::too_deep(&src, d).is_none())
                .unwrap_or(usize::MAX);
            (d, f)
        })
        .max()
        .unwrap();
    assert!(
        depth * 8 <= MAX_YAML_DEPTH_LEVELS,
        "{} nests {depth} levels",
        deepest.display()
    );
}

/// A file larger than the limit is refused unread, with an error that says so.
#[test]
fn a_yaml_file_beyond_the_size_limit_is_refused_unread() {
    let dir = scratch("large");
    let path = dir.join("large.yaml");
    let mut text = "id: large\n".to_string();
    text.push_str(&"#".repeat(MAX_YAML_FILE_BYTES as usize));
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::rotor_file::load(&path).unwrap_err();
    assert!(
        e.message.contains("larger than 16 MiB") && e.line.is_none(),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Any error shows a screen's width of a long line, around its column, and shortens what its
/// message quotes from the file.
#[test]
fn an_error_on_a_long_line_shows_a_screens_width_of_it() {
    let dir = scratch("long");
    let path = dir.join("long.yaml");
    // A bad value in the middle of a 60 kB line.
    let values: Vec<String> = (0..20_000)
        .map(|k| {
            if k == 10_000 {
                "x".into()
            } else {
                "0.5".into()
            }
        })
        .collect();
    let text = format!(
        "id: long\ntitle: t\nprovenance: {{source: s}}\nrotor:\n  chord_m: {{r_over_r: [{}], values: [1]}}\n",
        values.join(", ")
    );
    std::fs::write(&path, &text).unwrap();
    let e = cierva_harness::rotor_file::load(&path).unwrap_err();
    let r = e.render();
    assert!(fits_a_screen(&r) && r.len() < 1000, "{r}");
    // The caret is under the bad value.
    let lines: Vec<&str> = r.lines().collect();
    let (shown, caret) = (lines[2], lines[3]);
    let at = caret.find('^').expect("a caret");
    assert_eq!(&shown[at..at + 1], "x", "{r}");

    // A value 10,000 characters long that the message quotes is shortened.
    let value = "k".repeat(10_000);
    std::fs::write(&path, format!("id: long\nrotor: {{hub: {value}}}\n")).unwrap();
    let e = cierva_harness::rotor_file::load(&path).unwrap_err();
    let shown = e.to_string();
    assert!(
        shown.contains("unknown variant `kkkk") && shown.len() < 1000,
        "{shown}"
    );
    assert!(fits_a_screen(&e.render()), "{}", e.render());
    let _ = std::fs::remove_dir_all(&dir);
}
