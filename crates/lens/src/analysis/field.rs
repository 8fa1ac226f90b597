//! Fields: where the light comes from (an angle at infinity or an object
//! point, along y or with an x component), checked before any ray is made.

use crate::error::OpticsError;
use crate::model::Prescription;
use crate::paraxial::{FirstOrder, ObjectDistance};

/// Where the light comes from.
///
/// [`Field::Angle`] and [`Field::Height`] are fields along y (the
/// meridional plane of a co-axial lens); [`Field::Angles`] and
/// [`Field::Point`] add an x component (a tilted or decentred lens is not
/// symmetric about the y-z plane). [`Field::angles`] and [`Field::point`]
/// build either, the y-only kind when x is zero, so a y field traces the
/// same bits whichever way it was made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Field {
    /// Object at infinity, light arriving along (0, sin θ, cos θ): the image
    /// lands near y = +EFL tan θ. Degrees, |θ| < 90.
    Angle(f64),
    /// An object point at height `height` mm (+y) on a plane
    /// `object_distance` mm in front of the first vertex.
    Height {
        /// mm in front of the first vertex (> 0).
        object_distance: f64,
        /// Object height, mm.
        height: f64,
    },
    /// Object at infinity, a field in x and y: light arriving along
    /// (tan x, tan y, 1) normalised (the component angles of Zemax and
    /// optiland: `x_deg` is the angle of the ray's projection on the x-z
    /// plane to the axis, `y_deg` on the y-z plane). Degrees, each
    /// strictly between -90 and 90.
    Angles {
        /// Angle in the x-z plane, degrees (+: light travelling toward +x).
        x_deg: f64,
        /// Angle in the y-z plane, degrees (+: light travelling toward +y).
        y_deg: f64,
    },
    /// An object point at (x, y) mm on a plane `object_distance` mm in
    /// front of the first vertex.
    Point {
        /// mm in front of the first vertex (> 0).
        object_distance: f64,
        /// Object x, mm.
        x: f64,
        /// Object y, mm.
        y: f64,
    },
}

impl Field {
    /// The field of component angles `x_deg`, `y_deg` (degrees) at
    /// infinity: [`Field::Angle`] when `x_deg` is 0, [`Field::Angles`]
    /// otherwise.
    pub fn angles(x_deg: f64, y_deg: f64) -> Field {
        if x_deg == 0.0 {
            Field::Angle(y_deg)
        } else {
            Field::Angles { x_deg, y_deg }
        }
    }

    /// The object point (x, y) mm on the plane `object_distance` mm in
    /// front of the first vertex: [`Field::Height`] when `x` is 0,
    /// [`Field::Point`] otherwise.
    pub fn point(object_distance: f64, x: f64, y: f64) -> Field {
        if x == 0.0 {
            Field::Height { object_distance, height: y }
        } else {
            Field::Point { object_distance, x, y }
        }
    }

    /// The field of chief-ray angle `deg` (degrees) for `p` as designed:
    /// [`Field::Angle`] for an object at infinity; for a prescription with
    /// a finite design object distance d (`object_distance_mm`), the object
    /// point whose chief ray makes that angle with the axis, through the
    /// paraxial entrance pupil's centre: height `-(d + z_EP) tan(deg)` on
    /// the plane d mm in front of the first vertex (as Zemax and optiland
    /// take an angle field with a finite object).
    pub fn at_angle(p: &Prescription, first: &FirstOrder, deg: f64) -> Field {
        Field::from_angle(p.object_distance_mm(), first.entrance_pupil.z, deg)
    }

    /// [`Field::at_angle`] for an object `object_distance` mm in front of
    /// the first vertex (`None`: infinity) and the entrance pupil at `z_ep`.
    pub(crate) fn from_angle(object_distance: Option<f64>, z_ep: f64, deg: f64) -> Field {
        Field::from_angles(object_distance, z_ep, 0.0, deg)
    }

    /// [`Field::at_angle`] with an x component: component angles `x_deg`
    /// and `y_deg` (degrees, as [`Field::Angles`]) at infinity, or for a
    /// finite design object the point at `-(d + z_EP) (tan x, tan y)`.
    /// The y-only field of [`Field::at_angle`] when `x_deg` is 0.
    pub fn at_angles(p: &Prescription, first: &FirstOrder, x_deg: f64, y_deg: f64) -> Field {
        Field::from_angles(p.object_distance_mm(), first.entrance_pupil.z, x_deg, y_deg)
    }

    /// [`Field::at_angles`] for an object `object_distance` mm in front of
    /// the first vertex (`None`: infinity) and the entrance pupil at `z_ep`
    /// (the y-only variants when x is 0, through [`Field::point`] and
    /// [`Field::angles`]).
    fn from_angles(object_distance: Option<f64>, z_ep: f64, x_deg: f64, y_deg: f64) -> Field {
        let ok = |a: f64| a.is_finite() && a.abs() < 90.0;
        match object_distance {
            Some(d) if d.is_finite() && d > 0.0 && ok(x_deg) && ok(y_deg) => {
                let s = -(d + z_ep);
                Field::point(d, s * x_deg.to_radians().tan(), s * y_deg.to_radians().tan())
            }
            _ => Field::angles(x_deg, y_deg),
        }
    }

