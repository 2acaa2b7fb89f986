//! The layout's rules, checked on the source: no module of the harness library depends on
//! itself through others, `main.rs` is dispatch only, no function runs past 120 lines
//! without saying why in a comment that starts `Long:` (in its doc comment or first lines), and
//! each public type name is defined once across both crates.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// What `lib.rs` re-exports at the crate's top, item by item: `pub use run::*` (every item of
/// the module, by glob) or `pub use units::{FT_TO_M, ...}`: `(name or "*", module)`.
fn reexports(lib: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for line in lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub use "))
    {
        let line = line.trim_end_matches(';');
        let module = line.split("::").next().unwrap_or("").to_string();
        let tail = &line[module.len()..].trim_start_matches("::");
        let names = tail.trim_start_matches('{').trim_end_matches('}');
        for name in names.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let name = name.rsplit("::").next().unwrap_or(name);
            out.push((name.to_string(), module.clone()));
        }
    }
    out
}

/// `lib.rs` holds module declarations only (the layout issue, item 1; its re-exports went with
/// issue 49, `the_crate_root_re_exports_nothing`): nothing of its own that a module could reach
/// back for.
#[test]
fn lib_only_declares_modules() {
    let lib =
        std::fs::read_to_string(super::common::repo_root().join("harness/src/lib.rs")).unwrap();
    let items: Vec<&str> = lib
        .lines()
        .map(str::trim)
        .filter(|l| !(l.is_empty() || l.starts_with("//")))
        .filter(|l| !l.starts_with("pub mod "))
        .collect();
    assert!(
        items.is_empty(),
        "lib.rs holds more than declarations: {items:?}"
    );
}

/// The harness library's top-level modules and the ones each names as `crate::<module>`, or as
/// `crate::<item>` that `lib.rs` re-exports from that module (so that no module reaches through
/// the crate's top to one that depends on it).
fn module_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = super::common::repo_root().join("harness/src");
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    let reexported = reexports(&lib);
    // A module's public items, for the glob re-exports (`pub use run::*`): every `pub fn`,
    // `pub struct`, `pub enum`, `pub const`, `pub type` and `pub use` name in its files.
    let items_of = |module: &str| -> BTreeSet<String> {
        let mut files = Vec::new();
        let dir = src.join(module);
        if dir.is_dir() {
            rust_files(&dir, &mut files);
        } else {
            files.push(src.join(format!("{module}.rs")));
        }
        let mut names = BTreeSet::new();
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap_or_default();
            for line in text.lines().map(str::trim_start) {
                for kw in [
                    "pub fn ",
                    "pub struct ",
                    "pub enum ",
                    "pub const ",
                    "pub type ",
                ] {
                    if let Some(rest) = line.strip_prefix(kw) {
                        let name: String = rest
                            .chars()
                            .take_while(|c| c.is_alphanumeric() || *c == '_')
                            .collect();
                        names.insert(name);
                    }
                }
                if let Some(rest) = line.strip_prefix("pub use ") {
                    let list = rest.trim_end_matches(';');
                    for n in list.split([',', '{', '}', ' ']).map(str::trim) {
                        let n = n.rsplit("::").next().unwrap_or(n);
                        if !n.is_empty() && n != "as" && n != "*" {
                            names.insert(n.to_string());
                        }
                    }
                }
            }
        }
        names
    };
    let mut via_top: BTreeMap<String, String> = BTreeMap::new();
    for (name, module) in &reexported {
        if name == "*" {
            for item in items_of(module) {
                via_top.insert(item, module.clone());
            }
        } else {
            via_top.insert(name.clone(), module.clone());
        }
    }
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in &files {
        let rel = f
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if rel == "lib.rs"
            || rel == "main.rs"
            || rel.starts_with("cli/")
            || rel.ends_with("_tests.rs")
        {
            continue;
        }
        let module = rel
            .split('/')
            .next()
            .unwrap()
            .trim_end_matches(".rs")
            .to_string();
        let text = std::fs::read_to_string(f).unwrap();
        let deps = graph.entry(module.clone()).or_default();
        for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
            for part in line.split("crate::").skip(1) {
                let word: String = part
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                // A module by name, or an item re-exported at the top from its module.
                let name = via_top.get(&word).cloned().unwrap_or(word);
                if !name.is_empty() && name != module {
                    deps.insert(name);
                }
            }
        }
    }
    let names: BTreeSet<String> = graph.keys().cloned().collect();
    for deps in graph.values_mut() {
        deps.retain(|d| names.contains(d));
    }
    graph
}

