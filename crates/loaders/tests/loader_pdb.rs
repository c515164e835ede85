//! Thermal ellipsoids from PDB and mmCIF: the 50 % probability ellipsoid of every anisotropic
//! atom, the same from both dialects, and every malformed input rejected with its file, line,
//! field and reason -- without panicking on arbitrary bytes.

mod support;

use std::path::Path;

use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat_loaders::pdb::{
    element_color, load_structure, parse_structure, PROBABILITY_50_SCALE,
};
use ellipsoid_splat_loaders::Error;
use ellipsoid_splat_loaders::{LoadOptions, Loaded};
use glam::{DMat3, DVec3};
use support::{
    assert_contains, assert_mat_close, assert_note, loaded, parse_error, sample, sample_text,
    skipping, ParseError, Rng,
};

fn parse_with(text: &str, file: &str, options: &LoadOptions) -> Result<Loaded, Error> {
    parse_structure(text.as_bytes(), Path::new(file), options)
}

fn parse(text: &str, file: &str) -> Loaded {
    loaded(
        parse_with(text, file, &LoadOptions::default()),
        text.as_bytes(),
    )
}

/// Parses `bytes`, expecting a parse error naming `file`.
fn parse_err_bytes(bytes: &[u8], file: &str, options: &LoadOptions) -> ParseError {
    parse_error(
        parse_structure(bytes, Path::new(file), options),
        Path::new(file),
        bytes,
    )
}

/// Asserts the error's line and field, that the reason contains every one of `words`, and
/// returns the full message.
fn assert_err(text: &str, file: &str, line: usize, column: &str, words: &[&str]) -> String {
    assert_err_with(text, file, &LoadOptions::default(), line, column, words)
}

fn assert_err_with(
    text: &str,
    file: &str,
    options: &LoadOptions,
    line: usize,
    column: &str,
    words: &[&str],
) -> String {
    parse_err_bytes(text.as_bytes(), file, options).assert_at(line, column, words)
}

/// An `ATOM`/`HETATM` record; `name` is the 4-column atom name field (` CA `).
fn atom(
    record: &str,
    serial: u32,
    name: &str,
    res: &str,
    seq: i32,
    xyz: [f64; 3],
    el: &str,
) -> String {
    let [x, y, z] = xyz;
    format!(
        "{record:<6}{serial:>5} {name:<4} {res:>3} A{seq:>4}    {x:8.3}{y:8.3}{z:8.3}  1.00 20.00\
         {:10}{el:>2}  \n",
        ""
    )
}

/// An `ANISOU` record with `U` in 10^-4 A^2, in file order `U11 U22 U33 U12 U13 U23`.
fn anisou(serial: u32, name: &str, res: &str, seq: i32, u: [i64; 6], el: &str) -> String {
    let fields: String = u.iter().map(|v| format!("{v:>7}")).collect();
    format!("ANISOU{serial:>5} {name:<4} {res:>3} A{seq:>4}  {fields}      {el:>2}  \n")
}

/// Three anisotropic atoms of an alanine fragment.
fn three_atoms() -> String {
    [
        atom("ATOM", 1, " N  ", "ALA", 1, [11.104, 6.134, -6.504], "N"),
        anisou(1, " N  ", "ALA", 1, [2406, 1892, 1614, 198, 519, -216], "N"),
        atom("ATOM", 2, " CA ", "ALA", 1, [11.639, 6.071, -5.147], "C"),
        anisou(2, " CA ", "ALA", 1, [1600, 1500, 1400, 100, 50, -20], "C"),
        atom("ATOM", 3, " O  ", "ALA", 1, [13.052, 5.548, -5.208], "O"),
        anisou(3, " O  ", "ALA", 1, [3500, 1200, 2200, -300, 400, 100], "O"),
    ]
    .concat()
}

/// [`three_atoms`] with line `index` (0-based) cut to its first `len` columns.
fn three_atoms_cut(index: usize, len: usize) -> String {
    three_atoms()
        .lines()
        .enumerate()
        .map(|(i, l)| if i == index { &l[..len] } else { l }.to_string() + "\n")
        .collect()
}

/// `M M^T` of an ellipsoid: `c^2 U` for a thermal ellipsoid.
fn shape(e: &Ellipsoid) -> DMat3 {
    let m = e.to_world();
    m * m.transpose()
}

fn u_matrix(u: [f64; 6]) -> DMat3 {
    let [u11, u22, u33, u12, u13, u23] = u;
    DMat3::from_cols_array(&[u11, u12, u13, u12, u22, u23, u13, u23, u33])
}

// ---------------------------------------------------------------------------------------------
// accepted input

