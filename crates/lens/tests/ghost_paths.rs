//! Ghost paths traced: the reflecting step (one-ray path, batch and
//! mixed-wavelength batch agree bit for bit), the law of reflection, and
//! the Fresnel weights of a path against closed forms.

mod common;

use approx::assert_relative_eq;
use common::uniform;
use lens::coating::{Coating, MGF2_INDEX};
use lens::trace::{SpectralBatch, StopShape};
use lens::{DVec3, Outcome, Prescription, Ray, RayBatch, Tracer};
use std::sync::Arc;

fn library(name: &str) -> Prescription {
    Prescription::load(common::data_dir().join("library").join(name)).unwrap()
}

fn same(a: &Outcome, b: &Outcome) -> bool {
    let (ra, rb) = (a.ray(), b.ray());
    std::mem::discriminant(a) == std::mem::discriminant(b)
        && ra.origin.to_array().iter().zip(rb.origin.to_array()).all(|(x, y)| x.to_bits() == y.to_bits())
        && ra.direction.to_array().iter().zip(rb.direction.to_array()).all(|(x, y)| x.to_bits() == y.to_bits())
        && a.opl().to_bits() == b.opl().to_bits()
}

/// Rays from in front of the lens over its front aperture, up to 20
/// degrees off the axis.
fn rays_into(p: &Prescription, n: usize, seed: u64) -> Vec<Ray> {
    let mut u = uniform(seed);
    let sd = p.surfaces()[0].semi_diameter.unwrap_or(10.0);
    (0..n)
        .map(|_| {
            let (x, y) = (sd * (2.0 * u() - 1.0), sd * (2.0 * u() - 1.0));
            let (t, phi) = (0.35 * u(), std::f64::consts::TAU * u());
            let d = DVec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos());
            Ray::new(DVec3::new(x, y, -5.0) - 5.0 * d, d).unwrap()
        })
        .collect()
}

/// Every ghost path of three library lenses (one with aspheres, a zoom)
/// traced one ray at a time, in a batch, as rows of a struct of arrays, and
/// in a batch of mixed wavelengths: the same bits, and some rays of each
/// lens reach the film by every kind of ending. The Fresnel weights of a
/// batch (`trace_fresnel_soa`, with and without a square stop shape, the
/// coatings' reflectances from the table and from the formula) are the
/// one-ray path's bits too.
#[test]
fn ghost_paths_agree_bit_for_bit_on_every_path() {
    for name in [
        "double-gauss-100mm-f1.25-us2771006.json",
        "canon-35mm-f2-is-aspheric-us20150205081.json",
        "kit-zoom-18.5mm-f3.5-wide-us7277232.json",
    ] {
        let p = library(name);
        let n = p.surfaces().len();
        let rays = rays_into(&p, 67, n as u64);
        let mut reached = 0;
        let mut pairs = 0;
        for j in 1..n {
            for i in 0..j {
                let Some(t) = Tracer::ghost(&p, i, j, p.film_distance()) else { continue };
                pairs += 1;
                let mut out = vec![Outcome::default(); rays.len()];
                t.trace_batch(&rays, &mut out);
                let mut soa = RayBatch::default();
                rays.iter().for_each(|r| soa.push(*r));
                t.trace_soa(&mut soa);
                let mut spectral = SpectralBatch::with_capacity(rays.len());
                rays.iter().for_each(|r| spectral.push(*r, p.wavelength_nm()));
                t.trace_spectral(&mut spectral).unwrap();
                for (k, r) in rays.iter().enumerate() {
                    let one = t.trace(*r);
                    assert!(same(&one, &out[k]), "{name} ghost {i}-{j} ray {k}: {one:?} vs batch {:?}", out[k]);
                    assert!(same(&one, &t.outcome_of(&soa, k).unwrap()), "{name} ghost {i}-{j} ray {k}: soa");
                    assert!(same(&one, &t.outcome_of(&spectral.rays, k).unwrap()), "{name} {i}-{j} {k}: spectral");
                    reached += matches!(one, Outcome::Reached { .. }) as usize;
                }
                let stop = p.stop_index();
                let half = 0.8 * p.stop_semi_diameter();
                let square = Arc::new(move |x: f64, y: f64| f64::from(u8::from(x.abs().max(y.abs()) <= half)));
                let table = Arc::new(t.reflectance_table());
                for fresnel in [
                    t.clone(),
                    t.clone().with_reflectances(table),
                    t.clone().with_stop_shape(StopShape { surface: stop, transmission: square.clone() }),
                ] {
                    let mut soa = RayBatch::default();
                    rays.iter().for_each(|r| soa.push(*r));
                    let mut weights = Vec::new();
                    fresnel.trace_fresnel_soa(&mut soa, &mut weights);
                    for (k, r) in rays.iter().enumerate() {
                        let (one, w) = fresnel.trace_fresnel(*r);
                        assert!(same(&one, &fresnel.outcome_of(&soa, k).unwrap()), "{name} {i}-{j} {k}: fresnel");
                        assert_eq!(
                            w.to_bits(),
                            weights[k].to_bits(),
                            "{name} ghost {i}-{j} ray {k}: {w} vs {}",
                            weights[k]
                        );
                    }
                }
            }
        }
        assert!(pairs >= n * (n - 1) / 2 - 2 * n, "{name}: {pairs} ghost paths");
        assert!(4 * reached > pairs, "{name}: {reached} rays reached the film on {pairs} paths");
    }
}

