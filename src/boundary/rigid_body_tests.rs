//! Checks of the rigid-body dynamics against closed-form motions.

use super::*;
use crate::solver::Integrator;
use std::f64::consts::PI;

/// A body of mass `mass` with diagonal inertia `inertia` about its centre `centre`.
fn body(mass: f64, inertia: [f64; 3], centre: [f64; 3], freedom: Freedom) -> RigidBody {
    RigidBody {
        mass: MassProperties {
            mass,
            centre: Vector3::from(centre),
            inertia: Matrix3::from_diagonal(&Vector3::from(inertia)),
        },
        freedom,
        moorings: Vec::new(),
        gravity: Vector3::zeros(),
        contact: crate::boundary::contact::WallContact::None,
    }
}

type Load = dyn Fn(&BodyState) -> (Vector3<f64>, Vector3<f64>);

/// `steps` SSP-RK3 steps of `dt` [s] under the fluid load `load(state)`; the states after each.
fn rk3(b: &RigidBody, mut s: BodyState, dt: f64, steps: usize, load: &Load) -> Vec<BodyState> {
    let mut out = Vec::with_capacity(steps);
    for _ in 0..steps {
        let start = s;
        for &(a, c) in Integrator::Rk3.stage_weights_f64() {
            let (f, m) = load(&s);
            let rate = b.rate(&s, &f, &m);
            s = b.stage(&start, &s, &rate, a, c, dt);
        }
        out.push(s);
    }
    out
}

fn no_load(_: &BodyState) -> (Vector3<f64>, Vector3<f64>) {
    (Vector3::zeros(), Vector3::zeros())
}

/// The rotation angle [rad] of `q` about z (2D).
fn angle_z(q: &UnitQuaternion<f64>) -> f64 {
    let (_, _, yaw) = q.euler_angles();
    yaw
}

#[test]
fn a_free_body_falls_as_half_g_t_squared() {
    // SSP-RK3 integrates a constant acceleration exactly (third order, the motion is quadratic).
    let mut b = body(3.0, [1.0; 3], [0.5, 2.0, 0.0], Freedom::planar());
    b.gravity = Vector3::new(0.0, -9.81, 0.0);
    let dt = 1e-3;
    let states = rk3(&b, b.initial_state(), dt, 500, &no_load);
    let t = 500.0 * dt;
    let s = states.last().unwrap();
    assert!(
        (s.centre.y - (2.0 - 0.5 * 9.81 * t * t)).abs() < 1e-12,
        "{}",
        s.centre.y
    );
    assert!((s.velocity.y + 9.81 * t).abs() < 1e-12);
    assert_eq!(s.centre.x, 0.5);
    assert!(angle_z(&s.orientation).abs() < 1e-15);
}

#[test]
fn a_body_hanging_on_a_mooring_oscillates_at_the_spring_period() {
    // m = 2 kg on k = 50 N/m: ω = 5 rad/s, T = 1.2566 s; hanging 0.3924 m below the line's
    // rest length, released 0.1 m lower, it stays taut and moves as y_eq − 0.1 cos(ω t).
    let (m, k) = (2.0, 50.0);
    let mut b = body(m, [1.0; 3], [0.0, 0.0, 0.0], Freedom::planar());
    b.gravity = Vector3::new(0.0, -9.81, 0.0);
    let y_eq = 2.0 - 1.0 - m * 9.81 / k;
    b.mass.centre = Vector3::new(0.0, y_eq - 0.1, 0.0);
    b.moorings.push(Mooring {
        anchor: Vector3::new(0.0, 2.0, 0.0),
        fairlead: b.mass.centre,
        stiffness: k,
        rest_length: 1.0,
    });
    let dt = 1e-3;
    let states = rk3(&b, b.initial_state(), dt, 2500, &no_load);
    let omega = (k / m).sqrt();
    let worst = states
        .iter()
        .enumerate()
        .map(|(n, s)| (s.centre.y - (y_eq - 0.1 * (omega * (n + 1) as f64 * dt).cos())).abs())
        .fold(0.0, f64::max);
    // Phase error of RK3 over 2 periods at ω dt = 0.005: about ω⁴ dt³ t / 24 ≈ 1e-9 m.
    assert!(worst < 1e-7, "worst {worst:e} m");

    // Symplectic Euler keeps the period to first order in ω dt and the amplitude bounded.
    let mut s = b.initial_state();
    let mut lowest = f64::INFINITY;
    let mut highest = f64::NEG_INFINITY;
    for _ in 0..2500 {
        let rate = b.rate(&s, &Vector3::zeros(), &Vector3::zeros());
        s = b.symplectic_euler(&s, &rate, dt);
        lowest = lowest.min(s.centre.y);
        highest = highest.max(s.centre.y);
    }
    assert!(
        (highest - lowest - 0.2).abs() < 2e-3,
        "swing {}",
        highest - lowest
    );
}