#[test]
fn ellipsoid_is_the_50_percent_probability_surface_of_u() {
    let loaded = parse(&three_atoms(), "ala.pdb");
    assert_eq!(loaded.scene.len(), 3);
    assert_eq!(loaded.skipped, 0);
    let e = &loaded.scene.ellipsoids[0];
    assert_eq!(e.center, DVec3::new(11.104, 6.134, -6.504));
    let u = u_matrix([0.2406, 0.1892, 0.1614, 0.0198, 0.0519, -0.0216]);
    let c2 = PROBABILITY_50_SCALE * PROBABILITY_50_SCALE;
    assert_mat_close(shape(e), u * c2, 1e-12);
    // Semi-axes are c * sqrt(eigenvalues of U): their squares sum to c^2 trace(U).
    let sum: f64 = e.radii.to_array().iter().map(|r| r * r).sum();
    assert!((sum - c2 * (0.2406 + 0.1892 + 0.1614)).abs() < 1e-12);
    assert_eq!(e.color, element_color("N"));
    assert_eq!(loaded.scene.ellipsoids[1].color, element_color("C"));
    assert_eq!(loaded.scene.ellipsoids[2].color, element_color("O"));
    assert_contains(&loaded.notes[0], &["50 % probability", "1.5382"]);
}

#[test]
fn scale_is_the_chi_square_median_with_three_degrees_of_freedom() {
    // P(chi^2_3 <= x) = erf(sqrt(x/2)) - sqrt(2x/pi) exp(-x/2); erf by its Taylor series.
    fn erf(x: f64) -> f64 {
        let (mut term, mut sum) = (x, x);
        for n in 1..60 {
            term *= -x * x / n as f64;
            sum += term / (2 * n + 1) as f64;
        }
        sum * 2.0 / std::f64::consts::PI.sqrt()
    }
    let x = PROBABILITY_50_SCALE * PROBABILITY_50_SCALE;
    let cdf = erf((x / 2.0).sqrt()) - (2.0 * x / std::f64::consts::PI).sqrt() * (-x / 2.0).exp();
    assert!((cdf - 0.5).abs() < 1e-12, "{cdf}");
    assert!((PROBABILITY_50_SCALE - 1.5382).abs() < 1e-4);
    assert!((x - 2.3660).abs() < 1e-4);
}

#[test]
fn samples_give_the_same_ellipsoids_from_pdb_and_mmcif() {
    let pdb = load_structure(&sample("thermal.pdb"), &LoadOptions::default()).expect("pdb");
    let cif = load_structure(&sample("thermal.cif"), &LoadOptions::default()).expect("cif");
    // 20 glutathione heavy atoms and two waters are anisotropic; 16 hydrogens are not.
    assert_eq!(pdb.scene.len(), 22);
    assert_eq!(cif.scene.len(), 22);
    assert_eq!((pdb.skipped, cif.skipped), (0, 0));
    for loaded in [&pdb, &cif] {
        assert_note(&loaded.notes, "left out 16 atom(s)");
    }
    for (a, b) in pdb.scene.ellipsoids.iter().zip(&cif.scene.ellipsoids) {
        assert_eq!(a.center, b.center);
        assert_eq!(a.color, b.color);
        assert_mat_close(shape(a), shape(b), 1e-12);
    }
    let colors: Vec<[f32; 3]> = pdb.scene.ellipsoids.iter().map(|e| e.color).collect();
    for element in ["C", "N", "O", "S"] {
        assert!(colors.contains(&element_color(element)), "no {element}");
    }
    // The sample is plausible: 50 % semi-axes between 0.1 and 0.8 A.
    for e in &pdb.scene.ellipsoids {
        assert!(
            e.radii.min_element() > 0.1 && e.radii.max_element() < 0.8,
            "{}",
            e.radii
        );
    }
    // And `load` dispatches both by extension.
    let via_load = ellipsoid_splat_loaders::load(&sample("thermal.cif"), &LoadOptions::default())
        .expect("load");
    assert_eq!(via_load.scene, cif.scene);
}

#[test]
fn element_colours_follow_cpk() {
    assert_eq!(element_color("C"), [0.50, 0.50, 0.50]);
    assert_eq!(element_color("H"), [1.0, 1.0, 1.0]);
    let [r, g, b] = element_color("N");
    assert!(b > 0.9 && r < 0.3 && g < 0.4, "N blue");
    let [r, g, b] = element_color("O");
    assert!(r > 0.9 && g < 0.1 && b < 0.1, "O red");
    let [r, g, b] = element_color("S");
    assert!(r > 0.9 && g > 0.8 && b < 0.3, "S yellow");
    assert_eq!(element_color("P"), [1.0, 0.5, 0.0]);
    // Any case, charges ignored, metals and unknown symbols.
    assert_eq!(element_color("FE"), element_color("Fe"));
    assert_eq!(element_color("O1-"), element_color("O"));
    assert_eq!(element_color("Pt"), [0.75, 0.60, 0.90]);
    assert_eq!(element_color("Xe"), [1.00, 0.60, 0.75]);
    assert_eq!(element_color("Qq"), [1.00, 0.08, 0.58]);
    assert_eq!(element_color(""), [1.00, 0.08, 0.58]);
}

