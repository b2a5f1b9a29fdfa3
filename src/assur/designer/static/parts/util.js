// Units, small DOM and geometry helpers of the designer's page (one part of designer.js: see assembly.py).

export const SVG_NS = "http://www.w3.org/2000/svg";
export const SHARE_FORMAT = 1;
export const DRAG_THRESHOLD_PX = 3;
export const REQUEST_TIMEOUT_MS = 20000;

// ---------------------------------------------------------------------------------------------------------
// Units (display only)

export const LENGTH_FACTORS = { m: 1, mm: 1000 };
export const ANGLE_FACTORS = { rad: 1, deg: 180 / Math.PI };
export const SPEED_FACTORS = { "rad/s": 1, rpm: 60 / (2 * Math.PI) };
export const ANGLE_LABELS = { rad: "rad", deg: "°" };
export const GAIT_LENGTHS = new Set(["step_length", "lift", "sag"]);
export const GAIT_SPEEDS = new Set(["support_speed_mean"]);

export function formatNumber(value) {
  if (value === null || value === undefined || !Number.isFinite(value)) return "—";
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude >= 1e7 || magnitude < 1e-5)) return value.toExponential(4);
  return String(Number(value.toPrecision(6)));
}

export class UnitConverter {
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

export function html(tag, attrs = {}, ...children) {
  const element = document.createElement(tag);
  applyAttributes(element, attrs);
  for (const child of children.flat()) {
    if (child === null || child === undefined || child === false) continue;
    element.append(typeof child === "string" ? document.createTextNode(child) : child);
  }
  return element;
}

export function svg(tag, attrs = {}, ...children) {
  const element = document.createElementNS(SVG_NS, tag);
  applyAttributes(element, attrs);
  for (const child of children.flat()) {
    if (child === null || child === undefined) continue;
    element.append(typeof child === "string" ? document.createTextNode(child) : child);
  }
  return element;
}

export function applyAttributes(element, attrs) {
  for (const [key, value] of Object.entries(attrs)) {
    if (value === null || value === undefined || value === false) continue;
    if (key === "testid") element.setAttribute("data-testid", value);
    else if (key === "text") element.textContent = value;
    else if (key.startsWith("on") && typeof value === "function") element.addEventListener(key.slice(2), value);
    else element.setAttribute(key, value === true ? "" : String(value));
  }
}

export function setText(element, text) {
  if (element.textContent !== text) element.textContent = text;
}

export function namesOf(list) {
  if (!list) return [];
  if (Array.isArray(list)) return list.map((item) => (typeof item === "string" ? item : item.name));
  return Object.keys(list);
}

export function entriesOf(list) {
  // a model list given as an array of {name, ...} or as a table {name: {...}}
  if (!list) return [];
  if (Array.isArray(list)) return list.map((item) => (typeof item === "string" ? { name: item } : item));
  return Object.entries(list).map(([name, value]) => ({ name, ...value }));
}

// ---------------------------------------------------------------------------------------------------------
// Geometry helpers

export function bounds(pointsList) {
  let minX = Infinity; let minY = Infinity; let maxX = -Infinity; let maxY = -Infinity;
  for (const [x, y] of pointsList) {
    if (!Number.isFinite(x) || !Number.isFinite(y)) continue;
    minX = Math.min(minX, x); maxX = Math.max(maxX, x); minY = Math.min(minY, y); maxY = Math.max(maxY, y);
  }
  if (!Number.isFinite(minX)) return null;
  return { minX, minY, maxX, maxY };
}

export function wrapAngle(a) {
  return Math.atan2(Math.sin(a), Math.cos(a));
}

// the sample of the cycle nearest to an input value
export function sampleOfInput(qArray, q, linear) {
  let best = 0; let bestDistance = Infinity;
  for (let k = 0; k < qArray.length; k += 1) {
    const distance = Math.abs(linear ? qArray[k] - q : wrapAngle(qArray[k] - q));
    if (distance < bestDistance) { bestDistance = distance; best = k; }
  }
  return best;
}

// an SVG path through (x, y) samples, broken (a new "M") wherever a sample is missing
export function brokenPath(samples) {
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
export function preferReadbackCanvases() {
  const prototype = HTMLCanvasElement.prototype;
  if (prototype.getContext.__assurReadback) return;
  const original = prototype.getContext;
  const getContext = function getContext(type, options) {
    return original.call(this, type, type === "2d" && options === undefined ? { willReadFrequently: true } : options);
  };
  getContext.__assurReadback = true;
  prototype.getContext = getContext;
}
