// viewer.js - planetgen's globe viewer (docs/export.md, "The browser viewer"): loads the
// planet's .glb with three.js and shows it as a globe to orbit and zoom, with a relief
// exaggeration slider and a switch between the albedo and a shaded relief.
//
// The .glb (docs/export.md, "The globe") holds one mesh of six primitives, one per cube
// face, in ECEF metres, each vertex raised along the ellipsoid normal by
// max(height, sea level) x E, where E is the scene's extras.exaggeration. The slider
// rescales that relief on the CPU: a vertex at distance r from the centre, whose
// direction meets the ellipsoid at r0, moves to r0 + (r - r0) k / E for exaggeration k.
// Radial rather than along the ellipsoid normal: the two differ by at most the
// flattening's 0.19 degrees, far below a pixel. Seam vertices are bit-identical across
// faces in the .glb, and this map is a function of the position alone, so they stay
// identical: the globe stays closed at every exaggeration. Normals are recomputed from
// the rescaled triangles and averaged over the faces that share a seam vertex, and the
// normal map's strength follows k / E (it holds the detail the mesh lacks, at E).
//
// A tiled planet (docs/export.md, "Tiled planets") comes as one .glb per tile, each a
// mesh of one primitive in the same frame; viewer.json lists them under "tiles" and the
// page loads them all into one globe. Their border vertices are bit-identical too, so
// the seam groups below join tiles exactly as they join faces.
import * as THREE from 'three';
import { GLTFLoader } from './three/examples/jsm/loaders/GLTFLoader.js';
import { OrbitControls } from './three/examples/jsm/controls/OrbitControls.js';

const params = new URLSearchParams(window.location.search);
const $ = (id) => document.getElementById(id);

// Hypsometric tint of the shaded-relief mode, metres -> linear RGB; the sea (the mesh
// carries the water surface there) is one flat blue.
const TINT = [
  [0, [0.11, 0.36, 0.13]], [300, [0.35, 0.52, 0.2]], [1000, [0.72, 0.66, 0.38]],
  [2500, [0.55, 0.38, 0.24]], [4500, [0.85, 0.83, 0.82]], [8000, [1, 1, 1]],
];
const SEA = [0.06, 0.16, 0.4];

function tint(h, out) {
  let i = 0;
  while (i + 1 < TINT.length && TINT[i + 1][0] < h) i++;
  const [h0, c0] = TINT[i], [h1, c1] = TINT[Math.min(i + 1, TINT.length - 1)];
  const t = h1 > h0 ? Math.min(Math.max((h - h0) / (h1 - h0), 0), 1) : 0;
  for (let c = 0; c < 3; c++) out[c] = c0[c] + (c1[c] - c0[c]) * t;
}

// Where the unit direction (x, y, z) (ECEF, +z north) meets the ellipsoid.
function ellipsoidRadius(a, b, x, y, z) {
  return 1 / Math.sqrt((x * x + y * y) / (a * a) + (z * z) / (b * b));
}

// ECEF direction -> the globe's frame (the .glb's node turns +Z north into +Y up).
function ecefToScene(x, y, z) {
  return new THREE.Vector3(x, z, -y);
}

function viewDirection(view) {
  const rad = Math.PI / 180;
  if (view === 'north') return ecefToScene(0, 0, 1);
  if (view === 'south') return ecefToScene(0, 0, -1);
  if (view === 'corner') return ecefToScene(1, 1, 1).normalize(); // where +X, +Y, +Z meet
  const m = /^(-?[\d.]+),(-?[\d.]+)$/.exec(view || '');
  const lon = m ? Number(m[1]) * rad : 0, lat = m ? Number(m[2]) * rad : 20 * rad;
  return ecefToScene(Math.cos(lat) * Math.cos(lon), Math.cos(lat) * Math.sin(lon), Math.sin(lat));
}

