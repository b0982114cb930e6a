// The 3D view of a result: the surfaces of an exported .glb (server/export/gltf_writer.cpp) read by
// three.js's own GLTFLoader, orbited with OrbitControls, coloured by the file's display colour
// (COLOR_0, so the view shows what the exported file shows) or in false colour by the per-vertex
// illuminance or luminance; picking a patch reads its values back from the same vertices.

import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { colourScale, falseColourRamp } from "./colour_scale.js";
import { probeFromObject } from "./probes.js";

const kFovDeg = 40; // as `lambert render`'s default camera

// The vertex attributes of a Lambert .glb, as GLTFLoader names them (lower-cased custom names).
export const Quantity = Object.freeze({
  illuminance: { attribute: "_illuminance_lx", title: "Illuminance", unit: "lx" },
  luminance: { attribute: "_luminance_cd_m2", title: "Luminance", unit: "cd/m²" },
});

export class ResultView {
  constructor(canvas) {
    this.canvas = canvas;
    // preserveDrawingBuffer: the picture stays readable after it is shown (the "save picture"
    // button and the browser test read pixels).
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setClearColor(0x202020);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(kFovDeg, 1, 0.01, 100);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener("change", () => this.render());
    this.surfaces = []; // THREE.Mesh, each with userData.name and its original colours
    this.probes = [];
    this.overlay = null; // the probes' group
    this.highlight = null;
    this.onRender = () => {};
  }

  // Reads a .glb (ArrayBuffer) and shows it; throws on a file that is not a Lambert result.
  async load(bytes) {
    const gltf = await new GLTFLoader().parseAsync(bytes, "");
    const surfaces = [], probes = [];
    gltf.scene.traverse((object) => {
      if (object.isMesh) surfaces.push(object);
      else if (object.isPoints && object.userData.probe) probes.push(object);
    });
    if (surfaces.length === 0) throw new Error("the file holds no surfaces");
    for (const mesh of surfaces) {
      const g = mesh.geometry;
      for (const q of Object.values(Quantity)) {
        if (!g.getAttribute(q.attribute)) throw new Error(`surface ${mesh.userData.name}: no ${q.attribute} attribute (not a Lambert export?)`);
      }
      if (!g.getAttribute("color")) throw new Error(`surface ${mesh.userData.name}: no COLOR_0 attribute`);
      mesh.userData.displayColour = g.getAttribute("color").array.slice();
    }
    this.probes = probes.map(probeFromObject);
    for (const p of probes) p.parent.remove(p); // drawn by probes.js instead
    if (this.root) this.scene.remove(this.root);
    this.root = gltf.scene;
    this.scene.add(this.root);
    this.surfaces = surfaces;
    this.extras = gltf.scene.userData; // white_cd_m2, shading
    this.clearHighlight();
    this.bounds = new THREE.Box3();
    for (const mesh of surfaces) this.bounds.expandByObject(mesh);
  }

  // The range of a quantity over every vertex, and its colour scale.
  scaleOf(quantity, kind) {
    const arrays = this.surfaces.map((mesh) => mesh.geometry.getAttribute(quantity.attribute).array);
    const values = new Float32Array(arrays.reduce((n, a) => n + a.length, 0));
    arrays.reduce((offset, a) => (values.set(a, offset), offset + a.length), 0);
    let min = Infinity, max = -Infinity;
    for (const v of values) (min = Math.min(min, v)), (max = Math.max(max, v));
    return { scale: colourScale(values, kind), range: { min, max } };
  }

