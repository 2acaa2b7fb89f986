//! `cierva sensitivity`: which parameter would close a discrepancy, and is the value it would
//! need plausible (see [`cierva_harness::fit::sensitivity`]).

use super::*;
use cierva_harness::external::{CiervaAircraft, FlightModel};
use cierva_harness::fit::sensitivity::{self, BoundedQuantity};

/// Which parameter would close a discrepancy, and is the value it would need plausible? Asks
/// the model's trim and linear model with each parameter moved a step either way and prints
/// every quantity's derivative with respect to each; for a quantity outside its check's bound,
/// the change of each parameter alone that would bring it to the nearer edge (a linear
/// estimate), against the parameter's plausible range as the model declares it (an aircraft
/// file's `ranges:`; an external model's `describe`, protocol `cierva-external/2`).
///
/// Example: `cierva sensitivity --case cases/cierva-table2-vpm-m16-70mph-max-weight.yaml`,
/// or `cierva sensitivity aircraft/vpm-m16.yaml --airspeed-mph 70 --quantities N_v,L_v
/// --parameters airframe.fin.area_m2,mass.izz_kg_m2 --format json`.
#[derive(clap::Args)]
pub(crate) struct SensitivityArgs {
    /// An aircraft file (see aircraft/); or give --case.
    pub(crate) aircraft: Option<PathBuf>,
    /// A case of an aircraft: its aircraft, loading and condition, and the quantities of its
    /// derivative and trim checks with their bounds.
    #[arg(long)]
    pub(crate) case: Option<PathBuf>,
    /// True airspeed, mph (with a case: picks one of its conditions).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) airspeed_mph: Option<f64>,
    /// Mass, kg (default: the aircraft file's); with an aircraft file.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) mass_kg: Option<f64>,
    /// Density altitude, ft (ISA); with an aircraft file.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub(crate) density_altitude_ft: f64,
    /// Parameters to move, by their names in the aircraft file (default: those the file gives
    /// a plausible range, or every one it has).
    #[arg(long, value_delimiter = ',')]
    pub(crate) parameters: Vec<String>,
    /// Quantities to differentiate: derivatives or trim quantities (default: the case's, or the
    /// primary derivatives).
    #[arg(long, value_delimiter = ',')]
    pub(crate) quantities: Vec<String>,
    /// With --case: write the study's requests as a plan to this folder and stop; run its
    /// shards with `cierva evaluate DIR --shard I/N` on any engine, then finish it with
    /// `--from-plan DIR` (docs/scaling.md). For a simulation whose trims take minutes.
    #[arg(
        long,
        value_name = "DIR",
        requires = "case",
        conflicts_with = "from_plan"
    )]
    pub(crate) plan: Option<PathBuf>,
    /// Finish the study a plan in this folder describes, from its shards' results (its case,
    /// condition, parameters and quantities are the plan's).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["aircraft", "case", "airspeed_mph", "mass_kg", "parameters", "quantities"])]
    pub(crate) from_plan: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub(crate) format: Format,
}

/// The study as text or JSON.
fn print_study(study: &sensitivity::Study, format: Format) {
    match format {
        Format::Text => print!("{}", cierva_harness::report::sensitivity::table(study)),
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(study).expect("a study serialises")
        ),
    }
}

/// `--plan DIR` (with `--case`) and `--from-plan DIR`.
fn planned(a: &SensitivityArgs) -> Option<Result<ExitCode, Error>> {
    use cierva_harness::plan::{self, SensitivitySettings};
    if let Some(dir) = &a.from_plan {
        let done = plan::enter(dir)
            .and_then(|d| plan::load(&d))
            .and_then(|p| plan::finish_sensitivity(&p))
            .map_err(Error::from);
        return Some(done.and_then(|(study, _)| match study {
            Ok(s) => {
                print_study(&s, a.format);
                Ok(ExitCode::SUCCESS)
            }
            Err(e) => Err(Error::failure(e)),
        }));
    }
    let (dir, path) = (a.plan.as_ref()?, a.case.as_ref()?);
    let written = (cierva_harness::suite::case::load(path).map_err(Error::from)).and_then(|case| {
        let settings = SensitivitySettings {
            airspeed_mph: a.airspeed_mph,
            parameters: a.parameters.clone(),
            quantities: a.quantities.clone(),
        };
        plan::write_sensitivity(dir, &case, settings).map_err(Error::from)
    });
    Some(written.map(|file| {
        let d = dir.display();
        println!(
            "wrote {}: {} requests of {}'s model\nnext: `cierva evaluate {d} --shard I/N` for I = 1 to N (docs/scaling.md), then `cierva sensitivity --from-plan {d}`",
            plan::plan_path(dir).display(),
            file.evaluations.len(),
            file.cases[0].id
        );
        ExitCode::SUCCESS
    }))
}

pub(crate) fn sensitivity(a: SensitivityArgs) -> Result<ExitCode, Error> {
    if let Some(done) = planned(&a) {
        return done;
    }
    // The model is a case's subject (an aircraft or another simulation), or an aircraft file.
    let case;
    let file;
    let (model, loading, request, quantities): (
        Box<dyn FlightModel + '_>,
        _,
        _,
        Vec<BoundedQuantity>,
    ) = match (&a.case, &a.aircraft) {
        (Some(path), None) => {
            case = cierva_harness::suite::case::load(path)?;
            let (loading, request, quantities) =
                sensitivity::from_case(&case, a.airspeed_mph).map_err(Error::input)?;
            let (model, _) = cierva_harness::checks::flight_model(&case.subject)
                .expect("from_case took a flight model");
            (model, loading, request, quantities)
        }
        (None, Some(path)) => {
            let Some(v) = a.airspeed_mph else {
                if cierva_harness::suite::case::load(path).is_ok() {
                    return Err(Error::input(format!(
                        "{} is a case, not an aircraft file: give it with --case {0}",
                        path.display()
                    )));
                }
                return Err(Error::input("give --airspeed-mph with an aircraft file"));
            };
            file = load_aircraft(path)?;
            let loading = cierva_harness::inputs::condition::Loading {
                mass_kg: a.mass_kg,
                density_altitude_ft: a.density_altitude_ft,
            };
            let request = cierva_harness::inputs::condition::TrimRequest::level(v);
            let quantities = tables::PRIMARY_DERIVATIVES
                .iter()
                .map(|n| BoundedQuantity {
                    name: n.to_string(),
                    bound: None,
                })
                .collect();
            (
                Box::new(CiervaAircraft::new(&file)),
                loading,
                request,
                quantities,
            )
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
    // What the model declares: a model that cannot say (a `describe` that fails) is bad input.
    let declared = model.parameters().map_err(Error::input)?;
    let parameters: Vec<String> = if !a.parameters.is_empty() {
        a.parameters.clone()
    } else {
        sensitivity::default_parameters(&declared)
    };
    if parameters.is_empty() {
        return Err(Error::input(format!(
            "{} declares no parameters to move (an external model declares them in its \
             `describe` response, protocol `cierva-external/2`)",
            model.describe()
        )));
    }
    if let Err(e) = sensitivity::check_names(&model.describe(), &declared, &parameters, &quantities)
    {
        return Err(Error::input(e));
    }
    match sensitivity::run(model.as_ref(), request, loading, &parameters, &quantities) {
        Ok(study) => {
            print_study(&study, a.format);
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(Error::failure(e)),
    }
}