#[test]
fn pdb_element_inferred_from_the_atom_name_without_columns_77_78() {
    // " CA " (blank in column 13) is an alpha carbon; "CA  " is calcium.
    let strip = |line: String| line[..66].to_string() + "\n";
    let text = [
        strip(atom("ATOM", 1, " CA ", "ALA", 1, [0.0, 0.0, 0.0], "")),
        anisou(1, " CA ", "ALA", 1, [100, 100, 100, 0, 0, 0], ""),
        strip(atom("HETATM", 2, "CA  ", " CA", 2, [3.0, 0.0, 0.0], "")),
        anisou(2, "CA  ", " CA", 2, [100, 100, 100, 0, 0, 0], ""),
        strip(atom("ATOM", 3, "1HB ", "ALA", 1, [6.0, 0.0, 0.0], "")),
        anisou(3, "1HB ", "ALA", 1, [100, 100, 100, 0, 0, 0], ""),
    ]
    .concat();
    let loaded = parse(&text, "short.pdb");
    let colors: Vec<_> = loaded.scene.ellipsoids.iter().map(|e| e.color).collect();
    assert_eq!(
        colors,
        [element_color("C"), element_color("Ca"), element_color("H")]
    );
}

#[test]
fn pdb_records_in_any_order_with_crlf_and_only_the_first_model() {
    let first = three_atoms();
    // ANISOU before its ATOM, CRLF line ends.
    let lines: Vec<&str> = first.lines().collect();
    let reordered = [lines[1], lines[0], lines[3], lines[2], lines[5], lines[4]].join("\r\n");
    let loaded = parse(&reordered, "crlf.pdb");
    assert_eq!(loaded.scene, parse(&first, "a.pdb").scene);

    let models = format!("MODEL        1\n{first}ENDMDL\nMODEL        2\n{first}ENDMDL\nEND\n");
    let loaded = parse(&models, "models.pdb");
    assert_eq!(loaded.scene.len(), 3);
    assert_note(&loaded.notes, "2 models");
}

#[test]
fn pdb_anisou_matches_despite_spacing_but_not_another_atom() {
    // The same identifiers with different spacing (name left-justified) still match by serial.
    let text = atom("ATOM", 1, " N  ", "ALA", 1, [0.0, 0.0, 0.0], "N")
        + &anisou(1, "N   ", "ALA", 1, [100, 100, 100, 0, 0, 0], "N");
    assert_eq!(parse(&text, "a.pdb").scene.len(), 1);
    // Same serial, different atom name: not its atom.
    let text = atom("ATOM", 1, " N  ", "ALA", 1, [0.0, 0.0, 0.0], "N")
        + &anisou(1, " CB ", "ALA", 1, [100, 100, 100, 0, 0, 0], "N");
    let message = assert_err(
        &text,
        "a.pdb",
        2,
        "serial (columns 7-11)",
        &[
            "ANISOU for atom 1 CB (ALA A 1)",
            "atom 1 N (ALA A 1) (line 1)",
        ],
    );
    println!("{message}");
}

#[test]
fn mmcif_syntax_quotes_text_fields_uncertainties_b_values_and_single_items() {
    let text = "\
# leading comment
data_test
_struct.title
;A text field with 'quotes' and
data_ that is not a block header
;
_exptl.method 'X-RAY DIFFRACTION'
save_frame
_dictionary.item value
save_
loop_
_ATOM_SITE.id
_atom_site.type_symbol
_atom_site.label_atom_id
_atom_site.label_comp_id
_atom_site.auth_asym_id
_atom_site.auth_seq_id
_atom_site.Cartn_x
_atom_site.Cartn_y
_atom_site.Cartn_z
a1 N \"N'\" ALA A 1 1.0(2) 2.0 3.0 # comment after a row
a2 FE FE   HEM A 2 4.0 5.0(11) 6.0
loop_
_atom_site_anisotrop.id
_atom_site_anisotrop.B[1][1]
_atom_site_anisotrop.B[2][2]
_atom_site_anisotrop.B[3][3]
_atom_site_anisotrop.B[1][2]
_atom_site_anisotrop.B[1][3]
_atom_site_anisotrop.B[2][3]
a1 1.5791 1.5791 1.5791 0 0 0
a2 3.1583(5) 1.5791 1.5791 0.0 0.0 0.0
data_second
_atom_site.bogus 1
";
    let loaded = parse(text, "x.cif");
    assert_eq!(loaded.scene.len(), 2);
    let u = 1.5791 / (8.0 * std::f64::consts::PI.powi(2));
    let c2 = PROBABILITY_50_SCALE * PROBABILITY_50_SCALE;
    assert_mat_close(
        shape(&loaded.scene.ellipsoids[0]),
        u_matrix([u, u, u, 0.0, 0.0, 0.0]) * c2,
        1e-12,
    );
    assert_eq!(loaded.scene.ellipsoids[1].center, DVec3::new(4.0, 5.0, 6.0));
    assert_eq!(loaded.scene.ellipsoids[1].color, element_color("Fe"));
    assert_contains(&loaded.notes.join("\n"), &["B[i][j]", "data_second"]);

    // Single items and inline aniso_U in _atom_site; a `data_` first line picks mmCIF.
    let single = "data_one\n_atom_site.id 1\n_atom_site.type_symbol S\n_atom_site.Cartn_x 1\n\
                  _atom_site.Cartn_y 2\n_atom_site.Cartn_z 3\n_atom_site.aniso_U[1][1] 0.02\n\
                  _atom_site.aniso_U[2][2] 0.03\n_atom_site.aniso_U[3][3] 0.04\n\
                  _atom_site.aniso_U[1][2] 0.001\n_atom_site.aniso_U[1][3] ?\n\
                  _atom_site.aniso_U[2][3] 0\n";
    let err = assert_err(
        single,
        "no-extension",
        11,
        "_atom_site.aniso_U[1][3]",
        &["atom 1", "has no value (\"?\")"],
    );
    println!("{err}");
    let loaded = parse(&single.replace(" ?\n", " 0.0\n"), "no-extension");
    assert_eq!(loaded.scene.len(), 1);
    assert_eq!(loaded.scene.ellipsoids[0].color, element_color("S"));
}

