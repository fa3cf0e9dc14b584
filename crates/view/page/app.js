// The learnpnp view: a client of the Foxglove WebSocket protocol
// (https://github.com/foxglove/ws-protocol, subprotocol foxglove.sdk.v1) that
// draws the feed's records (crates/feed: one record type per channel, as
// JSON), live from the server that served this page or replayed from an MCAP
// file. The same `apply` and `render` serve both.
"use strict";

// The channels the page draws (the feed's /learnpnp/reward is not drawn: an
// episode's return comes with its end). Replaying, it reads them from the file.
const TOPIC = {
  plan: "/learnpnp/plan",
  marking: "/learnpnp/marking",
  choice: "/learnpnp/choice",
  episode: "/learnpnp/episode",
  curve: "/learnpnp/curve",
  health: "/learnpnp/health",
  latency: "/learnpnp/latency",
};
const TOPICS = new Set(Object.values(TOPIC));
// Live, the markings, choices, episode ends and the processes' health and
// latency come in the server's bundle (crates/view/src/bundle.rs), one
// message a second; the plans and the curve on their own.
const BUNDLE = "/learnpnp/bundle";
const LIVE_TOPICS = new Set(["/learnpnp/plan", "/learnpnp/curve", BUNDLE]);
const SVG = "http://www.w3.org/2000/svg";
const RETURN_WINDOW = 10; // episodes in the moving average of returns
// Live, the page and its chart are redrawn at most once a second, as often
// as the server sends its bundle, or as often as the header's "redraw every"
// (or `?every=SECONDS`, 0.1 to 60) asks, so that a page open on the machine
// of a run takes little of its CPU (a redraw costs a browser about ten
// milliseconds of style, layout, paint, raster and compositing work in
// software; every 2 s halves it); replaying, the page is redrawn on every
// animation frame and the chart four times a second.
let liveFrameMs = liveFrameMsOf(new URLSearchParams(location.search).get("every"));
const REPLAY_CURVE_MS = 250;
const CURVE_POINTS = 480; // a line of the chart is drawn with at most this many points (one a pixel)

// The live redraw period asked for by `?every=SECONDS`, in milliseconds.
function liveFrameMsOf(every) {
  const seconds = every === null ? NaN : Number(every);
  return Number.isFinite(seconds) ? 1000 * Math.min(60, Math.max(0.1, seconds)) : 1000;
}

const $ = (id) => document.getElementById(id);
const el = (name, attrs = {}, text) => {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
};
// Sets a node's text only when it changes (an unchanged page is not laid out
// again), in its one text node when it has one (no node made per change).
const setText = (node, text) => {
  const only = node.firstChild;
  if (only && only === node.lastChild && only.nodeType === Node.TEXT_NODE) {
    if (only.data !== text) only.data = text;
  } else if (node.textContent !== text) node.textContent = text;
};
const fmt = (v) => (v === null || v === undefined ? "-" : Math.abs(v) >= 100 ? v.toFixed(1) : v.toFixed(3));

// ---------------------------------------------------------------- the state

function emptyState() {
  return {
    agents: new Map(), // "run/agent" -> agent
    curve: new Map(), // run -> [{episode, value}]
    health: new Map(), // process -> ProcessHealth
    latency: new Map(), // process -> Map(measure -> LatencySummary)
    markings: 0,
    subMarkings: 0,
    choices: 0,
  };
}

let state = emptyState();
let selected = ""; // the agent drawn
const dirty = { plan: true, marking: true, curve: true, processes: true, agents: true };

function agentOf(source) {
  const key = `${source.run}/${source.agent}`;
  let a = state.agents.get(key);
  if (!a) {
    a = { key, shape: null, shapeJson: "", marking: null, subMarking: null, markings: 0, choices: new Map(), returns: [], episode: null };
    state.agents.set(key, a);
    dirty.agents = true;
    if (!selected) selected = key;
  }
  return a;
}

