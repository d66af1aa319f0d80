//! Opening output files so that a link planted in a run folder cannot redirect a write.
//!
//! - New files are created exclusively (`O_CREAT | O_EXCL`, plus `O_NOFOLLOW` on unix): an
//!   existing file or symbolic link of that name is an error, never written through.
//! - Existing files (a CSV log continued on `--resume`, the folder's lock) are opened with
//!   `O_NOFOLLOW`: a symbolic link is an error.
//! - Temporary files of atomic writes get a unique name in the target's folder
//!   ([`unique_tmp_path`]) and are created exclusively; the rename that publishes one replaces
//!   a link at the target name, it does not write through it.
//! - Sub-folders (`frames/`, `surface/`) must be real directories ([`ensure_dir`]).

use std::ffi::OsString;
use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Adds `O_NOFOLLOW` where the platform has it.
fn no_follow(options: &mut OpenOptions) -> &mut OpenOptions {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW);
    }
    options
}

/// Creates `path` for writing; fails if anything (a file, a folder or a link) has that name.
pub fn create_new(path: &Path) -> std::io::Result<File> {
    no_follow(OpenOptions::new().write(true).create_new(true)).open(path)
}

/// Opens the existing regular file `path` for reading and writing, refusing a symbolic link.
pub fn open_existing(path: &Path) -> std::io::Result<File> {
    no_follow(OpenOptions::new().read(true).write(true)).open(path)
}

/// Opens `path` for reading and writing, creating it if absent, refusing a symbolic link.
pub fn open_or_create(path: &Path) -> std::io::Result<File> {
    no_follow(
        OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false),
    )
    .open(path)
}

/// Counter that makes temporary names unique within the process.
static TMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// A fresh temporary name beside `path`: `.NAME.PID-N.tmp` with `suffix` appended (e.g.
/// `.png`, so that an encoder choosing its format by extension still sees it). Hidden, and
/// unique per process and call, so no file or link can be planted at it in advance by name.
pub fn unique_tmp_path(path: &Path, suffix: &str) -> PathBuf {
    let n = TMP_COUNTER.fetch_add(1, Ordering::Relaxed);
    let mut name = OsString::from(".");
    name.push(path.file_name().unwrap_or_default());
    name.push(format!(".{}-{n}.tmp{suffix}", std::process::id()));
    path.with_file_name(name)
}

/// Whether `name` is a temporary name [`unique_tmp_path`] makes (left behind by a kill).
pub fn is_tmp_name(name: &str) -> bool {
    name.starts_with('.') && name.contains(".tmp")
}

/// Makes `dir` exist as a real directory: created if absent; an error if it is a link or a
/// file.
pub fn ensure_dir(dir: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(dir) {
        Ok(meta) if meta.is_dir() => Ok(()),
        Ok(_) => Err(std::io::Error::new(
            std::io::ErrorKind::AlreadyExists,
            "exists and is not a directory (a file or a symbolic link); sph does not write through it",
        )),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => std::fs::create_dir(dir),
        Err(e) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("sph_safe_file_{}_{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn tmp_names_are_unique_hidden_siblings() {
        let a = unique_tmp_path(Path::new("run/frames/frame_00001.vtu"), "");
        let b = unique_tmp_path(Path::new("run/frames/frame_00001.vtu"), ".png");
        assert_ne!(a, b);
        assert_eq!(a.parent(), Some(Path::new("run/frames")));
        let name = a.file_name().unwrap().to_str().unwrap();
        assert!(
            name.starts_with(".frame_00001.vtu.") && is_tmp_name(name),
            "{name}"
        );
        assert!(b.to_str().unwrap().ends_with(".tmp.png"));
    }

    #[cfg(unix)]
    #[test]
    fn links_are_never_written_through() {
        let dir = scratch("links");
        let outside = dir.join("outside.txt");
        std::fs::write(&outside, "keep").unwrap();
        let link = dir.join("forces.csv");
        std::os::unix::fs::symlink(&outside, &link).unwrap();
        assert!(create_new(&link).is_err(), "create_new wrote through a link");
        assert!(open_existing(&link).is_err(), "open_existing followed a link");
        assert!(open_or_create(&link).is_err(), "open_or_create followed a link");
        let sub = dir.join("frames");
        std::os::unix::fs::symlink(&dir, &sub).unwrap();
        assert!(ensure_dir(&sub).is_err(), "a linked folder was accepted");
        assert_eq!(std::fs::read_to_string(&outside).unwrap(), "keep");
        ensure_dir(&dir.join("real")).unwrap();
        ensure_dir(&dir.join("real")).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
    }
}
