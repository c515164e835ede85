#!/usr/bin/env python3
"""How many of a frame's shown pixels show the same glyph a camera step later: reads two ID
images of `render --id` (the frame, then the turned one) and prints, as CSV, the pixels the
turned frame shows and how many of them show the glyph the first frame showed there.

    python3 same-glyph.py ID.png TURNED_ID.png
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from png_ids import NONE, read_ids  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    before, after = read_ids(sys.argv[1]), read_ids(sys.argv[2])
    if len(before) != len(after) or len(before[0]) != len(after[0]):
        sys.exit(f"{sys.argv[1]} and {sys.argv[2]} differ in size")
    shown = same = 0
    for old, new in zip(before, after):
        for a, b in zip(old, new):
            if b != NONE:
                shown += 1
                same += a == b
    print("pixels_shown,same_glyph")
    print(f"{shown},{same}")


main()
