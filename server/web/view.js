// DEMLink's view of a particle world: a live run (demlink-run/demlink-server --view) or a
// finished one (demlink-view). Frames arrive over a WebSocket as compact binary (layout in
// server/include/demlink/server/view/frame_encoder.hpp); positions, radii and colour values
// stay 16-bit integers up to the GPU, which scales them into the domain box.
//
// Level of detail: every particle is a point splat (a disc shaded like a sphere); those
// that cover more than kNearPixels on screen, up to kNearBudget of them, are drawn as
// instanced sphere meshes instead. While the camera moves, the spheres are not chosen
// again (the choice waits until it stops) and the splats drawn are every k-th particle,
// k set by the measured frame time, so a million particles stay interactive on any
// graphics hardware; when the camera stops, all are drawn.
import * as THREE from '/three/build/three.module.js';
import { OrbitControls } from '/three/examples/jsm/controls/OrbitControls.js';

const kHeaderBytes = 144;
const kMagic = 0x46564c44;
const kVersion = 2;
const kNearPixels = 6;       // projected radius above which a particle is drawn as a sphere [px]
const kNearBudget = 8000;    // most sphere instances
const kMovingFrameMs = 40;   // frame time aimed at while the camera moves [ms]
const kMovingMin = 20000;    // fewest splats drawn while the camera moves
const kStillAfterMs = 200;   // the camera counts as still this long after its last move [ms]
const kColourNames = ['speed', 'force', 'material', 'id'];
const kColourUnits = ['m/s', 'N', '', ''];

const params = new URLSearchParams(location.search);
const canvas = document.getElementById('scene');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
renderer.setPixelRatio(1);
renderer.setClearColor(0x1e2126);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(40, 1, 0.001, 1000);
camera.up.set(0, 0, 1);  // the simulation's z points up
const controls = new OrbitControls(camera, canvas);
scene.add(new THREE.AmbientLight(0xffffff, 0.45));
const headLight = new THREE.DirectionalLight(0xffffff, 0.65);
camera.add(headLight);
scene.add(camera);

// ---- shaders: shared colour map, splats and spheres ----
const colourGlsl = `
uniform float colourMin, colourMax, categorical;
vec3 sequential(float t) {  // dark blue -> teal -> yellow
  t = clamp(t, 0.0, 1.0);
  return clamp(vec3(0.28 + t * (1.9 * t - 0.35), 0.05 + 0.9 * t, 0.45 + 0.6 * t - 0.95 * t * t), 0.0, 1.0);
}
vec3 hue(float h) {
  vec3 k = abs(fract(vec3(h) + vec3(0.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0;
  return mix(vec3(1.0), clamp(k, 0.0, 1.0), 0.7);
}
vec3 colourOf(float t) {
  if (categorical > 0.5) {
    float value = floor(colourMin + t * (colourMax - colourMin) + 0.5);
    return hue(fract(value * 0.618034 + 0.1));
  }
  return sequential(t);
}`;
const boxGlsl = `uniform vec3 boxLower, boxSize; uniform float radiusMax, pixelScale;`;
const uniforms = {
  boxLower: { value: new THREE.Vector3() }, boxSize: { value: new THREE.Vector3(1, 1, 1) },
  radiusMax: { value: 1 }, pixelScale: { value: 1 },
  colourMin: { value: 0 }, colourMax: { value: 1 }, categorical: { value: 0 },
};
const splatMaterial = new THREE.ShaderMaterial({
  uniforms,
  vertexShader: `${boxGlsl}${colourGlsl}
    attribute float qradius, qcolour, near;
    varying vec3 vColour;
    void main() {
      vec4 viewPosition = modelViewMatrix * vec4(boxLower + position * boxSize, 1.0);
      gl_Position = projectionMatrix * viewPosition;
      gl_PointSize = max(2.0, 2.0 * qradius * radiusMax * pixelScale / max(-viewPosition.z, 1e-6));
      if (near > 0.5) gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // drawn as a sphere instead
      vColour = colourOf(qcolour);
    }`,
  fragmentShader: `
    varying vec3 vColour;
    void main() {
      vec2 c = gl_PointCoord * 2.0 - 1.0;
      float d = dot(c, c);
      if (d > 1.0) discard;
      vec3 n = vec3(c.x, -c.y, sqrt(1.0 - d));
      float light = 0.35 + 0.65 * max(dot(n, normalize(vec3(0.35, 0.55, 0.75))), 0.0);
      gl_FragColor = vec4(vColour * light, 1.0);
    }`,
});
const sphereMaterial = new THREE.ShaderMaterial({
  uniforms,
  vertexShader: `${boxGlsl}${colourGlsl}
    attribute vec3 offset;
    attribute float radius, tcolour;
    varying vec3 vColour, vNormal;
    void main() {
      vNormal = normalize(normalMatrix * normal);
      gl_Position = projectionMatrix * modelViewMatrix * vec4(offset + position * radius, 1.0);
      vColour = colourOf(tcolour);
    }`,
  fragmentShader: `
    varying vec3 vColour, vNormal;
    void main() {
      float light = 0.35 + 0.65 * max(dot(normalize(vNormal), normalize(vec3(0.35, 0.55, 0.75))), 0.0);
      gl_FragColor = vec4(vColour * light, 1.0);
    }`,
});

