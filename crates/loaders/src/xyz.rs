//! Reads extended XYZ files (ASE, OVITO, GPUMD; plain or gzipped), one or more frames back to
//! back.
//!
//! A frame is a line with the number of atoms, a comment line of `key=value` pairs (values may
//! be quoted, `"..."`, or braced, `{...}`; a key alone is a flag), then one line per atom. The
//! `Properties` key names the columns: `name:type:count` triplets, type `S` (string), `R`
//! (real), `I` (integer) or `L` (logical); without it the columns are `species:S:1:pos:R:3`,
//! as in plain XYZ. `Timestep=` (else `step=`, else an integer `time=`) gives the frame's
//! timestep ([`Trajectory::timestep`]); other keys (`Lattice`, energies) are not used: positions
//! are Cartesian.
//!
//! Properties read (our standard names; others are ignored and named once in the notes):
//!
//! - `pos:R:3`, the centre (required);
//! - `aspherical_shape:R:3`: the SEMI-AXES (half-lengths, not the diameters of a LAMMPS
//!   dump's `shapex` columns); else `radius:R:1`, for spheres. A zero shape takes the
//!   `radius`, if any. A file with neither is an error (map a property with
//!   [`LoadOptions::columns`]);
//! - `orientation:R:4`: the quaternion, holding x, y, z, w in that order, rotating the
//!   particle's frame into the lab frame; without it ellipsoids are drawn unrotated, with a
//!   note;
//! - `id:I:1`: frames are sorted by it; `species` (else `type`), `S` or `I`: the colour, from
//!   [`LoadOptions::type_colors`] or [`TYPE_PALETTE`]: an integer species is that type; names
//!   (`C`, `A`) are numbered 1, 2, ... by first appearance in id order, after the sort, so in
//!   a trajectory whose atoms keep their ids and species a name keeps its colour in every
//!   frame, whatever the order of the lines (without `id`, id order is file order);
//!   `color:R:3` (each in [0, 1]) gives colours directly. Without either, glyphs are coloured
//!   by shape.
//!
//! A `Properties` key declares at most [`MAX_FIELDS`] fields in all (a larger header is an
//! error, not an allocation).
//!
//! [`LoadOptions::columns`] maps our names to the file's property names
//! (`("aspherical_shape", "shape")`). Every rejection is an [`Error::Parse`](crate::Error::Parse)
//! naming the file, the line, and in its column text the frame (1-based, with its timestep) and
//! the property: `run.extxyz:9:frame 1, pos[2] (field 3): not a number: "x"`.
//!
//! [`Trajectory::timestep`]: crate::Trajectory::timestep
//! [`TYPE_PALETTE`]: crate::TYPE_PALETTE

use std::path::Path;

use glam::{DQuat, DVec3};

use crate::error::parse_error;
use crate::gzip::read_gunzipped;
use crate::loaded::Loaded;
use crate::options::LoadOptions;
use crate::particles::{
    atom_ellipsoid, check_mapping_names, fields, first_frame, integer, mapped, real, shown, Atom,
    AtomColumns, FrameParticles, FrameRef, Lines, Paint, Span,
};
use crate::Result;

/// The standard property names.
pub const PROPERTIES: [&str; 8] = [
    "id",
    "species",
    "type",
    "pos",
    "aspherical_shape",
    "orientation",
    "radius",
    "color",
];

/// What a column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Quantity {
    Id,
    Species,
    Pos,
    Shape,
    Orientation,
    Radius,
    Color,
}

/// Reads frame 1 of an extended XYZ file (plain or gzipped), with a note giving the number of
/// frames when there are several; [`Trajectory`](crate::Trajectory) reads the others.
pub fn load_xyz(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    first_frame(read_gunzipped(path)?, path, options, scan, parse_frame)
}

/// Parses frame 1 of the extended XYZ text in `bytes` (plain or gzipped); `file` only names
/// the source in errors.
pub fn parse_xyz(bytes: &[u8], file: &Path, options: &LoadOptions) -> Result<Loaded> {
    first_frame(bytes.to_vec(), file, options, scan, parse_frame)
}

