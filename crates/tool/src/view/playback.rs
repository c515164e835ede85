//! Stepping through a trajectory's frames in the viewer: the keys N (next), B (back) and
//! space (play and pause; playing draws the next frame each turn of the render loop and wraps
//! round at the end). A frame uploads the whole scene again; the moving sample keeps its
//! glyph indices, so the particle count must stay the same from frame to frame (as in a LAMMPS or extended-XYZ
//! trajectory of a fixed system); a frame with another count is reported and not shown.

use ellipsoid_splat::Scene;
use ellipsoid_splat_loaders::Trajectory;

use crate::error::Result;

use super::App;

/// The trajectory the viewer shows, and where in it.
pub(super) struct Playback {
    trajectory: Trajectory,
    /// The frame shown, 0-based.
    shown: usize,
    /// Frames advance by themselves.
    pub(super) playing: bool,
}

impl Playback {
    /// Playback of `trajectory` from frame 1, or `None` when it has one frame only.
    pub(super) fn of(trajectory: Trajectory) -> Option<Self> {
        (trajectory.len() > 1).then_some(Self {
            trajectory,
            shown: 0,
            playing: false,
        })
    }

    /// The number of the frame shown, from 1 (as `render --frames` takes it).
    pub(super) fn shown_number(&self) -> usize {
        self.shown + 1
    }
}

impl App {
    /// Shows the frame `step` frames from the one shown (wrapping round at either end).
    pub(super) fn step_frame(&mut self, step: isize) -> Result<()> {
        let Some(playback) = &mut self.playback else {
            if step != 0 {
                println!("frames: the scene has one frame");
            }
            return Ok(());
        };
        let count = playback.trajectory.len() as isize;
        let index = (playback.shown as isize + step).rem_euclid(count) as usize;
        let loaded = playback.trajectory.frame(index)?;
        let glyphs = loaded.scene.ellipsoids;
        if glyphs.len() != self.scene.len() {
            println!(
                "frame {}: {} particles, but the viewer shows {}; it steps through \
                 trajectories whose particle count stays the same",
                index + 1,
                glyphs.len(),
                self.scene.len()
            );
            playback.playing = false;
            return Ok(());
        }
        playback.shown = index;
        let timestep = playback
            .trajectory
            .timestep(index)
            .map(|t| format!(", timestep {t}"))
            .unwrap_or_default();
        if !playback.playing {
            println!("frame {} of {count}{timestep}", index + 1);
        }
        // A highlighted glyph of the last frame is not carried over.
        self.picked = None;
        self.pending.clear();
        self.file_colors = glyphs.iter().map(|e| e.color).collect();
        self.origins = loaded.origins;
        // The whole scene is uploaded again, with this frame's own origin: so the frame
        // draws exactly what `render --frames` draws of it (replaced glyphs would keep the
        // first frame's origin, and float32 positions relative to it).
        let mut glyphs = glyphs;
        for glyph in &mut glyphs {
            glyph.color = self.color_mode.color(glyph);
        }
        self.scene = Scene::new(glyphs);
        self.scene_replaced = true;
        self.redraw = true;
        Ok(())
    }

    /// Starts or stops playing.
    pub(super) fn toggle_playing(&mut self) {
        match &mut self.playback {
            Some(playback) => {
                playback.playing = !playback.playing;
                let state = if playback.playing {
                    "playing"
                } else {
                    "paused"
                };
                println!("frames: {state} at frame {}", playback.shown + 1);
            }
            None => println!("frames: the scene has one frame"),
        }
    }

    /// Whether frames advance by themselves.
    pub(super) fn playing(&self) -> bool {
        self.playback.as_ref().is_some_and(|p| p.playing)
    }
}
