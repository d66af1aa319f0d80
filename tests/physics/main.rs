//! The solver against exact physics: hydrostatics, conservation of mass and momentum, free fall
//! and thread-count independence (`basics`); plane Poiseuille start-up and the wall drag of the
//! viscosity (`poiseuille`); and the effects, each against its exact solution: the rotating
//! tank's parabola (`rotating_frame`), Laplace's pressure jump and round drops
//! (`surface_tension`), two fluid phases' piecewise hydrostatics and buoyancy (`multiphase`).

#[path = "../common/mod.rs"]
mod common;

mod basics;
mod dam_break_pressure;
mod density_diffusion;
mod floating;
mod floating_3d;
mod focused;
mod gauges;
mod multiphase;
mod open_channel;
mod poiseuille;
mod poiseuille_periodic;
mod rotating_frame;
mod surface_tension;
mod waves;
