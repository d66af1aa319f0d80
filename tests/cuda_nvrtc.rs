//! Every kernel of `kernels/` compiles with NVRTC through the same cudarc path the CUDA backend
//! uses (`backend::cuda::compile::compile_all`), and every entry of `kernels/launch.table` is
//! among the compiled entry points, for both dimensions and the oldest and newest
//! architectures the backend names (sm_75: CUDA 13 dropped sm_70). Needs `libnvrtc` but no GPU. Where the library is missing
//! the test says SKIPPED on stderr, unless `SPH_REQUIRE_NVRTC=1` (CI sets it), which makes a
//! missing library a failure.
#![cfg(feature = "cuda")]

use sph::backend::cuda::compile::compile_all;
use sph::backend::cuda::launch::KERNEL_NAMES;
use sph::backend::cuda::library::check_nvrtc;
use sph::backend::cuda::sources::KERNEL_SOURCES;

#[test]
fn every_kernel_compiles_with_nvrtc() {
    if let Err(e) = check_nvrtc() {
        let required = std::env::var("SPH_REQUIRE_NVRTC").is_ok_and(|v| v == "1");
        assert!(!required, "SPH_REQUIRE_NVRTC=1 but {e}");
        eprintln!("SKIPPED every_kernel_compiles_with_nvrtc: {e}");
        return;
    }
    assert!(KERNEL_SOURCES.len() >= 2, "kernels/ is embedded");
    for dim in [2, 3] {
        for arch in ["sm_75", "sm_90"] {
            let modules = compile_all(dim, arch).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(modules.len(), KERNEL_SOURCES.len());
            let mut entries = Vec::new();
            for (file, ptx) in &modules {
                let text = ptx.to_src();
                assert!(
                    text.contains(".entry"),
                    "kernels/{file}.cu for {arch}, D = {dim} has no kernel entry point"
                );
                // `.entry name(` for each `extern "C" __global__` kernel.
                entries.extend(
                    text.split(".entry ")
                        .skip(1)
                        .filter_map(|rest| rest.split('(').next().map(|n| n.trim().to_string())),
                );
            }
            // Every entry of kernels/launch.table is a kernel the GPU can load by name.
            for name in KERNEL_NAMES {
                assert!(
                    entries.iter().any(|e| e == name),
                    "kernels/launch.table names `{name}`, which no kernel file defines ({arch}, D = {dim})"
                );
            }
        }
    }
}

#[test]
fn a_kernel_error_names_the_file() {
    if check_nvrtc().is_err() {
        eprintln!("SKIPPED a_kernel_error_names_the_file: no NVRTC");
        return;
    }
    // D = 4 trips the `#error` of kernels/sph.cuh in every file.
    let Err(e) = compile_all(4, "sm_75") else {
        panic!("sph.cuh accepts only D = 2 or 3, but D = 4 compiled");
    };
    assert!(e.to_string().contains("kernels/"), "{e}");
    assert!(e.log.contains("SPH_DIM"), "the log names the cause: {}", e.log);
}
