//! `view`'s arguments: `render`'s, less the flags only `render` can honour, and the window's.

use std::path::PathBuf;

use clap::Args;

use super::render::{IntersectionArg, RenderArgs};
use crate::error::{Error, Result};

/// Arguments of `view`: `render`'s (scene, loading, camera, device) and the window's own.
#[derive(Debug, Clone, Args)]
pub struct ViewArgs {
    /// The scene, as `--scene` takes it (a file, `tensor-field[:N]`, `lattice[:N]`,
    /// `md-liquid[:N]` or `random:COUNT`).
    #[arg(value_name = "SCENE")]
    pub scene_name: Option<String>,
    /// Everything `render` takes; the depth, normal and ID image flags do not apply.
    #[command(flatten)]
    pub render: RenderArgs,
    /// Present without waiting for the display: mailbox, else immediate, where the window
    /// system offers them (default: FIFO, synchronised to the display).
    #[arg(long)]
    pub no_vsync: bool,
    /// Input events to play, one `FRAME COMMAND ARGS` a line (see `view/script.rs`).
    #[arg(long)]
    pub script: Option<PathBuf>,
    /// Close after this many turns of the render loop (drawn or skipped).
    #[arg(long)]
    pub exit_after: Option<u64>,
    /// While the camera moves, scenes with more glyphs draw a uniform sample of about this
    /// many; the first frame after it stops draws all. 0 turns sampling off.
    #[arg(long, default_value_t = crate::view::subset::DEFAULT_MOVING_GLYPHS)]
    pub moving_glyphs: usize,
}

impl ViewArgs {
    /// The `render` arguments the viewer starts from: the positional scene in `--scene`, and
    /// no flag that only `render` can honour.
    pub fn render_args(&self) -> Result<RenderArgs> {
        let mut render = self.render.clone();
        for (flag, given) in [
            ("--depth", render.depth.is_some()),
            ("--normal", render.normal.is_some()),
            ("--id", render.id.is_some()),
        ] {
            if given {
                return Err(Error::invalid(
                    flag,
                    "does not apply to `view`, which writes only screenshots (P); use `render`",
                ));
            }
        }
        if render.samples != 1 || render.per_sample_shading {
            return Err(Error::invalid(
                "--samples",
                "does not apply to `view`, which draws one sample per pixel; use `render`",
            ));
        }
        if render.supersample != 1 {
            return Err(Error::invalid(
                "--supersample",
                "does not apply to `view`, which shows the swapchain's pixels; use `render`",
            ));
        }
        for (flag, given, why) in [
            (
                "--jitter",
                render.jitter.is_some(),
                "does not apply to `view`, whose frames follow the mouse; use `render`",
            ),
            (
                "--viewport",
                render.viewport.is_some(),
                "does not apply to `view`, which draws the whole window; use `render`",
            ),
        ] {
            if given {
                return Err(Error::invalid(flag, why));
            }
        }
        if render.intersection != IntersectionArg::Stable {
            return Err(Error::invalid(
                "--intersection",
                "the textbook baseline is for `render` and `bench`; `view` draws the shipped \
                 (stable) intersection",
            ));
        }
        if let Some(name) = &self.scene_name {
            if render.scene != RenderArgs::default().scene && render.scene != *name {
                return Err(Error::invalid(
                    "--scene",
                    format!(
                        "'{}' and the scene '{name}' both name a scene; give one",
                        render.scene
                    ),
                ));
            }
            render.scene = name.clone();
        }
        Ok(render)
    }
}
