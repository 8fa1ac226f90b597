//! The dispersion formulas most catalogue glasses use, written once over
//! the lane type of the tracing kernel ([`crate::simd`]): the one-ray
//! [`Dispersion::index`] and the batch tracer's per-ray indices (four rays
//! at a time) run this same code, so a ray traced in a batch of mixed
//! wavelengths meets exactly the indices of the prescription at its own
//! wavelength, to the bit.
//!
//! Three forms cover the shipped catalogues but a few dozen glasses:
//! Sellmeier sums (refractiveindex.info 1 and 2, AGF 2, 6 and 11), series
//! in even powers of λ (refractiveindex.info 3 with even integer
//! exponents; AGF 1, 10, 12 and 13) and the model glass. The others
//! (tabulated data, general exponents) are evaluated one ray at a time by
//! [`Dispersion::index_general`].

use super::formula::Dispersion;
use super::{LINE_C_NM, LINE_D_NM, LINE_F_NM};
use crate::simd::lanes::Real;

/// Most terms of a Sellmeier sum (AGF Sellmeier 5).
const SELLMEIER_TERMS: usize = 5;
/// Most terms of an even power series (AGF Extended 3: a0 and 8 others).
const SERIES_TERMS: usize = 9;
/// Highest power of λ² (positive or negative) a series may hold.
const MAX_POWER: i32 = 8;

/// A dispersion formula in the form the kernel evaluates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Kernel {
    /// n² = base + Σ k λ² / (λ² - l), λ in µm (`base` is 1 plus any
    /// constant term), evaluated as one fraction ([`sellmeier`]).
    Sellmeier { base: f64, k: [f64; SELLMEIER_TERMS], l: [f64; SELLMEIER_TERMS], terms: usize },
    /// n² = Σ a λ^(2p) in the order written, λ in µm, the powers of λ² by
    /// repeated multiplication of λ² and of 1/λ².
    Series { a: [f64; SERIES_TERMS], p: [i32; SERIES_TERMS], terms: usize },
    /// The model glass: n = nd + b (1/λ² - 1/λd²), exactly nd at the d line.
    Model { nd: f64, b: f64, inv_d: f64 },
    /// Anything else, one ray at a time.
    General,
}

/// λ² (µm²) and its inverse for one or four rays, shared by every glass a
/// ray crosses.
#[derive(Clone, Copy)]
pub(crate) struct Lambda<L> {
    pub l2: L,
    pub inv_l2: L,
}

impl<L: Real> Lambda<L> {
    /// From wavelengths in nm.
    #[inline(always)]
    pub(crate) fn of_nm(nm: L) -> Self {
        let l = nm * L::splat(1e-3);
        let l2 = l * l;
        Lambda { l2, inv_l2: L::splat(1.0) / l2 }
    }

    /// [`Self::of_nm`] without 1/λ² (left NaN), for glasses whose formulas
    /// do not take it (the Sellmeier sums): it saves a division.
    #[inline(always)]
    pub(crate) fn squared_only(nm: L) -> Self {
        let l = nm * L::splat(1e-3);
        Lambda { l2: l * l, inv_l2: L::splat(f64::NAN) }
    }
}

/// 1/λ² in µm⁻² of a wavelength in nm, as [`Lambda::of_nm`] computes it.
fn inv_square_um(nm: f64) -> f64 {
    Lambda::<f64>::of_nm(nm).inv_l2
}

