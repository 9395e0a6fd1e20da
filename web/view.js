// Draws a frame's arrays (web/wasm `Frame`) with three.js: triangles lit,
// lines, and cells as points coloured by type; orbit controls for 3D and
// the plane alike.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

// Colour-map indices (segments, polygons, modules, curve series).
const PALETTE = [
  0x6b4f2a, 0x3f8f3a, 0x2f6fb0, 0xc0392b, 0xd4a017, 0x8e44ad, 0x16a085, 0xd35400,
  0x7f8c8d, 0x27ae60, 0x2980b9, 0xe67e22,
].map((c) => new THREE.Color(c));
const MESH = new THREE.Color(0xe8dcc4);

// An L-system's colour indices: bark brown (0) through olive to leaf green
// (8) and yellow-green (12), constant beyond, as `morphogen run` draws
// them (host-cli/src/outputs/plant.rs, `palette`).
const STOPS = [[0, [101, 67, 33]], [4, [110, 110, 40]], [8, [50, 130, 45]], [12, [150, 195, 70]]];
const RAMP = Array.from({ length: 13 }, (_, i) => {
  const k = Math.min(STOPS.findLastIndex((s) => s[0] <= i), STOPS.length - 2);
  const [[x0, c0], [x1, c1]] = [STOPS[k], STOPS[k + 1]];
  const t = (i - x0) / (x1 - x0);
  const [r, g, b] = [0, 1, 2].map((j) => Math.round(c0[j] + (c1[j] - c0[j]) * t) / 255);
  return new THREE.Color().setRGB(r, g, b, THREE.SRGBColorSpace);
});
const LOOSE = new THREE.Color(0x333333);

export class View {
  constructor(canvas) {
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.scene = new THREE.Scene();
    // Not white: white cells (amanita's spots) must show.
    this.scene.background = new THREE.Color(0xd5dbe1);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1e6);
    this.scene.add(this.camera);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x888877, 1.6));
    const light = new THREE.DirectionalLight(0xffffff, 1.6);
    light.position.set(1, 1, 2);
    this.camera.add(light);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener("change", () => this.render());
    this.group = new THREE.Group();
    this.scene.add(this.group);
    this.reset(null, []);
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  resize() {
    const c = this.renderer.domElement;
    const w = c.clientWidth || 640;
    const h = c.clientHeight || 480;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  // A new scenario: its model (for colours), cell colours by type (RGB
  // 0–255) and a fresh fit.
  reset(model, colours) {
    this.plant = model === "lsystem";
    this.index = this.plant ? (c) => RAMP[Math.min(c, 12)] : (c) => PALETTE[c % PALETTE.length];
    this.colours = (colours || []).map(([r, g, b]) => new THREE.Color().setRGB(r / 255, g / 255, b / 255, THREE.SRGBColorSpace));
    this.fitted = null;
    this.clear();
    this.render();
  }

  clear() {
    for (const o of [...this.group.children]) {
      o.geometry.dispose();
      o.material.dispose();
      this.group.remove(o);
    }
  }

  show(f) {
    this.clear();
    let lines = f.lines;
    if (f.chart && lines.length > 0) lines = stretched(lines);
    if (f.triangles.length > 0) {
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.BufferAttribute(f.triangles, 3));
      g.setAttribute("color", perVertex(f.triangleColours, 3, (c) => (c === 0 && !this.plant ? MESH : this.index(c))));
      g.computeVertexNormals();
      const mesh = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ vertexColors: true, side: THREE.DoubleSide, roughness: 0.7 }));
      if (f.points.length > 0) {
        // Under a surface mosaic's cells (points on its faces) the mesh is
        // drawn 3 % smaller about its centre, so that its facets do not
        // cut the cells.
        g.computeBoundingBox();
        const centre = g.boundingBox.getCenter(new THREE.Vector3());
        mesh.scale.setScalar(0.97);
        mesh.position.copy(centre.multiplyScalar(0.03));
      }
      this.group.add(mesh);
    }
    if (lines.length > 0) {
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.BufferAttribute(lines, 3));
      g.setAttribute("color", perVertex(f.lineColours, 2, this.index));
      this.group.add(new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: true })));
    }
    if (f.points.length > 0) {
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.BufferAttribute(f.points, 3));
      g.setAttribute("color", perVertex(f.pointKinds, 1, (k) => this.colours[k] || LOOSE));
      g.computeBoundingBox();
      const size = g.boundingBox.getSize(new THREE.Vector3());
      const flat = size.z === 0;
      // About one cell spacing: the points' area (or surface) over their count.
      const area = flat ? size.x * size.y : 2 * (size.x * size.y + size.y * size.z + size.z * size.x);
      const spacing = Math.sqrt(area / (f.points.length / 3)) || 1;
      const m = new THREE.PointsMaterial({ vertexColors: true, size: spacing * (flat ? 1.1 : 1.6), sizeAttenuation: true });
      this.group.add(new THREE.Points(g, m));
    }
    this.fit();
    this.render();
  }

  // Fits the camera when the drawing leaves the fitted box (it grows).
  fit() {
    const box = new THREE.Box3().setFromObject(this.group);
    if (box.isEmpty()) return;
    if (this.fitted && this.fitted.containsBox(box)) return;
    const size = box.getSize(new THREE.Vector3());
    const flat = size.z < 1e-6 * Math.max(size.x, size.y, 1e-9);
    this.fitted = box.clone().expandByScalar(0.05 * Math.max(size.x, size.y, size.z));
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(size.length() / 2, 1e-6);
    const distance = radius / Math.sin((this.camera.fov * Math.PI) / 360);
    if (flat) {
      this.camera.up.set(0, 1, 0);
      this.camera.position.copy(centre).add(new THREE.Vector3(0, 0, distance));
    } else {
      this.camera.up.set(0, 1, 0);
      this.camera.position.copy(centre).add(new THREE.Vector3(0.7, 0.4, 1).normalize().multiplyScalar(distance));
    }
    this.camera.near = distance / 1000;
    this.camera.far = distance * 10;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
  }

  png() {
    this.render();
    return this.renderer.domElement.toDataURL("image/png");
  }
}

// One colour per item, repeated for its `n` vertices.
function perVertex(items, n, colour) {
  const out = new Float32Array(items.length * n * 3);
  for (let i = 0; i < items.length; i++) {
    const c = colour(items[i]);
    for (let v = 0; v < n; v++) c.toArray(out, (i * n + v) * 3);
  }
  return new THREE.BufferAttribute(out, 3);
}

// A chart's samples, y stretched to 60 % of the x range.
function stretched(lines) {
  let xmin = Infinity, xmax = -Infinity, ymin = Infinity, ymax = -Infinity;
  for (let i = 0; i < lines.length; i += 3) {
    xmin = Math.min(xmin, lines[i]); xmax = Math.max(xmax, lines[i]);
    ymin = Math.min(ymin, lines[i + 1]); ymax = Math.max(ymax, lines[i + 1]);
  }
  const k = ymax > ymin ? (0.6 * (xmax - xmin || 1)) / (ymax - ymin) : 1;
  const out = new Float32Array(lines);
  for (let i = 1; i < out.length; i += 3) out[i] = (out[i] - ymin) * k;
  return out;
}
