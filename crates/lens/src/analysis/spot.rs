//! Spot diagrams: where a pupil pattern of rays lands on an image plane, its
//! RMS and geometric radii (weighted by each point's share of the pupil),
//! and the focus shift of least RMS spot. Rays go through the batch tracer
//! in chunks, so a 50-million-ray spot never holds more than a chunk of
//! rays at once.

use super::bundle::{launch, Bundle};
use super::fan::ImagePlane;
use super::launch::{Aim, Field, Launcher};
use super::pattern::{for_each, Pattern};
use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::imaging;
use crate::trace::{RayBatch, Tracer};
use rayon::prelude::*;
use serde::Serialize;

/// Most rays a spot diagram traces (a bound on memory, not on accuracy).
pub const MAX_RAYS: usize = 50_000_000;

/// A spot diagram at one field. Lengths in mm, on the image plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpotDiagram {
    /// Field angle (y), degrees, or `None` for a finite object.
    pub field_deg: Option<f64>,
    /// The field's x angle, degrees, for a field with an x component at
    /// infinity ([`Field::Angles`]); `None` (and not written) otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field_x_deg: Option<f64>,
    /// Which plane the spot is on: `"image_surface"` (the prescription's
    /// own, its last thickness), `"paraxial"` or `"film"` (a distance given).
    pub image_plane: &'static str,
    /// z of the image plane, mm from the first vertex.
    pub image_z: f64,
    /// Rays that reached the image plane.
    pub rays: usize,
    /// Rays blocked by a clear aperture (left out of the statistics),
    /// including those of `aim_failures`.
    pub vignetted: usize,
    /// Rays real aiming could not place on the stop (no real ray reaches that
    /// stop point); left out like vignetted rays.
    pub aim_failures: usize,
    /// Mean position of the rays.
    pub centroid: [f64; 2],
    /// RMS distance from the centroid.
    pub rms_radius: f64,
    /// RMS distance from the chief ray.
    pub rms_radius_chief: f64,
    /// Largest distance from the centroid.
    pub geo_radius: f64,
    /// Largest distance from the chief ray.
    pub geo_radius_chief: f64,
    /// Chief ray position.
    pub chief: [f64; 2],
    /// Airy disk radius 1.22 lambda N_w (lambda the traced wavelength,
    /// paraxial working f-number of the primary wavelength), for scale.
    pub airy_radius: f64,
    /// Axial shift of the plane (mm, + toward the image) that minimises the
    /// RMS radius about the centroid, and that radius.
    pub best_focus_shift: f64,
    /// RMS radius about the centroid at the best focus shift.
    pub rms_radius_best_focus: f64,
    /// Every ray that reached the plane: x, y, dx/dz, dy/dz.
    #[serde(skip)]
    pub hits: Vec<[f64; 4]>,
    /// Each hit's share of the pupil (the pattern's weight).
    #[serde(skip)]
    pub weights: Vec<f64>,
    /// The design's vignetting factors the pattern was launched with (the
    /// nearest design field's), where it has any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vignetting_factors: Option<crate::model::VignettingFactors>,
    /// The wavelengths traced, nm (one for a monochromatic spot).
    pub wavelengths_nm: Vec<f64>,
    /// Each wavelength's weight (its rays' pupil weights are multiplied by
    /// it over the sum of the weights).
    pub wavelength_weights: Vec<f64>,
    /// How many of `hits` (in order) each wavelength gave.
    #[serde(skip)]
    pub hits_per_wavelength: Vec<usize>,
}

