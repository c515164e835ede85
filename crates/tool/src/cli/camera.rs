//! The camera flags `render`, `view` and `bench --scene` share (the camera itself is made in
//! `camera_setup`).

use clap::Args;
use ellipsoid_splat::Intrinsics;
use glam::DVec3;

use super::values::{parse_intrinsics, parse_number, parse_vec3};

/// The camera flags `render`, `view` and `bench --scene` share: where the camera is, where it
/// looks and its projection (the defaults frame the scene, see
/// [`crate::camera_setup::camera_for`]).
#[derive(Debug, Clone, Args)]
pub struct CameraArgs {
    /// Eye position `x,y,z` (default: frames the scene).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<DVec3>,
    /// Point looked at `x,y,z` (default: the scene's centre).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<DVec3>,
    /// Up direction `x,y,z`.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,1,0")]
    pub up: DVec3,
    /// Vertical field of view in degrees (perspective).
    #[arg(
        long,
        default_value_t = DEFAULT_FOV_Y,
        conflicts_with = "ortho",
        value_parser = parse_number,
        allow_hyphen_values = true
    )]
    pub fov_y: f64,
    /// Orthographic projection with this view height.
    #[arg(long, value_parser = parse_number, allow_hyphen_values = true)]
    pub ortho: Option<f64>,
    /// A pinhole camera's intrinsics `fx,fy,cx,cy` in pixels (OpenCV's; instead of --fov-y):
    /// the ray through pixel centre (i + 0.5, j + 0.5), row 0 at the top, has the camera-frame
    /// direction ((i + 0.5 - cx) / fx, (j + 0.5 - cy) / fy, 1), x right, y down, z forward.
    /// Off-centre principal points, asymmetric frusta and non-square pixels. In the camera's
    /// pixels (--viewport's size when given).
    #[arg(
        long,
        value_parser = parse_intrinsics,
        allow_hyphen_values = true,
        conflicts_with_all = ["ortho", "fov_y"]
    )]
    pub intrinsics: Option<Intrinsics>,
}

impl CameraArgs {
    /// The first of these flags given a value other than its default, if any.
    pub fn given(&self) -> Option<&'static str> {
        [
            ("--eye", self.eye.is_some()),
            ("--target", self.target.is_some()),
            ("--up", self.up != DVec3::Y),
            ("--fov-y", self.fov_y != DEFAULT_FOV_Y),
            ("--ortho", self.ortho.is_some()),
            ("--intrinsics", self.intrinsics.is_some()),
        ]
        .into_iter()
        .find_map(|(flag, given)| given.then_some(flag))
    }
}

/// The vertical field of view `--fov-y` defaults to, degrees.
pub const DEFAULT_FOV_Y: f64 = 45.0;
