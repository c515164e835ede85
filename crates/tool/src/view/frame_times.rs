//! Frame times counted in bins of 0.1 % width instead of kept one by one, so a viewer left
//! open for days holds a fixed 166 KB for them (the hour-long soak, `scripts/soak.sh`, grew by
//! 16 bytes a frame when every time was kept), and the median it reports is within 0.05 % of
//! the exact one.

use std::time::Duration;

/// Each bin's upper edge is this factor times its lower edge.
const BIN_RATIO: f64 = 1.001;
/// The shortest time told apart (shorter ones count in the first bin).
const SHORTEST_SECONDS: f64 = 1e-7;
/// Bins from 0.1 us up to about 100 s (longer times count in the last bin).
const BINS: usize = 20_725;

/// How many frames took how long, in logarithmic bins, with the exact count and sum.
#[derive(Default)]
pub struct FrameTimes {
    /// Frames per bin; allocated with the first frame.
    bins: Vec<u64>,
    frames: u64,
    total: Duration,
}

impl FrameTimes {
    /// Counts one frame's time.
    pub fn push(&mut self, time: Duration) {
        if self.bins.is_empty() {
            self.bins = vec![0; BINS];
        }
        self.bins[bin_of(time)] += 1;
        self.frames += 1;
        self.total += time;
    }

    /// Frames counted.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The sum of every frame's time.
    pub fn total(&self) -> Duration {
        self.total
    }

    /// The median (the upper one of an even count, as `sorted[len / 2]`): the geometric
    /// centre of its bin, within 0.05 % (and a nanosecond) of the exact value inside the
    /// binned range. `None`
    /// before the first frame.
    pub fn median(&self) -> Option<Duration> {
        let wanted = self.frames / 2;
        let mut below = 0;
        for (bin, &count) in self.bins.iter().enumerate() {
            if below + count > wanted {
                let centre = SHORTEST_SECONDS * BIN_RATIO.powf(bin as f64 + 0.5);
                return Some(Duration::from_secs_f64(centre));
            }
            below += count;
        }
        None
    }
}

/// The bin holding `time`.
fn bin_of(time: Duration) -> usize {
    let ratio = time.as_secs_f64() / SHORTEST_SECONDS;
    if ratio <= 1.0 {
        return 0;
    }
    // Truncation picks the bin whose lower edge is at or below the time.
    ((ratio.ln() / BIN_RATIO.ln()) as usize).min(BINS - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact median the binned one stands for: `sorted[len / 2]`.
    fn exact_median(times: &[Duration]) -> Duration {
        let mut sorted = times.to_vec();
        sorted.sort();
        sorted[sorted.len() / 2]
    }

    #[test]
    fn the_median_is_within_a_twentieth_of_a_percent_of_the_exact_one() {
        // Frame times from 20 us to 2 s, spread unevenly, odd and even counts.
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        for count in [1usize, 2, 3, 10, 101, 5_000] {
            let mut times = Vec::new();
            let mut binned = FrameTimes::default();
            for _ in 0..count {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let unit = (state >> 11) as f64 / (1u64 << 53) as f64;
                let time = Duration::from_secs_f64(2e-5 * 1e5f64.powf(unit * unit));
                times.push(time);
                binned.push(time);
            }
            let exact = exact_median(&times).as_secs_f64();
            let median = binned.median().unwrap().as_secs_f64();
            assert!(
                (median - exact).abs() <= exact * 5.0e-4 + 1e-9,
                "{count} frames: binned median {median} s, exact {exact} s"
            );
            assert_eq!(binned.frames(), count as u64);
            let total: Duration = times.iter().sum();
            assert_eq!(binned.total(), total);
        }
    }

    #[test]
    fn times_outside_the_bins_count_at_the_ends_and_nothing_has_no_median() {
        let mut binned = FrameTimes::default();
        assert_eq!(binned.median(), None);
        binned.push(Duration::ZERO);
        binned.push(Duration::from_secs(1_000));
        binned.push(Duration::from_secs(2_000));
        assert_eq!(binned.frames(), 3);
        // The median of the three is in the last bin, about 100 s.
        let median = binned.median().unwrap().as_secs_f64();
        assert!((90.0..110.0).contains(&median), "{median}");
    }
}
