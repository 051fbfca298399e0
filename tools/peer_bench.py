#!/usr/bin/env python3
"""One drag on linear point systems: an ECLES edit through the `ecles` CLI against two peer
constraint solvers, SolveSpace's solver library and kiwisolver (Cassowary), on the same systems.
Prints one Markdown table on standard output (progress goes to standard error).

    pip install py-slvs kiwisolver       # py-slvs is imported as `py_slvs.slvs`
    python3 tools/peer_bench.py [--sizes 10 100 1000] [--systems chain grid parallelograms]
                                [--timeout 60]

The release binary target/release/ecles must exist (`cargo build --release`); this script does
not build it.

Systems (2D points, each point has parameters x and y; all constraints are linear, integer
initial positions satisfy them):

* `chain`: n points p_i = (i, 0); for i = 1 .. n-2, p_i is the midpoint of p_(i-1) and p_(i+1)
  (2 x_i - x_(i-1) - x_(i+1) = 0, same for y).
* `grid`: k × k points, k the integer whose square is closest to n (10 -> 3 × 3 = 9,
  100 -> 10 × 10, 1000 -> 32 × 32 = 1024); point (i, j) of row i and column j starts at
  (x, y) = (j, i); every row is horizontal (y_(i,j) - y_(i,0) = 0) and every column vertical
  (x_(i,j) - x_(0,j) = 0).
* `parallelograms`: a strip of m = n // 2 parallelograms' corners a_i = (2i, 0), b_i = (2i+2, 2),
  i = 0 .. m-1, each quad (a_i, b_i, b_(i+1), a_(i+1)) a parallelogram
  (a_(i+1) - a_i = b_(i+1) - b_i, both coordinates), plus an apex point c, the midpoint of the
  last pair a_(m-1), b_(m-1): 2m + 1 points (11, 101, 1001).

The edit: one point near the middle (chain p_(n//2), grid (k//2, k//2), parallelograms
a_(m//2)) is dragged by (3, -2) and must reach its target exactly; every other point may move.

How each solver does it, and what is timed:

* ecles: a run file with the built-in `linear` source (parameters `x<p>`, `y<p>` of point p,
  one text equation per scalar constraint), `cross_check: None`, and one generic edit: the
  dragged point's x and y as anchors, every other parameter derived (default hints and unit
  weights: the derived values move as little as possible, in exact least squares). The whole
  process `ecles run FILE --quiet --out DIR` is timed, best of 5, with the edit and with the
  same file and `edits: []` (the two alternate); their difference is the cost of the edit
  (process start-up varies by a millisecond or more, so at small sizes the difference is
  within that noise). The run must exit with 0 and its report.json must say the edit is
  solvable, `max_residual` "0", and give the dragged point exactly its target.
* SolveSpace (py-slvs): the points are 2D points of one workplane; chain and apex by
  SLVS_C_AT_MIDPOINT on a line between the neighbours, grid by SLVS_C_HORIZONTAL /
  SLVS_C_VERTICAL between two points, each parallelogram by a helper point at the midpoint of
  both diagonals (2 more unknowns and 4 equations per quad, the same degrees of freedom). The
  dragged point gets its target coordinates and a SLVS_C_WHERE_DRAGGED constraint (this binding
  does not expose the solver's `dragged` list). One `solve` is timed from the initial
  positions each time (parameters are reset between solves, untimed), up to 200 solves
  within about 2 s of solving: the best and the median are reported (a solve's time varies by
  a third from one solve to the next at 10 points; ecles' in-process figures are criterion's
  sample means, see `tools/in_process_vs_peers.py`, which compares like with like). The result must be SLVS_RESULT_OKAY, with the dragged point at
  its target and every scalar equation satisfied to 1e-9. py-slvs 1.0.6 wraps a fork of
  SolveSpace 2.3 whose solver uses dense matrices of at most 2048 unknowns (after its
  substitution of equal parameters): a larger system gets SLVS_RESULT_TOO_MANY_UNKNOWNS.
* kiwisolver: one variable per coordinate, the scalar equations as required constraints (added
  before the stays: the other order makes setup much slower), a weak stay `v == initial` on
  every coordinate, and strong edit variables on the dragged point's x and y. The first
  `suggestValue` + `updateVariables` after setup (the first drag, which does the simplex
  pivoting) is timed once; then 100 solves alternate between the original position and the
  target (each moves every point that follows the drag, but they reuse the optimal basis of
  the first drag), timed each. The result after a target solve must put the dragged point at
  its target and satisfy every scalar equation to 1e-9.

Each peer measurement runs in a child process killed after `--timeout` seconds (default 60;
the cell then says `timeout` and the stage it was in: setup, solve or first drag); each ecles
process is also limited to `--timeout` seconds. A failure (solver error, wrong result, timeout,
crash) is written into its cell instead of a time.

Columns:

* `system`, `points` (number of points), `equations` (scalar linear equations of the ECLES
  and kiwisolver formulation; SolveSpace's parallelograms add helper points and equations);
* `ecles with edit`, `ecles without` (ms): best whole `ecles run` process with the edit and
  with `edits: []`; `ecles per edit` (ms): their difference;
* `SolveSpace per solve, best / median` (ms): the best and the median single `solve`;
* `kiwi per solve` (µs): best / median of the 100 alternating solves; `kiwi first drag` (ms):
  the first solve after setup;
* `per edit / SolveSpace`, `per edit / kiwi`: ecles per edit (a best of whole processes)
  divided by the SolveSpace best per solve and by the kiwi best per solve (above 1: ecles is slower; `–` when a time is missing or the
  per-edit difference is not positive).
"""
import argparse
import json
import math
import multiprocessing
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from functools import cached_property

