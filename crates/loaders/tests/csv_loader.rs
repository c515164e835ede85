//! The Ellipsoid CSV loader: accepted forms round-trip numerically and every malformed input
//! is rejected with its file, line, column and reason.

mod support;

use std::path::Path;

use ellipsoid_splat::internals::shape_color;
use ellipsoid_splat::{Ellipsoid, Scene};
use ellipsoid_splat_loaders::{load_csv, parse_csv};
use glam::{DMat3, DQuat, DVec3};
use support::{assert_close, assert_io_error, assert_mat_close, loaded, parse_error, ParseError};

const FILE: &str = "scene.csv";

fn parse(text: &str) -> Scene {
    loaded(parse_csv(text, Path::new(FILE)), text.as_bytes())
}

/// Parses `text`, expecting a parse error naming [`FILE`].
fn parse_err(text: &str) -> ParseError {
    parse_error(
        parse_csv(text, Path::new(FILE)),
        Path::new(FILE),
        text.as_bytes(),
    )
}

/// Asserts the error's line, column and that the reason contains `word`.
fn assert_err(text: &str, line: usize, column: &str, word: &str) {
    parse_err(text).assert_at(line, column, &[word]);
}

const RQ_HEADER: &str = "x,y,z,rx,ry,rz,qw,qx,qy,qz";
const T_HEADER: &str = "x,y,z,txx,txy,txz,tyy,tyz,tzz";

#[test]
fn radii_quaternion_form_round_trips_and_normalises() {
    // Quaternion (2, 0, 0, 2) is 90 degrees about z, unnormalised.
    let scene = parse(&format!(
        "{RQ_HEADER},r,g,b\n1,2,3, 0.5,1,2, 2,0,0,2, 0.25,0.5,1\n"
    ));
    assert_eq!(scene.len(), 1);
    let e = scene.ellipsoids[0];
    assert_eq!(e.center, DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(e.radii, DVec3::new(0.5, 1.0, 2.0));
    assert!((e.rotation.length() - 1.0).abs() < 1e-15);
    let expected = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    assert!(
        e.rotation.dot(expected).abs() > 1.0 - 1e-12,
        "{}",
        e.rotation
    );
    assert_close(e.axes().x_axis, DVec3::Y, 1e-12);
    assert_eq!(e.color, [0.25, 0.5, 1.0]);
}

#[test]
fn tensor_form_round_trips() {
    let r = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::ZYX, 0.4, -0.7, 1.3));
    let t = r * DMat3::from_diagonal(DVec3::new(2.0, 0.75, 0.1)) * r.transpose();
    let row = format!(
        "-1,0.5,4,{:.17},{:.17},{:.17},{:.17},{:.17},{:.17}",
        t.x_axis.x, t.y_axis.x, t.z_axis.x, t.y_axis.y, t.z_axis.y, t.z_axis.z
    );
    let scene = parse(&format!("{T_HEADER}\n{row}\n"));
    let e = scene.ellipsoids[0];
    assert_eq!(e.center, DVec3::new(-1.0, 0.5, 4.0));
    assert_mat_close(e.to_world() * e.axes().transpose(), t, 1e-12);
    let mut radii = e.radii.to_array();
    radii.sort_by(f64::total_cmp);
    assert_close(DVec3::from(radii), DVec3::new(0.1, 0.75, 2.0), 1e-12);
    // Without r,g,b the glyph is coloured by shape.
    assert_eq!(e.color, shape_color(e.radii));
}

#[test]
fn matches_ellipsoid_constructors() {
    let scene = parse(&format!("{RQ_HEADER}\n0,0,0,3,1,1,1,0,0,0\n"));
    let expected = Ellipsoid::new(
        DVec3::ZERO,
        DVec3::new(3.0, 1.0, 1.0),
        DQuat::IDENTITY,
        None,
    )
    .unwrap();
    assert_eq!(scene.ellipsoids[0], expected);
    assert_eq!(scene.ellipsoids[0].color, shape_color(expected.radii));
}

