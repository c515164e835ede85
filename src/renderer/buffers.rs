//! The renderer's buffers, one per descriptor binding, as one table: each grows
//! through the same rule (a buffer too small is replaced, and the old one retired until no
//! recorded frame can use it).

use crate::allocator::MemoryAllocator;
use crate::allocator::MemoryUse;
use ash::vk;

use crate::error::{Error, Result};
use crate::frame_slots::{FrameSlots, Retired};
use crate::gpu::GpuBuffer;

/// The bindings of the renderer's descriptor set, each backed by one buffer.
///
/// Descriptor set 0, one buffer per `Binding` (`src/renderer/buffers.rs`), each chunk's set
/// pointing at its slices (design §5.4): storage buffers, but the instances, which every
/// shader only reads, are a uniform texel buffer, bindings 12 to 14 view the visibility
/// buffer, the occlusion tiles and the shading records as such for the passes that only read
/// them, and binding 15 views the shading records as a storage texel buffer for their writers:
///
/// | binding | `Binding` | contents | stages | per chunk |
/// |---:|---|---|---|---|
/// | 0 | `Instances` | instances (`Instance`, `CompactInstance`), a uniform texel buffer of `R32G32B32A32_UINT` texels | vertex, fragment (the splat's resolve), compute | slice |
/// | 1 | `FragmentCounter` | shaded fragments (`COUNT_FRAGMENTS`) and the compute splat's ray casts (`COUNT_RAY_CASTS`); host-visible | fragment, compute | whole |
/// | 2 | `Visible` | visible instance indices (`uint` each) | vertex, compute | slice |
/// | 3 | `IndirectDraw` | `IndirectDraw` | compute | the chunk's 40 bytes at `256 k` |
/// | 4 | `CullGroups` | per group of 256: 8 words of keep bits; after all groups, one count per group (SCAN turns it into the first output slot) (written by CLASSIFY, or by the compute splat for the glyphs it leaves to the draw) | compute | the chunk's slice, 256-aligned |
/// | 5 | `OcclusionTiles` | occlusion tiles (`uint` per 4 x 4 tile, row-major from the top left: view-depth float bits for the culled draw, depth-buffer value bits for the visible-first splat, whose second `CLASSIFY` and second splat pass read them through binding 13; `glsl/include/occlusion_tiles.glsl`) | compute | whole, shared |
/// | 6 | `ShadingRecords` | `ShadingRecord`s, written through binding 15 by CLASSIFY for the set-up-once draw or by the compute splat for its resolve (which reads them through binding 14) | fragment | slice (whole beyond `MAX_SETUP_ONCE_INSTANCES`) |
/// | 7 | `FootprintRecords` | `FootprintRecord`s | vertex, compute | slice (likewise) |
/// | 8 | `Visibility` | the compute splat's nearest hit per pixel, then its resolve tiles (`uint64_t`, row-major, design §5.6); its readers read it through binding 12 | compute, fragment (the benchmark's visibility draw) | whole, shared |
/// | 9 | `FloorPixels` | the visible-pixel floor's lists (host-visible; 8 bytes unless the benchmark sets them, design §5.7) | compute | whole |
/// | 10 | `GlyphStamps` | per glyph the stamps of the last frame that showed it and that left it to the draw (design §5.7) | compute | whole (frames with stamps have one chunk) |
/// | 11 | `TileLists` | the benchmark's tiled splat's lists (`research`; 8 bytes otherwise): per 8 x 8 tile and depth bucket a count and a first slot, 112 bytes per glyph (box, nearest depth, the hit's set-up), 64 entries of room per glyph (`glsl/research/tile_lists.glsl`) | compute | whole |
/// | 12 | (`VISIBILITY_KEYS` in `src/renderer/descriptors.rs`) | binding 8's buffer as a uniform texel buffer of `R32G32_UINT` texels, a key each, for the passes that only read it (the resolve, `KEY_TILES`, `MARK_SHOWN`) | vertex, fragment, compute | whole, shared |
/// | 13 | (`OCCLUSION_TILE_WORDS` there) | binding 5's buffer as a uniform texel buffer of `R32_UINT` texels, a tile's word each, for the visible-first splat's second `CLASSIFY` and second splat pass | compute | whole, shared |
/// | 14 | (`SHADING_RECORD_TEXELS` there) | binding 6's slice as a uniform texel buffer of `R32G32B32A32_UINT` texels, 8 a record, for the splat's resolve | fragment | slice (likewise) |
/// | 15 | (`SHADING_RECORD_STORES` there) | binding 6's slice as a storage texel buffer of the same texels, through which the pre-pass writes the records | compute | slice (likewise) |
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Binding {
    /// The instance records.
    Instances = 0,
    /// The benchmark's counts of shaded pixels and of the compute splat's ray casts.
    FragmentCounter = 1,
    /// Instance indices kept by the pre-pass.
    Visible = 2,
    /// The pre-pass's indirect draw commands, one slice per chunk.
    IndirectDraw = 3,
    /// The pre-pass's keep bits and group slots.
    CullGroups = 4,
    /// The pre-pass's occlusion tiles.
    OcclusionTiles = 5,
    /// Set-up records for the fragment stage.
    ShadingRecords = 6,
    /// Set-up records for the vertex stage.
    FootprintRecords = 7,
    /// The compute splat's nearest hit per pixel.
    Visibility = 8,
    /// The benchmark's visible-pixel floor: per glyph, the pixels it shows.
    FloorPixels = 9,
    /// The visible-first splat's glyph stamps: when each glyph last showed, or was left to
    /// the draw.
    GlyphStamps = 10,
    /// The benchmark's tiled splat: per screen tile, the glyphs whose box touches it.
    TileLists = 11,
}

