//! Reads diffusion tensor volumes in NIfTI-1 (`.nii`, `.nii.gz`) as fields of ellipsoid glyphs.
//!
//! # What is read
//! A single-file NIfTI-1 volume (magic `n+1`, either byte order, plain or gzipped) holding one
//! symmetric 3x3 tensor per voxel: shape `X x Y x Z x 6` (4-D, as FSL's `dtifit --save_tensor`
//! writes it) or `X x Y x Z x 1 x 6` (5-D, `NIFTI_INTENT_SYMMATRIX`, as DIPY's workflows write
//! it), `FLOAT32` or `FLOAT64`, with `scl_slope`/`scl_inter` applied when the slope is finite
//! and non-zero. The six components are in [`TensorOrder::Fsl`] order (`xx, xy, xz, yy, yz, zz`:
//! FSL, the default) or [`TensorOrder::Nifti`] order (lower triangle by rows,
//! `xx, yx, yy, zx, zy, zz`: the NIfTI standard, and DIPY's `Dxx, Dxy, Dyy, Dxz, Dyz, Dzz`).
//! The order is not guessed, but a note says so when the header's intent is
//! `NIFTI_INTENT_SYMMATRIX` and the FSL order is in effect. An optional mask
//! ([`LoadOptions::mask`]) is a NIfTI-1 volume on the same grid (`X x Y x Z`, any real
//! datatype); voxels where it is 0 are left out.
//!
//! # Where glyphs go
//! Voxel `(i, j, k)` is placed at `A (i, j, k) + b`, the voxel-to-world affine chosen as NIfTI-1
//! prescribes: the sform when `sform_code > 0`, else the qform (quaternion, offsets and
//! `pixdim`, with `qfac = pixdim[0]`) when `qform_code > 0`, else `diag(pixdim[1..4])` with no
//! offset. World units are the file's (normally millimetres).
//!
//! The tensors are taken to be in the voxel axes (the frame of the `i, j, k` indices, in which
//! FSL and DIPY fit them from FSL-style b-vectors), so each is rotated into world axes as
//! `T_world = R T R^T`, with `R` the rotation part of `A`: the orthogonal factor of its polar
//! decomposition `A = R S` (`R = A (A^T A)^(-1/2)`). For an affine made of a rotation (possibly
//! with a reflection) and voxel sizes, that is `A` with unit columns; voxel sizes and shears do
//! not distort the glyphs. (FSL's own convention flips the x axis of vectors in images whose
//! affine has a positive determinant; such tensors would need `xy` and `xz` negated first, which
//! is not done here.)
//!
//! # Which voxels become glyphs, and how big
//! Each voxel is tested in this order: left out where the mask is 0; left out as background
//! when all six components are exactly 0; an invalid record when a component is not finite or
//! the tensor is not positive definite -- an [`Error::Parse`] whose `column` names the voxel
//! (`"voxel i,j,k"`, `line` 0), or, with [`LoadOptions::skip_invalid`], dropped and counted in
//! [`Loaded::skipped`]; left out when its fractional anisotropy
//! ([`crate::anisotropy::fractional_anisotropy`] of the eigenvalues) is below
//! [`LoadOptions::min_fa`]. If no voxel is left, that is an error too.
//!
//! Semi-axes are the eigenvalues times one factor for the whole volume, chosen so that the
//! largest eigenvalue of any kept voxel becomes [`LoadOptions::glyph_scale`] times the smallest
//! voxel edge (the shortest column of `A`): with the default 0.5 the largest glyph is exactly
//! one voxel across, so glyphs do not overlap. Glyphs are coloured by shape
//! (`ellipsoid_splat::internals::shape_color`). The notes of [`Loaded`] give the factor in
//! effect and how many voxels were kept, background, below the FA threshold, masked and skipped.
//!
//! # Why not the `nifti` crate's reader and affine
//! The crate parses the header (`NiftiHeader`) and decodes the voxels (`InMemNiftiVolume`)
//! here. Its file reader is not used: it takes a `.nii.gz` as one gzip member and stops at the
//! end of the first, so a file of several members (as `bgzip` writes them, or files joined
//! with `cat`) comes out cut short (the test
//! `gzip_members_after_the_first_are_read_where_the_nifti_crate_stops` shows it); it tells
//! gzip by the name's `.gz` rather than by the bytes; and it reserves whatever the header
//! declares before reading, where this refuses more than [`MAX_DATA_BYTES`] or than the gzip
//! data can hold (read from the crate's 0.18.0 source). Its affine (behind
//! the feature `nalgebra_affine`, which would bring in `nalgebra`) is not used either: with
//! neither sform nor qform it returns nibabel's grid, centred and with x flipped, where NIfTI-1
//! places voxel 0 at the origin with `diag(pixdim)` (as here); it panics on a negative voxel
//! size (here an error naming `pixdim`) and on a `qfac` (`pixdim[0]`) other than +-1 (here its
//! sign, 0 counting as +1 as the standard says); and it checks no entry for being finite nor
//! the transform for being degenerate (read from the crate's 0.18.0 source; not tested, to
//! keep `nalgebra` out of the build).
//!
//! # Hostile input
//! [`parse_nifti`] never panics and never loops without consuming input. Every header field the
//! volume depends on (sizes, dimensions, datatype, `vox_offset`, transforms) is checked before
//! any voxel data is touched; the declared data must lie inside the bytes given, and at most
//! [`MAX_DATA_BYTES`] of it. Gzipped input is inflated with `flate2` (RFC 1951/1952, with CRC-32
//! and length checks) and never past what the header declares, so a small file cannot make the
//! loader allocate much more than the volume it claims to be.

