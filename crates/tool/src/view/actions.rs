//! What the viewer does for an input event or a script line: orbit, pan and zoom the camera,
//! the keys (fit, reset, projection, screenshot, colour mode, help, quit), and picking.

use std::time::Instant;

use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;

use crate::error::Result;

use super::script::{Action, Button};
use super::viewer::Viewer;
use super::{controls, pick, stats, App, CLICK_SLOP};

impl App {
    /// What an input event or a script line does.
    pub(super) fn act(&mut self, event_loop: &ActiveEventLoop, action: Action) {
        if let Err(e) = self.try_act(event_loop, action) {
            self.fail(event_loop, e);
        }
    }

    fn try_act(&mut self, event_loop: &ActiveEventLoop, action: Action) -> Result<()> {
        let (width, height) = self
            .viewer
            .as_ref()
            .and_then(Viewer::extent)
            .map_or(self.size, |e| (e.width, e.height));
        match action {
            Action::Move(x, y) => {
                let (dx, dy) = (x - self.input.cursor.0, y - self.input.cursor.1);
                self.input.cursor = (x, y);
                match self.input.left {
                    Some((at, pans)) => {
                        let travel = (x - at.0).hypot(y - at.1);
                        self.input.dragged |= travel >= CLICK_SLOP;
                        if pans {
                            self.view.pan(dx, dy, height);
                        } else if self.input.dragged {
                            self.view.orbit(dx, dy);
                        }
                    }
                    None if self.input.middle => self.view.pan(dx, dy, height),
                    None => return Ok(()),
                }
                self.redraw = true;
            }
            Action::Press(button, x, y) => {
                self.input.cursor = (x, y);
                match button {
                    Button::Left | Button::ShiftLeft => {
                        self.input.left = Some(((x, y), button == Button::ShiftLeft));
                        self.input.dragged = false;
                    }
                    Button::Middle => self.input.middle = true,
                    Button::Right => {}
                }
            }
            Action::Release(button, x, y) => {
                self.input.cursor = (x, y);
                match button {
                    Button::Left | Button::ShiftLeft => {
                        if let Some((_, pans)) = self.input.left.take() {
                            if !pans && !self.input.dragged {
                                self.pick(x, y)?;
                            }
                        }
                    }
                    Button::Middle => self.input.middle = false,
                    Button::Right => {}
                }
            }
            Action::Wheel(x, y, notches) => {
                self.input.cursor = (x, y);
                let point = self.zoom_point(x, y, width, height)?;
                self.view.zoom(notches, point);
                self.redraw = true;
            }
            Action::Key(key) => self.key(event_loop, key, width, height),
            Action::Resize(w, h) => {
                if let Some(window) = &self.window {
                    let _ = window.request_inner_size(PhysicalSize::new(w, h));
                }
            }
            Action::Minimise => {
                if let Some(window) = &self.window {
                    // Without a window manager (as under Xvfb) only hiding takes effect.
                    window.set_minimized(true);
                    window.set_visible(false);
                }
            }
            Action::Restore => {
                if let Some(window) = &self.window {
                    window.set_visible(true);
                    window.set_minimized(false);
                }
                self.redraw = true;
            }
            Action::Screenshot(path) => self.shot = Some(path),
            Action::Animate(frames) => self.animate_left = frames,
            Action::Memory => {
                if let Some(viewer) = &self.viewer {
                    let (scene, total) = viewer.gpu_memory();
                    println!(
                        "memory: frame {} gpu-scene {scene} gpu-total {total} rss {}",
                        self.tick,
                        stats::resident_bytes()
                    );
                }
            }
            Action::Camera => {
                println!("camera: {}", self.view.render_flags(width, height)?);
            }
        }
        Ok(())
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, key: char, width: u32, height: u32) {
        match key {
            'F' => self.view.fit(width, height),
            'R' => self.view = self.start,
            'O' => self.view.toggle_projection(height),
            'P' => {
                self.shots_taken += 1;
                let output = &self.render.output;
                let stem = output
                    .file_stem()
                    .map_or("view".into(), |s| s.to_string_lossy());
                let name = format!("{stem}-{:03}.png", self.shots_taken);
                self.shot = Some(output.with_file_name(name));
            }
            'C' => self.next_color_mode(),
            'N' | '.' => return self.step_or_fail(event_loop, 1),
            'B' | ',' => return self.step_or_fail(event_loop, -1),
            ' ' => self.toggle_playing(),
            'H' => println!("{}", controls::KEYS),
            'Q' => event_loop.exit(),
            _ => return,
        }
        self.redraw = true;
    }

