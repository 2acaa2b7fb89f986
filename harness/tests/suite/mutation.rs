//! Seeded mutation of every shipped input: each YAML and CSV file the loaders read is mutated
//! (8 times a file in the cold `cargo test`, about 800 mutants; 40 times, a few thousand in
//! all, in the full campaign of the ignored set) (a flipped bit, a deleted or duplicated line, a number replaced by
//! NaN, infinity or 1e308, a truncation) and loaded again, and cases whose subject is cheap (a
//! linear model, a derivative table) are evaluated too. Nothing may panic, and every error must
//! name the file it is about and, for a file that was read and parsed, the line and column.
//!
//! The files are copied into a scratch tree that mirrors the repository, so that relative
//! references between them (a case's `../aircraft/...`) still resolve.

use super::common::repo_root;
use cierva_harness::inputs::yaml::InputError;
use cierva_harness::inputs::{self, corrections, reference};
use cierva_harness::suite::{case, discrepancy, outcome, review, scoreboard};
use cierva_harness::{fit, ident};
use std::path::{Path, PathBuf};

/// Mutants per file in the full campaign (about 100 files): a few thousand in all.
const MUTANTS_PER_FILE: usize = 40;

/// Mutants per file in the cold `cargo test`: the first of each file's seeded stream, so the
/// cold set is a prefix of the full campaign (which `.ci/run` runs with the ignored set). The full
/// campaign took 19-23 s of the suite's processor time, the largest single test, and the cold
/// `cargo test` is held under 5 minutes on 2 cores.
const MUTANTS_PER_FILE_COLD: usize = 8;

/// A 64-bit linear congruential generator (Knuth's constants), seeded per file.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 11
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// One mutation of `text`, chosen by `rng`; `None` when it would change nothing.
fn mutate(text: &[u8], rng: &mut Lcg) -> Option<Vec<u8>> {
    let lines: Vec<&[u8]> = text.split_inclusive(|b| *b == b'\n').collect();
    let mut out = text.to_vec();
    match rng.below(6) {
        0 => {
            let i = rng.below(out.len());
            out[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = rng.below(lines.len());
            out = lines
                .iter()
                .enumerate()
                .filter(|(k, _)| *k != i)
                .flat_map(|(_, l)| l.iter().copied())
                .collect();
        }
        2 => {
            let i = rng.below(lines.len());
            out = lines
                .iter()
                .enumerate()
                .flat_map(|(k, l)| {
                    let n = if k == i { 2 } else { 1 };
                    std::iter::repeat_n(l.iter().copied(), n).flatten()
                })
                .collect();
        }
        3 | 4 => {
            // A number (a run of digits, with its sign, point and exponent) replaced.
            let starts: Vec<usize> = (0..out.len())
                .filter(|&i| {
                    out[i].is_ascii_digit() && (i == 0 || !out[i - 1].is_ascii_alphanumeric())
                })
                .collect();
            if starts.is_empty() {
                return None;
            }
            let a = starts[rng.below(starts.len())];
            let mut b = a;
            while b < out.len()
                && (out[b].is_ascii_digit() || matches!(out[b], b'.' | b'e' | b'E' | b'-' | b'+'))
            {
                b += 1;
            }
            let csv = text.starts_with(b"time_s") || !text.contains(&b':');
            let choices: &[&str] = if csv {
                &["NaN", "inf", "-inf", "1e308", "-1e308", "0", ""]
            } else {
                &[".nan", ".inf", "-.inf", "1e308", "-1e308", "0", "NaN"]
            };
            let with = choices[rng.below(choices.len())];
            out.splice(a..b, with.bytes());
        }
        _ => {
            let i = rng.below(out.len());
            out.truncate(i);
        }
    }
    (out != text).then_some(out)
}

/// What a file is, by where it lives: how to load it.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Case,
    /// The shared tolerance library.
    Library,
    Aircraft,
    Rotor,
    Reference,
    /// A time-history record (`time_history` checks) and its sidecar.
    History,
    /// A teeter record (seed 003 inflow) and its sidecar.
    Teeter,
    Fit,
    Corrections,
    Discrepancies,
    Scoreboard,
    /// The acceptance log.
    Acceptances,
}

