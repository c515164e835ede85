"""The ID images `render --id` writes (8-bit RGBA PNG, each pixel's instance as little-endian
bytes, all ones where none shows), read with the standard library."""
import struct
import sys
import zlib

# The ID of a pixel no instance shows.
NONE = 0xFFFFFFFF


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


def read_ids(path):
    """Each row of an ID image as a tuple of instance IDs."""
    return [struct.unpack(f"<{len(row) // 4}I", row) for row in png_rgba8(path)]
