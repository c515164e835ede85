//! Faults walked over the same typical run as `embedded_faults.rs`, through the C ABI: the
//! host's raw handles, its render passes, its allocator callbacks (which refuse the N-th
//! buffer as a C host's allocator would), cameras from its matrices. Each failing call must
//! return `ES_STATUS_ERROR_OUT_OF_MEMORY` or `ES_STATUS_ERROR_DEVICE_LOST` with a message
//! (`es_last_error`) naming what, never `ES_STATUS_ERROR_PANIC` (no panic unwinds into the
//! host: one would abort this process).

mod support;

use std::ffi::CStr;
use std::sync::OnceLock;

use ash::vk;
use ellipsoid_splat_capi::*;
use glam::DVec3;
use support::allocator::{self, CallbackHost};
use support::fault::Fault;
use support::host_side::{HostOr, HostSide};
use support::scenes;
use support::walk::{walk, Bits, Run, Step, Strides, TYPICAL_RUN};

/// A failed C call: its status and `es_last_error`.
#[derive(Debug)]
struct CFailure {
    status: EsStatus,
    message: String,
}

impl std::fmt::Display for CFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}: {}", self.status, self.message)
    }
}

/// `Ok` for `ES_STATUS_SUCCESS`, else the status with this thread's last error.
fn check(status: EsStatus) -> Result<(), CFailure> {
    if status == EsStatus::Success {
        return Ok(());
    }
    // SAFETY: the library keeps a valid C string per thread.
    let message = unsafe { CStr::from_ptr(es_last_error()) }
        .to_string_lossy()
        .into_owned();
    Err(CFailure { status, message })
}

/// The loader's `vkGetInstanceProcAddr`, as a C host passes it.
fn loader() -> &'static ash::Entry {
    static ENTRY: OnceLock<ash::Entry> = OnceLock::new();
    // SAFETY: the system loader; kept for the process.
    ENTRY.get_or_init(|| unsafe { ash::Entry::load() }.expect("the Vulkan loader"))
}

fn glyphs(scene: &ellipsoid_splat::Scene) -> Vec<EsGlyph> {
    scene.ellipsoids.iter().map(glyph).collect()
}

fn glyph(e: &ellipsoid_splat::Ellipsoid) -> EsGlyph {
    let q = e.rotation;
    EsGlyph {
        center: e.center.to_array(),
        radii: e.radii.to_array(),
        rotation: [q.w, q.x, q.y, q.z],
        color: e.color,
    }
}

struct CRun {
    side: Option<HostSide>,
    renderer: *mut EsRenderer,
    /// The callbacks' user data (at a fixed place for the renderer's life).
    callback_host: Option<Box<CallbackHost>>,
    /// Buffers the callbacks saw live before the renderer existed.
    live_before: i64,
    frames: u32,
}

type Outcome = Result<Option<Bits>, HostOr<CFailure>>;

impl CRun {
    fn side(&mut self) -> &mut HostSide {
        self.side.as_mut().expect("made by step 0")
    }

    /// The C target of the host's current render pass.
    fn target_info(&mut self, color: &vk::Format) -> EsTargetInfo {
        EsTargetInfo {
            struct_size: size_of::<EsTargetInfo>() as u32,
            render_pass: self.side().target.render_pass(),
            subpass: 0,
            color_attachment_count: 1,
            color_formats: color,
            depth_format: ellipsoid_splat_test_host::HostTarget::DEPTH_FORMAT,
            samples: 1,
            aux_outputs: 0,
        }
    }

    /// A camera from the host's matrices, as a C host makes it.
    fn camera(&mut self, eye: DVec3, x: u32, width: u32) -> Result<EsCamera, CFailure> {
        let height = self.side().target.extent().height;
        let view = glam::DMat4::look_at_rh(eye, DVec3::ZERO, DVec3::Y).as_mat4();
        let projection = ellipsoid_splat_test_host::standard_finite_perspective(
            0.9,
            width as f64 / height as f64,
            0.5,
            60.0,
        )
        .as_mat4();
        let viewport = EsViewport {
            x,
            y: 0,
            width,
            height: height as i32,
        };
        let mut camera = std::mem::MaybeUninit::<EsCamera>::uninit();
        // SAFETY: 16 floats each and a writable camera.
        check(unsafe {
            es_camera_from_matrices(
                view.to_cols_array().as_ptr(),
                projection.to_cols_array().as_ptr(),
                viewport,
                camera.as_mut_ptr(),
            )
        })?;
        // SAFETY: written by the successful call.
        Ok(unsafe { camera.assume_init() })
    }

