"""How many of a frame's shown glyphs fill a whole 4 x 4 occlusion tile (the glyphs
front-stamps.diff keeps in the first pass), and the share of the shown pixels they show.

    python3 whole-tiles.py ID_PNG...      (ID images of `render --id`, 1920x1080)
"""
import collections
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "2026-11-28g" / "visible-glyphs"))
from png_ids import NONE, read_ids  # noqa: E402

TILE = 4

for path in sys.argv[1:]:
    ids = read_ids(path)
    height, width = len(ids), len(ids[0])
    shown = collections.Counter()
    whole = set()
    for ty in range(0, height, TILE):
        for tx in range(0, width, TILE):
            tile = [ids[y][x] for y in range(ty, min(ty + TILE, height))
                    for x in range(tx, min(tx + TILE, width))]
            shown.update(g for g in tile if g != NONE)
            if tile[0] != NONE and all(g == tile[0] for g in tile):
                whole.add(tile[0])
    pixels = sum(shown.values())
    by_whole = sum(shown[g] for g in whole)
    print(f"{Path(path).name}: {len(shown)} glyphs shown, {len(whole)} fill a whole tile; "
          f"{pixels} pixels shown, {by_whole} ({by_whole / pixels:.0%}) by those")
