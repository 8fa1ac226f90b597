//! Decentred and tilted surfaces and elements: the batch and the one-ray
//! path agree bit for bit, exact geometric identities (a decentred whole
//! lens images a point at infinity decentred by as much; a tilted plate
//! displaces a ray by the textbook amount), validation, and the file
//! format's round trip.

mod common;
use common::*;
use lens::model::ElementSpec;
use lens::{DVec3, Outcome, Prescription, PrescriptionSpec, Ray, RayBatch, Tracer};

fn spec_of(name: &str) -> PrescriptionSpec {
    lens::load_spec(&data_dir().join(name)).unwrap()
}

/// `spec` with its second and third surfaces moved as an element and its
/// first (or last) tilted and decentred alone, by motions scaled by
/// `scale`.
fn perturbed(mut spec: PrescriptionSpec, scale: f64) -> PrescriptionSpec {
    let n = spec.surfaces.len();
    spec.surfaces[0].decenter_mm = Some([0.02 * scale, -0.03 * scale]);
    spec.surfaces[0].tilt_deg = Some([0.2 * scale, -0.1 * scale]);
    if n > 4 {
        spec.surfaces[n - 1].tilt_deg = Some([-0.15 * scale, 0.25 * scale]);
        spec.elements = Some(vec![ElementSpec {
            surfaces: [2, 3],
            decenter_mm: Some([-0.01 * scale, 0.04 * scale]),
            tilt_deg: Some([0.3 * scale, 0.2 * scale]),
        }]);
    }
    spec
}

/// Every shipped lens, perturbed (as little as its air gaps allow), traced
/// both ways with wild rays: the batch (structure of arrays and rows) is
/// the one-ray path to the bit, every kind of outcome included.
#[test]
fn batch_is_bit_for_bit_the_one_ray_path_through_tilted_lenses() {
    let mut uniform = uniform(0x9e37_79b9_7f4a_7c15);
    // the shipped lenses and the library's (aspheres, ideal surfaces)
    let mut lenses: Vec<String> = shipped_lenses().into_iter().map(|(name, _)| name).collect();
    let library = std::fs::read_dir(data_dir().join("library")).unwrap();
    lenses.extend(library.filter_map(|e| {
        let name = e.ok()?.file_name().to_string_lossy().into_owned();
        name.ends_with(".json").then(|| format!("library/{name}"))
    }));
    let mut tilted = 0;
    for name in &lenses {
        let Some(p) = [1.0, 0.3, 0.1, 0.01, 0.001]
            .iter()
            .find_map(|&k| Prescription::from_spec(&perturbed(spec_of(name), k)).ok())
        else {
            continue;
        };
        assert!(p.is_tilted());
        tilted += 1;
        let reach = p.surfaces().iter().filter_map(|s| s.semi_diameter).fold(0.0, f64::max) * 1.5;
        let film_z = p.last_vertex_z() + p.film_distance();
        for (tracer, z0, towards) in [(Tracer::forward(&p), -30.0, 1.0), (Tracer::reverse(&p), film_z + 5.0, -1.0)] {
            for len in [1usize, 5, 64, 131] {
                let (mut batch, mut rays, mut rows) = (RayBatch::default(), Vec::new(), Vec::new());
                for _ in 0..len {
                    let (x, y) = (reach * (2.0 * uniform() - 1.0), reach * (2.0 * uniform() - 1.0));
                    let (theta, phi) = (1.2 * uniform(), std::f64::consts::TAU * uniform());
                    let d = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), towards * theta.cos());
                    let r = Ray::new(DVec3::new(x, y, z0), d).unwrap();
                    batch.push(r);
                    rays.push(r);
                    rows.extend([x, y, z0, d.x, d.y, d.z]);
                }
                let mut out = vec![Outcome::default(); len];
                tracer.trace_batch(&rays, &mut out);
                tracer.trace_soa(&mut batch);
                let (mut ends, mut status) = (vec![0.0; 6 * len], vec![0u64; len]);
                tracer.trace_rows(&rows, &mut ends, &mut status).unwrap();
                for (i, r) in rays.iter().enumerate() {
                    let one = tracer.trace(*r);
                    assert!(same(&one, &out[i]), "{name} ray {i}: batch {:?} vs {one:?}", out[i]);
                    let soa = tracer.outcome_of(&batch, i).unwrap();
                    assert!(same(&one, &soa), "{name} ray {i}: soa {soa:?} vs {one:?}");
                    let row = one.ray();
                    let want = [row.origin.to_array(), row.direction.to_array()].concat();
                    assert!(want.iter().zip(&ends[6 * i..6 * i + 6]).all(|(a, b)| a.to_bits() == b.to_bits()));
                }
            }
        }
    }
    assert_eq!(tilted, lenses.len(), "every shipped lens takes the motions at some scale");
}

