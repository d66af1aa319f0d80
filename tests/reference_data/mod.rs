//! The experimental reference data of the validation suite (`--features validation-data`):
//! the directory named by `SPH_REFERENCE_DIR`. The suite fails, never skips, when it is not set
//! or lacks a file (docs/validation.md lists every file and its public source).

use std::path::PathBuf;

/// The reference directory; panics with what to do when `SPH_REFERENCE_DIR` is not set or is
/// not a directory.
pub fn reference_dir() -> PathBuf {
    let var = sph::scene::REFERENCE_DIR_ENV;
    let dir = std::env::var_os(var).filter(|v| !v.is_empty()).map(PathBuf::from);
    let Some(dir) = dir else {
        panic!(
            "the validation suite needs the reference data: set {var} to the directory holding \
             the files of docs/validation.md"
        )
    };
    assert!(dir.is_dir(), "{var}={} is not a directory", dir.display());
    dir
}

/// The reference file `name`; panics naming it when it is missing.
pub fn reference_file(name: &str) -> PathBuf {
    let path = reference_dir().join(name);
    assert!(
        path.is_file(),
        "reference file {} is missing (docs/validation.md says where to get it)",
        path.display()
    );
    path
}
