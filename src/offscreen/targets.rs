//! The offscreen renderer's attachments and the host buffer they are copied into, made for
//! one image size and one choice of outputs.

use crate::allocator::MemoryUse;
use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::error::Result;
use crate::gpu::{GpuBuffer, GpuImage};
use crate::target::Target;

use super::{OffscreenRenderer, Outputs, COLOR_FORMAT, DEPTH_FORMAT};

/// The attachments of one size: colour and depth always (the draw needs them), normal and ID
/// when asked for, and a readback buffer for the outputs that are read back. Multisampled,
/// the pass draws into `multisampled` and resolves into `read`, which is read back.
pub(super) struct Targets {
    pub outputs: Outputs,
    /// Single-sample: drawn into, or resolved into; copied to the readback buffer.
    pub read: Attachments,
    /// With more than one sample per pixel: the attachments drawn into.
    pub multisampled: Option<(vk::SampleCountFlags, Attachments)>,
    pub readback: GpuBuffer,
}

/// One set of attachments, all of one sample count.
pub(super) struct Attachments {
    pub color: GpuImage,
    pub depth: GpuImage,
    /// Normal and ID.
    pub aux: Option<(GpuImage, GpuImage)>,
}

impl Attachments {
    /// The colour attachments a frame of `outputs` draws: colour, then normal and ID when
    /// asked for.
    pub fn colors(&self, outputs: Outputs) -> Vec<&GpuImage> {
        let mut colors = vec![&self.color];
        if let (true, Some((normal, id))) = (outputs.aux(), &self.aux) {
            colors.extend([normal, id]);
        }
        colors
    }

    /// Takes colour, depth, then normal and ID, in the order `Targets::new` makes them.
    fn from_made(made: Vec<GpuImage>) -> Self {
        let mut it = made.into_iter();
        let (Some(color), Some(depth)) = (it.next(), it.next()) else {
            unreachable!("colour and depth targets were made");
        };
        Self {
            color,
            depth,
            aux: it.next().zip(it.next()),
        }
    }

    /// Destroys every image.
    ///
    /// # Safety
    /// No pending work uses them.
    unsafe fn destroy(self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: caller contract.
        unsafe {
            self.color.destroy(device, allocator);
            self.depth.destroy(device, allocator);
            if let Some((normal, id)) = self.aux {
                normal.destroy(device, allocator);
                id.destroy(device, allocator);
            }
        }
    }
}

/// Bytes per pixel of each output in the readback buffer.
const NORMAL_TEXEL: u64 = 16;
const WORD_TEXEL: u64 = 4;

impl Targets {
    /// Byte offsets of colour, depth, normal and ID inside the readback buffer (`None` for an
    /// output not read back), and its size. The normal comes first: a copy's buffer offset
    /// must be a multiple of its 16-byte texel (every region starts on 256 bytes).
    pub fn layout(extent: vk::Extent2D, outputs: Outputs) -> ([Option<u64>; 4], u64) {
        let pixels = extent.width as u64 * extent.height as u64;
        let mut at: u64 = 0;
        // Each region starts on 256 bytes: the most any device asks of a storage-buffer
        // offset (`minStorageBufferOffsetAlignment`), which the fetch of sample 0 binds.
        let mut place = |wanted: bool, texel: u64| {
            wanted.then(|| {
                let offset = at.next_multiple_of(256);
                at = offset + texel * pixels;
                offset
            })
        };
        let normal = place(outputs.normal, NORMAL_TEXEL);
        let color = place(outputs.color, WORD_TEXEL);
        let depth = place(outputs.depth, WORD_TEXEL);
        let id = place(outputs.id, WORD_TEXEL);
        ([color, depth, normal, id], at)
    }

