// The mbd browser viewer: reads the scene and the motion embedded in the page by
// `mbd animate` (viewer/src/html_export.cpp), draws the bodies with three.js and plays
// the motion. window.mbdViewer is the page's API (used by viewer/test/).
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { axisName, drawAxes, niceTicks, tickLabel } from './plot_axes.js';
import { countBodyPixels } from './pixel_coverage.js';
import { bodiesBox, chooseFraming, frameBox, meanPosition } from './framing.js';

function decodeBase64(text) {
  const s = text.trim();
  if (Uint8Array.fromBase64) return Uint8Array.fromBase64(s);
  const raw = atob(s);
  const bytes = new Uint8Array(raw.length);
  for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
  return bytes;
}
const floats = (b64) => { const b = decodeBase64(b64); return new Float32Array(b.buffer, b.byteOffset, b.byteLength / 4); };
const uints = (b64) => { const b = decodeBase64(b64); return new Uint32Array(b.buffer, b.byteOffset, b.byteLength / 4); };

const scene = JSON.parse(document.getElementById('mbd-scene').textContent);
// the motion (viewer/src/html_export.cpp): the keyframe times as float64, then each column
// as float32, a pose column at the keyframes, any other as its envelope (min, max over each
// of plotBuckets equal intervals of time)
let motion = decodeBase64(document.getElementById('mbd-motion').textContent);
if (motion.byteOffset % 8) motion = motion.slice();
const nKeyframes = scene.keyframes;
const columnNames = scene.columns.map((c) => c.name);
const series = scene.columns.map((c, i) => (i === 0
  ? new Float64Array(motion.buffer, motion.byteOffset, nKeyframes)
  : new Float32Array(motion.buffer, motion.byteOffset + c.offset, c.pose ? nKeyframes : 2 * scene.plotBuckets)));
const value = (row, column) => series[column][row];  // a keyframe of the time or a pose column
const tStart = value(0, 0), tEnd = value(nKeyframes - 1, 0);

// ---- three.js scene
const host = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
host.appendChild(renderer.domElement);
const world = new THREE.Scene();
world.background = new THREE.Color(0xf4f5f7);
const up = new THREE.Vector3(...scene.up);
const camera = new THREE.PerspectiveCamera(40, 1, 1e-3, 1e4);
camera.up.copy(up);
world.add(new THREE.HemisphereLight(0xffffff, 0x8890a0, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
world.add(sun);

const geometries = scene.meshes.map((m) => {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(floats(m.positions), 3));
  g.setAttribute('normal', new THREE.BufferAttribute(floats(m.normals), 3));
  g.setIndex(new THREE.BufferAttribute(uints(m.indices), 1));
  g.computeBoundingSphere();
  g.computeBoundingBox();
  return g;
});
const materials = new Map();
function material(color) {
  const key = color.join(',');
  if (!materials.has(key))
    materials.set(key, new THREE.MeshStandardMaterial({ color: new THREE.Color().setRGB(...color, THREE.LinearSRGBColorSpace), roughness: 0.6, metalness: 0.1 }));
  return materials.get(key);
}
// Every shape is drawn through one InstancedMesh per (triangle mesh, colour): a scene of
// hundreds of bodies is a few draw calls, not thousands.
const batches = new Map();
function addInstance(meshIndex, color, name, body, local) {
  const key = `${meshIndex}|${color.join(',')}`;
  if (!batches.has(key)) batches.set(key, { meshIndex, color, items: [] });
  const items = batches.get(key).items;
  items.push({ name, body, local });
  return { key, index: items.length - 1 };  // where the shape is drawn (see slotMatrix)
}
const shapeMatrix = (s) => new THREE.Matrix4().compose(new THREE.Vector3(...s.position),
  new THREE.Quaternion(...s.rotation), new THREE.Vector3(...s.scale));

const ground = new THREE.Group();
world.add(ground);
const groundSlots = scene.ground.map((s) => addInstance(s.mesh, s.color, 'ground', -1, shapeMatrix(s)));
let grid;
{
  const g = scene.grid;
  grid = new THREE.GridHelper(g.size, g.divisions, 0x9098a8, 0xc8ccd4);
  grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), new THREE.Vector3(...g.normal));
  grid.position.set(...g.centre);
  ground.add(grid);
}
// a body is an (empty) group whose matrixWorld is its pose; its shapes are instances
const bodySlots = [];
const bodies = scene.bodies.map((b, i) => {
  const group = new THREE.Group();
  group.name = b.name;
  bodySlots.push(b.shapes.map((s) => addInstance(s.mesh, s.color, b.name, i, shapeMatrix(s))));
  world.add(group);
  return group;
});
const connectorPoses = scene.connectors.map((c) => {
  const pose = new THREE.Matrix4();
  addInstance(scene.connectorMesh, c.color, c.name, -2, pose);
  return pose;
});
const pickable = [];
const instanced = [...batches.values()].map((batch) => {
  const mesh = new THREE.InstancedMesh(geometries[batch.meshIndex], material(batch.color), batch.items.length);
  mesh.frustumCulled = false;  // the instances move; their bounds are recomputed for picking
  mesh.userData.names = batch.items.map((item) => item.name);
  world.add(mesh);
  pickable.push(mesh);
  batch.mesh = mesh;
  return { mesh, items: batch.items };
});
// the matrix a shape is drawn with now (world)
const slotMatrix = (slot, out) => { batches.get(slot.key).mesh.getMatrixAt(slot.index, out); return out; };
const instanceMatrix = new THREE.Matrix4();
function placeInstances() {
  instanced.forEach(({ mesh, items }) => {
    items.forEach((item, i) => {
      if (item.body >= 0) instanceMatrix.multiplyMatrices(bodies[item.body].matrixWorld, item.local);
      else instanceMatrix.copy(item.local);  // ground (fixed) or a connector (posed in world)
      mesh.setMatrixAt(i, instanceMatrix);
    });
    mesh.instanceMatrix.needsUpdate = true;
    mesh.boundingSphere = null;
  });
}

