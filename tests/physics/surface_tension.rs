//! The `surface_tension` effect, both models, with their constants calibrated so that
//! the scene's `σ` is the model's surface tension on a flat face of the lattice:
//!
//! - `surface_stress` (the default, `physics::surface_stress`): the capillary stress
//!   `σ' |∇c| (I − N̂N̂ᵀ)` of the surface layers as a pair force, with Monaghan's artificial
//!   stress;
//! - `akinci` (`physics::surface_tension`): [AAT13] Akinci, Akinci & Teschner 2013 cohesion and
//!   curvature forces between all fluid particles within `h`.
//!
//! `scenes/droplet_2d.toml`: a 2 cm square of water in zero gravity, no walls, viscosity
//! μ = 1 Pa s (overdamped capillary relaxation, time μR/σ ≈ 0.16 s), σ = 0.072 N/m.
//!
//! Pressures. Outside a free droplet the pressure is zero. Inside, Laplace's law fixes the jump
//! of the *mechanical* pressure (the normal stress, Batchelor 1967 §1.4): in 2D `σ/R`. The test
//! measures the mechanical pressure of the droplet's core as the Irving–Kirkwood virial of every
//! pair force (pressure (16) and the model's), and reports the EOS pressure beside it. With the
//! surface stress the two agree: the bulk carries no capillary stress (`|∇c|` is below the
//! model's surface ramp there). With [AAT13] they do not: the cohesion is a pair attraction
//! between all particles within `h`, so the bulk carries a negative virial pressure of its own
//! (the van der Waals "internal pressure"), balanced by a positive EOS pressure `P0` that a flat
//! slab has too (`P0 ≈ 5 σ/h`, 30 times `σ/R` here).

use crate::common::tolerance::{CLOCK_SLACK, F64_SUM, LAPLACE_JUMP, PAIRWISE_MOMENTUM};
use sph::fields::{FLUID, Fields};
use sph::math::{Real, Vector};
use sph::physics::eos;
use sph::physics::pressure::pressure_acceleration;
use sph::physics::surface_stress::{surface_stress_acceleration, tensile_factor};
use sph::physics::surface_tension::{normal_term, surface_tension_acceleration};
use sph::run::simulation_from_scene;
use sph::scene::load_scene;
use sph::smoothing::{Smoothing, pair_offset};
use sph::solver::Simulation;
use sph::solver::stage::Stage;
use std::path::Path;

/// What one droplet run measured.
#[derive(Debug)]
struct Droplet {
    /// Laplace pressure `σ/R` [Pa] with `R = sqrt(A0/π)`, `A0` the initial area.
    laplace: f64,
    /// Time-averaged mechanical (virial) pressure of the particles within `R/2` of the centre.
    mechanical: f64,
    /// Time-averaged EOS pressure of the same particles.
    eos: f64,
    /// Time-averaged density (18) of the same particles over ρ0.
    core_density: f64,
    /// `(max − min)/mean` of the outermost radius over 24 angular sectors, at the start and end.
    spread_start: f64,
    spread_end: f64,
    /// Area at the end over the area at the start, both as the convex hull of the particles
    /// grown by `dx/2` ([`grown_hull_area`]).
    area_ratio: f64,
    /// Largest |total momentum| over the run, over `M · sqrt(σ/(ρ0 R))` (the capillary speed).
    momentum: f64,
}

/// Centre of mass of the fluid.
fn centre<const D: usize>(f: &Fields<D>) -> Vector<D> {
    let mut c = Vector::<D>::zeros();
    for x in &f.position {
        c += x;
    }
    c / f.len() as Real
}

/// `(max − min)/mean` of the outermost particle radius in each of 24 angular sectors (2D).
fn radius_spread(f: &Fields<2>) -> f64 {
    let c = centre(f);
    let sectors = 24;
    let mut outer = vec![0.0f64; sectors];
    for x in &f.position {
        let d = x - c;
        let theta = f64::from(d.y).atan2(f64::from(d.x)) + std::f64::consts::PI;
        let s = ((theta / (2.0 * std::f64::consts::PI) * sectors as f64) as usize).min(sectors - 1);
        outer[s] = outer[s].max(f64::from(d.norm()));
    }
    let mean = outer.iter().sum::<f64>() / sectors as f64;
    let (lo, hi) = outer
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    (hi - lo) / mean
}

