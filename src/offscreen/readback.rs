//! Turning the readback buffer into a [`Frame`].

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::frame::Frame;

use super::targets::Targets;
use super::{OffscreenRenderer, Outputs};

impl OffscreenRenderer {
    /// The frame the last read-back submission copied, with `outputs` filled in (the other
    /// images are left empty).
    pub(super) fn read_frame(&self, cameras: &[Camera], outputs: Outputs) -> Result<Frame> {
        let targets = self
            .targets
            .as_ref()
            .expect("targets exist after ensure_targets");
        let bytes = targets.readback.mapped().ok_or_else(|| Error::Allocation {
            what: "readback".into(),
            reason: "not host-visible".into(),
        })?;
        let extent = targets.read.color.extent();
        let ([color, depth, normal, id], _) = Targets::layout(extent, targets.outputs);
        let pixels = extent.width as usize * extent.height as usize;
        let word = |base: u64, i: usize| {
            let at = base as usize + 4 * i;
            [bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]
        };
        let wanted = |offset: Option<u64>, asked: bool| offset.filter(|_| asked);
        // Each pixel's depth map is its view's (the views do not overlap); pixels of no view
        // hold the clear value, which every view shares.
        let width = extent.width as usize;
        let mut view_of = vec![None; pixels];
        for (k, camera) in cameras.iter().enumerate() {
            let [x, y] = camera.viewport_origin.map(|v| v as usize);
            for row in y..y + camera.height as usize {
                view_of[row * width + x..row * width + x + camera.width as usize].fill(Some(k));
            }
        }
        let maps: Vec<_> = cameras.iter().map(Camera::depth_map).collect();
        let far_value = cameras[0].depth.clear_value();
        let mut frame = Frame {
            width: extent.width,
            height: extent.height,
            ..Frame::default()
        };
        if let Some(base) = wanted(color, outputs.color) {
            frame.color = (0..pixels).map(|i| word(base, i)).collect();
        }
        if let Some(base) = wanted(depth, outputs.depth) {
            // The clear value is "nothing here": infinitely far.
            frame.depth = (0..pixels)
                .map(|i| {
                    let z = f32::from_ne_bytes(word(base, i));
                    match view_of[i] {
                        Some(k) if z != far_value => maps[k].view_depth(z as f64) as f32,
                        _ => f32::INFINITY,
                    }
                })
                .collect();
            frame.device_depth = (0..pixels)
                .map(|i| f32::from_ne_bytes(word(base, i)))
                .collect();
        }
        if let Some(base) = wanted(normal, outputs.normal) {
            frame.normal = (0..pixels)
                .map(|i| {
                    let n = |k: usize| f32::from_ne_bytes(word(base, 4 * i + k));
                    [n(0), n(1), n(2)]
                })
                .collect();
        }
        if let Some(base) = wanted(id, outputs.id) {
            frame.id = (0..pixels)
                .map(|i| u32::from_ne_bytes(word(base, i)))
                .collect();
        }
        Ok(frame)
    }
}
