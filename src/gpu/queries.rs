//! GPU timestamps and pipeline statistics around one draw.

use ash::vk;

use crate::error::{Result, VkCall};

/// A timestamp pair and (when the device supports it) a fragment-shader-invocation counter.
pub struct FrameQueries {
    timestamps: vk::QueryPool,
    statistics: Option<vk::QueryPool>,
    period_ns: f64,
}

/// What the queries measured for one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QueryResults {
    /// Milliseconds between the timestamp before and after the rendering pass.
    pub gpu_ms: f64,
    /// Fragment shader invocations inside the pass; `None` without pipeline statistics.
    pub fragments: Option<u64>,
    /// Vertex shader invocations inside the pass (what culling saves); `None` without
    /// pipeline statistics.
    pub vertices: Option<u64>,
}

impl FrameQueries {
    /// Creates the pools; `statistics` only if the device enabled `pipelineStatisticsQuery`.
    pub fn new(device: &ash::Device, statistics: bool, period_ns: f32) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2);
        // SAFETY: valid create info; owned here, destroyed in `destroy`.
        let timestamps =
            unsafe { device.create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
        let statistics = if statistics {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::PIPELINE_STATISTICS)
                .query_count(1)
                .pipeline_statistics(
                    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS
                        | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
                );
            // SAFETY: as above; the feature was enabled at device creation.
            match unsafe { device.create_query_pool(&info, None) } {
                Ok(pool) => Some(pool),
                Err(result) => {
                    // SAFETY: just created, unused.
                    unsafe { device.destroy_query_pool(timestamps, None) };
                    return Err(crate::Error::vulkan("vkCreateQueryPool", result));
                }
            }
        } else {
            None
        };
        Ok(Self {
            timestamps,
            statistics,
            period_ns: period_ns as f64,
        })
    }

    /// Resets the queries and writes the first timestamp; record outside a rendering pass.
    pub fn begin(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is recording outside a render pass; the pools are owned by `self`.
        unsafe {
            device.cmd_reset_query_pool(cmd, self.timestamps, 0, 2);
            if let Some(pool) = self.statistics {
                device.cmd_reset_query_pool(cmd, pool, 0, 1);
            }
            device.cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                self.timestamps,
                0,
            );
        }
    }

    /// Starts counting vertex and fragment invocations; record inside the pass, before the draw.
    pub fn begin_statistics(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        if let Some(pool) = self.statistics {
            // SAFETY: the query was reset earlier in this command buffer.
            unsafe { device.cmd_begin_query(cmd, pool, 0, vk::QueryControlFlags::empty()) };
        }
    }

    /// Stops counting; record inside the pass, after the draw.
    pub fn end_statistics(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        if let Some(pool) = self.statistics {
            // SAFETY: matches `begin_statistics` in the same pass.
            unsafe { device.cmd_end_query(cmd, pool, 0) };
        }
    }

    /// Writes the second timestamp; record after the pass.
    pub fn end(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: query 1 was reset in `begin`.
        unsafe {
            device.cmd_write_timestamp(
                cmd,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                self.timestamps,
                1,
            )
        };
    }

    /// Reads the results of the last submitted frame (waits for them).
    pub fn read(&self, device: &ash::Device) -> Result<QueryResults> {
        let mut stamps = [0u64; 2];
        // SAFETY: both queries were written by the completed submission.
        unsafe {
            device.get_query_pool_results(
                self.timestamps,
                0,
                &mut stamps,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .call("vkGetQueryPoolResults")?;
        // Results come in the order of the flag bits: vertices, then fragments.
        let (vertices, fragments) = match self.statistics {
            Some(pool) => {
                // One query whose result is two counters (ash takes the query count from the
                // slice length and the stride from the element size).
                let mut count = [[0u64; 2]; 1];
                // SAFETY: the query was begun and ended in the completed submission.
                unsafe {
                    device.get_query_pool_results(
                        pool,
                        0,
                        &mut count,
                        vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
                    )
                }
                .call("vkGetQueryPoolResults")?;
                (Some(count[0][0]), Some(count[0][1]))
            }
            None => (None, None),
        };
        Ok(QueryResults {
            gpu_ms: stamps[1].wrapping_sub(stamps[0]) as f64 * self.period_ns * 1e-6,
            fragments,
            vertices,
        })
    }

    /// Destroys the pools.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: owned handles (null after the first call, which Vulkan ignores); caller
        // contract.
        unsafe {
            device.destroy_query_pool(self.timestamps, None);
            if let Some(pool) = self.statistics.take() {
                device.destroy_query_pool(pool, None);
            }
        }
        self.timestamps = vk::QueryPool::null();
    }
}
