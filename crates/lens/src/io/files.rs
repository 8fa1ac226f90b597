//! Reading and writing files safely: reads bounded in size (a prescription,
//! scene or catalogue is small; `/dev/zero` must not fill memory), writes
//! complete or not at all (to a temporary file beside the target, then
//! renamed over it, every error reported).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// The largest text file read as a prescription, scene, catalogue or mesh:
/// 256 MiB.
pub const MAX_TEXT_BYTES: u64 = 256 << 20;

/// Why a bounded read failed.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be opened or read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The file is larger than the limit.
    #[error("{}: larger than {} MiB, the most read here: is it the right file?", path.display(), limit >> 20)]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The limit, bytes.
        limit: u64,
    },
}

impl ReadError {
    /// What went wrong, without the file's name (for messages that give it
    /// already).
    pub fn reason(&self) -> String {
        match self {
            ReadError::Io { source, .. } => source.to_string(),
            ReadError::TooLarge { limit, .. } => {
                format!("larger than {} MiB, the most read here: is it the right file?", limit >> 20)
            }
        }
    }
}

/// The bytes of `path`, refusing files of more than `limit` bytes (read
/// up to the limit and one byte more, so a device or pipe that never ends
/// is refused too).
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let io = |source| ReadError::Io { path: path.to_path_buf(), source };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge { path: path.to_path_buf(), limit });
    }
    Ok(bytes)
}

/// The file a write to `path` lands in: `path` itself, or, where it is a
/// symbolic link (a chain of them, a dangling one too), the file it points
/// to, so that the link is kept and its target written (`latest.png ->
/// renders/x.png`). A loop of links is an error.
pub fn write_target(path: &Path) -> std::io::Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p)?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(std::io::Error::other(format!("{}: too many levels of symbolic links", path.display())))
}

/// Whether `path` (a link followed) exists and is neither a regular file
/// nor a folder: a device, a pipe, a socket, written in place
/// ([`write_atomic`]).
pub fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Writes `path` completely or not at all: `write` fills a temporary file
/// in the same folder (named after the target, with the process id), which
/// is flushed to disk and renamed over `path`; on any error the temporary
/// file is removed and `path` is left as it was. A symbolic link at `path`
/// is kept and the file it points to written so ([`write_target`]). A
/// device or pipe (`/dev/null`, `/dev/full`) cannot be replaced: it is
/// written in place, and every write error (a full device) is returned.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let target = write_target(path)?;
    let path = target.as_path();
    if is_special(path) {
        let mut out = std::io::BufWriter::new(std::fs::OpenOptions::new().write(true).open(path)?);
        write(&mut out)?;
        return out.into_inner().map_err(|e| e.into_error())?.flush();
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut out = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        write(&mut out)?;
        out.flush()?;
        out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// [`write_atomic`] of a byte string.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic(path, |w| w.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bounded_read_refuses_an_endless_device() {
        let e = read_bounded(Path::new("/dev/zero"), 1 << 20);
        assert!(matches!(e, Err(ReadError::TooLarge { .. })), "{e:?}");
    }

    #[test]
    fn a_failed_write_leaves_the_target_and_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("lens-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("out.txt");
        std::fs::write(&target, "before").unwrap();
        let e = write_atomic(&target, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("the encoder failed"))
        });
        assert!(e.is_err());
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "before");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "a temporary file stayed behind");
        write_bytes_atomic(&target, b"after").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "after");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A link is kept and its target written (through a chain of links, a
    /// relative one, and one whose target does not exist yet); a full
    /// device's error is returned.
    #[cfg(unix)]
    #[test]
    fn links_are_kept_and_their_targets_written() {
        let dir = std::env::temp_dir().join(format!("lens-links-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("renders")).unwrap();
        std::os::unix::fs::symlink("renders/x.png", dir.join("latest.png")).unwrap();
        std::os::unix::fs::symlink(dir.join("latest.png"), dir.join("second.png")).unwrap();
        write_bytes_atomic(&dir.join("second.png"), b"one").unwrap();
        assert!(std::fs::symlink_metadata(dir.join("latest.png")).unwrap().file_type().is_symlink());
        assert!(std::fs::symlink_metadata(dir.join("second.png")).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(dir.join("renders/x.png")).unwrap(), b"one");
        write_bytes_atomic(&dir.join("latest.png"), b"two").unwrap();
        assert_eq!(std::fs::read(dir.join("renders/x.png")).unwrap(), b"two");
        assert_eq!(std::fs::read_dir(dir.join("renders")).unwrap().count(), 1, "a temporary file stayed behind");
        std::os::unix::fs::symlink("loop", dir.join("loop")).unwrap();
        assert!(write_bytes_atomic(&dir.join("loop"), b"x").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
        if Path::new("/dev/full").exists() {
            assert!(write_bytes_atomic(Path::new("/dev/full"), &[0; 100_000]).is_err());
            write_bytes_atomic(Path::new("/dev/null"), b"fine").unwrap();
        }
    }
}
