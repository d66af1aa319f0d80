//! Measurements and their comparison with references: the reference-data readers and curve
//! comparison of `validation` on files the tests write (`readers`; the shipped digitisations
//! are read by the validation suite, `tests/validation_data.rs`), and the probes measured on
//! hand-made states (`probe`).

#[path = "../common/mod.rs"]
mod common;

mod probe;
mod readers;
