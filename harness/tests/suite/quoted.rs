//! The documents' quoted numbers (`report::quoted`): how a marker is read, and when a
//! printed number holds its source. The trial `cases::docs::quoted-numbers` applies them to
//! the shipped documents.

use cierva_harness::report::quoted::{self, Field, QuoteSource};

/// A temporary folder holding one file, `name`, with `text`; removed when dropped.
struct Folder(std::path::PathBuf);

impl Folder {
    fn path(&self) -> &std::path::Path {
        &self.0
    }
}

impl Drop for Folder {
    fn drop(&mut self) {
        std::fs::remove_dir_all(&self.0).ok();
    }
}

fn folder_with(name: &str, text: &str) -> Folder {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = crate::common::scratch(&format!("quoted-{k}"));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(name), text).unwrap();
    Folder(dir)
}

#[test]
fn a_marker_takes_the_number_just_before_it_with_its_digits_and_sign() {
    let text = "N_v is 0.209<!-- run: a::N_v --> and −0.783<!-- run: a::N_r::value.lower -->, \
                range 0.17<!-- file: f.yaml x.0.y -->-1.10<!-- file: f.yaml x.1.y percent abs -->; \
                cost 12,179<!-- run: a::fit#cost_start --> (<!-- not a marker -->)";
    let q = quoted::quotes(text).unwrap();
    let printed: Vec<(&str, f64, usize)> = q
        .iter()
        .map(|q| (q.printed.as_str(), q.value, q.decimals))
        .collect();
    assert_eq!(
        printed,
        [
            ("0.209", 0.209, 3),
            ("−0.783", -0.783, 3),
            ("0.17", 0.17, 2),
            ("1.10", 1.10, 2),
            ("12,179", 12179.0, 0)
        ]
    );
    assert_eq!(
        q[1].source,
        QuoteSource::Check {
            case: "a".into(),
            check: "N_r".into(),
            quantity: Some("value".into()),
            field: Field::Lower
        }
    );
    assert!(q[3].percent && q[3].magnitude);
    assert_eq!(
        q[4].source,
        QuoteSource::Fingerprint {
            case: "a".into(),
            check: "fit".into(),
            name: "cost_start".into()
        }
    );
    assert_eq!((q[1].line, q[1].column), (1, 38));
}

#[test]
fn a_printed_number_holds_its_source_rounded_to_its_digits_and_no_closer_one() {
    let q = &quoted::quotes("0.209<!-- run: a::b -->").unwrap()[0];
    assert!(q.holds(0.20871) && q.holds(0.2085) && q.holds(0.20949));
    assert!(!q.holds(0.2084) && !q.holds(0.2096) && !q.holds(-0.209));
    assert!(!q.holds(f64::NAN) && !q.holds(f64::INFINITY));
    let p = &quoted::quotes("5.75<!-- file: f k percent --> %").unwrap()[0];
    assert!(p.holds(0.057503) && !p.holds(0.0576));
    assert_eq!(p.written(0.0576), "5.76");
    let m = &quoted::quotes("−0.060<!-- run: a::b -->").unwrap()[0];
    assert!(m.holds(-0.0598598) && !m.holds(0.0598598));
    assert_eq!(m.written(-0.0612), "−0.061");
}

#[test]
fn a_marker_without_a_number_or_that_does_not_parse_is_a_located_error() {
    let e = quoted::quotes("text\nsee <!-- run: a::b -->").unwrap_err();
    assert!(
        e.contains("line 2, column 5") && e.contains("no number"),
        "{e}"
    );
    let e = quoted::quotes("1.0<!-- run: a -->").unwrap_err();
    assert!(e.contains("run: CASE::CHECK"), "{e}");
    let e = quoted::quotes("1.0<!-- file: only-a-path.yaml -->").unwrap_err();
    assert!(e.contains("file: PATH KEY"), "{e}");
}

