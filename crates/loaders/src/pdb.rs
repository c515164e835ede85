//! Reads crystallographic thermal ellipsoids from PDB and mmCIF files.
//!
//! # What is drawn
//!
//! Every atom with an anisotropic displacement tensor `U` (in Å², in the Cartesian axes of the
//! coordinate frame) becomes its 50 % probability ellipsoid, the ORTEP convention: centred on
//! the atom, with semi-axes `c * sqrt(lambda_i)` along the eigenvectors of `U`, where
//! `c^2 = 2.3660` is the median of the chi-square distribution with 3 degrees of freedom
//! (`c = 1.5382`, [`PROBABILITY_50_SCALE`]). In the terms of [`Ellipsoid`] the surface is
//! `{x + M p : |p| = 1}` with `M M^T = c^2 U`.
//!
//! [`Ellipsoid::from_tensor`] would need `M = c U^(1/2)` (its semi-axes are the eigenvalues
//! of what it is given), not `U`; so `U` is eigen-decomposed once here
//! ([`symmetric_eigen`]) and the ellipsoid built with [`Ellipsoid::new`].
//!
//! Atoms without anisotropic parameters (typically riding hydrogens, waters and whole
//! structures refined isotropically) are **left out** and counted in a note. They are not drawn
//! as spheres from their isotropic B: in a thermal-ellipsoid plot every glyph should be a
//! refined anisotropic displacement, and spheres made from B (which also absorbs disorder and
//! restraints) would look like data of the same kind. A file without any anisotropic atom is
//! an error. Glyphs are coloured by element, see [`element_color`].
//!
//! Only the first model is drawn (NMR ensembles and multi-model files are noted). Alternate
//! conformations are all drawn, as ORTEP does.
//!
//! # What is read
//!
//! * **PDB**: `ATOM`/`HETATM` (coordinates in columns 31-54, element in 77-78, else inferred
//!   from the atom name in 13-14) and `ANISOU` (`U11 U22 U33 U12 U13 U23` as integers of
//!   10^-4 Å² in columns 29-70). An `ANISOU` belongs to the `ATOM`/`HETATM` of the same model
//!   with the same columns 7-27 (serial, name, alternate location, residue, chain, sequence
//!   number, insertion code); a record whose serial matches but whose other identifiers differ
//!   only in spacing is accepted too. Records may come in any order. An `ANISOU` that matches
//!   no atom (of the first model) is an invalid record, reported on its line like any other
//!   (see below).
//! * **mmCIF**: the `_atom_site` category (`Cartn_x/y/z`, `type_symbol`, identifiers,
//!   `pdbx_PDB_model_num`, and optionally `aniso_U[i][j]` or `aniso_B[i][j]` inline) and the
//!   `_atom_site_anisotrop` category (`id` matching `_atom_site.id`, `U[i][j]` in Å² or
//!   `B[i][j] = 8 pi^2 U[i][j]`), as loops or single items. Standard uncertainties such as
//!   `0.0234(12)` are accepted; `?` and `.` mean "no value". Only the first data block is read.
//!   Small-molecule coreCIF (`_atom_site_aniso_U_11` in crystal axes) is rejected with a clear
//!   message, since it needs the unit cell to become Cartesian.
//!
//! # Why not pdbtbx's readers
//!
//! The `pdbtbx` crate (0.12) is used for its element table ([`pdbtbx::Element`]), but not for
//! reading the files, because on the inputs this loader must report precisely it either panics
//! or loses the record (checked against 0.12.0 in any `StrictnessLevel`):
//!
//! * its PDB reader panics on a non-finite coordinate (`Atom::new(..).expect(..)`), on an
//!   unknown `CRYST1` space group (`panic!("Invalid space group")`), and can panic by slicing a
//!   non-ASCII line at a byte that is not a character boundary;
//! * an `ANISOU` without a matching atom is dropped with a message on stderr, and the caller
//!   is not told (here it is an [`Error::Parse`] on the `ANISOU`'s line; with
//!   [`LoadOptions::skip_invalid`] it is counted and named in the notes);
//! * its mmCIF reader panics (`expect`) on a `?` in a required `_atom_site` column (element,
//!   coordinates) and on a `nan` coordinate, and locates value errors by "row N" of a loop
//!   rather than by line.
//!
//! The test `pdbtbx_readers_panic_or_lose_the_line_where_this_one_reports_it` feeds such
//! inputs to pdbtbx inside `catch_unwind` at each `StrictnessLevel`, and fails when pdbtbx no
//! longer panics or starts reporting the stray `ANISOU`.
//!
//! A `catch_unwind` around it would still leave errors without line numbers, so both dialects
//! are read here: the PDB records needed are fixed-column lines, and the mmCIF subset is a
//! small STAR tokenizer (quoted strings, `;` text fields, comments, loops, save frames). With
//! no pdbtbx reader there is no `StrictnessLevel` to choose: strictness is decided here instead.
//! Records this loader does not use (`HEADER`, `CRYST1`, `REMARK`, other mmCIF categories) are
//! not validated, so real files with harmless quirks load; every record that is used is
//! validated, and a bad one is an [`Error::Parse`] naming the file, line, field and atom.
//! With [`LoadOptions::skip_invalid`] a bad record (and only that atom, or that stray `ANISOU`
//! or `_atom_site_anisotrop` row) is dropped and counted, and the notes name the first one;
//! damage to the file's structure (binary data, a truncated loop, a missing coordinate column)
//! is always an error.
//!
//! Reading never panics and is linear in the input: every loop advances through the bytes.
//! [`LoadOptions::progress`] is not used: these files are read in one pass in well under a
//! second.

use std::collections::HashMap;
use std::path::Path;

use glam::{DMat3, DQuat, DVec3};

use crate::error::{line_at, parse_error, read_file};
use crate::loaded::{Loaded, Origins};
use crate::options::LoadOptions;
use crate::{Error, Result};
use ellipsoid_splat::Scene;
use ellipsoid_splat::{internals::symmetric_eigen, Ellipsoid};

/// The ellipsoid scale `c` of 50 % probability ellipsoids: `c^2 = 2.365_973_884_375_338` is the
/// median of the chi-square distribution with 3 degrees of freedom, so that an atom is inside
/// its ellipsoid `{x : x^T U^-1 x <= c^2}` half of the time.
pub const PROBABILITY_50_SCALE: f64 = 1.538_172_254_455_052_2;

/// A `U` whose smallest eigenvalue is at most this fraction of its largest is not positive
/// definite: the margin keeps rounding in the eigen-decomposition from passing a singular `U`.
const DEFINITE_TOLERANCE: f64 = 1e-12;

/// Reads a PDB or mmCIF file and returns its 50 % probability thermal ellipsoids.
///
/// The dialect is mmCIF for a `.cif` or `.mmcif` extension or text starting with `data_`,
/// PDB otherwise (see [`parse_structure`]).
pub fn load_structure(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    parse_structure(&read_file(path)?, path, options)
}

