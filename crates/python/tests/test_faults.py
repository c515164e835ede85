"""Faults walked over a typical run of the Python package (create, upload, frames, an update, a
larger image, a larger upload): the fault layer (crates/fault-layer, its library named by
ES_FAULT_LAYER, which scripts/test-python.sh builds) makes the N-th Vulkan call run out of
device memory, or loses the device from the N-th call that can report it on. Each run must
raise ``OutOfMemoryError`` or ``DeviceLostError`` from the call hit (never another error, never
a panic or ``PoisonedError``); after running out of memory every later call works and draws
what a run without the failed call draws (byte for byte), after a loss every later call that
needs the GPU raises ``DeviceLostError`` (a frame after failed uploads may say instead that
nothing is uploaded) and draws nothing. Validation is on: any message fails the call that
raised it. ES_FAULT_WALK=all tries every fault point (else a spread: each step's first, then a
short stride in the uploads, the update and the frames after the first, a long one elsewhere)."""

import ctypes
import gc
import os

import numpy as np
import pytest

import ellipsoid_splat as es

LAYER_NAME = "VK_LAYER_ELLIPSOID_SPLAT_fault_injection"
OUT_OF_MEMORY, DEVICE_LOST = 1, 2


@pytest.fixture(scope="module")
def layer(tmp_path_factory):
    """The fault layer: installed for the instances made from now on, loaded here so that its
    count lives across them, and armed through its exported functions."""
    library = os.environ["ES_FAULT_LAYER"]
    folder = tmp_path_factory.mktemp("fault-layer")
    (folder / "fault_layer.json").write_text(f"""{{
  "file_format_version": "1.1.2",
  "layer": {{"name": "{LAYER_NAME}", "type": "GLOBAL", "library_path": "{library}",
             "api_version": "1.3.239", "implementation_version": "1",
             "description": "ellipsoid-splat's test-only fault injection"}}
}}""")
    saved = {k: os.environ.get(k) for k in ("VK_ADD_LAYER_PATH", "VK_INSTANCE_LAYERS")}
    os.environ["VK_ADD_LAYER_PATH"] = ":".join(filter(None, [str(folder), saved["VK_ADD_LAYER_PATH"]]))
    os.environ["VK_INSTANCE_LAYERS"] = ":".join(filter(None, [LAYER_NAME, saved["VK_INSTANCE_LAYERS"]]))
    lib = ctypes.CDLL(library)
    lib.es_fault_arm.argtypes = [ctypes.c_uint32, ctypes.c_uint64]
    lib.es_fault_count.restype = ctypes.c_uint64
    lib.es_fault_fired.restype = ctypes.c_char_p
    yield lib
    lib.es_fault_pause(1)
    for key, value in saved.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value


def glyphs(n, seed):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return (rng.uniform(-3, 3, (n, 3)), rng.uniform(0.2, 0.5, (n, 3)), q,
            rng.uniform(0.1, 0.9, (n, 3)))


def camera(eye, width=96, height=64):
    return dict(eye=eye, target=(0.0, 0.0, 0.0), near=0.5, width=width, height=height)


class Run:
    """The typical run, step by step; each step gives a frame's bytes, or nothing."""

    STEPS = ["create", "upload", "frame 1", "frame 2", "update", "frame 3", "larger image",
             "larger upload", "frame 4"]
    #: Steps whose failure changes what later steps draw (a run without them says what).
    CHANGES = {"upload", "update", "larger upload"}
    #: Steps every fault point of which the suite's walk tries.
    DENSE = {"upload", "frame 2", "update", "frame 3", "larger upload", "frame 4"}

    def __init__(self):
        self.renderer = None

    def step(self, name):
        eye, other = (1.0, 2.0, 11.0), (-4.0, 3.0, 9.0)
        r = self.renderer
        if name == "create":
            self.renderer = es.Renderer(validation=True, plan="estimate")
        elif name == "upload":
            r.upload(*glyphs(300, 1))
        elif name == "larger upload":
            r.upload(*glyphs(900, 3))
        elif name == "update":
            centers, radii, _, _ = glyphs(40, 2)
            r.update(np.arange(100, 140), centers=0.7 * centers, radii=0.8 * radii)
        else:
            shot = {"frame 1": camera(eye), "frame 2": camera(other), "frame 3": camera(eye),
                    "larger image": camera(eye, 128, 96), "frame 4": camera(eye)}[name]
            frame = r.render_uploaded(**shot)
            return b"".join(a.tobytes() for a in (frame.color, frame.depth, frame.normal, frame.id))
        return None


