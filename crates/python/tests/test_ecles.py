"""The `ecles` Python package, end to end: the thesis examples exactly, values beyond 64 bits,
refusals with their labels, bad input, agreement with python-flint on random systems, and
property tests (hypothesis) that every update satisfies every equation exactly.

Run from a checkout: `pip install ./crates/python pytest hypothesis python-flint` then
`pytest crates/python/tests`.
"""

import json
import random
import subprocess
from fractions import Fraction
from pathlib import Path

import flint
import pytest
from hypothesis import given, settings, strategies as st

import ecles

ROOT = Path(__file__).resolve().parents[3]

# Matrix (4.3) of the thesis and the right-hand side of (8.17).
A_4_3 = [[4, 9, 16, 29], [-1, -6, -19, -16], [1, 5, 15, 19], [5, 6, -1, -12], [5, 10, 15, 20]]
B_8_17 = [142, 42, 40, -128, 50]


def pumps():
    """The pump example (thesis 2.2): p1 + p2 = p3, p4 = p3 + 5."""
    return ecles.System.from_equations(
        {"p1": 1, "p2": 2, "p3": 3, "p4": 8},
        ["p1 + p2 - p3 = 0", "p4 - p3 = 5"],
        source="pump",
    )


def test_matrix_4_3_has_rank_3_and_one_redundant_row_with_its_combination():
    # A basic solution of (8.17) as the values: the system is satisfied.
    s = ecles.System.from_matrix(
        A_4_3, B_8_17, values=[59, Fraction(-95, 2), 0, Fraction(23, 2)], source="t"
    )
    a = s.analyze()
    assert (a.rank, a.dof, a.consistent) == (3, 1, True)
    assert a.conflict is None
    assert len(a.redundant) == 2
    assert all(r["combination"] for r in a.redundant)
    assert a.to_dict()["satisfied"] is True
    assert s.values["t.p1"] == Fraction(-95, 2)


def test_least_squares_9_13_exactly():
    # With p0 at its least-squares value 3/2, the others follow hints (1, 1, 1): P'' of (9.13).
    s = ecles.System.from_matrix(
        A_4_3, B_8_17, values=[59, Fraction(-95, 2), 0, Fraction(23, 2)], source="t"
    )
    e = s.edit(
        anchors={"t.p0": Fraction(3, 2)},
        derived=["t.p1", "t.p2", "t.p3"],
        hints={"t.p1": 1, "t.p2": 1, "t.p3": 1},
    )
    out = e.update()
    assert [out[f"t.p{i}"] for i in range(4)] == [
        Fraction(3, 2),
        Fraction(-3, 2),
        Fraction(-23, 2),
        Fraction(23, 2),
    ]


def test_the_pump_edit_and_its_refusal_with_the_constraint_in_the_way():
    s = pumps()
    e = s.edit(anchors={"pump.p1": 4}, derived=["pump.p2", "pump.p3", "pump.p4"])
    assert e.update() == {
        "pump.p1": 4,
        "pump.p2": 0,
        "pump.p3": 4,
        "pump.p4": 9,
    }
    # Weights: p2 five times as heavy moves less (p2 = 8/7).
    w = s.edit(
        anchors={"pump.p1": 4},
        derived=["pump.p2", "pump.p3", "pump.p4"],
        weights={"pump.p2": 5},
    )
    assert w.update()["pump.p2"] == Fraction(8, 7)
    assert w.preview()["pump.p2"] == (8 / 7,)
    # p4 fixed: p3 cannot move alone.
    blocked = s.edit(anchors={"pump.p3": 10}, derived=["pump.p2"])
    with pytest.raises(ecles.Unsolvable) as refused:
        blocked.update()
    assert any("p4 - p3 = 5" in label for label in refused.value.labels)
    assert refused.value.explanation
    # Nothing changed; an applied edit changes the values and undo restores them.
    assert s.values["pump.p3"] == 3
    assert e.apply()["pump.p4"] == 9
    assert s.values["pump.p4"] == 9
    assert s.undo() is True
    assert s.values["pump.p4"] == 8


