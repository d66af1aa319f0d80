//! The viscosity choice against an exact solution: start-up of plane Poiseuille flow
//! (`scenes/poiseuille_2d.toml`; Morris, Fox & Zhu 1997, series in validation/SOURCES.md 7.3).
//!
//! Set-up (the scene's comments give the reasons): walls y = 0 and y = L = 0.1 m, fluid from
//! rest, body force F = 0.4 m/s² along x (the scene's `fluid.gravity`), ν = 0.01 m²/s, so
//! u0 = F L²/(8ν) = 0.05 m/s, Re = u0 L/ν = 0.5 and the viscous time L²/ν = 1 s; dx = L/20,
//! h = 2 dx, `wcsph` with C = 20 u0. Without periodic boundaries (`poiseuille_periodic.rs` has
//! them) the channel is a
//! block 6 L long with free ends: nothing builds a pressure gradient along x, and the ends'
//! influence spreads by viscous diffusion only, sqrt(ν t) ≤ 0.8 L by t = 0.6 s, while the
//! profile is measured in the middle L of the block, 2.5 L from either end (the block moves at
//! most u0 t = 0.3 L). The profile: mean `u_x` of the fluid particles in that section, in 20
//! bins one spacing wide across the channel, against the series at the bin centres, at
//! t = 0.02, 0.05, 0.1, 0.2 and 0.6 s (t ν/L² the same numbers; at 0.6 the series is within
//! 0.3 % of the steady parabola).
//!
//! Result (measured; docs/validation.md, "Poiseuille flow"): with the two measures below, the
//! paper's Laplacian viscosity (17) follows the series within the 5 % target: worst
//! bin 0.22, 0.23, 0.24, 0.48 and 0.91 % of u0 at t = 0.02, 0.05, 0.1, 0.2 and 0.6 s (L = 20 dx,
//! h = 2 dx); at L = 40 dx (h = 2 dx) 0.06, 0.06, 0.07, 0.34 and 0.73 %. Without them the error
//! grows to 29 % of u0 at the steady state (centreline 1.29 u0), from two causes:
//! - the SPH Laplacian of (17) on the lattice at h = 2 dx is λ = 0.85 of the true one (the
//!   second moment `Σ_j V_j r² ∇²W / (2D)`; 0.95 at h = 3 dx, 0.98 at 4 dx), so the fluid
//!   would feel ν λ and the parabola's curvature would be 1/λ = 1.17 times the series'. So (17) is
//!   divided by λ computed on the initial lattice (`physics::lattice::lattice_laplacian_moment`,
//!   `StepParams::viscosity_scale`), as the pressure force (16) is divided by κ;
//! - wall particles carrying zero velocity are not a no-slip condition at the wall face: the
//!   fluid slips with a slip length b ≈ h/4 (fitted 0.30 h; 0.27 h at h = 2 dx and 0.24 h at
//!   h = 4 dx with μ/λ), a uniform 4b/L ≈ 0.12 u0 on top of the profile. So, after Adami, Hu & Adams
//!   (2012) eqs. (22)–(23), the wall particles carry `2 u_wall − ũ` in (17), ũ the Shepard
//!   average of the fluid velocity around them (`boundary::wall_velocity`, stage
//!   `wall_velocity`).
//!
//! `lattice_calibration_and_no_slip_walls_remove_the_curvature_and_slip_errors` checks each
//! fix's share at the steady state (curvature, slip).
//! `no_slip_wall_drag_is_the_reaction_and_follows_rayleigh` checks the walls on their own: the
//! drag on a block sliding over a wall is Rayleigh's (Stokes' first problem) within 3 %, and the
//! force on the wall is its exact reaction; a moving wall uses its prescribed velocity.
//!
//! Artificial viscosity instead of (17): with α chosen so that its continuum equivalent
//! (`physics::artificial_viscosity::equivalent_viscosity`, Monaghan 2005) equals ν, the flow
//! never becomes Poiseuille flow: the switch (approaching pairs only) leaves most of the shear
//! unresisted and the fluid slides as a plug that keeps accelerating (centreline 3.0 u0 at
//! t = 0.6 s, 1.26 u0 more than at 0.4 s). `artificial_viscosity_is_not_a_shear_viscosity`.

