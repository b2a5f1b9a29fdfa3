// The "Run on the motor" panel: the committed document run from rest on its [motor] (the server's worker process,
// off the drag path), its speed against time with the start-up time to 95 % and the steady mean speed, δ beside the
// kinetostatic estimate, the motor's torque and current, and where a run that stops stopped. Methods of the Designer
// (mixed in by designer.js; one part of designer.js: see assembly.py).

import { formatNumber, html, svg, setText, sampleOfInput } from "./util.js";
import { decodeArrays } from "./channel.js";

// the share of the steady mean speed that ends the start-up (the engine's STARTUP_SHARE)
export const STARTUP_SHARE = 0.95;
// at most this many (t, value) pairs of a series are drawn: longer runs are drawn by their min and max per bucket
export const PLOT_BUCKETS = 600;
// the run's time (s) a mechanism that does not turn fully gets unless the user types another (it has no steady state)
export const MOTOR_DEFAULT_TIME = 5;
// the SI unit of a [motor] key given as a bare number
export const MOTOR_SI_UNITS = {
  torque: "N·m", force: "N", stall_torque: "N·m", stall_current: "A", torque_constant: "N·m/A", resistance: "Ω",
  voltage: "V", breakdown_torque: "N·m", pressure: "Pa", area: "m²", flow: "m³/s", rotor_inertia: "kg·m²",
  flywheel_inertia: "kg·m²",
};

export class MotorPart {
  buildMotorPanel(ui) {
    ui.motorDescription = html("div", { class: "asd-muted asd-motor-description", testid: "motor-description" });
    ui.motorHint = html("div", { class: "asd-motor-hint", testid: "motor-hint", hidden: true });
    ui.motorRun = html("button", { type: "button", testid: "motor-run", text: "Run from rest" });
    ui.motorCancel = html("button", { type: "button", testid: "motor-cancel", text: "Cancel", disabled: true });
    ui.motorTime = html("input", { type: "number", testid: "motor-time", min: 0, step: "any", placeholder: "to steady state", class: "asd-motor-time" });
    ui.motorTimeNote = html("div", { class: "asd-muted", testid: "motor-time-note", hidden: true,
      text: "the mechanism does not turn fully: it has no steady state, so it runs for the time given and stops where it can go no further" });
    ui.motorTime.addEventListener("input", () => { this.motor.timeTyped = ui.motorTime.value.trim() !== ""; });
    ui.motorStatus = html("div", { class: "asd-muted", testid: "motor-status" });
    ui.motorStale = html("div", { class: "asd-motor-stale", testid: "motor-stale", hidden: true,
      text: "the design changed since this run: run it again" });
    ui.motorStop = html("div", { class: "asd-motor-stop", testid: "motor-stop", hidden: true });
    ui.motorShowStop = html("button", { type: "button", testid: "motor-show-stop", text: "Show where", hidden: true,
      title: "move the mechanism to the input where the run stopped" });
    ui.motorSpeedPlot = svg("svg", { class: "asd-plot", testid: "motor-speed-plot", viewBox: "0 0 300 150" });
    ui.motorTorquePlot = svg("svg", { class: "asd-plot", testid: "motor-torque-plot", viewBox: "0 0 300 120" });
    ui.motorNumbers = html("div", { class: "asd-kv", testid: "motor-numbers" });
    ui.motorRun.addEventListener("click", () => this.startMotorRun());
    ui.motorCancel.addEventListener("click", () => this.request("motor_cancel"));
    ui.motorShowStop.addEventListener("click", () => this.showMotorStop());
    ui.motorPanel = this.section("Run on the motor", "motor-panel", ui.motorDescription, ui.motorHint,
      html("div", { class: "asd-row" }, ui.motorRun, ui.motorCancel, html("label", {}, " for ", ui.motorTime, " s")),
      ui.motorTimeNote, ui.motorStatus, ui.motorStale,
      html("div", { class: "asd-row" }, ui.motorStop, ui.motorShowStop), ui.motorNumbers, ui.motorSpeedPlot,
      ui.motorTorquePlot);
    this.motor = { running: false, status: null, message: "", summary: null, stop: null, arrays: {}, toml: null, stale: false };
    return ui.motorPanel;
  }

  startMotorRun() {
    this.motor = { ...this.motor, running: true, status: "starting", message: "starting the run…",
      toml: this.committed ? this.committed.message.toml : null };
    this.drawMotor();
    const time = Number(this.ui.motorTime.value);
    this.request("motor_start", this.ui.motorTime.value.trim() !== "" && time > 0 ? { time } : {});
  }

