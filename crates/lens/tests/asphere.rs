//! Aspheric surfaces: exact intersections against closed forms, the batch
//! against the one-ray path, paraxial optics at the vertex curvature, and
//! validation over the clear aperture.

mod common;

use lens::{DVec3, Outcome, Prescription, Ray, RayBatch, Tracer};

/// A prescription from JSON text.
fn lens(json: &str) -> Prescription {
    Prescription::from_json_str(json, "<test>").unwrap()
}

/// A refracting ellipsoid `k = -1 / n^2` from air into glass of index `n`
/// images a point at infinity perfectly (Descartes' ovoid): every ray
/// parallel to the axis, at any height, crosses the axis at `R n / (n - 1)`.
/// The trace reaches it to 1e-9 mm for heights to 0.9 of the rim.
#[test]
fn cartesian_ellipsoid_focuses_parallel_light_exactly() {
    let (r, n) = (20.0, 1.7);
    let f = r * n / (n - 1.0);
    let p = lens(&format!(
        r#"{{"surfaces": [
          {{"radius": {r}, "conic": {k}, "thickness": {f}, "ior": {n}, "semi_diameter": 14, "stop": true}}]}}"#,
        k = -1.0 / (n * n)
    ));
    let t = Tracer::forward(&p);
    let mut worst = 0.0f64;
    for i in 1..=30 {
        let h = 12.6 * i as f64 / 30.0;
        let o = t.trace(Ray::new(DVec3::new(0.0, h, -5.0), DVec3::Z).unwrap());
        let Outcome::Reached { ray, .. } = o else { panic!("h {h}: {o:?}") };
        worst = worst.max(ray.origin.y.abs());
    }
    assert!(worst < 1e-9, "largest miss of the focus {worst:e} mm");
    // the sphere of the same radius is far from it (spherical aberration)
    let s = lens(&format!(
        r#"{{"surfaces": [{{"radius": {r}, "thickness": {f}, "ior": {n}, "semi_diameter": 14, "stop": true}}]}}"#
    ));
    let o = Tracer::forward(&s).trace(Ray::new(DVec3::new(0.0, 12.0, -5.0), DVec3::Z).unwrap());
    assert!(o.reached().unwrap().origin.y.abs() > 0.1);
}

/// The aspheric double Gauss of this test: even terms on two surfaces,
/// conics on two (one a pure conic, met without Newton's iteration), odd
/// terms on a fifth.
const ASPHERIC: &str = r#"{"surfaces": [
  {"radius": 29.475, "conic": -0.3, "aspheric": [0, -2.1e-6, -1.2e-9], "thickness": 3.76, "ior": 1.67, "semi_diameter": 12.7},
  {"radius": 84.83, "thickness": 0.12, "semi_diameter": 12.7},
  {"radius": 19.275, "conic": -0.5, "thickness": 4.025, "ior": 1.67, "semi_diameter": 11.5},
  {"radius": 40.77, "thickness": 3.275, "ior": 1.699, "semi_diameter": 11.5},
  {"radius": 12.75, "thickness": 5.705, "semi_diameter": 9.0},
  {"thickness": 4.5, "semi_diameter": 8.7, "stop": true},
  {"radius": -14.495, "thickness": 1.18, "ior": 1.603, "semi_diameter": 9.0},
  {"radius": 40.77, "thickness": 6.065, "ior": 1.658, "semi_diameter": 10.0},
  {"radius": -20.385, "odd_aspheric": [0, 0, 1.5e-6, -4e-7], "thickness": 0.18, "semi_diameter": 10.0},
  {"radius": 437.065, "thickness": 3.22, "ior": 1.717, "semi_diameter": 11.0},
  {"radius": -39.73, "conic": 1.2, "aspheric": [0, 3e-6], "thickness": 37.0, "semi_diameter": 11.0}
]}"#;

