//! Probes: quantities sampled over a run (`[[probe]]` in a scene), written to `probes.csv`,
//! and compared with reference data when the probe names some (`[probe.reference]`).
//!
//! `front`: the surge front, the largest fluid coordinate along the probe's axis minus its
//! origin [m] (Martin & Moyce's z, measured from the back wall). Against a reference it is
//! normalised as `Z = z/a`, `T = t sqrt(g/a)` with `a` = `reference.length` and `g = |gravity|`
//! (square column, n = 1; docs/validation.md).
//!
//! `force`: the force of the fluid on one solid along the axis [N] (2D: [N/m]), averaged over
//! each sampling interval (the per-step force of particle methods is noisy). Against a
//! reference (time [s], force [N], e.g. Yeh & Petroff's column) the comparison is the first
//! peak: the largest force within the reference's `time_range`, and when it occurs.
//!
//! `pressure`, `velocity`: the fluid's pressure [Pa], or its velocity along the axis [m/s], at
//! the probe's point, interpolated from the fluid particles with Shepard's normalisation;
//! `level`: a wave gauge, the height [m] of the free surface above the probe's point along the
//! axis; `flow_rate`: the volume flux through a segment (2D, [m²/s]) or rectangle (3D, [m³/s])
//! normal to the axis ([`interpolate`] says how each is read). Each is the value at the
//! sampling time.
//!
//! `moment`: the moment about the probe's point of the fluid's force on one solid, along the
//! axis [N m] (2D: the out-of-plane moment [N m/m]), `M_P = M_O − P × F` from the solid's moment
//! about the origin `M_O = Σ_s x_s × f_s` and force `F` (`backend::SolidLoad`,
//! `boundary::solid_force::moment_about`); averaged over each sampling interval as the force.

pub mod compare;
pub mod interpolate;
pub mod reach;
pub mod signal;
pub mod waves;

pub use compare::{
    ONSET_FRACTION, Peak, ProbeComparison, ProbeError, check_references, compare, compare_samples,
    front_figure, write_figures,
};

use crate::boundary::solid_force::moment_about;
use crate::fields::{FLUID, Fields};
use crate::math::Real;
use crate::output::{CsvTable, CsvValue, OutputError, force_unit};
use crate::scene::{Averaging, Probe, ProbeKind, Scene, Sensor, SolverKind};
use crate::smoothing::Smoothing;
use std::path::{Path, PathBuf};

/// What a probe's reading depends on besides the particles: the scene's kernel support and
/// domain, and which pressure its solver's particles hold for a sensor.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeSpace {
    /// Kernel support radius `h` [m] of the interpolations.
    pub h: f64,
    /// Upper corner of the domain [m]: where a level gauge's line ends.
    pub domain_max: Vec<f64>,
    /// The pressure a pressure probe interpolates.
    pub pressure: PressureReading,
}

impl ProbeSpace {
    /// The scene's.
    pub fn of(scene: &Scene) -> ProbeSpace {
        ProbeSpace {
            h: scene.smoothing_length,
            domain_max: scene.domain.max.clone(),
            pressure: PressureReading::of(scene.solver.kind),
        }
    }
}

/// Which particle pressure a pressure probe interpolates: the one that acted on the fluid over
/// the last stage, as a transducer feels it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PressureReading {
    /// `Fields::pressure`: `wcsph`'s equation of state (19), the pressure its force stage uses.
    Carried,
    /// `Fields::acting_pressure`: the `corrected` solver's velocity solve pressure `P`, before it
    /// releases to what the next stage carries (docs/method.md, "Impact pressure"). The carried
    /// pressure forgets what stopped a sheet at a wall: it reads zero through an impact.
    Acting,
}

impl PressureReading {
    /// The reading of a run with `solver`.
    pub fn of(solver: SolverKind) -> PressureReading {
        match solver {
            SolverKind::Wcsph => PressureReading::Carried,
            SolverKind::Corrected => PressureReading::Acting,
        }
    }

    /// The per-particle pressures [Pa] this reading takes from `fields`.
    pub fn values<const D: usize>(self, fields: &Fields<D>) -> &[Real] {
        match self {
            PressureReading::Carried => &fields.pressure,
            PressureReading::Acting => &fields.acting_pressure,
        }
    }
}

