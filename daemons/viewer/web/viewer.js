// coopnav viewer page: draws the scene the viewer streams (/events, Server-Sent Events; or
// /scene.json once with ?once=1) in world metres, equal axes, with pan and zoom; the people's
// predicates and CA / CM plots and the daemons' statuses beside it; a timeline when the viewer
// replays a log (?t=SECONDS seeks there and pauses). What each frame drew is exposed as JSON in
// window.coopnavDrawn and <pre id="drawn">, and posted back to /ack (frame latency, tests).
"use strict";

(function () {
  const params = new URLSearchParams(location.search);
  const ONCE = params.get("once") === "1";
  const ACK = params.get("ack") !== "0";
  const SEEK = params.has("t") ? parseFloat(params.get("t")) : null;
  const BAND_T_MAX = 10; // [s] band colour scale: 0 s blue ... BAND_T_MAX red

  const canvas = document.getElementById("scene");
  const ctx = canvas.getContext("2d");
  const el = (id) => document.getElementById(id);
  let scene = null;
  let map = null; // {image (canvas), x0, y0, w_m, h_m}
  let view = { s: 40, ox: 0, oy: 0, follow: true };
  let frame = 0;
  let seekDone = SEEK === null;

  // ---- helpers
  const fin = (v) => typeof v === "number" && isFinite(v);
  const fmt = (v, d = 2) => (v === "inf" ? "∞" : fin(v) ? v.toFixed(d) : "–");
  const timeColour = (t) => {
    const f = Math.max(0, Math.min(1, t / BAND_T_MAX));
    return `hsl(${240 - 240 * f}, 80%, ${45 - 5 * f}%)`;
  };
  const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
  const X = (x) => view.ox + view.s * x;
  const Y = (y) => view.oy - view.s * y;

  // ---- map: run-length encoded grid, rows from the bottom
  function buildMap(m) {
    if (!m || !m.width) return null;
    const c = document.createElement("canvas");
    c.width = m.width;
    c.height = m.height;
    const g = c.getContext("2d");
    const img = g.createImageData(m.width, m.height);
    let k = 0;
    for (let r = 0; r < m.rle.length; r += 2) {
      const state = m.rle[r];
      const rgb = state === 1 ? [60, 64, 72] : state === -1 ? [205, 208, 214] : [255, 255, 255];
      for (let n = 0; n < m.rle[r + 1]; n++, k++) {
        const i = k % m.width;
        const j = (k - i) / m.width;
        const o = 4 * ((m.height - 1 - j) * m.width + i);
        img.data[o] = rgb[0];
        img.data[o + 1] = rgb[1];
        img.data[o + 2] = rgb[2];
        img.data[o + 3] = 255;
      }
    }
    g.putImageData(img, 0, 0);
    return { image: c, x0: m.origin[0], y0: m.origin[1], w_m: m.width * m.resolution,
      h_m: m.height * m.resolution, source: m.source };
  }

  // ---- view: fit to what matters (agents, bands, goals), pan and zoom by hand
  function resize() {
    const r = canvas.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    canvas.width = Math.max(1, Math.round(r.width * dpr));
    canvas.height = Math.max(1, Math.round(r.height * dpr));
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    draw();
  }
  // The box that matters: the agents and their bands (goals and the map only when there is
  // nothing else), at least MIN_SPAN metres across.
  const MIN_SPAN = 8;
  function sceneBox() {
    const xs = [], ys = [];
    const add = (x, y) => { if (fin(x) && fin(y)) { xs.push(x); ys.push(y); } };
    if (scene && scene.robot) add(scene.robot.x, scene.robot.y);
    if (scene) for (const h of scene.humans) add(h.x, h.y);
    if (scene && scene.bands) {
      for (const p of scene.bands.robot) add(p[1], p[2]);
      for (const b of scene.bands.humans) for (const p of b.poses) add(p[1], p[2]);
    }
    if (!xs.length && scene) for (const g of scene.goals) add(g.x, g.y);
    if (!xs.length && map) return [map.x0, map.y0, map.x0 + map.w_m, map.y0 + map.h_m];
    if (!xs.length) return [-5, -5, 5, 5];
    let [x0, y0, x1, y1] = [Math.min(...xs) - 1.5, Math.min(...ys) - 1.5, Math.max(...xs) + 1.5,
      Math.max(...ys) + 1.5];
    const grow = (a, b) => { const c = (a + b) / 2, h = Math.max(b - a, MIN_SPAN) / 2; return [c - h, c + h]; };
    [x0, x1] = grow(x0, x1);
    [y0, y1] = grow(y0, y1);
    return [x0, y0, x1, y1];
  }
  function fit() {
    const r = canvas.getBoundingClientRect();
    const [x0, y0, x1, y1] = sceneBox();
    const s = Math.min(r.width / Math.max(x1 - x0, 1), r.height / Math.max(y1 - y0, 1));
    view.s = Math.max(2, Math.min(200, s));
    view.ox = r.width / 2 - view.s * (x0 + x1) / 2;
    view.oy = r.height / 2 + view.s * (y0 + y1) / 2;
  }
  const pointers = new Map();
  let pinch = null;
  canvas.addEventListener("pointerdown", (e) => {
    canvas.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.offsetX, y: e.offsetY });
  });
  canvas.addEventListener("pointermove", (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    view.follow = false;
    if (pointers.size === 1) {
      view.ox += e.offsetX - p.x;
      view.oy += e.offsetY - p.y;
    } else if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const d0 = Math.hypot(a.x - b.x, a.y - b.y);
      p.x = e.offsetX; p.y = e.offsetY;
      const d1 = Math.hypot(a.x - b.x, a.y - b.y);
      if (pinch !== null && d0 > 0) zoomAt((a.x + b.x) / 2, (a.y + b.y) / 2, d1 / d0);
      pinch = d1;
    }
    p.x = e.offsetX;
    p.y = e.offsetY;
    draw();
  });
  const up = (e) => { pointers.delete(e.pointerId); pinch = null; };
  canvas.addEventListener("pointerup", up);
  canvas.addEventListener("pointercancel", up);
  function zoomAt(cx, cy, f) {
    const s = Math.max(2, Math.min(400, view.s * f));
    const k = s / view.s;
    view.ox = cx - k * (cx - view.ox);
    view.oy = cy - k * (cy - view.oy);
    view.s = s;
  }
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    view.follow = false;
    zoomAt(e.offsetX, e.offsetY, Math.exp(-e.deltaY * 0.0015));
    draw();
  }, { passive: false });
  el("fit").addEventListener("click", () => { view.follow = true; draw(); });
  window.addEventListener("resize", resize);

  // ---- drawing primitives (world coordinates)
  function line(pts, colour, width, dash) {
    if (pts.length < 2) return;
    ctx.beginPath();
    ctx.setLineDash(dash || []);
    ctx.strokeStyle = colour;
    ctx.lineWidth = width;
    ctx.moveTo(X(pts[0][0]), Y(pts[0][1]));
    for (const p of pts.slice(1)) ctx.lineTo(X(p[0]), Y(p[1]));
    ctx.stroke();
    ctx.setLineDash([]);
  }
  function label(x, y, text, colour, dx = 6, dy = -6) {
    ctx.font = "11px system-ui, sans-serif";
    const w = ctx.measureText(text).width;
    ctx.fillStyle = "rgba(255,255,255,0.8)";
    ctx.fillRect(X(x) + dx - 2, Y(y) + dy - 10, w + 4, 13);
    ctx.fillStyle = colour;
    ctx.fillText(text, X(x) + dx, Y(y) + dy);
  }
  function band(poses, width, dotted) {
    for (let i = 1; i < poses.length; i++) {
      const a = poses[i - 1], b = poses[i];
      ctx.beginPath();
      ctx.strokeStyle = timeColour(b[0]);
      ctx.lineWidth = width;
      ctx.setLineDash(dotted ? [4, 3] : []);
      ctx.moveTo(X(a[1]), Y(a[2]));
      ctx.lineTo(X(b[1]), Y(b[2]));
      ctx.stroke();
    }
    ctx.setLineDash([]);
    for (const p of poses) {
      ctx.beginPath();
      ctx.fillStyle = timeColour(p[0]);
      ctx.arc(X(p[1]), Y(p[2]), dotted ? 1.8 : 2.2, 0, 2 * Math.PI);
      ctx.fill();
    }
  }
  function agent(a, fill, stroke, text) {
    ctx.beginPath();
    ctx.fillStyle = fill;
    ctx.strokeStyle = stroke;
    ctx.lineWidth = 2;
    ctx.arc(X(a.x), Y(a.y), Math.max(2, view.s * a.radius), 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
    line([[a.x, a.y], [a.x + a.radius * 1.4 * Math.cos(a.theta), a.y + a.radius * 1.4 * Math.sin(a.theta)]],
      stroke, 2.5);
    label(a.x + a.radius * 0.7, a.y + a.radius * 0.7, text, stroke, 2, -2);
  }
  // Dir as the robot will see it: an arrow in the robot's heading beside the human's crossing
  // point, on the side the robot passes (the human's left or right at CP_h).
  function dirArrow(cp, h, rb, dir) {
    const hx = Math.cos(h.theta), hy = Math.sin(h.theta);
    const n = dir === "left" ? [-hy, hx] : [hy, -hx];
    const off = h.radius + 0.45, half = 0.6;
    const c = [cp[0] + n[0] * off, cp[1] + n[1] * off];
    const u = [Math.cos(rb.theta), Math.sin(rb.theta)];
    const a = [c[0] - u[0] * half, c[1] - u[1] * half], b = [c[0] + u[0] * half, c[1] + u[1] * half];
    line([a, b], "#1b4aa0", 3);
    // Head: two strokes back from the tip, at +-150 degrees of the arrow's direction (screen y is down).
    const ang = Math.atan2(-(b[1] - a[1]), b[0] - a[0]), len = 9;
    ctx.beginPath();
    ctx.strokeStyle = "#1b4aa0";
    ctx.lineWidth = 3;
    for (const da of [2.6, -2.6]) {
      ctx.moveTo(X(b[0]), Y(b[1]));
      ctx.lineTo(X(b[0]) + len * Math.cos(ang + da), Y(b[1]) + len * Math.sin(ang + da));
    }
    ctx.stroke();
    label(c[0], c[1], `passes on H${h.id}'s ${dir}`, "#1b4aa0", 6, 16);
  }
  function marker(p, colour, text) {
    ctx.beginPath();
    ctx.strokeStyle = colour;
    ctx.lineWidth = 2;
    const r = 6;
    ctx.moveTo(X(p[0]) - r, Y(p[1]) - r); ctx.lineTo(X(p[0]) + r, Y(p[1]) + r);
    ctx.moveTo(X(p[0]) - r, Y(p[1]) + r); ctx.lineTo(X(p[0]) + r, Y(p[1]) - r);
    ctx.stroke();
    label(p[0], p[1], text, colour, 7, 14);
  }
  // A speech bubble above and to the left of (x, y), `above` pixels higher for the n-th one.
  function bubble(x, y, lines, colour, above) {
    ctx.font = "12px system-ui, sans-serif";
    const w = Math.max(...lines.map((l) => ctx.measureText(l).width)) + 12;
    const h = 15 * lines.length + 8;
    const bx = Math.max(4, X(x) - w + 30), by = Math.max(4, Y(y) - 70 - h - above);
    ctx.fillStyle = "rgba(255,255,255,0.95)";
    ctx.strokeStyle = colour;
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(X(x), Y(y) - 10);
    ctx.lineTo(bx + w - 40, by + h);
    ctx.lineTo(bx + w - 22, by + h);
    ctx.closePath();
    ctx.fill();
    ctx.stroke();
    ctx.fillRect(bx, by, w, h);
    ctx.strokeRect(bx, by, w, h);
    ctx.fillStyle = "#1d2330";
    lines.forEach((l, i) => ctx.fillText(l, bx + 6, by + 16 + 15 * i));
    return h + 6;
  }
  function wrap(text, n) {
    const out = [];
    let cur = "";
    for (const w of text.split(" ")) {
      if ((cur + " " + w).trim().length > n && cur) { out.push(cur); cur = w; } else cur = (cur + " " + w).trim();
    }
    if (cur) out.push(cur);
    return out;
  }

  // ---- one frame of the scene; returns what was drawn
  function draw() {
    const r = canvas.getBoundingClientRect();
    ctx.clearRect(0, 0, r.width, r.height);
    const d = { frame, utime: scene ? scene.utime : null, t: scene ? scene.t : null, map: false,
      robot: null, humans: [], robot_band: 0, human_bands: [], reference_paths: [], crossings: [],
      segments: { d_h: [], d_oh: [], d_or: [], d_hr: [] }, predicates: {}, mode: null, bubbles: [],
      plots: [], statuses: [], sim: null, replay: null };
    const keys = [];
    if (!scene) return { d, keys };
    if (view.follow) fit();
    if (map) {
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(map.image, X(map.x0), Y(map.y0 + map.h_m), map.w_m * view.s, map.h_m * view.s);
      d.map = true;
      keys.push("map");
    }
    for (const p of scene.reference_paths) {
      line(p.points, "#8a8fa0", 1.5, [6, 4]);
      d.reference_paths.push(p.id);
      keys.push("ref_path:" + p.id);
    }
    for (const g of scene.goals) {
      marker([g.x, g.y], g.kind === "robot" ? "#1b4aa0" : "#b35a00", "goal " + g.id);
    }
    if (scene.bands) {
      for (const b of scene.bands.humans) {
        if (b.poses.length < 2) continue;
        band(b.poses, 2, true);
        d.human_bands.push(b.id);
        keys.push("human_band:" + b.id);
      }
      if (scene.bands.robot.length >= 2) {
        band(scene.bands.robot, 3.5, false);
        d.robot_band = scene.bands.robot.length;
        keys.push("robot_band");
      }
    }
    // Crossing: CP_h, CP_r, t_CROSS, Dir and the distances as segments.
    const segStyle = { d_h: ["#7b2cbf", "d_h"], d_oh: ["#1c8a3a", "d_OH"], d_or: ["#0a7f9e", "d_OR"],
      d_hr: ["#999", "d_HR"] };
    for (const s of scene.situations) {
      d.predicates[s.human_id] = s.predicates;
      keys.push("predicates:" + s.human_id);
      for (const k of Object.keys(segStyle)) {
        const seg = s.segments[k];
        if (!seg) continue;
        line(seg, segStyle[k][0], 2, k === "d_hr" ? [2, 3] : []);
        // Labelled three quarters along, away from the CP markers' own labels.
        const m = [seg[0][0] + 0.75 * (seg[1][0] - seg[0][0]), seg[0][1] + 0.75 * (seg[1][1] - seg[0][1])];
        label(m[0], m[1], `${segStyle[k][1]} ${fmt(s[k + "_m"])}`, segStyle[k][0]);
        d.segments[k].push(s.human_id);
        keys.push("seg_" + k + ":" + s.human_id);
      }
      if (s.cp_h && s.cp_r) {
        marker(s.cp_h, "#c0392b", `CP_h ${s.human_id}`);
        marker(s.cp_r, "#1b4aa0", "CP_r");
        label(s.cp_r[0], s.cp_r[1], `t_CROSS ${fmt(s.t_cross_s, 1)} s · Dir ${s.dir}`, "#333", 7, 28);
        const c = { human_id: s.human_id, t_cross_s: s.t_cross_s, dir: s.dir, dir_arrow: false };
        const hh = scene.humans.find((h) => h.id === s.human_id);
        if ((s.dir === "left" || s.dir === "right") && hh && scene.robot) {
          dirArrow(s.cp_h, hh, scene.robot, s.dir);
          c.dir_arrow = true;
          keys.push("dir_arrow:" + s.human_id);
        }
        d.crossings.push(c);
        keys.push("crossing:" + s.human_id);
      }
    }
    for (const h of scene.humans) {
      agent(h, "rgba(255,160,60,0.35)", "#b35a00", "H" + h.id);
      d.humans.push(h.id);
      keys.push("human:" + h.id);
    }
    if (scene.robot) {
      const rb = scene.robot;
      agent(rb, "rgba(70,120,230,0.35)", "#1b4aa0", "R");
      label(rb.x, rb.y - rb.radius, rb.mode + (rb.guard !== "none" ? ` (guard ${rb.guard})` : ""), "#1b4aa0", -20, 18);
      d.robot = { id: rb.id, x: rb.x, y: rb.y, mode: rb.mode };
      d.mode = rb.mode;
      keys.push("robot", "mode:" + rb.mode);
      // What the robot is saying now (or just said), one bubble per utterance: the newest nearest
      // the robot, older ones stacked above; drawn from the top down so that no tail crosses a
      // box below it.
      const shown = scene.utterances.filter((u) => u.active).reverse();
      const items = [];
      let dy = 0;
      for (const u of shown) {
        const said = u.delivery === "SAID" || u.delivery === "said";
        const head = `R${u.round} → H${u.human_id}${said ? "" : " (not said: " + u.delivery + ")"}`;
        const lines = [head, ...wrap(u.text, 42)];
        items.push({ lines, colour: said ? "#1b4aa0" : "#999", above: dy });
        dy += 15 * lines.length + 14;
        d.bubbles.push({ human_id: u.human_id, round: u.round, text: u.text, delivery: u.delivery });
        keys.push(`bubble:${u.human_id}:r${u.round}`);
      }
      for (const b of items.reverse()) bubble(rb.x, rb.y, b.lines, b.colour, b.above);
    }
    // Scale bar.
    const len = [0.5, 1, 2, 5, 10, 20].find((m) => m * view.s > 60) || 50;
    ctx.fillStyle = "#333";
    ctx.fillRect(r.width - 20 - len * view.s, r.height - 20, len * view.s, 3);
    ctx.font = "11px system-ui, sans-serif";
    ctx.fillText(`${len} m`, r.width - 20 - len * view.s, r.height - 26);
    return { d, keys };
  }

  // ---- side panel
  function plot(c, a, tau) {
    const dpr = window.devicePixelRatio || 1;
    const w = c.clientWidth || 300, h = c.clientHeight || 120;
    c.width = w * dpr; c.height = h * dpr;
    const g = c.getContext("2d");
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.clearRect(0, 0, w, h);
    const pc = Array.isArray(a.p_contributing_history) ? a.p_contributing_history : [];
    const pts = a.ca.concat(a.cm_history, pc);
    const ts = pts.map((p) => p[0]).concat(a.rounds.map((r) => r[0])).filter(fin);
    if (scene && fin(scene.t)) ts.push(scene.t);
    const vs = pts.map((p) => p[1]).filter(fin).concat([0, fin(tau) ? tau : 0.4]);
    if (!ts.length) return;
    const t0 = Math.min(...ts), t1 = Math.max(...ts, t0 + 1);
    const v0 = Math.min(...vs, -0.1), v1 = Math.max(...vs, 0.5) + 0.05;
    const L = 30, B = 14;
    const px = (t) => L + (w - L - 4) * (t - t0) / (t1 - t0);
    const py = (v) => (h - B) - (h - B - 4) * (v - v0) / (v1 - v0);
    g.font = "10px system-ui, sans-serif";
    g.fillStyle = "#667";
    g.strokeStyle = "#ccd";
    g.beginPath(); g.moveTo(L, py(0)); g.lineTo(w - 4, py(0)); g.stroke();
    g.fillText(v1.toFixed(1), 2, py(v1) + 9);
    g.fillText(v0.toFixed(1), 2, py(v0));
    g.fillText(`${t0.toFixed(0)} s`, L, h - 2);
    g.fillText(`${t1.toFixed(0)} s`, w - 30, h - 2);
    if (fin(tau)) {
      g.setLineDash([4, 3]); g.strokeStyle = "#c0392b";
      g.beginPath(); g.moveTo(L, py(tau)); g.lineTo(w - 4, py(tau)); g.stroke(); g.setLineDash([]);
      g.fillStyle = "#c0392b"; g.fillText("τ", w - 12, py(tau) - 2);
    }
    for (const [t, round, what] of a.rounds) {
      g.strokeStyle = "#7b2cbf";
      g.beginPath(); g.moveTo(px(t), 2); g.lineTo(px(t), h - B); g.stroke();
      g.fillStyle = "#7b2cbf"; g.fillText("R" + round, px(t) + 2, 11);
      g.fillText(String(what).toLowerCase().slice(0, 10), px(t) + 2, 21);
    }
    g.fillStyle = "#0a7f9e";
    for (const [t, v] of a.ca) if (fin(v)) g.fillRect(px(t) - 1, py(v) - 1, 2, 2);
    g.strokeStyle = "#1d2330"; g.lineWidth = 1.5;
    g.beginPath();
    a.cm_history.forEach(([t, v], i) => (i ? g.lineTo(px(t), py(v)) : g.moveTo(px(t), py(v))));
    g.stroke();
    // The forecast p_contributing (a probability, on the same axis as metres: 0..1).
    const known = pc.filter(([t, v]) => fin(t) && fin(v));
    if (known.length) {
      g.strokeStyle = "#e67e22"; g.lineWidth = 1.5;
      g.beginPath();
      known.forEach(([t, v], i) => (i ? g.lineTo(px(t), py(v)) : g.moveTo(px(t), py(v))));
      g.stroke();
      const [tl, vl] = known[known.length - 1];
      g.fillStyle = "#e67e22"; g.fillText("p", Math.min(px(tl) + 2, w - 10), py(vl) - 2);
    }
  }
  function panel(d) {
    const sim = scene.sim;
    const rb = scene.robot;
    el("clock").textContent = `t = ${fmt(scene.t, 2)} s`;
    const mode = el("mode");
    mode.textContent = rb ? rb.mode : "no robot";
    mode.className = "badge " + (rb ? rb.mode : "");
    el("header").innerHTML =
      `<h2>${esc(scene.viewer.mode === "replay" ? "Replay" : "Live")}${sim ? " · " + esc(sim.scenario) : ""}</h2>` +
      `<div class="kv"><span>robot</span><span>${rb ? esc(rb.mode) : "–"}</span><span>guard</span><span>${rb ? esc(rb.guard) : "–"}</span>` +
      `<span>sim</span><span>${sim ? esc(sim.state) : "–"}</span><span>min clear.</span><span>${sim ? fmt(sim.min_clearance_m) + " m" : "–"}</span>` +
      `<span>skipped</span><span>${scene.viewer.skipped_total}</span><span>pages</span><span>${scene.viewer.clients}</span></div>`;
    d.sim = sim ? sim.state : null;
    // One card per human: predicates, distances, CA / CM plot.
    const people = el("people");
    const ids = new Set(scene.humans.map((h) => h.id));
    for (const a of scene.assessments) ids.add(a.human_id);
    for (const s of scene.situations) ids.add(s.human_id);
    const want = [...ids].sort((x, y) => x - y);
    for (const c of [...people.children]) if (!want.includes(+c.dataset.id)) c.remove();
    for (const id of want) {
      let card = people.querySelector(`[data-id="${id}"]`);
      if (!card) {
        card = document.createElement("div");
        card.className = "card";
        card.dataset.id = id;
        card.innerHTML = '<div class="info"></div><canvas></canvas>';
        people.appendChild(card);
      }
      const s = scene.situations.find((x) => x.human_id === id);
      const a = scene.assessments.find((x) => x.human_id === id);
      const p = s ? s.predicates : {};
      const badge = (name, v) => `<span class="badge ${esc(v || "unknown")}">${name}: ${esc(v || "unknown")}</span>`;
      card.querySelector(".info").innerHTML =
        `<h2>Human ${id}${a ? " · " + esc(a.recording) : ""}</h2>` +
        `<div class="preds">${badge("NeedsToContribute", p.human_needs_to_contribute)}` +
        `${badge("HumanConstrained", p.human_is_constrained)}${badge("RobotConstrained", p.robot_is_constrained)}</div>` +
        `<div class="kv"><span>t_CROSS</span><span>${s ? fmt(s.t_cross_s, 1) + " s" : "–"}</span><span>Dir</span><span>${s ? esc(s.dir) : "–"}</span>` +
        `<span>d_h</span><span>${s ? fmt(s.d_h_m) : "–"}</span><span>d_OH</span><span>${s ? fmt(s.d_oh_m) : "–"}</span>` +
        `<span>d_OR</span><span>${s ? fmt(s.d_or_m) : "–"}</span><span>d_HR</span><span>${s ? fmt(s.d_hr_m) : "–"}</span>` +
        `<span>CM</span><span>${a ? fmt(a.cm_m) : "–"}</span><span>τ</span><span>${a ? fmt(a.tau_m) : "–"}</span>` +
        `<span>contrib.</span><span>${a ? esc(a.is_contributing) : "–"}</span><span>room</span><span>${s ? esc(s.room_plan) : "–"}</span>` +
        `<span>p_contrib.</span><span>${a ? fmt(a.p_contributing) : "–"}</span></div>`;
      if (a) {
        plot(card.querySelector("canvas"), a, a.tau_m);
        d.plots.push(id);
      }
    }
    // Daemons.
    const rows = scene.statuses.map((s) => {
      d.statuses.push(s.name);
      const state = s.silent ? `silent ${fmt(s.age_s, 0)} s` : s.state;
      return `<tr class="${s.silent ? "silent" : ""} ${esc(s.state)}"><td>${esc(s.name)}</td><td>${esc(state)}</td>` +
        `<td>${s.received}/${s.dropped}/${s.rejected}/${s.published}</td>` +
        `<td>${fmt(s.cycle_p50_ms, 1)}/${fmt(s.cycle_max_ms, 1)}</td><td>${s.backlog}</td></tr>`;
    });
    el("statuses").innerHTML = `<h2>Daemons</h2><table><tr><th>name</th><th>state</th>` +
      `<th title="received / dropped / rejected / published">recv/drop/rej/pub</th>` +
      `<th title="handling time p50 / max over the last second [ms]">ms p50/max</th>` +
      `<th title="messages waiting at a wake-up">backlog</th></tr>${rows.join("")}</table>`;
    // Timeline.
    const rp = scene.replay;
    el("timeline").hidden = !rp;
    if (rp) {
      d.replay = { t: rp.t, playing: rp.playing };
      const scrub = el("scrub");
      scrub.min = rp.start; scrub.max = rp.end;
      if (!scrubbing) scrub.value = rp.t;
      el("play").innerHTML = rp.playing ? "&#10074;&#10074;" : "&#9654;";
      el("tlabel").textContent = `${fmt(rp.t, 1)} / ${fmt(rp.end, 1)} s`;
      el("speed").value = String(rp.speed);
    }
    el("legend").innerHTML = `bands: t = 0<span class="bar"></span>${BAND_T_MAX} s · ` +
      '<span style="color:#7b2cbf">d_h</span> <span style="color:#1c8a3a">d_OH</span> ' +
      '<span style="color:#0a7f9e">d_OR</span>';
  }

  // ---- replay controls
  let scrubbing = false;
  const control = (command, value) =>
    fetch("/control", { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ command, value }) });
  el("play").addEventListener("click", () => control(scene && scene.replay && scene.replay.playing ? "pause" : "play", 0));
  el("speed").addEventListener("change", (e) => control("speed", parseFloat(e.target.value)));
  el("scrub").addEventListener("input", (e) => { scrubbing = true; control("seek", parseFloat(e.target.value)); });
  el("scrub").addEventListener("change", () => { scrubbing = false; });

  // ---- a frame arrives
  function onScene(s) {
    scene = s;
    window.coopnavScene = s;
    if (!seekDone && s.replay) {
      seekDone = true;
      control("pause", 0).then(() => control("seek", SEEK));
    }
    frame++;
    const { d, keys } = draw();
    panel(d);
    for (const id of d.plots) keys.push("plot:" + id);
    for (const n of d.statuses) keys.push("status:" + n);
    if (d.sim) keys.push("sim:" + d.sim);
    window.coopnavDrawn = d;
    el("drawn").textContent = JSON.stringify(d);
    if (ACK) {
      fetch("/ack", { method: "POST", headers: { "Content-Type": "application/json" },
        body: JSON.stringify({ utime: s.utime, drawn: d, keys }) }).catch(() => {});
    }
  }

  fetch("/map.json").then((r) => r.json()).then((m) => { map = buildMap(m); }).catch(() => {})
    .finally(() => {
      resize();
      if (ONCE) {
        // One frame from /scene.json; with ?t= (replay) the one of that time, once the seek is done.
        let tries = 0;
        const at = (rp) => Math.max(rp.start, Math.min(rp.end, SEEK));
        const loop = () => fetch("/scene.json").then((r) => r.json()).then((s) => {
          const ready = SEEK === null || !s.replay ||
            (Math.abs(s.replay.t - at(s.replay)) < 0.01 && !s.replay.playing);
          if (ready || ++tries > 50) return onScene(s);
          if (!seekDone) {
            seekDone = true;
            control("pause", 0).then(() => control("seek", SEEK));
          }
          setTimeout(loop, 100);
        });
        loop();
        return;
      }
      const es = new EventSource("/events");
      es.onmessage = (e) => onScene(JSON.parse(e.data));
      es.onerror = () => { el("clock").textContent += " (reconnecting)"; };
    });
})();
