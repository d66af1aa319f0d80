//! One test body per stage of the `Backend` trait, run on every backend available: the rayon
//! CPU backend always; with `--features cuda` the CUDA backend on the host shim (`Shim`: the
//! kernels of `kernels/`, their launch shapes and `backend/cuda`'s own sequencing, on the CPU,
//! so CI checks them without a GPU) and on a GPU where there is one (`SPH_REQUIRE_GPU=1` makes
//! a missing GPU a failure instead of a line on stderr).
//!
//! Each body checks its stage against a brute-force reference written here from the pure
//! functions of `sph::physics` and `sph::boundary`, over all pairs (no grid, no backend), so
//! the reference shares the formulas with the code under test and nothing else. Tolerances
//! (`setup`): a backend sums the same f32 pair terms in another order than the reference, so a
//! neighbour sum is compared against the sum of its terms' magnitudes ([`setup::SUM_ORDER`]);
//! arithmetic without sums is compared to f32 rounding or bitwise, as each module says.

#[path = "../common/mod.rs"]
mod common;

mod setup;

mod anderson_reference;
pub mod boundary;
mod correction;
mod correction_reference;
mod damping_zone;
mod density;
mod density_rate;
mod forces;
mod gradient_moment;
mod integrate;
mod open_boundary;
mod rigid_motion;
mod solid_forces;
mod sort_by_cell;
mod state_extremes;
mod surface_tension;
mod velocity_solve;
mod warm_start;
mod wrap_positions;
