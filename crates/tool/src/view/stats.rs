//! What the viewer measures: GPU time of moving and still frames, frames skipped while
//! minimised, the path the frame plan took and why, and the host's resident memory.

use crate::view::frame_times::FrameTimes;

/// GPU times of drawn frames, split by whether the camera moved.
#[derive(Default)]
pub struct FrameStats {
    /// Frames whose camera moved (drawing the sample, if there is one).
    pub moving: FrameTimes,
    /// Frames whose camera stood still (the full scene).
    pub still: FrameTimes,
    /// Turns of the loop that drew nothing because the window was minimised or zero-sized.
    pub skipped: u64,
    /// Frames presented.
    pub presented: u64,
    /// The last presented frame's path and why the plan took it (`plan::describe`).
    pub plan: Option<String>,
    /// Presented frames per path taken (`plan::path_name`), in the order first taken.
    pub paths: Vec<(&'static str, u64)>,
    /// Presented frames whose plan measures and had not settled (its class's candidates
    /// still being timed, with the best so far between trials).
    pub unsettled: u64,
}

impl FrameStats {
    /// Counts one presented frame's plan.
    pub fn count_plan(&mut self, path: &'static str, unsettled: bool) {
        match self.paths.iter_mut().find(|(name, _)| *name == path) {
            Some((_, frames)) => *frames += 1,
            None => self.paths.push((path, 1)),
        }
        self.unsettled += u64::from(unsettled);
    }

    /// The line on the paths taken: `paths (frames): splat 97, draw 12; 14 before the plan
    /// settled`.
    pub fn paths_summary(&self) -> Option<String> {
        if self.paths.is_empty() {
            return None;
        }
        let taken: Vec<String> = self
            .paths
            .iter()
            .map(|(name, frames)| format!("{name} {frames}"))
            .collect();
        Some(format!(
            "paths (frames): {}; {} before the plan settled",
            taken.join(", "),
            self.unsettled
        ))
    }

    /// The line printed when the viewer closes.
    pub fn summary(&self) -> String {
        let median = |times: &FrameTimes| match times.median() {
            Some(median) => format!("{:.1} ms", median.as_secs_f64() * 1e3),
            None => "-".to_string(),
        };
        let total = (self.moving.total() + self.still.total()).as_secs_f64() * 1e3;
        format!(
            "frames: {} presented, {} skipped while minimised; GPU time per frame (median): \
             moving {} ({} frames), still {} ({} frames); all frames {:.1} ms",
            self.presented,
            self.skipped,
            median(&self.moving),
            self.moving.frames(),
            median(&self.still),
            self.still.frames(),
            total
        )
    }
}

/// The process's resident set size in bytes (`VmRSS` of Linux's `/proc/self/status`; 0
/// where there is none).
pub fn resident_bytes() -> u64 {
    let Ok(text) = std::fs::read_to_string("/proc/self/status") else {
        return 0;
    };
    text.lines()
        .find_map(|line| {
            let kib = line.strip_prefix("VmRSS:")?.trim().strip_suffix("kB")?;
            kib.trim().parse::<u64>().ok()
        })
        .map_or(0, |kib| kib * 1024)
}
