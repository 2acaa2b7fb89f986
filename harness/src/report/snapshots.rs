//! A case's regression snapshots written out: the tables of what
//! [`crate::suite::snapshots::Snapshot::compute`] computed (this module computes nothing).

use super::tables;
use crate::suite::snapshots::Holds;

/// A snapshot's text.
pub fn render(computed: &Holds) -> String {
    match computed {
        Holds::Autorotation(rows) => tables::autorotation_table(rows),
        Holds::TimeHistories(rows) => tables::time_history_table(rows),
        Holds::Trim(columns) => tables::trim_table(columns),
        Holds::Linearised {
            model,
            components,
            modes,
        } => {
            let breakdown = components.as_ref().map_or(String::new(), |c| {
                tables::breakdown_table(model, c, tables::PRIMARY_DERIVATIVES) + "\n"
            });
            format!(
                "{breakdown}{}\n{}",
                tables::modes_table(modes),
                tables::derivatives_table(model)
            )
        }
        Holds::Derivatives(model) => tables::derivatives_table(model),
        Holds::Modes(modes) => tables::modes_table(modes),
        Holds::Milne(model) => tables::milne_table(model),
    }
}
