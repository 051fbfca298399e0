#!/usr/bin/env python3
"""Inputs of the editor's frame-time measurement (BENCHMARKS.md, "The editor in the browser").

Writes into OUTDIR:
  grid.obj, grid.ron          the 968-triangle benchmark grid (22 x 22 squares of side 10,
                              interior vertices displaced as `spline2d::mesh::grid(22, 10, true)`)
  figure.obj, figure.ron      the irregular real-looking mesh of issue 14
                              (crates/benchmarks/data/figure.obj)
  grid-model.obj, figure-model.obj
                              models of more than 10 000 vertices: each reference triangle
                              subdivided into 25, so every model vertex lies in the mesh
Usage: tools/make_editor_bench.py OUTDIR
"""

import sys
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SPLIT = 5  # each triangle becomes SPLIT^2 triangles


def grid(n=22, cell=10):
    vertices = []
    for y in range(n + 1):
        for x in range(n + 1):
            inner = 0 < x < n and 0 < y < n
            dx, dy = (((x * 7 + y * 3) % 5 - 2, (x * 2 + y * 5) % 5 - 2) if inner else (0, 0))
            vertices.append((Fraction(cell * x + dx), Fraction(cell * y + dy)))
    at = lambda x, y: y * (n + 1) + x
    triangles = []
    for y in range(n):
        for x in range(n):
            triangles.append((at(x, y), at(x + 1, y), at(x + 1, y + 1)))
            triangles.append((at(x, y), at(x + 1, y + 1), at(x, y + 1)))
    return vertices, triangles


def read_obj(path):
    vertices, triangles = [], []
    for line in path.read_text().splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append((Fraction(parts[1]), Fraction(parts[2])))
        elif parts[0] == "f":
            triangles.append(tuple(int(p.split("/")[0]) - 1 for p in parts[1:4]))
    return vertices, triangles


def write_mesh(path, vertices, triangles, comment):
    lines = [f"# {comment}", f"# {len(vertices)} vertices, {len(triangles)} triangles"]
    lines += [f"v {x} {y} 0" for x, y in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
    path.write_text("\n".join(lines) + "\n")


def decimal(q):
    return repr(float(q))


def subdivide(vertices, triangles, k=SPLIT):
    """Every triangle split into k^2; shared points are one vertex (exact keys)."""
    index, out_vertices, out_faces = {}, [], []

    def vertex(p):
        if p not in index:
            index[p] = len(out_vertices)
            out_vertices.append(p)
        return index[p]

    for a, b, c in triangles:
        pa, pb, pc = vertices[a], vertices[b], vertices[c]

        def point(i, j):
            # weights (k - i - j, i, j) / k on (a, b, c)
            w = (Fraction(k - i - j, k), Fraction(i, k), Fraction(j, k))
            return (w[0] * pa[0] + w[1] * pb[0] + w[2] * pc[0], w[0] * pa[1] + w[1] * pb[1] + w[2] * pc[1])

        for i in range(k):
            for j in range(k - i):
                p, q, r = vertex(point(i, j)), vertex(point(i + 1, j)), vertex(point(i, j + 1))
                out_faces.append((p, q, r))
                if i + j < k - 1:
                    s = vertex(point(i + 1, j + 1))
                    out_faces.append((q, s, r))
    return out_vertices, out_faces


def write_model(path, vertices, faces, comment):
    lines = [f"# {comment}", f"# {len(vertices)} vertices, {len(faces)} triangles"]
    lines += [f"v {decimal(x)} {decimal(y)} 0" for x, y in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


RUN = """// {what}: the editor's frame-time measurement (tools/make_editor_bench.py).
(
    sources: [
        (name: "{name}", plugin: "spline2d", config: (mesh: "{name}.obj", degree: 5, smoothness: 1)),
    ],
    outputs: [
        (source: "{name}", output: (model: "{name}-model.obj")),
    ],
)
"""


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    meshes = {
        "grid": (grid(), "the 968-triangle benchmark grid"),
        "figure": (read_obj(ROOT / "crates/benchmarks/data/figure.obj"), "an irregular real-looking figure"),
    }
    for name, ((vertices, triangles), what) in meshes.items():
        write_mesh(out / f"{name}.obj", vertices, triangles, what)
        mv, mf = subdivide(vertices, triangles)
        write_model(out / f"{name}-model.obj", mv, mf, f"{what}, each triangle split into {SPLIT * SPLIT}")
        (out / f"{name}.ron").write_text(RUN.format(what=what, name=name))
        print(f"{name}: {len(triangles)} triangles, model of {len(mv)} vertices and {len(mf)} triangles")


if __name__ == "__main__":
    main()