// ---- poses at time t (linear in position and angle, spherical linear in rotation)
const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
const zAxis = new THREE.Vector3(0, 0, 1);
function rowAt(t) {
  let lo = 0, hi = nKeyframes - 1;
  if (t <= value(0, 0)) return [0, 0];
  if (t >= value(hi, 0)) return [hi, 0];
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (value(mid, 0) <= t) lo = mid; else hi = mid; }
  return [lo, (t - value(lo, 0)) / (value(lo + 1, 0) - value(lo, 0))];
}
function quaternionAt(p, row, out) {
  if (p.angle >= 0) return out.setFromAxisAngle(zAxis, value(row, p.angle));
  return out.set(value(row, p.e[1]), value(row, p.e[2]), value(row, p.e[3]), value(row, p.e[0])).normalize();
}
function poseAt(index, row, f, position, quaternion) {
  const p = scene.poseColumns[index];
  const r2 = Math.min(row + 1, nKeyframes - 1);
  const lerp = (c) => (c < 0 ? 0 : value(row, c) + f * (value(r2, c) - value(row, c)));
  position.set(lerp(p.x), lerp(p.y), lerp(p.z));
  if (p.angle >= 0) return quaternion.setFromAxisAngle(zAxis, lerp(p.angle));
  quaternionAt(p, row, qa);
  quaternionAt(p, r2, qb);
  return quaternion.slerpQuaternions(qa, qb, f);
}
// ---- contacts (html_export.cpp json_contacts): at each keyframe the collision contacts, each
// [x, y, z, nx, ny, nz, normal force, friction x, y, z] (the forces on body j), drawn as at the
// keyframe at or before the time shown: a dot at the point, an arrow along the normal force and
// one along the friction force. Arrow lengths are in proportion to the forces, the median normal
// force of the run a sixth of the scene's length scale (impacts, far larger, are capped at the
// length scale). Drawn over the bodies (a resting body hides the points it stands on).
const contactFrames = scene.contacts || [];
const normalForces = contactFrames.flatMap((f) => f.map((c) => Math.abs(c[6]))).filter((f) => f > 0).sort((a, b) => a - b);
const typicalForce = normalForces.length ? normalForces[Math.floor(normalForces.length / 2)] : 0;
const metresPerNewton = typicalForce > 0 ? scene.lengthScale / (6 * typicalForce) : 0;
const contactDots = new THREE.Points(new THREE.BufferGeometry(),
  new THREE.PointsMaterial({ color: 0xd03020, size: 7, sizeAttenuation: false, depthTest: false }));