use std::borrow::Cow;
use std::path::Path;

use glam::{DMat3, DVec3};
use nifti::{Endianness, InMemNiftiVolume, IntoNdArray, NiftiHeader, NiftiType};

use crate::anisotropy::fractional_anisotropy;
use crate::error::read_file;
use crate::loaded::{Loaded, Origins};
use crate::options::{LoadOptions, TensorOrder};
use crate::{Error, Result};
use ellipsoid_splat::Scene;
use ellipsoid_splat::{internals::symmetric_eigen, Ellipsoid};

/// The most voxel data (in bytes, as stored) a volume may declare: 1 GiB. Headers declaring more
/// are refused before anything is allocated.
pub const MAX_DATA_BYTES: usize = 1 << 30;

/// Size of a NIfTI-1 header.
const HEADER_BYTES: usize = 348;
/// Header plus the 4-byte extension flag: where voxel data may start at the earliest.
const MIN_VOX_OFFSET: usize = 352;
/// `NIFTI_INTENT_SYMMATRIX`.
const INTENT_SYMMATRIX: i16 = 1005;
/// Deflate's largest expansion is 1032:1 (at best a 258-byte match costs 2 bits: 258 x 8 / 2); a
/// gzip file this many times smaller than the volume it declares cannot hold it.
const MAX_DEFLATE_RATIO: usize = 1032;
/// Volumes with at least this many voxels get a progress bar (when asked for and on a terminal).
const PROGRESS_MIN_VOXELS: usize = 1 << 20;

/// Reads the tensor volume `path` (and the mask file named in `options`, if any) and turns it
/// into glyphs; see the [module documentation](self) for the conventions.
pub fn load_nifti(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    parse_nifti(&read_file(path)?, path, options)
}

/// Turns the bytes of a tensor volume (plain or gzipped NIfTI-1) into glyphs; `file` only names
/// the source in errors. The mask named in `options`, if any, is read from disk.
///
/// Pure apart from reading the mask: any byte string gives either a scene or an error naming
/// `file`, the place (header field, `voxel i,j,k`, ...) and the reason, without panicking.
pub fn parse_nifti(bytes: &[u8], file: &Path, options: &LoadOptions) -> Result<Loaded> {
    check_options(options)?;
    let tensors = read_volume(bytes, file, Role::Tensor)?;
    let mask = match &options.mask {
        Some(path) => {
            let mask = read_volume(&read_file(path)?, path, Role::Mask)?;
            check_same_grid(&mask, &tensors, path, file)?;
            Some(mask)
        }
        None => None,
    };
    build_glyphs(&tensors, mask.as_ref(), file, options)
}

/// The options this loader uses must make sense before any work is done.
fn check_options(options: &LoadOptions) -> Result<()> {
    if !options.glyph_scale.is_finite() || options.glyph_scale <= 0.0 {
        return Err(Error::invalid(
            "glyph_scale",
            format!("must be finite and > 0, got {}", options.glyph_scale),
        ));
    }
    if options.min_fa.is_nan() {
        return Err(Error::invalid("min_fa", "must be a number, got NaN"));
    }
    Ok(())
}

/// A parse error at a place that is not a line (a header field, a voxel).
fn parse_error(file: &Path, column: impl Into<String>, reason: impl Into<String>) -> Error {
    crate::error::parse_error(file, 0, column, reason)
}

/// What a volume is read for: the shapes and datatypes accepted differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// Six tensor components per voxel, floating point.
    Tensor,
    /// One value per voxel, any real datatype.
    Mask,
}

/// Where the voxel-to-world affine came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum XformSource {
    Sform(i16),
    Qform(i16),
    VoxelSizes,
}

impl std::fmt::Display for XformSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            XformSource::Sform(code) => write!(f, "sform (code {code})"),
            XformSource::Qform(code) => write!(f, "qform (code {code})"),
            XformSource::VoxelSizes => write!(f, "voxel sizes (no sform or qform)"),
        }
    }
}

/// Voxel index to world position: `linear * (i, j, k) + offset`.
#[derive(Clone, Copy, Debug)]
struct Affine {
    linear: DMat3,
    offset: DVec3,
    source: XformSource,
}

impl Affine {
    fn apply(&self, ijk: DVec3) -> DVec3 {
        self.linear * ijk + self.offset
    }

    /// Lengths of the voxel edges in world units (the columns of the linear part).
    fn voxel_edges(&self) -> DVec3 {
        DVec3::new(
            self.linear.x_axis.length(),
            self.linear.y_axis.length(),
            self.linear.z_axis.length(),
        )
    }

