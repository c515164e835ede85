//! The descriptor set layout and the per-chunk descriptor sets. A set is never rewritten
//! once recorded: when a buffer is replaced, new sets are made in a new pool and the old pool
//! is retired.

use ash::vk;

use super::prepass::steps;
use crate::error::{Error, Result, VkCall};
use crate::gpu_layout::{FootprintRecord, IndirectDraw, ShadingRecord};

use super::buffers::{Binding, SceneBuffers};
use super::chunks::{Chunking, SLICE_ALIGN};
use super::plan::MAX_SETUP_ONCE_INSTANCES;

/// Creates the layout of the renderer's one descriptor set: a storage buffer per [`Binding`].
pub(crate) fn create_set_layout(device: &ash::Device) -> Result<vk::DescriptorSetLayout> {
    let bindings = Binding::ALL.map(|binding| {
        vk::DescriptorSetLayoutBinding::default()
            .binding(binding as u32)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(1)
            .stage_flags(binding.stages())
    });
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    // SAFETY: valid create info; the caller owns the layout.
    unsafe { device.create_descriptor_set_layout(&info, None) }.call("vkCreateDescriptorSetLayout")
}

/// Descriptor sets, one per chunk, and the pool they came from.
pub(crate) struct ChunkSets {
    pub pool: vk::DescriptorPool,
    pub sets: Vec<vk::DescriptorSet>,
}

/// Allocates and writes one set per chunk of `chunking` for one view, pointing at the
/// chunk's slices of the renderer's `shared` buffers and the view's own, in a new pool the
/// caller owns.
pub(crate) fn create_chunk_sets(
    device: &ash::Device,
    layout: vk::DescriptorSetLayout,
    (shared, view): (&SceneBuffers, &SceneBuffers),
    chunking: &Chunking,
    instance_stride: u64,
) -> Result<ChunkSets> {
    let handles = Binding::ALL
        .iter()
        .map(|&b| if b.per_view() { view } else { shared }.handle(b))
        .collect::<Result<Vec<_>>>()?;
    let sets = chunking.len();
    let sizes = [vk::DescriptorPoolSize::default()
        .ty(vk::DescriptorType::STORAGE_BUFFER)
        .descriptor_count(handles.len() as u32 * sets)];
    let info = vk::DescriptorPoolCreateInfo::default()
        .max_sets(sets)
        .pool_sizes(&sizes);
    // SAFETY: valid create info; the caller owns the pool.
    let pool =
        unsafe { device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")?;
    let layouts = vec![layout; sets as usize];
    let info = vk::DescriptorSetAllocateInfo::default()
        .descriptor_pool(pool)
        .set_layouts(&layouts);
    // SAFETY: the pool has room for exactly these sets; they are freed with the pool.
    let allocated = match unsafe { device.allocate_descriptor_sets(&info) } {
        Ok(sets) => sets,
        Err(result) => {
            // SAFETY: just created, unused.
            unsafe { device.destroy_descriptor_pool(pool, None) };
            return Err(Error::vulkan("vkAllocateDescriptorSets", result));
        }
    };
    // Set-up records exist per instance only for scenes that can use them.
    let records = chunking.count <= MAX_SETUP_ONCE_INSTANCES;
    let groups = chunking.groups_slice();
    let chunks: Vec<(u32, u32)> = chunking.chunks().collect();
    for (k, &set) in allocated.iter().enumerate() {
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
        let writes: Vec<vk::WriteDescriptorSet> = infos
            .iter()
            .enumerate()
            .map(|(binding, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(binding as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: the set is new (no command buffer uses it); every buffer is live and each
        // range lies inside its buffer (sized for the whole scene at upload).
        unsafe { device.update_descriptor_sets(&writes, &[]) };
    }
    Ok(ChunkSets {
        pool,
        sets: allocated,
    })
}
