// hullpose-web page: a three.js scene in the rig frame (millimetres, z up) with the floor, the
// capture volume, each camera as a small frustum where the rig file puts it, and the skeleton
// (bones in one colour, joints coloured by confidence: red 0 .. green 1; an invalid frame is
// drawn grey under a red banner). The panel lists each node's STATUS and the trigger ->
// skeleton latency. When the fusion host sends the coarse carved hull (HULL, --hull-rate), it is
// drawn as shaded voxels in HULL_COLOUR, shown or hidden with the 'hull' toggle.
// window.hullpose exposes the page's state (tests read it).
'use strict';

const BONE_COLOUR = 0xff9900;     // tests look for this colour at the bones' projected midpoints
const INVALID_COLOUR = 0x777777;
const HULL_COLOUR = 0x3fa7d6;     // lit: a pixel of the hull is this colour times its shade
const MAX_HULL_VOXELS = 64 * 64 * 64;
const JOINTS = ['HeadTop', 'Head', 'Neck', 'Chest', 'LSho', 'RSho', 'LElb', 'RElb', 'LHand', 'RHand', 'LFTip', 'RFTip',
  'UBack', 'Back', 'LBack', 'LHip', 'RHip', 'LKne', 'RKne', 'LAnk', 'RAnk', 'LFoot', 'RFoot', 'LToe', 'RToe'];
const J = Object.fromEntries(JOINTS.map((n, i) => [n, i]));
const BONES = [['Chest', 'Neck'], ['Neck', 'Head'], ['Head', 'HeadTop'], ['Chest', 'LSho'], ['Chest', 'RSho'],
  ['LSho', 'LElb'], ['RSho', 'RElb'], ['LElb', 'LHand'], ['RElb', 'RHand'], ['LHand', 'LFTip'], ['RHand', 'RFTip'],
  ['Chest', 'UBack'], ['UBack', 'Back'], ['Back', 'LBack'], ['LBack', 'LHip'], ['LBack', 'RHip'], ['LHip', 'LKne'],
  ['RHip', 'RKne'], ['LKne', 'LAnk'], ['RKne', 'RAnk'], ['LAnk', 'LFoot'], ['RAnk', 'RFoot'], ['LFoot', 'LToe'],
  ['RFoot', 'RToe']].map(([a, b]) => [J[a], J[b]]);
const REASONS = ['ok', 'too few cameras', 'empty hull', 'invalid tree', 'pose jump', 'fit failed'];

const state = window.hullpose = {
  skeletons: 0, valid: 0, invalid: 0, statuses: 0, hulls: 0, hullShown: null, showHull: true,
  paused: false, last: null, shown: null, latencies: [],
  pause() { this.paused = true; }, resume() { this.paused = false; },
  // Screen pixels (CSS px, origin top left) of every joint and bone midpoint of the shown pose.
  projected() { return projectShown(); },
  // Resolves after the next frame has been drawn.
  rendered() { return new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))); },
  boneColour: BONE_COLOUR,
  hullColour: HULL_COLOUR,
  setHull(on) { setHullVisible(on); },
  // Screen pixels of up to n of the drawn hull's voxel centres, evenly spread.
  projectedHull(n) { return projectHull(n); },
};

const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(window.innerWidth, window.innerHeight);
renderer.setClearColor(0x15181c);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight, 10, 100000);
camera.up.set(0, 0, 1);
const controls = new THREE.OrbitControls(camera, renderer.domElement);
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
});

const v3 = (a) => new THREE.Vector3(a[0], a[1], a[2]);

function drawRig(rig) {
  document.getElementById('rig').textContent = rig.rig_id || '';
  const min = v3(rig.volume.min), max = v3(rig.volume.max);
  const size = new THREE.Vector3().subVectors(max, min);
  const centre = new THREE.Vector3().addVectors(min, max).multiplyScalar(0.5);
  const empty = size.lengthSq() === 0;
  if (empty) { size.set(3000, 3000, 2200); centre.set(0, 0, 1100); }
  // Floor: a 500 mm grid on z = 0 around the volume.
  const extent = Math.ceil(Math.max(size.x, size.y, 4000) * 2 / 1000) * 1000;
  const grid = new THREE.GridHelper(extent, extent / 500, 0x3a4048, 0x2a2e34);
  grid.rotation.x = Math.PI / 2;
  grid.position.set(centre.x, centre.y, 0);
  scene.add(grid);
  if (!empty) {
    const box = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.BoxGeometry(size.x, size.y, size.z)),
      new THREE.LineBasicMaterial({ color: 0x4f7fbf }));
    box.position.copy(centre);
    scene.add(box);
  }
  for (const c of rig.cameras) {
    // A pyramid from the centre along the optical axis, 300 mm deep, the image's aspect.
    const o = v3(c.centre), f = v3(c.forward), r = v3(c.right), d = v3(c.down), depth = 300;
    const corner = (sx, sy) => o.clone().addScaledVector(f, depth).addScaledVector(r, sx * c.half_width * depth)
      .addScaledVector(d, sy * c.half_height * depth);
    const k = [corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1)];
    const pts = [o, k[0], o, k[1], o, k[2], o, k[3], k[0], k[1], k[1], k[2], k[2], k[3], k[3], k[0]];
    scene.add(new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(pts), new THREE.LineBasicMaterial({ color: 0xcccccc })));
  }
  // Look at the volume from a raised corner, far enough to see all of it.
  const radius = empty ? 3000 : size.length() / 2;
  camera.position.set(centre.x - 1.0 * radius, centre.y - 1.3 * radius, centre.z + 0.55 * radius);
  controls.target.copy(centre);
  controls.update();
}

