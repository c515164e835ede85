"""The Python package against the Rust API (byte for byte), the pinhole contract, bad input,
files and pictures. Run by scripts/test.sh with the package installed in a virtual
environment; ES_RUST_FRAME names the Rust API's frame writer (examples/rust_frame.rs)."""

import os
import subprocess
import tempfile

import numpy as np
import pytest

import ellipsoid_splat as es

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))


@pytest.fixture(scope="module")
def renderer():
    # Validation on: any message makes the renderer's teardown fail the process.
    return es.Renderer(validation=True)


def random_glyphs(n, seed=3):
    rng = np.random.default_rng(seed)
    centers = rng.uniform(-3, 3, (n, 3))
    radii = rng.uniform(0.1, 0.5, (n, 3))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    colors = rng.uniform(0, 1, (n, 3))
    return centers, radii, q, colors


def test_frames_equal_the_rust_api_byte_for_byte(renderer, tmp_path):
    ply = os.path.join(ROOT, "data", "samples", "splats.ply")
    scene = es.load(ply)
    assert scene["centers"].shape[1] == 3 and len(scene["centers"]) > 10
    camera = dict(eye=(4.0, 3.0, 6.0), target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0),
                  fov_y=40.0, near=0.5, width=200, height=150)
    frame = renderer.render(scene["centers"], scene["radii"], scene["rotations"],
                            scene["colors"], **camera)
    out = str(tmp_path / "rust")
    args = [os.environ["ES_RUST_FRAME"], ply, out, "4,3,6", "0,0,0", "0,1,0", "40", "0.5",
            "200", "150"]
    subprocess.run(args, check=True, capture_output=True)
    read = lambda ext: open(f"{out}.{ext}", "rb").read()  # noqa: E731
    assert (frame.id != es.NO_GLYPH).sum() > 1000, "the scene is in view"
    assert frame.color.tobytes() == read("color")
    assert frame.depth.astype("<f4").tobytes() == read("depth")
    assert frame.normal.astype("<f4").tobytes() == read("normal")
    assert frame.id.astype("<u4").tobytes() == read("id")
    # Float32 arrays are accepted (read in place, widened value by value): the same glyphs to
    # float32's precision.
    again = renderer.render(scene["centers"].astype(np.float32), scene["radii"].astype(np.float32),
                            scene["rotations"], scene["colors"], **camera)
    assert (again.id == frame.id).mean() > 0.99


def test_the_pinhole_puts_a_glyph_where_k_projects_it(renderer):
    K = np.array([[500.0, 0, 330.0], [0, 520.0, 215.0], [0, 0, 1]])
    angle = 0.3
    R = np.array([[np.cos(angle), 0, -np.sin(angle)], [0, 1, 0], [np.sin(angle), 0, np.cos(angle)]])
    t = np.array([0.2, -0.1, 6.0])
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = R, t
    world = np.array([[0.4, 0.3, -0.2]])
    frame = renderer.render(world, np.full((1, 3), 0.05), None, np.array([[1.0, 0.5, 0.2]]),
                            intrinsics=K, world_to_camera=pose, width=640, height=480)
    p = R @ world[0] + t
    u, v = K[0, 0] * p[0] / p[2] + K[0, 2], K[1, 1] * p[1] / p[2] + K[1, 2]
    covered = np.argwhere(frame.id == 0)
    assert len(covered) > 50
    centroid = covered.mean(axis=0) + 0.5  # (row, column) of pixel centres
    assert abs(centroid[1] - u) < 0.1 and abs(centroid[0] - v) < 0.1, (centroid, u, v)
    # The depth at the centre's pixel is the front of the sphere along that ray.
    j, i = int(v), int(u)
    assert frame.id[j, i] == 0
    assert abs(frame.depth[j, i] - (p[2] - 0.05)) < 2e-3


def test_tensors_draw_what_radii_and_rotations_draw(renderer):
    centers, radii, q, colors = random_glyphs(30)
    tensors = np.zeros((30, 3, 3))
    for k, (r, (w, x, y, z)) in enumerate(zip(radii, q)):
        rot = np.array([
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ])
        tensors[k] = rot @ np.diag(r) @ rot.T
    a = renderer.render(centers, radii, q, colors, width=160, height=120)
    b = renderer.render(centers, tensors=tensors, colors=colors, width=160, height=120)
    assert (a.id != es.NO_GLYPH).sum() > 500
    assert (a.id == b.id).mean() > 0.999


