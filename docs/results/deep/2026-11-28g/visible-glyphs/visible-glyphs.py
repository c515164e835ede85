#!/usr/bin/env python3
"""The glyphs a frame shows, as a scene of their own: reads `render --save-scene SCENE.csv
--id ID.png` (the ID image: each pixel's instance as RGBA8 little-endian bytes, all ones
where none shows) and writes the rows of the instances some pixel shows to OUT.csv, the
scene's header kept and the camera comment left out; prints the camera's flags (without
--near) and the count. Standard library only.

    python3 visible-glyphs.py SCENE.csv ID.png OUT.csv
"""
import struct
import sys
import zlib


def png_rgba8(path):
    """Rows of an 8-bit RGBA PNG (no interlacing) as bytes objects."""
    data = open(path, "rb").read()
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            if (depth, colour, body[12]) != (8, 6, 0):
                sys.exit(f"{path}: not an 8-bit RGBA PNG without interlacing")
        elif kind == b"IDAT":
            idat += body
    raw, stride, bpp = zlib.decompress(idat), width * 4, 4
    rows, prev, at = [], bytearray(stride), 0
    for _ in range(height):
        kind, cur = raw[at], bytearray(raw[at + 1:at + 1 + stride])
        at += 1 + stride
        if kind > 4:
            sys.exit(f"{path}: a row with PNG filter type {kind} (0-4 exist)")
        for x in range(stride):
            a = cur[x - bpp] if x >= bpp else 0
            b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
            if kind == 1:
                cur[x] = (cur[x] + a) & 255
            elif kind == 2:
                cur[x] = (cur[x] + b) & 255
            elif kind == 3:
                cur[x] = (cur[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                cur[x] = (cur[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(cur))
        prev = cur
    return rows


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    scene, ids, out = sys.argv[1:]
    shown = set()
    for row in png_rgba8(ids):
        shown.update(struct.unpack(f"<{len(row) // 4}I", row))
    shown.discard(0xFFFFFFFF)
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