import kiwisolver
from py_slvs import slvs

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
ECLES = os.path.join(ROOT, "target", "release", "ecles")
SYSTEMS = ("chain", "grid", "parallelograms")
DRAG = (3, -2)
TOLERANCE = 1e-9
ECLES_REPEATS = 5
SLVS_MAX_SOLVES = 200
SLVS_BUDGET_S = 2.0
KIWI_SOLVES = 100
# SolveSpace groups: the workplane is fixed (group 1); the points and constraints are solved
# (group 2).
SLVS_FIXED, SLVS_SOLVED = 1, 2
SLVS_RESULTS = {0: "OKAY", 1: "INCONSISTENT", 2: "DIDNT_CONVERGE", 3: "TOO_MANY_UNKNOWNS"}


@dataclass
class System:
    """Points with integer initial positions, geometric constraints on point indices, and the
    dragged point. Constraints are tuples: ("midpoint", p, a, b): p is the midpoint of a and b;
    ("horizontal", a, b) / ("vertical", a, b): equal y / equal x; ("parallelogram", a0, b0, b1,
    a1): a1 - a0 = b1 - b0."""

    name: str
    points: list
    constraints: list
    dragged: int

    @property
    def target(self):
        """The dragged point's new position."""
        x, y = self.points[self.dragged]
        return x + DRAG[0], y + DRAG[1]

    @cached_property
    def equations(self):
        """The scalar equations `sum coefficient * coordinate = 0`, as {coordinate: coefficient}
        dictionaries; coordinate 2p is x of point p, 2p + 1 its y."""
        return [eq for c in self.constraints for eq in scalar_equations(c)]


def scalar_equations(constraint):
    """The scalar linear equations of one geometric constraint (see `System`)."""
    kind, *p = constraint
    if kind == "midpoint":
        return [{2 * p[0] + k: 2, 2 * p[1] + k: -1, 2 * p[2] + k: -1} for k in (0, 1)]
    if kind == "horizontal":
        return [{2 * p[1] + 1: 1, 2 * p[0] + 1: -1}]
    if kind == "vertical":
        return [{2 * p[1]: 1, 2 * p[0]: -1}]
    a0, b0, b1, a1 = p
    return [{2 * a1 + k: 1, 2 * a0 + k: -1, 2 * b1 + k: -1, 2 * b0 + k: 1} for k in (0, 1)]


