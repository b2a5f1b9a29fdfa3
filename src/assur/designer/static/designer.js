// The browser front end of `assur design`: one self-contained ES module.
//
// `render({model, el})` builds the whole designer inside `el` and returns a cleanup function. `model` is an
// anywidget-like interface: `model.send(content)` sends a request to the server and
// `model.on("msg:custom", (msg, buffers) => ...)` receives its answers (docs/designer.md, "Protocol").
// The model stays in SI (m, rad, s); the unit selects change the display only.

const SVG_NS = "http://www.w3.org/2000/svg";
const SHARE_FORMAT = 1;
const DRAG_THRESHOLD_PX = 3;
const REQUEST_TIMEOUT_MS = 20000;

// ---------------------------------------------------------------------------------------------------------
// Units (display only)

const LENGTH_FACTORS = { m: 1, mm: 1000 };
const ANGLE_FACTORS = { rad: 1, deg: 180 / Math.PI };
const SPEED_FACTORS = { "rad/s": 1, rpm: 60 / (2 * Math.PI) };
const ANGLE_LABELS = { rad: "rad", deg: "°" };
const GAIT_LENGTHS = new Set(["step_length", "lift", "sag"]);
const GAIT_SPEEDS = new Set(["support_speed_mean"]);

function formatNumber(value) {
  if (value === null || value === undefined || !Number.isFinite(value)) return "—";
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude >= 1e7 || magnitude < 1e-5)) return value.toExponential(4);
  return String(Number(value.toPrecision(6)));
}

class UnitConverter {
  constructor(units) {
    this.units = units;
  }
  length(si) { return si * LENGTH_FACTORS[this.units.length]; }
  angle(si) { return si * ANGLE_FACTORS[this.units.angle]; }
  speed(si) { return si * SPEED_FACTORS[this.units.speed]; }
  get lengthLabel() { return this.units.length; }
  get angleLabel() { return ANGLE_LABELS[this.units.angle]; }
  get speedLabel() { return this.units.speed; }
  // the input q: an angle for a crank, a length for a linear driver
  input(si, linear) { return linear ? this.length(si) : this.angle(si); }
  inputLabel(linear) { return linear ? this.lengthLabel : this.angleLabel; }
  // a driver speed: angular (rad/s) for a crank, linear (m/s) for a linear driver
  driverSpeed(si, linear) { return linear ? this.length(si) : this.speed(si); }
  driverSpeedFromDisplay(value, linear) {
    return linear ? value / LENGTH_FACTORS[this.units.length] : value / SPEED_FACTORS[this.units.speed];
  }
  driverSpeedLabel(linear) { return linear ? `${this.lengthLabel}/s` : this.speedLabel; }
  // a parameter of the spatial view, by its SI unit
  // a parameter of the spatial view, by its SI unit ("m", "rad") or its kind ("length", "angle")
  param(si, unit) {
    if (unit === "m" || unit === "length") return this.length(si);
    if (unit === "rad" || unit === "angle") return this.angle(si);
    return si;
  }
  paramLabel(unit) {
    if (unit === "m" || unit === "length") return this.lengthLabel;
    if (unit === "rad" || unit === "angle") return this.angleLabel;
    return unit || "";
  }
}

// ---------------------------------------------------------------------------------------------------------
// Small DOM helpers

function html(tag, attrs = {}, ...children) {
  const element = document.createElement(tag);
  applyAttributes(element, attrs);
  for (const child of children.flat()) {
    if (child === null || child === undefined || child === false) continue;
    element.append(typeof child === "string" ? document.createTextNode(child) : child);
  }
  return element;
}

function svg(tag, attrs = {}, ...children) {
  const element = document.createElementNS(SVG_NS, tag);
  applyAttributes(element, attrs);
  for (const child of children.flat()) {
    if (child === null || child === undefined) continue;
    element.append(typeof child === "string" ? document.createTextNode(child) : child);
  }
  return element;
}

function applyAttributes(element, attrs) {
  for (const [key, value] of Object.entries(attrs)) {
    if (value === null || value === undefined || value === false) continue;
    if (key === "testid") element.setAttribute("data-testid", value);
    else if (key === "text") element.textContent = value;
    else if (key.startsWith("on") && typeof value === "function") element.addEventListener(key.slice(2), value);
    else element.setAttribute(key, value === true ? "" : String(value));
  }
}

function setText(element, text) {
  if (element.textContent !== text) element.textContent = text;
}

function namesOf(list) {
  if (!list) return [];
  if (Array.isArray(list)) return list.map((item) => (typeof item === "string" ? item : item.name));
  return Object.keys(list);
}

function entriesOf(list) {
  // a model list given as an array of {name, ...} or as a table {name: {...}}
  if (!list) return [];
  if (Array.isArray(list)) return list.map((item) => (typeof item === "string" ? { name: item } : item));
  return Object.entries(list).map(([name, value]) => ({ name, ...value }));
}

function messageType(message) {
  return message.type ?? message.op ?? message.kind;
}

// ---------------------------------------------------------------------------------------------------------
// Arrays of a result: little-endian float64 in the message's first buffer

function bytesOf(buffer) {
  if (!buffer) return null;
  if (buffer instanceof ArrayBuffer) return new Uint8Array(buffer);
  if (ArrayBuffer.isView(buffer)) return new Uint8Array(buffer.buffer, buffer.byteOffset, buffer.byteLength);
  return null;
}

function decodeArrays(message, buffers) {
  const arrays = {};
  const shapes = {};
  const bytes = message.binary && buffers ? bytesOf(buffers[0]) : null;
  if (!bytes || !message.arrays) return { arrays, shapes };
  for (const [name, [offset, length, shape]] of Object.entries(message.arrays)) {
    const start = bytes.byteOffset + offset * 8;
    arrays[name] = start % 8 === 0
      ? new Float64Array(bytes.buffer, start, length)
      : new Float64Array(bytes.slice(offset * 8, (offset + length) * 8).buffer);
    shapes[name] = shape;
  }
  return { arrays, shapes };
}

// A snapshot of one result: the message (without its array table) and its arrays, with accessors.
class Snapshot {
  constructor(message, arrays, shapes) {
    const { arrays: _table, binary: _binary, ...rest } = message;
    this.message = rest;
    this.arrays = arrays;
    this.shapes = shapes;
    this.model = rest.model || {};
    this.cycle = rest.cycle || null;
    // the arrays follow the compiled plan's point order (the document's order when it does not compile)
    this.pointNames = namesOf(this.model.point_order || this.model.points);
    this.pointIndex = new Map(this.pointNames.map((name, index) => [name, index]));
    this.framePoints = new Set(namesOf(this.model.frame_points));
    this.links = entriesOf(this.model.links).map((link) => ({ ...link, points: link.points || [] }));
    this.bodyNames = namesOf(this.model.body_names || this.model.bodies || []);
    this.dimension = this.model.dimension || 2;
    this.n = this.arrays.valid ? this.arrays.valid.length : (this.cycle ? this.cycle.n || 0 : 0);
    this.coordinates = this.shapes.pos ? this.shapes.pos[2] : this.dimension;
  }
  get movingPoints() { return this.pointNames.filter((name) => !this.framePoints.has(name)); }
  isValid(k) { return Boolean(this.arrays.valid && this.arrays.valid[k] > 0.5); }
  // a vector of point p at sample k in an (n, P, D) array
  vector(name, k, p) {
    const array = this.arrays[name];
    const shape = this.shapes[name];
    if (!array || !shape) return null;
    const [, count, dims] = shape;
    const base = (k * count + p) * dims;
    return Array.from(array.subarray(base, base + dims));
  }
  sketchOf(p) {
    const array = this.arrays.sketch;
    const shape = this.shapes.sketch;
    if (!array || !shape) return null;
    const dims = shape[1];
    return Array.from(array.subarray(p * dims, p * dims + dims));
  }
  scalar(name, k, column = 0) {
    const array = this.arrays[name];
    const shape = this.shapes[name];
    if (!array || !shape) return NaN;
    const width = shape.length > 1 ? shape[1] : 1;
    return array[k * width + column];
  }
  // the positions of every point: the cycle at sample k, or the sketch
  pose(kind, k) {
    return this.pointNames.map((_, p) => (kind === "cycle" ? this.vector("pos", k, p) : this.sketchOf(p)));
  }
}

// ---------------------------------------------------------------------------------------------------------
// The request channel: one request in flight, the newest pending request of a kind wins

