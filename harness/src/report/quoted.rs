//! Numbers the documents quote from a run or from a committed file that a run wrote, each
//! marked with where it comes from, so that a test holds it to its source.
//!
//! A marker is an HTML comment written straight after the number (Markdown renders it as
//! nothing):
//!
//! ```text
//! N_v is 0.209<!-- run: cierva-table2-vpm-m16-70mph-max-weight::N_v --> at 450 kg
//! rotor speed 5.75<!-- file: reports/scoreboard.yaml scores.naca-tr515-table-iii.low-mu-rpm-rms.value percent --> % RMS
//! ```
//!
//! - `run: CASE::CHECK` is the model's value of the check's first quantity as the run gives it;
//!   `CASE::CHECK::QUANTITY` names the quantity, and a last `.expected`, `.lower` or `.upper`
//!   takes the check's expected value or an end of its allowed range instead
//!   (`CASE::CHECK::value.upper`). `CASE::CHECK#NAME` is a number of the check's fingerprint
//!   (what a BCAR check records beside its quantities: `margin_1_s`, ...).
//! - `file: PATH KEY` is a number in a YAML file of the suite, `KEY` its dotted path (a list's
//!   items by their index, from 0): the scoreboard, a discrepancy record, the acceptance log
//!   (append-only, so an old entry's `old` and `new` stay where they are), fitted corrections,
//!   the uncertainty summary; or a number in a snapshot table (`reports/snapshots/*.snap`,
//!   which `cargo test` holds to the run), `KEY` a row's quantity (`alpha_deg`), `.N` for its
//!   N-th column (`alpha_deg.2`). A key that holds dots is written as it is
//!   (`corrections.estimated.mass.ixx_kg_m2`), one that holds spaces without them
//!   (`regimes.mu>0.35.unsolved.lift_coefficient`), and a record's change in the acceptance log,
//!   text such as `value 0.320768`, by the name of its number (`changes.34.old.value`).
//! - A last word `percent` compares the number with its source times 100; `abs`, with its
//!   magnitude.
//!
//! The quoted number holds when it is the source rounded to the digits it is printed with
//! (0.209 holds 0.20871; 5.75 with `percent` holds 0.057503). A number is digits with an
//! optional decimal point, thousands grouped by `,` or a thin space, and a sign (`-` or `−`)
//! where the character before the sign is not a digit, letter or `>`: in `0.17<!-- ... -->-1.10`
//! the second number is positive.

use std::fmt::Write as _;
use std::path::Path;

/// Where a quoted number comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum QuoteSource {
    /// A check's result in the run.
    Check {
        case: String,
        check: String,
        /// The quantity's name; the check's first quantity when `None`.
        quantity: Option<String>,
        field: Field,
    },
    /// A number of a check's fingerprint in the run.
    Fingerprint {
        case: String,
        check: String,
        name: String,
    },
    /// A number in a committed YAML file, by its path in the suite and its dotted key.
    File { path: String, key: String },
}

/// Which number of a check's quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Field {
    /// The model's value.
    Value,
    Expected,
    Lower,
    Upper,
}

/// One marked number of a document.
#[derive(Debug, Clone, PartialEq)]
pub struct Quote {
    /// 1-based line and column of the number.
    pub line: usize,
    pub column: usize,
    /// The number as printed.
    pub printed: String,
    pub value: f64,
    /// Digits after the decimal point.
    pub decimals: usize,
    pub source: QuoteSource,
    /// The marker as written (`run: CASE::CHECK percent`), for messages.
    pub marker: String,
    /// Compare with the source times 100.
    pub percent: bool,
    /// Compare with the source's magnitude.
    pub magnitude: bool,
}

impl Quote {
    /// The source's value as it would be printed here: scaled, and rounded to the printed
    /// digits, with the printed number's minus sign.
    pub fn written(&self, source: f64) -> String {
        let v = self.scaled(source);
        let s = format!("{:.*}", self.decimals, v);
        if self.printed.starts_with('−') {
            s.replacen('-', "−", 1)
        } else {
            s
        }
    }

