"use strict";
// Terrain sources (a "prisms" view, thesis part III and 18.3, 18.6): a layer of prisms over a
// planar reference mesh, with a bottom surface σ0, a top surface σ1 (heights) and a horizontal
// map φ (points), all Bézier splines of one degree. The page draws them in an oblique 3D view
// (z0 and z1 modes edit the heights, view mode only turns the scene) or from above (xy mode
// edits φ). Depends on geometry.js.

// The camera of the 3D view: azimuth and elevation in degrees, vertical exaggeration.
const camera = { azimuth: -30, elevation: 35, exaggeration: 1 };

// A point (x, y, z) of the world in the plane of the screen (before the view's pan and zoom),
// and its depth (larger: nearer the viewer).
function project3d([x, y, z]) {
  const a = (camera.azimuth * Math.PI) / 180, e = (camera.elevation * Math.PI) / 180;
  const X = x * Math.cos(a) - y * Math.sin(a);
  const Y = x * Math.sin(a) + y * Math.cos(a);
  const Z = z * camera.exaggeration;
  return { at: [X, Y * Math.sin(e) + Z * Math.cos(e)], depth: -Y * Math.cos(e) + Z * Math.sin(e) };
}

// How far a height changes per unit of vertical motion on the screen (world units), for
// dragging a point along its vertical line.
function heightPerScreenUnit() {
  const c = Math.cos((camera.elevation * Math.PI) / 180) * camera.exaggeration;
  return 1 / Math.max(c, 0.05);
}

// The structure of a prisms view for drawing: per surface the patches, and per control-point
// slot its domain point (where the identity puts it) and the φ point above it.
class PrismLayer {
  constructor(view, at) {
    this.view = view;
    this.at = at;
    const d = view.degree;
    const indices = multiIndices(d);
    // Where each height parameter sits horizontally: its φ point (xy), else its domain point.
    this.xyOf = new Map();
    this.domainOf = new Map();
    this.surfaceOf = new Map();
    view.triangles.forEach((tri, t) => {
      const [a, b, c] = tri.map((v) => view.vertices[v]);
      indices.forEach(([i, j, k], n) => {
        const domain = [(i * a[0] + j * b[0] + k * c[0]) / d, (i * a[1] + j * b[1] + k * c[1]) / d];
        for (const [surface, patches] of [["bottom", view.bottom], ["top", view.top], ["xy", view.xy]]) {
          if (!patches) continue;
          const id = patches[t][n];
          this.surfaceOf.set(id, surface);
          this.domainOf.set(id, domain);
          if (surface !== "xy" && view.xy) this.xyOf.set(id, view.xy[t][n]);
        }
      });
    });
  }

  // The horizontal position of a control point (a height's, or a φ point's).
  horizontal(id) {
    if (this.surfaceOf.get(id) === "xy") return this.at(id);
    const xy = this.xyOf.get(id);
    return xy === undefined ? this.domainOf.get(id) : this.at(xy);
  }

  // A height parameter's 3D position.
  position(id) {
    const [x, y] = this.horizontal(id);
    return [x, y, this.at(id)[0]];
  }
}

// A model of a prisms view deformed by ψ: horizontally φ at the vertex's place (the vertex's
// own x, y when φ is the identity), vertically (1 − α)·σ0 + α·σ1 with α its relative height.
class DeformedPrismModel extends EmbeddedModel {
  constructor(view, model) {
    super(view, model, [view.bottom, view.top, view.xy].filter((p) => p));
    const span = view.reference_top - view.reference_bottom;
    this.alpha = model.relative_height && model.relative_height.length === model.vertices.length
      ? model.relative_height
      : model.vertices.map((p) => (p[2] - view.reference_bottom) / span);
  }

  // As DeformedModel.update: recomputes the vertices of the triangles of `movedIds` (all when
  // null); returns how many.
  update(at, movedIds) {
    const v = this.view;
    let count = 0;
    for (const t of this.trianglesMovedBy(movedIds)) {
      const bottom = v.bottom[t].map((id) => at(id)[0]);
      const top = v.top[t].map((id) => at(id)[0]);
      const xy = v.xy ? v.xy[t].map(at) : null;
      for (const vertex of this.byTriangle[t]) {
        const w = this.weights[vertex];
        let s0 = 0, s1 = 0, x = 0, y = 0;
        for (let n = 0; n < w.length; n++) {
          s0 += w[n] * bottom[n];
          s1 += w[n] * top[n];
          if (xy) { x += w[n] * xy[n][0]; y += w[n] * xy[n][1]; }
        }
        const p = this.positions[vertex];
        if (xy) { p[0] = x; p[1] = y; }
        const alpha = this.alpha[vertex];
        p[2] = (1 - alpha) * s0 + alpha * s1;
        count++;
      }
    }
    return count;
  }
}
