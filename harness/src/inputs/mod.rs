//! What input files share beyond their own formats (the layout issue's `inputs/`): the
//! plausible ranges of estimated parameters, which aircraft and rotor files both carry, and the
//! flight condition and loading that cases, fit files and commands give.

pub mod condition;
pub mod ranges;
