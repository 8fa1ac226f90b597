//! Reading a Zemax sequential lens file (`.zmx`) into our format. What is
//! read, how, and what is refused: docs/zemax.md.

use super::breaks::coordinate_breaks;
use super::glass::glass_of;
use crate::glass::Catalogs;
use crate::model::{Prescription, PrescriptionSpec, SurfaceSpec, VignettingFactors};
use crate::paraxial::FirstOrder;

/// A problem with a Zemax file: what, where (1-based line, 0 for the whole
/// file) and what to change.
#[derive(Debug, Clone, PartialEq)]
pub struct ZemaxError {
    /// 1-based line, 0 when the problem is the file as a whole.
    pub line: usize,
    /// What is wrong and what to change.
    pub message: String,
}

/// How the file sets the aperture.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Aperture {
    /// `ENPD`: the entrance pupil's diameter, lens units.
    EntrancePupil(f64),
    /// `FNUM`: the image-space f-number (object at infinity).
    FNumber(f64),
    /// `FLOA`: the stop's own semi-diameter (`DIAM`).
    FloatByStop,
}

/// One `SURF` block as read.
#[derive(Debug, Clone, Default)]
pub(super) struct Block {
    pub(super) number: usize,
    pub(super) line: usize,
    pub(super) kind: Option<String>,
    curv: f64,
    pub(super) disz: Option<f64>,
    conic: f64,
    pub(super) parm: [f64; 9],
    glass: Option<(Vec<String>, usize)>,
    diam: Option<f64>,
    clap: Option<f64>,
    flap: Option<f64>,
    stop: bool,
}

/// Every value of the file that the prescription needs.
#[derive(Debug, Default)]
struct File {
    name: Option<String>,
    scale: f64,
    aperture: Option<Aperture>,
    field_type: Option<i64>,
    /// The line of `FTYP`.
    field_line: usize,
    field_count: Option<usize>,
    wave_count: Option<usize>,
    xfields: Vec<f64>,
    yfields: Vec<f64>,
    /// `VDXN`, `VDYN`, `VCXN`, `VCYN`, `VANN` (per field), and the line of
    /// the first.
    vignetting: [Vec<f64>; 5],
    vignetting_line: usize,
    waves: Vec<(usize, f64)>,
    /// Each wavelength slot's weight (`WAVM slot µm weight`).
    wave_weights: Vec<(usize, f64)>,
    primary: Option<usize>,
    gcat: Vec<String>,
    blocks: Vec<Block>,
}

/// Reads the text of a Zemax file into a prescription spec: glass names
/// resolved through `catalogs` (the vendors `GCAT` lists first) and written
/// `VENDOR:NAME`, the stop's semi-diameter set so that the entrance pupil or
/// f-number is the file's, lengths in mm.
pub fn read(text: &str, catalogs: &Catalogs) -> Result<PrescriptionSpec, ZemaxError> {
    let file = parse(text)?;
    let mut spec = to_spec(&file, catalogs)?;
    set_aperture(&file, &mut spec, catalogs)?;
    set_fields(&file, &mut spec, catalogs)?;
    Ok(spec)
}

/// The file's fields as radial values (the declared count of `XFLN`/`YFLN`
/// pairs; a field off the y axis by its distance from the axis), in the
/// file's units for heights.
fn radial_fields(f: &File) -> Vec<f64> {
    let count = f.field_count.unwrap_or(f.xfields.len().max(f.yfields.len()));
    (0..count.min(f.xfields.len().max(f.yfields.len())))
        .map(|k| {
            let x = f.xfields.get(k).copied().unwrap_or(0.0);
            let y = f.yfields.get(k).copied().unwrap_or(0.0);
            if x == 0.0 {
                y
            } else {
                x.hypot(y)
            }
        })
        .collect()
}

/// The fields' vignetting factors (`VDXN`, `VDYN`, `VCXN`, `VCYN`), one
/// set per field, or `None` where all are 0; a rotation of the vignetted
/// pupil (`VANN`) is refused.
fn vignetting(f: &File) -> Result<Option<Vec<VignettingFactors>>, ZemaxError> {
    let n = radial_fields(f).len();
    let at = |k: usize, i: usize| f.vignetting[k].get(i).copied().unwrap_or(0.0);
    if let Some(i) = (0..n).find(|&i| at(4, i) != 0.0) {
        return Err(err(
            f.vignetting_line,
            format!(
                "VANN: field {} turns its vignetted pupil by {} degrees, which is not supported; set the angle to 0 \
                 (or remove the vignetting factors)",
                i + 1,
                at(4, i)
            ),
        ));
    }
    let v: Vec<VignettingFactors> = (0..n)
        .map(|i| VignettingFactors {
            decenter_x: at(0, i),
            decenter_y: at(1, i),
            compress_x: at(2, i),
            compress_y: at(3, i),
        })
        .collect();
    Ok(v.iter().any(|x| !x.is_none()).then_some(v))
}

