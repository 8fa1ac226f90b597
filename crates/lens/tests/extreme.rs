//! Stiff and extreme cases, each with an exact or bounded expectation.

mod common;
use common::*;
use lens::paraxial::{imaging, FirstOrder, ObjectDistance};
use lens::trace::intersect;
use lens::{DVec3, OpticsError, Outcome, Ray, Tracer};

#[test]
fn near_flat_surface_r_1e9_matches_the_plane() {
    let d = DVec3::new(0.3, -0.2, 1.0).normalize();
    let p = DVec3::new(5.0, 3.0, -7.0);
    let plane = intersect(0.0, p, d).unwrap();
    for r in [1e9, -1e9] {
        let hit = intersect(1.0 / r, p, d).unwrap();
        // sag at h ~ 6 mm is h^2 / 2R ~ 2e-8 mm; the rest must agree to rounding
        let sag = hit.point.truncate().length_squared() / (2.0 * r);
        assert!((hit.point.z - sag).abs() < 1e-15, "{:?}", hit.point);
        assert!((hit.point.truncate() - plane.point.truncate()).length() < 1e-7);
    }
    // and a lens with such surfaces has (almost) no power: EFL ~ R / (n - 1) / 2
    let p = singlet(Some(1e9), Some(-1e9), 5.0, 1.5, 10.0, 50.0);
    let f = FirstOrder::of(&p).unwrap();
    assert!(rel(f.efl, 1e9) < 1e-6, "{}", f.efl);
}

#[test]
fn hemisphere_semi_diameter_equals_radius() {
    // A hemispherical front: rays up to 0.999 R hit the cap; the rim is valid.
    let r = 10.0;
    let p = singlet(Some(r), None, 10.0, 1.5, r, 30.0);
    let t = Tracer::forward(&p);
    for frac in [0.0, 0.5, 0.9, 0.999] {
        let o = t.trace(Ray::new(DVec3::new(0.0, frac * r, -20.0), DVec3::Z).unwrap());
        // it passes the hemisphere; near the rim it is bent so far that it is
        // totally reflected at the plane back, which is the right physics
        match o {
            Outcome::Reached { .. } => assert!(frac <= 0.9),
            Outcome::TotalInternalReflection { surface: 1, .. } => assert!(frac > 0.9),
            _ => panic!("{frac}: {o:?}"),
        }
        assert!(o.ray().direction.is_finite() && o.ray().origin.is_finite());
        let hit = intersect(1.0 / r, DVec3::new(0.0, frac * r, -20.0), DVec3::Z).unwrap();
        assert!((hit.point.z - lens::model::surface::sag(1.0 / r, frac * r).unwrap()).abs() < 1e-12);
    }
    // beyond the sphere the ray misses surface 1 (no NaN)
    let o = t.trace(Ray::new(DVec3::new(0.0, 1.01 * r, -20.0), DVec3::Z).unwrap());
    assert!(matches!(o, Outcome::Missed { surface: 0, .. }), "{o:?}");
}

#[test]
fn grazing_incidence_on_a_plane_refracts_at_the_critical_angle() {
    // 89.999 degrees onto glass: the refracted angle approaches asin(1/n).
    let theta = 89.999f64.to_radians();
    let d = DVec3::new(0.0, theta.sin(), theta.cos());
    let out = lens::trace::refract(d, DVec3::Z, 1.0, 1.5).unwrap();
    let sin_t = out.y;
    assert!((sin_t - theta.sin() / 1.5).abs() < 1e-15);
    // exactly parallel to a plane: a miss, not a NaN
    assert!(intersect(0.0, DVec3::new(0.0, 0.0, -1.0), DVec3::Y).is_none());
}

#[test]
fn total_internal_reflection_is_reported_at_its_surface() {
    // A plano-convex lens, plane side first: a ray parallel to the axis at
    // height 10 meets the rear sphere (R = -12) at sin(i) = 10/12 > 1/1.5.
    let p = singlet(None, Some(-12.0), 10.0, 1.5, 11.0, 20.0);
    let o = Tracer::forward(&p).trace(Ray::new(DVec3::new(0.0, 10.0, -5.0), DVec3::Z).unwrap());
    let Outcome::TotalInternalReflection { surface, ray, .. } = o else { panic!("{o:?}") };
    assert_eq!(surface, 1);
    let sag = lens::model::surface::sag(-1.0 / 12.0, 10.0).unwrap();
    assert!((ray.origin.z - (10.0 + sag)).abs() < 1e-12);
    assert_eq!(ray.direction, DVec3::Z);
    // just below the critical height (sin i = 1/1.5 at h = 8) it refracts
    let o = Tracer::forward(&p).trace(Ray::new(DVec3::new(0.0, 7.9, -5.0), DVec3::Z).unwrap());
    assert!(matches!(o, Outcome::Reached { .. }), "{o:?}");
}