#[test]
fn a_slack_mooring_pulls_nothing() {
    let mut b = body(1.0, [1.0; 3], [0.0, 1.0, 0.0], Freedom::planar());
    b.moorings.push(Mooring {
        anchor: Vector3::zeros(),
        fairlead: b.mass.centre,
        stiffness: 1e3,
        rest_length: 1.5,
    });
    let (f, m) = b.mooring_load(&b.initial_state());
    assert_eq!(f, Vector3::zeros());
    assert_eq!(m, Vector3::zeros());
    // Taut at 2 m: k (L − L0) = 500 N towards the anchor, a moment about the centre of the
    // fairlead's offset.
    b.moorings[0].rest_length = 0.5;
    b.moorings[0].fairlead = Vector3::new(0.1, 1.0, 0.0);
    let (f, m) = b.mooring_load(&b.initial_state());
    let line = Vector3::new(-0.1, -1.0, 0.0);
    let want: Vector3<f64> = line.normalize() * (1e3 * (line.norm() - 0.5));
    assert!((f - want).norm() < 1e-9, "{f:?}");
    assert!((m.z - (0.1 * want.y)).abs() < 1e-9, "{m:?}");
}

#[test]
fn a_constant_moment_turns_a_planar_body_as_half_alpha_t_squared() {
    let b = body(5.0, [9.0, 9.0, 0.4], [1.0, 1.0, 0.0], Freedom::planar());
    let torque = |_: &BodyState| (Vector3::zeros(), Vector3::new(0.0, 0.0, 0.2));
    let dt = 1e-3;
    let states = rk3(&b, b.initial_state(), dt, 1000, &torque);
    let s = states.last().unwrap();
    let want = 0.5 * (0.2 / 0.4) * 1.0;
    assert!(
        (angle_z(&s.orientation) - want).abs() < 1e-9,
        "{}",
        angle_z(&s.orientation)
    );
    assert!((s.angular_velocity.z - 0.5).abs() < 1e-12);
    assert_eq!(s.centre, b.mass.centre);
    // The planar body does not tip under an in-plane moment, nor move along a held axis.
    let tip = |_: &BodyState| (Vector3::new(0.0, 0.0, 7.0), Vector3::new(3.0, -2.0, 0.0));
    let s = rk3(&b, b.initial_state(), dt, 100, &tip)[99];
    assert_eq!(s.orientation, UnitQuaternion::identity());
    assert_eq!(s.centre, b.mass.centre);
}