/// A mirror-like reflection at a curved surface: the angle out equals the
/// angle in, the ray stays in its medium and turns back, on a sphere and on
/// a plane, rays at random heights and slopes.
#[test]
fn reflection_keeps_the_angle_and_the_medium() {
    let p = Prescription::from_json_str(
        r#"{"surfaces": [
        {"radius": 40, "thickness": 6, "ior": 1.6, "semi_diameter": 15, "stop": true},
        {"radius": -60, "thickness": 30, "semi_diameter": 15}]}"#,
        "<test>",
    )
    .unwrap();
    let t = Tracer::ghost(&p, 0, 1, 30.0).unwrap();
    let mut u = uniform(7);
    let mut checked = 0;
    for _ in 0..500 {
        let (h, a) = (12.0 * (2.0 * u() - 1.0), 0.3 * (2.0 * u() - 1.0));
        let r = Ray::new(DVec3::new(0.3 * h, h, -10.0), DVec3::new(0.1 * a, a, 1.0).normalize()).unwrap();
        let (path, o) = t.trace_path(r);
        if !matches!(o, Outcome::Reached { .. }) {
            continue;
        }
        // path: start, surface 1 (in), surface 2 (reflect), surface 1
        // (reflect), surface 2 (out), film
        assert_eq!(path.len(), 6);
        let d_in = (path[2] - path[1]).normalize();
        let d_back = (path[3] - path[2]).normalize();
        let d_fwd = (path[4] - path[3]).normalize();
        assert!(d_in.z > 0.0 && d_back.z < 0.0 && d_fwd.z > 0.0);
        // the normal of surface 2 (R = -60, vertex at z = 6) at the hit
        let c2 = DVec3::new(0.0, 0.0, 6.0 - 60.0);
        let n2 = (path[2] - c2).normalize();
        assert_relative_eq!(d_in.dot(n2).abs(), d_back.dot(n2).abs(), epsilon = 1e-12);
        assert!((d_back - (d_in - 2.0 * d_in.dot(n2) * n2)).length() < 1e-12);
        let c1 = DVec3::new(0.0, 0.0, 40.0);
        let n1 = (path[3] - c1).normalize();
        assert_relative_eq!(d_back.dot(n1).abs(), d_fwd.dot(n1).abs(), epsilon = 1e-12);
        checked += 1;
    }
    assert!(checked > 200, "{checked}");
}

