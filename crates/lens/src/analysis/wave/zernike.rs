//! Zernike polynomials over the unit pupil, and least-squares fits of a
//! wavefront to them, in the two orders optical programs use:
//!
//! - **Fringe** (University of Arizona order, 37 terms): Z1 = 1, Z2 = rho
//!   cos(theta), Z3 = rho sin(theta), Z4 = 2 rho^2 - 1, ... Z37 = the
//!   12th-order spherical term; not normalised (each term is 1 at the
//!   pupil's rim where its angular factor is 1). Terms come in groups of
//!   equal (n + |m|) / 2, larger |m| first, cosine before sine.
//! - **Standard** (Noll's order, RMS-normalised): Z_j = sqrt(n + 1) R_n^0
//!   for m = 0, sqrt(2 (n + 1)) R_n^m cos(m theta) for even j and sin(m
//!   theta) for odd j; each term's RMS over the unit disk is 1, so the RMS
//!   of a fitted wavefront without piston is sqrt(sum_{j >= 2} c_j^2).
//!
//! theta is measured from +x toward +y in the normalised pupil (x = rho
//! cos theta, y = rho sin theta), as in Zemax.

use super::opd::Wavefront;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Which Zernike order and normalisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ZernikeKind {
    /// Fringe (University of Arizona) order, not normalised.
    Fringe,
    /// Standard (Noll) order, RMS-normalised.
    Standard,
}

/// The terms fitted, as Zemax lists them.
pub const TERMS: usize = 37;

/// A term's radial degree n, azimuthal order |m|, and angular factor
/// (`true`: sine, `false`: cosine or none).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Term {
    /// Radial degree.
    pub n: u32,
    /// Azimuthal order |m|.
    pub m: u32,
    /// Whether the angular factor is sin(m theta) (else cos, or 1 for m = 0).
    pub sine: bool,
}

impl ZernikeKind {
    /// The term of 1-based index `j` (1 <= j; Fringe up to 37).
    pub fn term(self, j: usize) -> Term {
        match self {
            ZernikeKind::Fringe => fringe(j),
            ZernikeKind::Standard => noll(j),
        }
    }

    /// The value of term `j` at normalised pupil point (x, y).
    pub fn value(self, j: usize, x: f64, y: f64) -> f64 {
        let t = self.term(j);
        let rho = x.hypot(y);
        let theta = y.atan2(x);
        let angular = match (t.m, t.sine) {
            (0, _) => 1.0,
            (m, true) => (m as f64 * theta).sin(),
            (m, false) => (m as f64 * theta).cos(),
        };
        let norm = match self {
            ZernikeKind::Fringe => 1.0,
            ZernikeKind::Standard if t.m == 0 => ((t.n + 1) as f64).sqrt(),
            ZernikeKind::Standard => (2.0 * (t.n + 1) as f64).sqrt(),
        };
        norm * radial(t.n, t.m, rho) * angular
    }

    /// The name used in outputs: `"fringe"` or `"standard"`.
    pub fn name(self) -> &'static str {
        match self {
            ZernikeKind::Fringe => "fringe",
            ZernikeKind::Standard => "standard",
        }
    }
}

/// The Fringe term of index `j` (1-based): groups k = (n + m) / 2 = 0, 1,
/// 2, ..., in each |m| from k down to 0 (cosine then sine); Z37 is n = 12,
/// m = 0.
fn fringe(j: usize) -> Term {
    if j == 37 {
        return Term { n: 12, m: 0, sine: false };
    }
    let mut left = j.max(1);
    for k in 0u32.. {
        for m in (0..=k).rev() {
            let n = 2 * k - m;
            for sine in [false, true] {
                if m == 0 && sine {
                    continue;
                }
                left -= 1;
                if left == 0 {
                    return Term { n, m, sine };
                }
            }
        }
    }
    unreachable!("every index is reached")
}

/// The Noll term of index `j` (1-based).
fn noll(j: usize) -> Term {
    let j = j.max(1);
    let (mut n, mut rest) = (0usize, j - 1);
    while rest > n {
        n += 1;
        rest -= n;
    }
    let m = (n % 2) + 2 * ((rest + (n + 1) % 2) / 2);
    Term { n: n as u32, m: m as u32, sine: m != 0 && j % 2 == 1 }
}

