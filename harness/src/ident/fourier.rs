//! Fourier transforms of sampled signals at chosen frequencies: the trapezoidal finite Fourier
//! integral by a direct sum ([`transform`]) or, at evenly spaced frequencies, by chirp-z
//! ([`ChirpZ`], [`transform_uniform`]), and the Hann taper ([`hann`]). They are built in
//! `cierva-fft`, optimised in test builds (its crate documentation says why); this module is
//! where the identification and its users find them.

pub use cierva_fft::fourier::{ChirpZ, transform, transform_uniform};
pub use cierva_fft::hann;
