//! Root-locus sweeps: the modes of a model as one derivative varies over a range
//! (seed 002 Figs. 2, 3, 6-8).

use crate::analysis::linear::{Element, LinearModel, LinearModelError};
use crate::analysis::modes::{self, ModalAnalysis, ModesError};
use serde::Serialize;
use thiserror::Error;

/// One point of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LocusPoint {
    /// The value of the swept element.
    pub value: f64,
    pub analysis: ModalAnalysis,
}

/// Why a sweep failed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LocusError {
    #[error(transparent)]
    Model(#[from] LinearModelError),
    #[error("at {element} = {value}: {source}")]
    Modes {
        element: String,
        value: f64,
        source: ModesError,
    },
    #[error("a sweep needs at least two points, got {0}")]
    TooFewPoints(usize),
}

/// `n` evenly spaced values from `from` to `to` inclusive.
pub fn linspace(from: f64, to: f64, n: usize) -> Vec<f64> {
    match n {
        0 => vec![],
        1 => vec![from],
        _ => (0..n)
            .map(|i| from + (to - from) * i as f64 / (n - 1) as f64)
            .collect(),
    }
}

/// The modes of `model` with `element` set to each of `values` in turn.
pub fn root_locus(
    model: &LinearModel,
    element: Element,
    values: &[f64],
) -> Result<Vec<LocusPoint>, LocusError> {
    if values.len() < 2 {
        return Err(LocusError::TooFewPoints(values.len()));
    }
    values
        .iter()
        .map(|&value| {
            let m = model.with(element, value)?;
            let analysis = modes::modes(&m).map_err(|source| LocusError::Modes {
                element: model.element_name(element),
                value,
                source,
            })?;
            Ok(LocusPoint { value, analysis })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::modes::ModeKind;
    use crate::testdata::vpm_eq20;

    #[test]
    fn q_u_trades_damping_between_phugoid_and_rotorspeed() {
        // Seed 002 Fig. 2: as Q_u rises from 0.06 to 0.26 the phugoid loses damping and the
        // rotorspeed mode gains it. The branches are told apart by their eigenvalues (the only
        // real root, the slower complex pair), not by classification: at Q_u = 0.06 the real
        // root is an even mix of rotorspeed and u (participation 0.49 each), unclassified.
        let m = vpm_eq20();
        let e = m.derivative("Q_u").unwrap();
        let pts = root_locus(&m, e, &linspace(0.06, 0.26, 5)).unwrap();
        let real = |p: &LocusPoint| {
            p.analysis
                .modes
                .iter()
                .find(|m| !m.is_oscillatory())
                .unwrap()
                .eigenvalue
                .re
        };
        let slow_pair = |p: &LocusPoint| {
            p.analysis
                .modes
                .iter()
                .rfind(|m| m.is_oscillatory())
                .unwrap()
                .eigenvalue
                .re
        };
        for w in pts.windows(2) {
            assert!(slow_pair(&w[1]) > slow_pair(&w[0]));
            assert!(real(&w[1]) < real(&w[0]));
        }
        assert_eq!(pts[0].analysis.modes[1].kind, ModeKind::Unclassified);
        assert_eq!(pts[4].analysis.modes[1].kind, ModeKind::Rotorspeed);
    }

    #[test]
    fn sweeps_need_two_points() {
        let m = vpm_eq20();
        let e = m.derivative("Q_u").unwrap();
        assert_eq!(root_locus(&m, e, &[0.1]), Err(LocusError::TooFewPoints(1)));
    }
}