/// The radial polynomial R_n^m(rho).
fn radial(n: u32, m: u32, rho: f64) -> f64 {
    let fact = |k: u32| (1..=k).map(f64::from).product::<f64>();
    (0..=(n - m) / 2)
        .map(|s| {
            let c = fact(n - s) / (fact(s) * fact((n + m) / 2 - s) * fact((n - m) / 2 - s));
            let sign = if s % 2 == 0 { 1.0 } else { -1.0 };
            sign * c * rho.powi((n - 2 * s) as i32)
        })
        .sum()
}

/// A least-squares Zernike fit of a wavefront.
#[derive(Debug, Clone, PartialEq)]
pub struct ZernikeFit {
    /// The order and normalisation.
    pub kind: ZernikeKind,
    /// Coefficients, waves: `coefficients[j - 1]` multiplies term j.
    pub coefficients: Vec<f64>,
    /// The RMS of the wavefront's departure from the fit, waves.
    pub rms_residual: f64,
}

impl ZernikeFit {
    /// The fitted wavefront at normalised pupil point (x, y), waves.
    pub fn at(&self, x: f64, y: f64) -> f64 {
        self.coefficients.iter().enumerate().map(|(i, c)| c * self.kind.value(i + 1, x, y)).sum()
    }

    /// For a Standard fit, the RMS without piston from the coefficients,
    /// sqrt(sum_{j >= 2} c_j^2) (exact over the whole unit disk).
    pub fn rms_without_piston(&self) -> Option<f64> {
        (self.kind == ZernikeKind::Standard)
            .then(|| self.coefficients.iter().skip(1).map(|c| c * c).sum::<f64>().sqrt())
    }
}

/// Fits the first `terms` Zernike terms of `kind` to `w` by weighted least
/// squares over the cells whose rays pass (weights: the cells' area
/// shares). `None` when too few cells pass to fix the terms.
pub fn fit(w: &Wavefront, kind: ZernikeKind, terms: usize) -> Option<ZernikeFit> {
    let samples: Vec<((f64, f64), f64, f64)> = w.passing().collect();
    fit_samples(&samples, kind, terms)
}

/// The first terms of one order, ready to evaluate together: each term's
/// azimuthal order m, angular factor, and radial polynomial as rho^m times
/// a polynomial in rho^2 (its coefficients from the constant up, the
/// normalisation folded in).
struct Basis {
    terms: Vec<(usize, bool, Vec<f64>)>,
    /// The largest azimuthal order.
    m_max: usize,
}

impl Basis {
    fn new(kind: ZernikeKind, count: usize) -> Self {
        let fact = |k: u32| (1..=k).map(f64::from).product::<f64>();
        let terms: Vec<(usize, bool, Vec<f64>)> = (1..=count)
            .map(|j| {
                let t = kind.term(j);
                let norm = match kind {
                    ZernikeKind::Fringe => 1.0,
                    ZernikeKind::Standard if t.m == 0 => ((t.n + 1) as f64).sqrt(),
                    ZernikeKind::Standard => (2.0 * (t.n + 1) as f64).sqrt(),
                };
                // R = sum_s (-1)^s (n - s)! / (s! ((n+m)/2 - s)! ((n-m)/2 - s)!) rho^(n - 2s):
                // the power of rho^2 after rho^m is (n - m)/2 - s
                let top = ((t.n - t.m) / 2) as usize;
                let mut c = vec![0.0; top + 1];
                for s in 0..=(t.n - t.m) / 2 {
                    let sign = if s % 2 == 0 { 1.0 } else { -1.0 };
                    c[top - s as usize] =
                        norm * sign * fact(t.n - s) / (fact(s) * fact((t.n + t.m) / 2 - s) * fact((t.n - t.m) / 2 - s));
                }
                (t.m as usize, t.sine, c)
            })
            .collect();
        let m_max = terms.iter().map(|t| t.0).max().unwrap_or(0);
        Basis { terms, m_max }
    }

    /// Every term at (x, y) into `out`: rho^m cos/sin(m theta) by the
    /// recurrence of (x + i y)^m (no trigonometric calls), the rest by
    /// Horner's rule in rho^2.
    fn eval(&self, x: f64, y: f64, out: &mut [f64]) {
        let r2 = x * x + y * y;
        // (x + i y)^m = rho^m (cos m theta + i sin m theta)
        let mut pm = [(1.0, 0.0); 24];
        for m in 1..=self.m_max.min(23) {
            let (c, s) = pm[m - 1];
            pm[m] = (c * x - s * y, s * x + c * y);
        }
        for (o, (m, sine, c)) in out.iter_mut().zip(&self.terms) {
            let poly = c.iter().rev().fold(0.0, |acc, a| acc * r2 + a);
            let (re, im) = pm[*m];
            *o = poly * if *sine { im } else { re };
        }
    }
}