/// A whole lens decentred by (dx, dy) as one element, the film staying:
/// a ray enters it as the ray (dx, dy) lower enters the co-axial lens, so
/// it lands (dx, dy) from where that one lands. The same for a surface
/// met by its own decentre alone, element by element.
#[test]
fn a_decentred_lens_is_the_lens_moved() {
    let (dx, dy) = (0.37, -0.21);
    let mut spec = spec_of("double-gauss-50mm.json");
    let n = spec.surfaces.len();
    let straight = Prescription::from_spec(&spec).unwrap();
    spec.elements = Some(vec![ElementSpec { surfaces: [1, n], decenter_mm: Some([dx, dy]), tilt_deg: None }]);
    let moved = Prescription::from_spec(&spec).unwrap();
    let (a, b) = (Tracer::forward(&straight), Tracer::forward(&moved));
    let mut worst = 0.0f64;
    for k in 0..200 {
        let (x, y) = (-8.0 + 0.08 * k as f64, 5.0 - 0.05 * k as f64);
        let d = DVec3::new(0.02, -0.05, 1.0).normalize();
        let on = |t: &Tracer, x: f64, y: f64| t.trace(Ray::new(DVec3::new(x, y, -20.0), d).unwrap());
        let (Outcome::Reached { ray: r0, opl: o0 }, Outcome::Reached { ray: r1, opl: o1 }) =
            (on(&a, x - dx, y - dy), on(&b, x, y))
        else {
            continue;
        };
        worst = worst.max((r1.origin - r0.origin - DVec3::new(dx, dy, 0.0)).length());
        assert!((r1.direction - r0.direction).length() < 1e-13);
        assert!((o1 - o0).abs() < 1e-11);
    }
    assert!(worst < 1e-11, "{worst}");
}

/// A plane-parallel plate (thickness t, index n) tilted by theta about x
/// displaces a ray along the axis by t sin(theta) (1 - cos(theta) /
/// sqrt(n^2 - sin^2(theta))) in y, and leaves its direction unchanged; as
/// one element, and as two surfaces each tilted alone about their own
/// vertices (which is not the same plate: its back face slides, so the
/// displacement is the one of a plate whose back face was met at the
/// co-axial vertex's height).
#[test]
fn a_tilted_plate_displaces_a_ray_by_the_textbook_amount() {
    let (t, n, theta) = (10.0f64, 1.6f64, 20f64.to_radians());
    let mut spec = PrescriptionSpec {
        surfaces: vec![surf(None, t, Some(n), 20.0, true), surf(None, 30.0, None, 20.0, false)],
        ..PrescriptionSpec::default()
    };
    spec.elements = Some(vec![ElementSpec { surfaces: [1, 2], decenter_mm: None, tilt_deg: Some([20.0, 0.0]) }]);
    let p = Prescription::from_spec(&spec).unwrap();
    let Outcome::Reached { ray, .. } =
        Tracer::forward(&p).trace(Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z).unwrap())
    else {
        panic!()
    };
    let s = theta.sin();
    let shift = t * s * (1.0 - theta.cos() / (n * n - s * s).sqrt());
    // a positive tilt about x turns the plate's normal toward -y: the ray
    // is refracted toward the normal inside and leaves displaced to -y
    assert!((ray.origin.y + shift).abs() < 1e-12, "{} vs {}", ray.origin.y, -shift);
    assert!((ray.direction - DVec3::Z).length() < 1e-15);
    assert!(ray.origin.x.abs() < 1e-15);
    // the same about y: displaced toward +x
    spec.elements = Some(vec![ElementSpec { surfaces: [1, 2], decenter_mm: None, tilt_deg: Some([0.0, 20.0]) }]);
    let p = Prescription::from_spec(&spec).unwrap();
    let ray = Tracer::forward(&p).trace(Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z).unwrap()).ray();
    assert!((ray.origin.x - shift).abs() < 1e-12 && ray.origin.y.abs() < 1e-15, "{ray:?}");
}

