//! Zemax sequential lens files (`.zmx`): the bytes decoded in any of the
//! encodings they come in ([`text`]), read into our format ([`read`]) and
//! written back ([`write`]). docs/zemax.md lists what is read and refused.

pub mod read;
pub mod text;
pub mod write;

pub use read::{read, ZemaxError};
pub use write::write;
