//! The icosphere baselines' vertex and index buffers (`mesh-L0` ... `mesh-L4`), uploaded on
//! first use of each level.

use ash::vk;

use crate::allocator::{MemoryAllocator, MemoryUse};
use crate::error::{Error, Result};
use crate::gpu::GpuBuffer;

use super::icosphere::icosphere;

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
        allocator: &mut dyn MemoryAllocator,
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
        let upload = |allocator: &mut dyn MemoryAllocator, name, bytes: &[u8], usage| {
            let mut buffer = GpuBuffer::new(
                device,
                allocator,
                name,
                bytes.len() as u64,
                usage,
                MemoryUse::Upload,
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

    /// Binds the vertex and index buffers of icosphere `level`, if it was uploaded.
    ///
    /// # Safety
    /// `cmd` is recording; the buffers outlive its execution.
    pub unsafe fn bind(&self, device: &ash::Device, cmd: vk::CommandBuffer, level: u32) {
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
    pub unsafe fn destroy(&mut self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        for mesh in self.levels.drain(..) {
            // SAFETY: caller contract.
            unsafe {
                mesh.vertices.destroy(device, allocator);
                mesh.indices.destroy(device, allocator);
            }
        }
    }
}
