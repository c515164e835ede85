//! Multi-frame particle files (LAMMPS dumps, extended XYZ): the file is read (and gunzipped)
//! once, one scan finds each frame's byte range, and a frame is parsed only when asked for, so
//! random access to frame 900 of a long run costs one frame's parse.
//!
//! Also what the two particle formats share: the type palette ([`TYPE_PALETTE`]), the column
//! mapping of [`LoadOptions::columns`], a whitespace splitter over bytes, the label every
//! error carries (`frame 2 (timestep 1000)`) and the way a frame's particles become a scene
//! sorted by id.

use std::path::{Path, PathBuf};

use ellipsoid_splat::{Ellipsoid, Scene};
use glam::{DQuat, DVec3};

use crate::load::{detect_format, io_error, parse_error, read_file, Format, LoadOptions, Loaded};
use crate::load::{load_format, Origins};
use crate::{Error, Result};

/// The colours of particle types 1, 2, 3, ... (type `t` takes entry `(t - 1) mod 10`) when
/// [`LoadOptions::type_colors`] is empty: blue, orange, green, red, purple, brown, pink, grey,
/// olive, cyan. Every component is a multiple of 1/16, exact in binary and in short decimal, so
/// an Ellipsoid CSV written with these colours reads back to the same bits.
pub const TYPE_PALETTE: [[f32; 3]; 10] = [
    [0.125, 0.4375, 0.6875],
    [1.0, 0.5, 0.0625],
    [0.1875, 0.625, 0.1875],
    [0.8125, 0.1875, 0.1875],
    [0.5625, 0.375, 0.75],
    [0.5625, 0.3125, 0.25],
    [0.875, 0.4375, 0.75],
    [0.5, 0.5, 0.5],
    [0.75, 0.75, 0.125],
    [0.0625, 0.75, 0.8125],
];

/// Where one frame lies in the (decompressed) file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Span {
    /// Byte range of the frame.
    pub start: usize,
    pub end: usize,
    /// 1-based line of the frame's first byte.
    pub line: usize,
    /// The simulation timestep, where the file gives one.
    pub timestep: Option<i64>,
}

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

    /// Frame 1, with a note giving the number of frames when there are several: what
    /// [`load`](crate::load()) returns.
    pub(crate) fn first(&self) -> Result<Loaded> {
        let mut loaded = self.frame(0)?;
        if self.len() > 1 {
            loaded.notes.insert(
                0,
                format!(
                    "frame 1 of {} (the file holds {} frames; open it as a trajectory for the others)",
                    self.len(),
                    self.len()
                ),
            );
        }
        Ok(loaded)
    }
}

/// Loads frame 1 of a LAMMPS dump or extended XYZ file (see [`Trajectory::first`]).
pub(crate) fn load_first(path: &Path, format: Format, options: &LoadOptions) -> Result<Loaded> {
    Trajectory::from_bytes(read_file(path)?, path, format, options)?.first()
}

/// The options only the particle formats use, checked before any parsing.
fn check_options(options: &LoadOptions) -> Result<()> {
    for (i, c) in options.type_colors.iter().enumerate() {
        if c.iter().any(|v| !(0.0..=1.0).contains(v)) {
            return Err(Error::invalid(
                "type colour",
                format!(
                    "entry {} (type {}) is {c:?}: components must be in [0, 1]",
                    i,
                    i + 1
                ),
            ));
        }
    }
    for (i, (ours, theirs)) in options.columns.iter().enumerate() {
        if options.columns[..i].iter().any(|(o, _)| o == ours) {
            return Err(Error::invalid(
                "column mapping",
                format!("\"{ours}\" is mapped twice"),
            ));
        }
        if theirs.is_empty() || theirs.contains(char::is_whitespace) {
            return Err(Error::invalid(
                "column mapping",
                format!("\"{ours}\" -> \"{theirs}\": a file column name is one word"),
            ));
        }
    }
    Ok(())
}

/// The decompressed content of gzip `bytes` (several members are read back to back), or the
/// bytes themselves when they are not gzip.
fn gunzip_if_compressed(bytes: Vec<u8>, file: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Ok(bytes);
    }
    let mut out = Vec::with_capacity(bytes.len().saturating_mul(4));
    flate2::read::MultiGzDecoder::new(bytes.as_slice())
        .read_to_end(&mut out)
        .map_err(|e| {
            let reason = if e.kind() == std::io::ErrorKind::UnexpectedEof {
                format!(
                    "truncated gzip stream (after {} decompressed bytes)",
                    out.len()
                )
            } else {
                format!("corrupt gzip data: {e}")
            };
            parse_error(file, 0, "gzip", reason)
        })?;
    Ok(out)
}

