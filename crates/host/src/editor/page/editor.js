"use strict";
// The page of `ecles edit`: draws each source's view from the current values and drags
// control points. The server keeps the exact state; everything here is for drawing.
// Depends on geometry.js (assembled before this file).

const token = new URLSearchParams(location.search).get("token");
const canvas = document.getElementById("view");
const ctx = canvas.getContext("2d");
const statusBar = document.getElementById("status");
const conflictPanel = document.getElementById("conflict");
const element = (id) => document.getElementById(id);
const shown = (id) => element(id).checked;

let state = null;          // the server's state
let points = new Map();    // parameter id -> {name, value: [x, y], exact, source}
let models = [];           // DeformedModel (or DeformedPrismModel) per model of every view
let layers = new Map();    // PrismLayer per prisms view
let anchors = [];          // selected anchor ids
let derived = new Set();   // the derived set of the selection or of the drag
let relevant = [];         // rows the current edit keeps: {label, points}
let blocked = null;        // id of an anchor whose move was refused
let center = null;         // centre of rotation and scaling (world), set by right-click
let view = { scale: 1, x: 0, y: 0 };  // world -> screen: (x * scale + view.x, -y * scale + view.y)
let drag = null;           // the drag under way, see startDrag
let pan = null;
let orbit = null;          // turning the 3D scene (view mode)
let image = null;          // the target image: an HTMLImageElement
let last = { frame: null, server: null, draw: null, deviation: null, counts: null, local: false, criterion: null };
// The last 1000 drag frames' times in ms, for the status bar and measurements: `total` from
// the mouse event to the painted frame, `request` the round trip of its request, `server`
// the server's part of it, `deform` the model's deformation, `draw` the drawing, `ready` from
// the event to the frame drawn into the canvas (before the browser's next paint); `first` marks the mouse-down frame (2DSD
// Select, ExpandDerived and ECLES Initialize), `moved` counts the model vertices recomputed.
const frames = [];
// Times from the mouse release to the committed state drawn, in ms.
const commits = [];

// --- talking to the server -------------------------------------------------------------

// Work for the server under way; anything over 200 ms shows the progress indicator.
let busy = 0;
async function withProgress(work) {
  busy++;
  const timer = setTimeout(() => { element("progress").hidden = busy === 0; }, 200);
  try {
    return await work();
  } finally {
    clearTimeout(timer);
    busy--;
    if (busy === 0) element("progress").hidden = true;
  }
}

// A request with the token; the JSON answer, or the server's message as an error.
function send(path, method, contentType, body) {
  const headers = { "content-type": contentType };
  if (token) headers["x-ecles-token"] = token;
  return withProgress(async () => {
    const response = await fetch(path, { method, headers, body });
    const answer = await response.json().catch(() => ({ error: response.statusText }));
    if (!response.ok) throw new Error(answer.error || response.statusText);
    return answer;
  });
}

function api(path, body) {
  if (body === undefined) return send(path, "GET", "application/json", undefined);
  return send(path, "POST", "application/json", JSON.stringify(body));
}

// Drag frames travel over one WebSocket (no request overhead per frame); answers come in
// order. Before it is open, or once it is closed, frames go by HTTP.
let socket = null;
const waiting = [];
function openSocket() {
  const query = token ? `?token=${encodeURIComponent(token)}` : "";
  const ws = new WebSocket(`ws://${location.host}/api/frames${query}`);
  ws.onopen = () => { socket = ws; };
  ws.onmessage = (event) => {
    const next = waiting.shift();
    if (next) next(JSON.parse(event.data));
  };
  ws.onclose = () => {
    socket = null;
    while (waiting.length > 0) waiting.shift()({ error: "the frame connection closed" });
  };
}

function dragRequest(body) {
  if (socket === null || socket.readyState !== WebSocket.OPEN) return api("/api/drag", body);
  return withProgress(async () => {
    const answer = await new Promise((resolve) => {
      waiting.push(resolve);
      socket.send(JSON.stringify(body));
    });
    if (answer.error) throw new Error(answer.error);
    return answer;
  });
}

function setState(next) {
  // Models drawn from the same views keep their edges (see modelEdges).
  const previous = state !== null && state.views_version === next.views_version ? models : [];
  state = next;
  // Models and views are new objects: the picture of a drag's still part is stale.
  endMoving();
  points = new Map();
  const sourceOf = new Map();
  models = [];
  layers = new Map();
  for (const source of state.sources) {
    const v = source.view;
    if (!v || !v.kind) continue;
    if (v.kind === "bezier_triangles") {
      for (const patch of v.patches) for (const id of patch) sourceOf.set(id, source.name);
      for (const model of v.models || []) models.push(new DeformedModel(v, model));
    } else if (v.kind === "prisms") {
      for (const patches of [v.bottom, v.top, v.xy]) {
        if (patches) for (const patch of patches) for (const id of patch) sourceOf.set(id, source.name);
      }
      for (const model of v.models || []) models.push(new DeformedPrismModel(v, model));
    }
  }
  models.forEach((model, k) => { if (previous[k] && previous[k].edges) model.edges = previous[k].edges; });
  // New models get their edges while the page is idle, not at the first move of a drag.
  if (models.some((model) => !model.edges)) {
    setTimeout(() => { for (const model of models) modelEdges(model); }, 0);
  }
  for (const p of state.points) {
    points.set(p.id, { name: p.name, value: p.value, exact: p.exact, source: sourceOf.get(p.id) });
  }
  for (const source of state.sources) {
    const v = source.view;
    if (!v || v.kind !== "prisms") continue;
    const layer = new PrismLayer(v, at);
    layers.set(v, layer);
    for (const [id, surface] of layer.surfaceOf) {
      const p = points.get(id);
      if (p) { p.layer = layer; p.surface = surface; }
    }
  }
  element("modes").hidden = layers.size === 0;
  element("camera").hidden = layers.size === 0;
  for (const model of models) model.update(at, null);
  anchors = anchors.filter((id) => points.has(id) && points.get(id).source !== undefined);
  element("undo").disabled = !state.can_undo;
  element("redo").disabled = !state.can_redo;
  showSources();
  showOffer();
}

const at = (id) => points.get(id).value;

// --- drawing ---------------------------------------------------------------------------

const toScreen = ([x, y]) => [x * view.scale + view.x, -y * view.scale + view.y];
const toWorld = ([sx, sy]) => [(sx - view.x) / view.scale, -(sy - view.y) / view.scale];

// The editing mode of terrain sources: "view", "xy", "z0" or "z1".
const editMode = () => document.querySelector("input[name=mode]:checked").value;
const in3d = () => layers.size > 0 && editMode() !== "xy";

