//! Reads Ellipsoid CSV: one ellipsoid per row, given by semi-axes and a rotation or by a
//! tensor.
//!
//! UTF-8 text (a leading byte-order mark is skipped), `#` comment lines and blank lines anywhere,
//! one header row, then one row per ellipsoid. Columns are named in the header, in any order
//! (names are case-sensitive):
//!
//! - `x,y,z`: the centre (required);
//! - exactly one shape form: either `rx,ry,rz,qw,qx,qy,qz`, the semi-axes (all > 0) and the
//!   quaternion rotating local axes into world (non-zero; normalised on load), or
//!   `txx,txy,txz,tyy,tyz,tzz`, the upper triangle of the symmetric positive-definite `T` of
//!   `E = {c + T p : |p| = 1}`;
//! - optionally `r,g,b`, all three, each in [0, 1]: the display (sRGB) colour; without them
//!   glyphs are coloured by shape (`ellipsoid_splat::internals::shape_color`).
//!
//! Every rejection is an [`Error::Parse`] naming file, physical line, column and reason
//! (`scene.csv:7:rx: non-positive radius: -0.5 ...`), so a user can go straight to the bad
//! field.

use std::path::Path;

use glam::{DMat3, DQuat, DVec3};

use crate::error::{line_at, parse_error, read_file};
use crate::loaded::{Loaded, Origins};
use crate::options::LoadOptions;
use crate::{Error, Result};
use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat::Scene;

/// Every column the format knows; the groups below are indices into it.
const COLUMNS: [&str; 19] = [
    "x", "y", "z", "rx", "ry", "rz", "qw", "qx", "qy", "qz", "txx", "txy", "txz", "tyy", "tyz",
    "tzz", "r", "g", "b",
];
const CENTER: [usize; 3] = [0, 1, 2];
const RADII: [usize; 3] = [3, 4, 5];
const QUATERNION: [usize; 4] = [6, 7, 8, 9];
const TENSOR: [usize; 6] = [10, 11, 12, 13, 14, 15];
const COLOR: [usize; 3] = [16, 17, 18];

/// Column names of a group joined with commas, for errors about several columns at once.
fn names(group: &[usize]) -> String {
    group
        .iter()
        .map(|&c| COLUMNS[c])
        .collect::<Vec<_>>()
        .join(",")
}

/// Reads and parses an Ellipsoid CSV file.
pub fn load_csv(path: &Path) -> Result<Scene> {
    Ok(load_csv_with(path, &LoadOptions::default())?.scene)
}

/// Reads and parses an Ellipsoid CSV file; with `skip_invalid`, bad data rows are dropped and
/// counted instead of failing (a bad header still fails).
pub fn load_csv_with(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let bytes = read_file(path)?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        let at = e.valid_up_to();
        utf8_error(path, line_at(&bytes, at), at)
    })?;
    parse_rows(text, path, options.skip_invalid)
}

/// The error for bytes that are not UTF-8 from byte `offset` (on `line`) of the file.
pub(crate) fn utf8_error(file: &Path, line: usize, offset: usize) -> Error {
    parse_error(
        file,
        line,
        "text",
        format!("invalid UTF-8 at byte offset {offset}"),
    )
}

/// Ellipsoid CSV of `scene`: semi-axes, rotation and colour, every number written so that it
/// reads back to the same bits; `comments` go first, each as a `#` line. What
/// [`parse_csv`] reads back is the scene.
pub fn csv_text(scene: &Scene, comments: &[String]) -> String {
    let mut text = String::with_capacity(64 + scene.len() * 200);
    for comment in comments {
        for line in comment.lines() {
            text.push_str("# ");
            text.push_str(line);
            text.push('\n');
        }
    }
    text.push_str("x,y,z,rx,ry,rz,qw,qx,qy,qz,r,g,b\n");
    for e in &scene.ellipsoids {
        let (c, r, q) = (e.center, e.radii, e.rotation);
        let [red, green, blue] = e.color;
        text.push_str(&format!(
            "{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?}\n",
            c.x, c.y, c.z, r.x, r.y, r.z, q.w, q.x, q.y, q.z, red, green, blue
        ));
    }
    text
}

/// Writes `scene` as Ellipsoid CSV ([`csv_text`]) to `path`, whole or not at all
/// ([`write_atomically`](crate::write_atomically)).
pub fn save_csv(scene: &Scene, comments: &[String], path: &Path) -> Result<()> {
    let text = csv_text(scene, comments);
    crate::write_atomically(path, |w| std::io::Write::write_all(w, text.as_bytes())).map_err(
        |source| Error::Io {
            path: path.to_path_buf(),
            source,
        },
    )
}

