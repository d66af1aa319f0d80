//! The process's resident memory, for `sph bench`'s memory per particle: Linux reports the peak
//! resident set (`VmHWM` in `/proc/self/status`), and writing `5` to `/proc/self/clear_refs`
//! resets that peak to the current resident set, so each benchmark row measures its own peak.
//! Elsewhere both give nothing and the row says so.

use std::fs;

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
    let status = fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    line[key.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()
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