def run(lib, skip=None, counted=None):
    """One run: per step ("ok", frame or None) or (kind of error, message); `counted` gets the
    count after each step."""
    walk = Run()
    outcomes = []
    for name in Run.STEPS:
        if name == skip:
            outcomes.append(("ok", None))
            continue
        try:
            outcomes.append(("ok", walk.step(name)))
        except es.OutOfMemoryError as error:
            outcomes.append(("out of memory", str(error)))
        except es.DeviceLostError as error:
            outcomes.append(("device lost", str(error)))
        except Exception as error:  # noqa: BLE001 - any other error is what the walk reports
            outcomes.append(("other", f"{type(error).__name__}: {error}"))
        if counted is not None:
            counted.append(lib.es_fault_count())
        if name == "create" and outcomes[-1][0] != "ok":
            break
    del walk
    gc.collect()  # the renderer is destroyed here
    return outcomes


def chosen(counts, dense, sparse):
    """The fault points tried: every one with ES_FAULT_WALK=all, else each step's first and then
    every `dense`-th (in the dense steps) or `sparse`-th (elsewhere)."""
    every = os.environ.get("ES_FAULT_WALK") == "all"
    first = 1
    points = []
    for name, last in zip(Run.STEPS, counts):
        stride = dense if name in Run.DENSE else sparse
        points += [n for n in range(first, last + 1) if every or (n - first) % stride == 0]
        first = last + 1
    return points


@pytest.mark.parametrize("kind, named, dense, sparse", [(OUT_OF_MEMORY, "out of memory", 3, 12),
                                                        (DEVICE_LOST, "device lost", 1, 3)])
def test_faults_are_named_exceptions_and_leave_a_usable_renderer(layer, kind, named, dense,
                                                                 sparse):
    layer.es_fault_arm(kind, 0)
    counts = []
    clean = run(layer, counted=counts)
    assert all(o[0] == "ok" for o in clean), clean
    without = {}
    problems = []
    points = chosen(counts, dense, sparse)
    for n in points:
        layer.es_fault_arm(kind, n)
        outcomes = run(layer)
        fired = layer.es_fault_fired()
        if fired is None:
            problems.append(f"N = {n}: the fault never fired")
            continue
        failed = next((k for k, o in enumerate(outcomes) if o[0] != "ok"), None)
        if failed is None:
            expected = clean
        elif kind == OUT_OF_MEMORY and Run.STEPS[failed] in Run.CHANGES:
            if failed not in without:
                layer.es_fault_arm(kind, 0)
                without[failed] = run(layer, skip=Run.STEPS[failed])
            expected = without[failed]
        else:
            expected = clean
        for k, outcome in enumerate(outcomes):
            name = Run.STEPS[k]
            where = f"N = {n} ({fired.decode()}), '{name}'"
            if failed is None or k < failed:
                if outcome != clean[k]:
                    problems.append(f"{where}: not what the fault-free run did")
            elif k == failed:
                if outcome[0] != named:
                    problems.append(f"{where}: {outcome}")
            elif kind == OUT_OF_MEMORY:
                if outcome != expected[k]:
                    problems.append(f"{where} after '{Run.STEPS[failed]}' failed: "
                                    f"{outcome[0]} {'' if outcome[0] == 'ok' else outcome[1]}")
            elif outcome[0] == named or outcome == ("ok", None):
                pass  # reports the loss, or needed no GPU and drew nothing
            elif outcome[0] == "ok" or not outcome[1].startswith("ValueError: nothing uploaded"):
                # The uploads failed with the loss: a frame is refused for want of a scene.
                problems.append(f"{where} on the lost device: {outcome[0]} "
                                f"{'' if outcome[0] == 'ok' else outcome[1]}")
    print(f"{named}: {len(points)} of {counts[-1]} fault points tried")
    assert not problems, "\n".join(problems)