const REPLACEABLE_OPS = new Set(["preview", "set_params"]);
const SUPERSEDED_BY = { commit: ["preview"], cancel: ["preview"], preview: ["preview"], set_params: ["set_params"] };
const ANSWER_TYPES = {
  save: ["saved", "refused", "error"],
  synth_start: ["synth_started", "synth_done", "refused", "error"],
  synth_cancel: ["synth_done", "refused", "error"],
};
const DEFAULT_ANSWER_TYPES = ["result", "refused", "error"];

class RequestChannel {
  constructor(model) {
    this.model = model;
    this.seq = 0;
    this.inflight = null;
    this.queue = [];
    this.timer = null;
  }
  request(op, fields = {}, startedAt = null) {
    const superseded = SUPERSEDED_BY[op] || [];
    while (this.queue.length && superseded.includes(this.queue[this.queue.length - 1].message.op)) this.queue.pop();
    const request = { message: { op, ...fields }, startedAt };
    this.queue.push(request);
    this.pump();
    return request;
  }
  pump() {
    if (this.inflight || !this.queue.length) return;
    const request = this.queue.shift();
    this.seq += 1;
    request.message.seq = this.seq;
    this.inflight = request;
    this.timer = setTimeout(() => this.release(), REQUEST_TIMEOUT_MS);
    this.model.send(request.message);
  }
  // the request a message answers (and frees the slot), or null
  answer(message) {
    const request = this.inflight;
    if (!request) return null;
    const type = messageType(message);
    const expected = ANSWER_TYPES[request.message.op] || DEFAULT_ANSWER_TYPES;
    const matches = message.seq !== undefined && message.seq !== null
      ? message.seq === request.message.seq && expected.includes(type)
      : expected.includes(type);
    if (!matches) return null;
    this.release();
    return request;
  }
  release() {
    clearTimeout(this.timer);
    this.inflight = null;
    this.pump();
  }
  get busy() { return Boolean(this.inflight) || this.queue.length > 0; }
  dispose() { clearTimeout(this.timer); }
}

// ---------------------------------------------------------------------------------------------------------
// Share links: #m=1.<base64url(deflate-raw(UTF-8 of the toml))>

