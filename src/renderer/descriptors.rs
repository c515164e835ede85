//! The descriptor set layout and the per-chunk descriptor sets with the texel views they
//! point at. A set is never rewritten once recorded: when a buffer is replaced, new sets and
//! views are made (the sets in a new pool) and the old ones retired.

use ash::vk;

use super::prepass::steps;
use crate::error::{Result, VkCall};
use crate::gpu_layout::{FootprintRecord, IndirectDraw, ShadingRecord};

use super::buffers::{Binding, SceneBuffers};
use super::chunks::{Chunking, SLICE_ALIGN};
use super::plan::MAX_SETUP_ONCE_INSTANCES;

/// Binding of the visibility buffer's texel view (`visibility_keys` in
/// glsl/include/visibility_words.glsl): the keys, one `R32G32_UINT` texel each, for the
/// passes that only read them.
pub(crate) const VISIBILITY_KEYS: u32 = 12;

/// The stages that read the keys: the resolve's vertex stage (the tile words) and fragment
/// stage (the pixels' keys), and `KEY_TILES` and `MARK_SHOWN`.
pub(crate) const VISIBILITY_KEYS_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::VERTEX.as_raw()
        | vk::ShaderStageFlags::FRAGMENT.as_raw()
        | vk::ShaderStageFlags::COMPUTE.as_raw(),
);

/// Creates the layout of the renderer's one descriptor set: a buffer per [`Binding`], of its
/// descriptor type, and the visibility buffer's texel view.
pub(crate) fn create_set_layout(device: &ash::Device) -> Result<vk::DescriptorSetLayout> {
    let mut bindings = Binding::ALL
        .map(|binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding as u32)
                .descriptor_type(binding.descriptor_type())
                .descriptor_count(1)
                .stage_flags(binding.stages())
        })
        .to_vec();
    bindings.push(
        vk::DescriptorSetLayoutBinding::default()
            .binding(VISIBILITY_KEYS)
            .descriptor_type(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
            .descriptor_count(1)
            .stage_flags(VISIBILITY_KEYS_STAGES),
    );
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    // SAFETY: valid create info; the caller owns the layout.
    unsafe { device.create_descriptor_set_layout(&info, None) }.call("vkCreateDescriptorSetLayout")
}

/// Descriptor sets, one per chunk, the pool they came from and the texel views they point at
/// (one view of the visibility buffer, then each chunk's view of its instances).
#[derive(Default)]
pub(crate) struct ChunkSets {
    pub pool: vk::DescriptorPool,
    pub sets: Vec<vk::DescriptorSet>,
    pub views: Vec<vk::BufferView>,
}

impl ChunkSets {
    /// Destroys the pool (and with it the sets) and the views.
    ///
    /// # Safety
    /// No pending work uses them; all were created from `device` (null handles are ignored).
    pub unsafe fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: caller contract.
        unsafe {
            for view in self.views.drain(..) {
                device.destroy_buffer_view(view, None);
            }
            device.destroy_descriptor_pool(self.pool, None);
        }
        self.pool = vk::DescriptorPool::null();
        self.sets.clear();
    }
}

/// A texel view of `bytes` bytes of `buffer` from `offset`, in `format` (`texel` bytes a
/// texel), owned by `views`: at most `max_texels` texels, which `Chunking` and the plan keep
/// every range the shaders read within.
fn texel_view(
    device: &ash::Device,
    views: &mut Vec<vk::BufferView>,
    (buffer, offset, bytes): (vk::Buffer, u64, u64),
    (format, texel): (vk::Format, u64),
    max_texels: u32,
) -> Result<vk::BufferView> {
    let range = bytes.min(max_texels as u64 * texel) / texel * texel;
    let info = vk::BufferViewCreateInfo::default()
        .buffer(buffer)
        .format(format)
        .offset(offset)
        .range(range);
    // SAFETY: valid create info (the buffer has UNIFORM_TEXEL_BUFFER usage; the range lies
    // inside it); `views` owns the view.
    let view = unsafe { device.create_buffer_view(&info, None) }.call("vkCreateBufferView")?;
    views.push(view);
    Ok(view)
}

/// Allocates and writes one set per chunk of `chunking` for one view, pointing at the
/// chunk's slices of the renderer's `shared` buffers and the view's own, in a new pool, with
/// texel views of at most `max_texels` texels; the caller owns them all.
pub(crate) fn create_chunk_sets(
    device: &ash::Device,
    layout: vk::DescriptorSetLayout,
    (shared, view): (&SceneBuffers, &SceneBuffers),
    chunking: &Chunking,
    (instance_stride, max_texels): (u64, u32),
) -> Result<ChunkSets> {
    let mut made = ChunkSets::default();
    match write_chunk_sets(
        device,
        layout,
        (shared, view),
        chunking,
        (instance_stride, max_texels),
        &mut made,
    ) {
        Ok(()) => Ok(made),
        Err(e) => {
            // SAFETY: just made, never used.
            unsafe { made.destroy(device) };
            Err(e)
        }
    }
}

