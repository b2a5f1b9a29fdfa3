// The channel to the server: decoding a result's arrays, the request channel (one request in flight, the newest
// pending request of a kind wins) and share links (one part of designer.js: see assembly.py).

import { SHARE_FORMAT, REQUEST_TIMEOUT_MS, namesOf, entriesOf } from "./util.js";

export function messageType(message) {
  return message.type ?? message.op ?? message.kind;
}

// ---------------------------------------------------------------------------------------------------------
// Arrays of a result: little-endian float64 in the message's first buffer

export function bytesOf(buffer) {
  if (!buffer) return null;
  if (buffer instanceof ArrayBuffer) return new Uint8Array(buffer);
  if (ArrayBuffer.isView(buffer)) return new Uint8Array(buffer.buffer, buffer.byteOffset, buffer.byteLength);
  return null;
}

export function decodeArrays(message, buffers) {
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
export class Snapshot {
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

export const REPLACEABLE_OPS = new Set(["preview", "set_params"]);
export const SUPERSEDED_BY = {
  commit: ["preview"], cancel: ["preview"], preview: ["preview"], set_params: ["set_params"], assemblies: ["assemblies"],
};
export const ANSWER_TYPES = {
  save: ["saved", "refused", "error"],
  synth_start: ["synth_started", "synth_done", "refused", "error"],
  synth_cancel: ["synth_done", "refused", "error"],
  motor_start: ["motor_started", "motor_done", "refused", "error"],
  motor_cancel: ["motor_done", "refused", "error"],
  assemblies: ["assemblies", "refused", "error"],
};
export const DEFAULT_ANSWER_TYPES = ["result", "refused", "error"];

export class RequestChannel {
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

export function bytesToBase64Url(bytes) {
  let binary = "";
  for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(binary).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

export function base64UrlToBytes(text) {
  const base64 = text.replace(/-/g, "+").replace(/_/g, "/");
  const binary = atob(base64 + "=".repeat((4 - (base64.length % 4)) % 4));
  return Uint8Array.from(binary, (c) => c.charCodeAt(0));
}

export async function pipeBytes(bytes, stream) {
  const output = new Blob([bytes]).stream().pipeThrough(stream);
  return new Uint8Array(await new Response(output).arrayBuffer());
}

export const shareCodec = {
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
