//! The `state_extremes` stage with planted faults (non-finite fields, escaped particles,
//! negative and NaN densities), one phase and several, on every backend, against a brute-force
//! pass over the fields in the backend's current order.

use crate::setup::{DX, RHO0, Under, backends, scene};
use sph::backend::StateExtremes;
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::params::StepParams;
use sph::physics::multiphase::Phases;

/// The larger of `a` and `b`, NaN if either is: a non-finite state cannot hide behind a
/// maximum (the stage reports a NaN maximum as 0, after `.max(0.0)`).
fn max_or_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// `StateExtremes` of `f` (in the backend's current order) by brute force: the maxima and
/// means over fluid particles of the speed, the acceleration and the density error `(ρ −
/// ρ0_i)/ρ0_i` (in f64, `ρ0_i` each particle's own with several phases), the mean deficit as
/// mean |e| − mean compression; `escaped` the first fluid particle outside the domain box. The
/// first non-finite field (position, velocity, acceleration, density, pressure, in that order,
/// of any particle) is reported only when a fluid speed, acceleration or density error is not
/// finite: a NaN elsewhere alone (a pressure, a solid's field) is left to show there first.
fn reference_extremes<const D: usize>(f: &Fields<D>, p: &StepParams<D>) -> StateExtremes {
    let fluid: Vec<usize> = (0..f.len()).filter(|&i| f.kind[i] == FLUID).collect();
    let error = |i: usize| {
        let rho0 = f64::from(p.phases.rest_density(&f.rest_density, i, p.rho0));
        (f64::from(f.density[i]) - rho0) / rho0
    };
    let largest = |g: &dyn Fn(usize) -> f64| fluid.iter().map(|&i| g(i)).fold(f64::NEG_INFINITY, max_or_nan);
    let max_speed = largest(&|i| f64::from(f.velocity[i].norm()));
    let max_acceleration = largest(&|i| f64::from(f.acceleration[i].norm()));
    let max_abs = largest(&|i| error(i).abs());
    let max_compression = largest(&|i| error(i).max(0.0));
    let max_deficit = largest(&|i| (-error(i)).max(0.0));
    let abs_sum: f64 = fluid.iter().map(|&i| error(i).abs()).sum();
    let compression_sum: f64 = fluid.iter().map(|&i| error(i).max(0.0)).sum();
    let mean = |s: f64| {
        if fluid.is_empty() {
            0.0
        } else {
            s / fluid.len() as f64
        }
    };
    let finite = |v: &Vector<D>| v.iter().all(|c| c.is_finite());
    let non_finite = if (max_speed + max_acceleration + max_abs).is_finite() {
        None
    } else {
        (0..f.len()).find_map(|i| {
            [
                (!finite(&f.position[i]), "position"),
                (!finite(&f.velocity[i]), "velocity"),
                (!finite(&f.acceleration[i]), "acceleration"),
                (!f.density[i].is_finite(), "density"),
                (!f.pressure[i].is_finite(), "pressure"),
            ]
            .into_iter()
            .find_map(|(bad, name)| bad.then_some((i, name)))
        })
    };
    let outside = |x: &Vector<D>| (0..D).any(|k| x[k] < p.domain_min[k] || x[k] > p.domain_max[k]);
    StateExtremes {
        max_speed: max_speed.max(0.0),
        max_acceleration: max_acceleration.max(0.0),
        max_abs_density_error: max_abs.max(0.0),
        mean_abs_density_error: mean(abs_sum),
        max_compression: max_compression.max(0.0),
        mean_compression: mean(compression_sum),
        max_surface_deficit: max_deficit.max(0.0),
        mean_surface_deficit: mean(abs_sum - compression_sum),
        non_finite,
        escaped: fluid.iter().copied().find(|&i| outside(&f.position[i])),
    }
}

/// Relative tolerance of the means: f64 sums of a few thousand terms in another order differ
/// by at most `2 N u Σ|t|` (`u = 2⁻⁵³`), below 1e-12 of the sum.
const MEAN: f64 = 1.0e-12;

