#!/usr/bin/env python3
"""The CPU ray tracer beside us: Mitsuba 3's LLVM backend on the same cores, timing what a
deep scene costs a BVH ray tracer that stops at each ray's first hit.

    ellipsoid-splat render --scene lattice --save-scene lattice.csv --out /dev/null.png
    python3 scripts/cpu-raytracer.py lattice.csv [--frames 15] [--orbit DEG]

Reads the Ellipsoid CSV that `render --save-scene` writes (semi-axes and quaternion columns;
its first comment line holds the camera as `render` flags) and prints, per way, the median
wall time of warm frames and their range:

- `depth`: Mitsuba's `aov` integrator with the depth AOV, one sample per pixel (a depth image
  as `render --depth` gives, without colour);
- `rays`: raw primary rays -- one ray per pixel centre, `scene.ray_intersect`, the hit
  distances evaluated -- the least a ray tracer does per frame.

With `--orbit DEG` each frame's camera turns DEG degrees about the target further than the
last (as `bench --orbit`); a ray tracer keeps no history, so this changes little for it.
Needs `pip install mitsuba` (3.6 or later: the `ellipsoids` shape); not part of the tests.
"""

import argparse
import math
import statistics
import sys
import time

import numpy as np


def read_scene(path):
    camera = None
    comments = 0
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            comments += 1
            if line.startswith("# camera:"):
                camera = line.split(":", 1)[1].split()
    if camera is None:
        sys.exit(f"{path}: no '# camera:' line (write the file with render --save-scene)")
    flags = {camera[k]: camera[k + 1] for k in range(0, len(camera) - 1, 2)}
    data = np.genfromtxt(path, delimiter=",", names=True, skip_header=comments, comments=None)
    needed = ["x", "y", "z", "rx", "ry", "rz", "qw", "qx", "qy", "qz"]
    missing = [n for n in needed if n not in data.dtype.names]
    if missing:
        sys.exit(f"{path}: missing columns {missing} (semi-axes and quaternion form)")
    data = np.atleast_1d(data)
    centers = np.stack([data["x"], data["y"], data["z"]], axis=1)
    scales = np.stack([data["rx"], data["ry"], data["rz"]], axis=1)
    # Mitsuba's `ellipsoids` takes quaternions as x, y, z, w.
    quaternions = np.stack([data["qx"], data["qy"], data["qz"], data["qw"]], axis=1)
    quaternions /= np.linalg.norm(quaternions, axis=1, keepdims=True)
    return centers, scales, quaternions, flags


def vector(text):
    return [float(v) for v in text.split(",")]


def orbited(eye, target, up, degrees):
    """`eye` turned `degrees` about `target` around `up` (Rodrigues' formula)."""
    eye, target, up = (np.array(v, dtype=float) for v in (eye, target, up))
    k = up / np.linalg.norm(up)
    v = eye - target
    a = math.radians(degrees)
    turned = v * math.cos(a) + np.cross(k, v) * math.sin(a) + k * np.dot(k, v) * (1 - math.cos(a))
    return list(target + turned)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--frames", type=int, default=15)
    parser.add_argument("--orbit", type=float, default=0.0)
    args = parser.parse_args()
    if args.frames < 1:
        sys.exit("--frames must be at least 1")
    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    centers, scales, quaternions, flags = read_scene(args.scene)
    if "--fov-y" not in flags:
        sys.exit(f"{args.scene}: only perspective cameras (--fov-y) are supported here")
    width, height = int(flags["--width"]), int(flags["--height"])
    eye, target, up = vector(flags["--eye"]), vector(flags["--target"]), vector(flags["--up"])
    f32 = lambda a: mi.TensorXf(np.ascontiguousarray(a, dtype=np.float32))
    scene = mi.load_dict({
        "type": "scene",
        "glyphs": {"type": "ellipsoids", "extent": 1.0, "centers": f32(centers),
                   "scales": f32(scales), "quaternions": f32(quaternions)},
    })

    def sensor(step):
        return mi.load_dict({
            "type": "perspective", "fov": float(flags["--fov-y"]), "fov_axis": "y",
            "near_clip": float(flags["--near"]), "far_clip": 1e7,
            "to_world": mi.ScalarTransform4f().look_at(
                origin=orbited(eye, target, up, args.orbit * step), target=target, up=up),
            "film": {"type": "hdrfilm", "width": width, "height": height,
                     "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": 1},
        })


    depth = mi.load_dict({"type": "aov", "aovs": "dd:depth"})
    # Pixel centres, row-major.
    jj, ii = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    centres = mi.Point2f((ii.ravel() + 0.5) / width, (jj.ravel() + 0.5) / height)

    def depth_frame(camera):
        image = mi.render(scene, sensor=camera, integrator=depth, spp=1)
        dr.eval(image)
        return np.array(image)

    def ray_frame(camera):
        ray, _ = camera.sample_ray(0.0, 0.5, centres, mi.Point2f(0.5, 0.5))
        t = scene.ray_intersect(ray).t
        dr.eval(t)
        return np.array(t)

    hits = np.isfinite(ray_frame(sensor(0))).sum()
    print(f"{args.scene}: {len(centers):,} ellipsoids, {width}x{height}, {hits:,} pixels hit; "
          f"Mitsuba {mi.__version__} {mi.variant()}, median of {args.frames} warm frames")
    for name, frame in (("depth", depth_frame), ("rays", ray_frame)):
        for step in range(2):  # JIT compilation and caches
            frame(sensor(-2 + step))
        times = []
        for step in range(args.frames):
            camera = sensor(step + 1)  # made before the clock starts
            start = time.perf_counter()
            frame(camera)
            times.append((time.perf_counter() - start) * 1e3)
        print(f"{name}: {statistics.median(times):.1f} ms ({min(times):.1f}-{max(times):.1f})")


if __name__ == "__main__":
    main()
