//! The plan that measures: per scene class, the candidate paths are timed on frames the
//! renderer draws anyway, and the fastest is kept (as FFTW's planner times its candidates and
//! keeps "wisdom"). A frame's class is its own or a known one it lies near (`classify`). A new
//! class runs its nearest learned neighbour's choice first, else the first guess
//! (`estimate.rs`); then each other candidate gets a short trial, with frames of the best so
//! far between trials (timed too), waiting on the best while the trial's times are in
//! flight. A kind's first frame in the renderer's life warms up (its pipelines are built, and
//! lavapipe bakes the values that steer branches into its shaders) and is not timed; after
//! that every frame of a kind counts. A candidate whose median is far above the best's is
//! dropped at once, so a much slower path costs a frame or two per class. Of two close kinds,
//! the one timed first, if it lost, runs once more after the other (A B A, as a benchmark
//! interleaves), so a device still warming up does not favour the kind timed later. Once no
//! candidate is left to time the class is settled.
//! Every candidate is exact, so exploring changes no pixel beyond what each path's exactness
//! allows.
//!
//! # The rules in full
//!
//! **Scene classes** (`SceneClass`, `src/renderer/learning.rs`): frames alike enough to share a
//! fastest path -- the glyph count, the sampled glyphs' mean area on screen and the layers they
//! lie in (each in octaves), the image's pixels (octaves), the samples and whether the camera is
//! still. A class met for the first time is measured; one learned is planned as learned. A
//! frame whose size and layers lie within 0.75 octaves of a known class's (the same glyph count,
//! pixels, samples and camera) is planned as that class (`PlanLearning::classify`): glyphs
//! whose mean size sits at an octave's edge would otherwise flip a moving camera between two
//! classes, each explored from the start.
//!
//! **Exploring** (`PlanLearning::choose`, `commit`, `record`): a new class first runs the
//! choice (or the fastest so far) of its nearest neighbour -- a class of the same glyph count, pixels and
//! samples within three octaves of size and layers (a still camera's neighbour one step
//! further) -- or, without one, the first guess; a kind that took over twice its fastest's time
//! in that neighbour is not timed again. Then each other candidate gets a trial, with four
//! frames of the best so far between trials (exploring is spread out). A kind's first frame in
//! the renderer's life warms up (its pipelines are built, and lavapipe bakes branch-steering
//! values into its shaders) and is not timed; every later frame of it counts, in any class. A
//! candidate whose median exceeds 1.3 times the best's is dropped as soon as its time comes in,
//! so a far slower path costs one or two frames per class; the others are timed until each has
//! three frames, or seven where its median lies within 10 % of its nearest rival's (a frame's
//! noise on a shared CPU decides three frames' medians, and frames of either of two close
//! paths cost little). The best's frames between trials are timed too (its median then
//! comes from frames around the trials'), and of two close kinds the one timed first, if it
//! lost, runs once more after the other, only that run's times counting (A B A, as a
//! benchmark interleaves): a device still warming up makes the kind timed later look faster
//! -- an H200 picked the visible-first splat, 6 % slower than the splat, in three runs of four
//! on the million 2 px glyphs before this (`tests` in `learning.rs` model drifts of up to
//! 20 %). While a trial's timed frames are in flight (their times come back when the
//! host reuses the frame slot, frames in flight later), the trial waits on the best rather than
//! draw more frames of a path that may be far slower. A kind whose time is lost (its view's
//! draw was not recorded, or its timestamps were not available when its slot came round
//! again), or whose trial runs eight frames without its timed ones, is dropped; views past the
//! timer's first four count as frames with nothing to time. A class whose every time was lost
//! settles untimed and is planned by the first guess. When
//! no candidate is left to time, the class settles on the fastest median
//! (`PlanReason::Measured`: its median and the runner-up's); until then its frames say
//! `PlanReason::Exploring`, or `Estimated` while the first guess is timed. A frame of the
//! visible-first trial that only stamps is not timed.
//! The learning holds at most 256 classes, forgetting the least recently used.

use crate::path::PathKind;

use super::plan_reason::{Measured, PlanReason};

