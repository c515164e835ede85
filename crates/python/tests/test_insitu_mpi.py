"""In situ over MPI from Python: examples/insitu_mpi.py under mpirun (mpi4py, Debian's Open
MPI) with 1, 2 and 3 processes composites frames bit-identical to the one its root draws
alone; a rank whose glyphs fail stops every rank with named errors, none left waiting; a
communicator of the wrong kind, or MPI not initialised, is a named error. Run by
scripts/test.sh with the package built with its ``mpi`` feature."""

import os
import subprocess
import sys

import pytest

import ellipsoid_splat as es

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "examples", "insitu_mpi.py")


def mpirun(ranks, *args):
    # Ended after two minutes: a rank left waiting would otherwise hang the test.
    command = ["timeout", "120", "mpirun", "--oversubscribe", "--allow-run-as-root", "-n",
               str(ranks), sys.executable, EXAMPLE, *args]
    done = subprocess.run(command, capture_output=True, text=True)
    assert done.returncode == 0, f"{ranks} ranks: exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return done.stdout


@pytest.mark.parametrize("ranks", [1, 2, 3])
def test_composited_frames_equal_one_process(ranks):
    out = mpirun(ranks)
    cases = [line for line in out.splitlines() if line.startswith("case ")]
    assert [line.split(":")[0] for line in cases] == ["case random", "case blocks"], out
    for line in cases:
        assert ": match, " in line, line


def test_a_failing_rank_stops_every_rank_with_named_errors():
    out = mpirun(3, "--fail-rank", "1")
    for kind, own in (("nan", "centers holds a value that is not finite"),
                      ("zero", "glyph 7: invalid ellipsoid radii"),
                      ("tiny", "do not fit float32")):
        for rank in range(3):
            prefix = f"rank {rank} stopped ({kind}): "
            lines = [line for line in out.splitlines() if line.startswith(prefix)]
            assert len(lines) == 1, f"no line of rank {rank} ({kind}):\n{out}"
            expected = own if rank == 1 else "rank 1 failed drawing its share"
            assert expected in lines[0], lines[0]


def test_a_wrong_communicator_or_mpi_not_initialised_is_a_named_error():
    # This process never initialises MPI (it does not import mpi4py.MPI).
    renderer = es.Renderer(validation=True)
    glyph = dict(centers=[[0.0, 0.0, 0.0]], radii=[[1.0, 1.0, 1.0]], global_ids=[0],
                 eye=(0.0, 0.0, 5.0), target=(0.0, 0.0, 0.0), near=1.0)
    with pytest.raises(TypeError, match="mpi4py communicator"):
        renderer.render_composited("world", **glyph)
    with pytest.raises(ValueError, match="MPI is not initialised"):
        renderer.render_composited(0, **glyph)
