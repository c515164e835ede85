//! Reads LAMMPS `dump custom` text files (plain or gzipped), one or more frames, as the
//! ASPHERE package's ellipsoids (Gay-Berne, RE-squared) and plain spheres are written.
//!
//! What it reads -- the items, the columns and their standard names (`shapex` holds a
//! DIAMETER), the box, the colours -- and the form of every error are specified once, in the
//! repository's `docs/formats.md` ("LAMMPS dump"). Here: `scan` cuts a dump into frames at
//! `ITEM: TIMESTEP` ([`Trajectory`] keeps the cuts), and each frame is parsed on demand into
//! glyphs sorted by `id`, rejections being [`Error::Parse`](crate::Error::Parse) values
//! that name the file, the line, the frame and the column.
//!
//! [`Trajectory`]: crate::Trajectory

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

/// The standard column names, in the order of the indices below.
pub const COLUMNS: [&str; 26] = [
    "id", "type", "x", "y", "z", "xu", "yu", "zu", "xs", "ys", "zs", "xsu", "ysu", "zsu", "shapex",
    "shapey", "shapez", "quatw", "quati", "quatj", "quatk", "radius", "diameter", "r", "g", "b",
];
const ID: usize = 0;
const TYPE: usize = 1;
/// The first columns of the position triplets, in order of preference, and whether scaled.
const POSITIONS: [(usize, bool); 4] = [(2, false), (5, false), (8, true), (11, true)];
const SHAPE: usize = 14;
const QUAT: usize = 17;
const RADIUS: usize = 21;
const DIAMETER: usize = 22;
const COLOR: usize = 23;

/// Reads frame 1 of a LAMMPS dump (plain or gzipped), with a note giving the number of frames
/// when there are several; [`Trajectory`](crate::Trajectory) reads the others.
pub fn load_lammps(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    first_frame(read_gunzipped(path)?, path, options, scan, parse_frame)
}

/// Parses frame 1 of the LAMMPS dump in `bytes` (plain or gzipped); `file` only names the
/// source in errors.
pub fn parse_lammps(bytes: &[u8], file: &Path, options: &LoadOptions) -> Result<Loaded> {
    first_frame(bytes.to_vec(), file, options, scan, parse_frame)
}

/// The frames of a dump: each starts at an `ITEM: TIMESTEP` line (the first also takes any
/// lines before it, such as `ITEM: UNITS`); the timestep is the line after it.
pub(crate) fn scan(bytes: &[u8], file: &Path) -> Result<Vec<Span>> {
    let mut lines = Lines::new(bytes, 1);
    let mut starts: Vec<(usize, usize)> = Vec::new();
    loop {
        let offset = lines.offset();
        let Some((number, line)) = lines.next() else {
            break;
        };
        if is_timestep_item(line) {
            starts.push((offset, number));
        }
    }
    if starts.is_empty() {
        let reason = if bytes.iter().all(u8::is_ascii_whitespace) {
            "empty file: no frames"
        } else {
            "no ITEM: TIMESTEP line: not a LAMMPS dump (each frame starts with ITEM: TIMESTEP)"
        };
        return Err(parse_error(file, 0, "ITEM: TIMESTEP", reason));
    }
    // Lines before the first frame (ITEM: UNITS) are parsed with it.
    starts[0] = (0, 1);
    let mut spans = Vec::with_capacity(starts.len());
    for (i, &(start, line)) in starts.iter().enumerate() {
        let end = starts.get(i + 1).map_or(bytes.len(), |&(s, _)| s);
        let mut frame = Lines::new(&bytes[start..end], line);
        let timestep = frame
            .by_ref()
            .skip_while(|(_, l)| l.trim_ascii() != b"ITEM: TIMESTEP")
            .nth(1)
            .and_then(|(_, l)| integer(l.trim_ascii()).ok());
        spans.push(Span {
            start,
            end,
            line,
            timestep,
        });
    }
    Ok(spans)
}

