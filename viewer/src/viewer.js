// geotex web viewer: meshes side by side (one scissored viewport each, one shared camera, so the
// orbit controls are linked and sizes compare), flat/smooth shading, wireframe, edge labels as
// coloured lines, and per-vertex fields as a colour map with a legend. The page embeds its data as
// JSON in <script id="geotex-data">; arrays are zlib streams in base64 (format: src/tools/viewer.cpp):
//   positions  per axis, byte planes of delta-coded quantised values: x = offset + step * q, relative
//              to the mesh's origin (the centre of its faces' box);
//   indices    varints c: index = (next new index) − c, faces in the page's (breadth-first) order;
//   fields     16-bit codes in byte planes (65535 = no value): value = lo + step * code;
//   edges      vertex pairs as zigzag varints of the change from the previous index; labels as varints.

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

function bytesOf(b64) {
  const bin = atob(b64 || '');
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return bytes;
}

async function inflate(b64) {
  if (typeof DecompressionStream === 'undefined')
    throw new Error('this browser cannot read the page (no DecompressionStream; use a browser from 2023 or later)');
  const stream = new Blob([bytesOf(b64)]).stream().pipeThrough(new DecompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

function varints(bytes, n) {
  const out = new Uint32Array(n);
  let at = 0;
  for (let i = 0; i < n; ++i) {
    let v = 0, shift = 0, b;
    do {
      if (at >= bytes.length) throw new Error('truncated page data');
      b = bytes[at++];
      v += (b & 0x7f) * 2 ** shift;
      shift += 7;
    } while (b & 0x80);
    out[i] = v;
  }
  return out;
}

// Codes from byte planes of deltas (low byte first), block `block` of a stream of such blocks.
function planeCodes(bytes, n, planes, block) {
  const out = new Uint32Array(n), base = block * planes * n, mod = 2 ** (8 * planes);
  let q = 0;
  for (let i = 0; i < n; ++i) {
    let d = 0;
    for (let k = 0; k < planes; ++k) d += bytes[base + k * n + i] * 2 ** (8 * k);
    q = (q + d) % mod;
    out[i] = q;
  }
  return out;
}

// Decode one mesh's arrays: positions relative to its origin, indices, fields, edges.
async function decodeMesh(data) {
  const n = data.vertices, p = data.positions;
  const pos = await inflate(p.data), positions = new Float32Array(3 * n);
  for (let j = 0; j < 3; ++j) {
    const q = planeCodes(pos, n, p.planes, j);
    for (let i = 0; i < n; ++i) positions[3 * i + j] = p.offset[j] + p.step[j] * q[i];
  }
  const codes = varints(await inflate(data.indices), 3 * data.faces);
  const indices = new Uint32Array(codes.length);
  let next = 0;
  for (let i = 0; i < codes.length; ++i) {
    const g = next - codes[i];
    indices[i] = g;
    if (g >= next) next = g + 1;
  }
  const fields = {};
  for (const [name, f] of Object.entries(data.fields || {})) {
    const q = planeCodes(await inflate(f.data), n, 2, 0), values = new Float32Array(n);
    for (let i = 0; i < n; ++i) values[i] = q[i] === 65535 ? NaN : f.lo + f.step * q[i];
    fields[name] = values;
  }
  let edges = new Uint32Array(0), labels = new Uint32Array(0);
  if (data.edges) {
    const z = varints(await inflate(data.edges.pairs), 2 * data.edges.count);
    edges = new Uint32Array(z.length);
    let prev = 0;
    for (let i = 0; i < z.length; ++i) {
      prev += z[i] % 2 ? -(z[i] + 1) / 2 : z[i] / 2;
      edges[i] = prev;
    }
    labels = varints(await inflate(data.edges.labels), data.edges.count);
  }
  return { positions, indices, fields, edges, labels };
}

function formatNumber(v) {
  if (v === 0) return '0';
  const a = Math.abs(v);
  return a >= 1e4 || a < 1e-3 ? v.toExponential(2) : v.toPrecision(3);
}

class View {
  constructor(data, arrays, container) {
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

    // Positions arrive relative to the mesh's origin (the centre of its faces' box), which every
    // view puts at the shared camera's target: each mesh is centred in its view, and far-off meshes
    // keep float32 precision. The surface, its wireframe and the edge lines all hang from one group
    // and use these same positions, so nothing drawn for a mesh is placed on its own.
    const { positions, indices, fields, edges, labels } = arrays;
    this.positions = positions;
    this.indices = indices;
    this.fields = fields;
    this.radius = data.radius || 1;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(indices, 1));
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    this.colours = new THREE.BufferAttribute(new Float32Array(positions.length), 3);
    geometry.setAttribute('color', this.colours);
    this.geometry = geometry;

    this.material = new THREE.MeshPhongMaterial({
      color: 0xffffff, vertexColors: true, side: THREE.DoubleSide, shininess: 40, specular: 0x333333,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xffffff);
    this.group = new THREE.Group();
    this.scene.add(this.group);
    this.group.add(new THREE.Mesh(geometry, this.material));
    this.wire = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({
      color: 0x202020, wireframe: true, transparent: true, opacity: 0.35 }));
    this.wire.visible = false;
    this.group.add(this.wire);
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.45));
    this.light = new THREE.DirectionalLight(0xffffff, 2.2);
    this.scene.add(this.light);

    // Labelled edges as coloured line segments (copies of the surface's positions: one colour per segment).
    this.edges = null;
    if (edges.length > 0) {
      const p = new Float32Array(edges.length * 3), c = new Float32Array(edges.length * 3);
      for (let i = 0; i < edges.length; ++i) {
        p.set(positions.subarray(3 * edges[i], 3 * edges[i] + 3), 3 * i);
        const col = new THREE.Color().setRGB(...labelColour(labels.length ? labels[i >> 1] : 1), THREE.SRGBColorSpace);
        c.set([col.r, col.g, col.b], 3 * i);
      }
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(p, 3));
      g.setAttribute('color', new THREE.BufferAttribute(c, 3));
      this.edges = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: true }));
      this.group.add(this.edges);
    }
    this.scene.updateMatrixWorld(true);
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

