//! The camera and the pixel-ray contract of `docs/design.md` §3, in float64 ([`Camera`]).

use glam::{DVec2, DVec3};

use crate::depth::{DepthConvention, DepthMap};
use crate::error::{Error, Result};

/// The pinhole intrinsics of a camera, in pixels, as OpenCV writes them: focal lengths
/// `fx, fy` (pixels per unit of screen-plane slope in perspective; pixels per world unit in
/// orthographic) and the principal point `(cx, cy)` (x right, y down from the image's top-left
/// corner; the centre of a `W x H` image is `(W/2, H/2)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    /// Horizontal focal length in pixels.
    pub fx: f64,
    /// Vertical focal length in pixels.
    pub fy: f64,
    /// Principal point, x (pixels from the left edge).
    pub cx: f64,
    /// Principal point, y (pixels from the top edge).
    pub cy: f64,
}

impl Intrinsics {
    /// The intrinsics of an asymmetric perspective frustum (as OpenXR's per-eye field of view
    /// gives it) for a `width x height` image: the tangents of the angles from the view axis
    /// to the left, right, bottom and top edges, the left and bottom ones negative for a
    /// frustum holding the axis (`tan(angleLeft)` etc.).
    pub fn from_tangents(
        left: f64,
        right: f64,
        bottom: f64,
        top: f64,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        Self::from_window(left, right, bottom, top, width, height)
            .map_err(|why| Error::invalid("frustum tangents", why))
    }

    /// The intrinsics of an off-centre orthographic window (world units from the view axis to
    /// the left, right, bottom and top edges) for a `width x height` image.
    pub fn from_ortho_window(
        left: f64,
        right: f64,
        bottom: f64,
        top: f64,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        Self::from_window(left, right, bottom, top, width, height)
            .map_err(|why| Error::invalid("orthographic window", why))
    }

    fn from_window(
        left: f64,
        right: f64,
        bottom: f64,
        top: f64,
        width: u32,
        height: u32,
    ) -> std::result::Result<Self, String> {
        if ![left, right, bottom, top].iter().all(|v| v.is_finite()) {
            return Err(format!(
                "({left}, {right}, {bottom}, {top}) are not all finite"
            ));
        }
        if !(right > left && top > bottom) {
            return Err(format!(
                "need left < right and bottom < top, got ({left}, {right}, {bottom}, {top})"
            ));
        }
        let (w, h) = (width as f64, height as f64);
        let fx = w / (right - left);
        let fy = h / (top - bottom);
        Ok(Self {
            fx,
            fy,
            cx: -left * fx,
            cy: top * fy,
        })
    }
}

/// How the view volume is shaped.
///
/// The kinds are forms of one pinhole (or parallel) camera (design §3.2): `Perspective { fov_y_deg }` is `fx = fy =
/// (H/2) / tan(fov_y/2)`, `(cx, cy) = (W/2, H/2)`; `Orthographic { height }` is `fx = fy = H /
/// height`, centred; `PerspectiveIntrinsics(k)` and `OrthographicIntrinsics(k)` take any `k`
/// with positive finite focal lengths -- off-centre (calibrated cameras), asymmetric (each eye of
/// a stereo pair: `Intrinsics::from_tangents` takes OpenXR's per-eye angles), off-centre
/// orthographic windows (`Intrinsics::from_ortho_window`) and non-square pixels. The field of view is in (0, 180) degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Projection {
    /// Pinhole camera with the vertical field of view in degrees, in (0, 180), its principal
    /// point at the image's centre and square pixels.
    Perspective {
        /// Vertical field of view in degrees.
        fov_y_deg: f64,
    },
    /// Parallel rays; `height` is the world-space height of the view, centred on the eye,
    /// with square pixels.
    Orthographic {
        /// World-space height of the image.
        height: f64,
    },
    /// A pinhole camera with any frustum -- off-centre (calibrated cameras), asymmetric (one
    /// eye of a stereo pair), non-square pixels: the ray through pixel position `(x, y)` has
    /// the camera-frame direction `((x - cx) / fx, (y - cy) / fy, 1)`, x right, y down, z
    /// forward (OpenCV's convention).
    PerspectiveIntrinsics(Intrinsics),
    /// Parallel rays through any window: the ray through pixel position `(x, y)` leaves
    /// `eye + (x - cx) / fx r - (y - cy) / fy u` along `f` (`fx`, `fy` in pixels per world
    /// unit).
    OrthographicIntrinsics(Intrinsics),
}

