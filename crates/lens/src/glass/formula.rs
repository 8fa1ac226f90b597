//! Dispersion formulas: the refractive index of a glass against wavelength,
//! as the refractiveindex.info database and Zemax AGF catalogues write them.
//! Wavelengths in the formulas are micrometres, as in both sources; the
//! functions here take nanometres and convert. Indices are relative to air,
//! as the vendors' catalogues give them.

use super::kernel::{Kernel, Lambda};

/// How a glass's index depends on wavelength.
#[derive(Debug, Clone, PartialEq)]
pub enum Dispersion {
    /// refractiveindex.info formula 1-9 with its coefficients as written
    /// (λ in µm):
    ///
    /// 1. Sellmeier: n² - 1 = C1 + Σ C(i) λ² / (λ² - C(i+1)²)
    /// 2. Sellmeier-2: n² - 1 = C1 + Σ C(i) λ² / (λ² - C(i+1))
    /// 3. Polynomial: n² = C1 + Σ C(i) λ^C(i+1)
    /// 4. RefractiveIndex.INFO: n² = C1 + C2 λ^C3 / (λ² - C4^C5)
    ///    + C6 λ^C7 / (λ² - C8^C9) + Σ C(i) λ^C(i+1) (i = 10, 12, ...)
    /// 5. Cauchy: n = C1 + Σ C(i) λ^C(i+1)
    /// 6. Gases: n - 1 = C1 + Σ C(i) / (C(i+1) - λ⁻²)
    /// 7. Herzberger: n = C1 + C2 / (λ² - 0.028) + C3 / (λ² - 0.028)²
    ///    + C4 λ² + C5 λ⁴ + C6 λ⁶
    /// 8. Retro: (n² - 1) / (n² + 2) = C1 + C2 λ² / (λ² - C3) + C4 λ²
    /// 9. Exotic: n² = C1 + C2 / (λ² - C3) + C4 (λ - C5) / ((λ - C5)² + C6)
    Rii {
        /// Formula number, 1-9.
        formula: u8,
        /// Coefficients C1, C2, ...
        c: Vec<f64>,
    },
    /// Zemax AGF formula 1-13 with the catalogue's `CD` coefficients
    /// (λ in µm):
    ///
    /// 1. Schott: n² = a0 + a1 λ² + a2 λ⁻² + a3 λ⁻⁴ + a4 λ⁻⁶ + a5 λ⁻⁸
    /// 2. Sellmeier 1: n² - 1 = Σ(i=1..3) K(i) λ² / (λ² - L(i))
    /// 3. Herzberger: n = A + B L + C L² + D λ² + E λ⁴ + F λ⁶, L = 1 / (λ² - 0.028)
    /// 4. Sellmeier 2: n² - 1 = A + B1 λ² / (λ² - λ1²) + B2 / (λ² - λ2²)
    /// 5. Conrady: n = n0 + A / λ + B / λ^3.5
    /// 6. Sellmeier 3: n² - 1 = Σ(i=1..4) K(i) λ² / (λ² - L(i))
    /// 7. Handbook of Optics 1: n² = A + B / (λ² - C) - D λ²
    /// 8. Handbook of Optics 2: n² = A + B λ² / (λ² - C) - D λ²
    /// 9. Sellmeier 4: n² = A + B λ² / (λ² - C) + D λ² / (λ² - E)
    /// 10. Extended 1: n² = a0 + a1 λ² + a2 λ⁻² + a3 λ⁻⁴ + a4 λ⁻⁶ + a5 λ⁻⁸
    ///     + a6 λ⁻¹⁰ + a7 λ⁻¹²
    /// 11. Sellmeier 5: n² - 1 = Σ(i=1..5) K(i) λ² / (λ² - L(i))
    /// 12. Extended 2: n² = a0 + a1 λ² + a2 λ⁻² + a3 λ⁻⁴ + a4 λ⁻⁶ + a5 λ⁻⁸
    ///     + a6 λ⁴ + a7 λ⁶
    /// 13. Extended 3: n² = a0 + a1 λ² + a2 λ⁴ + a3 λ⁻² + a4 λ⁻⁴ + a5 λ⁻⁶
    ///     + a6 λ⁻⁸ + a7 λ⁻¹⁰ + a8 λ⁻¹²
    ///
    /// (K and L alternate in the coefficients: K1 L1 K2 L2 ...)
    Agf {
        /// Formula number, 1-13.
        formula: u8,
        /// The `CD` coefficients, in order.
        c: Vec<f64>,
    },
    /// Tabulated indices, interpolated by a cubic through the four nearest
    /// points (linear when there are only two), wavelengths in nm.
    Tabulated {
        /// Wavelengths, nm, increasing.
        nm: Vec<f64>,
        /// Index at each.
        n: Vec<f64>,
    },
    /// A model glass from nd and vd (see [`Dispersion::model`]).
    Model {
        /// Index at the helium d line.
        nd: f64,
        /// Abbe number (nd - 1) / (nF - nC).
        vd: f64,
    },
}

