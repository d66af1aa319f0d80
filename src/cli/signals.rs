//! SIGINT (Ctrl-C) and SIGTERM end a run after its current step: the run writes a checkpoint
//! and the `interrupted` status and `sph` exits with 128 + the signal's number (130, 143). A
//! second signal ends the process at once with that status.
//!
//! SIGXFSZ (a write past `ulimit -f`) is ignored, so that the write fails with an error the run
//! reports (status `failed` naming the file) instead of the signal ending the process.

use std::sync::atomic::AtomicUsize;
use std::sync::{Arc, OnceLock};

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
    let armed = Arc::new(AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM] {
        // Order matters: the shutdown checks the flag the first signal sets (signal-hook docs).
        let installed = flag::register_conditional_shutdown(signal, 128 + signal, armed.clone())
            .and_then(|_| flag::register(signal, armed.clone()))
            .and_then(|_| flag::register_usize(signal, stop.clone(), signal as usize));
        if let Err(e) = installed {
            eprintln!(
                "warning: cannot handle signal {signal} ({e}); it will end the run without a checkpoint"
            );
            return None;
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
                (Some(crate::Error::Interrupted { signal }), _)
                | (_, Some(crate::sweep::SweepError::Interrupted { signal })) => Some(128 + *signal as i32),
                _ => None,
            }
        })
        .unwrap_or(1)
}
