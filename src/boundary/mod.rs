//! Solid boundaries: walls and obstacles made of fixed solid particles, and the force the fluid
//! exerts on each named solid (the quantity of the paper's Fig. 4).
//!
//! Solid particles lie on the same lattice as the fluid, in layers at least `h` thick (so a fluid
//! particle next to a wall has a full kernel support). They take part in the density sum (18)
//! of fluid particles and in the pressure (16) and viscous (17) forces, so fluid cannot pass.
//! Their pressure follows the fluid by the extrapolation of Adami, Hu & Adams (2012), see
//! [`wall_pressure`]; their velocity is zero (no-slip, fixed walls).
//!
//! References: [A12] S. Adami, X. Y. Hu, N. A. Adams, "A generalized wall boundary condition for
//! smoothed particle hydrodynamics", J. Comput. Phys. 231, 7057–7075 (2012), eq. (27).

pub mod solid_force;
pub mod wall_pressure;
