//! Reading a CODE V `.seq` file into a prescription spec (the commands
//! and glasses [`super`] lists).

use super::{err, SeqError};
use crate::glass::Catalogs;
use crate::model::{GlassSpec, Prescription, PrescriptionSpec, SurfaceSpec, VignettingFactors};
use crate::paraxial::FirstOrder;

/// Object distances at or beyond this (mm) are infinity, as CODE V takes
/// its 1e10 and larger.
const INFINITE_MM: f64 = 1e10;

/// One command: its name (upper case), its arguments, its line.
struct Command {
    name: String,
    args: Vec<String>,
    line: usize,
}

/// Splits the text into commands: `;` and new lines separate them, `!`
/// starts a comment, quotes (' or ") keep spaces in one argument.
fn commands(text: &str) -> Vec<Command> {
    let mut out = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let mut words: Vec<String> = Vec::new();
        let mut word = String::new();
        let mut quote: Option<char> = None;
        let flush = |words: &mut Vec<String>, word: &mut String| {
            if !word.is_empty() {
                words.push(std::mem::take(word));
            }
        };
        let mut lines: Vec<Vec<String>> = Vec::new();
        for c in raw.chars() {
            match quote {
                Some(q) if c == q => {
                    words.push(std::mem::take(&mut word));
                    quote = None;
                }
                Some(_) => word.push(c),
                None if c == '\'' || c == '"' => {
                    flush(&mut words, &mut word);
                    quote = Some(c);
                }
                None if c == '!' => break,
                None if c == ';' => {
                    flush(&mut words, &mut word);
                    lines.push(std::mem::take(&mut words));
                }
                None if c.is_whitespace() => flush(&mut words, &mut word),
                None => word.push(c),
            }
        }
        if quote.is_some() || !word.is_empty() {
            words.push(word);
        }
        lines.push(words);
        for w in lines.into_iter().filter(|w| !w.is_empty()) {
            let mut it = w.into_iter();
            let name = it.next().unwrap_or_default().to_ascii_uppercase();
            out.push(Command { name, args: it.collect(), line: k + 1 });
        }
    }
    out
}

/// The glass of a `.seq` surface.
enum SeqGlass {
    Air,
    Spec(GlassSpec),
    Ior(f64),
}

/// The surfaces and settings as read, before the aperture is set.
#[derive(Default)]
struct Reading {
    name: Option<String>,
    scale: f64,
    radius_mode: bool,
    waves: Vec<f64>,
    weights: Vec<f64>,
    reference: Option<usize>,
    epd: Option<f64>,
    fno: Option<f64>,
    fields: Vec<f64>,
    /// Fields given as heights: `YOB`, `YIM` or `YRI`, the heights, the line.
    heights: Option<(String, Vec<f64>, usize)>,
    vignetting: [Vec<f64>; 4],
    object: Option<f64>,
    surfaces: Vec<SurfaceSpec>,
    pim: bool,
    /// The image surface's thickness: a defocus from the last surface's
    /// (after `PIM`'s solve).
    defocus: f64,
    private: Vec<(String, f64)>,
    ignored: Vec<(String, usize)>,
}

