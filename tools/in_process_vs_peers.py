#!/usr/bin/env python3
"""A whole exact ecles edit in process against one solve of SolveSpace and of kiwisolver, on
the same point systems as tools/peer_bench.py, in the same minutes, like with like.

    python3 tools/in_process_vs_peers.py [--sizes 10 100] [--measurement-time 3]

(py-slvs and kiwisolver installed, see tools/peer_bench.py.)

What is timed:

* ecles: the `run_edit` criterion bench (`crates/benchmarks/benches/run_edit.rs`: plan,
  Initialize, Update, the report's propagation analysis and structure, value text, commit and
  the report's JSON, each edit in a fresh session), run by `cargo bench` with the given
  measurement time. Each of criterion's samples is the mean of its iterations; the table gives
  the fastest sample and the median sample, per edit (read from criterion's `sample.json`).
* SolveSpace: `peer_bench.measure_slvs` (up to 200 solves from the initial positions): the
  fastest and the median single `solve`.
* kiwisolver: `peer_bench.measure_kiwi` (100 alternating `suggestValue` + `updateVariables`):
  the fastest and the median.

The ratios divide ecles' best by SolveSpace's best and ecles' median by SolveSpace's median.
(A criterion sample averages several edits, so ecles' best is, if anything, pessimistic against
a single fastest solve.)
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_bench  # noqa: E402  (the systems and the peers' measurements)

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
CRITERION = os.path.join(ROOT, "target", "criterion", "run-edit", "exact")


def bench_id(name, n):
    """The `run_edit` bench's id of a system (the parallelograms take one point more)."""
    return f"{name}{n + 1 if name == 'parallelograms' else n}"


def run_bench(ids, measurement_time):
    """Runs the `run_edit` bench for `ids` (criterion writes its samples under target/)."""
    pattern = "exact/(" + "|".join(ids) + ")$"
    subprocess.run(["cargo", "bench", "-q", "-p", "benchmarks", "--bench", "run_edit", "--",
                    "--warm-up-time", "1", "--measurement-time", str(measurement_time),
                    pattern], cwd=ROOT, check=True, stdout=subprocess.DEVNULL)


def ecles_per_edit(bench):
    """(best, median) of criterion's samples of `bench`, µs per edit."""
    with open(os.path.join(CRITERION, bench, "new", "sample.json")) as f:
        sample = json.load(f)
    per_edit = [t / i / 1e3 for t, i in zip(sample["times"], sample["iters"])]
    return min(per_edit), statistics.median(per_edit)


def cell(pair):
    """`best / median` of a pair of times in µs."""
    return " / ".join(peer_bench.number(x) for x in pair)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10],
                        help="numbers of points (default: 10; the bench has 10 and 100)")
    parser.add_argument("--measurement-time", type=float, default=3.0,
                        help="criterion's measurement time per bench, s (default: 3)")
    parser.add_argument("--timeout", type=float, default=60.0,
                        help="seconds allowed per peer measurement (default: 60)")
    args = parser.parse_args()
    cases = [(name, n) for name in peer_bench.SYSTEMS for n in args.sizes]
    print("ecles: the run_edit bench", file=sys.stderr, flush=True)
    run_bench([bench_id(name, n) for name, n in cases], args.measurement_time)
    lines = ["| system | points | ecles whole edit, best / median (µs) | "
             "SolveSpace solve, best / median (µs) | kiwi `suggestValue`, best / median (µs) | "
             "ecles / SolveSpace, best | ecles / SolveSpace, median |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for name, n in cases:
        system = peer_bench.BUILDERS[name](n)
        print(f"{name}, {len(system.points)} points: peers", file=sys.stderr, flush=True)
        ours = ecles_per_edit(bench_id(name, n))
        slvs = peer_bench.run_isolated(peer_bench.measure_slvs, system, args.timeout)
        kiwi = peer_bench.run_isolated(peer_bench.measure_kiwi, system, args.timeout)
        cells = [name, str(len(system.points)), cell(ours)]
        if isinstance(slvs, str):
            cells += [peer_bench.failure_cell(slvs)]
            ratios = ["–", "–"]
        else:
            theirs = (slvs["ms"] * 1e3, slvs["median_ms"] * 1e3)
            cells.append(cell(theirs))
            ratios = [f"{peer_bench.number(a / b)}×" for a, b in zip(ours, theirs)]
        cells.append(peer_bench.failure_cell(kiwi) if isinstance(kiwi, str)
                     else cell((kiwi["best_us"], kiwi["median_us"])))
        lines.append("| " + " | ".join(cells + ratios) + " |")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
