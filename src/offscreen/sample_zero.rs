//! Reading sample 0 of the multisampled depth and ID attachments into the read-back buffer
//! with a compute fetch (`glsl/offscreen/sample_zero_*.comp`), instead of resolving them with
//! `SAMPLE_ZERO` inside the pass: the NVIDIA 580 driver's `SAMPLE_ZERO` resolve of an
//! `R32_UINT` attachment returns another sample's value where a pixel's samples differ, and a
//! fetch of sample 0 is what every driver must return.

use ash::vk;

use crate::error::{Result, VkCall};
use crate::gpu_layout::SpecConstants;
use crate::renderer::pipelines::create_compute_pipeline;

/// The depth build: a `texture2DMS` whose sample 0 is written as float bits.
const DEPTH_COMP: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/sample_zero_depth.comp.spv"));
/// The ID build: a `utexture2DMS`.
const ID_COMP: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/sample_zero_id.comp.spv"));

/// Pixels per workgroup on each axis (`local_size_x` and `local_size_y` of the shaders).
pub(crate) const GROUP_EDGE: u32 = 8;

/// The binding of the multisampled attachment (a sampled image, no sampler).
pub(crate) const TEXTURE_BINDING: u32 = 0;
/// The binding of the output's region of the read-back buffer.
pub(crate) const WORDS_BINDING: u32 = 1;

/// Which attachment a copy reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Attachment {
    Depth = 0,
    Id = 1,
}

/// One copy of sample 0: the attachment's view (in `SHADER_READ_ONLY_OPTIMAL`) into the
/// read-back buffer's region at `offset` (4 bytes a pixel).
pub(super) struct Copy {
    pub attachment: Attachment,
    pub view: vk::ImageView,
    pub offset: u64,
}

/// The pipelines and the two descriptor sets of the copies; owned by the offscreen renderer.
pub(super) struct SampleZero {
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pool: vk::DescriptorPool,
    /// One set per attachment, rewritten before each frame that copies (nothing pending uses
    /// them then: every offscreen submission is waited for).
    sets: [vk::DescriptorSet; 2],
    pipelines: [vk::Pipeline; 2],
}

impl SampleZero {
    /// Creates the layouts, the pool and sets, and both pipelines; on failure destroys what
    /// it made.
    pub fn new(device: &ash::Device) -> Result<Self> {
        let mut this = Self {
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pool: vk::DescriptorPool::null(),
            sets: [vk::DescriptorSet::null(); 2],
            pipelines: [vk::Pipeline::null(); 2],
        };
        if let Err(e) = this.create(device) {
            // SAFETY: nothing made here was used yet; null handles are ignored.
            unsafe { this.destroy(device) };
            return Err(e);
        }
        Ok(this)
    }

    fn create(&mut self, device: &ash::Device) -> Result<()> {
        let bindings = [
            vk::DescriptorSetLayoutBinding::default()
                .binding(TEXTURE_BINDING)
                .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
            vk::DescriptorSetLayoutBinding::default()
                .binding(WORDS_BINDING)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
        ];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info; owned by `self`, destroyed in `destroy`.
        self.set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .call("vkCreateDescriptorSetLayout")?;
        let set_layouts = [self.set_layout];
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        // SAFETY: as above.
        self.layout =
            unsafe { device.create_pipeline_layout(&info, None) }.call("vkCreatePipelineLayout")?;
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::SAMPLED_IMAGE,
                descriptor_count: 2,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: 2,
            },
        ];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(2)
            .pool_sizes(&sizes);
        // SAFETY: as above.
        self.pool =
            unsafe { device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")?;
        let layouts = [self.set_layout; 2];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.pool)
            .set_layouts(&layouts);
        // SAFETY: allocated from our pool, freed with it.
        let sets =
            unsafe { device.allocate_descriptor_sets(&info) }.call("vkAllocateDescriptorSets")?;
        self.sets = [sets[0], sets[1]];
        for (k, code) in [DEPTH_COMP, ID_COMP].into_iter().enumerate() {
            // The shaders have no specialization constants: the defaults name none of theirs.
            let constants = SpecConstants::default();
            self.pipelines[k] = create_compute_pipeline(
                device,
                vk::PipelineCache::null(),
                self.layout,
                code,
                &constants,
            )?;
        }
        Ok(())
    }

    /// Points the sets at `copies` and records one dispatch per copy over an image of
    /// `extent`. The caller orders the attachments' writes before (and the buffer's host
    /// read after) with barriers.
    ///
    /// # Safety
    /// `cmd` is recording outside a pass; no pending work uses the sets (every earlier
    /// submission completed); the views and `buffer` outlive the submission.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        buffer: vk::Buffer,
        extent: vk::Extent2D,
        copies: &[Copy],
    ) {
        let bytes = 4 * extent.width as u64 * extent.height as u64;
        for copy in copies {
            let set = self.sets[copy.attachment as usize];
            let image = [vk::DescriptorImageInfo::default()
                .image_view(copy.view)
                .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)];
            let words = [vk::DescriptorBufferInfo::default()
                .buffer(buffer)
                .offset(copy.offset)
                .range(bytes)];
            let writes = [
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(TEXTURE_BINDING)
                    .descriptor_type(vk::DescriptorType::SAMPLED_IMAGE)
                    .image_info(&image),
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(WORDS_BINDING)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(&words),
            ];
            // SAFETY: caller contract: the set is not in use; the view and buffer are live.
            unsafe {
                device.update_descriptor_sets(&writes, &[]);
                device.cmd_bind_pipeline(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.pipelines[copy.attachment as usize],
                );
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    self.layout,
                    0,
                    &[set],
                    &[],
                );
                device.cmd_dispatch(
                    cmd,
                    extent.width.div_ceil(GROUP_EDGE),
                    extent.height.div_ceil(GROUP_EDGE),
                    1,
                );
            }
        }
    }

    /// Destroys every object (idempotent).
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: owned handles or null (ignored); caller contract. The sets go with the pool.
        unsafe {
            for pipeline in self.pipelines {
                device.destroy_pipeline(pipeline, None);
            }
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
        *self = Self {
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pool: vk::DescriptorPool::null(),
            sets: [vk::DescriptorSet::null(); 2],
            pipelines: [vk::Pipeline::null(); 2],
        };
    }
}
