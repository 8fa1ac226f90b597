//! Glass catalogues: the shipped ones (lens-data/glass/, converted from the
//! refractiveindex.info database by tools/convert_glass.py and compiled into
//! the library) and those a user brings (Zemax AGF files), and the lookup
//! of a glass by `VENDOR:NAME` or a bare name.

use super::{Dispersion, Glass, GlassError};
use serde::Deserialize;
use std::sync::OnceLock;

/// One vendor's glasses.
#[derive(Debug, Clone, PartialEq)]
pub struct Catalog {
    /// The vendor, upper case (`SCHOTT`).
    pub name: String,
    /// Where the data come from, with the catalogue's date.
    pub source: String,
    /// The glasses, sorted by name.
    pub glasses: Vec<Glass>,
}

/// A shipped catalogue file as written.
#[derive(Deserialize)]
struct CatalogFile {
    catalog: String,
    source: String,
    glasses: Vec<GlassEntry>,
}

#[derive(Deserialize)]
struct GlassEntry {
    name: String,
    formula: String,
    #[serde(default)]
    coefficients: Vec<f64>,
    #[serde(default)]
    data_nm_n: Vec<[f64; 2]>,
    range_nm: [f64; 2],
    nd: Option<f64>,
    vd: Option<f64>,
}

impl Catalog {
    /// Parses a catalogue in the shipped JSON form; `origin` names it in
    /// errors.
    pub fn from_json(text: &str, origin: &str) -> Result<Catalog, GlassError> {
        let err = |line: usize, message: String| GlassError::Parse { origin: origin.to_string(), line, message };
        let file: CatalogFile = serde_json::from_str(text).map_err(|e| err(e.line(), crate::io::json::message(&e)))?;
        let mut glasses = Vec::with_capacity(file.glasses.len());
        for g in file.glasses {
            let dispersion = match g.formula.split_whitespace().collect::<Vec<_>>().as_slice() {
                ["rii", k] => Dispersion::Rii {
                    formula: k.parse().ok().filter(|k| (1..=9).contains(k)).ok_or_else(|| {
                        err(0, format!("{}: formula \"{}\" is not refractiveindex.info 1-9", g.name, g.formula))
                    })?,
                    c: g.coefficients,
                },
                ["tabulated"] if g.data_nm_n.len() >= 2 => Dispersion::Tabulated {
                    nm: g.data_nm_n.iter().map(|r| r[0]).collect(),
                    n: g.data_nm_n.iter().map(|r| r[1]).collect(),
                },
                _ => return Err(err(0, format!("{}: unknown formula \"{}\"", g.name, g.formula))),
            };
            glasses.push(Glass {
                catalog: file.catalog.to_uppercase(),
                name: g.name,
                dispersion,
                range_nm: g.range_nm,
                catalog_nd: g.nd,
                catalog_vd: g.vd,
            });
        }
        glasses.sort_by(|a, b| a.name.cmp(&b.name));
        Ok(Catalog { name: file.catalog.to_uppercase(), source: file.source, glasses })
    }

    /// The glass of this name (exact, then case-insensitive).
    pub fn get(&self, name: &str) -> Option<&Glass> {
        self.glasses
            .iter()
            .find(|g| g.name == name)
            .or_else(|| self.glasses.iter().find(|g| g.name.eq_ignore_ascii_case(name)))
    }
}

