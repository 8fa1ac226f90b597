//! A glass outside the wavelengths its data cover. Catalogues state a range
//! for each glass (HIKARI's SK16: 400 to 700 nm); designers routinely ask
//! a little past it (the He r-line at 706.5 nm). As Zemax does, the index
//! is then computed with the glass's formula and the caller is warned
//! ([`RangeWarning`]); [`GlassRange::Strict`] refuses instead. Where the
//! formula itself has no value (tabulated data end, a pole, n <= 1) it is
//! an error either way ([`super::GlassError::NoValue`]).

use super::{Glass, GlassError};
use crate::error::{exact, num};

/// What to do at a wavelength outside a glass's stated data range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GlassRange {
    /// Compute with the formula (Zemax and optiland do); the caller reports
    /// a [`RangeWarning`] ([`Glass::range_warning`]).
    #[default]
    Extrapolate,
    /// Refuse with [`GlassError::OutOfRange`].
    Strict,
}

/// A wavelength at which a glass's index is computed outside its data.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RangeWarning {
    /// The glass, `VENDOR:NAME`.
    pub glass: String,
    /// The range its data cover, nm.
    pub range_nm: [f64; 2],
    /// The wavelength, nm.
    pub wavelength_nm: f64,
}

impl std::fmt::Display for RangeWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} nm is outside the glass's data ({} to {} nm); its index there is extrapolated from the formula \
             (--strict-glass-range refuses it)",
            self.glass,
            exact(self.wavelength_nm),
            num(self.range_nm[0]),
            num(self.range_nm[1])
        )
    }
}

/// Why a glass has no index at a wavelength ([`GlassError::NoValue`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoValue {
    /// Not a positive, finite wavelength.
    BadWavelength,
    /// The formula gives no real index (inside the data).
    Formula,
    /// Tabulated data, which end at the range.
    TableEnds,
    /// The formula extrapolated gives n <= 1, NaN, or crosses a pole.
    Extrapolated,
}

impl std::fmt::Display for NoValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NoValue::BadWavelength => "give a positive wavelength in nm",
            NoValue::Formula => "its formula has no real value there",
            NoValue::TableEnds => "its data are a table, which ends there",
            NoValue::Extrapolated => {
                "its formula extrapolated there has no index above 1 (a pole of the formula, or n <= 1)"
            }
        })
    }
}

/// Points a band outside the data is checked at, on each side
/// ([`Glass::check_band`]).
const BAND_CHECKS: usize = 64;

impl Glass {
    /// Whether the glass's data cover `wavelength_nm` (the range's last
    /// printed digit allowed: catalogues round it).
    pub fn covers(&self, wavelength_nm: f64) -> bool {
        let [lo, hi] = self.range_nm;
        let slack = 1e-6 * hi;
        wavelength_nm >= lo - slack && wavelength_nm <= hi + slack
    }

    /// The warning due where the index at `wavelength_nm` is extrapolated;
    /// `None` inside the data.
    pub fn range_warning(&self, wavelength_nm: f64) -> Option<RangeWarning> {
        (!self.covers(wavelength_nm)).then(|| RangeWarning {
            glass: self.full_name(),
            range_nm: self.range_nm,
            wavelength_nm,
        })
    }

    /// Checks that the index has a value at every wavelength from `lo_nm`
    /// to `hi_nm` (a spectral trace's band), under `range`: inside the data
    /// the formula holds; outside, each side's extension is sampled at
    /// `BAND_CHECKS` points (poles of the dispersion formulas lie far in
    /// the ultraviolet and infrared, where a sign change of n² - 1 shows
    /// them). The warnings for ends that are extrapolated are
    /// [`Self::range_warning`]'s: a tracer checking every batch makes none.
    pub fn check_band(&self, lo_nm: f64, hi_nm: f64, range: GlassRange) -> Result<(), GlassError> {
        let [lo, hi] = self.range_nm;
        for (from, to) in [(lo_nm, lo), (hi, hi_nm)] {
            if self.covers(from) && self.covers(to) || from >= to {
                continue;
            }
            for k in 0..=BAND_CHECKS {
                self.index_with(from + (to - from) * k as f64 / BAND_CHECKS as f64, range)?;
            }
        }
        for nm in [lo_nm, hi_nm] {
            self.index_with(nm, range)?;
        }
        Ok(())
    }

