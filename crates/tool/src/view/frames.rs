//! Two frames in flight: per frame slot a command buffer, a fence, the semaphore the acquired
//! swapchain image signals, and two timestamps around the frame's GPU work. One more command
//! buffer and fence serve synchronous reads (picking, zoom, screenshots).

use std::time::Duration;

use ash::vk;

use crate::error::Result;

use super::VkCall;

/// Frames the CPU may record ahead of the GPU.
pub const FRAMES_IN_FLIGHT: u32 = 2;

/// One frame slot's objects.
pub struct Slot {
    /// Records the frame.
    pub cmd: vk::CommandBuffer,
    /// Signalled when the frame's work is done (created signalled: the first wait passes).
    pub fence: vk::Fence,
    /// Signalled when the acquired swapchain image may be written.
    pub acquired: vk::Semaphore,
    /// The slot's last frame wrote its timestamps (they can be read once its fence passed).
    pub timed: bool,
}

/// The command pool, the slots, the read-back command buffer and the timestamp pool.
pub struct Frames {
    pool: vk::CommandPool,
    /// The frame slots.
    pub slots: Vec<Slot>,
    /// Records synchronous reads of the outputs.
    pub read_cmd: vk::CommandBuffer,
    /// Signalled when a read is done.
    pub read_fence: vk::Fence,
    /// Two timestamps per slot (start and end of its frame); null when the queue has no
    /// timestamps.
    queries: vk::QueryPool,
    /// Nanoseconds per timestamp tick.
    period: f64,
}

impl Frames {
    /// The objects for [`FRAMES_IN_FLIGHT`] slots on `family`'s queue; `timestamp_period` is
    /// the device's, `timestamps` says the queue family writes timestamps.
    pub fn new(
        device: &ash::Device,
        family: u32,
        timestamps: bool,
        timestamp_period: f32,
    ) -> Result<Self> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid create info; destroyed in `destroy`.
        let pool =
            unsafe { device.create_command_pool(&info, None) }.call("vkCreateCommandPool")?;
        let mut this = Self {
            pool,
            slots: Vec::new(),
            read_cmd: vk::CommandBuffer::null(),
            read_fence: vk::Fence::null(),
            queries: vk::QueryPool::null(),
            period: f64::from(timestamp_period),
        };
        // SAFETY: every object is made from `device` and owned by `this`; on failure
        // `destroy` releases what exists (null handles are ignored).
        match unsafe { this.fill(device, timestamps) } {
            Ok(()) => Ok(this),
            Err(e) => {
                // SAFETY: nothing was submitted.
                unsafe { this.destroy(device) };
                Err(e)
            }
        }
    }

    /// Makes the command buffers, fences, semaphores and the query pool.
    ///
    /// # Safety
    /// `self.pool` is a live pool of `device`.
    unsafe fn fill(&mut self, device: &ash::Device, timestamps: bool) -> Result<()> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(FRAMES_IN_FLIGHT + 1);
        // SAFETY: allocated from our pool; freed with it.
        let cmds =
            unsafe { device.allocate_command_buffers(&info) }.call("vkAllocateCommandBuffers")?;
        self.read_cmd = cmds[FRAMES_IN_FLIGHT as usize];
        let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        // SAFETY: valid create info; destroyed in `destroy`.
        self.read_fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .call("vkCreateFence")?;
        for &cmd in &cmds[..FRAMES_IN_FLIGHT as usize] {
            // SAFETY: valid create info; destroyed in `destroy`.
            let fence = unsafe { device.create_fence(&signalled, None) }.call("vkCreateFence")?;
            self.slots.push(Slot {
                cmd,
                fence,
                acquired: vk::Semaphore::null(),
                timed: false,
            });
            let info = vk::SemaphoreCreateInfo::default();
            // SAFETY: valid create info; destroyed in `destroy`.
            let semaphore = unsafe { device.create_semaphore(&info, None) };
            self.slots.last_mut().expect("just pushed").acquired =
                semaphore.call("vkCreateSemaphore")?;
        }
        if timestamps {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(2 * FRAMES_IN_FLIGHT);
            // SAFETY: valid create info; destroyed in `destroy`.
            self.queries =
                unsafe { device.create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
        }
        Ok(())
    }

    /// Records the frame's start timestamp (after resetting the slot's two queries).
    ///
    /// # Safety
    /// `slot`'s command buffer is recording, outside a pass.
    pub unsafe fn start_timer(&mut self, device: &ash::Device, slot: usize) {
        if self.queries == vk::QueryPool::null() {
            return;
        }
        let cmd = self.slots[slot].cmd;
        // SAFETY: caller contract; the slot's queries are not in use (its fence passed).
        unsafe {
            device.cmd_reset_query_pool(cmd, self.queries, 2 * slot as u32, 2);
            device.cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                self.queries,
                2 * slot as u32,
            );
        }
    }

    /// Records the frame's end timestamp.
    ///
    /// # Safety
    /// As [`Frames::start_timer`], later in the same recording.
    pub unsafe fn stop_timer(&mut self, device: &ash::Device, slot: usize) {
        if self.queries == vk::QueryPool::null() {
            return;
        }
        // SAFETY: caller contract.
        unsafe {
            device.cmd_write_timestamp(
                self.slots[slot].cmd,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                self.queries,
                2 * slot as u32 + 1,
            )
        };
        self.slots[slot].timed = true;
    }

    /// The GPU time of `slot`'s last frame, once its fence has passed.
    pub fn gpu_time(&mut self, device: &ash::Device, slot: usize) -> Option<Duration> {
        if !std::mem::take(&mut self.slots[slot].timed) {
            return None;
        }
        let mut ticks = [0u64; 2];
        // SAFETY: both queries were written by a submission whose fence passed.
        unsafe {
            device.get_query_pool_results(
                self.queries,
                2 * slot as u32,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64,
            )
        }
        .ok()?;
        let nanos = ticks[1].saturating_sub(ticks[0]) as f64 * self.period;
        Some(Duration::from_nanos(nanos as u64))
    }

    /// Destroys everything.
    ///
    /// # Safety
    /// No submitted work uses these objects.
    pub unsafe fn destroy(self, device: &ash::Device) {
        // SAFETY: caller contract; null handles are ignored.
        unsafe {
            for slot in self.slots {
                device.destroy_fence(slot.fence, None);
                device.destroy_semaphore(slot.acquired, None);
            }
            device.destroy_fence(self.read_fence, None);
            device.destroy_query_pool(self.queries, None);
            device.destroy_command_pool(self.pool, None);
        }
    }
}
