//! The kernel sources of `kernels/`, embedded at build time (`build.rs`) with their headers
//! inlined, so the binary compiles them with NVRTC without the source tree.

include!(concat!(env!("OUT_DIR"), "/kernels.rs"));

/// The source of kernel file `stem` (e.g. `"density"`), if there is one.
pub fn source(stem: &str) -> Option<&'static str> {
    KERNEL_SOURCES
        .iter()
        .find(|(s, _)| *s == stem)
        .map(|(_, src)| *src)
}
