//! Wave optics against closed forms: the optical path difference of a
//! stigmatic surface, defocus (W020, its RMS, Strehl and Zernike terms),
//! Maréchal's approximation, and the refusal of a grid too coarse.

use lens::analysis::fan::ImagePlane;
use lens::analysis::wave::zernike::{fit, ZernikeKind};
use lens::analysis::wave::{stats, wavefront};
use lens::analysis::{Aim, Field, Launcher};
use lens::{OpticsError, Prescription};

/// A refracting ellipsoid (k = -1/n^2) from air into glass of index n with
/// its image surface at the far focus, R n / (n - 1) behind the vertex: it
/// images the axial point at infinity perfectly (Descartes). `sd` is the
/// stop's semi-diameter at the surface; the film `dz` mm beyond focus.
fn ellipsoid(sd: f64, dz: f64) -> (Prescription, f64, f64) {
    let (r, n) = (20.0, 1.7);
    let f = r * n / (n - 1.0);
    let json = format!(
        r#"{{"surfaces": [{{"radius": {r}, "conic": {k}, "thickness": {t}, "ior": {n}, "semi_diameter": {sd}, "stop": true}}]}}"#,
        k = -1.0 / (n * n),
        t = f + dz
    );
    (Prescription::from_json_str(&json, "<test>").unwrap(), f, n)
}

#[test]
fn a_stigmatic_surface_has_no_wavefront_error() {
    for sd in [14.0, 6.0, 1.0] {
        let (p, _, _) = ellipsoid(sd, 0.0);
        let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
        let w = wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap();
        let worst = w.opd_waves.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
        println!("semi-diameter {sd} mm: largest |W| {worst:.2e} waves over {} rays", w.opd_waves.len());
        assert!(worst < 1e-6, "{worst}");
        assert_eq!(w.vignetted, 0);
        let s = stats(&w);
        assert!((s.strehl - 1.0).abs() < 1e-9, "Strehl {}", s.strehl);
    }
}

