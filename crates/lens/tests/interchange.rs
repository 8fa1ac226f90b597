//! Lens files for other tools: CODE V `.seq` (every shipped lens round
//! trips, `.zmx` -> `.seq` -> JSON keeps the EFL; a file in CODE V's own
//! layout reads as it says; what cannot be read is refused by line, what is
//! not used is listed) and pbrt-v4's realistic-camera lens file (the
//! export, traced by a reader written from pbrt-v4's rules here, focuses
//! where this project's paraxial model does).

use lens::glass::Catalogs;
use lens::io::{codev, dat, zemax};
use lens::model::GlassSpec;
use lens::paraxial::{imaging, FirstOrder, ObjectDistance};
use lens::Prescription;

fn shipped() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data"));
    let mut v: Vec<_> = [dir.to_path_buf(), dir.join("library")]
        .iter()
        .flat_map(|d| std::fs::read_dir(d).unwrap().map(|e| e.unwrap().path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    v
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

fn efl(p: &Prescription) -> f64 {
    FirstOrder::of(p).unwrap().efl
}

/// Every shipped lens written as `.seq` reads back as the same lens:
/// surfaces, glasses, aspheres, wavelengths, fields; the stop within
/// 1e-12 (sized again from the written EPD), the EFL within 1e-12. The
/// two lenses with odd aspheres are refused, by surface and reason.
#[test]
fn every_shipped_lens_round_trips_through_seq() {
    let (mut written, mut refused) = (0, 0);
    for path in shipped() {
        let p = Prescription::load(&path).unwrap();
        let name = path.display();
        let text = match codev::write(&p) {
            Ok(t) => t,
            Err(e) => {
                assert!(e.contains("odd asphere") && e.starts_with("surface "), "{name}: {e}");
                refused += 1;
                continue;
            }
        };
        let spec = codev::read(&text, Catalogs::shipped()).unwrap_or_else(|e| panic!("{name}: {e:?}\n{text}"));
        assert!(spec.warnings.is_empty(), "{name}: {:?}", spec.warnings);
        let q = Prescription::from_spec(&spec).unwrap();
        assert_eq!(p.surfaces().len(), q.surfaces().len(), "{name}");
        for (a, b) in p.surfaces().iter().zip(q.surfaces()) {
            assert!(close(a.curvature, b.curvature, 1e-15), "{name}: {a:?} {b:?}");
            assert_eq!(a.thickness, b.thickness, "{name}");
            assert_eq!(a.ior, b.ior, "{name}");
            assert_eq!(a.stop, b.stop, "{name}");
            assert_eq!(a.asphere, b.asphere, "{name}");
            match (a.semi_diameter, b.semi_diameter) {
                (Some(x), Some(y)) => assert!(close(x, y, 1e-12), "{name}: {x} {y}"),
                (x, y) => assert_eq!(x, y, "{name}"),
            }
        }
        assert_eq!(p.glasses(), q.glasses(), "{name}");
        assert_eq!(p.wavelengths_nm(), q.wavelengths_nm(), "{name}");
        assert_eq!(p.wavelength_weights(), q.wavelength_weights(), "{name}");
        assert_eq!(p.primary_wavelength_nm(), q.primary_wavelength_nm(), "{name}");
        assert_eq!(p.fields_deg(), q.fields_deg(), "{name}");
        assert_eq!(p.object_distance_mm(), q.object_distance_mm(), "{name}");
        assert!(close(efl(&p), efl(&q), 1e-12), "{name}: {} vs {}", efl(&p), efl(&q));
        written += 1;
    }
    assert_eq!((written, refused), (34, 2));
}

/// `.zmx` -> `.seq` -> JSON keeps the EFL to 1e-12 relative.
#[test]
fn zmx_to_seq_to_json_keeps_the_focal_length() {
    for path in shipped() {
        let p = Prescription::load(&path).unwrap();
        // (odd aspheres beyond r^8 are refused by the .zmx writer, all
        // odd ones by the .seq writer)
        let Ok(zmx) = zemax::write(&p) else { continue };
        let z = Prescription::from_spec(&zemax::read(&zmx, Catalogs::shipped()).unwrap()).unwrap();
        let Ok(seq) = codev::write(&z) else { continue };
        let spec = codev::read(&seq, Catalogs::shipped()).unwrap();
        let json = lens::PrescriptionSpec::from_json_str(&spec.to_json_string(), "<json>").unwrap();
        let q = Prescription::from_spec(&json).unwrap();
        assert!(close(efl(&p), efl(&q), 1e-12), "{}: {} vs {}", path.display(), efl(&p), efl(&q));
    }
}

/// A file in CODE V's own layout (as CODE V and rayoptics write them):
/// curvatures (`RDM N`), inches, glasses by CODE V's names and as codes, a
/// private glass, the paraxial image solve and a defocus on `SI`, the
/// aperture as `FNO`, fields as image heights, vignetting factors.
const SEQ: &str = "RDM N;LEN \"VERSION: 10.7\"
TITLE 'Test triplet; in inches'
FNO 4
DIM I
WL 656.2725 587.5618 486.1327
REF 2
WTW 1 2 1
INI ' '
YIM 0 0.3 0.4
VUY 0 0.2 0.4
VLY 0 0.25 0.4
PRV
PWL 587.5618 656.2725
'PLATE' 1.5 1.5
END
SO 0.0 1e+12
S 0.0671 0.1 NSK16_SCHOTT ! first element
  CCY 0
  CIR 0.5
S -0.0058 0.2
S -0.0558 0.04 SF2_SCHOTT
  CIR 0.4
S 0.0582 0.15
  CIR 0.4
  STO
S 0.0126 0.1 620000.6030
  ASP
  K -0.5
  A 1e-3
S -0.0718 0.05
S 0 0.02 PLATE
S 0 1.0
  PIM
SI 0 0.01
DER VAL I1 1e-5
GO
";

#[test]
fn a_seq_in_codev_layout_reads_as_it_says() {
    let spec = codev::read(SEQ, Catalogs::shipped()).unwrap();
    assert_eq!(spec.name.as_deref(), Some("Test triplet; in inches"));
    let s = &spec.surfaces;
    assert_eq!(s.len(), 8);
    // curvatures in 1/inch: radius = 25.4 / c mm
    assert!(close(s[0].radius.unwrap(), 25.4 / 0.0671, 1e-15));
    assert_eq!(s[0].thickness, 0.1 * 25.4);
    assert_eq!(s[0].glass, Some(GlassSpec::Name("SCHOTT:N-SK16".into())));
    assert_eq!(s[2].glass, Some(GlassSpec::Name("SCHOTT:SF2".into())));
    assert_eq!(s[4].glass, Some(GlassSpec::Model { nd: 1.62, vd: 60.3 }));
    assert_eq!(s[6].ior, Some(1.5));
    assert_eq!(s[0].semi_diameter, Some(0.5 * 25.4));
    assert!(s[3].stop && s.iter().filter(|x| x.stop).count() == 1);
    assert_eq!(s[4].conic, Some(-0.5));
    // A is r^4: 1e-3 inch^-3 in mm^-3
    let a = s[4].aspheric.as_deref().unwrap();
    assert!(a.len() == 2 && a[0] == 0.0 && close(a[1], 1e-3 * 25.4f64.powi(-3), 1e-15), "{a:?}");
    assert_eq!(spec.wavelength_weights, Some(vec![1.0, 2.0, 1.0]));
    assert_eq!(spec.primary_wavelength_nm, Some(587.5618));
    assert_eq!(spec.object_distance_mm, None, "1e12 inches is infinity");
    let p = Prescription::from_spec(&spec).unwrap();
    let first = FirstOrder::of(&p).unwrap();
    // FNO 4 sized the stop; PIM put the film at the paraxial image, SI's
    // 0.01 inch defocus after it
    assert!(close(first.f_number, 4.0, 1e-12), "{}", first.f_number);
    let film = p.surfaces().last().unwrap().thickness;
    assert!(close(film, first.bfl + 0.01 * 25.4, 1e-12), "{film} vs {}", first.bfl);
    // image heights became angles; vignetting as Zemax's factors
    let fields = spec.fields_deg.as_ref().unwrap();
    assert_eq!(fields.len(), 3);
    assert!(fields[0] == 0.0 && fields[1] > 0.0 && fields[2] > fields[1]);
    let v = &spec.vignetting_factors.as_ref().unwrap()[1];
    assert!(close(v.decenter_y, 0.025, 1e-12) && close(v.compress_y, 0.225, 1e-12), "{v:?}");
    // what was not read is listed with its lines, never dropped silently
    let w = spec.warnings.join("\n");
    for listed in ["LEN \"VERSION: 10.7\" (line 1)", "INI (line 8)", "CCY (line 18)", "DER (line 35)"] {
        assert!(w.contains(listed), "{listed}: {w}");
    }
}

#[test]
fn what_seq_cannot_hold_is_refused_by_line() {
    let with = |from: &str, to: &str| {
        let text = SEQ.replacen(from, to, 1);
        codev::read(&text, Catalogs::shipped()).unwrap_err()
    };
    let e = with("S -0.0058 0.2\n", "S -0.0058 0.2 REFL\n");
    assert!(e.line == 20 && e.message.contains("mirrors"), "{e:?}");
    let e = with("  CCY 0\n", "  ADE 0.5\n");
    assert!(e.line == 18 && e.message.contains("decentre or tilt"), "{e:?}");
    let e = with("NSK16_SCHOTT", "NBK77_SCHOTT");
    assert!(e.message.contains("glass NBK77_SCHOTT") && e.message.contains("NBK7_SCHOTT is SCHOTT:N-BK7"), "{e:?}");
    let e = with("YIM 0 0.3 0.4", "XAN 0 1 2\nYAN 0 1 2");
    assert!(e.message.contains("XAN"), "{e:?}");
    let e = with("SI 0 0.01", "SI -0.5 0");
    assert!(e.message.contains("curved"), "{e:?}");
    let e = with("FNO 4", "FNO -4");
    assert!(e.message.contains("FNO -4"), "{e:?}");
    let e = with("S 0.0671 0.1", "S 0.0671 x");
    assert!(e.line == 17 && e.message.contains("thickness \"x\""), "{e:?}");
    let e = with("'PLATE' 1.5 1.5\nEND\n", "'PLATE' 1.5 1.5\n");
    assert!(e.line == 15 && e.message.contains("in the PRV block of line 12"), "{e:?}");
    let e = with("SO 0.0 1e+12", "SO");
    assert!(e.line == 16 && e.message.contains("SO: give the object thickness"), "{e:?}");
    // writing: what CODE V's ASP cannot hold
    let p = Prescription::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../lens-data/library/phone-5.6mm-f3.5-us7535658.json"
    )))
    .unwrap();
    assert!(codev::write(&p).unwrap_err().starts_with("surface 2: an odd asphere"));
}

