//! Linear (small-perturbation) models `x' = A x + B u` with named states and controls.
//!
//! A [`LinearModel`] owns its matrices and the names of its states and controls, so that
//! derivatives are addressed the way flight-mechanics engineers write them (`M_w`, `Q_Omega`,
//! `L_eta_c`) rather than by index. Reordering and partitioning by name give the blocks of the
//! weakly coupled systems analysis (seed 002 Eq. 4).

use nalgebra::DMatrix;
use serde::Serialize;
use thiserror::Error;

/// Why a linear model could not be built or addressed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinearModelError {
    /// A is not square, or its size differs from the number of state names.
    #[error(
        "A is {rows}x{cols} but there are {states} state names: A must be square, one row and column per state"
    )]
    ShapeA {
        rows: usize,
        cols: usize,
        states: usize,
    },
    /// B has the wrong size for the states and controls.
    #[error(
        "B is {rows}x{cols} but there are {states} states and {controls} controls: B must be states x controls"
    )]
    ShapeB {
        rows: usize,
        cols: usize,
        states: usize,
        controls: usize,
    },
    /// A row of a matrix given as nested lists has a different length from the first row.
    #[error("matrix {matrix} row {row} has {len} entries, expected {expected}")]
    Ragged {
        matrix: &'static str,
        row: usize,
        len: usize,
        expected: usize,
    },
    /// A name is used twice among the states and controls.
    #[error("the name `{0}` is used twice among the states and controls")]
    DuplicateName(String),
    /// A name is empty.
    #[error("a state or control name is empty")]
    EmptyName,
    /// A matrix entry is NaN or infinite.
    #[error("{matrix}[{row}][{col}] is not finite ({value})")]
    NotFinite {
        matrix: &'static str,
        row: usize,
        col: usize,
        value: f64,
    },
    /// A state name that the model does not have.
    #[error("unknown state `{name}`; the model's states are [{known}]")]
    UnknownState { name: String, known: String },
    /// A state or control name that the model does not have.
    #[error("unknown state or control `{name}`; the model has [{known}]")]
    UnknownVariable { name: String, known: String },
    /// A reordering that is not a permutation of the states.
    #[error("reordering must name every state exactly once: got [{given}], states are [{known}]")]
    NotAPermutation { given: String, known: String },
    /// A derivative name that does not follow the `<force>_<variable>` convention.
    #[error(
        "`{0}` is not a derivative name: expected <force>_<variable> with force one of X Y Z L M N Q (for example M_w, Q_Omega, L_eta_c)"
    )]
    BadDerivativeName(String),
    /// A derivative whose force row is not a state of the model.
    #[error(
        "derivative `{name}` needs the state `{state}` (the row of force {force}), which the model does not have"
    )]
    MissingForceState {
        name: String,
        force: char,
        state: &'static str,
    },
}

/// A linear time-invariant model `x' = A x + B u` with named states and controls.
///
/// Invariants (checked by [`LinearModel::new`]): A is n x n and B is n x m for n state names and
/// m control names; names are unique and non-empty; every entry is finite.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearModel {
    states: Vec<String>,
    controls: Vec<String>,
    a: DMatrix<f64>,
    b: DMatrix<f64>,
}

/// Where a derivative lives: in A (column is a state) or in B (column is a control).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Element {
    /// `A[row][col]`.
    A { row: usize, col: usize },
    /// `B[row][col]`.
    B { row: usize, col: usize },
}

/// Body-axis force and moment letters and the state whose rate each one drives.
///
/// `X, Y, Z` drive `u, v, w` (m/s^2 per unit); `L, M, N` drive `p, q, r` (rad/s^2 per unit);
/// `Q` drives the rotorspeed `Omega` (rad/s^2 per unit), following seeds 000-002.
pub const FORCE_STATES: [(char, &str); 7] = [
    ('X', "u"),
    ('Y', "v"),
    ('Z', "w"),
    ('L', "p"),
    ('M', "q"),
    ('N', "r"),
    ('Q', "Omega"),
];