/// Defocus: a film dz beyond the focus F of a stigmatic system (its wave a
/// sphere of radius R about F through the exit pupil's centre) sees, on
/// the reference sphere of radius R + dz about its own axial point, W = n'
/// (rho - R) / lambda at the ray of image-space angle u', with rho =
/// sqrt((R + dz)^2 - dz^2 sin^2 u') - dz cos u' its distance from F there (the rim's
/// wave is ahead of the reference: W > 0 for dz > 0): for a slow cone W =
/// W020 rho^2 with W020 = n' dz (1 - cos u'_m), RMS to
/// centroid |W020| / sqrt(12), Strehl [sin(pi W020) / (pi W020)]^2, and the
/// Zernike defocus terms W020 / 2 (Fringe) and W020 / (2 sqrt 3)
/// (Standard).
#[test]
fn defocus_gives_w020_its_rms_strehl_and_zernike_terms() {
    let sd = 1.0;
    for dz in [0.05, 0.2, -0.3] {
        let (p, f, n) = ellipsoid(sd, dz);
        let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
        let w = wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap();
        // the marginal ray's image-space angle: from the rim of the
        // ellipsoid to the focus
        let (r, k) = (20.0f64, -1.0 / (n * n));
        let sag = |h: f64| h * h / (r * (1.0 + (1.0 - (1.0 + k) * h * h / (r * r)).sqrt()));
        let angle = |h: f64| (h / (f - sag(h))).atan();
        let lambda = p.wavelength_nm() * 1e-6;
        let exact = |h: f64| {
            let u = angle(h);
            let rho = -dz * u.cos() + ((f + dz).powi(2) - (dz * u.sin()).powi(2)).sqrt();
            n * (rho - f) / lambda
        };
        let w020 = exact(sd);
        // the sample nearest the rim, against the exact form there
        let (rim, rim_w) = w.passing().map(|(c, _, v)| (c.0.hypot(c.1), v)).fold((0.0, 0.0), |best, (rho, v)| {
            if rho > best.0 {
                (rho, v)
            } else {
                best
            }
        });
        let want_rim = exact(rim * sd);
        // every sample against the exact form
        let worst = w.passing().map(|(c, _, v)| (v - exact(c.0.hypot(c.1) * sd)).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-7, "largest departure from the exact W {worst:e} waves");
        let s = stats(&w);
        let strehl = ((std::f64::consts::PI * w020).sin() / (std::f64::consts::PI * w020)).powi(2);
        let fringe = fit(&w, ZernikeKind::Fringe, 37).unwrap();
        let standard = fit(&w, ZernikeKind::Standard, 37).unwrap();
        println!(
            "dz {dz}: W020 {w020:.6} waves; rim W {rim_w:.6} (exact {want_rim:.6}); RMS to centroid {:.6} (W020/sqrt 12 = {:.6}); \
             Strehl {:.6} (closed form {strehl:.6}); Fringe Z4 {:.6} (W020/2 = {:.6}); Standard Z4 {:.6} (W020/(2 sqrt 3) = {:.6}); \
             RMS from Standard {:.6} vs map {:.6}",
            s.rms_to_centroid,
            w020.abs() / 12f64.sqrt(),
            s.strehl,
            fringe.coefficients[3],
            w020 / 2.0,
            standard.coefficients[3],
            w020 / (2.0 * 3f64.sqrt()),
            standard.rms_without_piston().unwrap(),
            s.rms_to_chief
        );
        assert!((rim_w - want_rim).abs() < 1e-6 * want_rim.abs().max(1.0), "rim");
        assert!((s.rms_to_centroid - w020.abs() / 12f64.sqrt()).abs() < 2e-3 * w020.abs());
        assert!((s.rms_to_chief - s.rms_to_centroid).abs() < 1e-9 * w020.abs(), "no tilt on axis");
        assert!((s.strehl - strehl).abs() < 1e-3, "Strehl {} against {strehl}", s.strehl);
        assert!((fringe.coefficients[3] - w020 / 2.0).abs() < 1e-3 * w020.abs());
        assert!((standard.coefficients[3] - w020 / (2.0 * 3f64.sqrt())).abs() < 1e-3 * w020.abs());
        assert!((standard.rms_without_piston().unwrap() - s.rms_to_chief).abs() < 1e-3 * s.rms_to_chief);
    }
}

/// Maréchal: for small aberrations the Strehl ratio is about exp(-(2 pi
/// sigma)^2), sigma the RMS wavefront error to centroid.
#[test]
fn marechal_holds_for_small_defocus() {
    for dz in [0.01, 0.03, 0.06] {
        let (p, _, _) = ellipsoid(1.0, dz);
        let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
        let s = stats(&wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap());
        let marechal = (-(std::f64::consts::TAU * s.rms_to_centroid).powi(2)).exp();
        println!("dz {dz}: sigma {:.4} waves, Strehl {:.5}, Maréchal {marechal:.5}", s.rms_to_centroid, s.strehl);
        assert!(s.rms_to_centroid < 0.07);
        assert!((s.strehl - marechal).abs() < 0.01 * s.strehl);
    }
}

#[test]
fn a_grid_too_coarse_for_the_wavefront_is_refused_with_one_that_is_not() {
    let (p, _, _) = ellipsoid(6.0, 0.5);
    let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
    let err = wavefront(&p, &p, &launcher, 16, ImagePlane::ImageSurface).unwrap_err();
    println!("{err}");
    let OpticsError::PupilUndersampled { suggest, .. } = err else { panic!("{err:?}") };
    assert!(err.to_string().contains("half a wave"));
    wavefront(&p, &p, &launcher, suggest, ImagePlane::ImageSurface).expect("the suggested grid samples it");
}

/// The ellipsoid's working f-number from its real marginal ray: the cutoff
/// 1 / (lambda N_w) = 2 n' sin(u') / lambda, cycles/mm.
fn ellipsoid_cutoff(sd: f64, f: f64, n: f64, lambda: f64) -> f64 {
    let (r, k) = (20.0f64, -1.0 / (n * n));
    let sag = sd * sd / (r * (1.0 + (1.0 - (1.0 + k) * sd * sd / (r * r)).sqrt()));
    let sin_u = sd / (sd * sd + (f - sag).powi(2)).sqrt();
    2.0 * n * sin_u / lambda
}