/// The shipped catalogues' files, compiled in.
const SHIPPED: [(&str, &str); 15] = [
    ("SCHOTT", include_str!("../../../../lens-data/glass/SCHOTT.json")),
    ("OHARA", include_str!("../../../../lens-data/glass/OHARA.json")),
    ("HOYA", include_str!("../../../../lens-data/glass/HOYA.json")),
    ("HIKARI", include_str!("../../../../lens-data/glass/HIKARI.json")),
    ("SUMITA", include_str!("../../../../lens-data/glass/SUMITA.json")),
    ("CDGM", include_str!("../../../../lens-data/glass/CDGM.json")),
    ("LZOS", include_str!("../../../../lens-data/glass/LZOS.json")),
    ("BARBERINI", include_str!("../../../../lens-data/glass/BARBERINI.json")),
    ("AMI", include_str!("../../../../lens-data/glass/AMI.json")),
    ("CORNING", include_str!("../../../../lens-data/glass/CORNING.json")),
    ("LIGHTPATH", include_str!("../../../../lens-data/glass/LIGHTPATH.json")),
    ("MISC", include_str!("../../../../lens-data/glass/MISC.json")),
    ("MISC-CRYSTALS", include_str!("../../../../lens-data/glass/MISC-CRYSTALS.json")),
    ("NSG", include_str!("../../../../lens-data/glass/NSG.json")),
    ("VITRON", include_str!("../../../../lens-data/glass/VITRON.json")),
];

/// Loaded catalogues, searched in order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Catalogs {
    /// The catalogues.
    pub catalogs: Vec<Catalog>,
}

