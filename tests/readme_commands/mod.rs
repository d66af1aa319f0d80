//! The ```sh blocks of README.md and how to run them (`tests/readme.rs`, and the validation
//! suite for the blocks that need the reference data).
// Two test binaries include this module and each uses a part of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// What a block's commands need besides a CPU (its first line says so).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Needs {
    /// Nothing: runs on any machine.
    Cpu,
    /// `# needs the reference data`.
    ReferenceData,
    /// `# needs a GPU`.
    Gpu,
    /// `# needs MPI` (an MPI library and launcher; `.ci/run` runs split runs under `mpirun`).
    Mpi,
}

/// One ```sh block: its commands, one per line, without comments.
#[derive(Clone, Debug)]
pub struct Block {
    /// What it needs.
    pub needs: Needs,
    /// The commands.
    pub commands: Vec<String>,
}

/// The ```sh blocks of README.md, in order.
pub fn readme_blocks() -> Vec<Block> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
    let text = std::fs::read_to_string(&path).expect("README.md");
    let mut blocks = Vec::new();
    let mut current: Option<Vec<&str>> = None;
    for line in text.lines() {
        let fence = line.trim_start();
        match &mut current {
            None if fence == "```sh" => current = Some(Vec::new()),
            Some(lines) if fence.starts_with("```") => {
                let needs = match lines.first().map(|l| l.trim()) {
                    Some("# needs the reference data") => Needs::ReferenceData,
                    Some("# needs a GPU") => Needs::Gpu,
                    Some("# needs MPI") => Needs::Mpi,
                    _ => Needs::Cpu,
                };
                let commands = lines
                    .iter()
                    .map(|l| l.trim())
                    .filter(|l| !l.is_empty() && !l.starts_with('#'))
                    .map(str::to_string)
                    .collect();
                blocks.push(Block { needs, commands });
                current = None;
            }
            Some(lines) => lines.push(line),
            None => {}
        }
    }
    assert!(current.is_none(), "README.md: a ```sh block is not closed");
    blocks
}

/// A command line split into words as a POSIX shell would for the forms the README uses:
/// blanks separate words, single and double quotes group them.
pub fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut quote: Option<char> = None;
    let mut started = false;
    for c in line.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                started = true;
            }
            (None, c) if c.is_whitespace() => {
                if started || !word.is_empty() {
                    out.push(std::mem::take(&mut word));
                    started = false;
                }
            }
            (None, c) => word.push(c),
        }
    }
    assert!(quote.is_none(), "unclosed quote in {line:?}");
    if started || !word.is_empty() {
        out.push(word);
    }
    out
}

/// A fresh scratch folder that sees the repository's `scenes/`.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph_readme_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    #[cfg(unix)]
    std::os::unix::fs::symlink(&scenes, dir.join("scenes")).expect("link to scenes/");
    #[cfg(not(unix))]
    panic!("the README test links scenes/ and needs a Unix system");
    dir
}

/// Runs the `sph` commands of `block` in `dir` (with `SPH_REFERENCE_DIR` set to `reference_dir`
/// when given, else unset); `cargo` lines are left to `.ci/run`. Returns how many ran; panics
/// with the command and its output when one fails.
pub fn run_block(block: &Block, dir: &Path, reference_dir: Option<&Path>) -> usize {
    let mut ran = 0;
    for line in &block.commands {
        let w = words(line);
        match w[0].as_str() {
            "cargo" => continue,
            "sph" => {}
            other => panic!("README command {line:?}: unknown program {other}"),
        }
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_sph"));
        cmd.args(&w[1..]).current_dir(dir);
        match reference_dir {
            Some(r) => cmd.env(sph::scene::REFERENCE_DIR_ENV, r),
            None => cmd.env_remove(sph::scene::REFERENCE_DIR_ENV),
        };
        let output = cmd.output().unwrap_or_else(|e| panic!("{line}: {e}"));
        assert!(
            output.status.success(),
            "README command failed: {line}\nstdout:\n{}\nstderr:\n{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
        ran += 1;
    }
    ran
}

#[cfg(test)]
mod tests {
    use super::words;

    #[test]
    fn words_split_like_a_shell() {
        assert_eq!(
            words(r#"sph sweep s.toml --set 'effects=["a"],["b"]' --out "o p""#),
            [
                "sph",
                "sweep",
                "s.toml",
                "--set",
                r#"effects=["a"],["b"]"#,
                "--out",
                "o p"
            ]
        );
        assert_eq!(words("a  ''  b"), ["a", "", "b"]);
    }
}
