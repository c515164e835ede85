//! `ellipsoid-splat view SCENE`: an interactive window on the scene, the third example of
//! embedding the renderer (beside `examples/minimal.rs` and `examples/embed`): its own
//! instance, device, swapchain and output images, the renderer driven through the public
//! embedding API only.
//!
//! - `mod.rs`: the window and its event loop, turning events into actions.
//! - `actions.rs`: what an action does: orbit, pan, zoom, the keys, colour modes, picking.
//! - `controls.rs`: the camera and what mouse and keys do to it.
//! - `script.rs`: scripted input.
//! - `pick.rs`: what a click reports.
//! - `subset.rs`: the moving frames' sample.
//! - `stats.rs`: frame times and memory.
//! - `frame_times.rs`: frame times in fixed memory.
//! - `device.rs`: instance, surface, device, allocator.
//! - `swapchain.rs`: the swapchain.
//! - `targets.rs`: the renderer's output images.
//! - `frames.rs`: two frames in flight.
//! - `viewer/mod.rs`: the GPU side, drawing a frame through the embedding API.
//! - `viewer/record.rs`: recording one frame's commands.
//! - `viewer/readback.rs`: screenshots and the ID and depth under the cursor.
//!
//! The window's events and a script's lines become the same [`script::Action`]s, so tests
//! drive exactly the code a person does.

mod actions;
pub mod controls;
mod device;
pub mod frame_times;
mod frames;
pub mod pick;
mod playback;
pub mod script;
pub mod stats;
pub mod subset;
mod swapchain;
mod targets;
mod viewer;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use ash::vk;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::error::{Error, Result};
use ellipsoid_splat::{Ellipsoid, Scene, Settings};
use ellipsoid_splat::{PlanMode, PlanReason};
use ellipsoid_splat_loaders::{ColorMode, Trajectory};

use crate::cli::{self, SceneSpec, ViewArgs};
use controls::ViewCamera;
use playback::Playback;
use script::{Action, Button, Script};
use stats::FrameStats;
use viewer::{Outcome, SceneChange, Viewer};

/// Names the Vulkan call on a failed `VkResult`.
pub(crate) trait VkCall<T> {
    /// The result, or the crate's error naming `call`.
    fn call(self, call: &'static str) -> Result<T>;
}

impl<T> VkCall<T> for std::result::Result<T, vk::Result> {
    fn call(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::vulkan(call, result))
    }
}

/// A click that moves the cursor less than this (pixels) picks instead of orbiting.
const CLICK_SLOP: f64 = 3.0;
/// How often the title's frame time is refreshed.
const TITLE_PERIOD: Duration = Duration::from_millis(250);

/// Opens the window and runs until it is closed (or `--exit-after` frames). Any validation
/// message with `--validation` makes it fail.
pub fn run(args: &ViewArgs) -> Result<()> {
    let render = args.render_args()?;
    let plan = render.check()?;
    // A file is opened as a trajectory (one frame for most formats) so the frame keys can
    // step through it.
    let (loaded, playback) = match &plan.scene {
        SceneSpec::File(path) => {
            let trajectory = Trajectory::open(path, &render.load.options())?;
            (trajectory.frame(0)?, Playback::of(trajectory))
        }
        generated => (
            crate::scene_io::load(generated, &render.load.options())?,
            None,
        ),
    };
    for note in &loaded.notes {
        eprintln!("{}: {note}", render.scene);
    }
    let origins = loaded.origins;
    // The glyphs as loaded keep the file's colours, so the colour key can return to them.
    let file_colors: Vec<[f32; 3]> = loaded.scene.ellipsoids.iter().map(|e| e.color).collect();
    let color_mode = render.load.color_mode();
    let mut scene = loaded.scene;
    color_mode.apply(&mut scene.ellipsoids);
    let camera = crate::camera_setup::camera_for(&render, &scene)?;
    let bounds = scene
        .bounding_sphere()
        .ok_or_else(|| Error::invalid("--scene", "has no ellipsoids"))?;
    let view = ViewCamera::from_camera(&camera, render.near, bounds);
    let script = args.script.as_deref().map(Script::load).transpose()?;
    let event_loop = EventLoop::new().map_err(|e| {
        Error::invalid(
            "view",
            format!("cannot open a window ({e}); is DISPLAY or WAYLAND_DISPLAY set?"),
        )
    })?;
    let settings = {
        let mut settings = Settings::default();
        settings.instance_format = render.instance_format();
        // `measure` (the default) learns as the frames go: the moving frames' class while
        // the camera moves, the still frames' each time it stops.
        settings.plan = render.plan.mode();
        settings
    };
    let mut app = App {
        size: (render.width, render.height),
        render,
        options: args.clone(),
        spec: plan.scene,
        origins,
        settings,
        scene,
        file_colors,
        color_mode,
        start: view,
        view,
        script,
        window: None,
        viewer: None,
        error: None,
        log: None,
        input: Input::default(),
        tick: 0,
        stats: FrameStats::default(),
        pending: Vec::new(),
        scene_replaced: false,
        picked: None,
        animate_left: 0,
        animated: 0,
        shot: None,
        shots_taken: 0,
        occluded: false,
        redraw: true,
        title_at: Instant::now(),
        last_gpu: None,
        last_moving: false,
        pick_shown: None,
        playback,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::invalid("view", format!("the window's event loop failed: {e}")))?;
    app.finish()
}