#[test]
fn no_module_depends_on_itself_through_others() {
    let graph = module_graph();
    assert!(graph.len() >= 12, "{graph:?}");
    // Items named through the crate's top count against the module they come from: the checks
    // run the model by `crate::run::linearise::linearise_cached` (in `run`) and read `crate::inputs::condition::TrimRequest` (in
    // `inputs`).
    assert!(
        graph["checks"].contains("run") && graph["checks"].contains("inputs"),
        "{:?}",
        graph["checks"]
    );
    let mut cycles = Vec::new();
    for start in graph.keys() {
        let mut stack = vec![vec![start.clone()]];
        while let Some(path) = stack.pop() {
            let last = path.last().unwrap();
            for d in &graph[last] {
                if d == start {
                    cycles.push(format!("{} -> {start}", path.join(" -> ")));
                } else if !path.contains(d) {
                    let mut p = path.clone();
                    p.push(d.clone());
                    stack.push(p);
                }
            }
        }
    }
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

/// A function of either crate: its name, file, first line, length in lines, and whether a
/// `Long:` comment (in its doc comment or its first three lines) says why it is long.
type Function = (String, String, usize, usize, bool);

/// Every function of both crates.
fn functions() -> Vec<Function> {
    let root = super::common::repo_root();
    let mut files = Vec::new();
    rust_files(&root.join("harness/src"), &mut files);
    rust_files(&root.join("model/src"), &mut files);
    let mut out = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let mut i = 0;
        while i < lines.len() {
            let l = lines[i];
            let indent = l.len() - l.trim_start().len();
            let t = l.trim_start();
            let t = t
                .strip_prefix("pub(crate) ")
                .or_else(|| t.strip_prefix("pub "))
                .unwrap_or(t);
            let Some(rest) = t
                .strip_prefix("fn ")
                .or_else(|| t.strip_prefix("const fn "))
            else {
                i += 1;
                continue;
            };
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            let mut open = i;
            while open < lines.len() && !lines[open].trim_end().ends_with('{') {
                if lines[open].trim_end().ends_with(';') {
                    break;
                }
                open += 1;
            }
            if open >= lines.len() || !lines[open].trim_end().ends_with('{') {
                i += 1;
                continue;
            }
            let close = (open + 1..lines.len())
                .find(|&k| {
                    let l = lines[k];
                    l.trim() == "}" && l.len() - l.trim_start().len() == indent
                })
                .unwrap_or(lines.len() - 1);
            let length = close - i + 1;
            let doc = (0..i)
                .rev()
                .take_while(|&k| {
                    let s = lines[k].trim_start();
                    s.starts_with("///") || s.starts_with("#[") || s.starts_with("//")
                })
                .any(|k| lines[k].contains("Long:"));
            let first = lines[open + 1..(open + 4).min(close)]
                .iter()
                .any(|s| s.contains("Long:"));
            let rel = f
                .strip_prefix(&root)
                .unwrap()
                .to_string_lossy()
                .into_owned();
            out.push((name, rel, i + 1, length, doc || first));
            i = open + 1;
        }
    }
    out.sort_by_key(|f| std::cmp::Reverse(f.3));
    out
}

/// A function's length past which it needs a `Long:` reason (the layout issue, item 6).
const LONG_LINES: usize = 120;

