//! How much light a surface between two media reflects, for unpolarised
//! light at a given angle and wavelength: bare (the Fresnel equations) or
//! under thin-film coatings (interference in each layer, by the
//! characteristic-matrix method of Macleod, *Thin-Film Optical Filters*,
//! ch. 2). Lossless dielectrics only: what is not reflected is
//! transmitted. The ghosts a lens makes (light reflected at two surfaces
//! and sent back to the film) are weighted by these reflectances.

use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// Magnesium fluoride's index for the single-layer coating, at the d line
/// (1.3777 ordinary ray; its dispersion, under 0.5% across the visible, is
/// left out).
pub const MGF2_INDEX: f64 = 1.3777;

/// The wavelength a prescription's `"MgF2"` coating is a quarter wave at,
/// nm: mid-visible, where the eye is most sensitive (the usual choice).
pub const MGF2_DESIGN_NM: f64 = 550.0;

/// A surface's coating.
#[derive(Debug, Clone, PartialEq)]
pub enum Coating {
    /// Bare: the Fresnel reflectance.
    None,
    /// A single magnesium fluoride layer a quarter of `design_nm` thick
    /// optically at normal incidence: the common single-layer
    /// anti-reflection coating, least reflective at its design wavelength.
    MgF2 {
        /// The wavelength it is a quarter wave at, nm.
        design_nm: f64,
    },
    /// Layers, listed from the side of the first medium (the one light
    /// comes from when it meets the surface going toward the image).
    Layers(Vec<Layer>),
}

/// One thin film.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    /// Refractive index (real: lossless).
    pub index: f64,
    /// Physical thickness, nm.
    pub thickness_nm: f64,
}

impl Coating {
    /// The layers, listed from the first medium's side.
    pub fn layers(&self) -> Vec<Layer> {
        match self {
            Coating::None => Vec::new(),
            Coating::MgF2 { design_nm } => {
                vec![Layer { index: MGF2_INDEX, thickness_nm: design_nm / (4.0 * MGF2_INDEX) }]
            }
            Coating::Layers(l) => l.clone(),
        }
    }

    /// The reflectance for unpolarised light (the mean of the s and p
    /// reflectances) meeting the coated surface from medium `n1` with the
    /// cosine `cos1` of its angle of incidence (0 to 1), the other medium
    /// `n2`, at `nm`: from `n1`'s side the layers are met in their listed
    /// order (`reversed` for light going the other way). 1 beyond the
    /// critical angle (total internal reflection).
    pub fn reflectance(&self, n1: f64, n2: f64, cos1: f64, nm: f64, reversed: bool) -> f64 {
        // bare and single-layer surfaces in real arithmetic where no
        // medium is evanescent (the closed forms of the general path)
        match self {
            Coating::None => {
                if let Some(r) = bare_real(n1, n2, cos1) {
                    return r;
                }
            }
            Coating::MgF2 { design_nm } => {
                let layer = Layer { index: MGF2_INDEX, thickness_nm: design_nm / (4.0 * MGF2_INDEX) };
                if let Some(r) = single_layer_real(n1, layer, n2, cos1, nm) {
                    return r;
                }
            }
            Coating::Layers(l) if l.len() == 1 => {
                if let Some(r) = single_layer_real(n1, l[0], n2, cos1, nm) {
                    return r;
                }
            }
            Coating::Layers(_) => {}
        }
        let mut layers = self.layers();
        if reversed {
            layers.reverse();
        }
        let (s, p) = stack_reflectance(n1, &layers, n2, cos1, nm);
        0.5 * (s + p)
    }
}

