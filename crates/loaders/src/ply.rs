//! Reads 3D Gaussian Splatting scenes: the `.ply` files written by the reference implementation
//! of Kerbl et al. 2023, "3D Gaussian Splatting for Real-Time Radiance Field Rendering".
//!
//! Every record of the `vertex` element is one Gaussian:
//!
//! - `x, y, z`: the centre;
//! - `scale_0..2`: the natural log of the standard deviations along the local axes;
//! - `rot_0..3`: the rotation as an unnormalised quaternion `w, x, y, z`;
//! - `opacity`: a logit, the opacity being its sigmoid;
//! - `f_dc_0..2`: the degree-0 spherical-harmonic coefficients, colour `0.5 + SH_C0 * f_dc`
//!   clamped to [0, 1].
//!
//! Every other property (`nx, ny, nz`, `f_rest_*`, ...) and every other element is skipped,
//! whatever its type. A splat becomes the ellipsoid at [`LoadOptions::sigma`] standard
//! deviations, semi-axes `sigma * exp(scale_i)`; splats less opaque than
//! [`LoadOptions::min_opacity`] are left out.
//!
//! # Design
//!
//! The header goes through `ply-rs-bw`: its grammar checks each header line and its parser builds
//! the element and property definitions. The body does not. `ply-rs-bw` reads every record into
//! a `DefaultElement`, an `IndexMap<String, Property>` with one key `String` per property: 62
//! allocations and map insertions per splat for the reference layout, some 6 KB of heap per
//! splat, so 3 million splats would take some 18 GB that way. On 100,000 reference splats
//! (`examples/ply_body_time.rs`, run by `scripts/ply-body-figure.sh`; 2026-11-27, 2-core
//! Debian 12 at load 9.5, median of 7 interleaved rounds) `ply-rs-bw`'s maps alone took 4.8 s
//! and the whole of this loader 59 ms: 81 times faster (noisy: rerun it on a quiet machine).
//! Binary bodies are therefore read here, each wanted property at a byte offset
//! fixed by the header (records of scalar properties all have the same size), straight into the
//! ellipsoid list; ASCII bodies are read line by line, token by token. Both byte orders are
//! read.
//!
//! # Errors
//!
//! Every rejection is an [`Error::Parse`] naming the file, a line, a column and a reason. In the
//! header, `line` is the physical line. In a binary body it is the 1-based vertex index (the
//! reason says "vertex N"); in an ASCII body it is the physical line (the reason also says which
//! vertex). The column is the property concerned, or `header` / `body`. With
//! [`LoadOptions::skip_invalid`], invalid splats (non-finite numbers, zero quaternions, radii
//! that overflow or underflow, ASCII lines with missing, extra or non-numeric fields) are
//! dropped and counted; a bad header or a truncated body always fails.
//!
//! Nothing is allocated from a count in the header without first checking the body can hold
//! that many records, so arbitrary bytes give an error, never a panic or a huge allocation.

use std::io::Read;
use std::path::Path;

use glam::{DQuat, DVec3};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Encoding, PropertyType, ScalarType};

use crate::error::{io_error, parse_error};
use crate::loaded::{Loaded, Origins};
use crate::options::LoadOptions;
use crate::progress::Progress;
use crate::{Error, Result};
use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat::Scene;

/// `1 / (2 sqrt(pi))`, the degree-0 real spherical harmonic: colour = `0.5 + SH_C0 * f_dc`.
pub const SH_C0: f64 = 0.282_094_791_773_878_14;

/// The `vertex` properties a splat is made of (any other property is skipped).
pub const SPLAT_PROPERTIES: [&str; 14] = [
    "x", "y", "z", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3", "opacity",
    "f_dc_0", "f_dc_1", "f_dc_2",
];
const SCALE: usize = 3;
const ROT: usize = 6;
const OPACITY: usize = 10;
const F_DC: usize = 11;

/// Files at least this large get a progress bar (when asked for).
const LARGE_FILE: u64 = 64 << 20;
/// Bytes read per progress step.
const READ_CHUNK: u64 = 16 << 20;
/// Progress steps while parsing the records.
const PARSE_STEPS: u64 = 50;
/// A header is a few dozen lines; more than this is not a PLY header.
const MAX_HEADER_LINES: usize = 100_000;

/// The scalar type names `ply-rs-bw` knows, for error messages.
const TYPE_NAMES: [&str; 16] = [
    "char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8", "int16",
    "uint16", "int32", "uint32", "float32", "float64",
];
const ENCODINGS: [&str; 3] = ["ascii", "binary_little_endian", "binary_big_endian"];

/// Reads a 3D Gaussian Splatting PLY file (binary little- or big-endian, or ASCII).
///
/// With `options.progress`, files of 64 MiB and more show a progress bar on stderr while they
/// are read and parsed (only when stderr is a terminal). See [`parse_ply`] for the rest.
pub fn load_ply(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let io = io_error(path);
    let mut file = std::fs::File::open(path).map_err(io)?;
    let size = file.metadata().map_err(io)?.len();
    let progress = (options.progress && size >= LARGE_FILE)
        .then(|| Progress::new(size.div_ceil(READ_CHUNK) + PARSE_STEPS, "ply"));
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(usize::try_from(size).unwrap_or(usize::MAX))
        .map_err(|e| {
            io(std::io::Error::new(
                std::io::ErrorKind::OutOfMemory,
                format!("cannot hold the {size}-byte file in memory: {e}"),
            ))
        })?;
    loop {
        let read = (&mut file)
            .take(READ_CHUNK)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if read == 0 {
            break;
        }
        if let Some(p) = &progress {
            p.inc("reading");
        }
    }
    let loaded = parse(&bytes, path, options, progress.as_ref());
    if let Some(p) = &progress {
        p.finish();
    }
    loaded
}