function bytesToBase64Url(bytes) {
  let binary = "";
  for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(binary).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

function base64UrlToBytes(text) {
  const base64 = text.replace(/-/g, "+").replace(/_/g, "/");
  const binary = atob(base64 + "=".repeat((4 - (base64.length % 4)) % 4));
  return Uint8Array.from(binary, (c) => c.charCodeAt(0));
}

async function pipeBytes(bytes, stream) {
  const output = new Blob([bytes]).stream().pipeThrough(stream);
  return new Uint8Array(await new Response(output).arrayBuffer());
}

const shareCodec = {
  async encode(toml) {
    const compressed = await pipeBytes(new TextEncoder().encode(toml), new CompressionStream("deflate-raw"));
    return `${SHARE_FORMAT}.${bytesToBase64Url(compressed)}`;
  },
  async decode(fragment) {
    const body = String(fragment).replace(/^#/, "").replace(/^m=/, "");
    const dot = body.indexOf(".");
    const version = Number(dot < 0 ? body : body.slice(0, dot));
    if (!Number.isInteger(version) || version < 1) throw new Error("this share link is not readable");
    if (version > SHARE_FORMAT) {
      throw new Error(`this link was made by a newer designer (format ${version}); this page reads format ${SHARE_FORMAT}`);
    }
    const bytes = await pipeBytes(base64UrlToBytes(body.slice(dot + 1)), new DecompressionStream("deflate-raw"));
    return new TextDecoder().decode(bytes);
  },
};

// ---------------------------------------------------------------------------------------------------------
// Geometry helpers

function bounds(pointsList) {
  let minX = Infinity; let minY = Infinity; let maxX = -Infinity; let maxY = -Infinity;
  for (const [x, y] of pointsList) {
    if (!Number.isFinite(x) || !Number.isFinite(y)) continue;
    minX = Math.min(minX, x); maxX = Math.max(maxX, x); minY = Math.min(minY, y); maxY = Math.max(maxY, y);
  }
  if (!Number.isFinite(minX)) return null;
  return { minX, minY, maxX, maxY };
}

function wrapAngle(a) {
  return Math.atan2(Math.sin(a), Math.cos(a));
}

// the sample of the cycle nearest to an input value
function sampleOfInput(qArray, q, linear) {
  let best = 0; let bestDistance = Infinity;
  for (let k = 0; k < qArray.length; k += 1) {
    const distance = Math.abs(linear ? qArray[k] - q : wrapAngle(qArray[k] - q));
    if (distance < bestDistance) { bestDistance = distance; best = k; }
  }
  return best;
}

// an SVG path through (x, y) samples, broken (a new "M") wherever a sample is missing
function brokenPath(samples) {
  let d = ""; let runs = 0; let drawing = false;
  for (const sample of samples) {
    if (!sample || !Number.isFinite(sample[0]) || !Number.isFinite(sample[1])) { drawing = false; continue; }
    const command = drawing ? "L" : "M";
    if (!drawing) runs += 1;
    d += `${command}${sample[0].toFixed(2)},${sample[1].toFixed(2)}`;
    drawing = true;
  }
  return { d, runs };
}

// 2D canvas contexts created without options read back often (willReadFrequently): plotly's 3D text rendering
// reads every glyph back, and Chromium warns on the console otherwise. Installed once, for the 3D view only.
function preferReadbackCanvases() {
  const prototype = HTMLCanvasElement.prototype;
  if (prototype.getContext.__assurReadback) return;
  const original = prototype.getContext;
  const getContext = function getContext(type, options) {
    return original.call(this, type, type === "2d" && options === undefined ? { willReadFrequently: true } : options);
  };
  getContext.__assurReadback = true;
  prototype.getContext = getContext;
}

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
    this.showVectors = { vel: true, acc: true, ic: true };
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
    ui.share = html("button", { type: "button", testid: "share", text: "Share link" });
    ui.shareUrl = html("input", { type: "text", testid: "share-url", readonly: true, placeholder: "share link", class: "asd-share-url" });
    ui.fit = html("button", { type: "button", testid: "fit", text: "Fit view" });
    ui.unitLength = this.unitSelect("unit-length", ["mm", "m"]);
    ui.unitAngle = this.unitSelect("unit-angle", ["deg", "rad"]);
    ui.unitSpeed = this.unitSelect("unit-speed", ["rpm", "rad/s"]);
    const toolbar = html("div", { class: "asd-toolbar" },
      tools,
      html("div", { class: "asd-group" }, ui.undo, ui.redo, ui.history),
      html("div", { class: "asd-group" }, ui.save, ui.share, ui.shareUrl),
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

  buildCanvas() {
    const id = (name) => `asd-${name}-${this.uid}`;
    const arrow = (name) => svg("marker", {
      id: id(name), viewBox: "0 0 10 10", refX: 9, refY: 5, markerWidth: 7, markerHeight: 7, orient: "auto-start-reverse",
    }, svg("path", { d: "M0,0 L10,5 L0,10 z", class: `asd-arrow-${name}` }));
    const hatch = svg("pattern", { id: id("hatch"), width: 6, height: 6, patternUnits: "userSpaceOnUse", patternTransform: "rotate(45)" },
      svg("line", { x1: 0, y1: 0, x2: 0, y2: 6, class: "asd-hatch-line" }));
    const root = svg("svg", { class: "asd-canvas", testid: "canvas", role: "img", "aria-label": "mechanism" },
      svg("defs", {}, arrow("vel"), arrow("acc"), hatch));
    const layer = (name) => { const g = svg("g", { class: `asd-layer-${name}` }); root.append(g); return g; };
    const canvas = { root, ids: { vel: id("vel"), acc: id("acc"), hatch: id("hatch") } };
    canvas.background = svg("rect", { class: "asd-background", x: 0, y: 0, width: "100%", height: "100%" });
    root.append(canvas.background);
    for (const name of ["paths", "guides", "links", "ground", "vectors", "ics", "points", "targets", "pending"]) canvas[name] = layer(name);
    return canvas;
  }

  buildSidePanel(ui) {
    ui.refusal = html("div", { class: "asd-refusal", testid: "refusal", role: "alert" });
    ui.status = html("div", { class: "asd-status", testid: "status" });
    ui.formula = html("div", { class: "asd-formula", testid: "formula" });
    ui.assembled = html("span", { testid: "assembled-count", text: "0" });
    ui.groups = html("div", { class: "asd-groups", testid: "groups" });
    const mechanism = this.section("Mechanism", "mechanism-panel",
      ui.formula, html("div", {}, "assembled samples: ", ui.assembled), ui.groups);

    ui.selectionName = html("div", { class: "asd-selection-name", testid: "selection", text: "nothing selected" });
    ui.lockPoint = html("input", { type: "checkbox", testid: "lock-point" });
    ui.lockLink = html("input", { type: "checkbox", testid: "lock-link" });
    ui.lockPointRow = html("label", { class: "asd-row", hidden: true }, ui.lockPoint, " lock point");
    ui.lockLinkRow = html("label", { class: "asd-row", hidden: true }, ui.lockLink, " lock link length");
    ui.readoutInput = html("span", { testid: "readout-input", text: "—" });
    ui.readoutInputUnit = html("span", { class: "asd-unit" });
    ui.readoutVel = html("span", { testid: "readout-vel", text: "—" });
    ui.readoutVelUnit = html("span", { class: "asd-unit" });
    ui.readoutAcc = html("span", { testid: "readout-acc", text: "—" });
    ui.readoutAccUnit = html("span", { class: "asd-unit" });
    const selection = this.section("Selection", "selection-panel", ui.selectionName, ui.lockPointRow, ui.lockLinkRow,
      html("div", { class: "asd-row" }, "input ", ui.readoutInput, " ", ui.readoutInputUnit),
      html("div", { class: "asd-row" }, "|v| ", ui.readoutVel, " ", ui.readoutVelUnit),
      html("div", { class: "asd-row" }, "|a| ", ui.readoutAcc, " ", ui.readoutAccUnit));

    const toggle = (key, testid, label) => {
      const box = html("input", { type: "checkbox", testid, checked: true });
      box.addEventListener("change", () => { this.showVectors[key] = box.checked; this.drawPose(); });
      return html("label", { class: "asd-row" }, box, ` ${label}`);
    };
    const display = this.section("Display", "display-panel",
      toggle("vel", "show-vel", "velocity vectors"), toggle("acc", "show-acc", "acceleration vectors"),
      toggle("ic", "show-ic", "instant centres"));

    ui.drivers = html("div", { class: "asd-drivers" });
    const drivers = this.section("Drivers", "drivers-panel", ui.drivers);
    ui.params = html("div", { class: "asd-params" });
    ui.paramsPanel = this.section("Parameters", "params-panel", ui.params);
    ui.paramsPanel.hidden = true;

    ui.gait = html("div", { class: "asd-kv" });
    ui.feet = html("span", { testid: "feet-on-ground", text: "—" });
    ui.gaitPanel = this.section("Gait", "gait-panel", ui.gait, html("div", { class: "asd-row" }, "feet on the ground: ", ui.feet));
    ui.gaitPanel.hidden = true;

    ui.torquePlot = svg("svg", { class: "asd-plot", testid: "torque-plot", viewBox: "0 0 300 150" });
    ui.torquePeak = html("span", { testid: "torque-peak", text: "—" });
    ui.powerPeak = html("span", { testid: "power-peak", text: "—" });
    ui.torqueUnit = html("span", { class: "asd-unit", text: "N·m" });
    ui.torquePanel = this.section("Driving torque or force", "torque-panel", ui.torquePlot,
      html("div", { class: "asd-row" }, html("span", { class: "asd-torque-key" }, "peak effort "), ui.torquePeak, " ", ui.torqueUnit),
      html("div", { class: "asd-row" }, html("span", { class: "asd-power-key" }, "peak power "), ui.powerPeak, " W"));
    ui.torquePanel.hidden = true;

    ui.plotPoint = html("select", { testid: "plot-point" });
    ui.plotPoint.addEventListener("change", () => this.selectPoint(ui.plotPoint.value));
    ui.plotVel = svg("svg", { class: "asd-plot", testid: "plot-vel", viewBox: "0 0 300 120" });
    ui.plotAcc = svg("svg", { class: "asd-plot", testid: "plot-acc", viewBox: "0 0 300 120" });
    const pointPlot = this.section("Point", "point-plot", html("label", {}, "point ", ui.plotPoint), ui.plotVel, ui.plotAcc);

    const synth = this.buildSynthPanel(ui);
    ui.diagnostics = html("ul", { class: "asd-diagnostics", testid: "diagnostics" });
    const diagnostics = this.section("Diagnostics", "diagnostics-panel", ui.diagnostics);

    return html("aside", { class: "asd-side" }, ui.refusal, ui.status, mechanism, selection, display, drivers,
      ui.paramsPanel, ui.gaitPanel, ui.torquePanel, pointPlot, synth, diagnostics);
  }

  buildSynthPanel(ui) {
    ui.synthPoint = html("select", { testid: "synth-point" });
    ui.synthAddTargets = html("input", { type: "checkbox", testid: "synth-add-targets" });
    ui.synthClear = html("button", { type: "button", testid: "synth-clear", text: "Clear targets" });
    ui.synthBudget = html("input", { type: "number", testid: "synth-budget", min: 100, step: 100, value: 300 });
    ui.synthRun = html("button", { type: "button", testid: "synth-run", text: "Run" });
    ui.synthCancel = html("button", { type: "button", testid: "synth-cancel", text: "Cancel", disabled: true });
    ui.synthInsert = html("button", { type: "button", testid: "synth-insert", text: "Insert best", disabled: true });
    ui.synthProgress = html("span", { testid: "synth-progress", text: "0" });
    ui.synthBest = html("span", { testid: "synth-best", text: "—" });
    ui.synthStatus = html("span", { testid: "synth-status", class: "asd-muted" });
    ui.synthTargetCount = html("span", { testid: "synth-count", text: "0" });
    return this.section("Path synthesis", "synth-panel",
      html("label", { class: "asd-row" }, "point ", ui.synthPoint),
      html("label", { class: "asd-row" }, ui.synthAddTargets, " click on the canvas to add targets (", ui.synthTargetCount, ")"),
      html("label", { class: "asd-row" }, "budget ", ui.synthBudget, " evaluations"),
      html("div", { class: "asd-row" }, ui.synthRun, ui.synthCancel, ui.synthClear, ui.synthInsert),
      html("div", { class: "asd-row" }, "evaluations ", ui.synthProgress, " · best ", ui.synthBest, " ", ui.synthStatus));
  }

  section(title, testid, ...children) {
    return html("section", { class: "asd-section", testid }, html("h3", { text: title }), ...children);
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
    else if (type === "saved") setText(this.ui.status, `saved ${message.path}`);
    else if (type === "synth_started") this.onSynth({ running: true, status: "running", evaluations: 0, best: null, toml: null });
    else if (type === "synth_progress") this.onSynth({ evaluations: message.evaluations, best: message.best, elapsed: message.elapsed });
    else if (type === "synth_done") this.onSynth({ running: false, status: message.status, best: message.best ?? this.synth.best, toml: message.toml || null, evaluations: message.evaluations ?? this.synth.evaluations });
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
    this.showSnapshot(snapshot, previous);
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
    if (op && op.startsWith("synth")) return;
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

  onSynth(update) {
    Object.assign(this.synth, update);
    this.global.synth = this.synth;
    this.drawSynth();
  }

  // ---- showing a result ---------------------------------------------------------------------------------
  showSnapshot(snapshot, previous) {
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
    if (!this.view || (structureChanged && !this.dragging)) this.fitView();
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
    this.ui.save.title = history.dirty ? "save the changes to the file" : "the file is up to date";
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

  // ---- the side panels ----------------------------------------------------------------------------------
  drawMechanismPanel() {
    const snapshot = this.snapshot;
    const model = snapshot.model;
    setText(this.ui.formula, model.formula ? String(model.formula) : (model.mobility !== undefined ? `mobility ${model.mobility}` : ""));
    setText(this.ui.assembled, String(snapshot.cycle ? snapshot.cycle.assembled ?? 0 : 0));
    const groups = entriesOf(model.groups);
    const rows = groups.map((group, position) => {
      const index = group.index ?? position;
      const flip = html("button", {
        type: "button", testid: `flip-${index}`, text: "Flip", disabled: !group.flippable || snapshot.dimension === 3,
        title: `assemble ${group.label || group.point || index} on its other branch`,
      });
      flip.addEventListener("click", () => this.commit([{ kind: "flip", group: index }]));
      return html("div", { class: "asd-row asd-group-row" },
        html("span", { class: "asd-group-label", text: `${group.label || `group ${index}`} (${group.kind || ""})` }), flip);
    });
    // one transmission angle per group: column `position` of the array transmission (n, G)
    const transmission = groups.map((group, position) => html("div", { class: "asd-row" },
      `transmission angle ${group.label || group.point || position}: `,
      html("span", { testid: `transmission-${group.index ?? position}`, class: "asd-transmission", "data-column": position }),
      " ", html("span", { class: "asd-unit asd-angle-unit" })));
    this.ui.groups.replaceChildren(...rows, ...transmission);
  }

  drawReadouts() {
    const snapshot = this.snapshot;
    const convert = this.converter;
    const k = this.sample;
    const valid = snapshot.isValid(k);
    const linear = this.isLinearInput();
    const q = snapshot.arrays.q ? snapshot.arrays.q[k] : NaN;
    setText(this.ui.readoutInput, formatNumber(convert.input(q, linear)));
    setText(this.ui.readoutInputUnit, convert.inputLabel(linear));
    const point = this.selectedPoint;
    const p = snapshot.pointIndex.get(point);
    const magnitude = (vector) => (vector && valid ? Math.hypot(...vector) : NaN);
    const velocity = p === undefined ? NaN : magnitude(snapshot.vector("vel", k, p));
    const acceleration = p === undefined ? NaN : magnitude(snapshot.vector("acc", k, p));
    this.ui.readoutVel.setAttribute("data-testid", `readout-vel-${point ?? ""}`);
    this.ui.readoutAcc.setAttribute("data-testid", `readout-acc-${point ?? ""}`);
    setText(this.ui.readoutVel, formatNumber(convert.length(velocity)));
    setText(this.ui.readoutAcc, formatNumber(convert.length(acceleration)));
    setText(this.ui.readoutVelUnit, `${convert.lengthLabel}/s`);
    setText(this.ui.readoutAccUnit, `${convert.lengthLabel}/s²`);
    // selection and locks
    const locks = this.locks();
    if (this.selectedPoint) setText(this.ui.selectionName, `point ${this.selectedPoint}`);
    else if (this.selectedLink) setText(this.ui.selectionName, `link ${this.selectedLink}`);
    else setText(this.ui.selectionName, "nothing selected");
    this.ui.lockPointRow.hidden = !this.selectedPoint || snapshot.dimension === 3;
    this.ui.lockLinkRow.hidden = !this.selectedLink || snapshot.dimension === 3;
    this.ui.lockPoint.checked = Boolean(this.selectedPoint && locks.points.has(this.selectedPoint));
    this.ui.lockLink.checked = Boolean(this.selectedLink && locks.links.has(this.selectedLink));
    // transmission angles
    for (const element of this.ui.groups.querySelectorAll(".asd-transmission")) {
      const value = valid ? snapshot.scalar("transmission", k, Number(element.dataset.column)) : NaN;
      setText(element, formatNumber(convert.angle(value)));
    }
    for (const element of this.ui.groups.querySelectorAll(".asd-angle-unit")) setText(element, convert.angleLabel);
    // gait
    if (snapshot.arrays.feet) setText(this.ui.feet, formatNumber(snapshot.arrays.feet[k]));
  }

  locks() {
    const raw = this.snapshot.model.locks || {};
    const points = new Set(); const links = new Set();
    if (Array.isArray(raw)) {
      for (const lock of raw) {
        if (typeof lock === "string") points.add(lock);
        else if (lock.point) points.add(lock.point);
        else if (lock.link) links.add(lock.link);
      }
    } else {
      for (const name of namesOf(raw.points)) points.add(name);
      for (const name of namesOf(raw.links)) links.add(name);
    }
    return { points, links };
  }

  drawDrivers() {
    const convert = this.converter;
    const rows = entriesOf(this.snapshot.model.drivers).map((driver) => {
      const linear = driver.kind === "linear";
      const speed = this.driverSpeedSI(driver);
      const input = html("input", {
        type: "number", step: "any", testid: `speed-${driver.name}`, class: "asd-speed", "data-si": speed,
        value: Number.isFinite(speed) ? formatNumber(convert.driverSpeed(speed, linear)) : "",
      });
      input.dataset.shown = input.value;
      input.addEventListener("change", () => {
        const typed = Number(input.value);
        if (!input.isConnected || !Number.isFinite(typed) || input.value.trim() === "") return;
        input.dataset.shown = input.value;
        const si = this.converter.driverSpeedFromDisplay(typed, linear);
        const current = entriesOf(this.snapshot.model.drivers).find((item) => item.name === driver.name);
        const now = current ? this.driverSpeedSI(current) : NaN;
        if (Math.abs(si - now) <= 1e-12 * Math.max(1, Math.abs(now))) return;   // nothing changed
        this.commit([{ kind: "set_speed", driver: driver.name, speed: si }]);
      });
      const remove = html("button", { type: "button", testid: `delete-driver-${driver.name}`, title: `delete the driver ${driver.name}` }, "×");
      remove.addEventListener("click", () => this.commit([{ kind: "delete_driver", name: driver.name }]));
      return html("div", { class: "asd-row" },
        html("label", {}, `${driver.name} (${driver.kind || "rotary"}) `, input, ` ${convert.driverSpeedLabel(linear)} `), remove);
    });
    // a number being typed (not yet sent) stays
    const active = document.activeElement;
    if (active && this.ui.drivers.contains(active) && active.value !== active.dataset.shown) return;
    this.ui.drivers.replaceChildren(...rows);
  }

  // a driver's speed in SI, as the server read it from the document (NaN when the text is not a speed)
  driverSpeedSI(driver) {
    return Number.isFinite(driver.speed_si) ? driver.speed_si : NaN;
  }

  drawParams() {
    const params = entriesOf(this.snapshot.model.params);
    this.ui.paramsPanel.hidden = this.snapshot.dimension !== 3 || params.length === 0;
    const convert = this.converter;
    const existing = new Map([...this.ui.params.querySelectorAll("input[type=range]")].map((input) => [input.dataset.name, input]));
    const sameList = existing.size === params.length && params.every((param) => existing.has(param.name));
    if (!sameList) {
      const rows = params.map((param) => {
        const slider = html("input", {
          type: "range", testid: `param-${param.name}`, "data-name": param.name, min: param.min, max: param.max,
          step: (param.max - param.min) / 400 || "any", value: param.value,
        });
        slider.addEventListener("input", () => {
          this.paramOverrides[param.name] = Number(slider.value);
          this.request("set_params", { params: { ...this.paramOverrides } }, performance.now());
          this.drawParamValues();
        });
        return html("label", { class: "asd-row asd-param" }, html("span", { class: "asd-param-name", text: param.name }), slider,
          html("span", { class: "asd-param-value", "data-name": param.name }));
      });
      this.ui.params.replaceChildren(...rows);
    } else {
      for (const param of params) {
        const slider = existing.get(param.name);
        if (document.activeElement !== slider && this.paramOverrides[param.name] === undefined) slider.value = String(param.value);
      }
    }
    this.paramUnits = new Map(params.map((param) => [param.name, param.unit || param.kind]));
    this.drawParamValues(convert);
  }

  drawParamValues(convert = this.converter) {
    for (const span of this.ui.params.querySelectorAll(".asd-param-value")) {
      const slider = this.ui.params.querySelector(`input[data-name="${CSS.escape(span.dataset.name)}"]`);
      const unit = this.paramUnits ? this.paramUnits.get(span.dataset.name) : "";
      setText(span, `${formatNumber(convert.param(Number(slider.value), unit))} ${convert.paramLabel(unit)}`);
    }
  }

  drawGait() {
    const gait = this.snapshot.cycle && this.snapshot.cycle.gait;
    this.ui.gaitPanel.hidden = !gait;
    if (!gait) return;
    const rows = [];
    const convert = this.converter;
    const display = (key, value) => {
      if (typeof value !== "number") return [String(value), ""];
      if (GAIT_LENGTHS.has(key)) return [formatNumber(convert.length(value)), convert.lengthLabel];
      if (GAIT_SPEEDS.has(key)) return [formatNumber(convert.length(value)), `${convert.lengthLabel}/s`];
      return [formatNumber(value), ""];
    };
    const add = (key, value) => {
      if (value === null || value === undefined) return;
      if (typeof value === "object" && !Array.isArray(value)) { for (const [k, v] of Object.entries(value)) add(`${key}.${k}`, v); return; }
      const [text, unit] = Array.isArray(value) ? [value.map((v) => display(key, v)[0]).join(", "), ""] : display(key, value);
      rows.push(html("div", { class: "asd-row" }, html("span", { class: "asd-key", text: `${key.replace(/_/g, " ")}: ` }),
        html("span", { testid: `gait-${key}`, text }), unit ? html("span", { class: "asd-unit", text: unit }) : null));
    };
    for (const [key, value] of Object.entries(gait)) add(key, value);
    this.ui.gait.replaceChildren(...rows);
  }

  drawDiagnostics() {
    const diagnostics = this.snapshot.message.diagnostics || [];
    this.ui.diagnostics.replaceChildren(...diagnostics.map((item, index) => html("li", {
      class: `asd-diag asd-diag-${item.level || "info"}`, testid: `diagnostic-${index}`,
      title: item.where ? String(item.where) : null,
    }, html("b", { text: `${item.level || "info"}` }), ` ${item.code ? `[${item.code}] ` : ""}${item.message || ""}`)));
  }

  drawPointSelects() {
    const names = this.snapshot.pointNames;
    const fill = (select, selected) => {
      const current = [...select.options].map((option) => option.value).join();
      if (current !== names.join()) select.replaceChildren(...names.map((name) => html("option", { value: name, text: name })));
      if (selected && select.value !== selected) select.value = selected;
    };
    fill(this.ui.plotPoint, this.selectedPoint);
    fill(this.ui.synthPoint, this.synth.point);
    this.drawPointPlots();
  }

  selectPoint(name) {
    this.selectedPoint = name;
    this.selectedLink = null;
    if (this.ui.plotPoint.value !== name) this.ui.plotPoint.value = name;
    this.drawPointPlots();
    this.drawReadouts();
    if (this.snapshot.dimension !== 3) this.drawPose();
  }

  selectLink(name) {
    this.selectedLink = name;
    this.selectedPoint = null;
    this.drawReadouts();
    this.drawPose();
  }

  // ---- plots against the input --------------------------------------------------------------------------
  plotInputs() {
    const snapshot = this.snapshot;
    const q = snapshot.arrays.q;
    if (!q) return null;
    const linear = this.isLinearInput();
    const convert = this.converter;
    let xs = Array.from(q, (value) => convert.input(value, linear));
    if (!linear) {
      // unwrap the crank angle so that the axis increases over the turn
      const turn = convert.angle(2 * Math.PI);
      for (let k = 1; k < xs.length; k += 1) while (xs[k] < xs[k - 1] - turn / 2) xs[k] += turn;
    }
    return { xs, label: convert.inputLabel(linear) };
  }

  // a line plot of one or more series (each scaled to its own range) with gaps where invalid
  linePlot(target, series, width, height) {
    const inputs = this.plotInputs();
    const margin = { left: 8, right: 8, top: 16, bottom: 14 };
    const children = [svg("rect", { class: "asd-plot-frame", x: margin.left, y: margin.top, width: width - margin.left - margin.right, height: height - margin.top - margin.bottom })];
    if (!inputs || !inputs.xs.length) { target.replaceChildren(...children); return; }
    const { xs } = inputs;
    const x0 = Math.min(...xs); const x1 = Math.max(...xs);
    const toX = (x) => margin.left + ((x - x0) / (x1 - x0 || 1)) * (width - margin.left - margin.right);
    series.forEach((serie, index) => {
      const finite = serie.ys.filter((y, k) => Number.isFinite(y) && this.snapshot.isValid(k));
      const y0 = Math.min(0, ...finite); const y1 = Math.max(0, ...finite);
      const toY = (y) => height - margin.bottom - ((y - y0) / (y1 - y0 || 1)) * (height - margin.top - margin.bottom);
      const samples = serie.ys.map((y, k) => (this.snapshot.isValid(k) && Number.isFinite(y) ? [toX(xs[k]), toY(y)] : null));
      const { d, runs } = brokenPath(samples);
      children.push(svg("path", { class: `asd-plot-line ${serie.cls}`, d, "data-runs": runs, testid: serie.testid }));
      if (finite.length && y0 < 0 && y1 > 0) children.push(svg("line", { class: "asd-plot-zero", x1: margin.left, x2: width - margin.right, y1: toY(0), y2: toY(0) }));
      children.push(svg("text", { class: `asd-plot-label ${serie.cls}`, x: margin.left + 2 + index * (width / 2), y: 11, text: `${serie.label} max ${formatNumber(finite.length ? Math.max(...finite.map(Math.abs)) : NaN)} ${serie.unit}` }));
    });
    const cursor = svg("line", { class: "asd-plot-cursor", y1: margin.top, y2: height - margin.bottom });
    children.push(cursor);
    children.push(svg("text", { class: "asd-plot-axis", x: width - margin.right, y: height - 2, "text-anchor": "end", text: `input (${inputs.label})` }));
    target.replaceChildren(...children);
    target.__cursor = { element: cursor, xs, toX };
    this.placeCursor(target);
  }

  placeCursor(target) {
    const cursor = target.__cursor;
    if (!cursor || !cursor.xs.length) return;
    const x = cursor.toX(cursor.xs[Math.min(this.sample, cursor.xs.length - 1)]);
    cursor.element.setAttribute("x1", x.toFixed(2));
    cursor.element.setAttribute("x2", x.toFixed(2));
  }

  drawPlotCursors() {
    for (const target of [this.ui.plotVel, this.ui.plotAcc, this.ui.torquePlot]) this.placeCursor(target);
  }

  drawPointPlots() {
    const snapshot = this.snapshot;
    const point = this.ui.plotPoint.value || this.selectedPoint;
    const p = snapshot.pointIndex.get(point);
    const convert = this.converter;
    const magnitudes = (name) => Array.from({ length: snapshot.n }, (_, k) => {
      const vector = p === undefined ? null : snapshot.vector(name, k, p);
      return vector ? convert.length(Math.hypot(...vector)) : NaN;
    });
    this.linePlot(this.ui.plotVel, [{ ys: magnitudes("vel"), cls: "asd-series-vel", label: `|v| ${point ?? ""}`, unit: `${convert.lengthLabel}/s`, testid: "plot-vel-line" }], 300, 120);
    this.linePlot(this.ui.plotAcc, [{ ys: magnitudes("acc"), cls: "asd-series-acc", label: `|a| ${point ?? ""}`, unit: `${convert.lengthLabel}/s²`, testid: "plot-acc-line" }], 300, 120);
  }

  drawTorque() {
    const snapshot = this.snapshot;
    const torque = snapshot.arrays.torque;
    this.ui.torquePanel.hidden = !torque;
    if (!torque) return;
    const power = snapshot.arrays.power || new Float64Array(torque.length).fill(NaN);
    const peak = (array) => {
      let best = NaN;
      array.forEach((value, k) => { if (snapshot.isValid(k) && Number.isFinite(value) && !(Math.abs(value) <= best)) best = Math.abs(value); });
      return best;
    };
    const forces = (snapshot.cycle && snapshot.cycle.forces) || {};
    const effortUnit = forces.effort_unit || (this.isLinearInput() ? "N" : "N·m");
    setText(this.ui.torqueUnit, effortUnit);
    setText(this.ui.torquePeak, formatNumber(peak(torque)));
    setText(this.ui.powerPeak, formatNumber(peak(power)));
    this.linePlot(this.ui.torquePlot, [
      { ys: Array.from(torque), cls: "asd-series-torque", label: this.isLinearInput() ? "force" : "torque", unit: effortUnit, testid: "torque-line" },
      { ys: Array.from(power), cls: "asd-series-power", label: "power", unit: "W", testid: "power-line" },
    ], 300, 150);
  }

  // ---- synthesis ----------------------------------------------------------------------------------------
  startSynthesis() {
    const point = this.ui.synthPoint.value;
    this.synth.point = point;
    const budget = Math.round(Number(this.ui.synthBudget.value) || 300);
    this.onSynth({ running: true, status: "starting", evaluations: 0, best: null, toml: null });
    this.request("synth_start", { point, targets: this.synth.targets.map(([x, y]) => [x, y]), budget, seed: 1 });
  }

  drawSynth() {
    const synth = this.synth;
    setText(this.ui.synthProgress, String(synth.evaluations ?? 0));
    setText(this.ui.synthBest, formatNumber(synth.best));
    setText(this.ui.synthStatus, synth.status || "");
    setText(this.ui.synthTargetCount, String(synth.targets.length));
    this.ui.synthCancel.disabled = !synth.running;
    this.ui.synthRun.disabled = synth.running;
    this.ui.synthInsert.disabled = synth.running || !synth.toml;
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

  // ---- the 2D canvas: view ------------------------------------------------------------------------------
  onResize() {
    const rect = this.ui.canvas.root.getBoundingClientRect();
    if (rect.width < 10 || rect.height < 10) return;
    const first = !this.sized;
    this.sized = true;
    this.size = { width: rect.width, height: rect.height };
    this.ui.canvas.root.setAttribute("viewBox", `0 0 ${rect.width} ${rect.height}`);
    if (this.snapshot && this.snapshot.dimension !== 3) {
      if (first) this.fitView();
      this.drawScene();
    }
  }

  fitView() {
    const snapshot = this.snapshot;
    if (!snapshot || snapshot.dimension === 3) return;
    const rect = this.ui.canvas.root.getBoundingClientRect();
    if (rect.width >= 10 && rect.height >= 10) {
      this.size = { width: rect.width, height: rect.height };
      this.ui.canvas.root.setAttribute("viewBox", `0 0 ${rect.width} ${rect.height}`);
    }
    const samples = [];
    for (let p = 0; p < snapshot.pointNames.length; p += 1) {
      const sketch = snapshot.sketchOf(p);
      if (sketch) samples.push(sketch);
      for (let k = 0; k < snapshot.n; k += 1) if (snapshot.isValid(k)) samples.push(snapshot.vector("pos", k, p));
    }
    const box = bounds(samples) || { minX: -1, minY: -1, maxX: 1, maxY: 1 };
    const spanX = Math.max(box.maxX - box.minX, 1e-6);
    const spanY = Math.max(box.maxY - box.minY, 1e-6);
    const span = Math.max(spanX, spanY);
    const marginFactor = 1.25;
    const scale = Math.min(this.size.width / (Math.max(spanX, span * 0.2) * marginFactor), this.size.height / (Math.max(spanY, span * 0.2) * marginFactor));
    this.view = { cx: (box.minX + box.maxX) / 2, cy: (box.minY + box.maxY) / 2, scale };
    this.extent = span;
  }

  toScreen([x, y]) {
    const { cx, cy, scale } = this.view;
    return [this.size.width / 2 + (x - cx) * scale, this.size.height / 2 - (y - cy) * scale];
  }

  toWorld(event) {
    const rect = this.ui.canvas.root.getBoundingClientRect();
    const sx = event.clientX - rect.left; const sy = event.clientY - rect.top;
    const { cx, cy, scale } = this.view;
    return [cx + (sx - this.size.width / 2) / scale, cy - (sy - this.size.height / 2) / scale];
  }

  onWheel(event) {
    if (!this.view || !this.snapshot || this.snapshot.dimension === 3) return;
    event.preventDefault();
    const before = this.toWorld(event);
    this.view.scale *= Math.exp(-event.deltaY * 0.0015);
    const after = this.toWorld(event);
    this.view.cx += before[0] - after[0];
    this.view.cy += before[1] - after[1];
    this.drawScene();
  }

  // ---- the 2D canvas: drawing ---------------------------------------------------------------------------
  drawScene() {
    if (!this.snapshot || !this.view || this.snapshot.dimension === 3) return;
    this.drawPaths();
    this.drawPose();
    this.drawTargets();
    this.drawPending();
  }

  // which pose is on display: the sketch while editing, otherwise the cycle at the current sample
  displayedPose() {
    const snapshot = this.snapshot;
    if (this.dragging) return { kind: "sketch", note: "" };
    if (this.tool !== "select") return { kind: "sketch", note: "editing the sketch pose" };
    if (!snapshot.cycle || !snapshot.arrays.pos) return { kind: "sketch", note: "not a mechanism yet: showing the sketch" };
    if (!snapshot.isValid(this.sample)) return { kind: "invalid", note: "the mechanism does not assemble at this input: showing the sketch" };
    return { kind: "cycle", note: "" };
  }

  drawPaths() {
    const snapshot = this.snapshot;
    const layer = this.ui.canvas.paths;
    const children = [];
    if (snapshot.arrays.pos) {
      for (const name of snapshot.movingPoints) {
        const p = snapshot.pointIndex.get(name);
        const samples = Array.from({ length: snapshot.n }, (_, k) => (snapshot.isValid(k) ? this.toScreen(snapshot.vector("pos", k, p)) : null));
        const { d, runs } = brokenPath(samples);
        children.push(svg("path", { class: "asd-path", testid: `path-${name}`, "data-runs": runs, d }));
      }
    }
    layer.replaceChildren(...children);
  }

  drawPose() {
    const snapshot = this.snapshot;
    if (!snapshot || !this.view || snapshot.dimension === 3) return;
    const display = this.displayedPose();
    const pose = snapshot.pose(display.kind === "cycle" ? "cycle" : "sketch", this.sample);
    const at = (name) => pose[snapshot.pointIndex.get(name)];
    const root = this.ui.canvas.root;
    root.classList.toggle("asd-greyed", display.kind === "invalid");
    root.dataset.pose = display.kind;
    setText(this.ui.note, display.note);
    this.ui.note.hidden = !display.note;
    this.drawLinks(snapshot, at);
    this.drawGuides(snapshot, at);
    this.drawGround(snapshot, at);
    this.drawVectors(snapshot, display.kind === "cycle");
    this.drawInstantCentres(snapshot, display.kind === "cycle");
    this.drawPoints(snapshot, at);
  }

  drawLinks(snapshot, at) {
    const children = [];
    for (const link of snapshot.links) {
      if (link.name === "frame") continue;
      const corners = link.points.map(at).filter(Boolean).map((xy) => this.toScreen(xy));
      if (corners.length < 2) continue;
      const points = corners.map(([x, y]) => `${x.toFixed(2)},${y.toFixed(2)}`).join(" ");
      const tag = corners.length > 2 ? "polygon" : "polyline";
      children.push(svg(tag, {
        class: `asd-link${link.name === this.selectedLink ? " asd-selected" : ""}`, testid: `link-${link.name}`,
        "data-link": link.name, points,
      }));
    }
    // gear pairs: both pitch curves, turned with their links (pivot → arm now against the sketch)
    for (const gear of snapshot.model.gears || []) {
      gear.curves.forEach((curve, i) => {
        const p = at(curve.pivot);
        const q = at(curve.arm);
        if (!p || !q) return;
        const turn = Math.atan2(q[1] - p[1], q[0] - p[0]) - curve.angle0;
        const c = Math.cos(turn);
        const s = Math.sin(turn);
        const points = curve.xy.map(([x, y]) => this.toScreen([p[0] + c * x - s * y, p[1] + s * x + c * y]))
          .map(([x, y]) => `${x.toFixed(2)},${y.toFixed(2)}`).join(" ");
        children.push(svg("polygon", { class: "asd-gear", testid: `gear-${gear.name}-${i ? "b" : "a"}`, points }));
      });
    }
    this.ui.canvas.links.replaceChildren(...children);
  }

  // sliders (a block on a dashed guide line) and actuators (cylinder and rod)
  drawGuides(snapshot, at) {
    const children = [];
    for (const slider of entriesOf(snapshot.model.sliders)) {
      const name = slider.point || slider.link;
      const point = slider.point ? at(slider.point) : (snapshot.links.find((link) => link.name === slider.link) || { points: [] }).points.map(at)[0];
      if (!point) continue;
      let angle = this.sliderAngle(slider);
      if (slider.guide && slider.guide !== "frame") {
        const guide = snapshot.links.find((link) => link.name === slider.guide);
        const [a, b] = guide ? guide.points.map(at) : [];
        if (a && b) angle += Math.atan2(b[1] - a[1], b[0] - a[0]);
      }
      const reach = (this.extent || 1) * 0.6;
      const start = this.toScreen([point[0] - reach * Math.cos(angle), point[1] - reach * Math.sin(angle)]);
      const end = this.toScreen([point[0] + reach * Math.cos(angle), point[1] + reach * Math.sin(angle)]);
      const [sx, sy] = this.toScreen(point);
      const degrees = (-angle * 180) / Math.PI;
      children.push(svg("line", { class: "asd-guide", x1: start[0], y1: start[1], x2: end[0], y2: end[1] }));
      children.push(svg("rect", {
        class: "asd-slider", testid: `slider-${slider.name || name}`, "data-slider": slider.name || name,
        x: sx - 11, y: sy - 7, width: 22, height: 14, transform: `rotate(${degrees.toFixed(2)} ${sx.toFixed(2)} ${sy.toFixed(2)})`,
      }));
    }
    for (const actuator of entriesOf(snapshot.model.actuators)) {
      const [a, b] = (actuator.between || []).map(at);
      if (!a || !b) continue;
      const [ax, ay] = this.toScreen(a); const [bx, by] = this.toScreen(b);
      const mx = (ax + bx) / 2; const my = (ay + by) / 2;
      children.push(svg("line", { class: "asd-cylinder", testid: `actuator-${actuator.name}`, x1: ax, y1: ay, x2: mx + (bx - ax) * 0.1, y2: my + (by - ay) * 0.1 }));
      children.push(svg("line", { class: "asd-rod", x1: mx - (bx - ax) * 0.1, y1: my - (by - ay) * 0.1, x2: bx, y2: by }));
    }
    this.ui.canvas.guides.replaceChildren(...children);
  }

  // a slider's line direction (rad), as the server read it from the document
  sliderAngle(slider) {
    return Number.isFinite(slider.angle_si) ? slider.angle_si : 0;
  }

  drawGround(snapshot, at) {
    const children = [];
    for (const name of snapshot.framePoints) {
      const xy = at(name);
      if (!xy) continue;
      const [x, y] = this.toScreen(xy);
      children.push(svg("path", { class: "asd-ground", d: `M${x},${y} L${x - 10},${y + 14} L${x + 10},${y + 14} Z` }));
      children.push(svg("rect", { class: "asd-hatch", x: x - 14, y: y + 14, width: 28, height: 7, fill: `url(#${this.ui.canvas.ids.hatch})` }));
    }
    for (const driver of entriesOf(snapshot.model.drivers)) {
      const xy = driver.pivot ? at(driver.pivot) : null;
      if (!xy) continue;
      const [x, y] = this.toScreen(xy);
      children.push(svg("circle", { class: "asd-driver", testid: `driver-${driver.name}`, cx: x, cy: y, r: 12 }));
    }
    this.ui.canvas.ground.replaceChildren(...children);
  }

  vectorScales(snapshot) {
    if (snapshot.__vectorScales) return snapshot.__vectorScales;
    const largest = (name) => {
      const array = snapshot.arrays[name];
      if (!array) return 0;
      let best = 0;
      snapshot.movingPoints.forEach((pointName) => {
        const p = snapshot.pointIndex.get(pointName);
        for (let k = 0; k < snapshot.n; k += 1) {
          if (!snapshot.isValid(k)) continue;
          const vector = snapshot.vector(name, k, p);
          const size = Math.hypot(vector[0], vector[1]);
          if (Number.isFinite(size) && size > best) best = size;
        }
      });
      return best;
    };
    snapshot.__vectorScales = { vel: largest("vel"), acc: largest("acc") };
    return snapshot.__vectorScales;
  }

  drawVectors(snapshot, visible) {
    const children = [];
    if (visible) {
      const scales = this.vectorScales(snapshot);
      const screenLength = 0.2 * Math.min(this.size.width, this.size.height);
      for (const kind of ["vel", "acc"]) {
        if (!this.showVectors[kind] || !snapshot.arrays[kind] || !(scales[kind] > 0)) continue;
        for (const name of snapshot.movingPoints) {
          const p = snapshot.pointIndex.get(name);
          const origin = snapshot.vector("pos", this.sample, p);
          const vector = snapshot.vector(kind, this.sample, p);
          if (!vector.every(Number.isFinite)) continue;
          const [x1, y1] = this.toScreen(origin);
          const factor = screenLength / scales[kind];
          children.push(svg("line", {
            class: `asd-vector asd-${kind}`, testid: `${kind}-${name}`, x1, y1,
            x2: x1 + vector[0] * factor, y2: y1 - vector[1] * factor, "data-vx": vector[0], "data-vy": vector[1],
            "marker-end": `url(#${this.ui.canvas.ids[kind]})`,
          }));
        }
      }
    }
    this.ui.canvas.vectors.replaceChildren(...children);
  }

  drawInstantCentres(snapshot, visible) {
    const children = [];
    if (visible && this.showVectors.ic && snapshot.arrays.ic) {
      snapshot.bodyNames.forEach((name, b) => {
        const centre = snapshot.vector("ic", this.sample, b);
        if (!centre || !centre.every(Number.isFinite)) return;
        const [x, y] = this.toScreen(centre);
        if (Math.abs(x) > 1e6 || Math.abs(y) > 1e6) return;
        children.push(svg("g", { class: "asd-ic", testid: `ic-${name}`, "data-x": centre[0], "data-y": centre[1] },
          svg("circle", { cx: x, cy: y, r: 4 }),
          svg("text", { x: x + 6, y: y - 6, text: `I ${name}` })));
      });
    }
    this.ui.canvas.ics.replaceChildren(...children);
  }

  drawPoints(snapshot, at) {
    const children = [];
    const locks = this.locks();
    for (const name of snapshot.pointNames) {
      const xy = at(name);
      if (!xy || !xy.every(Number.isFinite)) continue;
      const [x, y] = this.toScreen(xy);
      const classes = ["asd-point"];
      if (snapshot.framePoints.has(name)) classes.push("asd-frame-point");
      if (name === this.selectedPoint) classes.push("asd-selected");
      if (locks.points.has(name)) classes.push("asd-locked");
      if (this.dragging && this.dragging.point === name) classes.push("asd-dragged");
      children.push(svg("g", { class: "asd-point-group" },
        svg("circle", { class: classes.join(" "), testid: `point-${name}`, "data-point": name, "data-x": xy[0], "data-y": xy[1], cx: x, cy: y, r: 6 }),
        svg("text", { class: "asd-point-label", x: x + 8, y: y - 8, text: name })));
    }
    this.ui.canvas.points.replaceChildren(...children);
  }

  drawTargets() {
    if (!this.view) return;
    const children = this.synth.targets.map((target, index) => {
      const [x, y] = this.toScreen(target);
      return svg("path", { class: "asd-target", testid: `synth-target-${index}`, "data-x": target[0], "data-y": target[1], d: `M${x - 5},${y - 5} L${x + 5},${y + 5} M${x - 5},${y + 5} L${x + 5},${y - 5}` });
    });
    this.ui.canvas.targets.replaceChildren(...children);
    setText(this.ui.synthTargetCount, String(this.synth.targets.length));
  }

  // the marks of a tool waiting for its next click
  drawPending() {
    if (!this.snapshot || !this.view) return;
    const children = [];
    const sketch = (name) => this.snapshot.sketchOf(this.snapshot.pointIndex.get(name));
    for (const item of this.pendingLinkPoints) {
      const xy = item.new ? item.at : sketch(item.name);
      if (!xy) continue;
      const [x, y] = this.toScreen(xy);
      children.push(svg("circle", { class: "asd-pending", cx: x, cy: y, r: 9 }));
    }
    if (this.pendingDriverPivot) {
      const xy = sketch(this.pendingDriverPivot);
      if (xy) { const [x, y] = this.toScreen(xy); children.push(svg("circle", { class: "asd-pending", cx: x, cy: y, r: 9 })); }
    }
    this.ui.canvas.pending.replaceChildren(...children);
  }

  // ---- the 2D canvas: pointer gestures ------------------------------------------------------------------
  onPointerDown(event) {
    if (!this.snapshot || !this.view || this.snapshot.dimension === 3 || event.button !== 0) return;
    const target = event.target;
    const point = target.getAttribute && target.getAttribute("data-point");
    const link = target.getAttribute && target.getAttribute("data-link");
    const slider = target.getAttribute && target.getAttribute("data-slider");
    this.gesture = { pointerId: event.pointerId, startX: event.clientX, startY: event.clientY, moved: false, point, link, slider, startView: { ...this.view } };
    this.ui.canvas.root.setPointerCapture(event.pointerId);
    event.preventDefault();
  }

  onPointerMove(event) {
    const gesture = this.gesture;
    if (!gesture || gesture.pointerId !== event.pointerId) return;
    const distance = Math.hypot(event.clientX - gesture.startX, event.clientY - gesture.startY);
    if (!gesture.moved && distance < DRAG_THRESHOLD_PX) return;
    if (!gesture.moved) {
      gesture.moved = true;
      gesture.kind = gesture.point && this.tool === "select" && !this.ui.synthAddTargets.checked ? "drag" : "pan";
      if (gesture.kind === "drag") this.startDrag(gesture.point);
    }
    if (gesture.kind === "drag") this.previewDrag(event);
    else this.pan(event, gesture);
  }

  onPointerUp(event) {
    const gesture = this.gesture;
    if (!gesture || gesture.pointerId !== event.pointerId) return;
    this.gesture = null;
    if (this.ui.canvas.root.hasPointerCapture(event.pointerId)) this.ui.canvas.root.releasePointerCapture(event.pointerId);
    if (gesture.kind === "drag") this.endDrag();
    else if (!gesture.moved) this.onClick(event, gesture);
  }

  pan(event, gesture) {
    this.view.cx = gesture.startView.cx - (event.clientX - gesture.startX) / this.view.scale;
    this.view.cy = gesture.startView.cy + (event.clientY - gesture.startY) / this.view.scale;
    this.drawScene();
  }

  startDrag(point) {
    this.selectedPoint = point;
    this.selectedLink = null;
    this.dragging = { point, to: null };
    if (this.ui.plotPoint.value !== point) this.ui.plotPoint.value = point;
    this.drawPose();
    this.drawReadouts();
  }

  previewDrag(event) {
    const to = this.toWorld(event);
    this.dragging.to = to;
    this.request("preview", { edits: this.dragEdits() }, performance.now());
  }

  dragEdits() {
    return [{ kind: "move_point", point: this.dragging.point, to: this.dragging.to }];
  }

  endDrag() {
    const drag = this.dragging;
    if (!drag) return;
    if (drag.to) this.commit(this.dragEdits());
    else this.dragging = null;
    // the display stays on the sketch until the commit's answer arrives
  }

  // Esc during a gesture: the committed document comes back
  cancelGesture(sendCancel = false) {
    const wasDragging = Boolean(this.dragging);
    if (this.gesture) {
      const { pointerId } = this.gesture;
      if (this.ui.canvas.root.hasPointerCapture(pointerId)) this.ui.canvas.root.releasePointerCapture(pointerId);
    }
    this.gesture = null;
    this.dragging = null;
    if (wasDragging) {
      if (sendCancel) this.request("cancel");
      if (this.committed) this.showSnapshot(this.committed, this.snapshot);
    }
  }

  onClick(event, gesture) {
    const at = this.toWorld(event);
    if (this.ui.synthAddTargets.checked) {
      this.synth.targets.push(at);
      this.drawTargets();
      return;
    }
    const handlers = {
      select: () => this.clickSelect(gesture),
      "add-point": () => this.clickAddPoint(gesture, at),
      "add-link": () => this.clickAddLink(gesture, at),
      "add-slider": () => this.clickAddSlider(gesture),
      "add-driver": () => this.clickAddDriver(gesture),
      delete: () => this.clickDelete(gesture),
    };
    handlers[this.tool]();
  }

  clickSelect(gesture) {
    if (gesture.point) this.selectPoint(gesture.point);
    else if (gesture.link) this.selectLink(gesture.link);
  }

  clickAddPoint(gesture, at) {
    this.commit([{ kind: "add_point", at, link: gesture.link || "frame" }]);
  }

  newPointName(taken) {
    let index = 1;
    while (taken.has(`P${index}`)) index += 1;
    taken.add(`P${index}`);
    return `P${index}`;
  }

  clickAddLink(gesture, at) {
    const taken = new Set([...this.snapshot.pointNames, ...this.pendingLinkPoints.map((item) => item.name)]);
    const item = gesture.point ? { name: gesture.point } : { name: this.newPointName(taken), at, new: true };
    this.pendingLinkPoints.push(item);
    if (this.pendingLinkPoints.length >= 2) {
      const items = this.pendingLinkPoints;
      this.pendingLinkPoints = [];
      const newPoints = Object.fromEntries(items.filter((i) => i.new).map((i) => [i.name, i.at]));
      const edit = { kind: "add_link", points: items.map((i) => i.name) };
      if (Object.keys(newPoints).length) edit.new_points = newPoints;
      this.commit([edit]);
    }
    this.drawPending();
  }

  clickAddSlider(gesture) {
    if (!gesture.point) return;
    const snapshot = this.snapshot;
    const pin = snapshot.sketchOf(snapshot.pointIndex.get(gesture.point));
    // a horizontal line through the clicked point, given by the nearest frame point and an offset to its left
    let through = null; let best = Infinity;
    for (const name of snapshot.framePoints) {
      const xy = snapshot.sketchOf(snapshot.pointIndex.get(name));
      const distance = Math.hypot(xy[0] - pin[0], xy[1] - pin[1]);
      if (name !== gesture.point && distance < best) { best = distance; through = name; }
    }
    if (!through) { this.setRefusal("a slider needs a frame point for its guide line"); return; }
    const origin = snapshot.sketchOf(snapshot.pointIndex.get(through));
    this.commit([{ kind: "add_slider", point: gesture.point, guide: "frame", through, angle: 0, offset: pin[1] - origin[1] }]);
  }

  clickAddDriver(gesture) {
    if (!gesture.point) return;
    if (!this.pendingDriverPivot) {
      this.pendingDriverPivot = gesture.point;
      this.drawPending();
      return;
    }
    const pivot = this.pendingDriverPivot;
    const arm = gesture.point;
    this.pendingDriverPivot = null;
    this.drawPending();
    const moving = this.snapshot.links.filter((link) => link.name !== "frame");
    const link = moving.find((l) => l.points.includes(pivot) && l.points.includes(arm)) || moving.find((l) => l.points.includes(arm));
    if (!link) { this.setRefusal(`no link carries ${arm}`); return; }
    this.commit([{ kind: "add_driver", link: link.name, pivot, arm, speed: 2 * Math.PI }]);
  }

  clickDelete(gesture) {
    if (gesture.point) this.commit([{ kind: "delete_point", point: gesture.point }]);
    else if (gesture.link) this.commit([{ kind: "delete_link", link: gesture.link }]);
    else if (gesture.slider) this.commit([{ kind: "delete_slider", name: gesture.slider }]);
  }

  // ---- the 3D view (spatial files) ----------------------------------------------------------------------
  // No hover picking (its GPU read-backs log driver warnings) and 2D canvases that read back often (plotly
  // rasterises its 3D text through getImageData): the console stays clean.
  draw3d(full) {
    const Plotly = window.Plotly;
    preferReadbackCanvases();
    const snapshot = this.snapshot;
    if (!Plotly && document.readyState !== "complete") {
      // the page loads plotly after this module: draw once it is there
      if (!this.waitingForPlotly) {
        this.waitingForPlotly = true;
        window.addEventListener("load", () => { this.waitingForPlotly = false; if (this.snapshot) this.drawAll(); }, { once: true });
      }
      setText(this.ui.note, "loading the 3D view…");
      this.ui.note.hidden = false;
      return;
    }
    if (!Plotly || !snapshot.arrays.pos) {
      setText(this.ui.note, Plotly ? "no motion to show" : "the 3D view needs plotly");
      this.ui.note.hidden = false;
      return;
    }
    const convert = this.converter;
    const valid = snapshot.isValid(this.sample);
    const pose = snapshot.pose(valid ? "cycle" : "sketch", this.sample);
    setText(this.ui.note, valid ? "" : "the mechanism does not assemble at this input: showing the sketch");
    this.ui.note.hidden = valid;
    const scaled = (xyz) => (xyz ? xyz.map((v) => convert.length(v)) : [null, null, null]);
    const traces = [];
    for (const link of snapshot.links) {
      const corners = link.points.map((name) => scaled(pose[snapshot.pointIndex.get(name)]));
      if (corners.length > 2) corners.push(corners[0]);
      traces.push({
        type: "scatter3d", mode: link.name === "frame" ? "markers" : "lines+markers", name: link.name,
        x: corners.map((c) => c[0]), y: corners.map((c) => c[1]), z: corners.map((c) => c[2] ?? 0),
        line: { width: 6 }, marker: { size: 4 }, hoverinfo: "skip",
      });
    }
    if (full || !this.pathTraces3d) {
      this.pathTraces3d = snapshot.movingPoints.map((name) => {
        const p = snapshot.pointIndex.get(name);
        const xs = []; const ys = []; const zs = [];
        for (let k = 0; k < snapshot.n; k += 1) {
          const xyz = snapshot.isValid(k) ? scaled(snapshot.vector("pos", k, p)) : [null, null, null];
          xs.push(xyz[0]); ys.push(xyz[1]); zs.push(xyz[2] ?? 0);
        }
        return { type: "scatter3d", mode: "lines", name: `path ${name}`, x: xs, y: ys, z: zs, line: { width: 2, dash: "dot" }, connectgaps: false, hoverinfo: "skip" };
      });
    }
    const axis = (title) => ({ title: `${title} (${convert.lengthLabel})` });
    // the camera and zoom the user chose carry over from the previous drawing
    const previous = (this.ui.view3d.layout && this.ui.view3d.layout.scene) || {};
    const scene = { aspectmode: "data", hovermode: false, xaxis: axis("x"), yaxis: axis("y"), zaxis: axis("z") };
    for (const key of ["camera", "aspectmode", "aspectratio"]) if (previous[key]) scene[key] = previous[key];
    const layout = { margin: { l: 0, r: 0, t: 0, b: 0 }, showlegend: false, hovermode: false, scene };
    Plotly.react(this.ui.view3d, [...this.pathTraces3d, ...traces], layout, { displaylogo: false, responsive: true, logging: 0 });
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
