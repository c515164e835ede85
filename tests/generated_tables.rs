//! Every table of figures in the docs is what `scripts/tables.py` makes from the committed
//! results under `docs/results/`: a table edited by hand, or results committed without running
//! the script, fails here naming the doc, the table and the first line that differs.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `python3 scripts/tables.py ARGS` in `dir`, a checkout or a copy of its docs and scripts.
fn tables(dir: &Path, args: &[&str]) -> Output {
    Command::new("python3")
        .arg(dir.join("scripts/tables.py"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|err| panic!("python3 scripts/tables.py could not start: {err}"))
}

fn copy_tree(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            fs::copy(entry.path(), &target).unwrap();
        }
    }
}

/// A copy of what the script reads and writes, so a test can spoil it.
fn scratch_copy(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("es-tables-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    copy_tree(&root().join("docs"), &dir.join("docs"));
    copy_tree(&root().join("scripts"), &dir.join("scripts"));
    fs::copy(root().join("README.md"), dir.join("README.md")).unwrap();
    dir
}

#[test]
fn the_docs_tables_match_the_committed_results() {
    let out = tables(root(), &["--check"]);
    assert!(
        out.status.success(),
        "a table no longer matches its results (run python3 scripts/tables.py and commit):\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_figure_typed_over_is_named_with_its_table_and_line() {
    let dir = scratch_copy("typed");
    let readme = dir.join("README.md");
    let text = fs::read_to_string(&readme).unwrap();
    let begin = text
        .find("<!-- table: headline ")
        .expect("README has the headline table");
    // The table's first body row (after its header and rule): a digit typed onto its last figure.
    let table_at = begin + text[begin..].find("\n|").expect("a table in the block") + 1;
    let row_at = (0..2).fold(table_at, |at, _| at + text[at..].find('\n').unwrap() + 1);
    let row_end = row_at + text[row_at..].find('\n').unwrap();
    let row = &text[row_at..row_end];
    let spoiled_row = format!("{}9 |", row.strip_suffix(" |").expect("a row ends in ' |'"));
    let line = text[..row_at].lines().count() + 1;
    fs::write(&readme, text.replacen(row, &spoiled_row, 1)).unwrap();

    let out = tables(&dir, &["--check"]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(1),
        "--check passed a spoiled table:\n{said}"
    );
    assert!(
        said.contains(&format!("README.md:{line}: table headline")),
        "not named at README.md:{line}:\n{said}"
    );
    assert!(said.contains(&spoiled_row) && said.contains(row), "{said}");

    // Writing mends it, and the check passes again.
    assert!(tables(&dir, &[]).status.success());
    assert_eq!(fs::read_to_string(&readme).unwrap(), text);
    assert!(tables(&dir, &["--check"]).status.success());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn results_changed_without_the_docs_fail_the_check() {
    let dir = scratch_copy("results");
    // The first run's time of the viewer's orbit, a digit typed in front of it.
    let log = dir.join("docs/results/plan/orbit-mesa-22.3.6.txt");
    let text = fs::read_to_string(&log).unwrap();
    assert!(text.contains("all frames "), "{text}");
    fs::write(&log, text.replacen("all frames ", "all frames 1", 1)).unwrap();
    let out = tables(&dir, &["--check"]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{said}");
    assert!(said.contains("table plan-orbit"), "{said}");
    fs::remove_dir_all(&dir).unwrap();
}
