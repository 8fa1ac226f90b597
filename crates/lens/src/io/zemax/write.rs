//! Writing a prescription as a Zemax sequential lens file (`.zmx`), text
//! that [`fn@super::read`] and optical design programs read back.

use crate::model::Prescription;
use crate::paraxial::FirstOrder;

/// The Abbe number a constant index is written with: a model glass this
/// close to non-dispersive reads back as a constant index (0, which would
/// say so directly, is a division by zero to other programs).
pub const NON_DISPERSIVE_ABBE: f64 = 1e9;

/// A number as Zemax files write them: enough digits to read back the same
/// f64 (Rust's shortest round-trip form, in exponent notation).
fn z(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:E}")
    }
}

/// The prescription as the text of a `.zmx` file: lens units mm, the
/// aperture as the paraxial entrance pupil diameter (`ENPD`, or `FLOA` for an
/// afocal system), the wavelengths in µm with the primary, the design's
/// field angles, an object surface at the design's distance (or infinity),
/// one `SURF` per surface (`STANDARD`, `EVENASPH` or `ODDASPHE`), and the
/// image. A decentred or tilted surface or element sits between two
/// coordinate breaks (`COORDBRK`: the decentre and tilts, order 0; then
/// the same negated, order 1), the run's last thickness taking the axis
/// back to its first vertex and the second break's on to the next
/// surface, so the surfaces after it are where they were. Catalogue glasses are written by name with their vendors in
/// `GCAT`; model glasses as Zemax model glasses (`___BLANK`, type 1); a
/// constant index as a model glass of Abbe number
/// [`NON_DISPERSIVE_ABBE`] (its index changes by less than 1e-9 over the
/// visible), which [`fn@super::read`] reads back as a constant index.
///
/// Errors (naming the surface) when a surface has terms Zemax's types do
/// not hold: odd-asphere terms beyond r^8 (`ODDASPHE` has eight).
pub fn write(p: &Prescription) -> Result<String, String> {
    for (i, s) in p.surfaces().iter().enumerate() {
        if let Some(a) = &s.asphere {
            if !a.is_even() && a.degree() > 8 {
                return Err(format!(
                    "surface {}: an odd asphere with terms to r^{}: Zemax's ODDASPHE holds r^1 to r^8 only; write JSON instead",
                    i + 1,
                    a.degree()
                ));
            }
        }
    }
    let mut o = String::new();
    let mut line = |s: String| {
        o.push_str(&s);
        o.push('\n');
    };
    line("VERS 190513 80 123457 L123457".into());
    line("MODE SEQ".into());
    line(format!("NAME {}", p.name().replace(['\n', '\r'], " ")));
    line("UNIT MM X W X CM MR CPMM".into());
    match FirstOrder::of(p) {
        Ok(f) => line(format!("ENPD {}", z(f.entrance_pupil.diameter))),
        Err(_) => line("FLOA".into()),
    }
    let mut vendors: Vec<String> = Vec::new();
    for g in p.glasses() {
        if g.catalog != "MODEL" && !vendors.contains(&g.catalog) {
            vendors.push(g.catalog.clone());
        }
    }
    if !vendors.is_empty() {
        line(format!("GCAT {}", vendors.join(" ")));
    }
    let mut waves: Vec<f64> = p.wavelengths_nm().to_vec();
    let mut weights = p.wavelength_weights();
    let primary = p.primary_wavelength_nm();
    let pw = waves.iter().position(|w| *w == primary).unwrap_or_else(|| {
        waves.push(primary);
        weights.push(0.0);
        waves.len() - 1
    });
    let fields: Vec<f64> = if p.fields_deg().is_empty() { vec![0.0] } else { p.fields_deg().to_vec() };
    line(format!("FTYP 0 0 {} {} 0 0 0", fields.len(), waves.len()));
    line(format!("XFLN {}", vec!["0"; fields.len()].join(" ")));
    line(format!("YFLN {}", fields.iter().map(|f| z(*f)).collect::<Vec<_>>().join(" ")));
    let vig = p.vignetting_factors();
    if !vig.is_empty() {
        let row = |key: &str, of: fn(&crate::model::VignettingFactors) -> f64| {
            format!("{key} {}", vig.iter().map(|v| z(of(v))).collect::<Vec<_>>().join(" "))
        };
        line(row("VDXN", |v| v.decenter_x));
        line(row("VDYN", |v| v.decenter_y));
        line(row("VCXN", |v| v.compress_x));
        line(row("VCYN", |v| v.compress_y));
    }
    for (i, (w, weight)) in waves.iter().zip(&weights).enumerate() {
        line(format!("WAVM {} {} {}", i + 1, z(w / 1000.0), z(*weight)));
    }
    line(format!("PWAV {}", pw + 1));
    line("SURF 0".into());
    line("  TYPE STANDARD".into());
    line("  CURV 0".into());
    line(match p.object_distance_mm() {
        Some(d) => format!("  DISZ {}", z(d)),
        None => "  DISZ INFINITY".into(),
    });
    // a decentred or tilted run of surfaces sits between a coordinate
    // break and the one that undoes it; its last surface's thickness goes
    // back to the run's first vertex, and the undoing break's goes on to
    // the next surface (the coordinates restored on the axis)
    let z_at = p.vertex_z();
    let mut number = 0;
    let mut next_surf = |line: &mut dyn FnMut(String)| {
        number += 1;
        line(format!("SURF {number}"));
    };
    let brk = |line: &mut dyn FnMut(String), d: [f64; 2], t: [f64; 2], undo: bool, disz: f64| {
        let sign = if undo { -1.0 } else { 1.0 };
        line("  TYPE COORDBRK".into());
        line("  CURV 0 0 0 0 0 \"\"".into());
        for (k, v) in [d[0], d[1], t[0], t[1]].iter().enumerate() {
            line(format!("  PARM {} {}", k + 1, z(sign * v)));
        }
        line("  PARM 5 0".into());
        line(format!("  PARM 6 {}", u8::from(undo)));
        line(format!("  DISZ {}", z(disz)));
    };
    for (i, s) in p.surfaces().iter().enumerate() {
        let element = p.elements().iter().find(|e| (e.surfaces[0]..=e.surfaces[1]).contains(&(i + 1)));
        let motion =
            |e: &crate::model::ElementSpec| (e.decenter_mm.unwrap_or([0.0; 2]), e.tilt_deg.unwrap_or([0.0; 2]));
        if let Some(e) = element.filter(|e| e.surfaces[0] == i + 1) {
            let (d, t) = motion(e);
            next_surf(&mut line);
            brk(&mut line, d, t, false, 0.0);
        }
        let own = s.decenter_mm != [0.0; 2] || s.tilt_deg != [0.0; 2];
        if own {
            next_surf(&mut line);
            brk(&mut line, s.decenter_mm, s.tilt_deg, false, 0.0);
        }
        let closes = element.filter(|e| e.surfaces[1] == i + 1);
        let thickness = closes.map_or(s.thickness, |e| z_at[e.surfaces[0] - 1] - z_at[i]);
        next_surf(&mut line);
        let kind = match &s.asphere {
            _ if s.paraxial.is_some() => "PARAXIAL",
            Some(a) if a.degree() > 0 && !a.is_even() => "ODDASPHE",
            Some(a) if a.degree() > 0 => "EVENASPH",
            _ => "STANDARD",
        };
        if s.stop {
            line("  STOP".into());
        }
        line(format!("  TYPE {kind}"));
        line(format!("  CURV {} 0 0 0 0 \"\"", z(s.curvature)));
        if let Some(f) = s.paraxial {
            // the focal length, and OPD mode 0 (exact for a plane wave)
            line(format!("  PARM 1 {}", z(f)));
            line("  PARM 2 0".into());
        }
        if let Some(a) = &s.asphere {
            let terms = if kind == "ODDASPHE" { a.all_terms() } else { a.even_terms() };
            for (k, t) in terms.iter().enumerate() {
                line(format!("  PARM {} {}", k + 1, z(*t)));
            }
            if a.conic != 0.0 {
                line(format!("  CONI {}", z(a.conic)));
            }
        }
        line(format!("  DISZ {}", z(if own { 0.0 } else { thickness })));
        match s.glass.and_then(|g| p.glasses().get(g)) {
            Some(g) if g.catalog == "MODEL" => {
                let (nd, vd) = (g.catalog_nd.unwrap_or(s.ior), g.catalog_vd.unwrap_or(0.0));
                line(format!("  GLAS ___BLANK 1 0 {} {} 0 0 0 0 0 0", z(nd), z(vd)));
            }
            Some(g) => {
                let (nd, vd) = (g.catalog_nd.unwrap_or(0.0), g.catalog_vd.unwrap_or(0.0));
                line(format!("  GLAS {} 0 0 {} {} 0 0 0 0 0 0", g.name, z(nd), z(vd)));
            }
            None if s.ior != 1.0 => {
                line(format!("  GLAS ___BLANK 1 0 {} {} 0 0 0 0 0 0", z(s.ior), z(NON_DISPERSIVE_ABBE)))
            }
            None => {}
        }
        if let Some(sd) = s.semi_diameter {
            // a fixed semi-diameter, and a floating aperture there: our
            // clear apertures clip, Zemax's semi-diameters alone do not
            line(format!("  DIAM {} 1 0 0 1 \"\"", z(sd)));
            if !s.stop {
                line(format!("  FLAP 0 {} 0", z(sd)));
            }
        }
        if own {
            next_surf(&mut line);
            brk(&mut line, s.decenter_mm, s.tilt_deg, true, thickness);
        }
        if let Some(e) = closes {
            let (d, t) = motion(e);
            next_surf(&mut line);
            brk(&mut line, d, t, true, z_at[i] - z_at[e.surfaces[0] - 1] + s.thickness);
        }
    }
    line(format!("SURF {}", number + 1));
    line("  TYPE STANDARD".into());
    line("  CURV 0".into());
    line("  DISZ 0".into());
    Ok(o)
}
