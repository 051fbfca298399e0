#!/usr/bin/env python3
"""The per-call cost of an exact ECLES update from Python (`import ecles`), against
kiwisolver's `suggestValue` + `updateVariables` and SolveSpace's `solve` (py-slvs) on the same
point systems as tools/peer_bench.py (chain, grid, parallelograms; one point dragged by
(3, -2), alternating between its start and its target). Prints one Markdown table.

    pip install ./crates/python kiwisolver py-slvs
    python3 tools/python_overhead.py [--sizes 10 100] [--systems chain grid parallelograms]

Timed, best and median of `--calls` (default 200) alternating calls after one warm-up:

* `ecles update`: `Edit.update(anchors=...)` — the exact least-squares values of every
  parameter as `Fraction`s (the Initialize, made once by `System.edit`, is not timed);
* `ecles preview`: `Edit.preview(...)` — the same verdict, floats;
* `kiwi`: `suggestValue` of both coordinates and `updateVariables`;
* `SolveSpace`: the best of up to 5 `solve`s of the sketch after setting the dragged point
  (tools/peer_bench.py's measurement; its setup untimed).
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import peer_bench  # noqa: E402  (the systems and the peers' setups)

import ecles  # noqa: E402


def times(call, calls):
    """Best and median seconds of `calls` calls of call(i), after one warm-up call."""
    call(0)
    spent = []
    for i in range(calls):
        start = time.perf_counter()
        call(i)
        spent.append(time.perf_counter() - start)
    return min(spent), statistics.median(spent)


def measure_ecles(system, calls):
    names = [peer_bench.coordinate_name(v) for v in range(2 * len(system.points))]
    values = {n: v for n, v in zip(names, (c for xy in system.points for c in xy))}
    equations = [peer_bench.equation_text(eq) for eq in system.equations]
    s = ecles.System.from_equations(values, equations, source="l")
    dx, dy = (f"l.{peer_bench.coordinate_name(2 * system.dragged + k)}" for k in (0, 1))
    derived = [f"l.{n}" for n in names if f"l.{n}" not in (dx, dy)]
    start_xy, target = system.points[system.dragged], system.target
    edit = s.edit(anchors={dx: target[0], dy: target[1]}, derived=derived)
    positions = [dict(zip((dx, dy), start_xy)), dict(zip((dx, dy), target))]
    out = edit.update(anchors=positions[1])
    assert (out[dx], out[dy]) == target
    update = times(lambda i: edit.update(anchors=positions[i % 2]), calls)
    preview = times(lambda i: edit.preview(anchors=positions[i % 2]), calls)
    return update, preview


def measure_kiwi(system, calls):
    solver = peer_bench.kiwisolver.Solver()
    variables = [peer_bench.kiwisolver.Variable(peer_bench.coordinate_name(v))
                 for v in range(2 * len(system.points))]
    for eq in system.equations:
        solver.addConstraint(sum(c * variables[v] for v, c in eq.items()) == 0)
    for variable, value in zip(variables, (c for xy in system.points for c in xy)):
        solver.addConstraint((variable == value) | "weak")
    dragged = variables[2 * system.dragged:2 * system.dragged + 2]
    for variable in dragged:
        solver.addEditVariable(variable, "strong")
    positions = (system.points[system.dragged], system.target)

    def solve(i):
        for variable, value in zip(dragged, positions[i % 2]):
            solver.suggestValue(variable, value)
        solver.updateVariables()
    return times(solve, calls)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 100])
    parser.add_argument("--systems", nargs="+", default=["chain", "grid", "parallelograms"])
    parser.add_argument("--calls", type=int, default=200)
    args = parser.parse_args()
    print("| system | points | ecles update (µs, best / median) | ecles preview (µs) "
          "| kiwi (µs) | SolveSpace (µs, best) | update / kiwi (median) | update / SolveSpace |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name in args.systems:
        for n in args.sizes:
            system = getattr(peer_bench, name)(n)
            (ub, um), (pb, pm) = measure_ecles(system, args.calls)
            kb, km = measure_kiwi(system, args.calls)
            solvespace = peer_bench.measure_slvs(system, lambda stage: None)
            if isinstance(solvespace, dict):
                sb = solvespace["ms"] * 1e-3
                slvs_cell, slvs_ratio = f"{sb * 1e6:.0f}", f"{ub / sb:.2f}×"
            else:
                slvs_cell, slvs_ratio = f"**{solvespace}**", "–"
            print(f"| {name} | {len(system.points)} | {ub * 1e6:.0f} / {um * 1e6:.0f} "
                  f"| {pb * 1e6:.0f} / {pm * 1e6:.0f} | {kb * 1e6:.1f} / {km * 1e6:.1f} "
                  f"| {slvs_cell} | {um / km:.0f}× | {slvs_ratio} |", flush=True)


if __name__ == "__main__":
    main()
