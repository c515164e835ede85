//! What a host tells the renderer about itself: its device, the pass the ellipsoids are drawn
//! into, its sample count, how many frames it keeps in flight, its pipeline cache.

use ash::vk;

use crate::error::{Error, Result};
use crate::features::DeviceFeatures;
use crate::settings::Settings;

/// The host's Vulkan objects the renderer works with, and the features the host enabled on
/// its device. The handles are borrowed: the renderer never destroys them, and the host keeps
/// them alive until it has destroyed the renderer.
///
/// `HostDevice::new(instance, physical_device, device, queue_family_index, enabled_features)`
/// -- the handles borrowed, and the features the host enabled, of those the renderer uses
/// (`DeviceFeatures`, `src/features.rs`: `maintenance4`, `dynamicRendering`,
/// `sampleRateShading`, `shaderInt64`, `shaderBufferInt64Atomics`; `to_vk` gives the structs to
/// chain into `VkDeviceCreateInfo`, `supported` reads what a device has, `missing_from` names
/// what is missing). What a target needs is `Target::required_features()`: always
/// `maintenance4` (the compute shaders use `LocalSizeId`); `dynamicRendering` only for
/// `Pass::Dynamic` (a render-pass host need not enable it); `sampleRateShading` only for a
/// multisampled target (its frames shade every sample with other sample counts, on devices
/// without the standard sample locations, or with `Settings::per_sample_shading`, which a host
/// may turn on at any frame). The compute splat
/// (design §5.6) runs only where the host enabled `DeviceFeatures::COMPUTE_SPLAT` too, and the plan
/// says so (`DrawReason`). `new` and `set_target` refuse a target whose features the host did
/// not enable, naming them; the queue family must support graphics and compute.
#[derive(Clone, Copy)]
#[non_exhaustive]
pub struct HostDevice<'a> {
    /// The instance the device was created from (to query the physical device).
    pub instance: &'a ash::Instance,
    /// The physical device behind `device`.
    pub physical_device: vk::PhysicalDevice,
    /// The host's device.
    pub device: &'a ash::Device,
    /// The queue family whose queue will execute the command buffers the renderer records
    /// into: it must support graphics and compute. The renderer records no queue-family
    /// ownership transfers.
    pub queue_family_index: u32,
    /// The features the host enabled on `device`, of those the renderer uses: each target
    /// needs its [`Target::required_features`], and the compute splat runs only where
    /// [`DeviceFeatures::COMPUTE_SPLAT`] are enabled too.
    pub enabled_features: DeviceFeatures,
}

impl<'a> HostDevice<'a> {
    /// The host's device, its queue family and the renderer's features it enabled.
    pub fn new(
        instance: &'a ash::Instance,
        physical_device: vk::PhysicalDevice,
        device: &'a ash::Device,
        queue_family_index: u32,
        enabled_features: DeviceFeatures,
    ) -> Self {
        Self {
            instance,
            physical_device,
            device,
            queue_family_index,
            enabled_features,
        }
    }
}

/// The kind of pass the ellipsoids are drawn in.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Pass {
    /// Dynamic rendering (`vkCmdBeginRendering`) with these attachments: `color_formats` in
    /// attachment order, and `depth_format`.
    Dynamic {
        /// Every colour attachment of the pass, in order.
        color_formats: Vec<vk::Format>,
        /// The depth attachment (a depth format: the renderer depth-tests and writes depth).
        depth_format: vk::Format,
    },
    /// Subpass `subpass` of the host's render pass. The renderer builds its pipelines against
    /// it and never destroys it.
    RenderPass {
        /// The host's render pass (borrowed).
        render_pass: vk::RenderPass,
        /// The subpass the ellipsoids are drawn in.
        subpass: u32,
        /// How many colour attachments that subpass has.
        color_attachment_count: u32,
        /// Its depth attachment's format.
        depth_format: vk::Format,
    },
}

