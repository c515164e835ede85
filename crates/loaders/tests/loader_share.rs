//! Files read in shares ([`load_share`]) by 1 to 7 processes, played here by threads: put
//! together by their global indices, the shares are the scene one process loads, glyph for
//! glyph and bit for bit (colours included), every glyph in exactly one share, with the same
//! notes and counts, whatever the cut (byte ranges start mid-line; a process may get nothing);
//! and a bad record fails every process with the whole load's error (file, line, reason) on
//! the process that holds it, the others naming that process.

mod support;

use std::path::Path;

use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat_loaders::{load, load_share, Error, LoadOptions, LoadedShare, Split};
use support::threads::run_as;
use support::{sample, skipping, Rng, TempDir};

/// The most processes tried.
const MOST: usize = 7;

/// Every process's result of reading `path` in `size` shares.
fn shares(path: &Path, options: &LoadOptions, size: usize) -> Vec<Result<LoadedShare, Error>> {
    run_as(size, |exchange| load_share(path, options, exchange))
}

/// The glyphs of `shares` at their global indices: each index from 0 to the total in exactly
/// one share, each share's indices increasing.
fn put_together(shares: &[LoadedShare]) -> Vec<Ellipsoid> {
    let total = shares[0].total as usize;
    let mut slots: Vec<Option<Ellipsoid>> = vec![None; total];
    for (rank, share) in shares.iter().enumerate() {
        assert_eq!(share.indices.len(), share.scene.len(), "rank {rank}");
        assert!(
            share.indices.windows(2).all(|w| w[0] < w[1]),
            "rank {rank}: indices not increasing"
        );
        for (e, &i) in share.scene.ellipsoids.iter().zip(&share.indices) {
            assert!(
                slots[i as usize].replace(*e).is_none(),
                "index {i} in two shares"
            );
        }
    }
    slots
        .into_iter()
        .enumerate()
        .map(|(i, e)| e.unwrap_or_else(|| panic!("index {i} in no share")))
        .collect()
}

/// Glyphs as text that tells every bit (Rust's shortest round-trip floats, `-0.0` included).
fn bits(glyphs: &[Ellipsoid]) -> Vec<String> {
    glyphs.iter().map(|e| format!("{e:?}")).collect()
}

/// The notes but the one about later frames (one process counts them; shares read frame 1).
fn notes(notes: &[String]) -> Vec<&String> {
    notes.iter().filter(|n| !n.starts_with("frame 1")).collect()
}

/// For 1 to 7 processes: the shares of `path` together are `load`'s scene bit for bit, with
/// its counts and notes, divided as `split` says.
fn assert_shares_are_the_whole(path: &Path, options: &LoadOptions, split: Split) {
    let whole = load(path, options).unwrap_or_else(|e| panic!("{e}"));
    for size in 1..=MOST {
        let shares: Vec<LoadedShare> = shares(path, options, size)
            .into_iter()
            .map(|r| r.unwrap_or_else(|e| panic!("{size} processes: {e}")))
            .collect();
        for share in &shares {
            assert_eq!(share.total, whole.scene.len() as u64, "{size} processes");
            assert_eq!(share.skipped, whole.skipped as u64, "{size} processes");
            assert_eq!(notes(&share.notes), notes(&whole.notes), "{size} processes");
            assert_eq!(share.split, split, "{size} processes");
        }
        assert!(
            bits(&put_together(&shares)) == bits(&whole.scene.ellipsoids),
            "{}: {size} processes: the shares differ from the whole",
            path.display()
        );
    }
}