impl LinearModel {
    /// Builds a model, checking shapes, names and finiteness.
    pub fn new(
        states: Vec<String>,
        controls: Vec<String>,
        a: DMatrix<f64>,
        b: DMatrix<f64>,
    ) -> Result<Self, LinearModelError> {
        let n = states.len();
        if a.nrows() != n || a.ncols() != n {
            return Err(LinearModelError::ShapeA {
                rows: a.nrows(),
                cols: a.ncols(),
                states: n,
            });
        }
        if b.nrows() != n || b.ncols() != controls.len() {
            return Err(LinearModelError::ShapeB {
                rows: b.nrows(),
                cols: b.ncols(),
                states: n,
                controls: controls.len(),
            });
        }
        let mut seen = std::collections::BTreeSet::new();
        for name in states.iter().chain(&controls) {
            if name.trim().is_empty() {
                return Err(LinearModelError::EmptyName);
            }
            if !seen.insert(name.as_str()) {
                return Err(LinearModelError::DuplicateName(name.clone()));
            }
        }
        for (matrix, m) in [("A", &a), ("B", &b)] {
            for i in 0..m.nrows() {
                for j in 0..m.ncols() {
                    let value = m[(i, j)];
                    if !value.is_finite() {
                        return Err(LinearModelError::NotFinite {
                            matrix,
                            row: i,
                            col: j,
                            value,
                        });
                    }
                }
            }
        }
        Ok(Self {
            states,
            controls,
            a,
            b,
        })
    }

    /// Builds a model from row-major nested lists, as they are written in case files.
    pub fn from_rows(
        states: Vec<String>,
        controls: Vec<String>,
        a: &[Vec<f64>],
        b: &[Vec<f64>],
    ) -> Result<Self, LinearModelError> {
        let a = matrix_from_rows("A", a, states.len())?;
        let b = matrix_from_rows("B", b, controls.len())?;
        Self::new(states, controls, a, b)
    }

    /// State names, in matrix order.
    pub fn states(&self) -> &[String] {
        &self.states
    }

    /// Control names, in matrix order.
    pub fn controls(&self) -> &[String] {
        &self.controls
    }

    /// The system matrix.
    pub fn a(&self) -> &DMatrix<f64> {
        &self.a
    }

    /// The control matrix.
    pub fn b(&self) -> &DMatrix<f64> {
        &self.b
    }

    /// Index of a state by name.
    pub fn state_index(&self, name: &str) -> Result<usize, LinearModelError> {
        self.states
            .iter()
            .position(|s| s == name)
            .ok_or_else(|| LinearModelError::UnknownState {
                name: name.to_string(),
                known: self.states.join(", "),
            })
    }

    /// Whether the model has a state of this name.
    pub fn has_state(&self, name: &str) -> bool {
        self.states.iter().any(|s| s == name)
    }

    /// The element of A or B at (row state, column state-or-control).
    pub fn element(&self, row: &str, col: &str) -> Result<Element, LinearModelError> {
        let r = self.state_index(row)?;
        if let Some(c) = self.states.iter().position(|s| s == col) {
            return Ok(Element::A { row: r, col: c });
        }
        if let Some(c) = self.controls.iter().position(|s| s == col) {
            return Ok(Element::B { row: r, col: c });
        }
        Err(LinearModelError::UnknownVariable {
            name: col.to_string(),
            known: self
                .states
                .iter()
                .chain(&self.controls)
                .cloned()
                .collect::<Vec<_>>()
                .join(", "),
        })
    }

    /// Resolves a derivative name such as `M_w`, `Q_Omega` or `L_eta_c` to its element.
    ///
    /// The letter before the first underscore names the force or moment and hence the row
    /// ([`FORCE_STATES`]); the rest names the state or control of the column.
    pub fn derivative(&self, name: &str) -> Result<Element, LinearModelError> {
        let (force, var) = split_derivative(name)?;
        let state = force_state(force)
            .ok_or_else(|| LinearModelError::BadDerivativeName(name.to_string()))?;
        if !self.has_state(state) {
            return Err(LinearModelError::MissingForceState {
                name: name.to_string(),
                force,
                state,
            });
        }
        self.element(state, var)
    }

    /// The value of an element.
    pub fn get(&self, e: Element) -> f64 {
        match e {
            Element::A { row, col } => self.a[(row, col)],
            Element::B { row, col } => self.b[(row, col)],
        }
    }

    /// The value of a named derivative.
    pub fn derivative_value(&self, name: &str) -> Result<f64, LinearModelError> {
        Ok(self.get(self.derivative(name)?))
    }

    /// A copy with one element set (for root-locus sweeps and what-if variants).
    ///
    /// Fails on a non-finite value, keeping the invariant that every entry is finite.
    pub fn with(&self, e: Element, value: f64) -> Result<Self, LinearModelError> {
        let (matrix, row, col) = match e {
            Element::A { row, col } => ("A", row, col),
            Element::B { row, col } => ("B", row, col),
        };
        if !value.is_finite() {
            return Err(LinearModelError::NotFinite {
                matrix,
                row,
                col,
                value,
            });
        }
        let mut m = self.clone();
        match e {
            Element::A { row, col } => m.a[(row, col)] = value,
            Element::B { row, col } => m.b[(row, col)] = value,
        }
        Ok(m)
    }

