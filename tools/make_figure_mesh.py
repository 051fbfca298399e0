#!/usr/bin/env python3
"""Generates `crates/benchmarks/data/figure.obj`: an irregular triangulation of a non-convex
figure with coordinates on a 0.5-unit lattice, shaped like the meshes real 2D mesh generators
write (quality Delaunay triangulations of an outline), for benchmarking the exact path on real
data rather than grids.

The outline is a star-like blob r(t) = R (1 + 0.22 sin 3t + 0.12 cos 5t + 0.05 sin 11t) sampled at
a fixed spacing; the interior is filled by seeded Poisson-disk sampling at the same spacing
(dart throwing, so point distances vary the way a mesh generator's do); every point is snapped to
the 0.5 lattice. Bowyer-Watson Delaunay triangulation with exact integer predicates (coordinates
doubled), then triangles whose centroid lies outside the outline are dropped and the mesh is
cleaned until it is a connected 2-manifold with boundary (no pinched vertices).

Deterministic: `python3 tools/make_figure_mesh.py` always writes the same file.
"""

import math
import random
import sys
from pathlib import Path

SEED = 20261202
RADIUS = 260.0  # about the size of a figure traced over a 500-pixel image
CENTRE = (300.0, 320.0)
SPACING = 16.5  # gives about 1 000 triangles


def outline_radius(t):
    return RADIUS * (1 + 0.22 * math.sin(3 * t) + 0.12 * math.cos(5 * t) + 0.05 * math.sin(11 * t))


def snap(v):
    """Nearest point of the 0.5 lattice, as an integer count of halves."""
    return int(round(v * 2))


def outline():
    pts = []
    t = 0.0
    while t < 2 * math.pi:
        r = outline_radius(t)
        pts.append((CENTRE[0] + r * math.cos(t), CENTRE[1] + r * math.sin(t)))
        # advance by one spacing of arc length
        dr = (outline_radius(t + 1e-4) - r) / 1e-4
        t += SPACING / math.hypot(r, dr)
    return pts


def inside(poly, x, y):
    c = False
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            c = not c
    return c


def distance_to_outline(poly, x, y):
    best = float("inf")
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        dx, dy = x2 - x1, y2 - y1
        s = max(0.0, min(1.0, ((x - x1) * dx + (y - y1) * dy) / (dx * dx + dy * dy)))
        best = min(best, math.hypot(x - x1 - s * dx, y - y1 - s * dy))
    return best