/// Mouse state between events.
#[derive(Default)]
struct Input {
    cursor: (f64, f64),
    /// Where the left button went down, and whether it pans (shift held).
    left: Option<((f64, f64), bool)>,
    /// The cursor moved too far since the left press for a click.
    dragged: bool,
    middle: bool,
    shift: bool,
}

/// The viewer's state between the window system's events.
struct App {
    render: cli::RenderArgs,
    options: ViewArgs,
    spec: SceneSpec,
    /// Where each glyph came from (a pick reports it).
    origins: ellipsoid_splat_loaders::Origins,
    settings: Settings,
    /// The scene as drawn now (colour mode, highlight and animation included).
    scene: Scene,
    /// Each glyph's colour as the scene gave it (`--color file`).
    file_colors: Vec<[f32; 3]>,
    /// How the glyphs are coloured now (`--color`, then the C key).
    color_mode: ColorMode,
    size: (u32, u32),
    start: ViewCamera,
    view: ViewCamera,
    script: Option<Script>,
    /// Declared before the window: fields drop in order, and the surface must go before the
    /// window it was made from.
    viewer: Option<Viewer>,
    window: Option<Window>,
    error: Option<Error>,
    log: Option<ellipsoid_splat::internals::validation::MessageLog>,
    input: Input,
    /// Turns of the render loop so far (drawn or skipped).
    tick: u64,
    stats: FrameStats,
    /// Glyph replacements for the next frame.
    pending: Vec<(u32, Ellipsoid)>,
    /// The next frame uploads the whole scene (a trajectory's frame changed; it holds any
    /// pending replacement too).
    scene_replaced: bool,
    /// The highlighted glyph and how it looked before.
    picked: Option<(u32, Ellipsoid)>,
    animate_left: u64,
    animated: u64,
    shot: Option<PathBuf>,
    shots_taken: u32,
    occluded: bool,
    /// Something changed: draw a frame.
    redraw: bool,
    title_at: Instant,
    last_gpu: Option<Duration>,
    last_moving: bool,
    /// When the last pick's click was handled, until the frame showing its highlight is
    /// presented.
    pick_shown: Option<Instant>,
    /// The trajectory's frames, where the scene file has several.
    playback: Option<Playback>,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let attributes = Window::default_attributes()
            .with_title("ellipsoid-splat view")
            .with_inner_size(PhysicalSize::new(self.size.0, self.size.1));
        let window = match event_loop.create_window(attributes) {
            Ok(w) => w,
            Err(e) => {
                return self.fail(
                    event_loop,
                    Error::invalid("view", format!("cannot create the window: {e}")),
                )
            }
        };
        let made = Viewer::new(
            &window,
            self.render.device.device.as_deref(),
            self.render.device.validation,
            !self.options.no_vsync,
            self.settings,
            &self.scene,
            self.options.moving_glyphs,
        );
        match made {
            Ok(viewer) => {
                self.log = Some(viewer.message_log());
                let (count, sample) = viewer.glyph_counts();
                let moving = sample.map_or(String::new(), |s| {
                    format!("; moving frames draw a uniform sample of {s}")
                });
                println!(
                    "view: {count} glyphs on {}{moving}; press H for the keys",
                    viewer.device_name()
                );
                self.viewer = Some(viewer);
                window.request_redraw();
            }
            Err(e) => self.fail(event_loop, e),
        }
        self.window = Some(window);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) => {
                if let Some(viewer) = &mut self.viewer {
                    viewer.stale = true;
                }
                self.redraw = true;
            }
            WindowEvent::Occluded(occluded) => {
                self.occluded = occluded;
                self.redraw = true;
            }
            WindowEvent::ModifiersChanged(m) => self.input.shift = m.state().shift_key(),
            WindowEvent::CursorMoved { position, .. } => {
                self.act(event_loop, Action::Move(position.x, position.y))
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let button = match button {
                    MouseButton::Left if self.input.shift => Button::ShiftLeft,
                    MouseButton::Left => Button::Left,
                    MouseButton::Middle => Button::Middle,
                    _ => Button::Right,
                };
                let (x, y) = self.input.cursor;
                let action = match state {
                    ElementState::Pressed => Action::Press(button, x, y),
                    ElementState::Released => Action::Release(button, x, y),
                };
                self.act(event_loop, action);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    // Touchpads scroll in pixels; 120 is a notch on most systems.
                    MouseScrollDelta::PixelDelta(p) => p.y / 120.0,
                };
                let (x, y) = self.input.cursor;
                self.act(event_loop, Action::Wheel(x, y, notches));
            }
            WindowEvent::KeyboardInput { event, .. }
                if event.state == ElementState::Pressed && !event.repeat =>
            {
                match event.logical_key {
                    Key::Named(NamedKey::Escape) => event_loop.exit(),
                    Key::Named(NamedKey::Space) => self.act(event_loop, Action::Key(' ')),
                    Key::Character(text) => {
                        if let Some(c) = text.chars().next() {
                            self.act(event_loop, Action::Key(c.to_ascii_uppercase()));
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.frame(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        // Scripted runs turn the loop continuously (their clock is the frame count);
        // otherwise a frame is drawn only when something changed.
        let continuous = self.script.is_some() || self.options.exit_after.is_some();
        if continuous || std::mem::take(&mut self.redraw) {
            if let Some(window) = &self.window {
                window.request_redraw();
            }
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        // The renderer and swapchain go before the window their surface belongs to.
        self.viewer = None;
        self.window = None;
    }
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    /// After the event loop: the summary, then the first error or validation message.
    fn finish(mut self) -> Result<()> {
        self.viewer = None;
        self.window = None;
        println!("{}", self.stats.summary());
        if let Some(paths) = self.stats.paths_summary() {
            println!("{paths}");
        }
        if let Some(plan) = &self.stats.plan {
            println!("plan of the last frame: {plan}");
        }
        if let Some(e) = self.error {
            return Err(e);
        }
        let messages = self
            .log
            .as_ref()
            .map(ellipsoid_splat::internals::validation::failures)
            .unwrap_or_default();
        for m in &messages {
            eprintln!("validation: {m}");
        }
        println!("validation messages: {}", messages.len());
        match messages.first() {
            None => Ok(()),
            Some(first) => Err(Error::Renderer(ellipsoid_splat::Error::Validation {
                count: messages.len(),
                first: first.to_string(),
            })),
        }
    }

    /// The window has nothing to show into: minimised, hidden, occluded or zero-sized.
    fn minimised(&self) -> bool {
        let Some(window) = &self.window else {
            return true;
        };
        let size = window.inner_size();
        self.occluded
            || size.width == 0
            || size.height == 0
            || window.is_minimized() == Some(true)
            || window.is_visible() == Some(false)
    }

    /// One turn of the render loop: the script's events for this frame, then a frame unless
    /// the window is minimised.
    fn frame(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        if let Some(script) = &mut self.script {
            for action in script.due(self.tick) {
                self.act(event_loop, action);
            }
        }
        if self
            .options
            .exit_after
            .is_some_and(|frames| self.tick >= frames)
        {
            event_loop.exit();
            return Ok(());
        }
        self.tick += 1;
        if self.minimised() {
            self.stats.skipped += 1;
            return Ok(());
        }
        if self.playing() {
            self.step_frame(1)?;
        }
        let (Some(window), Some(viewer)) = (&self.window, &mut self.viewer) else {
            return Ok(());
        };
        let size = window.inner_size();
        let wanted = vk::Extent2D {
            width: size.width,
            height: size.height,
        };
        if !viewer.ensure_swapchain(wanted)? {
            self.stats.skipped += 1;
            return Ok(());
        }
        let extent = viewer.extent().expect("ensure_swapchain made one");
        let camera = self.view.camera(extent.width, extent.height)?;
        // The rule of `subset.rs`: a frame whose camera moved may draw the sample; a
        // screenshot is always of the full scene.
        let moving = self.shot.is_none() && viewer.last_camera().is_some_and(|last| last != camera);
        if self.animate_left > 0 {
            self.animate_left -= 1;
            let index = (self.animated % self.scene.len() as u64) as u32;
            let mut glyph = self.scene.ellipsoids[index as usize];
            let phase = (self.animated % 7) as f32 / 7.0;
            glyph.color = [phase, 1.0 - phase, 0.5];
            self.scene.ellipsoids[index as usize] = glyph;
            self.pending.push((index, glyph));
            self.animated += 1;
        }
        let shot = self.shot.clone();
        let change = if self.scene_replaced {
            SceneChange::Whole(&self.scene)
        } else {
            SceneChange::Glyphs(&self.pending)
        };
        let outcome = viewer.draw(&camera, moving, change, shot.as_deref())?;
        for (time, moved) in viewer.take_finished() {
            if moved {
                self.stats.moving.push(time);
            } else {
                self.stats.still.push(time);
            }
            self.last_gpu = Some(time);
        }
        if outcome == Outcome::Skipped {
            // Out of date: the next turn makes the swapchain again and draws.
            self.redraw = true;
            return Ok(());
        }
        self.stats.presented += 1;
        if let Some(plan) = viewer.last_plan() {
            // A plan that measures has not settled while it explores or times its first guess.
            let unsettled = matches!(self.settings.plan, PlanMode::Measure)
                && matches!(
                    plan.reason,
                    PlanReason::Exploring | PlanReason::Estimated(_)
                );
            self.stats
                .count_plan(crate::plan::path_name(&plan.path), unsettled);
            self.stats.plan = Some(crate::plan::describe(&plan));
        }
        self.pending.clear();
        self.scene_replaced = false;
        self.last_moving = moving;
        if let Some(clicked) = self.pick_shown.take() {
            println!(
                "pick shown: the frame with the highlight was presented {:.1} ms after the click",
                clicked.elapsed().as_secs_f64() * 1e3
            );
        }
        if let Some(path) = self.shot.take() {
            // A trajectory's frame is drawn by `render --frames` (which numbers its file).
            let frame = self
                .playback
                .as_ref()
                .map(|p| format!(" --frames {}", p.shown_number()))
                .unwrap_or_default();
            println!(
                "screenshot: wrote {} ({}x{}); the same picture: ellipsoid-splat render --scene \
                 {}{frame} --color {} {}",
                path.display(),
                extent.width,
                extent.height,
                self.render.scene,
                self.color_mode.name(),
                self.view.render_flags(extent.width, extent.height)?
            );
        }
        // After a moving frame, the still frame follows even if nothing else happens; a
        // playing trajectory draws its next frame.
        self.redraw |= moving || self.playback.as_ref().is_some_and(|p| p.playing);
        if self.title_at.elapsed() >= TITLE_PERIOD {
            self.title_at = Instant::now();
            let (count, sample) = viewer.glyph_counts();
            let drawn = match (moving, sample) {
                (true, Some(s)) => format!("{s} of {count} glyphs (moving)"),
                _ => format!("{count} glyphs"),
            };
            let time = self
                .last_gpu
                .map_or("-".into(), |t| format!("{:.1} ms", t.as_secs_f64() * 1e3));
            let plan = self.stats.plan.as_deref().unwrap_or("-");
            window.set_title(&format!(
                "ellipsoid-splat view: {} | {drawn} | {time} GPU per frame | {plan}",
                self.render.scene
            ));
        }
        Ok(())
    }
}