#[test]
fn an_aberration_free_pupil_has_the_diffraction_limited_mtf() {
    use lens::analysis::wave::mtf::{diffraction_limited, mtf};
    for sd in [1.0, 6.0] {
        let (p, f, n) = ellipsoid(sd, 0.0);
        let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
        let lambda = p.wavelength_nm() * 1e-6;
        let cutoff = ellipsoid_cutoff(sd, f, n, lambda);
        let freqs: Vec<f64> = [0.02, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99].iter().map(|x| x * cutoff).collect();
        let m = mtf(&p, &p, &launcher, ImagePlane::ImageSurface, &freqs).unwrap();
        println!(
            "semi-diameter {sd}: cutoff T {:.6} S {:.6} (1/(lambda N_w) = {cutoff:.6}) cycles/mm, {} nodes",
            m.cutoff_tangential_per_mm, m.cutoff_sagittal_per_mm, m.nodes
        );
        assert!((m.cutoff_tangential_per_mm - cutoff).abs() < 1e-9 * cutoff);
        assert!((m.cutoff_sagittal_per_mm - cutoff).abs() < 1e-9 * cutoff);
        for (i, nu) in freqs.iter().enumerate() {
            let want = diffraction_limited(nu / cutoff);
            println!(
                "  {:.4} of the cutoff: T {:.8} S {:.8}, closed form {want:.8}",
                nu / cutoff,
                m.tangential[i],
                m.sagittal[i]
            );
            assert!((m.tangential[i] - want).abs() < 2e-4 && (m.sagittal[i] - want).abs() < 2e-4);
            assert!((m.diffraction_limit_tangential[i] - want).abs() < 2e-4);
        }
    }
}

/// Defocus W020 rho^2 turns the pupil autocorrelation's phase linear along
/// the shift: OTF(s) = (1/pi) integral over the overlap of exp(4 pi i W020
/// s a) (a along the shift), each chord integrated in closed form, sin(k h)
/// / k, and the chords summed finely: Hopkins' defocused MTF.
#[test]
fn defocus_gives_the_defocused_autocorrelation_mtf() {
    use lens::analysis::wave::mtf::mtf;
    let sd = 1.0;
    for dz in [0.3, 0.8] {
        let (p, f, n) = ellipsoid(sd, dz);
        let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
        let lambda = p.wavelength_nm() * 1e-6;
        let cutoff = ellipsoid_cutoff(sd, f, n, lambda);
        let w = wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap();
        // W020 from the fitted Fringe defocus and spherical terms: the
        // rho^2 coefficient, 2 Z4 - 6 Z9
        let z = fit(&w, ZernikeKind::Fringe, 37).unwrap().coefficients;
        let w020 = 2.0 * z[3] - 6.0 * z[8];
        let hopkins = |s: f64| {
            let c = (1.0 - 0.25 * s * s).sqrt();
            let k = 4.0 * std::f64::consts::PI * w020 * s;
            let steps = 200_000;
            let db = 2.0 * c / steps as f64;
            (0..steps)
                .map(|i| {
                    let b = -c + (i as f64 + 0.5) * db;
                    let h = (1.0 - b * b).sqrt() - 0.5 * s;
                    (if k.abs() < 1e-12 { 2.0 * h } else { 2.0 * (k * h).sin() / k }) * db
                })
                .sum::<f64>()
                / std::f64::consts::PI
        };
        let freqs: Vec<f64> = [0.05, 0.1, 0.2, 0.35, 0.5, 0.7].iter().map(|x| x * cutoff).collect();
        let m = mtf(&p, &p, &launcher, ImagePlane::ImageSurface, &freqs).unwrap();
        println!("dz {dz}: W020 {w020:.5} waves, {} nodes", m.nodes);
        for (i, nu) in freqs.iter().enumerate() {
            let want = hopkins(2.0 * nu / cutoff).abs();
            println!(
                "  {:.2} of the cutoff: T {:.6} S {:.6}, Hopkins {want:.6}",
                nu / cutoff,
                m.tangential[i],
                m.sagittal[i]
            );
            assert!((m.tangential[i] - want).abs() < 1e-3 && (m.sagittal[i] - want).abs() < 1e-3);
        }
    }
}

