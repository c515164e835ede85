"""Renderers used from several threads, float32 input read in place, partial updates and EXR
files read back. Run by scripts/test-python.sh (validation on: any message fails the call)."""

import struct
import threading
import tracemalloc

import numpy as np
import pytest

import ellipsoid_splat as es


def random_glyphs(n, seed):
    rng = np.random.default_rng(seed)
    centers = rng.uniform(-3, 3, (n, 3))
    radii = rng.uniform(0.1, 0.5, (n, 3))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    colors = rng.uniform(0, 1, (n, 3))
    return centers, radii, q, colors


def with_corners(centers, radii, q, colors):
    """Two large glyphs at opposite corners appended: they hold the scene's bounds and largest
    radius, so that updates inside keep the uploaded origin and radius scale."""
    corners = np.array([[-4.5] * 3, [4.5] * 3])
    return (np.vstack([centers, corners]), np.vstack([radii, np.full((2, 3), 0.9)]),
            np.vstack([q, [[1.0, 0, 0, 0]] * 2]), np.vstack([colors, [[0.5] * 3] * 2]))


def frame_bytes(frame):
    return [frame.color.tobytes(), frame.depth.tobytes(), frame.normal.tobytes(),
            frame.id.tobytes()]


def camera_of(k):
    angle = 0.7 * k
    return dict(eye=(9 * np.sin(angle), 1.0 + k, 9 * np.cos(angle)), target=(0.0, 0.0, 0.0),
                near=1.0, width=48, height=36)


FRAMES = 100


