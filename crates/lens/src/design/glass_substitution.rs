//! Glass substitution: a model glass (nd, vd) replaced by the catalogue
//! glass nearest to it on the glass map.
//!
//! Distance on the map is sqrt((100 dnd)^2 + dvd^2): a hundredth in nd
//! weighs as one unit of Abbe number (the map's useful span, about 0.55 in
//! nd and 75 in vd, is then about as wide as it is tall).

use crate::glass::{Catalogs, Glass};
use serde::Serialize;

/// One model glass replaced.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Substitution {
    /// The surface the glass follows, from 1.
    pub surface: usize,
    /// The model glass's nd and vd.
    pub model: [f64; 2],
    /// The catalogue glass, `VENDOR:NAME`.
    pub glass: String,
    /// Its nd and vd.
    pub catalogue: [f64; 2],
}

/// The distance between two glasses on the map.
pub fn map_distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (100.0 * (a[0] - b[0])).hypot(a[1] - b[1])
}

/// The glass of `catalogs` (only the vendors `only` names, where given,
/// case-insensitive) nearest to (nd, vd), with its nd and vd; `None` when
/// no glass qualifies.
pub fn nearest<'a>(catalogs: &'a Catalogs, only: Option<&[String]>, nd: f64, vd: f64) -> Option<(&'a Glass, [f64; 2])> {
    catalogs
        .catalogs
        .iter()
        .filter(|c| only.is_none_or(|names| names.iter().any(|n| n.eq_ignore_ascii_case(&c.name))))
        .flat_map(|c| c.glasses.iter())
        .filter_map(|g| Some((g, [g.nd().ok()?, g.vd().ok()?])))
        .filter(|(_, m)| m[0].is_finite() && m[1].is_finite() && m[1] > 0.0)
        .min_by(|a, b| map_distance(a.1, [nd, vd]).total_cmp(&map_distance(b.1, [nd, vd])))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// N-BK7's own numbers find N-BK7 among SCHOTT's glasses.
    #[test]
    fn finds_a_glass_by_its_numbers() {
        let only = vec!["schott".to_string()];
        let (g, m) = nearest(Catalogs::shipped(), Some(&only), 1.5168, 64.17).unwrap();
        assert_eq!(g.full_name(), "SCHOTT:N-BK7");
        assert!(map_distance(m, [1.5168, 64.17]) < 0.1);
    }
}