  onMotorMessage(message, buffers, request) {
    const type = message.type;
    if (type === "motor_started") {
      Object.assign(this.motor, { running: true, status: "running", message: "running from rest…", job: message.job });
    } else if (type === "motor_done") {
      const { arrays } = decodeArrays(message, buffers);
      Object.assign(this.motor, { running: false, status: message.status, message: message.message || "",
        summary: message.summary || null, stop: message.stop || null, arrays, elapsed: message.elapsed });
    } else if (type === "refused" && request && request.message.op === "motor_start") {
      Object.assign(this.motor, { running: false, status: "refused", message: message.message || "" });
    }
    this.drawMotor();
  }

  // what the tests read (window.__assur.motor): the run's status, summary and stop, and whether the design changed
  motorState() {
    const m = this.motor;
    return { running: m.running, status: m.status, message: m.message, summary: m.summary, stop: m.stop,
      stale: this.motorStale(), samples: m.arrays && m.arrays.t ? m.arrays.t.length : 0 };
  }

  motorStale() {
    const m = this.motor;
    return Boolean(m.summary && m.toml && this.committed && this.committed.message.toml !== m.toml);
  }

  motorLinear() {
    // the kind of the cycle's input (a run's summary gives a domain for a crank that cannot turn fully as well)
    return this.isLinearInput();
  }

  drawMotor() {
    const snapshot = this.snapshot;
    if (!snapshot || !this.ui.motorPanel) return;
    const model = snapshot.model;
    const table = model.motor;
    const hint = model.motor_hint;
    const hasDriver = (model.drivers || []).length > 0;
    this.ui.motorPanel.hidden = !table && !hint && !hasDriver;
    this.ui.motorHint.hidden = !hint;
    if (hint) {
      this.ui.motorHint.replaceChildren(html("div", { testid: "motor-hint-message", text: hint.message }),
        html("pre", { class: "asd-motor-example", testid: "motor-hint-example", text: hint.example || "" }));
      this.ui.motorHint.title = hint.where ? String(hint.where) : "";
    }
    setText(this.ui.motorDescription, table ? this.motorDescription(table) : "");
    const m = this.motor;
    this.global.motor = this.motorState();
    const cycle = snapshot.cycle;
    const full = Boolean(cycle && cycle.turn && cycle.assembled === cycle.n);
    if (!m.timeTyped) this.ui.motorTime.value = full || !cycle ? "" : String(MOTOR_DEFAULT_TIME);
    this.ui.motorTimeNote.hidden = full || !table || !cycle;
    this.ui.motorRun.disabled = m.running || !table || !snapshot.cycle;
    this.ui.motorCancel.disabled = !m.running;
    const took = m.status === "finished" && Number.isFinite(m.elapsed) ? ` (${formatNumber(m.elapsed)} s)` : "";
    setText(this.ui.motorStatus, m.status ? `${m.status}${took}: ${m.message}` : "");
    this.ui.motorStale.hidden = !this.motorStale();
    const stopped = m.stop && m.stop.kind !== "steady";
    this.ui.motorStop.hidden = !stopped;
    this.ui.motorShowStop.hidden = !stopped || !Number.isFinite(m.stop.q) || !snapshot.arrays.q;
    setText(this.ui.motorStop, stopped ? `stopped (${m.stop.kind}) at t = ${formatNumber(m.stop.t)} s, input `
      + `${formatNumber(this.converter.input(m.stop.q, this.motorLinear()))} ${this.converter.inputLabel(this.motorLinear())}` : "");
    this.drawMotorNumbers();
    this.drawMotorPlots();
  }

  // the motor's keys as the file gives them: a bare number is SI, a speed's in the file's angle unit per second and a
  // lead in its length unit (docs/format.md, Motors)
  motorDescription(table) {
    const { kind, driver, ...keys } = table;
    const units = (this.snapshot && this.snapshot.message.units) || {};
    const unitOf = (key) => MOTOR_SI_UNITS[key] || (key.endsWith("_speed") ? `${units.angle || "deg"}/s` : "")
      || (key === "lead" ? units.length || "m" : "");
    const text = (key, value) => (Array.isArray(value) ? `[${value.join(", ")}]`
      : typeof value === "number" && unitOf(key) ? `${value} ${unitOf(key)}` : String(value));
    const parts = Object.entries(keys).map(([key, value]) => `${key.replace(/_/g, " ")} ${text(key, value)}`);
    return `${kind || "motor"} on ${driver || "the first driver"}: ${parts.join(" · ")}`;
  }

