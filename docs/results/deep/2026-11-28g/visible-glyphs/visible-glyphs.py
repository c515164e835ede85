#!/usr/bin/env python3
"""The glyphs a frame shows, as a scene of their own: reads `render --save-scene SCENE.csv
--id ID.png` (the ID image: each pixel's instance as RGBA8 little-endian bytes, all ones
where none shows) and writes the rows of the instances some pixel shows to OUT.csv, the
scene's header kept and the camera comment left out; prints the camera's flags (without
--near) and the count. Standard library only.

    python3 visible-glyphs.py SCENE.csv ID.png OUT.csv
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from png_ids import NONE, read_ids  # noqa: E402


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    scene, ids, out = sys.argv[1:]
    shown = set()
    for row in read_ids(ids):
        shown.update(row)
    shown.discard(NONE)
    lines = open(scene).read().splitlines()
    camera, header, rows = lines[0], lines[1], lines[2:]
    if not camera.startswith("# camera:"):
        sys.exit(f"{scene}: its first line is not render's camera comment")
    kept = [r for i, r in enumerate(rows) if i in shown]
    open(out, "w").write("\n".join([header] + kept) + "\n")
    flags = camera.split("camera:", 1)[1].split()
    if "--near" in flags:
        at = flags.index("--near")
        del flags[at:at + 2]
    print(" ".join(flags))
    print(f"{len(kept)} of {len(rows)} glyphs shown", file=sys.stderr)


main()