/// `got` against `want`. The maxima are per-particle values, bitwise with one phase; with
/// several the CUDA kernel keeps the largest error as the density scaled to ρ0, `ρ ρ0/ρ0_i`,
/// rounded once to f32 (`kernels/state_extremes.cu`), so within `2⁻²⁴ (1 + e)` of the f64
/// error `e`. The means to [`MEAN`]; the mean deficit, a difference of two sums, to [`MEAN`]
/// of mean |e|. Indices and names exactly. Returns the largest deviation of the error maxima.
fn compare(under: Under, what: &str, got: &StateExtremes, want: &StateExtremes, phases: Phases) -> f64 {
    let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
    assert_eq!(
        got.max_speed.to_bits(),
        want.max_speed.to_bits(),
        "{under:?} {what}: max speed"
    );
    assert_eq!(
        got.max_acceleration.to_bits(),
        want.max_acceleration.to_bits(),
        "{under:?} {what}: max acceleration"
    );
    let mut worst = 0.0f64;
    for (a, b, name) in [
        (got.max_abs_density_error, want.max_abs_density_error, "max |e|"),
        (got.max_compression, want.max_compression, "max compression"),
        (
            got.max_surface_deficit,
            want.max_surface_deficit,
            "max surface deficit",
        ),
    ] {
        let tolerance = match phases {
            Phases::Single => 0.0,
            Phases::Multi => f64::powi(2.0, -24) * (1.0 + b),
        };
        assert!(
            same(a, b) || (a - b).abs() <= tolerance,
            "{under:?} {what}: {name}: {a} against {b}"
        );
        worst = worst.max((a - b).abs());
    }
    for (a, b, name, scale) in [
        (
            got.mean_abs_density_error,
            want.mean_abs_density_error,
            "mean |e|",
            want.mean_abs_density_error,
        ),
        (
            got.mean_compression,
            want.mean_compression,
            "mean compression",
            want.mean_compression,
        ),
        (
            got.mean_surface_deficit,
            want.mean_surface_deficit,
            "mean surface deficit",
            want.mean_abs_density_error,
        ),
    ] {
        assert!(
            same(a, b) || (a - b).abs() <= MEAN * scale,
            "{under:?} {what}: {name}: {a} against {b}"
        );
    }
    assert_eq!(got.non_finite, want.non_finite, "{under:?} {what}: non-finite");
    assert_eq!(got.escaped, want.escaped, "{under:?} {what}: escaped");
    worst
}

/// `state_extremes` on a fresh backend holding `f` as it is, without `sort_by_cell` (the stage
/// needs no grid), so that a non-finite position, which the grid refuses, can be planted; the
/// current order is `f`'s.
fn unsorted<const D: usize>(under: Under, f: &Fields<D>, p: &StepParams<D>) -> (Fields<D>, StateExtremes) {
    let mut f = f.clone();
    let mut backend = under.start(&f, p);
    let e = backend.state_extremes(&f, p);
    backend.download(&mut f).expect("download");
    assert!(backend.take_error().is_none(), "{under:?}: no device error");
    (f, e)
}

/// What a planted fault must make the reference report, whatever the backend's order, so
/// that it is planted where it counts (or, for a quiet one, where it must not).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shows {
    /// Neither a non-finite field nor an escaped particle.
    Nothing,
    /// An escaped fluid particle.
    Escaped,
    /// A non-finite field: this one, or (`None`) whichever comes first in the backend's order.
    NonFinite(Option<&'static str>),
}

/// A planted fault: its name, how it changes the fields (given the fluid and the solid
/// indices), whether the backend sorts first (without, a NaN position can be planted), and what
/// it shows.
type Fault<const D: usize> = (
    &'static str,
    Box<dyn Fn(&mut Fields<D>, &[usize], &[usize])>,
    bool,
    Shows,
);

fn fault<const D: usize>(
    name: &'static str,
    plant: impl Fn(&mut Fields<D>, &[usize], &[usize]) + 'static,
    sorted: bool,
    shows: Shows,
) -> Fault<D> {
    (name, Box::new(plant), sorted, shows)
}

