//! Faults walked over a typical run of the embedded renderer in a host engine (the test
//! host: its device, allocator, render pass and command buffer): create, upload, frames, an
//! update, a resize (a new render pass), two views, a larger upload, destroy. Out of device
//! memory at each Vulkan call the renderer makes, the host's allocator refusing each buffer,
//! and the device lost at each call that can report it, the host's submissions and waits
//! included (where a host sees a loss).

mod support;

use ash::vk;
use ellipsoid_splat::PlanMode;
use ellipsoid_splat::{Camera, EllipsoidRenderer, Error, HostDevice, RendererOptions};
use glam::DVec3;
use support::allocator::{self, FailingAllocator};
use support::fault::Fault;
use support::host_side::{HostOr, HostSide};
use support::scenes;
use support::walk::{walk, Bits, Run, Step, Strides, TYPICAL_RUN};

#[derive(Default)]
struct Embedded {
    side: Option<HostSide>,
    renderer: Option<EllipsoidRenderer>,
    /// Frames begun, for the frame slot.
    frames: u32,
    /// The buffers the failing allocator saw live before the renderer existed.
    live_before: i64,
}

type Outcome = Result<Option<Bits>, HostOr<Error>>;

impl Embedded {
    fn side(&mut self) -> &mut HostSide {
        self.side.as_mut().expect("made by step 0")
    }

    /// One submission in the next frame slot: `work` records into its command buffer.
    fn submission(
        &mut self,
        work: impl FnOnce(
            &mut EllipsoidRenderer,
            &ash::Device,
            &mut FailingAllocator<'_>,
            &ellipsoid_splat_test_host::HostTarget,
            vk::CommandBuffer,
        ) -> Result<bool, Error>,
    ) -> Outcome {
        let slot = self.frames % 2;
        self.frames += 1;
        let renderer = self.renderer.as_mut().expect("made by step 0");
        let side = self.side.as_mut().expect("made by step 0");
        side.submit(|host, target, cmd| {
            let (device, allocator) = host.device_and_allocator();
            let mut allocator = FailingAllocator(allocator);
            // SAFETY: the host waited for every earlier submission, so the slot's work is
            // done; `cmd` is recording outside a pass.
            unsafe { renderer.begin_frame(device, &mut allocator, slot) }?;
            work(renderer, device, &mut allocator, target, cmd)
        })
    }

    /// A frame of `cameras`: each view's pre-pass, then the pass drawing them all.
    fn frame(&mut self, cameras: &[Camera]) -> Outcome {
        self.submission(|renderer, device, allocator, target, cmd| {
            // SAFETY: pre-passes outside the pass, draws inside it, in the host's command
            // buffer, submitted and waited for by the host.
            unsafe {
                for camera in cameras {
                    renderer.record_prepass(device, allocator, cmd, camera)?;
                }
                target.begin_pass(device, cmd);
                for camera in cameras {
                    renderer.record(device, allocator, cmd, camera)?;
                }
                target.end_pass(device, cmd);
            }
            Ok(true)
        })
    }

    fn one_view(&mut self, eye: DVec3) -> Outcome {
        let side = self.side();
        let camera = side.camera(eye, 0, side.target.extent().width);
        self.frame(&[camera])
    }
}

impl Run for Embedded {
    type Error = HostOr<Error>;