fn describe(fs: &[&Function]) -> String {
    fs.iter()
        .map(|(n, f, l, len, _)| format!("  {f}:{l} {n}: {len} lines"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// No function runs past 120 lines without a `Long:` comment saying why; no such comment is
/// left on a function that has come under the limit; at most five carry one, none in `cli/`
/// (the layout issue, item 6).
#[test]
fn no_function_runs_past_120_lines_without_a_reason() {
    let all = functions();
    let unreasoned: Vec<&Function> = all.iter().filter(|f| f.3 > LONG_LINES && !f.4).collect();
    assert!(
        unreasoned.is_empty(),
        "functions over {LONG_LINES} lines with no `Long:` comment saying why:\n{}",
        describe(&unreasoned)
    );
    let stale: Vec<&Function> = all.iter().filter(|f| f.3 <= LONG_LINES && f.4).collect();
    assert!(
        stale.is_empty(),
        "`Long:` comments on functions of {LONG_LINES} lines or fewer (remove them):\n{}",
        describe(&stale)
    );
    let long: Vec<&Function> = all.iter().filter(|f| f.3 > LONG_LINES).collect();
    assert!(
        long.len() <= 5 && !long.iter().any(|f| f.1.starts_with("harness/src/cli/")),
        "at most 5 functions over {LONG_LINES} lines, none in cli/:\n{}",
        describe(&long)
    );
}

/// The harness library's root holds its groups, not loose modules: `lib.rs`, `main.rs` and
/// folders (the layout issue, item 2).
#[test]
fn the_harness_root_holds_only_groups() {
    let src = super::common::repo_root().join("harness/src");
    let loose: Vec<String> = std::fs::read_dir(&src)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .filter(|n| n != "lib.rs" && n != "main.rs")
        .collect();
    assert!(loose.is_empty(), "loose files in harness/src: {loose:?}");
}

/// The harness library's groups, lowest first: each depends only on groups before it. Input
/// formats know nothing of running the model; identification nothing of the runners; the
/// checks nothing of the suite that holds them; fits, uncertainty and reports sit on top.
const HARNESS_LAYERS: [&str; 14] = [
    "units",
    "inputs",
    "ident",
    "run",
    "estimate",
    "synth",
    "external",
    "checks",
    "suite",
    "fit",
    "uncertainty",
    "plan",
    "report",
    "bench",
];

#[test]
fn the_harness_groups_are_layered() {
    let graph = module_graph();
    let rank = |m: &str| HARNESS_LAYERS.iter().position(|l| *l == m);
    let mut breaches = Vec::new();
    for (module, deps) in &graph {
        let Some(r) = rank(module) else {
            breaches.push(format!("{module} is in no layer"));
            continue;
        };
        for d in deps {
            if rank(d).is_none_or(|rd| rd >= r) {
                breaches.push(format!("{module} -> {d}"));
            }
        }
    }
    assert!(
        breaches.is_empty(),
        "a lower group reaches up: {breaches:?}"
    );
}

/// The sampled and the first-order propagations do not use each other (issue 49: they were an
/// import cycle): the first-order method uses what the sampled one shares, and the entry
/// points that choose between them live above both (`uncertainty/study.rs`).
#[test]
fn the_uncertainty_methods_do_not_use_each_other() {
    let text = std::fs::read_to_string(
        super::common::repo_root().join("harness/src/uncertainty/propagate.rs"),
    )
    .unwrap();
    let uses: Vec<&str> = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("//") && l.contains("first_order::"))
        .collect();
    assert!(uses.is_empty(), "propagate.rs uses first_order: {uses:?}");
}

/// The library's root declares its modules and re-exports nothing (issue 49): an item is
/// named where it lives (`crate::run::trim::run_trim`), so a reader finds it from its path; and
/// `run/` re-exports none of its modules' items.
#[test]
fn the_crate_root_re_exports_nothing() {
    let root = super::common::repo_root();
    for file in ["harness/src/lib.rs", "harness/src/run/mod.rs"] {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        let uses: Vec<&str> = text
            .lines()
            .filter(|l| l.trim_start().starts_with("pub use"))
            .collect();
        assert!(uses.is_empty(), "{file} re-exports: {uses:?}");
    }
}

/// `main.rs` is dispatch only (the layout issue, item 4): at most 150 lines, no function but
/// `main` and the broken-pipe hook, and every command a variant `X(XArgs)` whose arguments
/// (and help) live with the command in `cli/`.
#[test]
fn main_is_dispatch_only() {
    let main =
        std::fs::read_to_string(super::common::repo_root().join("harness/src/main.rs")).unwrap();
    let lines = main.lines().count();
    assert!(lines <= 150, "main.rs has {lines} lines (at most 150)");
    let functions = main.lines().filter(|l| l.starts_with("fn ")).count();
    assert!(
        functions <= 2,
        "main.rs has {functions} functions: commands belong in harness/src/cli/"
    );
    let commands = main
        .split("enum Command {")
        .nth(1)
        .and_then(|rest| rest.split("\n}").next())
        .expect("main.rs declares `enum Command`");
    let variants: Vec<&str> = commands
        .lines()
        .map(str::trim)
        .filter(|l| !(l.is_empty() || l.starts_with("//") || l.starts_with("#[")))
        .collect();
    assert!(variants.len() >= 20, "{variants:?}");
    let inline: Vec<&&str> = variants
        .iter()
        .filter(|v| {
            let Some((name, args)) = v.trim_end_matches(',').split_once('(') else {
                return true;
            };
            args.trim_end_matches(')') != format!("{name}Args")
        })
        .collect();
    assert!(
        inline.is_empty(),
        "commands not written as `X(XArgs)`: {inline:?}"
    );
}

/// A command's module in `cli/` uses the library and what `cli/mod.rs` and `cli/args.rs` share,
/// never another command's module: what two commands share moves down, so no command depends
/// on another (the architecture test's cover of `cli/`).
#[test]
fn no_command_uses_another() {
    let dir = super::common::repo_root().join("harness/src/cli");
    let mut files = Vec::new();
    rust_files(&dir, &mut files);
    let commands: Vec<String> = files
        .iter()
        .filter_map(|f| f.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .filter(|s| s != "mod" && s != "args")
        .collect();
    assert!(commands.len() >= 20, "{commands:?}");
    let mut breaches = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (n, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("//") {
                continue;
            }
            for c in &commands {
                if line.contains(&format!("super::{c}::")) || line.contains(&format!("cli::{c}::"))
                {
                    breaches.push(format!("{}:{}: {}", f.display(), n + 1, line.trim()));
                }
            }
        }
    }
    let mod_rs = std::fs::read_to_string(dir.join("mod.rs")).unwrap();
    breaches.extend(
        mod_rs
            .lines()
            .filter(|l| l.starts_with("pub mod ") || l.starts_with("pub(crate) mod "))
            .map(|l| format!("cli/mod.rs: {l} (a command's module is private)")),
    );
    assert!(breaches.is_empty(), "{}", breaches.join("\n"));
}

/// The model's groups are layered: the components know nothing of the assembled aircraft, the
/// analyses, the simulations or the estimates; the aircraft knows nothing of the simulations
/// that fly it (the full model's periodic trim is a simulation's); analysis knows nothing of
/// the aircraft or simulation; the estimates (pure methods on geometry) use no other group. (Unit
/// tests, after `#[cfg(test)]` or in a folder's `tests.rs`, may reach across: a component's test
/// may check itself against an analysis.)
#[test]
fn the_model_groups_are_layered() {
    let src = super::common::repo_root().join("model/src");
    let rules: [(&str, &[&str]); 4] = [
        (
            "components",
            &["aircraft", "analysis", "simulation", "estimate"],
        ),
        ("aircraft", &["simulation"]),
        ("analysis", &["aircraft", "simulation"]),
        (
            "estimate",
            &["aircraft", "analysis", "simulation", "components"],
        ),
    ];
    let mut breaches = Vec::new();
    for (group, forbidden) in rules {
        let mut files = Vec::new();
        rust_files(&src.join(group), &mut files);
        assert!(!files.is_empty(), "model/src/{group} has files");
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            // A folder's `tests.rs` is its `#[cfg(test)] mod tests;`: test code throughout.
            let code = if f.file_name().is_some_and(|n| n == "tests.rs") {
                ""
            } else {
                text.split("#[cfg(test)]").next().unwrap_or("")
            };
            for (n, line) in code.lines().enumerate() {
                if line.trim_start().starts_with("//") {
                    continue;
                }
                for other in forbidden {
                    if line.contains(&format!("crate::{other}::"))
                        || line.contains(&format!("crate::{other};"))
                    {
                        breaches.push(format!("{}:{}: {}", f.display(), n + 1, line.trim()));
                    }
                }
            }
        }
    }
    assert!(
        breaches.is_empty(),
        "a lower group reaches up:\n{}",
        breaches.join("\n")
    );
}

/// The harness library builds no tests of its own (`[lib] test = false`, to spare the cold
/// `cargo test` a second optimised build), so a `#[cfg(test)]` module in it would never run:
/// its tests belong in `tests/suite/`.
#[test]
fn the_harness_library_holds_no_tests_that_never_run() {
    let mut files = Vec::new();
    rust_files(&super::common::repo_root().join("harness/src"), &mut files);
    let stranded: Vec<String> = files
        .iter()
        .filter(|f| {
            std::fs::read_to_string(f)
                .unwrap()
                .lines()
                .any(|l| l.trim() == "#[cfg(test)]" || l.trim() == "#[test]")
        })
        .map(|f| f.display().to_string())
        .collect();
    assert!(stranded.is_empty(), "tests that never run: {stranded:?}");
}

/// `ARCHITECTURE.md`'s code map matches the tree: every folder and every source file of the
/// three crates (but `mod.rs`, `lib.rs` and `main.rs` beside it) is named in it, as `` `name/` `` or
/// `` `name.rs` `` (a command's module by the command's name), so a module added, moved or renamed without the map fails.
#[test]
fn the_code_map_names_every_module() {
    let root = super::common::repo_root();
    let map = std::fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap();
    let mut missing = Vec::new();
    for krate in ["harness/src", "model/src", "fft/src"] {
        let mut files = Vec::new();
        rust_files(&root.join(krate), &mut files);
        for f in files {
            let rel = f.strip_prefix(root.join(krate)).unwrap();
            let name = rel.file_name().unwrap().to_string_lossy().into_owned();
            // The commands' modules (`cli/validate.rs`) are listed by command name.
            let stem = name.trim_end_matches(".rs");
            let named = map.contains(&format!("`{name}`"))
                || (rel.starts_with("cli") && map.contains(&format!("`{stem}`")));
            if !["mod.rs", "lib.rs", "main.rs"].contains(&name.as_str()) && !named {
                missing.push(format!("{krate}/{}", rel.display()));
            }
            for dir in rel.ancestors().skip(1) {
                let Some(d) = dir.file_name() else { continue };
                let d = d.to_string_lossy();
                if !map.contains(&format!("`{d}/")) && !map.contains(&format!("{d}/`")) {
                    missing.push(format!("{krate}/{}/", dir.display()));
                }
            }
        }
    }
    missing.sort();
    missing.dedup();
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md's code map does not name: {missing:?}"
    );
}