/// Tilting a surface between two equal media changes nothing, and a
/// decentred sphere's hit moves with it.
#[test]
fn a_moved_surface_is_met_where_it_is() {
    let mut spec = PrescriptionSpec {
        surfaces: vec![surf(Some(40.0), 5.0, Some(1.5), 12.0, true), surf(Some(-40.0), 50.0, None, 12.0, false)],
        ..PrescriptionSpec::default()
    };
    spec.surfaces[0].decenter_mm = Some([0.0, 1.0]);
    let p = Prescription::from_spec(&spec).unwrap();
    let (path, _) = Tracer::forward(&p).trace_path(Ray::new(DVec3::new(0.0, 1.0, -5.0), DVec3::Z).unwrap());
    // the ray on the decentred vertex meets the first surface at its vertex
    assert!((path[1] - DVec3::new(0.0, 1.0, 0.0)).length() < 1e-14, "{:?}", path[1]);
}

/// Bad motions and elements are errors naming the field and what to do.
#[test]
fn bad_motions_are_named() {
    let base = || spec_of("double-gauss-50mm.json");
    let errors = |spec: &PrescriptionSpec| -> String {
        Prescription::from_spec(spec)
            .expect_err("an error")
            .iter()
            .map(|f| f.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    };
    let mut s = base();
    s.surfaces[2].tilt_deg = Some([95.0, 0.0]);
    assert!(errors(&s).contains("tilt_deg"), "{}", errors(&s));
    let mut s = base();
    s.surfaces[2].decenter_mm = Some([f64::NAN, 0.0]);
    assert!(errors(&s).contains("decenter_mm"));
    for bad in [[0, 2], [3, 2], [4, 99]] {
        let mut s = base();
        s.elements = Some(vec![ElementSpec { surfaces: bad, decenter_mm: Some([0.1, 0.0]), tilt_deg: None }]);
        assert!(errors(&s).contains("first <= last"), "{bad:?}: {}", errors(&s));
    }
    let mut s = base();
    let e = |a, b| ElementSpec { surfaces: [a, b], decenter_mm: Some([0.1, 0.0]), tilt_deg: None };
    s.elements = Some(vec![e(1, 3), e(3, 4)]);
    assert!(errors(&s).contains("overlaps element 1"), "{}", errors(&s));
    // a tilt that drives a lens into its neighbour
    let mut s = base();
    s.elements = Some(vec![ElementSpec { surfaces: [1, 2], decenter_mm: None, tilt_deg: Some([25.0, 0.0]) }]);
    let msg = errors(&s);
    assert!(msg.contains("cross where they are decentred or tilted"), "{msg}");
    // motions within the same element keep their co-axial edge check
    let mut s = base();
    s.elements = Some(vec![e(1, 2)]);
    assert!(Prescription::from_spec(&s).is_ok());
}

/// Decentres, tilts and elements survive writing the prescription out and
/// reading it back.
#[test]
fn motions_round_trip_through_the_file_format() {
    let spec = perturbed(spec_of("double-gauss-50mm.json"), 0.3);
    let p = Prescription::from_spec(&spec).unwrap();
    let again =
        Prescription::from_spec(&PrescriptionSpec::from_json_str(&p.to_spec().to_json_string(), "<x>").unwrap())
            .unwrap();
    assert_eq!(p, again);
    assert_eq!(again.elements().len(), 1);
    assert!(again.placement(0).is_some() && again.placement(4).is_none());
}

/// Every shipped lens, perturbed, written as `.zmx` (coordinate breaks
/// around the moved runs) and read back: the same motions, thicknesses
/// within rounding of the run's sums, and rays landing within 1e-9 mm.
#[test]
fn motions_round_trip_through_zmx() {
    use lens::glass::Catalogs;
    use lens::io::zemax::{read, write};
    for (name, _) in shipped_lenses() {
        let Some(p) =
            [1.0, 0.3, 0.1, 0.01].iter().find_map(|&k| Prescription::from_spec(&perturbed(spec_of(&name), k)).ok())
        else {
            panic!("{name} takes no motion")
        };
        let text = write(&p).unwrap();
        assert!(text.contains("TYPE COORDBRK"), "{name}");
        let q = Prescription::from_spec(
            &read(&text, Catalogs::shipped()).unwrap_or_else(|e| panic!("{name}: {e:?}\n{text}")),
        )
        .unwrap();
        assert_eq!(p.elements(), q.elements(), "{name}");
        for (a, b) in p.surfaces().iter().zip(q.surfaces()) {
            assert_eq!((a.decenter_mm, a.tilt_deg), (b.decenter_mm, b.tilt_deg), "{name}");
            assert!((a.thickness - b.thickness).abs() < 1e-12 * (1.0 + p.total_track()), "{name}: {a:?} {b:?}");
        }
        let (tp, tq) = (Tracer::forward(&p), Tracer::forward(&q));
        let ep = lens::paraxial::FirstOrder::of(&p).unwrap().entrance_pupil;
        for k in 0..25 {
            let (x, y) =
                (0.7 * ep.diameter / 2.0 * (k % 5) as f64 / 4.0, 0.7 * ep.diameter / 2.0 * (k / 5) as f64 / 4.0);
            let ray =
                Ray::new(DVec3::new(x - 0.1 * 10.0, y, ep.z - 10.0), DVec3::new(0.1, 0.0, 1.0).normalize()).unwrap();
            if let (Outcome::Reached { ray: a, .. }, Outcome::Reached { ray: b, .. }) = (tp.trace(ray), tq.trace(ray)) {
                assert!((a.origin - b.origin).length() < 1e-9, "{name}: {a:?} {b:?}");
            }
        }
    }
}

/// A Zemax file written the way its tilt/decenter tool lays an element
/// out (a break, the element, its last thickness back to the first
/// vertex, the break undoing it with the thickness on) reads as an
/// element; breaks that do not restore the axis are refused with the
/// line and what to change.
#[test]
fn zemax_coordinate_breaks_read_as_elements_or_are_refused() {
    use lens::glass::Catalogs;
    let file = |close_disz: &str, last_disz: &str, tilt_z: &str| {
        format!(
            "MODE SEQ\nUNIT MM X W X CM MR CPMM\nENPD 10\nWAVM 1 0.5875618 1\nPWAV 1\n\
             SURF 0\n  DISZ INFINITY\n\
             SURF 1\n  STOP\n  CURV 0\n  DISZ 5\n  DIAM 5\n\
             SURF 2\n  TYPE COORDBRK\n  PARM 1 0.1\n  PARM 2 -0.2\n  PARM 3 1.5\n  PARM 4 -0.5\n  PARM 5 {tilt_z}\n  PARM 6 0\n  DISZ 0\n\
             SURF 3\n  CURV 0.02\n  DISZ 4\n  GLAS ___BLANK 1 0 1.5168 64.17\n  DIAM 8\n\
             SURF 4\n  CURV -0.02\n  DISZ {last_disz}\n  DIAM 8\n\
             SURF 5\n  TYPE COORDBRK\n  PARM 1 -0.1\n  PARM 2 0.2\n  PARM 3 -1.5\n  PARM 4 0.5\n  PARM 6 1\n  DISZ {close_disz}\n\
             SURF 6\n  CURV 0\n  DISZ 0\n"
        )
    };
    let spec = lens::io::zemax::read(&file("94", "-4", "0"), Catalogs::shipped()).unwrap();
    assert_eq!(
        spec.elements,
        Some(vec![ElementSpec { surfaces: [2, 3], decenter_mm: Some([0.1, -0.2]), tilt_deg: Some([1.5, -0.5]) }])
    );
    assert_eq!(spec.surfaces[2].thickness, 90.0);
    // the last thickness runs on along the tilted axis: refused, naming it
    let e = format!("{:?}", lens::io::zemax::read(&file("90", "0", "0"), Catalogs::shipped()).unwrap_err());
    assert!(e.contains("off where it was") && e.contains("SURF 4"), "{e}");
    let e = format!("{:?}", lens::io::zemax::read(&file("94", "-4", "3"), Catalogs::shipped()).unwrap_err());
    assert!(e.contains("tilted about z"), "{e}");
    // a break never undone
    let open = file("94", "-4", "0").replace("PARM 6 1", "PARM 6 0").replace("PARM 3 -1.5", "PARM 3 -1.4");
    let e = format!("{:?}", lens::io::zemax::read(&open, Catalogs::shipped()).unwrap_err());
    assert!(e.contains("coordinate break"), "{e}");
}

/// On a moved lens the ray analyses trace the moved surfaces (a decentred
/// element moves the spot by a known amount: the whole lens decentred
/// moves it by the decentre), and the analyses that rely on the lens's
/// symmetry refuse it, naming themselves and what to use instead.
#[test]
fn analyses_trace_moved_lenses_or_refuse_them() {
    use lens::analysis::{fan::ImagePlane, pattern::Pattern, spot::spot_diagram, Aim, Field};
    let mut spec = spec_of("double-gauss-50mm.json");
    let straight = Prescription::from_spec(&spec).unwrap();
    let n = spec.surfaces.len();
    spec.elements = Some(vec![ElementSpec { surfaces: [1, n], decenter_mm: Some([0.3, -0.2]), tilt_deg: None }]);
    let moved = Prescription::from_spec(&spec).unwrap();
    let spot = |p: &Prescription| {
        spot_diagram(p, Field::Angle(3.0), Pattern::Gauss, 8, Aim::Paraxial, ImagePlane::ImageSurface).unwrap()
    };
    // the rays are aimed at the unperturbed pupil, which the moved stop no
    // longer centres: the spot is not simply shifted, but its centroid
    // moves toward the decentre
    let (a, b) = (spot(&straight), spot(&moved));
    assert!(
        b.centroid[0] > a.centroid[0] + 0.1 && b.centroid[1] < a.centroid[1] - 0.05,
        "{:?} {:?}",
        a.centroid,
        b.centroid
    );
    let e = lens::analysis::focus::focus(&moved, lens::paraxial::ObjectDistance::Infinity).unwrap_err().to_string();
    assert!(e.contains("symmetric about its axis") && e.contains("fans, spots"), "{e}");
    let e = lens::analysis::curves::field_curves(&moved, None, 5, Aim::Paraxial).unwrap_err().to_string();
    assert!(e.contains("field curves"), "{e}");
}

/// Through a moved lens, a ray traced to the film and sent back from there
/// by the reverse tracer returns along its starting line, with the same
/// optical path: both directions place the moved surfaces alike.
#[test]
fn moved_lenses_are_reversible() {
    let p = Prescription::from_spec(&perturbed(spec_of("double-gauss-50mm.json"), 1.0)).unwrap();
    let (forward, reverse) = (Tracer::forward(&p), Tracer::reverse(&p));
    let mut checked = 0;
    for k in 0..121 {
        let (x, y) = (-6.0 + 1.2 * (k % 11) as f64, -6.0 + 1.2 * (k / 11) as f64);
        let start = Ray::new(DVec3::new(x, y, -20.0), DVec3::new(0.03, -0.06, 1.0)).unwrap();
        let Outcome::Reached { ray: end, opl } = forward.trace(start) else { continue };
        let back = Ray { origin: end.origin, direction: -end.direction };
        let Outcome::Reached { ray: front, opl: opl_back } = reverse.trace(back) else {
            panic!("ray {k} did not come back")
        };
        assert!((front.direction + start.direction).length() < 1e-12, "ray {k}");
        let s = (front.origin.z - start.origin.z) / start.direction.z;
        assert!((front.origin - start.at(s)).length() < 1e-9, "ray {k}: {:?} vs {:?}", front.origin, start.at(s));
        assert!((opl - s - opl_back).abs() < 1e-9, "ray {k}");
        checked += 1;
    }
    assert!(checked > 60, "{checked}");
}

/// Two surfaces moved together inside a moved element are two elements
/// that overlap: refused while reading, saying what may nest.
#[test]
fn zemax_runs_nest_one_surface_deep() {
    use lens::glass::Catalogs;
    let brk =
        |n: usize, v: f64, order: u8| format!("SURF {n}\n  TYPE COORDBRK\n  PARM 1 {v}\n  PARM 6 {order}\n  DISZ 0\n");
    let lens_surf = |n: usize, c: f64, disz: f64| format!("SURF {n}\n  CURV {c}\n  DISZ {disz}\n  DIAM 8\n");
    let text = format!(
        "MODE SEQ\nUNIT MM X W X CM MR CPMM\nENPD 10\nWAVM 1 0.5875618 1\nPWAV 1\nSURF 0\n  DISZ INFINITY\n\
         SURF 1\n  STOP\n  CURV 0\n  DISZ 5\n  DIAM 5\n{}{}{}{}{}{}{}SURF 9\n  CURV 0\n  DISZ 0\n",
        brk(2, 0.1, 0),
        brk(3, 0.2, 0),
        lens_surf(4, 0.02, 4.0),
        lens_surf(5, -0.02, 90.0),
        brk(6, -0.2, 1),
        brk(7, -0.1, 1),
        lens_surf(8, 0.0, 10.0),
    );
    let e = format!("{:?}", lens::io::zemax::read(&text, Catalogs::shipped()).unwrap_err());
    assert!(e.contains("only one surface's own decentre and tilt may nest"), "{e}");
}
