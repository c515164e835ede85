//! The offscreen renderer's one submission at a time: what the last one left decides whether
//! the command buffer may be recorded again. A call that fails before the GPU gets its work
//! (recording, resetting the fence, `vkQueueSubmit` itself: the spec has a failed submission
//! change nothing) leaves the renderer as usable as before; a wait that fails leaves work
//! that may still run, and a lost device stays lost.

use ash::vk;

use crate::error::{Error, Result, VkCall};

use super::{OffscreenRenderer, FRAME_TIMEOUT};

/// What the last submission left.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) enum Submission {
    /// Every submission completed, or failed before the GPU got it.
    #[default]
    Idle,
    /// A submission's wait failed or timed out: it may still be running, so nothing it uses
    /// may be recorded again or destroyed (until the teardown's idle wait).
    Unfinished,
    /// The device was lost; `call` reported it first.
    Lost(&'static str),
}

impl Submission {
    /// `Ok` where new work may be recorded; else the error every later call gets.
    pub fn usable(self) -> Result<()> {
        match self {
            Submission::Idle => Ok(()),
            Submission::Unfinished => Err(Error::invalid(
                "offscreen renderer",
                "an earlier frame did not finish (it timed out): create a new renderer",
            )),
            Submission::Lost(call) => Err(Error::DeviceLost { call }),
        }
    }
}

impl OffscreenRenderer {
    /// Notes a device loss `error` reports (every later call reports it too), and passes the
    /// error on.
    pub(super) fn noting_loss(&mut self, error: Error) -> Error {
        if let Error::DeviceLost { call } = error {
            if !matches!(self.submission, Submission::Lost(_)) {
                self.submission = Submission::Lost(call);
            }
        }
        error
    }

    /// Submits the recorded command buffer and waits for it.
    pub(super) fn submit_and_wait(&mut self) -> Result<()> {
        self.submission.usable()?;
        let device = self.context.device();
        let (queue, _) = self.context.queue();
        let buffers = [self.command_buffer];
        let submit = vk::SubmitInfo::default().command_buffers(&buffers);
        // SAFETY: the command buffer is fully recorded; the fence is owned by `self` and no
        // submission using it is pending (the last one was waited for, or never made).
        let submitted = unsafe {
            // Reset before submitting, not after waiting: a failure here leaves nothing
            // submitted and the renderer usable.
            device
                .reset_fences(&[self.fence])
                .call("vkResetFences")
                .and_then(|()| {
                    device
                        .queue_submit(queue, &[submit], self.fence)
                        .call("vkQueueSubmit")
                })
        };
        if let Err(e) = submitted {
            return Err(self.noting_loss(e));
        }
        self.submission = Submission::Unfinished;
        // SAFETY: the fence belongs to the submission just made.
        let waited =
            unsafe { device.wait_for_fences(&[self.fence], true, FRAME_TIMEOUT.as_nanos() as u64) };
        match waited {
            Ok(()) => {
                self.submission = Submission::Idle;
                Ok(())
            }
            Err(vk::Result::TIMEOUT) => Err(Error::vulkan(
                "vkWaitForFences (frame took longer than 300 s)",
                vk::Result::TIMEOUT,
            )),
            Err(result) => Err(self.noting_loss(Error::vulkan("vkWaitForFences", result))),
        }
    }
}