/// Parses the bytes of a 3D Gaussian Splatting PLY file; `file` only names the source in errors.
///
/// Pure and total: any bytes give a scene or an [`Error::Parse`] (an [`Error::Invalid`] for bad
/// `options`), never a panic, an allocation beyond what the bytes can hold, or an endless loop.
/// The notes always state the sigma in effect (`radii = 2 sigma`), and say how many splats the
/// opacity threshold left out, how many invalid ones were skipped, and which other elements
/// were ignored.
pub fn parse_ply(bytes: &[u8], file: &Path, options: &LoadOptions) -> Result<Loaded> {
    parse(bytes, file, options, None)
}

fn parse(
    bytes: &[u8],
    file: &Path,
    options: &LoadOptions,
    progress: Option<&Progress>,
) -> Result<Loaded> {
    check_options(options)?;
    let lines = split_header(bytes, file)?;
    let header = parse_header(&lines, bytes, file)?;
    let body = &bytes[lines.body_start..];
    let body_first_line = lines.lines.len() + 1;

    let vertex_index = header
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| {
            parse_error(
                file,
                lines.lines.len(),
                "header",
                "no `element vertex` in the header: a 3D Gaussian Splatting PLY stores the \
                 splats as vertices",
            )
        })?;
    let vertex = &header.elements[vertex_index];
    let layout = VertexLayout::new(vertex, file)?;

    let mut splats = Splats {
        file,
        sigma: options.sigma,
        min_opacity: options.min_opacity,
        skip_invalid: options.skip_invalid,
        ellipsoids: Vec::new(),
        vertices: Vec::new(),
        skipped: 0,
        first_skipped: None,
        transparent: 0,
    };
    let mut ticker = Ticker::new(progress, vertex.count);
    let trailing = match header.encoding {
        Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => {
            let read = if matches!(header.encoding, Encoding::BinaryBigEndian) {
                read_binary::<true>
            } else {
                read_binary::<false>
            };
            read(
                body,
                &header.elements,
                vertex_index,
                &layout,
                &mut splats,
                &mut ticker,
            )?
        }
        Encoding::Ascii => {
            read_ascii(
                body,
                body_first_line,
                &header.elements,
                vertex_index,
                &layout,
                &mut splats,
                &mut ticker,
            )?;
            0
        }
    };
    splats.finish(vertex, trailing, &header.elements, vertex_index)
}

/// The options splats are read with: a finite positive sigma, an opacity threshold that is a
/// number.
fn check_options(options: &LoadOptions) -> Result<()> {
    if !(options.sigma.is_finite() && options.sigma > 0.0) {
        return Err(Error::invalid(
            "sigma",
            format!("must be finite and > 0, got {}", options.sigma),
        ));
    }
    if options.min_opacity.is_nan() {
        return Err(Error::invalid("min-opacity", "must be a number, got NaN"));
    }
    Ok(())
}

/// The first bytes of `bytes`, printable.
fn preview_bytes(bytes: &[u8]) -> String {
    bytes[..bytes.len().min(24)].escape_ascii().to_string()
}

/// `text` shortened for a message.
fn preview_text(text: &str) -> String {
    const MAX: usize = 60;
    if text.chars().count() <= MAX {
        text.to_string()
    } else {
        format!("{}...", text.chars().take(MAX).collect::<String>())
    }
}

// ---------------------------------------------------------------------------------------------
// Header

/// The header's lines (without terminators, the first being `ply`, the last `end_header`) and
/// where the body starts.
struct HeaderLines<'a> {
    lines: Vec<&'a str>,
    body_start: usize,
}

/// Finds the header's lines up to `end_header`.
fn split_header<'a>(bytes: &'a [u8], file: &Path) -> Result<HeaderLines<'a>> {
    if bytes.is_empty() {
        return Err(parse_error(
            file,
            0,
            "header",
            "empty file: a PLY file starts with the line \"ply\"",
        ));
    }
    let not_ply = || {
        parse_error(
            file,
            1,
            "header",
            format!(
                "not a PLY file: it does not start with the line \"ply\" (first bytes: \"{}\")",
                preview_bytes(bytes)
            ),
        )
    };
    if !bytes.starts_with(b"ply") {
        return Err(not_ply());
    }
    let mut lines = Vec::new();
    let mut pos = 0;
    loop {
        let rest = &bytes[pos..];
        let (raw, next) = match rest.iter().position(|&b| b == b'\n') {
            Some(n) => (&rest[..n], pos + n + 1),
            None => (rest, bytes.len()),
        };
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        let number = lines.len() + 1;
        let Ok(line) = std::str::from_utf8(raw) else {
            if number == 1 {
                return Err(not_ply());
            }
            return Err(parse_error(
                file,
                number,
                "header",
                format!(
                    "header line {number} is not text (invalid UTF-8): is the `end_header` line \
                     missing before a binary body?"
                ),
            ));
        };
        let trimmed = line.trim_end_matches([' ', '\t']);
        if number == 1 && trimmed != "ply" {
            return Err(not_ply());
        }
        lines.push(line);
        if trimmed == "end_header" {
            return Ok(HeaderLines {
                lines,
                body_start: next,
            });
        }
        if next >= bytes.len() {
            return Err(parse_error(
                file,
                number,
                "header",
                format!(
                    "truncated header: the file ends after {number} header line(s) without an \
                     `end_header` line"
                ),
            ));
        }
        if lines.len() >= MAX_HEADER_LINES {
            return Err(parse_error(
                file,
                number,
                "header",
                format!("no `end_header` line in the first {MAX_HEADER_LINES} lines"),
            ));
        }
        pos = next;
    }
}

/// A scalar type of the body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_ply(t: &ScalarType) -> Self {
        match t {
            ScalarType::Char => Self::I8,
            ScalarType::UChar => Self::U8,
            ScalarType::Short => Self::I16,
            ScalarType::UShort => Self::U16,
            ScalarType::Int => Self::I32,
            ScalarType::UInt => Self::U32,
            ScalarType::Float => Self::F32,
            ScalarType::Double => Self::F64,
        }
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