/// The first decompressed bytes of a gzip file (up to `limit`; fewer if it is short or
/// corrupt): enough for [`detect_format`] to look inside.
pub(crate) fn gzip_head(path: &Path, limit: u64) -> Result<Vec<u8>> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(io_error(path))?;
    let mut out = Vec::new();
    // A corrupt stream leaves what was inflated before it: the loader names the damage.
    let _ = flate2::read::MultiGzDecoder::new(file)
        .take(limit)
        .read_to_end(&mut out);
    Ok(out)
}

/// The frame being parsed: the file, its 1-based number and where it lies; every error names
/// all of them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrameRef<'a> {
    pub file: &'a Path,
    pub number: usize,
    pub span: Span,
}

impl FrameRef<'_> {
    /// `frame 2 (timestep 1000)`.
    pub fn label(&self) -> String {
        match self.span.timestep {
            Some(t) => format!("frame {} (timestep {t})", self.number),
            None => format!("frame {}", self.number),
        }
    }

    /// An [`Error::Parse`] at `line` (1-based in the file), the column text starting with the
    /// frame: `scene.lammpstrj:42:frame 2 (timestep 1000), shapex (field 5): reason`.
    pub fn error(&self, line: usize, column: &str, reason: impl Into<String>) -> Error {
        parse_error(
            self.file,
            line,
            format!("{}, {column}", self.label()),
            reason,
        )
    }
}

/// The lines of a byte range with their 1-based numbers in the file; `\r\n` endings are cut.
pub(crate) struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// The number of the next line.
    pub next_line: usize,
}

impl<'a> Lines<'a> {
    /// The lines of `bytes`, whose first line is line `first_line` of the file.
    pub fn new(bytes: &'a [u8], first_line: usize) -> Self {
        Self {
            bytes,
            pos: 0,
            next_line: first_line,
        }
    }

    /// Bytes not yet read.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The byte offset of the next line in the range.
    pub fn offset(&self) -> usize {
        self.pos
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let (line, advance) = match rest.iter().position(|&b| b == b'\n') {
            Some(n) => (&rest[..n], n + 1),
            None => (rest, rest.len()),
        };
        self.pos += advance;
        let number = self.next_line;
        self.next_line += 1;
        Some((number, line.strip_suffix(b"\r").unwrap_or(line)))
    }
}

/// The whitespace-separated fields of a line (spaces and tabs), without allocating.
pub(crate) fn fields(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|f| !f.is_empty())
}

/// `text` shown in an error: lossy UTF-8, cut to 40 characters.
pub(crate) fn shown(text: &[u8]) -> String {
    let s = String::from_utf8_lossy(text);
    if s.chars().count() > 40 {
        format!("{}...", s.chars().take(40).collect::<String>())
    } else {
        s.into_owned()
    }
}

/// A finite number, or why not.
pub(crate) fn real(text: &[u8]) -> std::result::Result<f64, String> {
    let value: f64 = std::str::from_utf8(text)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| format!("not a number: \"{}\"", shown(text)))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("non-finite number: \"{}\"", shown(text)))
    }
}

/// An integer, or why not.
pub(crate) fn integer(text: &[u8]) -> std::result::Result<i64, String> {
    std::str::from_utf8(text)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| format!("not an integer: \"{}\"", shown(text)))
}

/// The file's column name for our standard name `ours`: its mapping in
/// [`LoadOptions::columns`], else the standard name itself.
pub(crate) fn mapped<'o>(options: &'o LoadOptions, ours: &'o str) -> &'o str {
    options
        .columns
        .iter()
        .find(|(o, _)| o == ours)
        .map_or(ours, |(_, theirs)| theirs.as_str())
}

/// Checks that every mapping names one of the format's standard names.
pub(crate) fn check_mapping_names(
    options: &LoadOptions,
    known: &[&str],
    format: &str,
) -> Result<()> {
    for (ours, theirs) in &options.columns {
        if !known.contains(&ours.as_str()) {
            return Err(Error::invalid(
                "column mapping",
                format!(
                    "\"{ours}\" -> \"{theirs}\": \"{ours}\" is not a standard {format} name \
                     (known: {})",
                    known.join(" ")
                ),
            ));
        }
    }
    Ok(())
}

