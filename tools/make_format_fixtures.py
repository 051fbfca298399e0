#!/usr/bin/env python3
"""Writes tests/fixtures/terrain-3x3.tif: a 3 x 3 float32 GeoTIFF elevation model for the
golden round-trip test (tests/tests/cli.rs), the same heights and positions as the ESRI grid
there: cells of 10 units, the raster's north-west corner at (0, 30) (PixelIsArea), one sample
GDAL_NODATA (-9999). A plain little-endian TIFF with one strip, written field by field so that
the file is small, deterministic and needs no library.

    python3 tools/make_format_fixtures.py
"""
import os, struct

HEIGHTS = [1, 2, 3, 4, -9999, 6, 7, 8, 9.5]  # the northernmost row first
WIDTH = HEIGHTS_ROWS = 3

def tiff(path):
    data = b"".join(struct.pack("<f", h) for h in HEIGHTS)
    scale = struct.pack("<3d", 10.0, 10.0, 0.0)
    tiepoint = struct.pack("<6d", 0.0, 0.0, 0.0, 0.0, 30.0, 0.0)
    # GeoKeyDirectory 1.1.0 with 2 keys: GTModelTypeGeoKey = projected, GTRasterTypeGeoKey = PixelIsArea.
    keys = struct.pack("<12H", 1, 1, 0, 2, 1024, 0, 1, 1, 1025, 0, 1, 1)
    nodata = b"-9999\0"
    # (tag, type, count, value bytes); types: 3 SHORT, 4 LONG, 2 ASCII, 12 DOUBLE.
    entries = [
        (256, 3, 1, struct.pack("<H", WIDTH)),
        (257, 3, 1, struct.pack("<H", HEIGHTS_ROWS)),
        (258, 3, 1, struct.pack("<H", 32)),
        (259, 3, 1, struct.pack("<H", 1)),
        (262, 3, 1, struct.pack("<H", 1)),
        (273, 4, 1, None),  # strip offset, filled below
        (277, 3, 1, struct.pack("<H", 1)),
        (278, 3, 1, struct.pack("<H", HEIGHTS_ROWS)),
        (279, 4, 1, struct.pack("<I", len(data))),
        (339, 3, 1, struct.pack("<H", 3)),
        (33550, 12, 3, scale),
        (33922, 12, 6, tiepoint),
        (34735, 3, 12, keys),
        (42113, 2, len(nodata), nodata),
    ]
    ifd_offset = 8
    ifd_size = 2 + 12 * len(entries) + 4
    extra_offset = ifd_offset + ifd_size
    extra = b""
    fields = []
    strip_offset = None
    # Values longer than 4 bytes go after the IFD, then the strip.
    for tag, kind, count, value in entries:
        if value is not None and len(value) > 4:
            fields.append((tag, kind, count, struct.pack("<I", extra_offset + len(extra))))
            extra += value
            if len(extra) % 2:
                extra += b"\0"
        else:
            fields.append((tag, kind, count, value))
    strip_offset = extra_offset + len(extra)
    out = b"II" + struct.pack("<HI", 42, ifd_offset) + struct.pack("<H", len(fields))
    for tag, kind, count, value in fields:
        if value is None:
            value = struct.pack("<I", strip_offset)
        out += struct.pack("<HHI", tag, kind, count) + value.ljust(4, b"\0")
    out += struct.pack("<I", 0) + extra + data
    with open(path, "wb") as f:
        f.write(out)

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
tiff(os.path.join(root, "tests", "fixtures", "terrain-3x3.tif"))
