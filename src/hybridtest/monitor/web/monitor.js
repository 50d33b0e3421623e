// The monitor's page: polls /api/state (twice a second) and /api/series (once a second) and
// draws the state, one meter group per actuator and the scopes. Time plots use uPlot when the
// build bundled it, else a plain canvas; the force–displacement loops are always on a canvas.
// Operator actions are POSTs with the token as a bearer token.
// The axis helpers (niceTicks, tickLabel, axisWidth) are pure and exported for node's test
// (tests/monitor/monitor_axes_test.js); everything else runs only in a browser.
"use strict";
const fmt = (v, digits = 4) => (v === null || v === undefined || Number.isNaN(v)) ? "–" : Number(v).toPrecision(digits);

function duration(s) {
  if (s === null || s === undefined || s < 0) return "–";
  if (s < 1) return (s * 1000).toFixed(0) + " ms";
  if (s < 60) return s.toFixed(1) + " s";
  const m = Math.floor(s / 60);
  if (m < 60) return m + " min " + Math.floor(s % 60) + " s";
  return Math.floor(m / 60) + " h " + (m % 60) + " min";
}

// ---- axes: ticks at 1, 2, 5 × 10^k, labels that keep their sign, an axis wide enough ----
function niceStep(span, count) {
  const raw = span / Math.max(1, count);
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
  return 10 * p;
}

// About `count` ticks covering [lo, hi] (lo < hi), at multiples of a 1–2–5 step.
function niceTicks(lo, hi, count = 5) {
  if (!Number.isFinite(lo) || !Number.isFinite(hi) || hi <= lo) return [];
  const step = niceStep(hi - lo, count);
  const ticks = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
    ticks.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  }
  return ticks;
}

// A tick's label: as many decimals as the step needs, thousands grouped, and a minus sign
// (U+2212) that is never dropped: "−2,500", "−0.005", "0".
function tickLabel(v, step) {
  let decimals = 0;  // as many as the step needs to be exact: 0.0025 → 4
  const scaled = (d) => step * Math.pow(10, d);
  while (step > 0 && decimals < 12 && Math.abs(Math.round(scaled(decimals)) - scaled(decimals)) > 1e-6 * scaled(decimals)) ++decimals;
  const text = Math.abs(v).toLocaleString("en-US", { minimumFractionDigits: decimals, maximumFractionDigits: decimals });
  const zero = Number(Math.abs(v).toFixed(decimals)) === 0;
  return (v < 0 && !zero ? "\u2212" : "") + text;
}

// Pixels an axis needs for `labels` at `charPx` per character, with room for the tick marks.
function axisWidth(labels, charPx = 7) {
  const longest = (labels || []).reduce((n, l) => Math.max(n, String(l === null ? "" : l).length), 0);
  return Math.max(40, Math.ceil(longest * charPx) + 18);
}

if (typeof module !== "undefined") module.exports = { niceTicks, tickLabel, axisWidth, niceStep };

// ---- plots: uPlot for time series when bundled, else (and for the x–y loops) a canvas ----
const colours = ["#1565c0", "#c62828", "#2e7d32", "#6a1b9a", "#ef6c00", "#00838f", "#5d4037", "#ad1457"];
const finiteOf = (a) => (a || []).filter((v) => v !== null && Number.isFinite(v));