#[test]
fn mmcif_only_the_first_model_and_unknown_anisotropic_rows() {
    let text = "data_m
loop_
_atom_site.id
_atom_site.type_symbol
_atom_site.Cartn_x
_atom_site.Cartn_y
_atom_site.Cartn_z
_atom_site.pdbx_PDB_model_num
1 C 0 0 0 1
2 C 3 0 0 1
3 C 0 0 0 2
loop_
_atom_site_anisotrop.id
_atom_site_anisotrop.U[1][1]
_atom_site_anisotrop.U[2][2]
_atom_site_anisotrop.U[3][3]
_atom_site_anisotrop.U[1][2]
_atom_site_anisotrop.U[1][3]
_atom_site_anisotrop.U[2][3]
1 0.02 0.02 0.02 0 0 0
2 ? ? ? ? ? ?
3 0.02 0.02 0.02 0 0 0
";
    let loaded = parse(text, "m.cif");
    assert_eq!(loaded.scene.len(), 1);
    assert_contains(
        &loaded.notes.join("\n"),
        &["first model (1)", "left out 1 atom(s)"],
    );
}

// ---------------------------------------------------------------------------------------------
// rejected input: one test per case, asserting the message

#[test]
fn empty_file() {
    for text in ["", "  \n\n\t\r\n"] {
        let message = assert_err(text, "empty.pdb", 0, "file", &["empty file"]);
        assert_eq!(
            message,
            "empty.pdb:0:file: empty file: no PDB or mmCIF records (nothing but white space)"
        );
    }
    // Comments only, as mmCIF.
    assert_err("# nothing\n", "c.cif", 0, "data_", &["no data_ block"]);
}

#[test]
fn binary_garbage() {
    let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x10";
    let message = parse_err_bytes(png, "image.pdb", &LoadOptions::default()).assert_at(
        2,
        "column 1",
        &["binary data", "0x1a"],
    );
    println!("{message}");
    let gzip = b"\x1f\x8b\x08\x00\x00\x00\x00\x00";
    let reason = parse_err_bytes(gzip, "x.cif", &LoadOptions::default()).reason;
    assert!(reason.contains("gzip"), "{reason}");
    // Invalid UTF-8 in an mmCIF file.
    let e = parse_err_bytes(b"data_x\n_a.b \xff\xfe\n", "x.cif", &LoadOptions::default());
    assert_eq!(e.line, 2);
    assert!(e.reason.contains("invalid UTF-8"), "{}", e.reason);
    // Non-ASCII in a fixed-column PDB record.
    let text = atom("ATOM", 1, " N  ", "ALA", 1, [0.0, 0.0, 0.0], "N").replace("ALA", "ÄLA");
    assert_err(&text, "a.pdb", 1, "column 18", &["non-ASCII byte 0xc3"]);
}

#[test]
fn anisou_with_a_non_numeric_field() {
    let text = three_atoms().replace("   1892", "   18x2");
    let message = assert_err(
        &text,
        "ala.pdb",
        2,
        "U22 (columns 36-42)",
        &["not an integer: \"18x2\""],
    );
    assert_eq!(
        message,
        "ala.pdb:2:U22 (columns 36-42): ANISOU for atom 1 N (ALA A 1): U22 is not an integer: \
         \"18x2\" (U in 10^-4 Å²)"
    );
    // A decimal is not the PDB format either; a short line names the missing field.
    let text = three_atoms().replace("   1892", "  0.189");
    assert_err(&text, "ala.pdb", 2, "U22 (columns 36-42)", &["\"0.189\""]);
    let short = three_atoms_cut(3, 60);
    assert_err(
        &short,
        "ala.pdb",
        4,
        "U13 (columns 57-63)",
        &["atom 2 CA", "line ends at column 60"],
    );
    // In mmCIF: the tag names the field.
    let text = sample_text("thermal.cif").replacen(" 0.0479 ", " 0.04x9 ", 1);
    let message = assert_err(
        &text,
        "thermal.cif",
        92,
        "_atom_site_anisotrop.U[1][1]",
        &["atom 1 N1 (GSH A 1)", "is not a number: \"0.04x9\""],
    );
    println!("{message}");
}

