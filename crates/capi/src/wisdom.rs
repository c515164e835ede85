//! What the frame plan learned on a device, as bytes a host saves and hands to a later
//! renderer on the same device and driver build (as it would `VkPipelineCache` data).

use crate::renderer::{with_renderer, EsRenderer};
use crate::status::{output, EsStatus, Failure};

/// The plan's wisdom: for each scene class the renderer settled on, the path it chose and the
/// candidates' median frame times, keyed by the device's vendor and device IDs, driver
/// version and pipeline-cache UUID. Two calls: with `bytes` null it writes the size needed to
/// `size`; then with a buffer of `*size` bytes it writes the bytes and their count. A buffer
/// smaller than needed fails (`ES_STATUS_ERROR_INVALID_ARGUMENT`, the message names the size)
/// and `*size` is set to the size needed. A renderer that settled nothing still gives valid
/// bytes (a header without entries). Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `size` points at a writable `size_t`; a non-null `bytes` points at
/// `*size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_plan_wisdom(
    renderer: *mut EsRenderer,
    bytes: *mut u8,
    size: *mut usize,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_plan_wisdom", |r| {
            let size = output(size, "size")?;
            let wisdom = r.renderer()?.plan_wisdom();
            if bytes.is_null() {
                *size = wisdom.len();
                return Ok(());
            }
            let room = *size;
            *size = wisdom.len();
            if room < wisdom.len() {
                return Err(Failure::invalid(
                    "size",
                    format!(
                        "{room} bytes is too small: the plan wisdom takes {} bytes",
                        wisdom.len()
                    ),
                ));
            }
            // SAFETY: caller contract: `bytes` holds `room >= wisdom.len()` writable bytes,
            // which cannot overlap the library's own vector.
            std::ptr::copy_nonoverlapping(wisdom.as_ptr(), bytes, wisdom.len());
            Ok(())
        })
    }
}

/// Takes in the wisdom of `es_renderer_plan_wisdom` from a renderer on the same device and
/// driver build: the scene classes it settled are then planned as learned, without exploring
/// them again. Bytes from another device, driver build or format, truncated or damaged ones
/// are refused (`ES_STATUS_ERROR_INVALID_ARGUMENT`, the message says which) and change
/// nothing. The bytes are read during the call only. Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; a non-null `bytes` points at `size` readable bytes.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_load_plan_wisdom(
    renderer: *mut EsRenderer,
    bytes: *const u8,
    size: usize,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_load_plan_wisdom", |r| {
            let wisdom: &[u8] = match (bytes.is_null(), size) {
                (_, 0) => &[],
                (true, _) => {
                    return Err(Failure::invalid(
                        "bytes",
                        format!("is null with size {size}"),
                    ))
                }
                // No buffer is that large: a slice of it could not be made.
                (false, n) if n > isize::MAX as usize => {
                    return Err(Failure::invalid(
                        "size",
                        format!("{n} bytes is implausible"),
                    ))
                }
                // SAFETY: caller contract: `size` readable bytes.
                (false, n) => std::slice::from_raw_parts(bytes, n),
            };
            r.renderer()?.load_plan_wisdom(wisdom)?;
            Ok(())
        })
    }
}

/// Writes to `out_can_measure` whether the plan can time its frames on this device (its
/// queue family has timestamps): 1 if so; 0 where `ES_PLAN_MODE_MEASURE` plans as
/// `ES_PLAN_MODE_ESTIMATE` does and no wisdom is learned. Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `out_can_measure` points at a writable `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_can_measure(
    renderer: *mut EsRenderer,
    out_can_measure: *mut u32,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_can_measure", |r| {
            let out = output(out_can_measure, "out_can_measure")?;
            *out = r.renderer()?.can_measure() as u32;
            Ok(())
        })
    }
}
