//! Writing a prescription as a CODE V `.seq` file that [`super::read`]
//! reads back to the same lens.

use crate::model::{Prescription, VignettingFactors};
use crate::paraxial::FirstOrder;

/// A number as the file writes it: Rust's shortest form that reads back
/// the same f64.
fn n(x: f64) -> String {
    format!("{x:?}")
}

/// The prescription as a CODE V `.seq` file that [`super::read`] reads back to the
/// same lens: `RDM`, the title, `DIM M`, `WL`/`WTW`/`REF`, `EPD` (the
/// paraxial entrance pupil), `YAN` and the vignetting factors as
/// `VUX`..`VLY`, `SO`, one `S` per surface (`CIR` its clear aperture, `STO`,
/// `ASP` with `K` and `A`..`J`), `SI` and `GO`. Catalogue glasses are
/// written `NAME_VENDOR` (hyphens and spaces left out, as CODE V names
/// them); model glasses as fictitious codes (the digits of nd after "1.",
/// then of vd / 100: read back to the same f64s); a constant index as a
/// private glass (`PRV`).
///
/// Refused, with the surface and the reason: decentred or tilted
/// surfaces, odd aspheres and an r^2 term (CODE V's `ASP` starts at r^4),
/// terms beyond r^20, ideal (paraxial) surfaces, model glasses of Abbe
/// number 100 or more.
pub fn write(p: &Prescription) -> Result<String, String> {
    let mut o = String::new();
    let mut line = |s: String| {
        o.push_str(&s);
        o.push('\n');
    };
    let private: Vec<f64> = {
        let mut v: Vec<f64> = Vec::new();
        for s in p.surfaces() {
            if s.glass.is_none() && s.ior != 1.0 && !v.contains(&s.ior) {
                v.push(s.ior);
            }
        }
        v
    };
    line(format!("! {} (written by lens)", p.name().replace(['\n', '\r'], " ")));
    line("RDM Y".into());
    // quotes end the title, and other readers split commands at ; and
    // comments at ! even inside it
    line(format!("TITLE '{}'", p.name().replace(['\n', '\r', '\'', '"', '!'], " ").replace(';', ",")));
    line("DIM M".into());
    let waves = p.wavelengths_nm();
    line(format!("WL {}", waves.iter().map(|w| n(*w)).collect::<Vec<_>>().join(" ")));
    line(format!("WTW {}", p.wavelength_weights().iter().map(|w| n(*w)).collect::<Vec<_>>().join(" ")));
    let primary = p.primary_wavelength_nm();
    match waves.iter().position(|w| *w == primary) {
        Some(k) => line(format!("REF {}", k + 1)),
        None => return Err(format!("the primary wavelength {primary} nm is not one of the wavelengths")),
    }
    let first = FirstOrder::of(p).map_err(|e| format!("the entrance pupil (EPD) cannot be written: {e}"))?;
    line(format!("EPD {}", n(first.entrance_pupil.diameter)));
    if !p.fields_deg().is_empty() {
        line(format!("YAN {}", p.fields_deg().iter().map(|f| n(*f)).collect::<Vec<_>>().join(" ")));
        let vig = p.vignetting_factors();
        if !vig.is_empty() {
            let row = |name: &str, f: &dyn Fn(&VignettingFactors) -> f64| {
                format!("{name} {}", vig.iter().map(|v| n(f(v))).collect::<Vec<_>>().join(" "))
            };
            // upper = compress - decenter, lower = compress + decenter
            line(row("VUX", &|v| v.compress_x - v.decenter_x));
            line(row("VLX", &|v| v.compress_x + v.decenter_x));
            line(row("VUY", &|v| v.compress_y - v.decenter_y));
            line(row("VLY", &|v| v.compress_y + v.decenter_y));
        }
    }
    if !private.is_empty() {
        line("PRV".into());
        line(format!("PWL {}", n(primary)));
        for (k, ior) in private.iter().enumerate() {
            line(format!("'IOR{}' {}", k + 1, n(*ior)));
        }
        line("END".into());
    }
    line(format!("SO 0 {}", p.object_distance_mm().map_or("1e+20".to_string(), n)));
    for (i, s) in p.surfaces().iter().enumerate() {
        let k = i + 1;
        let refuse = |why: &str| Err(format!("surface {k}: {why}; a CODE V .seq file is not written with it"));
        if s.decenter_mm != [0.0; 2]
            || s.tilt_deg != [0.0; 2]
            || p.elements().iter().any(|e| (e.surfaces[0]..=e.surfaces[1]).contains(&k))
        {
            return refuse("decentred or tilted (write .zmx or JSON to keep the motions)");
        }
        if s.paraxial.is_some() {
            return refuse("an ideal (paraxial) lens");
        }
        let glass = match s.glass.and_then(|g| p.glasses().get(g)) {
            Some(g) if g.catalog == "MODEL" => {
                let (nd, vd) = (g.catalog_nd.unwrap_or(s.ior), g.catalog_vd.unwrap_or(0.0));
                if !(vd > 0.0 && vd < 100.0) {
                    return refuse(&format!(
                        "a model glass of Abbe number {vd} (a fictitious glass code holds 0 to 100)"
                    ));
                }
                match fictitious(nd, vd) {
                    Some(code) => format!(" {code}"),
                    None => {
                        return refuse(&format!(
                            "a model glass of nd {nd}, vd {vd}: a fictitious glass code holds nd from 1 to 2"
                        ))
                    }
                }
            }
            Some(g) => {
                format!(" {}_{}", g.name.chars().filter(|c| !matches!(c, '-' | ' ')).collect::<String>(), g.catalog)
            }
            None if s.ior != 1.0 => format!(" IOR{}", private.iter().position(|x| *x == s.ior).unwrap_or(0) + 1),
            None => String::new(),
        };
        let r = if s.curvature == 0.0 { "0".to_string() } else { n(1.0 / s.curvature) };
        line(format!("S {r} {}{glass}", n(s.thickness)));
        if s.stop {
            line("  STO".into());
        }
        if let Some(sd) = s.semi_diameter {
            line(format!("  CIR {}", n(sd)));
        }
        if let Some(a) = &s.asphere {
            if !a.is_even() {
                return refuse("an odd asphere (CODE V's ASP is even)");
            }
            let terms = a.even_terms();
            if terms.first().is_some_and(|t| *t != 0.0) {
                return refuse("an r^2 aspheric term (CODE V's ASP starts at r^4)");
            }
            if terms.len() > 10 {
                return refuse("aspheric terms beyond r^20 (CODE V's ASP ends at J, r^20)");
            }
            line("  ASP".into());
            line(format!("  K {}", n(a.conic)));
            for (t, letter) in terms.iter().skip(1).zip(["A", "B", "C", "D", "E", "F", "G", "H", "J"]) {
                if *t != 0.0 {
                    line(format!("  {letter} {}", n(*t)));
                }
            }
        }
    }
    line("SI 0 0".into());
    line("GO".into());
    Ok(o)
}

/// A fictitious glass code for (nd, vd): the digits of nd after "1." (at
/// least six), a point, then vd's digits with two before its point
/// (516800.6417 is nd 1.5168, vd 64.17), each as Rust's shortest form prints it, so that
/// [`super::read`] (which puts the points back and parses) gets the same f64s;
/// `None` for nd of 2 or more, or a form with an exponent.
fn fictitious(nd: f64, vd: f64) -> Option<String> {
    let x = format!("{nd:?}");
    let v = format!("{vd:?}");
    if x.contains('e') || v.contains('e') {
        return None;
    }
    let (i, f) = v.split_once('.')?;
    // at least six digits of nd, as CODE V's codes are written (670000.4710)
    Some(format!("{:0<6}.{:0>2}{}", x.strip_prefix("1.")?, i, f.trim_end_matches('0')))
}
