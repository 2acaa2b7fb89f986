//! The `cierva` command line: the commands and their arguments, parsed and dispatched to
//! `cli/`, one module per command.

mod cli;

use clap::Subcommand;
use cli::*;

/// Verification and validation of rotorcraft flight-dynamics models against flight references.
///
/// Exit codes: 0 every check passed (or failed as its case expects, with the model where its
/// record says); 1 a check failed unexpectedly, a known discrepancy moved, an expected failure
/// passed, a check could not be evaluated or a score got worse; 2 bad input (a case or reference
/// file that does not load, a missing path, no cases).
#[derive(Parser)]
#[command(name = "cierva", version)]
struct Cli {
    /// No progress bars or progress messages on stderr (results and errors are still printed).
    /// Progress bars are drawn only when stderr is a terminal.
    #[arg(long, global = true)]
    quiet: bool,
    /// The suite to work on: a folder with a `cierva.toml` (default: the nearest one in the
    /// working directory or a folder above). Default paths (cases, reports, the scoreboard,
    /// discrepancy records, retune's outputs) are relative to it.
    #[arg(long, global = true, value_name = "DIR")]
    suite: Option<PathBuf>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Validate(ValidateArgs),
    Review(ReviewArgs),
    Fit(FitArgs),
    Modes(ModesArgs),
    Synth(SynthArgs),
    FrequencyResponse(FrequencyResponseArgs),
    Verify(VerifyArgs),
    Identify(IdentifyArgs),
    Inflow(InflowArgs),
    SynthTeeter(SynthTeeterArgs),
    Init(InitArgs),
    NewCase(NewCaseArgs),
    Bench(BenchArgs),
    Autorotate(AutorotateArgs),
    Sensitivity(SensitivityArgs),
    Serve(ServeArgs),
    Estimate(EstimateArgs),
    Uncertainty(UncertaintyArgs),
    Evaluate(EvaluateArgs),
    Linearize(LinearizeArgs),
    Simulate(SimulateArgs),
    SynthHistory(SynthHistoryArgs),
    SynthFlight(SynthFlightArgs),
    Retune(RetuneArgs),
    Trim(TrimArgs),
}

/// Output piped into a reader that stops early (`cierva validate | head`): `println!` panics on
/// the broken pipe. Leave quietly instead, with the exit status a shell gives a process that
/// SIGPIPE ended (128 + 13), so a pipeline can still tell the run was cut short.
fn quiet_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.contains("Broken pipe") {
            std::process::exit(141);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    quiet_on_broken_pipe();
    let cli = Cli::parse();
    QUIET.store(cli.quiet, std::sync::atomic::Ordering::Relaxed);
    let _ = SUITE_ARG.set(cli.suite);
    let run = match cli.command {
        Command::Validate(a) => validate(a),
        Command::Review(a) => review(a),
        Command::Fit(a) => fit(a),
        Command::Modes(a) => modes(a),
        Command::Synth(a) => synth(a),
        Command::FrequencyResponse(a) => frequency_response(a),
        Command::Verify(a) => verify(a),
        Command::Identify(a) => identify(a),
        Command::Inflow(a) => inflow(a),
        Command::SynthTeeter(a) => synth_teeter(a),
        Command::Init(a) => init(a),
        Command::NewCase(a) => new_case(a),
        Command::Bench(a) => bench(a),
        Command::Autorotate(a) => autorotate(a),
        Command::Sensitivity(a) => sensitivity(a),
        Command::Serve(a) => serve(a),
        Command::Estimate(a) => estimate(a),
        Command::Uncertainty(a) => uncertainty(a),
        Command::Evaluate(a) => evaluate(a),
        Command::Linearize(a) => linearize(a),
        Command::Simulate(a) => simulate(a),
        Command::SynthHistory(a) => synth_history(a),
        Command::SynthFlight(a) => synth_flight(a),
        Command::Retune(a) => retune(a),
        Command::Trim(a) => trim(a),
    };
    run.unwrap_or_else(Error::exit)
}
