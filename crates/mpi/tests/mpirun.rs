//! Sort-last compositing under `mpirun` (Debian's OpenMPI, scripts/setup.sh): 1, 2, 3, 4, 5 and 8
//! ranks as processes on this machine, every case of `composite-check` bit-identical to one
//! process drawing every glyph, under validation; and the bytes a rank sends stay below one
//! image however many ranks there are; a rank that fails stops them all with named errors.

use std::process::Command;

/// Bytes a 160 x 120 image takes in compositing words (32 a pixel).
const IMAGE_BYTES: u64 = 160 * 120 * 32;

fn mpirun(ranks: u32, args: &[&str]) -> std::process::Output {
    Command::new("mpirun")
        .args([
            "--oversubscribe",
            "--allow-run-as-root",
            "-n",
            &ranks.to_string(),
        ])
        .arg(env!("CARGO_BIN_EXE_composite-check"))
        .args(args)
        .output()
        .expect("mpirun (Debian's openmpi-bin, scripts/setup.sh) runs")
}

fn run(ranks: u32) -> String {
    let output = mpirun(ranks, &[]);
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
fn composited_frames_equal_one_process_for_1_to_5_and_8_ranks() {
    for ranks in [1, 2, 3, 4, 5, 8] {
        let out = run(ranks);
        let cases: Vec<&str> = out.lines().filter(|l| l.starts_with("case ")).collect();
        assert_eq!(cases.len(), 7, "{ranks} ranks:\n{out}");
        for line in cases {
            assert!(line.contains(": match,"), "{ranks} ranks: {line}");
            let bytes: u64 = line.rsplit(' ').next().unwrap().parse().unwrap();
            if ranks == 1 {
                assert_eq!(bytes, 0, "one rank sends nothing: {line}");
            } else {
                // Binary swap: at most one image each, whatever the rank count (a folded
                // rank sends one whole image; the others halves, quarters, ... and a slice).
                assert!(bytes <= IMAGE_BYTES, "{ranks} ranks: {line}");
            }
        }
    }
}

/// A rank whose share fails (a glyph float32 cannot hold) makes every rank stop with an
/// error -- the failing one naming the glyph, the others the failing rank -- and nobody waits
/// for the image it will not send: every rank prints its line and exits (a rank left waiting
/// would keep mpirun from ending, and `timeout` would end it with status 124). The failing rank
/// is the root, a swapping rank and the extra rank that folds into another.
#[test]
fn a_failing_rank_stops_every_rank_with_named_errors() {
    for failing in ["0", "1", "2"] {
        let output = Command::new("timeout")
            .args([
                "120",
                "mpirun",
                "--oversubscribe",
                "--allow-run-as-root",
                "-n",
                "3",
            ])
            .arg(env!("CARGO_BIN_EXE_composite-check"))
            .args(["--fail-rank", failing])
            .output()
            .expect("timeout and mpirun run");
        let stdout = String::from_utf8_lossy(&output.stdout);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            output.status.success(),
            "failing rank {failing}: exit {:?}\n{stdout}\n{stderr}",
            output.status.code()
        );
        for rank in ["0", "1", "2"] {
            let line = stdout
                .lines()
                .find(|l| l.starts_with(&format!("rank {rank} stopped: ")))
                .unwrap_or_else(|| {
                    panic!("failing rank {failing}: no line of rank {rank}:\n{stdout}")
                });
            let expected = if rank == failing {
                "ellipsoid 7".to_string()
            } else {
                format!("rank {failing} failed drawing its share")
            };
            assert!(line.contains(&expected), "failing rank {failing}: {line}");
        }
    }
}