    /// One submission in the next frame slot: `work` records into its command buffer.
    fn submission(
        &mut self,
        work: impl FnOnce(
            *mut EsRenderer,
            &ash::Device,
            &ellipsoid_splat_test_host::HostTarget,
            vk::CommandBuffer,
        ) -> Result<bool, CFailure>,
    ) -> Outcome {
        let slot = self.frames % 2;
        self.frames += 1;
        let renderer = self.renderer;
        self.side().submit(|host, target, cmd| {
            // SAFETY: the host waited for every earlier submission.
            check(unsafe { es_renderer_begin_frame(renderer, slot) })?;
            work(renderer, host.device(), target, cmd)
        })
    }

    /// A frame of `cameras`: each view's pre-pass, then the pass drawing them all.
    fn frame(&mut self, cameras: &[EsCamera]) -> Outcome {
        self.submission(|renderer, device, target, cmd| {
            // SAFETY: pre-passes outside the pass, draws inside it, in the host's command
            // buffer, which the host submits and waits for.
            unsafe {
                for camera in cameras {
                    check(es_renderer_record_prepass(renderer, cmd, camera))?;
                }
                target.begin_pass(device, cmd);
                for camera in cameras {
                    check(es_renderer_record(renderer, cmd, camera))?;
                }
                target.end_pass(device, cmd);
            }
            Ok(true)
        })
    }

    fn one_view(&mut self, eye: DVec3) -> Outcome {
        let width = self.side().target.extent().width;
        let camera = self.camera(eye, 0, width).map_err(HostOr::Renderer)?;
        self.frame(&[camera])
    }

    fn create(&mut self) -> Result<(), HostOr<CFailure>> {
        let side = HostSide::new(96, 64).map_err(HostOr::Host)?;
        let side = self.side.insert(side);
        self.live_before = allocator::live();
        let features = side.features();
        let mut bits = ES_FEATURE_MAINTENANCE4;
        if features.dynamic_rendering {
            bits |= ES_FEATURE_DYNAMIC_RENDERING | ES_FEATURE_SAMPLE_RATE_SHADING;
        }
        if features.shader_int64 && features.shader_buffer_int64_atomics {
            bits |= ES_FEATURE_SHADER_INT64 | ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS;
        }
        let device = EsDeviceInfo {
            struct_size: size_of::<EsDeviceInfo>() as u32,
            get_instance_proc_addr: Some(loader().static_fn().get_instance_proc_addr),
            instance: side.host.instance().handle(),
            physical_device: side.host.physical_device(),
            device: side.host.device().handle(),
            queue_family_index: side.host.queue_family(),
            enabled_features: bits,
        };
        let callback_host = Box::new(CallbackHost {
            device: side.host.device().clone(),
            allocator: side.host.allocator_mut(),
        });
        let callback_host = self.callback_host.insert(callback_host);
        let callbacks = allocator::callbacks(&mut **callback_host);
        let mut settings = std::mem::MaybeUninit::<EsSettings>::uninit();
        // SAFETY: a writable struct.
        check(unsafe { es_settings_default(settings.as_mut_ptr()) }).map_err(HostOr::Renderer)?;
        // SAFETY: written by the successful call.
        let mut settings = unsafe { settings.assume_init() };
        settings.plan_mode = EsPlanMode::Estimate as u32; // the same calls every run
        let color = ellipsoid_splat_test_host::HostTarget::COLOR_FORMAT;
        let target = self.target_info(&color);
        let info = EsRendererCreateInfo {
            struct_size: size_of::<EsRendererCreateInfo>() as u32,
            device: &device,
            target: &target,
            allocator: &callbacks,
            settings: &settings,
            frames_in_flight: 2,
            pipeline_cache: vk::PipelineCache::null(),
        };
        // SAFETY: valid structs; the host's handles belong together and outlive the renderer,
        // as do its render passes and the callbacks' user data.
        check(unsafe { es_renderer_create(&info, &mut self.renderer) }).map_err(HostOr::Renderer)
    }
}