    /// The same model with its states in the given order (B's rows follow).
    pub fn reorder(&self, order: &[&str]) -> Result<Self, LinearModelError> {
        let not_perm = || LinearModelError::NotAPermutation {
            given: order.join(", "),
            known: self.states.join(", "),
        };
        if order.len() != self.states.len() {
            return Err(not_perm());
        }
        let mut idx = Vec::with_capacity(order.len());
        for name in order {
            let i = self.state_index(name)?;
            if idx.contains(&i) {
                return Err(not_perm());
            }
            idx.push(i);
        }
        let n = idx.len();
        let a = DMatrix::from_fn(n, n, |i, j| self.a[(idx[i], idx[j])]);
        let b = DMatrix::from_fn(n, self.controls.len(), |i, j| self.b[(idx[i], j)]);
        let states = idx.iter().map(|&i| self.states[i].clone()).collect();
        Ok(Self {
            states,
            controls: self.controls.clone(),
            a,
            b,
        })
    }

    /// The sub-model on a subset of states (rows and columns of A, rows of B).
    pub fn subsystem(&self, names: &[&str]) -> Result<Self, LinearModelError> {
        let idx = names
            .iter()
            .map(|n| self.state_index(n))
            .collect::<Result<Vec<_>, _>>()?;
        let n = idx.len();
        let a = DMatrix::from_fn(n, n, |i, j| self.a[(idx[i], idx[j])]);
        let b = DMatrix::from_fn(n, self.controls.len(), |i, j| self.b[(idx[i], j)]);
        Self::new(
            idx.iter().map(|&i| self.states[i].clone()).collect(),
            self.controls.clone(),
            a,
            b,
        )
    }

    /// Partitions the model into the fast states `x1` and the rest `x2` (seed 002 Eq. 4).
    ///
    /// `x2` keeps the model's order of the remaining states.
    pub fn partition(&self, x1: &[&str]) -> Result<Partition, LinearModelError> {
        let x2: Vec<&str> = self
            .states
            .iter()
            .map(String::as_str)
            .filter(|s| !x1.contains(s))
            .collect();
        let mut order: Vec<&str> = x1.to_vec();
        order.extend(&x2);
        let m = self.reorder(&order)?;
        let k = x1.len();
        let n = m.states.len();
        let nu = m.controls.len();
        Ok(Partition {
            x1: m.states[..k].to_vec(),
            x2: m.states[k..].to_vec(),
            controls: m.controls.clone(),
            a11: m.a.view((0, 0), (k, k)).into_owned(),
            a12: m.a.view((0, k), (k, n - k)).into_owned(),
            a21: m.a.view((k, 0), (n - k, k)).into_owned(),
            a22: m.a.view((k, k), (n - k, n - k)).into_owned(),
            b1: m.b.view((0, 0), (k, nu)).into_owned(),
            b2: m.b.view((k, 0), (n - k, nu)).into_owned(),
        })
    }

    /// The name of a derivative at an element, where one exists (`M_w` for `A[q][w]`).
    ///
    /// Kinematic rows (attitudes) have no force letter; their elements are named
    /// `d(theta)/d(q)`.
    pub fn element_name(&self, e: Element) -> String {
        let (row, col) = match e {
            Element::A { row, col } => (row, self.states[col].as_str()),
            Element::B { row, col } => (row, self.controls[col].as_str()),
        };
        let state = self.states[row].as_str();
        match FORCE_STATES.iter().find(|(_, s)| *s == state) {
            Some((force, _)) => format!("{force}_{col}"),
            None => format!("d({state})/d({col})"),
        }
    }
}

/// The blocks of a partitioned model (seed 002 Eqs. 4-10).
#[derive(Debug, Clone, PartialEq)]
pub struct Partition {
    pub x1: Vec<String>,
    pub x2: Vec<String>,
    pub controls: Vec<String>,
    pub a11: DMatrix<f64>,
    pub a12: DMatrix<f64>,
    pub a21: DMatrix<f64>,
    pub a22: DMatrix<f64>,
    pub b1: DMatrix<f64>,
    pub b2: DMatrix<f64>,
}

