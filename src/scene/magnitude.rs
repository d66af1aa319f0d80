//! Magnitudes the solver can compute with: scene values, and the products of them the solver
//! forms, must be representable in its `f32` arithmetic ([`crate::math::Real`]).
//!
//! Why: validation otherwise only asks for finite, positive numbers in f64, so `fluid.rho0 =
//! 1e308` or `fluid.sound_speed = 5e-324` pass and the run fails at its first step (an
//! infinite particle mass, a sound speed flushed to 0). Each value must be 0 (where 0 is
//! allowed) or have a magnitude in [`MIN_MAGNITUDE`, `MAX_MAGNITUDE`]; so must the derived
//! scales: the particle mass `ρ0 dx^D`, the pressure scale `ρ0 C²`, the acoustic acceleration
//! `C²/h`, each pair term's equivalent kinematic viscosity in each phase (`μ/ρ0` for the
//! viscosity, `α C h/(4(D+2))` for the artificial viscosity) and the speed gravity gives over
//! the run, `|g| T`. The kernels' normalisation constants (up to
//! `h^-(D+6)`, `smoothing::Smoothing::new`) are stored as f32 and must be normal f32 numbers.
//! Coordinates (domain, boxes, rotation centre) may be 0 or tiny but not above the largest
//! magnitude.

use super::validate::{RawProblem, num};
use super::{KeyPath, Scene};
use crate::boundary::flap::FlapAmplitude;
use crate::boundary::motion::Motion;
use crate::physics::pair::ViscousMedium;
use crate::physics::sea_state::Sea;
use crate::smoothing::Smoothing;

/// The smallest non-zero magnitude of a scene value or derived scale (SI units): 1e-30. The
/// solver computes in f32, whose normal numbers span 1.2e-38 to 3.4e38; a value in [1e-30,
/// 1e30] leaves a factor of 1e8 either side for the products the kernels form from it
/// (a kernel value, a neighbour sum, a squared speed) before they leave that span.
pub const MIN_MAGNITUDE: f64 = 1e-30;

/// The largest magnitude of a scene value or derived scale (SI units): 1e30; see
/// [`MIN_MAGNITUDE`].
pub const MAX_MAGNITUDE: f64 = 1e30;

/// What a value may be.
#[derive(Clone, Copy, PartialEq)]
enum Rule {
    /// Positive, in `[MIN_MAGNITUDE, MAX_MAGNITUDE]`.
    Positive,
    /// 0, or a magnitude in `[MIN_MAGNITUDE, MAX_MAGNITUDE]`.
    ZeroOr,
    /// A coordinate: magnitude at most `MAX_MAGNITUDE`.
    Coordinate,
}

/// The range of `rule` in words, for an error message.
fn range(rule: Rule) -> String {
    match rule {
        Rule::Positive => format!("must have a magnitude in [{MIN_MAGNITUDE:e}, {MAX_MAGNITUDE:e}]"),
        Rule::ZeroOr => format!("must be 0 or have a magnitude in [{MIN_MAGNITUDE:e}, {MAX_MAGNITUDE:e}]"),
        Rule::Coordinate => format!("must have a magnitude of at most {MAX_MAGNITUDE:e}"),
    }
}

fn fits(rule: Rule, v: f64) -> bool {
    let a = v.abs();
    match rule {
        Rule::Positive => (MIN_MAGNITUDE..=MAX_MAGNITUDE).contains(&a),
        Rule::ZeroOr => a == 0.0 || (MIN_MAGNITUDE..=MAX_MAGNITUDE).contains(&a),
        Rule::Coordinate => a <= MAX_MAGNITUDE,
    }
}

/// Collects problems; remembers which keys failed so that a derived scale is only checked
/// when its factors passed (one problem per mistake).
struct Magnitudes {
    problems: Vec<RawProblem>,
    failed: Vec<String>,
}

impl Magnitudes {
    fn value(&mut self, path: KeyPath, v: f64, rule: Rule) {
        if !fits(rule, v) {
            self.failed.push(path.to_string());
            self.problems.push(RawProblem::new(
                path,
                format!(
                    "{} (the solver computes in f32, see scene::magnitude), got {}",
                    range(rule),
                    num(v)
                ),
            ));
        }
    }