#[test]
fn frequencies_outside_zero_to_the_cutoff_are_refused() {
    use lens::analysis::wave::mtf::mtf;
    let (p, _, _) = ellipsoid(1.0, 0.0);
    let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
    for f in [0.0, -5.0, f64::NAN, 1e6] {
        let e = mtf(&p, &p, &launcher, ImagePlane::ImageSurface, &[f]).unwrap_err().to_string();
        println!("{f}: {e}");
        assert!(e.contains("frequency"), "{e}");
    }
}

/// The first minimum of a radial profile sampled every `step` from the
/// centre (a parabola through the lowest sample and its neighbours).
fn first_minimum(profile: &[f64], step: f64) -> f64 {
    let k = (1..profile.len() - 1).find(|&k| profile[k] <= profile[k - 1] && profile[k] <= profile[k + 1]).unwrap();
    let (a, b, c) = (profile[k - 1], profile[k], profile[k + 1]);
    (k as f64 + 0.5 * (a - c) / (a - 2.0 * b + c)) * step
}

#[test]
fn an_aberration_free_pupil_images_the_airy_pattern() {
    use lens::analysis::wave::mtf::cutoffs;
    use lens::analysis::wave::psf::{fft_psf, huygens_psf};
    let (p, _, _) = ellipsoid(1.0, 0.0);
    let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
    let w = wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap();
    let (ct, cs) = cutoffs(&p, &p, &launcher, w.image_z).unwrap();
    let lambda_nw = 1.0 / ct;
    // FFT, padded 16 times: the first zero at 1.2197 lambda N_w, 83.8% of
    // the light inside it
    let fft = fft_psf(&w, (ct, cs), 16);
    let mid = fft.size / 2;
    let row: Vec<f64> = (mid..fft.size).map(|c| fft.intensity[mid * fft.size + c]).collect();
    let zero = first_minimum(&row, fft.pixel_mm.0);
    let ee = fft.encircled_energy((0.0, 0.0), &[1.2197 * lambda_nw])[0];
    println!("FFT: peak {:.6}, first zero {:.5} lambda N_w, energy inside it {ee:.4}", fft.peak(), zero / lambda_nw);
    assert!((fft.peak() - 1.0).abs() < 1e-9);
    assert!((zero / lambda_nw - 1.2197).abs() < 0.005 * 1.2197);
    assert!((ee - 0.838).abs() < 0.01);
    // Huygens over the sphere: the same zero
    let step = lambda_nw / 16.0;
    let h = huygens_psf(&w, 61, (step, step), (ct, cs));
    let mid = h.size / 2;
    let row: Vec<f64> = (mid..h.size).map(|c| h.intensity[mid * h.size + c]).collect();
    let zero = first_minimum(&row, step);
    let ee_h = h.encircled_energy((0.0, 0.0), &[1.2197 * lambda_nw])[0];
    println!(
        "Huygens: peak {:.6}, first zero {:.5} lambda N_w, energy inside it {ee_h:.4}",
        h.peak(),
        zero / lambda_nw
    );
    assert!((ee_h - 0.838).abs() < 0.01, "the whole plane's light as the FFT's");
    assert!((h.peak() - 1.0).abs() < 1e-9);
    assert!((zero / lambda_nw - 1.2197).abs() < 0.005 * 1.2197);
}

