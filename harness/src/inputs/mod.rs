//! What input files share beyond their own formats (the layout issue's `inputs/`): the
//! plausible ranges of estimated parameters, which aircraft and rotor files both carry, the
//! flight condition and loading that cases, fit files and commands give, and the limits on what
//! any file may ask for.

pub mod aircraft;
pub mod channels;
pub mod condition;
pub mod controls;
pub mod corrections;
pub mod limits;
pub mod parameters;
pub mod quantity;
pub mod ranges;
pub mod record;
pub mod reference;
pub mod rotor;
pub mod trim_points;
pub mod yaml;