/// A validated camera: position, orientation, projection, near plane, image size, jitter and
/// where the image lies in the host's attachments.
///
/// The camera keeps the pixel-ray contract of `docs/design.md` §3.1-3.2 in float64: its frame
/// ([`Camera::basis`]), [`Intrinsics`] in pixels and sub-pixel `jitter` place each pixel
/// position on the screen plane ([`Camera::pixel_to_screen`]) and give its ray
/// ([`Camera::ray_at_pixel`]); nothing nearer than `near` is visible. The camera's
/// `width x height` image is drawn at `viewport_origin` in the host's attachments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (perspective centre, or the point of the orthographic image plane on the
    /// view axis).
    pub eye: DVec3,
    /// Point looked at.
    pub target: DVec3,
    /// Approximate up direction.
    pub up: DVec3,
    /// Perspective or orthographic, and its intrinsics.
    pub projection: Projection,
    /// Distance of the near plane along the view direction, > 0.
    pub near: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// How view depth maps to the depth buffer (reversed Z, infinite far plane unless set).
    pub depth: DepthConvention,
    /// Sub-pixel offset of the samples, in pixels (x right, y down): pixel `(i, j)` samples the
    /// unjittered image plane at `(i + 0.5 + dx, j + 0.5 + dy)`, as a temporal antialiasing
    /// or upscaling sequence does. Zero unless set.
    pub jitter: DVec2,
    /// Where pixel `(0, 0)` of the camera's image lies in the host's attachments (the
    /// viewport's and scissor's offset): an editor viewport, one half of a split screen or a
    /// stereo pair. `[0, 0]` unless set.
    pub viewport_origin: [u32; 2],
}

/// The orthonormal camera frame: right, up, forward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Basis {
    /// `normalize(f x up)`.
    pub right: DVec3,
    /// `r x f`.
    pub up: DVec3,
    /// `normalize(target - eye)`.
    pub forward: DVec3,
}

/// A ray of the pixel-ray contract. For perspective `direction` has forward component exactly 1,
/// so the ray parameter is the view depth; for orthographic it is `f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: DVec3,
    /// Where it goes (not normalised for perspective).
    pub direction: DVec3,
}

/// Largest image side, and the largest `viewport_origin + size` on each axis.
const MAX_SIDE: u32 = 16384;

impl Camera {
    /// The most a camera's principal point (with its jitter) may lie from its image's centre, in
    /// half image widths and heights: the shaders' NDC of a pixel is the image's NDC plus this
    /// shift, and must stay well inside float32's range of exact small integers.
    pub const MAX_PRINCIPAL_SHIFT: f64 = 64.0;

    /// The most a camera's principal point (with its jitter) may lie from its image's centre, in
    /// pixels: the shaders add the shift to each pixel's NDC in float32, which adds at most
    /// `p 2^-23` pixels of rounding at a shift of `p` pixels to the `(W/2) 2^-23` (at most 2^-10)
    /// a centred camera has, so 8192 pixels keep every pixel's position within 2^-9 of a pixel,
    /// on any image size (§4.9).
    pub const MAX_PRINCIPAL_SHIFT_PX: f64 = 8192.0;

    /// A checked camera with the default depth convention, no jitter, drawn at the
    /// attachments' origin. Errors name the bad field.
    pub fn new(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        projection: Projection,
        near: f64,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        let camera = Self {
            eye,
            target,
            up,
            projection,
            near,
            width,
            height,
            depth: DepthConvention::default(),
            jitter: DVec2::ZERO,
            viewport_origin: [0, 0],
        };
        camera.validate()?;
        Ok(camera)
    }