/// With `skip_invalid`, `text` loads `ellipsoids` thermal ellipsoids, one record skipped, and the
/// last note names the error `message` that record gives without the option.
fn assert_skipped_one(text: &str, file: &str, ellipsoids: usize, message: &str) -> Loaded {
    let loaded = parse_with(text, file, &skipping()).unwrap();
    assert_eq!((loaded.scene.len(), loaded.skipped), (ellipsoids, 1));
    assert_eq!(
        loaded.notes.last(),
        Some(&format!(
            "skipped 1 invalid record(s); the first: {message}"
        ))
    );
    loaded
}

#[test]
fn anisou_without_a_matching_atom() {
    let text = three_atoms() + &anisou(7, " CB ", "ALA", 1, [100, 100, 100, 0, 0, 0], "C");
    let message = assert_err(
        &text,
        "ala.pdb",
        7,
        "serial (columns 7-11)",
        &["ANISOU for atom 7 CB (ALA A 1) has no matching ATOM/HETATM record"],
    );
    assert_eq!(
        message,
        "ala.pdb:7:serial (columns 7-11): ANISOU for atom 7 CB (ALA A 1) has no matching \
         ATOM/HETATM record (no atom with serial 7)"
    );
    // With skip_invalid the stray record is counted, named in the notes, and the atoms load.
    assert_skipped_one(&text, "ala.pdb", 3, &message);
    // mmCIF: an _atom_site_anisotrop row whose id is not an _atom_site.id.
    let text = sample_text("thermal.cif").replacen("\n37 ", "\n99 ", 1);
    let message = assert_err(
        &text,
        "thermal.cif",
        112,
        "_atom_site_anisotrop.id",
        &["id \"99\" has no matching _atom_site row"],
    );
    // Skipped, the row goes and its atom (water 37) has no anisotropic parameters left.
    let loaded = assert_skipped_one(&text, "thermal.cif", 21, &message);
    assert_note(&loaded.notes, "left out 17 atom(s)");
    // A second ANISOU for the same atom.
    let text = three_atoms() + &anisou(3, " O  ", "ALA", 1, [100, 100, 100, 0, 0, 0], "O");
    assert_err(
        &text,
        "ala.pdb",
        7,
        "U11..U23 (columns 29-70)",
        &[
            "second set of anisotropic parameters for atom 3 O (ALA A 1)",
            "line 6",
        ],
    );
}

#[test]
fn non_finite_coordinates() {
    let text = three_atoms().replace("  11.639", "     NaN");
    let message = assert_err(
        &text,
        "ala.pdb",
        3,
        "x (columns 31-38)",
        &["ATOM record for atom 2 CA (ALA A 1): x coordinate is not finite: \"NaN\""],
    );
    assert_eq!(
        message,
        "ala.pdb:3:x (columns 31-38): ATOM record for atom 2 CA (ALA A 1): x coordinate is not \
         finite: \"NaN\""
    );
    let text = three_atoms().replace("  -5.147", "     inf");
    assert_err(
        &text,
        "ala.pdb",
        3,
        "z (columns 47-54)",
        &["not finite: \"inf\""],
    );
    // Skipped: the atom and its ANISOU go, counted once.
    let loaded = parse_with(&text, "ala.pdb", &skipping()).unwrap();
    assert_eq!((loaded.scene.len(), loaded.skipped), (2, 1));
    // mmCIF.
    let text = sample_text("thermal.cif").replacen("   8.155   10.140", "   8.155 Infinity", 1);
    assert_err(
        &text,
        "thermal.cif",
        34,
        "_atom_site.Cartn_z",
        &["atom 1 N1 (GSH A 1)", "is not finite: \"Infinity\""],
    );
    // A line too short for the coordinates.
    let text = three_atoms_cut(4, 50);
    assert_err(
        &text,
        "ala.pdb",
        5,
        "z (columns 47-54)",
        &["atom 3 O", "missing: the line ends at column 50"],
    );
}