use crate::common::tolerance::{CLOCK_SLACK, F32_ACCUMULATION, F32_ROUNDING, F64_SUM};
use sph::fields::FLUID;
use sph::physics::lattice::lattice_mass;
use sph::probe::{ProbeSpace, measure};
use sph::run::simulation_from_scene;
use sph::scene::{Averaging, Probe, ProbeKind, Scene, Sensor, load_scene, parse_scene};
use sph::smoothing::Smoothing;
use std::path::Path;

/// Channel width L [m] (walls at y = 0 and y = L; the scene's fluid box).
pub(crate) const WIDTH: f64 = 0.1;
/// Centre of the measured section [m]: the middle of the fluid block x ∈ [0, 6 L].
const SECTION_CENTRE: f64 = 0.3;
/// Times [s] at which the profile is compared (t ν/L² the same numbers).
pub(crate) const TIMES: [f64; 5] = [0.02, 0.05, 0.1, 0.2, 0.6];
/// The target: largest |u_SPH − u_series| in a bin, as a fraction of the steady centreline
/// speed u0.
pub(crate) const TARGET: f64 = 0.05;

/// The shipped scene, with `sets` applied.
fn scene(sets: &[&str]) -> Scene {
    let path = format!("{}/scenes/poiseuille_2d.toml", env!("CARGO_MANIFEST_DIR"));
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    load_scene(Path::new(&path), &sets).expect("scenes/poiseuille_2d.toml is valid")
}

/// The driving body force F [m/s²] along the channel: the scene's gravity.
pub(crate) fn body_force(scene: &Scene) -> f64 {
    scene
        .gravity
        .as_ref()
        .expect("the body force is the scene's gravity")[0]
}

/// SOURCES.md 7.3, Poiseuille start-up: `u(y, t) = F/(2ν) y (L − y) − Σ_{n≥0} 4 F L²/(ν π³
/// (2n+1)³) sin((2n+1) π y/L) exp(−(2n+1)² π² ν t/L²)` [m/s]; y [m], t [s]. 200 terms: the
/// omitted tail is below 4 F L²/(ν π³) Σ_{k>400} k⁻³ ≈ 4e-7 u0.
pub(crate) fn series(y: f64, t: f64, f: f64, nu: f64) -> f64 {
    let (l, pi) = (WIDTH, std::f64::consts::PI);
    let mut u = f / (2.0 * nu) * y * (l - y);
    for n in 0..200 {
        let k = (2 * n + 1) as f64;
        u -= 4.0 * f * l * l / (nu * pi.powi(3) * k.powi(3))
            * (k * pi * y / l).sin()
            * (-k * k * pi * pi * nu * t / (l * l)).exp();
    }
    u
}

/// One measured profile: bin centres y [m] and the mean fluid `u_x` [m/s] in each bin, and
/// the flux [m²/s] a `flow_rate` probe reads across the channel at the section's centre.
struct Profile {
    time: f64,
    y: Vec<f64>,
    u: Vec<f64>,
    flux: f64,
}

/// A `flow_rate` probe across the channel, wall to wall, at the section's centre.
fn flux_probe() -> Probe {
    Probe {
        name: "flux".into(),
        kind: ProbeKind::FlowRate,
        axis: 0,
        origin: 0.0,
        solid: None,
        point: Some(vec![SECTION_CENTRE, WIDTH / 2.0]),
        size: Some(vec![WIDTH]),
        reference: None,
        sensor: Sensor::Point,
        averaging: Averaging::Instant,
    }
}

/// `∫_0^L series(y, t) dy` [m²/s], Simpson's rule on 400 intervals (the integrand is smooth).
fn series_flux(t: f64, f: f64, nu: f64) -> f64 {
    let n = 400;
    let dy = WIDTH / n as f64;
    let sum: f64 = (0..=n)
        .map(|k| {
            let weight = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            weight * series(k as f64 * dy, t, f, nu)
        })
        .sum();
    sum * dy / 3.0
}