    fn scaled(&self, source: f64) -> f64 {
        let v = if self.percent { 100.0 * source } else { source };
        if self.magnitude { v.abs() } else { v }
    }

    /// Whether the printed number is `source` rounded to its digits.
    pub fn holds(&self, source: f64) -> bool {
        let v = self.scaled(source);
        let half_unit = 0.5 * 10f64.powi(-(self.decimals as i32));
        // The rounding's half unit, and a relative slack for the source's own last bits
        // (a value stored as 7.5000000e-2 must round to 7.5 either way).
        v.is_finite() && (v - self.value).abs() <= half_unit * (1.0 + 1e-9) + 1e-12 * v.abs()
    }
}

const OPEN: &str = "<!-- ";
const CLOSE: &str = " -->";

/// Every marked number of a document, in order, leaving out markers shown as code (in a
/// backtick span or a fenced block); an error for a marker without a number before it or that
/// does not parse, located by line and column.
pub fn quotes(text: &str) -> Result<Vec<Quote>, String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for (index, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut from = 0;
        while let Some(at) = line[from..].find(OPEN).map(|k| from + k) {
            let body_start = at + OPEN.len();
            let Some(end) = line[body_start..].find(CLOSE).map(|k| body_start + k) else {
                break;
            };
            from = end + CLOSE.len();
            // A marker shown as code (between backticks) is an example, not a quote.
            if line[..at].matches('`').count() % 2 == 0 {
                out.extend(quote_at(line, index + 1, at, &line[body_start..end])?);
            }
        }
    }
    Ok(out)
}

/// The quote whose marker, its text `body`, starts at byte `at` of `line` (1-based `line_no`);
/// `None` for a comment that is no marker.
fn quote_at(line: &str, line_no: usize, at: usize, body: &str) -> Result<Option<Quote>, String> {
    let place = |byte: usize| {
        format!(
            "line {line_no}, column {}",
            line[..byte].chars().count() + 1
        )
    };
    let (is_run, spec) = match (body.strip_prefix("run: "), body.strip_prefix("file: ")) {
        (Some(s), _) => (true, s),
        (_, Some(s)) => (false, s),
        _ => return Ok(None),
    };
    let (printed, start) = number_before(&line[..at])
        .ok_or_else(|| format!("{}: a `{body}` marker with no number before it", place(at)))?;
    let value = parse_number(&printed)
        .ok_or_else(|| format!("{}: `{printed}` is not a number", place(start)))?;
    let mut words: Vec<&str> = spec.split_whitespace().collect();
    let (mut percent, mut magnitude) = (false, false);
    while let Some(last) = words.last() {
        match *last {
            "percent" => percent = true,
            "abs" => magnitude = true,
            _ => break,
        }
        words.pop();
    }
    let source = match (is_run, words.as_slice()) {
        (true, [one]) => check_source(one),
        (false, [path, key]) => Some(QuoteSource::File {
            path: path.to_string(),
            key: key.to_string(),
        }),
        _ => None,
    }
    .ok_or_else(|| {
        let form = if is_run {
            "a run's number is `run: CASE::CHECK`, with `::QUANTITY`, `.expected`, `.lower`, \
             `.upper` or `#FINGERPRINT` after it"
        } else {
            "a file's number is `file: PATH KEY`"
        };
        format!("{}: `{body}`: {form}", place(at))
    })?;
    Ok(Some(Quote {
        marker: body.to_string(),
        line: line_no,
        column: line[..start].chars().count() + 1,
        decimals: printed.split('.').nth(1).map_or(0, |d| d.chars().count()),
        printed,
        value,
        source,
        percent,
        magnitude,
    }))
}