#[test]
fn comments_blank_lines_and_whitespace_anywhere() {
    let text = "\
# leading comment
   # indented comment

 x , y,z,rx,ry,rz,qw,qx,qy,qz
# between header and data
1,1,1,1,1,1,1,0,0,0

   \t
 2 , 2 ,2,1,1,1,1,0,0,0   
#trailing
";
    let scene = parse(text);
    assert_eq!(scene.len(), 2);
    assert_eq!(scene.ellipsoids[1].center, DVec3::splat(2.0));
}

#[test]
fn line_numbers_count_comment_and_blank_lines() {
    let text = "\
# one

  # three
x,y,z,rx,ry,rz,qw,qx,qy,qz

# six
1,1,1,1,1,1,1,0,0,0
  \t

# ten
2,2,2,1,1,-1,1,0,0,0
";
    assert_err(text, 11, "rz", "non-positive");
    assert_err("\n\n\nx,y,z\n1,2,3\n", 4, "header", "no shape");
}

#[test]
fn column_order_is_free() {
    let shuffled = parse("qz,b,rx,y,qw,g,z,ry,qy,x,r,rz,qx\n0,1,1,2,1,0.5,3,2,0,1,0,3,0\n");
    let canonical = parse(&format!("{RQ_HEADER},r,g,b\n1,2,3,1,2,3,1,0,0,0,0,0.5,1\n"));
    assert_eq!(shuffled, canonical);
    let t1 = parse("tzz,x,tyz,y,txx,z,txy,tyy,txz\n3,1,0,2,1,3,0,2,0\n");
    let t2 = parse(&format!("{T_HEADER}\n1,2,3,1,0,0,2,0,3\n"));
    assert_eq!(t1, t2);
}

#[test]
fn crlf_line_endings() {
    let text =
        "# c\r\nx,y,z,rx,ry,rz,qw,qx,qy,qz\r\n1,2,3,1,1,1,1,0,0,0\r\n4,5,6,1,1,1,1,0,0,0\r\n";
    let scene = parse(text);
    assert_eq!(scene.len(), 2);
    assert_eq!(scene.ellipsoids[1].center, DVec3::new(4.0, 5.0, 6.0));
    // Line numbers still count physical lines.
    let bad = "# c\r\nx,y,z,rx,ry,rz,qw,qx,qy,qz\r\n\r\n1,2,3,1,1,1,1,0,0,oops\r\n";
    assert_err(bad, 4, "qz", "oops");
}

#[test]
fn no_trailing_newline_and_utf8_bom() {
    let scene = parse("\u{feff}x,y,z,rx,ry,rz,qw,qx,qy,qz\n1,2,3,1,1,1,1,0,0,0");
    assert_eq!(scene.len(), 1);
}

#[test]
fn load_csv_reads_files_and_rejects_invalid_utf8() {
    let dir = support::TempDir::new("csv-files");
    let good = dir.write("good.csv", format!("{RQ_HEADER}\n1,2,3,1,1,1,1,0,0,0\n"));
    assert_eq!(load_csv(&good).unwrap().len(), 1);

    let mut bytes = format!("{RQ_HEADER}\n1,2,3,1,1,1,1,0,0,0\n").into_bytes();
    bytes.extend_from_slice(b"4,5,\xff,1,1,1,1,0,0,0\n");
    let bad = dir.write("bad.csv", &bytes);
    let e = parse_error(load_csv(&bad), &bad, &bytes);
    assert_eq!(e.line, 3);
    assert!(e.reason.contains("UTF-8"), "{}", e.reason);

    let missing = dir.path("missing.csv");
    assert_io_error(load_csv(&missing), &missing);
}

#[test]
fn error_message_names_file_line_and_column() {
    let err = parse_csv(
        &format!("{RQ_HEADER}\n1,2,3,1,1,x7,1,0,0,0\n"),
        Path::new("dir/cells.csv"),
    )
    .unwrap_err();
    let text = err.to_string();
    assert!(text.starts_with("dir/cells.csv:2:rz:"), "{text}");
    assert!(text.contains("\"x7\""), "{text}");
}

// ---- malformed header ----

#[test]
fn empty_file_or_only_comments() {
    assert_err("", 0, "header", "empty");
    assert_err("# just a comment\n\n   \n", 0, "header", "no header");
}