def test_values_beyond_64_bits_round_trip_exactly():
    big = Fraction(2**200 + 1, 3**90)
    s = ecles.System.from_equations({"a": big, "b": -big}, ["a + b = 0"], source="x")
    assert s.values["x.a"] == big
    e = s.edit(anchors={"x.a": big * 7}, derived=["x.b"])
    assert e.update()["x.b"] == -big * 7
    # Integers of any size in a matrix.
    huge = 10**40 + 7
    m = ecles.System.from_matrix([[huge, 1]], [huge], values=[1, 0])
    assert m.analyze().consistent
    # numpy: int64 arrays, and object arrays of Python ints beyond 64 bits.
    np = pytest.importorskip("numpy")
    m = ecles.System.from_matrix(np.array([[huge, 1]], dtype=object), np.array([huge], dtype=object),
                                 values=np.array([1, 0], dtype=np.int64))
    assert m.analyze().to_dict()["satisfied"] is True
    with pytest.raises(TypeError, match="not exact"):
        ecles.System.from_matrix(np.array([[1.5, 1.0]]), [1])


def test_bad_input_raises_the_right_exceptions_with_the_item_named():
    with pytest.raises(ecles.InputError, match="coefficients must be integers"):
        ecles.System.from_equations({"a": 0}, ["0.5 a = 1"])
    s = pumps()
    with pytest.raises(ecles.InputError, match="pump.p9"):
        s.edit(anchors={"pump.p9": 1}, derived=["pump.p2"])
    with pytest.raises(TypeError, match="not exact"):
        s.edit(anchors={"pump.p1": 0.1}, derived=["pump.p2"])
    with pytest.raises(ecles.InputError, match="criterion"):
        s.edit(anchors={"pump.p1": 1}, derived=["pump.p2"], criterion="L3")
    with pytest.raises(ecles.InputError, match="hints belong to least squares"):
        s.edit(
            anchors={"pump.p1": 1}, derived=["pump.p2"], hints={"pump.p2": 1}, criterion="L1"
        )
    with pytest.raises(ecles.InputError, match="no/such.ron"):
        ecles.System.from_run_file("no/such.ron")
    # A run file's error names its line and column.
    with pytest.raises(ecles.InputError, match=r"equations:1:\d+"):
        ecles.System.from_equations({"a": 0}, ["a = = 1"])


def test_a_run_file_and_brenners_fewest_changed_edit_agree_with_the_cli(tmp_path):
    s = ecles.System.from_run_file(ROOT / "examples" / "brenner.ron")
    assert s.parameters["h.x1"] == 1
    derived = [f"h.{n}" for n in "x2 y2 x3 y3 a1 b1 c1 a2 b2 c2".split()]
    points = ["h.x2", "h.y2", "h.x3", "h.y3"]
    e = s.edit(
        anchors={"h.x1": 1, "h.y1": 0}, derived=derived, criterion="Fewest", primary=points
    )
    ours = e.update()
    report = tmp_path / "out"
    subprocess.run(
        ["cargo", "run", "--release", "-q", "-p", "host", "--", "run",
         str(ROOT / "examples" / "brenner.ron"), "--quiet", "--out", str(report)],
        cwd=ROOT, check=True,
    )
    cli = json.loads((report / "report.json").read_text())["edits"][4]["values"]
    assert {v["name"]: Fraction(v["exact"][0]) for v in cli} == ours
    # Vector parameters come back as tuples.
    worm = ecles.System.from_run_file(ROOT / "examples" / "worm.ron")
    assert worm.values["worm.v3"] == (36, 17)


def random_system(rng, rows, cols, bound=3):
    return [[rng.randint(-bound, bound) for _ in range(cols)] for _ in range(rows)]


@pytest.mark.parametrize("seed", range(40))
def test_rank_and_consistency_agree_with_python_flint(seed):
    rng = random.Random(seed)
    rows, cols = rng.randint(1, 7), rng.randint(1, 7)
    A = random_system(rng, rows, cols)
    # Consistent half of the time (b = A x), else an arbitrary b.
    if seed % 2 == 0:
        x = [rng.randint(-5, 5) for _ in range(cols)]
        b = [sum(a * v for a, v in zip(row, x)) for row in A]
    else:
        b = [rng.randint(-9, 9) for _ in range(rows)]
    a = ecles.System.from_matrix(A, b).analyze()
    rank = flint.fmpz_mat(A).rank()
    augmented = flint.fmpz_mat([row + [v] for row, v in zip(A, b)]).rank()
    assert a.rank == rank
    assert a.consistent == (augmented == rank)