/// A property's type: one scalar, or a list (length type, item type).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List(Scalar, Scalar),
}

impl Kind {
    /// Bytes taken by the smallest possible value (an empty list for lists).
    fn min_size(self) -> usize {
        match self {
            Kind::Scalar(t) | Kind::List(t, _) => t.size(),
        }
    }
}

struct Property {
    name: String,
    kind: Kind,
}

struct Element {
    name: String,
    count: usize,
    /// The header line declaring it.
    line: usize,
    properties: Vec<Property>,
}

impl Element {
    /// Bytes per record when every property is a scalar.
    fn fixed_size(&self) -> Option<usize> {
        self.properties
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(t) => Some(t.size()),
                Kind::List(..) => None,
            })
            .sum()
    }

    /// The property a record cut `into` bytes from its start ends in (for lists, counting
    /// only their length field).
    fn property_at(&self, into: usize) -> &str {
        let mut at = 0;
        let mut property = "";
        for p in &self.properties {
            property = &p.name;
            at += p.kind.min_size();
            if at > into {
                break;
            }
        }
        property
    }
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
}

/// Checks the header lines and builds the element definitions.
///
/// `ply-rs-bw` checks every line against its grammar and builds the definitions; this function
/// adds what its grammar cannot say (duplicate names, which its maps would silently merge, and
/// integer-typed list lengths) and explains rejected lines, since its messages are the raw
/// grammar's.
fn parse_header(lines: &HeaderLines, bytes: &[u8], file: &Path) -> Result<Header> {
    let parser = Parser::<DefaultElement>::new();
    for (i, line) in lines.lines.iter().enumerate().skip(1) {
        if parser.read_header_line(line).is_err() {
            let (column, reason) = explain_header_line(line);
            return Err(parse_error(file, i + 1, column, reason));
        }
    }

    // What the grammar lets through.
    let mut format: Option<(&str, usize)> = None;
    let mut elements: Vec<(&str, usize)> = Vec::new();
    let mut properties: Vec<&str> = Vec::new();
    for (i, line) in lines.lines.iter().enumerate().skip(1) {
        let number = i + 1;
        let tokens: Vec<&str> = line.split_ascii_whitespace().collect();
        let err = |column: &str, reason: String| parse_error(file, number, column, reason);
        match tokens.as_slice() {
            ["ply", ..] => {
                return Err(err(
                    "header",
                    "a second \"ply\" line inside the header".into(),
                ))
            }
            ["format", encoding, ..] => match format {
                Some((first, first_line)) if first != *encoding => {
                    return Err(err(
                        "format",
                        format!(
                            "format \"{encoding}\" contradicts \"{first}\" on line {first_line}"
                        ),
                    ))
                }
                Some(_) => {}
                None => format = Some((encoding, number)),
            },
            ["element", name, count] => {
                if let Some((_, before)) = elements.iter().find(|(n, _)| n == name) {
                    return Err(err(
                        &format!("element {name}"),
                        format!("duplicate element \"{name}\" (first declared on line {before})"),
                    ));
                }
                if count
                    .parse::<u64>()
                    .ok()
                    .and_then(|c| usize::try_from(c).ok())
                    .is_none()
                {
                    return Err(err(
                        &format!("element {name}"),
                        format!("element \"{name}\": count {count} is too large"),
                    ));
                }
                elements.push((name, number));
                properties.clear();
            }
            ["property", .., name] => {
                let Some((element, _)) = elements.last() else {
                    return Err(err(
                        name,
                        format!("property \"{name}\" comes before any `element` line"),
                    ));
                };
                if properties.contains(name) {
                    return Err(err(
                        name,
                        format!("duplicate property \"{name}\" in element \"{element}\""),
                    ));
                }
                if let ["property", "list", count_type, ..] = tokens.as_slice() {
                    if count_type.starts_with("float") || *count_type == "double" {
                        return Err(err(
                            name,
                            format!(
                                "list \"{name}\": the length type must be an integer type, not \
                                 {count_type}"
                            ),
                        ));
                    }
                }
                properties.push(name);
            }
            _ => {}
        }
    }
    if format.is_none() {
        return Err(parse_error(
            file,
            0,
            "format",
            "no `format` line in the header (e.g. `format binary_little_endian 1.0`)",
        ));
    }

    let mut header_bytes = &bytes[..lines.body_start];
    let parsed = parser.read_header(&mut header_bytes).map_err(|e| {
        let message = e.to_string();
        let first = message.lines().next().unwrap_or_default().to_string();
        parse_error(file, 0, "header", format!("invalid header: {first}"))
    })?;
    if parsed.version.major != 1 {
        let line = format.map_or(0, |(_, line)| line);
        return Err(parse_error(
            file,
            line,
            "format",
            format!("unsupported PLY version {} (expected 1.0)", parsed.version),
        ));
    }
    if parsed.elements.len() != elements.len() {
        return Err(parse_error(
            file,
            0,
            "header",
            "invalid header: inconsistent element definitions",
        ));
    }
    let elements = parsed
        .elements
        .values()
        .zip(&elements)
        .map(|(def, &(_, line))| Element {
            name: def.name.clone(),
            count: def.count,
            line,
            properties: def
                .properties
                .values()
                .map(|p| Property {
                    name: p.name.clone(),
                    kind: match &p.data_type {
                        PropertyType::Scalar(t) => Kind::Scalar(Scalar::from_ply(t)),
                        PropertyType::List(count, item) => {
                            Kind::List(Scalar::from_ply(count), Scalar::from_ply(item))
                        }
                    },
                })
                .collect(),
        })
        .collect();
    Ok(Header {
        encoding: parsed.encoding,
        elements,
    })
}