/// Reads a CODE V `.seq` file into a prescription spec (not yet
/// validated), its glasses looked up in `catalogs`; the commands it could
/// not use are listed in the spec's `warnings`.
///
/// ```
/// let text = "RDM Y\nTIT 'a singlet'\nDIM M\nWL 587.5618\nEPD 10\nSO 0 1e10\n\
///             S 50 4 NBK7_SCHOTT\n  STO\n  CIR 6\nS -50 0\n  PIM\nSI 0 0\nGO\n";
/// let spec = lens::io::codev::read(text, lens::glass::Catalogs::shipped()).unwrap();
/// assert_eq!(spec.surfaces.len(), 2);
/// assert!(spec.surfaces[1].thickness > 40.0); // at the paraxial image
/// ```
pub fn read(text: &str, catalogs: &Catalogs) -> Result<PrescriptionSpec, SeqError> {
    let mut r = Reading { scale: 1.0, radius_mode: false, ..Reading::default() };
    // the line of the PRV that opened a private catalogue, until its END
    let mut in_private: Option<usize> = None;
    let mut private_waves = 0usize;
    let mut seen_image = false;
    for c in commands(text) {
        let line = c.line;
        let num = |i: usize, what: &str| -> Result<f64, SeqError> {
            let t = c.args.get(i).ok_or_else(|| err(line, format!("{}: give the {what}", c.name)))?;
            t.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| err(line, format!("{}: the {what} \"{t}\" is not a number", c.name)))
        };
        let nums = |what: &str| -> Result<Vec<f64>, SeqError> { (0..c.args.len()).map(|i| num(i, what)).collect() };
        if in_private.is_some() {
            match c.name.as_str() {
                "END" => in_private = None,
                "PWL" => private_waves = c.args.len(),
                _ => {
                    // 'NAME' n1 n2 ...: one index per PWL wavelength
                    let name = c.name.clone();
                    let n: Vec<f64> = c
                        .args
                        .iter()
                        .map(|t| t.parse::<f64>().ok().filter(|v| v.is_finite() && *v >= 1.0))
                        .collect::<Option<Vec<f64>>>()
                        .filter(|v| !v.is_empty() && (private_waves == 0 || v.len() == private_waves))
                        .ok_or_else(|| {
                            err(
                                line,
                                format!(
                                    "private glass {name} (in the PRV block of line {}): give 'NAME' and one index of 1 or more per PWL wavelength, and close the block with END",
                                    in_private.unwrap_or(0)
                                ),
                            )
                        })?;
                    if n.iter().any(|x| *x != n[0]) {
                        return Err(err(
                            line,
                            format!(
                                "private glass {name}: an index that changes with wavelength is not read; give a catalogue glass or a fictitious nd.vd code"
                            ),
                        ));
                    }
                    r.private.push((name.to_ascii_uppercase(), n[0]));
                }
            }
            continue;
        }
        let surface_cmd = matches!(c.name.as_str(), "S" | "STO" | "SO" | "SI") && !c.args.is_empty();
        match c.name.as_str() {
            "RDM" => {
                r.radius_mode = !matches!(c.args.first().map(|a| a.to_ascii_uppercase()).as_deref(), Some("N" | "NO"))
            }
            "TIT" | "TITLE" => r.name = c.args.first().cloned().filter(|s| !s.trim().is_empty()),
            "LEN" => {
                if let Some(a) = c.args.first().filter(|a| !a.eq_ignore_ascii_case("NEW")) {
                    r.ignored.push((format!("LEN \"{a}\""), line));
                }
            }
            "DIM" => {
                r.scale = match c.args.first().map(|a| a.to_ascii_uppercase()).as_deref() {
                    Some("M") => 1.0,
                    Some("C") => 10.0,
                    Some("I") => 25.4,
                    other => {
                        return Err(err(
                            line,
                            format!("DIM {}: give M (mm), C (cm) or I (inches)", other.unwrap_or("")),
                        ))
                    }
                }
            }
            "WL" => r.waves = nums("wavelength (nm)")?,
            "WTW" => r.weights = nums("wavelength weight")?,
            "REF" => r.reference = Some(num(0, "reference wavelength's number")? as usize),
            "EPD" => r.epd = Some(num(0, "entrance pupil diameter")?),
            "FNO" => r.fno = Some(num(0, "f-number")?),
            "YAN" => r.fields = nums("field angle (degrees)")?,
            "XAN" => {
                if nums("field angle (degrees)")?.iter().any(|x| *x != 0.0) {
                    return Err(err(
                        line,
                        "XAN: fields with x angles are not read (a prescription's fields are along y); give YAN",
                    ));
                }
            }
            "YOB" | "YIM" | "YRI" => r.heights = Some((c.name.clone(), nums("field height")?, line)),
            "XOB" | "XIM" | "XRI" => {
                if nums("field height")?.iter().any(|x| *x != 0.0) {
                    return Err(err(
                        line,
                        format!(
                            "{}: fields with x components are not read (a prescription's fields are along y)",
                            c.name
                        ),
                    ));
                }
            }
            "VUX" => r.vignetting[0] = nums("vignetting factor")?,
            "VLX" => r.vignetting[1] = nums("vignetting factor")?,
            "VUY" => r.vignetting[2] = nums("vignetting factor")?,
            "VLY" => r.vignetting[3] = nums("vignetting factor")?,
            "PRV" => in_private = Some(line),
            "SO" => {
                // SO t, or SO r t
                let t = num(c.args.len().clamp(1, 2) - 1, "object thickness")?;
                if c.args.len() >= 2 && num(0, "object radius")? != 0.0 {
                    return Err(err(line, "SO: a curved object surface is not read; give radius 0"));
                }
                r.object = (t.abs() < INFINITE_MM).then_some(t);
            }
            "S" | "STO" if surface_cmd => {
                if seen_image {
                    return Err(err(line, format!("{}: a surface after the image (SI)", c.name)));
                }
                let radius_or_curvature = num(0, "radius")?;
                let thickness = if c.args.len() > 1 { num(1, "thickness")? } else { 0.0 };
                let glass = match c.args.get(2) {
                    Some(g) => glass_of(g, line, catalogs, &r.private)?,
                    None => SeqGlass::Air,
                };
                let radius = if r.radius_mode {
                    (radius_or_curvature != 0.0).then_some(radius_or_curvature)
                } else {
                    (radius_or_curvature != 0.0).then(|| 1.0 / radius_or_curvature)
                };
                let (ior, glass) = match glass {
                    SeqGlass::Air => (None, None),
                    SeqGlass::Ior(n) => (Some(n), None),
                    SeqGlass::Spec(g) => (None, Some(g)),
                };
                r.surfaces.push(SurfaceSpec {
                    ior,
                    glass,
                    stop: c.name == "STO",
                    ..SurfaceSpec::new(radius, thickness)
                });
            }
            "SI" => {
                seen_image = true;
                if !c.args.is_empty() {
                    if num(0, "image radius")? != 0.0 {
                        return Err(err(line, "SI: the image surface is curved: only a flat film is supported"));
                    }
                    if c.args.len() > 1 {
                        r.defocus += num(1, "image thickness")?;
                    }
                }
            }
            "STO" => match r.surfaces.last_mut() {
                Some(s) if !seen_image => s.stop = true,
                _ => return Err(err(line, "STO: no lens surface before it to be the stop")),
            },
            "GO" => break,
            _ => surface_qualifier(&c, &mut r, seen_image, &num)?,
        }
    }
    if let Some(opened) = in_private {
        return Err(err(opened, "PRV: the private glass block has no END"));
    }
    to_spec(r, catalogs)
}

