//! A run as JUnit XML (`cierva validate --junit FILE`), which every CI system reads: one
//! `testsuite` per class of evidence (validation, cross-code, verification, regression), one
//! `testcase` per check (`classname` the case, `name` the check), and one more suite for the
//! files that did not load.
//!
//! How outcomes map: a pass is a plain testcase; a failure, a discrepancy that moved and an
//! unexpected pass are `<failure>` (the run is red for them) with the check's explanation, its
//! numbers; an error is `<error>`; an expected failure that stays where it was recorded is
//! `<skipped>` with its reason (as pytest writes an `xfail`). Each input error is an `<error>`
//! testcase of the suite `input errors`.

use crate::checks::CheckClass;
use crate::suite::outcome::{CheckResult, Outcome};
use std::fmt::Write as _;

/// The run's checks and input errors as a JUnit XML document.
pub fn junit_xml(results: &[CheckResult], input_errors: &[String]) -> String {
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let (failures, errors, skipped) = tally(results.iter());
    let _ = writeln!(
        s,
        "<testsuites name=\"cierva validate\" tests=\"{}\" failures=\"{failures}\" errors=\"{}\" skipped=\"{skipped}\">",
        results.len() + input_errors.len(),
        errors + input_errors.len(),
    );
    for class in CheckClass::ALL {
        let of: Vec<&CheckResult> = results.iter().filter(|r| r.class == class).collect();
        if of.is_empty() {
            continue;
        }
        let (failures, errors, skipped) = tally(of.iter().copied());
        let _ = writeln!(
            s,
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"{errors}\" skipped=\"{skipped}\">",
            class.name(),
            of.len(),
        );
        for r in of {
            let open = format!(
                "    <testcase classname=\"{}\" name=\"{}\"",
                escape(&r.case),
                escape(&r.check)
            );
            let body = match r.outcome {
                Outcome::Pass => None,
                Outcome::Fail | Outcome::DiscrepancyMoved | Outcome::UnexpectedPass => {
                    Some(element("failure", outcome_name(r.outcome), &r.explain()))
                }
                Outcome::Error => Some(element("error", "error", &r.explain())),
                Outcome::ExpectedFailure => Some(format!(
                    "<skipped message=\"expected failure: {}\"/>",
                    escape(r.expected_failure.as_deref().unwrap_or(""))
                )),
            };
            match body {
                None => s += &format!("{open}/>\n"),
                Some(b) => s += &format!("{open}>\n      {b}\n    </testcase>\n"),
            }
        }
        s += "  </testsuite>\n";
    }
    if !input_errors.is_empty() {
        let _ = writeln!(
            s,
            "  <testsuite name=\"input errors\" tests=\"{0}\" failures=\"0\" errors=\"{0}\" skipped=\"0\">",
            input_errors.len()
        );
        for (k, e) in input_errors.iter().enumerate() {
            let first = e.lines().next().unwrap_or("");
            let _ = writeln!(
                s,
                "    <testcase classname=\"input\" name=\"input error {}\">\n      {}\n    </testcase>",
                k + 1,
                element("error", first, e)
            );
        }
        s += "  </testsuite>\n";
    }
    s += "</testsuites>\n";
    s
}

/// How many of the results are failures, errors and skipped (expected failures).
fn tally<'a>(results: impl Iterator<Item = &'a CheckResult>) -> (usize, usize, usize) {
    let mut t = (0, 0, 0);
    for r in results {
        match r.outcome {
            Outcome::Fail | Outcome::DiscrepancyMoved | Outcome::UnexpectedPass => t.0 += 1,
            Outcome::Error => t.1 += 1,
            Outcome::ExpectedFailure => t.2 += 1,
            Outcome::Pass => {}
        }
    }
    t
}

/// The outcome's name as the table prints it.
fn outcome_name(o: Outcome) -> &'static str {
    match o {
        Outcome::Pass => "pass",
        Outcome::Fail => "failed",
        Outcome::ExpectedFailure => "expected failure",
        Outcome::DiscrepancyMoved => "discrepancy moved",
        Outcome::UnexpectedPass => "unexpected pass",
        Outcome::Error => "error",
    }
}

/// `<tag message="...">text</tag>`, both escaped.
fn element(tag: &str, message: &str, text: &str) -> String {
    format!(
        "<{tag} message=\"{}\">{}</{tag}>",
        escape(message),
        escape(text)
    )
}

/// Text as XML character data or an attribute value: the five special characters escaped,
/// and the control characters XML 1.0 does not allow dropped.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out += "&amp;",
            '<' => out += "&lt;",
            '>' => out += "&gt;",
            '"' => out += "&quot;",
            '\'' => out += "&apos;",
            '\n' => out += "&#10;",
            '\t' | '\r' => out.push(c),
            c if (c as u32) < 0x20 => {}
            c => out.push(c),
        }
    }
    out
}