/// `CASE::CHECK`, `CASE::CHECK::QUANTITY[.FIELD]`, `CASE::CHECK.FIELD` or `CASE::CHECK#NAME`.
fn check_source(spec: &str) -> Option<QuoteSource> {
    if let Some((head, name)) = spec.split_once('#') {
        let (case, check) = head.split_once("::")?;
        return Some(QuoteSource::Fingerprint {
            case: case.into(),
            check: check.into(),
            name: name.into(),
        });
    }
    let (spec, field) = match spec.rsplit_once('.') {
        Some((s, "expected")) => (s, Field::Expected),
        Some((s, "lower")) => (s, Field::Lower),
        Some((s, "upper")) => (s, Field::Upper),
        _ => (spec, Field::Value),
    };
    let mut parts = spec.split("::");
    let case = parts.next().filter(|s| !s.is_empty())?;
    let check = parts.next().filter(|s| !s.is_empty())?;
    let quantity = parts.next().map(str::to_string);
    if parts.next().is_some() {
        return None;
    }
    Some(QuoteSource::Check {
        case: case.into(),
        check: check.into(),
        quantity,
        field,
    })
}

/// The number that ends `before` (digits, a decimal point, grouping commas or thin spaces,
/// a sign where it is one), with the byte offset where it starts.
fn number_before(before: &str) -> Option<(String, usize)> {
    let chars: Vec<(usize, char)> = before.char_indices().collect();
    let mut k = chars.len();
    let mut seen_digit = false;
    while k > 0 {
        let c = chars[k - 1].1;
        let grouping = (c == ',' || c == '\u{2009}')
            && seen_digit
            && k >= 2
            && chars[k - 2].1.is_ascii_digit();
        if c.is_ascii_digit() {
            seen_digit = true;
        } else if !(c == '.' || grouping) {
            break;
        }
        k -= 1;
    }
    if !seen_digit {
        return None;
    }
    // A leading `.` or grouping mark belongs to the prose, not the number.
    while k < chars.len() && !chars[k].1.is_ascii_digit() {
        k += 1;
    }
    if k > 0 {
        let sign = chars[k - 1].1;
        let before_sign = if k >= 2 { Some(chars[k - 2].1) } else { None };
        let is_sign = (sign == '-' || sign == '−')
            && !before_sign.is_some_and(|c| c.is_alphanumeric() || c == '>' || c == ')');
        if is_sign {
            k -= 1;
        }
    }
    let start = chars[k].0;
    Some((before[start..].to_string(), start))
}

fn parse_number(printed: &str) -> Option<f64> {
    let plain: String = printed
        .chars()
        .filter(|c| *c != ',' && *c != '\u{2009}')
        .map(|c| if c == '−' { '-' } else { c })
        .collect();
    plain.parse().ok()
}