contactDots.renderOrder = 2;
contactDots.frustumCulled = false;
world.add(contactDots);
const normalArrows = [], frictionArrows = [];
let shownContacts = [], shownRow = 0;
function arrowOf(pool, i, color) {
  if (!pool[i]) {
    const a = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 1, color);
    a.line.material.depthTest = false; a.cone.material.depthTest = false;
    a.renderOrder = 2; a.line.renderOrder = 2; a.cone.renderOrder = 2;
    world.add(a);
    pool[i] = a;
  }
  return pool[i];
}
function drawArrow(pool, i, color, point, force) {
  const length = Math.min(force.length() * metresPerNewton, scene.lengthScale);
  const a = arrowOf(pool, i, color);
  a.visible = length > 1e-9 * scene.lengthScale;
  if (!a.visible) return;
  a.position.copy(point);
  a.setDirection(force.clone().divideScalar(force.length()));
  a.setLength(length, Math.min(0.3 * length, 0.05 * scene.lengthScale), Math.min(0.15 * length, 0.025 * scene.lengthScale));
}
function placeContacts(row) {
  shownRow = row;
  shownContacts = contactFrames.length ? contactFrames[row] : [];
  const dots = new Float32Array(3 * shownContacts.length);
  const point = new THREE.Vector3(), force = new THREE.Vector3();
  shownContacts.forEach((c, i) => {
    point.set(c[0], c[1], c[2]);
    dots.set([c[0], c[1], c[2]], 3 * i);
    drawArrow(normalArrows, i, 0xd03020, point, force.set(c[3], c[4], c[5]).multiplyScalar(c[6]));
    drawArrow(frictionArrows, i, 0x2060d0, point, force.set(c[7], c[8], c[9]));
  });
  for (const pool of [normalArrows, frictionArrows]) for (let i = shownContacts.length; i < pool.length; i++) pool[i].visible = false;
  contactDots.geometry.setAttribute('position', new THREE.BufferAttribute(dots, 3));
  contactDots.visible = shownContacts.length > 0;
}

// ---- flexible bodies (html_export.cpp json_flexible): a tube through the nodes, rebuilt at each
// frame from the node positions (linear in time between keyframes, as the mass centres); with
// two nodes a straight tube, with more a centripetal Catmull-Rom curve through every node.
const flexibleTubes = (scene.flexible || []).map((f) => {
  const mesh = new THREE.Mesh(new THREE.BufferGeometry(), material(f.color));
  mesh.name = f.name;
  mesh.frustumCulled = false;
  world.add(mesh);
  return { body: f, mesh, nodes: f.nodes.map(() => new THREE.Vector3()) };
});
function placeFlexible(row, f) {
  const r2 = Math.min(row + 1, nKeyframes - 1);
  const lerp = (c) => (c < 0 ? 0 : value(row, c) + f * (value(r2, c) - value(row, c)));
  flexibleTubes.forEach((tube) => {
    tube.body.nodes.forEach((c, i) => tube.nodes[i].set(lerp(c[0]), lerp(c[1]), lerp(c[2])));
    const curve = new THREE.CatmullRomCurve3(tube.nodes, false, 'centripetal');
    tube.mesh.geometry.dispose();
    tube.mesh.geometry = new THREE.TubeGeometry(curve, 8 * Math.max(tube.nodes.length - 1, 1), tube.body.radius, 10, false);
  });
}