/// Area [m²] of the convex hull of the particles grown by `dx/2` (Steiner: `A + P dx/2 +
/// π dx²/4`): the area of a convex body of fluid, each particle standing for its `dx` cell
/// (for the initial square of side `L`, `L² − (1 − π/4) dx²`).
fn grown_hull_area(f: &Fields<2>, dx: f64) -> f64 {
    let mut p: Vec<(f64, f64)> = f
        .position
        .iter()
        .map(|x| (f64::from(x.x), f64::from(x.y)))
        .collect();
    p.sort_by(|a, b| a.partial_cmp(b).expect("finite positions"));
    let cross =
        |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    // Andrew's monotone chain.
    let mut hull: Vec<(f64, f64)> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let points: Vec<(f64, f64)> = if pass == 0 {
            p.clone()
        } else {
            p.iter().rev().copied().collect()
        };
        for q in points {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    let (mut area, mut perimeter) = (0.0, 0.0);
    for k in 0..hull.len() {
        let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
        area += 0.5 * (a.0 * b.1 - b.0 * a.1);
        perimeter += ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    }
    area + 0.5 * perimeter * dx + 0.25 * std::f64::consts::PI * dx * dx
}

/// The mechanical pressure [Pa] and the mean EOS pressure of the fluid particles within
/// `radius` of the centre, recomputed from the positions alone (brute force): density (18),
/// pressure (19), normals [AAT13] (3) (with rest volumes for the surface stress), then the virial
/// `P = (1/(2 D V)) Σ_{i∈core} Σ_j m_i x_ij · a_ij` over the pressure (16) and the run's
/// surface-tension pair accelerations `a_ij`, with `V = Σ_{i∈core} m_i/ρ_i`. Viscous forces are
/// left out (the drop is at rest).
fn core_pressure(sim: &Simulation<2>, radius: f64) -> (f64, f64, f64) {
    let f = &sim.fields;
    let p = sim.step_params();
    let kernel = Smoothing::<2>::new(p.h).expect("2D");
    let n = f.len();
    let neighbours = |i: usize, mut visit: Box<dyn FnMut(usize, Vector<2>, Real) + '_>| {
        for j in 0..n {
            let d = f.position[i] - f.position[j];
            let r2 = d.norm_squared();
            if r2 < p.h * p.h {
                let (d, r2) = pair_offset(d, r2, f.id[i], f.id[j], p.h);
                visit(j, d, r2);
            }
        }
    };
    let mut rho = vec![0.0 as Real; n];
    for (i, r) in rho.iter_mut().enumerate() {
        neighbours(i, Box::new(|j, _, r2| *r += f.mass[j] * kernel.w(r2)));
    }
    let pressure: Vec<Real> = rho.iter().map(|&r| eos::pressure(r, p.rho0, p.c2)).collect();
    let stress = p.surface_tension_model == sph::backend::SurfaceTensionModel::SurfaceStress;
    let mut normal = vec![Vector::<2>::zeros(); n];
    for (i, nrm) in normal.iter_mut().enumerate() {
        neighbours(
            i,
            Box::new(|j, d, _| {
                let volume_density = if stress { p.rho0 } else { rho[j] };
                *nrm += normal_term(&kernel, f.mass[j], volume_density, &d)
            }),
        );
        *nrm *= p.h;
    }
    let w_dx = kernel.w(p.spacing * p.spacing);
    let c = centre(f);
    let (mut virial, mut volume, mut eos_sum, mut count) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    let mut rho_sum = 0.0f64;
    for i in 0..n {
        if f.kind[i] != FLUID || f64::from((f.position[i] - c).norm()) > radius {
            continue;
        }
        volume += f64::from(f.mass[i] / rho[i]);
        eos_sum += f64::from(pressure[i]);
        rho_sum += f64::from(rho[i] / p.rho0);
        count += 1;
        neighbours(
            i,
            Box::new(|j, d, r2| {
                if j == i {
                    return;
                }
                let r = r2.sqrt();
                let grad = kernel.grad_w_spiky(&d, r) * p.pressure_gradient_scale;
                let capillary = if stress {
                    surface_stress_acceleration(
                        p.surface_tension_sigma,
                        p.h,
                        f.mass[j],
                        p.rho0,
                        p.rho0,
                        &normal[i],
                        &normal[j],
                        &grad,
                        tensile_factor(kernel.w(r2), w_dx),
                    )
                } else {
                    surface_tension_acceleration(
                        p.surface_tension_gamma,
                        p.rho0,
                        p.h,
                        f.mass[j],
                        rho[i],
                        rho[j],
                        &normal[i],
                        &normal[j],
                        &d,
                        r,
                    )
                };
                let a = pressure_acceleration(pressure[i], rho[i], pressure[j], rho[j], f.mass[j], &grad)
                    + capillary;
                virial += f64::from(f.mass[i]) * f64::from(d.dot(&a));
            }),
        );
    }
    (
        virial / (2.0 * 2.0 * volume),
        eos_sum / count as f64,
        rho_sum / count as f64,
    )
}

