//! Runs a sequence: the test host's device (validation with synchronization validation),
//! the renderer made on it, each operation applied to the host, the renderer and the model,
//! every answer checked against the model's, each submitted pass compared with the oracle;
//! at the end everything destroyed, the host's allocator back to where it began, and no
//! validation message.

use std::panic::{catch_unwind, AssertUnwindSafe};

use ash::vk;
use ellipsoid_splat::{
    Camera, DeviceFeatures, EllipsoidRenderer, HostDevice, OffscreenRenderer, Pass,
    RendererOptions, Scene, Target,
};
use ellipsoid_splat::{FramePath, HiddenLayers};
use ellipsoid_splat_reference::testing::{finish_validated, validated_renderer};
use ellipsoid_splat_test_host::{DepthKind, Host, HostTarget, TargetKind};

use super::cameras::CameraDefect;
use super::glyphs::{glyph, glyphs, GlyphDefect, Rng};
use super::model::{self, material_defect, Expect, Model, Open, Stats, MAX_VIEWS};
use super::ops::{
    Draw, Op, SceneSize, Sequence, TargetChoice, TargetDefect, UpdateStart, ViewChoice,
    WisdomChoice, TARGET_SIZES,
};
use super::oracle::{self, Compared};

/// What lives across sequences: the host's device, a pipeline cache (the renderer of each
/// sequence builds its pipelines through it, as a host that keeps one would) and the oracle.
pub struct Fixture {
    host: Host,
    cache: vk::PipelineCache,
    oracle: Option<OffscreenRenderer>,
    pub stats: Stats,
}

impl Fixture {
    pub fn new() -> Self {
        let host = Host::new(true).expect("a validated host device (lavapipe)");
        let info = vk::PipelineCacheCreateInfo::default();
        // SAFETY: valid device and create info; destroyed in `Drop`.
        let cache = unsafe { host.device().create_pipeline_cache(&info, None) }
            .expect("vkCreatePipelineCache");
        Self {
            host,
            cache,
            oracle: Some(validated_renderer()),
            stats: Stats::default(),
        }
    }

    /// Runs one sequence; on failure, says which operation and why.
    pub fn run(&mut self, sequence: &Sequence) -> Result<(), String> {
        self.stats.sequences += 1;
        let messages_before = self.host.messages().len();
        let baseline = self.live_allocations();
        let mut case = Case::new(self, sequence)?;
        let mut outcome = Ok(());
        for (k, op) in sequence.ops.iter().enumerate() {
            let applied = catch_unwind(AssertUnwindSafe(|| case.apply(op)));
            let result = match applied {
                Ok(result) => result,
                Err(panic) => Err(format!("panicked: {}", panic_message(&panic))),
            };
            let messages = case.fixture.host.messages();
            let result = result.and_then(|()| match messages.get(messages_before..) {
                Some([first, ..]) => Err(format!("validation: {first}")),
                _ => Ok(()),
            });
            if let Err(why) = result {
                outcome = Err(format!("operation {k} ({op:?}): {why}"));
                break;
            }
        }
        let ended = case.end(outcome.is_ok());
        outcome?;
        ended?;
        let messages = self.host.messages();
        if let Some(first) = messages.get(messages_before..).and_then(|m| m.first()) {
            return Err(format!("validation after the last operation: {first}"));
        }
        let after = self.live_allocations();
        if after != baseline {
            return Err(format!(
                "the host's allocator holds {} allocations of {} bytes after the renderer was \
                 destroyed, {} of {} before it was made",
                after.0, after.1, baseline.0, baseline.1
            ));
        }
        Ok(())
    }

    /// Allocations and bytes the host's allocator holds.
    fn live_allocations(&mut self) -> (usize, u64) {
        let report = self.host.allocator_mut().generate_report();
        (report.allocations.len(), report.total_allocated_bytes)
    }

    /// Tears down, failing on any validation message of the host or the oracle.
    pub fn finish(mut self) {
        let messages = self.host.messages();
        assert!(messages.is_empty(), "validation: {messages:#?}");
        finish_validated(self.oracle.take().expect("the oracle lives until finish"));
    }
}

impl Drop for Fixture {
    fn drop(&mut self) {
        // SAFETY: every renderer that built pipelines through the cache is destroyed.
        unsafe { self.host.device().destroy_pipeline_cache(self.cache, None) };
    }
}

fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "(no message)".into())
}

/// The renderer's features the host enabled.
fn host_features(host: &Host) -> DeviceFeatures {
    let mut features = DeviceFeatures::default();
    features.maintenance4 = true;
    features.dynamic_rendering = host.dynamic_rendering();
    features.sample_rate_shading = host.dynamic_rendering();
    if host.int64_atomics() {
        features = features.union(DeviceFeatures::COMPUTE_SPLAT);
    }
    features
}

/// A new renderer on the host with `options`.
fn new_renderer(
    host: &mut Host,
    options: RendererOptions,
) -> ellipsoid_splat::Result<EllipsoidRenderer> {
    let features = host_features(host);
    let handles = host.handles();
    let device = HostDevice::new(
        handles.instance,
        handles.physical_device,
        handles.device,
        handles.queue_family,
        features,
    );
    // SAFETY: the host's handles belong together and enable `features`; the pipeline cache
    // and every render pass outlive the renderer (destroyed after it, in `Case::end`).
    unsafe { EllipsoidRenderer::new(&device, handles.allocator, options) }
}

/// The renderer's description of a host target.
fn target_of(host_target: &HostTarget) -> Target {
    let pass = match host_target.kind() {
        TargetKind::Dynamic => Pass::Dynamic {
            color_formats: vec![HostTarget::COLOR_FORMAT],
            depth_format: HostTarget::DEPTH_FORMAT,
        },
        TargetKind::RenderPass => Pass::RenderPass {
            render_pass: host_target.render_pass(),
            subpass: 0,
            color_attachment_count: 1,
            depth_format: HostTarget::DEPTH_FORMAT,
        },
    };
    let mut target = Target::new(pass);
    target.samples = host_target.samples();
    target
}

fn make_target(host: &mut Host, choice: &TargetChoice) -> Result<HostTarget, String> {
    let (width, height) = TARGET_SIZES[choice.size];
    let kind = if choice.render_pass {
        TargetKind::RenderPass
    } else {
        TargetKind::Dynamic
    };
    let depth = if choice.standard_depth {
        DepthKind::StandardFinite
    } else {
        DepthKind::ReversedInfinite
    };
    let samples = if choice.multisampled {
        vk::SampleCountFlags::TYPE_4
    } else {
        vk::SampleCountFlags::TYPE_1
    };
    HostTarget::new(host, kind, depth, samples, width, height)
}

/// One sequence in progress.
struct Case<'f> {
    fixture: &'f mut Fixture,
    renderer: Option<EllipsoidRenderer>,
    target: HostTarget,
    /// Targets replaced: their render passes must outlive the renderer.
    replaced: Vec<HostTarget>,
    model: Model,
    /// The last pass recorded into the open command buffer, and the replaced target it
    /// drew into (`None`: the current one).
    pass: Option<(Option<usize>, oracle::Pass)>,
}

impl<'f> Case<'f> {
    fn new(fixture: &'f mut Fixture, sequence: &Sequence) -> Result<Self, String> {
        let target = make_target(&mut fixture.host, &sequence.target)?;
        let mut settings = model::settings(&sequence.settings);
        let mut options = RendererOptions::new(target_of(&target));
        options.frames_in_flight = sequence.frames_in_flight;
        options.pipeline_cache = fixture.cache;
        options.settings = settings;
        // A material no shading can use is refused at once, by name.
        if let Some(name) = material_defect(&settings.material) {
            let refused = new_renderer(&mut fixture.host, options.clone());
            let checked = fixture.stats.check("new", &refused, &Expect::refused(name));
            if let Ok(renderer) = refused {
                let (device, allocator) = fixture.host.device_and_allocator();
                // SAFETY: nothing was recorded with it.
                unsafe { renderer.destroy(device, allocator) };
            }
            checked?;
            settings.material = ellipsoid_splat::Material::default();
            options.settings = settings;
        }
        let renderer = new_renderer(&mut fixture.host, options).map_err(|e| format!("new: {e}"))?;
        let model = Model::new(sequence.frames_in_flight, settings);
        Ok(Self {
            fixture,
            renderer: Some(renderer),
            target,
            replaced: Vec::new(),
            model,
            pass: None,
        })
    }

