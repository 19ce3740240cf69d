//! The process's resident memory, for reports of what a step costs (`wavetrace info`
//! prints the BVH build's peak). Linux only (`/proc/self`); elsewhere every function
//! answers `None` or `false`.

/// Resident memory now, bytes (`VmRSS`).
pub fn resident() -> Option<u64> {
    status_kib("VmRSS:").map(|k| k * 1024)
}

/// Peak resident memory since the process started or since [`reset_peak`], bytes
/// (`VmHWM`).
pub fn peak() -> Option<u64> {
    status_kib("VmHWM:").map(|k| k * 1024)
}

/// Resets [`peak`] to the present resident memory (writing 5 to
/// `/proc/self/clear_refs`, Linux 4.0 and later); whether it could.
pub fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// How much a step raised the peak above the memory held before it: call
/// [`PeakMeter::start`] before the step and [`PeakMeter::extra`] after.
pub struct PeakMeter {
    base: Option<u64>,
}

impl PeakMeter {
    pub fn start() -> PeakMeter {
        let base = if reset_peak() { resident() } else { None };
        PeakMeter { base }
    }

    /// Bytes above the starting memory at the peak since [`PeakMeter::start`].
    pub fn extra(&self) -> Option<u64> {
        Some(peak()?.saturating_sub(self.base?))
    }
}

fn status_kib(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
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
    fn a_large_allocation_shows_in_the_peak() {
        let meter = PeakMeter::start();
        let Some(before) = meter.extra() else {
            return; // not Linux, or /proc unavailable: nothing to check
        };
        let big = vec![1u8; 64 << 20];
        std::hint::black_box(&big);
        drop(big);
        let after = meter.extra().unwrap();
        // Other tests run in this process at the same time, so only a lower bound holds.
        assert!(after >= before + (32 << 20), "{before} -> {after}");
    }
}
