//! The CUDA backend as one rank's share of a split run (`--features cuda,mpi`: one GPU per
//! rank): each rank's particles on its device, staged through the host at every halo rebuild
//! and ghost refresh, its reductions skipping ghosts on the device. Run on the host shim (the
//! CUDA kernels and the backend's sequencing on the CPU, so in CI without a GPU) and on a GPU
//! where there is one; ranks are threads (`LocalWorld`). Every ghost refresh is checked
//! (`verify_halo`): after it, every field of every ghost equals its owner's, the step-start
//! copies the device keeps included.

#![cfg(feature = "cuda")]

use crate::split_run::{On, Split, run_on};
use sph::distributed::{Method, Rebalance};

/// The devices the CUDA backend runs on here: the shim, and the GPU where one answers.
fn devices() -> Vec<On> {
    let mut on = vec![On::Shim];
    if sph::backend::cuda::probe().is_ok() {
        on.push(On::Gpu);
    } else {
        eprintln!("SKIPPED the GPU half: {:?}", sph::backend::cuda::probe());
    }
    on
}

/// The shipped 2D dam break at a/25 with `solver` to `end` [s] on `on`, whole or split.
fn dam_break(solver: &str, split: Option<Split>, end: f64, on: On) -> Vec<crate::split_run::Outcome> {
    let sets = [
        format!("solver.kind={solver}"),
        "particles.spacing=0.01".to_string(),
    ];
    run_on::<2>("scenes/dam_break_2d.toml", &sets, split, end, on)
}

/// The dam break on the CUDA backend split across 2 ranks (slabs) and 4 (bisection, with
/// rebalancing) against the same backend unsplit, to t = 0.1 s: the same steps, fluid
/// particles and mass, every particle owned once, the front within a tenth of the spacing
/// (1 mm) and the impulse on the tank within 1 %, as the CPU's split runs are held
/// (`split_run::two_and_four_ranks_agree_with_one`); with `corrected` every stage of every rank
/// ends below `δ`. A ghost counted by a reduction (the time step's extremes, the residual, the
/// sweep's scale, the velocity solve's products, the forces on solids) would count a particle
/// twice; a field missing from a refresh stops the step (`verify_halo`).
#[test]
fn the_cuda_backend_split_across_ranks_agrees_with_it_whole() {
    for on in devices() {
        for solver in ["wcsph", "corrected"] {
            let one = dam_break(solver, None, 0.1, on).remove(0);
            let splits = [
                (2, Method::Slabs, Rebalance::Never),
                (4, Method::Bisection, Rebalance::Above(0.1)),
            ];
            for (ranks, method, rebalance) in splits {
                let split = Split {
                    ranks,
                    method,
                    rebalance,
                };
                let runs = dam_break(solver, Some(split), 0.1, on);
                agrees(&format!("{on:?} {solver} on {ranks}"), &runs, &one);
                let r = &runs[0];
                assert!(
                    (r.front - one.front).abs() < 1e-3,
                    "{on:?} {solver}: front {} against {}",
                    r.front,
                    one.front
                );
                assert_eq!(r.unconverged, 0);
                if solver == "corrected" {
                    assert!(r.residual_after < 1e-4, "residual {}", r.residual_after);
                }
            }
        }
    }
}

/// Checks a split run's outcome against the whole run's on the same device: the same steps,
/// particles, mass and open-boundary counts, every particle owned once (none lost but those the
/// outflow removed), and the impulse on the
/// first solid within 1 % of its largest component.
fn agrees(label: &str, split: &[crate::split_run::Outcome], whole: &crate::split_run::Outcome) {
    for r in split {
        assert_eq!(
            r, &split[0],
            "{label}: every rank ends with the same global figures"
        );
    }
    let r = &split[0];
    eprintln!("{label}: {r:?}\n  whole: {whole:?}");
    assert_eq!(
        (r.steps, r.fluid, r.mass, r.created, r.outflow),
        (whole.steps, whole.fluid, whole.mass, whole.created, whole.outflow),
        "{label}"
    );
    // Missing: the scene's particles the outflow removed, as in the whole run.
    assert_eq!((r.duplicated, r.missing), (0.0, whole.missing), "{label}");
    let scale = whole.impulse[0].abs().max(whole.impulse[1].abs());
    for k in 0..2 {
        let (a, b) = (r.impulse[k], whole.impulse[k]);
        assert!(
            (a - b).abs() <= 0.01 * scale,
            "{label}: impulse[{k}] {a} against {b}"
        );
    }
}

/// The boundaries that change a device rank's particles from the host and the 3D kernels, on
/// the CUDA backend split across ranks against it whole: the open channel
/// (`scenes/open_channel_2d.toml`, particles created and removed on the host and the device
/// reloaded) on 2 ranks to 0.8 s, the periodic collapse (`tests/scenes/periodic_collapse_2d.toml`,
/// ghosts across the periodic face) on 4 to 0.1 s, and the 3D dam break against a column at
/// 4 times its spacing on 2 to 0.05 s.
#[test]
fn open_periodic_and_3d_runs_on_split_cuda_ranks_agree_with_whole() {
    let slabs = |ranks| Split {
        ranks,
        method: Method::Slabs,
        rebalance: Rebalance::Never,
    };
    let column = [
        "particles.spacing=0.0432".to_string(),
        "domain.min=[-0.1,-0.1,-0.1]".to_string(),
        "domain.max=[1.7,0.75,0.9]".to_string(),
    ];
    let open = ["domain.max=[0.65,1.0]".to_string()];
    for on in devices() {
        let (scene, sets) = ("scenes/open_channel_2d.toml", &open[..]);
        let whole = run_on::<2>(scene, sets, None, 0.8, on).remove(0);
        assert!(whole.created > 0 && whole.outflow > 0, "{whole:?}");
        agrees(
            &format!("{on:?} open channel on 2"),
            &run_on::<2>(scene, sets, Some(slabs(2)), 0.8, on),
            &whole,
        );
        let scene = "tests/scenes/periodic_collapse_2d.toml";
        let whole = run_on::<2>(scene, &[], None, 0.1, on).remove(0);
        let four = Split {
            ranks: 4,
            method: Method::Bisection,
            rebalance: Rebalance::Never,
        };
        agrees(
            &format!("{on:?} periodic collapse on 4"),
            &run_on::<2>(scene, &[], Some(four), 0.1, on),
            &whole,
        );
        let scene = "scenes/dam_break_column_3d.toml";
        let whole = run_on::<3>(scene, &column, None, 0.05, on).remove(0);
        agrees(
            &format!("{on:?} 3D column on 2"),
            &run_on::<3>(scene, &column, Some(slabs(2)), 0.05, on),
            &whole,
        );
    }
}
