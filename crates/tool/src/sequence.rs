//! `render --frames`: the frames of a trajectory file drawn to numbered images (and a movie),
//! the camera framed by the first frame drawn unless given. Loading the next frame, drawing
//! this one and writing the last one's files overlap: three threads joined by one-frame
//! queues, so a frame costs about its slowest stage rather than the sum of the three.

use std::path::PathBuf;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::time::{Duration, Instant};

use ellipsoid_splat::Frame;
use ellipsoid_splat_loaders::{Loaded, Progress, Trajectory};

use crate::camera_setup;
use crate::cli::{RenderArgs, SceneSpec};
use crate::error::{Error, Result};
use crate::frame_range::FrameRange;
use crate::movie::Movie;
use crate::output::{self, numbered, Image};
use crate::render_device::{self, Prepared};
use crate::scene_io;

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
        eprintln!("{}: frame {}: {note}", args.scene, indices[0] + 1);
    }
    let camera = camera_setup::camera_for(args, &first.scene)?;
    if let Some(warning) = camera_setup::nothing_in_view(args, &camera, &first.scene) {
        eprintln!("warning: frame {}: {warning}", indices[0] + 1);
    }
    scene_io::save_scene(args, &first.scene, &camera)?;
    // Started before the device is looked for, so a missing ffmpeg is said at once.
    let mut movie = match &args.movie {
        Some(file) => Some(Movie::start(file, args.width, args.height, args.fps)?),
        None => None,
    };
    let outputs = checked.outputs;
    // The plan settles on the first frame's camera; the camera stays, so later frames keep
    // what it learnt (a measuring plan goes on timing them).
    let mut prepared = render_device::prepare(args, &first.scene, &camera, outputs)
        .map_err(|e| e.in_frame(indices[0] + 1))?;
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
            &mut prepared,
            indices[0],
            loaded_rx,
            &frame_tx,
            |prepared| {
                let (frame, timing) = prepared.draw(args.supersample, outputs)?;
                device_times.push(timing.gpu_wall);
                Ok(frame)
            },
            &args.scene,
        );
        drop(frame_tx);
        let written = writer
            .join()
            .unwrap_or_else(|_| Err(Error::invalid("--frames", "the file writer stopped")));
        // The drawing's error first: a writer that stopped early may be its consequence.
        drawing.and(written)
    })?;
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

/// Draws frame `first` (uploaded already: the plan warmed up on it), then uploads and draws
/// each frame as it arrives, handing each to the writer; stops at the first error (naming the
/// frame), or where the writer stopped taking frames. A frame's loader notes (records left
/// out) are printed as it is drawn.
fn draw_frames(
    prepared: &mut Prepared,
    first: usize,
    loaded: Receiver<(usize, Result<Loaded>)>,
    frames: &SyncSender<(usize, Frame)>,
    mut draw: impl FnMut(&mut Prepared) -> Result<Frame>,
    scene: &str,
) -> Result<()> {
    let mut index = first;
    loop {
        let frame = draw(prepared).map_err(|e| e.in_frame(index + 1))?;
        if frames.send((index, frame)).is_err() {
            return Ok(()); // the writer failed: its error is the one to report
        }
        let Ok((next, loaded)) = loaded.recv() else {
            return Ok(()); // every frame drawn
        };
        // The loaders' errors name the frame and its timestep already.
        let loaded = loaded?;
        for note in &loaded.notes {
            eprintln!("{scene}: frame {}: {note}", next + 1);
        }
        prepared
            .renderer
            .upload(&loaded.scene)
            .map_err(|e| Error::from(e).in_frame(next + 1))?;
        index = next;
    }
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
            output::write_image(&frame, *image, &numbered(image.flag(), path, number)?)
                .map_err(|e| e.in_frame(number))?;
        }
        if let Some(movie) = movie.as_mut() {
            movie.push(&frame).map_err(|e| e.in_frame(number))?;
        }
        progress.inc(&format!("frame {number}"));
    }
    Ok(())
}