/// Runs `scenes/droplet_2d.toml` with `sets` to its end time; averages the core pressures over
/// frames every `frame` s in the last `average` s.
fn run_droplet(sets: &[&str], average: f64) -> Droplet {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let scene = load_scene(Path::new("scenes/droplet_2d.toml"), &sets).expect("shipped scene");
    let sigma = scene.surface_tension.expect("the effect is on");
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let initial_area: f64 = scene
        .fluid_boxes
        .iter()
        .map(|b| (b.region.max[0] - b.region.min[0]) * (b.region.max[1] - b.region.min[1]))
        .sum();
    let r = (initial_area / std::f64::consts::PI).sqrt();
    let mass = sim.fluid_mass();
    let capillary_speed = (sigma / (scene.rho0 * r)).sqrt();
    let spread_start = radius_spread(&sim.fields);
    let area_start = grown_hull_area(&sim.fields, scene.spacing);
    let end = scene.end_time;
    let frame = 0.01;
    let mut next = end - average;
    let (mut mechanical, mut eos_p, mut frames, mut momentum) = (0.0, 0.0, 0usize, 0.0f64);
    let mut core_density = 0.0;
    while sim.clock().time < end - F64_SUM {
        sim.step(end).expect("stable step");
        let m = sim.fluid_momentum();
        momentum = momentum.max((m[0] * m[0] + m[1] * m[1]).sqrt() / (mass * capillary_speed));
        if sim.clock().time + CLOCK_SLACK >= next {
            next += frame;
            let (pm, pe, rho) = core_pressure(&sim, 0.5 * r);
            mechanical += pm;
            eos_p += pe;
            core_density += rho;
            frames += 1;
        }
    }
    let f = &sim.fields;
    Droplet {
        laplace: sigma / r,
        mechanical: mechanical / frames as f64,
        eos: eos_p / frames as f64,
        core_density: core_density / frames as f64,
        spread_start,
        spread_end: radius_spread(f),
        area_ratio: grown_hull_area(f, scene.spacing) / area_start,
        momentum,
    }
}

/// The `--set` that selects [AAT13]'s model instead of the default surface stress.
const AKINCI: &str = "fluid.surface_tension_model=\"akinci\"";

/// The square relaxes to a circle. `scenes/droplet_2d.toml` (surface stress) to t = 1 s
/// (six times the relaxation time μR/σ): the outermost particle radius over 24 angular sectors
/// varies by `(max − min)/mean` = 0.32 on the square (corners at `√2` times the side's
/// half-width) and must fall below one spacing over the radius, `dx/R` = 0.089, the roughness of
/// a lattice disc. Measured 0.0047: the drop's outer layer is a smooth ring.
///
/// Area. The fluid's own measure, `M/ρ` of the core, stays within 1 % of the start (measured
/// +0.03 % density: the Laplace pressure σ/R = 6.4 Pa over `ρ0 C²` = 25 kPa). The drop's outline
/// (the particles' convex hull grown by dx/2, exact for the square) may differ by the
/// uncertainty of where a surface lies, ±dx/2 on the radius, so `dx/R` = 8.9 % of the area:
/// measured −2.6 %. The momentum stays at f32 round-off (every pair force is antisymmetric;
/// measured 1.9e-8 of `M sqrt(σ/(ρ0 R))`).
#[test]
fn square_droplet_relaxes_to_a_circle_of_the_same_area() {
    let d = run_droplet(&[], 0.1);
    eprintln!("{d:#?}");
    let r_over_dx = (4.0e-4 / std::f64::consts::PI).sqrt() / 0.001;
    assert!(d.spread_start > 0.3, "the start is a square: {}", d.spread_start);
    assert!(
        d.spread_end < 1.0 / r_over_dx,
        "radius spread {:.3} after relaxing (tolerance dx/R = {:.3})",
        d.spread_end,
        1.0 / r_over_dx
    );
    assert!(
        (d.core_density - 1.0).abs() < 0.01,
        "core density {:.4} rho0",
        d.core_density
    );
    assert!(
        (d.area_ratio - 1.0).abs() < 1.0 / r_over_dx,
        "outline area ratio {:.4} (tolerance dx/R)",
        d.area_ratio
    );
    assert!(
        d.momentum < PAIRWISE_MOMENTUM,
        "momentum {:.2e} of M u_capillary",
        d.momentum
    );
}

