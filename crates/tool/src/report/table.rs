//! Result tables: aligned plain text for the terminal, Markdown for reports, CSV for machines, and
//! [`fmt_sci`] for compact numbers in all three.
//!
//! Rows are slices of already formatted cells. A column whose cells are all numbers (or empty /
//! `-` / `n/a` placeholders) is right-aligned, every other column left-aligned. Rows may be shorter
//! or longer than the header: the table has as many columns as its widest row and missing cells are
//! empty (CSV is strict instead, see [`write_csv`]).

use std::path::Path;

use crate::error::{Error, Result};

/// Compact scientific notation with up to three significant digits: `4.5e-7`, `1.23e5`, `-2e0`.
///
/// Zero (of either sign) is `0`; infinities are `inf` / `-inf` and NaN is `nan`. Trailing zeros of
/// the mantissa are dropped, and the exponent has no `+` sign or padding.
pub fn fmt_sci(v: f64) -> String {
    fmt_sci_digits(v, 3)
}

/// [`fmt_sci`] with `digits` significant digits (at least 1) before trailing zeros are dropped.
pub(crate) fn fmt_sci_digits(v: f64, digits: usize) -> String {
    if v == 0.0 {
        return "0".to_string();
    }
    if v.is_nan() {
        return "nan".to_string();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.to_string();
    }
    let s = format!("{:.*e}", digits.max(1) - 1, v);
    match s.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            format!("{mantissa}e{exponent}")
        }
        _ => s,
    }
}

/// Whether a cell reads as a number (anything `f64` parses, e.g. `12`, `-3.5e-7`, `inf`, `NaN`,
/// optionally followed by `%`).
fn is_number(cell: &str) -> bool {
    let t = cell.trim();
    let t = t.strip_suffix('%').unwrap_or(t);
    !t.is_empty() && t.parse::<f64>().is_ok()
}

/// Whether a cell stands for "no value" and so does not decide a column's alignment.
fn is_placeholder(cell: &str) -> bool {
    matches!(cell.trim(), "" | "-" | "n/a" | "N/A")
}

/// Per-column layout: display width (in characters) and whether the column is right-aligned.
struct Layout {
    widths: Vec<usize>,
    right: Vec<bool>,
}

/// Measures columns over the header and every row (`escape` is applied to cells first).
fn layout(header: &[String], rows: &[Vec<String>]) -> Layout {
    let columns = rows
        .iter()
        .map(Vec::len)
        .chain([header.len()])
        .max()
        .unwrap_or(0);
    let mut widths = vec![0; columns];
    let mut numbers = vec![0usize; columns];
    let mut others = vec![0usize; columns];
    for (i, cell) in header.iter().enumerate() {
        widths[i] = cell.chars().count();
    }
    for row in rows {
        for (i, cell) in row.iter().enumerate() {
            widths[i] = widths[i].max(cell.chars().count());
            if is_number(cell) {
                numbers[i] += 1;
            } else if !is_placeholder(cell) {
                others[i] += 1;
            }
        }
    }
    let right = (0..columns)
        .map(|i| numbers[i] > 0 && others[i] == 0)
        .collect();
    Layout { widths, right }
}

/// `cell` padded with spaces to `width` characters, on the left when `right` is set.
fn pad(cell: &str, width: usize, right: bool) -> String {
    let fill = " ".repeat(width.saturating_sub(cell.chars().count()));
    if right {
        format!("{fill}{cell}")
    } else {
        format!("{cell}{fill}")
    }
}

