"""Exact ray-cast ellipsoids on Vulkan: NumPy arrays in, exact pictures out.

    import ellipsoid_splat as es
    r = es.Renderer()
    frame = r.render(centers, radii, rotations, colors, width=640, height=480)
    frame.color   # (H, W, 4) uint8, sRGB
    frame.depth   # (H, W) float32 view depth, +inf where nothing is hit
    frame.normal  # (H, W, 3) float32 world-space unit normal, 0 where nothing is hit
    frame.id      # (H, W) uint32 glyph index, 0xFFFFFFFF where nothing is hit

Each frame takes one of several exact paths (the draw, the compute splat, the visible-first
splat), which draw the same picture at different costs; by default the renderer times them on
its own frames and keeps the fastest (``plan``, ``last_plan``, ``plan_wisdom``).

Glyph arrays may be float64 or float32 (and integers, widened to float64): C-contiguous
float32 and float64 arrays reach the library as they are, without a copy. ``Renderer.update``
replaces some glyphs of the uploaded scene (their indices and any of their fields) without
uploading the rest again.

In situ over MPI (a package built with its ``mpi`` feature): ``Renderer.render_composited``
draws each process's own glyphs and gives the root the frame of all of them.

Threads: a ``Renderer`` may be used from any thread. Its calls run one at a time -- a call
waits, without holding the GIL, for the one another thread is making -- and ``render`` (upload
and draw) is one call, so threads drawing different scenes with one renderer each get their
own. The device works with the GIL released: other Python threads run meanwhile, and renderers
of their own in several threads render at once. ``upload_ms`` and ``last_plan`` describe the
renderer's last call, whichever thread made it.

A thin layer over the Rust library (the native module ``_native``): this file checks and
shapes the arguments, the library renders (with the GIL released). Errors: ``ValueError`` for
shapes, dtypes and values (naming the argument), ``OSError`` for files, ``DeviceError`` (a
``RuntimeError``) for the Vulkan device and for a failure inside the library (a bug: no Rust
panic reaches Python), after which that renderer raises ``PoisonedError`` (a ``DeviceError``)
on every call. Two subclasses of ``DeviceError`` name what a caller reacts to:
``OutOfMemoryError`` (the call changed nothing, the renderer stays usable) and
``DeviceLostError`` (make a new ``Renderer``); docs/python.md has the rules.
``OtherRankError`` (a ``RuntimeError``) is raised where another MPI process failed.
"""

from __future__ import annotations

import os
import threading
from typing import Any, Optional, Sequence

import numpy as np

from . import _native
from ._native import (DeviceError, DeviceLostError, OtherRankError, OutOfMemoryError,
                      PoisonedError)

__all__ = ["Renderer", "Frame", "Frames", "load", "load_frames", "from_ase", "type_colors",
           "TYPE_PALETTE", "DeviceError", "DeviceLostError", "OutOfMemoryError",
           "PoisonedError", "OtherRankError", "NO_GLYPH", "PLANS"]

#: The ``id`` of a pixel where no glyph is hit.
NO_GLYPH = 0xFFFFFFFF

#: How a renderer's frame plan may choose its path (``Renderer(plan=...)``): ``measure`` times
#: the paths that can serve a frame and keeps the fastest, ``estimate`` takes the first guess
#: from the scene's size on screen, and a path's name fixes that path wherever it can serve.
PLANS = ("measure", "estimate", "draw", "splat", "visible-first")


def _plan(value: Any) -> str:
    if not isinstance(value, str) or value not in PLANS:
        raise ValueError(f"plan must be one of {', '.join(map(repr, PLANS))}, got {value!r}")
    return value


_FLOATS = (np.dtype(np.float64), np.dtype(np.float32))