    /// Steps `step` frames through the trajectory; a frame that cannot be read ends the
    /// viewer with its error, as any other failure does.
    fn step_or_fail(&mut self, event_loop: &ActiveEventLoop, step: isize) {
        if let Err(e) = self.step_frame(step) {
            self.fail(event_loop, e);
        }
    }

    /// Recolours every glyph in the next colour mode (one update of the whole scene; a
    /// highlighted glyph stays highlighted and gets its new colour back when unpicked).
    fn next_color_mode(&mut self) {
        self.color_mode = self.color_mode.next();
        let mode = self.color_mode;
        self.pending.clear();
        for (index, (glyph, file_color)) in self
            .scene
            .ellipsoids
            .iter_mut()
            .zip(&self.file_colors)
            .enumerate()
        {
            glyph.color = *file_color;
            glyph.color = mode.color(glyph);
            if let Some((picked, original)) = &mut self.picked {
                if *picked as usize == index {
                    original.color = glyph.color;
                    glyph.color = pick::HIGHLIGHT;
                }
            }
            self.pending.push((index as u32, *glyph));
        }
        println!("colour mode: {}", mode.name());
    }

    /// The point a wheel notch at `(x, y)` zooms towards: the surface under the cursor in
    /// the last frame's depth output, else the point at the target's depth.
    fn zoom_point(&mut self, x: f64, y: f64, width: u32, height: u32) -> Result<glam::DVec3> {
        let depth = match &mut self.viewer {
            Some(viewer) => viewer.probe(x, y)?.and_then(|p| p.depth),
            None => None,
        };
        let camera = self.view.camera(width, height)?;
        let camera = self
            .viewer
            .as_ref()
            .and_then(Viewer::last_camera)
            .filter(|c| depth.is_some() && c.width == width && c.height == height)
            .unwrap_or(camera);
        let depth = depth.unwrap_or_else(|| self.view.target_depth());
        Ok(controls::point_at(&camera, x, y, depth))
    }

    /// Reads the glyph under `(x, y)`, prints what it is and highlights it (a scene update
    /// of its colour; the previous pick gets its colour back).
    fn pick(&mut self, x: f64, y: f64) -> Result<()> {
        let started = Instant::now();
        let Some(viewer) = &mut self.viewer else {
            return Ok(());
        };
        let Some(probe) = viewer.probe(x, y)? else {
            println!("pick ({x}, {y}): nothing drawn there yet");
            return Ok(());
        };
        let latency = started.elapsed().as_secs_f64() * 1e3;
        if let Some((index, original)) = self.picked.take() {
            self.scene.ellipsoids[index as usize] = original;
            self.pending.push((index, original));
        }
        let Some(index) = probe.glyph else {
            println!("pick ({x}, {y}): background ({latency:.1} ms)");
            self.redraw = true;
            return Ok(());
        };
        let glyph = self.scene.ellipsoids[index as usize];
        let source = pick::source(&self.spec, index, &self.origins);
        println!(
            "pick ({x}, {y}): {} ({latency:.1} ms)",
            pick::report(index, self.scene.len(), &glyph, &source)
        );
        let mut lit = glyph;
        lit.color = pick::HIGHLIGHT;
        self.scene.ellipsoids[index as usize] = lit;
        self.pending.push((index, lit));
        self.picked = Some((index, glyph));
        self.pick_shown = Some(started);
        self.redraw = true;
        Ok(())
    }
}
