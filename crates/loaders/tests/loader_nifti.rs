//! Diffusion tensor NIfTI-1 volumes: every malformed input is rejected naming file, place and
//! reason; tensor orders, transforms, scaling, filters and masks do what the `nifti` module
//! says; hostile bytes never panic.

mod support;

use std::path::Path;
use std::time::Instant;

use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat_loaders::nifti::{load_nifti, parse_nifti};
use ellipsoid_splat_loaders::Error;
use ellipsoid_splat_loaders::{LoadOptions, Loaded, Origins, TensorOrder};
use glam::{DMat3, DVec3};
use support::{
    assert_close, assert_contains, assert_io_error, assert_note, loaded, options, parse_error,
    sample, skipping, Rng, TempDir,
};

const FILE: &str = "tensors.nii";

// ---------------------------------------------------------------------------------------------
// Writing NIfTI-1 files.

/// A NIfTI-1 file to write: the header fields the tests vary and the voxel values (file order:
/// `i` fastest, the component slowest), encoded as `datatype` on writing.
#[derive(Clone, Debug)]
struct Nii {
    dims: Vec<i16>,
    datatype: i16,
    pixdim: [f32; 8],
    vox_offset: f32,
    scl_slope: f32,
    scl_inter: f32,
    intent_code: i16,
    qform_code: i16,
    sform_code: i16,
    /// quatern_b, c, d, x, y, z.
    quatern: [f32; 6],
    srow: [[f32; 4]; 3],
    magic: [u8; 4],
    sizeof_hdr: i32,
    big_endian: bool,
    values: Vec<f64>,
}

impl Nii {
    /// An `nx x ny x nz x 6` FLOAT32 tensor volume, 1 mm voxels, no transform; `f` gives the six
    /// stored components of voxel `(i, j, k)`.
    fn tensors(grid: [usize; 3], f: impl Fn(usize, usize, usize) -> [f64; 6]) -> Self {
        let [nx, ny, nz] = grid;
        let voxels = nx * ny * nz;
        let mut values = vec![0.0; voxels * 6];
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let n = i + nx * (j + ny * k);
                    for (c, v) in f(i, j, k).into_iter().enumerate() {
                        values[n + voxels * c] = v;
                    }
                }
            }
        }
        Self {
            dims: vec![nx as i16, ny as i16, nz as i16, 6],
            datatype: 16,
            pixdim: [1.0; 8],
            vox_offset: 352.0,
            scl_slope: 0.0,
            scl_inter: 0.0,
            intent_code: 0,
            qform_code: 0,
            sform_code: 0,
            quatern: [0.0; 6],
            srow: [[0.0; 4]; 3],
            magic: *b"n+1\0",
            sizeof_hdr: 348,
            big_endian: false,
            values,
        }
    }

    /// A 3-D UINT8 mask from `f(i, j, k)`.
    fn mask(grid: [usize; 3], f: impl Fn(usize, usize, usize) -> bool) -> Self {
        let [nx, ny, nz] = grid;
        let mut nii = Self::tensors(grid, |_, _, _| [0.0; 6]);
        nii.dims.truncate(3);
        nii.datatype = 2;
        nii.values = (0..nx * ny * nz)
            .map(|n| f(n % nx, (n / nx) % ny, n / (nx * ny)) as u8 as f64)
            .collect();
        nii
    }

    fn with_sform(mut self, rows: [[f32; 4]; 3]) -> Self {
        self.sform_code = 1;
        self.srow = rows;
        self
    }

    fn element_size(&self) -> usize {
        match self.datatype {
            2 | 256 => 1,
            4 | 512 => 2,
            8 | 16 | 768 => 4,
            32 | 1792 => 8 * (1 + (self.datatype == 1792) as usize),
            _ => 8,
        }
    }

    fn bytes(&self) -> Vec<u8> {
        let mut h = Vec::with_capacity(352);
        let be = self.big_endian;
        let i16b = |v: i16| if be { v.to_be_bytes() } else { v.to_le_bytes() };
        let i32b = |v: i32| if be { v.to_be_bytes() } else { v.to_le_bytes() };
        let f32b = |v: f32| if be { v.to_be_bytes() } else { v.to_le_bytes() };
        h.extend(i32b(self.sizeof_hdr));
        h.extend([0u8; 10 + 18]);
        h.extend(i32b(0)); // extents
        h.extend(i16b(0)); // session_error
        h.extend([b'r', 0]); // regular, dim_info
        let mut dim = [1i16; 8];
        dim[0] = self.dims.len() as i16;
        dim[1..=self.dims.len()].copy_from_slice(&self.dims);
        for d in dim {
            h.extend(i16b(d));
        }
        for _ in 0..3 {
            h.extend(f32b(0.0)); // intent_p1..3
        }
        h.extend(i16b(self.intent_code));
        h.extend(i16b(self.datatype));
        h.extend(i16b(8 * self.element_size() as i16));
        h.extend(i16b(0)); // slice_start
        for p in self.pixdim {
            h.extend(f32b(p));
        }
        h.extend(f32b(self.vox_offset));
        h.extend(f32b(self.scl_slope));
        h.extend(f32b(self.scl_inter));
        h.extend(i16b(0)); // slice_end
        h.extend([0u8, 2]); // slice_code, xyzt_units (mm)
        for _ in 0..4 {
            h.extend(f32b(0.0)); // cal_max, cal_min, slice_duration, toffset
        }
        h.extend(i32b(0));
        h.extend(i32b(0)); // glmax, glmin
        h.extend([0u8; 80 + 24]); // descrip, aux_file
        h.extend(i16b(self.qform_code));
        h.extend(i16b(self.sform_code));
        for q in self.quatern {
            h.extend(f32b(q));
        }
        for row in self.srow {
            for v in row {
                h.extend(f32b(v));
            }
        }
        h.extend([0u8; 16]); // intent_name
        h.extend(self.magic);
        assert_eq!(h.len(), 348);
        h.extend([0u8; 4]); // no extensions
        if (352.0..1e5).contains(&self.vox_offset) {
            h.resize(self.vox_offset as usize, 0);
        }
        for &v in &self.values {
            match self.datatype {
                2 => h.push(v as u8),
                4 => h.extend(i16b(v as i16)),
                16 => h.extend(f32b(v as f32)),
                64 => h.extend(if be { v.to_be_bytes() } else { v.to_le_bytes() }),
                _ => h.extend(vec![0u8; self.element_size()]),
            }
        }
        h
    }
}

