//! `cierva sensitivity`: which parameter would close a discrepancy, and is the value it would
//! need plausible (see [`cierva_harness::fit::sensitivity`]).

use super::*;
use cierva_harness::fit::sensitivity::{self, BoundedQuantity};

pub(crate) fn sensitivity(a: SensitivityArgs) -> Result<ExitCode, Error> {
    let (file, loading, request, quantities) = match (&a.case, &a.aircraft) {
        (Some(path), None) => {
            let case = cierva_harness::suite::case::load(path)?;
            sensitivity::from_case(&case, a.airspeed_mph).map_err(Error::input)?
        }
        (None, Some(path)) => {
            let Some(v) = a.airspeed_mph else {
                return Err(Error::input("give --airspeed-mph with an aircraft file"));
            };
            let file = load_aircraft(path)?;
            let loading = cierva_harness::Loading {
                mass_kg: a.mass_kg,
                density_altitude_ft: a.density_altitude_ft,
            };
            let request = cierva_harness::TrimRequest::level(v);
            let quantities = tables::PRIMARY_DERIVATIVES
                .iter()
                .map(|n| BoundedQuantity {
                    name: n.to_string(),
                    bound: None,
                })
                .collect();
            (file, loading, request, quantities)
        }
        _ => {
            return Err(Error::input("give an aircraft file or --case, not both"));
        }
    };
    let quantities: Vec<BoundedQuantity> = if a.quantities.is_empty() {
        quantities
    } else {
        a.quantities
            .iter()
            .map(|n| {
                quantities
                    .iter()
                    .find(|q| &q.name == n)
                    .cloned()
                    .unwrap_or(BoundedQuantity {
                        name: n.clone(),
                        bound: None,
                    })
            })
            .collect()
    };
    let parameters: Vec<String> = if !a.parameters.is_empty() {
        a.parameters.clone()
    } else if !file.ranges.is_empty() {
        file.ranges.keys().cloned().collect()
    } else {
        cierva_harness::inputs::parameters::PARAMETERS
            .iter()
            .filter(|p| {
                cierva_harness::inputs::parameters::parameter(&file.aircraft, p.name).is_some()
            })
            .map(|p| p.name.to_string())
            .collect()
    };
    if let Err(e) = sensitivity::check_names(&file, &parameters, &quantities) {
        return Err(Error::input(e));
    }
    match sensitivity::run(&file, request, loading, &parameters, &quantities) {
        Ok(study) => {
            match a.format {
                Format::Text => print!("{}", cierva_harness::report::sensitivity::table(&study)),
                Format::Json => println!(
                    "{}",
                    serde_json::to_string_pretty(&study).expect("a study serialises")
                ),
            }
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(Error::failure(e)),
    }
}
