// The side panels of the designer: mechanism, selection, drivers, parameters, gait, torque, point plots and
// diagnostics. Methods of the Designer (mixed in by designer.js; one part of designer.js: see assembly.py).

import { GAIT_LENGTHS, GAIT_SPEEDS, formatNumber, html, svg, setText, namesOf, entriesOf, brokenPath } from "./util.js";

export class PanelsPart {
  buildSidePanel(ui) {
    ui.refusal = html("div", { class: "asd-refusal", testid: "refusal", role: "alert" });
    ui.resumed = html("div", { class: "asd-resumed", testid: "resumed", hidden: true });
    ui.status = html("div", { class: "asd-status", testid: "status" });
    ui.formula = html("div", { class: "asd-formula", testid: "formula" });
    ui.assembled = html("span", { testid: "assembled-count", text: "0" });
    ui.groups = html("div", { class: "asd-groups", testid: "groups" });
    const mechanism = this.section("Mechanism", "mechanism-panel",
      ui.formula, html("div", {}, "assembled samples: ", ui.assembled), ui.groups);
    const chooser = this.buildChooserPanel(ui);

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
      const box = html("input", { type: "checkbox", testid, checked: this.showVectors[key] });
      box.addEventListener("change", () => { this.showVectors[key] = box.checked; this.drawPose(); });
      return html("label", { class: "asd-row" }, box, ` ${label}`);
    };
    const display = this.section("Display", "display-panel",
      toggle("vel", "show-vel", "velocity vectors"), toggle("acc", "show-acc", "acceleration vectors"),
      toggle("ic", "show-ic", "instant centres"), toggle("kennedy", "show-kennedy", "all centres (Kennedy)"));

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
    const motor = this.buildMotorPanel(ui);
    ui.diagnostics = html("ul", { class: "asd-diagnostics", testid: "diagnostics" });
    const diagnostics = this.section("Diagnostics", "diagnostics-panel", ui.diagnostics);

    return html("aside", { class: "asd-side" }, ui.refusal, ui.resumed, ui.status, mechanism, chooser, selection, display, drivers,
      ui.paramsPanel, ui.gaitPanel, ui.torquePanel, motor, pointPlot, synth, diagnostics);
  }

  section(title, testid, ...children) {
    return html("section", { class: "asd-section", testid }, html("h3", { text: title }), ...children);
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

  // a line plot of one or more series (each scaled to its own range) with gaps where invalid, and axis ticks: the
  // input along x (every quarter turn of a crank), the first series' range on the left, the second's on the right
  linePlot(target, series, width, height) {
    const inputs = this.plotInputs();
    const margin = { left: 40, right: series.length > 1 ? 40 : 8, top: 16, bottom: 24 };
    const children = [svg("rect", { class: "asd-plot-frame", x: margin.left, y: margin.top, width: width - margin.left - margin.right, height: height - margin.top - margin.bottom })];
    if (!inputs || !inputs.xs.length) { target.replaceChildren(...children); return; }
    const { xs } = inputs;
    const x0 = Math.min(...xs); const x1 = Math.max(...xs);
    const toX = (x) => margin.left + ((x - x0) / (x1 - x0 || 1)) * (width - margin.left - margin.right);
    const bottom = height - margin.bottom;
    const tick = (axis, value, x, y, anchor, cls = "") => svg("text", {
      class: `asd-plot-tick ${cls}`, x, y, "text-anchor": anchor, "data-axis": axis, "data-value": value, text: formatNumber(value),
    });
    for (const value of this.inputTicks(x0, x1)) {
      const x = toX(value);
      children.push(svg("line", { class: "asd-plot-grid", x1: x, x2: x, y1: bottom, y2: bottom + 3 }));
      children.push(tick("x", value, x, bottom + 12, "middle"));
    }
    series.forEach((serie, index) => {
      const finite = serie.ys.filter((y, k) => Number.isFinite(y) && this.snapshot.isValid(k));
      const y0 = Math.min(0, ...finite); const y1 = Math.max(0, ...finite);
      const toY = (y) => bottom - ((y - y0) / (y1 - y0 || 1)) * (height - margin.top - margin.bottom);
      const samples = serie.ys.map((y, k) => (this.snapshot.isValid(k) && Number.isFinite(y) ? [toX(xs[k]), toY(y)] : null));
      const { d, runs } = brokenPath(samples);
      children.push(svg("path", { class: `asd-plot-line ${serie.cls}`, d, "data-runs": runs, testid: serie.testid }));
      if (finite.length && y0 < 0 && y1 > 0) children.push(svg("line", { class: "asd-plot-zero", x1: margin.left, x2: width - margin.right, y1: toY(0), y2: toY(0) }));
      children.push(svg("text", { class: `asd-plot-label ${serie.cls}`, x: margin.left + 2 + index * ((width - margin.left) / 2), y: 11, text: `${serie.label} max ${formatNumber(finite.length ? Math.max(...finite.map(Math.abs)) : NaN)} ${serie.unit}` }));
      if (index < 2 && finite.length) {
        const left = index === 0;
        const x = left ? margin.left - 3 : width - margin.right + 3;
        const values = [...new Set([y0, 0, y1])].filter((v) => v === 0 || Math.abs(toY(v) - toY(0)) > 8);
        for (const value of values) children.push(tick(`y${index}`, value, x, toY(value) + 3, left ? "end" : "start", serie.cls));
      }
    });
    const cursor = svg("line", { class: "asd-plot-cursor", y1: margin.top, y2: bottom });
    children.push(cursor);
    children.push(svg("text", { class: "asd-plot-axis", x: width - margin.right, y: height - 1, "text-anchor": "end", text: `input (${inputs.label})` }));
    target.replaceChildren(...children);
    target.__cursor = { element: cursor, xs, toX };
    this.placeCursor(target);
  }

  // the input values that get a tick: every quarter turn of a crank (in the angle unit on display), or the two ends
  // and the middle of a linear driver's stroke
  inputTicks(x0, x1) {
    if (this.isLinearInput() || !(x1 > x0)) return x1 > x0 ? [x0, (x0 + x1) / 2, x1] : [x0];
    const quarter = this.converter.angle(Math.PI / 2);
    const out = [];
    for (let k = Math.ceil(x0 / quarter - 1e-9); k * quarter <= x1 + 1e-9 * quarter; k += 1) out.push(k * quarter);
    return out;
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
}
