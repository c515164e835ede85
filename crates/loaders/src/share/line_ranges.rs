//! A text file split between processes at line starts: process `k` of `n` reads the lines that
//! START in byte range `[k L / n, (k + 1) L / n)` of the data section (of `L` bytes), so each
//! line is read by exactly one process, the one where it starts, whatever the cut; reading
//! begins a byte early (to see whether the range starts a line) and runs past the range's end
//! to finish its last line. Line numbers are counted from the file's start only when an error
//! needs one.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use crate::error::io_error;
use crate::{Error, Result};

/// Bytes read at a time past a range's end, to finish its last line, and while counting lines.
const BLOCK: usize = 1 << 20;

/// The first read of a file's head, doubled until the head is complete.
const FIRST_HEAD: usize = 64 << 10;

/// Process `rank`'s share `[a, b)` of `[start, end)`: `size` near-equal parts, in order.
pub(crate) fn share_of(start: u64, end: u64, rank: usize, size: usize) -> (u64, u64) {
    let len = u128::from(end.saturating_sub(start));
    let at = |k: usize| start + (len * k as u128 / size.max(1) as u128) as u64;
    (at(rank), at(rank + 1))
}

/// The number of lines in `bytes` as the loaders count them: each `\n` ends one, and bytes
/// after the last `\n` are one more.
pub(crate) fn count_lines(bytes: &[u8]) -> usize {
    let ends = bytes.iter().filter(|&&b| b == b'\n').count();
    ends + usize::from(bytes.last().is_some_and(|&b| b != b'\n'))
}

/// `error` with its line moved `by` lines on: a line counted in a share is made the file's.
pub(crate) fn shift_line(error: Error, by: usize) -> Error {
    match error {
        Error::Parse {
            file,
            line,
            column,
            reason,
        } if line > 0 => Error::Parse {
            file,
            line: line + by,
            column,
            reason,
        },
        other => other,
    }
}

/// A file opened for reading ranges of it.
pub(crate) struct TextFile {
    file: File,
    path: PathBuf,
    len: u64,
}

/// Lines read from a file: `bytes` start at byte `start` of it, at a line start.
pub(crate) struct LineBlock {
    pub start: u64,
    pub bytes: Vec<u8>,
}

impl TextFile {
    pub fn open(path: &Path) -> Result<Self> {
        let io = io_error(path);
        let file = File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        Ok(Self {
            file,
            path: path.to_path_buf(),
            len,
        })
    }

    /// The file's length in bytes.
    pub fn len(&self) -> u64 {
        self.len
    }

    /// Bytes `[start, end)` (cut at the file's end). Memory that cannot be had is an error
    /// naming the file, not an abort.
    pub fn read(&self, start: u64, end: u64) -> Result<Vec<u8>> {
        let io = io_error(&self.path);
        let end = end.min(self.len);
        let want = usize::try_from(end.saturating_sub(start)).map_err(|_| {
            io(std::io::Error::new(
                std::io::ErrorKind::OutOfMemory,
                format!("bytes {start} to {end} do not fit this machine's address space"),
            ))
        })?;
        let mut bytes = Vec::new();
        bytes.try_reserve_exact(want).map_err(|e| {
            io(std::io::Error::new(
                std::io::ErrorKind::OutOfMemory,
                format!("cannot hold bytes {start} to {end} of the file in memory: {e}"),
            ))
        })?;
        bytes.resize(want, 0);
        // `&File` reads and seeks: one cursor, used by one thread.
        let mut file = &self.file;
        file.seek(SeekFrom::Start(start)).map_err(io)?;
        file.read_exact(&mut bytes).map_err(io)?;
        Ok(bytes)
    }

    /// The file's first bytes, as many as `complete` needs: it says, of a head, whether it
    /// holds all it must (each read doubles the head). The whole file where it never does.
    pub fn head(&self, complete: impl Fn(&[u8]) -> bool) -> Result<Vec<u8>> {
        let mut want = FIRST_HEAD as u64;
        loop {
            let head = self.read(0, want)?;
            if want >= self.len || complete(&head) {
                return Ok(head);
            }
            want = want.saturating_mul(2);
        }
    }