def test_bad_input_raises_naming_the_argument(renderer):
    centers, radii, q, colors = random_glyphs(5)
    cases = [
        (dict(centers=centers[:, :2], radii=radii), "centers"),
        (dict(centers=centers, radii=radii[:4]), "radii"),
        (dict(centers=centers, radii=-radii), "glyph 0"),
        (dict(centers=centers, radii=radii, rotations=q[:, :3]), "rotations"),
        (dict(centers=centers, radii=radii, colors=colors * 2), "colors"),
        (dict(centers=np.where(centers > 0, np.nan, centers), radii=radii), "centers"),
        (dict(centers=[["a", "b", "c"]], radii=[[1, 1, 1]]), "centers"),
        (dict(centers=centers, radii=radii, tensors=np.zeros((5, 3, 3))), "or tensors, not both"),
        (dict(centers=centers, radii=radii, width=0), "width"),
        (dict(centers=centers, radii=radii, fov_y=180), "fov_y"),
        (dict(centers=centers, radii=radii, intrinsics=np.eye(3)), "world_to_camera"),
        (dict(centers=centers, radii=radii, intrinsics=np.eye(2), world_to_camera=np.eye(4)),
         "intrinsics"),
        (dict(centers=centers, radii=radii, intrinsics=np.eye(3) * 100 + [[0, 0, 1], [0, 0, 1], [0, 0, -99]],
              world_to_camera=np.diag([1.0, 1.0, -1.0, 1.0])), "world_to_camera"),
        (dict(centers=centers, radii=radii, near=-1.0), "near"),
        (dict(centers=centers, radii=radii, supersample=9), "supersample"),
        (dict(centers=centers, radii=radii, width=True), "width"),
        (dict(centers=centers, radii=radii, near="x"), "near"),
        (dict(centers=centers, radii=radii, rotations=np.zeros((5, 4))), "glyph 0"),
        (dict(centers=centers, radii=radii, intrinsics=[[500, 3, 320], [0, 500, 240], [0, 0, 1]],
              world_to_camera=np.eye(4)), "skew"),
        (dict(centers=centers, radii=radii, intrinsics=np.diag([500.0, 500.0, 1.0]),
              world_to_camera=np.diag([2.0, 2.0, 2.0, 1.0])), "rotation"),
        (dict(centers=centers, tensors=np.tile(np.diag([1.0, -1.0, 1.0]), (5, 1, 1))), "glyph 0"),
    ]
    for kwargs, name in cases:
        with pytest.raises(ValueError, match=name):
            renderer.render(**kwargs)
    with pytest.raises(es.DeviceError):
        es.Renderer(device="no such device")
    assert issubclass(es.DeviceError, RuntimeError)
    with pytest.raises(OSError):
        es.load("/nonexistent/scene.csv")
    with pytest.raises(ValueError, match="color"):
        es.load(os.path.join(ROOT, "data", "samples", "splats.ply"), color="purple")


def test_supersampling_averages_the_samples_of_each_pixel(renderer):
    centers, radii, q, colors = random_glyphs(40)
    camera = dict(eye=(0.0, 0.0, 9.0), target=(0.0, 0.0, 0.0), near=1.0)
    one = renderer.render(centers, radii, q, colors, width=80, height=60, **camera)
    big = renderer.render(centers, radii, q, colors, width=240, height=180, **camera)
    three = renderer.render(centers, radii, q, colors, width=80, height=60, supersample=3,
                            **camera)
    # Each pixel's colour is the linear-light mean of the 3 x 3 samples the large frame
    # drew there; its id and depth are the centre sample's.
    linear = np.where(big.color[..., :3] / 255.0 <= 0.04045, big.color[..., :3] / 255.0 / 12.92,
                      ((big.color[..., :3] / 255.0 + 0.055) / 1.055) ** 2.4)
    mean = linear.reshape(60, 3, 80, 3, 3).mean(axis=(1, 3))
    encoded = np.where(mean <= 0.0031308, 12.92 * mean, 1.055 * mean ** (1 / 2.4) - 0.055)
    assert np.abs(np.round(encoded * 255) - three.color[..., :3]).max() <= 1
    assert (three.id == big.id[1::3, 1::3]).all()
    assert (three.id != es.NO_GLYPH).sum() > 300
    assert (one.id != three.id).sum() < 0.2 * one.id.size


