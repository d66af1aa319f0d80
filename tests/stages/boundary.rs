//! The boundary stages on every backend, against brute-force references from `sph::boundary` and
//! `sph::physics`: `wall_pressure` ([A12] eq. 27, both `WallModel`s, walls at rest and
//! accelerating, rotating frame on and off, both density kernels, one phase and [HA06]
//! several), `wall_velocity` ([A12] eqs. 22–23), `move_solids` (`boundary::motion`) and
//! `keep_out` (`boundary::keep_out`, nearest face and entry face).

use crate::setup::{
    DX, Rng, SUM_ORDER, add_strays, backends, by_id, in_id_order, neighbours, scene, solid_scene,
    use_density_kernel, use_phases,
};
use sph::backend::WallModel;
use sph::boundary::keep_out::{KeepOutBox, KeepOutReport, push_moment};
use sph::boundary::motion::{Rotation, SolidKinematics};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::params::StepParams;
use sph::physics::density::{DensityKernel, density_kernel};
use sph::physics::multiphase::Phases;
use sph::physics::rotating_frame::centrifugal_acceleration;

/// Accelerations [m/s²] of the floor and the left wall for the moving case: several g, so that
/// `g − a_w` moves the pressure of the wetted walls far beyond the tolerance.
fn wall_accelerations<const D: usize>() -> Vec<SolidKinematics<D>> {
    let (mut floor, mut side) = (Vector::<D>::zeros(), Vector::<D>::zeros());
    (floor[0], floor[1], side[0], side[1]) = (30.0, -60.0, -80.0, 25.0);
    [floor, side]
        .map(|acceleration| SolidKinematics {
            acceleration,
            ..SolidKinematics::rest()
        })
        .to_vec()
}

/// [A12] eq. (27) by brute force for solid `w` of `f` (id order), with the summed branch (18),
/// (19) for `WallModel::ExtrapolatedOrSummed`: the pressure and its tolerance [Pa]. The sums are
/// f32 terms summed in f64; a backend sums them in f32 in another order, so each sum is within
/// [`SUM_ORDER`] of the sum of its terms' magnitudes: `Σ p_f W` and `Σ W` (positive terms) and
/// `Σ ρ_f d_k W` (weighted by `|b_k|`) through the quotient, `C² Σ m W` for the summed branch;
/// the winning branch's where it wins beyond both, else the larger (`max` is 1-Lipschitz).
pub fn reference_wall_pressure<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    model: WallModel,
    kinematics: &[SolidKinematics<D>],
    w: usize,
) -> (f64, f64) {
    let kernel = p.smoothing();
    let weight = p.density_weight();
    let (mut sw, mut sp) = (0.0f64, 0.0f64);
    let (mut sr, mut sr_abs) = ([0.0f64; D], [0.0f64; D]);
    // The sum (18) includes the wall itself; [HA06] sums the number density instead.
    let self_kernel = f64::from(density_kernel(&kernel, weight, 0.0));
    let mut summed = if p.phases == Phases::Multi {
        self_kernel
    } else {
        f64::from(f.mass[w]) * self_kernel
    };
    for (j, d, _) in neighbours(f, p.h, w) {
        let r2 = d.norm_squared();
        let wd = density_kernel(&kernel, weight, r2);
        summed += f64::from(if p.phases == Phases::Multi {
            wd
        } else {
            f.mass[j] * wd
        });
        if f.kind[j] == FLUID {
            let wj = kernel.w(r2);
            sw += f64::from(wj);
            sp += f64::from(f.pressure[j] * wj);
            let offset = d * (f.density[j] * wj);
            for k in 0..D {
                sr[k] += f64::from(offset[k]);
                sr_abs[k] += f64::from(offset[k]).abs();
            }
        }
    }
    if p.phases == Phases::Multi {
        summed *= f64::from(f.mass[w]);
    }
    // The body acceleration in the wall's frame, `g − a_w` with the wall's acceleration at the
    // particle, plus the centrifugal one.
    let mut body = match kinematics.get(f.kind[w] as usize - 1) {
        Some(k) => p.gravity - k.acceleration_at(&f.position[w]),
        None => p.gravity,
    };
    if p.rotating() {
        body += centrifugal_acceleration(&p.angular_velocity, &p.rotation_centre, &f.position[w]);
    }
    let (mut pressure, mut tol) = (0.0, 0.0);
    if sw > 0.0 {
        let numerator = sp + (0..D).map(|k| f64::from(body[k]) * sr[k]).sum::<f64>();
        let magnitude = sp + (0..D).map(|k| f64::from(body[k]).abs() * sr_abs[k]).sum::<f64>();
        pressure = (numerator / sw).max(0.0);
        tol = SUM_ORDER * (magnitude + numerator.abs()) / sw;
    }
    if model == WallModel::ExtrapolatedOrSummed {
        let c2 = f64::from(p.c2);
        let (summed, summed_tol) = (
            (c2 * (summed - f64::from(p.rho0))).max(0.0),
            SUM_ORDER * c2 * summed,
        );
        // The branch that wins beyond both tolerances sets the tolerance.
        if summed - summed_tol > pressure + tol {
            tol = summed_tol;
        } else if pressure - tol <= summed + summed_tol {
            tol = tol.max(summed_tol);
        }
        pressure = pressure.max(summed);
    }
    (pressure, tol)
}

