//! Measurements and their comparison with references: the reference-data readers and curve
//! comparison of `validation` on files the tests write (`readers`; the shipped digitisations
//! are read by the validation suite, `tests/validation_data.rs`), and the probes measured on
//! hand-made states (`probe`); pressure, level and velocity against records, sampling windows
//! and sensor faces (`signal`).

#[path = "../common/mod.rs"]
mod common;

mod moment;
mod probe;
mod readers;
mod signal;