// Where a control point is drawn in the plane of the picture (before pan and zoom), or null
// when the current mode does not show it: spline points as they are; a terrain's φ points in
// xy mode, its heights in 3D in z0 (bottom) or z1 (top) mode.
function planeOf(id) {
  const p = points.get(id);
  if (p === undefined || p.source === undefined) return null;
  if (p.surface === undefined) return p.value;
  const mode = editMode();
  if (mode === "xy") return p.surface === "xy" ? p.value : null;
  if ((mode === "z0" && p.surface === "bottom") || (mode === "z1" && p.surface === "top")) {
    return project3d(p.layer.position(id)).at;
  }
  return null;
}

function screenOf(id) {
  const q = planeOf(id);
  return q === null ? null : toScreen(q);
}

function fit() {
  // The points this mode shows and, for terrains in 3D, both surfaces and the models.
  const all = [...points.keys()].map(planeOf).filter((q) => q !== null);
  if (in3d()) {
    for (const model of models) for (const p of model.positions) all.push(project3d(p).at);
    for (const layer of layers.values()) {
      for (const [id, surface] of layer.surfaceOf) if (surface !== "xy") all.push(project3d(layer.position(id)).at);
    }
  }
  if (all.length === 0) return;
  let [x0, x1, y0, y1] = [Infinity, -Infinity, Infinity, -Infinity];
  for (const [x, y] of all) {
    x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
  }
  // A canvas too small to fit anything keeps its view.
  const w = canvas.clientWidth, h = canvas.clientHeight, margin = 30;
  if (w <= 2 * margin || h <= 2 * margin) return;
  view.scale = Math.min((w - 2 * margin) / Math.max(x1 - x0, 1e-9), (h - 2 * margin) / Math.max(y1 - y0, 1e-9));
  view.x = (w - (x1 - x0) * view.scale) / 2 - x0 * view.scale;
  view.y = (h + (y1 - y0) * view.scale) / 2 + y0 * view.scale;
}

// Drawing goes to `g`: the page's canvas, or the cached picture of what a drag does not move.
let g = ctx;

// What the drag under way moves, for drawing only that at each frame: the moving points, and
// per view the triangles whose patches use them and per model the faces with a vertex in one
// of those triangles. `null`: no drag, everything is drawn.
let moving = null;
// The still part of the picture during a drag (an offscreen canvas), drawn once per drag.
let still = null;

// The part of the picture to draw: everything, only what a drag leaves still, or only what it
// moves.
const ALL = 0, STILL = 1, MOVING = 2;

function movingSets(ids) {
  const set = new Set(ids);
  const triangles = new Map();
  for (const source of state.sources) {
    const v = source.view;
    if (!v || !v.kind) continue;
    const t = new Set();
    const surfaces = v.kind === "prisms" ? [v.bottom, v.top, v.xy].filter((p) => p) : [v.patches];
    for (const patches of surfaces) {
      patches.forEach((patch, k) => { if (patch.some((id) => set.has(id))) t.add(k); });
    }
    triangles.set(v, t);
  }
  // Per model, its moving edges: those of a face with a vertex in a moving triangle.
  const edges = new Map();
  for (const model of models) {
    const t = triangles.get(model.view) || new Set();
    const { ends, ofFace } = modelEdges(model);
    const movingEdges = new Uint8Array(ends.length / 2);
    model.faces.forEach((face, k) => {
      if (face.some((vertex) => t.has(model.triangleOf[vertex]))) {
        for (const e of ofFace[k]) movingEdges[e] = 1;
      }
    });
    edges.set(model, movingEdges);
  }
  return { ids: set, triangles, edges };
}

// Each edge of a model's faces once, as vertex pairs (`ends`), and the edges of every face
// (`ofFace`): an edge shared by two faces is stroked once, half the path of drawing every
// face's outline. Made once per model.
function modelEdges(model) {
  if (model.edges) return model.edges;
  const index = new Map();
  const ends = [];
  const ofFace = model.faces.map((face) => face.map((a, n) => {
    const b = face[(n + 1) % face.length];
    // Vertex indices are below 2^26 (the editor's vertex limit is 4 000 000).
    const key = Math.min(a, b) * 67108864 + Math.max(a, b);
    let e = index.get(key);
    if (e === undefined) {
      e = ends.length / 2;
      index.set(key, e);
      ends.push(a, b);
    }
    return e;
  }));
  model.edges = { ends: Uint32Array.from(ends), ofFace };
  return model.edges;
}

// Starts drawing a drag of `ids` by parts: the still part is drawn once into `still`.
function beginMoving(ids) {
  moving = movingSets(ids);
  still = document.createElement("canvas");
  still.width = canvas.width;
  still.height = canvas.height;
  g = still.getContext("2d");
  const ratio = window.devicePixelRatio || 1;
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  drawLayers(STILL);
  g = ctx;
}

function endMoving() { moving = null; still = null; }

// Draws the points `ids` over the picture as it is (their colours for the selection).
function overlay(ids) {
  const began = performance.now();
  const ratio = window.devicePixelRatio || 1;
  ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
  moving = { ids: new Set(ids), triangles: new Map(), edges: new Map() };
  drawPoints(MOVING);
  moving = null;
  last.draw = performance.now() - began;
}

// Whether an item belongs to the part drawn: `isMoving` says whether the drag moves it.
const inPart = (part, isMoving) => part === ALL || (part === MOVING) === isMoving;

function line(a, b) {
  const [p, q] = [toScreen(a), toScreen(b)];
  g.moveTo(p[0], p[1]);
  g.lineTo(q[0], q[1]);
}

function polygon(corners) {
  corners.forEach((c, n) => {
    const [x, y] = toScreen(c);
    if (n === 0) g.moveTo(x, y); else g.lineTo(x, y);
  });
  g.closePath();
}

function drawImage() {
  if (!image || !shown("show-image")) return;
  // The image's top-left corner at (x, y) in the world, `units per pixel` world units wide.
  const unit = Number(element("image-scale").value) || 1;
  const [sx, sy] = toScreen([Number(element("image-x").value) || 0, Number(element("image-y").value) || 0]);
  g.globalAlpha = Number(element("image-opacity").value);
  g.drawImage(image, sx, sy, image.width * unit * view.scale, image.height * unit * view.scale);
  g.globalAlpha = 1;
}

function drawRows(rows, stroke, fill, part) {
  g.beginPath();
  for (const row of rows) {
    if (!row.points.every((id) => points.has(id))) continue;
    if (!inPart(part, moving !== null && row.points.some((id) => moving.ids.has(id)))) continue;
    polygon(convexHull(row.points.map(at)));
  }
  g.fillStyle = fill;
  g.fill();
  g.strokeStyle = stroke;
  g.lineWidth = 1;
  g.stroke();
}

