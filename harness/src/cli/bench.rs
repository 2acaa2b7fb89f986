//! `cierva bench`: timings of the model and the harness (reports/benchmarks.md), measured by
//! `cierva_harness::bench`.

use super::*;
use cierva_harness::bench::BenchGroup;

/// Time the model and the harness in groups and print medians as reports/benchmarks.md holds
/// them: the rotor (the blade right-hand side, a periodic blade solution, an autorotation), the
/// aircraft (trims, linearisations, simulations), identification, frequency responses,
/// fitting and retuning, uncertainty, and the command protocol's cost a request (`external`).
///
/// Example: `cargo run --release -- bench --repeat 51`
#[derive(Parser)]
pub(crate) struct BenchArgs {
    /// Repeats of each timed operation.
    #[arg(long, default_value_t = 21)]
    pub(crate) repeat: usize,
    /// `text` (a Markdown table, as in reports/benchmarks.md) or `json` (rows of operation,
    /// median and notes).
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
    /// Only this group of rows (all by default).
    #[arg(long, value_enum)]
    pub(crate) only: Option<BenchGroup>,
}

pub(crate) fn bench(a: BenchArgs) -> Result<ExitCode, Error> {
    let (repeat, format, only) = (a.repeat, a.format, a.only);
    let root = suite()?.root;
    let rows = std::cell::RefCell::new(Vec::new());
    // Text rows print as they are measured; JSON gathers them.
    let each = |line: &str| match format {
        Format::Text => println!("{line}"),
        Format::Json => rows.borrow_mut().push(line.to_string()),
    };
    for warning in cierva_harness::bench::run(&root, repeat, only, &each).map_err(Error::input)? {
        eprintln!("({warning})");
    }
    if format == Format::Json {
        let cells = |l: &str| -> Vec<String> {
            l.trim()
                .trim_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect()
        };
        let measured: Vec<serde_json::Value> = rows
            .borrow()
            .iter()
            .skip(2)
            .map(|l| {
                let c = cells(l);
                serde_json::json!({
                    "operation": c.first(),
                    "median": c.get(1),
                    "notes": c.get(2),
                })
            })
            .collect();
        done(
            format,
            String::new(),
            serde_json::json!({"repeat": repeat.max(3), "rows": measured}),
        );
    }
    Ok(ExitCode::SUCCESS)
}
