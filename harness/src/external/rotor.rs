//! cierva's isolated rotor in a wind tunnel as a model behind the model interface
//! ([`CiervaRotor`]): what an `autorotation` check, the uncertainty study and the snapshots ask
//! of a rotor, through [`super::FlightModel::autorotation`] as of any model.

use super::{FlightModel, Parameter, TunnelRequest, Values, check_values};
use crate::inputs::rotor::RotorFile;
use crate::run::autorotation::Autorotated;
use cierva_model::components::autorotation::AutorotationOptions;
use std::borrow::Cow;
use std::sync::Arc;

/// cierva's rotor of a rotor file, in a tunnel, solved by `solver` (the inflow model of its
/// file's physics or a case's, and the blade integration's numerics and Newton tolerances).
#[derive(Debug, Clone)]
pub struct CiervaRotor<'a> {
    pub file: Cow<'a, RotorFile>,
    pub solver: AutorotationOptions,
}

impl<'a> CiervaRotor<'a> {
    /// The rotor of `file`, solved by `solver`.
    pub fn new(file: &'a RotorFile, solver: AutorotationOptions) -> Self {
        Self {
            file: Cow::Borrowed(file),
            solver,
        }
    }

    /// The rotor, owned: a model a study can share ([`Arc<dyn FlightModel>`]).
    pub fn owned(file: RotorFile, solver: AutorotationOptions) -> CiervaRotor<'static> {
        CiervaRotor {
            file: Cow::Owned(file),
            solver,
        }
    }

    /// The rotor with the values set (itself where none are), checked: each a physical
    /// parameter of [`crate::inputs::parameters::ROTOR_PARAMETERS`] or one of its corrections
    /// (`corrections.<name>`, [`crate::inputs::corrections::CorrectionSet::of_rotor`]).
    fn with_values(&self, values: &Values) -> Result<Cow<'_, RotorFile>, String> {
        if values.is_empty() {
            return Ok(Cow::Borrowed(&*self.file));
        }
        check_values(&self.describe(), &self.parameters()?, values)?;
        let mut f = self.file.as_ref().clone();
        let corrections = super::set_values(&self.describe(), values, |name, v| {
            crate::inputs::parameters::set_rotor_parameter(&mut f.rotor, name, v)
        })?;
        corrections.apply_to_rotor(&mut f.rotor)?;
        Ok(Cow::Owned(f))
    }
}

impl FlightModel for CiervaRotor<'_> {
    fn describe(&self) -> String {
        format!("the rotor {}", self.file.path.display())
    }

    /// Every parameter of [`crate::inputs::parameters::ROTOR_PARAMETERS`] the rotor has, at the
    /// file's value, and every correction a rotor takes as `corrections.<name>`
    /// ([`crate::inputs::corrections::CorrectionSet::of_rotor`]); each with the file's
    /// `ranges:` entry where it gives one.
    fn parameters(&self) -> Result<Vec<Parameter>, String> {
        let r = &self.file.rotor;
        Ok(super::declared(
            crate::inputs::parameters::ROTOR_PARAMETERS.iter(),
            |name| crate::inputs::parameters::rotor_parameter(r, name),
            &crate::inputs::corrections::CorrectionSet::of_rotor(r),
            &self.file.ranges,
        ))
    }

    /// An autorotation alone.
    fn computes(&self) -> Vec<super::command::Compute> {
        vec![super::command::Compute::Autorotation]
    }

    fn autorotation(&self, request: &TunnelRequest) -> Result<Autorotated, String> {
        let file = self.with_values(&request.parameters)?;
        crate::run::autorotation::at_tunnel(&file.rotor, self.solver, &request.tunnel)
    }

    /// Each alone: its blade elements doubled (midpoint sums), the tunnel solver's azimuth step
    /// halved (fourth-order Runge-Kutta), and the solver's iterations converged ten times
    /// further (its periodicity and Newton tolerances a tenth, together: both are iteration
    /// error, not discretisation).
    fn refinements(&self) -> Vec<super::Refinement> {
        let (file, solver) = (self.file.as_ref(), self.solver);
        let (n, newton) = (&solver.numerics, &solver.newton);
        let refined = |tag: &str, change: &dyn Fn(&mut RotorFile, &mut AutorotationOptions)| {
            let (mut f, mut s) = (file.clone(), solver);
            change(&mut f, &mut s);
            f.path = format!("{}#{tag}", f.path.display()).into();
            Arc::new(CiervaRotor::owned(f, s)) as Arc<dyn FlightModel>
        };
        vec![
            super::Refinement {
                parameter: "blade elements".into(),
                words: format!("{} -> {}", file.rotor.elements, 2 * file.rotor.elements),
                ratio: 2.0,
                formal_order: 2.0,
                model: refined("elements", &|f, _| f.rotor.elements *= 2),
            },
            super::Refinement {
                parameter: "azimuth step".into(),
                words: format!(
                    "{:.3} -> {:.3} deg",
                    n.azimuth_step_rad.to_degrees(),
                    0.5 * n.azimuth_step_rad.to_degrees()
                ),
                ratio: 2.0,
                formal_order: 4.0,
                model: refined("azimuth-step", &|_, s| s.numerics.azimuth_step_rad *= 0.5),
            },
            super::Refinement {
                parameter: "solver tolerances".into(),
                words: format!(
                    "periodicity {:.0e} -> {:.0e}, Newton {:.0e} -> {:.0e}",
                    n.periodic_tolerance,
                    0.1 * n.periodic_tolerance,
                    newton.tolerance,
                    0.1 * newton.tolerance
                ),
                ratio: 10.0,
                formal_order: 1.0,
                model: refined("tolerances", &|_, s| {
                    s.numerics.periodic_tolerance *= 0.1;
                    s.newton.tolerance *= 0.1;
                }),
            },
        ]
    }
}