/// Fields given as heights (`FTYP 1` object height, `2` paraxial image
/// height, `3` real image height, at the primary wavelength as Zemax takes
/// them) become the angles of `fields_deg`: the chief ray's angle to the
/// entrance pupil for an object height, the angle whose paraxial or real
/// chief ray reaches that image height (`analysis::curves`). Other field
/// types are refused by name.
fn set_fields(f: &File, spec: &mut PrescriptionSpec, catalogs: &Catalogs) -> Result<(), ZemaxError> {
    let kind = f.field_type.unwrap_or(0);
    let heights = radial_fields(f);
    if kind == 0 || heights.is_empty() {
        return Ok(());
    }
    let what = match kind {
        1 => "object height",
        2 => "paraxial image height",
        3 => "real image height",
        4 => return Err(err(f.field_line, "FTYP 4: theodolite angle fields are not supported; give angles (FTYP 0)")),
        k => {
            return Err(err(f.field_line, format!("FTYP {k}: this field type is not supported; give angles (FTYP 0)")))
        }
    };
    let p = build(spec, catalogs)?;
    let mut deg = Vec::with_capacity(heights.len());
    for (k, h) in heights.iter().enumerate() {
        let h = h * f.scale;
        let angle = match kind {
            1 => crate::analysis::curves::field_deg_for_object_height(&p, h),
            _ => crate::analysis::curves::field_deg_for_image_height(&p, h, kind == 3),
        };
        deg.push(angle.map_err(|e| {
            err(f.field_line, format!("field {} ({what} {h} mm) cannot be taken to an angle: {e}", k + 1))
        })?);
    }
    spec.fields_deg = Some(deg);
    Ok(())
}

pub(super) fn err(line: usize, message: impl Into<String>) -> ZemaxError {
    ZemaxError { line, message: message.into() }
}

/// A number token of line `line` (`what` names it in the error).
pub(super) fn number(tok: Option<&&str>, line: usize, what: &str) -> Result<f64, ZemaxError> {
    let t = tok.ok_or_else(|| err(line, format!("{what}: a number is missing")))?;
    if t.eq_ignore_ascii_case("INFINITY") {
        return Ok(f64::INFINITY);
    }
    t.replace(',', ".")
        .parse::<f64>()
        .ok()
        .filter(|x| !x.is_nan())
        .ok_or_else(|| err(line, format!("{what}: \"{t}\" is not a number")))
}

/// The surface types read, and what the others are, for the error.
fn surface_type(name: &str) -> Result<(), String> {
    match name {
        "STANDARD" | "EVENASPH" | "ODDASPHE" | "PARAXIAL" | "COORDBRK" => Ok(()),
        "TOROIDAL" | "BICONICX" | "BICONIC" => Err("a toroidal or biconic surface (not rotationally symmetric)".into()),
        "DGRATING" | "ELLIGRAT" | "VARGRAT" | "BINARY_1" | "BINARY_2" => Err("a grating or diffractive surface".into()),
        "PARAX_XY" => Err("a paraxial lens with different x and y powers".into()),
        "NONSEQCO" => Err("a non-sequential component".into()),
        "GRINSUR1" | "GRINSUR4" | "GRINSUR5" | "GRADIENT" => Err("a gradient-index surface".into()),
        other => Err(format!("type {other}")),
    }
}

/// Unit tokens of `UNIT` and their length in mm.
fn unit_scale(unit: &str) -> Option<f64> {
    match unit.to_ascii_uppercase().as_str() {
        "MM" => Some(1.0),
        "CM" => Some(10.0),
        "IN" => Some(25.4),
        "METER" | "M" => Some(1000.0),
        _ => None,
    }
}