impl Kernel {
    /// The kernel form of `d`, [`Kernel::General`] where it has none.
    pub(crate) fn of(d: &Dispersion) -> Kernel {
        let at = |c: &[f64], k: usize| c.get(k).copied().unwrap_or(0.0);
        match d {
            Dispersion::Rii { formula: f @ (1 | 2), c } => {
                let pairs = c.get(1..).unwrap_or(&[]).chunks_exact(2);
                let l = |x: f64| if *f == 1 { x * x } else { x };
                Self::sellmeier(1.0 + at(c, 0), pairs.map(|p| (p[0], l(p[1]))))
            }
            Dispersion::Agf { formula, c } => match formula {
                2 | 6 | 11 => {
                    let terms = match formula {
                        2 => 3,
                        6 => 4,
                        _ => 5,
                    };
                    Self::sellmeier(1.0, (0..terms).map(|i| (at(c, 2 * i), at(c, 2 * i + 1))))
                }
                1 => Self::series(c, &[0, 1, -1, -2, -3, -4]),
                10 => Self::series(c, &[0, 1, -1, -2, -3, -4, -5, -6]),
                12 => Self::series(c, &[0, 1, -1, -2, -3, -4, 2, 3]),
                13 => Self::series(c, &[0, 1, 2, -1, -2, -3, -4, -5, -6]),
                _ => Kernel::General,
            },
            Dispersion::Rii { formula: 3, c } => {
                // n² = C1 + Σ C(i) λ^C(i+1): even integer exponents only
                let (mut a, mut p) = ([0.0; SERIES_TERMS], [0; SERIES_TERMS]);
                a[0] = at(c, 0);
                let mut n = 1;
                for pair in c.get(1..).unwrap_or(&[]).chunks_exact(2) {
                    let half = pair[1] / 2.0;
                    if n == SERIES_TERMS || !(half.fract() == 0.0 && half.abs() <= MAX_POWER as f64) {
                        return Kernel::General;
                    }
                    (a[n], p[n]) = (pair[0], half as i32);
                    n += 1;
                }
                Kernel::Series { a, p, terms: n }
            }
            Dispersion::Model { nd, vd } => {
                let (inv_f, inv_c, inv_d) =
                    (inv_square_um(LINE_F_NM), inv_square_um(LINE_C_NM), inv_square_um(LINE_D_NM));
                Kernel::Model { nd: *nd, b: (nd - 1.0) / (vd * (inv_f - inv_c)), inv_d }
            }
            _ => Kernel::General,
        }
    }

    fn sellmeier(base: f64, terms: impl Iterator<Item = (f64, f64)>) -> Kernel {
        let (mut k, mut l) = ([0.0; SELLMEIER_TERMS], [0.0; SELLMEIER_TERMS]);
        let mut n = 0;
        for (ki, li) in terms {
            if n == SELLMEIER_TERMS {
                return Kernel::General;
            }
            (k[n], l[n]) = (ki, li);
            n += 1;
        }
        Kernel::Sellmeier { base, k, l, terms: n }
    }

    /// The series Σ c\[i\] λ^(2 p\[i\]) (coefficients past the end of `c` are 0).
    fn series(c: &[f64], p: &[i32]) -> Kernel {
        if p.len() > SERIES_TERMS || c.len() > p.len() {
            return Kernel::General;
        }
        let (mut a, mut pw) = ([0.0; SERIES_TERMS], [0; SERIES_TERMS]);
        for (i, &e) in p.iter().enumerate() {
            a[i] = c.get(i).copied().unwrap_or(0.0);
            pw[i] = e;
        }
        Kernel::Series { a, p: pw, terms: p.len() }
    }

    /// The index for the wavelengths `w` (one ray or one per lane).
    /// Meaningless for [`Kernel::General`] (the caller evaluates those).
    #[inline(always)]
    pub(crate) fn eval<L: Real>(&self, w: &Lambda<L>) -> L {
        match self {
            Kernel::Sellmeier { base, k, l, terms } => match terms {
                3 => sellmeier::<L, 3>(w, *base, k, l),
                4 => sellmeier::<L, 4>(w, *base, k, l),
                5 => sellmeier::<L, 5>(w, *base, k, l),
                2 => sellmeier::<L, 2>(w, *base, k, l),
                1 => sellmeier::<L, 1>(w, *base, k, l),
                _ => L::splat(base.sqrt()),
            },
            Kernel::Series { a, p, terms } => {
                let mut n2 = L::splat(0.0);
                for i in 0..*terms {
                    n2 = n2 + L::splat(a[i]) * power(w, p[i]);
                }
                n2.sqrt()
            }
            Kernel::Model { nd, b, inv_d } => L::splat(*b).fma(w.inv_l2 - L::splat(*inv_d), L::splat(*nd)),
            Kernel::General => L::splat(f64::NAN),
        }
    }
}

