//! Whether this machine can hold a scene at all: its memory and swap (`/proc/meminfo`)
//! against the bytes each ellipsoid surely takes, checked before a generated scene is made.

use crate::error::{Error, Result};
use ellipsoid_splat::{Ellipsoid, InstanceFormat};

/// Host bytes each ellipsoid surely takes while a scene is uploaded: its record in the scene
/// plus its packed instance. Real use is higher (a staging copy, the culling list, the
/// driver), so a scene refused for this is certainly too large.
pub fn host_bytes_per_ellipsoid(format: InstanceFormat) -> u64 {
    (std::mem::size_of::<Ellipsoid>() + format.bytes()) as u64
}

/// This machine's memory plus swap in bytes (`/proc/meminfo`), a fixed figure rather than
/// what happens to be free; `None` where it cannot be read.
pub fn machine_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib = |key: &str| {
        text.lines().find_map(|line| {
            line.strip_prefix(key)?
                .trim()
                .strip_suffix("kB")?
                .trim()
                .parse::<u64>()
                .ok()
        })
    };
    Some((kib("MemTotal:")? + kib("SwapTotal:").unwrap_or(0)) * 1024)
}

/// Refuses `count` ellipsoids in `format` when even [`host_bytes_per_ellipsoid`] of them
/// exceed `memory` bytes (the machine's memory and swap; no check when unknown).
pub fn check_host_memory(
    spec: &str,
    count: u64,
    format: InstanceFormat,
    memory: Option<u64>,
) -> Result<()> {
    let Some(memory) = memory else {
        return Ok(());
    };
    let per = host_bytes_per_ellipsoid(format);
    let needed = count.saturating_mul(per);
    if needed <= memory {
        return Ok(());
    }
    Err(Error::invalid(
        "--scene",
        format!(
            "{spec} needs at least {} of host memory for {count} ellipsoids ({} bytes each for \
             the scene and {} for its packed instance), more than this machine's {} of memory \
             and swap",
            gib(needed),
            std::mem::size_of::<Ellipsoid>(),
            format.bytes(),
            gib(memory)
        ),
    ))
}

/// `bytes` in GiB with one decimal, as the messages give sizes.
pub(crate) fn gib(bytes: u64) -> String {
    format!("{:.1} GiB", bytes as f64 / (1u64 << 30) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn host_memory_estimate_refuses_what_cannot_fit() {
        let per = host_bytes_per_ellipsoid(InstanceFormat::Full);
        assert_eq!(per, 96 + 48);
        let eight_gib = Some(8u64 << 30);
        assert!(check_host_memory("random:1000", 1000, InstanceFormat::Full, eight_gib).is_ok());
        let fits = (8u64 << 30) / per;
        assert!(check_host_memory("x", fits, InstanceFormat::Full, eight_gib).is_ok());
        let e = check_host_memory("random:N", fits + 1, InstanceFormat::Full, eight_gib)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--scene") && e.contains("host memory") && e.contains("8.0 GiB"),
            "{e}"
        );
        // Compact instances take less.
        let compact = (8u64 << 30) / host_bytes_per_ellipsoid(InstanceFormat::Compact);
        assert!(check_host_memory("x", compact, InstanceFormat::Compact, eight_gib).is_ok());
        assert!(check_host_memory("x", u64::MAX, InstanceFormat::Full, None).is_ok());
        assert!(machine_memory().is_none_or(|m| m > 0));
    }
}
