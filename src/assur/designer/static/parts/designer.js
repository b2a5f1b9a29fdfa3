// The browser front end of `assur design`: the entry part of one self-contained ES module.
//
// `render({model, el})` builds the whole designer inside `el` and returns a cleanup function. `model` is an
// anywidget-like interface: `model.send(content)` sends a request to the server and
// `model.on("msg:custom", (msg, buffers) => ...)` receives its answers (docs/designer.md, "Protocol").
// The model stays in SI (m, rad, s); the unit selects change the display only.
//
// This is the entry part; util.js, channel.js, canvas.js, gestures.js, panels.js, synthesis.js, motor.js and
// chooser.js hold the rest by concern.
// assembly.py joins them into the one module the page and the widget load (no build tool).

import { formatNumber, UnitConverter, html, setText, sampleOfInput, preferReadbackCanvases } from "./util.js";
import { messageType, decodeArrays, Snapshot, RequestChannel, shareCodec } from "./channel.js";
import { CanvasPart } from "./canvas.js";
import { GesturesPart } from "./gestures.js";
import { PanelsPart } from "./panels.js";
import { SynthesisPart } from "./synthesis.js";
import { MotorPart } from "./motor.js";
import { ChooserPart } from "./chooser.js";

// ---------------------------------------------------------------------------------------------------------
// The designer

const TOOLS = [
  ["select", "Select / drag"],
  ["add-point", "Add point"],
  ["add-link", "Add link"],
  ["add-slider", "Add slider"],
  ["add-driver", "Add driver"],
  ["delete", "Delete"],
];

class Designer {
  constructor(model, el) {
    this.model = model;
    this.el = el;
    this.uid = Math.random().toString(36).slice(2, 8);
    this.channel = new RequestChannel(model);
    this.snapshot = null;        // the result on display
    this.committed = null;       // the last committed result (the page returns to it after a refused commit)
    this.sample = 0;
    this.units = { length: "mm", angle: "deg", speed: "rpm" };
    this.unitsChosen = false;
    this.tool = "select";
    this.selectedPoint = null;
    this.selectedLink = null;
    this.gesture = null;         // a pointer gesture on the canvas: drag of a point, pan, click
    this.dragging = null;        // {point, to} while a point drag previews
    this.pendingLinkPoints = []; // clicks of the add-link tool
    this.pendingDriverPivot = null;
    this.view = null;            // {cx, cy, scale} world → screen
    this.size = { width: 800, height: 560 };
    this.showVectors = { vel: true, acc: true, ic: true, kennedy: false };
    this.playing = false;
    this.playClock = null;
    this.paramOverrides = {};
    this.synth = { running: false, status: null, evaluations: 0, best: null, elapsed: null, toml: null, targets: [] };
    this.refusal = "";
    this.pendingShare = null;    // a share fragment to load after the first result
    this.pendingRoundTrips = [];
    this.cleanups = [];
    this.global = this.publishGlobal();
    this.ui = this.buildLayout();
    this.listen();
    this.readShareFragment();
    this.channel.request("hello");
  }

  // ---- window.__assur: what the tests and the benchmark read -------------------------------------------
  publishGlobal() {
    const state = {
      ready: false, seq: 0, result: null, arrays: {}, sample: 0, units: this.units, refusal: "", history: null,
      synth: this.synth, errors: [], roundTrips: [], share: shareCodec,
    };
    window.__assur = state;
    return state;
  }

  reportError(error) {
    const message = error && error.message ? error.message : String(error);
    this.global.errors.push(message);
    setText(this.ui.status, `error: ${message}`);
  }

