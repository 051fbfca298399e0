#!/usr/bin/env python3
"""Draws Brenner's figure 3 (2004, section 3.1) from an `ecles run` report of
`examples/brenner.ron`: one small SVG per panel, for docs/propagation.md.

    cargo run --release -q -p host -- run examples/brenner.ron --out /tmp/brenner.out
    python3 tools/brenner_figures.py /tmp/brenner.out/report.json examples/brenner.ron docs/propagation

writes `3a.svg` (the start), `3d.svg` (the start with l1 ⊥ l2) and, for each edit, the panel
named by its source ("c" -> `3c.svg`, also 3b, 3f, 3g, 3h): the configuration before the edit
(grey, dashed lines, hollow points) and after it (colour), p1's drag as an arrow. The start
values and the linearised rows come from the run file, the values after each edit from
`report.json`. For 3(g) (L1, not unique) the positions p2 and p3 take over the segment of
optima are drawn as bands; its ends are the single-coordinate changes of the points with the
reported L1 value, solved exactly from the run file's rows (every point between two optimal
changes is optimal). For 3(h) (fewest changed) each tie the report lists is solved the same
way and drawn faintly. Lines are drawn from their (a, b, c), a x + b y + c = 0: the rows are
the incidences linearised at the start, so after an edit a line can miss a moved point by a
second-order term (such misses are noted under the picture).

`--check` writes nothing and exits with status 1 when a file in OUT_DIR is missing or differs
from what would be written. Python 3 standard library only; the output is the same bytes on
every run.
"""

import argparse
import json
import re
import sys
from fractions import Fraction
from pathlib import Path

# The geometry of the figure.
POINTS = [("p1", "x1", "y1"), ("p2", "x2", "y2"), ("p3", "x3", "y3")]
LINES = [("l1", "a1", "b1", "c1"), ("l2", "a2", "b2", "c2")]
INCIDENCES = [("p1", "l1"), ("p2", "l1"), ("p1", "l2"), ("p3", "l2")]
POINT_COORDS = {"x1", "y1", "x2", "y2", "x3", "y3"}

# The drawing: model coordinates [LO, HI]² (y up) on PLOT x PLOT pixels under a header.
LO, HI = -0.6, 1.8
PLOT = 240
SCALE = PLOT / (HI - LO)
HEADER = 38
NOTE_LINE = 13
NOTE_LINES = 2
WIDTH = PLOT

GREY = "#9a9a9a"
LINE_COLOUR = {"l1": "#1f5fa8", "l2": "#c0392b"}
POINT_COLOUR = "#222222"
DRAG = "#1e8c3a"
BAND = "#27ae60"
TIE = "#e08a00"

# Label offsets in pixels (dx, dy, text-anchor), chosen so that coinciding points stay legible.
POINT_LABEL = {"p1": (-7, 15, "end"), "p2": (7, 15, "start"), "p3": (-7, -6, "end")}


def num(v):
    """A number with at most 2 decimals, no trailing zeros, no "-0"."""
    text = f"{float(v):.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def frac(v):
    """An exact value as text: "1/2", "-1"."""
    return str(Fraction(v))


def px(x, y):
    return ((x - LO) * SCALE, HEADER + (HI - y) * SCALE)


def esc(text):
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


# ---------------------------------------------------------------------------- the run file


def strip_comments(text):
    """RON text without // comments (strings kept as they are)."""
    return re.sub(r'("(?:[^"\\]|\\.)*")|//[^\n]*', lambda m: m.group(1) or "", text)


def parse_side(side):
    """A linear expression "2 b1 + c1 - 3" as ({name: coefficient}, constant)."""
    coeffs, constant = {}, Fraction(0)
    side = side.strip()
    if not side:
        raise ValueError("empty side of an equation")
    for sign, term in re.findall(r"([+-]?)\s*([^+-]+)", side):
        tokens = term.replace("*", " ").split()
        factor = Fraction(-1 if sign == "-" else 1)
        name = None
        for tok in tokens:
            if re.fullmatch(r"[A-Za-z_]\w*", tok):
                if name is not None:
                    raise ValueError(f"not linear: {term!r}")
                name = tok
            else:
                factor *= Fraction(tok)
        if name is None:
            constant += factor
        else:
            coeffs[name] = coeffs.get(name, Fraction(0)) + factor
    return coeffs, constant


def parse_equation(eq):
    """ "y2 + a1 + c1 = 0" as ({name: coefficient}, right-hand side)."""
    left, right = eq.split("=")
    lc, lk = parse_side(left)
    rc, rk = parse_side(right)
    coeffs = dict(lc)
    for name, c in rc.items():
        coeffs[name] = coeffs.get(name, Fraction(0)) - c
    return {n: c for n, c in coeffs.items() if c != 0}, rk - lk