    /// The 1-based line of byte `offset` (read from the file's start, in blocks).
    pub fn line_at(&self, offset: u64) -> Result<usize> {
        let mut newlines = 0;
        let mut at = 0;
        while at < offset {
            let end = offset.min(at + BLOCK as u64);
            newlines += self.read(at, end)?.iter().filter(|&&b| b == b'\n').count();
            at = end;
        }
        Ok(newlines + 1)
    }

    /// The lines of `[region_start, region_end)` that start in `[a, b)` (a range within it;
    /// `region_start` starts a line), whole.
    pub fn lines_starting_in(
        &self,
        (a, b): (u64, u64),
        (region_start, region_end): (u64, u64),
    ) -> Result<LineBlock> {
        let empty = LineBlock {
            start: b,
            bytes: Vec::new(),
        };
        if a >= b {
            return Ok(empty);
        }
        // From a byte early: a line starts at `a` when the byte before it ends one.
        let from = if a > region_start { a - 1 } else { a };
        let mut bytes = self.read(from, b)?;
        let skip = if a > region_start {
            match bytes.iter().position(|&c| c == b'\n') {
                Some(p) => p + 1,
                None => return Ok(empty),
            }
        } else {
            0
        };
        if from + skip as u64 >= b {
            return Ok(empty);
        }
        // The last line started before `b`: read on to its end.
        let mut at = b;
        while bytes.last() != Some(&b'\n') && at < region_end {
            let block = self.read(at, region_end.min(at + BLOCK as u64))?;
            match block.iter().position(|&c| c == b'\n') {
                Some(p) => {
                    bytes.extend_from_slice(&block[..=p]);
                    break;
                }
                None => bytes.extend_from_slice(&block),
            }
            at += block.len() as u64;
        }
        bytes.drain(..skip);
        Ok(LineBlock {
            start: from + skip as u64,
            bytes,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_cover_the_range_in_order() {
        for size in 1..=7 {
            let parts: Vec<(u64, u64)> = (0..size).map(|k| share_of(10, 47, k, size)).collect();
            assert_eq!(parts[0].0, 10);
            assert_eq!(parts[size - 1].1, 47);
            assert!(parts.windows(2).all(|w| w[0].1 == w[1].0));
        }
        assert_eq!(share_of(5, 5, 2, 3), (5, 5));
    }

    /// Every range `[a, b)` of a small file, the region starting after its first line: the
    /// lines read are exactly those starting in the range, whole.
    #[test]
    fn a_range_reads_the_lines_that_start_in_it() {
        let text = b"head\nab\n\ncdef\r\ng\n\nhij";
        let path = std::env::temp_dir().join(format!("line-ranges-{}", std::process::id()));
        std::fs::write(&path, text).unwrap();
        let file = TextFile::open(&path).unwrap();
        let region = (5, text.len() as u64);
        let starts: Vec<u64> = (region.0..region.1)
            .filter(|&p| p == region.0 || text[p as usize - 1] == b'\n')
            .collect();
        for a in region.0..=region.1 {
            for b in a..=region.1 {
                let block = file.lines_starting_in((a, b), region).unwrap();
                let inside: Vec<u64> = starts
                    .iter()
                    .copied()
                    .filter(|&s| a <= s && s < b)
                    .collect();
                let expected = match (inside.first(), inside.last()) {
                    (Some(&first), Some(&last)) => {
                        let end = text[last as usize..]
                            .iter()
                            .position(|&c| c == b'\n')
                            .map_or(text.len(), |p| last as usize + p + 1);
                        &text[first as usize..end]
                    }
                    _ => &b""[..],
                };
                assert_eq!(block.bytes, expected, "[{a}, {b})");
                if !expected.is_empty() {
                    assert_eq!(block.start, inside[0], "[{a}, {b})");
                }
            }
        }
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn lines_are_counted_as_the_loaders_do() {
        assert_eq!(count_lines(b""), 0);
        assert_eq!(count_lines(b"a"), 1);
        assert_eq!(count_lines(b"a\n"), 1);
        assert_eq!(count_lines(b"a\n\nb"), 3);
    }
}
