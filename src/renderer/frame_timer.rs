//! Timing the renderer's own work in the host's command buffers, for the plan that
//! measures: a timestamp before and after each view's pre-pass (outside the pass) and before
//! and after its draw (inside it), in a query pool of the renderer's. The results are read
//! when the frame slot begins again: the host waited for that slot then, so they are there
//! and reading them never waits.
//!
//! **Timing** (`FrameTimer`, `src/renderer/frame_timer.rs`): a query pool of its own, four
//! timestamps per view and frame slot (up to `TIMED_VIEWS` = 4 views): before and after the
//! pre-pass (reset there, outside the pass), and before and after the draw (inside the host's
//! pass). `begin_frame` reads a slot's results without waiting -- the host waited for that
//! slot's fence -- and hands each view's pre-pass plus draw time to the learning, or reports
//! it lost (the view's draw was not recorded, or the results were not available). A frame
//! with nothing to teach -- its class settled, or its kind already timed enough -- writes no
//! timestamp: lavapipe flushes its rasterizer at each, which cost small frames up to 9 % while
//! every frame wrote them (measured 2026-11-26; no result file kept). A queue family without
//! timestamps (`timestampValidBits` 0) gets no pool, and `PlanMode::Measure` then plans as
//! `Estimate` (`EllipsoidRenderer::can_measure`).

use ash::vk;

use crate::error::{Result, VkCall};

use super::learning::FrameToken;

/// Views of a frame that are timed (each takes four queries per frame slot).
pub(crate) const TIMED_VIEWS: usize = 4;
/// Queries per timed view: pre-pass start and end, draw start and end.
const QUERIES: u32 = 4;

/// One view's frame whose timestamps are being written.
#[derive(Clone, Copy, Debug)]
struct Pending {
    token: FrameToken,
    /// `record` wrote the draw's timestamps too.
    drawn: bool,
}

/// The renderer's timestamp queries, per frame slot and timed view.
pub(crate) struct FrameTimer {
    pool: vk::QueryPool,
    /// Nanoseconds per timestamp tick.
    period_ns: f64,
    /// Ticks wrap at this many bits.
    valid_bits: u32,
    /// Per frame slot and view: the frame being timed there.
    pending: Vec<Option<Pending>>,
}

