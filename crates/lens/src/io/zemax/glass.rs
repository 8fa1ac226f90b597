//! The glass of a `GLAS` line: a model glass from its nd and vd, a
//! constant index, or a catalogue glass found through the vendors `GCAT`
//! lists and then every loaded catalogue; an unknown name is an error,
//! never a default index (docs/zemax.md).

use super::read::{err, number, ZemaxError};
use crate::glass::Catalogs;
use crate::model::GlassSpec;

/// The glass after surface `surface`, from the tokens of its `GLAS` line
/// (`line`): a model glass, a constant index, or a catalogue glass.
///
/// A name found only outside the vendors `GCAT` lists (an obsolete SCHOTT
/// name that another vendor keeps for its equivalent, say) is taken only
/// where the nd and vd the file records with it are that glass's (nd within
/// 1e-3, vd within 0.5: the same glass type), and the substitution is noted
/// in `notes`; where they differ it is another glass of the same name, an
/// error.
pub(super) fn glass_of(
    tok: &[String],
    line: usize,
    surface: usize,
    gcat: &[String],
    catalogs: &Catalogs,
    notes: &mut Vec<String>,
) -> Result<(Option<GlassSpec>, Option<f64>), ZemaxError> {
    let Some(name) = tok.first() else { return Ok((None, None)) };
    if name.eq_ignore_ascii_case("MIRROR") {
        return Err(err(line, format!("surface {}: MIRROR: reflecting surfaces are not supported", surface)));
    }
    let model = tok.get(1).is_some_and(|t| t == "1") || name == "___BLANK";
    if model {
        let nd = number(tok.get(3).map(|s| s.as_str()).as_ref(), line, "model glass nd")?;
        let vd = number(tok.get(4).map(|s| s.as_str()).as_ref(), line, "model glass vd")?;
        if vd == 0.0 || vd >= super::write::NON_DISPERSIVE_ABBE {
            // a constant index (as we write one)
            return Ok((None, Some(nd)));
        }
        return Ok((Some(GlassSpec::Model { nd, vd }), None));
    }
    for vendor in gcat {
        if let Ok(g) = catalogs.find(&format!("{vendor}:{name}")) {
            return Ok((Some(GlassSpec::Name(g.full_name())), None));
        }
    }
    let searched = if gcat.is_empty() { "no vendor (the file has no GCAT)".to_string() } else { gcat.join(", ") };
    // the nd and vd a design program recorded with the name (0 when it
    // recorded none)
    let recorded = |k: usize| tok.get(k).and_then(|t| t.parse::<f64>().ok()).filter(|v| *v > 0.0);
    match catalogs.find(name) {
        Ok(g) => {
            let nd = g.catalog_nd.or_else(|| g.index(crate::glass::LINE_D_NM).ok());
            let (want_nd, want_vd) = (recorded(3), recorded(4));
            let differs = match (want_nd, nd) {
                (Some(w), Some(n)) => (w - n).abs() > 1e-3,
                _ => false,
            } || match (want_vd, g.catalog_vd) {
                (Some(w), Some(v)) => (w - v).abs() > 0.5,
                _ => false,
            };
            let show = |x: Option<f64>| x.map_or_else(|| "?".to_string(), |v| format!("{v}"));
            if differs {
                return Err(err(
                    line,
                    format!(
                        "surface {}: glass {name} is not in the catalogues GCAT lists ({searched}); {} has that name but \
                         nd {} and vd {} where the file records nd {} and vd {}: another glass; give the file's \
                         catalogue with --glass-catalog",
                        surface,
                        g.full_name(),
                        show(nd),
                        show(g.catalog_vd),
                        show(want_nd),
                        show(want_vd)
                    ),
                ));
            }
            notes.push(format!(
                "surface {}: {name} is not in {searched}; {} is (nd {}, vd {}{})",
                surface,
                g.full_name(),
                show(nd),
                show(g.catalog_vd),
                match (want_nd, want_vd) {
                    (Some(n), Some(v)) => format!("; the file records {n} and {v}"),
                    _ => "; the file records no nd and vd to check it by".into(),
                }
            ));
            Ok((Some(GlassSpec::Name(g.full_name())), None))
        }
        Err(e) => {
            // offered, never used unasked
            let hint = match (recorded(3), recorded(4)) {
                (Some(nd), Some(vd)) => format!(
                    "; the file records nd {nd} and vd {vd} for it: to trace a model glass of those, write the line as \
                     GLAS ___BLANK 1 0 {nd} {vd}"
                ),
                _ => String::new(),
            };
            Err(err(
                line,
                format!(
                    "surface {}: glass {name} is not in the catalogues GCAT lists ({searched}) nor in any loaded one ({e}); give its AGF catalogue with --glass-catalog{hint}",
                    surface,
                ),
            ))
        }
    }
}
