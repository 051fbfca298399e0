#!/usr/bin/env python3
"""Exact rank of spline C1 systems: this project (sparse fraction-free elimination) against
FLINT's fmpz_mat_rank (python-flint), on the same matrices, in the same run.

    pip install python-flint
    python3 tools/flint_compare.py [n ...]      # default sizes 3 6 10

For each n the C1 system of a degree-5 spline on an n × n perturbed grid (2 n² triangles) is
exported by `cargo run --release -p benchmarks --bin export_system`, which also times this
project's rank (best of 5); FLINT's rank is timed here (best of 3) on the dense fmpz_mat.
"""
import os
import subprocess
import sys
import tempfile
import time

import flint

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def export(n, path):
    out = subprocess.run(
        ["cargo", "run", "-q", "--release", "-p", "benchmarks", "--bin", "export_system", "--",
         str(n), path],
        cwd=ROOT, check=True, capture_output=True, text=True).stdout.split()
    fields = dict(zip(out[0::2], out[1::2]))
    return int(fields["rank"]), float(fields["mono_ms"]), float(fields["blockwise_ms"])


def load(path):
    with open(path) as f:
        rows, cols = map(int, f.readline().split())
        dense = [[0] * cols for _ in range(rows)]
        for i in range(rows):
            for cell in f.readline().split():
                c, v = cell.split(":")
                dense[i][int(c)] = int(v)
    return rows, cols, dense


def main():
    sizes = [int(a) for a in sys.argv[1:]] or [3, 6, 10]
    print("| triangles | matrix | rank | ours, monolithic | ours, block-wise | FLINT fmpz_mat_rank | FLINT / ours (block-wise) |")
    print("|---:|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            path = os.path.join(tmp, f"m{n}.txt")
            rank, mono, blockwise = export(n, path)
            rows, cols, dense = load(path)
            m = flint.fmpz_mat(dense)
            best = float("inf")
            for _ in range(3):
                t = time.perf_counter()
                r = m.rank()
                best = min(best, (time.perf_counter() - t) * 1e3)
            assert r == rank, f"FLINT rank {r} != ours {rank}"
            print(f"| {2 * n * n} | {rows} × {cols} | {rank} | {mono:.2f} ms | {blockwise:.2f} ms | "
                  f"{best:.2f} ms | {best / blockwise:.1f} |")


if __name__ == "__main__":
    main()