fn parse(text: &str) -> Result<File, ZemaxError> {
    let mut f = File { scale: 1.0, ..File::default() };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let tok: Vec<&str> = raw.split_whitespace().collect();
        let Some(&key) = tok.first() else { continue };
        let block = f.blocks.last_mut();
        match key {
            "MODE" => {
                if tok.get(1).is_some_and(|m| *m != "SEQ") {
                    return Err(err(
                        line,
                        "MODE is not SEQ: only sequential systems are read (non-sequential data is not)",
                    ));
                }
            }
            "NAME" => f.name = Some(tok[1..].join(" ")).filter(|n| !n.is_empty()),
            "UNIT" => {
                let u = tok.get(1).copied().unwrap_or("MM");
                f.scale = unit_scale(u)
                    .ok_or_else(|| err(line, format!("UNIT {u}: lens units must be MM, CM, IN or METER")))?;
            }
            "ENPD" => f.aperture = Some(Aperture::EntrancePupil(number(tok.get(1), line, "ENPD")?)),
            "FNUM" => f.aperture = Some(Aperture::FNumber(number(tok.get(1), line, "FNUM")?)),
            "FLOA" => f.aperture = Some(Aperture::FloatByStop),
            "OBNA" | "ONAX" | "NAIS" => {
                return Err(err(
                    line,
                    format!("{key}: an aperture by numerical aperture is not supported; set ENPD or FNUM in the file"),
                ))
            }
            "GCAT" => f.gcat = tok[1..].iter().map(|s| s.to_string()).collect(),
            "FTYP" => {
                let int = |k: usize| tok.get(k).and_then(|t| t.parse::<i64>().ok());
                f.field_type = int(1);
                f.field_line = line;
                f.field_count = int(3).and_then(|n| usize::try_from(n).ok());
                f.wave_count = int(4).and_then(|n| usize::try_from(n).ok());
            }
            "XFLN" | "XFLD" | "YFLN" | "YFLD" => {
                let v = tok[1..].iter().map(|t| number(Some(t), line, key)).collect::<Result<Vec<_>, _>>()?;
                if key.starts_with('X') {
                    f.xfields = v;
                } else {
                    f.yfields = v;
                }
            }
            "VDXN" | "VDYN" | "VCXN" | "VCYN" | "VANN" => {
                let v = tok[1..].iter().map(|t| number(Some(t), line, key)).collect::<Result<Vec<_>, _>>()?;
                let k = ["VDXN", "VDYN", "VCXN", "VCYN", "VANN"].iter().position(|x| *x == key).unwrap_or(0);
                f.vignetting[k] = v;
                if f.vignetting_line == 0 {
                    f.vignetting_line = line;
                }
            }
            "WAVM" => {
                let slot = number(tok.get(1), line, "WAVM slot")? as usize;
                f.waves.retain(|w| w.0 != slot);
                f.waves.push((slot, number(tok.get(2), line, "WAVM wavelength")?));
                f.wave_weights.retain(|w| w.0 != slot);
                if tok.len() > 3 {
                    f.wave_weights.push((slot, number(tok.get(3), line, "WAVM weight")?));
                }
            }
            "WAVL" => {
                for (k, t) in tok[1..].iter().enumerate() {
                    f.waves.push((k + 1, number(Some(t), line, "WAVL")?));
                }
            }
            "PWAV" => f.primary = Some(number(tok.get(1), line, "PWAV")? as usize),
            "SURF" => {
                let n = number(tok.get(1), line, "SURF")?;
                f.blocks.push(Block { number: n as usize, line, ..Block::default() });
            }
            _ => {
                let Some(b) = block else { continue };
                match key {
                    "TYPE" => {
                        let t = tok.get(1).copied().unwrap_or("STANDARD").to_string();
                        if let Err(what) = surface_type(&t) {
                            return Err(err(
                                line,
                                format!(
                                    "surface {}: TYPE {t} is {what}, which is not supported: only STANDARD, EVENASPH, ODDASPHE and PARAXIAL surfaces (and coordinate breaks around them) are read",
                                    b.number
                                ),
                            ));
                        }
                        b.kind = Some(t);
                    }
                    "CURV" => b.curv = number(tok.get(1), line, "CURV")?,
                    "DISZ" => b.disz = Some(number(tok.get(1), line, "DISZ")?),
                    "CONI" => b.conic = number(tok.get(1), line, "CONI")?,
                    "PARM" => {
                        let k = number(tok.get(1), line, "PARM index")? as usize;
                        let v = number(tok.get(2), line, "PARM value")?;
                        if (1..=8).contains(&k) {
                            b.parm[k] = v;
                        } else if v != 0.0 {
                            return Err(err(line, format!("surface {}: PARM {k} is not a term read here", b.number)));
                        }
                    }
                    "GLAS" => b.glass = Some((tok[1..].iter().map(|s| s.to_string()).collect(), line)),
                    "DIAM" => b.diam = Some(number(tok.get(1), line, "DIAM")?),
                    "CLAP" => {
                        let rmin = number(tok.get(1), line, "CLAP minimum radius")?;
                        if rmin != 0.0 {
                            return Err(err(
                                line,
                                format!(
                                    "surface {}: CLAP with a minimum radius of {rmin} (an annular aperture, a central obscuration) is not supported",
                                    b.number
                                ),
                            ));
                        }
                        b.clap = Some(number(tok.get(2), line, "CLAP maximum radius")?);
                    }
                    "FLAP" => b.flap = Some(number(tok.get(2), line, "FLAP semi-diameter")?),
                    "STOP" => b.stop = true,
                    "SQAP" | "ELAP" | "SPID" | "CLOB" | "SQOB" | "ELOB" | "UDAP" | "OBSC" => {
                        return Err(err(
                            line,
                            format!(
                                "surface {}: {key} (a non-circular aperture or obscuration) is not supported",
                                b.number
                            ),
                        ))
                    }
                    "DECX" | "DECY" | "TILTX" | "TILTY" | "TILTZ"
                        if tok.get(1).and_then(|t| t.parse::<f64>().ok()).is_some_and(|v| v != 0.0) =>
                    {
                        return Err(err(
                            line,
                            format!("surface {}: {key} (a tilt or decentre) is not supported", b.number),
                        ));
                    }
                    _ => {}
                }
            }
        }
    }
    if f.blocks.len() < 3 {
        return Err(err(0, "fewer than three SURF blocks: a Zemax lens has an object, a surface and an image"));
    }
    f.blocks.sort_by_key(|b| b.number);
    Ok(f)
}

