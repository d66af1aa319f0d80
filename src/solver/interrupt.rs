//! A stop request acted on inside a step: the run's stop flag (set by SIGINT or SIGTERM,
//! `cli::signals`) is polled after every step, and also by the loops a step may spend long in
//! (each sweep of the position correction and of the velocity solve). Inside a step the request
//! waits a grace time first, so that an ordinary step ends and the run stops after it with a
//! checkpoint; a step still running after the grace time is abandoned, and the run ends with
//! the state of its last finished step on disk (its last checkpoint, if one was written).

use super::{Simulation, StepError};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// The shortest grace time [s] a step gets to finish after a stop request.
pub const STOP_GRACE: Duration = Duration::from_secs(5);

/// The stop flag as a step polls it.
#[derive(Debug)]
pub struct Interrupt {
    /// The signal's number, 0 while none came.
    flag: Arc<AtomicUsize>,
    /// How long a step may go on after the request.
    grace: Duration,
    /// When a poll first saw the request.
    seen: Option<Instant>,
}

impl Interrupt {
    /// The signal, once it has been pending for longer than the grace time.
    fn due(&mut self) -> Option<usize> {
        let signal = self.flag.load(Ordering::SeqCst);
        if signal == 0 {
            return None;
        }
        let seen = *self.seen.get_or_insert_with(Instant::now);
        (seen.elapsed() > self.grace).then_some(signal)
    }
}

impl<const D: usize> Simulation<D> {
    /// Lets `flag` (a signal's number, 0 for none) end a step that is still running `grace`
    /// after the flag was set ([`STOP_GRACE`] at least): the step then fails with
    /// [`StepError::Interrupted`]. A run split across ranks does not use it (its ranks agree on
    /// a stop after a step).
    pub fn interrupt_long_steps(&mut self, flag: Arc<AtomicUsize>, grace: Duration) {
        self.interrupt = Some(Interrupt {
            flag,
            grace: grace.max(STOP_GRACE),
            seen: None,
        });
    }

    /// Sets the grace time of [`Simulation::interrupt_long_steps`] (at least [`STOP_GRACE`]),
    /// e.g. from the longest step so far.
    pub fn set_interrupt_grace(&mut self, grace: Duration) {
        if let Some(i) = &mut self.interrupt {
            i.grace = grace.max(STOP_GRACE);
        }
    }

    /// `Err(StepError::Interrupted)` once a stop request has waited longer than the grace time.
    pub(super) fn check_interrupt(&mut self) -> Result<(), StepError> {
        due(&mut self.interrupt, self.clock.step, self.clock.time)
    }
}

/// [`Simulation::check_interrupt`] on the interrupt alone, for loops that hold other fields of
/// the simulation.
pub(super) fn due(interrupt: &mut Option<Interrupt>, step: u64, time: f64) -> Result<(), StepError> {
    match interrupt.as_mut().and_then(Interrupt::due) {
        Some(signal) => Err(StepError::Interrupted {
            step: step + 1,
            time,
            signal,
        }),
        None => Ok(()),
    }
}