/// The commands that qualify the surface just given.
fn surface_qualifier(
    c: &Command,
    r: &mut Reading,
    seen_image: bool,
    num: &dyn Fn(usize, &str) -> Result<f64, SeqError>,
) -> Result<(), SeqError> {
    let line = c.line;
    let refused = |what: &str| Err(err(line, format!("{}: {what} is not read", c.name)));
    let last = if seen_image { None } else { r.surfaces.last_mut() };
    let Some(s) = last else {
        r.ignored.push((c.name.clone(), line));
        return Ok(());
    };
    let coefficient = |k: usize| -> Result<(usize, f64), SeqError> { Ok((k, num(0, "aspheric coefficient")?)) };
    let term = match c.name.as_str() {
        "CIR" if c.args.first().is_some_and(|a| a.parse::<f64>().is_err()) => {
            // CIR EDG (an edge aperture, drawn only) and other forms
            r.ignored.push((format!("CIR {}", c.args.join(" ")), line));
            None
        }
        "CIR" => {
            s.semi_diameter = Some(num(0, "clear-aperture radius")?);
            None
        }
        "SPH" | "CON" | "ASP" => None,
        "K" => {
            let k = num(0, "conic constant")?;
            s.conic = (k != 0.0).then_some(k);
            None
        }
        "A" => Some(coefficient(4)?),
        "B" => Some(coefficient(6)?),
        "C" => Some(coefficient(8)?),
        "D" => Some(coefficient(10)?),
        "E" => Some(coefficient(12)?),
        "F" => Some(coefficient(14)?),
        "G" => Some(coefficient(16)?),
        "H" => Some(coefficient(18)?),
        "J" => Some(coefficient(20)?),
        "RDY" => {
            let v = num(0, "radius")?;
            s.radius = (v != 0.0).then_some(v);
            None
        }
        "CUY" => {
            let v = num(0, "curvature")?;
            s.radius = (v != 0.0).then(|| 1.0 / v);
            None
        }
        "THI" => {
            s.thickness = num(0, "thickness")?;
            None
        }
        "PIM" => {
            r.pim = true;
            None
        }
        "ADE" | "BDE" | "CDE" | "XDE" | "YDE" | "ZDE" | "DAR" | "BEN" | "REV" | "RET" => {
            return refused("a decentre or tilt (write the lens as .zmx or JSON to keep it)")
        }
        "XTO" | "YTO" | "SPS" | "HOE" | "DOE" | "GRT" | "UDS" => return refused("this surface type"),
        "REFL" => return refused("a mirror"),
        _ => {
            r.ignored.push((c.name.clone(), line));
            None
        }
    };
    if let Some((power, v)) = term {
        // our even terms start at r^2: index power/2 - 1
        let a = s.aspheric.get_or_insert_with(Vec::new);
        let k = power / 2 - 1;
        if a.len() <= k {
            a.resize(k + 1, 0.0);
        }
        a[k] = v;
    }
    Ok(())
}

