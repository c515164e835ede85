//! gzip: the particle formats are read whole and gunzipped in memory; format detection looks
//! at the first bytes inside a stream.
//!
//! The inflating is `flate2`'s (its multi-member decoder, which checks each member's CRC-32 and
//! length); what this adds is only what the loaders need around it: bytes that are not gzip
//! pass through unchanged, a truncated stream is told apart from corrupt data in an
//! [`crate::Error::Parse`] naming the file, and detection inflates no more than it looks at.

use std::path::Path;

use crate::error::{io_error, parse_error};
use crate::Result;

/// The decompressed content of gzip `bytes` (several members are read back to back), or the
/// bytes themselves when they are not gzip.
pub(crate) fn gunzip_if_compressed(bytes: Vec<u8>, file: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Ok(bytes);
    }
    let mut out = Vec::with_capacity(bytes.len().saturating_mul(4));
    flate2::read::MultiGzDecoder::new(bytes.as_slice())
        .read_to_end(&mut out)
        .map_err(|e| {
            let reason = if e.kind() == std::io::ErrorKind::UnexpectedEof {
                format!(
                    "truncated gzip stream (after {} decompressed bytes)",
                    out.len()
                )
            } else {
                format!("corrupt gzip data: {e}")
            };
            parse_error(file, 0, "gzip", reason)
        })?;
    Ok(out)
}

/// The first decompressed bytes of a gzip file (up to `limit`; fewer if it is short or
/// corrupt): enough for `detect_format` to look inside.
pub(crate) fn gzip_head(path: &Path, limit: u64) -> Result<Vec<u8>> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(io_error(path))?;
    let mut out = Vec::new();
    // A corrupt stream leaves what was inflated before it: the loader names the damage.
    let _ = flate2::read::MultiGzDecoder::new(file)
        .take(limit)
        .read_to_end(&mut out);
    Ok(out)
}

/// The content of `path`, gunzipped if it is gzip.
pub(crate) fn read_gunzipped(path: &Path) -> Result<Vec<u8>> {
    let bytes = std::fs::read(path).map_err(io_error(path))?;
    gunzip_if_compressed(bytes, path)
}
