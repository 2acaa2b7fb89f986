//! `cierva serve`: cierva's own aircraft as an external model, speaking the command protocol
//! `cierva-external/2` (see [`cierva_harness::external::serve`]).

use super::*;

/// Serve an aircraft through the command protocol `cierva-external/2` (docs/external-models.md):
/// what another tool, or cierva itself, asks of an external model. With a request file's path
/// it answers that request (one-shot: the protocol appends the path); without one it answers
/// requests as JSON lines on stdin until stdin ends (persistent mode). Its parameters are the
/// aircraft file's physical parameters, with the file's `ranges:`.
///
/// Example, in a case: `model: {external: {command: [cierva, serve, ../aircraft/vpm-m16.yaml],
/// protocol: cierva-external/2, persistent: true, timeout_s: 600}}`.
#[derive(clap::Args)]
pub(crate) struct ServeArgs {
    /// The aircraft file (see aircraft/).
    pub(crate) aircraft: PathBuf,
    /// A request file (one-shot); none: requests as JSON lines on stdin (persistent).
    pub(crate) request: Option<PathBuf>,
}

pub(crate) fn serve(a: ServeArgs) -> Result<ExitCode, Error> {
    let file = load_aircraft(&a.aircraft)?;
    let model = cierva_harness::external::CiervaAircraft::new(&file);
    match &a.request {
        Some(request) => {
            cierva_harness::external::serve::answer_file(&model, request).map_err(Error::failure)?
        }
        None => {
            let stdin = std::io::stdin().lock();
            let stdout = std::io::stdout().lock();
            cierva_harness::external::serve::answer_lines(&model, stdin, stdout)
                .map_err(|e| Error::failure(e.to_string()))?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