/// A `.seq` glass: `REFL` (refused), a private glass by name, `nd:vd`, a
/// fictitious glass code `nnnn.vvvv` or a 6-digit code `nnnvvv` (nd 1.nnn,
/// vd vv.v),
/// or `NAME_VENDOR` (hyphens and spaces left out of NAME).
fn glass_of(text: &str, line: usize, catalogs: &Catalogs, private: &[(String, f64)]) -> Result<SeqGlass, SeqError> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("REFL") {
        return Err(err(line, "REFL: mirrors are not read (refracting lenses only)"));
    }
    if t.eq_ignore_ascii_case("AIR") {
        return Ok(SeqGlass::Air);
    }
    if let Some((_, n)) = private.iter().find(|(name, _)| name.eq_ignore_ascii_case(t)) {
        return Ok(if *n == 1.0 { SeqGlass::Air } else { SeqGlass::Ior(*n) });
    }
    if let Some((nd, vd)) = t.split_once(':').and_then(|(a, b)| Some((a.parse::<f64>().ok()?, b.parse::<f64>().ok()?)))
    {
        // n:v, a model glass written as its nd and vd
        return if nd > 1.0 && nd.is_finite() && vd > 0.0 && vd.is_finite() {
            Ok(SeqGlass::Spec(GlassSpec::Model { nd, vd }))
        } else {
            Err(err(line, format!("glass {t}: not an index above 1 and an Abbe number above 0")))
        };
    }
    if t.chars().all(|c| c.is_ascii_digit() || c == '.') && t.chars().any(|c| c.is_ascii_digit()) {
        let (a, b) = t.split_once('.').unwrap_or((t, ""));
        let model = |nd: f64, vd: f64| {
            if nd > 1.0 && vd > 0.0 {
                Ok(SeqGlass::Spec(GlassSpec::Model { nd, vd }))
            } else {
                Err(err(line, format!("glass code {t}: not an index above 1 and an Abbe number above 0")))
            }
        };
        let parse = |s: String| s.parse::<f64>().unwrap_or(f64::NAN);
        if b.is_empty() && a.len() == 6 {
            // nnnvvv: nd 1.nnn, vd vv.v
            return model(parse(format!("1.{}", &a[..3])), parse(format!("{}.{}", &a[3..5], &a[5..])));
        }
        // fictitious: the digits of nd after "1.", then of vd / 100
        let b = format!("{b:0<2}");
        return model(parse(format!("1.{a}")), parse(format!("{}.{}", &b[..2], &b[2..])));
    }
    let (name, vendor) = match t.rsplit_once('_') {
        Some((n, v)) => (n, Some(v)),
        None => (t, None),
    };
    let squash = |s: &str| s.chars().filter(|c| !matches!(c, '-' | ' ' | '_')).collect::<String>().to_ascii_uppercase();
    let wanted = squash(name);
    let mut hits: Vec<String> = Vec::new();
    for c in &catalogs.catalogs {
        if vendor.is_some_and(|v| !c.name.eq_ignore_ascii_case(v)) {
            continue;
        }
        for g in c.glasses.iter().filter(|g| squash(&g.name) == wanted) {
            let full = g.full_name();
            if !hits.contains(&full) {
                hits.push(full);
            }
        }
    }
    match hits.as_slice() {
        [one] => Ok(SeqGlass::Spec(GlassSpec::Name(one.clone()))),
        [] => Err(err(
            line,
            format!(
                "glass {t}: no loaded catalogue{} has a glass of that name (CODE V leaves hyphens and spaces out: NBK7_SCHOTT is SCHOTT:N-BK7); give the vendor's catalogue with --glass-catalog, or a fictitious glass nd.vd code",
                vendor.map_or(String::new(), |v| format!(" of vendor {v}"))
            ),
        )),
        many => Err(err(line, format!("glass {t}: several glasses match: {}; name the vendor (NAME_VENDOR)", many.join(", ")))),
    }
}

