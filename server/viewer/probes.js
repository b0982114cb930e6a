// The result's probes in the viewer: each point as a dot with its illuminance written beside it, and
// on every grid its isolux lines (marching squares, isolines.js) at the round values of the grid's
// own scale, strictly inside its range (the levels of `lambert render --probe-grid`,
// server/grid_map.h). Dots and lines are three.js objects in the scene; the numbers are HTML labels
// (labels.js) so that they read upright from every side.

import * as THREE from "three";
import { colourScale, scaleTicks, tickLabel } from "./colour_scale.js";
import { isolines } from "./isolines.js";

const kIsoluxTicks = 12; // as server/grid_map.cpp

// A probe as the .glb carries it (server/export/gltf_writer.cpp): a POINTS node named after the
// probe, extras {probe: "grid" | "point", nu, nv}, positions in metres, attribute _ILLUMINANCE_LX.
export function probeFromObject(object) {
  const extras = object.userData;
  const position = object.geometry.getAttribute("position");
  const lux = object.geometry.getAttribute("_illuminance_lx");
  if (!position || !lux || lux.count !== position.count)
    throw new Error(`probe ${extras.name ?? object.name}: the file has no illuminance for its points`);
  const nu = Number(extras.nu ?? 1), nv = Number(extras.nv ?? 1);
  const isGrid = extras.probe === "grid";
  if (isGrid && nu * nv !== position.count)
    throw new Error(`probe ${extras.name}: ${position.count} points for a ${nu} × ${nv} grid`);
  const points = [];
  for (let q = 0; q < position.count; ++q) points.push(new THREE.Vector3().fromBufferAttribute(position, q));
  return { name: extras.name ?? object.name, isGrid, nu, nv, points, lux: Array.from(lux.array) };
}

// min, mean, max and U0 = min/mean (EN 12464-1's uniformity).
export function probeSummary(probe) {
  const min = Math.min(...probe.lux), max = Math.max(...probe.lux);
  const mean = probe.lux.reduce((a, b) => a + b, 0) / probe.lux.length;
  return { min, mean, max, uniformity: mean > 0 ? min / mean : 0 };
}

// The isolux levels of a grid: its scale's ticks strictly inside the range of its values.
export function isoluxLevels(probe, kind) {
  const { min, max } = probeSummary(probe);
  return scaleTicks(colourScale(probe.lux, kind), kIsoluxTicks).map((t) => t.value).filter((v) => v > min && v < max);
}

// The point of lattice coordinates (i, j) of a grid (bilinear between its samples; the grid's
// points are an affine lattice, so this is exact).
function latticePoint(probe, i, j) {
  const { nu, points } = probe;
  const i0 = Math.min(Math.max(Math.floor(i), 0), nu - 2), j0 = Math.min(Math.max(Math.floor(j), 0), probe.nv - 2);
  const p00 = points[j0 * nu + i0], p10 = points[j0 * nu + i0 + 1], p01 = points[(j0 + 1) * nu + i0];
  const du = new THREE.Vector3().subVectors(p10, p00), dv = new THREE.Vector3().subVectors(p01, p00);
  return p00.clone().addScaledVector(du, i - i0).addScaledVector(dv, j - j0);
}

// Each level's segments in world space, and a label on its middle segment.
function isoluxLines(probe, kind, labels) {
  const vertices = [];
  const levels = probe.nu >= 2 && probe.nv >= 2 ? isoluxLevels(probe, kind) : [];
  for (const level of levels) {
    const segments = isolines(probe.lux, probe.nu, probe.nv, level);
    for (const [a, b] of segments) {
      for (const [i, j] of [a, b]) vertices.push(...latticePoint(probe, i, j).toArray());
    }
    if (segments.length > 0) {
      // Where the value may be written: the middle segment, then the quarters, ... (as
      // server/grid_map.cpp), the first place that covers no other label.
      const positions = [0.5, 0.25, 0.75, 0.125, 0.375, 0.625, 0.875].map((f) => {
        const [a, b] = segments[Math.floor(f * (segments.length - 1))];
        return latticePoint(probe, (a[0] + b[0]) / 2, (a[1] + b[1]) / 2);
      });
      labels.push({ positions, text: `${tickLabel(level)} lx`, kind: "isolux", priority: 0 });
    }
  }
  return { levels, vertices };
}

// Builds the probes' objects: returns {group, labels, grids} where labels are {positions, text, kind}
// for labels.js and grids list each probe's summary and isolux levels for the side panel.
export function buildProbes(probes, kind) {
  const group = new THREE.Group();
  group.name = "probes";
  const labels = [];
  const grids = [];
  const dots = [];
  for (const probe of probes) {
    probe.points.forEach((p, q) => {
      dots.push(...p.toArray());
      const text = probe.isGrid ? tickLabel(probe.lux[q]) : `${probe.name}: ${tickLabel(probe.lux[q])} lx`;
      labels.push({ positions: [p], text, kind: "value", priority: 1, value: probe.lux[q], probe: probe.name });
    });
    const { levels, vertices } = isoluxLines(probe, kind, labels);
    if (vertices.length > 0) {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.Float32BufferAttribute(vertices, 3));
      const lines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: 0x000000 }));
      lines.name = `isolux ${probe.name}`;
      lines.userData.segments = vertices.length / 6;
      group.add(lines);
    }
    grids.push({ name: probe.name, isGrid: probe.isGrid, nu: probe.nu, nv: probe.nv, levels,
                 segments: vertices.length / 6, ...probeSummary(probe) });
  }
  if (dots.length > 0) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.Float32BufferAttribute(dots, 3));
    group.add(new THREE.Points(geometry, new THREE.PointsMaterial({ color: 0x000000, size: 4, sizeAttenuation: false })));
  }
  return { group, labels, grids };
}