/// The simulation box: `origin + s.x * a + s.y * b + s.z * c` is the point of scaled
/// coordinates `s`.
///
/// A triclinic dump gives, per axis, the bounding box of the tilted cell and the tilt factors:
/// `xlo_bound = xlo + min(0, xy, xz, xy + xz)`,
/// `xhi_bound = xhi + max(0, xy, xz, xy + xz)`, `ylo_bound = ylo + min(0, yz)`,
/// `yhi_bound = yhi + max(0, yz)` (z unchanged), and the cell's edges `a = (xhi - xlo, 0, 0)`,
/// `b = (xy, yhi - ylo, 0)`, `c = (xz, yz, zhi - zlo)` from the origin `(xlo, ylo, zlo)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// The corner of scaled coordinates (0, 0, 0).
    pub origin: DVec3,
    /// The edge of scaled x.
    pub a: DVec3,
    /// The edge of scaled y.
    pub b: DVec3,
    /// The edge of scaled z.
    pub c: DVec3,
}

impl Cell {
    /// The cell of an orthogonal box's `[lo, hi]` per axis.
    pub fn orthogonal(bounds: [[f64; 2]; 3]) -> Self {
        let [x, y, z] = bounds;
        Cell {
            origin: DVec3::new(x[0], y[0], z[0]),
            a: DVec3::new(x[1] - x[0], 0.0, 0.0),
            b: DVec3::new(0.0, y[1] - y[0], 0.0),
            c: DVec3::new(0.0, 0.0, z[1] - z[0]),
        }
    }

    /// The cell of a triclinic dump's three lines `lo_bound hi_bound tilt` (tilts `xy`, `xz`,
    /// `yz` in that order).
    pub fn triclinic(lines: [[f64; 3]; 3]) -> Self {
        let [[xlo_b, xhi_b, xy], [ylo_b, yhi_b, xz], [zlo, zhi, yz]] = lines;
        let xlo = xlo_b - 0.0f64.min(xy).min(xz).min(xy + xz);
        let xhi = xhi_b - 0.0f64.max(xy).max(xz).max(xy + xz);
        let ylo = ylo_b - 0.0f64.min(yz);
        let yhi = yhi_b - 0.0f64.max(yz);
        Cell {
            origin: DVec3::new(xlo, ylo, zlo),
            a: DVec3::new(xhi - xlo, 0.0, 0.0),
            b: DVec3::new(xy, yhi - ylo, 0.0),
            c: DVec3::new(xz, yz, zhi - zlo),
        }
    }

    /// The point of scaled coordinates `s`.
    pub fn point(&self, s: DVec3) -> DVec3 {
        self.origin + s.x * self.a + s.y * self.b + s.z * self.c
    }
}

/// What the `ITEM: ATOMS` line says about every atom line.
struct Header {
    /// The file's column names.
    names: Vec<String>,
    /// For each field of an atom line, the standard column it holds, if read.
    slots: Vec<Option<usize>>,
    /// The first column of the position triplet read, and whether it is scaled.
    position: (usize, bool),
    shape: bool,
    quaternion: bool,
    /// `RADIUS` or `DIAMETER`, if either.
    sphere: Option<usize>,
    color: bool,
    id: bool,
    kind: bool,
    line: usize,
}