impl Binding {
    /// Every binding, in binding order.
    pub const ALL: [Binding; 12] = [
        Binding::Instances,
        Binding::FragmentCounter,
        Binding::Visible,
        Binding::IndirectDraw,
        Binding::CullGroups,
        Binding::OcclusionTiles,
        Binding::ShadingRecords,
        Binding::FootprintRecords,
        Binding::Visibility,
        Binding::FloorPixels,
        Binding::GlyphStamps,
        Binding::TileLists,
    ];

    /// Whether each view of a frame has a buffer of its own (what its pre-pass computes for
    /// its camera), or all share the renderer's (the instances, the benchmark's counters and
    /// floor lists).
    pub fn per_view(self) -> bool {
        !matches!(
            self,
            Binding::Instances | Binding::FragmentCounter | Binding::FloorPixels
        )
    }

    /// The shader stages that read or write the binding.
    pub fn stages(self) -> vk::ShaderStageFlags {
        let vertex_and_compute = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::COMPUTE;
        match self {
            // The compute splat's resolve reads the instances in the fragment stage.
            Binding::Instances => vertex_and_compute | vk::ShaderStageFlags::FRAGMENT,
            Binding::Visible | Binding::FootprintRecords => vertex_and_compute,
            // Fragments count shaded pixels, the compute splat its ray casts.
            Binding::FragmentCounter => {
                vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE
            }
            Binding::IndirectDraw
            | Binding::CullGroups
            | Binding::OcclusionTiles
            | Binding::FloorPixels
            | Binding::GlyphStamps
            | Binding::TileLists => vk::ShaderStageFlags::COMPUTE,
            // Read by the set-up-once draw's fragment stage; written through binding 15.
            Binding::ShadingRecords => vk::ShaderStageFlags::FRAGMENT,
            // Written by the splat, and by the benchmark's visibility draw (fragment); its
            // readers see it through binding 12 (`VISIBILITY_KEYS`).
            Binding::Visibility => vk::ShaderStageFlags::COMPUTE | vk::ShaderStageFlags::FRAGMENT,
        }
    }

    /// How the shaders see the binding: the instances as a uniform texel buffer (lavapipe
    /// gathers a texel fetch's lanes, and reads a storage buffer lane by lane), the rest as
    /// storage buffers.
    pub fn descriptor_type(self) -> vk::DescriptorType {
        match self {
            Binding::Instances => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
            _ => vk::DescriptorType::STORAGE_BUFFER,
        }
    }