// A Bézier-triangle spline from above; `key` is the view whose moving triangles apply (a
// terrain's φ is drawn as a spline of its own).
function drawView(v, part, key = v) {
  const layout = patchLayout(v.degree);
  const movingTriangles = moving === null ? null : moving.triangles.get(key) || null;
  const drawn = (t) => inPart(part, movingTriangles !== null && movingTriangles.has(t));
  if (shown("show-reference") && part !== MOVING) {
    g.beginPath();
    g.strokeStyle = "#c8c8c8";
    g.lineWidth = 1;
    for (const [a, b, c] of v.triangles) {
      line(v.vertices[a], v.vertices[b]); line(v.vertices[b], v.vertices[c]); line(v.vertices[c], v.vertices[a]);
    }
    g.stroke();
  }
  // `toScreen` inlined below: no array per point (a drag's frame draws thousands).
  const { scale, x: ox, y: oy } = view;
  if (shown("show-net")) {
    g.beginPath();
    // Solid and light: dashes cost much more to draw on a big net.
    g.strokeStyle = "#b4b4c8";
    v.patches.forEach((patch, t) => {
      if (!drawn(t)) return;
      for (const [a, b] of layout.net) {
        const p = at(patch[a]), q = at(patch[b]);
        g.moveTo(p[0] * scale + ox, -p[1] * scale + oy);
        g.lineTo(q[0] * scale + ox, -q[1] * scale + oy);
      }
    });
    g.stroke();
  }
  // The deformed mesh: the patches' boundary curves, each shared edge once.
  g.beginPath();
  g.strokeStyle = "#202020";
  g.lineWidth = 1.5;
  const d = v.degree;
  const samples = Math.max(2, 4 * d);
  const table = curveWeights(d, samples);
  const done = new Set();
  const ctrl = new Array(d + 1);
  v.patches.forEach((patch, t) => {
    if (!drawn(t)) return;
    for (const slots of layout.edges) {
      const [first, last] = [patch[slots[0]], patch[slots[d]]];
      const edgeKey = Math.min(first, last) * 67108864 + Math.max(first, last);
      if (done.has(edgeKey)) continue;
      done.add(edgeKey);
      for (let k = 0; k <= d; k++) ctrl[k] = at(patch[slots[k]]);
      for (let n = 0; n <= samples; n++) {
        const w = table[n];
        let x = 0, y = 0;
        for (let k = 0; k <= d; k++) { x += w[k] * ctrl[k][0]; y += w[k] * ctrl[k][1]; }
        const sx = x * scale + ox, sy = -y * scale + oy;
        if (n === 0) g.moveTo(sx, sy); else g.lineTo(sx, sy);
      }
    }
  });
  g.stroke();
}

function drawModels(part) {
  if (!shown("show-model")) return;
  g.beginPath();
  g.strokeStyle = "rgba(0, 120, 60, 0.55)";
  g.lineWidth = 0.75;
  for (const model of models) {
    const flat = !(model instanceof DeformedPrismModel && in3d());
    if (!flat && editMode() === "view" && shown("show-shaded")) { drawShaded(model); continue; }
    const p = flat ? model.positions : model.positions.map((q) => project3d(q).at);
    const movingEdges = moving === null ? null : moving.edges.get(model) || null;
    const { ends } = modelEdges(model);
    // `toScreen` inlined: no array per vertex (a drag's frame draws thousands of edges).
    const { scale, x: ox, y: oy } = view;
    for (let e = 0; e < ends.length / 2; e++) {
      if (!inPart(part, movingEdges !== null && movingEdges[e] === 1)) continue;
      const a = p[ends[2 * e]], b = p[ends[2 * e + 1]];
      g.moveTo(a[0] * scale + ox, -a[1] * scale + oy);
      g.lineTo(b[0] * scale + ox, -b[1] * scale + oy);
    }
  }
  g.stroke();
}

// A terrain model shaded (view mode): faces from far to near, Lambert shading from a light
// above and behind the viewer.
function drawShaded(model) {
  const light = [0.4, -0.5, 0.77];
  const p = model.positions;
  const faces = model.faces.map((face) => {
    const q = face.map((i) => project3d(p[i]));
    return { face, depth: q.reduce((s, x) => s + x.depth, 0) / q.length, q };
  });
  faces.sort((a, b) => a.depth - b.depth);
  for (const { face, q } of faces) {
    const [a, b, c] = face.map((i) => [p[i][0], p[i][1], p[i][2] * camera.exaggeration]);
    const u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]], v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    const length = Math.hypot(...n) || 1;
    const lambert = Math.abs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / length;
    const shade = Math.round(70 + 170 * lambert);
    g.fillStyle = `rgb(${shade}, ${Math.round(shade * 0.95)}, ${Math.round(shade * 0.85)})`;
    g.beginPath();
    q.forEach((x, n) => { const [sx, sy] = toScreen(x.at); if (n === 0) g.moveTo(sx, sy); else g.lineTo(sx, sy); });
    g.closePath();
    g.fill();
  }
}

// A terrain: from above in xy mode (φ as a spline), else in 3D: both surfaces' patch
// boundaries (the edited one dark), the edited surface's control net, the reference mesh at
// the bottom of the reference layer.
function drawPrisms(v, layer, part) {
  const mode = editMode();
  if (mode === "xy") {
    if (v.xy) {
      if (!layer.flat) layer.flat = { degree: v.degree, vertices: v.vertices, triangles: v.triangles, patches: v.xy };
      drawView(layer.flat, part, v);
    }
    return;
  }
  const movingTriangles = moving === null ? null : moving.triangles.get(v) || null;
  const drawn = (t) => inPart(part, movingTriangles !== null && movingTriangles.has(t));
  const plane = (q) => toScreen(project3d(q).at);
  if (shown("show-reference") && part !== MOVING) {
    g.beginPath();
    g.strokeStyle = "#c8c8c8";
    g.lineWidth = 1;
    for (const tri of v.triangles) {
      tri.forEach((a, n) => {
        const [x, y] = plane([...v.vertices[a], v.reference_bottom]);
        if (n === 0) g.moveTo(x, y); else g.lineTo(x, y);
      });
      g.closePath();
    }
    g.stroke();
  }
  const layout = patchLayout(v.degree);
  const edited = mode === "z0" ? "bottom" : mode === "z1" ? "top" : null;
  if (edited && shown("show-net")) {
    g.beginPath();
    g.strokeStyle = "#b4b4c8";
    g.lineWidth = 1;
    v[edited].forEach((patch, t) => {
      if (!drawn(t)) return;
      for (const [a, b] of layout.net) {
        const [p, q] = [plane(layer.position(patch[a])), plane(layer.position(patch[b]))];
        g.moveTo(p[0], p[1]);
        g.lineTo(q[0], q[1]);
      }
    });
    g.stroke();
  }
  const d = v.degree;
  const samples = Math.max(2, 4 * d);
  const table = curveWeights(d, samples);
  for (const surface of ["bottom", "top"]) {
    g.beginPath();
    g.strokeStyle = surface === edited ? "#202020" : "#8a8a8a";
    g.lineWidth = surface === edited ? 1.5 : 1;
    v[surface].forEach((patch, t) => {
      if (!drawn(t)) return;
      for (const slots of layout.edges) {
        const ctrl = slots.map((k) => layer.position(patch[k]));
        for (let n = 0; n <= samples; n++) {
          const w = table[n];
          const q = [0, 0, 0];
          for (let k = 0; k <= d; k++) for (let c = 0; c < 3; c++) q[c] += w[k] * ctrl[k][c];
          const [x, y] = plane(q);
          if (n === 0) g.moveTo(x, y); else g.lineTo(x, y);
        }
      }
    });
    g.stroke();
  }
}