    fn steps() -> &'static [Step] {
        TYPICAL_RUN
    }

    fn start() -> Self {
        Embedded::default()
    }

    fn step(&mut self, k: usize) -> Outcome {
        let eye = DVec3::new(1.0, 2.0, 11.0);
        let other = DVec3::new(-4.0, 3.0, 9.0);
        match k {
            0 => {
                let mut side = HostSide::new(96, 64).map_err(HostOr::Host)?;
                self.live_before = allocator::live();
                let mut options = RendererOptions::new(side.pass());
                options.frames_in_flight = 2;
                options.settings.plan = PlanMode::Estimate; // the same calls every run
                let features = side.features();
                let handles = side.host.handles();
                let device = HostDevice::new(
                    handles.instance,
                    handles.physical_device,
                    handles.device,
                    handles.queue_family,
                    features,
                );
                let mut allocator = FailingAllocator(handles.allocator);
                // SAFETY: the host's handles belong together and enable `features`; the
                // render passes outlive the renderer (the host keeps every target).
                let renderer = unsafe { EllipsoidRenderer::new(&device, &mut allocator, options) };
                self.side = Some(side);
                self.renderer = Some(renderer.map_err(HostOr::Renderer)?);
                Ok(None)
            }
            1 | 8 => {
                let scene = if k == 1 {
                    scenes::first_scene()
                } else {
                    scenes::second_scene()
                };
                self.submission(|renderer, device, allocator, _, cmd| {
                    // SAFETY: outside a pass; the host submits it before the next frame.
                    unsafe { renderer.upload(device, allocator, cmd, &scene) }?;
                    Ok(false)
                })
            }
            2 | 5 | 9 => self.one_view(eye),
            3 => self.one_view(other),
            4 => self.submission(|renderer, device, allocator, _, cmd| {
                let glyphs = scenes::updated_glyphs();
                // SAFETY: as for the upload.
                unsafe { renderer.update(device, allocator, cmd, scenes::UPDATE_FIRST, &glyphs) }?;
                Ok(false)
            }),
            6 => {
                self.side().resize(128, 96).map_err(HostOr::Host)?;
                let pass = self.side().pass();
                let renderer = self.renderer.as_mut().expect("made by step 0");
                // SAFETY: the host keeps every render pass until the renderer is gone.
                unsafe { renderer.set_target(pass) }.map_err(HostOr::Renderer)?;
                self.one_view(eye)
            }
            7 => {
                let side = self.side();
                let cameras = [side.camera(eye, 0, 64), side.camera(other, 64, 64)];
                self.frame(&cameras)
            }
            _ => unreachable!("{k} is not a step"),
        }
    }

    fn named(error: &HostOr<Error>) -> Option<Fault> {
        match error {
            HostOr::Renderer(Error::OutOfMemory { .. }) => Some(Fault::OutOfMemory),
            HostOr::Renderer(Error::DeviceLost { .. }) => Some(Fault::DeviceLost),
            host if host.host_lost() => Some(Fault::DeviceLost),
            _ => None,
        }
    }

    fn finish(self) -> Result<(), String> {
        let Some(mut side) = self.side else {
            return Ok(());
        };
        let mut problems = Vec::new();
        if let Some(renderer) = self.renderer {
            // A lost device says so; it is idle all the same.
            let _ = side.wait_idle();
            let (device, allocator) = side.host.device_and_allocator();
            // SAFETY: the device is idle; the renderer's own device and allocator.
            unsafe { renderer.destroy(device, &mut FailingAllocator(allocator)) };
        }
        let left = side.renderer_allocations();
        let live = allocator::live() - self.live_before;
        if left != 0 || live != 0 {
            problems.push(format!(
                "the destroyed renderer left {left} allocation(s) in the host's allocator, \
                 {live} buffer(s) not given back"
            ));
        }
        if let Err(e) = side.finish() {
            problems.push(e);
        }
        match problems.is_empty() {
            true => Ok(()),
            false => Err(problems.join("; ")),
        }
    }
}

/// One test: the layer's state and the environment are the process's.
#[test]
fn embedded_faults_are_named_errors_and_leave_a_usable_renderer() {
    support::layer::layer();
    support::log::install();
    walk::<Embedded>(
        Fault::OutOfMemory,
        Strides {
            dense: 3,
            sparse: 12,
        },
    );
    walk::<Embedded>(
        Fault::AllocatorFails,
        Strides {
            dense: 3,
            sparse: 8,
        },
    );
    walk::<Embedded>(
        Fault::DeviceLost,
        Strides {
            dense: 1,
            sparse: 2,
        },
    );
}
