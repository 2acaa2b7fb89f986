//! Reading YAML files with errors that name the file, line, column and field.
//!
//! Every input file is read within a size limit ([`MAX_YAML_FILE_BYTES`],
//! [`MAX_CSV_FILE_BYTES`]) and a YAML file's nesting is bounded ([`MAX_YAML_DEPTH_LEVELS`])
//! before it is parsed: the parser's work grows with the square of the nesting (a 400 kB file
//! nested 100,000 levels took 25 s to refuse). An error shows at most a screen's width of any
//! line ([`EXCERPT_CHARS`]), of the file and of what the message quotes from it.

use serde::de::DeserializeOwned;
use std::fmt;
use std::io::Read as _;
use std::path::{Path, PathBuf};

/// The largest YAML input file, bytes (16 MiB). The largest shipped one, the TR 515 case with
/// its 81 rows, is 55 kB; the acceptance log grows by about 1 kB an acceptance. A file beyond
/// it is refused before it is read.
pub const MAX_YAML_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// The largest CSV input file (a flight record, a control history, a response), bytes
/// (1 GiB): a record of [`crate::inputs::limits::MAX_RECORD_SAMPLES`] samples of 40 channels
/// at 25 characters a value. The largest shipped one is 207 kB. A file beyond it is refused
/// before it is read.
pub const MAX_CSV_FILE_BYTES: u64 = 1024 * 1024 * 1024;

/// The deepest nesting of a YAML file, levels (block and flow collections counted together).
/// The deepest shipped file nests 7 (an aircraft file's airframe tables); 64 is nine times
/// that. Checked before parsing, because the parser's work grows with the square of the
/// depth of flow collections (`[[[...]]]`, `{a: {a: ...}}`).
pub const MAX_YAML_DEPTH_LEVELS: usize = 64;

/// The most characters of a line an error shows (a screen's width), centred on the column;
/// and of anything a message quotes from the file (a value between backticks or quotes).
pub const EXCERPT_CHARS: usize = 100;

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
            write!(f, "field `{}`: ", shorten(field, EXCERPT_CHARS))?;
        }
        write!(f, "{}", shorten_quoted(&self.message))
    }
}

/// `text`, or, where it is longer than `max` characters, its first and last `max / 2 - 10`
/// with how many were left out between them.
pub(crate) fn shorten(text: &str, max: usize) -> String {
    let n = text.chars().count();
    if n <= max {
        return text.to_string();
    }
    let keep = max / 2 - 10;
    let head: String = text.chars().take(keep).collect();
    let tail: String = text.chars().skip(n - keep).collect();
    format!("{head}...({} characters)...{tail}", n - 2 * keep)
}

/// A message with every span it quotes (between backticks or double quotes: what serde and the
/// loaders quote from the file) shortened to [`EXCERPT_CHARS`].
fn shorten_quoted(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(4 * EXCERPT_CHARS));
    let mut rest = message;
    while let Some(open) = rest.find(['`', '"']) {
        let quote = &rest[open..open + 1];
        let Some(close) = rest[open + 1..].find(quote) else {
            break;
        };
        let inner = &rest[open + 1..open + 1 + close];
        out.push_str(&rest[..=open]);
        out.push_str(&shorten(inner, EXCERPT_CHARS));
        out.push_str(quote);
        rest = &rest[open + close + 2..];
    }
    out.push_str(rest);
    out
}

/// At most [`EXCERPT_CHARS`] characters of `line` around the 1-based character column `col`,
/// with `...` where it is cut, and the caret's column in the excerpt.
fn excerpt(line: &str, col: usize) -> (String, usize) {
    let chars: Vec<char> = line.chars().collect();
    if chars.len() <= EXCERPT_CHARS {
        return (line.to_string(), col);
    }
    let col = col.clamp(1, chars.len());
    let start = (col - 1)
        .saturating_sub(EXCERPT_CHARS / 2)
        .min(chars.len() - EXCERPT_CHARS);
    let end = start + EXCERPT_CHARS;
    let mut text: String = chars[start..end].iter().collect();
    let mut caret = col - start;
    if start > 0 {
        text = format!("...{text}");
        caret += 3;
    }
    if end < chars.len() {
        text.push_str("...");
    }
    (text, caret)
}

impl std::error::Error for InputError {}