/// Timed frames a candidate needs before its median counts as measured.
const SAMPLES: usize = 3;
/// Timed frames a candidate needs whose median lies within `CLOSE` of its nearest rival's:
/// picking the wrong one of two close paths costs little, but a frame's noise (several
/// percent on a shared CPU) decides three frames' medians, and frames of either cost little.
const CLOSE_SAMPLES: usize = 7;
/// Two medians within this ratio are close.
const CLOSE: f64 = 1.1;
/// Frames of the best so far between two trials: exploring is spread out.
const GAP: u32 = 4;
/// A candidate whose median takes this many times the best's is dropped.
const REJECT: f64 = 1.3;
/// The most recent timed frames kept per candidate.
const KEPT: usize = 8;
/// Frames a trial may run before its candidate is dropped (one that never gets its timed
/// frames must not explore forever).
const MAX_TRIAL: u32 = 8;
/// How far (in octaves) a frame's glyph size or layers may lie from a known class's and
/// still be planned as that class: a quarter octave beyond rounding, so glyphs whose size
/// sits at an octave's edge do not flip a moving camera between two classes (each explored).
const STICK: f64 = 0.75;
/// The most classes remembered; the least recently used goes first.
const MAX_CLASSES: usize = 256;
/// How far (in octaves of size and layers, one more for a camera still rather than moving)
/// a class with a fastest kind so far may lie from a new one of the same glyph count, pixels
/// and samples to lend it that kind as the first to time.
const NEIGHBOUR_REACH: i32 = 3;
/// A kind that took this many times its fastest candidate's median in the neighbouring class
/// is not timed in the new one.
const NEIGHBOUR_PRUNE: f64 = 2.0;

/// Frames alike enough to share a fastest path: the scene's glyph count, the glyphs' size
/// on screen and the layers they lie in (each in octaves), the image's pixels (octaves),
/// the samples per pixel and whether the camera holds still.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct SceneClass {
    /// `ceil(log2(glyphs + 1))`.
    pub glyphs: u8,
    /// `round(log2(mean projected area in px^2))`, clamped to an `i8`.
    pub area: i8,
    /// `round(log2(depth complexity))`, at least 0.
    pub layers: i8,
    /// `round(log2(width x height))`.
    pub pixels: u8,
    /// Samples per pixel of the target.
    pub samples: u8,
    /// The camera is the view's last pre-pass's.
    pub still: bool,
}

impl SceneClass {
    /// The class of a frame.
    pub fn new(
        glyphs: u32,
        mean_area_px: f64,
        depth_complexity: f64,
        pixels: u64,
        samples: u32,
        still: bool,
    ) -> Self {
        let octave = |x: f64| x.max(1e-30).log2().round().clamp(-128.0, 127.0) as i8;
        Self {
            glyphs: (32 - glyphs.leading_zeros()) as u8,
            area: octave(mean_area_px),
            layers: octave(depth_complexity).max(0),
            pixels: octave(pixels as f64).max(0) as u8,
            samples: samples.min(255) as u8,
            still,
        }
    }

    /// Its bytes in learned data (`wisdom.rs`).
    pub fn to_bytes(self) -> [u8; 8] {
        [
            self.glyphs,
            self.area as u8,
            self.layers as u8,
            self.pixels,
            self.samples,
            self.still as u8,
            0,
            0,
        ]
    }

    /// The class of `bytes` from [`SceneClass::to_bytes`], if they are one.
    pub fn from_bytes(bytes: [u8; 8]) -> Option<Self> {
        (bytes[5] <= 1 && bytes[6] == 0 && bytes[7] == 0).then_some(Self {
            glyphs: bytes[0],
            area: bytes[1] as i8,
            layers: bytes[2] as i8,
            pixels: bytes[3],
            samples: bytes[4],
            still: bytes[5] == 1,
        })
    }
}

/// What one frame's timestamps will be recorded against: its class, the kind chosen and
/// the kind it ran, and whether its time counts (a candidate's first frame in a row warms
/// up and does not).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FrameToken {
    pub class: SceneClass,
    pub ran: PathKind,
    pub timed: bool,
}

/// What is known of one class.
#[derive(Clone, Debug)]
struct ClassRecord {
    class: SceneClass,
    /// The candidates of its last frame.
    candidates: Vec<PathKind>,
    /// Timed frames per kind (milliseconds), the most recent last.
    times: [Vec<f64>; 3],
    /// Kinds dropped: far slower than the best, or a trial that never got a time.
    dropped: [bool; 3],
    /// The kind its first frame took: timed first.
    first: PathKind,
    /// The candidate on trial and the frames it has run (frames of the best while it waits
    /// for a time in flight do not end a trial).
    trial: Option<(PathKind, u32)>,
    /// Frames of the best so far since the last trial.
    since_trial: u32,
    /// Per kind, its timed frames whose time has not come back (frames in flight): a trial
    /// waits for them on the best so far rather than draw more frames of a path that may be
    /// far slower.
    awaiting: [u32; 3],
    /// Per kind, when its first time came (the count of times recorded in this class then);
    /// `u32::MAX` before.
    first_recorded: [u32; 3],
    /// Per kind, its times recorded since another kind's last.
    since_rival: [u8; 3],
    /// Per kind, whether its times were started again after its rival's (`unbalanced`).
    timed_again: [bool; 3],
    /// Times recorded in this class.
    recorded: u32,
    /// Every candidate was timed: the fastest, for good.
    settled: Option<PathKind>,
    /// The frame counter when this class was last used (for forgetting the oldest).
    last_used: u64,
}

