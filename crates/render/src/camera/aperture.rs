//! Aperture shapes: where on a unit aperture a sample lands.

use crate::scene::format::ApertureSpec;
use std::path::PathBuf;
use std::sync::Arc;

/// The most blades a polygonal aperture may have (the work per ray grows
/// with them).
pub const MAX_BLADES: u32 = 64;

/// Why an aperture shape could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ApertureError {
    /// A polygon with fewer than three blades or more than [`MAX_BLADES`].
    #[error("blades = {blades}: a polygon needs 3 to {MAX_BLADES} blades (irises have 5 to 20)")]
    Blades {
        /// Blades given.
        blades: u32,
    },
    /// A rotation that is not a finite angle.
    #[error("rotation_deg must be a finite angle in degrees")]
    Rotation,
    /// A mask that transmits nothing.
    #[error("the aperture mask transmits nothing: give an image with some white")]
    Opaque,
    /// A mask image that cannot be read.
    #[error("{}: cannot read the mask: {message}", path.display())]
    Read {
        /// The image.
        path: PathBuf,
        /// The decoder's message.
        message: String,
    },
}

/// A grey-scale transmission image over [-1, 1]^2, sampled in proportion to
/// its transmission.
#[derive(Debug, Clone, PartialEq)]
pub struct Mask {
    width: usize,
    height: usize,
    /// Transmission in [0, 1], row-major from the top.
    values: Vec<f64>,
    /// Cumulative transmission, for sampling a pixel.
    cdf: Vec<f64>,
}

impl Mask {
    /// From transmission values (row-major from the top). Errors when the
    /// image transmits nothing.
    pub fn new(width: usize, height: usize, values: Vec<f64>) -> Result<Self, ApertureError> {
        let mut cdf = Vec::with_capacity(values.len());
        let mut acc = 0.0;
        for v in &values {
            acc += v.clamp(0.0, 1.0);
            cdf.push(acc);
        }
        if width == 0 || height == 0 || acc <= 0.0 {
            return Err(ApertureError::Opaque);
        }
        Ok(Mask { width, height, values, cdf })
    }

    /// Transmission at (x, y) in [-1, 1]^2 (+y up).
    pub fn at(&self, x: f64, y: f64) -> f64 {
        if !(-1.0..1.0).contains(&x) || !(-1.0..1.0).contains(&y) {
            return 0.0;
        }
        let i = (((x + 1.0) / 2.0) * self.width as f64) as usize;
        let j = (((1.0 - y) / 2.0) * self.height as f64) as usize;
        self.values[j.min(self.height - 1) * self.width + i.min(self.width - 1)].clamp(0.0, 1.0)
    }

    /// A point with density proportional to the transmission.
    pub fn sample(&self, u: (f64, f64)) -> (f64, f64) {
        let total = *self.cdf.last().unwrap_or(&1.0);
        let target = u.0 * total;
        let k = self.cdf.partition_point(|c| *c <= target).min(self.cdf.len() - 1);
        let below = if k == 0 { 0.0 } else { self.cdf[k - 1] };
        let width = (self.cdf[k] - below).max(f64::MIN_POSITIVE);
        let fx = ((target - below) / width).clamp(0.0, 1.0);
        let (i, j) = (k % self.width, k / self.width);
        let x = -1.0 + 2.0 * (i as f64 + fx) / self.width as f64;
        let y = 1.0 - 2.0 * (j as f64 + u.1) / self.height as f64;
        (x, y)
    }
}

/// A shape inscribed in the unit circle (or, for a mask, its square).
#[derive(Debug, Clone, PartialEq)]
pub enum Aperture {
    /// The unit disc.
    Circle,
    /// A regular polygon with `blades` corners on the unit circle, rotated.
    Polygon {
        /// Corners.
        blades: u32,
        /// Rotation, radians.
        rotation: f64,
    },
    /// A grey-scale transmission image.
    Mask(Box<Mask>),
}

impl Aperture {
    /// From the scene spec; errors name the field. Mask images are read
    /// relative to `dir`.
    pub fn from_spec(s: &ApertureSpec, dir: &std::path::Path) -> Result<Self, ApertureError> {
        Ok(match *s {
            ApertureSpec::Mask { ref image } => Aperture::Mask(Box::new(load_mask(&dir.join(image))?)),
            ApertureSpec::Circle => Aperture::Circle,
            ApertureSpec::Polygon { blades, rotation_deg } => {
                if !(3..=MAX_BLADES).contains(&blades) {
                    return Err(ApertureError::Blades { blades });
                }
                if !rotation_deg.is_finite() {
                    return Err(ApertureError::Rotation);
                }
                Aperture::Polygon { blades, rotation: rotation_deg.to_radians() }
            }
        })
    }

