//! The host-facing surface stays small: the items at the crate root without features (what a
//! host on the library alone names), counted from `src/lib.rs`, and the minimal host's length.

/// The root's public items in `src/lib.rs` that no `#[cfg(feature = ...)]` or `#[doc(hidden)]`
/// guards: each name of a `pub use`, each `pub mod`, `pub fn`, `pub const`, `pub struct`,
/// `pub enum`, `pub trait` and `pub type`.
fn root_items(lib: &str) -> Vec<String> {
    let mut items = Vec::new();
    let mut guarded = false;
    let mut lines = lib.lines().peekable();
    while let Some(line) = lines.next() {
        let line = line.trim_end();
        // Only items at the top level (no indentation) are the root's.
        if line.starts_with("#[cfg(feature") || line.starts_with("#[doc(hidden)]") {
            guarded = true;
            continue;
        }
        if line.starts_with("#[") || line.starts_with("//") || line.is_empty() {
            continue;
        }
        let was_guarded = std::mem::take(&mut guarded);
        let Some(rest) = line.strip_prefix("pub ") else {
            continue;
        };
        if was_guarded {
            // A guarded `pub use` may span lines: skip to its end.
            let mut statement = rest.to_string();
            while !statement.contains(';') && !statement.ends_with('{') {
                statement += lines.next().unwrap_or(";");
            }
            continue;
        }
        if let Some(path) = rest.strip_prefix("use ") {
            let mut statement = path.to_string();
            while !statement.contains(';') {
                statement += lines.next().expect("a `pub use` ends with ;");
            }
            let names = match (statement.find('{'), statement.rfind('}')) {
                (Some(open), Some(close)) => statement[open + 1..close].to_string(),
                _ => statement.rsplit("::").next().unwrap_or("").to_string(),
            };
            for name in names.split(',') {
                let name = name.trim().trim_end_matches(';');
                if !name.is_empty() {
                    items.push(name.rsplit("::").next().unwrap_or(name).to_string());
                }
            }
        } else {
            let name = rest
                .split(|c: char| !(c.is_alphanumeric() || c == '_' || c == ' '))
                .next()
                .unwrap_or("")
                .split_whitespace()
                .nth(1)
                .unwrap_or("")
                .to_string();
            items.push(name);
        }
    }
    items
}

#[test]
fn the_root_holds_at_most_thirty_host_items() {
    let lib = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/lib.rs")).unwrap();
    let items = root_items(&lib);
    println!(
        "{} root items without features: {}",
        items.len(),
        items.join(", ")
    );
    // The host's vocabulary is there.
    for name in [
        "EllipsoidRenderer",
        "RendererOptions",
        "HostDevice",
        "Target",
        "Camera",
        "Scene",
        "Settings",
        "MemoryAllocator",
        "Error",
    ] {
        assert!(items.iter().any(|i| i == name), "{name} is not at the root");
    }
    // The feature-gated and hidden items are not counted.
    for name in ["OffscreenRenderer", "internals"] {
        assert!(!items.iter().any(|i| i == name), "{name} was counted");
    }
    assert!(items.len() <= 30, "{} root items: {items:?}", items.len());
}

#[test]
fn the_minimal_host_reads_on_150_lines() {
    let minimal =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/minimal.rs"))
            .unwrap();
    let lines = minimal.lines().count();
    assert!(lines <= 150, "examples/minimal.rs has {lines} lines");
}

/// The embedding guide's stereo-and-TAA example (`docs/embedding.md`) is the code
/// `tests/cameras.rs` runs against the reference, line for line.
#[test]
fn the_embedding_guides_stereo_taa_example_is_the_tested_code() {
    let read = |path: &str| {
        std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()
    };
    let (tests, guide) = (read("tests/cameras.rs"), read("docs/embedding.md"));
    let start = tests
        .find("// docs/embedding.md: stereo_taa_cameras\n")
        .expect("start marker");
    let end = tests.find("// docs/embedding.md: end").expect("end marker");
    let block = tests[start..end]
        .split_once('\n')
        .map(|(_, code)| code)
        .unwrap();
    assert!(block.lines().count() > 20, "the example is there");
    assert!(
        guide.contains(block),
        "docs/embedding.md does not hold tests/cameras.rs's stereo_taa_cameras verbatim"
    );
}