#[test]
fn a_spinning_asymmetric_body_keeps_its_angular_momentum_and_energy() {
    // Torque free, I = diag(1, 2, 3) kg m², spun about a direction off every principal axis:
    // the body tumbles, but L = I_w ω and ½ ω·I_w ω stay.
    let b = body(1.0, [1.0, 2.0, 3.0], [0.0; 3], Freedom::free());
    let mut s = b.initial_state();
    s.angular_velocity = Vector3::new(0.3, 2.0, 0.1);
    let invariants = |s: &BodyState| {
        let r = s.orientation.to_rotation_matrix();
        let i_w = r.matrix() * b.mass.inertia * r.matrix().transpose();
        let l = i_w * s.angular_velocity;
        (l, 0.5 * s.angular_velocity.dot(&l))
    };
    let (l0, e0) = invariants(&s);
    let states = rk3(&b, s, 1e-3, 5000, &no_load);
    let (l, e) = invariants(states.last().unwrap());
    // RK3 at |ω| dt = 2e-3 over 5 s: drift of order (ω dt)³ per step, about 1e-6 in total.
    assert!((l - l0).norm() / l0.norm() < 1e-5, "{l:?} vs {l0:?}");
    assert!((e - e0).abs() / e0 < 1e-5, "{e} vs {e0}");
    // And it does tumble: ω changed direction.
    assert!((states.last().unwrap().angular_velocity - s.angular_velocity).norm() > 0.1);
}

#[test]
fn a_hinged_body_swings_at_the_pendulum_period() {
    // A 2 kg box, I_c = 0.01 kg m² about z, its centre 0.8 m below a hinge along z: small swings
    // of period 2π sqrt(I_p / (m g l)), I_p = I_c + m l².
    let (m, ic, l) = (2.0, 0.01, 0.8);
    let hinge = Vector3::new(0.0, 1.0, 0.0);
    let mut b = body(
        m,
        [1.0, 1.0, ic],
        [0.0, 1.0 - l, 0.0],
        Freedom::Hinge {
            point: hinge,
            axis: Vector3::z(),
        },
    );
    b.gravity = Vector3::new(0.0, -9.81, 0.0);
    let mut s = b.initial_state();
    let theta0: f64 = 0.01;
    s.orientation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta0);
    s.centre = b.placed(&s, &b.mass.centre);
    let dt = 1e-3;
    let states = rk3(&b, s, dt, 6000, &no_load);
    // Zero crossings of the angle, linearly interpolated.
    let angles: Vec<f64> = states.iter().map(|s| angle_z(&s.orientation)).collect();
    let crossings: Vec<f64> = angles
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] > 0.0 && w[1] <= 0.0)
        .map(|(n, w)| (n as f64 + 1.0 + w[0] / (w[0] - w[1])) * dt)
        .collect();
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let want = 2.0 * PI * ((ic + m * l * l) / (m * 9.81 * l)).sqrt();
    // Small-angle period; the amplitude 0.01 rad lengthens it by θ0²/16 ≈ 6e-6.
    assert!((period - want).abs() / want < 1e-4, "{period} vs {want}");
    // The centre stays on its circle about the hinge.
    for s in &states {
        assert!(((s.centre - hinge).norm() - l).abs() < 1e-12);
    }
}

#[test]
fn the_mass_properties_of_a_sampled_box_are_the_boxs() {
    // 3D: a 0.2 x 0.1 x 0.05 m box of density 500 kg/m³ sampled by cells of 0.01 m: mass ρ V,
    // centre the box's, I_xx = M (b² + c²)/12 and so on. The cell sum with each cell's own
    // inertia is exact for a box tiled by cells (Σ over cell centres plus s²/12 per cell).
    let s = 0.01;
    let (a, bb, c) = (0.2, 0.1, 0.05);
    let mut points = Vec::new();
    for i in 0..20 {
        for j in 0..10 {
            for k in 0..5 {
                let p = |n: usize| (n as f64 + 0.5) * s;
                points.push(Vector3::new(1.0 + p(i), 2.0 + p(j), p(k)));
            }
        }
    }
    let props = MassProperties::of_cells(&points, s * s * s, 500.0, 3).unwrap();
    let m = 500.0 * a * bb * c;
    assert!((props.mass - m).abs() < 1e-12 * m);
    assert!((props.centre - Vector3::new(1.1, 2.05, 0.025)).norm() < 1e-12);
    let want = [
        m * (bb * bb + c * c) / 12.0,
        m * (a * a + c * c) / 12.0,
        m * (a * a + bb * bb) / 12.0,
    ];
    for k in 0..3 {
        assert!(
            (props.inertia[(k, k)] - want[k]).abs() < 1e-9 * want[k],
            "{k}: {}",
            props.inertia[(k, k)]
        );
    }
    assert!(props.inertia[(0, 1)].abs() < 1e-12);

    // 2D: a 0.3 x 0.1 m rectangle per metre of depth, I_zz = M (a² + b²)/12.
    let mut points = Vec::new();
    for i in 0..30 {
        for j in 0..10 {
            points.push(Vector3::new((i as f64 + 0.5) * s, (j as f64 + 0.5) * s, 0.0));
        }
    }
    let props = MassProperties::of_cells(&points, s * s, 1000.0, 2).unwrap();
    let m = 1000.0 * 0.3 * 0.1;
    let want = m * (0.09 + 0.01) / 12.0;
    assert!(
        (props.inertia[(2, 2)] - want).abs() < 1e-9 * want,
        "{}",
        props.inertia[(2, 2)]
    );
    assert!(MassProperties::of_cells(&[], s, 1.0, 2).is_none());
}

