#!/usr/bin/env python3
"""Writes the synthetic diffusion tensor samples data/samples/dti.nii.gz and dti_mask.nii.gz.

Python 3 standard library only; the output is deterministic (fixed seed, gzip mtime 0), so
running it again reproduces the committed files byte for byte.

dti.nii.gz: a NIfTI-1 tensor volume as FSL's `dtifit --save_tensor` writes it -- 24x24x8x6
FLOAT32, components in FSL order (xx, xy, xz, yy, yz, zz) and in the voxel axes, 2 mm voxels,
units mm^2/s -- placed by an sform (and the same qform) that turns the grid 10 degrees about z
and 5 degrees about x and centres it near the world origin. Inside an elliptic "brain" (zero
background outside):
  - a curved tract: an arc of radius 8 voxels in the i-j plane, its tensors linear
    (1.7, 0.35, 0.3)e-3 along the arc's tangent;
  - a straight tract along j through the arc's top; where the two cross, the tensor is their
    mean, planar in the i-j plane;
  - a tract along k (through the slices), linear again;
  - two isotropic "ventricles" (free water, 3.0e-3);
  - elsewhere tissue of low anisotropy (0.9, 0.75, 0.65)e-3 with random orientations;
  - small noise on every component (every tensor stays positive definite).

dti_mask.nii.gz: the matching UINT8 mask (same grid and transforms), the brain shrunk by about
one voxel, so that `--mask` visibly trims the rim.

Usage: python3 scripts/make-sample-dti.py [output-directory]   (default: data/samples)
"""

import gzip
import math
import os
import random
import struct
import sys

NX, NY, NZ = 24, 24, 8
VOXEL = 2.0  # mm
SEED = 20240607

FIBRE = (1.7e-3, 0.35e-3, 0.30e-3)
TISSUE = (0.9e-3, 0.75e-3, 0.65e-3)
WATER = 3.0e-3
NOISE = 0.03e-3

ARC_CENTRE = (11.5, 6.0)
ARC_RADIUS = 8.0
TRACT_HALF_WIDTH = 1.0  # voxels either side of a tract's centre line


def rotation_z_then_x(az_deg, ax_deg):
    """R = Rx(ax) @ Rz(az), as a row-major 3x3 list."""
    cz, sz = math.cos(math.radians(az_deg)), math.sin(math.radians(az_deg))
    cx, sx = math.cos(math.radians(ax_deg)), math.sin(math.radians(ax_deg))
    rz = [[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]]
    rx = [[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]]
    return [[sum(rx[r][k] * rz[k][c] for k in range(3)) for c in range(3)] for r in range(3)]


def quaternion_bcd(m):
    """(b, c, d) of the unit quaternion (a >= 0) of the rotation matrix m."""
    a = 0.5 * math.sqrt(max(0.0, 1.0 + m[0][0] + m[1][1] + m[2][2]))
    b = (m[2][1] - m[1][2]) / (4.0 * a)
    c = (m[0][2] - m[2][0]) / (4.0 * a)
    d = (m[1][0] - m[0][1]) / (4.0 * a)
    return b, c, d


ROTATION = rotation_z_then_x(10.0, 5.0)
# World position of voxel (i, j, k) is ROTATION @ (VOXEL * (i, j, k)) + OFFSET; the grid's centre
# lands on the origin.
_centre = [VOXEL * (NX - 1) / 2, VOXEL * (NY - 1) / 2, VOXEL * (NZ - 1) / 2]
OFFSET = [-sum(ROTATION[r][k] * _centre[k] for k in range(3)) for r in range(3)]