// ---- particles ----
const splatGeometry = new THREE.BufferGeometry();
const splats = new THREE.Points(splatGeometry, splatMaterial);
splats.frustumCulled = false;
scene.add(splats);
// While the camera moves: the same attributes, every k-th particle through an index.
const coarseGeometry = new THREE.BufferGeometry();
const coarseSplats = new THREE.Points(coarseGeometry, splatMaterial);
coarseSplats.frustumCulled = false;
coarseSplats.visible = false;
scene.add(coarseSplats);
let coarseStride = 0;
let capacity = 0;
let positionQ = null, radiusQ = null, colourQ = null, nearFlags = null;

const sphereGeometry = new THREE.InstancedBufferGeometry();
const unitSphere = new THREE.IcosahedronBufferGeometry(1, 2);
sphereGeometry.setIndex(unitSphere.index);
sphereGeometry.setAttribute('position', unitSphere.getAttribute('position'));
sphereGeometry.setAttribute('normal', unitSphere.getAttribute('normal'));
const sphereOffset = new THREE.InstancedBufferAttribute(new Float32Array(3 * kNearBudget), 3);
const sphereRadius = new THREE.InstancedBufferAttribute(new Float32Array(kNearBudget), 1);
const sphereColour = new THREE.InstancedBufferAttribute(new Float32Array(kNearBudget), 1);
sphereGeometry.setAttribute('offset', sphereOffset);
sphereGeometry.setAttribute('radius', sphereRadius);
sphereGeometry.setAttribute('tcolour', sphereColour);
sphereGeometry.maxInstancedCount = 0;
const spheres = new THREE.Mesh(sphereGeometry, sphereMaterial);
spheres.frustumCulled = false;
scene.add(spheres);

function ensureCapacity(count) {
  if (positionQ && count <= capacity) return;
  capacity = Math.max(count, Math.ceil(capacity * 1.5), 1024);
  positionQ = new Uint16Array(3 * capacity);
  radiusQ = new Uint16Array(capacity);
  colourQ = new Uint16Array(capacity);
  nearFlags = new Uint8Array(capacity);
  splatGeometry.dispose();
  splatGeometry.setAttribute('position', new THREE.BufferAttribute(positionQ, 3, true));
  splatGeometry.setAttribute('qradius', new THREE.BufferAttribute(radiusQ, 1, true));
  splatGeometry.setAttribute('qcolour', new THREE.BufferAttribute(colourQ, 1, true));
  splatGeometry.setAttribute('near', new THREE.BufferAttribute(nearFlags, 1, false));
  coarseGeometry.dispose();
  for (const name of ['position', 'qradius', 'qcolour', 'near']) coarseGeometry.setAttribute(name, splatGeometry.getAttribute(name));
  coarseStride = 0;  // the index is made again for the new arrays
  sizeRatio = new Float32Array(capacity);
}

/// Draws every `stride`-th of the frame's `count` particles as coarse splats.
function setCoarseStride(stride, count) {
  if (stride === coarseStride && coarseGeometry.userData.count === count) return;
  const index = new Uint32Array(Math.ceil(count / stride));
  for (let k = 0; k < index.length; ++k) index[k] = k * stride;
  coarseGeometry.setIndex(new THREE.BufferAttribute(index, 1));
  coarseGeometry.userData.count = count;
  coarseStride = stride;
}

// ---- scene geometry: planes, meshes, surfaces, regions ----
let sceneInfo = { planes: [], meshes: [], surfaces: [], regions: [], materials: [] };
const meshObjects = [];
const surfaceObjects = [];
const regionObjects = [];
const planeObjects = [];
const edgeMaterial = new THREE.LineBasicMaterial({ color: 0xc8d0da });
const regionMaterial = new THREE.LineBasicMaterial({ color: 0xffc857 });
const springMaterial = new THREE.LineBasicMaterial({ color: 0xf0d0ea });