    /// Name of the buffer (allocation names and errors).
    pub fn name(self) -> &'static str {
        match self {
            Binding::Instances => "ellipsoid instances",
            Binding::FragmentCounter => "fragment and ray-cast counters",
            Binding::Visible => "visible instances",
            Binding::IndirectDraw => "culled draw",
            Binding::CullGroups => "culling groups",
            Binding::OcclusionTiles => "occlusion tiles",
            Binding::ShadingRecords => "shading set-up",
            Binding::FootprintRecords => "footprint set-up",
            Binding::Visibility => "visibility buffer",
            Binding::FloorPixels => "visible-pixel floor",
            Binding::GlyphStamps => "glyph stamps",
            Binding::TileLists => "tiled splat lists",
        }
    }

    /// How the buffer is used: as its binding says, and filled or read indirectly where
    /// marked.
    pub fn usage(self) -> vk::BufferUsageFlags {
        let extra = match self {
            // Filled with vkCmdFillBuffer (the compute splat zeroes the keep bits, and the
            // stamps of a new scene).
            Binding::Instances
            | Binding::OcclusionTiles
            | Binding::Visibility
            | Binding::CullGroups
            | Binding::GlyphStamps
            | Binding::TileLists => vk::BufferUsageFlags::TRANSFER_DST,
            Binding::IndirectDraw => {
                vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST
            }
            _ => vk::BufferUsageFlags::empty(),
        };
        match self {
            // Only ever read through texel views (binding 0).
            Binding::Instances => vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER | extra,
            Binding::ShadingRecords => {
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
                    | vk::BufferUsageFlags::STORAGE_TEXEL_BUFFER
                    | extra
            }
            // Also read through binding 12's and 13's texel views.
            Binding::Visibility | Binding::OcclusionTiles => {
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
                    | extra
            }
            _ => vk::BufferUsageFlags::STORAGE_BUFFER | extra,
        }
    }

    /// Where the buffer lives: the counter is read by the host and the floor's pixel lists
    /// written by it; the rest only the GPU touches.
    pub fn memory_use(self) -> MemoryUse {
        match self {
            Binding::FragmentCounter => MemoryUse::Readback,
            Binding::FloorPixels => MemoryUse::Upload,
            _ => MemoryUse::GpuOnly,
        }
    }
}

/// One buffer per [`Binding`], each made on first need and grown on demand.
#[derive(Default)]
pub(crate) struct SceneBuffers {
    buffers: [Option<GpuBuffer>; 12],
    /// A buffer was replaced since the descriptor sets were written.
    pub replaced: bool,
}

impl SceneBuffers {
    /// The buffer of `binding`, if it exists.
    pub fn get(&self, binding: Binding) -> Option<&GpuBuffer> {
        self.buffers[binding as usize].as_ref()
    }

    /// The handle of `binding`'s buffer, or an error naming it.
    pub fn handle(&self, binding: Binding) -> Result<vk::Buffer> {
        self.get(binding).map(GpuBuffer::handle).ok_or_else(|| {
            Error::invalid(
                "descriptor set",
                format!(
                    "binding {} ({}) has no buffer",
                    binding as u32,
                    binding.name()
                ),
            )
        })
    }

    /// The buffer of `binding`, mutably (the host-visible counter; the research module's).
    #[allow(dead_code)]
    pub fn get_mut(&mut self, binding: Binding) -> Option<&mut GpuBuffer> {
        self.buffers[binding as usize].as_mut()
    }

    /// Makes `binding`'s buffer hold at least `bytes`: a smaller one is replaced and retired
    /// into `slots` until no recorded frame can use it.
    pub fn ensure(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        slots: &mut FrameSlots<Retired>,
        binding: Binding,
        bytes: u64,
    ) -> Result<()> {
        if self.get(binding).is_some_and(|b| b.size() >= bytes) {
            return Ok(());
        }
        self.replace(device, allocator, slots, binding, bytes)
            .map(|_| ())
    }

    /// Replaces `binding`'s buffer by a new one of `bytes` (the old one retired into `slots`
    /// until no recorded frame can use it). If the new one cannot be made, the old one stays.
    pub fn replace(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        slots: &mut FrameSlots<Retired>,
        binding: Binding,
        bytes: u64,
    ) -> Result<&mut GpuBuffer> {
        let buffer = GpuBuffer::new(
            device,
            allocator,
            binding.name(),
            bytes,
            binding.usage(),
            binding.memory_use(),
        )?;
        Ok(self.install(slots, binding, buffer))
    }

    /// Makes `buffer` `binding`'s (the old one retired into `slots` until no recorded frame
    /// can use it).
    pub fn install(
        &mut self,
        slots: &mut FrameSlots<Retired>,
        binding: Binding,
        buffer: GpuBuffer,
    ) -> &mut GpuBuffer {
        if let Some(old) = self.buffers[binding as usize].take() {
            slots.retire(Retired::Buffer(old));
        }
        self.replaced = true;
        self.buffers[binding as usize].insert(buffer)
    }

    /// Bytes of memory the allocator gave all buffers.
    pub fn memory_bytes(&self) -> u64 {
        self.buffers
            .iter()
            .flatten()
            .map(GpuBuffer::memory_bytes)
            .sum()
    }

    /// Destroys every buffer.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        for buffer in self.buffers.iter_mut().filter_map(Option::take) {
            // SAFETY: caller contract.
            unsafe { buffer.destroy(device, allocator) };
        }
    }
}