fn matrix_from_rows(
    name: &'static str,
    rows: &[Vec<f64>],
    cols_if_empty: usize,
) -> Result<DMatrix<f64>, LinearModelError> {
    let ncols = rows.first().map_or(cols_if_empty, Vec::len);
    for (i, r) in rows.iter().enumerate() {
        if r.len() != ncols {
            return Err(LinearModelError::Ragged {
                matrix: name,
                row: i,
                len: r.len(),
                expected: ncols,
            });
        }
    }
    Ok(DMatrix::from_fn(rows.len(), ncols, |i, j| rows[i][j]))
}

fn split_derivative(name: &str) -> Result<(char, &str), LinearModelError> {
    let bad = || LinearModelError::BadDerivativeName(name.to_string());
    let (force, var) = name.split_once('_').ok_or_else(bad)?;
    let mut chars = force.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) if !var.is_empty() => Ok((c, var)),
        _ => Err(bad()),
    }
}

fn force_state(force: char) -> Option<&'static str> {
    FORCE_STATES
        .iter()
        .find(|(f, _)| *f == force)
        .map(|(_, s)| *s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    fn small() -> LinearModel {
        LinearModel::from_rows(
            names(&["u", "w", "q", "theta"]),
            names(&["eta_s"]),
            &[
                vec![1.0, 2.0, 3.0, 4.0],
                vec![5.0, 6.0, 7.0, 8.0],
                vec![9.0, 10.0, 11.0, 12.0],
                vec![0.0, 0.0, 1.0, 0.0],
            ],
            &[vec![0.1], vec![0.2], vec![0.3], vec![0.0]],
        )
        .unwrap()
    }

    #[test]
    fn derivatives_resolve_by_name() {
        let m = small();
        assert_eq!(m.derivative_value("M_w").unwrap(), 10.0);
        assert_eq!(m.derivative_value("X_theta").unwrap(), 4.0);
        assert_eq!(m.derivative_value("Z_eta_s").unwrap(), 0.2);
        assert_eq!(m.element_name(m.derivative("M_w").unwrap()), "M_w");
        assert_eq!(
            m.element_name(Element::A { row: 3, col: 2 }),
            "d(theta)/d(q)"
        );
    }

    #[test]
    fn bad_names_are_errors() {
        let m = small();
        assert!(matches!(
            m.derivative("Mw"),
            Err(LinearModelError::BadDerivativeName(_))
        ));
        assert!(matches!(
            m.derivative("N_r"),
            Err(LinearModelError::MissingForceState { .. })
        ));
        assert!(matches!(
            m.derivative("M_Omega"),
            Err(LinearModelError::UnknownVariable { .. })
        ));
        assert!(matches!(
            m.reorder(&["u", "u", "q", "theta"]),
            Err(LinearModelError::NotAPermutation { .. })
        ));
    }

    #[test]
    fn shapes_and_values_are_checked() {
        let err = LinearModel::from_rows(
            names(&["u", "w"]),
            vec![],
            &[vec![1.0, 2.0], vec![3.0]],
            &[vec![], vec![]],
        );
        assert!(matches!(err, Err(LinearModelError::Ragged { row: 1, .. })));
        let err = LinearModel::from_rows(
            names(&["u", "w"]),
            vec![],
            &[vec![1.0, 2.0, 3.0], vec![3.0, 4.0, 5.0]],
            &[vec![], vec![]],
        );
        assert!(matches!(err, Err(LinearModelError::ShapeA { .. })));
        let err = LinearModel::from_rows(
            names(&["u", "u"]),
            vec![],
            &[vec![1.0, 2.0], vec![3.0, 4.0]],
            &[vec![], vec![]],
        );
        assert!(matches!(err, Err(LinearModelError::DuplicateName(_))));
        let err = LinearModel::from_rows(
            names(&["u", "w"]),
            vec![],
            &[vec![1.0, f64::NAN], vec![3.0, 4.0]],
            &[vec![], vec![]],
        );
        assert!(matches!(err, Err(LinearModelError::NotFinite { .. })));
    }

    #[test]
    fn partition_gives_the_blocks() {
        let p = small().partition(&["w", "q"]).unwrap();
        assert_eq!(p.x2, names(&["u", "theta"]));
        assert_eq!(p.a11[(0, 0)], 6.0); // Z_w
        assert_eq!(p.a11[(1, 0)], 10.0); // M_w
        assert_eq!(p.a12[(0, 0)], 5.0); // Z_u
        assert_eq!(p.a21[(0, 1)], 3.0); // X_q
        assert_eq!(p.a22[(1, 0)], 0.0); // theta row, u column
        assert_eq!(p.b1[(1, 0)], 0.3);
        assert_eq!(p.b2[(0, 0)], 0.1);
    }
}