def _matrix(value: Any, name: str, cols: Optional[int], dims: int = 2,
            float32: bool = False) -> np.ndarray:
    """``value`` as a C-contiguous float64 array -- or, with ``float32``, float32 where it is
    float32 already -- of ``dims`` dimensions, the last ``cols`` long (no copy when it already
    is one). Raises ``ValueError`` naming ``name``."""
    try:
        array = np.asarray(value)
    except Exception as error:  # noqa: BLE001 - NumPy raises many kinds here
        raise ValueError(f"{name}: not an array ({error})") from None
    if array.dtype.kind not in "fiu" or array.dtype.kind == "f" and array.dtype.itemsize < 4:
        raise ValueError(f"{name} must hold numbers (float32, float64 or integers), not {array.dtype}")
    if array.ndim != dims or (cols is not None and array.shape[-1] != cols):
        want = ", ".join(["N"] + [str(c) for c in ([cols] if dims == 2 else [3, 3])])
        raise ValueError(f"{name} has shape {array.shape}, expected ({want})")
    keep = float32 and array.dtype in _FLOATS  # native byte order only
    array = np.ascontiguousarray(array, dtype=array.dtype if keep else np.float64)
    if not np.isfinite(array).all():
        raise ValueError(f"{name} holds a value that is not finite")
    return array


def _vector(value: Any, name: str, length: int) -> list:
    array = _matrix(np.reshape(np.asarray(value, dtype=np.float64), (1, -1)), name, length)
    return [float(v) for v in array[0]]


def _glyph_arrays(centers: Any, radii: Any, rotations: Any, colors: Any,
                  tensors: Any) -> list:
    """The glyph arrays as the native half takes them (centers, radii, rotations, colors,
    tensors; ``None`` where not given), checked as ``Renderer.upload`` documents."""
    c = _matrix(centers, "centers", 3, float32=True)
    if (radii is None) == (tensors is None):
        raise ValueError("give radii (with optional rotations) or tensors, not both or neither")
    n = c.shape[0]

    def rows(value: Any, name: str, cols: int) -> Optional[np.ndarray]:
        if value is None:
            return None
        array = _matrix(value, name, cols, float32=True)
        if array.shape[0] != n:
            raise ValueError(f"{name} has {array.shape[0]} rows, centers has {n}")
        return array

    r = rows(radii, "radii", 3)
    q = rows(rotations, "rotations", 4)
    k = rows(colors, "colors", 3)
    t = None
    if tensors is not None:
        t = _matrix(tensors, "tensors", 3, dims=3, float32=True)
        if t.shape != (n, 3, 3):
            raise ValueError(f"tensors has shape {t.shape}, expected ({n}, 3, 3)")
    if k is not None and ((k < 0).any() or (k > 1).any()):
        raise ValueError("colors must lie in [0, 1]")
    return [c, r, q, k, t]