/// Nothing outside `checks/` dispatches on a check's kind: the fit, the sensitivity study, the
/// figures, the snapshots and the generated trials ask the kind (`Evaluate::measured`,
/// `model_name`, `placed`, `snapshotted`), so a new kind is one module and one line of the
/// registry (`checks::registry!`).
#[test]
fn nothing_outside_checks_matches_on_kinds() {
    let root = super::common::repo_root();
    let mut files = Vec::new();
    rust_files(&root.join("harness/src"), &mut files);
    files.push(root.join("harness/tests/cases.rs"));
    let checks = root.join("harness/src/checks");
    let offending: Vec<String> = files
        .iter()
        .filter(|f| !f.starts_with(&checks))
        .flat_map(|f| {
            let text = std::fs::read_to_string(f).unwrap();
            let rel = f.strip_prefix(&root).unwrap().display().to_string();
            text.lines()
                .enumerate()
                .filter(|(_, l)| l.contains("What::") || l.contains("CheckKind::"))
                .map(|(i, l)| format!("{rel}:{}: {}", i + 1, l.trim()))
                .collect::<Vec<_>>()
        })
        .collect();
    assert!(
        offending.is_empty(),
        "matches on check kinds outside checks/ (ask the kind through its trait instead):\n{}",
        offending.join("\n")
    );
}