// One primitive (cube face) of the globe, with what rescaling needs.
class Face {
  constructor(mesh, a, b) {
    this.mesh = mesh;
    this.geometry = mesh.geometry;
    const pos = this.geometry.attributes.position;
    this.original = Float64Array.from(pos.array);
    const n = pos.count;
    this.base = new Float64Array(n); // r0 of each vertex
    this.lift = new Float64Array(n); // r - r0, the exaggerated relief
    this.dir = new Float64Array(3 * n);
    for (let i = 0; i < n; i++) {
      const x = this.original[3 * i], y = this.original[3 * i + 1], z = this.original[3 * i + 2];
      const r = Math.hypot(x, y, z);
      this.dir[3 * i] = x / r;
      this.dir[3 * i + 1] = y / r;
      this.dir[3 * i + 2] = z / r;
      this.base[i] = ellipsoidRadius(a, b, x / r, y / r, z / r);
      this.lift[i] = r - this.base[i];
    }
    this.albedo = mesh.material;
    this.relief = new THREE.MeshStandardMaterial({
      vertexColors: true, roughness: 1, metalness: 0,
      normalMap: this.albedo.normalMap, normalScale: this.albedo.normalScale.clone(),
    });
    this.normalScale = this.albedo.normalScale.clone(); // as the loader set it (sign too)
  }

  // Vertex colours of the shaded relief from the heights the mesh carries.
  colour(exaggeration, seaLevel) {
    const n = this.base.length, col = new Float32Array(3 * n), c = [0, 0, 0];
    for (let i = 0; i < n; i++) {
      const h = exaggeration > 0 ? this.lift[i] / exaggeration : seaLevel;
      if (h <= seaLevel + 0.5) col.set(SEA, 3 * i);
      else {
        tint(h - seaLevel, c);
        col.set(c, 3 * i);
      }
    }
    this.geometry.setAttribute('color', new THREE.BufferAttribute(col, 3));
  }

  rescale(factor) {
    const pos = this.geometry.attributes.position;
    for (let i = 0; i < pos.count; i++) {
      const r = this.base[i] + this.lift[i] * factor;
      pos.array[3 * i] = this.dir[3 * i] * r;
      pos.array[3 * i + 1] = this.dir[3 * i + 1] * r;
      pos.array[3 * i + 2] = this.dir[3 * i + 2] * r;
    }
    pos.needsUpdate = true;
    this.geometry.computeVertexNormals();
    this.geometry.computeBoundingSphere();
    for (const m of [this.albedo, this.relief])
      m.normalScale.copy(this.normalScale).multiplyScalar(factor);
  }
}

// Vertices that several faces share (the seams), by their exact original position.
function seamGroups(faces) {
  const byKey = new Map();
  faces.forEach((f, fi) => {
    const o = f.original;
    for (let i = 0; i < o.length / 3; i++) {
      const key = `${o[3 * i]},${o[3 * i + 1]},${o[3 * i + 2]}`;
      const g = byKey.get(key);
      if (g) g.push(fi, i);
      else byKey.set(key, [fi, i]);
    }
  });
  return [...byKey.values()].filter((g) => g.length > 2);
}

function averageSeamNormals(faces, groups) {
  const s = new THREE.Vector3();
  for (const g of groups) {
    s.set(0, 0, 0);
    for (let k = 0; k < g.length; k += 2) {
      const nrm = faces[g[k]].geometry.attributes.normal;
      s.x += nrm.getX(g[k + 1]);
      s.y += nrm.getY(g[k + 1]);
      s.z += nrm.getZ(g[k + 1]);
    }
    s.normalize();
    for (let k = 0; k < g.length; k += 2)
      faces[g[k]].geometry.attributes.normal.setXYZ(g[k + 1], s.x, s.y, s.z);
  }
  for (const f of faces) f.geometry.attributes.normal.needsUpdate = true;
}

// The .glb files to show: ?glb=URL, else viewer.json's "glb" (one globe) or "tiles".
async function planetUrls() {
  if (params.get('glb')) return [params.get('glb')];
  const res = await fetch('./viewer.json');
  if (!res.ok) throw new Error(`viewer.json: HTTP ${res.status}`);
  const j = await res.json();
  return j.tiles || [j.glb];
}

// Load the files a few at a time, in order.
async function loadAll(urls) {
  const loader = new GLTFLoader(), out = new Array(urls.length);
  let next = 0;
  const worker = async () => {
    while (next < urls.length) {
      const k = next++;
      out[k] = await loader.loadAsync(urls[k]);
    }
  };
  await Promise.all(Array.from({ length: Math.min(6, urls.length) }, worker));
  return out;
}

