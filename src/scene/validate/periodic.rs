//! `[periodic]`: the periodic axes (`crate::periodic`), each one named once and within the
//! dimension, with a domain extent that holds at least 3 grid cells of size `h` (the wrapped
//! neighbour cells must be distinct; the grids stretch the cell to divide the period, so the
//! extent need not be a whole number of cells) and a whole number of particle spacings (so a
//! lattice that fills the period tiles across the face, with no gap or overlap at the seam).

use super::*;
use crate::periodic::PeriodicAxes;
use crate::scene::schema::PeriodicFile;

/// Relative slack of the whole-number test `L/dx`: far above the rounding of decimal inputs
/// (`0.6/0.005` is 119.99999999999999), far below a real fraction of a spacing.
const WHOLE_SPACINGS_SLACK: f64 = 1e-6;

/// The validated axes; `None` after reporting a problem.
pub(super) fn check_periodic(
    c: &mut Checker,
    file: &PeriodicFile,
    dim: Option<usize>,
    domain: Option<&Aabb>,
    spacing: Option<f64>,
    h: Option<f64>,
) -> Option<PeriodicAxes> {
    let path = KeyPath::key("periodic").k("axes");
    if file.axes.is_empty() {
        c.err(
            path,
            "lists no axis; name at least one (\"x\", \"y\" or \"z\") or drop [periodic]".into(),
        );
        return None;
    }
    let mut axes = PeriodicAxes::NONE;
    let mut ok = true;
    for (i, a) in file.axes.iter().enumerate() {
        let k = a.index();
        if dim.is_some_and(|d| k >= d) {
            c.err(
                path.i(i),
                format!("axis {} does not exist in {}D", axis_name(k), dim.unwrap_or(0)),
            );
            ok = false;
        } else if axes.contains(k) {
            c.err(path.i(i), format!("axis {} is listed twice", axis_name(k)));
            ok = false;
        }
        axes = axes.with(k);
    }
    let (Some(domain), Some(dx), Some(h)) = (domain, spacing, h) else {
        return None;
    };
    for (i, a) in file.axes.iter().enumerate() {
        let k = a.index();
        let (Some(lo), Some(hi)) = (domain.min.get(k), domain.max.get(k)) else {
            continue;
        };
        let length = hi - lo;
        if length < 3.0 * h * (1.0 - crate::periodic::CELL_SLACK) {
            c.err(
                path.i(i),
                format!(
                    "the domain's extent along {} is {} m, less than 3 smoothing lengths (3 h = {} m): the neighbour search needs 3 cells per period",
                    axis_name(k),
                    num(length),
                    num(3.0 * h)
                ),
            );
            ok = false;
        }
        let spacings = length / dx;
        if (spacings - spacings.round()).abs() > WHOLE_SPACINGS_SLACK * spacings.max(1.0) {
            c.err(
                path.i(i),
                format!(
                    "the domain's extent along {} is {} m = {:.4} particle spacings, not a whole number: a lattice filling the period would leave a gap or overlap at the periodic face",
                    axis_name(k),
                    num(length),
                    spacings
                ),
            );
            ok = false;
        }
    }
    ok.then_some(axes)
}
