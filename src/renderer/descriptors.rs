//! The descriptor set layout and the per-chunk descriptor sets with the texel views they
//! point at. A set is never rewritten once recorded: when a buffer is replaced, new sets and
//! views are made (the sets in a new pool) and the old ones retired.

use ash::vk;

use super::prepass::steps;
use crate::error::{Result, VkCall};
use crate::gpu_layout::{FootprintRecord, IndirectDraw, ShadingRecord};

use super::buffers::{Binding, SceneBuffers};
use super::chunks::{Chunking, SLICE_ALIGN};

/// A texel view of a storage binding's buffer (why texels: design §7): read as a uniform texel
/// buffer by the passes that only read it, or written as a storage texel buffer. Its binding,
/// the buffer it views, its descriptor type, its texels' format and bytes, the stages that
/// use it, and whether it views each chunk's slice of the buffer (as the storage binding
/// does) or the whole buffer, shared by all chunks.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TexelView {
    pub binding: u32,
    pub of: Binding,
    pub kind: vk::DescriptorType,
    pub format: vk::Format,
    pub texel: u64,
    pub stages: vk::ShaderStageFlags,
    pub sliced: bool,
}

/// The visibility buffer's keys (`visibility_keys` in glsl/include/visibility_words.glsl), one
/// `R32G32_UINT` texel each, read by the resolve's vertex stage (the tile words) and fragment
/// stage (the pixels' keys), and by `KEY_TILES` and `MARK_SHOWN`.
pub(crate) const VISIBILITY_KEYS: TexelView = TexelView {
    binding: 12,
    of: Binding::Visibility,
    kind: vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
    format: vk::Format::R32G32_UINT,
    texel: 8,
    stages: vk::ShaderStageFlags::from_raw(
        vk::ShaderStageFlags::VERTEX.as_raw()
            | vk::ShaderStageFlags::FRAGMENT.as_raw()
            | vk::ShaderStageFlags::COMPUTE.as_raw(),
    ),
    sliced: false,
};

/// The occlusion tiles' words (`occlusion_tile_words` in glsl/include/occlusion_tiles.glsl),
/// one `R32_UINT` texel each, read by the visible-first splat's second CLASSIFY and its second
/// splat pass. Only there:
/// a frame that splats has a visibility buffer (a texel per pixel) within the device's texel
/// limit, and an image has no more tiles than pixels; a culled draw's image may exceed it.
pub(crate) const OCCLUSION_TILE_WORDS: TexelView = TexelView {
    binding: 13,
    of: Binding::OcclusionTiles,
    kind: vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
    format: vk::Format::R32_UINT,
    texel: 4,
    stages: vk::ShaderStageFlags::COMPUTE,
    sliced: false,
};

/// The chunk's shading records (`shading_record_texels` in
/// glsl/include/shading_record_texels.glsl), 8 `R32G32B32A32_UINT` texels each, read by the
/// splat's resolve where the splat stored them (`SplatPath::setup_once`; the plan asks that they
/// fit the device's texel limit, `Chunking::shading_records_fit`).
pub(crate) const SHADING_RECORD_TEXELS: TexelView = TexelView {
    binding: 14,
    of: Binding::ShadingRecords,
    kind: vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
    format: vk::Format::R32G32B32A32_UINT,
    texel: 16,
    stages: vk::ShaderStageFlags::FRAGMENT,
    sliced: true,
};

/// The chunk's shading records (`shading_record_stores` in glsl/include/setup_records.glsl) as
/// the pre-pass writes them (CLASSIFY for the set-up-once draw, the splat for its resolve), 8
/// `R32G32B32A32_UINT` texels each: lavapipe stores a storage buffer's words lane by lane, a
/// texel at a time here (the plan asks that they fit the device's texel limit, likewise).
pub(crate) const SHADING_RECORD_STORES: TexelView = TexelView {
    binding: 15,
    of: Binding::ShadingRecords,
    kind: vk::DescriptorType::STORAGE_TEXEL_BUFFER,
    format: vk::Format::R32G32B32A32_UINT,
    texel: 16,
    stages: vk::ShaderStageFlags::COMPUTE,
    sliced: true,
};

/// Every texel view of a storage binding, in binding order.
pub(crate) const TEXEL_VIEWS: [TexelView; 4] = [
    VISIBILITY_KEYS,
    OCCLUSION_TILE_WORDS,
    SHADING_RECORD_TEXELS,
    SHADING_RECORD_STORES,
];

