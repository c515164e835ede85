//! Multi-frame particle files (LAMMPS dumps, extended XYZ): the file is read (and gunzipped)
//! once, one scan finds each frame's byte range, and a frame is parsed only when asked for, so
//! random access to frame 900 of a long run costs one frame's parse.
//!
//! What the two particle formats share (the type palette, the column mapping, the way a frame's
//! particles become a scene sorted by id) is in the `particles` module, which both formats
//! use; this module uses them, never the reverse.

use std::path::{Path, PathBuf};

use crate::error::read_file;
use crate::gzip::gunzip_if_compressed;
use crate::load::{detect_format, load_format, Format, LoadOptions, Loaded};
pub use crate::particles::TYPE_PALETTE;
use crate::particles::{check_options, FrameRef, Span};
use crate::{Error, Result};

/// A file of one or more frames, each parsed when asked for (see the module documentation).
pub struct Trajectory {
    path: PathBuf,
    format: Format,
    options: LoadOptions,
    /// The whole file, decompressed (empty for single-frame formats).
    bytes: Vec<u8>,
    frames: Vec<Span>,
    /// A single-frame format's scene, loaded by `open`.
    single: Option<Loaded>,
}

impl std::fmt::Debug for Trajectory {
    // The file's bytes would drown everything else.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Trajectory")
            .field("path", &self.path)
            .field("format", &self.format)
            .field("frames", &self.len())
            .field("bytes", &self.bytes.len())
            .finish()
    }
}

impl Trajectory {
    /// Opens `path` in any format `load` reads; a single-frame format has one frame.
    pub fn open(path: &Path, options: &LoadOptions) -> Result<Trajectory> {
        let format = detect_format(path)?;
        match format {
            Format::LammpsDump | Format::ExtendedXyz => {
                Self::from_bytes(read_file(path)?, path, format, options)
            }
            _ => Ok(Trajectory {
                path: path.to_path_buf(),
                format,
                options: options.clone(),
                bytes: Vec::new(),
                frames: vec![Span {
                    start: 0,
                    end: 0,
                    line: 1,
                    timestep: None,
                }],
                single: Some(load_format(path, format, options)?),
            }),
        }
    }

    /// A trajectory from a file's `bytes` (plain or gzipped) in `format`, a LAMMPS dump or
    /// extended XYZ; `file` only names the source in errors. (What [`Trajectory::open`] does
    /// after reading the file; the fuzz targets call it with arbitrary bytes.)
    pub fn from_bytes(
        bytes: Vec<u8>,
        file: &Path,
        format: Format,
        options: &LoadOptions,
    ) -> Result<Trajectory> {
        check_options(options)?;
        let bytes = gunzip_if_compressed(bytes, file)?;
        let frames = match format {
            Format::LammpsDump => crate::lammps::scan(&bytes, file)?,
            Format::ExtendedXyz => crate::xyz::scan(&bytes, file)?,
            other => {
                return Err(Error::invalid(
                    "trajectory format",
                    format!("{other:?} is not a multi-frame text format"),
                ))
            }
        };
        Ok(Trajectory {
            path: file.to_path_buf(),
            format,
            options: options.clone(),
            bytes,
            frames,
            single: None,
        })
    }

    /// The number of frames.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// True when there is no frame (never for an opened file: an empty one is an error).
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Frame `index` (0-based), parsed when asked; an index past the end is a named error.
    pub fn frame(&self, index: usize) -> Result<Loaded> {
        let Some(span) = self.frames.get(index) else {
            return Err(Error::invalid(
                "frame index",
                format!(
                    "{index} (0-based) is past the end of {}: it holds {} frame(s)",
                    self.path.display(),
                    self.len()
                ),
            ));
        };
        if let Some(single) = &self.single {
            return Ok(single.clone());
        }
        let frame = FrameRef {
            file: &self.path,
            number: index + 1,
            span: *span,
        };
        let bytes = &self.bytes[span.start..span.end];
        match self.format {
            Format::LammpsDump => crate::lammps::parse_frame(bytes, frame, &self.options),
            _ => crate::xyz::parse_frame(bytes, frame, &self.options),
        }
    }

    /// The simulation timestep of frame `index`, where the file gives one (LAMMPS
    /// `ITEM: TIMESTEP`; XYZ a `Timestep=`/`time=` key if present).
    pub fn timestep(&self, index: usize) -> Option<i64> {
        self.frames.get(index).and_then(|s| s.timestep)
    }

    /// The file's format.
    pub fn format(&self) -> Format {
        self.format
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}