/// The s and p reflectances of a stack of `layers` (listed from the
/// incident side) between media `n_in` and `n_out`, for light from `n_in`
/// with the cosine `cos_in` of its angle of incidence, at `nm`. Each layer
/// multiplies the characteristic matrix [[cos d, i sin d / y], [i y sin d,
/// cos d]] (d = 2 pi n t cos / lambda its phase thickness, y its tilted
/// admittance: n cos for s, n / cos for p); the stack's amplitude
/// reflectance is (y_in B - C) / (y_in B + C) with [B, C] = M [1, y_out].
/// Angles in every medium follow Snell's law, a cosine going imaginary
/// where the light is evanescent.
pub fn stack_reflectance(n_in: f64, layers: &[Layer], n_out: f64, cos_in: f64, nm: f64) -> (f64, f64) {
    let cos_in = cos_in.clamp(0.0, 1.0);
    let sin2 = (1.0 - cos_in * cos_in) * n_in * n_in;
    // the cosine in a medium of index n: sqrt(1 - sin^2 / n^2), imaginary
    // (evanescent) past the critical angle
    let cos_in_medium = |n: f64| Complex64::new(1.0 - sin2 / (n * n), 0.0).sqrt();
    let admittances = |n: f64| {
        let c = cos_in_medium(n);
        (c * n, Complex64::new(n, 0.0) / c)
    };
    let (ys_in, yp_in) = (Complex64::new(n_in * cos_in, 0.0), Complex64::new(n_in / cos_in.max(1e-300), 0.0));
    let (ys_out, yp_out) = admittances(n_out);
    let i = Complex64::new(0.0, 1.0);
    let one = Complex64::new(1.0, 0.0);
    // [B, C] for each polarisation, the stack applied from the exit side
    let mut bc_s = (one, ys_out);
    let mut bc_p = (one, yp_out);
    for l in layers.iter().rev() {
        let c = cos_in_medium(l.index);
        let delta = c * (2.0 * PI * l.index * l.thickness_nm / nm);
        let (cd, sd) = (delta.cos(), delta.sin());
        let (ys, yp) = (c * l.index, Complex64::new(l.index, 0.0) / c);
        bc_s = (cd * bc_s.0 + i * sd / ys * bc_s.1, i * ys * sd * bc_s.0 + cd * bc_s.1);
        bc_p = (cd * bc_p.0 + i * sd / yp * bc_p.1, i * yp * sd * bc_p.0 + cd * bc_p.1);
    }
    let r = |y: Complex64, (b, c): (Complex64, Complex64)| {
        let r = (y * b - c) / (y * b + c);
        r.norm_sqr().min(1.0)
    };
    if cos_in == 0.0 {
        // grazing: everything is reflected
        return (1.0, 1.0);
    }
    (r(ys_in, bc_s), r(yp_in, bc_p))
}

/// The cosine of the angle in a medium of index `n` of light with the
/// invariant `n1 sin1`, squared sine given as `sin2 = (n1 sin1)^2`; `None`
/// where the light is evanescent there.
fn cos_in(n: f64, sin2: f64) -> Option<f64> {
    let c2 = 1.0 - sin2 / (n * n);
    (c2 > 0.0).then(|| c2.sqrt())
}

/// The s and p amplitude reflection coefficients between media `a` and `b`
/// for light at cosines `ca` and `cb` (real: no evanescence).
fn fresnel_amplitudes(a: f64, ca: f64, b: f64, cb: f64) -> (f64, f64) {
    ((a * ca - b * cb) / (a * ca + b * cb), (b * ca - a * cb) / (b * ca + a * cb))
}

/// [`Coating::None`]'s reflectance in real arithmetic; `None` past the
/// critical angle (or at grazing incidence), left to the general path.
fn bare_real(n1: f64, n2: f64, cos1: f64) -> Option<f64> {
    let c1 = cos1.clamp(0.0, 1.0);
    if c1 == 0.0 {
        return None;
    }
    let sin2 = (1.0 - c1 * c1) * n1 * n1;
    let c2 = cos_in(n2, sin2)?;
    let (rs, rp) = fresnel_amplitudes(n1, c1, n2, c2);
    Some(0.5 * (rs * rs + rp * rp))
}