/// `create_chunk_sets` into `made` (which holds whatever was created when it fails).
fn write_chunk_sets(
    device: &ash::Device,
    layout: vk::DescriptorSetLayout,
    (shared, view): (&SceneBuffers, &SceneBuffers),
    chunking: &Chunking,
    (instance_stride, max_texels): (u64, u32),
    made: &mut ChunkSets,
) -> Result<()> {
    let handles = Binding::ALL
        .iter()
        .map(|&b| if b.per_view() { view } else { shared }.handle(b))
        .collect::<Result<Vec<_>>>()?;
    let sets = chunking.len();
    let storage = Binding::ALL
        .iter()
        .filter(|b| b.descriptor_type() == vk::DescriptorType::STORAGE_BUFFER)
        .count() as u32;
    let texel = Binding::ALL.len() as u32 + 1 - storage;
    let sizes = [
        vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(storage * sets),
        vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
            .descriptor_count(texel * sets),
    ];
    let info = vk::DescriptorPoolCreateInfo::default()
        .max_sets(sets)
        .pool_sizes(&sizes);
    // SAFETY: valid create info; `made` owns the pool.
    made.pool =
        unsafe { device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")?;
    let layouts = vec![layout; sets as usize];
    let info = vk::DescriptorSetAllocateInfo::default()
        .descriptor_pool(made.pool)
        .set_layouts(&layouts);
    // SAFETY: the pool has room for exactly these sets; they are freed with the pool.
    made.sets =
        unsafe { device.allocate_descriptor_sets(&info) }.call("vkAllocateDescriptorSets")?;
    // The keys, read where nothing writes them: one view for every chunk.
    let visibility = view.get(Binding::Visibility).map_or(0, |b| b.size());
    let keys = texel_view(
        device,
        &mut made.views,
        (handles[Binding::Visibility as usize], 0, visibility),
        (vk::Format::R32G32_UINT, 8),
        max_texels,
    )?;
    // Set-up records exist per instance only for scenes that can use them.
    let records = chunking.count <= MAX_SETUP_ONCE_INSTANCES;
    let groups = chunking.groups_slice();
    let chunks: Vec<(u32, u32)> = chunking.chunks().collect();
    for k in 0..made.sets.len() {
        let set = made.sets[k];
        let (first, count) = chunks.get(k).copied().unwrap_or((0, 1));
        let (first, count) = (first as u64, count.max(1) as u64);
        let slice = |bytes_each: u64| (first * bytes_each, count * bytes_each);
        let whole = (0, vk::WHOLE_SIZE);
        let record = |bytes_each: usize| {
            if records {
                slice(bytes_each as u64)
            } else {
                whole
            }
        };
        let ranges = Binding::ALL.map(|binding| match binding {
            Binding::Instances => slice(instance_stride),
            Binding::FragmentCounter
            | Binding::OcclusionTiles
            | Binding::Visibility
            | Binding::FloorPixels
            | Binding::GlyphStamps
            | Binding::TileLists => whole,
            Binding::Visible => slice(4),
            Binding::IndirectDraw => (k as u64 * SLICE_ALIGN, size_of::<IndirectDraw>() as u64),
            Binding::CullGroups => (k as u64 * groups, steps::groups_bytes(count as u32)),
            Binding::ShadingRecords => record(size_of::<ShadingRecord>()),
            Binding::FootprintRecords => record(size_of::<FootprintRecord>()),
        });
        // The chunk's instances as 16-byte texels. Chunks start at multiples of 256
        // instances, so the offset is a multiple of 256 bytes: of any device's
        // `minTexelBufferOffsetAlignment` (at most 256).
        let (offset, bytes) = ranges[Binding::Instances as usize];
        let instances = texel_view(
            device,
            &mut made.views,
            (handles[Binding::Instances as usize], offset, bytes),
            (vk::Format::R32G32B32A32_UINT, 16),
            max_texels,
        )?;
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = handles
            .iter()
            .zip(ranges)
            .map(|(&buffer, (offset, range))| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(buffer)
                    .offset(offset)
                    .range(range)]
            })
            .collect();
        let texel_views = [[instances], [keys]];
        let mut writes: Vec<vk::WriteDescriptorSet> = Binding::ALL
            .iter()
            .zip(&infos)
            .filter(|(b, _)| b.descriptor_type() == vk::DescriptorType::STORAGE_BUFFER)
            .map(|(&binding, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(binding as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        for (binding, view) in [Binding::Instances as u32, VISIBILITY_KEYS]
            .into_iter()
            .zip(&texel_views)
        {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(binding)
                    .descriptor_type(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
                    .texel_buffer_view(view),
            );
        }
        // SAFETY: the set is new (no command buffer uses it); every buffer and view is live
        // and each range lies inside its buffer (sized for the whole scene at upload).
        unsafe { device.update_descriptor_sets(&writes, &[]) };
    }
    Ok(())
}
