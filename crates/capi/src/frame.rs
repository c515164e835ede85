//! A frame read back into the host's own arrays: the offscreen renderer's output.

use ellipsoid_splat::{Frame, Outputs};

use crate::status::Failure;

/// The `id` of a pixel where no glyph is hit.
pub const ES_NO_GLYPH: u32 = u32::MAX;

/// Where a frame's outputs go: arrays the host allocated, each of `width * height` pixels
/// (the camera's), row by row from the top; a null pointer skips that output.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsFrameBuffers {
    /// `sizeof(EsFrameBuffers)`.
    pub struct_size: u32,
    /// RGBA8 colour, sRGB-encoded: 4 bytes a pixel.
    pub color: *mut u8,
    /// View depth (the distance along the view axis): 1 float a pixel, `+inf` where no glyph
    /// is hit.
    pub depth: *mut f32,
    /// World-space unit normal: 3 floats a pixel, zero where no glyph is hit.
    pub normal: *mut f32,
    /// The index of the glyph shown: 1 `uint32_t` a pixel, `ES_NO_GLYPH` where none is.
    pub id: *mut u32,
}

/// The size of the first version of [`EsFrameBuffers`] (64-bit targets), frozen.
pub(crate) const FRAME_BUFFERS_V1: usize = 40;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsFrameBuffers>() == FRAME_BUFFERS_V1);

impl EsFrameBuffers {
    /// The outputs whose arrays are given.
    pub(crate) fn outputs(&self) -> Outputs {
        let mut outputs = Outputs::ALL;
        outputs.color = !self.color.is_null();
        outputs.depth = !self.depth.is_null();
        outputs.normal = !self.normal.is_null();
        outputs.id = !self.id.is_null();
        outputs
    }

    /// Copies `frame`'s outputs into the arrays given (the frame holds each of them).
    ///
    /// # Safety
    /// Each non-null array holds `frame.len()` pixels of its output, writable, and none
    /// overlaps another.
    pub(crate) unsafe fn write(&self, frame: &Frame) -> Result<(), Failure> {
        let pixels = frame.len();
        let lacks = |what: &str| Failure::invalid("frame", format!("no {what} was read back"));
        /// Copies `from` (`pixels` values when given) into `to`.
        ///
        /// # Safety
        /// A non-null `to` holds `from.len()` writable values.
        unsafe fn copy<T: Copy>(from: &[T], to: *mut T) {
            if !to.is_null() {
                // SAFETY: caller contract; `from` is the library's own vector.
                unsafe { std::ptr::copy_nonoverlapping(from.as_ptr(), to, from.len()) };
            }
        }
        let outputs = self.outputs();
        for (asked, held, what) in [
            (outputs.color, frame.color.len(), "colour"),
            (outputs.depth, frame.depth.len(), "depth"),
            (outputs.normal, frame.normal.len(), "normal"),
            (outputs.id, frame.id.len(), "id"),
        ] {
            if asked && held != pixels {
                return Err(lacks(what));
            }
        }
        // SAFETY: caller contract: each array holds `pixels` pixels of its output (4 bytes
        // of colour, 3 floats of normal); the frame's vectors hold exactly `pixels` each.
        unsafe {
            copy(frame.color.as_flattened(), self.color);
            copy(&frame.depth, self.depth);
            copy(frame.normal.as_flattened(), self.normal);
            copy(&frame.id, self.id);
        }
        Ok(())
    }
}
