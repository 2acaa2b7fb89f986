//! Flight records as they come (issue 50): columns cierva does not know are kept (or left out
//! where they are not numbers), a sidecar's `channels:` map names a column, and a required
//! channel in another unit is converted. The known answer: the shipped stick sweep, rewritten
//! as a flight-test system might log it, loads to the same numbers as the canonical record.

use super::common::repo_root;
use cierva_harness::inputs::record;
use std::path::{Path, PathBuf};

/// The shipped stick sweep (cierva's own names and units), and its sidecar.
const SWEEP: &str = "flight-refs/synthetic-flight-vpm-m16-60mph-stick-sweep";

fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::scratch("records").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The shipped sweep as a logger might write it, in `dir` as `logged.csv` and its sidecar:
/// the pitch attitude as `PITCH` in degrees and the rotor speed as `NR` in rpm (both mapped by
/// `channels`), the airspeed in knots under cierva's name for that unit (`airspeed_kn`), and
/// two columns nobody asks for: a pressure altitude and a status word. `map` is the sidecar's
/// `channels:` block.
fn logged(dir: &Path, map: &str) -> PathBuf {
    let root = repo_root();
    let csv = std::fs::read_to_string(root.join(format!("{SWEEP}.csv"))).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let (theta, nr, v) = (
        col("theta_rad"),
        col("omega_rotor_rad_s"),
        col("airspeed_m_s"),
    );
    let mut out = String::new();
    let renamed: Vec<String> = header
        .iter()
        .enumerate()
        .map(|(k, h)| match k {
            _ if k == theta => "PITCH".to_string(),
            _ if k == nr => "NR".to_string(),
            _ if k == v => "airspeed_kn".to_string(),
            _ => h.to_string(),
        })
        .collect();
    out += &format!("{},alt_ft,status\n", renamed.join(","));
    for (row, line) in lines.enumerate() {
        let fields: Vec<String> = line
            .split(',')
            .enumerate()
            .map(|(k, f)| {
                let x: f64 = f.parse().unwrap();
                match k {
                    _ if k == theta => format!("{}", x.to_degrees()),
                    _ if k == nr => format!("{}", x * 60.0 / (2.0 * std::f64::consts::PI)),
                    _ if k == v => format!("{}", x * 3600.0 / 1852.0),
                    _ => f.to_string(),
                }
            })
            .collect();
        out += &format!("{},{},OK\n", fields.join(","), 2000 + row);
    }
    std::fs::write(dir.join("logged.csv"), out).unwrap();
    let side = std::fs::read_to_string(root.join(format!("{SWEEP}.yaml"))).unwrap();
    let id = SWEEP.rsplit('/').next().unwrap();
    std::fs::write(
        dir.join("logged.yaml"),
        side.replacen(&format!("id: {id}"), "id: logged", 1) + map,
    )
    .unwrap();
    dir.join("logged.csv")
}

/// A new suite in a scratch folder with the repository's `aircraft/` and `flight-refs/` linked
/// beside its cases (their relative paths).
fn linked_suite(name: &str) -> PathBuf {
    let dir = scratch(name);
    super::common::new_suite(&dir);
    for linked in ["aircraft", "flight-refs"] {
        std::os::unix::fs::symlink(repo_root().join(linked), dir.join(linked)).unwrap();
    }
    dir
}

const MAP: &str = "channels:\n  PITCH: theta_deg\n  NR: omega_rotor_rpm\n";