/// A plane-parallel plate: the axial ray's share on the ghost path of its
/// two faces is T R R T, on the direct path T T, bare (R = ((n-1)/(n+1))^2)
/// and with the quarter-wave MgF2 coating at its design wavelength (R =
/// ((n - nc^2)/(n + nc^2))^2); the ghost lands where the plate's two extra
/// crossings put it.
#[test]
fn plate_ghost_is_the_closed_form() {
    let n: f64 = 1.5168;
    for (coating, r) in [
        ("none", ((n - 1.0) / (n + 1.0)).powi(2)),
        ("MgF2", ((n - MGF2_INDEX * MGF2_INDEX) / (n + MGF2_INDEX * MGF2_INDEX)).powi(2)),
    ] {
        let p = Prescription::from_json_str(
            &format!(
                r#"{{"wavelengths_nm": [550], "surfaces": [
                {{"thickness": 8, "ior": {n}, "semi_diameter": 10, "stop": true, "coating": "{coating}"}},
                {{"thickness": 20, "semi_diameter": 10, "coating": "{coating}"}}]}}"#
            ),
            "<test>",
        )
        .unwrap();
        assert_eq!(p.coating(0), if coating == "none" { Coating::None } else { Coating::MgF2 { design_nm: 550.0 } });
        let axial = Ray::new(DVec3::new(1.0, 2.0, -5.0), DVec3::Z).unwrap();
        let (o, direct) = Tracer::forward(&p).trace_fresnel(axial);
        assert!(matches!(o, Outcome::Reached { .. }));
        assert_relative_eq!(direct, (1.0 - r) * (1.0 - r), max_relative = 1e-12);
        let (o, ghost) = Tracer::ghost(&p, 0, 1, 20.0).unwrap().trace_fresnel(axial);
        assert_relative_eq!(ghost, (1.0 - r) * r * r * (1.0 - r), max_relative = 1e-10);
        assert_relative_eq!(o.ray().origin.z, 28.0, epsilon = 1e-12);
        assert_relative_eq!(o.opl(), 5.0 + 3.0 * 8.0 * n + 20.0, max_relative = 1e-14);
    }
}

/// The default coatings: MgF2 where air meets glass, bare where glass
/// meets glass (a cemented doublet), none between two airs; a written
/// coating wins, and `with_coatings` overrides them all. Bad coatings are
/// findings that name the surface.
#[test]
fn default_coatings_and_findings() {
    let p = Prescription::from_json_str(
        r#"{"surfaces": [
        {"radius": 60, "thickness": 6, "glass": "SCHOTT:N-BK7", "semi_diameter": 12},
        {"radius": -40, "thickness": 2, "glass": "SCHOTT:N-SF5", "semi_diameter": 12},
        {"radius": -200, "thickness": 2, "semi_diameter": 12},
        {"thickness": 90, "semi_diameter": 10, "stop": true},
        {"thickness": 1, "semi_diameter": 10, "coating": [{"index": 1.38, "thickness_nm": 100}, {"index": 2.0, "thickness_nm": 60}]}]}"#,
        "<test>",
    )
    .unwrap();
    let mgf2 = Coating::MgF2 { design_nm: 550.0 };
    assert_eq!(p.coating(0), mgf2);
    assert_eq!(p.coating(1), Coating::None);
    assert_eq!(p.coating(2), mgf2);
    assert_eq!(p.coating(3), Coating::None);
    assert!(matches!(p.coating(4), Coating::Layers(ref l) if l.len() == 2));
    let bare = p.with_coatings(Some(Coating::None));
    assert!(bare.coatings().iter().all(|c| *c == Coating::None));
    // written back and read again, the coatings are kept
    let again = Prescription::from_spec(&p.to_spec()).unwrap();
    assert_eq!(again.coatings(), p.coatings());
    for (bad, says) in [
        (r#""gold""#, "unknown coating \"gold\""),
        (r#"[{"index": 0.5, "thickness_nm": 100}]"#, "index 0.5 must be"),
        (r#"[{"index": 1.4, "thickness_nm": -1}]"#, "thickness_nm -1 must be"),
    ] {
        let text = format!(
            r#"{{"surfaces": [{{"radius": 50, "thickness": 5, "ior": 1.5, "semi_diameter": 10, "stop": true, "coating": {bad}}},
            {{"thickness": 95, "semi_diameter": 10}}]}}"#
        );
        let e = Prescription::from_json_str(&text, "<test>").unwrap_err().to_string();
        assert!(e.contains("surface 1") && e.contains(says), "{e}");
    }
}