/// gzip with stored (uncompressed) deflate blocks: a valid `.gz` without a compressor.
fn gzip_stored(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 0xff];
    let chunks: Vec<&[u8]> = if data.is_empty() {
        vec![&[]]
    } else {
        data.chunks(65535).collect()
    };
    for (n, chunk) in chunks.iter().enumerate() {
        out.push((n + 1 == chunks.len()) as u8);
        let len = chunk.len() as u16;
        out.extend(len.to_le_bytes());
        out.extend((!len).to_le_bytes());
        out.extend(*chunk);
    }
    out.extend(crc32(data).to_le_bytes());
    out.extend((data.len() as u32).to_le_bytes());
    out
}

fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                0xedb8_8320 ^ (crc >> 1)
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

// ---------------------------------------------------------------------------------------------
// Tensors and checks.

/// Stored components (FSL order) of `R diag(l) R^T`.
fn fsl(t: DMat3) -> [f64; 6] {
    [
        t.x_axis.x, t.y_axis.x, t.z_axis.x, t.y_axis.y, t.z_axis.y, t.z_axis.z,
    ]
}

/// Stored components (NIfTI lower-triangle order: xx, yx, yy, zx, zy, zz).
fn nifti_order(t: DMat3) -> [f64; 6] {
    [
        t.x_axis.x, t.x_axis.y, t.y_axis.y, t.x_axis.z, t.y_axis.z, t.z_axis.z,
    ]
}

/// A smoothly varying, clearly anisotropic tensor with off-diagonal terms at every voxel.
fn varied(i: usize, j: usize, k: usize) -> DMat3 {
    let r = DMat3::from_euler(
        glam::EulerRot::ZYX,
        0.3 + 0.7 * i as f64,
        -0.2 + 0.5 * j as f64,
        0.1 + 0.9 * k as f64,
    );
    let l = DVec3::new(1.7e-3 + 1e-4 * i as f64, 0.5e-3 + 1e-4 * j as f64, 0.3e-3);
    r * DMat3::from_diagonal(l) * r.transpose()
}

fn diag(x: f64, y: f64, z: f64) -> [f64; 6] {
    [x, 0.0, 0.0, y, 0.0, z]
}

fn parse(bytes: &[u8], options: &LoadOptions) -> Loaded {
    loaded(parse_nifti(bytes, Path::new(FILE), options), bytes)
}

/// Expects a parse error naming `file` and `column` (never a line: `line` is 0) whose reason
/// contains every word.
fn assert_parse_err(
    result: ellipsoid_splat_loaders::Result<Loaded>,
    file: &Path,
    column: &str,
    words: &[&str],
) {
    parse_error(result, file, &[]).assert_at(0, column, words);
}

/// [`assert_parse_err`] for `bytes` with `options`.
fn assert_err_with(bytes: &[u8], options: &LoadOptions, column: &str, words: &[&str]) {
    assert_parse_err(
        parse_nifti(bytes, Path::new(FILE), options),
        Path::new(FILE),
        column,
        words,
    );
}

/// [`assert_parse_err`] for `bytes` with the default options.
fn assert_err(bytes: &[u8], column: &str, words: &[&str]) {
    assert_err_with(bytes, &LoadOptions::default(), column, words);
}

/// The world-space tensor `R diag(radii) R^T` of a glyph: comparable whatever the eigenvector
/// signs and order.
fn glyph_tensor(e: &Ellipsoid) -> DMat3 {
    e.axes() * DMat3::from_diagonal(e.radii) * e.axes().transpose()
}

fn same_glyphs(a: &Loaded, b: &Loaded, tol: f64) -> bool {
    a.scene.len() == b.scene.len()
        && a.scene
            .ellipsoids
            .iter()
            .zip(&b.scene.ellipsoids)
            .all(|(x, y)| {
                (x.center - y.center).abs().max_element() <= tol
                    && (glyph_tensor(x) - glyph_tensor(y))
                        .to_cols_array()
                        .iter()
                        .all(|d| d.abs() <= tol)
            })
}

/// The longest semi-axis of all glyphs.
fn largest_semi_axis(loaded: &Loaded) -> f64 {
    loaded
        .scene
        .ellipsoids
        .iter()
        .map(|e| e.radii.max_element())
        .fold(0.0, f64::max)
}

/// The unit direction of a glyph's longest axis.
fn long_axis(e: &Ellipsoid) -> DVec3 {
    let n = (0..3)
        .max_by(|&a, &b| e.radii[a].total_cmp(&e.radii[b]))
        .unwrap();
    e.axes().col(n)
}

/// Asserts that a glyph's longest axis is `axis` (either sign) to within `1 - |cos|` <= `tol`.
fn assert_long_axis(e: &Ellipsoid, axis: DVec3, tol: f64) {
    assert!(
        long_axis(e).dot(axis).abs() > 1.0 - tol,
        "{} vs {axis}",
        long_axis(e)
    );
}

fn small_volume() -> Nii {
    Nii::tensors([3, 2, 2], |i, j, k| fsl(varied(i, j, k)))
}

// ---------------------------------------------------------------------------------------------
// Malformed input.

#[test]
fn empty_file() {
    assert_err(&[], "file", &["empty file"]);
}