impl SpotDiagram {
    /// The geometric encircled energy: the share of the rays' pupil weight
    /// landing within each radius of `radii_mm` of the centroid.
    pub fn encircled_energy(&self, radii_mm: &[f64]) -> Vec<f64> {
        let total: f64 = self.weights.iter().sum();
        let mut d: Vec<(f64, f64)> = self
            .hits
            .iter()
            .zip(&self.weights)
            .map(|(h, w)| ((h[0] - self.centroid[0]).hypot(h[1] - self.centroid[1]), *w))
            .collect();
        d.sort_by(|a, b| a.0.total_cmp(&b.0));
        radii_mm
            .iter()
            .map(|&r| {
                let n = d.partition_point(|x| x.0 <= r);
                if total > 0.0 {
                    d[..n].iter().map(|x| x.1).sum::<f64>() / total
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// RMS radius about the centroid on a plane shifted by `dz` mm (+ toward
    /// the image): exact, since every ray is a straight line there.
    pub fn rms_at_shift(&self, dz: f64) -> f64 {
        let (pp, ps, ss) = self.moments();
        (pp + 2.0 * dz * ps + dz * dz * ss).max(0.0).sqrt()
    }

    /// Weighted mean of |p'|^2, p'.s' and |s'|^2 with p', s' the positions
    /// and slopes about their means.
    fn moments(&self) -> (f64, f64, f64) {
        let n = self.total_weight();
        let mean = |k: usize| self.hits.iter().zip(&self.weights).map(|(h, w)| w * h[k]).sum::<f64>() / n;
        let (mx, my, msx, msy) = (mean(0), mean(1), mean(2), mean(3));
        let (mut pp, mut ps, mut ss) = (0.0, 0.0, 0.0);
        for (h, w) in self.hits.iter().zip(&self.weights) {
            let (px, py, sx, sy) = (h[0] - mx, h[1] - my, h[2] - msx, h[3] - msy);
            pp += w * (px * px + py * py);
            ps += w * (px * sx + py * sy);
            ss += w * (sx * sx + sy * sy);
        }
        (pp / n, ps / n, ss / n)
    }

    fn total_weight(&self) -> f64 {
        self.weights.iter().sum::<f64>().max(f64::MIN_POSITIVE)
    }
}

/// Rays launched and traced per batch: large enough for the batch tracer's
/// speed, small enough that the batch stays in the caches.
const BATCH: usize = 16_384;

/// Chunks traced together, one per thread at a time.
const GROUP: usize = 8 * BATCH;

/// What one chunk of pupil points gave.
struct Traced {
    hits: Vec<[f64; 4]>,
    weights: Vec<f64>,
    vignetted: usize,
    aim_failures: usize,
}

/// Launches and traces one chunk of weighted pupil points.
fn trace_chunk(launcher: &Launcher, tracer: &Tracer, chunk: &[(f64, f64, f64)]) -> Result<Traced, OpticsError> {
    let mut batch = RayBatch::with_capacity(chunk.len());
    let aim_failures = launch(launcher, chunk.iter().map(|c| (c.0, c.1)), &mut batch)?;
    tracer.trace_soa(&mut batch);
    let mut t = Traced { hits: Vec::with_capacity(chunk.len()), weights: Vec::new(), vignetted: 0, aim_failures };
    t.weights.reserve(chunk.len());
    for (i, c) in chunk.iter().enumerate() {
        let dz = batch.dz[i];
        if batch.status[i] == 0 && dz != 0.0 {
            t.hits.push([batch.x[i], batch.y[i], batch.dx[i] / dz, batch.dy[i] / dz]);
            t.weights.push(c.2);
        } else {
            t.vignetted += 1;
        }
    }
    Ok(t)
}

/// Traces `pattern` (size `n`) at `field` to `plane` and measures the spot.
/// Errors when the chief ray is lost or every ray is vignetted.
pub fn spot_diagram(
    p: &Prescription,
    field: Field,
    pattern: Pattern,
    n: usize,
    aim: Aim,
    plane: ImagePlane,
) -> Result<SpotDiagram, OpticsError> {
    let launcher = Launcher::new(p, field, aim)?;
    spot_with(p, &launcher, pattern, n, plane)
}

/// [`spot_diagram`] with a launcher already made (first-order data computed
/// once by the caller).
pub fn spot_with(
    p: &Prescription,
    launcher: &Launcher,
    pattern: Pattern,
    n: usize,
    plane: ImagePlane,
) -> Result<SpotDiagram, OpticsError> {
    spot_traced(p, p, launcher, pattern, n, plane)
}

/// [`spot_with`] with the rays traced through `traced` (the same system at
/// another wavelength) while the launcher, the image plane and the Airy
/// radius's working f-number are those of `p` (the primary wavelength).
pub fn spot_traced(
    p: &Prescription,
    traced: &Prescription,
    launcher: &Launcher,
    pattern: Pattern,
    n: usize,
    plane: ImagePlane,
) -> Result<SpotDiagram, OpticsError> {
    let field = launcher.field();
    if pattern.count(n) > MAX_RAYS as f64 {
        return Err(OpticsError::BadInput {
            name: "pattern size n",
            value: n as f64,
            expected: "a pattern of at most 50 million rays (gauss n <= 3535, square n <= 7071, hexapolar n <= 4081)",
        });
    }
    if pattern.count(n) < 1.0 {
        return Err(OpticsError::BadInput { name: "pattern size n", value: n as f64, expected: "at least 1" });
    }
    let image_z = plane.z(p, launcher)?;
    let tracer = Tracer::forward_to_film(traced, image_z - p.last_vertex_z());
    let chief = chief_on(launcher, &tracer)?;
    let mut hits = Vec::new();
    let mut weights = Vec::new();
    let (mut vignetted, mut aim_failures) = (0, 0);
    // points gathered a group at a time, the group's chunks launched and
    // traced on all cores, their hits appended in pattern order (so the
    // result does not depend on the number of threads)
    let mut group: Vec<(f64, f64, f64)> = Vec::with_capacity(GROUP);
    let mut flush = |group: &mut Vec<(f64, f64, f64)>| -> Result<(), OpticsError> {
        let parts: Vec<Result<Traced, OpticsError>> =
            group.par_chunks(BATCH).map(|chunk| trace_chunk(launcher, &tracer, chunk)).collect();
        for part in parts {
            let t = part?;
            hits.extend(t.hits);
            weights.extend(t.weights);
            vignetted += t.vignetted;
            aim_failures += t.aim_failures;
        }
        group.clear();
        Ok(())
    };
    let mut error = Ok(());
    // the design's vignetting factors at this field: the pattern fills the
    // pupil that passes (the chief ray stays)
    let vig = launcher.vignetting(p)?;
    for_each(pattern, n, |x, y, w| {
        let (x, y) = vig.apply(x, y);
        group.push((x, y, w));
        if group.len() == GROUP && error.is_ok() {
            error = flush(&mut group);
        }
    });
    error?;
    flush(&mut group)?;
    if hits.is_empty() {
        return Err(OpticsError::NoRealRays {
            why: format!("all {vignetted} rays of the pupil pattern are vignetted at {}", field.describe()),
        });
    }
    let wavelengths = Wavelengths { nm: vec![traced.wavelength_nm()], weights: vec![1.0], hits: vec![hits.len()] };
    let counts = (vignetted, aim_failures);
    assemble(p, launcher, plane, image_z, (hits, weights, chief), counts, wavelengths, traced.wavelength_nm(), vig)
}

/// The wavelengths a spot traced: each one's weight and how many hits
/// (in order) it gave.
struct Wavelengths {
    nm: Vec<f64>,
    weights: Vec<f64>,
    hits: Vec<usize>,
}

/// A spot diagram from its weighted hits and the chief ray's point: the
/// statistics, the Airy radius at `airy_nm` (the working f-number of `p`
/// at the launcher's field) and the through-focus optimum.
#[allow(clippy::too_many_arguments)]
fn assemble(
    p: &Prescription,
    launcher: &Launcher,
    plane: ImagePlane,
    image_z: f64,
    (hits, weights, chief): (Vec<[f64; 4]>, Vec<f64>, [f64; 2]),
    (vignetted, aim_failures): (usize, usize),
    wavelengths: Wavelengths,
    airy_nm: f64,
    vig: crate::model::VignettingFactors,
) -> Result<SpotDiagram, OpticsError> {
    let field = launcher.field();
    let st = Stats::of(&hits, &weights, chief);
    let wfn = imaging(p, launcher.first_order(), field.object())?.working_f_number;
    let (pp, ps, ss) = st.moments;
    let best_focus_shift = if ss > 0.0 { -ps / ss } else { 0.0 };
    let dz = best_focus_shift;
    let (field_x_deg, field_deg) = field.reported_angles();
    Ok(SpotDiagram {
        field_deg,
        field_x_deg,
        image_plane: plane.name(),
        image_z,
        rays: hits.len(),
        vignetted,
        aim_failures,
        centroid: st.centroid,
        rms_radius: st.rms_radius,
        rms_radius_chief: st.rms_radius_chief,
        geo_radius: st.geo_radius,
        geo_radius_chief: st.geo_radius_chief,
        chief,
        airy_radius: 1.22 * airy_nm * 1e-6 * wfn,
        best_focus_shift,
        rms_radius_best_focus: (pp + 2.0 * dz * ps + dz * dz * ss).max(0.0).sqrt(),
        hits,
        weights,
        vignetting_factors: (!vig.is_none()).then_some(vig),
        wavelengths_nm: wavelengths.nm,
        wavelength_weights: wavelengths.weights,
        hits_per_wavelength: wavelengths.hits,
    })
}

/// Where `launcher`'s chief ray lands through `tracer`.
fn chief_on(launcher: &Launcher, tracer: &Tracer) -> Result<[f64; 2], OpticsError> {
    let ray = Bundle::trace(launcher, tracer, vec![(0.0, 0.0)])?.landings[0].chief(launcher.field())?;
    Ok([ray.origin.x, ray.origin.y])
}

/// The spot of several wavelengths together, as Zemax draws a
/// polychromatic spot: `wavelengths` are (nm, weight) pairs; each
/// wavelength's rays are traced through `p` at that wavelength from the
/// primary wavelength's pupils onto the primary's `plane`, each ray
/// weighted by its share of the pupil times its wavelength's weight over
/// the sum of the weights. The chief ray and the Airy radius are the
/// primary wavelength's. One wavelength of weight 1 gives
/// [`spot_traced`]'s spot.
///
/// ```
/// use lens::analysis::{fan::ImagePlane, pattern::Pattern, spot::spot_polychromatic, Aim, Field, Launcher};
/// let p = lens::Prescription::load("../../lens-data/achromat-fc-100mm.json").unwrap();
/// let l = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
/// let waves: Vec<(f64, f64)> = p.wavelengths_nm().iter().map(|&w| (w, 1.0)).collect();
/// let s = spot_polychromatic(&p, &l, Pattern::Gauss, 8, ImagePlane::Paraxial, &waves).unwrap();
/// assert_eq!(s.wavelengths_nm.len(), 3);
/// assert_eq!(s.hits.len(), s.hits_per_wavelength.iter().sum::<usize>());
/// ```
pub fn spot_polychromatic(
    p: &Prescription,
    launcher: &Launcher,
    pattern: Pattern,
    n: usize,
    plane: ImagePlane,
    wavelengths: &[(f64, f64)],
) -> Result<SpotDiagram, OpticsError> {
    let total: f64 = wavelengths.iter().map(|w| w.1).sum();
    if wavelengths.is_empty() || !wavelengths.iter().all(|w| w.1.is_finite() && w.1 >= 0.0) || total <= 0.0 {
        return Err(OpticsError::BadInput {
            name: "wavelength weights",
            value: total,
            expected: "at least one wavelength, weights finite and >= 0, at least one above 0",
        });
    }
    let image_z = plane.z(p, launcher)?;
    let chief = chief_on(launcher, &Tracer::forward_to_film(p, image_z - p.last_vertex_z()))?;
    let mut spots = Vec::with_capacity(wavelengths.len());
    for &(nm, w) in wavelengths {
        let q = p.at_wavelength(nm)?;
        let s = match spot_traced(p, &q, launcher, pattern, n, plane) {
            Ok(s) => s,
            // a wavelength of no weight that is all vignetted takes no part
            Err(_) if w == 0.0 => continue,
            Err(e) => return Err(e),
        };
        spots.push((nm, w, s));
    }
    let mut hits = Vec::new();
    let mut weights = Vec::new();
    let (mut vignetted, mut aim_failures, mut per) = (0, 0, Vec::new());
    for (_, w, s) in &spots {
        hits.extend_from_slice(&s.hits);
        weights.extend(s.weights.iter().map(|x| x * w / total));
        vignetted += s.vignetted;
        aim_failures += s.aim_failures;
        per.push(s.hits.len());
    }
    let vig = spots.first().and_then(|s| s.2.vignetting_factors).unwrap_or_default();
    let wavelengths = Wavelengths {
        nm: spots.iter().map(|s| s.0).collect(),
        weights: spots.iter().map(|s| s.1).collect(),
        hits: per,
    };
    let counts = (vignetted, aim_failures);
    assemble(p, launcher, plane, image_z, (hits, weights, chief), counts, wavelengths, p.wavelength_nm(), vig)
}

/// The spot's statistics in two passes over the hits (sums, then
/// deviations), each accumulator summed in hit order as its own formula
/// says, so the result is that of a pass per statistic.
struct Stats {
    centroid: [f64; 2],
    rms_radius: f64,
    rms_radius_chief: f64,
    geo_radius: f64,
    geo_radius_chief: f64,
    /// Weighted mean of |p'|^2, p'.s' and |s'|^2 about the means.
    moments: (f64, f64, f64),
}

impl Stats {
    fn of(hits: &[[f64; 4]], weights: &[f64], chief: [f64; 2]) -> Stats {
        let m: f64 = weights.iter().sum();
        let mut s = [-0.0f64; 4];
        for (h, w) in hits.iter().zip(weights) {
            for k in 0..4 {
                s[k] += w * h[k];
            }
        }
        let centroid = [s[0] / m, s[1] / m];
        let n = m.max(f64::MIN_POSITIVE);
        let (mx, my, msx, msy) = (s[0] / n, s[1] / n, s[2] / n, s[3] / n);
        let dist = |h: &[f64; 4], c: [f64; 2]| ((h[0] - c[0]).powi(2) + (h[1] - c[1]).powi(2)).sqrt();
        let (mut r_c, mut r_chief, mut g_c, mut g_chief) = (-0.0f64, -0.0f64, 0.0f64, 0.0f64);
        let (mut pp, mut ps, mut ss) = (0.0, 0.0, 0.0);
        for (h, w) in hits.iter().zip(weights) {
            let (dc, dh) = (dist(h, centroid), dist(h, chief));
            r_c += w * dc.powi(2);
            r_chief += w * dh.powi(2);
            g_c = g_c.max(dc);
            g_chief = g_chief.max(dh);
            let (px, py, sx, sy) = (h[0] - mx, h[1] - my, h[2] - msx, h[3] - msy);
            pp += w * (px * px + py * py);
            ps += w * (px * sx + py * sy);
            ss += w * (sx * sx + sy * sy);
        }
        Stats {
            centroid,
            rms_radius: (r_c / m).sqrt(),
            rms_radius_chief: (r_chief / m).sqrt(),
            geo_radius: g_c,
            geo_radius_chief: g_chief,
            moments: (pp / n, ps / n, ss / n),
        }
    }
}