/// The thick-lens model pbrt-v4's realistic camera makes of a lens file,
/// from its documented rules: elements front to back (radius, thickness
/// to the next, the index behind the element, 0 read as 1; aperture
/// diameter), radius 0 the aperture stop (no refraction); a ray parallel
/// to the axis traced through the spheres from the scene side finds the
/// rear focal point and principal plane, one from the film side the front
/// ones. Returns (front principal plane, front focal point, rear principal
/// plane, rear focal point), z in mm from the first vertex.
fn pbrt_cardinal_points(text: &str) -> (f64, f64, f64, f64) {
    let rows: Vec<[f64; 4]> = text
        .lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect();
    let eta = |k: usize| if rows[k][2] == 0.0 { 1.0 } else { rows[k][2] };
    let mut z = vec![0.0];
    for r in &rows[..rows.len() - 1] {
        z.push(z.last().unwrap() + r[1]);
    }
    // refracts (y, u) (height, slope) at the sphere of radius r whose
    // vertex is at zv, from index n1 to n2, exactly (a real ray in a
    // meridional plane)
    let refract = |p: [f64; 2], d: [f64; 2], zv: f64, r: f64, n1: f64, n2: f64| -> ([f64; 2], [f64; 2]) {
        // centre at zv + r on the axis; p = (z, y), d unit (dz, dy)
        let c = [zv + r, 0.0];
        let o = [p[0] - c[0], p[1] - c[1]];
        let b = o[0] * d[0] + o[1] * d[1];
        let disc = b * b - (o[0] * o[0] + o[1] * o[1] - r * r);
        let t = if (r > 0.0) == (d[0] > 0.0) { -b - disc.sqrt() } else { -b + disc.sqrt() };
        let hit = [p[0] + t * d[0], p[1] + t * d[1]];
        let mut nrm = [(hit[0] - c[0]) / r.abs(), (hit[1] - c[1]) / r.abs()];
        if nrm[0] * d[0] + nrm[1] * d[1] > 0.0 {
            nrm = [-nrm[0], -nrm[1]];
        }
        let mu = n1 / n2;
        let cos_i = -(nrm[0] * d[0] + nrm[1] * d[1]);
        let k = 1.0 - mu * mu * (1.0 - cos_i * cos_i);
        let f = mu * cos_i - k.sqrt();
        (hit, [mu * d[0] + f * nrm[0], mu * d[1] + f * nrm[1]])
    };
    let h = 1e-4;
    // from the scene: (z, y) start before the first vertex, travelling +z
    let (mut p, mut d) = ([-1.0, h], [1.0, 0.0]);
    for k in 0..rows.len() {
        if rows[k][0] == 0.0 {
            continue;
        }
        let n1 = if k == 0 { 1.0 } else { eta(k - 1) };
        (p, d) = refract(p, d, z[k], rows[k][0], n1, eta(k));
    }
    let axis = |p: [f64; 2], d: [f64; 2]| p[0] - p[1] * d[0] / d[1];
    let level = |p: [f64; 2], d: [f64; 2]| p[0] + (h - p[1]) * d[0] / d[1];
    let (rear_focal, rear_principal) = (axis(p, d), level(p, d));
    // from the film: travelling -z, in the last element's medium behind it
    let n = rows.len();
    let (mut p, mut d) = ([z[n - 1] + 1.0, h], [-1.0, 0.0]);
    for k in (0..n).rev() {
        if rows[k][0] == 0.0 {
            continue;
        }
        let n2 = if k == 0 { 1.0 } else { eta(k - 1) };
        (p, d) = refract(p, d, z[k], rows[k][0], eta(k), n2);
    }
    (level(p, d), axis(p, d), rear_principal, rear_focal)
}

