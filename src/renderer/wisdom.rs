//! What the plan learned, as bytes a host saves and loads (FFTW's "wisdom"), keyed like
//! `VkPipelineCache` data by the device and its driver build: a choice measured on one
//! device says nothing of another.
//!
//! Layout (little-endian): the magic `ESWISDOM`, the format version (u32), the vendor ID,
//! device ID and driver version (u32 each), the pipeline-cache UUID (16 bytes), the entry
//! count (u32), then per entry the scene class (8 bytes), the chosen kind (u32: 0 draw, 1
//! splat, 2 visible-first) and each kind's median frame time in milliseconds (3 x f32, NaN
//! where not timed); last, an FNV-1a hash of everything before it (u64).
//!
//! **Wisdom** (`src/renderer/wisdom.rs`): `plan_wisdom()` writes the settled classes -- class,
//! choice, each candidate's median -- after a header naming the device's vendor and device IDs,
//! driver version and pipeline-cache UUID (the key `VkPipelineCache` data is checked against),
//! with an FNV-1a checksum; `load_plan_wisdom` refuses bytes of another device or driver build,
//! another format version, or damaged ones, naming which, and changes nothing then.

use crate::error::{Error, Result};
use crate::path::PathKind;
use crate::target::DeviceIdentity;

use super::learning::{PlanLearning, SceneClass};

const MAGIC: &[u8; 8] = b"ESWISDOM";
/// 2: moving cameras gained the visible-first splat as a candidate and the splat its
/// per-pixel skip (2026-11-27), so classes learned before are timed again.
const VERSION: u32 = 2;
const HEADER: usize = 8 + 4 + 12 + 16 + 4;
const ENTRY: usize = 8 + 4 + 12;

/// `learning`'s settled classes as bytes for `identity`.
pub(crate) fn export(learning: &PlanLearning, identity: &DeviceIdentity) -> Vec<u8> {
    let settled = learning.settled();
    let mut bytes = Vec::with_capacity(HEADER + ENTRY * settled.len() + 8);
    bytes.extend_from_slice(MAGIC);
    for word in [
        VERSION,
        identity.vendor_id,
        identity.device_id,
        identity.driver_version,
    ] {
        bytes.extend_from_slice(&word.to_le_bytes());
    }
    bytes.extend_from_slice(&identity.pipeline_cache_uuid);
    bytes.extend_from_slice(&(settled.len() as u32).to_le_bytes());
    for (class, best, medians) in settled {
        bytes.extend_from_slice(&class.to_bytes());
        bytes.extend_from_slice(&(best.index() as u32).to_le_bytes());
        for ms in medians {
            bytes.extend_from_slice(&(ms as f32).to_le_bytes());
        }
    }
    let hash = fnv1a(&bytes);
    bytes.extend_from_slice(&hash.to_le_bytes());
    bytes
}

/// The settled classes of `bytes`, made by [`export`] for `identity`; an error names what
/// does not fit (another device or driver build, another format, damaged bytes).
pub(crate) fn import(
    bytes: &[u8],
    identity: &DeviceIdentity,
) -> Result<Vec<(SceneClass, PathKind, [f64; 3])>> {
    let invalid = |why: String| Err(Error::invalid("plan wisdom", why));
    if bytes.len() < HEADER + 8 || &bytes[..8] != MAGIC {
        return invalid(format!(
            "{} bytes that are not learned plans (no `ESWISDOM` header)",
            bytes.len()
        ));
    }
    let (body, hash) = bytes.split_at(bytes.len() - 8);
    if fnv1a(body).to_le_bytes() != hash {
        return invalid("damaged: the bytes do not match their checksum".into());
    }
    let word = |at: usize| u32::from_le_bytes(body[at..at + 4].try_into().expect("4 bytes"));
    let version = word(8);
    if version != VERSION {
        return invalid(format!(
            "format version {version}; this library reads version {VERSION}"
        ));
    }
    let theirs = DeviceIdentity {
        vendor_id: word(12),
        device_id: word(16),
        driver_version: word(20),
        pipeline_cache_uuid: body[24..40].try_into().expect("16 bytes"),
    };
    if theirs != *identity {
        return invalid(format!(
            "learned on {}, but this renderer's device is {}: what is fastest on one device \
             or driver build says nothing of another",
            describe(&theirs),
            describe(identity)
        ));
    }
    let count = word(40) as usize;
    if body.len() != HEADER + ENTRY * count {
        return invalid(format!(
            "{count} entries need {} bytes, not {}",
            HEADER + ENTRY * count + 8,
            bytes.len()
        ));
    }
    (0..count)
        .map(|k| {
            let at = HEADER + ENTRY * k;
            let class = SceneClass::from_bytes(body[at..at + 8].try_into().expect("8 bytes"));
            let kind = PathKind::ALL.get(word(at + 8) as usize).copied();
            let ms = |j: usize| {
                let at = at + 12 + 4 * j;
                f32::from_le_bytes(body[at..at + 4].try_into().expect("4 bytes")) as f64
            };
            match (class, kind) {
                (Some(class), Some(kind)) => Ok((class, kind, [ms(0), ms(1), ms(2)])),
                _ => Err(Error::invalid(
                    "plan wisdom",
                    format!("entry {k} names no scene class or path"),
                )),
            }
        })
        .collect()
}

/// A device identity as a person reads it.
fn describe(identity: &DeviceIdentity) -> String {
    let uuid: String = identity
        .pipeline_cache_uuid
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    format!(
        "vendor {:#06x} device {:#06x} driver version {:#x} (pipeline cache {uuid})",
        identity.vendor_id, identity.device_id, identity.driver_version
    )
}

/// 64-bit FNV-1a.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &b| {
        (hash ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn identity(driver_version: u32) -> DeviceIdentity {
        DeviceIdentity {
            vendor_id: 0x10de,
            device_id: 0x2335,
            driver_version,
            pipeline_cache_uuid: [7; 16],
        }
    }

    #[test]
    fn learned_choices_round_trip_and_are_refused_elsewhere() {
        let mut learning = PlanLearning::default();
        let class = SceneClass::new(8000, 380.0, 4.3, 1920 * 1080, 1, false);
        learning.insert_settled(class, PathKind::Splat, [61.0, 35.0, f64::NAN]);
        let bytes = export(&learning, &identity(1));
        let back = import(&bytes, &identity(1)).unwrap();
        assert_eq!(back.len(), 1);
        assert_eq!((back[0].0, back[0].1), (class, PathKind::Splat));
        assert_eq!(back[0].2[..2], [61.0, 35.0]);
        assert!(back[0].2[2].is_nan());

        let other = import(&bytes, &identity(2)).unwrap_err().to_string();
        assert!(other.contains("driver version 0x1"), "{other}");
        let mut damaged = bytes.clone();
        damaged[HEADER + 2] ^= 1;
        let damaged = import(&damaged, &identity(1)).unwrap_err().to_string();
        assert!(damaged.contains("checksum"), "{damaged}");
        let short = import(&bytes[..10], &identity(1)).unwrap_err().to_string();
        assert!(short.contains("not learned plans"), "{short}");
    }
}