/// A case of `wall_pressure`: the model, whether the walls accelerate, the rotating frame.
type WallCase = (WallModel, bool, bool);

fn check_wall_pressure<const D: usize>(seed: u64, kernel: DensityKernel, phases: Phases) {
    let (mut f, mut p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x5151);
    use_density_kernel(&mut p, kernel);
    use_phases(&mut f, &mut p, phases, false);
    let r = in_id_order(&f);
    let solids: Vec<usize> = (0..r.len()).filter(|&i| r.kind[i] != FLUID).collect();
    let mut cases: Vec<(WallCase, Vec<(f64, f64)>)> = Vec::new();
    for model in [WallModel::ExtrapolatedOrSummed, WallModel::Extrapolated] {
        for moving in [false, true] {
            for rotating in [false, true] {
                p.rotating_frame = u32::from(rotating);
                let acc = if moving { wall_accelerations() } else { Vec::new() };
                let want = (0..r.len())
                    .map(|w| match r.kind[w] {
                        FLUID => (0.0, 0.0),
                        _ => reference_wall_pressure(&r, &p, model, &acc, w),
                    })
                    .collect();
                cases.push(((model, moving, rotating), want));
            }
        }
    }
    let what = format!("{D}D {kernel:?} {phases:?}");
    // Each variant moves some wall far beyond the tolerance, so none passes vacuously.
    let find = |case: WallCase| &cases.iter().find(|c| c.0 == case).expect("every case").1;
    let changed = |a: &[(f64, f64)], b: &[(f64, f64)]| {
        solids
            .iter()
            .filter(|&&w| (a[w].0 - b[w].0).abs() > 100.0 * a[w].1.max(b[w].1))
            .count()
    };
    let rest = find((WallModel::Extrapolated, false, false));
    let summed = find((WallModel::ExtrapolatedOrSummed, false, false));
    let moving = changed(rest, find((WallModel::Extrapolated, true, false)));
    let rotating = changed(rest, find((WallModel::Extrapolated, false, true)));
    let summed_wins = changed(rest, summed);
    assert!(
        moving > 10,
        "{what}: accelerating walls changed {moving} wall pressures"
    );
    assert!(
        rotating > 10,
        "{what}: the rotating frame changed {rotating} wall pressures"
    );
    assert!(
        summed_wins > 10,
        "{what}: the summed branch won at {summed_wins} walls"
    );
    assert!(
        solids.iter().any(|&w| rest[w].0 > 1000.0),
        "{what}: pressed walls"
    );
    assert!(
        solids
            .iter()
            .any(|&w| summed[w].0 == rest[w].0 && rest[w].0 > 0.0),
        "{what}: the extrapolation wins somewhere"
    );
    if phases == Phases::Multi {
        // [HA06]'s summed branch (`m_w Σ W`) against eq. (18)'s (`Σ m_j W`) on the same walls.
        let single = StepParams {
            phases: Phases::Single,
            rotating_frame: 0,
            ..p
        };
        let model = WallModel::ExtrapolatedOrSummed;
        let eq_18: Vec<(f64, f64)> = (0..r.len())
            .map(|w| match r.kind[w] {
                FLUID => (0.0, 0.0),
                _ => reference_wall_pressure(&r, &single, model, &[], w),
            })
            .collect();
        let multi = changed(summed, &eq_18);
        assert!(
            multi > 10,
            "{what}: the number density changed {multi} wall pressures"
        );
    }
    let dry = solids.iter().filter(|&&w| rest[w] == (0.0, 0.0)).count();
    assert!(dry >= 12, "{what}: {dry} walls without fluid");
    for ((model, moving, rotating), want) in &cases {
        p.rotating_frame = u32::from(*rotating);
        let acc = if *moving { wall_accelerations() } else { Vec::new() };
        for under in backends() {
            let (out, ()) = under.run(&f, &p, |b, f| b.wall_pressure(f, &p, *model, &acc));
            let (pressure, density) = (by_id(&out, &out.pressure), by_id(&out, &out.density));
            let mut worst = 0.0f64;
            for id in 0..r.len() {
                if r.kind[id] == FLUID {
                    let unchanged = pressure[id].to_bits() == r.pressure[id].to_bits()
                        && density[id].to_bits() == r.density[id].to_bits();
                    assert!(unchanged, "{under:?} {what} {model:?}: fluid {id} keeps p and ρ");
                    continue;
                }
                let (p_want, p_tol) = want[id];
                let c2 = f64::from(p.c2);
                // ρ = ρ0 + p / C², rounded once to f32.
                let rho_want = f64::from(p.rho0) + p_want / c2;
                let rho_tol = p_tol / c2 + f64::from(p.rho0 * f32::EPSILON);
                let dp = (f64::from(pressure[id]) - p_want).abs();
                let drho = (f64::from(density[id]) - rho_want).abs();
                assert!(
                    dp <= p_tol && drho <= rho_tol,
                    "{under:?} {what} {model:?} moving {moving} rotating {rotating}: wall {id}: \
                     p {} want {p_want} ± {p_tol:.2e}, ρ {} want {rho_want} ± {rho_tol:.2e}",
                    pressure[id],
                    density[id]
                );
                if p_tol > 0.0 {
                    worst = worst.max(dp / p_tol);
                }
            }
            eprintln!(
                "{under:?} {what} wall_pressure {model:?} moving {moving} rotating {rotating}: \
                 worst |Δp| / tolerance {worst:.2e}"
            );
        }
    }
}