impl Header {
    fn parse(
        item: &[u8],
        line: usize,
        frame: &FrameRef,
        options: &LoadOptions,
    ) -> Result<(Self, Vec<String>)> {
        let err = |column: &str, reason: String| frame.error(line, column, reason);
        let names: Vec<String> = fields(item)
            .skip(1)
            .map(|f| String::from_utf8_lossy(f).into_owned())
            .collect();
        // `index[c]` is the field of standard column `c`, if the file has it.
        let mut index = [None; COLUMNS.len()];
        for (c, ours) in COLUMNS.iter().enumerate() {
            let theirs = mapped(options, ours);
            index[c] = names.iter().position(|n| n == theirs);
            if index[c].is_none() && theirs != *ours {
                return Err(err(
                    "ITEM: ATOMS",
                    format!(
                        "column mapping {ours} -> {theirs}: the file has no column \"{theirs}\" \
                         (its columns: {})",
                        names.join(" ")
                    ),
                ));
            }
        }
        let complete = |first: usize, n: usize| (first..first + n).all(|c| index[c].is_some());
        let any = |first: usize, n: usize| (first..first + n).any(|c| index[c].is_some());
        let group_error = |first: usize, n: usize, what: &str| {
            let group = COLUMNS[first..first + n].join(" ");
            let missing = (first..first + n)
                .find(|&c| index[c].is_none())
                .map_or("", |c| COLUMNS[c]);
            err(
                "ITEM: ATOMS",
                format!(
                    "partial {what}: column \"{missing}\" is missing (give all of {group} or none)"
                ),
            )
        };
        let Some(&position) = POSITIONS.iter().find(|(first, _)| complete(*first, 3)) else {
            return Err(err(
                "ITEM: ATOMS",
                format!(
                    "no position columns: need x y z (or xu yu zu, xs ys zs, xsu ysu zsu); the \
                     file has: {}",
                    names.join(" ")
                ),
            ));
        };
        for (first, n, what) in [
            (SHAPE, 3, "shape"),
            (QUAT, 4, "quaternion"),
            (COLOR, 3, "colour"),
        ] {
            if any(first, n) && !complete(first, n) {
                return Err(group_error(first, n, what));
            }
        }
        let shape = complete(SHAPE, 3);
        let sphere = [RADIUS, DIAMETER].into_iter().find(|&c| index[c].is_some());
        if !shape && sphere.is_none() {
            return Err(err(
                "ITEM: ATOMS",
                format!(
                    "no particle size: need shapex shapey shapez (diameters) or radius or \
                     diameter; the file has: {} (a column under another name, such as \
                     c_shape[1], can be mapped with the column mapping option)",
                    names.join(" ")
                ),
            ));
        }
        let mut used = vec![false; COLUMNS.len()];
        used[position.0..position.0 + 3].fill(true);
        used[ID] = true;
        used[TYPE] = true;
        if shape {
            used[SHAPE..SHAPE + 3].fill(true);
        }
        used[QUAT..QUAT + 4].fill(true);
        used[COLOR..COLOR + 3].fill(true);
        if let Some(c) = sphere {
            used[c] = true;
        }
        let mut slots = vec![None; names.len()];
        for c in 0..COLUMNS.len() {
            if let (true, Some(field)) = (used[c], index[c]) {
                if let Some(other) = slots[field] {
                    return Err(err(
                        &names[field],
                        format!(
                            "column \"{}\" is read as both {} and {}",
                            names[field], COLUMNS[other], COLUMNS[c]
                        ),
                    ));
                }
                slots[field] = Some(c);
            }
        }
        let ignored: Vec<String> = names
            .iter()
            .zip(&slots)
            .filter(|(_, s)| s.is_none())
            .map(|(n, _)| n.clone())
            .collect();
        Ok((
            Header {
                slots,
                position,
                shape,
                quaternion: complete(QUAT, 4),
                sphere,
                color: complete(COLOR, 3),
                id: index[ID].is_some(),
                kind: index[TYPE].is_some(),
                line,
                names,
            },
            ignored,
        ))
    }

    /// One atom line as a particle: its ellipsoid, line and id (`ordinal`, 1-based, without
    /// an `id` column).
    fn atom(
        &self,
        text: &[u8],
        line: usize,
        ordinal: usize,
        cell: Option<&Cell>,
        frame: &FrameRef,
        options: &LoadOptions,
    ) -> Result<(ellipsoid_splat::Ellipsoid, u32, i64)> {
        let mut values = [0.0f64; COLUMNS.len()];
        let (mut id, mut kind) = (ordinal as i64, 0i64);
        let mut count = 0;
        for (k, field) in fields(text).enumerate() {
            count = k + 1;
            let Some(slot) = self.slots.get(k) else {
                continue;
            };
            let Some(c) = *slot else {
                continue;
            };
            let at = || format!("{} (field {})", self.names[k], k + 1);
            match c {
                ID => id = integer(field).map_err(|r| frame.error(line, &at(), r))?,
                TYPE => kind = integer(field).map_err(|r| frame.error(line, &at(), r))?,
                _ => values[c] = real(field).map_err(|r| frame.error(line, &at(), r))?,
            }
        }
        if count != self.slots.len() {
            return Err(frame.error(
                line,
                "atom line",
                format!(
                    "wrong number of fields: expected {} (as ITEM: ATOMS on line {}), found {count}",
                    self.slots.len(),
                    self.line
                ),
            ));
        }
        let triple = |c: usize| DVec3::new(values[c], values[c + 1], values[c + 2]);
        let (first, scaled) = self.position;
        let center = match (scaled, cell) {
            (false, _) => triple(first),
            (true, Some(cell)) => cell.point(triple(first)),
            // Checked when the ATOMS item is read.
            (true, None) => triple(first),
        };
        let sphere = self.sphere.map(|c| {
            if c == DIAMETER {
                0.5 * values[c]
            } else {
                values[c]
            }
        });
        let paint = if self.color {
            Paint::Rgb(triple(COLOR).to_array())
        } else if self.kind {
            Paint::Type(kind)
        } else {
            Paint::Shape
        };
        let atom = Atom {
            center,
            // Diameters: halving is exact in binary, so semi-axes written in decimal elsewhere
            // match bit for bit.
            shape: self.shape.then(|| 0.5 * triple(SHAPE)),
            radius: sphere,
            rotation: self.quaternion.then(|| {
                let [w, i, j, k] = [0, 1, 2, 3].map(|n| values[QUAT + n]);
                DQuat::from_xyzw(i, j, k, w)
            }),
            paint,
        };
        let columns = AtomColumns {
            position: match first {
                2 => "x y z",
                5 => "xu yu zu",
                8 => "xs ys zs",
                _ => "xsu ysu zsu",
            },
            shape: "shapex shapey shapez",
            zero_shape: "shapex shapey shapez (a zero shape is a point particle: give it a \
                         radius or diameter column)",
            radius: COLUMNS[self.sphere.unwrap_or(RADIUS)],
            orientation: "quatw quati quatj quatk",
            color: "r g b",
        };
        let built = atom_ellipsoid(&atom, &columns, options, frame, line)?;
        Ok((built, u32::try_from(line).unwrap_or(u32::MAX), id))
    }
}

