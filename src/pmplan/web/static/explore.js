// pmplan explore: the page. Plain JS, no build step, no network but this server.
// The server plans (POST /api/plan, the JSON of `pmplan plan`) and maps domains
// (POST /api/domain-map); this page only draws and lets points be dragged.
"use strict";
(function () {
  const W = 800, H = 600, SNAP = 0.25, MAX_ROBOTS = 8, MIN_OBS = 2, MAX_OBS = 6;
  const COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
                  "#e377c2", "#8c564b"];
  const MAP_COLORS = ["#8dd3c7", "#ffffb3", "#bebada", "#fb8072", "#80b1d3", "#fdb462",
                      "#b3de69", "#fccde5", "#bc80bd", "#ccebc5", "#ffed6f", "#d9d9d9"];
  const SVGNS = "http://www.w3.org/2000/svg";
  const $ = (id) => document.getElementById(id);

  const state = {
    obstacles: [[0, 0], [4, 0]],
    start: [[1, 1]],
    goal: [[3, -1]],
    view: { x0: -3, y0: -4.5, scale: 50 },
    box: null,  // the workspace box [[x0, y0], [x1, y1]] (two draggable corners), or null
    plan: null, error: null, t: 0, playing: false,
    fitAfterPlan: false, mapKey: null, map: null,
  };
  const net = { seq: 0, busy: false, dirty: false, timer: null,
                mapBusy: false, mapDirty: false };

  // ---------------------------------------------------------------- geometry
  const sx = (x) => (x - state.view.x0) * state.view.scale;
  const sy = (y) => H - (y - state.view.y0) * state.view.scale;
  const wx = (px) => px / state.view.scale + state.view.x0;
  const wy = (py) => (H - py) / state.view.scale + state.view.y0;
  const snap = (v) => ($("snap").checked ? Math.round(v / SNAP) * SNAP : v);

  function fit(points) {
    let xs = points.map((p) => p[0]), ys = points.map((p) => p[1]);
    let xa = Math.min(...xs) - 1.5, xb = Math.max(...xs) + 1.5;
    let ya = Math.min(...ys) - 1.5, yb = Math.max(...ys) + 1.5;
    const scale = Math.min(W / (xb - xa), H / (yb - ya));
    // a scale that is a power of two times 10 keeps the 1/4 grid on whole pixels more often
    state.view.scale = scale;
    state.view.x0 = (xa + xb) / 2 - W / scale / 2;
    state.view.y0 = (ya + yb) / 2 - H / scale / 2;
  }

  function positionAt(plan, t) {  // (m+n, 2) at time t, linear between waypoints
    const ts = plan.times, wp = plan.waypoints;
    let k = 0;
    while (k < ts.length - 2 && ts[k + 1] < t) k++;
    const a = ts[k], b = ts[k + 1];
    const s = b > a ? Math.min(1, Math.max(0, (t - a) / (b - a))) : 1;
    return wp[k].map((p, i) => [p[0] + s * (wp[k + 1][i][0] - p[0]),
                                p[1] + s * (wp[k + 1][i][1] - p[1])]);
  }

  // ---------------------------------------------------------------- drawing
  function el(tag, attrs, parent) {
    const e = document.createElementNS(SVGNS, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    if (parent) parent.appendChild(e);
    return e;
  }

  function star(r) {
    const pts = [];
    for (let k = 0; k < 10; k++) {
      const a = Math.PI / 2 + k * Math.PI / 5, rr = k % 2 ? r * 0.45 : r;
      pts.push(`${(rr * Math.cos(a)).toFixed(2)},${(-rr * Math.sin(a)).toFixed(2)}`);
    }
    return pts.join(" ");
  }

  function drawGrid() {
    const g = $("grid");
    g.replaceChildren();
    const step = state.view.scale >= 30 ? 1 : 5;
    for (let x = Math.ceil(wx(0) / step) * step; x <= wx(W); x += step)
      el("line", { x1: sx(x), x2: sx(x), y1: 0, y2: H, class: x === 0 ? "axis" : "gridline" }, g);
    for (let y = Math.ceil(wy(H) / step) * step; y <= wy(0); y += step)
      el("line", { y1: sy(y), y2: sy(y), x1: 0, x2: W, class: y === 0 ? "axis" : "gridline" }, g);
  }

  function boxCorners() {  // [lo, hi] whichever corner was dragged where
    const [a, b] = state.box;
    return [[Math.min(a[0], b[0]), Math.min(a[1], b[1])], [Math.max(a[0], b[0]), Math.max(a[1], b[1])]];
  }

  function drawBox() {
    const g = $("workspace");
    g.replaceChildren();
    if (!state.box) return;
    const [lo, hi] = boxCorners();
    el("rect", { id: "box", class: "box", x: sx(lo[0]), y: sy(hi[1]),
                 width: (hi[0] - lo[0]) * state.view.scale,
                 height: (hi[1] - lo[1]) * state.view.scale }, g);
  }

  function drawPoints() {
    const g = $("points");
    g.replaceChildren();
    g.setAttribute("class", state.error ? "invalid" : "");
    drawBox();
    (state.box || []).forEach((p, k) => {
      const h = el("g", { id: `box-corner-${k + 1}`, class: "handle", "data-kind": "box",
                          "data-index": k, transform: `translate(${sx(p[0])},${sy(p[1])})` }, g);
      el("circle", { r: 15, class: "hit" }, h);
      el("rect", { x: -5, y: -5, width: 10, height: 10, class: "box-corner" }, h);
    });
    state.obstacles.forEach((p, k) => {
      const h = el("g", { id: `obstacle-${k + 1}`, class: "handle", "data-kind": "obstacles",
                          "data-index": k, transform: `translate(${sx(p[0])},${sy(p[1])})` }, g);
      el("circle", { r: 15, class: "hit" }, h);
      el("rect", { x: -7, y: -7, width: 14, height: 14, class: "obstacle" }, h);
      el("text", { x: 9, y: -9, class: "label" }, h).textContent = `o${k + 1}`;
    });
    ["start", "goal"].forEach((kind) => state[kind].forEach((p, i) => {
      const h = el("g", { id: `${kind}-${i + 1}`, class: "handle", "data-kind": kind,
                          "data-index": i, transform: `translate(${sx(p[0])},${sy(p[1])})` }, g);
      const c = COLORS[i % COLORS.length];
      el("circle", { r: 15, class: "hit" }, h);  // a generous grip around the marker
      if (kind === "start") el("circle", { r: 8, fill: c, class: "start", stroke: "#000" }, h);
      else el("polygon", { points: star(11), fill: c, class: "goal", stroke: "#000" }, h);
      el("text", { x: 10, y: 14, class: "label" }, h).textContent =
        kind === "start" ? `x${i + 1}` : `x'${i + 1}`;
    }));
  }

  function screenPoints(waypoints, k) {  // point k of every waypoint, as SVG "x,y" pairs
    return waypoints.map((w) => `${sx(w[k][0]).toFixed(2)},${sy(w[k][1]).toFixed(2)}`).join(" ");
  }

  function drawPlan() {
    const gp = $("paths"), gr = $("raw-paths");
    gp.replaceChildren(); gr.replaceChildren();
    const plan = state.plan;
    if (!plan) { drawMovers(); return; }
    const m = state.obstacles.length, n = plan.waypoints[0].length - m;
    if (plan.raw) {  // a refined motion: the planner's own motion, dashed, underneath
      for (let i = 0; i < n; i++) {
        el("polyline", { id: `raw-${i + 1}`, class: "raw-path", points: screenPoints(plan.raw.waypoints, m + i),
                         stroke: COLORS[i % COLORS.length] }, gr);
      }
    }
    for (let i = 0; i < n; i++) {
      el("polyline", { id: `path-${i + 1}`, class: "robot-path", points: screenPoints(plan.waypoints, m + i),
                       stroke: COLORS[i % COLORS.length],
                       "data-times": JSON.stringify(plan.times),
                       "data-world": JSON.stringify(plan.waypoints.map((w) => w[m + i])) }, gp);
    }
    drawMovers();
  }

  function drawMovers() {
    const g = $("movers"), gd = $("discs");
    g.replaceChildren(); gd.replaceChildren();
    const plan = state.plan;
    if (!plan) return;
    const m = state.obstacles.length, pos = positionAt(plan, state.t);
    if ($("discs-toggle").checked) {
      // discs of radius clearance/2 around every point: they never overlap along the motion
      const r = plan.clearance / 2 * state.view.scale;
      pos.forEach((p) => el("circle", { cx: sx(p[0]), cy: sy(p[1]), r: r, class: "disc" }, gd));
    }
    if (plan.refined && (plan.radius > 0 || plan.obstacle_radius > 0)) {
      // the robots and obstacles as discs of their radii: they never overlap when the radii
      // are kept (the "radii" row says whether they are, decided exactly)
      const s = state.view.scale;
      pos.forEach((p, i) => el("circle", {
        cx: sx(p[0]), cy: sy(p[1]), r: (i < m ? plan.obstacle_radius : plan.radius) * s,
        class: i < m ? "body obstacle-body" : "body robot-body",
        fill: i < m ? "#333" : COLORS[(i - m) % COLORS.length] }, gd));
    }
    pos.slice(m).forEach((p, i) => el("circle", {
      id: `mover-${i + 1}`, cx: sx(p[0]), cy: sy(p[1]), r: 5, class: "mover",
      fill: COLORS[i % COLORS.length] }, g));
    $("tlabel").textContent = `t = ${state.t.toFixed(2)}`;
  }

  function tex(s) {  // the paper's notation T^{2,3}_{3,4} as HTML
    const esc = s.replace(/&/g, "&amp;").replace(/</g, "&lt;");
    return esc.replace(/\^\{([^}]*)\}/g, "<sup>$1</sup>").replace(/_\{([^}]*)\}/g, "<sub>$1</sub>");
  }

  function showInfo() {
    const p = state.plan;
    $("planner").textContent = p ? p.planner : "-";
    $("domain").innerHTML = p ? `W<sub>${p.domain}</sub>` : "-";
    $("domain").dataset.label = p ? String(p.domain) : "";
    $("stratum").innerHTML = p ? tex(p.stratum) : "-";
    $("clearance").textContent = p ? p.clearance.toPrecision(4) : "-";
    const rd = (v) => (v === null ? "-" : v.toPrecision(3));
    $("radii").textContent = !p || !p.refined ? "-" :
      `${p.respects_radius ? "kept" : "not kept"} (robots ${rd(p.robot_distance)}, ` +
      `obstacles ${rd(p.obstacle_distance)} apart)`;
    $("radii").dataset.kept = p && p.refined ? String(p.respects_radius) : "";
    $("radii-why").textContent = p && p.refined && p.radius_reason ? p.radius_reason : "";
    $("radii-why").hidden = !(p && p.refined && p.radius_reason);
    const e = $("error");
    e.hidden = !state.error;
    e.textContent = state.error || "";
  }

  function redraw() { drawGrid(); drawMapCanvas(); drawPoints(); drawPlan(); showInfo(); }

  // ---------------------------------------------------------------- planning
  function query() {
    const q = { obstacles: state.obstacles, start: state.start, goal: state.goal };
    if (state.box) q.bounds = boxCorners();
    return q;
  }

  async function post(url, body) {
    const r = await fetch(url, { method: "POST", headers: { "Content-Type": "application/json" },
                                 body: JSON.stringify(body) });
    let data;
    try { data = await r.json(); } catch (e) { data = { error: `HTTP ${r.status}` }; }
    return { ok: r.ok, status: r.status, data };
  }

  function schedule(delay) {
    clearTimeout(net.timer);
    net.timer = setTimeout(() => { net.timer = null; replan(); }, delay);
  }

  function planUrl() {  // the refined motion: robots and obstacles of the same radius
    if (!$("refine-toggle").checked) return "/api/plan";
    const r = encodeURIComponent($("radius").value);
    return `/api/plan?refine=true&radius=${r}&obstacle_radius=${r}`;
  }

  async function replan() {
    if (net.busy) { net.dirty = true; return; }
    net.busy = true; net.dirty = false;
    document.body.dataset.state = "planning";
    const seq = ++net.seq;
    try {
      const r = await post(planUrl(), query());
      if (seq !== net.seq) return;
      if (r.ok) {
        state.plan = r.data; state.error = null;
        if (state.fitAfterPlan) {
          state.fitAfterPlan = false;
          fit(r.data.waypoints.flat());
        }
      } else {
        state.plan = null;
        state.error = r.data.error || `HTTP ${r.status}`;
      }
    } catch (e) {
      state.plan = null; state.error = `the server did not answer: ${e}`;
    } finally {
      net.busy = false;
      redraw();
      if (net.dirty) schedule(0);
      else {
        document.body.dataset.state = state.error ? "error" : "ready";
        document.body.dataset.seq = String(net.seq);
        updateMap();
      }
    }
  }

  // ---------------------------------------------------------------- domain map
  function mapRequest() {
    const mode = $("map-mode").value;
    const scale = state.view.scale;
    let h = Math.pow(2, Math.floor(Math.log2(4 / scale)));  // about 4 px, a power of two
    while (W / (h * scale) > 400 || H / (h * scale) > 400) h *= 2;
    const x0 = Math.ceil(wx(0) / h) * h, y0 = Math.ceil(wy(H) / h) * h;
    const nx = Math.min(400, Math.floor((wx(W) - x0) / h) + 1);
    const ny = Math.min(400, Math.floor((wy(0) - y0) / h) + 1);
    return { query: query(), which: mode, robot: 1, origin: [x0, y0], step: h, size: [nx, ny] };
  }

  async function updateMap() {
    const mode = $("map-mode").value;
    if (mode === "off" || state.start.length === 0) {
      state.map = null; state.mapKey = null; drawMapCanvas(); drawLegend(); return;
    }
    const req = mapRequest();
    const fixed = { ...req.query };
    fixed[mode] = req.query[mode].slice(1);  // the mapped point itself does not change the map
    const key = JSON.stringify([fixed, req.origin, req.step, req.size, mode]);
    if (key === state.mapKey) return;
    if (net.mapBusy) { net.mapDirty = true; return; }
    net.mapBusy = true;
    document.body.dataset.map = "computing";
    try {
      const r = await post("/api/domain-map", req);
      if (r.ok) { state.map = r.data; state.mapKey = key; }
      else { state.map = null; state.mapKey = null; }
    } finally {
      net.mapBusy = false;
      drawMapCanvas(); drawLegend();
      document.body.dataset.map = state.map ? "ready" : "none";
      if (net.mapDirty) { net.mapDirty = false; updateMap(); }
    }
  }

  function mapColor(label) {
    if (label === -1) return "#bbbbbb";
    if (label === -2) return "#000000";
    if (label === -3) return "#ffffff";
    if (label === -4) return "#f4f4f4";
    return MAP_COLORS[label % MAP_COLORS.length];
  }

  function drawBoundaries() {  // continuous lines, whatever the tilt of the line o1o2
    const g = $("boundaries");
    g.replaceChildren();
    const mp = state.map;
    if (!mp || $("map-mode").value === "off" || !mp.boundaries) return;
    const cx = wx(W / 2), cy = wy(H / 2), reach = Math.hypot(W, H) / state.view.scale;
    mp.boundaries.forEach((b, k) => {
      const [px, py] = b.point, [ux, uy] = b.direction;
      const t0 = (cx - px) * ux + (cy - py) * uy;  // the foot of the view's centre
      const a = [px + (t0 - reach) * ux, py + (t0 - reach) * uy];
      const c = [px + (t0 + reach) * ux, py + (t0 + reach) * uy];
      el("line", { id: `boundary-${k + 1}`, class: "boundary", x1: sx(a[0]).toFixed(2),
                   y1: sy(a[1]).toFixed(2), x2: sx(c[0]).toFixed(2), y2: sy(c[1]).toFixed(2) }, g);
    });
  }

  function drawMapCanvas() {
    const ctx = $("map").getContext("2d");
    ctx.clearRect(0, 0, W, H);
    drawBoundaries();
    const mp = state.map;
    if (!mp || $("map-mode").value === "off") return;
    const h = mp.step, px = h * state.view.scale;
    mp.domain.forEach((row, j) => row.forEach((lab, i) => {
      ctx.fillStyle = mapColor(lab);
      const cx = sx(mp.origin[0] + i * h), cy = sy(mp.origin[1] + j * h);
      ctx.fillRect(cx - px / 2, cy - px / 2, px + 0.5, px + 0.5);
    }));
  }

  function drawLegend() {
    const lg = $("legend");
    lg.replaceChildren();
    const mp = state.map;
    if (!mp || $("map-mode").value === "off") return;
    const head = document.createElement("div");
    head.textContent = `domain of robot 1's ${mp.which} at each pixel (${mp.planner}):`;
    lg.appendChild(head);
    const item = (color, html) => {
      const d = document.createElement("div");
      d.className = "item";
      d.innerHTML = `<span class="swatch" style="background:${color}"></span><span>${html}</span>`;
      lg.appendChild(d);
    };
    if (mp.boundaries && mp.boundaries.length) {
      const d = document.createElement("div");
      d.className = "item";
      d.innerHTML = '<span class="swatch boundary-swatch"></span>' +
        `<span>domain boundaries: the label changes on these ${mp.boundaries.length} lines</span>`;
      lg.appendChild(d);
    }
    mp.legend.forEach((e) => item(mapColor(e.domain),
      `W<sub>${e.domain}</sub>: ${e.strata.map(tex).join(", ")} (${e.count} px)`));
    if (mp.invalid) item(mapColor(-1), `coincides with another point (${mp.invalid} px)`);
    if (mp.uncertified) item(mapColor(-2), `not certified (${mp.uncertified} px)`);
    if (mp.unfinished) item(mapColor(-3), `not computed: time budget (${mp.unfinished} px)`);
    if (mp.outside) item(mapColor(-4), `outside the workspace box (${mp.outside} px)`);
  }

  // ---------------------------------------------------------------- dragging
  let drag = null;
  const svg = $("plane");
  // the pointer in the plane's own 800 x 600 units: on a narrow screen the SVG is drawn
  // smaller than that, so client pixels are scaled back
  const local = (ev) => {
    const r = svg.getBoundingClientRect();
    return [(ev.clientX - r.left) * W / r.width, (ev.clientY - r.top) * H / r.height];
  };
  svg.addEventListener("pointerdown", (ev) => {
    const h = ev.target.closest(".handle");
    if (!h) return;
    ev.preventDefault();
    const [px, py] = local(ev);
    const p = state[h.dataset.kind][Number(h.dataset.index)];
    // keep the offset between the pointer and the point: a drag by (dx, dy) pixels moves
    // the point by (dx, dy) pixels, wherever on the marker it was grabbed
    drag = { kind: h.dataset.kind, index: Number(h.dataset.index), id: ev.pointerId,
             dx: p[0] - wx(px), dy: p[1] - wy(py) };
    svg.setPointerCapture(ev.pointerId);
  });
  svg.addEventListener("pointermove", (ev) => {
    if (!drag || ev.pointerId !== drag.id) return;
    const [px, py] = local(ev);
    const x = snap(wx(px) + drag.dx), y = snap(wy(py) + drag.dy);
    const p = state[drag.kind][drag.index];
    if (p[0] === x && p[1] === y) return;
    state[drag.kind][drag.index] = [x, y];
    drawPoints();
    schedule(30);  // debounced: replan while dragging
  });
  const endDrag = (ev) => {
    if (!drag || ev.pointerId !== drag.id) return;
    drag = null;
    schedule(0);
  };
  svg.addEventListener("pointerup", endDrag);
  svg.addEventListener("pointercancel", endDrag);

  // ---------------------------------------------------------------- controls
  function freeSpot() {
    const pts = [...state.obstacles, ...state.start, ...state.goal];
    const cx = wx(W / 2), cy = wy(H / 2);
    for (let r = 0; r < 40; r++)
      for (let k = 0; k < 8; k++) {
        const x = snap(cx + (r * 0.75 + 0.5) * Math.cos(k * Math.PI / 4 + r));
        const y = snap(cy + (r * 0.75 + 0.5) * Math.sin(k * Math.PI / 4 + r));
        if (!pts.some((p) => p[0] === x && p[1] === y)) return [x, y];
      }
    return [cx + Math.random(), cy + Math.random()];
  }

  function defaultBox() {  // a box around every point, one unit of margin, on the 1/4 grid
    const pts = [...state.obstacles, ...state.start, ...state.goal];
    const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
    const r = (v) => Math.round(v / SNAP) * SNAP;
    return [[r(Math.min(...xs) - 1), r(Math.min(...ys) - 1)],
            [r(Math.max(...xs) + 1), r(Math.max(...ys) + 1)]];
  }

  function setQuery(q) {
    state.box = q.bounds ? q.bounds.map((p) => p.slice()) : null;
    state.obstacles = q.obstacles.map((p) => p.slice());
    state.start = q.start.map((p) => p.slice());
    state.goal = q.goal.map((p) => p.slice());
    if (!state.box && $("box-toggle").checked) state.box = defaultBox();
    $("box-toggle").checked = !!state.box;
    fit([...state.obstacles, ...state.start, ...state.goal, ...(state.box || [])]);
    state.fitAfterPlan = true;
    state.mapKey = null;
    redraw();
    schedule(0);
  }

  $("add-robot").onclick = () => {
    if (state.start.length >= MAX_ROBOTS) return;
    state.start.push(freeSpot()); state.goal.push(freeSpot()); redraw(); schedule(0);
  };
  $("remove-robot").onclick = () => {
    if (state.start.length <= 1) return;
    state.start.pop(); state.goal.pop(); redraw(); schedule(0);
  };
  $("add-obstacle").onclick = () => {
    if (state.obstacles.length >= MAX_OBS) return;
    state.obstacles.push(freeSpot()); redraw(); schedule(0);
  };
  $("remove-obstacle").onclick = () => {
    if (state.obstacles.length <= MIN_OBS) return;
    state.obstacles.pop(); redraw(); schedule(0);
  };
  $("examples").onchange = (ev) => {
    const ex = window.pmplanExamples[Number(ev.target.value)];
    if (ex) setQuery(ex.query);
  };
  $("map-mode").onchange = () => { state.mapKey = null; updateMap(); };
  $("discs-toggle").onchange = () => drawMovers();
  $("refine-toggle").onchange = () => schedule(0);
  $("box-toggle").onchange = () => {
    state.box = $("box-toggle").checked ? defaultBox() : null;
    if (state.box) fit([...state.obstacles, ...state.start, ...state.goal, ...state.box]);
    state.mapKey = null;
    redraw(); schedule(0);
  };
  $("radius").onchange = () => { if ($("refine-toggle").checked) schedule(0); };
  $("time").oninput = (ev) => { state.t = Number(ev.target.value) / 1000; drawMovers(); };

  let last = null;
  function frame(now) {
    if (!state.playing) return;
    if (last !== null) state.t += (now - last) / 4000;  // 4 s per motion
    last = now;
    if (state.t > 1) state.t = 0;
    $("time").value = String(Math.round(state.t * 1000));
    drawMovers();
    requestAnimationFrame(frame);
  }
  $("play").onclick = () => {
    state.playing = !state.playing;
    $("play").textContent = state.playing ? "pause" : "play";
    last = null;
    if (state.playing) requestAnimationFrame(frame);
  };

  async function init() {
    try {
      const r = await fetch("/api/examples");
      window.pmplanExamples = await r.json();
      const sel = $("examples");
      const groups = {};
      window.pmplanExamples.forEach((ex, k) => {
        if (!groups[ex.group]) {
          groups[ex.group] = document.createElement("optgroup");
          groups[ex.group].label = ex.group;
          sel.appendChild(groups[ex.group]);
        }
        const o = document.createElement("option");
        o.value = String(k); o.textContent = ex.name;
        groups[ex.group].appendChild(o);
      });
    } catch (e) { window.pmplanExamples = []; }
    setQuery(query());
  }
  // for tests and the console: is a replan scheduled or running?
  const pending = () => net.busy || net.dirty || net.timer !== null;
  window.pmplanExplore = { state, setQuery, sx, sy, wx, wy, pending };
  init();
})();
