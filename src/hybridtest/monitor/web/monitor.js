// The monitor's page: polls /api/state (twice a second) and /api/series (once a second) and
// draws the state, the meters and the scopes. Plots use uPlot when the build bundled it, else
// a plain canvas. Operator actions are POSTs with the token as a bearer token.
"use strict";
const $ = (id) => document.getElementById(id);
const fmt = (v, digits = 4) => (v === null || v === undefined || Number.isNaN(v)) ? "–" : Number(v).toPrecision(digits);
const state = { slotNames: [], series: null, generation: -1, since: -1, plots: {}, slots: 0, actuators: 0, p0: [] };

function duration(s) {
  if (s === null || s === undefined || s < 0) return "–";
  if (s < 1) return (s * 1000).toFixed(0) + " ms";
  if (s < 60) return s.toFixed(1) + " s";
  const m = Math.floor(s / 60);
  if (m < 60) return m + " min " + Math.floor(s % 60) + " s";
  return Math.floor(m / 60) + " h " + (m % 60) + " min";
}

// ---- plots: uPlot for time series when bundled, else (and for the x–y loop) a canvas ----
class CanvasPlot {
  constructor(el, names) {
    this.names = names;
    this.canvas = document.createElement("canvas");
    el.appendChild(this.canvas);
  }
  setData(data) {  // data[0] = x, data[1..] = y series
    const c = this.canvas, w = c.clientWidth || 480, h = c.clientHeight || 220;
    c.width = w; c.height = h;
    const g = c.getContext("2d");
    g.clearRect(0, 0, w, h);
    const colours = ["#1565c0", "#c62828", "#2e7d32", "#6a1b9a", "#ef6c00", "#00838f"];
    const finite = (a) => a.filter((v) => v !== null && Number.isFinite(v));
    const xs = finite(data[0]);
    const ys = finite([].concat(...data.slice(1)));
    if (xs.length < 2 || ys.length < 1) { g.fillText("no data yet", 10, 20); return; }
    let [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
    if (x1 === x0) x1 = x0 + 1;
    if (y1 === y0) { y0 -= 1; y1 += 1; }
    const L = 60, R = 10, T = 10, B = 20;
    const px = (x) => L + (x - x0) / (x1 - x0) * (w - L - R);
    const py = (y) => h - B - (y - y0) / (y1 - y0) * (h - T - B);
    g.strokeStyle = "#999"; g.strokeRect(L, T, w - L - R, h - T - B);
    g.fillStyle = "#333"; g.font = "11px sans-serif";
    g.fillText(fmt(y1, 3), 2, T + 10); g.fillText(fmt(y0, 3), 2, h - B);
    g.fillText(fmt(x0, 3), L, h - 4); g.fillText(fmt(x1, 3), w - R - 40, h - 4);
    for (let s = 1; s < data.length; ++s) {
      g.strokeStyle = colours[(s - 1) % colours.length]; g.beginPath();
      let pen = false;
      for (let i = 0; i < data[0].length; ++i) {
        const x = data[0][i], y = data[s][i];
        if (x === null || y === null || !Number.isFinite(x) || !Number.isFinite(y)) { pen = false; continue; }
        if (pen) g.lineTo(px(x), py(y)); else g.moveTo(px(x), py(y));
        pen = true;
      }
      g.stroke();
      g.fillStyle = colours[(s - 1) % colours.length];
      g.fillText(this.names[s - 1] || "", L + 8 + 90 * (s - 1), T + 12);
    }
  }
}

function makePlot(id, names, xy) {
  const el = $(id);
  el.innerHTML = "";
  if (window.uPlot && !xy) {
    const colours = ["#1565c0", "#c62828", "#2e7d32", "#6a1b9a", "#ef6c00", "#00838f"];
    const opts = { width: Math.max(el.clientWidth, 400), height: 220, scales: { x: { time: false } },
      series: [{ label: "t [s]" }].concat(names.map((n, i) => ({ label: n, stroke: colours[i % colours.length], spanGaps: false }))) };
    return new window.uPlot(opts, [[]].concat(names.map(() => [])), el);
  }
  return new CanvasPlot(el, names);
}

function setupPlots(series) {
  state.slots = series.slots; state.actuators = series.actuators;
  const slotNames = [...Array(series.slots).keys()].map((s) => state.slotNames[s] || "slot " + (s + 1));
  const act = [...Array(series.actuators).keys()];
  state.plots.d = makePlot("scope-d", slotNames.map((n) => "d " + n), false);
  state.plots.r = makePlot("scope-r", slotNames.map((n) => "r " + n), false);
  state.plots.track = makePlot("scope-track", [].concat(...act.map((a) => ["command " + (a + 1), "position " + (a + 1)])), false);
  state.plots.loop = makePlot("scope-loop", act.map((a) => "actuator " + (a + 1)), true);
  $("plot-note").textContent = window.uPlot ? "Plots: uPlot (bundled in the binary)."
    : "uPlot is not bundled with this build: plain canvas plots.";
}

function append(target, columns, reset) {
  if (reset || !target) return JSON.parse(JSON.stringify(columns));
  for (const k of Object.keys(columns)) target[k] = (target[k] || []).concat(columns[k]);
  return target;
}

function drawScopes() {
  const c = state.series;
  if (!c || !state.plots.d) return;
  const idx = (n) => [...Array(n).keys()];
  state.plots.d.setData([c.t].concat(idx(state.slots).map((s) => c["d" + s])));
  state.plots.r.setData([c.t].concat(idx(state.slots).map((s) => c["r" + s])));
  state.plots.track.setData([c.t].concat(...idx(state.actuators).map((a) => [c["command" + a], c["position" + a]])));
  if (state.actuators > 0) {
    // Force against actuator displacement from p0, one loop per actuator (x of the first).
    const p0 = state.p0[0] || 0;
    const x = c["position0"].map((v) => v === null ? null : v - p0);
    state.plots.loop.setData([x].concat(idx(state.actuators).map((a) => c["force" + a])));
  } else {
    state.plots.loop.setData([c["d0"] || [], c["r0"] || []]);
  }
}

async function pollSeries() {
  try {
    const r = await fetch(`/api/series?since=${state.since}&generation=${state.generation}`);
    const s = await r.json();
    if (!state.plots.d || s.slots !== state.slots || s.actuators !== state.actuators) setupPlots(s);
    state.series = append(state.series, s.columns, s.reset);
    state.generation = s.generation;
    const seq = state.series.seq;
    if (seq && seq.length) state.since = seq[seq.length - 1];
    drawScopes();
  } catch (e) { /* the state poll reports the connection */ }
}

// ---- state, identity, meters ----
function gauge(label, value, fraction, level, text) {
  const pct = Math.min(100, Math.max(0, 100 * (fraction || 0)));
  return `<div class="gauge ${level}"><span>${label}</span><div class="track"><div class="fill" style="width:${pct}%"></div></div>` +
         `<span>${text} (${pct.toFixed(0)} %)</span></div>`;
}

function renderMeters(actuators) {
  if (!actuators.length) return;
  $("meters").innerHTML = actuators.map((a) => {
    const l = a.limits, m = a.margin || { force_fraction: 0, stroke_fraction: 0, level: "normal" };
    const lim = l ? `stroke ${fmt(l.stroke_min, 3)} … ${fmt(l.stroke_max, 3)} m, max increment ${fmt(l.max_increment, 3)} m, ` +
                    `force soft ${fmt(l.force_soft, 4)} N, hard ${fmt(l.force_hard, 4)} N` : "no limits known";
    const strokeText = (v) => `${fmt(v)} m`;
    const strokeFrac = (v) => l && v !== null ? Math.abs(v - (l.stroke_max + l.stroke_min) / 2) / ((l.stroke_max - l.stroke_min) / 2) : 0;
    return `<div class="meter"><h3>Actuator of slot ${a.slot} — <span class="level ${m.level}">${m.level}</span></h3>` +
      gauge("command", a.command, strokeFrac(a.command), m.level, strokeText(a.command)) +
      gauge("position", a.position, m.stroke_fraction, m.level, strokeText(a.position)) +
      gauge("force", a.force, m.force_fraction, m.level, `${fmt(a.force)} N of ${l ? fmt(l.force_hard, 4) : "–"} N`) +
      `<p class="hint">Slot ${a.slot} force ${fmt(a.force)} N; limit (force_hard) ${l ? fmt(l.force_hard, 4) : "–"} N. Limits: ${lim}.</p></div>`;
  }).join("");
}

function render(s) {
  const badge = $("status");
  badge.textContent = s.status; badge.className = "badge " + s.status;
  document.title = `${s.status} — hybridtest monitor`;
  $("stop-panel").hidden = s.status !== "stopped";
  $("reason").textContent = s.reason;
  $("resume-command").textContent = s.resume_command || "(no journal: nothing to resume)";
  const id = s.identity;
  state.slotNames = s.slots.map((x) => x.name);
  state.p0 = s.actuators.map((a) => a.p0);
  $("identity").innerHTML = [["config", id.config], ["model", id.model], ["specimen", id.specimen || "–"],
    ["bench", id.bench], ["command", id.command], ["journal", id.csv || "(none)"], ["monitor", id.mode]]
    .map(([k, v]) => `<tr><th>${k}</th><td>${String(v).replace(/</g, "&lt;")}</td></tr>`).join("");
  $("t").textContent = Number(s.t).toFixed(4);
  $("end-time").textContent = s.end_time;
  $("progress-bar").style.width = (100 * s.fraction).toFixed(1) + "%";
  $("step").textContent = s.step;
  $("evaluations").textContent = s.physical_evaluations;
  $("lab-time").textContent = duration(s.lab_time);
  $("wall-time").textContent = duration(s.wall_time);
  $("eta").textContent = s.status === "finished" ? "done" : s.status === "holding" ? "holding"
    : s.status === "stopped" ? "stopped" : duration(s.eta_s);
  $("resumes").textContent = s.resumes.length ? s.resumes.map((t) => `t = ${fmt(t)} s`).join(", ") : "none";
  $("actions-policy").textContent = s.actions_policy;
  $("actions").innerHTML = s.actions.slice(-8).reverse().map((a) =>
    `<li>${a.action} ${a.refused ? "refused (" + a.refused + ")" : "at t = " + fmt(a.t) + " s"} — ${String(a.origin).replace(/</g, "&lt;")} ${a.applied_at || ""}</li>`).join("");
  renderMeters(s.actuators);
  const rt = s.realtime;
  if (rt && rt.available) {
    $("realtime").innerHTML = `<tr><th>deadline misses</th><td>${rt.deadline_misses}</td></tr>` +
      ["J1", "J2", "J3"].map((j) => `<tr><th>${j}</th><td>${fmt(rt[j])}</td></tr>`).join("");
  }
  $("frames").textContent = s.frames;
  $("dropped").textContent = s.dropped_frames;
  const live = s.status === "running" || s.status === "holding" || s.status === "starting";
  for (const b of ["hold", "continue", "stop"]) $(b).disabled = !live || s.actions_policy === "read-only";
}

async function pollState() {
  try {
    const r = await fetch("/api/state");
    render(await r.json());
    $("connection").textContent = "live";
  } catch (e) {
    $("connection").textContent = "no connection to the run (ended, or the monitor stopped); the last state is shown";
  }
}

async function act(name) {
  const token = $("token").value;
  sessionStorage.setItem("hybridtest-token", token);
  const headers = token ? { Authorization: "Bearer " + token } : {};
  try {
    const r = await fetch("/api/" + name, { method: "POST", headers });
    const body = await r.json();
    $("action-reply").textContent = `${name}: HTTP ${r.status} — ${body.ok || body.error}`;
  } catch (e) { $("action-reply").textContent = `${name}: no answer`; }
  pollState();
}

$("token").value = sessionStorage.getItem("hybridtest-token") || "";
for (const b of ["hold", "continue", "stop"]) $(b).addEventListener("click", () => act(b));
pollState().then(pollSeries);
setInterval(pollState, 500);
setInterval(pollSeries, 1000);