#[test]
fn not_a_nifti_file() {
    let random = Rng::new(7).bytes(1000);
    assert_err(&random, "sizeof_hdr", &["not a NIfTI-1 file", "348"]);
    assert_err(
        b"x,y,z\n1,2,3\n",
        "header",
        &["not a NIfTI-1 file", "12 bytes", "348-byte header"],
    );
    // A gzip file whose content is not NIfTI either.
    assert_err(&gzip_stored(&random), "sizeof_hdr", &["not a NIfTI-1 file"]);
    // Right size field, wrong magic.
    let mut nii = small_volume();
    nii.magic = *b"n+2\0";
    assert_err(
        &nii.bytes(),
        "magic",
        &["not a NIfTI-1 file", "n+2", "expected \"n+1\""],
    );
    nii.magic = *b"ni1\0";
    assert_err(
        &nii.bytes(),
        "magic",
        &[".hdr/.img pair", "single-file .nii"],
    );
    nii.magic = *b"n+1\0";
    nii.sizeof_hdr = 540;
    assert_err(&nii.bytes(), "sizeof_hdr", &["NIfTI-2"]);
}

#[test]
fn truncated_data() {
    let bytes = small_volume().bytes();
    assert_err(
        &bytes[..bytes.len() - 1],
        "data",
        &[
            "truncated",
            "288 bytes of voxel data (3x2x2x6 x FLOAT32) from offset 352",
            "639",
        ],
    );
    // Only the header.
    assert_err(&bytes[..352], "data", &["truncated", "only 352 bytes"]);
    // A gzip stream cut short.
    let gz = gzip_stored(&bytes);
    assert_err(
        &gz[..gz.len() - 40],
        "data",
        &[
            "truncated",
            "gzip stream ends early",
            "288 bytes of voxel data",
        ],
    );
    // A header declaring far more than a small gzip file can hold fails before inflating.
    let mut huge = small_volume();
    huge.dims = vec![1000, 1000, 20, 6];
    assert_err(
        &gzip_stored(&huge.bytes()),
        "data",
        &["truncated", "can hold at most"],
    );
    // Corrupt compressed data is named as such.
    let mut bad = gz.clone();
    let n = bad.len();
    bad[n - 20] ^= 0x55;
    assert_err(&bad, "gzip", &["corrupt gzip data", "checksum"]);
}

#[test]
fn wrong_dimensions() {
    let mut nii = small_volume();
    nii.dims = vec![3, 2, 2, 3];
    nii.values.truncate(36);
    assert_err(
        &nii.bytes(),
        "dim",
        &[
            "shape 3x2x2x3 is not a tensor volume",
            "XxYxZx6",
            "the last axis must hold the 6 tensor components, it has 3",
        ],
    );
    let mut nii = small_volume();
    nii.dims = vec![3, 2, 12];
    assert_err(
        &nii.bytes(),
        "dim",
        &["a 3-D volume (3x2x12) holds no tensors"],
    );
    let mut nii = small_volume();
    nii.dims = vec![3, 2, 2, 2, 6];
    assert_err(
        &nii.bytes(),
        "dim",
        &["shape 3x2x2x2x6", "XxYxZx1x6", "must have size 1"],
    );
    let mut nii = small_volume();
    nii.dims = vec![3, -2, 2, 6];
    assert_err(&nii.bytes(), "dim", &["dim[2] is -2", "must be positive"]);
    let mut nii = small_volume();
    nii.dims = vec![32767, 32767, 32767, 6];
    assert_err(
        &nii.bytes(),
        "dim",
        &[
            "32767x32767x32767x6 of FLOAT32 is too large",
            "1073741824 bytes",
        ],
    );
    let mut nii = small_volume();
    nii.vox_offset = 100.0;
    assert_err(
        &nii.bytes(),
        "vox_offset",
        &["vox_offset is 100", "at least 352"],
    );
}

#[test]
fn unsupported_datatype() {
    let mut nii = small_volume();
    nii.datatype = 32; // COMPLEX64
    assert_err(
        &nii.bytes(),
        "datatype",
        &[
            "unsupported datatype COMPLEX64 (code 32)",
            "FLOAT32",
            "FLOAT64",
        ],
    );
    nii.datatype = 4; // INT16
    assert_err(
        &nii.bytes(),
        "datatype",
        &["unsupported datatype INT16 (code 4)"],
    );
    nii.datatype = 17;
    assert_err(
        &nii.bytes(),
        "datatype",
        &["unsupported datatype code 17 (not a NIfTI datatype)"],
    );
}

#[test]
fn non_finite_tensor() {
    for bad in [f64::NAN, f64::INFINITY] {
        let nii = Nii::tensors([3, 2, 2], |i, j, k| {
            let mut t = fsl(varied(i, j, k));
            if (i, j, k) == (1, 0, 1) {
                t[4] = bad;
            }
            t
        });
        assert_err(
            &nii.bytes(),
            "voxel 1,0,1",
            &["non-finite component", "yz="],
        );
        let loaded = parse(&nii.bytes(), &skipping());
        assert_eq!((loaded.scene.len(), loaded.skipped), (11, 1));
    }
}

#[test]
fn non_positive_definite_tensor() {
    let nii = Nii::tensors([3, 2, 2], |i, j, k| {
        if (i, j, k) == (2, 1, 0) {
            diag(1e-3, -2e-4, 5e-4)
        } else {
            fsl(varied(i, j, k))
        }
    });
    assert_err(
        &nii.bytes(),
        "voxel 2,1,0",
        &["not positive definite", "-2.0000e-4", "yy=-2.0000e-4"],
    );
    let loaded = parse(&nii.bytes(), &skipping());
    assert_eq!((loaded.scene.len(), loaded.skipped), (11, 1));
    let note = loaded
        .notes
        .iter()
        .find(|n| n.starts_with("skipped"))
        .expect("a note on the skipped voxel");
    assert_contains(note, &["skipped 1 invalid voxel(s)", "voxel 2,1,0"]);
    // A singular tensor (zero eigenvalue) is not positive definite either.
    let nii = Nii::tensors([1, 1, 1], |_, _, _| diag(1e-3, 1e-3, 0.0));
    assert_err(&nii.bytes(), "voxel 0,0,0", &["not positive definite"]);
}