/// A lens of the odd aspheres [`ASPHERIC`] leaves out: terms to r^13 (the
/// longest chains' code) and an r^1 term (a cone at the vertex: Newton's
/// steps, chains of their own lengths).
const ODD_ASPHERIC: &str = r#"{"surfaces": [
  {"radius": 30, "conic": -0.5, "odd_aspheric": [0, 0, 2e-6, -1e-7, 3e-9, 0, 0, 0, 0, 0, 0, 0, 1e-17], "thickness": 5, "ior": 1.6, "semi_diameter": 12, "stop": true},
  {"radius": -80, "odd_aspheric": [1e-3, 0, -2e-6], "thickness": 40, "semi_diameter": 12}
]}"#;

/// The batch (AVX2) gives the one-ray path's bits on aspheric lenses, for
/// rays that pass, are blocked, miss or start off-axis at wild angles, and
/// rays from 0.3 to 100 m away beside them (an asphere's start moves those
/// near its vertex plane first).
/// The phone lens's aspheres (most with 128 rings) likewise, its rays
/// spread over its 2 mm front.
#[test]
fn batch_is_bit_for_bit_the_one_ray_path_on_aspheres() {
    batch_is_the_one_ray_path_on(ASPHERIC, 30.0);
    batch_is_the_one_ray_path_on(ODD_ASPHERIC, 30.0);
    let phone = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../lens-data/library/phone-5.6mm-f3.5-us7535658.json");
    batch_is_the_one_ray_path_on(&std::fs::read_to_string(phone).unwrap(), 2.5);
}

/// [`batch_is_bit_for_bit_the_one_ray_path_on_aspheres`] on the lens
/// `json`, its rays through a square `reach` mm wide 10 mm before it.
fn batch_is_the_one_ray_path_on(json: &str, reach: f64) {
    let p = lens(json);
    let t = Tracer::forward(&p);
    let mut rays = Vec::new();
    let mut next = common::uniform(0x9e37_79b9_7f4a_7c15);
    for i in 0..4001 {
        let o = DVec3::new(reach * (next() - 0.5), reach * (next() - 0.5), -10.0);
        let d = DVec3::new(0.6 * (next() - 0.5), 0.6 * (next() - 0.5), 1.0);
        let far = [300.0, 3000.0, 1e5][i % 3];
        if i % 4 == 1 {
            // from `far` mm away towards a point near the first vertex
            let from = DVec3::new(o.x - far * d.x, o.y - far * d.y, -10.0 - far);
            rays.push(Ray::new(from, d).unwrap());
        } else {
            rays.push(Ray::new(o, d).unwrap());
        }
    }
    let mut batch = RayBatch::with_capacity(rays.len());
    rays.iter().for_each(|r| batch.push(*r));
    t.trace_soa(&mut batch);
    let mut kinds = [0usize; 5];
    for (i, r) in rays.iter().enumerate() {
        let one = t.trace(*r);
        let many = t.outcome_of(&batch, i).unwrap();
        assert_eq!(format!("{one:?}"), format!("{many:?}"), "ray {i}");
        kinds[match one {
            Outcome::Reached { .. } => 0,
            Outcome::Missed { .. } => 1,
            Outcome::Blocked { .. } => 2,
            Outcome::TotalInternalReflection { .. } => 3,
            Outcome::NotConverged { .. } => 4,
        }] += 1;
    }
    assert!(kinds[0] > 100 && kinds[2] > 100, "{kinds:?}");
}

/// Even terms written as odd ones (the same powers) trace to the same
/// bits' worth: the hits agree to 1e-12 mm.
#[test]
fn even_terms_as_odd_terms_trace_the_same() {
    let even = lens(
        r#"{"surfaces": [{"radius": 40, "aspheric": [1e-4, -2e-7], "thickness": 5, "ior": 1.5, "semi_diameter": 15, "stop": true},
                         {"radius": -60, "thickness": 60, "semi_diameter": 15}]}"#,
    );
    let odd = lens(
        r#"{"surfaces": [{"radius": 40, "odd_aspheric": [0, 1e-4, 0, -2e-7, 0, 0, 1e-30], "thickness": 5, "ior": 1.5, "semi_diameter": 15, "stop": true},
                         {"radius": -60, "thickness": 60, "semi_diameter": 15}]}"#,
    );
    for h in [0.0, 3.0, 9.0, 14.0] {
        let r = Ray::new(DVec3::new(0.0, h, -3.0), DVec3::new(0.0, -0.05, 1.0)).unwrap();
        let a = Tracer::forward(&even).trace(r).reached().unwrap();
        let b = Tracer::forward(&odd).trace(r).reached().unwrap();
        assert!((a.origin - b.origin).length() < 1e-10, "{a:?} {b:?}");
    }
}