/// The frames of the file: each is its count line, its comment line and that many atom lines;
/// blank lines between frames are skipped.
pub(crate) fn scan(bytes: &[u8], file: &Path) -> Result<Vec<Span>> {
    let bytes_start = if bytes.starts_with(b"\xef\xbb\xbf") {
        3
    } else {
        0
    };
    let mut lines = Lines::new(&bytes[bytes_start..], 1);
    let mut spans = Vec::new();
    loop {
        let start = lines.offset();
        let Some((number, line)) = lines.next() else {
            break;
        };
        let text = line.trim_ascii();
        if text.is_empty() {
            continue;
        }
        let k = spans.len() + 1;
        let count = atom_count(text, number, k, file)?;
        let Some((_, comment)) = lines.next() else {
            return Err(no_comment_line(file, number, k));
        };
        let timestep = comment_timestep(comment);
        for read in 0..count {
            if lines.next().is_none() {
                let last = lines.next_line.saturating_sub(1);
                return Err(truncated(file, last, k, read, count));
            }
        }
        spans.push(Span {
            start: start + bytes_start,
            end: lines.offset() + bytes_start,
            line: number,
            timestep,
        });
    }
    if spans.is_empty() {
        return Err(parse_error(file, 0, "atom count", "empty file: no frames"));
    }
    Ok(spans)
}

/// The number of atoms on frame `k`'s count line `text` (line `number`).
pub(crate) fn atom_count(text: &[u8], number: usize, k: usize, file: &Path) -> Result<usize> {
    integer(text)
        .ok()
        .and_then(|n| usize::try_from(n).ok())
        .ok_or_else(|| {
            parse_error(
                file,
                number,
                format!("frame {k}, atom count"),
                format!(
                    "expected the number of atoms of frame {k}, found \"{}\"",
                    shown(text)
                ),
            )
        })
}

/// The error for frame `k`, whose file ends after its count line (line `number`).
pub(crate) fn no_comment_line(file: &Path, number: usize, k: usize) -> crate::Error {
    parse_error(
        file,
        number,
        format!("frame {k}, comment line"),
        "the file ends after the atom count: no comment line",
    )
}

/// The error for frame `k`, whose file ends (at line `last`) after `read` of `count` atom
/// lines.
pub(crate) fn truncated(
    file: &Path,
    last: usize,
    k: usize,
    read: usize,
    count: usize,
) -> crate::Error {
    parse_error(
        file,
        last,
        format!("frame {k}, atoms"),
        format!("truncated: the file ends after {read} of {count} atom lines"),
    )
}

/// The timestep a comment line gives, if any.
pub(crate) fn comment_timestep(comment: &[u8]) -> Option<i64> {
    comment_keys(comment)
        .ok()
        .and_then(|keys| timestep_of(&keys))
}

/// A `key=value` pair of a comment line.
type KeyValue<'a> = (&'a [u8], &'a [u8]);

/// The `key=value` pairs of a comment line; a key without `=` is a flag (value `T`). Quotes
/// and braces are removed from values.
fn comment_keys(line: &[u8]) -> std::result::Result<Vec<KeyValue<'_>>, String> {
    let mut keys = Vec::new();
    let mut i = 0;
    let space = |b: u8| b.is_ascii_whitespace();
    while i < line.len() {
        while i < line.len() && space(line[i]) {
            i += 1;
        }
        if i >= line.len() {
            break;
        }
        let start = i;
        while i < line.len() && !space(line[i]) && line[i] != b'=' {
            i += 1;
        }
        let key = &line[start..i];
        let mut j = i;
        while j < line.len() && space(line[j]) {
            j += 1;
        }
        if j >= line.len() || line[j] != b'=' {
            keys.push((key, &b"T"[..]));
            continue;
        }
        if key.is_empty() {
            return Err("a value without a key (\"=\" at the start of a pair)".into());
        }
        i = j + 1;
        while i < line.len() && space(line[i]) {
            i += 1;
        }
        let close = match line.get(i) {
            Some(b'"') => Some(b'"'),
            Some(b'{') => Some(b'}'),
            _ => None,
        };
        let value = if let Some(close) = close {
            let from = i + 1;
            let mut k = from;
            // A backslash escapes the next byte (a quote inside a quoted value).
            while k < line.len() && line[k] != close {
                k += if line[k] == b'\\' { 2 } else { 1 };
            }
            if k >= line.len() {
                return Err(format!(
                    "unterminated {} in the value of key \"{}\"",
                    if close == b'"' { "quote" } else { "brace" },
                    shown(key)
                ));
            }
            i = k + 1;
            &line[from..k]
        } else {
            let from = i;
            while i < line.len() && !space(line[i]) {
                i += 1;
            }
            &line[from..i]
        };
        keys.push((key, value));
    }
    Ok(keys)
}

/// The value of `key` (case-insensitive), the last if repeated.
fn key_value<'a>(keys: &[KeyValue<'a>], key: &str) -> Option<&'a [u8]> {
    keys.iter()
        .rev()
        .find(|(k, _)| k.eq_ignore_ascii_case(key.as_bytes()))
        .map(|(_, v)| *v)
}