    /// The attachments for `extent`, `outputs` and `samples` per pixel.
    fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        extent: vk::Extent2D,
        outputs: Outputs,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        let attach = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let color_aspect = vk::ImageAspectFlags::COLOR;
        let mut specs = vec![
            ("colour target", COLOR_FORMAT, attach, color_aspect),
            (
                "depth target",
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                vk::ImageAspectFlags::DEPTH,
            ),
        ];
        if outputs.aux() {
            specs.push(("normal target", Target::NORMAL_FORMAT, attach, color_aspect));
            specs.push(("id target", Target::ID_FORMAT, attach, color_aspect));
        }
        // Build one at a time so a failure frees the ones already made: the single-sample
        // images, then (multisampled) the attachments drawn into, which only the pass uses.
        let mut made: Vec<GpuImage> = Vec::new();
        let free = |made: Vec<GpuImage>, allocator: &mut Allocator| {
            for image in made {
                // SAFETY: just made, never used.
                unsafe { image.destroy(device, allocator) };
            }
        };
        let single = vk::SampleCountFlags::TYPE_1;
        let mut builds: Vec<_> = specs.iter().map(|&spec| (spec, single)).collect();
        if samples != single {
            // Colour and normal are resolved from, never copied: transient. Depth and ID are
            // read at sample 0 by a compute fetch (`sample_zero.rs`): sampled.
            let drawn_into = |usage: vk::ImageUsageFlags, format| {
                let attachment = usage & !vk::ImageUsageFlags::TRANSFER_SRC;
                if format == DEPTH_FORMAT || format == Target::ID_FORMAT {
                    attachment | vk::ImageUsageFlags::SAMPLED
                } else {
                    attachment | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT
                }
            };
            let multisampled_name = |name: &str| match name {
                "colour target" => "multisampled colour target",
                "depth target" => "multisampled depth target",
                "normal target" => "multisampled normal target",
                _ => "multisampled id target",
            };
            builds.extend(specs.iter().map(|&(name, format, usage, aspect)| {
                (
                    (
                        multisampled_name(name),
                        format,
                        drawn_into(usage, format),
                        aspect,
                    ),
                    samples,
                )
            }));
        }
        for ((name, format, usage, aspect), samples) in builds {
            let made_one = GpuImage::new(
                device,
                allocator,
                name,
                (format, samples),
                extent,
                usage,
                aspect,
            );
            match made_one {
                Ok(image) => made.push(image),
                Err(e) => {
                    free(made, allocator);
                    return Err(e);
                }
            }
        }
        let multisampled = (samples != single)
            .then(|| (samples, Attachments::from_made(made.split_off(specs.len()))));
        let readback = match GpuBuffer::new(
            device,
            allocator,
            "readback",
            Self::layout(extent, outputs).1,
            // Copies write it; on multisampled frames, so does the fetch of sample 0.
            vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryUse::Readback,
        ) {
            Ok(b) => b,
            Err(e) => {
                free(made, allocator);
                if let Some((_, m)) = multisampled {
                    // SAFETY: just made, never used.
                    unsafe { m.destroy(device, allocator) };
                }
                return Err(e);
            }
        };
        Ok(Self {
            outputs,
            read: Attachments::from_made(made),
            multisampled,
            readback,
        })
    }

    /// Destroys every image and the buffer.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: caller contract.
        unsafe {
            self.read.destroy(device, allocator);
            if let Some((_, m)) = self.multisampled {
                m.destroy(device, allocator);
            }
            self.readback.destroy(device, allocator);
        }
    }
}

impl OffscreenRenderer {
    /// Makes the targets match `extent` and the sample count and hold at least `outputs`,
    /// replacing them if they do not.
    pub(super) fn ensure_targets(&mut self, extent: vk::Extent2D, outputs: Outputs) -> Result<()> {
        let samples = self.samples;
        let samples_of = |t: &Targets| {
            t.multisampled
                .as_ref()
                .map_or(vk::SampleCountFlags::TYPE_1, |m| m.0)
        };
        if self.targets.as_ref().is_some_and(|t| {
            t.read.color.extent() == extent && t.outputs.covers(outputs) && samples_of(t) == samples
        }) {
            return Ok(());
        }
        let (device, allocator) = self.context.device_and_allocator();
        if let Some(old) = self.targets.take() {
            // SAFETY: every submission is waited for before returning, so nothing uses them.
            unsafe { old.destroy(device, allocator) };
        }
        self.targets = Some(Targets::new(device, allocator, extent, outputs, samples)?);
        Ok(())
    }
}