// Applies one record of the feed, from the channel `topic`.
function apply(topic, r) {
  switch (topic) {
    case TOPIC.plan: {
      const a = agentOf(r.source);
      // An agent sends its plan again now and then (for a view started
      // late): the plan drawn is drawn again only when it changed.
      const json = JSON.stringify(r);
      if (json === a.shapeJson) return;
      a.shapeJson = json;
      a.shape = r;
      a.layout = null;
      if (a.key === selected) dirty.plan = true;
      break;
    }
    case TOPIC.marking: {
      const a = agentOf(r.source);
      // A sub-plan's marking: its places are not the drawn plan's; shown as a line.
      if (r.sub_plan) {
        a.subMarking = r;
        state.subMarkings += 1;
        if (a.key === selected) dirty.marking = true;
        break;
      }
      if (!a.shape) missingPlan();
      a.marking = r;
      a.markings += 1;
      a.episode = r.episode;
      state.markings += 1;
      if (a.key === selected) dirty.marking = true;
      break;
    }
    case TOPIC.choice: {
      const a = agentOf(r.source);
      a.choices.set(r.choice_point, r);
      state.choices += 1;
      if (a.key === selected) dirty.marking = true;
      break;
    }
    case TOPIC.episode: {
      const a = agentOf(r.source);
      if (!r.evaluation) a.returns.push({ episode: r.episode, value: r.episode_return });
      a.episode = r.episode;
      if (a.key === selected) dirty.curve = true;
      break;
    }
    case TOPIC.curve: {
      if (!state.curve.has(r.run)) state.curve.set(r.run, []);
      state.curve.get(r.run).push({ episode: r.episode, value: r.value });
      dirty.curve = true;
      break;
    }
    case TOPIC.health:
      state.health.set(r.process, r);
      dirty.processes = true;
      break;
    case TOPIC.latency: {
      if (!state.latency.has(r.process)) state.latency.set(r.process, new Map());
      state.latency.get(r.process).set(r.measure, r);
      dirty.processes = true;
      break;
    }
    default:
      return;
  }
  schedule();
}

// Applies one bundle of the server's (see crates/view/src/bundle.rs): per
// agent, the second's last markings and each choice point's last choice, as
// their own records, and how many came; the returns of its episodes; each
// process's latest health and latency.
function applyBundle(bundle) {
  for (const h of bundle.processes) apply(TOPIC.health, h);
  for (const l of bundle.latency) apply(TOPIC.latency, l);
  for (const b of bundle.agents) {
    const a = agentOf(b.source);
    if (b.sub_plan_marking) apply(TOPIC.marking, b.sub_plan_marking);
    if (b.marking) apply(TOPIC.marking, b.marking);
    for (const c of b.latest_choices) apply(TOPIC.choice, c);
    // `apply` counted one of each it was given.
    a.markings += Math.max(0, b.markings - 1);
    state.markings += Math.max(0, b.markings - 1);
    state.subMarkings += Math.max(0, b.sub_plan_markings - 1);
    state.choices += b.choices - b.latest_choices.length;
    for (const [episode, value] of b.returns) a.returns.push({ episode, value });
    if (b.last_episode !== null) {
      a.episode = Math.max(a.episode ?? 0, b.last_episode);
      if (a.key === selected) dirty.curve = true;
    }
  }
  schedule();
}

// ---------------------------------------------------------------- the plan's layout

