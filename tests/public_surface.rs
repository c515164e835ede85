//! The host-facing surface stays small: the free items a host reaches without features (at the
//! crate root and through its public modules), counted from the sources, and the minimal
//! host's length.

use std::collections::BTreeMap;
use std::path::Path;

/// The free items (not associated ones) reachable without features from the module whose
/// source is `source` and whose child modules' files lie in `dir`, as `path -> name`: its
/// top-level `pub` items that no `#[cfg(...)]` needing a feature (or `test`) and no
/// `#[doc(hidden)]` guards -- each name a `pub use` brings in, each `pub mod`, `fn`, `const`,
/// `static`, `struct`, `enum`, `union`, `trait` and `type` -- and the same of each such
/// `pub mod`'s own file or block. This is the reach of rustdoc's JSON of the crate without
/// features walked from the root, which needs nightly (`scripts/count-public-items.sh` counts
/// it: run it when this count changes). `read` gives a file's text.
fn free_items(
    source: &str,
    dir: &Path,
    prefix: &str,
    read: &dyn Fn(&Path) -> String,
) -> BTreeMap<String, String> {
    let mut items = BTreeMap::new();
    let lines: Vec<&str> = source.lines().collect();
    let (mut guarded, mut path_attribute) = (false, None::<String>);
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i].trim_end();
        i += 1;
        // Only lines at column 0 are the module's own items: bodies are indented.
        if line.starts_with("#[") {
            let mut attribute = line.to_string();
            while attribute.matches('[').count() > attribute.matches(']').count() {
                attribute += lines[i].trim();
                i += 1;
            }
            guarded |= attribute.starts_with("#[doc(hidden)")
                || (attribute.starts_with("#[cfg(")
                    && !attribute.starts_with("#[cfg(not(")
                    && (attribute.contains("feature") || attribute.contains("test")));
            if let Some(path) = attribute.strip_prefix("#[path = \"") {
                path_attribute = path.split('"').next().map(str::to_string);
            }
            continue;
        }
        if line.is_empty() || line.starts_with("//") || line.starts_with(char::is_whitespace) {
            continue;
        }
        let (was_guarded, path_attribute) = (std::mem::take(&mut guarded), path_attribute.take());
        // The whole item: a `use` to its `;`, a block to the `}` that closes it at column 0.
        let mut statement = line.to_string();
        let mut block = Vec::new();
        if line.starts_with("pub use") {
            while !statement.contains(';') {
                statement += lines[i].trim();
                i += 1;
            }
        } else if line.ends_with('{') {
            while i < lines.len() && lines[i] != "}" {
                block.push(lines[i].strip_prefix("    ").unwrap_or(lines[i]));
                i += 1;
            }
            i += 1;
        }
        let Some(rest) = statement.strip_prefix("pub ") else {
            continue;
        };
        if was_guarded {
            continue;
        }
        if let Some(tree) = rest.strip_prefix("use ") {
            for name in use_names(tree.trim_end_matches(';')) {
                items.insert(format!("{prefix}{name}"), name);
            }
            continue;
        }
        let (kind, name) = kind_and_name(rest);
        items.insert(format!("{prefix}{name}"), name.clone());
        if kind == "mod" {
            let inner = if statement.ends_with('{') {
                block.join("\n")
            } else {
                let file = match path_attribute {
                    Some(path) => dir.join(path),
                    None if dir.join(format!("{name}.rs")).exists() => {
                        dir.join(format!("{name}.rs"))
                    }
                    None => dir.join(&name).join("mod.rs"),
                };
                read(&file)
            };
            items.extend(free_items(
                &inner,
                &dir.join(&name),
                &format!("{prefix}{name}::"),
                read,
            ));
        }
    }
    items
}

