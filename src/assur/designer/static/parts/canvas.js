// The 2D canvas of the designer: view and drawing, and the 3D view of a spatial file (the pointer gestures and
// the tools' clicks are in gestures.js). Methods of the Designer (mixed in by designer.js; see assembly.py).

import { svg, setText, entriesOf, bounds, brokenPath, preferReadbackCanvases } from "./util.js";

export class CanvasPart {
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
    for (const name of ["paths", "guides", "links", "ghost", "ground", "vectors", "ics", "points", "targets", "pending"]) canvas[name] = layer(name);
    return canvas;
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
    const box = this.drawingBounds(snapshot) || { minX: -1, minY: -1, maxX: 1, maxY: 1 };
    const spanX = Math.max(box.maxX - box.minX, 1e-6);
    const spanY = Math.max(box.maxY - box.minY, 1e-6);
    const span = Math.max(spanX, spanY);
    const marginFactor = 1.25;
    const scale = Math.min(this.size.width / (Math.max(spanX, span * 0.2) * marginFactor), this.size.height / (Math.max(spanY, span * 0.2) * marginFactor));
    this.view = { cx: (box.minX + box.maxX) / 2, cy: (box.minY + box.maxY) / 2, scale };
    this.extent = span;
  }

  // the bounding box of the sketch and of every point's path (world coordinates), or null
  drawingBounds(snapshot) {
    const samples = [];
    for (let p = 0; p < snapshot.pointNames.length; p += 1) {
      const sketch = snapshot.sketchOf(p);
      if (sketch) samples.push(sketch);
      for (let k = 0; k < snapshot.n; k += 1) if (snapshot.isValid(k)) samples.push(snapshot.vector("pos", k, p));
    }
    return bounds(samples);
  }

  // whether the whole drawing of a result lies inside the canvas at the current view
  fitsView(snapshot) {
    if (!this.view || snapshot.dimension === 3) return true;
    const box = this.drawingBounds(snapshot);
    if (!box) return true;
    const [x0, y0] = this.toScreen([box.minX, box.maxY]);
    const [x1, y1] = this.toScreen([box.maxX, box.minY]);
    return x0 >= 0 && y0 >= 0 && x1 <= this.size.width && y1 <= this.size.height;
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
    // cam pairs: the profile turned with its cam, the follower's roller at its trace point
    for (const cam of snapshot.model.cams || []) {
      const p = at(cam.pivot);
      const q = at(cam.arm);
      if (!p || !q) continue;
      const turn = Math.atan2(q[1] - p[1], q[0] - p[0]) - cam.angle0;
      const c = Math.cos(turn);
      const s = Math.sin(turn);
      const points = cam.xy.map(([x, y]) => this.toScreen([p[0] + c * x - s * y, p[1] + s * x + c * y]))
        .map(([x, y]) => `${x.toFixed(2)},${y.toFixed(2)}`).join(" ");
      children.push(svg("polygon", { class: "asd-cam", testid: `cam-${cam.name}`, points }));
      const r = at(cam.point);
      if (r && cam.roller > 0) {
        const [cx, cy] = this.toScreen(r);
        const [ex] = this.toScreen([r[0] + cam.roller, r[1]]);
        children.push(svg("circle", { class: "asd-cam-roller", cx, cy, r: Math.abs(ex - cx) }));
      }
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
    // a passive cylinder on its other branch (its RPR group's rod hinge behind the cylinder's hinge) points away
    const behind = new Set(entriesOf(snapshot.model.groups).filter((g) => g.kind === "RPR" && g.branch === -1).map((g) => g.slide));
    for (const actuator of entriesOf(snapshot.model.actuators)) {
      const [a, b] = (actuator.between || []).map(at);
      if (!a || !b) continue;
      const [ax, ay] = this.toScreen(a); const [bx, by] = this.toScreen(b);
      const s = behind.has(actuator.name) ? -1 : 1;
      const cx = ax + s * (bx - ax) * 0.6; const cy = ay + s * (by - ay) * 0.6;
      const rx = ax + s * (bx - ax) * 0.4; const ry = ay + s * (by - ay) * 0.4;
      children.push(svg("line", { class: "asd-cylinder", testid: `actuator-${actuator.name}`, "data-behind": s < 0, x1: ax, y1: ay, x2: cx, y2: cy }));
      children.push(svg("line", { class: "asd-rod", testid: `rod-${actuator.name}`, x1: rx, y1: ry, x2: bx, y2: by }));
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
          // below and right of the centre: a point's label sits above and right of it, and a crank's or a rocker's
          // centre is its pivot
          svg("text", { class: "asd-ic-label", testid: `ic-label-${name}`, x: x + 6, y: y + 16, text: `I ${name}` })));
      });
    }
    children.push(...this.kennedyCentres(snapshot, visible));
    this.ui.canvas.ics.replaceChildren(...children);
  }

  // every relative instant centre (labelled by its two bodies' numbers) and Kennedy's lines through each triple
  kennedyCentres(snapshot, visible) {
    const pairs = snapshot.model.centre_pairs || [];
    if (!visible || !this.showVectors.kennedy || !snapshot.arrays.centres || !pairs.length) return [];
    const at = (c) => {
      const xy = snapshot.vector("centres", this.sample, c);
      return xy && xy.every(Number.isFinite) ? this.toScreen(xy) : null;
    };
    const out = [];
    for (const triple of snapshot.model.kennedy || []) {
      const ends = triple.map(at).filter(Boolean);
      if (ends.length < 2) continue;
      const [[x0, y0], [x1, y1]] = [ends[0], ends[ends.length - 1]];
      const d = Math.hypot(x1 - x0, y1 - y0);
      if (!(d > 1e-6)) continue;
      const k = 4000 / d;
      out.push(svg("line", { class: "asd-kennedy", x1: x0 - k * (x1 - x0), y1: y0 - k * (y1 - y0),
                             x2: x0 + k * (x1 - x0), y2: y0 + k * (y1 - y0) }));
    }
    pairs.forEach(([i, j], c) => {
      const xy = at(c);
      if (!xy || Math.abs(xy[0]) > 1e6 || Math.abs(xy[1]) > 1e6) return;
      out.push(svg("g", { class: "asd-centre", testid: `centre-${i}-${j}` },
        svg("circle", { cx: xy[0], cy: xy[1], r: 3 }), svg("text", { x: xy[0] + 4, y: xy[1] + 12, text: `${i}${j}` })));
    });
    return out;
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
        svg("text", { class: "asd-point-label", testid: `label-${name}`, x: x + 8, y: y - 8, text: name })));
    }
    this.ui.canvas.points.replaceChildren(...children);
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
}