// A layered layout: the plan as a graph of places and transitions, its back
// edges (found depth-first from the initial places, those no transition
// feeds) set aside, each node on the layer of its longest path from an
// initial place, and the nodes of a layer ordered by their predecessors'
// mean position.
function layout(shape) {
  const nodes = [];
  const index = new Map();
  const add = (key, kind, item) => {
    index.set(key, nodes.length);
    nodes.push({ key, kind, item, out: [], inc: [], layer: 0, pos: 0 });
  };
  for (const p of shape.places) add(`p${p.id}`, "place", p);
  for (const t of shape.transitions) add(`t${t.id}`, "transition", t);
  const edges = [];
  const link = (a, b) => {
    const [i, j] = [index.get(a), index.get(b)];
    if (i === undefined || j === undefined) return;
    edges.push([i, j]);
    nodes[i].out.push(j);
    nodes[j].inc.push(i);
  };
  for (const t of shape.transitions) {
    for (const p of t.inputs) link(`p${p}`, `t${t.id}`);
    for (const p of t.outputs) link(`t${t.id}`, `p${p}`);
  }
  // Depth-first from the initial places (then from whatever is left): an
  // edge to a node on the current path is a back edge.
  const initial = nodes.map((n, i) => i).filter((i) => nodes[i].kind === "place" && nodes[i].inc.length === 0);
  const roots = initial.length ? initial : nodes.length ? [0] : [];
  const colour = new Array(nodes.length).fill(0); // 0 new, 1 on path, 2 done
  const back = new Set();
  const order = [];
  const visit = (root) => {
    const stack = [[root, 0]];
    colour[root] = 1;
    while (stack.length) {
      const top = stack[stack.length - 1];
      const [n, k] = top;
      if (k < nodes[n].out.length) {
        top[1] += 1;
        const m = nodes[n].out[k];
        if (colour[m] === 1) back.add(`${n}>${m}`);
        else if (colour[m] === 0) {
          colour[m] = 1;
          stack.push([m, 0]);
        }
      } else {
        colour[n] = 2;
        order.push(n);
        stack.pop();
      }
    }
  };
  for (const r of roots) if (colour[r] === 0) visit(r);
  for (let i = 0; i < nodes.length; i++) if (colour[i] === 0) visit(i);
  order.reverse(); // a topological order of the forward edges
  for (const n of order) {
    for (const m of nodes[n].out) {
      if (!back.has(`${n}>${m}`)) nodes[m].layer = Math.max(nodes[m].layer, nodes[n].layer + 1);
    }
  }
  const layers = [];
  for (const n of order) (layers[nodes[n].layer] ||= []).push(n);
  for (const layer of layers) {
    if (!layer) continue;
    const mean = (n) => {
      const preds = nodes[n].inc.filter((p) => nodes[p].layer < nodes[n].layer);
      return preds.length ? preds.reduce((s, p) => s + nodes[p].pos, 0) / preds.length : nodes[n].pos;
    };
    layer.sort((a, b) => mean(a) - mean(b));
    layer.forEach((n, i) => (nodes[n].pos = i));
  }
  const DX = 90;
  const DY = 70;
  const tallest = Math.max(1, ...layers.map((l) => (l ? l.length : 0)));
  for (const layer of layers) {
    if (!layer) continue;
    const offset = ((tallest - layer.length) * DY) / 2;
    for (const n of layer) {
      nodes[n].x = 50 + nodes[n].layer * DX;
      nodes[n].y = 50 + offset + nodes[n].pos * DY;
    }
  }
  const width = 100 + Math.max(0, layers.length - 1) * DX + 120; // room for the values
  const height = 100 + (tallest - 1) * DY;
  return { nodes, edges, width, height };
}

// ---------------------------------------------------------------- drawing

let drawn = null; // the SVG elements of the selected agent's plan

function drawPlan(a) {
  const svg = $("plan");
  svg.replaceChildren();
  drawn = null;
  $("plan-name").textContent = a && a.shape ? `${a.shape.plan} (run ${a.shape.source.run}, agent ${a.shape.source.agent})` : "";
  if (!a || !a.shape) return;
  a.layout ||= layout(a.shape);
  const { nodes, edges, width, height } = a.layout;
  svg.setAttribute("viewBox", `0 0 ${width} ${height}`);
  const defs = el("defs");
  const marker = el("marker", { id: "arrow", viewBox: "0 0 10 10", refX: 10, refY: 5, markerWidth: 6, markerHeight: 6, orient: "auto" });
  marker.append(el("path", { d: "M0,0 L10,5 L0,10 z", fill: "#888" }));
  defs.append(marker);
  svg.append(defs);
  const R = 14;
  const arcs = el("g");
  for (const [i, j] of edges) {
    const [a0, b0] = [nodes[i], nodes[j]];
    const dx = b0.x - a0.x;
    const dy = b0.y - a0.y;
    const len = Math.hypot(dx, dy) || 1;
    const cut = (n) => (n.kind === "place" ? R : 5);
    const x1 = a0.x + (dx / len) * cut(a0);
    const y1 = a0.y + (dy / len) * cut(a0);
    const x2 = b0.x - (dx / len) * cut(b0);
    const y2 = b0.y - (dy / len) * cut(b0);
    // Back edges bend below, so a loop is not drawn over the forward arcs.
    const low = Math.max(y1, y2) + 45;
    const d = b0.layer <= a0.layer
      ? `M${x1},${y1} C${x1 + 30},${low} ${x2 - 30},${low} ${x2},${y2}`
      : `M${x1},${y1} L${x2},${y2}`;
    arcs.append(el("path", { class: "arc", d }));
  }
  svg.append(arcs);
  const places = new Map();
  const transitions = new Map();
  for (const n of nodes) {
    if (n.kind === "place") {
      const g = el("g", { "data-place": n.item.id, "data-label": n.item.label });
      const circle = el("circle", { class: "place", cx: n.x, cy: n.y, r: R });
      const tokens = el("text", { class: "token", x: n.x, y: n.y }, "");
      g.append(circle, tokens, el("text", { class: "label", x: n.x, y: n.y + R + 11 }, n.item.label));
      svg.append(g);
      places.set(n.item.label, { id: n.item.id, g, circle, tokens, x: n.x, y: n.y });
    } else {
      const g = el("g", { "data-transition": n.item.id, "data-label": n.item.label });
      const bar = el("rect", { class: "transition", x: n.x - 3, y: n.y - 14, width: 6, height: 28 });
      g.append(bar, el("text", { class: "label", x: n.x, y: n.y - 18 }, n.item.label));
      svg.append(g);
      transitions.set(n.item.label, { bar });
    }
  }
  const values = el("g");
  svg.append(values);
  drawn = { places, transitions, values, byId: new Map([...places.values()].map((p) => [p.id, p])) };
}