#[test]
fn glyph_dropped_at_scaling_leaves_the_right_origins() {
    // FLOAT64 for a dynamic range FLOAT32 cannot hold: voxel 3's 1e150 sets the volume's
    // scale, at which voxel 1's 1e-180 semi-axes underflow to 0 and it is dropped.
    let mut nii = Nii::tensors([4, 1, 1], |i, _, _| match i {
        0 => diag(2e-3, 0.5e-3, 0.3e-3),
        1 => diag(3e-180, 2e-180, 1e-180),
        2 => diag(1.2e-3, 1.2e-3, 0.2e-3),
        _ => diag(1e150, 0.2e150, 0.2e150),
    });
    nii.datatype = 64;
    assert_err(
        &nii.bytes(),
        "voxel 1,0,0",
        &["give no usable semi-axes at the volume's scale"],
    );
    let loaded = parse(&nii.bytes(), &skipping());
    assert_eq!((loaded.scene.len(), loaded.skipped), (3, 1));
    // The glyphs after the dropped one still name their own voxels.
    assert_eq!(
        loaded.origins,
        Origins::Voxels(vec![[0, 0, 0], [2, 0, 0], [3, 0, 0]])
    );
    assert_eq!(
        loaded.origins.describe(1).as_deref(),
        Some("voxel (i, j, k) = (2, 0, 0)")
    );
    // 1 mm voxels, no transform: a glyph's centre is its voxel index.
    let centres: Vec<f64> = loaded.scene.ellipsoids.iter().map(|e| e.center.x).collect();
    assert_eq!(centres, [0.0, 2.0, 3.0]);
}

#[test]
fn mask_of_a_different_grid() {
    let tensors = small_volume();
    let dir = TempDir::new("nifti-grid-mask");
    let mask_path = dir.write("mask.nii", Nii::mask([3, 2, 3], |_, _, _| true).bytes());
    let options = options(|o| o.mask = Some(mask_path.clone()));
    assert_parse_err(
        parse_nifti(&tensors.bytes(), Path::new(FILE), &options),
        &mask_path,
        "grid",
        &[
            "the mask's grid 3x2x3 differs from the tensor volume's 3x2x2",
            FILE,
        ],
    );
    // Same dimensions, shifted by a voxel.
    let rows = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ];
    let mut shifted = rows;
    shifted[0][3] = 1.0;
    let tensors = tensors.with_sform(rows);
    let shifted_mask = Nii::mask([3, 2, 2], |_, _, _| true).with_sform(shifted);
    dir.write("mask.nii", shifted_mask.bytes());
    assert_parse_err(
        parse_nifti(&tensors.bytes(), Path::new(FILE), &options),
        &mask_path,
        "grid",
        &["voxel-to-world transform", "differs"],
    );
    // A mask that is not a mask.
    dir.write("mask.nii", small_volume().bytes());
    assert_parse_err(
        parse_nifti(&tensors.bytes(), Path::new(FILE), &options),
        &mask_path,
        "dim",
        &["shape 3x2x2x6 is not a mask"],
    );
    // A missing mask file is an I/O error naming it.
    std::fs::remove_file(&mask_path).unwrap();
    assert_io_error(
        parse_nifti(&tensors.bytes(), Path::new(FILE), &options),
        &mask_path,
    );
}

#[test]
fn everything_filtered_out() {
    // All background.
    let nii = Nii::tensors([2, 2, 2], |_, _, _| [0.0; 6]);
    assert_err(
        &nii.bytes(),
        "volume",
        &["no glyphs left", "of 8 voxels, 0 kept, 8 background"],
    );
    // Isotropic tissue below the FA threshold.
    let nii = Nii::tensors([2, 2, 2], |i, _, _| {
        diag(1e-3, 1e-3, 1e-3 + 1e-5 * i as f64)
    });
    assert_err_with(
        &nii.bytes(),
        &options(|o| o.min_fa = 0.5),
        "volume",
        &["no glyphs left", "8 with FA < 0.5"],
    );
    // All invalid and skipped: the first one is named.
    let nii = Nii::tensors([2, 1, 1], |_, _, _| diag(-1e-3, 1e-3, 1e-3));
    assert_err_with(
        &nii.bytes(),
        &skipping(),
        "volume",
        &["no glyphs left", "2 invalid skipped", "voxel 0,0,0"],
    );
    // All masked.
    let dir = TempDir::new("nifti-empty-mask");
    let mask_path = dir.write("mask.nii", Nii::mask([3, 2, 2], |_, _, _| false).bytes());
    assert_err_with(
        &small_volume().bytes(),
        &options(|o| o.mask = Some(mask_path)),
        "volume",
        &["12 masked"],
    );
}

// ---------------------------------------------------------------------------------------------
// What the glyphs are.

