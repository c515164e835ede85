#!/usr/bin/env python3
"""Writes the 3D Gaussian Splatting sample scenes in data/samples/ (Python 3 standard library).

- splats.ply: binary little-endian with the full property set of the reference implementation
  (Kerbl et al. 2023: x,y,z, nx,ny,nz, f_dc_0..2, f_rest_0..44, opacity, scale_0..2, rot_0..3,
  all float32, 248 bytes per splat). A hue-coloured torus of flat splats tangent to its surface
  around a pale sphere, plus faint "floaters" (opacity below 0.05, as training leaves them) that
  --min-opacity removes. 3,032 splats, about 750 KB.
- splats_ascii.ply: ASCII, a few splats with a comment and a skipped `nx,ny,nz`: an axis triad
  (red x, green y, blue z) around a white centre, plus one nearly transparent splat.

The output is deterministic (fixed seed). Usage: scripts/make-sample-splats.py [OUTPUT_DIR]
"""

import colorsys
import math
import os
import random
import struct
import sys

SH_C0 = 0.28209479177387814
SIGMA = 2.0  # the loader's default: radii are 2 standard deviations

REFERENCE_PROPERTIES = (
    ["x", "y", "z", "nx", "ny", "nz"]
    + [f"f_dc_{i}" for i in range(3)]
    + [f"f_rest_{i}" for i in range(45)]
    + ["opacity"]
    + [f"scale_{i}" for i in range(3)]
    + [f"rot_{i}" for i in range(4)]
)


