//! What the loader tests share (`mod support;` in each): the sample files, temporary files,
//! option builders, the checks of loaded scenes, parse errors and I/O errors, numeric
//! comparisons, and the one seeded random generator.

// Each test binary uses a part of this module.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

pub mod threads;

use ellipsoid_splat_loaders::Error;
use ellipsoid_splat_loaders::LoadOptions;
use glam::{DMat3, DVec3};

// ---------------------------------------------------------------------------------------------
// Files

/// A file of `data/samples/` at the repository root.
pub fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/samples")
        .join(name)
}

/// The text of a sample file.
pub fn sample_text(name: &str) -> String {
    let path = sample(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A directory of its own for one test, in the system's temporary directory; removed with
/// everything in it when dropped, also when the test fails.
pub struct TempDir(PathBuf);

impl TempDir {
    /// A fresh directory named after `test` and this process.
    pub fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!(
            "ellipsoid-splat-loaders-{test}-{}",
            std::process::id()
        ));
        // Left over from an earlier process with the same id.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        Self(dir)
    }

    /// The path of `name` in the directory (the file need not exist).
    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Writes `bytes` to `name` in the directory and returns its path.
    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.path(name);
        std::fs::write(&path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

// ---------------------------------------------------------------------------------------------
// Options

/// The default options with `set` applied: `options(|o| o.min_fa = 0.3)`.
pub fn options(set: impl FnOnce(&mut LoadOptions)) -> LoadOptions {
    let mut options = LoadOptions::default();
    set(&mut options);
    options
}

/// The default options with `skip_invalid`.
pub fn skipping() -> LoadOptions {
    options(|o| o.skip_invalid = true)
}

// ---------------------------------------------------------------------------------------------
// Results

/// The start of `input`, readable, for failure messages.
pub fn preview(input: &[u8]) -> String {
    String::from_utf8_lossy(&input[..input.len().min(2000)]).into_owned()
}

/// The value of a load that must succeed; `input` is shown if it did not.
pub fn loaded<T>(result: Result<T, Error>, input: &[u8]) -> T {
    result.unwrap_or_else(|e| panic!("should load: {e}\n{}", preview(input)))
}

/// An [`Error::Parse`], taken apart, with its message.
#[derive(Debug)]
pub struct ParseError {
    pub line: usize,
    pub column: String,
    pub reason: String,
    /// The error as displayed: `file:line:column: reason`.
    pub message: String,
    /// The start of the input, for failure messages.
    input: String,
}

impl ParseError {
    /// Asserts the line and column, and that the reason contains every one of `words`;
    /// returns the message.
    pub fn assert_at(&self, line: usize, column: &str, words: &[&str]) -> String {
        assert_eq!(
            (self.line, self.column.as_str()),
            (line, column),
            "message: {}\n{}",
            self.message,
            self.input
        );
        for word in words {
            assert!(
                self.reason.contains(word),
                "reason {:?} lacks {word:?}\n{}",
                self.reason,
                self.input
            );
        }
        self.message.clone()
    }
}

/// The parse error a load of `input` must end in; it must name `file`.
pub fn parse_error<T>(result: Result<T, Error>, file: &Path, input: &[u8]) -> ParseError {
    match result {
        Err(e @ Error::Parse { .. }) => {
            let message = e.to_string();
            let Error::Parse {
                file: named,
                line,
                column,
                reason,
            } = e
            else {
                unreachable!()
            };
            assert_eq!(named, file, "{message}");
            ParseError {
                line,
                column,
                reason,
                message,
                input: preview(input),
            }
        }
        Err(other) => panic!("expected a parse error, got {other:?}\n{}", preview(input)),
        Ok(_) => panic!(
            "expected a parse error, got a loaded {}\n{}",
            std::any::type_name::<T>(),
            preview(input)
        ),
    }
}

/// Asserts that `result` is an I/O error on `path`.
pub fn assert_io_error<T>(result: Result<T, Error>, path: &Path) {
    match result {
        Err(Error::Io { path: named, .. }) => assert_eq!(named, path),
        Err(other) => panic!("expected an I/O error on {}, got {other:?}", path.display()),
        Ok(_) => panic!("expected an I/O error on {}, got Ok", path.display()),
    }
}

/// Asserts that one of `notes` (a [`Loaded`](ellipsoid_splat_loaders::Loaded)'s) contains
/// `text`.
pub fn assert_note(notes: &[String], text: &str) {
    assert!(
        notes.iter().any(|n| n.contains(text)),
        "no note with {text:?}: {notes:?}"
    );
}

/// Asserts that `text` contains every one of `words`.
pub fn assert_contains(text: &str, words: &[&str]) {
    for word in words {
        assert!(text.contains(word), "{text:?} lacks {word:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Numbers

/// Asserts `|a - b| <= tol` in every component.
pub fn assert_close(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).abs().max_element() <= tol, "{a} vs {b}");
}

/// Asserts `|a - b| <= tol` in every element.
pub fn assert_mat_close(a: DMat3, b: DMat3, tol: f64) {
    for (x, y) in a.to_cols_array().iter().zip(b.to_cols_array()) {
        assert!((x - y).abs() <= tol, "{a} vs {b}");
    }
}

// ---------------------------------------------------------------------------------------------
// Random input

/// xorshift64* (Marsaglia's xorshift with Vigna's multiplier): a small deterministic stream for
/// mutated and random inputs. Each test gives its own fixed seed, so a failure reproduces.
pub struct Rng(u64);

impl Rng {
    /// A stream from `seed`, which must not be 0 (xorshift would stay at 0).
    pub fn new(seed: u64) -> Self {
        assert_ne!(seed, 0, "xorshift needs a non-zero seed");
        Self(seed)
    }

    /// The next 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// The low byte of the next value.
    pub fn byte(&mut self) -> u8 {
        self.next_u64() as u8
    }

    /// Uniform enough in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }

    /// `n` random bytes.
    pub fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.byte()).collect()
    }
}