    /// A point uniform over the shape (unit scale) from two uniforms.
    pub fn sample(&self, u: (f64, f64)) -> (f64, f64) {
        match *self {
            Aperture::Circle => concentric(u),
            Aperture::Polygon { blades, rotation } => {
                // pick a triangle of the fan, then a uniform point in it
                let n = blades as f64;
                let k = (u.0 * n).floor().min(n - 1.0);
                let v = u.0 * n - k; // reuse the remainder as a fresh uniform
                let a0 = rotation + std::f64::consts::TAU * k / n;
                let a1 = rotation + std::f64::consts::TAU * (k + 1.0) / n;
                let (mut s, mut t) = (v, u.1);
                if s + t > 1.0 {
                    s = 1.0 - s;
                    t = 1.0 - t;
                }
                (s * a0.cos() + t * a1.cos(), s * a0.sin() + t * a1.sin())
            }
            Aperture::Mask(ref m) => m.sample(u),
        }
    }

    /// The area of the shape on the unit aperture (π for the disc; a
    /// mask's is its transmission's integral over the square).
    pub fn unit_area(&self) -> f64 {
        match self {
            Aperture::Circle => std::f64::consts::PI,
            Aperture::Polygon { blades, .. } => {
                let n = *blades as f64;
                0.5 * n * (std::f64::consts::TAU / n).sin()
            }
            Aperture::Mask(_) => 4.0,
        }
    }

    /// Whether a point (unit scale) lies inside the shape.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        match *self {
            Aperture::Circle => x * x + y * y <= 1.0,
            Aperture::Polygon { rotation, .. } => {
                let step = self.period();
                // inside every edge's half-plane (at the apothem): the point
                // lies farthest beyond the edge whose normal is nearest its
                // direction, so that edge alone decides
                let k = ((y.atan2(x) - rotation) / step - 0.5).round();
                let (sin, cos) = (rotation + step * (k + 0.5)).sin_cos();
                x * cos + y * sin <= self.inradius()
            }
            Aperture::Mask(ref m) => m.at(x, y) > 0.0,
        }
    }

    /// Transmission at (x, y) (unit scale): 1 inside a circle or polygon,
    /// the grey level of a mask.
    pub fn transmission(&self, x: f64, y: f64) -> f64 {
        match self {
            Aperture::Mask(m) => m.at(x, y),
            _ => {
                if self.contains(x, y) {
                    1.0
                } else {
                    0.0
                }
            }
        }
    }

    /// A point uniform over the region [`Self::proposal_area`] measures: the
    /// shape for a circle or polygon, the mask's square [-1, 1]^2 for a
    /// mask (whose transmission then weights the sample).
    pub fn sample_uniform(&self, u: (f64, f64)) -> (f64, f64) {
        match *self {
            Aperture::Mask(_) => (2.0 * u.0 - 1.0, 2.0 * u.1 - 1.0),
            _ => self.sample(u),
        }
    }

    /// Area of the region [`Self::sample_uniform`] draws from, at unit scale.
    pub fn proposal_area(&self) -> f64 {
        match *self {
            Aperture::Circle => std::f64::consts::PI,
            Aperture::Polygon { blades, .. } => {
                let n = blades as f64;
                0.5 * n * (std::f64::consts::TAU / n).sin()
            }
            Aperture::Mask(_) => 4.0,
        }
    }

    /// The corners of the convex region [`Self::sample_uniform`] draws from,
    /// counter-clockwise, at unit scale: the polygon's, or the mask's
    /// square (a circle has none).
    pub fn outline(&self) -> Vec<(f64, f64)> {
        match *self {
            Aperture::Circle => Vec::new(),
            Aperture::Polygon { blades, rotation } => (0..blades)
                .map(|k| {
                    let a = rotation + std::f64::consts::TAU * k as f64 / blades as f64;
                    (a.cos(), a.sin())
                })
                .collect(),
            Aperture::Mask(_) => vec![(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)],
        }
    }

    /// The turn that maps the shape onto itself, radians: 2 pi / blades for
    /// a polygon, a whole turn for a mask.
    pub fn period(&self) -> f64 {
        match *self {
            Aperture::Polygon { blades, .. } => std::f64::consts::TAU / blades as f64,
            _ => std::f64::consts::TAU,
        }
    }

    /// Radius of the largest circle about the centre inside that region
    /// (the polygon's apothem; 1 for the circle and the mask's square).
    pub fn inradius(&self) -> f64 {
        match *self {
            Aperture::Polygon { blades, .. } => (std::f64::consts::PI / blades as f64).cos(),
            _ => 1.0,
        }
    }

    /// The shape's transmission at a point (x, y) mm of a stop of clear
    /// radius `radius` mm (the shape scaled by it), as one function for
    /// many points: a polygon's edges' half-planes worked out once, so
    /// that a point costs one product and comparison per blade and no
    /// trigonometry. `None` for the circle, which the stop's clear
    /// aperture is already.
    pub fn scaled(&self, radius: f64) -> Option<Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>> {
        match self {
            Aperture::Circle => None,
            Aperture::Polygon { blades, rotation } => {
                let n = f64::from(*blades);
                let edges: Vec<(f64, f64)> = (0..*blades)
                    .map(|k| (rotation + std::f64::consts::TAU * (f64::from(k) + 0.5) / n).sin_cos())
                    .map(|(sin, cos)| (cos, sin))
                    .collect();
                let apothem = self.inradius() * radius;
                Some(Arc::new(move |x: f64, y: f64| {
                    f64::from(u8::from(edges.iter().all(|&(c, s)| x * c + y * s <= apothem)))
                }))
            }
            Aperture::Mask(m) => {
                let m = m.clone();
                Some(Arc::new(move |x: f64, y: f64| m.at(x / radius, y / radius)))
            }
        }
    }
}

