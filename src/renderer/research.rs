//! The benchmark's side of the renderer (feature `research`): drawing with a baseline
//! configuration, icosphere meshes, and counting shaded pixels.

use ash::vk;
use gpu_allocator::vulkan::Allocator;
use gpu_allocator::MemoryLocation;

use crate::barriers;
use crate::draw::{DrawConfig, Geometry};
use crate::error::{Error, Result};
use crate::gpu::GpuBuffer;
use crate::icosphere::icosphere;

use super::buffers::Binding;
use super::EllipsoidRenderer;

impl EllipsoidRenderer {
    /// Draws with `config` from the next frame on (a baseline of the benchmark; the shipped
    /// renderer is `DrawConfig::default()`). Builds that configuration's pipelines on first
    /// use.
    pub fn set_draw_config(&mut self, config: DrawConfig) {
        self.config = config;
    }

    /// The configuration frames are drawn with.
    pub fn draw_config(&self) -> DrawConfig {
        self.config
    }

    /// Replaces the compute splat by one of its floors, for the benchmark's roofline: 1 reads
    /// every instance and nothing else, 2 ray casts every pixel centre without the atomics
    /// (and neither resolves); 0 is the splat itself. Frames that do not splat are unchanged.
    pub fn set_splat_floor(&mut self, floor: u32) {
        self.splat_floor = floor.min(2);
    }

    /// Counts shaded pixels with an atomic in separate builds of the fragment shaders (needs
    /// `fragmentStoresAndAtomics`); their arithmetic may round differently from the shipped
    /// ones.
    pub fn set_count_fragments(&mut self, on: bool) {
        self.count_fragments = on;
    }

    /// Zeroes the fragment counter; call before submitting a counting frame.
    pub fn reset_fragment_counter(&mut self) -> Result<()> {
        match self.buffers.get_mut(Binding::FragmentCounter) {
            Some(c) => c.write(&0u32.to_ne_bytes()),
            None => Ok(()),
        }
    }

    /// Pixels shaded by the last counting frame (after its fence, and after the barrier of
    /// [`EllipsoidRenderer::record_counter_barrier`]).
    pub fn fragment_count(&self) -> Option<u32> {
        let bytes = self.buffers.get(Binding::FragmentCounter)?.mapped()?;
        Some(u32::from_ne_bytes(bytes.get(..4)?.try_into().ok()?))
    }

    /// Makes the counter's atomic writes visible to the host; record after the pass.
    ///
    /// # Safety
    /// `cmd` is a command buffer of `device` recording outside a pass.
    pub unsafe fn record_counter_barrier(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: caller contract.
        unsafe { barriers::COUNTER_TO_HOST.record(device, cmd) };
    }
}

/// One icosphere level on the GPU.
struct MeshBuffers {
    level: u32,
    vertices: GpuBuffer,
    indices: GpuBuffer,
    index_count: u32,
}

/// The icosphere levels uploaded so far.
#[derive(Default)]
pub(crate) struct Meshes {
    levels: Vec<MeshBuffers>,
}

impl Meshes {
    /// Uploads icosphere `level` if it is not on the GPU yet.
    pub fn ensure(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        level: u32,
    ) -> Result<()> {
        if level > 4 {
            return Err(Error::invalid(
                "mesh level",
                format!("{level} is outside 0..=4"),
            ));
        }
        if self.levels.iter().any(|m| m.level == level) {
            return Ok(());
        }
        let mesh = icosphere(level);
        let vertex_bytes: &[u8] = bytemuck::cast_slice(&mesh.positions);
        let index_bytes: &[u8] = bytemuck::cast_slice(&mesh.indices);
        let upload = |allocator: &mut Allocator, name, bytes: &[u8], usage| {
            let mut buffer = GpuBuffer::new(
                device,
                allocator,
                name,
                bytes.len() as u64,
                usage,
                MemoryLocation::CpuToGpu,
            )?;
            if let Err(e) = buffer.write(bytes) {
                // SAFETY: just made, never used.
                unsafe { buffer.destroy(device, allocator) };
                return Err(e);
            }
            Ok(buffer)
        };
        let vertices = upload(
            allocator,
            "icosphere vertices",
            vertex_bytes,
            vk::BufferUsageFlags::VERTEX_BUFFER,
        )?;
        let indices = match upload(
            allocator,
            "icosphere indices",
            index_bytes,
            vk::BufferUsageFlags::INDEX_BUFFER,
        ) {
            Ok(b) => b,
            Err(e) => {
                // SAFETY: just made, never used.
                unsafe { vertices.destroy(device, allocator) };
                return Err(e);
            }
        };
        self.levels.push(MeshBuffers {
            level,
            vertices,
            indices,
            index_count: mesh.indices.len() as u32,
        });
        Ok(())
    }

    /// Indices of icosphere `level` (0 if it was never uploaded).
    pub fn index_count(&self, level: u32) -> u32 {
        self.levels
            .iter()
            .find(|m| m.level == level)
            .map_or(0, |m| m.index_count)
    }

    /// Binds the vertex and index buffers of `geometry`'s mesh, if it is one.
    ///
    /// # Safety
    /// `cmd` is recording; the buffers outlive its execution.
    pub unsafe fn bind(&self, device: &ash::Device, cmd: vk::CommandBuffer, geometry: Geometry) {
        let Geometry::Mesh(level) = geometry else {
            return;
        };
        if let Some(mesh) = self.levels.iter().find(|m| m.level == level) {
            // SAFETY: caller contract; the buffers are live.
            unsafe {
                device.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.handle()], &[0]);
                device.cmd_bind_index_buffer(cmd, mesh.indices.handle(), 0, vk::IndexType::UINT32);
            }
        }
    }

    /// Destroys every mesh.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device, allocator: &mut Allocator) {
        for mesh in self.levels.drain(..) {
            // SAFETY: caller contract.
            unsafe {
                mesh.vertices.destroy(device, allocator);
                mesh.indices.destroy(device, allocator);
            }
        }
    }
}
