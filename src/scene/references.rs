//! Where a probe's reference data are found.
//!
//! Experimental reference data are not part of the product: they come from public sources
//! (`docs/validation.md` lists each file and how to obtain it) and live in a directory the user
//! names (`--reference-dir DIR`, or the environment variable [`REFERENCE_DIR_ENV`]). A scene's
//! `[probe.reference] file` is a path relative to that directory, or an absolute path.
//!
//! A file that cannot be found does not stop a run: the probe is still sampled, its comparison is
//! skipped and the run records why ([`ReferenceLocation::Missing`]). A file that is found but
//! malformed is an error ([`crate::probe::check_references`]).

use std::fmt;
use std::path::{Path, PathBuf};

use super::Scene;

/// The environment variable naming the reference directory when `--reference-dir` is not given.
pub const REFERENCE_DIR_ENV: &str = "SPH_REFERENCE_DIR";

/// Where the document that lists every reference file's public source lives in the repository.
pub const REFERENCE_SOURCES_DOC: &str = "docs/validation.md";

/// Whether a probe's reference file has been looked up, and what was found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ReferenceLocation {
    /// Not looked up yet ([`locate_references`] has not run): reading it is an error.
    Unlocated,
    /// The file exists at this path.
    Found(PathBuf),
    /// The file is not available: the comparison is skipped.
    Missing(MissingReason),
}

/// Why a reference file is not available.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MissingReason {
    /// The file is relative and no reference directory was given.
    NoDirectory,
    /// The file is not at this path.
    NotFound(PathBuf),
    /// The path names something other than a regular file (a directory, a device, a pipe).
    NotRegular(PathBuf, &'static str),
}

impl fmt::Display for MissingReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MissingReason::NoDirectory => write!(
                f,
                "no reference directory is set (--reference-dir DIR or {REFERENCE_DIR_ENV})"
            ),
            MissingReason::NotFound(path) => write!(f, "{} does not exist", path.display()),
            MissingReason::NotRegular(path, kind) => {
                write!(f, "{} is {kind}, not a regular file", path.display())
            }
        }
    }
}

/// A probe whose comparison is skipped because its reference file is not available.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkippedReference {
    /// Probe name.
    pub probe: String,
    /// The file as the scene names it.
    pub file: PathBuf,
    /// Why it is not available.
    pub reason: MissingReason,
}

impl fmt::Display for SkippedReference {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "probe {}: reference {} not compared: {}; {REFERENCE_SOURCES_DOC} says where to get it",
            self.probe,
            self.file.display(),
            self.reason
        )
    }
}

/// Looks every probe's reference file up: an absolute file as it is, a relative one in `dir`.
/// Returns the probes whose file is not available (their comparison is skipped); the others'
/// locations become [`ReferenceLocation::Found`].
pub fn locate_references(scene: &mut Scene, dir: Option<&Path>) -> Vec<SkippedReference> {
    for reference in scene.probes.iter_mut().filter_map(|p| p.reference.as_mut()) {
        let path = if reference.file.is_absolute() {
            Some(reference.file.clone())
        } else {
            dir.map(|d| d.join(&reference.file))
        };
        use crate::bounded_read::{BoundedReadError, check_regular_file};
        reference.location = match path {
            Some(p) => match check_regular_file(&p) {
                Ok(()) => ReferenceLocation::Found(p),
                Err(BoundedReadError::NotRegular { kind, .. }) => {
                    ReferenceLocation::Missing(MissingReason::NotRegular(p, kind))
                }
                Err(_) => ReferenceLocation::Missing(MissingReason::NotFound(p)),
            },
            None => ReferenceLocation::Missing(MissingReason::NoDirectory),
        };
    }
    skipped_references(scene)
}

/// The probes of `scene` whose comparison is skipped (after [`locate_references`]).
pub fn skipped_references(scene: &Scene) -> Vec<SkippedReference> {
    scene
        .probes
        .iter()
        .filter_map(|p| {
            let r = p.reference.as_ref()?;
            match &r.location {
                ReferenceLocation::Missing(reason) => Some(SkippedReference {
                    probe: p.name.clone(),
                    file: r.file.clone(),
                    reason: reason.clone(),
                }),
                _ => None,
            }
        })
        .collect()
}

/// The reference directory given on the command line, or else by [`REFERENCE_DIR_ENV`] (an
/// empty value counts as unset).
pub fn reference_dir(given: Option<&Path>) -> Option<PathBuf> {
    given.map(Path::to_path_buf).or_else(|| {
        std::env::var_os(REFERENCE_DIR_ENV)
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse_scene;

    const SCENE: &str = r#"
dimension = 2
effects = ["gravity"]
[domain]
min = [0.0, 0.0]
max = [1.0, 1.0]
[particles]
spacing = 0.05
smoothing_ratio = 2.0
[fluid]
rho0 = 1000.0
sound_speed = 10.0
gravity = [0.0, -9.81]
[[fluid_box]]
min = [0.0, 0.0]
max = [0.2, 0.2]
[solver]
kind = "wcsph"
end_time = 0.1
[[probe]]
name = "front"
kind = "front"
axis = "x"
[probe.reference]
file = "front.csv"
length = 0.2
"#;

    fn location(scene: &Scene) -> &ReferenceLocation {
        &scene.probes[0].reference.as_ref().unwrap().location
    }

    #[test]
    fn a_loaded_scene_has_not_looked_its_files_up() {
        let scene = parse_scene(SCENE, "t", &[]).unwrap();
        assert_eq!(location(&scene), &ReferenceLocation::Unlocated);
    }

    #[test]
    fn without_a_directory_the_comparison_is_skipped() {
        let mut scene = parse_scene(SCENE, "t", &[]).unwrap();
        let skipped = locate_references(&mut scene, None);
        assert_eq!(skipped.len(), 1);
        assert_eq!(skipped[0].reason, MissingReason::NoDirectory);
        let line = skipped[0].to_string();
        assert!(
            line.contains("front.csv") && line.contains(REFERENCE_DIR_ENV),
            "{line}"
        );
        assert_eq!(skipped_references(&scene), skipped);
    }

    #[test]
    fn a_file_in_the_directory_is_found_and_a_missing_one_named() {
        let dir = std::env::temp_dir().join(format!("sph-references-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut scene = parse_scene(SCENE, "t", &[]).unwrap();
        let skipped = locate_references(&mut scene, Some(&dir));
        assert_eq!(
            skipped[0].reason,
            MissingReason::NotFound(dir.join("front.csv")),
            "{}",
            skipped[0]
        );
        std::fs::write(dir.join("front.csv"), "x\n").unwrap();
        assert!(locate_references(&mut scene, Some(&dir)).is_empty());
        assert_eq!(location(&scene), &ReferenceLocation::Found(dir.join("front.csv")));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