#[test]
fn tensor_orders_agree_when_the_data_matches() {
    let written_fsl = Nii::tensors([3, 2, 2], |i, j, k| fsl(varied(i, j, k))).bytes();
    let written_nifti = Nii::tensors([3, 2, 2], |i, j, k| nifti_order(varied(i, j, k))).bytes();
    let fsl_options = LoadOptions::default();
    let nifti_options = options(|o| o.tensor_order = TensorOrder::Nifti);
    let a = parse(&written_fsl, &fsl_options);
    let b = parse(&written_nifti, &nifti_options);
    assert_eq!(a.scene.len(), 12);
    assert!(same_glyphs(&a, &b, 1e-9), "same tensors, same glyphs");
    // The glyphs are the tensors (scaled): the first voxel's tensor comes back.
    let largest = largest_semi_axis(&a);
    assert!((largest - 0.5).abs() < 1e-9, "largest semi-axis {largest}");
    let t0 = glyph_tensor(&a.scene.ellipsoids[0]);
    let v0 = varied(0, 0, 0);
    let trace = |m: DMat3| m.x_axis.x + m.y_axis.y + m.z_axis.z;
    let ratio = trace(t0) / trace(v0);
    for (x, y) in t0.to_cols_array().iter().zip(v0.to_cols_array()) {
        assert!((x - ratio * y).abs() < 1e-6 * ratio * 1e-3, "{t0} vs {v0}");
    }
    // Read in the wrong order, the same bytes are other tensors (some not even positive
    // definite).
    let c = parse(
        &written_fsl,
        &LoadOptions {
            skip_invalid: true,
            ..nifti_options.clone()
        },
    );
    assert!(!same_glyphs(&a, &c, 1e-3));
    let d = parse(
        &written_nifti,
        &LoadOptions {
            skip_invalid: true,
            ..fsl_options
        },
    );
    assert!(!same_glyphs(&b, &d, 1e-3));
}

#[test]
fn sform_places_and_rotates_glyphs() {
    // Voxel x -> world +y, voxel y -> world -x, 2 mm voxels, offset (10, 20, 30).
    let rows = [
        [0.0, -2.0, 0.0, 10.0],
        [2.0, 0.0, 0.0, 20.0],
        [0.0, 0.0, 2.0, 30.0],
    ];
    let nii = Nii::tensors([2, 3, 4], |_, _, _| diag(3e-3, 1e-3, 1e-3)).with_sform(rows);
    let loaded = parse(&nii.bytes(), &LoadOptions::default());
    assert_eq!(loaded.scene.len(), 24);
    // Voxel (1, 2, 3) is glyph 1 + 2 (2 + 3 3) and sits at (10 - 4, 20 + 2, 30 + 6).
    let e = &loaded.scene.ellipsoids[1 + 2 * (2 + 3 * 3)];
    assert_close(e.center, DVec3::new(6.0, 22.0, 36.0), 1e-9);
    // Elongated along voxel x, so along world y; largest semi-axis 0.5 x 2 mm.
    assert_long_axis(e, DVec3::Y, 1e-9);
    assert!((e.radii.max_element() - 1.0).abs() < 1e-9, "{}", e.radii);
    assert!(
        (e.radii.min_element() - 1.0 / 3.0).abs() < 1e-6,
        "{}",
        e.radii
    );
    assert!(
        loaded.notes[0].contains("sform (code 1)"),
        "{:?}",
        loaded.notes
    );

    // An oblique tensor turns with the grid: voxel direction (1, 1, 0) becomes world (-1, 1, 0),
    // both with the sform above and with a reflecting one (x flipped, as in radiological
    // storage), which mirrors the tensor too.
    let d = DVec3::new(1.0, 1.0, 0.0).normalize();
    let t = DMat3::from_diagonal(DVec3::splat(1e-3)) + 2e-3 * outer(d, d);
    let flipped = [
        [-2.0, 0.0, 0.0, 0.0],
        [0.0, 2.0, 0.0, 0.0],
        [0.0, 0.0, 2.0, 0.0],
    ];
    for sform in [rows, flipped] {
        let nii = Nii::tensors([1, 1, 1], |_, _, _| fsl(t)).with_sform(sform);
        let e = parse(&nii.bytes(), &LoadOptions::default())
            .scene
            .ellipsoids[0];
        assert_long_axis(&e, DVec3::new(-1.0, 1.0, 0.0).normalize(), 1e-9);
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[test]
fn qform_and_voxel_sizes_place_glyphs() {
    // 90 degrees about z: quaternion (cos 45, 0, 0, sin 45); voxels 2 x 3 x 4 mm, qfac -1.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let mut nii = Nii::tensors([2, 3, 4], |_, _, _| diag(3e-3, 1e-3, 1e-3));
    nii.qform_code = 1;
    nii.quatern = [0.0, 0.0, s, 5.0, 6.0, 7.0];
    nii.pixdim = [-1.0, 2.0, 3.0, 4.0, 1.0, 1.0, 1.0, 1.0];
    let loaded = parse(&nii.bytes(), &LoadOptions::default());
    let e = &loaded.scene.ellipsoids[1 + 2 * (2 + 3 * 3)];
    // R (2 * 1, 3 * 2, -4 * 3) + offset, with R (x, y, z) = (-y, x, z).
    assert_close(e.center, DVec3::new(5.0 - 6.0, 6.0 + 2.0, 7.0 - 12.0), 1e-5);
    assert_long_axis(e, DVec3::Y, 1e-6);
    // The largest eigenvalue is half the smallest edge, 2 mm.
    assert!((e.radii.max_element() - 1.0).abs() < 1e-6, "{}", e.radii);
    assert!(
        loaded.notes[0].contains("qform (code 1)"),
        "{:?}",
        loaded.notes
    );

    // The sform wins over the qform when both are set.
    let both = nii.clone().with_sform([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ]);
    let e = parse(&both.bytes(), &LoadOptions::default())
        .scene
        .ellipsoids[1 + 2 * (2 + 3 * 3)];
    assert_close(e.center, DVec3::new(1.0, 2.0, 3.0), 1e-9);
    assert_long_axis(&e, DVec3::X, 1e-9);

    // Neither: voxel sizes only, no offset.
    let mut plain = nii;
    plain.qform_code = 0;
    let loaded = parse(&plain.bytes(), &LoadOptions::default());
    let e = &loaded.scene.ellipsoids[1 + 2 * (2 + 3 * 3)];
    assert_close(e.center, DVec3::new(2.0, 6.0, 12.0), 1e-9);
    assert!(
        loaded.notes[0].contains("voxel sizes"),
        "{:?}",
        loaded.notes
    );

    // Non-positive voxel sizes cannot place anything.
    plain.pixdim[2] = 0.0;
    assert_err(
        &plain.bytes(),
        "pixdim",
        &["voxel sizes pixdim[1..4] must be finite and > 0"],
    );
    // A singular sform neither.
    let flat = small_volume().with_sform([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0],
    ]);
    assert_err(&flat.bytes(), "sform", &["degenerate"]);
}

#[test]
fn glyph_scale_filters_and_notes() {
    // Voxel (0,0,0) background, (1,0,0) isotropic, (2,0,0) linear, the rest planar.
    let nii = Nii::tensors([3, 2, 1], |i, j, _| match (i, j) {
        (0, 0) => [0.0; 6],
        (1, 0) => diag(1e-3, 1e-3, 1e-3),
        (2, 0) => diag(2e-3, 0.2e-3, 0.2e-3),
        _ => diag(1.2e-3, 1.2e-3, 0.2e-3),
    });
    let mut with_sizes = nii.clone();
    with_sizes.pixdim = [1.0, 2.5, 2.0, 3.0, 1.0, 1.0, 1.0, 1.0];
    let loaded = parse(&with_sizes.bytes(), &options(|o| o.glyph_scale = 0.8));
    assert_eq!(loaded.scene.len(), 5);
    // The largest eigenvalue, 2e-3, becomes 0.8 x 2 mm.
    let linear = &loaded.scene.ellipsoids[1];
    assert!(
        (linear.radii.max_element() - 1.6).abs() < 1e-9,
        "{}",
        linear.radii
    );
    assert!(
        (linear.radii.min_element() - 0.16).abs() < 1e-6,
        "{}",
        linear.radii
    );
    // Coloured by shape: linear red, isotropic blue, planar green.
    assert_eq!(loaded.scene.ellipsoids[0].color, [0.0, 0.0, 1.0]);
    assert_eq!(linear.color[0], 1.0);
    assert_eq!(loaded.scene.ellipsoids[2].color[1], 1.0);
    assert_contains(
        &loaded.notes.join("\n"),
        &[
            "5 glyphs",
            "of 6 voxels, 5 kept, 1 background (all-zero tensor), 0 with FA < 0, 0 masked",
            "eigenvalues x 8.000000e2",
            "the largest eigenvalue 2.000000e-3 becomes 1.600000 (0.8 x the smallest voxel edge \
             2.000000)",
        ],
    );

    // The FA threshold drops the isotropic voxel (FA 0) and keeps the others (FA > 0.7).
    let loaded = parse(&nii.bytes(), &options(|o| o.min_fa = 0.3));
    assert_eq!(loaded.scene.len(), 4);
    assert!(
        loaded.notes[0].contains("1 with FA < 0.3"),
        "{:?}",
        loaded.notes
    );

    // A mask leaves voxels out, counted as masked.
    let dir = TempDir::new("nifti-filter-mask");
    let mask_path = dir.write("mask.nii", Nii::mask([3, 2, 1], |i, _, _| i != 2).bytes());
    let loaded = parse(&nii.bytes(), &options(|o| o.mask = Some(mask_path)));
    assert_eq!(loaded.scene.len(), 3);
    assert!(loaded.notes[0].contains("2 masked"), "{:?}", loaded.notes);

    // Nonsense options are refused.
    for glyph_scale in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let result = parse_nifti(
            &nii.bytes(),
            Path::new(FILE),
            &options(|o| o.glyph_scale = glyph_scale),
        );
        assert!(
            matches!(&result, Err(Error::Invalid { what, .. }) if what == "glyph_scale"),
            "{result:?}"
        );
    }
}

