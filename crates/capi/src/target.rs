//! The pass the ellipsoids are drawn into: a render pass and subpass, or dynamic rendering.

use ash::vk::{self, Format as VkFormat, RenderPass as VkRenderPass};
use ellipsoid_splat::{Pass, Target};

use crate::device::bits_from_features;
use crate::status::{guard, output, versioned, EsStatus, Failure};

/// The pass the renderer draws into.
#[repr(C)]
pub struct EsTargetInfo {
    /// `sizeof(EsTargetInfo)`.
    pub struct_size: u32,
    /// The host's render pass (borrowed), or `VK_NULL_HANDLE` for dynamic rendering.
    pub render_pass: VkRenderPass,
    /// The subpass the renderer draws in (render pass only).
    pub subpass: u32,
    /// The subpass's colour attachments (render pass), or the number of `color_formats`
    /// (dynamic rendering); at least 1. The renderer writes attachment 0 (and 1 and 2 with
    /// `aux_outputs`), and masks the others.
    pub color_attachment_count: u32,
    /// Dynamic rendering: the colour attachments' formats, `color_attachment_count` of them
    /// (ignored for a render pass).
    pub color_formats: *const VkFormat,
    /// The depth attachment's format (the renderer writes exact depth).
    pub depth_format: VkFormat,
    /// Samples per pixel: 1, 2, 4 or 8.
    pub samples: u32,
    /// Non-zero: attachment 1 takes world normals (`R32G32B32A32_SFLOAT`) and attachment 2
    /// instance indices (`R32_UINT`).
    pub aux_outputs: u32,
}

/// The size of the first version of [`EsTargetInfo`] (64-bit targets), frozen.
pub(crate) const TARGET_INFO_V1: usize = 48;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsTargetInfo>() == TARGET_INFO_V1);

/// The library's target of `info`.
///
/// # Safety
/// For dynamic rendering, `info.color_formats` points at `color_attachment_count` formats.
pub(crate) unsafe fn target_from(info: &EsTargetInfo) -> Result<Target, Failure> {
    let count = info.color_attachment_count;
    if count == 0 || count > 8 {
        return Err(Failure::invalid(
            "EsTargetInfo.color_attachment_count",
            format!("{count} is outside 1..=8"),
        ));
    }
    let pass = if info.render_pass != VkRenderPass::null() {
        Pass::RenderPass {
            render_pass: info.render_pass,
            subpass: info.subpass,
            color_attachment_count: count,
            depth_format: info.depth_format,
        }
    } else {
        if info.color_formats.is_null() {
            return Err(Failure::invalid(
                "EsTargetInfo.color_formats",
                "is null for dynamic rendering (render_pass is VK_NULL_HANDLE)",
            ));
        }
        // SAFETY: caller contract: `count` formats.
        let formats = unsafe { std::slice::from_raw_parts(info.color_formats, count as usize) };
        Pass::Dynamic {
            color_formats: formats.to_vec(),
            depth_format: info.depth_format,
        }
    };
    let samples = match info.samples {
        1 => vk::SampleCountFlags::TYPE_1,
        2 => vk::SampleCountFlags::TYPE_2,
        4 => vk::SampleCountFlags::TYPE_4,
        8 => vk::SampleCountFlags::TYPE_8,
        n => {
            return Err(Failure::invalid(
                "EsTargetInfo.samples",
                format!("{n} is not 1, 2, 4 or 8"),
            ))
        }
    };
    let mut target = Target::new(pass);
    target.samples = samples;
    target.aux_outputs = info.aux_outputs != 0;
    Ok(target)
}

/// The `ES_FEATURE_*` bits a device must have enabled for `target`. Any thread.
///
/// # Safety
/// `target` points at a valid `EsTargetInfo`; `out_features` at a writable `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn es_target_required_features(
    target: *const EsTargetInfo,
    out_features: *mut u32,
) -> EsStatus {
    guard("es_target_required_features", || {
        // SAFETY: caller contract.
        let info = unsafe { versioned(target, "target", TARGET_INFO_V1)? };
        // SAFETY: caller contract.
        let out = unsafe { output(out_features, "out_features")? };
        // SAFETY: caller contract on `color_formats`.
        let target = unsafe { target_from(info)? };
        *out = bits_from_features(target.required_features());
        Ok(())
    })
}