/// Runs `scene` and measures the profile at each of [`TIMES`].
fn profiles(scene: &Scene) -> Vec<Profile> {
    let mut sim = simulation_from_scene::<2>(scene).expect("the scene builds");
    let dx = scene.spacing;
    let bins = (WIDTH / dx).round() as usize;
    let mut out = Vec::new();
    for &t in &TIMES {
        while sim.clock().time < t - CLOCK_SLACK {
            sim.step(t).expect("the step succeeds");
        }
        sim.sync_fields().expect("CPU fields");
        let f = &sim.fields;
        let (mut sum, mut count) = (vec![0.0; bins], vec![0usize; bins]);
        for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
            let (x, y) = (f64::from(f.position[i][0]), f64::from(f.position[i][1]));
            if (x - SECTION_CENTRE).abs() > 0.5 * WIDTH {
                continue;
            }
            let b = ((y / dx).floor().max(0.0) as usize).min(bins - 1);
            sum[b] += f64::from(f.velocity[i][0]);
            count[b] += 1;
        }
        assert!(
            count.iter().all(|&c| c > 0),
            "every bin holds particles: {count:?}"
        );
        out.push(Profile {
            time: t,
            y: (0..bins).map(|b| (b as f64 + 0.5) * dx).collect(),
            u: sum.iter().zip(&count).map(|(s, &c)| s / c as f64).collect(),
            flux: measure(&flux_probe(), &ProbeSpace::of(scene), f, &[]),
        });
    }
    out
}

/// Largest |u − series| over the bins, as a fraction of `u0` [m/s].
fn worst_error(p: &Profile, f: f64, nu: f64, u0: f64) -> f64 {
    p.y.iter()
        .zip(&p.u)
        .map(|(&y, &u)| (u - series(y, p.time, f, nu)).abs() / u0)
        .fold(0.0, f64::max)
}

/// Second moment of the viscosity kernel's Laplacian on the lattice, `λ = Σ_{j≠i} V_j r_ij²
/// ∇²W^visc(r_ij) / (2D)` with the lattice volume `V = m/ρ0` (`physics::lattice`): the SPH
/// Laplacian (17) of a quadratic field on the lattice is `λ` times the true one (1 in the
/// continuum, where `∫ r² ∇²W dV = 2D ∫ W dV`).
fn lattice_laplacian_moment(h: f64, dx: f64) -> f64 {
    let kernel = Smoothing::<2>::new(h as f32).expect("2D");
    let volume = lattice_mass(&kernel, dx, 1.0);
    let n = (h / dx).ceil() as i64;
    let mut sum = 0.0;
    for i in -n..=n {
        for j in -n..=n {
            let r = ((i * i + j * j) as f64).sqrt() * dx;
            if r > 0.0 {
                sum += volume * r * r * f64::from(kernel.laplacian_w_viscosity(r as f32));
            }
        }
    }
    sum / 4.0
}

/// Least-squares fit `u(y) = a · 4 y (L − y)/L² + s` [m/s]: the curvature term and a uniform
/// slip velocity. Returns `(a, s, largest residual)`.
fn fit_parabola_and_slip(p: &Profile) -> (f64, f64, f64) {
    let basis: Vec<f64> =
        p.y.iter()
            .map(|&y| 4.0 * y * (WIDTH - y) / (WIDTH * WIDTH))
            .collect();
    let n = basis.len() as f64;
    let (sx, sy) = (basis.iter().sum::<f64>(), p.u.iter().sum::<f64>());
    let sxx: f64 = basis.iter().map(|x| x * x).sum();
    let sxy: f64 = basis.iter().zip(&p.u).map(|(x, u)| x * u).sum();
    let a = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let s = (sy - a * sx) / n;
    let residual = basis
        .iter()
        .zip(&p.u)
        .map(|(x, u)| (u - (a * x + s)).abs())
        .fold(0.0, f64::max);
    (a, s, residual)
}