#[test]
fn the_mooring_frequency_bounds_the_lines_modes_and_its_step_holds_them() {
    // A line at the centre of mass: exactly the spring's sqrt(k/M).
    let (m, k) = (2.0, 50.0);
    let mut b = body(m, [0.1; 3], [0.0, 0.0, 0.0], Freedom::planar());
    assert_eq!(b.mooring_frequency(2), None);
    b.moorings.push(Mooring {
        anchor: Vector3::new(0.0, 2.0, 0.0),
        fairlead: Vector3::zeros(),
        stiffness: k,
        rest_length: 1.0,
    });
    let w = b.mooring_frequency(2).expect("moored");
    assert!((w - (k / m).sqrt()).abs() < 1e-12, "{w}");
    // Two lines off the centre under gravity: translation and rotation couple. At the step the
    // time step allows (ω_m dt = CONTACT_STEP) SSP-RK3, stable on an oscillator up to
    // ω dt = √3, keeps the energy bounded over 200 periods of ω_m (it only damps: at most
    // 0.1 % above the start, and more than half of it left).
    b.gravity = Vector3::new(0.0, -9.81, 0.0);
    b.moorings = [-1.0, 1.0]
        .iter()
        .map(|&side| Mooring {
            anchor: Vector3::new(side * 1.5, 1.2, 0.0),
            fairlead: Vector3::new(side * 0.3, 0.1, 0.0),
            stiffness: k,
            rest_length: 1.0,
        })
        .collect();
    let w = b.mooring_frequency(2).expect("moored");
    let dt = crate::boundary::contact::CONTACT_STEP / w;
    let energy = |s: &BodyState| {
        let lines: f64 = b
            .moorings
            .iter()
            .map(|m| {
                let stretch = ((m.anchor - b.placed(s, &m.fairlead)).norm() - m.rest_length).max(0.0);
                0.5 * m.stiffness * stretch * stretch
            })
            .sum();
        0.5 * m * s.velocity.norm_squared()
            + 0.5 * 0.1 * s.angular_velocity.z * s.angular_velocity.z
            + m * 9.81 * s.centre.y
            + lines
    };
    let mut s = b.initial_state();
    s.velocity = Vector3::new(0.3, -0.2, 0.0);
    s.angular_velocity = Vector3::new(0.0, 0.0, 0.5);
    let (e0, floor) = (energy(&s), -m * 9.81 * 2.0);
    let steps = (200.0 * 2.0 * PI / w / dt) as usize;
    let states = rk3(&b, s, dt, steps, &no_load);
    // Measured from a level below any reachable state, so that the ratios mean something.
    let ratio = |s: &BodyState| (energy(s) - floor) / (e0 - floor);
    let highest = states.iter().map(ratio).fold(0.0, f64::max);
    let last = ratio(states.last().expect("steps"));
    assert!(
        highest < 1.001 && last > 0.5,
        "energy over its start: at most {highest}, at the end {last}"
    );
}