/// Shirley–Chiu concentric map of the unit square onto the unit disc.
pub fn concentric(u: (f64, f64)) -> (f64, f64) {
    let (a, b) = (2.0 * u.0 - 1.0, 2.0 * u.1 - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, std::f64::consts::FRAC_PI_4 * (b / a))
    } else {
        (b, std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_4 * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}

/// The PNG decoder's message with its debug dump of a chunk type
/// (`ChunkType { type: ageg, critical: false, ... }`) written as the chunk's
/// name (`"ageg"`): what a user can act on.
#[cfg(feature = "png")]
fn plain_decoder_message(m: &str) -> String {
    const DUMP: &str = "ChunkType { type: ";
    let Some(start) = m.find(DUMP) else { return m.to_string() };
    let rest = &m[start + DUMP.len()..];
    let name: String = rest.chars().take_while(|c| c.is_ascii_alphanumeric()).collect();
    let end = rest.find('}').map_or(m.len(), |e| start + DUMP.len() + e + 1);
    format!("{}\"{name}\"{}", &m[..start], &m[end..])
}

/// Reads a grey-scale PNG mask (needs the `png` feature).
#[cfg(feature = "png")]
fn load_mask(path: &std::path::Path) -> Result<Mask, ApertureError> {
    let read = |message: String| ApertureError::Read { path: path.to_path_buf(), message };
    let img = image::open(path).map_err(|e| read(plain_decoder_message(&e.to_string())))?.to_luma8();
    let (w, h) = (img.width() as usize, img.height() as usize);
    let values = img.pixels().map(|p| p.0[0] as f64 / 255.0).collect();
    Mask::new(w, h, values)
}

#[cfg(not(feature = "png"))]
fn load_mask(path: &std::path::Path) -> Result<Mask, ApertureError> {
    Err(ApertureError::Read {
        path: path.to_path_buf(),
        message: "aperture masks need the render crate's `png` feature".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) from a linear congruential generator
    /// seeded with `seed`: the same sequence on every run.
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A polygon holds a point exactly when the point lies inside every
    /// edge's half-plane, the edge nearest its direction deciding.
    #[test]
    fn polygon_holds_what_every_edge_does() {
        let mut next = uniform(11);
        for blades in 3..=12u32 {
            for rotation in [0.0, 0.3, -2.0, 7.5] {
                let a = Aperture::Polygon { blades, rotation };
                let n = f64::from(blades);
                let apothem = (std::f64::consts::PI / n).cos();
                let mut both = [0usize; 2];
                for _ in 0..4000 {
                    let (x, y) = (2.4 * next() - 1.2, 2.4 * next() - 1.2);
                    let every = (0..blades).all(|k| {
                        let mid = rotation + std::f64::consts::TAU * (f64::from(k) + 0.5) / n;
                        x * mid.cos() + y * mid.sin() <= apothem
                    });
                    assert_eq!(a.contains(x, y), every, "{blades} blades, rotation {rotation}, ({x}, {y})");
                    both[usize::from(every)] += 1;
                }
                assert!(both[0] > 100 && both[1] > 100, "{both:?}");
            }
            assert!(Aperture::Polygon { blades, rotation: 0.4 }.contains(0.0, 0.0));
        }
    }

    /// The scaled shape's transmission is the shape's at the point over
    /// the radius, for polygons and masks; the circle has none.
    #[test]
    fn scaled_shape_is_the_shape_at_the_scaled_point() {
        let mut next = uniform(5);
        let mask = Mask::new(3, 2, vec![0.0, 0.5, 1.0, 0.25, 1.0, 0.0]).unwrap();
        let shapes = [
            Aperture::Polygon { blades: 6, rotation: 0.17 },
            Aperture::Polygon { blades: 7, rotation: -1.0 },
            Aperture::Polygon { blades: 3, rotation: 0.0 },
            Aperture::Mask(Box::new(mask)),
        ];
        let radius = 6.25;
        for a in &shapes {
            let f = a.scaled(radius).unwrap();
            let mut seen = std::collections::BTreeSet::new();
            for _ in 0..4000 {
                let (x, y) = (radius * (2.4 * next() - 1.2), radius * (2.4 * next() - 1.2));
                let want = a.transmission(x / radius, y / radius);
                assert_eq!(f(x, y), want, "{a:?} at ({x}, {y})");
                seen.insert(want.to_bits());
            }
            assert!(seen.len() >= 2, "{a:?}: {seen:?}");
        }
        assert!(Aperture::Circle.scaled(radius).is_none());
    }
}