const pa = new THREE.Vector3(), pb = new THREE.Vector3(), d = new THREE.Vector3();
let current = tStart;
function apply(t) {
  current = Math.min(Math.max(t, tStart), tEnd);
  const [row, f] = rowAt(current);
  bodies.forEach((g, i) => poseAt(i, row, f, g.position, g.quaternion));
  world.updateMatrixWorld(true);
  const q = new THREE.Quaternion(), scale = new THREE.Vector3();
  scene.connectors.forEach((c, i) => {
    pa.set(...c.pointA); pb.set(...c.pointB);
    if (c.bodyA >= 0) pa.applyMatrix4(bodies[c.bodyA].matrixWorld);
    if (c.bodyB >= 0) pb.applyMatrix4(bodies[c.bodyB].matrixWorld);
    d.subVectors(pb, pa);
    const length = d.length();
    q.setFromUnitVectors(zAxis, length > 0 ? d.divideScalar(length) : zAxis);
    connectorPoses[i].compose(pa, q, scale.set(c.radius, c.radius, Math.max(length, 1e-9)));
  });
  placeInstances();
  placeFlexible(row, f);
  placeContacts(row);
  if (follow && lastMean) {  // the camera and its target move with the mechanism
    const now = meanPosition(bodies, new THREE.Vector3());
    camera.position.add(now.clone().sub(lastMean));
    controls.target.add(now.clone().sub(lastMean));
    controls.update();
    lastMean.copy(now);
  }
  slider.value = String(Math.round(((current - tStart) / Math.max(tEnd - tStart, 1e-300)) * 10000));
  timeLabel.textContent = `t = ${current.toFixed(3)} s`;
  drawPlot();
}

// ---- camera: the mechanism in view (framing.js), followed when it travels
const massCentres = { box: new THREE.Box3(), startBox: new THREE.Box3() };
const meanPath = new THREE.Box3();
const meanStart = new THREE.Vector3(), meanEnd = new THREE.Vector3();
{
  const p = new THREE.Vector3(), mean = new THREE.Vector3();
  const at = (r, c) => (c >= 0 ? value(r, c) : 0);
  for (let r = 0; r < nKeyframes; r += Math.max(1, Math.floor(nKeyframes / 400))) {
    mean.set(0, 0, 0);
    scene.poseColumns.forEach((c) => {
      p.set(at(r, c.x), at(r, c.y), at(r, c.z));
      massCentres.box.expandByPoint(p);
      if (r === 0) massCentres.startBox.expandByPoint(p);
      mean.add(p);
    });
    meanPath.expandByPoint(mean.multiplyScalar(1 / Math.max(scene.poseColumns.length, 1)));
    if (r === 0) meanStart.copy(mean);
    meanEnd.copy(mean);
  }
}
const viewDir = scene.dimension === 'planar'
  ? new THREE.Vector3(0, 0, 1)
  : (() => { const a = new THREE.Vector3(1, 0, 0); if (Math.abs(a.dot(up)) > 0.9) a.set(0, 1, 0);
      a.sub(up.clone().multiplyScalar(a.dot(up))).normalize(); const b = up.clone().cross(a);
      return a.multiplyScalar(1).add(b.multiplyScalar(-1.3)).add(up.clone().multiplyScalar(0.8)).normalize(); })();
const controls = new OrbitControls(camera, renderer.domElement);
let follow = false, lastMean = null, framing = null;
// called once the first frame is placed: the bodies' drawn box is known
function frameMechanism() {
  const start = bodiesBox(instanced, new THREE.Box3());
  if (start.isEmpty()) start.copy(massCentres.startBox).expandByScalar(0.3 * scene.lengthScale);
  if (start.isEmpty()) start.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3().setScalar(scene.lengthScale));
  framing = chooseFraming(start, massCentres, meanPath);
  // a vehicle is seen from its side, a little ahead and above
  const travel = meanEnd.clone().sub(meanStart);
  travel.addScaledVector(up, -travel.dot(up));
  if (framing.follow && scene.dimension !== 'planar' && travel.length() > 0) {
    travel.normalize();
    viewDir.copy(up.clone().cross(travel)).addScaledVector(travel, 0.35).addScaledVector(up, 0.45).normalize();
  }
  const radius = frameBox(camera, controls, framing.box, viewDir);
  sun.position.copy(camera.position).add(up.clone().multiplyScalar(radius * 2));
  setFollow(framing.follow);
}
function setFollow(on) {
  follow = on;
  followBox.checked = on;
  lastMean = on ? meanPosition(bodies, new THREE.Vector3()) : null;
}

function resize() {
  const w = host.clientWidth, h = host.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);

