//! Build script.
//!
//! - Embeds every CUDA kernel of `kernels/*.cu` in the binary, with the local `#include "x.cuh"`
//!   lines inlined, as `KERNEL_SOURCES` in `$OUT_DIR/kernels.rs` (`backend::cuda::sources`): the
//!   CUDA backend compiles them at run time with NVRTC, so no file of the source tree is needed.
//! - With `--features cuda`, compiles the same kernels as C++ with the host shim of
//!   `kernels/shim/` (once per dimension) into a static library, so the CUDA backend runs on the
//!   CPU (`backend::cuda::shim`, `tests/stages`, `tests/cuda_parity.rs`, `tests/cuda_shim.rs`).
//! - Generates from `kernels/launch.table` the CUDA backend's launchers (cudarc and host shim,
//!   `$OUT_DIR/launch.rs`) and the shim's C++ launchers (`$OUT_DIR/shim_exports.inc`):
//!   `build/kernel_table.rs`.
//! - Generates from `kernels/pair_terms.table` the force stage's optional pair terms: their Rust
//!   vocabulary (`$OUT_DIR/pair_terms.rs`, `model::pair_terms`) and CUDA mirror
//!   (`$OUT_DIR/pair_coefficients.cuh`, `$OUT_DIR/pair_terms_sum.cuh`): `build/pair_terms.rs`.
use std::fs;
use std::path::{Path, PathBuf};

#[path = "build/kernel_table.rs"]
mod kernel_table;
#[path = "build/pair_terms.rs"]
mod pair_terms;

/// `source` with every `#include "name"` of a file beside it or generated into `$OUT_DIR`
/// (`dirs`, searched in order) replaced by that file's text (recursively, each header once, as
/// `#pragma once` would).
fn inline_includes(dirs: &[&Path], source: &str, seen: &mut Vec<String>) -> String {
    let mut out = String::new();
    for line in source.lines() {
        let trimmed = line.trim();
        if let Some(rest) = trimmed.strip_prefix("#include \"") {
            let name = rest.trim_end_matches('"').to_string();
            if !seen.contains(&name) {
                let path = dirs
                    .iter()
                    .map(|d| d.join(&name))
                    .find(|p| p.exists())
                    .unwrap_or_else(|| panic!("kernels: no header {name}"));
                let text = fs::read_to_string(&path)
                    .unwrap_or_else(|e| panic!("kernels: cannot read {}: {e}", path.display()));
                seen.push(name);
                out.push_str(&inline_includes(dirs, &text, seen));
            }
            continue;
        }
        if trimmed == "#pragma once" {
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let kernels = manifest.join("kernels");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=kernels");
    println!("cargo::rerun-if-changed=build");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it"));
    let terms = pair_terms::parse(
        &fs::read_to_string(kernels.join("pair_terms.table")).expect("kernels/pair_terms.table"),
    );
    fs::write(out.join("pair_terms.rs"), pair_terms::rust(&terms)).expect("writable OUT_DIR");
    let (coefficients, sum) = pair_terms::cuda(&terms);
    fs::write(out.join("pair_coefficients.cuh"), coefficients).expect("writable OUT_DIR");
    fs::write(out.join("pair_terms_sum.cuh"), sum).expect("writable OUT_DIR");
    let table = fs::read_to_string(kernels.join("launch.table")).expect("kernels/launch.table");
    let entries = kernel_table::parse(&table, terms.len());
    for (name, text) in kernel_table::entries(&entries) {
        fs::write(out.join(name), text).expect("writable OUT_DIR");
    }
    let mut names: Vec<PathBuf> = fs::read_dir(&kernels)
        .expect("kernels/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "cu"))
        .collect();
    names.sort();
    let mut generated = String::from(
        "/// Every kernel file of `kernels/`: (file stem, source with its headers inlined).\n\
         pub const KERNEL_SOURCES: &[(&str, &str)] = &[\n",
    );
    for path in &names {
        println!("cargo::rerun-if-changed={}", path.display());
        let text = fs::read_to_string(path).expect("readable kernel");
        let source = inline_includes(&[&kernels, &out], &text, &mut Vec::new());
        let stem = path.file_stem().expect("file name").to_string_lossy();
        generated.push_str(&format!("    ({stem:?}, {source:?}),\n"));
    }
    generated.push_str("];\n");
    fs::write(out.join("kernels.rs"), generated).expect("writable OUT_DIR");

    let (launch, externs) = kernel_table::rust(&entries);
    fs::write(out.join("launch.rs"), launch).expect("writable OUT_DIR");
    fs::write(out.join("shim_externs.rs"), externs).expect("writable OUT_DIR");
    let mut exports = String::new();
    for path in &names {
        exports.push_str(&format!("#include {:?}\n", path.display().to_string()));
    }
    exports.push_str(&kernel_table::cpp(&entries));
    fs::write(out.join("shim_exports.inc"), exports).expect("writable OUT_DIR");

    #[cfg(feature = "cuda")]
    compile_shim(&kernels, &out);
}

/// The kernels as C++ for the CPU, one static library per dimension.
#[cfg(feature = "cuda")]
fn compile_shim(kernels: &Path, out: &Path) {
    for dim in ["2", "3"] {
        cc::Build::new()
            .cpp(true)
            .file(kernels.join("shim/shim.cpp"))
            .include(out)
            .define("SPH_DIM", dim)
            .flag_if_supported("-std=c++17")
            .flag_if_supported("-Wno-unused-function")
            .flag_if_supported("-Wno-unused-parameter")
            .opt_level(2)
            .compile(&format!("sph_kernel_shim_{dim}"));
    }
}
