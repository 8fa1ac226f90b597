//! Real-ray tracing: Snell's invariants, reversibility, agreement with the
//! paraxial focus near the axis, and the batch path equal to the one-ray path.

mod common;
use common::*;
use lens::paraxial::FirstOrder;
use lens::{DVec3, Outcome, Ray, RayBatch, Tracer};
use proptest::prelude::*;

fn unit_dir() -> impl Strategy<Value = DVec3> {
    (-0.6f64..0.6, -0.6f64..0.6).prop_map(|(x, y)| DVec3::new(x, y, 1.0).normalize())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Vector Snell: unit length, n sin(theta) conserved, and the normal,
    /// incident and refracted directions coplanar.
    #[test]
    fn snell_invariants(d in unit_dir(), nrm in unit_dir(), n1 in 1.0f64..2.5, n2 in 1.0f64..2.5) {
        let Some(out) = lens::trace::refract(d, nrm, n1, n2) else {
            // TIR only when going to a lower index beyond the critical angle
            let sin_i = d.cross(nrm).length();
            prop_assert!(n1 > n2 && n1 * sin_i > n2 * (1.0 - 1e-12));
            return Ok(());
        };
        prop_assert!((out.length() - 1.0).abs() < 1e-14);
        let sin_i = d.cross(nrm).length();
        let sin_t = out.cross(nrm).length();
        prop_assert!((n1 * sin_i - n2 * sin_t).abs() < 1e-13);
        prop_assert!(nrm.dot(d.cross(out)).abs() < 1e-13);
        // no reflection: the refracted ray continues on the same side
        prop_assert!(out.dot(nrm) * d.dot(nrm) >= 0.0);
    }

    /// Trace forward through a random singlet, then back from the film
    /// along the reversed ray: the ray returns to its start line.
    #[test]
    fn reversibility(r1 in 30.0f64..200.0, r2 in -200.0f64..-30.0, t in 1.0f64..10.0, n in 1.4f64..1.9,
                     y in -5.0f64..5.0, x in -5.0f64..5.0, angle in -0.15f64..0.15) {
        let p = singlet(Some(r1), Some(r2), t, n, 10.0, 80.0);
        let start = Ray::new(DVec3::new(x, y, -20.0), DVec3::new(0.1 * angle, angle, 1.0)).unwrap();
        let Outcome::Reached { ray: end, opl } = Tracer::forward(&p).trace(start) else { return Ok(()) };
        let back = Ray { origin: end.origin, direction: -end.direction };
        let Outcome::Reached { ray: front, opl: opl_back } = Tracer::reverse(&p).trace(back) else {
            return Err(TestCaseError::fail("reverse ray did not come back"));
        };
        // the returning ray runs back along the starting line
        prop_assert!((front.direction + start.direction).length() < 1e-12);
        let s = (front.origin.z - start.origin.z) / start.direction.z;
        let on_line = start.at(s);
        prop_assert!((front.origin - on_line).length() < 1e-9, "{:?} vs {:?}", front.origin, on_line);
        // optical path from the first surface to the film is the same both ways
        let opl_to_first = s; // in air, index 1
        prop_assert!((opl - opl_to_first - opl_back).abs() < 1e-9);
    }
}

#[test]
fn near_axis_real_rays_reproduce_paraxial_focus_on_every_shipped_lens() {
    for (name, p) in shipped_lenses() {
        let f = FirstOrder::of(&p).unwrap();
        let z_focus = p.last_vertex_z() + f.bfl;
        let h = 1e-4 * f.entrance_pupil.diameter / 2.0;
        let ray = Ray::new(DVec3::new(0.0, h, f.entrance_pupil.z), DVec3::Z).unwrap();
        let end = Tracer::forward(&p).trace(ray).reached().unwrap_or_else(|| panic!("{name}: blocked"));
        // where the real ray crosses the axis
        let z_cross = end.origin.z - end.origin.y * end.direction.z / end.direction.y;
        let err = (z_cross - z_focus).abs() / f.efl.abs();
        assert!(err < 1e-7, "{name}: real focus {z_cross} vs paraxial {z_focus} ({err:e} of the EFL)");
    }
}