#[test]
fn encodings_give_the_same_glyphs() {
    let reference_nii = Nii::tensors([3, 2, 2], |i, j, k| fsl(varied(i, j, k)));
    let reference = parse(&reference_nii.bytes(), &LoadOptions::default());
    let check = |nii: &Nii, what: &str| {
        let loaded = parse(&nii.bytes(), &LoadOptions::default());
        assert!(same_glyphs(&reference, &loaded, 1e-6), "{what}");
        let loaded = parse(&gzip_stored(&nii.bytes()), &LoadOptions::default());
        assert!(same_glyphs(&reference, &loaded, 1e-6), "{what}, gzipped");
    };
    check(&reference_nii, "float32");
    let mut nii = reference_nii.clone();
    nii.datatype = 64;
    check(&nii, "float64");
    nii.big_endian = true;
    check(&nii, "float64 big-endian");
    nii.datatype = 16;
    check(&nii, "float32 big-endian");
    let mut five = reference_nii.clone();
    five.dims = vec![3, 2, 2, 1, 6];
    check(&five, "5-D");
    let mut offset = reference_nii.clone();
    offset.vox_offset = 400.0;
    check(&offset, "vox_offset 400");
    // Scaled storage: true = stored x slope + inter, so the file holds (true - inter) / slope.
    let (slope, inter) = (2e-4f32, 1e-5f32);
    let mut scaled = reference_nii.clone();
    let stored: Vec<f64> = reference_nii
        .values
        .iter()
        .map(|&v| ((v as f32 - inter) / slope) as f64)
        .collect();
    scaled.values = stored;
    scaled.scl_slope = slope;
    scaled.scl_inter = inter;
    check(&scaled, "scl_slope and scl_inter");
    // Unset (zero) or non-finite slopes mean no scaling.
    let mut unset = reference_nii.clone();
    unset.scl_slope = f32::NAN;
    unset.scl_inter = 5.0;
    check(&unset, "NaN slope");
}