/// For 1 to 7 processes: reading `path` fails on every process; the processes that report an
/// error of their own report the whole load's, and the others name the lowest of them.
fn assert_fails_as_the_whole(path: &Path, options: &LoadOptions) {
    let whole = load(path, options)
        .expect_err("the file is bad")
        .to_string();
    for size in 1..=MOST {
        let errors: Vec<Error> = shares(path, options, size)
            .into_iter()
            .map(|r| r.expect_err("every process fails"))
            .collect();
        let reporting: Vec<usize> = (0..size)
            .filter(|&r| !matches!(errors[r], Error::OtherRank { .. }))
            .collect();
        assert!(!reporting.is_empty(), "{size} processes: nobody reports");
        for (rank, error) in errors.iter().enumerate() {
            match error {
                Error::OtherRank { rank: named, file } => {
                    assert_eq!(*named, reporting[0], "{size} processes, rank {rank}");
                    assert_eq!(file, path);
                }
                other => assert_eq!(other.to_string(), whole, "{size} processes, rank {rank}"),
            }
        }
    }
}

/// An Ellipsoid CSV of `rows` random rows among comment, blank and CRLF lines, after a
/// byte-order mark and comments; `bad` replaces row `bad`'s `ry` with text.
fn csv_text(rows: usize, seed: u64, bad: Option<usize>) -> String {
    let mut rng = Rng::new(seed);
    let mut n = || rng.below(1000) as f64 / 100.0;
    let mut text = String::from("\u{feff}# made by the share test\n\n  # indented comment\n");
    text.push_str("x,y,z,rx,ry,rz,qw,qx,qy,qz,r,g,b\n");
    for k in 0..rows {
        let ry = if bad == Some(k) {
            "oops".to_string()
        } else {
            format!("{}", n() + 0.1)
        };
        text.push_str(&format!(
            "{},{},\"{}\",{},{ry},{},{},{},{},{},{},{},{}",
            n(),
            n(),
            n(),
            n() + 0.1,
            n() + 0.1,
            n() + 0.1,
            n(),
            n(),
            n(),
            n() / 10.0,
            n() / 10.0,
            n() / 10.0,
        ));
        text.push_str(match k % 7 {
            0 => "\r\n",
            3 => "\n# a comment between rows\n",
            5 => "\n\n   \n",
            _ => "\n",
        });
    }
    text
}

#[test]
fn csv_rows_are_read_once_whatever_the_cut() {
    let dir = TempDir::new("share-csv");
    let many = dir.write("many.csv", csv_text(300, 11, None));
    assert_shares_are_the_whole(&many, &LoadOptions::default(), Split::Lines);
    // Fewer rows than processes: some get none; no newline at the end.
    let few = dir.write(
        "few.csv",
        "x,y,z,rx,ry,rz,qw,qx,qy,qz\n1,2,3,1,1,1,1,0,0,0\n4,5,6,1,2,1,1,0,0,1",
    );
    assert_shares_are_the_whole(&few, &LoadOptions::default(), Split::Lines);
    // Rows of one length: the cuts fall exactly on line starts.
    let mut equal = "x,y,z,rx,ry,rz,qw,qx,qy,qz\n".to_string();
    for k in 0..420 {
        equal.push_str(&format!("{:03},2,3,1,1,1,1,0,0,0\n", k));
    }
    let equal = dir.write("equal.csv", equal);
    assert_shares_are_the_whole(&equal, &LoadOptions::default(), Split::Lines);
    // Tensor rows without colours (shape colours).
    let sample = sample("gay-berne-frame1.csv");
    assert_shares_are_the_whole(&sample, &LoadOptions::default(), Split::Lines);
}

