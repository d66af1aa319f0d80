//! ParaView `.pvd` collections listing the frames of a run with their times.

use std::io::Write;
use std::path::Path;

use super::xml::{self, TagKind};
use super::{OutputError, fmt_f64, write_atomically};

/// A time series of output frames, written as a ParaView `.pvd` collection.
///
/// File names are stored as given (normally relative to the directory of
/// the `.pvd` file, which is how ParaView resolves them).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PvdSeries {
    entries: Vec<(f64, String)>,
}

impl PvdSeries {
    /// An empty series.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends a frame at simulated time `time` (seconds) stored in `file`.
    pub fn push(&mut self, time: f64, file: impl Into<String>) {
        self.entries.push((time, file.into()));
    }

    /// The recorded `(time, file)` pairs in the order they were pushed.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// `true` if no frame has been recorded.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Drops every frame whose time is greater than `time` (for restarts).
    pub fn truncate_after(&mut self, time: f64) {
        self.entries.retain(|(t, _)| *t <= time);
    }

    /// Writes the collection to `path` atomically (temporary file +
    /// rename), so the file on disk is always a complete, valid series.
    pub fn write(&self, path: &Path) -> Result<(), OutputError> {
        write_atomically(path, |w| {
            w.write_all(b"<?xml version=\"1.0\"?>\n")?;
            w.write_all(
                b"<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
            )?;
            for (t, file) in &self.entries {
                writeln!(
                    w,
                    "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>",
                    fmt_f64(*t),
                    xml::escape(file)
                )?;
            }
            w.write_all(b"  </Collection>\n</VTKFile>\n")
        })
    }

    /// Reads a `.pvd` collection (as written by [`write`](Self::write)).
    pub fn read(path: &Path) -> Result<Self, OutputError> {
        let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
        let tags = xml::scan(&text).map_err(|e| OutputError::malformed(path, e))?;
        let mut series = PvdSeries::new();
        let mut saw_collection = false;
        for tag in &tags {
            match (tag.name.as_str(), tag.kind) {
                ("VTKFile", TagKind::Start) => {
                    if tag.attr("type") != Some("Collection") {
                        return Err(OutputError::malformed(path, "VTKFile type is not Collection"));
                    }
                    saw_collection = true;
                }
                ("DataSet", TagKind::Start | TagKind::Empty) => {
                    let t = tag
                        .attr("timestep")
                        .unwrap_or("0")
                        .trim()
                        .parse::<f64>()
                        .map_err(|_| OutputError::malformed(path, "bad DataSet timestep"))?;
                    let file = tag
                        .attr("file")
                        .ok_or_else(|| OutputError::malformed(path, "DataSet without file"))?;
                    series.push(t, file);
                }
                _ => {}
            }
        }
        if !saw_collection {
            return Err(OutputError::malformed(path, "no <VTKFile type=\"Collection\">"));
        }
        Ok(series)
    }
}
