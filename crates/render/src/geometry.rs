//! Rays and hits in scene space (metres), and the shapes a scene is made of:
//! spheres, planes, quads (rectangles and box faces) and triangles.

use glam::DVec3;

/// A scene ray: origin and unit direction, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Origin, m.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
}

impl Ray {
    /// Point at distance `t`.
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}

/// Where a ray hit a shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Distance along the ray, m.
    pub t: f64,
    /// Point, m.
    pub p: DVec3,
    /// Unit geometric normal, facing out of the shape.
    pub n: DVec3,
    /// Surface coordinates for textures.
    pub uv: (f64, f64),
}

/// A primitive shape.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// Centre and radius, m.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius.
        radius: f64,
    },
    /// An infinite plane through `point` with unit normal `normal`.
    Plane {
        /// A point on it.
        point: DVec3,
        /// Unit normal (the front side).
        normal: DVec3,
    },
    /// A parallelogram: corner + s u + t v for s, t in [0, 1].
    Quad {
        /// Corner.
        corner: DVec3,
        /// First edge.
        u: DVec3,
        /// Second edge.
        v: DVec3,
    },
    /// A triangle.
    Triangle {
        /// Vertices.
        v: [DVec3; 3],
    },
}

/// Rays start this far (relative to the scene scale) beyond a surface to
/// avoid hitting it again.
pub const EPS: f64 = 1e-7;

impl Shape {
    /// The nearest hit with t in (t_min, t_max).
    pub fn intersect(&self, r: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        match *self {
            Shape::Sphere { center, radius } => {
                // numerically careful: closest approach first
                let oc = r.origin - center;
                let b = oc.dot(r.dir);
                let closest = oc - b * r.dir;
                let disc = radius * radius - closest.length_squared();
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                let q = -b - s.copysign(b);
                let (mut t0, mut t1) = (q, (oc.length_squared() - radius * radius) / q);
                if t0 > t1 {
                    std::mem::swap(&mut t0, &mut t1);
                }
                let t = if t0 > t_min && t0 < t_max {
                    t0
                } else if t1 > t_min && t1 < t_max {
                    t1
                } else {
                    return None;
                };
                let p = r.at(t);
                let n = (p - center) / radius;
                let uv =
                    (0.5 + n.z.atan2(n.x) / std::f64::consts::TAU, n.y.clamp(-1.0, 1.0).acos() / std::f64::consts::PI);
                Some(Hit { t, p, n, uv })
            }
            Shape::Plane { point, normal } => {
                let den = normal.dot(r.dir);
                if den == 0.0 {
                    return None;
                }
                let t = (point - r.origin).dot(normal) / den;
                if !(t > t_min && t < t_max) {
                    return None;
                }
                let p = r.at(t);
                // texture coordinates along two axes in the plane
                let a = if normal.x.abs() < 0.9 { DVec3::X } else { DVec3::Z };
                let e1 = normal.cross(a).normalize();
                let e2 = normal.cross(e1);
                let d = p - point;
                Some(Hit { t, p, n: normal, uv: (d.dot(e1), d.dot(e2)) })
            }
            Shape::Quad { corner, u, v } => {
                let n = u.cross(v);
                let den = n.dot(r.dir);
                if den == 0.0 {
                    return None;
                }
                let t = (corner - r.origin).dot(n) / den;
                if !(t > t_min && t < t_max) {
                    return None;
                }
                let p = r.at(t);
                let d = p - corner;
                let nn = n.length_squared();
                let s = d.cross(v).dot(n) / nn;
                let w = u.cross(d).dot(n) / nn;
                if !((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&w)) {
                    return None;
                }
                Some(Hit { t, p, n: n.normalize(), uv: (s, w) })
            }
            Shape::Triangle { v } => {
                // Moller-Trumbore
                let e1 = v[1] - v[0];
                let e2 = v[2] - v[0];
                let pv = r.dir.cross(e2);
                let det = e1.dot(pv);
                if det == 0.0 {
                    return None;
                }
                let inv = 1.0 / det;
                let tv = r.origin - v[0];
                let a = tv.dot(pv) * inv;
                if !(0.0..=1.0).contains(&a) {
                    return None;
                }
                let qv = tv.cross(e1);
                let b = r.dir.dot(qv) * inv;
                if b < 0.0 || a + b > 1.0 {
                    return None;
                }
                let t = e2.dot(qv) * inv;
                if !(t > t_min && t < t_max) {
                    return None;
                }
                Some(Hit { t, p: r.at(t), n: e1.cross(e2).normalize(), uv: (a, b) })
            }
        }
    }

    /// Axis-aligned bounds (min, max); planes are unbounded.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        match *self {
            Shape::Sphere { center, radius } => (center - DVec3::splat(radius), center + DVec3::splat(radius)),
            Shape::Plane { .. } => (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY)),
            Shape::Quad { corner, u, v } => {
                let pts = [corner, corner + u, corner + v, corner + u + v];
                pts.iter().fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                })
            }
            Shape::Triangle { v } => (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2])),
        }
    }

    /// Surface area, m^2 (infinite for planes).
    pub fn area(&self) -> f64 {
        match *self {
            Shape::Sphere { radius, .. } => 4.0 * std::f64::consts::PI * radius * radius,
            Shape::Plane { .. } => f64::INFINITY,
            Shape::Quad { u, v, .. } => u.cross(v).length(),
            Shape::Triangle { v } => 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length(),
        }
    }
}
