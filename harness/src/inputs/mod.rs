//! What input files share beyond their own formats (the layout issue's `inputs/`): the
//! plausible ranges of estimated parameters, which aircraft and rotor files both carry, and the
//! limits on what any file may ask for.

pub mod limits;
pub mod ranges;