/// The frame's timestep: `Timestep=`, else `step=`, else `time=` if it is an integer.
fn timestep_of(keys: &[KeyValue]) -> Option<i64> {
    ["timestep", "step", "time"]
        .iter()
        .find_map(|k| key_value(keys, k).and_then(|v| integer(v.trim_ascii()).ok()))
}

/// The most fields a `Properties` key may declare, all properties together. Each field costs a
/// slot per atom line's parse, and a count is a few bytes of text: without a cap a 1 MB
/// comment line of `a:R:1024:` triplets would ask for gigabytes. Real files have tens.
pub const MAX_FIELDS: usize = 4096;

/// One `Properties` entry.
struct Property {
    name: String,
    kind: u8,
    /// Its first field and number of fields.
    first: usize,
    count: usize,
}

/// What the comment line says about every atom line.
pub(crate) struct Header {
    /// For each field, what it holds (and which component), if read.
    slots: Vec<Option<(Quantity, usize)>>,
    /// The properties, for the name of a field in errors (`pos[2]`).
    props: Vec<Property>,
    shape: bool,
    orientation: bool,
    radius: bool,
    color: bool,
    id: bool,
    species: bool,
    /// The species is an `I` column.
    species_integer: bool,
}

impl Header {
    pub(crate) fn parse(
        comment: &[u8],
        line: usize,
        frame: &FrameRef,
        options: &LoadOptions,
    ) -> Result<(Header, Vec<String>)> {
        let err = |reason: String| frame.error(line, "Properties", reason);
        let keys = comment_keys(comment).map_err(|r| frame.error(line, "comment line", r))?;
        let spec = key_value(&keys, "Properties").unwrap_or(b"species:S:1:pos:R:3");
        let parts: Vec<&[u8]> = spec.split(|&b| b == b':').collect();
        if parts.len() % 3 != 0 {
            return Err(err(format!(
                "\"{}\" is not a list of name:type:count triplets",
                shown(spec)
            )));
        }
        let mut props = Vec::new();
        let mut first = 0;
        for t in parts.chunks(3) {
            let name = String::from_utf8_lossy(t[0]).into_owned();
            let kind = match t[1] {
                [k @ (b'S' | b'R' | b'I' | b'L')] => *k,
                other => {
                    return Err(err(format!(
                        "property \"{name}\" has type \"{}\": expected S, R, I or L",
                        shown(other)
                    )))
                }
            };
            let count = integer(t[2])
                .ok()
                .and_then(|c| usize::try_from(c).ok())
                .filter(|c| (1..=MAX_FIELDS).contains(c))
                .ok_or_else(|| {
                    err(format!(
                        "property \"{name}\" has count \"{}\": expected 1 to {MAX_FIELDS}",
                        shown(t[2])
                    ))
                })?;
            if first + count > MAX_FIELDS {
                return Err(err(format!(
                    "property \"{name}\" would make field {}: at most {MAX_FIELDS} fields are \
                     read per atom line",
                    first + count
                )));
            }
            props.push(Property {
                name,
                kind,
                first,
                count,
            });
            first += count;
        }
        let find = |ours: &str| -> Result<Option<&Property>> {
            let theirs = mapped(options, ours);
            let found = props.iter().find(|p| p.name == theirs);
            if found.is_none() && theirs != ours {
                return Err(err(format!(
                    "column mapping {ours} -> {theirs}: the file has no property \"{theirs}\" \
                     (its properties: {})",
                    props
                        .iter()
                        .map(|p| p.name.as_str())
                        .collect::<Vec<_>>()
                        .join(" ")
                )));
            }
            Ok(found)
        };
        // (quantity, our name, allowed types, count)
        let wanted: [(Quantity, &str, &[u8], usize); 8] = [
            (Quantity::Id, "id", b"I", 1),
            (Quantity::Species, "species", b"SI", 1),
            (Quantity::Species, "type", b"SI", 1),
            (Quantity::Pos, "pos", b"R", 3),
            (Quantity::Shape, "aspherical_shape", b"R", 3),
            (Quantity::Orientation, "orientation", b"R", 4),
            (Quantity::Radius, "radius", b"R", 1),
            (Quantity::Color, "color", b"R", 3),
        ];
        let mut slots = vec![None; first];
        let mut species_integer = false;
        let mut present = Vec::new();
        for (quantity, ours, kinds, count) in wanted {
            let Some(p) = find(ours)? else {
                continue;
            };
            // `type` is read only when there is no `species`.
            if present.contains(&quantity) {
                continue;
            }
            if !kinds.contains(&p.kind) || p.count != count {
                return Err(err(format!(
                    "property \"{}\" is {}:{}, expected {}:{count}",
                    p.name,
                    p.kind as char,
                    p.count,
                    kinds.iter().map(|&k| k as char).collect::<String>()
                )));
            }
            for c in 0..count {
                if slots[p.first + c].is_some() {
                    return Err(err(format!("property \"{}\" is read twice", p.name)));
                }
                slots[p.first + c] = Some((quantity, c));
            }
            if quantity == Quantity::Species {
                species_integer = p.kind == b'I';
            }
            present.push(quantity);
        }
        let has = |q| present.contains(&q);
        if !has(Quantity::Pos) {
            return Err(err("no pos:R:3 property: the centres are required".into()));
        }
        if !has(Quantity::Shape) && !has(Quantity::Radius) {
            return Err(err(format!(
                "no particle size: need aspherical_shape:R:3 (semi-axes) or radius:R:1; the \
                 file has: {} (a property under another name can be mapped with the column \
                 mapping option)",
                props
                    .iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(" ")
            )));
        }
        let ignored = props
            .iter()
            .filter(|p| slots[p.first].is_none())
            .map(|p| p.name.clone())
            .collect();
        Ok((
            Header {
                slots,
                props,
                shape: has(Quantity::Shape),
                orientation: has(Quantity::Orientation),
                radius: has(Quantity::Radius),
                color: has(Quantity::Color),
                id: has(Quantity::Id),
                species: has(Quantity::Species),
                species_integer,
            },
            ignored,
        ))
    }

