//! LAMMPS dumps and extended XYZ read in shares: frame 1, the frame one process loads. Every
//! process reads the frame's head (the items up to `ITEM: ATOMS`, or the count and comment
//! lines), then the lines that start in its byte range of the rest (`line_ranges`). The
//! processes count their lines to learn each line's place: the first `N` lines (`N` from the
//! head) are the atoms, each read as the whole file's load reads it (errors name the same
//! line); where the atoms take much less than the file (a trajectory), the processes divide
//! the atoms' bytes again so that each has its part. Where a process's LAMMPS atoms end, it
//! reads what follows up to the next frame as the whole load does.
//!
//! Indices are the whole load's: with an `id` column one process sorts the frame by id, so a
//! glyph's index is the number of atoms with smaller ids on every process (`ids`); without
//! one, file order. Species names are numbered by first appearance in that order (`species`).
//! What follows frame 1 is not read (one process's load checks the later frames' structure of
//! an extended XYZ file; here they are left alone), and a head not of the simple kind (no
//! `ITEM: TIMESTEP` first, no `ITEM: ATOMS`) is read whole, which gives its error.

use std::path::Path;

use super::collective::{offset, sum, Collective};
use super::ids::{number_ids, Numbered};
use super::line_ranges::{count_lines, share_of, LineBlock, TextFile};
use super::loaded_share::{check_total, indices, LoadedShare, Split};
use super::species::number_names;
use crate::lammps;
use crate::options::LoadOptions;
use crate::particles::{
    check_mapping_names, duplicate_id, integer, no_particles, skipped_note, type_color,
    FrameParticles, FrameRef, Lines, Span,
};
use crate::xyz;
use crate::{Error, Result};
use ellipsoid_splat::Scene;

/// The two particle formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Particles {
    Lammps,
    Xyz,
}

/// What a frame's head says about its atom lines, as each format reads it.
enum Reader {
    Lammps(lammps::Head),
    Xyz {
        header: xyz::Header,
        ignored: Vec<String>,
    },
}

/// Frame 1's head.
pub(crate) struct FrameHead {
    reader: Reader,
    /// The frame's first line and timestep, which every error names.
    span: Span,
    /// The number of atom lines.
    count: usize,
    /// The byte and the 1-based line where the atom lines begin.
    data_start: u64,
    first_line: usize,
}

impl FrameHead {
    /// Where the atom lines begin, and how many there are.
    pub fn atoms(&self) -> (u64, usize) {
        (self.data_start, self.count)
    }

    fn frame<'a>(&self, file: &'a Path) -> FrameRef<'a> {
        FrameRef {
            file,
            number: 1,
            span: self.span,
        }
    }
}

/// The lines of `bytes` with their byte offsets and 1-based numbers; `\r\n` endings cut.
fn numbered_lines(bytes: &[u8]) -> impl Iterator<Item = (usize, usize, &[u8])> + '_ {
    let mut offset = 0;
    Lines::new(bytes, 1).map(move |(number, line)| {
        let at = offset;
        offset += line.len();
        while offset < bytes.len() && bytes[offset] != b'\n' {
            offset += 1;
        }
        offset = (offset + 1).min(bytes.len());
        (at, number, line)
    })
}

/// The end of frame 1's `ITEM: ATOMS` line in a dump's first bytes `head`, if they hold it
/// (and it ends in `\n`), and whether a `ITEM: TIMESTEP` line comes before it.
fn lammps_atoms_line(head: &[u8]) -> Option<(usize, bool)> {
    let mut timesteps = 0;
    for (at, _, line) in numbered_lines(head) {
        if lammps::is_timestep_item(line) {
            timesteps += 1;
            if timesteps == 2 {
                return None;
            }
        }
        if lammps::is_atoms_item(line) {
            let end = head[at..].iter().position(|&b| b == b'\n')? + at + 1;
            return Some((end, timesteps == 1));
        }
    }
    None
}

/// Frame 1's head of a dump whose first bytes are `head`; `None` unless it is of the simple
/// kind (`ITEM: TIMESTEP` before `ITEM: ATOMS`, both in frame 1).
fn lammps_head(head: &[u8], path: &Path, options: &LoadOptions) -> Result<Option<FrameHead>> {
    let Some((end, true)) = lammps_atoms_line(head) else {
        return Ok(None);
    };
    let bytes = &head[..end];
    // As `lammps::scan` finds it: the line after the first `ITEM: TIMESTEP`.
    let timestep = Lines::new(bytes, 1)
        .skip_while(|(_, l)| l.trim_ascii() != b"ITEM: TIMESTEP")
        .nth(1)
        .and_then(|(_, l)| integer(l.trim_ascii()).ok());
    let span = Span {
        start: 0,
        end,
        line: 1,
        timestep,
    };
    let frame = FrameRef {
        file: path,
        number: 1,
        span,
    };
    check_mapping_names(options, &lammps::COLUMNS, "LAMMPS dump")?;
    let Some(head) = lammps::read_head(&mut Lines::new(bytes, 1), &frame, options)? else {
        return Ok(None);
    };
    Ok(Some(FrameHead {
        count: head.count,
        first_line: head.atoms_line + 1,
        reader: Reader::Lammps(head),
        span,
        data_start: end as u64,
    }))
}