function buildScene(info) {
  // A server's next simulation brings a new scene: the last one's objects go.
  for (const object of [...meshObjects, ...regionObjects, ...planeObjects, ...surfaceObjects.map((s) => s.mesh),
    ...surfaceObjects.filter((s) => s.lines).map((s) => s.lines)]) {
    scene.remove(object);
  }
  meshObjects.length = regionObjects.length = planeObjects.length = surfaceObjects.length = 0;
  state.fitted = false;
  sceneInfo = info;
  for (const mesh of info.meshes) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(mesh.vertices), 3));
    geometry.setIndex(mesh.triangles);
    geometry.computeVertexNormals();
    const group = new THREE.Group();
    group.add(new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({
      color: 0x7f93a8, side: THREE.DoubleSide, transparent: true, opacity: 0.55, depthWrite: false })));
    group.add(new THREE.LineSegments(new THREE.EdgesGeometry(geometry, 20), edgeMaterial));
    scene.add(group);
    meshObjects.push(group);
  }
  for (const surface of info.surfaces) {
    const geometry = new THREE.BufferGeometry();
    const mesh = new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({ color: 0xb07fa8, side: THREE.DoubleSide }));
    mesh.frustumCulled = false;
    scene.add(mesh);
    // A mass-spring body's springs as lines between its nodes; a torn spring is not drawn.
    const springs = surface.springs ?? [];
    let lines = null;
    if (springs.length > 0) {
      lines = new THREE.LineSegments(new THREE.BufferGeometry(), springMaterial);
      lines.frustumCulled = false;
      scene.add(lines);
    }
    surfaceObjects.push({ mesh, triangles: surface.triangles, activeKey: '', springs, lines, intactKey: '' });
  }
}

function updatePlanes(lower, upper) {
  if (planeObjects.length > 0 || sceneInfo.planes.length === 0) return;
  const size = Math.max(upper[0] - lower[0], upper[1] - lower[1], upper[2] - lower[2]) * 1.2 || 1;
  const centre = new THREE.Vector3((lower[0] + upper[0]) / 2, (lower[1] + upper[1]) / 2, (lower[2] + upper[2]) / 2);
  for (const plane of sceneInfo.planes) {
    const point = new THREE.Vector3(...plane.point);
    const normal = new THREE.Vector3(...plane.normal).normalize();
    // The square is centred on the projection of the domain's centre onto the plane.
    const foot = centre.clone().sub(normal.clone().multiplyScalar(centre.clone().sub(point).dot(normal)));
    const geometry = new THREE.PlaneBufferGeometry(size, size);
    const group = new THREE.Group();
    group.add(new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({
      color: 0x56606c, side: THREE.DoubleSide, transparent: true, opacity: 0.35, depthWrite: false })));
    group.add(new THREE.LineSegments(new THREE.EdgesGeometry(geometry), edgeMaterial));
    group.position.copy(foot);
    group.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), normal);
    scene.add(group);
    planeObjects.push(group);
  }
}

function regionObject(kind, half) {
  let geometry;
  if (kind === 0) geometry = new THREE.EdgesGeometry(new THREE.BoxBufferGeometry(2 * half[0], 2 * half[1], 2 * half[2]));
  else if (kind === 1) geometry = new THREE.WireframeGeometry(new THREE.IcosahedronBufferGeometry(half[0], 1));
  else if (kind === 2) geometry = new THREE.EdgesGeometry(new THREE.PlaneBufferGeometry(2 * half[0], 2 * half[1]));
  else geometry = new THREE.EdgesGeometry(new THREE.CircleBufferGeometry(half[0], 48));
  return new THREE.LineSegments(geometry, regionMaterial);
}

// ---- frames ----
const state = {
  status: null, framesReceived: 0, fps: 0, paused: false, fitted: false, live: true,
  frames: 0, times: [], frameIndex: 0, playing: false, nearCount: 0, shown: 0, bytes: 0, moving: false, splatsDrawn: 0,
  simulations: [], followed: 0, maxRate: 30, surfaces: [],
};
window.demlinkView = state;
let lastFrame = null;
let nearDirty = true;