// Points as squares (one path per colour: thousands of points draw in one call each).
function drawPoints(part) {
  if (!shown("show-points")) return;
  const styles = new Map();
  // A drag's frame looks only at the points it moves, not at every point.
  const candidates = part === MOVING && moving !== null ? moving.ids : points.keys();
  for (const id of candidates) {
    if (!inPart(part, moving !== null && moving.ids.has(id))) continue;
    const on = screenOf(id);
    if (on === null) continue;
    const anchor = anchors.includes(id);
    const isDerived = derived.has(id) && shown("show-derived");
    const colour = id === blocked ? "#d00000" : anchor ? "#e07000" : isDerived ? "#2060c0" : "#404040";
    const size = anchor || id === blocked ? 5 : isDerived ? 3.5 : 2.5;
    const key = `${colour} ${size}`;
    if (!styles.has(key)) styles.set(key, []);
    styles.get(key).push(on);
  }
  for (const [key, at] of styles) {
    const [colour, size] = key.split(" ");
    const r = Number(size);
    g.fillStyle = colour;
    g.beginPath();
    for (const [x, y] of at) g.rect(x - r, y - r, 2 * r, 2 * r);
    g.fill();
  }
}

function drawCenter() {
  if (drag && drag.lift) {
    // The anchor's vertical line (thesis 18.6): heights move along it.
    const p = points.get(anchors[0]);
    if (!p || !p.layer) return;
    const [x, y, z] = p.layer.position(anchors[0]);
    const span = p.layer.view.reference_top - p.layer.view.reference_bottom;
    const [a, b] = [toScreen(project3d([x, y, z - span]).at), toScreen(project3d([x, y, z + span]).at)];
    g.strokeStyle = "#8000a0";
    g.lineWidth = 1;
    g.setLineDash([6, 4]);
    g.beginPath();
    g.moveTo(a[0], a[1]); g.lineTo(b[0], b[1]);
    g.stroke();
    g.setLineDash([]);
    return;
  }
  if (!center || operation() === "translate") return;
  const [cx, cy] = toScreen(center);
  g.strokeStyle = "#8000a0";
  g.lineWidth = 1.5;
  g.beginPath();
  g.moveTo(cx - 7, cy); g.lineTo(cx + 7, cy); g.moveTo(cx, cy - 7); g.lineTo(cx, cy + 7);
  g.stroke();
  if (drag && drag.mouse) {
    // The guide line from the centre to the mouse (thesis 18.5.2–3).
    const [mx, my] = toScreen(drag.mouse);
    g.setLineDash([6, 4]);
    g.beginPath();
    g.moveTo(cx, cy); g.lineTo(mx, my);
    g.stroke();
    g.setLineDash([]);
  }
}

// The layers in order, restricted to `part`.
function drawLayers(part) {
  if (part !== MOVING) drawImage();
  if (shown("show-constraints")) drawRows(state.constraints, "rgba(150, 110, 0, 0.5)", "rgba(230, 190, 60, 0.12)", part);
  if (shown("show-relevant") && relevant.length > 0) drawRows(relevant, "rgba(200, 60, 0, 0.7)", "rgba(255, 120, 40, 0.15)", part);
  for (const source of state.sources) {
    const v = source.view;
    if (v && v.kind === "bezier_triangles") drawView(v, part);
    if (v && v.kind === "prisms") drawPrisms(v, layers.get(v), part);
  }
  drawModels(part);
  drawPoints(part);
  if (part !== STILL) drawCenter();
}

function draw() {
  const began = performance.now();
  const ratio = window.devicePixelRatio || 1;
  const width = Math.round(canvas.clientWidth * ratio), height = Math.round(canvas.clientHeight * ratio);
  if (canvas.width !== width || canvas.height !== height) {
    canvas.width = width;
    canvas.height = height;
    still = null;
    moving = null;
  }
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (state) {
    if (moving !== null && still !== null) {
      // A drag frame: the still picture, then what moves.
      ctx.drawImage(still, 0, 0);
      ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
      drawLayers(MOVING);
    } else {
      ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
      drawLayers(ALL);
    }
  }
  ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
  last.draw = performance.now() - began;
}

// --- status, conflicts, offers, help ---------------------------------------------------

function report() {
  if (!state) return;
  const s = state;
  const parts = [
    `${s.run}`,
    `${s.points.length} points`,
    `${s.rows} rows`,
    s.violated_rows === 0 ? "exact residual 0 (violated rows 0)" : `violated rows ${s.violated_rows}`,
    `${s.committed} edits (commits ${s.commit})`,
  ];
  if (last.counts) {
    const c = last.counts;
    parts.push(`|A| ${c.anchors} · |D| ${c.derived} · rank ${c.rank} · redundant ${c.redundant}`);
  } else if (anchors.length > 0) {
    parts.push(`|A| ${anchors.length} · |D| ${derived.size}`);
  }
  if (last.frame !== null && last.local) {
    parts.push(`frame ${last.frame.toFixed(1)} ms (from the motion response, drawing ${last.draw.toFixed(1)})`);
  } else if (last.frame !== null && last.server !== null) {
    parts.push(`frame ${last.frame.toFixed(1)} ms (server ${last.server.toFixed(1)}, drawing ${last.draw.toFixed(1)})`);
  }
  if (last.deviation !== null) parts.push(`float deviation ${last.deviation.toExponential(1)}`);
  if (last.criterion) parts.push(criterionText(last.criterion));
  if (s.autosave && s.autosave.error) parts.push(`AUTOSAVE FAILED: ${s.autosave.error}`);
  statusBar.textContent = parts.join(" · ");
}

// What a drag's change criterion chose, for the status bar.
function criterionText(c) {
  const names = c.changed.slice(0, 8).join(", ") + (c.changed.length > 8 ? ", …" : "");
  let text = `${c.measure} ${c.value}: ${c.changed.length} points changed (${names})`;
  if (c.unique === false) text += `, not unique (optima of dimension ${c.optimal_face_dimension})`;
  if (c.minimum_sets > 1) text += `, ${c.minimum_sets} equally small choices`;
  if (c.proven_minimal === false) text += ", not proven minimal";
  return text;
}

function showMessage(text) {
  conflictPanel.hidden = text === null;
  conflictPanel.textContent = text || "";
}