/// The colour of particle type `t`: the user's palette, else [`TYPE_PALETTE`], cycling.
pub(crate) fn type_color(options: &LoadOptions, t: i64) -> [f32; 3] {
    let palette: &[[f32; 3]] = if options.type_colors.is_empty() {
        &TYPE_PALETTE
    } else {
        &options.type_colors
    };
    // Types count from 1; 0 and negative types still get a colour.
    // i128: `t - 1` cannot overflow for any i64 type.
    palette[(i128::from(t) - 1).rem_euclid(palette.len() as i128) as usize]
}

/// One particle as read: its size as semi-axes, or a zero shape to be sized by a radius.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Particle {
    pub center: DVec3,
    pub semi_axes: DVec3,
    pub rotation: DQuat,
    pub color: Option<[f32; 3]>,
}

/// A particle as an ellipsoid, or the reason the renderer refuses it and which column to
/// blame (`radius`, `colour`, `quaternion`).
pub(crate) fn ellipsoid(p: &Particle) -> std::result::Result<Ellipsoid, (&'static str, String)> {
    Ellipsoid::new(p.center, p.semi_axes, p.rotation, p.color).map_err(|e| match e {
        ellipsoid_splat::Error::Invalid { what, reason } => {
            let blame = match what.as_str() {
                "ellipsoid radii" => "size",
                "ellipsoid colour" => "colour",
                "ellipsoid centre" => "position",
                _ => "orientation",
            };
            (blame, format!("{what} {reason}"))
        }
        other => ("particle", other.to_string()),
    })
}

/// The particles of one frame, collected in file order.
#[derive(Default)]
pub(crate) struct FrameParticles {
    pub ellipsoids: Vec<Ellipsoid>,
    /// `(line, id)` of each.
    pub origins: Vec<(u32, i64)>,
    pub has_ids: bool,
    pub skipped: usize,
    pub first_skipped: Option<Error>,
    pub notes: Vec<String>,
}

impl FrameParticles {
    /// The frame as a [`Loaded`]: sorted by id (when the file has ids) so that a glyph keeps
    /// its place from frame to frame; two particles with one id are an error.
    pub fn finish(mut self, frame: &FrameRef) -> Result<Loaded> {
        if self.ellipsoids.is_empty() {
            let reason = match &self.first_skipped {
                Some(e) => format!(
                    "no valid particles ({} skipped; the first: {e})",
                    self.skipped
                ),
                None => "no particles in the frame".to_string(),
            };
            return Err(frame.error(frame.span.line, "atoms", reason));
        }
        if self.has_ids && !self.origins.windows(2).all(|w| w[0].1 < w[1].1) {
            let mut order: Vec<u32> = (0..self.origins.len() as u32).collect();
            order.sort_by_key(|&i| self.origins[i as usize].1);
            if let Some(w) = order
                .windows(2)
                .find(|w| self.origins[w[0] as usize].1 == self.origins[w[1] as usize].1)
            {
                let (a, b) = (self.origins[w[0] as usize], self.origins[w[1] as usize]);
                let (first, second) = (a.0.min(b.0), a.0.max(b.0));
                return Err(frame.error(
                    second as usize,
                    "id",
                    format!("duplicate atom id {} (also on line {first})", a.1),
                ));
            }
            self.ellipsoids = order.iter().map(|&i| self.ellipsoids[i as usize]).collect();
            self.origins = order.iter().map(|&i| self.origins[i as usize]).collect();
        }
        if let Some(e) = self.first_skipped {
            self.notes.push(format!(
                "skipped {} invalid particle(s); the first: {e}",
                self.skipped
            ));
        }
        Ok(Loaded {
            scene: Scene::new(self.ellipsoids),
            skipped: self.skipped,
            notes: self.notes,
            origins: Origins::Particles(self.origins),
        })
    }

    /// Keeps a particle, or with `skip_invalid` counts the error `e` instead of failing.
    pub fn push(
        &mut self,
        particle: std::result::Result<(Ellipsoid, u32, i64), Error>,
        skip_invalid: bool,
    ) -> Result<()> {
        match particle {
            Ok((e, line, id)) => {
                self.ellipsoids.push(e);
                self.origins.push((line, id));
            }
            Err(e) if skip_invalid => {
                self.skipped += 1;
                self.first_skipped.get_or_insert(e);
            }
            Err(e) => return Err(e),
        }
        Ok(())
    }
}
