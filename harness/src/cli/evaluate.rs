//! `cierva evaluate`: one shard of a plan (see [`cierva_harness::plan`]).

use super::*;
use cierva_harness::plan;

/// Evaluate shard I of N of a plan (`cierva uncertainty --plan DIR` and `cierva sensitivity
/// --plan DIR` write one, and `cierva fit` and `cierva retune` given `--evaluate-with CMD` one a
/// batch, for CMD to run): an Nth of
/// its groups of evaluations, on every core this process may use, each evaluation's results
/// written as it finishes and the shard's to DIR/results/shard-I-of-N.yaml at its end. A shard
/// already done is skipped; one that was stopped takes up where it stopped (a killed worker
/// loses only the evaluation it was running). What an engine runs on each worker: a Slurm job
/// array's task, a Dask task (docs/scaling.md).
///
/// Example: `cierva uncertainty cases/cierva-table2-vpm-m16-70mph-max-weight.yaml --plan
/// /tmp/study`, then on each of 16 workers `cierva evaluate /tmp/study --shard I/16` (I from 1
/// to 16), then `cierva uncertainty --from-plan /tmp/study`.
#[derive(clap::Args)]
pub(crate) struct EvaluateArgs {
    /// The plan's folder.
    pub(crate) dir: PathBuf,
    /// Which shard, I of N (I from 1 to N): `--shard 3/16`.
    #[arg(long, default_value = "1/1")]
    pub(crate) shard: String,
    /// The most evaluations run at once (default: one a core this process may use, as its
    /// affinity or a batch scheduler's allocation sets it): 1 for a worker given one slot.
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

pub(crate) fn evaluate(a: EvaluateArgs) -> Result<ExitCode, Error> {
    let shard = plan::parse_shard(&a.shard).map_err(Error::input)?;
    match a.threads {
        Some(0) => return Err(Error::input("--threads 0: give at least 1")),
        Some(n) => cierva_harness::run::parallel::set_threads(n),
        None => {}
    }
    let loaded = plan::load(&plan::enter(&a.dir)?).map_err(Error::from)?;
    let mine = plan::shard_evaluations(&loaded, shard).len();
    let bar = progress(mine as u64, &format!("shard {}/{}", shard.0, shard.1));
    let report = plan::evaluate(&loaded, shard, || bar.inc(1)).map_err(Error::from)?;
    bar.finish_and_clear();
    let text = if report.already_done == report.evaluations {
        format!(
            "shard {} of {}: already done ({} evaluations in {})",
            report.shard,
            report.of,
            report.evaluations,
            report.path.display()
        )
    } else {
        format!(
            "shard {} of {}: {} evaluations ({} done before) in {:.1} s; wrote {}",
            report.shard,
            report.of,
            report.evaluations,
            report.already_done,
            report.seconds,
            report.path.display()
        )
    };
    done(
        a.format,
        text,
        serde_json::to_value(&report).expect("a report serialises"),
    );
    Ok(ExitCode::SUCCESS)
}
