//! CODE V sequence files (`.seq`): the commands that describe a
//! co-axial lens read into a prescription, and a prescription written as
//! them (docs/codev.md).
//!
//! A file is a list of commands, one per line or separated by `;`, `!`
//! starting a comment; a command is its name (case-insensitive) and its
//! numbers or quoted strings. Read: `RDM` (radius mode: `S` gives radii;
//! without it, or with `RDM N`, curvatures, as rayoptics reads CODE V), `TIT`/`TITLE`, `LEN`, `DIM` (M, C, I), `WL`, `REF`,
//! `WTW`, `EPD`, `FNO`, `YAN` (field angles), `VUX`/`VLX`/`VUY`/`VLY`
//! (vignetting), `SO` (the object: radius, thickness; 1e10 or more is
//! infinity), `S` and `STO` (a surface: radius, thickness, glass), `SI` (the
//! image: a thickness there defocuses, added to the last after `PIM`), and on the surface just
//! given `STO`, `CIR` (clear-aperture radius), `SPH`, `CON`, `ASP`, `K`,
//! `A`..`J` (r^4..r^20), `RDY`/`CUY`, `THI`, `PIM` (the last thickness to
//! the paraxial image), `PRV`...`END` (private glasses of constant index).
//! Glasses: `NAME_VENDOR` as CODE V writes catalogue names (hyphens and
//! spaces left out: `NBK7_SCHOTT`), a fictitious glass `nnnn.vvvv` (nd = 1.nnnn,
//! vd = vv.vv), a 6-digit code `nnnvvv` (nd 1.nnn, vd vv.v), `nd:vd`, `REFL` (a
//! mirror: refused). Fields as heights (`YOB`, `YIM` paraxial, `YRI` real
//! image height) become the angles of `fields_deg` as the Zemax reader
//! takes them. Every other command is listed in
//! the prescription's `warnings`, never dropped silently; what changes the
//! optics and cannot be read (decentres, mirrors, toroids, a curved image,
//! fields in x) is refused with the line.

mod read;
mod write;

pub use read::read;
pub use write::write;

/// Why a `.seq` file cannot be read: the line (1-based; 0 for the file as
/// a whole) and what to change.
#[derive(Debug, Clone, PartialEq)]
pub struct SeqError {
    /// 1-based line.
    pub line: usize,
    /// What is wrong and what to change.
    pub message: String,
}

fn err(line: usize, message: impl Into<String>) -> SeqError {
    SeqError { line, message: message.into() }
}
