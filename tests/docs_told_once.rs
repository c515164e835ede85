//! The documentation tells each fact once: no paragraph of at least `PARAGRAPH_WORDS` words and
//! no sentence of at least `SENTENCE_WORDS` words appears twice across `README.md`,
//! `docs/**/*.md` (the measurements' own files under `docs/results/` aside) and the doc
//! comments (`//!` and `///`) of `src/**/*.rs` and `crates/*/src/**/*.rs`. A repeat is a fact kept in two
//! places that will drift apart; keep it in the better one and link it from the other. Code
//! blocks, tables, headings and pictures are not prose and are not compared, nor is what
//! `scripts/tables.py` writes between its markers (made from one results file, it cannot
//! drift, and each table's line of date and machine may repeat another's). The README and the
//! design document also stay short enough to read (`MAX_README_LINES`, `MAX_DESIGN_LINES`):
//! past that, move detail to a topic file or the code's documentation.

use std::collections::BTreeMap;
use std::path::Path;

/// The shortest paragraph, in words, whose repeat fails the test.
const PARAGRAPH_WORDS: usize = 25;
/// The shortest sentence, in words, whose repeat fails the test.
const SENTENCE_WORDS: usize = 20;

/// The most lines `README.md` may have: what it is, the two commands, the main commands and
/// the headline table; the rest belongs in `docs/`.
const MAX_README_LINES: usize = 400;
/// The most lines `docs/design.md` may have: the why and the numerics; the API contract is
/// rustdoc and the user docs are topic files.
const MAX_DESIGN_LINES: usize = 900;

/// One paragraph of prose: where it starts (`file:line`) and its words.
struct Paragraph {
    place: String,
    words: Vec<String>,
}

/// The prose paragraphs of a Markdown text: blank lines end them, and so do code fences,
/// tables, headings and pictures; each list item is a paragraph of its own.
fn paragraphs(file: &str, markdown: &str) -> Vec<Paragraph> {
    let mut found = Vec::new();
    let mut current: Option<Paragraph> = None;
    let mut in_code = false;
    let mut in_generated = false;
    for (index, line) in markdown.lines().enumerate() {
        let text = line.trim();
        let fence = text.starts_with("```");
        if text.starts_with("<!-- table: ") {
            in_generated = true;
        }
        let not_prose = fence
            || in_code
            || in_generated
            || text.is_empty()
            || text.starts_with('|')
            || text.starts_with('#')
            || text.starts_with("![");
        let list_item = text.starts_with("- ")
            || text.starts_with("* ")
            || text
                .split_once(". ")
                .is_some_and(|(n, _)| !n.is_empty() && n.chars().all(|c| c.is_ascii_digit()));
        if not_prose || list_item {
            found.extend(current.take());
        }
        if fence {
            in_code = !in_code;
        }
        if text == "<!-- end table -->" {
            in_generated = false;
        }
        if not_prose {
            continue;
        }
        current
            .get_or_insert_with(|| Paragraph {
                place: format!("{file}:{}", index + 1),
                words: Vec::new(),
            })
            .words
            .extend(text.split_whitespace().map(str::to_string));
    }
    found.extend(current);
    found
}

/// The sentences of a paragraph: a word ending in `.`, `!` or `?` ends one when the next word
/// starts like a sentence (a capital, a bracket, code or emphasis), so "e.g. the" does not.
fn sentences(words: &[String]) -> Vec<&[String]> {
    let mut found = Vec::new();
    let mut start = 0;
    for i in 0..words.len() {
        let ends = words[i]
            .trim_end_matches([')', '*', '"', '_'])
            .ends_with(['.', '!', '?']);
        let next_starts = words.get(i + 1).is_none_or(|next| {
            next.starts_with(|c: char| c.is_uppercase() || "([`*\"".contains(c))
        });
        if ends && next_starts {
            found.push(&words[start..=i]);
            start = i + 1;
        }
    }
    if start < words.len() {
        found.push(&words[start..]);
    }
    found
}