/// The coefficient `k` (0-based), 0 where the list is short (catalogues
/// omit trailing zero terms).
fn at(c: &[f64], k: usize) -> f64 {
    c.get(k).copied().unwrap_or(0.0)
}

impl Dispersion {
    /// A model glass that has exactly index `nd` at the d line and Abbe
    /// number `vd`: the two-term Cauchy formula written about the d line,
    /// n(λ) = nd + B (λ⁻² - λd⁻²), with B = (nd - 1) / (vd (λF⁻² - λC⁻²))
    /// (F, d, C the lines of [`super::LINE_F_NM`] and the others; λ in µm).
    /// n(λd) is nd to the bit; vd is reproduced to rounding (1e-13).
    pub fn model(nd: f64, vd: f64) -> Dispersion {
        Dispersion::Model { nd, vd }
    }

    /// The formula's name, for reports (`"rii 2"`, `"agf 1 (Schott)"`,
    /// `"tabulated"`, `"model (nd, vd)"`).
    pub fn name(&self) -> String {
        match self {
            Dispersion::Rii { formula, .. } => format!("rii {formula}"),
            Dispersion::Agf { formula, .. } => {
                let names = [
                    "Schott",
                    "Sellmeier 1",
                    "Herzberger",
                    "Sellmeier 2",
                    "Conrady",
                    "Sellmeier 3",
                    "Handbook of Optics 1",
                    "Handbook of Optics 2",
                    "Sellmeier 4",
                    "Extended 1",
                    "Sellmeier 5",
                    "Extended 2",
                    "Extended 3",
                ];
                let name = (*formula as usize).checked_sub(1).and_then(|k| names.get(k)).unwrap_or(&"unknown");
                format!("agf {formula} ({name})")
            }
            Dispersion::Tabulated { .. } => "tabulated".into(),
            Dispersion::Model { .. } => "model (nd, vd)".into(),
        }
    }

    /// The index at `nm` nanometres (no range check: see
    /// [`super::Glass::index`]). NaN only where the formula itself has no
    /// real value (which a valid range excludes). The common forms are
    /// evaluated by the code the batch tracer runs per ray
    /// (`glass::kernel`), the others by [`Self::index_general`].
    pub fn index(&self, nm: f64) -> f64 {
        match Kernel::of(self) {
            Kernel::General => self.index_general(nm),
            k => k.eval(&Lambda::of_nm(nm)),
        }
    }

    /// The index at `nm` nanometres straight from the formula as written
    /// (powers by `powf`, tabulated data interpolated): what
    /// [`Self::index`] uses for the forms the kernel does not take.
    pub fn index_general(&self, nm: f64) -> f64 {
        let l = nm * 1e-3;
        match self {
            Dispersion::Rii { formula, c } => rii(*formula, c, l),
            Dispersion::Agf { formula, c } => agf(*formula, c, l),
            Dispersion::Tabulated { nm: x, n } => interpolate(x, n, nm),
            Dispersion::Model { .. } => Kernel::of(self).eval(&Lambda::of_nm(nm)),
        }
    }
}

fn rii(formula: u8, c: &[f64], l: f64) -> f64 {
    let l2 = l * l;
    let pairs = |from: usize| (from..c.len().saturating_sub(1)).step_by(2);
    match formula {
        1 => (1.0 + at(c, 0) + pairs(1).map(|i| c[i] * l2 / (l2 - c[i + 1] * c[i + 1])).sum::<f64>()).sqrt(),
        2 => (1.0 + at(c, 0) + pairs(1).map(|i| c[i] * l2 / (l2 - c[i + 1])).sum::<f64>()).sqrt(),
        3 => (at(c, 0) + pairs(1).map(|i| c[i] * l.powf(c[i + 1])).sum::<f64>()).sqrt(),
        4 => {
            let mut n2 = at(c, 0);
            n2 += at(c, 1) * l.powf(at(c, 2)) / (l2 - at(c, 3).powf(at(c, 4)));
            n2 += at(c, 5) * l.powf(at(c, 6)) / (l2 - at(c, 7).powf(at(c, 8)));
            n2 += pairs(9).map(|i| c[i] * l.powf(c[i + 1])).sum::<f64>();
            n2.sqrt()
        }
        5 => at(c, 0) + pairs(1).map(|i| c[i] * l.powf(c[i + 1])).sum::<f64>(),
        6 => 1.0 + at(c, 0) + pairs(1).map(|i| c[i] / (c[i + 1] - 1.0 / l2)).sum::<f64>(),
        7 => {
            let q = 1.0 / (l2 - 0.028);
            at(c, 0) + at(c, 1) * q + at(c, 2) * q * q + at(c, 3) * l2 + at(c, 4) * l2 * l2 + at(c, 5) * l2 * l2 * l2
        }
        8 => {
            let r = at(c, 0) + at(c, 1) * l2 / (l2 - at(c, 2)) + at(c, 3) * l2;
            ((1.0 + 2.0 * r) / (1.0 - r)).sqrt()
        }
        9 => {
            let d = l - at(c, 4);
            (at(c, 0) + at(c, 1) / (l2 - at(c, 2)) + at(c, 3) * d / (d * d + at(c, 5))).sqrt()
        }
        _ => f64::NAN,
    }
}