/// 0 reached, 1 blocked, 2 missed, 3 total internal reflection.
fn kind_index(o: &Outcome) -> usize {
    match o {
        Outcome::Reached { .. } => 0,
        Outcome::Blocked { .. } => 1,
        Outcome::Missed { .. } => 2,
        Outcome::TotalInternalReflection { .. } => 3,
        Outcome::NotConverged { .. } => 4,
    }
}

#[test]
fn batch_is_bit_for_bit_the_one_ray_path_on_every_shipped_lens() {
    for (name, p) in shipped_lenses() {
        let w = lens::trace::bench::Workload::new(&p, 3000).unwrap();
        let mut soa = w.rays.clone();
        w.tracer.trace_soa(&mut soa);
        let rays: Vec<Ray> = (0..w.rays.len())
            .map(|i| Ray {
                origin: DVec3::new(w.rays.x[i], w.rays.y[i], w.rays.z[i]),
                direction: DVec3::new(w.rays.dx[i], w.rays.dy[i], w.rays.dz[i]),
            })
            .collect();
        let mut out = vec![Outcome::default(); rays.len()];
        w.tracer.trace_batch(&rays, &mut out);
        let reverse = Tracer::reverse(&p);
        let mut kinds = [0usize; 4];
        for (i, r) in rays.iter().enumerate() {
            let one = w.tracer.trace(*r);
            assert!(
                same(&one, &w.tracer.outcome_of(&soa, i).unwrap()),
                "{name} ray {i}: soa {:?} vs {:?}",
                soa.status[i],
                one
            );
            assert!(same(&one, &out[i]), "{name} ray {i}: batch {:?} vs {:?}", out[i], one);
            kinds[kind_index(&one)] += 1;
            // and the reverse tracer agrees with itself too
            let back = Ray { origin: one.ray().origin, direction: -one.ray().direction };
            let mut b = RayBatch::default();
            b.push(back);
            reverse.trace_soa(&mut b);
            assert!(same(&reverse.trace(back), &reverse.outcome_of(&b, 0).unwrap()));
        }
        assert!(kinds[0] > 0, "{name}: no ray reached the film");
    }
}

/// Rows in, rows out (`trace_rows`, the layout of an (N, 6) array) are
/// the batch's rays to the bit, through every shipped lens both ways, for
/// wild rays of awkward counts with directions of any length; a row with
/// a number not finite or a zero direction is named by its index.
#[test]
fn rows_are_bit_for_bit_the_batch() {
    let mut uniform = uniform(0x9e37_79b9_7f4a_7c15);
    for (name, p) in shipped_lenses() {
        let reach = p.surfaces().iter().filter_map(|s| s.semi_diameter).fold(0.0, f64::max) * 1.5;
        let film_z = p.last_vertex_z() + p.film_distance();
        for (tracer, z0, towards) in [(Tracer::forward(&p), -30.0, 1.0), (Tracer::reverse(&p), film_z + 5.0, -1.0)] {
            for len in [1usize, 5, 64, 65, 300] {
                let mut rows = Vec::with_capacity(len * 6);
                let mut batch = RayBatch::default();
                for _ in 0..len {
                    let (x, y) = (reach * (2.0 * uniform() - 1.0), reach * (2.0 * uniform() - 1.0));
                    let (theta, phi) = (1.2 * uniform(), std::f64::consts::TAU * uniform());
                    let d = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), towards * theta.cos());
                    let scale = 0.1 + 5.0 * uniform();
                    rows.extend([x, y, z0, d.x * scale, d.y * scale, d.z * scale]);
                    batch.push(Ray { origin: DVec3::new(x, y, z0), direction: (d * scale).normalize() });
                }
                let (mut out, mut status) = (vec![0.0; len * 6], vec![0u64; len]);
                tracer.trace_rows(&rows, &mut out, &mut status).unwrap();
                tracer.trace_soa(&mut batch);
                for i in 0..len {
                    let soa = [batch.x[i], batch.y[i], batch.z[i], batch.dx[i], batch.dy[i], batch.dz[i]];
                    let row = &out[i * 6..i * 6 + 6];
                    assert!(
                        soa.iter().zip(row).all(|(a, b)| a.to_bits() == b.to_bits()),
                        "{name} ray {i} of {len}: rows {row:?} vs batch {soa:?}"
                    );
                    assert_eq!(status[i], batch.status[i], "{name} ray {i} of {len}");
                }
                // a bad row anywhere (in a group of four, in the tail, the
                // first of a chunk) is named by its index
                for at in [0, 3, 6, 64, 65, 299].into_iter().filter(|&at| at < len) {
                    let good: [f64; 6] = rows[at * 6..at * 6 + 6].try_into().unwrap();
                    let bad: [(usize, f64); 4] =
                        [(4, f64::NAN), (0, f64::INFINITY), (2, f64::NEG_INFINITY), (5, f64::NAN)];
                    for (field, value) in bad {
                        rows[at * 6 + field] = value;
                        assert_eq!(tracer.trace_rows(&rows, &mut out, &mut status), Err(at), "{name}: row {at}");
                        rows[at * 6 + field] = good[field];
                    }
                    rows[at * 6 + 3..at * 6 + 6].copy_from_slice(&[0.0, -0.0, 0.0]);
                    assert_eq!(
                        tracer.trace_rows(&rows, &mut out, &mut status),
                        Err(at),
                        "{name}: row {at} no direction"
                    );
                    rows[at * 6..at * 6 + 6].copy_from_slice(&good);
                }
            }
        }
    }
}