/// Parses PDB or mmCIF `bytes` into 50 % probability thermal ellipsoids (see the module
/// documentation); `file` names the source in errors and its extension may pick the dialect:
/// `.cif` and `.mmcif` are mmCIF, as is text whose first content is a `data_` block header;
/// anything else is read as PDB.
///
/// Every rejection is an [`Error::Parse`] with the file, the 1-based line (0 when not tied to
/// a line), the field and the reason, naming the atom (serial, name, residue) when there is
/// one. Any bytes are accepted without panicking.
pub fn parse_structure(bytes: &[u8], file: &Path, options: &LoadOptions) -> Result<Loaded> {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    check_text(bytes).map_err(|issue| issue.into_error(file))?;
    let structure = if is_mmcif(bytes, file) {
        read_mmcif(bytes)
    } else {
        Ok(read_pdb(bytes))
    }
    .map_err(|issue| issue.into_error(file))?;
    build(structure, file, options)
}

/// The display colour (sRGB, in [0, 1]) of an element, after the CPK colours as Jmol draws
/// them. `symbol` is an element symbol in any case (`"C"`, `"FE"`, `"Fe"`); trailing charges or
/// digits (`"O1-"`) are ignored.
///
/// | element | colour |
/// |---|---|
/// | H | white |
/// | C | grey |
/// | N | blue |
/// | O | red |
/// | S | yellow |
/// | P | orange |
/// | Se | dark orange |
/// | F, Cl | green, light green |
/// | Br | dark red |
/// | I | violet |
/// | B | salmon |
/// | Na, K | violet, purple |
/// | Mg, Ca | yellow-green, green |
/// | Mn, Fe, Co, Ni, Cu, Zn | lilac, rust, pink, green, copper, slate blue |
/// | any other metal | pale purple `(0.75, 0.60, 0.90)` |
/// | any other non-metal or metalloid | pale pink `(1.00, 0.60, 0.75)` |
/// | unknown symbol | deep pink `(1.00, 0.08, 0.58)` |
pub fn element_color(symbol: &str) -> [f32; 3] {
    let letters: String = symbol
        .trim()
        .chars()
        .take_while(char::is_ascii_alphabetic)
        .take(3)
        .collect();
    let Some(element) = pdbtbx::Element::from_symbol(&letters) else {
        return [1.00, 0.08, 0.58];
    };
    match element.symbol() {
        "H" => [1.00, 1.00, 1.00],
        "C" => [0.50, 0.50, 0.50],
        "N" => [0.19, 0.31, 0.97],
        "O" => [0.94, 0.05, 0.05],
        "S" => [1.00, 0.85, 0.20],
        "P" => [1.00, 0.50, 0.00],
        "SE" => [1.00, 0.63, 0.00],
        "F" => [0.56, 0.88, 0.31],
        "CL" => [0.12, 0.94, 0.12],
        "BR" => [0.65, 0.16, 0.16],
        "I" => [0.58, 0.00, 0.58],
        "B" => [1.00, 0.71, 0.71],
        "NA" => [0.67, 0.36, 0.95],
        "K" => [0.56, 0.25, 0.83],
        "MG" => [0.54, 1.00, 0.00],
        "CA" => [0.24, 1.00, 0.00],
        "MN" => [0.61, 0.48, 0.78],
        "FE" => [0.88, 0.40, 0.20],
        "CO" => [0.94, 0.56, 0.63],
        "NI" => [0.31, 0.82, 0.31],
        "CU" => [0.78, 0.50, 0.20],
        "ZN" => [0.49, 0.50, 0.69],
        _ if is_nonmetal(element.atomic_number()) => [1.00, 0.60, 0.75],
        _ => [0.75, 0.60, 0.90],
    }
}

/// Non-metals, noble gases and metalloids by atomic number; every other element is a metal.
fn is_nonmetal(z: usize) -> bool {
    matches!(
        z,
        1 | 2 | 5..=10 | 14..=18 | 32..=36 | 51..=54 | 85 | 86 | 117 | 118
    )
}

/// A rejected record, before it knows its file.
#[derive(Debug)]
struct Issue {
    line: usize,
    column: String,
    reason: String,
}

impl Issue {
    fn new(line: usize, column: impl Into<String>, reason: impl Into<String>) -> Self {
        Self {
            line,
            column: column.into(),
            reason: reason.into(),
        }
    }

    fn into_error(self, file: &Path) -> Error {
        parse_error(file, self.line, self.column, self.reason)
    }
}

/// The anisotropic displacement of one atom.
#[derive(Debug)]
enum Aniso {
    /// No anisotropic parameters: the atom is left out.
    Missing,
    /// `U11, U22, U33, U12, U13, U23` in Å², from `line`; `column` names the fields.
    Given {
        u: [f64; 6],
        line: usize,
        column: String,
    },
    /// The parameters were rejected (an [`Issue`] says why): the atom is dropped.
    Invalid,
}

/// One atom as read, in file order.
#[derive(Debug)]
struct Atom {
    /// Where the atom record is.
    line: usize,
    /// `atom 5 CA (ALA A 1)`, for messages.
    label: String,
    /// Element symbol as given or inferred (may be empty).
    element: String,
    /// `None` when the atom record was rejected (an [`Issue`] says why).
    center: Option<DVec3>,
    aniso: Aniso,
}

impl Atom {
    /// Attaches parameters read on `line`; a second set for the same atom is an issue.
    fn set_aniso(
        &mut self,
        parsed: std::result::Result<[f64; 6], Issue>,
        line: usize,
        column: String,
        issues: &mut Vec<Issue>,
    ) {
        if self.center.is_none() || matches!(self.aniso, Aniso::Invalid) {
            // The atom is already rejected and counted once.
            return;
        }
        if let Aniso::Given { line: first, .. } = self.aniso {
            issues.push(Issue::new(
                line,
                column,
                format!(
                    "second set of anisotropic parameters for {} (the first is on line {first})",
                    self.label
                ),
            ));
            return;
        }
        match parsed {
            Ok(u) => self.aniso = Aniso::Given { u, line, column },
            Err(issue) => {
                issues.push(issue);
                self.aniso = Aniso::Invalid;
            }
        }
    }
}

/// What a reader found.
#[derive(Debug, Default)]
struct Structure {
    atoms: Vec<Atom>,
    /// Rejected records; each one drops one atom or one stray record.
    issues: Vec<Issue>,
    notes: Vec<String>,
    /// What the atom records are called (`ATOM/HETATM`, `_atom_site`).
    atom_records: &'static str,
    /// What the anisotropic records are called (`ANISOU`, `_atom_site_anisotrop`).
    aniso_records: &'static str,
}

