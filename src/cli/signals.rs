//! SIGINT (Ctrl-C) and SIGTERM end a run after its current step: the run writes a checkpoint
//! and the `interrupted` status and `sph` exits with 128 + the signal's number (130, 143). A
//! step still running a grace time after the signal is abandoned (`solver::interrupt`). A
//! second signal ends the process with that status once the hook [`on_second_signal`] set
//! (the run's: `summary.json` says `interrupted`) has run, from a thread of its own: the
//! handlers themselves only set atomics. A third ends it at once.
//!
//! SIGXFSZ (a write past `ulimit -f`) is ignored, so that the write fails with an error the run
//! reports (status `failed` naming the file) instead of the signal ending the process.

use std::sync::atomic::AtomicUsize;
use std::sync::{Arc, Mutex, OnceLock};

/// What the second signal does before the process ends (its argument: the signal's number).
type Hook = Box<dyn Fn(usize) + Send>;

/// The hook [`on_second_signal`] set.
static LAST_WORDS: Mutex<Option<Hook>> = Mutex::new(None);

/// Sets what a second SIGINT or SIGTERM does before it ends the process (replacing any hook set
/// before): it runs on the signal thread, so it may write files.
pub fn on_second_signal(hook: impl Fn(usize) + Send + 'static) {
    if let Ok(mut h) = LAST_WORDS.lock() {
        *h = Some(Box::new(hook));
    }
}

/// The flag the handlers set to the signal's number (0: none yet), installed once.
static STOP: OnceLock<Option<Arc<AtomicUsize>>> = OnceLock::new();

/// Installs the handlers (first call) and returns the flag a run polls after each step; `None`
/// where signals cannot be handled (the run then ends as the platform ends it).
pub fn stop_flag() -> Option<Arc<AtomicUsize>> {
    STOP.get_or_init(install).clone()
}

#[cfg(unix)]
fn install() -> Option<Arc<AtomicUsize>> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use signal_hook::flag;
    use std::sync::atomic::AtomicBool;
    // SAFETY: setting a signal's action to "ignore" installs no handler code.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let stop = Arc::new(AtomicUsize::new(0));
    // Set by the signal thread at the second signal: a third one ends the process at once.
    let armed = Arc::new(AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM] {
        let installed = flag::register_conditional_shutdown(signal, 128 + signal, armed.clone())
            .and_then(|_| flag::register_usize(signal, stop.clone(), signal as usize));
        if let Err(e) = installed {
            eprintln!(
                "warning: cannot handle signal {signal} ({e}); it will end the run without a checkpoint"
            );
            return None;
        }
    }
    match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
        Ok(mut signals) => {
            std::thread::spawn(move || {
                for (count, signal) in signals.forever().enumerate() {
                    if count == 0 {
                        continue; // the stop flag acts on the first
                    }
                    armed.store(true, std::sync::atomic::Ordering::SeqCst);
                    if let Ok(hook) = LAST_WORDS.lock()
                        && let Some(hook) = hook.as_ref()
                    {
                        hook(signal as usize);
                    }
                    std::process::exit(128 + signal);
                }
            });
        }
        Err(e) => {
            // Without the thread a second signal ends the process at once.
            armed.store(true, std::sync::atomic::Ordering::SeqCst);
            eprintln!("warning: cannot watch for a second signal ({e}); it will end the process at once");
        }
    }
    Some(stop)
}

#[cfg(not(unix))]
fn install() -> Option<Arc<AtomicUsize>> {
    None
}

/// The process exit status for the error `sph` ends with: 128 + the signal's number for a run
/// ended by a signal, 1 otherwise.
pub fn exit_status(error: &anyhow::Error) -> i32 {
    error
        .chain()
        .find_map(|cause| {
            match (
                cause.downcast_ref::<crate::Error>(),
                cause.downcast_ref::<crate::sweep::SweepError>(),
            ) {
                (Some(crate::Error::Interrupted { signal, .. }), _)
                | (_, Some(crate::sweep::SweepError::Interrupted { signal })) => Some(128 + *signal as i32),
                _ => None,
            }
        })
        .unwrap_or(1)
}

/// Marks the run whose `summary.json` is at `path` as ended by `signal` where it still says
/// `running` (the second signal's hook of `sph run`), rewritten by `output::write_summary`; left
/// as it is if it cannot be read.
pub fn mark_interrupted(path: &std::path::Path, signal: usize) {
    let Ok(mut summary) = crate::output::read_summary(path) else {
        return;
    };
    if summary.status == "running" {
        summary.status =
            format!("interrupted (signal {signal}): a second signal ended the process inside a step");
        let _ = crate::output::write_summary(path, &summary);
    }
}