  // ---- layout -------------------------------------------------------------------------------------------
  buildLayout() {
    const ui = {};
    ui.toolButtons = {};
    const tools = html("div", { class: "asd-group asd-tools" }, TOOLS.map(([tool, label]) => {
      const button = html("button", { type: "button", testid: `tool-${tool}`, title: label, text: label });
      button.addEventListener("click", () => this.setTool(tool));
      ui.toolButtons[tool] = button;
      return button;
    }));
    ui.undo = html("button", { type: "button", testid: "undo", text: "Undo", title: "Undo (Ctrl+Z)", disabled: true });
    ui.redo = html("button", { type: "button", testid: "redo", text: "Redo", title: "Redo (Ctrl+Shift+Z)", disabled: true });
    ui.history = html("span", { class: "asd-history", testid: "history", text: "undo 0 · redo 0" });
    ui.save = html("button", { type: "button", testid: "save", text: "Save" });
    ui.saveFile = html("span", { class: "asd-save-file asd-muted", testid: "save-file" });
    ui.share = html("button", { type: "button", testid: "share", text: "Share link" });
    ui.shareUrl = html("input", { type: "text", testid: "share-url", readonly: true, placeholder: "share link", class: "asd-share-url" });
    ui.fit = html("button", { type: "button", testid: "fit", text: "Fit view" });
    ui.unitLength = this.unitSelect("unit-length", ["mm", "m"]);
    ui.unitAngle = this.unitSelect("unit-angle", ["deg", "rad"]);
    ui.unitSpeed = this.unitSelect("unit-speed", ["rpm", "rad/s"]);
    const toolbar = html("div", { class: "asd-toolbar" },
      tools,
      html("div", { class: "asd-group" }, ui.undo, ui.redo, ui.history),
      html("div", { class: "asd-group" }, ui.save, ui.saveFile, ui.share, ui.shareUrl),
      html("div", { class: "asd-group" },
        html("label", {}, "length ", ui.unitLength), html("label", {}, "angle ", ui.unitAngle),
        html("label", {}, "speed ", ui.unitSpeed), ui.fit));

    // the canvas and the 3D view
    ui.canvas = this.buildCanvas();
    ui.view3d = html("div", { class: "asd-view3d", testid: "view3d", hidden: true });
    ui.note = html("div", { class: "asd-note", testid: "pose-note" });
    const stage = html("div", { class: "asd-stage" }, ui.canvas.root, ui.view3d, ui.note);

    // the scrub bar
    ui.play = html("button", { type: "button", testid: "play", text: "▶ Play" });
    ui.scrub = html("input", { type: "range", testid: "scrub", min: 0, max: 0, value: 0, step: 1, class: "asd-scrub-input" });
    ui.deadCentres = html("div", { class: "asd-dead-centres", testid: "dead-centres" });
    ui.sampleIndex = html("span", { testid: "sample-index", text: "0" });
    ui.sampleCount = html("span", { class: "asd-muted", text: "/ 0" });
    const scrubBar = html("div", { class: "asd-scrub" }, ui.play,
      html("div", { class: "asd-scrub-track" }, ui.scrub, ui.deadCentres),
      html("span", { class: "asd-sample" }, "sample ", ui.sampleIndex, " ", ui.sampleCount));

    const main = html("div", { class: "asd-main" }, stage, scrubBar);
    const side = this.buildSidePanel(ui);
    ui.root = html("div", { class: "asd-root" }, toolbar, html("div", { class: "asd-body" }, main, side));
    this.el.replaceChildren(ui.root);
    return ui;
  }

  unitSelect(testid, options) {
    const select = html("select", { testid }, options.map((option) => html("option", { value: option, text: option })));
    return select;
  }

