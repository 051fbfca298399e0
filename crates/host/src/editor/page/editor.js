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
let models = [];           // DeformedModel per model of every view
let anchors = [];          // selected anchor ids
let derived = new Set();   // the derived set of the selection or of the drag
let relevant = [];         // rows the current edit keeps: {label, points}
let blocked = null;        // id of an anchor whose move was refused
let center = null;         // centre of rotation and scaling (world), set by right-click
let view = { scale: 1, x: 0, y: 0 };  // world -> screen: (x * scale + view.x, -y * scale + view.y)
let drag = null;           // the drag under way, see startDrag
let pan = null;
let image = null;          // the target image: an HTMLImageElement
let last = { frame: null, server: null, draw: null, deviation: null, counts: null };
// The last 1000 drag frames' times in ms, for the status bar and measurements: `total` from
// the mouse event to the painted frame, `request` the round trip of its request, `server`
// the server's part of it, `deform` the model's deformation, `draw` the drawing, `ready` from
// the event to the frame drawn into the canvas (before the browser's next paint); `first` marks the mouse-down frame (2DSD
// Select, ExpandDerived and ECLES Initialize), `moved` counts the model vertices recomputed.
const frames = [];
// Times from the mouse release to the committed state drawn, in ms.
const commits = [];

// --- talking to the server -------------------------------------------------------------

