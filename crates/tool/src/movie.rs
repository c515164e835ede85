//! A movie of rendered frames (`render --frames ... --movie FILE`): each frame's colour is
//! piped as raw RGBA to the system's `ffmpeg`, which encodes the container the file's
//! extension names (`.mp4`, `.mkv`, `.mov`: H.264 in 4:2:0, the form every player opens).
//! The movie is written under a hidden name beside the target (`.NAME.PID-N.partial.EXT`,
//! as `ellipsoid_splat_loaders::atomic_file` names partial files) and synced and renamed over
//! it only once `ffmpeg` has finished, so a failed run leaves no broken file in
//! its place (nor removes one that was there) and removes the partial one; a run killed
//! outright (Ctrl-C, a signal) may leave the hidden partial file, never a broken `NAME`.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::thread::JoinHandle;

use crate::error::{Error, Result};
use ellipsoid_splat::Frame;
use ellipsoid_splat_loaders::atomic_file::partial_name;

/// The program encoding the movie, looked up on `PATH`.
const FFMPEG: &str = "ffmpeg";

/// An `ffmpeg` process taking frames on its standard input.
pub struct Movie {
    child: Child,
    stdin: Option<ChildStdin>,
    /// `ffmpeg`'s messages, read on a thread so that a chatty encoder never blocks the pipe.
    messages: Option<JoinHandle<String>>,
    target: PathBuf,
    partial: PathBuf,
    size: (u32, u32),
    frames: usize,
}

impl Movie {
    /// Starts `ffmpeg` writing `target` from `width x height` frames at `fps` frames a
    /// second. A missing `ffmpeg` is an error naming `--movie` and the package to install.
    pub fn start(target: &Path, width: u32, height: u32, fps: u32) -> Result<Movie> {
        let partial = partial_movie(target)?;
        let extension = target
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        let mut command = Command::new(FFMPEG);
        command
            .args(["-hide_banner", "-loglevel", "error", "-nostdin", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgba"])
            .args(["-s", &format!("{width}x{height}"), "-r", &fps.to_string()])
            .args(["-i", "-"]);
        if matches!(extension.as_str(), "mp4" | "mkv" | "mov") {
            // 4:2:0 needs even sides: an odd one gets a copy of its last row or column.
            command.args([
                "-vf",
                "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                "-c:v",
                "libx264",
                "-pix_fmt",
                "yuv420p",
            ]);
        }
        command
            .arg(&partial)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let mut child = command.spawn().map_err(|e| {
            let reason = if e.kind() == std::io::ErrorKind::NotFound {
                "it is encoded by ffmpeg, which is not installed (Debian: apt install ffmpeg); \
                 the image sequence needs no ffmpeg"
                    .to_string()
            } else {
                format!("cannot start ffmpeg: {e}")
            };
            Error::invalid("--movie", reason)
        })?;
        let stdin = child.stdin.take();
        let messages = child.stderr.take().map(|mut stderr| {
            std::thread::spawn(move || {
                let mut text = String::new();
                let _ = stderr.read_to_string(&mut text);
                text
            })
        });
        Ok(Movie {
            child,
            stdin,
            messages,
            target: target.to_path_buf(),
            partial,
            size: (width, height),
            frames: 0,
        })
    }

    /// Appends `frame`'s colour (it must be the size the movie was started with).
    pub fn push(&mut self, frame: &Frame) -> Result<()> {
        if (frame.width, frame.height) != self.size {
            return Err(self.failed(format!(
                "frame {} is {}x{}, the movie {}x{}",
                self.frames + 1,
                frame.width,
                frame.height,
                self.size.0,
                self.size.1
            )));
        }
        let bytes: &[u8] = frame.color.as_flattened();
        let written = match self.stdin.as_mut() {
            Some(stdin) => stdin.write_all(bytes),
            None => Err(std::io::Error::other("ffmpeg's input is closed")),
        };
        if let Err(e) = written {
            let reason = format!("ffmpeg stopped taking frames ({e})");
            return Err(self.failed(reason));
        }
        self.frames += 1;
        Ok(())
    }

    /// Closes the input, waits for `ffmpeg` and puts the movie in place; the frame count.
    pub fn finish(mut self) -> Result<usize> {
        drop(self.stdin.take());
        let status = self.child.wait();
        let messages = self.messages();
        match status {
            Ok(status) if status.success() => {}
            Ok(status) => {
                let _ = std::fs::remove_file(&self.partial);
                return Err(self.encode_error(format!("ffmpeg failed ({status}): {messages}")));
            }
            Err(e) => {
                let _ = std::fs::remove_file(&self.partial);
                return Err(self.encode_error(format!("waiting for ffmpeg: {e}")));
            }
        }
        // On disk before it takes the target's name.
        let synced = std::fs::File::open(&self.partial).and_then(|file| file.sync_data());
        if let Err(e) = synced {
            let _ = std::fs::remove_file(&self.partial);
            return Err(self.encode_error(format!("cannot sync the movie: {e}")));
        }
        std::fs::rename(&self.partial, &self.target).map_err(|e| {
            let _ = std::fs::remove_file(&self.partial);
            self.encode_error(format!("cannot put the movie in place: {e}"))
        })?;
        Ok(self.frames)
    }

    /// Stops `ffmpeg`, removes the partial movie and makes the error of `reason` with what
    /// `ffmpeg` said.
    fn failed(&mut self, reason: String) -> Error {
        drop(self.stdin.take());
        let _ = self.child.kill();
        let _ = self.child.wait();
        let messages = self.messages();
        let _ = std::fs::remove_file(&self.partial);
        if messages.is_empty() {
            self.encode_error(reason)
        } else {
            self.encode_error(format!("{reason}: {messages}"))
        }
    }

    /// What `ffmpeg` wrote to its error stream, on one line.
    fn messages(&mut self) -> String {
        let text = self
            .messages
            .take()
            .and_then(|thread| thread.join().ok())
            .unwrap_or_default();
        text.split_whitespace().collect::<Vec<_>>().join(" ")
    }

    fn encode_error(&self, reason: String) -> Error {
        Error::Encode {
            path: self.target.clone(),
            reason,
        }
    }
}

impl Drop for Movie {
    /// A movie dropped unfinished (an error elsewhere) leaves neither a process nor a
    /// partial file behind.
    fn drop(&mut self) {
        if self.stdin.is_some() {
            drop(self.stdin.take());
            let _ = self.child.kill();
            let _ = self.child.wait();
            let _ = std::fs::remove_file(&self.partial);
        }
    }
}

/// A fresh hidden name beside `target` ([`partial_name`], this process's own) with the
/// target's extension added, so that `ffmpeg` picks the same container.
fn partial_movie(target: &Path) -> Result<PathBuf> {
    let partial = partial_name(target).map_err(|e| Error::invalid("--movie", e.to_string()))?;
    let extension = target
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    Ok(PathBuf::from(format!("{}{extension}", partial.display())))
}