  // ---- events -------------------------------------------------------------------------------------------
  listen() {
    const ui = this.ui;
    const on = (target, type, handler, options) => {
      const wrapped = (event) => { try { handler(event); } catch (error) { this.reportError(error); } };
      target.addEventListener(type, wrapped, options);
      this.cleanups.push(() => target.removeEventListener(type, wrapped, options));
    };
    const onMessage = (message, buffers) => {
      try { this.onMessage(message, buffers); } catch (error) { this.reportError(error); }
    };
    this.model.on("msg:custom", onMessage);
    this.cleanups.push(() => { if (this.model.off) this.model.off("msg:custom", onMessage); });

    on(ui.undo, "click", () => this.request("undo"));
    on(ui.redo, "click", () => this.request("redo"));
    on(ui.save, "click", () => this.request("save"));
    on(ui.share, "click", () => this.makeShareLink());
    on(ui.fit, "click", () => { this.fitView(); this.drawScene(); });
    on(ui.unitLength, "change", () => this.setUnit("length", ui.unitLength.value));
    on(ui.unitAngle, "change", () => this.setUnit("angle", ui.unitAngle.value));
    on(ui.unitSpeed, "change", () => this.setUnit("speed", ui.unitSpeed.value));
    on(ui.scrub, "input", () => this.setSample(Number(ui.scrub.value)));
    on(ui.play, "click", () => this.togglePlay());
    on(ui.lockPoint, "change", () => this.commit([{ kind: "lock_point", point: this.selectedPoint, locked: ui.lockPoint.checked }]));
    on(ui.lockLink, "change", () => this.commit([{ kind: "lock_link", link: this.selectedLink, locked: ui.lockLink.checked }]));
    on(ui.synthClear, "click", () => { this.synth.targets = []; this.drawTargets(); });
    on(ui.synthRun, "click", () => this.startSynthesis());
    on(ui.synthCancel, "click", () => this.request("synth_cancel"));
    on(ui.synthInsert, "click", () => this.request("synth_insert"));

    const canvas = ui.canvas.root;
    on(canvas, "pointerdown", (event) => this.onPointerDown(event));
    on(canvas, "pointermove", (event) => this.onPointerMove(event));
    on(canvas, "pointerup", (event) => this.onPointerUp(event));
    on(canvas, "pointercancel", () => this.cancelGesture());
    on(canvas, "wheel", (event) => this.onWheel(event), { passive: false });
    on(document, "keydown", (event) => this.onKeyDown(event));

    if (typeof ResizeObserver !== "undefined") {
      const observer = new ResizeObserver(() => { try { this.onResize(); } catch (error) { this.reportError(error); } });
      observer.observe(canvas);
      this.cleanups.push(() => observer.disconnect());
    }
  }

  onKeyDown(event) {
    if (event.key === "Escape") {
      if (this.dragging || this.gesture) this.cancelGesture(true);
      this.pendingLinkPoints = [];
      this.pendingDriverPivot = null;
      this.drawPending();
      return;
    }
    const target = event.target;
    const typing = target && (target.tagName === "TEXTAREA" || (target.tagName === "INPUT" && !["checkbox", "range", "button"].includes(target.type)));
    if (typing || !(event.ctrlKey || event.metaKey)) return;
    const key = event.key.toLowerCase();
    if (key === "z" && event.shiftKey) { event.preventDefault(); this.request("redo"); }
    else if (key === "z") { event.preventDefault(); this.request("undo"); }
    else if (key === "y") { event.preventDefault(); this.request("redo"); }
  }

  // ---- requests -----------------------------------------------------------------------------------------
  request(op, fields = {}, startedAt = null) {
    if (op !== "hello" && op !== "preview") this.setRefusal("");
    return this.channel.request(op, fields, startedAt);
  }

  commit(edits) {
    this.request("commit", { edits });
  }

  // ---- messages from the server -------------------------------------------------------------------------
  onMessage(message, buffers) {
    const type = messageType(message);
    const request = this.channel.answer(message);
    if (type === "result") this.onResult(message, buffers, request);
    else if (type === "refused") this.onRefused(message, request);
    else if (type === "saved") setText(this.ui.status, message.message || `saved ${message.path}`);
    else if (type === "synth_started") this.onSynth({ running: true, status: "running", evaluations: 0, best: null, toml: null });
    else if (type === "synth_progress") this.onSynth({ evaluations: message.evaluations, best: message.best, elapsed: message.elapsed });
    else if (type === "synth_done") this.onSynth({ running: false, status: message.status, best: message.best ?? this.synth.best, toml: message.toml || null, evaluations: message.evaluations ?? this.synth.evaluations });
    else if (type === "motor_started" || type === "motor_done") this.onMotorMessage(message, buffers, request);
    else if (type === "assemblies") this.onAssemblies(message, request);
    else if (type === "error") this.reportError(message.message || "server error");
    else if (type === "connection") setText(this.ui.status, `connection ${message.state}`);
  }