/// Rejects binary data: any control byte other than tab, line feed, carriage return and form
/// feed. (gzip is named, as it is the usual reason.)
fn check_text(bytes: &[u8]) -> std::result::Result<(), Issue> {
    if bytes.starts_with(&[0x1f, 0x8b]) {
        return Err(Issue::new(
            1,
            "column 1",
            "gzip-compressed data: decompress the file first (not a text file)",
        ));
    }
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(Issue::new(
            0,
            "file",
            "empty file: no PDB or mmCIF records (nothing but white space)",
        ));
    }
    let bad = bytes
        .iter()
        .position(|&b| (b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r' | 0x0c)) || b == 0x7f);
    if let Some(at) = bad {
        let line_start = bytes[..at]
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1);
        let column = 1 + at - line_start;
        return Err(Issue::new(
            line_at(bytes, at),
            format!("column {column}"),
            format!(
                "binary data, not a text file: control byte 0x{:02x} at byte offset {at}",
                bytes[at]
            ),
        ));
    }
    Ok(())
}

/// mmCIF by extension, or by a first `data_` after white space and comment lines.
fn is_mmcif(bytes: &[u8], file: &Path) -> bool {
    let extension = file
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if matches!(extension.as_deref(), Some("cif" | "mmcif")) {
        return true;
    }
    let mut rest = bytes;
    loop {
        let start = rest
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(rest.len());
        rest = &rest[start..];
        if rest.first() == Some(&b'#') {
            let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            rest = &rest[end..];
            continue;
        }
        return rest.len() >= 5 && rest[..5].eq_ignore_ascii_case(b"data_");
    }
}

/// Turns what a reader found into ellipsoids, applying `skip_invalid`.
fn build(structure: Structure, file: &Path, options: &LoadOptions) -> Result<Loaded> {
    let Structure {
        atoms,
        mut issues,
        mut notes,
        atom_records,
        aniso_records,
    } = structure;
    let mut ellipsoids = Vec::new();
    let mut origins = Vec::new();
    let mut missing = Vec::new();
    for atom in &atoms {
        let Some(center) = atom.center else { continue };
        match &atom.aniso {
            Aniso::Missing => missing.push(atom),
            Aniso::Invalid => {}
            Aniso::Given { u, line, column } => {
                match thermal_ellipsoid(center, *u, element_color(&atom.element)) {
                    Ok(e) => {
                        ellipsoids.push(e);
                        let line = u32::try_from(atom.line).unwrap_or(u32::MAX);
                        origins.push((line, atom.label.clone()));
                    }
                    Err(reason) => issues.push(Issue::new(
                        *line,
                        column.clone(),
                        format!("{}: {reason}", atom.label),
                    )),
                }
            }
        }
    }
    // Report the first bad record in the file, whichever check found it.
    issues.sort_by_key(|issue| issue.line);
    let skipped = issues.len();
    let first_skipped = match issues.into_iter().next() {
        Some(issue) if !options.skip_invalid => return Err(issue.into_error(file)),
        first => first.map(|issue| issue.into_error(file)),
    };

    if ellipsoids.is_empty() {
        let valid_atoms = atoms.iter().filter(|a| a.center.is_some()).count();
        let (column, reason) = if let Some(first) = &first_skipped {
            (
                aniso_records,
                format!(
                    "no valid anisotropic atoms: {skipped} invalid record(s) skipped (the first: \
                     {first}){}",
                    match missing.len() {
                        0 => String::new(),
                        n => format!(", {n} atom(s) without {aniso_records}"),
                    }
                ),
            )
        } else if valid_atoms == 0 {
            (
                atom_records,
                format!("no atoms: the file has no {atom_records} records"),
            )
        } else {
            (
                aniso_records,
                format!(
                    "no anisotropic atoms: none of the {valid_atoms} atom(s) has {aniso_records} \
                     parameters (isotropic B only), so there are no thermal ellipsoids to draw"
                ),
            )
        };
        return Err(Issue::new(0, column, reason).into_error(file));
    }

    notes.insert(
        0,
        format!(
            "{} thermal ellipsoids at 50 % probability (ORTEP): semi-axes \
             {PROBABILITY_50_SCALE:.4} * sqrt(eigenvalues of U), coloured by element",
            ellipsoids.len()
        ),
    );
    if let Some(first) = missing.first() {
        notes.push(format!(
            "left out {} atom(s) without {aniso_records} parameters (isotropic only), the first: \
             {} on line {}",
            missing.len(),
            first.label,
            first.line
        ));
    }
    if let Some(first) = &first_skipped {
        notes.push(format!(
            "skipped {skipped} invalid record(s); the first: {first}"
        ));
    }
    Ok(Loaded {
        scene: Scene::new(ellipsoids),
        skipped,
        notes,
        origins: Origins::Atoms(origins),
    })
}

/// The 50 % probability ellipsoid of `U = [U11, U22, U33, U12, U13, U23]` (Å²) about `center`;
/// the error says why `U` is not a displacement tensor.
fn thermal_ellipsoid(
    center: DVec3,
    u: [f64; 6],
    color: [f32; 3],
) -> std::result::Result<Ellipsoid, String> {
    let [u11, u22, u33, u12, u13, u23] = u;
    if u.iter().any(|v| !v.is_finite()) {
        return Err(format!("U has a non-finite component: {u:?}"));
    }
    let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return Err("U is zero, not positive definite".to_string());
    }
    // Decompose U / max|U_ij| so that squaring the entries cannot overflow or underflow.
    let m = DMat3::from_cols_array(&[u11, u12, u13, u12, u22, u23, u13, u23, u33]) * scale.recip();
    let (values, vectors) = symmetric_eigen(m);
    let values = values * scale;
    let (lo, hi) = (values.min_element(), values.max_element());
    if !(values.is_finite() && lo > 0.0 && lo > DEFINITE_TOLERANCE * hi) {
        let mut sorted = values.to_array();
        sorted.sort_by(|a, b| b.total_cmp(a));
        return Err(format!(
            "U is not positive definite: eigenvalues {:.6}, {:.6}, {:.6} Å² (a thermal \
             ellipsoid needs all three > 0)",
            sorted[0], sorted[1], sorted[2]
        ));
    }
    let radii =
        DVec3::new(values.x.sqrt(), values.y.sqrt(), values.z.sqrt()) * PROBABILITY_50_SCALE;
    Ellipsoid::new(center, radii, DQuat::from_mat3(&vectors), Some(color))
        .map_err(|e| e.to_string())
}

/// `atom 5 CA altloc B (ALA A 12A)`, leaving out empty parts.
fn describe(serial: &str, name: &str, alt: &str, residue: [&str; 4]) -> String {
    let mut label = format!("atom {serial}");
    if !name.is_empty() {
        label.push_str(&format!(" {name}"));
    }
    if !alt.is_empty() {
        label.push_str(&format!(" altloc {alt}"));
    }
    let [res_name, chain, seq, insertion] = residue;
    let parts: Vec<&str> = [res_name, chain]
        .into_iter()
        .filter(|p| !p.is_empty())
        .collect();
    let number = format!("{seq}{insertion}");
    let mut residue = parts.join(" ");
    if !number.is_empty() {
        if !residue.is_empty() {
            residue.push(' ');
        }
        residue.push_str(&number);
    }
    if !residue.is_empty() {
        label.push_str(&format!(" ({residue})"));
    }
    label
}