/// The Laplace jump. The mechanical pressure of the core (within R/2 of the centre,
/// averaged over t = 1.5–2 s) of the surface-stress drop against `σ/R` for σ = 0.072 and
/// 0.144 N/m, within 10 % each; and Laplace's dependence on σ: the second over the first is 2
/// within 10 %.
///
/// Measured (dx = 1 mm, h = 2 dx, R = 11.3 dx): 1.011 σ/R and 1.002 σ/R (EOS pressure 1.007 and
/// 0.992 σ/R), ratio 1.983. Robustness, the core's EOS pressure averaged over t = 0.5–1 s:
/// 1.028 σ/R at μ = 0.8 Pa s, 1.032 at 1.2, 1.029 at C = 10 m/s, 1.018 at σ = 0.144 N/m, and
/// 1.001 at t = 2 s. What it depends on: the artificial stress's `ε`
/// (`physics::surface_stress::ARTIFICIAL_STRESS`), 0.92 σ/R at ε = 0.25 and 0.79 σ/R at 0.3;
/// 0.2 is the smallest of these that keeps the surface layer from clumping (at 0.15 it clumps
/// and the core holds 0.5 σ/R).
#[test]
fn laplace_jump_is_sigma_over_r_within_10_percent_and_linear_in_sigma() {
    let mut core = Vec::new();
    for sigma in ["0.072", "0.144"] {
        let d = run_droplet(
            &[&format!("fluid.surface_tension={sigma}"), "solver.end_time=2.0"],
            0.5,
        );
        eprintln!("{d:#?}");
        let ratio = d.mechanical / d.laplace;
        assert!(
            (ratio - 1.0).abs() <= LAPLACE_JUMP,
            "sigma = {sigma} N/m: core pressure {:.3} Pa = {ratio:.3} sigma/R (tolerance 10 %; EOS pressure {:.3} Pa)",
            d.mechanical,
            d.eos
        );
        core.push(d.mechanical);
    }
    let ratio = core[1] / core[0];
    assert!(
        (ratio / 2.0 - 1.0).abs() <= LAPLACE_JUMP,
        "core pressure for 2 sigma over sigma: {ratio:.3} (tolerance 2 ± 10 %)"
    );
}

/// [AAT13]'s model on the same square. The outline's spread at t = 1 s against `dx/R` = 0.089.
///
/// Ignored: the outcome is not robust. Since the viscous force carries the lattice factor 1/λ
/// (`StepParams::viscosity_scale`) the spread at t = 1 s is 0.100 (μ = 1 Pa s), and it is
/// 0.100 at μ = 0.8, 0.082 at 0.9, 0.117 at 1.1, 0.086 at σ = 0.144 N/m, 0.082 at C = 10 m/s,
/// 0.103 at C = 20 m/s. The drop is round to about one spacing by t ≈ 0.3 s in every run, but it
/// does not settle: the particles keep creeping (rms speed 1e-4 to 1e-3 m/s, 0.1–1 % of the
/// capillary speed, for seconds) and the outermost particle of each sector comes and goes, so the
/// spread wanders between 0.06 and 0.12 (0.7–1.35 dx/R). The cohesion's bulk pressure
/// `P0 ≈ 5 σ/h` (170 Pa) does not depend on R while the capillary stress σ/R that drives the
/// relaxation is 1/27 of it at R = 11.3 dx, and the particle packing under `P0` resists
/// rearrangement like a solid; at R = 22.6 dx the drop jams at spread 0.17–0.19.
#[test]
#[ignore = "akinci model: measured spread 0.100 at t = 1 s (mu 0.8-1.1: 0.082-0.117; tolerance dx/R = 0.089): the drop's packing creeps and the one-dx outline wanders 0.06-0.12; see the doc comment"]
fn akinci_square_droplet_relaxes_to_a_circle() {
    let d = run_droplet(&[AKINCI], 0.1);
    eprintln!("{d:#?}");
    let r_over_dx = (4.0e-4 / std::f64::consts::PI).sqrt() / 0.001;
    assert!(
        d.spread_end < 1.0 / r_over_dx,
        "radius spread {:.3} after relaxing (tolerance dx/R = {:.3})",
        d.spread_end,
        1.0 / r_over_dx
    );
}

