//! The cameras of a sequence's views: every kind a host can describe (perspective,
//! orthographic, intrinsics of an asymmetric frustum or an off-centre window, the host's own
//! view and projection matrices; jittered or not), posed around the glyphs' cube and placed in
//! a strip of the target. And the degenerate ones, each with the name its refusal must carry.

use ellipsoid_splat::{Camera, DepthConvention, HostViewport, Intrinsics, Projection, Result};
use ellipsoid_splat_test_host::DepthKind;
use ellipsoid_splat_test_host::{reversed_infinite_perspective, standard_finite_perspective};
use glam::{DMat4, DVec2, DVec3, DVec4};

/// How a view's camera is described.
#[derive(Clone, Copy, Debug)]
pub enum CameraKind {
    LookAt {
        fov_y_deg: f64,
    },
    Orthographic {
        height: f64,
    },
    /// An asymmetric frustum by its edges' tangents (all positive: the axis inside).
    Tangents {
        left: f64,
        right: f64,
        bottom: f64,
        top: f64,
    },
    /// An off-centre orthographic window, in world units.
    Window {
        left: f64,
        right: f64,
        bottom: f64,
        top: f64,
    },
    /// The host's matrices (perspective or orthographic) in the target's depth convention.
    Matrices {
        fov_y_deg: f64,
        orthographic: bool,
    },
}

/// Where the eye is and what else the camera carries.
#[derive(Clone, Copy, Debug)]
pub struct CameraChoice {
    pub kind: CameraKind,
    /// Degrees around the vertical axis, and above the horizon.
    pub azimuth: f64,
    pub elevation: f64,
    pub distance: f64,
    /// The near plane as a share of the distance (large shares cut glyphs: caps).
    pub near_share: f64,
    /// The point looked at, near the cube's centre.
    pub look: [f64; 3],
    pub jitter: Option<[f64; 2]>,
}

/// A rectangle of the target: `(x, y, width, height)`.
pub type Rect = (u32, u32, u32, u32);

impl CameraChoice {
    fn eye_and_look(&self) -> (DVec3, DVec3) {
        let (az, el) = (self.azimuth.to_radians(), self.elevation.to_radians());
        let look = DVec3::from_array(self.look);
        let dir = DVec3::new(el.cos() * az.cos(), el.sin(), el.cos() * az.sin());
        (look + dir * self.distance, look)
    }

    fn near(&self) -> f64 {
        self.near_share * self.distance
    }

    fn far(&self) -> f64 {
        self.distance * 2.5
    }

    /// The camera drawing into `rect` of a target whose depth is `depth`.
    pub fn build(&self, rect: Rect, depth: DepthKind) -> Result<Camera> {
        let (x, y, w, h) = rect;
        let (eye, look) = self.eye_and_look();
        let (near, far) = (self.near(), self.far());
        let convention = match depth {
            DepthKind::ReversedInfinite => DepthConvention::REVERSED_INFINITE,
            DepthKind::StandardFinite => DepthConvention {
                reversed: false,
                far: Some(far),
            },
        };
        let projection = match self.kind {
            CameraKind::LookAt { fov_y_deg } => Projection::Perspective { fov_y_deg },
            CameraKind::Orthographic { height } => Projection::Orthographic { height },
            CameraKind::Tangents {
                left,
                right,
                bottom,
                top,
            } => Projection::PerspectiveIntrinsics(Intrinsics::from_tangents(
                -left, right, -bottom, top, w, h,
            )?),
            CameraKind::Window {
                left,
                right,
                bottom,
                top,
            } => Projection::OrthographicIntrinsics(Intrinsics::from_ortho_window(
                -left, right, -bottom, top, w, h,
            )?),
            CameraKind::Matrices {
                fov_y_deg,
                orthographic,
            } => {
                let view = DMat4::look_at_rh(eye, look, DVec3::Y);
                let aspect = w as f64 / h as f64;
                let projection = match (orthographic, depth) {
                    (false, DepthKind::ReversedInfinite) => {
                        reversed_infinite_perspective(fov_y_deg.to_radians(), aspect, near)
                    }
                    (false, DepthKind::StandardFinite) => {
                        standard_finite_perspective(fov_y_deg.to_radians(), aspect, near, far)
                    }
                    (true, depth) => {
                        orthographic_matrix(fov_y_deg / 20.0, aspect, near, far, depth)
                    }
                };
                let viewport = HostViewport {
                    x,
                    y,
                    width: w,
                    height: h as i32,
                };
                return Camera::from_view_projection_viewport(view, projection, viewport);
            }
        };
        let camera = Camera::new(eye, look, DVec3::Y, projection, near, w, h)?
            .with_depth(convention)?
            .with_viewport_origin(x, y)?;
        match self.jitter {
            Some([dx, dy]) => camera.with_jitter(DVec2::new(dx, dy)),
            None => Ok(camera),
        }
    }
}