def quaternion_from_columns(a, b, c):
    """Unit quaternion (w, x, y, z) of the rotation whose columns are the axes a, b, c."""
    m00, m10, m20 = a
    m01, m11, m21 = b
    m02, m12, m22 = c
    trace = m00 + m11 + m22
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        return (0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s)
    if m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        return ((m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s)
    if m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        return ((m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s)
    s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
    return ((m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s)


def cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def logit(p):
    return math.log(p / (1.0 - p))


def splat(rng, center, axes, stds, rgb, opacity):
    """One record of the reference layout, as a dict of property values."""
    w, x, y, z = quaternion_from_columns(*axes)
    # The reference stores unnormalised quaternions; scale by a random positive factor.
    k = rng.uniform(0.5, 2.0)
    record = {
        "x": center[0],
        "y": center[1],
        "z": center[2],
        "nx": 0.0,
        "ny": 0.0,
        "nz": 0.0,
        "opacity": logit(opacity),
        "rot_0": w * k,
        "rot_1": x * k,
        "rot_2": y * k,
        "rot_3": z * k,
    }
    for i in range(3):
        record[f"f_dc_{i}"] = (rgb[i] - 0.5) / SH_C0
        record[f"scale_{i}"] = math.log(stds[i])
    for i in range(45):
        record[f"f_rest_{i}"] = rng.gauss(0.0, 0.01)
    return record


def torus(rng, major=1.0, minor=0.35, around=64, across=38):
    out = []
    for i in range(around):
        for j in range(across):
            theta = 2 * math.pi * (i + rng.uniform(-0.15, 0.15)) / around
            phi = 2 * math.pi * (j + rng.uniform(-0.15, 0.15)) / across
            ring = major + minor * math.cos(phi)
            center = (ring * math.cos(theta), ring * math.sin(theta), minor * math.sin(phi))
            t1 = (-math.sin(theta), math.cos(theta), 0.0)
            t2 = (-math.sin(phi) * math.cos(theta), -math.sin(phi) * math.sin(theta), math.cos(phi))
            n = cross(t1, t2)
            stds = (
                0.36 * 2 * math.pi * ring / around,
                0.36 * 2 * math.pi * minor / across,
                0.004,
            )
            hue = (theta / (2 * math.pi)) % 1.0
            rgb = colorsys.hsv_to_rgb(hue, 0.75, 0.95)
            out.append(splat(rng, center, (t1, t2, n), stds, rgb, rng.uniform(0.85, 0.99)))
    return out


def sphere(rng, radius=0.3, count=500):
    out = []
    golden = math.pi * (3 - math.sqrt(5))
    spacing = math.sqrt(4 * math.pi / count) * radius
    for i in range(count):
        z = 1 - 2 * (i + 0.5) / count
        r = math.sqrt(1 - z * z)
        n = (r * math.cos(golden * i), r * math.sin(golden * i), z)
        center = tuple(radius * c for c in n)
        helper = (0.0, 0.0, 1.0) if abs(n[2]) < 0.9 else (1.0, 0.0, 0.0)
        t1 = normalize(cross(helper, n))
        t2 = cross(n, t1)
        stds = (0.34 * spacing, 0.34 * spacing, 0.003)
        grey = 0.88 + 0.05 * rng.random()
        out.append(splat(rng, center, (t1, t2, n), stds, (grey, grey * 0.97, grey * 0.9), 0.95))
    return out


def floaters(rng, count=100):
    out = []
    for _ in range(count):
        center = (rng.uniform(-1.3, 1.3), rng.uniform(-1.3, 1.3), rng.uniform(-0.6, 0.6))
        axes = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        stds = tuple(rng.uniform(0.004, 0.015) for _ in range(3))
        grey = rng.uniform(0.3, 0.6)
        out.append(splat(rng, center, axes, stds, (grey, grey, grey), rng.uniform(0.005, 0.04)))
    return out


def write_binary(path, records):
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(records)}"]
    header += [f"property float {name}" for name in REFERENCE_PROPERTIES]
    header.append("end_header")
    pack = struct.Struct("<" + "f" * len(REFERENCE_PROPERTIES)).pack
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        for r in records:
            f.write(pack(*(r[name] for name in REFERENCE_PROPERTIES)))


def write_ascii(path):
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2", "opacity"]
    names += ["scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    half = math.sqrt(0.5)
    # (centre, log std devs, quaternion w,x,y,z, rgb, opacity): the local x axis is the long
    # one; rotations turn it onto the world y and z axes.
    rows = [
        ((0, 0, 0), (0.08, 0.08, 0.08), (1, 0, 0, 0), (0.95, 0.95, 0.95), 0.99),
        ((0.45, 0, 0), (0.25, 0.05, 0.05), (1, 0, 0, 0), (0.9, 0.15, 0.1), 0.95),
        ((0, 0.45, 0), (0.25, 0.05, 0.05), (half, 0, 0, half), (0.15, 0.8, 0.2), 0.95),
        ((0, 0, 0.45), (0.25, 0.05, 0.05), (half, 0, -half, 0), (0.15, 0.3, 0.95), 0.95),
        ((0.3, 0.3, 0.3), (0.06, 0.06, 0.06), (2, 0, 0, 0), (0.5, 0.5, 0.5), 0.01),
    ]
    lines = [
        "ply",
        "format ascii 1.0",
        "comment 3D Gaussian Splatting sample: an axis triad (red x, green y, blue z)",
        "comment written by scripts/make-sample-splats.py",
        f"element vertex {len(rows)}",
    ]
    lines += [f"property float {name}" for name in names]
    lines.append("end_header")
    for center, stds, q, rgb, opacity in rows:
        values = {"x": center[0], "y": center[1], "z": center[2], "nx": 0, "ny": 0, "nz": 0}
        values["opacity"] = logit(opacity)
        for i in range(3):
            values[f"f_dc_{i}"] = (rgb[i] - 0.5) / SH_C0
            values[f"scale_{i}"] = math.log(stds[i] / SIGMA)
        for i in range(4):
            values[f"rot_{i}"] = q[i]
        lines.append(" ".join(f"{values[name]:.6g}" for name in names))
    with open(path, "w", encoding="ascii", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "data", "samples"
    )
    os.makedirs(out_dir, exist_ok=True)
    rng = random.Random(2023)
    records = torus(rng) + sphere(rng) + floaters(rng)
    write_binary(os.path.join(out_dir, "splats.ply"), records)
    write_ascii(os.path.join(out_dir, "splats_ascii.ply"))
    print(f"wrote {len(records)} splats to {os.path.join(out_dir, 'splats.ply')}")
    print(f"wrote 5 splats to {os.path.join(out_dir, 'splats_ascii.ply')}")


if __name__ == "__main__":
    main()