    /// An empty collection for a frame's particles, room for `room`, with the notes the
    /// header gives (`ignored`: the properties not read).
    pub(crate) fn particles(&self, ignored: &[String], room: usize) -> FrameParticles {
        let mut out = FrameParticles {
            has_ids: self.id,
            ellipsoids: Vec::with_capacity(room),
            origins: Vec::with_capacity(room),
            ..FrameParticles::default()
        };
        if !ignored.is_empty() {
            out.notes
                .push(format!("properties not read: {}", ignored.join(" ")));
        }
        if self.shape && !self.orientation {
            out.notes
                .push("no orientation property: ellipsoids are drawn unrotated".into());
        }
        out
    }

    /// The name of field `k` (0-based) in errors: `pos[2]`, or `radius` for a count of 1.
    fn field_name(&self, k: usize) -> String {
        match self
            .props
            .iter()
            .find(|p| (p.first..p.first + p.count).contains(&k))
        {
            Some(p) if p.count == 1 => p.name.clone(),
            Some(p) => format!("{}[{}]", p.name, k - p.first + 1),
            None => format!("field {}", k + 1),
        }
    }

    /// One atom line as a particle: its ellipsoid, line and id (`ordinal` without an `id`),
    /// and its species name's number in `species_names` (file order), if the species is a name.
    pub(crate) fn atom<'a>(
        &self,
        text: &'a [u8],
        line: usize,
        ordinal: usize,
        species_names: &mut Vec<&'a [u8]>,
        frame: &FrameRef,
        options: &LoadOptions,
    ) -> (Result<(ellipsoid_splat::Ellipsoid, u32, i64)>, Option<u32>) {
        let mut name = None;
        let result = self.read_atom(
            text,
            line,
            ordinal,
            species_names,
            &mut name,
            frame,
            options,
        );
        (result, name)
    }

    /// [`Header::atom`]'s body: `name` is set even when the line fails, so `?` can be used.
    #[allow(clippy::too_many_arguments)]
    fn read_atom<'a>(
        &self,
        text: &'a [u8],
        line: usize,
        ordinal: usize,
        species_names: &mut Vec<&'a [u8]>,
        name: &mut Option<u32>,
        frame: &FrameRef,
        options: &LoadOptions,
    ) -> Result<(ellipsoid_splat::Ellipsoid, u32, i64)> {
        let mut pos = [0.0f64; 3];
        let mut shape = [0.0f64; 3];
        let mut quat = [0.0f64; 4];
        let mut radius = 0.0f64;
        let mut color = [0.0f64; 3];
        let (mut id, mut kind) = (ordinal as i64, 0i64);
        let mut count = 0;
        for (k, field) in fields(text).enumerate() {
            count = k + 1;
            let Some(&Some((quantity, c))) = self.slots.get(k) else {
                continue;
            };
            let at = || format!("{} (field {})", self.field_name(k), k + 1);
            let value = || real(field).map_err(|r| frame.error(line, &at(), r));
            match quantity {
                Quantity::Id => id = integer(field).map_err(|r| frame.error(line, &at(), r))?,
                Quantity::Species if self.species_integer => {
                    kind = integer(field).map_err(|r| frame.error(line, &at(), r))?;
                }
                Quantity::Species => match integer(field) {
                    Ok(t) => kind = t,
                    Err(_) => {
                        let n = match species_names.iter().position(|s| *s == field) {
                            Some(n) => n,
                            None => {
                                species_names.push(field);
                                species_names.len() - 1
                            }
                        };
                        // A new name takes a line of its own: n is below the frame's lines.
                        *name = Some(u32::try_from(n).unwrap_or(u32::MAX));
                    }
                },
                Quantity::Pos => pos[c] = value()?,
                Quantity::Shape => shape[c] = value()?,
                Quantity::Orientation => quat[c] = value()?,
                Quantity::Radius => radius = value()?,
                Quantity::Color => color[c] = value()?,
            }
        }
        if count != self.slots.len() {
            return Err(frame.error(
                line,
                "atom line",
                format!(
                    "wrong number of fields: expected {} (as Properties gives), found {count}",
                    self.slots.len()
                ),
            ));
        }
        let paint = if self.color {
            Paint::Rgb(color)
        } else if let Some(n) = *name {
            Paint::Name(n)
        } else if self.species {
            Paint::Type(kind)
        } else {
            Paint::Shape
        };
        let atom = Atom {
            center: DVec3::from_array(pos),
            shape: self.shape.then(|| DVec3::from_array(shape)),
            radius: self.radius.then_some(radius),
            // `orientation` holds x, y, z, w.
            rotation: self.orientation.then(|| DQuat::from_array(quat)),
            paint,
        };
        let columns = AtomColumns {
            position: "pos",
            shape: "aspherical_shape",
            zero_shape: "aspherical_shape (a zero shape is a point particle: give a radius \
                         property)",
            radius: "radius",
            orientation: "orientation",
            color: "color",
        };
        let built = atom_ellipsoid(&atom, &columns, options, frame, line)?;
        Ok((built, u32::try_from(line).unwrap_or(u32::MAX), id))
    }
}