// ---------------------------------------------------------------------------------------------
// PDB

/// The `U` fields of an `ANISOU` record: name and 1-based inclusive columns.
const ANISOU_FIELDS: [(&str, usize, usize); 6] = [
    ("U11", 29, 35),
    ("U22", 36, 42),
    ("U33", 43, 49),
    ("U12", 50, 56),
    ("U13", 57, 63),
    ("U23", 64, 70),
];

/// Where the `U` fields are, for messages.
const ANISOU_AT: &str = "U11..U23 are in columns 29-70";

/// The coordinate fields of an `ATOM`/`HETATM` record.
const COORDINATE_FIELDS: [(&str, usize, usize); 3] = [("x", 31, 38), ("y", 39, 46), ("z", 47, 54)];

/// Where the coordinate fields are, for messages.
const COORDINATES_AT: &str = "coordinates are in columns 31-54";

/// Columns `first..=last` (1-based, inclusive: the PDB format's own column numbers) of an ASCII
/// line; a short line gives what it has.
fn cols(line: &str, first: usize, last: usize) -> &str {
    let end = last.min(line.len());
    let start = (first - 1).min(end);
    line.get(start..end).unwrap_or("")
}

/// The identifiers in columns 7-27, trimmed: serial, name, alternate location, residue name,
/// chain, sequence number, insertion code.
fn identifiers(line: &str) -> [&str; 7] {
    [
        cols(line, 7, 11).trim(),
        cols(line, 13, 16).trim(),
        cols(line, 17, 17).trim(),
        cols(line, 18, 20).trim(),
        cols(line, 22, 22).trim(),
        cols(line, 23, 26).trim(),
        cols(line, 27, 27).trim(),
    ]
}

fn pdb_label(ids: &[&str; 7]) -> String {
    describe(ids[0], ids[1], ids[2], [ids[3], ids[4], ids[5], ids[6]])
}

/// The element of a PDB atom: columns 77-78, else the atom name's columns 13-14 (a blank or a
/// digit in 13 means a one-letter element in 14: ` CA ` is carbon, `CA  ` calcium).
fn pdb_element(line: &str) -> String {
    let given = cols(line, 77, 78).trim();
    if !given.is_empty() && pdbtbx::Element::from_symbol(given).is_some() {
        return given.to_string();
    }
    let name = cols(line, 13, 14);
    let mut chars = name.chars();
    match (chars.next(), chars.next()) {
        (Some(a), Some(b)) if a.is_ascii_alphabetic() && b.is_ascii_alphabetic() => {
            if pdbtbx::Element::from_symbol(name).is_some() {
                name.to_string()
            } else {
                a.to_string()
            }
        }
        (Some(a), Some(b)) if !a.is_ascii_alphabetic() && b.is_ascii_alphabetic() => b.to_string(),
        (Some(a), _) if a.is_ascii_alphabetic() => a.to_string(),
        _ => String::new(),
    }
}

/// An `ANISOU` record waiting for its atom.
struct AnisouRecord {
    line: usize,
    /// Columns 7-27 verbatim.
    key: String,
    ids: [String; 7],
    label: String,
    parsed: std::result::Result<[f64; 6], Issue>,
}

const ANISOU_COLUMNS: &str = "U11..U23 (columns 29-70)";

/// Reads the `ATOM`, `HETATM`, `ANISOU` and `MODEL` records of a PDB file.
fn read_pdb(bytes: &[u8]) -> Structure {
    let mut structure = Structure {
        atom_records: "ATOM/HETATM",
        aniso_records: "ANISOU",
        ..Structure::default()
    };
    // Columns 7-27 and the trimmed identifiers of every atom, by index into `atoms`.
    let mut by_key: HashMap<String, usize> = HashMap::new();
    let mut by_serial: HashMap<String, usize> = HashMap::new();
    let mut atom_ids: Vec<[String; 7]> = Vec::new();
    let mut anisou = Vec::new();
    let mut models = 0usize;
    let mut ignored_records = 0usize;

    for (index, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let number = index + 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        let name = raw.get(..6).unwrap_or(raw);
        let end = name.iter().rposition(|&b| b != b' ').map_or(0, |p| p + 1);
        let record = &name[..end];
        let is_atom = matches!(record, b"ATOM" | b"HETATM");
        if record == b"MODEL" {
            models += 1;
            continue;
        }
        if !is_atom && record != b"ANISOU" {
            continue;
        }
        if models > 1 {
            ignored_records += 1;
            continue;
        }
        let kind = if is_atom {
            String::from_utf8_lossy(record).into_owned()
        } else {
            "ANISOU".to_string()
        };
        let line = String::from_utf8_lossy(raw);
        let key =
            String::from_utf8_lossy(raw.get(6..27.min(raw.len())).unwrap_or_default()).into_owned();
        let ids_str = identifiers(&line);
        let label = pdb_label(&ids_str);
        let ids: [String; 7] = ids_str.map(str::to_string);
        let non_ascii = raw.iter().position(|b| !b.is_ascii()).map(|at| {
            Issue::new(
                number,
                format!("column {}", at + 1),
                format!(
                    "{kind} record for {label}: non-ASCII byte 0x{:02x} in a fixed-column record",
                    raw[at]
                ),
            )
        });

        if is_atom {
            let center = match non_ascii {
                Some(issue) => Err(issue),
                None => pdb_coordinates(&line, number, &kind, &label),
            };
            let center = match center {
                Ok(c) => Some(c),
                Err(issue) => {
                    structure.issues.push(issue);
                    None
                }
            };
            let index = structure.atoms.len();
            structure.atoms.push(Atom {
                line: number,
                label,
                element: pdb_element(&line),
                center,
                aniso: Aniso::Missing,
            });
            by_key.insert(key, index);
            by_serial.insert(ids[0].clone(), index);
            atom_ids.push(ids);
        } else {
            let parsed = match non_ascii {
                Some(issue) => Err(issue),
                None => pdb_anisou(&line, number, &label),
            };
            anisou.push(AnisouRecord {
                line: number,
                key,
                ids,
                label,
                parsed,
            });
        }
    }

    for record in anisou {
        let matched = by_key.get(&record.key).copied().or_else(|| {
            by_serial
                .get(&record.ids[0])
                .copied()
                .filter(|&i| atom_ids[i] == record.ids)
        });
        let Some(index) = matched else {
            let same_serial = by_serial.get(&record.ids[0]).map(|&i| &structure.atoms[i]);
            let reason = unmatched_anisou(&record, same_serial, models > 0);
            structure
                .issues
                .push(Issue::new(record.line, "serial (columns 7-11)", reason));
            continue;
        };
        structure.atoms[index].set_aniso(
            record.parsed,
            record.line,
            ANISOU_COLUMNS.to_string(),
            &mut structure.issues,
        );
    }
    if models > 1 {
        structure.notes.push(format!(
            "the file has {models} models; only the first is drawn ({ignored_records} atom and \
             ANISOU records of the others ignored)"
        ));
    }
    structure
}

