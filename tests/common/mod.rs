//! Helpers shared by the integration tests: each test binary says `mod common;` (a binary made
//! of a folder, `tests/NAME/main.rs`, says `#[path = "../common/mod.rs"] mod common;`) and uses
//! the part it needs. Folders are named after the test binary (`CARGO_CRATE_NAME`), the process
//! and a counter, so tests running in parallel never share one.
#![allow(dead_code)] // each test binary uses a part

use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

pub mod run;
pub mod scene;
pub mod tolerance;

/// A path under the temporary directory, unique to this test binary, process, `name` and
/// call, with nothing at it (for an `--out` the program is to create).
pub fn fresh_path(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let path = std::env::temp_dir().join(format!(
        "sph_{}_{}_{name}_{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&path);
    path
}

/// A fresh, empty folder ([`fresh_path`], created).
pub fn scratch(name: &str) -> PathBuf {
    let dir = fresh_path(name);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// A fresh, empty folder removed when dropped.
pub struct ScratchDir(PathBuf);

impl Deref for ScratchDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh, empty folder ([`scratch`]) removed when the guard is dropped.
pub fn scratch_dir(name: &str) -> ScratchDir {
    ScratchDir(scratch(name))
}

/// Every shipped scene: the `*.toml` files of `scenes/` and `scenes/hard/`, sorted.
pub fn shipped_scenes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut all = Vec::new();
    for dir in ["scenes", "scenes/hard"] {
        for entry in std::fs::read_dir(root.join(dir)).expect("scene folder") {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|e| e == "toml") {
                all.push(path);
            }
        }
    }
    all.sort();
    all
}

/// No temporary file of the atomic writes (`output::safe_file::is_tmp_name`) is left in `dir`.
pub fn assert_no_tmp_left(dir: &Path) {
    for entry in std::fs::read_dir(dir).expect("folder") {
        let name = entry.expect("entry").file_name().to_string_lossy().into_owned();
        assert!(
            !sph::output::safe_file::is_tmp_name(&name),
            "{name} left in {}",
            dir.display()
        );
    }
}
