//! Ellipsoid CSV read in shares: every process reads the header row, then the rows that start
//! in its byte range of the rest (`line_ranges`), each checked as the whole file's load checks
//! it. A glyph's index is its place among the valid rows of the whole file: the counts of the
//! processes before this one, plus its place here. A row must lie on one line (a quoted field
//! running over a line's end is refused), since the file is cut at line starts.

use std::path::Path;

use super::collective::{offset, sum, Collective};
use super::line_ranges::{share_of, shift_line, LineBlock, TextFile};
use super::loaded_share::{indices, LoadedShare, Split};
use crate::csv::{self, blank_out_comments, read_rows, Header, LineCounter};
use crate::error::{line_at, parse_error};
use crate::options::LoadOptions;
use crate::Result;
use ellipsoid_splat::{Ellipsoid, Scene};

/// The header row: what it says and where the data rows begin.
pub(crate) struct CsvHead {
    header: Header,
    /// The header's 1-based line.
    line: usize,
    /// The byte after the header's line.
    data_start: u64,
}

impl CsvHead {
    /// The byte after the header's line.
    pub fn data_start(&self) -> u64 {
        self.data_start
    }
}

/// The glyphs of this process's rows and those dropped.
struct ShareRows {
    ellipsoids: Vec<Ellipsoid>,
    skipped: usize,
    /// The first row dropped, its line counted from the share's start.
    first_skipped: Option<crate::Error>,
    /// Where the share starts in the file.
    start: u64,
}

/// The header row of a file whose first bytes are `head`: its start, 1-based line and end
/// (the byte after its `\n`, `None` when `head` ends inside it); `None` when `head` holds no
/// row (only blank and comment lines).
fn header_line(head: &[u8]) -> Option<(usize, usize, Option<usize>)> {
    let bom = if head.starts_with("\u{feff}".as_bytes()) {
        3
    } else {
        0
    };
    let mut start = bom;
    let mut line = 1;
    while start < head.len() {
        let rest = &head[start..];
        let end = rest.iter().position(|&b| b == b'\n').map(|p| start + p + 1);
        let content = &head[start..end.map_or(head.len(), |e| e - 1)];
        // As `blank_out_comments` decides (a line not UTF-8 is no comment: it is the row).
        let blank = std::str::from_utf8(content).is_ok_and(|text| {
            let trimmed = text.trim_end_matches(['\n', '\r']).trim_start();
            trimmed.is_empty() || trimmed.starts_with('#')
        });
        if !blank {
            return Some((start, line, end));
        }
        match end {
            Some(end) => start = end,
            None => break,
        }
        line += 1;
    }
    None
}

/// Whether some line of `text` holds an odd number of quotes: a quoted field running on over
/// its end; its 1-based line in `text`, if so.
fn line_running_on(text: &str) -> Option<usize> {
    text.split('\n')
        .position(|line| line.bytes().filter(|&b| b == b'"').count() % 2 == 1)
        .map(|k| k + 1)
}

/// The error for a row (on `line`) whose quoted field runs over the line's end.
fn running_on(file: &Path, line: usize) -> crate::Error {
    parse_error(
        file,
        line,
        "row",
        "a quoted field runs on past the end of its line: a file read in shares is cut at line \
         starts, so each row must lie on one line (read the file with one process)",
    )
}

/// Reads the header row of `file`; `None` when the file has none (read whole, that gives its
/// error).
pub(crate) fn read_head(file: &TextFile, path: &Path) -> Result<Option<CsvHead>> {
    let head = file.head(|h| header_line(h).is_some_and(|(_, _, end)| end.is_some()))?;
    let Some((start, line, end)) = header_line(&head) else {
        return Ok(None);
    };
    let end = end.unwrap_or(head.len());
    let text = std::str::from_utf8(&head[..end])
        .map_err(|e| csv::utf8_error(path, line_at(&head, e.valid_up_to()), e.valid_up_to()))?;
    let row = &text[start..];
    let cleaned = blank_out_comments(row);
    if line_running_on(&cleaned).is_some() {
        return Err(running_on(path, line));
    }
    let Some(record) = csv::reader(&cleaned).records().next() else {
        return Ok(None);
    };
    let record = record.map_err(|e| shift_line(csv::malformed(path, e), line - 1))?;
    Ok(Some(CsvHead {
        header: Header::parse(&record, path, line)?,
        line,
        data_start: end as u64,
    }))
}