/// The pass the ellipsoids are drawn into and what the renderer writes there.
///
/// `Target::new(pass)` (fields `pass`, `samples`, `aux_outputs`; non-exhaustive) with
/// `Pass::RenderPass { render_pass, subpass, color_attachment_count, depth_format }` or
/// `Pass::Dynamic { color_formats, depth_format }` (`Target::dynamic(color, depth)` for the
/// single-sample, colour-and-depth case).
/// The renderer writes colour attachment 0, depth, and with `aux_outputs` attachments 1
/// ([`Target::NORMAL_FORMAT`], `R32G32B32A32_SFLOAT`) and 2 ([`Target::ID_FORMAT`], `R32_UINT`); other colour
/// attachments get a zero write mask. No blending. `set_target` switches targets; pipelines are
/// kept per target. With `samples` 2 or 4 on a device with the standard sample locations
/// (`FramePlan::coverage_samples`), the fragment stage runs once per pixel
/// (`sampleShadingEnable` off) and decides each standard sample position exactly
/// (`glsl/include/pixel_coverage.glsl`), writing the covered ones to `gl_SampleMask` (an empty
/// mask writes nothing). In perspective with nothing in front of the near plane (`NO_CAPS`) and
/// no far plane (`FAR_PLANE` off), a sample is covered where the silhouette's quadratic form
/// says so: hit_stable's `den > 0` and `|q| < 1` are `den > 0` and
/// `f = den^2 - k_y^2 |r_xy|^2 > 0` (design §4.2, §4.3), both affine or quadratic in the sample's
/// offset from the pixel centre, so no division per sample; the hit is then computed once.
/// Otherwise (caps, an eye inside, a far plane that may cut a glyph inside a pixel,
/// orthographic) every sample runs the full hit. The two ways are compile-time variants because
/// lavapipe executes both sides of a divergent branch. Either way the pixel gets one depth, the
/// nearest covered sample's (a glyph in front of the host's geometry at every sample it covers
/// shows at all of them; where they cross, a pixel's samples may fall on the wrong side), and is
/// shaded at that sample. Other counts, devices without standard locations, and
/// `Settings::per_sample_shading` shade every sample (`sampleShadingEnable`,
/// `minSampleShading` 1): depth exact per sample. Single-sample stages write `gl_SampleMask`
/// as it came in (the stage declares the output).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct Target {
    /// The pass's attachments.
    pub pass: Pass,
    /// Samples per pixel of the attachments (1 or a power of two the device supports); how
    /// more than one is covered and shaded is in the type's documentation.
    pub samples: vk::SampleCountFlags,
    /// Colour attachments 1 and 2 receive the world normal ([`Target::NORMAL_FORMAT`]) and the
    /// instance index ([`Target::ID_FORMAT`]); otherwise the renderer writes attachment 0 only. It
    /// never writes other colour attachments (write mask 0).
    pub aux_outputs: bool,
}

impl Target {
    /// Normal attachment format when [`Target::aux_outputs`] is set.
    pub const NORMAL_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
    /// Instance-ID attachment format when [`Target::aux_outputs`] is set.
    pub const ID_FORMAT: vk::Format = vk::Format::R32_UINT;

    /// A single-sample target of `pass` writing colour attachment 0 and depth (change
    /// `samples` and `aux_outputs` after).
    pub fn new(pass: Pass) -> Self {
        Self {
            pass,
            samples: vk::SampleCountFlags::TYPE_1,
            aux_outputs: false,
        }
    }

    /// A single-sample dynamic-rendering target with colour and depth attachments.
    pub fn dynamic(color: vk::Format, depth: vk::Format) -> Self {
        Self {
            pass: Pass::Dynamic {
                color_formats: vec![color],
                depth_format: depth,
            },
            samples: vk::SampleCountFlags::TYPE_1,
            aux_outputs: false,
        }
    }

    /// The depth attachment's format.
    pub fn depth_format(&self) -> vk::Format {
        match &self.pass {
            Pass::Dynamic { depth_format, .. } | Pass::RenderPass { depth_format, .. } => {
                *depth_format
            }
        }
    }