/// Value of one probe on the current state: the front position [m], the force on its solid
/// during the last step [N] (`solid_forces` as `Simulation::solid_forces`), or the pressure
/// [Pa], surface height [m] or velocity [m/s] at its point ([`interpolate`]). Without the
/// solids' moments a moment probe reads NaN: [`measure_loads`] takes them.
pub fn measure<const D: usize>(
    probe: &Probe,
    space: &ProbeSpace,
    fields: &Fields<D>,
    solid_forces: &[[f64; 3]],
) -> f64 {
    measure_loads(probe, space, fields, solid_forces, &[])
}

/// [`measure`], with the moments about the origin of the forces on the solids during the last
/// step [N m] (`solid_moments` as `Simulation::solid_moments`), which a moment probe reads.
pub fn measure_loads<const D: usize>(
    probe: &Probe,
    space: &ProbeSpace,
    fields: &Fields<D>,
    solid_forces: &[[f64; 3]],
    solid_moments: &[[f64; 3]],
) -> f64 {
    let at_point = |read: &dyn Fn(&Smoothing<D>, &[f64]) -> f64| -> f64 {
        match (Smoothing::<D>::new(space.h as Real), probe.point.as_deref()) {
            (Ok(kernel), Some(point)) if point.len() == D => read(&kernel, point),
            _ => f64::NAN,
        }
    };
    let pressure = space.pressure.values(fields);
    match probe.kind {
        ProbeKind::Pressure => match probe.sensor {
            Sensor::Point => at_point(&|k, x| interpolate::pressure_of(fields, pressure, k, x)),
            Sensor::Face { diameter, normal } => at_point(&|k, x| {
                let spacing = interpolate::FACE_SPACING * space.h;
                interpolate::face_average::<D>(x, normal.min(D - 1), diameter, spacing, |y| {
                    interpolate::pressure_of(fields, pressure, k, y)
                })
            }),
        },
        ProbeKind::Velocity => at_point(&|k, x| interpolate::velocity(fields, k, x, probe.axis.min(D - 1))),
        ProbeKind::FlowRate => at_point(&|k, x| {
            let size = probe.size.as_deref().unwrap_or(&[]);
            interpolate::flow_rate(fields, k, x, probe.axis.min(D - 1), size)
        }),
        ProbeKind::Level => at_point(&|k, x| {
            let axis = probe.axis.min(D - 1);
            let top = space.domain_max.get(axis).copied().unwrap_or(x[axis]);
            interpolate::level(fields, k, x, axis, top)
        }),
        ProbeKind::Front => {
            let axis = probe.axis.min(D - 1);
            let front = (0..fields.len())
                .filter(|&i| fields.kind[i] == FLUID)
                .map(|i| f64::from(fields.position[i][axis]))
                .fold(f64::NEG_INFINITY, f64::max);
            front - probe.origin
        }
        ProbeKind::Force => probe
            .solid
            .and_then(|k| solid_forces.get(k))
            .map_or(0.0, |f| f[probe.axis.min(2)]),
        ProbeKind::Moment => {
            let load = probe
                .solid
                .and_then(|k| Some((solid_forces.get(k)?, solid_moments.get(k)?)));
            match (load, probe.point.as_deref()) {
                (Some((f, m)), Some(point)) => {
                    let load = [f[0], f[1], f[2], m[0], m[1], m[2]];
                    moment_about(&load, point)[probe.axis.min(2)]
                }
                _ => f64::NAN,
            }
        }
    }
}

/// The column of `probe` in `probes.csv` of a `dimension`-D run: `<name>_m` for a front,
/// `<name>_N` for a force (`<name>_N_per_m` in 2D: per metre of depth), `<name>_Pa` for a
/// pressure, `<name>_m` for a level, `<name>_m_per_s` for a velocity, `<name>_m2_per_s` (2D)
/// or `<name>_m3_per_s` for a flow rate, `<name>_N_m` for a moment (`<name>_N_m_per_m` in 2D), as
/// [`crate::output::csv`]'s convention has it.
pub fn column_name(probe: &Probe, dimension: usize) -> String {
    match probe.kind {
        ProbeKind::Front | ProbeKind::Level => format!("{}_m", probe.name),
        ProbeKind::Force => format!("{}_{}", probe.name, force_unit(dimension)),
        ProbeKind::Pressure => format!("{}_Pa", probe.name),
        ProbeKind::Velocity => format!("{}_m_per_s", probe.name),
        ProbeKind::FlowRate if dimension == 2 => format!("{}_m2_per_s", probe.name),
        ProbeKind::FlowRate => format!("{}_m3_per_s", probe.name),
        ProbeKind::Moment => format!("{}_{}", probe.name, moment_unit(dimension)),
    }
}