// The token count of every place of the agent's plan, by label, from its
// last marking (its `tokens` in place-id order; its `marked` list if the
// shape has not come yet).
function tokensByLabel(a) {
  const m = a && a.marking;
  const out = new Map();
  if (!m) return out;
  if (a.shape) {
    for (const p of a.shape.places) out.set(p.label, m.tokens[p.id] || 0);
  }
  for (const p of m.marked) out.set(p.label, p.tokens);
  return out;
}

function drawMarking(a) {
  const m = a && a.marking;
  setText($("episode"), m ? String(m.episode) : "-");
  setText($("step"), m ? String(m.step) : "-");
  setText($("marking"), m ? m.marked.map((p) => (p.tokens === 1 ? p.label : `${p.label}×${p.tokens}`)).join(", ") || "(empty)" : "no marking yet");
  setText($("running"), m && m.running.length ? m.running.join(", ") : "-");
  const sub = a && a.subMarking;
  setText($("sub-plan"), sub ? `${sub.sub_plan}: ${sub.marked.map((p) => (p.tokens === 1 ? p.label : `${p.label}×${p.tokens}`)).join(", ") || "(empty)"}` : "-");
  const choices = a ? [...a.choices] : [];
  if (drawn) {
    const tokens = tokensByLabel(a);
    for (const [label, p] of drawn.places) {
      const n = tokens.get(label) || 0;
      p.circle.classList.toggle("marked", n > 0);
      p.g.toggleAttribute("data-marked", n > 0);
      setText(p.tokens, n > 0 ? String(n) : "");
      p.circle.classList.toggle("choice", a.choices.has(label));
    }
    const running = new Set(m ? m.running : []);
    for (const [label, t] of drawn.transitions) {
      // PNP names an action's transitions `action.start` / `action.end`.
      t.bar.classList.toggle("running", running.has(label.replace(/\.(start|end)$/, "")));
    }
    const shown = choices.filter(([point]) => drawn.places.has(point));
    drawValues(drawn.values, shown, (point, o, i) => {
      const p = drawn.places.get(point);
      return el("text", { class: "values", x: p.x - 14, y: p.y + 36 + i * 11 });
    }, (node, point, c, o, i) => {
      setText(node, `${(i === c.greedy ? "★" : " ") + (i === c.taken ? "▶" : " ")}${o.label} ${fmt(o.value)} (${o.updates})`);
      node.classList.toggle("taken", i === c.taken);
    });
  }
  drawValues($("choices").tBodies[0], choices, (point, o, i) => {
    const tr = document.createElement("tr");
    if (i === 0) tr.classList.add("first");
    for (let k = 0; k < 4; k++) tr.append(document.createElement("td"));
    tr.cells[1].className = "option";
    return tr;
  }, (tr, point, c, o, i) => {
    tr.classList.toggle("greedy", i === c.greedy);
    tr.classList.toggle("taken", i === c.taken);
    setText(tr.cells[0], i === 0 ? point : "");
    setText(tr.cells[1], o.label);
    setText(tr.cells[2], fmt(o.value));
    setText(tr.cells[3], String(o.updates));
    const explored = i === 0 && c.explored;
    tr.cells[0].classList.toggle("explored", explored);
    if (explored) tr.cells[0].title = "the last choice here explored";
    else tr.cells[0].removeAttribute("title");
  });
}