function decodeFrame(buffer) {
  const view = new DataView(buffer);
  if (buffer.byteLength < kHeaderBytes || view.getUint32(0, true) !== kMagic) throw new Error('not a DEMLink view frame');
  if (view.getUint32(4, true) !== kVersion) throw new Error(`view frame version ${view.getUint32(4, true)}, expected ${kVersion}`);
  const f32 = (offset) => view.getFloat32(offset, true);
  const frame = {
    time: view.getFloat64(8, true), step: view.getFloat64(16, true), rtf: view.getFloat64(24, true),
    stepRate: view.getFloat64(32, true), mass: view.getFloat64(40, true), inserted: view.getFloat64(48, true),
    removed: view.getFloat64(56, true), initialMass: view.getFloat64(64, true),
    total: view.getUint32(72, true), count: view.getUint32(76, true),
    lower: [f32(80), f32(84), f32(88)], upper: [f32(92), f32(96), f32(100)],
    radiusMax: f32(104), colourMin: f32(108), colourMax: f32(112), colourField: view.getUint32(116, true),
    meshCount: view.getUint32(120, true), surfaceCount: view.getUint32(124, true),
    regionCount: view.getUint32(128, true), frameIndex: view.getUint32(132, true), frameCount: view.getUint32(136, true),
  };
  const m = frame.count;
  const align = (offset) => (offset + 3) & ~3;
  let offset = kHeaderBytes;
  frame.positions = new Uint16Array(buffer, offset, 3 * m); offset = align(offset + 6 * m);
  frame.radii = new Uint16Array(buffer, offset, m); offset = align(offset + 2 * m);
  frame.colours = new Uint16Array(buffer, offset, m); offset = align(offset + 2 * m);
  frame.meshes = [];
  for (let k = 0; k < frame.meshCount; ++k, offset += 28) {
    frame.meshes.push(Array.from({ length: 7 }, (_, i) => f32(offset + 4 * i)));
  }
  frame.regions = [];
  for (let k = 0; k < frame.regionCount; ++k, offset += 44) {
    frame.regions.push({ kind: view.getUint32(offset, true), half: [f32(offset + 4), f32(offset + 8), f32(offset + 12)],
      pose: Array.from({ length: 7 }, (_, i) => f32(offset + 16 + 4 * i)) });
  }
  frame.surfaces = [];
  for (let k = 0; k < frame.surfaceCount; ++k) {
    const nodes = view.getUint32(offset, true), triangles = view.getUint32(offset + 4, true);
    const springs = view.getUint32(offset + 8, true);
    offset += 12;
    const positions = new Float32Array(buffer.slice(offset, offset + 12 * nodes)); offset += 12 * nodes;
    const active = new Uint8Array(buffer, offset, triangles); offset = align(offset + triangles);
    const intact = new Uint8Array(buffer, offset, springs); offset = align(offset + springs);
    frame.surfaces.push({ positions, active, intact });
  }
  return frame;
}

function setPose(object, pose) {
  object.position.set(pose[0], pose[1], pose[2]);
  object.quaternion.set(pose[3], pose[4], pose[5], pose[6]);
}

function applyFrame(frame) {
  ensureCapacity(frame.count);
  positionQ.set(frame.positions);
  radiusQ.set(frame.radii);
  colourQ.set(frame.colours);
  for (const name of ['position', 'qradius', 'qcolour']) splatGeometry.getAttribute(name).needsUpdate = true;
  splatGeometry.setDrawRange(0, frame.count);
  uniforms.boxLower.value.set(...frame.lower);
  uniforms.boxSize.value.set(frame.upper[0] - frame.lower[0], frame.upper[1] - frame.lower[1], frame.upper[2] - frame.lower[2]);
  uniforms.radiusMax.value = frame.radiusMax;
  uniforms.colourMin.value = frame.colourMin;
  uniforms.colourMax.value = frame.colourMax;
  uniforms.categorical.value = frame.colourField >= 2 ? 1 : 0;
  frame.meshes.forEach((pose, k) => { if (meshObjects[k]) setPose(meshObjects[k], pose); });
  while (regionObjects.length < frame.regions.length) {
    const region = frame.regions[regionObjects.length];
    const object = regionObject(region.kind, region.half);
    scene.add(object);
    regionObjects.push(object);
  }
  frame.regions.forEach((region, k) => setPose(regionObjects[k], region.pose));
  frame.surfaces.forEach((surface, k) => updateSurface(surfaceObjects[k], surface));
  // What each surface draws now (the browser tests read it): triangles and spring lines.
  state.surfaces = surfaceObjects.map((s) => ({
    triangles: (s.mesh.geometry.index?.count ?? 0) / 3, springs: (s.lines?.geometry.index?.count ?? 0) / 2 }));
  updatePlanes(frame.lower, frame.upper);
  if (!state.fitted && frame.count > 0) fitCamera(frame.lower, frame.upper);
  lastFrame = frame;
  nearDirty = true;
  showStatus(frame);
  drawLegend(frame);
}

