//! Where Newton's iteration on an asphere starts: the root of a conic near
//! the surface where the ray meets it.
//!
//! A strong asphere (a camera lens's: an r^4 term that moves the surface
//! tenths of a millimetre from its base conic at the rim; a phone lens's
//! odd and even terms to r^10) is too far from that conic for one Newton
//! step from its root to end within the tolerance, and every ray takes two
//! or more. Instead the clear aperture is cut into [`ZONES`] rings of equal
//! steps in s = r^2 ([`FINE_ZONES`] where too many of those fit poorly:
//! [`FINE_FROM_RINGS`]), and each ring gets the conic (with its vertex moved
//! along the axis) that osculates the surface, as a function of s, at the
//! ring's middle: same sag, dz/ds and d2z/ds2 (or, where that conic does
//! not exist or fits worse, the paraboloid tangent to the surface there: a
//! sag linear in s). A ray starts from the root of the conic of the ring
//! where it crosses the vertex plane; over the ring, its neighbours and the
//! ray's drift from the plane to the surface a camera asphere's conic is
//! within about 1e-5 mm of the surface (its error is the third
//! derivative's), and one third-order step ends the iteration
//! (docs/architecture.md, Aspheres).
//!
//! A ring's conic is a row of a small table (`[c, k c, z0, 0]`), read per
//! lane. A ring whose conic is not defined over the ring and its neighbours,
//! or neither within [`FIT_MM`] of the surface there nor ten times nearer
//! it than the surface's own start conic, keeps that start conic, as does
//! every ring of a surface that its start conic already fits within
//! [`ZONES_FROM_MM`]. The start only decides how many steps a ray takes,
//! never where it ends.

use crate::model::surface::Asphere;
use crate::simd::lanes::{Real, RingRows};

/// Rings of the clear aperture, of equal steps in s = r^2.
pub(crate) const ZONES: usize = 32;

/// Rings of a surface that [`ZONES`] rings fit poorly in more than
/// [`FINE_FROM_RINGS`] of them (a phone lens's wavy tenth-order surfaces):
/// rays start nearer the surface, and more end in one pass instead of two.
pub(crate) const FINE_ZONES: usize = 128;

/// A surface more than this many of whose [`ZONES`] rings' conics (or,
/// where a ring keeps it, its start conic) miss it by more than [`FIT_MM`]
/// over the ring and its neighbours gets [`FINE_ZONES`] rings instead: a
/// ray in such a ring takes a second step, and with it its vector (a
/// phone lens's surfaces have three to twenty such rings; a camera
/// asphere's none to two, at the rim, and the finer rings' look-up would
/// cost it more than they save).
pub const FINE_FROM_RINGS: usize = ZONES / 8;

/// A surface whose start conic is within this of it (mm, over the clear
/// aperture) starts its rays from that conic: one step from there ends the
/// iteration already.
pub const ZONES_FROM_MM: f64 = 1e-4;

/// A ring's conic must be within this of the surface (mm) over the ring and
/// its two neighbours, or ten times nearer it than the surface's start
/// conic, or the ring's rays start from that start conic.
pub const FIT_MM: f64 = 1e-4;

/// The rings' conics: row `i` is `[c, k c, z0, 0]` of ring `i`'s conic
/// `c s - 2 w + (1 + k) c w^2 = 0` in `w = z - z0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Zones {
    /// The rings: [`ZONES`] or [`FINE_ZONES`]; the tables' rows past them
    /// are unused.
    count: usize,
    /// `count / sd^2`, 1/mm^2: s times this is a ray's ring (truncated).
    per_s: f64,
    rows: [[f64; 4]; FINE_ZONES],
    /// The rows' first three numbers rounded to f32, by columns
    /// (`cols32[k][i] = rows[i][k]`): what the start reads (it is computed
    /// in f32: `trace/asphere.rs`).
    cols32: [[f32; FINE_ZONES]; 3],
}

