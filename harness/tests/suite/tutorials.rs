//! The tutorials in `docs/tutorials/` run as written (issue 35, item 4): each one's `sh` blocks,
//! in order, as one bash script with `set -euo pipefail`, in a fresh temporary folder, with the
//! test build's `cierva` first on `PATH` and `CIERVA` the repository's root (the tutorials' "your
//! checkout of cierva"). A command that fails, or a block that no longer matches the tool, fails
//! the test with the script's output.

use std::path::{Path, PathBuf};

/// The `sh` blocks of a Markdown file, in order, joined into one script.
fn script(markdown: &str) -> String {
    let mut out = String::new();
    let mut inside = false;
    for line in markdown.lines() {
        match (inside, line.trim_end()) {
            (false, "```sh") => inside = true,
            (true, "```") => inside = false,
            (true, _) => {
                out += line;
                out.push('\n');
            }
            _ => {}
        }
    }
    out
}

/// Runs one tutorial; its exit code and output.
fn run(tutorial: &Path, dir: &Path) -> (i32, String) {
    let text = std::fs::read_to_string(tutorial).unwrap();
    let body = script(&text);
    assert!(
        !body.trim().is_empty(),
        "{}: no `sh` block",
        tutorial.display()
    );
    std::fs::create_dir_all(dir).unwrap();
    let bin = Path::new(env!("CARGO_BIN_EXE_cierva")).parent().unwrap();
    let path = std::env::join_paths(std::iter::once(bin.to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))
    .unwrap();
    let out = std::process::Command::new("bash")
        .args(["-euo", "pipefail", "-c", &body])
        .current_dir(dir)
        .env("PATH", path)
        .env("CIERVA", super::common::repo_root())
        .output()
        .expect("bash runs");
    (
        out.status.code().unwrap_or(-1),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

/// Every tutorial runs as written, to exit code 0.
#[test]
#[ignore = "slow (the tutorials fly, retune and sample the aircraft: about a minute in a test build): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn the_tutorials_run_as_written() {
    let folder = super::common::repo_root().join("docs/tutorials");
    let mut tutorials: Vec<PathBuf> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    tutorials.sort();
    assert!(tutorials.len() >= 4, "{tutorials:?}");
    let root = crate::common::scratch("tutorials");
    let _ = std::fs::remove_dir_all(&root);
    let mut failed = Vec::new();
    for t in &tutorials {
        let name = t.file_stem().unwrap().to_string_lossy().into_owned();
        let (code, output) = run(t, &root.join(&name));
        eprintln!("{name}: exit {code}");
        if code != 0 {
            let tail: Vec<&str> = output.lines().rev().take(40).collect();
            let tail: Vec<&str> = tail.into_iter().rev().collect();
            failed.push(format!("{name}: exit {code}\n{}", tail.join("\n")));
        }
    }
    let _ = std::fs::remove_dir_all(&root);
    assert!(failed.is_empty(), "{}", failed.join("\n\n"));
}

/// The script is the `sh` blocks only, in order: text and other blocks are left out.
#[test]
fn a_tutorials_script_is_its_sh_blocks_in_order() {
    let md = "# T\n\ntext\n\n```sh\necho one\n```\n\n```yaml\nno: 1\n```\n\n```sh\necho two\n```\n";
    assert_eq!(script(md), "echo one\necho two\n");
}

/// The README stays a newcomer's page (issue 35, item 4): at most 250 lines, the rest in `docs/`.
#[test]
fn the_readme_is_at_most_250_lines() {
    let readme = std::fs::read_to_string(super::common::repo_root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= README_MAX_LINES, "README.md: {lines} lines");
}

/// The issue's bound on the README's length.
const README_MAX_LINES: usize = 250;