#[test]
fn symmatrix_intent_with_fsl_order_gets_a_note() {
    // xz == yy: the same tensor in either order.
    let mut nii = Nii::tensors([2, 2, 2], |_, _, _| [2e-3, 0.0, 1e-3, 1e-3, 0.0, 2e-3]);
    nii.intent_code = 1005;
    let loaded = parse(&nii.bytes(), &LoadOptions::default());
    assert_note(&loaded.notes, "NIFTI_INTENT_SYMMATRIX");
    let loaded = parse(
        &nii.bytes(),
        &options(|o| o.tensor_order = TensorOrder::Nifti),
    );
    assert!(!loaded.notes.iter().any(|n| n.contains("SYMMATRIX")));
}

// ---------------------------------------------------------------------------------------------
// The sample and files on disk.

#[test]
fn sample_volume_loads() {
    let path = sample("dti.nii.gz");
    let start = Instant::now();
    let loaded = load_nifti(&path, &LoadOptions::default()).expect("the sample loads");
    eprintln!(
        "{}: {} glyphs in {:.1} ms",
        path.display(),
        loaded.scene.len(),
        start.elapsed().as_secs_f64() * 1e3
    );
    for note in &loaded.notes {
        eprintln!("  {note}");
    }
    let n = loaded.scene.len();
    assert!((1500..24 * 24 * 8).contains(&n), "{n} glyphs");
    assert_eq!(loaded.skipped, 0);
    // Centred near the origin, 2 mm apart, at most one voxel across.
    let (centre, radius) = loaded.scene.bounding_sphere().unwrap();
    assert!(centre.length() < 4.0 && radius < 40.0, "{centre} {radius}");
    let largest = largest_semi_axis(&loaded);
    assert!((largest - 1.0).abs() < 1e-3, "{largest}");
    assert!(loaded.notes[0].contains("24x24x8 grid placed by the sform"));
    // The FA threshold keeps the tracts: mostly linear (red) glyphs.
    let tracts = load_nifti(&path, &options(|o| o.min_fa = 0.3)).unwrap();
    let m = tracts.scene.len();
    assert!(m > 100 && m < n / 2, "{m} of {n}");
    let linear = tracts
        .scene
        .ellipsoids
        .iter()
        .filter(|e| e.color[0] == 1.0)
        .count();
    assert!(linear * 2 > m, "{linear} linear of {m}");
    // The sample's mask trims the rim.
    let masked = load_nifti(
        &path,
        &options(|o| o.mask = Some(sample("dti_mask.nii.gz"))),
    )
    .unwrap();
    assert!(masked.scene.len() < n && masked.scene.len() > n / 2);
    // Decompressed, the same volume gives the same glyphs.
    let gz = std::fs::read(&path).unwrap();
    let dir = TempDir::new("nifti-sample");
    let plain_path = dir.write("dti.nii", system_gunzip(&gz));
    let again = load_nifti(&plain_path, &LoadOptions::default()).unwrap();
    assert!(same_glyphs(&loaded, &again, 0.0));
    // Recompressed by the system's gzip (a file name in the gzip header, other block choices).
    for level in ["-1", "-6"] {
        let out = std::process::Command::new("gzip")
            .args([level, "-c"])
            .arg(&plain_path)
            .output()
            .expect(NEEDS_GZIP);
        assert!(out.status.success());
        let again = parse(&out.stdout, &LoadOptions::default());
        assert!(same_glyphs(&loaded, &again, 0.0), "gzip {level}");
    }
}

/// Glyphs of the sample against nibabel 5 + numpy (`img.affine @ (i, j, k, 1)`,
/// `R T R^T` with `R = U V^T` from the SVD of the affine's linear part, `eigh`): index among the
/// kept voxels, centre, long axis, eigenvalues.
#[test]
fn sample_matches_an_independent_reader() {
    let loaded = load_nifti(&sample("dti.nii.gz"), &LoadOptions::default()).unwrap();
    let largest_eigenvalue = 3.120228460588866e-3;
    let cases = [
        // On the arc.
        (
            999,
            [-14.25117, -5.45084, -1.48071],
            [-0.32149, -0.94344, -0.08104],
            [0.00029103, 0.00034151, 0.00176115],
        ),
        // In the tract through the slices.
        (
            1284,
            [13.09031, -10.93808, 0.04686],
            [0.15627, 0.06925, 0.98528],
            [0.00020254, 0.00035688, 0.00171518],
        ),
        // Tissue.
        (
            363,
            [-16.91538, -1.52395, -5.15243],
            [0.33016, -0.21037, 0.92019],
            [0.00063633, 0.0007416, 0.00092386],
        ),
    ];
    for (index, centre, axis, eigenvalues) in cases {
        let e = &loaded.scene.ellipsoids[index];
        assert_close(e.center, DVec3::from_array(centre), 1e-4);
        let axis = DVec3::from_array(axis);
        assert_long_axis(e, axis, 1e-4);
        let mut radii = e.radii.to_array();
        radii.sort_by(f64::total_cmp);
        for (r, l) in radii.iter().zip(eigenvalues) {
            let expected = l / largest_eigenvalue;
            assert!((r - expected).abs() < 2e-5, "{radii:?} vs {eigenvalues:?}");
        }
    }
}

/// The system's `gzip` checks the loader's inflater independently. It is on every Debian
/// machine (an essential package); without it these checks would pass without checking.
const NEEDS_GZIP: &str = "the system's gzip (on Debian: apt-get install gzip)";

/// `gz` decompressed by the system's `gzip`.
fn system_gunzip(gz: &[u8]) -> Vec<u8> {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let mut child = Command::new("gzip")
        .arg("-dc")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect(NEEDS_GZIP);
    child.stdin.take().unwrap().write_all(gz).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    out.stdout
}

#[test]
fn missing_file_is_an_io_error() {
    let path = TempDir::new("nifti-missing").path("does-not-exist.nii.gz");
    assert_io_error(load_nifti(&path, &LoadOptions::default()), &path);
}

// ---------------------------------------------------------------------------------------------
// Hostile input: errors, never panics, quickly.