#[test]
fn a_bad_csv_row_fails_every_process_with_its_line() {
    let dir = TempDir::new("share-csv-bad");
    let bad = dir.write("bad.csv", csv_text(300, 12, Some(211)));
    assert_fails_as_the_whole(&bad, &LoadOptions::default());
    // Skipped instead: the first skipped row is the file's first, the count the whole's.
    let two = dir.write("two.csv", {
        let mut text = csv_text(300, 12, Some(211));
        text.push_str("1,2,3,1,-1,1,1,0,0,0,0,0,0\n");
        text
    });
    assert_shares_are_the_whole(&two, &skipping(), Split::Lines);
    // A row running over its line's end cannot be cut at line starts.
    let quoted = dir.write(
        "quoted.csv",
        "x,y,z,rx,ry,rz,qw,qx,qy,qz\n1,2,\"3\n\",1,1,1,1,0,0,0\n",
    );
    for result in shares(&quoted, &LoadOptions::default(), 3) {
        let error = result.expect_err("refused").to_string();
        assert!(
            error.contains("runs on past the end of its line") || error.contains("rank 0"),
            "{error}"
        );
    }
    // No header row: read whole, which names the reason.
    let empty = dir.write("empty.csv", "# nothing\n\n");
    assert_fails_as_the_whole(&empty, &LoadOptions::default());
}

/// A one-frame dump of `atoms` random ellipsoids, its ids shuffled (or no id column), types 1
/// to 3; `bad` gives atom line `bad` a non-number.
fn dump_text(atoms: usize, seed: u64, ids: bool, bad: Option<usize>) -> String {
    let mut rng = Rng::new(seed);
    let mut order: Vec<usize> = (1..=atoms).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.below(k + 1));
    }
    let columns = if ids {
        "id type x y z shapex shapey shapez quatw quati quatj quatk"
    } else {
        "type x y z shapex shapey shapez quatw quati quatj quatk"
    };
    let mut text = format!(
        "ITEM: UNITS\nlj\nITEM: TIMESTEP\n40\nITEM: NUMBER OF ATOMS\n{atoms}\n\
         ITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\nITEM: ATOMS {columns}\n"
    );
    for (k, id) in order.iter().enumerate() {
        let mut n = || (rng.below(1000) as f64 / 100.0).to_string();
        let x = if bad == Some(k) { "x".into() } else { n() };
        let id = if ids { format!("{id} ") } else { String::new() };
        text.push_str(&format!(
            "{id}{} {x} {} {} 3 1 1 {} {} {} {}\n",
            1 + k % 3,
            n(),
            n(),
            n(),
            n(),
            n(),
            n()
        ));
    }
    text
}

#[test]
fn lammps_atoms_are_read_once_and_numbered_by_id() {
    let dir = TempDir::new("share-lammps");
    // The sample: eight frames, ids in any order.
    assert_shares_are_the_whole(
        &sample("gay-berne.lammpstrj"),
        &LoadOptions::default(),
        Split::Lines,
    );
    let shuffled = dir.write("shuffled.lammpstrj", dump_text(500, 21, true, None));
    assert_shares_are_the_whole(&shuffled, &LoadOptions::default(), Split::Lines);
    let file_order = dir.write("order.lammpstrj", dump_text(97, 22, false, None) + "\n\n");
    assert_shares_are_the_whole(&file_order, &LoadOptions::default(), Split::Lines);
    // Two atoms for seven processes.
    let two = dir.write("two.lammpstrj", dump_text(2, 23, true, None));
    assert_shares_are_the_whole(&two, &LoadOptions::default(), Split::Lines);
    // gzip is read whole.
    let gz = dir.write("run.lammpstrj.gz", {
        use std::io::Write;
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        encoder
            .write_all(dump_text(50, 24, true, None).as_bytes())
            .unwrap();
        encoder.finish().unwrap()
    });
    assert_shares_are_the_whole(&gz, &LoadOptions::default(), Split::Whole);
}

