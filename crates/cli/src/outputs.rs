//! The files a command will write, checked before it does any work: each
//! has an extension the command can write, a folder that exists and takes
//! new files (that of a symbolic link's target: the link is kept), and is
//! none of the command's inputs nor another of its outputs. (Each is then
//! written completely or not at all, `lens::io::files::write_atomic`; a
//! device such as `/dev/null` in place, its write errors reported.)

use std::path::{Path, PathBuf};

/// One file to write and the extensions it may have (lower case, without
/// the dot; empty: any).
pub struct Output<'a> {
    /// The file.
    pub path: &'a Path,
    /// The flag that named it, for messages (`-o`, `--plot`).
    pub flag: &'a str,
    /// Allowed extensions.
    pub extensions: &'a [&'a str],
}

/// The path as the file system will resolve it: canonical when it exists,
/// else its folder's canonical form and its name.
fn resolved(p: &Path) -> PathBuf {
    if let Ok(c) = p.canonicalize() {
        return c;
    }
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match (dir.canonicalize(), p.file_name()) {
        (Ok(d), Some(n)) => d.join(n),
        _ => p.to_path_buf(),
    }
}

/// Checks `outputs` against each other and against `inputs`; the error says
/// which flag and what to change.
pub fn check(outputs: &[Output], inputs: &[PathBuf]) -> Result<(), String> {
    let ins: Vec<PathBuf> = inputs.iter().map(|p| resolved(p)).collect();
    let mut seen: Vec<(PathBuf, &str)> = Vec::new();
    for o in outputs {
        let shown = o.path.display();
        let ext = o.path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !o.extensions.is_empty() && !ext.as_deref().is_some_and(|e| o.extensions.contains(&e)) {
            let list: Vec<String> = o.extensions.iter().map(|e| format!(".{e}")).collect();
            return Err(format!("{} {shown}: choose a file ending in {}", o.flag, list.join(" or ")));
        }
        // a link is kept and the file it points to written
        let target = lens::io::files::write_target(o.path).map_err(|e| format!("{} {shown}: {e}", o.flag))?;
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if !dir.is_dir() {
            return Err(format!("{} {shown}: the folder {} does not exist", o.flag, dir.display()));
        }
        if target.is_dir() {
            return Err(format!("{} {shown}: is a folder; give a file name", o.flag));
        }
        if lens::io::files::is_special(&target) {
            // a device or pipe is written in place, its errors reported
            if let Err(e) = std::fs::OpenOptions::new().write(true).open(&target) {
                return Err(format!("{} {shown}: cannot write to it: {e}", o.flag));
            }
        } else {
            // the folder must take a new file (the write goes through one)
            let probe = dir.join(format!(".lens-write-check.{}", std::process::id()));
            match std::fs::File::create(&probe) {
                Ok(_) => {
                    let _ = std::fs::remove_file(&probe);
                }
                Err(e) => return Err(format!("{} {shown}: cannot write in {}: {e}", o.flag, dir.display())),
            }
        }
        let r = resolved(o.path);
        if let Some(i) = ins.iter().position(|i| *i == r) {
            return Err(format!(
                "{} {shown}: is an input of this command ({}); choose another output file",
                o.flag,
                inputs[i].display()
            ));
        }
        if let Some((_, other)) = seen.iter().find(|(p, _)| *p == r) {
            return Err(format!("{} {shown}: is also the file of {other}; give each output its own file", o.flag));
        }
        seen.push((r, o.flag));
    }
    Ok(())
}
