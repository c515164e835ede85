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

A thin layer over the Rust library (the native module ``_native``): this file checks and
shapes the arguments, the library renders (with the GIL released). Errors: ``ValueError`` for
shapes, dtypes and values (naming the argument), ``OSError`` for files, ``DeviceError`` (a
``RuntimeError``) for the Vulkan device.
"""

from __future__ import annotations

import os
from typing import Any, Optional, Sequence

import numpy as np

from . import _native
from ._native import DeviceError

__all__ = ["Renderer", "Frame", "load", "DeviceError", "NO_GLYPH", "PLANS"]

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


def _matrix(value: Any, name: str, cols: Optional[int], dims: int = 2) -> np.ndarray:
    """``value`` as a C-contiguous float64 array of ``dims`` dimensions, the last ``cols``
    long (no copy when it already is one). Raises ``ValueError`` naming ``name``."""
    try:
        array = np.asarray(value)
    except Exception as error:  # noqa: BLE001 - NumPy raises many kinds here
        raise ValueError(f"{name}: not an array ({error})") from None
    if array.dtype.kind not in "fiu" or array.dtype.kind == "f" and array.dtype.itemsize < 4:
        raise ValueError(f"{name} must hold numbers (float32, float64 or integers), not {array.dtype}")
    if array.ndim != dims or (cols is not None and array.shape[-1] != cols):
        want = ", ".join(["N"] + [str(c) for c in ([cols] if dims == 2 else [3, 3])])
        raise ValueError(f"{name} has shape {array.shape}, expected ({want})")
    array = np.ascontiguousarray(array, dtype=np.float64)
    if not np.isfinite(array).all():
        raise ValueError(f"{name} holds a value that is not finite")
    return array


def _vector(value: Any, name: str, length: int) -> list:
    array = _matrix(np.reshape(np.asarray(value, dtype=np.float64), (1, -1)), name, length)
    return [float(v) for v in array[0]]


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
        ID or, to a ``.png``, packed little-endian into RGBA8."""
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
            if what == "depth":
                floats = [("Z", self.depth.ravel().tolist())]
            elif what == "normal":
                floats = [(c, self.normal[..., k].ravel().tolist()) for k, c in enumerate("RGB")]
            else:
                floats = []
            uints = [("ID", self.id.ravel().tolist())] if what == "id" else []
            _native.write_exr(path, w, h, floats, uints)
            return
        with open(path, "wb") as file:
            file.write(data)


class Renderer:
    """A Vulkan renderer kept alive between calls.

    ``validation`` turns on the Khronos validation layer: any message it reports makes the
    upload or render that caused it raise ``DeviceError``. ``device`` picks a device by index
    or name (default: a real GPU, else lavapipe). ``plan`` is how each frame's path is chosen
    (one of ``PLANS``; every path draws the same picture)."""

    def __init__(self, validation: bool = False, device: Optional[str | int] = None, *,
                 plan: str = "measure") -> None:
        self._native = _native.Renderer(validation, None if device is None else str(device),
                                        _plan(plan))
        self._last: Optional[list] = None
        self._given: Optional[list] = None
        #: The Rust library's time for the last upload (building and uploading the glyphs), ms.
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
        (shape colours if omitted). Returns the glyph count."""
        c = _matrix(centers, "centers", 3)
        if c.shape[0] == 0:
            raise ValueError("centers is empty: nothing to render")
        if (radii is None) == (tensors is None):
            raise ValueError("give radii (with optional rotations) or tensors, not both or neither")
        n = c.shape[0]

        def rows(value: Any, name: str, cols: int) -> Optional[np.ndarray]:
            if value is None:
                return None
            array = _matrix(value, name, cols)
            if array.shape[0] != n:
                raise ValueError(f"{name} has {array.shape[0]} rows, centers has {n}")
            return array

        r = rows(radii, "radii", 3)
        q = rows(rotations, "rotations", 4)
        k = rows(colors, "colors", 3)
        t = None
        if tensors is not None:
            t = _matrix(tensors, "tensors", 3, dims=3)
            if t.shape != (n, 3, 3):
                raise ValueError(f"tensors has shape {t.shape}, expected ({n}, 3, 3)")
        if k is not None and ((k < 0).any() or (k > 1).any()):
            raise ValueError("colors must lie in [0, 1]")
        arrays = [c, r, q, k, t]

        def same(a: Optional[np.ndarray], b: Optional[np.ndarray]) -> bool:
            if a is None or b is None:
                return a is None and b is None
            # The first rows decide quickly for new glyphs; then every value.
            return a.shape == b.shape and np.array_equal(a[:16], b[:16]) and np.array_equal(a, b)

        if self._last is not None and all(same(a, b) for a, b in zip(arrays, self._last)):
            self.upload_ms = 0.0
            return n  # the same glyphs are on the GPU already
        count, self.upload_ms = self._native.upload(c, r, q, k, t)
        # A caller that passes the same array objects again may change them in place in
        # between: from then on a copy is kept to compare with. A caller with new arrays each
        # frame pays for no copy.
        given = [id(a) for a in (centers, radii, rotations, colors, tensors)]
        reused = given == self._given
        self._given = given
        self._last = [None if a is None else a.copy() for a in arrays] if reused else None
        return count

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
        color, depth, normal, ids, ms = self._native.render(
            None if eye is None else _vector(eye, "eye", 3),
            None if target is None else _vector(target, "target", 3),
            _vector(up, "up", 3), float(fov_y), k, pose, int(width), int(height),
            None if near is None else float(near), int(supersample))
        return Frame(color, depth, normal, ids, ms)

    def render(self, centers: Any, radii: Any = None, rotations: Any = None,
               colors: Any = None, *, tensors: Any = None, **camera: Any) -> Frame:
        """Uploads the glyphs, unless they equal the last upload's (compared value by value,
        so arrays changed in place are uploaded again), and renders them; the camera
        arguments are ``render_uploaded``'s."""
        self.upload(centers, radii, rotations, colors, tensors=tensors)
        return self.render_uploaded(**camera)


def load(path: "os.PathLike[str] | str", **options: Any) -> dict:
    """Loads a scene file (CSV, PLY, NIfTI, PDB/mmCIF) as the command-line tool does; returns
    ``centers``, ``radii``, ``rotations`` (w, x, y, z) and ``colors`` arrays, the loader's
    ``notes`` and the count of records ``skipped``. Options: ``skip_invalid``, ``sigma``,
    ``min_opacity``, ``tensor_order`` ('fsl' or 'nifti'), ``min_fa``, ``mask``,
    ``glyph_scale``, ``color`` ('file', 'shape', 'principal', 'principal-fa', 'uniform')."""
    return _native.load(os.fspath(path), **options)