def test_threads_share_a_renderer_or_have_their_own_and_draw_the_single_threaded_frames():
    scenes = [random_glyphs(40, seed=20 + k) for k in range(4)]
    single = es.Renderer(validation=True)
    # Every path draws the same picture bit for bit on lavapipe; elsewhere one path is fixed.
    plan = "measure" if "llvmpipe" in single.device else "draw"
    single.plan = plan
    expected = [frame_bytes(single.render(*scenes[k], **camera_of(k))) for k in range(4)]
    for k in range(4):
        assert (np.frombuffer(expected[k][3], np.uint32) != es.NO_GLYPH).sum() > 200

    def run(renderer, k, failures, frames):
        try:
            for _ in range(FRAMES):
                # Each thread its own scene and camera: ``render`` uploads and draws as one call.
                frame = renderer.render(*scenes[k], **camera_of(k))
                frames[k].append(frame_bytes(frame) == expected[k])
        except BaseException as error:  # noqa: BLE001 - any failure of the thread is the test's
            failures.append(error)

    shared = es.Renderer(validation=True, plan=plan)
    own = [es.Renderer(validation=True, plan=plan) for _ in range(4)]
    for renderers in ([shared] * 4, own):
        failures, frames = [], [[] for _ in range(4)]
        threads = [threading.Thread(target=run, args=(renderers[k], k, failures, frames))
                   for k in range(4)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        assert failures == [], failures
        assert [len(f) for f in frames] == [FRAMES] * 4
        assert all(all(f) for f in frames), [f.count(False) for f in frames]
    # The renderer a thread made serves the thread that made none.
    done = []
    worker = threading.Thread(target=lambda: done.append(frame_bytes(
        single.render(*scenes[1], **camera_of(1)))))
    worker.start()
    worker.join()
    assert done == [expected[1]]
    assert issubclass(es.PoisonedError, es.DeviceError)


def test_float32_arrays_reach_the_library_uncopied_and_draw_the_float64_frame():
    r = es.Renderer(validation=True)
    c, rad, q, k = (a.astype(np.float32) for a in random_glyphs(300, seed=31))
    camera = dict(eye=(0.0, 2.0, 9.0), target=(0.0, 0.0, 0.0), near=1.0, width=80, height=60)
    f32 = r.render(c, rad, q, k, **camera)
    # The library read NumPy's own buffers: the addresses it saw are the arrays' data.
    assert r._native._upload_addresses == [a.__array_interface__["data"][0]
                                           for a in (c, rad, q, k)] + [0]
    f64 = r.render(*(a.astype(np.float64) for a in (c, rad, q, k)), **camera)
    assert (f32.id != es.NO_GLYPH).sum() > 1000
    assert frame_bytes(f32) == frame_bytes(f64)
    # Tensors too; a strided float32 array is copied once, to contiguous float32.
    t = np.ascontiguousarray(np.stack([np.diag(row) for row in rad]), dtype=np.float32)
    r.upload(c, tensors=t, colors=k)
    address = lambda a: a.__array_interface__["data"][0]  # noqa: E731
    assert r._native._upload_addresses == [address(c), 0, 0, address(k), address(t)]
    wide = np.zeros((300, 6), np.float32)
    wide[:, ::2] = c
    strided = r.render(wide[:, ::2], rad, q, k, **camera)
    assert frame_bytes(strided) == frame_bytes(f32)
    # The measure: a float32 upload allocates no float64 copy on the Python side (before, the
    # centres and radii were widened: 2 x 24 bytes a glyph).
    n = 200_000
    rng = np.random.default_rng(2)
    centers = rng.uniform(-20, 20, (n, 3)).astype(np.float32)
    radii = rng.uniform(0.01, 0.03, (n, 3)).astype(np.float32)
    tracemalloc.start()
    r.upload(centers, radii)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert r._native._upload_addresses[:2] == [centers.__array_interface__["data"][0],
                                               radii.__array_interface__["data"][0]]
    assert peak < 0.5 * centers.nbytes, f"{peak} bytes allocated for {centers.nbytes}-byte input"


def test_a_partial_update_draws_what_uploading_the_updated_scene_draws():
    camera = dict(eye=(1.0, 2.0, 11.0), target=(0.0, 0.0, 0.0), near=0.5, width=96, height=72)
    for shape_colors in (False, True):
        c, rad, q, k = with_corners(*random_glyphs(200, seed=41))
        r = es.Renderer(validation=True)
        r.upload(c, rad, q, None if shape_colors else k)
        before = r.render_uploaded(**camera)
        rng = np.random.default_rng(5)
        # Unsorted, in runs and alone; float32 and float64 rows.
        idx = np.array([150, 10, 11, 12, 99, 13, 160, 161, 162, 3, 199])
        new_c = (c[idx] * 0.8 + 0.1).astype(np.float32)
        new_r = rad[idx] * 0.7
        new_q = rng.normal(size=(len(idx), 4))
        c2, r2, q2, k2 = c.copy(), rad.copy(), q.copy(), k.copy()
        c2[idx], r2[idx], q2[idx] = new_c, new_r, new_q
        r.update(idx, centers=new_c, radii=new_r, rotations=new_q)
        colored = np.array([40, 41, 180])
        new_k = rng.uniform(0, 1, (3, 3))
        k2[colored] = new_k
        r.update(colored, colors=new_k)
        partial = r.render_uploaded(**camera)
        assert r.count == len(c)

        whole = es.Renderer(validation=True)
        if shape_colors:
            # A full upload without colours (shape colours from the new radii), then the
            # recoloured glyphs' colours.
            whole.upload(c2, r2, q2)
            whole.update(colored, colors=new_k)
        else:
            whole.upload(c2, r2, q2, k2)
        full = whole.render_uploaded(**camera)
        assert np.isin(full.id, idx).sum() > 50, "the updated glyphs are in view"
        assert frame_bytes(partial) != frame_bytes(before)
        assert frame_bytes(partial) == frame_bytes(full), shape_colors


def test_bad_updates_raise_naming_the_argument_and_change_nothing():
    c, rad, q, k = random_glyphs(20, seed=9)
    r = es.Renderer(validation=True)
    with pytest.raises(ValueError, match="upload"):
        r.update([0], colors=[[1.0, 0.0, 0.0]])
    camera = dict(eye=(0.0, 0.0, 9.0), target=(0.0, 0.0, 0.0), near=1.0, width=64, height=48)
    before = frame_bytes(r.render(c, rad, q, k, **camera))
    cases = [
        (dict(indices=[20], colors=[[1.0, 0, 0]]), "indices: 20 is out of range"),
        (dict(indices=[-1], colors=[[1.0, 0, 0]]), "indices: -1 is out of range"),
        (dict(indices=[3, 4, 3], colors=np.ones((3, 3))), "indices: 3 appears more than once"),
        (dict(indices=[1.0], colors=[[1.0, 0, 0]]), "indices must be integers"),
        (dict(indices=[[1, 2]], colors=np.ones((2, 3))), "indices has shape"),
        (dict(indices=["a"], colors=[[1.0, 0, 0]]), "indices must be integers"),
        (dict(indices=[1, 2], colors=[[1.0, 0, 0]]), "colors has 1 rows"),
        (dict(indices=[1], radii=[[1.0, 0.0, 1.0]]), "glyph 1"),
        (dict(indices=[1, 5], rotations=[[1.0, 0, 0, 0], [0, 0, 0, 0]]), "glyph 5"),
        (dict(indices=[1], centers=[[np.nan, 0, 0]]), "centers"),
        (dict(indices=[1], colors=[[2.0, 0, 0]]), "colors"),
        (dict(indices=[1], centers=[[1.0, 0]]), "centers has shape"),
        (dict(indices=[1]), "give at least one"),
    ]
    for kwargs, message in cases:
        with pytest.raises(ValueError, match=message):
            r.update(**kwargs)
    # Nothing changed (a rejected glyph leaves the others of its update alone too).
    assert frame_bytes(r.render_uploaded(**camera)) == before
    r.update([], colors=np.zeros((0, 3)))  # an empty update changes nothing
    assert frame_bytes(r.render_uploaded(**camera)) == before


def read_exr(path):
    """The channels of a single-part EXR file (scan lines or one-level tiles, uncompressed or
    RLE, 32-bit samples) as (H, W) arrays: a reader of the format's specification, apart from
    the writer."""
    data = open(path, "rb").read()
    assert data[:4] == b"\x76\x2f\x31\x01", "EXR magic"
    tiled = bool(struct.unpack_from("<I", data, 4)[0] & 0x200)
    pos, attributes = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        size = struct.unpack_from("<i", data, type_end + 1)[0]
        attributes[data[pos:name_end].decode()] = data[type_end + 5:type_end + 5 + size]
        pos = type_end + 5 + size
    pos += 1
    listed, channels, p = attributes["channels"], [], 0
    while listed[p] != 0:
        end = listed.index(b"\0", p)
        kind = struct.unpack_from("<i", listed, end + 1)[0]  # 0 uint, 1 half, 2 float
        assert kind in (0, 2)
        channels.append((listed[p:end].decode(), "<u4" if kind == 0 else "<f4"))
        p = end + 17  # type, pLinear and reserved, x and y sampling
    compression = attributes["compression"][0]
    assert compression in (0, 1), f"compression {compression}"
    x0, y0, x1, y1 = struct.unpack("<4i", attributes["dataWindow"])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    out = {name: np.zeros((height, width), dtype) for name, dtype in channels}
    if tiled:
        tw, th, mode = struct.unpack("<IIB", attributes["tiles"])
        assert mode & 0xF == 0, "one level"
        chunks = -(-width // tw) * -(-height // th)
    else:
        chunks = height
    for offset in struct.unpack_from(f"<{chunks}Q", data, pos):
        if tiled:
            tx, ty, _, _, size = struct.unpack_from("<5i", data, offset)
            raw, bx, by = data[offset + 20:offset + 20 + size], tx * tw, ty * th
            bw, bh = min(tw, width - bx), min(th, height - by)
        else:
            y, size = struct.unpack_from("<2i", data, offset)
            raw, bx, by, bw, bh = data[offset + 8:offset + 8 + size], 0, y - y0, width, 1
        n = bw * bh * 4 * len(channels)
        if compression == 1 and size < n:  # RLE; a block it would not shrink is stored raw
            run, i = bytearray(), 0
            while i < len(raw):
                count = struct.unpack_from("b", raw, i)[0]
                if count < 0:
                    run += raw[i + 1:i + 1 - count]
                    i += 1 - count
                else:
                    run += raw[i + 1:i + 2] * (count + 1)
                    i += 2
            deltas = np.frombuffer(bytes(run), np.uint8).astype(np.int64)
            deltas[1:] -= 128
            split = (np.cumsum(deltas) & 0xFF).astype(np.uint8)
            raw = np.empty(n, np.uint8)
            raw[0::2], raw[1::2] = split[:(n + 1) // 2], split[(n + 1) // 2:]
            raw = raw.tobytes()
        block = np.frombuffer(raw, np.uint8).reshape(bh, len(channels), bw * 4)
        for k, (name, dtype) in enumerate(channels):
            out[name][by:by + bh, bx:bx + bw] = block[:, k, :].copy().view(dtype)
    return out


def test_saved_exr_files_read_back_as_the_frames_arrays(tmp_path):
    c, rad, q, k = random_glyphs(60, seed=12)
    r = es.Renderer(validation=True)
    # 150 x 100: two by two 64-pixel tiles, the last ones partial.
    frame = r.render(c, rad, q, k, eye=(0.0, 1.0, 8.0), target=(0.0, 0.0, 0.0), near=1.0,
                     width=150, height=100)
    hit = frame.id != es.NO_GLYPH
    assert 1000 < hit.sum() < hit.size, "hits and background"
    frame.save(tmp_path / "d.exr", "depth")
    frame.save(tmp_path / "n.exr", "normal")
    frame.save(tmp_path / "i.exr", "id")
    depth = read_exr(tmp_path / "d.exr")
    assert list(depth) == ["Z"]
    assert depth["Z"].view(np.uint32).tolist() == frame.depth.view(np.uint32).tolist()
    normal = read_exr(tmp_path / "n.exr")
    assert sorted(normal) == ["B", "G", "R"]
    for channel, name in enumerate("RGB"):
        assert np.array_equal(normal[name].view(np.uint32),
                              frame.normal[..., channel].view(np.uint32)), name
    assert np.array_equal(read_exr(tmp_path / "i.exr")["ID"], frame.id)
    # Arrays the caller replaced are written as they are (converted to float32 if need be).
    frame.depth = np.ascontiguousarray(frame.depth[::-1].astype(np.float64))
    frame.save(tmp_path / "flipped.exr", "depth")
    assert np.array_equal(read_exr(tmp_path / "flipped.exr")["Z"].view(np.uint32),
                          frame.depth.astype(np.float32).view(np.uint32))
