//! A rendered frame read back to the CPU: colour, view depth, world normal and instance ID,
//! all `width x height`, row 0 at the top, pixel-aligned.

/// Instance ID of a pixel that shows no ellipsoid.
pub const NO_INSTANCE: u32 = u32::MAX;

/// Per-pixel outputs of one render, row-major, row 0 at the top.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// sRGB-encoded RGBA8 colour.
    pub color: Vec<[u8; 4]>,
    /// View depth `dot(p - eye, f)`; `f32::INFINITY` where nothing is hit.
    pub depth: Vec<f32>,
    /// The depth attachment's own value, read with `depth`: in the camera's
    /// [`DepthConvention`](crate::DepthConvention), its clear value where nothing is hit.
    /// It is what the renderer compares (the nearer value wins, and of equal ones the lower
    /// instance index), so frames of parts of one scene drawn apart combine into the whole
    /// scene's frame exactly by the same rule; view depth, rounded from it, may tie where it
    /// does not.
    pub device_depth: Vec<f32>,
    /// World-space unit normal; zero where nothing is hit.
    pub normal: Vec<[f32; 3]>,
    /// Index of the visible ellipsoid in the scene; [`NO_INSTANCE`] where nothing is hit.
    pub id: Vec<u32>,
}

impl Frame {
    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// True for a 0x0 frame.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Linear index of pixel `(i, j)`.
    pub fn index(&self, i: u32, j: u32) -> usize {
        j as usize * self.width as usize + i as usize
    }

    /// The `width x height` rectangle at `(x, y)` of this frame, as a frame of its own (one
    /// view of a several-view frame: its camera's size at its `viewport_origin`). Outputs
    /// this frame lacks stay empty; `None` when the rectangle does not lie inside.
    pub fn crop(&self, x: u32, y: u32, width: u32, height: u32) -> Option<Frame> {
        if x as u64 + width as u64 > self.width as u64
            || y as u64 + height as u64 > self.height as u64
        {
            return None;
        }
        fn rows<T: Copy>(all: &[T], frame: &Frame, (x, y, w, h): (u32, u32, u32, u32)) -> Vec<T> {
            if all.is_empty() {
                return Vec::new();
            }
            (y..y + h)
                .flat_map(|j| {
                    let start = frame.index(x, j);
                    all[start..start + w as usize].iter().copied()
                })
                .collect()
        }
        let rect = (x, y, width, height);
        Some(Frame {
            width,
            height,
            color: rows(&self.color, self, rect),
            depth: rows(&self.depth, self, rect),
            device_depth: rows(&self.device_depth, self, rect),
            normal: rows(&self.normal, self, rect),
            id: rows(&self.id, self, rect),
        })
    }
}