/// This process's rows: those starting in its byte range of the data.
fn read_rows_of(
    file: &TextFile,
    head: &CsvHead,
    path: &Path,
    options: &LoadOptions,
    c: Collective,
) -> Result<ShareRows> {
    let region = (head.data_start, file.len());
    let block = file.lines_starting_in(share_of(region.0, region.1, c.rank(), c.size()), region)?;
    let LineBlock { start, bytes } = &block;
    // Lines are counted from the file's start only for an error.
    let lines_before = || file.line_at(*start).map(|line| line - 1);
    let text = match std::str::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => {
            let at = e.valid_up_to();
            let line = lines_before()? + line_at(bytes, at);
            return Err(csv::utf8_error(path, line, *start as usize + at));
        }
    };
    let cleaned = blank_out_comments(text);
    if let Some(line) = line_running_on(&cleaned) {
        return Err(running_on(path, lines_before()? + line));
    }
    let mut reader = csv::reader(&cleaned);
    let mut lines = LineCounter::new(&cleaned);
    let rows = match read_rows(
        reader.records(),
        &mut lines,
        &head.header,
        path,
        options.skip_invalid,
    ) {
        Ok(rows) => rows,
        Err(e) => return Err(shift_line(e, lines_before()?)),
    };
    Ok(ShareRows {
        ellipsoids: rows.ellipsoids,
        skipped: rows.skipped,
        first_skipped: rows.first_skipped,
        start: *start,
    })
}

/// This process's share of the Ellipsoid CSV `path`, whose header row is `head`.
pub(crate) fn load(
    file: &TextFile,
    head: &CsvHead,
    path: &Path,
    options: &LoadOptions,
    c: Collective,
) -> Result<LoadedShare> {
    let rows = read_rows_of(file, head, path, options, c);
    let (rows, all) = c.agree(rows, |r| vec![r.ellipsoids.len() as u64, r.skipped as u64])?;
    let (kept, skipped) = (sum(&all, 0), sum(&all, 1));
    let first_skipped = if skipped > 0 {
        // The file's first skipped row is the first process's with one: only that process
        // counts the lines before its share.
        let first = all.iter().position(|l| l[1] > 0) == Some(c.rank());
        let text = match rows.first_skipped {
            Some(e) if first => file
                .line_at(rows.start)
                .map(|line| Some(shift_line(e, line - 1))),
            _ => Ok(None),
        };
        let (text, _) = c.agree(text, |_| Vec::new())?;
        c.first_text(text.map(|e| e.to_string()).as_deref())?
    } else {
        None
    };
    if kept == 0 {
        return Err(csv::no_rows(
            path,
            head.line,
            skipped as usize,
            first_skipped.as_deref(),
        ));
    }
    let mine = rows.ellipsoids.len() as u64;
    Ok(LoadedShare {
        indices: indices(offset(&all, 0, c.rank()), mine, kept)?,
        scene: Scene::new(rows.ellipsoids),
        total: kept,
        skipped,
        notes: first_skipped
            .map(|e| vec![csv::skipped_note(skipped as usize, &e)])
            .unwrap_or_default(),
        split: Split::Lines,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_row_follows_blank_and_comment_lines() {
        assert_eq!(header_line(b"x,y\n1,2\n"), Some((0, 1, Some(4))));
        assert_eq!(
            header_line(b"\xef\xbb\xbf# c\n\n  \r\nx,y"),
            Some((12, 4, None))
        );
        assert_eq!(header_line(b"# only\n\n"), None);
    }

    #[test]
    fn odd_quotes_are_found() {
        assert_eq!(line_running_on("a,\"b\"\n\"c\n"), Some(2));
        assert_eq!(line_running_on("\"a\"\"b\",c\n"), None);
    }
}