async function main() {
  const data = JSON.parse(document.getElementById('geotex-data').textContent);
  document.title = data.title || 'geotex';
  const canvas = document.getElementById('gl');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setScissorTest(true);

  const container = document.getElementById('views');
  const arrays = await Promise.all(data.meshes.map(decodeMesh));
  const views = data.meshes.map((m, k) => new View(m, arrays[k], container));
  const radius = Math.max(...views.map((v) => v.radius));

  // One camera for every view, framed on the largest mesh: orbiting one orbits all, and one scale
  // holds for all, so that sizes compare.
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

  // The shared camera set up for one view's rectangle (page pixels).
  function aimAt(v) {
    const r = v.element.getBoundingClientRect();
    camera.aspect = r.width / Math.max(1, r.height);
    camera.zoom = Math.min(1, camera.aspect);  // narrow views zoom out so the mesh fits their width
    camera.updateProjectionMatrix();
    return r;
  }

  function render() {
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (canvas.width !== Math.floor(width * renderer.getPixelRatio()) ||
        canvas.height !== Math.floor(height * renderer.getPixelRatio())) renderer.setSize(width, height, false);
    const top = canvas.getBoundingClientRect();
    for (const v of views) {
      const r = aimAt(v);
      const x = r.left - top.left, y = height - (r.bottom - top.top);
      renderer.setViewport(x, y, r.width, r.height);
      renderer.setScissor(x, y, r.width, r.height);
      v.light.position.copy(camera.position).add(camera.up.clone().multiplyScalar(radius));
      renderer.render(v.scene, camera);
    }
  }

  // Page pixels of the points of a drawn object (its own geometry through its world transform).
  function screenPoints(v, object) {
    const r = aimAt(v), p = object.geometry.getAttribute('position'), out = [];
    const q = new THREE.Vector3();
    for (let i = 0; i < p.count; ++i) {
      q.fromBufferAttribute(p, i).applyMatrix4(object.matrixWorld).project(camera);
      out.push([r.left + (q.x + 1) / 2 * r.width, r.top + (1 - q.y) / 2 * r.height]);
    }
    return out;
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
  // For tests (viewer/test/viewer_check.mjs): where the edge lines are drawn, and the decoded box of
  // each mesh's faces in file coordinates (decoded positions + origin).
  const boxes = () => views.map((v) => {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const i of v.indices)
      for (let j = 0; j < 3; ++j) {
        const x = v.positions[3 * i + j] + v.data.origin[j];
        lo[j] = Math.min(lo[j], x); hi[j] = Math.max(hi[j], x);
      }
    return { lo, hi, expected: v.data.box };
  });
  window.geotexViewer = {
    views: views.length, fields: fieldNames, ready: true, boxes,
    labelScreenPoints: (k) => (views[k].edges ? screenPoints(views[k], views[k].edges) : []),
  };
}

main().catch((e) => {
  document.getElementById('error').textContent = `geotex viewer: ${e.message}`;
  console.error(e);
});