/// Every kind of ray, bit for bit: wild rays (wide angles, outside the
/// apertures, parallel to planes, some already finished) through every
/// shipped lens both ways, in batches of awkward lengths.
#[test]
fn batch_is_bit_for_bit_the_one_ray_path_for_wild_rays() {
    let mut uniform = uniform(0x2545_f491_4f6c_dd1d);
    let mut kinds = [0usize; 4];
    for (name, p) in shipped_lenses() {
        let reach = p.surfaces().iter().filter_map(|s| s.semi_diameter).fold(0.0, f64::max) * 1.5;
        let film_z = p.last_vertex_z() + p.film_distance();
        for (tracer, z0, towards) in [(Tracer::forward(&p), -30.0, 1.0), (Tracer::reverse(&p), film_z + 5.0, -1.0)] {
            for len in [1usize, 3, 4, 5, 63, 64, 65, 131, 1000] {
                let mut batch = RayBatch::default();
                let mut rays = Vec::new();
                for i in 0..len {
                    let (x, y) = (reach * (2.0 * uniform() - 1.0), reach * (2.0 * uniform() - 1.0));
                    let theta = 1.5 * uniform();
                    let phi = std::f64::consts::TAU * uniform();
                    let mut d = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), towards * theta.cos());
                    if i % 17 == 5 {
                        d = DVec3::new(phi.cos(), phi.sin(), 0.0); // parallel to every plane
                    }
                    let r = Ray::new(DVec3::new(x, y, z0), d).unwrap();
                    batch.push(r);
                    rays.push(r);
                }
                // a few rays already finished: the batch leaves them alone
                for i in (2..len).step_by(29) {
                    batch.status[i] = 1 << 3 | 2;
                }
                let before = batch.clone();
                let mut out = vec![Outcome::default(); len];
                tracer.trace_batch(&rays, &mut out);
                tracer.trace_soa(&mut batch);
                for (i, r) in rays.iter().enumerate() {
                    let one = tracer.trace(*r);
                    assert!(same(&one, &out[i]), "{name} ray {i} of {len}: batch {:?} vs {:?}", out[i], one);
                    if before.status[i] != 0 {
                        assert_eq!(batch.status[i], before.status[i]);
                        assert_eq!(batch.x[i].to_bits(), before.x[i].to_bits());
                        assert_eq!(batch.z[i].to_bits(), before.z[i].to_bits());
                        assert_eq!(batch.dz[i].to_bits(), before.dz[i].to_bits());
                        continue;
                    }
                    let soa = tracer.outcome_of(&batch, i).unwrap();
                    assert!(same(&one, &soa), "{name} ray {i} of {len}: soa {soa:?} vs {one:?}");
                    kinds[kind_index(&one)] += 1;
                }
            }
        }
    }
    // every outcome was exercised
    assert!(kinds.iter().all(|&k| k > 0), "outcomes reached/blocked/missed/TIR: {kinds:?}");
}