  drawMotorNumbers() {
    const s = this.motor.summary;
    const rows = [];
    if (s) {
      const convert = this.converter;
      const linear = this.motorLinear();
      const speed = (v) => (linear ? convert.length(v) : convert.speed(v));
      const speedUnit = linear ? `${convert.lengthLabel}/s` : convert.speedLabel;
      const est = s.kinetostatic || null;
      const effortUnit = linear ? "N" : "N·m";
      const add = (testid, key, value, unit = "", title = "") => rows.push(html("div", { class: "asd-row", title },
        html("span", { class: "asd-key", text: `${key}: ` }), html("span", { testid, "data-si": value ?? "", text: formatNumber(value ?? NaN) }),
        unit ? html("span", { class: "asd-unit", text: unit }) : null));
      add("motor-startup", "start-up time (to 95 %)", s.startup_time, "s", "the first time the speed reaches 95 % of the steady mean speed");
      const mean = Number.isFinite(s.mean_speed) ? speed(s.mean_speed) : NaN;
      add("motor-mean-speed", s.steady ? "steady mean speed" : "mean speed of the last turn", mean, speedUnit);
      add("motor-delta", "speed fluctuation δ", s.delta, "", "(max − min) / mean speed over the last turn");
      if (est) {
        add("motor-delta-estimate", "kinetostatic estimate of δ", est.delta_estimate, "", "ΔE / (I·ω̄²) at the steady mean speed");
        add("motor-delta-difference", "simulated δ − estimate", est.difference);
      }
      add("motor-torque-peak", `peak motor ${linear ? "force" : "torque"}`, s.motor_torque_peak, effortUnit);
      if (s.current_peak !== undefined) add("motor-current-peak", "peak current", s.current_peak, "A");
      add("motor-power-peak", "peak power", s.power_peak, "W");
      add("motor-turns", linear ? "strokes" : "turns", s.turns);
      add("motor-time", "simulated time", s.time, "s");
    }
    this.ui.motorNumbers.replaceChildren(...rows);
    // the mean speed is drawn in the unit on display: a unit change redraws the rows
  }

  drawMotorPlots() {
    const a = this.motor.arrays || {};
    const s = this.motor.summary;
    const show = Boolean(a.t && a.speed && s);
    this.ui.motorSpeedPlot.style.display = show ? "" : "none";
    this.ui.motorTorquePlot.style.display = show && a.motor_torque ? "" : "none";
    if (!show) return;
    const linear = this.motorLinear();
    const convert = this.converter;
    const speed = (v) => (linear ? convert.length(v) : convert.speed(v));
    const speedUnit = linear ? `${convert.lengthLabel}/s` : convert.speedLabel;
    const marks = { hlines: [], vlines: [] };
    if (Number.isFinite(s.mean_speed)) {
      marks.hlines.push({ y: speed(s.mean_speed), cls: "asd-motor-mean", testid: "motor-mean-line" });
      if (s.steady) marks.hlines.push({ y: speed(STARTUP_SHARE * s.mean_speed), cls: "asd-motor-share", testid: "motor-share-line" });
    }
    if (Number.isFinite(s.startup_time)) marks.vlines.push({ x: s.startup_time, cls: "asd-motor-startup", testid: "motor-startup-line" });
    const stop = this.motor.stop;
    if (stop && stop.kind !== "steady" && Number.isFinite(stop.t)) marks.vlines.push({ x: stop.t, cls: "asd-motor-stopped", testid: "motor-stop-line" });
    this.timePlot(this.ui.motorSpeedPlot, a.t, [{ ys: Array.from(a.speed, speed), cls: "asd-series-speed", label: "speed", unit: speedUnit, testid: "motor-speed-line" }], marks, 300, 150);
    if (a.motor_torque) {
      const series = [{ ys: Array.from(a.motor_torque), cls: "asd-series-torque", label: linear ? "motor force" : "motor torque", unit: linear ? "N" : "N·m", testid: "motor-torque-line" }];
      if (a.current) series.push({ ys: Array.from(a.current), cls: "asd-series-current", label: "current", unit: "A", testid: "motor-current-line" });
      this.timePlot(this.ui.motorTorquePlot, a.t, series, { hlines: [], vlines: [] }, 300, 120);
    }
  }