def read_run_file(path):
    """{source name: (start values {param: Fraction}, rows [(coeffs, rhs)])}."""
    text = strip_comments(Path(path).read_text(encoding="utf-8"))
    sources = {}
    pattern = re.compile(
        r'name:\s*"([^"]+)"\s*,\s*plugin:\s*"linear".*?parameters:\s*\{([^}]*)\}'
        r".*?equations:\s*\[([^\]]*)\]",
        re.S,
    )
    for name, params, equations in pattern.findall(text):
        start = {k: Fraction(v) for k, v in re.findall(r'"(\w+)"\s*:\s*"([^"]*)"', params)}
        rows = [parse_equation(e) for e in re.findall(r'"([^"]*)"', equations)]
        sources[name] = (start, rows)
    if not sources:
        raise SystemExit(f"{path}: no linear sources found")
    return sources


# ---------------------------------------------------------------------------- exact algebra


def residuals(rows, values):
    """Each row's left side minus its right side at `values`."""
    return [sum(c * values[n] for n, c in coeffs.items()) - rhs for coeffs, rhs in rows]


def solve_unique(rows, fixed, unknowns):
    """The only values of `unknowns` satisfying `rows` with `fixed` given, or None (no solution
    or more than one). Exact Gauss-Jordan elimination."""
    matrix = []
    for coeffs, rhs in rows:
        row = [coeffs.get(u, Fraction(0)) for u in unknowns]
        row.append(rhs - sum(c * fixed[n] for n, c in coeffs.items() if n not in unknowns))
        matrix.append(row)
    n = len(unknowns)
    pivots, r = [], 0
    for col in range(n):
        p = next((i for i in range(r, len(matrix)) if matrix[i][col] != 0), None)
        if p is None:
            continue
        matrix[r], matrix[p] = matrix[p], matrix[r]
        inv = 1 / matrix[r][col]
        matrix[r] = [v * inv for v in matrix[r]]
        for i in range(len(matrix)):
            if i != r and matrix[i][col] != 0:
                f = matrix[i][col]
                matrix[i] = [a - f * b for a, b in zip(matrix[i], matrix[r])]
        pivots.append(col)
        r += 1
    if any(row[n] != 0 for row in matrix[r:]) or len(pivots) < n:
        return None
    return {unknowns[col]: matrix[i][n] for i, col in enumerate(pivots)}


def with_support(rows, start, anchors, primary, secondary, support):
    """The configuration whose primary parameters change only in `support` (the others at
    their start values), solved exactly; None when that does not determine it."""
    fixed = dict(start)
    fixed.update(anchors)
    unknowns = [p for p in primary if p in support] + list(secondary)
    solved = solve_unique(rows, fixed, unknowns)
    if solved is None:
        return None
    values = dict(fixed)
    values.update(solved)
    return values


# ---------------------------------------------------------------------------- drawing


def clip_line(a, b, c):
    """The segment of a x + b y + c = 0 inside the viewport, or None."""
    a, b, c = float(a), float(b), float(c)
    if a == 0 and b == 0:
        return None
    found = []
    for x in (LO, HI):
        if b != 0:
            y = -(a * x + c) / b
            if LO - 1e-9 <= y <= HI + 1e-9:
                found.append((x, y))
    for y in (LO, HI):
        if a != 0:
            x = -(b * y + c) / a
            if LO - 1e-9 <= x <= HI + 1e-9:
                found.append((x, y))
    found = sorted(set((round(x, 9), round(y, 9)) for x, y in found))
    if len(found) < 2:
        return None
    return found[0], found[-1]


