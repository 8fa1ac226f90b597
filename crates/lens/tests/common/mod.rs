//! Helpers shared by the integration tests.
#![allow(dead_code)]

use lens::{DVec3, Outcome, Prescription, PrescriptionSpec, SurfaceSpec};

pub fn surf(radius: Option<f64>, thickness: f64, ior: Option<f64>, sd: f64, stop: bool) -> SurfaceSpec {
    SurfaceSpec { ior, semi_diameter: Some(sd), stop, ..SurfaceSpec::new(radius, thickness) }
}

/// A singlet: radii r1, r2 (None = plane), centre thickness t, index n,
/// stop on the first surface, film `film` mm behind. The semi-diameter is
/// `sd`, or less where the lens would be thinner than zero at its rim.
pub fn singlet(r1: Option<f64>, r2: Option<f64>, t: f64, n: f64, sd: f64, film: f64) -> Prescription {
    let c = |r: Option<f64>| r.map_or(0.0, |r| 1.0 / r);
    let edge = |h: f64| {
        let s1 = lens::model::surface::sag(c(r1), h).unwrap_or(f64::NAN);
        let s2 = lens::model::surface::sag(c(r2), h).unwrap_or(f64::NAN);
        t + s2 - s1
    };
    let mut sd = sd;
    while edge(sd).is_nan() || edge(sd) < 0.0 {
        sd *= 0.9;
    }
    let spec = PrescriptionSpec {
        surfaces: vec![surf(r1, t, Some(n), sd, true), surf(r2, film, None, sd, false)],
        ..PrescriptionSpec::default()
    };
    Prescription::from_spec(&spec).expect("valid singlet")
}

/// Uniform numbers in [0, 1) from a xorshift generator seeded with `seed`:
/// the same sequence on every run.
pub fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

pub fn data_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lens-data")
}

pub fn shipped_lenses() -> Vec<(String, Prescription)> {
    let mut v: Vec<_> = std::fs::read_dir(data_dir())
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), Prescription::load(&p).unwrap()))
        .collect();
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Whether two outcomes are the same to the bit: kind, ray and path length.
pub fn same(a: &Outcome, b: &Outcome) -> bool {
    let bits = |v: DVec3| v.to_array().map(f64::to_bits);
    std::mem::discriminant(a) == std::mem::discriminant(b)
        && bits(a.ray().origin) == bits(b.ray().origin)
        && bits(a.ray().direction) == bits(b.ray().direction)
        && a.opl().to_bits() == b.opl().to_bits()
}
