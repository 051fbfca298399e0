"""Exact constraint analysis and ECLES edits from Python.

Values are exact: ``int`` and ``fractions.Fraction`` in and out (decimal strings such as
``"0.1"`` are read exactly as 1/10); a ``float`` where an exact value is needed is refused
with ``TypeError``. The work is done by the Rust host library (the same code as the ``ecles``
command), with the GIL released.

>>> import ecles
>>> s = ecles.System.from_equations({"p1": 1, "p2": 2, "p3": 3, "p4": 8},
...                                 ["p1 + p2 - p3 = 0", "p4 - p3 = 5"], source="pump")
>>> e = s.edit(anchors={"pump.p1": 4}, derived=["pump.p2", "pump.p3", "pump.p4"])
>>> e.update()["pump.p2"]
Fraction(0, 1)
"""

from __future__ import annotations

import json
import re
import warnings
from fractions import Fraction
from numbers import Integral
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

from . import _ecles
from ._ecles import InputError

__all__ = ["System", "Spline2d", "Terrain", "Edit", "Analysis", "InputError", "Unsolvable", "Exact"]

Exact = Union[int, Fraction, str]
Value = Union[Fraction, Tuple[Fraction, ...]]


class Unsolvable(ValueError):
    """An edit the constraints forbid, with the constraints in the way.

    ``labels`` are the labels of the conflicting rows (a minimal set, with the exact
    certificate), ``explanation`` the lines ``ecles`` prints to say why.
    """

    def __init__(self, message: str, labels: Sequence[str], explanation: Sequence[str]):
        super().__init__(message)
        self.labels: List[str] = list(labels)
        self.explanation: List[str] = list(explanation)


def _text(value: Any, what: str) -> str:
    """The exact text of ``value``: an integer, a Fraction or a decimal/fraction string."""
    if isinstance(value, bool):
        raise TypeError(f"{what}: {value!r} is a bool, not a number")
    if isinstance(value, Integral):
        return str(int(value))
    if isinstance(value, Fraction):
        return f"{value.numerator}/{value.denominator}"
    if isinstance(value, str):
        return value
    if isinstance(value, float):
        raise TypeError(
            f"{what}: {value!r} is a float, which is not exact; pass an int, a Fraction "
            f"or a decimal string such as '0.1'"
        )
    # numpy integers and object arrays of Python ints.
    if hasattr(value, "dtype") and getattr(value.dtype, "kind", "") in "iu":
        return str(int(value))
    raise TypeError(f"{what}: {value!r} is not an exact number")