impl Catalogs {
    /// The shipped catalogues (parsed once per process).
    pub fn shipped() -> &'static Catalogs {
        static SHIPPED_CATALOGS: OnceLock<Catalogs> = OnceLock::new();
        SHIPPED_CATALOGS.get_or_init(|| Catalogs {
            catalogs: SHIPPED
                .iter()
                // the files are ours, checked by a test: a broken one is left out
                .filter_map(|(name, text)| Catalog::from_json(text, name).ok())
                .collect(),
        })
    }

    /// The shipped catalogues and `extra` (user catalogues, searched
    /// first: a user's glass of a shipped name replaces it).
    pub fn with(extra: Vec<Catalog>) -> Catalogs {
        let mut catalogs = extra;
        catalogs.extend(Catalogs::shipped().catalogs.iter().cloned());
        Catalogs { catalogs }
    }

    /// Every glass, `VENDOR:NAME`.
    pub fn names(&self) -> impl Iterator<Item = String> + '_ {
        self.catalogs.iter().flat_map(|c| c.glasses.iter().map(|g| g.full_name()))
    }

    /// A glass by `VENDOR:NAME` (vendor case-insensitive) or by `NAME`
    /// alone when exactly one catalogue has it. An unknown glass is an
    /// error with the nearest names; a bare name several catalogues have is
    /// an error listing them.
    ///
    /// ```
    /// let g = lens::glass::Catalogs::shipped().find("schott:N-BK7").unwrap();
    /// assert!((g.nd().unwrap() - 1.5168).abs() < 5e-6);
    /// ```
    pub fn find(&self, name: &str) -> Result<&Glass, GlassError> {
        let name = name.trim();
        if let Some((vendor, glass)) = name.split_once(':') {
            let found = self
                .catalogs
                .iter()
                .filter(|c| c.name.eq_ignore_ascii_case(vendor.trim()))
                .find_map(|c| c.get(glass.trim()));
            return found.ok_or_else(|| self.unknown(name));
        }
        let hits: Vec<&Glass> = self.catalogs.iter().filter_map(|c| c.get(name)).collect();
        let mut vendors: Vec<String> = hits.iter().map(|g| g.full_name()).collect();
        vendors.dedup();
        match hits.len() {
            0 => Err(self.unknown(name)),
            1 => Ok(hits[0]),
            _ if vendors.len() == 1 => Ok(hits[0]),
            _ => Err(GlassError::Ambiguous { name: name.to_string(), candidates: vendors }),
        }
    }

    /// A glass by name as [`Self::find`], or, for a retired name no loaded
    /// catalogue has (`BK7`, `SCHOTT:SK16`, as old Zemax files and patents
    /// write them), the vendor's successor: the one glass named with a
    /// vendor's new-series prefix (`N-BK7`, `N-SK16`; OHARA's `S-`, HOYA's
    /// and HIKARI's `E-` and `J-`, CDGM's `H-`), with the warning to report
    /// (`None` when the name was found as written).
    ///
    /// ```
    /// let (g, warning) = lens::glass::Catalogs::shipped().resolve("BK7").unwrap();
    /// assert_eq!(g.full_name(), "SCHOTT:N-BK7");
    /// assert!(warning.unwrap().contains("successor SCHOTT:N-BK7"));
    /// ```
    pub fn resolve(&self, name: &str) -> Result<(&Glass, Option<String>), GlassError> {
        let err = match self.find(name) {
            Ok(g) => return Ok((g, None)),
            Err(e @ GlassError::Unknown { .. }) => e,
            Err(e) => return Err(e),
        };
        // the first prefix (in SUCCESSOR_PREFIXES' order) that names one glass
        let found =
            SUCCESSOR_PREFIXES.iter().find_map(|prefix| match self.successors_with(name, &[prefix]).as_slice() {
                [] => None,
                [g] => Some(Some(*g)),
                _ => Some(None),
            });
        match found.flatten() {
            Some(g) => Ok((
                g,
                Some(format!(
                    "glass \"{}\" is a retired name no loaded catalogue has; using its successor {} (nd {}, vd {}): \
                     write {} to choose it, or give the old glass's catalogue with --glass-catalog",
                    name.trim(),
                    g.full_name(),
                    g.catalog_nd.map_or_else(|| "?".into(), |v| format!("{v}")),
                    g.catalog_vd.map_or_else(|| "?".into(), |v| format!("{v}")),
                    g.full_name()
                )),
            )),
            None => Err(err),
        }
    }

    /// The glasses a retired `name` may have become: the vendor's (or any
    /// vendor's, for a bare name) glass of the same name with a new-series
    /// prefix.
    fn successors(&self, name: &str) -> Vec<&Glass> {
        self.successors_with(name, &SUCCESSOR_PREFIXES)
    }

    /// [`Self::successors`] with these prefixes only.
    fn successors_with(&self, name: &str, prefixes: &[&str]) -> Vec<&Glass> {
        let name = name.trim();
        let (vendor, glass) = match name.split_once(':') {
            Some((v, g)) => (Some(v.trim()), g.trim()),
            None => (None, name),
        };
        let mut out: Vec<&Glass> = Vec::new();
        for c in self.catalogs.iter().filter(|c| vendor.is_none_or(|v| c.name.eq_ignore_ascii_case(v))) {
            for prefix in prefixes {
                if let Some(g) = c.get(&format!("{prefix}{glass}")) {
                    if !out.iter().any(|o| o.full_name() == g.full_name()) {
                        out.push(g);
                    }
                }
            }
        }
        out
    }

    fn unknown(&self, name: &str) -> GlassError {
        let key = name.rsplit(':').next().unwrap_or(name).to_ascii_uppercase();
        let mut scored: Vec<(usize, String)> = self
            .catalogs
            .iter()
            .flat_map(|c| c.glasses.iter())
            .map(|g| (distance(&key, &g.name.to_ascii_uppercase()), g.full_name()))
            .collect();
        scored.sort();
        let best = scored.first().map_or(usize::MAX, |s| s.0);
        // a retired name's successors first (BK7: N-BK7), then the nearest
        let mut suggestions: Vec<String> = self.successors(name).iter().map(|g| g.full_name()).collect();
        for s in scored.into_iter().take_while(|s| s.0 <= best + 1 && s.0 <= 3 + key.len() / 3) {
            if suggestions.len() >= 5 {
                break;
            }
            if !suggestions.contains(&s.1) {
                suggestions.push(s.1);
            }
        }
        GlassError::Unknown { name: name.to_string(), suggestions }
    }
}

/// The prefixes vendors gave their new (lead- and arsenic-free, or
/// environmentally safe) series of old glass types, in the order a retired
/// name is resolved: SCHOTT `N-` (most old names in files are SCHOTT's),
/// OHARA `S-`, HOYA and HIKARI `E-`, HIKARI `J-`, CDGM `H-`, then the
/// moulding glasses' `P-` and `D-`.
const SUCCESSOR_PREFIXES: [&str; 7] = ["N-", "S-", "E-", "J-", "H-", "P-", "D-"];

/// Levenshtein distance between two names.
fn distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let here = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(here + 1);
            prev = here;
        }
    }
    row[b.len()]
}