impl ClassRecord {
    fn new(class: SceneClass, first: PathKind) -> Self {
        Self {
            class,
            candidates: Vec::new(),
            times: Default::default(),
            dropped: [false; 3],
            first,
            trial: None,
            since_trial: 0,
            awaiting: [0; 3],
            first_recorded: [u32::MAX; 3],
            since_rival: [0; 3],
            timed_again: [false; 3],
            recorded: 0,
            settled: None,
            last_used: 0,
        }
    }

    fn median(&self, kind: PathKind) -> Option<f64> {
        // At most `KEPT` times: sorted on the stack (this runs several times a frame).
        let kept = &self.times[kind.index()];
        if kept.is_empty() {
            return None;
        }
        let kept = &kept[kept.len().saturating_sub(KEPT)..];
        let mut times = [0.0; KEPT];
        let times = &mut times[..kept.len()];
        times.copy_from_slice(kept);
        times.sort_by(f64::total_cmp);
        Some(times[times.len() / 2])
    }

    /// Whether `kind` still needs timed frames.
    fn pending(&self, kind: PathKind) -> bool {
        !self.dropped[kind.index()]
            && (self.times[kind.index()].len() < self.needed(kind) || self.unbalanced(kind))
    }

    /// Its nearest rival (the best, or for the best the runner-up; dropped kinds aside) and
    /// that rival's median, where both were timed and lie within `CLOSE`.
    fn close_rival(&self, kind: PathKind) -> Option<PathKind> {
        let ms = self.median(kind)?;
        let (rival, rival_ms) = PathKind::ALL
            .into_iter()
            .filter(|&k| k != kind && !self.dropped[k.index()])
            .filter_map(|k| Some((k, self.median(k)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        ((ms / rival_ms).max(rival_ms / ms) <= CLOSE).then_some(rival)
    }

    /// The timed frames `kind` needs: more where its median is close to its nearest rival's.
    fn needed(&self, kind: PathKind) -> usize {
        if self.close_rival(kind).is_some() {
            CLOSE_SAMPLES
        } else {
            SAMPLES
        }
    }

    /// Whether `kind`, timed before its close rival and now slower than it, is still to be
    /// timed again after the rival's frames. On a device whose speed drifts (a GPU clock
    /// rising, caches warming) the kind timed later looks faster: an H200 picked a path 6 %
    /// slower so, three runs in four. A benchmark interleaves (A B A); here the kind timed
    /// first gets one more run, and only that run's times count.
    fn unbalanced(&self, kind: PathKind) -> bool {
        let (Some(rival), Some(ms)) = (self.close_rival(kind), self.median(kind)) else {
            return false;
        };
        !self.timed_again[kind.index()]
            && self.median(rival).is_some_and(|rival_ms| rival_ms < ms)
            && self.first_recorded[kind.index()] < self.first_recorded[rival.index()]
    }

    /// The fastest of `candidates` timed so far (dropped ones aside).
    fn best(&self, candidates: &[PathKind]) -> Option<(PathKind, f64)> {
        candidates
            .iter()
            .filter(|&&k| !self.dropped[k.index()])
            .filter_map(|&k| Some((k, self.median(k)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Drops every candidate whose median is far above the best's.
    fn drop_the_slow(&mut self, candidates: &[PathKind]) {
        let Some((best, best_ms)) = self.best(candidates) else {
            return;
        };
        for &kind in candidates {
            if kind != best && self.median(kind).is_some_and(|ms| ms > REJECT * best_ms) {
                self.dropped[kind.index()] = true;
            }
        }
    }

    /// What `best` measured against the next fastest candidate.
    fn measured(&self, best: PathKind, candidates: &[PathKind]) -> PlanReason {
        let runner_up = candidates
            .iter()
            .filter(|&&k| k != best)
            .filter_map(|&k| Some((k, self.median(k)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        PlanReason::Measured(Measured {
            ms: self.median(best).unwrap_or(f64::NAN),
            runner_up,
        })
    }
}

/// The classes learned by one renderer: its choices, and the frames' times they rest on.
#[derive(Clone, Debug, Default)]
pub(crate) struct PlanLearning {
    classes: Vec<ClassRecord>,
    /// Kinds that have run in this renderer: their pipelines exist, their frames count.
    warmed: [bool; 3],
    /// Frames committed (a clock for forgetting the least recently used class).
    clock: u64,
}

impl PlanLearning {
    fn find(&self, class: &SceneClass) -> Option<&ClassRecord> {
        self.classes.iter().find(|r| r.class == *class)
    }

    /// The class a frame is planned as: its own when known, else a known class of the same
    /// glyph count, pixels, samples and camera whose size and layers lie within `STICK`
    /// octaves of the frame's (the nearest), else its own (new).
    pub fn classify(
        &self,
        glyphs: u32,
        mean_area_px: f64,
        depth_complexity: f64,
        pixels: u64,
        samples: u32,
        still: bool,
    ) -> SceneClass {
        let own = SceneClass::new(
            glyphs,
            mean_area_px,
            depth_complexity,
            pixels,
            samples,
            still,
        );
        if self.find(&own).is_some() {
            return own;
        }
        let area = mean_area_px.max(1e-30).log2();
        let layers = depth_complexity.max(1e-30).log2().max(0.0);
        self.classes
            .iter()
            .map(|r| r.class)
            .filter(|c| {
                (c.glyphs, c.pixels, c.samples, c.still)
                    == (own.glyphs, own.pixels, own.samples, own.still)
            })
            .map(|c| {
                let off = (area - f64::from(c.area)).abs();
                (c, off.max((layers - f64::from(c.layers)).abs()))
            })
            .filter(|&(_, off)| off <= STICK)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(own, |(c, _)| c)
    }

    /// The nearest class to `class` with a fastest kind so far, of the same glyph count,
    /// pixels and samples, if one lies within `NEIGHBOUR_REACH`: what a frame there found
    /// fastest is likely so here.
    fn neighbour(&self, class: &SceneClass) -> Option<&ClassRecord> {
        self.classes
            .iter()
            .filter(|r| r.class != *class && r.best(&PathKind::ALL).is_some())
            .filter(|r| {
                let c = &r.class;
                (c.glyphs, c.pixels, c.samples) == (class.glyphs, class.pixels, class.samples)
            })
            .map(|r| {
                let c = &r.class;
                let distance = (c.area as i32 - class.area as i32).abs()
                    + (c.layers as i32 - class.layers as i32).abs()
                    + (c.still != class.still) as i32;
                (distance, r)
            })
            .filter(|&(distance, _)| distance <= NEIGHBOUR_REACH)
            .min_by_key(|&(distance, _)| distance)
            .map(|(_, r)| r)
    }

    /// The kind a new class times first, among `candidates`: its neighbour's choice (the
    /// visible-first splat of a still neighbour is the splat of a moving class), else the
    /// first guess.
    fn first_for(&self, class: &SceneClass, candidates: &[PathKind], guess: PathKind) -> PathKind {
        let lent = self
            .neighbour(class)
            .and_then(|n| n.settled.or(n.best(&PathKind::ALL).map(|(k, _)| k)))
            .map(|k| match k {
                PathKind::VisibleFirst if !candidates.contains(&k) => PathKind::Splat,
                k => k,
            });
        lent.filter(|k| candidates.contains(k)).unwrap_or(guess)
    }

    /// The kind a frame of `class` takes among `candidates` (two or more, the first guess
    /// `guess` among them), and why; changes nothing.
    pub fn choose(
        &self,
        class: &SceneClass,
        candidates: &[PathKind],
        guess: (PathKind, PlanReason),
    ) -> (PathKind, PlanReason) {
        let Some(record) = self.find(class) else {
            let first = self.first_for(class, candidates, guess.0);
            return if first == guess.0 {
                guess
            } else {
                (first, PlanReason::Exploring)
            };
        };
        if let Some(best) = record.settled.filter(|k| candidates.contains(k)) {
            if record.median(best).is_none() {
                // Settled without a time (every candidate's frames were lost): the guess.
                return guess;
            }
            return (best, record.measured(best, candidates));
        }
        // Its first kind is timed first.
        let first = record.first;
        if candidates.contains(&first)
            && record.times[first.index()].is_empty()
            && !record.dropped[first.index()]
        {
            return if first == guess.0 {
                guess
            } else {
                (first, PlanReason::Exploring)
            };
        }
        let untimed = if candidates.contains(&first) {
            first
        } else {
            guess.0
        };
        let (best, _) = record.best(candidates).unwrap_or((untimed, f64::INFINITY));
        // Candidates never timed go before those that need more frames.
        let mut pending: Vec<PathKind> = candidates
            .iter()
            .copied()
            .filter(|&k| k != best && record.pending(k))
            .collect();
        pending.sort_by_key(|&k| !record.times[k.index()].is_empty());
        let Some(&next) = pending.first() else {
            if record.pending(best) {
                // Only the best is short of frames: it gets them as it runs.
                return (best, PlanReason::Exploring);
            }
            // Every candidate timed (the record settles with the next time it takes in).
            return (best, record.measured(best, candidates));
        };
        if let Some((trial, run)) = record.trial {
            if pending.contains(&trial) && run < MAX_TRIAL {
                // A trial under way goes on, or waits on the best while the time of its last
                // frame is in flight (so a far slower path is not drawn again before its time
                // can drop it).
                let in_flight = record.awaiting[trial.index()] > 0;
                return (if in_flight { best } else { trial }, PlanReason::Exploring);
            }
        }
        // Until the class settles, the frames between trials are part of exploring too.
        if record.since_trial < GAP {
            return (best, PlanReason::Exploring);
        }
        (next, PlanReason::Exploring)
    }

    /// Notes that a frame of `class` chose `chosen` among `candidates` and ran `ran` (`None`:
    /// a frame that only stamps what it shows); returns what its time will be recorded
    /// against (untimed: the kind's first frame in this renderer); `None` for a frame with
    /// nothing to time (a stamping frame, or a settled class's).
    pub fn commit(
        &mut self,
        class: SceneClass,
        candidates: &[PathKind],
        chosen: PathKind,
        ran: Option<PathKind>,
    ) -> Option<FrameToken> {
        self.clock += 1;
        let clock = self.clock;
        let record = match self.classes.iter().position(|r| r.class == class) {
            Some(k) => &mut self.classes[k],
            None => {
                let mut record = ClassRecord::new(class, chosen);
                // What the neighbour found far slower is not timed here.
                if let Some(neighbour) = self.neighbour(&class) {
                    if let Some((_, best)) = neighbour.best(&PathKind::ALL) {
                        for kind in PathKind::ALL {
                            let slow = neighbour
                                .median(kind)
                                .is_some_and(|ms| ms > NEIGHBOUR_PRUNE * best);
                            record.dropped[kind.index()] = slow && kind != chosen;
                        }
                    }
                }
                self.make_room();
                self.classes.push(record);
                self.classes.last_mut().expect("just pushed")
            }
        };
        record.last_used = clock;
        record.candidates = candidates.to_vec();
        let best = record.best(candidates).map(|(k, _)| k);
        let timing_first = best.is_none() && chosen == record.first;
        if Some(chosen) == best || timing_first {
            record.since_trial += 1;
        } else {
            record.since_trial = 0;
            let run = match record.trial {
                Some((trial, run)) if trial == chosen => run + 1,
                _ => 1,
            };
            record.trial = Some((chosen, run));
            // A trial that ran long without its timed frames: drop the candidate.
            if run >= MAX_TRIAL && record.pending(chosen) {
                record.dropped[chosen.index()] = true;
            }
        }
        Self::settle(record, candidates);
        let ran = ran?;
        let warmed = std::mem::replace(&mut self.warmed[ran.index()], true);
        // The best's frames between trials are timed until the class settles, so its median
        // comes from frames interleaved with the trials' rather than from the first frames
        // alone: a GPU clock or cache still warming up would favour whichever kind is
        // timed later (an H200 picked a path 6 % slower so, three runs in four).
        let interleaved = best == Some(chosen) && ran == chosen;
        if record.settled == Some(chosen) || !(record.pending(chosen) || interleaved) {
            // Nothing to learn from this frame (its class settled, or its kind has its
            // frames): it writes no timestamps, which cost a driver that flushes its
            // rasterizer at each a few percent of a small frame.
            return None;
        }
        if warmed {
            record.awaiting[ran.index()] += 1;
        }
        Some(FrameToken {
            class,
            ran,
            timed: warmed,
        })
    }

    /// Records the GPU time of a frame committed with `token`.
    pub fn record(&mut self, token: FrameToken, ms: f64) {
        if !token.timed || !ms.is_finite() || ms < 0.0 {
            return;
        }
        let Some(record) = self.classes.iter_mut().find(|r| r.class == token.class) else {
            return;
        };
        let in_flight = &mut record.awaiting[token.ran.index()];
        *in_flight = in_flight.saturating_sub(1);
        record.recorded = record.recorded.saturating_add(1);
        let ran = token.ran.index();
        record.first_recorded[ran] = record.first_recorded[ran].min(record.recorded);
        if record.since_rival[ran] == 0 && record.unbalanced(token.ran) {
            // Its run after the rival's begins: the earlier times no longer count.
            record.times[ran].clear();
            record.timed_again[ran] = true;
        }
        for kind in PathKind::ALL {
            let since = &mut record.since_rival[kind.index()];
            *since = if kind.index() == ran {
                since.saturating_add(1)
            } else {
                0
            };
        }
        let times = &mut record.times[token.ran.index()];
        times.push(ms);
        if times.len() > KEPT {
            times.remove(0);
        }
        if record.settled.is_none() {
            let candidates = std::mem::take(&mut record.candidates);
            record.drop_the_slow(&candidates);
            Self::settle(record, &candidates);
            record.candidates = candidates;
        }
    }

    /// Notes that the time of a frame committed with `token` will never come (its view was
    /// not drawn, or its timestamps were not available when its slot came round again): its
    /// kind cannot be measured in this class, and is dropped if it still needed frames.
    pub fn lost(&mut self, token: FrameToken) {
        let Some(record) = self.classes.iter_mut().find(|r| r.class == token.class) else {
            return;
        };
        if token.timed {
            let in_flight = &mut record.awaiting[token.ran.index()];
            *in_flight = in_flight.saturating_sub(1);
            if record.pending(token.ran) {
                record.dropped[token.ran.index()] = true;
            }
        }
        let candidates = std::mem::take(&mut record.candidates);
        Self::settle(record, &candidates);
        record.candidates = candidates;
    }

    /// Settles `record` on the fastest candidate once none is left to time.
    fn settle(record: &mut ClassRecord, candidates: &[PathKind]) {
        if record.settled.is_none() && candidates.iter().all(|&k| !record.pending(k)) {
            // With no time at all (every candidate's frames lost) it settles untimed, and
            // `choose` plans it by the first guess.
            let untimed = candidates.first().copied().unwrap_or(record.first);
            record.settled = Some(record.best(candidates).map_or(untimed, |(k, _)| k));
        }
    }

    /// The settled classes: each class, its choice and the medians of every kind timed.
    pub fn settled(&self) -> Vec<(SceneClass, PathKind, [f64; 3])> {
        self.classes
            .iter()
            .filter_map(|r| {
                let best = r.settled?;
                let medians = PathKind::ALL.map(|k| r.median(k).unwrap_or(f64::NAN));
                Some((r.class, best, medians))
            })
            .collect()
    }

    /// Takes in a settled class from learned data, replacing what is known of it.
    pub fn insert_settled(&mut self, class: SceneClass, best: PathKind, medians: [f64; 3]) {
        self.classes.retain(|r| r.class != class);
        let mut record = ClassRecord::new(class, best);
        for kind in PathKind::ALL {
            let ms = medians[kind.index()];
            if ms.is_finite() {
                record.times[kind.index()].push(ms);
            }
        }
        record.settled = Some(best);
        record.last_used = self.clock;
        self.make_room();
        self.classes.push(record);
    }

    /// Forgets the least recently used class when the learning is full.
    fn make_room(&mut self) {
        if self.classes.len() >= MAX_CLASSES {
            let oldest = (0..self.classes.len())
                .min_by_key(|&k| self.classes[k].last_used)
                .unwrap_or(0);
            self.classes.swap_remove(oldest);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::plan_reason::Guess;

    const ALL: [PathKind; 3] = PathKind::ALL;

    fn class() -> SceneClass {
        SceneClass::new(8000, 380.0, 4.3, 1920 * 1080, 1, true)
    }

    /// Runs `frames` frames with the given true time per kind (the visible-first splat's
    /// first frame of a run only stamps); returns the kinds chosen.
    fn run(
        learning: &mut PlanLearning,
        frames: usize,
        cost: impl Fn(PathKind) -> f64,
    ) -> Vec<PathKind> {
        run_from(learning, PathKind::Draw, frames, |kind, _| cost(kind))
    }

    /// As `run`, with `first` as the first guess and a time per kind and frame number.
    fn run_from(
        learning: &mut PlanLearning,
        first: PathKind,
        frames: usize,
        cost: impl Fn(PathKind, usize) -> f64,
    ) -> Vec<PathKind> {
        let guess = (first, PlanReason::Estimated(Guess::FewGlyphs));
        let mut chosen = Vec::new();
        let mut last = None;
        for frame in 0..frames {
            let (kind, _) = learning.choose(&class(), &ALL, guess);
            // The visible-first splat stamps on the first frame of a run.
            let ran = match kind {
                PathKind::VisibleFirst if last != Some(kind) => None,
                k => Some(k),
            };
            last = Some(kind);
            if let Some(token) = learning.commit(class(), &ALL, kind, ran) {
                learning.record(token, cost(token.ran, frame));
            }
            chosen.push(kind);
        }
        chosen
    }

    #[test]
    fn it_settles_on_the_fastest_candidate_and_explores_few_frames() {
        let mut learning = PlanLearning::default();
        let cost = |k| match k {
            PathKind::Draw => 60.0,
            PathKind::Splat => 35.0,
            PathKind::VisibleFirst => 40.0,
        };
        let chosen = run(&mut learning, 100, cost);
        assert_eq!(chosen[0], PathKind::Draw, "the first guess first");
        assert!(
            chosen[60..].iter().all(|&k| k == PathKind::Splat),
            "{chosen:?}"
        );
        let settled = learning.settled();
        assert_eq!(settled.len(), 1);
        assert_eq!(settled[0].1, PathKind::Splat);
        // Frames on a slower path than the best: the guess's, and the trials'.
        let slow = chosen.iter().filter(|&&k| k != PathKind::Splat).count();
        assert!(slow <= 12, "{slow} frames off the best: {chosen:?}");
    }

    #[test]
    fn a_device_warming_up_does_not_favour_the_kind_timed_later() {
        // Each frame faster than the one before until the device is warm (a GPU's clock
        // rising; up to 20 % in all): the first guess is 6 % faster than the visible-first
        // splat at any one moment, but its first frames were timed while the device was
        // slower (as an H200 ran the 1,000,000 2 px cloud: splat 2.07 ms, visible-first
        // 2.19, draw 9.3).
        let mut failures = Vec::new();
        for drift in [0.05, 0.1, 0.2] {
            for warm_up in [4, 8, 12, 16, 24, 32, 48] {
                let mut learning = PlanLearning::default();
                run_from(&mut learning, PathKind::Splat, 100, |kind, frame| {
                    let cold = (warm_up - frame.min(warm_up)) as f64 / warm_up as f64;
                    let cost = match kind {
                        PathKind::Splat => 2.07,
                        PathKind::VisibleFirst => 2.19,
                        PathKind::Draw => 9.3,
                    };
                    cost * (1.0 + drift * cold)
                });
                let settled = learning.settled();
                if settled.len() != 1 || settled[0].1 != PathKind::Splat {
                    failures.push((drift, warm_up, settled.first().map(|s| s.1)));
                }
            }
        }
        assert!(
            failures.is_empty(),
            "(drift, frames warming up, settled on): {failures:?}"
        );
    }

    #[test]
    fn a_far_slower_candidate_is_dropped_after_one_timed_frame() {
        let mut learning = PlanLearning::default();
        let cost = |k| match k {
            PathKind::Draw => 10.0,
            PathKind::Splat => 30.0,
            PathKind::VisibleFirst => 25.0,
        };
        let chosen = run(&mut learning, 60, cost);
        let splat = chosen.iter().filter(|&&k| k == PathKind::Splat).count();
        let visible_first = chosen
            .iter()
            .filter(|&&k| k == PathKind::VisibleFirst)
            .count();
        assert_eq!(splat, 2, "a warm-up frame and one timed: {chosen:?}");
        assert_eq!(visible_first, 3, "stamping, warm-up, one timed: {chosen:?}");
        assert_eq!(learning.settled()[0].1, PathKind::Draw);
    }

    #[test]
    fn a_neighbouring_class_starts_from_what_was_learned() {
        let mut learning = PlanLearning::default();
        let cost = |k| match k {
            PathKind::Draw => 60.0,
            PathKind::Splat => 20.0,
            PathKind::VisibleFirst => 40.0,
        };
        run(&mut learning, 60, cost);
        // Another class of the same scene: every kind has run, so every frame counts.
        let other = SceneClass::new(8000, 2000.0, 4.3, 1920 * 1080, 1, true);
        let guess = (PathKind::Draw, PlanReason::Estimated(Guess::FewGlyphs));
        let mut kinds = Vec::new();
        for _ in 0..60 {
            let (kind, _) = learning.choose(&other, &ALL, guess);
            if let Some(token) = learning.commit(other, &ALL, kind, Some(kind)) {
                learning.record(token, cost(token.ran));
            }
            kinds.push(kind);
        }
        // It starts from its settled neighbour's choice, and the draw, three times slower
        // there, is not timed again.
        assert_eq!(kinds[0], PathKind::Splat, "{kinds:?}");
        assert!(!kinds.contains(&PathKind::Draw), "{kinds:?}");
        let slow = kinds.iter().filter(|&&k| k != PathKind::Splat).count();
        assert!(slow <= 3, "{slow} frames off the best: {kinds:?}");
        assert_eq!(learning.settled().len(), 2, "{learning:?}");
    }

    /// With two frames in flight a time comes back two frames late: a far slower trial still
    /// draws only its warm-up frame and one timed frame, then waits on the best.
    #[test]
    fn frames_in_flight_do_not_lengthen_a_slow_trial() {
        let (learning, kinds) = frames_in_flight(300.0, 2);
        let draws = kinds.iter().filter(|&&k| k == PathKind::Draw).count();
        assert_eq!(draws, 2, "a warm-up and a timed frame: {kinds:?}");
        assert_eq!(learning.settled()[0].1, PathKind::Splat);
    }

    /// A close runner-up is not taken for lost while its times are in flight: it gets all
    /// its timed frames.
    #[test]
    fn frames_in_flight_still_time_a_close_candidate() {
        // Two frames in flight, and twelve (a host with many, or views sharing a class).
        for depth in [2, 12] {
            let (learning, kinds) = frames_in_flight(105.0, depth);
            let draws = kinds.iter().filter(|&&k| k == PathKind::Draw).count();
            // 105 against 100 ms: close, so each gets more frames.
            assert_eq!(
                draws,
                1 + CLOSE_SAMPLES,
                "a warm-up and the timed frames: {kinds:?}"
            );
            let (_, best, medians) = learning.settled()[0];
            assert_eq!(best, PathKind::Splat);
            assert_eq!(medians[PathKind::Draw.index()], 105.0);
        }
    }

    /// 100 frames of a moving camera whose times come back `depth` frames late: the splat
    /// (100 ms, the first guess) against the draw (`draw_ms`).
    fn frames_in_flight(draw_ms: f64, depth: usize) -> (PlanLearning, Vec<PathKind>) {
        let mut learning = PlanLearning::default();
        let cost = |k| match k {
            PathKind::Draw => draw_ms,
            PathKind::Splat => 100.0,
            PathKind::VisibleFirst => 400.0,
        };
        let moving = SceneClass::new(64_000, 40.0, 8.0, 1920 * 1080, 1, false);
        let candidates = [PathKind::Draw, PathKind::Splat];
        let guess = (PathKind::Splat, PlanReason::Estimated(Guess::SmallGlyphs));
        let mut in_flight = std::collections::VecDeque::new();
        let mut kinds = Vec::new();
        for _ in 0..100 {
            let (kind, _) = learning.choose(&moving, &candidates, guess);
            in_flight.push_back(learning.commit(moving, &candidates, kind, Some(kind)));
            if in_flight.len() > depth {
                if let Some(token) = in_flight.pop_front().flatten() {
                    learning.record(token, cost(token.ran));
                }
            }
            kinds.push(kind);
        }
        (learning, kinds)
    }

    #[test]
    fn an_untimed_trial_ends() {
        let mut learning = PlanLearning::default();
        let guess = (PathKind::Draw, PlanReason::Estimated(Guess::FewGlyphs));
        let mut kinds = Vec::new();
        for _ in 0..60 {
            let (kind, _) = learning.choose(&class(), &ALL, guess);
            // Only the draw's frames ever report a time; the others' are lost (their view
            // was not drawn, or their timestamps never became available).
            if let Some(token) = learning.commit(class(), &ALL, kind, Some(kind)) {
                if kind == PathKind::Draw {
                    learning.record(token, 10.0);
                } else {
                    learning.lost(token);
                }
            }
            kinds.push(kind);
        }
        assert!(
            kinds[20..].iter().all(|&k| k == PathKind::Draw),
            "{kinds:?}"
        );
        assert_eq!(learning.settled()[0].1, PathKind::Draw);
    }

    /// A host whose timestamps never come back: every kind is dropped once its timed frame is
    /// lost, and the class is planned by the first guess from then on, without timestamps.
    #[test]
    fn a_class_whose_times_are_all_lost_keeps_the_first_guess() {
        let mut learning = PlanLearning::default();
        let guess = (PathKind::Splat, PlanReason::Estimated(Guess::SmallGlyphs));
        let mut last = None;
        for _ in 0..40 {
            let choice = learning.choose(&class(), &ALL, guess);
            if let Some(token) = learning.commit(class(), &ALL, choice.0, Some(choice.0)) {
                learning.lost(token);
            }
            last = Some(choice);
        }
        assert_eq!(last, Some(guess));
        let (kind, _) = learning.choose(&class(), &ALL, guess);
        assert!(learning.commit(class(), &ALL, kind, Some(kind)).is_none());
    }

    /// Glyphs at an octave's edge: a moving camera stays in the class it met first.
    #[test]
    fn a_frame_near_a_known_class_is_planned_as_it() {
        let mut learning = PlanLearning::default();
        let at = |l: &PlanLearning, area| l.classify(8000, area, 4.3, 1 << 21, 1, false);
        let first = at(&learning, 380.0); // log2 8.57: octave 9
        assert_eq!(first.area, 9);
        learning.commit(first, &ALL, PathKind::Draw, Some(PathKind::Draw));
        assert_eq!(at(&learning, 350.0), first, "8.45 octaves: 0.55 from 9");
        assert_eq!(
            at(&learning, 250.0).area,
            8,
            "7.97 octaves: a class of its own"
        );
        let still = learning.classify(8000, 350.0, 4.3, 1 << 21, 1, true);
        assert_eq!(
            (still.area, still.still),
            (8, true),
            "a still camera is another class"
        );
    }

    #[test]
    fn classes_round_trip_through_bytes() {
        let c = SceneClass::new(64_000, 0.7, 8.0, 1920 * 1080, 4, false);
        assert_eq!(SceneClass::from_bytes(c.to_bytes()), Some(c));
        assert_eq!(c.area, -1);
        assert_eq!(c.layers, 3);
        assert_eq!(SceneClass::from_bytes([0, 0, 0, 0, 0, 2, 0, 0]), None);
    }
}