fn kind_of(rel: &Path) -> Option<Kind> {
    let s = rel.to_string_lossy();
    let ext = rel.extension()?.to_str()?;
    Some(match (s.split('/').next()?, ext) {
        ("cases", "yaml") if s.ends_with(case::LIBRARY_FILE) => Kind::Library,
        ("cases", "yaml") => Kind::Case,
        ("aircraft", "yaml") if s.ends_with("-rotor.yaml") || s.ends_with("-propeller.yaml") => {
            Kind::Rotor
        }
        ("aircraft", "yaml") => Kind::Aircraft,
        // Read by no loader (see flight-refs/README.md): the case holds the table's rows and
        // the synthetic bounds as its own checks and tolerances.
        _ if s == "flight-refs/naca-tr515-table-iii.csv"
            || s == "flight-refs/synthetic-seed000-vpm-m16-xu-zw.yaml" =>
        {
            return None;
        }
        ("flight-refs", "csv") if s.contains("teeter") => Kind::Teeter,
        ("flight-refs", "csv") => Kind::History,
        ("flight-refs", "yaml") if repo_root().join(rel).with_extension("csv").exists() => {
            if s.contains("teeter") {
                Kind::Teeter
            } else {
                Kind::History
            }
        }
        ("flight-refs", "yaml") => Kind::Reference,
        ("fits", "yaml") => Kind::Fit,
        ("corrections", "yaml") => Kind::Corrections,
        ("reports", "yaml") if s.starts_with("reports/discrepancies/") => Kind::Discrepancies,
        ("reports", "yaml") if s == "reports/scoreboard.yaml" => Kind::Scoreboard,
        ("reports", "yaml") if s == "reports/acceptances.yaml" => Kind::Acceptances,
        _ => return None,
    })
}

/// Loads `path` as `kind` (evaluating a cheap case), turning the value into `()`.
fn load(kind: Kind, path: &Path) -> Result<(), InputError> {
    match kind {
        Kind::Case => {
            let c = case::load(path)?;
            if matches!(
                c.subject,
                case::Subject::Linear { .. } | case::Subject::Table { .. }
            ) {
                let _ = outcome::run_case(&c);
            }
        }
        Kind::Aircraft => drop(inputs::aircraft::load(path)?),
        Kind::Rotor => drop(inputs::rotor::load(path)?),
        Kind::Reference => drop(reference::load(path)?),
        Kind::History => drop(inputs::record::load_with(
            &path.with_extension("csv"),
            &["time_s"],
            true,
        )?),
        Kind::Teeter => drop(inputs::record::load_with(
            &path.with_extension("csv"),
            &ident::flap::FLAP_REQUIRED,
            false,
        )?),
        Kind::Fit => drop(fit::file::load(path)?),
        Kind::Corrections => drop(corrections::load(path)?),
        Kind::Library => drop(case::load_library(path)?),
        Kind::Discrepancies => drop(discrepancy::load_file(path)?),
        Kind::Scoreboard => drop(scoreboard::load_file(path)?),
        Kind::Acceptances => drop(review::load_log(path)?),
    }
    Ok(())
}

fn copy_tree(from: &Path, to: &Path, rel: &Path, files: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(from.join(rel)).unwrap() {
        let p = e.unwrap().path();
        let r = rel.join(p.file_name().unwrap());
        if p.is_dir() {
            std::fs::create_dir_all(to.join(&r)).unwrap();
            copy_tree(from, to, &r, files);
        } else if matches!(p.extension().and_then(|e| e.to_str()), Some("yaml" | "csv")) {
            std::fs::copy(&p, to.join(&r)).unwrap();
            files.push(r);
        }
    }
}

#[test]
fn mutated_inputs_never_panic_and_every_error_is_located() {
    campaign(MUTANTS_PER_FILE_COLD);
}

