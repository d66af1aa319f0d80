//! The process's resident memory, for `sph bench`'s memory per particle: Linux reports the peak
//! resident set (`VmHWM` in `/proc/self/status`), and writing `5` to `/proc/self/clear_refs`
//! resets that peak to the current resident set, so each benchmark row measures its own peak.
//! Elsewhere both give nothing and the row says so.
//!
//! [`limit`] is the memory a new run may use: the least of the system's `MemAvailable`, the
//! cgroup's `memory.max` less its `memory.current` (containers, batch schedulers) and the
//! address-space limit (`ulimit -v`) less what the process already maps.

use std::fs;

/// The memory a new run may use \[B\] and where that bound comes from (for messages); `None`
/// where none of the sources can be read.
pub fn limit() -> Option<(u64, &'static str)> {
    let mut best: Option<(u64, &'static str)> = None;
    let mut take = |bytes: Option<u64>, what: &'static str| {
        if let Some(b) = bytes
            && best.is_none_or(|(m, _)| b < m)
        {
            best = Some((b, what));
        }
    };
    take(meminfo_kib("MemAvailable:").map(|k| k * 1024), "MemAvailable");
    take(cgroup_free(), "the cgroup's memory.max");
    take(address_space_free(), "ulimit -v");
    best
}

/// Address space each worker thread reserves beyond what it touches \[B\]: glibc's malloc
/// arena of the thread (64 MiB on 64-bit) and its stack (2 MiB). Measured: a run's `VmPeak`
/// grows by 66 MiB per added `--threads` (Xeon 2-core VM, the 3D column, 1, 2 and 4 threads).
pub const ADDRESS_SPACE_PER_THREAD: u64 = 66 << 20;

/// Address space a run maps beyond its resident set and its threads' reservations \[B\]: the
/// program's libraries and the main arena's reservations. Measured `VmPeak` less the peak
/// resident set of the 3D column on one thread: 51 MiB.
pub const ADDRESS_SPACE_BASE: u64 = 52 << 20;

/// The address space \[B\] a run with an estimated peak resident set of `resident` bytes
/// maps with `threads` worker threads, for the `ulimit -v` check of `sph run` (which knows
/// its thread count, unlike `sph check`).
pub fn address_space_need(resident: u64, threads: usize) -> u64 {
    resident
        .saturating_add(ADDRESS_SPACE_BASE)
        .saturating_add(ADDRESS_SPACE_PER_THREAD.saturating_mul(threads as u64))
}

/// The address-space limit (`RLIMIT_AS`, `ulimit -v`) \[B\]; `None` when unlimited.
pub fn address_space_limit() -> Option<u64> {
    #[cfg(unix)]
    {
        let mut limit = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit writes the struct it is given.
        let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } == 0;
        if !ok || limit.rlim_cur == libc::RLIM_INFINITY {
            return None;
        }
        // rlim_t is u64 on Linux, not on every unix.
        #[allow(clippy::unnecessary_cast)]
        Some(limit.rlim_cur as u64)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// `memory.max − memory.current` of this process's cgroup (v2) \[B\]; `None` without a limit.
fn cgroup_free() -> Option<u64> {
    let cgroup = fs::read_to_string("/proc/self/cgroup").ok()?;
    // cgroup v2: the line `0::/path`.
    let path = cgroup.lines().find_map(|l| l.strip_prefix("0::"))?.trim();
    let dir = std::path::Path::new("/sys/fs/cgroup").join(path.trim_start_matches('/'));
    let max: u64 = fs::read_to_string(dir.join("memory.max"))
        .ok()?
        .trim()
        .parse()
        .ok()?;
    let current: u64 = fs::read_to_string(dir.join("memory.current"))
        .ok()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(0);
    Some(max.saturating_sub(current))
}

/// The address-space limit (`RLIMIT_AS`, `ulimit -v`) less the process's mapped size \[B\].
fn address_space_free() -> Option<u64> {
    let mapped = status_kib("VmSize:").unwrap_or(0) * 1024;
    Some(address_space_limit()?.saturating_sub(mapped))
}

/// The value \[kB\] of line `key` of `/proc/meminfo`.
fn meminfo_kib(key: &str) -> Option<u64> {
    proc_kib("/proc/meminfo", key)
}

/// The value \[kB\] of the line starting with `key` (`"Name:"`) of the `/proc` file `path`.
fn proc_kib(path: &str, key: &str) -> Option<u64> {
    let text = fs::read_to_string(path).ok()?;
    let line = text.lines().find(|l| l.starts_with(key))?;
    line[key.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()
}

/// Peak resident set of this process since start or the last [`reset_peak_resident`] [B].
pub fn peak_resident_bytes() -> Option<u64> {
    status_kib("VmHWM:").map(|kib| kib * 1024)
}

/// Current resident set of this process [B].
pub fn resident_bytes() -> Option<u64> {
    status_kib("VmRSS:").map(|kib| kib * 1024)
}

/// Resets the peak resident set to the current one; false where the system cannot.
pub fn reset_peak_resident() -> bool {
    fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// The value [kB] of line `key` of `/proc/self/status`.
fn status_kib(key: &str) -> Option<u64> {
    proc_kib("/proc/self/status", key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_follows_a_large_allocation_and_resets() {
        if peak_resident_bytes().is_none() {
            // Not Linux: nothing to check, and the bench prints no figure.
            assert!(resident_bytes().is_none());
            return;
        }
        let before = resident_bytes().expect("VmRSS next to VmHWM");
        let block = vec![1u8; 256 << 20];
        std::hint::black_box(&block);
        let peak = peak_resident_bytes().expect("read");
        assert!(
            peak >= before + (250 << 20),
            "peak {peak} vs {before} before a 256 MiB block"
        );
        drop(block);
        if reset_peak_resident() {
            let after = peak_resident_bytes().expect("read");
            assert!(after < peak, "reset peak {after} still at {peak}");
        }
    }
}