// The conflict panel: the message, the constraints in the way, the explanation.
function showConflict(conflict) {
  conflictPanel.hidden = false;
  conflictPanel.textContent = "";
  const title = document.createElement("h3");
  title.textContent = "This move is impossible; nothing changed";
  const message = document.createElement("div");
  message.textContent = conflict.message;
  conflictPanel.append(title, message);
  for (const [heading, lines] of [["Constraints in the way", conflict.labels], ["Why", conflict.explanation]]) {
    if (!lines || lines.length === 0) continue;
    const h = document.createElement("h3");
    h.textContent = heading;
    const list = document.createElement("ul");
    for (const l of lines) {
      const item = document.createElement("li");
      item.textContent = l;
      list.append(item);
    }
    conflictPanel.append(h, list);
  }
}

function showOffer() {
  const banner = element("banner");
  const offer = state && state.autosave && state.autosave.offer;
  banner.hidden = !offer;
  if (!offer) return;
  banner.textContent = `An autosaved session with ${offer.edits} edits was found (${offer.path}). `;
  const resume = document.createElement("button");
  resume.id = "resume";
  resume.textContent = "Resume it";
  resume.addEventListener("click", () => decide(true));
  const fresh = document.createElement("button");
  fresh.textContent = "Start fresh (the first new edit replaces it)";
  fresh.addEventListener("click", () => decide(false));
  banner.append(resume, fresh);
}

async function decide(resume) {
  try {
    setState(await api("/api/resume", { resume }));
    showMessage(null);
  } catch (e) { showMessage(String(e.message || e)); }
  report();
  draw();
}

const shortcuts = [
  ["drag a point", "move it (the selection's anchors) with the operation chosen"],
  ["click", "make a point the only anchor"],
  ["Shift+click, or the Anchors box", "add or remove an anchor"],
  ["right-click", "centre of rotation and scaling"],
  ["drag on empty space / wheel", "pan / zoom"],
  ["T, R, S", "translate, rotate, scale"],
  ["+ / −, A", "δmax up / down, all points"],
  ["F", "fit to view"],
  ["Ctrl+Z / Ctrl+Y", "undo / redo a committed edit (a continuity switch or a loaded mesh too)"],
  ["Splines panel", "continuity C0…C(d−1); load a reference mesh or a model (kept beside the run file)"],
  ["Ctrl+S", "save the session (run file, outputs, exact values)"],
  ["E, or Explain", "how a change of the anchors propagates: where they can move, which constraints stop them, what must follow (Esc closes)"],
  ["Esc", "cancel the drag under way"],
  ["?", "this help"],
];

// The propagation analysis of the anchors (Brenner 3.1, exact): shown in a panel, hidden
// by Esc or by asking again.
async function explainAnchors() {
  const panel = element("explain");
  if (!panel.hidden) { panel.hidden = true; return; }
  if (anchors.length === 0) { showMessage("Pick a point first: Explain says how it can move."); return; }
  try {
    const answer = await api("/api/explain", { ids: anchors });
    panel.textContent = "";
    const title = document.createElement("h3");
    title.textContent = "How a change propagates";
    const body = document.createElement("div");
    body.textContent = answer.lines.join("\n");
    panel.append(title, body);
    panel.hidden = false;
  } catch (e) { showMessage(String(e.message || e)); }
}

function toggleHelp() {
  const help = element("help");
  if (help.childElementCount === 0) {
    const table = document.createElement("table");
    for (const [key, what] of shortcuts) {
      const row = table.insertRow();
      row.insertCell().textContent = key;
      row.insertCell().textContent = what;
    }
    help.append(table);
  }
  help.hidden = !help.hidden;
}

// --- selection and drags ---------------------------------------------------------------

function pointAt(sx, sy) {
  let best = null, bestDistance = 8;
  for (const id of points.keys()) {
    const on = screenOf(id);
    if (on === null) continue;
    const [x, y] = on;
    const distance = Math.hypot(x - sx, y - sy);
    if (distance < bestDistance) { best = id; bestDistance = distance; }
  }
  return best;
}

const operation = () => document.querySelector("input[name=operation]:checked").value;

function selection() {
  const first = points.get(anchors[0]);
  const source = first.source;
  // A terrain's point names carry the surface: `terrain.top.v4` is `v4` in mode z1.
  const prefix = first.surface === undefined ? source + "." : `${source}.${first.surface}.`;
  const modeOf = { bottom: "z0", top: "z1", xy: "xy" };
  return {
    source,
    anchors: anchors.map((id) => points.get(id).name.slice(prefix.length)),
    neighborhood: shown("all") ? null : Number(element("neighborhood").value),
    mode: first.surface === undefined ? null : modeOf[first.surface],
  };
}

// Shows the initial derived set S of the selection (thesis 18.4) without starting an edit.
async function showSelection() {
  last.counts = null;
  relevant = [];
  if (anchors.length === 0) { derived = new Set(); report(); draw(); return; }
  try {
    const answer = await api("/api/select", selection());
    derived = answer.ok ? new Set(answer.derived) : new Set();
    if (!answer.ok) showConflict(answer.conflict);
  } catch (e) { showMessage(String(e.message || e)); }
  report();
  // A drag under way draws its own frames (with the same derived set).
  if (drag === null) draw();
}

// Exact decimal text of a float (the server reads it exactly).
const decimal = (v, places) => (Math.round(v * 10 ** places) / 10 ** places).toFixed(places);

// A length of the picture as an exact dyadic fraction `n/2^k`, on the coarsest power-of-two
// grid at least as fine as a twentieth of a pixel at the current zoom: exact numbers with small
// denominators (cheap to solve with, short when committed), far below what the eye sees.
function dyadic(v) {
  const k = Math.min(30, Math.max(0, Math.ceil(Math.log2(20 * view.scale))));
  const scale = 2 ** k;
  const n = Math.round(v * scale);
  return n === 0 ? "0" : `${n}/${scale}`;
}

// The motion of the drag so far, as the server takes it.
function motion(d) {
  const [x, y] = d.mouse;
  if (d.lift) {
    // Along the anchor's vertical line: the screen's vertical motion, in heights.
    return { lift: { dz: dyadic((y - d.start[1]) * heightPerScreenUnit()) } };
  }
  if (d.operation === "translate") {
    return { translate: { dx: dyadic(x - d.start[0]), dy: dyadic(y - d.start[1]) } };
  }
  const c = d.center;
  const centerText = [dyadic(c[0]), dyadic(c[1])];
  if (d.operation === "rotate") {
    const angle = Math.atan2(y - c[1], x - c[0]) - Math.atan2(d.start[1] - c[1], d.start[0] - c[0]);
    let degrees = (angle * 180) / Math.PI;
    if (degrees > 180) degrees -= 360;
    if (degrees < -180) degrees += 360;
    return { rotate: { center: centerText, degrees: decimal(degrees, 3) } };
  }
  // Grabbed on the centre: no scaling can be read from the mouse.
  const from = Math.max(Math.hypot(d.start[0] - c[0], d.start[1] - c[1]), 4 / view.scale);
  const to = Math.hypot(x - c[0], y - c[1]);
  const factor = Math.max(to / Math.max(from, 1e-12), 1e-4);
  return { scale: { center: centerText, factor: decimal(factor, 4) } };
}