fn agf(formula: u8, c: &[f64], l: f64) -> f64 {
    let l2 = l * l;
    let sellmeier =
        |terms: usize| (1.0 + (0..terms).map(|i| at(c, 2 * i) * l2 / (l2 - at(c, 2 * i + 1))).sum::<f64>()).sqrt();
    // a0 + a1 λ² + a2 λ⁻² + a3 λ⁻⁴ + ... (the Schott-type series)
    let laurent = |pos: &[i32]| -> f64 { pos.iter().enumerate().map(|(i, p)| at(c, i) * l2.powi(*p)).sum::<f64>() };
    match formula {
        1 => laurent(&[0, 1, -1, -2, -3, -4]).sqrt(),
        2 => sellmeier(3),
        3 => {
            let q = 1.0 / (l2 - 0.028);
            at(c, 0) + at(c, 1) * q + at(c, 2) * q * q + at(c, 3) * l2 + at(c, 4) * l2 * l2 + at(c, 5) * l2 * l2 * l2
        }
        4 => {
            (1.0 + at(c, 0) + at(c, 1) * l2 / (l2 - at(c, 2) * at(c, 2)) + at(c, 3) / (l2 - at(c, 4) * at(c, 4))).sqrt()
        }
        5 => at(c, 0) + at(c, 1) / l + at(c, 2) / l.powf(3.5),
        6 => sellmeier(4),
        7 => (at(c, 0) + at(c, 1) / (l2 - at(c, 2)) - at(c, 3) * l2).sqrt(),
        8 => (at(c, 0) + at(c, 1) * l2 / (l2 - at(c, 2)) - at(c, 3) * l2).sqrt(),
        9 => (at(c, 0) + at(c, 1) * l2 / (l2 - at(c, 2)) + at(c, 3) * l2 / (l2 - at(c, 4))).sqrt(),
        10 => laurent(&[0, 1, -1, -2, -3, -4, -5, -6]).sqrt(),
        11 => sellmeier(5),
        12 => laurent(&[0, 1, -1, -2, -3, -4, 2, 3]).sqrt(),
        13 => laurent(&[0, 1, 2, -1, -2, -3, -4, -5, -6]).sqrt(),
        _ => f64::NAN,
    }
}

/// Cubic (Lagrange) interpolation through the four tabulated points around
/// `x` (the two nearest at the ends; linear with two points).
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let n = xs.len();
    if n == 0 {
        return f64::NAN;
    }
    if n == 1 {
        return ys[0];
    }
    let k = xs.partition_point(|v| *v <= x).clamp(1, n - 1);
    let lo = k.saturating_sub(2).min(n.saturating_sub(4));
    let hi = (lo + 4).min(n);
    let mut sum = 0.0;
    for i in lo..hi {
        let mut w = 1.0;
        for j in lo..hi {
            if i != j {
                w *= (x - xs[j]) / (xs[i] - xs[j]);
            }
        }
        sum += w * ys[i];
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same Sellmeier glass written in each form gives the same index.
    #[test]
    fn sellmeier_forms_agree() {
        // SCHOTT N-BK7 (B1 B2 B3, C1 C2 C3 in µm²)
        let (b, c) = ([1.03961212, 0.231792344, 1.01046945], [0.00600069867, 0.0200179144, 103.560653]);
        let rii2 = Dispersion::Rii { formula: 2, c: vec![0.0, b[0], c[0], b[1], c[1], b[2], c[2]] };
        let rii1 =
            Dispersion::Rii { formula: 1, c: vec![0.0, b[0], c[0].sqrt(), b[1], c[1].sqrt(), b[2], c[2].sqrt()] };
        let agf2 = Dispersion::Agf { formula: 2, c: vec![b[0], c[0], b[1], c[1], b[2], c[2]] };
        for nm in [400.0, 587.5618, 1000.0] {
            let n = rii2.index(nm);
            assert!((rii1.index(nm) - n).abs() < 1e-14 && (agf2.index(nm) - n).abs() < 1e-14);
        }
        assert!((rii2.index(587.5618) - 1.5168).abs() < 5e-6);
    }

    #[test]
    fn model_glass_reproduces_nd_and_vd() {
        let m = Dispersion::model(1.6, 40.0);
        let (nd, nf, nc) =
            (m.index(super::super::LINE_D_NM), m.index(super::super::LINE_F_NM), m.index(super::super::LINE_C_NM));
        assert!((nd - 1.6).abs() < 1e-15);
        assert!(((nd - 1.0) / (nf - nc) - 40.0).abs() < 1e-10);
    }

    #[test]
    fn tabulated_is_exact_at_the_points_and_smooth_between() {
        let t = Dispersion::Tabulated { nm: vec![400.0, 500.0, 600.0, 700.0], n: vec![1.53, 1.52, 1.515, 1.512] };
        assert_eq!(t.index(500.0), 1.52);
        let mid = t.index(550.0);
        assert!(mid < 1.52 && mid > 1.515);
    }
}
