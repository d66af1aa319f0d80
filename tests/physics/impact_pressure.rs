//! The pressure the `corrected` solver's fluid carries where the 2D dam-break surge
//! (`scenes/dam_break_2d.toml`, a = 0.25 m) reaches the far wall x = 5a: what a wall transducer
//! there reads (the probes interpolate the fluid particles' pressure, `probe::interpolate`).
//!
//! Why it reads zero (docs/method.md, "The velocity solve"): the arriving sheet sums (18) to
//! 930–970 kg/m³ (a thin sheet's kernel deficit), the position correction (23)–(24) only builds
//! pressure above ρ0 and releases it below (note 6), and the velocity solve, which is what
//! decelerates the sheet at the wall, keeps in the carried pressure only what it released,
//! `P = min(P, P_start)`. The impulse of the impact is in the velocities and in the force on the
//! tank, not in the pressure field.

use sph::math::Real;
use sph::probe::interpolate;
use sph::run::simulation_from_scene;
use sph::scene::parse_scene;
use sph::smoothing::Smoothing;
use std::path::Path;

/// Column height and width `a` [m] of the scene.
const A: f64 = 0.25;

/// The far-wall sensor's point [m]: on the wall x = 5a, 0.2 a = 50 mm above the floor (above
/// the kernel radius at a/25, so the floor does not cut the probe's support; low in the surge,
/// which arrives about a/4 thick).
const SENSOR: [f64; 2] = [5.0 * A, 0.2 * A];

/// End of the record [s]: the front reaches x = 5a near t = 0.56–0.64 s, the run-up jet
/// follows, and its fall back (t ≈ 1 s) is not yet there.
const END: f64 = 0.8;

/// The peak of the sensor's 1 ms running mean [Pa] (a transducer's bandwidth), sampled at the
/// end of every step, on the shipped dam break from the hydrostatic state with spacing `dx` [m]
/// and the `corrected` solver as shipped.
fn far_wall_peak(dx: f64) -> f64 {
    let path = Path::new("scenes/dam_break_2d.toml");
    let text = std::fs::read_to_string(path).expect("shipped scene");
    let sets = [
        format!("solver.end_time={END}"),
        format!("output.interval={END}"),
        "solver.kind=corrected".to_string(),
        "fluid.initial_state=hydrostatic".to_string(),
        format!("particles.spacing={dx}"),
    ];
    let scene = parse_scene(&text, "dam_break_2d.toml", &sets).expect("scene with overrides");
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let kernel = Smoothing::<2>::new(scene.smoothing_length as Real).expect("kernel");
    let mut samples: Vec<(f64, f64)> = Vec::new();
    while sim.clock().time < END - 1e-12 {
        sim.step(END).expect("stable step");
        sim.sync_fields().expect("fields");
        samples.push((
            sim.clock().time,
            interpolate::pressure(&sim.fields, &kernel, &SENSOR),
        ));
    }
    let window = 1e-3;
    samples
        .iter()
        .map(|(t, _)| {
            let near: Vec<f64> = samples
                .iter()
                .filter(|(s, _)| (s - t).abs() <= window / 2.0)
                .map(|s| s.1)
                .collect();
            near.iter().sum::<f64>() / near.len() as f64
        })
        .fold(0.0, f64::max)
}

/// The impact is read, and it converges: the peaks at a/25 and a/50 agree within 15 %, and
/// both are at least a quarter of the stagnation pressure `ρ0 u²/2` of the surge front's speed
/// at the wall, about 2 sqrt(g a) = 3.1 m/s (4.9 kPa). Why these bounds: wcsph reads 2,644 Pa
/// (a/25) and 2,771 Pa (a/50) there (`dam_break_pressure::far_wall_impact_converges_without_spikes`),
/// 4.6 % apart; a quarter of the stagnation pressure is 1.2 kPa, which an impact read as zero
/// (or as noise) cannot reach.
///
/// Measured with the solver as it is: 0 Pa at a/25 (no step reads a pressure at the sensor
/// through t = 0.8 s). Two changes to the velocity solve were measured against it (a/25 unless
/// said): (1) the divergence condition of DFSPH (Bender & Koschier 2017) for particles with at
/// least SPlisHSPlasH's neighbour count (7 in 2D) whatever their density, so a surrounded sheet
/// is stopped by pressure instead of compacting to ρ0: the sensor still reads 0 (the solve's
/// increments are not carried), and the front against Martin & Moyce moves from 5.6 % to 8.0 %
/// ahead (max over 1 ≤ T ≤ 3, a/50; the limit of `tests/dam_break.rs` is 8 %), because free-surface
/// particles with seven neighbours are then held apart. (2) With (1), carrying the solve's
/// pressure: everywhere, the sensor peaks at 1,477 Pa but the resting column of
/// `scenes/hard/rest_2d.toml` rings (floor force standard deviation over 1.5–2 s 4.2 N/m, limit
/// 2, against 0.32); only below 0.98 ρ0 (the particles the next position correction releases
/// anyway), 1,566 Pa at a/25 but 624 Pa at a/50 (no convergence), and 3.65 N/m at rest, where
/// 20–30 surface particles with full neighbourhoods carry up to 190 Pa of the divergence
/// condition's noise into the next force stage. On the Buchner tank (`scenes/dam_break_wall_2d.toml`,
/// H/40) that last variant lifts p_02H's peak from 0.086 to 0.578 ρgH (measured 0.691), at
/// T = 3.40 against the experiment's 2.74. Carrying the solve's pressure below 0.98 ρ0 without
/// the divergence condition reads 0 Pa: the sheet compacts to 0.98 ρ0 first.
#[test]
#[ignore = "fails: corrected's carried pressure is zero where the surge meets the far wall (the velocity solve's impact pressure is not carried)"]
fn corrected_far_wall_impact_is_read_and_converges() {
    let coarse = far_wall_peak(0.01);
    let fine = far_wall_peak(0.005);
    eprintln!("corrected far-wall peak (1 ms mean): a/25 {coarse:.0} Pa, a/50 {fine:.0} Pa");
    let stagnation = 0.5 * 1000.0 * (2.0 * (9.81 * A).sqrt()).powi(2);
    for (label, peak) in [("a/25", coarse), ("a/50", fine)] {
        assert!(
            peak >= 0.25 * stagnation,
            "{label}: peak {peak:.0} Pa, below a quarter of rho0 u^2/2 = {stagnation:.0} Pa"
        );
    }
    let agreement = (coarse - fine).abs() / fine;
    assert!(
        agreement <= 0.15,
        "peaks {coarse:.0} and {fine:.0} Pa differ by {:.0} %",
        100.0 * agreement
    );
}