    /// The orthogonal factor `R` of the polar decomposition `linear = R S` (`S` symmetric
    /// positive definite): `R = linear (linear^T linear)^(-1/2)`. Keeps a reflection if the
    /// affine has one. `linear` is known to be non-singular.
    fn rotation(&self) -> DMat3 {
        let (values, vectors) = symmetric_eigen(self.linear.transpose() * self.linear);
        let inv_sqrt = DMat3::from_diagonal(DVec3::new(
            values.x.max(f64::MIN_POSITIVE).sqrt().recip(),
            values.y.max(f64::MIN_POSITIVE).sqrt().recip(),
            values.z.max(f64::MIN_POSITIVE).sqrt().recip(),
        ));
        self.linear * (vectors * inv_sqrt * vectors.transpose())
    }
}

/// A volume after its header has been checked and its data decoded.
struct Volume {
    /// `X, Y, Z`.
    grid: [usize; 3],
    /// All values, scaled, in file (Fortran) order: `i` fastest, the component slowest.
    values: Vec<f64>,
    affine: Affine,
    intent_code: i16,
}

impl Volume {
    fn voxel_count(&self) -> usize {
        self.grid[0] * self.grid[1] * self.grid[2]
    }

    fn grid_text(&self) -> String {
        format!("{}x{}x{}", self.grid[0], self.grid[1], self.grid[2])
    }
}

/// Checks the header of `bytes` (decompressing as far as needed), then decodes the voxel data.
fn read_volume(bytes: &[u8], file: &Path, role: Role) -> Result<Volume> {
    let err = |column: &str, reason: String| parse_error(file, column, reason);
    if bytes.is_empty() {
        return Err(err(
            "file",
            "empty file (0 bytes): not a NIfTI-1 volume".into(),
        ));
    }
    let gzipped = bytes.starts_with(&[0x1f, 0x8b]);

    // The header first: only 348 bytes are inflated to learn how much the rest must be.
    let head: Cow<[u8]> = if gzipped {
        Cow::Owned(gunzip(bytes, HEADER_BYTES).map_err(|e| err("gzip", e))?.0)
    } else {
        Cow::Borrowed(bytes)
    };
    let header = check_header_bytes(&head, gzipped, file)?;
    let layout = Layout::of(&header, file, role)?;
    let affine = affine_of(&header, file)?;

    let needed = layout.vox_offset + layout.data_bytes;
    let (data, status): (Cow<[u8]>, GzEnd) = if gzipped {
        let most = bytes
            .len()
            .saturating_mul(MAX_DEFLATE_RATIO)
            .saturating_add(1024);
        if needed > most {
            return Err(err(
                "data",
                format!(
                    "truncated: the header declares {} but {} bytes of gzip data can hold at \
                     most {most} bytes",
                    layout.describe(needed),
                    bytes.len()
                ),
            ));
        }
        let (out, status) = gunzip(bytes, needed).map_err(|e| err("gzip", e))?;
        (Cow::Owned(out), status)
    } else {
        (Cow::Borrowed(bytes), GzEnd::Complete)
    };
    if status == GzEnd::Truncated {
        return Err(err(
            "data",
            format!(
                "truncated: the gzip stream ends early, after {} decompressed bytes; the header \
                 declares {}",
                data.len(),
                layout.describe(needed)
            ),
        ));
    }
    if data.len() < needed {
        return Err(err(
            "data",
            format!(
                "truncated: the header declares {}, but the {}file has only {} bytes",
                layout.describe(needed),
                if gzipped { "decompressed " } else { "" },
                data.len()
            ),
        ));
    }
    let raw = match data {
        Cow::Owned(mut inflated) => {
            inflated.truncate(needed);
            inflated.drain(..layout.vox_offset);
            inflated
        }
        Cow::Borrowed(bytes) => bytes[layout.vox_offset..needed].to_vec(),
    };

    let volume = InMemNiftiVolume::from_raw_fields(
        header.dim,
        layout.datatype,
        layout.scl_slope,
        layout.scl_inter,
        raw,
        header.endianness,
    )
    .map_err(|e| err("data", format!("cannot decode the voxel data: {e}")))?;
    let array = volume
        .into_ndarray::<f64>()
        .map_err(|e| err("data", format!("cannot decode the voxel data: {e}")))?;
    // The crate builds the array over the whole buffer with a Fortran-order shape, so its
    // memory order is file order and the buffer can be taken as it is.
    let values = if array.t().is_standard_layout() {
        array.into_raw_vec_and_offset().0
    } else {
        array.t().iter().copied().collect()
    };
    Ok(Volume {
        grid: layout.grid,
        values,
        affine,
        intent_code: header.intent_code,
    })
}

