#!/usr/bin/env python3
"""Writes examples/images/checker.png, the picture examples/image.ron deforms: 400 x 400
pixels over the 40 x 40 example grid (1/10 unit per pixel), a checkerboard of 2-unit squares
with a ring and a cross, so that a smooth deformation shows. Standard library only (PNG by zlib)."""

import math
import struct
import sys
import zlib

SIZE = 400


def colour(i, j):
    x, y = (i + 0.5) / 10.0, 40.0 - (j + 0.5) / 10.0  # model coordinates of the pixel centre
    r = math.hypot(x - 20.0, y - 20.0)
    if abs(r - 9.0) < 0.6:
        return (200, 40, 40)
    if abs(x - 20.0) < 0.3 or abs(y - 20.0) < 0.3:
        return (30, 90, 200)
    light = (int(x // 2) + int(y // 2)) % 2 == 0
    return (235, 235, 225) if light else (90, 110, 90)


def png(width, height, pixel):
    rows = b"".join(
        b"\x00" + bytes(c for i in range(width) for c in pixel(i, j)) for j in range(height)
    )

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(rows, 9))
        + chunk(b"IEND", b"")
    )


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "examples/images/checker.png"
    with open(out, "wb") as f:
        f.write(png(SIZE, SIZE, colour))
    print(f"wrote {out}")
