#!/usr/bin/env python3
"""Writes the whole-mesh benchmark inputs of BENCHMARKS.md ("Whole meshes"): a perturbed
`n × n` grid of squares of side 10, each split by its rising diagonal (`2 n²` triangles), and
two run files analysing it as a degree-5 C1 spline, with the default float cross-check and
without (`cross_check: None`).

    python3 tools/make_grid_mesh.py DIR N [--digits K]

Interior vertices move by up to 2 units in each direction (integers), or, with `--digits K`,
by a fraction with K decimal digits below 0.2 (coordinates such as `350.1234567890123456`),
which makes the exact elimination's numbers large. Deterministic: a fixed seed per mesh.
Writes `DIR/grid{N}.obj`, `DIR/grid{N}.ron`, `DIR/grid{N}x.ron` (with `--digits K`:
`grid{N}d{K}…`). Then, for example: `/usr/bin/time -f "%e s %M KB" ecles analyze DIR/grid224.ron`.
"""

import argparse
import random
from pathlib import Path


def vertex(x, y, n, rng, digits):
    """The vertex at grid position (x, y): boundary vertices stay on the grid."""
    if not (0 < x < n and 0 < y < n):
        return f"{10 * x} {10 * y}"
    if digits:
        bound = 2 * 10 ** (digits - 1)
        fx, fy = rng.randint(0, bound), rng.randint(0, bound)
        return f"{10 * x}.{fx:0{digits}d} {10 * y}.{fy:0{digits}d}"
    return f"{10 * x + rng.randint(-2, 2)} {10 * y + rng.randint(-2, 2)}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dir", type=Path)
    parser.add_argument("n", type=int)
    parser.add_argument("--digits", type=int, default=0)
    args = parser.parse_args()
    if args.n < 1 or args.digits < 0:
        parser.error("N must be positive and K not negative")
    n, digits = args.n, args.digits
    rng = random.Random(7 + 1000 * digits + n)
    name = f"grid{n}" + (f"d{digits}" if digits else "")
    args.dir.mkdir(parents=True, exist_ok=True)
    lines = [f"# {n} x {n} perturbed grid, {2 * n * n} triangles (tools/make_grid_mesh.py)"]
    lines += [f"v {vertex(x, y, n, rng, digits)}" for y in range(n + 1) for x in range(n + 1)]
    at = lambda x, y: y * (n + 1) + x + 1
    for y in range(n):
        for x in range(n):
            lines.append(f"f {at(x, y)} {at(x + 1, y)} {at(x + 1, y + 1)}")
            lines.append(f"f {at(x, y)} {at(x + 1, y + 1)} {at(x, y + 1)}")
    (args.dir / f"{name}.obj").write_text("\n".join(lines) + "\n")
    source = (
        f'sources: [(name: "grid", plugin: "spline2d", '
        f'config: (mesh: "{name}.obj", degree: 5, smoothness: 1))], edits: [], outputs: []'
    )
    (args.dir / f"{name}.ron").write_text(f"({source})\n")
    (args.dir / f"{name}x.ron").write_text(f"(cross_check: None, {source})\n")
    print(f"wrote {name}.obj ({2 * n * n} triangles), {name}.ron, {name}x.ron in {args.dir}")


if __name__ == "__main__":
    main()
