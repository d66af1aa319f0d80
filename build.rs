//! Build script: nothing to embed yet (the CUDA kernels arrive with the CUDA backend issue).
fn main() {
    println!("cargo::rerun-if-changed=build.rs");
}