// ---- controls: play, speed, time slider
const playButton = document.getElementById('play');
const speedSelect = document.getElementById('speed');
const slider = document.getElementById('slider');
const timeLabel = document.getElementById('time');
const followBox = document.getElementById('follow');
followBox.addEventListener('change', () => setFollow(followBox.checked));
let playing = false, speed = 1, last = null;
function setPlaying(on) { playing = on; last = on ? performance.now() : null; playButton.textContent = on ? 'pause' : 'play'; }
playButton.addEventListener('click', () => { if (!playing && current >= tEnd) apply(tStart); setPlaying(!playing); });
speedSelect.addEventListener('change', () => { speed = Number(speedSelect.value); });
slider.addEventListener('input', () => { setPlaying(false); apply(tStart + (Number(slider.value) / 10000) * (tEnd - tStart)); });
window.addEventListener('keydown', (e) => { if (e.code === 'Space' && e.target === document.body) { e.preventDefault(); playButton.click(); } });

// ---- names on hover
const tip = document.getElementById('tip');
const raycaster = new THREE.Raycaster();
renderer.domElement.addEventListener('pointermove', (e) => {
  const r = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  raycaster.setFromCamera(ndc, camera);
  const hit = raycaster.intersectObjects(pickable, false)[0];
  tip.style.display = hit ? 'block' : 'none';
  if (hit) { tip.textContent = hit.object.userData.names[hit.instanceId]; tip.style.left = `${e.clientX + 12}px`; tip.style.top = `${e.clientY + 12}px`; }
});

// ---- plot panel: any column against t, the cursor at the current time
const chart = document.getElementById('chart');
const ctx = chart.getContext('2d');
const columnSelect = document.getElementById('column');
columnNames.forEach((c, i) => { if (i > 0) columnSelect.add(new Option(c, String(i))); });
let plotColumn = Math.max(1, columnNames.indexOf(scene.plotColumn));
columnSelect.value = String(plotColumn);
columnSelect.addEventListener('change', () => { plotColumn = Number(columnSelect.value); plotCache = null; drawPlot(); });
let plotCache = null;
const margin = { left: 58, right: 8, top: 8, bottom: 30 };
let plotLabels = [];
// the plotted column's samples as (t, low, high): each keyframe of a pose column, or each
// non-empty interval of an envelope at the interval's middle
function forEachSample(column, visit) {
  const s = series[column];
  if (scene.columns[column].pose) { for (let r = 0; r < nKeyframes; r++) visit(value(r, 0), s[r], s[r]); return; }
  const n = scene.plotBuckets;
  for (let b = 0; b < n; b++)
    if (!Number.isNaN(s[2 * b])) visit(tStart + ((b + 0.5) / n) * (tEnd - tStart), s[2 * b], s[2 * b + 1]);
}
function plotData() {
  if (plotCache) return plotCache;
  const dataMin = scene.columns[plotColumn].min, dataMax = scene.columns[plotColumn].max;
  let lo = dataMin, hi = dataMax;
  if (hi - lo < 1e-12 * Math.max(1, Math.abs(hi))) { lo -= 0.5; hi += 0.5; }
  // the left margin holds the widest tick label and the rotated axis name
  const y = niceTicks(lo, hi, 5), x = niceTicks(tStart, tEnd, 4);
  const yTicks = y.ticks.map((v) => ({ value: v, text: tickLabel(v, y.step) }));
  const xTicks = x.ticks.map((v) => ({ value: v, text: tickLabel(v, x.step) }));
  ctx.font = '11px system-ui, sans-serif';
  margin.left = Math.ceil(18 + Math.max(...yTicks.map((t) => ctx.measureText(t.text).width)) + 6);
  // at most two points (min and max) per pixel column
  const w = chart.width - margin.left - margin.right, h = chart.height - margin.top - margin.bottom;
  const xOf = (t) => margin.left + ((t - tStart) / Math.max(tEnd - tStart, 1e-300)) * w;
  const yOf = (v) => margin.top + (1 - (v - lo) / (hi - lo)) * h;
  const path = [];
  let px = -1, vmin = 0, vmax = 0;
  forEachSample(plotColumn, (t, a, b) => {
    const x = Math.round(xOf(t));
    if (x !== px) { if (px >= 0) path.push([px, yOf(vmin)], [px, yOf(vmax)]); px = x; vmin = a; vmax = b; }
    else { vmin = Math.min(vmin, a); vmax = Math.max(vmax, b); }
  });
  path.push([px, yOf(vmin)], [px, yOf(vmax)]);
  plotCache = { lo, hi, dataMin, dataMax, path, xOf, yOf, yTicks, xTicks };
  return plotCache;
}
let cursorX = 0;
function drawPlot() {
  const { path, xOf, yOf, yTicks, xTicks } = plotData();
  ctx.clearRect(0, 0, chart.width, chart.height);
  ctx.fillStyle = '#fff'; ctx.fillRect(0, 0, chart.width, chart.height);
  plotLabels = drawAxes(ctx, { margin, width: chart.width, height: chart.height, xOf, yOf }, yTicks, xTicks,
                        { x: axisName('t'), y: axisName(columnNames[plotColumn]) });
  ctx.strokeStyle = '#1f5fbf'; ctx.lineWidth = 1.5; ctx.beginPath();
  path.forEach(([x, y], i) => (i ? ctx.lineTo(x, y) : ctx.moveTo(x, y)));
  ctx.stroke();
  cursorX = xOf(current);
  ctx.strokeStyle = '#d03020'; ctx.lineWidth = 1; ctx.beginPath();
  ctx.moveTo(cursorX, margin.top); ctx.lineTo(cursorX, chart.height - margin.bottom); ctx.stroke();
}