/// The number at `key` in the file `path` of the suite at `root`: in a YAML file, `key` is
/// dotted (list items by index; a mapping's key may hold dots, and is written without its
/// spaces; a last part may name a number in text of `name number` pairs, the acceptance log's
/// record changes); in a snapshot (`.snap`, a table of a quantity a row), `key` is the row's
/// quantity, with `.N` for its N-th column of numbers (the first without).
pub fn from_file(root: &Path, path: &str, key: &str) -> Result<f64, String> {
    let file = root.join(path);
    let text = std::fs::read_to_string(&file).map_err(|e| format!("{path}: {e}"))?;
    if path.ends_with(".snap") {
        return from_snapshot(&text, key).map_err(|e| format!("{path}: {e}"));
    }
    let doc: serde_yaml::Value = serde_yaml::from_str(&text).map_err(|e| format!("{path}: {e}"))?;
    let parts: Vec<&str> = key.split('.').collect();
    let mut node = &doc;
    let mut k = 0;
    while k < parts.len() {
        // A mapping's key may hold dots itself (`airframe.fin.area_m2` in fitted
        // corrections): the shortest run of parts that names one is taken. A key's spaces
        // are left out (`mu>0.35` names `mu > 0.35`), since the marker's words end at one.
        let (next, used) = match node {
            serde_yaml::Value::Sequence(items) => {
                (parts[k].parse::<usize>().ok().and_then(|i| items.get(i)), 1)
            }
            serde_yaml::Value::Mapping(map) => (k + 1..=parts.len())
                .find_map(|end| {
                    let want = parts[k..end].join(".");
                    map.iter()
                        .find(|(name, _)| name.as_str().is_some_and(|n| n.replace(' ', "") == want))
                        .map(|(_, n)| (n, end - k))
                })
                .map_or((None, 1), |(n, used)| (Some(n), used)),
            // A record's change in the acceptance log is text: `value 0.320768` or
            // `period_s 10.3; rotor_rpm 96.2`; a last part names one of its numbers.
            serde_yaml::Value::String(text) if k + 1 == parts.len() => {
                return named_number(text, parts[k]).ok_or_else(|| {
                    format!("{path}'s `{key}`: `{text}` has no number `{}`", parts[k])
                });
            }
            _ => (None, 1),
        };
        node = next.ok_or_else(|| format!("{path} has no `{key}` (no `{}`)", parts[k]))?;
        k += used;
    }
    node.as_f64()
        .ok_or_else(|| format!("{path}'s `{key}` is not a number"))
}

/// The number in the row `quantity[.N]` of a snapshot's table (its body after the header's
/// closing `---`): the row's N-th number, the first without `.N`.
fn from_snapshot(text: &str, key: &str) -> Result<f64, String> {
    let (quantity, column) = match key.rsplit_once('.') {
        Some((q, n)) if n.parse::<usize>().is_ok_and(|n| n >= 1) => {
            (q, n.parse::<usize>().unwrap_or(1))
        }
        _ => (key, 1),
    };
    let body = text
        .splitn(3, "---")
        .nth(2)
        .ok_or("not a snapshot (no header)")?;
    let row = body
        .lines()
        .find(|l| l.split_whitespace().next() == Some(quantity))
        .ok_or(format!("no row `{quantity}`"))?;
    row.split_whitespace()
        .skip(1)
        .filter_map(|w| w.parse::<f64>().ok())
        .nth(column - 1)
        .ok_or(format!("row `{quantity}` has no number {column}"))
}

/// The number after `name` in text of `name number` pairs separated by `;`.
fn named_number(text: &str, name: &str) -> Option<f64> {
    text.split(';').find_map(|pair| {
        let mut words = pair.split_whitespace();
        (words.next() == Some(name)).then(|| words.next()?.parse().ok())?
    })
}

/// Checks every marked number of the document `file` (its contents `text`) against its
/// source, which `resolve` gives; the number of quotes checked, or every one that does not
/// hold, one a line: `FILE:LINE:COLUMN: PRINTED quotes SOURCE, which is VALUE (write WANT)`,
/// the form `scripts/update-generated-docs` reads to put the wanted numbers in place.
pub fn check(
    file: &str,
    text: &str,
    resolve: &dyn Fn(&QuoteSource) -> Result<f64, String>,
) -> Result<usize, String> {
    let found = quotes(text).map_err(|e| format!("{file}: {e}"))?;
    let mut wrong = String::new();
    for q in &found {
        match resolve(&q.source) {
            Ok(v) if q.holds(v) => {}
            Ok(v) => {
                let _ = writeln!(
                    wrong,
                    "{file}:{}:{}: {} quotes {}, which is {v} (write {})",
                    q.line,
                    q.column,
                    q.printed,
                    q.marker,
                    q.written(v)
                );
            }
            Err(e) => {
                let _ = writeln!(
                    wrong,
                    "{file}:{}:{}: {} quotes {}, which cannot be read: {e}",
                    q.line, q.column, q.printed, q.marker
                );
            }
        }
    }
    if wrong.is_empty() {
        Ok(found.len())
    } else {
        Err(wrong)
    }
}
