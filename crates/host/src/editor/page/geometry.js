"use strict";
// Geometry of the page, pure functions on floats (drawing only: the server keeps the exact
// state). Bézier triangles as the view describes them: control points of degree d in the
// order of the multi-indices (i, j, k), i + j + k = d, lexicographically descending.

// The multi-indices of degree d in the view's order.
function multiIndices(d) {
  const out = [];
  for (let i = d; i >= 0; i--) for (let j = d - i; j >= 0; j--) out.push([i, j, d - i - j]);
  return out;
}

// d! / (i! j! k!) for every multi-index of degree d, in the view's order.
function trinomials(d) {
  const factorial = [1];
  for (let n = 1; n <= d; n++) factorial.push(factorial[n - 1] * n);
  return multiIndices(d).map(([i, j, k]) => factorial[d] / (factorial[i] * factorial[j] * factorial[k]));
}

// The Bernstein weights of the point with barycentric coordinates (u, v, w): the image of the
// point is Σ weights[n] · control[n].
function bernsteinWeights(d, [u, v, w]) {
  const coefficients = trinomials(d);
  return multiIndices(d).map(([i, j, k], n) => coefficients[n] * u ** i * v ** j * w ** k);
}

// Where things are in a patch of degree d (its control points in the view's order), computed
// once per degree: `edges[e]` the slots of boundary edge e's control points from its first
// corner to its second (edges 0–1, 1–2, 2–0), `net` the control net's segments as slot pairs.
const patchLayouts = new Map();
function patchLayout(d) {
  if (!patchLayouts.has(d)) {
    const indices = multiIndices(d);
    const slot = new Map(indices.map((m, k) => [m.join(","), k]));
    const at = (m) => slot.get(m.join(","));
    const edges = [[0, 1], [1, 2], [2, 0]].map(([a, b]) => {
      const out = [];
      for (let s = 0; s <= d; s++) {
        const m = [0, 0, 0];
        m[a] = d - s;
        m[b] = s;
        out.push(at(m));
      }
      return out;
    });
    const net = [];
    for (const [i, j, k] of indices) {
      const here = at([i, j, k]);
      if (i > 0) net.push([here, at([i - 1, j + 1, k])], [here, at([i - 1, j, k + 1])]);
      if (j > 0) net.push([here, at([i, j - 1, k + 1])]);
    }
    patchLayouts.set(d, { edges, net });
  }
  return patchLayouts.get(d);
}

// The Bernstein weights of degree d at `samples + 1` equally spaced parameters, for drawing
// curves by dot products (no allocation per point).
const curveWeightCache = new Map();
function curveWeights(d, samples) {
  const key = `${d} ${samples}`;
  if (!curveWeightCache.has(key)) {
    const binomial = [1];
    for (let k = 1; k <= d; k++) binomial.push((binomial[k - 1] * (d - k + 1)) / k);
    const table = [];
    for (let n = 0; n <= samples; n++) {
      const t = n / samples;
      table.push(binomial.map((b, k) => b * (1 - t) ** (d - k) * t ** k));
    }
    curveWeightCache.set(key, table);
  }
  return curveWeightCache.get(key);
}

// The convex hull of points (Andrew's monotone chain), counter-clockwise: how the page draws a
// constraint among several points (a C1 condition's quadrilateral).
function convexHull(points) {
  const sorted = points.slice().sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  if (sorted.length < 3) return sorted;
  const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  const lower = [], upper = [];
  for (const p of sorted) {
    while (lower.length >= 2 && cross(lower[lower.length - 2], lower[lower.length - 1], p) <= 0) lower.pop();
    lower.push(p);
  }
  for (const p of sorted.slice().reverse()) {
    while (upper.length >= 2 && cross(upper[upper.length - 2], upper[upper.length - 1], p) <= 0) upper.pop();
    upper.push(p);
  }
  return lower.slice(0, -1).concat(upper.slice(0, -1));
}

// A model placed in a view's reference mesh (each vertex's triangle and Bernstein weights,
// computed once), deformed from the control points' values: a frame recomputes only the
// vertices in triangles whose control points moved. `surfaces`: the view's patch lists whose
// points move the model.
class EmbeddedModel {
  constructor(view, model, surfaces) {
    this.name = model.name;
    this.view = view;
    this.faces = model.faces;
    this.reference = model.vertices;
    this.positions = model.vertices.map((p) => [p[0], p[1], p[2]]);
    this.byTriangle = view.triangles.map(() => []);
    this.weights = new Array(model.vertices.length).fill(null);
    // The reference triangle of each vertex (-1: outside the mesh, it does not move).
    this.triangleOf = new Int32Array(model.vertices.length).fill(-1);
    model.embedding.forEach((place, vertex) => {
      if (place === null) return;
      const [triangle, barycentric] = place;
      this.byTriangle[triangle].push(vertex);
      this.triangleOf[vertex] = triangle;
      this.weights[vertex] = bernsteinWeights(view.degree, barycentric);
    });
    // Which triangles use each control point.
    this.trianglesOf = new Map();
    for (const patches of surfaces) {
      patches.forEach((patch, t) => {
        for (const id of patch) {
          if (!this.trianglesOf.has(id)) this.trianglesOf.set(id, new Set());
          this.trianglesOf.get(id).add(t);
        }
      });
    }
  }

  // The triangles whose vertices a move of `movedIds` changes (every triangle when null);
  // the last answer is kept, since a drag moves the same points frame after frame.
  trianglesMovedBy(movedIds) {
    if (movedIds === null) return this.view.triangles.map((_, t) => t);
    if (this.lastMoved && this.lastMoved.ids === movedIds) return this.lastMoved.triangles;
    const set = new Set();
    for (const id of movedIds) for (const t of this.trianglesOf.get(id) || []) set.add(t);
    this.lastMoved = { ids: movedIds, triangles: [...set] };
    return this.lastMoved.triangles;
  }
}

// A model of a Bézier-triangle view (spline2d).
class DeformedModel extends EmbeddedModel {
  constructor(view, model) {
    super(view, model, [view.patches]);
    this.patches = view.patches;
  }

  // Recomputes the vertices in the triangles of `movedIds` (every triangle when null) from
  // `at(id)`, the current value of a control point; returns the number of vertices moved.
  update(at, movedIds) {
    let count = 0;
    for (const t of this.trianglesMovedBy(movedIds)) {
      const ctrl = this.patches[t].map(at);
      for (const vertex of this.byTriangle[t]) {
        const w = this.weights[vertex];
        let x = 0, y = 0;
        for (let n = 0; n < w.length; n++) { x += w[n] * ctrl[n][0]; y += w[n] * ctrl[n][1]; }
        const p = this.positions[vertex];
        p[0] = x; p[1] = y;
        count++;
      }
    }
    return count;
  }
}