/// [AAT13]'s model: the Laplace jump within 10 % and linear in σ, as the test above.
///
/// Ignored: measured 0.58–1.02 σ/R for μ = 0.8–1.1 Pa s at 0.072 N/m and 1.26 σ/R at
/// 0.144 N/m (ratio 4.19 at μ = 1). The core's mechanical pressure is
/// the small difference of two bulk terms 27 times σ/R (the EOS pressure `P0` and the
/// cohesion's virial), so a 1 % change in the local stress of the jammed packing moves it by
/// 0.3 σ/R: the packing the drop jams in, not σ, sets it. This is why the surface stress is the
/// default.
#[test]
#[ignore = "akinci model: measured 0.58-1.26 sigma/R, ratio 4.19 for 2 sigma: the jammed packing's stress, not sigma, sets the core pressure; see the doc comment"]
fn akinci_laplace_jump_is_sigma_over_r_and_linear_in_sigma() {
    let one = run_droplet(&[AKINCI, "solver.end_time=2.0"], 0.5);
    let two = run_droplet(
        &[AKINCI, "fluid.surface_tension=0.144", "solver.end_time=2.0"],
        0.5,
    );
    for d in [&one, &two] {
        let ratio = d.mechanical / d.laplace;
        assert!(
            (ratio - 1.0).abs() <= LAPLACE_JUMP,
            "core pressure {ratio:.3} sigma/R"
        );
    }
    let ratio = two.mechanical / one.mechanical;
    assert!((ratio / 2.0 - 1.0).abs() <= LAPLACE_JUMP, "ratio {ratio:.3}");
}

/// `r_max / r_rms` of the fluid about its centre: √3 = 1.73 for a continuous cube, `sqrt(5/3)`
/// = 1.29 for a continuous ball.
fn corner_ratio(f: &Fields<3>) -> f64 {
    let c = centre(f);
    let r: Vec<f64> = f.position.iter().map(|x| f64::from((x - c).norm())).collect();
    let rms = (r.iter().map(|r| r * r).sum::<f64>() / r.len() as f64).sqrt();
    r.iter().copied().fold(0.0, f64::max) / rms
}

