//! The 3D Gaussian Splatting PLY loader: the property conventions of the reference
//! implementation (Kerbl et al. 2023), binary little- and big-endian and ASCII bodies, skipping of
//! other properties and elements, and a precise error for every malformed input.

mod support;

use std::path::Path;
use std::time::Instant;

use ellipsoid_splat_loaders::ply::{load_ply, parse_ply, SH_C0, SPLAT_PROPERTIES};
use ellipsoid_splat_loaders::Error;
use ellipsoid_splat_loaders::{load, LoadOptions, Loaded};
use glam::{DQuat, DVec3};
use support::{
    assert_close, assert_io_error, loaded, options, parse_error, sample, skipping, ParseError, Rng,
};

const FILE: &str = "scene.ply";

/// One splat as the reference implementation stores it.
#[derive(Clone, Copy, Debug)]
struct Splat {
    center: [f64; 3],
    log_scale: [f64; 3],
    /// `w, x, y, z`, unnormalised.
    rot: [f64; 4],
    /// Logit.
    opacity: f64,
    f_dc: [f64; 3],
}

impl Splat {
    fn new(center: [f64; 3]) -> Self {
        Self {
            center,
            log_scale: [-2.0, -2.5, -3.0],
            rot: [1.0, 0.0, 0.0, 0.0],
            opacity: 3.0,
            f_dc: [0.5, -0.25, 1.0],
        }
    }

    /// The values of [`SPLAT_PROPERTIES`].
    fn values(&self) -> [f64; 14] {
        let mut v = [0.0; 14];
        v[..3].copy_from_slice(&self.center);
        v[3..6].copy_from_slice(&self.log_scale);
        v[6..10].copy_from_slice(&self.rot);
        v[10] = self.opacity;
        v[11..].copy_from_slice(&self.f_dc);
        v
    }
}

/// A few distinct, valid splats.
fn splats(n: usize) -> Vec<Splat> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            let mut s = Splat::new([t, -0.5 * t, 0.25 * t + 1.0]);
            s.log_scale = [-2.0 + 0.1 * t, -2.5, -3.0 - 0.05 * t];
            s.rot = [1.0 + t, 0.5, -0.25 * t, 0.125];
            s.opacity = 2.0 - 0.3 * t;
            s.f_dc = [0.1 * t, -0.2, 0.3];
            s
        })
        .collect()
}

/// The reference property list (all float): 62 properties, 248 bytes per splat.
fn reference_properties() -> Vec<(String, String)> {
    let mut names: Vec<String> = ["x", "y", "z", "nx", "ny", "nz"].map(String::from).to_vec();
    names.extend((0..3).map(|i| format!("f_dc_{i}")));
    names.extend((0..45).map(|i| format!("f_rest_{i}")));
    names.push("opacity".into());
    names.extend((0..3).map(|i| format!("scale_{i}")));
    names.extend((0..4).map(|i| format!("rot_{i}")));
    names.into_iter().map(|n| ("float".into(), n)).collect()
}

/// Only the required properties, as floats.
fn minimal_properties() -> Vec<(String, String)> {
    SPLAT_PROPERTIES
        .iter()
        .map(|n| ("float".to_string(), n.to_string()))
        .collect()
}

fn props(list: &[(&str, &str)]) -> Vec<(String, String)> {
    list.iter()
        .map(|(t, n)| (t.to_string(), n.to_string()))
        .collect()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Enc {
    Le,
    Be,
    Ascii,
}

impl Enc {
    fn format(self) -> &'static str {
        match self {
            Enc::Le => "binary_little_endian",
            Enc::Be => "binary_big_endian",
            Enc::Ascii => "ascii",
        }
    }
}

/// The value of property `name` for splat `s`; other properties get a filler that would show
/// if they were not skipped correctly.
fn value_of(name: &str, s: &Splat, i: usize) -> f64 {
    match SPLAT_PROPERTIES.iter().position(|p| *p == name) {
        Some(f) => s.values()[f],
        None => 100.0 + (i % 50) as f64,
    }
}

/// Binary bytes of `value` as PLY type `ty`.
fn encode(ty: &str, value: f64, enc: Enc) -> Vec<u8> {
    macro_rules! bytes {
        ($v:expr) => {
            if enc == Enc::Be {
                $v.to_be_bytes().to_vec()
            } else {
                $v.to_le_bytes().to_vec()
            }
        };
    }
    match ty {
        "char" | "int8" => bytes!(value as i8),
        "uchar" | "uint8" => bytes!(value as u8),
        "short" | "int16" => bytes!(value as i16),
        "ushort" | "uint16" => bytes!(value as u16),
        "int" | "int32" => bytes!(value as i32),
        "uint" | "uint32" => bytes!(value as u32),
        "float" | "float32" => bytes!(value as f32),
        "double" | "float64" => bytes!(value),
        other => panic!("unknown type {other}"),
    }
}

/// ASCII text of `value` as PLY type `ty`.
fn ascii(ty: &str, value: f64) -> String {
    if ty.starts_with("float") || ty == "double" {
        format!("{value}")
    } else {
        format!("{}", value as i64)
    }
}

/// The header lines of a one-element file (without `end_header`).
fn header(enc: Enc, count: impl std::fmt::Display, properties: &[(String, String)]) -> String {
    let mut h = format!("ply\nformat {} 1.0\nelement vertex {count}\n", enc.format());
    for (t, n) in properties {
        h += &format!("property {t} {n}\n");
    }
    h
}

/// A file with one `vertex` element holding `rows` (raw values per property).
fn ply_rows(enc: Enc, properties: &[(String, String)], rows: &[Vec<f64>]) -> Vec<u8> {
    let mut out = header(enc, rows.len(), properties).into_bytes();
    out.extend_from_slice(b"end_header\n");
    for row in rows {
        if enc == Enc::Ascii {
            let line: Vec<String> = properties
                .iter()
                .zip(row)
                .map(|((t, _), v)| ascii(t, *v))
                .collect();
            out.extend_from_slice(line.join(" ").as_bytes());
            out.push(b'\n');
        } else {
            for ((t, _), v) in properties.iter().zip(row) {
                out.extend(encode(t, *v, enc));
            }
        }
    }
    out
}