/// The unit suffix of moment columns in a `dimension`-D run: `N_m`, or `N_m_per_m` in 2D (per
/// metre of depth, as [`force_unit`]).
pub fn moment_unit(dimension: usize) -> &'static str {
    if dimension == 2 { "N_m_per_m" } else { "N_m" }
}

/// Samples of every probe of a scene, and the `probes.csv` they are written to.
pub struct ProbeLog {
    probes: Vec<Probe>,
    space: ProbeSpace,
    /// `(t [s], value)` per probe.
    samples: Vec<Vec<(f64, f64)>>,
    table: Option<CsvTable>,
    interval: f64,
    next: f64,
    /// Per probe: `Σ value · dt` and `Σ dt` since the last sample ([`Averaging::Interval`]).
    running: Vec<(f64, f64)>,
    /// Per probe: the steps `(t_start, t_end, value)` within its window
    /// ([`Averaging::Window`]).
    windows: Vec<Vec<(f64, f64, f64)>>,
}

/// What a [`ProbeLog`] has recorded, kept with a checkpoint.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ProbeState {
    /// `(t [s], value)` per probe.
    pub samples: Vec<Vec<(f64, f64)>>,
    /// Time of the next sample [s].
    pub next: f64,
    /// Per probe: `Σ value · dt` and `Σ dt` since the last sample.
    pub running: Vec<(f64, f64)>,
    /// Per probe: the steps `(t_start, t_end, value)` within its sampling window.
    #[serde(default)]
    pub windows: Vec<Vec<(f64, f64, f64)>>,
    /// Length of `probes.csv` [bytes], when written.
    pub table_len: Option<u64>,
}

impl ProbeLog {
    /// A log for `scene`'s probes, sampled every `interval` [s]; writes `probes.csv` in `dir`
    /// when given (columns `t_s` and one [`column_name`] per probe).
    pub fn create(scene: &Scene, dir: Option<&Path>, interval: f64) -> Result<Self, OutputError> {
        Self::open(scene, dir, interval, None)
    }

    /// The log as it was at a checkpoint: its samples, and `probes.csv` cut back to its length
    /// then.
    pub fn resume(
        scene: &Scene,
        dir: Option<&Path>,
        interval: f64,
        state: ProbeState,
    ) -> Result<Self, OutputError> {
        let mut log = Self::open(scene, dir, interval, state.table_len)?;
        if state.samples.len() != log.probes.len() || state.running.len() != log.probes.len() {
            return Err(OutputError::malformed(
                &dir.map_or_else(PathBuf::new, |d| d.join("checkpoint.bin")),
                "its probes are not this scene's",
            ));
        }
        log.samples = state.samples;
        log.running = state.running;
        if state.windows.len() == log.probes.len() {
            log.windows = state.windows;
        }
        log.next = state.next;
        Ok(log)
    }

    /// What the log has recorded (flushing `probes.csv` to learn its length).
    pub fn state(&mut self) -> Result<ProbeState, OutputError> {
        let table_len = match self.table.as_mut() {
            Some(t) => Some(t.len_on_disk()?),
            None => None,
        };
        Ok(ProbeState {
            samples: self.samples.clone(),
            next: self.next,
            running: self.running.clone(),
            windows: self.windows.clone(),
            table_len,
        })
    }

    fn open(
        scene: &Scene,
        dir: Option<&Path>,
        interval: f64,
        resume_len: Option<u64>,
    ) -> Result<Self, OutputError> {
        let probes = scene.probes.clone();
        let table = match dir {
            Some(dir) if !probes.is_empty() => {
                let mut columns = vec!["t_s".to_string()];
                columns.extend(probes.iter().map(|p| column_name(p, scene.dimension)));
                let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
                let path = dir.join("probes.csv");
                Some(match resume_len {
                    Some(len) => CsvTable::resume(&path, &columns, len)?,
                    None => CsvTable::create(&path, &columns)?,
                })
            }
            _ => None,
        };
        Ok(Self {
            space: ProbeSpace::of(scene),
            samples: vec![Vec::new(); probes.len()],
            running: vec![(0.0, 0.0); probes.len()],
            windows: vec![Vec::new(); probes.len()],
            probes,
            table,
            interval,
            next: 0.0,
        })
    }

