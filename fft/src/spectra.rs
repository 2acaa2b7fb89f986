//! Welch's averaged auto- and cross-spectra for one window length, and how correlated the
//! averages of different windows are.
//!
//! Each run is cut into segments of `len` samples, `hop` apart (overlapping when `hop < len`),
//! centred in the run. A segment's signals have their taper-weighted mean removed (so a
//! record's trim value leaks nothing into the band), are tapered by a Hann window
//! ([`hann`]) and transformed at the grid's frequencies:
//! `S_a(f) = sum_k w_k x_a(k) exp(-i 2 pi f k dt)`, the rectangle rule of the finite Fourier
//! integral in the harness's `ident::fourier` (its trapezoidal end terms vanish: the taper is
//! zero at both ends). The one-sided spectral matrix of a segment is `G_ab = 2 dt conj(S_a) S_b / sum_k w_k^2`
//! (Bendat and Piersol 2010, ch. 11: for white noise of variance `s^2` it is `2 s^2 dt`, the
//! one-sided density), averaged over every segment of every run (several records are
//! averaged, not joined).
//!
//! The transforms are those of the harness's `ident::fourier::transform` (checked against it in
//! the tests), done as one matrix product per window length: a table of `exp(-i w k dt)` for
//! the grid (made by the same re-seeded phasor recurrence) times the matrix of every tapered
//! segment of every signal, so the segments' many transforms at arbitrary frequencies cost one
//! product.
//!
//! In this crate for the build: its loops over frequencies, segments and signals were most of
//! the harness's frequency-response tests' time unoptimised (see `cierva-fft`'s crate doc).

use crate::hann;
use nalgebra::DMatrix;
use rustfft::num_complex::Complex64 as C;
use std::collections::HashMap;

/// A window length's segmenting, in samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Segmenting {
    pub len: usize,
    pub hop: usize,
}

impl Segmenting {
    /// The first sample of each segment of a run of `n` samples: as many as fit, `hop` apart,
    /// the unused remainder split between the run's two ends. None when `len > n`.
    pub fn starts(&self, n: usize) -> Vec<usize> {
        if self.len == 0 || self.hop == 0 || self.len > n {
            return Vec::new();
        }
        let k = (n - self.len) / self.hop + 1;
        let offset = (n - self.len - (k - 1) * self.hop) / 2;
        (0..k).map(|i| offset + i * self.hop).collect()
    }
}

/// One window length's averaged spectra.
#[derive(Debug, Clone)]
pub struct WindowSpectra {
    /// Segments averaged (over every run).
    pub segments: usize,
    /// Per frequency, the `p x p` spectral matrix, row-major: `g[a * p + b]` is the average of
    /// `G_ab = 2 dt conj(S_a) S_b / sum w^2`, signal units squared per hertz.
    pub g: Vec<Vec<C>>,
    /// Per run and signal, the signal's power in the grid's band (its auto-spectrum over that
    /// run's segments, integrated over the grid by the trapezoidal rule), units squared.
    pub band_power: Vec<Vec<f64>>,
}

/// Samples between re-seeds of the phasor recurrence (as in the harness's `fourier::transform`):
/// a complex product's rounding, about 1e-16 a step, stays below 1e-13 over 256 steps.
const RESEED: usize = 256;

/// `cos(w_j k dt)` and `-sin(w_j k dt)` for each grid frequency (rows) and sample `k < len`.
fn phasor_table(freqs_hz: &[f64], dt_s: f64, len: usize) -> (DMatrix<f64>, DMatrix<f64>) {
    let j = freqs_hz.len();
    let (mut re, mut im) = (DMatrix::zeros(j, len), DMatrix::zeros(j, len));
    for (row, f) in freqs_hz.iter().enumerate() {
        let th = -2.0 * std::f64::consts::PI * f * dt_s;
        let step = C::from_polar(1.0, th);
        let mut z = C::new(1.0, 0.0);
        for k in 0..len {
            if k % RESEED == 0 {
                z = C::from_polar(1.0, th * k as f64);
            }
            re[(row, k)] = z.re;
            im[(row, k)] = z.im;
            z *= step;
        }
    }
    (re, im)
}

