//! Scenes beyond one storage-buffer binding: the instances are split into chunks, each with
//! its own descriptor set (slices of the scene's buffers), pre-pass and draw, in instance
//! order so depth ties resolve as in one draw.
//!
//! The renderer splits the scene into chunks of `min(maxStorageBufferRange / stride,
//! 16 maxTexelBufferElements / stride, Settings::max_chunk_instances)` instances (the instances
//! are read as 16-byte texels, the other slices as storage buffers), rounded down to a
//! multiple of 256 and at least 256
//! (so every slice stays aligned). The scene's buffers stay whole; each chunk gets its own
//! descriptor set pointing at its slices (instances, visible list, indirect command at `256 k`,
//! groups and, for scenes that have them, set-up records), its own pre-pass and its own draw. The
//! push constant `first_instance` holds the chunk's first instance: shaders index chunk-relative
//! and write the global ID `v_id + first_instance`. The occlusion tiles (and the fragment counter)
//! are bound whole and shared by all chunks.

use super::plan::MAX_SETUP_ONCE_INSTANCES;

/// Alignment of each chunk's slice of a buffer: a multiple of every device's
/// `minStorageBufferOffsetAlignment` (at most 256 by the specification).
pub(crate) const SLICE_ALIGN: u64 = 256;

/// How a scene of `count` instances is split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Chunking {
    /// Instances per chunk, a multiple of 256 so every slice stays aligned.
    pub capacity: u32,
    /// Instances in the scene.
    pub count: u32,
}

impl Chunking {
    /// Chunks of as many instances of `stride` bytes as one binding of `max_range` bytes
    /// holds, and at most `max_instances`.
    pub fn new(count: u32, stride: usize, max_range: u64, max_instances: u32) -> Self {
        let by_device = max_range / stride as u64;
        let capacity = by_device.min(max_instances as u64) / 256 * 256;
        Self {
            capacity: capacity.max(256) as u32,
            count,
        }
    }

    /// The chunks: (first instance, instances); none for an empty scene.
    pub fn chunks(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        (0..self.count.div_ceil(self.capacity)).map(|k| {
            let first = k * self.capacity;
            (first, self.capacity.min(self.count - first))
        })
    }

    /// The bytes one binding read both as a storage buffer and through a texel view of
    /// `texel` bytes a texel may hold on a device of `limits` (the instances: 16; the
    /// visibility buffer's keys: 8).
    pub fn max_binding_bytes(limits: &ash::vk::PhysicalDeviceLimits, texel: u64) -> u64 {
        (limits.max_storage_buffer_range as u64)
            .min(limits.max_texel_buffer_elements as u64 * texel)
    }

    /// Whether the scene has set-up records, one per instance (at most
    /// `MAX_SETUP_ONCE_INSTANCES` instances: beyond, each record buffer holds one).
    pub fn has_records(&self) -> bool {
        self.count <= MAX_SETUP_ONCE_INSTANCES
    }

    /// Whether the scene has set-up records and each chunk's shading records fit one binding
    /// read and written through texel views of 16-byte texels on a device of `limits`.
    pub fn shading_records_fit(&self, limits: &ash::vk::PhysicalDeviceLimits) -> bool {
        let largest = self.capacity.min(self.count) as u64;
        let bytes = largest * size_of::<crate::gpu_layout::ShadingRecord>() as u64;
        self.has_records() && bytes <= Self::max_binding_bytes(limits, 16)
    }

    /// Number of chunks (at least one, so an empty scene still has a descriptor set).
    pub fn len(&self) -> u32 {
        self.count.div_ceil(self.capacity).max(1)
    }

    /// Bytes of one chunk's slice of the culling-groups buffer.
    pub fn groups_slice(&self) -> u64 {
        let chunk = self.capacity.min(self.count.max(1));
        super::prepass::steps::groups_bytes(chunk).next_multiple_of(SLICE_ALIGN)
    }
}
