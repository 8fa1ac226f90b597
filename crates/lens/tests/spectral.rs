//! Rays of mixed wavelengths in one batch land exactly where the
//! prescription at each ray's own wavelength puts them.

use lens::trace::SpectralBatch;
use lens::{DVec3, Outcome, Prescription, Ray, Tracer};

/// Every kind of glass the batch evaluates: a Sellmeier catalogue glass
/// (SCHOTT), an even power series (HOYA), a model glass, tabulated data
/// (LZOS, one ray at a time), a constant index; cemented and air-spaced.
const MIXED: &str = r#"{"surfaces": [
  {"radius": 40, "thickness": 5, "glass": "SCHOTT:N-BK7", "semi_diameter": 12},
  {"radius": -30, "thickness": 2, "glass": "HOYA:E-F5", "semi_diameter": 12},
  {"radius": -120, "thickness": 1, "semi_diameter": 12},
  {"thickness": 2, "semi_diameter": 9, "stop": true},
  {"radius": 60, "thickness": 4, "glass": {"nd": 1.72, "vd": 29.5}, "semi_diameter": 11},
  {"radius": 25, "thickness": 5, "glass": "LZOS:BF1", "semi_diameter": 11},
  {"radius": -80, "thickness": 1, "semi_diameter": 11},
  {"radius": 90, "thickness": 3, "ior": 1.6, "semi_diameter": 11},
  {"radius": -90, "thickness": 60, "semi_diameter": 11}
]}"#;

fn lenses() -> Vec<Prescription> {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/");
    let mut v = vec![Prescription::from_json_str(MIXED, "<mixed>").unwrap()];
    for f in ["cooke-triplet.json", "achromat-doublet-100mm.json", "double-gauss-50mm.json"] {
        v.push(Prescription::load(format!("{data}{f}")).unwrap());
    }
    v
}

/// Rays over the aperture and a few field angles, each at a wavelength
/// from 380 to 780 nm (a sequence that never repeats).
fn rays(p: &Prescription, n: usize) -> SpectralBatch {
    let r = p.surfaces()[0].semi_diameter.unwrap_or(10.0) * 1.1;
    let mut b = SpectralBatch::default();
    for k in 0..n {
        let u = [(0.5 + 0.754_877_666 * k as f64).fract(), (0.5 + 0.569_840_29 * k as f64).fract()];
        let (rho, phi) = (r * u[0].sqrt(), std::f64::consts::TAU * u[1]);
        let theta = (12.0 * ((k % 7) as f64 / 6.0)).to_radians();
        let d = DVec3::new(0.0, theta.sin(), theta.cos());
        let o = DVec3::new(rho * phi.cos(), rho * phi.sin(), 0.0) - d * 10.0;
        let nm = 380.0 + 400.0 * (0.5 + 0.618_033_988_7 * k as f64).fract();
        b.push(Ray::new(o, d).unwrap(), nm);
    }
    b
}

fn bits(o: &Outcome) -> Vec<u64> {
    let (ray, opl) = match *o {
        Outcome::Reached { ray, opl }
        | Outcome::Missed { ray, opl, .. }
        | Outcome::Blocked { ray, opl, .. }
        | Outcome::TotalInternalReflection { ray, opl, .. }
        | Outcome::NotConverged { ray, opl, .. } => (ray, opl),
    };
    [ray.origin.to_array(), ray.direction.to_array()].concat().iter().chain([opl].iter()).map(|x| x.to_bits()).collect()
}