#[test]
fn wall_pressure_is_eq_27_by_brute_force_for_every_model_and_frame() {
    for kernel in [DensityKernel::Poly6, DensityKernel::ScaledSpiky] {
        for phases in [Phases::Single, Phases::Multi] {
            check_wall_pressure::<2>(0x2545_f491_4f6c_dd1d, kernel, phases);
            check_wall_pressure::<3>(0x9e37_79b9_7f4a_7c15, kernel, phases);
        }
    }
}

/// [A12] eqs. (22)–(23) by brute force for solid `w` of `f` (id order): `2 u_w − ũ`, and its
/// tolerance per axis: the Shepard average's two sums, each within [`SUM_ORDER`] of its terms'
/// magnitudes (`Σ |u_f,k| W`, `Σ W`), and the rounding of `2 u_w − ũ`. `None` without fluid
/// neighbours (the wall keeps its own velocity).
fn reference_wall_velocity<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    w: usize,
) -> Option<([f64; D], [f64; D])> {
    let kernel = p.smoothing();
    let (mut sw, mut su, mut su_abs) = (0.0f64, [0.0f64; D], [0.0f64; D]);
    for (j, d, _) in neighbours(f, p.h, w) {
        if f.kind[j] == FLUID {
            let wj = kernel.w(d.norm_squared());
            sw += f64::from(wj);
            let term = f.velocity[j] * wj;
            for k in 0..D {
                su[k] += f64::from(term[k]);
                su_abs[k] += f64::from(term[k]).abs();
            }
        }
    }
    let own = f.velocity[w];
    if sw <= 0.0 {
        return None;
    }
    let want = std::array::from_fn(|k| 2.0 * f64::from(own[k]) - su[k] / sw);
    let tol =
        std::array::from_fn(|k| SUM_ORDER * ((su_abs[k] + su[k].abs()) / sw + 2.0 * f64::from(own[k]).abs()));
    Some((want, tol))
}