#[test]
fn unknown_column() {
    assert_err(
        &format!("# c\n{RQ_HEADER},alpha\n1,2,3,1,1,1,1,0,0,0,1\n"),
        2,
        "alpha",
        "unknown column",
    );
    // Names are case-sensitive.
    assert_err(
        "X,y,z,rx,ry,rz,qw,qx,qy,qz\n1,2,3,1,1,1,1,0,0,0\n",
        1,
        "X",
        "unknown",
    );
}

#[test]
fn empty_column_name() {
    assert_err(
        &format!("{RQ_HEADER},\n1,2,3,1,1,1,1,0,0,0,\n"),
        1,
        "column 11",
        "empty column name",
    );
}

#[test]
fn duplicate_column() {
    assert_err(
        &format!("{RQ_HEADER},x\n1,2,3,1,1,1,1,0,0,0,1\n"),
        1,
        "x",
        "duplicate",
    );
}

#[test]
fn missing_required_column() {
    assert_err(
        "x,z,rx,ry,rz,qw,qx,qy,qz\n1,3,1,1,1,1,0,0,0\n",
        1,
        "y",
        "missing",
    );
    assert_err(
        "x,y,z,rx,ry,rz,qw,qx,qz\n1,2,3,1,1,1,1,0,0\n",
        1,
        "qy",
        "missing",
    );
    assert_err(
        "x,y,z,txx,txy,txz,tyy,tzz\n1,2,3,1,0,0,1,1\n",
        1,
        "tyz",
        "missing",
    );
}

#[test]
fn both_or_neither_shape_forms() {
    assert_err(
        &format!("{RQ_HEADER},txx,txy,txz,tyy,tyz,tzz\n1,2,3,1,1,1,1,0,0,0,1,0,0,1,0,1\n"),
        1,
        "txx",
        "both shape forms",
    );
    assert_err(
        &format!("{RQ_HEADER},tyy\n1,2,3,1,1,1,1,0,0,0,1\n"),
        1,
        "tyy",
        "both",
    );
    assert_err("x,y,z\n1,2,3\n", 1, "header", "no shape columns");
    assert_err("x,y,z,r,g,b\n1,2,3,1,1,1\n", 1, "header", "no shape");
}

#[test]
fn partial_colour_triple() {
    assert_err(
        &format!("{RQ_HEADER},r,g\n1,2,3,1,1,1,1,0,0,0,1,1\n"),
        1,
        "b",
        "partial colour",
    );
    assert_err(
        &format!("{T_HEADER},b\n1,2,3,1,0,0,1,0,1,1\n"),
        1,
        "r",
        "partial colour",
    );
}

#[test]
fn zero_data_rows() {
    assert_err(
        &format!("# c\n{RQ_HEADER}\n# no rows\n"),
        2,
        "header",
        "no ellipsoids",
    );
}

// ---- malformed rows ----

#[test]
fn wrong_number_of_fields() {
    let text = format!("{RQ_HEADER}\n1,2,3,1,1,1,1,0,0,0\n1,2,3,1,1,1,1,0,0\n");
    parse_err(&text).assert_at(
        3,
        "row",
        &["wrong number of fields", "expected 10", "found 9"],
    );
    assert_err(
        &format!("{RQ_HEADER}\n1,2,3,1,1,1,1,0,0,0,5\n"),
        2,
        "row",
        "found 11",
    );
}

#[test]
fn non_numeric_field() {
    assert_err(
        &format!("{RQ_HEADER}\n1,2,3,1,1,1,1,0,0,0\n1,two,3,1,1,1,1,0,0,0\n"),
        3,
        "y",
        "not a number: \"two\"",
    );
    assert_err(
        &format!("{RQ_HEADER}\n1,2,3,1,,1,1,0,0,0\n"),
        2,
        "ry",
        "empty field",
    );
    // The first bad field in file order is reported.
    assert_err(
        "qz,qy,qx,qw,rz,ry,rx,z,y,x\n0,0,0,1,1,1,1,a,b,c\n",
        2,
        "z",
        "\"a\"",
    );
}