/// The spec of what was read: lengths scaled to mm, the aperture from
/// EPD or FNO (the stop resized), the last thickness at the paraxial
/// image if `PIM` asked.
fn to_spec(r: Reading, catalogs: &Catalogs) -> Result<PrescriptionSpec, SeqError> {
    let s = r.scale;
    if r.surfaces.is_empty() {
        return Err(err(0, "no surfaces (S lines) between SO and SI"));
    }
    let mut surfaces = r.surfaces;
    for x in &mut surfaces {
        x.radius = x.radius.map(|v| v * s);
        x.thickness *= s;
        x.semi_diameter = x.semi_diameter.map(|v| v * s);
        if let Some(a) = &mut x.aspheric {
            // the coefficient of r^j is in length^(1-j)
            for (k, c) in a.iter_mut().enumerate() {
                *c *= s.powi(1 - 2 * (k as i32 + 1));
            }
        }
    }
    if !surfaces.iter().any(|x| x.stop) {
        // CODE V's default stop is surface 1
        surfaces[0].stop = true;
    }
    let n = r.waves.len();
    if r.weights.len() > n || (!r.weights.is_empty() && r.weights.len() != n) {
        return Err(err(0, format!("WTW gives {} weights for {n} wavelengths (WL)", r.weights.len())));
    }
    let primary = match r.reference {
        Some(k) if k >= 1 && k <= n => Some(r.waves[k - 1]),
        Some(k) => return Err(err(0, format!("REF {k}: there are {n} wavelengths (WL)"))),
        // REF 1 unless given, as rayoptics reads CODE V
        None => r.waves.first().copied(),
    };
    let fields = r.fields;
    let field_count = r.heights.as_ref().map_or(fields.len(), |h| h.1.len());
    let vig = &r.vignetting;
    let count = vig.iter().map(Vec::len).max().unwrap_or(0);
    let vignetting = (count > 0)
        .then(|| {
            if vig.iter().any(|v| !v.is_empty() && v.len() != field_count) {
                return Err(err(
                    0,
                    format!("vignetting factors (VUX, VLX, VUY, VLY) must give one value per field ({field_count})"),
                ));
            }
            let at = |v: &Vec<f64>, k: usize| v.get(k).copied().unwrap_or(0.0);
            // the pupil spans -1 + lower .. 1 - upper: centre (lower - upper) / 2,
            // narrowed by (upper + lower) / 2
            Ok((0..field_count)
                .map(|k| VignettingFactors {
                    decenter_x: (at(&vig[1], k) - at(&vig[0], k)) / 2.0,
                    compress_x: (at(&vig[0], k) + at(&vig[1], k)) / 2.0,
                    decenter_y: (at(&vig[3], k) - at(&vig[2], k)) / 2.0,
                    compress_y: (at(&vig[2], k) + at(&vig[3], k)) / 2.0,
                })
                .collect::<Vec<_>>())
        })
        .transpose()?;
    let mut warnings = Vec::new();
    if !r.ignored.is_empty() {
        let mut names: Vec<(String, Vec<usize>)> = Vec::new();
        for (name, line) in r.ignored {
            match names.iter_mut().find(|(n, _)| *n == name) {
                Some((_, lines)) => lines.push(line),
                None => names.push((name, vec![line])),
            }
        }
        let list: Vec<String> = names
            .iter()
            .map(|(n, l)| {
                format!(
                    "{n} (line{} {})",
                    if l.len() > 1 { "s" } else { "" },
                    l.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(", ")
                )
            })
            .collect();
        warnings.push(format!(
            "CODE V commands not read (they do not change the lens as traced here): {}",
            list.join("; ")
        ));
    }
    let mut spec = PrescriptionSpec {
        name: r.name,
        units: Some("mm".into()),
        wavelengths_nm: (n > 0).then(|| r.waves.clone()),
        wavelength_weights: (!r.weights.is_empty() && r.weights.iter().any(|w| *w != 1.0)).then_some(r.weights),
        primary_wavelength_nm: primary,
        fields_deg: (!fields.is_empty()).then_some(fields),
        object_distance_mm: r.object.map(|d| d * s),
        surfaces,
        warnings,
        ..PrescriptionSpec::default()
    };
    let stop = spec.surfaces.iter().position(|x| x.stop).unwrap_or(0);
    if (r.epd.is_some() || r.fno.is_some()) && spec.surfaces[stop].semi_diameter.is_none() {
        // provisional: EPD or FNO sizes the stop below
        spec.surfaces[stop].semi_diameter = Some(1.0);
    }
    if r.pim {
        let last = spec.surfaces.len() - 1;
        spec.surfaces[last].thickness = 1.0;
        let p = build(&spec, catalogs)?;
        let first = FirstOrder::of(&p).map_err(|e| err(0, format!("PIM: no paraxial image: {e}")))?;
        let object = crate::paraxial::ObjectDistance::from_mm(spec.object_distance_mm.unwrap_or(f64::INFINITY))
            .map_err(|e| err(0, e.to_string()))?;
        let image = crate::paraxial::imaging(&p, &first, object).map_err(|e| err(0, format!("PIM: {e}")))?;
        spec.surfaces[last].thickness = image.image_distance;
    }
    if let Some(last) = spec.surfaces.last_mut() {
        last.thickness += r.defocus * s;
    }
    set_aperture(&mut spec, r.epd.map(|d| d * s), r.fno, catalogs)?;
    if let Some((kind, heights, line)) = r.heights {
        if spec.fields_deg.is_some() {
            return Err(err(line, format!("{kind}: fields are given twice (YAN too); give one kind")));
        }
        let p = build(&spec, catalogs)?;
        let mut deg = Vec::with_capacity(heights.len());
        for (k, h) in heights.iter().enumerate() {
            let h = h * s;
            let angle = match kind.as_str() {
                "YOB" => crate::analysis::curves::field_deg_for_object_height(&p, h),
                _ => crate::analysis::curves::field_deg_for_image_height(&p, h, kind == "YRI"),
            };
            deg.push(
                angle.map_err(|e| {
                    err(line, format!("field {} ({kind} {h} mm) cannot be taken to an angle: {e}", k + 1))
                })?,
            );
        }
        spec.fields_deg = Some(deg);
    }
    // last: the factors need their fields
    spec.vignetting_factors = vignetting;
    Ok(spec)
}

