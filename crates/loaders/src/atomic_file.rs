//! Files written whole or not at all. The bytes go to a hidden file beside the target
//! (`.NAME.PID.partial`, the same directory so the rename cannot cross file systems), which is
//! flushed, synced and renamed over the target only when complete: a full disk, a write error
//! or a failed encoder leaves the old file untouched and removes the partial one; a process
//! killed mid-write leaves the old file untouched and at most the hidden partial file. The
//! scene files the loaders save and every file the command-line tool writes go through it.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes `path` through `write`, atomically as the module says. The new file has the
/// permissions a new file gets (not the replaced one's).
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let partial = partial_path(path)?;
    let written = (|| {
        // `create_new`: never writes into a file someone else holds under that name.
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&partial)?;
        let mut writer = BufWriter::with_capacity(1 << 20, file);
        write(&mut writer)?;
        writer.flush()?;
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&partial, path)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    written
}

/// `dir/.NAME.PID.partial` for `dir/NAME`.
fn partial_path(path: &Path) -> std::io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("'{}' names no file", path.display()),
        )
    })?;
    Ok(path.with_file_name(format!(
        ".{}.{}.partial",
        name.to_string_lossy(),
        std::process::id()
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
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, [std::ffi::OsString::from("a.png")]);
        write_atomically(&target, |w| w.write_all(b"the new picture")).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"the new picture");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
