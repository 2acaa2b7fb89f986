//! What input files share beyond their own formats (the layout issue's `inputs/`): today the
//! plausible ranges of estimated parameters, which aircraft and rotor files both carry.

pub mod ranges;
