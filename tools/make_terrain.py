#!/usr/bin/env python3
"""Generates the bundled terrain example data in examples/terrains/ (run from anywhere).

* reference.obj: the reference mesh T of thesis Table 19.2 — 3 x 3 vertices 20 apart, 8
  triangles (the prisms' footprint).
* hills.asc: a 33 x 33-sample height field over [0, 40]^2 (1 089 vertices, 2 048 triangles as a
  model, Table 19.2) as an ESRI ASCII grid: a round hill near the centre, a north-south ridge at
  x = 31, a shallow valley running west to east, and a little texture. Heights are written with
  two decimals, so they are exact decimals.
* tower.obj: a small square tower standing on the hill's flank (a 3D model deformed with the
  terrain).

The data is deterministic: running the script again gives identical files.
"""
import math
import os

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "terrains")

SAMPLES = 33
CELL = 1.25  # 32 cells span 40 units


def height(x, y):
    hill = 7.0 * math.exp(-((x - 18.0) ** 2 + (y - 21.0) ** 2) / (2 * 5.0**2))
    ridge = 5.0 * math.exp(-((x - 31.0) ** 2) / (2 * 2.2**2)) * (0.6 + 0.4 * math.sin(y / 6.0))
    valley = -1.5 * math.exp(-((y - 8.0 - 0.15 * x) ** 2) / (2 * 1.5**2))
    texture = 0.3 * math.sin(x / 3.0) * math.cos(y / 4.0)
    return 2.0 + hill + ridge + valley + texture


def fmt(value):
    text = f"{value:.2f}"
    return "0.00" if text == "-0.00" else text


def reference():
    lines = ["# terrain reference mesh T (thesis Table 19.2): 9 vertices, 8 triangles; tools/make_terrain.py"]
    for y in range(3):
        for x in range(3):
            lines.append(f"v {20 * x} {20 * y}")
    at = lambda x, y: 3 * y + x + 1
    for y in range(2):
        for x in range(2):
            lines.append(f"f {at(x, y)} {at(x + 1, y)} {at(x + 1, y + 1)}")
            lines.append(f"f {at(x, y)} {at(x + 1, y + 1)} {at(x, y + 1)}")
    return "\n".join(lines) + "\n"


def hills():
    lines = [
        f"ncols {SAMPLES}",
        f"nrows {SAMPLES}",
        # The centre of the lower-left cell is at (0, 0): -0.625 + 1.25/2 = 0 exactly.
        "xllcorner -0.625",
        "yllcorner -0.625",
        f"cellsize {CELL}",
        "NODATA_value -9999",
    ]
    for row in range(SAMPLES):  # the first data row is the northernmost
        y = (SAMPLES - 1 - row) * CELL
        lines.append(" ".join(fmt(height(c * CELL, y)) for c in range(SAMPLES)))
    return "\n".join(lines) + "\n"


def tower():
    # A 3 x 3 square tower, 4 units tall, standing on the ground at its centre (11, 31).
    cx, cy, half, tall = 11.0, 31.0, 1.5, 4.0
    ground = round(height(cx, cy), 2)
    corners = [(cx - half, cy - half), (cx + half, cy - half), (cx + half, cy + half), (cx - half, cy + half)]
    vs = [(x, y, ground) for x, y in corners] + [(x, y, ground + tall) for x, y in corners]
    faces = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8)]  # bottom (facing down), top
    for k in range(4):
        a, b = k + 1, (k + 1) % 4 + 1
        faces += [(a, b, b + 4), (a, b + 4, a + 4)]
    lines = ["# a small tower on the terrain (8 vertices, 12 triangles); tools/make_terrain.py"]
    lines += [f"v {x:g} {y:g} {z:.2f}" for x, y, z in vs]
    lines += [f"f {a} {b} {c}" for a, b, c in faces]
    return "\n".join(lines) + "\n"


def main():
    os.makedirs(HERE, exist_ok=True)
    for name, text in [("reference.obj", reference()), ("hills.asc", hills()), ("tower.obj", tower())]:
        with open(os.path.join(HERE, name), "w") as f:
            f.write(text)
        print("wrote", os.path.normpath(os.path.join(HERE, name)))


if __name__ == "__main__":
    main()