def chain(n):
    """n equally spaced points on a line, each inner one the midpoint of its neighbours."""
    points = [(i, 0) for i in range(n)]
    constraints = [("midpoint", i, i - 1, i + 1) for i in range(1, n - 1)]
    return System("chain", points, constraints, n // 2)


def grid(n):
    """A k × k grid (k * k closest to n) with horizontal rows and vertical columns."""
    k = min(range(1, n + 1), key=lambda k: abs(k * k - n))
    points = [(j, i) for i in range(k) for j in range(k)]
    constraints = [("horizontal", i * k, i * k + j) for i in range(k) for j in range(1, k)]
    constraints += [("vertical", j, i * k + j) for i in range(1, k) for j in range(k)]
    return System("grid", points, constraints, (k // 2) * k + k // 2)


def parallelograms(n):
    """A strip of n // 2 point pairs a_i (index 2i), b_i (index 2i + 1) closing parallelograms,
    and an apex at the midpoint of the last pair."""
    m = n // 2
    points = [xy for i in range(m) for xy in ((2 * i, 0), (2 * i + 2, 2))]
    points.append((2 * m - 1, 1))
    constraints = [("parallelogram", 2 * i, 2 * i + 1, 2 * i + 3, 2 * i + 2) for i in range(m - 1)]
    constraints.append(("midpoint", 2 * m, 2 * m - 2, 2 * m - 1))
    return System("parallelograms", points, constraints, 2 * (m // 2))


# Each system's builder, by name.
BUILDERS = {"chain": chain, "grid": grid, "parallelograms": parallelograms}


def check_positions(system, coordinates):
    """None if the dragged point is at its target and every equation holds to TOLERANCE on the
    coordinates (x0, y0, x1, ...), else what is wrong."""
    d = system.dragged
    off = max(abs(coordinates[2 * d + k] - system.target[k]) for k in (0, 1))
    if off > TOLERANCE:
        return f"wrong result: dragged point {off:.1e} off target"
    residual = max(abs(sum(c * coordinates[v] for v, c in eq.items())) for eq in system.equations)
    if residual > TOLERANCE:
        return f"wrong result: residual {residual:.1e}"
    return None


def coordinate_name(v):
    """The parameter name of coordinate v: `x<p>` or `y<p>` of point p = v // 2."""
    return f"{'xy'[v % 2]}{v // 2}"


def equation_text(equation):
    """An equation in the `linear` source's text syntax, such as `2 x1 - x0 - x2 = 0`."""
    terms = [f"{'-' if c < 0 else '+'} {'' if abs(c) == 1 else f'{abs(c)} '}{coordinate_name(v)}"
             for v, c in equation.items()]
    return " ".join(terms).removeprefix("+ ") + " = 0"


def run_file(system, with_edit):
    """The RON run file of the system, with the drag as one ECLES edit or with no edit."""
    names = [coordinate_name(v) for v in range(2 * len(system.points))]
    values = [v for xy in system.points for v in xy]
    parameters = ", ".join(f'"{name}": "{v}"' for name, v in zip(names, values))
    equations = ", ".join(f'"{equation_text(eq)}"' for eq in system.equations)
    edits = ""
    if with_edit:
        d = system.dragged
        anchors = f'"c.x{d}": "{system.target[0]}", "c.y{d}": "{system.target[1]}"'
        derived = ", ".join(f'"c.{name}"' for name in names if name not in (f"x{d}", f"y{d}"))
        edits = f"Ecles(anchors: {{{anchors}}}, derived: [{derived}])"
    return (f'(\n    sources: [(name: "c", plugin: "linear", config: (\n'
            f"        parameters: {{{parameters}}},\n        equations: [{equations}],\n    ))],\n"
            f"    cross_check: None,\n    edits: [{edits}],\n)\n")


def run_ecles(path, out, timeout):
    """Wall time (ms) of one `ecles run` process, or a failure text."""
    start = time.perf_counter()
    try:
        proc = subprocess.run([ECLES, "run", path, "--quiet", "--out", out],
                              capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return f"timeout > {timeout:g} s"
    elapsed = (time.perf_counter() - start) * 1e3
    if proc.returncode != 0:
        message = (proc.stderr.strip().splitlines() or ["no message"])[0]
        return f"exit {proc.returncode}: {message}"
    return elapsed


def check_ecles_report(system, out):
    """None if report.json shows the edit solved exactly with the dragged point at its target,
    else what is wrong."""
    with open(os.path.join(out, "report.json")) as f:
        edit = json.load(f)["edits"][0]
    if not edit["solvable"]:
        return f"not solvable: {edit['error']}"
    if edit["max_residual"] != "0":
        return f"max_residual {edit['max_residual']}"
    values = {v["name"]: v["exact"] for v in edit["values"]}
    d = system.dragged
    if values[f"c.x{d}"] != [str(system.target[0])] or values[f"c.y{d}"] != [str(system.target[1])]:
        return "wrong result: dragged point off target"
    return None


def measure_ecles(system, directory, timeout):
    """ecles best times (ms) with the edit, without it, and their difference, or a failure
    text. The runs with and without the edit alternate, so both see the same machine load."""
    stem = os.path.join(directory, f"{system.name}-{len(system.points)}")
    best = {}
    for label, with_edit in (("with", True), ("without", False)):
        with open(f"{stem}-{label}.ron", "w") as f:
            f.write(run_file(system, with_edit))
        best[label] = math.inf
    for _ in range(ECLES_REPEATS):
        for label in best:
            elapsed = run_ecles(f"{stem}-{label}.ron", f"{stem}-{label}.out", timeout)
            if isinstance(elapsed, str):
                # A completed run that exits with 1 has a report saying why the edit failed.
                if label == "with" and os.path.exists(f"{stem}-with.out/report.json"):
                    return check_ecles_report(system, f"{stem}-with.out") or elapsed
                return f"{label} edit: {elapsed}"
            best[label] = min(best[label], elapsed)
    failure = check_ecles_report(system, f"{stem}-with.out")
    if failure:
        return failure
    return {**best, "per_edit": best["with"] - best["without"]}


def measure_slvs(system, stage):
    """SolveSpace: the best and the median time (ms) of one solve from the initial positions,
    and the number of solves timed, or a failure text. `stage(name)` reports progress to the
    parent process."""
    stage("setup")
    sketch = slvs.System()
    origin = sketch.addPoint3dV(0, 0, 0, SLVS_FIXED)
    normal = sketch.addNormal3dV(*slvs.makeQuaternion(1, 0, 0, 0, 1, 0), SLVS_FIXED)
    plane = sketch.addWorkplane(origin, normal, SLVS_FIXED)
    initial = [(float(x), float(y)) for x, y in system.points]
    entities = [sketch.addPoint2dV(plane, x, y, SLVS_SOLVED) for x, y in initial]
    for kind, *p in system.constraints:
        if kind == "midpoint":
            line = sketch.addLineSegment(entities[p[1]], entities[p[2]], SLVS_SOLVED)
            sketch.addMidPoint(entities[p[0]], line, plane, SLVS_SOLVED)
        elif kind == "horizontal":
            sketch.addPointsHorizontal(entities[p[0]], entities[p[1]], plane, SLVS_SOLVED)
        elif kind == "vertical":
            sketch.addPointsVertical(entities[p[0]], entities[p[1]], plane, SLVS_SOLVED)
        else:
            # A helper point at the midpoint of both diagonals (a0, b1) and (b0, a1).
            a0, b0, b1, a1 = p
            initial.append(tuple((initial[a0][k] + initial[b1][k]) / 2 for k in (0, 1)))
            entities.append(sketch.addPoint2dV(plane, *initial[-1], SLVS_SOLVED))
            for end0, end1 in ((a0, b1), (b0, a1)):
                diagonal = sketch.addLineSegment(entities[end0], entities[end1], SLVS_SOLVED)
                sketch.addMidPoint(entities[-1], diagonal, plane, SLVS_SOLVED)
    sketch.addWhereDragged(entities[system.dragged], plane, SLVS_SOLVED)
    handles = [(sketch.getEntityParam(e, 0), sketch.getEntityParam(e, 1)) for e in entities]
    times = []
    while len(times) < SLVS_MAX_SOLVES and sum(times) < SLVS_BUDGET_S:
        for (hx, hy), (x, y) in zip(handles, initial):
            sketch.getParam(hx).val, sketch.getParam(hy).val = x, y
        hx, hy = handles[system.dragged]
        sketch.getParam(hx).val, sketch.getParam(hy).val = system.target
        stage("solve")
        start = time.perf_counter()
        result = sketch.solve(SLVS_SOLVED)
        times.append(time.perf_counter() - start)
        if result != 0:
            return f"result {SLVS_RESULTS.get(result, result)} ({2 * len(entities)} unknowns)"
        coordinates = [sketch.getParam(h).val
                       for pair in handles[:len(system.points)] for h in pair]
        failure = check_positions(system, coordinates)
        if failure:
            return failure
    return {"ms": min(times) * 1e3, "median_ms": statistics.median(times) * 1e3,
            "solves": len(times)}


def measure_kiwi(system, stage):
    """kiwisolver: the first drag (ms) and the best and median (µs) of KIWI_SOLVES alternating
    solves, or a failure text. `stage(name)` reports progress to the parent process."""
    stage("setup")
    solver = kiwisolver.Solver()
    variables = [kiwisolver.Variable(coordinate_name(v)) for v in range(2 * len(system.points))]
    for eq in system.equations:
        solver.addConstraint(sum(c * variables[v] for v, c in eq.items()) == 0)
    initial = [v for xy in system.points for v in xy]
    for variable, value in zip(variables, initial):
        solver.addConstraint((variable == value) | "weak")
    dragged = variables[2 * system.dragged:2 * system.dragged + 2]
    for variable in dragged:
        solver.addEditVariable(variable, "strong")

    def solve(position):
        """Suggests the dragged point's position and solves; returns the time in seconds."""
        start = time.perf_counter()
        for variable, value in zip(dragged, position):
            solver.suggestValue(variable, value)
        solver.updateVariables()
        return time.perf_counter() - start

    stage("first drag")
    first = solve(system.target)
    failure = check_positions(system, [v.value() for v in variables])
    if failure:
        return failure
    stage("solve")
    positions = (system.points[system.dragged], system.target)
    times = [solve(positions[i % 2]) for i in range(KIWI_SOLVES)]
    failure = check_positions(system, [v.value() for v in variables])
    if failure:
        return failure
    return {"first_ms": first * 1e3, "best_us": min(times) * 1e6,
            "median_us": statistics.median(times) * 1e6}


def child(measure, system, conn):
    """Runs a measurement in a child process and sends its stages and result through conn."""
    try:
        result = measure(system, lambda name: conn.send(("stage", name)))
    except Exception as error:  # a solver error becomes a table cell, not a crash
        result = f"{type(error).__name__}: {error}"
    conn.send(("done", result))


def run_isolated(measure, system, timeout):
    """The result of measure(system, stage) run in a child process, or a failure text if it
    does not finish within timeout seconds or dies."""
    context = multiprocessing.get_context("fork")
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(target=child, args=(measure, system, sender))
    process.start()
    sender.close()
    deadline = time.monotonic() + timeout
    stage = "start"
    try:
        while True:
            if not receiver.poll(max(0.0, deadline - time.monotonic())):
                process.terminate()
                return f"timeout > {timeout:g} s ({stage})"
            try:
                kind, payload = receiver.recv()
            except EOFError:
                process.join()
                return f"crashed (exit code {process.exitcode})"
            if kind == "done":
                return payload
            stage = payload
    finally:
        process.join()
        receiver.close()


def number(x):
    """A time or ratio with three significant digits or so (whole numbers from 100 up)."""
    size = abs(x)
    if size >= 100:
        return f"{x:.0f}"
    return f"{x:.1f}" if size >= 10 else f"{x:.2f}" if size >= 1 else f"{x:.3g}"


def failure_cell(text):
    """A failure as a bold table cell."""
    return "**" + text.replace("|", "\\|").replace("\n", " ") + "**"


def ratio(a, b):
    """a / b as `r×`, or `–` when either is missing or a is not positive (a per-edit time
    within the noise of process start-up)."""
    return "–" if a is None or b is None or a <= 0 else f"{number(a / b)}×"


def row(system, ecles, solvespace, kiwi):
    """One table row from the three measurements (dicts of times, or failure texts)."""
    cells = [system.name, str(len(system.points)), str(len(system.equations))]
    if isinstance(ecles, str):
        cells += [failure_cell(ecles), "", ""]
        per_edit = None
    else:
        per_edit = ecles["per_edit"]
        cells += [number(ecles["with"]), number(ecles["without"]), number(per_edit)]
    slvs_ms = None if isinstance(solvespace, str) else solvespace["ms"]
    cells.append(failure_cell(solvespace) if slvs_ms is None
                 else f"{number(slvs_ms)} / {number(solvespace['median_ms'])}")
    if isinstance(kiwi, str):
        cells += [failure_cell(kiwi), ""]
        kiwi_ms = None
    else:
        cells += [f"{number(kiwi['best_us'])} / {number(kiwi['median_us'])}",
                  number(kiwi["first_ms"])]
        kiwi_ms = kiwi["best_us"] / 1e3
    cells += [ratio(per_edit, slvs_ms), ratio(per_edit, kiwi_ms)]
    return "| " + " | ".join(cells) + " |"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 100, 1000],
                        help="numbers of points (default: 10 100 1000)")
    parser.add_argument("--systems", nargs="+", choices=SYSTEMS, default=list(SYSTEMS),
                        help="systems to run (default: all)")
    parser.add_argument("--timeout", type=float, default=60.0,
                        help="seconds allowed per peer measurement and per ecles process "
                             "(default: 60)")
    args = parser.parse_args()
    lines = ["| system | points | equations | ecles with edit (ms) | ecles without (ms) | "
             "ecles per edit (ms) | SolveSpace per solve, best / median (ms) | "
             "kiwi per solve, best / median (µs) | "
             "kiwi first drag (ms) | per edit / SolveSpace | per edit / kiwi |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    with tempfile.TemporaryDirectory() as directory:
        for name in args.systems:
            for n in args.sizes:
                system = BUILDERS[name](n)
                print(f"{name}, {len(system.points)} points: ecles", file=sys.stderr, flush=True)
                ecles = measure_ecles(system, directory, args.timeout)
                print("  SolveSpace", file=sys.stderr, flush=True)
                solvespace = run_isolated(measure_slvs, system, args.timeout)
                print("  kiwisolver", file=sys.stderr, flush=True)
                kiwi = run_isolated(measure_kiwi, system, args.timeout)
                lines.append(row(system, ecles, solvespace, kiwi))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