/// Why an `ANISOU` has no atom: `same_serial` is the atom with its serial number, if any.
fn unmatched_anisou(record: &AnisouRecord, same_serial: Option<&Atom>, models: bool) -> String {
    let (label, serial) = (&record.label, &record.ids[0]);
    match same_serial {
        Some(atom) => format!(
            "ANISOU for {label} does not match its ATOM/HETATM: the record with serial {serial} \
             is {} (line {})",
            atom.label, atom.line
        ),
        None => format!(
            "ANISOU for {label} has no matching ATOM/HETATM record (no atom with serial \
             {serial}{})",
            if models { " in the first model" } else { "" }
        ),
    }
}

/// The coordinates of an ASCII `ATOM`/`HETATM` line.
fn pdb_coordinates(
    line: &str,
    number: usize,
    kind: &str,
    label: &str,
) -> std::result::Result<DVec3, Issue> {
    let mut xyz = [0.0; 3];
    for (value, (axis, first, last)) in xyz.iter_mut().zip(COORDINATE_FIELDS) {
        let column = format!("{axis} (columns {first}-{last})");
        let what = format!("{kind} record for {label}: {axis} coordinate");
        let text = fixed_field(line, number, (first, last), &column, &what, COORDINATES_AT)?;
        *value = parse_real(text)
            .map_err(|problem| Issue::new(number, column, format!("{what} {problem}")))?;
    }
    Ok(DVec3::from_array(xyz))
}

/// Columns `first..=last` of the fixed-column record `line` (line `number`), trimmed; an issue
/// on `column` when the line ends before `last`. `what` names the field and `where_` says where
/// its group of fields is, for the message.
fn fixed_field<'a>(
    line: &'a str,
    number: usize,
    (first, last): (usize, usize),
    column: &str,
    what: &str,
    where_: &str,
) -> std::result::Result<&'a str, Issue> {
    if line.len() < last {
        return Err(Issue::new(
            number,
            column,
            format!(
                "{what} is missing: the line ends at column {} ({where_})",
                line.len()
            ),
        ));
    }
    Ok(cols(line, first, last).trim())
}

/// A finite real number, or why not.
fn parse_real(text: &str) -> std::result::Result<f64, String> {
    parse_real_shown(text, text)
}

/// A finite real number from `text`, or why not, quoting `shown` (the field as written).
fn parse_real_shown(text: &str, shown: &str) -> std::result::Result<f64, String> {
    if text.is_empty() {
        return Err("is empty (expected a number)".to_string());
    }
    let value: f64 = text
        .parse()
        .map_err(|_| format!("is not a number: \"{}\"", clip(shown)))?;
    if !value.is_finite() {
        return Err(format!("is not finite: \"{}\"", clip(shown)));
    }
    Ok(value)
}

/// The `U` of an ASCII `ANISOU` line, in Å².
fn pdb_anisou(line: &str, number: usize, label: &str) -> std::result::Result<[f64; 6], Issue> {
    let mut u = [0.0; 6];
    for (value, (name, first, last)) in u.iter_mut().zip(ANISOU_FIELDS) {
        let column = format!("{name} (columns {first}-{last})");
        let what = format!("ANISOU for {label}: {name}");
        let text = fixed_field(line, number, (first, last), &column, &what, ANISOU_AT)?;
        if text.is_empty() {
            return Err(Issue::new(
                number,
                column,
                format!("{what} is empty (expected an integer, U in 10^-4 Å²)"),
            ));
        }
        let integer: i64 = text.parse().map_err(|_| {
            Issue::new(
                number,
                column,
                format!("{what} is not an integer: \"{text}\" (U in 10^-4 Å²)"),
            )
        })?;
        *value = integer as f64 * 1e-4;
    }
    Ok(u)
}

// ---------------------------------------------------------------------------------------------
// mmCIF

/// What a CIF token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// An unquoted value (`?` and `.` here mean unknown and inapplicable).
    Bare,
    /// A quoted string or a `;` text field.
    Quoted,
    Tag,
    Loop,
    Data,
    Save,
    /// `global_` or `stop_`, not allowed in CIF.
    Reserved,
}

#[derive(Clone, Copy, Debug)]
struct Token<'a> {
    kind: Kind,
    text: &'a str,
    /// 1-based line where the token starts.
    line: usize,
}

impl Token<'_> {
    fn is_value(&self) -> bool {
        matches!(self.kind, Kind::Bare | Kind::Quoted)
    }

    /// An unquoted `?` or `.`.
    fn is_null(&self) -> bool {
        self.kind == Kind::Bare && matches!(self.text, "?" | ".")
    }

    /// The value for messages and labels: nulls become empty.
    fn value(&self) -> &str {
        if self.is_null() {
            ""
        } else {
            self.text
        }
    }
}

/// CIF 1.1 tokens. Every split is at an ASCII byte, so slicing the `&str` is always on a
/// character boundary; every step advances `pos`.
struct Lexer<'a> {
    text: &'a str,
    pos: usize,
    line: usize,
    peeked: Option<Token<'a>>,
}

impl<'a> Lexer<'a> {
    fn new(text: &'a str) -> Self {
        Self {
            text,
            pos: 0,
            line: 1,
            peeked: None,
        }
    }