// ---- the loop
function frame(now) {
  if (playing) {
    if (last !== null) {
      let t = current + ((now - last) / 1000) * speed;
      if (t > tEnd) t = tStart + ((t - tStart) % Math.max(tEnd - tStart, 1e-300));
      apply(t);
    }
    last = now;
  }
  renderer.render(world, camera);
  requestAnimationFrame(frame);
}
document.getElementById('title').innerHTML = '';
{
  const b = document.createElement('b'); b.textContent = scene.name;
  const s = document.createElement('div');
  const g = (x) => Number(x.toPrecision(6));
  s.textContent = `${scene.dimension}, ${scene.bodies.length} bodies, ${scene.rows} rows, t = ${g(tStart)} .. ${g(tEnd)} s; drag to orbit, wheel to zoom`;
  document.getElementById('title').append(b, s);
}
resize();
apply(tStart);
frameMechanism();
requestAnimationFrame(frame);

// ---- the page API
const v3 = new THREE.Vector3();
window.mbdViewer = {
  seek(t) { setPlaying(false); apply(t); renderer.render(world, camera); return current; },
  play() { if (current >= tEnd) apply(tStart); setPlaying(true); },
  pause() { setPlaying(false); },
  isPlaying: () => playing,
  time: () => current,
  range: () => [tStart, tEnd],
  setSpeed(s) { speed = s; speedSelect.value = String(s); },
  bodyNames: () => scene.bodies.map((b) => b.name),
  // a flexible body's tube as drawn now: the nodes it runs through (world), its radius and the
  // bounding box of its vertices; null for no such body
  flexibleTube(name) {
    const tube = flexibleTubes.find((t) => t.body.name === name);
    if (!tube) return null;
    tube.mesh.geometry.computeBoundingBox();
    const b = tube.mesh.geometry.boundingBox;
    return { nodes: tube.nodes.map((p) => [p.x, p.y, p.z]), radius: tube.body.radius,
             box: [[b.min.x, b.min.y, b.min.z], [b.max.x, b.max.y, b.max.z]] };
  },
  // where the body's frame origin (its mass centre) is drawn, in CSS pixels of the canvas
  bodyScreenPosition(name) {
    const g = bodies.find((b) => b.name === name);
    if (!g) return null;
    v3.setFromMatrixPosition(g.matrixWorld).project(camera);
    const r = renderer.domElement.getBoundingClientRect();
    return { x: r.left + ((v3.x + 1) / 2) * r.width, y: r.top + ((1 - v3.y) / 2) * r.height };
  },
  camera() {
    camera.updateMatrixWorld(true);
    const r = renderer.domElement.getBoundingClientRect();
    return { projection: camera.projectionMatrix.toArray(), view: camera.matrixWorldInverse.toArray(),
             left: r.left, top: r.top, width: r.width, height: r.height };
  },
  // pixels of the view each body covers now, by name (pixel_coverage.js); the plot panel hides what is under it
  bodyCoverage() {
    const panel = document.getElementById('plot').getBoundingClientRect();
    const { counts, unknown } = countBodyPixels(renderer, world, camera, instanced, [grid], [panel], bodies.length);
    return { pixels: Object.fromEntries(scene.bodies.map((b, i) => [b.name, counts[i]])), unknown };
  },
  // the scene's joints: their bodies (indices, -1 the ground) and points in each body's frame
  joints: () => scene.joints.map((j) => ({ name: j.name, type: j.type, bodies: j.bodies, points: j.points })),
  // where each joint's marker is drawn now: world position and CSS pixels
  jointMarkers() {
    const m = new THREE.Matrix4();
    return scene.joints.filter((j) => j.marker).map((j) => {
      const slot = j.marker.body >= 0 ? bodySlots[j.marker.body][j.marker.shape] : groundSlots[j.marker.shape];
      v3.setFromMatrixPosition(slotMatrix(slot, m));
      const world = v3.toArray();
      v3.project(camera);
      const r = renderer.domElement.getBoundingClientRect();
      return { joint: j.name, drawnOn: j.marker.body, world, x: r.left + ((v3.x + 1) / 2) * r.width, y: r.top + ((1 - v3.y) / 2) * r.height };
    });
  },
  // the contacts drawn now, those of the keyframe at `time`: each point (world), its normal,
  // normal force and friction, and its normal force's arrow as drawn (null when not drawn): base
  // and tip, world and CSS pixels
  contacts() {
    const r = renderer.domElement.getBoundingClientRect();
    const screen = (p) => { v3.copy(p).project(camera); return [r.left + ((v3.x + 1) / 2) * r.width, r.top + ((1 - v3.y) / 2) * r.height]; };
    const list = shownContacts.map((c, i) => {
      const a = normalArrows[i];
      let arrow = null;
      if (a && a.visible) {
        a.updateMatrixWorld(true);
        const base = a.localToWorld(new THREE.Vector3(0, 0, 0)), tip = a.localToWorld(new THREE.Vector3(0, a.cone.position.y, 0));
        arrow = { base: base.toArray(), tip: tip.toArray(), baseScreen: screen(base), tipScreen: screen(tip) };
      }
      return { point: c.slice(0, 3), normal: c.slice(3, 6), normalForce: c[6], friction: c.slice(7, 10), arrow };
    });
    return { time: value(shownRow, 0), contacts: list, drawn: normalArrows.filter((a) => a.visible).length };
  },
  following: () => follow,
  setFollow(on) { setFollow(Boolean(on)); apply(current); renderer.render(world, camera); },
  framing: () => ({ follow: framing.follow, size: framing.size, travel: framing.travel }),
  // the shapes of a body as drawn now: mesh index, world matrix (column-major), geometry bounds
  bodyShapes(name) {
    const b = scene.bodies.findIndex((x) => x.name === name);
    if (b < 0) return null;
    const m = new THREE.Matrix4();
    return bodySlots[b].map((slot, k) => ({ mesh: scene.bodies[b].shapes[k].mesh, scale: scene.bodies[b].shapes[k].scale,
      matrix: slotMatrix(slot, m).toArray(), min: geometries[scene.bodies[b].shapes[k].mesh].boundingBox.min.toArray(),
      max: geometries[scene.bodies[b].shapes[k].mesh].boundingBox.max.toArray() }));
  },
  setPlotColumn(name) { const i = columnNames.indexOf(name); if (i < 1) return false; columnSelect.value = String(i); plotColumn = i; plotCache = null; drawPlot(); return true; },
  plotInfo() { const { lo, hi, dataMin, dataMax, path } = plotData(); return { column: columnNames[plotColumn], min: dataMin, max: dataMax, axis: [lo, hi], points: path.length, cursorX, width: chart.width, height: chart.height, margin: { ...margin }, labels: plotLabels, names: { x: axisName('t'), y: axisName(columnNames[plotColumn]) } }; },
};
