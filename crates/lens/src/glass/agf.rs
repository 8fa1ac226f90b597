//! Zemax AGF glass catalogues: `NM` (name, formula, MIL code, nd, vd, ...),
//! `CD` (the formula's coefficients) and `LD` (the valid range, µm) lines
//! per glass; other lines are ignored. The catalogue is named after the
//! file, as Zemax does. AGF files come as UTF-16 (little or big endian,
//! with or without a byte-order mark), UTF-8 or Latin-1; all are read.

use super::{Catalog, Dispersion, Glass, GlassError};
use std::path::Path;

/// Decodes an AGF file's bytes: UTF-16 LE or BE (by byte-order mark, or by
/// where the zero bytes of ASCII text fall), UTF-8 (with or without a mark),
/// else Latin-1.
pub fn decode(bytes: &[u8]) -> String {
    let utf16 = |b: &[u8], little: bool| {
        let units: Vec<u16> = b
            .chunks_exact(2)
            .map(|p| if little { u16::from_le_bytes([p[0], p[1]]) } else { u16::from_be_bytes([p[0], p[1]]) })
            .collect();
        String::from_utf16_lossy(&units)
    };
    match bytes {
        [0xFF, 0xFE, rest @ ..] => return utf16(rest, true),
        [0xFE, 0xFF, rest @ ..] => return utf16(rest, false),
        [0xEF, 0xBB, 0xBF, rest @ ..] => return String::from_utf8_lossy(rest).into_owned(),
        _ => {}
    }
    let sample = &bytes[..bytes.len().min(4096)];
    let zeros_at = |parity: usize| sample.iter().skip(parity).step_by(2).filter(|b| **b == 0).count();
    let half = sample.len() / 2;
    if half > 0 && zeros_at(1) * 3 > half {
        return utf16(bytes, true);
    }
    if half > 0 && zeros_at(0) * 3 > half {
        return utf16(bytes, false);
    }
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}

/// Reads an AGF file.
pub fn load(path: &Path) -> Result<Catalog, GlassError> {
    let origin = path.display().to_string();
    let bytes = crate::io::files::read_bounded(path, crate::io::files::MAX_TEXT_BYTES).map_err(|e| {
        GlassError::Parse { origin: origin.clone(), line: 0, message: format!("cannot read: {}", e.reason()) }
    })?;
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("USER").to_uppercase();
    parse(&decode(&bytes), &name, &origin)
}

/// Parses AGF text into the catalogue `name`; `origin` names the file in
/// errors.
pub fn parse(text: &str, name: &str, origin: &str) -> Result<Catalog, GlassError> {
    let err = |line: usize, message: String| GlassError::Parse { origin: origin.to_string(), line, message };
    struct Partial {
        name: String,
        formula: u8,
        nd: Option<f64>,
        vd: Option<f64>,
        c: Option<Vec<f64>>,
        range_um: Option<[f64; 2]>,
        line: usize,
    }
    let mut done: Vec<Partial> = Vec::new();
    let mut current: Option<Partial> = None;
    for (k, raw) in text.lines().enumerate() {
        let line = raw.trim_matches(|c: char| c.is_whitespace() || c == '\u{feff}');
        let mut words = line.split_whitespace();
        let Some(tag) = words.next() else { continue };
        let rest: Vec<&str> = words.collect();
        let nums = |what: &str| -> Result<Vec<f64>, GlassError> {
            rest.iter()
                .map(|w| w.parse::<f64>().map_err(|_| err(k + 1, format!("{what}: \"{w}\" is not a number"))))
                .collect()
        };
        match tag {
            "NM" => {
                if let Some(p) = current.take() {
                    done.push(p);
                }
                let glass = rest.first().ok_or_else(|| err(k + 1, "NM line without a glass name".into()))?;
                let formula = rest
                    .get(1)
                    .and_then(|f| f.parse::<f64>().ok())
                    .map(|f| f as u8)
                    .filter(|f| (1..=13).contains(f))
                    .ok_or_else(|| err(k + 1, format!("glass {glass}: the formula number is not 1-13")))?;
                let num = |i: usize| rest.get(i).and_then(|v| v.parse::<f64>().ok());
                current = Some(Partial {
                    name: glass.to_string(),
                    formula,
                    nd: num(3),
                    vd: num(4),
                    c: None,
                    range_um: None,
                    line: k + 1,
                });
            }
            "CD" => {
                if let Some(p) = current.as_mut() {
                    p.c = Some(nums("CD")?);
                }
            }
            "LD" => {
                if let Some(p) = current.as_mut() {
                    let v = nums("LD")?;
                    if v.len() < 2 || !(v[0] > 0.0 && v[1] > v[0]) {
                        return Err(err(
                            k + 1,
                            format!("glass {}: LD needs two wavelengths in µm, low < high", p.name),
                        ));
                    }
                    p.range_um = Some([v[0], v[1]]);
                }
            }
            _ => {}
        }
    }
    done.extend(current);
    if done.is_empty() {
        return Err(err(0, "no glass (NM line) in the file".into()));
    }
    let mut glasses = Vec::with_capacity(done.len());
    for p in done {
        let c = p.c.ok_or_else(|| err(p.line, format!("glass {}: no CD line with its coefficients", p.name)))?;
        // without LD, the visible and near infrared as design programs assume
        let [lo, hi] = p.range_um.unwrap_or([0.3, 2.5]);
        glasses.push(Glass {
            catalog: name.to_uppercase(),
            name: p.name,
            dispersion: Dispersion::Agf { formula: p.formula, c },
            range_nm: [lo * 1e3, hi * 1e3],
            catalog_nd: p.nd,
            catalog_vd: p.vd,
        });
    }
    glasses.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(Catalog { name: name.to_uppercase(), source: origin.to_string(), glasses })
}
