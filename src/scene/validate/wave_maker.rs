//! Wave makers against the scene they run in: the still-water depth fits in the domain, the
//! flap's bed lies inside it, and the particles resolve the wave a regular maker makes. Each
//! value is checked once, here, so `sph check` and `sph run` refuse the same scenes (a period of
//! 1e-9 s or a depth of 1e6 m used to pass the check and fail at the run's start naming no key).

use super::*;
use crate::boundary::flap::FlapAmplitude;
use crate::boundary::sea_maker::Paddle;
use crate::scene::count::axis_name;

/// Fewest particle spacings per wavelength of a regular wave maker's wave. Below this the wave
/// is shorter than the lattice can carry (the kernel support `h` is 2–4 spacings): the maker
/// would only stir particles. Practice resolves a wave with 20–50 spacings or more; 10 only
/// refuses the impossible.
pub const MIN_SPACINGS_PER_WAVELENGTH: f64 = 10.0;

/// The vertical axis: gravity's largest component.
fn vertical_axis(gravity: &[f64]) -> usize {
    (0..gravity.len())
        .max_by(|&a, &b| gravity[a].abs().total_cmp(&gravity[b].abs()))
        .unwrap_or(0)
}

/// Every wave maker's depth, bed and wavelength (module doc).
pub(super) fn check_wave_makers(c: &mut Checker, scene: &Scene) {
    let Some(gravity) = scene.gravity.as_deref() else {
        return; // a maker that needs gravity was refused already
    };
    let z = vertical_axis(gravity);
    let (bottom, top) = (scene.domain.min[z], scene.domain.max[z]);
    let height = top - bottom;
    for (i, s) in scene.solids.iter().enumerate() {
        let path = KeyPath::key("solid").i(i).k("motion");
        // (depth, hinge point and height of a flap, period of a regular wave, its wavenumber)
        let (depth, flap, regular) = match &s.motion {
            Some(Motion::Piston(p)) => (p.depth, None, Some((p.period, p.wavenumber()))),
            Some(Motion::Flap(f)) => match &f.amplitude {
                FlapAmplitude::Wave {
                    depth, hinge_height, ..
                } => (
                    *depth,
                    Some((f.hinge[z], *hinge_height)),
                    f.wavenumber().map(|k| (f.period, k)),
                ),
                FlapAmplitude::Angle(_) => continue,
            },
            Some(Motion::Sea(m)) => {
                let flap = match &m.paddle {
                    Paddle::Flap {
                        hinge, hinge_height, ..
                    } => Some((hinge[z], *hinge_height)),
                    Paddle::Piston { .. } => None,
                };
                (m.depth, flap, None)
            }
            _ => continue,
        };
        if depth > height {
            c.err(
                path.k("depth"),
                format!(
                    "the still-water depth {} m is more than the domain is high on axis {} ({} m)",
                    num(depth),
                    axis_name(z),
                    num(height)
                ),
            );
        }
        if let Some((hinge, hinge_height)) = flap {
            let bed = hinge - hinge_height;
            if !(bottom..=top).contains(&bed) {
                c.err(
                    path.k("hinge_height"),
                    format!(
                        "puts the bed at {} = {} m (the hinge at {} m minus hinge_height {} m), outside the domain [{}, {}] m",
                        axis_name(z),
                        num(bed),
                        num(hinge),
                        num(hinge_height),
                        num(bottom),
                        num(top)
                    ),
                );
            }
        }
        if let Some((period, k)) = regular {
            let length = std::f64::consts::TAU / k;
            let shortest = MIN_SPACINGS_PER_WAVELENGTH * scene.spacing;
            if length.is_nan() || length < shortest {
                c.err(
                    path.k("period"),
                    format!(
                        "a wave of period {} s on {} m of water is {} m long, shorter than {} particle spacings ({} m at particles.spacing = {} m): lengthen the period or refine the spacing",
                        num(period),
                        num(depth),
                        num(length),
                        MIN_SPACINGS_PER_WAVELENGTH,
                        num(shortest),
                        num(scene.spacing)
                    ),
                );
            }
        }
    }
}
