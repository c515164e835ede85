//! Every loader records where each glyph came from, one entry per glyph in scene order, and
//! the entries point at the records that were kept (filtered and skipped ones leave gaps).

use std::path::{Path, PathBuf};

use ellipsoid_splat_loaders::{load, LoadOptions, Origins};

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/samples")
        .join(name)
}

#[test]
fn csv_rows_are_named_by_their_lines() {
    let dir = std::env::temp_dir().join(format!("es-origins-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("rows.csv");
    // Line 1 header, 2 a comment, 3 a row, 4 an invalid row (skipped), 5 blank, 6 a row.
    let text = "x,y,z,rx,ry,rz,qw,qx,qy,qz\n# a comment\n0,0,0,1,1,1,1,0,0,0\n\
                0,0,0,-1,1,1,1,0,0,0\n\n2,0,0,1,2,3,1,0,0,0\n";
    std::fs::write(&path, text).unwrap();
    let options = LoadOptions {
        skip_invalid: true,
        ..LoadOptions::default()
    };
    let loaded = load(&path, &options).unwrap();
    assert_eq!(loaded.scene.len(), 2);
    assert_eq!(loaded.origins, Origins::Lines(vec![3, 6]));
    assert_eq!(loaded.origins.describe(1).as_deref(), Some("line 6"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn splats_keep_their_vertex_indices_when_some_are_left_out() {
    let all = load(&sample("splats.ply"), &LoadOptions::default()).unwrap();
    let Origins::Vertices(every) = &all.origins else {
        panic!("{:?}", all.origins);
    };
    assert_eq!(every.len(), all.scene.len());
    // Leave out the fainter splats: the kept ones keep their own vertex indices.
    let options = LoadOptions {
        min_opacity: 0.5,
        ..LoadOptions::default()
    };
    let some = load(&sample("splats.ply"), &options).unwrap();
    let Origins::Vertices(kept) = &some.origins else {
        panic!("{:?}", some.origins);
    };
    assert_eq!(kept.len(), some.scene.len());
    assert!(kept.len() < every.len() && kept.windows(2).all(|w| w[0] < w[1]));
    // The same splat at its vertex in the full load.
    let n = kept.len() / 2;
    let at_vertex = every.iter().position(|&v| v == kept[n]).unwrap();
    assert_eq!(some.scene.ellipsoids[n], all.scene.ellipsoids[at_vertex]);
    // Described 1-based, as the loader's "vertex N" errors number them.
    assert_eq!(
        some.origins.describe(n),
        Some(format!("splat (vertex) {}", kept[n] + 1))
    );
}

#[test]
fn atoms_are_named_with_residue_and_line() {
    for name in ["thermal.pdb", "thermal.cif"] {
        let loaded = load(&sample(name), &LoadOptions::default()).unwrap();
        let Origins::Atoms(atoms) = &loaded.origins else {
            panic!("{name}: {:?}", loaded.origins);
        };
        assert_eq!(atoms.len(), loaded.scene.len(), "{name}");
        let (line, label) = &atoms[0];
        assert!(
            *line > 0 && label.starts_with("atom ") && label.contains('('),
            "{name}: {label}"
        );
    }
    // docs/viewer.md's pick example: the sample's atom 5 is the second with ANISOU parameters.
    let loaded = load(&sample("thermal.pdb"), &LoadOptions::default()).unwrap();
    assert_eq!(
        loaded.origins.describe(1).as_deref(),
        Some("atom 5 CA1 (GSH A 1), line 11")
    );
}

#[test]
fn tensor_glyphs_are_named_by_their_voxels() {
    let options = LoadOptions {
        mask: Some(sample("dti_mask.nii.gz")),
        ..LoadOptions::default()
    };
    let loaded = load(&sample("dti.nii.gz"), &options).unwrap();
    let Origins::Voxels(voxels) = &loaded.origins else {
        panic!("{:?}", loaded.origins);
    };
    assert_eq!(voxels.len(), loaded.scene.len());
    assert!(voxels
        .windows(2)
        .all(|w| (w[0][2], w[0][1], w[0][0]) < (w[1][2], w[1][1], w[1][0])));
}