/// One thin film's reflectance in real arithmetic (Airy's sum of the
/// film's multiple reflections: |r|^2 = (r01^2 + r12^2 + 2 r01 r12 cos
/// 2d) / (1 + r01^2 r12^2 + 2 r01 r12 cos 2d) per polarisation, d the
/// film's phase thickness); `None` where any medium is evanescent.
fn single_layer_real(n1: f64, layer: Layer, n2: f64, cos1: f64, nm: f64) -> Option<f64> {
    let c1 = cos1.clamp(0.0, 1.0);
    if c1 == 0.0 {
        return None;
    }
    let sin2 = (1.0 - c1 * c1) * n1 * n1;
    let cf = cos_in(layer.index, sin2)?;
    let c2 = cos_in(n2, sin2)?;
    let (s01, p01) = fresnel_amplitudes(n1, c1, layer.index, cf);
    let (s12, p12) = fresnel_amplitudes(layer.index, cf, n2, c2);
    let cos2d = (4.0 * PI * layer.index * layer.thickness_nm * cf / nm).cos();
    let r = |a: f64, b: f64| {
        let cross = 2.0 * a * b * cos2d;
        (a * a + b * b + cross) / (1.0 + a * a * b * b + cross)
    };
    Some(0.5 * (r(s01, s12) + r(p01, p12)))
}

/// Bins of cos(incidence) over [0, 1] in a [`ReflectanceTable`].
pub const TABLE_BINS: usize = 512;

/// A bin is read by interpolation where that is within this of the exact
/// reflectance at the bin's quarter points (relative, or absolute below
/// 1e-4), else computed exactly.
pub const TABLE_TOLERANCE: f64 = 1e-6;

/// Every surface's reflectance, from either side, tabulated against the
/// cosine of incidence at one wavelength: what a tracer that weights many
/// rays by their Fresnel reflectances reads instead of evaluating each
/// coating's thin-film formula at every step ([`crate::Tracer::with_reflectances`]).
/// A Catmull-Rom spline through [`TABLE_BINS`] + 1 samples where it holds
/// to [`TABLE_TOLERANCE`] at each bin's quarter points; the exact formula
/// in the bins where it does not (the kink at the critical angle, grazing
/// light).
#[derive(Debug, Clone, PartialEq)]
pub struct ReflectanceTable {
    /// The wavelength, nm.
    pub wavelength_nm: f64,
    /// Per surface (0-based) and side (0: light travelling +z, 1: -z): the
    /// samples at cos = (k - 1) / TABLE_BINS for k = 0 to TABLE_BINS + 2
    /// (the two ends extrapolated), and whether each bin is left to the
    /// formula.
    rows: Vec<[(Vec<f64>, Vec<bool>); 2]>,
    /// What it was made from.
    coatings: Vec<Coating>,
    media: Vec<f64>,
}

/// The Catmull-Rom spline through `p` (four samples) at `f` (0 to 1)
/// between the middle two.
#[inline(always)]
fn catmull_rom(p: &[f64], f: f64) -> f64 {
    let (p0, p1, p2, p3) = (p[0], p[1], p[2], p[3]);
    let c1 = p2 - p0;
    let c2 = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3;
    let c3 = 3.0 * (p1 - p2) + p3 - p0;
    p1 + 0.5 * f * (c1 + f * (c2 + f * c3))
}

impl ReflectanceTable {
    /// The table of `coatings` (per surface) between the media `media`
    /// (the index before surface 0, then after each surface) at `nm`.
    pub fn new(coatings: &[Coating], media: &[f64], nm: f64) -> ReflectanceTable {
        let n = TABLE_BINS;
        let rows = coatings
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let (a, b) = (media.get(k).copied().unwrap_or(1.0), media.get(k + 1).copied().unwrap_or(1.0));
                [(a, b, false), (b, a, true)].map(|(n1, n2, back)| {
                    let at = |cos: f64| c.reflectance(n1, n2, cos, nm, back);
                    let mut v = vec![0.0; n + 3];
                    for (j, x) in v.iter_mut().enumerate().take(n + 2).skip(1) {
                        *x = at((j - 1) as f64 / n as f64);
                    }
                    v[0] = 2.0 * v[1] - v[2];
                    v[n + 2] = 3.0 * (v[n + 1] - v[n]) + v[n - 1];
                    // a bin where the spline misses the formula
                    let bad: Vec<bool> = (0..n)
                        .map(|i| {
                            [0.25, 0.5, 0.75].iter().any(|&f| {
                                let want = at((i as f64 + f) / n as f64);
                                let got = catmull_rom(&v[i..i + 4], f);
                                let close = (got - want).abs() <= TABLE_TOLERANCE * want.abs().max(1e-4);
                                !close
                            })
                        })
                        .collect();
                    (v, bad)
                })
            })
            .collect();
        ReflectanceTable { wavelength_nm: nm, rows, coatings: coatings.to_vec(), media: media.to_vec() }
    }

    /// Whether it was made from these coatings and media.
    pub fn covers(&self, coatings: &[Coating], media: &[f64]) -> bool {
        self.coatings == coatings && self.media == media
    }

    /// The reflectance of surface `surface` for light from its +z side
    /// (`backward` false: from the medium before it) at the cosine `cos1`;
    /// `None` where the table leaves it to the formula (or has no such
    /// surface).
    #[inline]
    pub fn get(&self, surface: usize, backward: bool, cos1: f64) -> Option<f64> {
        let (v, bad) = &self.rows.get(surface)?[usize::from(backward)];
        let t = cos1.clamp(0.0, 1.0) * TABLE_BINS as f64;
        let i = (t as usize).min(TABLE_BINS - 1);
        if bad[i] {
            return None;
        }
        Some(catmull_rom(&v[i..i + 4], t - i as f64))
    }
}