    fn peek(&mut self) -> std::result::Result<Option<Token<'a>>, Issue> {
        if self.peeked.is_none() {
            self.peeked = self.scan()?;
        }
        Ok(self.peeked)
    }

    fn next(&mut self) -> std::result::Result<Option<Token<'a>>, Issue> {
        match self.peeked.take() {
            Some(token) => Ok(Some(token)),
            None => self.scan(),
        }
    }

    fn scan(&mut self) -> std::result::Result<Option<Token<'a>>, Issue> {
        let bytes = self.text.as_bytes();
        loop {
            let Some(&b) = bytes.get(self.pos) else {
                return Ok(None);
            };
            match b {
                b'\n' => {
                    self.line += 1;
                    self.pos += 1;
                }
                b' ' | b'\t' | b'\r' | 0x0c => self.pos += 1,
                b'#' => {
                    self.pos = bytes[self.pos..]
                        .iter()
                        .position(|&c| c == b'\n')
                        .map_or(bytes.len(), |p| self.pos + p);
                }
                b';' if self.pos == 0 || bytes[self.pos - 1] == b'\n' => {
                    return self.text_field().map(Some)
                }
                b'\'' | b'"' => return self.quoted(b).map(Some),
                _ => return Ok(Some(self.bare())),
            }
        }
    }

    /// A `;` text field: from after the opening `;` to the line break before the closing `;`
    /// that starts a line.
    fn text_field(&mut self) -> std::result::Result<Token<'a>, Issue> {
        let bytes = self.text.as_bytes();
        let (start, start_line) = (self.pos + 1, self.line);
        let mut at = start;
        while let Some(offset) = bytes[at..].iter().position(|&c| c == b'\n') {
            let newline = at + offset;
            self.line += 1;
            if bytes.get(newline + 1) == Some(&b';') {
                self.pos = newline + 2;
                return Ok(Token {
                    kind: Kind::Quoted,
                    text: &self.text[start..newline],
                    line: start_line,
                });
            }
            at = newline + 1;
        }
        Err(Issue::new(
            start_line,
            "text field",
            "unterminated text field: no line starting with ';' closes the one opened here",
        ))
    }

    /// A string in `quote`s; it ends at a `quote` followed by white space or the end.
    fn quoted(&mut self, quote: u8) -> std::result::Result<Token<'a>, Issue> {
        let bytes = self.text.as_bytes();
        let start = self.pos + 1;
        let mut at = start;
        loop {
            match bytes.get(at) {
                None | Some(b'\n') => {
                    return Err(Issue::new(
                        self.line,
                        "quoted string",
                        format!(
                            "unterminated quoted string: no closing {} on this line",
                            quote as char
                        ),
                    ))
                }
                Some(&c) if c == quote && bytes.get(at + 1).is_none_or(u8::is_ascii_whitespace) => {
                    self.pos = at + 1;
                    return Ok(Token {
                        kind: Kind::Quoted,
                        text: &self.text[start..at],
                        line: self.line,
                    });
                }
                Some(_) => at += 1,
            }
        }
    }

    fn bare(&mut self) -> Token<'a> {
        let bytes = self.text.as_bytes();
        let start = self.pos;
        self.pos = bytes[start..]
            .iter()
            .position(u8::is_ascii_whitespace)
            .map_or(bytes.len(), |p| start + p);
        let text = &self.text[start..self.pos];
        let starts = |prefix: &str| {
            text.len() >= prefix.len()
                && text.as_bytes()[..prefix.len()].eq_ignore_ascii_case(prefix.as_bytes())
        };
        let kind = if text.starts_with('_') {
            Kind::Tag
        } else if text.eq_ignore_ascii_case("loop_") {
            Kind::Loop
        } else if starts("data_") {
            Kind::Data
        } else if starts("save_") {
            Kind::Save
        } else if text.eq_ignore_ascii_case("global_") || text.eq_ignore_ascii_case("stop_") {
            Kind::Reserved
        } else {
            Kind::Bare
        };
        Token {
            kind,
            text,
            line: self.line,
        }
    }
}

/// One category of interest, as a loop or as single items (one row).
struct Table<'a> {
    /// Where the loop (or the first single item) starts.
    line: usize,
    /// The full tags as written, e.g. `_atom_site.Cartn_x`.
    tags: Vec<&'a str>,
    /// Row-major values.
    values: Vec<Token<'a>>,
    is_loop: bool,
}

impl<'a> Table<'a> {
    /// The index of `category.item` (case-insensitive).
    fn column(&self, item: &str) -> Option<usize> {
        self.tags.iter().position(|tag| {
            tag.split_once('.')
                .is_some_and(|(_, name)| name.eq_ignore_ascii_case(item))
        })
    }

    fn rows(&self) -> impl Iterator<Item = &[Token<'a>]> {
        self.values.chunks(self.tags.len().max(1))
    }
}

/// The categories this loader uses (lower case).
const ATOM_SITE: &str = "_atom_site";
const ANISOTROP: &str = "_atom_site_anisotrop";

/// The lower-case category of a tag (`_atom_site` for `_atom_site.Cartn_x`); `None` for
/// tags without a `.` (CIF 1 dictionaries).
fn category(tag: &str) -> Option<String> {
    tag.split_once('.').map(|(c, _)| c.to_ascii_lowercase())
}

/// The first data block's `_atom_site` and `_atom_site_anisotrop`, checking the syntax of the
/// whole block.
struct Block<'a> {
    tables: HashMap<String, Table<'a>>,
    /// A coreCIF tag (`_atom_site_aniso_U_11`), for a clear message.
    core_cif: Option<Token<'a>>,
    notes: Vec<String>,
}

fn read_block(text: &str) -> std::result::Result<Block<'_>, Issue> {
    let mut lexer = Lexer::new(text);
    let mut block = Block {
        tables: HashMap::new(),
        core_cif: None,
        notes: Vec::new(),
    };
    match lexer.next()? {
        Some(token) if token.kind == Kind::Data => {}
        Some(token) => {
            return Err(Issue::new(
                token.line,
                "data_",
                format!(
                    "mmCIF must start with a data_ block header, found \"{}\"",
                    clip(token.text)
                ),
            ))
        }
        None => {
            return Err(Issue::new(
                0,
                "data_",
                "no data_ block: the file has only comments",
            ))
        }
    }
    while let Some(token) = lexer.next()? {
        match token.kind {
            Kind::Data => {
                block.notes.push(format!(
                    "only the first data block is read; \"{}\" on line {} and any after it are \
                     ignored",
                    clip(token.text),
                    token.line
                ));
                break;
            }
            Kind::Tag => {
                let value = match lexer.next()? {
                    Some(value) if value.is_value() => value,
                    other => {
                        let found = other.map_or("the end of the file".to_string(), |t| {
                            format!("\"{}\" on line {}", clip(t.text), t.line)
                        });
                        return Err(Issue::new(
                            token.line,
                            token.text,
                            format!("tag {} has no value (followed by {found})", token.text),
                        ));
                    }
                };
                block.note_core_cif(token);
                block.add_single(token, value)?;
            }
            Kind::Loop => {
                let mut tags: Vec<Token> = Vec::new();
                while let Some(tag) = lexer.peek()?.filter(|t| t.kind == Kind::Tag) {
                    lexer.next()?;
                    if let Some(before) =
                        tags.iter().find(|t| t.text.eq_ignore_ascii_case(tag.text))
                    {
                        return Err(Issue::new(
                            tag.line,
                            tag.text,
                            format!(
                                "duplicate tag {} in the loop_ (also on line {})",
                                tag.text, before.line
                            ),
                        ));
                    }
                    block.note_core_cif(tag);
                    tags.push(tag);
                }
                let Some(first) = tags.first() else {
                    return Err(Issue::new(token.line, "loop_", "loop_ without tags"));
                };
                let mut values = Vec::new();
                while let Some(value) = lexer.peek()?.filter(Token::is_value) {
                    lexer.next()?;
                    values.push(value);
                }
                check_loop(token, &tags, &values)?;
                let Some(name) = category(first.text).filter(|c| c == ATOM_SITE || c == ANISOTROP)
                else {
                    continue;
                };
                if let Some(before) = block.tables.get(&name) {
                    return Err(Issue::new(
                        token.line,
                        first.text,
                        format!(
                            "category {name} given twice (first on line {}, again in this loop_)",
                            before.line
                        ),
                    ));
                }
                if let Some(other) = tags
                    .iter()
                    .find(|t| category(t.text).as_deref() != Some(&name))
                {
                    return Err(Issue::new(
                        other.line,
                        other.text,
                        format!("tag {} in a loop_ of category {name}", other.text),
                    ));
                }
                block.tables.insert(
                    name,
                    Table {
                        line: token.line,
                        tags: tags.iter().map(|t| t.text).collect(),
                        values,
                        is_loop: true,
                    },
                );
            }
            Kind::Save => {
                if token.text.len() == "save_".len() {
                    return Err(Issue::new(
                        token.line,
                        "save_",
                        "save_ that closes no save frame",
                    ));
                }
                // Save frames hold dictionary definitions, not data: skip to the closing save_.
                loop {
                    match lexer.next()? {
                        Some(t) if t.kind == Kind::Save && t.text.len() == "save_".len() => break,
                        Some(_) => {}
                        None => {
                            return Err(Issue::new(
                                token.line,
                                token.text,
                                "unterminated save frame: no closing save_",
                            ))
                        }
                    }
                }
            }
            Kind::Reserved => {
                return Err(Issue::new(
                    token.line,
                    token.text,
                    format!("reserved word {} is not allowed in CIF", token.text),
                ))
            }
            Kind::Bare | Kind::Quoted => {
                return Err(Issue::new(
                    token.line,
                    "value",
                    format!("value \"{}\" without a tag", clip(token.text)),
                ))
            }
        }
    }
    Ok(block)
}