function updateSurface(object, surface) {
  if (!object) return;
  const geometry = object.mesh.geometry;
  const positions = new THREE.BufferAttribute(surface.positions, 3);
  geometry.setAttribute('position', positions);
  if (object.lines) {
    object.lines.geometry.setAttribute('position', positions);
    const key = surface.intact.join('');
    if (key !== object.intactKey) {  // a spring tore: only intact springs are drawn
      const index = [];
      object.springs.forEach((node, i) => { if (surface.intact[i >> 1]) index.push(node); });
      object.lines.geometry.setIndex(index);
      object.intactKey = key;
    }
  }
  const key = surface.active.join('');
  if (key !== object.activeKey) {  // a tear: only active triangles are drawn
    const index = [];
    object.triangles.forEach((v, i) => { if (surface.active[Math.floor(i / 3)]) index.push(v); });
    geometry.setIndex(index);
    object.activeKey = key;
  }
  geometry.computeVertexNormals();
}

function fitCamera(lower, upper) {
  // The particles' box, grown by the bodies and surfaces where they are now.
  const box = new THREE.Box3(new THREE.Vector3(...lower), new THREE.Vector3(...upper));
  scene.updateMatrixWorld();
  for (const object of [...meshObjects, ...surfaceObjects.map((s) => s.mesh)]) box.expandByObject(object);
  const centre = box.getCenter(new THREE.Vector3());
  const extent = box.getSize(new THREE.Vector3());
  const size = Math.max(extent.x, extent.y, extent.z) || 1;
  camera.near = size * 1e-3;
  camera.far = size * 100;
  camera.position.copy(centre).add(new THREE.Vector3(0.9, -1.5, 0.8).multiplyScalar(size));
  controls.target.copy(centre);
  camera.updateProjectionMatrix();
  controls.update();
  state.fitted = true;
}

const format = (value, digits = 4) => (Number.isFinite(value) ? Number(value.toPrecision(digits)).toString() : '–');
function showStatus(frame) {
  state.status = {
    time: frame.time, step: frame.step, rtf: frame.rtf, stepRate: frame.stepRate, particles: frame.total,
    shown: frame.count, mass: frame.mass, inserted: frame.inserted, removed: frame.removed,
    balance: frame.initialMass + frame.inserted - frame.removed - frame.mass,
  };
  const s = state.status;
  document.getElementById('time').textContent = s.time.toFixed(6);
  document.getElementById('rtf').textContent = state.live ? format(s.rtf, 3) : '–';
  document.getElementById('steprate').textContent = state.live ? format(s.stepRate, 4) : '–';
  document.getElementById('particles').textContent = String(s.particles);
  document.getElementById('shown').textContent = String(s.shown);
  // A recorded run's files hold no masses.
  const mass = (value, digits) => (state.live ? format(value, digits) : '–');
  document.getElementById('mass').textContent = mass(s.mass, 6);
  document.getElementById('inserted').textContent = mass(s.inserted, 6);
  document.getElementById('removed').textContent = mass(s.removed, 6);
  document.getElementById('balance').textContent = mass(s.balance, 2);
  if (!state.live) {
    document.getElementById('slider').value = String(frame.frameIndex);
    document.getElementById('frame-label').textContent = `frame ${frame.frameIndex + 1} / ${frame.frameCount}, t = ${format(frame.time, 6)} s`;
  }
}

