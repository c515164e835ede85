//! Particle files from molecular dynamics: LAMMPS `dump custom` and extended XYZ, plain and
//! gzipped, one frame or many. The same frame written as a dump, as extended XYZ and as
//! Ellipsoid CSV loads to the same scene bit for bit; conventions (diameters, quaternion
//! orders, triclinic boxes) against hand-computed values; every error names the file, frame,
//! timestep, line and column.

mod support;

use std::io::Write;
use std::path::Path;

use ellipsoid_splat::{Ellipsoid, Scene};
use ellipsoid_splat_loaders::load::detect_format;
use ellipsoid_splat_loaders::{
    load, parse_lammps, parse_xyz, Error, Format, LoadOptions, Loaded, Origins, Trajectory,
    TYPE_PALETTE,
};
use glam::DVec3;
use support::{assert_close, assert_contains, assert_note, options, sample, ParseError, TempDir};

/// The header lines of a one-frame orthogonal dump in a 10^3 box; `columns` follow `ATOMS`.
fn dump(step: i64, atoms: &[&str], columns: &str) -> String {
    let mut text = format!(
        "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS pp pp pp\n\
         0 10\n0 10\n0 10\nITEM: ATOMS {columns}\n",
        atoms.len()
    );
    for atom in atoms {
        text.push_str(atom);
        text.push('\n');
    }
    text
}

