//! Control time histories from CSV, and simulation output to CSV.
//!
//! An input CSV has a `time_s` column, rising, and any of `eta_s_percent`, `eta_c_percent`,
//! `eta_p_percent`, `eta_t_percent`: changes from the trimmed controls, in percent of travel
//! (longitudinal stick, lateral stick, pedal, throttle). Values are interpolated linearly in
//! time and held beyond the ends.

use crate::inputs::yaml::InputError;
use cierva_model::aircraft::Controls;
use cierva_model::simulation::timehistory::TimeHistory;
use std::path::Path;

/// The control columns an input CSV may carry.
pub const CONTROL_COLUMNS: [&str; 4] = [
    "eta_s_percent",
    "eta_c_percent",
    "eta_p_percent",
    "eta_t_percent",
];

/// Control changes from trim against time.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlTable {
    pub time_s: Vec<f64>,
    /// One column per [`CONTROL_COLUMNS`] entry (zeros where the file has none).
    pub changes: [Vec<f64>; 4],
}

impl ControlTable {
    /// The control changes at time `t`.
    pub fn at(&self, t: f64) -> [f64; 4] {
        let ts = &self.time_s;
        let i = ts.partition_point(|&x| x <= t);
        std::array::from_fn(|c| {
            let v = &self.changes[c];
            if i == 0 {
                v[0]
            } else if i >= ts.len() {
                v[ts.len() - 1]
            } else {
                let f = (t - ts[i - 1]) / (ts[i] - ts[i - 1]);
                v[i - 1] + f * (v[i] - v[i - 1])
            }
        })
    }

    /// Trim controls plus the changes at `t`.
    pub fn controls(&self, trim: &Controls, t: f64) -> Controls {
        let d = self.at(t);
        Controls {
            stick_longitudinal_percent: trim.stick_longitudinal_percent + d[0],
            stick_lateral_percent: trim.stick_lateral_percent + d[1],
            pedal_percent: trim.pedal_percent + d[2],
            throttle_percent: trim.throttle_percent + d[3],
        }
    }
}

/// Reads an input CSV; errors name the file, line and column.
pub fn read(path: &Path) -> Result<ControlTable, InputError> {
    let src = crate::inputs::yaml::read_csv(path)?;
    let mut lines = src
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    let (hline, header) = lines
        .next()
        .ok_or_else(|| InputError::file(path, "the file is empty"))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    // An error at a line, its caret under the `cell`-th comma-separated field (1-based column).
    let at_cell = |line: usize, text: &str, cell: usize, msg: String| {
        let mut e = InputError::file(path, msg);
        e.line = Some(line + 1);
        e.column = Some(crate::inputs::yaml::csv_field_column(text, cell));
        e
    };
    let at_line = |line: usize, text: &str, msg: String| at_cell(line, text, 0, msg);
    let time_col = names.iter().position(|n| *n == "time_s").ok_or_else(|| {
        at_line(
            hline,
            header,
            format!("no `time_s` column; the header has [{}]", names.join(", ")),
        )
    })?;
    let mut cols = [None; 4];
    for (k, n) in names.iter().enumerate() {
        if k == time_col {
            continue;
        }
        match CONTROL_COLUMNS.iter().position(|c| c == n) {
            Some(c) => cols[c] = Some(k),
            None => {
                let known: Vec<String> = std::iter::once("time_s")
                    .chain(CONTROL_COLUMNS.iter().copied())
                    .map(String::from)
                    .collect();
                let hint = crate::inputs::yaml::nearest(n, &known)
                    .map(|k| format!(" (did you mean `{k}`?)"))
                    .unwrap_or_default();
                return Err(at_cell(
                    hline,
                    header,
                    k,
                    format!(
                        "unknown column `{n}`{hint}: expected `time_s` and any of {}",
                        CONTROL_COLUMNS.join(", ")
                    ),
                ));
            }
        }
    }
    let mut table = ControlTable {
        time_s: Vec::new(),
        changes: Default::default(),
    };
    let most = crate::inputs::limits::MAX_RECORD_SAMPLES;
    for (row, (line, l)) in lines.enumerate() {
        if row == most {
            return Err(at_line(
                line,
                l,
                format!(
                    "a control history may have at most {most} rows (MAX_RECORD_SAMPLES); this one has more"
                ),
            ));
        }
        let cells: Vec<&str> = l.split(',').map(str::trim).collect();
        if cells.len() != names.len() {
            return Err(at_line(
                line,
                l,
                format!(
                    "{} values where the header has {}",
                    cells.len(),
                    names.len()
                ),
            ));
        }
        let value = |k: usize| -> Result<f64, InputError> {
            crate::inputs::yaml::number(cells[k])
                .map_err(|e| at_cell(line, l, k, format!("column `{}`: {e}", names[k])))
        };
        let t = value(time_col)?;
        if let Some(&last) = table.time_s.last()
            && t <= last
        {
            return Err(at_cell(
                line,
                l,
                time_col,
                format!("time {t} s does not rise (after {last} s)"),
            ));
        }
        table.time_s.push(t);
        for (column, source) in table.changes.iter_mut().zip(cols) {
            column.push(match source {
                Some(k) => value(k)?,
                None => 0.0,
            });
        }
    }
    if table.time_s.is_empty() {
        return Err(InputError::file(path, "no data rows"));
    }
    Ok(table)
}

/// A simulation as CSV: time, controls, body states, rotor and propeller speeds, rotor azimuth,
/// flap states and inflow, with units in the column names.
pub fn to_csv(h: &TimeHistory) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let nflap = h.samples.first().map_or(0, |x| x.state.flap.len());
    s.push_str(
        "time_s,eta_s_percent,eta_c_percent,eta_p_percent,eta_t_percent,u_m_s,v_m_s,w_m_s,p_rad_s,q_rad_s,r_rad_s,phi_rad,theta_rad,psi_rad,north_m,east_m,down_m,rotor_omega_rad_s,rotor_azimuth_rad",
    );
    for k in 1..=nflap {
        let _ = write!(s, ",flap{k}_rad,flap{k}_rate_rad_s");
    }
    s.push_str(",inflow_v0_m_s,inflow_v1s_m_s,inflow_v1c_m_s,propeller_omega_rad_s\n");
    for x in &h.samples {
        let c = &x.controls;
        let _ = write!(
            s,
            "{},{},{},{},{}",
            x.time_s,
            c.stick_longitudinal_percent,
            c.stick_lateral_percent,
            c.pedal_percent,
            c.throttle_percent
        );
        for v in x.state.body.to_array() {
            let _ = write!(s, ",{v}");
        }
        let _ = write!(
            s,
            ",{},{}",
            x.state.rotor_omega_rad_s, x.state.rotor_azimuth_rad
        );
        for f in &x.state.flap {
            let _ = write!(s, ",{},{}", f[0], f[1]);
        }
        let i = &x.state.inflow;
        let _ = writeln!(
            s,
            ",{},{},{},{}",
            i.v0, i.v1s, i.v1c, x.state.propeller_omega_rad_s
        );
    }
    s
}