/// The worst bin error / u0 at each of [`TIMES`], for the shipped scene with `sets`.
fn errors(sets: &[&str]) -> Vec<(f64, f64)> {
    let scene = scene(sets);
    let (f, nu) = (
        body_force(&scene),
        scene
            .pair_terms
            .get(sph::model::pair_terms::PairTerm::Viscosity)
            .expect("viscosity")
            / scene.rho0,
    );
    let u0 = f * WIDTH * WIDTH / (8.0 * nu);
    let profiles = profiles(&scene);
    let errors: Vec<(f64, f64)> = profiles
        .iter()
        .map(|p| (p.time, worst_error(p, f, nu, u0)))
        .collect();
    println!("{sets:?}: worst bin / u0 at each time [s]: {errors:.4?}");
    // The flow-rate probe against the series' flux, at every time: within 5 %.
    let fluxes: Vec<(f64, f64)> = profiles
        .iter()
        .map(|p| (p.time, p.flux / series_flux(p.time, f, nu) - 1.0))
        .collect();
    println!("{sets:?}: flow-rate probe / series flux - 1 at each time [s]: {fluxes:.4?}");
    assert!(
        fluxes.iter().all(|(_, e)| e.abs() <= FLUX_TARGET),
        "flow rate against the series' flux (target {FLUX_TARGET}): {fluxes:.4?}"
    );
    errors
}

/// The flow-rate probe's target: the series' flux through the section within 5 %.
const FLUX_TARGET: f64 = 0.05;

/// The target at the shipped resolution, L = 20 dx, h = 2 dx (measured: at most 0.91 %
/// of u0, at t = 0.6 s).
#[test]
fn start_up_profile_follows_the_series_within_5_percent_of_u0() {
    let errors = errors(&[]);
    assert!(
        errors.iter().all(|&(_, e)| e <= TARGET),
        "worst bin / u0 at each time [s] (target {TARGET}): {errors:.3?}"
    );
}

/// The same target at twice the resolution, L = 40 dx, h = 2 dx (measured: at most 0.73 % of u0,
/// at t = 0.6 s).
#[test]
#[ignore = "long: 4 times the particles at a quarter of the step (about 40 s in release)"]
fn start_up_profile_follows_the_series_within_5_percent_of_u0_at_40_particles_across() {
    let errors = errors(&["particles.spacing=0.0025"]);
    assert!(
        errors.iter().all(|&(_, e)| e <= TARGET),
        "worst bin / u0 at each time [s] (target {TARGET}): {errors:.3?}"
    );
}

