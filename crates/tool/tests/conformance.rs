//! `conformance` passes on this machine's driver with every case exact, writes JUnit XML, and
//! reports a renderer broken on purpose (every case drawn with the textbook intersection, a
//! benchmark baseline) with exit status 1 and the failing cases named.

use std::process::Command;

fn conformance(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .arg("conformance")
        .args(args)
        .output()
        .expect("the tool runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn every_case_passes_here_and_the_junit_file_says_so() {
    let junit = std::env::temp_dir().join(format!("conformance-{}.xml", std::process::id()));
    let (status, stdout, stderr) = conformance(&["--quick", "--junit", junit.to_str().unwrap()]);
    assert_eq!(status, 0, "{stdout}\n{stderr}");
    let cases = stdout.lines().filter(|l| l.starts_with("pass  ")).count();
    assert!(cases >= 10, "{stdout}");
    assert!(
        stdout.contains(&format!("{cases} of {cases} cases pass")),
        "{stdout}"
    );
    assert!(stdout.contains("coverage mismatch 0"), "{stdout}");
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert_eq!(xml.matches("<testcase ").count(), cases, "{xml}");
    assert!(xml.contains("failures=\"0\""), "{xml}");
    let _ = std::fs::remove_file(junit);
}

#[test]
fn a_renderer_broken_on_purpose_is_reported() {
    let (status, stdout, stderr) = conformance(&["--quick", "--method", "impostor-textbook"]);
    assert_eq!(status, 1, "{stdout}\n{stderr}");
    let failed: Vec<&str> = stdout.lines().filter(|l| l.starts_with("FAIL  ")).collect();
    assert!(failed.len() >= 2, "{stdout}");
    assert!(
        failed
            .iter()
            .any(|l| l.contains("coverage mismatches") || l.contains("depth relative error")),
        "{stdout}"
    );
}

#[test]
fn bad_arguments_are_named() {
    let (status, _, stderr) = conformance(&["--method", "no-such-method"]);
    assert_eq!(status, 1);
    assert!(stderr.contains("--method"), "{stderr}");
    let (status, _, stderr) = conformance(&["--junit", "/nonexistent/dir/out.xml"]);
    assert_eq!(status, 1);
    assert!(stderr.contains("--junit"), "{stderr}");
}
