//! `cierva new-case`: a commented case file to start from. It validates wherever it is
//! written: its model is written out in it, its tolerances are its own, and missing folders
//! are made.

use super::*;

/// Write a commented case file to start from (it validates as it is written).
///
/// Example: `cierva new-case cases/my-aircraft-70mph.yaml`
#[derive(clap::Args)]
pub(crate) struct NewCaseArgs {
    /// The case file to write; its id is the file name without `.yaml`.
    path: PathBuf,
    /// `text` for people, `json` for programs (what was written, as an object).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    format: Format,
}

pub(crate) fn new_case(a: NewCaseArgs) -> Result<ExitCode, Error> {
    let NewCaseArgs { path, format } = a;
    let Some(id) = path.file_stem().map(|s| s.to_string_lossy().to_string()) else {
        return Err(Error::input(format!("{}: not a file name", path.display())));
    };
    if path.exists() {
        return Err(Error::input(format!(
            "{} exists; not overwritten",
            path.display()
        )));
    }
    let text = cierva_harness::suite::EXAMPLE_CASE.replace("CASE_ID", &id);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && let Err(e) = std::fs::create_dir_all(dir)
    {
        return Err(Error::input(format!("cannot make {}: {e}", dir.display())));
    }
    match std::fs::write(&path, text) {
        Ok(()) => {
            done(
                format,
                format!(
                    "wrote {}: edit it, then `cierva validate {}`",
                    path.display(),
                    path.display()
                ),
                serde_json::json!({"wrote": [path.display().to_string()], "id": id}),
            );
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(Error::input(format!(
            "cannot write {}: {e}",
            path.display()
        ))),
    }
}