def _camera_args(eye: Optional[Sequence[float]], target: Optional[Sequence[float]],
                 up: Sequence[float], fov_y: float, intrinsics: Any, world_to_camera: Any,
                 width: int, height: int, near: Optional[float], supersample: int) -> tuple:
    """The camera arguments as the native half takes them, checked as
    ``Renderer.render_uploaded`` documents."""
    for name, value in (("width", width), ("height", height)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
                or not 1 <= value <= 16384:
            raise ValueError(f"{name} must be an integer in 1..=16384, got {value!r}")
    if isinstance(fov_y, bool) or not isinstance(fov_y, (int, float, np.integer, np.floating)) \
            or not 0 < fov_y < 180:
        raise ValueError(f"fov_y must be in (0, 180) degrees, got {fov_y!r}")
    if (intrinsics is None) != (world_to_camera is None):
        raise ValueError("intrinsics and world_to_camera go together")
    if intrinsics is not None and (eye is not None or target is not None):
        raise ValueError("give eye/target or intrinsics/world_to_camera, not both")
    k = None if intrinsics is None else _matrix(intrinsics, "intrinsics", 3)
    pose = None if world_to_camera is None else _matrix(world_to_camera, "world_to_camera", 4)
    if k is not None and k.shape != (3, 3):
        raise ValueError(f"intrinsics has shape {k.shape}, expected (3, 3)")
    if pose is not None and pose.shape != (4, 4):
        raise ValueError(f"world_to_camera has shape {pose.shape}, expected (4, 4)")
    if isinstance(supersample, bool) or not isinstance(supersample, (int, np.integer)) \
            or not 1 <= supersample <= 8:
        raise ValueError(f"supersample must be an integer in 1..=8, got {supersample!r}")
    if width * supersample > 16384 or height * supersample > 16384:
        raise ValueError(f"supersample {supersample} makes the drawn image larger than 16384")
    if near is not None and (isinstance(near, bool) or not isinstance(
            near, (int, float, np.integer, np.floating)) or not (np.isfinite(near) and near > 0)):
        raise ValueError(f"near must be a positive number, got {near!r}")
    return (None if eye is None else _vector(eye, "eye", 3),
            None if target is None else _vector(target, "target", 3),
            _vector(up, "up", 3), float(fov_y), k, pose, int(width), int(height),
            None if near is None else float(near), int(supersample))


def _communicator_handle(comm: Any) -> int:
    """The Fortran handle of an mpi4py communicator (``py2f()``), or ``comm`` as one."""
    if isinstance(comm, (int, np.integer)) and not isinstance(comm, bool):
        handle = int(comm)
    elif callable(getattr(comm, "py2f", None)):
        handle = int(comm.py2f())
    else:
        raise TypeError("comm must be an mpi4py communicator or its Fortran handle (an int), "
                        f"not {type(comm).__name__}")
    if not -2**31 <= handle < 2**31:
        raise ValueError(f"communicator handle {handle} is not a C int")
    return handle


def _global_ids(value: Any, n: int) -> np.ndarray:
    """``value`` as (n,) uint32 global glyph indices (their order is checked where they are
    used)."""
    try:
        ids = np.asarray(value)
    except Exception as error:  # noqa: BLE001 - NumPy raises many kinds here
        raise ValueError(f"global_ids: not an array ({error})") from None
    if ids.shape != (n,):
        raise ValueError(f"global_ids has shape {ids.shape}, expected ({n},): one per glyph")
    if n == 0:
        return np.zeros(0, dtype=np.uint32)
    if ids.dtype.kind not in "iu":
        raise ValueError(f"global_ids must be integers, not {ids.dtype}")
    if ids.min() < 0 or ids.max() >= NO_GLYPH:
        raise ValueError(f"global_ids must lie in 0..{NO_GLYPH - 1} ({NO_GLYPH} marks no glyph)")
    return np.ascontiguousarray(ids, dtype=np.uint32)


class Frame:
    """One rendered frame: ``color``, ``depth``, ``normal`` and ``id`` arrays, all H x W."""

    def __init__(self, color: np.ndarray, depth: np.ndarray, normal: np.ndarray,
                 id: np.ndarray, render_ms: float) -> None:  # noqa: A002 - the output's name
        self.color = color
        self.depth = depth
        self.normal = normal
        self.id = id
        #: The Rust library's time for the frame (render and read-back), in milliseconds.
        self.render_ms = render_ms

    @property
    def width(self) -> int:
        return int(self.color.shape[1])

    @property
    def height(self) -> int:
        return int(self.color.shape[0])

    def _repr_png_(self) -> bytes:
        """The colour as PNG bytes: a notebook shows the frame inline."""
        return _native.encode_png(self.color)

    def save(self, path: "os.PathLike[str] | str", what: str = "color") -> None:
        """Writes one output as the command-line tool does: ``color`` as PNG; ``depth``
        (channel Z) and ``normal`` (R, G, B) as float32 EXR; ``id`` as a 32-bit EXR channel
        ID or, to a ``.png``, packed little-endian into RGBA8. EXR is written from the arrays'
        buffers by the native writer (with the GIL released)."""
        path = os.fspath(path)
        ext = os.path.splitext(path)[1].lower()
        wants = {"color": (".png",), "depth": (".exr",), "normal": (".exr",), "id": (".exr", ".png")}
        if what not in wants:
            raise ValueError(f"what must be one of {sorted(wants)}, got {what!r}")
        if ext not in wants[what]:
            raise ValueError(f"{what} is written as {' or '.join(wants[what])}, not {ext or 'no extension'}")
        w, h = self.width, self.height
        if what == "color":
            data = self._repr_png_()
        elif what == "id" and ext == ".png":
            data = _native.encode_png(self.id.astype("<u4").view(np.uint8).reshape(h, w, 4))
        else:
            # Straight from the arrays: the native writer reads NumPy's buffers.
            if what == "depth":
                _native.write_exr_f32(path, ["Z"], np.asarray(self.depth, dtype=np.float32))
            elif what == "normal":
                _native.write_exr_f32(path, ["R", "G", "B"],
                                      np.asarray(self.normal, dtype=np.float32))
            else:
                _native.write_exr_u32(path, "ID", np.asarray(self.id, dtype=np.uint32))
            return
        # Whole or not at all: a hidden file beside the target, renamed over it when complete.
        directory, name = os.path.split(os.path.abspath(path))
        partial = os.path.join(directory, f".{name}.{os.getpid()}.partial")
        try:
            with open(partial, "xb") as file:
                file.write(data)
                file.flush()
                os.fsync(file.fileno())
            os.replace(partial, path)
        except BaseException:
            try:
                os.remove(partial)
            except OSError:
                pass
            raise


class Renderer:
    """A Vulkan renderer kept alive between calls.

    ``validation`` turns on the Khronos validation layer: any message it reports makes the
    upload or render that caused it raise ``DeviceError``. ``device`` picks a device by index
    or name (default: a real GPU, else lavapipe). ``plan`` is how each frame's path is chosen
    (one of ``PLANS``; every path draws the same picture).

    Any thread may use a renderer: its calls run one at a time (see the module's
    documentation); ``render`` uploads and draws as one call. The renderer keeps the uploaded
    glyphs (about 100 bytes each) for ``update``."""

    def __init__(self, validation: bool = False, device: Optional[str | int] = None, *,
                 plan: str = "measure") -> None:
        self._native = _native.Renderer(validation, None if device is None else str(device),
                                        _plan(plan))
        self._last: Optional[list] = None
        self._given: Optional[list] = None
        # Makes ``render`` (upload and draw) and the upload cache one call for other threads;
        # the native renderer has its own lock for each native call.
        self._lock = threading.RLock()
        #: The Rust library's time for the last upload or update (building and uploading the
        #: glyphs), ms.
        self.upload_ms = 0.0

    @property
    def device(self) -> str:
        """The Vulkan device's name."""
        return self._native.device

    @property
    def plan(self) -> str:
        """How each frame's path is chosen: one of ``PLANS``. Setting it keeps what the plan
        learned; a name not in ``PLANS`` raises ``ValueError`` and changes nothing."""
        return self._native.plan

    @plan.setter
    def plan(self, value: str) -> None:
        self._native.plan = _plan(value)

    @property
    def count(self) -> int:
        """How many glyphs are uploaded (0 before the first upload)."""
        return self._native.count

    @property
    def last_plan(self) -> Optional[dict]:
        """The plan of the last frame drawn (``None`` before the first), a dict:

        - ``path``: ``"draw"``, ``"splat"`` or ``"visible-first"``;
        - ``hidden``: what a splatted frame does about hidden glyphs -- ``"splat-all"``,
          ``"stamp-shown"`` (the visible-first splat's first frame, which stamps the
          glyphs it shows) or ``"visible-first"`` (those first, then the rest they do not
          hide); ``None`` for the draw;
        - ``reason``: why, as the library's sentence (``"measured: X ms against splat Y ms"``);
        - ``reason_kind``: ``"only"`` (no other path can serve the frame), ``"fixed"``,
          ``"estimated"``, ``"exploring"`` (a candidate being timed) or ``"measured"``;
        - ``measured_ms``: the path's median GPU time in milliseconds where measured, else
          ``None``; ``runner_up``, ``runner_up_ms``: the next fastest path and its time, or
          ``None``;
        - ``candidates``: the paths that could serve the frame."""
        return self._native.last_plan

    def plan_wisdom(self) -> bytes:
        """What the plan learned on this device: for each scene class it settled, the path
        it chose and the paths' times, keyed by the device, its driver build and pipeline-cache
        UUID. Save it and give it to ``load_plan_wisdom`` of a later renderer on the same
        device to skip the exploring."""
        return self._native.plan_wisdom()

    def load_plan_wisdom(self, data: "bytes | bytearray | memoryview") -> None:
        """Takes in ``plan_wisdom`` bytes of a renderer on the same device and driver build:
        the scene classes it settled are then planned as learned. Bytes from another device
        or driver, cut short or damaged raise ``ValueError`` saying which, and change
        nothing."""
        if not isinstance(data, (bytes, bytearray, memoryview)):
            raise TypeError(f"data must be bytes, not {type(data).__name__}")
        self._native.load_plan_wisdom(bytes(data))

    def upload(self, centers: Any, radii: Any = None, rotations: Any = None,
               colors: Any = None, *, tensors: Any = None) -> int:
        """Uploads the glyphs: ``centers`` (N, 3) with ``radii`` (N, 3) semi-axes and
        ``rotations`` (N, 4) unit quaternions (w, x, y, z; identity if omitted), or
        ``tensors`` (N, 3, 3) symmetric positive definite; ``colors`` (N, 3) in [0, 1]
        (shape colours if omitted). Each array may be float64 or float32 (the library reads
        C-contiguous ones where they are, without a copy), or integers. Returns the glyph
        count."""
        with self._lock:
            return self._upload(centers, radii, rotations, colors, tensors)

    def _upload(self, centers: Any, radii: Any, rotations: Any, colors: Any,
                tensors: Any) -> int:
        arrays = _glyph_arrays(centers, radii, rotations, colors, tensors)
        n = arrays[0].shape[0]
        if n == 0:
            raise ValueError("centers is empty: nothing to render")

        def same(a: Optional[np.ndarray], b: Optional[np.ndarray]) -> bool:
            if a is None or b is None:
                return a is None and b is None
            # The first rows decide quickly for new glyphs; then every value.
            return a.shape == b.shape and np.array_equal(a[:16], b[:16]) and np.array_equal(a, b)

        if self._last is not None and all(same(a, b) for a, b in zip(arrays, self._last)):
            self.upload_ms = 0.0
            return n  # the same glyphs are on the GPU already
        self._last = None  # compared again from the next successful upload on
        count, self.upload_ms = self._native.upload(*arrays)
        # A caller that passes the same array objects again may change them in place in
        # between: from then on a copy is kept to compare with. A caller with new arrays each
        # frame pays for no copy.
        given = [id(a) for a in (centers, radii, rotations, colors, tensors)]
        reused = given == self._given
        self._given = given
        self._last = [None if a is None else a.copy() for a in arrays] if reused else None
        return count

    def update(self, indices: Any, centers: Any = None, radii: Any = None,
               rotations: Any = None, colors: Any = None) -> None:
        """Replaces the glyphs at ``indices`` (integers, each an index of the uploaded scene,
        none twice, in any order) in the uploaded scene: each array given has one row per
        index -- ``centers`` (M, 3), ``radii`` (M, 3), ``rotations`` (M, 4), ``colors``
        (M, 3), float64 or float32 as for ``upload`` -- and replaces that field; the fields
        not given keep their values (a scene uploaded without colours keeps its shape
        colours). The indices are written as contiguous runs, without uploading the rest.
        A scene updated within its uploaded bounds and largest semi-axis draws exactly what
        uploading it whole draws (glyphs moved far outside them lose some float32
        precision). Raises
        ``ValueError`` naming the argument (and the glyph) for bad input, changing nothing."""
        with self._lock:
            self._update(indices, centers, radii, rotations, colors)

    def _update(self, indices: Any, centers: Any, radii: Any, rotations: Any,
                colors: Any) -> None:
        try:
            idx = np.asarray(indices)
        except Exception as error:  # noqa: BLE001 - NumPy raises many kinds here
            raise ValueError(f"indices: not an array ({error})") from None
        if idx.dtype.kind not in "iu" and not (idx.size == 0 and idx.dtype.kind == "f"):
            raise ValueError(f"indices must be integers, not {idx.dtype}")
        if idx.ndim > 1:
            raise ValueError(f"indices has shape {idx.shape}, expected (M,)")
        idx = idx.reshape(-1).astype(np.int64)
        m = len(idx)
        given = {name: value for name, value in (("centers", centers), ("radii", radii),
                                                  ("rotations", rotations), ("colors", colors))
                 if value is not None}
        if not given:
            raise ValueError("give at least one of centers, radii, rotations, colors")
        count = self._native.count
        if count == 0:
            raise ValueError("nothing uploaded: call upload first")
        arrays = {}
        for name, value in given.items():
            array = _matrix(value, name, 4 if name == "rotations" else 3, float32=True)
            if array.shape[0] != m:
                raise ValueError(f"{name} has {array.shape[0]} rows, indices has {m}")
            arrays[name] = array
        if "colors" in arrays and ((arrays["colors"] < 0).any() or (arrays["colors"] > 1).any()):
            raise ValueError("colors must lie in [0, 1]")
        if m == 0:
            return
        bad = (idx < 0) | (idx >= count)
        if bad.any():
            raise ValueError(f"indices: {idx[bad][0]} is out of range for the {count} glyphs "
                             "uploaded")
        if not (np.diff(idx) > 0).all():  # sort (rows with them), then refuse repeats
            order = np.argsort(idx, kind="stable")
            idx = idx[order]
            arrays = {name: np.ascontiguousarray(a[order]) for name, a in arrays.items()}
            repeated = np.flatnonzero(np.diff(idx) == 0)
            if len(repeated):
                raise ValueError(f"indices: {idx[repeated[0]]} appears more than once")
        # Contiguous runs: (first index, length).
        breaks = np.flatnonzero(np.diff(idx) != 1) + 1
        starts = np.concatenate(([0], breaks))
        lengths = np.diff(np.concatenate((starts, [m])))
        runs = list(zip(idx[starts].tolist(), lengths.tolist()))
        # The cache of the last upload no longer describes the scene.
        self._last = self._given = None
        self.upload_ms = self._native.update(runs, arrays.get("centers"), arrays.get("radii"),
                                             arrays.get("rotations"), arrays.get("colors"))

    def render_uploaded(self, *, eye: Optional[Sequence[float]] = None,
                        target: Optional[Sequence[float]] = None,
                        up: Sequence[float] = (0.0, 1.0, 0.0), fov_y: float = 45.0,
                        intrinsics: Any = None, world_to_camera: Any = None,
                        width: int = 640, height: int = 480,
                        near: Optional[float] = None, supersample: int = 1) -> Frame:
        """Renders the uploaded glyphs. The camera: ``eye``, ``target``, ``up`` and
        ``fov_y`` degrees (by default framing the glyphs), or ``intrinsics`` K (3, 3, pixels)
        with ``world_to_camera`` (4, 4, OpenCV axes: x right, y down, z forward) -- pixel
        (i, j)'s centre is at (i + 0.5, j + 0.5), as in COLMAP and gsplat (for a K calibrated
        with OpenCV's integer pixel centres, add 0.5 to cx and cy); ``near`` by
        default half the eye's distance to the glyphs' bounding sphere; ``supersample`` K
        (1 to 8) draws K x K samples per pixel and averages the colour in linear light (depth,
        normal and id come from one sample of each pixel)."""
        color, depth, normal, ids, ms = self._native.render(*_camera_args(
            eye, target, up, fov_y, intrinsics, world_to_camera, width, height, near,
            supersample))
        return Frame(color, depth, normal, ids, ms)

    def render(self, centers: Any, radii: Any = None, rotations: Any = None,
               colors: Any = None, *, tensors: Any = None, **camera: Any) -> Frame:
        """Uploads the glyphs, unless they equal the last upload's (compared value by value,
        so arrays changed in place are uploaded again), and renders them; the camera
        arguments are ``render_uploaded``'s. One call for other threads: no other thread's
        upload comes between the two."""
        with self._lock:
            self._upload(centers, radii, rotations, colors, tensors)
            return self.render_uploaded(**camera)

    def render_composited(self, comm: Any, centers: Any, radii: Any = None,
                          rotations: Any = None, colors: Any = None, *, global_ids: Any,
                          root: int = 0, tensors: Any = None,
                          eye: Optional[Sequence[float]] = None,
                          target: Optional[Sequence[float]] = None,
                          up: Sequence[float] = (0.0, 1.0, 0.0), fov_y: float = 45.0,
                          intrinsics: Any = None, world_to_camera: Any = None,
                          width: int = 640, height: int = 480, near: Optional[float] = None,
                          supersample: int = 1) -> Optional[Frame]:
        """In situ over MPI: every process of the communicator ``comm`` calls this with its
        own glyphs (``render``'s arrays; none is fine) and ``global_ids`` (N,), each glyph's
        index in the whole scene, strictly increasing (for glyphs numbered rank after rank:
        ``global_ids = (comm.exscan(n) or 0) + np.arange(n)``). The process of rank ``root``
        gets the frame of every process's glyphs -- exactly the frame one process drawing
        them all renders, ``id`` holding global indices -- and the others ``None``.

        The rules:

        - ``comm`` is an mpi4py communicator (its Fortran handle ``comm.py2f()`` is taken)
          or that handle as an int. It is borrowed, never freed; MPI is never initialised
          or finalised here (importing ``mpi4py.MPI`` does both).
        - Collective: every process of ``comm`` calls it, with the same ``root`` and the same
          camera, given in full -- ``eye`` and ``target`` (or ``intrinsics`` and
          ``world_to_camera``) and ``near``: a process sees only its share, so nothing can
          be framed by default. ``supersample`` K composites the K times larger image and
          filters it at the root.
        - A process whose arguments or drawing fail raises its own error and every other one
          ``OtherRankError`` naming the lowest failing rank: none waits for an image that
          will not come. (A ``comm`` that is not a communicator fails before any other process
          can be told.)
        - It uploads this process's glyphs: upload again before ``render_uploaded`` or
          ``update``.

        Needs the package built with the ``mpi`` feature (``maturin develop --features
        mpi``)."""
        handle = _communicator_handle(comm)
        if not hasattr(_native, "render_composited"):
            raise RuntimeError("this build of ellipsoid_splat has no MPI: build it with "
                               "maturin's --features mpi")
        with self._lock:
            try:
                arrays = _glyph_arrays(centers, radii, rotations, colors, tensors)
                ids = _global_ids(global_ids, arrays[0].shape[0])
                camera = _camera_args(eye, target, up, fov_y, intrinsics, world_to_camera,
                                      width, height, near, supersample)
                if isinstance(root, bool) or not isinstance(root, (int, np.integer)):
                    raise ValueError(f"root must be a rank (an integer), got {root!r}")
            except Exception:
                # The others learn that this process failed before any waits for it.
                _native.composite_failed(handle)
                raise
            # The upload cache no longer describes what the renderer holds.
            self._last = self._given = None
            out = _native.render_composited(self._native, handle, int(root), *arrays, ids,
                                            *camera)
        return None if out is None else Frame(*out)


_LOAD_OPTIONS_DOC = """Options: ``skip_invalid``, ``sigma``, ``min_opacity``,
    ``tensor_order`` ('fsl' or 'nifti'), ``min_fa``, ``mask``, ``glyph_scale``, ``color``
    ('file', 'shape', 'principal', 'principal-fa', 'uniform'), and for particle files
    ``columns`` (``{standard name: the file's column}``, e.g. ``{"shapex": "c_shape[1]"}``, as
    the tool's ``--columns``) and ``type_colors`` (a list of ``(r, g, b)`` for types 1, 2, ...;
    default ``TYPE_PALETTE``)."""


def load(path: "os.PathLike[str] | str", **options: Any) -> dict:
    """Loads a scene file (CSV, PLY, NIfTI, PDB/mmCIF, LAMMPS dump, extended XYZ; of a
    trajectory, its first frame) as the command-line tool does; returns ``centers``,
    ``radii``, ``rotations`` (w, x, y, z) and ``colors`` arrays, the loader's ``notes`` and
    the count of records ``skipped``. Unknown options raise ``ValueError``."""
    return _native.load(os.fspath(path), options)


load.__doc__ += "\n\n    " + _LOAD_OPTIONS_DOC


class Frames:
    """The frames of a scene file (every frame of a LAMMPS dump or extended XYZ trajectory;
    one for the other formats), read once and parsed as each is asked for:

        for frame in es.load_frames("run.lammpstrj"):
            image = r.render(frame["centers"], frame["radii"], frame["rotations"],
                             frame["colors"])

    ``len(frames)``, ``frames[i]`` (negative indices count from the end) and iteration give
    dicts as ``load`` returns, with the frame's ``timestep`` (``None`` where the file gives
    none). A bad frame raises ``ValueError`` naming the file, frame, line and column when it
    is reached."""

    def __init__(self, native: Any) -> None:
        self._native = native

    def __len__(self) -> int:
        return len(self._native)

    def __getitem__(self, index: int) -> dict:
        if isinstance(index, bool) or not isinstance(index, (int, np.integer)):
            raise TypeError(f"frame indices are integers, not {type(index).__name__}")
        n = len(self._native)
        if not -n <= index < n:
            raise IndexError(f"frame {index} is out of range: the file has {n} frames")
        return self._native.frame(int(index) % n)

    def __iter__(self):
        for index in range(len(self._native)):
            yield self._native.frame(index)


def load_frames(path: "os.PathLike[str] | str", **options: Any) -> Frames:
    """Opens a scene file for its frames (``Frames``); the options are ``load``'s."""
    return Frames(_native.load_frames(os.fspath(path), options))


#: The colours of particle types 1, 2, 3, ... (cycling) when a file or ``type_colors`` gives
#: none: the loaders' palette, each component a multiple of 1/16.
TYPE_PALETTE = np.array(_native.TYPE_PALETTE, dtype=np.float64)


def type_colors(types: Any, palette: Any = None) -> np.ndarray:
    """(N, 3) colours of integer particle ``types`` (1, 2, ...; cycling through ``palette``,
    default ``TYPE_PALETTE``), as the particle loaders colour them."""
    t = np.asarray(types)
    if t.ndim != 1 or t.dtype.kind not in "iu":
        raise ValueError(f"types must be a 1-D integer array, got {t.dtype} of shape {t.shape}")
    p = TYPE_PALETTE if palette is None else np.asarray(palette, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3 or len(p) == 0:
        raise ValueError(f"palette must have shape (K, 3), got {p.shape}")
    return p[(t.astype(np.int64) - 1) % len(p)]


def from_ase(atoms: Any, palette: Any = None) -> dict:
    """The glyphs of an ``ase.Atoms`` as ``render`` takes them (a dict of ``centers``,
    ``radii``, ``rotations``, ``colors``), from the arrays ASE keeps for an extended-XYZ file
    with OVITO's columns: ``atoms.arrays["aspherical_shape"]`` semi-axes (else ``"radius"``,
    else 0.5 for every atom), ``atoms.arrays["orientation"]`` quaternions in x, y, z, w order
    (normalised), colours by ``atoms.arrays["type"]`` if present, else by atomic number
    (``palette``, default ``TYPE_PALETTE``). For a file with integer types, shapes and
    orientations it gives the glyphs ``load`` gives (to rounding of the normalisation); the
    loader's other rules (a zero shape sized by its radius, species names numbered, an error
    where no size is given) are not repeated here. ASE itself is not imported: any object
    with ``positions`` and an ``arrays`` dict serves."""
    arrays = getattr(atoms, "arrays", {})
    centers = np.asarray(atoms.positions, dtype=np.float64)
    n = len(centers)
    if "aspherical_shape" in arrays:
        radii = np.asarray(arrays["aspherical_shape"], dtype=np.float64)
    elif "radius" in arrays:
        radii = np.repeat(np.asarray(arrays["radius"], dtype=np.float64).reshape(n, 1), 3, axis=1)
    else:
        radii = np.full((n, 3), 0.5)
    if "orientation" in arrays:
        xyzw = np.asarray(arrays["orientation"], dtype=np.float64)
        rotations = xyzw[:, [3, 0, 1, 2]]
        rotations = rotations / np.linalg.norm(rotations, axis=1, keepdims=True)
    else:
        rotations = np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
    types = arrays.get("type", arrays.get("numbers", np.ones(n, dtype=np.int64)))
    return {"centers": centers, "radii": radii, "rotations": rotations,
            "colors": type_colors(np.asarray(types).astype(np.int64), palette)}