fn to_spec(f: &File, catalogs: &Catalogs) -> Result<PrescriptionSpec, ZemaxError> {
    let s = f.scale;
    let n = f.blocks.len();
    let object = &f.blocks[0];
    let image = &f.blocks[n - 1];
    if image.curv != 0.0 {
        return Err(err(image.line, "the image surface is curved: only a flat film is supported"));
    }
    let mut surfaces = Vec::with_capacity(n - 2);
    let mut notes = Vec::new();
    let (real, motions) = coordinate_breaks(&f.blocks[1..n - 1], s)?;
    for (b, thickness) in real {
        let line = b.line;
        if !thickness.is_finite() {
            return Err(err(line, format!("surface {}: DISZ INFINITY: only the object may be at infinity", b.number)));
        }
        let (glass, ior) = match &b.glass {
            Some((tok, line)) => glass_of(tok, *line, b.number, &f.gcat, catalogs, &mut notes)?,
            None => (None, None),
        };
        let kind = b.kind.as_deref().unwrap_or("STANDARD");
        let terms = |odd: bool| -> Option<Vec<f64>> {
            let mut v: Vec<f64> = (1..=8)
                .map(|k| {
                    // the coefficient of r^j is in lens units^(1-j)
                    let j = if odd { k } else { 2 * k } as i32;
                    b.parm[k] * s.powi(1 - j)
                })
                .collect();
            while v.last() == Some(&0.0) {
                v.pop();
            }
            (!v.is_empty()).then_some(v)
        };
        // Zemax clips rays only at a surface aperture (CLAP, or FLAP at the
        // semi-diameter); DIAM alone is drawn, not a stop for rays. The
        // stop's DIAM is its size for FLOA (ENPD and FNUM size it anew).
        let aperture = b.clap.or(b.flap).or(if b.stop { b.diam } else { None });
        let semi = aperture.filter(|d| *d > 0.0).map(|d| d * s);
        surfaces.push(SurfaceSpec {
            ior,
            glass,
            semi_diameter: semi,
            stop: b.stop,
            conic: (b.conic != 0.0).then_some(b.conic),
            aspheric: if kind == "EVENASPH" { terms(false) } else { None },
            odd_aspheric: if kind == "ODDASPHE" { terms(true) } else { None },
            // Zemax's paraxial surface: PARM 1 its focal length
            kind: (kind == "PARAXIAL").then(|| "paraxial".to_string()),
            focal_length_mm: (kind == "PARAXIAL").then(|| b.parm[1] * s),
            ..SurfaceSpec::new((b.curv != 0.0).then(|| 1.0 / (b.curv / s)), thickness * s)
        });
    }
    let mut elements = Vec::new();
    for m in motions {
        let (decenter, tilt) = ((m.decenter != [0.0; 2]).then_some(m.decenter), (m.tilt != [0.0; 2]).then_some(m.tilt));
        let own = &mut surfaces[m.first];
        if m.first == m.last && own.decenter_mm.is_none() && own.tilt_deg.is_none() {
            own.decenter_mm = decenter;
            own.tilt_deg = tilt;
        } else {
            elements.push(crate::model::ElementSpec {
                surfaces: [m.first + 1, m.last + 1],
                decenter_mm: decenter,
                tilt_deg: tilt,
            });
        }
    }
    if !surfaces.iter().any(|x| x.stop) {
        // Zemax's default stop is surface 1
        surfaces[0].stop = true;
    }
    // wavelengths: the declared slots, in order; the file's are in µm
    let mut waves: Vec<(usize, f64)> = f.waves.clone();
    waves.sort_by_key(|w| w.0);
    if let Some(count) = f.wave_count.filter(|c| *c > 0) {
        waves.retain(|w| w.0 <= count);
    }
    // µm to nm, rounded to 1e-9 nm: 0.5875618 µm is 587.5618 nm, not
    // 587.5618000000001
    let to_nm = |um: f64| (um * 1e12).round() / 1e9;
    let nm: Vec<f64> = waves.iter().map(|w| to_nm(w.1)).collect();
    let primary = f.primary.and_then(|p| waves.iter().find(|w| w.0 == p)).map(|w| to_nm(w.1));
    let weights: Vec<f64> =
        waves.iter().map(|w| f.wave_weights.iter().find(|x| x.0 == w.0).map_or(1.0, |x| x.1)).collect();
    // angles as they are; heights become angles once the lens is built
    // (`set_fields`)
    let fields = if f.field_type.unwrap_or(0) == 0 { radial_fields(f) } else { Vec::new() };
    let object_distance = object.disz.filter(|d| d.is_finite()).map(|d| d * s);
    Ok(PrescriptionSpec {
        name: f.name.clone(),
        // what the import had to decide (read by `io::load_spec` into the
        // source it writes)
        source: (!notes.is_empty()).then(|| format!("glasses outside the file's GCAT vendors: {}", notes.join("; "))),
        warnings: notes.clone(),
        units: Some("mm".into()),
        wavelength_weights: (!nm.is_empty() && weights.iter().any(|w| *w != 1.0)).then_some(weights),
        wavelengths_nm: (!nm.is_empty()).then_some(nm),
        primary_wavelength_nm: primary,
        fields_deg: (!fields.is_empty()).then_some(fields),
        vignetting_factors: vignetting(f)?,
        object_distance_mm: object_distance,
        surfaces,
        elements: (!elements.is_empty()).then_some(elements),
        focus_group: None,
        ..PrescriptionSpec::default()
    })
}

