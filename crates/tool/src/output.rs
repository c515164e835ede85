//! Writing a [`Frame`] to files: colour PNG, float32 EXR view depth and world normal, and a
//! lossless 32-bit instance-ID image. All are `width x height`, row 0 at the top. Also the
//! checks `render` makes on its output files before any work starts: the name's extension
//! matches what is written, and the file can be written.

use std::fs::OpenOptions;
use std::path::{Path, PathBuf};

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image as ExrImage, Layer, LayerAttributes,
    SmallVec, WritableImage,
};

use crate::error::{Error, Result};
use ellipsoid_splat::Frame;
use ellipsoid_splat::Outputs;
use ellipsoid_splat_loaders::write_atomically;

fn encode_error(path: &Path, reason: impl ToString) -> Error {
    Error::Encode {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    }
}

/// Writes `path` whole or not at all ([`write_atomically`]): an error names the file and the
/// reason (the encoder's or the operating system's), and leaves any old file as it was.
pub fn write_file(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<()> {
    write_atomically(path, write).map_err(|e| encode_error(path, e))
}

/// `bytes` (`width x height` RGBA8) as a PNG file, whole or not at all.
pub fn write_rgba8_png(path: &Path, bytes: &[u8], width: u32, height: u32) -> Result<()> {
    use image::ImageEncoder;
    write_file(path, |w| {
        image::codecs::png::PngEncoder::new(w)
            .write_image(bytes, width, height, image::ExtendedColorType::Rgba8)
            .map_err(std::io::Error::other)
    })
}

/// sRGB colour as an 8-bit RGBA PNG.
pub fn write_color_png(frame: &Frame, path: &Path) -> Result<()> {
    let bytes: Vec<u8> = frame.color.iter().flatten().copied().collect();
    write_rgba8_png(path, &bytes, frame.width, frame.height)
}

fn write_exr(path: &Path, frame: &Frame, channels: Vec<AnyChannel<FlatSamples>>) -> Result<()> {
    let size = (frame.width as usize, frame.height as usize);
    let layer = Layer::new(
        size,
        LayerAttributes::named("ellipsoid-splat"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    let image = ExrImage::from_layer(layer);
    write_file(path, |w| {
        image.write().to_buffered(w).map_err(std::io::Error::other)
    })
}

/// View depth `dot(p - eye, f)` as a float32 EXR channel `Z`; background is +inf.
pub fn write_depth_exr(frame: &Frame, path: &Path) -> Result<()> {
    let z = AnyChannel::new("Z", FlatSamples::F32(frame.depth.clone()));
    write_exr(path, frame, vec![z])
}

/// World-space unit normal as float32 EXR channels `R, G, B`; background is 0.
pub fn write_normal_exr(frame: &Frame, path: &Path) -> Result<()> {
    let channel = |name: &str, k: usize| {
        AnyChannel::new(
            name,
            FlatSamples::F32(frame.normal.iter().map(|n| n[k]).collect()),
        )
    };
    write_exr(
        path,
        frame,
        vec![channel("R", 0), channel("G", 1), channel("B", 2)],
    )
}

/// Instance IDs, lossless: `.exr` writes a 32-bit unsigned channel `ID`; `.png` packs each ID
/// little-endian into RGBA8 (R = lowest byte). Background is `u32::MAX` (0xFFFFFFFF).
pub fn write_id_image(frame: &Frame, path: &Path) -> Result<()> {
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if is_png {
        let bytes: Vec<u8> = frame.id.iter().flat_map(|id| id.to_le_bytes()).collect();
        write_rgba8_png(path, &bytes, frame.width, frame.height)
    } else {
        let id = AnyChannel::new("ID", FlatSamples::U32(frame.id.clone()));
        write_exr(path, frame, vec![id])
    }
}

/// An image `render` can write, named by its flag.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Image {
    /// `--output`: sRGB colour, PNG.
    Color,
    /// `--depth`: float32 view depth, EXR.
    Depth,
    /// `--normal`: float32 world-space normal, EXR.
    Normal,
    /// `--id`: 32-bit instance IDs, EXR or PNG.
    Id,
}

impl Image {
    /// Every image, in the order they are written.
    pub const ALL: [Image; 4] = [Image::Color, Image::Depth, Image::Normal, Image::Id];

    /// The command-line flag that names this image's file.
    pub fn flag(self) -> &'static str {
        match self {
            Image::Color => "--output",
            Image::Depth => "--depth",
            Image::Normal => "--normal",
            Image::Id => "--id",
        }
    }

    /// File-name extensions (lower case, without the dot) this image can be written as.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Image::Color => &["png"],
            Image::Depth | Image::Normal => &["exr"],
            Image::Id => &["exr", "png"],
        }
    }

    /// How this image is encoded, for error messages.
    fn encoding(self) -> &'static str {
        match self {
            Image::Color => "colour is written as an 8-bit RGBA PNG",
            Image::Depth => "depth is written as a float32 OpenEXR image",
            Image::Normal => "normals are written as a float32 OpenEXR image",
            Image::Id => "IDs are written as a 32-bit OpenEXR channel or packed into an RGBA8 PNG",
        }
    }
}