const isStill = (m) =>
  (m.translate && Number(m.translate.dx) === 0 && Number(m.translate.dy) === 0) ||
  (m.lift && Number(m.lift.dz) === 0) ||
  (m.rotate && Number(m.rotate.degrees) === 0) ||
  (m.scale && Number(m.scale.factor) === 1);

// Applies the moved points of an answer to the drawing; returns their ids.
// `moved`: `[id, x, y]` (or `[id, z]`) per point.
function applyMoved(moved) {
  for (const [id, ...value] of moved) points.get(id).value = value;
  const ids = moved.map(([id]) => id);
  let vertices = 0;
  for (const model of models) vertices += model.update(at, ids);
  return vertices;
}

// Applies a commit's changes (the committed points with their exact values, the counts) to
// the state the page has.
function applyCommitted(changes) {
  const ids = [];
  for (const p of changes.points) {
    const point = points.get(p.id);
    point.value = p.value;
    point.exact = p.exact;
    ids.push(p.id);
  }
  for (const model of models) model.update(at, ids);
  for (const [key, value] of Object.entries(changes)) if (key !== "points") state[key] = value;
  endMoving();
  element("undo").disabled = !state.can_undo;
  element("redo").disabled = !state.can_redo;
  showOffer();
}

async function sendFrame(commit) {
  const d = drag;
  if (!d) return;
  if (d.inFlight) { d.pending = true; return; }
  // A release commits the last move the server accepted: the drag stops at the last valid
  // position when later moves were refused.
  const m = commit ? d.lastValid : motion(d);
  if (commit && (m === null || isStill(m))) { endDrag(); return; }
  d.inFlight = true;
  const began = commit ? d.releaseTime : d.eventTime;
  const first = d.sent === 0;
  d.sent++;
  let record = null;
  try {
    const requested = performance.now();
    const answer = await dragRequest({ selection: d.selection, motion: m, commit, criterion: d.criterion });
    const request = performance.now() - requested;
    if (answer.affine && d.criterion === "L2") d.affine = answer.affine;
    last.criterion = answer.criterion || null;
    if (answer.ok && d.local > 0 && !commit) {
      // The page drew a later move itself already: this frame is stale.
      record = null;
    } else if (answer.ok) {
      blocked = null;
      showMessage(null);
      if (answer.derived_ids) derived = new Set(answer.derived_ids);
      if (answer.relevant) relevant = answer.relevant;
      const starting = answer.derived_ids !== undefined && !commit;
      last.counts = answer;
      const before = commit ? new Map(answer.moved.map(([id]) => [id, points.get(id).value.slice()])) : null;
      const deforming = performance.now();
      const moved = applyMoved(answer.moved);
      const deform = performance.now() - deforming;
      // From the first frame on, only what the drag moves is drawn again.
      if (starting) {
        d.movingIds = [...anchors, ...answer.derived_ids];
        // Initialised again during the drag: the still picture is made again for the new set.
        if (moving !== null) endMoving();
      }
      if (!commit) d.lastValid = m;
      record = { first, request, server: answer.server_ms, deform, moved };
      if (commit) {
        // How far the last drawn frame was from the committed exact values (rounded).
        last.deviation = answer.moved.reduce((worst, [id, ...value]) => {
          const was = before.get(id);
          return Math.max(worst, ...value.map((v, k) => Math.abs(v - was[k])));
        }, 0);
        // What the commit changed, applied to the state the page has; the whole state again
        // only when the views changed meanwhile.
        if (answer.state && answer.state.views_version === state.views_version) applyCommitted(answer.state);
        else setState(await api("/api/state"));
        commits.push(performance.now() - began);
      }
      last.server = answer.server_ms;
    } else {
      blocked = anchors[0];
      showConflict(answer.conflict);
      // A refused release: the picture goes back to the state the server keeps.
      if (commit) await reloadValues();
    }
  } catch (e) {
    showMessage(String(e.message || e));
    if (commit) await reloadValues();
  }
  try {
    finishFrame(d, commit, record, began);
  } finally {
    d.inFlight = false;
  }
  if (commit) {
    // A drag started while this release was committed goes on.
    if (drag === d) endDrag(); else draw();
    return;
  }
  // Moves that came while this frame was computed: the latest is drawn before a release
  // commits it.
  if (d.pending) {
    d.pending = false;
    d.eventTime = performance.now();
    if (d.affine && !d.released) localFrame(d); else { await sendFrame(false); return; }
  }
  if (d.released) await sendFrame(true);
}

// Exact dyadic text `n/2^k` (or an integer) as a number: exact in floating point.
const dyadicValue = (text) => {
  const [n, s] = text.split("/");
  return s === undefined ? Number(n) : Number(n) / Number(s);
};

// A move drawn by the page itself, once the server sent the drag's motion response (a
// translation or lift): the exact optimum at motion c is base + Σ c_k · along_k, evaluated
// here for the screen without a round trip. The release still commits on the server, exactly.
function localFrame(d) {
  const began = d.eventTime;
  const m = motion(d);
  const c = m.lift ? [dyadicValue(m.lift.dz)] : [dyadicValue(m.translate.dx), dyadicValue(m.translate.dy)];
  const a = d.affine;
  if (c.length !== a.along.length) return false;
  const computing = performance.now();
  // In place: a drag's frames allocate nothing per point (no collector pauses mid-drag).
  for (let i = 0; i < a.ids.length; i++) {
    const value = points.get(a.ids[i]).value;
    for (let j = 0; j < a.dim; j++) {
      const at = i * a.dim + j;
      let v = a.base[at];
      for (let k = 0; k < c.length; k++) if (c[k] !== 0) v += c[k] * a.along[k][at];
      value[j] = v;
    }
  }
  let vertices = 0;
  for (const model of models) vertices += model.update(at, a.ids);
  const deform = performance.now() - computing;
  d.lastValid = m;
  d.local++;
  blocked = null;
  finishFrame(d, false, { first: false, request: 0, server: 0, deform, moved: vertices, local: true }, began);
  return true;
}

// Runs `then` as a task of its own: after the paint of the frame whose animation-frame
// callback calls this.
const painted = new MessageChannel();
const afterPaintQueue = [];
painted.port1.onmessage = () => afterPaintQueue.shift()();
function afterPaint(then) {
  afterPaintQueue.push(then);
  painted.port2.postMessage(null);
}

// Draws a frame of drag `d` and records its times.
function finishFrame(d, commit, record, began) {
  if (record !== null && record.first && d.movingIds && moving === null) {
    // The mouse-down frame moves nothing: the anchors and the derived set are drawn over the
    // picture, and the picture of what the drag leaves still is made once the frame is on
    // the screen (before the first move, unless that comes sooner).
    overlay(d.movingIds);
    measure(record, began);
    requestAnimationFrame(() => afterPaint(() => {
      if (drag === d && moving === null) beginMoving(d.movingIds);
    }));
  } else {
    if (drag === d && !commit && d.movingIds && moving === null) beginMoving(d.movingIds);
    draw();
    if (!commit) measure(record, began);
  }
  report();
}

