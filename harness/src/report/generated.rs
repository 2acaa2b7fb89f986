//! The generated sections of the documents: the text between `<!-- NAME:start ... -->` and
//! `<!-- NAME:end -->` that a run (or a committed file a run wrote) determines. `cargo test`'s
//! docs trials (`cases::docs::*`) compare each with what it should be through [`check`], and
//! `scripts/update-generated-docs` puts the wanted text in place from [`check`]'s message, whose
//! wording it reads.

/// The body of the section `name` in `text`: from the line after its start marker to its end
/// marker; `None` when either marker is missing.
pub fn section<'a>(text: &'a str, name: &str) -> Option<&'a str> {
    let start = format!("<!-- {name}:start");
    let end = format!("<!-- {name}:end -->");
    let body = &text[text.find(&start)?..];
    let first = body.find('\n')? + 1;
    let stop = body.find(&end)?;
    body.get(first..stop)
}

/// Whether the section `name` of the document `file` (its contents `text`) is `want`. The error
/// names the file and section and gives the whole wanted text after "replace it with:", as
/// `scripts/update-generated-docs` reads it.
pub fn check(file: &str, text: &str, name: &str, want: &str) -> Result<(), String> {
    let got = section(text, name).ok_or(format!("{file} has no {name} markers"))?;
    if got == want {
        Ok(())
    } else {
        Err(format!(
            "{file}'s {name} is not what the run gives; replace it with:\n{want}"
        ))
    }
}