impl<'a> Block<'a> {
    fn note_core_cif(&mut self, tag: Token<'a>) {
        let lower = tag.text.to_ascii_lowercase();
        if self.core_cif.is_none()
            && (lower.starts_with("_atom_site_aniso_") || lower.starts_with("_atom_site_fract_"))
        {
            self.core_cif = Some(tag);
        }
    }

    /// A `tag value` pair of a category of interest becomes a column of a one-row table.
    fn add_single(&mut self, tag: Token<'a>, value: Token<'a>) -> std::result::Result<(), Issue> {
        let Some(name) = category(tag.text).filter(|c| c == ATOM_SITE || c == ANISOTROP) else {
            return Ok(());
        };
        let table = self.tables.entry(name.clone()).or_insert_with(|| Table {
            line: tag.line,
            tags: Vec::new(),
            values: Vec::new(),
            is_loop: false,
        });
        if table.is_loop {
            return Err(Issue::new(
                tag.line,
                tag.text,
                format!(
                    "category {name} is given both as a loop_ (line {}) and as single items",
                    table.line
                ),
            ));
        }
        if table.tags.iter().any(|t| t.eq_ignore_ascii_case(tag.text)) {
            return Err(Issue::new(
                tag.line,
                tag.text,
                format!("duplicate tag {}", tag.text),
            ));
        }
        table.tags.push(tag.text);
        table.values.push(value);
        Ok(())
    }
}

/// A loop needs values, a whole number of rows of them.
fn check_loop(
    loop_token: Token,
    tags: &[Token],
    values: &[Token],
) -> std::result::Result<(), Issue> {
    let n = tags.len();
    let Some(last) = values.last() else {
        return Err(Issue::new(
            loop_token.line,
            tags[0].text,
            format!("loop_ with {n} tag(s) has no values (truncated file?)"),
        ));
    };
    let have = values.len() % n;
    if have == 0 {
        return Ok(());
    }
    let row_start = values[values.len() - have].line;
    let missing = &tags[have..];
    let more = if missing.len() > 1 {
        format!(" and {} more", missing.len() - 1)
    } else {
        String::new()
    };
    Err(Issue::new(
        last.line,
        missing[0].text,
        format!(
            "truncated loop_ (started on line {}): {} values for {n} columns, so the last row \
             (from line {row_start}) has only {have} of {n} values, missing {}{more} (a value is \
             missing there or earlier in the loop)",
            loop_token.line,
            values.len(),
            missing[0].text,
        ),
    ))
}

/// At most 40 characters of a token, for messages.
fn clip(text: &str) -> String {
    let mut chars = text.chars();
    let head: String = chars.by_ref().take(40).collect();
    if chars.next().is_some() {
        format!("{head}...")
    } else {
        head
    }
}

/// A real number from a CIF value, allowing a standard uncertainty such as `0.0234(12)`.
fn cif_real(token: &Token) -> std::result::Result<f64, String> {
    if token.is_null() {
        return Err(format!("has no value (\"{}\")", token.text));
    }
    let text = token.text.trim();
    let number = text
        .strip_suffix(')')
        .and_then(|t| t.rsplit_once('('))
        .filter(|(_, su)| !su.is_empty() && su.bytes().all(|b| b.is_ascii_digit()))
        .map_or(text, |(number, _)| number);
    parse_real_shown(number, text)
}

/// The six `U` (or `B`) columns of a table, with the factor that turns them into `U` (Å²).
struct UColumns {
    columns: [usize; 6],
    factor: f64,
    /// `U` or `B`, for messages.
    kind: char,
}

/// The `U[i][j]`/`B[i][j]` columns named `prefix + "U[1][1]"` etc.: all of U, else all of B,
/// else `Ok(None)` when none of them is present.
fn u_columns(table: &Table, prefix: &str) -> std::result::Result<Option<UColumns>, Issue> {
    const IJ: [&str; 6] = ["[1][1]", "[2][2]", "[3][3]", "[1][2]", "[1][3]", "[2][3]"];
    let find = |kind: char| IJ.map(|ij| table.column(&format!("{prefix}{kind}{ij}")));
    let tag_category = table
        .tags
        .first()
        .and_then(|t| t.split_once('.'))
        .map_or("", |(c, _)| c);
    for (kind, factor) in [
        ('U', 1.0),
        ('B', 1.0 / (8.0 * std::f64::consts::PI.powi(2))),
    ] {
        let found = find(kind);
        if found.iter().all(Option::is_some) {
            return Ok(Some(UColumns {
                columns: found.map(|c| c.unwrap_or(0)),
                factor,
                kind,
            }));
        }
        if let Some(missing) = found
            .iter()
            .position(Option::is_none)
            .filter(|_| found.iter().any(Option::is_some))
        {
            let tag = format!("{tag_category}.{prefix}{kind}{}", IJ[missing]);
            return Err(Issue::new(
                table.line,
                tag.clone(),
                format!("{tag_category} has some {prefix}{kind}[i][j] columns but not {tag}"),
            ));
        }
    }
    Ok(None)
}

/// The `U` (Å²) of one row, `Ok(None)` when all six values are `?` or `.`.
fn row_u(
    row: &[Token],
    columns: &UColumns,
    tags: &[&str],
    label: &str,
) -> std::result::Result<Option<[f64; 6]>, Issue> {
    if columns.columns.iter().all(|&c| row[c].is_null()) {
        return Ok(None);
    }
    let mut u = [0.0; 6];
    for (value, &c) in u.iter_mut().zip(&columns.columns) {
        let token = &row[c];
        *value = cif_real(token).map_err(|problem| {
            Issue::new(
                token.line,
                tags[c],
                format!("{label}: {} {problem}", tags[c]),
            )
        })? * columns.factor;
    }
    Ok(Some(u))
}