function drawLegend(frame) {
  const field = frame.colourField;
  document.getElementById('legend-title').textContent = kColourUnits[field] ? `${kColourNames[field]} [${kColourUnits[field]}]` : kColourNames[field];
  const bar = document.getElementById('legend-bar');
  const items = document.getElementById('legend-items');
  const context = bar.getContext('2d');
  if (field === 2) {
    bar.style.display = 'none';
    document.getElementById('legend-min').textContent = '';
    document.getElementById('legend-max').textContent = '';
    const html = sceneInfo.materials.map((name, k) => {
      const [r, g, b] = hueRgb(((k * 0.618034 + 0.1) % 1));
      return `<span class="legend-item"><span class="swatch" style="background:rgb(${r},${g},${b})"></span>${name}</span>`;
    }).join('');
    if (items.innerHTML !== html) items.innerHTML = html;
    return;
  }
  items.innerHTML = '';
  bar.style.display = '';
  for (let x = 0; x < bar.width; ++x) {
    const t = x / (bar.width - 1);
    const [r, g, b] = field === 3 ? hueRgb((Math.floor(t * 12) * 0.618034 + 0.1) % 1) : sequentialRgb(t);
    context.fillStyle = `rgb(${r},${g},${b})`;
    context.fillRect(x, 0, 1, bar.height);
  }
  document.getElementById('legend-min').textContent = format(frame.colourMin, 3);
  document.getElementById('legend-max').textContent = format(frame.colourMax, 3);
}
// The shaders' colour maps, for the legend.
function sequentialRgb(t) {
  const c = [0.28 + t * (1.9 * t - 0.35), 0.05 + 0.9 * t, 0.45 + 0.6 * t - 0.95 * t * t];
  return c.map((v) => Math.round(255 * Math.min(1, Math.max(0, v))));
}
function hueRgb(h) {
  return [0, 2 / 3, 1 / 3].map((s) => {
    const k = Math.min(1, Math.max(0, Math.abs(((h + s) % 1) * 6 - 3) - 1));
    return Math.round(255 * (1 + 0.7 * (k - 1)));
  });
}

// ---- level of detail ----
const cameraPosition = new THREE.Vector3();
const lastCameraPosition = new THREE.Vector3(Infinity, Infinity, Infinity);
const lastCameraQuaternion = new THREE.Quaternion();
let lastCanvasWidth = 0;
let lastMove = -Infinity;  // when the camera last moved [ms]
let lodStale = false;      // the camera moved since the spheres were chosen
let sizeRatio = null;          // per particle: quantised radius over camera distance
const nearIndex = new Uint32Array(kNearBudget);  // the particles drawn as spheres
let nearCount = 0;
const kRatioBins = 64;          // 4 bins per factor of 2: sizes up to 2^16 times the base
const ratioHistogram = new Uint32Array(kRatioBins);

/// Whether the camera moved since the last call. OrbitControls recomputes the camera from
/// spherical coordinates every frame, which moves it by round-off while it stands still:
/// a change below 1e-7 of the distance to the target (or of a turn) is none.
function cameraMoved() {
  const distance = Math.max(camera.position.distanceTo(controls.target), 1e-9);
  const moved = camera.position.distanceTo(lastCameraPosition) > 1e-7 * distance ||
    1 - Math.abs(camera.quaternion.dot(lastCameraQuaternion)) > 1e-14 || canvas.width !== lastCanvasWidth;
  if (moved) {
    lastCameraPosition.copy(camera.position);
    lastCameraQuaternion.copy(camera.quaternion);
    lastCanvasWidth = canvas.width;
  }
  return moved;
}

/// Picks the particles drawn as spheres: those whose projected radius exceeds a
/// threshold, kNearPixels or raised (through a histogram of log2 sizes, one pass) until
/// at most kNearBudget pass it.
function updateLevelOfDetail() {
  const now = performance.now();
  if (cameraMoved()) lastMove = now;
  state.moving = now - lastMove < kStillAfterMs;
  if (lastFrame && state.moving) {
    lodStale = true;
    if (nearDirty) placeSpheres(lastFrame);  // a new frame: the same particles, where they are now
    nearDirty = false;
    return;
  }
  if (!lastFrame || !nearDirty && !lodStale) return;
  nearDirty = false;
  lodStale = false;
  const f = lastFrame;
  const m = f.count;
  const lower = f.lower, size = [f.upper[0] - f.lower[0], f.upper[1] - f.lower[1], f.upper[2] - f.lower[2]];
  cameraPosition.setFromMatrixPosition(camera.matrixWorld);
  const scale = uniforms.pixelScale.value * f.radiusMax / 65535;
  const base = kNearPixels / scale;  // a size ratio above this is a sphere at kNearPixels
  nearFlags.fill(0, 0, m);
  ratioHistogram.fill(0);
  let candidates = 0;
  for (let i = 0; i < m; ++i) {
    const x = lower[0] + f.positions[3 * i] / 65535 * size[0] - cameraPosition.x;
    const y = lower[1] + f.positions[3 * i + 1] / 65535 * size[1] - cameraPosition.y;
    const z = lower[2] + f.positions[3 * i + 2] / 65535 * size[2] - cameraPosition.z;
    const ratio = f.radii[i] / Math.sqrt(x * x + y * y + z * z);
    sizeRatio[i] = ratio;
    if (ratio > base) {
      ++candidates;
      ratioHistogram[Math.min(kRatioBins - 1, Math.floor(4 * Math.log2(ratio / base)))] += 1;
    }
  }
  // The lowest bin edge above which at most kNearBudget remain.
  let threshold = base;
  if (candidates > kNearBudget) {
    let above = 0;
    let bin = kRatioBins;
    while (bin > 0 && above + ratioHistogram[bin - 1] <= kNearBudget) above += ratioHistogram[--bin];
    threshold = base * Math.pow(2, bin / 4);
  }
  let count = 0;
  for (let i = 0; i < m && count < kNearBudget; ++i) {
    if (sizeRatio[i] <= threshold) continue;
    nearFlags[i] = 1;
    nearIndex[count++] = i;
  }
  nearCount = count;
  placeSpheres(f);
  splatGeometry.getAttribute('near').needsUpdate = true;
}

