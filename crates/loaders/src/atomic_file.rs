//! Files written whole or not at all. The bytes go to a hidden file beside the target
//! ([`partial_name`]: the same directory, so the rename cannot cross file systems), which is
//! flushed, synced and renamed over the target only when complete: a full disk, a write error
//! or a failed encoder leaves the old file untouched and removes the partial one; a process
//! killed mid-write leaves the old file untouched and at most the hidden partial file. The
//! scene files the loaders save and every file the command-line tool writes go through it,
//! but the movie, which ffmpeg writes to such a partial name of its own before the rename.
//!
//! A symbolic link is followed (the file it points to is replaced, the link kept); a target
//! that exists and is not a regular file (`/dev/null`, a pipe) is written in place, as no
//! rename can stand for it. A replaced file gets a new file's permissions, not the old one's.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Writes `path` through `write`, atomically as the module says.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let target = match std::fs::canonicalize(path) {
        Ok(resolved) if !resolved.is_file() => return write_in_place(&resolved, write),
        Ok(resolved) => resolved,
        Err(_) => path.to_path_buf(),
    };
    // A name no other writer uses: this process's id and a count of its partial files (a
    // file of the name left by a killed process that had this id is not ours to remove).
    let (partial, file) = loop {
        let partial = partial_name(&target)?;
        match OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&partial)
        {
            Ok(file) => break (partial, file),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    };
    let written = (|| {
        let mut writer = BufWriter::with_capacity(1 << 20, file);
        write(&mut writer)?;
        writer.flush()?;
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_data()?;
        std::fs::rename(&partial, &target)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    written
}

/// A device or pipe: written as it is.
fn write_in_place(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let mut writer = BufWriter::new(OpenOptions::new().write(true).open(path)?);
    write(&mut writer)?;
    writer.flush()
}

/// A fresh hidden name beside `path` for its partial file: `.NAME.PID-N.partial`, N counting
/// this process's partial files.
pub fn partial_name(path: &Path) -> std::io::Result<PathBuf> {
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("'{}' names no file", path.display()),
        )
    })?;
    Ok(path.with_file_name(format!(
        ".{}.{}-{}.partial",
        name.to_string_lossy(),
        std::process::id(),
        COUNT.fetch_add(1, Ordering::Relaxed)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("es-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn names(dir: &Path) -> Vec<std::ffi::OsString> {
        let mut names: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_leaves_nothing_else() {
        let dir = scratch("failed");
        let target = dir.join("a.png");
        std::fs::write(&target, b"the good picture").unwrap();
        let failed = write_atomically(&target, |w| {
            w.write_all(b"half a pict")?;
            Err(std::io::Error::other("the encoder failed"))
        });
        assert_eq!(failed.unwrap_err().to_string(), "the encoder failed");
        assert_eq!(std::fs::read(&target).unwrap(), b"the good picture");
        assert_eq!(names(&dir), ["a.png"]);
        write_atomically(&target, |w| w.write_all(b"the new picture")).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"the new picture");
        assert_eq!(names(&dir), ["a.png"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn another_writers_partial_file_is_left_alone() {
        let dir = scratch("others");
        let target = dir.join("b.csv");
        // What a killed process that had this id left, or another writer's file: untouched.
        let theirs = target.with_file_name(format!(".b.csv.{}-0.partial", std::process::id()));
        std::fs::write(&theirs, b"not ours").unwrap();
        for _ in 0..3 {
            write_atomically(&target, |w| w.write_all(b"ours")).unwrap();
        }
        assert_eq!(std::fs::read(&target).unwrap(), b"ours");
        assert_eq!(std::fs::read(&theirs).unwrap(), b"not ours");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn links_are_followed_and_devices_written_in_place() {
        let dir = scratch("links");
        let real = dir.join("real.csv");
        std::fs::write(&real, b"old").unwrap();
        let link = dir.join("link.csv");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_atomically(&link, |w| w.write_all(b"new")).unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        write_atomically(Path::new("/dev/null"), |w| w.write_all(b"gone")).unwrap();
        assert!(!std::fs::metadata("/dev/null").unwrap().is_file());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