  onResult(message, buffers, request) {
    const { arrays, shapes } = decodeArrays(message, buffers);
    const snapshot = new Snapshot(message, arrays, shapes);
    const previous = this.snapshot;
    if (message.committed !== false) this.committed = snapshot;
    // a preview that arrives after the gesture ended (Esc, refused commit) must not overwrite the committed pose
    if (message.committed === false && !this.dragging && request && request.message.op === "preview") return;
    if (message.committed !== false) this.dragging = null;
    const op0 = request ? request.message.op : null;
    // a flip or a chosen assembly, an undo or redo, a loaded or inserted design: the whole drawing comes back into view if it left it
    const flip = op0 === "commit" && (request.message.edits || []).some((edit) => edit.kind === "flip" || edit.kind === "assembly");
    this.showSnapshot(snapshot, previous, flip || ["undo", "redo", "load", "synth_insert"].includes(op0));
    if (op0 === "hello" && !this.greeted) this.greet(message.history || {});
    const op = request ? request.message.op : null;
    if (op && op !== "preview" && op !== "hello") this.setRefusal("");
    this.global.seq = message.seq ?? this.global.seq;
    if (request && request.startedAt !== null) this.global.roundTrips.push(performance.now() - request.startedAt);
    if (!this.global.ready && !this.pendingShare) this.global.ready = true;
    if (op === "load" || (op === "hello" && !this.pendingShare)) this.global.ready = true;
    if (op === "hello" && this.pendingShare) this.loadShareFragment();
  }

  onRefused(message, request) {
    this.setRefusal(message.message || "refused");
    const op = request ? request.message.op : null;
    if (op === "synth_start") this.onSynth({ running: false, status: "refused" });
    if (op === "motor_start") this.onMotorMessage(message, null, request);
    if (op === "assemblies") { this.onAssemblies(message, request); return; }
    if (op && (op.startsWith("synth") || op.startsWith("motor"))) return;
    // a refused preview goes back to the last good pose, anything else to the committed document
    if (op !== "preview") this.dragging = null;
    if (op !== "preview" || !this.dragging) {
      if (this.committed && this.committed !== this.snapshot) this.showSnapshot(this.committed, this.snapshot);
      else this.drawAll();
    } else {
      this.drawPose();
    }
  }

  setRefusal(text) {
    this.refusal = text;
    this.global.refusal = text;
    setText(this.ui.refusal, text);
    this.ui.refusal.classList.toggle("asd-visible", Boolean(text));
  }

  // ---- showing a result ---------------------------------------------------------------------------------
  // the first answer of a page: a session that has history already (an earlier tab, a reload) says so
  greet(history) {
    this.greeted = true;
    const steps = (history.undo || 0) + (history.redo || 0);
    this.global.resumed = steps > 0;
    this.ui.resumed.hidden = steps === 0;
    if (steps) {
      setText(this.ui.resumed, `This page continues the designer's open session (an earlier tab or a reload): its `
        + `${history.undo || 0} undo and ${history.redo || 0} redo steps are kept; Undo walks back through them.`);
    }
  }

  showSnapshot(snapshot, previous, refit = false) {
    this.snapshot = snapshot;
    this.global.result = snapshot.message;
    this.global.arrays = snapshot.arrays;
    this.global.history = snapshot.message.history || null;
    if (!this.unitsChosen) this.chooseUnits(snapshot);
    this.sample = Math.min(this.sample, Math.max(0, snapshot.n - 1));
    this.global.sample = this.sample;
    this.keepSelection(snapshot);
    const structureChanged = !previous || previous.pointNames.join() !== snapshot.pointNames.join()
      || previous.dimension !== snapshot.dimension;
    if (!this.view || (structureChanged && !this.dragging) || (refit && !this.fitsView(snapshot))) this.fitView();
    this.drawAll();
  }

  chooseUnits(snapshot) {
    const units = (snapshot.message.doc && snapshot.message.doc.units) || {};
    this.units.length = ["mm", "cm"].includes(units.length) ? "mm" : "m";
    this.units.angle = units.angle === "rad" ? "rad" : "deg";
    this.ui.unitLength.value = this.units.length;
    this.ui.unitAngle.value = this.units.angle;
    this.ui.unitSpeed.value = this.units.speed;
    this.unitsChosen = true;
  }

  keepSelection(snapshot) {
    if (this.selectedPoint && !snapshot.pointIndex.has(this.selectedPoint)) this.selectedPoint = null;
    if (this.selectedLink && !snapshot.links.some((link) => link.name === this.selectedLink)) this.selectedLink = null;
    if (!this.selectedPoint && !this.selectedLink) {
      const foot = snapshot.model.foot || (snapshot.cycle && snapshot.cycle.gait && snapshot.cycle.gait.foot);
      const moving = snapshot.movingPoints;
      this.selectedPoint = snapshot.pointIndex.has(foot) ? foot : (moving[moving.length - 1] || snapshot.pointNames[0] || null);
    }
    if (this.synth.point === undefined || !snapshot.pointIndex.has(this.synth.point)) {
      const foot = snapshot.model.foot;
      this.synth.point = snapshot.pointIndex.has(foot) ? foot : this.selectedPoint;
    }
  }

