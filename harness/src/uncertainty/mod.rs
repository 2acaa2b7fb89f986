//! Uncertainty of the model's answers (`cierva uncertainty`).
//!
//! - [`calibration`]: a fit's predictive error by cross-validation, and the model-discrepancy
//!   term that makes its intervals cover held-out data.
//! - [`distribution`]: an uncertain input, its distribution (from an aircraft file's `ranges:`)
//!   and its quantiles.
//! - [`design`]: Saltelli's sampling design on Owen-scrambled Sobol' points.
//! - [`sobol`]: Sobol' first-order and total indices (Saltelli 2010, Jansen 1999).
//! - [`vv20`]: the validation comparison of ASME V&V 20-2009 and its verdicts.
//! - [`numerics`]: the numerical uncertainty, a grid study of each discretisation parameter
//!   refined alone and Roache's grid convergence index for each.
//! - [`propagate`]: all of it through a case, sampled: statistics, indices, the numerical
//!   uncertainty from the grid study, the data's from the tolerance, and the verdicts; and
//!   what the first-order method shares with it.
//! - [`first_order`]: the first-order propagation of a case with autorotation checks (an
//!   additive surrogate through two probes of each input, with a residual check).
//! - [`jobs`]: a case's study as the evaluations it needs (the nominal run, the grid study's
//!   refined cases, the propagation's points), run on this machine's cores or from a plan's
//!   shards ([`crate::plan`]), and what their results make.
//! - [`study`]: the entry points, [`study::propagate`] and [`study::propagate_from`]: a case's
//!   inputs, and the method that suits it.
//! - [`summary`]: a whole suite's verdicts per case, as committed in
//!   `reports/uncertainty-summary.yaml`, and the documents' tables of them.

pub mod calibration;
pub mod design;
pub mod distribution;
pub mod first_order;
pub mod jobs;
pub mod numerics;
pub mod propagate;
pub mod sobol;
pub mod study;
pub mod summary;
pub mod vv20;