#[test]
fn huygens_and_fft_psfs_agree_on_a_slow_defocused_pupil() {
    use lens::analysis::wave::mtf::cutoffs;
    use lens::analysis::wave::psf::{fft_psf, huygens_psf};
    // where both are valid: a Fresnel number a^2 / (lambda R) of ~300 (at
    // ~35, the ellipsoid at 1 mm, Huygens sees the defocused focus's
    // shift toward the pupil that Fraunhofer leaves out: 5e-3 of the peak)
    for dz in [0.0, 0.045] {
        let (p, _, _) = ellipsoid(3.0, dz);
        let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
        let w = wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap();
        let s = stats(&w);
        let (ct, cs) = cutoffs(&p, &p, &launcher, w.image_z).unwrap();
        let fft = fft_psf(&w, (ct, cs), 4);
        let huygens = huygens_psf(&w, 33, fft.pixel_mm, (ct, cs));
        let (f0, h0) = (fft.size / 2 - 16, 0);
        let mut worst: f64 = 0.0;
        for row in 0..33 {
            for col in 0..33 {
                let a = fft.intensity[(f0 + row) * fft.size + f0 + col];
                let b = huygens.intensity[(h0 + row) * 33 + col];
                worst = worst.max((a - b).abs());
            }
        }
        let centre = huygens.intensity[16 * 33 + 16];
        println!(
        "defocused: Strehl {:.5} (stats), {centre:.5} (Huygens at the centre), {:.5} (FFT); largest difference {worst:.2e}",
        s.strehl,
        fft.intensity[(fft.size / 2) * fft.size + fft.size / 2]
    );
        assert!(worst < 2e-3, "{worst}");
        assert!((centre - s.strehl).abs() < 2e-3);
    }
}

#[test]
fn a_polychromatic_mtf_is_the_weighted_sum_of_the_wavelengths_otfs() {
    use lens::analysis::wave::mtf::{diffraction_limited, mtf, polychromatic_mtf};
    let (p, f, n) = ellipsoid(1.0, 0.0);
    let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
    // a constant index: each wavelength's stigmatic Airy pattern, its own
    // cutoff 2 n' sin u' / lambda
    let freqs = [10.0, 40.0, 80.0, 110.0, 130.0];
    let waves = [(500.0, 1.0), (600.0, 2.0)];
    let m = polychromatic_mtf(&p, &launcher, ImagePlane::ImageSurface, &freqs, &waves).unwrap();
    for (k, nu) in freqs.iter().enumerate() {
        let want = waves
            .iter()
            .map(|&(nm, w)| w * diffraction_limited(nu / ellipsoid_cutoff(1.0, f, n, nm * 1e-6)))
            .sum::<f64>()
            / 3.0;
        println!("{nu} c/mm: T {:.8} S {:.8}, weighted closed forms {want:.8}", m.tangential[k], m.sagittal[k]);
        assert!((m.tangential[k] - want).abs() < 2e-4 && (m.sagittal[k] - want).abs() < 2e-4);
    }
    // one wavelength: the monochromatic MTF
    let one =
        polychromatic_mtf(&p, &launcher, ImagePlane::ImageSurface, &freqs[..3], &[(p.wavelength_nm(), 2.0)]).unwrap();
    let mono = mtf(&p, &p, &launcher, ImagePlane::ImageSurface, &freqs[..3]).unwrap();
    assert_eq!(one.tangential, mono.tangential);
}

/// A geometric MTF of a known spot.
#[test]
fn the_geometric_mtf_of_a_uniform_disk_spot_is_its_closed_form() {
    use lens::analysis::pattern::Pattern;
    use lens::analysis::spot::spot_diagram;
    use lens::analysis::wave::mtf::geometric_mtf;
    // a defocused stigmatic surface: the spot is a uniform disk of radius
    // rho, whose line spread along y is (2 / (pi rho)) sqrt(1 - (y/rho)^2):
    // its MTF 2 J1(2 pi nu rho) / (2 pi nu rho)
    let (p, _, _) = ellipsoid(1.0, 0.5);
    let spot =
        spot_diagram(&p, Field::Angle(0.0), Pattern::Gauss, 60, Aim::Paraxial, ImagePlane::ImageSurface).unwrap();
    let rho = spot.geo_radius;
    let freqs = [10.0, 30.0, 50.0, 80.0];
    let (t, s) = geometric_mtf(&spot, &freqs).unwrap();
    // J1 by its series, enough terms for these arguments
    let j1 = |x: f64| {
        let mut sum = 0.0;
        let mut term = x / 2.0;
        for k in 0..40 {
            sum += term;
            term *= -(x * x / 4.0) / ((k + 1) as f64 * (k + 2) as f64);
        }
        sum
    };
    for (k, nu) in freqs.iter().enumerate() {
        let x = std::f64::consts::TAU * nu * rho;
        let want = (2.0 * j1(x) / x).abs();
        println!("{nu} c/mm: T {:.5} S {:.5}, uniform disk of radius {rho:.5} mm: {want:.5}", t[k], s[k]);
        assert!((t[k] - want).abs() < 5e-3 && (s[k] - want).abs() < 5e-3);
    }
}