@settings(max_examples=40, deadline=None)
@given(
    st.integers(1, 4).flatmap(
        lambda rows: st.tuples(
            st.lists(st.lists(st.integers(-3, 3), min_size=5, max_size=5), min_size=rows,
                     max_size=rows),
            st.lists(st.integers(-4, 4), min_size=5, max_size=5),
            st.fractions(min_value=-10, max_value=10, max_denominator=50),
            st.sampled_from(["L2", "L1", "Fewest"]),
        )
    )
)
def test_every_update_satisfies_every_equation_exactly(case):
    A, x0, move, criterion = case
    b = [sum(a * v for a, v in zip(row, x0)) for row in A]
    s = ecles.System.from_matrix(A, b, values=x0)
    names = [f"m.p{i}" for i in range(5)]
    e = s.edit(anchors={names[0]: x0[0] + move}, derived=names[1:], criterion=criterion)
    try:
        out = e.update()
    except ecles.Unsolvable as refused:
        assert refused.labels
        return
    values = [out[n] for n in names]
    for row, rhs in zip(A, b):
        assert sum(a * v for a, v in zip(row, values)) == rhs


def grid_mesh(n=4, cell=10):
    """An (n+1)² grid of vertices `cell` apart, each square split by its rising diagonal."""
    vertices = [(cell * i, cell * j) for j in range(n + 1) for i in range(n + 1)]
    triangles = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            c, d = a + n + 1, b + n + 1
            triangles += [(a, b, d), (a, d, c)]
    return vertices, triangles


def cli_deformed_model(tmp_path, source_config, edit, model):
    """Runs `ecles run` on one source (`source_config`: its `(name: ..., ...)` entry), one
    edit and the model (rows x y z) as an OBJ output; returns the deformed OBJ's vertices and
    the report."""
    obj = tmp_path / "model.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in model) + "f 1 2 3\n")
    name = source_config.split('"')[1]
    run = tmp_path / "run.ron"
    run.write_text(
        f"(sources: [{source_config}], cross_check: None, edits: [{edit}], "
        f'outputs: [(source: "{name}", output: (model: "model.obj"))])'
    )
    subprocess.run(
        ["cargo", "run", "--release", "-q", "-p", "host", "--", "run", str(run), "--quiet",
         "--out", str(tmp_path / "out")],
        cwd=ROOT, check=True,
    )
    vertices = [
        [float(c) for c in line.split()[1:]]
        for line in (tmp_path / "out" / "model-deformed.obj").read_text().splitlines()
        if line.startswith("v ")
    ]
    return vertices, json.loads((tmp_path / "out" / "report.json").read_text())


def inline_mesh(vertices, triangles):
    points = ", ".join(f'("{x}", "{y}")' for x, y in vertices)
    faces = ", ".join(f"({a}, {b}, {c})" for a, b, c in triangles)
    return f"mesh: (vertices: [{points}], triangles: [{faces}])"


def test_a_spline_from_numpy_arrays_translates_exactly_and_deforms_like_the_cli(tmp_path):
    np = pytest.importorskip("numpy")
    vertices, triangles = grid_mesh()
    s = ecles.Spline2d(np.array(vertices, dtype=np.int64), np.array(triangles), degree=5,
                       smoothness=1, name="g")
    anchors, derived = s.select(["v12"], neighborhood=2)
    assert anchors == ["g.v12"] and len(derived) > 0
    # Before any edit psi is the identity: evaluate gives the points back and deform returns
    # every vertex exactly as given (no float noise on what does not move).
    model = np.array([[3.25, 7.5, 1.0], [21.0, 19.0, -2.0], [40.0, 40.0, 0.5], [55.0, 1.0, 0.0]])
    with pytest.warns(UserWarning, match="1 of 4 vertices lie outside"):
        same = s.deform(model)
    assert np.array_equal(same, model)
    out = s.translate(["v12"], (Fraction(5, 2), -4), neighborhood=2)
    assert out["g.v12"] == (Fraction(45, 2), 16)
    assert s.analyze().to_dict()["satisfied"] is True
    # psi at the vertex is the vertex's control point.
    at = s.evaluate(np.array([[20.0, 20.0], [-5.0, 0.0]]))
    assert at[0].tolist() == [22.5, 16.0]
    assert np.isnan(at[1]).all()
    # The same edit through the CLI, with the model deformed into an OBJ.
    cli, report = cli_deformed_model(
        tmp_path,
        f'(name: "g", plugin: "spline2d", config: ({inline_mesh(vertices, triangles)}, '
        "degree: 5, smoothness: 1))",
        'Source(source: "g", operation: (anchors: ["v12"], neighborhood: 2, '
        'translate: ("5/2", "-4")))',
        model[:3],
    )
    ours = s.deform(model[:3])
    assert np.allclose(ours, np.array(cli), rtol=0, atol=1e-12)
    # Every value is exact and the CLI committed the same.
    for v in report["edits"][0]["values"]:
        assert s.values[v["name"]] == tuple(Fraction(t) for t in v["exact"])