fn build(spec: &PrescriptionSpec, catalogs: &Catalogs) -> Result<Prescription, SeqError> {
    Prescription::from_spec_with(spec, catalogs).map_err(|findings| {
        let list: Vec<String> =
            findings.iter().filter(|x| x.severity == crate::model::Severity::Error).map(|x| x.to_string()).collect();
        err(0, format!("the lens is not valid: {}", list.join("; ")))
    })
}

/// The stop sized for the file's EPD or FNO (the paraxial entrance pupil
/// scales with the stop); with neither, the stop's CIR is the aperture.
fn set_aperture(
    spec: &mut PrescriptionSpec,
    epd: Option<f64>,
    fno: Option<f64>,
    catalogs: &Catalogs,
) -> Result<(), SeqError> {
    let stop = spec.surfaces.iter().position(|x| x.stop).unwrap_or(0);
    if epd.is_none() && fno.is_none() {
        if spec.surfaces[stop].semi_diameter.is_none() {
            return Err(err(0, format!("no aperture: give EPD or FNO, or CIR on the stop (surface {})", stop + 1)));
        }
        return Ok(());
    }
    for (what, v) in [("EPD", epd), ("FNO", fno)] {
        if v.is_some_and(|v| v.is_nan() || v <= 0.0) {
            return Err(err(0, format!("{what} {}: give a positive number", v.unwrap_or(0.0))));
        }
    }
    let given = spec.surfaces[stop].semi_diameter.unwrap_or(1.0);
    spec.surfaces[stop].semi_diameter = Some(given);
    let p = build(spec, catalogs)?;
    let first = FirstOrder::of(&p).map_err(|e| err(0, format!("cannot set the aperture: {e}")))?;
    let target = match (epd, fno) {
        (Some(d), _) => d,
        (None, Some(n)) => first.efl.abs() / n,
        (None, None) => unreachable!("one is given"),
    };
    let sd = given * target / first.entrance_pupil.diameter;
    if !(sd.is_finite() && sd > 0.0) {
        return Err(err(
            0,
            "the stop cannot be sized for the file's aperture (the entrance pupil does not scale with it)",
        ));
    }
    spec.surfaces[stop].semi_diameter = Some(sd);
    Ok(())
}