/// The prescription of `spec`, or an error listing what makes it invalid.
fn build(spec: &PrescriptionSpec, catalogs: &Catalogs) -> Result<Prescription, ZemaxError> {
    Prescription::from_spec_with(spec, catalogs).map_err(|findings| {
        let list: Vec<String> =
            findings.iter().filter(|x| x.severity == crate::model::Severity::Error).map(|x| x.to_string()).collect();
        err(0, format!("the lens is not valid: {}", list.join("; ")))
    })
}

/// Sets the stop's semi-diameter so that the paraxial entrance pupil (or
/// the f-number) is the file's: the pupil scales with the stop.
fn set_aperture(f: &File, spec: &mut PrescriptionSpec, catalogs: &Catalogs) -> Result<(), ZemaxError> {
    let stop = spec.surfaces.iter().position(|x| x.stop).unwrap_or(0);
    let given = spec.surfaces[stop].semi_diameter;
    let aperture = f.aperture.unwrap_or(Aperture::FloatByStop);
    if aperture == Aperture::FloatByStop {
        if given.is_none() {
            return Err(err(
                0,
                format!(
                    "the aperture floats by the stop's size (FLOA, or no ENPD or FNUM) but the stop (surface {}) has no DIAM",
                    stop + 1
                ),
            ));
        }
        return Ok(());
    }
    let target_ok = |v: f64| v.is_finite() && v > 0.0;
    spec.surfaces[stop].semi_diameter = Some(given.unwrap_or(1.0));
    let p = build(spec, catalogs)?;
    let first = FirstOrder::of(&p).map_err(|e| err(0, format!("cannot set the aperture: {e}")))?;
    let epd = match aperture {
        Aperture::EntrancePupil(d) if target_ok(d) => d * f.scale,
        Aperture::FNumber(n) if target_ok(n) => first.efl.abs() / n,
        Aperture::EntrancePupil(v) | Aperture::FNumber(v) => {
            return Err(err(0, format!("the aperture value {v} must be a positive number")))
        }
        Aperture::FloatByStop => unreachable!("handled above"),
    };
    let sd = spec.surfaces[stop].semi_diameter.unwrap_or(1.0) * epd / first.entrance_pupil.diameter;
    if !target_ok(sd) {
        return Err(err(
            0,
            "the stop cannot be sized for the file's aperture (the entrance pupil does not scale with it)",
        ));
    }
    spec.surfaces[stop].semi_diameter = Some(sd);
    Ok(())
}