#[test]
fn non_positive_definite_u() {
    // U12 = 2000 with U11 = 1600, U22 = 1500: det of the 2x2 block < 0.
    let text = three_atoms().replace("    100     50    -20", "   2000     50    -20");
    let message = assert_err(
        &text,
        "ala.pdb",
        4,
        "U11..U23 (columns 29-70)",
        &[
            "atom 2 CA (ALA A 1): U is not positive definite",
            "eigenvalues",
        ],
    );
    println!("{message}");
    assert!(
        message.contains("-0.0"),
        "negative eigenvalue shown: {message}"
    );

    let loaded = parse_with(&text, "ala.pdb", &skipping()).unwrap();
    assert_eq!((loaded.scene.len(), loaded.skipped), (2, 1));
    let note = loaded
        .notes
        .iter()
        .find(|n| n.starts_with("skipped 1 invalid record(s)"))
        .unwrap_or_else(|| panic!("{:?}", loaded.notes));
    assert!(note.contains("ala.pdb:4:"), "{note}");

    // A zero U and a singular one are not positive definite either.
    let zero = three_atoms().replace(
        "   1600   1500   1400    100     50    -20",
        &"      0".repeat(6),
    );
    assert_err(
        &zero,
        "ala.pdb",
        4,
        "U11..U23 (columns 29-70)",
        &["U is zero"],
    );
    let singular = three_atoms().replace(
        "   1600   1500   1400    100     50    -20",
        "   1000   1000   1000   1000   1000   1000",
    );
    assert_err(
        &singular,
        "ala.pdb",
        4,
        "U11..U23 (columns 29-70)",
        &["not positive definite"],
    );

    // All atoms invalid with skip_invalid: nothing left is an error that says why.
    let all_bad = three_atoms()
        .replace("  1892", " -1892")
        .replace("  1500", " -1500")
        .replace("  1200", " -1200");
    let message = assert_err_with(
        &all_bad,
        "ala.pdb",
        &skipping(),
        0,
        "ANISOU",
        &[
            "no valid anisotropic atoms: 3 invalid record(s) skipped",
            "ala.pdb:2:",
        ],
    );
    println!("{message}");

    // mmCIF: the row's line and the U columns.
    let text = sample_text("thermal.cif").replacen(
        " 0.0479  0.0457  0.0671 ",
        " 0.0479  0.0457 -0.0671 ",
        1,
    );
    assert_err(
        &text,
        "thermal.cif",
        92,
        "_atom_site_anisotrop.U[1][1].._atom_site_anisotrop.U[2][3]",
        &["atom 1 N1 (GSH A 1): U is not positive definite"],
    );
}

#[test]
fn no_anisotropic_atoms() {
    let text: String = three_atoms()
        .lines()
        .filter(|l| l.starts_with("ATOM"))
        .map(|l| format!("{l}\n"))
        .collect();
    let message = assert_err(&text, "iso.pdb", 0, "ANISOU", &["no anisotropic atoms"]);
    assert_eq!(
        message,
        "iso.pdb:0:ANISOU: no anisotropic atoms: none of the 3 atom(s) has ANISOU parameters \
         (isotropic B only), so there are no thermal ellipsoids to draw"
    );
    // No atoms at all.
    assert_err(
        "HEADER    NOTHING\nREMARK   1 EMPTY\nEND\n",
        "none.pdb",
        0,
        "ATOM/HETATM",
        &["no atoms"],
    );
    // mmCIF without the anisotropic category.
    let cif = sample_text("thermal.cif");
    let cut = &cif[..cif.find("loop_\n_atom_site_anisotrop").unwrap()];
    assert_err(
        cut,
        "thermal.cif",
        0,
        "_atom_site_anisotrop",
        &["none of the 38 atom(s)"],
    );
}

#[test]
fn truncated_mmcif_loop() {
    let cif = sample_text("thermal.cif");
    // Cut the file in the middle of the 10th _atom_site row, after Cartn_x.
    let row = cif.find("\nHETATM 10 ").unwrap() + 1;
    let cut = row + cif[row..].find("  2.665 ").unwrap() + "  2.665 ".len();
    let message = assert_err(
        &cif[..cut],
        "thermal.cif",
        43,
        "_atom_site.Cartn_y",
        &[
            "truncated loop_",
            "has only 11 of 21 values",
            "missing _atom_site.Cartn_y and 9 more",
        ],
    );
    println!("{message}");
    // Cut right after the anisotrop loop's header: no values.
    let header_end = cif.find("pdbx_auth_atom_id\n").unwrap() + "pdbx_auth_atom_id\n".len();
    assert_err(
        &cif[..header_end],
        "thermal.cif",
        73,
        "_atom_site_anisotrop.id",
        &["loop_ with 18 tag(s) has no values"],
    );
    // Unterminated quote and text field.
    assert_err(
        "data_x\n_a.b 'open\n",
        "q.cif",
        2,
        "quoted string",
        &["unterminated quoted string"],
    );
    assert_err(
        "data_x\n_a.b\n;text\nmore\n",
        "q.cif",
        3,
        "text field",
        &["unterminated text field"],
    );
    // A tag without a value at the end, a value without a tag.
    assert_err(
        "data_x\n_a.b 1\n_a.c\n",
        "q.cif",
        3,
        "_a.c",
        &["has no value"],
    );
    assert_err(
        "data_x\n_a.b 1 2\n",
        "q.cif",
        2,
        "value",
        &["\"2\" without a tag"],
    );
}