    fn renderer(&mut self) -> &mut EllipsoidRenderer {
        self.renderer
            .as_mut()
            .expect("the renderer lives until `end`")
    }

    fn depth_kind(&self) -> DepthKind {
        self.target.depth_kind()
    }

    /// Applies `op` to the host, the renderer and the model.
    fn apply(&mut self, op: &Op) -> Result<(), String> {
        let name = match op {
            Op::BeginFrame => "begin_frame",
            Op::BeginFrameBadSlot(_) => "begin_frame past the slots",
            Op::Upload { .. } => "upload",
            Op::UploadDefective { .. } => "upload of a defective glyph",
            Op::Update { .. } => "update",
            Op::Settings(_) => "set_settings",
            Op::Target(_) => "set_target (new host target)",
            Op::TargetDefective(_) => "set_target (defective)",
            Op::RendererDefective { .. } => "new (defective options)",
            Op::Draw(_) => "draw (pre-passes and pass)",
            Op::Submit => "submit",
            Op::SkipFrame => "skip a frame",
            Op::Wisdom(_) => "load_plan_wisdom",
        };
        let start = std::time::Instant::now();
        let applied = self.apply_op(op);
        self.fixture.stats.op(name, start.elapsed().as_secs_f64());
        applied?;
        self.check_state()
    }

    fn apply_op(&mut self, op: &Op) -> Result<(), String> {
        match op {
            Op::BeginFrame => self.begin_frame(),
            Op::BeginFrameBadSlot(past) => {
                let slot = self.model.frames_in_flight + *past as u32;
                let (device, allocator) = self.fixture.host.device_and_allocator();
                let renderer = self.renderer.as_mut().expect("renderer");
                // SAFETY: refused before anything is destroyed or recorded.
                let got = unsafe { renderer.begin_frame(device, allocator, slot) };
                self.fixture
                    .stats
                    .check("begin_frame", &got, &Expect::refused("frame slot"))
            }
            Op::Upload { size, seed } => {
                let scene = glyphs(self.scene_size(*size), *seed);
                self.upload(scene, Expect::Ok)
            }
            Op::UploadDefective {
                size,
                seed,
                at,
                defect,
            } => {
                let mut scene = glyphs(self.scene_size(*size).max(1), *seed);
                let k = ((*at * scene.len() as f64) as usize).min(scene.len() - 1);
                scene[k] = defect.apply(scene[k]);
                let expected = match defect {
                    // Alone it is drawn (far away); beside others, no float32 offset from
                    // one origin holds both.
                    GlyphDefect::HugeCentre if scene.len() == 1 => Expect::Ok,
                    GlyphDefect::HugeCentre => Expect::refused("scene"),
                    _ => Expect::refused(format!("ellipsoid {k}")),
                };
                self.upload(scene, expected)
            }
            Op::Update {
                start,
                len,
                seed,
                defect,
            } => self.update(*start, *len, *seed, *defect),
            Op::Settings(choice) => {
                let settings = model::settings(choice);
                self.renderer().set_settings(settings);
                self.model.settings = settings;
                Ok(())
            }
            Op::Target(choice) => self.new_target(choice),
            Op::TargetDefective(defect) => {
                let target = self.defective_target(*defect);
                // SAFETY: refused before it is kept.
                let got = unsafe { self.renderer().set_target(target) };
                self.fixture
                    .stats
                    .check("set_target", &got, &Expect::refused("render target"))
            }
            Op::RendererDefective { frames_in_flight } => {
                let mut options = RendererOptions::new(target_of(&self.target));
                options.frames_in_flight = *frames_in_flight;
                let got = new_renderer(&mut self.fixture.host, options);
                let checked =
                    self.fixture
                        .stats
                        .check("new", &got, &Expect::refused("frames in flight"));
                if let Ok(renderer) = got {
                    let (device, allocator) = self.fixture.host.device_and_allocator();
                    // SAFETY: nothing was recorded with it.
                    unsafe { renderer.destroy(device, allocator) };
                }
                checked
            }
            Op::Draw(draw) => self.draw(draw),
            Op::Submit => self.submit(),
            Op::SkipFrame => self.skip_frame(),
            Op::Wisdom(choice) => {
                let bytes = self.renderer().plan_wisdom();
                let (bytes, expected) = match choice {
                    WisdomChoice::RoundTrip => (bytes, Expect::Ok),
                    WisdomChoice::Truncated => (
                        bytes[..bytes.len() / 2].to_vec(),
                        Expect::refused("plan wisdom"),
                    ),
                    WisdomChoice::Garbage(seed) => {
                        let mut rng = Rng::new(*seed);
                        let len = (rng.next_u64() % 64) as usize;
                        let bytes = (0..len).map(|_| rng.next_u64() as u8).collect();
                        (bytes, Expect::refused("plan wisdom"))
                    }
                };
                let got = self.renderer().load_plan_wisdom(&bytes);
                self.fixture
                    .stats
                    .check("load_plan_wisdom", &got, &expected)
            }
        }
    }