#[test]
fn a_logged_record_loads_to_the_canonical_records_numbers() {
    let dir = scratch("logged");
    let canonical = record::load(&repo_root().join(format!("{SWEEP}.csv"))).unwrap();
    let got = record::load(&logged(&dir, MAP)).unwrap_or_else(|e| panic!("{}", e.render()));
    for (name, want) in canonical.channels.iter().zip(&canonical.data) {
        let have = got
            .channel(name)
            .unwrap_or_else(|| panic!("no `{name}`: {:?}", got.channels));
        for (a, b) in have.iter().zip(want) {
            // The logger's decimal text of a converted number and back: a few units in the
            // last place.
            assert!(
                (a - b).abs() <= 1e-13 * b.abs().max(1e-300),
                "{name}: {a} against {b}"
            );
        }
    }
    // The altitude is kept as it is, the status word left out, and the load says what it did.
    assert_eq!(got.channel("alt_ft").unwrap()[1], 2001.0);
    assert!(got.channel("status").is_none());
    let notes = got.notes.join("\n");
    for said in [
        "column `PITCH` read as `theta_deg`",
        "`theta_deg` converted to `theta_rad` (deg to rad)",
        "`omega_rotor_rpm` converted to `omega_rotor_rad_s` (rpm to rad/s)",
        "`airspeed_kn` converted to `airspeed_m_s` (kn to m/s)",
        "column `status` left out: `OK` at line 2 is not a number",
    ] {
        assert!(notes.contains(said), "`{said}` not in:\n{notes}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sidecar's map that cannot be applied is a located error at its entry.
#[test]
fn a_bad_channel_map_is_a_located_error() {
    let cases = [
        (
            "channels:\n  PTICH: theta_deg\n",
            "the record has no column `PTICH` (did you mean `PITCH`?)",
        ),
        (
            "channels:\n  PITCH: theta_degrees\n",
            "`theta_degrees`: name the channel with its unit as a suffix",
        ),
        (
            "channels:\n  PITCH: theta_deg\n  NR: theta_deg\n",
            "is mapped to `theta_deg` too",
        ),
        ("channels:\n  PITCH: alt_ft\n", "`alt_ft` is already column"),
    ];
    for (k, (map, want)) in cases.iter().enumerate() {
        let dir = scratch(&format!("bad-{k}"));
        let e = record::load(&logged(&dir, map)).unwrap_err();
        let text = e.render();
        assert!(text.contains(want), "{map}: {text}");
        assert!(
            text.contains("logged.yaml") && text.contains("channels."),
            "{text}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// The shipped time-history case's linear stick-doublet check, once on its record and once on
/// the record as a logger might write it: the pitch attitude in radians, the pitch rate as
/// `PITCH_RATE` in rad/s (mapped), an altitude and a status word beside them. The same numbers,
/// and the extra channels kept out of the comparison.
#[test]
fn a_time_history_check_reads_a_logged_record_as_the_canonical_one() {
    let dir = linked_suite("time-history");
    let record = "flight-refs/synthetic-vpm-m16-70mph-stick-doublet";
    let csv = std::fs::read_to_string(repo_root().join(format!("{record}.csv"))).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (theta, q) = (
        header.iter().position(|h| *h == "theta_deg").unwrap(),
        header.iter().position(|h| *h == "q_deg_s").unwrap(),
    );
    let mut out = header
        .iter()
        .map(|h| match *h {
            "theta_deg" => "theta_rad",
            "q_deg_s" => "PITCH_RATE",
            h => h,
        })
        .collect::<Vec<_>>()
        .join(",")
        + ",alt_ft,status\n";
    for line in lines {
        let fields: Vec<String> = line
            .split(',')
            .enumerate()
            .map(|(k, f)| match k {
                _ if k == theta || k == q => {
                    format!("{}", f.parse::<f64>().unwrap().to_radians())
                }
                _ => f.to_string(),
            })
            .collect();
        out += &format!("{},1500,GOOD\n", fields.join(","));
    }
    std::fs::create_dir_all(dir.join("logged")).unwrap();
    std::fs::write(dir.join("logged/doublet.csv"), out).unwrap();
    let side = std::fs::read_to_string(repo_root().join(format!("{record}.yaml"))).unwrap();
    let id = record.rsplit('/').next().unwrap();
    std::fs::write(
        dir.join("logged/doublet.yaml"),
        side.replacen(&format!("id: {id}"), "id: doublet", 1)
            + "channels:\n  PITCH_RATE: q_rad_s\n",
    )
    .unwrap();
    let case = std::fs::read_to_string(
        repo_root().join("cases/synthetic-time-history-vpm-m16-70mph.yaml"),
    )
    .unwrap();
    std::fs::write(
        dir.join("cases/synthetic-time-history-vpm-m16-70mph.yaml"),
        case.replace(
            "../flight-refs/synthetic-vpm-m16-70mph-stick-doublet.csv",
            "../logged/doublet.csv",
        ),
    )
    .unwrap();
    let quantities = |dir: &Path| {
        let (code, out, err) = super::common::cierva_in(
            dir,
            &[
                "validate",
                "--no-report",
                "--format",
                "json",
                "-k",
                "synthetic-time-history-vpm-m16-70mph::linear-stick-doublet",
            ],
        );
        assert!(code == 0 || code == 1, "{out}{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let r = v["results"].as_array().unwrap()[0].clone();
        assert!(r["error"].is_null(), "{r}");
        r["quantities"]
            .as_array()
            .unwrap()
            .iter()
            .map(|q| {
                (
                    q["quantity"].as_str().unwrap().to_string(),
                    q["value"].as_f64().unwrap(),
                )
            })
            .collect::<Vec<_>>()
    };
    let (canonical, logged) = (quantities(&repo_root()), quantities(&dir));
    assert_eq!(canonical.len(), logged.len());
    for ((n, a), (m, b)) in canonical.iter().zip(&logged) {
        assert_eq!(n, m);
        // Degrees to radians as the logger's text and back: rounding.
        assert!(
            (a - b).abs() <= 1e-9 * a.abs().max(1e-12),
            "{n}: {a} against {b}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A check flown where its record was not (issue 50): the shipped time-history case asked at
/// 80 mph and 300 kg against its record's 70 mph and 450 kg is an input error that names both
/// conditions, located at the check; a check that says why it differs runs.
#[test]
fn a_check_where_its_record_was_not_flown_is_refused_with_both_conditions() {
    let dir = linked_suite("condition");
    let case = std::fs::read_to_string(
        repo_root().join("cases/synthetic-time-history-vpm-m16-70mph.yaml"),
    )
    .unwrap();
    let path = dir.join("cases/synthetic-time-history-vpm-m16-70mph.yaml");
    let moved = case
        .replacen(
            "condition: {airspeed_mph: 70.0}",
            "condition: {airspeed_mph: 80.0}",
            1,
        )
        .replacen("mass_kg: 450.0", "mass_kg: 300.0", 1);
    std::fs::write(&path, &moved).unwrap();
    let e = cierva_harness::suite::case::load(&path)
        .unwrap_err()
        .render();
    for said in [
        "airspeed 80.0 mph against the record's 70.0 mph (RECORD_AIRSPEED_MATCH, 5 %)",
        "mass 300 kg against the record's 450 kg (RECORD_MASS_MATCH, 5 %)",
        "condition_differs_from_record",
        "checks[0].condition",
    ] {
        assert!(e.contains(said), "`{said}` not in:\n{e}");
    }
    let said_why = moved.replacen(
        "    condition: {airspeed_mph: 80.0}",
        "    condition: {airspeed_mph: 80.0}\n    condition_differs_from_record: the test's own",
        1,
    );
    let said_why = said_why.replace(
        "condition: {airspeed_mph: 70.0}",
        "condition: {airspeed_mph: 70.0}\n    condition_differs_from_record: the test's own (the case's mass is not the record's)",
    );
    std::fs::write(&path, said_why).unwrap();
    cierva_harness::suite::case::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sidecar's own bad numbers are blamed on the sidecar, at their field (issue 50's fuzzing:
/// they were blamed on the CSV, "signal `eta_s` is not finite at sample 0", "time step inf s").
#[test]
fn a_sidecars_bad_numbers_are_blamed_on_the_sidecar() {
    let root = repo_root();
    let side = std::fs::read_to_string(root.join(format!("{SWEEP}.yaml"))).unwrap();
    let id = SWEEP.rsplit('/').next().unwrap();
    let rate = side
        .lines()
        .find(|l| l.starts_with("sample_rate_hz:"))
        .unwrap()
        .to_string();
    let trim_line = side
        .lines()
        .skip_while(|l| !l.starts_with("trim:"))
        .nth(1)
        .unwrap()
        .to_string();
    let key = trim_line.trim().split(':').next().unwrap().to_string();
    for (k, (from, to, field, says)) in [
        (
            rate.as_str(),
            "sample_rate_hz: 2e-320".to_string(),
            "sample_rate_hz".to_string(),
            "whose time step (1 / rate) is finite, got 2e-320 Hz",
        ),
        (
            trim_line.as_str(),
            format!("  {key}: -.inf"),
            format!("trim.{key}"),
            "must be a finite number, got -inf",
        ),
    ]
    .iter()
    .enumerate()
    {
        let dir = scratch(&format!("sidecar-{k}"));
        std::fs::copy(root.join(format!("{SWEEP}.csv")), dir.join("bad.csv")).unwrap();
        std::fs::write(
            dir.join("bad.yaml"),
            side.replacen(&format!("id: {id}"), "id: bad", 1)
                .replacen(from, to, 1),
        )
        .unwrap();
        let e = record::load(&dir.join("bad.csv")).unwrap_err().render();
        assert!(
            e.contains("bad.yaml:") && e.contains(field.as_str()) && e.contains(says),
            "{e}"
        );
        assert!(!e.contains("bad.csv"), "blamed on the CSV: {e}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// A sidecar cut short before its `trim:` (issue 50's fuzzing: "regressors are singular", no
/// file named): the identification's failure names the records and says their sidecar gives
/// no trim values.
#[test]
fn an_identification_that_fails_names_its_records_and_an_empty_trim() {
    let root = repo_root();
    let side = std::fs::read_to_string(root.join(format!("{SWEEP}.yaml"))).unwrap();
    let id = SWEEP.rsplit('/').next().unwrap();
    let cut = side
        .lines()
        .take_while(|l| !l.starts_with("trim:"))
        .collect::<Vec<_>>()
        .join("\n");
    let dir = scratch("cut-short");
    std::fs::copy(root.join(format!("{SWEEP}.csv")), dir.join("cut.csv")).unwrap();
    std::fs::write(
        dir.join("cut.yaml"),
        cut.replacen(&format!("id: {id}"), "id: cut", 1) + "\n",
    )
    .unwrap();
    let (code, out, err) = super::common::cierva_in(
        &root,
        &[
            "identify",
            dir.join("cut.csv").to_str().unwrap(),
            "--setup",
            "longitudinal",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("cut.csv: ")
            && err.contains(
                "cut.yaml gives no `trim:` values, so the histories are taken about zero"
            ),
        "{err}"
    );
}

/// A file that is not UTF-8 (a logger's Latin-1 degree sign) is an error at the line and
/// column of its first bad byte (issue 50's fuzzing: about 350 errors gave no line).
#[test]
fn a_file_that_is_not_utf8_is_located_at_its_first_bad_byte() {
    let dir = scratch("latin1");
    let path = dir.join("latin1.csv");
    // "time_s,theta_deg\n0,1.5\n0.01,2" then a Latin-1 degree sign (0xb0) after `2`.
    let mut bytes = b"time_s,theta_deg\n0,1.5\n0.01,2".to_vec();
    bytes.push(0xb0);
    bytes.extend_from_slice(b"\n");
    std::fs::write(&path, &bytes).unwrap();
    let e = cierva_harness::inputs::yaml::read_csv(&path).unwrap_err();
    assert_eq!((e.line, e.column), (Some(3), Some(7)), "{}", e.render());
    assert!(
        e.render()
            .contains("latin1.csv:3:7: the file is not valid UTF-8 text: byte 0xb0"),
        "{}",
        e.render()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The stick's travel in the tests' own unit: -12 deg at 0 %, 14 deg at 100 % (a stick's
/// fore-and-aft angle; any two distinct ends would do).
const STICK_AT_0_DEG: f64 = -12.0;
const STICK_AT_100_DEG: f64 = 14.0;

/// `record`'s CSV and sidecar rewritten into `dir` as `stick.csv`, with the column
/// `eta_s_percent` logged as `STICK` in degrees (mapped to `eta_s_deg`), its values `x` becoming
/// `at_0 + x (at_100 - at_0) / 100` for positions or `x (at_100 - at_0) / 100` for changes
/// from trim, the trim's `eta_s_percent` given in degrees, and `extra` appended to the sidecar.
fn stick_in_degrees(dir: &Path, record: &str, positions: bool, extra: &str) -> PathBuf {
    let span = STICK_AT_100_DEG - STICK_AT_0_DEG;
    let to_deg = |x: f64| {
        if positions {
            STICK_AT_0_DEG + x * span / 100.0
        } else {
            x * span / 100.0
        }
    };
    let csv = std::fs::read_to_string(repo_root().join(format!("{record}.csv"))).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == "eta_s_percent").unwrap();
    let mut out = header
        .iter()
        .map(|h| if *h == "eta_s_percent" { "STICK" } else { h })
        .collect::<Vec<_>>()
        .join(",")
        + "\n";
    for line in lines {
        let fields: Vec<String> = line
            .split(',')
            .enumerate()
            .map(|(j, f)| match j {
                _ if j == k => format!("{}", to_deg(f.parse().unwrap())),
                _ => f.to_string(),
            })
            .collect();
        out += &(fields.join(",") + "\n");
    }
    std::fs::write(dir.join("stick.csv"), out).unwrap();
    let side = std::fs::read_to_string(repo_root().join(format!("{record}.yaml"))).unwrap();
    let id = record.rsplit('/').next().unwrap();
    let side: String = side
        .replacen(&format!("id: {id}"), "id: stick", 1)
        .lines()
        // The trim's stick position (the sidecar's `excitation` names a channel under the same
        // key).
        .map(|l| {
            match l
                .strip_prefix("  eta_s_percent: ")
                .and_then(|x| x.parse::<f64>().ok())
            {
                Some(x) => format!("  eta_s_deg: {}\n", STICK_AT_0_DEG + x * span / 100.0),
                None => format!("{l}\n"),
            }
        })
        .collect();
    let logged = if positions {
        "position"
    } else {
        "change_from_trim"
    };
    std::fs::write(
        dir.join("stick.yaml"),
        format!(
            "{side}channels:\n  STICK: eta_s_deg\ntravel:\n  eta_s: {{unit: deg, at_0_percent: \
             {STICK_AT_0_DEG}, at_100_percent: {STICK_AT_100_DEG}, logged: {logged}}}\n{extra}"
        ),
    )
    .unwrap();
    dir.join("stick.csv")
}

/// How closely a control logged in degrees comes back to % of travel: the logger's decimal text
/// of `at_0 + x span / 100` and back, a few rounding steps on values of order 100 %.
const TRAVEL_ROUND_TRIP_PERCENT: f64 = 1e-11;

/// A control logged in its own unit comes to % of travel through the sidecar's `travel:`, as a
/// position (an identification record: the shipped stick sweep, the stick in degrees, its trim
/// too) or as a change from trim (a time history: the shipped stick doublet), to the canonical
/// record's numbers. The same doublet read as positions is off by the travel's offset, so the
/// sidecar must say which. Before, a control had to be logged in %.
#[test]
fn a_control_in_its_own_unit_comes_to_percent_through_its_travel() {
    let dir = scratch("travel");
    let sweep = record::load(&repo_root().join(format!("{SWEEP}.csv"))).unwrap();
    let got = record::load(&stick_in_degrees(&dir, SWEEP, true, ""))
        .unwrap_or_else(|e| panic!("{}", e.render()));
    for (name, want) in sweep.channels.iter().zip(&sweep.data) {
        let have = got.channel(name).unwrap_or_else(|| panic!("no `{name}`"));
        for (a, b) in have.iter().zip(want) {
            assert!(
                (a - b).abs() <= TRAVEL_ROUND_TRIP_PERCENT * b.abs().max(1.0),
                "{name}: {a} against {b}"
            );
        }
    }
    let (a, b) = (
        got.meta.trim["eta_s_percent"],
        sweep.meta.trim["eta_s_percent"],
    );
    assert!((a - b).abs() <= TRAVEL_ROUND_TRIP_PERCENT * b, "{a} {b}");
    assert!(!got.meta.trim.contains_key("eta_s_deg"));
    let notes = got.notes.join("\n");
    assert!(
        notes.contains(
            "`eta_s_deg` converted to `eta_s_percent` through its travel (-12 deg at 0 %, 14 deg \
             at 100 %; positions)"
        ),
        "{notes}"
    );

    let doublet = "flight-refs/synthetic-vpm-m16-70mph-stick-doublet";
    let canonical =
        record::load_with(&repo_root().join(format!("{doublet}.csv")), &[], true).unwrap();
    let want = canonical.channel("eta_s_percent").unwrap();
    assert!(want.iter().any(|x| *x != 0.0));
    for positions in [false, true] {
        let sub = dir.join(format!("doublet-{positions}"));
        std::fs::create_dir_all(&sub).unwrap();
        // Written as changes; read as the sidecar says (positions: wrongly).
        let csv = stick_in_degrees(&sub, doublet, false, "");
        if positions {
            let side = std::fs::read_to_string(sub.join("stick.yaml")).unwrap();
            std::fs::write(
                sub.join("stick.yaml"),
                side.replace("logged: change_from_trim", "logged: position"),
            )
            .unwrap();
        }
        let got = record::load_with(&csv, &[], true).unwrap_or_else(|e| panic!("{}", e.render()));
        let have = got.channel("eta_s_percent").unwrap();
        let offset = 100.0 * STICK_AT_0_DEG / (STICK_AT_100_DEG - STICK_AT_0_DEG);
        for (a, b) in have.iter().zip(want) {
            let b = if positions { b - offset } else { *b };
            assert!(
                (a - b).abs() <= TRAVEL_ROUND_TRIP_PERCENT * b.abs().max(1.0),
                "positions {positions}: {a} against {b}"
            );
        }
    }
    // A unit cierva does not convert (the stick in mm), mapped by the sidecar's `channels:`:
    // the travel names it.
    let sub = dir.join("mm");
    std::fs::create_dir_all(&sub).unwrap();
    let csv = stick_in_degrees(&sub, SWEEP, true, "");
    let side = std::fs::read_to_string(sub.join("stick.yaml")).unwrap();
    std::fs::write(
        sub.join("stick.yaml"),
        side.replace("STICK: eta_s_deg", "STICK: eta_s_mm")
            .replace("eta_s_deg:", "eta_s_mm:")
            .replace("unit: deg", "unit: mm"),
    )
    .unwrap();
    let got = record::load(&csv).unwrap_or_else(|e| panic!("{}", e.render()));
    let (a, b) = (
        got.channel("eta_s_percent").unwrap(),
        sweep.channel("eta_s_percent").unwrap(),
    );
    assert!(
        a.iter()
            .zip(b)
            .all(|(a, b)| (a - b).abs() <= TRAVEL_ROUND_TRIP_PERCENT * b.abs().max(1.0))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cierva identify` on a record with its stick in degrees says how it read each column before
/// its estimates, so that a wrong travel shows.
#[test]
fn identify_says_how_it_read_a_logged_record() {
    let dir = scratch("identify-notes");
    let csv = stick_in_degrees(&dir, SWEEP, true, "");
    let (code, out, err) = super::common::cierva_in(&dir, &["identify", csv.to_str().unwrap()]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("  read: column `STICK` read as `eta_s_deg`"),
        "{out}"
    );
    assert!(
        out.contains("  read: `eta_s_deg` converted to `eta_s_percent` through its travel"),
        "{out}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A travel that cannot be applied is a located error at its entry in the sidecar.
#[test]
fn a_bad_travel_is_a_located_error() {
    let cases = [
        (
            ("eta_s: {unit: deg", "eta_z: {unit: deg"),
            "travel.eta_z",
            "`eta_z` is not a control of this record (did you mean `eta_s`?)",
        ),
        (
            ("at_100_percent: 14", "at_100_percent: -12"),
            "travel.eta_s",
            "a travel has two ends",
        ),
        (
            ("unit: deg", "unit: percent"),
            "travel.eta_s",
            "not `percent`",
        ),
        (
            ("logged: position", "logged: absolute"),
            "logged",
            "position",
        ),
    ];
    for (k, ((from, to), field, want)) in cases.iter().enumerate() {
        let dir = scratch(&format!("bad-travel-{k}"));
        let csv = stick_in_degrees(&dir, SWEEP, true, "");
        let side = std::fs::read_to_string(dir.join("stick.yaml")).unwrap();
        assert!(side.contains(from), "{from}");
        std::fs::write(dir.join("stick.yaml"), side.replacen(from, to, 1)).unwrap();
        let text = record::load(&csv).unwrap_err().render();
        assert!(text.contains(want), "{to}: {text}");
        assert!(
            text.contains("stick.yaml") && text.contains(field),
            "{text}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
    // The control's trim given twice, in % and in its own unit.
    let dir = scratch("bad-travel-trim");
    let csv = stick_in_degrees(&dir, SWEEP, true, "");
    let side = std::fs::read_to_string(dir.join("stick.yaml")).unwrap();
    std::fs::write(
        dir.join("stick.yaml"),
        side.replacen("trim:\n", "trim:\n  eta_s_percent: 48.0\n", 1),
    )
    .unwrap();
    let text = record::load(&csv).unwrap_err().render();
    assert!(text.contains("trim.eta_s_deg"), "{text}");
    assert!(text.contains("give the control's trim once"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The logged record of [`logged`] with the sidecar's `excitation` replaced by `block`.
fn with_excitation(dir: &Path, block: &str) -> PathBuf {
    let csv = logged(dir, MAP);
    let side = dir.join("logged.yaml");
    let text = std::fs::read_to_string(&side).unwrap();
    let mut kept = Vec::new();
    let mut skipping = false;
    for line in text.lines() {
        if line.starts_with("excitation:") {
            skipping = true;
            continue;
        }
        if skipping && line.starts_with(' ') {
            continue;
        }
        skipping = false;
        kept.push(line);
    }
    std::fs::write(&side, kept.join("\n") + "\n" + block).unwrap();
    csv
}

/// A sidecar's `excitation` names the channel recording what was added to a control: it loads
/// in any unit, kept as written; one that names no control of the record, no channel of the
/// CSV, or a control's own channel is a located error at its entry.
#[test]
fn a_records_excitation_is_checked_and_kept() {
    let dir = scratch("excitation-good");
    let rec = record::load(&with_excitation(
        &dir,
        "excitation:\n  eta_s_percent: alt_ft\n",
    ))
    .unwrap();
    assert_eq!(rec.meta.excitation["eta_s_percent"], "alt_ft");
    assert_eq!(rec.channel("alt_ft").unwrap()[0], 2000.0);
    let _ = std::fs::remove_dir_all(&dir);
    let cases = [
        (
            "excitation:\n  eta_z_percent: alt_ft\n",
            "`eta_z_percent` is not a control of this record",
        ),
        (
            "excitation:\n  eta_s_percent: sweep_cmd\n",
            "no channel `sweep_cmd` in",
        ),
        (
            "excitation:\n  eta_s_percent: eta_c_percent\n",
            "`eta_c_percent` is a control",
        ),
        (
            "excitation:\n  eta_s_percent: q_rad_s\n",
            "`q_rad_s` is a measured channel",
        ),
        (
            "excitation:\n  eta_s_percent: alt_ft\n  eta_t_percent: alt_ft\n",
            "is named for",
        ),
    ];
    for (k, (block, want)) in cases.iter().enumerate() {
        let dir = scratch(&format!("excitation-bad-{k}"));
        let e = record::load(&with_excitation(&dir, block)).unwrap_err();
        let text = e.render();
        assert!(text.contains(want), "{block}: {text}");
        assert!(
            text.contains("logged.yaml") && text.contains("excitation."),
            "{text}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