impl Image {
    /// Is this image among `outputs`?
    pub fn is_in(self, outputs: Outputs) -> bool {
        match self {
            Image::Color => outputs.color,
            Image::Depth => outputs.depth,
            Image::Normal => outputs.normal,
            Image::Id => outputs.id,
        }
    }

    /// The images among `outputs`, in [`Image::ALL`] order. The offscreen renderer allocates,
    /// draws and reads back only their targets, and only they are written.
    pub fn all_in(outputs: Outputs) -> impl Iterator<Item = Image> {
        Image::ALL.into_iter().filter(move |&i| i.is_in(outputs))
    }
}

/// Writes `image` of `frame` to `path` in the encoding its extension names (see
/// [`check_extension`]).
pub fn write_image(frame: &Frame, image: Image, path: &Path) -> Result<()> {
    match image {
        Image::Color => write_color_png(frame, path),
        Image::Depth => write_depth_exr(frame, path),
        Image::Normal => write_normal_exr(frame, path),
        Image::Id => write_id_image(frame, path),
    }
}

/// Refuses a file name whose extension (compared case-insensitively) is not one `image` is
/// written as, naming the flag, the file and the accepted extensions.
pub fn check_extension(image: Image, path: &Path) -> Result<()> {
    let accepted = image.extensions();
    let extension = path.extension().and_then(|e| e.to_str());
    if extension.is_some_and(|e| accepted.iter().any(|a| e.eq_ignore_ascii_case(a))) {
        return Ok(());
    }
    let found = match extension {
        Some(e) => format!("ends in .{e}"),
        None => "has no extension".to_string(),
    };
    let accepted = accepted
        .iter()
        .map(|a| format!(".{a}"))
        .collect::<Vec<_>>()
        .join(" or ");
    Err(Error::invalid(
        image.flag(),
        format!(
            "'{}' {found}, but {}; the file name must end in {accepted}",
            path.display(),
            image.encoding()
        ),
    ))
}

/// Checks that `path` can be written, without changing anything: its directory exists, and
/// the file either exists and opens for writing (not truncated) or can be created (the probe
/// is removed again). Errors name `flag` and the path.
pub fn check_writable(flag: &str, path: &Path) -> Result<()> {
    let refuse = |reason: String| {
        Error::invalid(flag, format!("cannot write '{}': {reason}", path.display()))
    };
    if path.file_name().is_none() || path.is_dir() {
        return Err(refuse("it is a directory, not a file".to_string()));
    }
    let dir = directory_of(path);
    if !dir.exists() {
        return Err(refuse(format!(
            "the directory '{}' does not exist",
            dir.display()
        )));
    }
    if !dir.is_dir() {
        return Err(refuse(format!("'{}' is not a directory", dir.display())));
    }
    let open_existing = || {
        OpenOptions::new()
            .write(true)
            .open(path)
            .map(|_| ())
            .map_err(|e| refuse(e.to_string()))
    };
    if path.exists() {
        // A regular file is replaced by a rename of a file made in its directory
        // (`write_atomically`): that directory must take a new file. Anything else (a
        // device, a pipe) is written in place.
        if std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
            let probe = ellipsoid_splat_loaders::atomic_file::partial_name(
                &std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
            )
            .map_err(|e| refuse(e.to_string()))?;
            return OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&probe)
                .and_then(|_| std::fs::remove_file(&probe))
                .map_err(|e| refuse(e.to_string()))
                .and_then(|()| open_existing());
        }
        return open_existing();
    }
    match OpenOptions::new().write(true).create_new(true).open(path) {
        Ok(_) => match std::fs::remove_file(path) {
            // Another run may have taken the same name meanwhile and removed it.
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(refuse(e.to_string())),
            _ => Ok(()),
        },
        // Another writer created it between the two checks: it is writable if it opens.
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => open_existing(),
        Err(e) => Err(refuse(e.to_string())),
    }
}

/// Creates the directory `dir` named by `flag` (as the reports would) and checks that `file`
/// can be written in it, so that a bad directory fails before a long run rather than after.
pub fn check_output_dir(flag: &str, dir: &Path, file: &str) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(Error::invalid(
            flag,
            format!("'{}' is not a directory", dir.display()),
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        Error::invalid(
            flag,
            format!("cannot create the directory '{}': {e}", dir.display()),
        )
    })?;
    check_writable(flag, &dir.join(file))
}

/// The directory `path` is in (`.` for a bare file name).
fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// Where `path` points once its directory's links and `..` are resolved (the file itself need
/// not exist); `path` unchanged when the directory cannot be resolved.
pub fn resolved(path: &Path) -> PathBuf {
    match (directory_of(path).canonicalize(), path.file_name()) {
        (Ok(dir), Some(name)) => {
            let joined = dir.join(name);
            joined.canonicalize().unwrap_or(joined)
        }
        _ => path.to_path_buf(),
    }
}

/// The digits a frame number gets where the file name gives no `%0Nd` of its own.
const DEFAULT_DIGITS: usize = 4;

