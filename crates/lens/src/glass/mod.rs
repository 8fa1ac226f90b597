//! Optical glasses: dispersion formulas ([`formula`]), the shipped
//! catalogues and those a user brings ([`catalog`], [`agf`]), and the
//! quantities an optical engineer reads off a glass (nd, vd, partial
//! dispersion). Wavelengths are nm; indices are relative to air, as the
//! vendors give them. docs/glass.md has the formats, formulas and sources.

pub mod agf;
pub mod catalog;
pub mod formula;
pub(crate) mod kernel;
pub mod range;

use crate::error::{exact, num};
pub use catalog::{Catalog, Catalogs};
pub use formula::Dispersion;
use kernel::{Kernel, Lambda};
pub use range::{GlassRange, RangeWarning};

/// The helium d line, nm: where nd is given.
pub const LINE_D_NM: f64 = 587.5618;
/// The hydrogen F line, nm.
pub const LINE_F_NM: f64 = 486.1327;
/// The hydrogen C line, nm.
pub const LINE_C_NM: f64 = 656.2725;
/// The mercury e line, nm.
pub const LINE_E_NM: f64 = 546.074;
/// The mercury g line, nm.
pub const LINE_G_NM: f64 = 435.8343;

/// Why a glass could not be found or evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GlassError {
    /// No loaded catalogue has the glass.
    #[error("unknown glass \"{name}\"{}", suggest(suggestions))]
    Unknown {
        /// The name asked for.
        name: String,
        /// The nearest names of the loaded catalogues, `VENDOR:NAME`.
        suggestions: Vec<String>,
    },
    /// A bare name that several catalogues have.
    #[error("glass \"{name}\" is in several catalogues: write one of {}", candidates.join(", "))]
    Ambiguous {
        /// The name asked for.
        name: String,
        /// The candidates, `VENDOR:NAME`.
        candidates: Vec<String>,
    },
    /// A wavelength outside the glass's data, refused by
    /// [`GlassRange::Strict`].
    #[error("{glass}: {} nm is outside the glass's data ({} to {} nm) and the strict glass range refuses it; choose a wavelength within the range, or drop the strict choice (--strict-glass-range) to extrapolate the formula", exact(*wavelength_nm), num(range_nm[0]), num(range_nm[1]))]
    OutOfRange {
        /// The glass, `VENDOR:NAME`.
        glass: String,
        /// The wavelength asked for, nm.
        wavelength_nm: f64,
        /// The valid range, nm.
        range_nm: [f64; 2],
    },
    /// A wavelength where the glass's formula has no index (tabulated
    /// data end, a pole, n <= 1).
    #[error("{glass}: no index at {} nm (the glass's data cover {} to {} nm): {reason}; choose a wavelength within the range or another glass", exact(*wavelength_nm), num(range_nm[0]), num(range_nm[1]))]
    NoValue {
        /// The glass, `VENDOR:NAME`.
        glass: String,
        /// The wavelength asked for, nm.
        wavelength_nm: f64,
        /// The range the data cover, nm.
        range_nm: [f64; 2],
        /// Why there is no value.
        reason: range::NoValue,
    },
    /// A catalogue file that cannot be read.
    #[error("{origin}: line {line}: {message}")]
    Parse {
        /// The file.
        origin: String,
        /// 1-based line (0 for the file as a whole).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A model glass with impossible numbers.
    #[error("model glass nd = {}, vd = {}: give nd > 1 and vd > 0 (finite)", num(*nd), num(*vd))]
    BadModel {
        /// Index at d.
        nd: f64,
        /// Abbe number.
        vd: f64,
    },
}

fn suggest(s: &[String]) -> String {
    if s.is_empty() {
        String::new()
    } else {
        format!(": did you mean {}?", s.join(", "))
    }
}

/// A glass's index formula made ready for many wavelengths
/// ([`Glass::prepared`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedIndex {
    kernel: Kernel,
    glass: Glass,
}

impl PreparedIndex {
    /// The index at `wavelength_nm`, extrapolated outside the glass's data
    /// (as [`Glass::index`]).
    #[inline]
    pub fn index(&self, wavelength_nm: f64) -> Result<f64, GlassError> {
        self.index_with(wavelength_nm, GlassRange::Extrapolate)
    }