/// The count and comment lines of frame 1 of an extended XYZ file whose first bytes are
/// `head` (after a byte-order mark): each line's offset, number and text, and the end of the
/// comment line; `None` unless `head` holds both, ending in `\n`.
fn xyz_head_lines(head: &[u8]) -> Option<[(usize, usize, &[u8]); 2]> {
    let mut lines = numbered_lines(head).skip_while(|(_, _, l)| l.trim_ascii().is_empty());
    let count = lines.next()?;
    let comment = lines.next()?;
    head[comment.0..]
        .contains(&b'\n')
        .then_some([count, comment])
}

/// The byte-order mark's length at the start of `head`.
fn bom(head: &[u8]) -> usize {
    if head.starts_with(b"\xef\xbb\xbf") {
        3
    } else {
        0
    }
}

/// Frame 1's head of an extended XYZ file whose first bytes are `head`; `None` unless it
/// holds the count and comment lines.
fn xyz_head(head: &[u8], path: &Path, options: &LoadOptions) -> Result<Option<FrameHead>> {
    let skip = bom(head);
    let Some([(_, count_line, count_text), (at, comment_line, comment)]) =
        xyz_head_lines(&head[skip..])
    else {
        return Ok(None);
    };
    let count = xyz::atom_count(count_text.trim_ascii(), count_line, 1, path)?;
    let span = Span {
        start: 0,
        end: 0,
        line: count_line,
        timestep: xyz::comment_timestep(comment),
    };
    let frame = FrameRef {
        file: path,
        number: 1,
        span,
    };
    check_mapping_names(options, &xyz::PROPERTIES, "extended XYZ")?;
    let (header, ignored) = xyz::Header::parse(comment, comment_line, &frame, options)?;
    let end = skip
        + at
        + head[skip + at..]
            .iter()
            .position(|&b| b == b'\n')
            .unwrap_or(0)
        + 1;
    Ok(Some(FrameHead {
        reader: Reader::Xyz { header, ignored },
        span,
        count,
        data_start: end as u64,
        first_line: comment_line + 1,
    }))
}

/// Reads frame 1's head of `file`; `None` where it is not of the simple kind.
pub(crate) fn read_head(
    file: &TextFile,
    path: &Path,
    format: Particles,
    options: &LoadOptions,
) -> Result<Option<FrameHead>> {
    crate::particles::check_options(options)?;
    match format {
        Particles::Lammps => {
            let head = file.head(|h| lammps_atoms_line(h).is_some())?;
            lammps_head(&head, path, options)
        }
        Particles::Xyz => {
            let head = file.head(|h| xyz_head_lines(&h[bom(h)..]).is_some())?;
            xyz_head(&head, path, options)
        }
    }
}

/// Where this process's lines are among the frame's.
struct Placed {
    block: LineBlock,
    /// The 0-based place in the frame of the block's first line.
    first: usize,
    /// How many of the block's lines are atom lines.
    atoms: usize,
}

/// This process's lines of `[a, b)` of `region`, and their count.
fn lines_of(file: &TextFile, region: (u64, u64), c: Collective) -> Result<(LineBlock, usize)> {
    let block = file.lines_starting_in(share_of(region.0, region.1, c.rank(), c.size()), region)?;
    let count = count_lines(&block.bytes);
    Ok((block, count))
}

/// The first `ITEM: TIMESTEP` line of `block`: its place among the block's lines and its
/// byte offset in the file.
fn first_timestep(block: &LineBlock) -> Option<(usize, u64)> {
    numbered_lines(&block.bytes)
        .enumerate()
        .find(|(_, (_, _, line))| lammps::is_timestep_item(line))
        .map(|(k, (at, _, _))| (k, block.start + at as u64))
}

/// The byte offset of line `k` (0-based) of `block`.
fn line_offset(block: &LineBlock, k: usize) -> u64 {
    numbered_lines(&block.bytes)
        .nth(k)
        .map_or(block.start + block.bytes.len() as u64, |(at, _, _)| {
            block.start + at as u64
        })
}