/// Size, magic and byte order, then the header through the `nifti` crate.
fn check_header_bytes(head: &[u8], gzipped: bool, file: &Path) -> Result<NiftiHeader> {
    let err = |column: &str, reason: String| parse_error(file, column, reason);
    if head.len() < HEADER_BYTES {
        let what = if gzipped {
            "the decompressed data has only"
        } else {
            "the file has only"
        };
        return Err(err(
            "header",
            format!(
                "not a NIfTI-1 file: {what} {} bytes, fewer than the 348-byte header",
                head.len()
            ),
        ));
    }
    let size = [head[0], head[1], head[2], head[3]];
    let (le, be) = (i32::from_le_bytes(size), i32::from_be_bytes(size));
    let endianness = match (le, be) {
        (348, _) => Endianness::Little,
        (_, 348) => Endianness::Big,
        (540, _) | (_, 540) => {
            return Err(err(
                "sizeof_hdr",
                "NIfTI-2 (540-byte header) is not supported: save the volume as NIfTI-1".into(),
            ))
        }
        _ => {
            return Err(err(
                "sizeof_hdr",
                format!(
                    "not a NIfTI-1 file: the first 4 bytes ({le} little-endian, {be} \
                     big-endian) are not the header size 348"
                ),
            ))
        }
    };
    let magic = &head[344..348];
    match magic {
        b"n+1\0" => {}
        b"ni1\0" => {
            return Err(err(
                "magic",
                "this is the header of a .hdr/.img pair (magic \"ni1\"); only single-file .nii \
                 volumes (magic \"n+1\") are read"
                    .into(),
            ))
        }
        _ => {
            return Err(err(
                "magic",
                format!(
                    "not a NIfTI-1 file: magic is \"{}\", expected \"n+1\"",
                    magic.escape_ascii()
                ),
            ))
        }
    }
    let header = NiftiHeader::from_reader(&head[..HEADER_BYTES])
        .map_err(|e| err("header", format!("unreadable NIfTI-1 header: {e}")))?;
    if header.endianness != endianness || header.sizeof_hdr != 348 {
        return Err(err(
            "dim",
            format!(
                "inconsistent byte order: sizeof_hdr reads as {endianness:?}-endian but dim[0] \
                 ({}) does not",
                header.dim[0]
            ),
        ));
    }
    Ok(header)
}

/// What the header says about the data, checked.
struct Layout {
    grid: [usize; 3],
    datatype: NiftiType,
    vox_offset: usize,
    data_bytes: usize,
    scl_slope: f32,
    scl_inter: f32,
    shape: String,
}

impl Layout {
    fn of(header: &NiftiHeader, file: &Path, role: Role) -> Result<Self> {
        let err = |column: &str, reason: String| parse_error(file, column, reason);
        // The header stores dimensions as signed 16-bit numbers.
        let dim: Vec<i16> = header.dim.iter().map(|&d| d as i16).collect();
        let rank = dim[0];
        if !(1..=7).contains(&rank) {
            return Err(err(
                "dim",
                format!("dim[0] (the number of dimensions) is {rank}; it must be 1 to 7"),
            ));
        }
        let rank = rank as usize;
        if let Some(n) = (1..=rank).find(|&n| dim[n] <= 0) {
            return Err(err(
                "dim",
                format!("dim[{n}] is {}; dimensions must be positive", dim[n]),
            ));
        }
        let sizes: Vec<usize> = dim[1..=rank].iter().map(|&d| d as usize).collect();
        let shape = sizes
            .iter()
            .map(|d| d.to_string())
            .collect::<Vec<_>>()
            .join("x");
        match role {
            Role::Tensor => {
                if rank < 4 {
                    return Err(err(
                        "dim",
                        format!(
                            "a {rank}-D volume ({shape}) holds no tensors: expected 4-D XxYxZx6 \
                             or 5-D XxYxZx1x6, the six tensor components along the last axis"
                        ),
                    ));
                }
                let last = sizes[rank - 1];
                let fits = match rank {
                    4 => last == 6,
                    5 => sizes[3] == 1 && last == 6,
                    _ => false,
                };
                if !fits {
                    let why = if last != 6 {
                        format!("the last axis must hold the 6 tensor components, it has {last}")
                    } else {
                        "one tensor per voxel: the axes between the third and the last must \
                         have size 1"
                            .into()
                    };
                    return Err(err(
                        "dim",
                        format!(
                            "shape {shape} is not a tensor volume: expected XxYxZx6 or \
                             XxYxZx1x6 ({why})"
                        ),
                    ));
                }
            }
            Role::Mask => {
                if rank < 3 || sizes[3..].iter().any(|&d| d != 1) {
                    return Err(err(
                        "dim",
                        format!("shape {shape} is not a mask: expected 3-D XxYxZ"),
                    ));
                }
            }
        }
        let grid = [
            sizes.first().copied().unwrap_or(1),
            sizes.get(1).copied().unwrap_or(1),
            sizes.get(2).copied().unwrap_or(1),
        ];

        let code = header.datatype;
        let name = match datatype_name(code) {
            known if !known.starts_with('(') => format!("{known} (code {code})"),
            unknown => format!("code {code} {unknown}"),
        };
        let datatype = match (role, nifti_type(code)) {
            (Role::Tensor, Some(t @ (NiftiType::Float32 | NiftiType::Float64))) => t,
            (
                Role::Mask,
                Some(
                    t @ (NiftiType::Uint8
                    | NiftiType::Int8
                    | NiftiType::Uint16
                    | NiftiType::Int16
                    | NiftiType::Uint32
                    | NiftiType::Int32
                    | NiftiType::Uint64
                    | NiftiType::Int64
                    | NiftiType::Float32
                    | NiftiType::Float64),
                ),
            ) => t,
            (Role::Tensor, _) => {
                return Err(err(
                    "datatype",
                    format!(
                        "unsupported datatype {name}: tensor volumes must be \
                         FLOAT32 (16) or FLOAT64 (64)"
                    ),
                ))
            }
            (Role::Mask, _) => {
                return Err(err(
                    "datatype",
                    format!(
                        "unsupported datatype {name}: a mask must hold real \
                         numbers (integers or FLOAT32/FLOAT64)"
                    ),
                ))
            }
        };

        let offset = header.vox_offset;
        if !offset.is_finite() || offset.fract() != 0.0 || offset < MIN_VOX_OFFSET as f32 {
            return Err(err(
                "vox_offset",
                format!(
                    "vox_offset is {offset}; in a .nii file the data starts at a whole byte \
                     offset of at least {MIN_VOX_OFFSET}"
                ),
            ));
        }
        if offset > MAX_DATA_BYTES as f32 {
            return Err(err(
                "vox_offset",
                format!("vox_offset {offset} is absurdly large (over {MAX_DATA_BYTES} bytes)"),
            ));
        }
        let vox_offset = offset as usize;

        let element = datatype.size_of();
        let data_bytes = sizes
            .iter()
            .try_fold(element, |acc, &d| acc.checked_mul(d))
            .filter(|&n| n <= MAX_DATA_BYTES)
            .ok_or_else(|| {
                err(
                    "dim",
                    format!(
                        "shape {shape} of {} is too large: the loader accepts at most \
                         {MAX_DATA_BYTES} bytes of voxel data",
                        datatype_name(code)
                    ),
                )
            })?;

        // Scaling applies when the slope is set (finite and non-zero), as in NIfTI-1.
        let (scl_slope, scl_inter) = if header.scl_slope.is_finite() && header.scl_slope != 0.0 {
            let inter = if header.scl_inter.is_finite() {
                header.scl_inter
            } else {
                0.0
            };
            (header.scl_slope, inter)
        } else {
            (0.0, 0.0)
        };
        Ok(Layout {
            grid,
            datatype,
            vox_offset,
            data_bytes,
            scl_slope,
            scl_inter,
            shape,
        })
    }

