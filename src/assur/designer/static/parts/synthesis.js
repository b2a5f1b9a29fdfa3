// The path-synthesis panel of the designer and its targets on the canvas. Methods of the Designer (mixed in by
// designer.js; one part of designer.js: see assembly.py).

import { formatNumber, html, svg, setText } from "./util.js";

// the budget a run gets unless the user types another: on the 11 shipped closed-form examples, with six targets off a
// point's path by 5 % of the mechanism's size, it halved the targets' distance in every run, in 3.2 s median (300
// did in 3 of 11; benchmarks/designer_synthesis_results.md)
export const SYNTH_DEFAULT_BUDGET = 2000;

export class SynthesisPart {
  buildSynthPanel(ui) {
    ui.synthPoint = html("select", { testid: "synth-point" });
    ui.synthAddTargets = html("input", { type: "checkbox", testid: "synth-add-targets" });
    ui.synthClear = html("button", { type: "button", testid: "synth-clear", text: "Clear targets" });
    ui.synthBudget = html("input", { type: "number", testid: "synth-budget", min: 100, step: 100, value: SYNTH_DEFAULT_BUDGET });
    ui.synthRun = html("button", { type: "button", testid: "synth-run", text: "Run" });
    ui.synthCancel = html("button", { type: "button", testid: "synth-cancel", text: "Cancel", disabled: true });
    ui.synthInsert = html("button", { type: "button", testid: "synth-insert", text: "Insert best", disabled: true });
    ui.synthProgress = html("span", { testid: "synth-progress", text: "0" });
    ui.synthBest = html("span", {
      testid: "synth-best", text: "—", title: "the best design's sum of the targets' distances to the point's path",
    });
    ui.synthBestUnit = html("span", { testid: "synth-best-unit", class: "asd-unit" });
    ui.synthStatus = html("span", { testid: "synth-status", class: "asd-muted" });
    ui.synthTargetCount = html("span", { testid: "synth-count", text: "0" });
    return this.section("Path synthesis", "synth-panel",
      html("label", { class: "asd-row" }, "point ", ui.synthPoint),
      html("label", { class: "asd-row" }, ui.synthAddTargets, " click on the canvas to add targets (", ui.synthTargetCount, ")"),
      html("label", { class: "asd-row" }, "budget ", ui.synthBudget, " evaluations"),
      html("div", { class: "asd-row" }, ui.synthRun, ui.synthCancel, ui.synthClear, ui.synthInsert),
      html("div", { class: "asd-row" }, "evaluations ", ui.synthProgress, " · best ", ui.synthBest, " ", ui.synthBestUnit,
        " ", ui.synthStatus));
  }

  onSynth(update) {
    Object.assign(this.synth, update);
    this.global.synth = this.synth;
    this.drawSynth();
  }

  // ---- synthesis ----------------------------------------------------------------------------------------
  startSynthesis() {
    const point = this.ui.synthPoint.value;
    this.synth.point = point;
    const budget = Math.round(Number(this.ui.synthBudget.value) || SYNTH_DEFAULT_BUDGET);
    this.onSynth({ running: true, status: "starting", evaluations: 0, best: null, toml: null });
    this.request("synth_start", { point, targets: this.synth.targets.map(([x, y]) => [x, y]), budget, seed: 1 });
  }

  drawSynth() {
    const synth = this.synth;
    setText(this.ui.synthProgress, String(synth.evaluations ?? 0));
    // the cost is a length (m): shown in the length unit on display
    const convert = this.converter;
    const known = synth.best !== null && synth.best !== undefined && Number.isFinite(synth.best);
    setText(this.ui.synthBest, known ? formatNumber(convert.length(synth.best)) : "—");
    setText(this.ui.synthBestUnit, known ? convert.lengthLabel : "");
    setText(this.ui.synthStatus, synth.status || "");
    setText(this.ui.synthTargetCount, String(synth.targets.length));
    this.ui.synthCancel.disabled = !synth.running;
    this.ui.synthRun.disabled = synth.running;
    this.ui.synthInsert.disabled = synth.running || !synth.toml;
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
}