class Svg:
    def __init__(self, notes):
        self.notes = notes
        if len(notes) > NOTE_LINES:
            raise SystemExit(f"too many notes for one picture: {notes}")
        self.height = HEADER + PLOT + NOTE_LINES * NOTE_LINE + 6
        self.body = []

    def add(self, text):
        self.body.append(text)

    def line(self, x0, y0, x1, y1, style):
        (u0, v0), (u1, v1) = px(x0, y0), px(x1, y1)
        self.add(f'<line x1="{num(u0)}" y1="{num(v0)}" x2="{num(u1)}" y2="{num(v1)}" {style}/>')

    def text(self, u, v, content, style):
        self.add(f'<text x="{num(u)}" y="{num(v)}" {style} stroke="#ffffff" stroke-width="3" '
                 f'stroke-linejoin="round" paint-order="stroke">{esc(content)}</text>')

    def render(self, title, subtitle):
        out = [
            f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{self.height}" '
            f'viewBox="0 0 {WIDTH} {self.height}" font-family="Helvetica, Arial, sans-serif">',
            "<defs>",
            f'<marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" '
            f'markerHeight="7" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" '
            f'fill="{DRAG}"/></marker>',
            f'<clipPath id="plot"><rect x="0" y="{HEADER}" width="{PLOT}" height="{PLOT}"/>'
            "</clipPath>",
            "</defs>",
            f'<rect x="0" y="0" width="{WIDTH}" height="{self.height}" fill="#ffffff"/>',
            f'<rect x="0.5" y="{HEADER + 0.5}" width="{PLOT - 1}" height="{PLOT - 1}" '
            'fill="none" stroke="#e2e2e2"/>',
            f'<text x="6" y="15" font-size="12" font-weight="bold" fill="#222">{esc(title)}</text>',
            f'<text x="6" y="30" font-size="10" fill="#444">{esc(subtitle)}</text>',
        ]
        out.append(self.axes())
        out.append('<g clip-path="url(#plot)">')
        out.extend(self.body)
        out.append("</g>")
        for i, note in enumerate(self.notes):
            y = HEADER + PLOT + NOTE_LINE * (i + 1)
            out.append(f'<text x="6" y="{y}" font-size="9.5" fill="#555">{esc(note)}</text>')
        out.append("</svg>")
        return "\n".join(out) + "\n"

    @staticmethod
    def axes():
        """Faint axes through the origin."""
        parts = []
        (u0, v0), (u1, v1) = px(LO, 0), px(HI, 0)
        parts.append(f'<line x1="{num(u0)}" y1="{num(v0)}" x2="{num(u1)}" y2="{num(v1)}" '
                     'stroke="#eeeeee"/>')
        (u0, v0), (u1, v1) = px(0, LO), px(0, HI)
        parts.append(f'<line x1="{num(u0)}" y1="{num(v0)}" x2="{num(u1)}" y2="{num(v1)}" '
                     'stroke="#eeeeee"/>')
        return "\n".join(parts)


def point(values, p):
    _, xn, yn = next(t for t in POINTS if t[0] == p)
    return values[xn], values[yn]


def draw_lines(svg, values, style_of, labelled):
    for name, an, bn, cn in LINES:
        seg = clip_line(values[an], values[bn], values[cn])
        if seg is None:
            continue
        (x0, y0), (x1, y1) = seg
        svg.line(x0, y0, x1, y1, style_of(name))
        if labelled:
            # l1 near its right end, l2 near its top end, 0.25 units inside, offset sideways.
            ends = sorted([(x0, y0), (x1, y1)], key=(lambda e: e[0]) if name == "l1" else (lambda e: e[1]))
            (ex, ey), (ox, oy) = ends[1], ends[0]
            length = ((ex - ox) ** 2 + (ey - oy) ** 2) ** 0.5
            tx, ty = ex + (ox - ex) * 0.25 / length, ey + (oy - ey) * 0.25 / length
            u, v = px(tx, ty)
            # the side away from the figure's centre (0.5, 0.5)
            nx, ny = -(ey - oy) / length, (ex - ox) / length
            if nx * (tx - 0.5) + ny * (ty - 0.5) < 0:
                nx, ny = -nx, -ny
            u, v = u + nx * 10, v - ny * 10
            svg.text(u, v + 4, name, f'font-size="11" font-style="italic" text-anchor="middle" '
                     f'fill="{LINE_COLOUR[name]}"')


def draw_points(svg, values, hollow, colour, labelled, radius=3.2):
    for name, xn, yn in POINTS:
        u, v = px(float(values[xn]), float(values[yn]))
        fill = "#ffffff" if hollow else colour
        svg.add(f'<circle cx="{num(u)}" cy="{num(v)}" r="{radius}" fill="{fill}" '
                f'stroke="{colour}" stroke-width="1.3"/>')
        if labelled:
            dx, dy, anchor = POINT_LABEL[name]
            svg.text(u + dx, v + dy, name, f'font-size="11" text-anchor="{anchor}" fill="{colour}"')


def right_angle(svg, colour):
    """The right-angle mark of the start configuration (l1 ⊥ l2 at the origin)."""
    s = 0.12
    pts = [px(s, 0), px(s, s), px(0, s)]
    d = "M" + " L".join(f"{num(u)},{num(v)}" for u, v in pts)
    svg.add(f'<path d="{d}" fill="none" stroke="{colour}" stroke-width="1"/>')


