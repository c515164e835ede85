//! The viewer's camera and what the mouse and keys do to it: a turntable orbit about the
//! target, pan in the view plane, zoom towards a point, fit, reset, and the projection toggle.
//! Pure math on [`Camera`], so it is tested without a window.

use glam::{DQuat, DVec2, DVec3};

use ellipsoid_splat::{Camera, Projection};

/// Radians of orbit per pixel of drag: a drag across 314 pixels turns half a revolution.
pub const ORBIT_RADIANS_PER_PIXEL: f64 = 0.01;
/// How much one wheel notch towards the scene shrinks the distance to the zoom point.
pub const ZOOM_PER_NOTCH: f64 = 0.8;
/// The nearest and farthest the wheel takes the view, in scene radii (eye-target distance,
/// or orthographic view height).
pub const ZOOM_RANGE: (f64, f64) = (1e-6, 1e6);
/// The orbit stops this close to the poles (radians), so the view never looks along `up`.
const POLE_MARGIN: f64 = 0.02;

/// The keys of the viewer, as `H` and `--help` list them.
pub const KEYS: &str = "\
mouse and keys of `view`:
  left drag           orbit about the target
  middle drag,
  shift + left drag   pan
  wheel               zoom towards the surface point under the cursor
  left click          pick: print the glyph under the cursor and highlight it
  F                   fit the scene in the window
  R                   reset the camera to the start
  O                   perspective / orthographic
  P                   screenshot of the window to PNG (--output, numbered)
  C                   next colour mode
  N or .              next frame of a trajectory
  B or ,              previous frame
  space               play / pause the trajectory
  H                   print these keys
  Esc, Q              quit";

/// The camera as the user moves it; [`ViewCamera::camera`] makes the renderer's camera of
/// any image size, with `render`'s near-plane rule, so a screenshot can be reproduced by
/// `render` with the flags [`ViewCamera::render_flags`] prints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewCamera {
    /// Eye position.
    pub eye: DVec3,
    /// Orbit centre and point looked at.
    pub target: DVec3,
    /// The turntable axis (`--up`); the orbit never rotates it.
    pub up: DVec3,
    /// Vertical field of view of the perspective projection, degrees.
    pub fov_y_deg: f64,
    /// `Some(view height)` while orthographic.
    pub ortho_height: Option<f64>,
    /// A fixed near plane (`--near`), or `None` for `render`'s rule.
    pub near: Option<f64>,
    /// The scene's bounding sphere, for the near-plane rule and fitting.
    pub bounds: (DVec3, f64),
}

impl ViewCamera {
    /// The camera state of `camera` (the one `render` would use) over a scene bounded by
    /// `bounds`.
    pub fn from_camera(camera: &Camera, near: Option<f64>, bounds: (DVec3, f64)) -> Self {
        // The window resizes, so the viewer keeps a centred projection with square pixels:
        // an intrinsics camera keeps its vertical field of view (or view height).
        let fy = camera.intrinsics().fy;
        let image_height = f64::from(camera.height);
        let (fov_y_deg, ortho_height) = match camera.projection {
            Projection::Perspective { fov_y_deg } => (fov_y_deg, None),
            // Switching to perspective later uses `render`'s default field of view.
            Projection::Orthographic { height } => (45.0, Some(height)),
            Projection::OrthographicIntrinsics(_) => (45.0, Some(image_height / fy)),
            // An intrinsics pinhole (and any later perspective kind): its vertical field.
            _ => (2.0 * (0.5 * image_height / fy).atan().to_degrees(), None),
        };
        Self {
            eye: camera.eye,
            target: camera.target,
            up: camera.up,
            fov_y_deg,
            ortho_height,
            near,
            bounds,
        }
    }

    /// The renderer's camera for a `width` x `height` image. The near plane follows
    /// `render`'s default: half the distance to the bounding sphere, or 1e-3 of its radius
    /// from inside.
    pub fn camera(&self, width: u32, height: u32) -> crate::error::Result<Camera> {
        let (center, radius) = self.bounds;
        let near = self.near.unwrap_or_else(|| {
            let gap = (center - self.eye).length() - radius;
            if gap > 0.0 {
                0.5 * gap
            } else {
                radius * 1e-3
            }
        });
        let projection = match self.ortho_height {
            Some(height) => Projection::Orthographic { height },
            None => Projection::Perspective {
                fov_y_deg: self.fov_y_deg,
            },
        };
        Ok(Camera::new(
            self.eye,
            self.target,
            self.up,
            projection,
            near,
            width,
            height,
        )?)
    }