/// Whether `name` is a PLY identifier as `ply-rs-bw` reads them.
fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// Why `ply-rs-bw`'s grammar rejected a header line: `(column, reason)`.
fn explain_header_line(line: &str) -> (String, String) {
    let tokens: Vec<&str> = line.split_ascii_whitespace().collect();
    let shown = preview_text(line);
    let malformed = |column: &str, expected: &str| {
        (
            column.to_string(),
            format!("malformed header line \"{shown}\": expected {expected}"),
        )
    };
    let known_types = TYPE_NAMES.join(", ");
    let unknown_type = |column: &str, t: &str| {
        (
            column.to_string(),
            format!("unknown property type \"{t}\" (known types: {known_types})"),
        )
    };
    match tokens.as_slice() {
        [] => ("header".into(), "blank line in the header".into()),
        ["format", rest @ ..] => {
            const FORM: &str = "`format binary_little_endian 1.0` or `format ascii 1.0`";
            match rest {
                [encoding, ..] if !ENCODINGS.contains(encoding) => (
                    "format".into(),
                    format!(
                        "unknown format \"{encoding}\": expected ascii, binary_little_endian or \
                         binary_big_endian"
                    ),
                ),
                [_, version] => (
                    "format".into(),
                    format!("bad version \"{version}\": expected {FORM}"),
                ),
                _ => malformed("format", FORM),
            }
        }
        ["element", rest @ ..] => match rest {
            [name, _] if !is_identifier(name) => {
                ("element".into(), format!("invalid element name \"{name}\""))
            }
            [name, count] => (
                format!("element {name}"),
                format!("element \"{name}\": count \"{count}\" is not a non-negative integer"),
            ),
            _ => malformed("element", "`element <name> <count>`"),
        },
        ["property", "list", rest @ ..] => match rest {
            [count, item, name] => {
                if !TYPE_NAMES.contains(count) {
                    unknown_type(name, count)
                } else if !TYPE_NAMES.contains(item) {
                    unknown_type(name, item)
                } else {
                    (
                        "property".into(),
                        format!("invalid property name \"{name}\""),
                    )
                }
            }
            _ => malformed(
                "property",
                "`property list <length type> <item type> <name>`",
            ),
        },
        ["property", rest @ ..] => match rest {
            [t, name] if !TYPE_NAMES.contains(t) => unknown_type(name, t),
            [_, name] => (
                "property".into(),
                format!("invalid property name \"{name}\""),
            ),
            _ => malformed("property", "`property <type> <name>`"),
        },
        [keyword @ ("ply" | "end_header" | "comment" | "obj_info"), ..] => {
            malformed("header", &format!("a valid `{keyword}` line"))
        }
        [keyword, ..] => (
            "header".into(),
            format!(
                "unknown header keyword \"{}\" (expected format, comment, obj_info, element, \
                 property or end_header)",
                preview_text(keyword)
            ),
        ),
    }
}

/// Where the splat's properties are among the vertex properties.
struct VertexLayout {
    /// `slot[p]`: which of [`SPLAT_PROPERTIES`] vertex property `p` is, if any.
    slot: Vec<Option<usize>>,
    /// For scalar-only records: the byte offset and type of each of [`SPLAT_PROPERTIES`], and
    /// the record size.
    fixed: Option<([(usize, Scalar); 14], usize)>,
}

impl VertexLayout {
    fn new(vertex: &Element, file: &Path) -> Result<Self> {
        let mut slot = vec![None; vertex.properties.len()];
        let mut types = [Scalar::F32; 14];
        let mut index = [0usize; 14];
        for (field, name) in SPLAT_PROPERTIES.iter().enumerate() {
            let Some(p) = vertex.properties.iter().position(|p| p.name == *name) else {
                return Err(parse_error(
                    file,
                    vertex.line,
                    *name,
                    format!(
                        "missing vertex property \"{name}\": a 3D Gaussian Splatting PLY needs \
                         x, y, z, scale_0..2, rot_0..3, opacity and f_dc_0..2"
                    ),
                ));
            };
            match vertex.properties[p].kind {
                Kind::Scalar(t) => types[field] = t,
                Kind::List(..) => {
                    return Err(parse_error(
                        file,
                        vertex.line,
                        *name,
                        format!("vertex property \"{name}\" must be a scalar, not a list"),
                    ))
                }
            }
            slot[p] = Some(field);
            index[field] = p;
        }
        let fixed = vertex.fixed_size().map(|size| {
            let mut offsets = [0usize; 14];
            let mut at = 0;
            let mut offset_of = vec![0usize; vertex.properties.len()];
            for (p, property) in vertex.properties.iter().enumerate() {
                offset_of[p] = at;
                at += property.kind.min_size();
            }
            for field in 0..14 {
                offsets[field] = offset_of[index[field]];
            }
            (std::array::from_fn(|f| (offsets[f], types[f])), size)
        });
        Ok(Self { slot, fixed })
    }
}

// ---------------------------------------------------------------------------------------------
// Splats

/// Why one record is invalid.
struct RecordError {
    column: String,
    reason: String,
}

fn record_error(column: &str, reason: String) -> RecordError {
    RecordError {
        column: column.to_string(),
        reason,
    }
}