/// Parses one frame (`bytes` is its range of the file).
pub(crate) fn parse_frame(bytes: &[u8], frame: FrameRef, options: &LoadOptions) -> Result<Loaded> {
    check_mapping_names(options, &COLUMNS, "LAMMPS dump")?;
    let mut lines = Lines::new(bytes, frame.span.line);
    let Some(head) = read_head(&mut lines, &frame, options)? else {
        return Err(no_atoms_item(&frame));
    };
    let atoms = head.count;
    let mut out = head.particles(lines.remaining());
    for ordinal in 1..=atoms {
        let Some((n, text)) = lines.next() else {
            let last = lines.next_line.saturating_sub(1).max(head.atoms_line);
            return Err(truncated(&frame, last, ordinal - 1, atoms));
        };
        let atom = head.atom(text, n, ordinal, &frame, options);
        out.push(atom, None, options.skip_invalid)?;
    }
    read_tail(&mut lines, &frame, atoms)?;
    out.finish(&frame, options)
}

/// A frame's items up to and including `ITEM: ATOMS`: what every atom line is read against.
pub(crate) struct Head {
    /// The number of atom lines (`ITEM: NUMBER OF ATOMS`).
    pub count: usize,
    /// The line of `ITEM: ATOMS`.
    pub atoms_line: usize,
    cell: Option<Cell>,
    header: Header,
    ignored: Vec<String>,
}

impl Head {
    /// An empty collection for the frame's particles, with the notes the header gives;
    /// `remaining` bytes at most follow (a count larger than they can hold reserves nothing
    /// more).
    pub fn particles(&self, remaining: usize) -> FrameParticles {
        // An atom line has at least two bytes.
        let room = self.count.min(remaining / 2);
        let mut out = FrameParticles {
            has_ids: self.header.id,
            ellipsoids: Vec::with_capacity(room),
            origins: Vec::with_capacity(room),
            ..FrameParticles::default()
        };
        if !self.ignored.is_empty() {
            out.notes
                .push(format!("columns not read: {}", self.ignored.join(" ")));
        }
        if self.header.shape && !self.header.quaternion {
            out.notes
                .push("no quatw quati quatj quatk columns: ellipsoids are drawn unrotated".into());
        }
        out
    }

    /// Atom line `text` (line `line`, the `ordinal`-th of the frame, from 1) as a particle.
    pub fn atom(
        &self,
        text: &[u8],
        line: usize,
        ordinal: usize,
        frame: &FrameRef,
        options: &LoadOptions,
    ) -> Result<(ellipsoid_splat::Ellipsoid, u32, i64)> {
        self.header
            .atom(text, line, ordinal, self.cell.as_ref(), frame, options)
    }
}