    /// The `render` flags that draw exactly this camera at `width` x `height`. Numbers are
    /// printed so they read back to the same float64 (Rust's shortest round-trip form).
    pub fn render_flags(&self, width: u32, height: u32) -> crate::error::Result<String> {
        Ok(crate::camera_setup::camera_flags(
            &self.camera(width, height)?,
        ))
    }

    /// Turns the eye about the target: `dx` pixels of drag turn about `up`, `dy` pixels tilt
    /// over the camera's right axis; the tilt stops short of the poles.
    pub fn orbit(&mut self, dx: f64, dy: f64) {
        let axis = self.up.normalize();
        let offset = self.eye - self.target;
        let yawed = DQuat::from_axis_angle(axis, -dx * ORBIT_RADIANS_PER_PIXEL) * offset;
        let right = (-yawed).cross(axis).normalize();
        // The angle between the offset and `up`, kept inside (margin, pi - margin).
        let polar = yawed.normalize().dot(axis).clamp(-1.0, 1.0).acos();
        let tilt = (-dy * ORBIT_RADIANS_PER_PIXEL).clamp(
            POLE_MARGIN - polar,
            std::f64::consts::PI - POLE_MARGIN - polar,
        );
        let tilted = DQuat::from_axis_angle(right, tilt) * yawed;
        self.eye = self.target + tilted;
    }

    /// World units per pixel at the target's depth in an image `height` pixels tall.
    fn world_per_pixel(&self, height: u32) -> f64 {
        let view_height = match self.ortho_height {
            Some(h) => h,
            None => {
                let distance = (self.target - self.eye).length();
                2.0 * distance * (0.5 * self.fov_y_deg.to_radians()).tan()
            }
        };
        view_height / f64::from(height.max(1))
    }

    /// Moves eye and target together so the point under the cursor follows a drag of
    /// `dx`, `dy` pixels (at the target's depth).
    pub fn pan(&mut self, dx: f64, dy: f64, height: u32) {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let step = self.world_per_pixel(height);
        let shift = (-dx * right + dy * up) * step;
        self.eye += shift;
        self.target += shift;
    }

    /// Zooms by `notches` wheel notches (positive: closer) towards `point`, which stays
    /// under the cursor: perspective scales the eye and target about it; orthographic
    /// scales the view height and shifts sideways only (the depth of an orthographic eye
    /// changes nothing but the near plane).
    ///
    /// The view stays between [`ZOOM_RANGE`]'s bounds times the scene's radius (eye-target
    /// distance, or view height): the wheel can never bring the eye onto the target or send
    /// it to infinity.
    pub fn zoom(&mut self, notches: f64, point: DVec3) {
        let radius = self.bounds.1.max(f64::MIN_POSITIVE);
        let (lo, hi) = (ZOOM_RANGE.0 * radius, ZOOM_RANGE.1 * radius);
        let size = match self.ortho_height {
            None => self.eye.distance(self.target),
            Some(height) => height,
        };
        let (min, max) = (lo / size, hi / size);
        if !(min.is_finite() && max.is_finite() && min <= max) {
            return;
        }
        let scale = ZOOM_PER_NOTCH.powf(notches).clamp(min, max);
        match &mut self.ortho_height {
            None => {
                self.eye = point + (self.eye - point) * scale;
                self.target = point + (self.target - point) * scale;
            }
            Some(height) => {
                *height *= scale;
                let forward = (self.target - self.eye).normalize();
                let lateral = (point - self.eye) - (point - self.eye).dot(forward) * forward;
                let shift = lateral * (1.0 - scale);
                self.eye += shift;
                self.target += shift;
            }
        }
    }

    /// Keeps the direction of view and frames the bounding sphere: the target moves to its
    /// centre and the eye back until the sphere fits the narrower field of view.
    pub fn fit(&mut self, width: u32, height: u32) {
        let (center, radius) = self.bounds;
        let forward = (self.target - self.eye).normalize();
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        let half_y = (0.5 * self.fov_y_deg.to_radians()).tan();
        let half = half_y.min(half_y * aspect).atan();
        let distance = radius / half.sin();
        self.target = center;
        self.eye = center - forward * distance;
        if let Some(h) = &mut self.ortho_height {
            *h = 2.0 * radius * (1.0f64).max(1.0 / aspect);
        }
    }

    /// Perspective to orthographic (with the view height that shows the target's depth
    /// plane as it was) and back.
    pub fn toggle_projection(&mut self, height: u32) {
        self.ortho_height = match self.ortho_height {
            None => Some(self.world_per_pixel(height) * f64::from(height.max(1))),
            Some(_) => None,
        };
    }

