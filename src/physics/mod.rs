//! The physical terms of the model, one file per term, as pure per-pair or per-particle math.
//!
//! Nothing here loops over particles or knows about backends; the backends call these functions
//! inside their loops. Equations: (6), (15)–(19) of the paper ([P], PAPER.md section 1), the
//! rotating frame's Coriolis and centrifugal forces ([B67] §3.2), surface tension by cohesion
//! and curvature ([AAT13] Akinci, Akinci & Teschner 2013), and the multiphase number-density
//! form ([HA06], `multiphase`).

pub mod artificial_viscosity;
pub mod correction;
pub mod damping_zone;
pub mod density;
pub mod density_diffusion;
pub mod eos;
pub mod gradient_moment;
pub mod gravity;
pub mod jonswap;
pub mod lattice;
pub mod multiphase;
pub mod pair;
pub mod pcg;
pub mod pressure;
pub mod rotating_frame;
pub mod sea_state;
pub mod surface_stress;
pub mod surface_tension;
pub mod viscosity;
pub mod waves;