  setUnit(kind, value) {
    this.units[kind] = value;
    this.global.units = this.units;
    this.drawAll();
  }

  get converter() { return new UnitConverter(this.units); }

  drawAll() {
    const snapshot = this.snapshot;
    if (!snapshot) return;
    const spatial = snapshot.dimension === 3;
    this.ui.canvas.root.style.display = spatial ? "none" : "";
    this.ui.view3d.hidden = !spatial;
    for (const [tool, button] of Object.entries(this.ui.toolButtons)) button.disabled = spatial && tool !== "select";
    this.drawToolbar();
    this.drawScrubBar();
    this.drawMechanismPanel();
    this.drawDrivers();
    this.drawParams();
    this.drawGait();
    this.drawTorque();
    this.drawPointSelects();
    this.drawSynth();
    this.drawMotor();
    this.refreshChooser();
    this.drawDiagnostics();
    if (spatial) this.draw3d(true);
    else this.drawScene();
    this.drawReadouts();
  }

  // the per-sample part: pose, vectors, read-outs, plot cursors
  drawSample() {
    if (!this.snapshot) return;
    setText(this.ui.sampleIndex, String(this.sample));
    if (Number(this.ui.scrub.value) !== this.sample) this.ui.scrub.value = String(this.sample);
    if (this.snapshot.dimension === 3) this.draw3d(false);
    else this.drawPose();
    this.drawReadouts();
    this.drawPlotCursors();
    this.refreshChooser();
  }

  setSample(k) {
    if (!this.snapshot || !this.snapshot.n) return;
    const n = this.snapshot.n;
    this.sample = ((Math.round(k) % n) + n) % n;
    this.global.sample = this.sample;
    this.drawSample();
  }

  // ---- toolbar, history, tools --------------------------------------------------------------------------
  drawToolbar() {
    const history = this.snapshot.message.history || { undo: 0, redo: 0 };
    this.ui.undo.disabled = !history.undo;
    this.ui.redo.disabled = !history.redo;
    setText(this.ui.history, `undo ${history.undo || 0} · redo ${history.redo || 0}`);
    this.ui.save.classList.toggle("asd-dirty", Boolean(history.dirty));
    const file = this.snapshot.message.file;
    const name = file ? String(file).split(/[\\/]/).pop() : "";
    setText(this.ui.saveFile, file ? `→ ${name}` : "no file: Share link keeps the design");
    this.ui.saveFile.title = file ? `Save writes ${file}` : "this designer was opened on a mechanism, not a file";
    this.ui.save.title = file ? `${history.dirty ? "save the changes to" : "up to date:"} ${file}` : "no file to save to";
    for (const [tool, button] of Object.entries(this.ui.toolButtons)) {
      button.classList.toggle("asd-active", tool === this.tool);
      button.setAttribute("aria-pressed", String(tool === this.tool));
    }
  }

  setTool(tool) {
    this.tool = tool;
    this.pendingLinkPoints = [];
    this.pendingDriverPivot = null;
    this.ui.canvas.root.dataset.tool = tool;
    if (this.snapshot) { this.drawToolbar(); this.drawScene(); }
  }

  // ---- the scrub bar ------------------------------------------------------------------------------------
  drawScrubBar() {
    const snapshot = this.snapshot;
    const n = snapshot.n;
    this.ui.scrub.max = String(Math.max(0, n - 1));
    this.ui.scrub.value = String(this.sample);
    this.ui.scrub.disabled = n === 0;
    this.ui.play.disabled = n === 0;
    setText(this.ui.sampleIndex, String(this.sample));
    setText(this.ui.sampleCount, `/ ${n}`);
    const marks = [];
    const deadCentres = (snapshot.cycle && snapshot.cycle.dead_centres) || [];
    const linear = this.isLinearInput();
    deadCentres.forEach((deadCentre, index) => {
      if (!snapshot.arrays.q || n < 2 || !Number.isFinite(deadCentre.q)) return;
      const k = sampleOfInput(snapshot.arrays.q, deadCentre.q, linear);
      const title = `dead centre${deadCentre.group !== undefined ? ` of group ${deadCentre.group}` : ""} at ${formatNumber(this.converter.input(deadCentre.q, linear))} ${this.converter.inputLabel(linear)}`;
      marks.push(html("span", {
        class: "asd-dead-centre", testid: `dead-centre-${index}`, title, "data-q": deadCentre.q, "data-sample": k,
        style: `left: calc(${(100 * k) / (n - 1)}% )`,
      }));
    });
    this.ui.deadCentres.replaceChildren(...marks);
  }

