#!/usr/bin/env python3
"""Exact rank of spline C1 systems: this project's sparse elimination against LinBox's sparse
elimination and FLINT's dense fmpz_mat_rank, on the same matrices, in the same run.

Install (Debian; LinBox 1.7's pkg-config flags link NTL, IML and FLINT, whose headers its
headers include, but liblinbox-dev does not pull in their -dev packages):

    apt-get install -y liblinbox-dev libntl-dev libiml-dev libflint-dev
    pip install python-flint

Run (the release binary target/release/export_system must be built):

    python3 tools/linbox_compare.py [--timeout S] [--flint-max-entries E] [n ...]

Default sizes: 8 22 70. For each n, `export_system n FILE` writes the scalar C1 constraint
matrix of a degree-5 spline on a perturbed n × n grid (2 n² triangles) and times this project's
exact rank of it (best of 5). tools/linbox_rank.cpp, compiled on demand into
$XDG_CACHE_HOME/ecles-linbox (default ~/.cache/ecles-linbox), times LinBox on the same file;
python-flint's fmpz_mat.rank (FLINT's fmpz_mat_rank) is timed here on the dense matrix, best
of 3. Times are of the rank computation only: not of reading the file or building the input
matrix, but of any copy or modular reduction the rank routine makes of it. Every rank obtained
must equal ours; otherwise the disagreements are printed and the exit status is 1.

Columns of the Markdown table:
  triangles          2 n²
  matrix             rows × columns, nonzero entries
  rank               this project's exact rank over Z
  ours, monolithic   exact_ldu::sparse::eliminate: fraction-free sparse elimination over Z
                     (Markowitz pivots, primitive rows), best of 5
  ours, block-wise   exact_ldu::sparse::eliminate_blockwise: the same per connected component,
                     identical components eliminated once, best of 5
  LinBox mod p       rank(A, Method::SparseElimination()) over Modular<uint32_t>, p = 2^31 − 1
                     (GaussDomain sparse elimination), best of 3, stopping after any run
                     over 10 s
  LinBox over Z      rank(A) over ZRing<Integer> (LinBox reduces modulo one random 23-bit prime
                     and eliminates there: a Monte Carlo rank, see linbox_rank.cpp), same timing
  FLINT              fmpz_mat_rank on the dense fmpz_mat, best of 3; skipped above
                     --flint-max-entries dense entries (default 10 000 000)
  LinBox / ours      LinBox's time over ours, monolithic (both eliminate the whole matrix)
A LinBox cell reads "timed out" when linbox_rank did not finish within --timeout seconds
(default 1200, for both of its ranks together).
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import flint

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
EXPORT_SYSTEM = os.path.join(ROOT, "target", "release", "export_system")
LINBOX_SOURCE = os.path.join(ROOT, "tools", "linbox_rank.cpp")
CACHE_DIR = os.path.join(
    os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "ecles-linbox")


def linbox_binary():
    """Path of linbox_rank, compiled first if missing or older than its source."""
    binary = os.path.join(CACHE_DIR, "linbox_rank")
    if (not os.path.exists(binary)
            or os.path.getmtime(binary) < os.path.getmtime(LINBOX_SOURCE)):
        os.makedirs(CACHE_DIR, exist_ok=True)
        flags = subprocess.run(["pkg-config", "--cflags", "--libs", "linbox"],
                               check=True, capture_output=True, text=True).stdout.split()
        subprocess.run(["g++", "-O2", "-std=c++17", LINBOX_SOURCE, "-o", binary, *flags],
                       check=True)
    return binary


def records(text):
    """Lines `name value key value ...` as {name: {"value": value, key: value, ...}}."""
    out = {}
    for line in text.splitlines():
        words = line.split()
        if words:
            out[words[0]] = dict(zip(["value", *words[2::2]], [words[1], *words[3::2]]))
    return out


def export(n, path):
    """Writes the system of size n to path; returns (rank, monolithic ms, block-wise ms)."""
    out = subprocess.run([EXPORT_SYSTEM, str(n), path],
                         check=True, capture_output=True, text=True).stdout.split()
    fields = dict(zip(out[0::2], out[1::2]))
    return int(fields["rank"]), float(fields["mono_ms"]), float(fields["blockwise_ms"])


def run_linbox(binary, path, timeout):
    """linbox_rank's records; those it printed before the time-out if it timed out."""
    try:
        return records(subprocess.run([binary, path], check=True, capture_output=True,
                                      text=True, timeout=timeout).stdout)
    except subprocess.TimeoutExpired as e:
        return records((e.stdout or b"").decode())