fn rows_of(properties: &[(String, String)], splats: &[Splat]) -> Vec<Vec<f64>> {
    splats
        .iter()
        .map(|s| {
            properties
                .iter()
                .enumerate()
                .map(|(i, (_, n))| value_of(n, s, i))
                .collect()
        })
        .collect()
}

fn ply(enc: Enc, properties: &[(String, String)], splats: &[Splat]) -> Vec<u8> {
    ply_rows(enc, properties, &rows_of(properties, splats))
}

fn parse_with(bytes: &[u8], options: &LoadOptions) -> Loaded {
    loaded(parse_ply(bytes, Path::new(FILE), options), bytes)
}

fn parse(bytes: &[u8]) -> Loaded {
    parse_with(bytes, &LoadOptions::default())
}

/// Parses `bytes`, expecting a parse error naming [`FILE`].
fn parse_err_with(bytes: &[u8], options: &LoadOptions) -> ParseError {
    parse_error(
        parse_ply(bytes, Path::new(FILE), options),
        Path::new(FILE),
        bytes,
    )
}

/// Asserts the error's line and column, and that the reason contains every one of `words`.
/// Returns the full message.
fn assert_err(bytes: &[u8], line: usize, column: &str, words: &[&str]) -> String {
    parse_err_with(bytes, &LoadOptions::default()).assert_at(line, column, words)
}

/// As [`assert_err`], and the error stays with `skip_invalid` (structural errors).
fn assert_structural(bytes: &[u8], line: usize, column: &str, words: &[&str]) -> String {
    let message = assert_err(bytes, line, column, words);
    parse_err_with(bytes, &skipping()).assert_at(line, column, &[]);
    message
}

fn same_rotation(a: DQuat, b: DQuat, tol: f64) -> bool {
    a.dot(b).abs() >= 1.0 - tol
}