/// The sphere instances of the chosen particles (nearIndex) at frame `f`.
function placeSpheres(f) {
  const lower = f.lower, size = [f.upper[0] - f.lower[0], f.upper[1] - f.lower[1], f.upper[2] - f.lower[2]];
  let count = 0;
  for (let k = 0; k < nearCount; ++k) {
    const i = nearIndex[k];
    if (i >= f.count) continue;  // the frame holds fewer particles than the chosen one's place
    sphereOffset.array[3 * count] = lower[0] + f.positions[3 * i] / 65535 * size[0];
    sphereOffset.array[3 * count + 1] = lower[1] + f.positions[3 * i + 1] / 65535 * size[1];
    sphereOffset.array[3 * count + 2] = lower[2] + f.positions[3 * i + 2] / 65535 * size[2];
    sphereRadius.array[count] = f.radii[i] / 65535 * f.radiusMax;
    sphereColour.array[count] = f.colours[i] / 65535;
    ++count;
  }
  sphereGeometry.maxInstancedCount = count;
  sphereOffset.needsUpdate = sphereRadius.needsUpdate = sphereColour.needsUpdate = true;
  state.nearCount = count;
}

/// While the camera moves, every k-th splat: k grows when a frame took longer than
/// kMovingFrameMs and shrinks when it took well under; all of them once it is still.
let movingBudget = 250000;
function chooseSplats(frameMs) {
  const m = lastFrame ? lastFrame.count : 0;
  if (!state.moving || m <= kMovingMin) {
    splats.visible = true;
    coarseSplats.visible = false;
    state.splatsDrawn = m;
    return;
  }
  if (frameMs > kMovingFrameMs) movingBudget = Math.max(kMovingMin, Math.floor(movingBudget * 0.6));
  else if (frameMs < 0.5 * kMovingFrameMs) movingBudget = Math.min(m, Math.ceil(movingBudget * 1.25));
  const stride = Math.max(1, Math.ceil(m / movingBudget));
  setCoarseStride(stride, m);
  splats.visible = stride === 1;
  coarseSplats.visible = stride > 1;
  state.splatsDrawn = Math.ceil(m / stride);
}