/// The names a `pub use` tree brings in: `a::B`, `a::{B, c::D}`, `a::B as C`, `a::{self}`.
fn use_names(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    if let (Some(open), true) = (tree.find('{'), tree.ends_with('}')) {
        let prefix = tree[..open].trim_end_matches("::");
        let mut names = Vec::new();
        let (mut depth, mut start) = (0, open + 1);
        for (at, c) in tree.char_indices().skip(open + 1) {
            match c {
                '{' => depth += 1,
                '}' if depth > 0 => depth -= 1,
                ',' | '}' if depth == 0 => {
                    match tree[start..at].trim() {
                        "" => {}
                        "self" => names.push(prefix.rsplit("::").next().unwrap().to_string()),
                        part => names.extend(use_names(part)),
                    }
                    start = at + 1;
                }
                _ => {}
            }
        }
        return names;
    }
    assert!(
        !tree.ends_with('*'),
        "`pub use {tree}`: a glob hides what it adds; name the items"
    );
    let name = match tree.split_once(" as ") {
        Some((_, alias)) => alias.trim(),
        None => tree.rsplit("::").next().unwrap(),
    };
    if name == "_" {
        Vec::new()
    } else {
        vec![name.to_string()]
    }
}

/// The kind (`fn`, `struct`, `mod`, ...) and name of a `pub` item's declaration, after `pub `.
fn kind_and_name(declaration: &str) -> (String, String) {
    let mut words = declaration
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
        .skip_while(|w| ["unsafe", "async", "extern", "C"].contains(w));
    let mut kind = words.next().unwrap_or("").to_string();
    let mut name = words.next().unwrap_or("");
    if (kind == "const" && name == "fn") || (kind == "static" && name == "mut") {
        kind = if name == "fn" { "fn".into() } else { kind };
        name = words.next().unwrap_or("");
    }
    (kind, name.to_string())
}

/// The crate's free items without features, by path.
fn crate_items() -> BTreeMap<String, String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let read = |path: &Path| {
        std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    };
    free_items(&read(&src.join("lib.rs")), &src, "", &read)
}

#[test]
fn at_most_thirty_free_items_without_features_the_root_the_hosts_vocabulary() {
    let items = crate_items();
    // An item reached at two paths (a re-export) is one item.
    let mut names: Vec<&String> = items.values().collect();
    names.sort();
    names.dedup();
    let paths: Vec<&String> = items.keys().collect();
    println!("{} free items without features: {paths:?}", names.len());
    // The host's vocabulary is at the root.
    for name in [
        "EllipsoidRenderer",
        "RendererOptions",
        "HostDevice",
        "DeviceFeatures",
        "Target",
        "Camera",
        "Scene",
        "Settings",
        "PlanMode",
        "PathKind",
        "FramePlan",
        "MemoryAllocator",
        "Error",
    ] {
        assert!(items.contains_key(name), "{name} is not at the root");
    }
    // The feature-gated and hidden items are not counted.
    for name in ["OffscreenRenderer", "internals", "research", "supersample"] {
        assert!(!items.contains_key(name), "{name} was counted");
    }
    assert!(names.len() <= 30, "{} free items: {paths:?}", names.len());
}

/// The count reaches into public modules, files and blocks, and leaves out what is guarded.
#[test]
fn the_count_follows_public_modules_and_skips_guarded_items() {
    let lib = r#"
pub mod shown;
mod hidden;
#[cfg(feature = "extra")]
pub mod gated;
pub use shown::{Inner as Renamed, deep::{self, Deeper}};
pub use hidden::Hidden;
#[doc(hidden)]
pub mod internals {
    pub struct Secret;
}
pub mod block {
    pub use crate::shown::{
        Kind,
    };
    pub const LIMIT: u32 = 1;
    pub(crate) fn private() {}
    #[cfg(not(feature = "extra"))]
    pub unsafe fn always() {}
}
pub(crate) struct Crate;
impl Crate {
    pub fn associated() {}
}
"#;
    let read = |path: &Path| match path.to_str().unwrap() {
        "src/shown/mod.rs" => "pub struct Inner;\npub enum Kind {}\n".to_string(),
        other => panic!("read {other}"),
    };
    let items = free_items(lib, Path::new("src"), "", &read);
    let paths: Vec<&str> = items.keys().map(String::as_str).collect();
    assert_eq!(
        paths,
        [
            "Deeper",
            "Hidden",
            "Renamed",
            "block",
            "block::Kind",
            "block::LIMIT",
            "block::always",
            "deep",
            "shown",
            "shown::Inner",
            "shown::Kind",
        ]
    );
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