#[test]
fn mmcif_structure_problems() {
    // Not starting with data_ (but named .cif).
    assert_err(
        "loop_\n_a.b\n1\n",
        "x.cif",
        1,
        "data_",
        &["must start with a data_ block header"],
    );
    // Missing coordinate column.
    let text = "data_x\nloop_\n_atom_site.id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n1 0 0\n";
    assert_err(
        text,
        "x.cif",
        2,
        "_atom_site.Cartn_z",
        &["no Cartn_z column"],
    );
    // Some U columns but not all.
    let text = "data_x\nloop_\n_atom_site.id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n\
                _atom_site.Cartn_z\n1 0 0 0\nloop_\n_atom_site_anisotrop.id\n\
                _atom_site_anisotrop.U[1][1]\n1 0.02\n";
    assert_err(
        text,
        "x.cif",
        8,
        "_atom_site_anisotrop.U[2][2]",
        &["not _atom_site_anisotrop.U[2][2]"],
    );
    // coreCIF.
    let text = "data_x\nloop_\n_atom_site_label\n_atom_site_fract_x\nC1 0.5\n";
    assert_err(
        text,
        "x.cif",
        4,
        "_atom_site_fract_x",
        &["small-molecule (core) CIF is not supported"],
    );
    // Duplicate _atom_site.id.
    let text = "data_x\nloop_\n_atom_site.id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n\
                _atom_site.Cartn_z\n_atom_site.aniso_U[1][1]\n_atom_site.aniso_U[2][2]\n\
                _atom_site.aniso_U[3][3]\n_atom_site.aniso_U[1][2]\n_atom_site.aniso_U[1][3]\n\
                _atom_site.aniso_U[2][3]\n\
                1 0 0 0 0.02 0.02 0.02 0 0 0\n1 1 0 0 0.02 0.02 0.02 0 0 0\n";
    assert_err(
        text,
        "x.cif",
        14,
        "_atom_site.id",
        &["duplicate _atom_site.id \"1\" (also on line 13)"],
    );
}

// ---------------------------------------------------------------------------------------------
// hostile input

/// Parses `bytes` as both dialects and with both skip settings; anything but a panic is fine,
/// and an error must be a parse error.
fn must_not_panic(bytes: &[u8]) {
    for file in ["f.pdb", "f.cif", "f"] {
        for options in [LoadOptions::default(), skipping()] {
            match parse_structure(bytes, Path::new(file), &options) {
                Ok(loaded) => assert!(!loaded.scene.is_empty()),
                Err(Error::Parse { .. }) => {}
                Err(other) => panic!("not a parse error: {other:?}"),
            }
        }
    }
}

#[test]
fn every_truncation_of_the_samples_is_handled() {
    for name in ["thermal.pdb", "thermal.cif"] {
        let bytes = std::fs::read(sample(name)).unwrap();
        for end in 0..bytes.len() {
            must_not_panic(&bytes[..end]);
        }
    }
}

#[test]
fn mutated_samples_and_random_bytes_do_not_panic() {
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let pieces: [&[u8]; 16] = [
        b"NaN",
        b"inf",
        b"-",
        b"'",
        b"\"",
        b"\n;",
        b";",
        b"#",
        b"loop_\n",
        b"_atom_site.id ",
        b"data_",
        b"save_x ",
        b"\xc3\xa9",
        b"\xff",
        b"ANISOU",
        b"ATOM  ",
    ];
    for name in ["thermal.pdb", "thermal.cif"] {
        let original = std::fs::read(sample(name)).unwrap();
        for _ in 0..1500 {
            let mut bytes = original.clone();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(bytes.len());
                match rng.below(4) {
                    0 => bytes[at] = rng.byte(),
                    1 => {
                        bytes.remove(at);
                    }
                    2 => {
                        let piece = pieces[rng.below(pieces.len())];
                        bytes.splice(at..at, piece.iter().copied());
                    }
                    _ => {
                        // Swap two lines' worth of bytes: records out of place.
                        let other = rng.below(bytes.len());
                        bytes.swap(at, other);
                    }
                }
            }
            must_not_panic(&bytes);
        }
    }
    for _ in 0..500 {
        let len = rng.below(300);
        let bytes = rng.bytes(len);
        must_not_panic(&bytes);
        // Printable garbage too, which passes the binary check.
        let text: Vec<u8> = (0..len)
            .map(|_| b" \n_.;'\"#data_loop_ATOMANISOU0123456789-"[rng.below(39)])
            .collect();
        must_not_panic(&text);
    }
}

