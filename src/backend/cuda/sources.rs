//! The kernel sources of `kernels/`, embedded at build time (`build.rs`) with their headers
//! inlined, so the binary compiles them with NVRTC without the source tree.

include!(concat!(env!("OUT_DIR"), "/kernels.rs"));