#[test]
fn non_finite_number() {
    for text in ["NaN", "inf", "-inf", "infinity"] {
        assert_err(
            &format!("{RQ_HEADER}\n1,2,{text},1,1,1,1,0,0,0\n"),
            2,
            "z",
            "non-finite",
        );
    }
    assert_err(
        &format!("{T_HEADER}\n1,2,3,1,0,0,1e400,0,1\n"),
        2,
        "tyy",
        "non-finite",
    );
}

#[test]
fn non_positive_radius() {
    assert_err(
        &format!("{RQ_HEADER}\n1,2,3,1,0,1,1,0,0,0\n"),
        2,
        "ry",
        "non-positive radius",
    );
    assert_err(
        &format!("{RQ_HEADER}\n1,2,3,1,1,-0.5,1,0,0,0\n"),
        2,
        "rz",
        "non-positive radius",
    );
}

#[test]
fn zero_quaternion() {
    assert_err(
        &format!("{RQ_HEADER}\n1,2,3,1,1,1,0,0,0,0\n"),
        2,
        "qw,qx,qy,qz",
        "zero quaternion",
    );
    // Too small to normalise reliably is rejected by `Ellipsoid::new` and reported the same way.
    assert_err(
        &format!("{RQ_HEADER}\n1,2,3,1,1,1,1e-20,0,0,0\n"),
        2,
        "qw,qx,qy,qz",
        "non-zero",
    );
}

#[test]
fn tensor_not_positive_definite() {
    assert_err(
        &format!("{T_HEADER}\n1,2,3,1,0,0,-1,0,1\n"),
        2,
        "txx,txy,txz,tyy,tyz,tzz",
        "positive definite",
    );
    // Singular (a flat disc) is not positive definite either.
    assert_err(
        &format!("{T_HEADER}\n1,2,3,1,0,0,1,0,0\n"),
        2,
        "txx,txy,txz,tyy,tyz,tzz",
        "positive definite",
    );
    // Positive diagonal but indefinite: eigenvalues 3 and -1.
    assert_err(
        &format!("{T_HEADER}\n1,2,3,1,2,0,1,0,1\n"),
        2,
        "txx,txy,txz,tyy,tyz,tzz",
        "positive definite",
    );
}

#[test]
fn colour_out_of_range() {
    assert_err(
        &format!("{RQ_HEADER},r,g,b\n1,2,3,1,1,1,1,0,0,0,0.5,1.5,0\n"),
        2,
        "g",
        "out of range",
    );
    assert_err(
        &format!("{T_HEADER},r,g,b\n1,2,3,1,0,0,1,0,1,-0.1,0,0\n"),
        2,
        "r",
        "[0, 1]",
    );
}

/// A scene written as Ellipsoid CSV reads back to the same ellipsoids, bit for bit where the
/// format keeps them (the quaternion is normalised on load: within an ulp), comments skipped.
#[test]
fn written_scenes_read_back_to_the_same_ellipsoids() {
    let scene = ellipsoid_splat_loaders::md_liquid(500, 3);
    let comments = vec!["camera: --eye 1,2,3".to_string(), "two\nlines".to_string()];
    let text = ellipsoid_splat_loaders::csv_text(&scene, &comments);
    assert!(text.starts_with("# camera: --eye 1,2,3\n# two\n# lines\nx,y,z,"));
    let read = parse_csv(&text, Path::new("written.csv")).unwrap();
    assert_eq!(read.len(), scene.len());
    for (a, b) in scene.ellipsoids.iter().zip(&read.ellipsoids) {
        assert_eq!((a.center, a.radii, a.color), (b.center, b.radii, b.color));
        assert!(a.rotation.abs_diff_eq(b.rotation, 1e-15), "{a:?} {b:?}");
    }
    let dir = std::env::temp_dir().join(format!("es-csv-written-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.csv");
    ellipsoid_splat_loaders::save_csv(&scene, &[], &path).unwrap();
    assert_eq!(load_csv(&path).unwrap().len(), scene.len());
    std::fs::remove_dir_all(&dir).unwrap();
    let missing = dir.join("no-such-dir").join("scene.csv");
    let err = ellipsoid_splat_loaders::save_csv(&scene, &[], &missing).unwrap_err();
    assert!(err.to_string().contains("no-such-dir"), "{err}");
}
