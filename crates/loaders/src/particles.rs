//! What the two particle formats (LAMMPS dumps, extended XYZ) share: the type palette
//! ([`TYPE_PALETTE`]), the checks of [`LoadOptions::columns`] and
//! [`LoadOptions::type_colors`], a whitespace splitter over bytes, the label every error
//! carries (`frame 2 (timestep 1000)`), the way an atom line's values become an ellipsoid, and
//! the way a frame's particles become a scene sorted by id. The formats use this module; it
//! uses neither them nor the trajectory or `load` modules.

use std::path::Path;

use ellipsoid_splat::{Ellipsoid, Scene};
use glam::{DQuat, DVec3};

use crate::error::parse_error;
use crate::gzip::gunzip_if_compressed;
use crate::loaded::{Loaded, Origins};
use crate::options::LoadOptions;
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

/// The options only the particle formats use, checked before any parsing.
pub(crate) fn check_options(options: &LoadOptions) -> Result<()> {
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

/// The colour an atom line asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Paint {
    /// `r g b` / `color`, each in [0, 1].
    Rgb([f64; 3]),
    /// A numbered type: its palette colour.
    Type(i64),
    /// A species name, the file's `n`-th distinct name (0-based, file order): numbered again
    /// in id order by [`FrameParticles::finish`], then coloured.
    Name(u32),
    /// No colour column: coloured by shape.
    Shape,
}

/// One atom line's values, before they become an ellipsoid.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Atom {
    pub center: DVec3,
    /// The semi-axes of the shape columns, when the file has them.
    pub shape: Option<DVec3>,
    /// The sphere radius, when the file has a radius (or diameter) column.
    pub radius: Option<f64>,
    /// The quaternion read, when the file has an orientation.
    pub rotation: Option<DQuat>,
    pub paint: Paint,
}

/// The format's names for an atom's columns, blamed in errors.
pub(crate) struct AtomColumns<'a> {
    pub position: &'a str,
    pub shape: &'a str,
    /// The shape blamed when it is zero and there is no radius to use instead.
    pub zero_shape: &'a str,
    pub radius: &'a str,
    pub orientation: &'a str,
    pub color: &'a str,
}

/// An atom line's values as an ellipsoid, or an error at `line` naming the column to blame.
/// The shape gives the size unless it is zero (a point particle) and there is a radius.
pub(crate) fn atom_ellipsoid(
    atom: &Atom,
    columns: &AtomColumns,
    options: &LoadOptions,
    frame: &FrameRef,
    line: usize,
) -> Result<Ellipsoid> {
    let shape_sized = match (atom.shape, atom.radius) {
        (Some(s), Some(_)) => s != DVec3::ZERO,
        (Some(_), None) => true,
        (None, _) => false,
    };
    let semi_axes = match atom.shape {
        Some(s) if shape_sized => s,
        // Headers without a shape or a radius are refused before any atom line.
        _ => DVec3::splat(atom.radius.unwrap_or(0.0)),
    };
    let rotation = match atom.rotation {
        Some(q) if q == DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0) => {
            return Err(frame.error(
                line,
                columns.orientation,
                "zero quaternion: it must be non-zero to define a rotation",
            ))
        }
        Some(q) => q,
        None => DQuat::IDENTITY,
    };
    let color = match atom.paint {
        Paint::Rgb(c) => Some(c.map(|v| v as f32)),
        Paint::Type(t) => Some(type_color(options, t)),
        // Given its colour once the frame is sorted; shape colour meanwhile.
        Paint::Name(_) | Paint::Shape => None,
    };
    Ellipsoid::new(atom.center, semi_axes, rotation, color).map_err(|e| {
        let (what, reason) = match e {
            ellipsoid_splat::Error::Invalid { what, reason } => (what, reason),
            other => (String::new(), other.to_string()),
        };
        let column = match what.as_str() {
            "ellipsoid radii" if shape_sized && semi_axes == DVec3::ZERO => columns.zero_shape,
            "ellipsoid radii" if shape_sized => columns.shape,
            "ellipsoid radii" => columns.radius,
            "ellipsoid colour" => columns.color,
            "ellipsoid centre" => columns.position,
            "" => "particle",
            _ => columns.orientation,
        };
        frame.error(
            line,
            column,
            format!("{what} {reason}").trim_start().to_string(),
        )
    })
}

/// The particles of one frame, collected in file order.
#[derive(Default)]
pub(crate) struct FrameParticles {
    pub ellipsoids: Vec<Ellipsoid>,
    /// `(line, id)` of each.
    pub origins: Vec<(u32, i64)>,
    /// The species name of each ([`Paint::Name`]), if it has one: a species column may mix
    /// names and type numbers.
    pub names: Vec<Option<u32>>,
    pub has_ids: bool,
    pub skipped: usize,
    pub first_skipped: Option<Error>,
    pub notes: Vec<String>,
}

