//! Reading YAML files with errors that name the file, line, column and field.

use serde::de::DeserializeOwned;
use std::fmt;
use std::path::{Path, PathBuf};

/// An input error located in a file.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    pub path: PathBuf,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// 1-based column, when known.
    pub column: Option<usize>,
    /// Dotted path of the field (`checks[2].expect.period_s`), when known.
    pub field: Option<String>,
    pub message: String,
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
            if let Some(c) = self.column {
                write!(f, ":{c}")?;
            }
        }
        write!(f, ": ")?;
        if let Some(field) = &self.field {
            write!(f, "field `{field}`: ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for InputError {}

impl InputError {
    /// The error as a person reads it: the message, then the offending line of the file with a
    /// caret under the column (when the file and the location are known).
    pub fn render(&self) -> String {
        let mut out = format!("error: {self}");
        let Some(line) = self.line else { return out };
        let Ok(src) = std::fs::read_to_string(&self.path) else {
            return out;
        };
        let Some(text) = src.lines().nth(line.saturating_sub(1)) else {
            return out;
        };
        let col = self.column.unwrap_or(1).max(1);
        let w = line.to_string().len();
        out += &format!(
            "\n{:w$} |\n{line} | {text}\n{:w$} | {}^",
            "",
            "",
            " ".repeat(col - 1)
        );
        out
    }
}

/// The 1-based column of the `k`-th comma-separated field of a CSV line (after its leading
/// spaces): where a caret points at a bad value.
pub fn csv_field_column(line: &str, k: usize) -> usize {
    let start: usize = line.split(',').take(k).map(|c| c.chars().count() + 1).sum();
    let pad = line
        .split(',')
        .nth(k)
        .map_or(0, |c| c.chars().take_while(|ch| ch.is_whitespace()).count());
    start + pad + 1
}

/// The closest name by edit distance, if it is close enough to be a likely typo.
pub fn nearest<'a>(want: &str, have: &'a [String]) -> Option<&'a str> {
    have.iter()
        .map(|h| (edit_distance(want, h), h.as_str()))
        .filter(|(d, h)| *d <= 3.max(want.len() / 3) && !h.is_empty() && *d > 0)
        .min_by_key(|(d, _)| *d)
        .map(|(_, h)| h)
}

/// Levenshtein distance.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut cur = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let sub = prev[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            cur[j] = sub.min(prev[j] + 1).min(cur[j - 1] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

/// For serde's "unknown field `x`, expected one of `a`, `b`, ..." a suggestion of the nearest
/// expected field.
pub fn suggestion(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    let (unknown, tail) = rest.split_once('`')?;
    let expected: Vec<String> = tail
        .split('`')
        .enumerate()
        .filter(|(i, _)| i % 2 == 1)
        .map(|(_, s)| s.to_string())
        .collect();
    nearest(unknown, &expected).map(|n| format!("did you mean `{n}`?"))
}

impl InputError {
    /// An error about a whole file (I/O, or no better location).
    pub fn file(path: &Path, message: impl Into<String>) -> Self {
        Self {
            path: path.to_path_buf(),
            line: None,
            column: None,
            field: None,
            message: message.into(),
        }
    }

    /// An error about a field, located by searching the source for its key path. A field that
    /// cannot be found (a missing key, an entry inside a flow sequence) is located at its
    /// nearest enclosing key that can, and a top-level one at the start of the file.
    pub fn field(path: &Path, src: &str, field: &str, message: impl Into<String>) -> Self {
        let mut at = field;
        let mut found = locate(src, at);
        while found.is_none() {
            match at.rfind(['.', '[']) {
                Some(i) if i > 0 => {
                    at = &at[..i];
                    found = locate(src, at);
                }
                _ => break,
            }
        }
        if found.is_none() && !src.trim().is_empty() {
            found = Some((1, 1));
        }
        let (line, column) = found.unzip();
        Self {
            path: path.to_path_buf(),
            line,
            column,
            field: Some(field.to_string()),
            message: message.into(),
        }
    }
}

