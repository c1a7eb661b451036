// geotex web viewer: meshes side by side (one scissored viewport each, one shared camera, so the
// orbit controls are linked), flat/smooth shading, wireframe, edge labels as coloured lines, and
// per-vertex fields as a colour map with a legend. The page embeds its data as JSON in
// <script id="geotex-data">; geometry arrives as base64 typed arrays (float32 positions, uint32 indices).

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

// Viridis at 9 stops, as in src/render.cpp, so pictures and pages agree.
const VIRIDIS = [[0.267, 0.005, 0.329], [0.283, 0.141, 0.458], [0.254, 0.265, 0.530], [0.207, 0.372, 0.553],
                 [0.164, 0.471, 0.558], [0.128, 0.567, 0.551], [0.135, 0.659, 0.518], [0.478, 0.821, 0.318],
                 [0.993, 0.906, 0.144]];
const LABEL_COLOURS = [[0.86, 0.10, 0.12], [0.12, 0.35, 0.85], [0.10, 0.65, 0.20], [0.95, 0.55, 0.05],
                       [0.60, 0.20, 0.70], [0.05, 0.70, 0.75]];
const BASE_COLOUR = new THREE.Color().setRGB(0.74, 0.76, 0.80, THREE.SRGBColorSpace);

function colourMap(t) {
  if (!Number.isFinite(t)) t = 0;
  t = Math.min(1, Math.max(0, t)) * 8;
  const k = Math.min(7, Math.floor(t)), f = t - k;
  return VIRIDIS[k].map((a, j) => (1 - f) * a + f * VIRIDIS[k + 1][j]);
}

function labelColour(label) {
  const n = LABEL_COLOURS.length;
  return LABEL_COLOURS[(((Math.max(label, 1) - 1) % n) + n) % n];
}

function decode(b64, Type) {
  if (!b64) return new Type(0);
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer);
}

function formatNumber(v) {
  if (v === 0) return '0';
  const a = Math.abs(v);
  return a >= 1e4 || a < 1e-3 ? v.toExponential(2) : v.toPrecision(3);
}

class View {
  constructor(data, container) {
    this.data = data;
    this.element = document.createElement('div');
    this.element.className = 'view';
    const caption = document.createElement('div');
    caption.className = 'caption';
    caption.textContent = data.name;
    const stats = document.createElement('span');
    stats.className = 'stats';
    stats.textContent = ` ${data.vertices} vertices, ${data.faces} faces`;
    caption.appendChild(stats);
    this.element.appendChild(caption);
    container.appendChild(this.element);

    const positions = decode(data.positions, Float32Array);
    const indices = decode(data.indices, Uint32Array);
    this.fields = {};
    for (const [name, b64] of Object.entries(data.fields || {})) this.fields[name] = decode(b64, Float32Array);

    // Geometry centred on its own bounding box, so that meshes at different places line up side by side.
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(indices, 1));
    geometry.computeBoundingBox();
    this.centre = geometry.boundingBox.getCenter(new THREE.Vector3());
    geometry.translate(-this.centre.x, -this.centre.y, -this.centre.z);
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    this.radius = geometry.boundingSphere.radius || 1;
    this.colours = new THREE.BufferAttribute(new Float32Array(positions.length), 3);
    geometry.setAttribute('color', this.colours);
    this.geometry = geometry;

    this.material = new THREE.MeshPhongMaterial({
      color: 0xffffff, vertexColors: true, side: THREE.DoubleSide, shininess: 40, specular: 0x333333,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xffffff);
    this.scene.add(new THREE.Mesh(geometry, this.material));
    this.wire = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({
      color: 0x202020, wireframe: true, transparent: true, opacity: 0.35 }));
    this.wire.visible = false;
    this.scene.add(this.wire);
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.45));
    this.light = new THREE.DirectionalLight(0xffffff, 2.2);
    this.scene.add(this.light);

    // Labelled edges as coloured line segments.
    const edges = decode(data.edges, Uint32Array), labels = decode(data.edgeLabels, Int32Array);
    this.edges = null;
    if (edges.length > 0) {
      const p = new Float32Array(edges.length * 3), c = new Float32Array(edges.length * 3);
      for (let i = 0; i < edges.length; ++i) {
        for (let j = 0; j < 3; ++j) p[3 * i + j] = positions[3 * edges[i] + j] - this.centre.getComponent(j);
        const col = new THREE.Color().setRGB(...labelColour(labels.length ? labels[i >> 1] : 1), THREE.SRGBColorSpace);
        c.set([col.r, col.g, col.b], 3 * i);
      }
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(p, 3));
      g.setAttribute('color', new THREE.BufferAttribute(c, 3));
      this.edges = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: true }));
      this.scene.add(this.edges);
    }
  }

  hasField(name) { return name in this.fields; }

  // Colour the vertices by a field over [lo, hi], or plainly.
  colourBy(name, lo, hi) {
    const c = this.colours.array, f = this.fields[name];
    const n = c.length / 3, tmp = new THREE.Color();
    for (let i = 0; i < n; ++i) {
      // The map is in sRGB; vertex colours are linear.
      if (f) tmp.setRGB(...colourMap((f[i] - lo) / (hi - lo)), THREE.SRGBColorSpace);
      else tmp.copy(BASE_COLOUR);
      c[3 * i] = tmp.r; c[3 * i + 1] = tmp.g; c[3 * i + 2] = tmp.b;
    }
    this.colours.needsUpdate = true;
  }
}