/// Parses Ellipsoid CSV text; `file` is only used to name the source in errors.
pub fn parse_csv(text: &str, file: &Path) -> Result<Scene> {
    Ok(parse_rows(text, file, false)?.scene)
}

/// Parses Ellipsoid CSV text, dropping bad data rows when `skip_invalid`.
fn parse_rows(text: &str, file: &Path, skip_invalid: bool) -> Result<Loaded> {
    // Spreadsheet exports often start with a byte-order mark; it is not part of the first name.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let cleaned = blank_out_comments(text);
    let mut reader = reader(&cleaned);
    let mut records = reader.records();
    let Some(first) = records.next() else {
        return Err(parse_error(
            file,
            0,
            "header",
            "empty file: no header row (only blank or comment lines)",
        ));
    };
    let mut lines = LineCounter::new(&cleaned);
    let first = first.map_err(|e| malformed(file, e))?;
    let header_line = lines.line_of(&first);
    let header = Header::parse(&first, file, header_line)?;
    let rows = read_rows(records, &mut lines, &header, file, skip_invalid)?;
    let first_skipped = rows.first_skipped.map(|e| e.to_string());
    if rows.ellipsoids.is_empty() {
        return Err(no_rows(
            file,
            header_line,
            rows.skipped,
            first_skipped.as_deref(),
        ));
    }
    Ok(Loaded {
        scene: Scene::new(rows.ellipsoids),
        skipped: rows.skipped,
        notes: first_skipped
            .map(|e| vec![skipped_note(rows.skipped, &e)])
            .unwrap_or_default(),
        origins: Origins::Lines(rows.lines),
    })
}

/// The reader of (comment-blanked) Ellipsoid CSV text: no header handling (the header row is
/// checked here), rows of any length (checked here, to name the line), fields trimmed.
pub(crate) fn reader(cleaned: &str) -> ::csv::Reader<&[u8]> {
    ::csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(::csv::Trim::All)
        .from_reader(cleaned.as_bytes())
}

/// The error for text the `csv` reader cannot split into fields.
pub(crate) fn malformed(file: &Path, e: ::csv::Error) -> Error {
    let line = e.position().map_or(0, |p| p.line() as usize);
    parse_error(file, line, "row", format!("malformed CSV: {e}"))
}

/// The data rows read: the glyphs and their lines, and those dropped as invalid.
pub(crate) struct Rows {
    pub ellipsoids: Vec<Ellipsoid>,
    /// The 1-based line of each glyph's row.
    pub lines: Vec<u32>,
    pub skipped: usize,
    pub first_skipped: Option<Error>,
}

/// The data rows of `records` as glyphs, each checked against `header`; `lines` numbers them.
/// With `skip_invalid` a bad row is counted and dropped, else it is the error.
pub(crate) fn read_rows(
    records: impl Iterator<Item = ::csv::Result<::csv::StringRecord>>,
    lines: &mut LineCounter,
    header: &Header,
    file: &Path,
    skip_invalid: bool,
) -> Result<Rows> {
    let mut rows = Rows {
        ellipsoids: Vec::new(),
        lines: Vec::new(),
        skipped: 0,
        first_skipped: None,
    };
    for record in records {
        let row = record.map_err(|e| malformed(file, e)).and_then(|record| {
            let line = lines.line_of(&record);
            Ok((header.ellipsoid(&record, file, line)?, line))
        });
        match row {
            Ok((e, line)) => {
                rows.ellipsoids.push(e);
                rows.lines.push(u32::try_from(line).unwrap_or(u32::MAX));
            }
            Err(e) if skip_invalid => {
                rows.skipped += 1;
                rows.first_skipped.get_or_insert(e);
            }
            Err(e) => return Err(e),
        }
    }
    Ok(rows)
}

/// The error for a file without one valid row: `skipped` were dropped, the first for
/// `first_skipped`.
pub(crate) fn no_rows(
    file: &Path,
    header_line: usize,
    skipped: usize,
    first_skipped: Option<&str>,
) -> Error {
    let reason = match first_skipped {
        Some(e) => format!("no valid rows ({skipped} skipped; the first: {e})"),
        None => "no ellipsoids: the header is not followed by any data rows".into(),
    };
    parse_error(file, header_line, "header", reason)
}

