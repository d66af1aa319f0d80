//! Reading a file that a scene or a command names, bounded: only a regular file is read (a
//! directory, a device, a FIFO or a socket is refused by its kind, before it is opened: opening
//! a FIFO would wait for a writer, and `/dev/zero` never ends), and at most `limit` bytes
//! (checked from the metadata before reading, and the read stops one byte past the limit in case
//! the file grows meanwhile). The scene file itself has its own reader with the same rules
//! (`scene::read`).

use std::io::Read;
use std::path::{Path, PathBuf};

/// Why a file was not read.
#[derive(Debug, thiserror::Error)]
pub enum BoundedReadError {
    /// The file cannot be inspected, opened or read (missing, unreadable).
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The path names something other than a regular file.
    #[error("{} is {kind}, not a regular file", path.display())]
    NotRegular {
        /// The path.
        path: PathBuf,
        /// What it is ("a directory", "a character device", ...).
        kind: &'static str,
    },
    /// The file is larger than the limit.
    #[error("{} is too large: {}, the limit is {limit} bytes", path.display(), size.map_or_else(|| "more than the limit could be read".to_string(), |s| format!("{s} bytes")))]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its length by its metadata, if that was above the limit.
        size: Option<u64>,
        /// The limit [bytes].
        limit: u64,
    },
}

/// What `meta` describes, unless it is a regular file.
fn not_regular(meta: &std::fs::Metadata) -> Option<&'static str> {
    let t = meta.file_type();
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_fifo() {
            return Some("a named pipe");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some("not a file")
}

/// Whether `path` (links followed) names a regular file; `Err` with its kind otherwise, or the
/// error of inspecting it.
pub fn check_regular_file(path: &Path) -> Result<(), BoundedReadError> {
    let meta = std::fs::metadata(path).map_err(|source| BoundedReadError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    match not_regular(&meta) {
        None => Ok(()),
        Some(kind) => Err(BoundedReadError::NotRegular {
            path: path.to_path_buf(),
            kind,
        }),
    }
}

/// The bytes of the regular file at `path` (links followed), at most `limit` of them.
///
/// # Errors
/// [`BoundedReadError::NotRegular`] for anything but a regular file (not opened),
/// [`BoundedReadError::TooLarge`] above `limit` (by the metadata, before reading, or by what
/// could be read), [`BoundedReadError::Io`] when it cannot be inspected or read.
pub fn read_regular_file(path: &Path, limit: u64) -> Result<Vec<u8>, BoundedReadError> {
    let io = |source| BoundedReadError::Io {
        path: path.to_path_buf(),
        source,
    };
    check_regular_file(path)?;
    let file = std::fs::File::open(path).map_err(io)?;
    let size = file.metadata().map_err(io)?.len();
    if size > limit {
        return Err(BoundedReadError::TooLarge {
            path: path.to_path_buf(),
            size: Some(size),
            limit,
        });
    }
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(BoundedReadError::TooLarge {
            path: path.to_path_buf(),
            size: None,
            limit,
        });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_regular_file_within_the_limit_is_read_and_others_are_refused_by_kind_or_size() {
        let dir = std::env::temp_dir().join(format!("sph_bounded_read_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.csv");
        std::fs::write(&file, b"t,x\n0,1\n").unwrap();
        assert_eq!(read_regular_file(&file, 8).unwrap(), b"t,x\n0,1\n");
        let e = read_regular_file(&file, 7).unwrap_err();
        assert!(
            matches!(
                e,
                BoundedReadError::TooLarge {
                    size: Some(8),
                    limit: 7,
                    ..
                }
            ),
            "{e}"
        );
        assert!(
            e.to_string().contains("8 bytes") && e.to_string().contains("limit is 7"),
            "{e}"
        );
        let e = read_regular_file(&dir, 1 << 20).unwrap_err();
        assert!(
            e.to_string().contains("is a directory, not a regular file"),
            "{e}"
        );
        #[cfg(unix)]
        {
            let e = read_regular_file(Path::new("/dev/zero"), 1 << 20).unwrap_err();
            assert!(e.to_string().contains("a character device"), "{e}");
            let link = dir.join("zero.obj");
            let _ = std::fs::remove_file(&link);
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            let e = read_regular_file(&link, 1 << 20).unwrap_err();
            assert!(
                e.to_string().contains("a character device"),
                "through a link: {e}"
            );
        }
        let e = read_regular_file(&dir.join("missing.csv"), 1).unwrap_err();
        assert!(matches!(e, BoundedReadError::Io { .. }), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