def _texts(value: Any, what: str) -> List[str]:
    """A parameter's value as text: a number, or a sequence of numbers (a point)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        return [_text(value, what)]
    return [_text(v, what) for v in value]


def _value(pairs: Sequence[Tuple[int, int]]) -> Value:
    """A parameter's exact value from its coordinates as (numerator, denominator) in lowest
    terms: a Fraction, or a tuple of them for a point."""
    values = tuple(Fraction(n, d) for n, d in pairs)
    return values[0] if len(values) == 1 else values


def _raising(call, *args, **kwargs):
    """Calls into the native module, turning its refusal into :class:`Unsolvable`."""
    try:
        return call(*args, **kwargs)
    except _ecles.Unsolvable as e:
        message, labels, explanation = e.args
        raise Unsolvable(message, labels, explanation) from None


class Analysis:
    """The analysis of a whole system, as ``ecles analyze --json`` gives it."""

    def __init__(self, report: Dict[str, Any]):
        self._report = report

    @property
    def rank(self) -> int:
        """Exact rank of the constraint matrix, in scalar equations."""
        return self._report["rank"]

    @property
    def dof(self) -> int:
        """Degrees of freedom: scalar unknowns minus the rank."""
        return self._report["dof"]

    @property
    def consistent(self) -> bool:
        """Whether some values satisfy every constraint."""
        return self._report["consistent"]

    @property
    def redundant(self) -> List[Dict[str, Any]]:
        """Redundant rows, each with the exact combination of others it equals."""
        return self._report["redundant"]

    @property
    def conflict(self) -> Optional[List[str]]:
        """Labels of contradicting rows, when the system is inconsistent."""
        return self._report["conflict"]

    @property
    def structure(self) -> Optional[Dict[str, Any]]:
        """Dulmage–Mendelsohn parts and blocks, structural and exact rank."""
        return self._report["structure"]

    def to_dict(self) -> Dict[str, Any]:
        """The whole report (the fields of ``report.json``)."""
        return json.loads(json.dumps(self._report))

    def __repr__(self) -> str:
        return (
            f"Analysis(rank={self.rank}, dof={self.dof}, consistent={self.consistent}, "
            f"redundant={len(self.redundant)})"
        )


class Edit:
    """An initialised ECLES edit (Initialize done): update it as often as needed."""

    def __init__(self, native: Any):
        self._native = native
        self.anchors, self.derived, self.rank = native.describe()

    @staticmethod
    def _pairs(values: Optional[Mapping[str, Any]], what: str):
        if values is None:
            return None
        return [(name, _texts(v, f"{what} {name}")) for name, v in values.items()]

    def update(
        self,
        anchors: Optional[Mapping[str, Any]] = None,
        hints: Optional[Mapping[str, Any]] = None,
    ) -> Dict[str, Value]:
        """ECLES.Update: exact values of the anchors and derived parameters.

        ``anchors`` gives every anchor a new value (default: the edit's); ``hints`` any derived
        parameters' hints. Raises :class:`Unsolvable` when the anchors cannot go there.
        """
        out = _raising(
            self._native.update, self._pairs(anchors, "anchor"), self._pairs(hints, "hint")
        )
        return {name: _value(pairs) for name, pairs in out}

    def preview(
        self,
        anchors: Optional[Mapping[str, Any]] = None,
        hints: Optional[Mapping[str, Any]] = None,
    ) -> Dict[str, Tuple[float, ...]]:
        """The same verdict as :meth:`update`, the values as floats (for drawing)."""
        out = _raising(
            self._native.preview, self._pairs(anchors, "anchor"), self._pairs(hints, "hint")
        )
        return {name: tuple(v) for name, v in out}

    def apply(
        self,
        anchors: Optional[Mapping[str, Any]] = None,
        hints: Optional[Mapping[str, Any]] = None,
    ) -> Dict[str, Value]:
        """Commits an update into the system's values (``System.undo`` restores them)."""
        out = _raising(
            self._native.apply, self._pairs(anchors, "anchor"), self._pairs(hints, "hint")
        )
        return {name: _value(pairs) for name, pairs in out}

    def __repr__(self) -> str:
        return f"Edit(anchors={self.anchors}, derived={len(self.derived)}, rank={self.rank})"


class System:
    """A constraint system with exact current values, built by the ``ecles`` host."""

    def __init__(self, native: Any):
        self._native = native

    @classmethod
    def from_matrix(
        cls,
        A: Iterable[Iterable[Any]],
        b: Iterable[Any],
        names: Optional[Sequence[str]] = None,
        values: Optional[Iterable[Any]] = None,
        source: str = "m",
    ) -> "System":
        """``A p = b`` over integers (Python ints of any size, numpy integer arrays or object
        arrays of ints); parameters named ``{source}.{name}`` (default names ``p0``, ``p1``…),
        with exact initial values (default 0)."""
        matrix = [[_text(a, "matrix entry") for a in row] for row in A]
        rhs = [_text(v, "right-hand side") for v in b]
        vals = None if values is None else [_text(v, "value") for v in values]
        return cls(
            _ecles.Session.from_matrix(
                matrix, rhs, None if names is None else list(names), vals, source
            )
        )

    @classmethod
    def from_equations(
        cls, parameters: Mapping[str, Any], equations: Sequence[str], source: str = "eq"
    ) -> "System":
        """Parameters (name → exact initial value, in order) and integer linear equations
        (``"p1 + 2 p2 = 3"``), as the ``linear`` source reads them."""
        params = [(name, _text(v, f"value of {name}")) for name, v in parameters.items()]
        return cls(_ecles.Session.from_equations(params, list(equations), source))

    @classmethod
    def from_run_file(cls, path: str, max_input_bytes: int = 256 << 20) -> "System":
        """The sources of a RON run file (its edits are not run)."""
        return cls(_ecles.Session.from_run_file(str(path), max_input_bytes))

    def analyze(self) -> Analysis:
        """Exact rank, consistency, redundant rows, conflicts and structure."""
        return Analysis(json.loads(self._native.analyze()))

    @property
    def parameters(self) -> Dict[str, int]:
        """Parameter name → dimension, in id order."""
        return dict(self._native.parameters())

    @property
    def values(self) -> Dict[str, Value]:
        """Parameter name → exact current value (a Fraction, or a tuple for points)."""
        return {name: _value(pairs) for name, pairs in self._native.values()}

    def explain(self, name: str) -> List[str]:
        """Why a parameter (or coordinate ``name[k]``) is fixed, limited or free."""
        return self._native.explain(name)

    def edit(
        self,
        anchors: Mapping[str, Any],
        derived: Sequence[str] = (),
        hints: Optional[Mapping[str, Any]] = None,
        weights: Optional[Mapping[str, Any]] = None,
        criterion: str = "L2",
        primary: Optional[Sequence[str]] = None,
        strong: bool = False,
    ) -> Edit:
        """ECLES.Initialize: move ``anchors`` (name → new value), let ``derived`` follow.

        ``criterion`` is ``"L2"`` (least squares, the default), ``"L1"`` or ``"Fewest"``
        (Brenner 3.1); ``primary`` parameters are minimised first. Raises :class:`InputError`
        for bad names or values and :class:`Unsolvable` when the edit cannot be set up.
        """
        native = _raising(
            self._native.edit,
            [(n, _texts(v, f"anchor {n}")) for n, v in anchors.items()],
            list(derived),
            [(n, _texts(v, f"hint {n}")) for n, v in (hints or {}).items()],
            [(n, _text(w, f"weight {n}")) for n, w in (weights or {}).items()],
            criterion,
            list(primary or ()),
            strong,
        )
        return Edit(native)

    def undo(self) -> bool:
        """Restores the values before the last applied edit; ``False`` when there is none."""
        return self._native.undo()

    def plan(self, source: str, operation: str) -> Tuple[List[str], List[str]]:
        """A source's plan of an operation written as in run files (for a terrain:
        ``'(mode: "z1", anchors: ["v4"], neighborhood: 3, dz: "16")'``): its anchors and
        derived parameters. Nothing changes."""
        return tuple(_raising(self._native.plan, source, operation))

    def operate(self, source: str, operation: str, criterion: str = "L2") -> Dict[str, Value]:
        """Runs and commits a source's operation written as in run files, under ``criterion``;
        returns the exact values of its anchors and derived parameters."""
        out = _raising(self._native.operate, source, operation, criterion)
        return {name: _value(pairs) for name, pairs in out}


def _numbers(value: Any, what: str) -> str:
    """A RON tuple of exact numbers as strings: `("1", "5/2")`."""
    return "(" + ", ".join(f'"{t}"' for t in _texts(value, what)) + ")"


def _array(rows: List[Any], width: int) -> Any:
    """Float rows as an (N, width) numpy array when numpy is installed, else as given."""
    try:
        import numpy
    except ImportError:
        return rows
    return numpy.array(rows, dtype=float).reshape(len(rows), width)


def _float_pairs(points: Any) -> List[Tuple[float, float]]:
    return [(float(p[0]), float(p[1])) for p in points]


class _MeshSource(System):
    """A source built on a reference triangulation from arrays: its run-file mesh, its
    operations (written as in run files) and the float deformation of models."""

    def __init__(
        self,
        name: str,
        plugin: str,
        vertices: Iterable[Sequence[Any]],
        triangles: Iterable[Sequence[int]],
        config: str,
    ):
        if not re.fullmatch(r"[A-Za-z0-9_-]+", name):
            raise InputError(f"source name {name!r}: letters, digits, '_' and '-' only")
        points = ", ".join(_numbers(v, "vertex") for v in vertices)
        faces = ", ".join("(" + ", ".join(str(int(i)) for i in t) + ")" for t in triangles)
        mesh = f"mesh: (vertices: [{points}], triangles: [{faces}])"
        text = (
            f'(sources: [(name: "{name}", plugin: "{plugin}", '
            f"config: ({config.replace('MESH', mesh)}))])"
        )
        super().__init__(_ecles.Session.from_run_text(text))
        self.name = name

    def _operation(
        self, anchors: Sequence[str], neighborhood: Optional[int], motion: str, mode: str = ""
    ) -> str:
        names = ", ".join(json.dumps(str(a)) for a in anchors)
        reach = '"all"' if neighborhood is None else str(int(neighborhood))
        return f"({mode}anchors: [{names}], neighborhood: {reach}, {motion})"

    def deform(self, vertices: Any) -> Any:
        """Model vertices (floats) deformed by psi: (N, 2) or (N, 3) for a spline (z kept),
        (N, 3) for a terrain. Vertices outside the mesh (or a terrain's layer) stay where they
        are, with a warning, and so does every vertex psi leaves exactly in place. A numpy
        array when numpy is installed, else a list."""
        rows = [[float(c) for c in v] for v in vertices]
        out, outside = self._native.deform(self.name, rows)
        if outside:
            warnings.warn(
                f"{outside} of {len(rows)} vertices lie outside the {type(self).__name__} "
                "and were not moved"
            )
        return _array(out, len(rows[0]) if rows else 0)


class Spline2d(_MeshSource):
    """A C^r spline deformation of the plane (the `spline2d` source): degree-`degree` Bézier
    patches over a reference triangulation given by `vertices` (exact: ints, Fractions or
    decimal strings; numpy integer arrays) and counter-clockwise `triangles` (0-based).

    Control points are named as in run files (`v3`, `e3-7:2`, `t5:2,2,1`); parameters are
    `{name}.v3` and so on.
    """

    def __init__(
        self,
        vertices: Iterable[Sequence[Any]],
        triangles: Iterable[Sequence[int]],
        degree: int = 5,
        smoothness: int = 1,
        name: str = "spline",
    ):
        config = f"MESH, degree: {int(degree)}, smoothness: {int(smoothness)}"
        super().__init__(name, "spline2d", vertices, triangles, config)

    def select(
        self, anchors: Sequence[str], neighborhood: Optional[int] = 3
    ) -> Tuple[List[str], List[str]]:
        """2DSD Select and ExpandDerived: the anchors' parameters and the derived set
        (`neighborhood=None`: every control point)."""
        return self.plan(self.name, self._operation(anchors, neighborhood, 'translate: ("0", "0")'))

    def translate(
        self,
        anchors: Sequence[str],
        by: Sequence[Any],
        neighborhood: Optional[int] = 3,
        criterion: str = "L2",
    ) -> Dict[str, Value]:
        """A soft translation of the anchors by `by` (exact), committed; the new values."""
        motion = f"translate: {_numbers(by, 'translation')}"
        return self.operate(self.name, self._operation(anchors, neighborhood, motion), criterion)

    def rotate(
        self,
        anchors: Sequence[str],
        center: Sequence[Any],
        degrees: Any,
        neighborhood: Optional[int] = 3,
        criterion: str = "L2",
    ) -> Dict[str, Value]:
        """A soft exact rational rotation about `center` by `degrees`, committed."""
        motion = (
            f"rotate: (center: {_numbers(center, 'center')}, "
            f'degrees: "{_text(degrees, "degrees")}")'
        )
        return self.operate(self.name, self._operation(anchors, neighborhood, motion), criterion)

    def scale(
        self,
        anchors: Sequence[str],
        center: Sequence[Any],
        factor: Any,
        neighborhood: Optional[int] = 3,
        criterion: str = "L2",
    ) -> Dict[str, Value]:
        """A soft exact scaling about `center` by `factor` (positive), committed."""
        motion = (
            f"scale: (center: {_numbers(center, 'center')}, "
            f'factor: "{_text(factor, "factor")}")'
        )
        return self.operate(self.name, self._operation(anchors, neighborhood, motion), criterion)

    def evaluate(self, points: Any) -> Any:
        """psi at each point of an (N, 2) array (floats), NaN outside the mesh; a numpy array
        when numpy is installed, else a list of pairs."""
        nan = float("nan")
        out = self._native.evaluate(self.name, _float_pairs(points))
        return _array([(nan, nan) if v is None else v for v in out], 2)


class Terrain(_MeshSource):
    """A 2.5D deformation of a layer of prisms (the `terrain` source) over a reference
    triangulation (exact `vertices`, counter-clockwise `triangles`), between `z = bottom` and
    `z = top` (exact; `bottom` defaults to `-top`): bottom and top height splines, and with
    `xy=True` a planar spline too. Control values are `{name}.bottom.v3`, `{name}.top.v3`,
    `{name}.xy.v3`.
    """

    def __init__(
        self,
        vertices: Iterable[Sequence[Any]],
        triangles: Iterable[Sequence[int]],
        top: Any,
        bottom: Any = None,
        degree: int = 3,
        smoothness: int = 1,
        xy: bool = False,
        name: str = "terrain",
    ):
        layer = f'top: "{_text(top, "top")}"'
        if bottom is not None:
            layer += f', bottom: "{_text(bottom, "bottom")}"'
        config = (
            f"spline: (MESH, degree: {int(degree)}, smoothness: {int(smoothness)}), "
            f"{layer}, xy: {'true' if xy else 'false'}"
        )
        super().__init__(name, "terrain", vertices, triangles, config)

    def lift(
        self,
        anchors: Sequence[str],
        dz: Any,
        surface: str = "z1",
        neighborhood: Optional[int] = 3,
        criterion: str = "L2",
    ) -> Dict[str, Value]:
        """Raises (or lowers) the anchors of the top (`"z1"`) or bottom (`"z0"`) surface by
        `dz` (exact), the derived points following; committed. The new values."""
        operation = self._operation(
            anchors, neighborhood, f'dz: "{_text(dz, "dz")}"', mode=f"mode: {json.dumps(surface)}, "
        )
        return self.operate(self.name, operation, criterion)

    def heights(self, points: Any) -> Any:
        """The bottom and top heights at each point of an (N, 2) array (floats; NaN outside
        the mesh): an (N, 2) numpy array when numpy is installed, else a list."""
        nan = float("nan")
        out = self._native.heights(self.name, _float_pairs(points))
        return _array([(nan, nan) if v is None else v for v in out], 2)
