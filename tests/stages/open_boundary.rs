//! Open boundaries (`sph::boundary::open`) on every backend. The buffer update itself runs on
//! the host (`solver::open`); what each backend must do is take the changed fields back
//! (`Backend::reload`): more particles after an inflow fills its buffer, fewer after an outflow
//! removes some, new velocities in both. Checked on the stage-test scene:
//! - the update against its rule, computed here: an empty inflow buffer two layers deep on the
//!   fluid's right end gains exactly two particles per column, at the prescribed velocity, with
//!   new ids; an outflow cutting the fluid removes exactly the fluid past its buffer and leaves
//!   the rest as they were, in their order;
//! - each backend, after a stage on the old fields, reloaded with the new ones, then sorted and
//!   summed (the `density` stage), gives bit for bit what a backend started on the new fields
//!   gives: nothing of the old count or order is left in it.

use crate::setup::{DX, RHO0, backends, scene};
use sph::boundary::open::{Flow, OpenBoundary, Profile, Template, update};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::params::StepParams;

/// A boundary on the plane x = `plane` with the section across the fluid block, `layers` deep.
fn boundary<const D: usize>(flow: Flow<D>, plane: f32, layers: f32, f: &Fields<D>) -> OpenBoundary<D> {
    let top = |k: usize| {
        (0..f.len())
            .filter(|&i| f.kind[i] == FLUID)
            .map(|i| f.position[i][k])
            .fold(0.0f32, f32::max)
    };
    let mut min = Vector::<D>::zeros();
    let mut max = Vector::<D>::from_fn(|k, _| (top(k) / DX).round() * DX);
    min[0] = plane;
    max[0] = plane;
    OpenBoundary {
        flow,
        axis: 0,
        inward: -1.0,
        min,
        max,
        depth: layers * DX,
    }
}

/// What created particles start from (any mass: the stages see it as it is).
const TEMPLATE: Template = Template {
    spacing: DX,
    mass: 0.1,
    rho0: RHO0,
};

/// Every backend: a stage on `before`, then reload with `after`, sort and `density`, against a
/// fresh backend on `after`; densities bitwise by id.
fn check_reload<const D: usize>(before: &Fields<D>, after: &Fields<D>, p: &StepParams<D>, what: &str) {
    for under in backends() {
        let (fresh, ()) = under.run(after, p, |b, f| b.density(f, p));
        let mut f = before.clone();
        let mut backend = under.start(&f, p);
        backend.sort_by_cell(&mut f, p).expect("finite positions");
        backend.density(&mut f, p);
        let mut g = after.clone();
        backend.reload(&g, p).expect("reload");
        backend.sort_by_cell(&mut g, p).expect("finite positions");
        backend.density(&mut g, p);
        backend.download(&mut g).expect("download");
        assert!(backend.take_error().is_none(), "{under:?}: no device error");
        assert_eq!(g.len(), after.len(), "{under:?} {D}D {what}: count");
        // By id (the ids are no longer 0..n once particles went or came).
        let bits = |f: &Fields<D>| -> Vec<(u32, u32)> {
            let mut v: Vec<(u32, u32)> =
                f.id.iter()
                    .zip(&f.density)
                    .map(|(&i, d)| (i, d.to_bits()))
                    .collect();
            v.sort_unstable();
            v
        };
        assert_eq!(
            bits(&g),
            bits(&fresh),
            "{under:?} {D}D {what}: densities after reload"
        );
    }
}

fn check_inflow<const D: usize>(seed: u64) {
    let (f, mut p) = scene::<D>(seed);
    let right = (0..f.len())
        .filter(|&i| f.kind[i] == FLUID)
        .map(|i| f.position[i][0])
        .fold(0.0f32, f32::max);
    let plane = (right / DX).round() * DX;
    p.domain_max[0] = p.domain_max[0].max(plane + 3.0 * DX);
    let u = Vector::<D>::from_fn(|k, _| if k == 0 { -0.3 } else { 0.1 });
    let flow = Flow::Inflow {
        velocity: u,
        profile: Profile::Uniform,
        level: None,
        ramp: None,
    };
    let b = boundary(flow, plane, 2.0, &f);
    let columns: usize = (1..D).map(|k| (b.max[k] / DX).round() as usize).product();
    let mut g = f.clone();
    let done = update(&mut g, &[b], &TEMPLATE, 0.0);
    assert_eq!(done.created as usize, 2 * columns, "{D}D: two layers per column");
    assert_eq!(done.removed, 0);
    let n = f.len();
    assert_eq!(g.len(), n + 2 * columns);
    let old_max = f.id.iter().copied().max().expect("particles");
    for i in n..g.len() {
        assert_eq!(g.kind[i], FLUID);
        assert_eq!(g.velocity[i], u, "{D}D: the inflow's velocity");
        assert!(g.id[i] > old_max, "{D}D: a new id");
        assert!(b.in_buffer(&g.position[i]), "{D}D: created in the buffer");
    }
    let mut ids = g.id.clone();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), g.len(), "{D}D: ids unique");
    check_reload(&f, &g, &p, "inflow");
}

fn check_outflow<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    // Past the buffer: the last 6 (2D) or 2 (3D) of the block's columns along x.
    let plane = if D == 2 { 16.0 * DX } else { 6.0 * DX };
    let b = boundary(Flow::Outflow, plane, 2.0, &f);
    let past: Vec<u32> = (0..f.len())
        .filter(|&i| {
            f.kind[i] == FLUID && b.across(&f.position[i]) && b.inward_distance(&f.position[i]) < -b.depth
        })
        .map(|i| f.id[i])
        .collect();
    let mut g = f.clone();
    let done = update(&mut g, &[b], &TEMPLATE, 0.0);
    assert!(!past.is_empty(), "{D}D: the outflow cuts the fluid");
    assert_eq!(
        (done.removed as usize, done.created),
        (past.len(), 0),
        "{D}D: the fluid past the buffer removed"
    );
    // The rest keep their order and every field: a free exit sets nothing.
    let kept: Vec<usize> = (0..f.len()).filter(|&i| !past.contains(&f.id[i])).collect();
    assert_eq!(
        g.id,
        kept.iter().map(|&i| f.id[i]).collect::<Vec<_>>(),
        "{D}D: order kept"
    );
    assert_eq!(
        g.velocity,
        kept.iter().map(|&i| f.velocity[i]).collect::<Vec<_>>(),
        "{D}D: velocities kept"
    );
    check_reload(&f, &g, &p, "outflow");
}

#[test]
fn an_inflow_fills_its_buffer_and_every_backend_takes_the_new_particles() {
    check_inflow::<2>(41);
    check_inflow::<3>(42);
}

#[test]
fn an_outflow_removes_past_its_buffer_and_every_backend_takes_the_fewer_particles() {
    check_outflow::<2>(43);
    check_outflow::<3>(44);
}