/// The error for a frame without `ITEM: ATOMS`.
pub(crate) fn no_atoms_item(frame: &FrameRef) -> crate::Error {
    frame.error(
        frame.span.line,
        "ITEM: ATOMS",
        "the frame has no ITEM: ATOMS",
    )
}

/// The error for a frame whose lines end (at line `last`) after `read` of `atoms` atom lines.
pub(crate) fn truncated(frame: &FrameRef, last: usize, read: usize, atoms: usize) -> crate::Error {
    frame.error(
        last,
        "ITEM: ATOMS",
        format!("truncated: the frame ends after {read} of {atoms} atom lines"),
    )
}

/// Whether `line` starts a frame (what [`scan`] looks for).
pub(crate) fn is_timestep_item(line: &[u8]) -> bool {
    // Atom lines start with a digit, a sign or a space: one byte rules most of them out.
    line.first() == Some(&b'I') && line.trim_ascii_end() == b"ITEM: TIMESTEP"
}

/// Whether `line` is the `ITEM: ATOMS` line, where a frame's atom lines begin.
pub(crate) fn is_atoms_item(line: &[u8]) -> bool {
    line.trim_ascii()
        .strip_prefix(b"ITEM:")
        .map(<[u8]>::trim_ascii)
        .is_some_and(|item| {
            item.starts_with(b"ATOMS") && item.get(5).is_none_or(|b| b.is_ascii_whitespace())
        })
}

/// Reads a frame's items up to `ITEM: ATOMS` (skipping those it does not use); `None` when
/// the lines end first.
pub(crate) fn read_head(
    lines: &mut Lines,
    frame: &FrameRef,
    options: &LoadOptions,
) -> Result<Option<Head>> {
    let mut count: Option<(usize, usize)> = None;
    let mut cell: Option<Cell> = None;
    // Inside an item this loader does not read: its values are skipped.
    let mut skipping = false;
    while let Some((number, line)) = lines.next() {
        let trimmed = line.trim_ascii();
        if trimmed.is_empty() {
            continue;
        }
        let Some(item) = trimmed.strip_prefix(b"ITEM:") else {
            if skipping {
                continue;
            }
            let reason = format!("expected an ITEM: line, found \"{}\"", shown(trimmed));
            return Err(frame.error(number, "line", reason));
        };
        let item = item.trim_ascii();
        if !is_atoms_item(trimmed) {
            skipping = read_item(item, number, lines, frame, &mut count, &mut cell)?;
            continue;
        }
        let Some((atoms, _)) = count else {
            return Err(frame.error(
                number,
                "ITEM: ATOMS",
                "ITEM: ATOMS before ITEM: NUMBER OF ATOMS: the number of atom lines is unknown",
            ));
        };
        let (header, ignored) = Header::parse(item, number, frame, options)?;
        if header.position.1 && cell.is_none() {
            return Err(frame.error(
                number,
                "ITEM: ATOMS",
                "scaled coordinates need ITEM: BOX BOUNDS before ITEM: ATOMS",
            ));
        }
        return Ok(Some(Head {
            count: atoms,
            atoms_line: number,
            cell,
            header,
            ignored,
        }));
    }
    Ok(None)
}

/// Reads what follows a frame's atom lines (`atoms` of them): blank lines and items; an atom
/// line too many or a second `ITEM: ATOMS` is an error.
pub(crate) fn read_tail(lines: &mut Lines, frame: &FrameRef, atoms: usize) -> Result<()> {
    let mut count = Some((atoms, 0));
    let mut cell = None;
    let mut skipping = false;
    while let Some((number, line)) = lines.next() {
        let trimmed = line.trim_ascii();
        if trimmed.is_empty() {
            continue;
        }
        let Some(item) = trimmed.strip_prefix(b"ITEM:") else {
            if skipping {
                continue;
            }
            let reason = format!(
                "more atom lines than ITEM: NUMBER OF ATOMS gives ({}): \"{}\"",
                count.map_or(0, |c| c.0),
                shown(trimmed)
            );
            return Err(frame.error(number, "line", reason));
        };
        if is_atoms_item(trimmed) {
            return Err(frame.error(number, "ITEM: ATOMS", "a second ITEM: ATOMS in one frame"));
        }
        skipping = read_item(
            item.trim_ascii(),
            number,
            lines,
            frame,
            &mut count,
            &mut cell,
        )?;
    }
    Ok(())
}

