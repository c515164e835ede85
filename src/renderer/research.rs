//! The benchmark's side of the renderer (feature `research`): drawing with a baseline
//! configuration, icosphere meshes, and counting shaded pixels.

use crate::allocator::MemoryAllocator;
use crate::allocator::MemoryUse;
use ash::vk;

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
    /// every instance and nothing else, 2 ray casts every pixel centre without the atomics, 3
    /// ray casts only the pixels each glyph shows (given by `set_floor_pixels` for the
    /// uploaded scene; a frame without them is an error), and none resolves; 0 is the splat
    /// itself. Frames that do not splat are unchanged.
    pub fn set_splat_floor(&mut self, floor: u32) {
        self.splat_floor = floor.min(3);
    }

    /// Forgets which glyphs the last frame showed, so that the next frame is drawn as a first
    /// frame of its scene would be (no visible-first splat; it stamps what it shows again):
    /// what the benchmark's `impostor-first-frame` measures.
    pub fn forget_shown(&mut self) {
        for view in &mut self.views {
            view.shown_stamped = None;
        }
    }

    /// Gives the visible-pixel floor (`set_splat_floor(3)`) the pixels each glyph shows:
    /// `ids` holds, row-major in rows of `width`, the scene index of the glyph each pixel
    /// shows (`u32::MAX` or any index beyond the scene: none), e.g. the float64 reference's.
    /// The floor's pass then reads every instance once and ray casts exactly these pixels,
    /// each once, keeping nothing. Writes a new host-visible buffer of 4 bytes per glyph and
    /// per visible pixel (the old one is retired).
    ///
    /// # Safety
    /// `device` is the renderer's device and `allocator` allocates from it.
    pub unsafe fn set_floor_pixels(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        ids: &[u32],
        width: u32,
    ) -> Result<()> {
        let lists = floor_pixel_lists(self.scene.count, ids, width)?;
        let buffer = self.buffers.replace(
            device,
            allocator,
            &mut self.slots,
            Binding::FloorPixels,
            4 * lists.len().max(2) as u64,
        )?;
        buffer.write(bytemuck::cast_slice(&lists))?;
        self.floor_pixels_for = Some(self.scene.count);
        Ok(())
    }

    /// Checks that a frame with `plan` can draw the visible-pixel floor: its lists were made
    /// for the uploaded scene.
    pub(crate) fn check_floor_pixels(&self, plan: &crate::FramePlan) -> Result<()> {
        if self.splat_floor == 3
            && plan.compute_splat
            && self.floor_pixels_for != Some(self.scene.count)
        {
            return Err(Error::invalid(
                "visible-pixel floor",
                "set_floor_pixels has not given the pixels of the uploaded scene",
            ));
        }
        Ok(())
    }

    /// Counts shaded pixels with an atomic in separate builds of the fragment shaders (needs
    /// `fragmentStoresAndAtomics`); their arithmetic may round differently from the shipped
    /// ones.
    pub fn set_count_fragments(&mut self, on: bool) {
        self.count_fragments = on;
    }

    /// Zeroes the fragment and ray-cast counters; call before submitting a counting frame.
    pub fn reset_fragment_counter(&mut self) -> Result<()> {
        match self.buffers.get_mut(Binding::FragmentCounter) {
            Some(c) => c.write(&[0; 8]),
            None => Ok(()),
        }
    }

    /// Pixels shaded by the last counting frame (after its fence, and after the barrier of
    /// [`EllipsoidRenderer::record_counter_barrier`]).
    pub fn fragment_count(&self) -> Option<u32> {
        let bytes = self.buffers.get(Binding::FragmentCounter)?.mapped()?;
        Some(u32::from_ne_bytes(bytes.get(..4)?.try_into().ok()?))
    }

    /// Ray casts the compute splat's passes made in the last counting frame (each evaluation
    /// of the exact hit at a pixel centre; the fragment stages' own are their shaded pixels).
    pub fn compute_ray_count(&self) -> Option<u32> {
        let bytes = self.buffers.get(Binding::FragmentCounter)?.mapped()?;
        Some(u32::from_ne_bytes(bytes.get(4..8)?.try_into().ok()?))
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

/// The visible-pixel floor's lists (GLSL `floor_pixels` in `splat.comp`): `count`, then
/// `count + 1` offsets, then per glyph its pixels as `x | y << 16`, in scene order.
fn floor_pixel_lists(count: u32, ids: &[u32], width: u32) -> Result<Vec<u32>> {
    if width == 0 || width > 1 << 16 || ids.len() % width as usize != 0 {
        return Err(Error::invalid(
            "floor pixels",
            format!("{} ids are no whole rows of {width} pixels", ids.len()),
        ));
    }
    // Pixels are packed as x | y << 16.
    if ids.len() / width as usize > 1 << 16 {
        return Err(Error::invalid(
            "floor pixels",
            format!("{} rows, more than 65536", ids.len() / width as usize),
        ));
    }
    let n = count as usize;
    let mut offsets = vec![0u32; n + 1];
    for &id in ids {
        if (id as usize) < n {
            offsets[id as usize + 1] += 1;
        }
    }
    for k in 0..n {
        offsets[k + 1] += offsets[k];
    }
    let mut pixels = vec![0u32; offsets[n] as usize];
    let mut next: Vec<u32> = offsets[..n].to_vec();
    for (at, &id) in ids.iter().enumerate() {
        if (id as usize) < n {
            let (x, y) = (at as u32 % width, at as u32 / width);
            pixels[next[id as usize] as usize] = x | y << 16;
            next[id as usize] += 1;
        }
    }
    Ok([&[count][..], &offsets, &pixels].concat())
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_lists_group_each_glyphs_pixels_in_order() {
        // 3 x 2 pixels: glyph 1 shows at (0,0) and (2,1), glyph 0 at (1,0); the rest nothing
        // or a glyph beyond the scene.
        let none = u32::MAX;
        let ids = [1, 0, none, 7, none, 1];
        let lists = floor_pixel_lists(3, &ids, 3).unwrap();
        assert_eq!(lists[0], 3);
        assert_eq!(
            &lists[1..5],
            &[0, 1, 3, 3],
            "offsets: glyph 0 one pixel, 1 two, 2 none"
        );
        assert_eq!(&lists[5..], &[1, 0, 2 | 1 << 16]);
        assert!(floor_pixel_lists(3, &ids, 4).is_err());
        assert!(floor_pixel_lists(3, &vec![0; (1 << 16) + 1], 1).is_err());
        assert!(floor_pixel_lists(3, &ids, 0).is_err());
    }
}
