//! The `failed` status of a run whose memory runs out.
//!
//! Rust ends the process when an allocation fails, so a run that outgrows its memory limit
//! cannot return an error. What it can do is leave the right status behind: while a run
//! writes into a folder, a `summary.json` with status `failed: out of memory …` is kept ready,
//! rendered in advance ([`prepare`]), and the `sph` program's allocator ([`FailureAware`])
//! writes it, with system calls that allocate nothing, when an allocation fails, before Rust
//! prints `memory allocation of N bytes failed` and aborts. A process killed by the kernel's
//! OOM killer (SIGKILL) leaves `running`.

use crate::output::Summary;
use std::alloc::{GlobalAlloc, Layout, System};
use std::ffi::CString;
use std::path::Path;
use std::sync::atomic::{AtomicPtr, AtomicUsize, Ordering};

/// A summary ready to be written without allocating.
struct Prepared {
    /// The summary's path and a temporary name beside it.
    path: CString,
    tmp: CString,
    /// The JSON text.
    bytes: Vec<u8>,
}

/// The summary to write if an allocation fails (null: none; set by [`prepare`]).
static PREPARED: AtomicPtr<Prepared> = AtomicPtr::new(std::ptr::null_mut());

/// Keeps `summary` (its status replaced) ready to be written to `path` if memory runs out.
/// Each call leaks the previous copy (a few kilobytes per run): freeing it could race an
/// allocation failure reading it on another thread.
pub fn prepare(path: &Path, summary: &Summary) {
    let mut failed = summary.clone();
    failed.status = "failed: out of memory: an allocation failed during the run (sph check prints the memory a scene needs and the limit it is held to)".into();
    let (Ok(bytes), Some(name)) = (serde_json::to_vec_pretty(&failed), path.file_name()) else {
        return;
    };
    let tmp = path.with_file_name(format!(".{}.out-of-memory.tmp", name.to_string_lossy()));
    let (Ok(path), Ok(tmp)) = (
        CString::new(path.as_os_str().as_encoded_bytes()),
        CString::new(tmp.as_os_str().as_encoded_bytes()),
    ) else {
        return;
    };
    let prepared = Box::into_raw(Box::new(Prepared { path, tmp, bytes }));
    PREPARED.store(prepared, Ordering::SeqCst);
}

/// Requests larger than this many bytes fail while a summary is prepared (fault injection for
/// the tests; `usize::MAX`, never, unless set by [`fail_allocations_above`]).
static FAIL_ABOVE: AtomicUsize = AtomicUsize::new(usize::MAX);

/// The environment variable that makes the `sph` program's allocations larger than its value
/// (in bytes) fail once a run writes into its folder, so that tests reach the out-of-memory
/// path at will (glibc reuses freed memory, so lowering `RLIMIT_AS` under a running process
/// does not make it fail at a predictable point).
pub const FAIL_ALLOCATIONS_ABOVE_VAR: &str = "SPH_TEST_FAIL_ALLOCATIONS_ABOVE";

/// Makes allocations larger than `bytes` fail while a summary is prepared (see
/// [`FAIL_ALLOCATIONS_ABOVE_VAR`]).
pub fn fail_allocations_above(bytes: usize) {
    FAIL_ABOVE.store(bytes, Ordering::SeqCst);
}

/// Whether a request of `size` bytes is to fail (fault injection; see [`FAIL_ABOVE`]).
fn injected_failure(size: usize) -> bool {
    size > FAIL_ABOVE.load(Ordering::Relaxed) && !PREPARED.load(Ordering::Relaxed).is_null()
}

/// Nothing to write any more (the run has ended and written its own status).
pub fn clear() {
    PREPARED.store(std::ptr::null_mut(), Ordering::SeqCst);
}

/// Writes the prepared summary, once; allocates nothing.
fn write_prepared() {
    let prepared = PREPARED.swap(std::ptr::null_mut(), Ordering::SeqCst);
    if prepared.is_null() {
        return;
    }
    // SAFETY: a pointer stored by `prepare` comes from `Box::into_raw` and is never freed.
    let p = unsafe { &*prepared };
    #[cfg(unix)]
    // SAFETY: the C strings are NUL-terminated and live for the process; the buffer is
    // `bytes.len()` long. The file is created without following a link.
    unsafe {
        let fd = libc::open(
            p.tmp.as_ptr(),
            libc::O_WRONLY | libc::O_CREAT | libc::O_TRUNC | libc::O_NOFOLLOW,
            0o644,
        );
        if fd < 0 {
            return;
        }
        let mut written = 0;
        while written < p.bytes.len() {
            let n = libc::write(fd, p.bytes[written..].as_ptr().cast(), p.bytes.len() - written);
            if n <= 0 {
                break;
            }
            written += n as usize;
        }
        libc::close(fd);
        if written == p.bytes.len() {
            libc::rename(p.tmp.as_ptr(), p.path.as_ptr());
        }
    }
    #[cfg(not(unix))]
    let _ = p;
}

/// The system allocator, which writes the prepared `failed` summary when an allocation fails
/// (the `sph` program's global allocator).
pub struct FailureAware;

// SAFETY: every call is forwarded to `System`; on failure only `write_prepared` runs, which
// allocates nothing.
unsafe impl GlobalAlloc for FailureAware {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if injected_failure(layout.size()) {
            write_prepared();
            return std::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            write_prepared();
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if injected_failure(layout.size()) {
            write_prepared();
            return std::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            write_prepared();
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded with the caller's guarantees.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if injected_failure(new_size) {
            write_prepared();
            return std::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's guarantees.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            write_prepared();
        }
        p
    }
}
