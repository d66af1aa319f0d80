//! A run's output folder, owned by one run at a time.
//!
//! - **Lock.** `.sph.lock` is locked exclusively for the life of the run (`flock`, an advisory
//!   lock the operating system drops on any exit, a kill included); a second run into the
//!   folder is refused while the first holds it.
//! - **Manifest.** `run_manifest.json` names the run (a run identifier, the scene's hash) and
//!   every file the run writes, relative to the folder. A file is listed *before* it is first
//!   created ([`RunFolder::claim`]), so a run killed at any moment leaves no file of its own
//!   unlisted, and a file sph did not list is never overwritten or removed.
//! - **A new run** into a folder holding anything (another run's files, or files of the user's)
//!   is refused unless forced; forced, it removes the files the previous run's manifest lists
//!   and nothing else, and still refuses to overwrite an unlisted file.
//! - **A resumed run** continues the folder's manifest; the run driver checks that the
//!   checkpoint names the same run.

use crate::output::safe_file;
use crate::output::write_atomically;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::fs::File;
use std::path::{Path, PathBuf};

/// The lock file's name in a run folder.
pub const LOCK_FILE: &str = ".sph.lock";
/// The manifest's name in a run folder.
pub const MANIFEST_FILE: &str = "run_manifest.json";

/// Errors of a run folder, each naming the folder or file.
#[derive(Debug, thiserror::Error)]
pub enum RunFolderError {
    /// An operating-system call on `path` failed.
    #[error("I/O error on {}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The run folder's path names something other than a folder (a file, a device).
    #[error("--out {} is {kind}, not a folder: choose a folder for the run's results", path.display())]
    NotAFolder {
        /// The path.
        path: PathBuf,
        /// What it is.
        kind: &'static str,
    },
    /// Another run holds the folder's lock.
    #[error(
        "{} is in use by another sph run (its lock {LOCK_FILE} is held); wait for it to end or choose another --out",
        dir.display()
    )]
    Locked {
        /// The folder.
        dir: PathBuf,
    },
    /// A new run was pointed at a folder that is not empty.
    #[error(
        "{} already holds {what} ({}); give --force to replace that run's files (only the files its manifest lists are removed), --resume DIR to continue a run, or another --out",
        dir.display(), names.join(", ")
    )]
    Occupied {
        /// The folder.
        dir: PathBuf,
        /// What it holds, in words.
        what: String,
        /// A few of the names found.
        names: Vec<String>,
    },
    /// A file the run would write exists and is not listed in the folder's manifest.
    #[error(
        "{} exists and was not written by this run (not in {MANIFEST_FILE}); sph does not overwrite it: move it away or choose another --out",
        path.display()
    )]
    Foreign {
        /// The file.
        path: PathBuf,
    },
    /// A folder to resume has no manifest.
    #[error("{} has no {MANIFEST_FILE}: it is not a run folder sph can continue", dir.display())]
    NoManifest {
        /// The folder.
        dir: PathBuf,
    },
    /// The manifest could not be read.
    #[error("{}: not a manifest of sph run: {reason}", path.display())]
    Manifest {
        /// The manifest file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

impl RunFolderError {
    fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Who a run is: a run identifier, unique per run and kept across resumes, and the FNV-1a
/// hash of its scene file's bytes (the `--set` overrides are stored with the run).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunIdentity {
    /// 16 hex digits from the start time and process id.
    pub run_id: String,
    /// 16 hex digits; empty when the run did not start from a file.
    pub scene_hash: String,
}

impl RunIdentity {
    /// A new run of the scene whose file holds `scene_bytes`.
    pub fn new(scene_bytes: Option<&[u8]>) -> Self {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let seed = format!("{nanos}:{}", std::process::id());
        Self {
            run_id: hex(seed.as_bytes()),
            scene_hash: scene_bytes.map(hex).unwrap_or_default(),
        }
    }
}

/// FNV-1a 64 of `bytes` as 16 hex digits.
pub fn hex(bytes: &[u8]) -> String {
    use crate::solver::checkpoint::{FNV_OFFSET, fnv1a};
    format!("{:016x}", fnv1a(bytes, FNV_OFFSET))
}

/// What `run_manifest.json` holds.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
struct Manifest {
    #[serde(flatten)]
    identity: RunIdentity,
    /// Files written by the run, relative to the folder (`/`-separated).
    files: BTreeSet<String>,
}

/// An output folder held by one run (module doc). The lock is released when this is dropped.
#[derive(Debug)]
pub struct RunFolder {
    dir: PathBuf,
    manifest: Manifest,
    _lock: File,
}

impl RunFolder {
    /// Takes `dir` for a new run `identity`: creates it, locks it and, when it holds anything,
    /// refuses ([`RunFolderError::Occupied`]) unless `force`; forced, removes the files the
    /// previous run's manifest lists.
    pub fn fresh(dir: &Path, identity: RunIdentity, force: bool) -> Result<Self, RunFolderError> {
        let lock = lock(dir)?;
        let previous = read_manifest(dir).inspect_err(|_| lock.abandon(dir))?;
        let names = entries(dir).inspect_err(|_| lock.abandon(dir))?;
        if !names.is_empty() && !force {
            let what = match &previous {
                Some(m) => format!("the files of run {}", m.identity.run_id),
                None => "files not written by sph".to_string(),
            };
            lock.abandon(dir);
            return Err(RunFolderError::Occupied {
                dir: dir.to_path_buf(),
                what,
                names: names.into_iter().take(5).collect(),
            });
        }
        if let Some(previous) = previous {
            remove_listed(dir, &previous.files)?;
        }
        let folder = Self {
            dir: dir.to_path_buf(),
            manifest: Manifest {
                identity,
                files: BTreeSet::new(),
            },
            _lock: lock.file,
        };
        folder.write_manifest()?;
        Ok(folder)
    }

    /// Takes `dir` to continue the run its manifest names.
    pub fn resume(dir: &Path) -> Result<Self, RunFolderError> {
        let lock = lock(dir)?;
        let manifest = read_manifest(dir)
            .and_then(|m| {
                m.ok_or_else(|| RunFolderError::NoManifest {
                    dir: dir.to_path_buf(),
                })
            })
            .inspect_err(|_| lock.abandon(dir))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            manifest,
            _lock: lock.file,
        })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The run the folder holds.
    pub fn identity(&self) -> &RunIdentity {
        &self.manifest.identity
    }

    /// Whether `relative` is one of this run's files.
    pub fn owns(&self, relative: &str) -> bool {
        self.manifest.files.contains(relative)
    }

    /// Lists `relative` (e.g. `frames/frame_00003.vtu`) as this run's before it is written and
    /// returns its path; its parent folders are created as real folders. A file or link of
    /// that name the run did not list is [`RunFolderError::Foreign`].
    pub fn claim(&mut self, relative: &str) -> Result<PathBuf, RunFolderError> {
        let path = self.dir.join(relative);
        if self.owns(relative) {
            return Ok(path);
        }
        if let Some(parent) = Path::new(relative).parent() {
            let mut sub = self.dir.clone();
            for part in parent.components() {
                sub.push(part);
                safe_file::ensure_dir(&sub).map_err(|e| RunFolderError::io(&sub, e))?;
            }
        }
        if std::fs::symlink_metadata(&path).is_ok() {
            return Err(RunFolderError::Foreign { path });
        }
        self.manifest.files.insert(relative.to_string());
        self.write_manifest()?;
        Ok(path)
    }

    /// Removes this run's file `relative` (e.g. a frame written after the checkpoint being
    /// resumed) and unlists it.
    pub fn discard(&mut self, relative: &str) -> Result<(), RunFolderError> {
        if !self.manifest.files.remove(relative) {
            return Ok(());
        }
        remove_listed(&self.dir, &BTreeSet::from([relative.to_string()]))?;
        self.write_manifest()
    }

    /// The files listed whose name starts with `prefix` (e.g. `frames/`).
    pub fn listed(&self, prefix: &str) -> Vec<String> {
        self.manifest
            .files
            .iter()
            .filter(|f| f.starts_with(prefix))
            .cloned()
            .collect()
    }

    fn write_manifest(&self) -> Result<(), RunFolderError> {
        let path = self.dir.join(MANIFEST_FILE);
        let json = serde_json::to_vec_pretty(&self.manifest).map_err(|e| RunFolderError::Manifest {
            path: path.clone(),
            reason: e.to_string(),
        })?;
        write_atomically(&path, |w| {
            use std::io::Write;
            w.write_all(&json)?;
            w.write_all(b"\n")
        })
        .map_err(|e| match e {
            crate::output::OutputError::Io { path, source } => RunFolderError::Io { path, source },
            other => RunFolderError::Manifest {
                path,
                reason: other.to_string(),
            },
        })
    }
}

