#!/usr/bin/env python3
"""The render flags of a camera turned DEGREES about its up axis through its target, as
`bench --orbit` turns it (crates/tool/src/bench/orbit.rs): reads the camera flags (one line,
as visible-glyphs.py prints them) on standard input and prints them with the eye moved.

    python3 turned-camera.py DEGREES < FLAGS
"""
import math
import sys


def vector(text):
    return [float(x) for x in text.split(",")]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    angle = math.radians(float(sys.argv[1]))
    flags = sys.stdin.read().split()
    values = dict(zip(flags[0::2], flags[1::2]))
    missing = [f for f in ("--eye", "--target", "--up") if f not in values]
    if missing:
        sys.exit(f"turned-camera.py: the camera flags lack {', '.join(missing)}")
    eye, target, up = (vector(values[f]) for f in ("--eye", "--target", "--up"))
    n = math.sqrt(sum(u * u for u in up))
    k = [u / n for u in up]
    v = [e - t for e, t in zip(eye, target)]
    # Rodrigues: v cos a + (k x v) sin a + k (k . v)(1 - cos a).
    kv = [k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]]
    dot = sum(a * b for a, b in zip(k, v))
    turned = [v[i] * math.cos(angle) + kv[i] * math.sin(angle) + k[i] * dot * (1 - math.cos(angle))
              for i in range(3)]
    values["--eye"] = ",".join(repr(t + w) for t, w in zip(target, turned))
    print(" ".join(f"{name} {value}" for name, value in values.items()))


main()
