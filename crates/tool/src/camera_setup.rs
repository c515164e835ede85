//! The camera `render`, `view` and `bench --scene` draw with, made from their flags and
//! framing the scene where they leave positions out; the warning when it shows nothing; and
//! a camera written back as `render` flags.

use ellipsoid_splat::Scene;
use ellipsoid_splat::{Camera, Projection};
use glam::{DVec2, DVec3};

use crate::cli::values::xyz;
use crate::cli::RenderArgs;
use crate::error::{Error, Result};

/// The camera of the render arguments, framing the scene where positions are not given.
/// Errors name the flag to change.
pub fn camera_for(args: &RenderArgs, scene: &Scene) -> Result<Camera> {
    camera_around(args, scene.bounding_sphere())
}

/// The camera of the render arguments, framing a scene of bounding sphere `sphere`
/// ([`Scene::bounding_sphere`]; `None` when empty) where positions are not given.
pub fn camera_around(args: &RenderArgs, sphere: Option<(DVec3, f64)>) -> Result<Camera> {
    let (center, radius) = sphere.ok_or_else(|| Error::invalid("--scene", "has no ellipsoids"))?;
    let projection = match (args.camera.ortho, args.camera.intrinsics) {
        (Some(height), _) => Projection::Orthographic { height },
        (None, Some(intrinsics)) => Projection::PerspectiveIntrinsics(intrinsics),
        (None, None) => Projection::Perspective {
            fov_y_deg: args.camera.fov_y,
        },
    };
    let (width, height) = args.camera_size();
    let mut camera = Camera::framing(center, radius, width, height)?;
    camera.projection = projection;
    camera.jitter = args.jitter.unwrap_or(DVec2::ZERO);
    if let Some([x, y, _, _]) = args.viewport {
        camera.viewport_origin = [x, y];
    }
    camera.up = args.camera.up;
    if let Some(target) = args.camera.target {
        camera.target = target;
    }
    if let Some(eye) = args.camera.eye {
        camera.eye = eye;
        if args.camera.target.is_none() {
            camera.target = center;
        }
    }
    let view = camera.target - camera.eye;
    if view.length() <= 1e-12 * camera.eye.length().max(1.0) {
        let (flag, what) = if args.camera.eye.is_some() && args.camera.target.is_none() {
            (
                "--eye",
                "is the scene's centre, which the camera looks at without --target",
            )
        } else {
            ("--target", "is where the camera is (--eye)")
        };
        return Err(Error::invalid(
            flag,
            format!(
                "{} {what}; give a --target away from --eye",
                xyz(camera.target)
            ),
        ));
    }
    if view.normalize().cross(args.camera.up.normalize()).length() < 1e-9 {
        return Err(Error::invalid(
            "--up",
            format!(
                "{} is parallel to the view direction (from {} to {}); give an --up across it",
                xyz(args.camera.up),
                xyz(camera.eye),
                xyz(camera.target)
            ),
        ));
    }
    camera.near = match args.near {
        Some(near) => near,
        None => {
            // Half way to the bounding sphere, or a small fraction of its size from inside.
            let gap = (center - camera.eye).length() - radius;
            if gap > 0.0 {
                0.5 * gap
            } else {
                radius * 1e-3
            }
        }
    };
    camera.validate().map_err(|e| match e {
        ellipsoid_splat::Error::Invalid { what, reason } if what.starts_with("camera ") => {
            let flag = match what.as_str() {
                "camera intrinsics" | "camera principal point"
                    if args.camera.intrinsics.is_some() =>
                {
                    "--intrinsics"
                }
                "camera principal point" | "camera jitter" => "--jitter",
                "camera viewport" => "--viewport",
                _ => return Error::invalid(what, reason),
            };
            Error::invalid(flag, reason)
        }
        other => Error::from(other),
    })?;
    Ok(camera)
}

/// Why `camera` certainly shows none of `scene`, if it does: the scene is behind the eye,
/// outside the field of view, or nearer than the near plane. Such an image is empty but not
/// an error (a camera path may pass by), so this is a warning to print.
pub fn nothing_in_view(args: &RenderArgs, camera: &Camera, scene: &Scene) -> Option<String> {
    nothing_in_view_around(args, camera, scene.bounding_sphere()?)
}

