//! One frame of a scene split between the processes of a communicator: each draws its share
//! with the whole scene's placement, and the frames are combined at the root into exactly the
//! frame one process drawing every glyph would read back.

use glam::DVec3;
use mpi::collective::SystemOperation;
use mpi::topology::Rank;
use mpi::traits::*;

use ellipsoid_splat::{Camera, Frame, OffscreenRenderer, Outputs, Placement, Scene};

use crate::binary_swap::{self, Traffic};
use crate::error::{Error, Result};
use crate::failure::first_failed;
use crate::pixels;

/// A composited frame and what producing it took on this process.
#[derive(Clone, Debug, Default)]
pub struct Composited {
    /// The whole frame, on the root only: IDs are global glyph indices.
    pub frame: Option<Frame>,
    /// What this process sent while compositing.
    pub traffic: Traffic,
    /// Seconds this process spent agreeing on the placement with the others, drawing and
    /// reading back its share.
    pub draw_seconds: f64,
    /// Seconds of the compositing itself: from every process having drawn (the all-reduce
    /// that also checks for failures) to this process's part of the gathered image sent (or,
    /// at the root, the whole image received).
    pub composite_seconds: f64,
}

/// Draws `part` (this process's glyphs; its glyph `i` is global glyph `global_ids[i]`,
/// strictly increasing, so that of two glyphs at one depth the lower global index wins here
/// as in one process) with `camera` and combines every process's frame over `comm` at `root`.
/// Collective: every process of `comm` calls it, with the same camera, outputs, root and
/// renderer settings (a process that does not call it leaves the others waiting). Depth and
/// ID are always drawn (they decide each pixel); `outputs` adds colour and normal. The
/// exchange runs on a duplicate of `comm`, so the caller's own messages are never taken.
///
/// A process whose share fails (a bad glyph, out of memory, a device error), or whose image
/// size, depth convention or root differs from the others', makes every process return an
/// error naming the first such rank, so none waits for it. Multisampled frames are refused:
/// a multisampled pixel blends several glyphs, and blends do not combine exactly (a frame
/// drawn larger and filtered after compositing does).
pub fn render_composited<C: Communicator>(
    comm: &C,
    root: Rank,
    renderer: &mut OffscreenRenderer,
    part: &Scene,
    global_ids: &[u32],
    camera: &Camera,
    outputs: Outputs,
) -> Result<Composited> {
    let comm = &comm.duplicate();
    let started = std::time::Instant::now();
    let placement = whole_placement(comm, part);
    let drawn = agreed(comm, root, camera)
        .and_then(|()| draw(renderer, part, global_ids, camera, outputs, placement));
    let draw_seconds = started.elapsed().as_secs_f64();
    // Every process learns whether any failed before anyone waits on another.
    let failed = first_failed(comm, drawn.is_err());
    let synced = std::time::Instant::now();
    let words = match (drawn, failed) {
        (Err(error), _) => return Err(error),
        (Ok(_), Some(rank)) => return Err(Error::OtherRank { rank }),
        (Ok(words), None) => words,
    };
    let pixels = camera.width as usize * camera.height as usize;
    let (_, mine, mut traffic) = binary_swap::composite(comm, words, pixels);
    let image = binary_swap::gather(comm, root, mine, pixels, &mut traffic);
    let composite_seconds = synced.elapsed().as_secs_f64();
    Ok(Composited {
        frame: image.map(|words| pixels::decode(&words, camera.width, camera.height, outputs)),
        traffic,
        draw_seconds,
        composite_seconds,
    })
}

/// The placement of the union of every process's `part` (what [`Placement::of`] gives the
/// whole scene): each part uploaded with it draws the whole scene's bits.
pub fn whole_placement<C: Communicator>(comm: &C, part: &Scene) -> Placement {
    let (lo, hi) = part
        .bounds()
        .unwrap_or((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)));
    let largest = part
        .ellipsoids
        .iter()
        .map(|e| e.radii.max_element())
        .fold(0.0, f64::max);
    let mut low = [0.0f64; 3];
    let mut high = [0.0f64; 3];
    let mut most = 0.0f64;
    comm.all_reduce_into(&lo.to_array()[..], &mut low[..], SystemOperation::min());
    comm.all_reduce_into(&hi.to_array()[..], &mut high[..], SystemOperation::max());
    comm.all_reduce_into(&largest, &mut most, SystemOperation::max());
    let bounds = (low[0] <= high[0]).then(|| (DVec3::from(low), DVec3::from(high)));
    Placement::enclosing(bounds, most)
}

/// Checks that every process passes the same root, image size and depth convention (their
/// least and greatest values over `comm` agree), and that the root is a rank of `comm`.
fn agreed<C: Communicator>(comm: &C, root: Rank, camera: &Camera) -> Result<()> {
    let mine = [
        i64::from(root),
        i64::from(camera.width),
        i64::from(camera.height),
        i64::from(camera.depth.reversed),
    ];
    let (mut least, mut most) = ([0i64; 4], [0i64; 4]);
    comm.all_reduce_into(&mine[..], &mut least[..], SystemOperation::min());
    comm.all_reduce_into(&mine[..], &mut most[..], SystemOperation::max());
    if least != most {
        return Err(Error::Invalid(format!(
            "the processes disagree on the root, image size or depth convention (this one: \
             root {root}, {}x{}, reversed depth {})",
            camera.width, camera.height, camera.depth.reversed
        )));
    }
    if !(0..comm.size()).contains(&root) {
        return Err(Error::Invalid(format!(
            "root {root} is not a rank of a communicator of {}",
            comm.size()
        )));
    }
    Ok(())
}

/// This process's frame as compositing words.
fn draw(
    renderer: &mut OffscreenRenderer,
    part: &Scene,
    global_ids: &[u32],
    camera: &Camera,
    outputs: Outputs,
    placement: Placement,
) -> Result<Vec<u64>> {
    if renderer.samples() != ash::vk::SampleCountFlags::TYPE_1 {
        return Err(Error::NotComposited(
            "multisampled frames: a pixel blends several glyphs, and blends do not combine \
             exactly (draw one sample per pixel)"
                .into(),
        ));
    }
    if camera.viewport_origin != [0, 0] {
        return Err(Error::NotComposited(
            "a camera drawn into a viewport of a larger image: composite the camera's own image"
                .into(),
        ));
    }
    if global_ids.len() != part.len() {
        return Err(Error::Invalid(format!(
            "{} global indices for {} glyphs",
            global_ids.len(),
            part.len()
        )));
    }
    if let Some(k) = global_ids.windows(2).position(|w| w[0] >= w[1]) {
        return Err(Error::Invalid(format!(
            "global indices must increase: glyph {} has {} after {}",
            k + 1,
            global_ids[k + 1],
            global_ids[k]
        )));
    }
    if global_ids.last() == Some(&ellipsoid_splat::NO_INSTANCE) {
        return Err(Error::Invalid(format!(
            "global index {} marks the background; glyph indices stay below it",
            ellipsoid_splat::NO_INSTANCE
        )));
    }
    let reversed = camera.depth.reversed;
    // An empty share draws too: its background is the renderer's own, bit for bit.
    let mut asked = outputs;
    asked.depth = true;
    asked.id = true;
    renderer.upload_placed(part, placement)?;
    let (frame, _) = renderer.render_views(camera.width, camera.height, &[*camera], asked)?;
    pixels::encode(&frame, reversed, global_ids).map_err(Error::Invalid)
}