// Shows every option of `choices` ([point, ChoiceRecord] pairs) as one child
// of `parent`: the children are made (`make(point, option, i)`) only when the
// choice points or their options' count change, and are otherwise updated in
// place (`update(node, point, choice, option, i)`).
function drawValues(parent, choices, make, update) {
  const shape = choices.map(([point, c]) => `${point}:${c.options.length}`).join("|");
  if (parent.dataset.shape !== shape) {
    parent.replaceChildren(...choices.flatMap(([point, c]) => c.options.map((o, i) => make(point, o, i))));
    parent.dataset.shape = shape;
  }
  let node = parent.firstElementChild;
  for (const [point, c] of choices) {
    c.options.forEach((o, i) => {
      update(node, point, c, o, i);
      node = node.nextElementSibling;
    });
  }
}

function movingAverage(points, w) {
  const out = [];
  let sum = 0;
  points.forEach((p, i) => {
    sum += p.value;
    if (i >= w) sum -= points[i - w].value;
    out.push({ episode: p.episode, value: sum / Math.min(i + 1, w) });
  });
  return out;
}

// At most `n` of `points`, evenly spaced, the last always among them.
function thinned(points, n) {
  if (points.length <= n) return points;
  const step = (points.length - 1) / (n - 1);
  return Array.from({ length: n }, (_, i) => points[Math.round(i * step)]);
}

// The chart's elements, made once and then updated in place.
let chart = null;

function drawCurve(a) {
  const W = 480;
  const H = 220;
  const L = 50;
  const B = 20;
  if (!chart) {
    const svg = $("curve");
    const tick = (attrs) => el("text", { class: "tick", ...attrs }, "");
    chart = {
      empty: el("text", { class: "tick", x: L + 10, y: H / 2 }, "no points yet"),
      y0: tick({ x: L - 4, "text-anchor": "end" }),
      y1: tick({ x: L - 4, "text-anchor": "end" }),
      x0: tick({ x: L, y: H - 5 }),
      x1: tick({ x: W - 10, y: H - 5, "text-anchor": "end" }),
      lines: el("g"),
    };
    svg.replaceChildren(
      el("line", { class: "axis", x1: L, y1: H - B, x2: W - 5, y2: H - B }),
      el("line", { class: "axis", x1: L, y1: 5, x2: L, y2: H - B }),
      chart.empty, chart.y0, chart.y1, chart.x0, chart.x1, chart.lines,
    );
  }
  const series = [];
  for (const [run, points] of [...state.curve].sort((x, y) => x[0] - y[0])) {
    series.push({ cls: "curve-line", points, run });
  }
  if (a && a.returns.length) series.push({ cls: "return-line", points: movingAverage(a.returns, RETURN_WINDOW) });
  for (const s of series) s.points = thinned(s.points, CURVE_POINTS);
  const all = series.flatMap((s) => s.points);
  chart.empty.setAttribute("visibility", all.length ? "hidden" : "visible");
  if (!all.length) {
    for (const t of [chart.y0, chart.y1, chart.x0, chart.x1]) setText(t, "");
    chart.lines.replaceChildren();
    return;
  }
  const x0 = Math.min(...all.map((p) => p.episode));
  const x1 = Math.max(x0 + 1, ...all.map((p) => p.episode));
  let y0 = Math.min(...all.map((p) => p.value));
  let y1 = Math.max(...all.map((p) => p.value));
  if (y1 - y0 < 1e-9) {
    y0 -= 1;
    y1 += 1;
  }
  const sx = (x) => L + ((x - x0) / (x1 - x0)) * (W - L - 10);
  const sy = (y) => H - B - ((y - y0) / (y1 - y0)) * (H - B - 10);
  for (const [t, v] of [[chart.y0, y0], [chart.y1, y1]]) {
    t.setAttribute("y", sy(v) + 3);
    setText(t, fmt(v));
  }
  setText(chart.x0, String(x0));
  setText(chart.x1, `${x1} episodes`);
  while (chart.lines.childElementCount > series.length) chart.lines.lastElementChild.remove();
  while (chart.lines.childElementCount < series.length) chart.lines.append(el("path"));
  series.forEach((s, i) => {
    const path = chart.lines.children[i];
    path.setAttribute("class", s.cls);
    path.setAttribute("d", s.points.map((p, k) => `${k ? "L" : "M"}${sx(p.episode).toFixed(1)},${sy(p.value).toFixed(1)}`).join(" "));
  });
}

// A heartbeat's age to the second: a healthy process's (a heartbeat every
// 100 ms) reads "< 1 s" and its row is not drawn again each second.
const heartbeatAge = (ms) => (ms < 1000 ? "< 1 s" : `${Math.floor(ms / 1000)} s`);

