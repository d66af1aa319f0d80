//! Reading a scene file with a size cap.
//!
//! A scene is a few kilobytes of TOML; the largest shipped one is under 4 KiB. The cap keeps a
//! mistaken path (a log, a binary, `/dev/zero`, a named pipe) from being read until memory runs
//! out: the file's metadata length is checked before reading, and the read itself stops one byte
//! past the cap, because a character device or a pipe reports a length of 0 whatever it holds.

use std::io::Read;
use std::path::Path;

use super::SceneError;

/// The largest scene file read \[bytes\]: 16 MiB. Far above any hand-written scene (the
/// shipped ones are under 4 KiB) and far below the memory a run needs, so that refusing a
/// larger file loses nothing while reading one could exhaust memory (the TOML parser holds the
/// text and its table, several times the file's size).
pub const MAX_SCENE_BYTES: u64 = 16 * 1024 * 1024;

/// The bytes of the scene file at `path`, at most [`MAX_SCENE_BYTES`].
///
/// Errors: [`SceneError::Io`] when the file cannot be opened or read (missing, a directory,
/// unreadable); [`SceneError::TooLarge`] when its metadata length is above the cap (nothing is
/// read then) or when more than the cap can be read from it (a device or a pipe).
pub fn read_scene_bytes(path: &Path) -> Result<Vec<u8>, SceneError> {
    let io = |source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if meta.len() > MAX_SCENE_BYTES {
        return Err(SceneError::TooLarge {
            path: path.to_path_buf(),
            size: Some(meta.len()),
        });
    }
    let mut bytes = Vec::new();
    file.take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_SCENE_BYTES {
        return Err(SceneError::TooLarge {
            path: path.to_path_buf(),
            size: None,
        });
    }
    Ok(bytes)
}