fn check_wall_velocity<const D: usize>(seed: u64) {
    let (mut f, p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x5151);
    let r = in_id_order(&f);
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.wall_velocity(f, &p));
        let got = by_id(&out, &out.wall_velocity);
        let (mut worst, mut mirrored, mut dry) = (0.0f64, 0, 0);
        for id in 0..r.len() {
            if r.kind[id] == FLUID {
                assert_eq!(got[id], r.wall_velocity[id], "{under:?} {D}D: fluid {id}'s entry");
                continue;
            }
            let Some((want, tol)) = reference_wall_velocity(&r, &p, id) else {
                // No fluid neighbour: its own velocity, exactly.
                assert_eq!(got[id], r.velocity[id], "{under:?} {D}D: dry wall {id}");
                dry += 1;
                continue;
            };
            for k in 0..D {
                let diff = (f64::from(got[id][k]) - want[k]).abs();
                assert!(
                    diff <= tol[k],
                    "{under:?} {D}D wall_velocity: wall {id} axis {k}: {} want {} ± {:.2e}",
                    got[id][k],
                    want[k],
                    tol[k]
                );
                worst = worst.max(diff / tol[k]);
            }
            // The mirror moves it from its own velocity far beyond the tolerance.
            mirrored +=
                usize::from((0..D).any(|k| (want[k] - f64::from(r.velocity[id][k])).abs() > 1.0e3 * tol[k]));
        }
        eprintln!(
            "{under:?} {D}D wall_velocity: worst |Δu| / tolerance {worst:.2e}, {mirrored} mirrored, {dry} dry"
        );
        assert!(
            mirrored > 10,
            "{under:?} {D}D: walls next to the fluid: {mirrored}"
        );
        assert!(dry >= 12, "{under:?} {D}D: solids away from the fluid: {dry}");
    }
}

#[test]
fn wall_velocity_is_the_mirrored_shepard_average_by_brute_force() {
    check_wall_velocity::<2>(0x2545_f491_4f6c_dd1d);
    check_wall_velocity::<3>(0x9e37_79b9_7f4a_7c15);
}

/// The bits of everything but position and velocity, to check that a stage leaves them.
pub fn other_bits<const D: usize>(f: &Fields<D>, i: usize) -> Vec<u32> {
    let mut v = vec![f.id[i], f.kind[i]];
    v.extend(f.acceleration[i].iter().map(|c| c.to_bits()));
    v.extend(
        f.wall_velocity
            .get(i)
            .into_iter()
            .flat_map(|x| x.iter().map(|c| c.to_bits())),
    );
    v.extend([f.density[i], f.pressure[i], f.mass[i]].map(f32::to_bits));
    v
}

/// `move_solids`: one f32 addition per component, so bitwise: every solid particle at
/// `x0 + d` with velocity `d'`, fluid untouched; twice, with other kinematics the second time.
fn check_move_solids<const D: usize>(seed: u64) {
    let (f, p, reference) = solid_scene::<D>(seed);
    let r = in_id_order(&f);
    let mut rng = Rng(seed ^ 0x0c1e);
    let mut kinematics = || -> Vec<SolidKinematics<D>> {
        (0..2)
            .map(|_| SolidKinematics {
                displacement: Vector::from_fn(|_, _| rng.sym(0.05)),
                velocity: Vector::from_fn(|_, _| rng.sym(0.8)),
                acceleration: Vector::from_fn(|_, _| rng.sym(9.0)),
                rotation: Rotation::None,
            })
            .collect()
    };
    let (first, second) = (kinematics(), kinematics());
    for under in backends() {
        let (out, once) = under.run(&f, &p, |b, f| {
            b.move_solids(f, &reference, &first);
            b.download(f).expect("download");
            let once = f.clone();
            b.move_solids(f, &reference, &second);
            once
        });
        for (state, k) in [(&once, &first), (&out, &second)] {
            let got = in_id_order(state);
            let mut moved = 0;
            for id in 0..r.len() {
                assert_eq!(
                    other_bits(&got, id),
                    other_bits(&r, id),
                    "{under:?} {D}D: particle {id}"
                );
                let (x, u) = if r.kind[id] == FLUID {
                    (r.position[id], r.velocity[id])
                } else {
                    let s = &k[r.kind[id] as usize - 1];
                    (
                        reference.position[id - reference.first_id as usize] + s.displacement,
                        s.velocity,
                    )
                };
                let bits = |v: &Vector<D>| v.map(f32::to_bits);
                assert_eq!(
                    bits(&got.position[id]),
                    bits(&x),
                    "{under:?} {D}D: position of {id}"
                );
                assert_eq!(
                    bits(&got.velocity[id]),
                    bits(&u),
                    "{under:?} {D}D: velocity of {id}"
                );
                moved += usize::from(got.position[id] != r.position[id]);
            }
            assert!(moved > 50, "{under:?} {D}D: {moved} solids moved");
        }
    }
}