/// `path` with `number` in its file name: in place of its `%d` or `%0Nd` (N up to 9), or
/// appended to the stem as `_0001` when it has none. An error names `flag` where the name
/// holds a `%` that is not one such pattern, or more than one.
pub fn numbered(flag: &str, path: &Path, number: usize) -> Result<PathBuf> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .ok_or_else(|| Error::invalid(flag, format!("'{}' names no file", path.display())))?;
    let bad = |why: &str| {
        Error::invalid(
            flag,
            format!(
                "'{}' {why}: a frame sequence's name holds one %d or %0Nd (N from 1 to 9) for \
                 the frame number, or none (then _{number:0DEFAULT_DIGITS$} is added)",
                path.display()
            ),
        )
    };
    let Some(at) = name.find('%') else {
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let extension = path
            .extension()
            .map(|e| format!(".{}", e.to_string_lossy()))
            .unwrap_or_default();
        return Ok(path.with_file_name(format!("{stem}_{number:0DEFAULT_DIGITS$}{extension}")));
    };
    let rest = &name[at + 1..];
    let (digits, after) = match rest.as_bytes() {
        [b'd', ..] => (1, &rest[1..]),
        [b'0', n @ b'1'..=b'9', b'd', ..] => (usize::from(n - b'0'), &rest[3..]),
        _ => return Err(bad("has a % that is not %d or %0Nd")),
    };
    if after.contains('%') {
        return Err(bad("has more than one %"));
    }
    Ok(path.with_file_name(format!("{}{number:0digits$}{after}", &name[..at])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extensions_match_case_insensitively() {
        assert!(check_extension(Image::Color, Path::new("a/b.PNG")).is_ok());
        assert!(check_extension(Image::Depth, Path::new("d.Exr")).is_ok());
        assert!(check_extension(Image::Id, Path::new("i.png")).is_ok());
        assert!(check_extension(Image::Id, Path::new("i.EXR")).is_ok());
        let e = check_extension(Image::Depth, Path::new("d.png")).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("--depth") && text.contains("d.png") && text.contains(".exr"),
            "{text}"
        );
        let e = check_extension(Image::Normal, Path::new("normal")).unwrap_err();
        assert!(e.to_string().contains("has no extension"), "{e}");
        let e = check_extension(Image::Id, Path::new("i.tif")).unwrap_err();
        assert!(e.to_string().contains(".exr or .png"), "{e}");
    }

    #[test]
    fn writable_check_leaves_files_as_they_were() {
        let dir =
            std::env::temp_dir().join(format!("ellipsoid-splat-probe-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let existing = dir.join("kept.png");
        std::fs::write(&existing, b"keep").unwrap();
        check_writable("--output", &existing).unwrap();
        assert_eq!(std::fs::read(&existing).unwrap(), b"keep");
        let fresh = dir.join("fresh.exr");
        check_writable("--depth", &fresh).unwrap();
        assert!(!fresh.exists());
        let e = check_writable("--depth", &dir).unwrap_err();
        assert!(e.to_string().contains("is a directory"), "{e}");
        let e = check_writable("--id", &existing.join("x.exr")).unwrap_err();
        assert!(e.to_string().contains("is not a directory"), "{e}");
        assert_eq!(
            resolved(
                &dir.join("../")
                    .join(dir.file_name().unwrap())
                    .join("kept.png")
            ),
            resolved(&existing)
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn frame_numbers_go_where_the_name_says() {
        let name = |p: &str, n| numbered("--output", Path::new(p), n).unwrap();
        assert_eq!(name("out_%04d.png", 7), PathBuf::from("out_0007.png"));
        assert_eq!(name("dir/f%d.exr", 12), PathBuf::from("dir/f12.exr"));
        assert_eq!(name("movie.png", 3), PathBuf::from("movie_0003.png"));
        assert_eq!(name("a/b%03d_x.png", 1234), PathBuf::from("a/b1234_x.png"));
    }

    #[test]
    fn bad_patterns_name_the_flag() {
        let error = |p: &str| {
            numbered("--depth", Path::new(p), 1)
                .unwrap_err()
                .to_string()
        };
        assert!(
            error("d_%s.exr").contains("--depth"),
            "{}",
            error("d_%s.exr")
        );
        assert!(error("d_%d_%d.exr").contains("more than one"));
    }

    /// An image whose encoder fails (an EXR of no pixels) leaves the old file as it was and
    /// no partial file beside it: every image kind is written through `write_file`.
    #[test]
    fn a_failed_encoder_keeps_the_old_file() {
        let dir = std::env::temp_dir().join(format!("es-output-failed-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let empty = Frame::default();
        for (image, name) in [
            (Image::Depth, "d.exr"),
            (Image::Normal, "n.exr"),
            (Image::Id, "i.exr"),
        ] {
            let path = dir.join(name);
            std::fs::write(&path, b"old").unwrap();
            let error = write_image(&empty, image, &path).unwrap_err().to_string();
            assert!(error.contains(name), "{error}");
            assert_eq!(std::fs::read(&path).unwrap(), b"old");
        }
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(left.len(), 3, "no partial file left");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
