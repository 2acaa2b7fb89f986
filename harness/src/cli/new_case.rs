//! `cierva new-case`: a commented case file to start from. It validates wherever it is
//! written: its model is written out in it, its tolerances are its own, and missing folders
//! are made.

use super::*;

pub(crate) fn new_case(path: PathBuf, format: Format) -> ExitCode {
    let Some(id) = path.file_stem().map(|s| s.to_string_lossy().to_string()) else {
        eprintln!("error: {}: not a file name", path.display());
        return ExitCode::from(2);
    };
    if path.exists() {
        eprintln!("error: {} exists; not overwritten", path.display());
        return ExitCode::from(2);
    }
    let text = cierva_harness::suite::EXAMPLE_CASE.replace("CASE_ID", &id);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && let Err(e) = std::fs::create_dir_all(dir)
    {
        eprintln!("error: cannot make {}: {e}", dir.display());
        return ExitCode::from(2);
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
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: cannot write {}: {e}", path.display());
            ExitCode::from(2)
        }
    }
}
