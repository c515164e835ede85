//! Which `render` flags `ellipsoid-splat-mpi` honours: all of them but those whose work cannot
//! be split between processes or combined exactly, each refused naming the flag and why
//! before anything is read or drawn.

use crate::cli::RenderArgs;
use crate::error::{Error, Result};

/// Refuses the flags of `args` the processes cannot honour together: a sequence of frames,
/// a movie, the whole scene saved, multisampling and a viewport.
pub fn check_distributable(args: &RenderArgs) -> Result<()> {
    let sequence = "draws a sequence of frames, which one process does \
                    (`ellipsoid-splat render --frames`); the processes draw frame 1";
    let multisampled = "a multisampled pixel blends glyphs, and blends drawn apart do not \
                        combine exactly: antialias with --supersample K";
    let refused = [
        ("--frames", args.frames.is_some(), sequence),
        ("--movie", args.movie.is_some(), sequence),
        (
            "--save-scene",
            args.save_scene.is_some(),
            "would gather the whole scene on one process: save it with `ellipsoid-splat \
             render --save-scene`",
        ),
        ("--samples", args.samples != 1, multisampled),
        (
            "--per-sample-shading",
            args.per_sample_shading,
            multisampled,
        ),
        (
            "--viewport",
            args.viewport.is_some(),
            "draws the camera's image into part of the output, and the processes combine whole \
             images: give the camera's own size with --width and --height",
        ),
    ];
    match refused.into_iter().find(|(_, given, _)| *given) {
        Some((flag, _, why)) => Err(Error::invalid(
            flag,
            format!("not under MPI (ellipsoid-splat-mpi): {why}"),
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;
    use crate::cli::{Cli, Command};

    fn render(flags: &[&str]) -> RenderArgs {
        let argv = ["ellipsoid-splat", "render"].iter().chain(flags);
        match Cli::parse_from(argv).command {
            Some(Command::Render(args)) => *args,
            _ => unreachable!("`render` parses to Render"),
        }
    }

    #[test]
    fn flags_that_cannot_be_split_are_refused_by_name() {
        for (flags, flag) in [
            (&["--frames", "all"][..], "--frames"),
            (&["--save-scene", "s.csv"], "--save-scene"),
            (&["--samples", "4"], "--samples"),
            (&["--viewport", "0,0,8,8"], "--viewport"),
        ] {
            let error = check_distributable(&render(flags)).unwrap_err().to_string();
            assert!(
                error.starts_with(&format!("invalid {flag}: not under MPI")),
                "{error}"
            );
        }
        let honoured = [
            "--supersample",
            "2",
            "--jitter",
            "0.25,0",
            "--compact",
            "--id",
            "i.png",
        ];
        check_distributable(&render(&honoured)).unwrap();
    }
}