/// A folder's lock, and whether taking it created the lock file.
struct Lock {
    file: File,
    created: bool,
}

impl Lock {
    /// A refused run leaves the folder as it found it: the lock file goes if this run made it.
    fn abandon(&self, dir: &Path) {
        if self.created {
            let _ = std::fs::remove_file(dir.join(LOCK_FILE));
        }
    }
}

/// Creates `dir` (and its parents) and takes its lock, without waiting.
fn lock(dir: &Path) -> Result<Lock, RunFolderError> {
    // A path that exists must be a folder (links followed): "File exists (os error 17)" from
    // `create_dir_all` would not say which.
    if let Ok(meta) = std::fs::metadata(dir) {
        if !meta.is_dir() {
            let kind = if meta.is_file() {
                "a file"
            } else {
                "not a folder or a file"
            };
            return Err(RunFolderError::NotAFolder {
                path: dir.to_path_buf(),
                kind,
            });
        }
    }
    std::fs::create_dir_all(dir).map_err(|e| RunFolderError::io(dir, e))?;
    let path = dir.join(LOCK_FILE);
    let created = std::fs::symlink_metadata(&path).is_err();
    let file = safe_file::open_or_create(&path).map_err(|e| RunFolderError::io(&path, e))?;
    match try_lock(&file) {
        Ok(true) => Ok(Lock { file, created }),
        Ok(false) => Err(RunFolderError::Locked {
            dir: dir.to_path_buf(),
        }),
        Err(e) => Err(RunFolderError::io(&path, e)),
    }
}