    /// Whether [`ProbeLog::record`] at time `t` [s] reads particle fields (a probe other than
    /// a force or moment is due, or averages over a window and so reads every step), so a
    /// device-resident backend must copy them to the host first.
    pub fn wants_fields(&self, t: f64, now: bool) -> bool {
        let due = t >= self.next || now;
        self.probes
            .iter()
            .any(|p| !p.kind.reads_solids() && (due || matches!(p.averaging, Averaging::Window(_))))
    }

    /// The sampling interval [s]: `output.interval / 10`, shortened to the shortest
    /// `1/sampling_rate` of the scene's probes, so a transducer's rate is at least met (every
    /// step when its window is shorter than the time step).
    pub fn interval_for(scene: &Scene) -> f64 {
        scene
            .probes
            .iter()
            .filter_map(|p| match p.averaging {
                Averaging::Window(w) => Some(w),
                _ => None,
            })
            .fold(scene.output_interval / 10.0, f64::min)
    }

    /// Called after every step of length `dt` [s] ending at `t` [s]: records the probes if a
    /// sample is due (or `now`), each as its [`Averaging`] says. Without the solids' moments a
    /// moment probe records NaN: [`ProbeLog::record_loads`] takes them.
    pub fn record<const D: usize>(
        &mut self,
        t: f64,
        dt: f64,
        fields: &Fields<D>,
        solid_forces: &[[f64; 3]],
        now: bool,
    ) -> Result<(), OutputError> {
        self.record_loads(t, dt, fields, solid_forces, &[], now)
    }

    /// [`ProbeLog::record`], with the moments about the origin of the forces on the solids
    /// [N m] ([`measure_loads`]).
    pub fn record_loads<const D: usize>(
        &mut self,
        t: f64,
        dt: f64,
        fields: &Fields<D>,
        solid_forces: &[[f64; 3]],
        solid_moments: &[[f64; 3]],
        now: bool,
    ) -> Result<(), OutputError> {
        if self.probes.is_empty() {
            return Ok(());
        }
        for ((p, run), window) in self.probes.iter().zip(&mut self.running).zip(&mut self.windows) {
            if dt <= 0.0 {
                continue;
            }
            match p.averaging {
                Averaging::Instant => {}
                Averaging::Interval => {
                    run.0 += measure_loads(p, &self.space, fields, solid_forces, solid_moments) * dt;
                    run.1 += dt;
                }
                Averaging::Window(width) => {
                    window.push((
                        t - dt,
                        t,
                        measure_loads(p, &self.space, fields, solid_forces, solid_moments),
                    ));
                    window.retain(|&(_, end, _)| end > t - width);
                }
            }
        }
        if t < self.next && !now {
            return Ok(());
        }
        while self.next <= t {
            self.next += self.interval;
        }
        let values: Vec<f64> = self
            .probes
            .iter()
            .zip(self.running.iter_mut())
            .zip(&self.windows)
            .map(|((p, run), window)| {
                let averaged = match p.averaging {
                    Averaging::Interval if run.1 > 0.0 => Some(run.0 / run.1),
                    Averaging::Window(width) => window_mean(window, t, width),
                    _ => None,
                };
                *run = (0.0, 0.0);
                averaged.unwrap_or_else(|| measure_loads(p, &self.space, fields, solid_forces, solid_moments))
            })
            .collect();
        for (s, v) in self.samples.iter_mut().zip(&values) {
            s.push((t, *v));
        }
        if let Some(table) = self.table.as_mut() {
            let mut row = vec![CsvValue::from(t)];
            row.extend(values.iter().map(|&v| CsvValue::from(v)));
            table.push_row(&row)?;
            table.flush()?;
        }
        Ok(())
    }

    /// The samples of probe `k`: `(t [s], value)`.
    pub fn samples(&self, k: usize) -> &[(f64, f64)] {
        &self.samples[k]
    }

    /// The probes.
    pub fn probes(&self) -> &[Probe] {
        &self.probes
    }
}

/// The time-weighted mean at `t` [s] of the per-step values `(t_start, t_end, value)` over the
/// window `[t − width, t]`: each step counts for the part of it inside the window (a
/// transducer of rate `1/width` [Hz] reads the signal's mean over its window). `None` when no
/// step overlaps the window.
pub fn window_mean(steps: &[(f64, f64, f64)], t: f64, width: f64) -> Option<f64> {
    let start = t - width;
    let (sum, weight) = steps.iter().fold((0.0, 0.0), |(sum, weight), &(t0, t1, v)| {
        let overlap = (t1.min(t) - t0.max(start)).max(0.0);
        (sum + v * overlap, weight + overlap)
    });
    (weight > 0.0).then(|| sum / weight)
}