/// The note for `skipped` rows dropped as invalid, the first for `first`.
pub(crate) fn skipped_note(skipped: usize, first: &str) -> String {
    format!("skipped {skipped} invalid row(s); the first: {first}")
}

/// Replaces comment lines and whitespace-only lines by empty lines, which the `csv` reader
/// skips; line breaks stay, so [`LineCounter`] still finds physical lines. (The reader's own
/// comment option only recognises `#` in the very first byte of a line.)
pub(crate) fn blank_out_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let content = line.trim_end_matches(['\n', '\r']);
        let trimmed = content.trim_start();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            out.push_str(&line[content.len()..]);
        } else {
            out.push_str(line);
        }
    }
    out
}

/// Physical line numbers of records. The `csv` reader stamps a record with the position where
/// it started looking, i.e. before the blank lines it skipped, so the record's real first line
/// is found by skipping line terminators from that byte offset.
pub(crate) struct LineCounter<'a> {
    text: &'a [u8],
    /// Byte offset up to which newlines have been counted.
    offset: usize,
    /// Number of `\n` in `text[..offset]`.
    newlines: usize,
}

impl<'a> LineCounter<'a> {
    pub(crate) fn new(text: &'a str) -> Self {
        Self {
            text: text.as_bytes(),
            offset: 0,
            newlines: 0,
        }
    }

    /// 1-based line of `record`; records come in file order, so counting only moves forward.
    pub(crate) fn line_of(&mut self, record: &::csv::StringRecord) -> usize {
        let Some(pos) = record.position() else {
            return 0;
        };
        let mut start = (pos.byte() as usize).clamp(self.offset, self.text.len());
        while start < self.text.len() && matches!(self.text[start], b'\n' | b'\r') {
            start += 1;
        }
        self.newlines += self.text[self.offset..start]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.offset = start;
        self.newlines + 1
    }
}

/// The two ways a row can give the shape.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ShapeForm {
    RadiiQuaternion,
    Tensor,
}

/// What the header says about every data row.
pub(crate) struct Header {
    /// `columns[i]` is the index into [`COLUMNS`] of the row's `i`-th field; its length is the
    /// number of fields every row must have.
    columns: Vec<usize>,
    shape: ShapeForm,
    has_color: bool,
}

impl Header {
    pub(crate) fn parse(record: &::csv::StringRecord, file: &Path, line: usize) -> Result<Self> {
        let err = |column: &str, reason: String| parse_error(file, line, column, reason);
        // `index[c]` is the header position of `COLUMNS[c]`, if present.
        let mut index = [None; COLUMNS.len()];
        let mut columns = Vec::with_capacity(record.len());
        for (pos, name) in record.iter().enumerate() {
            if name.is_empty() {
                return Err(err(
                    &format!("column {}", pos + 1),
                    "empty column name in the header".to_string(),
                ));
            }
            let Some(c) = COLUMNS.iter().position(|&known| known == name) else {
                return Err(err(
                    name,
                    format!(
                        "unknown column \"{name}\" (known columns: {})",
                        COLUMNS.join(",")
                    ),
                ));
            };
            if let Some(before) = index[c] {
                return Err(err(
                    name,
                    format!(
                        "duplicate column \"{name}\" (header fields {} and {})",
                        before + 1,
                        pos + 1
                    ),
                ));
            }
            index[c] = Some(pos);
            columns.push(c);
        }
        let present = |group: &[usize]| group.iter().filter(|&&c| index[c].is_some()).count();
        let first_missing = |group: &[usize]| {
            group
                .iter()
                .find(|&&c| index[c].is_none())
                .map(|&c| COLUMNS[c])
        };
        if let Some(missing) = first_missing(&CENTER) {
            return Err(err(
                missing,
                format!("missing required column \"{missing}\" (the centre needs x,y,z)"),
            ));
        }

        let radii_quat: Vec<usize> = RADII.iter().chain(&QUATERNION).copied().collect();
        let shape = match (present(&radii_quat) > 0, present(&TENSOR) > 0) {
            (true, true) => {
                let first_tensor = TENSOR
                    .iter()
                    .find(|&&c| index[c].is_some())
                    .map_or("txx", |&c| COLUMNS[c]);
                return Err(err(
                    first_tensor,
                    format!(
                        "both shape forms given: use either {} or {}, not both",
                        names(&radii_quat),
                        names(&TENSOR)
                    ),
                ));
            }
            (false, false) => {
                return Err(err(
                    "header",
                    format!(
                        "no shape columns: need either {} or {}",
                        names(&radii_quat),
                        names(&TENSOR)
                    ),
                ));
            }
            (true, false) => ShapeForm::RadiiQuaternion,
            (false, true) => ShapeForm::Tensor,
        };
        let (form, group): (&str, &[usize]) = match shape {
            ShapeForm::RadiiQuaternion => ("radii-and-quaternion", &radii_quat),
            ShapeForm::Tensor => ("tensor", &TENSOR),
        };
        if let Some(missing) = first_missing(group) {
            return Err(err(
                missing,
                format!(
                    "missing required column \"{missing}\" (the {form} shape form needs {})",
                    names(group)
                ),
            ));
        }

        let has_color = match present(&COLOR) {
            0 => false,
            3 => true,
            _ => {
                let missing = first_missing(&COLOR).unwrap_or("r");
                return Err(err(
                    missing,
                    format!(
                        "partial colour: column \"{missing}\" is missing; give all of r,g,b or none"
                    ),
                ));
            }
        };

        Ok(Self {
            columns,
            shape,
            has_color,
        })
    }