def test_frames_show_themselves_and_save_as_the_tool_does(renderer, tmp_path):
    centers, radii, q, colors = random_glyphs(20)
    frame = renderer.render(centers, radii, q, colors, width=64, height=48)
    png = frame._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 100
    frame.save(tmp_path / "c.png")
    assert open(tmp_path / "c.png", "rb").read() == png
    frame.save(tmp_path / "d.exr", "depth")
    frame.save(tmp_path / "n.exr", "normal")
    frame.save(tmp_path / "i.png", "id")
    frame.save(tmp_path / "i.exr", "id")
    for name in ("d.exr", "n.exr", "i.exr"):
        assert open(tmp_path / name, "rb").read(4) == b"\x76\x2f\x31\x01"  # EXR magic
    with pytest.raises(ValueError, match="png"):
        frame.save(tmp_path / "c.jpg")
    assert frame.depth.dtype == np.float32 and frame.id.dtype == np.uint32
    assert frame.color.shape == (48, 64, 4) and frame.normal.shape == (48, 64, 3)
    hit = frame.id != es.NO_GLYPH
    assert np.isinf(frame.depth[~hit]).all() and np.isfinite(frame.depth[hit]).all()
    lengths = np.linalg.norm(frame.normal[hit], axis=1)
    assert np.allclose(lengths, 1.0, atol=1e-4)


def test_arrays_changed_in_place_are_uploaded_again(renderer):
    centers, radii, q, colors = random_glyphs(20)
    camera = dict(eye=(0.0, 0.0, 9.0), target=(0.0, 0.0, 0.0), near=1.0, width=64, height=48)
    first = renderer.render(centers, radii, q, colors, **camera)
    # The same objects again: uploaded once more (they might have changed unseen), then
    # compared value by value from the next call on.
    renderer.render(centers, radii, q, colors, **camera)
    assert renderer.render(centers, radii, q, colors, **camera).id.tobytes() == first.id.tobytes()
    assert renderer.upload_ms == 0.0, "the same glyphs are not uploaded again"
    centers += 50.0  # moved out of view, in place
    moved = renderer.render(centers, radii, q, colors, **camera)
    assert renderer.upload_ms > 0.0 and (moved.id == es.NO_GLYPH).all()


def test_the_readme_example_runs_and_is_the_guides(tmp_path):
    example = os.path.join(ROOT, "crates", "python", "examples", "readme.py")
    code = open(example).read()
    guide = os.path.join(ROOT, "docs", "python.md")
    assert code in open(guide).read(), "docs/python.md lacks readme.py"
    out = tmp_path / "glyphs.png"
    done = subprocess.run([os.sys.executable, example, str(out)], cwd=ROOT, check=True,
                          capture_output=True, text=True)
    assert "22 atoms" in done.stdout
    png = open(out, "rb").read()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000


def test_a_million_glyphs_render_and_the_binding_costs_little(renderer):
    n = 1_000_000
    rng = np.random.default_rng(11)
    centers = rng.uniform(-20, 20, (n, 3)).astype(np.float32)  # float32 input is accepted
    radii = rng.uniform(0.01, 0.03, (n, 3))
    camera = dict(eye=(0.0, 0.0, 60.0), target=(0.0, 0.0, 0.0), width=640, height=360, near=1.0)
    start = __import__("time").perf_counter()
    frame = renderer.render(centers, radii, **camera)
    wall = (__import__("time").perf_counter() - start) * 1e3
    shown = np.unique(frame.id[frame.id != es.NO_GLYPH])
    assert len(shown) > 10_000 and shown.max() < n
    # Timing is the benchmark's (bench_overhead.py); here it is only reported.
    print(f"1M glyphs: {wall:.0f} ms in Python, {renderer.upload_ms + frame.render_ms:.0f} ms in Rust")


def frame_bytes(frame):
    return [frame.color.tobytes(), frame.depth.tobytes(), frame.normal.tobytes(),
            frame.id.tobytes()]


