// The pointer gestures on the 2D canvas (drag, pan, click) and the tools' clicks. Methods of the Designer (mixed in
// by designer.js; one part of designer.js: see assembly.py).

import { DRAG_THRESHOLD_PX } from "./util.js";

export class GesturesPart {
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
}