#[test]
fn hostile_bytes_never_panic() {
    // NIFTI_FUZZ_ROUNDS=300000 for a longer run.
    let rounds: usize = std::env::var("NIFTI_FUZZ_ROUNDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(6000);
    let start = Instant::now();
    let options = LoadOptions::default();
    let plain = small_volume().bytes();
    let gz = gzip_stored(&plain);
    let sample_gz = std::fs::read(sample("dti.nii.gz")).unwrap();
    // Every prefix.
    for bytes in [&plain, &gz] {
        for cut in 0..bytes.len() {
            assert!(parse_nifti(&bytes[..cut], Path::new(FILE), &options).is_err());
        }
    }
    for cut in (0..sample_gz.len()).step_by(97) {
        assert!(parse_nifti(&sample_gz[..cut], Path::new(FILE), &options).is_err());
    }
    // Random corruption of valid files, the header fields above all.
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut outcomes = [0usize; 2];
    for round in 0..rounds {
        let base: &[u8] = match round % 3 {
            0 => &plain,
            1 => &gz,
            _ => &sample_gz[..sample_gz.len().min(4000 + round)],
        };
        let mut bytes = base.to_vec();
        for _ in 0..1 + rng.below(4) {
            let at = if rng.below(2) == 0 {
                rng.below(bytes.len().min(360))
            } else {
                rng.below(bytes.len())
            };
            bytes[at] = match rng.below(4) {
                0 => 0xff,
                1 => 0,
                2 => bytes[at] ^ (1 << rng.below(8)),
                _ => rng.byte(),
            };
        }
        let ok = parse_nifti(&bytes, Path::new(FILE), &options).is_ok();
        outcomes[ok as usize] += 1;
    }
    eprintln!(
        "corrupted inputs: {} refused, {} loaded",
        outcomes[0], outcomes[1]
    );
    // Headers with random values in every field that matters.
    for _ in 0..rounds / 2 {
        let mut nii = small_volume();
        nii.dims = (0..1 + rng.below(7))
            .map(|_| match rng.below(3) {
                0 => rng.next_u64() as i16,
                _ => 1 + rng.below(8) as i16,
            })
            .collect();
        nii.datatype = [2, 4, 16, 32, 64, 128, 1536, 2304, rng.next_u64() as i16][rng.below(9)];
        nii.vox_offset = [
            352.0,
            0.0,
            -1.0,
            1e30,
            f32::NAN,
            353.5,
            rng.below(1000) as f32,
        ][rng.below(7)];
        nii.sform_code = rng.below(3) as i16 - 1;
        nii.qform_code = rng.below(3) as i16 - 1;
        nii.srow = [[f32::from_bits(rng.next_u64() as u32); 4]; 3];
        nii.quatern = [f32::from_bits(rng.next_u64() as u32); 6];
        nii.pixdim[rng.below(4)] = f32::from_bits(rng.next_u64() as u32);
        nii.scl_slope = f32::from_bits(rng.next_u64() as u32);
        let bytes = nii.bytes();
        let _ = parse_nifti(&bytes, Path::new(FILE), &options);
        let _ = parse_nifti(&gzip_stored(&bytes), Path::new(FILE), &options);
    }
    // Pure noise, plain and behind a gzip magic.
    for _ in 0..rounds / 3 {
        let n = rng.below(2000);
        let mut bytes = rng.bytes(n);
        if rng.below(2) == 0 && bytes.len() >= 3 {
            bytes[..3].copy_from_slice(&[0x1f, 0x8b, 8]);
        }
        assert!(parse_nifti(&bytes, Path::new(FILE), &options).is_err());
    }
    let elapsed = start.elapsed();
    assert!(elapsed.as_secs_f64() < 0.01 * rounds as f64, "{elapsed:?}");
}

#[test]
fn absurd_sizes_are_refused_without_allocating() {
    // 32767^2 x 8 x 6 float64 voxels claimed by a 352-byte file, plain and gzipped: refused by
    // arithmetic, immediately.
    let mut nii = small_volume();
    nii.dims = vec![32767, 32767, 8, 6];
    nii.datatype = 64;
    nii.values.clear();
    let start = Instant::now();
    assert_err(&nii.bytes(), "dim", &["too large"]);
    nii.dims = vec![4000, 4000, 1, 6];
    nii.datatype = 16;
    assert_err(
        &nii.bytes(),
        "data",
        &["truncated", "384000000 bytes of voxel data"],
    );
    assert_err(
        &gzip_stored(&nii.bytes()),
        "data",
        &["truncated", "can hold at most"],
    );
    assert!(start.elapsed().as_millis() < 500);
}

/// Why `nifti` inflates the file itself (its module documentation): the `nifti` crate's reader
/// takes a `.nii.gz` as one gzip member and stops where it ends, so a file of several members
/// (as `bgzip` writes, or files joined with `cat`) is cut short; this loader reads them all.
#[test]
fn gzip_members_after_the_first_are_read_where_the_nifti_crate_stops() {
    let bytes = small_volume().bytes();
    let mut members = gzip_stored(&bytes[..352]);
    members.extend(gzip_stored(&bytes[352..]));
    let dir = TempDir::new("nifti-members");
    let path = dir.write("tensors.nii.gz", &members);
    let ours = load_nifti(&path, &LoadOptions::default()).expect("both members are read");
    assert!(same_glyphs(
        &parse(&bytes, &LoadOptions::default()),
        &ours,
        0.0
    ));
    // The crate reads the same bytes as one member.
    let one = dir.write("one.nii.gz", gzip_stored(&bytes));
    assert!(nifti::ReaderOptions::new().read_file(&one).is_ok());
    let theirs = nifti::ReaderOptions::new().read_file(&path);
    assert!(
        theirs.is_err(),
        "the nifti crate read the second member too: the reason in the module docs is gone"
    );
}