/// An asphere's sag and its first two derivatives in s = r^2.
struct Sag<'a> {
    c: f64,
    k1: f64,
    asphere: &'a Asphere,
}

impl Sag<'_> {
    /// `(z, dz/ds, d2z/ds2)` at `s`, `None` outside the conic's domain (the
    /// sag itself is the surface's, [`Asphere::sag`]).
    fn at(&self, s: f64) -> Option<[f64; 3]> {
        let q = 1.0 - self.k1 * self.c * self.c * s;
        if q.is_nan() || q <= 0.0 {
            return None;
        }
        let m = q.sqrt();
        let r = s.sqrt();
        let z = self.asphere.sag(self.c, r)?;
        let mut z1 = self.c / (2.0 * m);
        let mut z2 = self.k1 * self.c.powi(3) / (4.0 * m * m * m);
        // the term a r^j = a s^(j / 2): its derivatives in s by integer
        // powers of r (an odd power's are infinite at s = 0: no conic there)
        for (i, a) in self.asphere.coefficients.iter().enumerate() {
            if *a == 0.0 {
                continue;
            }
            let j = i as i32 + 1;
            let e = f64::from(j) / 2.0;
            if j == 2 {
                // an r^2 term: no second derivative
                z1 += a;
            } else {
                z1 += a * e * r.powi(j - 2);
                z2 += a * e * (e - 1.0) * r.powi(j - 4);
            }
        }
        Some([z, z1, z2]).filter(|v| v.iter().all(|x| x.is_finite()))
    }
}

/// The sag at `s` of the conic of curvature `c` and `k c` = `kc` with its
/// vertex at `z0`, `None` outside its domain (with a margin: `1 - (1 + k)
/// c^2 s >= 0.01`).
fn conic_sag(c: f64, kc: f64, z0: f64, s: f64) -> Option<f64> {
    let q = 1.0 - (kc + c) * c * s;
    (q >= 0.01).then(|| z0 + c * s / (1.0 + q.sqrt()))
}

/// The conic `(c, k c, z0)` that osculates, at `s`, a sag whose value and
/// derivatives in s there are `[z, z1, z2]`; `None` where none does (a
/// sag flat in s there, or one whose osculating conic ends at `s`).
///
/// With `rho = (1 + k) c^2` and `m = sqrt(1 - rho s)`, the conic has
/// `dz/ds = c / (2 m)` and `d2z/ds2 = (1 + k) c^3 / (4 m^3)`, so that
/// `rho = 2 z2 / (z1 + 2 s z2)`, `c = 2 z1 m`, and `z0` puts its sag at `z`.
fn osculating([z, z1, z2]: [f64; 3], s: f64) -> Option<[f64; 3]> {
    let rho = 2.0 * z2 / (z1 + 2.0 * s * z2);
    let q = 1.0 - rho * s;
    if q.is_nan() || q <= 0.0 || !rho.is_finite() || z1 == 0.0 {
        return None;
    }
    let m = q.sqrt();
    let c = 2.0 * z1 * m;
    let kc = rho / c - c;
    let z0 = z - c * s / (1.0 + m);
    [c, kc, z0].iter().all(|v| v.is_finite()).then_some([c, kc, z0])
}

impl Zones {
    /// The rings whose rays start from a conic of their own (the others
    /// from the surface's start conic, whose vertex is not shifted).
    #[cfg(test)]
    pub(crate) fn own_conics(&self) -> usize {
        self.rows[..self.count].iter().filter(|r| r[2] != 0.0).count()
    }

