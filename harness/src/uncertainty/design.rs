//! The sampling design: Saltelli's two matrices `A` and `B` of `n` points in `d` inputs, drawn
//! as one `2d`-dimensional Owen-scrambled Sobol' sequence (`A` its first `d` dimensions, `B` the
//! next `d`), and for each input `i` the matrix `A_B^(i)`: `A` with its column `i` from `B`.
//! `n (d + 2)` points in all (Saltelli et al. 2010, Sec. 3; REFERENCES.md).
//!
//! The rows of `A` and `B` are `2n` independent draws of the inputs: the statistics of each
//! quantity (mean, percentiles, standard deviation) are taken over them, and the Sobol' indices
//! from all the matrices ([`super::sobol`]).

/// The fewest base points a design takes: below this the percentiles and indices mean nothing.
pub const MIN_SAMPLES: usize = 8;
/// The most base points: the Sobol' sequence's length (2^16) over the two matrices.
pub const MAX_SAMPLES: usize = 1 << 15;
/// The most inputs: the sequence's 256 dimensions over the two matrices.
pub const MAX_INPUTS: usize = 128;

/// A Saltelli design in the unit hypercube.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// Base points `n`.
    pub n: usize,
    /// Inputs `d`.
    pub d: usize,
    a: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
}

impl Design {
    /// `n` base points of `d` inputs from the scrambled Sobol' sequence of `seed`.
    pub fn sobol(n: usize, d: usize, seed: u32) -> Result<Self, String> {
        if n < MIN_SAMPLES {
            return Err(format!(
                "{n} samples are too few: give at least {MIN_SAMPLES}"
            ));
        }
        if n > MAX_SAMPLES {
            return Err(format!(
                "{n} samples are more than the Sobol' sequence holds: give at most {MAX_SAMPLES}"
            ));
        }
        if d == 0 || d > MAX_INPUTS {
            return Err(format!(
                "{d} uncertain inputs: the design takes 1 to {MAX_INPUTS}"
            ));
        }
        let point = |i: usize, first: usize| -> Vec<f64> {
            (0..d)
                .map(|k| f64::from(sobol_burley::sample(i as u32, (first + k) as u32, seed)))
                .collect()
        };
        Ok(Self {
            n,
            d,
            a: (0..n).map(|i| point(i, 0)).collect(),
            b: (0..n).map(|i| point(i, d)).collect(),
        })
    }

    /// Every point to evaluate, in the order [`Self::split`] reads them: `A`, `B`, then
    /// `A_B^(1)` to `A_B^(d)`.
    pub fn points(&self) -> Vec<Vec<f64>> {
        let mut out = Vec::with_capacity(self.n * (self.d + 2));
        out.extend(self.a.iter().cloned());
        out.extend(self.b.iter().cloned());
        for i in 0..self.d {
            out.extend(self.a.iter().zip(&self.b).map(|(a, b)| {
                let mut p = a.clone();
                p[i] = b[i];
                p
            }));
        }
        out
    }

    /// The values at [`Self::points`], split into `f(A)`, `f(B)` and `f(A_B^(i))` for each `i`.
    pub fn split<'a>(&self, values: &'a [f64]) -> (&'a [f64], &'a [f64], Vec<&'a [f64]>) {
        let n = self.n;
        let ab = (0..self.d)
            .map(|i| &values[(2 + i) * n..(3 + i) * n])
            .collect();
        (&values[..n], &values[n..2 * n], ab)
    }
}
