//! The analyses against the batch trace they are built on: a 1,000,000-ray
//! spot diagram (random pattern, 10 degrees) beside the batch trace of
//! 1,000,000 rays through the same lens, and the other analysis commands'
//! library calls on the double Gauss. Results are in docs/performance.md.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use lens::analysis::fan::{ray_fan, ImagePlane};
use lens::analysis::pattern::Pattern;
use lens::analysis::spot::spot_diagram;
use lens::analysis::{Aim, Field};
use lens::trace::bench::Workload;
use lens::Prescription;

fn double_gauss() -> Prescription {
    Prescription::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/double-gauss-50mm.json")).unwrap()
}

fn analyses(c: &mut Criterion) {
    let p = double_gauss();
    let w = Workload::new(&p, 1_000_000).unwrap();
    let mut g = c.benchmark_group("double_gauss");
    g.sample_size(10);
    g.bench_function("trace_soa_1M_one_core", |b| {
        b.iter_batched_ref(|| w.rays.clone(), |work| w.tracer.trace_soa(work), BatchSize::PerIteration)
    });
    let spot = |pattern, n| spot_diagram(&p, Field::Angle(10.0), pattern, n, Aim::Paraxial, ImagePlane::Paraxial);
    g.bench_function("spot_random_1M", |b| b.iter(|| spot(Pattern::Random, 1_000_000).unwrap()));
    g.bench_function("spot_gauss_default", |b| b.iter(|| spot(Pattern::Gauss, 12).unwrap()));
    g.bench_function("fan_21", |b| {
        b.iter(|| ray_fan(&p, Field::Angle(10.0), 21, Aim::Paraxial, ImagePlane::Paraxial).unwrap())
    });
    g.bench_function("field_curves_11", |b| {
        b.iter(|| lens::analysis::curves::field_curves(&p, None, 11, Aim::Paraxial).unwrap())
    });
    g.bench_function("coc_3", |b| {
        b.iter(|| lens::analysis::coc::circle_of_confusion(&p, 2000.0, &[1000.0, 5000.0, f64::INFINITY]).unwrap())
    });
    g.finish();
}

criterion_group!(benches, analyses);
criterion_main!(benches);