    /// "`N` bytes of voxel data (shape x TYPE) from offset O (N + O bytes in all)".
    fn describe(&self, needed: usize) -> String {
        format!(
            "{} bytes of voxel data ({} x {}) from offset {} ({needed} bytes in all)",
            self.data_bytes,
            self.shape,
            datatype_name(self.datatype as i16),
            self.vox_offset
        )
    }
}

/// The NIfTI-1 name of a datatype code.
fn datatype_name(code: i16) -> &'static str {
    match code {
        0 => "UNKNOWN",
        1 => "BINARY",
        2 => "UINT8",
        4 => "INT16",
        8 => "INT32",
        16 => "FLOAT32",
        32 => "COMPLEX64",
        64 => "FLOAT64",
        128 => "RGB24",
        256 => "INT8",
        512 => "UINT16",
        768 => "UINT32",
        1024 => "INT64",
        1280 => "UINT64",
        1536 => "FLOAT128",
        1792 => "COMPLEX128",
        2048 => "COMPLEX256",
        2304 => "RGBA32",
        _ => "(not a NIfTI datatype)",
    }
}

/// `NiftiType` from a code, `None` for unknown codes (through the `nifti` crate's own mapping).
fn nifti_type(code: i16) -> Option<NiftiType> {
    let header = NiftiHeader {
        datatype: code,
        ..NiftiHeader::default()
    };
    header.data_type().ok()
}

/// The voxel-to-world affine: sform if `sform_code > 0`, else qform if `qform_code > 0`, else
/// the voxel sizes.
fn affine_of(header: &NiftiHeader, file: &Path) -> Result<Affine> {
    let err = |column: &str, reason: String| parse_error(file, column, reason);
    let pixdim = |column: &str| -> Result<DVec3> {
        let d = DVec3::new(
            header.pixdim[1] as f64,
            header.pixdim[2] as f64,
            header.pixdim[3] as f64,
        );
        if !d.is_finite() || d.min_element() <= 0.0 {
            return Err(err(
                column,
                format!("voxel sizes pixdim[1..4] must be finite and > 0, got {d}"),
            ));
        }
        Ok(d)
    };
    let affine = if header.sform_code > 0 {
        let rows = [header.srow_x, header.srow_y, header.srow_z];
        if rows.iter().flatten().any(|v| !v.is_finite()) {
            return Err(err(
                "sform",
                format!("the sform has a non-finite entry: {rows:?}"),
            ));
        }
        let r = |row: usize, col: usize| rows[row][col] as f64;
        Affine {
            linear: DMat3::from_cols(
                DVec3::new(r(0, 0), r(1, 0), r(2, 0)),
                DVec3::new(r(0, 1), r(1, 1), r(2, 1)),
                DVec3::new(r(0, 2), r(1, 2), r(2, 2)),
            ),
            offset: DVec3::new(r(0, 3), r(1, 3), r(2, 3)),
            source: XformSource::Sform(header.sform_code),
        }
    } else if header.qform_code > 0 {
        let q = [
            header.quatern_b,
            header.quatern_c,
            header.quatern_d,
            header.quatern_x,
            header.quatern_y,
            header.quatern_z,
        ];
        if q.iter().any(|v| !v.is_finite()) {
            return Err(err(
                "qform",
                format!("the qform has a non-finite parameter: {q:?}"),
            ));
        }
        let (b, c, d) = (q[0] as f64, q[1] as f64, q[2] as f64);
        let bcd = b * b + c * c + d * d;
        // As nifti1_io: a = sqrt(1 - b^2 - c^2 - d^2), or a 180-degree turn when that is ~0.
        let (a, b, c, d) = if 1.0 - bcd < 1e-7 {
            let n = bcd.sqrt();
            if n == 0.0 {
                (1.0, 0.0, 0.0, 0.0)
            } else {
                (0.0, b / n, c / n, d / n)
            }
        } else {
            ((1.0 - bcd).sqrt(), b, c, d)
        };
        let rotation = DMat3::from_cols(
            DVec3::new(
                a * a + b * b - c * c - d * d,
                2.0 * (b * c + a * d),
                2.0 * (b * d - a * c),
            ),
            DVec3::new(
                2.0 * (b * c - a * d),
                a * a + c * c - b * b - d * d,
                2.0 * (c * d + a * b),
            ),
            DVec3::new(
                2.0 * (b * d + a * c),
                2.0 * (c * d - a * b),
                a * a + d * d - b * b - c * c,
            ),
        );
        let qfac = if header.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
        let size = pixdim("pixdim")? * DVec3::new(1.0, 1.0, qfac);
        Affine {
            linear: rotation * DMat3::from_diagonal(size),
            offset: DVec3::new(q[3] as f64, q[4] as f64, q[5] as f64),
            source: XformSource::Qform(header.qform_code),
        }
    } else {
        Affine {
            linear: DMat3::from_diagonal(pixdim("pixdim")?),
            offset: DVec3::ZERO,
            source: XformSource::VoxelSizes,
        }
    };
    let edges = affine.voxel_edges();
    let det = affine.linear.determinant();
    let volume = edges.x * edges.y * edges.z;
    if !(edges.min_element() > 0.0 && det.abs() > 1e-9 * volume && det.is_finite()) {
        let column = match affine.source {
            XformSource::Sform(_) => "sform",
            XformSource::Qform(_) => "qform",
            XformSource::VoxelSizes => "pixdim",
        };
        return Err(err(
            column,
            format!(
                "the voxel-to-world transform ({}) is degenerate: voxel edges {edges}, \
                 determinant {det}",
                affine.source
            ),
        ));
    }
    Ok(affine)
}