    /// What the renderer reports agrees with the model.
    fn check_state(&mut self) -> Result<(), String> {
        let count = self.model.scene.len();
        let bytes_each = self.model.format.bytes() as u64;
        let origin = self.model.placement.origin;
        let renderer = self.renderer();
        if renderer.count() as usize != count {
            return Err(format!(
                "count() is {}, the model uploaded {count}",
                renderer.count()
            ));
        }
        if count > 0 && renderer.origin() != origin {
            return Err(format!(
                "origin() is {}, the model's {origin}",
                renderer.origin()
            ));
        }
        if renderer.gpu_memory_bytes() < count as u64 * bytes_each {
            return Err(format!(
                "gpu_memory_bytes() is {}, less than {count} instances of {bytes_each} bytes",
                renderer.gpu_memory_bytes()
            ));
        }
        Ok(())
    }

    fn scene_size(&self, size: SceneSize) -> usize {
        match size {
            SceneSize::Empty => 0,
            SceneSize::One => 1,
            SceneSize::Few(n) => n as usize,
            SceneSize::AroundChunks { chunks, offset } => {
                (self.model.chunk_capacity() as i64 * chunks as i64 + offset as i64) as usize
            }
        }
    }

    /// Starts the next frame slot, submitting first if the open command buffer began it: its
    /// work must be done before the slot begins again.
    fn begin_frame(&mut self) -> Result<(), String> {
        let slot = self.model.next_slot;
        if self
            .model
            .open
            .as_ref()
            .is_some_and(|open| open.slots.contains(&slot))
        {
            self.submit()?;
        }
        if self.model.open.is_none() {
            self.fixture.host.begin()?;
            self.model.open = Some(Open::default());
        }
        let (device, allocator) = self.fixture.host.device_and_allocator();
        let renderer = self.renderer.as_mut().expect("renderer");
        // SAFETY: every command buffer recorded since `slot` last began was waited for, or
        // dropped with nothing of the renderer's in it, or is the open one, which has not
        // begun `slot`.
        let got = unsafe { renderer.begin_frame(device, allocator, slot) };
        self.fixture.stats.check("begin_frame", &got, &Expect::Ok)?;
        let open = self.model.open.as_mut().expect("opened above");
        open.slots.push(slot);
        open.views = 0;
        self.model.next_slot = (slot + 1) % self.model.frames_in_flight;
        Ok(())
    }

    /// The open command buffer, in a begun frame.
    fn command_buffer(&mut self) -> Result<vk::CommandBuffer, String> {
        if self.model.open.is_none() {
            self.begin_frame()?;
        }
        Ok(self.fixture.host.command_buffer())
    }

    /// Uploads `scene`, expecting `expected`; a refused upload changes nothing.
    fn upload(
        &mut self,
        scene: Vec<ellipsoid_splat::Ellipsoid>,
        expected: Expect,
    ) -> Result<(), String> {
        let cmd = self.command_buffer()?;
        let scene = Scene::new(scene);
        let (device, allocator) = self.fixture.host.device_and_allocator();
        let renderer = self.renderer.as_mut().expect("renderer");
        // SAFETY: `cmd` records outside a pass and is submitted (`skip_frame` submits what
        // the renderer recorded into) before any frame draws the scene.
        let got = unsafe { renderer.upload(device, allocator, cmd, &scene) };
        self.fixture.stats.check("upload", &got, &expected)?;
        if got.is_ok() {
            self.model.placement = ellipsoid_splat::Placement::of(&scene);
            self.model.scene = scene.ellipsoids;
            self.model.format = self.model.settings.instance_format;
            self.model.chunk_limit = self.model.settings.max_chunk_instances;
            self.model.open.as_mut().expect("open").recorded = true;
        }
        Ok(())
    }