/// Every paragraph and sentence long enough to count that appears more than once, with all
/// the places it appears, as lines of a report.
fn repeats(documents: &[(String, String)]) -> Vec<String> {
    let all: Vec<Paragraph> = documents
        .iter()
        .flat_map(|(file, text)| paragraphs(file, text))
        .collect();
    let mut by_paragraph: BTreeMap<String, Vec<&str>> = BTreeMap::new();
    let mut by_sentence: BTreeMap<String, Vec<&str>> = BTreeMap::new();
    for paragraph in &all {
        if paragraph.words.len() >= PARAGRAPH_WORDS {
            by_paragraph
                .entry(paragraph.words.join(" "))
                .or_default()
                .push(&paragraph.place);
        }
        for sentence in sentences(&paragraph.words) {
            if sentence.len() >= SENTENCE_WORDS {
                by_sentence
                    .entry(sentence.join(" "))
                    .or_default()
                    .push(&paragraph.place);
            }
        }
    }
    let mut report = Vec::new();
    for (kind, repeated) in [("paragraph", &by_paragraph), ("sentence", &by_sentence)] {
        for (text, places) in repeated {
            // A repeated paragraph's own sentences are reported with it.
            let within_repeated_paragraph = kind == "sentence"
                && by_paragraph
                    .iter()
                    .any(|(p, at)| at.len() > 1 && p.contains(text.as_str()));
            if places.len() > 1 && !within_repeated_paragraph {
                report.push(format!("{kind} at {}: \"{text}\"", places.join(" and ")));
            }
        }
    }
    report
}