/// [`nothing_in_view`] of a scene of bounding sphere `(center, radius)`.
pub fn nothing_in_view_around(
    args: &RenderArgs,
    camera: &Camera,
    (center, radius): (DVec3, f64),
) -> Option<String> {
    let basis = camera.basis();
    let offset = center - camera.eye;
    let depth = offset.dot(basis.forward);
    let lateral = (offset - depth * basis.forward).length();
    let looking = format!(
        "looking from {} towards {} (--eye, --target)",
        xyz(camera.eye),
        xyz(camera.target)
    );
    let sphere = format!("centre {}, radius {radius:.4}", xyz(center));
    if depth + radius <= 0.0 {
        return Some(format!(
            "the image is empty: {looking}, the whole scene ({sphere}) is behind the camera"
        ));
    }
    // The screen-plane corner farthest from the view axis.
    let (lo, hi) = camera.screen_window();
    let half_diagonal = lo.x.abs().max(hi.x.abs()).hypot(lo.y.abs().max(hi.y.abs()));
    let outside = if camera.is_orthographic() {
        lateral - radius > half_diagonal
    } else {
        // The frustum lies in the cone of half-angle atan(half_diagonal) around the view
        // direction; the sphere is outside when its angular distance from the axis exceeds
        // that half-angle plus its own angular radius.
        let distance = offset.length();
        distance > radius && {
            let angle = lateral.atan2(depth);
            let angular_radius = (radius / distance).asin();
            angle - angular_radius > half_diagonal.atan()
        }
    };
    if outside {
        return Some(format!(
            "the image is empty: {looking}, the scene ({sphere}) is outside the field of view"
        ));
    }
    if depth + radius <= camera.near {
        let near = match args.near {
            Some(near) => format!("--near {near}"),
            None => format!("the near plane at {:.4}", camera.near),
        };
        return Some(format!(
            "the image is empty: {near} is beyond the farthest point of the scene (view depth \
             {:.4})",
            depth + radius
        ));
    }
    None
}

/// The `render` flags of `camera`'s view and image (numbers in Rust's shortest round-trip
/// form, so they read back to the same float64).
pub fn camera_flags(camera: &Camera) -> String {
    let v = |v: DVec3| format!("{:?},{:?},{:?}", v.x, v.y, v.z);
    let projection = match camera.projection {
        Projection::Perspective { fov_y_deg } => format!("--fov-y {fov_y_deg:?}"),
        Projection::Orthographic { height } => format!("--ortho {height:?}"),
        Projection::PerspectiveIntrinsics(i) => {
            format!("--intrinsics {:?},{:?},{:?},{:?}", i.fx, i.fy, i.cx, i.cy)
        }
        // No `render` flag makes the others (the library's orthographic intrinsics).
        other => format!("(projection {other:?}: no render flag)"),
    };
    format!(
        "--width {} --height {} --eye {} --target {} --up {} {projection} --near {:?}",
        camera.width,
        camera.height,
        v(camera.eye),
        v(camera.target),
        v(camera.up),
        camera.near
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::render_args;
    use ellipsoid_splat_loaders as scene;

    #[test]
    fn empty_views_are_reported() {
        let scene = scene::random_cloud(10, 1, 4.0, 1.0);
        let warn = |extra: &[&str]| {
            let args = render_args(extra);
            let camera = camera_for(&args, &scene).unwrap();
            nothing_in_view(&args, &camera, &scene)
        };
        assert_eq!(warn(&[]), None);
        let behind = warn(&["--eye", "0,0,100", "--target", "0,0,200"]).unwrap();
        assert!(behind.contains("behind the camera"), "{behind}");
        let near = warn(&["--near", "1e6"]).unwrap();
        assert!(near.contains("--near"), "{near}");
        let aside = warn(&["--eye", "0,0,100", "--target", "500,0,100"]).unwrap();
        assert!(aside.contains("outside the field of view"), "{aside}");
        let ortho_aside = warn(&["--eye", "0,0,100", "--target", "500,0,100", "--ortho", "2"]);
        assert!(ortho_aside.is_some());
        assert_eq!(warn(&["--ortho", "2"]), None);
    }
}
