//! The numerical building blocks on synthetic input, mostly property tests: the smoothing
//! kernels' laws (`laws`), the neighbour grid against brute force (`grid`), and the position
//! correction of eqs. (23)–(24) on random fluid blocks (`correction`).

#[path = "../common/mod.rs"]
mod common;

mod correction;
mod grid;
mod laws;
mod periodic_grid;
