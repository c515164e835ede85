//! The engine the embedded runs draw in: the test host's device, a render-pass target (a
//! resize makes a new one, with a new render pass), one command buffer submitted and waited
//! for per step, and its checks at the end: no validation message (those raised while its
//! device is destroyed included) and every buffer the renderer had from its allocator given
//! back.

use ash::vk;
use ellipsoid_splat::{Camera, DeviceFeatures, Pass, Target};
use ellipsoid_splat_test_host::{
    standard_finite_perspective, DepthKind, Host, HostTarget, TargetKind,
};
use glam::{DMat4, DVec3};

use super::fault::host_call;
use super::layer::layer;
use super::walk::Bits;

/// An error of an embedded run: the renderer's, or the host's own (a submission that found
/// the device lost, say).
#[derive(Debug)]
pub enum HostOr<E> {
    Renderer(E),
    Host(String),
}

impl<E: std::fmt::Display> std::fmt::Display for HostOr<E> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HostOr::Renderer(e) => write!(f, "{e}"),
            HostOr::Host(e) => write!(f, "host: {e}"),
        }
    }
}

impl<E> HostOr<E> {
    /// Whether the host's own call found the device lost.
    pub fn host_lost(&self) -> bool {
        matches!(self, HostOr::Host(e) if e.contains("ERROR_DEVICE_LOST"))
    }
}

/// The test host with its target.
pub struct HostSide {
    pub host: Host,
    pub target: HostTarget,
    /// Targets replaced by a resize: their render passes outlive the renderer.
    old_targets: Vec<HostTarget>,
    /// The host allocator's allocations the host made itself (its targets').
    own_allocations: usize,
}

const NEAR: f64 = 0.5;
const FAR: f64 = 60.0;
const FOV_Y: f64 = 0.9;

impl HostSide {
    /// The host and a `width` x `height` target (not what a walk looks into: paused).
    pub fn new(width: u32, height: u32) -> Result<HostSide, String> {
        layer().paused(|| {
            let mut host = Host::new(true)?;
            let target = new_target(&mut host, width, height)?;
            let own_allocations = live_allocations(&mut host);
            Ok(HostSide {
                host,
                target,
                old_targets: Vec::new(),
                own_allocations,
            })
        })
    }

    /// The renderer's features the host's device enables.
    pub fn features(&self) -> DeviceFeatures {
        let mut features = DeviceFeatures::default();
        features.maintenance4 = true;
        features.dynamic_rendering = self.host.dynamic_rendering();
        features.sample_rate_shading = self.host.dynamic_rendering();
        if self.host.int64_atomics() {
            features = features.union(DeviceFeatures::COMPUTE_SPLAT);
        }
        features
    }

    /// The renderer's target: the host target's render pass.
    pub fn pass(&self) -> Target {
        Target::new(Pass::RenderPass {
            render_pass: self.target.render_pass(),
            subpass: 0,
            color_attachment_count: 1,
            depth_format: HostTarget::DEPTH_FORMAT,
        })
    }

    /// A new target of `width` x `height`, with a render pass of its own (paused).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), String> {
        let before = live_allocations(&mut self.host);
        let target = layer().paused(|| new_target(&mut self.host, width, height))?;
        self.own_allocations += live_allocations(&mut self.host) - before;
        self.old_targets
            .push(std::mem::replace(&mut self.target, target));
        Ok(())
    }

    /// The camera of a view from `eye` at column `x`, `width` wide and the target's height,
    /// from the host's matrices (standard depth, as the target clears it).
    pub fn camera(&self, eye: DVec3, x: u32, width: u32) -> Camera {
        let height = self.target.extent().height;
        let view = DMat4::look_at_rh(eye, DVec3::ZERO, DVec3::Y);
        let projection =
            standard_finite_perspective(FOV_Y, width as f64 / height as f64, NEAR, FAR);
        Camera::from_view_projection(view, projection, width, height)
            .and_then(|c| c.with_viewport_origin(x, 0))
            .expect("a valid camera")
    }

    /// One submission: `record` records into the command buffer (outside the pass; it may
    /// begin and end the target's pass, and says whether it drew); then submit, wait, and the
    /// picture if one was drawn. After a renderer error the command buffer is dropped
    /// unsubmitted.
    pub fn submit<E>(
        &mut self,
        record: impl FnOnce(&mut Host, &HostTarget, vk::CommandBuffer) -> Result<bool, E>,
    ) -> Result<Option<Bits>, HostOr<E>> {
        let cmd = host_call(|| self.host.begin()).map_err(HostOr::Host)?;
        let drew = record(&mut self.host, &self.target, cmd).map_err(HostOr::Renderer)?;
        host_call(|| self.host.submit_and_wait()).map_err(HostOr::Host)?;
        if !drew {
            return Ok(None);
        }
        let rgba = self.target.read_rgba().map_err(HostOr::Host)?;
        Ok(Some(
            rgba.chunks_exact(4)
                .map(|p| u32::from_le_bytes([p[0], p[1], p[2], p[3]]))
                .collect(),
        ))
    }

    /// Waits until the device is idle (its result: a lost device says so, once it is idle).
    pub fn wait_idle(&self) -> Result<(), String> {
        // SAFETY: the host's device; waiting has no other precondition.
        host_call(|| unsafe { self.host.device().device_wait_idle() })
            .map_err(|e| format!("vkDeviceWaitIdle: {e:?}"))
    }

    /// The host allocator's live allocations that are not the host's own: the renderer's.
    pub fn renderer_allocations(&mut self) -> usize {
        live_allocations(&mut self.host) - self.own_allocations
    }

    /// Destroys the targets and the host (paused); the error lists the validation messages
    /// of the whole run, its teardown included.
    pub fn finish(self) -> Result<(), String> {
        let HostSide {
            mut host,
            target,
            old_targets,
            ..
        } = self;
        let log = host.message_log();
        layer().paused(|| {
            for target in old_targets.into_iter().chain([target]) {
                target.destroy(&mut host);
            }
            drop(host);
        });
        let messages = log.lock().map(|m| m.clone()).unwrap_or_default();
        match messages.is_empty() {
            true => Ok(()),
            false => Err(format!("validation: {}", messages.join(" | "))),
        }
    }
}

fn live_allocations(host: &mut Host) -> usize {
    host.allocator_mut().generate_report().allocations.len()
}

fn new_target(host: &mut Host, width: u32, height: u32) -> Result<HostTarget, String> {
    HostTarget::new(
        host,
        TargetKind::RenderPass,
        DepthKind::StandardFinite,
        vk::SampleCountFlags::TYPE_1,
        width,
        height,
    )
}