#[test]
fn the_matrix_fourier_psf_is_the_fft_on_its_grid_and_sums_wavelengths() {
    use lens::analysis::wave::mtf::cutoffs;
    use lens::analysis::wave::psf::{fft_psf, huygens_psf, mft_psf, polychromatic_psf};
    let (p, _, _) = ellipsoid(3.0, 0.045);
    let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
    let w = wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap();
    let c = cutoffs(&p, &p, &launcher, w.image_z).unwrap();
    let fft = fft_psf(&w, c, 4);
    let mft = mft_psf(&w, c, fft.size, fft.pixel_mm, (0.0, 0.0));
    let worst = fft.intensity.iter().zip(&mft.intensity).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    println!("MFT against FFT on its grid: largest difference {worst:.2e}; totals {} and {}", fft.total, mft.total);
    assert!(worst < 1e-10 && (fft.total - mft.total).abs() < 1e-9 * fft.total);
    // two wavelengths (a constant index: the same wavefront in length, so
    // the waves and the cutoffs scale with 1 / lambda): the weighted sum of
    // each one's Huygens image on the common grid
    let waves = [(500.0, 1.0), (650.0, 3.0)];
    let parts: Vec<_> = waves
        .iter()
        .map(|&(nm, wt)| {
            let q = p.at_wavelength(nm).unwrap();
            let w = wavefront(&p, &q, &launcher, 64, ImagePlane::ImageSurface).unwrap();
            let c = cutoffs(&p, &q, &launcher, w.image_z).unwrap();
            (w, c, wt)
        })
        .collect();
    let refs: Vec<_> = parts.iter().map(|(w, c, wt)| (w, *c, *wt)).collect();
    let pixel = (fft.pixel_mm.0, fft.pixel_mm.1);
    let poly = polychromatic_psf(&refs, 33, pixel, w.chief_image);
    let mut worst: f64 = 0.0;
    let sum: Vec<f64> = {
        let mut acc = vec![0.0; 33 * 33];
        for (w, c, wt) in &parts {
            let h = huygens_psf(w, 33, pixel, *c);
            acc.iter_mut().zip(&h.intensity).for_each(|(a, b)| *a += wt * b / 4.0);
        }
        acc
    };
    for (a, b) in poly.intensity.iter().zip(&sum) {
        worst = worst.max((a - b).abs());
    }
    println!(
        "polychromatic MFT against the weighted Huygens images: largest difference {worst:.2e}, centre {:.5}",
        poly.intensity[16 * 33 + 16]
    );
    assert!(worst < 3e-3);
}

