//! Batch tracing throughput: 1,000,000 rays through the double Gauss, on one
//! core and on all cores. Results are recorded in docs/performance.md.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use lens::trace::bench::Workload;
use lens::{Outcome, Prescription, Ray};
use rayon::prelude::*;

const RAYS: usize = 1_000_000;

fn double_gauss() -> Prescription {
    Prescription::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/double-gauss-50mm.json")).unwrap()
}

fn trace(c: &mut Criterion) {
    let p = double_gauss();
    let w = Workload::new(&p, RAYS).unwrap();
    let mut g = c.benchmark_group("double_gauss_1M_rays");
    g.sample_size(10);
    // throughput in ray-surface intersections (11 surfaces per ray)
    g.throughput(Throughput::Elements((RAYS * p.surfaces().len()) as u64));

    // a fresh copy of the rays for each pass, made outside the timing (as
    // `lens bench` restores them untimed): copying 64 MB is a sixth of a pass
    g.bench_function("soa_one_core", |b| {
        b.iter_batched_ref(|| w.rays.clone(), |work| w.tracer.trace_soa(work), BatchSize::PerIteration)
    });

    let rays: Vec<Ray> = (0..RAYS)
        .map(|i| Ray {
            origin: lens::DVec3::new(w.rays.x[i], w.rays.y[i], w.rays.z[i]),
            direction: lens::DVec3::new(w.rays.dx[i], w.rays.dy[i], w.rays.dz[i]),
        })
        .collect();
    let mut out = vec![Outcome::default(); RAYS];
    g.bench_function("slice_one_core", |b| b.iter(|| w.tracer.trace_batch(&rays, &mut out)));
    g.bench_function("slice_all_cores", |b| {
        b.iter(|| rays.par_chunks(16384).zip(out.par_chunks_mut(16384)).for_each(|(r, o)| w.tracer.trace_batch(r, o)))
    });
    g.bench_function("one_ray_at_a_time", |b| {
        b.iter(|| {
            for (r, o) in rays.iter().zip(out.iter_mut()) {
                *o = w.tracer.trace(*r);
            }
        })
    });
    g.finish();
}

criterion_group!(benches, trace);
criterion_main!(benches);