def read_matrix(path):
    """(rows, cols, [(row, col, value)]) from export_system's text format."""
    with open(path) as f:
        rows, cols = map(int, f.readline().split())
        entries = []
        for i in range(rows):
            for cell in f.readline().split():
                c, v = cell.split(":")
                entries.append((i, int(c), int(v)))
    return rows, cols, entries


def matrix_size(path):
    """(rows, cols, nonzeros) of an exported system."""
    with open(path) as f:
        rows, cols = map(int, f.readline().split())
        return rows, cols, sum(line.count(":") for line in f)


def flint_rank(rows, cols, entries):
    """FLINT's rank of the dense matrix, best of 3: (rank, ms)."""
    m = flint.fmpz_mat(rows, cols)
    for i, j, v in entries:
        m[i, j] = v
    best = float("inf")
    for _ in range(3):
        t = time.perf_counter()
        r = m.rank()
        best = min(best, (time.perf_counter() - t) * 1e3)
    return r, best


def fmt_ms(ms):
    return f"{ms:,.0f} ms".replace(",", " ") if ms >= 100 else f"{ms:.2f} ms"


def fmt_ratio(r):
    return f"{r:.1f}" if r < 10 else f"{r:.0f}"


def fmt_int(k):
    return f"{k:,}".replace(",", " ")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sizes", nargs="*", type=int, default=[8, 22, 70],
                        help="grid sizes n (2 n² triangles)")
    parser.add_argument("--timeout", type=float, default=1200,
                        help="seconds allowed to one run of linbox_rank (both ranks)")
    parser.add_argument("--flint-max-entries", type=int, default=10_000_000,
                        help="largest rows × cols given to FLINT's dense rank")
    args = parser.parse_args()
    if not os.path.exists(EXPORT_SYSTEM):
        sys.exit("missing target/release/export_system: "
                 "cargo build --release -p benchmarks --bin export_system")
    binary = linbox_binary()

    print("| triangles | matrix (nonzeros) | rank | ours, monolithic | ours, block-wise "
          "| LinBox mod p | LinBox over Z | FLINT fmpz_mat_rank "
          "| LinBox mod p / ours | LinBox over Z / ours |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    disagreements = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.sizes:
            path = os.path.join(tmp, f"system_{n}.txt")
            rank, mono, blockwise = export(n, path)
            rows, cols, nonzeros = matrix_size(path)
            linbox = run_linbox(binary, path, args.timeout)
            cells = []
            for key in ("rank_mod_p", "rank_int"):
                if key in linbox:
                    got = int(linbox[key]["value"])
                    if got != rank:
                        disagreements.append(f"n = {n}: LinBox {key} {got} != ours {rank}")
                    cells.append(float(linbox[key]["time_ms"]))
                else:
                    cells.append(None)
            if rows * cols <= args.flint_max_entries:
                got, flint_ms = flint_rank(*read_matrix(path))
                if got != rank:
                    disagreements.append(f"n = {n}: FLINT rank {got} != ours {rank}")
                flint_cell = fmt_ms(flint_ms)
            else:
                flint_cell = "skipped: dense too large"
            linbox_cells = [fmt_ms(ms) if ms is not None else f"timed out ({args.timeout:.0f} s)"
                            for ms in cells]
            ratio_cells = [fmt_ratio(ms / mono) if ms is not None else "–" for ms in cells]
            print(f"| {fmt_int(2 * n * n)} | {fmt_int(rows)} × {fmt_int(cols)} "
                  f"({fmt_int(nonzeros)}) | {fmt_int(rank)} "
                  f"| {fmt_ms(mono)} | {fmt_ms(blockwise)} | {' | '.join(linbox_cells)} "
                  f"| {flint_cell} | {' | '.join(ratio_cells)} |", flush=True)
    for d in disagreements:
        print("RANK DISAGREEMENT:", d, file=sys.stderr)
    sys.exit(1 if disagreements else 0)


if __name__ == "__main__":
    main()