/// The mask must have the tensor volume's grid: the same dimensions and, when both files place
/// their voxels, the same voxel-to-world transform (to a thousandth of a voxel).
fn check_same_grid(mask: &Volume, tensors: &Volume, mask_file: &Path, file: &Path) -> Result<()> {
    if mask.grid != tensors.grid {
        return Err(parse_error(
            mask_file,
            "grid",
            format!(
                "the mask's grid {} differs from the tensor volume's {} ({})",
                mask.grid_text(),
                tensors.grid_text(),
                file.display()
            ),
        ));
    }
    let placed = |v: &Volume| v.affine.source != XformSource::VoxelSizes;
    if placed(mask) && placed(tensors) {
        let tolerance = 1e-3 * tensors.affine.voxel_edges().min_element();
        let (a, b) = (&mask.affine, &tensors.affine);
        let gap = (a.linear - b.linear)
            .to_cols_array()
            .iter()
            .chain((a.offset - b.offset).to_array().iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        if gap.is_nan() || gap > tolerance {
            return Err(parse_error(
                mask_file,
                "grid",
                format!(
                    "the mask's voxel-to-world transform ({}: voxel (0,0,0) at {}) differs from \
                     the tensor volume's ({}: at {}; {}) by up to {gap:.4}",
                    a.source,
                    a.offset,
                    b.source,
                    b.offset,
                    file.display()
                ),
            ));
        }
    }
    Ok(())
}

/// Why voxels were left out, and how many.
#[derive(Default)]
struct Counts {
    kept: usize,
    background: usize,
    below_fa: usize,
    masked: usize,
    skipped: usize,
}

impl Counts {
    fn summary(&self, total: usize, min_fa: f64) -> String {
        format!(
            "of {total} voxels, {} kept, {} background (all-zero tensor), {} with FA < {min_fa}, \
             {} masked, {} invalid skipped",
            self.kept, self.background, self.below_fa, self.masked, self.skipped
        )
    }
}

/// Component names in the stored order.
fn component_names(order: TensorOrder) -> [&'static str; 6] {
    match order {
        TensorOrder::Fsl => ["xx", "xy", "xz", "yy", "yz", "zz"],
        TensorOrder::Nifti => ["xx", "yx", "yy", "zx", "zy", "zz"],
    }
}

/// The symmetric tensor from six stored values.
fn tensor_from(v: [f64; 6], order: TensorOrder) -> DMat3 {
    let [xx, xy, xz, yy, yz, zz] = match order {
        TensorOrder::Fsl => v,
        TensorOrder::Nifti => [v[0], v[1], v[3], v[2], v[4], v[5]],
    };
    DMat3::from_cols(
        DVec3::new(xx, xy, xz),
        DVec3::new(xy, yy, yz),
        DVec3::new(xz, yz, zz),
    )
}

fn build_glyphs(
    tensors: &Volume,
    mask: Option<&Volume>,
    file: &Path,
    options: &LoadOptions,
) -> Result<Loaded> {
    let [nx, ny, nz] = tensors.grid;
    let voxels = tensors.voxel_count();
    let rotation = tensors.affine.rotation();
    let names = component_names(options.tensor_order);
    let progress = (options.progress && voxels >= PROGRESS_MIN_VOXELS)
        .then(|| crate::progress::Progress::new(nz as u64, "tensor volume"));

    let mut counts = Counts::default();
    let mut first_skipped: Option<Error> = None;
    let mut ellipsoids: Vec<Ellipsoid> = Vec::new();
    // The voxel of each glyph, for errors after scaling.
    let mut voxel_of: Vec<[u16; 3]> = Vec::new();
    let mut largest = 0.0f64;
    // With `skip_invalid` the error is counted, else returned.
    let mut invalid = |error: Error, counts: &mut Counts| -> Result<()> {
        if options.skip_invalid {
            counts.skipped += 1;
            first_skipped.get_or_insert(error);
            Ok(())
        } else {
            Err(error)
        }
    };
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let n = i + nx * (j + ny * k);
                if let Some(mask) = mask {
                    let m = mask.values[n];
                    if m == 0.0 || m.is_nan() {
                        counts.masked += 1;
                        continue;
                    }
                }
                let stored: [f64; 6] = std::array::from_fn(|c| tensors.values[n + voxels * c]);
                if stored.iter().all(|&v| v == 0.0) {
                    counts.background += 1;
                    continue;
                }
                let place = || format!("voxel {i},{j},{k}");
                let listing = || {
                    names
                        .iter()
                        .zip(stored)
                        .map(|(name, v)| format!("{name}={v:.4e}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                if stored.iter().any(|v| !v.is_finite()) {
                    let reason = format!("the tensor has a non-finite component ({})", listing());
                    invalid(parse_error(file, place(), reason), &mut counts)?;
                    continue;
                }
                let voxel_tensor = tensor_from(stored, options.tensor_order);
                // The glyph at scale 1 for now (semi-axes = eigenvalues); the volume-wide scale
                // is known only once every voxel has been seen. `from_tensor` finds the
                // eigenvalues once, for the validity test, FA and the glyph alike.
                let ijk = DVec3::new(i as f64, j as f64, k as f64);
                let world = rotation * voxel_tensor * rotation.transpose();
                let world = (world + world.transpose()) * 0.5;
                let glyph = match Ellipsoid::from_tensor(tensors.affine.apply(ijk), world, None) {
                    Ok(glyph) => glyph,
                    Err(e) => {
                        let (values, _) = symmetric_eigen(voxel_tensor);
                        let reason = if values.is_nan() || values.min_element() <= 0.0 {
                            format!(
                                "the tensor is not positive definite (eigenvalues {:.4e}, \
                                 {:.4e}, {:.4e}; {})",
                                values.x,
                                values.y,
                                values.z,
                                listing()
                            )
                        } else {
                            format!("the tensor gives no ellipsoid: {e} ({})", listing())
                        };
                        invalid(parse_error(file, place(), reason), &mut counts)?;
                        continue;
                    }
                };
                if fractional_anisotropy(glyph.radii) < options.min_fa {
                    counts.below_fa += 1;
                    continue;
                }
                largest = largest.max(glyph.radii.max_element());
                ellipsoids.push(glyph);
                // Dimensions are below 2^15.
                voxel_of.push([i as u16, j as u16, k as u16]);
            }
        }
        if let Some(progress) = &progress {
            progress.inc(&format!("slice {}/{nz}", k + 1));
        }
    }
    if let Some(progress) = &progress {
        progress.finish();
    }

    // Scaling keeps orientations and shape colours; only extreme dynamic ranges can fail it.
    let edge = tensors.affine.voxel_edges().min_element();
    let scale = options.glyph_scale * edge / largest;
    let mut kept = 0;
    for n in 0..ellipsoids.len() {
        let mut glyph = ellipsoids[n];
        let eigenvalues = glyph.radii;
        glyph.radii *= scale;
        if glyph.radii.is_finite() && glyph.radii.min_element() > 0.0 {
            ellipsoids[kept] = glyph;
            // The origins stay parallel to the glyphs.
            voxel_of[kept] = voxel_of[n];
            kept += 1;
        } else {
            let [i, j, k] = voxel_of[n];
            let reason = format!(
                "the eigenvalues {:.4e}, {:.4e}, {:.4e} give no usable semi-axes at the volume's \
                 scale {scale:.4e}",
                eigenvalues.x, eigenvalues.y, eigenvalues.z
            );
            invalid(
                parse_error(file, format!("voxel {i},{j},{k}"), reason),
                &mut counts,
            )?;
        }
    }
    ellipsoids.truncate(kept);
    voxel_of.truncate(kept);
    counts.kept = ellipsoids.len();
    let summary = counts.summary(voxels, options.min_fa);
    if ellipsoids.is_empty() {
        let first = match &first_skipped {
            Some(e) => format!("; the first invalid: {e}"),
            None => String::new(),
        };
        return Err(parse_error(
            file,
            "volume",
            format!("no glyphs left: {summary}{first}"),
        ));
    }

    let mut notes = vec![
        format!(
            "{} glyphs from a {} grid placed by the {}; {summary}",
            counts.kept,
            tensors.grid_text(),
            tensors.affine.source
        ),
        format!(
            "glyph semi-axes = eigenvalues x {scale:.6e}: the largest eigenvalue {largest:.6e} \
             becomes {:.6} ({} x the smallest voxel edge {edge:.6})",
            options.glyph_scale * edge,
            options.glyph_scale
        ),
    ];
    if tensors.intent_code == INTENT_SYMMATRIX && options.tensor_order == TensorOrder::Fsl {
        notes.push(
            "the header's intent is NIFTI_INTENT_SYMMATRIX (lower-triangle order xx,yx,yy,zx,zy,\
             zz) but the FSL order xx,xy,xz,yy,yz,zz is in effect; choose the NIfTI order if \
             the glyphs look wrong"
                .into(),
        );
    }
    if let Some(e) = first_skipped {
        notes.push(format!(
            "skipped {} invalid voxel(s); the first: {e}",
            counts.skipped
        ));
    }
    Ok(Loaded {
        scene: Scene::new(ellipsoids),
        skipped: counts.skipped,
        notes,
        origins: Origins::Voxels(voxel_of),
    })
}

