//! A study as a plan of independent evaluations (issue 53): written, run in shards, finished;
//! the same numbers as the one-machine run, bit for bit; every bad input a located error.

use crate::common::{cierva_in, repo_root};
use cierva_harness::plan::{self, PlanError, StudySettings};
use cierva_harness::uncertainty::propagate::{Propagation, PropagationSettings};
use std::path::{Path, PathBuf};

/// A fresh folder of its own under the system's temporary one.
fn fresh(name: &str) -> PathBuf {
    let dir = crate::common::scratch(&format!("plan-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The slow stand-in model's suite (examples/distributed/slow-model) copied to `dir`, its
/// trims instant (`--seconds 0`): a study's plumbing without its cost.
fn instant_model(dir: &Path) -> PathBuf {
    let from = repo_root().join("examples/distributed/slow-model");
    for sub in ["cases", "model", "fits"] {
        std::fs::create_dir_all(dir.join(sub)).unwrap();
        for f in std::fs::read_dir(from.join(sub)).unwrap() {
            let f = f.unwrap().path();
            std::fs::copy(&f, dir.join(sub).join(f.file_name().unwrap())).unwrap();
        }
    }
    let case = dir.join("cases/slow-model-trim.yaml");
    let text = std::fs::read_to_string(&case).unwrap().replace(
        "command: [python3, ../model/slow_model.py, --serve]",
        "command: [python3, ../model/slow_model.py, --serve, --seconds, '0']",
    );
    std::fs::write(&case, text).unwrap();
    case
}

/// The second batch's folder under `plans`, its plan edited (`from`'s first occurrence made
/// `to`).
fn edit_second_batch(plans: &Path, from: &str, to: &str) -> PathBuf {
    let batch = std::fs::read_dir(plans)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().contains("batch-0002-"))
        .unwrap();
    let text = std::fs::read_to_string(batch.join("plan.yaml")).unwrap();
    let edited = text.replacen(from, to, 1);
    assert_ne!(edited, text);
    std::fs::write(batch.join("plan.yaml"), edited).unwrap();
    batch
}

fn settings(samples: usize) -> StudySettings {
    StudySettings {
        samples,
        seed: 5,
        method: Propagation::Auto,
        validation_only: false,
    }
}

/// Seed 001 Table 2's case at 8 base points, planned, run in 3 shards out of order and
/// finished: every number the one-machine study states, bit for bit (the JSON of both, which
/// prints each double to the digits that read back to it).
#[test]
#[ignore = "slow (about 13 s in a release test run since the VPM M16's blades feel the hub's angular acceleration, 2026-11-30; out of the cold `cargo test`, held under 5 minutes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn a_plan_finishes_as_the_one_machine_study_bit_for_bit() {
    let dir = fresh("table2");
    let path = repo_root().join("cases/cierva-table2-vpm-m16-70mph-max-weight.yaml");
    let case = cierva_harness::suite::case::load(&path).unwrap();
    let file = plan::write(&dir, std::slice::from_ref(&case), &[], settings(8)).unwrap();
    // The nominal run, the grid study's refined cases, and 8 (14 + 2) points.
    assert_eq!(file.evaluations.len(), 1 + 8 + 8 * 16, "{:?}", file.cases);
    let loaded = plan::load(&dir).unwrap();
    for shard in [3, 1, 2] {
        let r = plan::evaluate(&loaded, (shard, 3), || ()).unwrap();
        assert_eq!(r.already_done, 0);
    }
    let finished = plan::finish(&loaded).unwrap();
    let one = cierva_harness::uncertainty::study::propagate(
        &case,
        PropagationSettings {
            samples: 8,
            seed: 5,
            validation_only: false,
            method: Propagation::Auto,
        },
        || (),
    )
    .unwrap();
    assert_eq!(finished.len(), 1);
    assert!(one.failed_points < one.evaluations, "{:?}", one.first_error);
    assert_eq!(
        serde_json::to_string(&finished[0].0).unwrap(),
        serde_json::to_string(&one).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A shard stopped part-way takes up where it stopped (its evaluations' files kept), and a
/// shard done is skipped; the finished study is the same.
#[test]
fn a_stopped_shard_resumes_and_a_done_one_is_skipped() {
    let dir = fresh("resume");
    let case = cierva_harness::suite::case::load(&instant_model(&dir)).unwrap();
    let study = dir.join("study");
    plan::write(&study, std::slice::from_ref(&case), &[], settings(8)).unwrap();
    let loaded = plan::load(&study).unwrap();
    plan::evaluate(&loaded, (1, 1), || ()).unwrap();
    let whole = serde_json::to_string(&plan::finish(&loaded).unwrap()[0].0).unwrap();
    // Stopped after 5 evaluations: the shard's file gone, 5 evaluations' files left.
    let shard_file = study.join("results/shard-1-of-1.yaml");
    let text = std::fs::read_to_string(&shard_file).unwrap();
    let all: plan::ResultsFile = serde_yaml::from_str(&text).unwrap();
    std::fs::remove_file(&shard_file).unwrap();
    let partial = study.join("results/shard-1-of-1");
    std::fs::create_dir_all(&partial).unwrap();
    for r in all.evaluations.iter().take(5) {
        let one = plan::ResultsFile {
            evaluations: vec![r.clone()],
            ..all.clone()
        };
        std::fs::write(
            partial.join(format!("evaluation-{}.yaml", r.evaluation)),
            serde_yaml::to_string(&one).unwrap(),
        )
        .unwrap();
    }
    match plan::finish(&loaded) {
        Err(PlanError::Incomplete(m)) => {
            assert!(m.contains("shard 1 of 1 (36 of its 41 evaluations"), "{m}")
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
    let r = plan::evaluate(&loaded, (1, 1), || ()).unwrap();
    assert_eq!((r.already_done, r.evaluations), (5, 41));
    assert!(!partial.exists());
    let r = plan::evaluate(&loaded, (1, 1), || ()).unwrap();
    assert_eq!(r.already_done, 41, "a done shard is skipped");
    let again = serde_json::to_string(&plan::finish(&loaded).unwrap()[0].0).unwrap();
    assert_eq!(again, whole);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Each bad input of a plan is a located error with exit code 2 (a missing shard: named, exit
/// 1, no verdict printed).
#[test]
fn a_plan_s_bad_input_is_a_located_error() {
    let dir = fresh("bad");
    let case_path = instant_model(&dir);
    let (code, out, err) = cierva_in(
        &dir,
        &[
            "uncertainty",
            "cases/slow-model-trim.yaml",
            "--samples",
            "8",
            "--plan",
            "a",
        ],
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("41 evaluations of 1 case in"), "{out}");
    // A shard out of range.
    for shard in ["0/2", "3/2", "2", "a/b", "1/42"] {
        let (code, _, err) = cierva_in(&dir, &["evaluate", "a", "--shard", shard]);
        assert_eq!(code, 2, "{shard}: {err}");
        assert!(err.contains(&format!("--shard {shard}")), "{err}");
    }
    // Not complete: shard 2 of 2 named, no verdict printed.
    assert_eq!(cierva_in(&dir, &["evaluate", "a", "--shard", "1/2"]).0, 0);
    let (code, out, err) = cierva_in(&dir, &["uncertainty", "--from-plan", "a"]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("shard 2 of 2") && err.contains("--shard 2/2"),
        "{err}"
    );
    // Results of another plan (seed 6): refused, naming the file.
    let (code, _, err) = cierva_in(
        &dir,
        &[
            "uncertainty",
            "cases/slow-model-trim.yaml",
            "--samples",
            "8",
            "--seed",
            "6",
            "--plan",
            "b",
        ],
    );
    assert_eq!(code, 0, "{err}");
    std::fs::create_dir_all(dir.join("b/results")).unwrap();
    std::fs::copy(
        dir.join("a/results/shard-1-of-2.yaml"),
        dir.join("b/results/shard-1-of-2.yaml"),
    )
    .unwrap();
    let (code, _, err) = cierva_in(&dir, &["uncertainty", "--from-plan", "b"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("b/results/shard-1-of-2.yaml:") && err.contains("results of another plan"),
        "{err}"
    );
    // Results files refused at finishing, located: each edit of the first shard's file and
    // what its error says besides the file's name.
    let shard = dir.join("a/results/shard-1-of-2.yaml");
    let text = std::fs::read_to_string(&shard).unwrap();
    assert!(
        text.contains("  checks:\n") && text.contains("  results:\n"),
        "{text}"
    );
    for (from, to, says) in [
        // Corrupted: its line and column.
        ("seconds:", "seconds: [", "shard-1-of-2.yaml:"),
        // A point's results that are not its checks' values alone (a point holds what the
        // study reads of each check, not the whole results a nominal run holds).
        (
            "  checks:\n",
            "  values: [1.0]\n  checks:\n",
            "1 checks' values",
        ),
        // A nominal run's with a point's checks' values beside its whole results.
        (
            "  results:\n",
            "  checks: []\n  results:\n",
            "1 checks' results",
        ),
    ] {
        std::fs::write(&shard, text.replacen(from, to, 1)).unwrap();
        let (code, _, err) = cierva_in(&dir, &["uncertainty", "--from-plan", "a"]);
        assert_eq!(code, 2, "{to}: {err}");
        assert!(
            err.contains("a/results/shard-1-of-2.yaml:") && err.contains(says),
            "{to}: {err}"
        );
    }
    // A nominal run's results that are an error alone: a nominal run always has its results.
    let mut doc: serde_yaml::Value = serde_yaml::from_str(&text).unwrap();
    let nominal = (doc["evaluations"].as_sequence_mut().unwrap().iter_mut())
        .find(|e| e.get("results").is_some())
        .expect("the nominal run's results in shard 1");
    let nominal = nominal.as_mapping_mut().unwrap();
    nominal.remove("results");
    nominal.insert("error".into(), "the case could not be made".into());
    std::fs::write(&shard, serde_yaml::to_string(&doc).unwrap()).unwrap();
    let (code, _, err) = cierva_in(&dir, &["uncertainty", "--from-plan", "a"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("a/results/shard-1-of-2.yaml:") && err.contains("1 checks' results"),
        "{err}"
    );
    std::fs::write(&shard, &text).unwrap();
    // Another cierva version's plan.
    let plan_path = dir.join("a/plan.yaml");
    let plan_text = std::fs::read_to_string(&plan_path).unwrap();
    std::fs::write(
        &plan_path,
        plan_text.replacen(
            &format!("cierva_version: {}", plan::VERSION),
            "cierva_version: 0.0.1",
            1,
        ),
    )
    .unwrap();
    let (code, _, err) = cierva_in(&dir, &["evaluate", "a", "--shard", "2/2"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("plan.yaml:2:") && err.contains("written by cierva 0.0.1"),
        "{err}"
    );
    // An edited plan: an evaluation's place taken by another's.
    std::fs::write(
        &plan_path,
        plan_text.replacen("- index: 1\n", "- index: 0\n", 1),
    )
    .unwrap();
    let (code, _, err) = cierva_in(&dir, &["evaluate", "a", "--shard", "2/2"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("field `evaluations[1]`") && err.contains("not the evaluation"),
        "{err}"
    );
    std::fs::write(&plan_path, &plan_text).unwrap();
    // A plan for other cases: the case changed since.
    let case_text = std::fs::read_to_string(&case_path).unwrap();
    std::fs::write(&case_path, case_text.replace("value: 3.95", "value: 3.96")).unwrap();
    let (code, _, err) = cierva_in(&dir, &["evaluate", "a", "--shard", "2/2"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("cases[0].fingerprint")
            && err.contains("has changed since the plan was written"),
        "{err}"
    );
    std::fs::write(&case_path, &case_text).unwrap();
    // Settings the plan fixes are not taken beside it.
    let (code, _, err) = cierva_in(&dir, &["uncertainty", "--from-plan", "a", "--seed", "3"]);
    assert_eq!(code, 2, "{err}");
    // And, all put back, the study finishes.
    assert_eq!(cierva_in(&dir, &["evaluate", "a", "--shard", "2/2"]).0, 0);
    let (code, out, err) = cierva_in(&dir, &["uncertainty", "--from-plan", "a"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("slow-model-trim"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sensitivity study as a plan (the stand-in model, its trims instant): its requests run in
/// two shards and finished give the study `cierva sensitivity --case` prints, byte for byte
/// (the model's description too: the commands work from the folder the plan was written in);
/// an uncertainty study's finish refuses its plan.
#[test]
fn a_sensitivity_plan_finishes_as_the_one_machine_study() {
    let dir = fresh("sensitivity");
    instant_model(&dir);
    let case = ["--case", "cases/slow-model-trim.yaml"];
    let (code, one, err) = cierva_in(
        &dir,
        &[&["sensitivity"], &case[..], &["--format", "json"]].concat(),
    );
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = cierva_in(
        &dir,
        &[&["sensitivity"], &case[..], &["--plan", "s"]].concat(),
    );
    assert_eq!(code, 0, "{err}");
    // The nominal request and each of 3 parameters down and up.
    assert!(
        out.contains("7 requests of slow-model-trim's model"),
        "{out}"
    );
    for shard in ["2/2", "1/2"] {
        let (code, _, err) = cierva_in(&dir, &["evaluate", "s", "--shard", shard]);
        assert_eq!(code, 0, "{err}");
    }
    let (code, merged, err) = cierva_in(
        &dir,
        &["sensitivity", "--from-plan", "s", "--format", "json"],
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(merged, one);
    assert!(merged.contains("\"derivative\""), "{merged}");
    let (code, _, err) = cierva_in(&dir, &["uncertainty", "--from-plan", "s"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("a sensitivity study's plan"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A fit's run (without its wall time) as `cierva fit --format json` prints it, and its exit code.
fn fit_run(dir: &Path, extra: &[&str]) -> (i32, serde_json::Value, String) {
    let mut args = vec![
        "fit",
        "fits/slow-model.yaml",
        "--report",
        "out/r.md",
        "--format",
        "json",
    ];
    if !extra.contains(&"--output") {
        args.extend(["--output", "out/c.yaml"]);
    }
    args.extend(extra);
    let (code, out, err) = cierva_in(dir, &args);
    let mut v: serde_json::Value = serde_json::from_str(&out).unwrap_or_default();
    if let Some(run) = v.get_mut("run").and_then(|r| r.as_object_mut()) {
        run.remove("seconds");
    }
    (code, v["run"].clone(), err)
}

/// A fit whose batches of evaluations go through plans (`cierva fit --evaluate-with`, issue
/// 53, item 3), each run by a command as an engine would (here `cierva evaluate` on each shard
/// in turn): the same fit as on one machine, bit for bit (its values, standard errors, every
/// target before and after, the predictions). Run again on the same folder it reads the
/// batches done and runs nothing (the command would fail); with a command that runs no shard
/// it is a model failure that names the batch and what to run; a command that does not name
/// `{plan}` is refused (exit 2).
#[test]
#[ignore = "slow (about 6 s in a release test run since the VPM M16's blades feel the hub's angular acceleration, 2026-11-30; out of the cold `cargo test`, held under 5 minutes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn a_fit_through_plans_is_the_fit_on_one_machine() {
    let dir = fresh("fit");
    instant_model(&dir);
    std::fs::copy(
        repo_root().join("examples/distributed/slow-model/cierva.toml"),
        dir.join("cierva.toml"),
    )
    .unwrap();
    let (code, local, err) = fit_run(&dir, &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(local["result"]["status"]["status"], "converged", "{local}");
    let engine = format!(
        "for i in $(seq 1 {{shards}}); do '{}' evaluate {{plan}} --shard $i/{{shards}} --quiet || exit 1; done",
        env!("CARGO_BIN_EXE_cierva")
    );
    let (code, planned, err) = fit_run(
        &dir,
        &[
            "--evaluate-with",
            &engine,
            "--plans",
            "plans",
            "--shards",
            "2",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(planned, local, "{err}");
    let batches = std::fs::read_dir(dir.join("plans")).unwrap().count();
    assert!(batches >= 3, "{batches} batches");

    let (code, again, err) = fit_run(
        &dir,
        &["--evaluate-with", "false {plan}", "--plans", "plans"],
    );
    assert_eq!(code, 0, "{err}");
    assert_eq!(again, local, "{err}");

    // An engine that runs no shard: the fit stops at its first batch (exit 1), says which and
    // what to run, and writes nothing.
    let (code, _, err) = fit_run(
        &dir,
        &[
            "--evaluate-with",
            "true {plan}",
            "--plans",
            "none",
            "--output",
            "out/none.yaml",
        ],
    );
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("through plans stopped")
            && err.contains("batch 1 of the fit")
            && err.contains("cierva evaluate"),
        "{err}"
    );
    assert!(!dir.join("out/none.yaml").exists());

    // An engine that fails on the third batch only (a trial step's): the fit stops there, not
    // on another path; run again with a sound engine on the same folder, it reads the two
    // batches done and ends as the one-machine fit.
    let flaky = format!("case {{plan}} in *batch-0003-*) exit 1;; esac; {engine}");
    let (code, _, err) = fit_run(
        &dir,
        &[
            "--evaluate-with",
            &flaky,
            "--plans",
            "flaky",
            "--output",
            "out/flaky.yaml",
        ],
    );
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("batch 3 of the fit"), "{err}");
    assert!(!dir.join("out/flaky.yaml").exists());
    let (code, resumed, err) = fit_run(&dir, &["--evaluate-with", &engine, "--plans", "flaky"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(resumed, local, "{err}");

    let (code, _, err) = cierva_in(
        &dir,
        &["fit", "fits/slow-model.yaml", "--evaluate-with", "echo"],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("{plan}"), "{err}");

    // A batch's plan edited to name a target the fit file does not have: a located error.
    let batch = edit_second_batch(&dir.join("plans"), "    - 3\n", "    - 99\n");
    let at = batch.display().to_string();
    let (code, _, err) = cierva_in(&dir, &["evaluate", &at]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("evaluations[1]") && err.contains("target 99") && err.contains("plan.yaml:"),
        "{err}"
    );
}

/// `validate --uncertainty --plan DIR` writes the plan `uncertainty --plan` would, and says
/// how to finish it; its shards run, `validate --uncertainty --from-plan DIR` gives the
/// one-machine run's uncertainty, number for number. A plan is of whole cases (`-k` refused
/// with `--plan`), its samples are its own (`--samples` refused with `--from-plan`), and its
/// corrections must be the run's.
#[test]
fn validate_with_uncertainty_runs_through_a_plan() {
    let dir = fresh("validate");
    let case = instant_model(&dir);
    std::fs::copy(
        repo_root().join("examples/distributed/slow-model/cierva.toml"),
        dir.join("cierva.toml"),
    )
    .unwrap();
    // A regression check ahead of the validation one: `--class validation` then runs the
    // second of the case's checks alone.
    let text = std::fs::read_to_string(&case)
        .unwrap()
        .replace("class: regression", "class: validation")
        .replace(
            "checks:\n",
            "checks:\n  - id: pitch-60mph\n    class: regression\n    description: the stand-in's pitch at 60 mph (synthetic)\n    kind: trim\n    condition: {airspeed_mph: 60.0}\n    expect:\n      pitch_deg: {value: 3.95, tolerance: made-up}\n",
        );
    std::fs::write(&case, text).unwrap();
    let json = |args: &[&str]| -> serde_json::Value {
        let (code, out, err) = cierva_in(&dir, args);
        assert!(code == 0 || code == 1, "{args:?}: exit {code}\n{out}{err}");
        let mut v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let u = v["uncertainty"].take();
        assert!(
            u.is_array() || u.is_object(),
            "{args:?}: no uncertainty in {out}"
        );
        // The validation check's quantities, with the case's summary.
        let check = (v["results"].as_array().unwrap().iter())
            .find(|r| r["check"] == "pitch-70mph")
            .map(|r| r["uncertainty"].clone())
            .unwrap_or_else(|| panic!("{args:?}: no pitch-70mph in {out}"));
        assert!(check.to_string().contains("u_input"), "{check}");
        serde_json::json!({"case": u, "check": check})
    };
    let run = [
        "validate",
        "--uncertainty",
        "--no-report",
        "--format",
        "json",
    ];
    let one = json(&[&run[..], &["--samples", "8"]].concat());
    let (code, out, err) = cierva_in(
        &dir,
        &["validate", "--uncertainty", "--samples", "8", "--plan", "p"],
    );
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("then `cierva validate --uncertainty --from-plan p`"),
        "{out}"
    );
    for shard in ["2/2", "1/2"] {
        let (code, _, err) = cierva_in(&dir, &["evaluate", "p", "--shard", shard]);
        assert_eq!(code, 0, "{err}");
    }
    let merged = json(&[&run[..], &["--from-plan", "p"]].concat());
    assert_eq!(strip_seconds(merged), strip_seconds(one.clone()));
    // A run of some of a case's checks studies those, each with its own nominal result (it
    // studied none when the validation check was not the case's first).
    let selected = json(&[&run[..], &["--samples", "8", "--class", "validation"]].concat());
    assert_eq!(strip_seconds(selected), strip_seconds(one.clone()));
    let narrowed = json(&[&run[..], &["--from-plan", "p", "--class", "validation"]].concat());
    assert_eq!(strip_seconds(narrowed), strip_seconds(one.clone()));
    let other = repo_root().join("corrections/seed000-vpm-m16.yaml");
    let other = other.to_str().unwrap();
    for (args, want) in [
        (
            &["validate", "--uncertainty", "--plan", "q", "-k", "pitch"][..],
            "a plan is of whole cases",
        ),
        (
            &[
                "validate",
                "--uncertainty",
                "--from-plan",
                "p",
                "--samples",
                "16",
            ][..],
            "cannot be used with",
        ),
        (
            &[
                "validate",
                "--uncertainty",
                "--from-plan",
                "p",
                "--corrections",
                other,
            ][..],
            "the plan was written with --corrections []",
        ),
    ] {
        let (code, out, err) = cierva_in(&dir, args);
        assert_eq!(code, 2, "{args:?}\n{out}{err}");
        assert!(err.contains(want), "{args:?}: no `{want}` in\n{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A JSON value with every `seconds` field taken out (wall times differ between runs).
fn strip_seconds(mut v: serde_json::Value) -> serde_json::Value {
    match &mut v {
        serde_json::Value::Object(m) => {
            m.remove("seconds");
            for x in m.values_mut() {
                *x = strip_seconds(x.take());
            }
        }
        serde_json::Value::Array(a) => {
            for x in a.iter_mut() {
                *x = strip_seconds(x.take());
            }
        }
        _ => {}
    }
    v
}

/// A retune whose fit's batches go through plans (`cierva retune --evaluate-with`, issue 53,
/// item 3), each run by `cierva evaluate` on its shards in turn as an engine would: the README
/// example's retune, the same as on one machine bit for bit (its values, standard errors,
/// intervals, chi-square, every response's J before and after). Run again on the same folder
/// it reads the batches done and runs nothing (the command would fail); an engine that runs no
/// shard stops it (exit 1) naming the batch, and nothing is written; a batch's plan edited to
/// name a parameter no aircraft has is a located error.
#[test]
#[ignore = "slow known answer (a synthetic flight and three retunes): run by .ci/run with `cargo test --test suite -- --ignored`"]
fn a_retune_through_plans_is_the_retune_on_one_machine() {
    let dir = fresh("retune");
    let record = crate::common::readme_record(&dir);
    let retune = |extra: &[&str]| -> (i32, serde_json::Value, String) {
        let (code, out, err) = crate::common::retune_hub_and_drag(&dir, &[&record], extra);
        let mut v: serde_json::Value = serde_json::from_str(&out).unwrap_or_default();
        // Where the files went is the same; the figures' names too.
        if let Some(o) = v.as_object_mut() {
            o.remove("wrote");
        }
        (code, v, err)
    };
    let (code, local, err) = retune(&[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(local["status"], "converged", "{local}");
    let plans = dir.join("plans");
    let plans = plans.to_str().unwrap();
    let engine = format!(
        "for i in $(seq 1 {{shards}}); do '{}' evaluate {{plan}} --shard $i/{{shards}} --quiet || exit 1; done",
        env!("CARGO_BIN_EXE_cierva")
    );
    let (code, planned, err) = retune(&["--evaluate-with", &engine, "--plans", plans]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(planned, local, "{err}");
    let batches = std::fs::read_dir(dir.join("plans")).unwrap().count();
    assert!(batches >= 5, "{batches} batches");

    let (code, again, err) = retune(&["--evaluate-with", "false {plan}", "--plans", plans]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(again, local, "{err}");

    let none = dir.join("none");
    let _ = std::fs::remove_file(dir.join("retuned.yaml"));
    let (code, _, err) = retune(&[
        "--evaluate-with",
        "true {plan}",
        "--plans",
        none.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("through plans stopped")
            && err.contains("batch 1 of the fit")
            && err.contains("cierva evaluate"),
        "{err}"
    );
    assert!(!dir.join("retuned.yaml").exists());

    // A batch's plan edited to name a parameter no aircraft has: a located error.
    let batch = edit_second_batch(&dir.join("plans"), "- hub_aoa_factor", "- hub_aoa_factr");
    let (code, _, err) = cierva_in(&dir, &["evaluate", batch.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("hub_aoa_factr") && err.contains("plan.yaml:"),
        "{err}"
    );
}
