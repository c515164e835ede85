//! Sort-last compositing under `mpirun` (Debian's OpenMPI, scripts/setup.sh): 1, 2, 3, 4 and 8
//! ranks as processes on this machine, every case of `composite-check` bit-identical to one
//! process drawing every glyph, under validation; and the bytes a rank sends stay below one
//! image however many ranks there are.

use std::process::Command;

/// Bytes a 160 x 120 image takes in compositing words (32 a pixel).
const IMAGE_BYTES: u64 = 160 * 120 * 32;

fn run(ranks: u32) -> String {
    let output = Command::new("mpirun")
        .args([
            "--oversubscribe",
            "--allow-run-as-root",
            "-n",
            &ranks.to_string(),
        ])
        .arg(env!("CARGO_BIN_EXE_composite-check"))
        .output()
        .expect("mpirun (Debian's openmpi-bin, scripts/setup.sh) runs");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{ranks} ranks: exit {:?}\n{stdout}\n{}",
        output.status.code(),
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

#[test]
fn composited_frames_equal_one_process_for_1_2_3_4_and_8_ranks() {
    for ranks in [1, 2, 3, 4, 8] {
        let out = run(ranks);
        let cases: Vec<&str> = out.lines().filter(|l| l.starts_with("case ")).collect();
        assert_eq!(cases.len(), 7, "{ranks} ranks:\n{out}");
        for line in cases {
            assert!(line.contains(": match,"), "{ranks} ranks: {line}");
            let bytes: u64 = line.rsplit(' ').next().unwrap().parse().unwrap();
            if ranks == 1 {
                assert_eq!(bytes, 0, "one rank sends nothing: {line}");
            } else {
                // Binary swap: less than one image each, whatever the rank count (a folded
                // rank sends one whole image; the others halves, quarters, ... and a slice).
                assert!(bytes <= IMAGE_BYTES, "{ranks} ranks: {line}");
            }
        }
    }
}