/// The atoms of an mmCIF file.
fn read_mmcif(bytes: &[u8]) -> std::result::Result<Structure, Issue> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let at = e.valid_up_to();
        Issue::new(
            line_at(bytes, at),
            "text",
            format!("invalid UTF-8 at byte offset {at} (mmCIF is ASCII or UTF-8 text)"),
        )
    })?;
    let Block {
        tables,
        core_cif,
        notes,
    } = read_block(text)?;
    let mut structure = Structure {
        notes,
        atom_records: "_atom_site",
        aniso_records: "_atom_site_anisotrop",
        ..Structure::default()
    };
    let Some(sites) = tables.get(ATOM_SITE) else {
        if let Some(tag) = core_cif {
            return Err(Issue::new(
                tag.line,
                tag.text,
                "small-molecule (core) CIF is not supported: its anisotropic parameters are in \
                 crystal axes and need the unit cell; use mmCIF (_atom_site.Cartn_x, \
                 _atom_site_anisotrop.U[1][1])",
            ));
        }
        return Ok(structure);
    };
    let required = |item: &str| {
        sites.column(item).ok_or_else(|| {
            Issue::new(
                sites.line,
                format!("{ATOM_SITE}.{item}"),
                format!(
                    "{ATOM_SITE} has no {item} column (Cartesian coordinates Cartn_x, Cartn_y, \
                     Cartn_z are required)"
                ),
            )
        })
    };
    let xyz = [
        required("Cartn_x")?,
        required("Cartn_y")?,
        required("Cartn_z")?,
    ];
    let either = |a: &str, b: &str| sites.column(a).or_else(|| sites.column(b));
    let id = sites.column("id");
    let atom_name = either("auth_atom_id", "label_atom_id");
    let alt = sites.column("label_alt_id");
    let residue = [
        either("auth_comp_id", "label_comp_id"),
        either("auth_asym_id", "label_asym_id"),
        either("auth_seq_id", "label_seq_id"),
        sites.column("pdbx_PDB_ins_code"),
    ];
    let type_symbol = sites.column("type_symbol");
    let model = sites.column("pdbx_PDB_model_num");
    let inline_u = u_columns(sites, "aniso_")?;

    // `_atom_site.id` -> index into `atoms`, `None` for atoms of ignored models.
    let mut by_id: HashMap<&str, Option<usize>> = HashMap::new();
    let mut first_model = None;
    let mut ignored = 0usize;
    for (row_index, row) in sites.rows().enumerate() {
        let get = |c: Option<usize>| c.map_or("", |c| row[c].value());
        let line = row[0].line;
        let serial = match id {
            Some(c) => row[c].text.to_string(),
            None => (row_index + 1).to_string(),
        };
        let name = get(atom_name);
        let label = describe(&serial, name, get(alt), residue.map(get));
        if let Some(c) = model {
            let this = row[c].text;
            if *first_model.get_or_insert(this) != this {
                ignored += 1;
                if let Some(c) = id {
                    by_id.entry(row[c].text).or_insert(None);
                }
                continue;
            }
        }
        let element = match type_symbol.map(|c| row[c].value()) {
            Some(symbol) if !symbol.is_empty() => symbol.to_string(),
            _ => name.chars().take(1).collect(),
        };
        let mut center = [0.0; 3];
        let mut issue = None;
        for (value, &c) in center.iter_mut().zip(&xyz) {
            match cif_real(&row[c]) {
                Ok(v) => *value = v,
                Err(problem) => {
                    issue = Some(Issue::new(
                        row[c].line,
                        sites.tags[c],
                        format!("{label}: {} {problem}", sites.tags[c]),
                    ));
                    break;
                }
            }
        }
        if let Some(c) = id {
            if let Some(Some(before)) = by_id.get(row[c].text) {
                let before: &Atom = &structure.atoms[*before];
                structure.issues.push(Issue::new(
                    row[c].line,
                    sites.tags[c],
                    format!(
                        "{label}: duplicate {} \"{}\" (also on line {})",
                        sites.tags[c], row[c].text, before.line
                    ),
                ));
                continue;
            }
        }
        let mut atom = Atom {
            line,
            label: label.clone(),
            element,
            center: None,
            aniso: Aniso::Missing,
        };
        match issue {
            Some(issue) => structure.issues.push(issue),
            None => atom.center = Some(DVec3::from_array(center)),
        }
        if let Some(columns) = &inline_u {
            let first = columns.columns[0];
            let column = format!("{}..{}", sites.tags[first], sites.tags[columns.columns[5]]);
            // All six `?` or `.`: this atom has no anisotropic parameters.
            if let Some(parsed) = row_u(row, columns, &sites.tags, &label).transpose() {
                atom.set_aniso(parsed, row[first].line, column, &mut structure.issues);
            }
        }
        if let Some(c) = id {
            by_id.insert(row[c].text, Some(structure.atoms.len()));
        }
        structure.atoms.push(atom);
    }
    if ignored > 0 {
        structure.notes.push(format!(
            "only the first model ({}) is drawn; {ignored} atom(s) of other models ignored",
            first_model.unwrap_or("?")
        ));
    }

    let Some(aniso) = tables.get(ANISOTROP) else {
        return Ok(structure);
    };
    let Some(aniso_id) = aniso.column("id") else {
        return Err(Issue::new(
            aniso.line,
            format!("{ANISOTROP}.id"),
            format!("{ANISOTROP} has no id column to match {ATOM_SITE}.id"),
        ));
    };
    if id.is_none() {
        return Err(Issue::new(
            sites.line,
            format!("{ATOM_SITE}.id"),
            format!("{ATOM_SITE} has no id column to match {ANISOTROP}.id"),
        ));
    }
    let Some(columns) = u_columns(aniso, "")? else {
        return Err(Issue::new(
            aniso.line,
            format!("{ANISOTROP}.U[1][1]"),
            format!("{ANISOTROP} has neither U[1][1]..U[2][3] nor B[1][1]..B[2][3] columns"),
        ));
    };
    let column = format!(
        "{}..{}",
        aniso.tags[columns.columns[0]], aniso.tags[columns.columns[5]]
    );
    for row in aniso.rows() {
        let key = &row[aniso_id];
        let index = match by_id.get(key.text) {
            Some(Some(index)) => *index,
            Some(None) => continue,
            None => {
                structure.issues.push(Issue::new(
                    key.line,
                    aniso.tags[aniso_id],
                    format!(
                        "{ANISOTROP} row for id \"{}\" has no matching {ATOM_SITE} row (no \
                         atom has that {ATOM_SITE}.id)",
                        clip(key.text)
                    ),
                ));
                continue;
            }
        };
        let label = structure.atoms[index].label.clone();
        let line = row[columns.columns[0]].line;
        if let Some(parsed) = row_u(row, &columns, &aniso.tags, &label).transpose() {
            structure.atoms[index].set_aniso(parsed, line, column.clone(), &mut structure.issues);
        }
    }
    if columns.kind == 'B' {
        structure.notes.push(format!(
            "{ANISOTROP} gives B[i][j]; converted to U[i][j] = B[i][j] / (8 pi^2)"
        ));
    }
    Ok(structure)
}