// Records the times of a frame drawn for an event at `began`: ready (drawn into the canvas)
// now, and painted. The browser paints a frame right after its animation-frame callbacks; a
// message posted from the callback is handled once that paint is done (and before work queued
// after it, such as the still picture of a drag).
function measure(record, began) {
  if (record === null) return;
  record.draw = last.draw;
  record.ready = performance.now() - began;
  requestAnimationFrame(() => afterPaint(() => {
    record.total = performance.now() - began;
    last.frame = record.total;
    last.local = record.local === true;
    frames.push(record);
    if (frames.length > 1000) frames.shift();
    report();
  }));
}

// The values as the server keeps them (after a refused or failed release).
async function reloadValues() {
  try {
    setState(await api("/api/state"));
  } catch (e) { showMessage(String(e.message || e)); }
}

function endDrag() { drag = null; endMoving(); draw(); }

function startDrag(id, e) {
  const world = toWorld([e.offsetX, e.offsetY]);
  const op = operation();
  const heights = points.get(id).surface === "top" || points.get(id).surface === "bottom";
  if (op !== "translate" && center === null && !heights) {
    showMessage("Right-click to set the centre of rotation and scaling first.");
    return;
  }
  drag = {
    selection: selection(),
    // The change criterion of the whole drag (frames under L1 or Fewest are not affine in
    // the motion: the server sends no motion response for them).
    criterion: element("criterion").value,
    operation: op,
    lift: heights,
    center,
    start: planeOf(id).slice(),
    grab: world,
    mouse: planeOf(id).slice(),
    lastValid: null,
    affine: null,     // the motion response, once the server sent it (see localFrame)
    local: 0,         // moves drawn by the page itself
    sent: 0,
    eventTime: performance.now(),
    inFlight: false,
    pending: false,
    released: false,
  };
}

canvas.addEventListener("contextmenu", (e) => {
  e.preventDefault();
  center = toWorld([e.offsetX, e.offsetY]);
  draw();
});

canvas.addEventListener("mousedown", (e) => {
  if (e.button !== 0) return;
  const id = pointAt(e.offsetX, e.offsetY);
  if (id === null && in3d() && editMode() === "view" && !e.shiftKey) {
    orbit = { x: e.offsetX, y: e.offsetY };
    return;
  }
  if (id === null) { pan = { x: e.offsetX, y: e.offsetY }; return; }
  const adding = e.shiftKey || shown("add-anchors");
  const sameSource = anchors.length === 0 || points.get(id).source === points.get(anchors[0]).source;
  let changed = false;
  if (adding && sameSource) {
    if (anchors.includes(id)) {
      if (anchors.length > 1) { anchors = anchors.filter((a) => a !== id); changed = true; showSelection(); return; }
    } else { anchors.push(id); changed = true; }
  } else if (!anchors.includes(id)) {
    anchors = [id];
    changed = true;
  }
  blocked = null;
  showMessage(null);
  startDrag(id, e);
  if (drag) {
    // Mouse-down: the edit is planned and initialised at once (a still frame, which also
    // gives the derived set), so the first move only updates.
    last.counts = null;
    relevant = [];
    sendFrame(false);
  } else if (changed) {
    showSelection();
  }
});

canvas.addEventListener("mousemove", (e) => {
  if (orbit) {
    // View mode: turn the scene (18.3).
    setCamera(camera.azimuth + (e.offsetX - orbit.x) * 0.4, camera.elevation + (e.offsetY - orbit.y) * 0.4);
    orbit = { x: e.offsetX, y: e.offsetY };
    return;
  }
  if (pan) {
    view.x += e.offsetX - pan.x; view.y += e.offsetY - pan.y;
    pan = { x: e.offsetX, y: e.offsetY };
    draw();
    return;
  }
  if (!drag) return;
  performance.mark("ecles-move");
  const world = toWorld([e.offsetX, e.offsetY]);
  // The grabbed point follows the mouse: its start plus the mouse's displacement.
  drag.mouse = [drag.start[0] + world[0] - drag.grab[0], drag.start[1] + world[1] - drag.grab[1]];
  drag.eventTime = performance.now();
  if (drag.affine && localFrame(drag)) return;
  sendFrame(false);
});

window.addEventListener("mouseup", () => {
  pan = null;
  orbit = null;
  if (!drag) return;
  drag.released = true;
  drag.releaseTime = performance.now();
  if (!drag.inFlight) sendFrame(true);
});

canvas.addEventListener("wheel", (e) => {
  e.preventDefault();
  const factor = Math.exp(-e.deltaY * 0.001);
  const [wx, wy] = toWorld([e.offsetX, e.offsetY]);
  view.scale *= factor;
  const [sx, sy] = toScreen([wx, wy]);
  view.x += e.offsetX - sx; view.y += e.offsetY - sy;
  viewChanged();
}, { passive: false });

// After a pan, zoom or fit: a drag's picture of what stays still is drawn again.
function viewChanged() {
  if (moving !== null) beginMoving([...moving.ids]);
  draw();
}

// --- the splines: continuity, loading a reference mesh or a model ---------------------

// A button that opens the file chooser; `chosen(file)` gets the file picked.
function fileButton(id, text, accept, chosen) {
  const label = document.createElement("label");
  label.className = "file";
  const input = document.createElement("input");
  input.type = "file";
  input.id = id;
  input.accept = accept;
  input.addEventListener("change", () => {
    if (input.files[0]) chosen(input.files[0]);
    input.value = "";
  });
  label.append(text, input);
  return label;
}

// Per spline: its degree, the continuity it keeps (C0 … C(d−1), what the source allows) and
// the files it can take from this computer.
function showSources() {
  const box = element("sources");
  box.textContent = "";
  for (const s of state.sources) {
    const v = s.view;
    if (!v || !v.kind) continue;
    const row = document.createElement("div");
    row.className = "source";
    const title = document.createElement("div");
    title.textContent = `${s.name}: degree ${v.degree}`;
    const continuity = document.createElement("select");
    continuity.id = `continuity-${s.name}`;
    for (let r = 0; r < Math.max(1, v.degree); r++) {
      const option = document.createElement("option");
      option.value = r;
      option.textContent = `C${r}`;
      option.selected = r === v.smoothness;
      continuity.append(option);
    }
    continuity.addEventListener("change", () => setContinuity(s.name, Number(continuity.value)));
    const label = document.createElement("label");
    label.title = "The continuity the spline keeps between its patches (C0: none beyond meeting)";
    label.append("continuity ", continuity);
    row.append(
      title,
      label,
      fileButton(`load-mesh-${s.name}`, "reference mesh… ", ".obj", (file) => loadFile(s.name, "mesh", file)),
      fileButton(`load-model-${s.name}`, "model… ", ".obj,.stl,.ply,.gltf,.glb,.asc,.tif,.tiff", (file) => loadFile(s.name, "model", file)),
    );
    box.append(row);
  }
  if (box.childElementCount === 0) box.textContent = "no spline";
}