/// The ellipsoid of one splat from its [`SPLAT_PROPERTIES`] values; `None` when it is less
/// opaque than `min_opacity`. Every check is made before the opacity filter, so an invalid
/// record is reported whatever its opacity.
fn splat(
    v: &[f64; 14],
    sigma: f64,
    min_opacity: f64,
) -> std::result::Result<Option<Ellipsoid>, RecordError> {
    for (name, &value) in SPLAT_PROPERTIES.iter().zip(v) {
        if !value.is_finite() {
            return Err(record_error(
                name,
                format!("{name} is not finite ({value})"),
            ));
        }
    }
    let [w, x, y, z] = [v[ROT], v[ROT + 1], v[ROT + 2], v[ROT + 3]];
    // Scaled by the largest component so that the length neither overflows nor underflows.
    let largest = w.abs().max(x.abs()).max(y.abs()).max(z.abs());
    if largest == 0.0 {
        return Err(record_error(
            "rot_0..3",
            "zero quaternion (rot_0..3 all 0) does not define a rotation".into(),
        ));
    }
    let rotation = DQuat::from_xyzw(x / largest, y / largest, z / largest, w / largest);
    let mut radii = [0.0; 3];
    for (i, radius) in radii.iter_mut().enumerate() {
        let scale = v[SCALE + i];
        let r = sigma * scale.exp();
        let name = SPLAT_PROPERTIES[SCALE + i];
        if !r.is_finite() {
            return Err(record_error(
                name,
                format!("radius overflows: {sigma} * exp({name} = {scale}) is not finite"),
            ));
        }
        if r <= 0.0 {
            return Err(record_error(
                name,
                format!("radius underflows: {sigma} * exp({name} = {scale}) is 0"),
            ));
        }
        *radius = r;
    }
    let color = [0, 1, 2].map(|i| (0.5 + SH_C0 * v[F_DC + i]).clamp(0.0, 1.0) as f32);
    let center = DVec3::new(v[0], v[1], v[2]);
    let ellipsoid = Ellipsoid::new(center, DVec3::from_array(radii), rotation, Some(color))
        .map_err(|e| match e {
            ellipsoid_splat::Error::Invalid { what, reason } => {
                let column = match what.as_str() {
                    "ellipsoid radii" => "scale_0..2",
                    "ellipsoid rotation" => "rot_0..3",
                    "ellipsoid colour" => "f_dc_0..2",
                    _ => "x,y,z",
                };
                record_error(column, format!("{what} {reason}"))
            }
            other => record_error("vertex", other.to_string()),
        })?;
    let opacity = 1.0 / (1.0 + (-v[OPACITY]).exp());
    Ok((opacity >= min_opacity).then_some(ellipsoid))
}

/// The splats read so far and what was dropped.
struct Splats<'a> {
    file: &'a Path,
    sigma: f64,
    min_opacity: f64,
    skip_invalid: bool,
    ellipsoids: Vec<Ellipsoid>,
    /// The vertex index of each kept splat.
    vertices: Vec<u32>,
    skipped: usize,
    first_skipped: Option<Error>,
    transparent: usize,
}

impl Splats<'_> {
    /// Adds the splat of `values`; `locate` turns a record error into the error to report.
    #[inline]
    fn add(
        &mut self,
        vertex: usize,
        values: &[f64; 14],
        locate: impl FnOnce(&Path, RecordError) -> Error,
    ) -> Result<()> {
        match splat(values, self.sigma, self.min_opacity) {
            Ok(Some(e)) => {
                self.ellipsoids.push(e);
                self.vertices
                    .push(u32::try_from(vertex).unwrap_or(u32::MAX));
            }
            Ok(None) => self.transparent += 1,
            Err(e) => self.invalid(locate(self.file, e))?,
        }
        Ok(())
    }

    /// An invalid record: skipped and counted, or the error.
    fn invalid(&mut self, error: Error) -> Result<()> {
        if !self.skip_invalid {
            return Err(error);
        }
        self.skipped += 1;
        self.first_skipped.get_or_insert(error);
        Ok(())
    }

    fn finish(
        self,
        vertex: &Element,
        trailing: usize,
        elements: &[Element],
        vertex_index: usize,
    ) -> Result<Loaded> {
        let tally = Tally {
            kept: self.ellipsoids.len(),
            skipped: self.skipped,
            transparent: self.transparent,
            first_skipped: self.first_skipped.map(|e| e.to_string()),
        };
        let options = (self.sigma, self.min_opacity);
        let notes = summary(
            self.file,
            &tally,
            options,
            vertex,
            trailing,
            elements,
            vertex_index,
        )?;
        Ok(Loaded {
            scene: Scene::new(self.ellipsoids),
            skipped: self.skipped,
            notes,
            origins: Origins::Vertices(self.vertices),
        })
    }
}

/// What became of a file's splats: kept, skipped as invalid (the first for
/// `first_skipped`), left out as less opaque than the threshold.
pub(crate) struct Tally {
    pub kept: usize,
    pub skipped: usize,
    pub transparent: usize,
    pub first_skipped: Option<String>,
}

/// The notes of a load that kept what `tally` says, read with `(sigma, min_opacity)`, or the
/// error when it kept nothing.
fn summary(
    file: &Path,
    tally: &Tally,
    (sigma, min_opacity): (f64, f64),
    vertex: &Element,
    trailing: usize,
    elements: &[Element],
    vertex_index: usize,
) -> Result<Vec<String>> {
    let count = vertex.count;
    if tally.kept == 0 {
        let reason = if count == 0 {
            "no splats: the header declares `element vertex 0`".to_string()
        } else if let Some(first) = &tally.first_skipped {
            format!(
                "no valid splats ({} skipped as invalid, {} below --min-opacity; the first \
                 invalid: {first})",
                tally.skipped, tally.transparent
            )
        } else {
            format!("no splats left: all {count} have an opacity below --min-opacity {min_opacity}")
        };
        return Err(parse_error(file, vertex.line, "vertex", reason));
    }
    let mut notes = vec![format!(
        "radii = {sigma} sigma: semi-axes are {sigma} * exp(scale) (--sigma)"
    )];
    if tally.transparent > 0 {
        notes.push(format!(
            "left out {} of {count} splat(s) with opacity below {min_opacity} (--min-opacity)",
            tally.transparent
        ));
    }
    if let Some(first) = &tally.first_skipped {
        notes.push(format!(
            "skipped {} invalid splat(s); the first: {first}",
            tally.skipped
        ));
    }
    for (i, element) in elements.iter().enumerate() {
        if i != vertex_index {
            notes.push(format!(
                "ignored element \"{}\" ({} record(s))",
                element.name, element.count
            ));
        }
    }
    if trailing > 0 {
        notes.push(format!("ignored {trailing} byte(s) after the vertex data"));
    }
    Ok(notes)
}

