//! Malformed aircraft files get a clear, located error, never a panic: every file in
//! `tests/bad-aircraft/` is a broken copy of `aircraft/vpm-m16.yaml` whose header says what the
//! error must contain and on which line of the file it must point.

use cierva_harness::aircraft_file;
use std::path::Path;

#[test]
fn every_bad_aircraft_gets_its_located_error() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad-aircraft");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "the bad-aircraft fixtures are missing");
    let mut problems = Vec::new();
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap();
        let header = |key: &str| {
            src.lines()
                .find_map(|l| l.strip_prefix(&format!("# {key}: ")))
                .unwrap_or_else(|| panic!("{} has no `# {key}:` header", f.display()))
                .to_string()
        };
        let (want, line) = (header("error"), header("line").parse::<usize>().unwrap());
        match std::panic::catch_unwind(|| aircraft_file::load(f)) {
            Err(_) => problems.push(format!("{}: panicked", f.display())),
            Ok(Ok(_)) => problems.push(format!("{}: loaded without error", f.display())),
            Ok(Err(e)) => {
                let msg = e.to_string();
                if !msg.contains(&want)
                    || e.line != Some(line)
                    || e.column.is_none()
                    || !msg.starts_with(&f.display().to_string())
                {
                    problems.push(format!(
                        "{}:\n  got      {msg}\n  (line {:?}, column {:?})\n  expected `{want}` at line {line}",
                        f.file_name().unwrap().to_string_lossy(),
                        e.line,
                        e.column
                    ));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