function drawProcesses() {
  const names = [...new Set([...state.health.keys(), ...state.latency.keys()])].sort();
  $("processes-panel").hidden = names.length === 0;
  const body = $("processes").tBodies[0];
  const shape = names.join("|");
  if (body.dataset.shape !== shape) {
    body.replaceChildren(...names.map(() => {
      const tr = document.createElement("tr");
      for (let k = 0; k < 7; k++) tr.append(document.createElement("td"));
      return tr;
    }));
    body.dataset.shape = shape;
  }
  names.forEach((name, i) => {
    const h = state.health.get(name);
    const lat = state.latency.get(name);
    const latency = lat
      ? [...lat.values()].map((l) => `${l.measure}: ${l.p50_us} / ${l.p90_us} / ${l.p99_us} / ${l.max_us} (${l.count})`).join("; ")
      : "-";
    const cells = h
      ? [name, h.pid ?? "-", h.alive ? "yes" : "no", heartbeatAge(h.heartbeat_age_ms), h.restarts, h.rejections, latency]
      : [name, "-", "-", "-", "-", "-", latency];
    cells.forEach((c, k) => setText(body.rows[i].cells[k], String(c)));
  });
}

function drawAgents() {
  const select = $("agent");
  const keys = [...state.agents.keys()].sort((x, y) => {
    const [a, b] = [x.split("/").map(Number), y.split("/").map(Number)];
    return a[0] - b[0] || a[1] - b[1];
  });
  if (select.options.length !== keys.length || keys.some((k, i) => select.options[i].value !== k)) {
    select.replaceChildren(...keys.map((k) => new Option(`run ${k.split("/")[0]}, agent ${k.split("/")[1]}`, k)));
  }
  select.value = selected;
}

// Writes what is shown into #state's attributes, for tests and scripts.
function report(a) {
  const s = $("state").dataset;
  s.markings = String(state.markings);
  s.subPlanMarkings = String(state.subMarkings);
  s.subPlan = $("sub-plan").textContent;
  s.choices = String(state.choices);
  s.agent = selected;
  s.episode = a && a.episode !== null ? String(a.episode) : "";
  s.curvePoints = String([...state.curve.values()].reduce((n, p) => n + p.length, 0));
  s.returns = String(a ? a.returns.length : 0);
  s.step = a && a.marking ? String(a.marking.step) : "";
  // The marked places as drawn: label and token count, in place-id order.
  s.marked = drawn
    ? JSON.stringify([...drawn.places.values()].filter((p) => p.tokens.textContent).sort((x, y) => x.id - y.id).map((p) => [p.g.dataset.label, Number(p.tokens.textContent)]))
    : "";
  s.tokens = a && a.marking ? a.marking.tokens.join(",") : "";
  s.lastMarking = a && a.marking ? JSON.stringify(a.marking) : "";
  if (s.mode === "replay") s.tNs = String(replay.at);
  const r = $("plan").getBoundingClientRect();
  s.planBox = [r.left + scrollX, r.top + scrollY, r.width, r.height].map((v) => Math.round(v)).join(",");
}

let frame = 0;
let frameTimer = 0;
let lastFrame = -Infinity;
let lastCurve = -Infinity;
let curveTimer = 0;

// Redraws once, whatever came in meanwhile: on the next animation frame,
// live no sooner than liveFrameMs after the last redraw. Nothing runs while
// nothing arrives.
function schedule() {
  if (frame || frameTimer) return;
  const wait = socket ? lastFrame + liveFrameMs - performance.now() : 0;
  if (wait <= 0) frame = requestAnimationFrame(render);
  else {
    frameTimer = setTimeout(() => {
      frameTimer = 0;
      schedule();
    }, wait);
  }
}

function render(now) {
  frame = 0;
  lastFrame = now;
  const a = state.agents.get(selected);
  if (dirty.agents) {
    drawAgents();
    dirty.agents = false;
  }
  if (dirty.plan) {
    drawPlan(a);
    dirty.plan = false;
    dirty.marking = true;
  }
  if (dirty.marking) {
    drawMarking(a);
    dirty.marking = false;
  }
  if (dirty.curve) {
    const every = socket ? liveFrameMs : REPLAY_CURVE_MS;
    if (now - lastCurve >= every) {
      drawCurve(a);
      lastCurve = now;
      dirty.curve = false;
    } else if (!curveTimer) {
      curveTimer = setTimeout(() => {
        curveTimer = 0;
        schedule();
      }, every - (now - lastCurve));
    }
  }
  if (dirty.processes) {
    drawProcesses();
    dirty.processes = false;
  }
  report(a);
}