/// Finds this process's atom lines: the frame's lines counted over every process, the frame's
/// end (a dump's next `ITEM: TIMESTEP`), a dump's lines after its atoms read as one process
/// reads them, and the atoms' bytes divided again where they take much less than the file.
/// Also whether the file goes on after frame 1.
fn place_atoms(
    file: &TextFile,
    head: &FrameHead,
    format: Particles,
    path: &Path,
    c: Collective,
) -> Result<(Placed, bool)> {
    let frame = head.frame(path);
    let end = file.len();
    let counted = lines_of(file, (head.data_start, end), c).map(|(block, lines)| {
        let timestep = match format {
            Particles::Lammps => first_timestep(&block),
            Particles::Xyz => None,
        };
        (block, lines, timestep)
    });
    let ((block, lines, _), all) = c.agree(counted, |(_, lines, timestep)| {
        let (k, at) = timestep.unwrap_or((usize::MAX, u64::MAX));
        vec![*lines as u64, k as u64, at]
    })?;
    // The frame ends at the first process's first `ITEM: TIMESTEP` line.
    let next_frame = all.iter().position(|l| l[2] != u64::MAX);
    let frame_end = next_frame.map_or(end, |r| all[r][2]);
    let in_frame = |r: usize| match next_frame {
        Some(t) if r > t => 0,
        Some(t) if r == t => all[r][1],
        _ => all[r][0],
    };
    let frame_lines = (0..c.size()).map(in_frame).sum::<u64>() as usize;
    let atoms = head.count;
    if frame_lines < atoms {
        return Err(match format {
            Particles::Lammps => {
                let last = head.first_line - 1 + frame_lines;
                lammps::truncated(&frame, last, frame_lines, atoms)
            }
            Particles::Xyz => xyz::truncated(
                path,
                head.first_line - 1 + frame_lines,
                1,
                frame_lines,
                atoms,
            ),
        });
    }
    let first = (0..c.rank()).map(in_frame).sum::<u64>() as usize;
    let mine = in_frame(c.rank()) as usize;
    debug_assert!(mine <= lines);
    // The process holding the line after the atoms: where they end, and (a dump) what follows
    // them in the frame, read as one process reads it.
    let holds_end = first <= atoms && atoms < first + mine;
    let after = if holds_end {
        let at = line_offset(&block, atoms - first);
        let tail = match format {
            Particles::Lammps => file.read(at, frame_end).and_then(|tail| {
                let mut lines = Lines::new(&tail, head.first_line + atoms);
                lammps::read_tail(&mut lines, &frame, atoms)
            }),
            Particles::Xyz => Ok(()),
        };
        tail.map(|()| at)
    } else {
        Ok(u64::MAX)
    };
    // Whether a line past the atoms holds anything: the file goes on.
    let more = numbered_lines(&block.bytes)
        .skip(atoms.saturating_sub(first).min(lines))
        .any(|(_, _, line)| !line.trim_ascii().is_empty());
    let (_, ends) = c.agree(after, |&at| vec![at, u64::from(more)])?;
    let atoms_end = ends
        .iter()
        .map(|l| l[0])
        .min()
        .unwrap_or(u64::MAX)
        .min(frame_end);
    let more = next_frame.is_some() || ends.iter().any(|l| l[1] != 0);
    let share = (end - head.data_start) / c.size() as u64;
    if c.size() == 1 || end - atoms_end <= share / 2 {
        let atoms_here = atoms.saturating_sub(first).min(mine);
        return Ok((
            Placed {
                block,
                first,
                atoms: atoms_here,
            },
            more,
        ));
    }
    // The atoms take much less than the file: divide their bytes again.
    drop(block);
    let again = lines_of(file, (head.data_start, atoms_end), c);
    let ((block, lines), all) = c.agree(again, |(_, lines)| vec![*lines as u64])?;
    Ok((
        Placed {
            block,
            first: offset(&all, 0, c.rank()) as usize,
            atoms: lines,
        },
        more,
    ))
}

/// The frame's particles on this process's atom lines, sorted by id where the file has ids;
/// and the species names they refer to (extended XYZ).
fn read_atoms<'a>(
    placed: &'a Placed,
    head: &FrameHead,
    path: &Path,
    options: &LoadOptions,
) -> Result<(FrameParticles, Vec<&'a [u8]>)> {
    let frame = head.frame(path);
    let remaining = placed.block.bytes.len();
    let mut out = match &head.reader {
        Reader::Lammps(h) => h.particles(remaining),
        Reader::Xyz { header, ignored } => {
            header.particles(ignored, placed.atoms.min(remaining / 2))
        }
    };
    let mut names = Vec::new();
    let lines = Lines::new(&placed.block.bytes, 1).take(placed.atoms);
    for (k, (_, text)) in lines.enumerate() {
        let ordinal = placed.first + k;
        let line = head.first_line + ordinal;
        match &head.reader {
            Reader::Lammps(h) => {
                let atom = h.atom(text, line, ordinal + 1, &frame, options);
                out.push(atom, None, options.skip_invalid)?;
            }
            Reader::Xyz { header, .. } => {
                let (atom, name) =
                    header.atom(text, line, ordinal + 1, &mut names, &frame, options);
                out.push(atom, name, options.skip_invalid)?;
            }
        }
    }
    if out.has_ids && !out.origins.windows(2).all(|w| w[0].1 < w[1].1) {
        // Stable: of equal ids (an error, found across processes) the earlier line first.
        let mut order: Vec<usize> = (0..out.origins.len()).collect();
        order.sort_by_key(|&i| out.origins[i].1);
        out.ellipsoids = order.iter().map(|&i| out.ellipsoids[i]).collect();
        out.origins = order.iter().map(|&i| out.origins[i]).collect();
        out.names = order.iter().map(|&i| out.names[i]).collect();
    }
    Ok((out, names))
}

