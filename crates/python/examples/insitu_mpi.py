"""In situ from Python: an MPI application (mpi4py) whose processes each hold their own share
of the glyphs hands them, with its communicator, to ``Renderer.render_composited``, and the
root gets the frame of all of them -- no file written or read on the way.

    mpirun -n 3 python insitu_mpi.py
    mpirun -n 3 python insitu_mpi.py --fail-rank 1

Each rank makes the same scene (a seeded generator) and keeps its share. Two frames: the
glyphs split at random, composited over ``MPI.COMM_WORLD`` at rank 0; then each rank holding a
block of consecutive glyphs numbered by an exclusive scan, over a duplicate of the world the
application made (and frees afterwards: the library never frees a host's communicator),
composited at the last rank from float32 arrays with 2 x 2 supersampling. The root also draws
the whole scene alone and compares the frames bit for bit (colour, depth, normal, id),
printing ``case NAME: match, N pixels shown``; a mismatch exits with status 1. Validation is
on: any message raises.

With ``--fail-rank R`` rank R passes a glyph with a centre that is not a number (found by the
Python half), then one with a zero semi-axis (found building the glyphs), then one float32
cannot hold (found uploading them, as this rank draws): for each, every rank
must raise -- R its own ``ValueError``, the others ``OtherRankError`` naming R -- and the root
prints each rank's ``rank K stopped (KIND): MESSAGE``; a rank left waiting would keep mpirun
from ending.

Run by crates/python/tests/test_insitu_mpi.py.
"""

import sys

import numpy as np
from mpi4py import MPI  # initialises MPI, and finalises it at exit

import ellipsoid_splat as es

CAMERA = dict(eye=(4.0, 6.0, 30.0), target=(0.0, 0.0, 0.0), near=5.0, fov_y=45.0,
              width=160, height=120)


def scene(n):
    """``n`` glyphs in a cube of side 12, the same on every rank."""
    rng = np.random.default_rng(7)
    centers = rng.uniform(-6.0, 6.0, (n, 3))
    radii = rng.uniform(0.15, 0.6, (n, 3))
    rotations = rng.normal(size=(n, 4))
    rotations /= np.linalg.norm(rotations, axis=1, keepdims=True)
    colors = rng.uniform(0.0, 1.0, (n, 3))
    return centers, radii, rotations, colors


def same(a, b):
    """Whether two frames are the same, bit for bit."""
    return all(x.tobytes() == y.tobytes() for x, y in
               ((a.color, b.color), (a.depth, b.depth), (a.normal, b.normal), (a.id, b.id)))


def check(name, renderer, frame, glyphs, **camera):
    """At the root: the composited frame against the whole scene drawn alone."""
    alone = renderer.render(*glyphs, **camera)
    shown = int((alone.id != es.NO_GLYPH).sum())
    print(f"case {name}: {'match' if same(frame, alone) else 'MISMATCH'}, {shown} pixels shown",
          flush=True)
    return same(frame, alone) and shown > 0


def composited(renderer, world):
    rank, size = world.rank, world.size
    glyphs = scene(2000)
    ok = True

    # Split at random: each glyph's rank drawn from a seeded generator, its index its own.
    owner = np.random.default_rng(11).integers(0, size, len(glyphs[0]))
    mine = np.flatnonzero(owner == rank)
    frame = renderer.render_composited(world, *(a[mine] for a in glyphs), global_ids=mine,
                                       root=0, **CAMERA)
    if rank == 0:
        ok &= check("random", renderer, frame, glyphs, **CAMERA)
    elif frame is not None:
        raise AssertionError("a rank other than the root got a frame")

    # Blocks of consecutive glyphs, numbered rank after rank; an application's communicator.
    comm = world.Dup()
    n = len(glyphs[0])
    first, end = n * comm.rank // comm.size, n * (comm.rank + 1) // comm.size
    block = [a[first:end].astype(np.float32) for a in glyphs]
    ids = (comm.exscan(len(block[0])) or 0) + np.arange(len(block[0]))
    root = comm.size - 1
    frame = renderer.render_composited(comm, *block, global_ids=ids, root=root, supersample=2,
                                       **CAMERA)
    if comm.rank == root:
        whole = [a.astype(np.float32) for a in glyphs]
        ok &= check("blocks", renderer, frame, whole, supersample=2, **CAMERA)
    comm.Free()  # still the application's
    return ok


def failing(renderer, world, failing_rank):
    rank = world.rank
    centers, radii, rotations, colors = scene(100)
    ids = np.arange(100)
    lines = []
    for kind, field, value in (("nan", centers, np.nan), ("zero", radii, 0.0),
                               ("tiny", radii, 1e-50)):
        kept = field.copy()
        if rank == failing_rank:
            field[7, 1] = value
        try:
            renderer.render_composited(world, centers, radii, rotations, colors, global_ids=ids,
                                       **CAMERA)
            raise AssertionError(f"rank {rank}: the failing rank's error did not reach here")
        except (ValueError, es.OtherRankError) as error:
            expected = ValueError if rank == failing_rank else es.OtherRankError
            if type(error) is not expected:
                raise AssertionError(f"rank {rank} got the wrong error: {error!r}") from None
            lines.append(f"rank {rank} stopped ({kind}): {error}")
        field[:] = kept
    # MPI still works after the failures: the root prints every rank's lines, whole.
    every = world.gather(lines, root=0)
    if rank == 0:
        print("\n".join(line for mine in every for line in mine), flush=True)
    return True


def main():
    world = MPI.COMM_WORLD
    renderer = es.Renderer(validation=True)
    args = sys.argv[1:]
    if args[:1] == ["--fail-rank"]:
        ok = failing(renderer, world, int(args[1]))
    else:
        ok = composited(renderer, world)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
