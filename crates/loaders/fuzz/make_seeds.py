#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets: the sample files in data/samples/ at the
repository root (large ones cut down) plus small hand-made edge cases per format. Standard
library only; the paths do not depend on the working directory.

    python3 crates/loaders/fuzz/make_seeds.py

Seeds are named `seed-*`, so re-running replaces them and leaves the files that `cargo fuzz`
added (named by their SHA-1) alone. `cargo fuzz cmin` may later drop seeds that add no coverage.
"""

import gzip
import hashlib
import pathlib
import re
import struct

FUZZ = pathlib.Path(__file__).resolve().parent
# crates/loaders/fuzz -> the repository root.
SAMPLES = FUZZ.parent.parent.parent / "data" / "samples"
CORPUS = FUZZ / "corpus"
# Sample files larger than this are cut down (PLY: fewer vertices) or skipped.
MAX_SEED = 64 * 1024


def write(target, name, data):
    if isinstance(data, str):
        data = data.encode()
    d = CORPUS / target
    d.mkdir(parents=True, exist_ok=True)
    (d / f"seed-{name}").write_bytes(data)


def truncations(target, name, data, cuts=(1, 2, 3)):
    """The first 1/4, 1/2 and 3/4 of `data` (truncated files)."""
    for k in cuts:
        write(target, f"{name}-trunc{k}of4", data[: len(data) * k // 4])


# ---------------------------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------------------------


def csv_seeds():
    for f in sorted(SAMPLES.glob("*.csv")):
        data = f.read_bytes()
        if len(data) <= MAX_SEED:
            write("csv", f"sample-{f.name}", data)
        else:
            lines = data.splitlines(keepends=True)
            write("csv", f"sample-{f.name}-head", b"".join(lines[:40]))
    quat = "x,y,z,rx,ry,rz,qw,qx,qy,qz\n"
    write("csv", "empty.csv", "")
    write("csv", "header-only.csv", quat)
    write("csv", "quat.csv", quat + "0,0,0,1,2,3,1,0,0,0\n1.5,-2,3e2,0.5,0.5,0.5,0.7071,0.7071,0,0\n")
    write(
        "csv",
        "quat-color.csv",
        "# comment line\nx,y,z,rx,ry,rz,qw,qx,qy,qz,r,g,b\n"
        "0,0,0,1,1,1,1,0,0,0,1,0,0\n# another\n1,1,1,2,1,1,0,0,0,1,0,0.5,1\n",
    )
    write(
        "csv",
        "tensor.csv",
        "txx,txy,txz,tyy,tyz,tzz,x,y,z\n4,1,0,3,0.5,2,0,0,0\n1,0,0,1,0,1,5,5,5\n",
    )
    write(
        "csv",
        "bom-quoted-crlf.csv",
        '\ufeff"x","y","z","rx","ry","rz","qw","qx","qy","qz"\r\n'
        ' 1 , 2 , 3 ,"1",1,1,1,0,0,0\r\n',
    )
    write("csv", "bad-values.csv", quat + "nan,0,0,1,1,1,1,0,0,0\n0,0,0,-1,1,1,1,0,0,0\n"
          "0,0,0,1,1,1,0,0,0,0\n0,0,0,inf,1,1,1,0,0,0\n0,0,0,1,1,1e400,1,0,0,0\n")
    write("csv", "bad-tensor.csv", "x,y,z,txx,txy,txz,tyy,tyz,tzz\n0,0,0,1,2,0,1,0,1\n"
          "0,0,0,-1,0,0,-1,0,-1\n")
    write("csv", "short-long-rows.csv", quat + "0,0,0,1,1,1\n0,0,0,1,1,1,1,0,0,0,9,9\n,,,,,,,,,\n")
    write("csv", "both-forms.csv", "x,y,z,rx,ry,rz,qw,qx,qy,qz,txx,txy,txz,tyy,tyz,tzz\n")
    write("csv", "duplicate-unknown.csv", "x,x,y,z,foo,rx,ry,rz,qw,qx,qy,qz\n")
    write("csv", "missing-center.csv", "y,z,rx,ry,rz,qw,qx,qy,qz\n1,1,1,1,1,1,0,0,0\n")
    write("csv", "unterminated-quote.csv", quat + '0,0,0,"1,1,1,1,0,0,0\n')
    write("csv", "comments-only.csv", "# nothing\n#\n\n")
    truncations("csv", "quat-color.csv", (CORPUS / "csv" / "seed-quat-color.csv").read_bytes())


# ---------------------------------------------------------------------------------------------
# PLY (3D Gaussian Splatting)
# ---------------------------------------------------------------------------------------------

SPLAT = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2", "opacity",
         "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]


def ply_header(fmt, count, props, extra=""):
    head = f"ply\nformat {fmt} 1.0\ncomment fuzz seed\nelement vertex {count}\n"
    head += "".join(f"property {t} {n}\n" for t, n in props)
    return (head + extra + "end_header\n").encode()


def splat_values(i):
    return [0.1 * i, -0.2 * i, 0.3, 0, 0, 0, 0.5, -0.25, 1.0, 2.0 - i,
            -2.0, -2.5, -3.0, 1.0, 0.1 * i, 0.0, 0.0]


def ply_seeds():
    for f in sorted(SAMPLES.glob("*.ply")):
        data = f.read_bytes()
        if len(data) <= MAX_SEED:
            write("ply", f"sample-{f.name}", data)
            continue
        # Keep the header and the first few vertices of a binary file.
        end = data.index(b"end_header\n") + len(b"end_header\n")
        header = data[:end].decode("ascii")
        m = re.search(r"element vertex (\d+)\n", header)
        props = header[m.end():].split("element")[0].count("property float")
        keep = 8
        header = header.replace(m.group(0), f"element vertex {keep}\n")
        write("ply", f"sample-{f.name}-{keep}v", header.encode() + data[end: end + keep * 4 * props])
    props = [("float", n) for n in SPLAT]
    rows = [splat_values(i) for i in range(4)]
    le = ply_header("binary_little_endian", 4, props) + b"".join(struct.pack("<17f", *r) for r in rows)
    be = ply_header("binary_big_endian", 4, props) + b"".join(struct.pack(">17f", *r) for r in rows)
    asc = ply_header("ascii", 4, props) + "".join(" ".join(f"{v:g}" for v in r) + "\n" for r in rows).encode()
    write("ply", "le.ply", le)
    write("ply", "be.ply", be)
    write("ply", "ascii.ply", asc)
    truncations("ply", "le.ply", le)
    write("ply", "empty.ply", "")
    write("ply", "magic-only.ply", "ply\n")
    write("ply", "header-no-end.ply", ply_header("ascii", 1, props)[: -len("end_header\n")])
    write("ply", "header-only.ply", ply_header("binary_little_endian", 1, props))
    write("ply", "zero-vertices.ply", ply_header("binary_little_endian", 0, props))
    write("ply", "huge-count.ply", ply_header("binary_little_endian", 4_000_000_000, props) + b"\0" * 68)
    write("ply", "no-vertex.ply", b"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n")
    # Other types, property order shuffled, extra properties and an element after the vertices.
    typed = [("double", "x"), ("float32", "y"), ("float", "z"), ("uchar", "red"), ("float", "opacity"),
             ("float", "rot_0"), ("float", "rot_1"), ("float", "rot_2"), ("float", "rot_3"),
             ("float", "scale_0"), ("float", "scale_1"), ("float", "scale_2"),
             ("float", "f_dc_0"), ("float", "f_dc_1"), ("float", "f_dc_2")]
    face = "element face 1\nproperty list uchar int vertex_indices\n"
    body = b""
    for i in range(2):
        body += struct.pack("<dffB", 1.0 * i, 2.0, 3.0, 200)
        body += struct.pack("<11f", 1.0, 1, 0, 0, 0, -1, -1, -1, 0.1, 0.2, 0.3)
    body += struct.pack("<Biii", 3, 0, 1, 1)
    write("ply", "typed-face.ply", ply_header("binary_little_endian", 2, typed, face) + body)
    asc_face = ply_header("ascii", 2, props, face) + b"".join(
        (" ".join(f"{v:g}" for v in r) + "\n").encode() for r in rows[:2]) + b"3 0 1 1\n"
    write("ply", "ascii-face.ply", asc_face)
    bad = [list(r) for r in rows[:3]]
    bad[0][0] = float("nan")
    bad[1][13:17] = [0, 0, 0, 0]
    bad[2][10] = float("inf")
    write("ply", "bad-values.ply", ply_header("binary_little_endian", 3, props)
          + b"".join(struct.pack("<17f", *r) for r in bad))
    write("ply", "ascii-short-rows.ply", ply_header("ascii", 3, props) + b"1 2 3\n\n1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18\nx\n")
    write("ply", "missing-props.ply", ply_header("binary_little_endian", 1, props[:5]) + b"\0" * 20)
    write("ply", "crlf.ply", asc.replace(b"\n", b"\r\n"))


# ---------------------------------------------------------------------------------------------
# NIfTI-1
# ---------------------------------------------------------------------------------------------


def nifti(dims, data, *, endian="<", datatype=16, vox_offset=352, intent=0, pixdim=(1, 1, 1, 1),
          qform=None, sform=None, slope=0.0, inter=0.0, magic=b"n+1\0"):
    """A single-file NIfTI-1 image: header, 4-byte extension flag, padding to vox_offset, data."""
    bitpix = {2: 8, 4: 16, 8: 32, 16: 32, 64: 64}[datatype]
    h = bytearray(348)
    e = endian
    struct.pack_into(e + "i", h, 0, 348)
    struct.pack_into(e + "8h", h, 40, len(dims), *dims, *([1] * (7 - len(dims))))
    struct.pack_into(e + "hhh", h, 68, intent, datatype, bitpix)
    qfac = -1.0 if qform and qform[0] < 0 else 1.0
    struct.pack_into(e + "8f", h, 76, qfac, *pixdim, 0, 0, 0)
    struct.pack_into(e + "3f", h, 108, float(vox_offset), slope, inter)
    h[148:148 + 10] = b"fuzz seed\0"
    if qform:
        struct.pack_into(e + "h", h, 252, 1)
        struct.pack_into(e + "6f", h, 256, *qform[1:])
    if sform:
        struct.pack_into(e + "h", h, 254, 2)
        struct.pack_into(e + "12f", h, 280, *sform)
    h[344:348] = magic
    fmt = {2: "B", 4: "h", 8: "i", 16: "f", 64: "d"}[datatype]
    body = struct.pack(e + f"{len(data)}{fmt}", *data)
    pad = b"\0" * max(0, int(vox_offset) - 348)
    return bytes(h) + pad + body


def tensor_volume(nx, ny, nz, tensors, five_d=True):
    """FSL order, component-major (the last axis is the slowest): data[c][k][j][i]."""
    n = nx * ny * nz
    data = []
    for c in range(6):
        data += [tensors[v % len(tensors)][c] for v in range(n)]
    dims = (nx, ny, nz, 1, 6) if five_d else (nx, ny, nz, 6)
    return dims, data


def nifti_seeds():
    for f in sorted(SAMPLES.glob("dti*.nii*")):
        data = f.read_bytes()
        raw = gzip.decompress(data) if f.name.endswith(".gz") else data
        if len(data) <= MAX_SEED:
            write("nifti", f"sample-{f.name}", data)
        # The gunzipped copy too (plain input takes other paths), even if somewhat larger.
        if f.name.endswith(".gz") and len(raw) <= 4 * MAX_SEED:
            write("nifti", f"sample-{f.name[:-3]}", raw)
    good = [(3e-3, 1e-4, 0, 1e-3, 0, 5e-4), (1e-3, 0, 0, 1e-3, 0, 1e-3), (0, 0, 0, 0, 0, 0),
            (2e-3, -5e-4, 1e-4, 1.5e-3, 2e-4, 4e-4)]
    dims, data = tensor_volume(2, 2, 1, good)
    v = nifti(dims, data, intent=1005)
    write("nifti", "f32-5d.nii", v)
    write("nifti", "f32-5d.nii.gz", gzip.compress(v, mtime=0))
    dims4, data4 = tensor_volume(2, 1, 1, good[:2], five_d=False)
    write("nifti", "f64-be-qform.nii", nifti(dims4, data4, endian=">", datatype=64,
                                             pixdim=(2, 2, 2.5, 1),
                                             qform=(-1, 0.0, 0.7071, 0.0, 10, -5, 3)))
    write("nifti", "f32-sform-slope.nii", nifti(dims4, data4, slope=2.0, inter=0.0,
                                                sform=(0, -1, 0, 5, 1, 0, 0, 6, 0, 0, 1.5, 7)))
    bad = [(1, 0, 0, 1, 0, -1), (float("nan"), 0, 0, 1, 0, 1), (1, 2, 0, 1, 0, 1)]
    dimsb, datab = tensor_volume(3, 1, 1, bad, five_d=False)
    write("nifti", "bad-tensors.nii", nifti(dimsb, datab))
    write("nifti", "int16-3d.nii", nifti((2, 2, 2), list(range(8)), datatype=4))
    write("nifti", "vox-offset-beyond.nii", nifti(dims4, data4, vox_offset=1 << 20)[:400])
    write("nifti", "huge-dims.nii", nifti((32767, 32767, 32767, 6), [], intent=1005) + b"\0" * 64)
    write("nifti", "huge-dims.nii.gz", gzip.compress(nifti((1000, 1000, 1000, 6), []) + b"\0" * 4096, mtime=0))
    write("nifti", "ni1-magic.nii", nifti(dims4, data4, magic=b"ni1\0"))
    write("nifti", "empty.nii", b"")
    write("nifti", "header-only.nii", v[:352])
    write("nifti", "short-header.nii", v[:200])
    truncations("nifti", "f32-5d.nii", v)
    gz = gzip.compress(v, mtime=0)
    truncations("nifti", "f32-5d.nii.gz", gz)
    write("nifti", "gzip-magic-only.nii.gz", gz[:3])
    write("nifti", "gzip-stored.nii.gz", gzip.compress(v, compresslevel=0, mtime=0))
    write("nifti", "gzip-two-members.nii.gz", gzip.compress(v[:200], mtime=0) + gzip.compress(v[200:], mtime=0))


# ---------------------------------------------------------------------------------------------
# PDB and mmCIF
# ---------------------------------------------------------------------------------------------

PDB_ATOMS = (
    "CRYST1    5.613    8.807   28.182  90.00  90.00  90.00 P 21 21 21    4          \n"
    "ATOM      1  N   GLY A   1       0.639   8.155  10.140  1.00  4.23           N  \n"
    "ANISOU    1  N   GLY A   1      479    457    671     69    103   -181       N  \n"
    "ATOM      2  CA  GLY A   1       2.129   8.155  10.140  1.00  3.10           C  \n"
    "ANISOU    2  CA  GLY A   1      479    289    411     26     34   -129       C  \n"
    "HETATM    3 FE   HEM A   2       1.000   1.000   1.000  1.00  3.10          FE2+\n"
    "ANISOU    3 FE   HEM A   2      200    200    200      0      0      0      FE  \n"
    "ATOM      4  O   GLY A   1       3.000   8.155  10.140  1.00  3.10           O  \n"
    "END\n"
)


def pdb_seeds():
    for f in sorted(SAMPLES.glob("*.pdb")) + sorted(SAMPLES.glob("*.ent")):
        data = f.read_bytes()
        if len(data) <= MAX_SEED:
            write("pdb", f"sample-{f.name}", data)
            truncations("pdb", f"sample-{f.name}", data, cuts=(2,))
    write("pdb", "small.pdb", PDB_ATOMS)
    write("pdb", "empty.pdb", "")
    write("pdb", "header-only.pdb", "HEADER    FUZZ SEED                               01-JAN-25   XXXX              \n")
    write("pdb", "anisou-without-atom.pdb", PDB_ATOMS.splitlines(True)[2])
    write("pdb", "not-definite.pdb",
          "ATOM      1  C   GLY A   1       0.000   0.000   0.000  1.00  4.23           C  \n"
          "ANISOU    1  C   GLY A   1     -479    457    671   9999    103   -181       C  \n")
    write("pdb", "models.pdb", "MODEL        1\n" + PDB_ATOMS.replace("END\n", "") + "ENDMDL\nMODEL        2\n"
          + PDB_ATOMS.replace("END\n", "") + "ENDMDL\nEND\n")
    write("pdb", "short-lines.pdb", "ATOM      1  N\nANISOU    1  N   GLY A   1      479\nATOM\n")
    write("pdb", "non-numeric.pdb", PDB_ATOMS.replace("479", "4x9").replace("8.155", "8.1.5"))
    write("pdb", "crlf-bom.pdb", b"\xef\xbb\xbf" + PDB_ATOMS.replace("\n", "\r\n").encode())
    write("pdb", "non-utf8.pdb", PDB_ATOMS.encode().replace(b"GLY", b"G\xffY", 1))


def cif_seeds():
    for f in sorted(SAMPLES.glob("*.cif")) + sorted(SAMPLES.glob("*.mmcif")):
        data = f.read_bytes()
        if len(data) <= MAX_SEED:
            write("mmcif", f"sample-{f.name}", data)
            truncations("mmcif", f"sample-{f.name}", data)
    small = (
        "data_FUZZ\n"
        "_cell.length_a 5.613\n_cell.length_b 8.807\n_cell.length_c 28.182\n"
        "_cell.angle_alpha 90\n_cell.angle_beta 90\n_cell.angle_gamma 90\n"
        "_symmetry.space_group_name_H-M 'P 1'\n"
        "loop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n"
        "_atom_site.label_atom_id\n_atom_site.label_comp_id\n_atom_site.label_asym_id\n"
        "_atom_site.label_seq_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n"
        "_atom_site.occupancy\n_atom_site.B_iso_or_equiv\n_atom_site.pdbx_PDB_model_num\n"
        "ATOM 1 N N GLY A 1 0.639 8.155 10.140 1.00 4.23 1\n"
        "ATOM 2 C CA GLY A 1 2.129 8.155 10.140 1.00 3.10 1\n"
        "HETATM 3 O \"O W\" HOH B . 1.0 1.0 1.0 1.00 3.10 1\n"
        "loop_\n_atom_site_anisotrop.id\n_atom_site_anisotrop.type_symbol\n"
        "_atom_site_anisotrop.U[1][1]\n_atom_site_anisotrop.U[2][2]\n_atom_site_anisotrop.U[3][3]\n"
        "_atom_site_anisotrop.U[1][2]\n_atom_site_anisotrop.U[1][3]\n_atom_site_anisotrop.U[2][3]\n"
        "1 N 0.0479 0.0457 0.0671 0.0069 0.0103 -0.0181\n"
        "2 C 0.0479 0.0289 0.0411 0.0026 0.0034 -0.0129\n"
        "3 O 0.01 0.02 0.02 0.005 0 0\n"
    )
    write("mmcif", "small.cif", small)
    write("mmcif", "empty.cif", "")
    write("mmcif", "data-only.cif", "data_X\n")
    write("mmcif", "atoms-no-anisotrop.cif", small.split("loop_\n_atom_site_anisotrop")[0])
    write("mmcif", "anisotrop-only.cif", "data_X\nloop_" + small.split("loop_")[2])
    write("mmcif", "semicolon-text.cif", "data_X\n_struct.title\n;\nmulti\nline\n;\n" + small[len("data_FUZZ\n"):])
    write("mmcif", "unknown-values.cif", small.replace("0.0457", "?").replace("2.129", "."))
    write("mmcif", "unterminated-quote.cif", "data_X\n_struct.title 'open\nloop_\n_atom_site.id\n1\n")
    write("mmcif", "two-blocks.cif", small + small.replace("data_FUZZ", "data_TWO"))
    write("mmcif", "bad-u.cif", small.replace("3 O 0.01 0.02 0.02 0.005", "3 O -0.01 0.02 0.02 0.5"))
    write("mmcif", "loop-count-mismatch.cif", small.replace("1 N 0.0479", "1 N", 1))


# ---------------------------------------------------------------------------------------------
# LAMMPS dump and extended XYZ
# ---------------------------------------------------------------------------------------------


def dump_frame(step, atoms, columns, box="ITEM: BOX BOUNDS pp pp pp\n0 10\n0 10\n0 10\n"):
    return (f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(atoms)}\n{box}"
            f"ITEM: ATOMS {columns}\n" + "".join(a + "\n" for a in atoms))


def lammps_seeds():
    for f in sorted(SAMPLES.glob("*.lammpstrj")):
        data = f.read_bytes()
        # The first two frames: the sample is larger than a seed should be.
        cut = data.split(b"ITEM: TIMESTEP")
        head = b"ITEM: TIMESTEP" + b"ITEM: TIMESTEP".join(cut[1:3])
        write("lammps", f"sample-{f.name}-2frames", head[:MAX_SEED])
        write("lammps", f"sample-{f.name}-2frames.gz", gzip.compress(head[:MAX_SEED], mtime=0))
    ell = "id type x y z shapex shapey shapez quatw quati quatj quatk"
    good = dump_frame(0, ["2 1 1 2 3 3 1 1 0.7071 0 0 0.7071", "1 2 4 4 4 1 1 1 1 0 0 0"], ell)
    write("lammps", "ellipsoids.lammpstrj", good)
    write("lammps", "two-frames.lammpstrj", good + good.replace("TIMESTEP\n0", "TIMESTEP\n100"))
    write("lammps", "units-time.lammpstrj", "ITEM: UNITS\nlj\nITEM: TIME\n0.5\n" + good)
    write("lammps", "spheres.lammpstrj", dump_frame(3, ["1 1 0 0 0 0.5", "2 1 1 1 1 0.25"],
                                                    "id type xu yu zu radius vx"))
    write("lammps", "diameter.lammpstrj", dump_frame(3, ["1 1 0 0 0 0.5"], "id type x y z diameter"))
    tri = "ITEM: BOX BOUNDS xy xz yz pp pp pp\n0 13 2\n2 11.5 -1\n-3 3 1.5\n"
    write("lammps", "triclinic-scaled.lammpstrj",
          dump_frame(1, ["1 1 0.5 0.5 0.5 1", "2 2 0 0 0 1"], "id type xs ys zs radius", tri))
    write("lammps", "c-shape.lammpstrj", dump_frame(0, ["1 1 0 0 0 2 1 1 1 0 0 0"],
          "id type x y z c_shape[1] c_shape[2] c_shape[3] c_orient[1] c_orient[2] c_orient[3] c_orient[4]"))
    write("lammps", "point-particles.lammpstrj", dump_frame(0, ["1 1 0 0 0 0 0 0 0.5", "2 1 0 0 0 0 0 0 0"],
          "id type x y z shapex shapey shapez radius"))
    write("lammps", "bad-values.lammpstrj", dump_frame(0, ["1 1 nan 0 0 3 1 1 1 0 0 0",
          "2 1 0 0 0 -3 1 1 1 0 0 0", "3 1 0 0 0 3 1 1 0 0 0 0", "4 x 0 0 0 3 1 1 1 0 0 0",
          "5 1 0 0", "5 1 0 0 0 1e400 1 1 1 0 0 0"], ell))
    write("lammps", "duplicate-ids.lammpstrj", dump_frame(0, ["1 1 0 0 0 1", "1 1 0 0 0 1"], "id type x y z radius"))
    write("lammps", "huge-count.lammpstrj", good.replace("ATOMS\n2\n", "ATOMS\n99999999999\n"))
    write("lammps", "no-size.lammpstrj", dump_frame(0, ["1 1 0 0 0"], "id type x y z"))
    write("lammps", "empty.lammpstrj", "")
    write("lammps", "timestep-only.lammpstrj", "ITEM: TIMESTEP\n")
    truncations("lammps", "ellipsoids.lammpstrj", good.encode())
    gz = gzip.compress(good.encode(), mtime=0)
    write("lammps", "ellipsoids.lammpstrj.gz", gz)
    write("lammps", "ellipsoids-cut.lammpstrj.gz", gz[: len(gz) // 2])


def xyz_seeds():
    for f in sorted(SAMPLES.glob("*.extxyz")) + sorted(SAMPLES.glob("*.xyz")):
        data = f.read_bytes()
        lines = data.splitlines(keepends=True)
        n = int(lines[0])
        head = b"".join(lines[: 2 * (n + 2)])
        write("xyz", f"sample-{f.name}-2frames", head[:MAX_SEED])
    props = "Properties=id:I:1:species:S:1:pos:R:3:aspherical_shape:R:3:orientation:R:4"
    good = (f'2\nLattice="10 0 0 0 10 0 0 0 10" {props} Timestep=5 pbc="T T T"\n'
            "2 A 1 2 3 1.5 0.5 0.5 0 0 0.7071 0.7071\n1 B 4 4 4 0.5 0.5 0.5 0 0 0 1\n")
    write("xyz", "ellipsoids.extxyz", good)
    write("xyz", "two-frames.extxyz", good + "\n" + good.replace("Timestep=5", "time=10"))
    write("xyz", "spheres.xyz", "2\nProperties=species:I:1:pos:R:3:radius:R:1:color:R:3:forces:R:3\n"
          "1 0 0 0 0.5 1 0 0 0 0 0\n2 1 1 1 0.25 0 1 0 0 0 0\n")
    write("xyz", "plain.xyz", "1\ncomment\nC 0 0 0\n")
    write("xyz", "bad-values.extxyz", good.replace("1 2 3 1.5", "nan 2 3 -1.5").replace("0 0 0 1\n", "0 0 0 0\n"))
    write("xyz", "bad-properties.extxyz", good.replace("pos:R:3", "pos:R:x").replace("id:I:1", "id:Q:1"))
    write("xyz", "unterminated-quote.extxyz", '1\nLattice="1 0 0 Properties=pos:R:3:radius:R:1\n0 0 0 1\n')
    write("xyz", "huge-count.extxyz", "99999999999\nProperties=pos:R:3:radius:R:1\n0 0 0 1\n")
    write("xyz", "empty.extxyz", "")
    truncations("xyz", "ellipsoids.extxyz", good.encode())
    write("xyz", "ellipsoids.extxyz.gz", gzip.compress(good.encode(), mtime=0))


if __name__ == "__main__":
    csv_seeds()
    ply_seeds()
    nifti_seeds()
    pdb_seeds()
    cif_seeds()
    lammps_seeds()
    xyz_seeds()
    for d in sorted(CORPUS.iterdir()):
        # A fuzzer-named copy (its SHA-1) of a seed is a duplicate: keep the seed's name.
        seeds = {hashlib.sha1(f.read_bytes()).hexdigest() for f in d.glob("seed-*")}
        for f in d.iterdir():
            if f.name in seeds:
                f.unlink()
        files = list(d.iterdir())
        print(f"{d.name}: {len(files)} files, {sum(f.stat().st_size for f in files)} bytes")