def sample_points(rng):
    poly = outline()
    points = [(snap(x), snap(y)) for x, y in poly]
    lo_x = min(p[0] for p in poly)
    hi_x = max(p[0] for p in poly)
    lo_y = min(p[1] for p in poly)
    hi_y = max(p[1] for p in poly)
    cell = SPACING / math.sqrt(2)
    grid = {}

    def key(x, y):
        return (int(x // cell), int(y // cell))

    for hx, hy in points:
        grid.setdefault(key(hx / 2, hy / 2), []).append((hx / 2, hy / 2))
    misses = 0
    while misses < 4000:
        x = rng.uniform(lo_x, hi_x)
        y = rng.uniform(lo_y, hi_y)
        if not inside(poly, x, y) or distance_to_outline(poly, x, y) < 0.8 * SPACING:
            misses += 1
            continue
        kx, ky = key(x, y)
        near = False
        for i in range(kx - 2, kx + 3):
            for j in range(ky - 2, ky + 3):
                for px, py in grid.get((i, j), ()):
                    if math.hypot(px - x, py - y) < SPACING:
                        near = True
        if near:
            misses += 1
            continue
        misses = 0
        hx, hy = snap(x), snap(y)
        grid.setdefault(key(hx / 2, hy / 2), []).append((hx / 2, hy / 2))
        points.append((hx, hy))
    return poly, points


def orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def in_circle(a, b, c, d):
    """> 0 when d is strictly inside the circle through the counter-clockwise a, b, c."""
    rows = []
    for p in (a, b, c):
        dx, dy = p[0] - d[0], p[1] - d[1]
        rows.append((dx, dy, dx * dx + dy * dy))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    return a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1)


def delaunay(points):
    big = 10 ** 7
    pts = list(points) + [(-big, -big), (big, -big), (0, big)]
    n = len(points)
    triangles = {(n, n + 1, n + 2)}
    for i in range(n):
        p = pts[i]
        bad = [t for t in triangles if in_circle(pts[t[0]], pts[t[1]], pts[t[2]], p) > 0]
        edges = {}
        for t in bad:
            for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                k = tuple(sorted(e))
                edges[k] = edges.get(k, 0) + 1
            triangles.remove(t)
        for t in bad:
            for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                if edges[tuple(sorted((a, b)))] == 1:
                    tri = (a, b, i)
                    if orient(pts[a], pts[b], pts[i]) < 0:
                        tri = (b, a, i)
                    triangles.add(tri)
    return [t for t in triangles if max(t) < n]


def clean(points, poly, triangles):
    """Drops triangles outside the outline, then pinched vertices and loose pieces."""
    kept = []
    for t in triangles:
        cx = sum(points[v][0] for v in t) / 6
        cy = sum(points[v][1] for v in t) / 6
        if inside(poly, cx, cy) and orient(*(points[v] for v in t)) != 0:
            kept.append(t)
    while True:
        # keep the largest edge-connected component
        by_edge = {}
        for i, t in enumerate(kept):
            for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                by_edge.setdefault(tuple(sorted((a, b))), []).append(i)
        seen = [False] * len(kept)
        best = []
        for s in range(len(kept)):
            if seen[s]:
                continue
            comp, stack = [], [s]
            seen[s] = True
            while stack:
                i = stack.pop()
                comp.append(i)
                t = kept[i]
                for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                    for j in by_edge[tuple(sorted((a, b)))]:
                        if not seen[j]:
                            seen[j] = True
                            stack.append(j)
            if len(comp) > len(best):
                best = comp
        kept = [kept[i] for i in sorted(best)]
        # a vertex is pinched when its triangles form more than one fan: drop the smaller fans
        around = {}
        for i, t in enumerate(kept):
            for v in t:
                around.setdefault(v, []).append(i)
        drop = set()
        for v, tris in around.items():
            fans = []
            left = set(tris)
            while left:
                start = left.pop()
                fan, stack = {start}, [start]
                while stack:
                    i = stack.pop()
                    for j in list(left):
                        if len(set(kept[i]) & set(kept[j])) == 2:
                            left.remove(j)
                            fan.add(j)
                            stack.append(j)
                fans.append(fan)
            if len(fans) > 1:
                fans.sort(key=len)
                for fan in fans[:-1]:
                    drop |= fan
        if not drop:
            return kept
        kept = [t for i, t in enumerate(kept) if i not in drop]


def half(v):
    return f"{v // 2}.5" if v % 2 else f"{v // 2}"


def main():
    rng = random.Random(SEED)
    poly, points = sample_points(rng)
    triangles = clean(points, poly, delaunay(points))
    used = sorted({v for t in triangles for v in t})
    number = {v: k + 1 for k, v in enumerate(used)}
    out = Path(__file__).resolve().parent.parent / "crates/benchmarks/data/figure.obj"
    lines = [
        "# An irregular triangulation of a star-like figure, coordinates on a 0.5 lattice",
        "# (generated by tools/make_figure_mesh.py; a benchmark input of real-mesh shape).",
        f"# {len(used)} vertices, {len(triangles)} triangles",
    ]
    for v in used:
        x, y = points[v]
        lines.append(f"v {half(x)} {half(y)} 0")
    for t in sorted(triangles):
        lines.append("f " + " ".join(str(number[v]) for v in t))
    out.write_text("\n".join(lines) + "\n")
    print(f"{out}: {len(used)} vertices, {len(triangles)} triangles", file=sys.stderr)


if __name__ == "__main__":
    main()