// The skeleton: unlit materials, so a pixel shows exactly the colour it was given.
const boneMaterial = new THREE.MeshBasicMaterial({ color: BONE_COLOUR });
const boneGeometry = new THREE.CylinderGeometry(16, 16, 1, 8);  // along +y, unit length, scaled per bone
const bones = BONES.map(() => { const m = new THREE.Mesh(boneGeometry, boneMaterial); m.visible = false; scene.add(m); return m; });
const jointGeometry = new THREE.SphereGeometry(22, 12, 8);
const joints = JOINTS.map(() => {
  const m = new THREE.Mesh(jointGeometry, new THREE.MeshBasicMaterial({ color: 0x00ff00 }));
  m.visible = false; scene.add(m); return m;
});
const Y = new THREE.Vector3(0, 1, 0);

// The hull: one instanced unit box per surface voxel, lit so that its shape reads.
scene.add(new THREE.AmbientLight(0xffffff, 0.55));
const sun = new THREE.DirectionalLight(0xffffff, 0.45);
sun.position.set(0.3, -0.5, 1);
scene.add(sun);
let hullMesh = null;
const hullToggle = document.getElementById('hull');
hullToggle.onchange = () => setHullVisible(hullToggle.checked);

function setHullVisible(on) {
  state.showHull = on;
  hullToggle.checked = on;
  if (hullMesh) hullMesh.visible = on;
}

function showHull(h) {
  const count = Math.min(h.voxels.length / 3, MAX_HULL_VOXELS);
  if (!hullMesh || hullMesh.userData.capacity < count) {
    if (hullMesh) { scene.remove(hullMesh); hullMesh.geometry.dispose(); hullMesh.material.dispose(); }
    const capacity = Math.max(count, 1024);
    hullMesh = new THREE.InstancedMesh(new THREE.BoxBufferGeometry(1, 1, 1),
      new THREE.MeshLambertMaterial({ color: HULL_COLOUR }), capacity);
    hullMesh.userData.capacity = capacity;
    scene.add(hullMesh);
  }
  const m = new THREE.Matrix4(), s = h.voxel_mm;
  for (let i = 0; i < count; ++i) {
    m.makeScale(s, s, s);
    m.setPosition(h.origin[0] + (h.voxels[3 * i] + 0.5) * s, h.origin[1] + (h.voxels[3 * i + 1] + 0.5) * s,
      h.origin[2] + (h.voxels[3 * i + 2] + 0.5) * s);
    hullMesh.setMatrixAt(i, m);
  }
  hullMesh.count = count;
  hullMesh.instanceMatrix.needsUpdate = true;
  hullMesh.visible = state.showHull;
  state.hullShown = { seq: h.seq, voxels: h.voxels.slice(0, 3 * count), origin: h.origin, voxel_mm: s, occupied: h.occupied };
  document.getElementById('hullinfo').textContent = `seq ${h.seq}, ${h.occupied} voxels of ${s.toFixed(0)} mm`;
}

function onHull(h) {
  state.hulls++;
  hullToggle.disabled = false;
  if (!state.paused) showHull(h);
}

function projectHull(n) {
  const h = state.hullShown;
  if (!h || !hullMesh || !hullMesh.visible) return [];
  scene.updateMatrixWorld(true);
  const w = renderer.domElement.clientWidth, ht = renderer.domElement.clientHeight;
  const total = h.voxels.length / 3, step = Math.max(1, Math.floor(total / n)), out = [];
  for (let i = 0; i < total && out.length < n; i += step) {
    const q = new THREE.Vector3(h.origin[0] + (h.voxels[3 * i] + 0.5) * h.voxel_mm, h.origin[1] + (h.voxels[3 * i + 1] + 0.5) * h.voxel_mm,
      h.origin[2] + (h.voxels[3 * i + 2] + 0.5) * h.voxel_mm).project(camera);
    out.push({ x: (q.x + 1) / 2 * w, y: (1 - q.y) / 2 * ht });
  }
  return out;
}