let busy = 0;
async function api(path, body) {
  const headers = { "content-type": "application/json" };
  if (token) headers["x-ecles-token"] = token;
  busy++;
  // Anything over 200 ms shows the progress indicator.
  const timer = setTimeout(() => { element("progress").hidden = busy === 0; }, 200);
  try {
    const response = await fetch(path, {
      method: body === undefined ? "GET" : "POST",
      headers,
      body: body === undefined ? undefined : JSON.stringify(body),
    });
    const answer = await response.json().catch(() => ({ error: response.statusText }));
    if (!response.ok) throw new Error(answer.error || response.statusText);
    return answer;
  } finally {
    clearTimeout(timer);
    busy--;
    if (busy === 0) element("progress").hidden = true;
  }
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

async function dragRequest(body) {
  if (socket === null || socket.readyState !== WebSocket.OPEN) return api("/api/drag", body);
  busy++;
  const timer = setTimeout(() => { element("progress").hidden = busy === 0; }, 200);
  try {
    const answer = await new Promise((resolve) => {
      waiting.push(resolve);
      socket.send(JSON.stringify(body));
    });
    if (answer.error) throw new Error(answer.error);
    return answer;
  } finally {
    clearTimeout(timer);
    busy--;
    if (busy === 0) element("progress").hidden = true;
  }
}

function setState(next) {
  state = next;
  // Models and views are new objects: the picture of a drag's still part is stale.
  endMoving();
  points = new Map();
  const sourceOf = new Map();
  models = [];
  for (const source of state.sources) {
    const v = source.view;
    if (!v || !v.patches) continue;
    for (const patch of v.patches) for (const id of patch) sourceOf.set(id, source.name);
    for (const model of v.models || []) models.push(new DeformedModel(v, model));
  }
  for (const p of state.points) {
    points.set(p.id, { name: p.name, value: p.value, exact: p.exact, source: sourceOf.get(p.id) });
  }
  for (const model of models) model.update(at, null);
  anchors = anchors.filter((id) => points.has(id) && points.get(id).source !== undefined);
  element("undo").disabled = !state.can_undo;
  element("redo").disabled = !state.can_redo;
  element("sources").textContent = state.sources
    .filter((s) => s.view && s.view.kind)
    .map((s) => `${s.name}: degree ${s.view.degree}, C${s.view.smoothness}`)
    .join("\n") || "no spline";
  showOffer();
}

const at = (id) => points.get(id).value;

// --- drawing ---------------------------------------------------------------------------

const toScreen = ([x, y]) => [x * view.scale + view.x, -y * view.scale + view.y];
const toWorld = ([sx, sy]) => [(sx - view.x) / view.scale, -(sy - view.y) / view.scale];

function fit() {
  const all = [...points.values()].filter((p) => p.source !== undefined).map((p) => p.value);
  if (all.length === 0) return;
  const xs = all.map((p) => p[0]), ys = all.map((p) => p[1]);
  const [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
  const w = canvas.clientWidth, h = canvas.clientHeight, margin = 30;
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
    if (!v || !v.patches) continue;
    const t = new Set();
    v.patches.forEach((patch, k) => { if (patch.some((id) => set.has(id))) t.add(k); });
    triangles.set(v, t);
  }
  const faces = new Map();
  for (const model of models) {
    const t = triangles.get(model.view) || new Set();
    const inside = new Uint8Array(model.faces.length);
    model.faces.forEach((face, k) => {
      if (face.some((vertex) => t.has(model.triangleOf[vertex]))) inside[k] = 1;
    });
    faces.set(model, inside);
  }
  return { ids: set, triangles, faces };
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

function drawView(v, part) {
  const indices = multiIndices(v.degree);
  const slot = new Map(indices.map((m, k) => [m.join(","), k]));
  const movingTriangles = moving === null ? null : moving.triangles.get(v) || null;
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
  if (shown("show-net")) {
    g.beginPath();
    // Solid and light: dashes cost much more to draw on a big net.
    g.strokeStyle = "#b4b4c8";
    v.patches.forEach((patch, t) => {
      if (!drawn(t)) return;
      for (const [i, j, k] of indices) {
        const here = at(patch[slot.get([i, j, k].join(","))]);
        if (i > 0) {
          line(here, at(patch[slot.get([i - 1, j + 1, k].join(","))]));
          line(here, at(patch[slot.get([i - 1, j, k + 1].join(","))]));
        }
        if (j > 0) line(here, at(patch[slot.get([i, j - 1, k + 1].join(","))]));
      }
    });
    g.stroke();
  }
  // The deformed mesh: each patch's three boundary curves.
  g.beginPath();
  g.strokeStyle = "#202020";
  g.lineWidth = 1.5;
  const d = v.degree;
  v.patches.forEach((patch, t) => {
    if (!drawn(t)) return;
    for (const edge of [[0, 1], [1, 2], [2, 0]]) {
      const ctrl = [];
      for (let s = 0; s <= d; s++) {
        const m = [0, 0, 0];
        m[edge[0]] = d - s;
        m[edge[1]] = s;
        ctrl.push(at(patch[slot.get(m.join(","))]));
      }
      const samples = Math.max(2, 4 * d);
      const table = curveWeights(d, samples);
      for (let n = 0; n <= samples; n++) {
        const w = table[n];
        let x = 0, y = 0;
        for (let k = 0; k <= d; k++) { x += w[k] * ctrl[k][0]; y += w[k] * ctrl[k][1]; }
        const [sx, sy] = toScreen([x, y]);
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
    const p = model.positions;
    const inside = moving === null ? null : moving.faces.get(model) || null;
    model.faces.forEach((face, k) => {
      if (!inPart(part, inside !== null && inside[k] === 1)) return;
      const [x0, y0] = toScreen(p[face[0]]);
      g.moveTo(x0, y0);
      for (let n = 1; n < face.length; n++) {
        const [x, y] = toScreen(p[face[n]]);
        g.lineTo(x, y);
      }
      g.lineTo(x0, y0);
    });
  }
  g.stroke();
}

// Points as squares (one path per colour: thousands of points draw in one call each).
function drawPoints(part) {
  if (!shown("show-points")) return;
  const styles = new Map();
  for (const [id, p] of points) {
    if (p.source === undefined) continue;
    if (!inPart(part, moving !== null && moving.ids.has(id))) continue;
    const anchor = anchors.includes(id);
    const isDerived = derived.has(id) && shown("show-derived");
    const colour = id === blocked ? "#d00000" : anchor ? "#e07000" : isDerived ? "#2060c0" : "#404040";
    const size = anchor || id === blocked ? 5 : isDerived ? 3.5 : 2.5;
    const key = `${colour} ${size}`;
    if (!styles.has(key)) styles.set(key, []);
    styles.get(key).push(toScreen(p.value));
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
    if (source.view && source.view.kind === "bezier_triangles") drawView(source.view, part);
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
    `${s.committed} edits`,
  ];
  if (last.counts) {
    const c = last.counts;
    parts.push(`|A| ${c.anchors} · |D| ${c.derived} · rank ${c.rank} · redundant ${c.redundant}`);
  } else if (anchors.length > 0) {
    parts.push(`|A| ${anchors.length} · |D| ${derived.size}`);
  }
  if (last.frame !== null && last.server !== null) {
    parts.push(`frame ${last.frame.toFixed(1)} ms (server ${last.server.toFixed(1)}, drawing ${last.draw.toFixed(1)})`);
  }
  if (last.deviation !== null) parts.push(`float deviation ${last.deviation.toExponential(1)}`);
  if (s.autosave && s.autosave.error) parts.push(`AUTOSAVE FAILED: ${s.autosave.error}`);
  statusBar.textContent = parts.join(" · ");
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
  ["Ctrl+Z / Ctrl+Y", "undo / redo a committed edit"],
  ["Ctrl+S", "save the session (run file, outputs, exact values)"],
  ["Esc", "cancel the drag under way"],
  ["?", "this help"],
];

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
  for (const [id, p] of points) {
    if (p.source === undefined) continue;
    const [x, y] = toScreen(p.value);
    const distance = Math.hypot(x - sx, y - sy);
    if (distance < bestDistance) { best = id; bestDistance = distance; }
  }
  return best;
}

const operation = () => document.querySelector("input[name=operation]:checked").value;

function selection() {
  const source = points.get(anchors[0]).source;
  const prefix = source + ".";
  return {
    source,
    anchors: anchors.map((id) => points.get(id).name.slice(prefix.length)),
    neighborhood: shown("all") ? null : Number(element("neighborhood").value),
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

// The motion of the drag so far, as the server takes it.
function motion(d) {
  const [x, y] = d.mouse;
  if (d.operation === "translate") {
    return { translate: { dx: decimal(x - d.start[0], 6), dy: decimal(y - d.start[1], 6) } };
  }
  const c = d.center;
  const centerText = [decimal(c[0], 6), decimal(c[1], 6)];
  if (d.operation === "rotate") {
    const angle = Math.atan2(y - c[1], x - c[0]) - Math.atan2(d.start[1] - c[1], d.start[0] - c[0]);
    let degrees = (angle * 180) / Math.PI;
    if (degrees > 180) degrees -= 360;
    if (degrees < -180) degrees += 360;
    return { rotate: { center: centerText, degrees: decimal(degrees, 3) } };
  }
  const from = Math.hypot(d.start[0] - c[0], d.start[1] - c[1]);
  const to = Math.hypot(x - c[0], y - c[1]);
  const factor = Math.max(to / Math.max(from, 1e-12), 1e-4);
  return { scale: { center: centerText, factor: decimal(factor, 4) } };
}

const isStill = (m) =>
  (m.translate && Number(m.translate.dx) === 0 && Number(m.translate.dy) === 0) ||
  (m.rotate && Number(m.rotate.degrees) === 0) ||
  (m.scale && Number(m.scale.factor) === 1);

// Applies the moved points of an answer to the drawing; returns their ids.
function applyMoved(moved) {
  for (const m of moved) points.get(m.id).value = m.value;
  const ids = moved.map((m) => m.id);
  let vertices = 0;
  for (const model of models) vertices += model.update(at, ids);
  return vertices;
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
    const answer = await dragRequest({ selection: d.selection, motion: m, commit });
    const request = performance.now() - requested;
    if (answer.ok) {
      blocked = null;
      showMessage(null);
      if (answer.derived_ids) derived = new Set(answer.derived_ids);
      if (answer.relevant) relevant = answer.relevant;
      const starting = answer.derived_ids !== undefined && !commit;
      last.counts = answer;
      const before = commit ? new Map(answer.moved.map((x) => [x.id, points.get(x.id).value.slice()])) : null;
      const deforming = performance.now();
      const moved = applyMoved(answer.moved);
      const deform = performance.now() - deforming;
      // From the first frame on, only what the drag moves is drawn again.
      if (starting) beginMoving([...anchors, ...answer.derived_ids]);
      if (!commit) d.lastValid = m;
      record = { first, request, server: answer.server_ms, deform, moved };
      if (commit) {
        // How far the last drawn frame was from the committed exact values (rounded).
        last.deviation = Math.max(0, ...answer.moved.map((x) => {
          const was = before.get(x.id);
          return Math.max(...x.value.map((v, k) => Math.abs(v - was[k])));
        }));
        setState(await api("/api/state"));
        commits.push(performance.now() - began);
      }
      last.server = answer.server_ms;
    } else {
      blocked = anchors[0];
      showConflict(answer.conflict);
    }
  } catch (e) {
    showMessage(String(e.message || e));
  }
  draw();
  if (!commit && record !== null) {
    record.draw = last.draw;
    record.ready = performance.now() - began;
    // Painted: the next animation frame runs after this one is on the screen.
    requestAnimationFrame(() => {
      record.total = performance.now() - began;
      last.frame = record.total;
      frames.push(record);
      if (frames.length > 1000) frames.shift();
      report();
    });
  }
  report();
  d.inFlight = false;
  if (commit) { endDrag(); return; }
  // Moves that came while this frame was computed: the latest is drawn before a release
  // commits it.
  if (d.pending) { d.pending = false; d.eventTime = performance.now(); await sendFrame(false); return; }
  if (d.released) await sendFrame(true);
}

function endDrag() { drag = null; endMoving(); draw(); }

function startDrag(id, e) {
  const world = toWorld([e.offsetX, e.offsetY]);
  const op = operation();
  if (op !== "translate" && center === null) {
    showMessage("Right-click to set the centre of rotation and scaling first.");
    return;
  }
  drag = {
    selection: selection(),
    operation: op,
    center,
    start: points.get(id).value.slice(),
    grab: world,
    mouse: points.get(id).value.slice(),
    lastValid: null,
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
  sendFrame(false);
});

window.addEventListener("mouseup", () => {
  pan = null;
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
  draw();
}, { passive: false });

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
element("fit").addEventListener("click", () => { fit(); draw(); });
element("save").addEventListener("click", save);
element("help-button").addEventListener("click", toggleHelp);
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
  else if (e.key === "f") { fit(); draw(); }
  else if (e.key === "t") setOperation("translate");
  else if (e.key === "r") setOperation("rotate");
  else if (e.key === "s") setOperation("scale");
  else if (e.key === "a") { element("all").checked = !element("all").checked; showSelection(); }
  else if (e.key === "+" || e.key === "-") {
    const input = element("neighborhood");
    input.value = Math.max(0, Number(input.value) + (e.key === "+" ? 1 : -1));
    showSelection();
  } else if (e.key === "?") toggleHelp();
  else if (e.key === "Escape") {
    if (drag) { drag = null; endMoving(); reload(); }
    element("help").hidden = true;
  }
});
window.addEventListener("resize", draw);

(async () => {
  openSocket();
  try {
    setState(await api("/api/state"));
    fit();
    report();
  } catch (e) {
    statusBar.textContent = `cannot load the state: ${e.message || e}`;
  }
  draw();
})();