    fn values(&mut self, path: KeyPath, vs: &[f64], rule: Rule) {
        for (i, &v) in vs.iter().enumerate() {
            self.value(path.i(i), v, rule);
        }
    }

    /// A derived scale `what = formula` [unit] made of `factors` (key, value): checked only when
    /// no factor failed; the problem is reported at the factor furthest from 1 in magnitude (the
    /// likeliest mistake) and names every factor.
    fn derived(&mut self, what: &str, value: f64, unit: &str, factors: &[(KeyPath, f64)]) {
        let failed = |p: &KeyPath| {
            let p = p.to_string();
            // The key itself, or an entry of it (`fluid.gravity[1]` for `fluid.gravity`).
            self.failed
                .iter()
                .any(|f| p == *f || f.starts_with(&format!("{p}[")))
        };
        if factors.iter().any(|(p, _)| failed(p)) || fits(Rule::Positive, value) {
            return;
        }
        let extreme = factors
            .iter()
            .max_by(|a, b| a.1.abs().log10().abs().total_cmp(&b.1.abs().log10().abs()));
        let Some((path, _)) = extreme else {
            return;
        };
        let named: Vec<String> = factors
            .iter()
            .map(|(p, v)| format!("{p} = {}", num(*v)))
            .collect();
        self.problems.push(RawProblem::new(
            path.clone(),
            format!(
                "{what} = {} {unit} {} ({}; the solver computes in f32, see scene::magnitude)",
                short(value),
                range(Rule::Positive),
                named.join(", ")
            ),
        ));
    }
}

