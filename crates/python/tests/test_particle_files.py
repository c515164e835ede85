"""Simulation files from Python: LAMMPS dumps and extended XYZ through ``load`` and
``load_frames`` (the same arrays as the Ellipsoid CSV of the same frame, every frame with its
timestep), column mapping, bad options and frames named, and ``from_ase`` reading an
``ase.Atoms``-like object as the extended-XYZ loader reads the file."""

import os

import numpy as np
import pytest

import ellipsoid_splat as es

HERE = os.path.dirname(os.path.abspath(__file__))
SAMPLES = os.path.abspath(os.path.join(HERE, "..", "..", "..", "data", "samples"))
LAMMPS = os.path.join(SAMPLES, "gay-berne.lammpstrj")
XYZ = os.path.join(SAMPLES, "gay-berne.extxyz")
CSV = os.path.join(SAMPLES, "gay-berne-frame1.csv")
FIELDS = ("centers", "radii", "rotations", "colors")


def assert_same_glyphs(a, b):
    for field in FIELDS:
        assert a[field].tobytes() == b[field].tobytes(), field


def test_the_first_frame_of_each_format_is_the_csvs():
    csv = es.load(CSV)
    assert len(csv["centers"]) == 240
    for path in (LAMMPS, XYZ):
        assert_same_glyphs(es.load(path), csv)
        assert_same_glyphs(es.load_frames(path)[0], csv)


def test_frames_iterate_index_and_carry_timesteps():
    dump, xyz = es.load_frames(LAMMPS), es.load_frames(XYZ)
    assert len(dump) == len(xyz) == 8
    frames = list(dump)
    assert [f["timestep"] for f in frames] == [500 * k for k in range(8)]
    for k, frame in enumerate(frames):
        # The dump's atoms come shuffled, the XYZ file's sorted: both load in id order.
        assert_same_glyphs(frame, xyz[k])
    assert_same_glyphs(dump[-1], frames[7])
    # The particles move: no two frames alike.
    assert frames[0]["centers"].tobytes() != frames[1]["centers"].tobytes()
    with pytest.raises(IndexError, match="8 frames"):
        dump[8]
    with pytest.raises(TypeError):
        dump["1"]
    # A single-frame format has one frame.
    assert len(es.load_frames(CSV)) == 1


def test_options_are_checked_and_columns_map(tmp_path):
    with pytest.raises(ValueError, match='unknown option "colour"'):
        es.load(LAMMPS, colour="shape")
    with pytest.raises(ValueError, match=r"type colour: entry 1 \(type 2\)"):
        es.load(LAMMPS, type_colors=[(0, 0, 1), (2, 0, 0)])
    # Type colours given replace the palette, cycling.
    blue = es.load(LAMMPS, type_colors=[(0.0, 0.0, 1.0)])
    assert (blue["colors"] == [0.0, 0.0, 1.0]).all()
    # Older LAMMPS builds name the shape columns after a compute: mapped by name.
    text = open(LAMMPS).read().split("ITEM: TIMESTEP")[1]
    renamed = "ITEM: TIMESTEP" + text.replace("shapex shapey shapez", "c_s[1] c_s[2] c_s[3]")
    path = tmp_path / "renamed.lammpstrj"
    path.write_text(renamed)
    with pytest.raises(ValueError, match="renamed.lammpstrj"):
        es.load(path)
    mapped = es.load(path, columns={"shapex": "c_s[1]", "shapey": "c_s[2]", "shapez": "c_s[3]"})
    assert_same_glyphs(mapped, es.load(CSV))


def test_a_bad_frame_is_named_when_reached(tmp_path):
    frames = open(LAMMPS).read().split("ITEM: TIMESTEP")
    # Frame 2's first atom line gets a non-number in its x column.
    lines = frames[2].split("\n")
    atoms = lines.index("ITEM: ATOMS id type x y z shapex shapey shapez quatw quati quatj quatk")
    fields = lines[atoms + 1].split()
    fields[2] = "x?"
    lines[atoms + 1] = " ".join(fields)
    frames[2] = "\n".join(lines)
    path = tmp_path / "bad.lammpstrj"
    path.write_text("ITEM: TIMESTEP".join(frames))
    opened = es.load_frames(path)
    assert len(opened) == 8
    opened[0]  # frame 1 is good
    with pytest.raises(ValueError, match=r"bad.lammpstrj:\d+:frame 2 \(timestep 500\), x"):
        opened[1]


class FakeAtoms:
    """What ``ase.io.read`` makes of an extended-XYZ file with OVITO's columns."""

    def __init__(self, positions, arrays):
        self.positions = positions
        self.arrays = arrays


def test_from_ase_reads_the_columns_as_the_xyz_loader_does():
    frame = es.load(XYZ)
    # The file's own columns, as ASE would hold them: OVITO's x, y, z, w order, types.
    lines = open(XYZ).read().split("\n")
    n = int(lines[0])
    rows = [line.split() for line in lines[2:2 + n]]
    columns = np.array([[float(v) for v in row[2:]] for row in rows])
    atoms = FakeAtoms(columns[:, 0:3], {
        "aspherical_shape": columns[:, 3:6],
        "orientation": columns[:, 6:10],
        "type": np.array([int(row[1]) for row in rows]),
    })
    glyphs = es.from_ase(atoms)
    np.testing.assert_allclose(glyphs["centers"], frame["centers"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(glyphs["radii"], frame["radii"], rtol=0, atol=0)
    # The loader normalises in float32, from_ase in float64: the same rotations to float32.
    np.testing.assert_allclose(glyphs["rotations"], frame["rotations"], rtol=0, atol=1e-6)
    np.testing.assert_array_equal(glyphs["colors"], frame["colors"])
    np.testing.assert_array_equal(es.type_colors([1, 2, 11]),
                                  es.TYPE_PALETTE[[0, 1, 0]])
    with pytest.raises(ValueError, match="integer"):
        es.type_colors([1.5])