/// Takes an exclusive advisory lock on `file` without waiting: `Ok(false)` when another
/// process holds it. The lock goes with the file's descriptor, so any exit releases it.
#[cfg(unix)]
fn try_lock(file: &File) -> std::io::Result<bool> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock only reads the descriptor, which `file` keeps open for the call.
    let result = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
    if result == 0 {
        return Ok(true);
    }
    let error = std::io::Error::last_os_error();
    if error.raw_os_error() == Some(libc::EWOULDBLOCK) {
        Ok(false)
    } else {
        Err(error)
    }
}

/// Without flock the folder is not locked (the manifest still guards its files).
#[cfg(not(unix))]
fn try_lock(_file: &File) -> std::io::Result<bool> {
    Ok(true)
}

/// The folder's manifest, if it has one.
fn read_manifest(dir: &Path) -> Result<Option<Manifest>, RunFolderError> {
    let path = dir.join(MANIFEST_FILE);
    let file = match safe_file::open_existing(&path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(RunFolderError::io(&path, e)),
    };
    // A manifest lists file names; 64 MiB is far beyond any run's and bounds a hostile one.
    let reader = std::io::Read::take(file, 64 << 20);
    serde_json::from_reader(std::io::BufReader::new(reader))
        .map(Some)
        .map_err(|e| RunFolderError::Manifest {
            path,
            reason: e.to_string(),
        })
}