#[test]
fn blocked_rays_carry_the_surface_and_hit_point() {
    let p = singlet(Some(50.0), Some(-50.0), 5.0, 1.5, 10.0, 60.0);
    let t = Tracer::forward(&p);
    let o = t.trace(Ray::new(DVec3::new(0.0, 11.0, -5.0), DVec3::Z).unwrap());
    let Outcome::Blocked { surface, ray, .. } = o else { panic!("{o:?}") };
    assert_eq!(surface, 0);
    assert!((ray.origin.y - 11.0).abs() < 1e-12);
    let sag = lens::model::surface::sag(1.0 / 50.0, 11.0).unwrap();
    assert!((ray.origin.z - sag).abs() < 1e-12);
    assert_eq!(ray.direction, DVec3::Z);
}

#[test]
fn hand_set_statuses_are_left_alone_and_bad_ones_are_errors() {
    let p = singlet(Some(50.0), Some(-50.0), 5.0, 1.5, 10.0, 60.0);
    let t = Tracer::forward(&p);
    let mut b = RayBatch::with_capacity(8);
    for _ in 0..8 {
        b.push(Ray::new(DVec3::new(0.0, 1.0, -5.0), DVec3::Z).unwrap());
    }
    // 3 steps (two surfaces and the film): valid codes are (1..=3) << 3 | 1..=4
    let set = [0, 1, 3, 5, (1 << 3) | 2, (3 << 3) | 1, (4 << 3) | 1, (2 << 3) | 5];
    b.status.copy_from_slice(&set);
    let before = b.clone();
    t.trace_soa(&mut b);
    for (i, &st) in set.iter().enumerate() {
        if st != 0 {
            assert_eq!(b.status[i], st, "ray {i}");
            assert_eq!(b.y[i].to_bits(), before.y[i].to_bits(), "ray {i} was moved");
        }
        let valid = st == 0 || [(1 << 3) | 2, (3 << 3) | 1].contains(&st);
        match t.outcome_of(&b, i) {
            Ok(o) => assert!(valid, "status {st}: {o:?}"),
            Err(e) => assert!(!valid && e.to_string().contains("status"), "status {st}: {e}"),
        }
    }
    assert!(matches!(t.outcome_of(&b, 0), Ok(Outcome::Reached { .. })));
    assert!(matches!(t.outcome_of(&b, 4), Ok(Outcome::Blocked { surface: 0, .. })));
}

/// A forward trace split at any surface (object to k, then k on to the
/// film) lands where the whole forward trace does, and stops at the same
/// surface.
#[test]
fn forward_range_pieces_join_to_the_whole_trace() {
    for (name, p) in shipped_lenses() {
        let w = lens::trace::bench::Workload::new(&p, 500).unwrap();
        let n = p.surfaces().len();
        let mut whole = w.rays.clone();
        Tracer::forward(&p).trace_soa(&mut whole);
        for k in [0, 1, p.stop_index(), n - 1, n] {
            let mut split = w.rays.clone();
            Tracer::forward_range(&p, 0..k).trace_soa(&mut split);
            Tracer::forward_range(&p, k..n).trace_soa(&mut split);
            for i in 0..whole.len() {
                assert_eq!(whole.status[i] == 0, split.status[i] == 0, "{name} split at {k}, ray {i}");
                if whole.status[i] == 0 {
                    let d = (whole.x[i] - split.x[i]).abs().max((whole.y[i] - split.y[i]).abs());
                    assert!(d < 1e-9 && (whole.z[i] - split.z[i]).abs() < 1e-9, "{name} split at {k}, ray {i}: {d}");
                }
            }
        }
    }
}
