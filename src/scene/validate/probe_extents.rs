//! Probes against the scene they read: a sensor's face and a flow-rate section lie inside the
//! domain, and a sampling rate makes at most [`MAX_SAMPLES`] samples over the run. Both bound
//! work a probe does per reading or per run (a face of diameter 1e6 m is sampled every
//! `spacing`, a section every `h/4`, and a rate of 1e30 Hz advanced its next sampling time in
//! steps of 1e-30 s), and both come from the scene's own sizes.

use super::*;
use crate::scene::count::axis_name;
use crate::scene::magnitude::short;
use crate::scene::{Averaging, Sensor};

/// The most samples a probe with a `sampling_rate` may take over a run, `end_time ×
/// sampling_rate`: 1e7, ten times the frame limit's samples (`scene::progress::MAX_FRAMES`
/// frames, ten probe samples each). A transducer of 20 kHz over 500 s is 1e7 samples; past
/// that `probes.csv` alone is gigabytes.
pub const MAX_SAMPLES: f64 = 1e7;

/// Faces, sections and sampling rates of every probe (module doc).
pub(super) fn check_probe_extents(c: &mut Checker, scene: &Scene) {
    let domain = &scene.domain;
    let tol = 1e-6 * scene.spacing;
    for (i, p) in scene.probes.iter().enumerate() {
        let path = KeyPath::key("probe").i(i);
        if let (Some(point), Sensor::Face { diameter, normal }) = (&p.point, &p.sensor) {
            let radius = diameter / 2.0;
            let outside = (0..point.len()).filter(|&k| k != *normal).find(|&k| {
                point[k] - radius < domain.min[k] - tol || point[k] + radius > domain.max[k] + tol
            });
            if let Some(k) = outside {
                c.err(
                    path.k("diameter"),
                    format!(
                        "a face of {} m centred at {} = {} m reaches [{}, {}] m, outside the domain [{}, {}] m on that axis",
                        num(*diameter),
                        axis_name(k),
                        num(point[k]),
                        num(point[k] - radius),
                        num(point[k] + radius),
                        num(domain.min[k]),
                        num(domain.max[k])
                    ),
                );
            }
        }
        if let (Some(point), Some(size)) = (&p.point, &p.size) {
            let across = (0..point.len()).filter(|&k| k != p.axis);
            for (a, (k, w)) in across.zip(size).enumerate() {
                let (lo, hi) = (point[k] - w / 2.0, point[k] + w / 2.0);
                if lo < domain.min[k] - tol || hi > domain.max[k] + tol {
                    c.err(
                        path.k("size").i(a),
                        format!(
                            "a section {} m wide centred at {} = {} m reaches [{}, {}] m, outside the domain [{}, {}] m on that axis",
                            num(*w),
                            axis_name(k),
                            num(point[k]),
                            num(lo),
                            num(hi),
                            num(domain.min[k]),
                            num(domain.max[k])
                        ),
                    );
                }
            }
        }
        if let Averaging::Window(window) = p.averaging {
            let samples = scene.end_time / window;
            if samples.is_nan() || samples > MAX_SAMPLES {
                c.err(
                    path.k("sampling_rate"),
                    format!(
                        "{} Hz over solver.end_time = {} s is {} samples, more than the limit of {MAX_SAMPLES:e} (scene::validate::probe_extents::MAX_SAMPLES); use sampling_rate <= {} Hz",
                        short(1.0 / window),
                        short(scene.end_time),
                        short(samples.ceil()),
                        short(MAX_SAMPLES / scene.end_time)
                    ),
                );
            }
        }
    }
}