impl FrameParticles {
    /// The frame as a [`Loaded`]: sorted by id (when the file has ids) so that a glyph keeps
    /// its place from frame to frame; two particles with one id are an error. Species names
    /// are numbered 1, 2, ... by first appearance in id order, AFTER the sort, so that a
    /// trajectory whose atoms keep their ids and species keeps its colours, however each
    /// frame orders its lines.
    pub fn finish(mut self, frame: &FrameRef, options: &LoadOptions) -> Result<Loaded> {
        if self.ellipsoids.is_empty() {
            let first = self.first_skipped.map(|e| e.to_string());
            return Err(no_particles(frame, self.skipped, first.as_deref()));
        }
        if self.has_ids && !self.origins.windows(2).all(|w| w[0].1 < w[1].1) {
            let mut order: Vec<u32> = (0..self.origins.len() as u32).collect();
            order.sort_by_key(|&i| self.origins[i as usize].1);
            if let Some(w) = order
                .windows(2)
                .find(|w| self.origins[w[0] as usize].1 == self.origins[w[1] as usize].1)
            {
                let (a, b) = (self.origins[w[0] as usize], self.origins[w[1] as usize]);
                return Err(duplicate_id(frame, a.1, a.0.min(b.0), a.0.max(b.0)));
            }
            self.ellipsoids = order.iter().map(|&i| self.ellipsoids[i as usize]).collect();
            self.origins = order.iter().map(|&i| self.origins[i as usize]).collect();
            self.names = order.iter().map(|&i| self.names[i as usize]).collect();
        }
        if self.names.iter().any(Option::is_some) {
            // File-order name number -> id-order number (0 = not seen yet). Names of skipped
            // lines count in the file order, hence the maximum, not the length.
            let size = self
                .names
                .iter()
                .flatten()
                .max()
                .map_or(0, |&m| m as usize + 1);
            let mut number = vec![0i64; size];
            let mut seen = 0;
            for (e, name) in self.ellipsoids.iter_mut().zip(&self.names) {
                let Some(name) = *name else {
                    continue;
                };
                let n = &mut number[name as usize];
                if *n == 0 {
                    seen += 1;
                    *n = seen;
                }
                e.color = type_color(options, *n);
            }
        }
        if let Some(e) = self.first_skipped {
            self.notes.push(skipped_note(self.skipped, &e.to_string()));
        }
        Ok(Loaded {
            scene: Scene::new(self.ellipsoids),
            skipped: self.skipped,
            notes: self.notes,
            origins: Origins::Particles(self.origins),
        })
    }

    /// Keeps a particle (`name`: its species name, if named), or with `skip_invalid` counts
    /// the error `e` instead of failing.
    pub fn push(
        &mut self,
        particle: Result<(Ellipsoid, u32, i64)>,
        name: Option<u32>,
        skip_invalid: bool,
    ) -> Result<()> {
        match particle {
            Ok((e, line, id)) => {
                self.ellipsoids.push(e);
                self.origins.push((line, id));
                self.names.push(name);
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

/// The error for a frame without one valid particle: `skipped` were dropped, the first for
/// `first_skipped`.
pub(crate) fn no_particles(frame: &FrameRef, skipped: usize, first_skipped: Option<&str>) -> Error {
    let reason = match first_skipped {
        Some(e) => format!("no valid particles ({skipped} skipped; the first: {e})"),
        None => "no particles in the frame".to_string(),
    };
    frame.error(frame.span.line, "atoms", reason)
}

/// The error for atom `id` on two lines, `first` and `second` (the later).
pub(crate) fn duplicate_id(frame: &FrameRef, id: i64, first: u32, second: u32) -> Error {
    frame.error(
        second as usize,
        "id",
        format!("duplicate atom id {id} (also on line {first})"),
    )
}

/// The note for `skipped` particles dropped as invalid, the first for `first`.
pub(crate) fn skipped_note(skipped: usize, first: &str) -> String {
    format!("skipped {skipped} invalid particle(s); the first: {first}")
}

/// The note `load` adds to frame 1 of a file of several frames.
fn note_frames(loaded: &mut Loaded, frames: usize) {
    if frames > 1 {
        loaded.notes.insert(
            0,
            format!(
                "frame 1 of {frames} (the file holds {frames} frames; open it as a trajectory for \
                 the others)"
            ),
        );
    }
}

/// Finds a file's frames in its bytes.
pub(crate) type Scan = fn(&[u8], &Path) -> Result<Vec<Span>>;
/// Parses one frame's byte range.
pub(crate) type ParseFrame = fn(&[u8], FrameRef, &LoadOptions) -> Result<Loaded>;

/// Frame 1 of a particle file's `bytes` (plain or gzipped), with a note giving the number of
/// frames when there are several: what `load` returns for a particle file.
pub(crate) fn first_frame(
    bytes: Vec<u8>,
    file: &Path,
    options: &LoadOptions,
    scan: Scan,
    parse: ParseFrame,
) -> Result<Loaded> {
    check_options(options)?;
    let bytes = gunzip_if_compressed(bytes, file)?;
    let spans = scan(&bytes, file)?;
    let Some(&span) = spans.first() else {
        return Err(parse_error(file, 0, "frames", "empty file: no frames"));
    };
    let frame = FrameRef {
        file,
        number: 1,
        span,
    };
    let mut loaded = parse(&bytes[span.start..span.end], frame, options)?;
    note_frames(&mut loaded, spans.len());
    Ok(loaded)
}
