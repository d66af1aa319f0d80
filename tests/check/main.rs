//! What a scene asks of a run, known before it runs: `sph check`'s refusals of input that cannot
//! run (`guards`), `sph plan` (`plan`), the fields a scene's plan allocates (`field_allocation`)
//! and `sph check`'s memory estimate against the peak a run reaches (`memory_estimate`).

#[path = "../common/mod.rs"]
mod common;

mod field_allocation;
mod guards;
mod memory_estimate;
mod plan;