/// Welch's spectra of `runs` (each a list of `p` signals of one length, sampled at `dt_s`) for
/// one segmenting, at `freqs_hz`.
pub fn window_spectra(
    runs: &[&[Vec<f64>]],
    dt_s: f64,
    seg: Segmenting,
    freqs_hz: &[f64],
) -> WindowSpectra {
    let p = runs.first().map_or(0, |r| r.len());
    let (taper, _) = hann(seg.len, dt_s);
    let sum_w: f64 = taper.iter().sum();
    let sum_w2: f64 = taper.iter().map(|w| w * w).sum();
    let starts: Vec<Vec<usize>> = runs
        .iter()
        .map(|r| seg.starts(r.first().map_or(0, Vec::len)))
        .collect();
    let total: usize = starts.iter().map(Vec::len).sum();
    // Every tapered, de-meaned segment of every signal, one column each: run, segment, signal.
    let mut y = DMatrix::<f64>::zeros(seg.len, total * p);
    let mut col = 0;
    for (run, st) in runs.iter().zip(&starts) {
        for &s in st {
            for x in run.iter() {
                let part = &x[s..s + seg.len];
                let mean = part.iter().zip(&taper).map(|(v, w)| v * w).sum::<f64>() / sum_w;
                let mut c = y.column_mut(col);
                for (k, (v, w)) in part.iter().zip(&taper).enumerate() {
                    c[k] = w * (v - mean);
                }
                col += 1;
            }
        }
    }
    let (er, ei) = phasor_table(freqs_hz, dt_s, seg.len);
    let (sr, si) = (&er * &y, &ei * &y);
    let scale = 2.0 * dt_s / sum_w2;
    let nf = freqs_hz.len();
    let mut g = vec![vec![C::new(0.0, 0.0); p * p]; nf];
    let mut run_auto = vec![vec![vec![0.0; p]; nf]; runs.len()];
    let mut col = 0;
    for (r, st) in starts.iter().enumerate() {
        for _ in st {
            for (f, gf) in g.iter_mut().enumerate() {
                let s: Vec<C> = (0..p)
                    .map(|a| C::new(sr[(f, col + a)], si[(f, col + a)]))
                    .collect();
                for a in 0..p {
                    for b in 0..p {
                        gf[a * p + b] += s[a].conj() * s[b] * scale;
                    }
                    run_auto[r][f][a] += s[a].norm_sqr() * scale / st.len() as f64;
                }
            }
            col += p;
        }
    }
    for gf in &mut g {
        for v in gf.iter_mut() {
            *v /= total.max(1) as f64;
        }
    }
    let band_power = run_auto
        .iter()
        .map(|auto| {
            (0..p)
                .map(|a| {
                    (1..nf)
                        .map(|f| {
                            0.5 * (auto[f][a] + auto[f - 1][a]) * (freqs_hz[f] - freqs_hz[f - 1])
                        })
                        .sum()
                })
                .collect()
        })
        .collect();
    WindowSpectra {
        segments: total,
        g,
        band_power,
    }
}

/// The normalised covariance of the windows' averaged spectra, `R_ij = cov(G_i, G_j) / G^2`,
/// under the spectrum locally flat over a window's bandwidth (Gaussian data).
///
/// Two tapered segments `a`, `b` of one run have `cov(|S_a|^2, |S_b|^2) / (E|S_a|^2 E|S_b|^2) =
/// (sum_n w_a(n) w_b(n))^2 / (sum w_a^2 sum w_b^2)` (white noise: `E[S_a conj(S_b)]` is the
/// variance times the tapers' overlap; Welch 1967's overlap correction is the case of one
/// window length); segments of different runs are independent. `R_ii` is one over window
/// `i`'s equivalent number of independent averages; the off-diagonal terms are what the
/// windows share, since they cut the same records.
pub fn averages_covariance(run_lengths: &[usize], dt_s: f64, segs: &[Segmenting]) -> DMatrix<f64> {
    let nw = segs.len();
    let tapers: Vec<Vec<f64>> = segs.iter().map(|s| hann(s.len, dt_s).0).collect();
    let norms: Vec<f64> = tapers
        .iter()
        .map(|t| t.iter().map(|w| w * w).sum())
        .collect();
    let mut cache: HashMap<(usize, usize, isize), f64> = HashMap::new();
    let mut overlap = |i: usize, j: usize, d: isize| -> f64 {
        // Window j starts d samples after window i.
        *cache.entry((i, j, d)).or_insert_with(|| {
            let (ti, tj) = (&tapers[i], &tapers[j]);
            let sum: f64 = (0..ti.len())
                .filter_map(|n| {
                    let m = n as isize - d;
                    (m >= 0 && (m as usize) < tj.len()).then(|| ti[n] * tj[m as usize])
                })
                .sum();
            sum * sum / (norms[i] * norms[j])
        })
    };
    let mut r = DMatrix::zeros(nw, nw);
    let mut counts = vec![0usize; nw];
    for &n in run_lengths {
        let starts: Vec<Vec<usize>> = segs.iter().map(|s| s.starts(n)).collect();
        for i in 0..nw {
            counts[i] += starts[i].len();
            for j in i..nw {
                let mut sum = 0.0;
                for &a in &starts[i] {
                    for &b in &starts[j] {
                        let d = b as isize - a as isize;
                        if d < segs[i].len as isize && -d < segs[j].len as isize {
                            sum += overlap(i, j, d);
                        }
                    }
                }
                r[(i, j)] += sum;
            }
        }
    }
    for i in 0..nw {
        for j in i..nw {
            let v = r[(i, j)] / (counts[i].max(1) * counts[j].max(1)) as f64;
            r[(i, j)] = v;
            r[(j, i)] = v;
        }
    }
    r
}