// After the sources were rebuilt: no selection or edit of the old system is kept.
function clearEdit() {
  anchors = []; derived = new Set(); relevant = []; blocked = null; last.counts = null;
}

async function setContinuity(source, smoothness) {
  try {
    const answer = await api("/api/continuity", { source, smoothness });
    setState(answer);
    clearEdit();
    const moved = answer.configured.projected;
    showMessage(moved > 0
      ? `${source} is C${smoothness} now: the deformation was not, so ${moved} points moved to the nearest C${smoothness} one (Undo takes it back).`
      : null);
  } catch (e) {
    showSources();
    showMessage(`Continuity not changed: ${e.message || e}`);
  }
  report();
  draw();
}

// A file from this computer as the reference mesh or the model of `source`; the server keeps a
// copy beside the run file and checks it as `ecles run` would.
async function loadFile(source, kind, file) {
  const query = new URLSearchParams({ source, kind, name: file.name });
  try {
    const answer = await send(`/api/load?${query}`, "POST", "application/octet-stream", file);
    setState(answer);
    clearEdit();
    if (kind === "mesh") fit();
    showMessage(`Loaded ${file.name} as the ${kind === "mesh" ? "reference mesh" : "model"} of ${source} (kept as ${answer.loaded}).`);
  } catch (e) {
    showMessage(String(e.message || e));
  }
  report();
  draw();
}

// --- history, saving, settings ---------------------------------------------------------

async function history(path) {
  try {
    setState(await api(path, {}));
    derived = new Set(); relevant = []; blocked = null; last.counts = null; showMessage(null);
  } catch (e) { showMessage(String(e.message || e)); }
  report();
  draw();
}

// Back to the server's state (a drag cancelled: nothing was committed).
async function reload() {
  try {
    setState(await api("/api/state"));
    blocked = null; showMessage(null);
  } catch (e) { showMessage(String(e.message || e)); }
  report();
  draw();
}

async function save() {
  const name = element("save-name").value.trim();
  try {
    const saved = await api("/api/save", { name: name === "" ? null : name });
    showMessage(`Saved ${saved.edits} edits as ${saved.run}; ${saved.files.join(", ")} and report.json in ${saved.out}.`);
  } catch (e) { showMessage(`Not saved: ${e.message || e}`); }
}

element("undo").addEventListener("click", () => history("/api/undo"));
element("redo").addEventListener("click", () => history("/api/redo"));
element("fit").addEventListener("click", () => { fit(); viewChanged(); });
element("save").addEventListener("click", save);
element("help-button").addEventListener("click", toggleHelp);
element("explain-button").addEventListener("click", explainAnchors);
for (const id of ["show-net", "show-reference", "show-points", "show-model", "show-image", "show-derived",
  "show-constraints", "show-relevant", "image-opacity", "image-x", "image-y", "image-scale"]) {
  element(id).addEventListener("input", () => {
    if (moving !== null) beginMoving([...moving.ids]);
    draw();
  });
}
for (const input of document.querySelectorAll("input[name=operation]")) input.addEventListener("change", draw);
for (const id of ["neighborhood", "all"]) element(id).addEventListener("change", showSelection);
element("image-file").addEventListener("change", () => {
  const file = element("image-file").files[0];
  if (!file) return;
  const loaded = new Image();
  loaded.onload = () => { image = loaded; draw(); };
  loaded.onerror = () => showMessage(`${file.name} is not an image this browser can read`);
  loaded.src = URL.createObjectURL(file);
});

function setCamera(azimuth, elevation) {
  camera.azimuth = ((azimuth % 360) + 540) % 360 - 180;
  camera.elevation = Math.min(90, Math.max(0, elevation));
  element("azimuth").value = camera.azimuth;
  element("elevation").value = camera.elevation;
  draw();
}

for (const id of ["azimuth", "elevation", "exaggeration"]) {
  element(id).addEventListener("input", () => {
    camera.exaggeration = Number(element("exaggeration").value) || 1;
    setCamera(Number(element("azimuth").value), Number(element("elevation").value));
  });
}
for (const input of document.querySelectorAll("input[name=mode]")) {
  input.addEventListener("change", () => {
    anchors = [];
    derived = new Set();
    relevant = [];
    fit();
    draw();
  });
}
element("show-shaded").addEventListener("input", draw);

function setOperation(value) {
  document.querySelector(`input[name=operation][value=${value}]`).checked = true;
  draw();
}

window.addEventListener("keydown", (e) => {
  if (e.target.tagName === "INPUT" && (e.target.type === "number" || e.target.type === "text")) return;
  const ctrl = e.ctrlKey || e.metaKey;
  if (ctrl && e.key === "z") { e.preventDefault(); history("/api/undo"); }
  else if (ctrl && e.key === "y") { e.preventDefault(); history("/api/redo"); }
  else if (ctrl && e.key === "s") { e.preventDefault(); save(); }
  else if (ctrl) return;
  else if (e.key === "f") { fit(); viewChanged(); }
  else if (e.key === "t") setOperation("translate");
  else if (e.key === "r") setOperation("rotate");
  else if (e.key === "s") setOperation("scale");
  else if (e.key === "a") { element("all").checked = !element("all").checked; showSelection(); }
  else if (e.key === "+" || e.key === "-") {
    const input = element("neighborhood");
    input.value = Math.max(0, Number(input.value) + (e.key === "+" ? 1 : -1));
    showSelection();
  } else if (e.key === "?") toggleHelp();
  else if (e.key === "e") explainAnchors();
  else if (e.key === "Escape") {
    if (drag) { drag = null; endMoving(); reload(); }
    element("help").hidden = true;
    element("explain").hidden = true;
  }
});
window.addEventListener("resize", draw);

// The run file's target image (its settings into the panel, the picture from the server).
function loadTargetImage(settings) {
  element("image-opacity").value = settings.opacity;
  element("image-x").value = settings.x;
  element("image-y").value = settings.y;
  element("image-scale").value = settings.units_per_pixel;
  const loaded = new Image();
  loaded.onload = () => { image = loaded; draw(); };
  loaded.onerror = () => showMessage(`${settings.file}: this browser cannot draw it`);
  loaded.src = token ? `/api/image?token=${encodeURIComponent(token)}` : "/api/image";
}

(async () => {
  openSocket();
  try {
    setState(await api("/api/state"));
    if (state.image) loadTargetImage(state.image);
    fit();
    report();
  } catch (e) {
    statusBar.textContent = `cannot load the state: ${e.message || e}`;
  }
  draw();
})();