    /// The index at `wavelength_nm` under `range`: inside the data the
    /// formula's value; outside it the formula's value with
    /// [`GlassRange::Extrapolate`] ([`GlassError::NoValue`] where there is
    /// none: tabulated data, a pole, n <= 1), [`GlassError::OutOfRange`]
    /// with [`GlassRange::Strict`].
    pub fn index_with(&self, wavelength_nm: f64, range: GlassRange) -> Result<f64, GlassError> {
        self.index_by(wavelength_nm, range, |nm| self.dispersion.index(nm))
    }

    /// [`Self::index_with`] with the formula evaluated by `eval` (the
    /// prepared kernel or the formula as written).
    pub(super) fn index_by(
        &self,
        wavelength_nm: f64,
        range: GlassRange,
        eval: impl Fn(f64) -> f64,
    ) -> Result<f64, GlassError> {
        let no_value = |reason: NoValue| GlassError::NoValue {
            glass: self.full_name(),
            wavelength_nm,
            range_nm: self.range_nm,
            reason,
        };
        if !(wavelength_nm.is_finite() && wavelength_nm > 0.0) {
            return Err(no_value(NoValue::BadWavelength));
        }
        if self.covers(wavelength_nm) {
            let n = eval(wavelength_nm);
            return if n.is_finite() && n > 0.0 { Ok(n) } else { Err(no_value(NoValue::Formula)) };
        }
        if range == GlassRange::Strict {
            return Err(GlassError::OutOfRange { glass: self.full_name(), wavelength_nm, range_nm: self.range_nm });
        }
        if matches!(self.dispersion, super::Dispersion::Tabulated { .. }) {
            return Err(no_value(NoValue::TableEnds));
        }
        let n = eval(wavelength_nm);
        if n.is_finite() && n > 1.0 {
            Ok(n)
        } else {
            Err(no_value(NoValue::Extrapolated))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glass::Catalogs;

    /// HIKARI's SK16 is stated for 400-700 nm: the He r-line is computed
    /// (with a warning), strictly refused, and far outside refused too.
    #[test]
    fn sk16_at_the_r_line() {
        let g = Catalogs::shipped().find("HIKARI:SK16").unwrap();
        assert_eq!(g.range_nm, [400.0, 700.0]);
        let n = g.index(706.5188).unwrap();
        let n700 = g.index(700.0).unwrap();
        assert!(n < n700 && n700 - n < 1e-3, "{n} {n700}");
        let w = g.range_warning(706.5188).unwrap();
        assert_eq!(w.glass, "HIKARI:SK16");
        assert!(w.to_string().contains("706.5188 nm is outside the glass's data (400 to 700 nm)"), "{w}");
        assert!(g.range_warning(587.5618).is_none());
        assert!(matches!(g.index_with(706.5188, GlassRange::Strict), Err(GlassError::OutOfRange { .. })));
        assert_eq!(g.index_with(587.5618, GlassRange::Strict), g.index(587.5618));
    }

    /// A table ends where its data end; a formula with no value above 1 is
    /// an error, whatever the choice.
    #[test]
    fn no_value_is_an_error() {
        let t = Glass {
            catalog: "T".into(),
            name: "TAB".into(),
            dispersion: crate::glass::Dispersion::Tabulated { nm: vec![400.0, 700.0], n: vec![1.52, 1.51] },
            range_nm: [400.0, 700.0],
            catalog_nd: None,
            catalog_vd: None,
        };
        assert!(matches!(t.index(750.0), Err(GlassError::NoValue { .. })));
        assert!(t.index(600.0).is_ok());
        // N-BK7's Sellmeier pole at sqrt(C3) = 10.2 µm: n² < 0 just below it
        let bk7 = Catalogs::shipped().find("SCHOTT:N-BK7").unwrap();
        let e = bk7.index(10_100.0).unwrap_err();
        assert!(matches!(e, GlassError::NoValue { .. }), "{e}");
        assert!(bk7.check_band(300.0, 12_000.0, GlassRange::Extrapolate).is_err());
        bk7.check_band(250.0, 830.0, GlassRange::Extrapolate).unwrap();
        let w = [250.0, 830.0].map(|nm| bk7.range_warning(nm));
        assert!(w[0].as_ref().is_some_and(|w| w.wavelength_nm == 250.0) && w[1].is_none(), "{w:?}");
        assert!(bk7.check_band(250.0, 830.0, GlassRange::Strict).is_err());
        bk7.check_band(300.0, 830.0, GlassRange::Strict).unwrap();
        assert!(bk7.range_warning(300.0).is_none());
    }
}