/// Creates the layout of the renderer's one descriptor set: a buffer per [`Binding`], of its
/// descriptor type, and the texel views of [`TEXEL_VIEWS`].
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
    bindings.extend(TEXEL_VIEWS.map(|view| {
        vk::DescriptorSetLayoutBinding::default()
            .binding(view.binding)
            .descriptor_type(view.kind)
            .descriptor_count(1)
            .stage_flags(view.stages)
    }));
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    // SAFETY: valid create info; the caller owns the layout.
    unsafe { device.create_descriptor_set_layout(&info, None) }.call("vkCreateDescriptorSetLayout")
}

/// Descriptor sets, one per chunk, the pool they came from and the texel views they point at
/// (those of [`TEXEL_VIEWS`], then each chunk's view of its instances).
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
    // SAFETY: valid create info (the buffer has the texel usage of every view made of it,
    // `Binding::usage`; the range lies inside it); `views` owns the view.
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
    let owner = |b: Binding| if b.per_view() { view } else { shared };
    let handles = Binding::ALL
        .iter()
        .map(|&b| owner(b).handle(b))
        .collect::<Result<Vec<_>>>()?;
    let size = |b: Binding| owner(b).get(b).map_or(0, |buffer| buffer.size());
    let sets = chunking.len();
    let storage = Binding::ALL
        .iter()
        .filter(|b| b.descriptor_type() == vk::DescriptorType::STORAGE_BUFFER)
        .count() as u32;
    let stores = TEXEL_VIEWS
        .iter()
        .filter(|r| r.kind == vk::DescriptorType::STORAGE_TEXEL_BUFFER)
        .count() as u32;
    let texel = Binding::ALL.len() as u32 + TEXEL_VIEWS.len() as u32 - storage - stores;
    let sizes = [
        vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_TEXEL_BUFFER)
            .descriptor_count(stores * sets),
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
    // The views of whole buffers, read where nothing writes them: one of each for every
    // chunk (the sliced ones are made per chunk below).
    let mut whole_views = Vec::with_capacity(TEXEL_VIEWS.len());
    for read in TEXEL_VIEWS.iter().filter(|r| !r.sliced) {
        let made_view = texel_view(
            device,
            &mut made.views,
            (handles[read.of as usize], 0, size(read.of)),
            (read.format, read.texel),
            max_texels,
        )?;
        whole_views.push((read, made_view));
    }
    // Set-up records exist per instance only for scenes that can use them.
    let records = chunking.has_records();
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
        let mut texel_views: Vec<(u32, [vk::BufferView; 1], vk::DescriptorType)> =
            std::iter::once((
                Binding::Instances as u32,
                [instances],
                vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
            ))
            .chain(
                whole_views
                    .iter()
                    .map(|&(read, v)| (read.binding, [v], read.kind)),
            )
            .collect();
        for read in TEXEL_VIEWS.iter().filter(|r| r.sliced) {
            let (offset, bytes) = ranges[read.of as usize];
            // A slice's offset is a multiple of 256 instances' records, so of any device's
            // `minTexelBufferOffsetAlignment`; a whole buffer (no records) starts at 0.
            let bytes = if bytes == vk::WHOLE_SIZE {
                size(read.of)
            } else {
                bytes
            };
            let sliced = texel_view(
                device,
                &mut made.views,
                (handles[read.of as usize], offset, bytes),
                (read.format, read.texel),
                max_texels,
            )?;
            texel_views.push((read.binding, [sliced], read.kind));
        }
        for (binding, view, kind) in &texel_views {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(*binding)
                    .descriptor_type(*kind)
                    .texel_buffer_view(view),
            );
        }
        // SAFETY: the set is new (no command buffer uses it); every buffer and view is live
        // and each range lies inside its buffer (sized for the whole scene at upload).
        unsafe { device.update_descriptor_sets(&writes, &[]) };
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each texel view has a binding of its own, and its buffer the usage a view needs.
    #[test]
    fn texel_views_have_their_own_bindings_and_texel_usage() {
        for view in TEXEL_VIEWS {
            assert!(
                Binding::ALL.iter().all(|&b| b as u32 != view.binding),
                "binding {} is also a buffer's",
                view.binding
            );
            let usage = match view.kind {
                vk::DescriptorType::UNIFORM_TEXEL_BUFFER => {
                    vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
                }
                vk::DescriptorType::STORAGE_TEXEL_BUFFER => {
                    vk::BufferUsageFlags::STORAGE_TEXEL_BUFFER
                }
                kind => panic!("binding {} is a {kind:?}, not a texel view", view.binding),
            };
            assert!(
                view.of.usage().contains(usage),
                "{:?} cannot be viewed as {:?}",
                view.of,
                view.kind
            );
        }
        let mut bindings: Vec<u32> = TEXEL_VIEWS.iter().map(|v| v.binding).collect();
        bindings.sort_unstable();
        bindings.dedup();
        assert_eq!(bindings.len(), TEXEL_VIEWS.len());
    }
}