    /// How many rings.
    #[cfg(test)]
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// The rings of the asphere `asphere` on a base of curvature `c` with
    /// clear radius squared `sd2` (mm^2), whose rays would otherwise start
    /// from the conic of conic constant `start_k` (no vertex shift); `None`
    /// where that conic fits within [`ZONES_FROM_MM`], where no ring has a
    /// conic that holds (module docs) or the aperture is unbounded.
    pub(crate) fn of(c: f64, asphere: &Asphere, sd2: f64, start_k: f64) -> Option<Zones> {
        if asphere.degree() == 0 || !(sd2 > 0.0 && sd2.is_finite()) {
            return None;
        }
        let sag = Sag { c, k1: 1.0 + asphere.conic, asphere };
        let start = [c, start_k * c, 0.0, 0.0];
        let far = (0..=64).map(|i| sd2 * i as f64 / 64.0).any(|s| match (sag.at(s), conic_sag(c, start[1], 0.0, s)) {
            (Some([z, ..]), Some(zc)) => (z - zc).abs() > ZONES_FROM_MM,
            _ => true,
        });
        if !far {
            return None;
        }
        let (zones, any, poor) = Self::rings(&sag, start, sd2, ZONES);
        if poor <= FINE_FROM_RINGS {
            return any.then_some(zones);
        }
        let (fine, fine_any, _) = Self::rings(&sag, start, sd2, FINE_ZONES);
        if fine_any {
            Some(fine)
        } else {
            any.then_some(zones)
        }
    }

    /// `count` rings of the surface `sag` over the clear radius squared
    /// `sd2`, each with its conic or the start conic `start` ([`Self::of`]),
    /// whether any has a conic of its own, and how many rings' conics lie
    /// farther than [`FIT_MM`] from the surface over the ring and its
    /// neighbours.
    fn rings(sag: &Sag, start: [f64; 4], sd2: f64, count: usize) -> (Zones, bool, usize) {
        let width = sd2 / count as f64;
        let mut zones = Zones { count, per_s: 1.0 / width, rows: [start; FINE_ZONES], cols32: [[0.0; FINE_ZONES]; 3] };
        let (mut any, mut poor) = (false, 0);
        for (i, row) in zones.rows[..count].iter_mut().enumerate() {
            let s = (i as f64 + 0.5) * width;
            // the ring and its neighbours
            let (lo, hi) = ((i as f64 - 1.0).max(0.0) * width, ((i + 2) as f64 * width).min(sd2));
            let worst = |[c, kc, z0]: [f64; 3]| {
                (0..=8).map(|j| lo + (hi - lo) * j as f64 / 8.0).try_fold(0.0f64, |w, s| {
                    match (sag.at(s), conic_sag(c, kc, z0, s)) {
                        (Some([z, ..]), Some(zc)) => Some(w.max((z - zc).abs())),
                        _ => None,
                    }
                })
            };
            let own = worst([start[0], start[1], 0.0]).unwrap_or(f64::INFINITY);
            // the osculating conic, or the tangent paraboloid (a sag linear
            // in s, defined everywhere), whichever fits better
            let best = sag.at(s).and_then(|at| {
                let tangent = [2.0 * at[1], -2.0 * at[1], at[0] - at[1] * s];
                [osculating(at, s), Some(tangent)]
                    .into_iter()
                    .flatten()
                    .filter_map(|k| worst(k).map(|w| (k, w)))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
            });
            let mut fit = own;
            if let Some(([ci, kci, z0], w)) = best {
                if w <= FIT_MM || w < 0.1 * own {
                    *row = [ci, kci, z0, 0.0];
                    any = true;
                    fit = w;
                }
            }
            // NaN (no fit) counts as poor
            poor += usize::from(fit.is_nan() || fit > FIT_MM);
        }
        for (i, row) in zones.rows.iter().enumerate() {
            for (col, v) in zones.cols32.iter_mut().zip(row) {
                col[i] = *v as f32;
            }
        }
        (zones, any, poor)
    }

    /// The conic `(c, k c, z0)` of each lane's ray `p + u d` (the surface's
    /// frame): that of the ring where the ray crosses the vertex plane, the
    /// crossing found with `1 / dz` to first order in `dx^2 + dy^2` (no
    /// division; a steep ray's error only moves it towards a neighbouring
    /// ring, whose conic fits there too); a ray crossing past the aperture,
    /// or parallel to the plane, takes the outermost ring.
    #[inline(always)]
    pub(crate) fn of_ray<L: RingRows>(&self, p: [L; 3], d: [L; 3]) -> (L, L, L) {
        self.of_ring(self.ring(p, d))
    }