/// The error for atom id `id` given twice: the first two lines bearing it, over every process.
fn duplicate(out: &FrameParticles, id: i64, frame: &FrameRef, c: Collective) -> Result<Error> {
    let mut lines: Vec<u64> = out
        .origins
        .iter()
        .filter(|o| o.1 == id)
        .map(|o| u64::from(o.0))
        .collect();
    lines.sort_unstable();
    lines.resize(2, u64::MAX);
    let all = c.gather(&lines[..2])?;
    let mut every: Vec<u64> = all.into_iter().flatten().collect();
    every.sort_unstable();
    let (first, second) = (every[0] as u32, every[1] as u32);
    Ok(duplicate_id(frame, id, first, second))
}

/// This process's share of frame 1 of the particle file `path`, whose head is `head`.
pub(crate) fn load(
    file: &TextFile,
    head: &FrameHead,
    format: Particles,
    path: &Path,
    options: &LoadOptions,
    c: Collective,
) -> Result<LoadedShare> {
    let frame = head.frame(path);
    let (placed, more) = place_atoms(file, head, format, path, c)?;
    let read = read_atoms(&placed, head, path, options);
    let ((out, names), all) = c.agree(read, |(out, _)| {
        vec![out.ellipsoids.len() as u64, out.skipped as u64]
    })?;
    let (kept, skipped) = (sum(&all, 0), sum(&all, 1));
    let first_skipped = if skipped > 0 {
        c.first_text(out.first_skipped.as_ref().map(|e| e.to_string()).as_deref())?
    } else {
        None
    };
    if kept == 0 {
        return Err(no_particles(
            &frame,
            skipped as usize,
            first_skipped.as_deref(),
        ));
    }
    let mine = out.ellipsoids.len() as u64;
    let global: Vec<u32> = if out.has_ids {
        let ids: Vec<i64> = out.origins.iter().map(|o| o.1).collect();
        match number_ids(&ids, c)? {
            Numbered::Duplicate(id) => return Err(duplicate(&out, id, &frame, c)?),
            Numbered::Indices(at) => {
                check_total(kept)?;
                at.into_iter().map(|i| i as u32).collect()
            }
        }
    } else {
        indices(offset(&all, 0, c.rank()), mine, kept)?
    };
    let mut scene = out.ellipsoids;
    if format == Particles::Xyz {
        let mut first = vec![None; names.len()];
        for (name, &at) in out.names.iter().zip(&global) {
            if let Some(n) = name {
                let slot = &mut first[*n as usize];
                *slot = Some(slot.map_or(u64::from(at), |s: u64| s.min(u64::from(at))));
            }
        }
        let numbers = number_names(&names, &first, c)?;
        for (e, name) in scene.iter_mut().zip(&out.names) {
            if let Some(number) = name.and_then(|n| numbers[n as usize]) {
                e.color = type_color(options, number);
            }
        }
    }
    let mut notes = out.notes;
    if more {
        notes.insert(
            0,
            "frame 1 (the file goes on after it: the processes read frame 1 only)".into(),
        );
    }
    if let Some(e) = first_skipped {
        notes.push(skipped_note(skipped as usize, &e));
    }
    Ok(LoadedShare {
        scene: Scene::new(scene),
        indices: global,
        total: kept,
        skipped,
        notes,
        split: Split::Lines,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_come_with_their_offsets() {
        let lines: Vec<(usize, usize, &[u8])> = numbered_lines(b"ab\r\n\ncd").collect();
        assert_eq!(
            lines,
            vec![(0, 1, &b"ab"[..]), (4, 2, &b""[..]), (5, 3, &b"cd"[..])]
        );
    }

    #[test]
    fn the_atoms_item_ends_the_head() {
        let dump = b"ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x\n1 0\n";
        assert_eq!(lammps_atoms_line(dump), Some((58, true)));
        assert_eq!(lammps_atoms_line(&dump[..50]), None);
        assert_eq!(
            lammps_atoms_line(b"ITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS x\n"),
            Some((38, false))
        );
    }
}