    fn update(
        &mut self,
        start: UpdateStart,
        len: u8,
        seed: u64,
        defect: Option<GlyphDefect>,
    ) -> Result<(), String> {
        let count = self.model.scene.len() as u64;
        let first = match start {
            UpdateStart::Share(share) => (share * count as f64) as u64,
            UpdateStart::PastEnd(past) => count + past as u64,
            UpdateStart::Overflow => u32::MAX as u64,
        } as u32;
        let mut rng = Rng::new(seed);
        let mut new: Vec<_> = (0..len).map(|_| glyph(&mut rng)).collect();
        let defective = match defect {
            Some(defect) if !new.is_empty() => {
                let k = new.len() / 2;
                new[k] = defect.apply(new[k]);
                Some(k)
            }
            _ => None,
        };
        // Each glyph's own fields are checked first; then the glyphs keep the uploaded
        // scene's origin, and the first float32 cannot reach from it is refused.
        let origin = self.model.placement.origin;
        let unreachable = new
            .iter()
            .position(|e| e.center.is_finite() && !(e.center - origin).as_vec3().is_finite());
        let own_field = defective.filter(|_| defect != Some(GlyphDefect::HugeCentre));
        let expected = if first as u64 + len as u64 > count {
            Expect::refused("update")
        } else if let Some(k) = own_field.or(unreachable) {
            Expect::refused(format!("ellipsoid {}", first as usize + k))
        } else {
            Expect::Ok
        };
        let cmd = self.command_buffer()?;
        let (device, allocator) = self.fixture.host.device_and_allocator();
        let renderer = self.renderer.as_mut().expect("renderer");
        // SAFETY: as for `upload`.
        let got = unsafe { renderer.update(device, allocator, cmd, first, &new) };
        self.fixture.stats.check("update", &got, &expected)?;
        if got.is_ok() && !new.is_empty() {
            let first = first as usize;
            self.model.scene[first..first + new.len()].copy_from_slice(&new);
            self.model.open.as_mut().expect("open").recorded = true;
        }
        Ok(())
    }

    /// A new host target made current (submitting first: the old one may be in use).
    fn new_target(&mut self, choice: &TargetChoice) -> Result<(), String> {
        self.submit()?;
        let target = make_target(&mut self.fixture.host, choice)?;
        let description = target_of(&target);
        let old = std::mem::replace(&mut self.target, target);
        self.replaced.push(old);
        // SAFETY: the render pass lives until the renderer is destroyed (`end`).
        let got = unsafe { self.renderer().set_target(description) };
        self.fixture.stats.check("set_target", &got, &Expect::Ok)?;
        Ok(())
    }

    fn defective_target(&self, defect: TargetDefect) -> Target {
        let dynamic = |color, depth| Target::dynamic(color, depth);
        let (color, depth) = (HostTarget::COLOR_FORMAT, HostTarget::DEPTH_FORMAT);
        match defect {
            TargetDefect::TwoSampleCounts => {
                let mut t = dynamic(color, depth);
                t.samples = vk::SampleCountFlags::TYPE_1 | vk::SampleCountFlags::TYPE_4;
                t
            }
            TargetDefect::UnsupportedSamples => {
                let mut t = dynamic(color, depth);
                t.samples = vk::SampleCountFlags::TYPE_64;
                t
            }
            TargetDefect::ColourAsDepth => dynamic(color, color),
            TargetDefect::AuxWithoutAttachments => {
                let mut t = dynamic(color, depth);
                t.aux_outputs = true;
                t
            }
            TargetDefect::NullRenderPass => Target::new(Pass::RenderPass {
                render_pass: vk::RenderPass::null(),
                subpass: 0,
                color_attachment_count: 1,
                depth_format: depth,
            }),
            TargetDefect::UndefinedColour => dynamic(vk::Format::UNDEFINED, depth),
        }
    }

