//! The benchmark's moving camera (`bench --orbit DEG`): every frame a method draws has its
//! camera turned DEG degrees further about the target than the frame before it, so no frame
//! repeats the last one's camera -- the frames a user sees while turning a scene, which no
//! history of a still camera helps. The frame compared with the reference and the frame
//! counted are at the scene's own camera, each after a frame one step before it.

use glam::DQuat;

use ellipsoid_splat::Camera;

/// How the camera of the timed frames moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Every frame has the scene's camera.
    Still,
    /// Each frame turns the eye about the target, around the camera's up axis.
    Orbit {
        /// Degrees per frame.
        degrees: f64,
    },
}

impl Motion {
    /// The camera of frame `step` of a method's run (0: the scene's own).
    pub fn camera(self, camera: &Camera, step: i64) -> Camera {
        match self {
            Motion::Still => *camera,
            Motion::Orbit { degrees } => {
                let turn = DQuat::from_axis_angle(
                    camera.up.normalize(),
                    (degrees * step as f64).to_radians(),
                );
                Camera {
                    eye: camera.target + turn * (camera.eye - camera.target),
                    ..*camera
                }
            }
        }
    }

    /// Whether each frame needs the same method's frame one step before it.
    pub fn moves(self) -> bool {
        matches!(self, Motion::Orbit { .. })
    }

    /// The `camera` column of `results.csv`: `still` or `orbit DEG deg/frame`.
    pub fn label(self) -> String {
        match self {
            Motion::Still => "still".into(),
            Motion::Orbit { degrees } => format!("orbit {degrees} deg/frame"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn an_orbit_turns_the_eye_about_the_target_and_keeps_its_distance() {
        let camera = Camera::look_at(
            DVec3::new(0.0, 0.0, 10.0),
            DVec3::new(0.0, 0.0, 1.0),
            45.0,
            1.0,
            64,
            48,
        )
        .unwrap();
        let orbit = Motion::Orbit { degrees: 90.0 };
        assert_eq!(orbit.camera(&camera, 0).eye, camera.eye);
        let turned = orbit.camera(&camera, 1);
        assert!(
            (turned.eye - DVec3::new(9.0, 0.0, 1.0)).length() < 1e-12,
            "{turned:?}"
        );
        assert_eq!((turned.target, turned.up), (camera.target, camera.up));
        let back = orbit.camera(&camera, -1);
        assert!(
            (back.eye - DVec3::new(-9.0, 0.0, 1.0)).length() < 1e-12,
            "{back:?}"
        );
        assert_eq!(Motion::Still.camera(&camera, 5), camera);
    }
}
