//! Zemax sequential lens files (`.zmx`): the bytes decoded in any of the
//! encodings they come in ([`text`]), read into our format ([`mod@read`];
//! the glasses of its `GLAS` lines in `glass.rs`, its coordinate
//! breaks in `breaks.rs`) and
//! written back ([`mod@write`]). docs/zemax.md lists what is read and refused.

mod breaks;
mod glass;
pub mod read;
pub mod text;
pub mod write;

pub use read::{read, ZemaxError};
pub use write::write;
