// The chooser of assemblies of a mechanism with a Newton-solved group (a class-III triad, …): every assembly the
// engine finds at the current input, the current one marked, each drawn as a ghost on the canvas while the pointer is
// on its row, and Choose puts the sketch on it (one undo step). Methods of the Designer (mixed in by designer.js; one
// part of designer.js: see assembly.py).

import { formatNumber, html, svg, setText } from "./util.js";

// the list follows the scrub bar once it has rested this long (ms): no request per frame while playing or scrubbing
export const CHOOSER_DELAY_MS = 120;

export class ChooserPart {
  buildChooserPanel(ui) {
    ui.chooserInput = html("span", { testid: "assemblies-input", text: "—" });
    ui.chooserInputUnit = html("span", { class: "asd-unit" });
    ui.chooserList = html("div", { class: "asd-assemblies", testid: "assemblies-list" });
    ui.chooserStatus = html("div", { class: "asd-muted", testid: "assemblies-status" });
    ui.chooserPanel = this.section("Assemblies", "assemblies-panel",
      html("div", { class: "asd-row" }, "at the input ", ui.chooserInput, " ", ui.chooserInputUnit), ui.chooserList, ui.chooserStatus);
    ui.chooserPanel.hidden = true;
    this.chooser = { message: null, key: null, asked: null, timer: null, hover: null };
    return ui.chooserPanel;
  }

  chooserShown() {
    const snapshot = this.snapshot;
    return Boolean(snapshot && snapshot.model.chooser && snapshot.dimension === 2 && snapshot.cycle && snapshot.arrays.q);
  }

  // the list belongs to one committed document and one input
  chooserKey() {
    const toml = this.committed ? this.committed.message.toml : "";
    return `${toml.length}:${hashText(toml)}|${this.sample}`;
  }

  // after a result or a move of the scrub bar: ask for the list at the current input once the bar rests
  refreshChooser() {
    const shown = this.chooserShown();
    this.ui.chooserPanel.hidden = !shown;
    if (!shown) { this.setChooserGhost(null); return; }
    this.drawChooser();
    if (this.dragging || this.committed !== this.snapshot) return;
    const key = this.chooserKey();
    if (key === this.chooser.key || key === this.chooser.asked) return;
    clearTimeout(this.chooser.timer);
    this.chooser.timer = setTimeout(() => {
      if (this.playing || this.dragging || !this.chooserShown() || this.chooserKey() !== key) return;
      this.chooser.asked = key;
      const input = this.snapshot.cycle.input || {};
      this.request("assemblies", { input: this.snapshot.arrays.q[this.sample], index: input.index ?? 0 });
    }, CHOOSER_DELAY_MS);
  }

  onAssemblies(message, request) {
    this.setChooserGhost(null);
    if (message.type === "refused") {
      this.chooser.message = null;
      setText(this.ui.chooserStatus, message.message || "refused");
    } else {
      this.chooser.message = message;
      setText(this.ui.chooserStatus, "");
    }
    this.chooser.key = this.chooser.asked;
    this.chooser.asked = null;
    this.global.assemblies = this.chooser.message;
    this.drawChooser();
    // the bar moved on meanwhile: ask again
    if (request && this.chooserShown() && this.chooserKey() !== this.chooser.key) this.refreshChooser();
  }

  drawChooser() {
    const message = this.chooser.message;
    const current = message && this.chooser.key === this.chooserKey();
    const linear = this.isLinearInput();
    const convert = this.converter;
    setText(this.ui.chooserInput, message ? formatNumber(convert.input(message.input, linear)) : "—");
    setText(this.ui.chooserInputUnit, convert.inputLabel(linear));
    this.ui.chooserList.classList.toggle("asd-stale", !current);
    const rows = (message ? message.assemblies : []).map((entry) => {
      const choose = html("button", {
        type: "button", testid: `assembly-choose-${entry.index}`, text: entry.current ? "current" : "Choose",
        disabled: entry.current || !current || Boolean(this.dragging),
        title: entry.current ? "the mechanism is on this assembly" : "put the sketch on this assembly (one undo step)",
      });
      choose.addEventListener("click", () => this.chooseAssembly(entry));
      const row = html("div", {
        class: `asd-row asd-assembly${entry.current ? " asd-current" : ""}`, testid: `assembly-${entry.index}`,
        "data-current": entry.current, "data-branches": JSON.stringify(entry.branches),
      }, html("span", { class: "asd-assembly-label", text: `${entry.index + 1}. ${entry.label}` }),
      entry.certified ? null : html("span", { class: "asd-diag-warning", title: "next to a singular position: two assemblies may not be told apart", text: " (uncertain)" }),
      choose);
      row.addEventListener("pointerenter", () => this.setChooserGhost(entry));
      row.addEventListener("pointerleave", () => this.setChooserGhost(null));
      return row;
    });
    if (message && !rows.length) rows.push(html("div", { class: "asd-muted", text: "the mechanism does not assemble at this input" }));
    this.ui.chooserList.replaceChildren(...rows);
  }

  chooseAssembly(entry) {
    const message = this.chooser.message;
    if (!message) return;
    this.setChooserGhost(null);
    this.commit([{ kind: "assembly", input: message.input, index: message.index, branches: entry.branches }]);
  }

  // an assembly's links, dashed, over the mechanism on the canvas (null: none)
  setChooserGhost(entry) {
    this.chooser.hover = entry;
    const layer = this.ui.canvas.ghost;
    if (!entry || !this.view || !this.chooser.message) { layer.replaceChildren(); return; }
    const order = this.chooser.message.point_order;
    const at = (name) => entry.positions[order.indexOf(name)];
    const children = [];
    for (const link of this.snapshot.links) {
      if (link.name === "frame") continue;
      const corners = link.points.map(at).filter(Boolean).map((xy) => this.toScreen(xy));
      if (corners.length < 2) continue;
      const points = corners.map(([x, y]) => `${x.toFixed(2)},${y.toFixed(2)}`).join(" ");
      children.push(svg(corners.length > 2 ? "polygon" : "polyline", { class: "asd-ghost", testid: `ghost-${link.name}`, points }));
    }
    layer.replaceChildren(...children);
  }
}

// a short digest of a text (the chooser's key of a document): FNV-1a, 32 bits
export function hashText(text) {
  let h = 0x811c9dc5;
  for (let i = 0; i < text.length; i += 1) {
    h ^= text.charCodeAt(i);
    h = Math.imul(h, 0x01000193) >>> 0;
  }
  return h.toString(16);
}