function redrawAll() {
  for (const k of Object.keys(dirty)) dirty[k] = true;
  lastCurve = -Infinity;
  schedule();
}

$("agent").addEventListener("change", (e) => {
  selected = e.target.value;
  redrawAll();
});

// The header's "redraw every" (on a page served live) shows the live period
// (an `?every` it does not list is added to it) and sets it, kept in the
// address so that a reload keeps it.
function showEvery() {
  $("every-control").hidden = !(location.protocol === "http:" || location.protocol === "https:");
  const select = $("every");
  const seconds = String(liveFrameMs / 1000);
  if (![...select.options].some((o) => o.value === seconds)) select.add(new Option(`${seconds} s`, seconds));
  select.value = seconds;
}
$("every").addEventListener("change", (e) => {
  liveFrameMs = liveFrameMsOf(e.target.value);
  const params = new URLSearchParams(location.search);
  params.set("every", String(liveFrameMs / 1000));
  history.replaceState(null, "", `?${params}`);
  if (frameTimer) {
    clearTimeout(frameTimer);
    frameTimer = 0;
  }
  schedule();
});
showEvery();

function setStatus(text, cls) {
  const s = $("status");
  s.textContent = text;
  s.className = `status ${cls || ""}`;
}

function fail(message) {
  setStatus(message, "error");
  $("state").dataset.error = message;
}

// ---------------------------------------------------------------- live

let socket = null;
let retry = 0;
// Asks the server again for the plans it keeps (see `missingPlan`).
let askForPlans = () => {};
let askedForPlans = 0;

// A marking came from an agent whose plan has not: the server sends the plans
// it keeps to each new subscriber of /learnpnp/plan, so subscribe again (at
// most every two seconds) until the plan comes.
function missingPlan() {
  const now = performance.now();
  if (now - askedForPlans < 2000) return;
  askedForPlans = now;
  askForPlans();
}

function connect() {
  const ws = new WebSocket(`ws://${location.host}/`, ["foxglove.sdk.v1"]);
  socket = ws;
  ws.binaryType = "arraybuffer";
  const topics = new Map(); // subscription id -> topic
  const subscribed = new Map(); // channel id -> subscription id
  let next = 1;
  ws.onopen = () => setStatus("live", "live");
  askForPlans = () => {
    for (const [channel, id] of subscribed) {
      if (topics.get(id) !== TOPIC.plan || ws.readyState !== WebSocket.OPEN) continue;
      const again = next++;
      ws.send(JSON.stringify({ op: "unsubscribe", subscriptionIds: [id] }));
      ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: again, channelId: channel }] }));
      topics.delete(id);
      topics.set(again, TOPIC.plan);
      subscribed.set(channel, again);
    }
  };
  ws.onmessage = (event) => {
    if (typeof event.data === "string") {
      const msg = JSON.parse(event.data);
      if (msg.op === "advertise") {
        const subscriptions = [];
        for (const ch of msg.channels) {
          if (!LIVE_TOPICS.has(ch.topic) || subscribed.has(ch.id)) continue;
          const id = next++;
          topics.set(id, ch.topic);
          subscribed.set(ch.id, id);
          subscriptions.push({ id, channelId: ch.id });
        }
        if (subscriptions.length) ws.send(JSON.stringify({ op: "subscribe", subscriptions }));
      } else if (msg.op === "unadvertise") {
        for (const id of msg.channelIds) {
          topics.delete(subscribed.get(id));
          subscribed.delete(id);
        }
      }
      return;
    }
    // Binary: opcode 0x01 (message data), u32 subscription id, u64 log time, payload.
    const view = new DataView(event.data);
    if (view.byteLength < 13 || view.getUint8(0) !== 0x01) return;
    const topic = topics.get(view.getUint32(1, true));
    if (!topic) return;
    try {
      const record = JSON.parse(new TextDecoder().decode(new Uint8Array(event.data, 13)));
      if (topic !== BUNDLE) apply(topic, record);
      else applyBundle(record);
    } catch (e) {
      console.warn(`a record on ${topic} could not be read: ${e}`);
    }
  };
  ws.onclose = () => {
    if (socket !== ws) return;
    setStatus("disconnected: retrying", "");
    // Back off up to ten seconds: a page left open on a finished run stays idle.
    retry = Math.min(retry + 1, 10);
    setTimeout(() => socket === ws && connect(), retry * 1000);
  };
}