def test_every_plan_draws_the_same_picture_and_says_why():
    r = es.Renderer(validation=True, plan="draw")
    assert r.plan == "draw" and r.last_plan is None
    centers, radii, q, colors = random_glyphs(300, seed=5)
    camera = dict(eye=(0.0, 0.0, 9.0), target=(0.0, 0.0, 0.0), near=1.0, width=96, height=72)
    r.upload(centers, radii, q, colors)
    frames, plans = {}, {}
    assert sorted(es.PLANS) == sorted(["draw", "splat", "visible-first", "estimate", "measure"])
    for plan in ("draw", "splat", "visible-first", "estimate", "measure"):
        r.plan = plan
        # The camera holds still: the visible-first splat's first frame stamps what it shows,
        # its second splats that first.
        for stamping in (True, False):
            frames[plan, stamping] = r.render_uploaded(**camera)
            plans[plan, stamping] = r.last_plan
        assert r.plan == plan
    drawn = frames["draw", False]
    assert (drawn.id != es.NO_GLYPH).sum() > 1000
    if "llvmpipe" in r.device:  # bit for bit on lavapipe; other drivers round paths apart
        for key, frame in frames.items():
            assert frame_bytes(frame) == frame_bytes(drawn), key
    draw = plans["draw", False]
    assert draw["path"] == "draw" and draw["hidden"] is None
    assert draw["reason_kind"] in ("fixed", "only") and draw["measured_ms"] is None
    assert isinstance(draw["reason"], str) and draw["reason"]
    if "splat" in draw["candidates"]:
        assert draw["reason_kind"] == "fixed" and draw["reason"] == "fixed by the host"
        splat = plans["splat", False]
        assert (splat["path"], splat["hidden"], splat["reason_kind"]) == \
            ("splat", "splat-all", "fixed")
        assert (plans["visible-first", True]["path"], plans["visible-first", True]["hidden"]) \
            == ("visible-first", "stamp-shown")
        assert (plans["visible-first", False]["path"], plans["visible-first", False]["hidden"]) \
            == ("visible-first", "visible-first")
    assert plans["estimate", False]["reason_kind"] in ("estimated", "only")
    # A name not among the plans is refused and changes nothing.
    with pytest.raises(ValueError, match="'measure', 'estimate', 'draw', 'splat', 'visible-first'"):
        r.plan = "fastest"
    with pytest.raises(ValueError, match="plan"):
        r.plan = None
    assert r.plan == "measure"
    with pytest.raises(ValueError, match="visible-first"):
        es.Renderer(plan="quickest")


def test_plan_wisdom_goes_to_a_second_renderer_and_bad_bytes_are_refused():
    first = es.Renderer(validation=True)
    second = es.Renderer(validation=True)
    empty = second.plan_wisdom()
    assert isinstance(empty, bytes) and len(empty) > 0
    centers, radii, q, colors = random_glyphs(300, seed=8)
    camera = dict(eye=(0.0, 1.0, 9.0), target=(0.0, 0.0, 0.0), near=1.0, width=96, height=72)
    # The same camera until the plan settles its scene class (each trial is bounded).
    frames = 0
    while len(first.plan_wisdom()) == len(empty) and frames < 90:
        first.render(centers, radii, q, colors, **camera)
        frames += 1
    wisdom = first.plan_wisdom()
    assert len(wisdom) > len(empty), f"nothing settled in {frames} frames"
    first.render(centers, radii, q, colors, **camera)
    learned = first.last_plan
    assert learned["reason_kind"] == "measured" and learned["measured_ms"] >= 0
    assert learned["reason"].startswith("measured: ")
    assert (learned["runner_up"] is None) == (learned["runner_up_ms"] is None)

    second.load_plan_wisdom(wisdom)
    assert second.plan_wisdom() == wisdom, "what a renderer loads it gives back"
    # Its first frame's camera moves in (a class of its own); the next holds still and is
    # planned as learned, without exploring.
    second.render(centers, radii, q, colors, **camera)
    second.render(centers, radii, q, colors, **camera)
    assert second.last_plan["reason_kind"] == "measured"
    assert second.last_plan["path"] == learned["path"]

    damaged = bytearray(wisdom)
    damaged[len(damaged) // 2] ^= 0x40
    for bad in (b"these bytes are not plan wisdom", wisdom[:-1], bytes(damaged), b""):
        with pytest.raises(ValueError, match="plan wisdom"):
            second.load_plan_wisdom(bad)
    with pytest.raises(TypeError):
        second.load_plan_wisdom("not bytes")
    second.load_plan_wisdom(memoryview(wisdom))  # any bytes-like object