    /// Number of colour attachments of the pass.
    pub fn color_attachment_count(&self) -> u32 {
        match &self.pass {
            Pass::Dynamic { color_formats, .. } => color_formats.len() as u32,
            Pass::RenderPass {
                color_attachment_count,
                ..
            } => *color_attachment_count,
        }
    }

    /// More than one sample per pixel.
    pub fn multisampled(&self) -> bool {
        self.samples != vk::SampleCountFlags::TYPE_1
    }

    /// The device features drawing into this target needs: `maintenance4` always (the
    /// pre-pass's compute shaders), `dynamicRendering` only for [`Pass::Dynamic`] (a
    /// render-pass host need not enable it), `sampleRateShading` only for multisampled
    /// targets, where the renderer may shade every sample (it is needed only then:
    /// `Settings::per_sample_shading`, or sample counts or devices without the standard
    /// sample locations).
    pub fn required_features(&self) -> DeviceFeatures {
        DeviceFeatures {
            maintenance4: true,
            dynamic_rendering: matches!(self.pass, Pass::Dynamic { .. }),
            sample_rate_shading: self.multisampled(),
            ..DeviceFeatures::default()
        }
    }

    /// Checks the description against itself and what the device allows.
    pub(crate) fn validate(&self, caps: &DeviceCaps) -> Result<()> {
        let bad = |why: String| Err(Error::invalid("render target", why));
        let depth = self.depth_format();
        if !matches!(
            depth,
            vk::Format::D32_SFLOAT
                | vk::Format::D32_SFLOAT_S8_UINT
                | vk::Format::D24_UNORM_S8_UINT
                | vk::Format::D16_UNORM
                | vk::Format::D16_UNORM_S8_UINT
                | vk::Format::X8_D24_UNORM_PACK32
        ) {
            return bad(format!(
                "depth format {depth:?} is not a depth format (the renderer needs a depth attachment)"
            ));
        }
        let colors = self.color_attachment_count();
        let needed = if self.aux_outputs { 3 } else { 1 };
        if colors < needed {
            return bad(format!(
                "{colors} colour attachments, the renderer writes {needed}"
            ));
        }
        if let Pass::Dynamic { color_formats, .. } = &self.pass {
            if color_formats[0] == vk::Format::UNDEFINED {
                return bad("colour attachment 0 has format UNDEFINED".into());
            }
            if self.aux_outputs
                && (color_formats[1] != Target::NORMAL_FORMAT
                    || color_formats[2] != Target::ID_FORMAT)
            {
                return bad(format!(
                    "aux outputs need attachments 1 and 2 as {:?} and {:?}, got {:?} and {:?}",
                    Target::NORMAL_FORMAT,
                    Target::ID_FORMAT,
                    color_formats[1],
                    color_formats[2]
                ));
            }
        }
        if let Pass::RenderPass { render_pass, .. } = &self.pass {
            if *render_pass == vk::RenderPass::null() {
                return bad("the render pass handle is null".into());
            }
        }
        let s = self.samples;
        let supported = caps.limits.framebuffer_color_sample_counts
            & caps.limits.framebuffer_depth_sample_counts;
        if s.as_raw().count_ones() != 1 || !supported.contains(s) {
            return bad(format!(
                "{s:?} samples per pixel: the device supports {supported:?} for colour and depth"
            ));
        }
        // sampleRateShading is checked where a frame shades every sample (the plan).
        let needed = DeviceFeatures {
            sample_rate_shading: false,
            ..self.required_features()
        };
        let missing = needed.missing_from(caps.enabled);
        if !missing.is_empty() {
            return bad(format!(
                "{} needs {}, which the host did not enable (HostDevice::enabled_features)",
                match self.pass {
                    Pass::Dynamic { .. } => "a dynamic-rendering target",
                    Pass::RenderPass { .. } => "a render-pass target",
                },
                missing.join(", ")
            ));
        }
        Ok(())
    }
}

