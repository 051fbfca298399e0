"use strict";
// The page of `ecles edit`: draws each source's view from the current values and drags
// control points. The server keeps the exact state; everything here is for drawing.

const token = new URLSearchParams(location.search).get("token");
const canvas = document.getElementById("view");
const ctx = canvas.getContext("2d");
const statusBar = document.getElementById("status");
const conflictPanel = document.getElementById("conflict");

let state = null;          // the server's state
let points = new Map();    // parameter id -> {name, value: [x, y], source}
let anchors = [];          // selected anchor ids
let derived = new Set();   // ids moved by the last drag
let blocked = null;        // id of an anchor whose move was refused
let view = { scale: 1, x: 0, y: 0 };  // world -> screen: (x * scale + view.x, -y * scale + view.y)
let drag = null;           // {start: [x, y], last: [dx, dy], base: Map, inFlight, pending}
let pan = null;

async function api(path, body) {
  const headers = { "content-type": "application/json" };
  if (token) headers["x-ecles-token"] = token;
  const response = await fetch(path, {
    method: body === undefined ? "GET" : "POST",
    headers,
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  const answer = await response.json().catch(() => ({ error: response.statusText }));
  if (!response.ok) throw new Error(answer.error || response.statusText);
  return answer;
}

function setState(next) {
  state = next;
  points = new Map();
  const sourceOf = new Map();
  for (const source of state.sources) {
    if (source.view && source.view.patches) {
      for (const patch of source.view.patches) for (const id of patch) sourceOf.set(id, source.name);
    }
  }
  for (const p of state.points) {
    points.set(p.id, { name: p.name, value: p.value, exact: p.exact, source: sourceOf.get(p.id) });
  }
  undoButton().disabled = !state.can_undo;
  redoButton().disabled = !state.can_redo;
}

const undoButton = () => document.getElementById("undo");
const redoButton = () => document.getElementById("redo");

// Multi-indices (i, j, k), i + j + k = d, lexicographically descending (the view's order).
function multiIndices(d) {
  const out = [];
  for (let i = d; i >= 0; i--) for (let j = d - i; j >= 0; j--) out.push([i, j, d - i - j]);
  return out;
}

function bezierCurve(ctrl, t) {
  const pts = ctrl.map((p) => p.slice());
  for (let r = 1; r < pts.length; r++) {
    for (let i = 0; i < pts.length - r; i++) {
      pts[i] = [pts[i][0] * (1 - t) + pts[i + 1][0] * t, pts[i][1] * (1 - t) + pts[i + 1][1] * t];
    }
  }
  return pts[0];
}

const toScreen = ([x, y]) => [x * view.scale + view.x, -y * view.scale + view.y];
const toWorld = ([sx, sy]) => [(sx - view.x) / view.scale, -(sy - view.y) / view.scale];

function fit() {
  const all = [...points.values()].map((p) => p.value);
  if (all.length === 0) return;
  const xs = all.map((p) => p[0]), ys = all.map((p) => p[1]);
  const [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
  const w = canvas.clientWidth, h = canvas.clientHeight, margin = 30;
  view.scale = Math.min((w - 2 * margin) / Math.max(x1 - x0, 1e-9), (h - 2 * margin) / Math.max(y1 - y0, 1e-9));
  view.x = (w - (x1 - x0) * view.scale) / 2 - x0 * view.scale;
  view.y = (h + (y1 - y0) * view.scale) / 2 + y0 * view.scale;
}

function line(a, b) {
  const [p, q] = [toScreen(a), toScreen(b)];
  ctx.moveTo(p[0], p[1]);
  ctx.lineTo(q[0], q[1]);
}

function draw() {
  const ratio = window.devicePixelRatio || 1;
  canvas.width = canvas.clientWidth * ratio;
  canvas.height = canvas.clientHeight * ratio;
  ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
  ctx.clearRect(0, 0, canvas.clientWidth, canvas.clientHeight);
  if (!state) return;
  const at = (id) => points.get(id).value;
  for (const source of state.sources) {
    const v = source.view;
    if (!v || v.kind !== "bezier_triangles") continue;
    const indices = multiIndices(v.degree);
    const slot = new Map(indices.map((m, k) => [m.join(","), k]));
    if (document.getElementById("show-reference").checked) {
      ctx.beginPath();
      ctx.strokeStyle = "#c8c8c8";
      ctx.lineWidth = 1;
      for (const [a, b, c] of v.triangles) {
        line(v.vertices[a], v.vertices[b]); line(v.vertices[b], v.vertices[c]); line(v.vertices[c], v.vertices[a]);
      }
      ctx.stroke();
    }
    if (document.getElementById("show-net").checked) {
      ctx.beginPath();
      ctx.strokeStyle = "#9a9a9a";
      ctx.setLineDash([3, 3]);
      for (const patch of v.patches) {
        for (const [i, j, k] of indices) {
          const here = at(patch[slot.get([i, j, k].join(","))]);
          if (i > 0) {
            line(here, at(patch[slot.get([i - 1, j + 1, k].join(","))]));
            line(here, at(patch[slot.get([i - 1, j, k + 1].join(","))]));
          }
          if (j > 0) line(here, at(patch[slot.get([i, j - 1, k + 1].join(","))]));
        }
      }
      ctx.stroke();
      ctx.setLineDash([]);
    }
    // The deformed mesh: each patch's three boundary curves.
    ctx.beginPath();
    ctx.strokeStyle = "#202020";
    ctx.lineWidth = 1.5;
    const d = v.degree;
    for (const patch of v.patches) {
      for (const edge of [[0, 1], [1, 2], [2, 0]]) {
        const ctrl = [];
        for (let s = 0; s <= d; s++) {
          const m = [0, 0, 0];
          m[edge[0]] = d - s;
          m[edge[1]] = s;
          ctrl.push(at(patch[slot.get(m.join(","))]));
        }
        const samples = Math.max(2, 4 * d);
        let prev = toScreen(ctrl[0]);
        ctx.moveTo(prev[0], prev[1]);
        for (let n = 1; n <= samples; n++) {
          const p = toScreen(bezierCurve(ctrl, n / samples));
          ctx.lineTo(p[0], p[1]);
        }
      }
    }
    ctx.stroke();
  }
  if (document.getElementById("show-points").checked) {
    for (const [id, p] of points) {
      if (p.source === undefined) continue;
      const [x, y] = toScreen(p.value);
      const anchor = anchors.includes(id);
      ctx.fillStyle = id === blocked ? "#d00000" : anchor ? "#e07000" : derived.has(id) ? "#2060c0" : "#404040";
      ctx.beginPath();
      ctx.arc(x, y, anchor ? 5 : 3, 0, 2 * Math.PI);
      ctx.fill();
    }
  }
}

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

function report(text) { statusBar.textContent = text; }

function describe(extra) {
  const s = state;
  return `${s.run} · ${s.points.length} points · ${s.rows} rows · violated rows ${s.violated_rows}` +
    (extra ? ` · ${extra}` : "");
}

function showConflict(message) {
  conflictPanel.hidden = message === null;
  conflictPanel.textContent = message || "";
}

// Exact decimal text for a displacement (the server reads it exactly).
const decimal = (v) => (Math.round(v * 1e6) / 1e6).toFixed(6);

async function sendFrame(commit) {
  if (!drag) return;
  if (drag.inFlight) { drag.pending = true; if (commit) drag.commitPending = true; return; }
  drag.inFlight = true;
  const [dx, dy] = drag.last;
  const source = points.get(anchors[0]).source;
  const prefix = source + ".";
  const all = document.getElementById("all").checked;
  const body = {
    source,
    anchors: anchors.map((id) => points.get(id).name.slice(prefix.length)),
    neighborhood: all ? null : Number(document.getElementById("neighborhood").value),
    dx: decimal(dx),
    dy: decimal(dy),
    commit,
  };
  const began = performance.now();
  try {
    const answer = await api("/api/drag", body);
    if (answer.ok) {
      blocked = null;
      showConflict(null);
      derived = new Set();
      for (const m of answer.moved) {
        points.get(m.id).value = m.value;
        if (!anchors.includes(m.id)) derived.add(m.id);
      }
      const frame = (performance.now() - began).toFixed(1);
      report(describe(`|D| ${answer.derived} · rank ${answer.rank} · redundant ${answer.redundant} · ` +
        `server ${answer.server_ms.toFixed(1)} ms · frame ${frame} ms`));
      if (answer.committed) setState(await api("/api/state"));
    } else {
      blocked = anchors[0];
      showConflict(answer.conflict);
      if (commit) setState(await api("/api/state"));
    }
  } catch (e) {
    showConflict(String(e.message || e));
  }
  draw();
  if (!drag) return;
  drag.inFlight = false;
  if (drag.commitPending) { drag.commitPending = false; drag.pending = false; await sendFrame(true); drag = null; return; }
  if (drag.pending) { drag.pending = false; await sendFrame(false); }
}

canvas.addEventListener("mousedown", (e) => {
  const id = pointAt(e.offsetX, e.offsetY);
  if (id === null) { pan = { x: e.offsetX, y: e.offsetY }; return; }
  if (e.shiftKey) {
    if (!anchors.includes(id) && points.get(id).source === points.get(anchors[0] ?? id).source) anchors.push(id);
  } else if (!anchors.includes(id)) {
    anchors = [id];
  }
  derived = new Set();
  drag = { start: toWorld([e.offsetX, e.offsetY]), last: [0, 0], inFlight: false, pending: false };
  draw();
});

canvas.addEventListener("mousemove", (e) => {
  if (pan) {
    view.x += e.offsetX - pan.x; view.y += e.offsetY - pan.y;
    pan = { x: e.offsetX, y: e.offsetY };
    draw();
    return;
  }
  if (!drag) return;
  const [x, y] = toWorld([e.offsetX, e.offsetY]);
  drag.last = [x - drag.start[0], y - drag.start[1]];
  sendFrame(false);
});

window.addEventListener("mouseup", async () => {
  pan = null;
  if (!drag) return;
  const d = drag;
  if (d.last[0] === 0 && d.last[1] === 0) { drag = null; return; }
  if (d.inFlight) { d.commitPending = true; return; }
  await sendFrame(true);
  drag = null;
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

async function history(path) {
  try {
    setState(await api(path, {}));
    derived = new Set(); blocked = null; showConflict(null);
    report(describe());
  } catch (e) { showConflict(String(e.message || e)); }
  draw();
}

undoButton().addEventListener("click", () => history("/api/undo"));
redoButton().addEventListener("click", () => history("/api/redo"));
document.getElementById("fit").addEventListener("click", () => { fit(); draw(); });
for (const id of ["show-net", "show-reference", "show-points"]) {
  document.getElementById(id).addEventListener("change", draw);
}
window.addEventListener("keydown", (e) => {
  if (e.target.tagName === "INPUT" && e.target.type === "number") return;
  if ((e.ctrlKey || e.metaKey) && e.key === "z") history("/api/undo");
  else if ((e.ctrlKey || e.metaKey) && e.key === "y") history("/api/redo");
  else if (e.key === "f") { fit(); draw(); }
});
window.addEventListener("resize", draw);

(async () => {
  try {
    setState(await api("/api/state"));
    fit();
    report(describe());
  } catch (e) {
    report(`cannot load the state: ${e.message || e}`);
  }
  draw();
})();