// ---------------------------------------------------------------- replay

const replay = {
  messages: [], // {t (ns since the first), topic, record}
  span: 0,
  at: 0, // the time shown, ns since the first message
  next: 0, // index of the first message not applied
  playing: false,
  speed: 1,
  wall: 0,
};

function load(buffer, name) {
  if (socket) {
    const ws = socket;
    socket = null;
    ws.close();
  }
  let file;
  try {
    file = LearnpnpMcap.read(buffer);
  } catch (e) {
    fail(`${name}: ${e.message}`);
    return false;
  }
  const own = file.messages.filter((m) => TOPICS.has(m.topic));
  const first = own.length ? own[0].logTime : 0n;
  const decoder = new TextDecoder();
  replay.messages = [];
  for (const m of own) {
    try {
      replay.messages.push({ t: Number(m.logTime - first), topic: m.topic, record: JSON.parse(decoder.decode(m.data)) });
    } catch (e) {
      console.warn(`a record on ${m.topic} could not be read: ${e}`);
    }
  }
  replay.span = replay.messages.length ? replay.messages[replay.messages.length - 1].t : 0;
  $("replay").hidden = false;
  $("every-control").hidden = true;
  $("state").dataset.mode = "replay";
  $("state").dataset.spanNs = String(replay.span);
  setStatus(`replay: ${name}${file.truncated ? " (truncated)" : ""}`, "replay");
  state = emptyState();
  selected = "";
  replay.next = 0;
  seek(replay.span);
  return true;
}

// Shows the state at `t` ns after the first message: every record logged at
// or before it applied, in log-time order.
function seek(t) {
  t = Math.round(Math.max(0, Math.min(replay.span, t)));
  if (t < replay.at || replay.next === 0) {
    const keep = selected;
    state = emptyState();
    selected = keep;
    replay.next = 0;
    redrawAll();
  }
  while (replay.next < replay.messages.length && replay.messages[replay.next].t <= t) {
    const m = replay.messages[replay.next++];
    apply(m.topic, m.record);
  }
  replay.at = t;
  $("slider").value = String(replay.span ? Math.round((t / replay.span) * 1000) : 1000);
  $("clock").textContent = `${(t / 1e9).toFixed(2)} / ${(replay.span / 1e9).toFixed(2)} s`;
  schedule();
}

function tick(now) {
  if (!replay.playing) return;
  const elapsed = now - replay.wall;
  replay.wall = now;
  seek(replay.at + elapsed * 1e6 * replay.speed);
  if (replay.at >= replay.span) {
    setPlaying(false);
    return;
  }
  requestAnimationFrame(tick);
}

function setPlaying(on) {
  replay.playing = on;
  $("play").textContent = on ? "pause" : "play";
  if (on) {
    if (replay.at >= replay.span) seek(0);
    replay.wall = performance.now();
    requestAnimationFrame(tick);
  }
}

$("play").addEventListener("click", () => setPlaying(!replay.playing));
$("speed").addEventListener("change", (e) => (replay.speed = Number(e.target.value)));
$("slider").addEventListener("input", (e) => seek((Number(e.target.value) / 1000) * replay.span));
$("file").addEventListener("change", async (e) => {
  const f = e.target.files[0];
  if (f) load(await f.arrayBuffer(), f.name);
});

// ---------------------------------------------------------------- start

async function start() {
  const params = new URLSearchParams(location.search);
  const url = params.get("mcap");
  if (!url) {
    if (location.protocol === "http:" || location.protocol === "https:") connect();
    else setStatus("open an MCAP file", "");
    schedule();
    return;
  }
  let buffer;
  try {
    const response = await fetch(url);
    if (!response.ok) throw new Error(`HTTP ${response.status}`);
    buffer = await response.arrayBuffer();
  } catch (e) {
    fail(`${url}: ${e.message}`);
    return;
  }
  if (!load(buffer, url)) return;
  // `t` is a fraction (0 to 1) of the recording's span.
  const t = Number(params.get("t"));
  if (params.has("t") && Number.isFinite(t)) seek(Math.round(Math.max(0, Math.min(1, t)) * replay.span));
  const speed = params.get("speed");
  if (speed && [...$("speed").options].some((o) => o.value === speed)) {
    $("speed").value = speed;
    replay.speed = Number(speed);
  }
  if (params.has("play")) setPlaying(true);
}

start();