    /// The chief-ray angle of this field in the y-z plane, degrees, the
    /// entrance pupil at `z_ep`: the angle itself, or for an object point
    /// the angle of its chief ray to the paraxial entrance pupil's centre
    /// (the inverse of [`Field::at_angle`]).
    pub fn angle_deg(&self, z_ep: f64) -> f64 {
        self.angles_deg(z_ep)[1]
    }

    /// The chief ray's component angles `[x, y]`, degrees, the entrance
    /// pupil at `z_ep` (the inverse of [`Field::at_angles`]; x is 0 for a
    /// y field).
    pub fn angles_deg(&self, z_ep: f64) -> [f64; 2] {
        let of_point = |d: f64, h: f64| (-h / (d + z_ep)).atan().to_degrees();
        match *self {
            Field::Angle(deg) => [0.0, deg],
            Field::Angles { x_deg, y_deg } => [x_deg, y_deg],
            Field::Height { object_distance, height } => [0.0, of_point(object_distance, height)],
            Field::Point { object_distance, x, y } => [of_point(object_distance, x), of_point(object_distance, y)],
        }
    }

    /// The field's angles as analyses report them: `(x, y)` degrees for an
    /// object at infinity (x `None` for a y field), both `None` for an
    /// object point.
    pub fn reported_angles(&self) -> (Option<f64>, Option<f64>) {
        match *self {
            Field::Angle(d) => (None, Some(d)),
            Field::Angles { x_deg, y_deg } => (Some(x_deg), Some(y_deg)),
            Field::Height { .. } | Field::Point { .. } => (None, None),
        }
    }

    /// Whether the field has an x component.
    pub fn has_x(&self) -> bool {
        matches!(self, Field::Angles { .. } | Field::Point { .. })
    }

    /// The field `s` of the way from the axis to this one (angles' tangents
    /// and object heights scaled by `s`; for `s` in 0..=1).
    pub(super) fn scaled(&self, s: f64) -> Field {
        let scale_angle = |a: f64| if s == 1.0 { a } else { (a.to_radians().tan() * s).atan().to_degrees() };
        match *self {
            Field::Angle(d) => Field::Angle(d * s),
            Field::Angles { x_deg, y_deg } => Field::Angles { x_deg: scale_angle(x_deg), y_deg: scale_angle(y_deg) },
            Field::Height { object_distance, height } => Field::Height { object_distance, height: height * s },
            Field::Point { object_distance, x, y } => Field::Point { object_distance, x: x * s, y: y * s },
        }
    }

    /// The object distance this field implies.
    pub fn object(&self) -> ObjectDistance {
        match *self {
            Field::Angle(_) | Field::Angles { .. } => ObjectDistance::Infinity,
            Field::Height { object_distance, .. } | Field::Point { object_distance, .. } => {
                ObjectDistance::Finite(object_distance)
            }
        }
    }

    /// Human-readable form for messages.
    pub fn describe(&self) -> String {
        match *self {
            Field::Angle(d) => format!("field {d} deg"),
            Field::Angles { x_deg, y_deg } => format!("field x {x_deg} deg, y {y_deg} deg"),
            Field::Height { object_distance, height } => {
                format!("object height {height} mm at {object_distance} mm")
            }
            Field::Point { object_distance, x, y } => {
                format!("object point x {x} mm, y {y} mm at {object_distance} mm")
            }
        }
    }
}

/// Checks a field: angles strictly inside (-90, 90) degrees, or a finite
/// object point at a positive object distance.
pub(super) fn check_field(field: Field) -> Result<(), OpticsError> {
    let angle = |name: &'static str, d: f64| {
        if d.is_finite() && d.abs() < 90.0 {
            Ok(())
        } else {
            Err(OpticsError::BadInput { name, value: d, expected: "an angle in degrees strictly between -90 and 90" })
        }
    };
    let height = |name: &'static str, h: f64| {
        if h.is_finite() {
            Ok(())
        } else {
            Err(OpticsError::BadInput { name, value: h, expected: "a finite height in mm" })
        }
    };
    match field {
        Field::Angle(d) => angle("field angle", d),
        Field::Angles { x_deg, y_deg } => {
            angle("x field angle", x_deg)?;
            angle("y field angle", y_deg)
        }
        Field::Height { object_distance, height: h } => {
            ObjectDistance::from_mm(object_distance)?;
            height("object height", h)
        }
        Field::Point { object_distance, x, y } => {
            ObjectDistance::from_mm(object_distance)?;
            height("object x", x)?;
            height("object y", y)
        }
    }
}