/// Reads an item other than `ITEM: ATOMS` (on line `number`) with its values; whether the
/// lines that follow are its values, to be skipped (an item this loader does not read).
fn read_item(
    item: &[u8],
    number: usize,
    lines: &mut Lines,
    frame: &FrameRef,
    count: &mut Option<(usize, usize)>,
    cell: &mut Option<Cell>,
) -> Result<bool> {
    let mut value_line = |what: &str| {
        lines
            .next()
            .map(|(n, l)| (n, l.trim_ascii()))
            .ok_or_else(|| frame.error(number, what, format!("the frame ends after ITEM: {what}")))
    };
    if item == b"TIMESTEP" {
        let (n, value) = value_line("TIMESTEP")?;
        integer(value).map_err(|r| frame.error(n, "TIMESTEP", r))?;
    } else if item == b"NUMBER OF ATOMS" {
        let (n, value) = value_line("NUMBER OF ATOMS")?;
        let atoms = integer(value)
            .ok()
            .and_then(|v| usize::try_from(v).ok())
            .ok_or_else(|| {
                frame.error(
                    n,
                    "NUMBER OF ATOMS",
                    format!("not a count of atoms: \"{}\"", shown(value)),
                )
            })?;
        *count = Some((atoms, n));
    } else if item.starts_with(b"BOX BOUNDS") {
        *cell = Some(read_box(item, number, lines, frame)?);
    } else {
        // ITEM: UNITS, ITEM: TIME and items of later LAMMPS versions.
        return Ok(true);
    }
    Ok(false)
}

/// The three lines after `ITEM: BOX BOUNDS`, orthogonal or triclinic.
fn read_box(item: &[u8], number: usize, lines: &mut Lines, frame: &FrameRef) -> Result<Cell> {
    let flags: Vec<&[u8]> = fields(item).skip(2).collect();
    let triclinic = flags.len() >= 3 && flags[..3] == [b"xy", b"xz", b"yz"];
    if flags.first() == Some(&&b"abc"[..]) {
        return Err(frame.error(
            number,
            "ITEM: BOX BOUNDS",
            "a general triclinic box (abc origin) is not read: dump it with \
             dump_modify triclinic/general no",
        ));
    }
    let want = if triclinic { 3 } else { 2 };
    let mut rows = [[0.0f64; 3]; 3];
    for (axis, row) in rows.iter_mut().enumerate() {
        let Some((n, text)) = lines.next() else {
            return Err(frame.error(
                number,
                "ITEM: BOX BOUNDS",
                format!("the frame ends after {axis} of 3 bound lines"),
            ));
        };
        let mut found = 0;
        for (k, field) in fields(text).enumerate() {
            found = k + 1;
            if k < want {
                let name = ["lo", "hi", "tilt"][k];
                row[k] = real(field).map_err(|r| {
                    frame.error(
                        n,
                        &format!("BOX BOUNDS {} {name}", ["x", "y", "z"][axis]),
                        r,
                    )
                })?;
            }
        }
        if found != want {
            return Err(frame.error(
                n,
                "BOX BOUNDS",
                format!(
                    "expected {want} numbers ({}), found {found}",
                    if triclinic {
                        "lo_bound hi_bound tilt"
                    } else {
                        "lo hi"
                    }
                ),
            ));
        }
    }
    Ok(if triclinic {
        Cell::triclinic(rows)
    } else {
        Cell::orthogonal(rows.map(|r| [r[0], r[1]]))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triclinic_bounds_give_the_cell() {
        // xlo=0 xhi=10, ylo=0 yhi=8, zlo=0 zhi=6, xy=2 xz=-1 yz=1.5.
        let cell = Cell::triclinic([[-1.0, 12.0, 2.0], [0.0, 9.5, -1.0], [0.0, 6.0, 1.5]]);
        assert_eq!(cell.origin, DVec3::ZERO);
        assert_eq!(cell.a, DVec3::new(10.0, 0.0, 0.0));
        assert_eq!(cell.b, DVec3::new(2.0, 8.0, 0.0));
        assert_eq!(cell.c, DVec3::new(-1.0, 1.5, 6.0));
        assert_eq!(
            cell.point(DVec3::new(0.5, 0.5, 0.5)),
            DVec3::new(5.5, 4.75, 3.0)
        );
    }
}