#[test]
#[ignore = "slow (the full campaign, 40 mutants a file, 19-23 s in a test build, 2026-12-01; its first 8 a file run in the cold `cargo test`, held under 5 minutes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn every_mutant_of_the_full_campaign_is_refused_with_a_located_error_or_loads() {
    campaign(MUTANTS_PER_FILE);
}

/// Mutates every shipped input `per_file` times, loads each mutant, and checks that nothing
/// panics, that every error is located, and that the loaders refuse a fair share.
fn campaign(per_file: usize) {
    let root = repo_root();
    let scratch = crate::common::scratch(&format!("mutation-{per_file}"));
    let mut files = Vec::new();
    for dir in super::common::DATA_DIRS {
        std::fs::create_dir_all(scratch.join(dir)).unwrap();
        copy_tree(&root, &scratch, Path::new(dir), &mut files);
    }
    files.sort();
    let targets: Vec<(PathBuf, Kind)> = files
        .iter()
        .filter_map(|r| kind_of(r).map(|k| (r.clone(), k)))
        .collect();
    assert!(targets.len() >= 60, "too few inputs found: {targets:?}");

    let mut problems = Vec::new();
    let (mut mutants, mut rejected) = (0usize, 0usize);
    for (n, (rel, kind)) in targets.iter().enumerate() {
        let path = scratch.join(rel);
        let original = std::fs::read(&path).unwrap();
        // The shipped file itself loads.
        if let Err(e) = load(*kind, &path) {
            problems.push(format!(
                "{}: the shipped file does not load: {e}",
                rel.display()
            ));
        }
        let mut rng = Lcg(0x5eed_0015 ^ (n as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        for _ in 0..per_file {
            let Some(m) = mutate(&original, &mut rng) else {
                continue;
            };
            std::fs::write(&path, &m).unwrap();
            mutants += 1;
            let outcome = std::panic::catch_unwind(|| load(*kind, &path));
            match outcome {
                Err(_) => problems.push(format!(
                    "{}: panicked on a mutant (kept as {}.panic)",
                    rel.display(),
                    path.display()
                )),
                Ok(Ok(())) => {}
                Ok(Err(e)) => {
                    rejected += 1;
                    let msg = e.to_string();
                    // The error names a file of the scratch tree (the mutant, or a file it
                    // references), and a file that was read has a line and column.
                    let names_file = msg.contains(scratch.to_string_lossy().as_ref())
                        || msg.contains(root.to_string_lossy().as_ref());
                    let read = e.path.exists() && e.path.is_file();
                    if !names_file || (read && e.line.is_none() && !unlocatable(&e)) {
                        problems.push(format!("{}: unlocated error: {msg}", rel.display()));
                    }
                }
            }
            if problems.last().is_some_and(|p| p.contains("panicked")) {
                std::fs::write(path.with_extension("panic"), &m).unwrap();
            }
        }
        std::fs::write(&path, &original).unwrap();
    }
    let _ = std::fs::remove_dir_all(&scratch);
    eprintln!(
        "{} files, {mutants} mutants, {rejected} rejected with an error",
        targets.len()
    );
    // Most mutations change the file (a number replaced where a file has none, or by the same
    // text, does not): at least half of those asked for.
    assert!(
        mutants >= targets.len() * per_file / 2,
        "only {mutants} mutants of {} asked for",
        targets.len() * per_file
    );
    assert!(
        rejected > mutants / 4,
        "only {rejected} of {mutants} mutants were rejected: the loaders check too little"
    );
    problems.dedup();
    assert!(
        problems.is_empty(),
        "{} problems in {mutants} mutants:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

/// Errors about a whole file, which have no line to point at: bytes that are not UTF-8, an empty
/// file, a missing file or sidecar, a record with no rows.
fn unlocatable(e: &InputError) -> bool {
    let m = e.message.to_lowercase();
    [
        "utf-8",
        "utf8",
        "empty",
        "no such file",
        "cannot read",
        "sidecar",
        "no rows",
        "no data",
    ]
    .iter()
    .any(|k| m.contains(k))
}
