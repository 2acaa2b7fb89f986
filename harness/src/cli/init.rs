//! `cierva init`: a new suite, which validates as it is written.

use super::*;

/// Make a new suite in a folder: its marker (`cierva.toml`), the shared tolerances and an example
/// case that validates as it is written.
///
/// Example: `cierva init my-suite && cd my-suite && cierva validate`
#[derive(clap::Args)]
pub(crate) struct InitArgs {
    /// The folder to make a suite (made if missing; `.` for the working directory).
    pub(crate) dir: PathBuf,
    /// `text` for people, `json` for programs (what was written, as an object).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

pub(crate) fn init(a: InitArgs) -> Result<ExitCode, Error> {
    match cierva_harness::suite::init(&a.dir) {
        Ok(written) => {
            let shown: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
            done(
                a.format,
                format!(
                    "wrote {}: `cd {} && cierva validate` runs the example case",
                    shown.join(", "),
                    a.dir.display()
                ),
                serde_json::json!({"wrote": shown}),
            );
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(Error::input(e)),
    }
}
