//! `render --frames`: the frames of a trajectory file drawn to numbered images (and a movie),
//! the camera framed by the first frame drawn unless given. Loading the next frame, drawing
//! this one and writing the last one's files overlap: three threads joined by one-frame
//! queues, so a frame costs about its slowest stage rather than the sum of the three.

use std::path::PathBuf;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::time::{Duration, Instant};

use ellipsoid_splat::{supersample, Frame};
use ellipsoid_splat_loaders::{Loaded, Progress, Trajectory};

use crate::cli::{self, RenderArgs, SceneSpec};
use crate::error::{Error, Result};
use crate::frame_range::FrameRange;
use crate::movie::Movie;
use crate::output::{self, numbered, Image};
use crate::plan;
use crate::render_device;

/// What a finished sequence took.
#[derive(Clone, Debug)]
pub struct SequenceReport {
    /// Frames drawn.
    pub frames: usize,
    /// From the start of the command to the last file written.
    pub total: Duration,
    /// The median of the frames' times on the device (submit to fence).
    pub median_frame: Duration,
}

/// Draws `range` of the trajectory `args.scene` names as `args` ask, writing each frame's
/// images to numbered files and, with `--movie`, the colour to the movie.
pub fn render_sequence(args: &RenderArgs, range: FrameRange) -> Result<SequenceReport> {
    let start = Instant::now();
    let checked = args.check()?;
    let SceneSpec::File(path) = &checked.scene else {
        return Err(Error::invalid(
            "--frames",
            format!(
                "'{}' is generated, with one frame; --frames reads a trajectory file",
                args.scene
            ),
        ));
    };
    let trajectory = Trajectory::open(path, &args.load.options())?;
    let indices = range
        .indices(trajectory.len())
        .map_err(|reason| Error::invalid("--frames", format!("{}: {reason}", path.display())))?;
    let colored = |loaded: Result<Loaded>| {
        loaded.map(|mut loaded| {
            args.load.color_mode().apply(&mut loaded.scene.ellipsoids);
            loaded
        })
    };
    let first = colored(trajectory.frame(indices[0]).map_err(Error::from))?;
    for note in &first.notes {
        eprintln!("{}: {note}", args.scene);
    }
    let camera = cli::camera_for(args, &first.scene)?;
    if let Some(warning) = cli::nothing_in_view(args, &camera, &first.scene) {
        eprintln!("warning: frame {}: {warning}", indices[0] + 1);
    }
    // Started before the device is looked for, so a missing ffmpeg is said at once.
    let mut movie = match &args.movie {
        Some(file) => Some(Movie::start(file, args.width, args.height, args.fps)?),
        None => None,
    };
    let mut renderer = render_device::offscreen_renderer(args)?;
    let k = args.supersample;
    let drawn = supersample::supersampled_camera(&camera, k)?;
    let extent = ash::vk::Extent2D {
        width: args.width * k,
        height: args.height * k,
    };
    let outputs = checked.outputs;
    renderer.upload(&first.scene)?;
    // The plan settles on the first frame's camera; the camera stays, so later frames keep
    // what it learnt (a measuring plan goes on timing them).
    plan::warm_up(&mut renderer, &drawn, extent, outputs, args.plan)?;

    let images: Vec<(Image, PathBuf)> = Image::all_in(outputs)
        .filter(|&image| !(image == Image::Color && movie.is_some()))
        .filter_map(|image| Some((image, args.file(image)?.to_path_buf())))
        .collect();
    let progress = Progress::new(indices.len() as u64, "frames");
    let mut device_times = Vec::with_capacity(indices.len());
    std::thread::scope(|scope| -> Result<()> {
        let (loaded_tx, loaded_rx) = sync_channel::<(usize, Result<Loaded>)>(1);
        let rest = &indices[1..];
        let trajectory = &trajectory;
        scope.spawn(move || {
            for &index in rest {
                if loaded_tx
                    .send((index, colored(trajectory.frame(index).map_err(Error::from))))
                    .is_err()
                {
                    break; // the drawing stopped
                }
            }
        });
        let (frame_tx, frame_rx) = sync_channel::<(usize, Frame)>(1);
        let writer = scope.spawn({
            let images = &images;
            let progress = &progress;
            let movie = &mut movie;
            move || write_frames(frame_rx, images, movie, progress)
        });
        let drawing = draw_frames(
            &mut renderer,
            (indices[0], first),
            loaded_rx,
            &frame_tx,
            |renderer| {
                let (frame, timing) =
                    renderer.render_views(extent.width, extent.height, &[drawn], outputs)?;
                device_times.push(timing.gpu_wall);
                Ok(if k > 1 {
                    supersample::box_filter(&frame, k)?
                } else {
                    frame
                })
            },
        );
        drop(frame_tx);
        let written = writer
            .join()
            .unwrap_or_else(|_| Err(Error::invalid("--frames", "the file writer stopped")));
        // The drawing's error first: a writer that stopped early may be its consequence.
        drawing.and(written)
    })?;
    renderer.context().check_validation()?;
    progress.finish();
    let frames = match movie {
        Some(movie) => movie.finish()?,
        None => indices.len(),
    };
    device_times.sort();
    Ok(SequenceReport {
        frames,
        total: start.elapsed(),
        median_frame: device_times
            .get(device_times.len() / 2)
            .copied()
            .unwrap_or_default(),
    })
}

/// Uploads and draws each frame as it arrives (the first already loaded), handing it to the
/// writer; stops at the first error, or where the writer stopped taking frames.
fn draw_frames(
    renderer: &mut ellipsoid_splat::OffscreenRenderer,
    first: (usize, Loaded),
    loaded: Receiver<(usize, Result<Loaded>)>,
    frames: &SyncSender<(usize, Frame)>,
    mut draw: impl FnMut(&mut ellipsoid_splat::OffscreenRenderer) -> Result<Frame>,
) -> Result<()> {
    let (index, scene) = first;
    let mut next = Some((index, Ok(scene)));
    while let Some((index, scene)) = next.take().or_else(|| loaded.recv().ok()) {
        let scene = scene?.scene;
        renderer.upload(&scene)?;
        if frames.send((index, draw(renderer)?)).is_err() {
            return Ok(()); // the writer failed: its error is the one to report
        }
    }
    Ok(())
}

/// Writes each drawn frame's images to their numbered files and its colour to the movie.
fn write_frames(
    frames: Receiver<(usize, Frame)>,
    images: &[(Image, PathBuf)],
    movie: &mut Option<Movie>,
    progress: &Progress,
) -> Result<()> {
    for (index, frame) in frames {
        let number = index + 1;
        for (image, path) in images {
            output::write_image(&frame, *image, &numbered(image.flag(), path, number)?)?;
        }
        if let Some(movie) = movie.as_mut() {
            movie.push(&frame)?;
        }
        progress.inc(&format!("frame {number}"));
    }
    Ok(())
}
