//! Files in the spelling before issue 34 made it one: a control in % of travel was `<x>_pct`
//! in a record (its header, its sidecar's `controls` and `trim`) and `controls_pct` in a
//! sensors file. They load as `<x>_percent` and `controls_percent`, the same as files written
//! today; one channel named both ways is a located error.

use super::common::{cierva_in, repo_root};
use cierva_harness::inputs::record;
use cierva_harness::synth::flight::sensors::Instrumentation;
use std::path::{Path, PathBuf};

/// The shipped stick sweep (its controls all in %), and its sidecar.
const SWEEP: &str = "flight-refs/synthetic-flight-vpm-m16-60mph-stick-sweep";

fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::scratch("old-spelling").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The shipped sweep written into `dir` (as `sweep.csv` and `sweep.yaml`) with its percent
/// channels spelled `suffix`, after `edit` of the CSV's and the sidecar's text.
fn sweep_in(
    dir: &Path,
    suffix: &str,
    edit: impl Fn(String, String) -> (String, String),
) -> PathBuf {
    let root = repo_root();
    let read = |ext: &str| std::fs::read_to_string(root.join(format!("{SWEEP}.{ext}"))).unwrap();
    // Whichever spelling is shipped, to `suffix`.
    let respell = |t: &str| t.replace("_pct", "_percent").replace("_percent", suffix);
    let id = SWEEP.rsplit('/').next().unwrap();
    let csv = respell(&read("csv"));
    // The sidecar's names (trim, controls), not its generator's settings (free text, indented
    // deeper), which the reader keeps as written.
    let side: String = read("yaml")
        .lines()
        .map(|l| match l.starts_with("    ") {
            true => format!("{l}\n"),
            false => respell(l) + "\n",
        })
        .collect();
    let side = side.replacen(&format!("id: {id}"), "id: sweep", 1);
    let (csv, side) = edit(csv, side);
    let path = dir.join("sweep.csv");
    std::fs::write(&path, csv).unwrap();
    std::fs::write(record::sidecar_path(&path), side).unwrap();
    path
}