    /// View depth of the target, where a zoom over the background aims.
    pub fn target_depth(&self) -> f64 {
        (self.target - self.eye).length()
    }
}

/// The point on `camera`'s ray through window position `(x, y)` (fractional pixels from the
/// top left) at view depth `depth`.
pub fn point_at(camera: &Camera, x: f64, y: f64, depth: f64) -> DVec3 {
    let ray = camera.ray_at_pixel(DVec2::new(x, y));
    let forward = camera.basis().forward;
    // Perspective rays have forward component 1; orthographic rays are unit `forward`.
    ray.origin + ray.direction * (depth / ray.direction.dot(forward))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> ViewCamera {
        ViewCamera {
            eye: DVec3::new(0.0, 0.0, 10.0),
            target: DVec3::ZERO,
            up: DVec3::Y,
            fov_y_deg: 45.0,
            ortho_height: None,
            near: None,
            bounds: (DVec3::ZERO, 1.0),
        }
    }

    #[test]
    fn orbit_turns_about_up_and_keeps_the_distance() {
        let mut view = start();
        // A drag to the left of a quarter turn's pixels takes the eye from +z to +x (the
        // scene turns with the cursor).
        view.orbit(-std::f64::consts::FRAC_PI_2 / ORBIT_RADIANS_PER_PIXEL, 0.0);
        assert!(
            (view.eye - DVec3::new(10.0, 0.0, 0.0)).length() < 1e-9,
            "{}",
            view.eye
        );
        view.orbit(0.0, 1e6);
        assert!((view.eye.length() - 10.0).abs() < 1e-9);
        // Clamped short of the pole: never parallel to up.
        assert!(view.eye.normalize().dot(DVec3::Y).abs() < 1.0 - 1e-4);
        assert!(view.camera(64, 48).is_ok());
    }

    #[test]
    fn zoom_keeps_the_point_under_the_cursor() {
        for ortho in [None, Some(4.0)] {
            let mut view = start();
            view.ortho_height = ortho;
            let (w, h) = (320, 240);
            let point = point_at(&view.camera(w, h).unwrap(), 250.0, 60.0, 9.0);
            view.zoom(3.0, point);
            let depth = view.camera(w, h).unwrap().view_depth(point);
            let again = point_at(&view.camera(w, h).unwrap(), 250.0, 60.0, depth);
            assert!((again - point).length() < 1e-9, "{again} {point}");
        }
    }

    /// However far the wheel turns, the view stays within `ZOOM_RANGE` scene radii and the
    /// camera valid.
    #[test]
    fn zoom_stops_at_its_range() {
        for ortho in [None, Some(4.0)] {
            let radius = start().bounds.1;
            let size = |v: &ViewCamera| v.ortho_height.unwrap_or(v.eye.distance(v.target));
            let mut view = start();
            view.ortho_height = ortho;
            for _ in 0..2_000 {
                let target = view.target;
                view.zoom(1.0, target);
            }
            assert!(size(&view) >= 0.999 * ZOOM_RANGE.0 * radius, "{view:?}");
            assert!(view.camera(320, 240).is_ok(), "{view:?}");
            for _ in 0..4_000 {
                let target = view.target;
                view.zoom(-1.0, target);
            }
            assert!(size(&view) <= 1.001 * ZOOM_RANGE.1 * radius, "{view:?}");
            assert!(view.camera(320, 240).is_ok(), "{view:?}");
        }
    }

    #[test]
    fn pan_moves_the_target_by_the_drag() {
        let mut view = start();
        let before = point_at(&view.camera(320, 240).unwrap(), 100.0, 100.0, 10.0);
        view.pan(30.0, -20.0, 240);
        let after = point_at(&view.camera(320, 240).unwrap(), 130.0, 80.0, 10.0);
        assert!((after - before).length() < 1e-9);
    }

    #[test]
    fn fit_frames_the_sphere_and_render_flags_round_trip() {
        let mut view = start();
        view.eye = DVec3::new(0.0, 0.0, 100.0);
        view.fit(320, 240);
        assert!((view.eye.z - 1.0 / (22.5f64.to_radians().tan().atan().sin())).abs() < 1e-9);
        let flags = view.render_flags(320, 240).unwrap();
        assert!(
            flags.starts_with("--width 320 --height 240 --eye 0.0,0.0,"),
            "{flags}"
        );
        view.toggle_projection(240);
        assert!(view.render_flags(320, 240).unwrap().contains("--ortho "));
    }
}