/// The Fresnel reflectance of a bare surface for unpolarised light: the
/// mean of the s and p reflectances, light from medium `n1` with the
/// cosine `cos1` of its angle of incidence into medium `n2` (1 beyond the
/// critical angle).
pub fn fresnel(n1: f64, n2: f64, cos1: f64) -> f64 {
    Coating::None.reflectance(n1, n2, cos1, 550.0, false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The table holds every surface's reflectance from both sides within
    /// its tolerance, through the critical angle and at grazing light.
    #[test]
    fn table_matches_the_formula() {
        let coatings = [
            Coating::MgF2 { design_nm: 550.0 },
            Coating::None,
            Coating::Layers(vec![
                Layer { index: 1.38, thickness_nm: 99.6 },
                Layer { index: 2.1, thickness_nm: 130.9 },
                Layer { index: 1.62, thickness_nm: 84.9 },
            ]),
        ];
        let media = [1.0, 1.5168, 1.7552, 1.0];
        let nm = 486.1;
        let table = ReflectanceTable::new(&coatings, &media, nm);
        let mut formula = 0;
        for (k, c) in coatings.iter().enumerate() {
            for back in [false, true] {
                let (n1, n2) = if back { (media[k + 1], media[k]) } else { (media[k], media[k + 1]) };
                for i in 0..=20_000 {
                    let cos = i as f64 / 20_000.0;
                    let want = c.reflectance(n1, n2, cos, nm, back);
                    match table.get(k, back, cos) {
                        Some(got) => assert!(
                            (got - want).abs() <= 2.0 * TABLE_TOLERANCE * want.max(1e-4),
                            "surface {k} back {back} cos {cos}: {got} vs {want}"
                        ),
                        None => formula += 1,
                    }
                }
            }
        }
        // the bins left to the formula are few (the kinks at the critical
        // angles, grazing light)
        assert!(formula > 0 && formula < 6 * 20_000 / 20, "{formula}");
        assert_eq!(table.get(3, false, 0.5), None);
    }

    /// At normal incidence a bare surface reflects ((n1 - n2) / (n1 +
    /// n2))^2 (4.2% for N-BK7 in air), from either side.
    #[test]
    fn bare_normal_incidence() {
        let n: f64 = 1.5168;
        let want = ((n - 1.0) / (n + 1.0)).powi(2);
        assert_relative_eq!(fresnel(1.0, n, 1.0), want, max_relative = 1e-14);
        assert_relative_eq!(fresnel(n, 1.0, 1.0), want, max_relative = 1e-14);
    }

    /// p light is not reflected at Brewster's angle, tan = n2 / n1; the s
    /// reflectance there is the closed form ((n1 c1 - n2 c2) / (n1 c1 +
    /// n2 c2))^2.
    #[test]
    fn brewster_angle_reflects_no_p_light() {
        let (n1, n2): (f64, f64) = (1.0, 1.5168);
        let theta = (n2 / n1).atan();
        let (c1, s1) = (theta.cos(), theta.sin());
        let c2 = (1.0 - (n1 * s1 / n2).powi(2)).sqrt();
        let (s, p) = stack_reflectance(n1, &[], n2, c1, 550.0);
        assert!(p < 1e-28, "{p}");
        assert_relative_eq!(s, ((n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2)).powi(2), max_relative = 1e-12);
    }

    /// Beyond the critical angle (glass to air), everything is reflected,
    /// coated or not.
    #[test]
    fn total_internal_reflection() {
        let n: f64 = 1.5168;
        let cos = (1.0f64 - (1.0 / n / 0.99).powi(2)).sqrt() * 0.5;
        assert_relative_eq!(fresnel(n, 1.0, cos), 1.0, max_relative = 1e-12);
        let c = Coating::MgF2 { design_nm: 550.0 };
        assert_relative_eq!(c.reflectance(n, 1.0, cos, 500.0, true), 1.0, max_relative = 1e-12);
    }

    /// A quarter-wave layer at its design wavelength and normal incidence
    /// reflects ((n0 ns - nc^2) / (n0 ns + nc^2))^2: 1.3% on N-BK7 for
    /// MgF2, against 4.2% bare; a half-wave layer is absent.
    #[test]
    fn quarter_and_half_wave_layers() {
        let (ns, nc) = (1.5168, MGF2_INDEX);
        let c = Coating::MgF2 { design_nm: 550.0 };
        let want = ((ns - nc * nc) / (ns + nc * nc)).powi(2);
        assert_relative_eq!(c.reflectance(1.0, ns, 1.0, 550.0, false), want, max_relative = 1e-12);
        assert!(want < 0.014 && want > 0.012, "{want}");
        // away from the design wavelength it reflects more
        assert!(c.reflectance(1.0, ns, 1.0, 420.0, false) > want);
        let half = Coating::Layers(vec![Layer { index: 2.0, thickness_nm: 550.0 / 4.0 }]);
        assert_relative_eq!(half.reflectance(1.0, ns, 1.0, 550.0, false), fresnel(1.0, ns, 1.0), max_relative = 1e-12);
    }

    /// The real-arithmetic forms (bare, one film) equal the general
    /// characteristic-matrix path at every angle, wavelength and pair of
    /// media, past the critical angle too (where they defer to it).
    #[test]
    fn real_forms_equal_the_general_path() {
        let mut next = crate::trace::uniform(42);
        for _ in 0..20_000 {
            let (n1, n2) = (1.0 + next(), 1.0 + next());
            let cos1 = next();
            let nm = 380.0 + 400.0 * next();
            let layer = Layer { index: 1.2 + next(), thickness_nm: 300.0 * next() };
            let general = |l: &[Layer]| {
                let (s, p) = stack_reflectance(n1, l, n2, cos1, nm);
                0.5 * (s + p)
            };
            let bare = Coating::None.reflectance(n1, n2, cos1, nm, false);
            assert!((bare - general(&[])).abs() < 1e-12, "bare {n1} {n2} {cos1}: {bare} vs {}", general(&[]));
            let one = Coating::Layers(vec![layer]).reflectance(n1, n2, cos1, nm, false);
            assert!(
                (one - general(&[layer])).abs() < 1e-12,
                "{layer:?} {n1} {n2} {cos1} {nm}: {one} vs {}",
                general(&[layer])
            );
        }
    }

    /// A lossless stack reflects the same from either side at angles Snell
    /// relates (reciprocity), and never more than 1 or less than 0.
    #[test]
    fn reciprocity_and_bounds() {
        let layers = Coating::Layers(vec![
            Layer { index: 1.38, thickness_nm: 99.6 },
            Layer { index: 2.1, thickness_nm: 65.0 },
            Layer { index: 1.62, thickness_nm: 84.0 },
        ]);
        let (n1, n2): (f64, f64) = (1.0, 1.7);
        for k in 0..20 {
            let c1 = 1.0 - k as f64 / 20.0 * 0.9;
            let s1 = (1.0 - c1 * c1).sqrt();
            let c2 = (1.0 - (n1 * s1 / n2).powi(2)).sqrt();
            for nm in [420.0, 550.0, 680.0] {
                let a = layers.reflectance(n1, n2, c1, nm, false);
                let b = layers.reflectance(n2, n1, c2, nm, true);
                assert_relative_eq!(a, b, max_relative = 1e-10);
                assert!((0.0..=1.0).contains(&a));
            }
        }
    }
}