/// The batch (AVX2 where the CPU has it), the one-ray spectral path and
/// the one-wavelength tracer of `at_wavelength` agree to the bit, on every
/// ray, reached or stopped.
#[test]
fn each_ray_meets_the_indices_of_its_own_wavelength() {
    for p in lenses() {
        let tracer = Tracer::forward(&p);
        let mut b = rays(&p, 1001);
        let launched = b.clone();
        tracer.trace_spectral(&mut b).unwrap();
        let (mut reached, mut stopped) = (0, 0);
        for i in 0..b.len() {
            let nm = launched.wavelength_nm[i];
            let ray = Ray {
                origin: DVec3::new(launched.rays.x[i], launched.rays.y[i], launched.rays.z[i]),
                direction: DVec3::new(launched.rays.dx[i], launched.rays.dy[i], launched.rays.dz[i]),
            };
            let mono = Tracer::forward(&p.at_wavelength(nm).unwrap()).trace(ray);
            let batch = tracer.outcome_of(&b.rays, i).unwrap();
            let one = tracer.trace_at(ray, nm).unwrap();
            assert_eq!(bits(&batch), bits(&mono), "{}: ray {i} at {nm} nm: {batch:?} vs {mono:?}", p.name());
            assert_eq!(bits(&one), bits(&mono), "{}: ray {i} one by one", p.name());
            assert_eq!(std::mem::discriminant(&batch), std::mem::discriminant(&mono));
            if matches!(mono, Outcome::Reached { .. }) {
                reached += 1
            } else {
                stopped += 1
            }
        }
        assert!(reached > 300 && stopped > 30, "{}: {reached} reached, {stopped} stopped", p.name());
    }
}

/// Colour is there: F and C rays through the achromat's margin land apart,
/// and a constant-index lens gives every wavelength the same landing.
#[test]
fn dispersion_separates_wavelengths_and_constant_indices_do_not() {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/");
    let achromat = Prescription::load(format!("{data}achromat-doublet-100mm.json")).unwrap();
    let constant = Prescription::load(format!("{data}biconvex-singlet.json")).unwrap();
    for (p, differ) in [(&achromat, true), (&constant, false)] {
        let ray = Ray::new(DVec3::new(0.0, 8.0, -5.0), DVec3::Z).unwrap();
        let mut b = SpectralBatch::default();
        b.push(ray, 486.1327);
        b.push(ray, 656.2725);
        Tracer::forward(p).trace_spectral(&mut b).unwrap();
        assert_eq!(b.rays.y[0] != b.rays.y[1], differ, "{}", p.name());
    }
}

/// A wavelength where a glass has no index (N-BK7 from 7.6 µm up to its
/// Sellmeier pole at 10.2 µm, or between the data's end and such a
/// wavelength), or none at all, is an error that names the glass or the
/// wavelength, and nothing is traced. A little outside the data the
/// formulas are extrapolated: that traces.
#[test]
fn wavelengths_without_an_index_are_errors() {
    let p = Prescription::from_json_str(MIXED, "<mixed>").unwrap();
    let t = Tracer::forward(&p);
    let ray = Ray::new(DVec3::new(0.0, 1.0, -5.0), DVec3::Z).unwrap();
    let singlet = MIXED.replace("HOYA:E-F5", "SCHOTT:N-SF5").replace("LZOS:BF1", "SCHOTT:N-BK7");
    let mut b = SpectralBatch::default();
    b.push(ray, 550.0);
    b.push(ray, 2600.0);
    Tracer::forward(&Prescription::from_json_str(&singlet, "<extrapolated>").unwrap()).trace_spectral(&mut b).unwrap();
    for nm in [9000.0, 11_000.0, f64::NAN, -5.0, 0.0, f64::INFINITY] {
        let mut b = SpectralBatch::default();
        b.push(ray, 550.0);
        b.push(ray, nm);
        let before = b.clone();
        let e = t.trace_spectral(&mut b).unwrap_err().to_string();
        assert!(e.contains("nm") || e.contains("wavelength"), "{e}");
        assert_eq!(b.rays, before.rays);
        assert!(t.trace_at(ray, nm).is_err());
    }
    let mut b = SpectralBatch::default();
    b.push(ray, 550.0);
    b.wavelength_nm.push(600.0);
    assert!(t.trace_spectral(&mut b).is_err());
}