/// A record with `eta_*_pct` channels, controls and trim loads as the same record spelled
/// `eta_*_percent`, and gives the same frequency response; a channel asked for as `eta_s_pct`
/// is an error that names `eta_s_percent`.
#[test]
fn a_record_in_the_old_spelling_loads_as_the_new() {
    let old_path = sweep_in(&scratch("old"), "_pct", |c, s| (c, s));
    let new_path = sweep_in(&scratch("new"), "_percent", |c, s| (c, s));
    let old_header = std::fs::read_to_string(&old_path).unwrap();
    assert!(old_header.lines().next().unwrap().contains(",eta_s_pct,"));
    let old = record::load(&old_path).unwrap();
    let new = record::load(&new_path).unwrap();
    assert_eq!(
        new.meta.controls,
        [
            "eta_s_percent",
            "eta_c_percent",
            "eta_p_percent",
            "eta_t_percent"
        ]
    );
    assert!(new.meta.trim.contains_key("eta_s_percent"));
    // Nothing past the reader sees the old spelling.
    assert_eq!(old.channels, new.channels);
    assert_eq!(old.meta, new.meta);
    assert_eq!(old.data, new.data);
    assert!(
        !old.channels.iter().any(|c| c.contains("pct")),
        "{:?}",
        old.channels
    );

    // The same response from either, by the command that reads records.
    let run = |path: &Path| {
        let (code, out, err) = cierva_in(
            path.parent().unwrap(),
            &[
                "frequency-response",
                "sweep.csv",
                "--input",
                "eta_s_percent",
                "--output",
                "q_rad_s",
                "--format",
                "csv",
            ],
        );
        assert_eq!(code, 0, "{err}");
        out
    };
    let (old_out, new_out) = (run(&old_path), run(&new_path));
    assert!(old_out.lines().count() > 10, "{old_out}");
    assert_eq!(old_out, new_out);

    // A channel asked for in the old spelling is named in the new.
    let (code, _, err) = cierva_in(
        old_path.parent().unwrap(),
        &[
            "frequency-response",
            "sweep.csv",
            "--input",
            "eta_s_pct",
            "--output",
            "q_rad_s",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("sweep.csv:1:")
            && err.contains("channel `eta_s_pct` is missing; `eta_s_percent` is there")
            && err.contains("ask for `eta_s_percent`"),
        "{err}"
    );
}

/// A record that names one channel both ways, in its header, its sidecar's controls or its
/// trim, is an error where it says so (at the second name; in the trim, a map, at the old
/// one), never a silent pick.
#[test]
fn a_record_naming_a_channel_both_ways_is_a_located_error() {
    // The header: `eta_s_percent` in the column after `eta_s_pct` (one more column in every row).
    let path = sweep_in(&scratch("both-header"), "_pct", |csv, side| {
        let csv = csv
            .lines()
            .enumerate()
            .map(|(k, l)| {
                let mut f: Vec<&str> = l.split(',').collect();
                let s = f.iter().position(|c| *c == "eta_s_pct").unwrap_or(10);
                let dup = if k == 0 { "eta_s_percent" } else { f[s] };
                f.insert(s + 1, dup);
                f.join(",") + "\n"
            })
            .collect();
        (csv, side)
    });
    let header = std::fs::read_to_string(&path).unwrap();
    let header = header.lines().next().unwrap();
    let e = record::load(&path).unwrap_err();
    assert_eq!(e.path, path);
    assert_eq!(e.line, Some(1), "{e}");
    assert_eq!(
        e.column,
        Some(header.find(",eta_s_percent").unwrap() + 2),
        "{e}"
    );
    assert!(
        e.message
            .contains("`eta_s_pct` (column 11) and `eta_s_percent` (column 12)")
            && e.message.contains("keep one"),
        "{e}"
    );

    // The sidecar's controls.
    let path = sweep_in(&scratch("both-controls"), "_pct", |csv, side| {
        let side = side.replacen("- eta_c_pct\n", "- eta_c_pct\n- eta_s_percent\n", 1);
        (csv, side)
    });
    let side_path = record::sidecar_path(&path);
    let side = std::fs::read_to_string(&side_path).unwrap();
    let e = record::load(&path).unwrap_err();
    assert_eq!(e.path, side_path);
    let line = side.lines().position(|l| l == "- eta_s_percent").unwrap() + 1;
    assert_eq!((e.line, e.column), (Some(line), Some(3)), "{e}");
    assert_eq!(e.field.as_deref(), Some("controls[2]"));
    assert!(
        e.message
            .contains("`eta_s_pct` and `eta_s_percent` are one channel"),
        "{e}"
    );

    // The sidecar's trim.
    let path = sweep_in(&scratch("both-trim"), "_pct", |csv, side| {
        let side = side.replacen("trim:\n", "trim:\n  eta_c_percent: 50.0\n", 1);
        (csv, side)
    });
    let side = std::fs::read_to_string(record::sidecar_path(&path)).unwrap();
    let e = record::load(&path).unwrap_err();
    let line = side
        .lines()
        .position(|l| l.starts_with("  eta_c_pct:"))
        .unwrap()
        + 1;
    assert_eq!(e.line, Some(line), "{e}");
    assert_eq!(e.field.as_deref(), Some("trim.eta_c_pct"));
    assert!(
        e.message
            .contains("`eta_c_pct` and `eta_c_percent` are one channel"),
        "{e}"
    );
}

fn sensors_file(dir: &str, text: &str) -> PathBuf {
    let p = scratch(dir).join("boom.yaml");
    std::fs::write(&p, text).unwrap();
    p
}

/// A sensors file's `controls_pct` (under `channels` and in `sources`) is read as
/// `controls_percent`: the same instrumentation, the record's controls measured by it.
#[test]
fn a_sensors_file_in_the_old_spelling_loads_as_the_new() {
    let text = |name: &str| {
        format!(
            "id: boom\ntitle: t\nchannels:\n  {name}: {{noise: 0.2, lag_s: 0.05}}\n  q_rad_s: {{bias: 0.01}}\nsources:\n  channels.{name}.noise: \"estimated: test noise\"\n  channels.{name}: \"estimated: test\"\n  channels.q_rad_s.bias: \"estimated: test bias\"\n"
        )
    };
    let old = Instrumentation::load(&sensors_file("sensors-old", &text("controls_pct"))).unwrap();
    let new =
        Instrumentation::load(&sensors_file("sensors-new", &text("controls_percent"))).unwrap();
    assert_eq!(old, new);
    let c = new.channels["controls_percent"];
    assert_eq!((c.noise, c.lag_s), (0.2, 0.05));
    assert_eq!(new.channel("eta_p_percent"), Some(c));
    assert!(
        new.sources["channels.controls_percent"].contains("noise 0.2: estimated: test noise"),
        "{:?}",
        new.sources
    );
    assert!(!old.channels.contains_key("controls_pct"));
    assert!(
        !old.sources.keys().any(|k| k.contains("pct")),
        "{:?}",
        old.sources
    );
}

/// Both names in one sensors file are an error at the old one, under `channels` or `sources`.
#[test]
fn a_sensors_file_naming_controls_both_ways_is_a_located_error() {
    let p = sensors_file(
        "sensors-both",
        "id: boom\ntitle: t\nchannels:\n  controls_percent: {noise: 0.2}\n  controls_pct: {noise: 0.3}\nsources:\n  channels: \"estimated: test\"\n",
    );
    let e = Instrumentation::load(&p).unwrap_err();
    assert_eq!((e.line, e.column), (Some(5), Some(3)), "{e}");
    assert_eq!(e.field.as_deref(), Some("channels.controls_pct"));
    assert!(
        e.message.contains(
            "`controls_pct` is the old name of `controls_percent`, which `channels` gives as well"
        ),
        "{e}"
    );
    let p = sensors_file(
        "sensors-both-sources",
        "id: boom\ntitle: t\nchannels:\n  controls_percent: {noise: 0.2}\nsources:\n  channels.controls_percent: \"estimated: a\"\n  channels.controls_pct: \"estimated: b\"\n",
    );
    let e = Instrumentation::load(&p).unwrap_err();
    assert_eq!(e.line, Some(7), "{e}");
    assert!(
        e.message.contains(
            "`channels.controls_pct` is the old name of `channels.controls_percent`, which `sources` gives as well"
        ),
        "{e}"
    );
}