#[test]
fn move_solids_places_every_solid_at_its_reference_plus_displacement_bitwise() {
    check_move_solids::<2>(0x0dd_ba11_cafe_f00d);
    check_move_solids::<3>(0xfee1_600d_dead_beef);
}

/// `keep_out` after a step's start and a move (`store_step_start`, `integrate`), with the boxes
/// of a container (the floor and the left wall slabs, solid 0) cutting into the fluid and a
/// moving plate (solid 1) in the block, so particles are pushed through every face. The guard is
/// per-particle f32 comparisons and assignments (`KeepOutBox::push_out` box after box):
/// positions and velocities bitwise, the push count exactly; the impulses are f64 sums of the
/// same f64 terms in another order, within `2 N 2⁻⁵³` of their magnitudes: 1e-12 for the few
/// hundred pushes here. Returns the positions after the guard, by id.
/// `plate_solid`: the solid the inner plate names; one past the scene's two solids checks that
/// such a box still pushes while its impulse is dropped (as `KeepOutReport` has no slot for it).
fn check_keep_out<const D: usize>(seed: u64, from_step_start: bool, plate_solid: u32) -> Vec<Vector<D>> {
    const IMPULSE_ORDER: f64 = 1.0e-12;
    let (f, p) = scene::<D>(seed);
    // The top corner of the fluid block (`setup::scene`'s lattice counts).
    let counts = if D == 2 {
        [24.0, 16.0, 1.0]
    } else {
        [10.0, 8.0, 8.0]
    };
    let top = Vector::<D>::from_fn(|k, _| counts[k] * DX);
    let mut boxes = KeepOutBox::<D>::container(Vector::repeat(DX), top, 2.0 * DX, true, 0);
    let mut plate = KeepOutBox::<D>::fixed(top * 0.4, top * 0.6, plate_solid);
    plate.velocity[0] = 0.7;
    boxes.push(plate);
    let margin = 1.0e-5;
    let start = in_id_order(&f).position;
    let inside = |x: &Vector<D>| {
        boxes
            .iter()
            .any(|b| (0..D).all(|k| x[k] > b.min[k] && x[k] < b.max[k]))
    };
    let mut results = Vec::new();
    for under in backends() {
        let (out, (before, report)) = under.run(&f, &p, |b, f| {
            b.store_step_start(f);
            b.integrate(f, 0.02);
            b.download(f).expect("download");
            let before = f.clone();
            (before, b.keep_out(f, &boxes, 2, margin, from_step_start))
        });
        let (r, got) = (in_id_order(&before), in_id_order(&out));
        let mut want = KeepOutReport::none(2);
        let mut magnitude = [[0.0f64; 3]; 2];
        let mut angular_magnitude = [[0.0f64; 3]; 2];
        let mut outside_moved = 0;
        for id in 0..r.len() {
            assert_eq!(
                other_bits(&got, id),
                other_bits(&r, id),
                "{under:?} {D}D: particle {id}"
            );
            let (mut x, mut u) = (r.position[id], r.velocity[id]);
            if r.kind[id] == FLUID {
                let from = from_step_start.then_some(&start[id]);
                for b in &boxes {
                    let u_before = u;
                    if let Some(axis) = b.push_out(&mut x, &mut u, margin, from) {
                        let dp = f64::from(r.mass[id]) * (f64::from(u[axis]) - f64::from(u_before[axis]));
                        want.pushes += 1;
                        if let Some(slot) = want.impulse.get_mut(b.solid as usize) {
                            slot[axis] += dp;
                            magnitude[b.solid as usize][axis] += dp.abs();
                            let moment = push_moment(&x, axis, dp);
                            for c in 0..3 {
                                want.angular_impulse[b.solid as usize][c] += moment[c];
                                angular_magnitude[b.solid as usize][c] += moment[c].abs();
                            }
                        }
                    }
                }
                assert!(!inside(&x), "{under:?} {D}D: {id} still inside");
                outside_moved += usize::from(x != r.position[id] && !inside(&r.position[id]));
            }
            let bits = |v: &Vector<D>| v.map(f32::to_bits);
            assert_eq!(
                bits(&got.position[id]),
                bits(&x),
                "{under:?} {D}D: position of {id}"
            );
            assert_eq!(
                bits(&got.velocity[id]),
                bits(&u),
                "{under:?} {D}D: velocity of {id}"
            );
        }
        assert_eq!(report.pushes, want.pushes, "{under:?} {D}D: pushes");
        let mut worst = 0.0f64;
        for s in 0..2 {
            for k in 0..3 {
                let diff = (report.impulse[s][k] - want.impulse[s][k]).abs();
                assert!(
                    diff <= IMPULSE_ORDER * magnitude[s][k],
                    "{under:?} {D}D: impulse on solid {s} axis {k}: {} want {}",
                    report.impulse[s][k],
                    want.impulse[s][k]
                );
                if magnitude[s][k] > 0.0 {
                    worst = worst.max(diff / magnitude[s][k]);
                }
                // The angular impulse: the same pushes' `x × dp` at the pushed position, summed
                // in another order.
                let diff = (report.angular_impulse[s][k] - want.angular_impulse[s][k]).abs();
                assert!(
                    diff <= IMPULSE_ORDER * angular_magnitude[s][k],
                    "{under:?} {D}D: angular impulse on solid {s} axis {k}: {} want {}",
                    report.angular_impulse[s][k],
                    want.angular_impulse[s][k]
                );
            }
        }
        assert!(
            angular_magnitude[0].iter().sum::<f64>() > 0.0,
            "{under:?} {D}D: the pushes carry angular momentum"
        );
        eprintln!(
            "{under:?} {D}D keep_out from_step_start {from_step_start}: {} pushes, {outside_moved} \
             crossings, worst impulse |Δ| / Σ|terms| {worst:.2e}",
            want.pushes
        );
        assert!(want.pushes > 20, "{under:?} {D}D: only {} pushes", want.pushes);
        // Only the crossing rule (with the step start) moves a particle that ended outside.
        assert_eq!(
            outside_moved > 0,
            from_step_start,
            "{under:?} {D}D: {outside_moved} crossings"
        );
        results.push(got.position);
    }
    results.swap_remove(0)
}