#[test]
fn check_names_every_number_that_does_not_hold_with_what_to_write() {
    let text =
        "a 0.209<!-- run: c::N_v --> b\nc 0.5<!-- run: c::gone --> d\ne 3<!-- run: c::N_r --> f";
    let resolve = |s: &QuoteSource| match s {
        QuoteSource::Check { check, .. } if check == "N_v" => Ok(0.2201),
        QuoteSource::Check { check, .. } if check == "N_r" => Ok(3.2),
        _ => Err("case `c` has no check `gone`".to_string()),
    };
    let e = quoted::check("doc.md", text, &resolve).unwrap_err();
    let lines: Vec<&str> = e.lines().collect();
    assert_eq!(lines.len(), 2, "{e}");
    assert_eq!(
        lines[0],
        "doc.md:1:3: 0.209 quotes run: c::N_v, which is 0.2201 (write 0.220)"
    );
    assert!(lines[1].starts_with("doc.md:2:3: 0.5 quotes run: c::gone, which cannot be read"));
    assert_eq!(
        quoted::check("doc.md", "e 3<!-- run: c::N_r -->", &resolve),
        Ok(1)
    );
}

#[test]
fn a_file_number_is_read_by_its_dotted_key_with_list_indices() {
    let dir = folder_with(
        "r.yaml",
        "scores:\n  a-case:\n    rms: {value: 5.75e-2}\nlog:\n- changes: [{old: 21.0}]\n",
    );
    let dir = dir.path();
    assert_eq!(
        quoted::from_file(dir, "r.yaml", "scores.a-case.rms.value"),
        Ok(0.0575)
    );
    assert_eq!(
        quoted::from_file(dir, "r.yaml", "log.0.changes.0.old"),
        Ok(21.0)
    );
    let e = quoted::from_file(dir, "r.yaml", "scores.b-case.rms").unwrap_err();
    assert!(e.contains("no `b-case`"), "{e}");
    assert!(quoted::from_file(dir, "missing.yaml", "x").is_err());
}

#[test]
fn a_key_may_hold_dots_and_a_logged_record_change_names_its_numbers() {
    let dir = folder_with(
        "r.yaml",
        "estimated:\n  airframe.fin.area_m2: 0.66\nchanges:\n- old: value 0.320768\n  new: period_s 10.3; rotor_rpm 96.2\n",
    );
    let dir = dir.path();
    assert_eq!(
        quoted::from_file(dir, "r.yaml", "estimated.airframe.fin.area_m2"),
        Ok(0.66)
    );
    assert_eq!(
        quoted::from_file(dir, "r.yaml", "changes.0.old.value"),
        Ok(0.320768)
    );
    assert_eq!(
        quoted::from_file(dir, "r.yaml", "changes.0.new.rotor_rpm"),
        Ok(96.2)
    );
    assert!(quoted::from_file(dir, "r.yaml", "changes.0.new.drag").is_err());
}

#[test]
fn a_marker_shown_as_code_is_an_example_not_a_quote() {
    let text = "write `0.209<!-- run: CASE::CHECK -->` after it\n```\n1.0<!-- run: a::b -->\n```\n2.0<!-- run: a::c -->";
    let q = quoted::quotes(text).unwrap();
    assert_eq!(q.len(), 1);
    assert_eq!((q[0].printed.as_str(), q[0].line), ("2.0", 5));
}

#[test]
fn a_snapshot_number_is_read_by_its_row_and_column() {
    let dir = folder_with(
        "t.snap",
        "---\nsource: x\n---\nquantity      30 mph   70 mph\nalpha_deg      2.582    1.104\nrotor_rpm      417.5    430.2\n",
    );
    let dir = dir.path();
    assert_eq!(quoted::from_file(dir, "t.snap", "alpha_deg"), Ok(2.582));
    assert_eq!(quoted::from_file(dir, "t.snap", "rotor_rpm.2"), Ok(430.2));
    assert!(quoted::from_file(dir, "t.snap", "rotor_rpm.3").is_err());
    assert!(quoted::from_file(dir, "t.snap", "pitch_deg").is_err());
}
