//! Golden outputs: every `--json` command of golden/commands.txt on every
//! shipped lens, compared character for character (serde_json writes the
//! shortest representation that reads back to the same f64, so equal text
//! is equal bits). The files were written by the code before the batch
//! tracer took over the analyses; docs/analyses.md lists each deliberate
//! difference since and why it is better.
//!
//! To rewrite them after a deliberate change: `LENS_BLESS=1 cargo test
//! --release -p lens-cli --test golden`, then review the diff.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn slug(cmd: &str) -> String {
    let s: String = cmd
        .replace("{lens}", "")
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '.' { c } else { '-' })
        .collect();
    s.split('-').filter(|p| !p.is_empty()).collect::<Vec<_>>().join("-")
}

#[test]
fn json_outputs_match_the_golden_files() {
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let commands = std::fs::read_to_string(golden.join("commands.txt")).unwrap();
    let bless = std::env::var_os("LENS_BLESS").is_some();
    let mut lenses: Vec<PathBuf> = std::fs::read_dir(root().join("lens-data"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    lenses.sort();
    let mut failures = Vec::new();
    let mut checked = 0;
    for lens in &lenses {
        let name = lens.file_stem().unwrap().to_str().unwrap();
        let rel = format!("lens-data/{name}.json");
        for cmd in commands.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')) {
            let args: Vec<String> = cmd.split_whitespace().map(|a| a.replace("{lens}", &rel)).collect();
            let out = Command::new(env!("CARGO_BIN_EXE_lens")).args(&args).current_dir(root()).output().unwrap();
            let text = format!(
                "exit {}\n{}",
                out.status.code().unwrap_or(-1),
                if out.status.success() {
                    String::from_utf8_lossy(&out.stdout).into_owned()
                } else {
                    String::from_utf8_lossy(&out.stderr).into_owned()
                }
            );
            let file = golden.join(name).join(format!("{}.txt", slug(cmd)));
            checked += 1;
            if bless {
                std::fs::create_dir_all(file.parent().unwrap()).unwrap();
                std::fs::write(&file, &text).unwrap();
                continue;
            }
            let want = std::fs::read_to_string(&file).unwrap_or_default();
            if want != text {
                failures.push(format!(
                    "{}: `lens {}`\n  want {}\n  got  {}",
                    file.display(),
                    args.join(" "),
                    want.trim(),
                    text.trim()
                ));
            }
        }
    }
    assert!(checked >= 8 * 10, "{checked} outputs");
    assert!(failures.is_empty(), "{} of {checked} outputs differ:\n{}", failures.len(), failures.join("\n"));
}