/// A slow plano-convex singlet on axis at its paraxial image plane: the
/// wavefront's rho^4 term is the Seidel W040 = S_I / 8.
#[test]
fn a_slow_singlets_spherical_aberration_is_its_seidel_sum() {
    use lens::analysis::aperture::with_f_number;
    use lens::paraxial::seidel::seidel;
    use lens::paraxial::{FirstOrder, ObjectDistance};
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data/plano-convex-singlet.json");
    let full = Prescription::load(std::path::Path::new(path)).unwrap();
    for f_number in [20.0, 12.0] {
        let p = with_f_number(&full, f_number).unwrap();
        let first = FirstOrder::of(&p).unwrap();
        let s = seidel(&p, &first, ObjectDistance::Infinity, 0.0).unwrap();
        let lambda = p.wavelength_nm() * 1e-6;
        let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
        let w = wavefront(&p, &p, &launcher, 64, ImagePlane::Paraxial).unwrap();
        // least squares W = a + b rho^2 + c rho^4 + d rho^6
        let mut ata = [[0.0f64; 4]; 4];
        let mut atb = [0.0f64; 4];
        for ((x, y), wt, v) in w.passing() {
            let r2 = x * x + y * y;
            let t = [1.0, r2, r2 * r2, r2 * r2 * r2];
            for i in 0..4 {
                atb[i] += wt * t[i] * v;
                for j in 0..4 {
                    ata[i][j] += wt * t[i] * t[j];
                }
            }
        }
        let m = nalgebra::Matrix4::from_fn(|i, j| ata[i][j]);
        let c = m.lu().solve(&nalgebra::Vector4::from(atb)).unwrap();
        let seidel_waves = s.w040() / lambda;
        println!(
            "f/{f_number}: rho^4 term {:.6} waves, Seidel W040 = S_I/8 = {seidel_waves:.6} waves; rho^2 term {:.2e}, rho^6 {:.2e}",
            c[2], c[1], c[3]
        );
        assert!((c[2] - seidel_waves).abs() < 1e-3 * seidel_waves.abs(), "{} against {seidel_waves}", c[2]);
    }
}

/// An ideal lens (`"type": "paraxial"`) of focal length f with its stop
/// at the lens, the film `dz` beyond the focal plane.
fn ideal(f: f64, sd: f64, dz: f64) -> Prescription {
    let json = format!(
        r#"{{"surfaces": [{{"type": "paraxial", "focal_length_mm": {f}, "thickness": {t}, "semi_diameter": {sd}, "stop": true}}]}}"#,
        t = f + dz
    );
    Prescription::from_json_str(&json, "<test>").unwrap()
}

#[test]
fn the_ideal_lens_is_perfect_on_and_off_axis() {
    use lens::analysis::wave::mtf::{diffraction_limited, mtf};
    let p = ideal(100.0, 2.5, 0.0);
    let first = lens::paraxial::FirstOrder::of(&p).unwrap();
    assert!((first.efl - 100.0).abs() < 1e-12, "EFL {}", first.efl);
    for deg in [0.0, 5.0, 20.0] {
        let launcher = Launcher::new(&p, Field::Angle(deg), Aim::Paraxial).unwrap();
        let w = wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap();
        let worst = w.opd_waves.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
        let s = stats(&w);
        let m = mtf(&p, &p, &launcher, ImagePlane::ImageSurface, &[10.0, 40.0]).unwrap();
        let want = |nu: f64, c: f64| diffraction_limited(nu / c);
        println!(
            "{deg} deg: largest |W| {worst:.2e} waves, Strehl {:.9}, MTF T {:.6} / {:.6} (closed form {:.6} / {:.6}), chief at y = {:.9} (f tan = {:.9})",
            s.strehl,
            m.tangential[0],
            m.tangential[1],
            want(10.0, m.cutoff_tangential_per_mm),
            want(40.0, m.cutoff_tangential_per_mm),
            w.chief_image.y,
            100.0 * deg.to_radians().tan()
        );
        assert!(worst < 1e-6, "{worst}");
        assert!((s.strehl - 1.0).abs() < 1e-9);
        assert!((w.chief_image.y - 100.0 * deg.to_radians().tan()).abs() < 1e-9);
        for (k, nu) in [10.0, 40.0].iter().enumerate() {
            assert!((m.tangential[k] - want(*nu, m.cutoff_tangential_per_mm)).abs() < 2e-4);
            assert!((m.sagittal[k] - want(*nu, m.cutoff_sagittal_per_mm)).abs() < 2e-4);
        }
    }
    // defocus dz on a slow cone: W020 = dz / (8 N^2), N = f / D = 20, to
    // first order in dz (the next term, dz^2 u^2 / (2 (f + dz)), is dz / f
    // of it: 0.1% here) and the grid's quadrature (0.1%)
    let dz = 0.1;
    let p = ideal(100.0, 2.5, dz);
    let launcher = Launcher::new(&p, Field::Angle(0.0), Aim::Paraxial).unwrap();
    let s = stats(&wavefront(&p, &p, &launcher, 64, ImagePlane::ImageSurface).unwrap());
    let w020 = dz / (8.0 * 20.0 * 20.0) / (p.wavelength_nm() * 1e-6);
    println!(
        "defocus {dz} mm at f/20: RMS to centroid {:.6} waves, W020/sqrt(12) = {:.6}",
        s.rms_to_centroid,
        w020 / 12f64.sqrt()
    );
    assert!((s.rms_to_centroid - w020 / 12f64.sqrt()).abs() < 3e-3 * w020 / 12f64.sqrt());
}

