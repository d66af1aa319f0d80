//! Launchers of the force, integration and correction kernels (`kernels/shim/exports_dynamics.inc`).
#![allow(missing_docs)]
