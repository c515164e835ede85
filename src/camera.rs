//! The camera and the pixel-ray contract of `docs/design.md` §3, in float64.
//!
//! `f = normalize(target - eye)`, `r = normalize(f x up)`, `u = r x f`. Pixel `(i, j)` (row 0 at
//! the top) has `ndc = ((2i+1)/W - 1, 1 - (2j+1)/H)`. Perspective: the ray leaves `eye` along
//! `f + tan(fovy/2) (ndc_x W/H r + ndc_y u)`. Orthographic with view height `h`: the ray leaves
//! `eye + h/2 (ndc_x W/H r + ndc_y u)` along `f`. View depth of `p` is `dot(p - eye, f)`; nothing
//! nearer than `near` is visible.

use glam::DVec3;

use crate::depth::{DepthConvention, DepthMap};
use crate::error::{Error, Result};

/// How the view volume is shaped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole camera with the vertical field of view in degrees, in (0, 180).
    Perspective {
        /// Vertical field of view in degrees.
        fov_y_deg: f64,
    },
    /// Parallel rays; `height` is the world-space height of the view.
    Orthographic {
        /// World-space height of the image.
        height: f64,
    },
}

/// A validated camera: position, orientation, projection, near plane and image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (perspective centre, or centre of the orthographic image plane).
    pub eye: DVec3,
    /// Point looked at.
    pub target: DVec3,
    /// Approximate up direction.
    pub up: DVec3,
    /// Perspective or orthographic.
    pub projection: Projection,
    /// Distance of the near plane along the view direction, > 0.
    pub near: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// How view depth maps to the depth buffer (reversed Z, infinite far plane unless set).
    pub depth: DepthConvention,
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

impl Camera {
    /// A checked camera. Errors name the bad field.
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
        if self.width == 0 || self.height == 0 || self.width > 16384 || self.height > 16384 {
            return Err(Error::invalid(
                "image size",
                format!("{}x{} is outside 1..=16384", self.width, self.height),
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
        }
        Ok(())
    }

    /// The camera frame of the contract.
    pub fn basis(&self) -> Basis {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        Basis { right, up, forward }
    }

    /// `W / H`.
    pub fn aspect(&self) -> f64 {
        self.width as f64 / self.height as f64
    }

    /// Normalised device coordinates of pixel `(i, j)`'s centre.
    pub fn pixel_ndc(&self, i: u32, j: u32) -> (f64, f64) {
        (
            (2.0 * i as f64 + 1.0) / self.width as f64 - 1.0,
            1.0 - (2.0 * j as f64 + 1.0) / self.height as f64,
        )
    }

    /// Screen-plane scale factors: how far along `r` and `u` one NDC unit reaches, per unit of
    /// forward travel (perspective) or in world units (orthographic).
    pub fn ndc_scale(&self) -> (f64, f64) {
        let half = match self.projection {
            Projection::Perspective { fov_y_deg } => (fov_y_deg.to_radians() * 0.5).tan(),
            Projection::Orthographic { height } => 0.5 * height,
        };
        (half * self.aspect(), half)
    }

    /// The ray through the centre of pixel `(i, j)`.
    pub fn ray(&self, i: u32, j: u32) -> Ray {
        let (x, y) = self.pixel_ndc(i, j);
        self.ray_at_ndc(x, y)
    }

    /// The ray through an arbitrary NDC position.
    pub fn ray_at_ndc(&self, x: f64, y: f64) -> Ray {
        let b = self.basis();
        let (sx, sy) = self.ndc_scale();
        let offset = x * sx * b.right + y * sy * b.up;
        match self.projection {
            Projection::Perspective { .. } => Ray {
                origin: self.eye,
                direction: b.forward + offset,
            },
            Projection::Orthographic { .. } => Ray {
                origin: self.eye + offset,
                direction: b.forward,
            },
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
        matches!(self.projection, Projection::Orthographic { .. })
    }

    /// A camera that frames a bounding sphere from a pleasant oblique direction.
    pub fn framing(center: DVec3, radius: f64, width: u32, height: u32) -> Result<Self> {
        if width == 0 || height == 0 || width > 16384 || height > 16384 {
            return Err(Error::invalid(
                "image size",
                format!("{width}x{height} is outside 1..=16384"),
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