/// Each fix's share at the steady state (t = 0.6 s, series within 0.3 % of steady), where the
/// uncorrected operator had the profile's curvature 1/λ = 1.17 times the series' and a uniform
/// slip of 0.12 u0 (slip length 0.30 h). Asserted: λ = 0.8516 at h = 2 dx, from this file's own
/// lattice sum and from `physics::lattice` (whose inverse the simulation applies); the profile
/// is a parabola plus a uniform slip within 0.01 u0 (measured 0.0014 u0), its curvature the
/// series' within 2 % (measured 0.4 %; the uncorrected 17 % fails), and the slip length below
/// 0.03 h (measured 0.005 h; the zero-velocity walls' 0.30 h fails). Before the walls' influence
/// reaches the centre (t = 0.02 s) the core accelerates at F.
#[test]
fn lattice_calibration_and_no_slip_walls_remove_the_curvature_and_slip_errors() {
    let scene = scene(&[]);
    let (f, nu) = (
        body_force(&scene),
        scene
            .pair_terms
            .get(sph::model::pair_terms::PairTerm::Viscosity)
            .expect("viscosity")
            / scene.rho0,
    );
    let u0 = f * WIDTH * WIDTH / (8.0 * nu);
    let h = scene.smoothing_length;
    let lambda = lattice_laplacian_moment(h, scene.spacing);
    assert!((lambda - 0.8516).abs() < 1e-3, "λ = {lambda} at h = 2 dx");
    let kernel = Smoothing::<2>::new(h as f32).expect("2D");
    let library = sph::physics::lattice::lattice_laplacian_moment(&kernel, scene.spacing, 1000.0);
    assert!(
        (library - lambda).abs() < 1e-5,
        "physics::lattice λ = {library}, here {lambda}"
    );
    let sim = simulation_from_scene::<2>(&scene).expect("the scene builds");
    assert!(
        (f64::from(sim.viscosity_scale()) * lambda - 1.0).abs() < F32_ROUNDING,
        "the simulation scales (17) by 1/λ: {}",
        sim.viscosity_scale()
    );
    let all = profiles(&scene);
    let early = &all[0];
    let centre = early.u[early.u.len() / 2];
    let expected = series(early.y[early.u.len() / 2], early.time, f, nu);
    assert!(
        (centre - expected).abs() <= 0.005 * u0,
        "core at t = 0.02 s: {centre} vs {expected} m/s"
    );
    let steady = all.last().expect("profiles");
    let (a, s, residual) = fit_parabola_and_slip(steady);
    let worst = worst_error(steady, f, nu, u0);
    let b = s * WIDTH / (4.0 * u0);
    println!(
        "t = 0.6 s: worst {worst:.4} u0, curvature {:.4} u0, slip {:.4} u0 (b = {:.4} h), fit residual {:.4} u0",
        a / u0,
        s / u0,
        b / h,
        residual / u0
    );
    assert!(
        residual <= 0.01 * u0,
        "not a parabola plus slip: residual {residual}"
    );
    assert!(
        (a / u0 - 1.0).abs() <= 0.02,
        "curvature {} u0, the series' is 1 (uncorrected: 1/λ = {})",
        a / u0,
        1.0 / lambda
    );
    assert!(b.abs() <= 0.03 * h, "slip length {b} m = {} h", b / h);
}

/// Why the artificial viscosity gets no lattice scale like (17)'s `1/λ`: its continuum
/// equivalent (Monaghan 2005) rests on the isotropic fourth moment of the kernel gradient,
/// `∫ x_a x_b x_c x_d W'(r)/r³ dV = −(δ_ab δ_cd + δ_ac δ_bd + δ_ad δ_bc)/(D + 2)`, and on the
/// lattice at h = 2 dx that moment (with the `1/κ`-scaled spiky gradient the force stage uses)
/// is not a multiple of the isotropic one: measured 0.65 of it for `xxyy` (a shear along a
/// lattice axis) and 1.12 for `xxxx` (a compression along it), so no single factor calibrates
/// it, and its switch (approaching pairs only) removes more. It stays as it is: a numerical
/// damping with a tuned α, whose continuum equivalent serves only the time-step bound, where the
/// continuum value is the larger one for shear (a shorter, safer step). Asserted: the two ratios
/// within 0.02 of the measured values.
#[test]
fn artificial_viscosity_has_no_single_lattice_scale() {
    let reference = scene(&[]);
    let (h, dx) = (reference.smoothing_length, reference.spacing);
    let kernel = Smoothing::<2>::new(h as f32).expect("2D");
    let volume = lattice_mass(&kernel, dx, 1.0);
    let kappa = sph::physics::lattice::lattice_gradient_moment(&kernel, dx, 1.0);
    let n = (h / dx).ceil() as i64;
    let (mut xxyy, mut xxxx) = (0.0, 0.0);
    for i in -n..=n {
        for j in -n..=n {
            let (x, y) = (i as f64 * dx, j as f64 * dx);
            let r2 = x * x + y * y;
            if r2 == 0.0 || r2 >= h * h {
                continue;
            }
            // W'(r)/r from the gradient's x component (offset along x), scaled by 1/κ.
            let r = r2.sqrt();
            let mut along = sph::math::Vector::<2>::zeros();
            along[0] = r as f32;
            let dw_over_r = f64::from(kernel.grad_w_spiky(&along, r as f32)[0]) / r / kappa;
            xxyy += volume * x * x * y * y * dw_over_r / r2;
            xxxx += volume * x.powi(4) * dw_over_r / r2;
        }
    }
    let (shear, normal) = (xxyy / (-1.0 / 4.0), xxxx / (-3.0 / 4.0));
    println!("artificial viscosity's lattice moment / continuum: xxyy {shear:.4}, xxxx {normal:.4}");
    assert!((shear - 0.65).abs() < 0.02, "xxyy {shear}");
    assert!((normal - 1.12).abs() < 0.02, "xxxx {normal}");
}

