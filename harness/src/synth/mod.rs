//! Synthetic records, labelled so: a linear model flown through a test input with seeded noise
//! and turbulence ([`linear`]), a flight test flown by the full individual-blade model
//! ([`flight`]), and a reference record's control changes flown again with noise on its
//! responses ([`history`]), and a teeter record of a rotor's autorotation ([`teeter`]).

pub mod flight;
pub mod history;
pub mod linear;
pub mod teeter;