    /// The views' pre-passes, then (after any change `draw` makes between) one pass over
    /// the target drawing each view into its vertical strip.
    fn draw(&mut self, draw: &Draw) -> Result<(), String> {
        let cmd = self.command_buffer()?;
        let extent = self.target.extent();
        let (width, height) = (extent.width, extent.height);
        let n = draw.views.len() as u32;
        let depth = self.depth_kind();
        // Per view that reaches the renderer: its camera, the name its refusal carries if
        // the camera is defective, and whether its pre-pass was recorded.
        let mut drawn: Vec<(Camera, Option<&'static str>, bool)> = Vec::new();
        for (k, view) in draw.views.iter().enumerate() {
            let k = k as u32;
            let (x0, x1) = (k * width / n, (k + 1) * width / n);
            if x1 == x0 {
                continue; // a pixel-wide target has room for one view
            }
            let rect = (x0, 0, x1 - x0, height);
            let (camera, defect, skip_prepass) = match view {
                ViewChoice::Matrices(defect) => {
                    let got = defect.construct(rect);
                    let expected = Expect::refused(defect.name());
                    let call = "Camera::from_view_projection_viewport";
                    self.fixture.stats.check(call, &got, &expected)?;
                    continue;
                }
                ViewChoice::Defective { camera, defect } => {
                    let valid = camera
                        .build(rect, depth)
                        .map_err(|e| format!("camera {camera:?} in {rect:?}: {e}"))?;
                    let bad = defect.apply(valid);
                    let expected = Expect::refused(defect.name());
                    let constructed = CameraDefect::construct(&bad);
                    self.fixture
                        .stats
                        .check("Camera::new", &constructed, &expected)?;
                    (bad, Some(defect.name()), false)
                }
                ViewChoice::Camera {
                    camera,
                    skip_prepass,
                } => {
                    let camera = camera
                        .build(rect, depth)
                        .map_err(|e| format!("camera {camera:?} in {rect:?}: {e}"))?;
                    // A view without a pre-pass plans for the target current at its draw,
                    // which must then be the pass's: not after a new target.
                    (camera, None, *skip_prepass && draw.target_between.is_none())
                }
            };
            let refusal = defect.or(self.model.material_refusal());
            let expected = refusal.map_or(Expect::Ok, Expect::refused);
            let plan = self.renderer.as_ref().expect("renderer").plan(&camera);
            self.fixture.stats.check("plan", &plan, &expected)?;
            let prepared = !skip_prepass && self.record_prepass(cmd, &camera, expected)?;
            drawn.push((camera, defect, prepared));
        }
        if let Some(choice) = &draw.settings_between {
            let settings = model::settings(choice);
            self.renderer().set_settings(settings);
            self.model.settings = settings;
        }
        let drawing_into = match &draw.target_between {
            Some(choice) => {
                let target = make_target(&mut self.fixture.host, choice)?;
                let description = target_of(&target);
                self.replaced
                    .push(std::mem::replace(&mut self.target, target));
                // SAFETY: the render pass lives until the renderer is destroyed (`end`).
                let got = unsafe { self.renderer().set_target(description) };
                self.fixture.stats.check("set_target", &got, &Expect::Ok)?;
                Some(self.replaced.len() - 1)
            }
            None => None,
        };
        self.model.open.as_mut().expect("open").recorded = true;
        let (device, allocator) = self.fixture.host.device_and_allocator();
        let target = match drawing_into {
            Some(k) => &self.replaced[k],
            None => &self.target,
        };
        target.begin_pass(device, cmd);
        let mut cameras = Vec::new();
        for (camera, defect, prepared) in &drawn {
            let expected = match defect.or(material_defect(&self.model.settings.material)) {
                Some(name) => Expect::refused(name),
                None if self.model.scene.is_empty() || *prepared => Expect::Ok,
                None => self.model.record_without_prepass(),
            };
            let renderer = self.renderer.as_mut().expect("renderer");
            // SAFETY: `cmd` records inside the pass over the target current at the views'
            // pre-passes (and at the draws of views without one), whose attachments hold
            // each camera's strip.
            let got = unsafe { renderer.record(device, allocator, cmd, camera) };
            self.fixture.stats.check("record", &got, &expected)?;
            if got.is_ok() {
                cameras.push(*camera);
            }
        }
        target.end_pass(device, cmd);
        self.pass = Some((
            drawing_into,
            oracle::Pass {
                scene: self.model.scene.clone(),
                placement: self.model.placement,
                format: self.model.format,
                chunk_limit: self.model.chunk_limit,
                settings: self.model.settings,
                samples: target.samples(),
                extent: (width, height),
                cameras,
            },
        ));
        Ok(())
    }

    /// Records `camera`'s pre-pass expecting `expected` (unless the frame has no view left);
    /// whether it was recorded.
    fn record_prepass(
        &mut self,
        cmd: vk::CommandBuffer,
        camera: &Camera,
        expected: Expect,
    ) -> Result<bool, String> {
        let open = self.model.open.as_mut().expect("a frame is open");
        let expected = if open.views >= MAX_VIEWS {
            Expect::refused("record_prepass")
        } else {
            open.views += 1;
            expected
        };
        let (device, allocator) = self.fixture.host.device_and_allocator();
        let renderer = self.renderer.as_mut().expect("renderer");
        // SAFETY: `cmd` records outside a pass, in the frame begun last, and is submitted
        // before its slot begins again.
        let got = unsafe { renderer.record_prepass(device, allocator, cmd, camera) };
        self.fixture
            .stats
            .check("record_prepass", &got, &expected)?;
        if got.is_ok() {
            let plan = renderer
                .last_plan()
                .ok_or("no last_plan after a pre-pass")?;
            let path = match plan.path {
                FramePath::Draw(_) => "draw",
                FramePath::Splat(s) => match s.hidden {
                    HiddenLayers::SplatAll => "splat",
                    HiddenLayers::StampShown => "splat, stamping what it shows",
                    HiddenLayers::VisibleFirst { .. } => "visible-first splat",
                },
            };
            *self.fixture.stats.paths.entry(path).or_default() += 1;
        }
        Ok(got.is_ok())
    }

    /// Submits the open command buffer (if any), waits, and compares its last pass.
    fn submit(&mut self) -> Result<(), String> {
        if self.model.open.take().is_none() {
            return Ok(());
        }
        self.fixture.host.submit_and_wait()?;
        self.fixture.stats.frames_submitted += 1;
        let Some((replaced, pass)) = self.pass.take() else {
            return Ok(());
        };
        let rgba = match replaced {
            Some(k) => self.replaced[k].read_rgba()?,
            None => self.target.read_rgba()?,
        };
        let oracle = self.fixture.oracle.as_mut().expect("oracle");
        let Compared { pixels, covered } = oracle::compare(oracle, &pass, &rgba)?;
        oracle
            .context()
            .check_validation()
            .map_err(|e| format!("the oracle's {e}"))?;
        let stats = &mut self.fixture.stats;
        stats.passes_compared += 1;
        stats.pixels_compared += pixels;
        stats.pixels_covered += covered;
        Ok(())
    }

    /// Submits what the renderer recorded, begins the next frame and drops its command
    /// buffer unsubmitted: all a host may drop (the crate docs' order of calls).
    fn skip_frame(&mut self) -> Result<(), String> {
        if self.model.open.as_ref().is_some_and(|open| open.recorded) {
            self.submit()?;
        }
        self.begin_frame()?;
        let cmd = self.fixture.host.command_buffer();
        // SAFETY: the host's command buffer is recording; `Host::begin` resets its pool
        // before recording again.
        unsafe { self.fixture.host.device().end_command_buffer(cmd) }
            .map_err(|e| format!("vkEndCommandBuffer: {e}"))?;
        self.model.open = None;
        self.pass = None;
        self.fixture.stats.frames_dropped += 1;
        Ok(())
    }

    /// Submits what is open, destroys the renderer and the targets. After a failure
    /// (`clean` false) only tears down, as far as it can.
    fn end(mut self, clean: bool) -> Result<(), String> {
        let submitted = if clean { self.submit() } else { Ok(()) };
        let Case {
            fixture,
            renderer,
            target,
            replaced,
            model,
            ..
        } = self;
        let host = &mut fixture.host;
        if model.open.is_some() {
            let cmd = host.command_buffer();
            // SAFETY: ends the recording; it is never submitted.
            let _ = unsafe { host.device().end_command_buffer(cmd) };
        }
        // SAFETY: everything submitted was waited for (idle below); nothing recorded is
        // submitted again.
        unsafe {
            let _ = host.device().device_wait_idle();
            let (device, allocator) = host.device_and_allocator();
            if let Some(renderer) = renderer {
                renderer.destroy(device, allocator);
            }
        }
        target.destroy(host);
        for target in replaced {
            target.destroy(host);
        }
        submitted
    }
}