/// Checks `loaded` holds `splats` converted with `sigma` (f32 precision).
fn assert_matches(loaded: &Loaded, splats: &[Splat], sigma: f64) {
    assert_eq!(loaded.scene.len(), splats.len());
    for (e, s) in loaded.scene.ellipsoids.iter().zip(splats) {
        let tol = 1e-5;
        assert_close(e.center, DVec3::from_array(s.center), tol * 10.0);
        let radii = DVec3::from_array(s.log_scale.map(|l| sigma * l.exp()));
        assert!(
            ((e.radii - radii) / radii).abs().max_element() < tol,
            "{} vs {radii}",
            e.radii
        );
        let [w, x, y, z] = s.rot;
        let q = DQuat::from_xyzw(x, y, z, w).normalize();
        assert!(same_rotation(e.rotation, q, 1e-6), "{} vs {q}", e.rotation);
        for c in 0..3 {
            let want = (0.5 + SH_C0 * s.f_dc[c]).clamp(0.0, 1.0) as f32;
            assert!((e.color[c] - want).abs() < 1e-5, "{:?}", e.color);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Accepted files

#[test]
fn sample_binary_file_loads() {
    let path = sample("splats.ply");
    let loaded = load_ply(&path, &LoadOptions::default()).unwrap();
    assert_eq!(loaded.scene.len(), 3032);
    assert_eq!(loaded.skipped, 0);
    assert_eq!(
        loaded.notes,
        vec!["radii = 2 sigma: semi-axes are 2 * exp(scale) (--sigma)".to_string()]
    );
    // The torus (major radius 1, minor 0.35) and the floaters stay within these bounds.
    let (lo, hi) = loaded.scene.bounds().unwrap();
    assert!(
        lo.min_element() > -1.5 && hi.max_element() < 1.5,
        "{lo} {hi}"
    );

    // The faint floaters go with --min-opacity.
    let options = options(|o| {
        o.min_opacity = 0.05;
        o.progress = true;
    });
    let loaded = load_ply(&path, &options).unwrap();
    assert_eq!(loaded.scene.len(), 2932);
    assert_eq!(
        loaded.notes[1],
        "left out 100 of 3032 splat(s) with opacity below 0.05 (--min-opacity)"
    );

    // The dispatcher picks this loader by extension.
    let dispatched = load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(dispatched.scene.len(), 3032);
}

#[test]
fn sample_ascii_file_loads() {
    let path = sample("splats_ascii.ply");
    let loaded = load(&path, &LoadOptions::default()).unwrap();
    let e = &loaded.scene.ellipsoids;
    assert_eq!(e.len(), 5);
    // The white centre: radii 0.08 at 2 sigma.
    assert_close(e[0].radii, DVec3::splat(0.08), 1e-6);
    assert!(e[0].color.iter().all(|&c| (c - 0.95).abs() < 1e-4));
    // The green splat is long along world y: its local x axis is turned onto y.
    assert_close(e[2].axes().x_axis, DVec3::Y, 1e-6);
    assert_close(e[2].radii, DVec3::new(0.25, 0.05, 0.05), 1e-6);
    assert_close(e[3].axes().x_axis, DVec3::Z, 1e-6);
    let options = options(|o| o.min_opacity = 0.1);
    assert_eq!(load_ply(&path, &options).unwrap().scene.len(), 4);
}

#[test]
fn conventions_of_the_reference_implementation() {
    let mut s = Splat::new([1.0, 2.0, 3.0]);
    s.log_scale = [0.0, 1.0f64.ln(), 0.5f64.ln()];
    // Unnormalised w, x, y, z: 90 degrees about z.
    s.rot = [2.0, 0.0, 0.0, 2.0];
    // Colours: mid grey, clamped to 1, clamped to 0.
    s.f_dc = [0.0, 10.0, -10.0];
    for sigma in [1.0, 2.0, 3.0] {
        let options = options(|o| o.sigma = sigma);
        let loaded = parse_with(&ply(Enc::Le, &minimal_properties(), &[s]), &options);
        let e = loaded.scene.ellipsoids[0];
        assert_close(e.center, DVec3::new(1.0, 2.0, 3.0), 0.0);
        assert_close(e.radii, DVec3::new(sigma, sigma, 0.5 * sigma), 1e-7);
        let want = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
        assert!(same_rotation(e.rotation, want, 1e-12), "{}", e.rotation);
        assert_close(e.axes().x_axis, DVec3::Y, 1e-7);
        assert_eq!(e.color, [0.5, 1.0, 0.0]);
        assert_eq!(
            loaded.notes[0],
            format!("radii = {sigma} sigma: semi-axes are {sigma} * exp(scale) (--sigma)")
        );
    }
    // 0.5 + C0 * f_dc, unclamped in between.
    s.f_dc = [1.0, -1.0, 0.5];
    let e = parse(&ply(Enc::Ascii, &minimal_properties(), &[s]))
        .scene
        .ellipsoids[0];
    let want = [0.5 + 0.28209479, 0.5 - 0.28209479, 0.5 + 0.5 * 0.28209479];
    for (got, want) in e.color.iter().zip(want) {
        assert!((*got as f64 - want).abs() < 1e-6, "{:?}", e.color);
    }
}

#[test]
fn opacity_threshold_uses_the_sigmoid() {
    let mut list = splats(4);
    // sigmoid: 0.5, ~0.119, ~0.881, ~0.0067
    for (s, logit) in list.iter_mut().zip([0.0, -2.0, 2.0, -5.0]) {
        s.opacity = logit;
    }
    let bytes = ply(Enc::Le, &reference_properties(), &list);
    assert_eq!(parse(&bytes).scene.len(), 4);
    for (threshold, kept) in [(0.0, 4), (0.01, 3), (0.2, 2), (0.5, 2), (0.6, 1)] {
        let options = options(|o| o.min_opacity = threshold);
        let loaded = parse_with(&bytes, &options);
        assert_eq!(loaded.scene.len(), kept, "threshold {threshold}");
        if kept < 4 {
            assert_eq!(
                loaded.notes[1],
                format!(
                    "left out {} of 4 splat(s) with opacity below {threshold} (--min-opacity)",
                    4 - kept
                )
            );
        } else {
            assert_eq!(loaded.notes.len(), 1);
        }
    }
    // Everything left out is an error, not an empty scene.
    let options = options(|o| o.min_opacity = 0.99);
    parse_err_with(&bytes, &options).assert_at(3, "vertex", &["no splats left: all 4"]);
}

#[test]
fn every_encoding_and_layout_gives_the_same_splats() {
    let list = splats(7);
    for properties in [minimal_properties(), reference_properties()] {
        for enc in [Enc::Le, Enc::Be, Enc::Ascii] {
            let loaded = parse(&ply(enc, &properties, &list));
            assert_matches(&loaded, &list, 2.0);
            assert_eq!(loaded.skipped, 0);
        }
    }
}

#[test]
fn skips_properties_of_every_type_in_any_order() {
    // Required properties of several types among ignored ones of every type.
    let properties = props(&[
        ("uchar", "red"),
        ("double", "x"),
        ("float", "y"),
        ("char", "flag"),
        ("float64", "z"),
        ("short", "s16"),
        ("float", "rot_0"),
        ("float", "rot_1"),
        ("ushort", "u16"),
        ("float", "rot_2"),
        ("float", "rot_3"),
        ("int", "i32"),
        ("float", "opacity"),
        ("uint", "u32"),
        ("double", "scale_0"),
        ("float32", "scale_1"),
        ("float", "scale_2"),
        ("int8", "i8"),
        ("uint8", "u8"),
        ("float", "f_dc_2"),
        ("float", "f_dc_1"),
        ("float", "f_dc_0"),
        ("double", "nx"),
    ]);
    let list = splats(5);
    for enc in [Enc::Le, Enc::Be, Enc::Ascii] {
        assert_matches(&parse(&ply(enc, &properties, &list)), &list, 2.0);
    }
    // Integer-typed required properties are read as numbers too.
    let properties = props(&[
        ("int", "x"),
        ("short", "y"),
        ("uchar", "z"),
        ("char", "scale_0"),
        ("char", "scale_1"),
        ("char", "scale_2"),
        ("int", "rot_0"),
        ("int", "rot_1"),
        ("int", "rot_2"),
        ("int", "rot_3"),
        ("char", "opacity"),
        ("short", "f_dc_0"),
        ("short", "f_dc_1"),
        ("short", "f_dc_2"),
    ]);
    let mut s = Splat::new([-3.0, 200.0, 255.0]);
    s.log_scale = [-1.0, -2.0, -3.0];
    s.rot = [0.0, 0.0, 1.0, 0.0];
    s.f_dc = [0.0, 1.0, -1.0];
    for enc in [Enc::Le, Enc::Be, Enc::Ascii] {
        assert_matches(&parse(&ply(enc, &properties, &[s])), &[s], 2.0);
    }
}

/// A binary or ASCII file with a `camera` element (scalars) and a `face` element (lists)
/// before the vertices, and an `edge` element after.
fn multi_element_file(enc: Enc, list: &[Splat]) -> Vec<u8> {
    let properties = reference_properties();
    let mut text = format!("ply\nformat {} 1.0\n", enc.format());
    text += "comment made by a test\nobj_info nothing\n";
    text += "element camera 2\nproperty double fx\nproperty uchar id\n";
    text += "element face 3\nproperty list uchar int vertex_indices\nproperty float area\n";
    text += &format!("element vertex {}\n", list.len());
    for (t, n) in &properties {
        text += &format!("property {t} {n}\n");
    }
    text += "element edge 2\nproperty int a\nproperty int b\nend_header\n";
    let mut out = text.into_bytes();
    let faces: [&[i32]; 3] = [&[0, 1, 2], &[], &[3, 4, 5, 6]];
    if enc == Enc::Ascii {
        out.extend_from_slice(b"500.5 1\n600.25 2\n");
        for f in faces {
            let items: Vec<String> = f.iter().map(|v| v.to_string()).collect();
            out.extend_from_slice(format!("{} {} 0.5\n", f.len(), items.join(" ")).as_bytes());
        }
    } else {
        for (fx, id) in [(500.5, 1.0), (600.25, 2.0)] {
            out.extend(encode("double", fx, enc));
            out.extend(encode("uchar", id, enc));
        }
        for f in faces {
            out.push(f.len() as u8);
            for &v in f {
                out.extend(encode("int", v as f64, enc));
            }
            out.extend(encode("float", 0.5, enc));
        }
    }
    let body = ply(enc, &properties, list);
    let end = b"end_header\n";
    let at = body.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    out.extend_from_slice(&body[at..]);
    if enc == Enc::Ascii {
        out.extend_from_slice(b"0 1\n1 2\n");
    } else {
        for v in [0.0, 1.0, 1.0, 2.0] {
            out.extend(encode("int", v, enc));
        }
    }
    out
}

#[test]
fn skips_other_elements_before_and_after_the_vertices() {
    let list = splats(4);
    for enc in [Enc::Le, Enc::Be, Enc::Ascii] {
        let loaded = parse(&multi_element_file(enc, &list));
        assert_matches(&loaded, &list, 2.0);
        assert_eq!(
            loaded.notes[1..],
            [
                "ignored element \"camera\" (2 record(s))",
                "ignored element \"face\" (3 record(s))",
                "ignored element \"edge\" (2 record(s))",
            ]
        );
    }
}

#[test]
fn list_properties_in_the_vertex_element() {
    let mut properties = minimal_properties();
    properties.insert(3, ("list uchar float".into(), "extra".into()));
    properties.push(("list int ushort".into(), "more".into()));
    let list = splats(3);
    let lengths = [2usize, 0, 5];
    for enc in [Enc::Le, Enc::Be, Enc::Ascii] {
        let mut out = header(enc, list.len(), &properties).into_bytes();
        out.extend_from_slice(b"end_header\n");
        for (s, &n) in list.iter().zip(&lengths) {
            let v = s.values();
            let mut fields: Vec<String> = Vec::new();
            let mut bytes: Vec<u8> = Vec::new();
            for (i, value) in v.iter().enumerate() {
                if i == 3 {
                    fields.push(n.to_string());
                    bytes.push(n as u8);
                    for k in 0..n {
                        fields.push(format!("{}", k as f64 + 0.5));
                        bytes.extend(encode("float", k as f64 + 0.5, enc));
                    }
                }
                fields.push(format!("{}", *value as f32));
                bytes.extend(encode("float", *value, enc));
            }
            fields.push("1".into());
            fields.push("7".into());
            bytes.extend(encode("int", 1.0, enc));
            bytes.extend(encode("ushort", 7.0, enc));
            if enc == Enc::Ascii {
                out.extend_from_slice(fields.join(" ").as_bytes());
                out.push(b'\n');
            } else {
                out.extend(bytes);
            }
        }
        assert_matches(&parse(&out), &list, 2.0);
    }
}

#[test]
fn crlf_headers_and_trailing_data() {
    let list = splats(2);
    let bytes = ply(Enc::Le, &minimal_properties(), &list);
    let text_end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let header = String::from_utf8(bytes[..text_end].to_vec()).unwrap();
    let mut crlf = header.replace('\n', "\r\n").into_bytes();
    crlf.extend_from_slice(&bytes[text_end..]);
    assert_matches(&parse(&crlf), &list, 2.0);
    // Bytes after the last element are ignored, with a note.
    let mut longer = bytes.clone();
    longer.extend_from_slice(&[0u8; 5]);
    let loaded = parse(&longer);
    assert_matches(&loaded, &list, 2.0);
    assert_eq!(loaded.notes[1], "ignored 5 byte(s) after the vertex data");
    // ASCII with CRLF lines and trailing spaces.
    let text = String::from_utf8(ply(Enc::Ascii, &minimal_properties(), &list)).unwrap();
    let crlf = text.replace('\n', " \r\n");
    assert_matches(&parse(crlf.as_bytes()), &list, 2.0);
}

#[test]
fn load_ply_reads_files_and_reports_io_errors() {
    let dir = support::TempDir::new("ply-files");
    let list = splats(3);
    let path = dir.write("tiny.ply", ply(Enc::Le, &reference_properties(), &list));
    let options = options(|o| o.progress = true);
    assert_matches(&load_ply(&path, &options).unwrap(), &list, 2.0);
    // Errors from a file name that file.
    let text = b"ply\nformat ascii 1.0\n";
    let bad = dir.write("bad.ply", text);
    parse_error(load_ply(&bad, &options), &bad, text);
    let missing = dir.path("missing.ply");
    assert_io_error(load_ply(&missing, &options), &missing);
}

#[test]
fn bad_options_are_rejected() {
    let bytes = ply(Enc::Le, &minimal_properties(), &splats(1));
    for sigma in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let options = options(|o| o.sigma = sigma);
        let e = parse_ply(&bytes, Path::new(FILE), &options).unwrap_err();
        assert!(
            matches!(&e, Error::Invalid { what, .. } if what == "sigma"),
            "{e}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Malformed files: file, record, property and reason.

#[test]
fn empty_file() {
    let m = assert_structural(b"", 0, "header", &["empty file"]);
    assert_eq!(
        m,
        "scene.ply:0:header: empty file: a PLY file starts with the line \"ply\""
    );
}

#[test]
fn not_a_ply_file() {
    let garbage: Vec<u8> = (0..200u32).map(|i| (i * 37 + 11) as u8).collect();
    assert_structural(&garbage, 1, "header", &["not a PLY file", "first bytes"]);
    assert_structural(b"x,y,z\n1,2,3\n", 1, "header", &["not a PLY file"]);
    // Starts with "ply" but the first line is something else.
    assert_structural(b"plywood\n", 1, "header", &["not a PLY file"]);
}

#[test]
fn truncated_header() {
    let full = header(Enc::Le, 3, &minimal_properties());
    let m = assert_structural(
        full.as_bytes(),
        17,
        "header",
        &["truncated header", "without an `end_header` line"],
    );
    assert!(
        m.starts_with("scene.ply:17:header: truncated header"),
        "{m}"
    );
    assert_structural(b"ply", 1, "header", &["truncated header"]);
    assert_structural(b"ply\nformat ascii 1.0", 2, "header", &["truncated header"]);
    // A binary body with the end_header line missing: the header "line" is not text.
    let mut bytes = header(Enc::Le, 1, &minimal_properties()).into_bytes();
    bytes.extend_from_slice(&[0xff, 0xfe, 0x80, b'\n', 1, 2, 3]);
    assert_structural(&bytes, 18, "header", &["not text", "end_header"]);
}

#[test]
fn header_lacks_a_required_property() {
    for missing in SPLAT_PROPERTIES {
        let properties: Vec<_> = reference_properties()
            .into_iter()
            .filter(|(_, n)| n != missing)
            .collect();
        let bytes = ply(Enc::Le, &properties, &splats(2));
        let m = assert_structural(
            &bytes,
            3,
            missing,
            &[
                &format!("missing vertex property \"{missing}\""),
                "scale_0..2",
            ],
        );
        if missing == "f_dc_1" {
            assert_eq!(
                m,
                "scene.ply:3:f_dc_1: missing vertex property \"f_dc_1\": a 3D Gaussian \
                 Splatting PLY needs x, y, z, scale_0..2, rot_0..3, opacity and f_dc_0..2"
            );
        }
    }
    // A required property that is a list.
    let mut properties = minimal_properties();
    properties[10] = ("list uchar float".into(), "opacity".into());
    let text = header(Enc::Ascii, 1, &properties) + "end_header\n";
    assert_structural(
        text.as_bytes(),
        3,
        "opacity",
        &["must be a scalar, not a list"],
    );
    // No vertex element at all.
    let text = "ply\nformat ascii 1.0\nelement face 1\nproperty float x\nend_header\n1\n";
    assert_structural(text.as_bytes(), 5, "header", &["no `element vertex`"]);
}

/// The minimal ASCII header with line `at` (1-based) replaced by `line`.
fn header_with_line(at: usize, line: &str) -> Vec<u8> {
    let text = header(Enc::Ascii, 1, &minimal_properties()) + "end_header\n";
    let mut lines: Vec<&str> = text.lines().collect();
    lines[at - 1] = line;
    let mut body = lines.join("\n");
    body += "\n0 0 0 -1 -1 -1 1 0 0 0 1 0 0 0\n";
    body.into_bytes()
}

/// Each `(at, line, column, words)`: the minimal ASCII file with header line `at` replaced by
/// `line` fails on that line at `column`, the reason holding every one of `words`, with and
/// without `skip_invalid` ([`assert_structural`]).
fn assert_bad_header_lines(cases: &[(usize, &str, &str, &[&str])]) {
    for &(at, line, column, words) in cases {
        assert_structural(&header_with_line(at, line), at, column, words);
    }
}

#[test]
fn unknown_format() {
    let m = assert_structural(
        &header_with_line(2, "format binary_middle_endian 1.0"),
        2,
        "format",
        &[
            "unknown format \"binary_middle_endian\"",
            "binary_little_endian",
        ],
    );
    assert_eq!(
        m,
        "scene.ply:2:format: unknown format \"binary_middle_endian\": expected ascii, \
         binary_little_endian or binary_big_endian"
    );
    assert_bad_header_lines(&[
        (2, "format ascii one", "format", &["bad version \"one\""]),
        (
            2,
            "format ascii 2.0",
            "format",
            &["unsupported PLY version 2.0"],
        ),
    ]);
    assert_structural(
        &header_with_line(2, "comment no format line"),
        0,
        "format",
        &["no `format` line"],
    );
    // Contradicting format lines.
    let mut bytes = b"ply\nformat ascii 1.0\n".to_vec();
    bytes.extend_from_slice(&header_with_line(2, "format binary_little_endian 1.0")[4..]);
    assert_structural(&bytes, 3, "format", &["contradicts \"ascii\" on line 2"]);
}

#[test]
fn unknown_property_type() {
    let m = assert_structural(
        &header_with_line(4, "property float16 x"),
        4,
        "x",
        &["unknown property type \"float16\"", "known types: char"],
    );
    assert!(
        m.starts_with("scene.ply:4:x: unknown property type \"float16\""),
        "{m}"
    );
    assert_bad_header_lines(&[
        (
            4,
            "property list uchar half x",
            "x",
            &["unknown property type \"half\""],
        ),
        (
            4,
            "property list float int x",
            "x",
            &["length type must be an integer type"],
        ),
        (
            4,
            "property float",
            "property",
            &["malformed header line", "`property <type> <name>`"],
        ),
        (
            5,
            "property float x",
            "x",
            &["duplicate property \"x\" in element \"vertex\""],
        ),
        (
            4,
            "propety float x",
            "header",
            &["unknown header keyword \"propety\""],
        ),
        (4, "", "header", &["blank line"]),
    ]);
}

#[test]
fn element_count_not_a_number() {
    let m = assert_structural(
        &header_with_line(3, "element vertex many"),
        3,
        "element vertex",
        &["count \"many\" is not a non-negative integer"],
    );
    assert_eq!(
        m,
        "scene.ply:3:element vertex: element \"vertex\": count \"many\" is not a non-negative \
         integer"
    );
    assert_bad_header_lines(&[
        (3, "element vertex -5", "element vertex", &["count \"-5\""]),
        (
            3,
            "element vertex 99999999999999999999999",
            "element vertex",
            &["too large"],
        ),
        (
            3,
            "element vertex",
            "element",
            &["`element <name> <count>`"],
        ),
    ]);
    // A property before any element.
    let text = "ply\nformat ascii 1.0\nproperty float x\nelement vertex 0\nend_header\n";
    assert_structural(text.as_bytes(), 3, "x", &["before any `element` line"]);
    // A second element of the same name.
    let text = "ply\nformat ascii 1.0\nelement vertex 0\nelement vertex 0\nend_header\n";
    assert_structural(text.as_bytes(), 4, "element vertex", &["duplicate element"]);
    // An empty vertex element.
    let text = header(Enc::Le, 0, &minimal_properties()) + "end_header\n";
    assert_structural(text.as_bytes(), 3, "vertex", &["`element vertex 0`"]);
}

#[test]
fn binary_body_truncated() {
    let bytes = ply(Enc::Le, &reference_properties(), &splats(20));
    // Cut inside vertex 17's f_rest_2: 16 whole records of 248 bytes, then 6 + 3 + 2 floats
    // and one byte.
    let body_start = bytes.len() - 20 * 248;
    let cut = body_start + 16 * 248 + 11 * 4 + 1;
    let m = assert_structural(
        &bytes[..cut],
        17,
        "f_rest_2",
        &[
            "body truncated in vertex 17 of 20",
            "the header promises 20 vertices of 248 bytes (4960 bytes)",
            "4013 bytes follow the header",
        ],
    );
    assert_eq!(
        m,
        "scene.ply:17:f_rest_2: body truncated in vertex 17 of 20: the header promises 20 \
         vertices of 248 bytes (4960 bytes) but 4013 bytes follow the header; the file ends \
         inside property \"f_rest_2\""
    );
    // Every cut fails, never panics.
    for cut in body_start..bytes.len() {
        parse_err_with(&bytes[..cut], &LoadOptions::default());
    }
    // In an element before the vertices, with lists.
    let bytes = multi_element_file(Enc::Le, &splats(2));
    let at = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    // camera: 2 records of 9 bytes; face: 17 bytes, 5 bytes, then 3 of 21.
    assert_structural(
        &bytes[..at + 18 + 17 + 5 + 3],
        3,
        "vertex_indices",
        &[
            "body truncated in element \"face\" record 3 of 3: the file ends inside property \
           \"vertex_indices\"",
        ],
    );
    assert_structural(
        &bytes[..at + 8],
        1,
        "id",
        &["body truncated in element \"camera\" record 1 of 2"],
    );
}

#[test]
fn huge_vertex_count_with_a_tiny_body() {
    let started = Instant::now();
    for enc in [Enc::Le, Enc::Be] {
        let mut bytes = header(enc, 4_000_000_000u64, &reference_properties()).into_bytes();
        bytes.extend_from_slice(b"end_header\n");
        bytes.extend_from_slice(&[0u8; 1000]);
        assert_structural(
            &bytes,
            5,
            "z",
            &[
                "body truncated in vertex 5 of 4000000000",
                "(992000000000 bytes) but 1000 bytes follow",
            ],
        );
    }
    let mut bytes = header(Enc::Ascii, u64::MAX, &minimal_properties()).into_bytes();
    bytes.extend_from_slice(b"end_header\n0 0 0 -1 -1 -1 1 0 0 0 1 0 0 0\n");
    let m = assert_structural(
        &bytes,
        20,
        "body",
        &[
            "body truncated: the header promises 18446744073709551615 record(s) of element \
           \"vertex\" but the file ends after 1",
        ],
    );
    assert!(m.starts_with("scene.ply:20:body:"), "{m}");
    assert!(started.elapsed().as_secs_f64() < 1.0);
}

#[test]
fn non_finite_numbers() {
    let mut list = splats(20);
    list[16].center[0] = f64::NAN;
    let m = assert_err(
        &ply(Enc::Le, &reference_properties(), &list),
        17,
        "x",
        &["vertex 17: x is not finite (NaN)"],
    );
    assert_eq!(m, "scene.ply:17:x: vertex 17: x is not finite (NaN)");
    let mut list = splats(3);
    list[1].log_scale[2] = f64::INFINITY;
    assert_err(
        &ply(Enc::Be, &reference_properties(), &list),
        2,
        "scale_2",
        &["vertex 2: scale_2 is not finite (inf)"],
    );
    list[1].log_scale[2] = -1.0;
    list[2].opacity = f64::NEG_INFINITY;
    assert_err(
        &ply(Enc::Le, &minimal_properties(), &list),
        3,
        "opacity",
        &["vertex 3: opacity is not finite (-inf)"],
    );
    // ASCII: the physical line, the vertex in the reason.
    let mut text = String::from_utf8(ply(Enc::Ascii, &minimal_properties(), &splats(3))).unwrap();
    text = text.replacen("\n1 ", "\nnan ", 1);
    let m = assert_err(
        text.as_bytes(),
        20,
        "x",
        &["vertex 2: x is not finite (NaN)"],
    );
    assert_eq!(m, "scene.ply:20:x: vertex 2: x is not finite (NaN)");
}

#[test]
fn zero_quaternion() {
    let mut list = splats(3);
    list[1].rot = [0.0; 4];
    let m = assert_err(
        &ply(Enc::Le, &reference_properties(), &list),
        2,
        "rot_0..3",
        &["vertex 2: zero quaternion"],
    );
    assert_eq!(
        m,
        "scene.ply:2:rot_0..3: vertex 2: zero quaternion (rot_0..3 all 0) does not define a \
         rotation"
    );
    // Tiny and huge but non-zero quaternions are fine (they are normalised).
    list[1].rot = [0.0, 1e-30, 0.0, 0.0];
    list[2].rot = [3e38, 0.0, 3e38, 0.0];
    let loaded = parse(&ply(Enc::Le, &reference_properties(), &list));
    assert_matches(&loaded, &list, 2.0);
}

#[test]
fn radii_that_overflow_or_underflow() {
    let mut list = splats(3);
    list[2].log_scale[0] = 800.0;
    let m = assert_err(
        &ply(Enc::Le, &reference_properties(), &list),
        3,
        "scale_0",
        &["vertex 3: radius overflows"],
    );
    assert_eq!(
        m,
        "scene.ply:3:scale_0: vertex 3: radius overflows: 2 * exp(scale_0 = 800) is not finite"
    );
    list[2].log_scale[0] = -1.0;
    list[0].log_scale[1] = -800.0;
    let m = assert_err(
        &ply(Enc::Le, &reference_properties(), &list),
        1,
        "scale_1",
        &["vertex 1: radius underflows"],
    );
    assert_eq!(
        m,
        "scene.ply:1:scale_1: vertex 1: radius underflows: 2 * exp(scale_1 = -800) is 0"
    );
    // Overflow through a large sigma.
    list[0].log_scale[1] = 700.0;
    let options = options(|o| o.sigma = 1e10);
    parse_err_with(&ply(Enc::Le, &minimal_properties(), &list), &options).assert_at(
        1,
        "scale_1",
        &["radius overflows"],
    );
}

/// The minimal ASCII file of `splats(3)` with line `at` (1-based, physical) replaced.
fn ascii_with_line(at: usize, line: &str) -> Vec<u8> {
    let text = String::from_utf8(ply(Enc::Ascii, &minimal_properties(), &splats(3))).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    lines[at - 1] = line;
    (lines.join("\n") + "\n").into_bytes()
}

#[test]
fn ascii_lines_with_bad_fields() {
    // Header: 17 lines (ply, format, element, 14 properties) and end_header; vertex 2 is on
    // line 20.
    let m = assert_err(
        &ascii_with_line(20, "1 2 3 -1 -1 -1 1 0 0 0 1 0 0"),
        20,
        "f_dc_2",
        &["vertex 2: too few fields: found 13, expected 14 (missing \"f_dc_2\")"],
    );
    assert_eq!(
        m,
        "scene.ply:20:f_dc_2: vertex 2: too few fields: found 13, expected 14 (missing \
         \"f_dc_2\")"
    );
    assert_err(
        &ascii_with_line(20, ""),
        20,
        "x",
        &["too few fields: found 0, expected 14"],
    );
    let m = assert_err(
        &ascii_with_line(20, "1 2 3 -1 abc -1 1 0 0 0 1 0 0 0"),
        20,
        "scale_1",
        &["vertex 2: not a number: \"abc\""],
    );
    assert_eq!(m, "scene.ply:20:scale_1: vertex 2: not a number: \"abc\"");
    assert_err(
        &ascii_with_line(21, "1 2 3 -1 -1 -1 1 0 0 0 1 0 0 0 5"),
        21,
        "line",
        &["vertex 3: too many fields: 1 field(s) after the last property \"f_dc_2\""],
    );
    assert_err(
        &ascii_with_line(19, "1,2,3,-1,-1,-1,1,0,0,0,1,0,0,0"),
        19,
        "x",
        &["vertex 1: not a number: \"1,2,3,-1,-1,-1,1,0,0,0,1,0,0,0\""],
    );
    // Fewer lines than vertices is a truncated body.
    let text = String::from_utf8(ply(Enc::Ascii, &minimal_properties(), &splats(3))).unwrap();
    let short: Vec<&str> = text.lines().take(20).collect();
    assert_structural(
        (short.join("\n") + "\n").as_bytes(),
        21,
        "body",
        &[
            "body truncated",
            "promises 3 record(s) of element \"vertex\" but the file ends after 2",
        ],
    );
    // A list whose length runs past the line, and a bad list length.
    let mut properties = minimal_properties();
    properties.push(("list uchar int".into(), "ids".into()));
    let mut text = header(Enc::Ascii, 2, &properties) + "end_header\n";
    text += "0 0 0 -1 -1 -1 1 0 0 0 1 0 0 0 3 1 2\n";
    text += "0 0 0 -1 -1 -1 1 0 0 0 1 0 0 0 x\n";
    assert_err(
        text.as_bytes(),
        20,
        "ids",
        &["vertex 1: too few fields: list \"ids\" declares 3 item(s) but the line ends after 2"],
    );
    let skip = skipping();
    // The element's header line.
    parse_err_with(text.as_bytes(), &skip).assert_at(3, "vertex", &["no valid splats (2 skipped"]);
    let text = text.replace(" 3 1 2\n", " 2 1 2\n");
    assert_err(
        text.as_bytes(),
        21,
        "ids",
        &["vertex 2: list length \"x\" is not a non-negative integer"],
    );
}

#[test]
fn skip_invalid_drops_bad_splats_and_counts_them() {
    let mut list = splats(8);
    list[1].center[1] = f64::NAN;
    list[4].rot = [0.0; 4];
    list[6].log_scale[0] = 1000.0;
    let good: Vec<Splat> = [0, 2, 3, 5, 7].map(|i| list[i]).to_vec();
    let skip = skipping();
    for enc in [Enc::Le, Enc::Be, Enc::Ascii] {
        let bytes = ply(enc, &reference_properties(), &list);
        let loaded = parse_with(&bytes, &skip);
        assert_matches(&loaded, &good, 2.0);
        assert_eq!(loaded.skipped, 3);
        let first = if enc == Enc::Ascii {
            // 3 + 62 property lines + end_header: vertex 2 is on line 68.
            "scene.ply:68:y: vertex 2: y is not finite (NaN)"
        } else {
            "scene.ply:2:y: vertex 2: y is not finite (NaN)"
        };
        assert_eq!(
            loaded.notes[1],
            format!("skipped 3 invalid splat(s); the first: {first}")
        );
        // Without the option the first one fails.
        let line = if enc == Enc::Ascii { 68 } else { 2 };
        parse_err_with(&bytes, &LoadOptions::default()).assert_at(line, "y", &[]);
    }
    // ASCII lines with bad fields are skipped too.
    let bytes = ascii_with_line(20, "1 2 3 four");
    let loaded = parse_with(&bytes, &skip);
    assert_eq!((loaded.scene.len(), loaded.skipped), (2, 1));
    assert_eq!(
        loaded.notes[1],
        "skipped 1 invalid splat(s); the first: scene.ply:20:scale_0: vertex 2: not a number: \
         \"four\""
    );
    // Skipped and transparent splats are counted apart.
    let mut list = splats(4);
    list[0].opacity = -10.0;
    list[1].center[2] = f64::INFINITY;
    let options = options(|o| {
        o.skip_invalid = true;
        o.min_opacity = 0.01;
    });
    let loaded = parse_with(&ply(Enc::Le, &minimal_properties(), &list), &options);
    assert_eq!((loaded.scene.len(), loaded.skipped), (2, 1));
    assert_eq!(
        loaded.notes[1],
        "left out 1 of 4 splat(s) with opacity below 0.01 (--min-opacity)"
    );
    assert!(loaded.notes[2].starts_with("skipped 1 invalid splat(s)"));
    // Nothing valid at all is an error.
    let mut list = splats(2);
    list[0].rot = [0.0; 4];
    list[1].rot = [0.0; 4];
    let e = parse_err_with(&ply(Enc::Le, &minimal_properties(), &list), &skip);
    e.assert_at(3, "vertex", &[]);
    assert!(
        e.reason
            .starts_with("no valid splats (2 skipped as invalid"),
        "{}",
        e.reason
    );
}

#[test]
fn structural_errors_fail_even_with_skip_invalid() {
    // assert_structural checks every header and truncation case with skip_invalid; here a
    // negative binary list length, which loses the record boundaries.
    let mut properties = minimal_properties();
    properties.push(("list char float".into(), "extra".into()));
    let mut bytes = header(Enc::Le, 2, &properties).into_bytes();
    bytes.extend_from_slice(b"end_header\n");
    for value in Splat::new([0.0; 3]).values() {
        bytes.extend(encode("float", value, Enc::Le));
    }
    bytes.push(0xfe); // -2 items
    assert_structural(
        &bytes,
        1,
        "extra",
        &["vertex 1: list \"extra\" has a negative length -2"],
    );
}

// ---------------------------------------------------------------------------------------------
// Robustness: arbitrary bytes give an error or a scene, quickly.

#[test]
fn mutated_files_never_panic() {
    let seeds = [
        ply(Enc::Le, &reference_properties(), &splats(6)),
        ply(Enc::Be, &minimal_properties(), &splats(6)),
        ply(Enc::Ascii, &minimal_properties(), &splats(6)),
        multi_element_file(Enc::Le, &splats(3)),
        multi_element_file(Enc::Ascii, &splats(3)),
    ];
    let tokens: [&[u8]; 12] = [
        b"4000000000",
        b"18446744073709551615",
        b"list",
        b"\n",
        b"\r",
        b" ",
        b"end_header\n",
        b"element",
        b"property list uint float q\n",
        b"nan",
        b"-",
        b"\xff",
    ];
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let started = Instant::now();
    let skip = skipping();
    for i in 0..6000 {
        let mut bytes = seeds[i % seeds.len()].clone();
        for _ in 0..1 + rng.below(4) {
            let at = rng.below(bytes.len());
            match rng.below(5) {
                0 => bytes[at] = rng.byte(),
                1 => bytes.truncate(at),
                2 => {
                    let t = tokens[rng.below(tokens.len())];
                    bytes.splice(at..at, t.iter().copied());
                }
                3 => {
                    let end = (at + 1 + rng.below(12)).min(bytes.len());
                    bytes.drain(at..end);
                }
                _ => {
                    // Overwrite a header digit run with a huge number.
                    if let Some(p) = bytes[..bytes.len().min(400)]
                        .iter()
                        .position(|b| b.is_ascii_digit())
                    {
                        bytes.splice(p..p + 1, b"999999999".iter().copied());
                    }
                }
            }
            if bytes.is_empty() {
                break;
            }
        }
        let options = if i % 2 == 0 {
            &skip
        } else {
            &LoadOptions::default()
        };
        let _ = parse_ply(&bytes, Path::new(FILE), options);
    }
    assert!(
        started.elapsed().as_secs_f64() < 20.0,
        "took {:?}",
        started.elapsed()
    );
}

// ---------------------------------------------------------------------------------------------
// Speed: `cargo test --release --test loader_ply -- --ignored --nocapture`

/// Writes a reference-layout binary file of `n` splats (248 bytes each) to `path`.
fn write_big_file(path: &Path, n: usize) {
    use std::io::Write;
    let properties = reference_properties();
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    out.write_all(header(Enc::Le, n, &properties).as_bytes())
        .unwrap();
    out.write_all(b"end_header\n").unwrap();
    let mut record = Vec::with_capacity(248);
    for i in 0..n {
        let t = i as f32 * 1e-6;
        record.clear();
        for (_, name) in &properties {
            let v: f32 = match name.as_str() {
                "x" => t.sin(),
                "y" => t.cos(),
                "z" => t,
                "scale_0" | "scale_1" | "scale_2" => -4.0,
                "rot_0" => 1.0,
                "rot_1" => t,
                "opacity" => 2.0 - t,
                _ => 0.1,
            };
            record.extend_from_slice(&v.to_le_bytes());
        }
        out.write_all(&record).unwrap();
    }
    out.flush().unwrap();
}

#[test]
#[ignore = "writes a 744 MB file to the temp directory; run with --ignored --nocapture"]
fn three_million_splats_load_whole() {
    let n = 3_000_000;
    let path = std::env::temp_dir().join("ellipsoid-splat-3m.ply");
    let started = Instant::now();
    write_big_file(&path, n);
    let size = std::fs::metadata(&path).unwrap().len();
    println!(
        "wrote {n} splats ({:.0} MB) in {:.2} s",
        size as f64 / 1e6,
        started.elapsed().as_secs_f64()
    );

    let options = LoadOptions::default();
    let started = Instant::now();
    let bytes = std::fs::read(&path).unwrap();
    let read = started.elapsed().as_secs_f64();
    let mut parse = f64::INFINITY;
    for _ in 0..3 {
        let started = Instant::now();
        let loaded = parse_ply(&bytes, &path, &options).unwrap();
        parse = parse.min(started.elapsed().as_secs_f64());
        assert_eq!(loaded.scene.len(), n);
    }
    drop(bytes);
    println!("std::fs::read {read:.2} s, parse_ply {parse:.2} s (best of 3)");

    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let started = Instant::now();
        let loaded = load_ply(&path, &options).unwrap();
        best = best.min(started.elapsed().as_secs_f64());
        assert_eq!(loaded.scene.len(), n);
    }
    println!(
        "load_ply: {best:.2} s (best of 3) for {n} splats ({:.0} ns per splat, {:.0} MB/s)",
        best * 1e9 / n as f64,
        size as f64 / 1e6 / best
    );
    std::fs::remove_file(&path).unwrap();
}
