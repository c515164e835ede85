//! The renderer's pipelines: what each is specialised for (`keys.rs`, derived from the
//! frame plan), how one is created (`create.rs`, with the fixed-function state of
//! `raster.rs`), and here the layouts and the cache of every pipeline built so far, each on
//! first use.

mod create;
pub(crate) mod keys;
pub(crate) mod raster;

use ash::vk;

use crate::error::{Result, VkCall};
use crate::gpu_layout::PushConstants;
use crate::target::Target;

use super::descriptors::create_set_layout;
// The offscreen renderer's own compute passes (the fetch of sample 0) are made the same way.
#[cfg(feature = "offscreen")]
pub(crate) use create::create_compute_pipeline;
use create::{create_cull_pipeline, create_pipeline, create_splat_pipeline};
use keys::{CullKey, PipelineKey, SplatKey};

/// Graphics stages that read the push constants. The pre-pass has a layout of its own with a
/// compute-only range: lavapipe 22.3.6 crashes dispatching with a range shared between
/// graphics and compute stages.
pub(crate) const DRAW_PUSH_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::VERTEX.as_raw() | vk::ShaderStageFlags::FRAGMENT.as_raw(),
);

/// Layouts and pipelines; the pipeline cache is the host's (borrowed, may be null).
pub(crate) struct Pipelines {
    cache: vk::PipelineCache,
    set_layout: vk::DescriptorSetLayout,
    /// The draw's layout.
    pub draw_layout: vk::PipelineLayout,
    /// The pre-pass's layout.
    pub cull_layout: vk::PipelineLayout,
    draw: Vec<(PipelineKey, vk::Pipeline)>,
    cull: Vec<(CullKey, vk::Pipeline)>,
    splat: Vec<(SplatKey, vk::Pipeline)>,
}

impl Pipelines {
    /// No objects yet; `create_layouts` makes the layouts.
    pub fn new(cache: vk::PipelineCache) -> Self {
        Self {
            cache,
            set_layout: vk::DescriptorSetLayout::null(),
            draw_layout: vk::PipelineLayout::null(),
            cull_layout: vk::PipelineLayout::null(),
            draw: Vec::new(),
            cull: Vec::new(),
            splat: Vec::new(),
        }
    }

    /// Creates the descriptor-set layout and the two pipeline layouts.
    pub fn create_layouts(&mut self, device: &ash::Device) -> Result<()> {
        self.set_layout = create_set_layout(device)?;
        let layouts = [self.set_layout];
        let pipeline_layout = |stages: vk::ShaderStageFlags| {
            let ranges = [vk::PushConstantRange::default()
                .stage_flags(stages)
                .size(size_of::<PushConstants>() as u32)];
            let info = vk::PipelineLayoutCreateInfo::default()
                .set_layouts(&layouts)
                .push_constant_ranges(&ranges);
            // SAFETY: valid create info; owned by `self`, destroyed in `destroy`.
            unsafe { device.create_pipeline_layout(&info, None) }.call("vkCreatePipelineLayout")
        };
        self.draw_layout = pipeline_layout(DRAW_PUSH_STAGES)?;
        self.cull_layout = pipeline_layout(vk::ShaderStageFlags::COMPUTE)?;
        Ok(())
    }

    /// The descriptor-set layout.
    pub fn set_layout(&self) -> vk::DescriptorSetLayout {
        self.set_layout
    }

    /// The host's pipeline cache (borrowed; may be null).
    #[cfg_attr(not(feature = "research"), allow(dead_code))]
    pub fn cache(&self) -> vk::PipelineCache {
        self.cache
    }

    /// The draw pipeline for `key` into `target`, built now if this is its first use.
    pub fn draw(
        &mut self,
        device: &ash::Device,
        key: PipelineKey,
        target: &Target,
    ) -> Result<vk::Pipeline> {
        if let Some((_, p)) = self.draw.iter().find(|(k, _)| *k == key) {
            return Ok(*p);
        }
        let pipeline = create_pipeline(device, self.cache, self.draw_layout, target, key)?;
        self.draw.push((key, pipeline));
        Ok(pipeline)
    }

    /// The pre-pass pipeline for `key`, built now if this is its first use.
    pub fn cull(&mut self, device: &ash::Device, key: CullKey) -> Result<vk::Pipeline> {
        if let Some((_, p)) = self.cull.iter().find(|(k, _)| *k == key) {
            return Ok(*p);
        }
        let pipeline = create_cull_pipeline(device, self.cache, self.cull_layout, key)?;
        self.cull.push((key, pipeline));
        Ok(pipeline)
    }

    /// The compute splat's pipeline for `key`, built now if this is its first use. It shares
    /// the pre-pass's layout.
    pub fn splat(&mut self, device: &ash::Device, key: SplatKey) -> Result<vk::Pipeline> {
        if let Some((_, p)) = self.splat.iter().find(|(k, _)| *k == key) {
            return Ok(*p);
        }
        let pipeline = create_splat_pipeline(device, self.cache, self.cull_layout, key)?;
        self.splat.push((key, pipeline));
        Ok(pipeline)
    }

    /// Destroys every object.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: created from `device` (or null, which Vulkan ignores); caller contract.
        unsafe {
            let draw = self.draw.drain(..).map(|(_, p)| p);
            let cull = self.cull.drain(..).map(|(_, p)| p);
            for pipeline in draw.chain(cull).chain(self.splat.drain(..).map(|(_, p)| p)) {
                device.destroy_pipeline(pipeline, None);
            }
            device.destroy_pipeline_layout(self.draw_layout, None);
            device.destroy_pipeline_layout(self.cull_layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