/// Where the vertex records of a binary file lie when they, and every record before them,
/// have a fixed size: enough to read any range of them without the rest of the file.
pub(crate) struct VertexRecords {
    /// The byte offset of vertex 0 in the file.
    pub offset: u64,
    /// Bytes per vertex record.
    pub stride: usize,
    /// The number of vertices.
    pub count: usize,
    big_endian: bool,
    /// The offset and type of each of [`SPLAT_PROPERTIES`] in a record.
    fields: [(usize, Scalar); 14],
    header: Header,
    vertex_index: usize,
    /// Bytes after the vertex records, when they are the last element (ignored, with a note).
    trailing: usize,
}

/// The vertex records of a binary PLY file of `file_len` bytes whose first bytes are
/// `prefix`: `None` unless the header is complete in `prefix`, valid, and every record up to
/// the vertices' end has a fixed size and is in the file (anything else is read whole, which
/// gives its error or its scene).
pub(crate) fn vertex_records(prefix: &[u8], file_len: u64, file: &Path) -> Option<VertexRecords> {
    let lines = split_header(prefix, file).ok()?;
    let header = parse_header(&lines, prefix, file).ok()?;
    let big_endian = match header.encoding {
        Encoding::BinaryLittleEndian => false,
        Encoding::BinaryBigEndian => true,
        Encoding::Ascii => return None,
    };
    let vertex_index = header.elements.iter().position(|e| e.name == "vertex")?;
    let vertex = &header.elements[vertex_index];
    let (fields, stride) = VertexLayout::new(vertex, file).ok()?.fixed?;
    let mut before = 0u64;
    for element in &header.elements[..vertex_index] {
        let size = element.fixed_size()? as u64;
        before = before.checked_add((element.count as u64).checked_mul(size)?)?;
    }
    let offset = (lines.body_start as u64).checked_add(before)?;
    let end = offset.checked_add((vertex.count as u64).checked_mul(stride as u64)?)?;
    if end > file_len {
        return None;
    }
    let trailing = if vertex_index + 1 == header.elements.len() {
        usize::try_from(file_len - end).ok()?
    } else {
        0
    };
    Some(VertexRecords {
        offset,
        stride,
        count: vertex.count,
        big_endian,
        fields,
        vertex_index,
        trailing,
        header,
    })
}

impl VertexRecords {
    /// The splats of `bytes`, the records of vertices `first`, `first + 1`, ... (each error
    /// names its vertex, as the whole file's load does): the glyphs kept and the tally.
    pub(crate) fn read(
        &self,
        bytes: &[u8],
        first: usize,
        file: &Path,
        options: &LoadOptions,
    ) -> Result<(Vec<Ellipsoid>, Tally)> {
        check_options(options)?;
        let mut splats = Splats {
            file,
            sigma: options.sigma,
            min_opacity: options.min_opacity,
            skip_invalid: options.skip_invalid,
            ellipsoids: Vec::with_capacity(bytes.len() / self.stride),
            vertices: Vec::with_capacity(bytes.len() / self.stride),
            skipped: 0,
            first_skipped: None,
            transparent: 0,
        };
        let read = if self.big_endian {
            read_scalar::<true>
        } else {
            read_scalar::<false>
        };
        for (j, record) in bytes.chunks_exact(self.stride).enumerate() {
            let k = first + j;
            let values: [f64; 14] =
                std::array::from_fn(|f| read(record, self.fields[f].0, self.fields[f].1));
            splats.add(k, &values, |file, e| {
                parse_error(
                    file,
                    k + 1,
                    e.column,
                    format!("vertex {}: {}", k + 1, e.reason),
                )
            })?;
        }
        let tally = Tally {
            kept: splats.ellipsoids.len(),
            skipped: splats.skipped,
            transparent: splats.transparent,
            first_skipped: splats.first_skipped.map(|e| e.to_string()),
        };
        Ok((splats.ellipsoids, tally))
    }

    /// The notes of the whole file's load, or its error, from the tally of every share.
    pub(crate) fn summary(
        &self,
        tally: &Tally,
        file: &Path,
        options: &LoadOptions,
    ) -> Result<Vec<String>> {
        summary(
            file,
            tally,
            (options.sigma, options.min_opacity),
            &self.header.elements[self.vertex_index],
            self.trailing,
            &self.header.elements,
            self.vertex_index,
        )
    }
}

/// Counts records towards a progress bar, [`PARSE_STEPS`] steps in all.
struct Ticker<'a> {
    progress: Option<&'a Progress>,
    every: usize,
    next: usize,
}

impl<'a> Ticker<'a> {
    fn new(progress: Option<&'a Progress>, count: usize) -> Self {
        let every = count.div_ceil(PARSE_STEPS as usize).max(1);
        Self {
            progress,
            every,
            next: if progress.is_some() {
                every
            } else {
                usize::MAX
            },
        }
    }

