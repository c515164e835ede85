//! The committed SPIR-V in `spirv/` (what `build.rs` uses where glslangValidator is missing)
//! is byte for byte what `build.rs` compiles from `glsl/`, and holds nothing else.

use std::path::{Path, PathBuf};

/// The builds of this feature set, one a line (written by `build.rs`).
const BUILT: &str = include_str!(concat!(env!("OUT_DIR"), "/spirv-files.txt"));
/// `compiled` and the compiler's version, or `committed` and why (written by `build.rs`).
const ORIGIN: &str = include_str!(concat!(env!("OUT_DIR"), "/spirv-origin.txt"));
/// The hash of the sources in `glsl/` now (written by `build.rs`).
const SOURCES: &str = include_str!(concat!(env!("OUT_DIR"), "/spirv-sources.txt"));

/// `spirv/SOURCES` records the sources `spirv/` was made from: they are today's (on any
/// machine, with or without the compiler).
#[test]
fn the_committed_spirv_was_made_from_todays_sources() {
    let recorded = std::fs::read_to_string(committed_dir().join("SOURCES")).expect("spirv/SOURCES");
    assert_eq!(
        recorded.trim(),
        SOURCES.trim(),
        "glsl/ changed since spirv/ was made: run scripts/update-spirv.sh and commit spirv/"
    );
}

fn committed_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("spirv")
}

#[test]
fn every_compiled_shader_equals_its_committed_copy() {
    let mut lines = ORIGIN.lines();
    if lines.next() != Some("compiled") {
        eprintln!(
            "skipped: build.rs used the committed SPIR-V ({}), so there is nothing to compare",
            lines.next().unwrap_or("no reason given")
        );
        return;
    }
    let compiler = lines.next().unwrap_or("unknown");
    let committed_by = std::fs::read_to_string(committed_dir().join("COMPILER"))
        .unwrap_or_else(|e| format!("unknown ({e})"));
    let out = Path::new(env!("OUT_DIR"));
    let mut stale = Vec::new();
    for name in BUILT.lines() {
        let built = std::fs::read(out.join(name)).expect("build.rs wrote it");
        match std::fs::read(committed_dir().join(name)) {
            Ok(committed) if committed == built => {}
            Ok(_) => stale.push(format!("{name} differs")),
            Err(e) => stale.push(format!("{name} is missing ({e})")),
        }
    }
    assert!(
        BUILT.lines().count() > 0,
        "build.rs listed no SPIR-V in spirv-files.txt"
    );
    assert!(
        stale.is_empty(),
        "spirv/ does not match what {compiler} compiles (spirv/ came from {}): {}.\n\
         Run scripts/update-spirv.sh and commit spirv/.",
        committed_by.trim(),
        stale.join(", ")
    );
}

/// The source a committed file was built from: `ellipsoid.frag.aux.counted.spv` is
/// `ellipsoid.frag`.
fn source_name(spv: &str) -> &str {
    let mut name = spv.strip_suffix(".spv").unwrap_or(spv);
    for variant in [".counted", ".aux"] {
        name = name.strip_suffix(variant).unwrap_or(name);
    }
    name
}

#[test]
fn every_committed_file_has_a_shader_source() {
    let glsl = Path::new(env!("CARGO_MANIFEST_DIR")).join("glsl");
    let mut orphans = Vec::new();
    let mut count = 0;
    for entry in std::fs::read_dir(committed_dir()).expect("spirv/ exists") {
        let name = entry.expect("directory entry").file_name();
        let name = name.to_string_lossy();
        if !name.ends_with(".spv") {
            continue;
        }
        count += 1;
        let source = source_name(&name);
        let folders = ["", "research", "offscreen"];
        if !folders.iter().any(|f| glsl.join(f).join(source).is_file()) {
            orphans.push(name.into_owned());
        }
    }
    assert!(count > 0, "spirv/ holds no SPIR-V");
    assert!(
        orphans.is_empty(),
        "committed SPIR-V without a source in glsl/: {orphans:?} (scripts/update-spirv.sh \
         removes them)"
    );
}

#[test]
fn source_names_strip_every_variant() {
    assert_eq!(
        source_name("ellipsoid.frag.aux.counted.spv"),
        "ellipsoid.frag"
    );
    assert_eq!(source_name("mesh.frag.counted.spv"), "mesh.frag");
    assert_eq!(source_name("cull.comp.spv"), "cull.comp");
}