// ---------------------------------------------------------------------------------------------
// gzip through `flate2` (RFC 1952: its multi-member decoder checks every member's CRC-32 and
// length), read only up to an output limit so a hostile header cannot make it inflate more.

/// How inflating ended (corrupt data is an error instead).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum GzEnd {
    /// Every member ended, with matching CRC-32 and length.
    Complete,
    /// Stopped on reaching the output limit.
    Limit,
    /// The input ended inside a member.
    Truncated,
}

/// Inflates the gzip members in `input` until they end or `limit` bytes are out. On reaching
/// the limit it still reads on (up to `TRAILING_LIMIT` more bytes, discarded) to see the
/// stream end with its CRC-32 and length: a file cut after its data is still truncated.
fn gunzip(input: &[u8], limit: usize) -> std::result::Result<(Vec<u8>, GzEnd), String> {
    use std::io::Read;
    const TRAILING_LIMIT: u64 = 1 << 20;
    let classify = |e: std::io::Error| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            Ok(GzEnd::Truncated)
        } else {
            Err(format!("corrupt gzip data: {e}"))
        }
    };
    let mut out = Vec::new();
    let mut decoder = flate2::read::MultiGzDecoder::new(input).take(limit as u64);
    if let Err(e) = decoder.read_to_end(&mut out) {
        return classify(e).map(|end| (out, end));
    }
    if out.len() < limit {
        return Ok((out, GzEnd::Complete));
    }
    let mut rest = decoder.into_inner().take(TRAILING_LIMIT);
    let end = match std::io::copy(&mut rest, &mut std::io::sink()) {
        Ok(_) => GzEnd::Limit,
        Err(e) => classify(e)?,
    };
    Ok((out, end))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `gzip.compress(b"hello hello hello hello\n" * 3, mtime=0)`: fixed Huffman codes with
    /// back-references.
    const FIXED: &[u8] = &[
        0x1f, 0x8b, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x03, 0xcb, 0x48, 0xcd, 0xc9, 0xc9,
        0x57, 0xc8, 0x40, 0x27, 0xb9, 0x32, 0x48, 0x14, 0x07, 0x00, 0x4a, 0x0e, 0xce, 0x11, 0x48,
        0x00, 0x00, 0x00,
    ];

    fn fixed_text() -> Vec<u8> {
        b"hello hello hello hello\n".repeat(3)
    }

    #[test]
    fn inflates_fixed_huffman() {
        let (out, end) = gunzip(FIXED, usize::MAX).unwrap();
        assert_eq!(end, GzEnd::Complete);
        assert_eq!(out, fixed_text());
    }

    #[test]
    fn stops_at_the_limit_and_reports_truncation() {
        let (out, end) = gunzip(FIXED, 10).unwrap();
        assert_eq!((out.as_slice(), end), (&fixed_text()[..10], GzEnd::Limit));
        for cut in 0..FIXED.len() {
            let (out, end) = gunzip(&FIXED[..cut], usize::MAX).unwrap();
            assert_eq!(end, GzEnd::Truncated, "cut at {cut}");
            assert!(fixed_text().starts_with(&out));
        }
    }

    #[test]
    fn concatenated_members_and_bad_crc() {
        let two = [FIXED, FIXED].concat();
        let (out, end) = gunzip(&two, usize::MAX).unwrap();
        assert_eq!(end, GzEnd::Complete);
        assert_eq!(out, [fixed_text(), fixed_text()].concat());
        let mut bad = FIXED.to_vec();
        let n = bad.len();
        bad[n - 8] ^= 1;
        let err = gunzip(&bad, usize::MAX).unwrap_err();
        assert!(err.contains("corrupt gzip data"), "{err}");
    }

    #[test]
    fn rotation_of_a_scaled_sheared_affine_is_orthogonal() {
        let affine = Affine {
            linear: DMat3::from_cols(
                DVec3::new(0.0, 2.0, 0.0),
                DVec3::new(-2.5, 0.1, 0.0),
                DVec3::new(0.0, 0.0, -3.0),
            ),
            offset: DVec3::ZERO,
            source: XformSource::VoxelSizes,
        };
        let r = affine.rotation();
        let identity = r.transpose() * r;
        for (x, y) in identity
            .to_cols_array()
            .iter()
            .zip(DMat3::IDENTITY.to_cols_array())
        {
            assert!((x - y).abs() < 1e-12, "{r}");
        }
        assert!(r.determinant() < 0.0, "the reflection is kept");
        assert!((r.x_axis - DVec3::Y).length() < 0.03, "{r}");
    }
}
