#!/usr/bin/env python3
"""Writes a small Gay-Berne-like trajectory in the three particle-file forms the loaders read:

    data/samples/gay-berne.lammpstrj     LAMMPS dump custom, 8 frames, atoms in shuffled order
    data/samples/gay-berne.extxyz        the same frames as extended XYZ, sorted by id
    data/samples/gay-berne-frame1.csv    frame 1 as Ellipsoid CSV, coloured by the default
                                         type palette

240 particles in a 20^3 box: 160 rods of type 1 (diameters 3:1:1) and 80 spheres of type 2
(diameter 1), each moving and turning a little per frame. Standard library only; run from any
directory:

    python3 scripts/make-md-samples.py

or, for a larger run at the same density (measurements; not committed),

    python3 scripts/make-md-samples.py --particles 8000 --frames 100 --out /tmp/md

Every number is written once as text and that same text goes into all three files: positions
with 2 decimals, quaternion components with 3 (not exactly unit: the loaders normalise), and
shapes whose halves are exact (LAMMPS holds diameters 3 and 1, extended XYZ and the CSV the
semi-axes 1.5 and 0.5). So the three files load to bit-identical scenes (the loaders' tests
check it).
"""

import argparse
import math
import pathlib
import random

OUT = pathlib.Path(__file__).resolve().parent.parent / "data" / "samples"
# The committed samples: two rods to a sphere, 240 particles in a box of side 20.
PARTICLES, FRAMES, BOX, STEPS = 240, 8, 20.0, 500
# TYPE_PALETTE's first two entries (crates/loaders/src/trajectory.rs), as exact decimals.
PALETTE = {1: ("0.125", "0.4375", "0.6875"), 2: ("1.0", "0.5", "0.0625")}


def unit_quaternion(rng):
    """A random rotation (w, x, y, z), uniform on the sphere of unit quaternions."""
    q = [rng.gauss(0, 1) for _ in range(4)]
    n = math.sqrt(sum(v * v for v in q))
    return [v / n for v in q]


def turn(q, rng, angle):
    """`q` followed by a small random rotation of about `angle` radians."""
    axis = [rng.gauss(0, 1) for _ in range(3)]
    n = math.sqrt(sum(v * v for v in axis))
    s = math.sin(angle / 2) / n
    w2, x2, y2, z2 = math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s
    w1, x1, y1, z1 = q
    r = [
        w2 * w1 - x2 * x1 - y2 * y1 - z2 * z1,
        w2 * x1 + x2 * w1 + y2 * z1 - z2 * y1,
        w2 * y1 - x2 * z1 + y2 * w1 + z2 * x1,
        w2 * z1 + x2 * y1 - y2 * x1 + z2 * w1,
    ]
    n = math.sqrt(sum(v * v for v in r))
    return [v / n for v in r]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--particles", type=int, default=PARTICLES)
    parser.add_argument("--frames", type=int, default=FRAMES)
    parser.add_argument("--out", type=pathlib.Path, default=OUT)
    args = parser.parse_args()
    rng = random.Random(2024)
    n = args.particles
    RODS = n * 2 // 3
    # The samples' density at any count (a whole number of units, as the samples' 20).
    BOX = float(round(20.0 * (n / PARTICLES) ** (1 / 3)))
    atoms = []
    for i in range(n):
        rod = i < RODS
        atoms.append({
            "id": i + 1,
            "type": 1 if rod else 2,
            "pos": [rng.uniform(1, BOX - 1) for _ in range(3)],
            "quat": unit_quaternion(rng) if rod else [1.0, 0.0, 0.0, 0.0],
            # (diameters, semi-axes) as text
            "shape": (("3", "1", "1"), ("1.5", "0.5", "0.5")) if rod
            else (("1", "1", "1"), ("0.5", "0.5", "0.5")),
        })
    dump, xyz, csv = [], [], []
    for frame in range(args.frames):
        if frame:
            for a in atoms:
                a["pos"] = [p + rng.uniform(-0.15, 0.15) for p in a["pos"]]
                if a["type"] == 1:
                    a["quat"] = turn(a["quat"], rng, 0.1)
        rows = []
        for a in atoms:
            pos = [f"{p:.2f}" for p in a["pos"]]
            # A negative zero would read back as -0.0 in every file alike, but keep it tidy.
            quat = [f"{q:.3f}".replace("-0.000", "0.000") for q in a["quat"]]
            rows.append((a, pos, quat))
        step = frame * STEPS
        dump.append(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{n}\n"
                    f"ITEM: BOX BOUNDS pp pp pp\n0 {BOX:g}\n0 {BOX:g}\n0 {BOX:g}\n"
                    "ITEM: ATOMS id type x y z shapex shapey shapez quatw quati quatj quatk\n")
        # LAMMPS writes atoms in the order its processors hold them: shuffle.
        shuffled = rows[:]
        rng.shuffle(shuffled)
        for a, pos, quat in shuffled:
            dump.append(" ".join([str(a["id"]), str(a["type"]), *pos, *a["shape"][0], *quat]) + "\n")
        xyz.append(f"{n}\nLattice=\"{BOX:g} 0 0 0 {BOX:g} 0 0 0 {BOX:g}\" "
                   "Properties=id:I:1:species:S:1:pos:R:3:aspherical_shape:R:3:orientation:R:4 "
                   f"Timestep={step} pbc=\"T T T\"\n")
        for a, pos, quat in rows:
            # OVITO's orientation order: x y z w.
            xyz.append(" ".join([str(a["id"]), str(a["type"]), *pos, *a["shape"][1],
                                 *quat[1:], quat[0]]) + "\n")
        if frame == 0:
            csv.append("# Frame 1 of gay-berne.lammpstrj (scripts/make-md-samples.py)\n")
            csv.append("x,y,z,rx,ry,rz,qw,qx,qy,qz,r,g,b\n")
            for a, pos, quat in rows:
                csv.append(",".join([*pos, *a["shape"][1], *quat, *PALETTE[a["type"]]]) + "\n")
    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    for name, text in [("gay-berne.lammpstrj", dump), ("gay-berne.extxyz", xyz),
                       ("gay-berne-frame1.csv", csv)]:
        (out / name).write_text("".join(text))
        print(f"{out / name}: {(out / name).stat().st_size} bytes")


if __name__ == "__main__":
    main()
