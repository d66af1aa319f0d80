//! Open boundaries in the run (`boundary::open`): set up by [`Simulation::with_open_boundaries`],
//! updated once a step at its start on the host, like the removal of escaped particles
//! (`solver::escape`): the fields are synced from the backend, [`crate::boundary::open::update`]
//! removes, sets and creates buffer particles, and the backend is built again from the fields
//! on its device (`Backend::reload`). Created particles and those removed past an outflow are
//! counted in the step's report, the run's statistics, `steps.csv` and `summary.json`
//! (`created_particles`, `outflow_particles`). A checkpoint then holds particles the scene did not have;
//! restoring it accepts fluid particles of ids above the scene's.
//!
//! Split across ranks, each rank updates its own particles; each column's rear, the largest id
//! and the counts are reduced over the ranks, every rank computes the same created particles
//! and keeps those its region holds (`boundary::open::update_share`), and every rank rebuilds
//! its backend when any rank's particles changed (the next sort then rebuilds the halo).

use super::{SetupError, Simulation, StepError};
use crate::backend::Backend;
use crate::boundary::open::{OpenBoundary, Share, Template, Update, update_share};
use crate::distributed::Decomposition;
use crate::math::{Real, Vector};
use crate::physics::lattice::lattice_mass;
use crate::smoothing::Smoothing;

/// A run's open boundaries and what their created particles start from.
#[derive(Clone, Debug, PartialEq)]
pub struct OpenBoundaries<const D: usize> {
    /// The boundaries, in scene order.
    pub boundaries: Vec<OpenBoundary<D>>,
    /// Spacing, lattice mass and `ρ0` of a created particle.
    pub template: Template,
}

impl<const D: usize> Simulation<D> {
    /// Adds open boundaries (`[[open_boundary]]`, `boundary::open`); none: a no-op. Call before
    /// the first step.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] for the `corrected` solver (its position correction would move
    /// the buffer particles whose positions the buffer's columns follow), or the `multiphase`
    /// effect (a created particle has no phase).
    pub fn with_open_boundaries(mut self, boundaries: Vec<OpenBoundary<D>>) -> Result<Self, SetupError> {
        if boundaries.is_empty() {
            return Ok(self);
        }
        let invalid = |reason: &str| SetupError::Invalid {
            key: "open_boundary",
            reason: reason.into(),
        };
        if self.config.correction.is_some() {
            return Err(invalid("needs solver.kind = \"wcsph\""));
        }
        if self.multiphase() {
            return Err(invalid("cannot be combined with the multiphase effect"));
        }
        let c = &self.config;
        let kernel = Smoothing::<D>::new(c.h as Real)?;
        let template = Template {
            spacing: c.spacing as Real,
            mass: lattice_mass(&kernel, c.spacing, c.rho0) as Real,
            rho0: c.rho0 as Real,
        };
        self.open = Some(OpenBoundaries { boundaries, template });
        Ok(self)
    }

    /// The run's open boundaries, if any.
    pub fn open_boundaries(&self) -> Option<&OpenBoundaries<D>> {
        self.open.as_ref()
    }

    /// The open boundaries' update at the step's start (module doc); what it did.
    pub(super) fn update_open_boundaries(&mut self) -> Result<Update, StepError> {
        if self.open.is_none() {
            return Ok(Update::default());
        }
        let step = self.clock.step;
        let backend = |source| StepError::Backend { step, source };
        self.sync_fields().map_err(backend)?;
        let Some(open) = &self.open else {
            return Ok(Update::default());
        };
        let region = self.backend.decomposition().zip(self.backend.partition().rank());
        let mut share = BackendShare {
            backend: self.backend.as_mut(),
            region,
        };
        let done = update_share(
            &mut self.fields,
            &open.boundaries,
            &open.template,
            self.clock.time,
            &mut share,
        );
        self.stats.created_particles += done.created;
        self.stats.outflow_particles += done.removed;
        // A device holds its own copy, whose buffer velocities are now stale even where the
        // count did not change; the CPU works on `fields` and needs new buffers only for a new
        // count (over all ranks: each rank's next sort is then a collective halo rebuild).
        if self.backend.holds_state() || done.created + done.removed > 0 {
            self.reload_backend().map_err(backend)?;
        }
        Ok(done)
    }
}

/// The simulation's backend as the open boundaries' [`Share`]: its owned particles, the region
/// its rank holds (`None`: the whole simulation) and its reductions over ranks.
struct BackendShare<'a, const D: usize> {
    backend: &'a mut (dyn Backend<D> + Send),
    region: Option<(Decomposition<D>, usize)>,
}

impl<const D: usize> Share<D> for BackendShare<'_, D> {
    fn counts(&self, i: usize) -> bool {
        self.backend.partition().counts(i)
    }
    fn owns(&self, x: &Vector<D>) -> bool {
        self.region
            .as_ref()
            .is_none_or(|(decomposition, rank)| decomposition.owner(x) == *rank)
    }
    fn max(&mut self, values: &mut [f64]) {
        self.backend.max_over_ranks(values);
    }
    fn sum(&mut self, values: &mut [f64]) {
        self.backend.sum_over_ranks(values);
    }
}
