// Text labels pinned to points of the 3D scene (the probes' numbers, the isolux values), as HTML
// elements over the canvas: they read upright from every side and at every distance. A label that
// would cover one already placed is hidden until the view leaves room for it (isolux values are
// placed first), so that a large grid seen from afar does not turn into a smear of digits.

import * as THREE from "three";

const kBucket = 32; // px: the side of the cells of the lookup of placed labels

export class LabelLayer {
  constructor(container) {
    this.container = container;
    this.labels = []; // {positions, element, width, height, priority}
  }

  // Replaces every label. labels: {positions: [THREE.Vector3, ...] (the places it may take, in order of
  // preference), text, kind, priority}.
  set(labels) {
    this.container.replaceChildren();
    this.labels = labels.map((label) => {
      const element = document.createElement("span");
      element.className = `label label-${label.kind}`;
      element.textContent = label.text;
      if (label.value !== undefined) element.dataset.value = String(label.value);
      if (label.probe !== undefined) element.dataset.probe = label.probe;
      this.container.append(element);
      return { ...label, element };
    });
    this.labels.sort((a, b) => a.priority - b.priority);
    this.measured = false;
  }

  // Places the labels for `camera` on a canvas of width × height CSS pixels.
  update(camera, width, height, visible) {
    this.container.hidden = !visible;
    if (!visible) return;
    if (!this.measured) {
      // Once, in one layout pass, while the layer is shown (hidden elements measure 0).
      for (const label of this.labels) label.element.hidden = false;
      for (const label of this.labels) {
        label.width = label.element.offsetWidth;
        label.height = label.element.offsetHeight;
      }
      this.measured = true;
    }
    const placed = new Map(); // bucket → boxes
    const overlaps = (box) => {
      for (let bx = Math.floor(box.x0 / kBucket); bx <= Math.floor(box.x1 / kBucket); ++bx) {
        for (let by = Math.floor(box.y0 / kBucket); by <= Math.floor(box.y1 / kBucket); ++by) {
          for (const other of placed.get(`${bx},${by}`) ?? []) {
            if (box.x0 < other.x1 && other.x0 < box.x1 && box.y0 < other.y1 && other.y0 < box.y1) return true;
          }
        }
      }
      return false;
    };
    const place = (box) => {
      for (let bx = Math.floor(box.x0 / kBucket); bx <= Math.floor(box.x1 / kBucket); ++bx) {
        for (let by = Math.floor(box.y0 / kBucket); by <= Math.floor(box.y1 / kBucket); ++by) {
          const key = `${bx},${by}`;
          if (!placed.has(key)) placed.set(key, []);
          placed.get(key).push(box);
        }
      }
    };
    const p = new THREE.Vector3();
    const boxAt = (label, position) => {
      p.copy(position).project(camera);
      const x = ((p.x + 1) / 2) * width, y = ((1 - p.y) / 2) * height;
      const box = { x0: x - label.width / 2, y0: y - label.height / 2, x1: x + label.width / 2, y1: y + label.height / 2 };
      const free = p.z < 1 && box.x1 > 0 && box.x0 < width && box.y1 > 0 && box.y0 < height && !overlaps(box);
      return free ? box : null;
    };
    for (const label of this.labels) {
      let box = null;
      for (const position of label.positions) if ((box = boxAt(label, position))) break;
      label.element.hidden = !box;
      if (!box) continue;
      place(box);
      label.element.style.transform = `translate(${box.x0}px, ${box.y0}px)`;
    }
  }
}