/// Writes `text` to `path` (making its folder) unless the file already holds it; returns whether
/// the file changed. For the files `cierva review --accept` writes, so that accepting what did
/// not move leaves them untouched.
pub fn write_if_changed(path: &Path, text: &str) -> std::io::Result<bool> {
    if std::fs::read_to_string(path).ok().as_deref() == Some(text) {
        return Ok(false);
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(path, text)?;
    Ok(true)
}

/// Reads a file to a string, with an error naming the file.
pub fn read(path: &Path) -> Result<String, InputError> {
    std::fs::read_to_string(path).map_err(|e| InputError::file(path, format!("cannot read: {e}")))
}

/// Parses YAML into `T`, turning a parse error into a located [`InputError`].
pub fn parse<T: DeserializeOwned>(path: &Path, src: &str) -> Result<T, InputError> {
    serde_yaml::from_str(src).map_err(|e| {
        let loc = e.location();
        let text = e.to_string();
        // yaml_serde writes "<field path>: <message> at line L column C".
        let text = match text.rfind(" at line ") {
            Some(i) if loc.is_some() => text[..i].to_string(),
            _ => text,
        };
        let (field, mut message) = match text.split_once(": ") {
            Some((f, m)) if looks_like_field_path(f) => (Some(f.to_string()), m.to_string()),
            _ => (None, text.clone()),
        };
        if let Some(hint) = suggestion(&message) {
            message = format!("{message}; {hint}");
        }
        let (mut line, mut column) = (loc.as_ref().map(|l| l.line()), loc.map(|l| l.column()));
        if line.is_none()
            && let Some((l, c)) = field.as_deref().and_then(|f| locate(src, f))
        {
            (line, column) = (Some(l), Some(c));
        }
        InputError {
            path: path.to_path_buf(),
            line,
            column,
            field,
            message,
        }
    })
}

fn looks_like_field_path(s: &str) -> bool {
    !s.is_empty()
        && !s.contains(' ')
        && s.chars()
            .all(|c| c.is_alphanumeric() || "_.[]-".contains(c))
}

/// Finds the line and column of a dotted key path (`checks[2].expect.value`) in YAML source.
///
/// A best-effort search for error messages: each key is looked for as `key:` at a deeper
/// indentation than its parent, and `[n]` selects the n-th `- ` item below the parent.
pub fn locate(src: &str, field: &str) -> Option<(usize, usize)> {
    let lines: Vec<&str> = src.lines().collect();
    let mut start = 0usize;
    let mut parent_indent: isize = -1;
    let mut found = None;
    // Inside a flow mapping (`{a: 1, b: {c: 2}}`): the line and column to search on from.
    let mut flow: Option<(usize, usize)> = None;
    let parts: Vec<&str> = field.split('.').collect();
    let mut i = 0;
    while i < parts.len() {
        // A key may itself contain dots (`sources: {mass.mass_kg: ...}`): try the longest.
        let mut matched = false;
        for j in (i..parts.len()).rev() {
            if j > i && parts[i..=j].iter().any(|p| p.contains('[')) {
                continue;
            }
            let joined = parts[i..=j].join(".");
            let (key, index) = match joined.split_once('[') {
                Some((k, rest)) => (
                    k.to_string(),
                    rest.trim_end_matches(']').parse::<usize>().ok(),
                ),
                None => (joined.clone(), None),
            };
            if key.is_empty() {
                if let Some(n) = index {
                    let (l, dash) = find_item(&lines, start, parent_indent, n)?;
                    found = Some((l + 1, dash as usize + 3));
                    start = l;
                    parent_indent = dash;
                }
                matched = true;
                i = j + 1;
                break;
            }
            if flow.is_none()
                && let Some((l, indent)) = find_key(&lines, start, parent_indent, &key)
            {
                found = Some((l + 1, indent as usize + 1));
                start = l + 1;
                parent_indent = indent;
                if let Some(n) = index {
                    // Keys of the item sit after "- ": deeper than the dash, the new parent.
                    let (l, dash) = find_item(&lines, start, parent_indent, n)?;
                    found = Some((l + 1, dash as usize + 3));
                    start = l;
                    parent_indent = dash;
                }
                matched = true;
                i = j + 1;
                break;
            }
            if index.is_none() {
                let from = flow.unwrap_or((start.saturating_sub(1), 0));
                if let Some((l, c)) = find_flow_key(&lines, from, parent_indent, &key) {
                    found = Some((l + 1, c + 1));
                    flow = Some((l, c + key.len()));
                    matched = true;
                    i = j + 1;
                    break;
                }
            }
        }
        if !matched {
            return None;
        }
    }
    found
}

/// A key inside a flow mapping, from line `from.0` column `from.1` on, over the lines that
/// continue the parent's block: its line and column (0-based).
fn find_flow_key(
    lines: &[&str],
    from: (usize, usize),
    parent: isize,
    key: &str,
) -> Option<(usize, usize)> {
    for (i, line) in lines.iter().enumerate().skip(from.0) {
        if i > from.0 && !line.trim().is_empty() && indent_of(line) <= parent {
            return None;
        }
        let skip = if i == from.0 {
            from.1.min(line.len())
        } else {
            0
        };
        let mut pos = skip;
        while let Some(k) = line[pos..].find(key) {
            let at = pos + k;
            let before = line[..at].trim_end();
            let after = line[at + key.len()..].trim_start();
            if (before.ends_with('{') || before.ends_with(',') || (i > from.0 && before.is_empty()))
                && after.starts_with(':')
            {
                return Some((i, at));
            }
            pos = at + key.len();
        }
    }
    None
}

fn indent_of(line: &str) -> isize {
    (line.len() - line.trim_start().len()) as isize
}

fn find_key(lines: &[&str], start: usize, parent: isize, key: &str) -> Option<(usize, isize)> {
    for (i, line) in lines.iter().enumerate().skip(start) {
        let t = line.trim_start();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let ind = indent_of(line);
        let t2 = t.strip_prefix("- ").unwrap_or(t);
        let ind2 = if t2.len() != t.len() { ind + 2 } else { ind };
        if ind2 <= parent && i > start {
            return None;
        }
        let key_quoted = [
            format!("{key}:"),
            format!("\"{key}\":"),
            format!("'{key}':"),
        ];
        if ind2 > parent && key_quoted.iter().any(|k| t2.starts_with(k.as_str())) {
            return Some((i, ind2));
        }
    }
    None
}

fn find_item(lines: &[&str], start: usize, parent: isize, n: usize) -> Option<(usize, isize)> {
    let mut count = 0;
    let mut item_indent = None;
    for (i, line) in lines.iter().enumerate().skip(start) {
        let t = line.trim_start();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let ind = indent_of(line);
        if ind <= parent && !t.starts_with('-') {
            return None;
        }
        if t.starts_with('-') && item_indent.is_none_or(|k| k == ind) {
            item_indent = Some(ind);
            if count == n {
                return Some((i, ind));
            }
            count += 1;
        }
    }
    None
}