  isLinearInput() {
    const input = this.snapshot && this.snapshot.cycle && this.snapshot.cycle.input;
    return Boolean(input && input.kind === "linear");
  }

  togglePlay() {
    this.playing = !this.playing;
    setText(this.ui.play, this.playing ? "❚❚ Pause" : "▶ Play");
    if (!this.playing) return;
    let last = performance.now();
    let position = this.sample;
    const step = (now) => {
      if (!this.playing || !this.snapshot) return;
      const n = this.snapshot.n;
      const input = this.snapshot.cycle && this.snapshot.cycle.input;
      const speed = input && Number.isFinite(input.speed) && !this.isLinearInput() ? Math.abs(input.speed) : 0;
      const period = speed > 0 ? Math.min(8, Math.max(2, (2 * Math.PI) / speed)) : 4;
      position = (position + ((now - last) / 1000 / period) * n) % n;
      last = now;
      if (Math.floor(position) !== this.sample) this.setSample(Math.floor(position));
      this.playClock = requestAnimationFrame(step);
    };
    this.playClock = requestAnimationFrame(step);
  }

  // ---- share links and the fragment on load -------------------------------------------------------------
  async makeShareLink() {
    const toml = this.snapshot && this.snapshot.message.toml;
    if (!toml) return;
    try {
      const fragment = await shareCodec.encode(toml);
      const base = `${location.origin}${location.pathname}${location.search}`;
      this.ui.shareUrl.value = `${base}#m=${fragment}`;
      setText(this.ui.status, "share link ready");
    } catch (error) {
      this.reportError(error);
    }
  }

  readShareFragment() {
    const hash = typeof location !== "undefined" ? location.hash : "";
    if (hash.startsWith("#m=")) this.pendingShare = hash.slice(3);
  }

  async loadShareFragment() {
    const fragment = this.pendingShare;
    this.pendingShare = null;
    try {
      const toml = await shareCodec.decode(fragment);
      this.request("load", { toml });
    } catch (error) {
      this.setRefusal(error.message);
      this.global.ready = true;
    }
  }

  dispose() {
    this.playing = false;
    if (this.playClock) cancelAnimationFrame(this.playClock);
    this.channel.dispose();
    for (const cleanup of this.cleanups.splice(0)) cleanup();
    if (window.Plotly && this.snapshot && this.snapshot.dimension === 3) window.Plotly.purge(this.ui.view3d);
    this.el.replaceChildren();
  }
}

// the methods of the other parts, by concern
for (const part of [CanvasPart, GesturesPart, PanelsPart, SynthesisPart, MotorPart, ChooserPart]) {
  for (const name of Object.getOwnPropertyNames(part.prototype)) {
    if (name !== "constructor") Object.defineProperty(Designer.prototype, name, Object.getOwnPropertyDescriptor(part.prototype, name));
  }
}


// ---------------------------------------------------------------------------------------------------------
// The anywidget entry point

// In a notebook the widget ships plotly.js as the synced trait `_plotly_js` (spatial documents only): evaluate it
// once, before the first 3D drawing, when the page has no Plotly of its own.
function loadWidgetPlotly(model) {
  const source = model && typeof model.get === "function" ? model.get("_plotly_js") : "";
  if (!window.Plotly && typeof source === "string" && source) new Function(source)();
}

function render({ model, el }) {
  loadWidgetPlotly(model);
  const designer = new Designer(model, el);
  const onPlotly = () => {
    try { loadWidgetPlotly(model); if (designer.snapshot) designer.drawAll(); } catch (error) { designer.reportError(error); }
  };
  if (typeof model.on === "function") model.on("change:_plotly_js", onPlotly);
  return () => {
    if (typeof model.off === "function") model.off("change:_plotly_js", onPlotly);
    designer.dispose();
  };
}

export default { render };
export { render, shareCodec, preferReadbackCanvases };