def solid(name):
    return f'stroke="{LINE_COLOUR[name]}" stroke-width="1.8"'


def dashed(_name):
    return f'stroke="{GREY}" stroke-width="1.2" stroke-dasharray="5 4"'


def faint(_name):
    return f'stroke="{TIE}" stroke-width="1.3" stroke-dasharray="2 3" stroke-opacity="0.8"'


def perpendicular(rows):
    """Whether a row ties the two lines' normals to each other (l1 ⊥ l2, linearised)."""
    normals = [{an, bn} for _, an, bn, _ in LINES]
    return any(set(c) <= normals[0] | normals[1] and set(c) & normals[0] and set(c) & normals[1]
               for c, _ in rows)


def misses(values):
    """Notes on incidences the values keep only to first order."""
    notes = []
    for p, l in INCIDENCES:
        x, y = point(values, p)
        _, an, bn, cn = next(t for t in LINES if t[0] == l)
        r = values[an] * x + values[bn] * y + values[cn]
        if r != 0:
            notes.append(f"{p} is off {l}: a x + b y + c = {frac(r)} (rows linearised)")
    return notes


def start_panel(panel, start, perpendicular):
    svg = Svg([])
    draw_lines(svg, start, solid, True)
    if perpendicular:
        right_angle(svg, "#444444")
    draw_points(svg, start, False, POINT_COLOUR, True)
    title = f"3({panel}) start" + (" with l1 ⊥ l2" if perpendicular else "")
    subtitle = "p1, p2 on l1; p1, p3 on l2" + ("; l1 ⊥ l2" if perpendicular else "")
    return svg.render(title, subtitle)


def describe(edit, source, rows, start, after):
    """Title and subtitle of an edit's panel."""
    crit = edit.get("criterion")
    prefix = "l1 ⊥ l2; " if perpendicular(rows) else ""
    if crit is None:
        derived = [d.split(".", 1)[1] for d in edit["derived"]]
        total = sum((after[d] - start[d]) ** 2 for d in derived)
        return f"3({source}) {prefix}L2 on all derived", f"points and lines alike; Σ Δ² = {frac(total)}"
    primary = [p.split(".", 1)[1] for p in crit["primary"]]
    where = "on the points" if set(primary) == POINT_COORDS - {"x1", "y1"} else "on " + ", ".join(primary)
    measure = crit["measure"]
    if measure == "L2":
        return f"3({source}) {prefix}L2 {where} first", f"then the rest; Σ Δ² {where} = {crit['value']}"
    if measure == "L1":
        if crit.get("unique") is False:
            dim = crit["optimal_face_dimension"]
            optima = "a segment of optima" if dim == 1 else f"a {dim}-dimensional set of optima"
            return (f"3({source}) {prefix}L1 {where}",
                    f"one of {optima} (dim {dim}); Σ|Δ| = {crit['value']}")
        return f"3({source}) {prefix}L1 {where}", f"unique optimum; Σ|Δ| = {crit['value']}"
    if measure == "Fewest":
        changed = [c.split(".", 1)[1] for c in crit["changed"] if c.split(".", 1)[1] in POINT_COORDS]
        ties = [",".join(t.split(".", 1)[1] for t in tie) for tie in crit.get("ties", [])]
        tie = f" (tie: {'; '.join(ties)})" if ties else ""
        return (f"3({source}) {prefix}fewest changed",
                f"{crit['value']} point coordinate: {', '.join(changed)}{tie}")
    return f"3({source}) {measure}", ""


