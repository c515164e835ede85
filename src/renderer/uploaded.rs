//! What the renderer keeps of the uploaded scene on the CPU: the facts that choose shader
//! variants and footprints each frame.

use glam::{DVec2, DVec3};

use crate::camera::Camera;
use crate::instances::{InstanceFormat, PackedInstances};
use crate::scene::Scene;

/// How many instances the footprint and set-up choice looks at.
const SIZE_SAMPLE: usize = 4096;

/// The uploaded scene, as far as per-frame decisions need it.
#[derive(Clone, Debug, Default)]
pub(crate) struct UploadedScene {
    /// Instances on the GPU.
    pub count: u32,
    /// The point instance positions are relative to.
    pub origin: DVec3,
    /// How the instances are stored.
    pub format: InstanceFormat,
    /// The compact format's unit of semi-axes.
    pub radius_unit: f32,
    /// The most instances per chunk when the scene was uploaded (`Settings::max_chunk_instances`
    /// then): the buffers and descriptor sets are cut for it.
    pub chunk_limit: u32,
    /// A box holding every ellipsoid whole, in world coordinates.
    pub extent: Option<(DVec3, DVec3)>,
    /// Up to `SIZE_SAMPLE` instances: centre, largest semi-axis, and `pi r1 r2` of the two
    /// largest.
    pub size_sample: Vec<(DVec3, f64, f64)>,
}

impl UploadedScene {
    /// The facts of `scene`, packed as `packed` and cut into chunks of at most `chunk_limit`.
    pub fn new(scene: &Scene, packed: &PackedInstances, chunk_limit: u32) -> Self {
        let step = scene.len().div_ceil(SIZE_SAMPLE).max(1);
        let size_sample = scene
            .ellipsoids
            .iter()
            .step_by(step)
            .map(|e| {
                let mut r = e.radii.to_array();
                r.sort_by(|a, b| b.total_cmp(a));
                (e.center, r[0], std::f64::consts::PI * r[0] * r[1])
            })
            .collect();
        Self {
            count: packed.len() as u32,
            origin: packed.origin,
            format: packed.format(),
            radius_unit: packed.radius_scale,
            chunk_limit,
            extent: packed.extent,
            size_sample,
        }
    }

    /// Takes in instances replaced by `update` (the size sample stays as uploaded).
    pub fn merge_update(&mut self, packed: &PackedInstances) {
        if let (Some((lo, hi)), Some((new_lo, new_hi))) = (self.extent, packed.extent) {
            self.extent = Some((lo.min(new_lo), hi.max(new_hi)));
        }
    }

    /// Mean projected area in square pixels of the sampled glyphs on screen beyond the near
    /// plane (each `pi a1 a2` of its two largest semi-axes, scaled by the projection at its
    /// centre, only glyphs near the screen, each capped at the screen area), and their share
    /// of the sample; `None` when no sampled glyph is on screen beyond
    /// the near plane.
    pub fn projected_sample(&self, camera: &Camera) -> Option<(f64, f64)> {
        let k = camera.intrinsics();
        // Square pixels per square screen-plane unit.
        let pixels_per_area = k.fx * k.fy;
        let screen = camera.width as f64 * camera.height as f64;
        let (lo, hi) = camera.screen_window();
        let basis = camera.basis();
        let orthographic = camera.is_orthographic();
        let (mut sum, mut n) = (0.0, 0usize);
        for &(center, radius, area) in &self.size_sample {
            let depth = camera.view_depth(center);
            if depth <= camera.near {
                continue;
            }
            // Only glyphs that reach the screen (bounding sphere against the view rectangle,
            // widened by the radius), each counted for at most the whole screen.
            let offset = center - camera.eye;
            let scale = if orthographic { 1.0 } else { depth };
            let p = DVec2::new(offset.dot(basis.right), offset.dot(basis.up));
            let (lo, hi) = (lo * scale, hi * scale);
            let reach = radius * 1.5;
            if p.x < lo.x - reach || p.x > hi.x + reach || p.y < lo.y - reach || p.y > hi.y + reach
            {
                continue;
            }
            let on_screen = (area * pixels_per_area / (scale * scale)).min(screen);
            sum += on_screen;
            n += 1;
        }
        let share = n as f64 / self.size_sample.len().max(1) as f64;
        (n > 0).then(|| (sum / n as f64, share))
    }

    /// The share of the image that the box holding every ellipsoid covers for `camera` (the
    /// screen rectangle around its projected corners; 1 when a corner lies at or before the
    /// near plane).
    pub fn screen_share(&self, camera: &Camera) -> f64 {
        let Some((lo, hi)) = self.extent else {
            return 1.0;
        };
        let basis = camera.basis();
        let (window_lo, window_hi) = camera.screen_window();
        let (mut min, mut max) = (window_hi, window_lo);
        for k in 0..8 {
            let corner = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let offset = corner - camera.eye;
            let depth = offset.dot(basis.forward);
            let scale = if camera.is_orthographic() {
                1.0
            } else if depth <= camera.near {
                return 1.0;
            } else {
                depth
            };
            let screen = DVec2::new(offset.dot(basis.right), offset.dot(basis.up)) / scale;
            min = min.min(screen);
            max = max.max(screen);
        }
        let size = window_hi - window_lo;
        let side =
            |a: usize| (max[a].min(window_hi[a]) - min[a].max(window_lo[a])).max(0.0) / size[a];
        side(0) * side(1)
    }

    /// Whether the box holding every ellipsoid lies wholly beyond the near plane of `camera`
    /// (view depth is linear, so its nearest point is a corner): then no cap can show.
    pub fn beyond_near_plane(&self, camera: &Camera) -> bool {
        let Some((lo, hi)) = self.extent else {
            return false;
        };
        let corners: Vec<DVec3> = (0..8)
            .map(|k| {
                DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        // The shaders decide "reaches the near plane" in float32 from positions relative to
        // the scene origin: keep clear of the plane by many times that rounding.
        let reach = corners
            .iter()
            .map(|c| (*c - camera.eye).length())
            .fold(0.0, f64::max);
        let margin = 1e-5 * (reach + (camera.eye - self.origin).length() + camera.near);
        corners
            .iter()
            .all(|&c| camera.view_depth(c) > camera.near + margin)
    }
}
