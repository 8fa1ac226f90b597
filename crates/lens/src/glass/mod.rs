//! Optical glasses: dispersion formulas ([`formula`]), the shipped
//! catalogues and those a user brings ([`catalog`], [`agf`]), and the
//! quantities an optical engineer reads off a glass (nd, vd, partial
//! dispersion). Wavelengths are nm; indices are relative to air, as the
//! vendors give them. docs/glass.md has the formats, formulas and sources.

pub mod agf;
pub mod catalog;
pub mod formula;
pub(crate) mod kernel;

pub use catalog::{Catalog, Catalogs};
pub use formula::Dispersion;
use kernel::{Kernel, Lambda};

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
    /// A wavelength outside the glass's data.
    #[error("{glass}: {wavelength_nm} nm is outside the glass's data ({} to {} nm)", range_nm[0], range_nm[1])]
    OutOfRange {
        /// The glass, `VENDOR:NAME`.
        glass: String,
        /// The wavelength asked for, nm.
        wavelength_nm: f64,
        /// The valid range, nm.
        range_nm: [f64; 2],
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
    #[error("model glass nd = {nd}, vd = {vd}: give nd > 1 and vd > 0 (finite)")]
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
    /// The index at `wavelength_nm`; an error outside the glass's range
    /// (as [`Glass::index`]).
    #[inline]
    pub fn index(&self, wavelength_nm: f64) -> Result<f64, GlassError> {
        let [lo, hi] = self.glass.range_nm;
        let slack = 1e-6 * hi;
        let n = if wavelength_nm >= lo - slack && wavelength_nm <= hi + slack {
            match self.kernel {
                Kernel::General => self.glass.dispersion.index_general(wavelength_nm),
                k => k.eval(&Lambda::of_nm(wavelength_nm)),
            }
        } else {
            f64::NAN
        };
        if n.is_finite() && n > 0.0 {
            Ok(n)
        } else {
            Err(GlassError::OutOfRange { glass: self.glass.full_name(), wavelength_nm, range_nm: self.glass.range_nm })
        }
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

    /// The index at `wavelength_nm`; an error outside the glass's range.
    pub fn index(&self, wavelength_nm: f64) -> Result<f64, GlassError> {
        let [lo, hi] = self.range_nm;
        // the range as printed in catalogues is rounded: allow its last digit
        let slack = 1e-6 * hi;
        if !(wavelength_nm >= lo - slack && wavelength_nm <= hi + slack) {
            return Err(GlassError::OutOfRange { glass: self.full_name(), wavelength_nm, range_nm: self.range_nm });
        }
        let n = self.dispersion.index(wavelength_nm);
        if n.is_finite() && n > 0.0 {
            Ok(n)
        } else {
            Err(GlassError::OutOfRange { glass: self.full_name(), wavelength_nm, range_nm: self.range_nm })
        }
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

    /// nd, from the formula.
    pub fn nd(&self) -> Result<f64, GlassError> {
        self.index(LINE_D_NM)
    }

    /// The Abbe number vd = (nd - 1) / (nF - nC), from the formula.
    pub fn vd(&self) -> Result<f64, GlassError> {
        Ok((self.nd()? - 1.0) / (self.index(LINE_F_NM)? - self.index(LINE_C_NM)?))
    }

    /// The relative partial dispersion PgF = (ng - nF) / (nF - nC).
    pub fn partial_dispersion_gf(&self) -> Result<f64, GlassError> {
        let (f, c) = (self.index(LINE_F_NM)?, self.index(LINE_C_NM)?);
        Ok((self.index(LINE_G_NM)? - f) / (f - c))
    }
}