/// n = sqrt(base + Σ k λ²/(λ² - l)) over the first `N` terms, the sum as
/// one fraction λ² P / Q with Q = Π (λ² - l) and P = Σ k Π_{j≠i} (λ² - l_j):
/// one division instead of one per term (the batch tracer's slowest
/// operation), and the same conditioning (P / Q is Σ k / (λ² - l) term for
/// term). `N` a constant, so the loops unroll.
#[inline(always)]
fn sellmeier<L: Real, const N: usize>(
    w: &Lambda<L>,
    base: f64,
    k: &[f64; SELLMEIER_TERMS],
    l: &[f64; SELLMEIER_TERMS],
) -> L {
    let mut d = [L::splat(0.0); N];
    for i in 0..N {
        d[i] = w.l2 - L::splat(l[i]);
    }
    // before[i] = Π_{j<i} d_j; `after` runs over Π_{j>i} d_j and ends as Q
    let mut before = [L::splat(1.0); N];
    for i in 1..N {
        before[i] = before[i - 1] * d[i - 1];
    }
    let mut after = L::splat(1.0);
    let mut p = L::splat(0.0);
    for i in (0..N).rev() {
        p = L::splat(k[i]).fma(before[i] * after, p);
        after = after * d[i];
    }
    (w.l2 * p / after + L::splat(base)).sqrt()
}

/// λ^(2p): λ² or 1/λ² multiplied by itself, left to right (1 for p = 0).
#[inline(always)]
fn power<L: Real>(w: &Lambda<L>, p: i32) -> L {
    let base = if p < 0 { w.inv_l2 } else { w.l2 };
    let mut x = L::splat(1.0);
    for k in 0..p.unsigned_abs() {
        x = if k == 0 { base } else { x * base };
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glass::Catalogs;

    /// The kernel gives every shipped glass the index its formula as
    /// written gives (powers by `powf` there, by multiplication here) to
    /// within a few ulps, over its whole range; and it takes all but a few
    /// dozen of them.
    #[test]
    fn kernel_is_the_formula_as_written() {
        let (mut taken, mut all, mut worst) = (0, 0, 0.0f64);
        for g in Catalogs::shipped().catalogs.iter().flat_map(|c| c.glasses.iter()) {
            all += 1;
            let k = Kernel::of(&g.dispersion);
            if k == Kernel::General {
                continue;
            }
            taken += 1;
            let [lo, hi] = g.range_nm;
            for i in 0..=20 {
                let nm = lo + (hi - lo) * i as f64 / 20.0;
                let (a, b) = (k.eval(&Lambda::of_nm(nm)), written(&g.dispersion, nm));
                if b.is_finite() {
                    worst = worst.max((a - b).abs() / b);
                }
            }
        }
        assert!(worst < 1e-14, "worst relative difference {worst:e}");
        assert_eq!(all - taken, 98, "{taken} of {all} glasses in the kernel (docs/glass.md)");
    }

    /// The formulas as the catalogues write them, straight (Sellmeier and
    /// power series by `powf`).
    fn written(d: &Dispersion, nm: f64) -> f64 {
        let l = nm * 1e-3;
        match d {
            Dispersion::Rii { formula: 3, c } => {
                let s: f64 = c[1..].chunks_exact(2).map(|p| p[0] * l.powf(p[1])).sum();
                (c[0] + s).sqrt()
            }
            Dispersion::Rii { formula: f @ (1 | 2), c } => {
                let s: f64 = c[1..]
                    .chunks_exact(2)
                    .map(|p| p[0] * l * l / (l * l - if *f == 1 { p[1] * p[1] } else { p[1] }))
                    .sum();
                (1.0 + c[0] + s).sqrt()
            }
            _ => d.index_general(nm),
        }
    }

    /// The model glass is nd to the bit at the d line and has Abbe number
    /// vd.
    #[test]
    fn model_is_nd_at_d() {
        for (nd, vd) in [(1.67, 47.1), (1.5168, 64.17), (1.9, 20.0)] {
            let d = Dispersion::model(nd, vd);
            assert_eq!(d.index(LINE_D_NM), nd);
            let v = (nd - 1.0) / (d.index(LINE_F_NM) - d.index(LINE_C_NM));
            assert!((v - vd).abs() < 1e-11 * vd, "{v} vs {vd}");
        }
    }
}
