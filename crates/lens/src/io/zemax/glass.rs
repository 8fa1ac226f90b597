//! The glass of a `GLAS` line: a model glass from its nd and vd, a
//! constant index, or a catalogue glass found through the vendors `GCAT`
//! lists and then every loaded catalogue; an unknown name is an error,
//! never a default index (docs/zemax.md).

use super::read::{err, number, ZemaxError};
use crate::glass::{Catalogs, Glass, GlassError};
use crate::model::GlassSpec;

/// The glass after surface `surface`, from the tokens of its `GLAS` line
/// (`line`): a model glass, a constant index, or a catalogue glass.
///
/// A name not in the vendors `GCAT` lists as written is looked for as a
/// retired name of theirs (SCHOTT's `BK7` is `N-BK7` now), then in every
/// loaded catalogue (an obsolete SCHOTT name that another vendor keeps for
/// its equivalent; of several vendors', the first of the right type), then
/// as any vendor's retired name. Such a glass is taken only where the nd
/// and vd the file records with it are that glass's (nd within 1e-3, vd
/// within 0.5: the same glass type), and the substitution is noted in
/// `notes` (the prescription's warnings); where they differ it is another
/// glass of the same name, an error.
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
    let (want_nd, want_vd) = (recorded(3), recorded(4));
    let nd_of = |g: &Glass| g.catalog_nd.or_else(|| g.index(crate::glass::LINE_D_NM).ok());
    // the same glass type: nd within 1e-3, vd within 0.5 of what the file records
    let same_type = |g: &Glass| {
        !(match (want_nd, nd_of(g)) {
            (Some(w), Some(n)) => (w - n).abs() > 1e-3,
            _ => false,
        } || match (want_vd, g.catalog_vd) {
            (Some(w), Some(v)) => (w - v).abs() > 0.5,
            _ => false,
        })
    };
    let show = |x: Option<f64>| x.map_or_else(|| "?".to_string(), |v| format!("{v}"));
    let records = match (want_nd, want_vd) {
        (Some(n), Some(v)) => format!("; the file records {n} and {v}"),
        _ => "; the file records no nd and vd to check it by".into(),
    };
    // then every loaded catalogue: the name as written (of one vendor, or
    // of several: the first of the same type; the nearest there is to an
    // obsolete glass's own data), else the GCAT vendors' successor of a
    // retired name (SCHOTT's BK7 is N-BK7), else any vendor's
    let mut candidates: Vec<&Glass> = match catalogs.find(name) {
        Ok(g) => vec![g],
        Err(GlassError::Ambiguous { candidates, .. }) => {
            candidates.iter().filter_map(|c| catalogs.find(c).ok()).collect()
        }
        Err(_) => Vec::new(),
    };
    let mut successor = false;
    if !candidates.iter().any(|g| same_type(g)) {
        let retired = gcat.iter().map(|v| format!("{v}:{name}")).chain([name.to_string()]);
        if let Some(g) = retired.filter_map(|n| catalogs.resolve(&n).ok()).find_map(|(g, w)| w.and(Some(g))) {
            if same_type(g) || candidates.is_empty() {
                (candidates, successor) = (vec![g], true);
            }
        }
    }
    if let Some(g) = candidates.iter().find(|g| same_type(g)) {
        let others: Vec<String> =
            candidates.iter().filter(|c| c.full_name() != g.full_name()).map(|c| c.full_name()).collect();
        notes.push(format!(
            "surface {}: {name} is not in {searched}; {} is{} (nd {}, vd {}{}){records}",
            surface,
            g.full_name(),
            if successor { " its successor" } else { "" },
            show(nd_of(g)),
            show(g.catalog_vd),
            if others.is_empty() { String::new() } else { format!("; also named so: {}", others.join(", ")) },
        ));
        return Ok((Some(GlassSpec::Name(g.full_name())), None));
    }
    if let Some(g) = candidates.first() {
        return Err(err(
            line,
            format!(
                "surface {}: glass {name} is not in the catalogues GCAT lists ({searched}); {} {} but \
                 nd {} and vd {} where the file records nd {} and vd {}: another glass; give the file's \
                 catalogue with --glass-catalog",
                surface,
                g.full_name(),
                if successor { "is its successor" } else { "has that name" },
                show(nd_of(g)),
                show(g.catalog_vd),
                show(want_nd),
                show(want_vd)
            ),
        ));
    }
    let e = catalogs.find(name).err().map_or_else(String::new, |e| e.to_string());
    // offered, never used unasked
    let hint = match (want_nd, want_vd) {
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