/// Each public type name (`pub struct`, `pub enum`, `pub type`, `pub trait`) is defined once
/// across both crates (the layout issue, item 7), so that a name says which type it is without
/// its path: `fit::TargetCondition` beside the model's `trim::Condition`, not two `Condition`s.
/// Private helper types local to a module (a function's `Group`, an `Entry`) are not counted.
#[test]
fn each_type_name_is_defined_once() {
    let root = super::common::repo_root();
    let mut defined: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for krate in ["harness/src", "model/src"] {
        let mut files = Vec::new();
        rust_files(&root.join(krate), &mut files);
        for f in files {
            let rel = f.strip_prefix(&root).unwrap().display().to_string();
            let text = std::fs::read_to_string(&f).unwrap();
            for line in text.lines().map(str::trim_start) {
                for kw in ["pub struct ", "pub enum ", "pub type ", "pub trait "] {
                    if let Some(rest) = line.strip_prefix(kw) {
                        let name: String = rest
                            .chars()
                            .take_while(|c| c.is_alphanumeric() || *c == '_')
                            .collect();
                        defined.entry(name).or_default().push(rel.clone());
                    }
                }
            }
        }
    }
    assert!(defined.len() > 100, "{} type names", defined.len());
    let twice: Vec<String> = defined
        .iter()
        .filter(|(_, at)| at.len() > 1)
        .map(|(name, at)| format!("{name}: {}", at.join(", ")))
        .collect();
    assert!(
        twice.is_empty(),
        "type names defined more than once (give each type its own name):\n{}",
        twice.join("\n")
    );
}