/// How the renderer is set up for a host: [`RendererOptions::new`], then change the fields
/// that differ.
///
/// `RendererOptions::new(target)` (fields `target`, `frames_in_flight` (1 ..= 16), `settings`,
/// `pipeline_cache` (borrowed, may be null); non-exhaustive) gives one frame in flight,
/// `Settings::default()` and no pipeline cache.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct RendererOptions {
    /// The pass the ellipsoids are drawn into (more can be added with `set_target`).
    pub target: Target,
    /// How many frames the host records before waiting for the oldest: the renderer keeps
    /// what it replaces alive until every frame slot has begun again (`begin_frame`).
    pub frames_in_flight: u32,
    /// The material and the work-skipping the renderer does.
    pub settings: Settings,
    /// The host's pipeline cache, used for every pipeline the renderer builds (borrowed; null
    /// for none).
    pub pipeline_cache: vk::PipelineCache,
}

impl RendererOptions {
    /// One frame in flight, no pipeline cache.
    pub fn new(target: Target) -> Self {
        Self {
            target,
            frames_in_flight: 1,
            pipeline_cache: vk::PipelineCache::null(),
            settings: Settings::default(),
        }
    }
}

/// What the renderer learns about the host's device when it is created.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DeviceCaps {
    pub limits: vk::PhysicalDeviceLimits,
    /// What the host enabled, of what the device supports.
    pub enabled: DeviceFeatures,
    /// Valid bits of the queue family's timestamps (0: none, and the plan cannot measure).
    pub timestamp_valid_bits: u32,
    /// Which device and driver build: what learned plans are keyed by.
    pub identity: DeviceIdentity,
}

/// A device and its driver build, as the plan's learned choices are keyed (as
/// `VkPipelineCache` data is: the pipeline-cache UUID changes with the driver build).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct DeviceIdentity {
    pub vendor_id: u32,
    pub device_id: u32,
    pub driver_version: u32,
    pub pipeline_cache_uuid: [u8; vk::UUID_SIZE],
}

impl HostDevice<'_> {
    /// Checks the queue family and features; returns the limits later checks need.
    pub(crate) fn caps(&self) -> Result<DeviceCaps> {
        // SAFETY: the host guarantees `physical_device` comes from `instance`.
        let families = unsafe {
            self.instance
                .get_physical_device_queue_family_properties(self.physical_device)
        };
        let family = families
            .get(self.queue_family_index as usize)
            .ok_or_else(|| {
                Error::invalid(
                    "queue family",
                    format!(
                        "index {} but the device has {}",
                        self.queue_family_index,
                        families.len()
                    ),
                )
            })?;
        if !family
            .queue_flags
            .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
        {
            return Err(Error::invalid(
                "queue family",
                format!(
                    "{} has {:?}; the renderer records graphics and compute work",
                    self.queue_family_index, family.queue_flags
                ),
            ));
        }
        // SAFETY: as above.
        let supported = unsafe { DeviceFeatures::supported(self.instance, self.physical_device) };
        let unsupported = self.enabled_features.missing_from(supported);
        if !unsupported.is_empty() {
            return Err(Error::invalid(
                "HostDevice::enabled_features",
                format!(
                    "names {}, which the physical device does not support",
                    unsupported.join(", ")
                ),
            ));
        }
        // SAFETY: as above.
        let properties = unsafe {
            self.instance
                .get_physical_device_properties(self.physical_device)
        };
        Ok(DeviceCaps {
            limits: properties.limits,
            enabled: self.enabled_features,
            timestamp_valid_bits: family.timestamp_valid_bits,
            identity: DeviceIdentity {
                vendor_id: properties.vendor_id,
                device_id: properties.device_id,
                driver_version: properties.driver_version,
                pipeline_cache_uuid: properties.pipeline_cache_uuid,
            },
        })
    }
}