/// An aligned plain-text table: header, a dashed rule, then the rows, columns two spaces apart,
/// numeric columns right-aligned. Lines end in `\n` and carry no trailing spaces.
///
/// ```
/// use ellipsoid_splat_tool::report::format_table;
/// let t = format_table(&["scene", "max error"], &[vec!["sphere".into(), "1.3e-7".into()]]);
/// assert_eq!(t, "scene   max error\n------  ---------\nsphere     1.3e-7\n");
/// ```
pub fn format_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let header: Vec<String> = header.iter().map(|h| h.to_string()).collect();
    let l = layout(&header, rows);
    let mut out = String::new();
    let mut line = |cells: &[String]| {
        let text: Vec<String> = (0..l.widths.len())
            .map(|i| {
                let cell = cells.get(i).map(String::as_str).unwrap_or("");
                pad(cell, l.widths[i], l.right[i])
            })
            .collect();
        out.push_str(text.join("  ").trim_end());
        out.push('\n');
    };
    line(&header);
    let rule: Vec<String> = l.widths.iter().map(|&w| "-".repeat(w.max(1))).collect();
    line(&rule);
    for row in rows {
        line(row);
    }
    out
}

/// A GitHub-flavoured Markdown table with padded columns; numeric columns are right-aligned
/// (`---:`). `|` in a cell is escaped as `\|` and line breaks become spaces.
///
/// ```
/// use ellipsoid_splat_tool::report::markdown_table;
/// let t = markdown_table(&["scene", "px"], &[vec!["sphere".into(), "29580".into()]]);
/// assert_eq!(t, "| scene  |    px |\n| ------ | ----: |\n| sphere | 29580 |\n");
/// ```
pub fn markdown_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let escape = |s: &str| s.replace('|', "\\|").replace(['\r', '\n'], " ");
    let header: Vec<String> = header.iter().map(|h| escape(h)).collect();
    let rows: Vec<Vec<String>> = rows
        .iter()
        .map(|r| r.iter().map(|c| escape(c)).collect())
        .collect();
    let mut l = layout(&header, &rows);
    for w in &mut l.widths {
        *w = (*w).max(3); // room for the `---` / `--:` rule
    }
    let mut out = String::new();
    let mut line = |cells: Vec<String>| {
        out.push_str("| ");
        out.push_str(&cells.join(" | "));
        out.push_str(" |\n");
    };
    let cells = |row: &[String]| -> Vec<String> {
        (0..l.widths.len())
            .map(|i| {
                let cell = row.get(i).map(String::as_str).unwrap_or("");
                pad(cell, l.widths[i], l.right[i])
            })
            .collect()
    };
    line(cells(&header));
    line(
        l.widths
            .iter()
            .zip(&l.right)
            .map(|(&w, &right)| {
                if right {
                    format!("{}:", "-".repeat(w - 1))
                } else {
                    "-".repeat(w)
                }
            })
            .collect(),
    );
    for row in &rows {
        line(cells(row));
    }
    out
}