/// 3D sanity, both models: `scenes/droplet_3d.toml` (a 1 cm cube, 1,000 particles) to t = 0.3 s
/// (3.4 relaxation times): every step finite, the momentum at f32 round-off (measured 1.2e-8 of
/// `M sqrt(σ/(ρ0 R))` with the surface stress, 4e-8 with [AAT13]), and the shape from cube to
/// ball: `r_max/r_rms` is 1.567 on the 10³ lattice cube and must fall to a lattice ball's, at
/// most 1.30 (a ball of radius R = 6.2 dx whose outer layer sits dx/2 inside has
/// `(R − dx/2)/(sqrt(3/5) R)` = 1.19, the continuum ball 1.29; measured 1.228 and 1.24).
#[test]
fn cube_droplet_becomes_a_ball_in_3d() {
    for sets in [vec![], vec![AKINCI.to_string()]] {
        let mut sets = sets;
        sets.push("solver.end_time=0.3".into());
        let scene = load_scene(Path::new("scenes/droplet_3d.toml"), &sets).expect("shipped scene");
        let mut sim = simulation_from_scene::<3>(&scene).expect("builds");
        let (mass, r) = (
            sim.fluid_mass(),
            (3.0e-6 / (4.0 * std::f64::consts::PI)).powf(1.0 / 3.0),
        );
        let speed = (0.072 / (scene.rho0 * r)).sqrt();
        let start = corner_ratio(&sim.fields);
        let mut momentum = 0.0f64;
        while sim.clock().time < scene.end_time - F64_SUM {
            sim.step(scene.end_time).expect("finite, stable step");
            let m = sim.fluid_momentum();
            momentum = momentum.max((m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt() / (mass * speed));
        }
        let end = corner_ratio(&sim.fields);
        eprintln!("{sets:?}: r_max/r_rms {start:.3} -> {end:.3}; momentum {momentum:.2e} of M u_capillary");
        assert!(start > 1.5, "the start is a cube: {start}");
        assert!(end <= 1.30, "{sets:?}: r_max/r_rms = {end:.3}");
        assert!(momentum < PAIRWISE_MOMENTUM, "{sets:?}: momentum {momentum:.2e}");
    }
}

/// The jump goes as 1/R: the surface-stress square of side 2 cm (R = 11.3 dx) against 4 cm
/// (R = 22.6 dx), the core's mechanical pressure averaged over t = 1.5–2 s, ratio R2/R1 = 2
/// within 10 % (measured 6.450 Pa = 1.011 σ/R and 3.016 Pa = 0.945 σ/R, ratio 2.139). Long:
/// the large drop has 1,600 particles.
#[test]
#[ignore = "long: about 80 s in release"]
fn laplace_jump_goes_as_one_over_r() {
    let small = run_droplet(&["solver.end_time=2.0"], 0.5);
    let large = run_droplet(
        &[
            "solver.end_time=2.0",
            "fluid_box.0.min=[-0.02,-0.02]",
            "fluid_box.0.max=[0.02,0.02]",
        ],
        0.5,
    );
    let ratio = small.mechanical / large.mechanical;
    eprintln!(
        "core pressure {:.3} Pa ({:.3} sigma/R) and {:.3} Pa ({:.3} sigma/R): ratio {ratio:.3}",
        small.mechanical,
        small.mechanical / small.laplace,
        large.mechanical,
        large.mechanical / large.laplace
    );
    assert!(
        (ratio / 2.0 - 1.0).abs() <= LAPLACE_JUMP,
        "ratio {ratio:.3} (tolerance 2 ± 10 %)"
    );
}

/// A restart is exact with the effect on: the normals are not saved (`Checkpoint` clears them,
/// the `surface_normals` stage recomputes them before every use), so a run restored from a
/// checkpoint after 200 steps takes the next 100 bit for bit as the run that went on.
#[test]
fn a_restart_with_surface_tension_is_bit_identical() {
    let scene = load_scene(Path::new("scenes/droplet_2d.toml"), &[]).expect("shipped scene");
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    for _ in 0..200 {
        sim.step(scene.end_time).expect("stable step");
    }
    let saved = sim.checkpoint(serde_json::Value::Null).expect("cpu checkpoint");
    assert!(saved.fields.normal.is_empty(), "normals are not saved");
    assert_eq!(
        sim.fields.normal.len(),
        sim.fields.len(),
        "the stage allocated them"
    );
    let mut restored = simulation_from_scene::<2>(&scene).expect("builds");
    restored.restore(saved).expect("same scene");
    for _ in 0..100 {
        sim.step(scene.end_time).expect("stable step");
        restored.step(scene.end_time).expect("stable step");
    }
    assert_eq!(sim.fields.position, restored.fields.position);
    assert_eq!(sim.fields.velocity, restored.fields.velocity);
    assert_eq!(sim.clock(), restored.clock());
}

/// A scene without the effect never allocates the normals (a field no stage needs is not
/// allocated) and has neither stage in its plan.
#[test]
fn without_the_effect_there_is_no_normal_field() {
    let scene = load_scene(Path::new("scenes/hydrostatic_2d.toml"), &[]).expect("shipped scene");
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    for _ in 0..5 {
        sim.step(scene.end_time).expect("stable step");
    }
    assert!(sim.fields.normal.is_empty());
    assert_eq!(sim.surface_tension_gamma(), 0.0);
    assert!(
        !sim.plan()
            .iter()
            .any(|s| matches!(s, Stage::SurfaceNormals(_) | Stage::SurfaceTension(_)))
    );
}
