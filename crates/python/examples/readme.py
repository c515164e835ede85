import sys

import numpy as np
import ellipsoid_splat as es

rng = np.random.default_rng(1)
n = 2000
centers = rng.uniform(-4, 4, (n, 3))
radii = rng.uniform(0.08, 0.45, (n, 3))
rotations = rng.normal(size=(n, 4))
rotations /= np.linalg.norm(rotations, axis=1, keepdims=True)  # unit quaternions (w, x, y, z)
colors = rng.uniform(0.2, 1.0, (n, 3))

r = es.Renderer()  # validation=False, device=None: a real GPU if there is one, else lavapipe
frame = r.render(centers, radii, rotations, colors, width=640, height=480)
frame.color   # (480, 640, 4) uint8, sRGB
frame.depth   # (480, 640) float32 view depth, +inf where nothing is hit
frame.normal  # (480, 640, 3) float32 world-space unit normal
frame.id      # (480, 640) uint32 glyph index, es.NO_GLYPH where nothing is hit

# A calibrated camera: OpenCV intrinsics K (pixels) and world-to-camera extrinsics [R | t].
K = np.array([[600.0, 0, 330], [0, 600, 235], [0, 0, 1]])
pose = np.eye(4)
pose[2, 3] = 14.0
frame = r.render(centers, radii, rotations, colors, intrinsics=K, world_to_camera=pose,
                 width=640, height=480, supersample=2)
frame.save(sys.argv[1] if len(sys.argv) > 1 else "glyphs.png")

# Files load as the command-line tool loads them, with its colour modes.
scene = es.load("data/samples/thermal.pdb", color="principal")
print(f"{len(scene['centers'])} atoms", *scene["notes"], sep="\n")