/// Writes an RFC 4180 CSV file (comma-separated, quoted where needed, `\n` line ends): the header
/// row, then `rows`. Every row must have as many cells as the header.
///
/// Failures are [`Error::Io`] naming `path`; a row of the wrong length is reported as an
/// `InvalidData` I/O error.
pub fn write_csv(path: &Path, header: &[&str], rows: &[Vec<String>]) -> Result<()> {
    let io = |source: std::io::Error| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let csv_error = |e: csv::Error| {
        let message = e.to_string();
        match e.into_kind() {
            csv::ErrorKind::Io(source) => io(source),
            _ => io(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                message,
            )),
        }
    };
    // Written whole or not at all (ellipsoid_splat_loaders::write_atomically).
    let mut failed = None;
    let written = ellipsoid_splat_loaders::write_atomically(path, |file| {
        let mut writer = csv::Writer::from_writer(file);
        let mut rows_written = || -> std::result::Result<(), csv::Error> {
            writer.write_record(header)?;
            for row in rows {
                writer.write_record(row)?;
            }
            Ok(())
        };
        if let Err(e) = rows_written() {
            failed = Some(csv_error(e));
            return Err(std::io::Error::other("a row could not be written"));
        }
        writer.flush()
    });
    match (failed, written) {
        (Some(error), _) => Err(error),
        (None, written) => written.map_err(io),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(cells: &[&str]) -> Vec<String> {
        cells.iter().map(|c| c.to_string()).collect()
    }

    #[test]
    fn sci_formatting() {
        assert_eq!(fmt_sci(4.5e-7), "4.5e-7");
        assert_eq!(fmt_sci(0.0), "0");
        assert_eq!(fmt_sci(-0.0), "0");
        assert_eq!(fmt_sci(1.0), "1e0");
        assert_eq!(fmt_sci(-2.0), "-2e0");
        assert_eq!(fmt_sci(123456.0), "1.23e5");
        assert_eq!(fmt_sci(1e-12), "1e-12");
        assert_eq!(fmt_sci(9.999e6), "1e7");
        assert_eq!(fmt_sci(1.05e-3), "1.05e-3");
        assert_eq!(fmt_sci(f64::INFINITY), "inf");
        assert_eq!(fmt_sci(f64::NEG_INFINITY), "-inf");
        assert_eq!(fmt_sci(f64::NAN), "nan");
        assert_eq!(fmt_sci(f64::MIN_POSITIVE), "2.23e-308");
        assert_eq!(fmt_sci_digits(1.000002e6, 7), "1.000002e6");
        assert_eq!(fmt_sci_digits(2.6, 0), "3e0");
    }

    #[test]
    fn table_alignment() {
        let rows = vec![
            strings(&["sphere", "29580", "1.3e-7", "ok"]),
            strings(&["rotated ellipsoid", "5188", "-", "bound broken"]),
            strings(&["random", "35565", "4.8e-6"]),
        ];
        let t = format_table(&["scene", "px", "max", "note"], &rows);
        let expected = "\
scene                 px     max  note
-----------------  -----  ------  ------------
sphere             29580  1.3e-7  ok
rotated ellipsoid   5188       -  bound broken
random             35565  4.8e-6
";
        assert_eq!(t, expected);
        // The rule spans the full width of a row that fills every column.
        let widths: Vec<usize> = t.lines().map(|l| l.chars().count()).collect();
        assert_eq!(widths[1], widths[3]);
    }

    #[test]
    fn table_edge_cases() {
        assert_eq!(format_table(&[], &[]), "\n\n");
        // Unicode widths count characters, extra cells get a column, percentages are numbers.
        let t = format_table(&["é", "share"], &[strings(&["ü", "50%", "x"])]);
        assert_eq!(t, "é  share\n-  -----  -\nü    50%  x\n");
    }

    #[test]
    fn markdown() {
        let rows = vec![strings(&["a|b", "1.5"]), strings(&["c", "nan"])];
        let t = markdown_table(&["name", "value"], &rows);
        let expected = "\
| name | value |
| ---- | ----: |
| a\\|b |   1.5 |
| c    |   nan |
";
        assert_eq!(t, expected);
    }

    #[test]
    fn csv_round_trip() {
        let dir =
            std::env::temp_dir().join(format!("ellipsoid-splat-table-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("round_trip.csv");
        let header = ["name", "error", "note"];
        let rows = vec![
            strings(&["sphere", "1.3e-7", "plain"]),
            strings(&["with, comma", "-4.5e-7", "quote \" and\nnewline"]),
        ];
        write_csv(&path, &header, &rows).unwrap();
        let mut reader = csv::Reader::from_path(&path).unwrap();
        assert_eq!(
            reader.headers().unwrap(),
            &csv::StringRecord::from(header.to_vec())
        );
        let back: Vec<Vec<String>> = reader
            .records()
            .map(|r| r.unwrap().iter().map(str::to_string).collect())
            .collect();
        assert_eq!(back, rows);

        let bad = write_csv(&path, &header, &[strings(&["short"])]).unwrap_err();
        assert!(matches!(bad, Error::Io { .. }), "{bad}");
        let missing = dir.join("no/such/dir/x.csv");
        let err = write_csv(&missing, &header, &rows).unwrap_err();
        assert!(err.to_string().contains("x.csv"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