impl Run for CRun {
    type Error = HostOr<CFailure>;

    fn steps() -> &'static [Step] {
        TYPICAL_RUN
    }

    fn start() -> Self {
        CRun {
            side: None,
            renderer: std::ptr::null_mut(),
            callback_host: None,
            live_before: 0,
            frames: 0,
        }
    }

    fn step(&mut self, k: usize) -> Outcome {
        let eye = DVec3::new(1.0, 2.0, 11.0);
        let other = DVec3::new(-4.0, 3.0, 9.0);
        match k {
            0 => self.create().map(|_| None),
            1 | 8 => {
                let glyphs = glyphs(&if k == 1 {
                    scenes::first_scene()
                } else {
                    scenes::second_scene()
                });
                self.submission(|renderer, _, _, cmd| {
                    // SAFETY: outside a pass; `glyphs` holds `len` glyphs.
                    check(unsafe {
                        es_renderer_upload(renderer, cmd, glyphs.as_ptr(), glyphs.len())
                    })?;
                    Ok(false)
                })
            }
            2 | 5 | 9 => self.one_view(eye),
            3 => self.one_view(other),
            4 => {
                let glyphs: Vec<EsGlyph> = scenes::updated_glyphs().iter().map(glyph).collect();
                self.submission(|renderer, _, _, cmd| {
                    // SAFETY: as for the upload.
                    check(unsafe {
                        es_renderer_update(
                            renderer,
                            cmd,
                            scenes::UPDATE_FIRST,
                            glyphs.as_ptr(),
                            glyphs.len(),
                        )
                    })?;
                    Ok(false)
                })
            }
            6 => {
                self.side().resize(128, 96).map_err(HostOr::Host)?;
                let color = ellipsoid_splat_test_host::HostTarget::COLOR_FORMAT;
                let target = self.target_info(&color);
                // SAFETY: a live renderer; the host keeps the render pass past it.
                check(unsafe { es_renderer_set_target(self.renderer, &target) })
                    .map_err(HostOr::Renderer)?;
                self.one_view(eye)
            }
            7 => {
                let cameras = [
                    self.camera(eye, 0, 64).map_err(HostOr::Renderer)?,
                    self.camera(other, 64, 64).map_err(HostOr::Renderer)?,
                ];
                self.frame(&cameras)
            }
            _ => unreachable!("{k} is not a step"),
        }
    }

    fn named(error: &HostOr<CFailure>) -> Option<Fault> {
        match error {
            HostOr::Renderer(CFailure { status, message }) if !message.is_empty() => match status {
                EsStatus::ErrorOutOfMemory => Some(Fault::OutOfMemory),
                EsStatus::ErrorDeviceLost => Some(Fault::DeviceLost),
                _ => None,
            },
            host if host.host_lost() => Some(Fault::DeviceLost),
            _ => None,
        }
    }

    fn finish(self) -> Result<(), String> {
        let Some(side) = self.side else {
            return Ok(());
        };
        let mut problems = Vec::new();
        // A lost device says so; it is idle all the same.
        let _ = side.wait_idle();
        // SAFETY: the device is idle; the renderer (or null) is not used again.
        if let Err(e) = check(unsafe { es_renderer_destroy(self.renderer) }) {
            problems.push(format!("es_renderer_destroy: {e}"));
        }
        let mut side = side;
        let left = side.renderer_allocations();
        let live = allocator::live() - self.live_before;
        if left != 0 || live != 0 {
            problems.push(format!(
                "the destroyed renderer left {left} allocation(s) in the host's allocator, \
                 {live} buffer(s) not given back"
            ));
        }
        drop(self.callback_host);
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
fn c_abi_faults_are_named_statuses_and_leave_a_usable_renderer() {
    support::layer::layer();
    support::log::install();
    walk::<CRun>(
        Fault::OutOfMemory,
        Strides {
            dense: 4,
            sparse: 16,
        },
    );
    walk::<CRun>(
        Fault::AllocatorFails,
        Strides {
            dense: 4,
            sparse: 8,
        },
    );
    walk::<CRun>(
        Fault::DeviceLost,
        Strides {
            dense: 1,
            sparse: 2,
        },
    );
}