#[test]
fn keep_out_is_push_out_box_after_box_bitwise_for_both_face_rules() {
    let nearest = check_keep_out::<2>(0x0bad_cafe_1234_5678, false, 1);
    let entry = check_keep_out::<2>(0x0bad_cafe_1234_5678, true, 1);
    assert_ne!(nearest, entry, "2D: the step start changes some particle's face");
    let nearest = check_keep_out::<3>(0x5678_1234_cafe_0bad, false, 1);
    let entry = check_keep_out::<3>(0x5678_1234_cafe_0bad, true, 1);
    assert_ne!(nearest, entry, "3D: the step start changes some particle's face");
}

#[test]
fn keep_out_box_of_a_solid_past_the_count_pushes_without_an_impulse_slot() {
    check_keep_out::<2>(0x0bad_cafe_1234_5678, true, 5);
    check_keep_out::<3>(0x5678_1234_cafe_0bad, false, 5);
}

/// Walls that stop accelerating (an empty list after a full one) are walls at rest: the
/// pressure equals that of a backend that never saw the accelerations, bitwise.
fn check_wall_acceleration_reset<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let model = WallModel::ExtrapolatedOrSummed;
    let acc = wall_accelerations::<D>();
    for under in backends() {
        let (after, ()) = under.run(&f, &p, |b, f| {
            b.wall_pressure(f, &p, model, &acc);
            b.wall_pressure(f, &p, model, &[]);
        });
        let (at_rest, ()) = under.run(&f, &p, |b, f| b.wall_pressure(f, &p, model, &[]));
        let (moving, ()) = under.run(&f, &p, |b, f| b.wall_pressure(f, &p, model, &acc));
        let bits = |g: &Fields<D>| {
            by_id(g, &g.pressure)
                .iter()
                .map(|x| x.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(
            bits(&after),
            bits(&at_rest),
            "{under:?} {D}D: walls at rest again"
        );
        assert_ne!(
            bits(&moving),
            bits(&at_rest),
            "{under:?} {D}D: the accelerations show"
        );
    }
}

#[test]
fn wall_pressure_forgets_accelerations_once_the_walls_stop() {
    check_wall_acceleration_reset::<2>(0x3141_5926_5358_9793);
    check_wall_acceleration_reset::<3>(0x2718_2818_2845_9045);
}