#[test]
fn inputs_that_make_pdbtbx_panic_are_loaded_or_reported() {
    // pdbtbx 0.12 panics on each of these (see the module documentation of `pdb`).
    let cryst = "CRYST1   10.000   10.000   10.000  90.00  90.00  90.00 Q 9 9 9       1\n";
    assert_eq!(
        parse(&(cryst.to_string() + &three_atoms()), "a.pdb")
            .scene
            .len(),
        3
    );
    assert_err("ATOMX\u{e9} 1\n", "a.pdb", 0, "ATOM/HETATM", &["no atoms"]);
    let head = "data_x\nloop_\n_atom_site.id\n_atom_site.type_symbol\n_atom_site.label_atom_id\n\
                _atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n\
                _atom_site.aniso_U[1][1]\n_atom_site.aniso_U[2][2]\n_atom_site.aniso_U[3][3]\n\
                _atom_site.aniso_U[1][2]\n_atom_site.aniso_U[1][3]\n_atom_site.aniso_U[2][3]\n";
    // An unknown element: inferred from the atom name.
    let loaded = parse(
        &format!("{head}1 ? N 1 2 3 0.02 0.02 0.02 0 0 0\n"),
        "x.cif",
    );
    assert_eq!(loaded.scene.ellipsoids[0].color, element_color("N"));
    // An unknown or NaN coordinate: reported on its line.
    assert_err(
        &format!("{head}1 N N ? 2 3 0.02 0.02 0.02 0 0 0\n"),
        "x.cif",
        15,
        "_atom_site.Cartn_x",
        &["atom 1 N: _atom_site.Cartn_x has no value (\"?\")"],
    );
    assert_err(
        &format!("{head}1 N N nan 2 3 0.02 0.02 0.02 0 0 0\n"),
        "x.cif",
        15,
        "_atom_site.Cartn_x",
        &["is not finite: \"nan\""],
    );
}

/// pdbtbx 0.12's reader on `text` at each strictness level: `Err` where it panicked, else its
/// atoms and the messages it returned.
fn pdbtbx_read(text: &str, format: pdbtbx::Format) -> Vec<Result<(usize, Vec<String>), ()>> {
    use pdbtbx::StrictnessLevel::{Loose, Medium, Strict};
    [Strict, Medium, Loose]
        .into_iter()
        .map(|level| {
            let read = std::panic::catch_unwind(|| {
                pdbtbx::ReadOptions::new()
                    .set_format(format)
                    .set_level(level)
                    .read_raw(std::io::BufReader::new(text.as_bytes()))
            })
            .map_err(|_| ())?;
            Ok(match read {
                Ok((pdb, messages)) => (
                    pdb.atom_count(),
                    messages.iter().map(|m| m.to_string()).collect(),
                ),
                Err(messages) => (0, messages.iter().map(|m| m.to_string()).collect()),
            })
        })
        .collect()
}

#[test]
fn pdbtbx_readers_panic_or_lose_the_line_where_this_one_reports_it() {
    // The reason `pdb` reads the files itself (its module documentation): these inputs make
    // pdbtbx panic at every strictness level. The loader's answers are in the test above.
    let cryst = "CRYST1   10.000   10.000   10.000  90.00  90.00  90.00 Q 9 9 9       1\n";
    let unknown_space_group = cryst.to_string() + &three_atoms();
    let head = "data_x\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n\
                _atom_site.label_atom_id\n_atom_site.label_alt_id\n_atom_site.label_comp_id\n\
                _atom_site.label_asym_id\n_atom_site.label_seq_id\n_atom_site.Cartn_x\n\
                _atom_site.Cartn_y\n_atom_site.Cartn_z\n_atom_site.occupancy\n\
                _atom_site.B_iso_or_equiv\n_atom_site.pdbx_PDB_model_num\n";
    let cif_unknown_x = format!("{head}ATOM 1 N N . ALA A 1 ? 2 3 1 20 1\n");
    let cif_nan_x = format!("{head}ATOM 1 N N . ALA A 1 nan 2 3 1 20 1\n");
    for (what, text, format) in [
        (
            "unknown CRYST1 space group",
            &unknown_space_group,
            pdbtbx::Format::Pdb,
        ),
        (
            "mmCIF '?' coordinate",
            &cif_unknown_x,
            pdbtbx::Format::Mmcif,
        ),
        ("mmCIF NaN coordinate", &cif_nan_x, pdbtbx::Format::Mmcif),
    ] {
        let outcomes = pdbtbx_read(text, format);
        assert!(outcomes.iter().all(Result::is_err), "{what}: {outcomes:?}");
    }
    // The same files with the fault mended read without a panic.
    for (text, format) in [
        (three_atoms(), pdbtbx::Format::Pdb),
        (
            cif_unknown_x.replace(" ? 2 3 ", " 1 2 3 "),
            pdbtbx::Format::Mmcif,
        ),
    ] {
        let outcomes = pdbtbx_read(&text, format);
        assert!(outcomes.iter().all(Result::is_ok), "{text}: {outcomes:?}");
    }
    // An ANISOU that matches no atom: pdbtbx reads the three atoms and tells its caller
    // nothing about the stray record or its line 7.
    let stray = three_atoms() + &anisou(7, " CB ", "ALA", 1, [100, 100, 100, 0, 0, 0], "C");
    for outcome in pdbtbx_read(&stray, pdbtbx::Format::Pdb) {
        let (atoms, messages) = outcome.expect("no panic on a stray ANISOU");
        assert_eq!(atoms, 3);
        assert!(
            !messages.iter().any(|m| m.contains("ANISOU")),
            "{messages:?}"
        );
    }
    let e = parse_err_bytes(stray.as_bytes(), "ala.pdb", &LoadOptions::default());
    e.assert_at(
        7,
        "serial (columns 7-11)",
        &["has no matching ATOM/HETATM record"],
    );
}