    /// One data row as an ellipsoid, with every field checked.
    pub(crate) fn ellipsoid(
        &self,
        record: &::csv::StringRecord,
        file: &Path,
        line: usize,
    ) -> Result<Ellipsoid> {
        let err = |column: &str, reason: String| parse_error(file, line, column, reason);
        if record.len() != self.columns.len() {
            return Err(err(
                "row",
                format!(
                    "wrong number of fields: expected {} (as in the header), found {}",
                    self.columns.len(),
                    record.len()
                ),
            ));
        }
        // Fields are parsed in file order, so the first bad field is the one reported.
        let mut values = [0.0f64; COLUMNS.len()];
        for (text, &c) in record.iter().zip(&self.columns) {
            let name = COLUMNS[c];
            if text.is_empty() {
                return Err(err(name, "empty field, expected a number".to_string()));
            }
            let value: f64 = text
                .parse()
                .map_err(|_| err(name, format!("not a number: \"{text}\"")))?;
            if !value.is_finite() {
                return Err(err(name, format!("non-finite number: \"{text}\"")));
            }
            values[c] = value;
        }

        let vec3 = |g: [usize; 3]| DVec3::new(values[g[0]], values[g[1]], values[g[2]]);
        let center = vec3(CENTER);
        let color = if self.has_color {
            for c in COLOR {
                let v = values[c];
                if !(0.0..=1.0).contains(&v) {
                    return Err(err(
                        COLUMNS[c],
                        format!("colour component out of range [0, 1]: {v}"),
                    ));
                }
            }
            Some(COLOR.map(|c| values[c] as f32))
        } else {
            None
        };

        let (built, shape_columns): (_, &[usize]) = match self.shape {
            ShapeForm::RadiiQuaternion => {
                for c in RADII {
                    let v = values[c];
                    if v <= 0.0 {
                        return Err(err(
                            COLUMNS[c],
                            format!("non-positive radius: {v} (semi-axes must be > 0)"),
                        ));
                    }
                }
                let q = QUATERNION.map(|c| values[c]);
                if q.iter().all(|&v| v == 0.0) {
                    return Err(err(
                        &names(&QUATERNION),
                        "zero quaternion: it must be non-zero to define a rotation".to_string(),
                    ));
                }
                let rotation = DQuat::from_xyzw(q[1], q[2], q[3], q[0]);
                (
                    Ellipsoid::new(center, vec3(RADII), rotation, color),
                    &QUATERNION,
                )
            }
            ShapeForm::Tensor => {
                let [xx, xy, xz, yy, yz, zz] = TENSOR.map(|c| values[c]);
                let t = DMat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz]);
                (Ellipsoid::from_tensor(center, t, color), &TENSOR)
            }
        };
        // Anything `Ellipsoid` still rejects (a near-zero quaternion, an indefinite or
        // overflowing tensor) is reported against the columns that caused it.
        built.map_err(|e| match e {
            ellipsoid_splat::Error::Invalid { what, reason } => {
                let group: &[usize] = match what.as_str() {
                    "ellipsoid radii" => &RADII,
                    "ellipsoid colour" => &COLOR,
                    "ellipsoid centre" => &CENTER,
                    _ => shape_columns,
                };
                err(&names(group), format!("{what} {reason}"))
            }
            other => Error::from(other),
        })
    }
}