impl FrameTimer {
    /// A pool for `slots` frame slots, or none where the queue family has no timestamps
    /// (`valid_bits` 0): then nothing is timed.
    pub fn new(device: &ash::Device, slots: u32, period_ns: f32, valid_bits: u32) -> Result<Self> {
        let count = slots as usize * TIMED_VIEWS;
        let mut timer = Self {
            pool: vk::QueryPool::null(),
            period_ns: period_ns as f64,
            valid_bits,
            pending: vec![None; count],
        };
        if valid_bits == 0 || period_ns <= 0.0 {
            return Ok(timer);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(count as u32 * QUERIES);
        // SAFETY: valid create info; owned here, destroyed in `destroy`.
        timer.pool = unsafe { device.create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
        Ok(timer)
    }

    /// Whether frames can be timed.
    pub fn available(&self) -> bool {
        self.pool != vk::QueryPool::null()
    }

    /// Whether frames of `view` can be timed (a pool, and one of the first `TIMED_VIEWS`).
    pub fn times_view(&self, view: usize) -> bool {
        self.available() && view < TIMED_VIEWS
    }

    fn index(slot: u32, view: usize) -> Option<usize> {
        (view < TIMED_VIEWS).then_some(slot as usize * TIMED_VIEWS + view)
    }

    /// Reads the times of the frames slot `slot` recorded last (the host waited for them)
    /// and forgets them: each token with its GPU time in milliseconds, the pre-pass's and
    /// the draw's added, or `None` where it will never have one (the view's draw was not
    /// recorded, or its timestamps were not available).
    pub fn begin_slot(
        &mut self,
        device: &ash::Device,
        slot: u32,
    ) -> Vec<(FrameToken, Option<f64>)> {
        let mut times = Vec::new();
        for view in 0..TIMED_VIEWS {
            let Some(at) = Self::index(slot, view) else {
                continue;
            };
            let Some(pending) = self.pending.get_mut(at).and_then(Option::take) else {
                continue;
            };
            if !pending.drawn {
                times.push((pending.token, None));
                continue;
            }
            let mut stamps = [0u64; QUERIES as usize];
            // SAFETY: the four queries were reset and written by work the host waited for;
            // without WAIT the call returns NOT_READY rather than blocking if they were not.
            let read = unsafe {
                device.get_query_pool_results(
                    self.pool,
                    at as u32 * QUERIES,
                    &mut stamps,
                    vk::QueryResultFlags::TYPE_64,
                )
            };
            if read.is_err() {
                times.push((pending.token, None));
                continue;
            }
            let mask = if self.valid_bits >= 64 {
                u64::MAX
            } else {
                (1u64 << self.valid_bits) - 1
            };
            let ticks = |a: u64, b: u64| (b.wrapping_sub(a) & mask) as f64;
            let ms =
                (ticks(stamps[0], stamps[1]) + ticks(stamps[2], stamps[3])) * self.period_ns * 1e-6;
            times.push((pending.token, Some(ms)));
        }
        times
    }

    /// Resets the view's queries and writes the pre-pass's first timestamp; record outside
    /// a pass, before the pre-pass. A view beyond the timed ones, or no pool, records nothing.
    ///
    /// # Safety
    /// `cmd` is recording outside a pass, for the slot `slot`.
    pub unsafe fn prepass_start(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        slot: u32,
        view: usize,
        token: Option<FrameToken>,
    ) {
        let (Some(at), Some(token), true) = (Self::index(slot, view), token, self.available())
        else {
            if let Some(at) = Self::index(slot, view) {
                self.pending[at] = None;
            }
            return;
        };
        self.pending[at] = Some(Pending {
            token,
            drawn: false,
        });
        let first = at as u32 * QUERIES;
        // SAFETY: caller contract; the queries belong to this slot and view.
        unsafe {
            device.cmd_reset_query_pool(cmd, self.pool, first, QUERIES);
            device.cmd_write_timestamp(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, self.pool, first);
        }
    }

    /// Writes the pre-pass's last timestamp.
    ///
    /// # Safety
    /// As [`FrameTimer::prepass_start`], after it in the same command buffer.
    pub unsafe fn prepass_end(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        slot: u32,
        view: usize,
    ) {
        self.write(
            device,
            cmd,
            slot,
            view,
            1,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
        );
    }

    /// Writes the draw's first timestamp (inside the host's pass).
    ///
    /// # Safety
    /// `cmd` records the view's draw, submitted after the command buffer of its pre-pass.
    pub unsafe fn draw_start(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        slot: u32,
        view: usize,
    ) {
        self.write(
            device,
            cmd,
            slot,
            view,
            2,
            vk::PipelineStageFlags::TOP_OF_PIPE,
        );
    }

    /// Writes the draw's last timestamp; the view's frame is then complete.
    ///
    /// # Safety
    /// As [`FrameTimer::draw_start`], after it.
    pub unsafe fn draw_end(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        slot: u32,
        view: usize,
    ) {
        self.write(
            device,
            cmd,
            slot,
            view,
            3,
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
        );
        if let Some(Some(pending)) = Self::index(slot, view).map(|at| &mut self.pending[at]) {
            pending.drawn = true;
        }
    }

    fn write(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        slot: u32,
        view: usize,
        query: u32,
        stage: vk::PipelineStageFlags,
    ) {
        let Some(at) = Self::index(slot, view) else {
            return;
        };
        if self.pending[at].is_none_or(|p| p.drawn) {
            return; // not reset this frame, or already complete
        }
        // SAFETY: the query was reset by this frame's `prepass_start` for the view, recorded
        // before (the callers' contracts); the pool is owned here.
        unsafe { device.cmd_write_timestamp(cmd, stage, self.pool, at as u32 * QUERIES + query) };
    }

    /// Destroys the pool.
    ///
    /// # Safety
    /// No pending work uses it.
    pub unsafe fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: owned (or null, ignored); caller contract.
        unsafe { device.destroy_query_pool(self.pool, None) };
        self.pool = vk::QueryPool::null();
    }
}
