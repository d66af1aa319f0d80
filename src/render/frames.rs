//! A finished (or stopped) run's frames as the renderer needs them: the `.pvd` series, the
//! dimension and particle spacing, and per frame the positions, the coloured field and the
//! particle kinds.
//!
//! The dimension and spacing come from `summary.json`; a run stopped before writing it (killed,
//! still running) falls back to the first frame: 2D when every z is 0, and the spacing as the
//! median nearest-neighbour distance of a sample of particles.

use super::{ColorField, RenderError};
use crate::output::{PvdSeries, read_summary, read_vtu};
use std::path::{Path, PathBuf};

/// Particles sampled for the nearest-neighbour spacing estimate.
const SPACING_SAMPLE: usize = 256;

/// The frames of one run directory.
#[derive(Debug, Clone)]
pub struct RunFrames {
    /// The run directory.
    pub dir: PathBuf,
    /// `(t [s], frame file)` in series order, files resolved against `dir`.
    pub frames: Vec<(f64, PathBuf)>,
    /// Spatial dimension, 2 or 3.
    pub dimension: usize,
    /// Initial particle spacing [m].
    pub spacing: f64,
}

/// The particles of one frame, reduced to what is drawn.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameParticles {
    /// Positions [m] (z = 0 in 2D).
    pub position: Vec<[f32; 3]>,
    /// The coloured field per particle, in the field's unit ([`ColorField`]).
    pub value: Vec<f64>,
    /// Particle kind: 0 = fluid, k > 0 = the k-th named solid (drawn grey).
    pub kind: Vec<u32>,
}

impl RunFrames {
    /// Opens the run in `dir`: its `particles.pvd`, and `summary.json` when present.
    ///
    /// # Errors
    /// [`RenderError::NoRunDir`], [`RenderError::NoFrames`] (no `particles.pvd`, or one that
    /// lists no frame), [`RenderError::Output`] for an unreadable series, summary or first frame.
    pub fn open(dir: &Path) -> Result<Self, RenderError> {
        if !dir.is_dir() {
            return Err(RenderError::NoRunDir {
                dir: dir.to_path_buf(),
            });
        }
        let pvd = dir.join("particles.pvd");
        if !pvd.is_file() {
            return Err(RenderError::NoFrames {
                dir: dir.to_path_buf(),
            });
        }
        let series = PvdSeries::read(&pvd)?;
        if series.is_empty() {
            return Err(RenderError::NoFrames {
                dir: dir.to_path_buf(),
            });
        }
        let frames: Vec<(f64, PathBuf)> = series.entries().iter().map(|(t, f)| (*t, dir.join(f))).collect();
        let summary_path = dir.join("summary.json");
        let summary = if summary_path.is_file() {
            Some(read_summary(&summary_path)?)
        } else {
            None
        };
        let from_summary = summary.as_ref().and_then(|s| {
            let spacing = s.extra.get("spacing")?.as_f64()?;
            ((s.dimension == 2 || s.dimension == 3) && spacing > 0.0).then_some((s.dimension, spacing))
        });
        let (dimension, spacing) = match from_summary {
            Some(found) => found,
            None => {
                let first = read_vtu(&frames[0].1)?;
                let dimension = if first.points.iter().all(|p| p[2] == 0.0) {
                    2
                } else {
                    3
                };
                let spacing = median_nearest_distance(&first.points).ok_or_else(|| RenderError::Spacing {
                    frame: frames[0].1.clone(),
                })?;
                (dimension, spacing)
            }
        };
        Ok(RunFrames {
            dir: dir.to_path_buf(),
            frames,
            dimension,
            spacing,
        })
    }
}

/// Reads the frame file `path` and reduces it to positions, `field` and kinds.
///
/// # Errors
/// [`RenderError::Output`] for an unreadable file, [`RenderError::MissingArray`] when an array
/// the picture needs is absent or has the wrong shape.
pub fn read_frame(path: &Path, field: ColorField) -> Result<FrameParticles, RenderError> {
    let data = read_vtu(path)?;
    let n = data.points.len();
    let array = |name: &'static str, components: usize| {
        data.point_array(name)
            .filter(|a| a.components == components && a.values.len() == n * components)
            .ok_or_else(|| RenderError::MissingArray {
                frame: path.to_path_buf(),
                name,
            })
    };
    let kind = array("kind", 1)?;
    let value = match field {
        ColorField::Speed => array("velocity", 3)?
            .values
            .chunks_exact(3)
            .map(|u| (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt())
            .collect(),
        ColorField::Pressure => array("pressure", 1)?.values.clone(),
        ColorField::Density => array("density", 1)?.values.clone(),
    };
    // Kinds are stored as UInt32, so the conversion back from f64 is exact.
    let kind = kind.values.iter().map(|&k| k as u32).collect();
    Ok(FrameParticles {
        position: data.points,
        value,
        kind,
    })
}

/// The median distance from a sample of up to [`SPACING_SAMPLE`] particles (evenly spread over
/// the index range) to their nearest other particle [m]; `None` with fewer than two distinct
/// points.
fn median_nearest_distance(points: &[[f32; 3]]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let stride = points.len().div_ceil(SPACING_SAMPLE).max(1);
    let mut nearest: Vec<f64> = (0..points.len())
        .step_by(stride)
        .filter_map(|i| {
            let p = points[i].map(f64::from);
            points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| {
                    let d = [0, 1, 2].map(|c| f64::from(q[c]) - p[c]);
                    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
                })
                .filter(|d| *d > 0.0 && d.is_finite())
                .min_by(f64::total_cmp)
        })
        .collect();
    if nearest.is_empty() {
        return None;
    }
    let mid = nearest.len() / 2;
    Some(*nearest.select_nth_unstable_by(mid, f64::total_cmp).1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_distance_of_a_lattice_is_its_spacing() {
        let points: Vec<[f32; 3]> = (0..30)
            .flat_map(|i| (0..20).map(move |j| [0.01 * i as f32, 0.01 * j as f32, 0.0]))
            .collect();
        let d = median_nearest_distance(&points).unwrap();
        assert!((d - 0.01).abs() < 1e-6, "{d}");
        assert_eq!(median_nearest_distance(&[[0.0; 3]]), None);
        assert_eq!(median_nearest_distance(&[[0.0; 3], [0.0; 3]]), None);
    }
}