function main() {
  const data = JSON.parse(document.getElementById('geotex-data').textContent);
  document.title = data.title || 'geotex';
  const canvas = document.getElementById('gl');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setScissorTest(true);

  const container = document.getElementById('views');
  const views = data.meshes.map((m) => new View(m, container));
  const radius = Math.max(...views.map((v) => v.radius));

  // One camera for every view: orbiting one orbits all.
  const camera = new THREE.PerspectiveCamera(35, 1, radius / 100, radius * 100);
  // geotex shapes are z-up; scans are often y-up (the page's "up"). The initial direction is given
  // for z-up and rotated with the up axis.
  const up = new THREE.Vector3(...(data.up || [0, 0, 1])).normalize();
  camera.up.copy(up);
  const direction = new THREE.Vector3(1, -1, 0.8).normalize()
    .applyQuaternion(new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 0, 1), up));
  camera.position.copy(direction.multiplyScalar(radius / Math.sin((35 / 2) * Math.PI / 180) * 1.1));
  const controls = new OrbitControls(camera, canvas);
  controls.target.set(0, 0, 0);
  controls.update();

  // Controls: shading, wireframe, edges, field.
  const ui = {
    flat: document.getElementById('flat'), wire: document.getElementById('wire'),
    edges: document.getElementById('edges'), field: document.getElementById('field'),
    legend: document.getElementById('legend'),
  };
  const fieldNames = [...new Set(views.flatMap((v) => Object.keys(v.fields)))];
  for (const name of fieldNames) {
    const o = document.createElement('option');
    o.value = name;
    o.textContent = name;
    ui.field.appendChild(o);
  }
  if (data.initialField && fieldNames.includes(data.initialField)) ui.field.value = data.initialField;
  ui.flat.checked = !!data.flat;
  ui.wire.checked = !!data.wireframe;
  ui.edges.disabled = !views.some((v) => v.edges);

  function applyField() {
    const name = ui.field.value;
    // One range over every mesh that has the field, so colours compare across views.
    let lo = Infinity, hi = -Infinity;
    for (const v of views) {
      const f = v.fields[name];
      if (!f) continue;
      for (const x of f) if (Number.isFinite(x)) { lo = Math.min(lo, x); hi = Math.max(hi, x); }
    }
    if (!(hi > lo)) hi = lo + 1;
    for (const v of views) v.colourBy(name, lo, hi);
    ui.legend.style.display = name ? 'flex' : 'none';
    if (name) {
      document.getElementById('legend-name').textContent = name;
      document.getElementById('legend-hi').textContent = formatNumber(hi);
      document.getElementById('legend-mid').textContent = formatNumber((lo + hi) / 2);
      document.getElementById('legend-lo').textContent = formatNumber(lo);
    }
    render();
  }

  function applyToggles() {
    for (const v of views) {
      v.material.flatShading = ui.flat.checked;
      v.material.needsUpdate = true;
      v.wire.visible = ui.wire.checked;
      if (v.edges) v.edges.visible = ui.edges.checked;
    }
    render();
  }

  function render() {
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (canvas.width !== Math.floor(width * renderer.getPixelRatio()) ||
        canvas.height !== Math.floor(height * renderer.getPixelRatio())) renderer.setSize(width, height, false);
    const top = canvas.getBoundingClientRect();
    for (const v of views) {
      const r = v.element.getBoundingClientRect();
      const x = r.left - top.left, y = height - (r.bottom - top.top);
      renderer.setViewport(x, y, r.width, r.height);
      renderer.setScissor(x, y, r.width, r.height);
      camera.aspect = r.width / Math.max(1, r.height);
      camera.zoom = Math.min(1, camera.aspect);  // narrow views zoom out so the mesh fits their width
      camera.updateProjectionMatrix();
      v.light.position.copy(camera.position).add(camera.up.clone().multiplyScalar(radius));
      renderer.render(v.scene, camera);
    }
  }

  ui.field.addEventListener('change', applyField);
  for (const t of [ui.flat, ui.wire, ui.edges]) t.addEventListener('change', applyToggles);
  window.addEventListener('keydown', (e) => {
    const t = { f: ui.flat, w: ui.wire, e: ui.edges }[e.key];
    if (t && !t.disabled) { t.checked = !t.checked; applyToggles(); }
  });
  controls.addEventListener('change', render);
  window.addEventListener('resize', render);
  applyToggles();
  applyField();
  window.geotexViewer = { views: views.length, fields: fieldNames, ready: true };
}

try {
  main();
} catch (e) {
  document.getElementById('error').textContent = `geotex viewer: ${e.message}`;
  console.error(e);
}