/// The inviscid alternative: artificial viscosity alone, with α set so that its continuum
/// equivalent equals ν, does not give Poiseuille flow. Measured: the fluid slides as a plug
/// still accelerating at t = 0.6 s (centreline 3.0 u0, the series 0.995 u0); asserted: the
/// centreline is above 2 u0 and still gained more than 0.5 u0 since t = 0.2 s (the series
/// gains 0.14 u0).
#[test]
fn artificial_viscosity_is_not_a_shear_viscosity() {
    let reference = scene(&[]);
    let nu = reference
        .pair_terms
        .get(sph::model::pair_terms::PairTerm::Viscosity)
        .expect("viscosity")
        / reference.rho0;
    let f = body_force(&reference);
    let u0 = f * WIDTH * WIDTH / (8.0 * nu);
    let (c, h) = (reference.sound_speed, reference.smoothing_length);
    let alpha = nu / sph::physics::artificial_viscosity::equivalent_viscosity(1.0, c, h, 2);
    let path = format!("{}/scenes/poiseuille_2d.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("scene file");
    let text = text
        .replace(
            r#"effects = ["gravity", "viscosity"]"#,
            r#"effects = ["gravity", "artificial_viscosity"]"#,
        )
        .replace("viscosity = 10.0", &format!("artificial_viscosity = {alpha}"));
    let scene = parse_scene(&text, &path, &[]).expect("the artificial-viscosity variant is valid");
    assert_eq!(
        scene.pair_terms.get(sph::model::pair_terms::PairTerm::Viscosity),
        None,
        "no (17) in this variant"
    );
    let all = profiles(&scene);
    let mid = all[0].u.len() / 2;
    let (at_02, at_06) = (all[3].u[mid], all[4].u[mid]);
    println!(
        "α = {alpha}: centreline {:.3} u0 at 0.2 s, {:.3} u0 at 0.6 s",
        at_02 / u0,
        at_06 / u0
    );
    assert!(at_06 > 2.0 * u0, "centreline {} u0 at 0.6 s", at_06 / u0);
    assert!(
        at_06 - at_02 > 0.5 * u0,
        "still accelerating: {} -> {} u0",
        at_02 / u0,
        at_06 / u0
    );
}

/// A fluid block (0.2 m × 0.1 m, μ = 10 Pa s, ν = 0.01 m²/s, no gravity) sliding at U = 0.5 m/s
/// over a wall `floor_motion` (the scene's `motion` table or nothing), the first `end` seconds.
fn sliding_block(floor_motion: &str, end: f64) -> sph::solver::Simulation<2> {
    let text = format!(
        r#"
        dimension = 2
        effects = ["viscosity"]
        [domain]
        min = [-0.1, -0.1]
        max = [0.6, 0.3]
        [particles]
        spacing = 0.005
        smoothing_ratio = 2.0
        [fluid]
        rho0 = 1000.0
        sound_speed = 5.0
        viscosity = 10.0
        [[fluid_box]]
        min = [0.1, 0.0]
        max = [0.3, 0.1]
        velocity = [0.5, 0.0]
        [[solid]]
        name = "floor"
        shape = "box"
        min = [-0.05, -0.015]
        max = [0.55, 0.0]
        {floor_motion}
        [solver]
        kind = "wcsph"
        end_time = {end}
    "#
    );
    let scene = parse_scene(&text, "sliding_block", &[]).expect("valid scene");
    simulation_from_scene::<2>(&scene).expect("builds")
}

/// No-slip walls ([A12] eqs. 22–23) and the force on the solid: the wall's viscous drag on a
/// sliding block is the exact reaction of what the fluid feels, `ΔP_fluid = −Σ F_wall dt`
/// (1e-4 of the initial momentum: f32 over ~400 steps), and it is Rayleigh's (Stokes' first
/// problem): a wall shear stress `μ U / sqrt(π ν t)`, impulse `2 μ U W sqrt(t / (π ν))` over
/// the block's length W by t = 0.1 s, when the diffusion depth sqrt(ν t) = 0.03 m is a third
/// of the block's height. Asserted within 10 % (measured 0.97: 3.469 against 3.568 N s/m; the
/// block lost 35 % of its momentum).
#[test]
fn no_slip_wall_drag_is_the_reaction_and_follows_rayleigh() {
    let end = 0.1;
    let mut sim = sliding_block("", end);
    let p0 = sim.fluid_momentum();
    let mut impulse = [0.0f64; 3];
    while sim.clock().time < end - F64_SUM {
        let r = sim.step(end).expect("stable");
        for k in 0..3 {
            impulse[k] += sim.solid_forces()[0][k] * r.dt;
        }
    }
    let p1 = sim.fluid_momentum();
    for k in 0..2 {
        let change = p1[k] - p0[k];
        assert!(
            (change + impulse[k]).abs() <= F32_ACCUMULATION * p0[0],
            "axis {k}: fluid momentum change {change:.6e}, wall impulse {:.6e}",
            impulse[k]
        );
    }
    let (mu, nu, u, w) = (10.0, 0.01, 0.5, 0.2);
    let rayleigh = 2.0 * mu * u * w * (end / (std::f64::consts::PI * nu)).sqrt();
    println!(
        "wall impulse {:.4} N s/m, Rayleigh {rayleigh:.4} (ratio {:.3}); momentum {:.3} -> {:.3}",
        impulse[0],
        impulse[0] / rayleigh,
        p0[0],
        p1[0]
    );
    assert!(
        (impulse[0] / rayleigh - 1.0).abs() <= 0.1,
        "wall impulse {} N s/m, Rayleigh {rayleigh}",
        impulse[0]
    );
}

/// A moving wall's no-slip velocity uses its prescribed velocity `d'(t)` as `u_wall`
/// (`boundary::motion`): on the first step the fluid is at rest, so every floor particle with
/// fluid neighbours carries exactly `2 d'(0)` in (17) and the others their own `d'(0)`.
#[test]
fn moving_wall_carries_twice_its_velocity_next_to_fluid_at_rest() {
    let mut sim = sliding_block(
        "motion = { amplitude = [0.01, 0.0], period = 0.2, ramp = 0.0 }",
        1.0,
    );
    // Fluid at rest, so that the Shepard average ũ is exactly zero on the first step.
    for i in 0..sim.fields.len() {
        if sim.fields.kind[i] == FLUID {
            sim.fields.velocity[i] = sph::math::Vector::<2>::zeros();
        }
    }
    sim.step(1.0).expect("one step");
    sim.sync_fields().expect("CPU fields");
    let f = &sim.fields;
    let u_wall = 0.01 * 2.0 * std::f64::consts::PI / 0.2;
    let (mut wet, mut dry) = (0, 0);
    for i in (0..f.len()).filter(|&i| f.kind[i] != FLUID) {
        assert!(
            (f64::from(f.velocity[i][0]) - u_wall).abs() < 1e-5,
            "the floor moves at d'(0): {}",
            f.velocity[i][0]
        );
        if f.wall_velocity[i] == f.velocity[i] * 2.0 {
            wet += 1;
        } else {
            assert_eq!(
                f.wall_velocity[i], f.velocity[i],
                "particle {i}: {:?}",
                f.wall_velocity[i]
            );
            dry += 1;
        }
    }
    // The top layer under the block's 40 columns (the next layer lies h below the fluid).
    assert!(
        wet >= 40 && dry > 0,
        "{wet} floor particles by the fluid, {dry} away from it"
    );
}