// ---- connection ----
let socket = null;
function request(text) { if (socket && socket.readyState === WebSocket.OPEN) socket.send(text); }
function currentRequest() {
  // The server's cap (--view-max-rate, in its hello) bounds the rate asked for.
  const rate = Math.min(Number(document.getElementById('rate').value), state.maxRate);
  return `rate=${rate} max=${document.getElementById('budget').value} ` +
    `colour=${document.getElementById('colour').value}`;
}
function connect() {
  const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws` +
    (params.get('token') ? `?token=${encodeURIComponent(params.get('token'))}` : '');
  socket = new WebSocket(url);
  socket.binaryType = 'arraybuffer';
  const connection = document.getElementById('connection');
  socket.onopen = () => { connection.textContent = 'connected'; };
  socket.onclose = () => { connection.textContent = 'disconnected (the run ended or the server stopped)'; };
  socket.onmessage = (event) => {
    if (typeof event.data === 'string') { onText(JSON.parse(event.data)); return; }
    state.framesReceived += 1;
    state.bytes = event.data.byteLength;
    document.getElementById('received').textContent = String(state.framesReceived);
    if (state.paused) return;
    applyFrame(decodeFrame(event.data));
    if (state.playing) schedulePlay();
  };
}
function onText(message) {
  if (message.kind === 'scene') buildScene(message);
  else if (message.kind === 'hello') {
    state.maxRate = message.maxRate;
    request(currentRequest());  // the first request: it needs the hello's rate cap
    state.live = message.live;
    state.frames = message.frames;
    state.times = message.times;
    if (!state.live) {
      document.getElementById('timeline').classList.remove('hidden');
      document.getElementById('slider').max = String(Math.max(0, message.frames - 1));
      request('frame=0');
    }
  } else if (message.kind === 'simulations') {
    showSimulations(message);
  } else if (message.kind === 'error') {
    document.getElementById('connection').textContent = `server: ${message.message}`;
  }
}

// A server's simulations, when it runs several: the choice shows which one this page follows
// (the server's default until the page picks one, and again when the picked one closes).
function showSimulations(message) {
  state.simulations = message.simulations;
  state.followed = message.followed;
  document.getElementById('simulation-choice').classList.toggle('hidden', message.simulations.length < 2);
  const select = document.getElementById('simulation');
  const ids = message.simulations.map((s) => String(s.id));
  if (Array.from(select.options, (o) => o.value).join() !== ids.join()) {
    select.replaceChildren(...ids.map((id) => new Option('', id)));
  }
  message.simulations.forEach((s, k) => {
    select.options[k].textContent = `${s.name}: ${s.particles} particles, t = ${format(s.time, 4)} s`;
  });
  if (message.followed) select.value = String(message.followed);
}

// ---- controls ----
document.getElementById('simulation').addEventListener('change', (event) => request(`sim=${event.target.value}`));
for (const id of ['colour', 'budget', 'rate']) document.getElementById(id).addEventListener('change', () => request(currentRequest()));
document.getElementById('pause').addEventListener('click', (event) => {
  state.paused = !state.paused;
  event.target.textContent = state.paused ? 'resume view' : 'pause view';
});
document.getElementById('fit').addEventListener('click', () => { if (lastFrame) fitCamera(lastFrame.lower, lastFrame.upper); });
function showFrame(index) {
  state.frameIndex = Math.min(Math.max(0, index), Math.max(0, state.frames - 1));
  request(`frame=${state.frameIndex}`);
}
let playTimer = null;
function schedulePlay() {
  if (playTimer) return;
  playTimer = setTimeout(() => {
    playTimer = null;
    if (!state.playing) return;
    if (state.frameIndex + 1 >= state.frames) { setPlaying(false); return; }
    showFrame(state.frameIndex + 1);
  }, 1000 / Number(document.getElementById('rate').value));
}
function setPlaying(playing) {
  state.playing = playing;
  document.getElementById('play').textContent = playing ? 'pause' : 'play';
  if (playing) { if (state.frameIndex + 1 >= state.frames) showFrame(0); else schedulePlay(); }
}
document.getElementById('play').addEventListener('click', () => setPlaying(!state.playing));
document.getElementById('step').addEventListener('click', () => { setPlaying(false); showFrame(state.frameIndex + 1); });
document.getElementById('back').addEventListener('click', () => { setPlaying(false); showFrame(state.frameIndex - 1); });
document.getElementById('slider').addEventListener('input', (event) => { setPlaying(false); showFrame(Number(event.target.value)); });

// ---- drawing ----
function resize() {
  const width = canvas.clientWidth, height = canvas.clientHeight;
  if (canvas.width !== width || canvas.height !== height) {
    renderer.setSize(width, height, false);
    camera.aspect = width / Math.max(1, height);
    camera.updateProjectionMatrix();
  }
  uniforms.pixelScale.value = height / (2 * Math.tan(camera.fov * Math.PI / 180 / 2));
}
// Screen position (CSS pixels) of a world point, for tests that check what is drawn where.
state.project = (x, y, z) => {
  const p = new THREE.Vector3(x, y, z).project(camera);
  return { x: (p.x + 1) / 2 * canvas.clientWidth, y: (1 - p.y) / 2 * canvas.clientHeight, visible: Math.abs(p.z) <= 1 };
};
let drawn = 0, fpsStart = performance.now(), lastDraw = performance.now();
function animate() {
  requestAnimationFrame(animate);
  const start = performance.now();
  const frameMs = start - lastDraw;
  lastDraw = start;
  resize();
  controls.update();
  camera.updateMatrixWorld();
  updateLevelOfDetail();
  chooseSplats(frameMs);
  renderer.render(scene, camera);
  drawn += 1;
  const now = performance.now();
  if (now - fpsStart >= 1000) {
    state.fps = drawn * 1000 / (now - fpsStart);
    document.getElementById('fps').textContent = state.fps.toFixed(1);
    drawn = 0;
    fpsStart = now;
  }
}
connect();
animate();