async function main() {
  const canvas = $('pg-canvas');
  if (params.get('ui') === '0') $('pg-panel').style.display = 'none';
  const bg = /^[0-9a-fA-F]{6}$/.test(params.get('bg') || '') ? '#' + params.get('bg') : '#0b0e14';
  document.body.style.background = bg;

  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setClearColor(new THREE.Color(bg), 1);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
  scene.add(camera);
  scene.add(new THREE.AmbientLight(0xffffff, 0.9));
  const sun = new THREE.DirectionalLight(0xffffff, 2.2);
  sun.position.set(-1, 1.2, 2); // a headlight from the upper left, moving with the camera
  camera.add(sun);
  camera.add(sun.target);

  const urls = await planetUrls();
  const gltfs = await loadAll(urls);
  const url = urls.length === 1 ? urls[0] : `${urls.length} tiles`;
  const extras = gltfs[0].scene.userData || {};
  const a = Number(extras.radius_m), flat = Number(extras.flattening || 0);
  const e0 = Number(extras.exaggeration || 0), seaLevel = Number(extras.sea_level_m || 0);
  if (!(a > 0)) throw new Error(`${url}: no radius_m in the scene extras (not a planetgen .glb)`);
  const b = a * (1 - flat);

  const globe = new THREE.Group();
  globe.scale.setScalar(1 / a); // one unit = one equatorial radius
  for (const g of gltfs) globe.add(g.scene);
  scene.add(globe);
  const faces = [];
  for (const g of gltfs) g.scene.traverse((o) => { if (o.isMesh) faces.push(new Face(o, a, b)); });
  if (faces.length === 0) throw new Error(`${url}: no mesh`);
  const groups = seamGroups(faces);
  for (const f of faces) f.colour(e0, seaLevel);

  const controls = new OrbitControls(camera, canvas);
  controls.enableDamping = false;
  controls.enablePan = false;
  controls.minDistance = 1.05;
  controls.maxDistance = 20;
  camera.position.copy(viewDirection(params.get('view')).multiplyScalar(4));
  camera.up.set(0, 1, 0);
  if (params.get('view') === 'north' || params.get('view') === 'south') camera.up.set(0, 0, -1);
  camera.lookAt(0, 0, 0);
  // Slower rotation when close, so that a close-up can be steered.
  const tuneSpeed = () => {
    controls.rotateSpeed = Math.min(1, 0.6 * (camera.position.length() - 1));
  };

  const render = () => renderer.render(scene, camera);
  const resize = () => {
    const w = canvas.clientWidth, h = canvas.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  };
  controls.addEventListener('change', () => { tuneSpeed(); render(); });
  window.addEventListener('resize', resize);

  // relief exaggeration
  const slider = $('pg-exaggeration'), label = $('pg-exaggeration-value');
  let exaggeration = e0;
  const setExaggeration = (k) => {
    exaggeration = k;
    label.textContent = `${k}×`;
    if (e0 > 0) {
      for (const f of faces) f.rescale(k / e0);
      averageSeamNormals(faces, groups);
    }
    render();
  };
  slider.max = String(Math.max(100, 2 * e0));
  slider.disabled = !(e0 > 0); // a flat mesh has no relief to scale
  slider.addEventListener('input', () => setExaggeration(Number(slider.value)));

  // albedo / shaded relief
  const setMode = (mode) => {
    for (const f of faces) f.mesh.material = mode === 'relief' ? f.relief : f.albedo;
    $('pg-albedo').classList.toggle('on', mode !== 'relief');
    $('pg-relief').classList.toggle('on', mode === 'relief');
    render();
  };
  $('pg-albedo').addEventListener('click', () => setMode('albedo'));
  $('pg-relief').addEventListener('click', () => setMode('relief'));

  const start = Number(params.get('relief'));
  slider.value = String(params.has('relief') && start >= 0 ? start : e0);
  setMode(params.get('mode') === 'relief' ? 'relief' : 'albedo');
  setExaggeration(Number(slider.value));
  $('pg-info').textContent =
    `${url}\nradius ${(a / 1000).toFixed(0)} km, ${faces.length} ${urls.length > 1 ? 'tiles' : 'faces'}, ` +
    `${extras.tiles}×${extras.tiles} tiles of ${extras.tile_size}² texels per face\n` +
    `seed ${extras.seed}, exported at ${e0}× relief`;
  tuneSpeed();
  resize();
  document.body.dataset.faces = String(faces.length);
  if ($('pg-errors').textContent === '') document.body.dataset.status = 'ready';
}

main().catch((e) => window.pgReportError(`error: ${e && e.message ? e.message : e}`));