/// The names in `dir` other than the lock (sorted).
fn entries(dir: &Path) -> Result<Vec<String>, RunFolderError> {
    let read = std::fs::read_dir(dir).map_err(|e| RunFolderError::io(dir, e))?;
    let mut names = Vec::new();
    for entry in read {
        let entry = entry.map_err(|e| RunFolderError::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name != LOCK_FILE {
            names.push(name);
        }
    }
    names.sort();
    Ok(names)
}

/// Whether every folder on the way from `dir` to `dir/relative` is a real folder, not a link.
fn real_folders(dir: &Path, relative: Option<&Path>) -> bool {
    let mut at = dir.to_path_buf();
    for part in relative.into_iter().flat_map(|r| r.components()) {
        at.push(part);
        if !std::fs::symlink_metadata(&at).is_ok_and(|m| m.is_dir()) {
            return false;
        }
    }
    true
}

/// Removes the listed files (a link is removed, never followed), temporary files a kill left
/// in their folders, then the folders the listing emptied; nothing else.
fn remove_listed(dir: &Path, files: &BTreeSet<String>) -> Result<(), RunFolderError> {
    let mut folders = BTreeSet::new();
    for relative in files {
        // A listed name is relative and stays inside the folder.
        let path = Path::new(relative);
        if path.is_absolute()
            || path
                .components()
                .any(|c| !matches!(c, std::path::Component::Normal(_)))
        {
            return Err(RunFolderError::Manifest {
                path: dir.join(MANIFEST_FILE),
                reason: format!("lists {relative:?}, which is not a name inside the folder"),
            });
        }
        if !real_folders(dir, path.parent()) {
            // A listed file behind a linked folder is not removed through the link.
            continue;
        }
        let full = dir.join(path);
        match std::fs::symlink_metadata(&full) {
            Ok(meta) if !meta.is_dir() => {
                std::fs::remove_file(&full).map_err(|e| RunFolderError::io(&full, e))?
            }
            Ok(_) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(RunFolderError::io(&full, e)),
        }
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            folders.insert(parent.to_path_buf());
        }
    }
    folders.insert(PathBuf::new());
    for folder in folders.iter().rev() {
        if !real_folders(dir, Some(folder)) {
            continue;
        }
        let full = dir.join(folder);
        let Ok(read) = std::fs::read_dir(&full) else {
            continue;
        };
        for entry in read.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if safe_file::is_tmp_name(&name) && entry.file_type().is_ok_and(|t| t.is_file()) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
        if !folder.as_os_str().is_empty() {
            // Only an emptied folder goes; one holding the user's files stays.
            let _ = std::fs::remove_dir(&full);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("sph_run_folder_{}_{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn a_second_run_is_refused_while_the_first_holds_the_lock() {
        let dir = scratch("lock");
        let first = RunFolder::fresh(&dir, RunIdentity::new(None), false).unwrap();
        let second = RunFolder::resume(&dir);
        assert!(matches!(second, Err(RunFolderError::Locked { .. })), "{second:?}");
        drop(first);
        RunFolder::resume(&dir).expect("free once the first is dropped");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn forcing_removes_only_the_listed_files() {
        let dir = scratch("force");
        let mut run = RunFolder::fresh(&dir, RunIdentity::new(None), false).unwrap();
        for name in ["summary.json", "frames/frame_00000.vtu"] {
            std::fs::write(run.claim(name).unwrap(), "run").unwrap();
        }
        let old = run.identity().run_id.clone();
        drop(run);
        std::fs::write(dir.join("notes.txt"), "mine").unwrap();
        std::fs::write(dir.join("frames/mine.vtu"), "mine").unwrap();
        let refused = RunFolder::fresh(&dir, RunIdentity::new(None), false);
        match refused {
            Err(RunFolderError::Occupied { what, .. }) => assert!(what.contains(&old), "{what}"),
            other => panic!("{other:?}"),
        }
        let mut run = RunFolder::fresh(&dir, RunIdentity::new(b"x".as_slice().into()), true).unwrap();
        assert!(!dir.join("summary.json").exists() && !dir.join("frames/frame_00000.vtu").exists());
        assert_eq!(std::fs::read_to_string(dir.join("notes.txt")).unwrap(), "mine");
        assert_eq!(
            std::fs::read_to_string(dir.join("frames/mine.vtu")).unwrap(),
            "mine"
        );
        assert!(matches!(
            run.claim("notes.txt"),
            Err(RunFolderError::Foreign { .. })
        ));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_manifest_cannot_reach_outside_its_folder() {
        let dir = scratch("escape");
        std::fs::create_dir_all(&dir).unwrap();
        let outside = scratch("escape_target");
        std::fs::create_dir_all(&outside).unwrap();
        std::fs::write(outside.join("keep"), "keep").unwrap();
        let name = format!("../{}/keep", outside.file_name().unwrap().to_string_lossy());
        let manifest = format!(r#"{{"run_id":"a","scene_hash":"","files":["{name}"]}}"#);
        std::fs::write(dir.join(MANIFEST_FILE), manifest).unwrap();
        let forced = RunFolder::fresh(&dir, RunIdentity::new(None), true);
        assert!(
            matches!(forced, Err(RunFolderError::Manifest { .. })),
            "{forced:?}"
        );
        assert!(outside.join("keep").exists());
        let _ = std::fs::remove_dir_all(&dir);
        let _ = std::fs::remove_dir_all(&outside);
    }
}
