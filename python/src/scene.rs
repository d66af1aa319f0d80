//! `Scene`: a loaded and validated scene, from a file (`sph::cli::load_located`, as `sph run`
//! and `sph check` load it) or from a table given as JSON text (the Python package turns a dict
//! into it).

use crate::errors::{from_lib, to_py};
use anyhow::Context;
use pyo3::prelude::*;
use sph::scene::Scene;
use std::path::{Path, PathBuf};

/// How a scene made from a dict is named in messages and in `check()`'s report.
const DICT_ORIGIN: &str = "<dict>";

/// A validated scene; immutable.
#[pyclass(name = "Scene", module = "sph._sph", frozen)]
pub struct PyScene {
    /// The validated scene.
    pub scene: Scene,
    /// The file it was read from (`None` for a scene made from a dict).
    pub path: Option<PathBuf>,
    /// The overrides applied, each `KEY=VALUE`.
    pub sets: Vec<String>,
}

impl PyScene {
    /// The name `sph check` shows for the scene: its file, or `<dict>`.
    pub fn shown(&self) -> PathBuf {
        self.path.clone().unwrap_or_else(|| PathBuf::from(DICT_ORIGIN))
    }
}

#[pymethods]
impl PyScene {
    /// Loads the scene file at `path` with `sets` (each `KEY=VALUE`, as `sph run --set`) and
    /// looks its probes' reference files up in `reference_dir` (default: `SPH_REFERENCE_DIR`).
    #[staticmethod]
    #[pyo3(signature = (path, sets=Vec::new(), reference_dir=None))]
    fn load(path: PathBuf, sets: Vec<String>, reference_dir: Option<PathBuf>) -> PyResult<Self> {
        let scene = sph::cli::load_located(&path, &sets, reference_dir.as_deref(), false)
            .with_context(|| format!("loading scene {}", path.display()))
            .map_err(to_py)?;
        Ok(Self {
            scene,
            path: Some(path),
            sets,
        })
    }

    /// Parses a scene given as JSON text (a table with the keys of a scene file), with `sets`;
    /// relative files it names (meshes) are read from `base_dir`.
    #[staticmethod]
    #[pyo3(signature = (json, sets=Vec::new(), base_dir=PathBuf::from("."), reference_dir=None))]
    fn from_json(
        json: &str,
        sets: Vec<String>,
        base_dir: PathBuf,
        reference_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        let table: toml::Table = serde_json::from_str(json)
            .map_err(|e| sph::scene::SceneError::Invalid {
                origin: DICT_ORIGIN.into(),
                problems: vec![sph::scene::Problem {
                    key: String::new(),
                    location: sph::scene::Location::Unknown,
                    reason: format!("not a scene table (TOML has no null; {e})"),
                }],
            })
            .map_err(from_lib)?;
        let text = toml::to_string(&table).map_err(|e| to_py(e.into()))?;
        let mut scene = sph::scene::parse_scene_in(&text, DICT_ORIGIN, &sets, &base_dir)
            .with_context(|| format!("loading scene {DICT_ORIGIN}"))
            .map_err(to_py)?;
        let dir = sph::scene::reference_dir(reference_dir.as_deref());
        sph::scene::locate_references(&mut scene, dir.as_deref());
        Ok(Self {
            scene,
            path: None,
            sets,
        })
    }

    /// What `sph check` prints for this scene: particle counts, memory needed and the stage
    /// plan, one line each. Raises as `sph check` fails (a malformed reference file).
    fn check(&self, py: Python<'_>) -> PyResult<String> {
        let shown = self.shown();
        py.detach(|| sph::cli::check_report(&self.scene, Path::new(&shown)))
            .map_err(to_py)
    }

    /// The scene's name (`name` key), if it has one.
    #[getter]
    fn name(&self) -> Option<String> {
        self.scene.name.clone()
    }

    /// 2 or 3.
    #[getter]
    fn dimension(&self) -> usize {
        self.scene.dimension
    }

    /// End time [s].
    #[getter]
    fn end_time(&self) -> f64 {
        self.scene.end_time
    }

    /// Particle spacing [m].
    #[getter]
    fn spacing(&self) -> f64 {
        self.scene.spacing
    }

    /// The file the scene was read from (`None` for a scene made from a dict).
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.path.clone()
    }

    /// The overrides applied, each `KEY=VALUE`.
    #[getter]
    fn sets(&self) -> Vec<String> {
        self.sets.clone()
    }

    /// The named solids, in scene order.
    #[getter]
    fn solids(&self) -> Vec<String> {
        self.scene.solids.iter().map(|s| s.name.clone()).collect()
    }

    /// The probes' names, in scene order.
    #[getter]
    fn probes(&self) -> Vec<String> {
        self.scene.probes.iter().map(|p| p.name.clone()).collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({}, {}D, end_time={} s)",
            self.shown().display(),
            self.scene.dimension,
            self.scene.end_time
        )
    }
}