impl InputError {
    /// The error as a person reads it: the message, then the offending line of the file with a
    /// caret under the column (when the file and the location are known).
    pub fn render(&self) -> String {
        let mut out = format!("error: {self}");
        let Some(line) = self.line else { return out };
        let Ok(src) = read_limited(&self.path, MAX_CSV_FILE_BYTES) else {
            return out;
        };
        let Some(text) = src.lines().nth(line.saturating_sub(1)) else {
            return out;
        };
        let (text, col) = excerpt(text, self.column.unwrap_or(1).max(1));
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

/// A number as a file or a model writes it (`3.2`, `-1e-3`): `Err` with the reason for text that
/// is not a number, a number that is not finite, and a number too small for a double (below
/// about 5e-324), which the standard parser would read as 0 without a word (`1e-400`).
pub fn number(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let v: f64 = t
        .parse()
        .map_err(|_| format!("`{}` is not a number", shorten(t, EXCERPT_CHARS)))?;
    if !v.is_finite() {
        return Err(format!(
            "`{}` is not a finite number",
            shorten(t, EXCERPT_CHARS)
        ));
    }
    if underflows(t, v) {
        return Err(underflow_message(t));
    }
    Ok(v)
}

/// Whether the number written `t` (which reads as `v`) is not zero but reads as zero.
fn underflows(t: &str, v: f64) -> bool {
    v == 0.0
        && t.split(['e', 'E'])
            .next()
            .is_some_and(|mantissa| mantissa.bytes().any(|b| (b'1'..=b'9').contains(&b)))
}

fn underflow_message(t: &str) -> String {
    format!(
        "`{}` is too small for a double (the smallest is about 5e-324) and would read as 0: \
         write 0 where 0 is meant",
        shorten(t, EXCERPT_CHARS)
    )
}

/// The first number in a JSON text that is not zero but would read as zero (`1e-400`), with
/// its 1-based line and column: JSON parsers take it as 0 without a word.
pub fn json_underflow(text: &str) -> Option<(usize, usize, String)> {
    let bytes = text.as_bytes();
    let (mut line, mut line_start) = (1, 0);
    let mut in_string = false;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if in_string {
            match b {
                b'\\' => i += 1,
                b'"' => in_string = false,
                b'\n' => (line, line_start) = (line + 1, i + 1),
                _ => {}
            }
            i += 1;
            continue;
        }
        match b {
            b'"' => in_string = true,
            b'\n' => (line, line_start) = (line + 1, i + 1),
            b'-' | b'0'..=b'9' => {
                let start = i;
                while i < bytes.len()
                    && matches!(bytes[i], b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9')
                {
                    i += 1;
                }
                let t = &text[start..i];
                if let Ok(v) = t.parse::<f64>()
                    && underflows(t, v)
                {
                    let column = text[line_start..start].chars().count() + 1;
                    return Some((line, column, underflow_message(t)));
                }
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// The closest name by edit distance, if it is close enough to be a likely typo.
pub fn nearest<'a>(want: &str, have: &'a [String]) -> Option<&'a str> {
    have.iter()
        .map(|h| (edit_distance(want, h), h.as_str()))
        .filter(|(d, h)| *d <= 3.max(want.len() / 3) && !h.is_empty() && *d > 0)
        .min_by_key(|(d, _)| *d)
        .map(|(_, h)| h)
}

/// How many edits away from a name cierva reads (a response a record lacks, a trim point's
/// quantity) a column is taken for a misspelling of it (`theta_dg`, `rotor_rmp`) rather than
/// another column: two, a transposition or a dropped and a changed letter. A logger's other
/// channels (altitudes, accelerations, temperatures: `alt_ft`, `nz_g`) lie further from these
/// names.
pub const NEAR_MISS_EDITS: usize = 2;

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

/// Reads a YAML file to a string, with an error naming the file; one larger than
/// [`MAX_YAML_FILE_BYTES`] is refused unread.
pub fn read(path: &Path) -> Result<String, InputError> {
    read_limited(path, MAX_YAML_FILE_BYTES)
}

/// Reads a CSV file to a string, with an error naming the file; one larger than
/// [`MAX_CSV_FILE_BYTES`] is refused unread.
pub fn read_csv(path: &Path) -> Result<String, InputError> {
    read_limited(path, MAX_CSV_FILE_BYTES)
}

/// A file that is not UTF-8 text: an error at the line and column of its first bad byte
/// (the column counts the characters before it on its line, plus one), naming the byte.
fn not_utf8(path: &Path, bytes: &[u8], e: std::str::Utf8Error) -> InputError {
    let good = &bytes[..e.valid_up_to()];
    let line_start = good.iter().rposition(|b| *b == b'\n').map_or(0, |i| i + 1);
    let line = good.iter().filter(|b| **b == b'\n').count() + 1;
    let column = String::from_utf8_lossy(&good[line_start..]).chars().count() + 1;
    let byte = bytes.get(e.valid_up_to()).copied().unwrap_or(0);
    InputError {
        path: path.to_path_buf(),
        line: Some(line),
        column: Some(column),
        field: None,
        message: format!(
            "the file is not valid UTF-8 text: byte 0x{byte:02x} at line {line}, column \
             {column} (save it as UTF-8; a spreadsheet's \"CSV UTF-8\" does)"
        ),
    }
}

/// Reads at most `limit` bytes of a file; a longer one is an error that says so.
pub fn read_limited(path: &Path, limit: u64) -> Result<String, InputError> {
    let cannot = |e: std::io::Error| InputError::file(path, format!("cannot read: {e}"));
    let file = std::fs::File::open(path).map_err(cannot)?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > limit {
        let kind = if limit == MAX_CSV_FILE_BYTES {
            "CSV"
        } else {
            "YAML"
        };
        return Err(InputError::file(
            path,
            format!(
                "the file is larger than {} MiB, the most a {kind} input file may be \
                 (MAX_{kind}_FILE_BYTES)",
                limit >> 20
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|e| not_utf8(path, e.as_bytes(), e.utf8_error()))
}

/// The first place where `src` nests collections deeper than `limit` levels, 1-based line and
/// column, if any. A scan of the text, linear in its length, for [`parse`] to run before the
/// parser (whose work grows with the square of the depth): block collections are counted by
/// their indentation and `- ` items, flow collections by their brackets outside quoted
/// scalars, comments and block scalars. Where the text is not valid YAML the count is a guess,
/// and the parser's own error follows for any file within the limit.
pub fn too_deep(src: &str, limit: usize) -> Option<(usize, usize)> {
    let mut scan = DepthScan::default();
    for (i, line) in src.lines().enumerate() {
        if let Some(at) = scan.line(line.as_bytes(), limit) {
            // The scan's columns are bytes; the error's is characters.
            let col = line.get(..at).map_or(at, |s| s.chars().count());
            return Some((i + 1, col + 1));
        }
    }
    None
}

/// The state of [`too_deep`]'s scan between lines.
#[derive(Default)]
struct DepthScan {
    /// The open block collections: the column of each and whether it is a sequence.
    blocks: Vec<(usize, bool)>,
    /// Open flow collections (`[`, `{`).
    flow: usize,
    /// Inside a quoted scalar that runs on: its quote.
    quote: Option<u8>,
    /// Inside a block scalar (`|`, `>`): the column its lines are indented beyond.
    block_scalar: Option<usize>,
}

impl DepthScan {
    /// Scans one line; the 0-based byte column where the depth first exceeds `limit`. The scan
    /// goes by bytes, without allocating: every character it looks for is ASCII, which no byte
    /// of a longer UTF-8 character can be mistaken for, and YAML's white space is ASCII.
    fn line(&mut self, chars: &[u8], limit: usize) -> Option<usize> {
        let indent = chars.iter().take_while(|c| **c == b' ').count();
        let blank = chars[indent..].iter().all(u8::is_ascii_whitespace);
        if let Some(parent) = self.block_scalar {
            if blank || indent > parent {
                return None;
            }
            self.block_scalar = None;
        }
        if self.quote.is_some() || self.flow > 0 {
            return self.inline(chars, 0, limit);
        }
        if blank || chars[indent] == b'#' {
            return None;
        }
        let text = &chars[indent..];
        if text.starts_with(b"---") || text.starts_with(b"...") || text.starts_with(b"%") {
            self.blocks.clear();
            return None;
        }
        let item = |at: usize| {
            chars.get(at) == Some(&b'-') && chars.get(at + 1).is_none_or(|c| *c == b' ')
        };
        let seq = item(indent);
        // Close the collections this line is outside; a sequence's items may sit at its key's
        // column.
        while let Some(&(col, is_seq)) = self.blocks.last() {
            if col > indent || (col == indent && is_seq && !seq) {
                self.blocks.pop();
            } else {
                break;
            }
        }
        let mut at = indent;
        let mut is_seq = seq;
        loop {
            if self.blocks.last() != Some(&(at, is_seq)) {
                let key = !is_seq && key_ends(chars, at).is_some();
                if !is_seq && !key {
                    // A scalar on its own line (a plain scalar's continuation).
                    return self.value(chars, at, indent, limit);
                }
                self.blocks.push((at, is_seq));
                if self.blocks.len() + self.flow > limit {
                    return Some(at);
                }
            }
            let next = if is_seq {
                at + 1
            } else {
                match key_ends(chars, at) {
                    Some(colon) => colon + 1,
                    None => return self.value(chars, at, indent, limit),
                }
            };
            let start = next
                + chars[next.min(chars.len())..]
                    .iter()
                    .take_while(|c| **c == b' ')
                    .count();
            if start >= chars.len() {
                return None;
            }
            if item(start) {
                (at, is_seq) = (start, true);
            } else if is_seq && key_ends(chars, start).is_some() {
                (at, is_seq) = (start, false);
            } else {
                let owner = self.blocks.last().map_or(indent, |b| b.0);
                return self.value(chars, start, owner, limit);
            }
        }
    }

    /// A value from column `at` on (after `key:` or `- `), in a collection at column `owner`.
    fn value(&mut self, chars: &[u8], at: usize, owner: usize, limit: usize) -> Option<usize> {
        let mut at = at;
        // Anchors and tags come before the value.
        while matches!(chars.get(at), Some(b'&' | b'!')) {
            at += chars[at..].iter().take_while(|c| **c != b' ').count();
            at += chars[at..].iter().take_while(|c| **c == b' ').count();
        }
        match chars.get(at) {
            Some(b'[' | b'{' | b'\'' | b'"') => self.inline(chars, at, limit),
            Some(b'|' | b'>') => {
                self.block_scalar = Some(owner);
                None
            }
            _ => None,
        }
    }

    /// Flow collections and quoted scalars from column `from` on.
    fn inline(&mut self, chars: &[u8], from: usize, limit: usize) -> Option<usize> {
        let mut token_start = true;
        let mut k = from;
        while k < chars.len() {
            let c = chars[k];
            match self.quote {
                Some(b'\'') if c == b'\'' => {
                    if chars.get(k + 1) == Some(&b'\'') {
                        k += 1;
                    } else {
                        self.quote = None;
                        token_start = false;
                    }
                }
                Some(b'"') if c == b'\\' => k += 1,
                Some(b'"') if c == b'"' => {
                    self.quote = None;
                    token_start = false;
                }
                Some(_) => {}
                None => match c {
                    b'[' | b'{' => {
                        self.flow += 1;
                        if self.blocks.len() + self.flow > limit {
                            return Some(k);
                        }
                        token_start = true;
                    }
                    b']' | b'}' => {
                        self.flow = self.flow.saturating_sub(1);
                        token_start = false;
                        if self.flow == 0 {
                            return None;
                        }
                    }
                    b',' => token_start = true,
                    b':' => token_start = chars.get(k + 1).is_none_or(u8::is_ascii_whitespace),
                    b'\'' | b'"' if token_start => self.quote = Some(c),
                    b'#' if k == 0 || chars[k - 1].is_ascii_whitespace() => return None,
                    c if c.is_ascii_whitespace() => {}
                    _ => token_start = false,
                },
            }
            k += 1;
        }
        None
    }
}

/// Where the key of a block mapping entry starting at column `at` ends: the column of its
/// `:` (followed by a space or the end of the line), outside quotes, before any comment.
fn key_ends(chars: &[u8], at: usize) -> Option<usize> {
    let mut k = at;
    if let Some(&q) = chars.get(at).filter(|c| matches!(c, b'\'' | b'"')) {
        k = at + 1 + chars[at + 1..].iter().position(|c| *c == q)? + 1;
    } else if matches!(
        chars.get(at),
        Some(b'[' | b'{' | b'#' | b'|' | b'>' | b'&' | b'*' | b'!')
    ) {
        return None;
    }
    while k < chars.len() {
        match chars[k] {
            b':' if chars.get(k + 1).is_none_or(|c| *c == b' ') => return Some(k),
            b'#' if chars[k - 1] == b' ' => return None,
            _ => k += 1,
        }
    }
    None
}

/// Parses YAML into `T`, turning a parse error into a located [`InputError`]. A file nested
/// deeper than [`MAX_YAML_DEPTH_LEVELS`] is refused before the parser sees it.
pub fn parse<T: DeserializeOwned>(path: &Path, src: &str) -> Result<T, InputError> {
    if let Some((line, column)) = too_deep(src, MAX_YAML_DEPTH_LEVELS) {
        return Err(InputError {
            path: path.to_path_buf(),
            line: Some(line),
            column: Some(column),
            field: None,
            message: format!(
                "nested deeper than {MAX_YAML_DEPTH_LEVELS} levels, the most a YAML input file \
                 may nest (MAX_YAML_DEPTH_LEVELS)"
            ),
        });
    }
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