function showSkeleton(s) {
  // An invalid frame's joints are not a fresh estimate: draw the last valid pose, grey.
  if (s.valid) state.lastValid = s;
  const p = (s.valid || !state.lastValid ? s : state.lastValid).joints.map(v3);
  boneMaterial.color.setHex(s.valid ? BONE_COLOUR : INVALID_COLOUR);
  BONES.forEach(([a, b], i) => {
    const dir = new THREE.Vector3().subVectors(p[b], p[a]);
    const len = dir.length();
    const m = bones[i];
    m.visible = len > 1;
    if (!m.visible) return;
    m.position.copy(p[a]).addScaledVector(dir, 0.5);
    m.quaternion.setFromUnitVectors(Y, dir.clone().normalize());
    m.scale.set(1, len, 1);
  });
  p.forEach((q, i) => {
    const c = Math.max(0, Math.min(1, s.confidence[i]));
    joints[i].material.color.setRGB(s.valid ? 1 - c : 0.5, s.valid ? c : 0.5, s.valid ? 0 : 0.5);
    joints[i].position.copy(q);
    joints[i].visible = true;
  });
  state.shown = { ...s, joints: p.map((q) => [q.x, q.y, q.z]) };
  document.getElementById('seq').textContent = s.seq;
  const banner = document.getElementById('banner');
  banner.className = s.valid ? 'valid' : 'invalid';
  banner.textContent = s.valid ? 'tracking' : 'INVALID frame: ' + (REASONS[s.reason] || 'reason ' + s.reason) + ' (last pose shown grey)';
}

function projectShown() {
  const s = state.shown;
  if (!s) return null;
  scene.updateMatrixWorld(true);
  const w = renderer.domElement.clientWidth, h = renderer.domElement.clientHeight;
  const px = (v) => { const q = v.clone().project(camera); return { x: (q.x + 1) / 2 * w, y: (1 - q.y) / 2 * h, depth: q.z }; };
  const p = s.joints.map(v3);
  return {
    valid: s.valid, seq: s.seq,
    joints: p.map((q, i) => ({ name: JOINTS[i], ...px(q) })),
    bones: BONES.map(([a, b]) => ({ name: JOINTS[a] + '-' + JOINTS[b], ...px(p[a].clone().add(p[b]).multiplyScalar(0.5)) })),
  };
}

function percentile(values, q) {
  if (!values.length) return NaN;
  const v = values.slice().sort((a, b) => a - b);
  return v[Math.min(v.length - 1, Math.max(0, Math.ceil(q * v.length) - 1))];
}

function onSkeleton(s) {
  state.skeletons++;
  if (s.valid) state.valid++; else state.invalid++;
  state.last = s;
  if (s.latency_ms > 0) { state.latencies.push(s.latency_ms); if (state.latencies.length > 300) state.latencies.shift(); }
  document.getElementById('count').textContent = state.skeletons;
  document.getElementById('valid').textContent = state.valid;
  document.getElementById('latency').textContent = state.latencies.length
    ? `${s.latency_ms.toFixed(1)} ms (p50 ${percentile(state.latencies, 0.5).toFixed(1)}, p99 ${percentile(state.latencies, 0.99).toFixed(1)} over ${state.latencies.length})`
    : 'not measured (playback)';
  if (!state.paused) showSkeleton(s);
}

const nodes = new Map();
function onStatus(st) {
  state.statuses++;
  nodes.set(`${st.role}/${st.node_id}`, st);
  const rows = [...nodes.values()].sort((a, b) => (a.role + a.node_id).localeCompare(b.role + b.node_id)).map((n) => {
    const c = n.counters || {};
    const drops = Object.entries(c).filter(([k]) => !k.startsWith('trigger_residual')).reduce((s, [, v]) => s + v, 0);
    const res = c.trigger_residual_mean_us !== undefined
      ? `${(c.trigger_residual_mean_us / 1000).toFixed(2)} / ${(c.trigger_residual_max_us / 1000).toFixed(2)} ms` : '–';
    const name = n.role === 'camera_node' ? `camera ${n.node_id}` : n.role;
    const states = ['starting', 'running', 'degraded', 'error', 'stopped'];
    return `<tr><td>${name}</td><td>${states[n.state] || n.state}</td><td>${n.fps.toFixed(1)}</td><td>${drops}</td><td>${res}</td></tr>`;
  });
  document.querySelector('#cameras tbody').innerHTML = rows.join('');
}

document.getElementById('pause').onclick = (e) => {
  state.paused = !state.paused;
  e.target.textContent = state.paused ? 'resume' : 'pause';
  if (!state.paused && state.last) showSkeleton(state.last);
};

function connect() {
  const ws = new WebSocket(`ws://${location.host}/ws`);
  ws.onmessage = (e) => {
    const m = JSON.parse(e.data);
    if (m.type === 'skeleton') onSkeleton(m); else if (m.type === 'status') onStatus(m); else if (m.type === 'hull') onHull(m);
  };
  ws.onclose = () => setTimeout(connect, 1000);  // the server restarted: reconnect
}

fetch('/rig.json').then((r) => r.json()).then((rig) => { drawRig(rig); state.rig = rig; connect(); });
(function loop() { requestAnimationFrame(loop); controls.update(); renderer.render(scene, camera); })();