/// A Vulkan orthographic projection (y down, z in [0, 1]) `height` world units tall, in the
/// target's depth convention between `near` and `far`.
fn orthographic_matrix(height: f64, aspect: f64, near: f64, far: f64, depth: DepthKind) -> DMat4 {
    let (sx, sy) = (2.0 / (height * aspect), -2.0 / height);
    // View depth d = -z: standard z = (d - n) / (f - n), reversed z = (f - d) / (f - n).
    let (zz, zw) = match depth {
        DepthKind::StandardFinite => (-1.0 / (far - near), -near / (far - near)),
        DepthKind::ReversedInfinite => (1.0 / (far - near), far / (far - near)),
    };
    DMat4::from_cols(
        DVec4::new(sx, 0.0, 0.0, 0.0),
        DVec4::new(0.0, sy, 0.0, 0.0),
        DVec4::new(0.0, 0.0, zz, 0.0),
        DVec4::new(0.0, 0.0, zw, 1.0),
    )
}

/// A field of a valid camera set to what no renderer can draw with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraDefect {
    ZeroWidth,
    ZeroHeight,
    Oversize,
    NearZero,
    NearNegative,
    NearNan,
    FarAtNear,
    FarNan,
    FovZero,
    Fov180,
    FovNan,
    OrthoHeightZero,
    OrthoHeightInfinite,
    FocalZero,
    FocalNegative,
    FocalHuge,
    FocalTiny,
    PrincipalNan,
    PrincipalFar,
    EyeNan,
    EyeInfinite,
    TargetAtEye,
    UpZero,
    UpAlongView,
    JitterNan,
    ViewportBeyond,
}

impl CameraDefect {
    pub const ALL: [CameraDefect; 26] = [
        CameraDefect::ZeroWidth,
        CameraDefect::ZeroHeight,
        CameraDefect::Oversize,
        CameraDefect::NearZero,
        CameraDefect::NearNegative,
        CameraDefect::NearNan,
        CameraDefect::FarAtNear,
        CameraDefect::FarNan,
        CameraDefect::FovZero,
        CameraDefect::Fov180,
        CameraDefect::FovNan,
        CameraDefect::OrthoHeightZero,
        CameraDefect::OrthoHeightInfinite,
        CameraDefect::FocalZero,
        CameraDefect::FocalNegative,
        CameraDefect::FocalHuge,
        CameraDefect::FocalTiny,
        CameraDefect::PrincipalNan,
        CameraDefect::PrincipalFar,
        CameraDefect::EyeNan,
        CameraDefect::EyeInfinite,
        CameraDefect::TargetAtEye,
        CameraDefect::UpZero,
        CameraDefect::UpAlongView,
        CameraDefect::JitterNan,
        CameraDefect::ViewportBeyond,
    ];