def edit_panel(edit, source, start, rows):
    after = dict(start)
    for entry in edit["values"]:
        name = entry["name"].split(".", 1)[1]
        after[name] = Fraction(entry["exact"][0])
    for i, r in enumerate(residuals(rows, after)):
        if r != 0:
            raise SystemExit(f"edit {edit['index']}: row {i + 1} of source {source} is off by {r}")
    notes = misses(after)
    crit = edit.get("criterion") or {}
    derived = [d.split(".", 1)[1] for d in edit["derived"]]
    anchors = {a.split(".", 1)[1]: after[a.split(".", 1)[1]] for a in edit["anchors"]}
    primary = [p.split(".", 1)[1] for p in crit.get("primary", [])]
    secondary = [d for d in derived if d not in primary]

    band = None
    if crit.get("measure") == "L1" and crit.get("unique") is False:
        best = Fraction(crit["value"])
        optima = []
        for p in primary:
            values = with_support(rows, start, anchors, primary, secondary, {p})
            if values is not None and sum(abs(values[q] - start[q]) for q in primary) == best:
                optima.append(values)
        if len(optima) == 2:
            band = optima
            notes.insert(0, "green: p2 and p3 over the segment of optima")
    ties = []
    if crit.get("measure") == "Fewest":
        for tie in crit.get("ties", []):
            support = {t.split(".", 1)[1] for t in tie}
            values = with_support(rows, start, anchors, primary, secondary, support)
            if values is None:
                notes.append(f"tie {', '.join(sorted(support))}: not determined, not drawn")
                continue
            moved = ", ".join(
                f"{p} -> ({num(x)}, {num(y)})"
                for p, _, _ in POINTS
                if point(values, p) != point(start, p) and p != "p1"
                for x, y in [point(values, p)]
            )
            ties.append(values)
            notes.insert(0, f"orange, dotted: the tie {', '.join(sorted(support))} ({moved})")

    svg = Svg(notes)
    draw_lines(svg, start, dashed, False)
    if band:
        for p in ("p2", "p3"):
            (x0, y0), (x1, y1) = point(band[0], p), point(band[1], p)
            if (x0, y0) != (x1, y1):
                svg.line(float(x0), float(y0), float(x1), float(y1),
                         f'stroke="{BAND}" stroke-width="7" stroke-opacity="0.3" stroke-linecap="round"')
    for values in ties:
        draw_lines(svg, values, faint, False)
    draw_lines(svg, after, solid, True)
    (x0, y0), (x1, y1) = point(start, "p1"), point(after, "p1")
    if (x0, y0) != (x1, y1):
        (u0, v0), (u1, v1) = px(float(x0), float(y0)), px(float(x1), float(y1))
        length = ((u1 - u0) ** 2 + (v1 - v0) ** 2) ** 0.5
        shrink = 6 / length
        svg.add(f'<line x1="{num(u0 + (u1 - u0) * shrink)}" y1="{num(v0 + (v1 - v0) * shrink)}" '
                f'x2="{num(u1 - (u1 - u0) * shrink)}" y2="{num(v1 - (v1 - v0) * shrink)}" '
                f'stroke="{DRAG}" stroke-width="2" marker-end="url(#arrow)"/>')
    draw_points(svg, start, True, GREY, False)
    draw_points(svg, after, False, POINT_COLOUR, True)
    for values in ties:
        # rings on top (a tie's point may fall on a point of the answer), labelled
        for name, xn, yn in POINTS:
            if name == "p1" or point(values, name) == point(start, name):
                continue
            u, v = px(float(values[xn]), float(values[yn]))
            svg.add(f'<circle cx="{num(u)}" cy="{num(v)}" r="6" fill="none" stroke="{TIE}" '
                    'stroke-width="1.5"/>')
            svg.text(u + 8, v - 7, f"{name} (tie)", f'font-size="10" fill="{TIE}"')
    title, subtitle = describe(edit, source, rows, start, after)
    return svg.render(title, subtitle)


def figures(report_path, run_path):
    """{file name: SVG text}, in a fixed order."""
    report = json.loads(Path(report_path).read_text(encoding="utf-8"))
    sources = read_run_file(run_path)
    out = {}
    no_perp = next((s for s, (_, rows) in sources.items() if not perpendicular(rows)), None)
    perp = next((s for s, (_, rows) in sources.items() if perpendicular(rows)), None)
    if no_perp:
        out["3a.svg"] = start_panel("a", sources[no_perp][0], False)
    if perp:
        out["3d.svg"] = start_panel("d", sources[perp][0], True)
    for edit in report["edits"]:
        if not edit.get("anchors") or not edit.get("values"):
            continue
        source = edit["anchors"][0].split(".", 1)[0]
        if source not in sources:
            continue
        start, rows = sources[source]
        out[f"3{source}.svg"] = edit_panel(edit, source, start, rows)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("report", help="report.json of `ecles run examples/brenner.ron`")
    parser.add_argument("run_file", help="examples/brenner.ron")
    parser.add_argument("out_dir", help="where the SVGs go (docs/propagation)")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 if a file in OUT_DIR is missing or differs")
    args = parser.parse_args()
    files = figures(args.report, args.run_file)
    out_dir = Path(args.out_dir)
    if args.check:
        stale = [n for n, text in files.items()
                 if not (out_dir / n).is_file() or (out_dir / n).read_text(encoding="utf-8") != text]
        for name in stale:
            print(f"{out_dir / name}: out of date", file=sys.stderr)
        return 1 if stale else 0
    out_dir.mkdir(parents=True, exist_ok=True)
    for name, text in files.items():
        (out_dir / name).write_text(text, encoding="utf-8", newline="\n")
        print(out_dir / name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