/// Parses one frame (`bytes` is its range of the file, from its count line).
pub(crate) fn parse_frame(bytes: &[u8], frame: FrameRef, options: &LoadOptions) -> Result<Loaded> {
    check_mapping_names(options, &PROPERTIES, "extended XYZ")?;
    let mut lines = Lines::new(bytes, frame.span.line);
    // The scan has checked the count and that every line is there.
    let (count_line, count_text) = lines.next().unwrap_or((frame.span.line, b""));
    let count = integer(count_text.trim_ascii())
        .ok()
        .and_then(|n| usize::try_from(n).ok())
        .ok_or_else(|| frame.error(count_line, "atom count", "not a count of atoms"))?;
    let Some((comment_line, comment)) = lines.next() else {
        return Err(frame.error(count_line, "comment line", "no comment line"));
    };
    let (header, ignored) = Header::parse(comment, comment_line, &frame, options)?;
    let mut out = header.particles(&ignored, count.min(lines.remaining() / 2));
    let mut species_names = Vec::new();
    for ordinal in 1..=count {
        let Some((n, text)) = lines.next() else {
            return Err(frame.error(
                comment_line,
                "atoms",
                format!(
                    "truncated: the frame ends after {} of {count} atom lines",
                    ordinal - 1
                ),
            ));
        };
        let (atom, name) = header.atom(text, n, ordinal, &mut species_names, &frame, options);
        out.push(atom, name, options.skip_invalid)?;
    }
    out.finish(&frame, options)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comment_keys_take_quotes_braces_and_flags() {
        let keys = comment_keys(
            br#"Lattice="1 0 0 0 1 0 0 0 1" Properties=species:S:1:pos:R:3 pbc = "T T T" flag info={a b} Timestep=40"#,
        )
        .unwrap();
        assert_eq!(
            keys,
            vec![
                (&b"Lattice"[..], &b"1 0 0 0 1 0 0 0 1"[..]),
                (b"Properties", b"species:S:1:pos:R:3"),
                (b"pbc", b"T T T"),
                (b"flag", b"T"),
                (b"info", b"a b"),
                (b"Timestep", b"40"),
            ]
        );
        assert_eq!(timestep_of(&keys), Some(40));
        assert!(comment_keys(br#"Lattice="1 0 0"#).is_err());
    }
}