def normalise(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def frame(e1):
    """A right-handed orthonormal frame whose first axis is e1."""
    e1 = normalise(e1)
    helper = [0.0, 0.0, 1.0] if abs(e1[2]) < 0.9 else [1.0, 0.0, 0.0]
    e2 = normalise(cross(helper, e1))
    e3 = cross(e1, e2)
    return e1, e2, e3


def tensor(axes, values):
    """sum_n values[n] axes[n] axes[n]^T as a 3x3 list."""
    return [
        [sum(values[n] * axes[n][r] * axes[n][c] for n in range(3)) for c in range(3)]
        for r in range(3)
    ]


def mean(t1, t2):
    return [[(t1[r][c] + t2[r][c]) / 2 for c in range(3)] for r in range(3)]


def random_direction(rng):
    while True:
        v = [rng.uniform(-1, 1) for _ in range(3)]
        n = sum(x * x for x in v)
        if 1e-6 < n <= 1.0:
            return normalise(v)


def brain_radius_factor(k):
    """The brain's in-plane half-size shrinks towards the top and bottom slices."""
    t = (k - (NZ - 1) / 2) / (NZ / 2 + 1.5)
    return math.sqrt(max(0.0, 1.0 - t * t))


def in_brain(i, j, k, shrink=0.0):
    f = brain_radius_factor(k)
    rx, ry = 11.2 * f - shrink, 10.6 * f - shrink
    if rx <= 0 or ry <= 0:
        return False
    return ((i - 11.5) / rx) ** 2 + ((j - 11.5) / ry) ** 2 <= 1.0


def voxel_tensor(i, j, k, rng):
    """The tensor at voxel (i, j, k) in voxel axes, or None for background."""
    if not in_brain(i, j, k):
        return None
    # Ventricles: free water.
    for ci, cj in ((6.5, 14.5), (16.5, 14.5)):
        if (i - ci) ** 2 + (j - cj) ** 2 <= 2.0 ** 2 and 2 <= k <= 5:
            return tensor(([1, 0, 0], [0, 1, 0], [0, 0, 1]), (WATER, WATER, WATER))
    fibres = []
    # Curved tract: the upper half of a circle in the i-j plane.
    di, dj = i - ARC_CENTRE[0], j - ARC_CENTRE[1]
    r = math.hypot(di, dj)
    if dj > -1.0 and abs(r - ARC_RADIUS) <= TRACT_HALF_WIDTH + 0.3 and 1 <= k <= 6:
        tangent = [-dj / r, di / r, 0.0]
        fibres.append(tensor(frame(tangent), FIBRE))
    # Straight tract along j through the arc's top.
    if abs(i - 11.5) <= TRACT_HALF_WIDTH and 3 <= j <= 20 and 2 <= k <= 5:
        fibres.append(tensor(frame([0.0, 1.0, 0.0]), FIBRE))
    # Tract through the slices.
    if (i - 17.0) ** 2 + (j - 5.0) ** 2 <= 1.6 ** 2:
        fibres.append(tensor(frame([0.15, 0.1, 1.0]), FIBRE))
    if len(fibres) == 1:
        return fibres[0]
    if len(fibres) >= 2:
        return mean(fibres[0], fibres[1])
    return tensor(frame(random_direction(rng)), TISSUE)


def header(dims, datatype, bitpix, intent_code, descrip):
    """A NIfTI-1 header (348 bytes, little-endian) with the sample's sform and qform."""
    dim = [len(dims)] + list(dims) + [1] * (7 - len(dims))
    pixdim = [1.0, VOXEL, VOXEL, VOXEL] + [1.0] * 4  # pixdim[0] = qfac = 1
    b, c, d = quaternion_bcd(ROTATION)
    srow = [[ROTATION[r][0] * VOXEL, ROTATION[r][1] * VOXEL, ROTATION[r][2] * VOXEL, OFFSET[r]]
            for r in range(3)]
    fields = struct.pack(
        "<i10s18sihBB8h3f4h8f3fhBB4f2i80s24s2h6f4f4f4f16s4s",
        348, b"", b"", 0, 0, b"r"[0], 0,
        *dim,
        0.0, 0.0, 0.0,
        intent_code, datatype, bitpix, 0,
        *pixdim,
        352.0, 1.0, 0.0,  # vox_offset, scl_slope (1 = identity), scl_inter
        0, 0, 2 | 8,  # slice_end, slice_code, xyzt_units: mm and s
        0.0, 0.0, 0.0, 0.0,
        0, 0,
        descrip.encode()[:79], b"",
        1, 1,  # qform_code, sform_code: scanner coordinates
        b, c, d, OFFSET[0], OFFSET[1], OFFSET[2],
        *srow[0], *srow[1], *srow[2],
        b"", b"n+1\0",
    )
    assert len(fields) == 348
    return fields + b"\0\0\0\0"  # no extensions


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.normpath(os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "data", "samples"))
    rng = random.Random(SEED)
    components = [[0.0] * (NX * NY * NZ) for _ in range(6)]
    mask = bytearray(NX * NY * NZ)
    for k in range(NZ):
        for j in range(NY):
            for i in range(NX):
                n = i + NX * (j + NY * k)
                t = voxel_tensor(i, j, k, rng)
                if t is None:
                    continue
                mask[n] = 1 if in_brain(i, j, k, shrink=1.0) else 0
                fsl = (t[0][0], t[0][1], t[0][2], t[1][1], t[1][2], t[2][2])
                for comp, value in enumerate(fsl):
                    components[comp][n] = value + rng.gauss(0.0, NOISE)
    data = b"".join(struct.pack("<%df" % len(c), *c) for c in components)
    volume = header((NX, NY, NZ, 6), 16, 32, 0,
                    "synthetic DTI sample (scripts/make-sample-dti.py)") + data
    mask_file = header((NX, NY, NZ), 2, 8, 0,
                       "synthetic DTI sample mask (scripts/make-sample-dti.py)") + bytes(mask)
    os.makedirs(out_dir, exist_ok=True)
    for name, content in (("dti.nii.gz", volume), ("dti_mask.nii.gz", mask_file)):
        path = os.path.join(out_dir, name)
        with open(path, "wb") as f:
            f.write(gzip.compress(content, compresslevel=9, mtime=0))
        print(f"{path}: {os.path.getsize(path)} bytes ({len(content)} uncompressed)")


if __name__ == "__main__":
    main()