/// The doc comments of a Rust file (`//!` and `///` lines, not `////`) as Markdown, each on its
/// own line so that a paragraph is named by its file and line; every other line is blank, so
/// each doc block is a paragraph source of its own.
fn doc_comments(rust: &str) -> String {
    rust.lines()
        .map(|line| {
            let line = line.trim_start();
            let text = match line.strip_prefix("//!") {
                Some(text) => text,
                None if !line.starts_with("////") => line.strip_prefix("///").unwrap_or(""),
                None => "",
            };
            text.strip_prefix(' ').unwrap_or(text)
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The files under `dir` (sorted, at any depth) whose path from `root` ends in `extension`,
/// skipping the folders `skip`, with their text.
fn files(root: &Path, dir: &Path, extension: &str, skip: &[&str]) -> Vec<(String, String)> {
    fn walk(
        root: &Path,
        dir: &Path,
        extension: &str,
        skip: &[&str],
        out: &mut Vec<(String, String)>,
    ) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
            .map(|entry| entry.unwrap().path())
            .collect();
        entries.sort();
        for path in entries {
            let name = path
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .into_owned();
            if path.is_dir() {
                if !skip.contains(&name.as_str()) {
                    walk(root, &path, extension, skip, out);
                }
            } else if name.ends_with(extension) {
                out.push((name, std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    let mut found = Vec::new();
    walk(root, dir, extension, skip, &mut found);
    found
}

/// README.md, every Markdown file under docs/ but docs/results/, and the doc comments of
/// every Rust file under src/ and each crate's src/, by path from the root.
fn documentation(root: &Path) -> Vec<(String, String)> {
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let mut documents = vec![("README.md".to_string(), readme)];
    documents.extend(files(root, &root.join("docs"), ".md", &["docs/results"]));
    let mut sources = vec![root.join("src")];
    let mut crates: Vec<_> = std::fs::read_dir(root.join("crates"))
        .unwrap_or_else(|e| panic!("reading crates/: {e}"))
        .map(|entry| entry.unwrap().path().join("src"))
        .filter(|src| src.is_dir())
        .collect();
    crates.sort();
    sources.extend(crates);
    for src in sources {
        for (file, rust) in files(root, &src, ".rs", &[]) {
            documents.push((file, doc_comments(&rust)));
        }
    }
    documents
}

#[test]
fn no_paragraph_or_sentence_of_the_documentation_is_told_twice() {
    let documents = documentation(Path::new(env!("CARGO_MANIFEST_DIR")));
    assert!(
        documents.len() > 10
            && documents.iter().any(|(f, _)| f == "docs/design.md")
            && documents
                .iter()
                .any(|(f, text)| f == "src/lib.rs" && text.contains("# Embedding"))
            && documents
                .iter()
                .any(|(f, text)| f == "crates/capi/src/lib.rs" && !text.trim().is_empty()),
        "README.md, docs/ and the doc comments of src/ and crates/*/src/ are read"
    );
    let report = repeats(&documents);
    assert!(
        report.is_empty(),
        "told twice (keep one, link it from the other):\n{}",
        report.join("\n")
    );
}

/// The check itself: a planted repeat is found in prose, named at both places, and the same
/// words in code, tables and headings are not prose.
#[test]
fn a_planted_repeat_is_named_at_both_places() {
    let fact = "The renderer never submits and never waits, so the host decides when its command \
                buffers go to the queue and which fences it waits for before reusing them.";
    let short = "Too short to count, however often it is said.";
    let first = format!("# Title\n\nIntro line.\n{fact}\n\n{short}\n\n```\n{fact}\n```\n");
    let second = format!("| {fact} |\n\n## {fact}\n\n- An item. {fact}\n\n{short}\n");
    let report = repeats(&[("a.md".into(), first), ("b.md".into(), second)]);
    assert_eq!(report.len(), 1, "{report:?}");
    assert!(
        report[0].starts_with("sentence at a.md:3 and b.md:5:"),
        "{report:?}"
    );
    let twice = format!("{fact} And it says so in one more sentence of its own.");
    let report = repeats(&[
        ("a.md".into(), twice.clone()),
        ("b.md".into(), format!("Other.\n\n{twice}")),
    ]);
    assert_eq!(report.len(), 1, "{report:?}");
    assert!(
        report[0].starts_with("paragraph at a.md:1 and b.md:3:"),
        "{report:?}"
    );
}

#[test]
fn the_readme_and_the_design_stay_short() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (file, limit) in [
        ("README.md", MAX_README_LINES),
        ("docs/design.md", MAX_DESIGN_LINES),
    ] {
        let lines = std::fs::read_to_string(root.join(file))
            .unwrap_or_else(|e| panic!("reading {file}: {e}"))
            .lines()
            .count();
        assert!(
            lines <= limit,
            "{file} has {lines} lines, more than {limit}: move detail to a docs/ topic file or \
             the code's documentation, and link it"
        );
    }
}

/// Doc comments are read as Markdown on their own lines: `//!` and `///` lines (indented or
/// not) without their prefix, every other line (code, `//` and `////` comments) blank, so a
/// paragraph is named at its line of the file and two doc blocks never join.
#[test]
fn doc_comments_keep_their_lines_and_nothing_else() {
    let rust = "//! # Title\n//!\n//! Text here.\n\nuse x;\n    /// An item.\n    // a note\n//// ruled\nfn f() {}\n";
    assert_eq!(
        doc_comments(rust),
        "# Title\n\nText here.\n\n\nAn item.\n\n\n"
    );
    let report = repeats(&[(
        "a.rs".into(),
        doc_comments(&format!(
            "/// {fact}\nfn f() {{}}\n    /// {fact}\n",
            fact = "The renderer never submits and never waits, so the host decides when its \
                    command buffers go to the queue and which fences it waits for."
        )),
    )]);
    assert_eq!(report.len(), 1, "{report:?}");
    assert!(
        report[0].starts_with("paragraph at a.rs:1 and a.rs:3:"),
        "{report:?}"
    );
}

/// A reader goes from the README to every topic in one click: each relative link of the
/// README and `docs/` names a file (and heading) that exists (`scripts/check-doc-links.py`).
#[test]
fn every_relative_link_of_the_documentation_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let output = std::process::Command::new("python3")
        .arg(root.join("scripts/check-doc-links.py"))
        .current_dir(root)
        .output()
        .unwrap_or_else(|err| panic!("python3 scripts/check-doc-links.py could not start: {err}"));
    assert!(
        output.status.success(),
        "broken links in the documentation:\n{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}