#[test]
fn extreme_indices_n4_and_n1_0001() {
    for n in [4.0, 1.0001] {
        let r = 50.0;
        let p = singlet(Some(r), Some(-r), 4.0, n, 10.0, 100.0);
        let f = FirstOrder::of(&p).unwrap();
        let phi1 = (n - 1.0) / r;
        let phi = 2.0 * phi1 - 4.0 / n * phi1 * phi1;
        assert!(rel(f.efl, 1.0 / phi) < 1e-12, "n {n}");
        let o = Tracer::forward(&p).trace(Ray::new(DVec3::new(0.0, 5.0, -1.0), DVec3::Z).unwrap());
        assert!(matches!(o, Outcome::Reached { .. }), "n {n}: {o:?}");
    }
}

#[test]
fn one_micrometre_stop() {
    let p = singlet(Some(50.0), Some(-50.0), 4.0, 1.5, 10.0, 48.0);
    let p = p.with_stop_semi_diameter(0.5e-3).unwrap();
    let f = FirstOrder::of(&p).unwrap();
    assert!((f.entrance_pupil.diameter - 1e-3).abs() < 1e-15);
    assert!(rel(f.f_number, f.efl / 1e-3) < 1e-12);
    let focus = lens::analysis::focus::focus(&p, ObjectDistance::Infinity).unwrap();
    // a pinhole-sized bundle: real and paraxial focus agree to a few nm
    assert!((focus.best_focus_film_distance - focus.film_distance).abs() < 1e-5);
    assert!(focus.rms_radius_at_best_focus < 1e-9);
}

#[test]
fn object_at_1e12_mm_images_at_the_rear_focal_point() {
    let p = singlet(Some(50.0), Some(-50.0), 4.0, 1.5, 10.0, 48.0);
    let f = FirstOrder::of(&p).unwrap();
    let img = imaging(&p, &f, ObjectDistance::Finite(1e12)).unwrap();
    // Newton: x' = -f^2 / x with x ~ -1e12 mm
    let expected = f.bfl + f.efl * f.efl / (1e12 + f.ffd);
    assert!((img.image_distance - expected).abs() < 1e-9, "{} vs {expected}", img.image_distance);
    assert!(img.magnification.is_finite() && img.magnification.abs() < 1e-10);
    let film = lens::paraxial::film_distance(&p, ObjectDistance::Finite(1e12)).unwrap();
    assert!((film - expected).abs() < 1e-9);
}

#[test]
fn object_at_the_front_focal_plane_is_an_error_not_a_nan() {
    let p = lens::Prescription::load(data_dir().join("double-gauss-50mm.json")).unwrap();
    let f = FirstOrder::of(&p).unwrap();
    let d = -f.ffd;
    let e = imaging(&p, &f, ObjectDistance::Finite(d)).unwrap_err();
    assert!(matches!(e, OpticsError::ImageAtInfinity { .. }), "{e:?}");
    assert!(lens::paraxial::film_distance(&p, ObjectDistance::Finite(d)).is_err());
    // just inside the focal plane: a virtual image, also an error for focusing
    let e = lens::paraxial::film_distance(&p, ObjectDistance::Finite(d * 0.9)).unwrap_err();
    assert!(matches!(e, OpticsError::NoRealImage { .. }), "{e:?}");
}

#[test]
fn fisheye_near_its_full_field() {
    // The Muller fisheye is specified for 155.9 deg. Sweep parallel fans
    // across the whole front aperture: every outcome is finite, rays reach
    // the film at every field up to 76 deg with image heights growing with
    // the field, and the clear apertures of this prescription (pbrt's) cut
    // the field off before 78 deg.
    let p = lens::Prescription::load(data_dir().join("fisheye-10mm.json")).unwrap();
    let t = Tracer::forward(&p);
    let sd = p.surfaces()[0].semi_diameter.unwrap();
    let mut last_mean_y = -1.0;
    for deg in [0.0, 20.0, 40.0, 60.0, 70.0, 76.0, 78.0] {
        let th = f64::to_radians(deg);
        let d = DVec3::new(0.0, th.sin(), th.cos());
        let mut ys = Vec::new();
        // the chief ray crosses z = 0 far below the axis at large fields
        let (lo, hi) = (-1.5 * sd - 15.0 * d.y / d.z, 1.5 * sd);
        for k in 0..=8000 {
            let y0 = lo + (hi - lo) * k as f64 / 8000.0;
            let o = t.trace(Ray::new(DVec3::new(0.0, y0 - 20.0 * d.y / d.z, -20.0), d).unwrap());
            assert!(o.ray().origin.is_finite() && o.ray().direction.is_finite() && o.opl().is_finite(), "{o:?}");
            if let Outcome::Reached { ray, .. } = o {
                ys.push(ray.origin.y);
            }
        }
        if deg > 77.0 {
            assert!(ys.is_empty(), "{deg} deg: {} rays pass beyond the apertures' cut-off", ys.len());
            continue;
        }
        assert!(!ys.is_empty(), "{deg} deg: no ray reaches the film");
        let mean = ys.iter().sum::<f64>() / ys.len() as f64;
        assert!(mean > last_mean_y, "{deg} deg: image height {mean} not beyond {last_mean_y}");
        last_mean_y = mean;
    }
}