class CanvasPlot {
  // names: one per series; units: [x unit, y unit]; xy: each series has its own x.
  constructor(el, names, units, xy) {
    Object.assign(this, { names, units, xy });
    this.canvas = document.createElement("canvas");
    el.appendChild(this.canvas);
  }
  // time plots: [x, y1, y2, ...]; xy plots: [[x1, y1], [x2, y2], ...]
  setData(data) {
    const pairs = this.xy ? data : data.slice(1).map((y) => [data[0], y]);
    const c = this.canvas, w = c.clientWidth || 480, h = c.clientHeight || 160;
    c.width = w; c.height = h;
    const g = c.getContext("2d");
    g.clearRect(0, 0, w, h);
    g.font = "11px sans-serif";
    const xs = finiteOf([].concat(...pairs.map((p) => p[0])));
    const ys = finiteOf([].concat(...pairs.map((p) => p[1])));
    if (xs.length < 2 || ys.length < 1) { g.fillStyle = "#333"; g.fillText("no data yet", 10, 20); return; }
    let [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
    if (x1 === x0) { x0 -= 1; x1 += 1; }
    if (y1 === y0) { y0 -= 1; y1 += 1; }
    c.dataset.xRange = `${x0} ${x1}`;  // what the axes span, for a test to read from the page
    c.dataset.yRange = `${y0} ${y1}`;
    const yTicks = niceTicks(y0, y1, 5), xTicks = niceTicks(x0, x1, 6);
    const yStep = niceStep(y1 - y0, 5), xStep = niceStep(x1 - x0, 6);
    const yLabels = yTicks.map((v) => tickLabel(v, yStep));
    const L = axisWidth(yLabels) + 14, R = 12, T = 22, B = 36;
    const px = (x) => L + (x - x0) / (x1 - x0) * (w - L - R);
    const py = (y) => h - B - (y - y0) / (y1 - y0) * (h - T - B);
    g.strokeStyle = "#999"; g.strokeRect(L, T, w - L - R, h - T - B);
    g.fillStyle = "#333"; g.strokeStyle = "#ddd";
    g.textAlign = "right"; g.textBaseline = "middle";
    yTicks.forEach((v, i) => {
      g.beginPath(); g.moveTo(L, py(v)); g.lineTo(w - R, py(v)); g.stroke();
      g.fillText(yLabels[i], L - 4, py(v));
    });
    g.textAlign = "center"; g.textBaseline = "top";
    xTicks.forEach((v) => {
      g.beginPath(); g.moveTo(px(v), T); g.lineTo(px(v), h - B); g.stroke();
      g.fillText(tickLabel(v, xStep), px(v), h - B + 3);
    });
    g.fillText(this.units[0], L + (w - L - R) / 2, h - 14);
    g.save(); g.translate(10, T + (h - T - B) / 2); g.rotate(-Math.PI / 2); g.fillText(this.units[1], 0, -6); g.restore();
    g.textAlign = "left"; g.textBaseline = "alphabetic";
    pairs.forEach(([xv, yv], s) => {
      g.strokeStyle = colours[s % colours.length]; g.beginPath();
      let pen = false;
      for (let i = 0; i < (xv || []).length; ++i) {
        const x = xv[i], y = yv ? yv[i] : null;
        if (x === null || y === null || !Number.isFinite(x) || !Number.isFinite(y)) { pen = false; continue; }
        if (pen) g.lineTo(px(x), py(y)); else g.moveTo(px(x), py(y));
        pen = true;
      }
      g.stroke();
      g.fillStyle = colours[s % colours.length];
      g.fillText(this.names[s] || "", L + 8 + 150 * s, 14);
    });
  }
}

function makePlot(id, names, units, xy) {
  const el = document.getElementById(id);
  el.innerHTML = "";
  if (window.uPlot && !xy) {
    const yValues = (u, splits, axis, space, incr) => splits.map((v) => tickLabel(v, incr));
    const opts = { width: Math.max(el.clientWidth, 280), height: 170, scales: { x: { time: false } },
      axes: [{ label: units[0] }, { label: units[1], values: yValues, size: (u, values) => axisWidth(values) }],
      series: [{ label: units[0] }].concat(names.map((n, i) => ({ label: n, stroke: colours[i % colours.length], spanGaps: false }))) };
    return new window.uPlot(opts, [[]].concat(names.map(() => [])), el);
  }
  return new CanvasPlot(el, names, units, xy);
}

if (typeof document !== "undefined") {
  const $ = (id) => document.getElementById(id);
  const state = { slotNames: [], actuators: [], series: null, generation: -1, since: -1, plots: {}, slots: 0, count: 0 };
  const actName = (a) => (state.actuators[a] && state.actuators[a].name) || "actuator " + (a + 1);

  const setupPlots = (series) => {
    state.slots = series.slots; state.count = series.actuators;
    const slotNames = [...Array(series.slots).keys()].map((s) => state.slotNames[s] || "slot " + (s + 1));
    const act = [...Array(series.actuators).keys()];
    state.plots.d = makePlot("scope-d", slotNames.map((n) => "d " + n), ["t [s]", "d [m]"], false);
    state.plots.r = makePlot("scope-r", slotNames.map((n) => "r " + n), ["t [s]", "r [N]"], false);
    state.plots.track = makePlot("scope-track", [].concat(...act.map((a) => ["command " + actName(a), "position " + actName(a)])), ["t [s]", "position [m]"], false);
    state.plots.force = makePlot("scope-force", act.map((a) => "force " + actName(a)), ["t [s]", "force [N]"], false);
    state.plots.loop = makePlot("scope-loop", act.map((a) => actName(a)), ["displacement from p0 [m]", "force [N]"], true);
    $("plot-note").textContent = window.uPlot ? "Plots: uPlot (bundled in the binary)."
      : "uPlot is not bundled with this build: plain canvas plots.";
  };

  const append = (target, columns, reset) => {
    if (reset || !target) return JSON.parse(JSON.stringify(columns));
    for (const k of Object.keys(columns)) target[k] = (target[k] || []).concat(columns[k]);
    return target;
  };

  const drawScopes = () => {
    const c = state.series;
    if (!c || !state.plots.d) return;
    const idx = (n) => [...Array(n).keys()];
    state.plots.d.setData([c.t].concat(idx(state.slots).map((s) => c["d" + s])));
    state.plots.r.setData([c.t].concat(idx(state.slots).map((s) => c["r" + s])));
    state.plots.track.setData([c.t].concat(...idx(state.count).map((a) => [c["command" + a], c["position" + a]])));
    state.plots.force.setData([c.t].concat(idx(state.count).map((a) => c["force" + a])));
    // Force against each actuator's own displacement from its own p0.
    state.plots.loop.setData(idx(state.count).map((a) => {
      const p0 = (state.actuators[a] && state.actuators[a].p0) || 0;
      return [(c["position" + a] || []).map((v) => v === null ? null : v - p0), c["force" + a]];
    }));
  };

  const pollSeries = async () => {
    try {
      const r = await fetch(`/api/series?since=${state.since}&generation=${state.generation}`);
      const s = await r.json();
      if (!state.plots.d || s.slots !== state.slots || s.actuators !== state.count) setupPlots(s);
      state.series = append(state.series, s.columns, s.reset);
      state.generation = s.generation;
      const seq = state.series.seq;
      if (seq && seq.length) state.since = seq[seq.length - 1];
      drawScopes();
    } catch (e) { /* the state poll reports the connection */ }
  };

  // ---- state, identity, meters ----
  const gauge = (label, fraction, level, text) => {
    const pct = Math.min(100, Math.max(0, 100 * (fraction || 0)));
    return `<div class="gauge ${level}"><span>${label}</span><div class="track"><div class="fill" style="width:${pct}%"></div></div>` +
           `<span>${text} (${pct.toFixed(0)} %)</span></div>`;
  };

  const renderMeters = (actuators) => {
    if (!actuators.length) return;
    $("meters").innerHTML = actuators.map((a) => {
      const l = a.limits, m = a.margin || { force_fraction: 0, stroke_fraction: 0, level: "normal" };
      const lim = l ? `stroke ${fmt(l.stroke_min, 3)} … ${fmt(l.stroke_max, 3)} m, max increment ${fmt(l.max_increment, 3)} m, ` +
                      `force soft ${fmt(l.force_soft, 4)} N, hard ${fmt(l.force_hard, 4)} N` : "no limits known";
      const strokeFrac = (v) => l && v !== null ? Math.abs(v - (l.stroke_max + l.stroke_min) / 2) / ((l.stroke_max - l.stroke_min) / 2) : 0;
      const of = a.slots.length > 1 ? `actuator ${a.index + 1} of ${a.substructure} (slots ${a.slots.join(", ")})`
        : a.name === a.substructure ? "" : `of ${a.substructure}`;
      return `<div class="meter"><h3>Actuator ${a.name} <small>${of}</small> — <span class="level ${m.level}">${m.level}</span></h3>` +
        `<p class="hint">p0 ${a.p0 === null ? "unknown" : fmt(a.p0) + " m"}; displacement from p0 ${fmt(a.displacement)} m</p>` +
        gauge("command", strokeFrac(a.command), m.level, `${fmt(a.command)} m`) +
        gauge("position", m.stroke_fraction, m.level, `${fmt(a.position)} m`) +
        gauge("force", m.force_fraction, m.level, `${fmt(a.force)} N of ${l ? fmt(l.force_hard, 4) : "–"} N`) +
        `<p class="hint">Actuator ${a.name} force ${fmt(a.force)} N; limit (force_hard) ${l ? fmt(l.force_hard, 4) : "–"} N. Limits: ${lim}.</p></div>`;
    }).join("");
  };

  const us = (v) => v === null || v === undefined ? "–" : (1e6 * v).toFixed(0) + " µs";
  const renderRealTime = (rt) => {
    if (!rt || !rt.available) {
      $("realtime").innerHTML = rt && rt.paced ? "<tr><td>a real-time run: its statistics are shown when it has ended (a followed journal)</td></tr>"
        : "<tr><td>not a real-time run</td></tr>";
      return;
    }
    const row = (k, v) => `<tr><th>${k}</th><td>${v}</td></tr>`;
    const pct = (v) => v === null || v === undefined ? "–" : fmt(v, 3) + " %";
    let html = row("source", rt.source === "live" ? "live, from the paced loop" : "as the run recorded it") +
      row("clock, tick", `${rt.clock || "–"}, ${us(rt.tick_s)}`) +
      row("ticks", rt.ticks === null ? "–" : rt.ticks) +
      row("deadline misses", `${rt.misses === null ? "–" : rt.misses} (in a row now ${rt.misses_in_a_row === null || rt.misses_in_a_row === undefined ? "–" : rt.misses_in_a_row}, ` +
          `most in a row ${rt.max_consecutive_misses === null ? "–" : rt.max_consecutive_misses}; holds after ${rt.hold_after_misses || "never"})`) +
      row("overruns", rt.overruns === null ? "–" : rt.overruns) +
      row("lateness p50 / p99 / max", rt.late_s ? `${us(rt.late_s.p50)} / ${us(rt.late_s.p99)} / ${us(rt.late_s.max)}` : "–") +
      row("compute p50 / p99 / max", rt.compute_s ? `${us(rt.compute_s.p50)} / ${us(rt.compute_s.p99)} / ${us(rt.compute_s.max)}` : "–") +
      row("J1 tracking delay", rt.J1_ms === null || rt.J1_ms === undefined ? "at the end of the run" : fmt(rt.J1_ms, 3) + " ms") +
      row("J2 RMS tracking error", pct(rt.J2)) + row("J3 peak tracking error", pct(rt.J3));
    const estimate = (label, c) => {
      const delay = c.estimated_delay_s !== undefined ? c.estimated_delay_s : c.delay_s;
      const more = c.a0 !== undefined ? `; a0 ${fmt(c.a0, 4)}, a1 ${fmt(1e3 * c.a1_s, 4)} ms, a2 ${fmt(c.a2_s2, 3)} s²` : "";
      return row(label, `delay estimate ${delay === null || delay === undefined ? "–" : fmt(1e3 * delay, 4) + " ms"}${more}`);
    };
    // One row per compensated actuator (live: {name, delay_s}; recorded: the sidecar's).
    for (const [name, c] of Object.entries(rt.compensation || {})) {
      if (!Array.isArray(c.actuators)) { html += estimate(`compensator ${name}`, c); continue; }
      c.actuators.forEach((a, k) => { html += estimate(`compensator ${a.name || name + " actuator " + (k + 1)}`, a); });
    }
    $("realtime").innerHTML = html;
  };

  const render = (s) => {
    const badge = $("status");
    badge.textContent = s.status; badge.className = "badge " + s.status;
    document.title = `${s.status} — hybridtest monitor`;
    $("stop-panel").hidden = s.status !== "stopped";
    $("reason").textContent = s.reason;
    $("resume-command").textContent = s.resume_command || "(no journal: nothing to resume)";
    const id = s.identity;
    state.slotNames = s.slots.map((x) => x.name);
    state.actuators = s.actuators;
    const follow = id.mode === "follow";
    const ended = s.status === "finished" || s.status === "stopped";
    $("connection").textContent = !follow ? "live" : ended ? "a run that has ended, from its files (read-only)"
      : "following the run's files (read-only)";
    $("identity").innerHTML = [["config", id.config], ["model", id.model], ["specimen", id.specimen || "–"],
      ["bench", id.bench], ["command", id.command], ["journal", id.csv || "(none)"],
      ["monitor", follow ? "follows the journal" : "the run's own"]]
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
    renderRealTime(s.realtime);
    $("frames").textContent = s.frames;
    $("dropped").textContent = s.dropped_frames;
    const live = s.status === "running" || s.status === "holding" || s.status === "starting";
    for (const b of ["hold", "continue", "stop"]) $(b).disabled = !live || s.actions_policy === "read-only";
  };

  const pollState = async () => {
    try {
      const r = await fetch("/api/state");
      render(await r.json());
    } catch (e) {
      $("connection").textContent = "no connection to the run (ended, or the monitor stopped); the last state is shown";
    }
  };

  const act = async (name) => {
    const token = $("token").value;
    sessionStorage.setItem("hybridtest-token", token);
    const headers = token ? { Authorization: "Bearer " + token } : {};
    try {
      const r = await fetch("/api/" + name, { method: "POST", headers });
      const body = await r.json();
      $("action-reply").textContent = `${name}: HTTP ${r.status} — ${body.ok || body.error}`;
    } catch (e) { $("action-reply").textContent = `${name}: no answer`; }
    pollState();
  };

  $("token").value = sessionStorage.getItem("hybridtest-token") || "";
  for (const b of ["hold", "continue", "stop"]) $(b).addEventListener("click", () => act(b));
  pollState().then(pollSeries);
  setInterval(pollState, 500);
  setInterval(pollSeries, 1000);
}