/// [`fit`] over samples (normalised pupil point, weight, W in waves): the
/// normal equations (the terms are nearly orthogonal over the pupil, so
/// they are well conditioned), solved by Cholesky, or by a truncated
/// eigen-decomposition where vignetting leaves terms nearly dependent.
pub fn fit_samples(samples: &[((f64, f64), f64, f64)], kind: ZernikeKind, terms: usize) -> Option<ZernikeFit> {
    if terms == 0 || samples.len() < terms || (kind == ZernikeKind::Fringe && terms > TERMS) {
        return None;
    }
    let basis = Basis::new(kind, terms);
    // the normal equations' upper triangle (row by row) and right side,
    // summed over chunks of samples on all cores (well conditioned: the
    // terms are nearly orthogonal over the pupil)
    let tri = terms * (terms + 1) / 2;
    let (g, rhs, total) = samples
        .par_chunks(4096)
        .map(|chunk| {
            let mut g = vec![0.0; tri];
            let mut rhs = vec![0.0; terms];
            let mut total = 0.0;
            let mut z = vec![0.0; terms];
            for &((x, y), wt, v) in chunk {
                basis.eval(x, y, &mut z);
                let mut off = 0;
                for a in 0..terms {
                    let za = wt * z[a];
                    rhs[a] += za * v;
                    for (g, zb) in g[off..off + terms - a].iter_mut().zip(&z[a..]) {
                        *g += za * zb;
                    }
                    off += terms - a;
                }
                total += wt;
            }
            (g, rhs, total)
        })
        // collected in order and added in order: the same bits however
        // many threads share the chunks
        .collect::<Vec<_>>()
        .into_iter()
        .fold((vec![0.0; tri], vec![0.0; terms], 0.0), |mut a, b| {
            a.0.iter_mut().zip(&b.0).for_each(|(x, y)| *x += y);
            a.1.iter_mut().zip(&b.1).for_each(|(x, y)| *x += y);
            (a.0, a.1, a.2 + b.2)
        });
    let mut ata = DMatrix::<f64>::zeros(terms, terms);
    let mut off = 0;
    for a in 0..terms {
        for b in a..terms {
            ata[(a, b)] = g[off + b - a];
            ata[(b, a)] = g[off + b - a];
        }
        off += terms - a;
    }
    let atb = DVector::from_vec(rhs);
    let c = match ata.clone().cholesky() {
        Some(ch) => ch.solve(&atb),
        None => {
            let e = ata.clone().symmetric_eigen();
            let top = e.eigenvalues.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let inv = e.eigenvalues.map(|v| if v.abs() > 1e-12 * top { 1.0 / v } else { 0.0 });
            &e.eigenvectors * DMatrix::from_diagonal(&inv) * e.eigenvectors.transpose() * &atb
        }
    };
    if !c.iter().all(|v| v.is_finite()) {
        return None;
    }
    // the residual's weighted sum of squares, summed directly (from the
    // normal equations' pieces it would cancel digits)
    let residual: f64 = samples
        .par_chunks(4096)
        .map(|chunk| {
            let mut z = vec![0.0; terms];
            chunk
                .iter()
                .map(|&((x, y), wt, v)| {
                    basis.eval(x, y, &mut z);
                    let fit: f64 = z.iter().zip(c.iter()).map(|(a, b)| a * b).sum();
                    wt * (v - fit) * (v - fit)
                })
                .sum::<f64>()
        })
        .collect::<Vec<f64>>()
        .into_iter()
        .sum();
    Some(ZernikeFit { kind, coefficients: c.iter().copied().collect(), rms_residual: (residual / total).sqrt() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_orders_list_the_terms_zemax_lists() {
        // Fringe: Z4 defocus, Z9 spherical, Z16 and Z25, Z36, Z37
        let f = |j| ZernikeKind::Fringe.term(j);
        assert_eq!(f(2), Term { n: 1, m: 1, sine: false });
        assert_eq!(f(3), Term { n: 1, m: 1, sine: true });
        assert_eq!(f(4), Term { n: 2, m: 0, sine: false });
        assert_eq!(f(5), Term { n: 2, m: 2, sine: false });
        assert_eq!(f(8), Term { n: 3, m: 1, sine: true });
        assert_eq!(f(9), Term { n: 4, m: 0, sine: false });
        assert_eq!(f(10), Term { n: 3, m: 3, sine: false });
        assert_eq!(f(16), Term { n: 6, m: 0, sine: false });
        assert_eq!(f(25), Term { n: 8, m: 0, sine: false });
        assert_eq!(f(26), Term { n: 5, m: 5, sine: false });
        assert_eq!(f(36), Term { n: 10, m: 0, sine: false });
        assert_eq!(f(37), Term { n: 12, m: 0, sine: false });
        // Noll: Z4 defocus, Z5 sin 2theta, Z6 cos 2theta, Z7 sin, Z8 cos
        // coma, Z11 spherical, Z22 secondary spherical, Z37 n = 10
        let s = |j| ZernikeKind::Standard.term(j);
        assert_eq!(s(2), Term { n: 1, m: 1, sine: false });
        assert_eq!(s(3), Term { n: 1, m: 1, sine: true });
        assert_eq!(s(4), Term { n: 2, m: 0, sine: false });
        assert_eq!(s(5), Term { n: 2, m: 2, sine: true });
        assert_eq!(s(6), Term { n: 2, m: 2, sine: false });
        assert_eq!(s(7), Term { n: 3, m: 1, sine: true });
        assert_eq!(s(8), Term { n: 3, m: 1, sine: false });
        assert_eq!(s(11), Term { n: 4, m: 0, sine: false });
        assert_eq!(s(22), Term { n: 6, m: 0, sine: false });
        assert_eq!(s(37), Term { n: 8, m: 0, sine: false });
        // Fringe Z9 = 6 rho^4 - 6 rho^2 + 1, Z37 = 924 rho^12 - ... + 1
        let r: f64 = 0.7;
        let z9 = 6.0 * r.powi(4) - 6.0 * r * r + 1.0;
        assert!((ZernikeKind::Fringe.value(9, r, 0.0) - z9).abs() < 1e-14);
        let z37 = 924.0 * r.powi(12) - 2772.0 * r.powi(10) + 3150.0 * r.powi(8) - 1680.0 * r.powi(6)
            + 420.0 * r.powi(4)
            - 42.0 * r * r
            + 1.0;
        assert!((ZernikeKind::Fringe.value(37, 0.0, r) - z37).abs() < 1e-12);
    }

    #[test]
    fn standard_terms_are_orthonormal_over_the_disk() {
        let g = super::super::pupil::PupilGrid::new(256);
        let cell = g.cell_area() / std::f64::consts::PI;
        for j in 1..=TERMS {
            for k in j..=TERMS {
                let dot: f64 = g
                    .cells
                    .iter()
                    .map(|c| {
                        let (x, y) = c.centre;
                        c.area * ZernikeKind::Standard.value(j, x, y) * ZernikeKind::Standard.value(k, x, y)
                    })
                    .sum::<f64>()
                    * cell;
                let want = if j == k { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < 5e-3, "<Z{j}, Z{k}> = {dot}");
            }
        }
    }

    #[test]
    fn a_fit_recovers_the_coefficients_it_was_made_of() {
        let g = super::super::pupil::PupilGrid::new(64);
        let want: Vec<f64> = (1..=TERMS).map(|j| ((j * 7919) % 13) as f64 / 13.0 - 0.5).collect();
        for kind in [ZernikeKind::Fringe, ZernikeKind::Standard] {
            let samples: Vec<_> = g
                .cells
                .iter()
                .map(|c| {
                    let (x, y) = c.centre;
                    let w: f64 = want.iter().enumerate().map(|(i, a)| a * kind.value(i + 1, x, y)).sum();
                    (c.centre, c.area, w)
                })
                .collect();
            let fit = fit_samples(&samples, kind, TERMS).expect("fit");
            let worst = fit.coefficients.iter().zip(&want).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            println!("{}: worst coefficient error {worst:.2e}, residual {:.2e}", kind.name(), fit.rms_residual);
            assert!(worst < 1e-9 && fit.rms_residual < 1e-9);
        }
    }
}
