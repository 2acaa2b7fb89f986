//! Constrained fitting of the model's empirical corrections, and of an aircraft's estimated
//! physical parameters, against flight (or tunnel) references.
//!
//! # Problem
//! Parameters `p` (corrections or estimated physical parameters, with bounds), targets `y_k(p)` (derivatives or trim quantities
//! of an aircraft at flight conditions, or autorotation quantities of a rotor alone at tunnel
//! conditions) with references `d_k` and standard errors `s_k`. The cost is
//!
//! ```text
//! C(p) = sum_k ((y_k(p) - d_k) / s_k)^2 + sum_i w_i ((p_i - p0_i) / range_i)^2
//! ```
//!
//! (the second sum is the optional regularisation towards the uncorrected model `p0`), subject
//! to the parameter bounds and, optionally, bounds on targets (`y_k` within its flight bounds),
//! soft (a violation `v_k` adds `w_k (v_k / s_k)^2`) or hard (the same with a weight of 1e6; a
//! hard bound still violated at the end makes the fit infeasible).
//!
//! # Method
//! Sequential linearisation: forward-difference sensitivities `J = dy/dp` through trim and
//! linearisation (conditions in parallel), then a quadratic program for the step, solved by
//! clarabel, with the parameter bounds, a box trust region and a slack for each bounded target
//! (the linearised violation).
//! A step is taken when it lowers the cost; the trust region shrinks when the prediction was
//! poor and grows when it was good and the step reached it.
//!
//! # Result
//! A status (never a panic), the parameters with approximate standard errors from
//! `(J' J)^-1` at the solution (targets are normalised by their standard errors, so this is
//! the usual linearised covariance), and every target before and after.

pub mod file;
mod qp;
pub mod retune;
pub mod sensitivity;
mod solve;
pub mod starts;
mod targets;

pub use solve::{
    BatchEvaluator, Birge, Executor, FitOptions, FitResult, INTERVAL_Z, Interval, POSTERIOR_METHOD,
    Problem, STALLED_MEANS, Status, fit, interval, posterior, scale_by_birge,
};
pub use targets::{
    Bounds, ConditionStarts, Enforce, FitParameter, FitSubject, Measure, ParameterKind,
    PointEvaluation, ResponsePoint, TUNNEL_QUANTITIES, Target, TargetCondition, check, evaluate,
    evaluate_each, evaluate_each_from, evaluate_each_here, evaluate_each_here_from, evaluate_from,
    sensitivities, values_or_nan,
};