    /// The ring of the ray `p + u d`, as a number whose integer part it is
    /// (the first part of [`Self::of_ray`]).
    #[inline(always)]
    pub(crate) fn ring<L: Real>(&self, p: [L; 3], d: [L; 3]) -> L {
        let rho2 = d[0].fma(d[0], d[1] * d[1]);
        // 1 / sqrt(1 - rho2) = 1 + rho2 / 2 + 3 rho2^2 / 8 + ...: the first
        // two terms (at 25 deg off the axis the crossing moves by 1.2% of
        // the ray's distance from the plane, a fraction of a ring)
        let inv_dz = rho2.fma(L::splat(0.5), L::splat(1.0));
        let t = p[2] * inv_dz;
        let x = (-t).fma(d[0], p[0]);
        let y = (-t).fma(d[1], p[1]);
        x.fma(x, y * y) * L::splat(self.per_s)
    }

    /// The conic `(c, k c, z0)` of the ring [`Self::ring`] gave.
    #[inline(always)]
    pub(crate) fn of_ring<L: RingRows>(&self, ring: L) -> (L, L, L) {
        let [c, kc, z0] = if self.count == ZONES {
            let [a, b, c] = &self.cols32;
            L::rows32([first(a), first(b), first(c)], ring)
        } else {
            let [a, b, c] = &self.cols32;
            L::rows128([a, b, c], ring)
        };
        (c, kc, z0)
    }
}

/// The first [`ZONES`] numbers of a column. A function, not a closure (one
/// not inlined runs outside the batch's target features).
#[inline(always)]
fn first(col: &[f32; FINE_ZONES]) -> &[f32; ZONES] {
    col.first_chunk().expect("ZONES of FINE_ZONES")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A conic with a vertex shift is its own osculating conic everywhere;
    /// every ring of the 35 mm f/2's asphere (an r^4 term moving it 0.3 mm
    /// from its base sphere at the rim) has its own conic, within 1e-6 mm
    /// of the surface over the ring; a mild asphere keeps its start conic.
    #[test]
    fn rings_osculate_the_surface() {
        let conic = Asphere::new(-0.7, &[], &[]).unwrap();
        let sag = Sag { c: 1.0 / 40.0, k1: 0.3, asphere: &conic };
        for s in [1.0, 50.0, 300.0] {
            let [c, kc, z0] = osculating(sag.at(s).unwrap(), s).unwrap();
            assert!((c - 1.0 / 40.0).abs() < 1e-12 && (kc + 0.7 / 40.0).abs() < 1e-12 && z0.abs() < 1e-12);
        }
        let canon = Asphere::new(0.0, &[0.0, -1.49529e-05, 4.91763e-09, -4.11063e-11], &[]).unwrap();
        let c = 1.0 / -91.82;
        let sd2 = 11.9f64 * 11.9;
        let z = Zones::of(c, &canon, sd2, 0.0).expect("the asphere is far from its sphere");
        let sag = Sag { c, k1: 1.0, asphere: &canon };
        let w = sd2 / ZONES as f64;
        for (i, [ci, kci, z0, _]) in z.rows[..z.count].iter().enumerate() {
            assert!(*z0 != 0.0, "ring {i} has its own conic");
            for j in 0..=8 {
                let s = (i as f64 + j as f64 / 8.0) * w;
                let zc = conic_sag(*ci, *kci, *z0, s).unwrap();
                assert!((zc - sag.at(s).unwrap()[0]).abs() < 1e-6, "ring {i} at s {s}");
            }
        }
        let mild = Asphere::new(-0.01, &[0.0, 1e-9, 1e-13], &[]).unwrap();
        assert!(Zones::of(1.0 / 29.475, &mild, 12.6 * 12.6, -0.01).is_none());
    }
}