    /// The index at `wavelength_nm` under `range` (as [`Glass::index_with`]).
    #[inline]
    pub fn index_with(&self, wavelength_nm: f64, range: GlassRange) -> Result<f64, GlassError> {
        self.glass.index_by(wavelength_nm, range, |nm| match self.kernel {
            Kernel::General => self.glass.dispersion.index_general(nm),
            k => k.eval(&Lambda::of_nm(nm)),
        })
    }

    /// The glass.
    pub fn glass(&self) -> &Glass {
        &self.glass
    }
}

/// A glass: its catalogue, name, dispersion and valid range.
#[derive(Debug, Clone, PartialEq)]
pub struct Glass {
    /// The catalogue (vendor) as it names itself, upper case.
    pub catalog: String,
    /// The glass's name as the vendor writes it.
    pub name: String,
    /// How its index depends on wavelength.
    pub dispersion: Dispersion,
    /// Wavelengths where the data hold, nm.
    pub range_nm: [f64; 2],
    /// The vendor's nd, where the catalogue gives it.
    pub catalog_nd: Option<f64>,
    /// The vendor's vd, where the catalogue gives it.
    pub catalog_vd: Option<f64>,
}

impl Glass {
    /// A model glass with index `nd` at the d line and Abbe number `vd`
    /// (see [`Dispersion::model`]), valid over 300-2500 nm.
    pub fn model(nd: f64, vd: f64) -> Result<Glass, GlassError> {
        if !(nd.is_finite() && nd > 1.0 && vd.is_finite() && vd > 0.0) {
            return Err(GlassError::BadModel { nd, vd });
        }
        Ok(Glass {
            catalog: "MODEL".into(),
            name: format!("{nd}/{vd}"),
            dispersion: Dispersion::model(nd, vd),
            range_nm: [300.0, 2500.0],
            catalog_nd: Some(nd),
            catalog_vd: Some(vd),
        })
    }

    /// `VENDOR:NAME`.
    pub fn full_name(&self) -> String {
        format!("{}:{}", self.catalog, self.name)
    }

    /// The index at `wavelength_nm`. Outside the glass's data the formula
    /// is extrapolated (as Zemax does; [`Self::range_warning`] gives the
    /// warning to report, [`Self::index_with`] with [`GlassRange::Strict`]
    /// refuses); an error where it has no value (tabulated data, a pole,
    /// n <= 1).
    pub fn index(&self, wavelength_nm: f64) -> Result<f64, GlassError> {
        self.index_with(wavelength_nm, GlassRange::Extrapolate)
    }

    /// The glass's index prepared for many wavelengths: the formula put
    /// once into the form the batch tracer evaluates (a Sellmeier sum as
    /// one fraction, powers by multiplication), so that each index after
    /// that costs a few multiplications. Gives what [`Self::index`] gives,
    /// to the bit.
    ///
    /// ```
    /// use lens::glass::Catalogs;
    /// let g = Catalogs::shipped().find("SCHOTT:N-BK7").unwrap();
    /// let n = g.prepared();
    /// assert_eq!(n.index(587.5618).unwrap(), g.index(587.5618).unwrap());
    /// ```
    pub fn prepared(&self) -> PreparedIndex {
        PreparedIndex { kernel: Kernel::of(&self.dispersion), glass: self.clone() }
    }

    /// nd, from the formula; an error where the data do not cover the d
    /// line (a catalogue property is not extrapolated).
    pub fn nd(&self) -> Result<f64, GlassError> {
        self.index_with(LINE_D_NM, GlassRange::Strict)
    }

    /// The Abbe number vd = (nd - 1) / (nF - nC), from the formula (the
    /// lines within the data, as for [`Self::nd`]).
    pub fn vd(&self) -> Result<f64, GlassError> {
        let at = |nm| self.index_with(nm, GlassRange::Strict);
        Ok((self.nd()? - 1.0) / (at(LINE_F_NM)? - at(LINE_C_NM)?))
    }

    /// The relative partial dispersion PgF = (ng - nF) / (nF - nC) (the
    /// lines within the data, as for [`Self::nd`]).
    pub fn partial_dispersion_gf(&self) -> Result<f64, GlassError> {
        let at = |nm| self.index_with(nm, GlassRange::Strict);
        let (f, c) = (at(LINE_F_NM)?, at(LINE_C_NM)?);
        Ok((at(LINE_G_NM)? - f) / (f - c))
    }
}