#[test]
fn an_ideal_surface_is_refused_where_it_cannot_be() {
    let bad = |surface: &str| {
        let json = format!(r#"{{"surfaces": [{surface}]}}"#);
        Prescription::from_json_str(&json, "<test>").unwrap_err().to_string()
    };
    let e = bad(r#"{"type": "paraxial", "thickness": 100, "semi_diameter": 2, "stop": true}"#);
    assert!(e.contains("focal_length_mm"), "{e}");
    let e = bad(r#"{"type": "paraxial", "focal_length_mm": 0, "thickness": 100, "semi_diameter": 2, "stop": true}"#);
    assert!(e.contains("not 0"), "{e}");
    let e = bad(
        r#"{"type": "paraxial", "focal_length_mm": 50, "radius": 40, "thickness": 100, "semi_diameter": 2, "stop": true}"#,
    );
    assert!(e.contains("plane"), "{e}");
    let e = bad(
        r#"{"type": "paraxial", "focal_length_mm": 50, "ior": 1.5, "thickness": 100, "semi_diameter": 2, "stop": true}"#,
    );
    assert!(e.contains("same medium"), "{e}");
    let e = bad(r#"{"type": "mirror", "thickness": 100, "semi_diameter": 2, "stop": true}"#);
    assert!(e.contains("not a surface type"), "{e}");
    let e = bad(r#"{"focal_length_mm": 50, "thickness": 100, "semi_diameter": 2, "stop": true}"#);
    assert!(e.contains("paraxial"), "{e}");
}

#[test]
fn the_batch_and_one_ray_paths_agree_on_an_ideal_lens_and_the_zemax_file_keeps_it() {
    use lens::{DVec3, Outcome, Ray, RayBatch, Tracer};
    let p = ideal(-80.0, 3.0, 180.0);
    // a diverging ideal lens: rays of every slope, both tracers
    let t = Tracer::forward(&p);
    let rays: Vec<Ray> = (0..200)
        .map(|k| {
            let (a, b) = ((k % 20) as f64 / 19.0 - 0.5, (k / 20) as f64 / 9.0 - 0.5);
            Ray::new(DVec3::new(5.0 * a, 5.0 * b, -10.0), DVec3::new(0.2 * b, 0.3 * a, 1.0)).unwrap()
        })
        .collect();
    let mut batch = RayBatch::with_capacity(rays.len());
    for r in &rays {
        batch.push(*r);
    }
    t.trace_soa(&mut batch);
    for (i, r) in rays.iter().enumerate() {
        let one = t.trace(*r);
        let many = t.outcome_of(&batch, i).unwrap();
        assert_eq!(one, many, "ray {i}");
        if let Outcome::Reached { ray, .. } = one {
            // a diverging lens: the slopes grow by h / |f|
            assert!(ray.direction.is_finite());
        }
    }
    // Zemax's PARAXIAL surface, PARM 1 its focal length: written and read
    let zmx = lens::io::zemax::write(&p).unwrap();
    assert!(zmx.contains("TYPE PARAXIAL") && zmx.contains("PARM 1 -8E1"), "{zmx}");
    let back = lens::io::zemax::read(&zmx, &lens::glass::Catalogs::with(Vec::new())).unwrap();
    assert_eq!(back.surfaces[0].paraxial_focal_length(), Some(-80.0));
}