    /// Called with the number of records done.
    #[inline]
    fn at(&mut self, done: usize) {
        if done >= self.next {
            self.next = self.next.saturating_add(self.every);
            if let Some(p) = self.progress {
                p.inc("parsing");
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Binary bodies

/// Reads a scalar at `at`; the caller has checked `at + t.size() <= b.len()`.
#[inline(always)]
fn read_scalar<const BIG_ENDIAN: bool>(b: &[u8], at: usize, t: Scalar) -> f64 {
    macro_rules! read {
        ($ty:ty, $n:literal) => {{
            let mut a = [0u8; $n];
            a.copy_from_slice(&b[at..at + $n]);
            (if BIG_ENDIAN {
                <$ty>::from_be_bytes(a)
            } else {
                <$ty>::from_le_bytes(a)
            }) as f64
        }};
    }
    match t {
        Scalar::I8 => read!(i8, 1),
        Scalar::U8 => read!(u8, 1),
        Scalar::I16 => read!(i16, 2),
        Scalar::U16 => read!(u16, 2),
        Scalar::I32 => read!(i32, 4),
        Scalar::U32 => read!(u32, 4),
        Scalar::F32 => read!(f32, 4),
        Scalar::F64 => read!(f64, 8),
    }
}

/// Why a binary record could not be walked.
enum Cut {
    /// The body ends inside this property.
    End,
    /// A list length is negative.
    NegativeLength(f64),
}

/// Steps over property `kind` at `pos`, returning the position after it; for a scalar, also
/// reads it.
#[inline]
fn step<const BIG_ENDIAN: bool>(
    body: &[u8],
    pos: usize,
    kind: Kind,
) -> std::result::Result<(usize, f64), Cut> {
    match kind {
        Kind::Scalar(t) => {
            let end = pos.checked_add(t.size()).ok_or(Cut::End)?;
            if end > body.len() {
                return Err(Cut::End);
            }
            Ok((end, read_scalar::<BIG_ENDIAN>(body, pos, t)))
        }
        Kind::List(count_type, item) => {
            let start = pos.checked_add(count_type.size()).ok_or(Cut::End)?;
            if start > body.len() {
                return Err(Cut::End);
            }
            let n = read_scalar::<BIG_ENDIAN>(body, pos, count_type);
            if n < 0.0 {
                return Err(Cut::NegativeLength(n));
            }
            // Integer list lengths are exact in f64 and at most u32::MAX.
            let end = (n as usize)
                .checked_mul(item.size())
                .and_then(|len| start.checked_add(len))
                .ok_or(Cut::End)?;
            if end > body.len() {
                return Err(Cut::End);
            }
            Ok((end, 0.0))
        }
    }
}

/// The error for a binary record that cannot be walked: the body is truncated (or a list
/// length is negative).
fn cut_error(
    file: &Path,
    cut: Cut,
    element: &Element,
    record: usize,
    property: &str,
    body_len: usize,
) -> Error {
    let name = &element.name;
    let count = element.count;
    let what = if name == "vertex" {
        format!("vertex {record}")
    } else {
        format!("element \"{name}\" record {record}")
    };
    match cut {
        Cut::End => parse_error(
            file,
            record,
            property,
            format!(
                "body truncated in {what} of {count}: the file ends inside property \
                 \"{property}\" ({body_len} bytes follow the header)"
            ),
        ),
        Cut::NegativeLength(n) => parse_error(
            file,
            record,
            property,
            format!("{what}: list \"{property}\" has a negative length {n}"),
        ),
    }
}

/// Reads the binary body: skips the elements before the vertices, reads the vertices and
/// returns the number of bytes after them when they are the last element.
fn read_binary<const BIG_ENDIAN: bool>(
    body: &[u8],
    elements: &[Element],
    vertex_index: usize,
    layout: &VertexLayout,
    splats: &mut Splats,
    ticker: &mut Ticker,
) -> Result<usize> {
    let file = splats.file;
    let mut pos = 0;
    for element in &elements[..vertex_index] {
        pos = skip_binary::<BIG_ENDIAN>(body, pos, element, file)?;
    }
    let vertex = &elements[vertex_index];
    let count = vertex.count;
    let locate = |k: usize| {
        move |file: &Path, e: RecordError| {
            parse_error(
                file,
                k + 1,
                e.column,
                format!("vertex {}: {}", k + 1, e.reason),
            )
        }
    };

    if let Some((fields, stride)) = &layout.fixed {
        let stride = *stride;
        let available = body.len() - pos;
        let complete = available / stride;
        if complete < count {
            let property = vertex.property_at(available % stride);
            let needed = count as u128 * stride as u128;
            return Err(parse_error(
                file,
                complete + 1,
                property,
                format!(
                    "body truncated in vertex {} of {count}: the header promises {count} \
                     vertices of {stride} bytes ({needed} bytes) but {available} bytes follow \
                     the header{}; the file ends inside property \"{property}\"",
                    complete + 1,
                    if pos > 0 {
                        " and the elements before the vertices"
                    } else {
                        ""
                    },
                ),
            ));
        }
        let end = pos + count * stride;
        // The origins grow alongside the glyphs.
        splats.ellipsoids.reserve_exact(count);
        splats.vertices.reserve_exact(count);
        for (k, record) in body[pos..end].chunks_exact(stride).enumerate() {
            let values: [f64; 14] = std::array::from_fn(|f| {
                read_scalar::<BIG_ENDIAN>(record, fields[f].0, fields[f].1)
            });
            splats.add(k, &values, locate(k))?;
            ticker.at(k + 1);
        }
        return Ok(if vertex_index + 1 == elements.len() {
            body.len() - end
        } else {
            0
        });
    }

    // Records with list properties: walked property by property.
    let min_record: usize = vertex.properties.iter().map(|p| p.kind.min_size()).sum();
    let at_most = count.min((body.len() - pos) / min_record.max(1));
    splats.ellipsoids.reserve(at_most);
    splats.vertices.reserve(at_most);
    let mut values = [0.0f64; 14];
    for k in 0..count {
        for (p, property) in vertex.properties.iter().enumerate() {
            let (next, value) = step::<BIG_ENDIAN>(body, pos, property.kind)
                .map_err(|cut| cut_error(file, cut, vertex, k + 1, &property.name, body.len()))?;
            if let Some(field) = layout.slot[p] {
                values[field] = value;
            }
            pos = next;
        }
        splats.add(k, &values, locate(k))?;
        ticker.at(k + 1);
    }
    Ok(if vertex_index + 1 == elements.len() {
        body.len() - pos
    } else {
        0
    })
}

/// Steps over every record of a binary element before the vertices.
fn skip_binary<const BIG_ENDIAN: bool>(
    body: &[u8],
    pos: usize,
    element: &Element,
    file: &Path,
) -> Result<usize> {
    if element.properties.is_empty() || element.count == 0 {
        return Ok(pos);
    }
    if let Some(size) = element.fixed_size() {
        let available = body.len() - pos;
        return match element.count.checked_mul(size) {
            Some(len) if len <= available => Ok(pos + len),
            _ => {
                let record = available / size + 1;
                let property = element.property_at(available % size);
                Err(cut_error(
                    file,
                    Cut::End,
                    element,
                    record,
                    property,
                    body.len(),
                ))
            }
        };
    }
    // Every record takes at least one byte, so this loop ends within the body.
    let mut pos = pos;
    for k in 0..element.count {
        for property in &element.properties {
            pos = step::<BIG_ENDIAN>(body, pos, property.kind)
                .map_err(|cut| cut_error(file, cut, element, k + 1, &property.name, body.len()))?
                .0;
        }
    }
    Ok(pos)
}

// ---------------------------------------------------------------------------------------------
// ASCII bodies

/// The lines of a body with their physical line numbers, without terminators.
struct Lines<'a> {
    rest: &'a [u8],
    number: usize,
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(n) => (&self.rest[..n], &self.rest[n + 1..]),
            None => (self.rest, &self.rest[self.rest.len()..]),
        };
        self.rest = rest;
        let number = self.number;
        self.number += 1;
        Some((number, line.strip_suffix(b"\r").unwrap_or(line)))
    }
}

/// Reads the ASCII body: one record per line, fields separated by spaces or tabs.
fn read_ascii(
    body: &[u8],
    first_line: usize,
    elements: &[Element],
    vertex_index: usize,
    layout: &VertexLayout,
    splats: &mut Splats,
    ticker: &mut Ticker,
) -> Result<()> {
    let file = splats.file;
    let mut lines = Lines {
        rest: body,
        number: first_line,
    };
    let truncated = |element: &Element, done: usize, line: usize| {
        parse_error(
            file,
            line,
            "body",
            format!(
                "body truncated: the header promises {} record(s) of element \"{}\" but the \
                 file ends after {done}",
                element.count, element.name
            ),
        )
    };
    for element in &elements[..vertex_index] {
        // Each record is a line, so this loop ends with the body.
        for done in 0..element.count {
            if lines.next().is_none() {
                return Err(truncated(element, done, lines.number));
            }
        }
    }
    let vertex = &elements[vertex_index];
    // A line holds at least one character and a separator per property.
    let min_line = 2 * vertex.properties.len();
    let at_most = vertex.count.min(body.len() / min_line.max(1));
    splats.ellipsoids.reserve(at_most);
    splats.vertices.reserve(at_most);
    for k in 0..vertex.count {
        let Some((number, line)) = lines.next() else {
            return Err(truncated(vertex, k, lines.number));
        };
        let locate = |file: &Path, e: RecordError| {
            parse_error(
                file,
                number,
                e.column,
                format!("vertex {}: {}", k + 1, e.reason),
            )
        };
        match ascii_values(line, vertex, layout) {
            Ok(values) => splats.add(k, &values, locate)?,
            Err(e) => splats.invalid(locate(file, e))?,
        }
        ticker.at(k + 1);
    }
    Ok(())
}

/// The [`SPLAT_PROPERTIES`] values of one ASCII vertex line.
fn ascii_values(
    line: &[u8],
    vertex: &Element,
    layout: &VertexLayout,
) -> std::result::Result<[f64; 14], RecordError> {
    let Ok(text) = std::str::from_utf8(line) else {
        return Err(record_error(
            "line",
            "the line is not text (invalid UTF-8)".into(),
        ));
    };
    let total = || text.split_ascii_whitespace().count();
    let has_lists = layout.fixed.is_none();
    let mut tokens = text.split_ascii_whitespace();
    let mut values = [0.0f64; 14];
    for (p, property) in vertex.properties.iter().enumerate() {
        let name = &property.name;
        let too_few = || {
            let reason = if has_lists {
                format!(
                    "too few fields: the line has {} and ends before property \"{name}\"",
                    total()
                )
            } else {
                format!(
                    "too few fields: found {}, expected {} (missing \"{name}\")",
                    total(),
                    vertex.properties.len()
                )
            };
            record_error(name, reason)
        };
        let token = tokens.next().ok_or_else(too_few)?;
        match property.kind {
            Kind::Scalar(_) => {
                if let Some(field) = layout.slot[p] {
                    values[field] = token.parse().map_err(|_| {
                        record_error(name, format!("not a number: \"{}\"", preview_text(token)))
                    })?;
                }
            }
            Kind::List(..) => {
                let n: usize = token.parse().map_err(|_| {
                    record_error(
                        name,
                        format!(
                            "list length \"{}\" is not a non-negative integer",
                            preview_text(token)
                        ),
                    )
                })?;
                // Ends with the line's tokens, whatever `n`.
                for i in 0..n {
                    if tokens.next().is_none() {
                        return Err(record_error(
                            name,
                            format!(
                                "too few fields: list \"{name}\" declares {n} item(s) but the \
                                 line ends after {i}"
                            ),
                        ));
                    }
                }
            }
        }
    }
    let extra = tokens.count();
    if extra > 0 {
        return Err(record_error(
            "line",
            format!(
                "too many fields: {extra} field(s) after the last property \"{}\"",
                vertex.properties.last().map_or("", |p| p.name.as_str())
            ),
        ));
    }
    Ok(values)
}