#[test]
fn bad_lammps_frames_fail_every_process_as_one_process_fails() {
    let dir = TempDir::new("share-lammps-bad");
    let bad = dir.write("bad.lammpstrj", dump_text(300, 31, true, Some(222)));
    assert_fails_as_the_whole(&bad, &LoadOptions::default());
    assert_shares_are_the_whole(&bad, &skipping(), Split::Lines);
    // Atom id 5 twice, on lines far apart.
    let text = dump_text(300, 32, true, None);
    let doubled = text.replacen("\n5 ", "\n6 ", 1);
    assert_ne!(doubled, text);
    let doubled = dir.write("doubled.lammpstrj", doubled);
    assert_fails_as_the_whole(&doubled, &LoadOptions::default());
    // Fewer atom lines than promised, and more.
    let text = dump_text(300, 33, true, None);
    let cut = text.lines().take(200).collect::<Vec<_>>().join("\n");
    let cut = dir.write("cut.lammpstrj", cut);
    assert_fails_as_the_whole(&cut, &LoadOptions::default());
    let longer = dir.write("longer.lammpstrj", text + "\n301 1 1 1 1 3 1 1 1 0 0 0\n");
    assert_fails_as_the_whole(&longer, &LoadOptions::default());
}

/// An extended XYZ frame of `atoms` ellipsoids with species names, ids shuffled (or none).
fn xyz_text(atoms: usize, seed: u64, ids: bool) -> String {
    let mut rng = Rng::new(seed);
    let mut order: Vec<usize> = (1..=atoms).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.below(k + 1));
    }
    let id = if ids { "id:I:1:" } else { "" };
    let mut text =
        format!("{atoms}\nProperties={id}species:S:1:pos:R:3:aspherical_shape:R:3 Timestep=7\n");
    for &k in &order {
        let species = ["Ar", "C", "7", "Xe", "H"][(k * 7 + rng.below(2)) % 5];
        let mut n = || (rng.below(1000) as f64 / 100.0).to_string();
        let id = if ids { format!("{k} ") } else { String::new() };
        text.push_str(&format!(
            "{id}{species} {} {} {} 1.5 0.5 0.5\n",
            n(),
            n(),
            n()
        ));
    }
    text
}

#[test]
fn xyz_atoms_are_read_once_with_species_numbered_as_one_process_does() {
    let dir = TempDir::new("share-xyz");
    assert_shares_are_the_whole(
        &sample("gay-berne.extxyz"),
        &LoadOptions::default(),
        Split::Lines,
    );
    let named = dir.write("named.extxyz", xyz_text(400, 41, true));
    assert_shares_are_the_whole(&named, &LoadOptions::default(), Split::Lines);
    let unnumbered = dir.write(
        "plain.xyz",
        format!("\u{feff}\n{}", xyz_text(150, 42, false)),
    );
    assert_shares_are_the_whole(&unnumbered, &LoadOptions::default(), Split::Lines);
    // Two frames: the second is not read.
    let frames = dir.write(
        "two.extxyz",
        xyz_text(300, 43, true) + &xyz_text(300, 44, true),
    );
    assert_shares_are_the_whole(&frames, &LoadOptions::default(), Split::Lines);
    let mut cut = xyz_text(300, 45, true);
    cut.truncate(cut.len() / 2);
    let cut = dir.write("cut.extxyz", cut);
    assert_fails_as_the_whole(&cut, &LoadOptions::default());
}

#[test]
fn binary_splats_are_read_in_record_ranges_and_ascii_whole() {
    let dir = TempDir::new("share-ply");
    let options = LoadOptions {
        min_opacity: 0.3,
        ..LoadOptions::default()
    };
    assert_shares_are_the_whole(&sample("splats.ply"), &options, Split::Records);
    assert_shares_are_the_whole(&sample("splats_ascii.ply"), &options, Split::Whole);
    // Vertex 2001's opacity made NaN: an error naming it, or skipped.
    let mut bytes = std::fs::read(sample("splats.ply")).unwrap();
    let body = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let stride = 62 * 4;
    let opacity = 54 * 4;
    let at = body + 2000 * stride + opacity;
    bytes[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let bad = dir.write("bad.ply", bytes);
    assert_fails_as_the_whole(&bad, &LoadOptions::default());
    assert_shares_are_the_whole(&bad, &skipping(), Split::Records);
}