/// The double Gauss written for pbrt-v4 focuses, under pbrt's own rules
/// (its thick-lens model), where this project's paraxial model does: the
/// focal points and principal planes within 1e-8 mm, and the film for an
/// object 1 m away within 1e-6 mm. A lens with glasses needs a
/// wavelength; what pbrt cannot hold is refused.
#[test]
fn pbrt_export_focuses_where_the_lens_does() {
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../lens-data"));
    let p = Prescription::load(dir.join("double-gauss-50mm.json")).unwrap();
    assert!(dat::write_dat(&p, None).unwrap_err().contains("--wavelength-nm"));
    let text = dat::write_dat(&p, Some(587.5618)).unwrap();
    let f = FirstOrder::of(&p.at_wavelength(587.5618).unwrap()).unwrap();
    let (fp, ff, rp, rf) = pbrt_cardinal_points(&text);
    let last = p.last_vertex_z();
    for (what, pbrt, ours) in [
        ("front principal plane", fp, f.front_principal_plane),
        ("front focal point", ff, f.ffd),
        ("rear principal plane", rp, f.back_principal_plane),
        ("rear focal point", rf, last + f.bfl),
    ] {
        assert!((pbrt - ours).abs() < 1e-8, "{what}: pbrt {pbrt} vs ours {ours}");
    }
    // the thick-lens focus of an object 1000 mm in front of the first vertex
    let efl = rf - rp;
    let s = fp + 1000.0;
    let image = rp + 1.0 / (1.0 / efl - 1.0 / s);
    let ours = last + imaging(&p, &f, ObjectDistance::Finite(1000.0)).unwrap().image_distance;
    assert!((image - ours).abs() < 1e-6, "pbrt's film {image} vs ours {ours}");
    // the file reads back through our pbrt reader as the same lens
    let back = Prescription::from_spec(&dat::parse_dat(&text, "<dat>").unwrap()).unwrap();
    assert!(close(FirstOrder::of(&back).unwrap().efl, f.efl, 1e-12));
    // refusals, by surface
    let refused =
        |file: &str| dat::write_dat(&Prescription::load(dir.join(file)).unwrap(), Some(587.5618)).unwrap_err();
    assert!(refused("plano-convex-n-bk7-50mm.json").contains("a plane refracting surface"));
    assert!(refused("library/phone-5.6mm-f3.5-us7535658.json").contains("an asphere"));
}