    /// What the refusal names (`Error::Invalid::what`).
    pub fn name(self) -> &'static str {
        use CameraDefect::*;
        match self {
            ZeroWidth | ZeroHeight | Oversize => "image size",
            NearZero | NearNegative | NearNan => "camera near",
            FarAtNear | FarNan => "camera far",
            FovZero | Fov180 | FovNan => "camera fov-y",
            OrthoHeightZero | OrthoHeightInfinite => "camera ortho height",
            FocalZero | FocalNegative | FocalHuge | FocalTiny | PrincipalNan => "camera intrinsics",
            PrincipalFar => "camera principal point",
            EyeNan | EyeInfinite => "camera eye",
            TargetAtEye => "camera target",
            UpZero | UpAlongView => "camera up",
            JitterNan => "camera jitter",
            ViewportBeyond => "camera viewport",
        }
    }

    /// `camera` (valid) with this defect written into its fields.
    pub fn apply(self, camera: Camera) -> Camera {
        use CameraDefect::*;
        let mut c = camera;
        let intrinsics = |c: &Camera| c.intrinsics();
        match self {
            ZeroWidth => c.width = 0,
            ZeroHeight => c.height = 0,
            Oversize => c.height = 20_000,
            NearZero => c.near = 0.0,
            NearNegative => c.near = -0.5,
            NearNan => c.near = f64::NAN,
            FarAtNear => c.depth.far = Some(c.near),
            FarNan => c.depth.far = Some(f64::NAN),
            FovZero => c.projection = Projection::Perspective { fov_y_deg: 0.0 },
            Fov180 => c.projection = Projection::Perspective { fov_y_deg: 180.0 },
            FovNan => {
                c.projection = Projection::Perspective {
                    fov_y_deg: f64::NAN,
                }
            }
            OrthoHeightZero => c.projection = Projection::Orthographic { height: 0.0 },
            OrthoHeightInfinite => {
                c.projection = Projection::Orthographic {
                    height: f64::INFINITY,
                }
            }
            FocalZero | FocalNegative | FocalHuge | FocalTiny | PrincipalNan | PrincipalFar => {
                let mut k = intrinsics(&c);
                match self {
                    FocalZero => k.fx = 0.0,
                    FocalNegative => k.fy = -k.fy,
                    FocalHuge => k.fx = 1e300,
                    FocalTiny => k.fy = 1e-300,
                    PrincipalNan => k.cx = f64::NAN,
                    _ => k.cx += 1e5,
                }
                c.projection = if c.is_orthographic() {
                    Projection::OrthographicIntrinsics(k)
                } else {
                    Projection::PerspectiveIntrinsics(k)
                };
            }
            EyeNan => c.eye.y = f64::NAN,
            EyeInfinite => c.eye.x = f64::NEG_INFINITY,
            TargetAtEye => c.target = c.eye,
            UpZero => c.up = DVec3::ZERO,
            UpAlongView => c.up = c.target - c.eye,
            JitterNan => c.jitter.x = f64::NAN,
            ViewportBeyond => c.viewport_origin[0] = 16_384,
        }
        c
    }

    /// The same camera asked of the checked constructors: refused with the same name.
    pub fn construct(camera: &Camera) -> Result<Camera> {
        Camera::new(
            camera.eye,
            camera.target,
            camera.up,
            camera.projection,
            camera.near,
            camera.width,
            camera.height,
        )?
        .with_depth(camera.depth)?
        .with_jitter(camera.jitter)?
        .with_viewport_origin(camera.viewport_origin[0], camera.viewport_origin[1])
    }
}

/// Host matrices or a host viewport no camera can be made from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixDefect {
    NanEntry,
    /// Every point to one clip position.
    Singular,
    EmptyViewport,
    /// A flipped viewport whose bottom edge lies above its height.
    FlippedAboveTop,
}

impl MatrixDefect {
    pub const ALL: [MatrixDefect; 4] = [
        MatrixDefect::NanEntry,
        MatrixDefect::Singular,
        MatrixDefect::EmptyViewport,
        MatrixDefect::FlippedAboveTop,
    ];

    pub fn name(self) -> &'static str {
        match self {
            MatrixDefect::NanEntry | MatrixDefect::Singular => "host view and projection matrices",
            MatrixDefect::EmptyViewport | MatrixDefect::FlippedAboveTop => "host viewport",
        }
    }

    /// Asks `Camera::from_view_projection_viewport` for the defective camera in `rect`.
    pub fn construct(self, rect: Rect) -> Result<Camera> {
        let (x, y, w, h) = rect;
        let view = DMat4::look_at_rh(DVec3::new(0.0, 1.0, 8.0), DVec3::ZERO, DVec3::Y);
        let mut projection = reversed_infinite_perspective(0.8, w as f64 / h as f64, 0.5);
        let mut viewport = HostViewport {
            x,
            y,
            width: w,
            height: h as i32,
        };
        match self {
            MatrixDefect::NanEntry => projection.x_axis.y = f64::NAN,
            MatrixDefect::Singular => projection = DMat4::ZERO,
            MatrixDefect::EmptyViewport => viewport.width = 0,
            MatrixDefect::FlippedAboveTop => {
                viewport.height = -(h as i32);
                viewport.y = h - 1;
            }
        }
        Camera::from_view_projection_viewport(view, projection, viewport)
    }
}
