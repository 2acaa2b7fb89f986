//! `cierva serve`: cierva's own aircraft as an external model, speaking the command protocol
//! `cierva-external/2` (see [`cierva_harness::external::serve`]).

use super::*;

/// Serve an aircraft or a rotor through the command protocol `cierva-external/2`
/// (docs/external-models.md): what another tool, or cierva itself, asks of an external model.
/// With a request file's path it answers that request (one-shot: the protocol appends the
/// path); without one it answers requests as JSON lines on stdin until stdin ends (persistent
/// mode). An aircraft answers trims, linear models, time histories and frequency responses, a
/// rotor its autorotation in a wind tunnel (with its file's physics); the parameters are the
/// file's physical parameters, with its `ranges:`, and its corrections.
///
/// Example, in a case: `model: {external: {command: [cierva, serve, ../aircraft/vpm-m16.yaml],
/// protocol: cierva-external/2, persistent: true, timeout_s: 600}}`.
#[derive(clap::Args)]
pub(crate) struct ServeArgs {
    /// The aircraft or rotor file (see aircraft/).
    pub(crate) file: PathBuf,
    /// A request file (one-shot); none: requests as JSON lines on stdin (persistent).
    pub(crate) request: Option<PathBuf>,
}

pub(crate) fn serve(a: ServeArgs) -> Result<ExitCode, Error> {
    let text = std::fs::read_to_string(&a.file)
        .map_err(|e| Error::input(format!("{}: {e}", a.file.display())))?;
    let top: serde_yaml::Value = serde_yaml::from_str(&text).unwrap_or_default();
    if top.get("rotor").is_some() && top.get("aircraft").is_none() {
        let file = cierva_harness::inputs::rotor::load(&a.file)
            .map_err(|e| Error::input(e.to_string()))?;
        let solver = file.physics().model().into();
        let model = cierva_harness::external::rotor::CiervaRotor::new(&file, solver);
        return answer(&model, a.request.as_deref());
    }
    let file = load_aircraft(&a.file)?;
    let model = cierva_harness::external::CiervaAircraft::new(&file);
    answer(&model, a.request.as_deref())
}

/// Answers the request file, or the requests on stdin.
fn answer(
    model: &dyn cierva_harness::external::FlightModel,
    request: Option<&std::path::Path>,
) -> Result<ExitCode, Error> {
    match request {
        Some(request) => {
            cierva_harness::external::serve::answer_file(model, request).map_err(Error::failure)?
        }
        None => {
            let stdin = std::io::stdin().lock();
            let stdout = std::io::stdout().lock();
            cierva_harness::external::serve::answer_lines(model, stdin, stdout)
                .map_err(|e| Error::failure(e.to_string()))?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