  // a plot against time (s) of series each scaled to its own range, with horizontal marks in the first series' unit and
  // vertical marks at given times; long runs are drawn by each bucket's min and max (the extremes stay visible)
  timePlot(target, t, series, marks, width, height) {
    const margin = { left: 40, right: series.length > 1 ? 40 : 8, top: 16, bottom: 24 };
    const bottom = height - margin.bottom;
    const t0 = t[0]; const t1 = t[t.length - 1];
    const toX = (x) => margin.left + ((x - t0) / (t1 - t0 || 1)) * (width - margin.left - margin.right);
    const children = [svg("rect", { class: "asd-plot-frame", x: margin.left, y: margin.top, width: width - margin.left - margin.right, height: height - margin.top - margin.bottom })];
    const tick = (axis, value, x, y, anchor, cls = "") => svg("text", { class: `asd-plot-tick ${cls}`, x, y, "text-anchor": anchor, "data-axis": axis, "data-value": value, text: formatNumber(value) });
    [[t0, "start"], [(t0 + t1) / 2, "middle"], [t1, "end"]].forEach(([value, anchor]) => {
      children.push(svg("line", { class: "asd-plot-grid", x1: toX(value), x2: toX(value), y1: bottom, y2: bottom + 3 }));
      children.push(tick("x", value, toX(value), bottom + 12, anchor));
    });
    series.forEach((serie, index) => {
      const finite = serie.ys.filter(Number.isFinite);
      const extra = index === 0 ? marks.hlines.map((mark) => mark.y) : [];
      const y0 = Math.min(0, ...finite, ...extra); const y1 = Math.max(0, ...finite, ...extra);
      const toY = (y) => bottom - ((y - y0) / (y1 - y0 || 1)) * (height - margin.top - margin.bottom);
      const d = envelopePath(t, serie.ys, toX, toY);
      children.push(svg("path", { class: `asd-plot-line ${serie.cls}`, d, testid: serie.testid }));
      children.push(svg("text", { class: `asd-plot-label ${serie.cls}`, x: margin.left + 2 + index * ((width - margin.left) / 2), y: 11, text: `${serie.label} max ${formatNumber(finite.length ? Math.max(...finite.map(Math.abs)) : NaN)} ${serie.unit}` }));
      if (index === 0) {
        for (const mark of marks.hlines) children.push(svg("line", { class: `asd-plot-mark ${mark.cls}`, testid: mark.testid, "data-value": mark.y, x1: margin.left, x2: width - margin.right, y1: toY(mark.y), y2: toY(mark.y) }));
      }
      if (index < 2 && finite.length) {
        const left = index === 0;
        const x = left ? margin.left - 3 : width - margin.right + 3;
        for (const value of [...new Set([y0, 0, y1])].filter((v) => v === 0 || Math.abs(toY(v) - toY(0)) > 8)) {
          children.push(tick(`y${index}`, value, x, toY(value) + 3, left ? "end" : "start", serie.cls));
        }
      }
    });
    for (const mark of marks.vlines) children.push(svg("line", { class: `asd-plot-mark ${mark.cls}`, testid: mark.testid, "data-value": mark.x, x1: toX(mark.x), x2: toX(mark.x), y1: margin.top, y2: bottom }));
    children.push(svg("text", { class: "asd-plot-axis", x: width - margin.right, y: height - 1, "text-anchor": "end", text: "time (s)" }));
    target.replaceChildren(...children);
  }

  // the scrub bar to the sample nearest the input where the run stopped
  showMotorStop() {
    const stop = this.motor.stop;
    const q = this.snapshot && this.snapshot.arrays.q;
    if (!stop || !q || !Number.isFinite(stop.q)) return;
    this.setSample(sampleOfInput(q, stop.q, this.motorLinear()));
  }
}

// an SVG path of (t, y) samples: every sample when there are few, else each bucket's first, min, max and last samples
// in time order (so that a fluctuation faster than the pixels keeps its extremes)
export function envelopePath(t, ys, toX, toY) {
  const n = Math.min(t.length, ys.length);
  const picked = [];
  if (n <= 2 * PLOT_BUCKETS) {
    for (let k = 0; k < n; k += 1) picked.push(k);
  } else {
    for (let b = 0; b < PLOT_BUCKETS; b += 1) {
      const start = Math.floor((b * n) / PLOT_BUCKETS); const end = Math.floor(((b + 1) * n) / PLOT_BUCKETS);
      let low = start; let high = start;
      for (let k = start; k < end; k += 1) { if (ys[k] < ys[low]) low = k; if (ys[k] > ys[high]) high = k; }
      picked.push(...[...new Set([start, low, high, end - 1])].sort((p, q) => p - q));
    }
  }
  let d = ""; let drawing = false;
  for (const k of picked) {
    if (!Number.isFinite(ys[k])) { drawing = false; continue; }
    d += `${drawing ? "L" : "M"}${toX(t[k]).toFixed(2)},${toY(ys[k]).toFixed(2)}`;
    drawing = true;
  }
  return d;
}
