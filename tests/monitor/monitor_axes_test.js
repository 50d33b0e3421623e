// The monitor page's axis helpers (src/hybridtest/monitor/web/monitor.js) under node: labels
// below zero keep their minus sign (issue 38: "2,500, 5,000" was shown for −2,500, −5,000),
// ticks sit at 1–2–5 steps covering the range, and the axis is wide enough for its longest
// label. Run by monitor_axes_test.cc (skipped without node). Exits 1 on the first failure.
"use strict";
const assert = require("node:assert/strict");
const path = require("node:path");
const { niceTicks, tickLabel, axisWidth, niceStep } = require(path.join(process.argv[2], "src/hybridtest/monitor/web/monitor.js"));

const MINUS = "\u2212";
// Force axes of the blade's actuators, down to −5 kN.
const ticks = niceTicks(-5000, 1500, 5);
const step = niceStep(6500, 5);
assert.equal(step, 2000);
assert.deepEqual(ticks, [-4000, -2000, 0]);
assert.deepEqual(ticks.map((v) => tickLabel(v, step)), [MINUS + "4,000", MINUS + "2,000", "0"]);
assert.equal(tickLabel(-2500, 500), MINUS + "2,500");
assert.equal(tickLabel(-5000, 500), MINUS + "5,000");
// Small displacements: decimals from the step, the sign kept, no "−0".
assert.equal(tickLabel(-0.005, 0.005), MINUS + "0.005");
assert.equal(tickLabel(-0.0123, 0.01), MINUS + "0.01");
assert.equal(tickLabel(-1e-15, 0.005), "0.000");
assert.equal(tickLabel(0.02, 0.005), "0.020");
assert.equal(tickLabel(-0.0025, 0.0025), MINUS + "0.0025");  // never rounded to "−0.003"
assert.equal(tickLabel(-7.5, 2.5), MINUS + "7.5");
// Every tick is inside the range and a multiple of the step; the range is covered to a step.
for (const [lo, hi] of [[-0.0123, 0.004], [-45.8, 53.6], [0.02, 0.0232], [-3000, 3000]]) {
  const t = niceTicks(lo, hi, 5), s = niceStep(hi - lo, 5);
  assert.ok(t.length >= 2, `${lo}..${hi}: ${t}`);
  for (const v of t) {
    assert.ok(v >= lo - 1e-12 && v <= hi + 1e-12, `${v} outside ${lo}..${hi}`);
    assert.ok(Math.abs(v / s - Math.round(v / s)) < 1e-6, `${v} not a multiple of ${s}`);
  }
  assert.ok(t[0] - lo < s + 1e-12 && hi - t[t.length - 1] < s + 1e-12);
}
// The axis holds its longest label (7 px a character), never narrower than 40 px.
assert.ok(axisWidth([MINUS + "4,000", MINUS + "2,000", "0"]) >= 6 * 7);
assert.ok(axisWidth([MINUS + "0.00012"]) > axisWidth(["0.1"]));
assert.equal(axisWidth(null), 40);
console.log("monitor axes: ok");