    /// This camera with the depth convention `depth`, checked.
    pub fn with_depth(self, depth: DepthConvention) -> Result<Self> {
        let camera = Self { depth, ..self };
        camera.validate()?;
        Ok(camera)
    }

    /// This camera with its samples offset by `jitter` pixels (x right, y down), checked.
    pub fn with_jitter(self, jitter: DVec2) -> Result<Self> {
        let camera = Self { jitter, ..self };
        camera.validate()?;
        Ok(camera)
    }

    /// This camera drawn with its pixel `(0, 0)` at attachment pixel `(x, y)`, checked.
    pub fn with_viewport_origin(self, x: u32, y: u32) -> Result<Self> {
        let camera = Self {
            viewport_origin: [x, y],
            ..self
        };
        camera.validate()?;
        Ok(camera)
    }

    /// The map from view depth to depth-buffer value of this camera.
    pub fn depth_map(&self) -> DepthMap {
        self.depth.map(self.near, self.is_orthographic())
    }

    /// Checks every field; called by `new` and by the renderers before use.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [("eye", self.eye), ("target", self.target), ("up", self.up)] {
            if !v.is_finite() {
                return Err(Error::invalid(
                    format!("camera {name}"),
                    format!("not finite: {v}"),
                ));
            }
        }
        let f = self.target - self.eye;
        if f.length() <= 1e-12 * self.eye.length().max(1.0) {
            return Err(Error::invalid("camera target", "coincides with the eye"));
        }
        let f = f.normalize();
        let up = self.up.normalize_or_zero();
        if up == DVec3::ZERO || f.cross(up).length() < 1e-9 {
            return Err(Error::invalid(
                "camera up",
                "is zero or parallel to the view direction",
            ));
        }
        if !(self.near.is_finite() && self.near > 0.0) {
            return Err(Error::invalid(
                "camera near",
                format!("must be > 0, got {}", self.near),
            ));
        }
        if self.width == 0 || self.height == 0 || self.width > MAX_SIDE || self.height > MAX_SIDE {
            return Err(Error::invalid(
                "image size",
                format!("{}x{} is outside 1..={MAX_SIDE}", self.width, self.height),
            ));
        }
        let [x, y] = self.viewport_origin;
        if x as u64 + self.width as u64 > MAX_SIDE as u64
            || y as u64 + self.height as u64 > MAX_SIDE as u64
        {
            return Err(Error::invalid(
                "camera viewport",
                format!(
                    "a {}x{} image at ({x}, {y}) reaches beyond {MAX_SIDE} pixels",
                    self.width, self.height
                ),
            ));
        }
        self.depth.validate(self.near)?;
        match self.projection {
            Projection::Perspective { fov_y_deg } => {
                if !(fov_y_deg.is_finite() && fov_y_deg > 0.0 && fov_y_deg < 180.0) {
                    return Err(Error::invalid(
                        "camera fov-y",
                        format!("must be in (0, 180) degrees, got {fov_y_deg}"),
                    ));
                }
            }
            Projection::Orthographic { height } => {
                if !(height.is_finite() && height > 0.0) {
                    return Err(Error::invalid(
                        "camera ortho height",
                        format!("must be > 0, got {height}"),
                    ));
                }
            }
            Projection::PerspectiveIntrinsics(k) | Projection::OrthographicIntrinsics(k) => {
                if !(k.fx.is_finite() && k.fx > 0.0 && k.fy.is_finite() && k.fy > 0.0) {
                    return Err(Error::invalid(
                        "camera intrinsics",
                        format!("fx and fy must be > 0, got {} and {}", k.fx, k.fy),
                    ));
                }
                if !(k.cx.is_finite() && k.cy.is_finite()) {
                    return Err(Error::invalid(
                        "camera intrinsics",
                        format!("the principal point ({}, {}) is not finite", k.cx, k.cy),
                    ));
                }
            }
        }
        if !self.jitter.is_finite() {
            return Err(Error::invalid(
                "camera jitter",
                format!("not finite: {}", self.jitter),
            ));
        }
        let (scale_x, scale_y) = self.ndc_scale();
        // The push constants hold the scales in float32: they must be normal numbers there.
        for (axis, scale) in [("x", scale_x), ("y", scale_y)] {
            if !(scale as f32).is_normal() {
                let k = self.intrinsics();
                return Err(Error::invalid(
                    "camera intrinsics",
                    format!(
                        "the {axis} focal length ({} by {}) gives a screen scale of {scale:e},                          beyond float32's normal range",
                        k.fx, k.fy
                    ),
                ));
            }
        }
        let (shift_x, shift_y) = self.ndc_shift();
        let shift_px =
            (0.5 * shift_x.abs() * self.width as f64).max(0.5 * shift_y.abs() * self.height as f64);
        if shift_px > Self::MAX_PRINCIPAL_SHIFT_PX {
            let k = self.intrinsics();
            return Err(Error::invalid(
                "camera principal point",
                format!(
                    "({}, {}) with jitter ({}, {}) lies {shift_px:.0} pixels from the centre of \
                     the {}x{} image, more than {} (float32 would round \
                     pixel positions)",
                    k.cx,
                    k.cy,
                    self.jitter.x,
                    self.jitter.y,
                    self.width,
                    self.height,
                    Self::MAX_PRINCIPAL_SHIFT_PX
                ),
            ));
        }
        if shift_x.abs().max(shift_y.abs()) > Self::MAX_PRINCIPAL_SHIFT {
            let k = self.intrinsics();
            return Err(Error::invalid(
                "camera principal point",
                format!(
                    "({}, {}) with jitter ({}, {}) lies more than {} half images from the \
                     centre of the {}x{} image",
                    k.cx,
                    k.cy,
                    self.jitter.x,
                    self.jitter.y,
                    Self::MAX_PRINCIPAL_SHIFT,
                    self.width,
                    self.height
                ),
            ));
        }
        Ok(())
    }

    /// The camera frame of the contract.
    #[doc(hidden)] // For the float64 reference, as its types (`internals`).
    pub fn basis(&self) -> Basis {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        Basis { right, up, forward }
    }

    /// The projection's intrinsics in pixels (without the jitter): the general form of every
    /// [`Projection`].
    pub fn intrinsics(&self) -> Intrinsics {
        let (w, h) = (self.width as f64, self.height as f64);
        let centred = |f: f64| Intrinsics {
            fx: f,
            fy: f,
            cx: 0.5 * w,
            cy: 0.5 * h,
        };
        match self.projection {
            Projection::Perspective { fov_y_deg } => {
                centred(0.5 * h / (fov_y_deg.to_radians() * 0.5).tan())
            }
            Projection::Orthographic { height } => centred(h / height),
            Projection::PerspectiveIntrinsics(k) | Projection::OrthographicIntrinsics(k) => k,
        }
    }

    /// The screen-plane point (x along `r`, y along `u`; slopes per unit of view depth in
    /// perspective, world units in orthographic) that continuous pixel position `pixel` (x
    /// right, y down, pixel `(i, j)`'s centre at `(i + 0.5, j + 0.5)`) samples, jitter
    /// included.
    pub fn pixel_to_screen(&self, pixel: DVec2) -> DVec2 {
        let k = self.intrinsics();
        DVec2::new(
            (pixel.x + self.jitter.x - k.cx) / k.fx,
            (k.cy - pixel.y - self.jitter.y) / k.fy,
        )
    }

    /// The continuous pixel position that samples screen-plane point `screen` (the inverse
    /// of [`Camera::pixel_to_screen`]).
    pub fn screen_to_pixel(&self, screen: DVec2) -> DVec2 {
        let k = self.intrinsics();
        DVec2::new(
            k.cx - self.jitter.x + screen.x * k.fx,
            k.cy - self.jitter.y - screen.y * k.fy,
        )
    }

    /// The screen-plane rectangle the image covers, `(low, high)` corners.
    pub fn screen_window(&self) -> (DVec2, DVec2) {
        let a = self.pixel_to_screen(DVec2::new(0.0, self.height as f64));
        let b = self.pixel_to_screen(DVec2::new(self.width as f64, 0.0));
        (a, b)
    }

    /// The shaders' screen map (design §3.2, `PushConstants`): their NDC `v` is a screen-plane point over these
    /// scales, `s = (v.x sx, v.y sy)`, and Vulkan's NDC of the image is `v - ndc_shift` (y
    /// up). Centred cameras have `sx / sy = W / H` and no shift.
    pub fn ndc_scale(&self) -> (f64, f64) {
        let k = self.intrinsics();
        (
            0.5 * self.width as f64 / k.fx,
            0.5 * self.height as f64 / k.fy,
        )
    }

    /// How far the shaders' NDC lies from Vulkan's NDC of the image (y up), from the
    /// principal point and the jitter: 0 for a centred camera.
    pub fn ndc_shift(&self) -> (f64, f64) {
        let k = self.intrinsics();
        (
            1.0 - 2.0 * (k.cx - self.jitter.x) / self.width as f64,
            2.0 * (k.cy - self.jitter.y) / self.height as f64 - 1.0,
        )
    }

    /// The ray through the centre of pixel `(i, j)`.
    #[doc(hidden)] // For the float64 reference, as its types (`internals`).
    pub fn ray(&self, i: u32, j: u32) -> Ray {
        self.ray_at_pixel(DVec2::new(i as f64 + 0.5, j as f64 + 0.5))
    }

    /// The ray through continuous pixel position `pixel` (pixel `(i, j)`'s centre at
    /// `(i + 0.5, j + 0.5)`), jitter included.
    #[doc(hidden)] // For the float64 reference, as its types (`internals`).
    pub fn ray_at_pixel(&self, pixel: DVec2) -> Ray {
        let b = self.basis();
        let s = self.pixel_to_screen(pixel);
        let offset = s.x * b.right + s.y * b.up;
        if self.is_orthographic() {
            Ray {
                origin: self.eye + offset,
                direction: b.forward,
            }
        } else {
            Ray {
                origin: self.eye,
                direction: b.forward + offset,
            }
        }
    }

    /// View depth of a world point: `dot(p - eye, f)`.
    pub fn view_depth(&self, p: DVec3) -> f64 {
        (p - self.eye).dot(self.basis().forward)
    }

    /// A perspective camera with +Y up, checked.
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        fov_y_deg: f64,
        near: f64,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        Self::new(
            eye,
            target,
            DVec3::Y,
            Projection::Perspective { fov_y_deg },
            near,
            width,
            height,
        )
    }

    /// Is this an orthographic camera?
    pub fn is_orthographic(&self) -> bool {
        matches!(
            self.projection,
            Projection::Orthographic { .. } | Projection::OrthographicIntrinsics(_)
        )
    }

    /// A camera that frames a bounding sphere from a pleasant oblique direction.
    pub fn framing(center: DVec3, radius: f64, width: u32, height: u32) -> Result<Self> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(Error::invalid(
                "image size",
                format!("{width}x{height} is outside 1..={MAX_SIDE}"),
            ));
        }
        let fov_y_deg: f64 = 45.0;
        let radius = radius.max(1e-9);
        // Fit the sphere into the narrower of the two fields of view.
        let half_v = (fov_y_deg.to_radians() * 0.5).tan();
        let half = half_v.min(half_v * width as f64 / height as f64);
        let distance = radius * (1.0 + half * half).sqrt() / half * 1.05;
        let direction = DVec3::new(0.55, 0.45, 1.0).normalize();
        Camera::new(
            center + direction * distance,
            center,
            DVec3::Y,
            Projection::Perspective { fov_y_deg },
            (distance - radius).max(distance * 1e-3) * 0.5,
            width,
            height,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(projection: Projection) -> Camera {
        Camera::new(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            projection,
            0.1,
            4,
            2,
        )
        .unwrap()
    }

    /// A principal point far off a large image is refused (float32 would round its pixels),
    /// the same offset on a small image within its half-image bound is not; focal lengths
    /// outside float32's range are refused.
    #[test]
    fn principal_points_and_focal_lengths_stay_in_float32s_reach() {
        let at = |cx: f64, width: u32, fx: f64| {
            Camera::new(
                DVec3::new(0.0, 0.0, 5.0),
                DVec3::ZERO,
                DVec3::Y,
                Projection::PerspectiveIntrinsics(Intrinsics {
                    fx,
                    fy: 1000.0,
                    cx,
                    cy: 8.0,
                }),
                0.1,
                width,
                16,
            )
        };
        assert!(at(8192.0 + 8000.0, 16384, 1000.0).is_ok());
        let far = at(8192.0 + 8200.0, 16384, 1000.0).unwrap_err().to_string();
        assert!(far.contains("8200 pixels") && far.contains("8192"), "{far}");
        assert!(at(100.0 + 6000.0, 200, 1000.0).is_ok());
        let beyond = at(100.0 + 6500.0, 200, 1000.0).unwrap_err().to_string();
        assert!(beyond.contains("half images"), "{beyond}");
        for fx in [1e-300, 1e300] {
            let error = at(8.0, 16, fx).unwrap_err().to_string();
            assert!(error.contains("float32"), "{fx}: {error}");
        }
    }

    #[test]
    fn basis_follows_contract() {
        let b = camera(Projection::Perspective { fov_y_deg: 90.0 }).basis();
        assert!((b.forward - DVec3::NEG_Z).length() < 1e-15);
        assert!((b.right - DVec3::X).length() < 1e-15);
        assert!((b.up - DVec3::Y).length() < 1e-15);
    }

    #[test]
    fn perspective_corner_pixel_ray() {
        let c = camera(Projection::Perspective { fov_y_deg: 90.0 });
        // Pixel (0,0): ndc = (1/4 - 1, 1 - 1/2) = (-0.75, 0.5); tan(45) = 1, aspect 2.
        let ray = c.ray(0, 0);
        let want = DVec3::new(-0.75 * 2.0, 0.5, -1.0);
        assert!((ray.direction - want).length() < 1e-12, "{:?}", ray);
        assert_eq!(ray.origin, c.eye);
    }

    #[test]
    fn orthographic_pixel_ray() {
        let c = camera(Projection::Orthographic { height: 2.0 });
        let ray = c.ray(3, 1);
        // ndc = (7/4 - 1, 1 - 3/2) = (0.75, -0.5); h/2 = 1, aspect 2.
        let want = c.eye + DVec3::new(1.5, -0.5, 0.0);
        assert!((ray.origin - want).length() < 1e-12);
        assert_eq!(ray.direction, DVec3::NEG_Z);
    }

    #[test]
    fn framing_names_a_bad_image_size() {
        let err = Camera::framing(DVec3::ZERO, 1.0, 0, 100).unwrap_err();
        assert!(err.to_string().contains("image size"), "{err}");
    }

    #[test]
    fn bad_fields_are_named() {
        let mut c = camera(Projection::Perspective { fov_y_deg: 45.0 });
        c.near = 0.0;
        assert!(c.validate().unwrap_err().to_string().contains("near"));
        c.near = 1.0;
        c.up = DVec3::Z;
        assert!(c.validate().unwrap_err().to_string().contains("up"));
        c.up = DVec3::Y;
        c.projection = Projection::Perspective { fov_y_deg: 180.0 };
        assert!(c.validate().unwrap_err().to_string().contains("fov"));
    }
}