fn faults<const D: usize>(p: &StepParams<D>) -> Vec<Fault<D>> {
    let (lo, hi) = (p.domain_min, p.domain_max);
    vec![
        fault("clean", |_, _, _| {}, true, Shows::Nothing),
        fault(
            "escaped",
            // Three fluid particles (through three faces) and a solid outside.
            move |f, fluid, solid| {
                let m = fluid.len();
                f.position[fluid[m / 3]][D - 1] = lo[D - 1] - 0.5 * DX;
                f.position[fluid[m / 2]][0] = hi[0] + 0.5 * DX;
                f.position[fluid[2 * m / 3]][1] = hi[1] + 3.0 * DX;
                f.position[solid[0]][0] = lo[0] - 1.0;
            },
            true,
            Shows::Escaped,
        ),
        fault(
            "NaN solid pressure",
            |f, _, solid| f.pressure[solid[1]] = f32::NAN,
            true,
            Shows::Nothing,
        ),
        fault(
            "NaN fluid pressure",
            |f, fluid, _| f.pressure[fluid[9]] = f32::NAN,
            true,
            Shows::Nothing,
        ),
        fault(
            "NaN velocity, infinite density, NaN pressure",
            |f, fluid, _| {
                let m = fluid.len();
                f.velocity[fluid[m / 2]][1] = f32::NAN;
                f.density[fluid[m / 4]] = f32::INFINITY;
                f.pressure[fluid[3 * m / 4]] = f32::NAN;
            },
            true,
            Shows::NonFinite(None),
        ),
        fault(
            "infinite velocity",
            |f, fluid, _| f.velocity[fluid[5]][0] = f32::NEG_INFINITY,
            true,
            Shows::NonFinite(Some("velocity")),
        ),
        fault(
            "NaN acceleration",
            |f, fluid, _| f.acceleration[fluid[11]][D - 1] = f32::NAN,
            true,
            Shows::NonFinite(Some("acceleration")),
        ),
        fault(
            "NaN density",
            |f, fluid, _| f.density[fluid[5]] = -f32::NAN,
            true,
            Shows::NonFinite(Some("density")),
        ),
        fault(
            "negative density",
            |f, fluid, _| f.density[fluid[7]] = -5.0,
            true,
            Shows::Nothing,
        ),
        fault(
            "NaN position before a NaN acceleration",
            |f, fluid, _| {
                f.position[fluid[3]][0] = f32::NAN;
                f.acceleration[fluid[fluid.len() - 2]][0] = f32::NAN;
            },
            false,
            Shows::NonFinite(Some("position")),
        ),
        fault(
            "NaN solid pressure before an infinite acceleration",
            |f, fluid, solid| {
                f.pressure[solid[0]] = f32::NAN;
                f.acceleration[*fluid.last().expect("fluid")][0] = f32::INFINITY;
            },
            false,
            Shows::NonFinite(Some("pressure")),
        ),
    ]
}

fn check_state_extremes<const D: usize>(seed: u64, phases: Phases) {
    let (mut base, mut p) = scene::<D>(seed);
    p.phases = phases;
    if phases == Phases::Multi {
        base.rest_density = (0..base.len())
            .map(|i| if base.id[i] % 3 == 0 { 0.8 * RHO0 } else { RHO0 })
            .collect();
        for i in 0..base.len() {
            base.density[i] *= base.rest_density[i] / RHO0;
        }
    }
    let fluid: Vec<usize> = (0..base.len()).filter(|&i| base.kind[i] == FLUID).collect();
    let solid: Vec<usize> = (0..base.len()).filter(|&i| base.kind[i] != FLUID).collect();
    for (name, plant, sorted, shows) in faults(&p) {
        let mut f = base.clone();
        plant(&mut f, &fluid, &solid);
        let what = format!("{D}D {phases:?} {name}");
        for under in backends() {
            let (out, got) = if sorted {
                under.run(&f, &p, |b, f| b.state_extremes(f, &p))
            } else {
                unsorted(under, &f, &p)
            };
            let want = reference_extremes(&out, &p);
            match shows {
                Shows::Nothing => assert_eq!((want.non_finite, want.escaped), (None, None), "{what}"),
                Shows::Escaped => assert!(want.escaped.is_some() && want.non_finite.is_none(), "{what}"),
                Shows::NonFinite(field) => {
                    let (_, named) = want.non_finite.unwrap_or_else(|| panic!("{what}: reported"));
                    assert!(field.is_none_or(|field| field == named), "{what}: {named}");
                }
            }
            let worst = compare(under, &what, &got, &want, phases);
            eprintln!(
                "{under:?} {what}: worst error maximum {worst:.2e}, non-finite {:?}, escaped {:?}",
                want.non_finite, want.escaped
            );
        }
        if name == "negative density" {
            let want = reference_extremes(&f, &p);
            assert!(want.max_abs_density_error > 1.0, "{what}");
        }
        if name == "clean" {
            let want = reference_extremes(&f, &p);
            assert!(
                want.max_compression > 0.0 && want.max_surface_deficit > 0.0,
                "{what}"
            );
        }
    }
}

#[test]
fn state_extremes_are_the_brute_force_pass_with_planted_faults() {
    for phases in [Phases::Single, Phases::Multi] {
        check_state_extremes::<2>(0x0123_4567_89ab_cdef, phases);
        check_state_extremes::<3>(0xfedc_ba98_7654_3210, phases);
    }
}