/// The pipeline "run cases, score, judge" is assembled once (issue 49):
/// `suite::validation::validate`. Outside it (and the modules that define the pieces), no code
/// of the library, the command line or the test generator runs a set of cases, scores a case
/// or judges scores (a study running one case at its design points is not a validation run).
#[test]
fn cases_are_run_scored_and_judged_in_one_place() {
    let root = super::common::repo_root();
    let mut files = Vec::new();
    rust_files(&root.join("harness/src"), &mut files);
    files.push(root.join("harness/tests/cases.rs"));
    let allowed = [
        "harness/src/suite/validation.rs",
        "harness/src/suite/outcome.rs",
        "harness/src/suite/review.rs",
    ];
    let offending: Vec<String> = files
        .iter()
        .flat_map(|f| {
            let rel = f.strip_prefix(&root).unwrap().display().to_string();
            if allowed.contains(&rel.as_str()) {
                return vec![];
            }
            let text = std::fs::read_to_string(f).unwrap();
            text.lines()
                .enumerate()
                .filter(|(_, l)| {
                    ["run_cases(", "scores_of(", "judge("].iter().any(|p| {
                        l.contains(&format!("outcome::{p}")) || l.contains(&format!("review::{p}"))
                    })
                })
                .map(|(i, l)| format!("{rel}:{}: {}", i + 1, l.trim()))
                .collect::<Vec<_>>()
        })
        .collect();
    assert!(
        offending.is_empty(),
        "cases run or scored outside suite::validation (call `validation::validate`):\n{}",
        offending.join("\n")
    );
}