/// Paraxial optics sees the vertex curvature c + 2 a2: an r^2 term of a
/// on a plane is a sphere of radius 1 / (2 a) near the axis.
#[test]
fn paraxial_power_uses_the_vertex_curvature() {
    let a2 = 0.01; // a sphere of R = 50 mm near the axis
    let asph = lens(&format!(
        r#"{{"surfaces": [{{"aspheric": [{a2}], "thickness": 4, "ior": 1.5, "semi_diameter": 5, "stop": true}},
                         {{"thickness": 90, "semi_diameter": 5}}]}}"#
    ));
    let sph = lens(
        r#"{"surfaces": [{"radius": 50, "thickness": 4, "ior": 1.5, "semi_diameter": 5, "stop": true},
                         {"thickness": 90, "semi_diameter": 5}]}"#,
    );
    let fa = lens::paraxial::FirstOrder::of(&asph).unwrap();
    let fs = lens::paraxial::FirstOrder::of(&sph).unwrap();
    assert!((fa.efl - fs.efl).abs() < 1e-12 * fs.efl, "{} vs {}", fa.efl, fs.efl);
    assert!((fa.efl - 100.0).abs() < 1e-9);
}

/// Validation names the surface: an asphere undefined inside its clear
/// aperture, too many terms, a non-finite conic, aspheres that cross.
#[test]
fn aspheres_are_validated_over_their_clear_aperture() {
    let err = |json: &str| Prescription::from_json_str(json, "<test>").unwrap_err().to_string();
    // an oblate ellipsoid k = 3 of R = 20 reaches r = 10 mm only
    let e = err(
        r#"{"surfaces": [{"radius": 20, "conic": 3, "thickness": 5, "ior": 1.5, "semi_diameter": 12, "stop": true},
                                 {"thickness": 50, "semi_diameter": 12}]}"#,
    );
    assert!(e.contains("surface 1") && e.contains("semi_diameter") && e.contains("reaches 10 mm"), "{e}");
    // a hyperboloid may be larger than |R|
    Prescription::from_json_str(
        r#"{"surfaces": [{"radius": 20, "conic": -3, "thickness": 12, "ior": 1.5, "semi_diameter": 25, "stop": true},
                         {"thickness": 50, "semi_diameter": 25}]}"#,
        "<test>",
    )
    .unwrap();
    let e = err(
        r#"{"surfaces": [{"radius": 20, "aspheric": [0,0,0,0,0,0,0,0,1e-30], "thickness": 5, "ior": 1.5, "semi_diameter": 5, "stop": true},
                                 {"thickness": 50, "semi_diameter": 5}]}"#,
    );
    assert!(e.contains("surface 1") && e.contains("aspheric") && e.contains("at most 8"), "{e}");
    let e = err(
        r#"{"surfaces": [{"radius": 20, "conic": 1e400, "thickness": 5, "ior": 1.5, "semi_diameter": 5, "stop": true},
                                 {"thickness": 50, "semi_diameter": 5}]}"#,
    );
    assert!(e.contains("conic") || e.contains("number"), "{e}");
    // a strong r^4 term bends the rim of surface 1 into surface 2
    let e = err(
        r#"{"surfaces": [{"radius": 40, "aspheric": [0, 1e-3], "thickness": 2, "ior": 1.5, "semi_diameter": 8, "stop": true},
                                 {"radius": -40, "thickness": 50, "semi_diameter": 8}]}"#,
    );
    assert!(e.contains("surfaces 1 and 2 cross"), "{e}");
}

/// A JSON prescription with aspheres survives writing and reading.
#[test]
fn aspheres_round_trip_through_json() {
    let p = lens(ASPHERIC);
    let text = p.to_spec().to_json_string();
    let q = Prescription::from_json_str(&text, "<again>").unwrap();
    assert_eq!(p.surfaces(), q.surfaces());
}
