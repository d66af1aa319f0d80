//! What a run writes and how it is drawn: the VTK frames, series, force log and summary
//! (`formats`), the one CSV reader and the files read back through it, the frames and surfaces
//! read by an independent reader (`vtkio`), the free-surface reconstruction and `sph surface`,
//! the PNG figure writer, and the pictures of runs (`sph render`, `sph plot`, the golden frames
//! of `tests/golden/`).

#[path = "../common/mod.rs"]
mod common;

mod csv;
mod formats;
mod pictures;
mod pieces;
mod plot;
mod readers;
mod surface;
mod waves;