def test_spline_operations_take_criteria_and_refuse_floats():
    vertices, triangles = grid_mesh()
    s = ecles.Spline2d(vertices, triangles, degree=3, smoothness=1, name="g")
    before = s.values
    out = s.rotate(["v12"], center=(20, 20), degrees=30, neighborhood=2, criterion="Fewest")
    moved = [n for n in out if out[n] != before[n]]
    assert "g.v12" not in moved  # rotating about itself leaves the vertex in place
    assert s.analyze().to_dict()["satisfied"] is True
    s.scale(["v6"], center=(0, 0), factor=Fraction(3, 2), neighborhood=1, criterion="L1")
    assert s.analyze().to_dict()["satisfied"] is True
    with pytest.raises(TypeError, match="not exact"):
        ecles.Spline2d([(0.5, 0), (1, 0), (0, 1)], [(0, 1, 2)])
    with pytest.raises(ecles.InputError):
        ecles.Spline2d([(0, 0), (1, 0), (2, 0)], [(0, 1, 2)])  # zero area


def test_a_keyboard_interrupt_stops_waiting_for_a_long_analysis():
    import _thread
    import threading
    import time

    rng = random.Random(1)
    n = 110
    A = [[rng.randint(-10**12, 10**12) for _ in range(n)] for _ in range(n)]
    s = ecles.System.from_matrix(A, [0] * n)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        s.analyze()  # seconds of exact elimination
    assert time.monotonic() - start < 2.0
    # The session still answers (after the abandoned analysis finishes on its thread).
    assert s.parameters["m.p0"] == 1


def test_a_terrain_lift_from_a_run_file_is_exact():
    t = ecles.System.from_run_file(ROOT / "examples" / "terrain.ron")
    lift = '(mode: "z1", anchors: ["v4"], neighborhood: 3, dz: "16")'
    anchors, derived = t.plan("terrain", lift)
    assert anchors == ["terrain.top.v4"] and derived
    before = t.values["terrain.top.v4"]
    out = t.operate("terrain", lift, criterion="Fewest")
    assert out["terrain.top.v4"] == before + 16
    assert t.analyze().to_dict()["satisfied"] is True
    with pytest.raises(ecles.InputError, match="terrain"):
        t.operate("terrain", '(mode: "z7", anchors: ["v4"], dz: "1")')


def test_a_terrain_from_numpy_arrays_lifts_exactly_and_deforms_like_the_cli(tmp_path):
    np = pytest.importorskip("numpy")
    vertices, triangles = grid_mesh(3, 10)
    t = ecles.Terrain(np.array(vertices), np.array(triangles), top=10, bottom=0, degree=3,
                      name="hills")
    model = np.array([[12.5, 7.5, 10.0], [15.0, 15.0, 5.0], [2.0, 2.0, 0.0], [9.0, 9.0, 11.0]])
    with pytest.warns(UserWarning, match="1 of 4 vertices lie outside"):
        same = t.deform(model)
    assert np.array_equal(same, model)
    out = t.lift(["v5"], dz=Fraction(7, 2), neighborhood=2)
    assert out["hills.top.v5"] == Fraction(27, 2)
    assert t.analyze().to_dict()["satisfied"] is True
    heights = t.heights(np.array([[10.0, 10.0], [50.0, 0.0]]))
    assert heights[0].tolist() == [0.0, 13.5]
    assert np.isnan(heights[1]).all()
    # The same lift through the CLI with the model as an OBJ.
    cli, _ = cli_deformed_model(
        tmp_path,
        f'(name: "hills", plugin: "terrain", config: (spline: ({inline_mesh(vertices, triangles)}, '
        'degree: 3, smoothness: 1), top: "10", bottom: "0"))',
        'Source(source: "hills", operation: (mode: "z1", anchors: ["v5"], neighborhood: 2, '
        'dz: "7/2"))',
        model[:3],
    )
    assert np.allclose(t.deform(model[:3]), np.array(cli), rtol=0, atol=1e-12)