  // False colour of `quantity` on `scale`, or (quantity null) the file's display colour.
  colour(quantity, scale) {
    const c = new THREE.Color();
    for (const mesh of this.surfaces) {
      const colours = mesh.geometry.getAttribute("color");
      if (!quantity) {
        colours.array.set(mesh.userData.displayColour);
      } else {
        const values = mesh.geometry.getAttribute(quantity.attribute).array;
        for (let v = 0; v < values.length; ++v) {
          const [r, g, b] = falseColourRamp(scale.position(values[v]));
          // The ramp is in sRGB bytes; the vertex colours are linear and the renderer encodes its
          // output as sRGB, so the screen shows the ramp's bytes.
          c.setRGB(r / 255, g / 255, b / 255, THREE.SRGBColorSpace);
          colours.setXYZ(v, c.r, c.g, c.b);
        }
      }
      colours.needsUpdate = true;
    }
  }

  setProbeOverlay(group) {
    if (this.overlay) this.scene.remove(this.overlay);
    this.overlay = group;
    if (group) this.scene.add(group);
  }

  // "front": the scene's bounding sphere seen from −z with +y up, as `lambert render` sees it, but
  // from 20° above, so that floors and work planes show; "top": tilted further up over the scene,
  // looking down, +z up the screen.
  setView(which) {
    const sphere = this.bounds.getBoundingSphere(new THREE.Sphere());
    const distance = sphere.radius / Math.sin(THREE.MathUtils.degToRad(kFovDeg / 2));
    const elevation = THREE.MathUtils.degToRad(which === "top" ? 89.99 : 20);
    const direction = new THREE.Vector3(0, Math.sin(elevation), -Math.cos(elevation));
    this.camera.position.copy(sphere.center).addScaledVector(direction, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(sphere.center);
    this.controls.update();
    this.render();
  }

  resize(width, height) {
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / Math.max(1, height);
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
    this.onRender();
  }

  // The surface point under client coordinates (x, y) and its values: the patch's own with flat
  // shading, interpolated between the triangle's corners with smooth shading. null: no surface.
  pick(clientX, clientY) {
    const rect = this.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(ndc, this.camera);
    const hit = raycaster.intersectObjects(this.surfaces, false)[0];
    if (!hit) return null;
    const g = hit.object.geometry;
    const corners = [hit.face.a, hit.face.b, hit.face.c];
    const weights = [hit.barycoord.x, hit.barycoord.y, hit.barycoord.z];
    const at = (attribute, component = 0) =>
      corners.reduce((sum, v, k) => sum + weights[k] * attribute.getComponent(v, component), 0);
    const triangle = corners.map((v) => new THREE.Vector3().fromBufferAttribute(g.getAttribute("position"), v));
    const display = new THREE.Color(...[0, 1, 2].map((c) => corners.reduce(
      (sum, v, k) => sum + weights[k] * hit.object.userData.displayColour[3 * v + c], 0)));
    this.showHighlight(triangle.map((p) => p.clone().applyMatrix4(hit.object.matrixWorld)));
    return {
      surface: hit.object.userData.name ?? hit.object.name,
      point: hit.point,
      illuminance: at(g.getAttribute(Quantity.illuminance.attribute)),
      luminance: at(g.getAttribute(Quantity.luminance.attribute)),
      colour: `#${display.getHexString(THREE.SRGBColorSpace)}`,
      area: new THREE.Triangle(...triangle).getArea(),
    };
  }

  showHighlight(corners) {
    this.clearHighlight();
    const geometry = new THREE.BufferGeometry().setFromPoints(corners);
    this.highlight = new THREE.LineLoop(geometry, new THREE.LineBasicMaterial({ color: 0xff00ff, depthTest: false }));
    this.highlight.renderOrder = 1;
    this.scene.add(this.highlight);
    this.render();
  }

  clearHighlight() {
    if (!this.highlight) return;
    this.scene.remove(this.highlight);
    this.highlight.geometry.dispose();
    this.highlight = null;
  }

  // Client coordinates of a world point (metres), for the page's tests and labels.
  project(point) {
    const rect = this.canvas.getBoundingClientRect();
    const p = new THREE.Vector3(...point).project(this.camera);
    return { x: rect.left + ((p.x + 1) / 2) * rect.width, y: rect.top + ((1 - p.y) / 2) * rect.height };
  }
}