fn lammps(text: &str) -> Loaded {
    lammps_with(text, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn lammps_with(text: &str, options: &LoadOptions) -> Result<Loaded, Error> {
    parse_lammps(text.as_bytes(), Path::new("run.lammpstrj"), options)
}

fn xyz(text: &str) -> Loaded {
    parse_xyz(
        text.as_bytes(),
        Path::new("run.extxyz"),
        &LoadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The parse error of a load that must fail, taken apart.
fn parse_err<T: std::fmt::Debug>(result: Result<T, Error>, file: &str) -> ParseError {
    support::parse_error(result, Path::new(file), b"")
}

/// Every field of two scenes' ellipsoids compared by their bits.
fn assert_same_bits(a: &Scene, b: &Scene, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    let bits = |e: &Ellipsoid| {
        let mut v: Vec<u64> = e.center.to_array().map(f64::to_bits).to_vec();
        v.extend(e.radii.to_array().map(f64::to_bits));
        v.extend(e.rotation.to_array().map(f64::to_bits));
        v.extend(e.color.map(|c| u64::from(c.to_bits())));
        v
    };
    for (i, (x, y)) in a.ellipsoids.iter().zip(&b.ellipsoids).enumerate() {
        assert_eq!(bits(x), bits(y), "{what}: ellipsoid {i}: {x:?} vs {y:?}");
    }
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

#[test]
fn one_frame_as_dump_xyz_and_csv_is_the_same_scene_bit_for_bit() {
    let options = LoadOptions::default();
    let dump = load(&sample("gay-berne.lammpstrj"), &options).unwrap();
    let xyz = load(&sample("gay-berne.extxyz"), &options).unwrap();
    let csv = load(&sample("gay-berne-frame1.csv"), &options).unwrap();
    assert_eq!(dump.scene.len(), 240);
    assert_same_bits(&dump.scene, &csv.scene, "dump vs CSV");
    assert_same_bits(&xyz.scene, &csv.scene, "extended XYZ vs CSV");
    // The dump's atoms come shuffled; sorted by id both name the same atoms in order.
    let ids = |l: &Loaded| match &l.origins {
        Origins::Particles(p) => p.iter().map(|&(_, id)| id).collect::<Vec<_>>(),
        other => panic!("{other:?}"),
    };
    assert_eq!(ids(&dump), (1..=240).collect::<Vec<i64>>());
    assert_eq!(ids(&xyz), ids(&dump));
    // Rods are type 1 with diameters 3:1:1, spheres type 2 with diameter 1.
    let rod = &dump.scene.ellipsoids[0];
    assert_eq!(
        (rod.radii, rod.color),
        (DVec3::new(1.5, 0.5, 0.5), TYPE_PALETTE[0])
    );
    let sphere = &dump.scene.ellipsoids[239];
    assert_eq!(
        (sphere.radii, sphere.color),
        (DVec3::splat(0.5), TYPE_PALETTE[1])
    );
    assert_note(&dump.notes, "frame 1 of 8");
    assert_note(&xyz.notes, "frame 1 of 8");
}

#[test]
fn every_frame_of_the_samples_agrees_and_is_reached_at_random() {
    let options = LoadOptions::default();
    let dump = Trajectory::open(&sample("gay-berne.lammpstrj"), &options).unwrap();
    let xyz = Trajectory::open(&sample("gay-berne.extxyz"), &options).unwrap();
    assert_eq!((dump.len(), xyz.len()), (8, 8));
    assert_eq!(
        (dump.format(), xyz.format()),
        (Format::LammpsDump, Format::ExtendedXyz)
    );
    assert_eq!(dump.path(), sample("gay-berne.lammpstrj"));
    for i in [5, 0, 7, 2] {
        let (a, b) = (dump.frame(i).unwrap(), xyz.frame(i).unwrap());
        assert_same_bits(&a.scene, &b.scene, &format!("frame {}", i + 1));
        assert_eq!(dump.timestep(i), Some(500 * i as i64));
        assert_eq!(xyz.timestep(i), Some(500 * i as i64));
    }
    // Particles move from frame to frame.
    let (first, last) = (dump.frame(0).unwrap(), dump.frame(7).unwrap());
    assert_ne!(
        first.scene.ellipsoids[0].center,
        last.scene.ellipsoids[0].center
    );
    let past = dump.frame(8).unwrap_err().to_string();
    assert_contains(&past, &["frame index", "8", "8 frame(s)"]);
    assert_eq!(dump.timestep(8), None);
    // A single-frame format is a trajectory of one frame.
    let csv = Trajectory::open(&sample("gay-berne-frame1.csv"), &options).unwrap();
    assert_eq!(
        (csv.len(), csv.is_empty(), csv.timestep(0)),
        (1, false, None)
    );
    assert_same_bits(&csv.frame(0).unwrap().scene, &first.scene, "CSV trajectory");
    assert!(csv.frame(1).is_err());
}

#[test]
fn gzip_loads_the_same_as_plain_and_is_recognised_inside() {
    let dir = TempDir::new("particles-gzip");
    let options = LoadOptions::default();
    for name in ["gay-berne.lammpstrj", "gay-berne.extxyz"] {
        let plain = std::fs::read(sample(name)).unwrap();
        let gz = dir.write(&format!("{name}.gz"), gzip(&plain));
        let a = Trajectory::open(&sample(name), &options).unwrap();
        let b = Trajectory::open(&gz, &options).unwrap();
        assert_eq!(a.len(), b.len());
        for i in 0..a.len() {
            assert_same_bits(&a.frame(i).unwrap().scene, &b.frame(i).unwrap().scene, name);
        }
        // No telling extension: the format is found inside the gzip stream.
        let bare = dir.write(&format!("{name}-data.gz"), gzip(&plain));
        let bare_plain = dir.write(&format!("{name}-data"), &plain);
        assert_eq!(detect_format(&bare).unwrap(), a.format());
        assert_eq!(detect_format(&bare_plain).unwrap(), a.format());
        assert_same_bits(
            &load(&bare, &options).unwrap().scene,
            &a.frame(0).unwrap().scene,
            name,
        );
    }
    // Gzip that is not a particle file is still NIfTI.
    assert_eq!(detect_format(&sample("dti.nii.gz")).unwrap(), Format::Nifti);
    let other = dir.write("volume.gz", gzip(b"not a particle file"));
    assert_eq!(detect_format(&other).unwrap(), Format::Nifti);
    // A truncated stream is a named error.
    let plain = std::fs::read(sample("gay-berne.lammpstrj")).unwrap();
    let gz = gzip(&plain);
    let cut = parse_err(
        parse_lammps(&gz[..gz.len() / 2], Path::new("cut.lammpstrj.gz"), &options),
        "cut.lammpstrj.gz",
    );
    cut.assert_at(0, "gzip", &["truncated gzip stream"]);
}

#[test]
fn extensions_pick_the_particle_formats() {
    for (name, format) in [
        ("a.lammpstrj", Format::LammpsDump),
        ("a.dump", Format::LammpsDump),
        ("a.lammpsdump.gz", Format::LammpsDump),
        ("A.XYZ", Format::ExtendedXyz),
        ("a.extxyz.gz", Format::ExtendedXyz),
        ("a.nii.gz", Format::Nifti),
    ] {
        // The file need not exist: the extension decides.
        assert_eq!(detect_format(Path::new(name)).unwrap(), format, "{name}");
    }
}

#[test]
fn shape_columns_are_diameters_and_quaternions_rotate_body_into_lab() {
    // Diameters (2, 1, 1) turned 90 degrees about z: the long axis lies along y.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let atom = format!("1 1 1 2 3 2 1 1 {h} 0 0 {h}");
    let loaded = lammps(&dump(
        0,
        &[&atom],
        "id type x y z shapex shapey shapez quatw quati quatj quatk",
    ));
    let e = &loaded.scene.ellipsoids[0];
    assert_eq!(e.center, DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(e.radii, DVec3::new(1.0, 0.5, 0.5));
    let (lo, hi) = loaded.scene.bounds().unwrap();
    assert_close((hi - lo) / 2.0, DVec3::new(0.5, 1.0, 0.5), 1e-12);
    assert_close(e.to_world().x_axis, DVec3::new(0.0, 1.0, 0.0), 1e-12);
    // The same particle in extended XYZ: semi-axes, quaternion x y z w.
    let text = format!(
        "1\nProperties=species:S:1:pos:R:3:aspherical_shape:R:3:orientation:R:4\n\
         A 1 2 3 1 0.5 0.5 0 0 {h} {h}\n"
    );
    let x = xyz(&text);
    assert_eq!(x.scene.ellipsoids[0], *e);
    // And in Ellipsoid CSV (qw first): the same ellipsoid.
    let csv = ellipsoid_splat_loaders::parse_csv(
        &format!(
            "x,y,z,rx,ry,rz,qw,qx,qy,qz,r,g,b\n1,2,3,1,0.5,0.5,{h},0,0,{h},0.125,0.4375,0.6875\n"
        ),
        Path::new("one.csv"),
    )
    .unwrap();
    assert_eq!(csv.ellipsoids[0], *e);
}

#[test]
fn spheres_take_radius_or_diameter_and_zero_shapes_their_radius() {
    let r = lammps(&dump(0, &["1 1 1 1 1 0.75"], "id type x y z radius"));
    assert_eq!(r.scene.ellipsoids[0].radii, DVec3::splat(0.75));
    let d = lammps(&dump(0, &["1 1 1 1 1 0.75"], "id type x y z diameter"));
    assert_eq!(d.scene.ellipsoids[0].radii, DVec3::splat(0.375));
    // Gay-Berne mixtures: point particles have shape 0 0 0 and a radius.
    let mixed = lammps(&dump(
        0,
        &["1 1 0 0 0 3 1 1 0.5", "2 2 5 5 5 0 0 0 0.25"],
        "id type x y z shapex shapey shapez radius",
    ));
    assert_eq!(mixed.scene.ellipsoids[0].radii, DVec3::new(1.5, 0.5, 0.5));
    assert_eq!(mixed.scene.ellipsoids[1].radii, DVec3::splat(0.25));
    assert_note(&mixed.notes, "unrotated");
    // Without a radius a zero shape is an error naming the shape columns.
    let e = parse_err(
        lammps_with(
            &dump(
                7,
                &["1 1 0 0 0 0 0 0"],
                "id type x y z shapex shapey shapez",
            ),
            &LoadOptions::default(),
        ),
        "run.lammpstrj",
    );
    e.assert_at(10, "frame 1 (timestep 7), shapex shapey shapez (a zero shape is a point particle: give it a radius or diameter column)", &["radii"]);
}

#[test]
fn scaled_coordinates_go_through_the_triclinic_box() {
    // xlo=1 xhi=11, ylo=2 yhi=10, zlo=-3 zhi=3; xy=2 xz=-1 yz=1.5. The bounds LAMMPS writes:
    // x: 1 + min(0, 2, -1, 1) = 0 and 11 + max(0, 2, -1, 1) = 13; y: 2 + 0 and 10 + 1.5.
    let text = "ITEM: TIMESTEP\n3\nITEM: NUMBER OF ATOMS\n2\n\
                ITEM: BOX BOUNDS xy xz yz pp pp pp\n0 13 2\n2 11.5 -1\n-3 3 1.5\n\
                ITEM: ATOMS id type xs ys zs radius\n\
                2 1 0.5 0.5 0.5 1\n1 1 0 0 0 1\n";
    let loaded = lammps(text);
    // Sorted by id: the origin corner first, then the cell's centre
    // origin + (a + b + c) / 2 = (1, 2, -3) + ((10 + 2 - 1) / 2, (8 + 1.5) / 2, 6 / 2).
    assert_eq!(
        loaded.scene.ellipsoids[0].center,
        DVec3::new(1.0, 2.0, -3.0)
    );
    assert_eq!(
        loaded.scene.ellipsoids[1].center,
        DVec3::new(6.5, 6.75, 0.0)
    );
    assert_eq!(loaded.origins, Origins::Particles(vec![(11, 1), (10, 2)]));
    // Orthogonal box, xsu: x = lo + s (hi - lo).
    let ortho = lammps(&dump(
        0,
        &["1 1 0.25 1.5 -0.5 1"],
        "id type xsu ysu zsu radius",
    ));
    assert_eq!(
        ortho.scene.ellipsoids[0].center,
        DVec3::new(2.5, 15.0, -5.0)
    );
}

#[test]
fn atoms_in_any_order_are_sorted_by_id_and_described() {
    let text = dump(
        0,
        &["30 1 3 0 0 1", "10 2 1 0 0 1", "20 1 2 0 0 1"],
        "id type x y z radius",
    );
    let loaded = lammps(&text);
    let xs: Vec<f64> = loaded.scene.ellipsoids.iter().map(|e| e.center.x).collect();
    assert_eq!(xs, [1.0, 2.0, 3.0]);
    assert_eq!(
        loaded.origins,
        Origins::Particles(vec![(11, 10), (12, 20), (10, 30)])
    );
    assert_eq!(
        loaded.origins.describe(0).as_deref(),
        Some("atom id 10, line 11")
    );
    let colors: Vec<[f32; 3]> = loaded.scene.ellipsoids.iter().map(|e| e.color).collect();
    assert_eq!(colors, [TYPE_PALETTE[1], TYPE_PALETTE[0], TYPE_PALETTE[0]]);
    // Two atoms with one id: an error naming both lines.
    let twice = dump(0, &["5 1 3 0 0 1", "5 1 1 0 0 1"], "id type x y z radius");
    parse_err(
        lammps_with(&twice, &LoadOptions::default()),
        "run.lammpstrj",
    )
    .assert_at(
        11,
        "frame 1 (timestep 0), id",
        &["duplicate atom id 5", "line 10"],
    );
}

#[test]
fn types_cycle_through_the_palette_or_the_users_colours() {
    let atoms: Vec<String> = (1..=12).map(|t| format!("{t} {t} 0 0 0 1")).collect();
    let atoms: Vec<&str> = atoms.iter().map(String::as_str).collect();
    let text = dump(0, &atoms, "id type x y z radius");
    let loaded = lammps(&text);
    assert_eq!(loaded.scene.ellipsoids[10].color, TYPE_PALETTE[0]);
    assert_eq!(loaded.scene.ellipsoids[11].color, TYPE_PALETTE[1]);
    let user = options(|o| o.type_colors = vec![[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
    let loaded = lammps_with(&text, &user).unwrap();
    assert_eq!(loaded.scene.ellipsoids[2].color, [1.0, 0.0, 0.0]);
    assert_eq!(loaded.scene.ellipsoids[3].color, [0.0, 0.0, 1.0]);
    // Any integer type has a colour: 0, negative, the extremes.
    let odd = lammps(&dump(
        0,
        &[
            "1 0 0 0 0 1",
            "2 -1 0 0 0 1",
            "3 -9223372036854775808 0 0 0 1",
            "4 9223372036854775807 0 0 0 1",
        ],
        "id type x y z radius",
    ));
    let colors: Vec<[f32; 3]> = odd.scene.ellipsoids.iter().map(|e| e.color).collect();
    // (t - 1) mod 10: 9, 8, 1 (-2^63 - 1 = -9223372036854775809), 6 (2^63 - 2).
    assert_eq!(
        colors,
        [
            TYPE_PALETTE[9],
            TYPE_PALETTE[8],
            TYPE_PALETTE[1],
            TYPE_PALETTE[6]
        ]
    );
    let bad = options(|o| o.type_colors = vec![[2.0, 0.0, 0.0]]);
    assert!(matches!(
        lammps_with(&text, &bad),
        Err(Error::Invalid { .. })
    ));
    // Without a type, glyphs are coloured by shape, as Ellipsoid CSV without colours.
    let plain = lammps(&dump(0, &["1 0 0 0 1"], "id x y z radius"));
    assert_eq!(
        plain.scene.ellipsoids[0].color,
        Ellipsoid::new(DVec3::ZERO, DVec3::ONE, glam::DQuat::IDENTITY, None)
            .unwrap()
            .color
    );
}

#[test]
fn columns_of_older_builds_are_read_through_the_mapping() {
    let text = dump(
        0,
        &["1 1 0 0 0 4 2 2 1 0 0 0 0.5 0.25 1 9.5"],
        "id type x y z c_shape[1] c_shape[2] c_shape[3] c_orient[1] c_orient[2] c_orient[3] \
         c_orient[4] c_rgb[1] c_rgb[2] c_rgb[3] vx",
    );
    // Unmapped, the file has no size.
    let missing = parse_err(lammps_with(&text, &LoadOptions::default()), "run.lammpstrj");
    missing.assert_at(
        9,
        "frame 1 (timestep 0), ITEM: ATOMS",
        &["no particle size", "shapex", "radius"],
    );
    let mut mapping: Vec<(String, String)> = ["shapex", "shapey", "shapez"]
        .iter()
        .enumerate()
        .map(|(i, s)| (s.to_string(), format!("c_shape[{}]", i + 1)))
        .collect();
    for (i, s) in ["quatw", "quati", "quatj", "quatk"].iter().enumerate() {
        mapping.push((s.to_string(), format!("c_orient[{}]", i + 1)));
    }
    for (i, s) in ["r", "g", "b"].iter().enumerate() {
        mapping.push((s.to_string(), format!("c_rgb[{}]", i + 1)));
    }
    let loaded = lammps_with(&text, &options(|o| o.columns = mapping.clone())).unwrap();
    let e = &loaded.scene.ellipsoids[0];
    assert_eq!(e.radii, DVec3::new(2.0, 1.0, 1.0));
    assert_eq!(e.color, [0.5, 0.25, 1.0]);
    assert_eq!(loaded.notes, ["columns not read: vx"]);
    // A mapping to a column the file lacks, and an unknown standard name.
    mapping.push(("radius".into(), "c_radius".into()));
    let lacks = parse_err(
        lammps_with(&text, &options(|o| o.columns = mapping.clone())),
        "run.lammpstrj",
    );
    lacks.assert_at(
        9,
        "frame 1 (timestep 0), ITEM: ATOMS",
        &["radius -> c_radius", "no column \"c_radius\""],
    );
    let unknown = options(|o| o.columns = vec![("shape".into(), "c_shape[1]".into())]);
    let e = lammps_with(&text, &unknown).unwrap_err();
    assert!(matches!(e, Error::Invalid { .. }), "{e}");
    assert_contains(
        &e.to_string(),
        &["\"shape\" is not a standard LAMMPS dump name"],
    );
    // Extended XYZ properties map the same way.
    let text = "1\nProperties=pos:R:3:semi:R:3\n0 0 0 3 2 1\n";
    let mapped = options(|o| o.columns = vec![("aspherical_shape".into(), "semi".into())]);
    let x = parse_xyz(text.as_bytes(), Path::new("m.xyz"), &mapped).unwrap();
    assert_eq!(x.scene.ellipsoids[0].radii, DVec3::new(3.0, 2.0, 1.0));
}

#[test]
fn errors_name_file_frame_timestep_line_and_column() {
    let frame1 = dump(100, &["1 1 0 0 0 1"], "id type x y z radius");
    let frame2 = dump(
        200,
        &["1 1 0 0 0 1", "2 1 0 nan 0 1"],
        "id type x y z radius",
    );
    let text = frame1 + &frame2;
    let dir = TempDir::new("particles-errors");
    let path = dir.write("bad.lammpstrj", &text);
    let t = Trajectory::open(&path, &LoadOptions::default()).unwrap();
    assert!(t.frame(0).is_ok());
    let e = parse_err(t.frame(1), path.to_str().unwrap());
    let message = e.assert_at(
        21,
        "frame 2 (timestep 200), y (field 4)",
        &["non-finite", "nan"],
    );
    assert!(
        message.starts_with(&format!("{}:21:", path.display())),
        "{message}"
    );
    // skip_invalid drops the atom and says which.
    let t = Trajectory::open(&path, &options(|o| o.skip_invalid = true)).unwrap();
    let kept = t.frame(1).unwrap();
    assert_eq!((kept.scene.len(), kept.skipped), (1, 1));
    assert_note(
        &kept.notes,
        "bad.lammpstrj:21:frame 2 (timestep 200), y (field 4)",
    );

    let short = dump(5, &["1 1 0 0 0 1", "2 1 0 0"], "id type x y z radius");
    parse_err(
        lammps_with(&short, &LoadOptions::default()),
        "run.lammpstrj",
    )
    .assert_at(
        11,
        "frame 1 (timestep 5), atom line",
        &["expected 6", "found 4"],
    );
    let truncated = dump(5, &["1 1 0 0 0 1"], "id type x y z radius").replace("ATOMS 1", "ATOMS 3");
    let truncated = truncated.replace("ATOMS\n1\n", "ATOMS\n3\n");
    parse_err(
        lammps_with(&truncated, &LoadOptions::default()),
        "run.lammpstrj",
    )
    .assert_at(
        10,
        "frame 1 (timestep 5), ITEM: ATOMS",
        &["truncated", "1 of 3"],
    );
    let no_dump = parse_err(
        lammps_with("hello\n", &LoadOptions::default()),
        "run.lammpstrj",
    );
    no_dump.assert_at(0, "ITEM: TIMESTEP", &["not a LAMMPS dump"]);
    let partial = dump(
        0,
        &["1 0 0 0 1 1 1 1 0 0"],
        "id x y z shapex shapey shapez quatw quati quatj",
    );
    parse_err(
        lammps_with(&partial, &LoadOptions::default()),
        "run.lammpstrj",
    )
    .assert_at(
        9,
        "frame 1 (timestep 0), ITEM: ATOMS",
        &["partial quaternion", "quatk"],
    );

    // Extended XYZ: frame 2, its line and property component.
    let text = "1\nProperties=pos:R:3:radius:R:1 Timestep=10\n0 0 0 1\n\
                1\nProperties=pos:R:3:radius:R:1 Timestep=20\n0 x 0 1\n";
    let t = Trajectory::from_bytes(
        text.as_bytes().to_vec(),
        Path::new("run.extxyz"),
        Format::ExtendedXyz,
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!((t.timestep(0), t.timestep(1)), (Some(10), Some(20)));
    parse_err(t.frame(1), "run.extxyz").assert_at(
        6,
        "frame 2 (timestep 20), pos[2] (field 2)",
        &["not a number: \"x\""],
    );
    let truncated = parse_err(
        parse_xyz(
            b"3\nProperties=pos:R:3:radius:R:1\n0 0 0 1\n",
            Path::new("t.xyz"),
            &LoadOptions::default(),
        ),
        "t.xyz",
    );
    truncated.assert_at(3, "frame 1, atoms", &["1 of 3"]);
    let no_size = parse_err(
        parse_xyz(
            b"1\nProperties=species:S:1:pos:R:3\nC 0 0 0\n",
            Path::new("s.xyz"),
            &LoadOptions::default(),
        ),
        "s.xyz",
    );
    no_size.assert_at(
        2,
        "frame 1, Properties",
        &["no particle size", "aspherical_shape", "radius"],
    );
}

#[test]
fn extended_xyz_reads_species_ids_and_colours() {
    let text = "3\nLattice=\"10 0 0 0 10 0 0 0 10\" Properties=species:S:1:pos:R:3:radius:R:1:id:I:1:forces:R:3 energy=-1.5\n\
                Ar 0 0 0 1 3 0 0 0\nNe 1 0 0 2 1 0 0 0\nAr 2 0 0 1 2 0 0 0\n";
    let loaded = xyz(text);
    let xs: Vec<f64> = loaded.scene.ellipsoids.iter().map(|e| e.center.x).collect();
    assert_eq!(xs, [1.0, 2.0, 0.0]);
    // Names are numbered by first appearance in id order: Ne (id 1) 1, Ar 2.
    let colors: Vec<[f32; 3]> = loaded.scene.ellipsoids.iter().map(|e| e.color).collect();
    assert_eq!(colors, [TYPE_PALETTE[0], TYPE_PALETTE[1], TYPE_PALETTE[1]]);
    assert_eq!(loaded.notes, ["properties not read: forces"]);
    assert_eq!(
        loaded.origins,
        Origins::Particles(vec![(4, 1), (5, 2), (3, 3)])
    );
    let colored = xyz("1\nProperties=pos:R:3:radius:R:1:color:R:3\n0 0 0 1 0.25 0.5 1\n");
    assert_eq!(colored.scene.ellipsoids[0].color, [0.25, 0.5, 1.0]);
}

#[test]
fn lammps_errors_name_the_frame_and_timestep() {
    let text = "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n\
                0 1\n0 1\n0 1\nITEM: ATOMS id x y z radius\n1 0 0 0 0.5\n\
                ITEM: TIMESTEP\n200\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n\
                0 1\n0 1\n0 1\nITEM: ATOMS id x y z radius\n1 0 0 zz 0.5\n";
    let t = Trajectory::from_bytes(
        text.as_bytes().to_vec(),
        Path::new("t.lammpstrj"),
        Format::LammpsDump,
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(
        (t.len(), t.timestep(0), t.timestep(1)),
        (2, Some(100), Some(200))
    );
    let e = t.frame(1).unwrap_err().to_string();
    assert_eq!(
        e,
        "t.lammpstrj:20:frame 2 (timestep 200), z (field 4): not a number: \"zz\""
    );
}

#[test]
fn species_names_keep_their_colours_when_frames_reorder_their_lines() {
    // The same three atoms (fixed ids and species), listed in another order in frame 2.
    let text = "3\nProperties=species:S:1:pos:R:3:radius:R:1:id:I:1 Timestep=0\n\
                C 0 0 0 1 3\nO 1 0 0 1 1\nH 2 0 0 1 2\n\
                3\nProperties=species:S:1:pos:R:3:radius:R:1:id:I:1 Timestep=10\n\
                H 2 0 0 1 2\nC 0 0 0 1 3\nO 1 0 0 1 1\n";
    let t = Trajectory::from_bytes(
        text.as_bytes().to_vec(),
        Path::new("md.extxyz"),
        Format::ExtendedXyz,
        &LoadOptions::default(),
    )
    .unwrap();
    let colors = |i: usize| -> Vec<[f32; 3]> {
        let frame = t.frame(i).unwrap();
        frame.scene.ellipsoids.iter().map(|e| e.color).collect()
    };
    // Id order O (1), H (2), C (3): O is species 1, H 2, C 3 in both frames.
    let expected = [TYPE_PALETTE[0], TYPE_PALETTE[1], TYPE_PALETTE[2]];
    assert_eq!(colors(0), expected);
    assert_eq!(colors(1), expected);
    // `load` gives frame 1 the same colours.
    let first = parse_xyz(
        text.as_bytes(),
        Path::new("md.extxyz"),
        &LoadOptions::default(),
    )
    .unwrap();
    let first: Vec<[f32; 3]> = first.scene.ellipsoids.iter().map(|e| e.color).collect();
    assert_eq!(first, expected);
}

#[test]
fn species_names_of_skipped_lines_do_not_count() {
    // "Xe" first appears on a bad line; with skip_invalid the kept atoms number Ar 1, Ne 2.
    let text = "4\nProperties=species:S:1:pos:R:3:radius:R:1:id:I:1\n\
                Xe 0 0 0 -1 1\nKr 0 0 0 -1 2\nNe 1 0 0 1 4\nAr 2 0 0 1 3\n";
    let loaded = parse_xyz(
        text.as_bytes(),
        Path::new("skip.extxyz"),
        &options(|o| o.skip_invalid = true),
    )
    .unwrap();
    assert_eq!(loaded.skipped, 2);
    let colors: Vec<[f32; 3]> = loaded.scene.ellipsoids.iter().map(|e| e.color).collect();
    assert_eq!(colors, [TYPE_PALETTE[0], TYPE_PALETTE[1]]);
}

#[test]
fn properties_declaring_too_many_fields_are_a_parse_error_not_an_allocation() {
    // One huge count.
    let text = "1\nProperties=pos:R:3:radius:R:1:a:R:100000000\n0 0 0 1 0\n";
    let e = parse_err(
        parse_xyz(
            text.as_bytes(),
            Path::new("big.extxyz"),
            &LoadOptions::default(),
        ),
        "big.extxyz",
    );
    assert_eq!((e.line, e.column.as_str()), (2, "frame 1, Properties"));
    assert_contains(&e.reason, &["a", "100000000", "expected 1 to 4096"]);
    // Many triplets, each within the per-property count: 10,000 of a:R:1024 would be ten
    // million fields.
    let text = format!(
        "1\nProperties=pos:R:3:radius:R:1{}\n0 0 0 1\n",
        ":a:R:1024".repeat(10_000)
    );
    let e = parse_err(
        parse_xyz(
            text.as_bytes(),
            Path::new("many.extxyz"),
            &LoadOptions::default(),
        ),
        "many.extxyz",
    );
    assert_eq!((e.line, e.column.as_str()), (2, "frame 1, Properties"));
    assert_contains(&e.reason, &["field 4100", "at most 4096 fields"]);
    // Up to the cap is read; a field's name in errors is built from its property.
    let fill = " 0".repeat(4000);
    let good = format!(
        "1\nProperties=a:R:4000:pos:R:3:radius:R:1:b:R:92\n{fill} 0 0 0 1{}\n",
        " 0".repeat(92)
    );
    let loaded = xyz(&good);
    assert_eq!(loaded.scene.len(), 1);
    assert_eq!(loaded.notes, ["properties not read: a b"]);
    let bad = format!(
        "1\nProperties=a:R:4000:pos:R:3:radius:R:1:b:R:92\n{fill} 0 y 0 1{}\n",
        " 0".repeat(92)
    );
    let e = parse_err(
        parse_xyz(
            bad.as_bytes(),
            Path::new("cap.extxyz"),
            &LoadOptions::default(),
        ),
        "cap.extxyz",
    );
    assert_eq!(e.column, "frame 1, pos[2] (field 4002)");
    assert_eq!(e.reason, "not a number: \"y\"");
}

#[test]
fn a_species_column_may_mix_names_and_type_numbers() {
    // Found by the xyz fuzz target: a name among integers (and the id sort) indexed past
    // the names. Integers are types; names are numbered 1, 2, ... in id order.
    let text = "3\nProperties=id:I:1:species:S:1:pos:R:3:radius:R:1\n\
                3 C 0 0 0 1\n1 3 1 0 0 1\n2 O 2 0 0 1\n";
    let loaded = xyz(text);
    let colors: Vec<[f32; 3]> = loaded.scene.ellipsoids.iter().map(|e| e.color).collect();
    assert_eq!(colors, [TYPE_PALETTE[2], TYPE_PALETTE[0], TYPE_PALETTE[1]]);
}