/// The magnitude problems of `scene` (empty when every value and scale fits).
pub(crate) fn check(scene: &Scene) -> Vec<RawProblem> {
    let mut m = Magnitudes {
        problems: Vec::new(),
        failed: Vec::new(),
    };
    let key = KeyPath::key;
    let (fp, pp, sp) = (key("fluid"), key("particles"), key("solver"));
    m.values(key("domain").k("min"), &scene.domain.min, Rule::Coordinate);
    m.values(key("domain").k("max"), &scene.domain.max, Rule::Coordinate);
    m.value(pp.k("spacing"), scene.spacing, Rule::Positive);
    m.value(fp.k("rho0"), scene.rho0, Rule::Positive);
    m.value(fp.k("sound_speed"), scene.sound_speed, Rule::Positive);
    for (term, coefficient) in scene.pair_terms.iter() {
        m.value(fp.k(term.name()), coefficient, Rule::ZeroOr);
    }
    if let Some(g) = &scene.gravity {
        m.values(fp.k("gravity"), g, Rule::ZeroOr);
        m.value(fp.k("gravity_ramp"), scene.gravity_ramp, Rule::ZeroOr);
    }
    if let Some(omega) = scene.angular_velocity {
        for w in omega {
            m.value(fp.k("angular_velocity"), w, Rule::ZeroOr);
        }
        m.values(fp.k("rotation_centre"), &scene.rotation_centre, Rule::Coordinate);
    }
    if let Some(sigma) = scene.surface_tension {
        m.value(fp.k("surface_tension"), sigma, Rule::Positive);
    }
    for (i, b) in scene.fluid_boxes.iter().enumerate() {
        let path = key("fluid_box").i(i);
        m.values(path.k("min"), &b.region.min, Rule::Coordinate);
        m.values(path.k("max"), &b.region.max, Rule::Coordinate);
        m.values(path.k("velocity"), &b.velocity, Rule::ZeroOr);
        if let Some(rho0) = b.rho0 {
            m.value(path.k("rho0"), rho0, Rule::Positive);
        }
    }
    for (i, s) in scene.solids.iter().enumerate() {
        let path = key("solid").i(i);
        m.values(path.k("min"), &s.region.min, Rule::Coordinate);
        m.values(path.k("max"), &s.region.max, Rule::Coordinate);
        let mp = path.k("motion");
        match &s.motion {
            Some(Motion::Sway(sway)) => {
                m.values(mp.k("amplitude"), &sway.amplitude, Rule::ZeroOr);
                m.value(mp.k("period"), sway.period, Rule::Positive);
                m.value(mp.k("ramp"), sway.ramp, Rule::ZeroOr);
            }
            Some(Motion::Piston(piston)) => {
                m.value(mp.k("wave_height"), piston.wave_height, Rule::Positive);
                m.value(mp.k("depth"), piston.depth, Rule::Positive);
                m.value(mp.k("period"), piston.period, Rule::Positive);
                m.value(mp.k("ramp"), piston.ramp, Rule::ZeroOr);
            }
            Some(Motion::Flap(flap)) => {
                m.values(mp.k("hinge"), &flap.hinge, Rule::Coordinate);
                match &flap.amplitude {
                    FlapAmplitude::Angle(a) => m.value(mp.k("angle"), *a, Rule::Positive),
                    FlapAmplitude::Wave {
                        wave_height,
                        depth,
                        hinge_height,
                        ..
                    } => {
                        m.value(mp.k("wave_height"), *wave_height, Rule::Positive);
                        m.value(mp.k("depth"), *depth, Rule::Positive);
                        m.value(mp.k("hinge_height"), *hinge_height, Rule::Coordinate);
                    }
                }
                m.value(mp.k("period"), flap.period, Rule::Positive);
                m.value(mp.k("ramp"), flap.ramp, Rule::ZeroOr);
            }
            Some(Motion::Series(series)) => {
                m.values(mp.k("file"), &series.displacement, Rule::ZeroOr);
                m.values(mp.k("file"), &series.time, Rule::Coordinate);
            }
            Some(Motion::Sea(maker)) => {
                m.value(mp.k("depth"), maker.depth, Rule::Positive);
                m.value(mp.k("ramp"), maker.ramp, Rule::ZeroOr);
                let sp = mp.k("sea");
                let band = maker.sea.band();
                m.value(sp.k("peak_period"), band.peak_period, Rule::Positive);
                m.value(sp.k("f_min"), band.f_min, Rule::Positive);
                m.value(sp.k("f_max"), band.f_max, Rule::Positive);
                match &maker.sea {
                    Sea::Irregular {
                        significant_height, ..
                    } => m.value(sp.k("significant_height"), *significant_height, Rule::Positive),
                    Sea::Focused {
                        amplitude,
                        focus_position,
                        focus_time,
                        ..
                    } => {
                        m.value(sp.k("amplitude"), *amplitude, Rule::Positive);
                        m.value(sp.k("focus_position"), *focus_position, Rule::Positive);
                        m.value(sp.k("focus_time"), *focus_time, Rule::Coordinate);
                    }
                }
                // The largest stroke amplitude the sea gives, at the key that sets it.
                let largest = maker.stroke.iter().fold(0.0, |a: f64, x| a.max(x.abs()));
                m.value(mp.k("sea"), largest, Rule::Positive);
            }
            None => {}
        }
    }
    if let Some(dt) = scene.dt {
        m.value(sp.k("dt"), dt, Rule::Positive);
    }
    m.value(sp.k("end_time"), scene.end_time, Rule::Positive);
    m.value(key("output").k("interval"), scene.output_interval, Rule::Positive);

    derived_scales(&mut m, scene);
    kernel(&mut m, scene);
    m.problems
}

