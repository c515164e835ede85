//! Without the `research` feature: what the renderer's code asks of the research module,
//! answered for a renderer that draws only the shipped impostor. `Baseline` has no value, so
//! a frame plan never holds one and every baseline branch is dead code the compiler proves so.

use ash::vk;

use crate::allocator::MemoryAllocator;
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::footprint::Footprint;
use crate::gpu::shaders::FragmentShader;
use crate::gpu_layout::{PushConstants, SpecConstants};
use crate::renderer::pipelines::raster::Raster;
use crate::renderer::prepass::TracedDispatch;
use crate::renderer::{EllipsoidRenderer, FramePlan};
use crate::target::Target;

/// A benchmark baseline: none exists without the feature.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Baseline {}

#[allow(clippy::unused_self)]
impl Baseline {
    pub fn check_camera(self, _orthographic: bool) -> Result<()> {
        match self {}
    }
    pub fn through_prepass(self) -> bool {
        match self {}
    }
    pub fn setup_once_allowed(self) -> bool {
        match self {}
    }
    pub fn visibility_draw(self) -> bool {
        match self {}
    }
    pub fn vertices(self, _chosen: Footprint) -> u32 {
        match self {}
    }
    pub fn specialize(self, _chosen: Footprint, _constants: &mut SpecConstants) {
        match self {}
    }
    pub fn stages(self, _setup_once: bool) -> Result<(&'static [u8], FragmentShader)> {
        match self {}
    }
    pub fn raster(self) -> Raster {
        match self {}
    }
    pub fn own_pass_target(self) -> Option<Target> {
        match self {}
    }
}

/// The research state of a renderer without the feature: nothing.
#[derive(Default)]
pub(crate) struct Research {}

impl Research {
    pub fn baseline(&self) -> Option<Baseline> {
        None
    }
    pub fn count_fragments(&self) -> bool {
        false
    }
    pub fn splat_floor(&self) -> u32 {
        0
    }
    pub fn tiled_splat(&self) -> bool {
        false
    }
    pub fn splat_variant(&self) -> bool {
        false
    }
    pub fn forget_upload(&mut self) {}
    pub fn forget_instances(&mut self) {}
    pub fn prepare(
        &mut self,
        _device: &ash::Device,
        _allocator: &mut dyn MemoryAllocator,
        _plan: &FramePlan,
    ) -> Result<()> {
        Ok(())
    }
    /// # Safety
    /// Never called: no baseline exists.
    pub unsafe fn record_draw(
        &self,
        _device: &ash::Device,
        _cmd: vk::CommandBuffer,
        baseline: Baseline,
        _indirect: Option<(vk::Buffer, u64)>,
        _count: u32,
        _footprint: Footprint,
    ) {
        match baseline {}
    }
    /// # Safety
    /// Nothing to destroy.
    pub unsafe fn destroy(&mut self, _device: &ash::Device, _allocator: &mut dyn MemoryAllocator) {}
}

/// No traced path without the feature: no device is asked for ray queries.
///
/// # Safety
/// None needed: it calls nothing.
#[cfg(feature = "offscreen")]
pub(crate) unsafe fn ray_query_supported(
    _instance: &ash::Instance,
    _physical_device: vk::PhysicalDevice,
) -> bool {
    false
}

/// The benchmark's tiled splat exists only with the feature.
pub(crate) const TILED_SPLAT_COMP: &[u8] = &[];
/// Likewise its binning steps.
pub(crate) const TILED_BINS_COMP: &[u8] = &[];

/// The counting builds exist only with the feature.
pub(crate) fn counted(shader: &FragmentShader, _aux: bool) -> Result<&'static [u8]> {
    Err(Error::invalid(
        "fragment shader",
        format!(
            "{}'s counting build needs the `research` feature",
            shader.name
        ),
    ))
}

/// No frame counts without the feature.
#[cfg(feature = "offscreen")]
pub(crate) fn begin_counting(
    _renderer: &mut EllipsoidRenderer,
    _readback: bool,
    _supported: bool,
) -> Result<bool> {
    Ok(false)
}

/// No counts without the feature.
#[cfg(feature = "offscreen")]
pub(crate) fn counts(_renderer: &EllipsoidRenderer) -> (Option<u64>, Option<u64>) {
    (None, None)
}

impl EllipsoidRenderer {
    /// No floor, nothing to check.
    pub(crate) fn check_floor_pixels(&self, _plan: &FramePlan) -> Result<()> {
        Ok(())
    }

    /// No traced path without the feature: every frame splats.
    ///
    /// # Safety
    /// None needed: it records nothing.
    pub(crate) unsafe fn record_traced_build(
        &mut self,
        _device: &ash::Device,
        _allocator: &mut dyn MemoryAllocator,
        _cmd: vk::CommandBuffer,
        _plan: &FramePlan,
        _set0: vk::DescriptorSet,
        _push: &PushConstants,
    ) -> Result<Option<TracedDispatch>> {
        Ok(None)
    }

    /// Never called: only a baseline draws into the visibility buffer.
    ///
    /// # Safety
    /// None needed: it records nothing.
    pub(crate) unsafe fn record_visibility_draw(
        &mut self,
        _device: &ash::Device,
        _cmd: vk::CommandBuffer,
        _view: usize,
        _camera: &Camera,
        _plan: &FramePlan,
        _pipeline: vk::Pipeline,
    ) -> Result<()> {
        Ok(())
    }

    /// Without the feature nothing counts (the offscreen renderer's counting frames call it).
    ///
    /// # Safety
    /// None needed: it records nothing.
    #[cfg(feature = "offscreen")]
    pub(crate) unsafe fn record_counter_barrier(
        &self,
        _device: &ash::Device,
        _cmd: vk::CommandBuffer,
    ) {
    }
}