/// The products of scene values the solver forms (see the module documentation).
fn derived_scales(m: &mut Magnitudes, scene: &Scene) {
    let key = KeyPath::key;
    let (fp, pp) = (key("fluid"), key("particles"));
    let (dx, h, c) = (scene.spacing, scene.smoothing_length, scene.sound_speed);
    let d = scene.dimension as i32;
    // Every phase's rest density, with its key.
    let mut densities = vec![(fp.k("rho0"), scene.rho0)];
    for (i, b) in scene.fluid_boxes.iter().enumerate() {
        if let Some(rho0) = b.rho0 {
            densities.push((key("fluid_box").i(i).k("rho0"), rho0));
        }
    }
    for (rho_key, rho0) in &densities {
        m.derived(
            &format!("particle mass {rho_key} * spacing^{d}"),
            rho0 * dx.powi(d),
            "kg",
            &[(rho_key.clone(), *rho0), (pp.k("spacing"), dx)],
        );
        m.derived(
            &format!("pressure scale {rho_key} * sound_speed^2"),
            rho0 * c * c,
            "Pa",
            &[(rho_key.clone(), *rho0), (fp.k("sound_speed"), c)],
        );
        // Each pair term's equivalent kinematic viscosity in this phase (the step limit's),
        // naming the scene values it depends on.
        for (term, coefficient) in scene.pair_terms.iter().filter(|(_, v)| *v > 0.0) {
            let nu = |sound_speed: f64, rho: f64| {
                term.step_viscosity(
                    coefficient,
                    &ViscousMedium {
                        sound_speed,
                        h,
                        dimension: scene.dimension,
                        lightest_rho0: rho,
                        viscosity_scale: 1.0,
                    },
                )
            };
            let by_density = nu(c, 2.0 * rho0) != nu(c, *rho0);
            if !by_density && rho_key != &fp.k("rho0") {
                continue; // the same in every phase: checked once
            }
            let mut factors = vec![(fp.k(term.name()), coefficient)];
            if by_density {
                factors.push((rho_key.clone(), *rho0));
            }
            if nu(2.0 * c, *rho0) != nu(c, *rho0) {
                factors.push((fp.k("sound_speed"), c));
            }
            m.derived(
                &format!("viscosity of {}", term.name()),
                nu(c, *rho0),
                "m^2/s",
                &factors,
            );
        }
    }
    m.derived(
        "acoustic acceleration sound_speed^2 / h",
        c * c / h,
        "m/s^2",
        &[(fp.k("sound_speed"), c), (pp.k("spacing"), dx)],
    );
    if let Some(g) = &scene.gravity {
        let norm = g.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.0 {
            m.derived(
                "speed gained under gravity |gravity| * end_time",
                norm * scene.end_time,
                "m/s",
                &[
                    (fp.k("gravity"), norm),
                    (key("solver").k("end_time"), scene.end_time),
                ],
            );
        }
    }
}

/// The kernels' normalisation constants must be normal f32 numbers (they are stored as f32).
fn kernel(m: &mut Magnitudes, scene: &Scene) {
    let path = KeyPath::key("particles").k("spacing");
    let h = scene.smoothing_length;
    if m.failed.iter().any(|f| f.starts_with("particles")) || !fits(Rule::Positive, h) {
        return;
    }
    let normal = match scene.dimension {
        2 => Smoothing::<2>::new(h as f32).is_ok_and(|k| k.constants_are_normal()),
        3 => Smoothing::<3>::new(h as f32).is_ok_and(|k| k.constants_are_normal()),
        _ => true,
    };
    if !normal {
        let d = scene.dimension;
        m.problems.push(RawProblem::new(
            path,
            format!(
                "the support radius h = {} m makes the kernel's normalisation 1/h^{} leave the range of f32 (the kernels store it as f32, see smoothing::Smoothing::new); use a support radius between about 1e-4 m and 1e4 m",
                num(h),
                d + 6
            ),
        ));
    }
}

/// `v` with four significant digits, plain in [1e-4, 1e9) and in exponent form otherwise
/// (`6.386e-33`, `1.566`), so that a problem stays one readable line.
pub(crate) fn short(v: f64) -> String {
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if v == 0.0 || !v.is_finite() {
        format!("{v}")
    } else if (1e-4..1e9).contains(&v.abs()) {
        let decimals = (3 - v.abs().log10().floor() as i32).max(0) as usize;
        trim(format!("{v:.decimals$}"))
    } else {
        let text = format!("{v:.3e}");
        match text.split_once('e') {
            Some((mantissa, exponent)) => format!("{}e{exponent}", trim(mantissa.to_string())),
            None => text,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn short_numbers_keep_four_digits() {
        assert_eq!(short(6.385508568141009e-33), "6.386e-33");
        assert_eq!(short(1.5660459763365826), "1.566");
        assert_eq!(short(0.2), "0.2");
        assert_eq!(short(35.0), "35");
        assert_eq!(short(9.396275859e9), "9.396e9");
        assert_eq!(short(1e30), "1e30");
        assert_eq!(short(0.0), "0");
    }
}
